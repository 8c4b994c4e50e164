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


# --- the one estimator: gutenberg_richter -------------------------------------------------


def incomplete_gr(b, n, rng, m_complete=1.0):
    """A Gutenberg-Richter catalog from M = 0 whose events below m_complete are detected
    with probability (M / m_complete)^4 (an incomplete catalog, as observed ones are)."""
    out = []
    while sum(len(o) for o in out) < n:
        m = rng.exponential(1.0 / (b * np.log(10)), 4 * n)
        keep = rng.random(m.size) < np.minimum(m / m_complete, 1.0) ** 4
        out.append(m[keep])
    return np.concatenate(out)[:n]


@pytest.mark.parametrize("b", [0.8, 1.0, 1.5])
def test_gutenberg_richter_recovers_b_within_its_interval(b):
    rng = np.random.default_rng(11)
    m = incomplete_gr(b, 3000, rng)
    # through moments, as every route gives them: M = (2/3) log10(moment)
    est = stats.gutenberg_richter(10 ** (1.5 * m))
    assert est.ok, est.reason
    assert est.lo < b < est.hi
    assert est.lo < est.b < est.hi
    # the interval's half-width is near Shi-Bolt's 1.96 sigma and Aki's b/sqrt(n)
    assert (est.hi - est.lo) / 2 == pytest.approx(1.96 * b / np.sqrt(est.n), rel=0.3)
    # Mc: maximum curvature of the incomplete catalog (mode in [0.9, 1.0)) + 0.2, where
    # the catalog is complete; below it the estimate would be biased
    assert 1.0 <= est.m_c <= 1.3
    assert stats.gutenberg_richter(magnitudes=m).b == pytest.approx(est.b, rel=1e-9)
    # the naive estimate over all events (Mc = the smallest) is far off: Mc matters
    naive = stats.b_value(m, m_c=float(m.min())).b
    assert abs(naive - b) > 3 * (est.hi - est.lo)


@pytest.mark.parametrize("b", [0.8, 1.0, 1.5])
def test_gutenberg_richter_interval_covers_b_at_its_confidence(b):
    # over independent catalogs the 95 % interval holds the true b in about 95 % of them
    rng = np.random.default_rng(5)
    hits = []
    for _ in range(160):
        est = stats.gutenberg_richter(magnitudes=incomplete_gr(b, 400, rng), n_boot=300)
        hits.append(est.lo <= b <= est.hi)
    # binomial sd at p = 0.95, 160 catalogs: 0.017
    assert 0.89 <= np.mean(hits) <= 0.995


def test_gutenberg_richter_binned_magnitudes_use_utsu_correction():
    rng = np.random.default_rng(2)
    binned = np.round(incomplete_gr(1.0, 20000, rng), 1)
    est = stats.gutenberg_richter(magnitudes=binned, dm=0.1)
    assert est.lo < 1.0 < est.hi and est.m_c == pytest.approx(1.2, abs=0.11)
    # without the correction (dm = 0) the binned catalog's b is biased beyond the interval
    assert not est.lo < stats.gutenberg_richter(magnitudes=binned).b < est.hi


def test_gutenberg_richter_refuses_degenerate_and_small_catalogs():
    rng = np.random.default_rng(0)
    # a noiseless ring: every rupture is ring-wide, moments equal to a CV of 1e-5
    ring = 548.9 * (1 + 1e-5 * rng.standard_normal(400))
    est = stats.gutenberg_richter(ring)
    assert not est.ok and np.isnan(est.b) and np.isnan(est.lo)
    assert "degenerate" in est.reason and "CV of moments 1.0e-05" in est.reason
    assert est.text().startswith("no b-value: degenerate")
    small = stats.gutenberg_richter(magnitudes=incomplete_gr(1.0, 40, rng))
    assert not small.ok and "too few" in small.reason
    # many small events below Mc and, above it, only identical ring-wide ones
    mixed = np.concatenate([rng.uniform(0.0, 0.1, 1000), np.full(60, 2.0)])
    assert "degenerate" in stats.gutenberg_richter(magnitudes=mixed).reason
    assert stats.gutenberg_richter([]).reason == "no event with a positive moment"
    with pytest.raises(bk.ParameterError, match="moment"):
        stats.gutenberg_richter()
    with pytest.raises(bk.ParameterError, match="confidence"):
        stats.gutenberg_richter([1.0], confidence=1.0)


def test_moment_magnitude():
    np.testing.assert_allclose(stats.moment_magnitude([1e3, 1.0]), [2.0, 0.0])
    assert np.isnan(stats.moment_magnitude([0.0, -1.0])).all()


def test_gutenberg_richter_tests_the_law_itself():
    """The Kolmogorov-Smirnov p-value of M - Mc against the fitted exponential: uniform on
    (0, 1) for Gutenberg-Richter catalogs (rejected at 5 % about 5 % of the time), tiny for
    a catalog of one-block slips and system-size events, whose b only summarises it."""
    rng = np.random.default_rng(8)
    p = [
        stats.gutenberg_richter(magnitudes=incomplete_gr(1.0, 400, rng), n_boot=0).fit_p
        for _ in range(120)
    ]
    assert 0.0 <= np.mean(np.array(p) < 0.05) <= 0.12  # binomial sd 0.02 at 0.05
    assert 0.35 < np.mean(p) < 0.65
    est = stats.gutenberg_richter(magnitudes=incomplete_gr(1.0, 400, rng))
    assert est.fits and "not a Gutenberg-Richter" not in est.text()
    # two populations: many small slips, and big events of a narrow spread
    two = np.concatenate([rng.uniform(0.0, 0.1, 300), 2.0 + 0.1 * rng.random(200)])
    two = np.concatenate([two, 0.2 + rng.exponential(0.1, 100)])
    est = stats.gutenberg_richter(magnitudes=two)
    assert est.ok and not est.fits and est.fit_p < 0.01  # (1/401: none of 400 simulations)
    assert "not a Gutenberg-Richter law above Mc" in est.text()
    # binned magnitudes are not tested (the KS law is for continuous ones)
    binned = stats.gutenberg_richter(magnitudes=np.round(incomplete_gr(1.0, 2000, rng), 1), dm=0.1)
    assert np.isnan(binned.fit_p) and binned.fits
