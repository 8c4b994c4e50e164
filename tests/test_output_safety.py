"""Files the user owns and I/O errors (issue 27): --overwrite removes only what bkwaves
wrote, at every depth; a user's OUT.lock is refused, never overwritten; a failed write
(full disk, a folder removed or made read-only) ends in one line, keeps what fits and
the last checkpoint; damaged outputs and sweep stores are reported in one line; a sweep
re-run verifies what it skips."""

from __future__ import annotations

import errno
import subprocess
import sys

import numpy as np
import pytest
from small_run import SMALL, SMALL_TOML

import bkwaves as bk
from bkwaves import io
from bkwaves.config import parse_config
from bkwaves.io import OutputError, partial_path
from bkwaves.runner import OutputFull, checkpoint_path, resume, run

BK = [sys.executable, "-m", "bkwaves"]


def _lines(stderr: str) -> list[str]:
    return [ln for ln in stderr.splitlines() if ln.strip()]


# --------------------------------------------------------------------------- ownership


def test_overwrite_never_removes_a_users_file_deep_inside_a_zarr_output(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(SMALL_TOML)
    out = tmp_path / "o.zarr"
    assert (
        subprocess.run([*BK, "run", str(cfg), "-o", str(out)], capture_output=True).returncode == 0
    )
    for mine in (out / "u" / "notes.txt", out / "u" / "c" / "mine.txt"):
        mine.write_text("keep")
        r = subprocess.run(
            [*BK, "run", str(cfg), "-o", str(out), "--overwrite"], capture_output=True, text=True
        )
        assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
        lines = _lines(r.stderr)
        assert len(lines) == 1 and "not written by bkwaves" in lines[0], r.stderr
        assert mine.read_text() == "keep"
        assert bk.load(out)[0].sizes["t"] == 61  # the output is intact
        mine.unlink()
    # without foreign files: replaced
    r = subprocess.run(
        [*BK, "run", str(cfg), "-o", str(out), "--overwrite"], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stderr


def test_a_users_lock_file_is_refused_and_kept(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(SMALL_TOML)
    out = tmp_path / "o.nc"
    lock = tmp_path / "o.nc.lock"
    lock.write_text("my notes, not a lock\n")
    r = subprocess.run([*BK, "run", str(cfg), "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    lines = _lines(r.stderr)
    assert len(lines) == 1 and str(lock) in lines[0] and "not written by bkwaves" in lines[0]
    assert lock.read_text() == "my notes, not a lock\n"
    assert not partial_path(out).exists() and not out.exists()
    # a lock a killed bkwaves run left (its PID, as earlier versions wrote it, or the
    # current text): taken over, and removed when the run ends
    for stale in ("999999\n", "bkwaves lock pid 999999\n"):
        lock.write_text(stale)
        r = subprocess.run(
            [*BK, "run", str(cfg), "-o", str(out), "--overwrite"], capture_output=True, text=True
        )
        assert r.returncode == 0, r.stderr
        assert not lock.exists()


# --------------------------------------------------------------------------- I/O errors


def test_enospc_while_taking_the_lock_is_one_line_and_leaves_nothing(tmp_path, monkeypatch):
    real_open = open

    def full_open(path, mode="r", *a, **k):
        if str(path).endswith(".tmp") and ".lock." in str(path) and "x" in mode:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return real_open(path, mode, *a, **k)

    monkeypatch.setattr("builtins.open", full_open)
    out = tmp_path / "o.nc"
    with pytest.raises(OutputError) as err:
        run(parse_config(SMALL), out)
    monkeypatch.undo()
    msg = err.value.strerror
    assert "\n" not in msg and msg.startswith(f"cannot write {out}: No space left on device")
    assert not any(tmp_path.iterdir())


def test_enospc_while_creating_the_zarr_store_is_one_line_and_leaves_nothing(tmp_path, monkeypatch):
    def full(self):
        (self._zarr_store).mkdir()
        raise OSError(errno.ENOSPC, "No space left on device", str(self._zarr_store))

    monkeypatch.setattr(io.RunWriter, "_create_zarr", full)
    from bkwaves.cli import main

    out = tmp_path / "o.zarr"
    cfg = tmp_path / "c.toml"
    cfg.write_text(SMALL_TOML)
    with pytest.raises(SystemExit) as ex:
        main(["run", str(cfg), "-o", str(out), "--quiet"])
    assert ex.value.code == 1
    assert {p.name for p in tmp_path.iterdir()} == {"c.toml"}  # no partial, no lock


@pytest.mark.parametrize("failure", ["EACCES", "ENOENT"])
def test_a_folder_made_unwritable_mid_run_keeps_the_checkpoint_in_one_line(
    tmp_path, monkeypatch, failure
):
    """A write that fails mid-run (the folder made read-only, or OUT.partial removed):
    one line naming the path, the records committed and the last checkpoint kept; when
    the folder is back, --resume finishes the run equal to an uninterrupted one."""
    cfg = parse_config(SMALL)
    ref = tmp_path / "ref.nc"
    run(cfg, ref)
    out = tmp_path / "o.nc"
    calls = []
    write = io._write_bytes

    def failing(path, data):
        calls.append(path)
        if len(calls) == 6:
            if failure == "EACCES":
                raise PermissionError(errno.EACCES, "Permission denied", str(path))
            raise FileNotFoundError(errno.ENOENT, "No such file or directory", str(path))
        write(path, data)

    monkeypatch.setattr(io, "_write_bytes", failing)
    with pytest.raises(OutputError) as err:
        run(cfg, out, chunk=300, flush_every=0.0, checkpoint_every=1e-9)
    monkeypatch.undo()
    msg = err.value.strerror
    assert not isinstance(err.value, OutputFull)
    assert "\n" not in msg and msg.startswith(f"cannot write {out}: ")
    assert f"bkwaves run --resume {out}" in msg and "kept" in msg
    assert checkpoint_path(out).exists()
    s = resume(out)
    assert not s.interrupted
    a, ca = bk.load(out)
    b, cb = bk.load(ref)
    np.testing.assert_array_equal(a.u.values, b.u.values)
    np.testing.assert_array_equal(a.t.values, b.t.values)
    assert ca.equals(cb)


def test_the_cli_reports_a_failed_write_in_one_line(tmp_path, monkeypatch, capsys):
    from bkwaves.cli import main

    def failing(path, data):
        raise PermissionError(errno.EACCES, "Permission denied", str(path))

    monkeypatch.setattr(io, "_write_bytes", failing)
    cfg = tmp_path / "c.toml"
    cfg.write_text(SMALL_TOML)
    with pytest.raises(SystemExit) as ex:
        main(["run", str(cfg), "-o", str(tmp_path / "o.nc"), "--quiet"])
    assert ex.value.code == 1
    err = capsys.readouterr().err
    assert (
        len(_lines(err)) == 1 and err.startswith("Error: cannot write") and "Traceback" not in err
    )


def test_a_full_disk_keeps_every_snapshot_that_fits(tmp_path, monkeypatch):
    """A disk of fixed size (simulated at the write layer): the records of a commit
    block that fit are kept (the block is split down to single records), not dropped
    whole (the run here commits its 61 snapshots as one block)."""
    cfg = parse_config(SMALL)
    ref = tmp_path / "ref.nc"
    run(cfg, ref)
    b, _ = bk.load(ref)
    record = 200 * 17  # bytes of one snapshot (u, u_t: 8 bytes, sliding: 1, per block)
    kept = []
    write = io._write_bytes
    for capacity in (4, 20, 45):  # snapshots' worth of space
        used = []

        def sized(path, data, limit=capacity * record + 30_000, used=used):
            if path.suffix == ".nc":
                if sum(used) + len(data) > limit:
                    raise OSError(errno.ENOSPC, "No space left on device", str(path))
                used.append(len(data))
            write(path, data)

        monkeypatch.setattr(io, "_write_bytes", sized)
        out = tmp_path / f"full{capacity}.nc"
        with pytest.raises(OutputFull):
            run(cfg, out)
        monkeypatch.undo()
        with pytest.warns(UserWarning, match="unfinished"):
            a, _ = bk.load(out)
        n = a.sizes["t"]
        assert 0 < n < 61, (capacity, n)
        np.testing.assert_array_equal(a.u.values, b.u.values[:n])
        kept.append(n)
    assert kept[0] < kept[1] < kept[2]


def test_load_of_a_zarr_run_killed_before_its_store_existed_is_one_line(tmp_path):
    out = tmp_path / "o.zarr"
    w = io.RunWriter(out, np.arange(3.0), {"u": ("1", "u", "f8")})
    w.abandon()  # (a run killed here: a marker, no store yet)
    import shutil

    shutil.rmtree(partial_path(out) / out.name)
    with pytest.raises(bk.ParameterError, match="has no records"):
        bk.load(out)


@pytest.mark.parametrize("damage", ["cut", "metadata"])
def test_plot_of_a_damaged_netcdf_is_one_line(tmp_path, damage):
    """A file cut short, or whose metadata near its start is overwritten (the audit's
    case: h5netcdf's File, half-built when it failed, raised AttributeError at exit
    under 'Exception ignored in', after the one-line error)."""
    cfg = tmp_path / "c.toml"
    cfg.write_text(SMALL_TOML)
    out = tmp_path / "o.nc"
    assert (
        subprocess.run([*BK, "run", str(cfg), "-o", str(out)], capture_output=True).returncode == 0
    )
    data = bytearray(out.read_bytes())
    if damage == "cut":
        data[len(data) // 3 : len(data) // 3 + 4096] = b"\xff" * 4096
        out.write_bytes(bytes(data[: len(data) // 2]))
    else:
        data[200:2200] = bytes(2000)
        out.write_bytes(bytes(data))
    r = subprocess.run([*BK, "plot", str(out), "-o", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert "Exception ignored" not in r.stderr, r.stderr
    lines = _lines(r.stderr)
    assert len(lines) == 1 and lines[0].startswith(f"Error: cannot read {out}")


# --------------------------------------------------------------------------- sweeps

WAVE = {
    "task": "wave",
    "base": {"gamma": 0.3},
    "axes": {
        "u_plus": {"linspace": {"start": 0.2, "stop": 0.8, "num": 8}},
        "gamma": {"values": [0.0, 0.3]},
    },
}


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    cluster = LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0"
    )
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_a_sweep_that_lost_a_value_chunk_recomputes_its_points(tmp_path, client):
    from bkwaves.sweeps import SweepRepairWarning, sweep

    out = tmp_path / "w.zarr"
    first = sweep(WAVE, out, client=client)
    assert first.computed == 16
    chunks = [p for p in (out / "c").rglob("*") if p.is_file()]
    assert chunks, "the value array c has chunk files"
    for p in chunks:
        p.unlink()  # the values of c are lost: they read as NaN
    with pytest.warns(SweepRepairWarning, match="no longer hold the values"):
        again = sweep(WAVE, out, client=client)
    assert again.skipped == 0 and again.computed == 16
    np.testing.assert_array_equal(again.dataset["c"].values, first.dataset["c"].values)
    assert np.isfinite(again.dataset["c"].values).all()
    third = sweep(WAVE, out, client=client)
    assert (third.computed, third.skipped) == (0, 16)


def test_a_sweep_notices_a_missing_per_point_catalog(tmp_path, client):
    from pathlib import Path

    from bkwaves.sweeps import SweepRepairWarning, points_dir, sweep

    base = bk.config.load_config(
        Path(__file__).parents[1] / "examples" / "free_boundary_random.toml"
    ).to_dict()
    base["run"] = {"t_end": 300.0}
    doc = {
        "task": "run",
        "base": base,
        "axes": {"seed": {"seeds": 2}},
        "output": {"catalogs": True},
    }
    out = tmp_path / "s.zarr"
    assert sweep(doc, out, client=client).computed == 2
    lost = sorted(points_dir(out).glob("*.events.parquet"))[0]
    lost.unlink()
    with pytest.warns(SweepRepairWarning, match="miss their files"):
        again = sweep(doc, out, client=client)
    assert (again.computed, again.skipped) == (1, 1)
    assert lost.exists()


def test_a_damaged_sweep_store_is_one_line(tmp_path, client):
    from bkwaves.sweeps import sweep

    out = tmp_path / "w.zarr"
    sweep(WAVE, out, client=client)
    for p in (out / "status" / "c").rglob("*"):
        if p.is_file():
            p.write_bytes(b"\x00garbage" * 10)
    toml = tmp_path / "w.toml"
    toml.write_text(
        'task = "wave"\n[base]\ngamma = 0.3\n[axes.u_plus]\n'
        "linspace = {start = 0.2, stop = 0.8, num = 8}\n[axes.gamma]\nvalues = [0.0, 0.3]\n"
    )
    r = subprocess.run(
        [*BK, "sweep", str(toml), "-o", str(out), "--workers", "1"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    lines = [ln for ln in _lines(r.stderr) if "distributed" not in ln]
    assert len(lines) == 1 and "damaged" in lines[0] and "status" in lines[0], r.stderr


def test_a_finished_point_is_written_while_the_others_compute(tmp_path, client):
    """A point is in the store as soon as it arrives, not when the next one does (the
    store was written only when a point arrived: a fast point waited for a slow one)."""
    import threading
    import time

    import zarr

    from bkwaves.sweeps import DONE, sweep

    doc = {
        "task": "run",
        # the pulse costs ~45 blocks per step whatever the length: 20 and 21 blocks are
        # done at once; 30000 take ~6e6 steps at step 0.005 (h = 2.5e-4), seconds even on
        # an idle machine (at the default step, 6e5 steps, it ended 0.12 s after the fast
        # points on an idle machine and the test could not tell)
        "base": {**SMALL, "run": {"t_end": 1500.0, "step": 0.005}, "output": {}},
        "axes": {"domain.blocks": {"values": [20, 21, 30000]}},
    }
    out = tmp_path / "two.zarr"
    done_at, result = [], {}

    def go():
        result["r"] = sweep(doc, out, client=client)
        result["end"] = time.perf_counter()

    th = threading.Thread(target=go)
    th.start()
    while th.is_alive():
        try:
            status = zarr.open_group(str(out), mode="r", use_consolidated=False)["status"][...]
        except Exception:  # noqa: BLE001 - not created yet, or being written
            status = np.zeros(0)
        if (status == DONE).sum() >= 2 and not done_at:  # both fast points
            done_at.append(time.perf_counter())
        time.sleep(0.02)
    th.join()
    assert result["r"].computed == 3
    assert done_at, "the fast points were not in the store before the sweep ended"
    assert result["end"] - done_at[0] > 0.5  # the slow point was still running


def test_reading_a_damaged_sweep_store_is_one_line(tmp_path, client):
    from bkwaves.sweeps import load_sweep_result, sweep

    out = tmp_path / "w.zarr"
    sweep(WAVE, out, client=client)
    for p in (out / "c" / "c").rglob("*"):
        if p.is_file():
            p.write_bytes(b"\x00garbage" * 10)
    with pytest.raises(bk.ParameterError, match="damaged") as err:
        load_sweep_result(out)
    assert "\n" not in str(err.value)
    r = subprocess.run([*BK, "plot", str(out), "-o", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert len(_lines(r.stderr)) == 1 and "damaged" in r.stderr
