"""Step-size control (``bk.Chain(step_tolerance=...)``, docs/chain.md "Step-size control"):
the key is validated, a creeping chain is followed to its exact solution with long steps,
and a controlled run saved and loaded continues bit for bit."""

import math

import numpy as np
import pytest

import bkwaves as bk

GAMMA, V, DELTA = 1.5, 1e-3, 0.3
SLOW = GAMMA - math.sqrt(GAMMA * GAMMA - 1.0)


def creeping(n=20, **kw):
    """Every block on the slow eigenmode of u'' = -u + 2 gamma (v - u'): u = 2 gamma v +
    DELTA exp(-SLOW t), sliding forward for ever with Lap u = 0 (free ends)."""
    p = bk.Params(gamma=GAMMA, v=V, dx=0.05)
    u0 = 2 * GAMMA * V + DELTA
    return bk.Chain(n, p, u0=u0, u_t0=np.full(n, -SLOW * DELTA), **kw)


@pytest.mark.parametrize("bad", [0.0, -1e-9, math.nan, math.inf, "1e-9", True])
def test_bad_tolerances_are_refused_naming_the_key(bad):
    with pytest.raises(bk.ParameterError, match="step_tolerance"):
        creeping(step_tolerance=bad)


def test_step_control_is_refused_with_the_midpoint_rule():
    with pytest.raises(bk.ParameterError, match="step_tolerance.*rk4"):
        creeping(step_tolerance=1e-12, integrator="midpoint")


def test_a_creeping_chain_is_followed_with_long_steps():
    exact = 2 * GAMMA * V + DELTA * math.exp(-SLOW * 20.0)
    fixed = creeping().run(20.0)
    ctrl = creeping(step_tolerance=1e-12).run(20.0, snapshots=[10.0])
    assert fixed.counters["steps"] == 8000
    # the step grows to RK4's stability limit (about 350 steps) and stays exact
    assert ctrl.counters["steps"] < 450
    assert np.max(np.abs(ctrl.u - exact)) < 1e-10
    assert abs(ctrl.energy["residual"]) < 1e-8 * ctrl.energy["viscous_work"]
    # recorded in the outputs ("none" without control)
    assert ctrl.snapshots.attrs["step_tolerance"] == 1e-12
    snap = creeping().run(1.0, snapshots=[0.5]).snapshots
    assert snap.attrs["step_tolerance"] == "none"


def test_a_controlled_run_saved_and_loaded_continues_bit_for_bit(tmp_path):
    # both stopped at t = 4 (a t_end inside an event shortens a step, so the reference is
    # the run stopped there too), one continued in place, one saved and loaded: the
    # controller's step is in the checkpoint
    whole = creeping(step_tolerance=1e-12).kick(5, -0.4, t=2.0)
    whole.run(4.0)
    part = creeping(step_tolerance=1e-12).kick(5, -0.4, t=2.0)
    part.run(4.0)
    part.save(tmp_path / "c.ckpt")
    back = bk.Chain.load(tmp_path / "c.ckpt")
    assert back.step_tolerance == 1e-12
    r_whole, r_back = whole.run(10.0), back.run(10.0)
    assert np.array_equal(r_whole.u, r_back.u) and np.array_equal(r_whole.u_t, r_back.u_t)
    assert r_whole.counters == r_back.counters
    assert r_whole.counters["steps"] < 3200  # the fixed step: 4000 to t = 10 (here 2535)
    # a chain without control (or with another tolerance) refuses these bytes
    for tol in (None, 1e-11):
        other = creeping(step_tolerance=tol)
        with pytest.raises(Exception, match="step-size control"):
            other._engine.restore(part._engine.checkpoint())
