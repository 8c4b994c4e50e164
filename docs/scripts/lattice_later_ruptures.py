"""The loaded lattice's later ruptures as dx -> 0: how many per unit area, what share of
the area and of the moment, how large (docs/lattice.md, "Measured: the later ruptures as
dx -> 0"; docs/free_boundary_2d.md, "What is open").

Run: nice -n 5 python docs/scripts/lattice_later_ruptures.py --scale 2 --dx 0.2 0.1 0.05
     --seeds 0 1 2 [--ring] [--json FILE]

The loaded square of docs/scripts/free_boundary_2d_loaded.py (a base of 0.6 and three
Gaussian bumps, peaks 0.91, gamma = 0.45) at `--scale` s: side 12 s, bumps of width 1.5 s,
v = 0.02/s, held fixed in x units while dx falls. Seed 0 puts the bumps where that script
does; seed k > 0 draws their centres uniformly over the square (numpy's default_rng(k)),
the same at every dx: independent fields for error bars.

The lattice (local events) runs to `--t-end` (times s); its slips are split into
ruptures as in that script (a slip continues the rupture of a neighbour, or of its own
block, that slipped within the last 2 time units). A rupture is *later* when the block
that starts it had slipped before (a re-rupture of swept ground); the others are the
first cycle's (FreeBoundary2D has exactly those: 3, matched one to one in the scripts
above). Measured per (seed, dx), at windows t_w = T_SWEEP s + k W s (the sweep ends at
T_SWEEP s = 8 s; the smooth stress gains v k W s = 0.02 k W in a window, the same at every
scale):

- counts: later ruptures started by t_w, per unit area (x units) and per block;
- area share: blocks that slipped in a later rupture (a slip started by t_w) over all;
- moment share: the later slips' dx^2 sum of slip over the first cycle's moment;
- sizes: every later rupture's area (blocks, and blocks dx^2) at the end of the run;
- the stress the first cycle leaves: phi of every block that is stuck at t_snap =
  T_SWEEP s + T_PULSE (the pulses have healed, the later ruptures have barely begun):
  the share above 0.45, 0.7, 0.9 and the 99th, 99.9th percentiles.

- the stall lines (the plane): neighbours whose first slips ended more than 0.5 apart
  (a healing front that waited): their length per unit area, and the share of the
  blocks above 0.7 within two blocks of them.

`--ring`: the same in 1D (a ring of side 12 s, the bumps at 0.25 and 0.75 of the side,
bk.Chain): later ruptures and the stress left, for the comparison of the two geometries;
`--ring --ahead`: the stress 0.5 before each later slip, their durations and slips.
`--table --json FILE [--first-cycle FILE]`: the table of docs/lattice.md from saved runs.
`--stall-lines --json FILE`: the first cycle only, its stall lines for the thresholds 0.25,
0.5, 1.0 against the meeting lines of its fronts (stall_lines).
A run with --json keeps the (dx, seed) already in FILE (same scale, t_end, geometry):
an interrupted run resumes.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

import bkwaves as bk

sys.path.insert(0, str(Path(__file__).resolve().parent))
import free_boundary_2d_loaded as fbl  # noqa: E402
import free_boundary_2d_loaded_dx as fbl_dx  # noqa: E402

T_SWEEP, T_PULSE = 8.0, 4.0  # (times the scale) the first sweep's end; a pulse's duration
WINDOW = 2.0  # (times the scale) the windows' step: a loading of 0.04 per window
N_WINDOWS = 8
GAP = fbl.GAP
PHI_LEVELS = (0.45, 0.7, 0.9)
STALL = 0.5  # a healing stall: neighbours' first sticks this far apart in time


def centres(seed):
    if seed == 0:
        return fbl.CENTRES
    rng = np.random.default_rng(seed)
    return tuple((float(a), float(b)) for a, b in rng.uniform(0, 1, size=(3, 2)))


def split(blocks, t0, t1, neighbours, n_blocks, gap=GAP):
    """Rupture label of every slip (slips in order of start, ties by block) and each
    rupture's birth slip: a slip takes the rupture of the earliest-started of its block and
    neighbours that slipped within ``gap``, else it is a birth (free_boundary_2d_loaded.py's
    rule). ``neighbours(b)``: the blocks next to b."""
    last_t = np.full(n_blocks, -np.inf)
    last_s = np.full(n_blocks, -np.inf)
    last_r = np.full(n_blocks, -1)
    label = np.empty(len(blocks), dtype=np.int64)
    births = []
    for k, (b, ta, tb) in enumerate(zip(blocks, t0, t1, strict=True)):
        best, best_s = -1, np.inf
        for q in (b, *neighbours(b)):
            if last_r[q] >= 0 and last_t[q] >= ta - gap and last_s[q] < best_s:
                best, best_s = last_r[q], last_s[q]
        if best < 0:
            best = len(births)
            births.append(k)
        label[k] = best
        last_t[b], last_s[b], last_r[b] = max(last_t[b], tb), ta, best
    return label, np.array(births, dtype=np.int64)


def close_live(slips, t_now, u_now, v):
    """Slips still running at the end: their slip so far and t_end = now."""
    s = slips.copy()
    live = s["slip"].isna().to_numpy()
    u_live = np.asarray(u_now).ravel()[s["block"].to_numpy()[live]]
    s.loc[live, "slip"] = v * (t_now - s["t_start"][live]) - (u_live - s["u_start"][live])
    s.loc[live, "t_end"] = t_now
    return s, int(live.sum())


def measure(slips, n_blocks, dx, neighbours, t_windows, area_unit):
    """The later ruptures (module docstring) from the slip table."""
    s = slips.sort_values(["t_start", "block"], kind="stable").reset_index(drop=True)
    blocks = s["block"].to_numpy()
    t0, t1, slip = s["t_start"].to_numpy(), s["t_end"].to_numpy(), s["slip"].to_numpy()
    label, births = split(blocks, t0, t1, neighbours, n_blocks)
    first_slip = np.full(n_blocks, np.inf)
    np.minimum.at(first_slip, blocks, t0)
    # a later rupture: born at a block that had slipped before
    later_r = t0[births] > first_slip[blocks[births]]
    is_later = later_r[label]
    first_moment = float(slip[~is_later].sum() * area_unit)
    out = {
        "ruptures_first_cycle": int((~later_r).sum()),
        "first_cycle_births": [float(t0[k]) for k in births[~later_r]][:20],
        "first_cycle_moment": first_moment,
        "t_swept": float(first_slip.max()),
        "unswept_blocks": int(np.isinf(first_slip).sum()),
        "t_first_later": float(t0[births[later_r]].min()) if later_r.any() else None,
        "block_first_later": int(blocks[births[later_r][0]]) if later_r.any() else None,
        "windows": [],
    }
    area = n_blocks * area_unit
    for tw in t_windows:
        m = is_later & (t0 <= tw)
        rl = later_r & (t0[births] <= tw)
        hit = np.unique(blocks[m])
        out["windows"].append(
            {
                "t": float(tw),
                "count": int(rl.sum()),
                "per_area": float(rl.sum() / area),
                "per_block": float(rl.sum() / n_blocks),
                "area_share": float(len(hit) / n_blocks),
                "moment_share": float(slip[m].sum() * area_unit / first_moment),
                "slips": int(m.sum()),
            }
        )
    # sizes of the later ruptures over the whole run
    lab_l = label[is_later]
    if len(lab_l):
        pairs = np.unique(np.stack([lab_l, blocks[is_later]]), axis=1)
        _, nblk = np.unique(pairs[0], return_counts=True)
    else:
        nblk = np.zeros(0, dtype=np.int64)
    a_phys = nblk * area_unit
    out["sizes"] = {
        "blocks": [int(q) for q in np.sort(nblk)[::-1]],
        "blocks_quantiles": {
            q: float(np.percentile(nblk, q)) if len(nblk) else 0.0 for q in (50, 90, 99, 100)
        },  # fmt: skip
        "area_quantiles": {
            q: float(np.percentile(a_phys, q)) if len(a_phys) else 0.0 for q in (50, 90, 99, 100)
        },  # fmt: skip
        "single_block_share": float(np.mean(nblk == 1)) if len(nblk) else 0.0,
    }
    return out


def stress_left(phi, modes, dist=None, loads=()):
    """The stuck blocks' phi: quantiles and shares above PHI_LEVELS; with ``dist`` (each
    block's distance from the nearest hypocentre) the share above 0.7 in bins of unit
    width of that distance; for each (t_w, load) of ``loads`` the share of all blocks whose
    phi + load is above 0 (the stress a front can run into by t_w, if nothing slipped)."""
    stuck = np.asarray(modes).ravel() == 0
    p = np.asarray(phi).ravel()[stuck]
    prof = {}
    if dist is not None:
        d = np.asarray(dist).ravel()
        rbin = np.floor(d).astype(int)
        for r in range(int(d.max()) + 1):
            sel = rbin == r
            if sel.sum():
                prof[r] = float(np.mean((np.asarray(phi).ravel()[sel] > 0.7) & stuck[sel]))
    allp = np.asarray(phi).ravel()
    return {
        "share_above_0.7_by_distance": prof,
        "quantiles": {q: float(np.percentile(allp, q)) for q in (10, 25, 50, 75, 90)},
        "positive_by_window": {float(t): float(np.mean(allp + ld > 0)) for t, ld in loads},
        "stuck_share": float(stuck.mean()),
        "median": float(np.median(p)),
        "p99": float(np.percentile(p, 99)),
        "p999": float(np.percentile(p, 99.9)),
        "max": float(p.max()),
        **{f"above_{q}": float(np.mean(p > q)) for q in PHI_LEVELS},
    }


def stalls(slips, n, dx, phi, modes, threshold=STALL):
    """Where the first cycle's healing stalled: neighbours (along either axis) whose first
    slips ended more than ``threshold`` (STALL) apart (the stuck one waited while the other
    slid on). The stall lines' length per unit area (edges dx pi/4: a line at a uniform
    random angle crosses 4/pi of its length over dx edges) and the share of the blocks
    above 0.7 within two blocks of a stall edge (against the share of all blocks there)."""
    first = slips.sort_values("t_start").groupby("block").first()
    ts = np.full(n * n, np.nan)
    ts[first.index] = first["t_end"].to_numpy(dtype=float)
    ts = ts.reshape(n, n)
    edges = 0
    mark = np.zeros((n, n), bool)
    for ax in (0, 1):
        d = np.nan_to_num(np.abs(ts - np.roll(ts, 1, ax)), nan=0.0) > threshold
        edges += int(d.sum())
        mark |= d | np.roll(d, -1, ax)
    near = mark.copy()
    for _ in range(2):
        near = near | np.roll(near, 1, 0) | np.roll(near, -1, 0)
        near = near | np.roll(near, 1, 1) | np.roll(near, -1, 1)
    hi = (np.asarray(phi) > 0.7) & (np.asarray(modes) == 0)
    return {
        "length_per_area": float(edges * dx * np.pi / 4 / (n * n * dx * dx)),
        "near_share_all": float(near.mean()),
        "near_share_above_0.7": float(near[hi].mean()) if hi.any() else None,
    }


STALL_THRESHOLDS = (0.25, 0.5, 1.0)


def stall_lines(dx, scale, seed, thresholds=STALL_THRESHOLDS):
    """The first cycle's stall lines against the meeting lines of its fronts (docs/lattice.md,
    "Derived and measured: where the first healing stalls"): the lattice run to the end of
    the first cycle; the stall lines' length per unit area for each threshold on the
    neighbours' first-stick difference; the meeting lines (blocks whose first slip is later
    than both neighbours' along a row or a column, the 1D collisions) and their length per
    unit area (the same pi/4 count); each stall edge's distance from the nearest meeting
    block (periodic), against the 1D prediction d = T c/(1 + c) from the edge's own stuck
    side (T its first slip's duration, c = 1/|grad t_r| there, t_r the first slip times);
    the stress met at the meeting lines (phi_0 + v t_r)."""
    from scipy.spatial import cKDTree

    la, n, size, v, target = square_lattice(dx, scale, seed)
    c0 = time.process_time()
    slips = la.run(t_end=(T_SWEEP + T_PULSE) * scale, progress=False).slips
    cpu = time.process_time() - c0
    first = slips.sort_values("t_start").groupby("block").first()
    tr, th = np.full(n * n, np.nan), np.full(n * n, np.nan)
    tr[first.index] = first["t_start"].to_numpy(dtype=float)
    th[first.index] = first["t_end"].to_numpy(dtype=float)
    tr, th = tr.reshape(n, n), th.reshape(n, n)
    area = size * size
    meet = np.zeros((n, n), bool)
    for ax in (0, 1):
        meet |= (tr > np.roll(tr, 1, ax)) & (tr >= np.roll(tr, -1, ax))
    n_meet = sum(int(((tr > np.roll(tr, 1, ax)) & (tr >= np.roll(tr, -1, ax))).sum())
                 for ax in (0, 1))  # fmt: skip
    jj, ii = np.nonzero(meet)  # rows are y
    tree = cKDTree(np.c_[ii * dx, jj * dx] % size, boxsize=size)
    gy, gx = np.gradient(tr, dx)
    c_loc = 1.0 / np.hypot(gx, gy)
    out = {"dx": dx, "seed": seed, "blocks": n * n, "cpu_s": cpu,
           "meeting_length_per_area": n_meet * dx * np.pi / 4 / area,
           "u_plus_meeting_10_50_90": [float(q) for q in
                                       np.percentile((target + v * tr)[meet], [10, 50, 90])],
           "by_threshold": {}}  # fmt: skip
    for thr in thresholds:
        pts, pred, jumps = [], [], []
        for ax in (0, 1):
            diff = np.abs(th - np.roll(th, 1, ax))
            edge = np.nan_to_num(diff, nan=0.0) > thr
            r, c = np.nonzero(edge)
            r0, c0_ = (r - 1) % n if ax == 0 else r, c if ax == 0 else (c - 1) % n
            # the stuck side: the block of the pair that stuck first
            first_r = np.where(th[r, c] < th[r0, c0_], r, r0)
            first_c = np.where(th[r, c] < th[r0, c0_], c, c0_)
            pts.append(np.c_[(c - 0.5 * (ax == 1)) * dx, (r - 0.5 * (ax == 0)) * dx] % size)
            t_dur = th[first_r, first_c] - tr[first_r, first_c]
            cc = c_loc[first_r, first_c]
            pred.append(t_dur * cc / (1 + cc))
            jumps.append(diff[edge])
        pts, pred, jumps = np.vstack(pts), np.concatenate(pred), np.concatenate(jumps)
        entry = {"length_per_area": len(pts) * dx * np.pi / 4 / area, "edges": len(pts)}
        if len(pts):
            dist = tree.query(pts)[0]
            entry.update(
                distance_10_25_50_75_90=[
                    float(q) for q in np.percentile(dist, [10, 25, 50, 75, 90])
                ],
                predicted_50=float(np.median(pred)),
                ratio_50=float(np.median(dist / pred)),
                jump_50=float(np.median(jumps)),
            )  # fmt: skip
        out["by_threshold"][str(thr)] = entry
    return out


def stall_lines_table(out):
    """The table of docs/lattice.md from a --stall-lines json: mean +- sd over the fields."""
    lines = ["| dx | fields | meeting lines (length per area) | stall lines at threshold "
             "0.25, 0.5, 1.0 | stall / meeting length (0.5) | distance from the meeting "
             "lines, median at 0.25, 0.5, 1.0 | its quartiles (0.5) | distance / (T c/(1+c)), "
             "median (0.5) | jump across the stall, median (0.5) |",
             "|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for dx in sorted({r["dx"] for r in out["runs"]}, reverse=True):
        rs = [r for r in out["runs"] if r["dx"] == dx]

        def ms(vals, f="{:.3f}"):
            v = np.asarray(vals, dtype=float)
            return (f + " +- " + f).format(v.mean(), v.std(ddof=1))

        def th(t, key, rs=rs):
            return [r["by_threshold"][t][key] for r in rs]

        length = " ; ".join(ms(th(t, "length_per_area")) for t in ("0.25", "0.5", "1.0"))
        dist = ", ".join(f"{np.mean([q[2] for q in th(t, 'distance_10_25_50_75_90')]):.2f}"
                         for t in ("0.25", "0.5", "1.0"))  # fmt: skip
        quart = th("0.5", "distance_10_25_50_75_90")
        ratio = [a / r["meeting_length_per_area"]
                 for a, r in zip(th("0.5", "length_per_area"), rs, strict=True)]  # fmt: skip
        lines.append(f"| {dx} | {len(rs)} | {ms([r['meeting_length_per_area'] for r in rs])} | "
                     f"{length} | {ms(ratio, '{:.2f}')} | {dist} | "
                     f"{min(q[1] for q in quart):.2f}-{max(q[3] for q in quart):.2f} | "
                     f"{ms(th('0.5', 'ratio_50'))} | "
                     f"{ms(th('0.5', 'jump_50'), '{:.2f}')} |")  # fmt: skip
    return lines


def square_lattice(dx, scale, seed):
    """The loaded square of side ``fbl.L * scale`` at dx, its bumps from ``seed``: the
    periodic lattice (local events) at the stress field's u0, loaded at
    ``fbl.V_LOAD / scale``; returns (lattice, n, size, v, target stress)."""
    size, v, sigma = fbl.L * scale, fbl.V_LOAD / scale, fbl.SIGMA * scale
    n = int(round(size / dx))
    x = np.arange(n) * dx
    xx, yy = np.meshgrid(x, x)
    target = fbl.field(xx, yy, size=size, sigma=sigma, centres=centres(seed))
    la = bk.Lattice((n, n), bk.Params(gamma=fbl.GAMMA, v=v, dx=dx),
                    u0=fbl.displacement(target, dx), boundary="periodic",
                    events="local")  # fmt: skip
    return la, n, size, v, target


def window_times(scale, t_end=None):
    tw = [(T_SWEEP + k * WINDOW) * scale for k in range(1, N_WINDOWS + 1)]
    return [q for q in tw if t_end is None or q <= t_end + 1e-9]


def lattice_run(dx, scale, seed, t_end):
    la, n, size, v, target = square_lattice(dx, scale, seed)
    t_snap = (T_SWEEP + T_PULSE) * scale
    c0 = time.process_time()
    first_cycle = la.run(t_end=t_snap, progress=False)
    hyp = [{"x": cx * size, "y": cy * size} for cx, cy in centres(seed)]
    loads = [(q, v * (q - t_snap)) for q in window_times(scale) if q > t_snap]
    dist = fbl_dx.hypocentre_distance(hyp, n, dx, size)
    left = stress_left(la.phi, la.modes, dist, loads)
    left["stalls"] = stalls(first_cycle.slips, n, dx, la.phi, la.modes)
    res = la.run(t_end=t_end, progress=False)
    cpu = time.process_time() - c0
    slips, live = close_live(res.slips, res.t, la.u, v)

    def nbrs(b):
        i, j = b % n, b // n
        return (j * n + (i + 1) % n, j * n + (i - 1) % n, ((j + 1) % n) * n + i,
                ((j - 1) % n) * n + i)  # fmt: skip

    tw = window_times(scale, t_end)
    out = measure(slips, n * n, dx, nbrs, tw, dx * dx)
    out.update(dx=dx, seed=seed, blocks=n * n, cpu_s=cpu, t_end=t_end, t_snap=t_snap,
               slips=len(slips), still_sliding=live, stress_left=left,
               peaks=[float(target.max())])  # fmt: skip
    return out


def _ring_chain(dx, scale):
    """The ring of the 1D runs: two of the field's bumps on a periodic chain of side
    ``fbl.L * scale``, at the stress field (u0 solving (1 - Laplacian) u0 = target),
    loaded at ``fbl.V_LOAD / scale``; returns (chain, x, n, size, v)."""
    size, v, sigma = fbl.L * scale, fbl.V_LOAD / scale, fbl.SIGMA * scale
    n = int(round(size / dx))
    x = np.arange(n) * dx
    f = np.zeros(n)
    for c, h in ((0.25, 1.0), (0.75, 0.985)):
        for sh in (-size, 0.0, size):
            f += h * np.exp(-((x - c * size - sh) ** 2) / (2 * sigma**2))
    target = fbl.BASE + fbl.HEIGHT * f / f.max()
    lap = -(4 / dx**2) * np.sin(np.pi * np.fft.fftfreq(n)) ** 2
    u0 = np.real(np.fft.ifft(np.fft.fft(target) / (1.0 - lap)))
    ch = bk.Chain(n, bk.Params(gamma=fbl.GAMMA, v=v, dx=dx), u0=u0, boundary="periodic")
    return ch, x, n, size, v


def ring_run(dx, scale, t_end):
    ch, x, n, size, v = _ring_chain(dx, scale)
    t_snap = (T_SWEEP + T_PULSE) * scale
    c0 = time.process_time()
    ch.run(t_end=t_snap, progress=False)
    dist = np.min([np.minimum(np.abs(x - c * size), size - np.abs(x - c * size))
                   for c in (0.25, 0.75)], axis=0)  # fmt: skip
    loads = [(q, v * (q - t_snap)) for q in window_times(scale) if q > t_snap]
    left = stress_left(ch.phi, ch.modes, dist, loads)
    res = ch.run(t_end=t_end, progress=False)
    cpu = time.process_time() - c0
    slips, live = close_live(res.slips, res.t, ch.u, v)

    def nbrs(b):
        return ((b + 1) % n, (b - 1) % n)

    tw = window_times(scale, t_end)
    out = measure(slips, n, dx, nbrs, tw, dx)
    out.update(dx=dx, blocks=n, cpu_s=cpu, t_end=t_end, t_snap=t_snap, slips=len(slips),
               still_sliding=live, stress_left=left)  # fmt: skip
    return out


def ring_stress_ahead(dx, scale, t0=20.0, t1=44.0, frame=0.1):
    """The chain's later slips (a block's slip starting more than 2.5 after its first and
    after t0 + 0.5, in units of the scale 2 run): the stress at the block 0.5 before
    (the u_+ the later ruptures run into), their durations and slips."""
    ch, x, n, size, v = _ring_chain(dx, scale)
    ch.run(t_end=t0, progress=False)
    ts = np.arange(t0, t1 + 1e-9, frame)
    phis = []
    for t in ts:
        ch.run(t_end=float(t), progress=False)
        phis.append(np.array(ch.phi))
    phis = np.array(phis)
    s = ch.run(t_end=t1 + frame, progress=False).slips
    first = s.groupby("block").t_start.min()
    later = s[(s.t_start.to_numpy() > first.reindex(s.block).to_numpy() + 2.5)
              & (s.t_start.to_numpy() > t0 + 0.5)]  # fmt: skip
    k = np.searchsorted(ts, later.t_start.to_numpy() - 0.5) - 1
    up = phis[k, later.block.to_numpy()]
    done = later.dropna(subset=["t_end"])
    return {
        "dx": dx,
        "later_slips": len(later),
        "u_plus_quantiles_10_50_90": [float(q) for q in np.percentile(up, [10, 50, 90])],
        "share_below_u_c": float(np.mean(up < fbl.GAMMA)),
        "duration_median": float((done.t_end - done.t_start).median()),
        "slip_median": float(done.slip.median()),
        "still_sliding": int(later.t_end.isna().sum()),
    }


def summary(line):
    w = line["windows"][-1] if line["windows"] else {}
    sl = line["stress_left"]
    return (f"dx {line['dx']} seed {line.get('seed', '-')}: {line['blocks']} blocks, cpu "
            f"{line['cpu_s']:.1f} s; first cycle {line['ruptures_first_cycle']}; later by "
            f"t = {w.get('t')}: {w.get('count')} ({w.get('per_area', 0):.4g}/area), area "
            f"{w.get('area_share', 0):.3e}, moment {w.get('moment_share', 0):.3e}; "
            f"stress left > 0.7: {sl['above_0.7']:.2e}, > 0.9: {sl['above_0.9']:.2e}, "
            f"p99.9 {sl['p999']:.3f}")  # fmt: skip


def mean_sd(vals):
    v = np.array([q for q in vals if q is not None], dtype=float)
    if len(v) == 0:
        return "-"
    if len(v) == 1:
        return f"{v[0]:.3g}"
    return f"{v.mean():.3g} +- {v.std(ddof=1):.2g}"


def plane_table(out, first=None):
    """The plane's rows of docs/lattice.md (mean +- standard deviation over the seeds):
    windows from ``out`` (the run to t = 40 s/2), the first later rupture, the stress left
    and the stall lines from ``first`` (the first-cycle run) where given."""
    first = first or {"runs": []}
    rows = []
    for dx in sorted({r["dx"] for r in out["runs"]} | {r["dx"] for r in first["runs"]},
                     reverse=True):  # fmt: skip
        rs = [r for r in out["runs"] if r["dx"] == dx]
        fs = [r for r in first["runs"] if r["dx"] == dx] or rs

        def win(t, key, rs=rs):
            return mean_sd([w[key] for r in rs for w in r["windows"] if w["t"] == t])

        st = [r["stress_left"].get("stalls", {}) for r in fs]

        def big(runs, area, dx=dx):
            """later ruptures of at least ``area`` per unit area, by the run's end"""
            return mean_sd([sum(q * dx * dx >= area for q in r["sizes"]["blocks"])
                            / (r["blocks"] * dx * dx) for r in runs])  # fmt: skip

        cells = [
            f"{dx:g}",
            str(fs[0]["blocks"]),
            f"{len(rs)} / {len(fs)}",
            mean_sd([r.get("t_first_later") for r in fs]),
            win(24.0, "per_area", fs),
            win(40.0, "per_area"),
            win(24.0, "area_share", fs),
            win(32.0, "area_share"),
            win(40.0, "area_share"),
            big([r for r in fs if r["t_end"] == 24.0], 0.1),
            big([r for r in rs if r["t_end"] == 40.0], 1.0),
            win(24.0, "moment_share", fs),
            win(40.0, "moment_share"),
            mean_sd([r["stress_left"]["above_0.7"] for r in fs]),
            mean_sd([q.get("length_per_area") for q in st]),
            mean_sd([q.get("near_share_above_0.7") for q in st]),
            mean_sd([q.get("near_share_all") for q in st]),
        ]
        rows.append("| " + " | ".join(cells) + " |")
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dx", type=float, nargs="+", default=[0.2, 0.1])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--scale", type=float, default=2.0)
    ap.add_argument(
        "--t-end",
        type=float,
        default=T_SWEEP + N_WINDOWS * WINDOW,
        help="in units of the scale (default 24: eight windows after the sweep)",
    )
    ap.add_argument("--ring", action="store_true", help="the 1D ring instead of the plane")
    ap.add_argument(
        "--ahead",
        action="store_true",
        help="with --ring: the stress ahead of the later slips (prints JSON)",
    )
    ap.add_argument(
        "--stall-lines",
        action="store_true",
        help="the plane's first cycle only: stall lines by threshold against the meeting lines",
    )
    ap.add_argument("--json")
    ap.add_argument("--table", action="store_true", help="print the table of --json, run nothing")
    ap.add_argument("--first-cycle", help="with --table: the first-cycle run's json (the plane)")
    a = ap.parse_args()
    if a.table:
        out = json.loads(Path(a.json).read_text())
        if "thresholds" in out:  # a --stall-lines json
            print("\n".join(stall_lines_table(out)))
            return
        if out["geometry"] == "ring":
            for r in out["runs"]:
                w = {q["t"]: q for q in r["windows"]}
                wins = {t: (q["per_area"], q["area_share"], q["moment_share"])
                        for t, q in w.items()}  # fmt: skip
                print(r["dx"], r.get("t_first_later"), r.get("block_first_later"), wins,
                      r["stress_left"]["above_0.7"] * out["L"])  # fmt: skip
            return
        first = json.loads(Path(a.first_cycle).read_text()) if a.first_cycle else None
        print("\n".join(plane_table(out, first)))
        return
    t_end = a.t_end * a.scale
    if a.stall_lines:
        res = {"scale": a.scale, "thresholds": STALL_THRESHOLDS, "runs": []}
        if a.json and Path(a.json).exists():  # an interrupted run resumes
            res["runs"] = json.loads(Path(a.json).read_text())["runs"]
        done = {(r["dx"], r["seed"]) for r in res["runs"]}
        for dx in a.dx:
            for seed in a.seeds:
                if (dx, seed) not in done:
                    res["runs"].append(stall_lines(dx, a.scale, seed))
                    print(json.dumps(res["runs"][-1]), flush=True)
                    if a.json:
                        Path(a.json).write_text(json.dumps(res, indent=1))
        return
    if a.ring and a.ahead:
        for dx in a.dx:
            print(json.dumps(ring_stress_ahead(dx, a.scale)), flush=True)
        return
    out = {"scale": a.scale, "L": fbl.L * a.scale, "sigma": fbl.SIGMA * a.scale,
           "v": fbl.V_LOAD / a.scale, "gamma": fbl.GAMMA, "t_end": t_end,
           "geometry": "ring" if a.ring else "square", "runs": []}  # fmt: skip
    if a.json and Path(a.json).exists():  # keep what an earlier, interrupted run measured
        old = json.loads(Path(a.json).read_text())
        if {k: old.get(k) for k in ("scale", "t_end", "geometry")} == {
            k: out[k] for k in ("scale", "t_end", "geometry")
        }:
            out["runs"] = old["runs"]
    done = {(r["dx"], r.get("seed")) for r in out["runs"]}
    for dx in a.dx:
        for seed in [None] if a.ring else a.seeds:
            if (dx, seed) in done:
                continue
            line = ring_run(dx, a.scale, t_end) if a.ring else lattice_run(dx, a.scale, seed, t_end)
            print(summary(line), flush=True)
            out["runs"].append(line)
            if a.json:
                Path(a.json).write_text(json.dumps(out, indent=1))
    if not a.ring:
        print("\n".join(plane_table(out)))


if __name__ == "__main__":
    main()
