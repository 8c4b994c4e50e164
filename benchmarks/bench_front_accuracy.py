"""One front at matched accuracy: step against c error and CPU time, this build against a
baseline build, on the fronts of issue 16 (docs/benchmarks.md).

    python benchmarks/bench_front_accuracy.py [--baseline BASELINE_PYTHON_DIR] [--repeat 3]

For each front (u_+, gamma, dx) a chain of L/dx blocks (L = 25) is kicked at one end
(``_core.front_measure``, beta = inf: the paper's model) and c is measured on the window;
its error is against the finite-dx tip solution (``bk.tip_solve``), the converged
finite-dx value. Each (front, step, build) runs in a fresh interpreter, the builds
alternating, after a warm-up call (the first call imports numpy); medians of the CPU time
of the work (``time.process_time``). The matched
accuracy is 1e-6: the coarsest step whose c is within it, this build's time there against
the baseline's at its default step (0.05). BASELINE_PYTHON_DIR holds a ``bkwaves`` package
with its built extension (see bench_engine_ab.py).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FRONTS = ((0.6, 0.45, 0.00625), (0.5, 0.3, 0.0125), (0.9, 0.45, 0.025))
STEPS = (0.4, 0.2, 0.1, 0.05, 0.025)
LENGTH = 25.0
TARGET = 1e-6
DEFAULT_STEP = 0.05

WORK = r"""
import json, sys, time
from bkwaves import _core
u, gamma, dx, n, step = (float(x) for x in sys.argv[1:6])
# warm up: the first call imports numpy for its results (~0.1 s of CPU, not the engine's)
_core.front_measure(u, dx, 16, heal=False, step=step, friction={"gamma": gamma})
t0 = time.process_time()
r = _core.front_measure(u, dx, int(n), heal=False, step=step, friction={"gamma": gamma})
cpu = time.process_time() - t0
print(json.dumps({"cpu": cpu, "c": r["c"], "block_steps": r["block_steps"]}))
"""


def once(pythonpath: str, u: float, gamma: float, dx: float, n: int, step: float) -> dict:
    env = dict(os.environ, PYTHONPATH=pythonpath)
    args = [str(x) for x in (u, gamma, dx, n, step)]
    out = subprocess.run(
        [sys.executable, "-c", WORK, *args], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--baseline", help="directory holding the baseline bkwaves package")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "python"))
    import bkwaves as bk

    this = str(ROOT / "python")
    builds = {"this": this} | ({"baseline": args.baseline} if args.baseline else {})
    print(f"load average at start: {os.getloadavg()}")
    summary = []
    for u, gamma, dx in FRONTS:
        n = round(LENGTH / dx)
        c_ref = bk.tip_solve(u, dx=dx, gamma=gamma)["c"]
        print(f"\nfront u_+ = {u}, gamma = {gamma}, dx = {dx} ({n} blocks), tip c = {c_ref:.12f}")
        print("| step | c error | CPU this build | CPU baseline | baseline / this | same c |")
        print("|---|---|---|---|---|---|")
        rows = {}
        for step in STEPS:
            cpu = {k: [] for k in builds}
            cs = {k: set() for k in builds}
            for _ in range(args.repeat):
                for k, path in builds.items():
                    r = once(path, u, gamma, dx, n, step)
                    cpu[k].append(r["cpu"])
                    cs[k].add(r["c"])
            med = {k: statistics.median(v) for k, v in cpu.items()}
            c = next(iter(cs["this"]))
            err = c / c_ref - 1.0
            rows[step] = (err, med)
            base = med.get("baseline", float("nan"))
            same = cs["this"] == cs.get("baseline", cs["this"])
            print(
                f"| {step} | {err:+.2e} | {med['this']:.3f} s | {base:.3f} s | "
                f"{base / med['this']:.2f} | {same} |",
                flush=True,
            )
        ok = [s for s in STEPS if abs(rows[s][0]) <= TARGET]
        if ok and "baseline" in builds:
            s = max(ok)
            t_new = rows[s][1]["this"]
            t_old = rows[DEFAULT_STEP][1]["baseline"]
            summary.append((u, gamma, dx, s, rows[s][0], t_new, rows[DEFAULT_STEP][0], t_old))
    if summary:
        print("\nmatched accuracy (|c error| <= 1e-6): this build at its coarsest such step")
        print("against the baseline at its default step 0.05")
        print("| front | step | c error | CPU | baseline c error (0.05) | baseline CPU |", end="")
        print(" speed-up |")
        print("|---|---|---|---|---|---|---|")
        for u, g, dx, s, e, t, e0, t0 in summary:
            print(
                f"| ({u}, {g}, {dx}) | {s} | {e:+.1e} | {t:.3f} s | {e0:+.1e} | {t0:.3f} s | "
                f"{t0 / t:.2f} |"
            )
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
