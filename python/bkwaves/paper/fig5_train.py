"""Fig. 5: a wave train that selects itself on a ring, and the claims on trains: eqs.
(L) and (Lmin)."""

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
from ..waves import front_speed
from .common import CACHE, GAMMA_FB, V_FB, fb_params, fb_train, selected_u_plus, train_summary
from .figure import register_claims, register_figure


def fb_lmin(quick: bool):
    """Trains on rings just below and above L_min (eq. Lmin): one shock on a ramp of slope
    -v/c(u_a), u_a = u_c + 0.02 (u_+ = u_a on the first lap), the stress behind it u_a - v
    L/c(u_a) (not u_-(u_a): not the train). Creep rule "stop": a shock ends where u_+ falls
    to u_c. Does the train persist?

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    dict
        ``rows`` (per ring: its length L in dimensionless x, the creep stops, the laps
        run and done, and for a persisting train u_+ with the value eq. (L) selects),
        ``lmin`` (eq. Lmin, dimensionless x) and the ramp's top ``ua`` (dimensionless).
        Cached in ``CACHE``.
    """
    key = ("lmin", quick)
    if key not in CACHE:
        from ..free_boundary import FreeBoundary

        uc = theory.critical_stress(GAMMA_FB)
        lmin = float(theory.min_wavelength(GAMMA_FB, V_FB))
        ua = uc + 0.02
        ca = float(front_speed(ua))
        rows = []
        for f in (0.9, 0.97, 1.03, 1.1):
            L = f * lmin
            n = 100 if quick else 200
            h = L / n
            x = np.arange(n) * h
            xf = 0.37 * h
            u0 = ua - (V_FB / ca) * np.mod(x - xf, L)
            fb = FreeBoundary(fb_params(), x, u0, "periodic", shocks=[(xf, 1)], creep="stop")
            laps = 20 if quick else 40
            r = fb.run(t_end=laps * L / float(front_speed(uc)))
            sh = r.shocks
            first = sh[sh.shock == sh.shock.min()]
            stops = int((first.kind == "creep_stop").sum())
            laps_done = int((first.kind == "node").sum()) / n
            row = dict(f=f, L=L, stops=stops, laps=laps_done, laps_run=laps)
            if stops == 0:
                row["up"] = float(first.u_plus.iloc[-1])
                row["up_star"] = selected_u_plus(L)
            rows.append(row)
        CACHE[key] = dict(rows=rows, lmin=lmin, ua=ua)
    return CACHE[key]


@register_claims(rank=90)
def claims_trains(quick: bool) -> list[Claim]:
    """Sec. V: wave trains, their wavelength (L) and the shortest one (Lmin).

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
    m = fb_lmin(quick)
    lmin = m["lmin"]
    checks = []
    desc = []
    for row in m["rows"]:
        persists = row["stops"] == 0 and row["laps"] >= row["laps_run"] - 1
        desc.append(
            f"{row['f']:.2f} L_min: "
            + (
                f"persists ({row['laps']:.0f} laps, u_+ = {row['up']:.5f} vs eq. (L) "
                f"{row['up_star']:.5f})"
                if persists
                else f"dies in creep after {row['laps']:.0f} laps"
            )
        )
        if row["f"] < 1:
            checks.append(_holds(f"no train on a ring of {row['f']:.2f} L_min", not persists))
        else:
            checks.append(_holds(f"a train on a ring of {row['f']:.2f} L_min", persists))
            if persists:
                checks.append(
                    Check(
                        f"u_+ - u_+(eq. L) at {row['f']:.2f} L_min",
                        row["up"] - row["up_star"],
                        -1e-4,
                        1e-4,
                    )
                )
    out.append(
        Claim(
            "Lmin",
            "(Lmin)",
            "wave trains need L > L_min = c(u_c) u_c / v",
            f"L_min = {lmin:.4f} (gamma = {GAMMA_FB}, v = {V_FB})",
            "free-boundary rings, one shock started at u_+ = u_c + "
            f"{m['ua'] - theory.critical_stress(GAMMA_FB):.2f}: " + "; ".join(desc),
            checks,
        )
    )
    r, mt = fb_train(quick)
    s = train_summary(mt)
    up_star = selected_u_plus(mt["L"])
    c_star = float(front_speed(up_star))
    A_star = float(theory.amplitude(up_star, c_star, GAMMA_FB))
    out.append(
        Claim(
            "L",
            "(L)",
            "a periodic wave train has L = c A / v and T = A / v",
            f"for L = {mt['L']:.4f}: u_+ = {up_star:.6f}, A = {A_star:.6f}, T = "
            f"{A_star / V_FB:.4f}",
            f"free-boundary ring of {mt['teeth']} x {mt['L']:.4f} from uniform u = {mt['u0']} "
            f"and {mt['teeth']} shocks: after {s['passages']} passages u_+ = {s['up']:.6f}, "
            f"A = {s['A']:.6f}, period {s['period']:.4f} (last change of u_+ {s['drift']:.1e})",
            [
                Check("selected u_+ - root of eq. (L)", s["up"] - up_star, -1e-5, 1e-5),
                Check("measured A / eq. (A) at the root - 1", s["A"] / A_star - 1, -1e-5, 1e-5),
                Check("measured period / (A/v) - 1", s["period"] * V_FB / s["A"] - 1, -1e-5, 1e-5),
            ],
            note="the ring length is the only input: amplitude, speed and period are selected by "
            f"the dynamics (u_+ went from {mt['up'][0]:.3f} on the first lap to {s['up']:.6f})",
        )
    )
    return out


@register_figure("fig5_wave_train", 2)
def fig_train(axes, quick):
    """Fig. 5 (period): a wave train selected on a ring from uniform stress.

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
    r, m = fb_train(quick)
    ds = r.snapshots
    s = train_summary(m)
    ax = axes[0]
    ax.plot(m["x"], ds.u.isel(t=0), color="0.6", lw=1, label="start: uniform $u$")
    for k in range(m["teeth"]):
        ax.axvline(
            m["xf"] + k * m["L"],
            color="0.6",
            ls="-.",
            lw=1,
            label="start: its right-moving shocks" if k == 0 else None,
        )
    t_end = float(ds.t[-1])
    # the final profile drawn wide and pale under the thin saw-tooth, so both show
    ax.plot(
        m["x"], ds.u.isel(t=-1), "C0", lw=4, alpha=0.5, label=f"free boundary, $t = {t_end:.0f}$"
    )
    # the saw-tooth of the train whose wavelength is the ring's (eq. L solved for u_+),
    # placed at the front of the final profile (its largest rise, left to right)
    u_end = ds.u.isel(t=-1).to_numpy()
    i = int(np.argmax(np.diff(u_end)))
    x_front = 0.5 * (m["x"][i] + m["x"][i + 1])
    up_star = selected_u_plus(m["L"])
    ax.plot(
        m["x"],
        theory.sawtooth(m["x"], 0.0, up_star, GAMMA_FB, V_FB, x0=x_front),
        "k--",
        lw=1,
        label=f"saw-tooth of eq. (L): $u_+ = {up_star:.4f}$",
    )
    ax.set_xlabel("$x$")
    ax.set_ylabel("$u$")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=2)
    ax.set_title(f"Wave train on a ring, $\\gamma = {GAMMA_FB}$, $v = {V_FB}$ (Fig. 5)", fontsize=9)
    first = ds.isel(t=slice(0, -1))
    mesh = axes[1].pcolormesh(
        first.x, first.t, first.u, shading="nearest", cmap="viridis", rasterized=True
    )
    axes[1].figure.colorbar(mesh, ax=axes[1], label="$u$")
    axes[1].set_xlabel("$x$")
    axes[1].set_ylabel("$t$")
    axes[1].set_title("$u(x, t)$, first laps: the train selects its amplitude", fontsize=9)
    return (
        f"Fig. 5: a periodic wave train that selected itself. A ring of length "
        f"{m['teeth']} x {m['L']:.2f} (gamma = {GAMMA_FB}, v = {V_FB}) starts at uniform "
        f"u = {m['u0']} with {m['teeth']} equally spaced right-moving shocks (grey, "
        f"dash-dotted); the free boundary engine (`bk.FreeBoundary`) runs it to "
        f"t = {t_end:.0f}. Left: the final profile (broad pale blue) under the saw-tooth "
        f"(dashed) of the train whose wavelength L = c A / v is the ring's: measured "
        f"u_+ = {s['up']:.6f} vs {up_star:.6f}. Right: u(x, t) over the first "
        f"{float(first.t[-1]):.0f} time units; the first laps (u_+ = {m['up'][0]:.3f} on "
        "the first) relax to the train."
    )
