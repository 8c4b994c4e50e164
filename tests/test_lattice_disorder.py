"""Correlated disorder fields in the plane (bk.disorder.smooth_field, docs/lattice.md):
the chain's generator, in two dimensions, with the correlation function it promises."""

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
