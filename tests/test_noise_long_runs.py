"""Issue 14: long runs of the noisy chain against the free boundary engine with the
calibrated Lambda, at a setup where the chain cycles through separate ruptures
(docs/noise.md, "A chain that cycles").

At gamma = 0.3 the chain's collision patterns fire before the background is back near
threshold and the ring walks down into creep (docs/noise.md); at gamma = 0.85 the
patterns are weak enough (the ring is next fired at a background above the last u_+)
and at v = 1e-5 the pulses re-stick under load, so the ring cycles. There the two
engines' long runs can be compared, rupture by rupture."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import stats

import bkwaves as bk
from bkwaves import noise_stats as ns
from bkwaves import theory

GAMMA, V, DX, N = 0.85, 1e-5, 0.05, 400
L = N * DX
PHI0 = 0.01
# rate per block at phi = 1: one rupture expected once the ring is at about u = 0.94
CHAIN_NOISE = {"law": "exponential", "rate": 1e-3, "phi0": PHI0, "kick": 0.5}
U0, T_END = GAMMA + 0.01, 1e7
P = bk.Params(gamma=GAMMA, v=V, dx=DX, beta=math.inf)


def mean_recurrence(phi, rate):
    """Exact recurrence law from a rupture to the next (``ns.first_slip``): the ring's
    stuck blocks at phi rising at v, each slipping (and nucleating: P = 1 for this kick)
    at rate rate exp(-(1 - phi)/phi0)."""
    return ns.first_slip(phi, {"law": "exponential", "rate": rate, "phi0": PHI0}, V)


@pytest.fixture(scope="module")
def runs():
    ch = bk.Chain(N, P, "periodic", np.full(N, U0), noise=CHAIN_NOISE, seed=1)
    chain_result = ch.run(t_end=T_END, progress=False, max_event_duration=1e9)
    cat = chain_result.catalog
    fb_noise = ns.calibrated_noise(CHAIN_NOISE, DX, GAMMA)
    x = np.arange(200) * 0.1
    fb = bk.FreeBoundary(P, x, np.full(x.size, U0), "periodic", noise=fb_noise, seed=2)
    fb_result = fb.run(t_end=T_END)
    return cat, ns.ruptures(fb_result), fb_noise, chain_result, fb_result.events


def test_the_chain_cycles_through_separate_ring_wide_ruptures(runs):
    cat, rup, _, chain_result, fb_events = runs
    assert len(cat) >= 100
    # every event ended (no creep, no steady sliding) and swept the ring from one noise slip
    assert not cat.t_end.isna().any()
    assert (cat.kind == "noise").all() and (cat.n_blocks == N).all()
    assert cat.duration.max() < 20  # a pulse pair crossing the ring, not a slow creep
    assert rup.spontaneous.all() and np.allclose(rup.swept, L)
    assert abs(len(fb_events) - len(cat)) <= 2  # recurrences with a CV of 1.4 %
    # the chain's ruptures: all spontaneous, each event's moment shared out among them; at
    # this noise (nu_R << 1) a second nucleation during a sweep is rare (one in 107 here)
    per = ns.chain_ruptures(chain_result)
    assert per.spontaneous.all() and len(cat) <= len(per) <= 1.05 * len(cat)
    shared = per.groupby("event").moment.sum().to_numpy()
    assert np.allclose(shared, cat.moment.to_numpy(), rtol=1e-12)


def test_long_run_rupture_rates_agree_and_the_gap_is_the_chains_own_u_minus(runs):
    """The mean recurrence of the chain and of the calibrated free boundary agree within
    the statistical error. Each also agrees with its own exact recurrence: the free
    boundary with the pulse's u_-(u_+), the chain with the state its ruptures really
    leave (a noiseless ring-wide rupture at the mean starting stress), whose
    hazard-weighted stress is lower than u_- (the birth and collision zones slip more):
    that is the measured gap between the engines, and it is dx-independent."""
    cat, rup, fb_noise, _, fb_events = runs
    # event starts (a rupture that starts while another sweeps belongs to its event) in
    # both engines: the exact laws below are for the first nucleation after a sweep
    dc = np.diff(cat.t_start.to_numpy())
    df = np.diff(fb_events.t_start.to_numpy())
    se_c, se_f = (d.std(ddof=1) / math.sqrt(d.size) for d in (dc, df))
    assert abs(dc.mean() - df.mean()) < 3 * math.hypot(se_c, se_f)

    u_start = float(rup.u_start.mean())
    # free boundary: the ring sits at u_-(u_+) after each rupture, Lambda = rate P / dx
    u_minus = float(theory.u_minus(u_start, theory.c_exact(u_start), GAMMA))
    fb_mean, fb_surv = mean_recurrence(np.full(N, u_minus), fb_noise["rate"] * DX)
    assert abs(df.mean() - fb_mean) < 3 * se_f
    assert stats.kstest(df, lambda t: 1 - fb_surv(t)).pvalue > 0.01

    # chain: the phi its rupture leaves, hazard-weighted
    ring = bk.Chain(
        N, bk.Params(gamma=GAMMA, v=0.0, dx=DX, beta=math.inf), "periodic", np.full(N, u_start)
    )
    ring.kick(0, -CHAIN_NOISE["kick"], 0.0).run(t_end=60.0, progress=False)
    phi = ring.phi
    u_after = PHI0 * math.log(np.mean(np.exp(phi / PHI0)))
    assert u_after < u_minus - 1e-3  # the chain's ring is left lower than u_-
    ch_mean, ch_surv = mean_recurrence(phi, CHAIN_NOISE["rate"])
    assert abs(dc.mean() - ch_mean) < 3 * se_c
    assert stats.kstest(dc, lambda t: 1 - ch_surv(t)).pvalue > 0.01
    # and the calibration matters: forgetting the 1/dx (Lambda = rate P) is rejected
    wrong = mean_recurrence(np.full(N, u_minus), fb_noise["rate"] * DX * DX)[1]
    assert stats.kstest(df, lambda t: 1 - wrong(t)).pvalue < 1e-6


def test_chain_ruptures_splits_an_event_at_the_fronts_meeting_points():
    """Two pairs started 0.5 apart in time at opposite points of a ring make one catalog
    event; chain_ruptures gives each its ground: the fronts meet where their arrival
    times are equal, so the first gets 10 + c/2 of the ring of length 20."""
    p = bk.Params(gamma=GAMMA, v=0.0, dx=DX, beta=math.inf)
    ch = bk.Chain(N, p, "periodic", np.full(N, 0.93))
    res = ch.kick(0, -0.5, 0.0).kick(200, -0.5, 0.5).run(t_end=100.0, progress=False)
    assert len(res.catalog) == 1
    rup = ns.chain_ruptures(res)
    assert rup.block.tolist() == [0, 200] and rup.t_start.tolist() == [0.0, 0.5]
    c = bk.front_speed(0.93, dx=DX, gamma=GAMMA)
    assert abs(rup.n_blocks[0] - (L / 2 + 0.5 * c) / DX) <= 4  # the births' start-up lag
    assert rup.n_blocks.sum() == N
    assert math.isclose(rup.moment.sum(), res.catalog.moment.sum(), rel_tol=1e-12)
    with pytest.raises(bk.ParameterError, match="boundary"):
        ns.chain_ruptures(res, "ring")
    # the result records its boundary: another one is refused (it would mis-assign the
    # slips at the ring's wrap), and a result without it needs the argument
    assert res.boundary == "periodic"
    with pytest.raises(bk.ParameterError, match=r"boundary = 'free'.*'periodic'"):
        ns.chain_ruptures(res, "free")
    bare = dataclasses.replace(res, boundary=None)
    with pytest.raises(bk.ParameterError, match="boundary"):
        ns.chain_ruptures(bare)
    assert ns.chain_ruptures(bare, "periodic").equals(rup)


def test_a_law_steeper_than_the_lattice_patterns_nucleates_the_chain_at_them():
    """A rate that steps from 0 to its full value over 1e-4 in phi at 0.95: the free
    boundary nucleates at u = 0.95 exactly, several pairs per loading (sizes of all
    kinds); the chain nucleates where the kick that started the last rupture left a
    lattice-scale pattern (phi - u ~ 0.02, 4-5 length units from that kick), at a
    background ~0.02 lower, one ring-wide rupture per loading. The disagreement is the
    chain's phi != u at the scale of the law, not a calibration error."""
    step, rate, t_end = 0.95, 2.8e-3, 1e6
    chain_noise = {
        "law": "table",
        "rate": rate,
        "u": [step, step + 1e-4],
        "g": [0.0, 1.0],
        "kick": 0.5,
    }
    ch = bk.Chain(N, P, "periodic", np.full(N, 0.9), noise=chain_noise, seed=1)
    res = ch.run(t_end=t_end, progress=False, max_event_duration=1e9)
    per = ns.chain_ruptures(res)
    fb_noise = ns.calibrated_noise(chain_noise, DX, GAMMA)
    x = np.arange(200) * 0.1
    fb = bk.FreeBoundary(P, x, np.full(x.size, 0.9), "periodic", noise=fb_noise, seed=2)
    fb_result = fb.run(t_end=t_end)
    rup = ns.ruptures(fb_result)
    assert len(fb_result.events) >= 10 and len(rup) > 1.2 * len(fb_result.events)
    assert np.all(np.abs(rup.u_start - step) <= 1e-4)
    per = per[per.event >= 1]  # after the first loading, which starts from a flat ring
    assert len(per) >= 9 and per.spontaneous.all() and (per.n_blocks == N).all()
    assert per.u_start.max() < step - 0.01
    b = per.block.to_numpy()
    from_birth = np.minimum((b[1:] - b[:-1]) % N, (b[:-1] - b[1:]) % N) * DX
    # uniform nucleation would put 1/8 of them in this band; the pattern puts most there
    assert np.mean((from_birth >= 3.5) & (from_birth <= 4.8)) >= 0.7
