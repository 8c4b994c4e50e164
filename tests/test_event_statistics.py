"""Event statistics, one definition through every route (issue 23): the moment column of
both engines from Chain.run / FreeBoundary.run, bk.run, `bkwaves run` + bk.load; the
ruptures table of runs; one b from the summary, bk.stats, `bkwaves stats` and the plot;
degenerate catalogs get no b."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
import tomllib

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import noise_stats as ns
from bkwaves import stats
from bkwaves.catalog import MOMENT_DEFINITION, MOMENT_SCALE
from bkwaves.config import initial_state
from bkwaves.config import parse_config as _parse
from bkwaves.runner import chain_from_config

RING = """
model = "free_boundary"
seed = 7
[params]
gamma = 0.3
v = 1e-2
dx = 1e-3
[domain]
length = 100.0
grid = 500
boundary = "periodic"
[initial]
kind = "random"
mean = 0.5
amplitude = 0.05
correlation_length = 25.0
[run]
t_end = 600.0
"""

NOISY_RING = (
    RING
    + """
[noise]
law = "exponential"
rate = 0.01
phi0 = 0.05
"""
)

# a chain under loading between walls (the paper's long catalog): 300 events, 415 ruptures
CHAIN = """
model = "chain"
seed = 1
[params]
gamma = 0.3
v = 1e-3
dx = 0.05
beta = 5.0
[domain]
blocks = 400
boundary = "fixed"
[initial]
kind = "random"
mean = 0.5
amplitude = 0.15
correlation_length = 2.0
[run]
max_events = 300
"""


def parse_config(text: str):
    return _parse(tomllib.loads(text))


def cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "bkwaves", *map(str, args)], capture_output=True, text=True
    )


def test_the_moment_is_one_column_with_one_value_and_unit_from_every_route(tmp_path):
    """int slip dx, the same number from FreeBoundary.run, bk.run and `bkwaves run` +
    bk.load (was: 548716 from one route, 548.9 from the others), and the chain's is dx
    times its sum of block slips from Chain.run, bk.run and bk.load alike."""
    cfg = parse_config(RING)
    fb = bk.FreeBoundary(cfg.params, cfg.x(), initial_state(cfg), "periodic", seed=cfg.seed)
    direct = fb.run(t_end=cfg.t_end).events
    mem = bk.run(cfg).events
    (tmp_path / "ring.toml").write_text(RING)
    r = cli("run", tmp_path / "ring.toml", "-o", tmp_path / "ring.nc", "--quiet")
    assert r.returncode == 0, r.stderr
    _, loaded = bk.load(tmp_path / "ring.nc")
    done = direct[direct.complete]
    assert len(done) >= 3
    for df in (mem, loaded):
        np.testing.assert_array_equal(df.moment.to_numpy()[: len(done)], done.moment.to_numpy())
    for df in (direct, mem, loaded):
        assert "slip_integral" not in df
        assert df.attrs["units"]["moment"] == "1"
        assert df.attrs["scales"]["moment"] == MOMENT_SCALE
        assert df.attrs["descriptions"]["moment"] == MOMENT_DEFINITION
    # a ring-wide event of the free boundary: its moment is int A dx = mean A times L
    row = done.iloc[-1]
    assert row.moment == pytest.approx(row.stress_drop * row.swept, rel=1e-12)

    ch = parse_config(CHAIN.replace("max_events = 300", "max_events = 30"))
    res = chain_from_config(ch).run(max_events=30)
    mem = bk.run(ch).events
    (tmp_path / "chain.toml").write_text(CHAIN.replace("max_events = 300", "max_events = 30"))
    bk.run(tmp_path / "chain.toml", tmp_path / "chain.nc")
    _, loaded = bk.load(tmp_path / "chain.nc")
    sums = res.slips.groupby("event").slip.sum().to_numpy()
    np.testing.assert_allclose(res.catalog.moment, ch.params.dx * sums, rtol=1e-12)
    for df in (mem, loaded):
        np.testing.assert_array_equal(df.moment.to_numpy(), res.catalog.moment.to_numpy())
        assert df.attrs["descriptions"]["moment"] == MOMENT_DEFINITION
    assert res.catalog.attrs["descriptions"]["moment"] == MOMENT_DEFINITION


def test_si_moments_are_slip_times_length_in_m2():
    from pathlib import Path

    from bkwaves.config import load_config

    cfg = load_config(Path(__file__).parents[1] / "examples" / "bristol_board.toml")
    si = bk.run(cfg)
    dimless = bk.run(dataclasses.replace(cfg, output_units="dimensionless"))
    units = cfg.params.units
    scale = units.length_scale * units.displacement_scale  # m per x', m per slip'
    assert len(si.events) >= 1
    np.testing.assert_allclose(si.events.moment, dimless.events.moment * scale, rtol=1e-12)
    assert si.events.attrs["units"]["moment"] == "m2"
    rup = si.tables["ruptures"]
    assert rup.attrs["units"]["moment"] == "m2" and len(rup) >= 1
    np.testing.assert_allclose(rup.magnitude, stats.moment_magnitude(rup.moment), rtol=1e-12)
    assert rup.kind.iloc[0] == "trigger"


def test_runs_write_ruptures_that_share_out_the_events():
    """With noise a ring's ruptures overlap and the events merge them: the ruptures table
    of bk.run is noise_stats.ruptures of the same run (the config's [initial]), and its
    moments add up to the events' moments."""
    cfg = parse_config(NOISY_RING)
    run = bk.run(cfg)
    rup, ev = run.tables["ruptures"], run.events
    assert run.summary["ruptures"] == len(rup) > run.summary["events"] > 0
    assert run.summary["statistics_catalog"] == "ruptures"
    assert set(rup.kind) == {"noise", "threshold"}
    assert (rup.spontaneous == (rup.kind == "noise")).all()
    fb = bk.FreeBoundary(
        cfg.params, cfg.x(), initial_state(cfg), "periodic", noise=cfg.noise, seed=cfg.seed
    )
    ref = ns.ruptures(fb.run(t_end=cfg.t_end)).sort_values("t_start", kind="stable")
    np.testing.assert_array_equal(rup.t_start, ref.t_start)
    np.testing.assert_array_equal(rup.moment, ref.moment)
    done = ev[ev.complete]
    mine = rup[rup.event.isin(done.index)]  # (events are numbered from 0 in order)
    # node resets (sum A h) against the engine's trapezoid on the paths: O(h) apart
    assert mine.moment.sum() == pytest.approx(done.moment.sum(), rel=3e-3)
    assert (rup.duration == rup.t_end - rup.t_start).all() or rup.t_end.isna().any()

    ch = bk.run(parse_config(CHAIN.replace("max_events = 300", "max_events = 40")))
    r, e = ch.tables["ruptures"], ch.events
    per_event = r.groupby("event").moment.sum()
    np.testing.assert_allclose(per_event.to_numpy(), e.moment.to_numpy(), rtol=1e-12)
    assert (r.magnitude == stats.moment_magnitude(r.moment)).all()


def test_one_catalog_gives_one_b_through_every_route(tmp_path):
    path = tmp_path / "chain.toml"
    path.write_text(CHAIN)
    out = tmp_path / "chain.nc"
    mem = bk.run(path)
    r = cli("run", path, "-o", out, "--quiet")
    assert r.returncode == 0, r.stderr
    _, tables = bk.io.load_tables(out)
    rup = tables["ruptures"]
    gr = stats.gutenberg_richter(rup.moment[rup.complete].to_numpy())
    assert gr.ok, gr.reason
    s = mem.summary
    assert (s["b_value"], s["b_value_lo"], s["b_value_hi"], s["m_c"]) == (
        gr.b,
        gr.lo,
        gr.hi,
        gr.m_c,
    )
    r = cli("stats", out, "--json")
    assert r.returncode == 0, r.stderr
    rep = json.loads(r.stdout)
    assert rep["b"]["value"] == gr.b and rep["b"]["m_c"] == gr.m_c
    assert rep["ruptures"] == int(rup.complete.sum()) and rep["events"] == len(tables["events"])
    assert rep["magnitude"]["max"] == pytest.approx(float(np.nanmax(rup.magnitude)))
    big = rup.loc[rup.moment.idxmax()]
    assert rep["largest"]["moment"] == big.moment
    t = np.sort(rup.t_start[rup.complete].to_numpy())
    assert rep["recurrence"]["mean"] == pytest.approx(np.diff(t).mean(), rel=1e-12)
    text = cli("stats", out).stdout
    assert f"b-value: {gr.b:.3f}" in text and "Mc = " in text
    # one-block slips and system-size ruptures: b summarises them, no Gutenberg-Richter law
    assert rep["b"]["fit_p"] == gr.fit_p == s["b_value_fit_p"] < 0.05
    assert "not a Gutenberg-Richter law above Mc" in text
    from bkwaves import plot

    title = plot.frequency_magnitude(rup.moment[rup.complete]).get_title()
    assert title.startswith(f"b = {gr.b:.2f} [{gr.lo:.2f}, {gr.hi:.2f}]")
    assert plot.size_frequency(rup.moment[rup.complete]).get_title() == title
    files = plot.plot_run(out, tmp_path / "pics")
    assert tmp_path / "pics" / "chain_frequency_magnitude.png" in files


def test_a_degenerate_catalog_gets_no_b_anywhere(tmp_path):
    """A noiseless ring synchronises: its events sweep the ring, of one size to ~1e-5
    (bkwaves printed b = 1302 +- 20 for such a catalog); its ruptures (the pairs of the
    first loadings, then the ring-wide ones) are too few above Mc. No route prints a b,
    and every route gives the same reason."""
    path = tmp_path / "ring.toml"
    path.write_text(RING.replace("t_end = 600.0", "t_end = 2000.0"))
    out = tmp_path / "ring.nc"
    run = bk.run(path, out)
    ev = run.events[run.events.complete]
    late = ev.moment.to_numpy()[2:]  # after the first loadings
    assert np.std(late) / np.mean(late) < 1e-3
    gr = stats.gutenberg_richter(ev.moment.to_numpy())
    assert np.isnan(gr.b) and gr.reason.startswith("degenerate catalog")
    s = run.summary
    assert np.isnan(s["b_value"]) and s["b_value_note"]
    rep = json.loads(cli("stats", out, "--json").stdout)
    assert rep["b"]["value"] is None and rep["b"]["reason"] == s["b_value_note"]
    text = cli("stats", out).stdout
    assert f"b-value: none: {s['b_value_note']}" in text
    from bkwaves import plot

    rup = run.tables["ruptures"]
    title = plot.frequency_magnitude(rup.moment[rup.complete]).get_title()
    assert "no b-value" in title and "b =" not in title
    title = plot.frequency_magnitude(ev.moment).get_title()
    assert "no b-value (degenerate catalog)" in title


def test_stats_command_refuses_a_missing_output(tmp_path):
    r = cli("stats", tmp_path / "nothing.nc")
    assert r.returncode == 2 and "output not found" in r.stderr


def test_stats_command_refuses_a_sweep_store(tmp_path):
    import xarray as xr

    store = tmp_path / "sweep.zarr"
    xr.Dataset({"c": ("u_plus", [1.1, 1.2])}, attrs={"bkwaves_sweep": "bkwaves-sweep 1"}).to_zarr(
        store
    )
    r = cli("stats", store)
    assert r.returncode == 2 and "OUT" in r.stderr and "not a sweep store" in r.stderr
