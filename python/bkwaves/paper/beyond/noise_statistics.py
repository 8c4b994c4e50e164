"""Beyond the paper: noise-triggered slips on a free-boundary ring, rupture statistics
against the noise strength (issue 14, docs/noise.md)."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import numpy as np

from ..common import CACHE, GAMMA_FB, V_FB, fb_params
from ..figure import register_figure


def noise_scan(quick: bool) -> dict:
    """Rupture statistics on a free boundary ring against the noise strength (constant
    law, :func:`bkwaves.noise_stats.statistics_vs_strength`), from a smooth start (the
    synchronised regime of Sec. V, all maxima a < a_max) and a sharp one (a >> a_max,
    spatiotemporal chaos), with the same noise seed.

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    dict
        The ring's length ``L`` and grid spacing ``h`` (dimensionless x), the source
        period ``T`` (units of sqrt(m/k_p)), ``periods`` and ``burn``, and per start
        ("smooth", "sharp") what :func:`bkwaves.noise_stats.statistics_vs_strength`
        returns. Cached in ``CACHE``.
    """
    from ... import theory
    from ...config import _smooth_random
    from ...noise_stats import statistics_vs_strength

    key = ("noise_scan", quick)
    if key not in CACHE:
        L, h = (200.0, 0.4) if quick else (400.0, 0.2)
        periods, burn = (12, 4) if quick else (40, 10)
        nus = [0, 0.3, 3, 30] if quick else [0, 0.03, 0.1, 0.3, 1, 3, 10, 30, 100, 1000]
        x = np.arange(int(round(L / h))) * h
        T = theory.source_period(V_FB, GAMMA_FB)
        out = {"L": L, "h": h, "T": T, "periods": periods, "burn": burn}
        for name, amp, corr in (("smooth", 0.02, 25.0), ("sharp", 0.3, 4.0)):
            u0 = 0.5 + amp * _smooth_random(x, corr, np.random.default_rng(1), True)
            out[name] = statistics_vs_strength(
                fb_params(), x, u0, nus, t_end=periods * T, burn_in=burn * T
            )
        CACHE[key] = out
    return CACHE[key]


#: The noise strength's axis label (Lambda is constant for u > 0: nu_R = Lambda R_0 / v).
NU_R_LABEL = r"noise strength $\nu_R = \Lambda R_0 / v$"


@register_figure("beyond_noise_statistics", 3, beyond=True)
def fig_noise_statistics(axes, quick):
    """Noise-triggered slips (issue 14): size-frequency, b-value and recurrence against
    the noise strength, from the synchronised and the chaotic regimes to noise dominated.

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
    from ... import stats, theory

    m = noise_scan(quick)
    v, g = V_FB, GAMMA_FB
    tab_s, runs_s = m["smooth"]
    r0 = float(tab_s.swept[tab_s.nu == 0].iloc[0])  # noiseless rupture length, smooth start
    ax = axes[0]
    picks = [i for i, nu in enumerate(tab_s.nu) if nu == 0 or i % 2 == 0 or i == len(tab_s) - 1]
    for k, i in enumerate(picks):
        cat = runs_s[i]["ruptures"]
        if len(cat) < 2:
            continue
        s, cc = stats.size_frequency(cat.moment.to_numpy())
        nu_r = tab_s.Lambda_mean[i] * r0 / v
        lab = "no noise" if tab_s.nu[i] == 0 else f"$\\nu_R = {nu_r:.2g}$"
        ax.loglog(s, cc, "-", color=f"C{k}", lw=1.2, label=f"{lab} ({len(cat)})")
    ax.set_xlabel(r"rupture moment $\int A\,dx$")
    ax.set_ylabel(r"fraction of ruptures $\geq$ size")
    ax.legend(fontsize=6, loc="lower left")
    ax.set_title("Size-frequency (smooth start)", fontsize=9)
    ax = axes[1]
    for name, col, dx in (("smooth", "C0", 1.0), ("sharp", "C3", 1.08)):
        tab = m[name][0]
        noisy = tab[tab.nu > 0]
        nu_r = noisy.Lambda_mean * r0 / v * dx
        yerr = [noisy.b - noisy.b_lo, noisy.b_hi - noisy.b]  # the 95 % bootstrap interval
        has_b = bool(
            np.isfinite(noisy.b.to_numpy(float)).any()
        )  # (a legend entry only with points)
        ax.errorbar(
            nu_r, noisy.b, yerr=yerr, fmt="o-", color=col, ms=3, label=name if has_b else None
        )
        q = tab[tab.nu == 0]
        if len(q) and np.isfinite(q.b.iloc[0]) and q.b.iloc[0] < 20:
            ax.axhline(q.b.iloc[0], color=col, ls=":", lw=1, label=f"{name}, no noise")
    ax.axvline(1.0, color="k", ls="--", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel(NU_R_LABEL)
    ax.set_ylabel("$b$ (moment magnitudes above $M_c$)")
    # below the axes: a legend inside would hide points
    if ax.get_legend_handles_labels()[1]:
        ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncols=2)
    ax.set_title("b-value, 95 % interval (no point: no b)", fontsize=9)
    ax = axes[2]
    a1 = 1.0 - theory.u_minus_at_one(g)
    noisy = tab_s[tab_s.nu > 0]
    nu_r = noisy.Lambda_mean * r0 / v
    ax.loglog(nu_r, noisy.v_recurrence, "o", color="C0", ms=4, label=r"$v \times$ mean recurrence")
    lam = np.geomspace(v**2 / (2 * a1**2), noisy.Lambda_mean.max(), 50)
    ax.loglog(lam * r0 / v, v / np.sqrt(2 * lam), "k-", lw=0.8, label=r"$v\,(2\Lambda)^{-1/2}$")
    ax.axhline(a1, color="k", ls=":", lw=0.8, label="$A(1) = v\\,T$, no noise")
    ax.axvline(1.0, color="k", ls="--", lw=0.8)
    ax.set_xlabel(NU_R_LABEL)
    ax.set_ylabel(r"$v \times$ mean recurrence time at a point")
    from matplotlib.ticker import FormatStrFormatter

    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
    # the spontaneous fraction is another quantity: its own (linear) axis on the right
    ay = ax.twinx()
    ay.plot(nu_r, noisy.spontaneous, "s", color="C2", ms=3, label="spontaneous fraction")
    ay.set_ylim(-0.05, 1.05)
    ay.set_ylabel("spontaneous fraction of ruptures", color="C2")
    ay.tick_params(axis="y", colors="C2")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ay.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncols=2)
    ax.set_title("Recurrence at a point", fontsize=9)
    half = noisy.spontaneous.to_numpy()
    cross = (
        float(np.exp(np.interp(0.5, half, np.log(nu_r.to_numpy()))))
        if np.all(np.diff(half) >= 0) and half[0] < 0.5 < half[-1]
        else float("nan")
    )
    top = noisy.iloc[-1]
    mf = float(top.recurrence * np.sqrt(2 * top.rupture_rate))
    return (
        f"Noise-triggered slips (issue 14): free boundary ring L = {m['L']:.0f} (grid "
        f"{m['h']}), gamma = {g}, v = {v}, constant rate density Lambda for u > 0, "
        f"{m['periods'] - m['burn']} source periods after {m['burn']} discarded, same noise "
        "seed for every strength; statistics per rupture (the shocks born together and what "
        "they sweep: the engine's events merge overlapping ruptures). nu_R = "
        f"Lambda R_0 / v (on both axes) with R_0 = {r0:.0f} the noiseless rupture length of "
        "the smooth start: "
        "the expected nucleations in a rupture's region during one loading from u = 0 to 1. "
        "Left: size-frequency. Middle: b of moment magnitudes (bk.stats.gutenberg_richter: Mc "
        "by maximum curvature + 0.2, Aki-Utsu, 95 % bootstrap interval; none where fewer "
        "than 50 ruptures lie above Mc or they have one size), smooth start (synchronised "
        "regime) and sharp start "
        "(chaotic transient), with the noiseless values dotted. Right: v times the mean "
        f"recurrence time at a point falls from A(1) = {a1:.3f} to the noise-dominated "
        f"v (2 Lambda)^-1/2 (mean field; measured/estimate {mf:.2f} at the strongest noise, "
        "with the measured rate of ruptures for Lambda); the "
        f"spontaneous fraction of ruptures (squares, right axis) passes 1/2 at nu_R = {cross:.2g}."
    )
