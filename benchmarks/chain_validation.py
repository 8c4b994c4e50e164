"""Validation tables of the chain simulator (docs/validation.md, chain section).

    python benchmarks/chain_validation.py [--out docs/chain_validation.json]

For gamma in {0, 0.3, 0.45} and u_+ in {0.3, 0.5, 0.7, 0.9}: the front speed c of the
chain at dx = 0.1, 0.05, 0.025, 0.0125 (1600 blocks, window 50-75%), the finite-dx tip
solver at the same dx (the exact steady front), the observed order in dx, Richardson
extrapolation to dx -> 0 against bk.front_speed; for gamma > 0 and u_+ > u_c = gamma,
u_- and w from ``bk.chain.front`` (default chain: the window two settling lengths from the
trigger, docs/chain.md; beta = inf, no backward slip) extrapolated against App. B.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import bkwaves as bk
from bkwaves import _core

DXS = (0.1, 0.05, 0.025, 0.0125)
GAMMAS = (0.0, 0.3, 0.45)
US = (0.3, 0.5, 0.7, 0.9)
STEPS = (0.4, 0.2, 0.1, 0.05, 0.025)


def richardson(values):
    """Tableau for dx halving, assuming c = c0 + a1 dx + a2 dx^2 + a3 dx^3 + ...:
    returns [R0 (raw), R1 (dx term removed), R2, R3] lists."""
    tab = [list(values)]
    for k in range(1, len(values)):
        prev = tab[-1]
        f = 2.0**k
        tab.append([(f * prev[i + 1] - prev[i]) / (f - 1.0) for i in range(len(prev) - 1)])
    return tab


def observed_order(v):
    d1, d2 = v[-3] - v[-2], v[-2] - v[-1]
    return math.log2(abs(d1 / d2)) if d2 != 0 else math.nan


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="docs/chain_validation.json")
    args = ap.parse_args()
    rows = []
    t0 = time.perf_counter()
    for g in GAMMAS:
        for u in US:
            if g > 0 and u == g:
                continue  # exactly critical
            row = {"gamma": g, "u_plus": u, "c_theory": float(bk.front_speed(u))}
            cs, tips = [], []
            for dx in DXS:
                r = _core.front_measure(u, dx, 1600, friction={"gamma": g}, heal=False)
                cs.append(r["c"])
                try:
                    tips.append(float(bk.tip_solve(u, dx=dx, gamma=g)["c"]))
                except Exception as e:  # noqa: BLE001 - recorded in the table
                    tips.append(None)
                    row.setdefault("tip_errors", []).append(f"dx={dx}: {e}")
            row["c"] = cs
            row["c_tip"] = tips
            row["order"] = observed_order(cs)
            tab = richardson(cs)
            row["c_R1"], row["c_R2"], row["c_R3"] = tab[1][-1], tab[2][-1], tab[3][-1]
            if g > 0 and u > g:
                tw = bk.traveling_wave(u, g)
                row["u_minus_theory"], row["w_theory"] = tw.u_minus, tw.w
                ums, ws, regimes = [], [], []
                for dx in DXS:
                    m = bk.chain.front(u, g, dx)
                    regimes.append(m.regime == "pulse")
                    ums.append(m.u_minus if m.u_minus is not None else math.nan)
                    ws.append(m.w if m.w is not None else math.nan)
                row["pulse"] = regimes
                row["u_minus"], row["w"] = ums, ws
                if all(regimes):
                    row["u_minus_order"] = observed_order(ums)
                    row["w_order"] = observed_order(ws)
                    row["u_minus_R2"] = richardson(ums)[2][-1]
                    row["w_R2"] = richardson(ws)[2][-1]
            elif g > 0:
                row["pulse"] = [bk.chain.front(u, g, DXS[-1]).regime == "pulse"]
            rows.append(row)
            print(json.dumps(row), flush=True)
    steps = []
    tip = float(bk.tip_solve(0.6, dx=0.05, gamma=0.3)["c"])
    for st in STEPS:
        c = _core.front_measure(0.6, 0.05, 1600, step=st, friction={"gamma": 0.3}, heal=False)["c"]
        steps.append({"step": st, "c": c, "rel_err": c / tip - 1})
        print(json.dumps(steps[-1]), flush=True)
    out = {
        "dx": DXS,
        "rows": rows,
        "time_step": steps,
        "seconds": time.perf_counter() - t0,
        "version": bk.__version__,
    }
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1, default=lambda x: None if x is None else float(x))
    print(f"wrote {args.out} in {out['seconds']:.0f} s")
    print(markdown(out))


def _f(x, fmt):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, fmt)


def markdown(out) -> str:
    """The tables of docs/validation.md from the JSON."""
    lines = ["| gamma | u_+ | " + " | ".join(f"c, dx={d}" for d in out["dx"]) + " | order |"]
    lines.append("|---" * (3 + len(out["dx"])) + "|")
    for r in out["rows"]:
        cells = [_f(c, ".9f") for c in r["c"]]
        lines.append(
            f"| {r['gamma']} | {r['u_plus']} | " + " | ".join(cells) + f" | {r['order']:.2f} |"
        )
    lines += ["", "| gamma | u_+ | max rel. diff. chain vs tip(dx) | R1 - c | R2 - c | R3 - c |"]
    lines.append("|---|---|---|---|---|---|")
    for r in out["rows"]:
        diffs = [abs(a / b - 1) for a, b in zip(r["c"], r["c_tip"], strict=True) if b]
        ct = r["c_theory"]
        lines.append(
            f"| {r['gamma']} | {r['u_plus']} | {max(diffs):.1e} | {r['c_R1'] - ct:.1e} | "
            f"{r['c_R2'] - ct:.1e} | {r['c_R3'] - ct:.1e} |"
        )
    lines += ["", "| gamma | u_+ | quantity | " + " | ".join(f"dx={d}" for d in out["dx"])]
    lines[-1] += " | order | R2 | App. B | R2 - App. B |"
    lines.append("|---" * (7 + len(out["dx"])) + "|")
    for r in out["rows"]:
        if "u_minus" not in r:
            continue
        for q, th in (("u_minus", "u_minus_theory"), ("w", "w_theory")):
            vals = " | ".join(_f(x, ".6f") for x in r[q])
            r2 = r.get(q + "_R2")
            diff = None if r2 is None else r2 - r[th]
            lines.append(
                f"| {r['gamma']} | {r['u_plus']} | {q} | {vals} | {_f(r.get(q + '_order'), '.2f')} "
                f"| {_f(r2, '.6f')} | {r[th]:.6f} | {_f(diff, '.1e')} |"
            )
    lines += ["", "| step (h/dx) | c | rel. error vs tip(dx) |", "|---|---|---|"]
    for s in out["time_step"]:
        lines.append(f"| {s['step']} | {s['c']:.12f} | {s['rel_err']:.2e} |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
