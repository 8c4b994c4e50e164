"""Cost of one disordered-front realisation (issue 13): the tip marcher
(bk.disorder.tip_march) against the whole chain (bk.Chain with per-block thresholds, run
as front_speed_ensemble(method="chain") runs it), same thresholds, same session.

Wall time (time.perf_counter(); both engines run in the calling thread), the median of
--repeat runs, for fronts of several lengths at u_+ = 0.6, gamma = 0.3 (a pulse: blocks
re-stick w/dx spacings behind the tip) at dx = 0.1, 0.05, 0.02, and u_+ = 0.25,
gamma = 0.3 (creep: every block behind the front slides for ever, the chain's worst case);
thresholds 1 + 0.1 xi (uniform). Prints a markdown table.

Run: python benchmarks/bench_tip_march.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

import bkwaves as bk
from bkwaves.disorder import thresholds, tip_march

CASES = [(0.6, 0.3, 0.1, n) for n in (1000, 2000, 4000)]
CASES += [(0.6, 0.3, dx, 4000) for dx in (0.05, 0.02)]
CASES += [(0.25, 0.3, 0.1, n) for n in (1000, 2000, 4000)]


def chain(u, g, dx, th):
    ch = bk.Chain(len(th), bk.Params(gamma=g, v=0.0, dx=dx), u0=u, threshold=th)
    ch.kick(0, -2.0)
    return ch.run(t_end=4.0 * len(th) * dx + 100.0, max_events=1).first_slip_times()


def wall(f, repeat):
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return statistics.median(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print("| u_+ | gamma | dx | blocks | chain (s) | tip march (s) | chain/tip | tip us/block |")
    print("|---|---|---|---|---|---|---|---|")
    tip_march(0.6, thresholds(100, 0.1), dx=0.1)  # warm up
    chain(0.6, 0.3, 0.1, thresholds(100, 0.1))
    for u, g, dx, n in CASES:
        th = thresholds(n, 0.1, seed=[1, 0])
        tc = wall(lambda: chain(u, g, dx, th), args.repeat)  # noqa: B023 (called at once)
        tt = wall(lambda: tip_march(u, th, gamma=g, dx=dx), args.repeat)  # noqa: B023
        print(
            f"| {u} | {g} | {dx} | {n} | {tc:.3f} | {tt:.3f} | {tc / tt:.1f} | "
            f"{1e6 * tt / n:.0f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
