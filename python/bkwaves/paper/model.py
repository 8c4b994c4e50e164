"""The model (Figs. 1, 2) and the claims on no figure: the Bristol-board numbers of
Sec. VI and eq. (crit)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from .. import presets
from ..report import Check, Claim
from ..report import yes_no as _holds
from .figure import register_claims, register_figure


def _sig_round(x: float, digits: int) -> float:
    return float(f"{x:.{digits - 1}e}")


def _printed(text: str) -> tuple[float, int]:
    """A number as the paper prints it ("2.4e-12", "1.6e-2") and its significant digits."""
    mant = text.lower().split("e")[0]
    return float(text), len(mant.replace(".", "").lstrip("0"))


@register_claims(rank=140)
def claims_bristol(quick: bool) -> list[Claim]:
    """The numbers of the paper's Bristol-board example (Sec. VI) against bkwaves'.

    Parameters
    ----------
    quick : bool
        Unused (the numbers are closed forms).

    Returns
    -------
    list of bkwaves.report.Claim
        One claim per number (m, k_c, k_p, f_r - f_s, the sliding speed, the slip per
        wave, gamma) and eq. (crit), values in SI units.

    Examples
    --------
    >>> from bkwaves.paper.model import claims_bristol
    >>> [(c.key, c.verdict) for c in claims_bristol(True)][:3]
    [('bristol-m', 'confirmed'), ('bristol-k_c', 'confirmed'), ('bristol-k_p', 'rounding')]
    """
    exact = presets.bristol_board(V=1e-6, paper_rounding=False)
    rounded = presets.bristol_board(V=1e-6, paper_rounding=True)
    u, ur = exact.units, rounded.units
    rows = [
        ("m", "2.4e-12", "kg", u.mass, ur.mass),
        ("k_c", "3.8e7", "N/m", u.k_c, ur.k_c),
        ("k_p", "2.3e1", "N/m", u.k_p, ur.k_p),
        ("f_r - f_s", "1.2e-7", "N", u.force_scale, ur.force_scale),
        (
            "sliding speed (f_r - f_s)/sqrt(k_p m)",
            "1.6e-2",
            "m/s",
            u.velocity_scale,
            ur.velocity_scale,
        ),
        ("slip per wave 2(f_r - f_s)/k_p", "1e-8", "m", u.slip(2.0), ur.slip(2.0)),
        ("gamma", "0.45", "", exact.gamma, rounded.gamma),
    ]
    out = []
    for name, printed, unit, ours, paper_way in rows:
        val, digits = _printed(printed)
        ours_r, paper_way_r = _sig_round(ours, digits), _sig_round(paper_way, digits)
        agrees = abs(ours_r - val) <= 1e-12 * abs(val)
        explained = abs(paper_way_r - val) <= 1e-12 * abs(val)
        note = ""
        if not agrees:
            note = (
                f"the unrounded data give {ours:.4g} ({ours_r:g} to the paper's {digits} "
                f"digits); the paper's {printed} is {paper_way:.4g} from m and k_c rounded to "
                f"{ur.mass:.2g} kg and {ur.k_c:.2g} N/m before k_p = k_c (pi a/2h)^2"
                + ("" if explained else "; its rounding does not explain it either")
            )
        out.append(
            Claim(
                f"bristol-{name}",
                "Sec. VI",
                f"Bristol board: {name}",
                f"{printed} {unit}".strip(),
                f"{ours:.4g} {unit} unrounded".strip()
                + f" ({paper_way:.4g} with the paper's rounded m and k_c)",
                [
                    Check(f"{name} from the data (unrounded)", ours, lo=0.0),
                ],
                paper_check=_holds(f"unrounded value to {digits} digits = {printed}", agrees),
                rounding_check=_holds(
                    f"with the paper's rounded m and k_c, to {digits} digits = {printed}",
                    explained,
                ),
                note=note,
            )
        )
    margin = u.crit_velocity / presets.BRISTOL_BOARD["V_f"]
    wanted = 10.0  # what "<<" asks for at least
    p_needed = presets.BRISTOL_BOARD["pressure"] * wanted / margin  # f_r - f_s grows like p
    out.append(
        Claim(
            "crit",
            "(crit)",
            f"V_f = {presets.BRISTOL_BOARD['V_f']:g} m/s satisfies V_f << (f_r - f_s)/sqrt(k_c m)",
            "satisfied",
            f"(f_r - f_s)/sqrt(k_c m) = {u.crit_velocity:.3g} m/s: margin {margin:.2f}",
            [Check("(f_r - f_s)/sqrt(k_c m) / V_f", margin, lo=1.0)],
            kind="refinement",
            note=f"satisfied only marginally: the margin is a factor {margin:.2f}, not <<; a "
            f"margin of {wanted:g} needs p = {p_needed:.1e} Pa",
        )
    )
    return out


@register_figure("fig1_model")
def fig_schematic(ax):
    """Fig. 1: the Burridge-Knopoff model.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.

    Returns
    -------
    str
        The caption.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from bkwaves.paper.model import fig_schematic
    >>> fig, ax = plt.subplots()
    >>> fig_schematic(ax)[:32]
    'Fig. 1: the model: blocks of mas'
    """
    ax.set_xlim(-0.5, 6.5)
    ax.set_ylim(-0.6, 2.4)
    ax.axis("off")
    ax.fill_between([-0.5, 6.5], -0.6, -0.3, color="0.8", hatch="//")
    ax.text(6.4, -0.5, "frictional surface", ha="right", fontsize=8)
    ax.fill_between([-0.5, 6.5], 2.0, 2.2, color="0.6")
    ax.text(6.4, 2.25, r"loader plate, speed $V \rightarrow$", ha="right", fontsize=8)
    for i in range(6):
        ax.add_patch(plt.Rectangle((i + 0.05, -0.3), 0.5, 0.5, color="C0"))
        zz = np.linspace(0.2, 2.0, 30)
        ax.plot(i + 0.3 + 0.08 * np.sin(zz * 25), zz, color="C1", lw=1)
        if i < 5:
            xx = np.linspace(i + 0.55, i + 1.05, 30)
            ax.plot(xx, -0.05 + 0.05 * np.sin((xx - i) * 60), color="C2", lw=1)
    ax.text(0.6, 1.0, "$k_p$", color="C1")
    ax.text(1.65, 0.1, "$k_c$", color="C2")
    ax.text(2.2, -0.2, "$m$", color="white")
    ax.set_title("The Burridge-Knopoff model (Fig. 1)")
    return (
        "Fig. 1: the model: blocks of mass m coupled by springs k_c, pulled through springs "
        "k_p by a loader plate at speed V over a frictional surface. Schematic."
    )


@register_figure("fig2_friction")
def fig_friction(ax):
    """Fig. 2: friction force vs block velocity (static jump, kinetic level, viscous slope).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.

    Returns
    -------
    str
        The caption.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from bkwaves.paper.model import fig_friction
    >>> fig, ax = plt.subplots()
    >>> fig_friction(ax)[:33]
    'Fig. 2: the friction law of the m'
    """
    fr, fs, alpha = 1.0, 0.6, 0.25
    vel = np.linspace(0, 2, 50)
    ax.plot(vel, fs + alpha * vel, "C0", lw=2)
    ax.plot(-vel, -(fs + alpha * vel), "C0", lw=2)
    ax.plot([0, 0], [-fr, fr], "C0", lw=2)
    ax.plot([0], [fr], "o", color="C0")
    ax.plot([0], [-fr], "o", color="C0")
    ax.annotate("$f_r$ (static)", (0, fr), (0.25, fr + 0.05))
    ax.annotate(r"$f_s + \alpha\,v$", (1.2, fs + alpha * 1.2), (0.9, fs + alpha * 1.2 - 0.35))
    ax.axhline(0, color="0.7", lw=0.8)
    ax.set_xlabel("block velocity $v$")
    ax.set_ylabel("friction force $f$")
    ax.set_title("Coulomb friction with viscous term (Fig. 2)")
    return (
        f"Fig. 2: the friction law of the model: static threshold f_r = {fr:g}, kinetic "
        f"friction f_s + alpha v (f_s = {fs:g}, alpha = {alpha:g}: illustrative values) at "
        "nonzero velocity, any force in [-f_r, f_r] at rest. Drawn from the formula (the law "
        "bkwaves' `friction::Coulomb` implements); no simulation."
    )
