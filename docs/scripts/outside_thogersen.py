"""An outside reference for the chain's front speed: Thogersen's public 1D rupture code.

kjetilthogersen/1D-rupture (`run_continuum.py`, the model of Thogersen et al.,
PRE 100, 043004 (2019)) integrates, for a sliding block,

    U_tt = tau - gbar U + U_xx + frictionLaw,      slip when that force >= 1,

with Euler-Cromer steps of fixed dt and the static threshold tested once a step. With
u = tau - gbar U, t' = sqrt(gbar) t, x' = sqrt(gbar) x this is the paper's chain
(eq. dimless) at v = 0: phi = u - u_x'x' is the force, slip at phi >= 1, the prestress
tau = u_+, its grid spacing dx/sqrt(gbar) is our dx, and a viscous friction alpha U_t
(through its `frictionLaw` hook) is our 2 gamma u_t' with alpha = 2 gamma sqrt(gbar).
We use gbar = 1, where the map is the identity.

Its code is not part of bkwaves: clone it yourself and pass the folder,

    git clone https://github.com/kjetilthogersen/1D-rupture /tmp/1D-rupture
    python docs/scripts/outside_thogersen.py /tmp/1D-rupture

The script measures c from the recorded unstick times over a window of blocks far from
the trigger, for dt = dx/10, dx/20, ..., and compares with `bk.chain.front` (the
event-located chain) at the same (u_+, gamma, dx), with the CPU time of each.
Results: docs/validation.md ("An outside code") and docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np


class Viscous:
    """A friction law for the outside code's hook: force alpha U_t on sliding blocks."""

    def __init__(self, alpha: float):
        self.alpha = alpha

    def getFriction(self, x, u, v, tau, stuck):  # noqa: N802 (the outside code's name)
        return self.alpha * v

    def step(self, x, u, v, tau, stuck, dt):
        return None


def outside_front(repo: str, u_plus: float, gamma: float, dx: float, n: int, dt: float):
    sys.path.insert(0, repo)
    from run_continuum import run_continuum  # the outside code, from the user's clone

    x = dx * np.arange(n, dtype=float)
    tau = np.full(n, u_plus)
    tau[:2] = 1.05  # nucleation: the first two blocks start above the threshold
    tmax = 0.8 * x[-1]  # the front runs faster than 1 (c > 1): it has crossed by then
    t0 = time.process_time()
    out = run_continuum(
        x,
        tau,
        tau.copy(),
        dt,
        1.0,
        output_interval=10**9,
        tmax=tmax,
        beta=0.0,
        frictionLaw=Viscous(2.0 * gamma),
    )
    cpu = time.process_time() - t0
    ts = out["unstickTime"]
    a, b = int(0.4 * n), int(0.7 * n)
    sel = np.arange(a, b + 1)
    ok = np.isfinite(ts[sel])
    if ok.sum() < 10:
        return None, cpu
    slope = np.polyfit(x[sel][ok], ts[sel][ok], 1)[0]
    return 1.0 / slope, cpu


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("repo", help="a clone of kjetilthogersen/1D-rupture")
    ap.add_argument("--u-plus", type=float, default=0.6)
    ap.add_argument("--gamma", type=float, default=0.3)
    ap.add_argument("--dx", type=float, default=0.1)
    ap.add_argument("--blocks", type=int, default=1500)
    ap.add_argument("--halvings", type=int, default=5)
    args = ap.parse_args(argv)
    import bkwaves as bk

    t0 = time.process_time()
    ref = bk.chain.front(args.u_plus, args.gamma, args.dx)
    cpu_bk = time.process_time() - t0
    rows = []
    for k in range(args.halvings + 1):
        dt = args.dx / 10 / 2**k
        c, cpu = outside_front(args.repo, args.u_plus, args.gamma, args.dx, args.blocks, dt)
        rows.append(
            {"dt": dt, "c": c, "rel_err": None if c is None else c / ref.c - 1, "cpu_s": cpu}
        )
        print(json.dumps(rows[-1]), flush=True)
    print(
        json.dumps(
            {
                "bkwaves_c": ref.c,
                "bkwaves_cpu_s": cpu_bk,
                "u_plus": args.u_plus,
                "gamma": args.gamma,
                "dx": args.dx,
            }
        )
    )


if __name__ == "__main__":
    main()
