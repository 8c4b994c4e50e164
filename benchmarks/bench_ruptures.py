"""The chain's ruptures table (bkwaves.noise_stats.chain_ruptures, the runs' ``ruptures``):
its rupture ids computed by numpy (``_rupture_ids``) against the slip-by-slip loop they
replaced (:func:`rupture_ids_loop`, kept here as the reference; tests/test_noise_stats.py
checks that both give the same ids), on the slips of two real runs: one front across a
chain (one rupture, a chain of parents as long as the chain) and a noisy ring (many
ruptures). CPU time (time.process_time), best of ``--repeat`` rounds, in one process.

Run: python benchmarks/bench_ruptures.py [--blocks 100000] [--repeat 3] [--json out.json]
"""

import argparse
import json
import time

import numpy as np

import bkwaves as bk
from bkwaves import noise_stats as ns


def rupture_ids_loop(ev, blk, t0, spont, n, periodic):
    """chain_ruptures' rule slip by slip (the code before it was vectorised)."""
    last_t = np.full(n, -np.inf)
    owner = np.full(n, -1, dtype=np.int64)
    rid = np.empty(blk.size, dtype=np.int64)
    starts = []
    current = None
    for k in range(blk.size):
        if ev[k] != current:
            current = ev[k]
            last_t[:] = -np.inf
            owner[:] = -1
        b = blk[k]
        left, right = (b - 1) % n if periodic else b - 1, (b + 1) % n if periodic else b + 1
        best, best_t = -1, -np.inf
        for j in (left, right):
            if 0 <= j < n and owner[j] >= 0 and last_t[j] <= t0[k] and last_t[j] > best_t:
                best, best_t = owner[j], last_t[j]
        if spont[k] or best < 0:
            best = len(starts)
            starts.append(k)
        rid[k] = best
        owner[b] = best
        last_t[b] = t0[k]
    return rid, np.array(starts, dtype=np.int64)


def sorted_columns(slips):
    order = np.lexsort((slips.block.to_numpy(), slips.t_start.to_numpy(), slips.event.to_numpy()))
    return (
        slips.event.to_numpy()[order],
        slips.block.to_numpy()[order].astype(np.int64),
        slips.t_start.to_numpy()[order],
        slips.kind.to_numpy()[order] == "noise",
    )


def best_cpu(repeat, f, *args):
    best = np.inf
    for _ in range(repeat):
        t = time.process_time()
        out = f(*args)
        best = min(best, time.process_time() - t)
    return best, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=100000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json")
    a = ap.parse_args()
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
    front = bk.Chain(a.blocks, p, u0=0.6).kick(0, -2.0).run(max_events=1, progress=False)
    # the cycling noisy ring of tests/test_noise_long_runs.py (gamma = 0.85, v = 1e-5)
    ring = bk.Chain(
        400,
        bk.Params(gamma=0.85, v=1e-5, dx=0.05, beta=float("inf")),
        "periodic",
        np.full(400, 0.86),
        noise={"law": "exponential", "rate": 1e-3, "phi0": 0.01, "kick": 0.5},
        seed=1,
    ).run(t_end=2e6, progress=False, max_event_duration=1e9)
    rows = []
    for name, res, n, periodic in (
        (f"front, {a.blocks} blocks", front, a.blocks, False),
        ("noisy ring, 400 blocks", ring, 400, True),
    ):
        cols = sorted_columns(res.slips)
        t_loop, (rid0, st0) = best_cpu(a.repeat, rupture_ids_loop, *cols, n, periodic)
        t_vec, (rid1, st1) = best_cpu(a.repeat, ns._rupture_ids, *cols, n, periodic)
        assert np.array_equal(rid0, rid1) and np.array_equal(st0, st1)
        b = "periodic" if periodic else "free"
        t_table, table = best_cpu(a.repeat, ns.chain_ruptures, res, b)
        slips = len(res.slips)
        rows.append(
            {
                "case": name,
                "slips": slips,
                "ruptures": len(table),
                "loop_us_per_slip": 1e6 * t_loop / slips,
                "numpy_us_per_slip": 1e6 * t_vec / slips,
                "ratio": t_loop / t_vec,
                "table_us_per_slip": 1e6 * t_table / slips,
            }
        )
    print(
        "| case | slips | ruptures | loop us/slip | numpy us/slip | loop/numpy "
        "| whole table us/slip |"
    )
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['case']} | {r['slips']} | {r['ruptures']} | {r['loop_us_per_slip']:.2f} | "
            f"{r['numpy_us_per_slip']:.3f} | {r['ratio']:.0f} | {r['table_us_per_slip']:.2f} |"
        )
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
