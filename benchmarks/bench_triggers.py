"""Cost of scheduling triggers in the chain (issue 14, the event sources): CPU time to
schedule N kicks at scattered times (a permutation of 0..N) on a chain of 8 blocks and run
through all of them, for N = 1e4 and 1e5. The triggers sit in a binary heap, so the cost
grows as N log N (a ratio about 12.5 from 1e4 to 1e5); a list re-sorted on every push grows
as N^2 (a ratio about 100).

Run: python benchmarks/bench_triggers.py [--repeat 3] [--core DIR]
(--core DIR: import the extension module ``_core`` from DIR instead, e.g. an older build.)
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np


def cost(core, n: int) -> float:
    try:
        eng = core.ChainEngine(np.full(8, 0.2), 0.1, 0.0, 0.05, friction={"gamma": 0.3})
    except TypeError:  # an engine from before the friction registry
        eng = core.ChainEngine(np.full(8, 0.2), 0.1, 0.0, 0.3, 0.5, 0.05)
    times = ((np.arange(n) * 7919) % n).astype(float)
    cpu = time.process_time()
    for k in range(n):
        eng.add_trigger(float(times[k]), k % 8, "kick", 0.0)
    while eng.advance(float(n), 2**62, 2**62) == "steps":
        pass
    return time.process_time() - cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--core", default=None)
    args = ap.parse_args()
    if args.core:
        sys.path.insert(0, args.core)
        import _core as core
    else:
        from bkwaves import _core as core
    small = statistics.median(cost(core, 10_000) for _ in range(args.repeat))
    big = statistics.median(cost(core, 100_000) for _ in range(args.repeat))
    print("| N | CPU s |\n|---|---|")
    print(f"| 1e4 | {small:.3f} |\n| 1e5 | {big:.3f} |")
    print(f"\nratio 1e5 / 1e4: {big / small:.1f}")


if __name__ == "__main__":
    main()
