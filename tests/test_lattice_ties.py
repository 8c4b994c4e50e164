"""Ties: identical blocks switch at identical instants (docs/lattice.md, "Ties: a lattice
uniform across y").

A lattice whose state does not vary across y has y couplings that are an exact zero
(u_{j+1} + u_{j-1} - 2 u_j of equal floats), so every row computes the chain's floats and
the rows must stay equal to the bit, through any number of events, in both event modes,
and equal the chain at dx. Before the fix the rows split at the first slip popped from the
loading queue whose twin in the next row was left at phi = 1 - 2e-15 (1.3e-13 in time,
then 1e-5 from the chain at t = 60: the rows cut separate steps).
"""

import numpy as np
import pytest

import bkwaves as bk

NX, DX, V, T_END = 24, 0.25, 0.02, 200.0
COLUMNS = ["i", "t_start", "t_end", "u_start", "u_end", "slip", "direction"]


def _u0(nx=NX):
    k = np.arange(nx)
    return 0.55 + 0.2 * np.sin(0.7 * k)


def _rows(slips, ny):
    return [slips[slips["j"] == j][COLUMNS].to_numpy() for j in range(ny)]


@pytest.mark.parametrize("events", ["local", "global"])
@pytest.mark.parametrize("ny", [2, 3, 5])
@pytest.mark.parametrize("y_boundary", ["periodic", "free"])
def test_a_loaded_lattice_uniform_across_y_stays_uniform_to_the_bit(events, ny, y_boundary):
    """24 x ny blocks periodic along x, loaded at v = 0.02 from a stress varying along x
    only, to t = 200 (253 slips and as many sticks per row): at 80 snapshots and at the
    end every row's u and u_t are row 0's bit for bit, and so is every slip record (block,
    start, end, displacements, slip). On main before the fix the rows split at t = 8.74
    (local events) or 14.70 (global cut) and ended 2e-5 to 2e-4 apart at t = 60."""
    p = bk.Params(gamma=0.45, v=V, dx=DX)
    u0 = np.tile(_u0(), (ny, 1))
    la = bk.Lattice((NX, ny), p, u0=u0, boundary=("periodic", y_boundary), events=events)
    res = la.run(t_end=T_END, snapshots=np.arange(1, 81) * 2.5, progress=False)
    snaps = res.snapshots
    assert snaps.sizes["t"] == 80
    for name in ("u", "u_t"):
        a = snaps[name].to_numpy()
        np.testing.assert_array_equal(a, np.broadcast_to(a[:, :1, :], a.shape), err_msg=name)
        # (the test can fail: the rows move; snapshots catch sliding states, not only the
        # stuck end state)
        assert np.ptp(a[:, 0, :]) > 0.01
    np.testing.assert_array_equal(la.u, np.broadcast_to(la.u[:1], la.u.shape))
    np.testing.assert_array_equal(la.u_t, np.broadcast_to(la.u_t[:1], la.u_t.shape))
    rows = _rows(res.slips, ny)
    assert len(rows[0]) >= 200 and res.counters["switches"] >= 2 * 200 * ny
    for j in range(1, ny):
        np.testing.assert_array_equal(rows[j], rows[0], err_msg=f"row {j}")


@pytest.mark.parametrize("events", ["local", "global"])
@pytest.mark.parametrize(
    ("x_boundary", "nx", "dx", "v", "seed"),
    [("periodic", 24, 0.25, 0.02, 0), ("free", 40, 0.2, 0.01, 1), ("fixed", 17, 0.25, 0.02, 3)],
)
def test_a_loaded_lattice_uniform_across_y_is_the_chain_to_the_bit(
    events, x_boundary, nx, dx, v, seed
):
    """The exact reduction over a long loaded run: every row of a lattice uniform in y
    (3 rows, periodic in y) is the chain at dx with the same event mode, bit for bit: u,
    u_t, every slip record, and the same number of steps (the same cuts). Why exact: the
    y coupling is an exact zero in the stages' force and in the Hermite data of phi that
    locate the crossings (formed as d + u - 2 up), so every float operation is the
    chain's. (Before: 5.5e-15 from the chain over t = 200 with the twins fixed, from the
    Hermite data's other sum order, and up to 1e-4 in slip times on the free 40-block
    chain, where a loaded run amplifies it; 1e-5 with the twins split.)"""
    ny = 3
    if x_boundary == "periodic":
        u0 = _u0(nx)
    else:
        f = bk.disorder.smooth_field((nx,), (dx,), 4 * dx, seed=seed)
        u0 = 0.5 + 0.3 * f
    p = bk.Params(gamma=0.45, v=v, dx=dx)
    la = bk.Lattice(
        (nx, ny), p, u0=np.tile(u0, (ny, 1)), boundary=(x_boundary, "periodic"), events=events
    )
    rl = la.run(t_end=300.0, progress=False)
    ch = bk.Chain(nx, p, x_boundary, u0=u0, events=events)
    rc = ch.run(t_end=300.0, progress=False)
    assert len(rc.slips) >= 150
    for j in range(ny):
        np.testing.assert_array_equal(la.u[j], ch.u)
        np.testing.assert_array_equal(la.u_t[j], ch.u_t)
    s = rl.slips
    for j in range(ny):
        mine = s[s["j"] == j]
        np.testing.assert_array_equal(mine["i"].to_numpy(), rc.slips["block"].to_numpy())
        for col in ("t_start", "t_end", "u_start", "slip"):
            np.testing.assert_array_equal(mine[col].to_numpy(), rc.slips[col].to_numpy())
    assert rl.counters["steps"] == rc.counters["steps"]
    assert rl.counters["switches"] == ny * rc.counters["switches"]


@pytest.mark.parametrize("dx", [0.2, 0.25])
def test_mirror_twins_of_a_loaded_chain_slip_together(dx):
    """A chain mirror-symmetric about the bond between blocks 11 and 12 (u_i = u_{23-i},
    free ends) has mirror twins whose phi are equal floats (l + r = r + l), so their
    closed-form slip times from the loading queue are equal to the bit: both slip at that
    instant and the chain stays mirror-symmetric to the bit through its events (loaded at
    v = 0.01 to t = 400, both modes). Before the fix the queue slipped one and left its
    neighbour twin (phi = 1 - ulps) for the next step: the mirror broke, 0.049 in u at
    t = 400 with the global cut at dx = 0.2, 0.021 with local events at dx = 0.25."""
    n = 24
    k = np.arange(n)
    half = 0.55 + 0.2 * np.sin(1.1 * k[: n // 2])
    u0 = np.concatenate([half, half[::-1]])
    p = bk.Params(gamma=0.45, v=0.01, dx=dx)
    for events in ("global", "local"):
        ch = bk.Chain(n, p, "free", u0=u0, events=events)
        res = ch.run(t_end=400.0, snapshots=np.arange(1, 81) * 5.0, progress=False)
        a = res.snapshots["u"].to_numpy()
        np.testing.assert_array_equal(a, a[:, ::-1], err_msg=events)
        np.testing.assert_array_equal(ch.u, ch.u[::-1])
        s = res.slips
        # each slip of the left half and its mirror image's, as sets (blocks that slip
        # at one instant are recorded in index order)
        left, right = s[s["block"] < n // 2], s[s["block"] >= n // 2]
        assert len(left) >= 60

        def records(part, mirror):
            b = part["block"].to_numpy()
            r = np.column_stack([n - 1 - b if mirror else b, part[["t_start", "t_end", "slip"]]])
            return r[np.lexsort((r[:, 0], r[:, 1]))]

        np.testing.assert_array_equal(records(left, False), records(right, True))


@pytest.mark.parametrize("events", ["local", "global"])
def test_per_block_media_loaded_lattice_uniform_across_y_is_the_chain_to_the_bit(events):
    """Thresholds, masses and loader springs varying along x (rows alike), dy != dx,
    loaded at v = 0.01 to t = 200 (251 slips): every row is the chain with the same
    per-block arrays bit for bit (u, u_t, slip records, steps). Before the fix they
    agreed to 1e-9 over 40 time units (tests/test_lattice_disorder.py)."""
    n, ny, dx, dy = 24, 3, 0.25, 0.3
    k = np.arange(n)
    u0 = 0.55 + 0.2 * np.sin(0.7 * k)
    props = {
        "threshold": 1.0 + 0.15 * np.cos(1.3 * k),
        "mass": 1.0 + 0.5 * np.sin(0.4 * k) ** 2,
        "loader": 0.7 + 0.6 * (k % 5) / 4,
    }
    p = bk.Params(gamma=0.45, v=0.01, dx=dx)
    la = bk.Lattice(
        (n, ny),
        p,
        u0=np.tile(u0, (ny, 1)),
        dy=dy,
        boundary=("free", "periodic"),
        events=events,
        **{name: np.tile(a, (ny, 1)) for name, a in props.items()},
    )
    rl = la.run(t_end=200.0, progress=False)
    ch = bk.Chain(n, p, "free", u0=u0, events=events, **props)
    rc = ch.run(t_end=200.0, progress=False)
    assert len(rc.slips) >= 200
    np.testing.assert_array_equal(la.u, np.broadcast_to(ch.u, la.u.shape))
    np.testing.assert_array_equal(la.u_t, np.broadcast_to(ch.u_t, la.u_t.shape))
    s = rl.slips
    for j in range(ny):
        mine = s[s["j"] == j]
        np.testing.assert_array_equal(mine["i"].to_numpy(), rc.slips["block"].to_numpy())
        np.testing.assert_array_equal(mine["t_start"].to_numpy(), rc.slips["t_start"].to_numpy())
        np.testing.assert_array_equal(mine["slip"].to_numpy(), rc.slips["slip"].to_numpy())
    assert rl.counters["steps"] == rc.counters["steps"]
