"""Cost of the two-dimensional free boundary engine per rupture, and a long run.

Run: python benchmarks/bench_free_boundary_2d.py [--scaling] [--long] [--lattice] [--json FILE]
  --scaling: on one 1024 x 1024 periodic grid (h = 0.25, v = 0), a disk of radius R
      stressed to u = 0.6 in u = -0.2 is triggered at its centre; the front sweeps the
      A ~ pi R^2/h^2 nodes of the disk and stops at its edge. CPU time of the sweep
      (median of 5 rounds, a fresh engine each, construction not timed) for A from 1e3 to
      8e5 nodes (7 sizes): time per node and per node and log2(A), as ratios to the smallest disk
      measured in the same run (the baseline), and the fits t = k A log2 A (k the geometric
      mean of t/(A log2 A); the last column is t over the fit) and t = k' A^p.
  --long: a 1024 x 1024 periodic grid (h = 0.5), gamma = 0.3, v = 1e-3, creep rule
      "stop", u0 = 0.3 x a random field of correlation length 3, noise law "power"
      (exponent 8, rate 1 per unit area and time at u = 1), run until 1e5 ruptures are
      complete: CPU time, ruptures, areas.
  --lattice: one rupture through a smooth stress field on the quadrant [0, 8]^2 (the
      validation of docs/free_boundary_2d.md, docs/scripts/free_boundary_2d_lattice.py),
      run by bk.Lattice and by FreeBoundary2D on the same nodes (h = dx, dx = 0.2, 0.1
      and 0.05): CPU time of each (construction included, one round each, after a round
      of the first case not kept), and their ratio.
Timed by CPU time (time.process_time() around the engine call: the machine is shared).
Prints markdown tables; --json writes the numbers.
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import statistics
import time

import numpy as np

import bkwaves as bk
from bkwaves.free_boundary_2d import random_field


def disk_sweep(n: int, h: float, radius: float) -> tuple[float, int]:
    """CPU seconds of the sweep of a stressed disk of `radius`, and the nodes swept."""
    x = (np.arange(n) - n // 2) * h
    xx, yy = np.meshgrid(x, x)
    u0 = np.where(np.hypot(xx, yy) <= radius, 0.6, -0.2)
    fb = bk.FreeBoundary2D(
        bk.Params(gamma=0.3, v=0.0, dx=1e-2), (n, n), h, u0, "periodic", origin=(x[0], x[0])
    )
    fb.trigger(0.0, 0.0)
    t0 = time.process_time()
    fb._engine.advance(math.inf, 2**62, 1)
    dt = time.process_time() - t0
    return dt, int(fb._engine.ruptures()["n_nodes"][0])


def scaling(rounds: int = 5) -> list[dict]:
    n, h = 1024, 0.25
    rows = []
    for area in (1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 8e5):
        radius = math.sqrt(area / math.pi) * h
        times, nodes = [], 0
        for _ in range(rounds):
            dt, nodes = disk_sweep(n, h, radius)
            times.append(dt)
        med = statistics.median(times)
        rows.append({"area_nodes": nodes, "cpu_s": med, "per_node_ns": 1e9 * med / nodes})
    base = rows[0]
    for r in rows:
        r["per_node_ratio"] = r["per_node_ns"] / base["per_node_ns"]
        r["per_node_log_ratio"] = (
            r["per_node_ratio"] * math.log2(base["area_nodes"]) / (math.log2(r["area_nodes"]))
        )
    a = np.array([r["area_nodes"] for r in rows], dtype=float)
    t = np.array([r["cpu_s"] for r in rows])
    # fits: t = k A log2 A (least squares in log t: the constant is the geometric mean of
    # t/(A log2 A)), and a free power t = k' A^p
    k = float(np.exp(np.mean(np.log(t / (a * np.log2(a))))))
    p, logk = np.polyfit(np.log(a), np.log(t), 1)
    for r in rows:
        r["per_node_log_fit"] = r["cpu_s"] / (k * r["area_nodes"] * math.log2(r["area_nodes"]))
    fit = {"k_ns": 1e9 * k, "power": float(p), "power_prefactor_ns": 1e9 * math.exp(logk)}
    print("| nodes swept A | CPU s (median) | ns per node | per node / smallest | "
          "per (node log2 A) / smallest | t / (k A log2 A) |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['area_nodes']} | {r['cpu_s']:.4f} | {r['per_node_ns']:.0f} | "
            f"{r['per_node_ratio']:.2f} | {r['per_node_log_ratio']:.2f} | "
            f"{r['per_node_log_fit']:.2f} |"
        )
    print(f"fit t = k A log2 A: k = {fit['k_ns']:.1f} ns; free power t ~ A^{p:.3f}")
    return {"rows": rows, "fit": fit}


def long_run(target: int = 100_000) -> dict:
    n, h = 1024, 0.5
    p = bk.Params(gamma=0.3, v=1e-3, dx=1e-2)
    u0 = 0.3 * random_field((n, n), h, 3.0, seed=1)
    fb = bk.FreeBoundary2D(
        p, (n, n), h, u0, "periodic", creep="stop",
        noise={"law": "power", "rate": 1.0, "exponent": 8.0}, seed=2,
    )  # fmt: skip
    t0, w0 = time.process_time(), time.perf_counter()
    status = "steps"
    while status == "steps":
        status = fb._engine.advance(math.inf, 20_000_000, target)
        print(  # progress, so that a stopped run still says how far it got
            f"cpu {time.process_time() - t0:.1f} s, t {fb.time:.0f}, events "
            f"{fb._engine.steps}, noise (candidates, nucleations) {fb._engine.noise_counters}",
            flush=True,
        )
    cpu, wall = time.process_time() - t0, time.perf_counter() - w0
    ru = fb._engine.ruptures()
    done = ru["complete"]
    nodes = ru["n_nodes"][done]
    out = {
        "ruptures_complete": int(done.sum()),
        "time": fb.time,
        "cpu_s": cpu,
        "wall_s": wall,
        "engine_events": fb._engine.steps,
        "noise_candidates": fb._engine.noise_counters[0],
        "mean_nodes": float(nodes.mean()),
        "median_nodes": float(np.median(nodes)),
        "max_nodes": int(nodes.max()),
        "nodes_swept": int(nodes.sum()),
        "max_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }
    print("| quantity | value |\n|---|---|")
    for k, v in out.items():
        print(f"| {k} | {v:.6g} |" if isinstance(v, float) else f"| {k} | {v} |")
    return out


def lattice_vs_free_boundary(dxs=(0.2, 0.1, 0.05)) -> list[dict]:
    import pathlib
    import sys

    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "docs" / "scripts"))
    from free_boundary_2d_lattice import GAMMA, L, field

    rows = []
    for k, dx in enumerate((dxs[0], *dxs)):
        # (the first case twice, the first round not kept: it pays the imports of the
        # result tables, pandas and xarray)
        n = int(round(L / dx))
        x = (np.arange(n) + 0.5) * dx
        xx, yy = np.meshgrid(x, x)
        u0 = field(xx, yy)
        p = bk.Params(gamma=GAMMA, v=0.0, dx=dx)
        t0 = time.process_time()
        la = bk.Lattice((n, n), p, u0=u0)
        phi = np.array(la.phi)
        la.kick((0, 0), -2.0)
        la.run(t_end=1.8 * L, progress=False)
        t_la = time.process_time() - t0
        t0 = time.process_time()
        fb = bk.FreeBoundary2D(p, (n, n), dx, phi, "free", origin=(x[0], x[0]))
        fb.trigger(x[0], x[0])
        fb.run(max_events=1)
        t_fb = time.process_time() - t0
        if k:
            rows.append({"dx": dx, "blocks": n * n, "lattice_cpu_s": t_la, "fb2d_cpu_s": t_fb,
                         "ratio": t_la / t_fb})  # fmt: skip
    print("| dx | blocks = nodes | lattice CPU s | FreeBoundary2D CPU s | ratio |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['dx']} | {r['blocks']} | {r['lattice_cpu_s']:.2f} | "
              f"{r['fb2d_cpu_s']:.4f} | {r['ratio']:.0f} |")  # fmt: skip
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scaling", action="store_true")
    ap.add_argument("--long", action="store_true")
    ap.add_argument("--lattice", action="store_true")
    ap.add_argument("--json")
    a = ap.parse_args()
    out = {}
    if a.scaling or not (a.long or a.lattice):
        out["scaling"] = scaling()
    if a.lattice:
        out["lattice"] = lattice_vs_free_boundary()
    if a.long:
        out["long"] = long_run()
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
