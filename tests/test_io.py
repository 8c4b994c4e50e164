"""Outputs: incremental NetCDF/Zarr snapshots, Parquet/CSV tables, interruption safety."""

import subprocess
import sys
import textwrap

import numpy as np
import pandas as pd
import pytest

import bkwaves as bk
from bkwaves.io import RunWriter, finalize, load, load_tables, table_path

VARS = {"u": ("1", "stress u", "f8"), "state": ("1", "0 stuck, 1 forward, -1 backward", "i1")}


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_round_trip_with_attributes_and_tables(tmp_path, suffix):
    out = tmp_path / f"run{suffix}"
    x = np.linspace(0, 1, 11)
    with RunWriter(
        out, x, VARS, attrs={"seed": 3, "params": {"gamma": 0.3}}, coord_units=("m", "s")
    ) as w:
        for k in range(4):
            w.append(0.5 * k, u=np.sin(x + k), state=(np.arange(11) % 3 - 1))
        w.write_table(
            "events",
            pd.DataFrame({"t_start": [0.1, 0.7], "slip": [1.0, 2.0]}),
            units={"t_start": "s", "slip": "m"},
        )
    ds, tables = load_tables(out)
    assert load(out)[1].equals(tables["events"])
    assert ds.sizes == {"t": 4, "x": 11}
    np.testing.assert_allclose(ds.t, [0, 0.5, 1.0, 1.5])
    np.testing.assert_allclose(ds.u.isel(t=2), np.sin(x + 2))
    assert ds.state.dtype == np.int8 and int(ds.state[0, 0]) == -1
    assert ds.x.attrs["units"] == "m" and ds.t.attrs["units"] == "s"
    assert ds.attrs["seed"] == 3 and '"gamma": 0.3' in ds.attrs["params"]
    assert ds.attrs["Conventions"] == "CF-1.10" and ds.attrs["bkwaves_version"] == bk.__version__
    ev = tables["events"]
    assert list(ev.slip) == [1.0, 2.0] and ev.attrs["units"]["t_start"] == "s"
    assert pd.read_csv(table_path(out, "events", ".csv")).shape == (2, 2)


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_a_killed_writer_keeps_its_committed_records_with_their_catalog(tmp_path, suffix):
    out = tmp_path / f"killed{suffix}"
    code = textwrap.dedent(f"""
        import os, numpy as np, pandas as pd
        from bkwaves.io import RunWriter
        w = RunWriter({str(out)!r}, np.arange(5.0), {{"u": ("1", "u", "f8")}})
        for k in range(3):
            w.append_rows("events", pd.DataFrame({{"event": [k]}}))
            w.append(float(k), u=np.full(5, k))
        w.commit()
        w.append(3.0, u=np.full(5, 3))   # buffered, never committed: lost
        os._exit(1)   # no close, no cleanup: like a crash or SIGKILL
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 1, r.stderr
    assert not out.exists()  # nothing published
    with pytest.warns(UserWarning, match="unfinished"):
        ds, catalog = load(out)
    assert ds.sizes["t"] == 3
    np.testing.assert_allclose(ds.u.values[:, 0], [0, 1, 2])
    assert list(catalog.event) == [0, 1, 2]
    finalize(out)  # publish what the crash left
    assert not (tmp_path / f"killed{suffix}.partial").exists()
    ds, catalog = load(out)
    assert ds.sizes["t"] == 3 and ds.u.values[2, 4] == 2 and len(catalog) == 3


def _zarr_partial(tmp_path, records=3):
    out = tmp_path / "torn.zarr"
    w = RunWriter(out, np.arange(4.0), {"u": ("1", "u", "f8"), "v": ("1", "v", "f8")})
    for k in range(records):
        w.append(float(k), u=np.full(4, k), v=np.full(4, -k))
    w.commit()
    return out, w


@pytest.mark.parametrize("torn_after", ["u", "v", "t"])
def test_a_torn_zarr_store_loads_up_to_its_last_complete_record(tmp_path, torn_after):
    """A block killed after some of its variables (here: by hand, as SIGKILL would leave
    it): the arrays have different lengths, and bk.load reads the committed records."""
    import zarr

    out, w = _zarr_partial(tmp_path)
    g = zarr.open_group(str(tmp_path / "torn.zarr.partial" / "torn.zarr"), mode="r+")
    for name in ("u", "v", "t"):  # the order a block is written in
        a = g[name]
        a.resize((5, *a.shape[1:]))
        a[3:5] = 9.0
        if name == torn_after:
            break
    with pytest.warns(UserWarning, match="dropped the uncommitted records beyond record 3"):
        ds, _ = load(out)
    assert ds.sizes["t"] == 3 and list(ds.t.values) == [0, 1, 2]
    np.testing.assert_array_equal(ds.v.values[:, 0], [0, -1, -2])
    w.abandon()


def test_a_zarr_writer_killed_inside_a_block_keeps_the_blocks_before(tmp_path):
    """A real SIGKILL in the middle of a block (after its first variable)."""
    out = tmp_path / "k.zarr"
    code = textwrap.dedent(f"""
        import os, signal, numpy as np, zarr
        from bkwaves.io import RunWriter
        spec = {{"u": ("1", "u", "f8"), "v": ("1", "v", "f8")}}
        w = RunWriter({str(out)!r}, np.arange(4.0), spec)
        for k in range(3):
            w.append(float(k), u=np.full(4, k), v=np.full(4, k))
        w.commit()
        setitem = zarr.Array.__setitem__
        def dying(self, key, value):
            setitem(self, key, value)
            os.kill(os.getpid(), signal.SIGKILL)
        zarr.Array.__setitem__ = dying
        w.append(3.0, u=np.full(4, 3), v=np.full(4, 3))
        w.commit()
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == -9, r.stderr
    with pytest.warns(UserWarning, match="dropped the uncommitted records"):
        ds, _ = load(out)
    assert ds.sizes["t"] == 3 and ds.u.values[2, 0] == 2


def test_an_existing_output_is_refused_and_only_bkwaves_files_are_replaced(tmp_path):
    x = np.arange(3.0)
    # a directory tree that merely ends in .zarr
    d = tmp_path / "d.zarr"
    (d / "sub").mkdir(parents=True)
    (d / "precious.txt").write_text("keep")
    with pytest.raises(bk.ParameterError, match="exists.*--overwrite"):
        RunWriter(d, x, VARS)
    with pytest.raises(bk.ParameterError, match="not written by bkwaves"):
        RunWriter(d, x, VARS, overwrite=True)
    assert (d / "precious.txt").read_text() == "keep" and (d / "sub").is_dir()
    # an unrelated catalog beside the output
    out = tmp_path / "o.nc"
    mine = table_path(out, "events", ".csv")
    mine.write_text("a,b\n1,2\n")
    with pytest.raises(bk.ParameterError, match="exists"):
        RunWriter(out, x, VARS)
    with pytest.raises(bk.ParameterError, match="not written by bkwaves"):
        RunWriter(out, x, VARS, overwrite=True)
    assert mine.read_text() == "a,b\n1,2\n" and not out.exists()
    mine.unlink()
    # a bkwaves output is replaced (with its tables; one the new run does not write goes)
    with RunWriter(out, x, VARS) as w:
        w.append(0.0, u=x, state=[0, 0, 0])
        w.write_table("events", pd.DataFrame({"a": [1.0]}))
        w.write_table("shocks", pd.DataFrame({"b": [1.0]}), csv=False)
    with RunWriter(out, x, VARS, overwrite=True) as w:
        w.append(5.0, u=x, state=[1, 1, 1])
        w.write_table("events", pd.DataFrame({"a": [2.0, 3.0]}))
    ds, tables = load_tables(out)
    assert list(ds.t.values) == [5.0] and set(tables) == {"events"}
    assert list(tables["events"].a) == [2.0, 3.0]
    assert not table_path(out, "shocks").exists()
    assert pd.read_csv(table_path(out, "events", ".csv")).a.tolist() == [2.0, 3.0]
    # an edited CSV is no longer bkwaves' own: not replaced
    table_path(out, "events", ".csv").write_text("a\n7\n")
    with pytest.raises(bk.ParameterError, match="o.nc.events.csv: not written by bkwaves"):
        RunWriter(out, x, VARS, overwrite=True)


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_a_failed_run_leaves_the_earlier_output_whole(tmp_path, suffix, monkeypatch):
    """Publishing is atomic: a full disk in the new run keeps the old output and its
    catalog together; the new records stay in OUT.partial."""
    import errno

    import bkwaves.io as bio

    out = tmp_path / f"o{suffix}"
    x = np.arange(3.0)
    with RunWriter(out, x, VARS) as w:
        w.append(0.0, u=x, state=[0, 0, 0])
        w.write_table("events", pd.DataFrame({"a": [1.0]}))

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    with pytest.raises(OSError, match="No space"):
        with RunWriter(out, x, VARS, overwrite=True) as w:
            w.append(1.0, u=x + 1, state=[1, 1, 1])
            w.write_table("events", pd.DataFrame({"a": [2.0, 3.0]}))
            w.commit()
            w.append(2.0, u=x + 2, state=[1, 1, 1])
            monkeypatch.setattr(bio, "_write_bytes", full)
            monkeypatch.setattr(bio.RunWriter, "_append_zarr", full)
            w.commit()
    monkeypatch.undo()
    with pytest.warns(UserWarning, match="unfinished newer run"):
        ds, catalog = load(out)
    assert list(ds.t.values) == [0.0] and list(catalog.a) == [1.0]
    assert not list(tmp_path.rglob("*.tmp"))
    assert not (tmp_path / f"o{suffix}.lock").exists()  # the lock went with the writer
    finalize(out)  # what the failed run committed, published on request
    ds, catalog = load(out)
    assert list(ds.t.values) == [1.0] and list(catalog.a) == [2.0, 3.0]


def test_load_never_pairs_snapshots_with_another_runs_catalog(tmp_path):
    x = np.arange(3.0)
    a, b = tmp_path / "a.nc", tmp_path / "b.nc"
    for out, v in ((a, 1.0), (b, 2.0)):
        with RunWriter(out, x, VARS) as w:
            w.append(v, u=x, state=[0, 0, 0])
            w.write_table("events", pd.DataFrame({"a": [v]}))
    table_path(b, "events").replace(table_path(a, "events"))
    with pytest.warns(UserWarning, match="'events' of .* belongs to another run"):
        ds, catalog = load(a)
    assert catalog is None and list(ds.t.values) == [1.0]


def test_a_second_writer_on_the_same_output_fails_at_once(tmp_path):
    out = tmp_path / "same.nc"
    with RunWriter(out, [0.0], VARS) as w:
        with pytest.raises(bk.ParameterError, match="being written by another bkwaves run"):
            RunWriter(out, [0.0], VARS, overwrite=True)
        w.append(0.0, u=[1.0], state=[0])
    assert load(out)[0].sizes["t"] == 1


def test_snapshots_are_written_in_blocks_and_tables_appended_in_row_groups(tmp_path, monkeypatch):
    import pyarrow.parquet as pq

    import bkwaves.io as bio

    writes = []
    write_bytes, write_part = bio._write_bytes, bio._write_parquet_part
    monkeypatch.setattr(bio, "_write_bytes", lambda p, d: writes.append(p) or write_bytes(p, d))
    parts = []
    monkeypatch.setattr(
        bio, "_write_parquet_part", lambda p, t: parts.append(t.num_rows) or write_part(p, t)
    )
    out = tmp_path / "b.nc"
    x = np.arange(100.0)
    with RunWriter(out, x, VARS, flush_every=1e9) as w:
        for k in range(1001):
            w.append(float(k), u=x, state=np.zeros(100))
            if k % 100 == 0:
                w.append_rows("events", pd.DataFrame({"k": [k]}))
                w.commit()
    blocks = [p for p in writes if p.name.startswith("block-")]
    assert len(blocks) == 11  # one per commit, not 1001 writes
    assert sum(parts) == 11  # every row written once: appended, never rewritten
    assert pq.ParquetFile(table_path(out, "events")).num_row_groups == 11
    ds, cat = load(out)
    assert ds.sizes["t"] == 1001 and list(cat.k) == list(range(0, 1001, 100))


def test_published_zarr_opens_without_warnings(tmp_path):
    import warnings

    import xarray as xr

    out = tmp_path / "c.zarr"
    with RunWriter(out, [0.0, 1.0], VARS) as w:
        w.append(0.0, u=[1.0, 2.0], state=[0, 1])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = xr.open_zarr(out)
        assert ds.sizes["t"] == 1


def test_bad_paths_and_missing_fields(tmp_path):
    with pytest.raises(bk.ParameterError, match="suffixes"):
        RunWriter(tmp_path / "run.h5", [0.0], VARS)
    with pytest.raises(bk.ParameterError, match="not found"):
        load(tmp_path / "nothing.nc")
    with RunWriter(tmp_path / "r.nc", [0.0, 1.0], VARS) as w:
        with pytest.raises(bk.ParameterError, match="state"):
            w.append(0.0, u=[1.0, 2.0])


def test_plot_run_renders_every_kind(tmp_path):
    from bkwaves.plot import plot_run

    out = tmp_path / "demo.nc"
    x = np.linspace(0, 10, 101)
    with RunWriter(out, x, VARS, coord_units=("1", "1")) as w:
        for k in range(20):
            front = 0.5 * k
            w.append(k * 1.0, u=np.where(x < front, -0.2, 0.6), state=(np.abs(x - front) < 1))
        rng = np.random.default_rng(0)
        w.write_table("events", pd.DataFrame({"moment": rng.pareto(1.0, 200) + 1.0}))
        w.write_table("fronts", pd.DataFrame({"t": np.arange(20.0), "x": 0.5 * np.arange(20.0)}))
    for fmt in ("png", "svg", "pdf"):
        files = plot_run(out, tmp_path / fmt, fmt=fmt)
        names = {f.name for f in files}
        assert names == {
            f"demo_spacetime_u.{fmt}",
            f"demo_spacetime_state.{fmt}",
            f"demo_profiles.{fmt}",
            f"demo_fronts.{fmt}",
            f"demo_size_frequency.{fmt}",
            f"demo_frequency_magnitude.{fmt}",
        }
        assert all(f.stat().st_size > 3000 for f in files)
