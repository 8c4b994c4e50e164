"""Fig. 4: the traveling waves behind a front (creep and pulse, App. B, with the direct
chain's profiles) and the claims on them: eqs. (gammac), (w), (um), (A) and creep."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import numpy as np

from .. import theory
from ..report import Check, Claim
from ..report import yes_no as _holds
from ..waves import front_speed, tip_solve, traveling_wave
from .common import PAPER_BETA, rel
from .figure import register_claims, register_figure


def _slidet(u_plus, gamma, c, zmax=400.0):
    from scipy.integrate import solve_ivp

    def rhs(z, y):
        return [y[1], (2 * c * gamma * y[1] - y[0]) / (c * c - 1)]

    def stick(z, y):
        return y[1] + 1e-13

    stick.terminal, stick.direction = True, -1
    h = 1e-6
    y0 = [u_plus - u_plus * h * h / (2 * (c * c - 1)), u_plus * h / (c * c - 1)]
    return solve_ivp(rhs, (-h, -zmax), y0, events=stick, rtol=1e-12, atol=1e-14)


def _critical_stress_from_tip_solver(gamma: float) -> float:
    """u_c solving eq. (gammac), gamma = sqrt(c^2 - 1)/c, with c(u) from the tip solver."""
    from scipy.optimize import brentq

    def f(u):
        c = tip_solve(u)["c"]
        return np.sqrt(c * c - 1.0) / c - gamma

    return float(brentq(f, 0.5 * gamma, min(0.999, 2.0 * gamma), xtol=1e-14, rtol=1e-14))


@register_claims(rank=70)
def claims_wave(quick: bool) -> list[Claim]:
    """App. B: the critical stress (gammac), the pulse width (w), the stress behind (um), the
    slip (A) and creep.

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
    g = 0.3
    uc_tip = _critical_stress_from_tip_solver(g)
    # the sliding ODE (c from the tip solver) just above and below u_c: re-sticks or creeps
    above = _slidet(1.01 * uc_tip, g, tip_solve(1.01 * uc_tip)["c"])
    below = _slidet(0.99 * uc_tip, g, tip_solve(0.99 * uc_tip)["c"])
    n_above, n_below = len(above.t_events[0]), len(below.t_events[0])
    out.append(
        Claim(
            "gammac",
            "(gammac)",
            "critical stress u_c: gamma = sqrt(c(u_c)^2 - 1)/c(u_c)",
            "u_c implicit",
            f"gamma = {g}: eq. (gammac) solved with the numerical tip solver gives u_c = "
            f"{uc_tip:.12f}; the sliding ODE re-sticks at u_+ = 1.01 u_c ({n_above} stick "
            f"point) and not at 0.99 u_c ({n_below})",
            [
                Check("u_c (eq. gammac, tip solver) - gamma", uc_tip - g, -1e-10, 1e-10),
                Check("stick points of the ODE at u_+ = 1.01 u_c", n_above, lo=1),
                Check("stick points of the ODE at u_+ = 0.99 u_c", n_below, hi=0),
            ],
            kind="refinement",
            note=f"with the exact c = 1/sqrt(1 - u_+^2), u_c = gamma exactly (here to "
            f"{abs(uc_tip - g):.1e})",
        )
    )
    werr, uerr, aerr = [], [], []
    for u in (0.5, 0.7, 0.9):
        w = traveling_wave(u, g)
        sol = _slidet(u, g, w.c)
        werr.append(rel(-sol.t_events[0][0], w.w))
        um_ode = sol.y_events[0][0][0]
        uerr.append(rel(um_ode, w.u_minus))
        # the paper's closed form of eq. (A), with the exact c, against u_+ - u_-(ODE)
        gt = float(theory.gamma_tilde(w.c, g))
        a_paper = u * (1 + np.exp(-np.pi * gt / np.sqrt(1 - gt * gt)))
        aerr.append(rel(a_paper, u - um_ode))
    w7 = traveling_wave(0.7, g)
    out.append(
        Claim(
            "w",
            "(w)",
            "pulse width w",
            "closed form",
            f"max rel. diff vs ODE {max(werr):.1e} (u_+ = 0.5, 0.7, 0.9, gamma = {g})",
            [
                Check(
                    "max relative difference of eq. (w) from the ODE stick point",
                    max(werr),
                    hi=1e-6,
                )
            ],
        )
    )
    out.append(
        Claim(
            "um",
            "(um)",
            "stress behind u_- < 0",
            "closed form",
            f"max rel. diff vs ODE {max(uerr):.1e}; u_-(0.7) = {w7.u_minus:.5f}",
            [
                Check("max relative difference of eq. (um) from the ODE", max(uerr), hi=1e-6),
                Check("u_-(0.7)", w7.u_minus, hi=-1e-300),
            ],
        )
    )
    out.append(
        Claim(
            "A",
            "(A)",
            "total slip A = u_+ - u_-",
            "u_+ (1 + exp(-pi gamma~/sqrt(1 - gamma~^2)))",
            f"A(0.7) = {w7.A:.6f}; the closed form vs u_+ - u_-(ODE): max rel. diff "
            f"{max(aerr):.1e}",
            [Check("max relative difference of eq. (A) from u_+ - u_-(ODE)", max(aerr), hi=1e-6)],
            kind="identity",
            note="A = u_+ - u_- is the definition of the slip (a block's stress falls by its "
            "slip); the paper's closed form is eq. (um) inserted",
        )
    )
    creep = traveling_wave(0.2, g)
    sol = _slidet(0.2, g, creep.c)
    out.append(
        Claim(
            "creep",
            "Sec. III",
            "below u_c blocks never re-stick (creep, u -> 0)",
            "u_- = 0, w = inf",
            f"ODE at u_+ = 0.2: {len(sol.t_events[0])} stick points, u(-400) = {sol.y[0][-1]:.1e}",
            [
                Check("stick points of the ODE at u_+ = 0.2", len(sol.t_events[0]), hi=0),
                Check("|u(-400)|", abs(float(sol.y[0][-1])), hi=1e-6),
                _holds("bk.traveling_wave(0.2, 0.3) is creep", creep.regime == "creep"),
            ],
        )
    )
    return out


def chain_profile(u_plus, gamma, dx=0.05, n=2400):
    """u(x) of the direct chain (v = 0) when the front triggered at block 0 is 80% along;
    returns z = x - x_front and u.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float, default 0.05
        Lattice spacing (dimensionless).
    n : int, default 2400
        Blocks of the chain.

    Returns
    -------
    z : numpy.ndarray
        Positions relative to the front (dimensionless x).
    u : numpy.ndarray
        The stress there (dimensionless).

    Examples
    --------
    Ahead of the front the chain is still at u_+:

    >>> from bkwaves.paper.fig4_waves import chain_profile
    >>> z, u = chain_profile(0.6, 0.3, dx=0.1, n=300)
    >>> float(u[z > 1].min()), float(u[z > 1].max())
    (0.6, 0.6)
    """
    from ..chain import Chain
    from ..params import Params

    # kicked forward like `bkwaves front` (a release alone starts no front at small u_+)
    ch = Chain(n, Params(gamma=gamma, v=0.0, dx=dx, beta=PAPER_BETA), "free", u0=u_plus).kick(
        0, -2.0
    )
    c = float(front_speed(u_plus, dx=dx, gamma=gamma))
    ch.run(t_end=0.8 * n * dx / c, progress=False)
    u = ch.u
    moved = np.nonzero(ch.modes != 0)[0]
    tip = int(moved.max()) if moved.size else 0
    # sub-block front position from the slip threshold of the next block: phi reaches 1
    z = (np.arange(n) - tip) * dx
    return z, u


@register_figure("fig4_waves", 2)
def fig_waves(axes):
    """Fig. 4: the two traveling-wave types from theory, direct-chain profiles overlaid.

    Parameters
    ----------
    axes : matplotlib.axes.Axes or numpy.ndarray of Axes
        The panels to draw into (:func:`bkwaves.paper.figure.panels` hands them over).

    Returns
    -------
    str
        The caption, with the numbers computed for the figure.
    """
    for ax, (u, g) in zip(axes, ((0.25, 0.3), (0.7, 0.3)), strict=True):
        w = traveling_wave(u, g)
        if w.w:
            zmin = -1.6 * w.w
        else:  # creep never re-sticks: show the support, where u exceeds 1% of u_+, and as
            # much again of the flat tail
            z = np.linspace(-25.0, 0.0, 2501)
            zmin = 2.0 * float(z[np.argmax(np.abs(w.profile(z)) > 0.01 * u)])
        z = np.linspace(zmin, 2.0, 600)
        ax.plot(z, w.profile(z), "C0", lw=2, label="App. B (continuum)")
        zc, uc = chain_profile(u, g)
        sel = (zc >= zmin) & (zc <= 2.0)
        ax.plot(zc[sel], uc[sel], ".", color="C1", ms=2, label=r"direct chain, $\Delta x = 0.05$")
        ax.legend(fontsize=7)
        ax.axhline(0, color="0.7", lw=0.8)
        lab = r"(a) $u_+ < u_c$: creep" if w.regime == "creep" else r"(b) $u_+ > u_c$: pulse"
        ax.set_title(f"{lab}, $u_+ = {u}$, $\\gamma = {g}$", fontsize=9)
        ax.set_xlabel(r"$z = x - c\,t$")
        ax.set_ylabel(r"$u$")
    return (
        "Fig. 4: the two traveling waves behind a front at gamma = 0.3: (a) creep below the "
        "critical stress u_c = gamma, (b) a pulse that re-sticks at z = -w above it. Lines: "
        "App. B profile with the exact c (`bk.traveling_wave`); dots: the direct chain "
        "(`bk.Chain`, dx = 0.05, v = 0, no backward slip) when its front is 80% along."
    )
