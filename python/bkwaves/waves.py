"""The traveling shock: front speed c(u_+) and the wave behind it (Sec. III, App. A, B)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from . import _core
from . import _validate as V

__all__ = ["front_speed", "traveling_wave", "TravelingWave", "tip_solve"]


def _scalar_or_array(a: np.ndarray):
    return a.item() if a.ndim == 0 else a


def front_speed(u_plus, *, dx: float = 0.0, gamma: float = 0.0, method: str = "exact"):
    """Front speed c(u_+) of the traveling shock at v = 0 (paper Sec. III, App. A).

    Continuum limit (``dx = 0``, the paper's c(u_+)): c = 1/sqrt(1 - u_+^2), the exact
    solution of the tip problem of App. A (docs/theory.md); gamma drops out.
    Discrete chain (``dx > 0``): with ``gamma = 0`` the closed form
    c = dx / (2 u_+ asin(dx sqrt(1 - u_+^2) / (2 u_+))); with ``gamma > 0`` the finite-dx
    tip problem solved numerically (the damping enters at order dx). Both let every
    block behind the tip slide for ever, while the chain re-sticks it about w/dx spacings
    behind the tip; so a speed is returned only where it is the chain's: c > 1 and, for a
    pulse (u_+ > gamma), X = lambda w/(c dx) >= 20 (w the pulse width of App. B, lambda
    the decay rate of the lattice behind the tip; roughly u_+^2/dx >= 2 for small u_+ and
    gamma); creep (u_+ <= gamma) never re-sticks.

    Parameters
    ----------
    u_plus : float or array_like
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless: u = 0 is the kinetic,
        u = 1 the static friction level).
    dx : float, default 0
        Lattice spacing sqrt(k_p/k_c) (dimensionless); 0 is the continuum limit.
    gamma : float, default 0
        Viscous damping alpha/(2 sqrt(k_p m)) (dimensionless); matters only at dx > 0.
    method : {"exact", "tip"}
        ``"exact"``: the closed forms above (the tip solver where there is none);
        ``"tip"``: always the numerical tip solver (about a millisecond per value; it
        agrees with the closed forms to ~1e-12).

    Returns
    -------
    float or numpy.ndarray
        The front speed, in units of the sound speed a sqrt(k_c/m) (c > 1: supersonic);
        a float for a scalar ``u_plus``, else an array of its shape.

    Raises
    ------
    bkwaves.ParameterError
        A parameter out of range, or a front that is not the chain's (a narrow pulse at
        dx > 0): the message names u_plus, dx and gamma and says to measure the front
        with :func:`bkwaves.chain.front` (docs/theory.md, "Narrow pulses").

    See Also
    --------
    tip_solve : the numerical tip problem with its diagnostics.
    bkwaves.chain.front : the front measured in the simulated chain.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.front_speed(0.6)
    1.25
    >>> bk.front_speed([0.3, 0.9])
    array([1.04828484, 2.29415734])
    >>> round(bk.front_speed(0.6, dx=0.1), 6)       # the discrete chain, gamma = 0
    1.249073
    """
    u = V.array("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    dx = V.number("dx", dx, lo=0.0)
    gamma = V.number("gamma", gamma, lo=0.0)
    method = V.choice("method", method, ("exact", "tip"))
    if u.size > 10**7:
        V._fail("u_plus", f"an array of {u.size} values", "at most 10**7 values")
    if dx > 0.0 and gamma == 0.0 and u.size:
        # a steady undamped lattice front needs dx sqrt(1 - u^2) <= 2 u: name dx too
        worst = float(np.max(dx * np.sqrt((1.0 - u) * (1.0 + u)) / (2.0 * u)))
        if worst > 1.0:
            u_min = float(u.ravel()[np.argmax(dx * np.sqrt(1.0 - u * u) / (2.0 * u))])
            V._fail(
                "dx",
                dx,
                f"dx <= 2 u_plus / sqrt(1 - u_plus^2) = {2 * u_min / math.sqrt(1 - u_min**2):.6g}"
                f" at u_plus = {u_min:g} (beyond it no steady lattice front exists)",
            )
    if method == "exact" and dx == 0.0:
        return _scalar_or_array(_core.front_speed(u))
    if method == "exact" and gamma == 0.0:
        return _scalar_or_array(_core.lattice_front_speed(u, dx))
    # (the tip solver makes the same domain check at dx > 0)
    out = np.array([_core.tip_solve_u_plus(float(x), 16, 40.0, dx, gamma)["c"] for x in u.ravel()])
    return _scalar_or_array(out.reshape(u.shape))


def _tip_memory(c: float, degree: int, decay: float) -> float:
    """Bytes of the tip solver's banded system for speed c: (decay / (lambda T) + 4)
    intervals of degree + 1 nodes, a band of 6 (degree + 1) entries per row (LU fill
    included) and a copy; lambda T from lambda = 2 sinh(lambda T / 2), T = 1/c."""
    m = degree + 1
    if c >= 2.0:  # lambda T grows with c (4.3 at c = 2): 2 bounds the system from above
        return (decay / 2.0 + 4.0) * m * 6.0 * m * 8.0 * 2.0
    lam_t = math.sqrt(24.0 * (c - 1.0))  # small-(c - 1) root, refined by Newton
    for _ in range(50):
        f = lam_t * c - 2.0 * math.sinh(lam_t / 2.0)
        df = c - math.cosh(lam_t / 2.0)
        if df == 0.0:
            break
        step = f / df
        lam_t -= step
        if abs(step) < 1e-12 * lam_t:
            break
    if not lam_t > 0.0:
        return math.inf
    return (decay / lam_t + 4.0) * m * 6.0 * m * 8.0 * 2.0


def tip_solve(
    u_plus=None, *, c=None, degree=16, decay=40.0, dx=0.0, gamma=0.0, chain_domain=True
) -> dict:
    """Solve the discrete tip problem (App. A) numerically, given u_plus or c.

    ``dx > 0`` keeps the finite lattice spacing and the damping gamma: the steady front of
    the discrete chain at v = 0 where the pulse is wide in lattice units (the tip problem
    lets every block slide for ever; the chain re-sticks them). Outside that domain (the
    one of :func:`front_speed`) a ParameterError names u_plus, dx and gamma and points to
    :func:`bkwaves.chain.front`. ``dx = 0`` is the paper's continuum limit.

    Parameters
    ----------
    u_plus : float, optional
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless). Give exactly one of
        u_plus and c.
    c : float, optional
        Front speed (> 1, units of the sound speed a sqrt(k_c/m)); the solver finds u_+.
    degree : int, default 16
        Polynomial degree per interval between slips (4..64).
    decay : float, default 40
        e-folds of the slowest transient kept behind the tip (> 0). A solve whose system
        would exceed ``bkwaves.limits.LIMITS["max_solver_bytes"]`` is refused.
    dx : float, default 0
        Lattice spacing sqrt(k_p/k_c) (dimensionless); 0 is the continuum limit.
    gamma : float, default 0
        Viscous damping alpha/(2 sqrt(k_p m)) (dimensionless).
    chain_domain : bool, default True
        False solves the linear tip problem as stated also where it is not the chain's
        front (for studies of the tip problem itself).

    Returns
    -------
    dict
        ``c`` (front speed), ``theta`` = (1 - u_+)/u_+ (the slip threshold in the tip
        variables), ``u_plus``, ``intervals`` (slip intervals kept behind the tip),
        ``decay_rate`` (of the slowest transient, per interval) and ``tip_velocity``.

    See Also
    --------
    front_speed : the closed forms.

    Examples
    --------
    >>> import bkwaves as bk
    >>> sol = bk.tip_solve(0.6)
    >>> round(sol["c"], 10), round(sol["theta"], 10)
    (1.25, 0.6666666667)
    >>> round(bk.tip_solve(c=1.25)["u_plus"], 10)
    0.6
    """
    from .limits import LIMITS, _bytes

    if (u_plus is None) == (c is None):
        raise V.ParameterError("give exactly one of u_plus or c")
    if not isinstance(chain_domain, bool):
        V._fail("chain_domain", chain_domain, "True or False")
    degree = V.integer("degree", degree, lo=4, hi=64)
    decay = V.number("decay", decay, lo=0.0, lo_open=True)
    dx = V.number("dx", dx, lo=0.0)
    gamma = V.number("gamma", gamma, lo=0.0)
    if u_plus is not None:
        u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
        speed, key = 1.0 / math.sqrt((1.0 - u_plus) * (1.0 + u_plus)), "u_plus"
    else:
        c = V.number("c", c, lo=1.0, lo_open=True)
        speed, key = c, "c"
    need = _tip_memory(speed, degree, decay)
    if need > LIMITS["max_solver_bytes"]:
        raise V.ParameterError(
            f"invalid decay = {decay:g}: at {key} = {u_plus if c is None else c:g} (c ~ "
            f"{speed:.6g}) the tip solve needs about {_bytes(need)}, more than the limit "
            f"{_bytes(LIMITS['max_solver_bytes'])} (bkwaves.limits.LIMITS['max_solver_bytes']); "
            "lower decay or degree"
        )
    if u_plus is not None:
        return _core.tip_solve_u_plus(u_plus, degree, decay, dx, gamma, chain_domain)
    return _core.tip_solve_speed(c, degree, decay, dx, gamma, chain_domain)


@dataclass(frozen=True)
class TravelingWave:
    """The traveling wave with stress u_plus ahead and damping gamma (Sec. III, App. B).

    Made by :func:`traveling_wave`. Lengths in units of a sqrt(k_c/k_p), speeds in units
    of the sound speed a sqrt(k_c/m), stresses u dimensionless (eq. dimless).

    Attributes
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    c : float
        Front speed 1/sqrt(1 - u_+^2), in units of the sound speed.
    regime : {"pulse", "creep"}
        ``"pulse"`` for u_+ > u_c (the blocks re-stick: a self-healing pulse), else
        ``"creep"`` (they never do; u -> 0 behind).
    u_c : float or None
        Critical stress of eq. (gammac) (None for gamma >= 1).
    w : float or None
        Pulse width (eq. w), in units of a sqrt(k_c/k_p) (dimensionless x); None in
        creep.
    u_minus : float or None
        Stress left behind (eq. um), dimensionless; None in creep.
    A : float or None
        Total slip u_+ - u_- (eq. A), in units of the stress u (times
        (f_r - f_s)/k_p for metres); None in creep.

    Examples
    --------
    The slip balances the stress drop: A = u_+ - u_- (eq. A).

    >>> import bkwaves as bk
    >>> tw = bk.traveling_wave(0.6, 0.3)
    >>> tw.regime, tw.c, round(tw.A, 12) == round(tw.u_plus - tw.u_minus, 12)
    ('pulse', 1.25, True)
    """

    u_plus: float
    gamma: float
    c: float
    regime: str
    u_c: float | None
    w: float | None
    u_minus: float | None
    A: float | None

    def profile(self, z):
        """The stress profile u(z) (App. B).

        Parameters
        ----------
        z : float or array_like
            Comoving positions z = x - c t (dimensionless, the paper's x): the front at
            0, u_+ ahead (z > 0).

        Returns
        -------
        float or numpy.ndarray
            u at z, of the shape of z.

        Examples
        --------
        >>> import bkwaves as bk
        >>> bk.traveling_wave(0.6, 0.3).profile([-1.0, 0.0, 1.0])
        array([0.28718902, 0.6       , 0.6       ])
        """
        z = np.asarray(z, dtype=float)
        return _scalar_or_array(_core.wave_profile(self.u_plus, self.gamma, z))

    def to_dict(self) -> dict:
        """The fields as a dict (what ``bkwaves wave --json`` prints).

        Returns
        -------
        dict
            Field name -> value (units as in the class).

        Examples
        --------
        >>> import bkwaves as bk
        >>> d = bk.traveling_wave(0.6, 0.3).to_dict()
        >>> d["regime"], d["c"]
        ('pulse', 1.25)
        """
        return asdict(self)


def traveling_wave(u_plus: float, gamma: float) -> TravelingWave:
    """The traveling wave behind a front at stress u_plus (Sec. III, App. B).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).

    Returns
    -------
    TravelingWave
        Speed (exact c(u_+)), regime, critical stress, and for a pulse its width, u_- and
        total slip.

    Examples
    --------
    >>> import bkwaves as bk
    >>> w = bk.traveling_wave(0.6, gamma=0.3)
    >>> w.regime, round(w.w, 4), round(w.u_minus, 4), round(w.A, 4)
    ('pulse', 2.7207, -0.0978, 0.6978)
    >>> bk.traveling_wave(0.2, gamma=0.3).regime     # u_+ < u_c = gamma
    'creep'
    """
    u = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    g = V.number("gamma", gamma, lo=0.0)
    return TravelingWave(**_core.traveling_wave(u, g))
