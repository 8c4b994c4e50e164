"""The run-cost estimate (bkwaves.limits, bkwaves._cost) against measured runs.

Each case is estimated, then run once in this process (imports warmed up by a first
small run) and its CPU time measured (time.process_time: these machines are shared, CPU
time is what the run costs). Prints one JSON line per case: estimate, measured, ratio,
and the engine's counters beside the estimated work. The expensive cases' figures are
stated in docs/benchmarks.md ("Run-cost estimate") and checked by tests/test_estimate.py.

    python benchmarks/bench_estimate.py                 # every case (~5 min of CPU)
    python benchmarks/bench_estimate.py --cases front_1e6 chain_run_1e7
    python benchmarks/bench_estimate.py --list
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import bkwaves as bk

U, GAMMA, DX = 0.6, 0.3, 0.05  # the front of examples/chain_front.toml


def _front(blocks):
    from bkwaves.chain import front as measure
    from bkwaves.chain import front_cost

    def run():
        measure(U, GAMMA, DX, blocks)
        return {}

    return front_cost(U, GAMMA, DX, blocks)[1], run


def _chain_front(n, dx=DX):
    p = bk.Params(gamma=GAMMA, v=0.0, dx=dx)
    c = 1.0 / math.sqrt(1.0 - U * U)
    t_end = n * dx / c + 5.0
    ch = bk.Chain(n, p, "free", np.full(n, U))
    ch.kick(0, -2.0, 0.0)
    from bkwaves.chain import default_max_event_duration

    _, wall, _ = ch._estimate(t_end, None, default_max_event_duration(n, dx), 0)

    def run():
        ch.run(t_end=t_end, progress=False)
        return ch._engine.counters()

    return wall, run


def config_case(doc):
    """(estimate, run) of a config dict run to a NetCDF file (snapshots and tables)."""
    from bkwaves.config import parse_config
    from bkwaves.limits import estimate
    from bkwaves.runner import run as run_config

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cfg = parse_config(doc)
    est = estimate(cfg)

    def run():
        out = Path(tempfile.mkdtemp()) / "out.nc"
        s = run_config(cfg, out)
        return s.extra.get("counters") or {}

    return est.wall_s, run


def _chain_doc(blocks, v, t_end=None, max_events=None, value=U, kick=True, dx=0.1, **extra):
    doc = {
        "model": "chain",
        "params": {"gamma": GAMMA, "v": v, "dx": dx},
        "domain": {"blocks": blocks},
        "initial": {"kind": "uniform", "value": value},
        "run": {k: x for k, x in (("t_end", t_end), ("max_events", max_events)) if x},
    }
    if kick:
        doc["triggers"] = [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}]
    doc.update(extra)
    return doc


def _example(name):
    import tomllib

    path = Path(__file__).parents[1] / "examples" / f"{name}.toml"
    doc = tomllib.loads(path.read_text())
    doc.pop("output", None)
    out = tomllib.loads(path.read_text()).get("output", {})
    doc["output"] = {k: x for k, x in out.items() if k != "path"}
    if "initial" in doc and doc["initial"].get("kind") == "file":
        doc["initial"]["path"] = str(path.parent / doc["initial"]["path"])
    return doc


EXAMPLES = [
    "bristol_board",
    "chain_front",
    "chain_loading",
    "chain_noise",
    "chain_velocity_weakening",
    "free_boundary_disordered",
    "free_boundary_noise",
    "free_boundary_random",
    "free_boundary_source",
]

#: name -> a function returning (estimated seconds, run); cheap ones first
CASES = {
    **{f"example_{e}": (lambda e=e: config_case(_example(e))) for e in EXAMPLES},
    "v0_quiet_t_end_1e6": lambda: config_case(_chain_doc(3000, 0.0, t_end=1e6)),
    "velocity_weakening_v_f_1e-9": lambda: config_case(
        _chain_doc(
            200, 0.0, t_end=2e-5, friction={"law": "velocity_weakening", "v_f": 1e-9}, dx=0.1
        )
    ),
    "fb_v_1e-12_max_events": lambda: config_case(
        {
            "model": "free_boundary",
            "params": {"gamma": GAMMA, "v": 1e-12, "dx": 0.01},
            "domain": {"length": 100.0, "grid": 500},
            "initial": {"kind": "uniform", "value": 0.5},
            "run": {"max_events": 3},
            "output": {"snapshot_every": 1e9},
        }
    ),
    "chain_front_2e4_dx_0.5": lambda: _chain_front(20000, dx=0.5),
    "front_1e5": lambda: _front(100_000),
    "front_1e6": lambda: _front(1_000_000),
    "config_front_4e5": lambda: config_case(
        _chain_doc(400_000, 0.0, t_end=400_000 * 0.05 / 1.25 + 5.0, dx=0.05)
    ),
    "chain_1e4_uniform_20_events": lambda: config_case(
        _chain_doc(10_000, 1e-3, max_events=20, value=0.5, kick=False)
    ),
    "front_1e7": lambda: _front(10_000_000),
    "chain_run_1e7": lambda: _chain_front(10_000_000),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", default=list(CASES))
    ap.add_argument("--list", action="store_true")
    args = ap.parse_args(argv)
    if args.list:
        print("\n".join(CASES))
        return
    warm, run = config_case(_chain_doc(200, 0.0, t_end=5.0, output={"snapshot_every": 1.0}))
    run()
    for name in args.cases:
        est, run = CASES[name]()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.process_time()
            counters = run()
            cpu = time.process_time() - t0
        row = {"case": name, "estimate_s": round(est, 4), "cpu_s": round(cpu, 4)}
        row["ratio"] = round(est / cpu, 3) if cpu > 0 else None
        row["counters"] = counters
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
