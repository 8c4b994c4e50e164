"""Checkpoints (Chain.save, FreeBoundary.save, the runner's OUT.checkpoint) are data only:
loading a pickle never runs it, and files of another format, kind or version are refused
with a message naming the file."""

import json
import pickle
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import _checkpoint

BK = [sys.executable, "-m", "bkwaves"]


class _Touch:
    """A pickle payload that creates ``path`` when unpickled (as an attacker's would run
    any code)."""

    def __init__(self, path):
        self.path = Path(path)

    def __reduce__(self):
        return (Path.touch, (self.path,))


def _booby_trapped(tmp_path, name):
    marker = tmp_path / f"{name}.ran"
    payload = pickle.dumps(_Touch(marker))
    # the payload is live: unpickling it really runs code
    probe = tmp_path / f"{name}.probe"
    pickle.loads(pickle.dumps(_Touch(probe)))
    assert probe.exists()
    return payload, marker


def chain():
    p = bk.Params(gamma=0.3, v=1e-2, dx=0.2, beta=0.5)
    return bk.Chain(30, p, boundary="periodic", u0=0.6, seed=3).kick(3, -0.5)


def free_boundary():
    x = np.linspace(0.0, 20.0, 41)
    return bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-3, dx=0.1), x, 0.5 + 5e-4 * x)


@pytest.mark.parametrize("cls", [bk.Chain, bk.FreeBoundary])
def test_a_pickle_is_refused_without_running_it(tmp_path, cls):
    payload, marker = _booby_trapped(tmp_path, cls.__name__)
    path = tmp_path / "evil.ckpt"
    path.write_bytes(payload)
    with pytest.raises(bk.ParameterError, match="pickle") as e:
        cls.load(path)
    assert str(path) in str(e.value) and "arbitrary code" in str(e.value)
    assert not marker.exists(), "loading the checkpoint ran the pickle's code"


def test_resume_refuses_a_pickled_run_checkpoint_without_running_it(tmp_path):
    payload, marker = _booby_trapped(tmp_path, "run")
    out = tmp_path / "o.nc"
    (tmp_path / "o.nc.checkpoint").write_bytes(payload)
    r = subprocess.run(
        [*BK, "run", "--resume", str(out)], capture_output=True, text=True, timeout=120
    )
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "pickle" in r.stderr and "o.nc.checkpoint" in r.stderr
    assert not marker.exists(), "resuming ran the pickle's code"


def _rewrite_header(path, **changes):
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    header = json.loads(arrays["header"].tobytes())
    header.update(changes)
    arrays["header"] = np.frombuffer(json.dumps(header).encode(), dtype=np.uint8)
    with open(path, "wb") as f:
        np.savez(f, **arrays)


def test_checkpoint_is_plain_data_with_a_format_version(tmp_path):
    ch = chain()
    ch.run(t_end=5.0, progress=False)
    ch.save(tmp_path / "c.ckpt")
    assert zipfile.is_zipfile(tmp_path / "c.ckpt")
    with np.load(tmp_path / "c.ckpt", allow_pickle=False) as z:
        assert not any(z[k].dtype.hasobject for k in z.files)
        header = json.loads(z["header"].tobytes())
    assert header["format"] == "bkwaves-checkpoint" and header["version"] == 1
    assert header["kind"] == "chain" and header["meta"]["seed"] == 3


@pytest.mark.parametrize("version", [0, 2, "1"])
def test_checkpoint_of_another_format_version_is_refused(tmp_path, version):
    path = tmp_path / "c.ckpt"
    chain().save(path)
    _rewrite_header(path, version=version)
    with pytest.raises(bk.ParameterError, match="format version") as e:
        bk.Chain.load(path)
    assert str(path) in str(e.value) and "reads version 1" in str(e.value)


def test_checkpoint_of_another_kind_or_garbage_is_refused(tmp_path):
    path = tmp_path / "c.ckpt"
    chain().save(path)
    with pytest.raises(bk.ParameterError, match="is a chain checkpoint, not"):
        bk.FreeBoundary.load(path)
    data = path.read_bytes()
    for name, content in {
        "empty": b"",
        "text": b"hello world\n",
        "truncated": data[: len(data) // 2],
        "npy": b"\x93NUMPY" + data[6:100],
    }.items():
        bad = tmp_path / name
        bad.write_bytes(content)
        with pytest.raises(bk.ParameterError, match="not a bkwaves chain checkpoint"):
            bk.Chain.load(bad)
    with pytest.raises(bk.ParameterError, match="cannot read checkpoint"):
        bk.Chain.load(tmp_path / "missing.ckpt")
    # a well-formed archive whose engine bytes are not a chain's
    _rewrite_header(path)
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["engine"] = np.frombuffer(b"BKFREEB1" + bytes(40), dtype=np.uint8)
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    with pytest.raises(bk.ParameterError, match="cannot restore the engine"):
        bk.Chain.load(path)


def test_physical_units_and_snapshots_survive_a_checkpoint(tmp_path):
    p = bk.Params.from_physical(
        mass=1e-3,
        k_c=50.0,
        k_p=1.0,
        f_static=1.0,
        f_kinetic=0.5,
        alpha=0.01,
        V=1e-3,
        spacing=1e-3,
    )
    ch = bk.Chain(20, p, u0=0.5, fixed=(0.25, 0.75), step=0.05, integrator="midpoint")
    ch.save(tmp_path / "si.ckpt")
    back = bk.Chain.load(tmp_path / "si.ckpt")
    assert back.params == p and back.params.units == p.units
    assert (back.fixed, back.step, back.integrator, back.seed) == (
        (0.25, 0.75),
        0.05,
        "midpoint",
        None,
    )
    fb = free_boundary()
    fb.run(t_end=3.0, snapshots=[1.0, 2.0])
    fb.save(tmp_path / "fb.ckpt")
    fb2 = bk.FreeBoundary.load(tmp_path / "fb.ckpt")
    assert fb2._snap_t == fb._snap_t and fb2._snap_n == fb._snap_n
    np.testing.assert_array_equal(np.array(fb2._snap_u), np.array(fb._snap_u))
    np.testing.assert_array_equal(fb2.x, fb.x)
    assert _checkpoint.params_from_record(_checkpoint.params_record(p)) == p


def test_an_archive_with_a_pickled_array_is_refused_without_running_it(tmp_path):
    """The npz container itself can carry pickles (object arrays): never unpickled."""
    payload, marker = _booby_trapped(tmp_path, "npz")
    path = tmp_path / "c.ckpt"
    chain().save(path)
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["engine"] = np.array([_Touch(marker)], dtype=object)
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    with pytest.raises(bk.ParameterError, match="not a bkwaves chain checkpoint"):
        bk.Chain.load(path)
    assert not marker.exists()


@pytest.mark.parametrize("kind", ["chain", "lattice"])
@pytest.mark.parametrize(
    "change",
    [{"shape": "x"}, {"shape": [3]}, {"params": None}, {"params": 1.0}, {"fixed": 0.5}, "drop"],
)
def test_a_checkpoint_whose_record_was_edited_is_refused_in_one_line(tmp_path, kind, change):
    """A header of the right format, version and kind whose record is not one bkwaves
    wrote (session 35: a lattice checkpoint with meta shape = "x" raised "ValueError: not
    enough values to unpack", a missing key a KeyError): a ParameterError naming the file."""
    p = bk.Params(gamma=0.45, v=0.01, dx=0.1)
    model = bk.Lattice((5, 4), p, u0=0.5) if kind == "lattice" else bk.Chain(5, p, u0=0.5)
    path = tmp_path / "c.npz"
    model.save(path)
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    header = json.loads(arrays["header"].tobytes())
    if kind == "chain" and change != "drop" and "shape" in change:
        change = {"n": change["shape"]}  # the chain's size
    if change == "drop":
        header["meta"].pop("params")
    else:
        header["meta"].update(change)
    arrays["header"] = np.frombuffer(json.dumps(header).encode(), dtype=np.uint8)
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    cls = bk.Lattice if kind == "lattice" else bk.Chain
    with pytest.raises(bk.ParameterError) as e:
        cls.load(path)
    assert str(path) in str(e.value) and "\n" not in str(e.value)


def test_a_checkpoint_that_cannot_be_written_names_the_users_path(tmp_path):
    """Lattice.save into a missing folder or under a file (session 35: the error named
    the temporary file, "x.npz.tmp", that the user never asked for); nothing is left."""
    la = bk.Lattice((5, 4), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.5)
    (tmp_path / "a_file").write_text("mine")
    for where, err in (
        (tmp_path / "missing" / "x.npz", FileNotFoundError),
        (tmp_path / "a_file" / "x.npz", NotADirectoryError),
    ):
        with pytest.raises(err) as e:
            la.save(where)
        assert str(e.value).endswith(f"'{where}'") and ".tmp" not in str(e.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]
    assert (tmp_path / "a_file").read_text() == "mine"
