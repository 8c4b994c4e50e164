"""Issue 16, "event location: refine each event time on the step": step against c error and
CPU time with and without a Newton refinement of every located event time, on the three
fronts of bench_front_accuracy.py (docs/benchmarks.md, "Event-time refinement on the step:
not kept").

    python benchmarks/bench_event_refine.py --build PROTOTYPE_PYTHON_DIR [--repeat 5]

The refinement is not in the engine (it did not win); it lives on the branch
``refine-proto`` (commits 7afaff1, cd206b3 and c564f6c, on main at 0656a9e), which reads the
environment: BKWAVES_EVENT_REFINE=N allows up to N Newton redos per located event (0: the
engine as on main, bit for bit),
BKWAVES_STATS=1 prints the step counters of ``front_measure`` on stderr,
BKWAVES_FRONT_CHUNK=K makes ``front_measure`` scan for the crossing every K steps (the
engine's 20000 times up to 20000 steps past the crossing too, a share that jumps with the
step; the c and slip times are the same bits at any K).
PROTOTYPE_PYTHON_DIR is the ``python/`` tree of that branch with its built extension:

    git worktree add /tmp/refine-proto refine-proto && cd /tmp/refine-proto
    cargo build --release -p bkwaves-py
    cp target/release/lib_core.so python/bkwaves/_core.abi3.so   # DIR = /tmp/refine-proto/python

Modes: ``hermite`` (N = 0: the event time is the root of the cubic Hermite dense output,
the step redone to it), ``newton1`` (N = 1: then one Newton step on the true event
function at the redone step's end, g(s) = u_t - v of the block coming to rest or the
stress margin phi - 1 of the neighbour starting to slip, slope h g'(t): one more redo per
event), ``converged`` (N = 4, Newton until the correction is below 1e-13 s: the event time
is the root of the RK4 map, to round-off; its c error is the truncation part).
Each (front, step, mode) runs in a fresh interpreter after a warm-up call, the modes
alternating; medians of the CPU time of the work (``time.process_time``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

# the same fronts, target and run (front_measure from a warm interpreter, its CPU time)
from bench_front_accuracy import FRONTS, LENGTH, TARGET, WORK

ROOT = Path(__file__).resolve().parents[1]
STEPS = (0.4, 0.2, 0.16, 0.14, 0.12, 0.1, 0.05)
MODES = {"hermite": 0, "newton1": 1, "converged": 4}


def once(build: str, refine: int, chunk: int, u, gamma, dx, n, step):
    env = dict(
        os.environ,
        PYTHONPATH=build,
        BKWAVES_EVENT_REFINE=str(refine),
        BKWAVES_STATS="1",
        BKWAVES_FRONT_CHUNK=str(chunk),
    )
    args = [str(x) for x in (u, gamma, dx, n, step)]
    out = subprocess.run(
        [sys.executable, "-c", WORK, *args], env=env, capture_output=True, text=True, check=True
    )
    r = json.loads(out.stdout.strip().splitlines()[-1])
    stats = [line.split() for line in out.stderr.splitlines() if line.startswith("STATS")]
    if not stats:
        raise SystemExit(f"{build}: no STATS line (not the refine-proto build?)")
    # the last STATS line is the measured run: steps, block_steps, switches, refine_redos
    last = stats[-1]
    r["steps"], r["work"], r["redos"] = int(last[2]), int(last[4]), int(last[8])
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True, help="python/ tree of the refine-proto branch")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--steps", type=float, nargs="+", default=STEPS)
    ap.add_argument(
        "--chunk",
        type=int,
        default=500,
        help="steps per run call of front_measure (the engine's is 20000: up to 20000 steps "
        "past the crossing are timed too)",
    )
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "python"))
    import bkwaves as bk

    print(f"load average at start: {os.getloadavg()}; chunk {args.chunk} steps")
    summary = []
    for u, gamma, dx in FRONTS:
        n = round(LENGTH / dx)
        c_ref = bk.tip_solve(u, dx=dx, gamma=gamma)["c"]
        print(f"\nfront u_+ = {u}, gamma = {gamma}, dx = {dx} ({n} blocks), tip c = {c_ref:.12f}")
        print(
            "| step | c error hermite | c error newton1 | c error converged | "
            "CPU hermite | CPU newton1 | newton1 / hermite | steps hermite | steps newton1 | "
            "block updates newton1 / hermite |"
        )
        print("|---|---|---|---|---|---|---|---|---|---|")
        rows = {}
        for step in args.steps:
            cpu = {m: [] for m in MODES}
            res = {}
            for _ in range(args.repeat):
                for m, k in MODES.items():
                    r = once(args.build, k, args.chunk, u, gamma, dx, n, step)
                    cpu[m].append(r["cpu"])
                    if m in res and res[m]["c"] != r["c"]:
                        raise SystemExit(f"c not reproducible: {m} {step}")
                    res[m] = r
            med = {m: statistics.median(v) for m, v in cpu.items()}
            err = {m: res[m]["c"] / c_ref - 1.0 for m in MODES}
            rows[step] = (err, med)
            print(
                f"| {step} | {err['hermite']:+.2e} | {err['newton1']:+.2e} | "
                f"{err['converged']:+.2e} | {med['hermite']:.4f} s | {med['newton1']:.4f} s | "
                f"{med['newton1'] / med['hermite']:.2f} | {res['hermite']['steps']} | "
                f"{res['newton1']['steps']} ({res['newton1']['redos']} refinement redos) | "
                f"{res['newton1']['work'] / res['hermite']['work']:.3f} |",
                flush=True,
            )
        best = {}
        for m in ("hermite", "newton1"):
            ok = [s for s in args.steps if abs(rows[s][0][m]) <= TARGET]
            s = max(ok)
            best[m] = (s, rows[s][0][m], rows[s][1][m])
        summary.append(((u, gamma, dx), best))
    print("\nmatched accuracy (|c error| <= 1e-6): the coarsest step of the grid, each mode")
    print("| front | hermite: step, c error, CPU | newton1: step, c error, CPU | gain |")
    print("|---|---|---|---|")
    for front, best in summary:
        (sh, eh, th), (sn, en, tn) = best["hermite"], best["newton1"]
        print(
            f"| {front} | {sh}, {eh:+.1e}, {th:.4f} s | {sn}, {en:+.1e}, {tn:.4f} s | "
            f"{1 - tn / th:+.0%} |"
        )
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
