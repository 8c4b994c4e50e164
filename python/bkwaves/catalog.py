"""The catalog columns every route gives (``Chain.run().catalog``,
``FreeBoundary.run().events``, ``bk.run``, ``bkwaves run``, ``bk.load``): one definition,
name and unit each, written into the tables' attributes (``df.attrs["descriptions"]``,
``df.attrs["units"]``, and ``df.attrs["scales"]`` for dimensionless columns).

The moment of a one-dimensional event is the slip integrated along the chain,

    moment = int slip dx,

in the run's units: dimensionless (the paper's x' and slips in (f_r - f_s)/k_p; the
chain's blocks are dx apart, so its moment is dx times the sum of its block slips, and
the free boundary's is int A dx over the ground its shocks swept: the two agree as
dx -> 0), or m^2 in SI (slip in m times length in m: the potency per unit width of the
fault, whose product with the shear modulus and the width is the seismic moment). It
does not depend on dx at a fixed physical event, unlike a sum of block slips.

The ``ruptures`` table (:func:`run_ruptures`) splits the events, which merge ruptures
that overlap in time (with noise, a ring is one event that never ends), into ruptures:
the slip a single nucleation causes (docs/usage.md "Ruptures").
"""

from __future__ import annotations

import numpy as np

from .stats import FIT_P_MIN, MAGNITUDE_DEFINITION, moment_magnitude

__all__ = [
    "MOMENT_DEFINITION",
    "MOMENT_SCALE",
    "DESCRIPTIONS",
    "RUPTURE_COLUMNS",
    "describe",
    "run_ruptures",
    "statistics",
    "summary_scalars",
]

#: What the ``moment`` column of every catalog is (its description in the tables' attrs).
MOMENT_DEFINITION = (
    "int slip dx: the slip integrated along the chain (chain: dx times the sum of its "
    "block slips; free boundary: int A dx over the swept ground)"
)
#: How the dimensionless moment is scaled (its unit is "1").
MOMENT_SCALE = "slip (f_r - f_s)/k_p times length a sqrt(k_c/k_p) (paper eq. dimless)"
#: The moment's unit in SI outputs: m (slip) times m (length), the potency per unit width.
MOMENT_SI = "m2"

#: Definitions of the columns shared by the catalogs of both engines and the ruptures.
DESCRIPTIONS = {
    "moment": MOMENT_DEFINITION,
    "magnitude": MAGNITUDE_DEFINITION,
    "t_start": "nucleation time: start of the first slip",
    "t_end": "end of the last slip (not finite: still slipping when the run stopped)",
    "duration": "t_end - t_start",
    "x_start": "nucleation place",
    "swept": "extent: length of chain that slipped (chain: blocks times dx; free "
    "boundary: grid nodes reset times the grid spacing)",
    "kind": "what started it: threshold (u - u_xx reached the static threshold), noise "
    "(a spontaneous slip), trigger (a configured kick or release), initial (sliding in "
    "the initial state: a chain block moving at t = 0, a shock given at the start)",
    "spontaneous": "started by noise",
    "u_start": "stress u where it started",
    "event": "the event (catalog row) it belongs to",
    "complete": "it ended before the run stopped",
}

#: The columns of the ruptures table of a run, in order.
RUPTURE_COLUMNS = (
    "t_start",
    "t_end",
    "duration",
    "x_start",
    "swept",
    "moment",
    "magnitude",
    "kind",
    "spontaneous",
    "u_start",
    "event",
    "complete",
)


def describe(df, units: dict | None = None, scales: dict | None = None):
    """Set ``df.attrs``: the definitions of its columns, and their units and scales.

    Parameters
    ----------
    df : pandas.DataFrame
        A catalog table; its columns found in ``DESCRIPTIONS`` get their definition.
    units : dict, optional
        Column -> unit (e.g. ``"1"`` for the paper's dimensionless units, ``"s"``).
    scales : dict, optional
        Column -> factor from the dimensionless value to the unit.

    Returns
    -------
    pandas.DataFrame
        ``df`` itself, its ``attrs`` set.

    Examples
    --------
    >>> import pandas as pd
    >>> import bkwaves as bk
    >>> df = bk.catalog.describe(pd.DataFrame({"t_start": [0.0]}), units={"t_start": "1"})
    >>> df.attrs["descriptions"]["t_start"], df.attrs["units"]
    ('nucleation time: start of the first slip', {'t_start': '1'})
    """
    df.attrs["descriptions"] = {c: DESCRIPTIONS[c] for c in df.columns if c in DESCRIPTIONS}
    if units is not None:
        df.attrs["units"] = dict(units)
    if scales is not None:
        df.attrs["scales"] = dict(scales)
    return df


def _fb_kind(kind: str) -> str:
    return {"birth": "threshold", "nucleation": "noise"}.get(kind, kind)


def run_ruptures(engine: str, table, *, n: int, dx: float, boundary: str, x0: float = 0.0):
    """The ruptures table of a run (:data:`RUPTURE_COLUMNS`), dimensionless, from the
    engine's whole record: the chain's slips (``table``: the engine's slip columns and
    ``x``; ``n`` blocks dx apart) or the free boundary's shock paths (``table``, every node
    crossing recorded; ``n`` grid nodes ``dx`` apart from ``x0``: here ``dx`` is the grid
    spacing h). Built by :func:`bkwaves.noise_stats.chain_ruptures` /
    :func:`bkwaves.noise_stats.ruptures`, which define the rupture.

    Parameters
    ----------
    engine : {"chain", "free_boundary"}
        Which engine's record ``table`` is.
    table : pandas.DataFrame
        The chain's slips (with ``x``) or the free boundary's shock paths.
    n : int
        Blocks of the chain, or grid nodes.
    dx : float
        The chain's lattice spacing, or the grid spacing h (dimensionless).
    boundary : {"free", "fixed", "periodic"}
        The run's boundary.
    x0 : float, default 0
        Position of the first grid node (dimensionless x).

    Returns
    -------
    pandas.DataFrame
        One row per rupture, the columns of :data:`RUPTURE_COLUMNS` in the paper's
        dimensionless units (times in sqrt(m/k_p), positions in x, moment int slip dx).

    Examples
    --------
    Two pairs in one catalog event are two ruptures; their moments add up to the event's:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=0.0, dx=0.05)
    >>> ring = bk.Chain(400, p, "periodic", np.full(400, 0.93))
    >>> res = ring.kick(0, -0.5, 0.0).kick(200, -0.5, 0.5).run(t_end=100.0)  # two pairs
    >>> rup = bk.catalog.run_ruptures("chain", res.slips, n=400, dx=0.05, boundary="periodic")
    >>> len(res.catalog), len(rup), bool(np.isclose(rup.moment.sum(), res.catalog.moment.sum()))
    (1, 2, True)
    """
    import pandas as pd

    from . import noise_stats as ns

    if engine == "chain":
        r = ns._chain_ruptures(table, n, dx, boundary)
        kind = r.pop("kind")
        out = pd.DataFrame(
            {
                "t_start": r.t_start,
                "t_end": r.t_end,
                "x_start": r.x_start,
                "swept": r.swept,
                "moment": r.moment,
                "kind": kind,
                "spontaneous": r.spontaneous,
                "u_start": r.u_start,
                "event": r.event,
            }
        )
        out["complete"] = np.isfinite(out.t_end.to_numpy(dtype=float))
    else:
        r = ns._fb_ruptures(table, h=dx, x0=x0, nodes=n, periodic=boundary == "periodic")
        out = pd.DataFrame(
            {
                "t_start": r.t_start,
                "t_end": r.t_end,
                "x_start": r.x_start,
                "swept": r.swept,
                "moment": r.moment,
                "kind": [_fb_kind(k) for k in r.kind],
                "spontaneous": r.spontaneous,
                "u_start": r.u_start,
                "event": r.event,
                "complete": r.complete,
            }
        )
        out.loc[~out.complete.to_numpy(dtype=bool), "t_end"] = np.nan
    out.insert(2, "duration", out.t_end - out.t_start)
    out.insert(out.columns.get_loc("moment") + 1, "magnitude", moment_magnitude(out.moment))
    out = out.sort_values("t_start", kind="stable").reset_index(drop=True)
    return out[list(RUPTURE_COLUMNS)]


#: The columns of the largest rupture (or event) that :func:`statistics` reports (those
#: a catalog has: the planar models' hypocentre y, area and perimeter besides).
_LARGEST = (
    "t_start",
    "duration",
    "x_start",
    "y_start",
    "swept",
    "area",
    "perimeter",
    "moment",
    "kind",
    "n_blocks",
)


def _complete_rows(df):
    """The rows of ``df`` that ended before the run stopped (a cut one's slip is partial)."""
    if df is None:
        return None
    if "complete" in df:
        return df[df["complete"].to_numpy(dtype=bool)]
    return df


def statistics(events, ruptures=None) -> dict:
    """What a catalog shows, as every route reports it (the run summary, ``bkwaves
    stats``, ``bkwaves plot``): over the complete ``ruptures`` when given (events merge
    the ruptures that overlap in time), else over the complete events. Keys: ``catalog``
    (which one), ``n_events``, ``n_ruptures`` (None without ruptures), ``n`` (rows of the
    catalog used, complete), ``max_moment``, ``magnitude_min`` / ``magnitude_max``,
    ``largest`` (the row of the largest moment, as a dict), ``mean_interval`` and
    ``interval_cv`` (times between successive starts), and ``b`` (the
    :class:`bkwaves.stats.GutenbergRichter` of the moments).

    Parameters
    ----------
    events : pandas.DataFrame or None
        The events catalog (columns ``t_start``, ``moment``, ...; dimensionless).
    ruptures : pandas.DataFrame, optional
        The ruptures table (:func:`run_ruptures`).

    Returns
    -------
    dict
        The keys above; ``max_moment`` dimensionless (int slip dx), magnitudes
        dimensionless, ``mean_interval`` in units of sqrt(m/k_p).

    Examples
    --------
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=0.0, dx=0.05)
    >>> ring = bk.Chain(400, p, "periodic", np.full(400, 0.93))
    >>> res = ring.kick(0, -0.5, 0.0).kick(200, -0.5, 0.5).run(t_end=100.0)  # two pairs
    >>> rup = bk.catalog.run_ruptures("chain", res.slips, n=400, dx=0.05, boundary="periodic")
    >>> st = bk.catalog.statistics(res.catalog, rup)
    >>> st["catalog"], st["n_events"], st["n_ruptures"], st["mean_interval"], st["b"].ok
    ('ruptures', 1, 2, 0.5, False)
    """
    import math

    from .stats import gutenberg_richter

    ev = _complete_rows(events)
    ru = _complete_rows(ruptures)
    cat = ru if ru is not None else ev
    out = {
        "catalog": "ruptures" if ru is not None else "events",
        "n_events": 0 if ev is None else len(ev),
        "n_ruptures": None if ru is None else len(ru),
        "n": 0 if cat is None else len(cat),
        "max_moment": math.nan,
        "magnitude_min": math.nan,
        "magnitude_max": math.nan,
        "largest": None,
        "mean_interval": math.nan,
        "interval_cv": math.nan,
        "b": gutenberg_richter(np.array([])),
    }
    if cat is None or not len(cat):
        return out
    if "moment" in cat:
        m = cat["moment"].to_numpy(dtype=float)
        ok = np.isfinite(m) & (m > 0)
        if ok.any():
            mags = moment_magnitude(m[ok])
            out["max_moment"] = float(m[ok].max())
            out["magnitude_min"] = float(mags.min())
            out["magnitude_max"] = float(mags.max())
            row = cat.iloc[int(np.flatnonzero(ok)[np.argmax(m[ok])])]
            out["largest"] = {
                k: (v.item() if hasattr(v, "item") else v) for k, v in row.items() if k in _LARGEST
            }
            out["largest"]["magnitude"] = float(moment_magnitude(row["moment"]))
        out["b"] = gutenberg_richter(m[ok])
    if "t_start" in cat and len(cat) >= 2:
        dt = np.diff(np.sort(cat["t_start"].to_numpy(dtype=float)))
        out["mean_interval"] = float(dt.mean())
        if dt.mean() > 0:
            out["interval_cv"] = float(dt.std() / dt.mean())
    return out


def summary_scalars(stats: dict) -> dict:
    """The scalars of :func:`statistics` that a run summary holds (``bk.run``'s
    ``summary``, sweep outputs): counts, the largest moment, magnitudes, recurrence and
    the b-value with its interval and Mc, or ``b_value_note`` saying why there is none.

    Parameters
    ----------
    stats : dict
        What :func:`statistics` returns.

    Returns
    -------
    dict
        Name -> number (NaN where undefined; units as in :func:`statistics`), and the
        strings ``statistics_catalog`` and ``b_value_note``.

    Examples
    --------
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=0.0, dx=0.05)
    >>> ring = bk.Chain(400, p, "periodic", np.full(400, 0.93))
    >>> res = ring.kick(0, -0.5, 0.0).kick(200, -0.5, 0.5).run(t_end=100.0)  # two pairs
    >>> s = bk.catalog.summary_scalars(bk.catalog.statistics(res.catalog))
    >>> s["n_events"], s["b_value_note"][:20]                 # one event: one size
    (1.0, 'degenerate catalog: ')
    """
    import math

    b = stats["b"]
    return {
        "statistics_catalog": stats["catalog"],
        "n_events": float(stats["n_events"]),
        "n_ruptures": math.nan if stats["n_ruptures"] is None else float(stats["n_ruptures"]),
        "max_moment": stats["max_moment"],
        "magnitude_min": stats["magnitude_min"],
        "magnitude_max": stats["magnitude_max"],
        "mean_interval": stats["mean_interval"],
        "interval_cv": stats["interval_cv"],
        "b_value": b.b,
        "b_value_lo": b.lo,
        "b_value_hi": b.hi,
        "m_c": b.m_c,
        "b_value_fit_p": b.fit_p,
        "b_value_note": b.reason or "",
    }


def _finite(x):
    import math

    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def report(out) -> dict:
    """What a run output holds and shows (``bkwaves stats OUT``): the model, units,
    parameters and seed, the time reached, the counts of events and ruptures, the magnitude
    range, the b-value with its interval and Mc (or why there is none), the recurrence
    (mean and CV of the times between successive starts) and the largest one, over the
    ruptures when the output has them (:func:`statistics`). JSON-ready (NaN -> None)."""
    import json
    from pathlib import Path

    from .io import load_tables
    from .plot import _is_sweep

    if _is_sweep(Path(out)):
        from ._validate import _fail

        _fail("OUT", str(out), "a run output (.nc or .zarr of bkwaves run), not a sweep store")
    ds, tables = load_tables(out)
    events, ruptures = tables.get("events"), tables.get("ruptures")
    st = statistics(events, ruptures)
    cat = ruptures if ruptures is not None else events
    attrs = ds.attrs
    try:
        params = json.loads(attrs.get("params", "{}"))
    except (TypeError, ValueError):
        params = {}
    units = (cat.attrs.get("units", {}) if cat is not None else {}).get("moment")
    b = st["b"]
    t = ds["t"].values if "t" in ds.coords else np.array([])
    return {
        "out": str(out),
        "model": attrs.get("model"),
        "units": attrs.get("units_system"),
        "params": params,
        "seed": attrs.get("seed"),
        "t_end": _finite(float(t.max())) if t.size else None,
        "catalog": st["catalog"],
        "events": st["n_events"],
        "events_running": 0 if events is None else len(events) - st["n_events"],
        "ruptures": st["n_ruptures"],
        "moment": {
            "units": units,
            # (the catalog's own: a planar model's is int slip dA)
            "definition": (cat.attrs.get("descriptions", {}) if cat is not None else {}).get(
                "moment", MOMENT_DEFINITION
            ),
        },
        "magnitude": {
            "min": _finite(st["magnitude_min"]),
            "max": _finite(st["magnitude_max"]),
            "definition": MAGNITUDE_DEFINITION,
        },
        "b": {
            "value": _finite(b.b),
            "lo": _finite(b.lo),
            "hi": _finite(b.hi),
            "confidence": b.confidence,
            "m_c": _finite(b.m_c),
            "n": b.n,
            "fit_p": _finite(b.fit_p),
            "reason": b.reason,
            "method": b.method,
        },
        "recurrence": {"mean": _finite(st["mean_interval"]), "cv": _finite(st["interval_cv"])},
        "largest": st["largest"],
    }


def report_text(rep: dict) -> str:
    """:func:`report` as lines of text."""

    def g(x):
        return "n/a" if x is None else f"{x:.4g}"

    p = ", ".join(f"{k} = {v}" for k, v in rep["params"].items() if not isinstance(v, dict))
    what = rep["catalog"]
    lines = [
        f"{rep['out']}: {rep['model']} run, {rep['units']}, t up to {g(rep['t_end'])}, "
        f"seed {rep['seed'] if rep['seed'] not in ('', None) else 'none'}",
        f"parameters: {p}",
        f"events: {rep['events']} complete"
        + (f" (+{rep['events_running']} cut by the end)" if rep["events_running"] else "")
        + (f"; ruptures: {rep['ruptures']} complete" if rep["ruptures"] is not None else ""),
        f"statistics over the {what}; moment = {rep['moment']['definition']}"
        + (f" [{rep['moment']['units']}]" if rep["moment"]["units"] else ""),
        f"magnitudes M = (2/3) log10(moment): {g(rep['magnitude']['min'])} to "
        f"{g(rep['magnitude']['max'])}",
    ]
    b = rep["b"]
    if b["value"] is None:
        lines.append(f"b-value: none: {b['reason']}")
    else:
        lines.append(
            f"b-value: {b['value']:.3f}, {round(100 * b['confidence'])} % interval "
            f"[{b['lo']:.3f}, {b['hi']:.3f}] (bootstrap), Mc = {b['m_c']:.2f} (maximum "
            f"curvature + 0.2), {b['n']} {what} above Mc"
        )
        if b["fit_p"] is not None and b["fit_p"] < FIT_P_MIN:
            lines.append(
                f"  not a Gutenberg-Richter law above Mc (Kolmogorov-Smirnov p = "
                f"{b['fit_p']:.2g}): b summarises the catalog, it is no power-law exponent"
            )
    r = rep["recurrence"]
    lines.append(f"recurrence (between successive starts): mean {g(r['mean'])}, CV {g(r['cv'])}")
    big = rep["largest"]
    if big:
        lines.append("largest: " + ", ".join(f"{k} = {v:.6g}" if isinstance(v, float) else
                                            f"{k} = {v}" for k, v in big.items()))  # fmt: skip
    return "\n".join(lines)
