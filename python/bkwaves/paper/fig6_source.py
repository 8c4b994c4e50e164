"""Fig. 6: a source of counter-propagating waves, and the claims on sources: eq. (b),
the map (ap) measured at each birth, the period T and a > a_max."""

from __future__ import annotations

#: Not an API: the drawing and claim functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`), called by :func:`bkwaves.paper.reproduce` and
#: ``bkwaves paper``; each costs seconds to minutes of computation (docs/paper.md says how
#: to add or change a figure).
__all__: list[str] = []

import numpy as np

from .. import theory
from ..report import Check, Claim
from .common import GAMMA_FB, V_FB, fb_source
from .figure import register_claims, register_figure


@register_claims(rank=110)
def claims_free_boundary(quick: bool) -> list[Claim]:
    """Sec. V: sources, the shocks' start (b), the map (ap) at each birth, the period T and a >
    a_max.

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
    a = 1e-4
    r, m = fb_source(quick, a)
    sh = r.shocks
    right = sh[(sh.shock == 0) & (sh.kind == "node")]
    tb = float(r.events.t_start.iloc[0])
    b = float(theory.source_b(a, V_FB))
    early = right[(right.x - m["x0"] > 0.05) & (right.x - m["x0"] < 0.5)]
    dev = np.max(np.abs((early.x - m["x0"]) / np.sqrt(b * (early.t - tb)) - 1))
    out.append(
        Claim(
            "b",
            "(b)",
            "shocks start as x0 +- sqrt(b t)",
            f"b = {b:.4f}",
            f"free-boundary shocks within {dev:.1e} of x0 + sqrt(b t) at |x - x0| < 0.5",
            [
                Check(
                    "max |x - x0| / sqrt(b (t - t_birth)) - 1 for |x - x0| in (0.05, 0.5)",
                    dev,
                    hi=1e-4,
                )
            ],
            note=f"the deviation ({dev:.1e}) grows like 1 - u_+: eq. (cc) is the large-c form of c",
        )
    )
    curv = r.events.curvature.to_numpy()
    pred = theory.iterate_map(curv[0], V_FB, GAMMA_FB, len(curv) - 1)
    dev = float(np.max(np.abs(curv[1:] / pred[1:] - 1)))
    out.append(
        Claim(
            "ap",
            "(ap)",
            "after the shocks pass the curvature at x0 is a' (the map a -> a')",
            f"a' = {pred[1]:.6e} from a = {curv[0]:.1e}",
            f"curvature at each new birth follows {len(curv) - 1} iterates within {dev:.1e}",
            [Check("max relative deviation of the measured curvatures from the map", dev, hi=1e-4)],
        )
    )
    periods = np.diff(r.events.t_start.to_numpy())
    dev_t = float(np.max(np.abs(periods / m["T"] - 1)))
    out.append(
        Claim(
            "Tsource",
            "Sec. V",
            "the source has period T = (1 + exp(-pi gamma/sqrt(1-gamma^2)))/v",
            f"T = {m['T']:.6f}",
            f"birth intervals within {dev_t:.1e} of T",
            [Check("max |birth interval / T - 1|", dev_t, hi=1e-6)],
        )
    )
    amax = theory.a_max(V_FB, GAMMA_FB)
    r2, m2 = fb_source(quick, 4 * amax, events=2)
    x_second = float(r2.events.x_start.iloc[1]) - m2["x0"]
    out.append(
        Claim(
            "amax-run",
            "(amax)",
            "with a > a_max the maximum at x0 is lost",
            "next births away from x0",
            f"a = 4 a_max: second birth at x0 {x_second:+.3f}",
            [Check("|second birth - x0|", abs(x_second), lo=1.0)],
        )
    )
    return out


@register_figure("fig6_source", 2)
def fig_source(axes, quick):
    """Fig. 6 (guide): a source of counter-propagating waves: the space-time diagram and
    the shock paths near two births, with eq. (b).

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
    r, m = fb_source(quick)
    ds = r.snapshots
    ax = axes[0]
    # zoomed into the first birth: its two shocks (from the shock table, red) run out of x0
    # as a V over u(x, t)
    ev0 = r.events.iloc[0]
    first = r.shocks[
        (r.shocks.event == ev0.id) & r.shocks.kind.isin(["birth", "node", "exit", "death"])
    ]
    t0, t1 = float(ev0.t_start), float(first.t.max())
    pad = 0.15 * (t1 - t0)
    lo = max(t0 - pad, float(ds.t[0]))
    near = ds.sel(t=slice(lo, t1 + pad))
    mesh = ax.pcolormesh(near.x, near.t, near.u, shading="nearest", cmap="viridis", rasterized=True)
    cb = ax.figure.colorbar(mesh, ax=ax, pad=0.02)
    cb.ax.set_title("$u$", fontsize=9)  # above the bar, clear of the next panel
    for k, (_, g) in enumerate(first.groupby("shock")):
        ax.plot(g.x, g.t, "-", color="C3", lw=1.5, label="shock paths" if k == 0 else None)
    ax.set_ylim(lo, t1 + pad)
    ax.legend(fontsize=7, loc="upper center")
    ax.set_xlabel("$x$")
    ax.set_ylabel("$t$")
    ax.set_title(f"Source, $a = {m['a']:g} < a_{{\\max}}$: the first birth", fontsize=9)
    ax = axes[1]
    ev = r.events
    sh = r.shocks
    span = 3.0
    for k, col in ((0, "C0"), (1, "C3")):
        tb, a_k = float(ev.t_start.iloc[k]), float(ev.curvature.iloc[k])
        b = float(theory.source_b(a_k, V_FB))
        near = sh[(sh.event == ev.id.iloc[k]) & (np.abs(sh.x - m["x0"]) <= span)]
        for _, g in near.groupby("shock"):
            ax.plot(g.x - m["x0"], g.t - tb, ".", color=col, ms=3)
        xs = np.linspace(-span, span, 201)
        ax.plot(
            xs,
            xs**2 / b,
            "-",
            color=col,
            lw=0.8,
            label=f"birth {k + 1}: $x_0 \\pm \\sqrt{{b\\,t}}$, $a = {a_k:.2e}$, $b = {b:.0f}$",
        )
    ax.set_xlabel("$x - x_0$")
    ax.set_ylabel(r"$t - t_{\mathrm{birth}}$")
    ax.legend(fontsize=7, loc="upper center")
    ax.set_title("Shock paths near the birth (dots) and eq. (b)", fontsize=9)
    return (
        f"Fig. 6: a source of counter-propagating waves: u = 1 - 1e-3 - a (x - x0)^2 with "
        f"a = {m['a']:g} < a_max at gamma = {GAMMA_FB}, v = {V_FB}, {len(ev)} births (free "
        "boundary engine, `bk.FreeBoundary`). Left: u(x, t) around the first birth with its "
        "two shock paths (red, from the engine's shock table): born at u = 1, where c is "
        "infinite, they leave x0 as a V. "
        f"Right: the V (here a parabola t = (x - x0)^2/b) of the two shocks within {span:g} of "
        "x0 after the first two births, as recorded by the engine (dots, every grid node "
        "crossed), with eq. (b) for the curvature measured at each birth (lines)."
    )
