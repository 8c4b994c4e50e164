"""The hostile-input campaign (issue 27; docs/reliability.md): generated run configs
(every TOML table, every friction law, noise law, initial kind and model) and calls of
the public Python API with absurd-but-legal and illegal values, each under a wall-time
bound, classified by outcome.

    python benchmarks/hostile.py --seed 27 --configs 1500 --calls 1000
    python benchmarks/hostile.py --seed 5 --configs 40 --calls 40 --json out.json

Cases are generated from (seed, index) alone, so any one is rerun by its index
(``--only config:17``). They run in a worker process (``--worker``) that imports bkwaves
once; the parent gives each case ``--timeout`` seconds of the worker's CPU time (and ten
times that of wall time: a loaded machine does not make a hang), kills and restarts the
worker on a hang or a crash. Each case runs with ``LIMITS["warn_wall_s"]`` at a tenth
of the bound and the LongRunWarning raised as an error, so a run estimated long stops
before any work. Classes:

- ok: finished (a run, or a value returned);
- error: a one-line ``ParameterError`` or ``ConvergenceError`` naming the parameter (one
  of the keys or arguments the case changed, or the key it names first);
- unnamed: such an error whose message names none of them, or spans several lines;
- traceback: any other exception (its type and first line are kept);
- crash: the worker died by a signal;
- hang: no answer within the bound, and no warning;
- warned-long: a LongRunWarning before any work (estimated beyond a tenth of the bound);
- silent-wrong: finished without a warning, but not as asked (:func:`check_config_run`,
  :func:`check_call`): a config's run that did not end at run.t_end (or ran past
  run.max_events), misses or adds a snapshot of output.snapshot_every, whose first
  snapshot is not its [initial] state, or whose attributes record other params, seed
  or friction law than the config's; an API run without the snapshot times or the
  t_end it was given.

The worker dies with the campaign (PR_SET_PDEATHSIG on Linux, and it ends when its
parent's pipe closes): killing the parent leaves no worker running.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import re
import select
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve()
ROOT = HERE.parents[1]

# ---------------------------------------------------------------- values
ILLEGAL = [
    math.nan,
    math.inf,
    -math.inf,
    -1,
    -1.0,
    0,
    0.0,
    "x",
    "",
    "1.5",
    "a\x00b",
    True,
    False,
    [],
    [1, 2],
    {},
    {"a": 1},
    2**63 - 1,
    -(2**63),
    2**64,
    1e308,
    -1e308,
]
ABSURD = [
    1e-300,
    5e-324,
    1e-310,
    1e-100,
    1e-30,
    1e-12,
    1e-9,
    1e-6,
    0.999999,
    1.000001,
    2,
    3,
    5,
    7,
    1e6,
    1e8,
    1e12,
    1e30,
    1e100,
    1e300,
    10**6,
    10**9,
    0.5,
    1.5,
]
#: per key: values that are legal but extreme
LEGAL = {
    "t_end": [1e-30, 1e-100, 1e-310, 1e-5, 1e6, 1e12, 5e-324],
    "max_events": [1, 2, 10**6, 2**31],
    "v": [0.0, 1e-12, 1e-9, 0.5, 0.99],
    "gamma": [0.0, 1e-9, 0.999, 1.0, 5.0, 450.0],
    "dx": [1e-4, 1e-3, 0.5, 0.99, 5.0],
    "beta": [0.0, 1e-9, 1e9, math.inf],
    "v_f": [1e-9, 1e-6, 10.0, 1e6],
    "blocks": [2, 3, 16, 10**5, 10**7],
    "grid": [5, 6, 10**5, 10**7],
    "shape": [[1, 2], [2, 1], [3, 3], [64, 64], [10**4, 10**4], [10**6, 10**6]],
    "spacing": [1e-300, 1e-6, 0.5, 99.0, 1e6],
    "dy": [1e-4, 0.05, 0.5, 1e6],
    "line": [[[0, 0], [5, 5]], [[0, 0], [0, 0]], [[3, 0], [3, 7]]],
    "disc": [[[2, 2], 0.0], [[2, 2], 0.3], [[0, 0], 1e9]],
    "arrivals": [True, False],
    "length": [1e-6, 1e-3, 1e6, 1e12],
    "correlation_length": [1e-300, 1e-6, 1e3, 1e8, 1e300],
    "amplitude": [0.0, 1e-12, 0.99, 2.0, 1e6],
    "mean": [-1e6, -1.0, 0.0, 0.999, 1.0, 2.0],
    "value": [-1e6, -0.5, 0.0, 0.99999, 1.0, 1.5],
    "snapshot_every": [1e-9, 1e-3, 1e9],
    "snapshot_events": [1, 10**6],
    "rate": [0.0, 1e-9, 1e3, 1e12],
    "phi0": [1e-300, 1e-3, 1e3],
    "exponent": [0.0, 1e-3, 50.0, 1e3],
    "kick": [0.0, 1e-9, 1e6],
    "velocity": [-1e6, -1.0, 1e-12, 1e6],
    "time": [0.0, 1e-300, 1e6, 1e300],
    "spread": [0.0, 1e-9, 0.5, 1.0, 10.0],
    "width": [1e-300, 1e-6, 1e6, 1e300],
    "center": [-1e300, 0.0, 1e300],
    "height": [-1e6, 0.0, 0.5, 1e6],
    "step": [1e-9, 1e-3, 0.5, 2.0],
    "step_tolerance": [1e-300, 1e-12, 1.0],
    "max_event_slips": [1, 2, 2**40],
    "max_event_duration": [1e-300, 1e-3, 1e30],
    "seed": [0, 1, 2**63 - 1, 2**63],
}


def _value(rng: random.Random, key: str):
    r = rng.random()
    if r < 0.45 and key in LEGAL:
        return rng.choice(LEGAL[key])
    if r < 0.75:
        return rng.choice(ABSURD)
    return rng.choice(ILLEGAL)


# ---------------------------------------------------------------- configs
NOISE_LAWS = ("constant", "exponential", "power", "table")
INITIAL = ("uniform", "ramp", "random", "bumps", "file")
LAWS = ("coulomb", "velocity_weakening")


def _noise(rng, model):
    law = rng.choice(NOISE_LAWS)
    t = {"law": law, "rate": rng.choice([1e-3, 1e-2, 0.1])}
    if law == "exponential":
        t["phi0"] = 0.05
    elif law == "power":
        t["exponent"] = 2.0
    elif law == "table":
        t["u"] = [0.0, 0.5, 1.0]
        t["g"] = [0.0, 0.5, 1.0]
    if model in ("chain", "lattice") and rng.random() < 0.5:
        t["kick"] = 0.05
    return t


def _initial(rng, model, files):
    planar = model in ("lattice", "free_boundary_2d")
    kind = rng.choice(INITIAL if not planar else ("uniform", "ramp", "random", "file"))
    if kind == "uniform":
        t = {"kind": kind, "value": 0.6 if model == "chain" else 0.5}
    elif kind == "ramp":
        t = {"kind": kind, "start": 0.4, "end": 0.7 if model == "chain" else 0.6}
    elif kind == "random":
        t = {"kind": kind, "mean": 0.5, "amplitude": 0.2, "correlation_length": 2.0}
    elif kind == "bumps":
        t = {"kind": kind, "base": 0.4, "bumps": [{"center": 5.0, "width": 2.0, "height": 0.3}]}
    else:
        t = {"kind": kind, "path": str(files[rng.choice(sorted(files))])}
    if model in ("chain", "lattice") and rng.random() < 0.2:
        t["velocity"] = rng.choice([0.0, 0.5])
    return t


def _config(rng, files) -> dict:
    model = rng.choice(["chain", "chain", "free_boundary", "lattice", "free_boundary_2d"])
    doc: dict = {"model": model, "title": "hostile"}
    if rng.random() < 0.5:
        doc["seed"] = rng.randrange(100)
    if model == "chain":
        if rng.random() < 0.15:
            doc["physical"] = {"preset": "bristol_board", "V": 1e-6}
            if rng.random() < 0.5:
                doc["input_units"] = "dimensionless"
        else:
            doc["params"] = {"gamma": 0.3, "v": rng.choice([0.0, 1e-3]), "dx": 0.1}
            if rng.random() < 0.4:
                doc["params"]["beta"] = 5.0
        law = rng.choice(LAWS)
        if law != "coulomb" or rng.random() < 0.3:
            doc["friction"] = {"law": law}
            if law == "velocity_weakening":
                doc["friction"]["v_f"] = 0.01
        doc["domain"] = {"blocks": rng.choice([20, 50, 200]), "boundary": rng.choice(
            ["free", "fixed", "periodic"])}  # fmt: skip
        if rng.random() < 0.3:
            prop = rng.choice(["threshold", "mass", "loader", "coupling"])
            doc["disorder"] = {prop: {"distribution": "uniform", "mean": 1.0, "spread": 0.1}}
        if rng.random() < 0.6:
            doc["triggers"] = [{"time": 0.0, "block": 0, "kind": rng.choice(["kick", "release"])}]
            if doc["triggers"][0]["kind"] == "kick":
                doc["triggers"][0]["velocity"] = 2.0
    elif model == "lattice":
        doc["params"] = {"gamma": 0.3, "v": rng.choice([0.0, 1e-3]), "dx": 0.1}
        nx, ny = rng.choice([(10, 8), (20, 20), (5, 40)])
        b = ["free", "fixed", "periodic"]
        doc["domain"] = {
            "shape": [nx, ny],
            "boundary": rng.choice(b) if rng.random() < 0.5 else [rng.choice(b), rng.choice(b)],
        }
        if rng.random() < 0.3:
            doc["domain"]["dy"] = rng.choice([0.1, 0.15])
        if rng.random() < 0.3:
            prop = rng.choice(["threshold", "mass", "loader"])
            doc["disorder"] = {
                prop: rng.choice(
                    [
                        {"distribution": "uniform", "mean": 1.0, "spread": 0.1},
                        {"mean": 1.0, "amplitude": 0.05, "correlation_length": 0.3},
                    ]
                )
            }
        if rng.random() < 0.6:
            place = rng.choice(
                [
                    {"block": [0, 0]},
                    {"line": [[0, 0], [nx - 1, 0]]},
                    {"disc": [[nx // 2, ny // 2], 0.2]},
                ]
            )
            doc["triggers"] = [{"time": 0.0, **place, "kind": rng.choice(["kick", "release"])}]
            if doc["triggers"][0]["kind"] == "kick":
                doc["triggers"][0]["velocity"] = 2.0
    elif model == "free_boundary_2d":
        doc["params"] = {"gamma": 0.3, "v": 1e-2, "dx": 1e-3}
        b = ["free", "periodic"]
        doc["domain"] = {
            "shape": rng.choice([[16, 16], [40, 24]]),
            "spacing": rng.choice([0.5, 1.0]),
            "boundary": rng.choice(b) if rng.random() < 0.5 else [rng.choice(b), rng.choice(b)],
        }
        if rng.random() < 0.3:
            doc["speed"] = {"u_plus": [0.5, 0.6, 0.7], "c": [1.15, 1.25, 1.4]}
        if rng.random() < 0.3:
            doc["disorder"] = {
                "threshold": {"mean": 1.0, "amplitude": 0.05, "correlation_length": 3.0}
            }
    else:
        doc["params"] = {"gamma": 0.3, "v": 1e-2, "dx": 1e-3}
        doc["domain"] = {"length": 40.0, "grid": 201, "boundary": rng.choice(["free", "periodic"])}
        if rng.random() < 0.3:
            doc["speed"] = {"u_plus": [0.5, 0.6, 0.7], "c": [1.15, 1.25, 1.4]}
        if rng.random() < 0.3:
            doc["disorder"] = {
                "threshold": {"mean": 1.0, "amplitude": 0.05, "correlation_length": 10.0}
            }
    doc["initial"] = _initial(rng, model, files)
    blocks = model in ("chain", "lattice")
    if rng.random() < 0.3 and "disorder" not in doc or blocks and rng.random() < 0.2:
        doc["noise"] = _noise(rng, model)
    run = {}
    if rng.random() < 0.8:
        run["t_end"] = 5.0 if blocks else 200.0
    if not run or rng.random() < 0.3:
        run["max_events"] = 2
    if blocks and rng.random() < 0.2:
        key = rng.choice(["step", "integrator", "max_event_slips", "max_event_duration"])
        run[key] = {"step": 0.02, "integrator": "midpoint", "max_event_slips": 10**5,
                    "max_event_duration": 1e3}[key]  # fmt: skip
    doc["run"] = run
    out = {}
    if rng.random() < 0.6:
        out["snapshot_every"] = 1.0 if blocks else 50.0
    elif rng.random() < 0.5:
        out["snapshot_events"] = 1
    if rng.random() < 0.3:
        out["units"] = rng.choice(["native", "dimensionless"])
    if model in ("lattice", "free_boundary_2d") and rng.random() < 0.3:
        out["arrivals"] = True
    doc["output"] = out
    # the hostile part: 0 to 3 leaves set, deleted or added
    changed = []
    for _ in range(rng.choice([0, 1, 1, 2, 2, 3])):
        leaves = list(_leaves(doc))
        path, _ = rng.choice(leaves)
        op = rng.random()
        parent = doc
        for k in path[:-1]:
            parent = parent[k]
        key = path[-1]
        name = key if isinstance(key, str) else str(path[-2])
        if op < 0.1 and isinstance(parent, dict) and key != "model":
            del parent[key]
        elif op < 0.15 and isinstance(parent, dict):
            parent[rng.choice(["typo", "gama", "t_ned", "blocks_"])] = 1.0
            name = "typo|gama|t_ned|blocks_"
        else:
            parent[key] = _value(rng, name)
        changed.append(name)
    return {"doc": doc, "keys": changed}


def _leaves(d, prefix=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield prefix + (k,), v
            yield from _leaves(v, prefix + (k,))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield prefix + (i,), v
            yield from _leaves(v, prefix + (i,))


# ---------------------------------------------------------------- API calls
def _api_table():
    """name -> (argument names, defaults, function of a kwargs dict)."""
    import numpy as np

    import bkwaves as bk
    from bkwaves import chain as chain_mod
    from bkwaves import disorder, noise, stats, theory, velocity_weakening

    p0 = dict(gamma=0.3, v=0.0, dx=0.1)
    x = np.linspace(0.0, 20.0, 101)

    def chain(kw):
        args = {"n": 40, "u0": 0.6, **kw}
        params = bk.Params(**{**p0, **{k: args.pop(k) for k in list(args) if k in p0}})
        n = args.pop("n")
        run = {k: args.pop(k) for k in list(args) if k in ("t_end", "max_events", "snapshots")}
        kick = {k: args.pop(k) for k in list(args) if k in ("block", "du_t")}
        ch = bk.Chain(n, params, **args)
        ch.kick(kick.get("block", 0), kick.get("du_t", -2.0))
        return ch.run(**{"t_end": 3.0, **run}, progress=False)

    def fb(kw):
        args = dict(kw)
        params = bk.Params(
            gamma=args.pop("gamma", 0.3), v=args.pop("v", 1e-2), dx=args.pop("dx", 1e-3)
        )
        run = {k: args.pop(k) for k in list(args) if k in ("t_end", "max_events", "snapshots")}
        f = bk.FreeBoundary(params, args.pop("x", x), args.pop("u0", 0.9 - 1e-3 * (x - 10) ** 2),
                            **args)  # fmt: skip
        return f.run(**{"max_events": 1, **run})

    def cfg_run(kw):
        doc = {
            "model": "chain",
            "params": {**p0, "v": kw.pop("v", 0.0)},
            "domain": {"blocks": kw.pop("blocks", 30)},
            "initial": {"kind": "uniform", "value": kw.pop("value", 0.6)},
            "run": {"t_end": kw.pop("t_end", 2.0)},
        }
        from bkwaves.config import parse_config

        return bk.run(parse_config(doc), **kw)

    return {
        "Params": (["gamma", "v", "dx", "beta"], lambda kw: bk.Params(**{**p0, **kw})),
        "Params.from_physical": (
            ["mass", "k_c", "k_p", "f_static", "f_kinetic", "alpha", "V", "spacing"],
            lambda kw: bk.Params.from_physical(
                **{
                    "mass": 1e-3,
                    "k_c": 1e3,
                    "k_p": 10.0,
                    "f_static": 1.0,
                    "f_kinetic": 0.5,
                    "alpha": 0.01,
                    "V": 1e-3,
                    "spacing": 1e-3,
                    **kw,
                }  # fmt: skip
            ),
        ),
        "Chain.run": (
            [
                "n",
                "u0",
                "gamma",
                "v",
                "dx",
                "step",
                "boundary",
                "integrator",
                "threshold",
                "mass",
                "t_end",
                "max_events",
                "snapshots",
                "block",
                "du_t",
                "seed",
            ],  # fmt: skip
            chain,
        ),
        "FreeBoundary.run": (
            [
                "gamma",
                "v",
                "dx",
                "x",
                "u0",
                "boundary",
                "creep",
                "tol",
                "threshold",
                "t_end",
                "max_events",
                "snapshots",
                "record_path",
            ],  # fmt: skip
            fb,
        ),
        "run": (["v", "blocks", "value", "t_end", "snapshots"], cfg_run),
        "front_speed": (
            ["u_plus", "dx", "gamma", "method"],
            lambda kw: bk.front_speed(**{"u_plus": 0.5, **kw}),
        ),  # fmt: skip
        "traveling_wave": (
            ["u_plus", "gamma"],
            lambda kw: bk.traveling_wave(**{"u_plus": 0.5, "gamma": 0.3, **kw}),
        ),  # fmt: skip
        "tip_solve": (
            ["c", "degree", "decay", "dx", "gamma"],
            lambda kw: bk.tip_solve(**{"c": 1.5, **kw}),
        ),  # fmt: skip
        "chain.front": (
            ["u_plus", "gamma", "dx", "blocks", "step", "beta"],
            lambda kw: chain_mod.front(
                **{"u_plus": 0.6, "gamma": 0.3, "dx": 0.1, "blocks": 80, **kw}
            ),  # fmt: skip
        ),
        "chain.smooth_random_stress": (
            ["n", "dx", "mean", "amplitude", "correlation", "seed"],
            lambda kw: chain_mod.smooth_random_stress(**{"n": 50, "dx": 0.1, **kw}),
        ),
        "disorder.draw": (
            ["distribution", "n", "mean", "spread", "seed"],
            lambda kw: disorder.draw(
                **{"distribution": "uniform", "n": 10, "spread": 0.1, "seed": 1, **kw}
            ),
        ),  # fmt: skip
        "disorder.thresholds": (
            ["n", "sigma", "distribution", "seed"],
            lambda kw: disorder.thresholds(**{"n": 10, "sigma": 0.1, **kw}),
        ),  # fmt: skip
        "disorder.marched_speed": (
            ["u_plus", "gamma", "dx"],
            lambda kw: disorder.marched_speed(**{"u_plus": 0.6, **kw}),
        ),  # fmt: skip
        "noise.rate_density": (
            ["u", "noise"],
            lambda kw: noise.rate_density(
                kw.get("u", 0.5), kw.get("noise", {"law": "constant", "rate": 1.0})
            ),
        ),  # fmt: skip
        "noise.kick_threshold": (
            ["u", "dx", "gamma"],
            lambda kw: noise.kick_threshold(**{"u": 0.6, "dx": 0.1, "gamma": 0.3, **kw}),
        ),  # fmt: skip
        "noise.release_stress": (
            ["dx", "gamma"],
            lambda kw: noise.release_stress(**{"dx": 0.1, "gamma": 0.3, **kw}),
        ),  # fmt: skip
        "stats.b_value": (
            ["mags", "m_c", "dm"],
            lambda kw: stats.b_value(**{"mags": [1.0, 2.0, 3.0, 1.5], **kw}),
        ),  # fmt: skip
        "stats.magnitudes": (
            ["sizes", "kind"],
            lambda kw: stats.magnitudes(**{"sizes": [1.0, 2.0], **kw}),
        ),  # fmt: skip
        "stats.power_law_exponent": (
            ["sizes", "s_min"],
            lambda kw: stats.power_law_exponent(**{"sizes": [1.0, 2.0, 5.0, 9.0], **kw}),
        ),  # fmt: skip
        "stats.recurrence_times": (
            ["times", "positions", "window"],
            lambda kw: stats.recurrence_times(**{"times": [1.0, 2.0, 4.0], **kw}),
        ),  # fmt: skip
        "theory.wavelength": (
            ["u_plus", "gamma", "v", "c"],
            lambda kw: theory.wavelength(**{"u_plus": 0.6, "gamma": 0.3, "v": 1e-2, **kw}),
        ),  # fmt: skip
        "theory.iterate_map": (
            ["a0", "v", "gamma", "n"],
            lambda kw: theory.iterate_map(**{"a0": 0.5, "v": 1e-2, "gamma": 0.3, "n": 3, **kw}),
        ),  # fmt: skip
        "theory.restick_time": (
            ["u_plus", "gamma", "v", "c"],
            lambda kw: theory.restick_time(**{"u_plus": 0.9, "gamma": 0.85, "v": 1e-5, **kw}),
        ),  # fmt: skip
        "theory.profile": (
            ["z", "u_plus", "gamma", "c"],
            lambda kw: theory.profile(**{"z": [0.0, 1.0], "u_plus": 0.6, "gamma": 0.3, **kw}),
        ),  # fmt: skip
        "theory.min_wavelength": (
            ["gamma", "v"],
            lambda kw: theory.min_wavelength(**{"gamma": 0.3, "v": 1e-2, **kw}),
        ),  # fmt: skip
        "velocity_weakening.front": (
            ["u_plus", "gamma", "dx", "v_f", "length", "step"],
            lambda kw: velocity_weakening.front(
                **{"u_plus": 0.6, "gamma": 0.3, "dx": 0.1, "v_f": 0.01, "length": 5.0, **kw}
            ),
        ),  # fmt: skip
        "velocity_weakening.min_friction": (
            ["gamma", "v_f"],
            lambda kw: velocity_weakening.min_friction(**{"gamma": 0.3, "v_f": 0.01, **kw}),
        ),  # fmt: skip
        "friction.law": (
            ["name", "v_f", "gamma"],
            lambda kw: bk.friction.law(kw.pop("name", "velocity_weakening"), **kw),
        ),  # fmt: skip
        "presets.bristol_board": (["V"], lambda kw: bk.presets.bristol_board(**kw)),
        "loaded_pulse": (
            ["u_plus", "gamma", "v", "dx", "window"],
            lambda kw: chain_mod.loaded_pulse(
                **{"u_plus": 0.6, "gamma": 0.5, "v": 1e-3, "dx": 0.1, **kw}
            ),
        ),  # fmt: skip
    }


# ---------------------------------------------------------------- cases
def case(seed: int, kind: str, index: int, files: dict, api=None):
    """The case ``index`` of ``kind`` ("config" or "call") for ``seed``."""
    rng = random.Random(f"{seed}:{kind}:{index}")
    if kind == "config":
        return _config(rng, files)
    names = sorted(api)
    name = rng.choice(names)
    args = api[name][0]
    chosen = rng.sample(args, k=min(len(args), rng.choice([1, 1, 2])))
    return {"name": name, "kw": {a: _value(rng, a) for a in chosen}, "keys": chosen}


def _files(tmp: Path) -> dict:
    import numpy as np

    files = {
        "ok.npy": tmp / "ok.npy",
        "short.txt": tmp / "short.txt",
        "pickled.npy": tmp / "pickled.npy",
        "junk.npy": tmp / "junk.npy",
        "missing.npy": tmp / "missing.npy",
    }
    np.save(files["ok.npy"], np.full(200, 0.5))
    files["short.txt"].write_text("0.5 0.5\n")
    np.save(files["pickled.npy"], np.array([{"a": 1}], dtype=object), allow_pickle=True)
    files["junk.npy"].write_bytes(b"\x93NUMPY junk" * 3)
    return files


def _named(msg: str, keys) -> bool:
    """The message names one of the changed keys, or starts with a parameter's name
    (``params.gamma: ...``, ``invalid u_plus = ...``)."""
    if any(name in msg for k in keys for name in str(k).split("|")):
        return True
    first = msg.removeprefix("invalid ").split()[0] if msg.strip() else ""
    return bool(re.fullmatch(r"[A-Za-z_][\w.\[\]/]*:?", first))


def check_config_run(cfg, doc: dict, summary, out: Path) -> str | None:
    """What a config's finished run did otherwise than its config asked, read back from
    its output (None: nothing). Expected values come from the config alone: snapshot
    times t_k = k dt through t_end (the last within 1e-9 dt of t_end), the [initial]
    state (drawn again with the seed the output records), params and friction law."""
    import dataclasses

    import numpy as np

    import bkwaves as bk
    from bkwaves.config import initial_state
    from bkwaves.runner import _Units

    scale = float(_Units(cfg).t(1.0))  # output time units per time unit
    ds, _ = bk.load(out)
    try:
        t = np.asarray(ds.t.values, dtype=float) / scale
        u_first = np.asarray(ds.u.values[0]) if t.size else None
        attrs = dict(ds.attrs)
    finally:
        ds.close()
    end = summary.t / scale
    stop = summary.extra.get("stop")
    found = []
    if cfg.max_events is not None and summary.events > cfg.max_events:
        found.append(f"{summary.events} events, run.max_events = {cfg.max_events}")
    by_time = cfg.t_end is not None and (cfg.max_events is None or summary.events < cfg.max_events)
    if by_time and stop in (None, "time") and not math.isclose(end, cfg.t_end, rel_tol=1e-9):
        found.append(f"ended at t = {end!r}, run.t_end = {cfg.t_end!r}")
    if cfg.snapshot_every is not None and cfg.t_end is not None:
        dt = cfg.snapshot_every
        last = min(cfg.t_end, end)
        want = dt * np.arange(int(math.floor(last / dt + 1e-9)) + 1)
        if math.isclose(last, cfg.t_end, rel_tol=1e-12):
            want = np.minimum(want, cfg.t_end)
        if t.size != want.size or not np.allclose(t, want, rtol=1e-9, atol=1e-9 * dt):
            missing = sorted(
                set(np.round(want / dt).astype(int)) - set(np.round(t / dt).astype(int))
            )
            found.append(
                f"{t.size} snapshots, output.snapshot_every = {dt!r} to t = {last!r} asks "
                f"{want.size} (k dt for k = 0..{want.size - 1}; missing k: {missing[:5]})"
            )
    if u_first is not None and t[0] == 0.0:
        seed = attrs.get("seed")
        seeded = dataclasses.replace(cfg, seed=int(seed)) if str(seed).strip() else cfg
        u0 = initial_state(seeded)
        if u0.shape != u_first.shape or not np.allclose(u_first, u0, rtol=1e-12, atol=1e-12):
            found.append("the first snapshot is not the [initial] state")
    params = json.loads(attrs.get("params", "{}"))
    for key in ("gamma", "v", "dx"):
        want_p = float(getattr(cfg.params, key))
        if key not in params or not math.isclose(float(params[key]), want_p, rel_tol=1e-12):
            found.append(f"attribute params.{key} = {params.get(key)!r}, config {want_p!r}")
    law = (doc.get("friction") or {}).get("law", "coulomb") if cfg.model == "chain" else None
    if isinstance(law, str):
        recorded = json.loads(attrs.get("friction_law", "{}")).get("law")
        if recorded != law:
            found.append(f"attribute friction_law {recorded!r}, config friction.law {law!r}")
    return "; ".join(found) or None


def check_call(name: str, kw: dict, result) -> str | None:
    """What an API run did otherwise than asked (None: nothing): ``Chain.run`` ends at
    its t_end (unless stopped by events) with a snapshot at every requested time up to
    it; ``FreeBoundary.run`` has a snapshot at every requested time up to its end."""
    import numpy as np

    if name not in ("Chain.run", "FreeBoundary.run") or result is None:
        return None
    found = []
    if name == "Chain.run":
        end = float(result.t)
        t_end = kw.get("t_end", 3.0)
        if result.stop == "time" and not math.isclose(end, float(t_end), rel_tol=1e-12):
            found.append(f"ended at t = {end!r}, t_end = {t_end!r}")
    else:
        end = float(result.snapshots.t.values[-1]) if result.snapshots is not None else -math.inf
    if "snapshots" in kw and kw["snapshots"] is not None:
        asked = np.sort(np.atleast_1d(np.asarray(kw["snapshots"], dtype=float)).ravel())
        asked = asked[asked <= end]
        got = np.array([]) if result.snapshots is None else result.snapshots.t.values
        absent = [a for a in asked if not np.any(np.isclose(got, a, rtol=1e-12, atol=0.0))]
        if absent:
            found.append(f"snapshots {absent[:3]} asked, not taken")
    return "; ".join(found) or None


def _die_with_parent() -> None:
    """The worker ends when the campaign does (Linux: PR_SET_PDEATHSIG = SIGKILL)."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass  # elsewhere: the worker ends when its stdin (the parent's pipe) closes
    if os.getppid() == 1:  # the parent died before the call above
        os._exit(1)


def worker(seed: int, timeout: float) -> None:
    """Read "kind index" lines, run each case, print one JSON result line per case."""
    import warnings

    import bkwaves as bk
    from bkwaves.config import parse_config
    from bkwaves.limits import LIMITS, LongRunWarning
    from bkwaves.runner import run

    LIMITS["warn_wall_s"] = timeout / 10.0
    tmp = Path(tempfile.mkdtemp(prefix="bkhostile"))
    files = _files(tmp)
    api = _api_table()
    errors = (bk.ParameterError, bk.ConvergenceError)
    for line in sys.stdin:
        kind, index = line.split()
        index = int(index)
        if kind == "sleep":  # busy for INDEX seconds (tests that it dies with its parent)
            time.sleep(index)
            continue
        c = case(seed, kind, index, files, api)
        t0 = time.perf_counter()
        out = {"kind": kind, "index": index, "keys": [str(k) for k in c["keys"]]}
        try:
            with warnings.catch_warnings(record=True) as warned:
                warnings.simplefilter("always")
                warnings.simplefilter("error", LongRunWarning)
                if kind == "config":
                    cfg = parse_config(c["doc"], base_dir=tmp)
                    path = tmp / f"c{index}.nc"
                    s = run(cfg, path)
                else:
                    result = api[c["name"]][1](dict(c["kw"]))
            out["class"] = "ok"
            if not warned:  # (a deviation announced by a warning is not silent)
                if kind == "config":
                    wrong = check_config_run(cfg, c["doc"], s, path)
                else:
                    wrong = check_call(c["name"], c["kw"], result)
                if wrong:
                    out["class"], out["msg"] = "silent-wrong", wrong[:300]
        except LongRunWarning as e:
            out["class"], out["msg"] = "warned-long", str(e)[:300]
        except errors as e:
            msg = str(e)
            ok = "\n" not in msg.strip() and _named(msg, c["keys"])
            out["class"], out["msg"] = ("error" if ok else "unnamed"), msg[:300]
        except BaseException as e:  # noqa: BLE001 - everything else is a finding
            out["class"] = "traceback"
            out["msg"] = f"{type(e).__name__}: {str(e).splitlines()[0] if str(e) else ''}"[:300]
        out["wall_s"] = round(time.perf_counter() - t0, 3)
        if kind == "call":
            out["name"] = c["name"]
        print(json.dumps(out, default=str), flush=True)


class _Worker:
    def __init__(self, seed, timeout):
        self.p = subprocess.Popen(
            [
                sys.executable,
                str(HERE),
                "--worker",
                "--seed",
                str(seed),
                "--timeout",
                str(timeout),
            ],  # fmt: skip
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
            start_new_session=True,
        )

    def cpu(self) -> float:
        """CPU seconds the worker has used (Linux /proc; wall time elsewhere)."""
        try:
            fields = Path(f"/proc/{self.p.pid}/stat").read_text().rsplit(")", 1)[1].split()
            return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
        except (OSError, ValueError, IndexError):
            return time.monotonic()

    def ask(self, kind, index, timeout):
        """The worker's answer, or None past ``timeout`` seconds of its CPU time (a
        loaded machine does not make a hang) or ten times that of wall time."""
        self.p.stdin.write(f"{kind} {index}\n")
        self.p.stdin.flush()
        cpu0, wall0 = self.cpu(), time.monotonic()
        while True:
            ready, _, _ = select.select([self.p.stdout], [], [], 0.25)
            if ready:
                line = self.p.stdout.readline()
                return json.loads(line) if line else "died"
            if self.cpu() - cpu0 > timeout or time.monotonic() - wall0 > 10 * timeout:
                return None

    def kill(self):
        try:
            os.killpg(self.p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.p.wait()


def campaign(seed, n_configs, n_calls, timeout, only=None, log=None):
    jobs = [("config", i) for i in range(n_configs)] + [("call", i) for i in range(n_calls)]
    if only:
        jobs = [(k, int(i)) for k, i in (o.split(":") for o in only)]
    results = []
    w = None
    start_bound = timeout + 60.0  # the worker's imports come first
    for kind, index in jobs:
        if w is None:
            w, bound = _Worker(seed, timeout), start_bound
        else:
            bound = timeout
        r = w.ask(kind, index, bound)
        if r is None:
            w.kill()
            w = None
            r = {"kind": kind, "index": index, "class": "hang"}
        elif r == "died":
            code = w.p.wait()
            w = None
            cls = "crash" if code < 0 else "traceback"
            r = {"kind": kind, "index": index, "class": cls, "msg": f"exit {code}"}
        results.append(r)
        if log:
            print(json.dumps(r, default=str), file=log, flush=True)
    if w is not None:
        w.p.stdin.close()
        w.p.wait()
    return results


CLASSES = ("ok", "error", "unnamed", "traceback", "crash", "hang", "warned-long", "silent-wrong")


def summary(results) -> dict:
    out = {}
    for kind in ("config", "call"):
        rows = [r for r in results if r["kind"] == kind]
        out[kind] = {c: sum(r["class"] == c for r in rows) for c in CLASSES}
        out[kind]["total"] = len(rows)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=27)
    ap.add_argument("--configs", type=int, default=1500)
    ap.add_argument("--calls", type=int, default=1000)
    ap.add_argument("--timeout", type=float, default=20.0, help="CPU seconds per case")
    ap.add_argument("--only", nargs="*", help="cases as kind:index (config:17 call:3)")
    ap.add_argument("--json", help="write every result and the summary here")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        _die_with_parent()
        worker(args.seed, args.timeout)
        return
    t0 = time.time()
    results = campaign(args.seed, args.configs, args.calls, args.timeout, args.only, sys.stderr)
    s = summary(results)
    bad = ("unnamed", "traceback", "crash", "hang", "silent-wrong")
    findings = [r for r in results if r["class"] in bad]
    doc = {"seed": args.seed, "timeout": args.timeout, "summary": s, "findings": findings,
           "wall_s": round(time.time() - t0, 1)}  # fmt: skip
    if args.json:
        Path(args.json).write_text(json.dumps({**doc, "results": results}, default=str))
    print(json.dumps({k: v for k, v in doc.items() if k != "findings"}))
    for f in findings:
        print(json.dumps(f, default=str))


if __name__ == "__main__":
    main()
