"""Beyond the paper: the front speed in a chain with quenched disorder (random
thresholds) against the local-speed theories and the exact sigma^2 coefficient of one
defect (docs/disorder.md)."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import numpy as np

from ..figure import register_figure


@register_figure("beyond_disorder_speed", 2, beyond=True)
def fig_disorder_speed(axes, quick):
    """c_eff of a front in a chain with iid uniform thresholds 1 + sigma xi (the tip
    marcher, docs/disorder.md) against the theories; right: the sigma^2 coefficient.

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

    from ...disorder import defect_response, front_speed_ensemble, local_theories

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
