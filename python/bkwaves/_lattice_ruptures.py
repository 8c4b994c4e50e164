"""The ruptures of a lattice run: its events split into the slip of single nucleations.

An event of the chain's engine is a maximal stretch of time in which some block slides,
so it merges the ruptures that overlap in time (two kicks far apart, noise on a loaded
plane); the chain splits its events along the line (``bkwaves.noise_stats.
chain_ruptures``). The plane's split is the same rule on four neighbours:

- a slip's parent is the latest earlier slip of the same event on one of the block's
  four neighbours (across a periodic side too): the one whose start is latest and not
  after the slip's own (on a tie, the first of left, right, below, above);
- a noise slip, or one without a parent, starts a rupture; every other slip belongs to
  its parent's;
- slips that start at the same instant on neighbouring blocks (a line or a disc kicked at
  once, blocks sliding in the initial state) are one rupture.

So a rupture is a connected set of blocks that slipped in one event, grown from one
nucleation: the front that reached each block came from a neighbour of that rupture.
Its row: the nucleation (time, block (i, j), place (x, y) = (i dx, j dy), stress, kind:
threshold, noise, trigger or initial), t_end (the end of its last slip; NaN if a slip was
still running when the run stopped), the blocks it slipped, area (blocks x dx dy), moment
(the integral of slip over the area: dx dy x the sum of its slips), mean slip and
perimeter: the Crofton estimate of the free boundary model in the plane
(``bkwaves.FreeBoundary2D``'s catalog) on the blocks' grid, P = (1/2) sum over four
directions of w delta N, N the boundary crossings of the lattice lines of that direction
(along x, along y and the two diagonals of a cell), delta their spacing (dy, dx and
dx dy/sqrt(dx^2 + dy^2)) and w the direction's share of the half circle (theta, pi/4,
pi/2 - theta, pi/4 with theta = atan(dy/dx): pi/4 each when dx = dy, where it is the
free boundary model's pi/8 (N_axis h + N_diag h/sqrt 2)). Free and fixed sides are not
counted (no block beyond them); a periodic side is crossed.
"""

from __future__ import annotations

import math

import numpy as np

#: The columns of the lattice's ruptures table, in order.
COLUMNS = (
    "id",
    "t_start",
    "t_end",
    "duration",
    "x_start",
    "y_start",
    "i_start",
    "j_start",
    "u_start",
    "n_blocks",
    "area",
    "moment",
    "magnitude",
    "mean_slip",
    "perimeter",
    "kind",
    "spontaneous",
    "event",
    "complete",
)

#: Definitions of the columns the shared catalog definitions do not have.
DESCRIPTIONS = {
    "id": "the rupture's number: 0, 1, ... in the order the ruptures start (the arrivals "
    "table's rupture column)",
    "x_start": "where the rupture started: x = i dx of its first block",
    "y_start": "where the rupture started: y = j dy of its first block",
    "i_start": "column of the block that slipped first",
    "j_start": "row of the block that slipped first",
    "n_blocks": "blocks the rupture slipped",
    "area": "the area that slipped: n_blocks dx dy",
    "moment": "the rupture's moment: the integral of slip over the area, dx dy times the "
    "sum of its slips",
    "mean_slip": "moment / area",
    "perimeter": "length of the rupture's boundary (Crofton estimate over the lattice's "
    "four directions, as the free boundary model's)",
}


def _neighbour(blk, nx: int, ny: int, di: int, dj: int, periodic: tuple[bool, bool]):
    """The block (i + di, j + dj) of each block, and whether it exists."""
    i, j = blk % nx, blk // nx
    i2, j2 = i + di, j + dj
    ok = np.ones(blk.size, dtype=bool)
    if periodic[0]:
        i2 = i2 % nx
    else:
        ok &= (i2 >= 0) & (i2 < nx)
    if periodic[1]:
        j2 = j2 % ny
    else:
        ok &= (j2 >= 0) & (j2 < ny)
    return np.where(ok, i2 + nx * j2, 0), ok


def rupture_ids(ev, blk, t0, spont, nx: int, ny: int, periodic: tuple[bool, bool]):
    """The rupture of each slip (module docs), for slips sorted by event, start and
    block: ``rid`` (0, 1, ... in the order the ruptures start) and ``starts`` (each
    rupture's first slip). Vectorised: the parents by a sorted search, the ruptures as
    the connected components of parent and same-instant links."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    size = blk.size
    n = nx * ny
    idx = np.arange(size, dtype=np.int64)
    ev_rank = np.concatenate(([0], np.cumsum(ev[1:] != ev[:-1]))).astype(np.int64)
    group = ev_rank * n + blk  # (event, block)
    by_group = np.lexsort((idx, group))
    g_sorted = group[by_group]
    head = np.empty(size, dtype=bool)
    head[0] = True
    np.not_equal(g_sorted[1:], g_sorted[:-1], out=head[1:])
    groups = g_sorted[head]
    rank = np.cumsum(head) - 1
    key = rank * size + idx[by_group]  # (group rank, slip): ascending

    def latest_before(nb, valid):
        """The latest slip before each slip k on block nb in k's event (-1: none)."""
        gq = ev_rank * n + np.where(valid, nb, 0)
        r = np.searchsorted(groups, gq)
        present = valid & (r < groups.size)
        present[present] = groups[r[present]] == gq[present]
        p = np.searchsorted(key, r * size + idx) - 1
        found = present & (p >= 0)
        found[found] = key[p[found]] // size == r[found]
        return np.where(found, idx[by_group][np.maximum(p, 0)], -1)

    best = np.full(size, -1, dtype=np.int64)
    best_t = np.full(size, -np.inf)
    links = []
    for di, dj in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        nb, ok = _neighbour(blk, nx, ny, di, dj, periodic)
        p = latest_before(nb, ok)
        tp = np.where(p >= 0, t0[np.maximum(p, 0)], -np.inf)
        better = (p >= 0) & (tp <= t0) & (tp > best_t)
        best = np.where(better, p, best)
        best_t = np.where(better, tp, best_t)
        # same-instant links: the neighbour's slip at k's start (kicked together)
        same = (p >= 0) & (tp == t0) & ~spont & ~spont[np.maximum(p, 0)]
        links.append(np.column_stack([idx[same], p[same]]))
    new = spont | (best < 0)
    edges = [np.column_stack([idx[~new], best[~new]]), *links]
    e = np.concatenate(edges) if edges else np.empty((0, 2), dtype=np.int64)
    graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(size, size))
    _, label = connected_components(graph, directed=False)
    # each component's first slip (the slips are in start order): its rupture's start
    first = np.full(label.max() + 1, size, dtype=np.int64)
    np.minimum.at(first, label, idx)
    order = np.argsort(first, kind="stable")
    rid_of_label = np.empty_like(order)
    rid_of_label[order] = np.arange(order.size)
    return rid_of_label[label], first[order]


def perimeter(rid, blk, m: int, nx: int, ny: int, dx: float, dy: float, periodic) -> np.ndarray:
    """The Crofton perimeter (module docs) of the blocks of each of the ``m`` ruptures
    (``rid``, ``blk``: distinct (rupture, block) pairs)."""
    n = nx * ny
    members = np.unique(rid.astype(np.int64) * n + blk)
    theta = math.atan2(dy, dx)
    diag = dx * dy / math.hypot(dx, dy)
    weight = {
        (1, 0): theta * dy,  # lines along x, dy apart
        (0, 1): (0.5 * math.pi - theta) * dx,  # lines along y, dx apart
        (1, 1): 0.25 * math.pi * diag,
        (1, -1): 0.25 * math.pi * diag,
    }
    out = np.zeros(m)
    for (di, dj), w in weight.items():
        for s in (1, -1):
            nb, ok = _neighbour(blk, nx, ny, s * di, s * dj, periodic)
            key = rid.astype(np.int64) * n + nb
            pos = np.minimum(np.searchsorted(members, key), members.size - 1)
            outside = ok & (members[pos] != key)
            out += 0.5 * w * np.bincount(rid[outside], minlength=m)
    return out


def _sorted_ids(slips, nx: int, ny: int, boundary):
    """The slips in (event, start, block) order with the rupture of each: (order, rid,
    starts), ``order`` indexing ``slips``' rows, ``rid`` and ``starts`` as
    ``rupture_ids``'."""
    periodic = tuple(b == "periodic" for b in boundary)
    order = np.lexsort((slips.block.to_numpy(), slips.t_start.to_numpy(), slips.event.to_numpy()))
    s = slips.iloc[order]
    blk = s.block.to_numpy().astype(np.int64)
    spont = s.kind.to_numpy() == "noise"
    rid, starts = rupture_ids(
        s.event.to_numpy(), blk, s.t_start.to_numpy(dtype=float), spont, nx, ny, periodic
    )
    return order, rid, starts


def slip_ruptures(slips, nx: int, ny: int, boundary) -> np.ndarray:
    """The rupture (the ruptures table's ``id``) of each of ``slips``' rows, in their
    order (the engine's slip columns: event, block, t_start, kind)."""
    if not len(slips):
        return np.empty(0, dtype=np.int64)
    order, rid, _ = _sorted_ids(slips, nx, ny, boundary)
    out = np.empty(len(slips), dtype=np.int64)
    out[order] = rid
    return out


def lattice_ruptures(slips, nx: int, ny: int, dx: float, dy: float, boundary):
    """The ruptures table (``COLUMNS``, dimensionless) of a lattice of nx x ny blocks
    spaced dx, dy with ``boundary`` = (along x, along y), from its slips (the engine's
    slip columns: event, block, t_start, t_end, slip, u_start, kind)."""
    import pandas as pd

    from .stats import moment_magnitude

    periodic = tuple(b == "periodic" for b in boundary)
    if not len(slips):
        out = pd.DataFrame({c: [] for c in COLUMNS})
        for c in ("t_start", "t_end", "duration", "x_start", "y_start", "u_start"):
            out[c] = out[c].astype(float)
        return out
    order, rid, starts = _sorted_ids(slips, nx, ny, boundary)
    s = slips.iloc[order]
    blk = s.block.to_numpy().astype(np.int64)
    spont = s.kind.to_numpy() == "noise"
    m = starts.size
    first = s.iloc[starts]
    # a slip still running (a run stopped mid-event) has no slip yet: the finished count
    moment = dx * dy * np.bincount(rid, weights=np.nan_to_num(s.slip.to_numpy()), minlength=m)
    t_end = np.full(m, -np.inf)
    with np.errstate(invalid="ignore"):
        np.maximum.at(t_end, rid, s.t_end.to_numpy(dtype=float))
    pairs = np.unique(rid.astype(np.int64) * (nx * ny) + blk)
    prid, pblk = pairs // (nx * ny), pairs % (nx * ny)
    count = np.bincount(prid, minlength=m)
    fb = first.block.to_numpy().astype(np.int64)
    area = count * dx * dy
    out = pd.DataFrame(
        {
            "id": np.arange(m, dtype=np.int64),
            "t_start": first.t_start.to_numpy(dtype=float),
            "t_end": t_end,
            "duration": t_end - first.t_start.to_numpy(dtype=float),
            "x_start": (fb % nx) * dx,
            "y_start": (fb // nx) * dy,
            "i_start": fb % nx,
            "j_start": fb // nx,
            "u_start": first.u_start.to_numpy(dtype=float),
            "n_blocks": count,
            "area": area,
            "moment": moment,
            "magnitude": moment_magnitude(moment),
            "mean_slip": moment / area,
            "perimeter": perimeter(prid, pblk, m, nx, ny, dx, dy, periodic),
            "kind": first.kind.to_numpy(),
            "spontaneous": spont[starts],
            "event": first.event.to_numpy(),
        }
    )
    out["complete"] = np.isfinite(out.t_end.to_numpy(dtype=float))
    return out[list(COLUMNS)].reset_index(drop=True)
