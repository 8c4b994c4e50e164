"""Cost of noise (issue 14) in both engines, against the noiseless engine on the same state
in the same session: CPU time per engine step and per event.

Free boundary: the state of examples/free_boundary_noise.toml (a ring of length 200, 1000
nodes, u0 = 0.5 + 0.05 f(x) smooth random, gamma = 0.3, v = 1e-2), run to t = 3000.
Chain: the state of examples/chain_noise.toml (a ring of 400 blocks, dx = 0.05,
gamma = 0.3, v = 1e-3, beta = 5, u0 = 0.5 + 0.3 f(x) smooth random), run to t = 600.
Each case is timed by its CPU time (time.process_time() around the engine calls; the
machine is shared), the median of --repeat runs. Prints markdown tables.

Run: python benchmarks/bench_noise.py [--repeat 3] [--model both|chain|free_boundary]
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


CHAIN_CASES = [
    ("none", None),
    ("exponential rate 1e-3, phi0 0.05", {"law": "exponential", "rate": 1e-3, "phi0": 0.05}),
    ("exponential rate 1e-2, phi0 0.05", {"law": "exponential", "rate": 1e-2, "phi0": 0.05}),
    ("exponential rate 1e-1, phi0 0.05", {"law": "exponential", "rate": 1e-1, "phi0": 0.05}),
    ("exponential rate 1, phi0 0.01", {"law": "exponential", "rate": 1.0, "phi0": 0.01}),
    ("constant rate 1e-4", {"law": "constant", "rate": 1e-4}),
    ("power rate 1e-2, exponent 4", {"law": "power", "rate": 1e-2, "exponent": 4.0}),
]


def one_chain(noise, t_end=600.0):
    from bkwaves.config import initial_state, parse_config

    cfg = parse_config(
        {
            "model": "chain",
            "seed": 7,
            "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05, "beta": 5.0},
            "domain": {"blocks": 400, "boundary": "periodic"},
            "initial": {
                "kind": "random",
                "mean": 0.5,
                "amplitude": 0.3,
                "correlation_length": 2.0,
            },
            "run": {"t_end": t_end},
        }
    )
    if noise is not None:
        noise = {**noise, "kick": 0.05}
    ch = bk.Chain(400, cfg.params, "periodic", u0=initial_state(cfg), noise=noise, seed=7)
    eng = ch._engine
    cpu = time.process_time()
    while eng.advance(t_end, 2**62, 2**62) == "steps":
        pass
    cpu = time.process_time() - cpu
    c = eng.counters()
    return cpu, c["steps"], eng.events_finished, eng.noise_counters or (0, 0)


def chain_table(repeat):
    rows = []
    for name, noise in CHAIN_CASES:
        runs = [one_chain(noise) for _ in range(repeat)]
        cpu = statistics.median(r[0] for r in runs)
        _, steps, events, (cand, slips) = runs[0]
        rows.append((name, cpu, steps, events, cand, slips))
    base_step = rows[0][1] / rows[0][2]
    base_event = rows[0][1] / rows[0][3]
    print(
        "| chain noise | CPU s | steps | events | candidates | spontaneous slips "
        "| CPU per step / noiseless | CPU per event / noiseless |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name, cpu, steps, events, cand, slips in rows:
        print(
            f"| {name} | {cpu:.3f} | {steps} | {events} | {cand} | {slips} "
            f"| {cpu / steps / base_step:.2f} | {cpu / max(events, 1) / base_event:.2f} |"
        )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--model", choices=("both", "chain", "free_boundary"), default="both")
    args = ap.parse_args()
    if args.model in ("both", "chain"):
        chain_table(args.repeat)
    if args.model == "chain":
        return
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
