"""Pictures: matplotlib figures with the paper's axes.

matplotlib is imported only when a picture is drawn, and bkwaves never changes its global
state: no backend is chosen (``bkwaves`` on the command line draws off-screen with Agg)
and the bkwaves look (:data:`STYLE`) applies only inside these functions, through
``matplotlib.rc_context``.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np

from . import theory
from .waves import TravelingWave, front_speed

__all__ = [
    "wave_profile",
    "speed_curve",
    "spacetime",
    "profiles",
    "trajectories",
    "size_frequency",
    "frequency_magnitude",
    "plot_run",
    "plot_sweep",
    "save",
    "FORMATS",
    "STYLE",
]

FORMATS = ("png", "svg", "pdf")
"""The picture formats bkwaves writes (chosen by the file suffix)."""

STYLE = {
    "figure.dpi": 110,
    "savefig.dpi": 150,
    "font.size": 10,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "savefig.bbox": "tight",
}
"""rcParams applied while bkwaves draws and saves a figure (never globally)."""


def _styled(draw):
    """Run ``draw`` with :data:`STYLE` in force, leaving the caller's rcParams alone."""

    @functools.wraps(draw)
    def styled(*args, **kwargs):
        import matplotlib

        with matplotlib.rc_context(STYLE):
            return draw(*args, **kwargs)

    return styled


def _new_axes(figsize):
    import matplotlib.pyplot as plt

    _, ax = plt.subplots(figsize=figsize, layout="constrained")
    return ax


@_styled
def wave_profile(wave: TravelingWave, ax=None):
    """u(z) behind the front (paper Fig. 4): front at z = 0, stick point at z = -w.

    Parameters
    ----------
    wave : bkwaves.TravelingWave
        The wave (:func:`bkwaves.traveling_wave`).
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
        The axes: z (dimensionless x) against u (dimensionless).

    Examples
    --------
    >>> import bkwaves as bk
    >>> ax = bk.plot.wave_profile(bk.traveling_wave(0.6, 0.3))
    >>> ax.get_title(), float(ax.lines[0].get_ydata()[-1])       # u_+ ahead of the front
    ('pulse: u+ = 0.6, gamma = 0.3, c = 1.25', 0.6)
    """
    if ax is None:
        ax = _new_axes((6, 3.6))
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


@_styled
def speed_curve(u_points=None, ax=None):
    """c(u_+) (paper Fig. 3): exact tip-problem speed, the interpolation formula eq. (c)
    dashed, and the wrong formal continuum answer dotted; optional marked points.

    Parameters
    ----------
    u_points : array_like, optional
        Stresses u_+ to mark on the curve (dimensionless).
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
        The axes: u_+ (dimensionless) against c (units of the sound speed).

    Examples
    --------
    >>> import bkwaves as bk
    >>> ax = bk.plot.speed_curve([0.6])
    >>> ax.lines[-1].get_xydata().tolist()                  # the marked point on c(u_+)
    [[0.6, 1.25]]
    """
    if ax is None:
        ax = _new_axes((5, 3.8))
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


def _unit_suffix(u) -> str:
    """`` [unit]`` for a physical unit; nothing for a dimensionless one ("1" or empty): the
    figure's title says the run is in the paper's dimensionless units instead."""
    u = str(u or "")
    return f" [{u}]" if u and u != "1" else ""


def _units(da) -> str:
    return _unit_suffix(da.attrs.get("units", ""))


def run_title(attrs) -> str:
    """Two lines naming a run from its output attributes: its title and model, then its
    parameters (gamma, v, dx, the friction law) and its unit system."""
    import json

    title = str(attrs.get("title", "") or "")
    model = str(attrs.get("model", "") or "")
    head = " - ".join(x for x in (title, model) if x) or "bkwaves run"
    parts = []
    try:
        params = json.loads(attrs.get("params", "") or "{}")
    except (TypeError, ValueError):
        params = {}
    names = {"gamma": r"$\gamma$", "v": r"$v$", "dx": r"$\Delta x$", "beta": r"$\beta$"}
    for key in ("gamma", "v", "dx", "beta"):
        val = params.get(key)
        if isinstance(val, (int, float)) and (key != "beta" or math.isfinite(val)):
            parts.append(f"{names[key]} = {val:.3g}")
    try:
        law = json.loads(attrs.get("friction_law", "") or "{}").get("law")
    except (TypeError, ValueError, AttributeError):
        law = None
    if law and law != "coulomb":
        parts.append(law.replace("_", " "))
    system = str(attrs.get("units_system", "") or "")
    if system.startswith("dimensionless"):
        parts.append("dimensionless units (paper eq. dimless)")
    elif system:
        parts.append(system)
    return head + ("\n" + ", ".join(parts) if parts else "")


def _edges(c):
    """Cell edges around the sample points ``c`` (sorted, e.g. block positions): midpoints
    between neighbours, the outer edges half a spacing beyond the ends."""
    c = np.asarray(c, dtype=float)
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def _constant(values) -> bool:
    v = np.asarray(values)
    if v.dtype.kind == "f":
        v = v[np.isfinite(v)]
    return v.size == 0 or bool(np.all(v == v.flat[0]))


def _event_marks(ax, events, x_of, t_col="t_start"):
    """Nucleation points of a catalog on a space-time diagram: threshold events as white
    circles, noise-triggered ones as red stars, each kind in the legend once."""
    if events is None or not len(events) or t_col not in events:
        return
    x = x_of(events)
    if x is None:
        return
    t = events[t_col].to_numpy(dtype=float)
    kind = (
        events["kind"].astype(str).to_numpy()
        if "kind" in events
        else np.full(len(events), "threshold")
    )
    styles = {
        "threshold": dict(marker="o", mfc="none", mec="w", ms=5, mew=1.0),
        "noise": dict(marker="*", mfc="C3", mec="k", ms=8, mew=0.5),
    }
    for k in np.unique(kind):
        sel = kind == k
        st = styles.get(k, dict(marker="s", mfc="none", mec="C1", ms=5))
        ax.plot(x[sel], t[sel], ls="none", label=f"nucleation ({k})", **st)
    leg = ax.legend(
        fontsize=7,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.12),
        ncols=3,
        facecolor="0.45",
        edgecolor="0.45",
        labelcolor="w",
    )
    leg.get_frame().set_alpha(1.0)


@_styled
def spacetime(ds, var: str = "u", ax=None, cmap=None, events=None):
    """Space-time diagram of ``ds[var]`` (dimensions t, x): slip fronts are the edges.

    Each snapshot is held until the next one (the last, the final state, is in the
    profiles), so nothing is drawn before it happened: a change appears at the first
    snapshot after it, and the snapshot times are ticked on the right edge so sparse
    snapshots are seen as such. ``events`` (a catalog with ``t_start``
    and ``nucleation`` block or ``x_start``) marks where and when each event began,
    threshold and noise-triggered ones told apart.

    Parameters
    ----------
    ds : xarray.Dataset
        Snapshots with dimensions (t, x) (a run output, :func:`bkwaves.load`).
    var : str, default "u"
        The variable drawn.
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).
    cmap : str, optional
        The colour map (default viridis; coolwarm for the sliding state).
    events : pandas.DataFrame, optional
        A catalog whose nucleations are marked.

    Returns
    -------
    matplotlib.axes.Axes
        The axes: x against t, in the units the output records (dimensionless by
        default).

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = {"model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...        "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...        "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...        "run": {"t_end": 20.0}, "output": {"snapshot_every": 1.0}}
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> _ = bk.run(cfg, out)
    >>> ds, catalog = bk.load(out)
    >>> ax = bk.plot.spacetime(ds, events=catalog)
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('x', 't')
    """
    if ax is None:
        ax = _new_axes((7, 4.4))
    da = ds[var]
    discrete = da.dtype.kind in "iu" or var == "sliding"
    if cmap is None:
        cmap = "coolwarm" if discrete else "viridis"
    t = ds.t.values.astype(float)
    x = ds.x.values.astype(float)
    kw = dict(vmin=-1, vmax=1) if discrete else {}
    values = da.values
    if t.size > 1:  # snapshot k held on [t_k, t_k+1)
        t_edges, values = t, values[:-1]
    else:
        t_edges = np.array([t[0], t[0] + 1.0])
    m = ax.pcolormesh(
        _edges(x),
        t_edges,
        values,
        shading="flat",
        cmap=cmap,
        rasterized=True,
        **kw,
    )
    cb = ax.figure.colorbar(m, ax=ax)
    cb.set_label(da.attrs.get("long_name", var) + _units(da), fontsize=8)
    if discrete:
        cb.set_ticks([-1, 0, 1])
    ax.set_xlabel("x" + _units(ds.x))
    ax.set_ylabel("t" + _units(ds.t))
    ax.set_ylim(t[0], t[-1] if t[-1] > t[0] else t[0] + 1.0)
    ax.plot(
        np.full(t.size, x[-1] + 0.5 * (x[-1] - x[-2] if x.size > 1 else 1.0)),
        t,
        ls="none",
        marker="_",
        color="k",
        ms=6,
        clip_on=False,
    )

    def x_of(ev):
        if "x_start" in ev:
            return ev["x_start"].to_numpy(dtype=float)
        if "nucleation" in ev:
            idx = ev["nucleation"].to_numpy(dtype=int)
            return x[np.clip(idx, 0, x.size - 1)]
        return None

    _event_marks(ax, events, x_of)
    ax.set_title(run_title(ds.attrs) + f"\n{var}(x, t); snapshots ticked at right", fontsize=8)
    return ax


@_styled
def profiles(ds, var: str = "u", n: int = 6, ax=None):
    """Profiles ``var(x)`` at ``n`` snapshots spread over the run.

    Parameters
    ----------
    ds : xarray.Dataset
        Snapshots with dimensions (t, x).
    var : str, default "u"
        The variable drawn.
    n : int, default 6
        How many snapshots.
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
        The axes: x against var, in the units the output records.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = {"model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...        "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...        "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...        "run": {"t_end": 20.0}, "output": {"snapshot_every": 1.0}}
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> _ = bk.run(cfg, out)
    >>> ax = bk.plot.profiles(bk.load(out)[0], n=3)
    >>> [line.get_label() for line in ax.lines]
    ['t = 0', 't = 10', 't = 20']
    """
    if ax is None:
        ax = _new_axes((7, 3.8))
    nt = ds.sizes["t"]
    idx = np.unique(np.linspace(0, nt - 1, min(n, nt)).round().astype(int))
    import matplotlib

    colors = matplotlib.colormaps["viridis"](np.linspace(0, 1, len(idx)))
    for c, i in zip(colors, idx, strict=True):
        ax.plot(
            ds.x.values,
            ds[var].values[i],
            color=c,
            lw=1.2,
            label=f"t = {float(ds.t.values[i]):.4g}",
        )
    ax.set_xlabel("x" + _units(ds.x))
    ax.set_ylabel(var + _units(ds[var]))
    ax.legend(fontsize=7, ncols=2)
    ax.set_title(run_title(ds.attrs) + f"\n{var}(x) at {len(idx)} snapshots", fontsize=8)
    return ax


@_styled
def trajectories(
    df, *, x: str = "x", t: str = "t", by: str | None = None, ax=None, points: bool = False
):
    """Front or shock trajectories x(t) from a table, one line per ``by`` group (or
    points, for fronts that spread both ways from their nucleation).

    Parameters
    ----------
    df : pandas.DataFrame
        The table (a run's ``slips``, a free boundary's ``shocks``).
    x : str, default "x"
        Its position column (dimensionless x, or the unit in ``df.attrs["units"]``).
    t : str, default "t"
        Its time column (units of sqrt(m/k_p), or the unit in ``df.attrs["units"]``).
    by : str, optional
        One line per value of this column (e.g. ``shock``).
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).
    points : bool, default False
        Draw points instead of lines.

    Returns
    -------
    matplotlib.axes.Axes
        The axes: x against t.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = {"model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...        "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...        "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...        "run": {"t_end": 20.0}, "output": {"snapshot_every": 1.0}}
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> _ = bk.run(cfg, out)
    >>> slips = bk.io.load_tables(out)[1]["slips"]
    >>> ax = bk.plot.trajectories(slips, x="x", t="t_start", points=True)
    >>> ax.get_xlabel(), ax.get_ylabel(), len(ax.lines[0].get_xdata()) == len(slips)
    ('x', 't_start', True)
    """
    if ax is None:
        ax = _new_axes((7, 4.2))
    import matplotlib

    groups = [(None, df)] if by is None or by not in df else list(df.groupby(by))
    # one colour per group from a sequential map, keyed to the group's order: with more
    # groups than a legend can hold, a colour bar says which is which
    cmap = matplotlib.colormaps["viridis"]
    n = max(len(groups), 1)
    for k, (_, g) in enumerate(groups):
        g = g.sort_values(t)
        color = cmap(k / max(n - 1, 1)) if by is not None else "C0"
        if points:
            ax.plot(g[x].values, g[t].values, ".", ms=1.5, color=color)
        else:
            ax.plot(g[x].values, g[t].values, lw=1.0, color=color)
    if by is not None and len(groups) > 1:
        sm = matplotlib.cm.ScalarMappable(
            cmap=cmap, norm=matplotlib.colors.Normalize(0, len(groups) - 1)
        )
        cb = ax.figure.colorbar(sm, ax=ax)
        cb.set_label(f"{by} (in order of the catalog)", fontsize=8)
    units = df.attrs.get("units", {})
    ax.set_xlabel(x + _unit_suffix(units.get(x)))
    ax.set_ylabel(t + _unit_suffix(units.get(t)))
    ax.set_title("trajectories")
    return ax


#: Fewest events above Mc for a b-value (:data:`bkwaves.stats.MIN_EVENTS`).
MIN_EVENTS_B_VALUE = 50


def _b_title(gr) -> str:
    """A plot title: the b of :func:`bkwaves.stats.gutenberg_richter`, or why there is none."""
    if gr.ok:
        return (
            f"b = {gr.b:.2f} [{gr.lo:.2f}, {gr.hi:.2f}] ({round(100 * gr.confidence)} %), "
            f"Mc = {gr.m_c:.2f}, n = {gr.n}"
            + ("" if gr.fits else f"; not Gutenberg-Richter (KS p = {gr.fit_p:.2g})")
        )
    return f"n = {gr.n_total}: no b-value ({gr.reason.split(':')[0]})"


@_styled
def size_frequency(sizes, ax=None, label: str = "event size"):
    """Size-frequency (complementary cumulative) plot of moments, titled with their b
    (:func:`bkwaves.stats.gutenberg_richter`: moment magnitudes, Mc by maximum curvature,
    a bootstrap interval) or the reason there is none (too few events, one size).

    Parameters
    ----------
    sizes : array_like
        Event moments int slip dx (dimensionless); others than finite and > 0 are left
        out.
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).
    label : str, default "event size"
        The x label.

    Returns
    -------
    matplotlib.axes.Axes
        The axes, log-log.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> mags = np.random.default_rng(0).exponential(math.log10(math.e), 300)   # b = 1
    >>> moments = 10 ** (1.5 * mags)
    >>> bk.plot.size_frequency(moments).get_title()
    'b = 0.91 [0.80, 1.05] (95 %), Mc = 0.20, n = 211'
    """
    from . import stats

    if ax is None:
        ax = _new_axes((5, 4))
    s = np.asarray(sizes, dtype=float)
    s = s[np.isfinite(s) & (s > 0)]
    x, ccdf = stats.size_frequency(s)
    ax.loglog(x, ccdf, ".", ms=4, label="N(>= size) / N")
    ax.set_title(_b_title(stats.gutenberg_richter(s)), fontsize=9)
    ax.set_xlabel(label)
    ax.set_ylabel("fraction of events >= size")
    if s.size and np.log10(s.max() / s.min()) < 2.0:  # (wider: matplotlib labels none)
        _sparse_minor_labels(ax.xaxis)
    return ax


def _sparse_minor_labels(axis) -> None:
    """On a log axis spanning about a decade matplotlib labels the minor ticks 2 to 9
    times a power of ten, and side by side along x they overlap (3 x 10^1, 4 x 10^1):
    label only those at 2 and 5 times a power of ten."""
    from matplotlib.ticker import FuncFormatter

    def label(x, pos=None):
        if not x > 0:
            return ""
        e = int(np.floor(np.log10(x) + 1e-9))
        m = x / 10.0**e
        return (
            rf"${round(m)}\times10^{{{e}}}$"
            if abs(m - round(m)) < 1e-6 and round(m) in (2, 5)
            else ""
        )

    axis.set_minor_formatter(FuncFormatter(label))


@_styled
def frequency_magnitude(moments, ax=None, what: str = "events"):
    """The frequency-magnitude distribution of moments: the number of ``what`` with
    magnitude >= M (M = (2/3) log10(moment)) and per bin of 0.1, the magnitude of
    completeness Mc and the Gutenberg-Richter fit N(>= M) = N(>= Mc) 10^(-b (M - Mc))
    above it (:func:`bkwaves.stats.gutenberg_richter`), or the reason there is no b.

    Parameters
    ----------
    moments : array_like
        Event moments int slip dx (dimensionless).
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure).
    what : str, default "events"
        What is counted, for the labels.

    Returns
    -------
    matplotlib.axes.Axes
        The axes: magnitude (dimensionless) against counts, log scale.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> mags = np.random.default_rng(0).exponential(math.log10(math.e), 300)   # b = 1
    >>> moments = 10 ** (1.5 * mags)
    >>> ax = bk.plot.frequency_magnitude(moments, what="ruptures")
    >>> ax.get_title()
    'b = 0.91 [0.80, 1.05] (95 %), Mc = 0.20, n = 211'
    """
    from . import stats

    if ax is None:
        ax = _new_axes((5, 4))
    mom = np.asarray(moments, dtype=float)
    mom = mom[np.isfinite(mom) & (mom > 0)]
    m = np.sort(stats.moment_magnitude(mom))
    gr = stats.gutenberg_richter(mom)
    if m.size:
        ax.semilogy(m[::-1], np.arange(1, m.size + 1), "-", color="C0", lw=1.2,
                    label=f"{what} with magnitude >= M")  # fmt: skip
        k = np.floor(m / stats.MC_BIN).astype(np.int64)
        ks, counts = np.unique(k, return_counts=True)
        ax.semilogy((ks + 0.5) * stats.MC_BIN, counts, "o", color="C1", ms=3,
                    label=f"{what} per magnitude bin of {stats.MC_BIN}")  # fmt: skip
    if gr.ok:
        mm = np.linspace(gr.m_c, m.max(), 50)
        ax.semilogy(mm, gr.n * 10 ** (-gr.b * (mm - gr.m_c)), "k--", lw=1,
                    label=f"Gutenberg-Richter fit, b = {gr.b:.2f}")  # fmt: skip
        ax.axvline(gr.m_c, color="0.5", ls=":", lw=1, label=f"Mc = {gr.m_c:.2f}")
    ax.set_title(_b_title(gr), fontsize=9)
    ax.set_xlabel("magnitude M = (2/3) log10(moment)")
    ax.set_ylabel(f"number of {what}")
    if m.size:
        ax.legend(fontsize=7)
    return ax


@_styled
def plot_run(out, outdir=None, fmt: str = "png") -> list[Path]:
    """The standard pictures of a run output (see :func:`bkwaves.io.load`): space-time
    diagrams of every field, profiles, trajectories and the catalog's size-frequency.

    A sweep store (``bkwaves sweep``) is drawn by :func:`plot_sweep`.

    Parameters
    ----------
    out : str or pathlib.Path
        The run output (or a sweep store).
    outdir : str or pathlib.Path, optional
        Where the pictures go (default: beside ``out``).
    fmt : {"png", "svg", "pdf"}, default "png"
        Their format.

    Returns
    -------
    list of pathlib.Path
        The files written.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = {"model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...        "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...        "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...        "run": {"t_end": 20.0}, "output": {"snapshot_every": 1.0}}
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> _ = bk.run(cfg, out)
    >>> files = bk.plot.plot_run(out, os.path.join(os.path.dirname(out), "figures"))
    >>> [f.name for f in files]  # doctest: +NORMALIZE_WHITESPACE
    ['front_spacetime_u.png', 'front_spacetime_u_t.png', 'front_spacetime_sliding.png',
     'front_profiles.png', 'front_slips.png']
    """
    from .io import _readable, load_tables

    if fmt not in FORMATS:
        from ._validate import _fail

        _fail("fmt", fmt, " or ".join(repr(f) for f in FORMATS))
    from ._paths import check_writable

    out = Path(out)
    check_writable(outdir if outdir is not None else out.parent, "outdir", directory=True)
    if _is_sweep(out):
        return plot_sweep(out, outdir, fmt)
    ds, tables = load_tables(out)
    ds = _readable(out, ds.load)  # (a damaged chunk: one line, not a codec's traceback)
    outdir = Path(outdir) if outdir is not None else out.parent
    stem = out.name.rsplit(".", 1)[0]
    written = []
    events = tables.get("events")
    if "y" in ds.dims:  # a planar run: maps (bkwaves._plot_plane)
        from ._plot_plane import plot_plane

        written += plot_plane(ds, tables, outdir, stem, fmt, run_title(ds.attrs))
    for var in ds.data_vars:
        if set(ds[var].dims) == {"t", "x"} and ds.sizes["t"] > 1:
            if _constant(ds[var].values):
                continue  # e.g. no block sliding at any snapshot: a blank panel says nothing
            ax = spacetime(ds, var, events=events)
            written.append(save(ax, outdir / f"{stem}_spacetime_{var}.{fmt}"))
    if "u" in ds and "y" not in ds.dims:
        written.append(save(profiles(ds, "u"), outdir / f"{stem}_profiles.{fmt}"))
    for name, df in tables.items():
        if "y" in df.columns:
            continue  # a planar run's tables: its maps above
        if {"x", "t"} <= set(df.columns):
            by = next((c for c in ("front", "shock", "event", "id") if c in df.columns), None)
            ax = trajectories(df, by=by)
            ax.set_title(run_title(ds.attrs) + f"\n{name}: x(t)", fontsize=8)
            written.append(save(ax, outdir / f"{stem}_{name}.{fmt}"))
        elif {"x", "t_start", "block"} <= set(df.columns) and len(df):
            # the chain's slips: the first slip of each block in each event is the slip front
            first = df.sort_values("t_start").groupby(["event", "block"], as_index=False).first()
            ax = trajectories(first, t="t_start", by="event", points=True)
            if "kind" in first:
                noise = first[first["kind"].astype(str) == "noise"]
                if len(noise):
                    ax.plot(
                        noise["x"],
                        noise["t_start"],
                        "*",
                        color="C3",
                        mec="k",
                        mew=0.5,
                        ms=8,
                        ls="none",
                        label="noise-triggered slip",
                    )
                    ax.legend(fontsize=7, loc="upper left")
            ax.set_title(
                run_title(ds.attrs) + "\nslip fronts (first slip of each block, per event)",
                fontsize=8,
            )
            written.append(save(ax, outdir / f"{stem}_{name}.{fmt}"))
    # the catalog statistics use: the ruptures when the run has them, else the events
    what = "ruptures" if "ruptures" in tables else "events"
    cat = tables.get(what)
    if cat is not None and "complete" in cat:
        cat = cat[cat["complete"].to_numpy(dtype=bool)]  # a cut one's slip is partial
    if cat is not None and len(cat) >= 2 and "moment" in cat:
        unit = cat.attrs.get("units", {}).get("moment")
        label = f"moment of {what}" + (f" [{unit}]" if unit else "")
        m = cat["moment"]
        for ax, kind in (
            (size_frequency(m, label=label), "size_frequency"),
            (frequency_magnitude(m, what=what), "frequency_magnitude"),
        ):
            ax.set_title(run_title(ds.attrs) + "\n" + ax.get_title(), fontsize=8)
            written.append(save(ax, outdir / f"{stem}_{kind}.{fmt}"))
    return written


@_styled
def save(ax, path) -> Path:
    """Save the figure of ``ax`` to ``path`` (format from the suffix: one of
    :data:`FORMATS`) and close it. The file is written whole (beside, then renamed).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Any axes of the figure.
    path : str or pathlib.Path
        The file, ending in .png, .svg or .pdf.

    Returns
    -------
    pathlib.Path
        The file written.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> path = bk.plot.save(bk.plot.speed_curve(), os.path.join(tempfile.mkdtemp(), "c.svg"))
    >>> path.read_text().startswith("<?xml")
    True
    """
    import matplotlib.pyplot as plt

    from ._paths import write_atomic

    path = check_path(path)
    fmt = path.suffix.lower().lstrip(".")
    try:
        write_atomic(path, lambda p: ax.figure.savefig(p, format=fmt))
    finally:
        plt.close(ax.figure)
    return path


def check_path(path, name: str = "path") -> Path:
    """``path`` as a Path if its suffix is one of :data:`FORMATS`, else a ParameterError
    naming ``name``."""
    path = Path(path)
    if path.suffix.lower().lstrip(".") not in FORMATS:
        from ._validate import _fail

        _fail(name, str(path), "a file name ending in " + ", ".join("." + f for f in FORMATS))
    return path


_SWEEP_BOOKKEEPING = ("status", "error", "key", "wall_s")
#: Summaries that describe how a point was computed, not what it found: not drawn as
#: results (they stay in the store).
_SWEEP_DIAGNOSTICS = (
    "blocks",
    "passes",
    "steps",
    "slips",
    "backward_slips",
    "steadiness",
    "unsteadiness",
    "settling_length",
    "beta",
)


def _is_sweep(out: Path) -> bool:
    if out.suffix != ".zarr" or not out.is_dir():
        return False
    import zarr

    try:
        g = zarr.open_group(str(out), mode="r", use_consolidated=False)
    except Exception:  # noqa: BLE001 - not a readable group: not a sweep
        return False
    return str(g.attrs.get("bkwaves_sweep", "")).startswith("bkwaves-sweep")


@_styled
def plot_sweep(out, outdir=None, fmt: str = "png") -> list[Path]:
    """The summaries of a sweep store (``bkwaves sweep``) against its axes: one figure per
    numeric summary, the first axis along x, one line per value of the second; an axis
    named ``seed`` is averaged over (mean with its standard error, n realisations in the
    legend). For the front speed c against u_plus, the exact continuum c = 1/sqrt(1 -
    u_+^2) and, per dx, the finite-dx tip solver are drawn with the points, and a second
    panel shows c - 1/sqrt(1 - u_+^2).

    Parameters
    ----------
    out : str or pathlib.Path
        The sweep store (.zarr).
    outdir : str or pathlib.Path, optional
        Where the pictures go (default: beside ``out``).
    fmt : {"png", "svg", "pdf"}, default "png"
        Their format.

    Returns
    -------
    list of pathlib.Path
        The files written.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> out = os.path.join(tempfile.mkdtemp(), "speed.zarr")
    >>> spec = {"task": "speed", "axes": {"u_plus": {"values": [0.3, 0.6, 0.8]}}}
    >>> _ = bk.sweep(spec, out, workers=1)
    >>> [f.name for f in bk.plot.plot_sweep(out)]
    ['speed_c.png']
    """
    import matplotlib.pyplot as plt

    from .sweeps import load_sweep_result

    if fmt not in FORMATS:
        from ._validate import _fail

        _fail("fmt", fmt, " or ".join(repr(f) for f in FORMATS))
    out = Path(out)
    ds = load_sweep_result(out)
    outdir = Path(outdir) if outdir is not None else out.parent
    stem = out.name.rsplit(".", 1)[0]
    done = ds["status"] == 1
    axes = [d for d in ds["status"].dims if d != "point"] or [
        c for c in ds.coords if c != "point" and ds[c].dims == ("point",)
    ]
    written = []
    for var in ds.data_vars:
        if var in _SWEEP_BOOKKEEPING or var in _SWEEP_DIAGNOSTICS or ds[var].dtype.kind != "f":
            continue
        da = ds[var].where(done)
        vals = da.values[np.isfinite(da.values)]
        if vals.size == 0 or np.all(vals == vals[0]):
            continue  # nothing to show (an input echoed back, or no finished point)
        fig, panels = _sweep_figure(ds, var, axes)
        _sweep_panel(panels[0], da, axes, var)
        if var == "c" and "u_plus" in axes:
            _speed_theory(panels, ds, da, axes)
        fig.suptitle(f"{ds.attrs.get('title', 'sweep')}: {var}", fontsize=10)
        written.append(save(panels[0], outdir / f"{stem}_{var}.{fmt}"))
        plt.close(fig)
    return written


#: Mathtext for the names a sweep's axes and summaries usually carry.
_MATH = {
    "u_plus": r"$u_+$",
    "u_minus": r"$u_-$",
    "c": r"$c$",
    "w": r"$w$",
    "gamma": r"$\gamma$",
    "dx": r"$\Delta x$",
    "v": r"$v$",
    "v_f": r"$v_f$",
    "beta": r"$\beta$",
    "A": r"$A$",
}


def _label(name) -> str:
    return _MATH.get(str(name), str(name))


def _sweep_figure(ds, var, axes):
    import matplotlib.pyplot as plt

    two = var == "c" and "u_plus" in axes
    fig, panels = plt.subplots(
        1, 2 if two else 1, figsize=(9.5 if two else 5.5, 3.8), layout="constrained"
    )
    return fig, np.atleast_1d(panels)


def _sweep_panel(ax, da, axes, var):
    """Lines of ``da`` against its first axis (mean and standard error over seeds)."""
    if "point" in da.dims:  # zip or adaptive: points along the first axis coordinate
        x = da[axes[0]].values
        order = np.argsort(x)
        ax.plot(x[order], da.values[order], "o-", ms=3, label="measured")
        ax.set_xlabel(_label(axes[0]))
        ax.set_ylabel(_label(var))
        return
    seed = "seed" if "seed" in da.dims else None
    if seed:
        n = da.count(seed)
        mean = da.mean(seed)
        sem = da.std(seed, ddof=1) / np.sqrt(n.where(n > 1))
    else:
        mean, sem = da, None
    dims = [d for d in mean.dims]
    x = dims[0]
    other = dims[1] if len(dims) > 1 else None
    rest = dims[2:]
    if rest:  # more axes than a panel shows: the first value of each
        mean = mean.isel({d: 0 for d in rest})
        sem = sem.isel({d: 0 for d in rest}) if sem is not None else None
    lines = mean[other].values if other else [None]
    for v in lines:
        m = mean.sel({other: v}) if other else mean
        label = f"{_label(other)} = {v:g}" if other else "measured"
        if sem is not None:
            s = sem.sel({other: v}) if other else sem
            label = (label + ", " if label else "") + f"mean of {int(n.max())} seeds"
            ax.errorbar(
                m[x].values, m.values, yerr=s.values, fmt="o-", ms=3, capsize=2, label=label
            )
        else:
            ax.plot(m[x].values, m.values, "o", ms=4, label=label)
    ax.set_xlabel(_label(x))
    ax.set_ylabel(_label(var))
    ax.legend(fontsize=8)
    if rest:
        ax.set_title(", ".join(f"{d} = {mean[d].values!s}" for d in rest), fontsize=8)


def _speed_theory(panels, ds, da, axes):
    """c(u_+): the exact continuum curve, and per dx the finite-dx tip solver."""
    from .waves import front_speed, tip_solve

    u = ds["u_plus"].values
    uu = np.linspace(u.min(), u.max(), 200)
    panels[0].plot(
        uu, front_speed(uu), "k-", lw=1, label=r"$1/\sqrt{1 - u_+^2}$ (exact, $\Delta x \to 0$)"
    )
    panels[0].legend(fontsize=8)
    ax = panels[1]
    gamma = float(ds["gamma"].values.ravel()[0]) if "gamma" in ds else _base(ds, "gamma", 0.0)
    on_axis = "dx" in axes and "point" not in da.dims
    if on_axis:
        dxs = ds["dx"].values
    else:  # one dx for every point: the sweep's [base] (or a coordinate of the points)
        base_dx = _base(ds, "dx", None)
        dxs = [base_dx] if base_dx is not None and "point" not in da.dims else []
    for k, dx in enumerate(dxs):
        color = f"C{k}"
        pts = da.sel(dx=dx) if on_axis else da
        if pts.ndim > 1:  # other axes (seeds, gamma): their first value, as the left panel
            pts = pts.isel({d: 0 for d in pts.dims if d != "u_plus"})
        ax.plot(
            u,
            pts.values - front_speed(u),
            "o",
            color=color,
            ms=4,
            label=rf"chain, $\Delta x$ = {dx:g}",
        )
        tip = []
        for x in uu:
            try:
                tip.append(tip_solve(float(x), dx=float(dx), gamma=gamma)["c"] - front_speed(x))
            except Exception:  # noqa: BLE001 - outside its range or the chain domain: a gap
                tip.append(np.nan)
        ax.plot(uu, tip, "-", color=color, lw=1, label=rf"tip solver, $\Delta x$ = {dx:g}")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel(_label("u_plus"))
    ax.set_ylabel(r"$c - 1/\sqrt{1 - u_+^2}$")
    if len(dxs):
        ax.legend(fontsize=8)


def _base(ds, key, default):
    import json

    try:
        value = json.loads(ds.attrs["sweep"])["base"].get(key, default)
        return default if value is None else float(value)
    except (KeyError, ValueError, TypeError):
        return default
