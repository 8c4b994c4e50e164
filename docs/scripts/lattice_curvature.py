"""The curvature correction of an expanding rupture on the lattice (docs/lattice.md):
the local speed c(R) along the axes and the diagonal of a rupture from a point, fitted as
c(R) = c0 - D/R, for a few u_+, gamma and dx, each on a quadrant of SIZE and of 2 SIZE
blocks (the measurement's convergence), with the planar speeds of the exact reductions.
Writes docs/lattice_curvature.json and the figure docs/figures/beyond_lattice_curvature.png.

    python docs/scripts/lattice_curvature.py        # about 15 minutes on one busy core
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

import bkwaves as bk

SIZE = 64
CASES = [
    (0.6, 0.45, 0.1),
    (0.7, 0.45, 0.1),
    (0.6, 0.3, 0.1),
    (0.6, 0.45, 0.2),
]
HERE = Path(__file__).resolve().parent.parent


def main() -> None:
    rows = []
    ruptures = []
    print(
        "| u_+ | gamma | dx | direction | planar c | fit c0, D | D (c0 = planar), lower / "
        "upper half | the same at 2x size |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for u, g, dx in CASES:
        r = bk.lattice.rupture(u, g, dx, SIZE)
        ruptures.append(r)
        for k in ("x", "diagonal"):
            c0, d = r.fits[k]
            c02, d2 = r.check["fits"][k]
            e1, e2 = r.eikonal[k]
            f1, f2 = r.check["eikonal"][k]
            row = {
                "u_plus": u,
                "gamma": g,
                "dx": dx,
                "direction": k,
                "planar_c": r.planar[k],
                "c0": c0,
                "D": d,
                "c0_2x": c02,
                "D_2x": d2,
                "D_planar_halves": [e1, e2],
                "D_planar_halves_2x": [f1, f2],
                "fit_range": list(r.fit_range),
                "continuum_c": 1.0 / math.sqrt(1.0 - u * u),
            }
            rows.append(row)
            print(
                f"| {u} | {g} | {dx} | {k} | {r.planar[k]:.5f} | {c0:.5f}, {d:.4f} | "
                f"{e1:.4f} / {e2:.4f} | {f1:.4f} / {f2:.4f} |"
            )
    (HERE / "lattice_curvature.json").write_text(json.dumps(rows, indent=1) + "\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for r in ruptures:
        lab = f"u+={r.u_plus}, g={r.gamma}, dx={r.dx}"
        color = None
        for k, ls in (("x", "-"), ("diagonal", "--")):
            p = r.profiles[k]
            m = np.isfinite(p["c"]) & (p["r"] > 2.0 * r.dx * 8)
            x, y = r.dx / p["r"][m], p["c"][m] - r.planar[k]
            line = ax[0].plot(x, y, ls, lw=1, color=color, label=lab if k == "x" else None)[0]
            color = line.get_color()
        a = r.arrival
        ax[1].contour(a, levels=8, linewidths=0.6) if r is ruptures[0] else None
    ax[0].set_xlabel("dx/R (R in blocks: 1/R)")
    ax[0].set_ylabel("c(R) - c_planar (solid: along x, dashed: diagonal)")
    ax[0].legend(fontsize=7)
    ax[1].set_title("arrival-time contours (first case, quadrant)")
    ax[1].set_aspect("equal")
    fig.tight_layout()
    fig.savefig(HERE / "figures" / "beyond_lattice_curvature.png", dpi=120)


if __name__ == "__main__":
    main()
