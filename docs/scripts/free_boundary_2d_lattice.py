"""FreeBoundary2D against the lattice (bk.Lattice): one rupture in a smooth stress field.

Run: python docs/scripts/free_boundary_2d_lattice.py [--dx 0.2 0.1 0.05] [--table]
[--json FILE]

The physical domain is a quadrant [0, L]^2, L = 8 (in the paper's units), with free
edges: the lattice's free edge is a mirror plane at half a spacing, so blocks sit at
((i + 1/2) dx, (j + 1/2) dx) and a field even about both edges (cosines of m pi x/L)
has no spurious gradient there. The stress u(x, y) = 0.62 + 0.1 f, f a fixed random
combination of cos(m pi x/L) cos(n pi y/L), m, n <= 2, normalised to max |f| = 1, v = 0,
gamma = 0.45: u_+ in [0.52, 0.68], above u_c everywhere, so the rupture runs through the
whole quadrant. The lattice is kicked at its corner block (u_t -= 2); FreeBoundary2D is
triggered at the same node on the same nodes (h = dx), with the lattice's stress
phi = u - Lap u (the force on a stuck block, which decides slip; it differs from u by
the field's Laplacian, up to 0.05 here) as its u_+ field, and also with u itself.

Compared: the first-slip times of the lattice and the arrival times of FreeBoundary2D,
over the nodes at distance > L/4 from the corner (away from the kick): the mean
difference, the largest, and the largest after removing the median (the start: a kick
is not a point source), for
- "plain": the exact law c = 1/sqrt(1 - u_+^2), no curvature correction;
- "speed": the lattice's planar speed along x at this dx (bk.tip_solve, the chain's c at
  dx) as the speed law;
- "speed_diag": that law along the axes and the chain's c at dx/sqrt(2) (the lattice's
  exact diagonal reduction) along the diagonals (``speed_diagonal=``);
- "speed_curv": the axis law with the lattice's curvature correction c_n = c - D kappa,
  D = a dx with a = 0.24 along the axes and 0.44 along the diagonals (docs/lattice.md,
  "Measured: the curvature correction"; ``curvature=``);
- "shape": both (the diagonal law and the curvature correction);
- "curv_theory", "shape_theory": as "speed_curv" and "shape" with the derived D at the
  axis and the diagonal (bk.theory.curvature_coefficient at the field's mean u_+ = 0.62)
  instead of the measured a;
- with --table, "curv_table", "shape_table": as "curv_theory" and "shape_theory" with the
  derived D along five lattice directions (1, 0), (3, 1), (2, 1), (3, 2), (1, 1) as a table
  in theta (bk.free_boundary_2d.lattice_curvature at u_+ = 0.62), interpolated in
  cos(4 theta) instead of the sin^2(2 theta) between the axis and the diagonal.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import bkwaves as bk

L, GAMMA = 8.0, 0.45
A_AXIS, A_DIAG = 0.24, 0.44
VARIANTS = (
    "plain_u", "plain", "speed", "speed_diag", "speed_curv", "shape", "curv_theory",
    "shape_theory",
)  # fmt: skip


def field(x, y):
    rng = np.random.default_rng(3)
    f = np.zeros_like(x)
    for m in range(3):
        for n in range(3):
            if m or n:
                f += rng.normal() * np.cos(m * np.pi * x / L) * np.cos(n * np.pi * y / L)
    return 0.62 + 0.1 * f / np.abs(f).max()


def speed_at(dx):
    u = np.arange(0.4, 0.951, 0.025)
    return {"u_plus": list(u), "c": [bk.tip_solve(float(q), dx=dx, gamma=GAMMA)["c"] for q in u]}


def compare(dx: float, table: bool = False) -> dict:
    n = int(round(L / dx))
    x = (np.arange(n) + 0.5) * dx
    xx, yy = np.meshgrid(x, x)
    u0 = field(xx, yy)
    p = bk.Params(gamma=GAMMA, v=0.0, dx=dx)
    t0 = time.process_time()
    la = bk.Lattice((n, n), p, u0=u0)
    phi = np.array(la.phi)
    la.kick((0, 0), -2.0)
    tl = la.run(t_end=1.8 * L, progress=False).first_slip_times()
    out = {"dx": dx, "blocks": n * n, "lattice_cpu_s": time.process_time() - t0}
    far = np.hypot(xx, yy) > L / 4
    out["phi_minus_u_max"] = float(np.abs(phi - u0).max())
    axis, diag = speed_at(dx), speed_at(dx / np.sqrt(2.0))
    curv = (A_AXIS * dx, A_DIAG * dx)
    theory = tuple(
        float(bk.theory.curvature_coefficient(0.62, GAMMA, dx, direction=d))
        for d in ("x", "diagonal")
    )
    out["curvature_theory"] = list(theory)
    variants = {
        "plain_u": dict(u=u0),
        "plain": dict(u=phi),
        "speed": dict(u=phi, speed=axis),
        "speed_diag": dict(u=phi, speed=axis, speed_diagonal=diag),
        "speed_curv": dict(u=phi, speed=axis, curvature=curv),
        "shape": dict(u=phi, speed=axis, speed_diagonal=diag, curvature=curv),
        "curv_theory": dict(u=phi, speed=axis, curvature=theory),
        "shape_theory": dict(u=phi, speed=axis, speed_diagonal=diag, curvature=theory),
    }
    if table:
        t0 = time.process_time()
        dirs = bk.free_boundary_2d.lattice_curvature(0.62, GAMMA, dx)
        out["curvature_table"] = dirs
        out["curvature_table_cpu_s"] = time.process_time() - t0
        variants["curv_table"] = dict(u=phi, speed=axis, curvature=dirs)
        variants["shape_table"] = dict(u=phi, speed=axis, speed_diagonal=diag, curvature=dirs)
    for name, kw in variants.items():
        t0 = time.process_time()
        fb = bk.FreeBoundary2D(
            p, (n, n), dx, kw["u"], "free", origin=(x[0], x[0]), record_arrivals=True,
            speed=kw.get("speed"), speed_diagonal=kw.get("speed_diagonal"),
            curvature=kw.get("curvature"),
        )  # fmt: skip
        fb.trigger(x[0], x[0])
        fb.run(max_events=1, progress=False)
        tf = fb.arrival_time(0)
        d = (tl - tf)[far]
        off = float(np.median(d))
        out[name] = {
            "cpu_s": time.process_time() - t0,
            "mean": float(d.mean()),
            "max_abs": float(np.abs(d).max()),
            "max_abs_minus_median": float(np.abs(d - off).max()),
            "rms_minus_median": float(np.sqrt(np.mean((d - off) ** 2))),
            "median": off,
            "t_far_max": float(tl[far].max()),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dx", type=float, nargs="+", default=[0.2, 0.1, 0.05])
    ap.add_argument("--table", action="store_true", help="also the D(theta) table variants")
    ap.add_argument("--json")
    a = ap.parse_args()
    rows = []
    print("| dx | variant | mean | max abs | max abs - median | rms - median |")
    print("|---|---|---|---|---|---|")
    for dx in a.dx:
        r = compare(dx, a.table)
        rows.append(r)
        for name in VARIANTS + (("curv_table", "shape_table") if a.table else ()):
            q = r[name]
            print(
                f"| {dx} | {name} | {q['mean']:.4f} | {q['max_abs']:.4f} | "
                f"{q['max_abs_minus_median']:.4f} | {q['rms_minus_median']:.4f} |",
                flush=True,
            )
    if a.json:
        with open(a.json, "w") as f:
            doc = {"L": L, "gamma": GAMMA, "a_axis": A_AXIS, "a_diag": A_DIAG, "rows": rows}
            json.dump(doc, f, indent=1)


if __name__ == "__main__":
    main()
