"""Velocity weakening on the lattice (docs/lattice.md, "Velocity weakening on the
lattice"): the onsets' sub-steps in the plane, against the chain it reduces to."""

import numpy as np

import bkwaves as bk


def _params(dx=0.1, v_f=1e-4):
    law = bk.friction.law("velocity_weakening", v_f=v_f)
    return bk.Params(gamma=0.3, v=0.0, dx=dx, friction_law=law)


def test_a_velocity_weakening_front_along_x_periodic_in_y_is_the_chain():
    # every row is the chain: each row's onset is a part of the same patch (the rows'
    # blocks at the front are neighbours), stiff alike, so the patch takes the chain's
    # sub-steps and the rows its times
    n, ny = 60, 3
    ch = bk.Chain(n, _params(), u0=0.6)
    ch.kick(0, -2.0)
    res_c = ch.run(t_end=4.0, progress=False)
    t_chain = res_c.first_slip_times()
    la = bk.Lattice((n, ny), _params(), u0=0.6, boundary=("free", "periodic"), events="global")
    for j in range(ny):
        la.kick((0, j), -2.0)
    res = la.run(t_end=4.0, progress=False)
    t = res.first_slip_times()
    slipped = np.isfinite(t_chain)
    assert slipped.sum() > 30
    # the onsets took sub-steps (else this would test the Coulomb path), the same in
    # every row as in the chain
    coulomb = bk.Chain(n, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6)
    coulomb.kick(0, -2.0)
    plain = coulomb.run(t_end=4.0, progress=False).counters["block_steps"]
    assert res_c.counters["block_steps"] > 2 * plain
    assert res.counters["block_steps"] == ny * res_c.counters["block_steps"]
    for j in range(ny):
        assert np.array_equal(np.isfinite(t[j]), slipped)
        assert np.max(np.abs(t[j][slipped] - t_chain[slipped])) < 1e-12


def _rupture(shape, params):
    nx, ny = shape
    return bk.Lattice(shape, params, u0=0.6).kick((nx // 2, ny // 2), -2.0)


def test_the_plane_healing_after_a_rupture_costs_a_bounded_multiple_of_coulomb():
    # the rupture fills the lattice, every block slides, then the plane heals: many
    # blocks near rest at once, each with its stiff 1/s tail. The onsets' patch is split
    # into groups of one stiffness class, each on its own sub-steps (chain/onset.rs);
    # the patch takes at a step's start the blocks that will be stiff in it, and a redo up
    # to an event starts from the last integration's dense output: 6.7x the Coulomb run's
    # block-steps to t = 5 (8.6x before those two, 38.6x with each connected part of the
    # patch on the sub-steps of its stiffest block; on 48 x 32 10.8x, 14.4x, against
    # today's Coulomb run), the same rupture and healing (docs/lattice.md, "Velocity
    # weakening on the lattice")
    shape, t_end = (24, 16), 5.0
    plain = _rupture(shape, bk.Params(gamma=0.3, v=0.0, dx=0.1)).run(t_end=t_end, progress=False)
    la = _rupture(shape, _params())
    res = la.run(t_end=t_end, progress=False)
    ratio = res.counters["block_steps"] / plain.counters["block_steps"]
    assert ratio < 7.5, ratio
    # every block slipped, and about as many slips and sticks as with Coulomb friction
    n = shape[0] * shape[1]
    assert np.isfinite(res.first_slip_times()).all()
    assert abs(len(res.slips) - len(plain.slips)) < 0.05 * n
    assert abs(res.counters["switches"] - plain.counters["switches"]) < 0.1 * n
    # where the work went (the engine's onset_stats): the patch seldom grows after a
    # step (15 of 1081 steps with a patch; 261 of 1077 when it took only the blocks
    # stiff at the step's start), a redo takes no loose pass, and the parts add up
    st = la._engine.onset_stats()
    assert st["steps"] > 500
    assert st["integrations_growth"] < 0.03 * st["steps"], st
    assert st["integrations_redo"] > 0.3 * st["steps"], st
    assert st["loose_block_steps_redo"] == 0 and st["group_block_steps_redo"] > 0, st
    parts = sum(
        st[f"{w}_block_steps_{c}"] for w in ("group", "runs") for c in ("first", "growth", "redo")
    )
    assert (
        0.5 * res.counters["block_steps"]
        < parts + st["turned_block_steps"]
        <= res.counters["block_steps"]
    )
    # Coulomb friction has no onsets: nothing counted
    co = _rupture(shape, bk.Params(gamma=0.3, v=0.0, dx=0.1))
    co.run(t_end=1.0, progress=False)
    assert not any(co._engine.onset_stats().values())


def test_a_velocity_weakening_rupture_converges_in_the_step():
    # first slip times of a rupture from the centre (onsets at the front, the parts of
    # the patch on their own sub-steps) at step 0.1, 0.05, 0.025, 0.0125: the changes
    # fall by more than 8 per halving (measured 4.7e-6, 2.0e-8, 2.3e-9: 240, 8.6)
    times = []
    for step in (0.1, 0.05, 0.025, 0.0125):
        la = bk.Lattice((20, 14), _params(), u0=0.6, step=step).kick((10, 7), -2.0)
        times.append(la.run(t_end=1.2, progress=False).first_slip_times())
    slipped = np.isfinite(times[0])
    assert slipped.sum() > 200
    changes = []
    for a, b in zip(times[:-1], times[1:], strict=True):
        assert np.array_equal(np.isfinite(b), slipped)
        changes.append(np.max(np.abs(a[slipped] - b[slipped])))
    assert changes[0] < 1e-5 and changes[-1] < 1e-8, changes
    assert all(x > 8 * y for x, y in zip(changes[:-1], changes[1:], strict=True)), changes
