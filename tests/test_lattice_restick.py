"""A lone sliding block in a stuck lattice (docs/lattice.md, "Measured: the stress an
irregular healing leaves"): the creep state the loaded run's last sliding blocks sit in,
derived, and the stress it passes to its stuck neighbours.

A sliding block whose four neighbours are stuck obeys u_tt = -phi - 2 gamma (u_t - v) with
phi_t = (1 + 4/dx^2) u_t - 4 v/dx^2: its fixed point is the speed over the ground
s = v - u_t = v/(1 + 4/dx^2) with phi = 2 gamma s, about which it oscillates at frequency
sqrt(1 + 4/dx^2), damped at the rate gamma. Each stuck neighbour's phi then rises at
v + s/dx^2.
"""

import numpy as np
import pytest

import bkwaves as bk

DX, GAMMA, V, N = 0.2, 0.45, 0.02, 5
S_CREEP = V / (1 + 4 / DX**2)


def lone_block(s0: float) -> bk.Lattice:
    """A periodic 5 x 5 lattice, all stuck at u = 0 except the centre, sliding at speed s0
    over the ground with phi at the creep state's 2 gamma S_CREEP."""
    u0 = np.zeros((N, N))
    u0[2, 2] = 2 * GAMMA * S_CREEP / (1 + 4 / DX**2)
    u_t0 = np.full((N, N), V)
    u_t0[2, 2] = V - s0
    return bk.Lattice((N, N), bk.Params(gamma=GAMMA, v=V, dx=DX), u0=u0, u_t0=u_t0,
                      boundary="periodic")  # fmt: skip


def test_a_lone_block_at_the_creep_state_creeps_on_and_loads_its_neighbours():
    la = lone_block(S_CREEP)
    assert la.modes[2, 2] == 1
    phi_n0 = la.phi[2, 3]
    la.run(t_end=10.0, progress=False)
    assert la.modes[2, 2] == 1  # never sticks
    assert V - la.u_t[2, 2] == pytest.approx(S_CREEP, rel=1e-9)
    assert la.phi[2, 2] == pytest.approx(2 * GAMMA * S_CREEP, rel=1e-9)
    # a stuck neighbour: v per unit time from the loader, s/dx^2 from the spring
    rate = (la.phi[2, 3] - phi_n0) / 10.0
    assert rate == pytest.approx(V + S_CREEP / DX**2, rel=1e-6)
    # (not the rate of a neighbour of a stuck block: v)
    assert abs(rate - V) > 0.2 * V


@pytest.mark.parametrize(("s0", "sticks"), [(0.5 * S_CREEP, False), (2.5 * S_CREEP, True)])
def test_a_lone_block_sticks_only_if_its_swing_reaches_zero_speed(s0, sticks):
    """Started s0 - S_CREEP off the fixed point, the speed swings to S_CREEP - (s0 - S_CREEP)
    exp(-gamma pi/omega) half a period later: below 0 (it sticks) for s0 = 2.5 S_CREEP
    (-0.30 S_CREEP), never for s0 = 0.5 S_CREEP (the swing stays within 0.5 S_CREEP)."""
    omega = np.sqrt(1 + 4 / DX**2)
    half = S_CREEP - (s0 - S_CREEP) * np.exp(-GAMMA * np.pi / omega)
    assert (half < 0) == sticks
    la = lone_block(s0)
    res = la.run(t_end=5.0, progress=False)
    assert (la.modes[2, 2] == 0) == sticks
    if sticks:
        t_stick = res.slips["t_end"].dropna()
        assert len(t_stick) == 1
        # the first zero of s lies within the first half period
        assert 0 < t_stick.iloc[0] < np.pi / omega
    else:
        assert V - la.u_t[2, 2] == pytest.approx(S_CREEP, abs=0.5 * S_CREEP)
