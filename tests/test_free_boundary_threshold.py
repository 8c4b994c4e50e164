"""The free boundary engine with a slowly varying threshold field s(x) (issue 13): block x
slips when u - u_xx >= s(x). Against the exact scaling of a uniform threshold, closed forms
and the direct chain with the same smooth thresholds (docs/free_boundary.md, "Threshold
field")."""

from __future__ import annotations

import math
import pickle
import warnings

import numpy as np
import pytest
from scipy.integrate import quad

import bkwaves as bk


def c_exact(r):
    return 1.0 / np.sqrt(1.0 - np.asarray(r) ** 2)


def quiet(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        return bk.FreeBoundary(*args, **kw)


def bumps(x):
    return 0.6 + 0.3 * np.exp(-(((x - 70) / 30) ** 2)) + 0.25 * np.exp(-(((x - 150) / 25) ** 2))


@pytest.mark.parametrize("speed", [None, "table"])
def test_a_uniform_threshold_is_the_rescaled_uniform_model(speed):
    """Threshold s everywhere = s x (the model at u/s, v/s): the same times and places,
    u_+, u_-, slip and curvature scaled by s (docs/disorder.md (a), exact for the chain;
    the engine keeps it to rounding). With a front-speed table too: c(u_+/s)."""
    s0 = 1.3
    x = np.linspace(0, 200.0, 401)
    u0 = bumps(x) * s0 * 0.98
    gamma, v = 0.3, 1e-2
    law = None
    if speed == "table":
        q = np.linspace(0.05, 0.95, 19)
        law = {"u_plus": q, "c": (1 + 0.25 * q**2) * c_exact(q)}
    a = quiet(bk.Params(gamma=gamma, v=v, dx=1e-3), x, u0, threshold=np.full(x.size, s0),
              speed=law).run(max_events=4)  # fmt: skip
    b = quiet(bk.Params(gamma=gamma, v=v / s0, dx=1e-3), x, u0 / s0, speed=law).run(max_events=4)
    assert len(a.events) == len(b.events) == 4 and len(a.shocks) == len(b.shocks)
    assert (a.shocks.kind.values == b.shocks.kind.values).all()
    np.testing.assert_allclose(a.shocks.t, b.shocks.t, rtol=1e-10, atol=1e-9)
    # x of births and meetings near u = s (flat maximum; speed ~1e5) is ill-conditioned
    flat = np.isin(b.shocks.kind.values, ["birth", "annihilation"])
    assert np.all(np.abs(a.shocks.x - b.shocks.x)[~flat] <= 1e-9)
    assert np.all(np.abs(a.shocks.x - b.shocks.x)[flat] <= 1e-3)
    for col in ("u_plus", "u_minus"):
        np.testing.assert_allclose(a.shocks[col], s0 * b.shocks[col], rtol=1e-9, atol=1e-12)
    for col in ("moment", "stress_drop", "curvature"):
        np.testing.assert_allclose(a.events[col], s0 * b.events[col], rtol=1e-6)
    np.testing.assert_allclose(a.events.t_start, b.events.t_start, rtol=1e-12)


def test_a_shock_moves_at_c_of_u_over_s_and_leaves_u_minus_of_that_speed():
    """v = 0, u = u_0: dx/dt = c(u_0/s(x)), so the arrival time is int dx/c(u_0/s); behind
    the shock u_- = -u_0 E(c(u_0/s)) (eq. um with the local speed)."""
    gamma, u0 = 0.2, 0.6
    x = np.linspace(0.0, 40.0, 401)

    def s(x):
        return 1.0 + 0.2 * np.sin(2 * np.pi * np.asarray(x) / 20.0)

    p = bk.Params(gamma=gamma, v=0.0, dx=1e-3)
    fb = bk.FreeBoundary(p, x, np.full(x.size, u0), shocks=[(1e-12, 1)], threshold=s)
    r = fb.run(t_end=100.0)
    nodes = r.shocks[r.shocks.kind.isin(["node", "exit"])]
    assert len(nodes) == 400
    for row in nodes.iloc[::25].itertuples():
        t = quad(lambda q: 1.0 / float(c_exact(u0 / s(q))), 0.0, row.x, epsabs=1e-13)[0]
        assert row.t == pytest.approx(t, rel=1e-9)
        c = float(c_exact(u0 / s(row.x)))
        gt = c * gamma / math.sqrt(c * c - 1)
        assert row.u_minus == pytest.approx(-u0 * math.exp(-math.pi * gt / math.sqrt(1 - gt**2)))


def test_births_are_where_u_reaches_the_threshold():
    """u = u_0 + v t uniform under s(x) = 1 + a (x - x_0)^2: the pair is born at x_0 at
    t = (1 - u_0)/v; with u_0(x) instead, where u_0 - s is largest."""
    x = np.linspace(-20.0, 20.0, 201)
    p = bk.Params(gamma=0.3, v=1e-3, dx=1e-3)
    s = 1.0 + 2e-3 * (x - 3.3) ** 2
    fb = bk.FreeBoundary(p, x, np.full(x.size, 0.9), threshold=s)
    r = fb.run(max_events=1)
    ev = r.events.iloc[0]
    assert ev.t_start == pytest.approx(0.1 / 1e-3, rel=1e-12)
    assert ev.x_start == pytest.approx(3.3, abs=1e-6)
    assert ev.curvature == pytest.approx(2e-3, rel=1e-6)  # of u - s
    b = r.shocks[r.shocks.kind == "birth"]
    assert np.allclose(b.u_plus, 1.0, atol=1e-12)


def test_the_creep_threshold_scales_with_s():
    """The stop rule ends a shock where u_+/s = u_c (u_+ = s u_c)."""
    gamma = 0.3
    x = np.linspace(0, 10, 101)
    s = np.full(x.size, 1.5)
    p = bk.Params(gamma=gamma, v=0.0, dx=1e-3)
    fb = quiet(p, x, 0.8 - 0.05 * x, shocks=[(1e-9, 1)], creep="stop", threshold=s)
    r = fb.run(t_end=100.0)
    end = r.shocks[r.shocks.kind == "creep_stop"].iloc[0]
    assert end.u_plus == pytest.approx(1.5 * gamma, rel=1e-12)
    assert end.x == pytest.approx((0.8 - 1.5 * gamma) / 0.05, abs=1e-6)


def test_a_smooth_threshold_field_front_agrees_with_the_chain():
    """A front at v = 0 into u_+ = 0.6 under s(x) = 1 + 0.15 sin(2 pi x/40): the chain with
    thresholds s(i dx) against the engine, arrival times from x = 10 (past the trigger) to
    x = 70 (the local speed varies by 25 % over the window).

    - With the continuum law the chain lags by O(dx), accumulating with the distance: the
      uniform chain's own speed differs from the continuum by O(gamma dx). It halves with dx.
    - With the uniform chain's speed at this dx and gamma as the engine's law
      (``speed=`` a table of ``bk.front_speed(u, dx=, gamma=)``, applied at u/s), what is
      left is a boundary term that does not accumulate: the chain's front arrives at x
      when the engine's reaches x + kappa dx, kappa ~ 2 blocks (its tip feels the
      threshold ahead), so t_chain - t_engine = kappa dx (T(x) - T(x_0)), T = 1/c(u/s(x)):
      back to ~0 after a full wavelength (x = 50), and never more than 3 dx |T - T_0| + 0.1 dx."""
    u_plus, gamma = 0.6, 0.3

    def s(x):
        return 1.0 + 0.15 * np.sin(2 * np.pi * np.asarray(x) / 40.0)

    xf = np.linspace(0.0, 80.0, 801)
    xs = np.arange(10.0, 70.1, 5.0)

    def engine_times(speed):
        p = bk.Params(gamma=gamma, v=0.0, dx=0.05)
        fb = bk.FreeBoundary(p, xf, np.full(xf.size, u_plus), shocks=[(1e-12, 1)],
                             threshold=s, speed=speed)  # fmt: skip
        path = fb.run(t_end=200.0).shocks
        path = path[path.kind.isin(["node", "exit"])]
        t = np.interp(xs, path.x, path.t)
        return t - t[0]

    continuum = engine_times(None)
    lag = []
    for dx in (0.1, 0.05):
        n = int(round(80.0 / dx)) + 1
        ch = bk.Chain(n, bk.Params(gamma=gamma, v=0.0, dx=dx), u0=u_plus,
                      threshold=s(np.arange(n) * dx))  # fmt: skip
        ch.kick(0, -2.0)
        ts = ch.run(t_end=200.0, max_events=1).first_slip_times()[np.rint(xs / dx).astype(int)]
        chain = ts - ts[0]
        lag.append(np.max(np.abs(chain - continuum)))
        q = np.linspace(0.45, 0.8, 15)
        lattice = engine_times({"u_plus": q, "c": bk.front_speed(q, dx=dx, gamma=gamma)})
        d = chain - lattice
        big_t = 1.0 / bk.front_speed(u_plus / s(xs), dx=dx, gamma=gamma)
        assert np.all(np.abs(d) <= 3.0 * dx * np.abs(big_t - big_t[0]) + 0.1 * dx), d / dx
        assert abs(d[xs == 50.0][0]) < 0.1 * dx  # one wavelength on: nothing accumulated
        assert np.max(np.abs(d)) > 1.5 * dx * 0.14  # (the term is there: kappa > 1.5)
    # the continuum engine: an O(dx) lag (0.61 at dx = 0.1 over 48 time units)
    assert 1.8 < lag[0] / lag[1] < 2.3 and lag[1] < 0.4, lag


@pytest.mark.parametrize(
    "threshold, key",
    [
        (np.zeros(11), "threshold"),
        (np.full(11, np.nan), "threshold"),
        (np.ones(10), "threshold"),
        (-1.0, "threshold"),
        (np.full(11, 0.4), "u0"),
        ("1", "threshold"),
    ],
)
def test_bad_threshold_fields_name_the_parameter(threshold, key):
    with pytest.raises(bk.ParameterError, match=rf"invalid {key}\b.*allowed"):
        bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), np.linspace(0, 10, 11),
                        np.full(11, 0.5), threshold=threshold)  # fmt: skip


def test_noise_with_a_threshold_field_is_refused():
    with pytest.raises(bk.ParameterError, match="noise"):
        bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), np.linspace(0, 10, 11),
                        np.full(11, 0.5), threshold=np.full(11, 1.2),
                        noise={"law": "constant", "rate": 1e-3}, seed=1)  # fmt: skip


def test_a_threshold_of_one_is_the_default_bit_for_bit():
    x = np.linspace(0, 200.0, 401)
    a = quiet(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x, bumps(x)).run(max_events=3)
    b = quiet(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x, bumps(x), threshold=1.0)
    assert b.threshold is None
    b = b.run(max_events=3)
    assert a.shocks.equals(b.shocks) and a.events.equals(b.events)


@pytest.mark.parametrize("boundary", ["free", "periodic"])
def test_checkpoint_with_a_field_and_a_table_continues_bit_for_bit(boundary, tmp_path):
    x = np.linspace(0, 200.0, 401)[: (400 if boundary == "periodic" else 401)]
    s = 1.0 + 0.1 * np.cos(2 * np.pi * x / 200.0)
    q = np.linspace(0.05, 0.95, 10)
    kw = dict(threshold=s, speed={"u_plus": q, "c": (1 + 0.1 * q) * c_exact(q)})
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3)
    u0 = bumps(x) * 0.95
    fb = quiet(p, x, u0, boundary, **kw)
    while not fb._engine.n_shocks:
        assert fb._engine.advance(300.0, 7, 2**62) == "steps"
    fb._engine.advance(300.0, 11, 2**62)
    assert fb._engine.n_shocks > 0
    t_cut = fb.time
    a = quiet(p, x, u0, boundary, **kw).run(t_end=300.0, snapshots=[t_cut + 0.5])
    fb.run(t_end=t_cut + 0.5)
    fb.save(tmp_path / "fb.npz")
    for b_fb in (pickle.loads(pickle.dumps(fb)), bk.FreeBoundary.load(tmp_path / "fb.npz")):
        np.testing.assert_array_equal(b_fb.threshold, s)
        b = b_fb.run(t_end=300.0)
        assert len(a.events) >= 3
        assert a.events.equals(b.events) and a.shocks.equals(b.shocks)
        np.testing.assert_array_equal(a.snapshots.u.values, b.snapshots.u.values)
        np.testing.assert_array_equal(b.snapshots.threshold.values, s)
    other = quiet(p, x, u0, boundary, speed=kw["speed"], threshold=s * 1.01)
    with pytest.raises(bk.ParameterError, match="threshold field"):
        other._engine.restore(fb._engine.checkpoint())


def test_toml_threshold_field():
    """[disorder] threshold for the free boundary model: a number, an array on the grid,
    drawn per node, or a smooth random field; checked with the key's name."""
    from bkwaves.config import initial_state, parse_config, threshold_field

    doc = {
        "model": "free_boundary",
        "seed": 3,
        "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
        "disorder": {"threshold": {"mean": 1.0, "amplitude": 0.1, "correlation_length": 20.0}},
        "domain": {"length": 400.0, "grid": 801, "boundary": "periodic"},
        "initial": {"kind": "uniform", "value": 0.5},
        "run": {"max_events": 3},
    }
    cfg = parse_config(doc)
    assert parse_config(cfg.to_dict()) == cfg
    s = threshold_field(cfg)
    assert s.shape == (801,) and np.max(np.abs(s - 1.0)) == pytest.approx(0.1)
    # smooth: neighbouring nodes (h = 0.5) differ by far less than the amplitude
    assert np.max(np.abs(np.diff(s))) < 0.01
    # the same seed, the same field; the run uses it
    np.testing.assert_array_equal(threshold_field(parse_config(doc)), s)
    r = bk.run(cfg)
    x = cfg.x()
    fb = bk.FreeBoundary(cfg.params, x, initial_state(cfg), "periodic", threshold=s)
    assert r.events.t_start.values[0] == fb.run(max_events=1).events.t_start.values[0]
    d = dict(doc["disorder"])
    for threshold, key in (
        (
            {"mean": 1.0, "amplitude": 1.0, "correlation_length": 20.0},
            "disorder.threshold.amplitude",
        ),
        ([1.0, 1.1], "disorder.threshold"),
    ):
        with pytest.raises(bk.ParameterError, match=key.replace(".", r"\.")):
            parse_config({**doc, "disorder": {**d, "threshold": threshold}})
    # (the initial state is checked when it is built, as for u0 < 1)
    low = parse_config({**doc, "disorder": {"threshold": 0.4}})
    with pytest.raises(bk.ParameterError, match=r"initial\.value.*threshold"):
        initial_state(low)
    with pytest.raises(bk.ParameterError, match=r"disorder\.mass"):
        parse_config({**doc, "disorder": {"mass": 1.0}})
    with pytest.raises(bk.ParameterError, match="noise"):
        parse_config({**doc, "noise": {"law": "constant", "rate": 1e-3}})
    # a number and an array
    assert np.all(threshold_field(parse_config({**doc, "disorder": {"threshold": 1.2}})) == 1.2)
    arr = list(np.linspace(0.9, 1.1, 801))
    got = threshold_field(parse_config({**doc, "disorder": {"threshold": arr}}))
    np.testing.assert_array_equal(got, arr)
