"""How many sub-steps one velocity-weakening onset needs, alone: RK4 against an
exponential integrator (docs/benchmarks.md, "Onset"; issue 22).

    python benchmarks/bench_vw_onset_scalar.py [-o OUT.json]

The model is one block at the front's tip, its neighbours' push taken as given: from its
slip (s = 0, R(0) = theta = 1, m = 1) to the next slip of the chain, t in [0, dx/c],

    s_t = P(t) - R(s),   R(s) = 1/(1 + s/v_f) + 2 gamma s,   P(t) = 1 + t/(c dx),

(gamma = 0.3, dx = 0.05, c = 1.1: the benchmark front of bench_vw_onset.py). It is
integrated by classical RK4 and by ETD-RK4 (Cox and Matthews' exponential RK4 with the
linear part frozen at each sub-step's start, L = -R'(s_n): exact for the onset's
exponential phase while s << v_f), both under one step-doubling controller that holds each
sub-step's error, as a time shift (error in s over s_t), below the engine's shift
tolerance 1e-4 step^5 dx at step 0.05. Printed: the sub-steps taken (accepted and
rejected) and the time shift at the end against scipy's Radau at rtol 1e-13. This is a
count of work, not a timing.
"""

from __future__ import annotations

import argparse
import json
import math

GAMMA, DX, C, STEP = 0.3, 0.05, 1.1, 0.05
TOL = 1e-4 * STEP**5 * DX


def rate(t, s, v_f):
    return 1.0 + t / (C * DX) - (1.0 / (1.0 + abs(s) / v_f) + 2 * GAMMA * s)


def slope(s, v_f):
    """dR/ds."""
    return -1.0 / v_f / (1.0 + abs(s) / v_f) ** 2 + 2 * GAMMA


def rk4(t, s, h, v_f):
    k1 = rate(t, s, v_f)
    k2 = rate(t + h / 2, s + h / 2 * k1, v_f)
    k3 = rate(t + h / 2, s + h / 2 * k2, v_f)
    k4 = rate(t + h, s + h * k3, v_f)
    return s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def _phi1(z):
    return 1.0 + z / 2 + z * z / 6 if abs(z) < 1e-6 else math.expm1(z) / z


def _etd_weights(z):
    """Cox-Matthews' f1, f2, f3 (each 1/6 at z = 0; Taylor below |z| = 0.02)."""
    if abs(z) < 0.02:
        return (
            1 / 6 + z / 6 + 3 * z * z / 40,
            1 / 6 + z / 12 + z * z / 40,
            1 / 6 - z * z / 120,
        )
    e, z3 = math.exp(z), z**3
    return (
        (-4 - z + e * (4 - 3 * z + z * z)) / z3,
        (2 + z + e * (-2 + z)) / z3,
        (-4 - 3 * z - z * z + e * (4 - z)) / z3,
    )


def etd4(t, s, h, v_f):
    lin = -slope(s, v_f)

    def rest(tt, y):
        return rate(tt, y, v_f) - lin * y

    z = h * lin
    e2, e = math.exp(z / 2), math.exp(z)
    p = h / 2 * _phi1(z / 2)
    n0 = rest(t, s)
    a = e2 * s + p * n0
    na = rest(t + h / 2, a)
    b = e2 * s + p * na
    nb = rest(t + h / 2, b)
    c = e2 * a + p * (2 * nb - n0)
    nc = rest(t + h, c)
    f1, f2, f3 = _etd_weights(z)
    return e * s + h * (f1 * n0 + 2 * f2 * (na + nb) + f3 * nc)


def integrate(method, v_f, t_end):
    t, s, h, taken = 0.0, 0.0, STEP * v_f, 0
    while t < t_end:
        h = min(h, t_end - t)
        full = method(t, s, h, v_f)
        half = method(t + h / 2, method(t, s, h / 2, v_f), h / 2, v_f)
        err = abs(full - half) / 15 / max(abs(rate(t + h, half, v_f)), 1e-3)
        taken += 1
        if err <= TOL:
            t, s = t + h, half
            h *= min(4.0, 0.9 * (TOL / max(err, 1e-300)) ** 0.2)
        else:
            h *= max(0.2, 0.9 * (TOL / err) ** 0.2)
    return s, taken


def main() -> None:
    from scipy.integrate import solve_ivp

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--out", default=None)
    a = ap.parse_args()
    t_end = DX / C
    rows = []
    for v_f in (1e-3, 1e-4, 1e-5, 1e-6):
        ref = solve_ivp(
            lambda t, y, v=v_f: [rate(t, y[0], v)],
            (0.0, t_end),
            [0.0],
            method="Radau",
            rtol=1e-13,
            atol=1e-16,
            first_step=v_f * 1e-3,
        ).y[0, -1]
        row = {"v_f": v_f, "v_f_over_dx": v_f / DX}
        for name, m in (("rk4", rk4), ("etd_rk4", etd4)):
            s, n = integrate(m, v_f, t_end)
            row[name] = {"substeps": n, "shift": (s - ref) / rate(t_end, ref, v_f)}
        rows.append(row)
        print(
            f"v_f {v_f:.0e}: RK4 {row['rk4']['substeps']} sub-steps (shift "
            f"{row['rk4']['shift']:.1e}), ETD-RK4 {row['etd_rk4']['substeps']} "
            f"(shift {row['etd_rk4']['shift']:.1e})"
        )
    if a.out:
        with open(a.out, "w") as f:
            json.dump({"gamma": GAMMA, "dx": DX, "c": C, "tol": TOL, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
