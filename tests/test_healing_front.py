"""The stress a healing (re-sticking) front leaves behind it (docs/lattice.md, "Derived:
the stress a healing front leaves").

Across a healing front moving at speed c_h (along its normal), u, u_t = v and u_x are
continuous; differentiating the continuity along the front gives [u_tt] = c_h^2 [u_xx]. Just
ahead the block slides with u_tt = a (the rate at which its speed over the ground falls to
zero) and phi = u - u_xx = -u_tt - 2 gamma (u_t - v) = -a; just behind it is stuck, u_tt = 0.
So the stress left is

    phi_left = -a + a/c_h^2 = a (1/c_h^2 - 1),

below zero for a supersonic front (c_h > 1), at the threshold 1 when c_h^2 = a/(1 + a), and
unbounded where the front stops (c_h -> 0): a block next to a stopped healing front is
pushed past the threshold by its sliding neighbours and slips again. For the steady pulse
(c_h = c, a = -c^2 u_-/(c^2 - 1) from the paper's eq. slidet) it is the paper's u_-.

Checked on the discrete chain (a ring with two stress bumps, the 1D loaded run of
docs/scripts/lattice_later_ruptures.py at scale 2): the healing that starts at the
hypocentre runs outward at c_h from 70 down to 2.5, and the stress each block keeps
follows a (1/c_h^2 - 1) at two dx; the first healing front stops 4.2 from the
hypocentre, and the blocks that slip again in the first cycle are there.
"""

import numpy as np
import pytest

import bkwaves as bk

GAMMA, SIDE, V, SIGMA = 0.45, 24.0, 0.01, 3.0
X_HYPO = 6.0  # the highest bump (0.25 of the side): the first birth, t = 9.0
FRAME = 0.0025


def ring(dx):
    """The ring: stress 0.6 plus two Gaussian bumps (peaks 0.91 and ~0.905), set exactly as
    phi = u - Lap u by FFT."""
    n = int(round(SIDE / dx))
    x = np.arange(n) * dx
    f = np.zeros(n)
    for c, h in ((0.25, 1.0), (0.75, 0.985)):
        for sh in (-SIDE, 0.0, SIDE):
            f += h * np.exp(-((x - c * SIDE - sh) ** 2) / (2 * SIGMA**2))
    target = 0.6 + 0.31 * f / f.max()
    lap = -(4 / dx**2) * np.sin(np.pi * np.fft.fftfreq(n)) ** 2
    u0 = np.real(np.fft.ifft(np.fft.fft(target) / (1 - lap)))
    ch = bk.Chain(n, bk.Params(gamma=GAMMA, v=V, dx=dx), u0=u0, boundary="periodic")
    assert np.abs(np.asarray(ch.phi) - target).max() < 1e-10
    return x, ch


def first_sticks(slips, n):
    first = slips.sort_values("t_start").groupby("block").first()
    t = np.full(n, np.nan)
    t[first.index] = first["t_end"]
    return t


@pytest.fixture(scope="module", params=[0.025, 0.0125])
def healing(request):
    """Per block between 2.6 and 5.9 (the healing from the hypocentre outward): a, c_h and
    the stress kept."""
    dx = request.param
    x, ch = ring(dx)
    ch.run(t_end=12.6, progress=False)
    ts = np.arange(12.6 + FRAME, 13.6 + 1e-9, FRAME)
    phis, modes, uts = [], [], []
    for t in ts:
        ch.run(t_end=float(t), progress=False)
        phis.append(np.array(ch.phi))
        modes.append(np.array(ch.modes))
        uts.append(np.array(ch.u_t))
    phis, modes, uts = np.array(phis), np.array(modes), np.array(uts)
    t_st = first_sticks(ch.run(t_end=13.6, progress=False).slips, len(x))
    idx = np.where((x > 2.6) & (x < 5.9))[0]
    a, c_h, left = [], [], []
    for i in idx:
        # a: the speed over the ground falls linearly to 0 at the stick (t_st, from the
        # located event); read 2-4.5e-3 before it
        k = np.searchsorted(ts, t_st[i] - 0.002) - 1
        a.append((V - uts[k, i]) / (t_st[i] - ts[k]))
        c_h.append(2 * dx / abs(t_st[i + 1] - t_st[i - 1]))
        # kept: at the first frame with the block and both neighbours stuck, less the
        # loading since the stick
        ok = np.where((ts > t_st[i]) & (modes[:, i] == 0) & (modes[:, i - 1] == 0)
                      & (modes[:, i + 1] == 0))[0]  # fmt: skip
        left.append(phis[ok[0], i] - V * (ts[ok[0]] - t_st[i]))
    return dx, np.array(a), np.array(c_h), np.array(left)


def test_the_stress_left_is_a_over_c_h_squared_minus_a(healing):
    dx, a, c_h, left = healing
    assert c_h.min() < 3.0 and c_h.max() > 40.0  # the front slows from 40+ to ~2.5
    err = left - a * (1 / c_h**2 - 1)
    # measured: max 0.0063, 0.0051 and rms 0.0027, 0.0018 at dx = 0.025, 0.0125
    assert np.abs(err).max() < 0.0075 * (dx / 0.025) ** 0.25
    assert np.sqrt(np.mean(err**2)) < 0.0032 * (dx / 0.025) ** 0.5
    # the alternatives miss: the stress frozen at the stick (-a, no jump), and the jump of
    # the steady pulse's speed c(u_+) (1.89 here) instead of the front's own
    assert np.abs(left + a).max() > 0.011
    c = bk.front_speed(0.85, dx=dx, gamma=GAMMA)
    assert np.abs(left - a * (1 / c**2 - 1)).max() > 0.03


def test_where_the_first_healing_front_stops_the_blocks_slip_again():
    """The healing front from the hypocentre stops 4.2 from it (its first-stick time jumps
    by about 1 from one block to the next); the blocks that slip again in the first cycle
    lie at that stop and within 1 behind it, at both dx."""
    stops = []
    for dx in (0.025, 0.0125):
        x, ch = ring(dx)
        slips = ch.run(t_end=16.0, progress=False).slips
        t_st = first_sticks(slips, len(x))
        j = np.where((x > 0.5) & (x < X_HYPO))[0]
        jump = np.abs(np.diff(t_st[j]))
        k = int(np.nanargmax(jump))
        assert jump[k] > 0.5
        x_stop = 0.5 * (x[j[k]] + x[j[k + 1]])
        stops.append(x_stop)
        counts = np.bincount(slips["block"], minlength=len(x))
        again = x[(counts > 1) & (x > 0.5) & (x < X_HYPO)]
        assert len(again) >= 3
        assert again.min() > x_stop - 0.1 and again.max() < x_stop + 1.0
    assert abs(stops[0] - stops[1]) < 0.05
    assert X_HYPO - stops[1] == pytest.approx(4.2, abs=0.15)
