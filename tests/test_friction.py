"""Friction laws behind one registry, per-block properties, and the uniform engine kept
bit for bit (issue 13, "The engine")."""

import math
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import _core
from bkwaves.chain import smooth_random_stress
from bkwaves.config import disorder_arrays, parse_config

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = Path(__file__).parent / "data" / "chain_uniform_78ca566.npz"


# --- the uniform engine, bit for bit -------------------------------------------------------


def _reference_runs(ones: bool):
    """The runs recorded in REFERENCE by the engine of commit 78ca566 (before the friction
    registry and per-block properties): a front with backward slips, loading cycles with
    fixed ends, a ring with the midpoint integrator. ones=True gives every block its
    properties as arrays of ones (the per-block engine)."""

    def props(n, boundary="free"):
        if not ones:
            return {}
        bonds = {"free": n - 1, "fixed": n + 1, "periodic": n}[boundary]
        return dict(
            threshold=np.ones(n), mass=np.ones(n), loader=np.ones(n), coupling=np.ones(bonds)
        )

    ch = bk.Chain(100, bk.Params(gamma=0.0, v=0.0, dx=0.1, beta=0.0), u0=0.6, **props(100))
    ch.kick(0, -2.0)
    yield "front", ch, dict(t_end=12.0, snapshots=[1.0, 7.5])
    u0 = smooth_random_stress(128, 0.05, mean=0.7, amplitude=0.2, correlation=0.5, seed=3)
    p = bk.Params(gamma=0.45, v=1e-3, dx=0.05, beta=0.5)
    ch = bk.Chain(128, p, "fixed", u0=u0, **props(128, "fixed"))
    yield "cycles", ch, dict(t_end=1e5, max_events=12, snapshot_every=3)
    rng = np.random.default_rng(7)
    u0 = 0.5 + 0.3 * rng.random(96)
    ut0 = np.where(rng.random(96) < 0.1, -0.5, 1e-2)
    p = bk.Params(gamma=0.2, v=1e-2, dx=0.2, beta=1.0)
    kw = dict(integrator="midpoint", step=0.1, **props(96, "periodic"))
    ch = bk.Chain(96, p, "periodic", u0=u0, u_t0=ut0, **kw)
    yield "ring", ch, dict(t_end=60.0, snapshots=[3.0, 30.0])


def _reference_outputs(ones: bool) -> dict:
    """Every output REFERENCE holds, from this build."""
    got = {}
    for name, ch, kw in _reference_runs(ones):
        r = ch.run(progress=False, **kw)
        got[f"{name}/u"] = r.u
        got[f"{name}/u_t"] = r.u_t
        got[f"{name}/modes"] = ch.modes
        got[f"{name}/t"] = np.array([r.t])
        # (every column of the engine of 78ca566; ``kind``, the cause of a slip, came later)
        for k in r.catalog.columns.drop("kind"):
            got[f"{name}/catalog/{k}"] = r.catalog[k].to_numpy()
        # (the moment was then the sum of block slips; it is int slip dx = dx times it)
        got[f"{name}/catalog/moment"] = r.catalog["moment"].to_numpy() / ch.params.dx
        for k in r.slips.columns.drop("kind"):
            got[f"{name}/slips/{k}"] = r.slips[k].to_numpy()
        for k in ("loader_work", "friction_work", "viscous_work", "stick_projection"):
            got[f"{name}/energy/{k}"] = np.array([r.energy[k]])
        for k in ("injected", "kinetic", "coupling_springs", "loader_springs"):
            got[f"{name}/energy/{k}"] = np.array([r.energy[k]])
        for k, v in r.counters.items():
            got[f"{name}/counters/{k}"] = np.array([v])
        for k in ("t", "u", "u_t"):
            got[f"{name}/snap/{k}"] = r.snapshots[k].values
    m = _core.front_measure(0.6, 0.1, 100, friction={"gamma": 0.3, "beta": 0.0})
    for k in ("c", "u_minus", "w", "slip_times", "stick_times"):
        got[f"front_measure/{k}"] = np.atleast_1d(m[k])
    return got


# The engine of 78ca566 bisected each event's monotone piece of the Hermite cubic; this one
# narrows it by Newton steps first (chain/events.rs, `locate`): the same float wherever the
# computed cubic changes sign once on the piece, else another of its sign changes within
# rounding noise, a few ulps of the event time. Those ulps then propagate: the largest
# difference in these runs is 1.7e-12 in a time (the ring at t ~ 60: a slip time moves by
# d(phi)/v with v = 1e-2). REFERENCE_TOL, relative to each array's largest value, is 1e-10:
# a hundredth of the step error of the engine's fronts at the default step (c error
# 1e-8, docs/benchmarks.md) and far below the midpoint rule's O(h^2) at the ring's h = 0.02,
# so a change of the integration itself still fails; discrete outputs (modes, counters,
# blocks, directions, counts) must match exactly.
REFERENCE_TOL = 1e-10


def test_the_uniform_chain_is_the_engine_before_the_registry():
    ref = np.load(REFERENCE)
    got = _reference_outputs(ones=False)
    assert sorted(got) == sorted(ref.files)
    differ = []
    for k in ref.files:
        a, b = ref[k], got[k]
        if a.shape != b.shape or a.dtype.kind != b.dtype.kind:
            differ.append(k)
        elif a.dtype.kind != "f":
            if not np.array_equal(a, b):
                differ.append(k)
        elif not np.array_equal(np.isnan(a), np.isnan(b)):
            differ.append(k)
        else:
            a, b = a[~np.isnan(a)], b[~np.isnan(b)]
            if a.size and np.max(np.abs(a - b)) > REFERENCE_TOL * max(1.0, np.max(np.abs(a))):
                differ.append((k, float(np.max(np.abs(a - b)))))
    assert not differ, differ
    assert (ref["front/slips/direction"] < 0).any()  # the backward branch is exercised


def test_arrays_of_ones_are_the_uniform_chain_bit_for_bit():
    uniform, ones = _reference_outputs(ones=False), _reference_outputs(ones=True)
    assert sorted(uniform) == sorted(ones)
    differ = [k for k in uniform if uniform[k].tobytes() != ones[k].tobytes()]
    assert not differ, differ


# --- the registries come from the core ---------------------------------------------------


def test_python_reads_the_registries_of_the_core():
    assert list(bk.friction.LAWS) == [d["name"] for d in _core.friction_laws()]
    assert bk.friction.DEFAULT == list(bk.friction.LAWS)[0] == "coulomb"
    coulomb = bk.friction.LAWS["coulomb"]
    assert [p.name for p in coulomb.params] == ["gamma", "beta"]
    beta = coulomb.param("beta")
    assert beta.default == np.inf and beta.hi_closed  # inf: no backward slip, a value
    assert coulomb.param("gamma").required
    assert bk.chain.BOUNDARIES == ("free", "fixed", "periodic")
    assert bk.chain.INTEGRATORS == ("rk4", "midpoint")
    assert bk.chain.TRIGGERS == ("kick", "release")
    assert bk.chain.SLIP_CAUSES[:3] == ("threshold", "initial", "trigger")
    assert bk.chain.DEFAULT_STEP == _core.defaults()["step"] == 0.05
    assert bk.config.BOUNDARIES["chain"] == bk.chain.BOUNDARIES


@pytest.mark.parametrize(
    "call,words",
    [
        (lambda: bk.friction.law("colomb"), ['"colomb"', "one of: coulomb"]),
        (lambda: bk.friction.law("coulomb", v_f=0.1), ['"v_f"', "one of: gamma, beta"]),
        (lambda: bk.friction.law("coulomb", beta=-1.0), ["beta = -1", "0 <= beta <= inf"]),
        (lambda: _core.friction_resolve("coulomb", {}), ["gamma is required"]),
        (
            lambda: _core.ChainEngine(np.zeros(4), 0.1, 0.0, 0.05, boundary="open"),
            ['"open"', "one of: free, fixed, periodic"],
        ),
        (
            lambda: _core.ChainEngine(
                np.zeros(4), 0.1, 0.0, 0.05, friction={"gamma": 0.1}
            ).set_integrator("euler"),
            ['"euler"', "one of: rk4, midpoint"],
        ),
        (
            lambda: _core.ChainEngine(
                np.zeros(4), 0.1, 0.0, 0.05, friction={"gamma": 0.1}
            ).add_trigger(0.0, 0, "push", 1.0),
            ['"push"', "one of: kick, release"],
        ),
    ],
)
def test_unknown_names_say_which_names_exist(call, words):
    with pytest.raises(bk.ParameterError) as e:
        call()
    assert all(w in str(e.value) for w in words), str(e.value)


def test_params_carry_the_law_and_refuse_ambiguity():
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1, friction_law="coulomb")
    assert p.law_values() == {"gamma": 0.3, "beta": np.inf}  # beta: Params default, inf
    assert p.to_dict()["friction"] == {"law": "coulomb"}
    assert "friction" not in bk.Params(gamma=0.3, v=0.0, dx=0.1).to_dict()
    with pytest.raises(bk.ParameterError, match="friction.beta"):
        bk.Params(gamma=0.3, v=0.0, dx=0.1, friction_law=bk.friction.law("coulomb", beta=1.0))
    with pytest.raises(bk.ParameterError, match="colomb"):
        bk.Params(gamma=0.3, v=0.0, dx=0.1, friction_law="colomb")


def test_the_docs_show_the_law_tables_of_the_core():
    text = (ROOT / "docs" / "chain.md").read_text()
    assert bk.friction.markdown() in text


# --- per-block properties ------------------------------------------------------------------


def test_bad_per_block_values_name_the_block_and_the_property():
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
    th = np.ones(10)
    th[3] = -0.5
    with pytest.raises(bk.ParameterError, match=r"threshold\[3\] = -0.5"):
        bk.Chain(10, p, threshold=th)
    with pytest.raises(bk.ParameterError, match=r"mass\[0\] = nan"):
        bk.Chain(10, p, mass=[np.nan] + [1.0] * 9)
    with pytest.raises(bk.ParameterError, match=r"loader.*a scalar or 10 values"):
        bk.Chain(10, p, loader=np.ones(9))
    # one coupling per bond: n - 1 free, n + 1 fixed, n periodic
    bk.Chain(10, p, "free", coupling=np.ones(9))
    bk.Chain(10, p, "fixed", coupling=np.ones(11))
    bk.Chain(10, p, "periodic", coupling=np.ones(10))
    with pytest.raises(bk.ParameterError, match=r"coupling.*a scalar or 11 values"):
        bk.Chain(10, p, "fixed", coupling=np.ones(9))
    # the core checks too (the binding is not only used through bk.Chain)
    with pytest.raises(bk.ParameterError, match=r"invalid mass\[1\] = NaN"):
        _core.ChainEngine(
            np.zeros(3), 0.1, 0.0, 0.05, friction={"gamma": 0.1}, mass=np.array([1, np.nan, 1.0])
        )
    with pytest.raises(bk.ParameterError, match=r"one value per bond \(4 for 3 blocks with fixed"):
        _core.ChainEngine(
            np.zeros(3),
            0.1,
            0.0,
            0.05,
            friction={"gamma": 0.1},
            boundary="fixed",
            coupling=np.ones(3),
        )


def test_a_threshold_field_is_the_threshold_of_each_block():
    # a single block among stuck neighbours, loaded at rate v: it slips when
    # k_p u - Lap u/dx^2 reaches its own threshold, i.e. at t = (theta - phi0)/(k_p v)
    th = np.array([1.3, 0.7, 1.1, 0.9])
    kp = np.array([1.0, 2.0, 0.5, 1.5])
    p = bk.Params(gamma=0.3, v=1e-2, dx=1.0)
    ch = bk.Chain(4, p, "free", u0=0.0, threshold=th, loader=kp)
    np.testing.assert_array_equal(ch._engine.thresholds(), th)
    r = ch.run(max_events=1, t_end=1e4, progress=False)
    first = r.slips.iloc[0]
    t_expected = (th / (kp * p.v)).min()
    assert first["block"] == int(np.argmin(th / kp))
    assert first["t_start"] == pytest.approx(t_expected, rel=1e-12)


def test_outputs_and_checkpoints_carry_the_law_and_the_properties(tmp_path):
    p = bk.Params(gamma=0.3, v=1e-2, dx=0.2, beta=0.5)
    th = bk.disorder.draw("uniform", 40, mean=1.0, spread=0.1, seed=4)
    ch = bk.Chain(40, p, "periodic", u0=0.8, threshold=th)
    r = ch.run(t_end=5.0, snapshots=[5.0], progress=False)
    a = r.snapshots.attrs
    assert a["friction_law"] == "coulomb" and a["friction_gamma"] == 0.3
    assert a["friction_beta"] == 0.5 and a["properties"] == "threshold"
    ch.save(tmp_path / "c.pkl")
    back = bk.Chain.load(tmp_path / "c.pkl")
    np.testing.assert_array_equal(back._engine.thresholds(), th)
    # a checkpoint is refused by a chain with other thresholds
    other = bk.Chain(40, p, "periodic", threshold=th * (1 + 1e-12))
    with pytest.raises(bk.ParameterError, match="per-block properties"):
        other._engine.restore(ch._engine.checkpoint())


# --- TOML -----------------------------------------------------------------------------------

BASE = {
    "model": "chain",
    "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05},
    "domain": {"blocks": 50, "boundary": "free"},
    "run": {"t_end": 10.0},
}


def test_toml_friction_and_disorder_tables():
    doc = dict(BASE, friction={"law": "coulomb", "beta": 2.0})
    c = parse_config(doc)
    assert c.params.beta == 2.0 and c.params.law.name == "coulomb"
    # gamma may sit in [friction] instead of [params]
    doc = dict(BASE, params={"v": 1e-3, "dx": 0.05}, friction={"gamma": 0.2})
    assert parse_config(doc).params.gamma == 0.2
    doc = dict(
        BASE,
        seed=5,
        disorder={
            "threshold": {"distribution": "uniform", "mean": 1.0, "spread": 0.2},
            "mass": 2.0,
            "coupling": [1.0] * 49,
        },
    )
    c = parse_config(doc)
    arrays = disorder_arrays(c)
    th = arrays["threshold"]
    assert th.shape == (50,) and 0.8 <= th.min() and th.max() <= 1.2
    np.testing.assert_array_equal(th, disorder_arrays(parse_config(doc))["threshold"])
    assert arrays["mass"] == 2.0 and arrays["loader"] is None
    other_seed = disorder_arrays(parse_config(dict(doc, seed=6)))["threshold"]
    assert not np.array_equal(th, other_seed)


def test_toml_velocity_weakening():
    doc = dict(BASE, friction={"law": "velocity_weakening", "v_f": 0.05})
    p = parse_config(doc).params
    assert p.law.name == "velocity_weakening"
    assert p.law_values() == {"gamma": p.gamma, "v_f": 0.05, "beta": math.inf}
    # [physical] V_f: v_f = V_f sqrt(k_p m)/(f_r - f_s) = 0.01 * 4 / 2
    si = dict(mass=2.0, k_c=800.0, k_p=8.0, f_static=3.0, f_kinetic=1.0, alpha=1.6, V=0.5)
    doc = {k: v for k, v in BASE.items() if k != "params"}
    doc["physical"] = dict(si, spacing=0.1, V_f=0.01)
    p = parse_config(doc).params
    assert p.law.name == "velocity_weakening"
    assert p.law_values()["v_f"] == pytest.approx(0.02)
    assert p.law_values()["beta"] == pytest.approx(0.5)
    with pytest.raises(bk.ParameterError, match=r"^physical.V_f"):
        parse_config(dict(doc, friction={"law": "velocity_weakening", "v_f": 0.1}))


@pytest.mark.parametrize(
    "changes,where,words",
    [
        ({"friction": {"law": "colomb"}}, "friction.law", "coulomb"),
        ({"friction": {"law": "velocity_weakening", "v_f": 0.0}}, "friction.v_f", "0 < v_f"),
        ({"friction": {"law": "velocity_weakening"}}, "friction.v_f", "missing required"),
        ({"friction": {"v_f": 1.0}}, "friction.v_f", "valid keys here: law, gamma, beta"),
        ({"friction": {"beta": -1.0}}, "friction.beta", "0 <= beta <= inf"),
        ({"friction": {"gamma": 0.2}}, "friction.gamma", "given in [params] too"),
        ({"disorder": {"thresold": 1.0}}, "disorder.thresold", "threshold, mass"),
        ({"disorder": {"mass": [1.0, -1.0] + [1.0] * 48}}, "disorder.mass[1]", "> 0"),
        ({"disorder": {"coupling": [1.0] * 50}}, "disorder.coupling", "49"),
        (
            {"disorder": {"loader": {"distribution": "cauchy", "spread": 0.1}}},
            "disorder.loader.distribution",
            "uniform, normal, lognormal",
        ),
        (
            {"disorder": {"loader": {"distribution": "uniform", "spread": 1.5}}},
            "disorder.loader",
            "spread < mean",
        ),
    ],
)
def test_toml_errors_name_the_key(changes, where, words):
    with pytest.raises(bk.ParameterError) as e:
        parse_config(dict(BASE, **changes))
    msg = str(e.value)
    assert msg.startswith(where) and words in msg, msg
