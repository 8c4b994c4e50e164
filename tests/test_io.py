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
def test_a_killed_writer_keeps_its_completed_records(tmp_path, suffix):
    out = tmp_path / f"killed{suffix}"
    code = textwrap.dedent(f"""
        import os, numpy as np
        from bkwaves.io import RunWriter
        w = RunWriter({str(out)!r}, np.arange(5.0), {{"u": ("1", "u", "f8")}})
        for k in range(3):
            w.append(float(k), u=np.full(5, k))
        os._exit(1)   # no close, no cleanup: like a crash or SIGKILL
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 1
    ds, _ = load(out)
    assert ds.sizes["t"] == 3
    np.testing.assert_allclose(ds.u.values[:, 0], [0, 1, 2])
    if suffix == ".nc":
        finalize(out)  # merge the parts left by the crash into one NetCDF file
        assert not (tmp_path / "killed.nc.parts").exists()
        ds, _ = load(out)
        assert ds.sizes["t"] == 3 and ds.u.values[2, 4] == 2


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
        }
        assert all(f.stat().st_size > 3000 for f in files)
