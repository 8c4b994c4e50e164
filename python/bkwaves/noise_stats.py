"""What noise does to the wave statistics (issue 14), with the free boundary engine.

With noise, ruptures overlap in time and the engine's catalog (an event lasts while any
shock lives) merges them: in the noise-dominated regime a whole run is one event. The
statistics here are therefore per *rupture*: the shocks born together (a pair, at u = 1 or
by noise, or one shock at a free end) and the ground they sweep until each of them ends
(annihilation, exit, death). :func:`ruptures` builds that catalog from the shock paths
(``record_path=True``), :func:`point_recurrence` the times between successive ruptures of
the same point, and :func:`statistics_vs_strength` runs a ring at several noise rates
and summarises size-frequency, b-value (with its uncertainty) and recurrence against
the noise strength

    nu = R int_0^1 Lambda(u) du / v,

the expected number of spontaneous pairs on a length R while a point loads from u = 0
(where the medium becomes excitable) to the slip threshold u = 1. With R = R_0, the
rupture length of the noiseless pattern, nu << 1 keeps the patterns of Sec. V (sources at
u = 1) and nu >> 1 is noise dominated (point recurrence (2 Lambda)^(-1/2)).
docs/noise.md, "What noise does to the wave statistics".

The calibrated rate: :func:`calibrated_noise` turns a chain's ``[noise]`` table (law
lambda(phi) and kick, ``bk.Chain(noise=...)``) into the free boundary's Lambda(u) =
lambda(u) P(u) / dx (docs/noise.md, "The calibrated rate"), and with ``deferred=True``
(releases) adds the pairs that failed releases start later, when the loading brings their
neighbours to the threshold (docs/noise.md, "Deferred nucleation").
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from . import _validate as V
from . import noise as _noise
from . import stats as _stats
from .params import Params

__all__ = [
    "noise_strength",
    "ruptures",
    "chain_ruptures",
    "point_recurrence",
    "ring_statistics",
    "statistics_vs_strength",
    "calibrated_noise",
    "first_slip",
]

ORIGINS = ("initial", "birth", "nucleation")


def noise_strength(noise: dict, length: float, v: float) -> float:
    """nu = length int_0^1 Lambda(u) du / v: the expected number of noise nucleations on
    ``length`` while a uniform stress loads at rate v from 0 to 1 (the engine nucleates
    only where u > 0).

    Parameters
    ----------
    noise : dict
        A free boundary ``[noise]`` table (``bk.noise.check_noise``; rate per unit
        length and unit time, dimensionless).
    length : float
        The length R, > 0 (dimensionless, the paper's x).
    v : float
        Loading rate, > 0 (dimensionless).

    Returns
    -------
    float
        nu (a count, dimensionless).

    Examples
    --------
    A constant rate Lambda: nu = R Lambda / v.

    >>> import bkwaves as bk
    >>> round(bk.noise_stats.noise_strength({"law": "constant", "rate": 0.3}, 50.0, 0.02), 9)
    750.0
    """
    length = V.number("length", length, lo=0.0, lo_open=True)
    v = V.number("v", v, lo=0.0, lo_open=True)
    noise = _noise.check_noise(noise)
    u = np.linspace(0.0, 1.0, 20001)
    lam = np.asarray(_noise.rate_density(u, noise), dtype=float)
    integral = float(np.sum(0.5 * (lam[1:] + lam[:-1]) * np.diff(u)))
    return length * integral / v


def _law_primitive(noise: dict, lo: float):
    """x -> int_lo^x Lambda(u) du for the laws other than the exponential (vectorised)."""
    rate, law = noise["rate"], noise["law"]
    if law == "constant":
        return lambda x: rate * (np.asarray(x, dtype=float) - lo)
    if law == "power":
        q = noise["exponent"] + 1.0

        def prim(y):
            return np.maximum(y, 0.0) ** q / q

        return lambda x: rate * (prim(np.asarray(x, dtype=float)) - prim(lo))
    # table: Lambda is piecewise linear in u between the nodes (constant beyond them), so
    # the trapezoid rule on a grid holding every node is exact at the grid points;
    # between them the primitive is interpolated linearly (error <= max|Lambda'| d^2 / 8)
    nodes = np.asarray(noise["u"], dtype=float)
    inner = nodes[(nodes > lo) & (nodes < 1.0)]
    grid = np.unique(np.concatenate([np.linspace(lo, 1.0, 200001), inner]))
    lam = np.asarray(_noise.rate_density(grid, noise), dtype=float)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (lam[1:] + lam[:-1]) * np.diff(grid))])
    return lambda x: np.interp(x, grid, cum)


def first_slip(phi, noise: dict, v: float):
    """The waiting time to the first slip of stuck blocks loaded at rate ``v`` from the
    stresses ``phi``: each slips by noise, independently, at the rate
    Lambda(phi_i + v t) of the ``[noise]`` table (``bk.noise.rate_density``; a chain's
    ``kick`` is accepted and ignored), until the first reaches the threshold 1 at
    t_1 = (1 - max phi) / v and slips for sure.

    Returns ``(mean, survival)``: survival(t) = P(no slip by t) = exp(-H(t)) for t < t_1
    (0 from t_1 on), H(t) = sum_i int_0^t Lambda(phi_i + v s) ds, in closed form for the
    constant, exponential and power laws and for the piecewise-linear table (up to the
    interpolation of its primitive between grid points 5e-6 (1 - min phi) apart);
    mean = int_0^t_1 survival(t) dt. With v = 0 the hazard is constant:
    mean = 1 / sum_i Lambda(phi_i).

    When every noise slip starts a rupture (a kick above ``bk.noise.kick_threshold`` at
    these stresses), this is the recurrence law of the ruptures of a ring that the last
    one left at ``phi`` (docs/noise.md, "Long runs compared"): e.g. ``phi = chain.phi``
    after a noiseless rupture, or ``np.full(n, u_minus)`` for the free boundary's n cells
    of length dx with the per-cell rate Lambda dx.

    Parameters
    ----------
    phi : array_like
        The stuck blocks' stresses phi_i < = 1 (dimensionless), at least one.
    noise : dict
        A ``[noise]`` table (rate per block and unit time, dimensionless).
    v : float
        Loading rate, >= 0 (dimensionless).

    Returns
    -------
    mean : float
        The mean waiting time, in units of sqrt(m/k_p) (inf without noise at v = 0).
    survival : callable
        t -> P(no slip by t), t in units of sqrt(m/k_p) (vectorised).

    Examples
    --------
    Ten blocks at rate 0.1 each: at v = 0 the wait is exponential with mean 1; loading at
    v = 0.01 they reach the threshold only at t_1 = 50, long after:

    >>> import numpy as np
    >>> from bkwaves import noise_stats as ns
    >>> mean, survival = ns.first_slip(np.full(10, 0.5), {"law": "constant", "rate": 0.1}, 0.0)
    >>> mean, round(float(survival(1.0)), 6)
    (1.0, 0.367879)
    >>> mean, survival = ns.first_slip(np.full(10, 0.5), {"law": "constant", "rate": 0.1}, 0.01)
    >>> round(mean, 9), survival(50.0)
    (1.0, 0.0)
    """
    noise = _noise.check_noise(noise, "noise", model="chain")
    noise.pop("kick")  # the rate law alone
    phi = V.array("phi", phi, hi=1.0)
    if phi.size == 0:
        V._fail("phi", phi, "at least one stuck block's stress")
    v = V.number("v", v, lo=0.0)
    if v == 0.0:
        total = float(np.sum(_noise.rate_density(phi, noise)))

        def survival(t):
            return np.exp(-total * np.asarray(t, dtype=float))

        return (math.inf if total == 0.0 else 1.0 / total), survival
    t_1 = (1.0 - float(phi.max())) / v
    if noise["law"] == "exponential":
        phi0 = noise["phi0"]
        # sum_i exp(-(1 - phi_i) / phi0), its exponent shifted by its largest term
        top = float(phi.max())
        weight = float(np.sum(np.exp((phi - top) / phi0)))
        k = noise["rate"] * phi0 / v * weight * math.exp(-(1.0 - top) / phi0)

        def hazard(t):
            return k * np.expm1(v * t / phi0)
    else:
        prim = _law_primitive(noise, float(phi.min()))
        base = np.sum(prim(phi))

        def hazard(t):
            x = phi[None, :] + v * np.atleast_1d(t)[:, None]
            return (np.sum(prim(x), axis=1) - base) / v

    def survival(t):
        t = np.asarray(t, dtype=float)
        tt = np.clip(np.atleast_1d(t), 0.0, t_1)
        out = np.where(np.atleast_1d(t) < t_1, np.exp(-hazard(tt)), 0.0)
        return out.reshape(t.shape) if t.ndim else float(out[0])

    # the time scale where H = 1 (S = 1/e) as a break point of the quadrature
    h_end = float(np.atleast_1d(hazard(np.array([t_1])))[0])
    t_e = t_1
    if h_end > 1.0:
        from scipy import optimize

        t_e = optimize.brentq(
            lambda t: float(np.atleast_1d(hazard(np.array([t])))[0]) - 1.0,
            0.0,
            t_1,
            xtol=1e-12 * t_1,
            rtol=1e-12,
        )
    from scipy import integrate

    points = [t_e] if 0.0 < t_e < t_1 else None
    mean = integrate.quad(survival, 0.0, t_1, limit=400, points=points)[0]
    return mean, survival


def _resets(result):
    """Node resets of a result's shock paths (:func:`_node_resets`)."""
    return _node_resets(
        result.shocks,
        float(result.meta["grid_spacing"]),
        float(result.snapshots.x.values[0]),
        result.snapshots.x.size,
        result.meta.get("boundary") == "periodic",
    )


def _node_resets(sh, h: float, x0: float, nodes: int, periodic: bool):
    """Node resets of shock paths ``sh`` on the grid x0 + k h (``nodes`` nodes): the
    ``node`` rows, and a pair born exactly at a node (its birth resets that node; recorded
    only in the two birth rows: one kept)."""
    nodes_rows = sh[sh.kind == "node"]
    born = sh[sh.kind.isin(ORIGINS[1:])]
    off = (born.x.to_numpy() - x0) / h
    at_node = born[np.abs(off - np.rint(off)) <= 1e-9].drop_duplicates(["t", "x", "kind"])
    if len(at_node):
        import pandas as pd

        nodes_rows = pd.concat([nodes_rows, at_node]).sort_values("t", kind="stable")
    out = nodes_rows
    k = np.rint((out.x.to_numpy() - x0) / h).astype(np.int64)
    if periodic:
        k = np.mod(k, nodes)
    return out.assign(node=k)


#: Shock path rows that end a shock.
ENDS = ("annihilation", "exit", "death", "creep_stop")


def ruptures(result, h: float | None = None):
    """Per-rupture catalog of a free boundary result run with ``record_path=True``: one row
    per group of shocks born together (same time, place and kind), with ``t_start``,
    ``x_start``, ``spontaneous`` (started by noise), ``u_start`` (u where it started),
    ``shocks``, ``t_end`` (the last node crossing of its shocks), ``swept`` (grid nodes its
    shocks reset, times h), ``moment`` (sum of A h over them: int A dx, the catalogs'
    ``moment``, :mod:`bkwaves.catalog`) and ``mean_u_plus``. Sizes are on the grid: each
    reset node stands for the cell h around it. ``h``: the grid spacing (default: the
    result's).

    Parameters
    ----------
    result : bkwaves.FreeBoundaryResult
        A run with ``record_path=True``.
    h : float, optional
        The grid spacing, > 0 (dimensionless, the paper's x); default the result's.

    Returns
    -------
    pandas.DataFrame
        One row per rupture; times in units of sqrt(m/k_p), positions and ``swept`` in
        the paper's dimensionless x, ``u_start`` and ``mean_u_plus`` dimensionless
        stresses, ``moment`` the dimensionless int A dx.

    Examples
    --------
    One maximum on a ring: one pair born at u = 1 sweeps the whole ring, with the moment
    of the engine's own catalog:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> from bkwaves import noise_stats as ns
    >>> p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3)
    >>> x = np.arange(200) * 0.2                        # a ring of length 40
    >>> u0 = 0.999 - 1e-4 * (x - 20) ** 2               # one maximum: a source
    >>> r = bk.FreeBoundary(p, x, u0, "periodic").run(max_events=1)
    >>> cat = ns.ruptures(r)
    >>> cat[["shocks", "swept", "spontaneous", "u_start"]].values.tolist()
    [[2, 40.0, False, 1.0]]
    >>> round(float(cat.moment[0]), 6), round(float(r.events.moment[0]), 6)
    (54.419218, 54.419218)
    """
    meta = result.meta
    h = float(meta["grid_spacing"]) if h is None else V.number("h", h, lo=0.0, lo_open=True)
    if not meta.get("record_path", 1):
        V._fail("result", "shock paths without node crossings", "a run with record_path=True")
    out = _fb_ruptures(
        result.shocks,
        h=h,
        x0=float(result.snapshots.x.values[0]),
        nodes=result.snapshots.x.size,
        periodic=meta.get("boundary") == "periodic",
    )
    return out[
        [
            "t_start",
            "x_start",
            "spontaneous",
            "u_start",
            "shocks",
            "t_end",
            "swept",
            "moment",
            "mean_u_plus",
        ]
    ]


def _fb_ruptures(sh, *, h: float, x0: float, nodes: int, periodic: bool):
    """:func:`ruptures` from the shock paths ``sh``, with the columns ``kind`` (of the
    first shock: initial, birth, nucleation), ``event`` and ``complete`` (every shock
    of it ended) besides."""
    import pandas as pd

    cols = [
        "t_start",
        "x_start",
        "spontaneous",
        "u_start",
        "shocks",
        "t_end",
        "swept",
        "moment",
        "mean_u_plus",
        "kind",
        "event",
        "complete",
    ]
    if not len(sh):
        return pd.DataFrame(columns=cols)
    origin = sh[sh.kind.isin(ORIGINS)]
    key = origin[["t", "x", "kind"]].astype(str).agg("|".join, axis=1)
    rid = pd.factorize(key)[0]
    owner = pd.Series(rid, index=origin.shock.to_numpy())
    reset = _node_resets(sh, h, x0, nodes, periodic)
    # without record_path the paths hold births and ends only
    if reset.shock.map(owner).isna().any():
        V._fail("result", "shock paths without node crossings", "a run with record_path=True")
    first = origin.groupby(rid).first()
    out = pd.DataFrame(
        {
            "t_start": first.t.to_numpy(),
            "x_start": first.x.to_numpy(),
            "spontaneous": (first.kind == "nucleation").to_numpy(),
            "u_start": first.u_plus.to_numpy(),
            "shocks": origin.groupby(rid).size().to_numpy(),
        }
    )
    r = reset.shock.map(owner).to_numpy()
    amp = (reset.u_plus - reset.u_minus).to_numpy()
    n = len(out)
    count = np.bincount(r, minlength=n)
    slip = np.bincount(r, weights=amp * h, minlength=n)
    up = np.bincount(r, weights=reset.u_plus.to_numpy(), minlength=n)
    t_end = out.t_start.to_numpy().copy()
    np.maximum.at(t_end, r, reset.t.to_numpy())
    out["t_end"] = t_end
    out["swept"] = count * h
    out["moment"] = slip
    with np.errstate(invalid="ignore", divide="ignore"):
        out["mean_u_plus"] = np.where(count > 0, up / np.maximum(count, 1), np.nan)
    out["kind"] = first.kind.to_numpy()
    out["event"] = first.event.to_numpy() if "event" in first else -1
    ended = set(sh.shock[sh.kind.isin(ENDS)].to_numpy().tolist())
    alive = np.array([s not in ended for s in origin.shock.to_numpy()])
    out["complete"] = np.bincount(rid, weights=alive, minlength=n) == 0
    return out


def chain_ruptures(result, boundary: str | None = None):
    """Per-rupture catalog of a chain result, the counterpart of :func:`ruptures`. The
    chain's catalog merges ruptures that overlap in time into one event; here every slip
    is given to the rupture that caused it: a spontaneous (``noise``) slip, or a
    ``threshold`` slip with no neighbour slipping before it in the same event, starts a
    rupture; any other slip belongs to the rupture of the neighbour whose latest slip
    started last (the front that loaded it). One row per rupture: ``t_start``,
    ``x_start``, ``block``, ``spontaneous``, ``u_start`` (the starting block's u),
    ``t_end`` (its last slip's end; NaN while one of its slips runs, a run stopped
    mid-event), ``n_blocks`` (distinct blocks), ``swept``
    (n_blocks dx), ``moment`` (dx times the sum of its slips: int slip dx, the free
    boundary's ``moment``),
    ``event`` (the catalog event it belongs to). ``boundary``: the chain's (``periodic``
    wraps the neighbours); by default the one the result records, and refused if it
    differs from it.

    Parameters
    ----------
    result : bkwaves.ChainResult
        A chain run.
    boundary : {"free", "fixed", "periodic"}, optional
        The chain's boundary; default the one the result records.

    Returns
    -------
    pandas.DataFrame
        One row per rupture; times in units of sqrt(m/k_p), ``x_start`` and ``swept`` in
        the paper's dimensionless x, ``u_start`` a dimensionless stress, ``moment`` the
        dimensionless int slip dx.

    Examples
    --------
    Two pairs started 0.5 apart at opposite points of a ring make one catalog event; each
    rupture gets the ground its fronts swept:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=0.0, dx=0.05)
    >>> ch = bk.Chain(400, p, "periodic", np.full(400, 0.93))
    >>> res = ch.kick(0, -0.5, 0.0).kick(200, -0.5, 0.5).run(t_end=100.0)
    >>> rup = bk.noise_stats.chain_ruptures(res)
    >>> len(res.catalog), rup.block.tolist(), int(rup.n_blocks.sum())
    (1, [0, 200], 400)
    """
    kept = getattr(result, "boundary", None)
    if boundary is None:
        if kept is None:
            V._fail("boundary", None, "the chain's boundary: free, fixed or periodic")
        boundary = kept
    boundary = V.choice("boundary", boundary, ("free", "fixed", "periodic"))
    if kept is not None and boundary != kept:
        V._fail("boundary", boundary, f"the boundary the result was run with, {kept!r}")
    return _chain_ruptures(result.slips, int(np.asarray(result.u).size), result.params.dx,
                           boundary).drop(columns="kind")  # fmt: skip


def _chain_ruptures(slips, n: int, dx: float, boundary: str):
    """:func:`chain_ruptures` from the slips table of a chain of ``n`` blocks ``dx`` apart,
    with the ``kind`` of each rupture's first slip besides."""
    import pandas as pd

    cols = [
        "t_start",
        "x_start",
        "block",
        "spontaneous",
        "u_start",
        "t_end",
        "n_blocks",
        "swept",
        "moment",
        "event",
        "kind",
    ]
    if not len(slips):
        return pd.DataFrame(columns=cols)
    dx = float(dx)
    order = np.lexsort((slips.block.to_numpy(), slips.t_start.to_numpy(), slips.event.to_numpy()))
    ev = slips.event.to_numpy()[order]
    blk = slips.block.to_numpy()[order].astype(np.int64)
    t0 = slips.t_start.to_numpy()[order]
    spont = slips.kind.to_numpy()[order] == "noise"
    rid, starts = _rupture_ids(ev, blk, t0, spont, n, boundary == "periodic")
    s = slips.iloc[order]
    first = s.iloc[starts]
    m = starts.size
    # a slip still running (a run stopped mid-event) has no slip yet: the finished ones
    # count, as in the catalog's moment of an open event; the moment is int slip dx
    moment = dx * np.bincount(rid, weights=np.nan_to_num(s.slip.to_numpy(), nan=0.0), minlength=m)
    t_end = np.full(m, -np.inf)
    with np.errstate(invalid="ignore"):  # a slip still running (t_end NaN): NaN, no warning
        np.maximum.at(t_end, rid, s.t_end.to_numpy())
    distinct = pd.DataFrame({"r": rid, "b": blk}).drop_duplicates()
    count = np.bincount(distinct.r.to_numpy(), minlength=m)
    x = first.x.to_numpy() if "x" in first else first.block.to_numpy() * dx
    return pd.DataFrame(
        {
            "t_start": first.t_start.to_numpy(),
            "x_start": x,
            "block": first.block.to_numpy(),
            "spontaneous": (first.kind == "noise").to_numpy(),
            "u_start": first.u_start.to_numpy(),
            "t_end": t_end,
            "n_blocks": count,
            "swept": count * dx,
            "moment": moment,
            "event": first.event.to_numpy(),
            "kind": first.kind.to_numpy(),
        }
    )


def _rupture_ids(ev, blk, t0, spont, n: int, periodic: bool):
    """The rupture of each slip (:func:`chain_ruptures`' rule), for slips sorted by event,
    start and block: ``rid`` (0, 1, ... in the order the ruptures start) and ``starts``
    (the index of each rupture's first slip). Slip k's parent is the latest earlier slip
    of the same event on a neighbour block, the one (left first on a tie) whose start is
    latest and not after k's; a noise slip, or one without a parent, starts a rupture;
    every other slip belongs to its parent's. Vectorised: the parents by a sorted search,
    the ruptures by pointer jumping (as many passes as log2 of the longest chain)."""
    size = blk.size
    idx = np.arange(size, dtype=np.int64)
    ev_rank = np.concatenate(([0], np.cumsum(ev[1:] != ev[:-1]))).astype(np.int64)
    group = ev_rank * n + blk  # (event, block): one group per block and event
    by_group = np.lexsort((idx, group))
    g_sorted = group[by_group]
    head = np.empty(size, dtype=bool)
    head[0] = True
    np.not_equal(g_sorted[1:], g_sorted[:-1], out=head[1:])
    groups = g_sorted[head]  # sorted, distinct
    key = (np.cumsum(head) - 1) * size + idx[by_group]  # (group rank, k): ascending

    def latest_before(j, valid):
        """Index of the latest slip before k on block j in k's event (-1: none)."""
        gq = ev_rank * n + np.where(valid, j, 0)
        r = np.searchsorted(groups, gq)
        present = valid & (r < groups.size)
        present[present] = groups[r[present]] == gq[present]
        p = np.searchsorted(key, r * size + idx) - 1  # largest key below (group, k)
        found = present & (p >= 0)
        found[found] = key[p[found]] // size == r[found]
        return np.where(found, idx[by_group][np.maximum(p, 0)], -1)

    if periodic:
        left, right = (blk - 1) % n, (blk + 1) % n
        valid_l = valid_r = np.ones(size, dtype=bool)
    else:
        left, right = blk - 1, blk + 1
        valid_l, valid_r = left >= 0, right < n
    pl, pr = latest_before(left, valid_l), latest_before(right, valid_r)
    tl = np.where(pl >= 0, t0[np.maximum(pl, 0)], -np.inf)
    tr = np.where(pr >= 0, t0[np.maximum(pr, 0)], -np.inf)
    ok_l = (pl >= 0) & (tl <= t0) & (tl > -np.inf)
    best_t = np.where(ok_l, tl, -np.inf)
    ok_r = (pr >= 0) & (tr <= t0) & (tr > best_t)
    parent = np.where(ok_r, pr, np.where(ok_l, pl, -1))
    new = spont | (parent < 0)
    root = np.where(new, idx, parent)
    while True:  # every slip's parent is earlier: the roots are rupture starts
        nxt = root[root]
        if np.array_equal(nxt, root):
            break
        root = nxt
    starts = idx[new]
    return np.searchsorted(starts, root), starts


def point_recurrence(result, t_min: float = -math.inf):
    """Times between successive resets of the same grid node (ruptures passing a point).

    Parameters
    ----------
    result : bkwaves.FreeBoundaryResult
        A run with ``record_path=True``.
    t_min : float, default -inf
        Only resets after this time (units of sqrt(m/k_p)).

    Returns
    -------
    numpy.ndarray
        The recurrence times, pooled over the nodes, in units of sqrt(m/k_p).

    Examples
    --------
    A source's waves pass every point once per loading from u_-(1) to 1:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> from bkwaves import noise_stats as ns
    >>> p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3)
    >>> x = np.arange(200) * 0.2                        # a ring of length 40
    >>> u0 = 0.999 - 1e-4 * (x - 20) ** 2               # one maximum: a source
    >>> r = bk.FreeBoundary(p, x, u0, "periodic").run(max_events=3)
    >>> rec = ns.point_recurrence(r)
    >>> from bkwaves import theory
    >>> round(float(rec.mean()), 1), round(float(1 - theory.u_minus_at_one(0.3)) / 1e-2, 1)
    (136.9, 137.2)
    """
    nodes = _resets(result)
    nodes = nodes[nodes.t >= t_min]
    if not len(nodes):
        return np.array([])
    k = nodes.node.to_numpy()
    t = nodes.t.to_numpy()
    order = np.lexsort((t, k))
    k, t = k[order], t[order]
    same = k[1:] == k[:-1]
    return np.diff(t)[same]


def ring_statistics(
    params: Params,
    x,
    u0,
    noise: dict | None,
    *,
    t_end: float,
    burn_in: float = 0.0,
    seed: int = 1,
) -> dict:
    """One free boundary ring (``boundary="periodic"``, grid ``x``, start ``u0``) with
    ``noise`` (None: noiseless) run to ``t_end``; the ruptures starting after ``burn_in``
    and their statistics: ``ruptures`` (catalog), ``rate`` (ruptures per unit time and
    length), ``spontaneous`` (fraction started by noise), ``b``
    (:class:`bkwaves.stats.GutenbergRichter` of the ruptures' moments, the estimator of
    every bkwaves b: Mc by maximum curvature, a bootstrap interval, no b for a degenerate
    or small catalog), ``recurrence`` (point recurrence times), ``u_start`` mean,
    ``swept`` mean; each count's standard error from the ruptures as independent samples
    (``rate_err`` = sqrt(N)/(span L), the Poisson error, an upper bound when ruptures
    come once per loading; ``u_start_sem``, ``swept_sem`` = sd/sqrt(N)): a run twice as
    long moves them within these errors (tests/test_noise_stats.py).

    Parameters
    ----------
    params : bkwaves.Params
        gamma, v (dimensionless) and dx.
    x : array_like
        The ring's grid (dimensionless, the paper's x).
    u0 : float or array_like
        The initial stress (dimensionless).
    noise : dict or None
        A free boundary ``[noise]`` table (rate per unit length and time,
        dimensionless), or None.
    t_end : float
        End of the run, > 0 (units of sqrt(m/k_p)).
    burn_in : float, default 0
        Ruptures starting before it are left out, 0 <= burn_in < t_end (units of
        sqrt(m/k_p)).
    seed : int, default 1
        Seed of the noise.

    Returns
    -------
    dict
        ``ruptures``, ``length`` and ``span`` (the ring's length and the time counted,
        dimensionless), ``rate`` (per unit length and time) and ``rate_err``,
        ``spontaneous``, ``recurrence`` (units of sqrt(m/k_p)), ``u_start`` and
        ``u_start_sem``, ``swept`` and ``swept_sem``, and ``b``.

    Examples
    --------
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> from bkwaves import noise_stats as ns
    >>> p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3)
    >>> x = np.arange(200) * 0.2                        # a ring of length 40
    >>> u0 = 0.999 - 1e-4 * (x - 20) ** 2               # one maximum: a source
    >>> T = float(bk.theory.source_period(1e-2, 0.3))
    >>> out = ns.ring_statistics(p, x, u0, None, t_end=3.5 * T)
    >>> len(out["ruptures"]), out["spontaneous"], round(out["span"] / T, 2)
    (4, 0.0, 3.5)
    """
    from .free_boundary import FreeBoundary, NoCreepWarning

    t_end = V.number("t_end", t_end, lo=0.0, lo_open=True)
    burn_in = V.number("burn_in", burn_in, lo=0.0, hi=t_end, hi_open=True)
    x = V.array("x", x)
    length = float(x[-1] - x[0]) * x.size / (x.size - 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NoCreepWarning)
        fb = FreeBoundary(params, x, u0, "periodic", record_path=True, noise=noise, seed=seed)
    res = fb.run(t_end=t_end)
    cat = ruptures(res)
    cat = cat[(cat.t_start >= burn_in) & (cat.swept > 0)].reset_index(drop=True)
    span = t_end - burn_in
    n = len(cat)

    def sem(col):
        return float(cat[col].std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan

    return {
        "ruptures": cat,
        "length": length,
        "span": span,
        "rate": n / (span * length),
        "rate_err": math.sqrt(n) / (span * length),
        "u_start_sem": sem("u_start"),
        "swept_sem": sem("swept"),
        "spontaneous": float(cat.spontaneous.mean()) if len(cat) else math.nan,
        "recurrence": point_recurrence(res, burn_in),
        "u_start": float(cat.u_start.mean()) if len(cat) else math.nan,
        "swept": float(cat.swept.mean()) if len(cat) else math.nan,
        "b": _stats.gutenberg_richter(cat.moment.to_numpy(dtype=float)),
    }


def statistics_vs_strength(
    params: Params,
    x,
    u0,
    strengths,
    *,
    law: str = "constant",
    law_params: dict | None = None,
    t_end: float,
    burn_in: float = 0.0,
    seed: int = 1,
    length: float | None = None,
):
    """Ruptures on a ring against noise strength: for each nu in ``strengths`` (0: no
    noise) the rate of the ``law`` (with ``law_params``) is set so that
    :func:`noise_strength` over ``length`` (default: the ring's) is nu, and
    :func:`ring_statistics` is run (same ``seed`` for every strength).
    Returns (table, runs): a pandas DataFrame with one row per strength (nu, rate,
    Lambda_mean = int_0^1 Lambda du, nu_R = Lambda_mean R_0 / v with R_0 the mean rupture
    length of the noiseless run when 0 is among the strengths, ruptures, spontaneous
    fraction, rupture rate per unit length and time with its Poisson error
    rupture_rate_err, b with its 95 % interval b_lo, b_hi
    and m_c, b_fit_p (:func:`bkwaves.stats.gutenberg_richter`; NaN without a b; the
    KS p-value of the Gutenberg-Richter law above m_c), mean u where
    ruptures start and mean swept length with their standard errors u_start_sem,
    swept_sem (:func:`ring_statistics`), mean and CV of the point recurrence time (no
    error: the nodes a rupture sweeps share its times), v times
    the mean recurrence, and the balance rupture_rate * swept * recurrence, which is 1
    in a steady state: every point is swept once per recurrence) and the runs' dicts.

    Parameters
    ----------
    params : bkwaves.Params
        gamma, v (dimensionless) and dx.
    x : array_like
        The ring's grid (dimensionless, the paper's x).
    u0 : float or array_like
        The initial stress (dimensionless).
    strengths : array_like
        The noise strengths nu, >= 0 (dimensionless counts).
    law : {"constant", "exponential", "power", "table"}, default "constant"
        The rate law.
    law_params : dict, optional
        Its parameters (``phi0``, ``exponent``: dimensionless; ``u``, ``g``).
    t_end : float
        End of each run (units of sqrt(m/k_p)).
    burn_in : float, default 0
        Ruptures starting before it are left out (units of sqrt(m/k_p)).
    seed : int, default 1
        Seed of the noise (the same for every strength).
    length : float, optional
        The length R of nu (dimensionless x); default the ring's.

    Returns
    -------
    table : pandas.DataFrame
        One row per strength (rates per unit length and time, lengths in the paper's x,
        times in units of sqrt(m/k_p), stresses dimensionless).
    runs : list of dict
        :func:`ring_statistics` of each strength.

    Examples
    --------
    The rate is set so that nu is the expected count of pairs on the ring over one
    loading:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> from bkwaves import noise_stats as ns
    >>> p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3)
    >>> x = np.arange(200) * 0.2                        # a ring of length 40
    >>> u0 = 0.999 - 1e-4 * (x - 20) ** 2               # one maximum: a source
    >>> T = float(bk.theory.source_period(1e-2, 0.3))
    >>> tab, runs = ns.statistics_vs_strength(p, x, u0, [0, 5], t_end=3 * T)
    >>> [round(r, 9) for r in tab.rate], float(tab.spontaneous.iloc[0])
    ([0.0, 0.00125], 0.0)
    >>> round(ns.noise_strength({"law": "constant", "rate": 0.00125}, 40.0, 1e-2), 9)
    5.0
    """
    import pandas as pd

    if not isinstance(params, Params):
        V._fail("params", params, "a bkwaves.Params instance")
    x = V.array("x", x)
    ring = float(x[-1] - x[0]) * x.size / (x.size - 1)
    length = ring if length is None else V.number("length", length, lo=0.0, lo_open=True)
    law_params = dict(law_params or {})
    unit = {"law": law, "rate": 1.0, **law_params}
    per_rate = noise_strength(unit, 1.0, params.v) * params.v  # int_0^1 Lambda du / rate
    rows, runs = [], []
    for nu in V.array("strengths", strengths, lo=0.0).ravel():
        nu = float(nu)
        if nu > 0:
            rate = nu * params.v / (length * per_rate)
            noise = {**unit, "rate": rate}
        else:
            rate, noise = 0.0, None
        run = ring_statistics(
            params,
            x,
            u0,
            noise,
            t_end=t_end,
            burn_in=burn_in,
            seed=seed,
        )
        b = run["b"]
        rec = run["recurrence"]
        mean_rec = float(rec.mean()) if rec.size else math.nan
        rows.append(
            {
                "nu": nu,
                "rate": rate,
                "Lambda_mean": rate * per_rate,
                "ruptures": len(run["ruptures"]),
                "spontaneous": run["spontaneous"],
                "rupture_rate": run["rate"],
                "rupture_rate_err": run["rate_err"],
                "b": b.b,
                "b_lo": b.lo,
                "b_hi": b.hi,
                "m_c": b.m_c,
                "b_fit_p": b.fit_p,
                "u_start": run["u_start"],
                "u_start_sem": run["u_start_sem"],
                "swept": run["swept"],
                "swept_sem": run["swept_sem"],
                "recurrence": mean_rec,
                "recurrence_cv": float(rec.std() / rec.mean()) if rec.size else math.nan,
                "v_recurrence": params.v * mean_rec,
                "balance": run["rate"] * run["swept"] * mean_rec,
            }
        )
        runs.append(run)
    table = pd.DataFrame(rows)
    quiet = table[table.nu == 0]
    r0 = float(quiet.swept.iloc[0]) if len(quiet) else math.nan
    table.insert(3, "nu_R", table.Lambda_mean * r0 / params.v)
    return table, runs


def calibrated_noise(
    chain_noise: dict,
    dx: float,
    gamma: float,
    *,
    distribution: str = "fixed",
    grid: int = 2001,
    deferred: bool = False,
) -> dict:
    """The free boundary noise that stands for a chain's noise (docs/noise.md, "The
    calibrated rate"). In the chain (``chain_noise``, the ``[noise]`` table of
    ``bk.Chain(noise=...)``: rate per block at phi = 1, and ``kick``) a stuck block slips
    spontaneously at lambda(phi) per unit time with a forward kick (``distribution``
    "fixed", or "exponential" with mean ``kick``); it starts a pair with probability P(u)
    (:func:`bkwaves.noise.nucleation_probability`); there are 1/dx blocks per unit
    length; so

        Lambda(u) = lambda(u) P(u) / dx.

    phi = u - Lap/dx^2 is the kicked block's own distance to threshold, = u - u_xx for a
    smooth field: in the free boundary limit (u_xx ~ a << 1) phi = u. Returned as a
    ``[noise]`` table for :class:`bkwaves.FreeBoundary`: when P(u) is the same on all of
    0 < u < 1 (checked on ``grid`` points, in closed form), the chain's law with rate
    P rate / dx; otherwise (a release, kick = 0, a kick below some K_c(u), or
    exponentially distributed kicks) the law ``table`` through g(u) P(u) on ``grid``
    points of 0 <= u <= 1, with rate rate P(1) / dx (P(1) = 1: K_c(1) = 0). A step of P
    (a fixed kick or a release: P = 1 where K_c(u) <= kick) is placed at its stress u*
    (bisected to the last bit) as a ramp 1e-12 wide; above u = 1 the table is constant
    (stuck points stay at u <= 1). Valid above the lattice's propagation-failure stress
    u_f (docs/noise.md).

    P(u) counts only the pairs a kick starts at once. On a loading chain a kick that
    fails is not lost: it leaves its neighbours closer to the threshold, and they start a
    pair when the background reaches :func:`bkwaves.noise.deferred_stress` u_b(u).
    ``deferred=True`` counts those pairs too, for a release (kick = 0), where u_b = 1 - c u
    (0 < u < u_r) sends the failed releases of (0, u_r) onto (u_r, 1):

        Lambda(u) = [lambda(u) + lambda((1 - u)/c)/c] / dx   (u_r <= u <= 1), 0 below,

    exact for points that have loaded from u <= 0 without a rupture since (every failed
    release of (0, u_r) then lies behind them; after a rupture, u_- <= 0 at the creep
    rule ``"zero"``), while the deferred pairs are not pre-empted. For the exponential and
    power laws this rate falls just above u_r (lambda((1 - u)/c) falls as u rises faster
    than lambda(u) rises there); the engines thin under its running maximum, so any law
    is fine.

    Parameters
    ----------
    chain_noise : dict
        The chain's ``[noise]`` table (rate per block and unit time at phi = 1, and
        ``kick``, dimensionless, in units of (f_r - f_s)/sqrt(k_p m)).
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    gamma : float
        Viscous damping, 0 <= gamma < 1 (dimensionless).
    distribution : {"fixed", "exponential"}, default "fixed"
        The law of the kick sizes.
    grid : int, default 2001
        Points of the table on 0 <= u <= 1, >= 3.
    deferred : bool, default False
        Count the pairs that failed releases start later (kick = 0 only).

    Returns
    -------
    dict
        A ``[noise]`` table for :class:`bkwaves.FreeBoundary` (rate per unit length and
        unit time, dimensionless).

    Examples
    --------
    A kick above K_c(u) everywhere nucleates every time: the chain's rate per block over
    dx blocks per unit length:

    >>> from bkwaves import noise_stats as ns
    >>> ns.calibrated_noise({"law": "constant", "rate": 0.01, "kick": 2.0}, 0.05, 0.3)
    {'law': 'constant', 'rate': 0.19999999999999998}
    """
    from .noise import kick_threshold, nucleation_probability

    chain_noise = _noise.check_noise(chain_noise, "chain_noise", model="chain")
    dx, gamma = _noise._check(dx, gamma)
    grid = V.integer("grid", grid, lo=3)
    kick = chain_noise["kick"]
    law = {k: val for k, val in chain_noise.items() if k != "kick"}
    if deferred:
        return _deferred_release_noise(law, kick, dx, gamma, grid)
    u = np.linspace(0.0, 1.0, grid)
    kc = np.asarray(kick_threshold(u, dx, gamma), dtype=float)
    if kick > 0:
        p = np.asarray(nucleation_probability(u, kick, dx, gamma, distribution=distribution))
    else:  # a release: a pair exactly where the first swing from rest trips the neighbours
        p = (kc == 0).astype(float)
    inner = p[1:-1]  # P(0) = 0 (K_c = inf: nothing ahead is excitable) and P(1) = 1
    if np.ptp(inner) == 0:
        return {**law, "rate": law["rate"] * float(inner[0]) / dx}
    steps = np.flatnonzero(np.diff(p))
    if distribution == "fixed" or kick == 0:
        # one step 0 -> 1 between two grid points: K_c(u) <= kick from u* on
        if steps.size != 1 or p[steps[0]] != 0:
            raise AssertionError(f"P(u) is not one step: {p}")
        lo, hi = float(u[steps[0]]), float(u[steps[0] + 1])
        while (mid := 0.5 * (lo + hi)) not in (lo, hi):
            lo, hi = (lo, mid) if kick_threshold(mid, dx, gamma) <= kick else (mid, hi)
        below = hi - 1e-12
        at = steps[0] + 1
        if u[at - 1] < below:
            new_u, new_p = ([below, hi], [0.0, 1.0]) if hi < u[at] else ([below], [0.0])
            u, p = np.insert(u, at, new_u), np.insert(p, at, new_p)
    g = np.asarray(_noise.rate_density(u, {**law, "rate": 1.0}), dtype=float)  # g(1) = 1
    return {
        "law": "table",
        "rate": law["rate"] * float(p[-1]) / dx,
        "u": u.tolist(),
        "g": (g * p / p[-1]).tolist(),
    }


def _deferred_release_noise(law: dict, kick: float, dx: float, gamma: float, grid: int) -> dict:
    """``calibrated_noise(..., deferred=True)``: releases that start a pair at once
    (u >= u_r) or later, at u_b = 1 - c u (the failed ones of 0 < u < u_r)."""
    from .noise import release_stress

    if kick != 0:
        V._fail(
            "chain_noise.kick",
            kick,
            "0 (a release) with deferred=True (a failed kick's deferred stress depends on "
            "where the loading started)",
        )
    u_r = release_stress(dx, gamma)
    c = (1.0 - u_r) / u_r  # u_b(u_r) = u_r: 1 - c u_r = u_r
    u = np.linspace(u_r, 1.0, grid)
    g1 = {**law, "rate": 1.0}
    g = (
        np.asarray(_noise.rate_density(u, g1), dtype=float)
        + np.asarray(_noise.rate_density((1.0 - u) / c, g1), dtype=float) / c
    )
    return {
        "law": "table",
        "rate": law["rate"] * float(g[-1]) / dx,
        "u": [u_r - 1e-12, *u.tolist()],
        "g": [0.0, *(g / g[-1]).tolist()],
    }
