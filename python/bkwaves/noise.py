"""Noise-triggered slips (issue 14; the open question of the paper's Sec. VI).

Rate laws (:data:`LAWS`, the ``[noise]`` table): spontaneous pair nucleation at a rate
density Lambda(u) = rate g(u) with g(1) = 1, so ``rate`` is the rate at the slip threshold
(per unit length and unit time in the free boundary problem): ``"constant"`` g = 1,
``"exponential"`` g = exp(-(1 - u)/phi0) (an activated law), ``"power"`` g = max(u, 0)^exponent,
``"table"`` g piecewise linear through nodes ``u`` (strictly increasing) and values ``g``
(>= 0; it may fall: the engines thin under its running maximum), constant outside the
nodes and divided by its value at u = 1
(:func:`bkwaves.noise_stats.calibrated_noise` builds one for the free boundary). In the
chain every law is a function of the block's stress from its threshold, x = 1 - (threshold
- phi), in place of u.
:func:`check_noise` validates a ``[noise]`` table, :func:`rate_density` evaluates Lambda(u)
(the core's laws, ``crates/bkwaves-core/src/noise.rs``, are the ones the engines use).

The chain's response to a kick (docs/noise.md): a stuck block at stress u in a uniform
chain, kicked forward with speed ``kick`` over the ground (``Chain.kick(i, -kick)``), starts
a pair of counter-propagating fronts exactly when its neighbours reach the slip threshold
during its first swing. :func:`kick_threshold` is that threshold in closed form,
:func:`nucleates` and :func:`measured_kick_threshold` measure it in the chain, and
:func:`nucleation_probability` is the response function: the probability that a kick
(of fixed size, or exponentially distributed) nucleates a pair at stress u.

>>> import bkwaves as bk
>>> bk.noise.kick_threshold(0.3, dx=0.1, gamma=0.3)       # doctest: +ELLIPSIS
0.0787...
"""

from __future__ import annotations

import math

import numpy as np

from . import _validate as V
from .params import Params

__all__ = [
    "DISTRIBUTIONS",
    "LAWS",
    "check_noise",
    "noise_seed",
    "rate_density",
    "kick_threshold",
    "measured_kick_threshold",
    "nucleates",
    "nucleation_probability",
    "release_stress",
    "deferred_stress",
]

#: Kick-size distributions of :func:`nucleation_probability`.
DISTRIBUTIONS = ("fixed", "exponential")

#: The rate laws by name: each law's own parameters (their ranges: the ``[noise]`` table
#: of ``bkwaves._validate.CONFIG``).
LAWS = {"constant": (), "exponential": ("phi0",), "power": ("exponent",), "table": ("u", "g")}


#: Keys of a ``[noise]`` table besides the law's own, per model: the chain's spontaneous
#: slips also take ``kick`` (optional, default 0: a release).
MODEL_KEYS = {"free_boundary": (), "chain": ("kick",)}


def check_noise(table, where: str = "noise", model: str = "free_boundary") -> dict:
    """A validated ``[noise]`` table: ``law`` (one of :data:`LAWS`), ``rate`` >= 0 and the
    law's own parameters (required; another law's parameters are refused); for the
    chain (``model="chain"``) also ``kick`` >= 0 (forward speed of a spontaneous kick over
    the ground; default 0: the block is released). Errors name the key as written
    (``noise.phi0``) and its allowed range.

    Parameters
    ----------
    table : dict
        The ``[noise]`` table: ``law``, ``rate`` (>= 0; per unit length and unit time in
        the free boundary problem, per block and unit time in the chain, dimensionless
        in the paper's units) and the law's parameters (``phi0`` > 0 and ``exponent``
        dimensionless; ``u`` and ``g`` lists: stress nodes, dimensionless, and relative
        rates).
    where : str, default "noise"
        The table's name in error messages.
    model : {"free_boundary", "chain"}, default "free_boundary"
        The model it is for (the chain also takes ``kick``, dimensionless, in units of
        (f_r - f_s)/sqrt(k_p m)).

    Returns
    -------
    dict
        The validated table, with ``kick`` filled in (0) for the chain.

    Raises
    ------
    bkwaves.ParameterError
        An unknown law or key, a missing parameter, or a value out of range.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.noise.check_noise({"law": "exponential", "rate": 2.0, "phi0": 0.1})
    {'law': 'exponential', 'rate': 2.0, 'phi0': 0.1}
    >>> bk.noise.check_noise({"law": "exponential", "rate": 2.0})
    Traceback (most recent call last):
    ...
    bkwaves._core.ParameterError: invalid noise.phi0 = None: allowed a number phi0 > 0
    """
    specs = V.CONFIG["noise"]
    if not isinstance(table, dict):
        V._fail(where, table, "a table with law, rate and the law's parameters")
    law = specs["law"].check(table.get("law"), f"{where}.law")
    optional = MODEL_KEYS[model]
    allowed = ("law", "rate", *LAWS[law], *optional)
    for key in table:
        if key not in allowed:
            V._fail(
                f"{where}.{key}",
                table[key],
                f"keys of law {law!r}: " + ", ".join(allowed),
            )
    out = {"law": law}
    for key in allowed[1:]:
        if key in optional and key not in table:
            out[key] = 0.0
            continue
        if key not in table:
            V._fail(f"{where}.{key}", None, specs[key].allowed(key))
        out[key] = specs[key].check(table[key], f"{where}.{key}")
    if law == "table":
        _check_table(out, where)
    return out


#: The largest |u| of a ``table`` node (the core's ``TABLE_NODE_MAX``).
TABLE_NODE_MAX = 1e3


def _check_table(out: dict, where: str) -> None:
    """The ``table`` law's nodes (the core checks the same): as lists of floats."""
    u = np.atleast_1d(np.asarray(out["u"], dtype=float))
    g = np.atleast_1d(np.asarray(out["g"], dtype=float))
    if u.ndim != 1 or u.size < 2 or np.any(np.diff(u) <= 0):
        V._fail(f"{where}.u", out["u"], "at least two strictly increasing nodes")
    if np.any(np.abs(u) > TABLE_NODE_MAX):
        # the engines' primitive runs from the first node: a node far from every stress
        # makes it too large to resolve a candidate's increment near u = 1
        V._fail(f"{where}.u", out["u"], "nodes with |u| <= 1000")
    if g.shape != u.shape:
        V._fail(f"{where}.g", out["g"], f"{u.size} values >= 0 (one per node of u)")
    at_one = np.interp(1.0, u, g)
    if not at_one > 0:
        V._fail(f"{where}.g", out["g"], "values >= 0 whose interpolant is > 0 at u = 1")
    with np.errstate(over="ignore", invalid="ignore"):
        ratio = g / at_one
        integral = np.sum(0.5 * (ratio[1:] + ratio[:-1]) * np.diff(u))
    if not (np.all(np.isfinite(ratio)) and np.isfinite(integral)):
        V._fail(
            f"{where}.g",
            out["g"],
            "values >= 0 with g/g(1) finite (and its integral over the nodes)",
        )
    out["u"], out["g"] = u.tolist(), g.tolist()


def noise_seed(seed, noise):
    """The noise generator's seed: the user's, else a random one when there is noise.

    Parameters
    ----------
    seed : int or None
        The user's seed, 0 <= seed < 2**64, or None.
    noise : dict or None
        The ``[noise]`` table, or None (no noise).

    Returns
    -------
    int or None
        ``seed``; without it a seed drawn at random (to be recorded) when there is noise,
        else None.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.noise.noise_seed(5, None), bk.noise.noise_seed(None, None)
    (5, None)
    >>> isinstance(bk.noise.noise_seed(None, {"law": "constant", "rate": 1.0}), int)
    True
    """
    if seed is None:
        if noise is None:
            return None
        import secrets

        return secrets.randbits(63)
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or not 0 <= seed < 2**64:
        V._fail("seed", seed, "an integer 0 <= seed < 2**64")
    return int(seed)


def rate_density(u, noise: dict):
    """The nucleation rate density Lambda(u) = rate g(u) of a ``[noise]`` table.

    Parameters
    ----------
    u : float or array_like
        Stress (dimensionless: 0 is the kinetic, 1 the static friction level).
    noise : dict
        A ``[noise]`` table (:func:`check_noise`).

    Returns
    -------
    float or numpy.ndarray
        Lambda(u), in the unit of ``rate`` (per unit length and unit time of the paper's
        dimensionless variables in the free boundary problem); a float for a scalar u.

    Examples
    --------
    The exponential law is the rate at u = 1 and falls by e over phi0:

    >>> import bkwaves as bk
    >>> noise = {"law": "exponential", "rate": 2.0, "phi0": 0.1}
    >>> bk.noise.rate_density([1.0, 0.9], noise)
    array([2.        , 0.73575888])
    """
    noise = check_noise(noise)
    u = V.array("u", u)
    if noise["law"] == "constant":
        g = np.ones_like(u)
    elif noise["law"] == "exponential":
        g = np.exp(-(1.0 - u) / noise["phi0"])
    elif noise["law"] == "table":
        g = np.interp(u, noise["u"], noise["g"]) / np.interp(1.0, noise["u"], noise["g"])
    else:
        g = np.where(u > 0, np.maximum(u, 0.0) ** noise["exponent"], 0.0)
    out = noise["rate"] * g
    return out.item() if out.ndim == 0 else out


#: The lattice spacings the kick response accepts: dx^2 and 2/dx^2 (the kicked block's
#: Omega^2 = 1 + 2/dx^2) must be finite normal numbers; Params allows dx <= 1e6 too.
DX_RANGE = (1e-150, 1e6)


def _check(dx, gamma):
    dx = V.number("dx", dx, lo=DX_RANGE[0], hi=DX_RANGE[1])
    gamma = V.number("gamma", gamma, lo=0.0, hi=1.0, hi_open=True)
    return dx, gamma


def _swing(dx, gamma):
    """The kicked block's oscillator: Omega^2, damped frequency, and the deflection
    Delta = (1 - u) dx^2 (per unit 1 - u) that trips its neighbours."""
    om2 = 1.0 + 2.0 / dx**2
    return om2, math.sqrt(om2 - gamma**2)


def release_stress(dx: float, gamma: float) -> float:
    """The stress u_r above which any forward slip of one block, however small (a release
    from rest), trips both neighbours: u_r = (2 + dx^2)/(3 + dx^2 + exp(-pi gamma/omega_d)),
    omega_d = sqrt(1 + 2/dx^2 - gamma^2). u_r -> 1/2 undamped as dx -> 0.

    Parameters
    ----------
    dx : float
        Lattice spacing sqrt(k_p/k_c), 1e-150 <= dx <= 1e6 (dimensionless).
    gamma : float
        Viscous damping, 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float
        u_r (dimensionless stress).

    Examples
    --------
    >>> import bkwaves as bk
    >>> round(bk.noise.release_stress(1e-6, 0.0), 9)          # the continuum limit
    0.5
    >>> round(bk.noise.release_stress(0.1, 0.3), 6)
    0.509419
    """
    dx, gamma = _check(dx, gamma)
    _, wd = _swing(dx, gamma)
    return (2.0 + dx**2) / (3.0 + dx**2 + math.exp(-math.pi * gamma / wd))


def deferred_stress(u, kick: float, dx: float, gamma: float):
    """The background stress at which a kick that does not nucleate at once nucleates
    later, on a chain loading uniformly (docs/noise.md, "Deferred nucleation"). The kicked
    block's first swing (amplitude w_max < (1 - u) dx^2) leaves it u - w_max behind and
    raises both neighbours to phi = u + w_max/dx^2 < 1; everything then loads at v, so the
    two neighbours reach the threshold together when the background reaches

        u_b = 1 - w_max/dx^2,

    and, released at phi = 1 beside a block at the background stress, start a pair (if the
    background is excitable, u_b > u_f). A release (kick = 0) at 0 < u < u_r has
    w_max = (1 + exp(-pi gamma/omega_d)) u/Omega^2 exactly, so u_b = 1 - c u with
    c = (1 + exp(-pi gamma/omega_d))/(2 + dx^2) (-> 1 - u as dx -> 0: the mirror stress).
    Returns u where the kick nucleates at once (kick >= K_c(u)); 1 where the block does
    not move (a release at u <= 0); for a kick at u <= 0 whose swing trips the neighbours
    at once (no pair: nothing ahead is excitable), nan. Vectorised in u.

    Parameters
    ----------
    u : float or array_like
        Stress of the uniform chain when the block is kicked (dimensionless).
    kick : float
        Forward speed of the kick over the ground, >= 0 (dimensionless, in units of
        (f_r - f_s)/sqrt(k_p m); 0: a release).
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    gamma : float
        Viscous damping, 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        u_b, the background stress at which the pair starts (dimensionless).

    Examples
    --------
    A release at u = 0.2 nucleates when the background reaches 1 - c u:

    >>> import bkwaves as bk
    >>> c = (1 + 1) / (2 + 0.1**2)                    # undamped: exp(-0) = 1
    >>> bk.noise.deferred_stress(0.2, 0.0, 0.1, 0.0), 1 - c * 0.2
    (0.8009950248756219, 0.8009950248756219)
    """
    dx, gamma = _check(dx, gamma)
    kick = V.number("kick", kick, lo=0.0)
    om2, wd = _swing(dx, gamma)

    def one(x):
        if kick >= _threshold_one(x, dx, gamma):
            return x
        if x >= 1.0:
            return x
        w = max(_first_swing_max(kick, x / om2, om2, wd, gamma), 0.0)
        u_b = 1.0 - w / dx**2
        return u_b if u_b > x else math.nan

    u = V.array("u", u)
    out = np.vectorize(lambda x: one(float(x)), otypes=[float])(u)
    return out.item() if out.ndim == 0 else out


def _first_swing_max(kick, w_star, om2, wd, gamma):
    """Largest deflection w = u - u_i of the kicked block before it re-sticks:
    w'' + 2 gamma w' + Omega^2 (w - w*) = 0, w(0) = 0, w'(0) = kick; the first zero of w'
    is at omega_d t = x in (0, pi], the root of kick (wd cos x - gamma sin x) + Omega^2 w* sin x."""
    c = (om2 * w_star - gamma * kick) / wd  # w' = e^{-gamma t} (kick cos + c sin)
    x = math.atan2(-kick, c) % math.pi  # kick cos x + c sin x = 0
    if x == 0.0:
        x = math.pi
    b = (kick - gamma * w_star) / wd
    return w_star + math.exp(-gamma * x / wd) * (-w_star * math.cos(x) + b * math.sin(x))


def _threshold_one(u, dx, gamma):
    if u <= 0.0:
        return math.inf  # nothing ahead is excitable: no pair propagates (docs/noise.md)
    if u >= 1.0:
        return 0.0
    om2, wd = _swing(dx, gamma)
    w_star = u / om2
    need = (1.0 - u) * dx**2
    if _first_swing_max(0.0, w_star, om2, wd, gamma) >= need:
        return 0.0
    lo, hi = 0.0, math.sqrt(om2) * need + 1.0  # undamped bound Omega Delta, plus room
    while _first_swing_max(hi, w_star, om2, wd, gamma) < need:
        hi *= 2.0
    for _ in range(200):  # bisection to the last bit (w_max is increasing in kick)
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if _first_swing_max(mid, w_star, om2, wd, gamma) >= need:
            hi = mid
        else:
            lo = mid
    return hi


def kick_threshold(u, dx: float, gamma: float):
    """The smallest forward kick (speed over the ground, units (f_r - f_s)/sqrt(k_p m)) of a
    stuck block at stress u in a uniform chain at rest that trips its neighbours
    (phi = u + (u - u_i)/dx^2 reaches 1): the kicked block's first swing must reach
    u - u_i = (1 - u) dx^2. Undamped this is Omega sqrt(Delta (Delta - 2 u/Omega^2)),
    Omega^2 = 1 + 2/dx^2, Delta = (1 - u) dx^2, i.e. ~ dx sqrt(2 (1 - u)(1 - 2u)) as dx -> 0;
    0 above :func:`release_stress`; inf for u <= 0. Vectorised in u. The chain nucleates a
    propagating pair exactly at this kick (measured, docs/noise.md) for u above the
    propagation-failure stress of the lattice (where fronts die however started).

    Parameters
    ----------
    u : float or array_like
        Stress of the uniform chain (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    gamma : float
        Viscous damping, 0 <= gamma < 1 (dimensionless).

    Returns
    -------
    float or numpy.ndarray
        K_c(u), in units of (f_r - f_s)/sqrt(k_p m) (dimensionless speed).

    Examples
    --------
    Undamped, the closed form above:

    >>> import math
    >>> import bkwaves as bk
    >>> u, dx = 0.3, 0.1
    >>> om2, delta = 1 + 2 / dx**2, (1 - u) * dx**2
    >>> round(bk.noise.kick_threshold(u, dx, 0.0), 12)
    0.075159829696
    >>> round(math.sqrt(om2 * delta * (delta - 2 * u / om2)), 12)
    0.075159829696
    """
    dx, gamma = _check(dx, gamma)
    u = V.array("u", u)
    out = np.vectorize(lambda x: _threshold_one(float(x), dx, gamma), otypes=[float])(u)
    return out.item() if out.ndim == 0 else out


def nucleates(u: float, kick: float, dx: float, gamma: float, *, blocks: int = 600) -> bool:
    """Measure in the chain: does a forward kick of size ``kick`` at the centre block of a
    uniform chain of ``blocks`` blocks at stress u (v = 0, free ends) start a pair of
    fronts that reach both ends? (Fronts are supersonic, so the run lasts blocks*dx.)

    Parameters
    ----------
    u : float
        Stress of the uniform chain, -1 <= u < 1 (dimensionless).
    kick : float
        Forward speed of the kick over the ground, > 0 (dimensionless, in units of
        (f_r - f_s)/sqrt(k_p m)).
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    gamma : float
        Viscous damping, 0 <= gamma < 1 (dimensionless).
    blocks : int, default 600
        Blocks of the chain, >= 5.

    Returns
    -------
    bool
        Whether both ends slipped.

    Examples
    --------
    Just above and just below the closed-form threshold K_c = 0.07878:

    >>> import bkwaves as bk
    >>> bk.noise.nucleates(0.3, 0.080, 0.1, 0.3, blocks=200)
    True
    >>> bk.noise.nucleates(0.3, 0.078, 0.1, 0.3, blocks=200)
    False
    """
    from .chain import Chain

    u = V.number("u", u, lo=-1.0, hi=1.0, hi_open=True)
    kick = V.number("kick", kick, lo=0.0, lo_open=True)
    dx, gamma = _check(dx, gamma)
    if isinstance(blocks, bool) or not isinstance(blocks, int | np.integer) or blocks < 5:
        V._fail("blocks", blocks, "an integer blocks >= 5")
    ch = Chain(blocks, Params(gamma=gamma, v=0.0, dx=dx), u0=u)
    ch.kick(blocks // 2, -kick)
    first = ch.run(t_end=blocks * dx).first_slip_times()
    return bool(np.isfinite(first[0]) and np.isfinite(first[-1]))


def measured_kick_threshold(
    u: float,
    dx: float,
    gamma: float,
    *,
    blocks: int = 600,
    rtol: float = 1e-6,
    kick_max=64.0,
    kick_min=1e-12,
) -> float:
    """The smallest kick for which :func:`nucleates` is true, by bisection.

    0 if a kick of ``kick_min`` already nucleates (above :func:`release_stress` the
    block's own swing trips its neighbours: :func:`kick_threshold` is 0 there, and no
    positive kick is the smallest).

    Parameters
    ----------
    u : float
        Stress of the uniform chain (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    gamma : float
        Viscous damping, 0 <= gamma < 1 (dimensionless).
    blocks : int, default 600
        Blocks of the chain.
    rtol : float, default 1e-6
        Relative tolerance of the bisection, 0 < rtol < 1.
    kick_max : float, default 64
        The largest kick tried (dimensionless, units of (f_r - f_s)/sqrt(k_p m)).
    kick_min : float, default 1e-12
        The smallest kick tried, 0 < kick_min <= kick_max (same units).

    Returns
    -------
    float
        The threshold kick (dimensionless, units of (f_r - f_s)/sqrt(k_p m)); inf if even
        ``kick_max`` does not start a propagating pair, 0 if ``kick_min`` does.

    Examples
    --------
    The chain's threshold is the closed form :func:`kick_threshold`:

    >>> import bkwaves as bk
    >>> k = bk.noise.measured_kick_threshold(0.3, 0.1, 0.3, blocks=200, rtol=1e-3)
    >>> abs(k / bk.noise.kick_threshold(0.3, 0.1, 0.3) - 1) < 1e-3
    True
    """
    rtol = V.number("rtol", rtol, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    kick_max = V.number("kick_max", kick_max, lo=0.0, lo_open=True)
    kick_min = V.number("kick_min", kick_min, lo=0.0, hi=kick_max, lo_open=True)
    hi = min(1e-3, kick_max)
    while not nucleates(u, hi, dx, gamma, blocks=blocks):
        if hi >= kick_max:
            return math.inf
        hi = min(2.0 * hi, kick_max)
    if nucleates(u, kick_min, dx, gamma, blocks=blocks):
        return 0.0
    lo = kick_min
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if nucleates(u, mid, dx, gamma, blocks=blocks):
            hi = mid
        else:
            lo = mid
    return hi


def nucleation_probability(u, kick: float, dx: float, gamma: float, *, distribution="fixed"):
    """The response function: probability that a kick nucleates a propagating pair at
    stress u (closed form :func:`kick_threshold` K_c(u)). ``distribution="fixed"``: a kick
    of size ``kick``, P = 1 if kick >= K_c(u) else 0 (a uniform chain answers
    deterministically); ``"exponential"``: kick sizes exponential with mean ``kick``,
    P = exp(-K_c(u)/kick). Vectorised in u. Valid above the lattice's propagation-failure
    stress (docs/noise.md, measured there).

    Parameters
    ----------
    u : float or array_like
        Stress of the uniform chain (dimensionless).
    kick : float
        The kick (fixed) or its mean (exponential), > 0 (dimensionless, in units of
        (f_r - f_s)/sqrt(k_p m)).
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    gamma : float
        Viscous damping, 0 <= gamma < 1 (dimensionless).
    distribution : {"fixed", "exponential"}, default "fixed"
        The law of the kick sizes.

    Returns
    -------
    float or numpy.ndarray
        The probability P(u), in [0, 1].

    Examples
    --------
    >>> import math
    >>> import bkwaves as bk
    >>> bk.noise.nucleation_probability([0.2, 0.3, 0.6], 0.1, 0.1, 0.3)
    array([0., 1., 1.])
    >>> p = bk.noise.nucleation_probability(0.3, 0.1, 0.1, 0.3, distribution="exponential")
    >>> p == math.exp(-bk.noise.kick_threshold(0.3, 0.1, 0.3) / 0.1)
    True
    """
    if distribution not in DISTRIBUTIONS:
        V._fail("distribution", distribution, "one of " + ", ".join(DISTRIBUTIONS))
    kick = V.number("kick", kick, lo=0.0, lo_open=True)
    kc = np.asarray(kick_threshold(u, dx, gamma), dtype=float)
    p = (kick >= kc).astype(float) if distribution == "fixed" else np.exp(-kc / kick)
    return p.item() if p.ndim == 0 else p
