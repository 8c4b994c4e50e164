"""Outputs that cannot be written: one `Error:` line naming the path, exit status 2, no
traceback, refused before any work (nothing computed, nothing half-written).

The unwritable folder is a read-only tmpfs mount, since root (as in CI containers)
ignores permission bits; without the right to mount, a non-root user gets a folder
without write permission, and root skips with the reason."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

BK = [sys.executable, "-m", "bkwaves"]


def bk(*args, cwd=None):
    return subprocess.run(
        [*BK, *map(str, args)], capture_output=True, text=True, timeout=300, cwd=cwd
    )


def _writable(d: Path) -> bool:
    try:
        (d / ".probe").write_text("x")
    except OSError:
        return False
    (d / ".probe").unlink()
    return True


@pytest.fixture
def readonly(tmp_path):
    """A folder nobody can write into, even root."""
    d = tmp_path / "ro"
    d.mkdir()
    mount = shutil.which("mount")
    r = None
    if mount is not None:
        r = subprocess.run(
            [mount, "-t", "tmpfs", "-o", "ro,size=64k", "bkwaves-test", str(d)],
            capture_output=True,
            text=True,
        )
    if r is not None and r.returncode == 0:
        try:
            assert not _writable(d)
            yield d
        finally:
            subprocess.run(["umount", str(d)], check=False)
        return
    why = "no mount command" if r is None else (r.stderr.strip() or f"status {r.returncode}")
    if os.geteuid() == 0:
        pytest.skip(f"cannot mount a read-only tmpfs ({why}); root ignores permission bits")
    d.chmod(0o555)
    try:
        if _writable(d):
            pytest.skip("a folder without write permission is still writable here")
        yield d
    finally:
        d.chmod(0o755)


def one_error_line(r, path):
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    assert "Traceback" not in r.stderr, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: "), r.stderr
    assert str(path) in lines[0], (path, lines[0])
    return lines[0]


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="no /proc file system")
def test_paper_under_proc():
    r = bk("paper", "-o", "/proc/x", "--quick")
    one_error_line(r, "/proc/x")
    assert "cannot write" in r.stderr


def test_paper_into_a_read_only_folder(readonly):
    for target in (readonly, readonly / "sub" / "paper"):
        r = bk("paper", "-o", target, "--quick", "--json")
        one_error_line(r, target)
        assert r.stdout == ""  # refused before any work
    assert list(readonly.iterdir()) == []


def test_wave_and_speed_plot_into_a_read_only_folder(readonly):
    r = bk("wave", "--u-plus", "0.6", "--gamma", "0.3", "--plot", readonly / "w.png")
    one_error_line(r, readonly / "w.png")
    assert r.stdout == ""  # refused before the results are printed
    r = bk("speed", "0.3", "0.6", "--plot", readonly / "s.pdf")
    one_error_line(r, readonly / "s.pdf")
    assert r.stdout == ""
    assert list(readonly.iterdir()) == []


def test_plot_into_a_read_only_folder(tmp_path, readonly):
    import bkwaves as bk_

    cfg = {
        "model": "chain",
        "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        "domain": {"blocks": 20},
        "initial": {"kind": "uniform", "value": 0.6},
        "triggers": [{"block": 0, "kind": "kick", "velocity": 2.0}],
        "run": {"t_end": 2.0},
        "output": {"snapshot_every": 0.5},
    }
    out = tmp_path / "r.nc"
    bk_.run(cfg, out)
    r = bk("plot", out, "-o", readonly)
    one_error_line(r, readonly)
    assert list(readonly.iterdir()) == []


def test_sweep_into_a_read_only_folder(tmp_path, readonly):
    sweep = tmp_path / "s.toml"
    sweep.write_text('task = "speed"\n[axes.u_plus]\nvalues = [0.3, 0.5]\n')
    r = bk("sweep", sweep, "-o", readonly / "s.zarr", "--quiet")
    one_error_line(r, readonly / "s.zarr")
    # the default store, beside a sweep file in a read-only folder: the API refuses too
    import bkwaves as bk_

    with pytest.raises(bk_.ParameterError, match="cannot write"):
        bk_.sweep(sweep, readonly / "s.zarr")
    assert list(readonly.iterdir()) == []


def test_plot_file_written_whole(tmp_path):
    """A picture is written beside and renamed: a failure while drawing leaves no file."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bkwaves import plot

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])

    def boom(path, *a, **k):  # half a file, then the disk is full
        Path(path).write_bytes(b"\x89PNG\r\n half")
        raise OSError(28, "No space left on device")

    fig.savefig = boom
    with pytest.raises(OSError):
        plot.save(ax, tmp_path / "a.png")
    assert list(tmp_path.iterdir()) == []


def test_an_unforeseen_os_error_is_one_line(tmp_path):
    """The command line's last resort: an OSError it did not foresee is one line naming
    the file, exit status 2."""
    code = (
        "import sys, bkwaves.cli as c\n"
        "def boom(args):\n"
        "    open(sys.argv[1] + '/none/here.txt')\n"
        "c.COMMANDS['wave'] = c.COMMANDS['wave']._replace(run=boom)\n"
        "c.main(['wave', '--u-plus', '0.5', '--gamma', '0.3'])\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True, timeout=60
    )
    one_error_line(r, tmp_path / "none" / "here.txt")
    assert "No such file or directory" in r.stderr


def test_plot_under_a_file(tmp_path):
    """--plot under a path whose parent is a file: refused before the JSON is printed."""
    bad = tmp_path / "a_file"
    bad.write_text("x")
    r = bk("wave", "--u-plus", "0.6", "--gamma", "0.3", "--json", "--plot", bad / "w.png")
    one_error_line(r, bad / "w.png")
    assert r.stdout == "" and bad.read_text() == "x"
