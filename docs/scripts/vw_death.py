"""Where velocity-weakening fronts die (docs/velocity_weakening.md, "Where fronts die"):
the v_f above which the front of ``bkwaves front`` stops, per (gamma, u_+, dx), measured
with the converged front (``bk.velocity_weakening.front``: the chain doubled until c moves
by less than 1e-6, so a front that fades slowly and dies far out is seen dying).

    python docs/scripts/vw_death.py [--dx 0.1 0.05 0.025] [--out FILE]

Bisection in log v_f to 1 % between a v_f whose front lives (status "steady": converged)
and one whose front dies; a v_f whose front neither converged nor died within the
measurement's budget ("undecided") is reported and ends the bisection for that case.
"""

from __future__ import annotations

import argparse
import json
import math
import time

from bkwaves import velocity_weakening as vw

CASES = [(0.3, 0.4), (0.3, 0.6), (0.3, 0.8), (0.0, 0.4), (0.0, 0.6)]
#: gamma = 0 has no v_f*: start the bracket around the chain-20 values of the old table.
GUESS = {(0.0, 0.4): 0.3, (0.0, 0.6): 0.65}
C_ONLY = {"zone": math.inf, "u_minus": math.inf}
FACTOR = 1.01


def classify(u, gamma, dx, v_f, log):
    f = vw.front(u, gamma, dx, v_f, weakening=False, tolerance=C_ONLY, max_seconds=120.0)
    log.append(
        dict(v_f=v_f, status=f.status, reached=f.reached, lengths=f.lengths, c=f.c, why=f.reason)
    )
    return f.status


def death(u, gamma, dx):
    star = vw.v_f_existence(u, gamma)
    guess = star if math.isfinite(star) else GUESS[(gamma, u)]
    lo, hi = 0.5 * guess, 1.0 * guess
    log: list = []
    while classify(u, gamma, dx, lo, log) != "steady":
        if log[-1]["status"] == "undecided":
            return None, None, star, log
        lo, hi = lo / 1.5, lo
    while classify(u, gamma, dx, hi, log) != "dies":
        if log[-1]["status"] == "undecided":
            return lo, None, star, log
        lo, hi = hi, hi * 1.5
    while hi / lo > FACTOR:
        mid = math.sqrt(lo * hi)
        st = classify(u, gamma, dx, mid, log)
        if st == "undecided":
            return lo, hi, star, log  # the bracket so far; the log shows the undecided v_f
        lo, hi = (mid, hi) if st == "steady" else (lo, mid)
    return lo, hi, star, log


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--dx", type=float, nargs="+", default=[0.1, 0.05, 0.025])
    ap.add_argument("--out")
    args = ap.parse_args()
    print(
        "| gamma | u_+ | v_f* | dx | v_f at death (bracket) | / v_f* | v_f/dx | the dying front "
        "stops at x | longest chain | undecided v_f |\n|---|---|---|---|---|---|---|---|---|---|",
        flush=True,
    )
    rows = []
    for gamma, u in CASES:
        for dx in args.dx:
            t0 = time.perf_counter()
            lo, hi, star, log = death(u, gamma, dx)
            und = [r["v_f"] for r in log if r["status"] == "undecided"]
            dead = [r for r in log if r["status"] == "dies" and hi is not None and r["v_f"] == hi]
            where = f"{dead[0]['reached']:.4g}" if dead else "-"
            longest = max(max(r["lengths"]) for r in log)
            mid = math.sqrt(lo * hi) if lo and hi else None
            ratio = "-" if mid is None or not math.isfinite(star) else f"{mid / star:.3f}"
            br = f"{lo:.4g}-{hi:.4g}" if lo and hi else f"{lo}-{hi}"
            print(
                f"| {gamma} | {u} | {star:.4g} | {dx} | {br} | {ratio} | "
                f"{'-' if mid is None else format(mid / dx, '.3g')} | {where} | {longest:g} | "
                f"{', '.join(f'{x:.4g}' for x in und) or '-'} |",
                flush=True,
            )
            rows.append(
                dict(gamma=gamma, u_plus=u, dx=dx, v_f_star=star, bracket=[lo, hi], log=log,
                     seconds=time.perf_counter() - t0)
            )  # fmt: skip
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(rows, fh, indent=1, default=str)


if __name__ == "__main__":
    main()
