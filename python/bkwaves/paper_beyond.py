"""Beyond the paper: figures of what Sec. VI leaves open, in ``bkwaves paper``.

The paper closes by naming what it does not answer: blocks that are not all alike
(quenched disorder and the renormalised front speed), velocity-weakening friction and its
continuum limit (eq. crit), and noise-triggered slips. bkwaves answers these with its own
engines; the answers are bkwaves' results, not claims of the paper, so they are reported
in their own section of ``report.md``/``report.html`` ("Beyond the paper"), after the
paper's figures.

A figure is one builder plus one line in :data:`BEYOND_FIGURES`. A builder has the
signature of the paper's figures, ``builder(outdir, quick, name) -> (paths, caption)``;
:func:`bkwaves.paper._panels` turns a function ``draw(axes[, quick]) -> caption`` into one.
Its caption is computed from the data drawn (no literal numbers), and ``quick=True`` must
keep ``bkwaves paper --quick`` fast (CI runs it).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .paper import _panels

__all__ = ["BEYOND_FIGURES"]

#: Figure builders of the "Beyond the paper" section: name -> builder(outdir, quick, name).
BEYOND_FIGURES: dict[str, Callable] = {}


def fig_disorder_speed(axes, quick):
    """c_eff of a front in a chain with iid uniform thresholds 1 + sigma xi (the tip
    marcher, docs/disorder.md) against the theories; right: the sigma^2 coefficient."""
    import numpy as np

    from .disorder import defect_response, front_speed_ensemble, local_theories

    dx, gamma = 0.1, 0.0
    ups = (0.6,) if quick else (0.6, 0.7)
    blocks, reals = (600, 4) if quick else (4000, 48)
    parts = []
    for i, u in enumerate(ups):
        top = (1.0 - u) / np.sqrt(3.0)  # uniform noise keeps every threshold above u_+
        sig = np.linspace(top / 4, 0.9 * top, 3) if quick else np.linspace(top / 8, 0.9 * top, 7)
        d = defect_response(u, gamma, dx=dx, blocks=blocks if quick else 1500)
        ens = [
            front_speed_ensemble(u, gamma, s, dx=dx, blocks=blocks, realisations=reals, seed=1)
            for s in sig
        ]
        th = [local_theories(u, gamma, s, dx=dx) for s in sig]
        fine = np.linspace(sig[0] / 4, sig[-1], 10 if quick else 30)
        thf = [local_theories(u, gamma, s, dx=dx) for s in fine]
        harm = np.array([t.harmonic for t in thf])
        c = np.array([e.c_mean for e in ens])
        err = np.array([e.c_sem for e in ens])
        col = f"C{i}"
        ax = axes[0]
        # error bars with caps and markers smaller than them, so that bars of one standard
        # error (often ~1e-3 in c) show; the theories are labelled once (the colour is u_+)
        once = i == 0
        ax.errorbar(
            sig, c, err, fmt="o", color=col, ms=3, capsize=4, label=f"tip marcher, $u_+ = {u}$"
        )
        s0 = np.r_[0.0, fine]
        ax.plot(
            s0,
            d.c0 + d.k * s0**2,
            "-",
            color=col,
            lw=1,
            label=r"$c_0 + k\,\sigma^2$ (one defect)" if once else None,
        )
        ax.plot(
            fine,
            harm,
            "--",
            color=col,
            lw=1,
            label=r"harmonic $1/\langle 1/c(u_+/\theta)\rangle$" if once else None,
        )
        arith = [t.arithmetic for t in thf]
        ax.plot(
            fine,
            arith,
            ":",
            color=col,
            lw=1,
            label=r"arithmetic $\langle c(u_+/\theta)\rangle$" if once else None,
        )
        # the sigma^2 coefficient, paired with the same realisations' harmonic prediction
        k = np.array(
            [
                (t.harmonic + e.excess_mean - d.c0) / s**2
                for t, e, s in zip(th, ens, sig, strict=True)
            ]
        )
        kerr = np.array([e.excess_sem / s**2 for e, s in zip(ens, sig, strict=True)])
        ax = axes[1]
        ax.errorbar(
            sig, k, kerr, fmt="o", color=col, ms=3, capsize=4, label=f"measured, $u_+ = {u}$"
        )
        ax.axhline(
            d.k, color=col, lw=1, label=r"one defect (exact as $\sigma \to 0$)" if once else None
        )
        ax.plot(
            fine,
            (harm - d.c0) / fine**2,
            "--",
            color=col,
            lw=1,
            label="harmonic local theory" if once else None,
        )
        parts.append(
            f"at u_+ = {u:g} the measured k goes from {k[0]:.3g} +- {kerr[0]:.1g} at "
            f"sigma = {sig[0]:.3g} (single defect: {d.k:.3g}; harmonic local theory: "
            f"{th[0].k_harmonic:.3g}, {th[0].k_harmonic / d.k:.1f} times larger) to "
            f"{k[-1]:.3g} at sigma = {sig[-1]:.3g}, where c_eff = {c[-1]:.4f} +- {err[-1]:.1g} "
            f"against {d.c0 + d.k * sig[-1] ** 2:.4f} at second order and "
            f"{th[-1].harmonic:.4f} harmonic"
        )
    axes[0].set_xlabel(r"threshold standard deviation $\sigma$")
    axes[0].set_ylabel(r"front speed $c_{\mathrm{eff}}$")
    axes[0].legend(fontsize=6, loc="upper left")
    axes[0].set_title("Front speed in a disordered chain", fontsize=9)
    axes[1].set_xlabel(r"threshold standard deviation $\sigma$")
    axes[1].set_ylabel(r"$k = (c_{\mathrm{eff}} - c_0)/\sigma^2$")
    axes[1].set_yscale("log")
    from matplotlib.ticker import FormatStrFormatter

    # plain numbers (0.4, 0.6, 1) on the log axis, not 4x10^-1
    axes[1].yaxis.set_major_formatter(FormatStrFormatter("%g"))
    axes[1].yaxis.set_minor_formatter(FormatStrFormatter("%g"))
    axes[1].legend(fontsize=6, loc="lower left", bbox_to_anchor=(0.0, 0.1))
    axes[1].set_title(r"The $\sigma^2$ coefficient", fontsize=9)
    return (
        f"Quenched disorder: a front at stress u_+ ahead runs into blocks with iid uniform "
        f"thresholds 1 + sigma xi (dx = {dx:g}, gamma = {gamma:g}); c_eff is the mean over "
        f"{reals} realisations of {blocks} blocks marched by the tip solver "
        f"(bk.disorder.tip_march), error bars one standard error. Disorder "
        f"{'speeds the front up' if c[-1] > d.c0 else 'slows the front down'}, at order "
        f"sigma^2, by {'less' if d.k < th[0].k_harmonic else 'more'} than the local-speed "
        f"theories say: "
        + "; ".join(parts)
        + ". The rise of k with sigma is the sigma^4 term (docs/disorder.md)."
    )


BEYOND_FIGURES["beyond_disorder_speed"] = _panels(fig_disorder_speed, 2)


def fig_vw_crossover(axes, quick):
    """Velocity-weakening friction against eq. (crit): front speed c and slipping zone
    (lattice spacings) against v_f/dx at several dx (bkwaves.velocity_weakening)."""
    from . import velocity_weakening as vw
    from .waves import front_speed, traveling_wave

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


BEYOND_FIGURES["beyond_vw_crossover"] = _panels(fig_vw_crossover, 2)


# ---------------------------------------------------------------- noise statistics
def noise_scan(quick: bool) -> dict:
    """Rupture statistics on a free boundary ring against the noise strength (constant
    law, :func:`bkwaves.noise_stats.statistics_vs_strength`), from a smooth start (the
    synchronised regime of Sec. V, all maxima a < a_max) and a sharp one (a >> a_max,
    spatiotemporal chaos), with the same noise seed."""
    from . import paper, theory
    from .config import _smooth_random
    from .noise_stats import statistics_vs_strength

    key = ("noise_scan", quick)
    if key not in paper._CACHE:
        L, h = (200.0, 0.4) if quick else (400.0, 0.2)
        periods, burn = (12, 4) if quick else (40, 10)
        nus = [0, 0.3, 3, 30] if quick else [0, 0.03, 0.1, 0.3, 1, 3, 10, 30, 100, 1000]
        x = np.arange(int(round(L / h))) * h
        T = theory.source_period(paper.V_FB, paper.GAMMA_FB)
        out = {"L": L, "h": h, "T": T, "periods": periods, "burn": burn}
        for name, amp, corr in (("smooth", 0.02, 25.0), ("sharp", 0.3, 4.0)):
            u0 = 0.5 + amp * _smooth_random(x, corr, np.random.default_rng(1), True)
            out[name] = statistics_vs_strength(
                paper._fb_params(), x, u0, nus, t_end=periods * T, burn_in=burn * T
            )
        paper._CACHE[key] = out
    return paper._CACHE[key]


#: The noise strength's axis label (Lambda is constant for u > 0: nu_R = Lambda R_0 / v).
NU_R_LABEL = r"noise strength $\nu_R = \Lambda R_0 / v$"


def fig_noise_statistics(axes, quick):
    """Noise-triggered slips (issue 14): size-frequency, b-value and recurrence against
    the noise strength, from the synchronised and the chaotic regimes to noise dominated."""
    from . import paper, stats, theory

    m = noise_scan(quick)
    v, g = paper.V_FB, paper.GAMMA_FB
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
        ax.errorbar(nu_r, noisy.b, yerr=yerr, fmt="o-", color=col, ms=3, label=name)
        q = tab[tab.nu == 0]
        if len(q) and np.isfinite(q.b.iloc[0]) and q.b.iloc[0] < 20:
            ax.axhline(q.b.iloc[0], color=col, ls=":", lw=1, label=f"{name}, no noise")
    ax.axvline(1.0, color="k", ls="--", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel(NU_R_LABEL)
    ax.set_ylabel("$b$ (moment magnitudes above $M_c$)")
    # below the axes: a legend inside would hide points
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


BEYOND_FIGURES["beyond_noise_statistics"] = _panels(fig_noise_statistics, 3)
