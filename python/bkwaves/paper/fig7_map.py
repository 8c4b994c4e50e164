"""Fig. 7: the source map a -> a' of eq. (ap), and the claims on it: eqs. (kappa),
(amax) and the asymptote of a_n."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import numpy as np

from .. import theory
from ..report import Check, Claim
from ..waves import front_speed
from .common import GAMMA_FB, V_FB, fb_source
from .figure import register_claims, register_figure


@register_claims(rank=80)
def claims_patterns(quick: bool) -> list[Claim]:
    """App. C: the source map a -> a', its kappa, a_max and the asymptote of a_n.

    Parameters
    ----------
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    list of bkwaves.report.Claim
        The claims, with the checks computed here (values in the paper's dimensionless
        units) and the verdict derived from them.
    """
    v, g = V_FB, GAMMA_FB
    out = []
    k = theory.kappa(g)
    h = 1e-6
    um = [float(theory.u_minus(x, front_speed(x), g)) for x in (1 - 3 * h, 1 - h)]
    k_num = -(um[1] - um[0]) / (2 * h)
    out.append(
        Claim(
            "kappa",
            "(kappa)",
            "kappa = -du_-/du_+ at u_+ = 1, 0 < kappa < 1",
            f"{k:.6f}",
            f"{k_num:.6f} (finite difference of u_- with the exact c)",
            [
                Check("finite difference / eq. (kappa) - 1", k_num / k - 1, -1e-4, 1e-4),
                Check("kappa", k, 1e-300, 1 - 1e-300),
            ],
        )
    )
    amax = theory.a_max(v, g)
    below = float(theory.a_prime(0.99 * amax, v, g))
    above = float(theory.a_prime(1.01 * amax, v, g))
    out.append(
        Claim(
            "amax",
            "(amax)",
            "the source survives (a' > 0) iff a < a_max",
            f"a_max = {amax:.4e}",
            f"map of eq. (ap): a'(0.99 a_max) = {below:.2e}, a'(1.01 a_max) = {above:.2e}",
            [
                Check("a'(0.99 a_max)", below, lo=1e-300),
                Check("a'(1.01 a_max)", above, hi=-1e-300),
            ],
            note="checked on the map here; (amax) in a run and (ap) check the map itself",
        )
    )
    n = 2000 if quick else 20000
    it = theory.iterate_map(0.5 * amax, v, g, n)
    ratio = float(it[-1] / theory.a_n_asymptote(n, v, g))
    out.append(
        Claim(
            "an",
            "Sec. V",
            "a_n ~ v^2/(2 n (1 + kappa))",
            "asymptote",
            f"a_n / asymptote = {ratio:.4f} at n = {n} (map iterated from a = a_max/2)",
            [Check("a_n / asymptote", ratio, 0.98, 1.02)],
        )
    )
    return out


@register_figure("fig7_source_map", 2)
def fig_map(axes, quick):
    """Fig. 7 (aa): a'(a) at gamma = 0.3 with the diagonal and the iterates of the map;
    right: the same on log axes, where the iterates and the measured births lie.

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
    v, g = 1e-2, 0.3
    amax = theory.a_max(v, g)
    r, m = fb_source(quick)
    curv = r.events.curvature.to_numpy() / amax
    it = theory.iterate_map(0.9 * amax, v, g, 8) / amax
    for k, ax in enumerate(axes):
        log = k == 1  # the right panel: the same series, named by the left panel's legend
        a = np.geomspace(amax * 1e-3, 1.3 * amax, 400)
        ap = theory.a_prime(a, v, g) / amax
        if log:  # a' < 0 past a_max (no source) has no place on a log axis
            ap = np.where(ap > 0, ap, np.nan)
        ax.plot(a / amax, ap, "C0", lw=2, label=None if log else r"$a'(a)$, eq. (ap)")
        ax.plot(a / amax, a / amax, "k:", lw=1, label=None if log else r"$a' = a$")
        # the staircase a_0 -> a_1 -> a_1 on the diagonal -> a_2 ...; on log axes it starts
        # at (a_0, a_1), the axis a' = 0 being out of reach
        xs, ys = ([it[0]], [it[1]]) if log else ([it[0]], [0.0])
        for i in range(len(it) - 1):
            xs += [it[i], it[i + 1]]
            ys += [it[i + 1], it[i + 1]]
        ax.plot(xs, ys, "C1-", lw=0.8, label=None if log else r"iterates from $a = 0.9\,a_{\max}$")
        ax.axvline(1.0, color="C3", ls="--", lw=1, label=None if log else r"$a_{\max}$, eq. (amax)")
        ax.plot(
            curv[:-1],
            curv[1:],
            "o",
            color="C2",
            mfc="none",
            label=None if log else "measured in a free-boundary run",
        )
        ax.set_xlabel(r"$a / a_{\max}$")
        ax.set_ylabel(r"$a' / a_{\max}$")
        if log:
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlim(1e-2, 1.3)
            ax.set_ylim(1e-2, 1.3)
            ax.set_title("The same on log axes: the iterates and the births", fontsize=9)
        else:
            ax.axhline(0, color="0.7", lw=0.8)
            ax.legend(fontsize=7)
            ax.set_title(f"Source map at $\\gamma = {g}$, $v = {v}$ (Fig. 7)", fontsize=9)
    return (
        f"Fig. 7: the map a -> a' of eq. (ap) at gamma = {g}, v = {v} (a_max = {amax:.3e}), "
        "the diagonal, the iterates from a = 0.9 a_max (`bk.theory`) and, as circles, the "
        f"curvature at successive births of a free-boundary source ({curv.size} births from "
        f"a = {m['a']:g}, `bk.FreeBoundary`). Right: the same on log axes, where the iterates "
        "and the measured births, which crowd the corner a < 0.1 a_max on linear axes, are "
        "apart."
    )
