"""`bkwaves run`: every example config runs; outputs describe themselves; SIGTERM keeps
what was computed; SI outputs are the dimensionless ones converted."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves.config import load_config, parse_config
from bkwaves.runner import run

EXAMPLES = sorted(
    p
    for p in (Path(__file__).parent.parent / "examples").glob("*.toml")
    if not p.name.startswith("sweep_")  # sweep descriptions: tests/test_sweep.py
)
BK = [sys.executable, "-m", "bkwaves"]


def test_there_is_an_example_per_use_case():
    names = {p.stem for p in EXAMPLES}
    assert {
        "chain_front",
        "chain_loading",
        "free_boundary_source",
        "free_boundary_random",
        "bristol_board",
    } <= names


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs_and_describes_itself(example, tmp_path):
    out = tmp_path / (example.stem + ".nc")
    r = subprocess.run(
        [*BK, "run", str(example), "-o", str(out), "--json"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert not summary["interrupted"]
    cfg = load_config(example)
    ds, catalog = bk.load(out)
    assert ds.sizes["t"] == summary["snapshots"] >= 2
    assert json.loads(ds.attrs["config"])["model"] == cfg.model
    assert ds.attrs["bkwaves_version"] == bk.__version__
    assert ds.attrs["seed"] == cfg.seed
    assert np.all(np.isfinite(ds.u.values))
    if cfg.model == "chain":
        # the sliding state is consistent with the velocities: stuck blocks move with v
        moving = ds.u_t.values != cfg.params.v
        assert np.array_equal(ds.sliding.values != 0, moving)
    assert catalog is not None and len(catalog) == summary["events"]
    if cfg.max_events is not None:
        assert summary["events"] == cfg.max_events
    if cfg.physical:
        assert ds.t.attrs["units"] == "s" and ds.x.attrs["units"] == "m"
        assert catalog.attrs["units"]["t_start"] == "s"
    # the pictures of the run render
    r = subprocess.run(
        [*BK, "plot", str(out), "-o", str(tmp_path / "fig")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    assert len(list((tmp_path / "fig").glob("*.png"))) >= 2


def test_si_outputs_are_the_dimensionless_ones_converted(tmp_path):
    doc = {
        "model": "chain",
        "physical": {"preset": "bristol_board", "V": 1e-6},
        "domain": {"blocks": 300},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [{"block": 0, "kind": "kick", "velocity": 0.03}],
        "run": {"t_end": 4e-7},
        "output": {"snapshot_every": 1e-7},
    }
    si = parse_config(doc)
    dimless = parse_config({**doc, "output": {**doc["output"], "units": "dimensionless"}})
    run(si, tmp_path / "si.nc")
    run(dimless, tmp_path / "dl.nc")
    a, ca = bk.load(tmp_path / "si.nc")
    b, cb = bk.load(tmp_path / "dl.nc")
    u = si.params.units
    np.testing.assert_allclose(a.t.values, u.time(b.t.values), rtol=1e-12)
    np.testing.assert_allclose(a.x.values, u.length(b.x.values), rtol=1e-12)
    np.testing.assert_array_equal(a.u.values, b.u.values)


def test_bad_config_exits_2_with_key_path(tmp_path):
    cfg = tmp_path / "bad.toml"
    cfg.write_text('model = "chain"\n[params]\ngamma = 0.3\nv = 0.0\ndx = 0.05\nspeed = 1\n')
    r = subprocess.run(
        [*BK, "run", str(cfg), "-o", str(tmp_path / "o.nc")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2 and "params.speed: unknown key" in r.stderr
    assert "Traceback" not in r.stderr


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_sigterm_stops_cleanly_and_keeps_the_records(tmp_path, suffix):
    cfg = tmp_path / "long.toml"
    cfg.write_text(
        'model = "free_boundary"\nseed = 1\n[params]\ngamma = 0.3\nv = 1e-2\ndx = 1e-3\n'
        '[domain]\nlength = 3000.0\ngrid = 15000\nboundary = "periodic"\n'
        '[initial]\nkind = "random"\nmean = 0.5\namplitude = 0.02\ncorrelation_length = 25.0\n'
        "[run]\nt_end = 1e7\n[output]\nsnapshot_every = 20.0\n"
    )
    out = tmp_path / f"long{suffix}"
    p = subprocess.Popen(
        [*BK, "run", str(cfg), "-o", str(out), "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.time() + 60
    parts = tmp_path / "long.nc.parts"

    def records():
        if suffix == ".nc":
            return len(list(parts.glob("part-*.nc"))) if parts.exists() else 0
        try:  # the run is appending: the arrays may be read at different lengths
            return bk.load(out)[0].sizes["t"] if out.exists() else 0
        except Exception:  # noqa: BLE001 - a half-appended store is retried
            return 0

    while time.time() < deadline and records() < 3:
        time.sleep(0.2)
    os.kill(p.pid, signal.SIGTERM)
    stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == 0, stderr
    summary = json.loads(stdout)
    assert summary["interrupted"]
    ds, catalog = bk.load(out)
    assert ds.sizes["t"] == summary["snapshots"] >= 3
    assert not parts.exists()  # NetCDF parts merged on the way out
    assert catalog is not None


LOADING = {
    "model": "chain",
    "seed": 5,
    "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05, "beta": 5.0},
    "domain": {"blocks": 300, "boundary": "periodic"},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 2.0},
    "run": {"max_events": 12},
    "output": {"snapshot_events": 1},
}


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_resumed_chain_run_equals_the_uninterrupted_one_bit_for_bit(tmp_path, suffix):
    from bkwaves.runner import checkpoint_path, resume

    cfg = parse_config(LOADING)
    ref = run(cfg, tmp_path / f"ref{suffix}", chunk=300)
    out = tmp_path / f"cut{suffix}"
    # the first, system-size event takes most of the steps: find a cut after it
    for k in range(ref.extra["counters"]["steps"] // 300, 0, -1):
        first = run(cfg, out, chunk=300, _stop_after_chunks=k)
        if first.interrupted and 0 < first.events < ref.events - 1:
            break
    assert first.interrupted and checkpoint_path(out).exists()
    assert 0 < first.events < ref.events
    last = resume(out, chunk=300)
    assert not last.interrupted and not checkpoint_path(out).exists()
    a, ca = bk.load(tmp_path / f"ref{suffix}")
    b, cb = bk.load(out)
    assert a.sizes == b.sizes
    np.testing.assert_array_equal(a.t.values, b.t.values)
    np.testing.assert_array_equal(a.u.values, b.u.values)
    np.testing.assert_array_equal(a.u_t.values, b.u_t.values)
    assert ca.equals(cb)
    assert last.events == ref.events and last.t == ref.t


FB_RING = {
    "model": "free_boundary",
    "seed": 3,
    "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
    "domain": {"length": 200.0, "grid": 400, "boundary": "periodic"},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.05, "correlation_length": 10.0},
}


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
@pytest.mark.parametrize(
    "stop",
    [
        {"run": {"max_events": 8}, "output": {"snapshot_events": 1}},
        {"run": {"t_end": 400.0}, "output": {"snapshot_every": 10.0}},
    ],
    ids=["every-event", "every-time"],
)
def test_resumed_free_boundary_run_equals_the_uninterrupted_one_bit_for_bit(tmp_path, suffix, stop):
    import pandas as pd

    from bkwaves.io import table_path
    from bkwaves.runner import checkpoint_path, resume

    cfg = parse_config({**FB_RING, **stop})
    chunk = 40
    ref = run(cfg, tmp_path / f"ref{suffix}", chunk=chunk)
    assert not ref.interrupted and ref.events >= 3 and ref.snapshots >= 5
    a, ca = bk.load(tmp_path / f"ref{suffix}")
    out = tmp_path / f"cut{suffix}"
    # a cut on a step budget (not at a snapshot) after the first event, with events left
    # to run; the interrupted run also writes the state at the cut, which the resumed run
    # drops (it continues after the checkpoint's records)
    for k in range(1, ref.extra["steps"] // chunk + 100, 2):
        first = run(cfg, out, chunk=chunk, _stop_after_chunks=k)
        if first.interrupted and 0 < first.events < ref.events - 1 and first.t not in a.t.values:
            break
    assert first.interrupted and checkpoint_path(out).exists()
    assert 0 < first.events < ref.events - 1 and first.snapshots < ref.snapshots
    # resumed twice: a checkpoint written by a resumed run resumes too
    second = resume(out, chunk=chunk, _stop_after_chunks=3)
    assert second.interrupted and first.t < second.t < ref.t
    last = resume(out, chunk=chunk)
    assert not last.interrupted and not checkpoint_path(out).exists()
    b, cb = bk.load(out)
    assert a.sizes == b.sizes and a.sizes["t"] == ref.snapshots == last.snapshots
    np.testing.assert_array_equal(a.t.values, b.t.values)
    np.testing.assert_array_equal(a.u.values, b.u.values)
    assert ca.equals(cb)
    sa = pd.read_parquet(table_path(tmp_path / f"ref{suffix}", "shocks"))
    sb = pd.read_parquet(table_path(out, "shocks"))
    assert len(sa) > 0 and sa.equals(sb)
    assert last.events == ref.events and last.t == ref.t
    assert last.extra["steps"] == ref.extra["steps"]


def test_resume_drops_records_written_after_the_checkpoint(tmp_path):
    """A crash after a checkpoint leaves extra records: resuming drops them first."""
    from bkwaves.io import RunWriter
    from bkwaves.runner import resume

    cfg = parse_config(LOADING)
    ref = run(cfg, tmp_path / "ref.nc", chunk=300)
    out = tmp_path / "crash.nc"
    for k in range(ref.extra["counters"]["steps"] // 300, 0, -1):
        cut = run(cfg, out, chunk=300, _stop_after_chunks=k)
        if cut.interrupted and 0 < cut.events < ref.events:
            break
    ds, _ = bk.load(out)
    # simulate records written after the checkpoint by a run that then died
    with RunWriter(
        out,
        ds.x.values,
        {"u": ("1", "u", "f8"), "u_t": ("1", "u_t", "f8")},
        resume_count=ds.sizes["t"],
    ) as w:
        w.append(1e9, u=np.zeros(ds.sizes["x"]), u_t=np.zeros(ds.sizes["x"]))
    assert bk.load(out)[0].sizes["t"] == ds.sizes["t"] + 1
    resume(out, chunk=300)
    a, _ = bk.load(tmp_path / "ref.nc")
    b, _ = bk.load(out)
    np.testing.assert_array_equal(a.u.values, b.u.values)
    assert ref.events == len(bk.load(out)[1])


def test_resume_cli_and_errors(tmp_path):
    cfgfile = tmp_path / "c.toml"
    cfgfile.write_text(
        'model = "chain"\nseed = 5\n[params]\ngamma = 0.3\nv = 1e-3\ndx = 0.05\nbeta = 5.0\n'
        '[domain]\nblocks = 300\nboundary = "periodic"\n'
        '[initial]\nkind = "random"\nmean = 0.5\namplitude = 0.3\ncorrelation_length = 2.0\n'
        "[run]\nmax_events = 6\n[output]\nsnapshot_events = 1\n"
    )
    r = subprocess.run(
        [*BK, "run", "--resume", str(tmp_path / "none.nc")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2 and "no checkpoint" in r.stderr
    r = subprocess.run(
        [*BK, "run", str(cfgfile), "-o", str(tmp_path / "o.nc"), "--checkpoint-every", "-1"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2 and "checkpoint_every" in r.stderr
    r = subprocess.run(
        [
            *BK,
            "run",
            str(cfgfile),
            "-o",
            str(tmp_path / "o.nc"),
            "--json",
            "--checkpoint-every",
            "1000",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 0 and json.loads(r.stdout)["events"] == 6
