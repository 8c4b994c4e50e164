"""Cost of the free boundary engine per event, and against the direct chain.

Run: python benchmarks/bench_free_boundary.py [--chain]
The physical run: a ring of length L = 0.3/v with two smooth bumps on a sinusoidal ramp
(the cross-check state of docs/validation.md), gamma = 0.3, v = 1e-3. Prints markdown
tables of medians over repeats (2-core shared machine: quote medians and ratios).
"""

from __future__ import annotations

import statistics
import sys
import time
import warnings

import numpy as np

import bkwaves as bk

GAMMA, V = 0.3, 1e-3
L = 0.3 / V


def periodic_distance(x, c):
    return np.mod(x - c + 0.5 * L, L) - 0.5 * L


def u0(x):
    w = 40.0 * L / 300.0
    return (
        0.9
        + 0.015 * np.sin(2 * np.pi * x / L)
        + 0.03 * np.exp(-((periodic_distance(x, 0.3 * L) / w) ** 2))
        + 0.025 * np.exp(-((periodic_distance(x, 0.7 * L) / w) ** 2))
    )


def fb_run(h, events):
    x = np.arange(int(round(L / h))) * h
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        fb = bk.FreeBoundary(
            bk.Params(gamma=GAMMA, v=V, dx=1e-3), x, u0(x), "periodic", record_path=False
        )
    t0 = time.perf_counter()
    fb._engine.advance(float("inf"), 2**62, events)
    wall = time.perf_counter() - t0
    return wall, fb._engine.steps, fb._engine.completed_events


def median(f, repeat):
    out = [f() for _ in range(repeat)]
    return statistics.median(o[0] for o in out), out[0][1], out[0][2]


def main():
    print("## free boundary engine: 1000 events on the ring (L = 300, v = 1e-3)")
    print()
    print("| grid h | events | engine events | wall | per event | per engine event |")
    print("|---|---|---|---|---|---|")
    for h in (1.0, 0.5, 0.25):
        wall, steps, ev = median(lambda h=h: fb_run(h, 1000), 3)
        print(
            f"| {h} | {ev} | {steps} | {wall:.3f} s | {wall / ev * 1e3:.3f} ms "
            f"| {wall / steps * 1e6:.2f} us |"
        )
    if "--chain" in sys.argv:
        chain_table()


def chain_table():
    if not hasattr(bk, "Chain"):
        print("\nbk.Chain is not available in this build: chain comparison skipped")
        return
    raise SystemExit("chain comparison: see docs/benchmarks.md")


if __name__ == "__main__":
    main()
