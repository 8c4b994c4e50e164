"""The calibrated rate (docs/noise.md, "The calibrated rate"): the chain's kick noise and
the free boundary engine with Lambda = lambda P / dx, at one setup.

    python docs/scripts/noise_calibration.py          # ~10 minutes on one core

1. Time to the first rupture over 40 seeds: chain, free boundary, exact survival.
2. Long runs (1500 time units) of both: the chain's catalog, the free boundary's ruptures.
3. What the chain leaves where two pulses collide: phi - u.

The chain's long runs stop where its runaway guard finds an event that does not end.
"""

import math

import numpy as np
from scipy import integrate

import bkwaves as bk
from bkwaves import noise_stats as ns

GAMMA, V, DX, N, KICK = 0.3, 0.02, 0.05, 400, 0.5
CHAIN_NOISE = {"law": "exponential", "rate": 0.01, "phi0": 0.1, "kick": KICK}
P = bk.Params(gamma=GAMMA, v=V, dx=DX, beta=math.inf)
X = np.arange(200) * 0.1  # free boundary ring of length N DX


def first_ruptures(u0=0.5, seeds=range(40)):
    fb_noise = ns.calibrated_noise(CHAIN_NOISE, DX, GAMMA)
    ch_t, fb_t = [], []
    for seed in seeds:
        ch = bk.Chain(N, P, "periodic", np.full(N, u0), noise=CHAIN_NOISE, seed=seed)
        ch_t.append(ch.run(t_end=200.0, max_events=1, progress=False).catalog.t_start.iloc[0])
        # another seed: the engines draw noise alike, equal seeds would give equal times
        fb = bk.FreeBoundary(
            P, X, np.full(X.size, u0), "periodic", noise=fb_noise, seed=1000 + seed
        )
        fb_t.append(fb.run(max_events=1).events.t_start.iloc[0])
    L, lam, f0 = N * DX, fb_noise["rate"], CHAIN_NOISE["phi0"]

    def survival(t):
        return math.exp(
            -L * lam * f0 * (math.exp(-(1 - u0 - V * t) / f0) - math.exp(-(1 - u0) / f0)) / V
        )

    exact = integrate.quad(survival, 0, (1 - u0) / V + 10)[0]
    print(f"Lambda = {fb_noise}")
    for name, t in (("chain", np.array(ch_t)), ("free boundary", np.array(fb_t))):
        print(f"  first rupture, {name}: {t.mean():.3f} +- {t.std(ddof=1) / math.sqrt(t.size):.3f}")
    print(f"  exact mean: {exact:.3f}")


def long_runs(u0=0.3, t_end=1500.0, kick=KICK):
    noise = {**CHAIN_NOISE, "kick": kick}
    ch = bk.Chain(N, P, "periodic", np.full(N, u0), noise=noise, seed=1)
    res = ch.run(t_end=t_end, progress=False)
    cat = res.catalog
    print(f"\nchain: run to t = {ch.t:.1f} of {t_end} (kick {kick})")
    print("\nchain catalog:")
    print(cat[["t_start", "t_end", "nucleation", "n_blocks", "moment", "kind"]].to_string())
    fb_noise = ns.calibrated_noise(noise, DX, GAMMA)
    fb = bk.FreeBoundary(P, X, np.full(X.size, u0), "periodic", noise=fb_noise, seed=2)
    rup = ns.ruptures(fb.run(t_end=t_end))
    print(
        f"\nfree boundary: {len(rup)} ruptures, {rup.spontaneous.mean():.2f} spontaneous, "
        f"u at start {rup.u_start.mean():.3f} +- {rup.u_start.std():.3f}, swept "
        f"{rup.swept.mean():.2f}"
    )


def collision(u_plus=0.79, kick=0.1, blocks=N, gamma=GAMMA):
    p = bk.Params(gamma=gamma, v=0.0, dx=DX, beta=math.inf)
    ch = bk.Chain(blocks, p, "periodic", np.full(blocks, u_plus)).kick(0, -kick, 0.0)
    ch.run(t_end=blocks * DX, progress=False)
    d = ch.phi - ch.u
    far = np.nonzero(d > 0.2)[0]
    print(
        f"\ncollision of two pulses at u_+ = {u_plus}, gamma = {gamma}: max phi - u = "
        f"{d.max():.3f} at block {int(np.argmax(d))} (collision at {blocks // 2}); "
        f"phi - u > 0.2 at blocks {far.min()}-{far.max()}"
    )


if __name__ == "__main__":
    first_ruptures()
    collision()
    collision(gamma=0.6)
    long_runs()
    long_runs(kick=0.1)
