"""Fig. 9 (Sec. V): synchronisation against spatiotemporal chaos on free-boundary
rings, and the claims on it: sources at the maxima, the coarsening exponent and
prefactor of R ~ a_n^(-1/2), and chaos for a > a_max."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import math

import numpy as np

from .. import theory
from ..report import Check, Claim
from .common import (
    GAMMA_FB,
    SYNC_DECIDE,
    SYNC_FIT_FROM,
    SYNC_PREFACTOR_FACTOR,
    V_FB,
    coarsening_exponent,
    found,
    sync_chaos,
)
from .figure import register_claims, register_figure


@register_claims(rank=120)
def claims_sync(quick: bool) -> list[Claim]:
    """Sec. V: sources at the maxima, the coarsening exponent and prefactor of R ~ a_n^(-1/2),
    chaos for a > a_max.

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
    m = sync_chaos(quick)
    amax = theory.a_max(V_FB, GAMMA_FB)
    smooth = {k: r for k, r in m["res"].items() if k.startswith("smooth")}
    sh = m["res"]["sharp"]
    early = float(np.nanmean(sh["recurrent"][1:6]))
    late = float(np.nanmean(sh["recurrent"][-5:]))
    peak = int(np.argmax(sh["births"]))
    smooth_rec = min(float(np.nanmean(r["recurrent"][1:])) for r in smooth.values())
    a_top = max(float(np.max(r["a"])) for r in smooth.values())
    first = [int(r["sites"][0]) for r in smooth.values()]
    last = [int(r["sites"][-1]) for r in smooth.values()]
    rises = max(int(np.max(np.diff(r["sites"][1:]))) for r in smooth.values())
    fit = coarsening_exponent(m)
    p_last, s_last = fit["local"][-1]["p"], fit["local"][-1]["sigma"]
    drift, drift_s = fit.get("drift", 0.0), fit.get("drift_sigma", math.inf)
    rec5 = np.convolve(np.nan_to_num(sh["recurrent"]), np.ones(5) / 5, "valid")
    settled = int(np.argmax(rec5 >= 0.9)) + 1 if np.any(rec5 >= 0.9) else None
    if settled is not None:
        found(
            f"In the free boundary problem the spatiotemporal chaos of fields with a > a_max "
            f"(here a median {np.median(sh['a']) / amax:.0f} a_max, ring L = {m['L']:.0f}) is a "
            f"transient: births wander for the first periods (recurrent fraction {early:.2f}), "
            f"peak at period {peak + 1} and settle on fixed sources from period {settled} "
            f"(5-period mean of the recurrent fraction >= 0.9); docs/validation.md finds the "
            f"lifetime independent of the ring length."
        )
    return [
        Claim(
            "sync",
            "Sec. V",
            "maxima with a < a_max become sources; the system synchronises",
            "sources at the maxima; the flatter source takes over",
            f"{len(smooth)} rings L = {m['L']:.0f}, all a < a_max (max {a_top / amax:.2f} "
            f"a_max): births recur at the same sites (fraction >= {smooth_rec:.2f}), sources "
            f"{sum(first)} -> {sum(last)} over all rings ({min(first)}-{max(first)} -> "
            f"{min(last)}-{max(last)} per ring) in {m['periods']} periods (between two periods "
            f"the count rises by at most {rises})",
            [
                Check("largest curvature of the maxima / a_max", a_top / amax, hi=1.0),
                Check("smallest mean recurrent fraction", smooth_rec, lo=0.95),
                Check(
                    "sites at the end - at the start (largest)",
                    max(lst - fst for fst, lst in zip(first, last, strict=True)),
                    hi=-1,
                ),
            ],
        ),
        Claim(
            "sync-R",
            "Sec. V",
            "the synchronised regions grow as R ~ a_n^(-1/2) ~ t^(1/2)",
            f"R ~ t^{0.5:g}",
            f"R = L / (sites averaged over {fit['rings']} rings L = {m['L']:.0f}) fitted as n^p, "
            "bootstrap over rings, local exponent against the window: "
            + ", ".join(
                f"periods {w['window'][0]}-{w['window'][1]}: {w['p']:.2f} +- {w['sigma']:.2f}"
                for w in fit["local"]
            )
            + f"; periods {SYNC_FIT_FROM}-{fit['periods']}: {fit['p']:.2f} +- {fit['sigma']:.2f}",
            [Check("rings resampled", fit["rings"], lo=2)],
            applies=Check(
                f"max(|drift of p between the last two windows| / (2 its bootstrap error), "
                f"error of p in the last window / {SYNC_DECIDE:g}): settled and known",
                max(abs(drift) / (2 * drift_s), s_last / SYNC_DECIDE),
                hi=1.0,
            ),
            paper_check=Check(
                "(p - 1/2) / its bootstrap error, last window", (p_last - 0.5) / s_last, -2.0, 2.0
            ),
            note=(
                f"undecided: the local exponent still moves (by {drift:+.2f} +- {drift_s:.2f} "
                f"between the last two windows) or is not known to {SYNC_DECIDE:g} "
                f"(+- {s_last:.2f}); longer runs on more rings are needed"
                if abs(drift) > 2 * drift_s or s_last > SYNC_DECIDE
                else f"the local exponent has settled at {p_last:.2f} +- {s_last:.2f}, "
                f"{abs(p_last - 0.5) / s_last:.1f} standard errors from 1/2"
            ),
        ),
        Claim(
            "sync-R-prefactor",
            "Sec. V",
            "the size of a synchronised region is R ~ a_n^(-1/2), a_n ~ v^2/(2 n (1 + kappa))",
            "R a_n^(1/2) of order 1",
            f"R a_n^(1/2) = {fit['prefactor']:.3f} +- {fit['prefactor_sigma']:.3f} over periods "
            f"{fit['prefactor_window'][0]}-{fit['prefactor_window'][1]} ({fit['rings']} rings, "
            f"bootstrap), where a_n^(-1/2) is {fit['paper_R']:.0f} (geometric mean)",
            [Check("rings resampled", fit["rings"], lo=2)],
            applies=Check(
                "a_n^(-1/2) over the window / (L/2) (a ring holds regions that large)",
                fit["paper_R"] / (m["L"] / 2),
                hi=1.0,
            ),
            paper_check=Check(
                f"R a_n^(1/2), moved toward 1 by 2 bootstrap errors, within a factor "
                f"{SYNC_PREFACTOR_FACTOR:g} of 1",
                fit["prefactor_near"],
                1.0 / SYNC_PREFACTOR_FACTOR,
                SYNC_PREFACTOR_FACTOR,
            ),
            note=(
                f"the rings (L = {m['L']:.0f}) cannot hold regions of the paper's size "
                f"a_n^(-1/2) = {fit['paper_R']:.0f}: undecided"
                if fit["paper_R"] > m["L"] / 2
                else f"the regions are {1 / fit['prefactor']:.1f} times smaller than the "
                "paper's estimate for one isolated source: many sources compete"
                if fit["prefactor"] < 1
                else f"the regions are {fit['prefactor']:.1f} times the paper's estimate"
            ),
        ),
        Claim(
            "chaos",
            "Sec. V",
            "random fields with a > a_max give spatiotemporal chaos",
            "births at random places",
            f"median a = {np.median(sh['a']) / amax:.0f} a_max: recurrent fraction "
            f"{early:.2f} in periods 2-6, births peak at period {peak + 1}, then "
            f"{late:.2f} and {sh['births'][-1]} births per period at the end",
            [
                Check(
                    "median curvature of the maxima / a_max",
                    float(np.median(sh["a"]) / amax),
                    lo=1.0,
                ),
                Check("recurrent fraction, periods 2-6", early, hi=0.3),
                Check("recurrent fraction, last 5 periods", late, lo=0.9),
                Check(
                    "births in the last period / at the peak",
                    sh["births"][-1] / sh["births"][peak],
                    hi=0.2,
                ),
            ],
            kind="refinement",
            note=f"in the free boundary problem the chaos is a transient: births settle on fixed "
            f"sources from period {settled} (docs/validation.md: its lifetime does not grow "
            f"with L)",
        ),
    ]


@register_figure("fig9_sync_chaos", 3)
def fig_sync(axes, quick):
    """Synchronisation vs chaos (Sec. V): births per period, their recurrence, and the
    growth of the synchronised regions.

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
    from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter

    m = sync_chaos(quick)
    amax = theory.a_max(V_FB, GAMMA_FB)
    for name, col in (("smooth", "C0"), ("sharp", "C3")):
        r = m["res"][name]
        k = np.arange(1, r["births"].size + 1)
        lab = f"{name}: median $a = {np.median(r['a']) / amax:.2g}\\,a_{{\\max}}$"
        axes[0].semilogy(k, np.maximum(r["births"], 0.5), "-", color=col, label=lab)
        axes[1].plot(k, r["recurrent"], "-", color=col, label=lab)
    ax = axes[0]
    ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("source period $n$")
    ax.set_ylabel("births per period")
    ax.legend(fontsize=7)
    ax.set_title(f"Ring of length {m['L']:.0f}, $\\gamma = {GAMMA_FB}$, $v = {V_FB}$", fontsize=9)
    axes[1].set_xlabel("source period $n$")
    axes[1].legend(fontsize=7, loc="lower right")
    axes[1].set_ylabel("fraction of births at a previous site")
    axes[1].set_ylim(-0.05, 1.05)
    axes[1].set_title("Synchronisation (1) vs wandering births (0)", fontsize=9)
    ax = axes[2]
    fit = coarsening_exponent(m)
    k = np.arange(1, fit["periods"] + 1)
    for name, r in m["res"].items():
        if name.startswith("smooth"):
            ax.loglog(k, m["L"] / np.maximum(r["sites"], 1), ".", color="0.75", ms=2)
    ax.loglog(k, fit["R"], "k.", ms=4, label=f"mean over {fit['rings']} rings")
    for i, w in enumerate(fit["local"]):
        lo, hi = w["window"]
        kk = k[(k >= lo) & (k <= hi)]
        ax.loglog(
            kk,
            fit["R"][lo - 1] * (kk / lo) ** w["p"],
            "-",
            color=f"C{i}",
            lw=1.5,
            label=f"{lo}-{hi}: $p = {w['p']:.2f} \\pm {w['sigma']:.2f}$",
        )
    kk = k[k >= SYNC_FIT_FROM]
    r0 = fit["R"][SYNC_FIT_FROM - 1]
    ax.loglog(
        kk, r0 * (kk / SYNC_FIT_FROM) ** 0.5, "k--", lw=1, label=r"paper: $R \propto n^{1/2}$"
    )
    ax.xaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 1.5, 2.0, 3.0, 5.0, 7.0)))
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("source period $n$")
    ax.set_ylabel("$R = L$ / sources")
    ax.legend(fontsize=7)
    ax.set_title("Coarsening: local exponent $p$ against the window", fontsize=9)
    return (
        f"Synchronisation vs chaos (Sec. V): free-boundary rings (`bk.FreeBoundary`) of length "
        f"{m['L']:.0f}, gamma = {GAMMA_FB}, v = {V_FB}, grid h = 0.2, from u = 0.5 + a "
        "periodic random field: smooth (amplitude 0.02, correlation 25: every maximum has "
        "a < a_max) and sharp (0.3, 4: a >> a_max), run for "
        f"{fit['periods']} source periods (sharp: {m['sharp'][1]}). Left: births per period. "
        "Middle: the fraction of them within 1 of a birth of the previous period (1: fixed "
        "sources). Right: the size of the synchronised regions R = L / sources on "
        f"{fit['rings']} smooth rings (grey: each ring; black: L / the mean number of sources), "
        "fitted as n^p on doubling windows of periods (lines; +- one bootstrap standard error "
        f"over rings), and the paper's n^1/2 (dashed). Over periods {SYNC_FIT_FROM}-"
        f"{fit['periods']}: p = {fit['p']:.2f} +- {fit['sigma']:.2f}."
    )
