"""How long the events of a lattice last, against the runaway bound on one event's
duration (docs/lattice.md, "An event's duration").

- ruptures from the corner of an N x N free lattice (dx = 0.1, v = 0; u_+ and gamma
  across the regimes: pulses, wide slip, gamma near 1): the event's duration in
  crossings of a side, N dx (sound crosses one in N dx: the speed of sound is 1);
- loaded lattices (v = 0.01, a random stress, a drawn threshold; free and periodic): the
  longest of their events, in crossings of the longer side;
- a creeping lattice (gamma >= 1: sliding blocks never re-stick, the event never ends)
  kicked at its centre under the default bound: where it stops, after how many steps
  and how much CPU, against the gamma = 0.45 rupture across the same lattice.

Writes docs/lattice_event_duration.json:

    nice -n 5 python docs/scripts/lattice_event_duration.py
"""

import json
import time
import warnings
from pathlib import Path

import numpy as np

import bkwaves as bk

out = {"corner": [], "loaded": [], "creep": []}
for n in (32, 64, 128):
    for u_plus, gamma in ((0.7, 0.45), (0.95, 0.3), (0.7, 0.9), (0.5, 0.45), (0.4, 0.45)):
        p = bk.Params(gamma=gamma, v=0.0, dx=0.1)
        la = bk.Lattice((n, n), p, u0=u_plus).kick((0, 0), -2.0)
        t0 = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = la.run(t_end=60.0 * n * 0.1, max_events=1, progress=False)
        cat = res.catalog
        row = {
            "n": n,
            "u_plus": u_plus,
            "gamma": gamma,
            "stop": res.stop,
            "duration": float(cat["duration"].iloc[0]) if len(cat) else None,
            "crossing": n * 0.1,
            "blocks_slipped": int(cat["n_blocks"].iloc[0]) if len(cat) else 0,
            "cpu": time.process_time() - t0,
        }
        if row["duration"] is not None:
            row["crossings"] = row["duration"] / row["crossing"]
        out["corner"].append(row)
        print(row, flush=True)

for boundary in ("free", "periodic"):
    doc = {
        "model": "lattice",
        "seed": 3,
        "params": {"gamma": 0.45, "v": 0.01, "dx": 0.2},
        "domain": {"shape": [32, 32], "boundary": boundary},
        "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 0.8},
        "disorder": {"threshold": {"distribution": "uniform", "mean": 1.0, "spread": 0.05}},
        "run": {"t_end": 400.0},
    }
    t0 = time.process_time()
    res = bk.run(doc)
    ev = res.tables["events"]
    done = ev[ev["complete"]]
    row = {
        "boundary": boundary,
        "shape": [32, 32],
        "events": len(done),
        "ruptures": len(res.tables["ruptures"]),
        "longest": float(done["duration"].max()),
        "crossing": 32 * 0.2,
        "longest_crossings": float(done["duration"].max() / (32 * 0.2)),
        "median_crossings": float(np.median(done["duration"]) / (32 * 0.2)),
        "cpu": time.process_time() - t0,
    }
    out["loaded"].append(row)
    print(row, flush=True)

for n in (16, 32):
    p_creep = bk.Params(gamma=1.5, v=0.0, dx=0.1)
    la = bk.Lattice((n, n), p_creep, u0=0.7).kick((n // 2, n // 2), -2.0)
    t0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = la.run(t_end=1e9, progress=False)
    cpu = time.process_time() - t0
    rup = bk.Lattice((n, n), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
    rup.kick((n // 2, n // 2), -2.0)
    t1 = time.process_time()
    r2 = rup.run(t_end=1e9, max_events=1, progress=False)
    row = {
        "n": n,
        "stop": res.stop,
        "t": res.t,
        "bound": bk.lattice.default_max_event_duration((n, n), 0.1, 0.1),
        "steps": res.counters["steps"],
        "cpu": cpu,
        "rupture_duration": float(r2.catalog["duration"].iloc[0]),
        "rupture_steps": r2.counters["steps"],
        "rupture_cpu": time.process_time() - t1,
    }
    out["creep"].append(row)
    print(row, flush=True)

path = Path(__file__).resolve().parents[1] / "lattice_event_duration.json"
path.write_text(json.dumps(out, indent=1) + "\n")
