"""Event statistics: size-frequency, Gutenberg-Richter b-value, recurrence times.

The paper (Sec. V) argues that a medium dominated by periodic wave trains shows shocks of
amplitude A at a point with frequency omega ~ 1/A: a Gutenberg-Richter law with b = 1 for
the amplitude magnitude M = log10(A). These functions estimate such laws from a catalog.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as V

__all__ = [
    "BValue",
    "b_value",
    "magnitudes",
    "size_frequency",
    "power_law_exponent",
    "recurrence_times",
]

LOG10_E = np.log10(np.e)


@dataclass(frozen=True)
class BValue:
    """Maximum-likelihood b-value (Aki 1965) above the completeness magnitude m_c."""

    b: float
    sigma_aki: float  # b / sqrt(n)
    sigma_shi_bolt: float  # Shi & Bolt (1982)
    n: int
    m_c: float


def magnitudes(sizes, kind: str = "amplitude"):
    """Magnitudes of event sizes: ``"amplitude"`` M = log10(size) (the paper's b = 1 argument
    uses the slip amplitude A); ``"moment"`` M = (2/3) log10(size) for seismic moments."""
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
    2.3 b^2 sqrt(sum (M - mean)^2 / (n (n - 1))).
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


def power_law_exponent(sizes, s_min: float | None = None) -> tuple[float, float]:
    """Hill estimator of beta in P(size >= s) ~ s^-beta for s >= s_min, with its standard
    error beta / sqrt(n). For amplitude magnitudes b = beta; for moments b = 1.5 beta."""
    s = V.array("sizes", sizes, lo=0.0, lo_open=True)
    s_min = float(s.min()) if s_min is None else V.number("s_min", s_min, lo=0.0, lo_open=True)
    sel = s[s >= s_min]
    if sel.size < 2:
        V._fail("sizes", sel.size, "at least 2 sizes >= s_min")
    beta = sel.size / np.sum(np.log(sel / s_min))
    return float(beta), float(beta / np.sqrt(sel.size))


def size_frequency(sizes):
    """Complementary cumulative distribution: sorted sizes s and N(>= s) / n."""
    s = np.sort(V.array("sizes", sizes, lo=0.0, lo_open=True))[::-1]
    return s, np.arange(1, s.size + 1) / s.size


def recurrence_times(times, positions=None, *, window: float | None = None):
    """Intervals between successive events: all events, or (with positions and a window)
    between events whose positions lie within ``window`` of each other in turn."""
    t = np.sort(V.array("times", times))
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
