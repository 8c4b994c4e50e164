"""Sweep throughput on Dask against a bare loop over the same points (docs/benchmarks.md).

    python benchmarks/bench_sweep.py [--points 16] [--blocks 3000] [--repeats 3]

Work: CPU-bound points (task "front": one front in a chain of BLOCKS blocks, a fraction of
a second each, the GIL released inside the engine). Measured in one run, medians of
REPEATS:
- bare loop: bkwaves.sweeps.run_point over the points in this process (the baseline);
- the sweep through a LocalCluster of 1 and 2 worker processes, and of 2 threads in one
  process (cluster start-up timed apart; the sweep itself includes submitting, gathering
  and writing every point to the Zarr store);
- the machinery's cost per point: the same sweep of trivial points (task "speed", microseconds
  of work each) against the bare loop over them.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import tempfile
import time
from pathlib import Path


def _points(n: int, blocks: int) -> dict:
    return {
        "task": "front",
        "base": {"gamma": 0.3, "dx": 0.05, "blocks": blocks},
        "axes": {"u_plus": {"linspace": {"start": 0.5, "stop": 0.8, "num": n}}},
    }


def _bare(doc) -> float:
    from bkwaves.sweeps import parse_sweep, run_point

    spec = parse_sweep(doc)
    t0 = time.perf_counter()
    for idx in spec.indices():
        run_point(spec.task, spec.point(idx))
    return time.perf_counter() - t0


def _swept(doc, client, tmp: Path) -> float:
    from bkwaves.sweeps import sweep

    out = tmp / "b.zarr"
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.perf_counter()
    r = sweep(doc, out, client=client)
    wall = time.perf_counter() - t0
    assert r.computed == r.dataset["status"].size and r.failed == 0
    return wall


def _cluster(kind: str):
    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    if kind == "threads-2":
        cl = LocalCluster(
            n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0"
        )
    else:
        n = int(kind.split("-")[1])
        cl = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0")
    c = Client(cl)
    return c, cl, time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=16)
    ap.add_argument("--blocks", type=int, default=3000)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    heavy = _points(a.points, a.blocks)
    light = {
        "task": "speed",
        "axes": {"u_plus": {"linspace": {"start": 0.01, "stop": 0.99, "num": 200}}},
    }
    tmp = Path(tempfile.mkdtemp())
    rows = {}
    bare = statistics.median(_bare(heavy) for _ in range(a.repeats))
    rows["bare loop (baseline)"] = (bare, None)
    for kind in ("processes-1", "processes-2", "threads-2"):
        c, cl, start = _cluster(kind)
        try:
            _swept(heavy, c, tmp)  # warm the workers (imports)
            t = statistics.median(_swept(heavy, c, tmp) for _ in range(a.repeats))
            light_t = statistics.median(_swept(light, c, tmp) for _ in range(a.repeats))
        finally:
            c.close()
            cl.close()
        rows[f"sweep, {kind}"] = (t, start, light_t)
    light_bare = statistics.median(_bare(light) for _ in range(a.repeats))
    n = a.points
    print(f"{n} points of task 'front' (blocks = {a.blocks}); medians of {a.repeats}\n")
    print("| how | wall (s) | points/s | vs bare loop | cluster start (s) |")
    print("|---|---|---|---|---|")
    print(f"| bare loop (baseline) | {bare:.2f} | {n / bare:.2f} | 1.00 | - |")
    one = rows["sweep, processes-1"][0]
    for k, (t, start, _lt) in ((k, v) for k, v in rows.items() if v[1] is not None):
        print(f"| {k} | {t:.2f} | {n / t:.2f} | {bare / t:.2f} | {start:.2f} |")
    print(f"\nspeed-up of 2 worker processes over 1: {one / rows['sweep, processes-2'][0]:.2f}")
    print(f"speed-up of 2 threads over 1 process: {one / rows['sweep, threads-2'][0]:.2f}")
    print("\nmachinery cost per point (200 trivial 'speed' points, sweep minus bare loop):")
    for k, (_t, _start, lt) in ((k, v) for k, v in rows.items() if v[1] is not None):
        print(f"  {k}: {(lt - light_bare) / 200 * 1e3:.2f} ms per point")
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
