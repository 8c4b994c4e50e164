"""Cost of a velocity-weakening front against the Coulomb front as v_f -> 0 (docs/benchmarks.md).

    python benchmarks/bench_vw_onset.py [--blocks 400] [--repeat 3] [--v-f 1e-1 ... 1e-6]
        [--label NAME] [-o OUT.json]

One front (the `bkwaves front` experiment: uniform u_+ = 0.5 at v = 0, gamma = 0.3,
dx = 0.05, block 0 kicked) on one chain of `--blocks` blocks (400: 20 units long), measured
with Coulomb friction and with velocity weakening at each v_f, in this process, each
``--repeat`` times; the median CPU time (``time.process_time``) of each front and its
ratio to the Coulomb front's median from the same run are printed and written as JSON
with the front speed c and the engine's work counters (steps, block-steps). At v_f << dx
the front's onset is stiff (the friction falls over the speed v_f, so a block that has just
slipped accelerates at the rate theta/v_f); the ratio says what that costs.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

from bkwaves import _core

U_PLUS, GAMMA, DX = 0.5, 0.3, 0.05


def front(law: str, v_f: float | None, blocks: int) -> tuple[float, dict]:
    friction = {"gamma": GAMMA} if v_f is None else {"gamma": GAMMA, "v_f": v_f}
    t0 = time.process_time()
    r = _core.front_measure(U_PLUS, DX, blocks, law=law, friction=friction)
    return time.process_time() - t0, r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--blocks", type=int, default=400)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--v-f", type=float, nargs="+", default=[1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6])
    ap.add_argument("--label", default="this build")
    ap.add_argument("-o", "--out", default=None)
    a = ap.parse_args()
    cases = [("coulomb", None)] + [("velocity_weakening", v) for v in a.v_f]
    rows = []
    for law, v_f in cases:
        cpu, last = [], None
        for _ in range(a.repeat):
            t, last = front(law, v_f, a.blocks)
            cpu.append(t)
        rows.append(
            {
                "law": law,
                "v_f": v_f,
                "v_f_over_dx": None if v_f is None else v_f / DX,
                "cpu_s": statistics.median(cpu),
                "cpu_all": cpu,
                "c": last["c"],
                "block_steps": int(last["block_steps"]),
                "steps": int(last.get("steps", 0)),
            }
        )
    base = rows[0]
    print(f"{a.label}: u_+ = {U_PLUS}, gamma = {GAMMA}, dx = {DX}, {a.blocks} blocks")
    print(f"{'law':>20} {'v_f':>8} {'cpu s':>9} {'/Coulomb':>9} {'block-steps':>12} {'/C':>8} c")
    for r in rows:
        r["cpu_ratio"] = r["cpu_s"] / base["cpu_s"]
        r["block_steps_ratio"] = r["block_steps"] / base["block_steps"]
        v = "-" if r["v_f"] is None else f"{r['v_f']:.0e}"
        print(
            f"{r['law']:>20} {v:>8} {r['cpu_s']:9.4f} {r['cpu_ratio']:9.2f} "
            f"{r['block_steps']:12d} {r['block_steps_ratio']:8.2f} {r['c']:.12f}"
        )
    if a.out:
        with open(a.out, "w") as f:
            json.dump(
                {
                    "label": a.label,
                    "u_plus": U_PLUS,
                    "gamma": GAMMA,
                    "dx": DX,
                    "blocks": a.blocks,
                    "repeat": a.repeat,
                    "rows": rows,
                },
                f,
                indent=1,
            )


if __name__ == "__main__":
    main()
