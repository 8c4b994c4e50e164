"""The chain's velocity-weakening fronts against the step (docs/chain.md, "Step"): c of
the benchmark's front (u_+ = 0.5, gamma = 0.3, dx = 0.05, 400 blocks, beta = inf) at steps
0.1 to 0.00625, Coulomb and v_f = 1e-3 to 1e-6; the relative changes per halving, their
ratios and the default step's c against the finest.

    python docs/scripts/chain_vw_step.py [--out FILE]
"""

from __future__ import annotations

import argparse
import json

from bkwaves import _core

STEPS = (0.1, 0.05, 0.025, 0.0125, 0.00625)
LAWS = (None, 1e-3, 1e-4, 1e-5, 1e-6)


def c_at(v_f, step):
    if v_f is None:
        law, fr = "coulomb", {"gamma": 0.3}
    else:
        law, fr = "velocity_weakening", {"gamma": 0.3, "v_f": v_f}
    return _core.front_measure(0.5, 0.05, 400, step=step, law=law, friction=fr)["c"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/chain_vw_step.json")
    a = ap.parse_args()
    out = {"steps": list(STEPS), "laws": {}}
    for v_f in LAWS:
        cs = [c_at(v_f, s) for s in STEPS]
        changes = [abs(x / y - 1) for x, y in zip(cs[:-1], cs[1:], strict=True)]
        ratios = [x / y for x, y in zip(changes[:-1], changes[1:], strict=True)]
        default = cs[STEPS.index(0.05)] / cs[-1] - 1
        name = "coulomb" if v_f is None else f"v_f={v_f:g}"
        out["laws"][name] = {"c": cs, "changes": changes, "ratios": ratios, "default": default}
        print(name, changes, ratios, default, flush=True)
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
