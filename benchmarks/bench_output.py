"""Snapshot output: ``bkwaves run`` writing blocks vs the former one-write-per-snapshot.

The run: a 100-block periodic chain under loading (gamma = 0.3, v = 1e-3, dx = 0.05),
t_end = 1000 with a snapshot every time unit: 1001 snapshots, 34 events. Measured in one
process: the run without output (the computation), the run writing NetCDF and Zarr
(records buffered and committed in blocks, published at the end), and, as the baseline,
the same 1001 snapshots written the way bkwaves wrote them before: one complete NetCDF
file per snapshot (then merged), one xarray Zarr append per snapshot.

    python benchmarks/bench_output.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from bkwaves.config import parse_config
from bkwaves.runner import run

CONFIG = {
    "model": "chain",
    "seed": 5,
    "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05, "beta": 5.0},
    "domain": {"blocks": 100, "boundary": "periodic"},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 2.0},
    "run": {"t_end": 1000.0},
    "output": {"snapshot_every": 1.0},
}


def per_snapshot_netcdf(d: Path, ds) -> None:
    """The former writer: one complete file per snapshot, merged on close."""
    import xarray as xr

    parts = d / "o.nc.parts"
    parts.mkdir()
    for k in range(ds.sizes["t"]):
        tmp = parts / f"part-{k:08d}.tmp"
        ds.isel(t=slice(k, k + 1)).to_netcdf(tmp, engine="h5netcdf")
        tmp.replace(parts / f"part-{k:08d}.nc")
    files = sorted(parts.glob("part-*.nc"))
    dss = [xr.open_dataset(f, engine="h5netcdf") for f in files]
    xr.concat(dss, dim="t", combine_attrs="override").load().to_netcdf(
        d / "o.nc", engine="h5netcdf", unlimited_dims=["t"]
    )
    for x in dss:
        x.close()


def per_snapshot_zarr(d: Path, ds) -> None:
    """The former writer: one xarray append per snapshot."""
    for k in range(ds.sizes["t"]):
        one = ds.isel(t=slice(k, k + 1))
        if k == 0:
            one.to_zarr(d / "o.zarr", mode="w", consolidated=False)
        else:
            one.to_zarr(d / "o.zarr", append_dim="t", consolidated=False)


def timed(f) -> float:
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    import bkwaves as bk

    cfg = parse_config(CONFIG)
    rows: dict[str, list[float]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        run(cfg, tmp / "ref.nc")
        ds = bk.load(tmp / "ref.nc")[0].load()
        assert ds.sizes["t"] == 1001
        for _ in range(args.repeats):
            for name, f in (
                ("computation only (no output)", lambda d: run(cfg, None)),
                ("bkwaves run -> .nc (blocks)", lambda d: run(cfg, d / "o.nc")),
                ("bkwaves run -> .zarr (blocks)", lambda d: run(cfg, d / "o.zarr")),
                ("1001 snapshots, one NetCDF file each", lambda d: per_snapshot_netcdf(d, ds)),
                ("1001 snapshots, one Zarr append each", lambda d: per_snapshot_zarr(d, ds)),
            ):
                d = tmp / "w"
                d.mkdir()
                rows.setdefault(name, []).append(timed(lambda f=f, d=d: f(d)))
                shutil.rmtree(d)
    med = {k: statistics.median(v) for k, v in rows.items()}
    print(f"| work | median of {args.repeats} |")
    print("|---|---|")
    for k, v in med.items():
        print(f"| {k} | {v:.3f} s |")
    nc = med["1001 snapshots, one NetCDF file each"] / med["bkwaves run -> .nc (blocks)"]
    zr = med["1001 snapshots, one Zarr append each"] / med["bkwaves run -> .zarr (blocks)"]
    print(f"\nper-snapshot NetCDF writes / bkwaves run .nc: {nc:.1f}")
    print(f"per-snapshot Zarr appends / bkwaves run .zarr: {zr:.1f}")


if __name__ == "__main__":
    main()
