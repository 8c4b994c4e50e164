"""The tables of docs/velocity_weakening.md: fronts with velocity-weakening friction
against v_f/dx (the crossover of the paper's eq. crit), each measured by the converged
front (``bk.velocity_weakening.front``: the chain doubled from 20 until c, the slipping
zone and u_- move by less than its TOLERANCE, or MAX_SECONDS of CPU per chain is reached:
"undecided"), with the change at the last doubling beside each number, and the Coulomb
chain's finite-dx speed. Where fronts die: docs/scripts/vw_death.py.

    python docs/scripts/vw_crossover.py [out.json]    # about an hour on one core
    python docs/scripts/vw_crossover.py --continuum   # only the fixed-v_f table
    python docs/scripts/vw_crossover.py --small       # only the approach to Coulomb
    python docs/scripts/vw_crossover.py --case 0.3 0.6  # one (gamma, u_+) crossover table
"""

from __future__ import annotations

import json
import math
import sys

import bkwaves as bk
from bkwaves import velocity_weakening as vw

RATIOS = (0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0)
DXS = (0.1, 0.05, 0.025)
CASES = [(0.3, u) for u in (0.4, 0.6, 0.8)] + [(0.0, u) for u in (0.4, 0.6)]


def coulomb(u, gamma, dx) -> float:
    """The Coulomb chain's front speed at this dx: the finite-dx tip problem, or the
    chain itself where the tip problem is outside its domain (narrow pulses)."""
    try:
        return float(bk.front_speed(u, dx=dx, gamma=gamma))
    except bk.ParameterError:
        return bk.chain.front(u, gamma, dx).c


def _f(x, fmt) -> str:
    return "-" if x is None or x != x else format(x, fmt)


#: The budget of each chain of a measurement (seconds).
MAX_SECONDS = 20.0


def _d(f, k) -> str:
    """The change of quantity k at the last doubling (c, zone relative; u_- absolute)."""
    if f.convergence is None or f.convergence.get(k) is None:
        return "-"
    return f"{f.convergence[k]:.0e}"


#: (gamma, u_+, v_f): fixed v_f as dx -> 0, the paper's continuum limit at v_f >> dx.
CONTINUUM = [(0.3, 0.6, 0.1), (0.3, 0.8, 0.3), (0.0, 0.6, 0.05)]


def continuum_table() -> list[dict]:
    """Fixed v_f, dx -> 0: speed, slipping zone (in lattice spacings and in x) and
    weakening zone, converged, with the changes at the last doubling."""
    print(
        "\n### Fixed v_f, dx -> 0\n\n| gamma | u_+ | v_f | dx | v_f/dx | status | c | dc | "
        "c - 1 | zone/dx | dzone | zone (x) | u_- | du_- | longest chain | weakening/dx |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        flush=True,
    )
    out = []
    for gamma, u, v_f in CONTINUUM:
        for dx in (0.1, 0.05, 0.025, 0.0125):
            f = vw.front(u, gamma, dx, v_f, max_seconds=MAX_SECONDS)
            zone_x = None if f.zone is None else f.zone * dx
            print(
                f"| {gamma} | {u} | {v_f} | {dx} | {v_f / dx:.3g} | {f.status} | "
                f"{_f(f.c, '.6f')} | {_d(f, 'c')} | {_f(f.c - 1.0, '+.4f')} | "
                f"{_f(f.zone, '.4g')} | {_d(f, 'zone')} | {_f(zone_x, '.3f')} | "
                f"{_f(f.u_minus, '.4f')} | {_d(f, 'u_minus')} | {max(f.lengths):g} | "
                f"{_f(f.weakening, '.2f')} |",
                flush=True,
            )
            out.append(f.to_dict())
    return out


#: (gamma, u_+) at dx = 0.1 for the approach to the Coulomb chain, v_f/dx -> 0.
SMALL = [(0.3, 0.4), (0.3, 0.6), (0.3, 0.8), (0.0, 0.6)]
#: (down to v_f/dx = 1e-5: the onset has its own sub-steps, so a front costs about what
#: one at v_f/dx = 1e-2 does; docs/benchmarks.md, "Onset")
SMALL_RATIOS = (0.03, 0.01, 0.003, 0.001, 3e-4, 1e-4, 3e-5, 1e-5)


def small_table() -> list[dict]:
    """g = c_Coulomb/c - 1 as v_f/dx -> 0 (dx = 0.1; c converged to 1e-6, zone and u_-
    not asked for), against r ln(1/r) and the derived bound 2 c_C r ln(1/r)."""
    print(
        "\n### Approach to the Coulomb chain, dx = 0.1\n\n| gamma | u_+ | c Coulomb | v_f/dx | "
        "c | dc | g = c_C/c - 1 | g/(c_C r ln(1/r)) | local slope of g/r in ln(1/r), / c_C |\n"
        "|---|---|---|---|---|---|---|---|---|",
        flush=True,
    )
    out = []
    dx = 0.1
    c_only = {"zone": math.inf, "u_minus": math.inf}
    for gamma, u in SMALL:
        cc = coulomb(u, gamma, dx)
        prev = None
        for r in SMALL_RATIOS:
            f = vw.front(u, gamma, dx, r * dx, weakening=False, tolerance=c_only, max_seconds=120.0)
            g = cc / f.c - 1.0
            slope = None
            if prev is not None:
                slope = (g / r - prev[1] / prev[0]) / math.log(prev[0] / r) / cc
            print(
                f"| {gamma} | {u} | {cc:.5f} | {r:g} | {f.c:.6f} | {_d(f, 'c')} | {g:.3e} | "
                f"{g / (cc * r * math.log(1 / r)):.3f} | {_f(slope, '.3f')} |",
                flush=True,
            )
            prev = (r, g)
            out.append({"c_coulomb": cc, "front": f.to_dict()})
    return out


def crossover_table(gamma, u) -> list[dict]:
    print(
        f"\n### Crossover: gamma = {gamma}, u_+ = {u} (v_f* = "
        f"{vw.v_f_existence(u, gamma):.3g})\n\n| dx | c Coulomb | v_f/dx | status | c | dc | "
        "c/c_C | zone/dx | dzone | u_- | du_- | longest chain | weakening/dx | s_max/v_f |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        flush=True,
    )
    rows = []
    for dx in DXS:
        cc = coulomb(u, gamma, dx)
        for r in RATIOS:
            f = vw.front(u, gamma, dx, r * dx, max_seconds=MAX_SECONDS)
            status = f.status
            if f.status == "dies":
                status += f" at x = {f.reached:.3g}"
            print(
                f"| {dx} | {cc:.5f} | {r:g} | {status} | {_f(f.c, '.6f')} | {_d(f, 'c')} | "
                f"{_f(f.c / cc, '.4f')} | {_f(f.zone, '.4g')} | {_d(f, 'zone')} | "
                f"{_f(f.u_minus, '.4f')} | {_d(f, 'u_minus')} | {max(f.lengths):g} | "
                f"{_f(f.weakening, '.2f')} | {_f(f.peak, '.3g')} |",
                flush=True,
            )
            rows.append({"c_coulomb": cc, "front": f.to_dict()})
    return rows


def main() -> None:
    if sys.argv[1:2] == ["--continuum"]:
        continuum_table()
        return
    if sys.argv[1:2] == ["--small"]:
        small_table()
        return
    if sys.argv[1:2] == ["--case"]:
        crossover_table(float(sys.argv[2]), float(sys.argv[3]))
        return
    rows = []
    for gamma, u in CASES:
        rows += crossover_table(gamma, u)
    continuum = continuum_table()
    small = small_table()
    if len(sys.argv) > 1:
        with open(sys.argv[1], "w") as fh:
            json.dump({"crossover": rows, "continuum": continuum, "small": small}, fh, indent=1)


if __name__ == "__main__":
    main()
