"""The coarsening exponent of Sec. V (R ~ t^(1/2)) with more rings and periods than the
report's (docs/paper.md, "Synchronisation"): smooth free-boundary rings (amplitude 0.02,
correlation 25: every maximum below a_max), R = L / (mean sources over rings) fitted as
n^p on doubling windows of periods, bootstrap over rings (bkwaves.paper's estimator).

    python docs/scripts/sync_exponent.py [--rings 32] [--length 1600] [--periods 320]

Rings run on 2 processes. Prints the local exponent against the window with its bootstrap
standard error, the drift between the last two windows and the prefactor R a_n^(1/2).
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from bkwaves import paper
from bkwaves.config import _smooth_random


def ring(args):
    seed, length, periods = args
    h = 0.2
    n = int(round(length / h))
    x = np.arange(n) * h
    u0 = 0.5 + 0.02 * _smooth_random(x, 25.0, np.random.default_rng(seed), True)
    return f"smooth-{seed}", paper.ring_births(length, u0, periods)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rings", type=int, default=32)
    ap.add_argument("--length", type=float, default=1600.0)
    ap.add_argument("--periods", type=int, default=320)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    t0 = time.process_time()
    jobs = [(s, args.length, args.periods) for s in range(1, args.rings + 1)]
    with ProcessPoolExecutor(args.workers) as ex:
        res = dict(ex.map(ring, jobs))
    m = dict(res=res, L=args.length)
    f = paper.coarsening_exponent(m)
    print(f"{args.rings} rings, L = {args.length:g}, {args.periods} periods")
    print("| periods | p | bootstrap error |\n|---|---|---|")
    for w in f["local"]:
        print(f"| {w['window'][0]}-{w['window'][1]} | {w['p']:.3f} | {w['sigma']:.3f} |")
    print(f"| {paper.SYNC_FIT_FROM}-{f['periods']} | {f['p']:.3f} | {f['sigma']:.3f} |")
    print(f"drift of p between the last two windows: {f['drift']:+.3f} +- {f['drift_sigma']:.3f}")
    print(
        f"R a_n^(1/2) over periods {f['prefactor_window']}: {f['prefactor']:.3f} +- "
        f"{f['prefactor_sigma']:.3f} (a_n^(-1/2) = {f['paper_R']:.0f})"
    )
    sites = np.array([r["sites"] for r in res.values()])
    print(f"sources per ring: {sites[:, 0].mean():.1f} -> {sites[:, -1].mean():.1f}")
    print(f"(main process CPU {time.process_time() - t0:.0f} s)")


if __name__ == "__main__":
    main()
