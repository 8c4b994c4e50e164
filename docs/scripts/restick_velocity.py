"""Re-sticking behind a pulse under load: the chain's v_c against
bk.theory.restick_velocity (docs/theory.md, section 6).

    python docs/scripts/restick_velocity.py         # a few minutes on one core
    python docs/scripts/restick_velocity.py ramp    # the old, biased trigger

Each run is ``bk.chain.loaded_pulse``: a steady pulse in a free chain loaded at v (the
stress u_+ - v x/c meets the front as u_+), a window of 100 blocks two settling lengths
from the kick; it re-sticks if most window blocks stick within their first backswing.
v_c is bracketed to 0.5 % by bisection in log v, from a bracket off-centre around the
continuum theory; below v_c the sliding time is compared with bk.theory.restick_time.
The stress ahead is u_+ - v t_i (t_i: the front's arrival at v = 0, the same kick), so
the window blocks slip at u_+ (the printed bias); `ramp` runs the old u_+ - v x/c, which
the kick biases (the front leads x/c).
Last, the ring of docs/noise.md (400 blocks, two pulses that collide before they settle).
"""

import math
import sys
import warnings

import numpy as np

import bkwaves as bk
from bkwaves import theory
from bkwaves.chain import loaded_pulse

POINTS = (  # (u_+, gamma, dx)
    (0.9, 0.85, 0.05),
    (0.95, 0.85, 0.05),
    (0.95, 0.9, 0.05),
    (0.99, 0.85, 0.05),
    (0.6, 0.5, 0.05),
    (0.4, 0.3, 0.05),
    (0.87, 0.85, 0.05),
    (0.93, 0.85, 0.05),
    (0.9, 0.85, 0.1),
    (0.6, 0.5, 0.025),
    (0.6, 0.5, 0.1),
    (0.4, 0.3, 0.1),
    (0.8, 0.3, 0.05),
)


#: The bracket's relative width: the stated accuracy of each chain v_c.
FACTOR = 1.005


def bisect(resticks, guess, factor=FACTOR):
    """[lo, hi] with resticks(lo), not resticks(hi), hi/lo <= factor (bisection in log v)."""
    lo, hi = guess / 7.0, guess * 3.0
    while not resticks(lo):
        lo, hi = lo / 2.0, lo
    while resticks(hi):
        lo, hi = hi, hi * 2.0
    while hi / lo > factor:
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if resticks(mid) else (lo, mid)
    return lo, hi


def leading_without_amplitude(u_plus, gamma, c):
    """The closed form as docs/theory.md stated it before the amplitude: m/(1 + 2 zeta m)."""
    root_mu = math.sqrt(c * c - 1.0) / c
    zeta = gamma / root_mu
    k = math.sqrt(1.0 - zeta * zeta)
    m = math.exp(-zeta * (math.pi + math.acos(zeta)) / k)
    return m / (1.0 + 2.0 * zeta * m)


def steady_pulses(stress="arrival"):
    print(
        f"stress = {stress}: chain v_c bracketed to {100 * (FACTOR - 1):g} %; bias: the window "
        "blocks' mean u at their slip - u_+ at the bracket's lower end, and the v_c shift it "
        "makes (bias x dv_c/du_+ / v_c, theory); errors of the three forms (chain's c) "
        "against the bracket's middle"
    )
    print(
        "| u_+ | gamma | dx | chain v_c (bracket) | bias | its v_c shift | restick_velocity "
        "| error | closed form | error | m/(1 + 2 zeta m) | error | exact c |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for u_plus, gamma, dx in POINTS:
        lo, hi = bisect(
            lambda v, u=u_plus, g=gamma, d=dx: loaded_pulse(u, g, v, d, stress=stress).resticks,
            theory.restick_velocity(u_plus, gamma),
        )
        mid = math.sqrt(lo * hi)
        bias = loaded_pulse(u_plus, gamma, lo, dx, stress=stress).bias
        c = float(bk.front_speed(u_plus, dx=dx, gamma=gamma))
        num = float(theory.restick_velocity(u_plus, gamma, c=c))
        closed = float(theory.restick_velocity_closed_form(u_plus, gamma, c=c))
        old = leading_without_amplitude(u_plus, gamma, c)
        du = 1e-4
        c2 = float(bk.front_speed(u_plus + du, dx=dx, gamma=gamma))
        slope = (float(theory.restick_velocity(u_plus + du, gamma, c=c2)) - num) / du
        print(
            f"| {u_plus} | {gamma} | {dx} | {lo:.4g} - {hi:.4g} | {bias:+.1e} | "
            f"{bias * slope / num:+.1e} | {num:.4g} | {100 * (num / mid - 1):+.1f} % | "
            f"{closed:.4g} | {100 * (closed / mid - 1):+.1f} % | {old:.4g} | "
            f"{100 * (old / mid - 1):+.1f} % | "
            f"{theory.restick_velocity(u_plus, gamma):.4g} |",
            flush=True,
        )


def ramp():
    """The old trigger, u = u_+ - v x/c: biased by the kick (the front leads x/c)."""
    steady_pulses("ramp")


def sliding_times():
    print("\nsliding time of the window blocks: chain mean (spread), theory with the chain's c")
    print("| u_+ | gamma | dx | v/v_c | chain | spread | restick_time | continuum |")
    print("|---|---|---|---|---|---|---|---|")
    for u_plus, gamma, dx in POINTS:
        c = bk.front_speed(u_plus, dx=dx, gamma=gamma)
        v_c = theory.restick_velocity(u_plus, gamma, c=c)
        for f in (0.0, 0.5, 0.9):
            run = loaded_pulse(u_plus, gamma, f * v_c, dx)
            pred = theory.restick_time(u_plus, gamma, f * v_c, c=c)
            cont = theory.restick_time(u_plus, gamma, f * v_c)
            print(
                f"| {u_plus} | {gamma} | {dx} | {f} | {np.mean(run.sliding):.4f} | "
                f"{np.ptp(run.sliding):.1e} | {pred:.4f} | {cont:.4f} |",
                flush=True,
            )


def ring(u_plus, gamma, v, n=400, dx=0.05):
    """The ring of docs/noise.md (docs/scripts/noise_long_runs.py): duration, or NaN."""
    p = bk.Params(gamma=gamma, v=v, dx=dx, beta=math.inf)
    ch = bk.Chain(n, p, "periodic", np.full(n, u_plus))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cat = ch.kick(0, -0.5, 0.0).run(t_end=200.0, max_events=1, progress=False).catalog
    return cat.duration.iloc[0] if not math.isnan(cat.t_end.iloc[0]) else math.nan


def rings():
    print("\nthe ring of docs/noise.md: event duration against v (nan: open at t = 200)")
    for u_plus, vs in (
        (0.9, (6e-5, 7e-5, 7.29e-5, 7.37e-5, 7.5e-5, 9e-5)),
        (0.95, (3.5e-4, 4e-4, 4.2e-4, 4.25e-4, 4.7e-4, 5e-4, 6e-4)),
    ):
        c = bk.front_speed(u_plus, dx=0.05, gamma=0.85)
        row = ", ".join(f"{v:.3g}: {ring(u_plus, 0.85, v):.1f}" for v in (0.0, *vs))
        print(
            f"  u_+ = {u_plus} (steady pulse v_c "
            f"{theory.restick_velocity(u_plus, 0.85, c=c):.3g}): {row}"
        )


if __name__ == "__main__":
    parts = sys.argv[1:] or ["steady_pulses", "sliding_times", "rings"]
    for part in parts:
        globals()[part]()
