"""Frequency-size statistics of ruptures in the plane (docs/free_boundary_2d.md,
"Gutenberg-Richter in the plane?").

    nice -n 5 python docs/scripts/free_boundary_2d_gr.py --json docs/free_boundary_2d_gr.json

Periodic squares of side 64, 128, 256 at h = 0.5 (128^2, 256^2, 512^2 nodes), gamma = 0.3,
v = 1e-3, creep rule "stop" (a front stops where u_+ <= u_c = 0.3), initial stress 0.3 x a
random field of correlation length 3, noise law "power" (g = u^8) at a rate per unit area
and time (at u = 1); independent seeds (field and noise). Catalogs after a transient of
5000 time units (five loading times 1/v): complete ruptures with t_start in (5000,
t_end]. Each catalog: b from the moments (``bk.stats.gutenberg_richter``: M = (2/3)
log10 moment, Mc by maximum curvature + 0.2, Aki-Utsu, 95 % bootstrap interval, the
Kolmogorov-Smirnov p of the exponential law above Mc), the Hill exponent beta of P(area
>= a) ~ a^-beta above a = 25, the largest area over the system's. Seeds give the mean and
its standard error (sd / sqrt(seeds)). Runs to t = 20000 (a catalog over 15000 time units,
15 loading times). Knobs turned: the system (side x2, x4 at rate 1), the run length (the
windows up to 20000 and 35000 of the same runs at side 128: 15000 and 30000 time units),
the noise rate (x10 steps) and the grid spacing (h = 0.25 at side 128, two seeds).
"""

from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import bkwaves as bk
from bkwaves.paper.beyond import plane_ruptures as pr

T0, A_MIN = pr.GR_T0, pr.GR_A_MIN  # the transient; the Hill exponent's cut (area units)
BINS = np.arange(-1.0, 6.01, 0.1)  # log10 area, for the histograms the figure draws


def catalog_numbers(ru, side: float, span: float) -> dict:
    gr = bk.stats.gutenberg_richter(ru.moment.values)
    beta, sbeta = bk.stats.power_law_exponent(ru.area.values, s_min=A_MIN)
    area = ru.area.to_numpy()
    return {
        "ruptures": int(len(ru)),
        "per_time": len(ru) / span,
        "mean_area": float(area.mean()),
        "max_area_frac": float(area.max() / side**2),
        "frac_quarter": float(np.mean(area > 0.25 * side**2)),
        "b": gr.b,
        "b_lo": gr.lo,
        "b_hi": gr.hi,
        "fit_p": gr.fit_p,
        "m_c": gr.m_c,
        "m_max": gr.m_max,
        "n_above": gr.n,
        "beta": beta,
        "beta_err": sbeta,
        "u_start": float(ru.u_start.mean()),
        "hist": np.histogram(np.log10(area), BINS)[0].tolist(),
    }


def run(job: dict) -> dict:
    side, t_end, v = job["side"], job["t_end"], job.get("v", pr.GR_V)
    ru, cpu = pr.gr_catalog(job["rate"], side, job["h"], t_end, job["seed"], v)
    out = dict(job, cpu_s=cpu, windows={})
    t0 = T0 * pr.GR_V / v
    for w in job.get("windows", [t_end]):
        out["windows"][f"{w:g}"] = catalog_numbers(ru[ru.t_start <= w], side, w - t0)
    return out


def jobs(seeds: int) -> list[dict]:
    js = []
    for s in range(1, seeds + 1):
        js.append(dict(case="size", rate=1.0, side=64.0, h=0.5, t_end=20000.0, seed=s))
        js.append(
            dict(case="size", rate=1.0, side=128.0, h=0.5, t_end=35000.0, seed=s,
                 windows=[20000.0, 35000.0])
        )  # fmt: skip
        js.append(dict(case="size", rate=1.0, side=256.0, h=0.5, t_end=20000.0, seed=s))
        js.append(dict(case="rate", rate=0.1, side=128.0, h=0.5, t_end=20000.0, seed=s))
        js.append(dict(case="rate", rate=10.0, side=128.0, h=0.5, t_end=20000.0, seed=s))
    for s in range(1, min(seeds, 2) + 1):
        js.append(dict(case="h", rate=1.0, side=128.0, h=0.25, t_end=20000.0, seed=s))
    return js


def extra_jobs(seeds: int) -> list[dict]:
    """The second run (--extra): Lambda = 0.1 on squares of 256 (the square of 128 cuts its
    largest ruptures), and the loading rate doubled with Lambda doubled (Lambda/v fixed,
    the same 15 loadings after 5 discarded)."""
    js = []
    for s in range(1, seeds + 1):
        js.append(dict(case="rate", rate=0.1, side=256.0, h=0.5, t_end=20000.0, seed=s))
        js.append(dict(case="v", rate=2.0, side=128.0, h=0.5, t_end=10000.0, seed=s, v=2e-3))
    return js


KEYS = ("b", "fit_p", "m_c", "n_above", "beta", "mean_area", "max_area_frac", "per_time")


def combine(runs: list[dict]) -> list[dict]:
    """Mean and standard error over seeds, per (rate, side, h, window)."""
    groups: dict = {}
    for r in runs:
        for w, c in r["windows"].items():
            key = (r["rate"], r["side"], r["h"], float(w), r.get("v", pr.GR_V))
            groups.setdefault(key, []).append(c)
    rows = []
    for (rate, side, h, w, v), cs in sorted(groups.items()):
        row = dict(rate=rate, side=side, h=h, t_end=w, v=v, seeds=len(cs))
        for k in KEYS:
            x = np.array([c[k] for c in cs], float)
            ok = x[np.isfinite(x)]
            row[k] = float(ok.mean()) if ok.size else float("nan")
            row[k + "_se"] = float(ok.std(ddof=1) / np.sqrt(ok.size)) if ok.size > 1 else 0.0
            row[k + "_n"] = int(ok.size)
        row["b_per_seed"] = [
            [c["b"], c["b_lo"], c["b_hi"]] for c in cs
        ]  # the per-catalog fits, for the record
        row["hist"] = np.sum([c["hist"] for c in cs], axis=0).tolist()
        rows.append(row)
    return rows


def table(rows: list[dict]) -> None:
    print(
        "| rate | v | side (nodes) | h | t_end | seeds | ruptures / time | mean area "
        "| largest / L^2 | b (mean +- se) | per-seed b [95 %] | KS p (mean) | Mc | n >= Mc "
        "| beta (area >= 25) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        per = ", ".join(
            f"{b:.2f} [{lo:.2f}, {hi:.2f}]" if np.isfinite(b) else "none"
            for b, lo, hi in r["b_per_seed"]
        )
        nodes = int(round(r["side"] / r["h"]))
        print(
            f"| {r['rate']:g} | {r.get('v', pr.GR_V):g} | {r['side']:g} ({nodes}^2) "
            f"| {r['h']:g} | {r['t_end']:g} "
            f"| {r['seeds']} | {r['per_time']:.4g} +- {r['per_time_se']:.2g} "
            f"| {r['mean_area']:.3g} +- {r['mean_area_se']:.2g} "
            f"| {r['max_area_frac']:.2f} +- {r['max_area_frac_se']:.2f} "
            f"| {r['b']:.2f} +- {r['b_se']:.2f} ({r['b_n']}) | {per} | {r['fit_p']:.2g} "
            f"| {r['m_c']:.2f} | {r['n_above']:.0f} | {r['beta']:.3f} +- {r['beta_se']:.3f} |"
        )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--extra", action="store_true", help="only the second run's cases")
    ap.add_argument("--json", default=None)
    ap.add_argument("--from-json", default=None, help="only print a saved run")
    args = ap.parse_args()
    if args.from_json:
        table(json.loads(Path(args.from_json).read_text())["rows"])
        return
    js = sorted(
        (extra_jobs if args.extra else jobs)(args.seeds),
        key=lambda j: -(j["side"] ** 2) * j["t_end"] / j["h"] ** 2,
    )
    with ProcessPoolExecutor(args.workers) as ex:
        runs = list(ex.map(run, js))
    rows = combine(runs)
    table(rows)
    print(f"CPU in the runs: {sum(r['cpu_s'] for r in runs):.0f} s")
    if args.json:
        Path(args.json).write_text(json.dumps({"args": vars(args), "rows": rows, "runs": runs}))


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
