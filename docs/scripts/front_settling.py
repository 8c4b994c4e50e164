"""How fast the healing front of `bkwaves front` settles (docs/chain.md, "The front
experiment"): the measurement behind the default chain length.

For each (gamma, u_+, dx) the default measurement (``bk.chain.front``) gives c, w and the
settling length x_s = w v/(c - v) (v: the fastest lattice wave). A chain 4 x_s long is then
run once more and the sliding time of every block compared with the steady value (the
sliding time at 0.8 of the chain): the table gives the largest relative deviation beyond
k x_s (up to 0.8 of the chain) for k = 0.5, 1, 1.5, 2, and the default measurement's
regime, steadiness, blocks and wall time.

Run: python docs/scripts/front_settling.py   (about a minute on 2 cores)
"""

from __future__ import annotations

import time

import numpy as np

import bkwaves as bk
from bkwaves import _core

CASES = [
    (0.3, 0.4, 0.025),
    (0.0, 0.3, 0.025),
    (0.3, 0.6, 0.05),
    (0.0, 0.5, 0.025),
    (0.45, 0.6, 0.025),
    (0.3, 0.35, 0.025),
    (0.1, 0.15, 0.025),
    (0.0, 0.1, 0.025),
    (0.15, 0.8, 0.04),
    (0.3, 0.99, 0.05),
]
KS = (0.5, 1.0, 1.5, 2.0)


def main() -> None:
    head = "| gamma | u_+ | dx | c | w | x_s | " + " | ".join(f"dev > {k} x_s" for k in KS)
    print(head + " | default: regime, steadiness, blocks, wall |")
    print("|" + "---|" * (6 + len(KS) + 1))
    for g, u, dx in CASES:
        m = bk.chain.front(u, g, dx)
        xs = m.settling_length
        n = int(4 * xs / dx) + 200
        r = _core.front_measure(u, dx, n, friction={"gamma": g}, window=(0.8, 0.9))
        dur = r["stick_times"] - r["slip_times"]
        end = int(0.8 * n)
        dev = np.abs(dur / dur[end] - 1)
        cells = [f"{dev[int(k * xs / dx) : end].max():.0e}" for k in KS]
        print(
            f"| {g} | {u} | {dx} | {m.c:.5f} | {m.w:.4f} | {xs:.1f} | "
            + " | ".join(cells)
            + f" | {m.regime}, {m.steadiness:.0e}, {m.blocks}, {m.wall_s:.2f} s |",
            flush=True,
        )


if __name__ == "__main__":
    t0 = time.perf_counter()
    main()
    print(f"\n({time.perf_counter() - t0:.0f} s)")
