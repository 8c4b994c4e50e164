"""The chain's response to a kick (docs/noise.md, "The response function").

For each (dx, gamma, u): the smallest forward kick that starts a pair of fronts reaching both
ends of a uniform chain of ``--blocks`` blocks at rest (``bk.noise.measured_kick_threshold``,
bisection to 1e-6), beside the closed form ``bk.noise.kick_threshold`` (the kicked block's
first swing trips its neighbours). Then, per (dx, gamma), the propagation-failure stress
u_f: the largest u of a grid below which a kick of 5 starts no propagating pair.

Run: python docs/scripts/noise_response.py   (about a minute on one core)
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import bkwaves as bk

CASES = [(0.1, 0.0), (0.1, 0.3), (0.05, 0.3), (0.025, 0.3), (0.1, 0.6)]
STRESSES = [0.05, 0.1, 0.2, 0.3, 0.4, 0.5]


def failure_stress(dx, gamma, blocks, kick=5.0):
    """Bracket (lo, hi) of the propagation-failure stress on a 0.005 grid."""
    grid = np.round(np.arange(0.005, 0.2001, 0.005), 3)
    ok = [bk.noise.nucleates(float(u), kick, dx, gamma, blocks=blocks) for u in grid]
    if all(ok):
        return 0.0, float(grid[0])
    last_fail = max(i for i, good in enumerate(ok) if not good)
    return float(grid[last_fail]), float(grid[min(last_fail + 1, len(grid) - 1)])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=600)
    args = ap.parse_args()
    print("| dx | gamma | u | K_c chain | K_c closed form | rel. diff |")
    print("|---|---|---|---|---|---|")
    for dx, gamma in CASES:
        for u in STRESSES:
            measured = bk.noise.measured_kick_threshold(u, dx, gamma, blocks=args.blocks)
            theory = bk.noise.kick_threshold(u, dx, gamma)
            rel = abs(measured - theory) / theory if theory > 0 else math.nan
            print(f"| {dx} | {gamma} | {u} | {measured:.6g} | {theory:.6g} | {rel:.1e} |")
    print()
    print("| dx | gamma | u_r (release trips neighbours) | u_f (fronts die below) |")
    print("|---|---|---|---|")
    for dx, gamma in CASES:
        lo, hi = failure_stress(dx, gamma, args.blocks)
        ur = bk.noise.release_stress(dx, gamma)
        print(f"| {dx} | {gamma} | {ur:.4f} | {lo:.3f} < u_f <= {hi:.3f} |")


if __name__ == "__main__":
    main()
