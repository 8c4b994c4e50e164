"""Pictures of a planar run (`bkwaves plot` on an output with dims (t, y, x)): the slip
map, the arrival-time contours of the largest rupture, the catalog on a map and the
stress at the last snapshot (the frequency-magnitude plot is ``bkwaves.plot``'s).

The tables they read: a lattice's slips (i, j, slip), ruptures (id, x_start, y_start,
area: its catalog map and its arrival map) and arrivals (rupture, x, y, t) when written
(without them: the largest event's arrivals, from the slips and events); a planar free
boundary run's ruptures (id, x_start, y_start, area) and arrivals (rupture, x, y, t),
and its snapshots (the slip of a rupture is u_+ - u_-: the stress dropped under the
loading, u(0) + v t - u(t)).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

#: the catalog map's marker areas (pt^2): the largest rupture's, and the least
MAX_MARKER, MIN_MARKER = 200.0, 6.0
#: a map is drawn to scale when its height over its width lies within 1/MAX_ASPECT and
#: MAX_ASPECT
MAX_ASPECT = 6.0


def _unit(df, col) -> str:
    u = str((df.attrs.get("units", {}) if df is not None else {}).get(col, "") or "")
    return f" [{u}]" if u and u != "1" else ""


def _coord_unit(ds) -> str:
    u = str(ds["x"].attrs.get("units", "") or "")
    return f" [{u}]" if u and u != "1" else ""


def _map_axes(ds, figsize=(6.0, 4.6)):
    import matplotlib.pyplot as plt

    from .plot import _edges

    fig, ax = plt.subplots(figsize=figsize, layout="constrained")
    ax.set_xlabel("x (along the slip)" + _coord_unit(ds))
    wide, tall = (float(np.ptp(_edges(ds[c].values))) for c in ("x", "y"))
    if 1 / MAX_ASPECT <= tall / wide <= MAX_ASPECT:
        ax.set_aspect("equal")
        ax.set_ylabel("y (across)" + _coord_unit(ds))
    else:  # to scale, a plane of dy = 1e3 dx would be a line: y stretched, and said so
        ax.set_ylabel("y (across; not to the scale of x)" + _coord_unit(ds))
    # few ticks: a map of a few blocks is small and its labels long (-0.025, 0.075)
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(MaxNLocator(nbins=5))
    return fig, ax


def _grid_of(ds, df, value, fill=np.nan) -> np.ndarray:
    """The column ``value`` of rows (x, y) of ``df`` on the grid of ``ds`` (ny, nx)."""
    x, y = ds["x"].values, ds["y"].values
    out = np.full((len(y), len(x)), fill, dtype=float)
    i = np.clip(
        np.searchsorted(x, df["x"].to_numpy(dtype=float) - 1e-9 * max(1.0, np.ptp(x))),
        0,
        len(x) - 1,
    )
    j = np.clip(
        np.searchsorted(y, df["y"].to_numpy(dtype=float) - 1e-9 * max(1.0, np.ptp(y))),
        0,
        len(y) - 1,
    )
    out[j, i] = df[value].to_numpy(dtype=float)
    return out


def _slip(ds, tables):
    """(slip (ny, nx), units): the lattice's total finished slip per block, or the free
    boundary's stress dropped over the run, u(0) + v (t - t_0) - u(t)."""
    sl = tables.get("slips")
    if sl is not None and {"x", "y", "slip"} <= set(sl.columns):
        done = sl[np.isfinite(sl["slip"].to_numpy(dtype=float))]
        total = done.groupby(["x", "y"], as_index=False)["slip"].sum()
        return _grid_of(ds, total, "slip", 0.0), _unit(sl, "slip")
    if "u" not in ds or ds.sizes["t"] < 2:
        return None, ""
    try:
        v = float(json.loads(ds.attrs.get("params", "{}")).get("v", 0.0))
    except (TypeError, ValueError):
        v = 0.0
    t = ds["t"].values
    if str(ds["t"].attrs.get("units", "1")) not in ("1", ""):
        return None, ""  # (SI times: v is dimensionless; left out)
    u0, u1 = ds["u"].isel(t=0).values, ds["u"].isel(t=-1).values
    return u0 + v * (t[-1] - t[0]) - u1, " (stress dropped, (f_r - f_s)/k_p)"


def slip_map(ds, tables, title: str):
    slip, unit = _slip(ds, tables)
    if slip is None or not np.nan_to_num(slip).any():
        return None  # no slip ended: a blank map under a made-up colour scale says nothing
    fig, ax = _map_axes(ds)
    x, y = ds["x"].values, ds["y"].values
    from .plot import _edges

    mesh = ax.pcolormesh(_edges(x), _edges(y), slip, cmap="viridis", shading="flat")
    cb = fig.colorbar(mesh, ax=ax)
    cb.set_label("slip over the run" + unit)
    ax.set_title(title + "\nslip map", fontsize=8)
    return ax


def _largest(cat):
    """The catalog row of largest moment among the complete ones (a ``complete`` column:
    ruptures that ended before the run stopped), or among all rows when none is complete or the
    catalog has no such column; None without a finite moment."""
    if cat is None or not len(cat) or "moment" not in cat:
        return None
    ok = cat["complete"].to_numpy(dtype=bool) if "complete" in cat else np.ones(len(cat), bool)
    pick = cat[ok] if ok.any() else cat
    m = pick["moment"].to_numpy(dtype=float)
    if not np.isfinite(m).any():
        return None
    return pick.iloc[int(np.nanargmax(m))]


def arrival_map(ds, tables, title: str):
    """Arrival (first slip) times of the largest complete rupture (the largest of all when
    none is complete): each block coloured by the band of its arrival time, the contour
    lines labelled, its hypocentre marked. From the arrivals table when it has a rupture
    column (the free boundary model's; a lattice's written with ``arrivals = true``);
    else the largest event's, from the arrivals or the slips per event (a lattice run
    without its arrivals table, or one written before they were per rupture)."""
    ru = tables.get("ruptures")
    arr = tables.get("arrivals")
    per_rupture = ru is not None and "id" in ru and arr is not None and "rupture" in arr
    what = "ruptures" if per_rupture else "events"
    cat = tables.get(what)
    row = _largest(cat)
    if row is None:
        return None
    key = "id" if what == "ruptures" else "event"
    if arr is not None and len(arr):
        col = "rupture" if "rupture" in arr else "event"
        one = arr[arr[col] == row[key]]
        t_unit = _unit(arr, "t")
    else:
        sl = tables.get("slips")
        if sl is None or not {"x", "y", "t_start"} <= set(sl.columns):
            return None
        one = sl[sl["event"] == row[key]].groupby(["x", "y"], as_index=False)["t_start"].min()
        one = one.rename(columns={"t_start": "t"})
        t_unit = _unit(sl, "t_start")
    if len(one) < 4:
        return None
    grid = _grid_of(ds, one, "t")
    fig, ax = _map_axes(ds)
    x, y = ds["x"].values, ds["y"].values
    levels = np.linspace(np.nanmin(grid), np.nanmax(grid), 12)
    if not levels[-1] > levels[0]:
        return None
    # every block that slipped, coloured by its arrival in the contours' bands (filled
    # contours drew nothing where the blocks that slipped form a line: one row of a
    # lattice of weak springs across, or a lattice of one row or column)
    from matplotlib.colors import BoundaryNorm

    from .plot import _edges

    ex, ey = _edges(x), _edges(y)
    norm = BoundaryNorm(levels, 256)
    filled = ax.pcolormesh(
        ex, ey, np.ma.masked_invalid(grid), cmap="magma_r", norm=norm, shading="flat"
    )
    if min(grid.shape) >= 2 and np.isfinite(grid).sum() >= 4:
        lines = ax.contour(
            x, y, np.ma.masked_invalid(grid), levels=levels[1:-1:2], colors="k", linewidths=0.6
        )
        ax.clabel(lines, fontsize=6, fmt="%.3g")
    cb = fig.colorbar(filled, ax=ax)
    cb.set_label("arrival time" + t_unit)
    hx, hy = _hypocentre(row)
    if hx is not None:
        # (not clipped: a rupture kicked on an edge block has its star on the frame)
        ax.plot(
            [hx],
            [hy],
            "*",
            color="C0",
            mec="w",
            ms=11,
            ls="none",
            label="hypocentre",
            clip_on=False,
            zorder=5,
        )
        ax.legend(fontsize=7, loc=_far_corner(hx, hy, x, y))
    ax.set_xlim(ex[0], ex[-1])
    ax.set_ylim(ey[0], ey[-1])
    name = "rupture" if what == "ruptures" else "event"
    ax.set_title(
        title + f"\narrival times of the largest {name} ({name} {int(row[key])})", fontsize=8
    )
    return ax


def _far_corner(hx: float, hy: float, x, y) -> str:
    """The legend's corner farthest from the hypocentre (hx, hy) on the grid (x, y): a
    legend in a fixed corner hid the star of a rupture that started there."""
    fx = (hx - x[0]) / (x[-1] - x[0]) if x[-1] > x[0] else 0.5
    fy = (hy - y[0]) / (y[-1] - y[0]) if y[-1] > y[0] else 0.5
    return ("lower" if fy > 0.5 else "upper") + (" left" if fx > 0.5 else " right")


def _hypocentre(row):
    for a, b in (("hypocentre_x", "hypocentre_y"), ("x_start", "y_start")):
        if a in row and b in row:
            return float(row[a]), float(row[b])
    return None, None


def catalog_map(ds, tables, title: str):
    """The catalog on a map: each event's (rupture's) hypocentre, a marker of area
    proportional to its slipped area (at least ``MIN_MARKER`` pt^2) and its start time as
    the colour (one colour and the time in the title when all start at once)."""
    what = "ruptures" if "ruptures" in tables else "events"
    cat = tables.get(what)
    if cat is None or not len(cat):
        return None
    xs = "hypocentre_x" if "hypocentre_x" in cat else "x_start"
    ys = "hypocentre_y" if "hypocentre_y" in cat else "y_start"
    if xs not in cat or ys not in cat:
        return None
    fig, ax = _map_axes(ds)
    x, y = ds["x"].values, ds["y"].values
    area = cat["area"].to_numpy(dtype=float) if "area" in cat else np.ones(len(cat))
    big = np.nanmax(area) if np.isfinite(area).any() and np.nanmax(area) > 0 else 1.0
    size = np.maximum(MAX_MARKER * np.nan_to_num(area) / big, MIN_MARKER)
    t0 = cat["t_start"].to_numpy(dtype=float)
    once = np.isfinite(t0).any() and np.nanmin(t0) == np.nanmax(t0)
    colour = {"color": "C0"} if once else {"c": t0, "cmap": "viridis"}
    sc = ax.scatter(cat[xs], cat[ys], s=size, edgecolors="k", linewidths=0.4, **colour)
    when = ""
    if once:  # a colour bar of one value spans made-up times around it (t < 0 for t = 0)
        when = f", all starting at t = {np.nanmin(t0):.4g}" + _unit(cat, "t_start")
    else:
        cb = fig.colorbar(sc, ax=ax)
        cb.set_label("start time" + _unit(cat, "t_start"))
    ax.set_xlim(*_pad(x))
    ax.set_ylim(*_pad(y))
    ax.set_title(
        title + f"\n{len(cat)} {what[:-1] if len(cat) == 1 else what}: hypocentres, marker "
        f"area ~ slipped area{when}",
        fontsize=8,
    )
    return ax


def _pad(c):
    c = np.asarray(c, dtype=float)
    h = (c[1] - c[0]) if c.size > 1 else 0.5
    return c[0] - h, c[-1] + h


def stress_map(ds, title: str):
    if "u" not in ds:
        return None
    fig, ax = _map_axes(ds)
    from .plot import _edges

    u = ds["u"].isel(t=-1).values
    mesh = ax.pcolormesh(
        _edges(ds["x"].values), _edges(ds["y"].values), u, cmap="RdBu_r", shading="flat"
    )
    cb = fig.colorbar(mesh, ax=ax)
    cb.set_label("stress u (1: static threshold)")
    t = float(ds["t"].values[-1])
    ax.set_title(title + f"\nstress at the last snapshot, t = {t:.4g}", fontsize=8)
    return ax


def plot_plane(ds, tables, outdir: Path, stem: str, fmt: str, title: str) -> list[Path]:
    """The pictures of a planar run (module docs), saved as ``{stem}_{kind}.{fmt}``."""
    from .plot import save

    written = []
    for kind, ax in (
        ("slip_map", slip_map(ds, tables, title)),
        ("arrivals", arrival_map(ds, tables, title)),
        ("catalog_map", catalog_map(ds, tables, title)),
        ("stress", stress_map(ds, title)),
    ):
        if ax is not None:
            written.append(save(ax, outdir / f"{stem}_{kind}.{fmt}"))
    return written
