"""Per-block media of the plane: correlated disorder fields (bk.disorder.smooth_field,
docs/lattice.md) with the correlation function they promise; per-block thresholds, masses
and loader springs against the chain they reduce to; noise per block."""

import math

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import config


def test_in_one_dimension_it_is_the_chain_configs_generator_bit_for_bit():
    # x with span/(n - 1) = h exactly: the config's spacing is the same number
    for n, h, corr, per in ((65, 0.25, 1.3, False), (64, 0.5, 2.0, True)):
        x = np.arange(n) * h
        ref = config._smooth_random(x, corr, np.random.default_rng(7), per)
        new = bk.disorder.smooth_field((n,), h, corr, periodic=per, seed=7)
        assert np.array_equal(ref, new)


def _correlation(fields: np.ndarray, lag: tuple[int, int]) -> float:
    """<f(r) f(r + lag)> / <f^2> over periodic fields, each normalised by its own
    variance (their scales differ: each is scaled to a largest |value| of 1)."""
    f = fields - fields.mean(axis=(1, 2), keepdims=True)
    g = np.roll(f, shift=(-lag[0], -lag[1]), axis=(1, 2))
    return float(np.mean((f * g).mean(axis=(1, 2)) / (f * f).mean(axis=(1, 2))))


@pytest.mark.parametrize("dy, dx", [(0.1, 0.1), (0.15, 0.1)])
def test_a_plane_field_has_the_gaussian_correlation_in_x_y_and_diagonal(dy, dx):
    # periodic fields of 96 x 96 blocks, correlation length 0.4 (4 blocks along x): the
    # measured correlation at lags along x, y and the diagonal against
    # exp(-s^2 / (2 corr^2)), s the lag in the plane; 40 fields, the statistical error
    # about 0.005 (measured within 0.006; the wrong law exp(-s^2 / corr^2) is off by
    # 0.2 at s = corr)
    corr = 0.4
    fields = np.stack(
        [
            bk.disorder.smooth_field((96, 96), (dy, dx), corr, periodic=True, seed=s)
            for s in range(40)
        ]
    )
    assert fields.shape == (40, 96, 96)
    assert np.allclose(np.abs(fields).max(axis=(1, 2)), 1.0)
    assert np.allclose(fields.mean(axis=(1, 2)), 0.0, atol=1e-12)
    for lag in [(0, 2), (0, 4), (0, 6), (2, 0), (3, 0), (5, 0), (2, 2), (3, 3)]:
        s2 = (lag[0] * dy) ** 2 + (lag[1] * dx) ** 2
        want = np.exp(-s2 / (2 * corr**2))
        assert _correlation(fields, lag) == pytest.approx(want, abs=0.02), lag


def test_a_lattice_takes_a_field_as_its_thresholds_and_bad_input_is_named():
    th = 1.0 + 0.1 * bk.disorder.smooth_field((12, 16), (0.15, 0.1), 0.3, seed=2)
    la = bk.Lattice((16, 12), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.6, dy=0.15, threshold=th)
    assert np.array_equal(la._engine.thresholds().reshape(12, 16), th)
    with pytest.raises(bk.ParameterError, match="correlation"):
        bk.disorder.smooth_field((8, 8), 0.1, 0.0)
    with pytest.raises(bk.ParameterError, match="spacing"):
        bk.disorder.smooth_field((8, 8), (0.1, 0.1, 0.1), 1.0)
    with pytest.raises(bk.ParameterError, match="shape"):
        bk.disorder.smooth_field((8, 0), 0.1, 1.0)
    # not periodic: a different field from the periodic one, no wrap-around
    a = bk.disorder.smooth_field((32, 32), 0.1, 0.5, seed=1)
    b = bk.disorder.smooth_field((32, 32), 0.1, 0.5, periodic=True, seed=1)
    assert not np.allclose(a, b)


@pytest.mark.parametrize("axis", ["x", "y"])
def test_per_block_thresholds_masses_and_loaders_varying_along_one_axis_are_the_chains(axis):
    """A lattice periodic across, whose stress, thresholds, masses and loader springs vary
    along one axis only, kicked on a whole line across, is the chain along that axis (the
    Laplacian across vanishes identically): u, u_t and every slip equal the chain's with
    the same per-block arrays to round-off (measured 2e-16), at dx along x and at dy along
    y. A lattice that read its (ny, nx) arrays transposed, or dropped a property, would
    not. (Loaded at v > 0 they are the same bits too, through hundreds of events:
    tests/test_lattice_ties.py; docs/lattice.md, "Ties".)"""
    n, other, dx, dy, step = 24, 3, 0.25, 0.3, 0.05
    k = np.arange(n)
    u0 = 0.55 + 0.2 * np.sin(0.7 * k)
    props = {
        "threshold": 1.0 + 0.15 * np.cos(1.3 * k),
        "mass": 1.0 + 0.5 * np.sin(0.4 * k) ** 2,
        "loader": 0.7 + 0.6 * (k % 5) / 4,
    }
    if axis == "x":
        shape, boundary, h, chain_step = (n, other), ("free", "periodic"), dx, step
        grid = lambda a: np.tile(a, (other, 1))  # noqa: E731 - (ny, nx): rows alike
        kicked = [(5, j) for j in range(other)]
    else:
        # the chain at dy, stepped with the lattice's time step (step is a fraction of
        # min(dx, dy) = dx)
        shape, boundary, h, chain_step = (other, n), ("periodic", "free"), dy, step * dx / dy
        grid = lambda a: np.tile(a[:, None], (1, other))  # noqa: E731 - columns alike
        kicked = [(i, 5) for i in range(other)]
    p = bk.Params(gamma=0.45, v=0.0, dx=dx)
    la = bk.Lattice(
        shape,
        p,
        u0=grid(u0),
        dy=dy,
        boundary=boundary,
        events="global",
        **{name: grid(a) for name, a in props.items()},
    )
    for b in kicked:
        la.kick(b, -2.0)
    rl = la.run(t_end=20.0, progress=False)
    ch = bk.Chain(n, bk.Params(gamma=0.45, v=0.0, dx=h), "free", u0=u0, step=chain_step, **props)
    rc = ch.kick(5, -2.0).run(t_end=20.0, progress=False)
    assert len(rc.slips) >= n and rc.slips["block"].nunique() >= n // 2
    lines = (rl.u, rl.u_t) if axis == "x" else (rl.u.T, rl.u_t.T)
    for line, speed in zip(*lines, strict=True):
        np.testing.assert_allclose(line, rc.u, rtol=0, atol=1e-12)
        np.testing.assert_allclose(speed, rc.u_t, rtol=0, atol=1e-12)
    # every slip of the chain, once on each line across (same block, start and slip)
    s = rl.slips
    along, across = (s["i"], s["j"]) if axis == "x" else (s["j"], s["i"])
    assert len(s) == other * len(rc.slips)
    for line in range(other):
        mine = s[across == line]
        np.testing.assert_array_equal(along[mine.index].to_numpy(), rc.slips["block"].to_numpy())
        np.testing.assert_allclose(mine["t_start"], rc.slips["t_start"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(mine["slip"], rc.slips["slip"], rtol=0, atol=1e-12)


def test_noise_on_the_lattice_follows_each_blocks_own_threshold():
    """Spontaneous slips of stuck blocks (the chain's noise source, per block): on a
    loaded free lattice at uniform u (phi = u0 + v t everywhere) with thresholds theta
    (ny, nx), the exponential law's rate at block k is rate exp(-(theta_k - phi)/phi0),
    so the first slip's block is k with probability exp(-theta_k/phi0)/sum (at any
    time), and its time has the survival exp(-sum_k int rate ...). Over 300 seeds both
    hold (chi-square, KS); the same counts against the thresholds read transposed, or
    the time against the thresholds ignored, are refused."""
    from scipy import stats

    nx, ny, v, u0, rate, phi0 = 4, 3, 0.01, 0.3, 2.0, 0.1
    theta = 0.8 + 0.2 * np.arange(nx * ny).reshape(ny, nx) / (nx * ny - 1)
    p = bk.Params(gamma=0.3, v=v, dx=0.5)
    noise = {"law": "exponential", "rate": rate, "phi0": phi0}

    def mass(t, th):
        x0 = u0 + 1.0 - th
        return np.sum(rate * phi0 / v * np.exp(-(1 - x0) / phi0) * (math.exp(v * t / phi0) - 1))

    first = np.zeros(nx * ny)
    right, wrong = [], []
    for seed in range(300):
        la = bk.Lattice((nx, ny), p, u0=u0, threshold=theta, noise=noise, seed=seed)
        r = la.run(t_end=1e4, max_events=1, progress=False)
        row = r.catalog.iloc[0]
        assert row["kind"] == "noise"
        first[int(row["hypocentre_i"]) + nx * int(row["hypocentre_j"])] += 1
        right.append(1 - math.exp(-mass(row["t_start"], theta)))
        wrong.append(1 - math.exp(-mass(row["t_start"], np.ones_like(theta))))
    assert stats.kstest(right, "uniform").pvalue > 0.01
    assert stats.kstest(wrong, "uniform").pvalue < 1e-3

    def chi2(th):
        w = np.exp(-th.ravel() / phi0)
        return stats.chisquare(first, 300 * w / w.sum()).pvalue

    assert chi2(theta) > 0.01
    assert chi2(theta.T.reshape(ny, nx)) < 1e-3


def test_energy_books_close_with_every_per_block_and_per_bond_property():
    """The books with per-block thresholds, masses and loader springs and per-bond springs
    along both axes (free x fixed, loaded, 13 events to t = 60): the residual over the
    viscous work falls with the step at the integrator's order (measured 3.2e-8, 4.2e-9,
    3.3e-10 at steps 0.05, 0.025, 0.0125): a kinetic energy without the masses, or a
    coupling energy without the bonds, would leave an O(1) residual."""
    nx, ny = 20, 16
    rng = np.random.default_rng(1)
    u0 = 0.6 + 0.15 * bk.disorder.smooth_field((ny, nx), (0.3, 0.25), 1.0, seed=2)
    props = {
        "threshold": 1 + 0.1 * rng.random((ny, nx)),
        "mass": 1 + 0.5 * rng.random((ny, nx)),
        "loader": 0.8 + 0.4 * rng.random((ny, nx)),
        "coupling": (0.5 + rng.random((ny, nx - 1)), 0.5 + rng.random((ny + 1, nx))),
    }
    p = bk.Params(gamma=0.45, v=0.01, dx=0.25)
    res = []
    for step in (0.05, 0.025, 0.0125):
        la = bk.Lattice((nx, ny), p, u0=u0, dy=0.3, boundary=("free", "fixed"), step=step, **props)
        r = la.run(t_end=60.0, progress=False)
        assert len(r.catalog) >= 5
        res.append(abs(r.energy["residual"]) / r.energy["viscous_work"])
    assert res[0] / res[1] > 5 and res[1] / res[2] > 5 and res[2] < 1e-9, res
