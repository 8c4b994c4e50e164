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
    # the seed the run used: the config's, or none ("") when nothing in it is random
    if cfg.seed is not None:
        assert ds.attrs["seed"] == cfg.seed
    elif not cfg.random:
        assert ds.attrs["seed"] == ""
    assert np.all(np.isfinite(ds.u.values))
    if cfg.model == "chain":
        # the sliding state is consistent with the velocities: stuck blocks move with v
        # (u_t is du/dt in 1/s in SI outputs: v converted the same way)
        v = cfg.params.v
        if cfg.physical and cfg.output_units == "native":
            v = v / cfg.params.units.time_scale
        moving = ds.u_t.values != v
        assert np.array_equal(ds.sliding.values != 0, moving)
    assert catalog is not None and len(catalog) == summary["events"]
    if cfg.max_events is not None:
        assert summary["events"] == cfg.max_events
    # UDUNITS-parseable units; dimensionless ones say how they are scaled
    for v in (*ds.data_vars.values(), ds.t, ds.x):
        assert v.attrs["units"] in ("1", "m", "s", "s-1"), (v.name, v.attrs["units"])
    assert all(u in ("1", "m", "s", "m2") for u in catalog.attrs["units"].values())
    if cfg.physical:
        assert ds.t.attrs["units"] == "s" and ds.x.attrs["units"] == "m"
        assert catalog.attrs["units"]["t_start"] == "s"
        if "u_t" in ds:
            assert ds.u_t.attrs["units"] == "s-1"
    else:
        assert "t' = t sqrt(k_p/m)" in ds.t.attrs["scale"]
        assert "t' = t sqrt(k_p/m)" in catalog.attrs["scales"]["t_start"]
    # snapshots in time start with the initial state
    if cfg.snapshot_every is not None:
        assert ds.t.values[0] == 0.0
    if cfg.snapshot_every is not None and cfg.model == "free_boundary":
        from bkwaves.config import initial_state

        np.testing.assert_array_equal(ds.u.values[0], initial_state(cfg))
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
    # u_t = du/dt in 1/s
    np.testing.assert_allclose(a.u_t.values, b.u_t.values / u.time_scale, rtol=1e-12)
    assert a.u_t.attrs["units"] == "s-1" and b.u_t.attrs["units"] == "1"


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


LONG_FB = (
    'model = "free_boundary"\nseed = 1\n[params]\ngamma = 0.3\nv = 1e-2\ndx = 1e-3\n'
    '[domain]\nlength = 3000.0\ngrid = 15000\nboundary = "periodic"\n'
    '[initial]\nkind = "random"\nmean = 0.5\namplitude = 0.02\ncorrelation_length = 25.0\n'
    "[run]\nt_end = 1e7\n[output]\nsnapshot_every = 20.0\n"
)


def _committed(out) -> int:
    """Records a running or killed run has committed so far (0 while none)."""
    import warnings

    from bkwaves.io import partial_path

    if not partial_path(out).exists() and not out.exists():
        return 0
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return bk.load(out)[0].sizes["t"]
    except Exception:  # noqa: BLE001 - the writer is still creating its first records
        return 0


def _start_long_run(tmp_path, suffix, *extra):
    cfg = tmp_path / "long.toml"
    cfg.write_text(LONG_FB)
    out = tmp_path / f"long{suffix}"
    p = subprocess.Popen(
        [*BK, "run", str(cfg), "-o", str(out), "--json", *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.time() + 90
    while time.time() < deadline and _committed(out) < 3:
        time.sleep(0.2)
    return cfg, out, p


def _messages(stderr: str) -> list[str]:
    """The lines of stderr besides the estimate warnings given before a run starts (these
    runs are long or large on purpose: bkwaves.limits.LongRunWarning, which the command
    line prints as one line `Warning: ...`)."""
    return [ln for ln in stderr.splitlines() if ln.strip() and not ln.startswith("Warning: ")]


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_sigterm_stops_cleanly_keeps_the_records_and_says_how_to_resume(tmp_path, suffix):
    cfg, out, p = _start_long_run(tmp_path, suffix)
    # a second run on the same output fails at once, naming the reason
    t0 = time.time()
    r = subprocess.run(
        [*BK, "run", str(cfg), "-o", str(out), "--overwrite"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2 and "being written by another bkwaves run" in r.stderr
    assert time.time() - t0 < 30
    os.kill(p.pid, signal.SIGTERM)
    stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == 143, stderr
    summary = json.loads(stdout)
    assert summary["interrupted"] and summary["signal"] == "SIGTERM"
    lines = _messages(stderr)
    assert len(lines) == 1 and f"bkwaves run --resume {out}" in lines[0]
    assert not out.exists()  # an incomplete run is not published
    with pytest.warns(UserWarning, match="unfinished"):
        ds, catalog = bk.load(out)
    assert ds.sizes["t"] == summary["snapshots"] >= 3
    assert catalog is not None
    from bkwaves.runner import checkpoint_path

    assert checkpoint_path(out).exists()


def test_sigkill_leaves_every_snapshot_with_its_catalog(tmp_path):
    """Catalog rows are committed with (before) the snapshots they belong with: after
    SIGKILL, every event that ended before the last kept snapshot is in the catalog."""
    cfg, out, p = _start_long_run(tmp_path, ".nc")
    os.kill(p.pid, signal.SIGKILL)
    p.communicate(timeout=60)
    with pytest.warns(UserWarning, match="unfinished"):
        ds, catalog = bk.load(out)
    t_last = float(ds.t.values[-1])
    assert ds.sizes["t"] >= 3 and catalog is not None
    ref_cfg = load_config(cfg)
    ref_cfg = parse_config({**ref_cfg.to_dict(), "run": {"t_end": t_last}})
    run(ref_cfg, tmp_path / "ref.nc")
    ref_ds, ref = bk.load(tmp_path / "ref.nc")
    np.testing.assert_array_equal(ref_ds.u.values[-1], ds.u.values[-1])
    ended = ref[ref.t_end <= t_last].reset_index(drop=True)
    assert len(ended) > 0
    assert len(catalog) >= len(ended)
    assert catalog.iloc[: len(ended)].equals(ended)


CHAIN_SIGNAL = (
    'model = "chain"\n[params]\ngamma = 0.3\nv = 0.0\ndx = 0.05\n'
    '[domain]\nblocks = 20000\n[initial]\nkind = "uniform"\nvalue = 0.6\n'
    '[[triggers]]\nblock = 0\nkind = "kick"\nvelocity = 2.0\n'
    "[run]\nt_end = 1e6\n[output]\nsnapshot_every = 1.0\n"
)


def test_sigint_before_the_first_chunk_ends_keeps_what_was_computed(tmp_path):
    from bkwaves.io import partial_path
    from bkwaves.runner import checkpoint_path

    cfg = tmp_path / "c.toml"
    cfg.write_text(CHAIN_SIGNAL)
    out = tmp_path / "c.nc"
    p = subprocess.Popen(
        [*BK, "run", str(cfg), "-o", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.time() + 60
    while time.time() < deadline and not partial_path(out).exists():
        time.sleep(0.02)
    time.sleep(1.0)
    os.kill(p.pid, signal.SIGINT)  # the first chunk (several seconds) is running
    stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == 130, stderr
    assert "interrupted by SIGINT" in stderr and "--resume" in stderr
    assert "Traceback" not in stderr
    with pytest.warns(UserWarning, match="unfinished"):
        ds, _ = bk.load(out)
    # every snapshot the first chunk computed is kept
    n = ds.sizes["t"]
    assert n >= 2 and f"kept {n} snapshots" in stderr
    np.testing.assert_array_equal(ds.t.values, np.arange(n))
    assert checkpoint_path(out).exists()


def _tmpfs_available() -> bool:
    import shutil

    if shutil.which("unshare") is None:
        return False
    r = subprocess.run(
        ["unshare", "-rm", "sh", "-c", "mount -t tmpfs -o size=64k tmpfs /mnt"],
        capture_output=True,
    )
    return r.returncode == 0


SMALL_CHAIN = (
    'model = "chain"\nseed = 5\n[params]\ngamma = 0.3\nv = 1e-3\ndx = 0.05\nbeta = 5.0\n'
    '[domain]\nblocks = 100\nboundary = "periodic"\n'
    '[initial]\nkind = "random"\nmean = 0.5\namplitude = 0.3\ncorrelation_length = 2.0\n'
    "[run]\nt_end = 1000.0\n[output]\nsnapshot_every = 1.0\n"
)


@pytest.mark.skipif(not _tmpfs_available(), reason="needs unshare -rm to mount a small tmpfs")
@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_a_full_disk_keeps_what_was_written_and_says_so_in_one_line(tmp_path, suffix):
    cfg = tmp_path / "small.toml"
    cfg.write_text(SMALL_CHAIN)
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    out = mnt / f"o{suffix}"
    script = (
        f"mount -t tmpfs -o size=200k tmpfs {mnt} && "
        f"{sys.executable} -m bkwaves run {cfg} -o {out} --quiet; rc=$?; "
        f"ls {out}.partial > /dev/null && echo partial-kept; exit $rc"
    )
    r = subprocess.run(
        ["unshare", "-rm", "sh", "-c", script],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PYTHONPATH": os.environ.get("PYTHONPATH", "")},
    )
    assert r.returncode == 1, (r.returncode, r.stderr)  # not 139 (segfault), not 0
    lines = _messages(r.stderr)
    assert len(lines) == 1 and lines[0].startswith("Error: disk full writing"), r.stderr
    assert "kept" in lines[0] and "needs about" in lines[0] and "free" in lines[0]
    assert "partial-kept" in r.stdout


def test_a_full_disk_mid_run_keeps_the_committed_records(tmp_path, monkeypatch):
    """Simulated: the third commit of snapshots fails with ENOSPC."""
    import errno

    from bkwaves.io import RunWriter
    from bkwaves.runner import OutputFull

    cfg = parse_config(LOADING)
    calls = []
    commit = RunWriter.commit

    def failing(self):
        if self._buf_t:
            calls.append(len(self._buf_t))
            if len(calls) == 3:
                raise OSError(errno.ENOSPC, "No space left on device")
        commit(self)

    monkeypatch.setattr(RunWriter, "commit", failing)
    out = tmp_path / "full.nc"
    with pytest.raises(OutputFull) as err:
        run(cfg, out, chunk=300, flush_every=0.0)
    monkeypatch.undo()
    msg = str(err.value.strerror)
    assert "\n" not in msg and msg.startswith(f"disk full writing {out} (the run reached t = ")
    kept = calls[0] + calls[1]
    assert f"kept {kept} snapshots" in msg
    # the size it asks for is the one the warning before the run gives
    from bkwaves.limits import _bytes, estimate

    assert f"needs about {_bytes(estimate(cfg).output_bytes)} of snapshots" in msg
    with pytest.warns(UserWarning, match="unfinished"):
        ds, catalog = bk.load(out)
    assert ds.sizes["t"] == kept and catalog is not None
    # the catalog holds every event that ended before the last kept snapshot
    assert (catalog.t_end <= ds.t.values[-1]).sum() >= 1


def test_run_refuses_an_existing_output_and_never_deletes_foreign_files(tmp_path):
    cfg = tmp_path / "small.toml"
    cfg.write_text(SMALL_CHAIN.replace("t_end = 1000.0", "t_end = 10.0"))
    d = tmp_path / "d.zarr"
    (d / "sub").mkdir(parents=True)
    (d / "precious.txt").write_text("keep")
    for extra in ([], ["--overwrite"]):
        r = subprocess.run(
            [*BK, "run", str(cfg), "-o", str(d), *extra], capture_output=True, text=True
        )
        assert r.returncode == 2 and "Traceback" not in r.stderr
    assert (d / "precious.txt").read_text() == "keep" and (d / "sub").is_dir()
    out = tmp_path / "o.nc"
    r = subprocess.run([*BK, "run", str(cfg), "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([*BK, "run", str(cfg), "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 2 and "--overwrite" in r.stderr
    r = subprocess.run(
        [*BK, "run", str(cfg), "-o", str(out), "--overwrite"], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stderr
    assert bk.load(out)[0].sizes["t"] == 11


LOADING = {
    "model": "chain",
    "seed": 5,
    "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05, "beta": 5.0},
    "domain": {"blocks": 300, "boundary": "periodic"},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 2.0},
    "run": {"max_events": 12},
    "output": {"snapshot_events": 1},
}


CHAIN_NOISE = {"law": "exponential", "rate": 1e-2, "phi0": 0.05, "kick": 0.05}


@pytest.mark.parametrize(
    "suffix,noise", [(".nc", None), (".zarr", None), (".nc", CHAIN_NOISE)], ids=str
)
def test_resumed_chain_run_equals_the_uninterrupted_one_bit_for_bit(tmp_path, suffix, noise):
    from bkwaves.runner import checkpoint_path, resume

    cfg = parse_config({**LOADING, "noise": noise} if noise else LOADING)
    ref = run(cfg, tmp_path / f"ref{suffix}", chunk=300)
    if noise:  # spontaneous slips, counted and marked, and resumed with their generator
        assert ref.extra["counters"]["noise_slips"] > 0
    out = tmp_path / f"cut{suffix}"
    # the first, system-size event takes most of the steps: find a cut after it
    for k in range(ref.extra["counters"]["steps"] // 300, 0, -1):
        first = run(cfg, out, chunk=300, overwrite=True, _stop_after_chunks=k)
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
    assert (ca["kind"] == "noise").any() == bool(noise)


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
        first = run(cfg, out, chunk=chunk, overwrite=True, _stop_after_chunks=k)
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
    for k in range(ref.extra["counters"]["steps"] // 300, 0, -1):
        out = tmp_path / f"crash{k}.nc"  # (a run that completes publishes its output)
        cut = run(cfg, out, chunk=300, _stop_after_chunks=k)
        if cut.interrupted and 0 < cut.events < ref.events:
            break
    ds, _ = bk.load(out)
    # simulate records written after the checkpoint by a run that then died
    w = RunWriter(
        out,
        ds.x.values,
        {"u": ("1", "u", "f8"), "u_t": ("1", "u_t", "f8"), "sliding": ("1", "s", "i1")},
        resume_count=ds.sizes["t"],
    )
    zeros = np.zeros(ds.sizes["x"])
    w.append(1e9, u=zeros, u_t=zeros, sliding=zeros)
    w.close(publish=False)  # the run died before it was complete
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
