"""Rupture statistics against noise strength on a free boundary ring (docs/noise.md, "What
noise does to the wave statistics"): the table of the figure `noise_statistics` of
`bkwaves paper`, its check by doubling the run, and a ring four times longer (the
crossover is set by the rupture length, not the ring).

    python docs/scripts/noise_statistics.py          # ~10 minutes on one core
"""

import numpy as np
import pandas as pd

import bkwaves as bk
from bkwaves import noise_stats, theory
from bkwaves.config import _smooth_random

GAMMA, V = 0.3, 1e-2
COLS = [
    "nu",
    "nu_R",
    "ruptures",
    "spontaneous",
    "b",
    "b_lo",
    "b_hi",
    "b_fit_p",
    "u_start",
    "swept",
    "v_recurrence",
    "recurrence_cv",
    "balance",
    "mean_field",
]


def markdown(tab):
    lines = ["| " + " | ".join(COLS) + " |", "|" + "---|" * len(COLS)]
    for _, row in tab[COLS].iterrows():
        lines.append("| " + " | ".join(f"{row[c]:.4g}" for c in COLS) + " |")
    return "\n".join(lines)


def scan(L, h, amp, corr, periods, burn, nus, r0=None):
    x = np.arange(int(round(L / h))) * h
    u0 = 0.5 + amp * _smooth_random(x, corr, np.random.default_rng(1), True)
    T = theory.source_period(V, GAMMA)
    p = bk.Params(gamma=GAMMA, v=V, dx=1e-3)
    tab, _ = noise_stats.statistics_vs_strength(p, x, u0, nus, t_end=periods * T, burn_in=burn * T)
    if r0 is not None:
        tab["nu_R"] = tab.Lambda_mean * r0 / V
    # noise dominated: every point is crossed by fronts at rate n c, n = sqrt(2 Lambda)
    # (pairs born at 2 Lambda, annihilating at n^2/2 per unit length, c ~ 1), Lambda the
    # rate of ruptures (the engine does not nucleate in cells a shock is crossing)
    tab["mean_field"] = tab.recurrence * np.sqrt(2 * tab.rupture_rate)
    return tab


def main():
    pd.set_option("display.width", 200)
    nus = [0, 0.03, 0.1, 0.3, 1, 3, 10, 30, 100, 1000]
    r0 = None
    for name, amp, corr in (("smooth", 0.02, 25.0), ("sharp", 0.3, 4.0)):
        for periods in (40, 80):
            tab = scan(400.0, 0.2, amp, corr, periods, 10, nus, r0)
            if r0 is None:
                r0 = float(tab.swept[tab.nu == 0].iloc[0])
                tab["nu_R"] = tab.Lambda_mean * r0 / V
            print(f"\nring L = 400, {name} start, {periods - 10} periods after 10 (R_0 = {r0:.0f})")
            print(markdown(tab), flush=True)
    tab = scan(1600.0, 0.4, 0.02, 25.0, 40, 10, [0, 0.4, 1.2, 4, 12, 40, 400], r0)
    print(f"\nring L = 1600, smooth start, 30 periods after 10 (nu_R with R_0 = {r0:.0f})")
    print(markdown(tab), flush=True)


if __name__ == "__main__":
    main()
