"""Noise in the chain (issue 14): spontaneous slips of stuck blocks at rate g(x), x the
block's stress from its threshold, seeded, checkpointed, from bk.Chain and TOML [noise].
The core's tests (crates/bkwaves-core/src/chain/tests_noise.rs) check the Poisson
statistics of every law on a loading ramp and during events, and the restart bit for bit
in Rust; these check the Python surface, per-block thresholds and the config."""

import json
import math

import numpy as np
import pytest
from scipy import stats

import bkwaves as bk
from bkwaves.config import parse_config

NOISE = {"law": "exponential", "rate": 0.05, "phi0": 0.1, "kick": 0.2}
# a table law in x: zero below 0.3, a flat piece, a steep step, kinks
TABLE = {
    "law": "table",
    "rate": 0.05,
    "u": [0.3, 0.5, 0.6, 0.601, 0.8, 1.0],
    "g": [0.0, 0.05, 0.05, 0.5, 1.0, 1.5],
    "kick": 0.2,
}


def _chain(seed=11, noise=NOISE, n=60):
    u0 = 0.5 + 0.3 * np.sin(0.37 * np.arange(n))
    p = bk.Params(gamma=0.3, v=1e-2, dx=0.2, beta=0.5)
    return bk.Chain(n, p, "periodic", u0=u0, noise=noise, seed=seed)


@pytest.mark.parametrize("noise", [NOISE, TABLE], ids=["exponential", "table"])
def test_a_noisy_chain_saved_and_loaded_continues_bit_for_bit(tmp_path, noise):
    whole = _chain(noise=noise).run(t_end=150.0, progress=False)
    spont = whole.catalog[whole.catalog["kind"] == "noise"]
    assert len(spont) >= 3 and whole.counters["noise_slips"] >= 3
    ch = _chain(noise=noise)
    k = 0
    while True:
        r = ch.run(t_end=150.0, max_events=4, progress=False)
        if r.stop != "events":
            break
        ch.save(tmp_path / f"c{k}.npz")
        ch = bk.Chain.load(tmp_path / f"c{k}.npz")
        k += 1
    assert k >= 3
    assert ch.noise == noise and ch.seed == 11
    assert r.u.tobytes() == whole.u.tobytes()
    assert r.catalog.equals(whole.catalog)
    assert r.counters == whole.counters


def test_seeded_runs_repeat_and_the_seed_is_recorded():
    a = _chain(seed=3).run(t_end=100.0, progress=False)
    b = _chain(seed=3).run(t_end=100.0, progress=False)
    c = _chain(seed=4).run(t_end=100.0, progress=False)
    assert a.catalog.equals(b.catalog) and not a.catalog.equals(c.catalog)
    assert a.snapshots.attrs["seed"] == 3 and json.loads(a.snapshots.attrs["noise"]) == NOISE
    # without a seed, noise draws one and records it
    ch = _chain(seed=None)
    assert isinstance(ch.seed, int)
    # a zero rate is the noiseless chain bit for bit
    quiet = _chain(noise={**NOISE, "rate": 0.0}).run(t_end=100.0, progress=False)
    plain = _chain(noise=None).run(t_end=100.0, progress=False)
    assert quiet.u.tobytes() == plain.u.tobytes() and quiet.catalog.equals(plain.catalog)


def test_the_rate_follows_the_distance_to_each_blocks_own_threshold():
    """Per-block thresholds theta_i: x_i = 1 - (theta_i - phi_i). The first spontaneous
    slip of a loaded chain (free ends, uniform u: phi_i = u0 + v t) has the survival
    exp(-sum_i int rate g(x_i(s)) ds); over 300 seeds its transform is uniform (KS), and
    the same transform with phi in place of x (ignoring the thresholds) is refused."""
    n, v, u0, rate, phi0 = 8, 0.01, 0.3, 2.0, 0.1
    theta = np.linspace(0.8, 1.6, n)
    p = bk.Params(gamma=0.3, v=v, dx=0.5)
    noise = {"law": "exponential", "rate": rate, "phi0": phi0}

    def mass(t, x0):
        # int_0^t rate exp(-(1 - x0 - v s)/phi0) ds, summed over blocks
        return np.sum(rate * phi0 / v * np.exp(-(1 - x0) / phi0) * (math.exp(v * t / phi0) - 1))

    x0 = u0 + 1.0 - theta
    right, wrong = [], []
    for seed in range(300):
        ch = bk.Chain(n, p, u0=u0, threshold=theta, noise=noise, seed=seed)
        r = ch.run(t_end=1e4, max_events=1, progress=False)
        row = r.catalog.iloc[0]
        assert row["kind"] == "noise"
        right.append(1 - math.exp(-mass(row["t_start"], x0)))
        wrong.append(1 - math.exp(-mass(row["t_start"], np.full(n, u0))))
    assert stats.kstest(right, "uniform").pvalue > 0.01
    assert stats.kstest(wrong, "uniform").pvalue < 1e-3


def _table_primitive(x, nodes, values):
    """int_{-inf}^x g for g piecewise linear through (nodes, values), zero below the
    first node here: the trapezoid rule on the nodes below x and x itself is exact."""
    pts = np.append(np.asarray(nodes)[np.asarray(nodes) < x], x)
    return np.trapezoid(np.interp(pts, nodes, values), pts) if pts.size > 1 else 0.0


def test_a_table_law_has_the_exact_first_slip_statistics():
    """The law ``table`` through bk.Chain (the binding passes the nodes): per-block
    thresholds theta_i, uniform u (free ends: phi_i = u0 + v t), so x_i = u0 + v t + 1 -
    theta_i; the first spontaneous slip has the survival exp(-sum_i int rate g(x_i(s))
    ds) with g the piecewise-linear table divided by g(1). Over 300 seeds its transform
    is uniform (KS); with the rate twice too large (the same table not divided by g(1)
    would be 4 times) it is refused (300 seeds resolve KS distances ~ 0.1; the core's
    test, tests_noise.rs, refuses a rate 20 % off over 2000 seeds). The x_i
    start below the step (0.45 at most) and sweep the zero stretch, the flat piece and the
    step before the slip."""
    n, v, u0, rate = 8, 0.02, 0.3, 0.5
    theta = np.linspace(0.85, 1.5, n)
    p = bk.Params(gamma=0.3, v=v, dx=0.5)
    nodes, values = [0.3, 0.45, 0.5, 0.501, 0.6, 1.0], [0.0, 0.5, 0.5, 1.5, 2.0, 4.0]
    noise = {"law": "table", "rate": rate, "u": nodes, "g": values}
    g1 = np.interp(1.0, nodes, values)
    x0 = u0 + 1.0 - theta

    def mass(t):
        G = _table_primitive
        return sum(rate / g1 * (G(x + v * t, nodes, values) - G(x, nodes, values)) / v for x in x0)

    z, x_slip = [], []
    for seed in range(300):
        ch = bk.Chain(n, p, u0=u0, threshold=theta, noise=noise, seed=seed)
        r = ch.run(t_end=1e4, max_events=1, progress=False)
        row = r.catalog.iloc[0]
        assert row["kind"] == "noise"
        z.append(mass(row["t_start"]))
        x_slip.append(x0[int(r.slips.block.iloc[0])] + v * row["t_start"])
    z = np.array(z)
    # the slips fell on the zero-free pieces below and above the step
    counts = np.histogram(x_slip, bins=[0.3, 0.5, 0.501, 1.0])[0]
    assert counts[0] >= 20 and counts[2] >= 20 and len(x_slip) == counts.sum()
    assert stats.kstest(1 - np.exp(-z), "uniform").pvalue > 0.01
    assert stats.kstest(1 - np.exp(-2 * z), "uniform").pvalue < 1e-3


def test_noise_table_in_chain_configs():
    doc = {
        "model": "chain",
        "seed": 5,
        "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05},
        "domain": {"blocks": 100, "boundary": "periodic"},
        "initial": {"kind": "uniform", "value": 0.5},
        "noise": {"law": "power", "rate": 0.01, "exponent": 2.0},
        "run": {"max_events": 5},
    }
    cfg = parse_config(doc)
    assert cfg.noise == {"law": "power", "rate": 0.01, "exponent": 2.0, "kick": 0.0}
    assert parse_config(cfg.to_dict()) == cfg
    # per-block thresholds ([disorder]) and noise go together in the chain
    with_thresholds = parse_config({**doc, "disorder": {"threshold": 1.2}})
    assert with_thresholds.noise == cfg.noise
    a, b = bk.run(cfg), bk.run(cfg)
    assert (a.events["kind"] == "noise").any()
    assert a.events.equals(b.events)
    # the table law: nodes in x, no slip where g = 0 (x < 0.55: the uniform chain at
    # u = 0.5, loading at v = 1e-3, has its first spontaneous slip after t = 50)
    table = {"law": "table", "rate": 0.05, "u": [0.55, 1.0], "g": [0.0, 1.0]}
    tab = parse_config({**doc, "noise": table})
    assert tab.noise == {**table, "kick": 0.0}
    assert parse_config(tab.to_dict()) == tab
    r = bk.run(tab)
    spont = r.events[r.events["kind"] == "noise"]
    assert len(spont) >= 1
    slips = r.tables["slips"]
    first = slips[slips["kind"] == "noise"].iloc[0]
    assert 0.5 + 1e-3 * first["t_start"] > 0.55
    # SI: rate per second, kick in m/s
    si = {k: v for k, v in doc.items() if k != "params"}
    si["physical"] = {"preset": "bristol_board", "V": 1e-6}
    si["noise"] = {"law": "constant", "rate": 2.0, "kick": 0.01}
    u = parse_config(si).params.units
    got = parse_config(si).noise
    assert got["rate"] == pytest.approx(2.0 * u.time_scale, rel=1e-15)
    assert got["kick"] == pytest.approx(0.01 / u.velocity_scale, rel=1e-15)
    # errors name the key and the range
    bad = [
        ({"law": "exponential", "rate": 0.1}, r"noise\.phi0"),
        (
            {"law": "power", "rate": 0.1, "exponent": 1.0, "kick": -1.0},
            r"noise\.kick.*0 <= noise\.kick",
        ),
        ({"law": "constant", "rate": -1.0}, r"noise\.rate"),
        ({"law": "constant", "rate": 1.0, "phi0": 0.1}, r"noise\.phi0"),
        ({"law": "gauss", "rate": 1.0}, r"noise\.law.*constant, exponential, power"),
    ]
    for table, words in bad:
        with pytest.raises(bk.ParameterError, match=words):
            parse_config({**doc, "noise": table})
    with pytest.raises(bk.ParameterError, match=r"noise\.kick"):
        bk.Chain(10, bk.Params(gamma=0.3, v=0.0, dx=0.1), noise={**NOISE, "kick": math.nan})
