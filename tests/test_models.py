"""The run models of the registry (bkwaves._models) through every route: TOML configs,
bk.run, outputs, checkpoints, bkwaves stats, the run-cost estimate (issues 25 and 26).

The planar models are checked against independent computations: the lattice's config
route against bk.Lattice built by hand, and a planar front on a lattice periodic in y
against the chain (an exact reduction: the y-Laplacian vanishes)."""

from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import _models as models
from bkwaves.config import parse_config
from bkwaves.runner import checkpoint_path, resume, run

LATTICE_LOADING = {
    "model": "lattice",
    "seed": 5,
    "params": {"gamma": 0.45, "v": 0.01, "dx": 0.2},
    "domain": {"shape": [20, 16], "boundary": ["free", "periodic"]},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 0.8},
    "disorder": {"threshold": {"distribution": "uniform", "mean": 1.0, "spread": 0.05}},
    "run": {"t_end": 60.0},
    "output": {"snapshot_every": 10.0},
}

LATTICE_RUPTURE = {
    "model": "lattice",
    "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
    "domain": {"shape": [24, 18]},
    "initial": {"kind": "uniform", "value": 0.7},
    "triggers": [{"time": 0.0, "block": [12, 9], "kind": "kick", "velocity": 2.0}],
    "run": {"t_end": 4.0},
    "output": {"snapshot_every": 1.0, "arrivals": True},
}


def _with(doc: dict, path: str, value) -> dict:
    """``doc`` with the key at ``path`` (a.b.c) set (None: removed)."""
    out = copy.deepcopy(doc)
    *head, last = path.split(".")
    d = out
    for k in head:
        d = d.setdefault(k, {})
    if value is None:
        d.pop(last, None)
    else:
        d[last] = value
    return out


def test_every_model_is_one_entry_of_the_registry():
    assert set(models.NAMES) >= {"chain", "free_boundary", "lattice"}
    for name in models.NAMES:
        entry = models.get(name)
        assert entry.name == name and entry.boundaries and entry.domain_keys
    assert bk.config.MODELS == models.NAMES
    with pytest.raises(bk.ParameterError, match="model: unknown model 'plane'"):
        models.get("plane")


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        ("domain.shape", [0, 5], r"domain\.shape\[0\]: .*>= 1"),
        ("domain.shape", [10], r"domain\.shape: expected \[nx, ny\], two integers >= 1"),
        ("domain.blocks", 10, r"domain\.blocks: unknown key; valid keys here: shape, dy, boundary"),
        ("domain.boundary", ["free", "open"], r"domain\.boundary: expected one of free, fixed, "),
        ("domain.dy", -0.1, r"domain\.dy: invalid dy = -0\.1: allowed 0 < dy <= 1000000"),
        ("disorder.coupling", 1.0, r"disorder\.coupling: unknown key; valid keys here: "),
        ("initial.kind", "bumps", r"initial\.kind: .*uniform, ramp, random, file"),
        (
            "triggers",
            [{"block": [24, 0], "kind": "release"}],
            r"triggers\[0\]\.block: invalid block = \[24, 0\]: ",
        ),
        (
            "triggers",
            [{"block": 3, "kind": "release"}],
            r"triggers\[0\]\.block: .*allowed \[i, j\] with 0 <= i < 24",
        ),
        ("run.step", 0.9, r"run\.step: step = 0\.9 is too large for RK4 stability.*<= 0\.856107"),
        ("speed", {"u_plus": [0.5], "c": [1.2]}, r"speed: a front-speed law applies to the "),
    ],
)
def test_lattice_config_errors_name_the_key_and_the_range(path, value, message):
    with pytest.raises(bk.ParameterError, match=message) as e:
        parse_config(_with(LATTICE_RUPTURE, path, value))
    assert "\n" not in str(e.value)


def test_lattice_step_bound_is_the_engines():
    """The config's RK4 bound on run.step is the engine's: sqrt(1 + 4/dx^2 + 4/dy^2)."""
    p = bk.Params(gamma=0.45, v=0.0, dx=0.1)
    parse_config(_with(LATTICE_RUPTURE, "run.step", 0.85))
    bk.Lattice((24, 18), p, u0=0.7, step=0.85)
    with pytest.raises(bk.ParameterError, match="step"):
        bk.Lattice((24, 18), p, u0=0.7, step=0.86)
    with pytest.raises(bk.ParameterError, match=r"run\.step"):
        parse_config(_with(LATTICE_RUPTURE, "run.step", 0.86))


def test_one_dimensional_models_refuse_the_planar_keys():
    chain = _with(LATTICE_RUPTURE, "model", "chain")
    chain["domain"] = {"blocks": 50}
    chain["triggers"] = [{"block": 3, "kind": "release"}]
    with pytest.raises(bk.ParameterError, match=r"output\.arrivals: applies to the lattice"):
        parse_config(chain)
    with pytest.raises(bk.ParameterError, match=r"domain\.shape: unknown key"):
        parse_config(_with(_with(chain, "output.arrivals", None), "domain.shape", [5, 5]))


def test_lattice_config_round_trips_through_its_document():
    cfg = parse_config(LATTICE_LOADING)
    assert cfg.shape == (20, 16) and cfg.boundary == ("free", "periodic")
    assert parse_config(cfg.to_dict()) == cfg
    cfg = parse_config(_with(LATTICE_RUPTURE, "domain.dy", 0.15))
    assert cfg.to_dict()["triggers"][0]["block"] == [12, 9]
    assert parse_config(cfg.to_dict()) == cfg


def test_a_lattice_config_runs_as_the_lattice_built_by_hand():
    """bk.run(config) against bk.Lattice built by hand: the same slips, bit for bit."""
    res = bk.run(LATTICE_RUPTURE)
    p = bk.Params(gamma=0.45, v=0.0, dx=0.1)
    la = bk.Lattice((24, 18), p, u0=0.7).kick((12, 9), -2.0)
    ref = la.run(t_end=4.0, progress=False)
    arr = res.tables["arrivals"]
    t = np.full((18, 24), np.nan)
    t[arr["j"], arr["i"]] = arr["t"]
    np.testing.assert_array_equal(t, ref.first_slip_times())
    assert np.isfinite(t).all()  # the rupture crossed the lattice by t = 4
    sl = res.tables["slips"]
    np.testing.assert_array_equal(sl["t_start"], ref.slips["t_start"])
    np.testing.assert_array_equal(sl["slip"], ref.slips["slip"])
    np.testing.assert_array_equal(sl[["i", "j"]], ref.slips[["i", "j"]])


@pytest.mark.parametrize("events", ["global", "local"])
def test_a_planar_front_on_a_lattice_periodic_in_y_is_the_chain(events):
    """An exact reduction through the config route: u independent of j, so the
    y-Laplacian vanishes and every row is the chain at dx (issue 25). Both with the same
    event mode: the same arithmetic (the y coupling an exact +0), so the same bits
    (docs/lattice.md, "Ties")."""
    base = {
        "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        "initial": {"kind": "uniform", "value": 0.6},
        "run": {"t_end": 8.0, "events": events},
    }
    chain = bk.run(
        {
            **base,
            "model": "chain",
            "domain": {"blocks": 60},
            "triggers": [{"block": 0, "kind": "kick", "velocity": 2.0}],
        }
    )
    lat = bk.run(
        {
            **base,
            "model": "lattice",
            "domain": {"shape": [60, 3], "boundary": ["free", "periodic"]},
            "triggers": [{"block": [0, j], "kind": "kick", "velocity": 2.0} for j in range(3)],
            "output": {"arrivals": True},
        }
    )
    first = chain.tables["slips"].groupby("block")["t_start"].min().to_numpy()
    arr = lat.tables["arrivals"]
    assert len(first) == 60 and len(arr) == 180
    for j in range(3):
        row = arr[arr["j"] == j].sort_values("i")["t"].to_numpy()
        assert np.array_equal(row, first), f"row {j}"
    # and the front moves at the chain's c: a check that the run did something
    c = (0.1 * 20) / (first[40] - first[20])
    assert 1.2 < c < 1.3


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_lattice_outputs_have_dims_t_y_x_and_the_planar_catalog(tmp_path, suffix):
    out = tmp_path / f"la{suffix}"
    res = bk.run(LATTICE_RUPTURE, out, snapshots=True)
    ds, tables = bk.io.load_tables(out)
    for var in ("u", "u_t", "sliding"):
        assert ds[var].dims == ("t", "y", "x")
    assert ds.sizes == {"t": 5, "y": 18, "x": 24}
    np.testing.assert_allclose(ds["y"].values, 0.1 * np.arange(18))
    assert res.snapshots["u"].dims == ("t", "y", "x")
    np.testing.assert_array_equal(res.snapshots["u"].values, ds["u"].values)
    ev = tables["events"]
    assert {"hypocentre_i", "hypocentre_j", "hypocentre_x", "hypocentre_y", "area"} <= set(ev)
    assert ev.loc[0, "hypocentre_i"] == 12 and ev.loc[0, "hypocentre_j"] == 9
    # moment = int slip dA = dx dy times the sum of the slips of the event's blocks
    sl = tables["slips"]
    done = sl[sl["event"] == 0]["slip"].sum()
    assert ev.loc[0, "moment"] == pytest.approx(0.01 * done, rel=1e-12)
    assert set(tables) == {"events", "slips", "arrivals", "ruptures"}


def test_lattice_physical_outputs_convert_areas_and_moments():
    doc = copy.deepcopy(LATTICE_RUPTURE)
    doc.pop("params")
    doc["physical"] = {"preset": "bristol_board", "V": 1e-9}
    cfg = parse_config(doc)
    p = cfg.params
    # trigger times and t_end are seconds now; run the same rupture to its end
    doc["run"] = {"t_end": float(p.units.time(4.0))}
    doc["triggers"][0]["velocity"] = float(2.0 * p.units.velocity_scale)
    res = bk.run(doc)
    ev = res.tables["events"]
    assert ev.attrs["units"]["moment"] == "m3" and ev.attrs["units"]["area"] == "m2"
    ls = p.units.length_scale
    assert ev.loc[0, "area"] == pytest.approx(ev.loc[0, "n_blocks"] * (p.dx * ls) ** 2)


def test_resumed_lattice_run_equals_the_uninterrupted_one_bit_for_bit(tmp_path):
    # with the arrivals table: a cut run wrote it whole, and its resumption appended it
    # again (twice the rows) until the resumed run rewrote it as it does the ruptures
    cfg = parse_config(_with(LATTICE_LOADING, "output.arrivals", True))
    ref = run(cfg, tmp_path / "ref.nc", chunk=200)
    assert ref.events >= 5
    out = tmp_path / "cut.nc"
    # a cut after the first, lattice-wide event, with events left to run
    for k in range(6, ref.extra["counters"]["steps"] // 200, 4):
        first = run(cfg, out, chunk=200, overwrite=True, _stop_after_chunks=k)
        if first.interrupted and 2 <= first.events < ref.events - 2:
            break
    assert first.interrupted and checkpoint_path(out).exists()
    assert 0 < first.events < ref.events
    last = resume(out, chunk=200)
    assert not last.interrupted and not checkpoint_path(out).exists()
    a, ta = bk.io.load_tables(tmp_path / "ref.nc")
    b, tb = bk.io.load_tables(out)
    assert a.sizes == b.sizes
    for var in ("t", "u", "u_t", "sliding"):
        np.testing.assert_array_equal(a[var].values, b[var].values)
    assert set(ta) == set(tb) == {"events", "slips", "ruptures", "arrivals"}
    for name in ta:
        assert len(ta[name]) > 0 and ta[name].equals(tb[name]), name
    assert last.events == ref.events and last.t == ref.t


def test_lattice_catalog_is_the_same_from_bk_run_bk_load_and_bkwaves_stats(tmp_path):
    out = tmp_path / "la.nc"
    res = bk.run(LATTICE_LOADING, out)
    mem = bk.run(LATTICE_LOADING)
    _, cat = bk.load(out)
    assert cat.equals(res.events)
    np.testing.assert_array_equal(cat["moment"], mem.events["moment"])
    stats = subprocess.run(
        [sys.executable, "-m", "bkwaves", "stats", str(out), "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    rep = json.loads(stats.stdout)
    assert rep["model"] == "lattice"
    assert rep["events"] == int(res.events["complete"].sum()) == mem.summary["n_events"] >= 5
    # the statistics are over the ruptures (the events split into single nucleations)
    n_ruptures = int(res.tables["ruptures"]["complete"].sum())
    assert rep["catalog"] == "ruptures" and rep["ruptures"] == n_ruptures >= rep["events"]
    assert mem.summary["n_ruptures"] == n_ruptures
    assert rep["largest"]["moment"] == res.summary["max_moment"] == mem.summary["max_moment"]
    assert "dx dy" in rep["moment"]["definition"]
    assert rep["b"]["m_c"] == pytest.approx(mem.summary["m_c"])


def test_lattice_estimate_and_memory_limits():
    est = bk.limits.estimate(parse_config(LATTICE_RUPTURE))
    assert est.snapshots == 5
    assert est.output_bytes == 5 * 24 * 18 * 17
    assert 0 < est.wall_s < 60
    # the work against the engine's own count (a rupture across the lattice): the
    # block-steps (sliding, and redone to locate each slip and stick) and the steps,
    # with local events (the default) and the global cut (ratios 1.53/1.06, 1.19/1.09)
    for events in (None, "global"):
        cfg = parse_config(_with(LATTICE_RUPTURE, "run.events", events))
        est = bk.limits.estimate(cfg)
        counted = bk.runner.run(cfg, None).extra["counters"]
        assert 0.5 < est.detail.block_steps / counted["block_steps"] < 2.0, events
        assert 0.5 < est.detail.steps / counted["steps"] < 2.0, events
    with pytest.raises(
        bk.ParameterError,
        match=r"domain\.shape = \[1048576, 1048576\] \(1099511627776 blocks\): the engine",
    ):
        parse_config(_with(LATTICE_RUPTURE, "domain.shape", [2**20, 2**20]))


def test_lattice_sweep_runs_each_point_as_bk_run(tmp_path):
    from distributed import Client, LocalCluster

    doc = {
        "task": "run",
        "base": _with(LATTICE_RUPTURE, "run.t_end", 10.0),
        "axes": {"initial.value": {"values": [0.6, 0.7]}},
        "output": {"catalogs": True, "snapshots": True},
    }
    cluster = LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0"
    )
    with Client(cluster) as client:
        r = bk.sweep(doc, tmp_path / "sweep.zarr", client=client)
    cluster.close()
    assert r.computed == 2 and r.failed == 0
    direct = bk.run(_with(doc["base"], "initial.value", 0.6))
    assert direct.summary["n_events"] == 1  # the rupture ended
    cell = r.dataset.sel(value=0.6)
    assert float(cell["t"]) == direct.summary["t"]
    assert float(cell["max_moment"]) == direct.summary["max_moment"]


@pytest.mark.parametrize("where", ["params", "friction"])
def test_free_boundary_refuses_beta_it_would_ignore(where):
    doc = {
        "model": "free_boundary",
        "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
        "domain": {"length": 20.0, "grid": 41},
        "initial": {"kind": "uniform", "value": 0.5},
        "run": {"t_end": 10.0},
    }
    parse_config(doc)
    for model in ("free_boundary", "free_boundary_2d"):
        if model == "free_boundary_2d":
            doc = {**doc, "model": model, "domain": {"shape": [5, 5], "spacing": 1.0}}
        doc.setdefault(where, {})["beta"] = math.inf  # (the default: no backward slip)
        cfg = parse_config(doc)
        assert parse_config(cfg.to_dict()) == cfg
        doc[where]["beta"] = 5.0
        with pytest.raises(
            bk.ParameterError,
            match=rf"^{where}\.beta: invalid beta = 5\.0: the {model} model has no backward slip",
        ):
            parse_config(doc)


def test_lattice_line_and_disc_triggers_and_smooth_fields_are_bk_lattices():
    """A line and a disc trigger and a correlated threshold field from the config are
    what bk.Lattice and bk.disorder.smooth_field give (bit for bit)."""
    doc = _with(LATTICE_RUPTURE, "domain.dy", 0.15)
    doc["seed"] = 11
    doc["triggers"] = [
        {"time": 0.0, "line": [[2, 2], [20, 2]], "kind": "kick", "velocity": 2.0},
        {"time": 0.5, "disc": [[12, 12], 0.35], "kind": "release"},
    ]
    doc["disorder"] = {"threshold": {"mean": 1.0, "amplitude": 0.05, "correlation_length": 0.4}}
    doc["run"] = {"t_end": 1.5}
    cfg = parse_config(doc)
    assert parse_config(cfg.to_dict()) == cfg
    res = bk.run(cfg)
    p = bk.Params(gamma=0.45, v=0.0, dx=0.1)
    seed = bk.disorder.property_seed(11, "threshold")
    field = bk.disorder.smooth_field((18, 24), (0.15, 0.1), 0.4, seed=seed)
    la = bk.Lattice((24, 18), p, u0=0.7, dy=0.15, threshold=1.0 + 0.05 * field)
    la.kick({"line": ((2, 2), (20, 2))}, -2.0, 0.0)
    la.release({"disc": ((12, 12), 0.35)}, 0.5)
    ref = la.run(t_end=1.5, progress=False)
    assert len(la.blocks({"line": ((2, 2), (20, 2))})) == 19
    np.testing.assert_array_equal(res.tables["slips"]["t_start"], ref.slips["t_start"])
    np.testing.assert_array_equal(res.tables["slips"]["block"], ref.slips["block"])
    with pytest.raises(bk.ParameterError, match=r"triggers\[0\]: give one of block"):
        parse_config(
            {**doc, "triggers": [{"kind": "release", "block": [1, 1], "line": [[1, 1], [2, 2]]}]}
        )
    with pytest.raises(bk.ParameterError, match=r"triggers\[0\]\.disc\[1\]: invalid radius"):
        parse_config({**doc, "triggers": [{"kind": "release", "disc": [[1, 1], -1.0]}]})


def test_lattice_pictures_pass_the_figure_checks(tmp_path):
    """bkwaves plot on a lattice output: slip map, arrival-time contours, the catalog on a
    map, the stress, and the frequency-magnitude plot, each readable (figure_checks)."""
    from figure_checks import figure_problems

    import bkwaves.plot
    from bkwaves.plot import plot_run

    out = tmp_path / "la.nc"
    bk.run({**LATTICE_LOADING, "output": {"snapshot_every": 10.0, "arrivals": True}}, out)
    problems, save = {}, bkwaves.plot.save

    def checked_save(ax, path):
        problems[Path(path).name] = figure_problems(ax.figure)
        return save(ax, path)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(bkwaves.plot, "save", checked_save)
        files = plot_run(out, tmp_path)
    names = {f.name for f in files}
    for kind in ("slip_map", "arrivals", "catalog_map", "stress", "frequency_magnitude"):
        assert f"la_{kind}.png" in names, names
    assert not {k: v for k, v in problems.items() if v}, problems


# ------------------------------------------------------------------ free_boundary_2d
FB2D = {
    "model": "free_boundary_2d",
    "seed": 3,
    "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
    "domain": {"shape": [40, 32], "spacing": 0.5, "boundary": "periodic"},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 1.0},
    "run": {"t_end": 140.0},
    "output": {"snapshot_every": 20.0, "arrivals": True},
}


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        ("domain.shape", [2, 5], r"domain\.shape\[0\]: .*>= 3"),
        ("domain.spacing", None, r"domain\.spacing: missing required key"),
        ("domain.boundary", "fixed", r"domain\.boundary: expected one of free, periodic"),
        ("domain.grid", 10, r"domain\.grid: unknown key; valid keys here: shape, spacing"),
        ("triggers", [{"time": 1.0, "x": 30.0, "y": 1.0}], r"triggers\[0\]\.x: invalid x = 30"),
        ("run.step", 0.01, r"run\.step: applies to the chain model only \(and the lattice model\)"),
        ("params.gamma", 1.0, r"params\.gamma: gamma = 1: the free boundary model needs"),
        ("disorder.mass", 1.0, r"disorder\.mass: unknown key; valid keys here: threshold"),
        ("initial.kind", "bumps", r"initial\.kind: .*uniform, ramp, random, file"),
        ("domain.spacing", 200.0, r"domain\.spacing: invalid spacing h = 200 .*allowed v h <= 1"),
        ("speed", {"curvature": -0.1}, r"speed\.curvature: invalid curvature = -0\.1"),
        ("speed", {"curvature": [0.1, 0.2, 0.3]}, r"speed\.curvature: .*pair"),
        ("speed", {"diagonal": {"u_plus": [0.5]}}, r"speed\.diagonal\.c: missing required key"),
        ("speed", {"twist": 1.0}, r"speed\.twist: unknown key; valid keys here: u_plus, c, curv"),
    ],
)
def test_free_boundary_2d_config_errors_name_the_key_and_the_range(path, value, message):
    with pytest.raises(bk.ParameterError, match=message) as e:
        parse_config(_with(FB2D, path, value))
    assert "\n" not in str(e.value)


def test_free_boundary_2d_refuses_an_initial_state_over_the_threshold():
    doc = _with(FB2D, "initial", {"kind": "uniform", "value": 0.9})
    doc["disorder"] = {"threshold": {"distribution": "uniform", "mean": 1.0, "spread": 0.2}}
    with pytest.raises(bk.ParameterError, match=r"^initial\.value: the initial state reaches"):
        parse_config(doc)
    parse_config(_with(doc, "initial.value", 0.7))


def test_free_boundary_2d_config_runs_as_the_engine_built_by_hand():
    cfg = parse_config(FB2D)
    assert parse_config(cfg.to_dict()) == cfg
    res = bk.run(cfg)
    u0 = 0.5 + 0.3 * bk.disorder.smooth_field((32, 40), (0.5, 0.5), 1.0, periodic=True, seed=3)
    p = bk.Params(gamma=0.3, v=0.01, dx=0.001)
    fb = bk.FreeBoundary2D(p, (40, 32), 0.5, u0, "periodic", record_arrivals=True)
    ref = fb.run(t_end=140.0)
    rup = res.tables["ruptures"]
    assert len(rup) == len(ref.ruptures) >= 3
    for col in ("t_start", "t_end", "x_start", "y_start", "area", "moment", "perimeter"):
        np.testing.assert_array_equal(rup[col], ref.ruptures[col])
    arr = res.tables["arrivals"]
    first = int(rup.loc[rup["complete"], "id"].iloc[0])
    mine = np.full((32, 40), np.nan)
    one = arr[arr["rupture"] == first]
    mine[one["j"], one["i"]] = one["t"]
    np.testing.assert_array_equal(mine, fb.arrival_time(first))


def test_free_boundary_2d_front_shape_from_the_speed_table():
    # [speed] curvature and [speed.diagonal] (the lattice's front shape) run as the
    # engine built by hand with curvature= and speed_diagonal=; the 1D model refuses them
    diag = {"u_plus": [0.3, 0.6, 0.9], "c": [1.06, 1.26, 2.3]}
    doc = _with(FB2D, "speed", {"curvature": [0.02, 0.04], "diagonal": diag})
    cfg = parse_config(doc)
    assert parse_config(cfg.to_dict()) == cfg
    res = bk.run(cfg)
    u0 = 0.5 + 0.3 * bk.disorder.smooth_field((32, 40), (0.5, 0.5), 1.0, periodic=True, seed=3)
    p = bk.Params(gamma=0.3, v=0.01, dx=0.001)
    kw = dict(curvature=(0.02, 0.04), speed_diagonal=diag)
    ref = bk.FreeBoundary2D(p, (40, 32), 0.5, u0, "periodic", **kw).run(t_end=140.0)
    plain = bk.FreeBoundary2D(p, (40, 32), 0.5, u0, "periodic").run(t_end=140.0)
    rup = res.tables["ruptures"]
    assert len(rup) == len(ref.ruptures) >= 3
    np.testing.assert_array_equal(rup["t_end"], ref.ruptures["t_end"])
    assert not np.array_equal(rup["t_end"], plain.ruptures["t_end"][: len(rup)])
    one_d = {
        "model": "free_boundary",
        "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
        "domain": {"length": 20.0, "grid": 64},
        "run": {"t_end": 10.0},
        "speed": {"curvature": 0.1},
    }
    with pytest.raises(bk.ParameterError, match=r"speed\.curvature: unknown key"):
        parse_config(one_d)


def test_free_boundary_2d_curvature_table_from_the_speed_table():
    # [speed] curvature = {theta, D} (a table over directions) runs as the engine built by
    # hand with curvature={"theta": ..., "D": ...}, and differs from the pair of its ends
    table = {"theta": [0.0, 0.4636476090008061, np.pi / 4], "D": [0.02, 0.06, 0.04]}
    doc = _with(FB2D, "speed", {"curvature": table})
    cfg = parse_config(doc)
    assert parse_config(cfg.to_dict()) == cfg
    res = bk.run(cfg)
    u0 = 0.5 + 0.3 * bk.disorder.smooth_field((32, 40), (0.5, 0.5), 1.0, periodic=True, seed=3)
    p = bk.Params(gamma=0.3, v=0.01, dx=0.001)
    ref = bk.FreeBoundary2D(p, (40, 32), 0.5, u0, "periodic", curvature=table)
    ref = ref.run(t_end=140.0)
    pair = bk.FreeBoundary2D(p, (40, 32), 0.5, u0, "periodic", curvature=(0.02, 0.04))
    pair = pair.run(t_end=140.0)
    rup = res.tables["ruptures"]
    assert len(rup) == len(ref.ruptures) >= 3
    np.testing.assert_array_equal(rup["t_end"], ref.ruptures["t_end"])
    assert not np.array_equal(rup["t_end"], pair.ruptures["t_end"][: len(rup)])
    bad = _with(FB2D, "speed", {"curvature": {"theta": [0.0, 0.5], "D": [0.1, 0.1]}})
    with pytest.raises(bk.ParameterError, match=r"speed\.curvature"):
        parse_config(bad)


def test_free_boundary_2d_moments_add_up_to_the_stress_dropped():
    """Conservation through the outputs: the ruptures' moments (int (u_+ - u_-) dA) add
    up to the stress the field dropped, sum of (u(0) + v t - u(t)) h^2 over the nodes
    (every rupture complete at the end)."""
    res = bk.run(FB2D, snapshots=True)
    rup = res.tables["ruptures"]
    assert rup["complete"].all() and len(rup) >= 3
    u = res.snapshots["u"]
    t = float(u["t"][-1])
    dropped = float(np.sum(u.isel(t=0) + 0.01 * t - u.isel(t=-1))) * 0.25
    assert dropped == pytest.approx(rup["moment"].sum(), rel=1e-9)


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_free_boundary_2d_outputs_and_resume_bit_for_bit(tmp_path, suffix):
    cfg = parse_config(FB2D)
    ref = run(cfg, tmp_path / f"ref{suffix}", chunk=50)
    a, ta = bk.io.load_tables(tmp_path / f"ref{suffix}")
    assert a["u"].dims == ("t", "y", "x") and a.sizes == {"t": 8, "y": 32, "x": 40}
    assert set(ta) == {"ruptures", "arrivals"}
    out = tmp_path / f"cut{suffix}"
    for k in range(2, ref.extra["steps"] // 50, 3):
        first = run(cfg, out, chunk=50, overwrite=True, _stop_after_chunks=k)
        if first.interrupted and 0 < first.events < ref.events - 1:
            break
    assert first.interrupted and checkpoint_path(out).exists()
    last = resume(out, chunk=50)
    assert not last.interrupted and last.events == ref.events
    b, tb = bk.io.load_tables(out)
    np.testing.assert_array_equal(a["t"].values, b["t"].values)
    np.testing.assert_array_equal(a["u"].values, b["u"].values)
    for name in ("ruptures", "arrivals"):
        assert ta[name].equals(tb[name])


def test_free_boundary_2d_catalog_from_bk_run_bk_load_and_bkwaves_stats(tmp_path):
    out = tmp_path / "fb.nc"
    res = bk.run(FB2D, out)
    mem = bk.run(FB2D)
    assert res.tables["ruptures"].equals(bk.io.load_tables(out)[1]["ruptures"])
    np.testing.assert_array_equal(
        res.tables["ruptures"]["moment"], mem.tables["ruptures"]["moment"]
    )
    rep = json.loads(
        subprocess.run(
            [sys.executable, "-m", "bkwaves", "stats", str(out), "--json"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    )
    assert rep["model"] == "free_boundary_2d" and rep["catalog"] == "ruptures"
    assert rep["ruptures"] == len(res.tables["ruptures"]) == mem.summary["n_ruptures"]
    assert rep["largest"]["moment"] == mem.summary["max_moment"]
    assert "u_+ - u_-" in rep["moment"]["definition"]


def test_free_boundary_2d_physical_units():
    """[physical]: spacing in metres, the noise rate per m^2 and s, areas and moments
    back in SI."""
    doc = copy.deepcopy(FB2D)
    doc.pop("params")
    doc["physical"] = {"preset": "bristol_board", "V": 1e-4}
    p = bk.presets.bristol_board(V=1e-4)
    ls, ts = p.units.length_scale, p.units.time_scale
    doc["domain"]["spacing"] = 0.5 * ls
    doc["run"] = {"t_end": 140.0 / p.v * 0.01 * ts}
    doc["noise"] = {"law": "constant", "rate": 1e-6 / (ls * ls * ts)}
    doc["output"] = {}
    cfg = parse_config(doc)
    assert cfg.spacing == pytest.approx(0.5)
    assert cfg.noise["rate"] == pytest.approx(1e-6)
    res = bk.run(cfg)
    rup = res.tables["ruptures"]
    assert rup.attrs["units"]["area"] == "m2" and rup.attrs["units"]["moment"] == "m3"
    np.testing.assert_allclose(rup["area"], rup["n_nodes"] * (0.5 * ls) ** 2, rtol=1e-12)


def test_free_boundary_2d_pictures_pass_the_figure_checks(tmp_path):
    from figure_checks import figure_problems

    import bkwaves.plot
    from bkwaves.plot import plot_run

    out = tmp_path / "fb.nc"
    bk.run(FB2D, out)
    problems, save = {}, bkwaves.plot.save

    def checked_save(ax, path):
        problems[Path(path).name] = figure_problems(ax.figure)
        return save(ax, path)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(bkwaves.plot, "save", checked_save)
        files = plot_run(out, tmp_path)
    names = {f.name for f in files}
    for kind in ("slip_map", "arrivals", "catalog_map", "stress", "frequency_magnitude"):
        assert f"fb_{kind}.png" in names, names
    assert not {k: v for k, v in problems.items() if v}, problems


def test_free_boundary_2d_estimate_and_memory_limits():
    cfg = parse_config(FB2D)
    est = bk.limits.estimate(cfg)
    assert est.snapshots == 8 and est.output_bytes == 8 * 40 * 32 * 8
    # the 1D model's work over the nx ny nodes: ~10 v T crossings per node after the
    # first node reaches the threshold (max u = mean + amplitude = 0.8: t_1 = 20)
    assert est.detail.crossings == pytest.approx(10 * 0.01 * (140.0 - 20.0) * 40 * 32, rel=0.01)
    with pytest.raises(bk.ParameterError, match=r"domain\.shape = \[1048576, 1048576\] \("):
        parse_config(_with(FB2D, "domain.shape", [2**20, 2**20]))


def test_planar_initial_files_are_read_row_after_row(tmp_path):
    """[initial] kind = "file" on a plane: an (ny, nx) .npy array, or nx ny values row
    after row in a text file; an array of another shape is refused naming initial.path."""
    u = 0.5 + 0.01 * np.arange(24 * 18).reshape(18, 24) / (24 * 18)
    np.save(tmp_path / "u.npy", u)
    np.savetxt(tmp_path / "u.txt", u.ravel())
    np.save(tmp_path / "bad.npy", u.T.copy())
    for name in ("u.npy", "u.txt"):
        cfg = parse_config(
            _with(LATTICE_RUPTURE, "initial", {"kind": "file", "path": str(tmp_path / name)})
        )
        np.testing.assert_array_equal(bk.config.initial_state(cfg), u)
        fb = parse_config(
            _with(
                _with(FB2D, "initial", {"kind": "file", "path": str(tmp_path / name)}),
                "domain.shape",
                [24, 18],
            )
        )
        np.testing.assert_array_equal(bk.config.initial_state(fb), u)
    with pytest.raises(bk.ParameterError, match=r"^initial\.path: .* shape \(24, 18\); expected"):
        bk.run(
            _with(LATTICE_RUPTURE, "initial", {"kind": "file", "path": str(tmp_path / "bad.npy")})
        )
