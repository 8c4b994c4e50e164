"""Deferred nucleation (docs/noise.md, "Deferred nucleation: a failed kick nucleates
later"): the chain's first rupture when kicks do not always nucleate at once.

    python docs/scripts/noise_deferred.py          # ~1 minute on one core

1. One failed kick or release on a loading ring: the background stress at which its
   neighbours start a pair, against bk.noise.deferred_stress.
2. First ruptures of a ring with releases (constant law, from u = 0): chain, free boundary
   with the step calibration (P(u) alone), with deferred=True, and the exact survivals.
3. The same with a small kick (0.02, u* inside the range swept) from u = 0.2: the chain
   against the exact survival with the deferred map (no closed-form free boundary law:
   the deferred pairs of a kick depend on where the loading started).
"""

import math
import warnings

import numpy as np
from scipy import stats

import bkwaves as bk
from bkwaves import noise_stats as ns
from bkwaves.chain import RunawayEventWarning

GAMMA, V, DX = 0.3, 0.02, 0.05
P = bk.Params(gamma=GAMMA, v=V, dx=DX, beta=math.inf)


def first_rupture(ch, slips=20):
    """Run until an event has more than ``slips`` slips; when its rupture started, and
    how: "noise" (a kick that tripped its neighbours at once, within one swing) or
    "threshold" (blocks that reached the threshold: a deferred nucleation). Not the
    event's start: a block released at u < ~v/Omega never re-sticks (its first swing
    cannot bring its speed over the ground back to zero), and opens an event that
    lasts."""
    while True:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RunawayEventWarning)
            r = ch.run(t_end=1e3, max_events=1, max_event_slips=slips, progress=False)
        if r.stop != "events":
            break
    s = r.slips[r.slips.event == r.catalog.event.iloc[-1]]
    t1 = s.t_start[s.kind == "threshold"].min()
    kicks = s.t_start[(s.kind == "noise") & (s.t_start <= t1) & (s.t_start > t1 - 0.2)]
    return (kicks.max(), "noise") if len(kicks) else (t1, "threshold")


def single_kicks():
    print("1. one failed kick at u_k, ring of 200 blocks loading at v = 0.02")
    print("| kick | u_k | K_c(u_k) | deferred_stress | measured | diff |")
    print("|---|---|---|---|---|---|")
    for kick in (0.0, 0.01, 0.02, 0.03):
        for u_k in (0.1, 0.2, 0.3, 0.4, 0.45):
            kc = bk.noise.kick_threshold(u_k, DX, GAMMA)
            if kick >= kc:
                continue
            ch = bk.Chain(200, P, "periodic", np.full(200, u_k))
            if kick > 0:
                ch.kick(100, -kick)
            else:
                ch.release(100)
            t, _ = first_rupture(ch)
            pred = bk.noise.deferred_stress(u_k, kick, DX, GAMMA)
            meas = u_k + V * t
            print(f"| {kick} | {u_k} | {kc:.4f} | {pred:.5f} | {meas:.5f} | {meas - pred:.1e} |")


def survival_with_delays(rate_of_u, u0, u_star, u_b, t):
    """Exact first-rupture survival on a uniform ring loading from u0: kicks at time s
    (rate n lambda(u0 + v s)) start a pair at s if u0 + v s >= u_star, else when the
    background reaches u_b(u0 + v s)."""
    s = np.linspace(0.0, (1.0 - u0) / V, 20001)
    u = u0 + V * s
    tau = np.where(u >= u_star, s, (u_b(u) - u0) / V)
    lam = rate_of_u(u)
    return np.array(
        [math.exp(-np.trapezoid(lam * (tau <= tt), s)) if tt < s[-1] else 0.0 for tt in t]
    )


def ring(chain_noise, u0, seeds, fb_laws, N):
    se = lambda a: a.std(ddof=1) / math.sqrt(a.size)  # noqa: E731
    ch_t, kinds = [], []
    for seed in seeds:
        ch = bk.Chain(N, P, "periodic", np.full(N, u0), noise=chain_noise, seed=seed)
        t, kind = first_rupture(ch)
        ch_t.append(t)
        kinds.append(kind)
    ch_t = np.array(ch_t)
    print(
        f"chain: {ch_t.mean():.3f} +- {se(ch_t):.3f} over {len(seeds)} seeds "
        f"({kinds.count('threshold')} deferred, {kinds.count('noise')} at once)"
    )
    out = {"chain": ch_t}
    X = np.arange(N // 2) * 0.1  # free boundary ring of length N DX
    for name, law in fb_laws.items():
        fb_t = []
        for seed in seeds:
            fb = bk.FreeBoundary(
                P, X, np.full(X.size, u0), "periodic", noise=law, seed=100000 + seed
            )
            fb_t.append(fb.run(max_events=1).events.t_start.iloc[0])
        fb_t = np.array(fb_t)
        out[name] = fb_t
        d = (ch_t.mean() - fb_t.mean()) / math.hypot(se(ch_t), se(fb_t))
        print(
            f"free boundary, {name}: {fb_t.mean():.3f} +- {se(fb_t):.3f} (chain - fb: {d:.1f} se)"
        )
    return out


def releases(n, rate, seeds=range(400)):
    print(f"\n2. releases, constant law {rate} per block, ring of {n} blocks from u = 0")
    chain_noise = {"law": "constant", "rate": rate, "kick": 0.0}
    u_r = bk.noise.release_stress(DX, GAMMA)
    c = (1 - u_r) / u_r
    laws = {
        "deferred": ns.calibrated_noise(chain_noise, DX, GAMMA, deferred=True),
        "step": ns.calibrated_noise(chain_noise, DX, GAMMA),
    }
    out = ring(chain_noise, 0.0, seeds, laws, n)
    total, t_r = n * rate, u_r / V
    early = out["chain"] < t_r
    print(f"chain ruptures before u_r: {early.sum()} of {len(seeds)}")
    exact = {"deferred": (1 + 1 / c, t_r), "step": (1.0, t_r), "P = 1": (1.0, 0.0)}
    for name, (factor, start) in exact.items():
        mean = start + 1 / (total * factor)
        cdf = lambda t, f=factor, s=start: 1 - np.exp(-total * f * np.clip(t - s, 0, None))  # noqa: E731
        ps = {k: stats.kstest(v, cdf).pvalue for k, v in out.items()}
        print(
            f"exact {name}: mean {mean:.3f}; KS p "
            + ", ".join(f"{k} {p:.2g}" for k, p in ps.items())
        )


def small_kick(n, rate, kick=0.02, u0=0.2, seeds=range(400)):
    print(f"\n3. kick {kick}, constant law {rate} per block, ring of {n} blocks from u = {u0}")
    chain_noise = {"law": "constant", "rate": rate, "kick": kick}
    step = ns.calibrated_noise(chain_noise, DX, GAMMA)
    u_star = step["u"][int(np.flatnonzero(step["g"])[0])]
    print(
        f"u* = {u_star:.5f} (K_c(u*) = {kick}); deferred_stress({u0}) = "
        f"{bk.noise.deferred_stress(u0, kick, DX, GAMMA):.4f}"
    )
    out = ring(chain_noise, u0, seeds, {"step": step}, n)
    print(f"chain ruptures before u*: {(out['chain'] < (u_star - u0) / V).sum()} of {len(seeds)}")
    lam = lambda u: n * rate * np.ones_like(u)  # noqa: E731
    ub = lambda u: bk.noise.deferred_stress(u, kick, DX, GAMMA)  # noqa: E731
    grid = np.linspace(0.0, (1 - u0) / V, 4001)
    for name, delayed, start in (
        ("deferred", True, u_star),
        ("step", False, u_star),
        ("P = 1", False, u0),
    ):
        if delayed:
            surv = survival_with_delays(lam, u0, start, ub, grid)
        else:
            surv = np.exp(-n * rate * np.clip(grid - (start - u0) / V, 0, None))
        mean = np.trapezoid(surv, grid)
        cdf = lambda t, s=surv: 1 - np.interp(t, grid, s)  # noqa: E731
        ps = {k: stats.kstest(v, cdf).pvalue for k, v in out.items()}
        print(
            f"exact {name}: mean {mean:.3f}; KS p "
            + ", ".join(f"{k} {p:.2g}" for k, p in ps.items())
        )


if __name__ == "__main__":
    single_kicks()
    # the same total rate n lambda = 0.2 on 400 and 1600 blocks: pairs of failed kicks
    # within a few blocks of each other (a fraction ~ lambda t_r x a few blocks) fire early
    for n, rate in ((400, 5e-4), (1600, 1.25e-4)):
        releases(n, rate)
        small_kick(n, rate)
