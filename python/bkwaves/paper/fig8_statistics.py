"""Fig. 8 (Sec. V): event statistics, the wave-train frequency law and the catalogs of
long runs, and the claims on them: omega ~ 1/A, recurrence ~ A/v and the b-value."""

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
from .common import GAMMA_FB, V_CHAIN, V_FB, fb_train, fb_trains, long_catalogs
from .figure import register_claims, register_figure


@register_claims(rank=130)
def claims_statistics(quick: bool) -> list[Claim]:
    """Sec. V: omega ~ 1/A, recurrence ~ A/v and the b-value of long catalogs.

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
    from .. import stats

    out = []
    tr = fb_trains(quick)
    slope = float(np.polyfit(np.log10(tr[:, 1]), np.log10(tr[:, 2]), 1)[0])
    wa = tr[:, 2] * tr[:, 1] / V_FB
    # the identity itself, passage by passage at a node once the train runs alone (after
    # the last birth or annihilation of the selection): the stress grows at rate v from the
    # u_- one shock leaves to the u_+ the next one meets
    load, n_alone = 0.0, []
    for u in tr[:, 0]:
        r, m = fb_train(quick, ring=float(theory.wavelength(u, GAMMA_FB, V_FB)), teeth=1)
        sh = r.shocks
        quiet = float(sh[sh.kind.isin(["birth", "annihilation"])].t.max()) if len(sh) else 0.0
        alone = m["t"] > (quiet if np.isfinite(quiet) else -np.inf)
        t, up, um = m["t"][alone], m["up"][alone], m["um"][alone]
        n_alone.append(t.size)
        if t.size >= 2:
            load = max(load, float(np.max(np.abs(V_FB * np.diff(t) - (up[1:] - um[:-1])))))
    out.append(
        Claim(
            "gr-train",
            "Sec. V",
            "in a wave train omega ~ 1/A: Gutenberg-Richter b = 1",
            "b = 1",
            f"free-boundary trains selected on rings (A = {tr[0, 1]:.2f}-{tr[-1, 1]:.2f}): "
            f"omega A / v = {wa.min():.6f}-{wa.max():.6f}, b = {-slope:.6f}",
            [
                Check(
                    "max |v (t_k - t_k-1) - (u_+,k - u_-,k-1)| over passages at a node",
                    load,
                    hi=1e-9,
                ),
                Check("fewest passages of a lone train at the node", min(n_alone), lo=3),
            ],
            kind="identity",
            note="any periodic state in which u grows at rate v and falls by A once per period "
            "has A = v T: it says nothing about catalogs",
        )
    )
    cat = long_catalogs(quick)
    ev = cat["chain"].catalog
    nb = len(cat["chain"].u)
    big = ev[ev.n_blocks >= 0.5 * nb]
    rt = stats.recurrence_times(big.t_start.to_numpy())
    # mean slip per block of each event (the moment is int slip dx = dx sum of slips)
    slip = (big.moment / (big.n_blocks * cat["chain"].params.dx)).to_numpy()
    ratio = V_CHAIN * rt / slip[:-1]
    cv = float(np.std(rt) / np.mean(rt))
    corr = float(np.corrcoef(rt, slip[:-1])[0, 1])
    q1, med, q3 = (float(q) for q in np.percentile(ratio, [25, 50, 75]))
    out.append(
        Claim(
            "recurrence",
            "Sec. V",
            "between ruptures the stress grows at rate v (eq. rest): recurrence ~ A / v",
            "T = A / v for trains and sources",
            f"chain under loading, {len(big)} events over half the chain: v T_k / A_k (T_k the "
            f"time to the next one, A_k the mean slip) median {med:.2f}, quartiles "
            f"{q1:.2f}-{q3:.2f}; correlation of T_k with A_k {corr:.2f}; CV of T_k {cv:.2f}",
            [
                Check("median of v T_k / A_k", med, 0.5, 2.0),
            ],
            kind="refinement",
            note=f"holds event by event on average, but the intervals are irregular (CV {cv:.2f}):"
            f" no periodic train forms in the chain; the free-boundary trains and sources above "
            f"recur at T exactly",
        )
    )
    mom = ev.moment.to_numpy()
    mom = mom[mom > 0]
    b = stats.gutenberg_richter(mom)
    # the bootstrap interval's width as a sigma (NaN without a b)
    b_dist = abs(b.b - 1) / ((b.hi - b.lo) / (2 * 1.96)) if b.ok else math.nan
    single = float(np.mean(ev.n_blocks == 1))
    out.append(
        Claim(
            "b-chain",
            "Sec. V",
            "b = 1 would be observed if the dynamics were dominated by periodic wave trains",
            "b = 1 for trains; 0.8 < b < 1.2 for earthquakes",
            f"chain under loading, fixed ends ({b.n_total} events), moment magnitudes: "
            f"{b.text()}; one-block slips {100 * single:.0f}% of events, large events "
            f"recur irregularly (CV {cv:.2f})",
            [Check("events above Mc", b.n, lo=stats.MIN_EVENTS)],
            # b = 1 is expected only where trains dominate (regular recurrence): the check
            # of b against 1 applies only then
            applies=Check(
                f"CV of the large events' recurrence (trains: below {B_CHAIN_REGULAR_CV:g})",
                cv,
                hi=B_CHAIN_REGULAR_CV,
            ),
            paper_check=Check(
                "|b - 1| / sigma (sigma: half the 95 % interval / 1.96)", b_dist, hi=2.0
            ),
            kind="refinement",
            note=(
                f"the check cannot apply: the chain is not train-dominated (recurrence CV "
                f"{cv:.2f} > {B_CHAIN_REGULAR_CV:g}), and its {b.text()} ({b_dist:.0f} sigma "
                f"from 1) summarises a catalog mixing system-size events and one-block "
                f"slips, not a Gutenberg-Richter exponent"
                if cv > B_CHAIN_REGULAR_CV
                else f"the large events recur regularly (CV {cv:.2f}): {b.text()}, "
                f"{b_dist:.1f} sigma from 1"
            ),
        )
    )
    return out


#: The b = 1 of trains is expected in a catalog only where the large events recur regularly
#: (coefficient of variation of their recurrence times below this).
B_CHAIN_REGULAR_CV = 0.3


@register_figure("fig8_statistics", 3)
def fig_statistics(axes, quick):
    """Event statistics: the wave-train frequency law and the catalogs of long runs.

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
    from .. import stats

    tr = fb_trains(quick)
    ax = axes[0]
    a = np.linspace(tr[:, 1].min() * 0.9, tr[:, 1].max() * 1.1, 50)
    ax.loglog(a, V_FB / a, "k--", lw=1, label=r"$\omega = v / A$ ($b = 1$)")
    ax.loglog(tr[:, 1], tr[:, 2], "o", color="C0", label="free-boundary trains, selected")
    ax.set_xlabel("amplitude $A$")
    ax.set_ylabel(r"frequency at a point, $\omega$")
    ax.legend(fontsize=7)
    ax.set_title("Gutenberg-Richter of wave trains (Sec. V)", fontsize=9)
    cat = long_catalogs(quick)
    ax = axes[1]
    ch, fb = cat["chain"], cat["fb"]
    nb = len(ch.u)
    # the fraction of the system that ruptured: the one size both catalogs define alike
    frac_chain = ch.catalog.n_blocks.to_numpy() / nb
    # (rounded: a front that swept the whole ring does so to ~1e-12, not exactly)
    frac_fb = np.minimum(np.round(fb.events.swept.to_numpy() / cat["L"], 9), 1.0)
    # the complementary distribution at each distinct size (ties are one point, not a column
    # of points); the free boundary's merged events all span the ring, one point at (1, 1)
    for k, (name, f) in enumerate(
        (
            (f"chain, {nb} blocks, fixed ends, $v = {V_CHAIN}$", frac_chain),
            (f"free boundary, ring $L = {cat['L']:.0f}$, $v = {V_FB}$", frac_fb),
        )
    ):
        f = f[np.isfinite(f) & (f > 0)]
        if f.size:
            xs = np.unique(f)
            cc = np.array([np.mean(f >= x) for x in xs])
            whole = f" ({f.size} events" + (", all span the ring)" if xs.size == 1 else ")")
            ax.loglog(xs, cc, "os"[k], ms=4 + 3 * k, color=f"C{k}", label=name + whole)
    ax.set_xlabel("fraction of the system ruptured")
    ax.set_ylabel(r"fraction of events $\geq$ size")
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title("Catalogs of two different systems", fontsize=9)
    ax = axes[2]
    ev = ch.catalog
    big = ev[ev.n_blocks >= 0.5 * nb]
    rt = stats.recurrence_times(big.t_start.to_numpy())
    if rt.size:
        ax.hist(V_CHAIN * rt, bins=12, color="C0", alpha=0.8, edgecolor="k", lw=0.6)
    ax.set_xlabel(r"$v \times$ recurrence time of events over half the chain")
    ax.set_ylabel("count")
    ax.set_title("Chain: recurrence of large events", fontsize=9)
    return (
        "Statistics (Sec. V). Left: frequency at a point against amplitude for wave trains "
        f"selected on rings (free boundary, gamma = {GAMMA_FB}, v = {V_FB}) on omega = v/A; "
        "this is an identity of any periodic state (report row gr-train). Middle: size "
        "distributions of two catalogs, as the fraction of the system that ruptured (the "
        f"only size both define alike): the direct chain (`bk.Chain`, {nb} blocks, dx = "
        f"{ch.params.dx}, fixed ends, gamma = {ch.params.gamma}, v = {V_CHAIN}, smooth random "
        f"start, no backward slip) and the free boundary problem (ring L = {cat['L']:.0f}, "
        f"v = {V_FB}, rough random start; events overlapping in time merge into one, so "
        "most of its events span the ring: "
        f"{int(np.sum(frac_fb >= 1.0))} of {frac_fb.size} here, drawn once at 1 as ties are). "
        "They are not the same system and are not compared: "
        "the chain spans "
        f"{nb * ch.params.dx:g} length units, too short and too loaded for the free boundary "
        "limit (v << 1, smooth fields, many pulse widths), while the continuum has no "
        "one-block slips; a like-with-like comparison of single ruptures is in "
        "docs/validation.md. Right: the chain's recurrence times of events over half the "
        "chain, times v (report row recurrence)."
    )
