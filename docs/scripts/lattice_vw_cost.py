"""The cost of velocity weakening on the lattice (docs/lattice.md, "Velocity weakening
on the lattice"): ruptures from the centre (u_+ = 0.6, gamma = 0.3, dx = 0.1, step 0.05,
v_f = 1e-4), Coulomb and velocity weakening, block-steps from the engine's counters and
CPU seconds, one run each; and the 48 x 32 run in quarters of a time unit (how many
blocks slide, how slowly, what each quarter cost, and where the onsets' block-steps went:
the engine's onset_stats); and the first slip times of the 48 x 32 rupture to t = 2 at
steps 0.05 and 0.025 against step 0.0125.

    python docs/scripts/lattice_vw_cost.py [--out FILE]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import bkwaves as bk

CASES = [((24, 16), 3.0), ((24, 16), 5.0), ((34, 23), 4.0), ((48, 32), 3.0), ((48, 32), 5.0)]
CAUSES = ("first", "growth", "redo")


def params(v_f, step=None):
    if v_f is None:
        return bk.Params(gamma=0.3, v=0.0, dx=0.1)
    law = bk.friction.law("velocity_weakening", v_f=v_f)
    return bk.Params(gamma=0.3, v=0.0, dx=0.1, friction_law=law)


def rupture(shape, v_f, step=0.05):
    nx, ny = shape
    return bk.Lattice(shape, params(v_f), u0=0.6, step=step).kick((nx // 2, ny // 2), -2.0)


def split(stats):
    """The onsets' block-steps by cause (first integration of a step, growth, redo up to
    an event): the patch's groups, of which their first (loose) passes, and the runs."""
    return (
        {
            f"{what}_{c}": stats[f"{what}_block_steps_{c}"]
            for what in ("group", "loose", "runs")
            for c in CAUSES
        }
        | {"integrations_" + c: stats["integrations_" + c] for c in CAUSES}
        | {
            "onset_steps": stats["steps"],
            "turned": stats["turned_block_steps"],
        }
    )


def one(shape, t_end, v_f):
    la = rupture(shape, v_f)
    c0 = time.process_time()
    res = la.run(t_end=t_end, progress=False)
    cpu = time.process_time() - c0
    out = {"cpu_s": cpu, "slips": len(res.slips), **res.counters}
    if v_f is not None:
        out["onsets"] = split(la._engine.onset_stats())
    return out


def phases(v_f, t_end=5.0, dt=0.25):
    la = rupture((48, 32), v_f)
    rows, prev, c0 = [], 0, time.process_time()
    before = split(la._engine.onset_stats())
    for t in np.arange(dt, t_end + 1e-9, dt):
        res = la.run(t_end=float(t), progress=False)
        s = np.abs(la.u_t[la.modes != 0])  # speed over the ground (v = 0)
        bs = res.counters["block_steps"]
        now = split(la._engine.onset_stats())
        onsets = {k: now[k] - before[k] for k in now}
        before = now
        rows.append(
            {
                "t": float(t),
                "block_steps": bs - prev,
                "cpu_s": time.process_time() - c0,
                "sliding": int(s.size),
                "below_1e-2": int((s < 1e-2).sum()),
                "median_speed": float(np.median(s)) if s.size else 0.0,
                "switches": res.counters["switches"],
                "onsets": onsets,
            }
        )
        prev = bs
    return rows


def accuracy(shape=(48, 32), t_end=2.0, steps=(0.05, 0.025, 0.0125)):
    """The largest change of the first slip times against the finest step."""
    times = [
        rupture(shape, 1e-4, s).run(t_end=t_end, progress=False).first_slip_times() for s in steps
    ]
    ok = np.isfinite(times[-1])
    out = {"shape": list(shape), "t_end": t_end, "steps": list(steps), "slipped": int(ok.sum())}
    out["same_blocks_slipped"] = all(bool(np.array_equal(np.isfinite(t), ok)) for t in times)
    out["max_change_vs_finest"] = [float(np.max(np.abs(t[ok] - times[-1][ok]))) for t in times[:-1]]
    return out


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
    out["accuracy"] = accuracy()
    print(json.dumps(out["accuracy"]), flush=True)
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
