"""The calibrated rate (docs/noise.md, "The calibrated rate"): the chain's kick noise and
the free boundary engine with Lambda = lambda P / dx, at one setup.

    python docs/scripts/noise_calibration.py          # ~11 minutes on one core

1. Time to the first rupture over 40 seeds: chain, free boundary, exact survival.
2. Long runs (1500 time units) of both: the chain's catalog, the free boundary's ruptures.
3. What the chain leaves where two pulses collide: phi - u, against dx, the time step, u_+.
4. gamma = 0 and 0.05: the chain's state in a long run, the free boundary's rupture rate.
5. Noiseless rings: the chain's second event starts at the first one's collision pattern.

The chain's long runs stop where its runaway guard finds an event that does not end.
"""

import math
import warnings

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


def collision(u_plus=0.79, kick=0.1, gamma=GAMMA, dx=DX, **chain_options):
    """Two pulses on a ring of length N DX (blocks = N DX / dx) from a kick at block 0."""
    blocks = round(N * DX / dx)
    p = bk.Params(gamma=gamma, v=0.0, dx=dx, beta=math.inf)
    ch = bk.Chain(blocks, p, "periodic", np.full(blocks, u_plus), **chain_options)
    ch.kick(0, -kick, 0.0).run(t_end=N * DX, progress=False)
    d = ch.phi - ch.u
    far = np.nonzero(d > 0.2)[0]
    i = int(np.argmax(d))
    span = f"blocks {far.min()}-{far.max()}" if far.size else "no block"
    print(
        f"\ncollision of two pulses at u_+ = {u_plus}, gamma = {gamma}, dx = {dx} "
        f"{chain_options or ''}: max phi - u = {d.max():.4f} at x = {i * dx:.2f} (u {ch.u[i]:.3f}; "
        f"collision at x = {N * DX / 2}; the pattern fires at background u = {1 - d.max():.3f}); "
        f"phi - u > 0.2 at {span}"
    )


def no_creep_range(gamma, t_end=600.0, sample=5.0):
    """gamma = 0 or small: the chain's long run (runaway guard off) sampled every `sample`
    after t = 100, and the calibrated free boundary's ruptures over t = 100-3000."""
    p = bk.Params(gamma=gamma, v=V, dx=DX, beta=math.inf)
    ch = bk.Chain(N, p, "periodic", np.full(N, 0.3), noise=CHAIN_NOISE, seed=1)
    rows = []
    for t in np.arange(100.0, t_end + 1, sample):
        res = ch.run(t_end=t, progress=False, max_event_slips=10**9, max_event_duration=1e9)
        sliding = np.sum(np.abs(np.asarray(ch.u_t) - V) > 1e-9)
        rows.append((np.median(ch.u), ch.u.max(), ch.phi.max(), sliding))
    med, umax, phimax, sliding = np.array(rows).T
    cat = res.catalog
    print(f"\nchain, gamma = {gamma}:")
    print(cat[["t_start", "t_end", "n_blocks", "kind"]].to_string())
    print(
        f"  t = 100-{t_end}: median u {med.mean():.3f} +- {med.std():.3f}, max u "
        f"{umax.mean():.3f}, max phi {phimax.mean():.2f}, sliding blocks {sliding.mean():.1f} "
        f"(none in {np.mean(sliding == 0):.0%} of the samples)"
    )
    x = np.arange(200) * 0.1
    fb = ns.calibrated_noise(CHAIN_NOISE, DX, gamma)
    r = ns.ring_statistics(p, x, np.full(x.size, 0.3), fb, t_end=3000.0, burn_in=100.0, seed=2)
    n, span, rec = len(r["ruptures"]), r["span"], r["recurrence"]
    print(
        f"free boundary, gamma = {gamma}: {n} ruptures, rate {n / span:.4f} +- "
        f"{math.sqrt(n) / span:.4f}, spontaneous {r['spontaneous']:.2f}, u_start "
        f"{r['u_start']:.3f} +- {r['ruptures'].u_start.std():.3f}, swept {r['swept']:.2f}, "
        f"recurrence {rec.mean():.1f} (CV {rec.std() / rec.mean():.2f})"
    )


def noiseless_rings():
    """A ring just below threshold with a bump inside the no-creep bound, no noise."""
    x = np.arange(N) * DX
    length = N * DX
    print()
    for gamma in (0.3, 0.6):
        for v in (0.005, 0.02, 0.05):
            p = bk.Params(gamma=gamma, v=v, dx=DX, beta=math.inf)
            amp = 0.8 * v * math.sqrt(1 - gamma**2) * length / (2 * math.pi)
            u0 = 1 - 1e-3 - amp + amp * np.cos(2 * np.pi * x / length)
            ch = bk.Chain(N, p, "periodic", u0)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                cat = ch.run(t_end=8 / v, progress=False).catalog
            print(
                f"noiseless ring, gamma = {gamma}, v = {v}: stopped at t = {ch.t:.1f}, "
                f"{len(cat)} events ({cat.t_end.isna().sum()} open), nucleation blocks "
                f"{cat.nucleation.tolist()[:6]}, sizes {cat.n_blocks.tolist()[:6]}"
            )


if __name__ == "__main__":
    first_ruptures()
    for dx in (0.1, DX, 0.025):
        collision(dx=dx)
        collision(gamma=0.0, dx=dx)
    collision(step=0.0125)
    collision(step=0.0125, integrator="midpoint")
    for gamma in (0.0, GAMMA, 0.6):
        for u_plus in (0.5, 0.65, 0.79, 0.85, 0.9, 0.95, 0.99):
            collision(u_plus=u_plus, gamma=gamma)
    no_creep_range(0.0)
    no_creep_range(0.05)
    noiseless_rings()
    long_runs()
    long_runs(kick=0.1)
