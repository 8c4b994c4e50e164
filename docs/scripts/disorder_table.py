"""The table of docs/disorder.md: c_eff of a front in a chain with iid thresholds
1 + sigma xi against the theories (local-speed means and the single-defect response),
measured with the tip marcher (bk.disorder.tip_march).

    python docs/scripts/disorder_table.py            # about ten minutes on one core
"""

from __future__ import annotations

import math

import bkwaves as bk

DX = 0.1
BLOCKS = 4000
REALISATIONS = 64
ROWS = [(g, u) for g in (0.0, 0.3) for u in (0.5, 0.6, 0.7, 0.8)]
SIGMAS = (0.05, 0.1, 0.15)


def main() -> None:
    print(
        "| gamma | u_+ | sigma | noise | c0 | c_eff (mean +- s.e., N) | c0 + k sigma^2 | "
        "k measured | k single defect | k harmonic <1/c> | k arithmetic <c> |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for g, u in ROWS:
        d = bk.disorder.defect_response(u, g, dx=DX)
        for noise, s in [("uniform", s) for s in SIGMAS] + [("normal", 0.05)] * (g == 0):
            if noise == "uniform" and s * math.sqrt(3.0) >= 1.0 - u:
                continue  # some threshold at or below u_+: refused
            try:
                e = bk.disorder.front_speed_ensemble(
                    u,
                    g,
                    s,
                    dx=DX,
                    blocks=BLOCKS,
                    realisations=REALISATIONS,
                    distribution=noise,
                    seed=1,
                )
            except bk.ParameterError as err:
                print(f"| {g} | {u} | {s} | {noise} | refused: {err} ||||||", flush=True)
                continue
            head = (
                f"| {g} | {u} | {s} | {noise} | {d.c0:.6f} | {e.c_mean:.5f} +- "
                f"{e.c_sem:.1e}, {e.realisations} | {d.c0 + d.k * s**2:.5f} |"
            )
            try:
                th = bk.disorder.local_theories(u, g, s, dx=DX, distribution=noise)
            except bk.ParameterError:  # local speeds outside bk.front_speed's domain
                th = None
            if th is None or e.excess_mean is None:
                k = (e.c_mean - d.c0) / s**2
                print(f"{head} {k:.3f} +- {e.c_sem / s**2:.3f} | {d.k:.3f} | - | - |", flush=True)
                continue
            # paired estimator: the ensemble harmonic mean plus the measured excess
            k = (th.harmonic + e.excess_mean - th.c0) / s**2
            print(
                f"{head} {k:.3f} +- {e.excess_sem / s**2:.3f} | {d.k:.3f} | "
                f"{th.k_harmonic:.3f} | {th.k_arithmetic:.3f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
