"""Event statistics: size-frequency, Gutenberg-Richter b-value, recurrence times.

The paper (Sec. V) argues that a medium dominated by periodic wave trains shows shocks of
amplitude A at a point with frequency omega ~ 1/A: a Gutenberg-Richter law with b = 1 for
the amplitude magnitude M = log10(A). These functions estimate such laws from a catalog.

Every b that bkwaves prints (``bkwaves stats``, ``bkwaves plot``, the run summary's
``b_value``, the paper's figures) comes from one estimator, :func:`gutenberg_richter`:
moment magnitudes M = (2/3) log10(moment) (:func:`moment_magnitude`, the ``moment``
column of every catalog, docs/usage.md "Event statistics"), a magnitude of completeness
by maximum curvature plus 0.2, Aki-Utsu maximum likelihood above it, and a bootstrap
confidence interval; a catalog too small or of events all of one size gets no b, with
the reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _validate as V

__all__ = [
    "MAGNITUDE_DEFINITION",
    "MC_BIN",
    "MC_CORRECTION",
    "MIN_EVENTS",
    "MIN_SPREAD",
    "FIT_P_MIN",
    "BValue",
    "GutenbergRichter",
    "gutenberg_richter",
    "moment_magnitude",
    "completeness_magnitude",
    "b_value",
    "magnitudes",
    "size_frequency",
    "power_law_exponent",
    "recurrence_times",
]

LOG10_E = np.log10(np.e)


@dataclass(frozen=True)
class BValue:
    """Maximum-likelihood b-value (Aki 1965) above the completeness magnitude m_c.

    What :func:`b_value` returns; every field is dimensionless (magnitudes and b).

    Parameters
    ----------
    b : float
        The b-value.
    sigma_aki : float
        Aki's standard error b / sqrt(n).
    sigma_shi_bolt : float
        Shi & Bolt's (1982) standard error.
    n : int
        Events with M >= m_c.
    m_c : float
        The magnitude of completeness used.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> rng = np.random.default_rng(0)
    >>> mags = rng.exponential(math.log10(math.e), 2000)   # a Gutenberg-Richter law, b = 1
    >>> bv = bk.stats.b_value(mags, 0.0)
    >>> abs(bv.b - 1) < 3 * bv.sigma_aki, bv.n
    (True, 2000)
    """

    b: float
    sigma_aki: float  # b / sqrt(n)
    sigma_shi_bolt: float  # Shi & Bolt (1982)
    n: int
    m_c: float


def magnitudes(sizes, kind: str = "amplitude"):
    """Magnitudes of event sizes: ``"amplitude"`` M = log10(size) (the paper's b = 1 argument
    uses the slip amplitude A); ``"moment"`` M = (2/3) log10(size) for seismic moments.

    Parameters
    ----------
    sizes : array_like
        Event sizes, > 0 (slip amplitudes or moments, in the paper's dimensionless units;
        a change of unit shifts every M by one constant, which leaves b unchanged).
    kind : {"amplitude", "moment"}, default "amplitude"
        Which magnitude.

    Returns
    -------
    numpy.ndarray
        The magnitudes (dimensionless).

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.stats.magnitudes([10.0, 100.0]), bk.stats.magnitudes([1e3], "moment")
    (array([1., 2.]), array([2.]))
    """
    s = V.array("sizes", sizes, lo=0.0, lo_open=True)
    if kind == "amplitude":
        return np.log10(s)
    if kind == "moment":
        return (2.0 / 3.0) * np.log10(s)
    V._fail("kind", kind, "'amplitude' or 'moment'")


def b_value(mags, m_c: float | None = None, dm: float = 0.0) -> BValue:
    """Aki's maximum-likelihood b = log10(e) / (mean(M) - (m_c - dm/2)) for M >= m_c.

    ``dm`` is the binning width of catalog magnitudes (0 for continuous values, as from a
    simulation). The uncertainty is given both as Aki's b/sqrt(n) and Shi & Bolt's
    2.3 b^2 sqrt(sum (M - mean)^2 / (n (n - 1))). :func:`gutenberg_richter` is the
    estimator bkwaves reports (with Mc chosen and a bootstrap interval).

    Parameters
    ----------
    mags : array_like
        Magnitudes (dimensionless).
    m_c : float, optional
        Magnitude of completeness; default the smallest magnitude.
    dm : float, default 0
        Binning width of the magnitudes, >= 0 (0: continuous).

    Returns
    -------
    BValue
        b with its two standard errors, n and m_c.

    Raises
    ------
    bkwaves.ParameterError
        Fewer than 2 events above m_c, or a mean not above m_c - dm/2.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> rng = np.random.default_rng(0)
    >>> mags = rng.exponential(math.log10(math.e), 2000)   # a Gutenberg-Richter law, b = 1
    >>> bv = bk.stats.b_value(mags, 0.0)
    >>> round(bv.b, 3), round(bv.sigma_aki, 3), bv.n
    (0.988, 0.022, 2000)
    """
    m = V.array("mags", mags)
    if m_c is None:
        m_c = float(m.min()) if m.size else 0.0
    m_c = V.number("m_c", m_c)
    dm = V.number("dm", dm, lo=0.0)
    sel = m[m >= m_c]
    n = sel.size
    if n < 2:
        V._fail("mags", n, "at least 2 events with M >= m_c")
    mean = sel.mean()
    denom = mean - (m_c - dm / 2.0)
    if denom <= 0:
        V._fail("mags", float(mean), "a mean magnitude above m_c - dm/2")
    b = LOG10_E / denom
    sb = 2.3 * b * b * np.sqrt(np.sum((sel - mean) ** 2) / (n * (n - 1)))
    return BValue(
        b=float(b),
        sigma_aki=float(b / np.sqrt(n)),
        sigma_shi_bolt=float(sb),
        n=int(n),
        m_c=float(m_c),
    )


#: What a magnitude is, wherever bkwaves computes one (catalog attributes, summaries).
MAGNITUDE_DEFINITION = (
    "M = (2/3) log10(moment), the moment in the catalog's units (a moment magnitude up to "
    "a constant shift, which leaves b unchanged)"
)
#: Bin width of the magnitude histogram whose mode is the maximum curvature.
MC_BIN = 0.1
#: Added to the maximum-curvature magnitude (Woessner & Wiemer 2005: MAXC underestimates
#: the completeness magnitude of gradually curved distributions by about 0.2).
MC_CORRECTION = 0.2
#: Fewest events above Mc for a b: Aki's relative error 1/sqrt(n) is 14 % at n = 50.
MIN_EVENTS = 50
#: Below this Kolmogorov-Smirnov p-value the magnitudes above Mc are reported as not
#: following a Gutenberg-Richter law (b is still given: it then summarises the catalog).
FIT_P_MIN = 0.05
#: Smallest standard deviation of the magnitudes above Mc for a b: a Gutenberg-Richter law
#: spreads them by sd = log10(e)/b, 0.01 only at b = 43; less is a catalog of one size.
MIN_SPREAD = 0.01


def moment_magnitude(moment):
    """M = (2/3) log10(moment): the magnitude of every bkwaves statistic.

    :data:`MAGNITUDE_DEFINITION` says the same in words for the outputs' attributes.

    Parameters
    ----------
    moment : float or array_like
        Moments int slip dx (dimensionless, the catalogs' ``moment``).

    Returns
    -------
    numpy.ndarray
        M (dimensionless), NaN where the moment is <= 0 or not finite.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.stats.moment_magnitude([1e3, 0.0, -1.0])
    array([ 2., nan, nan])
    """
    m = np.asarray(moment, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.isfinite(m) & (m > 0), (2.0 / 3.0) * np.log10(np.abs(m)), np.nan)


def _mode_bins(mags, dm: float):
    """Histogram of magnitudes: (integer bin of each magnitude, magnitude of bin 0's
    lower edge..., width). Continuous magnitudes (dm = 0) fall into bins [k w, (k+1) w)
    of w = MC_BIN; magnitudes binned at dm are their own bins (centred on the values)."""
    if dm > 0:
        return np.rint(mags / dm).astype(np.int64), dm, 0.0
    return np.floor(mags / MC_BIN).astype(np.int64), MC_BIN, 0.0


def completeness_magnitude(mags, dm: float = 0.0) -> float:
    """Magnitude of completeness by maximum curvature plus :data:`MC_CORRECTION`: the
    magnitude of the fullest bin of the non-cumulative histogram (bins of ``dm``, or of
    :data:`MC_BIN` = 0.1 for continuous magnitudes: its lower edge), plus 0.2 (Wiemer &
    Wyss 2000, Woessner & Wiemer 2005). The events with M >= Mc enter the b-value.

    Parameters
    ----------
    mags : array_like
        Magnitudes (dimensionless); non-finite ones are ignored.
    dm : float, default 0
        Binning width of the magnitudes, >= 0 (0: continuous).

    Returns
    -------
    float
        Mc (dimensionless).

    Examples
    --------
    An exponential law is fullest in its first bin, [0, 0.1): Mc = 0 + 0.2.

    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> rng = np.random.default_rng(0)
    >>> mags = rng.exponential(math.log10(math.e), 2000)   # a Gutenberg-Richter law, b = 1
    >>> bk.stats.completeness_magnitude(mags)
    0.2
    """
    m = V.array("mags", mags)
    m = m[np.isfinite(m)]
    if not m.size:
        V._fail("mags", "no finite magnitude", "at least one magnitude")
    dm = V.number("dm", dm, lo=0.0)
    k, w, _ = _mode_bins(m, dm)
    counts = np.bincount(k - k.min())
    return float((k.min() + int(np.argmax(counts))) * w + MC_CORRECTION)


@dataclass(frozen=True)
class GutenbergRichter:
    """The b-value of a catalog (:func:`gutenberg_richter`). ``b`` is NaN when the
    catalog has none, and ``reason`` says why (too few events, events of one size).

    Every number is dimensionless (magnitudes, b and its interval).

    Parameters
    ----------
    b : float
        The b-value (NaN: none).
    lo, hi : float
        Its confidence interval (bootstrap percentiles).
    confidence : float
        The interval's confidence level.
    sigma_shi_bolt : float
        Shi & Bolt's (1982) standard error, for comparison.
    m_c : float
        The magnitude of completeness.
    n : int
        Events with M >= m_c.
    n_total : int
        Events with a finite magnitude (moment > 0).
    m_min, m_max : float
        The range of the magnitudes.
    dm : float, default 0
        Their binning width.
    reason : str or None, default None
        Why there is no b.
    fit_p : float, default nan
        Kolmogorov-Smirnov p-value of the Gutenberg-Richter law above m_c.
    magnitude : str
        What a magnitude is (:data:`MAGNITUDE_DEFINITION`).
    method : str
        The estimator, in words.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> rng = np.random.default_rng(0)
    >>> mags = rng.exponential(math.log10(math.e), 2000)   # a Gutenberg-Richter law, b = 1
    >>> gr = bk.stats.gutenberg_richter(magnitudes=mags, n_boot=200)
    >>> gr.ok, gr.fits, bool(gr.lo < 1 < gr.hi)
    (True, True, True)
    """

    b: float
    lo: float  # the confidence interval (bootstrap percentiles)
    hi: float
    confidence: float
    sigma_shi_bolt: float  # Shi & Bolt (1982), for comparison
    m_c: float  # magnitude of completeness
    n: int  # events with M >= m_c
    n_total: int  # events with a finite magnitude (moment > 0)
    m_min: float
    m_max: float
    dm: float = 0.0
    reason: str | None = None
    fit_p: float = math.nan  # KS p-value of the Gutenberg-Richter law above Mc
    magnitude: str = MAGNITUDE_DEFINITION
    method: str = (
        "Aki-Utsu maximum likelihood b = log10(e)/(mean(M) - (Mc - dm/2)) over M >= Mc; "
        "Mc by maximum curvature (bins of 0.1) + 0.2; interval: bootstrap percentiles "
        "(Mc and b recomputed on each resample); fit: Kolmogorov-Smirnov p-value of the "
        "exponential law of M - Mc with the fitted b (Lilliefors, by simulation)"
    )

    @property
    def ok(self) -> bool:
        """Whether there is a b (no ``reason``)."""
        return self.reason is None

    @property
    def fits(self) -> bool:
        """Whether the magnitudes above Mc are consistent with a Gutenberg-Richter law
        (KS p >= :data:`FIT_P_MIN`; True when untested: binned magnitudes)."""
        return not self.fit_p < FIT_P_MIN

    def text(self) -> str:
        """One line: the b with its interval and Mc, or why there is none.

        Returns
        -------
        str
            The line ``bkwaves stats`` prints.

        Examples
        --------
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> bk.stats.gutenberg_richter(np.full(100, 2.0)).text()[:38]
        'no b-value: degenerate catalog: all 10'
        """
        if not self.ok:
            return f"no b-value: {self.reason}"
        pct = round(100 * self.confidence)
        out = (
            f"b = {self.b:.3g} [{self.lo:.3g}, {self.hi:.3g}] ({pct} %), Mc = {self.m_c:.3g}, "
            f"n = {self.n} of {self.n_total}"
        )
        if not self.fits:
            out += f"; not a Gutenberg-Richter law above Mc (KS p = {self.fit_p:.2g})"
        return out

    def to_dict(self) -> dict:
        """The fields as a dict for JSON (NaN and inf as None).

        Returns
        -------
        dict
            Field name -> value.

        Examples
        --------
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> d = bk.stats.gutenberg_richter(np.full(100, 2.0)).to_dict()
        >>> d["b"], d["n_total"]
        (None, 100)
        """
        from dataclasses import asdict

        return {k: (None if isinstance(v, float) and not np.isfinite(v) else v)
                for k, v in asdict(self).items()}  # fmt: skip


def _b_rows(mags, dm: float, k0: int, w: float):
    """Vectorised Mc (maximum curvature + correction) and b of each row of ``mags``."""
    k, _, _ = _mode_bins(mags, dm)
    off = k - k0
    nb = int(off.max()) + 1
    rows = mags.shape[0]
    counts = np.bincount((np.arange(rows)[:, None] * nb + off).ravel(), minlength=rows * nb)
    mc = (k0 + np.argmax(counts.reshape(rows, nb), axis=1)) * w + MC_CORRECTION
    lo = mc - dm / 2.0
    above = mags >= lo[:, None] - (1e-9 * dm)
    n = above.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(above, mags, 0.0).sum(axis=1) / n
        b = LOG10_E / (mean - lo)
    return np.where(n >= 2, b, np.nan)


def _ks_exponential(x):
    """Kolmogorov-Smirnov distance of each row of ``x`` (>= 0) from the exponential law of
    its own mean."""
    x = np.sort(x, axis=-1)
    n = x.shape[-1]
    f = -np.expm1(-x / x.mean(axis=-1, keepdims=True))
    i = np.arange(1, n + 1)
    return np.maximum((i / n - f).max(axis=-1), (f - (i - 1) / n).max(axis=-1))


def _fit_p(excess, rng, sims: int = 400) -> float:
    """p-value of the exponential law for ``excess`` = M - Mc, its rate fitted: the share
    of ``sims`` simulated exponential samples of the same size (rate refitted on each:
    Lilliefors' test; the law of D does not depend on the rate) at least as far from
    their fitted law."""
    d = float(_ks_exponential(excess[None, :])[0])
    n = excess.size
    per = max(1, 4_000_000 // n)
    ds = []
    for start in range(0, sims, per):
        ds.append(_ks_exponential(rng.exponential(1.0, (min(per, sims - start), n))))
    return float((np.sum(np.concatenate(ds) >= d) + 1) / (sims + 1))


def gutenberg_richter(
    moment=None,
    *,
    magnitudes=None,
    dm: float = 0.0,
    confidence: float = 0.95,
    n_boot: int = 1000,
    seed: int = 0,
) -> GutenbergRichter:
    """The b-value of a catalog: the one estimator behind every b bkwaves prints.

    Magnitudes M = (2/3) log10(moment) of the events with a positive moment (or
    ``magnitudes`` given directly, e.g. binned at ``dm``); the magnitude of completeness
    Mc by maximum curvature + 0.2 (:func:`completeness_magnitude`); Aki-Utsu maximum
    likelihood b = log10(e) / (mean(M) - (Mc - dm/2)) over M >= Mc (``dm``: the binning
    width; 0 for continuous magnitudes, as a simulation's); the ``confidence`` interval
    from ``n_boot`` bootstrap resamples of the whole catalog, Mc chosen anew on each (a
    fixed ``seed``: the same catalog always gets the same interval). Shi & Bolt's sigma
    is given beside it. ``fit_p`` tests the law itself: the Kolmogorov-Smirnov p-value of
    the exponential distribution of M - Mc with the fitted b (Lilliefors, by simulation;
    continuous magnitudes only); below :data:`FIT_P_MIN` the text says the catalog is not
    a Gutenberg-Richter law above Mc, and b only summarises it.

    No b (NaN, with ``reason``) for fewer than :data:`MIN_EVENTS` events above Mc, or
    magnitudes above Mc spread by less than :data:`MIN_SPREAD` (events of one size, e.g.
    a noiseless ring's ring-wide ruptures).

    Parameters
    ----------
    moment : array_like, optional
        The events' moments int slip dx (dimensionless, a catalog's ``moment``); give
        exactly one of moment and magnitudes.
    magnitudes : array_like, optional
        Magnitudes given directly (dimensionless).
    dm : float, default 0
        Binning width of the magnitudes, >= 0 (0: continuous).
    confidence : float, default 0.95
        Level of the interval, 0 < confidence < 1.
    n_boot : int, default 1000
        Bootstrap resamples, >= 0 (0: no interval).
    seed : int, default 0
        Seed of the bootstrap, >= 0.

    Returns
    -------
    GutenbergRichter
        b with its interval, Mc, counts and the fit's p-value, or the reason for no b.

    Examples
    --------
    Moments drawn from a Gutenberg-Richter law with b = 1 (M = (2/3) log10(moment)):

    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> rng = np.random.default_rng(0)
    >>> mags = rng.exponential(math.log10(math.e), 2000)   # a Gutenberg-Richter law, b = 1
    >>> gr = bk.stats.gutenberg_richter(10 ** (1.5 * mags), n_boot=200)
    >>> gr.m_c, bool(gr.lo < 1 < gr.hi), gr.fits
    (0.2, True, True)
    >>> bk.stats.gutenberg_richter(np.full(100, 2.0)).ok   # events of one size: no b
    False
    """
    if (moment is None) == (magnitudes is None):
        V._fail("moment", "both or neither of moment and magnitudes", "exactly one of them")
    if magnitudes is None:
        sizes = V.array("moment", moment)
        m = moment_magnitude(sizes)
    else:
        m = V.array("magnitudes", magnitudes)
    dm = V.number("dm", dm, lo=0.0)
    confidence = V.number("confidence", confidence, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    n_boot = V.integer("n_boot", n_boot, lo=0)
    seed = V.integer("seed", seed, lo=0)
    m = m[np.isfinite(m)].ravel()
    nan = math.nan
    base = {"confidence": confidence, "n_total": int(m.size), "dm": dm}
    if m.size == 0:
        return GutenbergRichter(nan, nan, nan, sigma_shi_bolt=nan, m_c=nan, n=0,
                                m_min=nan, m_max=nan, reason="no event with a positive moment",
                                **base)  # fmt: skip
    base.update(m_min=float(m.min()), m_max=float(m.max()))
    m_c = completeness_magnitude(m, dm)
    lo_edge = m_c - dm / 2.0
    sel = m[m >= lo_edge - 1e-9 * dm]
    n = int(sel.size)
    reason = None
    if np.std(m) < MIN_SPREAD:
        cv = ""
        if magnitudes is None:
            s = sizes[np.isfinite(sizes) & (sizes > 0)]
            cv = f", CV of moments {np.std(s) / np.mean(s):.1e}"
        reason = (
            f"degenerate catalog: all {m.size} events have nearly one size (magnitudes "
            f"spread by sd {np.std(m):.1e} < {MIN_SPREAD}{cv}): no magnitude-frequency law"
        )
    elif n < MIN_EVENTS:
        reason = (
            f"too few events: {n} of {m.size} above Mc = {m_c:.3g} (a b needs at least "
            f"{MIN_EVENTS}: its relative error is 1/sqrt(n))"
        )
    elif np.std(sel) < MIN_SPREAD:
        reason = (
            f"degenerate catalog: the {n} events above Mc = {m_c:.3g} have nearly one size "
            f"(magnitudes spread by sd {np.std(sel):.1e} < {MIN_SPREAD})"
        )
    if reason is not None:
        return GutenbergRichter(nan, nan, nan, sigma_shi_bolt=nan, m_c=m_c, n=n,
                                reason=reason, **base)  # fmt: skip
    mean = float(sel.mean())
    b = LOG10_E / (mean - lo_edge)
    sigma_sb = 2.3 * b * b * math.sqrt(float(np.sum((sel - mean) ** 2)) / (n * (n - 1)))
    lo = hi = nan
    fit_p = _fit_p(sel - m_c, np.random.default_rng([seed, 1])) if dm == 0 else nan
    if n_boot:
        rng = np.random.default_rng(seed)
        k, w, _ = _mode_bins(m, dm)
        k0 = int(k.min())
        per = max(1, 4_000_000 // m.size)
        bs = []
        for start in range(0, n_boot, per):
            rows = min(per, n_boot - start)
            bs.append(_b_rows(m[rng.integers(0, m.size, (rows, m.size))], dm, k0, w))
        bs = np.concatenate(bs)
        bs = bs[np.isfinite(bs)]
        if bs.size:
            a = (1.0 - confidence) / 2.0
            lo, hi = (float(q) for q in np.quantile(bs, [a, 1.0 - a]))
    return GutenbergRichter(
        b=float(b),
        lo=lo,
        hi=hi,
        sigma_shi_bolt=sigma_sb,
        m_c=m_c,
        n=n,
        fit_p=fit_p,
        **base,
    )


def power_law_exponent(sizes, s_min: float | None = None) -> tuple[float, float]:
    """Hill estimator of beta in P(size >= s) ~ s^-beta for s >= s_min.

    For amplitude magnitudes b = beta; for moments b = 1.5 beta.

    Parameters
    ----------
    sizes : array_like
        Event sizes, > 0 (any unit: beta does not depend on it).
    s_min : float, optional
        The smallest size counted, > 0 (the unit of ``sizes``); default the smallest.

    Returns
    -------
    beta : float
        The exponent (dimensionless).
    error : float
        Its standard error beta / sqrt(n).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> rng = np.random.default_rng(0)
    >>> mags = rng.exponential(math.log10(math.e), 2000)   # a Gutenberg-Richter law, b = 1
    >>> beta, err = bk.stats.power_law_exponent(10**mags, 1.0)
    >>> bool(abs(beta - 1) < 3 * err)
    True
    """
    s = V.array("sizes", sizes, lo=0.0, lo_open=True).ravel()
    if s.size < 2:
        V._fail("sizes", s.tolist(), "at least 2 sizes >= s_min")
    s_min = float(s.min()) if s_min is None else V.number("s_min", s_min, lo=0.0, lo_open=True)
    sel = s[s >= s_min]
    if sel.size < 2:
        V._fail("sizes", sel.size, "at least 2 sizes >= s_min")
    beta = sel.size / np.sum(np.log(sel / s_min))
    return float(beta), float(beta / np.sqrt(sel.size))


def size_frequency(sizes):
    """Complementary cumulative distribution of event sizes.

    Parameters
    ----------
    sizes : array_like
        Event sizes, > 0 (any unit).

    Returns
    -------
    s : numpy.ndarray
        The sizes, largest first (the unit of ``sizes``).
    fraction : numpy.ndarray
        N(>= s) / n.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.stats.size_frequency([3.0, 1.0, 2.0])
    (array([3., 2., 1.]), array([0.33333333, 0.66666667, 1.        ]))
    """
    s = np.sort(V.array("sizes", sizes, lo=0.0, lo_open=True))[::-1]
    return s, np.arange(1, s.size + 1) / s.size


def recurrence_times(times, positions=None, *, window: float | None = None):
    """Intervals between successive events, anywhere or near the same place.

    Parameters
    ----------
    times : array_like
        Event times (1-d; units of sqrt(m/k_p), or any unit).
    positions : array_like, optional
        Event positions, the shape of ``times`` (dimensionless x, or any unit); with it,
        each event's interval is to the next event within ``window`` of it.
    window : float, optional
        The distance, > 0 (the unit of ``positions``); required with positions.

    Returns
    -------
    numpy.ndarray
        The intervals, in the unit of ``times``.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.stats.recurrence_times([0, 1, 3, 6])
    array([1., 2., 3.])
    >>> bk.stats.recurrence_times([0, 1, 3, 6], [0, 10, 0.5, 10], window=1.0)
    array([3., 5.])
    """
    t = np.sort(V.array("times", times).ravel())
    if np.ndim(times) != 1:
        V._fail("times", f"an array of shape {np.shape(times)}", "a 1-d array of event times")
    if positions is None:
        return np.diff(t)
    x = V.array("positions", positions)
    if x.shape != np.shape(times):
        V._fail("positions", x.shape, f"the shape of times {np.shape(times)}")
    order = np.argsort(np.asarray(times, dtype=float))
    t, x = np.asarray(times, dtype=float)[order], x[order]
    w = V.number("window", window, lo=0.0, lo_open=True)
    out = []
    for i in range(len(t)):
        later = np.nonzero(np.abs(x[i + 1 :] - x[i]) <= w)[0]
        if later.size:
            out.append(t[i + 1 + later[0]] - t[i])
    return np.array(out)
