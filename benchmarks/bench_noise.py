"""Cost of noise in the free boundary engine (issue 14): CPU time per engine step and per
event with spontaneous nucleation, against the noiseless engine on the same state in the
same session.

The state is that of examples/free_boundary_noise.toml (a ring of length 200, 1000 nodes,
u0 = 0.5 + 0.05 f(x) smooth random, gamma = 0.3, v = 1e-2), run to t = 3000. Each case is
timed by its CPU time (time.process_time() around the engine calls; the machine is
shared), the median of --repeat runs. Prints a markdown table.

Run: python benchmarks/bench_noise.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

import numpy as np

import bkwaves as bk
from bkwaves.config import _smooth_random

CASES = [
    ("none", None),
    ("exponential rate 1e-3, phi0 0.05", {"law": "exponential", "rate": 1e-3, "phi0": 0.05}),
    ("exponential rate 1e-2, phi0 0.05", {"law": "exponential", "rate": 1e-2, "phi0": 0.05}),
    ("exponential rate 1e-1, phi0 0.05", {"law": "exponential", "rate": 1e-1, "phi0": 0.05}),
    ("constant rate 1e-3", {"law": "constant", "rate": 1e-3}),
    ("power rate 1e-2, exponent 4", {"law": "power", "rate": 1e-2, "exponent": 4.0}),
]


def one(noise, t_end=3000.0):
    x = np.linspace(0.0, 200.0, 1001)[:-1]
    u0 = 0.5 + 0.05 * _smooth_random(x, 25.0, np.random.default_rng(7), True)
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fb = bk.FreeBoundary(p, x, u0, "periodic", noise=noise, seed=7)
    eng = fb._engine
    cpu = time.process_time()
    while eng.advance(t_end, 100_000, 2**62) == "steps":
        pass
    cpu = time.process_time() - cpu
    ev = eng.events()
    counters = eng.noise_counters or (0, 0)
    return cpu, eng.steps, len(ev["t_start"]), counters


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    rows = []
    for name, noise in CASES:
        runs = [one(noise) for _ in range(args.repeat)]
        cpu = statistics.median(r[0] for r in runs)
        _, steps, events, (cand, nuc) = runs[0]
        rows.append((name, cpu, steps, events, cand, nuc))
    base = rows[0][1] / rows[0][2]
    print(
        "| noise | CPU s | engine steps | events | candidates | nucleations "
        "| CPU per step / noiseless |"
    )
    print("|---|---|---|---|---|---|---|")
    for name, cpu, steps, events, cand, nuc in rows:
        print(
            f"| {name} | {cpu:.3f} | {steps} | {events} | {cand} | {nuc} "
            f"| {cpu / steps / base:.2f} |"
        )


if __name__ == "__main__":
    main()
