"""Cost of the free boundary engine per event, and against the direct chain.

Run: python benchmarks/bench_free_boundary.py [--chain]   (--chain: also bk.Chain, ~30 s)
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


def chain_run(dx):
    n = int(round(L / dx))
    p = bk.Params(gamma=GAMMA, v=V, dx=dx, beta=0.0)  # as measured in docs/benchmarks.md
    ch = bk.Chain(n, p, "periodic", u0(np.arange(n) * dx))
    t0 = time.perf_counter()
    r = ch.run(max_events=1, progress=False)
    return time.perf_counter() - t0, r.catalog.moment.iloc[0] * dx


def chain_table():
    """The same physical run through the Python APIs: first event of bk.Chain against
    bk.FreeBoundary's median cost per event over 1000 events (grid h = 1)."""
    fb_event, _, _ = median(lambda: fb_run(1.0, 1000), 3)
    fb_event /= 1000
    print()
    print("## bk.Chain (first event, median of 3) vs bk.FreeBoundary (per event, h = 1)")
    print()
    print("| dx | blocks | chain | free boundary | ratio | slip chain / fb - 1 |")
    print("|---|---|---|---|---|---|")
    x = np.arange(300) * (L / 300)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        ref = bk.FreeBoundary(bk.Params(gamma=GAMMA, v=V, dx=1.0), x, u0(x), "periodic")
    slip_fb = ref.run(max_events=1).events.slip_integral.iloc[0]
    for dx in (0.1, 0.05, 0.025):
        runs = [chain_run(dx) for _ in range(3)]
        wall = statistics.median(r[0] for r in runs)
        print(
            f"| {dx} | {int(round(L / dx))} | {wall:.3f} s | {fb_event * 1e3:.2f} ms "
            f"| {wall / fb_event:.0f} | {runs[0][1] / slip_fb - 1:+.1e} |"
        )


if __name__ == "__main__":
    main()
