"""Frequency-size statistics of ruptures in the plane (docs/free_boundary_2d.md,
"Gutenberg-Richter in the plane?").

    python docs/scripts/free_boundary_2d_gr.py      # a few minutes of CPU

Periodic 256 x 256 grid (h = 0.5, a 128 x 128 square), gamma = 0.3, v = 1e-3, creep rule
"stop" (a front stops where u_+ <= u_c = 0.3), initial stress 0.3 x a random field of
correlation length 3, noise law "power" (g = u^8) at several rates per unit area and time
(at u = 1). After a transient of 5000 time units (five loading times 1/v), the catalog's
moments give b (bk.stats.gutenberg_richter: Mc by maximum curvature + 0.2, Aki-Utsu, 95 %
bootstrap interval) and the areas a Hill exponent beta (P(area >= a) ~ a^-beta above a
fixed a_min). Knobs turned: the noise rate (x10 steps), the grid spacing at the same
square (h = 0.5 and 0.25 at rate 1), the run length (t_end and twice it at rate 1).
"""

import time

import numpy as np

import bkwaves as bk
from bkwaves.free_boundary_2d import random_field

GAMMA, V, T0 = 0.3, 1e-3, 5000.0


def run(rate: float, h: float = 0.5, side: float = 128.0, t_end: float = 35000.0, seed=1):
    n = int(round(side / h))
    u0 = 0.3 * random_field((n, n), h, 3.0, seed=seed)
    fb = bk.FreeBoundary2D(
        bk.Params(gamma=GAMMA, v=V, dx=1e-2),
        (n, n),
        h,
        u0,
        "periodic",
        creep="stop",
        noise={"law": "power", "rate": rate, "exponent": 8.0},
        seed=seed + 1,
    )
    t = time.process_time()
    r = fb.run(t_end=t_end)
    cpu = time.process_time() - t
    ru = r.ruptures[(r.ruptures.t_start > T0) & r.ruptures.complete & (r.ruptures.n_nodes > 0)]
    gr = bk.stats.gutenberg_richter(ru.moment.values)
    a_min = 25.0  # area units (100 nodes at h = 0.5)
    beta, sbeta = bk.stats.power_law_exponent(ru.area.values, s_min=a_min)
    span = t_end - T0
    return {
        "rate": rate,
        "h": h,
        "t_end": t_end,
        "ruptures": len(ru),
        "per_time": len(ru) / span,
        "mean_area": float(ru.area.mean()),
        "max_area": float(ru.area.max()),
        "system": side * side,
        "b": gr.b,
        "b_lo": gr.lo,
        "b_hi": gr.hi,
        "m_c": gr.m_c,
        "n_above": gr.n,
        "beta_area": beta,
        "beta_err": sbeta,
        "u_start": float(ru.u_start.mean()),
        "cpu_s": cpu,
    }


def main():
    print(
        "| rate | h | t_end | ruptures | per unit time | mean area | max area | b [95 %] | "
        "Mc | n >= Mc | beta (area >= 25) | mean u_start | CPU s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|", flush=True)
    rows = []
    for kw in (
        dict(rate=1.0),
        dict(rate=0.1),
        dict(rate=1.0, t_end=65000.0),
        dict(rate=1.0, h=0.25),
        dict(rate=10.0),
    ):
        r = run(**kw)
        rows.append(r)
        print(
            f"| {r['rate']:g} | {r['h']:g} | {r['t_end']:g} | {r['ruptures']} | "
            f"{r['per_time']:.3g} | {r['mean_area']:.3g} | {r['max_area']:.4g} | "
            f"{r['b']:.2f} [{r['b_lo']:.2f}, {r['b_hi']:.2f}] | {r['m_c']:.2f} | "
            f"{r['n_above']} | {r['beta_area']:.2f} +- {r['beta_err']:.2f} | "
            f"{r['u_start']:.3f} | {r['cpu_s']:.1f} |",
            flush=True,
        )
    return rows


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
