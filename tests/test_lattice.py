"""bk.Lattice: the plane (docs/lattice.md), against the chain it reduces to."""

import math

import numpy as np
import pytest

import bkwaves as bk


def _params(dx=0.1):
    return bk.Params(gamma=0.45, v=0.0, dx=dx)


@pytest.mark.parametrize("events", ["global", "local"])
@pytest.mark.parametrize("bx", ["free", "periodic", "fixed"])
def test_a_front_along_x_on_a_lattice_periodic_in_y_is_the_chain(events, bx):
    # u depends on i only: the y coupling of every block is an exact +0 and the x
    # coupling the chain's floats, in the stages and in the event location, so every row
    # is the chain with the same event mode to the bit: every slip record, u and u_t at
    # the end (docs/lattice.md, "Ties"; was 3.5e-14 in slip times when the event
    # location summed phi as (k_p + 2 k_x + 2 k_y) u - ..., counting the y springs)
    n, ny = 80, 3
    ch = bk.Chain(n, _params(), u0=0.6, boundary=bx, events=events)
    ch.kick(0, -2.0)
    rc = ch.run(t_end=5.0, progress=False)
    t_chain = rc.first_slip_times()
    la = bk.Lattice((n, ny), _params(), u0=0.6, boundary=(bx, "periodic"), events=events)
    for j in range(ny):
        la.kick((0, j), -2.0)
    res = la.run(t_end=5.0, progress=False)
    t = res.first_slip_times()
    assert t.shape == (ny, n)
    slipped = np.isfinite(t_chain)
    assert slipped.sum() > 40
    cols = ["t_start", "t_end", "u_start", "u_end", "slip"]
    for j in range(ny):
        assert np.array_equal(t[j], t_chain, equal_nan=True), f"row {j}"
        row = res.slips[res.slips["j"] == j]
        assert np.array_equal(row["i"].to_numpy(), rc.slips["block"].to_numpy())
        same = np.array_equal(row[cols].to_numpy(), rc.slips[cols].to_numpy(), equal_nan=True)
        assert same, f"row {j}"
        assert np.array_equal(la.u[j], ch.u) and np.array_equal(la.u_t[j], ch.u_t)


def test_a_point_rupture_gives_maps_a_catalog_and_snapshots_shaped_like_the_lattice():
    nx, ny, dy = 24, 18, 0.15
    la = bk.Lattice((nx, ny), _params(), u0=0.7, dy=dy)
    la.kick((5, 7), -2.0)
    res = la.run(t_end=30.0, snapshots=[0.5, 1.0], progress=False)
    assert la.u.shape == (ny, nx) and la.phi.shape == (ny, nx)
    t = res.first_slip_times()
    assert t.shape == (ny, nx) and t[7, 5] == 0.0
    # it spreads: the neighbours slip after the kicked block, farther blocks later
    assert 0 < t[7, 6] < t[7, 9]
    ev = res.catalog.iloc[0]
    assert (ev["hypocentre_i"], ev["hypocentre_j"]) == (5, 7)
    assert ev["hypocentre_x"] == pytest.approx(0.5) and ev["hypocentre_y"] == pytest.approx(1.05)
    assert ev["area"] == pytest.approx(ev["n_blocks"] * 0.1 * dy)
    # the moment is the integral of slip over the area
    assert np.isfinite(ev["t_end"]) and ev["duration"] > 0
    slips = res.slips[res.slips["event"] == 0]["slip"]
    assert ev["moment"] == pytest.approx(slips.sum() * 0.1 * dy, rel=1e-12)
    slip = res.slip_map()
    assert slip.shape == (ny, nx) and slip[7, 5] > 0
    ds = res.snapshots
    assert ds["u"].dims == ("t", "y", "x") and ds["u"].shape == (2, ny, nx)
    assert ds["y"].values[1] == pytest.approx(dy)
    s = res.slips.iloc[0]
    assert (s["i"], s["j"]) == (5, 7) and s["y"] == pytest.approx(7 * dy)
    assert abs(res.energy["residual"]) < 1e-8 * res.energy["viscous_work"]


def test_a_saved_lattice_continues_bit_for_bit(tmp_path):
    p = bk.Params(gamma=0.45, v=1e-2, dx=0.25)
    rng = np.random.default_rng(3)
    u0 = 0.6 + 0.05 * rng.standard_normal((12, 16))
    whole = bk.Lattice((16, 12), p, u0=u0, dy=0.3, boundary=("periodic", "fixed"))
    whole.run(t_end=30.0, progress=False)
    part = bk.Lattice((16, 12), p, u0=u0, dy=0.3, boundary=("periodic", "fixed"))
    part.run(t_end=30.0, max_events=1, progress=False)
    part.save(tmp_path / "la.npz")
    back = bk.Lattice.load(tmp_path / "la.npz")
    r = back.run(t_end=30.0, progress=False)
    assert np.array_equal(back.u, whole.u) and np.array_equal(back.u_t, whole.u_t)
    assert r.u.shape == (12, 16)


def test_bad_input_names_the_parameter():
    with pytest.raises(bk.ParameterError, match="shape"):
        bk.Lattice((0, 3), _params())
    with pytest.raises(bk.ParameterError, match="dy"):
        bk.Lattice((3, 3), _params(), dy=-1.0)
    with pytest.raises(bk.ParameterError, match="u0"):
        bk.Lattice((3, 4), _params(), u0=np.zeros((3, 4)))
    la = bk.Lattice((3, 4), _params())
    with pytest.raises(bk.ParameterError, match="block"):
        la.kick((3, 0), -1.0)
    with pytest.raises(bk.ParameterError, match="boundary"):
        bk.Lattice((3, 3), _params(), boundary=("free", "open"))


@pytest.mark.parametrize(
    "kwargs, match",
    [
        # the memory bound names the shape (it named the chain's "n"; a (2^40, 2) lattice
        # hung before it, averaging a row of 2^40 values for the default walls)
        ({"shape": (10**6, 10**6)}, r"^shape = \(1000000, 1000000\): the engine state needs"),
        ({"shape": (2**40, 2)}, r"^shape = \(1099511627776, 2\): the engine state needs"),
        # a NaN in u0 was reported as the default wall it made ("fixed[1][0] = nan")
        ({"u0": np.full((4, 3), np.nan)}, r"^invalid u0 = nan"),
        # arrays of the wrong rank: one line, their shape (the repr spanned lines)
        ({"u0": np.zeros(12)}, r"^invalid u0 = 'array of shape \(12,\)'.*\(ny, nx\) = \(4, 3\)$"),
        (
            {"threshold": np.ones((4, 3, 1))},
            r"^invalid threshold = 'array of shape \(4, 3, 1\)'.*\(4, 3\)$",
        ),
        # walls not given as pairs (a TypeError before), and each wall by its place
        ({"boundary": "fixed", "fixed": (1, 2)}, r"^invalid fixed\[0\] = 1: allowed a pair"),
        ({"boundary": "fixed", "fixed": ((np.nan, 0), (0, 0))}, r"^invalid fixed\[0\]\[0\] = nan"),
        ({"boundary": ("free", "open")}, r"^invalid boundary\[1\] = 'open': allowed one of"),
    ],
)
def test_hostile_lattice_arguments_are_one_line_errors_naming_the_parameter(kwargs, match):
    kwargs = {"shape": (3, 4), **kwargs}
    shape = kwargs.pop("shape")
    with pytest.raises(bk.ParameterError, match=match) as e:
        bk.Lattice(shape, _params(), **kwargs)
    assert "\n" not in str(e.value)


def test_a_diagonal_front_has_the_speed_of_the_chain_at_dx_over_sqrt2():
    # the measurement on an N x N torus kicked on an anti-diagonal against a ring of N
    # blocks at spacing dx/sqrt(2) kicked at block 0, stepped with the same time step:
    # the same window of the normal coordinate gives the same c (docs/lattice.md)
    nn, dx = 32, 0.2
    # tolerance inf: measured at nn (and checked at 2 nn) only, not doubled further
    diag = bk.lattice.front(0.6, 0.45, dx, angle=45, blocks=nn, tolerance=math.inf)
    h = dx / np.sqrt(2)
    ring = bk.Chain(
        nn,
        bk.Params(gamma=0.45, v=0.0, dx=h),
        "periodic",
        u0=0.6,
        step=bk.chain.DEFAULT_STEP * dx / h,
    )
    ring.kick(0, -2.0)
    t = ring.run(t_end=nn * h, progress=False).first_slip_times()
    a, b = (int(round(f * nn / 2)) for f in diag.window)
    c_ring = h * (b - a) / (t[b] - t[a])
    assert diag.spacing == pytest.approx(h)
    assert np.isfinite(diag.c) and diag.c > 1.0
    assert abs(diag.c - c_ring) < 1e-10 * c_ring, (diag, c_ring)
    with pytest.raises(bk.ParameterError, match="angle"):
        bk.lattice.front(0.6, 0.45, 0.2, angle=30)


def test_a_point_rupture_tends_to_the_planar_speeds_from_below():
    # c(R) along x and along the diagonal rises towards the planar speeds (the chain at dx,
    # at dx/sqrt(2)); D = (c_planar - c) R > 0 is the eikonal coefficient
    r = bk.lattice.rupture(0.6, 0.45, 0.2, 48, check=False)
    assert r.arrival.shape == (48, 48)
    assert np.array_equal(r.arrival, r.arrival.T, equal_nan=True)  # x <-> y: exact
    for k in ("x", "diagonal"):
        c0, d = r.fits[k]
        assert abs(c0 - r.planar[k]) < 0.01 * r.planar[k], (k, c0, r.planar)
        assert d > 0 and all(e > 0 for e in r.eikonal[k]), (k, r.eikonal)
        far = r.profiles[k]["c"][-3]
        assert far < r.planar[k]


def test_a_line_kicked_across_a_lattice_periodic_in_x_is_the_chain_at_dy():
    # every column of a lattice periodic in x whose row j0 is kicked along its whole
    # length is the same chain along y: the x Laplacian vanishes identically, so each
    # column's first slip times are the chain's at spacing dy (the lattice's step is
    # step min(dx, dy) = step dy, the chain's step dy: the same)
    nx, ny, dx, dy, j0 = 3, 60, 0.15, 0.1, 20
    ch = bk.Chain(ny, _params(dy), u0=0.6)
    ch.kick(j0, -2.0)
    t_chain = ch.run(t_end=4.0, progress=False).first_slip_times()
    # (the global cut, as the chain's: equal to round-off; see the test above)
    la = bk.Lattice(
        (nx, ny), _params(dx), u0=0.6, dy=dy, boundary=("periodic", "free"), events="global"
    )
    line = {"line": ((0, j0), (nx - 1, j0))}
    assert la.blocks(line).tolist() == [[i, j0] for i in range(nx)]
    t = la.kick(line, -2.0).run(t_end=4.0, progress=False).first_slip_times()
    slipped = np.isfinite(t_chain)
    assert slipped.sum() > 30
    for i in range(nx):
        assert np.array_equal(np.isfinite(t[:, i]), slipped)
        assert np.max(np.abs(t[:, i][slipped] - t_chain[slipped])) < 1e-12


def test_line_and_disc_regions_are_the_blocks_they_name():
    la = bk.Lattice((30, 20), _params(0.1), u0=0.6, dy=0.2)
    # a diagonal, a column and a segment of slope 1/2 (the blocks nearest to it)
    assert la.blocks({"line": ((2, 3), (5, 6))}).tolist() == [[2, 3], [3, 4], [4, 5], [5, 6]]
    assert la.blocks({"line": ((7, 9), (7, 5))})[:, 1].tolist() == [5, 6, 7, 8, 9]
    seg = la.blocks({"line": ((0, 0), (4, 2))})
    assert seg.tolist() == la.blocks({"line": ((4, 2), (0, 0))}).tolist()
    assert len(seg) == 5 and set(seg[:, 1]) == {0, 1, 2}
    # a disc is a circle in (x, y) = (i dx, j dy): semi-axes r/dx = 5 and r/dy = 2.5 blocks
    d = la.blocks({"disc": ((15, 10), 0.5)})
    di, dj = d[:, 0] - 15, d[:, 1] - 10
    assert di.max() == 5 and di.min() == -5 and dj.max() == 2 and dj.min() == -2
    brute = [
        (i, j)
        for j in range(20)
        for i in range(30)
        if ((i - 15) * 0.1) ** 2 + ((j - 10) * 0.2) ** 2 <= 0.25
    ]
    assert [tuple(b) for b in d] == brute
    assert la.blocks({"disc": ((15, 10), 0.0)}).tolist() == [[15, 10]]
    with pytest.raises(bk.ParameterError, match="block"):
        la.kick({"ring": ((1, 1), 2.0)}, -2.0)
    with pytest.raises(bk.ParameterError, match="radius"):
        la.kick({"disc": ((1, 1), -1.0)}, -2.0)
    with pytest.raises(bk.ParameterError, match="block"):
        la.kick({"line": ((0, 0), (30, 0))}, -2.0)


def test_a_disc_of_radius_zero_is_a_point_kick_and_a_disc_rupture_is_symmetric():
    def run(region):
        la = bk.Lattice((21, 21), _params(0.2), u0=0.6)
        return la.kick(region, -2.0).run(t_end=2.0, progress=False).first_slip_times()

    point = run((10, 10))
    assert np.array_equal(run({"disc": ((10, 10), 0.0)}), point, equal_nan=True)
    t = run({"disc": ((10, 10), 0.45)})  # i^2 + j^2 <= 5.06: 21 blocks
    assert np.count_nonzero(t == 0.0) == 21
    ok = np.isfinite(t)
    assert ok.sum() > 21 and np.isfinite(point).sum() < ok.sum()
    for other in (t[::-1], t[:, ::-1], t.T):
        assert np.array_equal(np.isfinite(other), ok)
        assert np.array_equal(other[ok], t[ok])  # reflections and x <-> y: exact


def test_per_bond_springs_shapes_checkpoints_and_errors(tmp_path):
    # k_x: (ny, bonds of a row), k_y: (bonds of a column, nx); free x (nx - 1 bonds),
    # periodic y (ny bonds); all ones is the uniform lattice bit for bit
    nx, ny = 12, 9
    p = bk.Params(gamma=0.45, v=1e-2, dx=0.2)
    rng = np.random.default_rng(3)
    u0 = 0.6 + 0.2 * rng.random((ny, nx))

    def lattice(coupling):
        la = bk.Lattice((nx, ny), p, u0=u0, boundary=("free", "periodic"), coupling=coupling)
        return la.kick((3, 4), -2.0)

    ones = (np.ones((ny, nx - 1)), np.ones((ny, nx)))
    a = lattice(None).run(t_end=20.0, progress=False)
    b = lattice(ones).run(t_end=20.0, progress=False)
    assert (
        np.array_equal(a.first_slip_times(), b.first_slip_times(), equal_nan=True)
        and np.isfinite(a.first_slip_times()).sum() > 20
    )
    kx = 1.0 + 0.5 * rng.random((ny, nx - 1))
    ky = 0.5 * rng.random((ny, nx))
    la = lattice((kx, ky))
    la.run(t_end=5.0, progress=False)
    la.save(tmp_path / "la.npz")
    back = bk.Lattice.load(tmp_path / "la.npz")
    r1 = la.run(t_end=20.0, progress=False)
    r2 = back.run(t_end=20.0, progress=False)
    assert np.array_equal(la.u, back.u) and np.array_equal(r1.slip_map(), r2.slip_map())
    assert not np.allclose(r1.slip_map(), b.slip_map())
    with pytest.raises(bk.ParameterError, match=r"coupling\[0\]"):
        lattice((np.ones((ny, nx)), 1.0))
    with pytest.raises(bk.ParameterError, match=r"coupling\[1\]\[2, 5\]"):
        bad = np.ones((ny, nx))
        bad[2, 5] = -1.0
        lattice((1.0, bad))
    with pytest.raises(bk.ParameterError, match="coupling"):
        lattice(2.0)


def test_a_rupture_with_dx_over_dy_1_5_tends_to_a_circle_in_the_plane():
    # the continuum problem is isotropic in (x, y) = (i dx, j dy): the aspect in blocks
    # tends to dy/dx as dx -> 0 (docs/lattice.md: 0.029, 0.018, 0.012 above it at t = 1
    # for dx = 0.2, 0.1, 0.05); two spacings here
    dev = []
    for dx in (0.2, 0.1):
        dy = dx / 1.5
        r = bk.lattice.rupture(0.6, 0.45, dx, size=int(round(4.0 / dx)), dy=dy, check=False)
        dev.append(r.aspect(1.0) * dx / dy - 1.0)
    assert 0.0 < dev[1] < 0.8 * dev[0] < 0.03


def test_save_replaces_only_a_bkwaves_checkpoint(tmp_path):
    # Lattice.save (and Chain.save) wrote over any file at the path: a user's file of the
    # same name was lost
    la = bk.Lattice((4, 3), _params(), u0=0.5)
    mine = tmp_path / "notes.npz"
    mine.write_text("my notes")
    with pytest.raises(bk.ParameterError, match=r"^not replacing .*notes\.npz: it is not a"):
        la.save(mine)
    with pytest.raises(bk.ParameterError, match="not replacing"):
        bk.Chain(5, _params()).save(mine)
    assert mine.read_text() == "my notes"
    (tmp_path / "folder.npz").mkdir()
    with pytest.raises(bk.ParameterError, match="not replacing"):
        la.save(tmp_path / "folder.npz")
    # an earlier checkpoint is replaced (of any kind: a chain's by a lattice's)
    ck = tmp_path / "ck.npz"
    bk.Chain(5, _params()).save(ck)
    la.save(ck)
    assert bk.Lattice.load(ck).shape == (4, 3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ck.npz", "folder.npz", "notes.npz"]
