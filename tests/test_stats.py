"""Event statistics against synthetic catalogs with known laws."""

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import stats


def gr_magnitudes(b, n, m_c, rng):
    # Gutenberg-Richter: P(M >= m) = 10^(-b (m - m_c))  <=> exponential with rate b ln 10
    return m_c + rng.exponential(1.0 / (b * np.log(10)), n)


@pytest.mark.parametrize("b", [0.8, 1.0, 1.2])
def test_b_value_recovers_the_law_within_its_uncertainty(b):
    rng = np.random.default_rng(7)
    est = stats.b_value(gr_magnitudes(b, 20000, 2.0, rng), m_c=2.0)
    assert abs(est.b - b) < 3 * est.sigma_aki
    assert est.sigma_aki == pytest.approx(b / np.sqrt(20000), rel=0.05)
    # the quoted uncertainty matches the scatter over independent catalogs
    reps = [stats.b_value(gr_magnitudes(b, 2000, 0.0, rng), m_c=0.0).b for _ in range(200)]
    assert np.std(reps) == pytest.approx(b / np.sqrt(2000), rel=0.2)


def test_binning_correction():
    rng = np.random.default_rng(1)
    m = gr_magnitudes(1.0, 50000, 0.95, rng)
    binned = np.round(m, 1)  # catalog magnitudes in bins 1.0, 1.1, ... (edges 0.95, 1.05, ...)
    naive = stats.b_value(binned, m_c=1.0).b
    corrected = stats.b_value(binned, m_c=1.0, dm=0.1).b
    assert abs(corrected - 1.0) < 0.03 < abs(naive - 1.0)


def test_power_law_and_magnitude_kinds():
    rng = np.random.default_rng(3)
    s = (1 - rng.random(30000)) ** (-1 / 1.5)  # Pareto, beta = 1.5, s >= 1
    beta, se = stats.power_law_exponent(s, 1.0)
    assert abs(beta - 1.5) < 3 * se
    # amplitude magnitudes of a beta power law give b = beta; moment magnitudes b = 1.5 beta
    assert stats.b_value(stats.magnitudes(s), m_c=0.0).b == pytest.approx(1.5, rel=0.03)
    assert stats.b_value(stats.magnitudes(s, "moment"), m_c=0.0).b == pytest.approx(2.25, rel=0.03)
    x, ccdf = stats.size_frequency(s)
    assert ccdf[-1] == 1.0 and np.all(np.diff(x) <= 0)


def test_recurrence_times():
    t = np.array([0.0, 1.0, 2.5, 4.0])
    np.testing.assert_allclose(stats.recurrence_times(t), [1.0, 1.5, 1.5])
    x = np.array([0.0, 10.0, 0.2, 10.1])
    np.testing.assert_allclose(stats.recurrence_times(t, x, window=0.5), [2.5, 3.0])


def test_bad_input():
    with pytest.raises(bk.ParameterError, match="mags"):
        stats.b_value([1.0])
    with pytest.raises(bk.ParameterError, match="sizes"):
        stats.magnitudes([1.0, -2.0])
    with pytest.raises(bk.ParameterError, match="kind"):
        stats.magnitudes([1.0], "energy")
