"""FreeBoundary2D against the lattice in a loaded run, as dx -> 0 at a fixed field: what
converges, at which rate, and what does not.

Run: nice -n 5 python docs/scripts/free_boundary_2d_loaded_dx.py --dx 0.2 0.1 0.05
     [--scale S] [--events local|global] [--json FILE]

The problem of free_boundary_2d_loaded.py (a periodic square of side 12 s, three
Gaussian bumps of width 1.5 s on a base of 0.6, peaks 0.91, gamma = 0.45, v = 0.02/s),
held fixed in x units while the lattice's spacing dx halves, over its first cycle
(t_end = 8 s + 4: three births, the fronts expand and annihilate, the square is swept
once by t = 8 s, and the pulses heal).
FreeBoundary2D runs on the lattice's nodes (h = dx) from the lattice's stress phi, with
the variants
- "exact": the continuum's c(u_+) (the free boundary problem itself);
- "chain": the chain's planar speed at this dx (bk.tip_solve), along every normal;
- "chain_curv": that and the derived curvature coefficients (D_axis, D_diag)
  (bk.theory.curvature_coefficient at the median u_+ the fronts meet), ``curvature=``;
- "shape": that and the chain at dx/sqrt(2) along the diagonals, ``speed_diagonal=``.

Compared (lattice - FreeBoundary2D): the births (time, place); the arrival times (the
lattice's first-slip time against FreeBoundary2D's arrival, at every node both swept:
mean, rms, max abs, and the same beyond r_far = 1.5 s of the hypocentres); the partition
of the square (the share of nodes whose first arrival comes from another rupture, and
the largest relative difference of a rupture's area); the moments (relative).

Why these converge and these rates (docs/free_boundary_2d.md, "Against the lattice: a
loaded run, dx -> 0"): the lattice's front moves at c(u_+, dx) = c(u_+) - O(dx), slowed
by D kappa with D = O(dx), and leaves an anisotropy c_diag - c_axis = O(dx); integrated
over a path of length R these put the arrival times off by O(dx R): first order for
"exact" and "chain"; with the speed law at dx and the shape options what is left is the
options' own error (D's interpolation between axis and diagonal, D's kappa dependence,
O(dx^2)) and the scheme's O(h^2). The births are at the same nodes in both (identical).
The moments are not local: the lattice's pulse, w ~ 5-8 wide, carries slip from where the
stress was higher, a difference of order w/sigma that does not depend on dx.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import bkwaves as bk

sys.path.insert(0, str(Path(__file__).resolve().parent))
import free_boundary_2d_loaded as loaded  # noqa: E402

# the first cycle: the square is swept by t = 8 s (the last arrival: 7.98 s), and the
# pulse's slip lasts ~4 more (its duration does not scale with s)
T_SWEEP, T_PULSE = 8.0, 4.0
VARIANTS = ("exact", "chain", "chain_curv", "shape")


def variant_options(name, dx, u_ref, gamma=loaded.GAMMA):
    """The FreeBoundary2D options of a variant at spacing dx; u_ref: the u_+ at which the
    curvature coefficients are taken."""
    if name == "exact":
        return {"speed": None}
    opts = {"speed": loaded.speed_at(dx, gamma)}
    if name in ("chain_curv", "shape"):
        opts["curvature"] = tuple(
            float(bk.theory.curvature_coefficient(u_ref, gamma, dx, direction=d))
            for d in ("x", "diagonal")
        )
    if name == "shape":
        opts["speed_diagonal"] = loaded.speed_at(dx / np.sqrt(2.0), gamma)
    return opts


def fb_labels(fb_run, n):
    """FreeBoundary2D's partition: the row number of the rupture whose front reached each
    node (-1 where none), from the recorded arrivals."""
    engine = fb_run["engine"]
    label = np.full((n, n), -1)
    for k, row in enumerate(fb_run["rows"]):
        t = engine.arrival_time(row["id"])
        label[np.isfinite(t) & (label < 0)] = k
    return label


def hypocentre_distance(rows, n, dx, size):
    """The periodic distance of every node from the nearest of the ruptures' starts."""
    x = np.arange(n) * dx
    xx, yy = np.meshgrid(x, x)
    best = np.full((n, n), np.inf)
    for r in rows:
        ddx = np.abs(xx - r["x"])
        ddy = np.abs(yy - r["y"])
        ddx, ddy = np.minimum(ddx, size - ddx), np.minimum(ddy, size - ddy)
        best = np.minimum(best, np.hypot(ddx, ddy))
    return best


def arrival_stats(d):
    return {
        "nodes": int(d.size),
        "mean": float(d.mean()),
        "rms": float(np.sqrt(np.mean(d**2))),
        "max_abs": float(np.abs(d).max()),
        "p99_abs": float(np.percentile(np.abs(d), 99)),
        "median": float(np.median(d)),
        "rms_minus_median": float(np.sqrt(np.mean((d - np.median(d)) ** 2))),
    }


def one_dx(dx, scale, events, variants=VARIANTS, t_end=None):
    size, v, sigma = loaded.L * scale, loaded.V_LOAD / scale, loaded.SIGMA * scale
    t_end = T_SWEEP * scale + T_PULSE if t_end is None else t_end
    kw = {} if events is None else {"lattice_kw": {"events": events}}
    la = loaded.run_lattice(dx, size=size, t_end=t_end, v=v, sigma=sigma, **kw)
    n = la["n"]
    out = {"dx": dx, "blocks": n * n, "lattice_cpu_s": la["cpu_s"], "t_end": t_end,
           "lattice_ruptures": len(la["rows"]), "variants": {}}  # fmt: skip
    t_la = la["t_first"]
    u_ref = None
    for name in variants:
        if u_ref is None and name in ("chain_curv", "shape"):
            # the u_+ the fronts meet: phi + v T at arrival, from the exact-law run
            fb0 = loaded.run_fb2d(dx, la["phi"], None, size=size, t_end=t_end, v=v)
            ta = fb0["engine"].last_arrival()
            u_ref = float(np.nanmedian(la["phi"] + v * ta))
            out["u_ref"] = u_ref
        opts = variant_options(name, dx, u_ref)
        fb = loaded.run_fb2d(
            dx, la["phi"], opts.pop("speed"), size=size, t_end=t_end, v=v,
            record_arrivals=True, **opts,
        )  # fmt: skip
        pairs, summary = loaded.compare(la, fb, size=size)
        t_fb = fb["engine"].last_arrival()
        both = np.isfinite(t_la) & np.isfinite(t_fb)
        far = both & (hypocentre_distance(fb["rows"], n, dx, size) > 1.5 * scale)
        d = t_la - t_fb
        # the partition: the lattice's rupture of each block's first slip, carried to
        # FreeBoundary2D's numbering by the matched pairs
        to_fb = {q["lattice"]: q["fb"] for q in pairs}
        lut = np.full(len(la["rows"]) + 1, -2)  # (index -1: a block that did not slip)
        for m, k in to_fb.items():
            lut[m] = k
        la_lab = lut[la["label"]]
        fb_lab = fb_labels(fb, n)
        swept = fb_lab >= 0
        res = {
            "cpu_s": fb["cpu_s"],
            "options": {k: q for k, q in opts.items() if k == "curvature"},
            "births_matched": summary["matched"],
            "fb_ruptures": summary["fb_ruptures"],
            "birth_max_abs_dt": summary["max_abs_dt"],
            "birth_max_dplace": summary["max_dplace"],
            "arrival": arrival_stats(d[both]),
            "arrival_far": arrival_stats(d[far]),
            "unswept_lattice": int((~np.isfinite(t_la) & swept).sum()),
            "partition_mismatch": float(np.mean(la_lab[swept] != fb_lab[swept])),
            "max_abs_darea_rel": summary["max_abs_darea_rel"],
            "dmoment_rel": [q["dmoment_rel"] for q in pairs],
            "total_moment_rel": summary["total_moment_rel"],
        }
        out["variants"][name] = res
        if "lattice_other" not in out:
            # the lattice's ruptures without a partner: when they start (against the
            # sweep's end, T_SWEEP s) and how large they are
            left = summary["lattice_unmatched"]
            ts = np.array([r["t_start"] for r in left]) if left else np.zeros(0)
            ar = np.array([r["area"] for r in left]) if left else np.zeros(0)
            out["lattice_other"] = {
                "count": len(left),
                "before_sweep_end": int((ts < T_SWEEP * scale).sum()),
                "t_first": float(ts.min()) if left else None,
                "area_total": float(ar.sum()),
                "area_max": float(ar.max()) if left else 0.0,
                "area_median": float(np.median(ar)) if left else 0.0,
            }
        a, af = res["arrival"], res["arrival_far"]
        print(
            f"dx {dx} {name:10s} births {res['births_matched']}/{res['fb_ruptures']} "
            f"dt {res['birth_max_abs_dt']:.2g} | arrival mean {a['mean']:+.4f} rms "
            f"{a['rms']:.4f} max {a['max_abs']:.4f} | far rms {af['rms']:.4f} max "
            f"{af['max_abs']:.4f} | partition {res['partition_mismatch']:.4f} area "
            f"{res['max_abs_darea_rel']:.4f} | moment "
            + " ".join(f"{q:+.3f}" for q in res["dmoment_rel"]),
            flush=True,
        )
    print(f"dx {dx}: {n}^2 blocks, lattice CPU {la['cpu_s']:.1f} s; other lattice ruptures",
          out["lattice_other"], flush=True)  # fmt: skip
    return out


def rates(runs, key_path):
    """log2 of the ratio of a metric between successive dx (the order per halving) and
    the slope of a least-squares fit of log(metric) against log(dx)."""
    vals = []
    for r in runs:
        q = r
        for k in key_path:
            q = q[k]
        vals.append(abs(q))
    dxs = np.array([r["dx"] for r in runs])
    vals = np.array(vals)
    steps = [float(np.log(vals[i] / vals[i + 1]) / np.log(dxs[i] / dxs[i + 1]))
             for i in range(len(vals) - 1)]  # fmt: skip
    fit = float(np.polyfit(np.log(dxs), np.log(vals), 1)[0]) if len(vals) > 1 else np.nan
    return {"values": [float(q) for q in vals], "orders": steps, "fit": fit}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dx", type=float, nargs="+", default=[0.2, 0.1])
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--events", choices=("local", "global"), default=None)
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=VARIANTS)
    ap.add_argument("--json")
    a = ap.parse_args()
    result = {"scale": a.scale, "L": loaded.L * a.scale, "sigma": loaded.SIGMA * a.scale,
              "v": loaded.V_LOAD / a.scale, "gamma": loaded.GAMMA, "events": a.events,
              "runs": []}  # fmt: skip
    for dx in a.dx:
        result["runs"].append(one_dx(dx, a.scale, a.events, a.variants))
        if a.json:  # what is done is kept if a later dx is interrupted
            with open(a.json, "w") as f:
                json.dump(result, f, indent=1)
    table = {}
    for name in a.variants:
        for key in (("arrival", "rms"), ("arrival", "max_abs"), ("arrival_far", "rms"),
                    ("partition_mismatch",), ("max_abs_darea_rel",),
                    ("total_moment_rel",)):  # fmt: skip
            r = rates(result["runs"], ("variants", name, *key))
            table[f"{name}:{'.'.join(key)}"] = r
            vals = " ".join(f"{q:.4g}" for q in r["values"])
            orders = " ".join(f"{q:.2f}" for q in r["orders"])
            print(f"{name:10s} {'.'.join(key):20s} {vals} orders {orders} fit {r['fit']:.2f}")
    result["rates"] = table
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
