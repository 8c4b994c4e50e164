"""The cost of velocity weakening on the lattice (docs/lattice.md, "Velocity weakening
on the lattice"): ruptures from the centre (u_+ = 0.6, gamma = 0.3, dx = 0.1, step 0.05,
v_f = 1e-4), Coulomb and velocity weakening, block-steps from the engine's counters and
CPU seconds, one run each; and the 48 x 32 run in quarters of a time unit (how many
blocks slide, how slowly, what each quarter cost).

    python docs/scripts/lattice_vw_cost.py [--out FILE]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import bkwaves as bk

CASES = [((24, 16), 3.0), ((34, 23), 4.0), ((48, 32), 3.0), ((48, 32), 5.0)]


def params(v_f):
    if v_f is None:
        return bk.Params(gamma=0.3, v=0.0, dx=0.1)
    law = bk.friction.law("velocity_weakening", v_f=v_f)
    return bk.Params(gamma=0.3, v=0.0, dx=0.1, friction_law=law)


def rupture(shape, v_f):
    nx, ny = shape
    return bk.Lattice(shape, params(v_f), u0=0.6).kick((nx // 2, ny // 2), -2.0)


def one(shape, t_end, v_f):
    la = rupture(shape, v_f)
    c0 = time.process_time()
    res = la.run(t_end=t_end, progress=False)
    cpu = time.process_time() - c0
    return {"cpu_s": cpu, "slips": len(res.slips), **res.counters}


def phases(v_f, t_end=5.0, dt=0.25):
    la = rupture((48, 32), v_f)
    rows, prev, c0 = [], 0, time.process_time()
    for t in np.arange(dt, t_end + 1e-9, dt):
        res = la.run(t_end=float(t), progress=False)
        s = np.abs(la.u_t[la.modes != 0])  # speed over the ground (v = 0)
        bs = res.counters["block_steps"]
        rows.append(
            {
                "t": float(t),
                "block_steps": bs - prev,
                "cpu_s": time.process_time() - c0,
                "sliding": int(s.size),
                "below_1e-2": int((s < 1e-2).sum()),
                "median_speed": float(np.median(s)) if s.size else 0.0,
                "switches": res.counters["switches"],
            }
        )
        prev = bs
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/lattice_vw_cost.json")
    a = ap.parse_args()
    out = {"runs": [], "phases": {}}
    for shape, t_end in CASES:
        row = {"shape": list(shape), "t_end": t_end}
        for name, v_f in (("coulomb", None), ("vw", 1e-4)):
            row[name] = one(shape, t_end, v_f)
        vw, co = row["vw"], row["coulomb"]
        row["onset_block_steps_per_slip"] = (vw["block_steps"] - co["block_steps"]) / vw["slips"]
        print(json.dumps(row), flush=True)
        out["runs"].append(row)
    for name, v_f in (("coulomb", None), ("vw", 1e-4)):
        out["phases"][name] = phases(v_f)
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
