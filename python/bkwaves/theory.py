"""The paper's closed forms, numpy-vectorised. Each docstring cites its equation of
C. B. Muratov, Phys. Rev. E 59, 3847 (1999).

Front speed: :func:`c_exact` is c(u_+) = 1/sqrt(1 - u_+^2), the solution of the tip
problem of App. A found by bkwaves (docs/theory.md); the paper's approximations are
:func:`c_interpolation` (eq. c), :func:`c_large` (eq. ca), :func:`c_small` (eq. c1),
and :func:`c_formal_continuum` is the *wrong* continuum answer of Sec. VI.

Functions taking ``c`` accept any speed (exact, interpolated or measured) so that the
paper's formulas can be evaluated exactly as printed.
"""

from __future__ import annotations

import numpy as np

from . import _core
from . import _validate as V
from .waves import front_speed

__all__ = [
    "c_exact",
    "c_interpolation",
    "u_plus_interpolation",
    "c_large",
    "c_small",
    "c_formal_continuum",
    "critical_stress",
    "gamma_tilde",
    "width",
    "u_minus",
    "amplitude",
    "profile",
    "restick_velocity",
    "restick_velocity_closed_form",
    "restick_time",
    "critical_stress_under_load",
    "wavelength",
    "train_period",
    "min_wavelength",
    "sawtooth",
    "source_b",
    "kappa",
    "u_minus_at_one",
    "a_prime",
    "a_max",
    "iterate_map",
    "a_n_asymptote",
    "source_period",
    "lattice_front_speed",
    "curvature_coefficient",
]

PAPER_FOURTH_COEFFICIENT = 0.2719
"""The coefficient of 1/c^8 in eq. (ca) quoted by the paper (the exact c gives 35/128)."""


def _out(a):
    a = np.asarray(a, dtype=float)
    return a.item() if a.ndim == 0 else a


def _u(u_plus):
    return V.array("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)


def _c(c):
    return V.array("c", c, lo=1.0, lo_open=True)


def _gamma(gamma):
    return V.number("gamma", gamma, lo=0.0)


def _v(v):
    return V.number("v", v, lo=0.0, lo_open=True)


# --------------------------------------------------------------------------- speed
def c_exact(u_plus):
    """c(u_+) = 1/sqrt(1 - u_+^2): the exact solution of the tip problem (App. A).

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).

    Returns
    -------
    float or numpy.ndarray
        The front speed in units of the sound speed, of the shape of u_plus.

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.c_exact(0.6)
    1.25
    """
    return front_speed(u_plus)


def u_plus_interpolation(c):
    """Eq. (c): the stress u_+ ahead of a front of speed c, interpolated.

    u_+ = (1 + (2 + c^2 + 4c^4)/(8 c^5 sqrt(c^2 - 1)))^-1.

    Parameters
    ----------
    c : float or array_like
        Front speed, > 1, in units of the sound speed a sqrt(k_c/m) (exact, interpolated or
        measured).

    Returns
    -------
    float or numpy.ndarray
        u_+ in (0, 1).

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.u_plus_interpolation(1.25), 4)   # exact: 0.6
    0.5787
    """
    c = _c(c)
    return _out(1.0 / (1.0 + (2.0 + c**2 + 4.0 * c**4) / (8.0 * c**5 * np.sqrt(c**2 - 1.0))))


def c_interpolation(u_plus):
    """Eq. (c) solved for c: the paper's interpolated front speed.

    Bisection in ln(c - 1) (eq. (c) is monotone in c). The paper says it is good to "a few
    per cent"; against the exact c it is within 2%.

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).

    Returns
    -------
    float or numpy.ndarray
        The front speed in units of the sound speed, of the shape of u_plus.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.c_interpolation(0.6), 4)         # exact: 1.25
    1.2746
    """
    u = _u(u_plus)
    lo = np.full(u.shape, -80.0)
    hi = np.full(u.shape, 40.0)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        c = 1.0 + np.exp(mid)
        f = 1.0 / (1.0 + (2.0 + c**2 + 4.0 * c**4) / (8.0 * c**5 * np.sqrt((c - 1) * (c + 1))))
        up = f < u
        lo = np.where(up, mid, lo)
        hi = np.where(up, hi, mid)
    return _out(1.0 + np.exp(0.5 * (lo + hi)))


def c_large(u_plus, *, fourth: float | None = None):
    """Eq. (ca) solved for c: the large-c series of the front speed.

    1/(2c^2) + 3/(8c^4) + 5/(16c^6) [+ fourth/c^8] = (1 - u_+)/u_+. Where the truncated
    series has no root with c > 1 (small u_+, outside its range of validity) the result is
    NaN.

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).
    fourth : float, optional
        The coefficient of 1/c^8: ``PAPER_FOURTH_COEFFICIENT`` adds the paper's 0.2719 term
        (the exact value is 35/128); default: the series to 1/c^6.

    Returns
    -------
    float or numpy.ndarray
        The front speed in units of the sound speed, of the shape of u_plus.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.c_large(0.9), 4), round(theory.c_exact(0.9), 4)
    (2.2903, 2.2942)
    """
    u = _u(u_plus)
    theta = (1.0 - u) / u
    k4 = 0.0 if fourth is None else float(fourth)

    def series(x):
        return x * (0.5 + x * (0.375 + x * (0.3125 + x * k4)))

    lo = np.zeros(u.shape)
    hi = np.ones(u.shape)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        up = series(mid) < theta
        lo = np.where(up, mid, lo)
        hi = np.where(up, hi, mid)
    x = 0.5 * (lo + hi)
    valid = series(1.0) >= theta
    return _out(np.where(valid, 1.0 / np.sqrt(x), np.nan))


def c_small(u_plus):
    """Eq. (c1): c = 1 + u_+^2/2, the small-u_+ limit.

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).

    Returns
    -------
    float or numpy.ndarray
        The front speed in units of the sound speed, of the shape of u_plus.

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.c_small(0.1), round(theory.c_exact(0.1), 6)
    (1.005, 1.005038)
    """
    u = _u(u_plus)
    return _out(1.0 + 0.5 * u**2)


def c_formal_continuum(u_plus):
    """WRONG on purpose: c = 1/sqrt(1 - u_+), the formal continuum answer the paper
    warns against (Sec. VI). Provided only for comparison; never use it as c(u_+).

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        1/sqrt(1 - u_+), which is not the front speed.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.c_formal_continuum(0.6), 4), theory.c_exact(0.6)
    (1.5811, 1.25)
    """
    u = _u(u_plus)
    return _out(1.0 / np.sqrt(1.0 - u))


def critical_stress(gamma, speed=None):
    """Eq. (gammac): the critical stress u_c, pulses above it, creep below.

    u_c solves gamma = sqrt(c(u_c)^2 - 1)/c(u_c); with the exact c, u_c = gamma.

    Parameters
    ----------
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    speed : callable, optional
        Another front-speed law c(u_+) (default: the exact one); where it raises
        ValueError (no supersonic front at that stress, as the chain's tip solver at
        finite dx says for small u_+) the stress counts as creeping.

    Returns
    -------
    float or None
        u_c, or None for gamma >= 1 (every wave creeps).

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.critical_stress(0.3)
    0.3
    """
    g = _gamma(gamma)
    if speed is None:
        return _core.critical_stress(g)
    if g >= 1.0:
        return None
    if g == 0.0:
        return 0.0
    lo, hi = 1e-300, 1.0 - 1e-16
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        try:
            c = float(speed(mid))
        except ValueError:
            # a law that has no supersonic front at this stress (the chain's tip solver at
            # finite dx refuses subsonic or marginal fronts): c -> 1, the creep side
            c = 1.0
        if np.sqrt((c - 1.0) * (c + 1.0)) / c < g:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ------------------------------------------------------------- the wave (App. B)
def gamma_tilde(c, gamma):
    """App. B: gamma-tilde = c gamma / sqrt(c^2 - 1); < 1 pulse, >= 1 creep (= 1: the
    critically damped wave, which never re-sticks). With the exact c it is gamma/u_+.

    Parameters
    ----------
    c : float or array_like
        Front speed, > 1, in units of the sound speed a sqrt(k_c/m).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        gamma-tilde (dimensionless).

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.gamma_tilde(1.25, 0.3)
    0.5
    """
    return _out(_core.gamma_tilde(_c(c), _gamma(gamma)))


def width(c, gamma):
    """Eq. (w): the width of the slip pulse, w = pi (c^2 - 1)/sqrt(c^2 (1 - gamma^2) - 1).

    Parameters
    ----------
    c : float or array_like
        Front speed, > 1, in units of the sound speed a sqrt(k_c/m) (exact, interpolated or
        measured).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        w in units of a sqrt(k_c/k_p); NaN in the creep regime.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.width(1.25, 0.3), 6)
    2.720699
    """
    c = _c(c)
    um, w = _core.wave_from_speed(np.full(c.shape, 0.5), c, _gamma(gamma))
    return _out(w)


def u_minus(u_plus, c, gamma):
    """Eq. (um): the stress left behind the pulse.

    u_- = -u_+ exp(-pi gamma c / sqrt(c^2 (1 - gamma^2) - 1)).

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).
    c : float or array_like
        Front speed, > 1, in units of the sound speed a sqrt(k_c/m) (exact, interpolated or
        measured).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        u_- (< 0); NaN in the creep regime.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.u_minus(0.6, 1.25, 0.3), 6)
    -0.09782
    """
    u, c = np.broadcast_arrays(_u(u_plus), _c(c))
    um, _ = _core.wave_from_speed(np.array(u), np.array(c), _gamma(gamma))
    return _out(um)


def amplitude(u_plus, c, gamma):
    """Eq. (A): the total slip of a block, A = u_+ - u_-.

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).
    c : float or array_like
        Front speed, > 1, in units of the sound speed a sqrt(k_c/m) (exact, interpolated or
        measured).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        A in units of the stress u (times (f_r - f_s)/k_p for metres); NaN in creep.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.amplitude(0.6, 1.25, 0.3), 6)
    0.69782
    """
    return _out(np.asarray(u_plus, dtype=float) - np.asarray(u_minus(u_plus, c, gamma)))


def profile(z, u_plus, gamma, c=None):
    """App. B profile u(z), z = x - c t: eq. (complex) with (ab) for a pulse (u = u_- behind
    z = -w), eq. (real) for creep, u_+ ahead of the front. Exact c unless given.

    Parameters
    ----------
    z : float or array_like
        Comoving positions z = x - c t (dimensionless, the paper's x; front at 0, u_+ ahead).
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    c : float, optional
        The front speed in units of the sound speed (default: the exact c(u_+)).

    Returns
    -------
    float or numpy.ndarray
        u(z), of the shape of z.

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.profile([-1.0, 0.0], 0.6, 0.3)
    array([0.28718902, 0.6       ])
    """
    u = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    z = V.array("z", z)  # (a dict or text: a one-line error, not numpy's TypeError)
    cc = None if c is None else V.number("c", c, lo=1.0, lo_open=True)
    return _out(_core.wave_profile(u, _gamma(gamma), z, cc))


# ------------------------------------------- re-sticking under load (beyond the paper)
def _tail_oscillator(u_plus: float, gamma: float, root_mu: float):
    """A block behind a steady front of speed c, in phase theta = omega_d tau (tau: time
    since its slip): zeta (= gamma-tilde), k = sqrt(1 - zeta^2), the amplitude of its
    speed over the ground u_+/sqrt(mu), mu = 1 - 1/c^2 its effective mass, and omega_d =
    k/sqrt(mu) (docs/theory.md, section 6). None in creep (zeta >= 1)."""
    zeta = gamma / root_mu
    if zeta >= 1.0:
        return None
    k = np.sqrt((1.0 - zeta) * (1.0 + zeta))
    return zeta, k, u_plus / root_mu, k / root_mu


def _tail_terms(theta, zeta, k):
    """s = v a(theta) + amp b(theta): a is the step response of the block's oscillator (the
    pull of the loader), b its free swing from the slip (s = 0, s_tau = u_+/mu)."""
    decay = np.exp(-zeta * theta / k)
    a = 1.0 - decay * (np.cos(theta) + (zeta / k) * np.sin(theta))
    b = decay * np.sin(theta) / k
    return a, b


def _root_mass(u_plus, gamma, c):
    """u_+, gamma and sqrt(mu) = sqrt(c^2 - 1)/c (= u_+ for the exact c: no cancellation
    and no underflow at tiny u_+)."""
    u = _u(u_plus)
    g = _gamma(gamma)
    if c is None:
        return u, g, u
    c = _c(c)
    try:
        u, c = np.broadcast_arrays(u, c)
    except ValueError:
        V._fail("c", c.tolist(), f"a speed or an array of speeds shaped like u_plus {u.shape}")
    return u, g, np.sqrt((c - 1.0) * (c + 1.0)) / c


def _deepest_backswing(zeta: float, k: float, amp: float):
    """The phase theta_R in the first backswing (pi, 2 pi) where -amp b/a is largest, and
    that largest value, v_c: s = a (v - R(theta)) with R = -amp b/a, a > 0, and R rises
    from 0 at pi to v_c at theta_R (it is unimodal there), so s has a zero iff v <= v_c."""
    from scipy.optimize import minimize_scalar  # scipy only where used (`bkwaves speed`)

    def minus_ratio(theta):
        a, b = _tail_terms(theta, zeta, k)
        return amp * b / a

    opt = minimize_scalar(
        minus_ratio, bounds=(np.pi, 2.0 * np.pi), method="bounded", options={"xatol": 1e-12}
    )
    return float(opt.x), max(-float(opt.fun), 0.0)


def restick_velocity(u_plus, gamma, c=None):
    """The largest loading rate v at which the blocks behind a steady pulse re-stick
    (beyond the paper, which takes v -> 0; derivation: docs/theory.md, section 6).

    Behind a front of speed c a sliding block obeys (1 - 1/c^2) u_tt + 2 gamma u_t + u =
    2 gamma v; its speed over the ground s = v - u_t starts at 0 and swings like a damped
    oscillator of damping ratio gamma-tilde = gamma c/sqrt(c^2 - 1) about the plate's v.
    It re-sticks only if s comes back to 0 in its first backswing, i.e. if v <= v_c; to
    leading order v_c = m/(1 + 2 gamma-tilde m), m = exp(-gamma-tilde (pi + acos
    gamma-tilde)/sqrt(1 - gamma-tilde^2)) = |u_-|/u_+ times the peak slip speed. 0 in creep
    (gamma-tilde >= 1); inf at gamma = 0 (an undamped swing always comes back). The exact c
    by default; pass the chain's, ``bk.front_speed(u_plus, dx=dx, gamma=gamma)``, for a
    lattice (it matters near u_c). Assumes a steady front (the stress it meets constant
    while a block slides) whose speed the loading does not change; checked against the
    chain for 8.6e-8 <= v_c <= 0.16 (docs/theory.md).

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    c : float, optional
        The front speed in units of the sound speed (default: the exact c(u_+); pass the chain's,
        ``bk.front_speed(u_plus, dx=dx, gamma=gamma)``, for a lattice).

    Returns
    -------
    float or numpy.ndarray
        v_c (0 in creep, inf at gamma = 0).

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(float(theory.restick_velocity(0.6, 0.3)), 5)
    0.08206
    """
    u, g, root_mu = _root_mass(u_plus, gamma, c)
    out = np.empty(u.shape)
    for i in np.ndindex(u.shape):
        osc = _tail_oscillator(float(u[i]), g, float(root_mu[i]))
        if osc is None:
            out[i] = 0.0
        elif osc[0] == 0.0:
            out[i] = np.inf
        else:
            out[i] = _deepest_backswing(*osc[:3])[1]
    return _out(out)


def restick_velocity_closed_form(u_plus, gamma, c=None):
    """The closed form of :func:`restick_velocity`: v_c = A m/(1 + 2 zeta m), with
    m = exp(-zeta (pi + acos zeta)/sqrt(1 - zeta^2)), zeta = gamma c/sqrt(c^2 - 1) and the
    swing's amplitude A = u_+ c/sqrt(c^2 - 1) (= 1 for the exact c, not for a lattice's:
    docs/theory.md, section 6). It is the ratio -b/a at the peak of the swing, theta =
    pi + acos zeta; the true maximum lies a little later, so it is low by O(zeta m^2)
    relative (2e-6 at v_c ~ 2e-3, 2e-5 at 7e-3, 1 % at v_c = 0.15). 0 in creep, inf at gamma = 0.

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    c : float, optional
        The front speed in units of the sound speed (default: the exact c(u_+); pass the chain's,
        ``bk.front_speed(u_plus, dx=dx, gamma=gamma)``, for a lattice).

    Returns
    -------
    float or numpy.ndarray
        v_c from the closed form.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(float(theory.restick_velocity_closed_form(0.6, 0.3)), 5)
    0.08178
    """
    u, g, root_mu = _root_mass(u_plus, gamma, c)
    out = np.empty(u.shape)
    for i in np.ndindex(u.shape):
        osc = _tail_oscillator(float(u[i]), g, float(root_mu[i]))
        if osc is None:
            out[i] = 0.0
        elif osc[0] == 0.0:
            out[i] = np.inf
        else:
            zeta, k, amp, _ = osc
            m = np.exp(-zeta * (np.pi + np.arccos(zeta)) / k)
            out[i] = amp * m / (1.0 + 2.0 * zeta * m)
    return _out(out)


def restick_time(u_plus, gamma, v, c=None):
    """Time from a block's slip to its re-stick behind a steady pulse loaded at rate v: the
    first zero of its speed over the ground s(tau) (docs/theory.md, section 6). At v = 0
    it is w/c (App. B); NaN when the block does not re-stick (v > :func:`restick_velocity`,
    or creep). Exact c by default, or the given one (a lattice's).

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), >= 0 (dimensionless).
    c : float, optional
        The front speed in units of the sound speed (default: the exact c(u_+); pass the chain's,
        ``bk.front_speed(u_plus, dx=dx, gamma=gamma)``, for a lattice).

    Returns
    -------
    float or numpy.ndarray
        The time in units of sqrt(m/k_p); NaN when the block does not re-stick.

    Examples
    --------
    >>> import bkwaves as bk
    >>> from bkwaves import theory
    >>> w = bk.traveling_wave(0.6, 0.3)
    >>> round(float(theory.restick_time(0.6, 0.3, 0.0)), 6), round(w.w / w.c, 6)
    (2.176559, 2.176559)
    """
    from scipy.optimize import brentq

    u, g, root_mu = _root_mass(u_plus, gamma, c)
    v = V.number("v", v, lo=0.0)
    out = np.full(u.shape, np.nan)
    for i in np.ndindex(u.shape):
        osc = _tail_oscillator(float(u[i]), g, float(root_mu[i]))
        if osc is None:
            continue
        zeta, k, amp, omega = osc
        if v == 0.0:
            out[i] = np.pi / omega
            continue
        if zeta == 0.0:  # undamped: s = v (1 - cos) + amp sin, zero where tan(theta/2) = -amp/v
            out[i] = 2.0 * (np.pi - np.arctan(amp / v)) / omega
            continue
        theta_r, v_c = _deepest_backswing(zeta, k, amp)
        if v > v_c:
            continue

        def s(theta, zeta=zeta, k=k, amp=amp):
            a, b = _tail_terms(theta, zeta, k)
            return v * a + amp * b

        # s > 0 up to pi and <= 0 at theta_r, with one sign change between (see above)
        out[i] = brentq(s, np.pi, theta_r, xtol=1e-14, rtol=1e-14) / omega
    return _out(out)


def critical_stress_under_load(gamma, v, speed=None):
    """The creep/pulse boundary at loading rate v > 0: the u_+ above which the blocks
    behind a steady pulse re-stick, i.e. restick_velocity(u_+, gamma) = v (the paper's
    u_c = gamma is its v -> 0 limit, approached only like 1/ln^2 v: to leading order
    u_c(v) = gamma/sqrt(1 - pi^2/ln^2(1/(e v))); docs/theory.md, section 6).

    ``speed`` may be another c(u_+), e.g. the chain's ``lambda u: bk.front_speed(u, dx=dx,
    gamma=gamma)``. None when no u_+ < 1 re-sticks at this v (gamma >= 1, or v above
    the value at u_+ -> 1); 0 at gamma = 0 (every pulse re-sticks).

    Parameters
    ----------
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    speed : callable, optional
        Another front-speed law c(u_+) (default: the exact one).

    Returns
    -------
    float or None
        The critical u_+ at this v (None where no u_+ < 1 re-sticks).

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.critical_stress_under_load(0.3, 1e-3), 4)    # u_c = 0.3 at v -> 0
    0.3388
    """
    from scipy.optimize import brentq

    g = V.number("gamma", gamma, lo=0.0)
    v = _v(v)
    if g >= 1.0:
        return None
    if g == 0.0:
        return 0.0

    def margin(u):
        c = None if speed is None else float(speed(u))
        return float(restick_velocity(u, g, c=c)) - v

    lo = float(critical_stress(g, speed))
    hi = 1.0 - 1e-6  # c = 707, inside the tip solver's range (speed at finite dx)
    if margin(hi) < 0.0:
        return None
    return brentq(margin, lo, hi, xtol=1e-13, rtol=1e-12)


# ------------------------------------------------------------ wave trains (Sec. V)
def _speed_and_amplitude(u_plus, gamma, c):
    """c and A for eqs. (L) and (T): the given c with eq. (A), or, without one, the exact
    wave of App. B from u_+ itself (its cancellation-free forms hold down to u_+ -> 0,
    where c rounds to 1 and the speed-based forms could not tell pulse from creep)."""
    u = _u(u_plus)
    if c is not None:
        c = _c(c)
        return c, np.asarray(amplitude(u, c, gamma))
    g = _gamma(gamma)
    waves = [_core.traveling_wave(float(x), g) for x in np.ravel(u)]
    speed = np.reshape([w["c"] for w in waves], np.shape(u))
    amp = np.reshape([np.nan if w["A"] is None else w["A"] for w in waves], np.shape(u))
    return speed, amp


def wavelength(u_plus, gamma, v, c=None):
    """Eq. (L): the spatial period L = c A / v of the periodic wave train (Sec. V).

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    c : float, optional
        The front speed in units of the sound speed (default: the exact c(u_+)).

    Returns
    -------
    float
        L in units of a sqrt(k_c/k_p).

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.wavelength(0.6, 0.3, 0.01), 3)
    87.228
    """
    c, amp = _speed_and_amplitude(u_plus, gamma, c)
    return _out(c * amp / _v(v))


def train_period(u_plus, gamma, v, c=None):
    """The time period T = A / v of the wave train (Sec. V).

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    c : float, optional
        The front speed in units of the sound speed (default: the exact c(u_+)).

    Returns
    -------
    float
        T in units of sqrt(m/k_p).

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.train_period(0.6, 0.3, 0.01), 3)
    69.782
    """
    _, amp = _speed_and_amplitude(u_plus, gamma, c)
    return _out(amp / _v(v))


def min_wavelength(gamma, v, speed=None):
    """Eq. (Lmin): L_min = c(u_c) u_c / v; trains exist only for L > L_min.
    None for gamma >= 1 (no train exists).

    Parameters
    ----------
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    speed : callable, optional
        Another front-speed law c(u_+) (default: the exact one).

    Returns
    -------
    float
        L_min in units of a sqrt(k_c/k_p).

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.min_wavelength(0.3, 0.01), 4)
    31.4485
    """
    uc = critical_stress(gamma, speed)
    if uc is None:
        return None
    if uc == 0.0:
        return 0.0
    c = front_speed(uc) if speed is None else float(speed(uc))
    return c * uc / _v(v)


def sawtooth(x, t, u_plus, gamma, v, x0=0.0):
    """The saw-tooth wave train moving right (Sec. V).

    A front at x0 + c t (mod L); behind each front u recovers linearly from u_- to u_+
    over one period L.

    Parameters
    ----------
    x : float or array_like
        Positions (dimensionless, the paper's x = (X/a) dx).
    t : float
        Time, in units of sqrt(m/k_p).
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless, eq. dimless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    x0 : float, default 0
        Position of a front at t = 0 (dimensionless x).

    Returns
    -------
    float or numpy.ndarray
        u(x, t).

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.sawtooth([0.0, 40.0], 0.0, 0.6, 0.3, 0.01).round(4)
    array([0.6 , 0.28])
    """
    u = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    c = float(front_speed(u))
    um = float(u_minus(u, c, gamma))
    if np.isnan(um):
        V._fail("u_plus", u_plus, f"u_plus > u_c = {critical_stress(gamma)} (pulse regime)")
    L = c * (u - um) / _v(v)
    z = np.mod(np.asarray(x, dtype=float) - x0 - c * np.asarray(t, dtype=float), L) - L
    return _out(((z + L) * um - z * u) / L)


# ------------------------------------------------------ sources (Sec. V, App. C)
def source_b(a, v):
    """Eq. (b): how fast the shocks born at a stress maximum separate.

    Shocks born at a maximum u = 1 - a (x - x0)^2 + v t start as x0 +- sqrt(b t), with
    b = (v + sqrt(v^2 + 8a)) / (2a).

    Parameters
    ----------
    a : float
        Curvature of the maximum, > 0.
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).

    Returns
    -------
    float
        b.

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.source_b(1e-4, 0.01)
    200.0
    """
    a = V.array("a", a, lo=0.0, lo_open=True)
    v = V.number("v", v, lo=0.0)
    return _out((v + np.sqrt(v * v + 8.0 * a)) / (2.0 * a))


def _exponent(gamma):
    g = V.number("gamma", gamma, lo=0.0, hi=1.0, hi_open=True)
    return g, np.pi * g / np.sqrt(1.0 - g * g)


def kappa(gamma):
    """Eq. (kappa): kappa = -du_-/du_+ at u_+ = 1.

    kappa = (1 + pi gamma/(1 - gamma^2)^{3/2}) exp(-pi gamma/sqrt(1 - gamma^2)).

    Parameters
    ----------
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float
        kappa.

    Examples
    --------
    >>> from bkwaves import theory
    >>> float(round(theory.kappa(0.3), 6))
    0.77656
    """
    g, e = _exponent(gamma)
    return (1.0 + np.pi * g / (1.0 - g * g) ** 1.5) * np.exp(-e)


def u_minus_at_one(gamma):
    """u_-(1) = -exp(-pi gamma / sqrt(1 - gamma^2)) (eq. um at u_+ = 1).

    Parameters
    ----------
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float
        u_-(1).

    Examples
    --------
    >>> from bkwaves import theory
    >>> float(round(theory.u_minus_at_one(0.3), 6))
    -0.372326
    """
    _, e = _exponent(gamma)
    return -np.exp(-e)


def a_prime(a, v, gamma):
    """Eq. (ap): the curvature of the stress maximum after the shocks have passed.

    a' = -a kappa + 2 a v (1 + kappa)/(v + sqrt(v^2 + 8a)).

    Parameters
    ----------
    a : float
        Curvature before, > 0.
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float
        a' (<= 0: the maximum is lost).

    Examples
    --------
    >>> from bkwaves import theory
    >>> f"{theory.a_prime(1e-4, 0.01, 0.3):.6e}"
    '1.117201e-05'
    """
    a = V.array("a", a, lo=0.0, lo_open=True)
    v = V.number("v", v, lo=0.0)
    k = kappa(gamma)
    # a / (v + sqrt(v^2 + 8a)) first, and sqrt(v^2 + 8a) = sqrt(a) sqrt(v^2/a + 8): no
    # overflow for any finite a (a = 1e308 gave nan, a fuzz finding)
    root = np.sqrt(a) * np.sqrt(v * v / a + 8.0)
    return _out(-a * k + 2.0 * v * (1.0 + k) * (a / (v + root)))


def a_max(v, gamma):
    """Eq. (amax): the largest curvature for which a source survives and synchronises.

    a' > 0 iff a < a_max = v^2 (1 + kappa)/(2 kappa^2); above it, spatiotemporal chaos.

    Parameters
    ----------
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float
        a_max.

    Examples
    --------
    >>> from bkwaves import theory
    >>> f"{theory.a_max(0.01, 0.3):.6e}"
    '1.472991e-04'
    """
    v = V.number("v", v, lo=0.0)
    k = kappa(gamma)
    return v * v * (1.0 + k) / (2.0 * k * k)


MAX_MAP_ITERATIONS = 10**7  # an array of n + 1 floats; ~10 s of Python per 10**7


def iterate_map(a0, v, gamma, n: int):
    """The map a -> a' of eq. (ap) iterated n times from a0: array a_0 .. a_n
    (0 <= n <= 10**7). Iteration stops (NaN after) once a' <= 0, where the maximum is
    lost.

    Parameters
    ----------
    a0 : float
        Initial curvature, > 0.
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), 0 <= gamma < 1 (dimensionless).
    n : int
        Iterations, 0 <= n <= 10**7.

    Returns
    -------
    numpy.ndarray
        a_0 .. a_n (NaN after the maximum is lost).

    Examples
    --------
    >>> from bkwaves import theory
    >>> theory.iterate_map(1e-4, 0.01, 0.3, 2)
    array([1.00000000e-04, 1.11720093e-05, 8.03013780e-06])
    """
    n = V.integer("n", n, lo=0, hi=MAX_MAP_ITERATIONS)
    out = np.full(n + 1, np.nan)
    out[0] = V.number("a0", a0, lo=0.0, lo_open=True)
    for i in range(n):
        nxt = float(a_prime(out[i], v, gamma))
        if nxt <= 0.0:
            out[i + 1] = nxt
            break
        out[i + 1] = nxt
    return out


def a_n_asymptote(n, v, gamma):
    """Sec. V: after n >> 1 iterations a_n ~ v^2 / (2 n (1 + kappa)).

    Parameters
    ----------
    n : int or array_like
        Iteration number(s), >= 1.
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        a_n.

    Examples
    --------
    >>> from bkwaves import theory
    >>> a = theory.iterate_map(1e-4, 0.01, 0.3, 100)[-1]
    >>> round(float(a / theory.a_n_asymptote(100, 0.01, 0.3)), 2)
    0.99
    """
    n = V.array("n", n, lo=0.0, lo_open=True)
    v = V.number("v", v, lo=0.0)
    return _out(v * v / (2.0 * n * (1.0 + kappa(gamma))))


def source_period(v, gamma):
    """The period of a source: T = (1 + exp(-pi gamma/sqrt(1 - gamma^2)))/v (Sec. V).

    Parameters
    ----------
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), > 0 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float
        T in units of sqrt(m/k_p).

    Examples
    --------
    >>> from bkwaves import theory
    >>> float(round(theory.source_period(0.01, 0.3), 4))
    137.2326
    """
    _, e = _exponent(gamma)
    return (1.0 + np.exp(-e)) / _v(v)


# ------------------------------------------------------------------- the plane
def _direction(direction):
    named = {"x": (1, 0), "y": (0, 1), "diagonal": (1, 1)}
    if isinstance(direction, str):
        if direction not in named:
            raise ValueError(
                f"direction must be 'x', 'y', 'diagonal' or two integers (q, p), got {direction!r}"
            )
        return named[direction]
    try:
        q, p = (int(direction[0]), int(direction[1]))
        ok = len(direction) == 2 and (q, p) == tuple(direction) and (q, p) != (0, 0)
    except (TypeError, ValueError, IndexError):
        ok = False
    if not ok or np.gcd(q, p) != 1:
        raise ValueError(
            "direction must be 'x', 'y', 'diagonal' or two integers (q, p) without a common "
            f"factor, got {direction!r}"
        )
    return (abs(q), abs(p))


def lattice_front_speed(u_plus, gamma, dx, direction=(1, 0)):
    """The speed of a planar front on the square lattice (dx = dy) whose normal is the
    lattice direction (q, p): the lattice's anisotropy, exactly (beyond the paper;
    docs/lattice.md, "Derived: the anisotropy").

    The front reaches every block on a line m = q i + p j at once, so the lattice is
    exactly a chain in m of spacing dx/sqrt(p^2 + q^2) along the normal whose blocks are
    coupled to m +- q and m +- p. (1, 0) is the chain at dx (``bk.front_speed(u_plus,
    dx=dx, gamma=gamma)``, returned as such), (1, 1) the chain at dx/sqrt(2) (likewise);
    other directions are integrated by an independent numpy chain (seconds). All tend to
    1/sqrt(1 - u_+^2) as dx -> 0.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_x) = sqrt(k_p/k_y), 0 < dx < 1 (dimensionless length).
    direction : {"x", "y", "diagonal"} or tuple of two int
        The normal (q, p) (without a common factor; its angle to the x axis is
        atan(p/q)).

    Returns
    -------
    float
        c along the normal, in units of the sound speed.

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.lattice_front_speed(0.6, 0.45, 0.1, "diagonal"), 6)
    1.233152
    """
    u = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    g = _gamma(gamma)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    q, p = _direction(direction)
    if q == 0 or p == 0:
        return float(front_speed(u, dx=dx, gamma=g))
    if q == p:
        return float(front_speed(u, dx=dx / np.sqrt(2.0), gamma=g))
    from . import _curved_chain

    return _curved_chain.front_speed(u, g, dx, (q, p))[0]


def curvature_coefficient(u_plus, gamma, dx, direction="x", *, dy=None):
    """D of the lattice's eikonal law c_n = c_planar - D kappa for a gently curved front
    (kappa -> 0), derived (beyond the paper; docs/theory.md, section 7).

    A front of curvature kappa reaches the blocks beside a block later than the block
    itself; to first order in kappa that is a delay of the neighbours' displacements, a
    neighbour at tangential offset s by kappa s^2/(2c). Along an axis the two neighbours
    across the front are on the block's own line: an extra drag (kappa/c) u_t, i.e.
    gamma -> gamma + kappa/(2c), so D = -(dc/dgamma)/(2c) with c the chain's speed at the
    spacing along the normal (``bk.front_speed(u_plus, dx=dx, gamma=gamma)``). Along the
    diagonal (dx = dy) the four neighbours are each delayed by kappa dx^2/(4c): the chain
    at h = dx/sqrt(2) whose neighbour values are u - delta u_t, delta = kappa h^2/(2c);
    other lattice directions (q, p) likewise (``lattice_front_speed``'s chain with
    delays), integrated here by an independent numpy chain (seconds). D is proportional
    to dx (c depends on gamma at order gamma dx) and vanishes in the continuum. The
    lattice's ruptures reach it as kappa -> 0: the local D of a rupture, measured with its
    local curvature, differs by a term linear in kappa (docs/lattice.md).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_x) along x, 0 < dx < 1 (dimensionless length).
    direction : {"x", "y", "diagonal"} or tuple of two int
        The direction of the front's normal: an axis, the diagonal or a lattice direction
        (q, p) without a common factor (not an axis: dx = dy).
    dy : float, optional
        Lattice spacing across, sqrt(k_p/k_y), 0 < dy < 1 (dimensionless length;
        default dx; directions off the axes need dy = dx).

    Returns
    -------
    float
        D, a length in units of x (c_n - c_planar = -D kappa, kappa in 1/length).

    Examples
    --------
    >>> from bkwaves import theory
    >>> round(theory.curvature_coefficient(0.6, 0.45, 0.1), 4)
    0.021
    """
    from . import _curved_chain

    u = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    g = _gamma(gamma)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    dy = dx if dy is None else V.number("dy", dy, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    q, p = _direction(direction)
    if q == 0 or p == 0:
        h = dx if p == 0 else dy
        e = 0.01
        c = [float(front_speed(u, dx=h, gamma=g + i * e)) for i in range(3)]
        dc_dgamma = (-3.0 * c[0] + 4.0 * c[1] - c[2]) / (2.0 * e)
        return float(-dc_dgamma / (2.0 * c[0]))
    if dy != dx:
        raise ValueError(
            f"direction {direction!r} off the axes needs dy = dx, got dx = {dx}, dy = {dy}"
        )
    c0 = lattice_front_speed(u, g, dx, (q, p))
    eps = 0.05
    cs = [_curved_chain.front_speed(u, g, dx, (q, p), kappa=k, c_ref=c0)[0] for k in (-eps, eps)]
    return float(-(cs[1] - cs[0]) / (2.0 * eps))
