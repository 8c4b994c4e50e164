"""Local events from Python and configs (docs/lattice.md, "Local events"): ``events=
"local" | "global"`` on bk.Lattice (and bk.Chain), ``run.events`` in a config, against
the global cut, through checkpoints, and refused where they cannot apply."""

from __future__ import annotations

import numpy as np
import pytest

import bkwaves as bk
from bkwaves.config import parse_config


def _rupture(step, events, t_end=6.0):
    """A point rupture on 20 x 16 blocks, free along x and periodic along y, dx = 0.25,
    dy = 0.3 (u_+ = 0.6, gamma = 0.45: every block slips, the centre sticks again)."""
    p = bk.Params(gamma=0.45, v=0.0, dx=0.25)
    la = bk.Lattice(
        (20, 16), p, u0=0.6, dy=0.3, boundary=("free", "periodic"), step=step, events=events
    )
    la.kick((6, 8), -2.0)
    return la, la.run(t_end=t_end, progress=False)


def _slips_per_block(res):
    return res.slips.groupby("block").size().sort_index()


def test_local_events_give_the_global_cuts_slips_to_the_steps_order():
    """Both modes slip the same blocks as often; their first slip times differ by the
    step's error, which falls at the integrator's order (4: by 16 per halving) as the
    step halves, so the test fails if the two modes solve different problems (measured:
    2.2e-6, 1.3e-7, 6.0e-9 at steps 0.1, 0.05, 0.025; 323 slips in both)."""
    diffs = []
    for step in (0.1, 0.05):
        g, rg = _rupture(step, "global")
        loc, rl = _rupture(step, "local")
        assert (g.events, loc.events) == ("global", "local")
        # the mode is the engine's: local events took the steps with switches
        assert loc._engine.local_stats()["event_steps"] > 50
        assert g._engine.local_stats()["event_steps"] == 0
        tg, tl = rg.first_slip_times(), rl.first_slip_times()
        assert np.isfinite(tg).all()
        np.testing.assert_array_equal(np.isfinite(tl), np.isfinite(tg))
        assert _slips_per_block(rg).equals(_slips_per_block(rl))
        assert rg.catalog.shape == rl.catalog.shape
        diffs.append(float(np.max(np.abs(tl - tg))))
    assert 0 < diffs[0] < 1e-5, diffs
    assert diffs[0] / max(diffs[1], 1e-300) > 8, diffs


def test_a_local_lattice_checkpoint_continues_bit_for_bit(tmp_path):
    p = bk.Params(gamma=0.45, v=1e-2, dx=0.25)
    rng = np.random.default_rng(3)
    u0 = 0.6 + 0.05 * rng.standard_normal((12, 16))

    def build():
        return bk.Lattice(
            (16, 12), p, u0=u0, dy=0.3, boundary=("periodic", "fixed"), events="local"
        )

    whole = build()
    rw = whole.run(t_end=30.0, progress=False)
    part = build()
    part.run(t_end=30.0, max_events=1, progress=False)
    part.save(tmp_path / "la.npz")
    back = bk.Lattice.load(tmp_path / "la.npz")
    assert back.events == "local"
    rb = back.run(t_end=30.0, progress=False)
    assert whole._engine.local_stats()["event_steps"] > 0
    assert np.array_equal(back.u, whole.u) and np.array_equal(back.u_t, whole.u_t)
    np.testing.assert_array_equal(rb.slips["t_start"], rw.slips["t_start"])
    # the engine's bytes of one mode are refused by an engine of the other
    glob = bk.Lattice((16, 12), p, u0=u0, dy=0.3, boundary=("periodic", "fixed"), events="global")
    with pytest.raises(bk.ParameterError, match="event location") as e:
        glob._engine.restore(part._engine.checkpoint())
    assert "\n" not in str(e.value)


def test_events_bad_values_and_where_local_events_cannot_apply():
    p = bk.Params(gamma=0.45, v=0.0, dx=0.25)
    with pytest.raises(bk.ParameterError, match=r"events.*global.*local") as e:
        bk.Lattice((4, 4), p, events="fast")
    assert "\n" not in str(e.value)
    with pytest.raises(bk.ParameterError, match=r"events.*midpoint"):
        bk.Lattice((4, 4), p, step=0.2, integrator="midpoint", events="local")
    with pytest.raises(bk.ParameterError, match=r"events.*step_tolerance"):
        bk.Lattice((4, 4), p, step_tolerance=1e-12, events="local")
    # a law whose onset takes sub-steps (velocity weakening with v_f << dx)
    vw = bk.Params(
        gamma=0.3, v=0.0, dx=0.25, friction_law=bk.friction.law("velocity_weakening", v_f=1e-4)
    )
    with pytest.raises(bk.ParameterError, match=r"events.*sub-steps") as e:
        bk.Lattice((4, 4), vw, events="local")
    assert "\n" not in str(e.value)
    # where they cannot apply, the global cut is the one asked for and allowed
    assert bk.Lattice((4, 4), vw, events="global").events == "global"
    assert bk.Lattice((4, 4), p, step=0.2, integrator="midpoint").events == "global"
    # the chain takes them too (the same engine); its default is the global cut
    assert bk.Chain(8, p).events == "global"
    assert bk.Chain(8, p, events="local").events == "local"


RUPTURE = {
    "model": "lattice",
    "params": {"gamma": 0.45, "v": 0.0, "dx": 0.25},
    "domain": {"shape": [20, 16], "dy": 0.3, "boundary": ["free", "periodic"]},
    "initial": {"kind": "uniform", "value": 0.6},
    "triggers": [{"block": [6, 8], "kind": "kick", "velocity": 2.0}],
    "run": {"t_end": 3.0, "events": "local"},
    "output": {"arrivals": True},
}


def test_a_config_with_run_events_runs_as_the_lattice_built_by_hand(tmp_path):
    out = tmp_path / "la.nc"
    res = bk.run(RUPTURE, out)
    la, ref = _rupture(0.05, "local", t_end=3.0)
    sl = res.tables["slips"]
    np.testing.assert_array_equal(sl["t_start"], ref.slips["t_start"])
    np.testing.assert_array_equal(sl["slip"], ref.slips["slip"])
    # ... and not as the global cut's (the key reaches the engine)
    _, glob = _rupture(0.05, "global", t_end=3.0)
    assert not np.array_equal(sl["t_start"], glob.slips["t_start"])
    ds, _ = bk.io.load_tables(out)
    assert ds.attrs["events"] == "local"
    cfg = parse_config(RUPTURE)
    assert cfg.events == "local" and parse_config(cfg.to_dict()) == cfg


@pytest.mark.parametrize(
    ("run", "message"),
    [
        ({"events": "fast"}, r"run\.events: .*global, local"),
        ({"events": "local", "integrator": "midpoint", "step": 0.2}, r"run\.events: .*midpoint"),
        ({"events": "local", "step_tolerance": 1e-12}, r"run\.events: .*step_tolerance"),
    ],
)
def test_config_events_errors_name_the_key(run, message):
    doc = {**RUPTURE, "run": {"t_end": 3.0, **run}}
    with pytest.raises(bk.ParameterError, match=message) as e:
        parse_config(doc)
    assert "\n" not in str(e.value)


def _front_rows(step, events):
    """A planar front on 60 x 3 blocks periodic in y, kicked on column 0 (u_+ = 0.6,
    gamma = 0.45, dx = 0.1): every row is the chain at dx."""
    p = bk.Params(gamma=0.45, v=0.0, dx=0.1)
    kw = {} if events is None else {"events": events}
    la = bk.Lattice((60, 3), p, u0=0.6, boundary=("free", "periodic"), step=step, **kw)
    for j in range(3):
        la.kick((0, j), -2.0)
    return la, la.run(t_end=5.0, progress=False).first_slip_times()


def test_the_local_default_is_the_exact_reduction_to_the_steps_accuracy():
    """The lattice's default is local events; the exact reductions (tests/test_lattice.py:
    a planar front = the chain at dx, to 1e-12) pin the global cut, the chain's. With the
    default, every row is the chain's slip times within the step's error, which falls at
    order 4 as the step halves (measured 5.1e-7, 4.5e-8, 3.2e-9 at steps 0.1, 0.05, 0.025)."""
    diffs = []
    for step in (0.1, 0.05):
        ch = bk.Chain(60, bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.6, step=step)
        t_chain = ch.kick(0, -2.0).run(t_end=5.0, progress=False).first_slip_times()
        la, t = _front_rows(step, None)
        assert la.events == "local" and ch.events == "global"
        slipped = np.isfinite(t_chain)
        assert slipped.sum() > 40
        for j in range(3):
            np.testing.assert_array_equal(np.isfinite(t[j]), slipped)
        diffs.append(float(np.max(np.abs(t[:, slipped] - t_chain[slipped]))))
        # the global cut is the chain to round-off
        _, tg = _front_rows(step, "global")
        assert np.max(np.abs(tg[:, slipped] - t_chain[slipped])) < 1e-12
    assert 0 < diffs[0] < 2e-6, diffs
    assert diffs[0] / diffs[1] > 8, diffs
