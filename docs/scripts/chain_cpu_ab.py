"""CPU time of the noisy ring of docs/noise.md "Ruptures of many sizes" on the installed build.

Run it with two builds' interpreters in turn (old and new alternated) to compare them on
the same work::

    python docs/scripts/chain_cpu_ab.py LENGTH T_END

LENGTH 1000 (v = 1e-4) or 3000 (v = 3e-5), noise seed 1, gamma = 0.85, dx = 0.05, the
exponential nucleation law (phi0 = 0.01, one nucleation expected by u = 0.96), as
``noise_long_runs.py``'s chain. Prints the CPU seconds of the run and its slip count (the
same count on two builds says they did the same work). Uses only API that has been there
since 7dc3050, so an old build can run it.
"""

import math
import sys
import time
import warnings

import numpy as np

import bkwaves as bk

DX, KICK = 0.05, 0.5


def main(length, t_end):
    gamma, phi0, u_star = 0.85, 0.01, 0.96
    v = 1e-4 if length == 1000 else 3e-5
    n = round(length / DX)
    rate = DX * v / (length * phi0 * math.exp(-(1 - u_star) / phi0))
    noise = {"law": "exponential", "rate": rate, "phi0": phi0, "kick": KICK}
    p = bk.Params(gamma=gamma, v=v, dx=DX, beta=math.inf)
    ch = bk.Chain(n, p, "periodic", np.full(n, 0.9), noise=noise, seed=1)
    c0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ch.run(t_end=t_end, progress=False, max_event_duration=1e9)
    cpu = time.process_time() - c0
    print(f"{bk.__file__}: L = {length:g}, t = {ch.t:.6g}, CPU {cpu:.2f} s, {len(res.slips)} slips")


if __name__ == "__main__":
    main(float(sys.argv[1]), float(sys.argv[2]))
