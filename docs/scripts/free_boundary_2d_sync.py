"""Synchronisation or chaos in the plane (docs/free_boundary_2d.md, "Sources in the plane:
synchronisation and chaos").

    nice -n 5 python docs/scripts/free_boundary_2d_sync.py --json docs/free_boundary_2d_sync.json

Periodic squares, gamma = 0.3, v = 1e-2, creep rule "zero" (the paper's no-creep model),
no noise: u0 = 0.5 + A f(x, y), f a Gaussian random field of correlation length l scaled
to max |f| = 1 (``plane_ruptures.sync_field``: drawn on a grid of 2, interpolated exactly
onto finer grids). Fields as in 1D (docs/scripts/fb_sync_chaos.py): "smooth" (A = 0.02,
l = 25: the maxima's curvatures below a_max) and "sharp" (A = 0.3, l = 4: far above).
Default runs: 4 smooth squares of side 600 at h = 2 over 120 source periods T = (1 +
exp(-pi gamma / sqrt(1 - gamma^2)))/v = 137.2; the grid check, 2 smooth squares of 300 at
h = 1 and h = 2 (the same fields) over 60; one sharp square of 300 at h = 1 over 40; and
rings of 1600 (h = 0.2) from the 1D recipe, 6 smooth over 120 periods and one sharp over
40 (about 150 s of CPU).

Per period k: the births (ruptures of origin "birth", i.e. where u reached 1), the sites
(births of one period closer than ``D_SITE`` counted once: single-linkage clusters on the
torus), the fraction of births within ``D_SITE`` of a birth of the previous period
("recurrent": 1 for fixed sources, small when births wander), the ruptures and the
largest one's area / L^2 (1: the whole square slides in one rupture). The coarsening
length R(n) = L / sqrt(mean sites over the squares) is fitted as n^p on doubling windows
of periods with a bootstrap over squares (squares resampled with replacement), as the
1D exponent is (``bkwaves.paper.common.coarsening_exponent``, R = L / sites there). The
same fields' 1D rings (a cut through the 2D recipe: ``_smooth_random`` of the 1D
scripts, same A, l, gamma, v, creep, h) give the 1D exponent in the same run.
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from bkwaves import theory
from bkwaves.paper.beyond import plane_ruptures as pr
from bkwaves.paper.common import GAMMA_FB as G
from bkwaves.paper.common import V_FB as V

FIT_FROM = pr.FIT_FROM


def job(args):
    kind, field, L, h, seed, periods = args
    run = pr.sync_square if kind == 2 else pr.sync_ring
    return run(field, L, h, seed, periods)


def summary(res: list[dict]) -> dict:
    out = {}
    for dim in (1, 2):
        for field in pr.SYNC_FIELDS:
            for L in sorted({r["L"] for r in res}):
                for h in sorted({r["h"] for r in res}):
                    rs = [
                        r
                        for r in res
                        if (r["dim"], r["field"], r["L"], r["h"]) == (dim, field, L, h)
                    ]
                    if not rs:
                        continue
                    key = f"{dim}d-{field}-L{L:g}-h{h:g}"
                    P = min(r["periods"] for r in rs)
                    rec = np.array([r["recurrent"][:P] for r in rs], float)
                    s = dict(
                        runs=len(rs),
                        periods=P,
                        recurrent=np.nanmean(rec, axis=0).tolist(),
                        births_mean=np.mean([r["births"][:P] for r in rs], axis=0).tolist(),
                        cpu_s=float(sum(r["cpu_s"] for r in rs)),
                    )
                    if len(rs) >= 3 and P >= 2 * FIT_FROM:
                        s["coarsening"] = pr.coarsening(rs)
                    if dim == 2:
                        s["largest_mean"] = np.mean([r["largest"][:P] for r in rs], 0).tolist()
                        s["a_below_a_max"] = float(np.mean([r["a_below_a_max"] for r in rs]))
                    out[key] = s
    return out


def report(summ: dict) -> None:
    print(f"a_max = {theory.a_max(V, G):.3e}, T = {theory.source_period(V, G):.2f}")
    for key, s in summ.items():
        print(f"\n{key}: {s['runs']} runs x {s['periods']} periods, CPU {s['cpu_s']:.0f} s")
        if "a_below_a_max" in s:
            print(f"  maxima of u0 with both curvatures < a_max: {s['a_below_a_max']:.2f}")
        rec = np.array(s["recurrent"])
        P = s["periods"]
        for lo, hi in ((1, 10), (10, 20), (20, 40), (40, 80), (80, 160), (160, 320)):
            if hi <= P:
                w = slice(lo - 1, hi)
                line = f"  periods {lo}-{hi}: births/T {np.mean(s['births_mean'][w]):.1f}"
                line += f", recurrent {np.nanmean(rec[w]):.2f}"
                if "largest_mean" in s:
                    line += f", largest area/L^2 {np.mean(s['largest_mean'][w]):.2f}"
                if "coarsening" in s:
                    line += f", sites {np.mean(s['coarsening']['sites_mean'][w]):.1f}"
                print(line)
        c = s.get("coarsening")
        if c:
            for w in c["local"]:
                print(f"  p over {w['window']}: {w['p']:.3f} +- {w['sigma']:.3f}")
            print(f"  p over {FIT_FROM}-{c['periods']}: {c['p']:.3f} +- {c['sigma']:.3f}")
            pf, ps = c["prefactor"], c["prefactor_sigma"]
            print(f"  R a_n^(1/2) (periods 10-20): {pf:.3f} +- {ps:.3f}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--L", type=float, default=600.0, help="side of the smooth squares")
    ap.add_argument("--h", type=float, default=2.0, help="their grid spacing")
    ap.add_argument("--seeds", type=int, default=4, help="smooth squares")
    ap.add_argument("--periods", type=int, default=120)
    ap.add_argument("--check-L", type=float, default=300.0, help="squares of the h check")
    ap.add_argument("--check-seeds", type=int, default=2)
    ap.add_argument("--check-periods", type=int, default=60)
    ap.add_argument("--sharp-seeds", type=int, default=1)
    ap.add_argument("--sharp-periods", type=int, default=40)
    ap.add_argument("--ring-L", type=float, default=1600.0)
    ap.add_argument("--ring-h", type=float, default=0.2)
    ap.add_argument("--rings", type=int, default=6)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--json", default=None)
    ap.add_argument("--from-json", default=None, help="only print a saved run")
    args = ap.parse_args()
    if args.from_json:
        report(json.loads(Path(args.from_json).read_text())["summary"])
        return
    cL, cP = args.check_L, args.check_periods
    jobs = [(2, "smooth", args.L, args.h, s, args.periods) for s in range(1, args.seeds + 1)]
    jobs += [(2, "sharp", cL, 1.0, s, args.sharp_periods) for s in range(1, args.sharp_seeds + 1)]
    for h in (1.0, 2.0):
        jobs += [(2, "smooth", cL, h, s, cP) for s in range(1, args.check_seeds + 1)]
    rL, rh = args.ring_L, args.ring_h
    jobs += [(1, "smooth", rL, rh, s, args.periods) for s in range(1, args.rings + 1)]
    jobs += [(1, "sharp", rL, rh, 1, args.sharp_periods)]
    t0 = time.time()
    with ProcessPoolExecutor(args.workers) as ex:
        res = list(ex.map(job, jobs))
    summ = summary(res)
    report(summ)
    print(f"wall {time.time() - t0:.0f} s")
    if args.json:
        Path(args.json).write_text(json.dumps({"args": vars(args), "summary": summ, "runs": res}))


if __name__ == "__main__":
    main()
