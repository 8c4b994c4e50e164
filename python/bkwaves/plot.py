"""Pictures: matplotlib figures with the paper's axes (headless, Agg backend)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import theory  # noqa: E402
from .waves import TravelingWave, front_speed  # noqa: E402

__all__ = ["wave_profile", "speed_curve", "save"]


def wave_profile(wave: TravelingWave, ax=None):
    """u(z) behind the front (paper Fig. 4): front at z = 0, stick point at z = -w."""
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3.6), constrained_layout=True)
    if wave.w is not None:
        z = np.linspace(-1.6 * wave.w, 0.25 * wave.w, 800)
    else:
        s = np.sqrt(wave.c**2 - 1.0)
        z = np.linspace(-25.0 * s * max(1.0, wave.gamma / wave.u_plus), 2.0 * s, 800)
    ax.plot(z, wave.profile(z), color="C0", lw=2, label="u(z)")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.axvline(0.0, color="C3", ls=":", lw=1, label="slip point z = 0")
    if wave.w is not None:
        ax.axvline(-wave.w, color="C2", ls=":", lw=1, label=f"stick point z = -w = {-wave.w:.3g}")
        ax.axhline(wave.u_minus, color="C2", ls="--", lw=0.8, label=f"u_- = {wave.u_minus:.3g}")
    ax.set_xlabel("z = x - c t")
    ax.set_ylabel("u")
    ax.set_title(f"{wave.regime}: u+ = {wave.u_plus:g}, gamma = {wave.gamma:g}, c = {wave.c:.4g}")
    ax.legend(fontsize=8, loc="best")
    return ax


def speed_curve(u_points=None, ax=None):
    """c(u_+) (paper Fig. 3): exact tip-problem speed, the interpolation formula eq. (c)
    dashed, and the wrong formal continuum answer dotted; optional marked points."""
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 3.8), constrained_layout=True)
    u = np.linspace(0.005, 0.96, 400)
    ax.plot(u, front_speed(u), color="C0", lw=2, label="tip problem: 1/sqrt(1 - u+^2)")
    ax.plot(u, theory.c_interpolation(u), "k--", lw=1, label="interpolation, eq. (c)")
    ax.plot(
        u,
        theory.c_formal_continuum(u),
        ":",
        color="C3",
        lw=1,
        label="formal continuum 1/sqrt(1 - u+) (wrong)",
    )
    if u_points is not None and len(u_points):
        up = np.asarray(u_points, dtype=float)
        ax.plot(up, front_speed(up), "o", color="C1", label="requested")
    ax.set_xlabel("u+")
    ax.set_ylabel("c")
    ax.set_ylim(1.0, 4.0)
    ax.set_xlim(0.0, 1.0)
    ax.legend(fontsize=8, loc="upper left")
    return ax


def save(ax, path) -> Path:
    """Save the figure of ``ax`` (format from the suffix: png, svg, pdf)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ax.figure.savefig(path, dpi=150)
    plt.close(ax.figure)
    return path
