"""A first result pays only for what it uses (issue 27): `Chain.run` and `bkwaves front`
import neither xarray (nor, through it, dask) nor pandas; reading the result's tables or
snapshots imports them then, and gives the same values. (What it costs: benchmarks/
bench_cli.py and docs/benchmarks.md; here only what is imported, not timed.)"""

import json
import subprocess
import sys

HEAVY = ("xarray", "dask", "pandas", "matplotlib", "zarr", "distributed")

CHAIN = (
    "import bkwaves as bk; ch = bk.Chain(200, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6); "
    "ch.kick(0, -2.0); r = ch.run(t_end=5.0, snapshots=[1.0, 2.0], progress=False); "
)


def imported_after(code: str) -> list[str]:
    probe = (
        f"{code}\nimport sys, json\nprint(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))"
    )
    r = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_chain_run_imports_no_tables_or_datasets():
    assert imported_after(CHAIN + "r.counters; r.energy; r.u") == []


def test_front_command_imports_no_tables_or_datasets():
    code = (
        "from bkwaves.cli import main\n"
        "try:\n"
        "    main(['front', '--u-plus', '0.6', '--gamma', '0.3', '--dx', '0.05', '--json'])\n"
        "except SystemExit as e:\n"
        "    assert not e.code, e.code\n"
    )
    assert imported_after(code) == []


def test_chain_result_tables_on_first_use():
    code = CHAIN + (
        "import numpy as np\n"
        "cat, sl, ds = r.catalog, r.slips, r.snapshots\n"
        "assert r.catalog is cat and r.snapshots is ds\n"  # built once
        "assert len(cat) == 1 and cat['n_blocks'].iloc[0] == sl['block'].nunique() > 50\n"
        "assert ds.sizes == {'t': 2, 'x': 200} and ds.attrs['gamma'] == 0.3\n"
        "np.testing.assert_array_equal(sl['x'], sl['block'] * 0.1)\n"
        # the tables are the engine's records at the end of the run, not later ones
        "n = len(sl); ch.run(t_end=6.0, progress=False); assert len(r.slips) == n\n"
    )
    assert set(imported_after(code)) >= {"pandas", "xarray"}


def test_run_command_writes_netcdf_and_zarr_without_xarray_or_dask(tmp_path):
    """`bkwaves run` writes its snapshots with h5netcdf or zarr directly: neither xarray
    nor dask is imported (xarray was, for .zarr, and dask came with it on older runs)."""
    from pathlib import Path

    front = Path(__file__).resolve().parents[1] / "examples" / "chain_front.toml"
    for suffix in (".nc", ".zarr"):
        out = tmp_path / f"x{suffix}"
        code = (
            "from bkwaves.cli import main\n"
            "try:\n"
            f"    main(['run', {str(front)!r}, '-o', {str(out)!r}, '--quiet'])\n"
            "except SystemExit as e:\n"
            "    assert not e.code, e.code\n"
        )
        got = imported_after(code)
        assert out.exists()
        assert "xarray" not in got and "dask" not in got, (suffix, got)
