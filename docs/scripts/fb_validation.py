"""Numbers quoted in docs/validation.md, section "Free boundary problem".

Run: python docs/scripts/fb_validation.py  (a few seconds)
"""

from __future__ import annotations

import warnings

import numpy as np

import bkwaves as bk
from bkwaves import theory

warnings.simplefilter("ignore", bk.NoCreepWarning)
G = 0.3


def source(a, v, n=801, X=40.0, tol=1e-12):
    x = np.linspace(-X, X, n)
    h = x[1] - x[0]
    x0 = 0.3 * h
    fb = bk.FreeBoundary(bk.Params(gamma=G, v=v, dx=1e-3), x, 1 - 1e-3 - a * (x - x0) ** 2, tol=tol)
    return fb, x0


def map_table():
    print("## curvature at x0 at successive births vs the map of eq. (ap), a0 = 1e-4, v = 1e-2")
    print("| grid h | tol | max rel. deviation over 7 iterates |")
    print("|---|---|---|")
    for n in (401, 801, 1601):
        for tol in (1e-9, 1e-12):
            fb, x0 = source(1e-4, 1e-2, n=n, tol=tol)
            e = fb.run(max_events=8).events
            th = theory.iterate_map(1e-4, 1e-2, G, len(e) - 1)
            dev = np.max(np.abs(e.curvature.to_numpy()[1:] / th[1:] - 1))
            print(f"| {fb.h:.3g} | {tol:g} | {dev:.2e} |")


def window_table():
    print()
    print("## curvature of u after one passage fitted over |x - x0| < w, vs eq. (ap)")
    print("| a | v | a' (eq. ap) | w | a u-range 1 - u_+ at w | fitted a' | rel. dev. |")
    print("|---|---|---|---|---|---|---|")
    for a, v in ((1e-4, 1e-2), (1e-3, 1e-2), (1e-3, 3e-2)):
        fb, x0 = source(a, v, n=3201, X=40.0)
        fb.run(max_events=1)
        ap = theory.a_prime(a, v, G)
        u = fb.u()
        for w in (0.25, 1.0, 4.0, 16.0):
            near = np.abs(fb.x - x0) < w
            fit = -np.polyfit(fb.x[near] - x0, u[near], 2)[0]
            print(
                f"| {a:g} | {v:g} | {ap:.6e} | {w:g} | {a * w * w:.1e} | {fit:.6e} "
                f"| {fit / ap - 1:+.2e} |"
            )


def birth_table():
    print()
    print("## early shock positions vs x0 + sqrt(b t) (eq. b), a = 1e-3, v = 1e-2")
    print("| distance from x0 | 1 - u_+ | |x - x0| / sqrt(b t) - 1 |")
    print("|---|---|---|")
    a, v = 1e-3, 1e-2
    fb, x0 = source(a, v, n=8001)
    r = fb.run(max_events=1)
    b = theory.source_b(a, v)
    tb = r.events.t_start.iloc[0]
    s = r.shocks[(r.shocks.dir == 1) & (r.shocks.kind == "node")]
    d = s.x.to_numpy() - x0
    for target in (0.01, 0.1, 1.0, 3.0, 10.0):
        i = int(np.argmin(np.abs(d - target)))
        t = s.t.iloc[i] - tb
        print(f"| {d[i]:.3g} | {1 - s.u_plus.iloc[i]:.2e} | {d[i] / np.sqrt(b * t) - 1:+.2e} |")


if __name__ == "__main__":
    map_table()
    window_table()
    birth_table()
