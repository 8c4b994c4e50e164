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
