"""What publishing a NetCDF output costs now that HDF5 never writes to disk in the run's
process (session 33, a full disk crashed the run): the merged file built in memory and
written by Python, or written by a child process, against the baseline of the same merge
written by HDF5 to disk in the run's process (the old way, unsafe on a full disk); and the
checkpoint a complete run now writes before publishing, against its publication.

Run: python benchmarks/bench_publish.py [--repeat N] [--json OUT.json]
Each case: an unfinished output of random records (chain fields u, u_t: f8, sliding: u1)
in blocks of 8 MB, merged ``--repeat`` times per mode, modes interleaved; CPU time is this
process's plus its children's (``RUSAGE_CHILDREN``). Prints medians and the ratios to the
baseline measured in the same run.
"""

from __future__ import annotations

import argparse
import json
import resource
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from bkwaves import _nc_publish, io

CHAIN = {"u": ("1", "u", "f8"), "u_t": ("1", "u_t", "f8"), "sliding": ("1", "s", "u1")}
#: (name, blocks, records)
CASES = [
    ("0.2 MB (61 x 200 blocks)", 200, 61),
    ("17 MB (1000 x 1000)", 1000, 1000),
    ("170 MB (1000 x 10 000)", 10_000, 1000),
]


def _cpu() -> float:
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


def _blocks(d: Path, nx: int, records: int):
    rng = np.random.default_rng(0)
    w = io.RunWriter(d / "b.nc", np.arange(float(nx)), CHAIN, flush_every=1e9)
    per = max(1, (8 << 20) // (17 * nx))
    for i in range(0, records, per):
        k = min(per, records - i)
        w.append_block(
            np.arange(i, i + k, dtype=float),
            u=rng.random((k, nx)),
            u_t=rng.random((k, nx)),
            sliding=rng.integers(-1, 2, (k, nx)).astype("u1"),
        )
        w.commit()
    w.abandon()
    return io._blocks(w.partial / "snapshots")


def _merge(mode: str, blocks, target: Path) -> None:
    if mode == "direct":  # the baseline: HDF5 writes the file in this process
        _nc_publish.merge_to(blocks, target)
        return
    _nc_publish.IN_MEMORY_BYTES = (1 << 40) if mode == "memory" else 0
    _nc_publish.merge(blocks, target, lambda: None)


def _checkpoint_s(nx: int, repeat: int) -> float:
    """Seconds to write the checkpoint of a chain of ``nx`` blocks (median)."""
    import bkwaves as bk

    ch = bk.Chain(nx, bk.Params(gamma=0.3, v=0.0, dx=0.05), u0=0.6)
    d = Path(tempfile.mkdtemp(prefix="bench_publish_ck_"))
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        ch.save(d / "c.npz")
        times.append(time.perf_counter() - t0)
        (d / "c.npz").unlink()
    shutil.rmtree(d)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    rows = []
    for name, nx, records in CASES:
        d = Path(tempfile.mkdtemp(prefix="bench_publish_"))
        blocks = _blocks(d, nx, records)
        wall = {m: [] for m in ("direct", "memory", "child")}
        cpu = {m: [] for m in wall}
        size = 0
        for _ in range(args.repeat):
            for mode in wall:
                target = d / f"{mode}.nc"
                c0, t0 = _cpu(), time.perf_counter()
                _merge(mode, blocks, target)
                wall[mode].append(time.perf_counter() - t0)
                cpu[mode].append(_cpu() - c0)
                size = target.stat().st_size
                target.unlink()
        row = {"case": name, "blocks": nx, "records": records, "file_bytes": size}
        for mode in wall:
            row[f"{mode}_wall_s"] = statistics.median(wall[mode])
            row[f"{mode}_cpu_s"] = statistics.median(cpu[mode])
        for mode in ("memory", "child"):
            row[f"{mode}_cpu_ratio"] = row[f"{mode}_cpu_s"] / row["direct_cpu_s"]
            row[f"{mode}_wall_ratio"] = row[f"{mode}_wall_s"] / row["direct_wall_s"]
        row["checkpoint_s"] = _checkpoint_s(nx, args.repeat)
        row["checkpoint_over_publish"] = (
            row["checkpoint_s"] / row["memory_wall_s" if size <= (32 << 20) else "child_wall_s"]
        )
        rows.append(row)
        shutil.rmtree(d)
        print(
            f"| {name} | {size / 1e6:.2f} MB | {row['direct_cpu_s']:.3f} | "
            f"{row['memory_cpu_s']:.3f} ({row['memory_cpu_ratio']:.2f}x) | "
            f"{row['child_cpu_s']:.3f} ({row['child_cpu_ratio']:.2f}x) | "
            f"{row['direct_wall_s']:.3f} / {row['memory_wall_s']:.3f} / "
            f"{row['child_wall_s']:.3f} | "
            f"{row['checkpoint_s']:.4f} ({row['checkpoint_over_publish']:.2f}) |",
            flush=True,
        )
    if args.json:
        args.json.write_text(json.dumps({"repeat": args.repeat, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
