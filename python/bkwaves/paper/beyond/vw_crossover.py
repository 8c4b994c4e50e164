"""Beyond the paper: velocity-weakening friction against eq. (crit), the front speed
and slipping zone against v_f/dx (docs/velocity_weakening.md)."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import math

from ..figure import register_figure


@register_figure("beyond_vw_crossover", 2, beyond=True)
def fig_vw_crossover(axes, quick):
    """Velocity-weakening friction against eq. (crit): front speed c and slipping zone
    (lattice spacings) against v_f/dx at several dx (bkwaves.velocity_weakening).

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
    from ... import velocity_weakening as vw
    from ...waves import front_speed, traveling_wave

    u, gamma = 0.6, 0.3
    dxs = (0.1, 0.05) if quick else (0.1, 0.05, 0.025)
    ratios = (0.03, 0.3, 3.0, 30.0) if quick else (0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0)
    ax, az = axes
    gaps, near_one, deaths, first_dead, zone_at = [], [], [], [], {}
    c_ref, c_all, z_all = [], [], []
    w_c = traveling_wave(u, gamma).w
    # converged fronts (the chain doubled until c and the zone stop moving): c to 1e-6,
    # the zone to 1e-3 (u_- is not plotted)
    tol = {"c": 1e-6, "zone": 1e-3, "u_minus": math.inf}
    moved = {"c": 0.0, "zone": 0.0}
    undecided = []
    for i, dx in enumerate(dxs):
        fronts = [vw.front(u, gamma, dx, r * dx, weakening=False, tolerance=tol) for r in ratios]
        for f in fronts:
            if f.status == "undecided":
                undecided.append(f"v_f/dx = {f.ratio:g} at dx = {dx:g}")
            if f.convergence:
                for k in moved:
                    moved[k] = max(moved[k], f.convergence[k] or 0.0)
        live = [f for f in fronts if f.status != "dies"]
        dead = [f.ratio for f in fronts if f.status == "dies"]
        c_c = float(front_speed(u, dx=dx, gamma=gamma))
        r = [f.ratio for f in live]
        ax.semilogx(
            r, [f.c for f in live], "o-", color=f"C{i}", ms=4, label=f"$\\Delta x = {dx:g}$"
        )
        ax.axhline(c_c, color=f"C{i}", ls="--", lw=0.8, label=f"Coulomb, $\\Delta x = {dx:g}$")
        # no front, no c: the crosses sit in a strip along the bottom edge (axes coordinates)
        ax.plot(
            dead,
            [0.035 + 0.05 * i] * len(dead),
            "x",
            color=f"C{i}",
            ms=7,
            transform=ax.get_xaxis_transform(),
            label=f"no front, $\\Delta x = {dx:g}$" if dead else None,
        )
        az.loglog(
            r, [f.zone for f in live], "o-", color=f"C{i}", ms=4, label=f"$\\Delta x = {dx:g}$"
        )
        az.axhline(
            w_c / dx, color=f"C{i}", ls="--", lw=0.8, label=f"Coulomb pulse, $\\Delta x = {dx:g}$"
        )
        c_ref.append(c_c)
        c_all += [f.c for f in live]
        z_all += [f.zone for f in live] + [w_c / dx]
        gaps.append(1.0 - live[0].c / c_c)
        near_one += [abs(f.c - 1.0) for f in live if f.ratio >= 1.0]
        if dead:  # the first v_f of the grid at which the front dies
            first_dead.append(min(dead) * dx)
            deaths.append(f"{min(dead) * dx:.2g} at dx = {dx:g}")
        zone_at[dx] = {f.ratio: f.zone for f in live}
    ax.axhline(1.0, color="k", ls=":", lw=1, label="sound speed $c = 1$")
    ax.set_xlabel(r"$v_f / \Delta x$")
    ax.set_ylabel("front speed $c$")
    # room below the data for the strip of crosses, above for the reference lines
    lo, hi = min(c_all + [1.0]), max(c_all + c_ref)
    ax.set_ylim(lo - 0.25 * (hi - lo), hi + 0.08 * (hi - lo))
    # the strip: a grey band below a line, labelled, and no c ticks inside it
    from matplotlib.patches import Rectangle

    ax.add_patch(Rectangle((0, 0), 1, 0.12, transform=ax.transAxes, color="0.9", zorder=0))
    ax.text(0.01, 0.06, "no front:", transform=ax.transAxes, fontsize=7, va="center")
    y0, y1 = ax.get_ylim()
    ax.set_yticks([t for t in ax.get_yticks() if y0 + 0.13 * (y1 - y0) <= t <= y1])
    ax.legend(fontsize=6, loc="center right")
    ax.set_title(f"Front speed, $u_+ = {u:g}$, $\\gamma = {gamma:g}$ (x: no front)", fontsize=9)
    from matplotlib.ticker import FormatStrFormatter, ScalarFormatter

    az.yaxis.set_major_formatter(ScalarFormatter())
    az.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
    az.set_xlabel(r"$v_f / \Delta x$")
    az.set_ylabel(r"slipping zone / $\Delta x$")
    az.set_ylim(min(z_all) / 1.3, max(z_all) * 1.3)
    az.legend(fontsize=6, loc="lower left")
    az.set_title("Slipping zone in lattice spacings", fontsize=9)
    star = vw.v_f_existence(u, gamma)
    # the slipping zone at the largest v_f/dx where every dx has a front
    common = max(set.intersection(*(set(z) for z in zone_at.values())))
    zone = ", ".join(f"{zone_at[dx][common]:.0f}" for dx in dxs)
    grows = all(zone_at[a][common] < zone_at[b][common] for a, b in zip(dxs, dxs[1:], strict=False))
    where = "above" if min(first_dead) > star else "near"
    return (
        f"Velocity-weakening friction, R(s) = 1/(1 + s/v_f) + 2 gamma s, u_+ = {u:g}, "
        f"gamma = {gamma:g}: the front of `bkwaves front` against v_f/dx (eq. crit), dashed: "
        f"the Coulomb chain at the same dx (left: its speed from the finite-dx tip problem; "
        f"right: App. B's pulse width w/dx). At v_f/dx = {ratios[0]:g} the front is still "
        f"{100 * min(gaps):.1f}-{100 * max(gaps):.1f} % slower than Coulomb's: the Coulomb "
        f"limit needs v_f << dx by far more than a factor {1 / ratios[0]:.0f}. For "
        f"v_f >= dx it runs within {100 * max(near_one):.1f} % of the sound speed, as the "
        f"paper says. At v_f/dx = {common:g} the slipping zone is {zone} lattice spacings at "
        f"dx = {', '.join(f'{dx:g}' for dx in dxs)} (the Coulomb pulse: "
        f"{', '.join(f'{w_c / dx:.0f}' for dx in dxs)}); "
        f"{'it grows as dx falls (a few lattice spacings only at coarse dx). ' if grows else ''}"
        f"The front dies (crosses in the grey strip) on this grid from v_f = "
        f"{', '.join(deaths)} on, {where} "
        f"v_f* = {star:.2g} where min R reaches u_+, whatever dx: the v_f >> dx regime "
        f"needs dx << v_f*. Every front is converged: the chain was doubled until the last "
        f"doubling moved c by at most {moved['c']:.0e} and the slipping zone by at most "
        f"{moved['zone']:.0e} (relative)"
        + (f"; not converged: {', '.join(undecided)}." if undecided else ".")
    )
