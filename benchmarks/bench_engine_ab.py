"""The chain engine against an older build of itself, on the same work (docs/benchmarks.md).

    python benchmarks/bench_engine_ab.py BASELINE_PYTHON_DIR [--repeat 5]

BASELINE_PYTHON_DIR holds a ``bkwaves`` package with its built extension (e.g.
``git archive <commit> python | tar -x -C /tmp/base`` and the ``_core.abi3.so`` built
from that commit copied into ``/tmp/base/python/bkwaves``). Each workload runs in a fresh
interpreter, the two builds alternating, and the medians of the CPU time of the work
(``time.process_time``: less sensitive than wall time to other jobs on a shared machine)
are compared:

(a) one front across 4000 blocks (dx = 0.01, gamma = 0.3, u_+ = 0.6, the uniform Coulomb
chain at v = 0), (b) 40 loading cycles of 2000 blocks (dx = 0.05, gamma = 0.3, v = 1e-4,
smooth random stress, free ends), (c) = (b) with per-block thresholds (this build only:
the per-block engine's cost against the uniform one).
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

WORK = r"""
import json, sys, time
import numpy as np
import bkwaves as bk
from bkwaves import _core
from bkwaves.chain import smooth_random_stress
kind = sys.argv[1]
if kind == "front":
    t0 = time.process_time()
    try:
        r = _core.front_measure(0.6, 0.01, 4000, friction={"gamma": 0.3, "beta": 0.0}, heal=False)
    except TypeError:
        r = _core.front_measure(0.6, 0.3, 0.01, 4000, beta=0.0, heal=False)
    cpu = time.process_time() - t0
    print(json.dumps({"cpu": cpu, "check": r["c"]}))
else:
    n = 2000
    u0 = smooth_random_stress(n, 0.05, mean=0.8, amplitude=0.15, correlation=2.0, seed=1)
    kw = {}
    if kind == "cycles_threshold":
        kw["threshold"] = 1.0 + 0.05 * np.random.default_rng(2).standard_normal(n)
    ch = bk.Chain(n, bk.Params(gamma=0.3, v=1e-4, dx=0.05, beta=0.0), u0=u0, **kw)
    t0 = time.process_time()
    r = ch.run(t_end=1e9, max_events=40, progress=False)
    cpu = time.process_time() - t0
    print(json.dumps({"cpu": cpu, "check": float(r.u.sum())}))
"""


def once(pythonpath: str, kind: str) -> dict:
    env = dict(os.environ, PYTHONPATH=pythonpath)
    out = subprocess.run(
        [sys.executable, "-c", WORK, kind], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("baseline", help="directory holding the baseline bkwaves package")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    this = str(ROOT / "python")
    rows = []
    for kind in ("front", "cycles"):
        t_new, t_old, checks = [], [], set()
        for _ in range(args.repeat):
            a = once(args.baseline, kind)
            b = once(this, kind)
            t_old.append(a["cpu"])
            t_new.append(b["cpu"])
            checks.add((a["check"], b["check"]))
        m_old, m_new = statistics.median(t_old), statistics.median(t_new)
        same = all(x == y for x, y in checks)
        rows.append((kind, m_old, m_new, m_new / m_old, same))
        print(
            f"{kind}: baseline {m_old:.3f} s, this build {m_new:.3f} s, ratio {m_new / m_old:.3f}, "
            f"same result: {same}",
            flush=True,
        )
    t_u, t_t = [], []
    for _ in range(args.repeat):
        t_u.append(once(this, "cycles")["cpu"])
        t_t.append(once(this, "cycles_threshold")["cpu"])
    mu, mt = statistics.median(t_u), statistics.median(t_t)
    print(
        f"cycles, per-block thresholds vs uniform (this build): {mt:.3f} s vs {mu:.3f} s, "
        f"ratio {mt / mu:.3f}"
    )
    print("| workload | baseline | this build | ratio | same result |")
    print("|---|---|---|---|---|")
    for kind, a, b, r, same in rows:
        print(f"| {kind} | {a:.3f} s | {b:.3f} s | {r:.3f} | {same} |")


if __name__ == "__main__":
    main()
