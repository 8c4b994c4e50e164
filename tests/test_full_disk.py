"""A full disk (or a file past ``ulimit -f``) while a run or a sweep writes NetCDF or Zarr:
never a crash, one line, every computed record and the checkpoint kept, the user's own
files untouched, and the run finished by ``--resume`` equal to an uninterrupted one.

HDF5 does not survive a failed write (h5py: "file write failed ... errno = 28", then
SIGSEGV), so these run bkwaves in a subprocess: a crash fails the test instead of
killing pytest. The file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored: writes fail with
EFBIG) needs no privilege; the full disk is a small tmpfs mounted in a user namespace
(``unshare -rm``), skipped where that is not allowed."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest
from small_run import SMALL, SMALL_TOML

import bkwaves as bk
from bkwaves import _nc_publish, io
from bkwaves.config import parse_config
from bkwaves.io import partial_path
from bkwaves.runner import checkpoint_path, resume, run

#: bytes of the 61 snapshots of SMALL (u, u_t: 8 bytes a block, sliding: 1)
SMALL_DATA = 61 * 200 * 17

# `bkwaves run` as the console script runs it, with a file-size limit and the merged
# file written in memory or by the child process
LIMITED = textwrap.dedent(
    """
    import resource, sys
    limit, in_memory = int(sys.argv[1]), int(sys.argv[2])
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    from bkwaves import _nc_publish, _signals
    _nc_publish.IN_MEMORY_BYTES = in_memory
    from bkwaves.cli import _main
    _main(sys.argv[3:], _signals, process=True)
    """
)


def _same_run(out: Path, ref: Path) -> None:
    a, ca = bk.load(out)
    b, cb = bk.load(ref)
    for name in ("t", "u", "u_t", "sliding"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert ca.equals(cb)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    d = tmp_path_factory.mktemp("ref")
    (d / "small.toml").write_text(SMALL_TOML)
    run(parse_config(SMALL), d / "ref.nc")
    return d


@pytest.mark.parametrize("where", ["memory", "child"])
def test_publishing_past_a_file_size_limit_is_one_line_and_resumes(tmp_path, reference, where):
    """The run's files fit under the limit (its snapshots are committed in pieces that
    do), the merged NetCDF does not: HDF5 never meets the failed write in the run's
    process (in memory: Python writes the file; child: the child fails, the run
    reports it). Before: SIGSEGV or h5py's 'Exception ignored' tracebacks."""
    out = tmp_path / "o.nc"
    mine = tmp_path / "o.nc.notes.txt"
    mine.write_text("my notes")
    limit = 150_000  # above every piece the run writes, below the merged file
    r = subprocess.run(
        [sys.executable, "-c", LIMITED, str(limit), str(0 if where == "child" else 1 << 30)]
        + ["run", str(reference / "small.toml"), "-o", str(out), "--quiet"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 1, (r.returncode, r.stderr)  # not -11 / 139 (SIGSEGV), not 0
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith(f"Error: file size limit reached publishing {out}"), lines[0]
    assert "kept all 61 snapshots" in lines[0] and f"bkwaves run --resume {out}" in lines[0]
    assert "raise the limit" in lines[0]
    assert not out.exists() and partial_path(out).is_dir() and checkpoint_path(out).exists()
    assert not (partial_path(out) / "final").exists()
    assert mine.read_text() == "my notes"
    s = resume(out)  # (no limit now)
    assert not s.interrupted and s.snapshots == 61
    _same_run(out, reference / "ref.nc")
    assert not partial_path(out).exists() and not checkpoint_path(out).exists()
    assert mine.read_text() == "my notes"


def _userns_tmpfs() -> bool:
    if shutil.which("unshare") is None or not sys.platform.startswith("linux"):
        return False
    r = subprocess.run(
        ["unshare", "-rm", "sh", "-c", "mount -t tmpfs -o size=64k tmpfs /mnt"],
        capture_output=True,
    )
    return r.returncode == 0


# the run on a tmpfs of each size, then the disk made larger and the run finished
FULL = textwrap.dedent(
    """
    set -u
    py=$1; cfg=$2; mnt=$3; suffix=$4; shift 4
    for size in "$@"; do
      d=$mnt/$size; mkdir -p $d
      mount -t tmpfs -o size=$size tmpfs $d || exit 90
      printf 'my notes' > $d/notes.txt
      $py -m bkwaves run $cfg -o $d/o$suffix --quiet > $d.stdout 2> $d.stderr
      echo $? > $d.rc
      ls -a $d > $d.files
      mount -o remount,size=64m $d
      $py -c "$RECOVER" $d/o$suffix > $d.recovered 2>&1
      cat $d/notes.txt > $d.notes
      umount $d
    done
    """
)
RECOVER = textwrap.dedent(
    """
    import sys, warnings
    warnings.simplefilter("ignore")
    from pathlib import Path
    import bkwaves as bk
    from bkwaves.runner import checkpoint_path, resume
    out = Path(sys.argv[1])
    if checkpoint_path(out).exists():
        resume(out); print("resumed")
    elif bk.io.partial_path(out).exists():
        bk.io.finalize(out); print("finalized")
    else:
        print("published" if out.exists() else "nothing")
    """
)


@pytest.mark.skipif(not _userns_tmpfs(), reason="needs unshare -rm to mount a small tmpfs")
@pytest.mark.parametrize(
    "suffix, sizes",
    [
        # mid-run (some snapshots fit), at the publication, and room for the whole
        # NetCDF (0.23 MB; on a 2 to 9 MB disk the 9 MB file HDF5 wrote before
        # crashed the process)
        (".nc", ["96k", "256k", "400k", "2m", "8m"]),
        (".zarr", ["64k", "96k", "160k", "200k", "1m"]),
    ],
)
def test_a_full_disk_at_every_phase_is_one_line_and_the_run_finishes(
    tmp_path, reference, suffix, sizes
):
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    r = subprocess.run(
        ["unshare", "-rm", "sh", "-c", FULL, "full", sys.executable]
        + [str(reference / "small.toml"), str(mnt), suffix, *sizes],
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "RECOVER": RECOVER},
    )
    assert r.returncode == 0, r.stderr
    phases = set()
    for size in sizes:
        d = mnt / size
        rc = int((mnt / f"{size}.rc").read_text())
        err = (mnt / f"{size}.stderr").read_text()
        recovered = (mnt / f"{size}.recovered").read_text().strip().splitlines()
        lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("Warning")]
        assert rc in (0, 1), (size, rc, err)  # never a signal (139: SIGSEGV)
        assert "Traceback" not in err and "Exception ignored" not in err, (size, err)
        assert (mnt / f"{size}.notes").read_text() == "my notes", size
        if rc == 1:
            assert len(lines) == 1 and lines[0].startswith("Error: disk full "), (size, err)
            phase = lines[0].split()[3]  # writing (mid-run) or publishing (complete)
            phases.add(phase)
            if phase == "publishing":
                assert "kept all 61 snapshots" in lines[0], lines
                if f"`bkwaves run --resume {d}/o{suffix}` publishes it" in lines[0]:
                    assert recovered[-1:] == ["resumed"], (size, recovered)
                    phases.add("resumed")
                else:  # (no room for the checkpoint of its end)
                    assert "publish it with bkwaves.io.finalize" in lines[0], lines
                    assert recovered[-1:] == ["finalized"], (size, recovered)
            else:
                assert recovered[-1:] in (["resumed"], ["finalized"]), (size, recovered)
        else:
            assert not lines and recovered[-1:] == ["published"], (size, err, recovered)
    # the sizes reach both phases (and a NetCDF publication that kept its checkpoint)
    assert {"writing", "publishing"} <= phases, phases
    assert suffix == ".zarr" or "resumed" in phases, phases


def _blocks_of(tmp_path, name, x, y, records, per_block, variables):
    """An unfinished output of ``records`` random records in blocks of ``per_block``."""
    rng = np.random.default_rng(7)
    w = io.RunWriter(tmp_path / f"{name}.nc", x, variables, y=y, flush_every=1e9)
    shape = (len(x),) if y is None else (len(y), len(x))
    for i in range(0, records, per_block):
        k = min(per_block, records - i)
        t = np.arange(i, i + k, dtype=float)
        w.append_block(t, **{v: rng.random((k, *shape)) for v in variables})
        w.commit()
    w.abandon()
    return io._blocks(w.partial / "snapshots")


CHAIN = {"u": ("1", "u", "f8"), "u_t": ("1", "u_t", "f8"), "sliding": ("1", "s", "u1")}


@pytest.mark.parametrize(
    "name, nx, ny, records, per_block",
    [
        ("one record", 200, None, 1, 1),
        ("many records", 50, None, 9000, 1500),  # 3 chunks in t (4096 at most)
        ("wide records", 300_000, None, 5, 2),  # 2 chunks per record of u
        ("plane", 64, 48, 300, 40),
    ],
)
def test_the_merged_netcdf_is_sized_before_it_is_written(
    tmp_path, monkeypatch, name, nx, ny, records, per_block
):
    """The bound the free space is checked against holds, and is tight (the file is
    its data, its chunks cut evenly: no 4 MiB chunk for a few records); the file is
    the same built in memory or by the child process."""
    x = np.arange(float(nx))
    y = None if ny is None else np.arange(float(ny))
    blocks = _blocks_of(tmp_path, "b", x, y, records, per_block, CHAIN)
    need = _nc_publish.merged_bytes(blocks)
    data = records * (nx * (ny or 1)) * 17 + records * 8 + 8 * (nx + (ny or 0))
    sizes = {}
    for where, limit in (("memory", 1 << 40), ("child", 0)):
        monkeypatch.setattr(_nc_publish, "IN_MEMORY_BYTES", limit)
        f = tmp_path / f"{where}.nc"
        _nc_publish.merge(blocks, f, lambda: None)
        sizes[where] = f.stat().st_size
        assert sizes[where] <= need, (where, sizes[where], need)
    assert need <= 1.03 * max(sizes.values()) + (128 << 10), (need, sizes)
    assert max(sizes.values()) <= 1.02 * data + (64 << 10), (sizes, data)
    a, b = io._open_nc(tmp_path / "memory.nc"), io._open_nc(tmp_path / "child.nc")
    for v in ("t", "u", "u_t", "sliding"):
        np.testing.assert_array_equal(a[v].values, b[v].values)
    assert a.sizes["t"] == records


def test_a_published_netcdf_is_about_its_data(tmp_path, reference):
    """61 snapshots of 200 blocks (0.21 MB of values): the published file was 9.3 MB
    (4 MiB chunks stored whole), larger than the free-space check assumed."""
    size = (reference / "ref.nc").stat().st_size
    assert SMALL_DATA < size < 1.15 * SMALL_DATA + (64 << 10), size


def test_a_stop_while_the_child_writes_ends_the_child(tmp_path, monkeypatch):
    """A signal while the child merges: the child is killed and reaped, the stop
    raised; the blocks are untouched."""
    blocks = _blocks_of(tmp_path, "s", np.arange(50.0), None, 2000, 500, CHAIN)
    before = {f: f.read_bytes() for _, _, f in blocks}
    monkeypatch.setattr(_nc_publish, "IN_MEMORY_BYTES", 0)
    started = []
    popen = subprocess.Popen

    def recording(*a, **kw):
        started.append(popen(*a, **kw))
        return started[-1]

    monkeypatch.setattr(subprocess, "Popen", recording)
    asked = []

    def check():
        asked.append(1)
        if started:  # the child runs: the user presses Ctrl-C
            raise io.PublishStopped

    with pytest.raises(io.PublishStopped):
        _nc_publish.merge(blocks, tmp_path / "m.nc", check)
    assert len(started) == 1 and started[0].returncode is not None
    assert {f: f.read_bytes() for _, _, f in blocks} == before


@pytest.mark.parametrize(
    "rc, stderr, errno_, words",
    [
        (3, '{"errno": 28, "message": "No space left"}\n', 28, "failed (exit 3)"),
        (-11, "RuntimeError: ... errno = 27, error message = 'File too large'", 27, "SIGSEGV"),
        (-11, "", 5, "died by SIGSEGV"),  # no errno said, room on the disk: EIO
    ],
)
def test_a_failed_child_is_one_oserror(tmp_path, rc, stderr, errno_, words):
    e = _nc_publish._child_error(rc, stderr, tmp_path / "o.nc", 1000)
    assert e.errno == errno_ and words in e.strerror and "\n" not in e.strerror
    assert e.filename == str(tmp_path / "o.nc")


SWEEP_POINT = textwrap.dedent(
    """
    import resource, sys
    from pathlib import Path
    import numpy as np, xarray as xr
    from bkwaves.sweeps import _write_point_files, points_dir
    out = Path(sys.argv[1])
    ds = xr.Dataset({"u": (("t", "x"), np.random.default_rng(1).random((40, 1000)))})
    resource.setrlimit(resource.RLIMIT_FSIZE, (100_000, resource.RLIM_INFINITY))
    import signal
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    try:
        _write_point_files(out, "p0", {"__snapshots__": ds})
        print("written")
    except OSError as e:
        print("OSError", e.errno)
    print(sorted(p.name for p in points_dir(out).iterdir()))
    """
)


def test_a_sweep_point_past_a_file_size_limit_is_an_oserror_and_leaves_nothing(tmp_path):
    """A point's snapshots (320 kB) past a 100 kB file-size limit: an OSError (the
    sweep stops in one line) and no torn file; before, HDF5 wrote into the folder."""
    r = subprocess.run(
        [sys.executable, "-c", SWEEP_POINT, str(tmp_path / "s.zarr")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, (r.returncode, r.stderr)
    out = r.stdout.splitlines()
    assert out[0] == "OSError 27", r.stdout + r.stderr
    assert json.loads(out[1].replace("'", '"')) == [], out
    assert "Exception ignored" not in r.stderr, r.stderr


def test_load_reads_what_a_failed_publication_kept(tmp_path, reference, monkeypatch):
    """In-process: the publication fails for space (the check before the merge); the
    run is kept whole with its checkpoint, bk.load reads it, --resume publishes it."""
    monkeypatch.setattr(_nc_publish, "_free", lambda folder: 1000)
    out = tmp_path / "o.nc"
    with pytest.raises(bk.runner.OutputFull) as err:
        run(parse_config(SMALL), out)
    monkeypatch.undo()
    msg = err.value.strerror
    assert msg.startswith(f"disk full publishing {out}") and "publishing needs up to" in msg, msg
    assert checkpoint_path(out).exists()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds, _ = bk.load(out)
    assert ds.sizes["t"] == 61
    resume(out)
    _same_run(out, reference / "ref.nc")


def test_the_end_checkpoint_gives_its_room_to_an_output_that_needs_it(
    tmp_path, reference, monkeypatch
):
    """A disk where the output fits only without the checkpoint of the run's end: the
    checkpoint is given up and the output published (as it was before that checkpoint
    was written first)."""
    frees = []

    def short(folder):  # the first look: just short of the need by less than a checkpoint
        frees.append(folder)
        if len(frees) == 1:
            return _nc_publish.merged_bytes(io._blocks(folder.parent / "snapshots")) - 100
        return shutil.disk_usage(folder).free

    monkeypatch.setattr(_nc_publish, "_free", short)
    out = tmp_path / "o.nc"
    s = run(parse_config(SMALL), out)
    assert not s.interrupted and len(frees) == 2
    assert out.exists() and not partial_path(out).exists() and not checkpoint_path(out).exists()
    _same_run(out, reference / "ref.nc")


SWEEP_TOML = (
    'title = "full disk"\ntask = "run"\n[base]\nmodel = "chain"\n'
    "[base.params]\ngamma = 0.3\nv = 0.0\ndx = 0.05\n[base.domain]\nblocks = 200\n"
    '[base.initial]\nkind = "uniform"\nvalue = 0.6\n'
    '[[base.triggers]]\nblock = 0\nkind = "kick"\nvelocity = 2.0\n'
    "[base.run]\nt_end = 30.0\n[base.output]\nsnapshot_every = 0.5\n"
    '[axes."params.gamma"]\nvalues = [0.3, 0.4, 0.5, 0.6]\n'
    "[output]\ncatalogs = true\nsnapshots = true\n"
)
FULL_SWEEP = textwrap.dedent(
    """
    set -u
    py=$1; spec=$2; mnt=$3; shift 3
    for size in "$@"; do
      d=$mnt/$size; mkdir -p $d
      mount -t tmpfs -o size=$size tmpfs $d || exit 90
      printf 'my notes' > $d/notes.txt
      $py -m bkwaves sweep $spec -o $d/s.zarr --workers 1 --quiet > $d.stdout 2> $d.stderr
      echo $? > $d.rc
      ls -a $d/s.zarr.points > $d.files 2>/dev/null
      mount -o remount,size=64m $d
      $py -m bkwaves sweep $spec -o $d/s.zarr --workers 1 --quiet > $d.stdout2 2> $d.stderr2
      echo $? > $d.rc2
      $py -c "$CHECK" $d/s.zarr > $d.check 2>&1
      cat $d/notes.txt > $d.notes
      umount $d
    done
    """
)
SWEEP_CHECK = textwrap.dedent(
    """
    import sys
    from pathlib import Path
    import bkwaves as bk
    out = Path(sys.argv[1])
    ds = bk.sweep_result(out)
    n = [bk.io._open_nc(out.with_name(out.name + ".points") / f"{k}.nc").sizes["t"]
         for k in ds.key.values]
    print(int(ds.status.sum()), sorted(set(n)))
    """
)


@pytest.mark.skipif(not _userns_tmpfs(), reason="needs unshare -rm to mount a small tmpfs")
def test_a_sweep_onto_a_full_disk_is_one_line_and_the_same_command_finishes(tmp_path):
    """Per-point snapshots and catalogs (0.25 MB a point) onto a disk that fills: one
    line, exit 1, no torn or temporary file among the points' files; with room, the same
    command computes the rest. Before: SIGSEGV inside HDF5 (rc 139), `.KEY.nc.tmp` and
    `.KEY.slips.parquet.tmp` left behind."""
    spec = tmp_path / "sweep.toml"
    spec.write_text(SWEEP_TOML)
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    sizes = ["300k", "600k", "900k"]
    r = subprocess.run(
        ["unshare", "-rm", "sh", "-c", FULL_SWEEP, "full", sys.executable, str(spec), str(mnt)]
        + sizes,
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "CHECK": SWEEP_CHECK},
    )
    assert r.returncode == 0, r.stderr
    for size in sizes:
        rc = int((mnt / f"{size}.rc").read_text())
        err = (mnt / f"{size}.stderr").read_text()
        assert rc == 1, (size, rc, err)  # not 139 (SIGSEGV); the disk is too small for all
        errors = [ln for ln in err.splitlines() if ln.startswith("Error:")]
        assert len(errors) == 1 and "No space left on device" in errors[0], (size, err)
        assert "same command" in errors[0] and "Traceback" not in err, (size, err)
        files = (mnt / f"{size}.files").read_text().split()
        assert not [f for f in files if f.endswith(".tmp")], (size, files)
        assert int((mnt / f"{size}.rc2").read_text()) == 0, (mnt / f"{size}.stderr2").read_text()
        assert (mnt / f"{size}.check").read_text().split("\n")[0] == "4 [61]", size
        assert (mnt / f"{size}.notes").read_text() == "my notes"


CHECKPOINTED = textwrap.dedent(
    """
    import sys, json
    from bkwaves.config import parse_config
    from bkwaves import _checkpoint
    from bkwaves.runner import OutputFull, checkpoint_path, run
    write = _checkpoint.write
    def noted(*a, **kw):  # which write the disk refused: a checkpoint's, or a record's
        try:
            return write(*a, **kw)
        except OSError:
            print("checkpoint refused")
            raise
    _checkpoint.write = noted
    cfg = parse_config(json.loads(sys.argv[2]))
    try:  # a checkpoint after every chunk: the disk fills while one is written, or after
        run(cfg, sys.argv[1], chunk=300, flush_every=0.0, checkpoint_every=1e-9)
        print("done")
    except OutputFull as e:
        print("full", checkpoint_path(sys.argv[1]).exists())
    """
)
FULL_CHECKPOINTS = textwrap.dedent(
    """
    set -u
    py=$1; cfg=$2; mnt=$3; shift 3
    for size in "$@"; do
      d=$mnt/$size; mkdir -p $d
      mount -t tmpfs -o size=$size tmpfs $d || exit 90
      $py -c "$RUN" $d/o.nc "$cfg" > $d.run 2>&1
      echo $? > $d.rc
      mount -o remount,size=64m $d
      $py -c "$RECOVER" $d/o.nc > $d.recovered 2>&1
      $py -c "$SAME" $d/o.nc > $d.same 2>&1
      umount $d
    done
    """
)


@pytest.mark.skipif(not _userns_tmpfs(), reason="needs unshare -rm to mount a small tmpfs")
def test_a_disk_that_fills_between_checkpoints_keeps_the_last_one(tmp_path, reference):
    """Checkpoints after every engine chunk onto a disk that fills mid-run: the last
    checkpoint that was written whole is kept (a checkpoint is written under a temporary
    name and renamed; a failed one leaves the earlier), and --resume from it finishes the
    run equal to an uninterrupted one."""
    mnt = tmp_path / "mnt"
    mnt.mkdir()
    sizes = ["128k", "256k", "400k"]
    same = (
        "import sys, warnings, numpy as np, bkwaves as bk\n"
        "warnings.simplefilter('ignore')\n"
        f"a, ca = bk.load(sys.argv[1]); b, cb = bk.load({str(reference / 'ref.nc')!r})\n"
        "print(all(np.array_equal(a[v].values, b[v].values) for v in ('t', 'u', 'u_t'))"
        " and ca.equals(cb))\n"
    )
    r = subprocess.run(
        ["unshare", "-rm", "sh", "-c", FULL_CHECKPOINTS, "full", sys.executable]
        + [json.dumps(SMALL), str(mnt), *sizes],
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "RUN": CHECKPOINTED, "RECOVER": RECOVER, "SAME": same},
    )
    assert r.returncode == 0, r.stderr
    refused = 0
    for size in sizes:
        assert (mnt / f"{size}.rc").read_text().strip() == "0", (mnt / f"{size}.run").read_text()
        refused += "checkpoint refused" in (mnt / f"{size}.run").read_text()
        said = (mnt / f"{size}.run").read_text().strip().splitlines()  # (a warning first)
        assert said[-1] == "full True", (size, said)
        assert (mnt / f"{size}.recovered").read_text().split()[-1:] == ["resumed"], size
        assert (mnt / f"{size}.same").read_text().split() == ["True"], (
            size,
            (mnt / f"{size}.same").read_text(),
        )
    assert refused, "the disk never filled while a checkpoint was written"
