"""Speed of the front-speed computations (issue: c(u_+) to machine precision, fast).

Run: python benchmarks/bench_speed.py
Prints a markdown table of medians over repeats; every ratio is measured in this run
against a baseline doing the same work.
"""

import statistics
import time

import numpy as np
from scipy.optimize import brentq

import bkwaves as bk
from bkwaves import theory as th


def median_time(fn, repeat=7, number=1):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        ts.append((time.perf_counter() - t0) / number)
    return statistics.median(ts)


def interpolation_brentq(u):
    """What a user writes without bkwaves: eq. (c) solved per value with scipy."""

    def f(c, x):
        return 1 / (1 + (2 + c * c + 4 * c**4) / (8 * c**5 * np.sqrt(c * c - 1))) - x

    return np.array([brentq(f, 1 + 1e-15, 1e8, args=(x,), xtol=1e-14) for x in u])


def main():
    rng = np.random.default_rng(1)
    u = rng.uniform(0.01, 0.99, 100_000)
    rows = []
    t_fs = median_time(lambda: bk.front_speed(u))
    t_np = median_time(lambda: 1.0 / np.sqrt((1.0 - u) * (1.0 + u)))
    rows.append(("bk.front_speed, 1e5 values (exact c)", t_fs, "numpy closed form", t_np))
    t_vec = median_time(lambda: th.c_interpolation(u), repeat=3)
    rows.append(("bk.front_speed, 1e5 values", t_fs, "eq. (c) by vectorised bisection", t_vec))
    few = u[:2000]
    t_brent = median_time(lambda: interpolation_brentq(few), repeat=3) * (len(u) / len(few))
    rows.append(
        ("bk.front_speed, 1e5 values", t_fs, "eq. (c) per value with brentq (scaled)", t_brent)
    )
    for x in (0.05, 0.5, 0.95):
        t_tip = median_time(lambda x=x: bk.tip_solve(x), repeat=7)
        t_one = median_time(lambda x=x: bk.tip_solve(c=float(bk.front_speed(x))), repeat=7)
        rows.append(
            (f"bk.tip_solve(u_plus={x}) (root in c)", t_tip, "one linear solve at given c", t_one)
        )
    print("| work | time | baseline | baseline time | ratio |")
    print("|---|---|---|---|---|")
    for name, t, base, tb in rows:
        print(f"| {name} | {t * 1e3:.3f} ms | {base} | {tb * 1e3:.3f} ms | {tb / t:.1f} |")


if __name__ == "__main__":
    main()
