"""The free boundary engine in other media (issue 13): a front-speed law c(u_+) given as a
table (the renormalised c_eff of a disordered medium), against closed forms."""

from __future__ import annotations

import json
import math
import pickle
import warnings

import numpy as np
import pytest
from scipy.integrate import quad

import bkwaves as bk
from bkwaves.disorder import EnsembleFront
from bkwaves.free_boundary import speed_table


def exact(u):
    return 1.0 / np.sqrt(1.0 - np.asarray(u) ** 2)


def faster(u):
    """A law that is not a straight line in (u^2, 1/c^2): the table is only interpolated."""
    u = np.asarray(u)
    return (1.0 + 0.25 * u**2) / np.sqrt(1.0 - u**2)


def u_minus(u_plus, c, gamma):
    """Eq. (um) for a front of speed c: u_- = -u_+ exp(-pi gt/sqrt(1 - gt^2)),
    gt = c gamma/sqrt(c^2 - 1)."""
    gt = c * gamma / np.sqrt(c**2 - 1.0)
    return -u_plus * np.exp(-math.pi * gt / np.sqrt(1.0 - gt**2))


def quiet(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        return bk.FreeBoundary(*args, **kw)


def field_run(speed, boundary="free", events=4):
    x = np.linspace(0, 200.0, 401)[: (400 if boundary == "periodic" else 401)]
    u0 = 0.6 + 0.3 * np.exp(-(((x - 70) / 30) ** 2)) + 0.25 * np.exp(-(((x - 150) / 25) ** 2))
    fb = quiet(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x, u0, boundary, speed=speed)
    return fb, fb.run(max_events=events)


# ------------------------------------------------------------------ front-speed law
def test_a_table_of_the_closed_form_gives_the_default_run():
    """In (X, Y) = (u^2, 1/c^2) the exact law is the line Y = 1 - X, which the monotone
    interpolant reproduces: 9 nodes give the default run to rounding (events, births,
    annihilations, every node crossing)."""
    u = np.linspace(0.1, 0.9, 9)
    _, a = field_run(None)
    for speed in ({"u_plus": u, "c": exact(u)}, exact):
        _, b = field_run(speed)
        assert len(a.events) == len(b.events) == 4 and len(a.shocks) == len(b.shocks)
        assert (a.shocks.kind.values == b.shocks.kind.values).all()
        for col in ("t", "x", "u_plus", "u_minus"):
            # x of a birth (a flat maximum: dx ~ sqrt(rounding/curvature)) and where two
            # fresh shocks meet near u = 1 (speed ~1e5, dx = c dt) is ill-conditioned
            flat = np.isin(a.shocks.kind.values, ["birth", "annihilation"]) & (col == "x")
            tol = np.where(flat, 1e-3, 1e-9)
            assert np.all(np.abs(b.shocks[col] - a.shocks[col]) <= tol), col
    # and a law that differs gives a different run
    _, c = field_run(faster)
    assert abs(c.events.t_end.iloc[0] - a.events.t_end.iloc[0]) > 1e-2


def test_a_shock_moves_at_the_tabled_speed_and_leaves_u_minus_of_that_speed():
    """A shock into a uniform field u_0 loading at rate v: dx/dt = c(u_0 + v t), so it
    reaches x at t with int_{u_0}^{u_0 + v t} c(q) dq = v (x - x_s); behind it
    u_- = eq. (um) with the law's c. The law (1 + u^2/4)/sqrt(1 - u^2) sampled on 256 nodes
    (a callable) and on a coarse table of 12: the error is the interpolation's."""
    gamma, v, u0 = 0.2, 0.02, 0.4
    x = np.linspace(0.0, 20.0, 201)
    p = bk.Params(gamma=gamma, v=v, dx=1e-3)
    coarse = np.linspace(0.05, 0.95, 12)
    for speed, tol in ((faster, 1e-7), ({"u_plus": coarse, "c": faster(coarse)}, 2e-3)):
        fb = bk.FreeBoundary(p, x, np.full(x.size, u0), shocks=[(1e-12, 1)], speed=speed)
        r = fb.run(t_end=25.0)  # (before u reaches 1 at t = 30)
        s = r.shocks[r.shocks.kind.isin(["node", "exit"])]
        assert len(s) == 200
        for row in s.iloc[::20].itertuples():
            travelled = quad(lambda q: float(faster(q)), u0, row.u_plus, epsabs=1e-13)[0] / v
            assert travelled == pytest.approx(row.x, rel=tol, abs=tol)
            assert row.u_plus == pytest.approx(u0 + v * row.t, abs=1e-12)
            c = float(faster(row.u_plus))
            assert row.u_minus == pytest.approx(u_minus(row.u_plus, c, gamma), rel=tol)
        # the law the engine uses
        assert fb.front_speed(0.5) == pytest.approx(float(faster(0.5)), rel=tol)
    # the default law would be slower: x(t) differs at the end by much more than tol
    d = bk.FreeBoundary(p, x, np.full(x.size, u0), shocks=[(1e-12, 1)]).run(t_end=25.0)
    assert d.shocks.t.iloc[-1] - s.t.iloc[-1] > 0.3


def test_critical_stress_and_creep_follow_the_law():
    """c(u/s) (a uniform threshold s, docs/disorder.md (a)): u_c = s gamma, where
    c(u_c) = 1/sqrt(1 - gamma^2); the "stop" rule ends a shock there, the "zero" rule
    leaves u_- = 0 below it."""
    s, gamma = 1.5, 0.3
    u = np.linspace(0.05, 1.4, 28)
    table = {"u_plus": u / 1.5 * 0.99, "c": exact(u / 1.5 * 0.99 / s)}
    x = np.linspace(0, 10, 101)
    p = bk.Params(gamma=gamma, v=0.0, dx=1e-3)
    fb = bk.FreeBoundary(p, x, 0.8 - 0.05 * x, shocks=[(1e-9, 1)], creep="stop", speed=table)
    assert fb.critical_stress == pytest.approx(s * gamma, rel=1e-9)
    r = fb.run(t_end=100.0)
    end = r.shocks[r.shocks.kind == "creep_stop"].iloc[0]
    assert end.x == pytest.approx((0.8 - s * gamma) / 0.05, abs=1e-6)
    nodes = r.shocks[r.shocks.kind == "node"]
    assert np.all(nodes.u_plus > s * gamma) and not nodes.creep.any()
    zero = bk.FreeBoundary(p, x, 0.8 - 0.05 * x, shocks=[(1e-9, 1)], speed=table).run(t_end=1e3)
    crept = zero.shocks[zero.shocks.creep & (zero.shocks.kind == "node")]
    assert len(crept) > 0 and np.all(crept.u_plus <= s * gamma + 1e-12)
    assert np.all(crept.u_minus == 0)
    # the default law's u_c is gamma
    assert bk.FreeBoundary(p, x, 0.8 - 0.05 * x).critical_stress == gamma


def test_ensemble_results_make_a_table():
    """The output of bk.disorder.front_speed_ensemble (one or a list): u_plus, c_mean."""
    runs = [
        EnsembleFront(u, 0.0, 0.1, 0.1, 2000, "uniform", 1, (0, 1), np.array([c, c + 2e-3]), None)
        for u, c in ((0.7, 1.41), (0.5, 1.154), (0.6, 1.25))
    ]
    t = speed_table(runs)
    assert t["u_plus"] == [0.5, 0.6, 0.7]
    np.testing.assert_allclose(t["c"], [1.155, 1.251, 1.411], rtol=1e-15)
    fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), np.linspace(0, 10, 11),
                         np.zeros(11), speed=runs)  # fmt: skip
    assert fb.front_speed(0.6) == pytest.approx(1.251, rel=1e-12)
    assert json.loads(fb.run(t_end=1.0).snapshots.attrs["speed"]) == t
    assert speed_table(runs[0]) == {"u_plus": [0.7], "c": [1.411]}


@pytest.mark.parametrize(
    "speed, key",
    [
        ({"u_plus": [0.5, 0.4], "c": [1.2, 1.3]}, "speed.u_plus"),
        ({"u_plus": [0.0, 0.4], "c": [1.2, 1.3]}, "speed.u_plus"),
        ({"u_plus": [0.5, 1.0], "c": [1.2, 1.3]}, "speed.u_plus"),
        ({"u_plus": [0.4, 0.5], "c": [1.3, 1.2]}, "speed.c"),
        ({"u_plus": [0.4, 0.5], "c": [0.9, 1.2]}, "speed.c"),
        ({"u_plus": [0.4, 0.5], "c": [1.1, math.inf]}, "speed.c"),
        ({"u_plus": [0.4, 0.5], "c": [1.1]}, "speed.c"),
        ({"u": [0.4], "c": [1.1]}, "speed"),
        (lambda u: 1.0 + 0 * u, "speed.c"),
        ("exact", "speed"),
    ],
)
def test_bad_tables_name_the_key_and_the_range(speed, key):
    with pytest.raises(bk.ParameterError, match=rf"invalid {key}\b.*allowed"):
        bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), np.linspace(0, 10, 11),
                        np.zeros(11), speed=speed)  # fmt: skip


@pytest.mark.parametrize("boundary", ["free", "periodic"])
def test_checkpoint_with_a_table_continues_bit_for_bit(boundary, tmp_path):
    """save/load (and pickle) mid-event with a table law: the continuation equals the
    uninterrupted run exactly; an engine with another law refuses the bytes."""
    x = np.linspace(0, 200.0, 401)[: (400 if boundary == "periodic" else 401)]
    u0 = 0.6 + 0.3 * np.exp(-(((x - 70) / 30) ** 2)) + 0.25 * np.exp(-(((x - 150) / 25) ** 2))
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3)
    fb = quiet(p, x, u0, boundary, speed=faster)
    while not fb._engine.n_shocks:
        assert fb._engine.advance(300.0, 7, 2**62) == "steps"
    fb._engine.advance(300.0, 11, 2**62)
    assert fb._engine.n_shocks > 0
    t_cut = fb.time
    a = quiet(p, x, u0, boundary, speed=faster).run(t_end=300.0, snapshots=[t_cut + 0.5])
    fb.run(t_end=t_cut + 0.5)
    fb.save(tmp_path / "fb.npz")
    for b_fb in (pickle.loads(pickle.dumps(fb)), bk.FreeBoundary.load(tmp_path / "fb.npz")):
        assert b_fb.speed == fb.speed
        b = b_fb.run(t_end=300.0)
        assert len(a.events) >= 3
        assert a.events.equals(b.events) and a.shocks.equals(b.shocks)
        np.testing.assert_array_equal(a.snapshots.u.values, b.snapshots.u.values)
    with pytest.raises(bk.ParameterError, match="front-speed law"):
        quiet(p, x, u0, boundary)._engine.restore(fb._engine.checkpoint())


def test_toml_speed_table(tmp_path):
    """[speed] u_plus, c: validated with the key's name, written back by to_dict, used by
    the run and recorded in its config."""
    from bkwaves.config import parse_config

    doc = {
        "model": "free_boundary",
        "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
        "speed": {"u_plus": [0.2, 0.5, 0.8], "c": [1.03, 1.2, 1.8]},
        "domain": {"length": 20.0, "grid": 41},
        "initial": {"kind": "uniform", "value": 0.9},
        "run": {"max_events": 1},
    }
    cfg = parse_config(doc)
    assert cfg.speed == doc["speed"]
    assert parse_config(cfg.to_dict()) == cfg
    for bad, key in (
        ({"u_plus": [0.2, 0.5], "c": [1.03, 1.0]}, "speed.c"),
        ({"u_plus": [0.2], "c": [1.03], "x": 1}, "speed.x"),
        ({"u_plus": "0.2", "c": [1.03]}, "speed.u_plus"),
        ({"c": [1.03]}, "speed.u_plus"),
    ):
        with pytest.raises(bk.ParameterError, match=key.replace(".", r"\.")):
            parse_config({**doc, "speed": bad})
    with pytest.raises(bk.ParameterError, match="speed"):
        parse_config({**doc, "model": "chain", "domain": {"blocks": 10}})
