"""bk.FreeBoundary2D: the free boundary problem in the plane (docs/free_boundary_2d.md).

The engine's accuracy (circles at second order, the planar reduction to the 1D engine node
by node, conservation, checkpoints) is tested in Rust (crates/bkwaves-core/src/
free_boundary_2d/tests.rs); here: the Python surface against independent computations."""

import doctest

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import free_boundary_2d as fb2d


def test_module_example():
    assert doctest.testmod(fb2d).failed == 0


def test_a_triggered_disk_spreads_as_a_circle_at_c():
    # v = 0, uniform u0: T = (r - rho)/c(u0) outside the triggered disk of radius rho
    p = bk.Params(gamma=0.3, v=0.0, dx=1e-2)
    h, rho, u0 = 0.1, 0.5, 0.6
    fb = bk.FreeBoundary2D(p, (101, 101), h, u0, "free", origin=(-5, -5), record_arrivals=True)
    fb.trigger(0.0, 0.0, radius=rho)
    r = fb.run(max_events=1)
    t = fb.arrival_time(0)
    xx, yy = np.meshgrid(fb.x, fb.y)
    rr = np.hypot(xx, yy)
    c = bk.front_speed(u0)
    exact = np.maximum(rr - rho, 0.0) / c
    # the disk of nodes is jagged to O(h): errors O(h/c) (measured 0.49 h/c at r < 1,
    # 0.40 h/c beyond, 0.26 and 0.20 h/c at h = 0.05), not growing with r
    err = np.abs(t - exact)
    near, far = err[(rr > 1) & (rr < 2)], err[(rr > 3) & (rr < 4.5)]
    assert err[rr < 4.5].max() < 0.65 * h / c, err.max()
    assert far.max() <= near.max() + 1e-6 and far.mean() < 1.2 * near.mean()
    # the same times in last_arrival; the stress left is u_-(u0) from bk.traveling_wave
    np.testing.assert_array_equal(fb.last_arrival(), t)
    um = bk.traveling_wave(u0, 0.3).u_minus
    np.testing.assert_allclose(r.snapshots.u.isel(t=-1).values, um, atol=1e-12)
    row = r.ruptures.iloc[0]
    assert row.origin == "trigger" and row.complete and row.n_nodes == 101 * 101
    assert row.moment == pytest.approx(row.area * (u0 - um), rel=1e-12)


def test_a_planar_run_has_the_births_of_the_1d_engine():
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
    h, length = 0.1, 40.0
    x = np.arange(0, length, h)
    k = 2 * np.pi / length
    u1 = 0.85 + 0.1 * np.cos(k * x) + 0.04 * np.sin(3 * k * x + 0.3)
    with pytest.warns(bk.NoCreepWarning):  # (the 2D engine does not check eq. nocreep)
        one = bk.FreeBoundary(p, x, u1, "periodic").run(t_end=395.0)
    two = bk.FreeBoundary2D(p, (x.size, 3), h, np.tile(u1, (3, 1)), "periodic").run(t_end=395.0)
    births_1d = one.shocks[one.shocks.kind == "birth"].drop_duplicates(["t", "x"])
    b2 = two.ruptures[two.ruptures.origin == "birth"]
    assert len(b2) == len(births_1d) == 6
    np.testing.assert_allclose(b2.t_start.values, births_1d.t.values, atol=0.15 * h * h)
    np.testing.assert_allclose(b2.x_start.values, births_1d.x.values, atol=h * (1 + 1e-9))
    # the stress at the end agrees wherever no front is near (rows identical)
    u2 = two.snapshots.u.isel(t=-1).values
    np.testing.assert_array_equal(u2[1], u2[0])
    assert np.median(np.abs(u2[0] - one.snapshots.u.isel(t=-1).values)) < 1e-3


def test_a_checkpoint_continues_bit_for_bit(tmp_path):
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
    shape, h = (40, 32), 0.25
    u0 = 0.6 + 0.35 * fb2d.random_field(shape, h, 2.0, seed=4)
    kw = dict(noise={"law": "power", "rate": 0.01, "exponent": 4.0}, seed=7)
    a = bk.FreeBoundary2D(p, shape, h, u0, **kw)
    a.run(t_end=150.0, snapshots=[50.0, 100.0])
    a.save(tmp_path / "c.npz")
    b = bk.FreeBoundary2D.load(tmp_path / "c.npz")
    ra = a.run(t_end=400.0, snapshots=[300.0])
    rb = b.run(t_end=400.0, snapshots=[300.0])
    assert len(ra.ruptures) > 5 and (ra.ruptures.origin == "nucleation").any()
    assert ra.ruptures.equals(rb.ruptures)
    np.testing.assert_array_equal(ra.snapshots.u.values, rb.snapshots.u.values)
    assert ra.snapshots.t.size == 6  # 0, 50, 100, 150 (end of the first run), 300, 400


def test_random_field_has_the_asked_correlation():
    # white noise filtered by exp(-(k l)^2/4): correlation exp(-r^2/(2 l^2)), 0.607 at r = l
    h, corr = 0.5, 4.0
    f = fb2d.random_field((256, 192), h, corr, seed=1)
    assert f.shape == (192, 256)
    assert abs(f.mean()) < 1e-12 and np.abs(f).max() == pytest.approx(1.0)
    lag = int(corr / h)
    c0 = np.mean(f * f)
    cx = np.mean(f * np.roll(f, lag, axis=1)) / c0
    cy = np.mean(f * np.roll(f, lag, axis=0)) / c0
    assert cx == pytest.approx(np.exp(-0.5), abs=0.08)
    assert cy == pytest.approx(np.exp(-0.5), abs=0.08)
    # a free axis: drawn padded, the same statistics
    g = fb2d.random_field((64, 64), h, corr, seed=1, periodic=False)
    assert g.shape == (64, 64) and np.abs(g).max() == pytest.approx(1.0)


def test_a_threshold_field_scales_the_speed():
    # s uniform 1.25 with u0 = 0.5: the front moves at c(0.5/1.25) = c(0.4)
    p = bk.Params(gamma=0.3, v=0.0, dx=1e-2)
    fb = bk.FreeBoundary2D(
        p, (81, 3), 0.1, 0.5, ("free", "periodic"), threshold=1.25, record_arrivals=True
    )
    fb.trigger(0.0, 0.1, radius=0.0)
    fb.run(max_events=1)
    t = fb.arrival_time(0)
    # one node starts it; past a few h the front is planar along x (3 periodic rows)
    slope = np.polyfit(fb.x[40:], t[1, 40:], 1)[0]
    assert slope == pytest.approx(1.0 / bk.front_speed(0.4), rel=2e-3)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(shape=(2, 5)), "shape"),
        (dict(h=0.0), "h"),
        (dict(u0=1.0), "u0"),
        (dict(boundary="ring"), "boundary"),
        (dict(creep="slow"), "creep"),
        (dict(threshold=0.3), "u0"),
        (dict(threshold=1.2, noise={"law": "constant", "rate": 1.0}, seed=1), "noise"),
        (dict(curvature=-0.1), "curvature"),
        (dict(curvature=(0.1, 0.2, 0.3)), "curvature"),
        (dict(curvature=(0.1, float("nan"))), "curvature"),
        (dict(curvature={"theta": [0.0, 0.5], "D": [0.1, 0.1]}), "curvature.theta"),
        (dict(curvature={"theta": [0.0, 0.3, 0.2, np.pi / 4], "D": [0.1] * 4}), "theta"),
        (dict(curvature={"theta": [0.0, np.pi / 4], "D": [0.1, -1.0]}), "curvature.D"),
        (dict(curvature={"theta": [0.0, np.pi / 4]}), "curvature"),
        (dict(speed_diagonal={"u_plus": [0.5], "c": [0.9]}), "c"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, name):
    args = dict(shape=(8, 8), h=0.5, u0=0.5)
    args.update(kwargs)
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
    with pytest.raises(bk.ParameterError, match=name):
        bk.FreeBoundary2D(p, args.pop("shape"), args.pop("h"), args.pop("u0"), **args)


def test_arrival_times_need_recording():
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
    fb = bk.FreeBoundary2D(p, (8, 8), 0.5, 0.5)
    with pytest.raises(bk.ParameterError, match="record_arrivals"):
        fb.arrival_time(0)


def test_against_the_lattice_the_difference_shrinks_with_dx():
    # one rupture through a smooth field on [0, 8]^2 (docs/free_boundary_2d.md, "Against
    # the lattice"): the spread of lattice - FreeBoundary2D arrival times away from the
    # kick falls with dx, the lattice's planar speed law at dx removes most of it, and its
    # curvature correction more
    import pathlib
    import sys

    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "docs" / "scripts"))
    from free_boundary_2d_lattice import compare

    a, b = compare(0.2), compare(0.1)
    for v in ("plain", "speed"):
        assert b[v]["max_abs_minus_median"] < 0.75 * a[v]["max_abs_minus_median"], v
    for r in (a, b):
        assert r["speed"]["max_abs_minus_median"] < 0.5 * r["plain"]["max_abs_minus_median"]
    assert abs(b["plain"]["mean"]) < 0.02
    # the lattice's curvature correction (curvature=) narrows the spread further, more so
    # at the smaller dx (rms 0.0202 -> 0.0153 at dx = 0.2, 0.0137 -> 0.0065 at 0.1), and
    # with the diagonal law too its largest deviation falls (0.050 -> 0.042, 0.031 -> 0.021)
    rms = "rms_minus_median"
    assert a["speed_curv"][rms] < 0.85 * a["speed"][rms]
    assert b["speed_curv"][rms] < 0.6 * b["speed"][rms]
    for r in (a, b):
        assert r["shape"]["max_abs_minus_median"] < 0.9 * r["speed"]["max_abs_minus_median"]


def _disk_arrivals(h, seed=None, **kw):
    # a rupture from the disk of radius 1 at the centre of [-6, 6]^2, u_+ = 0.6, v = 0:
    # triggered at t = 0, or its nodes seeded at the times seed(r)
    p = bk.Params(gamma=0.3, v=0.0, dx=1e-3)
    n = int(round(12.0 / h)) + 1
    fb = bk.FreeBoundary2D(p, (n, n), h, 0.6, "free", origin=(-6.0, -6.0), record_arrivals=True,
                           **kw)  # fmt: skip
    if seed is None:
        fb.trigger(0.0, 0.0, radius=1.0)
    else:
        xx, yy = np.meshgrid(fb.x, fb.y)
        r = np.hypot(xx, yy).ravel()
        nodes = np.flatnonzero(r <= 1.0)
        fb._engine.trigger(nodes.astype(np.int64), seed(r[nodes]))
    fb.run(max_events=1, progress=False)
    return fb, fb.arrival_time(0)


def test_the_curvature_option_slows_a_circle_by_d_over_r():
    # a circle expanding at dR/dt = c - D/R from R = 1 at T_0 = 1/(c - D) (the seeds
    # inside at T_0 + (r - 1)/(c - D)) arrives at R at T_0 + (R - 1)/c + (D/c^2) ln((c R
    # - D)/(c - D)): along the axes and the diagonals alike (an isotropic D); the
    # correction is 0.107 at R = 5, the error at h = 0.1 below 5 % of it
    h, d, c = 0.1, 0.1, 1.25
    t0 = 1.0 / (c - d)

    def exact(r):
        inner = t0 + (r - 1.0) / (c - d)
        rr = np.maximum(r, 1.0)
        outer = t0 + (r - 1.0) / c + d / c**2 * np.log((c * rr - d) / (c - d))
        return np.where(r <= 1.0, inner, outer)

    fb, t_curv = _disk_arrivals(h, seed=exact, curvature=d)
    _, t_plain = _disk_arrivals(h, seed=exact)
    xx, yy = np.meshgrid(fb.x, fb.y)
    r = np.hypot(xx, yy)
    ring = (r > 1.0) & (r <= 5.0)
    effect = float(exact(5.0) - t0 - 4.0 / c)
    assert effect > 0.1
    err = np.abs(t_curv - exact(r))[ring]
    miss = np.abs(t_plain - exact(r))[ring & (r > 4.9)]
    assert err.max() < 0.05 * effect, err.max()
    assert miss.min() > 0.9 * effect  # without the option: the whole correction
    # D = 0 is the plain engine's front (to rounding)
    _, t0_run = _disk_arrivals(h, seed=exact, curvature=0.0)
    np.testing.assert_allclose(t0_run, t_plain, atol=1e-12, equal_nan=True)
    assert fb.result().meta["curvature"] == "[0.1, 0.1]"


def test_the_diagonal_law_speeds_up_the_diagonals():
    # c_diag = 1.03 c along the diagonals: the front reaches (5/sqrt 2, 5/sqrt 2) 3 % sooner
    # (after the disk) than the plain one, and (5, 0) at the same time
    h = 0.1
    law = lambda u: 1.03 / np.sqrt(1.0 - u * u)  # noqa: E731
    fb, t_diag = _disk_arrivals(h, speed_diagonal=law)
    _, t_plain = _disk_arrivals(h)
    i0, i5 = int(round(6.0 / h)), int(round(11.0 / h))
    assert abs(t_diag[i0, i5] - t_plain[i0, i5]) < 1e-9
    j = i0 + int(round(5.0 / np.sqrt(2.0) / h))
    rd = np.hypot(fb.x[j], fb.y[j])
    gain = (rd - 1.0) / 1.25 * (1.0 - 1.0 / 1.03)
    assert abs((t_plain[j, j] - t_diag[j, j]) / gain - 1.0) < 0.1


def test_the_shape_options_checkpoint_bit_for_bit(tmp_path):
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
    shape, h = (40, 32), 0.25
    u0 = 0.6 + 0.35 * fb2d.random_field(shape, h, 2.0, seed=4)
    kw = dict(curvature=(0.03, 0.05), speed_diagonal=lambda u: 1.01 / np.sqrt(1.0 - u * u))
    a = bk.FreeBoundary2D(p, shape, h, u0, **kw)
    a.run(t_end=150.0)
    a.save(tmp_path / "c.npz")
    b = bk.FreeBoundary2D.load(tmp_path / "c.npz")
    assert b.curvature == [0.03, 0.05]
    ra, rb = a.run(t_end=400.0), b.run(t_end=400.0)
    assert len(ra.ruptures) > 3
    assert ra.ruptures.equals(rb.ruptures)
    plain = bk.FreeBoundary2D(p, shape, h, u0).run(t_end=400.0)
    assert not plain.ruptures.t_end.equals(ra.ruptures.t_end)


@pytest.mark.parametrize("speed", [None, "table"])
def test_a_ridge_through_diagonal_nodes_is_one_rupture(speed):
    # u = 0.9 - a (x - y)^2: a planar problem along the normal (1, -1)/sqrt 2, whose
    # maximum every node of the diagonal reaches together; the 1D engine has one birth
    # per ridge, and so must the plane (the diagonal node is not a trial node of its
    # neighbour's front: each node of the ridge used to be a rupture of its own)
    if speed == "table":
        uu = np.linspace(0.05, 0.9, 18)
        speed = {"u_plus": uu, "c": 0.97 / np.sqrt(1 - uu**2) + 0.03}
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
    n, h = 40, 0.1
    xs = np.arange(n) * h
    xx, yy = np.meshgrid(xs, xs)
    u0 = 0.9 - 0.01 * (xx - yy) ** 2
    r = bk.FreeBoundary2D(p, (n, n), h, u0, "periodic", speed=speed).run(t_end=20.0)
    assert len(r.ruptures) == 1, r.ruptures
    row = r.ruptures.iloc[0]
    assert row.origin == "birth" and row.n_nodes == n * n
    assert row.t_start == pytest.approx(10.0, abs=1e-9)
    # the field stays symmetric about the diagonal: u(x, y) = u(y, x) at the end
    u = r.snapshots.u.isel(t=-1).values
    np.testing.assert_allclose(u, u.T, atol=1e-12)


def test_a_curvature_table_checkpoints_bit_for_bit(tmp_path):
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
    shape, h = (40, 32), 0.25
    u0 = 0.6 + 0.35 * fb2d.random_field(shape, h, 2.0, seed=4)
    table = {"theta": [0.0, 0.32, 0.46, 0.59, np.pi / 4], "D": [0.03, 0.06, 0.07, 0.075, 0.08]}
    a = bk.FreeBoundary2D(p, shape, h, u0, curvature=table)
    a.run(t_end=150.0)
    a.save(tmp_path / "c.npz")
    b = bk.FreeBoundary2D.load(tmp_path / "c.npz")
    assert b.curvature == table
    ra, rb = a.run(t_end=400.0), b.run(t_end=400.0)
    assert len(ra.ruptures) > 3
    assert ra.ruptures.equals(rb.ruptures)
    # the pair of the table's ends is another engine: it refuses the checkpoint, and runs
    # otherwise (the table between the ends matters)
    pair = bk.FreeBoundary2D(p, shape, h, u0, curvature=(0.03, 0.08))
    assert pair._engine.curvature_at(0.46) < a._engine.curvature_at(0.46)
    with pytest.raises(bk.ParameterError, match="checkpoint"):
        pair._engine.restore(a._engine.checkpoint())


@pytest.fixture(scope="module")
def lattice_table():
    # the lattice's D along five directions (u_+ = 0.6, gamma = 0.45, dx = 0.2), and at
    # two more to check the interpolation between them
    table = fb2d.lattice_curvature(0.6, 0.45, 0.2)
    check = {qp: bk.theory.curvature_coefficient(0.6, 0.45, 0.2, direction=qp)
             for qp in [(4, 1), (5, 2)]}  # fmt: skip
    return table, check


def test_the_lattice_curvature_table_interpolates_the_derived_coefficient(lattice_table):
    # the engine's D(theta) through the five directions against the derived D at two
    # directions between them, and against the old interpolation D_axis cos^2(2 theta) +
    # D_diag sin^2(2 theta) of the two ends (6-10 % low near the axis)
    table, check = lattice_table
    np.testing.assert_allclose(table["theta"], np.arctan2([0, 1, 1, 2, 1], [1, 3, 2, 3, 1]))
    p = bk.Params(gamma=0.45, v=0.0, dx=0.2)
    fb = bk.FreeBoundary2D(p, (8, 8), 0.5, 0.5, curvature=table)
    pair = bk.FreeBoundary2D(p, (8, 8), 0.5, 0.5, curvature=(table["D"][0], table["D"][-1]))
    for theta, d in zip(table["theta"], table["D"], strict=True):
        assert fb._engine.curvature_at(theta) == pytest.approx(d, rel=1e-12)
        # symmetric directions: -theta, pi/2 - theta
        assert fb._engine.curvature_at(np.pi / 2 - theta) == pytest.approx(d, rel=1e-12)
    errors = {}
    for (q, pp), d in check.items():
        theta = np.arctan2(pp, q)
        errors[(q, pp)] = (fb._engine.curvature_at(theta) / d - 1,
                           pair._engine.curvature_at(theta) / d - 1)  # fmt: skip
    print(errors)
    for table_err, pair_err in errors.values():
        assert abs(table_err) < 0.02
        assert abs(table_err) < 0.3 * abs(pair_err)
