"""Fig. 3: the front speed c(u_+) (tip problem, interpolation eq. (c), chain fronts, the
finite-dx correction) and the claims on it: eqs. (c), (c1), (ca), the formal continuum
answer, c > 1, convergence in dx, and the chain's fronts against the tip problem."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import math

import numpy as np

from .. import theory
from .._validate import ParameterError
from ..report import Check, Claim
from ..waves import front_speed, tip_solve, traveling_wave
from .common import chain_fronts, rel
from .figure import register_claims, register_figure


@register_claims(rank=10)
def claim_speed_interpolation(quick: bool) -> Claim:
    """Eq. (c): the interpolation formula against the tip solver over 0 < u_+ < 1.

    Parameters
    ----------
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    bkwaves.report.Claim
        The claim, with the checks computed here (values in the paper's dimensionless
        units) and the verdict derived from them.
    """
    u = np.linspace(0.02, 0.98, 49 if quick else 197)
    c = np.array([tip_solve(x)["c"] for x in u])
    err = float(np.max(np.abs(theory.c_interpolation(u) / c - 1)))
    return Claim(
        "c",
        "(c)",
        "the interpolation formula gives c(u_+) to a few per cent",
        "a few per cent",
        f"max error {100 * err:.2f}% vs the tip solver ({u.size} points, u_+ = "
        f"{u[0]:.2f}-{u[-1]:.2f})",
        [Check("max relative error of eq. (c) vs the tip solver", err, hi=0.05)],
    )


@register_claims(rank=20)
def claim_c1(quick: bool) -> Claim:
    """Eq. (c1): (c - 1)/u_+^2 -> 1/2 as u_+ -> 0, fitted to the tip solver.

    Parameters
    ----------
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    bkwaves.report.Claim
        The claim, with the checks computed here (values in the paper's dimensionless
        units) and the verdict derived from them.
    """
    u = np.linspace(0.02, 0.08, 7)
    c = np.array([tip_solve(x)["c"] for x in u])
    a0 = float(np.polyfit(u**2, (c - 1) / u**2, 2)[-1])
    return Claim(
        "c1",
        "(c1)",
        "c = 1 + u_+^2/2 for small u_+",
        "(c - 1)/u_+^2 -> 1/2",
        f"{a0:.8f} (fit of tip-solver output)",
        [Check("(c - 1)/u_+^2 at u_+ -> 0, fitted", a0, 0.5 - 1e-3, 0.5 + 1e-3)],
    )


def _series_fit():
    c = np.linspace(2.5, 40.0, 80)
    theta = np.array([tip_solve(c=x)["theta"] for x in c])
    x = 1.0 / c**2
    A = np.vstack([x**k for k in range(1, 9)]).T
    return np.linalg.lstsq(A, theta, rcond=None)[0]


@register_claims(rank=30)
def claims_series(quick: bool) -> list[Claim]:
    """Eq. (ca): the large-c series of (1 - u_+)/u_+ in 1/c^2, its coefficients fitted to the
    tip solver.

    Parameters
    ----------
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    list of bkwaves.report.Claim
        The claims, with the checks computed here (values in the paper's dimensionless
        units) and the verdict derived from them.

    Examples
    --------
    >>> from bkwaves.paper.fig3_speed import claims_series
    >>> [(c.key, c.verdict) for c in claims_series(True)]
    [('ca', 'confirmed'), ('ca4', 'corrected')]
    """
    a = _series_fit()
    exact = [0.5, 0.375, 0.3125, 35 / 128]  # 1/sqrt(1 - x) - 1 = x/2 + 3x^2/8 + 5x^3/16 + ...
    dev3 = float(max(abs(a[k] - exact[k]) for k in range(3)))
    p4 = theory.PAPER_FOURTH_COEFFICIENT
    return [
        Claim(
            "ca",
            "(ca)",
            "large-c series (1-u_+)/u_+ = 1/(2c^2) + 3/(8c^4) + 5/(16c^6)",
            "1/2, 3/8, 5/16",
            ", ".join(f"{v:.6f}" for v in a[:3]) + " (fit of tip-solver output, c = 2.5-40)",
            [Check("max deviation of the fitted coefficients from 1/2, 3/8, 5/16", dev3, hi=1e-4)],
        ),
        Claim(
            "ca4",
            "(ca)",
            "next term of the series",
            f"{p4}/c^8",
            f"{a[3]:.5f}/c^8 (fit; exact: 35/128 = {exact[3]:.5f})",
            [Check("fitted fourth coefficient - 35/128", float(a[3] - exact[3]), -1e-3, 1e-3)],
            paper_check=Check("the paper's coefficient - fitted", float(p4 - a[3]), -1e-3, 1e-3),
            note=f"the tip problem has the closed form c = 1/sqrt(1 - u_+^2); the series is that "
            f"of 1/sqrt(1 - x) - 1, x = 1/c^2; the paper's term is off by {p4 - a[3]:+.5f}",
        ),
    ]


@register_claims(rank=40)
def claim_formal(quick: bool) -> Claim:
    """Sec. VI: the formal continuum answer c = 1/sqrt(1 - u_+) is not the tip problem's.

    Parameters
    ----------
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    bkwaves.report.Claim
        The claim, with the checks computed here (values in the paper's dimensionless
        units) and the verdict derived from them.

    Examples
    --------
    >>> from bkwaves.paper.fig3_speed import claim_formal
    >>> claim = claim_formal(True)
    >>> claim.key, claim.verdict
    ('formal', 'confirmed')
    """
    c = tip_solve(0.6)["c"]
    wrong = float(theory.c_formal_continuum(0.6))
    return Claim(
        "formal",
        "Sec. VI",
        "the formal continuum answer c = 1/sqrt(1 - u_+) is wrong",
        "incorrect",
        f"c(0.6) = {c:.6f} vs formal {wrong:.6f}",
        [
            Check(
                "relative difference of the formal answer from the tip solver",
                rel(wrong, c),
                lo=0.1,
            )
        ],
    )


@register_claims(rank=50)
def claim_c_above_one(quick: bool) -> Claim:
    """Fig. 3: c > 1 for every 0 < u_+ < 1, diverging as u_+ -> 1.

    Parameters
    ----------
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    bkwaves.report.Claim
        The claim, with the checks computed here (values in the paper's dimensionless
        units) and the verdict derived from them.
    """
    u = np.linspace(0.01, 0.999, 40)
    c = np.array([tip_solve(x)["c"] for x in u])
    return Claim(
        "c>1",
        "Fig. 3",
        "c > 1 for all 0 < u_+ < 1 and diverges as u_+ -> 1",
        "supersonic, divergent",
        f"min c - 1 = {c.min() - 1:.2e}, c(0.999) = {c[-1]:.2f}",
        [
            Check("min (c - 1) over u_+ = 0.01-0.999", float(c.min() - 1), lo=1e-300),
            Check("min increment of c between neighbours", float(np.min(np.diff(c))), lo=1e-300),
            Check("c(0.999)", float(c[-1]), lo=20.0),
        ],
    )


@register_claims(rank=60)
def claim_dx(quick: bool) -> Claim:
    """Sec. III: c becomes independent of dx as dx -> 0 (the finite-dx tip problem).

    Parameters
    ----------
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    bkwaves.report.Claim
        The claim, with the checks computed here (values in the paper's dimensionless
        units) and the verdict derived from them.
    """
    hs = (0.1, 0.05, 0.025)
    errs = [abs(tip_solve(0.7, dx=h, gamma=0.3)["c"] / float(front_speed(0.7)) - 1) for h in hs]
    errs0 = [abs(tip_solve(0.7, dx=h, gamma=0.0)["c"] / float(front_speed(0.7)) - 1) for h in hs]
    order = float(np.log2(errs[1] / errs[2]))
    order0 = float(np.log2(errs0[1] / errs0[2]))
    return Claim(
        "dx",
        "Sec. III",
        "c becomes independent of dx as dx -> 0",
        "yes",
        f"finite-dx tip problem at u_+ = 0.7: error {errs[0]:.1e}, {errs[1]:.1e}, "
        f"{errs[2]:.1e} at dx = 0.1, 0.05, 0.025 (gamma = 0.3, order {order:.2f}); "
        f"{errs0[0]:.1e}, {errs0[1]:.1e}, {errs0[2]:.1e} (gamma = 0, order {order0:.2f})",
        [
            Check("error ratio dx = 0.05 / 0.1 (gamma = 0.3)", errs[1] / errs[0], hi=0.99),
            Check("error ratio dx = 0.025 / 0.05 (gamma = 0.3)", errs[2] / errs[1], hi=0.99),
            Check("convergence order at gamma = 0.3", order, 0.8, 1.2),
            Check("convergence order at gamma = 0", order0, 1.8, 2.2),
        ],
        kind="refinement",
        note=f"order {order:.2f} in dx with damping, {order0:.2f} without (closed form at "
        f"gamma = 0, docs/theory.md)",
    )


def _richardson(values, dxs, orders):
    """Repeated Richardson extrapolation (halving dx) removing dx^p for p in orders."""
    v = list(values)
    for p in orders:
        v = [v[i + 1] + (v[i + 1] - v[i]) / (2**p - 1) for i in range(len(v) - 1)]
        if len(v) == 1:
            break
    return v[-1]


@register_claims(rank=100)
def claims_chain(quick: bool) -> list[Claim]:
    """The fronts of the direct chain against the tip problem (c, u_-, w at finite dx).

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
    out = []
    m = chain_fronts(quick)
    devs, narrow = [], 0
    for dx, cs in m["fig3"].items():
        for u, c in zip(m["us"], cs, strict=True):
            try:  # the lattice closed form refuses narrow pulses (docs/theory.md)
                devs.append(abs(c / float(front_speed(u, dx=dx)) - 1))
            except ParameterError:
                narrow += 1
    dev = max(devs, default=math.inf)
    out.append(
        Claim(
            "c-chain",
            "Sec. III",
            "direct simulations support c(u_+) from the tip problem",
            "qualitative",
            f"chain fronts (gamma = 0, dx = 0.1, 0.05, u_+ = 0.3-0.9) equal the finite-dx tip "
            f"problem within {dev:.1e}"
            + (f" ({narrow} too narrow for the lattice closed form skipped)" if narrow else ""),
            [
                Check("max relative difference, chain vs finite-dx tip problem", dev, hi=1e-6),
                Check("chain fronts compared", len(devs), lo=4),
            ],
            note="c(u_+; dx) -> 1/sqrt(1 - u_+^2) at order dx^2 (Fig. 3, right)",
        )
    )
    fr = m["pulse"]
    dxs = m["dxs"]
    w = traveling_wave(0.7, 0.3)
    orders = [1, 2, 3]

    def extrapolated(key):
        """The Richardson value and its change when the coarsest dx is left out (one
        order fewer): how far the extrapolation has converged."""
        v = [getattr(fr[d], key) for d in dxs]
        best = _richardson(v, dxs, orders)
        return best, abs(best - _richardson(v[1:], dxs[1:], orders[: len(dxs) - 2]))

    (c_ex, c_err), (um_ex, um_err), (w_ex, w_err) = map(extrapolated, ("c", "u_minus", "w"))
    out.append(
        Claim(
            "um-chain",
            "(um), (w)",
            "u_- and w of the pulse (u_+ = 0.7, gamma = 0.3)",
            f"u_- = {w.u_minus:.5f}, w = {w.w:.4f}, c = {w.c:.6f}",
            f"chain, dx = {', '.join(str(d) for d in dxs)} extrapolated: u_- = {um_ex:.5f} "
            f"(+- {um_err:.0e}), w = {w_ex:.4f} (+- {w_err:.0e}), c = {c_ex:.6f} "
            f"(+- {c_err:.0e}; +-: the change without the coarsest dx)",
            [
                Check("u_- (chain, extrapolated) - eq. (um)", um_ex - w.u_minus, -1e-3, 1e-3),
                Check("w (chain, extrapolated) / eq. (w) - 1", w_ex / w.w - 1, -1e-2, 1e-2),
                Check("c (chain, extrapolated) / c - 1", c_ex / w.c - 1, -1e-4, 1e-4),
                # the extrapolation itself converged well inside those tolerances
                Check("change of u_- without the coarsest dx", um_err, hi=1e-4),
                Check("relative change of w without the coarsest dx", w_err / w_ex, hi=1e-3),
                Check("relative change of c without the coarsest dx", c_err / c_ex, hi=1e-4),
            ],
        )
    )
    return out


@register_figure("fig3_speed", 2)
def fig_speed(axes, quick):
    """Fig. 3 (cf): c(u_+) from the tip solver, interpolation dashed; right: what finite dx
    changes, c(0) - c(dx), with its laws.

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
    ax = axes[0]
    u = np.linspace(0.01, 0.96, 300)
    ax.plot(u, front_speed(u), "C0", lw=2, label=r"$c = 1/\sqrt{1 - u_+^2}$ (exact tip problem)")
    us = np.linspace(0.05, 0.95, 10 if quick else 19)
    ax.plot(
        us,
        [tip_solve(x)["c"] for x in us],
        "o",
        color="C0",
        ms=4,
        label=r"numerical tip solver, $\Delta x \to 0$",
    )
    ax.plot(u, theory.c_interpolation(u), "k--", lw=1, label="interpolation, eq. (c)")
    m = chain_fronts(quick)
    ax.plot(
        m["us"],
        m["fig3"][0.1],
        "s",
        mfc="none",
        color="C3",
        ms=7,
        label=r"direct chain, $\gamma = 0$, $\Delta x = 0.1$",
    )
    ax.set_xlabel(r"$u_+$")
    ax.set_ylabel("front speed $c$")
    ax.set_ylim(1, 4)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title("Front speed (Fig. 3)", fontsize=9)
    ax = axes[1]
    hs = np.array([0.1, 0.05, 0.025, 0.0125])
    outside = []
    for i, up in enumerate((0.3, 0.7)):
        c0 = float(front_speed(up))
        for g, mk in ((0.0, "o"), (0.3, "^")):
            d = []
            for h in hs:
                try:  # the finite-dx tip problem is the chain's only for wide pulses
                    d.append(c0 - tip_solve(up, dx=h, gamma=g)["c"])
                except ParameterError:
                    d.append(np.nan)
                    outside.append(f"u_+ = {up}, gamma = {g:g}, dx = {h:g}")
            ax.loglog(
                hs,
                d,
                mk + "-",
                color=f"C{i}",
                lw=0.8,
                mfc="none" if g else None,
                label=f"tip problem, $u_+ = {up}$, $\\gamma = {g:g}$",
            )
        dch = [c0 - m["fig3"][h][m["us"].index(up)] for h in (0.1, 0.05)]
        ax.loglog(
            [0.1, 0.05],
            dch,
            "x",
            color=f"C{i}",
            ms=9,
            label=f"direct chain, $u_+ = {up}$, $\\gamma = 0$",
        )
    ax.loglog(hs, 0.4 * hs**2, "k:", lw=1, label=r"$\propto \Delta x^2$ ($\gamma = 0$)")
    # the guide sits a factor 3 below the u_+ = 0.7, gamma = 0.3 series it describes, so
    # that it hides no data (only its slope carries information), and stops short of dx = 0.1
    # where the chain's crosses are
    ax.loglog(
        hs[1:],
        0.15 * 0.3 * hs[1:],
        "k--",
        lw=1,
        label=r"$\propto \gamma\,\Delta x$ ($\gamma = 0.3$)",
    )
    from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullLocator

    ax.xaxis.set_major_locator(FixedLocator(hs))
    ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.set_xlabel(r"lattice spacing $\Delta x$")
    ax.set_ylabel(r"$c(\Delta x \to 0) - c(\Delta x)$")
    ax.legend(fontsize=6, loc="lower right")
    ax.set_title(r"What the lattice changes: $c(0) - c(\Delta x)$", fontsize=9)
    return (
        "Fig. 3: front speed. Left: c(u_+) of the tip problem (line: the closed form "
        "1/sqrt(1 - u_+^2); dots: bkwaves' numerical tip solver), the paper's interpolation eq. "
        "(c) dashed, and fronts measured in the direct chain (`bk.chain.front`, gamma = 0, "
        "dx = 0.1, no backward slip), which on this scale sit on the curve. Right: the "
        "difference the lattice makes, c(dx -> 0) - c(dx) against dx, from the finite-dx tip "
        "problem (`bk.tip_solve(u, dx=, gamma=)`) at gamma = 0 (filled) and 0.3 (open), and "
        "from the chain at gamma = 0 (crosses, dx = 0.1 and 0.05): order dx^2 without "
        "damping, order gamma dx with it (dotted and dashed guides; the dashed one drawn a "
        "factor 3 below the data so as not to hide it)."
        + (
            f" Not drawn: {'; '.join(outside)}, outside the domain where the finite-dx tip "
            "problem is the chain's (the pulse too narrow in lattice units, docs/theory.md); the "
            "chain's own value is there."
            if outside
            else ""
        )
    )
