"""Synchronisation or chaos on a ring (docs/validation.md, Free boundary problem,
"Synchronisation or chaos").

Periodic random fields u0 = 0.5 + A f(x) (f: Gaussian random field of correlation length
corr, max |f| = 1, ``bkwaves.config._smooth_random``), gamma = 0.3, v = 1e-2, grid h = 0.2,
run by ``bk.FreeBoundary`` for ``--periods`` source periods T = (1 + exp(-pi gamma /
sqrt(1 - gamma^2)))/v. Fields: "sharp" (A = 0.3, corr = 4: maxima with a >> a_max),
"smooth" (A = 0.02, corr = 25: all maxima with a < a_max), and "sharper" (A = 0.3,
corr = 2), "blunter" (A = 0.3, corr = 8): curvatures x4 and /4 of "sharp".

Per period k it records the births, the birth sites (births of one period closer than 1
counted once), the fraction of the period during which shocks exist anywhere on the ring
("active": 1 when shocks never stop, small when all blocks slide within a short time),
the events started and the largest complete one's swept length / L (1: the whole ring
slides in one event), and the fraction of births within 1 of a birth of the previous
period ("recurrent": 1 for fixed sources, small when births wander: chaos).

Run: python docs/scripts/fb_sync_chaos.py  (a few minutes on 2 cores for the default set;
--lengths 400 --periods 20 for a quick look); --out FILE saves the per-period series as
JSON.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import bkwaves as bk
from bkwaves import theory
from bkwaves.config import _smooth_random

G, V, H = 0.3, 1e-2, 0.2
FIELDS = {"sharp": (0.3, 4.0), "smooth": (0.02, 25.0), "sharper": (0.3, 2.0), "blunter": (0.3, 8.0)}

WINDOWS = ((0, 10), (10, 20), (40, 50), (140, 150))


def initial(length: float, field: str, seed: int, h: float = H):
    """The field made on the grid of spacing H, band-limited: on a finer grid h it is
    interpolated exactly (Fourier), so runs with different h start from the same field."""
    n = int(round(length / H))
    x = np.arange(n) * (length / n)
    amp, corr = FIELDS[field]
    u0 = 0.5 + amp * _smooth_random(x, corr, np.random.default_rng(seed), True)
    m = int(round(length / h))
    if m != n:
        u0 = np.fft.irfft(np.fft.rfft(u0), m) * (m / n)
        x = np.arange(m) * (length / m)
    return x, u0


def maxima_curvature(u0: np.ndarray, h: float) -> np.ndarray:
    """a = -u''/2 at the local maxima of u0 on the nodes (second difference)."""
    um, up = np.roll(u0, 1), np.roll(u0, -1)
    k = (u0 > um) & (u0 >= up)
    return -(um[k] - 2 * u0[k] + up[k]) / (2 * h * h)


def one(job):
    length, field, seed, periods, h = job
    x, u0 = initial(length, field, seed, h)
    T = theory.source_period(V, G)
    a = maxima_curvature(u0, h)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        fb = bk.FreeBoundary(bk.Params(gamma=G, v=V, dx=1e-3), x, u0, "periodic", record_path=False)
    t0 = time.time()
    r = fb.run(t_end=periods * T)
    s = r.shocks
    tb = s[s.kind == "birth"].t.to_numpy()
    # a pair is two rows (on a ring every birth is a pair)
    births = np.bincount((tb / T).astype(int), minlength=periods)[:periods] // 2
    # birth sites: births of one period closer than 1 (on the ring) counted once
    xb = s[(s.kind == "birth") & (s.dir > 0)]
    # recurrent: births within 1 of a birth of the previous period
    sites, recurrent, prev = [], [], np.array([])
    for k in range(periods):
        xs = np.sort(xb.x.to_numpy()[(xb.t.to_numpy() >= k * T) & (xb.t.to_numpy() < (k + 1) * T)])
        gaps = np.diff(np.append(xs, xs[:1] + length)) if xs.size else xs
        sites.append(max(1, int(np.sum(gaps > 1.0))) if xs.size > 1 else int(xs.size))
        if xs.size and prev.size:
            d = np.abs(xs[:, None] - prev[None, :])
            d = np.minimum(d, length - d).min(axis=1)
            recurrent.append(float(np.mean(d < 1.0)))
        else:
            recurrent.append(float("nan"))
        prev = xs
    e = r.events
    t1 = np.where(np.isfinite(e.t_end.to_numpy()), e.t_end.to_numpy(), fb.time)
    t0s = e.t_start.to_numpy()
    active = [
        float(np.sum(np.clip(np.minimum(t1, (k + 1) * T) - np.maximum(t0s, k * T), 0, None)) / T)
        for k in range(periods)
    ]
    # events started in each period, and the largest complete one's swept length / L
    ke = (t0s / T).astype(int)
    n_ev = np.bincount(ke, minlength=periods)[:periods]
    big = np.full(periods, np.nan)
    done = e.complete.to_numpy()
    np.fmax.at(big, np.minimum(ke, periods - 1)[done], e.swept.to_numpy()[done] / length)
    return {
        "L": length,
        "h": h,
        "field": field,
        "seed": seed,
        "n_maxima": int(a.size),
        "a_min": float(a.min()),
        "a_median": float(np.median(a)),
        "a_max_field": float(a.max()),
        "births": births.tolist(),
        "sites": sites,
        "recurrent": recurrent,
        "active": active,
        "events": n_ev.tolist(),
        "largest": big.tolist(),
        "steps": int(r.steps),
        "seconds": time.time() - t0,
    }


def window_mean(v, w):
    v = np.asarray(v, dtype=float)
    return float(np.nanmean(v[w[0] : w[1]])) if len(v) >= w[1] else float("nan")


def burst(births):
    """(peak births/T, its period)."""
    b = np.asarray(births)
    k = int(np.argmax(b))
    return int(b[k]), k + 1


def settled(recurrent, level=0.9, width=5):
    """First period from which the mean of `recurrent` over `width` periods is >= level."""
    r = np.nan_to_num(np.asarray(recurrent, dtype=float), nan=0.0)
    m = np.convolve(r, np.ones(width) / width, mode="valid")
    k = np.nonzero(m >= level)[0]
    return int(k[0]) + 1 if k.size else None


def table(res, periods):
    ws = [w for w in WINDOWS if w[1] <= periods]
    head = " | ".join(f"births/T (recurrent) {a + 1}-{b}" for a, b in ws)
    last = ws[-1]
    print(
        f"| field | L | h | seed | maxima of u0 | a at maxima (median, max) | {head} "
        f"| peak births/T (period) | recurrent >= 0.9 from period "
        f"| sites/T, events/T, largest swept/L, active {last[0] + 1}-{last[1]} |"
    )
    print("|---|---|---|---|---|---|" + "---|" * (len(ws) + 3))
    for d in res:
        b = " | ".join(
            f"{window_mean(d['births'], w):.1f} ({window_mean(d['recurrent'], w):.2f})" for w in ws
        )
        pk, kp = burst(d["births"])
        ks = settled(d["recurrent"])
        c = ", ".join(
            f"{window_mean(d[q], last):.{p}f}"
            for q, p in (("sites", 1), ("events", 1), ("largest", 2), ("active", 2))
        )
        a = f"{d['a_median']:.1e}, {d['a_max_field']:.1e}"
        print(
            f"| {d['field']} | {d['L']:g} | {d['h']:g} | {d['seed']} | {d['n_maxima']} | {a} "
            f"| {b} | {pk} ({kp}) | {ks if ks else '-'} | {c} |"
        )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lengths", type=float, nargs="+", default=[400.0, 1600.0, 6400.0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--fields", nargs="+", default=["sharp", "smooth"], choices=list(FIELDS))
    ap.add_argument("--periods", type=int, default=150)
    ap.add_argument("--h", type=float, nargs="+", default=[H], help="grid spacings")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default=None)
    ap.add_argument("--from-json", nargs="+", default=None, help="only print saved runs")
    args = ap.parse_args()
    print(f"a_max = {theory.a_max(V, G):.3e}, T = {theory.source_period(V, G):.3f}")
    if args.from_json:
        res = [d for f in args.from_json for d in json.loads(Path(f).read_text())]
    else:
        jobs = [
            (length, f, s, args.periods, h)
            for length in sorted(args.lengths, reverse=True)
            for h in args.h
            for f in args.fields
            for s in args.seeds
        ]
        with ProcessPoolExecutor(args.workers) as pool:
            res = list(pool.map(one, jobs))
        if args.out:
            Path(args.out).write_text(json.dumps(res))
    res.sort(key=lambda d: (d["field"], d["L"], d["seed"], -d["h"]))
    table(res, min(len(d["births"]) for d in res))
    for d in res:
        print(d["field"], d["L"], d["h"], d["seed"], f"{d['seconds']:.0f} s", d["births"])


if __name__ == "__main__":
    main()
