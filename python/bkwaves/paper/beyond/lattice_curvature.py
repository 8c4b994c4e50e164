"""Beyond the paper: the curvature law of the lattice, c_n = c_planar - D kappa, measured
on an expanding rupture with its local curvature, against D derived from the linearised
curved tip problem (docs/lattice.md, docs/theory.md section 7)."""

from __future__ import annotations

#: Not an API: the drawing function below is a plug-in of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; it costs seconds (docs/paper.md says how to add or change a figure).
__all__: list[str] = []

import numpy as np

from ..figure import register_figure


@register_figure("beyond_lattice_curvature_law", 2, beyond=True)
def fig_lattice_curvature_law(axes, quick):
    """Left: the local D = (c_planar - c)/kappa of a rupture on the lattice against its
    local curvature, along x and the diagonal, with the derived kappa -> 0 values. Right:
    the derived coefficient a = D/dx against u_+ along both directions.

    Parameters
    ----------
    axes : matplotlib.axes.Axes or numpy.ndarray of Axes
        The panels to draw into (:func:`bkwaves.paper.figure.panels` hands them over).
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    str
        The caption, with the numbers computed for the figure.
    """
    from ... import lattice, theory

    u, gamma, dx = 0.6, 0.45, 0.1
    size = 48 if quick else 128
    r = lattice.rupture(u, gamma, dx, size=size, check=False)
    ax = axes[0]
    parts = []
    for col, k, name in (("C0", "x", "along $x$"), ("C3", "diagonal", "along the diagonal")):
        m = r.curvature(k)
        d_th = theory.curvature_coefficient(u, gamma, dx, k)
        n = m["kappa"].size
        tail = slice(2 * n // 3, n)
        e, d0 = np.polyfit(m["kappa"][tail], m["D"][tail], 1)
        ok = m["kappa"] < 0.6
        ax.plot(m["kappa"][ok], m["D"][ok], "o", ms=2.5, color=col, label=f"lattice, {name}")
        kk = np.linspace(0.0, m["kappa"][tail].max(), 20)
        ax.plot(kk, d0 + e * kk, "--", lw=0.8, color=col)
        ax.plot([0.0], [d_th], "*", ms=9, color=col, mec="k", mew=0.5, label=f"derived, {name}")
        parts.append(
            f"{k}: derived D = {d_th:.5f}, lattice {m['D'][-1]:.5f} at kappa = "
            f"{m['kappa'][-1]:.3f}, extrapolated to kappa -> 0: {d0:.5f}"
        )
    ax.set_xlim(left=-0.01)
    ax.set_xlabel(r"local curvature $\kappa$")
    ax.set_ylabel(r"$D = (c_{\mathrm{planar}} - c)/\kappa$")
    ax.set_title(rf"Rupture on a lattice, $u_+ = {u}$, $\Delta x = {dx}$", fontsize=9)
    ax.legend(fontsize=6, loc="center right")

    ups = (0.4, 0.6, 0.8) if quick else (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)
    h = 0.05
    ax_ = [theory.curvature_coefficient(v, 0.3, h, "x") / h for v in ups]
    ad = [theory.curvature_coefficient(v, 0.3, h, "diagonal") / h for v in ups]
    ax = axes[1]
    ax.plot(ups, ax_, "o-", color="C0", ms=3, label="along $x$")
    ax.plot(ups, ad, "s-", color="C3", ms=3, label="along the diagonal")
    ax.set_xlabel(r"stress ahead $u_+$")
    ax.set_ylabel(r"$a = D/\Delta x$")
    ax.set_ylim(bottom=0.0)
    ax.set_title(r"Derived coefficient, $\Delta x = 0.05$, $\gamma = 0.3$", fontsize=9)
    ax.legend(fontsize=6, loc="upper left")
    return (
        f"The curvature law of the lattice, c_n = c_planar - D kappa. Left: a rupture from a "
        f"point (u_+ = {u:g}, gamma = {gamma:g}, dx = {dx:g}, a quadrant of {size} blocks), "
        f"its local speed and local curvature where it crosses the x axis and the diagonal "
        f"(Rupture.curvature), the local D against kappa, a line through the outer third "
        f"(dashed) and the kappa -> 0 value derived from the linearised curved tip problem "
        f"(stars; bk.theory.curvature_coefficient): "
        + "; ".join(parts)
        + f". Right: a = D/dx at dx = {h:g}: along x from {ax_[0]:.3f} to {ax_[-1]:.3f}, "
        f"along the diagonal from {ad[0]:.3f} to {ad[-1]:.3f} as u_+ goes from {ups[0]:g} to "
        f"{ups[-1]:g}: the law is anisotropic, more so at high stress."
    )
