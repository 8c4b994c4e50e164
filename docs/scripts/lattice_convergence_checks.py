"""Convergence of the lattice's derived numbers (docs/lattice.md, "Derived: the curvature
coefficient" and "Derived: the anisotropy"; issue 22): at u_+ = 0.6, gamma = 0.45,
dx = 0.1,

- D along an axis, -(dc/dgamma)/(2c) by a one-sided difference in gamma: steps 0.02,
  0.01 (bk.theory.curvature_coefficient's), 0.005;
- the independent numpy chain (bkwaves._curved_chain) off the axes, (4, 1), (3, 1),
  (2, 1), (3, 2): c at its default length and twice as long and with twice the steps per
  slip, D by the difference in kappa at +-0.05 (the API's) and +-0.025, and on the chain
  twice as long;
- the diagonal (1, 1): the same against the tip solver's chain at dx/sqrt(2), and D with
  twice the steps per slip.

    nice -n 5 python docs/scripts/lattice_convergence_checks.py docs/lattice_convergence_checks.json

About 5 minutes of CPU.
"""

import json
import sys
import time

import bkwaves as bk
from bkwaves import _curved_chain as cc

U, G, DX = 0.6, 0.45, 0.1


def d_axis(e):
    c = [float(bk.front_speed(U, dx=DX, gamma=G + i * e)) for i in range(3)]
    return -((-3 * c[0] + 4 * c[1] - c[2]) / (2 * e)) / (2 * c[0])


def d_of(qp, c_ref, eps=0.05, **kw):
    cs = [cc.front_speed(U, G, DX, qp, kappa=k, c_ref=c_ref, **kw)[0] for k in (-eps, eps)]
    return -(cs[1] - cs[0]) / (2 * eps)


def off_axis(qp):
    n0 = 170 + 90 * max(qp)  # the chain's default length
    t = time.process_time()
    row = {"c": cc.front_speed(U, G, DX, qp)[0]}
    row["c_2n"] = cc.front_speed(U, G, DX, qp, blocks=2 * n0)[0]
    row["c_2steps"] = cc.front_speed(U, G, DX, qp, steps_per_slip=80)[0]
    row["D_eps0.05"] = d_of(qp, row["c"])
    row["D_eps0.025"] = d_of(qp, row["c"], eps=0.025)
    row["D_2n"] = d_of(qp, row["c"], blocks=2 * n0)
    row["cpu"] = time.process_time() - t
    return row


def diagonal():
    qp, n0 = (1, 1), 170 + 90
    t = time.process_time()
    row = {"c": cc.front_speed(U, G, DX, qp)[0]}
    row["tip"] = float(bk.front_speed(U, dx=DX / 2**0.5, gamma=G))
    row["c_2n"] = cc.front_speed(U, G, DX, qp, blocks=2 * n0)[0]
    row["D_eps0.05"] = d_of(qp, row["tip"])
    row["D_eps0.025"] = d_of(qp, row["tip"], eps=0.025)
    row["D_2n"] = d_of(qp, row["tip"], blocks=2 * n0)
    row["D_2steps"] = d_of(qp, row["tip"], steps_per_slip=80)
    row["D_api"] = bk.theory.curvature_coefficient(U, G, DX, "diagonal")
    row["cpu"] = time.process_time() - t
    return row


if __name__ == "__main__":
    out = {"D_x": {str(e): d_axis(e) for e in (0.02, 0.01, 0.005)}}
    for qp in [(4, 1), (3, 1), (2, 1), (3, 2)]:
        out[str(qp)] = off_axis(qp)
        print(qp, out[str(qp)], flush=True)
    out["(1, 1)"] = diagonal()
    print(out["(1, 1)"])
    with open(sys.argv[1], "w") as f:
        json.dump(out, f, indent=1)
