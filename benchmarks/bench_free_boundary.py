"""Cost of the free boundary engine per event, its scaling with the number of shocks,
and the engine against the direct chain.

Run: python benchmarks/bench_free_boundary.py [--chain] [--scaling] [--baseline DIR]
  (default) the physical run: a ring of length L = 0.3/v with two smooth bumps on a
      sinusoidal ramp (the cross-check state of docs/validation.md), gamma = 0.3,
      v = 1e-3, 1000 events;
  --chain: also bk.Chain on the same state (~30 s);
  --scaling: the first event on rings of N nodes (h = 1) whose u0 is flat (exactly, or to
      1e-9): pairs are born at nearly every other node at once, so an event has ~N shocks;
      per-event cost for N = 2000, 20000, 200000;
  --baseline DIR: also run every case with the bkwaves package found in DIR (a `python/`
      tree of another build, e.g. an older commit) in the same session, and compare.
Runs are done in subprocesses (one package per process) and timed by their CPU time
(time.process_time() around the engine call: the machine is shared, so wall time, also
printed, depends on the load).
Prints markdown tables.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import warnings

import numpy as np

import bkwaves as bk

GAMMA, V = 0.3, 1e-3
L = 0.3 / V


def periodic_distance(x, c):
    return np.mod(x - c + 0.5 * L, L) - 0.5 * L


def u0(x):
    w = 40.0 * L / 300.0
    return (
        0.9
        + 0.015 * np.sin(2 * np.pi * x / L)
        + 0.03 * np.exp(-((periodic_distance(x, 0.3 * L) / w) ** 2))
        + 0.025 * np.exp(-((periodic_distance(x, 0.7 * L) / w) ** 2))
    )


def quiet_engine(x, u, boundary="periodic"):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        return bk.FreeBoundary(
            bk.Params(gamma=GAMMA, v=V, dx=1e-3), x, u, boundary, record_path=False
        )


def timed_advance(fb, events):
    """Run to `events` completed events: (wall, cpu) of the engine call alone."""
    t0, c0 = time.perf_counter(), time.process_time()
    fb._engine.advance(float("inf"), 2**62, events)
    return time.perf_counter() - t0, time.process_time() - c0


def fb_run(h, events):
    x = np.arange(int(round(L / h))) * h
    fb = quiet_engine(x, u0(x))
    wall, _ = timed_advance(fb, events)
    return wall, fb._engine.steps, fb._engine.completed_events


def flat_ring(kind, n):
    """u0 = 0.9 on a ring of n nodes (h = 1): exactly ("flat": every pair is born at the
    same time and moves at infinite speed, u_+ = 1) or to 1e-9 ("flat to 1e-9": births
    within 1e-6 of each other at the maxima of the noise)."""
    u = np.full(n, 0.9)
    if kind == "flat to 1e-9":
        u += 1e-9 * np.random.default_rng(1).random(n)
    return np.arange(n) * 1.0, u


# ---------------------------------------------------------------------- worker side
def worker(case):
    """One timed run (in this process's bkwaves), as a dict."""
    if case["what"] == "ring":
        x = np.arange(int(round(L / case["h"]))) * case["h"]
        fb = quiet_engine(x, u0(x))
        events = case["events"]
    else:
        fb = quiet_engine(*flat_ring(case["what"], case["n"]))
        events = 1
    wall, cpu = timed_advance(fb, events)
    ev = fb.result().events
    return {
        "wall": wall,
        "cpu": cpu,
        "steps": fb._engine.steps,
        "events": int(fb._engine.completed_events),
        "shocks": int(ev.n_shocks.sum()),
        "catalog": {k: ev[k].tolist() for k in ("t_start", "t_end", "moment", "n_shocks")},
    }


def run_case(case, tree=None):
    """`worker(case)` in a subprocess importing bkwaves from `tree` (None: this one)."""
    env = dict(os.environ)
    if tree is not None:
        env["PYTHONPATH"] = tree
    out = subprocess.run(
        [sys.executable, __file__, "--worker", json.dumps(case)],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.splitlines()[-1])


def best_of(case, repeat, tree=None):
    """The run of least CPU time out of `repeat` (identical work each time)."""
    runs = [run_case(case, tree) for _ in range(repeat)]
    return min(runs, key=lambda r: r["cpu"])


def catalog_difference(a, b):
    """Largest |difference| of event times and relative difference of slip (NaN if the
    catalogs do not have the same events and shocks)."""
    ca, cb = a["catalog"], b["catalog"]
    if len(ca["t_start"]) != len(cb["t_start"]) or ca["n_shocks"] != cb["n_shocks"]:
        return float("nan"), float("nan")
    dt = max(abs(p - q) for k in ("t_start", "t_end") for p, q in zip(ca[k], cb[k], strict=True))
    ds = max(abs(p / q - 1) for p, q in zip(ca["moment"], cb["moment"], strict=True))
    return dt, ds


# ---------------------------------------------------------------------- tables
def ring_table(baseline):
    print("## free boundary engine: 1000 events on the ring (L = 300, v = 1e-3)")
    print()
    head = "| grid h | events | engine events | CPU | per event | per engine event |"
    line = "|---|---|---|---|---|---|"
    if baseline:
        head += " baseline per event | baseline / this | catalogs: max dt, max slip rel. |"
        line += "---|---|---|"
    print(head)
    print(line)
    for h in (1.0, 0.5, 0.25):
        case = {"what": "ring", "h": h, "events": 1000}
        r = best_of(case, 3)
        row = (
            f"| {h} | {r['events']} | {r['steps']} | {r['cpu']:.3f} s "
            f"| {r['cpu'] / r['events'] * 1e3:.3f} ms | {r['cpu'] / r['steps'] * 1e6:.2f} us |"
        )
        if baseline:
            b = best_of(case, 3, baseline)
            dt, ds = catalog_difference(r, b)
            row += (
                f" {b['cpu'] / b['events'] * 1e3:.3f} ms | {b['cpu'] / r['cpu']:.2f} "
                f"| {dt:.1e}, {ds:.1e} |"
            )
        print(row)


def scaling_table(baseline, sizes, baseline_sizes):
    print()
    print("## free boundary engine: one event with N shocks (flat u0 on a ring of N nodes)")
    print()
    head = "| u0 | nodes | shocks | engine events | CPU (wall) | per engine event |"
    line = "|---|---|---|---|---|---|"
    if baseline:
        head += " baseline CPU (wall) | baseline per engine event | baseline / this | catalogs |"
        line += "---|---|---|---|"
    print(head)
    print(line)
    for kind, kind_sizes in (
        ("flat", sizes),
        ("flat to 1e-9", [n for n in sizes if n <= 20000]),
    ):
        for n in kind_sizes:
            case = {"what": kind, "n": n}
            r = run_case(case)
            row = (
                f"| {kind} | {n} | {r['shocks']} | {r['steps']} "
                f"| {r['cpu']:.3f} s ({r['wall']:.3f} s) | {r['cpu'] / r['steps'] * 1e6:.1f} us |"
            )
            limit = baseline_sizes.get(kind, 0)
            if baseline and n <= limit:
                b = run_case(case, baseline)
                dt, ds = catalog_difference(r, b)
                same = f"max dt {dt:.0e}, max slip rel. {ds:.0e}"
                if r["catalog"] == b["catalog"]:
                    same = "identical"
                row += (
                    f" {b['cpu']:.3f} s ({b['wall']:.3f} s) "
                    f"| {b['cpu'] / b['steps'] * 1e6:.1f} us | {b['cpu'] / r['cpu']:.0f} | {same} |"
                )
            elif baseline:
                row += " not run | | | |"
            print(row)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--chain", action="store_true")
    ap.add_argument("--scaling", action="store_true")
    ap.add_argument("--baseline", metavar="DIR", help="python/ tree of the build to compare")
    ap.add_argument("--sizes", type=int, nargs="+", default=[2000, 20000, 200000])
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        print(json.dumps(worker(json.loads(a.worker))))
        return
    if a.scaling:
        # the baseline is O(N^2): its flat N = 20000 event takes minutes, N = 200000 hours
        scaling_table(a.baseline, a.sizes, {"flat": 20000, "flat to 1e-9": 2000})
    else:
        ring_table(a.baseline)
    if a.chain:
        chain_table()


def chain_run(dx):
    n = int(round(L / dx))
    p = bk.Params(gamma=GAMMA, v=V, dx=dx, beta=0.0)  # as measured in docs/benchmarks.md
    ch = bk.Chain(n, p, "periodic", u0(np.arange(n) * dx))
    t0 = time.perf_counter()
    r = ch.run(max_events=1, progress=False)
    return time.perf_counter() - t0, r.catalog.moment.iloc[0]  # int slip dx


def median(f, repeat):
    out = [f() for _ in range(repeat)]
    return statistics.median(o[0] for o in out), out[0][1], out[0][2]


def chain_table():
    """The same physical run through the Python APIs: first event of bk.Chain against
    bk.FreeBoundary's median cost per event over 1000 events (grid h = 1)."""
    fb_event, _, _ = median(lambda: fb_run(1.0, 1000), 3)
    fb_event /= 1000
    print()
    print("## bk.Chain (first event, median of 3) vs bk.FreeBoundary (per event, h = 1)")
    print()
    print("| dx | blocks | chain | free boundary | ratio | slip chain / fb - 1 |")
    print("|---|---|---|---|---|---|")
    x = np.arange(300) * (L / 300)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        ref = bk.FreeBoundary(bk.Params(gamma=GAMMA, v=V, dx=1.0), x, u0(x), "periodic")
    slip_fb = ref.run(max_events=1).events.moment.iloc[0]
    for dx in (0.1, 0.05, 0.025):
        runs = [chain_run(dx) for _ in range(3)]
        wall = statistics.median(r[0] for r in runs)
        print(
            f"| {dx} | {int(round(L / dx))} | {wall:.3f} s | {fb_event * 1e3:.2f} ms "
            f"| {wall / fb_event:.0f} | {runs[0][1] / slip_fb - 1:+.1e} |"
        )


if __name__ == "__main__":
    main()
