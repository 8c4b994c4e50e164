"""The tables of docs/velocity_weakening.md: fronts with velocity-weakening friction
against v_f/dx (the crossover of the paper's eq. crit), each measured on chains 20 and
40 units long (the doubling check), with the Coulomb chain's finite-dx speed.

    python docs/scripts/vw_crossover.py [out.json]    # ~15 minutes on one core
    python docs/scripts/vw_crossover.py --continuum   # only the fixed-v_f table
    python docs/scripts/vw_crossover.py --small       # only the approach to Coulomb
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
LENGTH = 20.0


def coulomb(u, gamma, dx) -> float:
    """The Coulomb chain's front speed at this dx: the finite-dx tip problem, or the
    chain itself where the tip problem is outside its domain (narrow pulses)."""
    try:
        return float(bk.front_speed(u, dx=dx, gamma=gamma))
    except bk.ParameterError:
        return bk.chain.front(u, gamma, dx).c


def _f(x, fmt) -> str:
    return "-" if x is None or x != x else format(x, fmt)


def death_v_f(u, gamma, dx, lo, hi, steps=7) -> tuple[float, float]:
    """Bisect (in log v_f) between a v_f whose front lives and one whose front dies, on
    a chain 2 LENGTH long."""
    for _ in range(steps):
        mid = (lo * hi) ** 0.5
        if vw.front(u, gamma, dx, mid, length=2 * LENGTH).status == "dies":
            hi = mid
        else:
            lo = mid
    return lo, hi


def death_table() -> list[dict]:
    """Where fronts stop existing: the v_f above which the front dies, per dx, against
    v_f* = (1 - sqrt(1 - u_+))^2/(2 gamma) (min R < u_+)."""
    print(
        "\n### Where fronts die\n\n| gamma | u_+ | v_f* | dx | v_f at death (bracket) | "
        "/ v_f* | v_f/dx at death |\n|---|---|---|---|---|---|---|",
        flush=True,
    )
    out = []
    for gamma, u in CASES:
        star = vw.v_f_existence(u, gamma)
        for dx in DXS:
            lo, hi = death_v_f(u, gamma, dx, 0.05 * min(star, 1.0), 4.0 * min(star, 1.0))
            mid = (lo * hi) ** 0.5
            print(
                f"| {gamma} | {u} | {star:.4g} | {dx} | {lo:.4g}-{hi:.4g} | "
                f"{_f(mid / star if star < float('inf') else None, '.3f')} | {mid / dx:.3g} |",
                flush=True,
            )
            out.append(
                {"gamma": gamma, "u_plus": u, "dx": dx, "v_f_star": star, "bracket": [lo, hi]}
            )
    return out


#: (gamma, u_+, v_f): fixed v_f as dx -> 0, the paper's continuum limit at v_f >> dx.
CONTINUUM = [(0.3, 0.6, 0.1), (0.3, 0.8, 0.3), (0.0, 0.6, 0.05)]


def continuum_table() -> list[dict]:
    """Fixed v_f, dx -> 0: speed, slipping zone (in lattice spacings and in x) and
    weakening zone, on chains LENGTH and 2 LENGTH long."""
    print(
        "\n### Fixed v_f, dx -> 0\n\n| gamma | u_+ | v_f | dx | v_f/dx | c | c (2x longer) | "
        "c - 1 | zone/dx | zone (x) | u_- | weakening/dx |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
        flush=True,
    )
    out = []
    for gamma, u, v_f in CONTINUUM:
        for dx in (0.1, 0.05, 0.025, 0.0125):
            f1 = vw.front(u, gamma, dx, v_f, length=LENGTH, weakening=False)
            f2 = vw.front(u, gamma, dx, v_f, length=2 * LENGTH)
            zone_x = None if f2.zone is None else f2.zone * dx
            print(
                f"| {gamma} | {u} | {v_f} | {dx} | {v_f / dx:.3g} | {_f(f1.c, '.5f')} | "
                f"{_f(f2.c, '.5f')} | {_f(f2.c - 1.0, '+.4f')} | {_f(f2.zone, '.3g')} | "
                f"{_f(zone_x, '.3f')} | {_f(f2.u_minus, '.3f')} | {_f(f2.weakening, '.2f')} |",
                flush=True,
            )
            out.append({"short": f1.to_dict(), "long": f2.to_dict()})
    return out


#: (gamma, u_+) at dx = 0.1 for the approach to the Coulomb chain, v_f/dx -> 0.
SMALL = [(0.3, 0.4), (0.3, 0.6), (0.3, 0.8), (0.0, 0.6)]
SMALL_RATIOS = (0.03, 0.01, 0.003, 0.001, 0.0003)


def small_table() -> list[dict]:
    """g = c_Coulomb/c - 1 as v_f/dx -> 0 (dx = 0.1, chains 10 long: c agrees with the
    20-long chain's to 4e-6 at r = 0.03 and better below), against r ln(1/r) and the
    derived bound 2 c_C r ln(1/r)."""
    print(
        "\n### Approach to the Coulomb chain, dx = 0.1\n\n| gamma | u_+ | c Coulomb | v_f/dx | "
        "c | g = c_C/c - 1 | g/(c_C r ln(1/r)) | local slope of g/r in ln(1/r), / c_C |\n"
        "|---|---|---|---|---|---|---|---|",
        flush=True,
    )
    out = []
    dx = 0.1
    for gamma, u in SMALL:
        cc = coulomb(u, gamma, dx)
        prev = None
        for r in SMALL_RATIOS:
            f = vw.front(u, gamma, dx, r * dx, length=10.0, weakening=False)
            g = cc / f.c - 1.0
            slope = None
            if prev is not None:
                slope = (g / r - prev[1] / prev[0]) / math.log(prev[0] / r) / cc
            print(
                f"| {gamma} | {u} | {cc:.5f} | {r:g} | {f.c:.6f} | {g:.3e} | "
                f"{g / (cc * r * math.log(1 / r)):.3f} | {_f(slope, '.3f')} |",
                flush=True,
            )
            prev = (r, g)
            out.append({"c_coulomb": cc, "front": f.to_dict()})
    return out


def main() -> None:
    if sys.argv[1:2] == ["--continuum"]:
        continuum_table()
        return
    if sys.argv[1:2] == ["--small"]:
        small_table()
        return
    rows = []
    for gamma, u in CASES:
        print(
            f"\n### Crossover: gamma = {gamma}, u_+ = {u} (v_f* = "
            f"{vw.v_f_existence(u, gamma):.3g})\n\n| dx | c Coulomb | v_f/dx | status | c | "
            "c (2x longer) | c/c_C | unsteadiness | zone/dx | u_- | weakening/dx | s_max/v_f |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|",
            flush=True,
        )
        for dx in DXS:
            cc = coulomb(u, gamma, dx)
            for r in RATIOS:
                f1 = vw.front(u, gamma, dx, r * dx, length=LENGTH)
                f2 = vw.front(u, gamma, dx, r * dx, length=2 * LENGTH)
                status = f2.status if f1.status == f2.status else f"{f1.status}/{f2.status}"
                if f2.status == "dies":
                    status += f" at x = {f2.reached:.3g}"
                print(
                    f"| {dx} | {cc:.5f} | {r:g} | {status} | {_f(f1.c, '.6f')} | "
                    f"{_f(f2.c, '.6f')} | {_f(f2.c / cc, '.4f')} | "
                    f"{_f(f2.unsteadiness, '.1e')} | {_f(f2.zone, '.3g')} | "
                    f"{_f(f2.u_minus, '.3f')} | "
                    f"{_f(f2.weakening, '.2f')} | {_f(f2.peak, '.3g')} |",
                    flush=True,
                )
                rows.append({"c_coulomb": cc, "short": f1.to_dict(), "long": f2.to_dict()})
    deaths = death_table()
    continuum = continuum_table()
    small = small_table()
    if len(sys.argv) > 1:
        with open(sys.argv[1], "w") as fh:
            json.dump(
                {"crossover": rows, "deaths": deaths, "continuum": continuum, "small": small},
                fh,
                indent=1,
            )


if __name__ == "__main__":
    main()
