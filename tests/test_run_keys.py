"""The chain's integration settings in a run config: ``run.step``, ``run.integrator`` and
``run.step_tolerance`` reach the engine as ``bk.Chain(step=, integrator=,
step_tolerance=)`` takes them, are checked when the config is built (naming the key),
enter the RK4-stability check and the work estimate, are recorded in the outputs and
kept by a resumed run."""

import copy
import math

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import _checkpoint
from bkwaves.chain import DEFAULT_STEP, INTEGRATORS, MIDPOINT_MAX_STEP
from bkwaves.config import parse_config
from bkwaves.limits import estimate
from bkwaves.runner import chain_from_config, checkpoint_path, resume, run, run_result

# a pulse across a chain at rest (v = 0): block 0 kicked forward
FRONT = {
    "model": "chain",
    "params": {"gamma": 0.3, "v": 0.0, "dx": 0.05},
    "domain": {"blocks": 200},
    "initial": {"kind": "uniform", "value": 0.6},
    "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    "run": {"t_end": 5.0},
}

# every block on the slow eigenmode of u'' = -u + 2 gamma (v - u') (tests/test_step_control):
# u = 2 gamma v + DELTA exp(-SLOW t), sliding forward for ever with Lap u = 0 (free ends)
GAMMA, V, DELTA = 1.5, 1e-3, 0.3
SLOW = GAMMA - math.sqrt(GAMMA * GAMMA - 1.0)
CREEP = {
    "model": "chain",
    "params": {"gamma": GAMMA, "v": V, "dx": 0.05},
    "domain": {"blocks": 20},
    # initial.velocity is the forward speed over the ground: u_t0 = v - velocity
    "initial": {"kind": "uniform", "value": 2 * GAMMA * V + DELTA, "velocity": V + SLOW * DELTA},
    "run": {"t_end": 20.0},
}

FB = {
    "model": "free_boundary",
    "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
    "domain": {"length": 20.0, "grid": 41},
    "initial": {"kind": "uniform", "value": 0.5},
    "run": {"t_end": 10.0},
}


def with_run(doc, **keys):
    doc = copy.deepcopy(doc)
    doc["run"].update(keys)
    return doc


def refused(doc, where, *words):
    with pytest.raises(bk.ParameterError) as e:
        parse_config(doc)
    msg = str(e.value)
    assert msg.startswith(where) and all(w in msg for w in words), msg
    return msg


# ------------------------------------------------------------------ the keys reach the engine
def test_run_step_sets_the_time_step():
    """The creeping chain has no event: its steps are t_end/(step dx) exactly, 8000 at
    the default step, 4000 at step = 0.1; both follow the exact solution."""
    exact = 2 * GAMMA * V + DELTA * math.exp(-SLOW * 20.0)
    counts = {}
    for step in (None, 0.1):
        cfg = parse_config(CREEP if step is None else with_run(CREEP, step=step))
        s = run(cfg, None)
        counts[step] = s.extra["counters"]["steps"]
        ch = chain_from_config(cfg)
        assert ch.step == (DEFAULT_STEP if step is None else step)
        r = ch.run(20.0)
        assert r.counters == s.extra["counters"]  # the runner's chain is this one
        assert np.max(np.abs(r.u - exact)) < 1e-12
    assert counts == {None: 8000, 0.1: 4000}


def test_a_config_run_equals_bk_chain_with_the_same_settings_bit_for_bit():
    """The run of a config with run.step = 0.1 is the bk.Chain(step=0.1) run: same
    slips to the bit (and not those of the default step)."""
    cfg = parse_config(with_run(FRONT, step=0.1))
    res = run_result(cfg)
    ch = bk.Chain(200, bk.Params(gamma=0.3, v=0.0, dx=0.05), u0=0.6, step=0.1)
    ch.kick(0, -2.0, 0.0)
    slips = ch.run(5.0).slips
    mine = res.tables["slips"]
    assert len(mine) == len(slips) > 100
    np.testing.assert_array_equal(mine["t_start"].to_numpy(), slips["t_start"].to_numpy())
    np.testing.assert_array_equal(mine["slip"].to_numpy(), slips["slip"].to_numpy())
    default = run_result(parse_config(FRONT)).tables["slips"]
    assert len(default) != len(mine) or not np.array_equal(
        default["t_start"].to_numpy(), mine["t_start"].to_numpy()
    )


def test_run_integrator_midpoint_closes_the_energy_books_to_round_off():
    """docs/chain.md: the midpoint rule's books close to round-off; RK4's residual is
    its O(h^4) truncation (2e-7 of the 16 units dissipated here)."""
    residual = {}
    for name in INTEGRATORS:
        cfg = parse_config(with_run(FRONT, integrator=name))
        ch = chain_from_config(cfg)
        assert ch.integrator == name
        e = ch.run(5.0).energy
        assert e["viscous_work"] > 10.0 and e["injected"] == 2.0
        residual[name] = abs(e["residual"]) / e["viscous_work"]
    assert residual["midpoint"] < 1e-13
    assert residual["rk4"] > 1e-9


def test_run_step_tolerance_lets_the_step_grow_on_a_creeping_chain():
    """With 1e-12 the step grows to RK4's stability limit (about 400 steps instead of
    8000) and stays on the exact solution; a tolerance never met (1e-300) keeps the
    fixed step: the same run bit for bit."""
    exact = 2 * GAMMA * V + DELTA * math.exp(-SLOW * 20.0)
    fixed = chain_from_config(parse_config(CREEP)).run(20.0, snapshots=[10.0])
    grown = chain_from_config(parse_config(with_run(CREEP, step_tolerance=1e-12)))
    assert grown.step_tolerance == 1e-12
    r = grown.run(20.0)
    assert fixed.counters["steps"] == 8000 and r.counters["steps"] < 450
    assert np.max(np.abs(r.u - exact)) < 1e-10
    never = chain_from_config(parse_config(with_run(CREEP, step_tolerance=1e-300)))
    same = never.run(20.0, snapshots=[10.0])
    assert same.counters == fixed.counters
    np.testing.assert_array_equal(same.u, fixed.u)
    np.testing.assert_array_equal(same.snapshots.u.values, fixed.snapshots.u.values)


def test_a_tolerance_never_met_gives_the_fixed_step_run_with_events_bit_for_bit():
    a = run_result(parse_config(FRONT), snapshots=True)
    b = run_result(parse_config(with_run(FRONT, step_tolerance=1e-300)), snapshots=True)
    assert a.tables["events"].equals(b.tables["events"])
    assert a.tables["slips"].equals(b.tables["slips"]) and len(a.tables["slips"]) > 100
    np.testing.assert_array_equal(a.snapshots.u.values, b.snapshots.u.values)
    assert b.snapshots.attrs["step_tolerance"] == 1e-300


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_the_outputs_record_the_settings(tmp_path, suffix):
    keys = {"step": 0.04, "integrator": "rk4", "step_tolerance": 1e-11}
    run(parse_config(with_run(FRONT, **keys)), tmp_path / f"o{suffix}")
    ds, _ = bk.load(tmp_path / f"o{suffix}")
    assert {k: ds.attrs[k] for k in keys} == keys
    run(parse_config(FRONT), tmp_path / f"d{suffix}")
    ds, _ = bk.load(tmp_path / f"d{suffix}")
    # the defaults the run used, as bk.Chain writes them
    assert (ds.attrs["step"], ds.attrs["integrator"], ds.attrs["step_tolerance"]) == (
        DEFAULT_STEP,
        "rk4",
        "none",
    )
    assert ds.attrs["step"] == bk.Chain(2, bk.Params(0.3, 0.0, 0.05)).integration_attrs()["step"]


def test_the_keys_round_trip_through_to_dict():
    cfg = parse_config(with_run(FRONT, step=0.2, integrator="midpoint"))
    doc = cfg.to_dict()
    assert doc["run"] == {"t_end": 5.0, "step": 0.2, "integrator": "midpoint"}
    assert parse_config(doc) == cfg
    assert "step" not in parse_config(FRONT).to_dict()["run"]


# ------------------------------------------------------------------ bad values name the key
@pytest.mark.parametrize(
    "keys, where, words",
    [
        ({"step": 0.0}, "run.step", ["0 < step < 1"]),
        ({"step": 1.0}, "run.step", ["0 < step < 1"]),
        ({"step": -0.1}, "run.step", ["0 < step < 1"]),
        ({"step": math.nan}, "run.step", ["0 < step < 1"]),
        ({"step": math.inf}, "run.step", ["0 < step < 1"]),
        ({"step": "0.1"}, "run.step", ["expected a number"]),
        ({"step": True}, "run.step", ["expected a number"]),
        ({"integrator": "rk5"}, "run.integrator", ["rk4, midpoint"]),
        ({"integrator": "RK4"}, "run.integrator", ["rk4, midpoint"]),
        ({"integrator": 4}, "run.integrator", ["rk4, midpoint"]),
        ({"step_tolerance": 0.0}, "run.step_tolerance", ["0 < step_tolerance < inf"]),
        ({"step_tolerance": -1e-12}, "run.step_tolerance", ["0 < step_tolerance < inf"]),
        ({"step_tolerance": math.inf}, "run.step_tolerance", ["0 < step_tolerance < inf"]),
        ({"step_tolerance": math.nan}, "run.step_tolerance", ["0 < step_tolerance < inf"]),
        ({"step_tolerance": "1e-12"}, "run.step_tolerance", ["expected a number"]),
        ({"integrator": "midpoint", "step": 0.8}, "run.step", ["step <= 0.5", "midpoint"]),
        (
            {"integrator": "midpoint", "step_tolerance": 1e-12},
            "run.step_tolerance",
            ["rk4", "midpoint"],
        ),
    ],
    ids=str,
)
def test_bad_values_are_refused_naming_the_key(keys, where, words):
    refused(with_run(FRONT, **keys), where, *words)


def test_midpoint_takes_steps_up_to_the_cores_limit():
    """The config's bound is the core's: bk.Chain refuses midpoint above it, takes it at it."""
    p = bk.Params(gamma=0.3, v=0.0, dx=0.05)
    bk.Chain(5, p, integrator="midpoint", step=MIDPOINT_MAX_STEP)
    with pytest.raises(bk.ParameterError, match="step"):
        bk.Chain(5, p, integrator="midpoint", step=math.nextafter(MIDPOINT_MAX_STEP, 1.0))
    cfg = parse_config(with_run(FRONT, integrator="midpoint", step=MIDPOINT_MAX_STEP))
    assert chain_from_config(cfg).step == MIDPOINT_MAX_STEP
    refused(
        with_run(FRONT, integrator="midpoint", step=math.nextafter(MIDPOINT_MAX_STEP, 1.0)),
        "run.step",
    )


@pytest.mark.parametrize(
    "keys", [{"step": 0.1}, {"integrator": "midpoint"}, {"step_tolerance": 1e-12}], ids=str
)
def test_the_keys_are_chain_only(keys):
    (key,) = keys
    refused(with_run(FB, **keys), f"run.{key}", "chain model only")


# ------------------------------------------------------------------ stability and estimates
def test_the_rk4_stability_check_uses_the_configured_step():
    """h (sqrt(1 + 4/dx^2) + 2 gamma) <= 2.5 with h = step dx: at dx = 0.05 gamma <= 480
    at the default step, <= 30 at step 0.5, <= 2480 at step 0.01; the config refuses
    what the engine would refuse, naming the key the user wrote."""
    dx = 0.05
    sound = math.sqrt(1.0 + 4.0 / dx**2)

    def g_max(step):
        return 0.5 * (2.5 / (step * dx) - sound)

    def doc(gamma, **keys):
        return with_run({**FRONT, "params": {"gamma": gamma, "v": 0.0, "dx": dx}}, **keys)

    # a gamma allowed at the default step is refused at step 0.5, naming run.step
    parse_config(doc(100.0))
    msg = refused(doc(100.0, step=0.5), "run.step", "RK4 stability", "params.gamma")
    assert f"step <= {2.5 / (dx * (sound + 200.0)):.6g}" in msg
    # ... and the reverse: refused at the default step (naming gamma), allowed at 0.01
    refused(doc(600.0), "params.gamma", f"gamma <= {g_max(DEFAULT_STEP):.6g}")
    parse_config(doc(600.0, step=0.01))
    # the bound is the engine's, on both sides
    for step in (0.5, DEFAULT_STEP, 0.01):
        below, above = 0.999 * g_max(step), 1.001 * g_max(step)
        keys = {} if step == DEFAULT_STEP else {"step": step}
        cfg = parse_config(doc(below, **keys))
        chain_from_config(cfg)
        with pytest.raises(bk.ParameterError):
            parse_config(doc(above, **keys))
        with pytest.raises(bk.ParameterError, match="RK4 stability"):
            bk.Chain(5, bk.Params(gamma=above, v=0.0, dx=dx), step=step)


def test_the_work_estimate_uses_the_configured_step():
    """work = sliding block-time / (step dx): the front reaches c t_end/dx blocks, each
    sliding w/c (App. B); half at twice the step; with step_tolerance the estimate at the
    floor is a bound, and says so. After the front nothing slides: a t_end of 3e9 costs
    what the front costs (issue 27: it was refused at "2 years")."""
    import warnings

    w = {s: estimate(parse_config(with_run(FRONT, step=s))).work for s in (0.05, 0.1)}
    tw = bk.traveling_wave(0.6, 0.3)
    reached = tw.c * 5.0 / 0.05
    assert 100 < reached < 200
    # plus the event location: each of the 2 switches per block redoes a step over the
    # pulse's c tau/dx = w/dx blocks (independent of the step)
    redo = 2 * reached * (tw.w / 0.05)
    assert w[0.05] == pytest.approx(reached * (tw.w / tw.c) / (0.05 * 0.05) + redo)
    assert w[0.1] - redo == pytest.approx((w[0.05] - redo) / 2, rel=1e-12)
    assert estimate(parse_config(FRONT)).work == w[0.05]
    bound = estimate(parse_config(with_run(FRONT, step=0.1, step_tolerance=1e-12)))
    assert bound.work == w[0.1] and "at most" in bound.notes[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error", bk.limits.LongRunWarning)
        big = estimate(parse_config(with_run(FRONT, t_end=3e9)))
    assert big.work == pytest.approx(200 * (tw.w / tw.c) / (0.05 * 0.05) + 2 * 200 * tw.w / 0.05)


# ------------------------------------------------------------------ resume keeps the settings
def test_a_resumed_run_keeps_its_step_and_a_checkpoint_changed_is_refused(tmp_path):
    cfg = parse_config(
        {
            "model": "chain",
            "seed": 5,
            "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05, "beta": 5.0},
            "domain": {"blocks": 300, "boundary": "periodic"},
            "initial": {
                "kind": "random",
                "mean": 0.5,
                "amplitude": 0.3,
                "correlation_length": 2.0,
            },
            "run": {"max_events": 8, "step": 0.1, "step_tolerance": 1e-12},
            "output": {"snapshot_events": 1},
        }
    )
    ref = run(cfg, tmp_path / "ref.nc", chunk=50)
    out = tmp_path / "cut.nc"
    for k in range(ref.extra["counters"]["steps"] // 50, 0, -1):
        first = run(cfg, out, chunk=50, overwrite=True, _stop_after_chunks=k)
        if first.interrupted and 0 < first.events < ref.events - 1:
            break
    assert first.interrupted and 0 < first.events < ref.events
    ck = checkpoint_path(out)
    meta, arrays = _checkpoint.read(ck, "run", "bkwaves run")
    assert meta["engine"]["step"] == 0.1 and meta["config"]["run"]["step"] == 0.1
    # a checkpoint whose config asks for another step than its engine is refused
    changed = copy.deepcopy(meta)
    changed["config"]["run"]["step"] = 0.05
    _checkpoint.write(ck, "run", changed, arrays)
    with pytest.raises(bk.ParameterError, match=r"run\.step = 0\.05"):
        resume(out, chunk=50)
    # an engine record with another step than its bytes is refused by the fingerprint
    changed = copy.deepcopy(meta)
    changed["engine"]["step"] = changed["config"]["run"]["step"] = 0.05
    _checkpoint.write(ck, "run", changed, arrays)
    with pytest.raises(bk.ParameterError, match="same blocks, dx, v, step"):
        resume(out, chunk=50)
    # the checkpoint as written resumes with its own settings, bit for bit
    _checkpoint.write(ck, "run", meta, arrays)
    last = resume(out, chunk=50)
    assert not last.interrupted and last.events == ref.events
    a, ca = bk.load(tmp_path / "ref.nc")
    b, cb = bk.load(out)
    np.testing.assert_array_equal(a.u.values, b.u.values)
    assert ca.equals(cb)
    assert (b.attrs["step"], b.attrs["step_tolerance"]) == (0.1, 1e-12)


def test_midpoint_refuses_a_damping_its_fixed_point_solve_cannot_handle():
    """The midpoint rule solves each step by fixed-point iteration, whose contraction
    factor is bounded by (h/2)^2 (1 + 4/dx^2) + h gamma (h = step dx). Beyond 0.8 its 200
    passes no longer reach round-off: at dx = 0.05, step 0.05, gamma = 420 (a factor of
    1.05) the engine used to accept the unconverged state silently (a kicked block
    stopping after two steps with the energy books still closing, helper finding). Now
    bk.Chain refuses it naming step, the config names run.integrator (or run.step), and
    just inside the bound the books still close to round-off."""
    from bkwaves.config import MIDPOINT_CONTRACTION

    dx, step = 0.05, DEFAULT_STEP
    h = step * dx

    def q(gamma):
        return 0.25 * h * h * (1 + 4 / dx**2) + h * gamma

    g_edge = (MIDPOINT_CONTRACTION - q(0.0)) / h  # the largest gamma accepted
    for gamma in (420.0, g_edge * 1.01):
        assert q(gamma) > MIDPOINT_CONTRACTION
        p = bk.Params(gamma=gamma, v=0.0, dx=dx)
        with pytest.raises(bk.ParameterError, match=r"step"):
            bk.Chain(40, p, u0=0.6, integrator="midpoint")
        doc = copy.deepcopy(FRONT)
        doc["params"]["gamma"] = gamma
        doc["run"]["integrator"] = "midpoint"
        with pytest.raises(bk.ParameterError, match=r"run\.integrator.*contract"):
            parse_config(doc)
        doc["run"]["step"] = step
        with pytest.raises(bk.ParameterError, match=r"run\.step.*contract"):
            parse_config(doc)
    # just inside: accepted, and every step solved (the energy books close to round-off)
    p = bk.Params(gamma=0.99 * g_edge, v=0.0, dx=dx)
    ch = bk.Chain(40, p, u0=0.6, integrator="midpoint")
    res = ch.kick(0, -2.0).run(t_end=0.5, progress=False)
    assert abs(res.energy["residual"]) < 1e-13 * res.energy["injected"]
