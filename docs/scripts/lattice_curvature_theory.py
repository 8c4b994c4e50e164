"""The derived curvature coefficient against the lattice (docs/lattice.md, "Derived: the
curvature coefficient"; docs/theory.md, section 7).

For each case: D from ``bk.theory.curvature_coefficient`` (kappa -> 0, along x and the
diagonal), and the lattice's local D = (c_planar - c)/kappa of a rupture from a point,
with kappa measured from the arrival times (``Rupture.curvature``), on quadrants of 64
and 128 blocks; the local D is extrapolated to kappa -> 0 by a line through its outer
third (D_lattice(kappa) = D_0 + E kappa). Then the coefficient a = D/dx of the theory as
dx -> 0. Writes docs/lattice_curvature_theory.json.

    python docs/scripts/lattice_curvature_theory.py     # about 3 minutes of CPU
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import bkwaves as bk

CASES = [(0.6, 0.45, 0.1), (0.7, 0.45, 0.1), (0.6, 0.3, 0.1), (0.6, 0.45, 0.2)]
SIZES = (64, 128)
LIMIT_U = (0.4, 0.6, 0.8)
LIMIT_DX = (0.1, 0.05, 0.025)
DIRECTIONS = [(1, 0), (4, 1), (3, 1), (2, 1), (3, 2), (1, 1)]
ANISO = [(0.6, 0.45, 0.1), (0.6, 0.45, 0.05), (0.6, 0.0, 0.1), (0.6, 0.0, 0.05)]
HERE = Path(__file__).resolve().parent.parent


def lattice_d(u, g, dx, size):
    r = bk.lattice.rupture(u, g, dx, size=size, check=False)
    out = {}
    for k in ("x", "diagonal"):
        m = r.curvature(k)
        n = m["kappa"].size
        sl = slice(2 * n // 3, n)
        e, d0 = np.polyfit(m["kappa"][sl], m["D"][sl], 1)
        out[k] = {
            "kappa_min": float(m["kappa"][-1]),
            "D_at_kappa_min": float(m["D"][-1]),
            "D_extrapolated": float(d0),
            "slope_E": float(e),
        }
    return out


def main() -> None:
    rows = []
    print(
        "| u_+ | gamma | dx | direction | D derived | lattice 64: kappa_min, D there, D(kappa->0) "
        "| lattice 128: kappa_min, D there, D(kappa->0) |"
    )
    print("|---|---|---|---|---|---|---|")
    for u, g, dx in CASES:
        th = {k: bk.theory.curvature_coefficient(u, g, dx, k) for k in ("x", "diagonal")}
        lat = {s: lattice_d(u, g, dx, s) for s in SIZES}
        for k in ("x", "diagonal"):
            cells = []
            for s in SIZES:
                m = lat[s][k]
                cells.append(
                    f"{m['kappa_min']:.3f}, {m['D_at_kappa_min']:.5f}, {m['D_extrapolated']:.5f}"
                )
            print(f"| {u} | {g} | {dx} | {k} | {th[k]:.5f} | " + " | ".join(cells) + " |")
            rows.append(
                {
                    "u_plus": u,
                    "gamma": g,
                    "dx": dx,
                    "direction": k,
                    "D_derived": th[k],
                    "lattice": {str(s): lat[s][k] for s in SIZES},
                }
            )
    limit = []
    print()
    print("| u_+ | gamma | dx | a_x = D_x/dx | a_diagonal = D_diagonal/dx |")
    print("|---|---|---|---|---|")
    for u in LIMIT_U:
        for dx in LIMIT_DX:
            ax = bk.theory.curvature_coefficient(u, 0.3, dx, "x") / dx
            ad = bk.theory.curvature_coefficient(u, 0.3, dx, "diagonal") / dx
            print(f"| {u} | 0.3 | {dx} | {ax:.4f} | {ad:.4f} |")
            limit.append({"u_plus": u, "gamma": 0.3, "dx": dx, "a_x": ax, "a_diagonal": ad})
    aniso = []
    print()
    print("| u_+ | gamma | dx | " + " | ".join(f"c({q},{p})" for q, p in DIRECTIONS) + " |")
    print("|---|---|---|" + "---|" * len(DIRECTIONS))
    for u, g, dx in ANISO:
        cs = [bk.theory.lattice_front_speed(u, g, dx, d) for d in DIRECTIONS]
        ds = (
            [bk.theory.curvature_coefficient(u, g, dx, d) for d in DIRECTIONS]
            if dx == 0.1
            else None
        )
        print(f"| {u} | {g} | {dx} | " + " | ".join(f"{c:.6f}" for c in cs) + " |")
        if ds:
            print(f"| D | {g} | {dx} | " + " | ".join(f"{d:.5f}" for d in ds) + " |")
        aniso.append(
            {"u_plus": u, "gamma": g, "dx": dx, "directions": DIRECTIONS, "c": cs, "D": ds}
        )
    out = HERE / "lattice_curvature_theory.json"
    out.write_text(
        json.dumps({"cases": rows, "limit": limit, "anisotropy": aniso}, indent=1) + "\n"
    )
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
