"""The anisotropy check of docs/lattice.md: ruptures with dx/dy = 1.5 as dx -> 0.

A rupture from a point (u_+ = 0.6, gamma = 0.45, v = 0) on a quadrant 4 units of x wide,
kicked at its corner block (the free edges are mirror planes, as in bk.lattice.rupture),
at spacings dx from 0.2 down to 0.0125 (dy = dx/1.5; the CPU time grows like dx^-4: 4
minutes at 0.0125), its aspect (extent along x over extent along y, in blocks) at t = 1,
1.5, 2, 2.5 against dy/dx (a circle in the plane). The run stops at t = 2.6: the front
(c < 1.25) is then at most 3.3 units out, inside the quadrant, and the blocks ahead of
it are stuck and inert, so the quadrant's far edges play no part (checked: a quadrant
3.4 units wide gives the same bits). Besides the deviation dev = aspect dx/dy - 1 it
records

- planar: c(dx)/c(dy) - 1, where the deviation goes as t -> infinity at fixed dx (the
  planar fronts along the axes are the chains at dx and dy, bk.front_speed);
- excess = dev - planar: the part that decays as the rupture grows;
- dev_step: dev with the time step halved (dx >= 0.05), the integrator's error;
- dev_cubic: dev with the extents read by cubic instead of linear interpolation of the
  arrival times, the reading's error.

Writes docs/lattice_anisotropy.json, one row per spacing (written after each). Then

    python docs/scripts/lattice_anisotropy.py --fit

adds the fits of docs/lattice.md to it (no runs): at each t, excess = A dx^p by least
squares in logs over all spacings, p again without the coarsest two and without the
finest two (its spread), the local exponents between successive spacings of dev, excess
and planar, and E = excess t/dx against ln(1/dx) (its slope between successive
spacings). And

    python docs/scripts/lattice_anisotropy.py --kicks

adds the excess at dx = 0.1 and 0.05 with the corner block kicked by 1, 2, 4, 8 instead
of 2 (a few seconds): the excess is the start-up's, it grows with the kick. And

    python docs/scripts/lattice_anisotropy.py --collapse

adds E = excess t/dx at a fixed t/dx (tau = 10, 20, 40, 80) and kick/dx (K = 10, 20, 40,
80) for dx = 0.1, 0.05, 0.025, 0.0125 (10 s): the lattice's equations in the units u =
u_+ + dx^2 U, t = dx tau keep dx only in the loader and drag terms, so E tends to a
function G(tau, K) like dx; G through the two finest spacings, and its slopes in ln tau
and ln K (docs/lattice.md, "The start-up in the lattice's own units").

    nice -n 5 python docs/scripts/lattice_anisotropy.py
"""

import json
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

import bkwaves as bk

U_PLUS, GAMMA, RATIO, WIDTH, T_END = 0.6, 0.45, 1.5, 4.0, 2.6
TIMES = (1.0, 1.5, 2.0, 2.5)
SPACINGS = (0.2, 0.14, 0.1, 0.07, 0.05, 0.035, 0.025, 0.0175, 0.0125)


def extent(arrival, t, cubic=False):
    """The front's place along a row of blocks at time t, in blocks from the centre
    (block k at k + 1/2): arrival times interpolated between blocks."""
    ok = np.isfinite(arrival)
    n = arrival.size if ok.all() else int(np.argmin(ok))
    a = arrival[:n]
    if n < 4 or not (a[0] <= t <= a[-1]) or np.any(np.diff(a) <= 0):
        return math.nan
    k = np.arange(n) + 0.5
    return float(CubicSpline(a, k)(t)) if cubic else float(np.interp(t, a, k))


def quadrant(dx, width=WIDTH, step=bk.chain.DEFAULT_STEP, kick=2.0):
    dy = dx / RATIO
    nx = int(round(width / dx))
    ny = int(round(nx * RATIO))
    p = bk.Params(gamma=GAMMA, v=0.0, dx=dx)
    la = bk.Lattice((nx, ny), p, u0=U_PLUS, dy=dy, step=step)
    la.kick((0, 0), -kick)
    t0 = time.process_time()
    a = la.run(t_end=T_END, progress=False).first_slip_times()
    return a[0], a[:, 0], (nx, ny), time.process_time() - t0


def devs(ax, ay, dx, cubic=False):
    dy = dx / RATIO
    return {t: extent(ax, t, cubic) / extent(ay, t, cubic) * dx / dy - 1.0 for t in TIMES}


def fit(rows):
    """The power laws of the rows' deviations (module docs)."""
    dx = np.array([r["dx"] for r in rows])
    fits = {}
    for t in TIMES:
        exc = np.array([r[f"excess_{t}"] for r in rows])
        dev = np.array([r[f"dev_{t}"] for r in rows])
        p, log_a = np.polyfit(np.log(dx), np.log(exc), 1)
        p_coarse = np.polyfit(np.log(dx[:-2]), np.log(exc[:-2]), 1)[0]
        p_fine = np.polyfit(np.log(dx[2:]), np.log(exc[2:]), 1)[0]
        resid = np.log(exc) - (log_a + p * np.log(dx))

        def local(y):
            return (np.diff(np.log(y)) / np.diff(np.log(dx))).tolist()

        fits[str(t)] = {
            "excess_A": float(np.exp(log_a)),
            "excess_p": float(p),
            "excess_p_without_finest_two": float(p_coarse),
            "excess_p_without_coarsest_two": float(p_fine),
            "excess_fit_rms_log": float(np.sqrt(np.mean(resid**2))),
            "local_exponent_dev": local(dev),
            "local_exponent_excess": local(exc),
        }
    for t in TIMES:
        e = np.array([r[f"excess_{t}"] for r in rows]) * t / dx
        fits[str(t)]["E"] = e.tolist()
        fits[str(t)]["E_slope_vs_ln_1_over_dx"] = (np.diff(e) / -np.diff(np.log(dx))).tolist()
    planar = np.array([-r["planar"] for r in rows])
    fits["planar_over_dx"] = (-planar / dx).tolist()
    fits["local_exponent_planar"] = (np.diff(np.log(planar)) / np.diff(np.log(dx))).tolist()
    return fits


TAUS = (10, 20, 40, 80)
KS = (10, 20, 40, 80)
COLLAPSE_SPACINGS = (0.1, 0.05, 0.025, 0.0125)


def collapse():
    """The excess at a fixed t/dx and kick/dx for each spacing (module docs): the rows,
    then per (tau, K) the limit dx -> 0 (linear in dx through the finest two) and the
    slopes of that limit G in ln tau and ln K."""
    rows = []
    for tau in TAUS:
        for k in KS:
            for dx in COLLAPSE_SPACINGS:
                t, kick = tau * dx, k * dx
                if t + 4 * dx > T_END:
                    continue
                # (the front is at most 1.25 t out: a quadrant a few blocks wider is
                # the same bits as a larger one, the blocks ahead of the front inert)
                width = min(WIDTH, 1.3 * (t + 4 * dx) + 8 * dx)
                dy = dx / RATIO
                nx = int(round(width / dx))
                ny = int(round(nx * RATIO))
                p = bk.Params(gamma=GAMMA, v=0.0, dx=dx)
                la = bk.Lattice((nx, ny), p, u0=U_PLUS, dy=dy)
                la.kick((0, 0), -kick)
                a = la.run(t_end=t + 4 * dx, progress=False).first_slip_times()
                dev = extent(a[0], t) / extent(a[:, 0], t) * dx / dy - 1.0
                cx = bk.front_speed(U_PLUS, dx=dx, gamma=GAMMA)
                cy = bk.front_speed(U_PLUS, dx=dy, gamma=GAMMA)
                excess = dev - (cx / cy - 1.0)
                row = {
                    "tau": tau,
                    "K": k,
                    "dx": dx,
                    "t": t,
                    "kick": kick,
                    "size": [nx, ny],
                    "dev": dev,
                    "excess": excess,
                    "E": excess * t / dx,
                }
                rows.append(row)
                print(row, flush=True)
    limits = {}
    for tau in TAUS:
        for k in KS:
            e = sorted(
                (r["dx"], r["E"])
                for r in rows
                if r["tau"] == tau and r["K"] == k and math.isfinite(r["E"])
            )
            if len(e) >= 2:
                (d1, e1), (d2, e2) = e[0], e[1]
                limits[(tau, k)] = e1 - d1 * (e2 - e1) / (d2 - d1)
    slopes = {"dG_dln_tau": {}, "dG_dln_K": {}}
    for tau, tau2 in zip(TAUS[:-1], TAUS[1:], strict=True):
        for k in KS:
            if (tau, k) in limits and (tau2, k) in limits:
                s = (limits[(tau2, k)] - limits[(tau, k)]) / math.log(tau2 / tau)
                slopes["dG_dln_tau"][f"{tau}-{tau2}, K {k}"] = s
    for k, k2 in zip(KS[:-1], KS[1:], strict=True):
        for tau in TAUS:
            if (tau, k) in limits and (tau, k2) in limits:
                s = (limits[(tau, k2)] - limits[(tau, k)]) / math.log(k2 / k)
                slopes["dG_dln_K"][f"tau {tau}, {k}-{k2}"] = s
    return {
        "rows": rows,
        "G_limit": [{"tau": tau, "K": k, "G": g} for (tau, k), g in limits.items()],
        **slopes,
    }


def main():
    path = Path(__file__).resolve().parents[1] / "lattice_anisotropy.json"
    if any(a in sys.argv for a in ("--fit", "--kicks", "--collapse")):
        doc = json.loads(path.read_text())
        doc = doc if isinstance(doc, dict) else {"rows": doc}
        if "--fit" in sys.argv:
            doc["fits"] = fit(doc["rows"])
        if "--kicks" in sys.argv:
            doc["kicks"] = kicks()
        if "--collapse" in sys.argv:
            doc["collapse"] = collapse()
        path.write_text(json.dumps(doc, indent=1) + "\n")
        return
    spacings(path)


def kicks():
    """The excess at dx = 0.1 and 0.05 with the corner block kicked by 1, 2, 4, 8."""
    out = []
    for dx in (0.1, 0.05):
        cx = bk.front_speed(U_PLUS, dx=dx, gamma=GAMMA)
        cy = bk.front_speed(U_PLUS, dx=dx / RATIO, gamma=GAMMA)
        for kick in (1.0, 2.0, 4.0, 8.0):
            ax, ay, _, _ = quadrant(dx, kick=kick)
            d = devs(ax, ay, dx)
            row = {"dx": dx, "kick": kick}
            row.update({f"excess_{t}": d[t] - (cx / cy - 1.0) for t in TIMES})
            out.append(row)
            print(row, flush=True)
    return out


def spacings(path):
    """The table of docs/lattice.md: one row per spacing, written after each."""
    out = []
    for dx in SPACINGS:
        dy = dx / RATIO
        ax, ay, size, cpu = quadrant(dx)
        cx = bk.front_speed(U_PLUS, dx=dx, gamma=GAMMA)
        cy = bk.front_speed(U_PLUS, dx=dy, gamma=GAMMA)
        row = {"dx": dx, "dy": dy, "size": list(size), "cpu": cpu, "c_x": cx, "c_y": cy}
        row["planar"] = cx / cy - 1.0
        d, dc = devs(ax, ay, dx), devs(ax, ay, dx, cubic=True)
        for t in TIMES:
            row[f"aspect_{t}"] = (d[t] + 1.0) * dy / dx
            row[f"dev_{t}"] = d[t]
            row[f"excess_{t}"] = d[t] - row["planar"]
            row[f"dev_cubic_{t}"] = dc[t]
        if dx >= 0.05:
            bx, by, _, _ = quadrant(dx, step=bk.chain.DEFAULT_STEP / 2)
            for t, v in devs(bx, by, dx).items():
                row[f"dev_step_{t}"] = v
        if dx in (0.1, 0.05):
            sx, sy, small, _ = quadrant(dx, width=3.4)
            n = min(sx.size, ax.size)
            m = min(sy.size, ay.size)
            same = np.array_equal(sx[:n], ax[:n], equal_nan=True)
            row["smaller_quadrant"] = list(small)
            row["smaller_quadrant_same_bits"] = bool(
                same and np.array_equal(sy[:m], ay[:m], equal_nan=True)
            )
        out.append(row)
        print(row, flush=True)
        path.write_text(json.dumps(out, indent=1) + "\n")  # (after each spacing)


if __name__ == "__main__":
    main()
