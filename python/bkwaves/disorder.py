"""Quenched disorder: per-block properties drawn from a distribution with a seed.

>>> import bkwaves as bk
>>> th = bk.disorder.draw("uniform", 400, mean=1.0, spread=0.1, seed=3)
>>> ch = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6, threshold=th)

A property (``threshold``, ``mass``, ``loader``, ``coupling``: ``bk.chain.PROPERTIES``) is
a scalar, an array (one value per block; ``coupling`` one per bond) or drawn here. In a
TOML config the ``[disorder]`` table gives each property as a number, an array or a table
``{distribution = "uniform", mean = 1.0, spread = 0.1}`` drawn with the config's ``seed``
(each property from its own stream, so adding one does not change the others).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _validate as V
from ._core import ParameterError

__all__ = [
    "DISTRIBUTIONS",
    "DefectResponse",
    "METHODS",
    "defect_response",
    "NOISE",
    "EnsembleFront",
    "LocalTheories",
    "draw",
    "front_speed_ensemble",
    "local_theories",
    "marched_speed",
    "property_seed",
    "smooth_field",
    "thresholds",
    "TipMarch",
    "tip_march",
]

#: Distributions by name: what ``mean`` and ``spread`` mean for each.
DISTRIBUTIONS = {
    "uniform": "uniform on [mean - spread, mean + spread] (0 <= spread < mean)",
    "normal": "normal with this mean and standard deviation spread (every value must be > 0)",
    "lognormal": "log-normal with this mean and log-standard-deviation spread",
}


#: The most values one draw returns (800 MB of float64)
MAX_DRAW = 10**8


def check_seed(seed, name: str = "seed") -> int | list[int]:
    """A seed of numpy's generator as bkwaves takes it: an integer 0 <= seed < 2**64 or a
    non-empty sequence of such integers (a float, even 2.0, is refused, never truncated)."""
    allowed = "an integer 0 <= seed < 2**64, or a non-empty list of such integers"
    if isinstance(seed, list | tuple | np.ndarray):
        items = list(np.asarray(seed, dtype=object).ravel())
        if not items:
            V._fail(name, seed, allowed)
        return [check_seed(x, name) for x in items]  # type: ignore[misc]
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or not 0 <= seed < 2**64:
        V._fail(name, seed, allowed)
    return int(seed)


def draw(distribution: str, n: int, *, mean: float = 1.0, spread: float, seed) -> np.ndarray:
    """Draw n per-block values of a property from a named distribution.

    The values are drawn with numpy's default generator seeded by ``seed``; the same
    seed gives the same values.

    Parameters
    ----------
    distribution : {"uniform", "normal", "lognormal"}
        The law (``DISTRIBUTIONS`` says what ``mean`` and ``spread`` mean for each).
    n : int
        How many values, 0 <= n <= 10**8.
    mean : float, default 1
        Their mean, > 0, in the property's own unit (dimensionless: a threshold, mass,
        loader or coupling in units of the uniform chain's).
    spread : float
        Half-width (uniform, 0 <= spread < mean), standard deviation (normal) or
        standard deviation of the logarithm (lognormal), in the unit of ``mean``
        (dimensionless for lognormal).
    seed : int or sequence of int
        Seed of the generator, 0 <= seed < 2**64 (a list: several such integers).

    Returns
    -------
    numpy.ndarray
        The n values (float64), in the unit of ``mean``.

    Examples
    --------
    >>> import bkwaves as bk
    >>> th = bk.disorder.draw("uniform", 100_000, mean=1.0, spread=0.1, seed=3)
    >>> bool(th.min() >= 0.9 and th.max() <= 1.1), round(float(th.std()) * 3**0.5, 2)
    (True, 0.1)
    """
    distribution = V.choice("distribution", distribution, tuple(DISTRIBUTIONS))
    n = V.integer("n", n, lo=0, hi=MAX_DRAW)
    mean = V.number("mean", mean, lo=0.0, lo_open=True)
    spread = V.number("spread", spread, lo=0.0)
    rng = np.random.default_rng(check_seed(seed))
    if distribution == "uniform":
        if spread >= mean:
            V._fail("spread", spread, f"0 <= spread < mean = {mean} (positive values)")
        return rng.uniform(mean - spread, mean + spread, n)
    if distribution == "normal":
        return mean + spread * rng.standard_normal(n)
    return mean * np.exp(spread * rng.standard_normal(n) - 0.5 * spread**2)


def property_seed(seed: int, name: str) -> list[int]:
    """The seed with which a config draws one property: its own stream.

    Each property gets ``[seed, 1 + its index in bk.chain.PROPERTIES]``, so adding a
    drawn property to a config does not change the others.

    Parameters
    ----------
    seed : int
        The config's ``seed``, 0 <= seed < 2**64.
    name : {"threshold", "mass", "loader", "coupling", "coupling_x", "coupling_y"}
        The property; ``coupling_x`` and ``coupling_y`` are the lattice's per-bond
        springs along x (the chain's ``coupling`` stream) and along y (the next one).

    Returns
    -------
    list of int
        The seed to pass to :func:`draw`.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.disorder.property_seed(7, "threshold"), bk.disorder.property_seed(7, "mass")
    ([7, 1], [7, 2])
    """
    from .chain import PROPERTIES

    names = (*PROPERTIES, "coupling_y")
    name = "coupling" if name == "coupling_x" else name
    if name not in names:
        V._fail("name", name, "one of " + ", ".join((*PROPERTIES, "coupling_x", "coupling_y")))
    return [check_seed(seed), 1 + names.index(name)]


def smooth_field(
    shape,
    spacing,
    correlation: float,
    *,
    periodic=False,
    seed=0,
) -> np.ndarray:
    """A spatially correlated random field on a grid of ``shape`` (a chain: (n,), a
    lattice: (ny, nx)) with ``spacing`` per axis ((dy, dx) for a lattice; a scalar for
    all axes): zero mean, largest |value| 1, Gaussian correlation
    <f(r) f(r + s)> / <f^2> = exp(-|s|^2 / (2 correlation^2)) in the plane (s in units
    of x, |s|^2 the sum over the axes).

    The generator of a chain config's smooth fields ([disorder] ... correlation_length,
    ``initial.kind = "random"``), in any number of dimensions: white noise filtered in
    Fourier space by exp(-(k correlation)^2 / 4), on a grid padded by 6 correlation
    lengths along each non-periodic axis (so the field does not wrap around), cut to
    ``shape``, its mean removed, scaled to a largest |value| of 1. ``periodic``: per
    axis or for all (then the field is periodic along it). Use it for a property:
    ``threshold = 1 + 0.1 * smooth_field((ny, nx), (dy, dx), 0.5, seed=1)``.

    Parameters
    ----------
    shape : int or tuple of int
        Nodes per axis ((n,) or (ny, nx)).
    spacing : float or tuple of float
        Node spacing per axis (dimensionless, the paper's x: dx for a chain).
    correlation : float
        Correlation length (dimensionless, the paper's x).
    periodic : bool or tuple of bool, default False
        Periodic along all axes, or per axis.
    seed : int, default 0
        Seed of the generator.

    Returns
    -------
    numpy.ndarray
        The field, of ``shape`` (dimensionless: zero mean, largest absolute value 1).

    Examples
    --------
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> f = bk.disorder.smooth_field((30, 40), (0.1, 0.1), 0.5, seed=1)
    >>> f.shape, float(np.abs(f).max()), abs(float(f.mean())) < 1e-12
    ((30, 40), 1.0, True)
    """
    shape = (shape,) if V._is_int(shape) else tuple(shape)
    if not shape or len(shape) > 3:
        V._fail("shape", shape, "a tuple of 1 to 3 block counts >= 1")
    shape = tuple(V.integer(f"shape[{a}]", n, lo=1, hi=MAX_DRAW) for a, n in enumerate(shape))
    if np.prod(shape, dtype=float) > MAX_DRAW:
        V._fail("shape", shape, f"at most {MAX_DRAW} values")
    d = len(shape)
    spacing = (spacing,) * d if np.ndim(spacing) == 0 else tuple(spacing)
    per = (periodic,) * d if np.ndim(periodic) == 0 else tuple(periodic)
    if len(spacing) != d or len(per) != d:
        V._fail("spacing", spacing, f"a spacing (and periodic flag) per axis ({d})")
    spacing = tuple(V.number(f"spacing[{a}]", h, lo=1e-12, hi=1e9) for a, h in enumerate(spacing))
    corr = V.number("correlation", correlation, lo=0.0, lo_open=True, hi=1e9)
    rng = np.random.default_rng(check_seed(seed))
    return _smooth(shape, spacing, corr, rng, tuple(bool(p) for p in per))


def _smooth(shape, spacing, corr, rng, periodic) -> np.ndarray:
    pad = tuple(
        n if p else n + int(np.ceil(6 * corr / max(h, 1e-300)))
        for n, h, p in zip(shape, spacing, periodic, strict=True)
    )
    if np.prod(pad, dtype=float) > 4 * MAX_DRAW:
        V._fail("correlation", corr, "a correlation length short enough for the padded grid")
    noise = rng.standard_normal(pad)
    kc2 = 0.0  # (k correlation)^2 summed over the axes
    for a, (m, h) in enumerate(zip(pad, spacing, strict=True)):
        f = np.fft.rfftfreq(m, d=h) if a == len(pad) - 1 else np.fft.fftfreq(m, d=h)
        k = (2 * np.pi * f).reshape([-1 if b == a else 1 for b in range(len(pad))])
        kc2 = kc2 + (k * corr) ** 2
    axes = tuple(range(len(pad)))
    field_ = np.fft.irfftn(np.fft.rfftn(noise) * np.exp(-0.25 * kc2), s=pad, axes=axes)
    field_ = field_[tuple(slice(0, n) for n in shape)]
    field_ = field_ - field_.mean()
    m = np.max(np.abs(field_))
    return field_ / m if m > 0 else field_


# --- the front in a disordered chain (docs/disorder.md) ---------------------------------

#: Distributions of the threshold noise xi (zero mean, unit variance): theta = 1 + sigma xi.
NOISE = {
    "uniform": "uniform on [-sqrt(3), sqrt(3)]",
    "normal": "standard normal",
}


def thresholds(n: int, sigma: float, *, distribution: str = "uniform", seed=0) -> np.ndarray:
    """Draw n slip thresholds theta_i = 1 + sigma xi_i around the uniform chain's 1.

    xi_i are independent with zero mean and unit variance (``NOISE``), drawn with numpy's
    default generator seeded by ``seed``.

    Parameters
    ----------
    n : int
        How many blocks, 0 <= n <= 10**8.
    sigma : float
        Standard deviation of the thresholds, >= 0 (dimensionless, in units of the
        static-minus-kinetic friction gap f_r - f_s; uniform: sigma < 1/sqrt(3), so every
        threshold stays > 0).
    distribution : {"uniform", "normal"}, default "uniform"
        The law of xi.
    seed : int or sequence of int, default 0
        Seed of the generator.

    Returns
    -------
    numpy.ndarray
        The n thresholds (dimensionless; 1 is the uniform chain's).

    Examples
    --------
    >>> import bkwaves as bk
    >>> th = bk.disorder.thresholds(100_000, 0.1, seed=1)
    >>> round(float(th.mean()), 3), round(float(th.std()), 3)
    (1.0, 0.1)
    """
    distribution = V.choice("distribution", distribution, tuple(NOISE))
    n = V.integer("n", n, lo=0, hi=MAX_DRAW)
    sigma = V.number("sigma", sigma, lo=0.0)
    rng = np.random.default_rng(check_seed(seed))
    if distribution == "uniform":
        if sigma * np.sqrt(3.0) >= 1.0:
            V._fail("sigma", sigma, "0 <= sigma < 1/sqrt(3) (uniform thresholds stay > 0)")
        return 1.0 + sigma * rng.uniform(-np.sqrt(3.0), np.sqrt(3.0), n)
    return 1.0 + sigma * rng.standard_normal(n)


def _noise_quadrature(distribution: str):
    """Nodes and weights of E[h(xi)] for the noise ``distribution`` (unit variance):
    48 Gauss-Legendre nodes; 20 Gauss-Hermite nodes (|xi| <= 7.6)."""
    if distribution == "uniform":
        x, w = np.polynomial.legendre.leggauss(48)
        return np.sqrt(3.0) * x, w / 2.0
    x, w = np.polynomial.hermite_e.hermegauss(20)
    return x, w / np.sqrt(2.0 * np.pi)


def local_speed(u_plus: float, gamma: float, dx: float):
    """theta -> c(u_+/theta; dx, gamma), the uniform chain's front speed at threshold
    theta (a uniform threshold s is the uniform chain at u_+/s exactly: docs/disorder.md):
    ``bk.front_speed`` where the tip problem is the chain's, else the uniform chain's
    front marched by :func:`tip_march` (narrow pulses, whose blocks re-stick within the
    tip region)."""
    from .waves import front_speed

    def one(u):
        try:
            return float(front_speed(u, dx=dx, gamma=gamma))
        except ParameterError:
            return marched_speed(u, gamma=gamma, dx=dx)

    def c(theta):
        u = u_plus / np.asarray(theta, dtype=float)
        try:
            return front_speed(u, dx=dx, gamma=gamma)
        except ParameterError:
            return np.vectorize(one, otypes=[float])(u)

    return c


#: marched_speed's stated tolerance: the speed moves by less than this (relative) when the
#: marched chain is doubled once more (tests/test_tip_march.py doubles it).
MARCHED_TOLERANCE = 1e-10
#: The longest chain marched_speed marches (its doubling starts at 400 blocks).
MARCHED_MAX_BLOCKS = 102_400


def marched_speed(
    u_plus: float, *, gamma: float = 0.0, dx: float = 0.1, full: bool = False
) -> float | tuple[float, float, int]:
    """The uniform chain's steady front speed, from fronts marched by :func:`tip_march`.

    c over the second half of n uniform blocks, n doubled from 400 until c moves by less
    than MARCHED_TOLERANCE (relative): the trigger's transient decays over a number of
    blocks that grows as c -> 1 (at u_+ = 0.3, gamma = 0, 400 blocks leave c 1.1e-7 off
    at dx = 0.1 and 9.6e-6 off at dx = 0.0125; docs/validation.md, "Convergence of every
    measurement"). Unlike ``bk.front_speed`` it holds where blocks re-stick close behind
    the tip (narrow pulses).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float, default 0
        Viscous damping, >= 0 (dimensionless).
    dx : float, default 0.1
        Lattice spacing sqrt(k_p/k_c), 1e-4 <= dx < 1 (dimensionless).
    full : bool, default False
        Also return the last doubling's change and the blocks marched.

    Returns
    -------
    float or (float, float, int)
        The front speed, in units of the sound speed a sqrt(k_c/m); with ``full``, also
        |c_n / c_(n/2) - 1| (below MARCHED_TOLERANCE) and n.

    Raises
    ------
    bkwaves.ParameterError
        A parameter out of range, a front that stops, or one whose speed has not settled
        to MARCHED_TOLERANCE within MARCHED_MAX_BLOCKS blocks.

    Examples
    --------
    >>> import bkwaves as bk
    >>> c = bk.disorder.marched_speed(0.6, dx=0.1)
    >>> round(c, 9), round(float(bk.front_speed(0.6, dx=0.1)), 9)  # gamma = 0: closed form
    (1.249072905, 1.249072905)
    >>> c, change, n = bk.disorder.marched_speed(0.3, dx=0.1, full=True)
    >>> round(c, 9), bool(change < bk.disorder.MARCHED_TOLERANCE), n
    (1.043837303, True, 3200)
    """
    full = V.flag("full", full)
    n, prev = 400, None
    while True:
        m = tip_march(u_plus, np.ones(n), gamma=gamma, dx=dx)
        if m.stopped:
            V._fail("u_plus", u_plus, f"a stress whose front crosses {n} blocks (it stopped)")
        c = m.speed(n // 2)
        if prev is not None:
            change = abs(c / prev - 1.0)
            if change < MARCHED_TOLERANCE:
                return (c, change, n) if full else c
        if 2 * n > MARCHED_MAX_BLOCKS:
            V._fail(
                "u_plus",
                u_plus,
                f"a front whose speed settles to {MARCHED_TOLERANCE:g} within "
                f"{MARCHED_MAX_BLOCKS} blocks (it still moved by {change:.2g})",
            )
        n, prev = 2 * n, c


@dataclass
class LocalTheories:
    """Averages of local front speeds over the threshold noise (:func:`local_theories`).

    The local speed of block i is c_i = c(u_+/theta_i), the uniform chain's at threshold
    theta_i. The sigma^2 coefficients come from the derivatives of f(theta) = c(u_+/theta)
    at theta = 1: k_arithmetic = f''/2, k_harmonic = f''/2 - f'^2/f, so that
    c_eff = c0 + k sigma^2 + O(sigma^4). Every speed is in units of the sound speed
    a sqrt(k_c/m).

    Parameters
    ----------
    c0 : float
        The uniform chain's speed (theta = 1).
    arithmetic : float
        <c_i>, the arithmetic mean over the noise.
    harmonic : float
        1/<1/c_i> (each block crossed in dx/c_i): the time-averaged speed.
    k_arithmetic : float
        sigma^2 coefficient of the arithmetic mean (speed units).
    k_harmonic : float
        sigma^2 coefficient of the harmonic mean (speed units).

    Examples
    --------
    >>> import bkwaves as bk
    >>> lt = bk.disorder.local_theories(0.6, 0.0, 0.05, dx=0.1)
    >>> lt.harmonic < lt.arithmetic                     # Jensen: 1/<1/c> <= <c>
    True
    >>> k_sigma2 = lt.k_arithmetic * 0.05**2              # the sigma^2 term, 0.004
    >>> abs(lt.arithmetic - (lt.c0 + k_sigma2)) < 0.03 * k_sigma2   # O(sigma^4) left
    True
    """

    c0: float
    arithmetic: float
    harmonic: float
    k_arithmetic: float
    k_harmonic: float


#: local_theories' sigma^2 coefficients move by less than this (relative) when the
#: difference step is halved.
LOCAL_K_TOLERANCE = 2e-3


def local_theories(
    u_plus: float,
    gamma: float,
    sigma: float,
    *,
    dx: float,
    distribution: str = "uniform",
) -> LocalTheories:
    """The local-speed theories of the front speed in a chain with noisy thresholds.

    Thresholds theta = 1 + sigma xi (``NOISE``); the local speeds are the uniform chain's
    at the same dx and gamma (``bk.front_speed``, or a marched front where the tip problem
    is not the chain's), averaged by quadrature over xi (48 Gauss-Legendre or 20
    Gauss-Hermite nodes: twice or 1.5 times as many move the averages by < 1e-13); the
    sigma^2 coefficients by central differences of step 1e-2 in theta, within
    LOCAL_K_TOLERANCE of the step halved (measured 2e-4 to 7e-4 relative;
    tests/test_disorder.py).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    sigma : float
        Standard deviation of the thresholds, >= 0 (dimensionless); every threshold over
        the noise's range must exceed u_plus.
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    distribution : {"uniform", "normal"}, default "uniform"
        The law of xi.

    Returns
    -------
    LocalTheories
        The uniform speed, the arithmetic and harmonic averages and their sigma^2
        coefficients (speeds in units of the sound speed).

    Examples
    --------
    >>> import bkwaves as bk
    >>> lt = bk.disorder.local_theories(0.6, 0.0, 0.05, dx=0.1)
    >>> round(lt.c0, 6), round(lt.harmonic, 6), round(lt.arithmetic, 6)
    (1.249073, 1.252243, 1.253289)
    """
    if distribution not in NOISE:
        V._fail("distribution", distribution, "one of " + ", ".join(NOISE))
    sigma = V.number("sigma", sigma, lo=0.0)
    c = local_speed(u_plus, gamma, dx)
    xi, w = _noise_quadrature(distribution)
    theta = 1.0 + sigma * xi
    if np.any(theta <= u_plus):
        V._fail("sigma", sigma, f"thresholds above u_plus = {u_plus} over the noise's range")
    ci = c(theta)
    h = 1e-2
    f0, fp, fm = c(np.array([1.0, 1.0 + h, 1.0 - h]))
    d1 = (fp - fm) / (2 * h)
    d2 = (fp - 2 * f0 + fm) / h**2
    return LocalTheories(
        c0=float(f0),
        arithmetic=float(np.sum(w * ci)),
        harmonic=float(1.0 / np.sum(w / ci)),
        k_arithmetic=float(d2 / 2),
        k_harmonic=float(d2 / 2 - d1**2 / f0),
    )


@dataclass
class TipMarch:
    """What :func:`tip_march` returns: the first slip time of every block and counters.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    threshold : numpy.ndarray
        The blocks' slip thresholds (dimensionless).
    slip_times : numpy.ndarray
        First slip time of every block, in units of sqrt(m/k_p) (block 0: 0, its kick;
        NaN beyond where the front stopped).
    stopped : bool
        Whether the front stopped before the last block.
    behind : int
        Blocks simulated behind the tip.
    steps : int
        Taylor steps taken.
    events : int
        Slips and re-sticks located.
    max_window : int
        The most blocks simulated at once.

    Examples
    --------
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> m = bk.disorder.tip_march(0.6, np.ones(400), dx=0.1)
    >>> m.stopped, float(m.slip_times[0]), round(0.1 / float(m.intervals[-1]), 6)
    (False, 0.0, 1.249073)
    """

    u_plus: float
    gamma: float
    dx: float
    threshold: np.ndarray
    slip_times: np.ndarray
    stopped: bool
    behind: int
    steps: int
    events: int
    max_window: int

    @property
    def intervals(self) -> np.ndarray:
        """t_{i+1} - t_i: the time the front takes from block i to block i + 1."""
        return np.diff(self.slip_times)

    def speed(self, start: int, stop: int | None = None) -> float:
        """The mean front speed c = dx (stop - start)/(t_stop - t_start) between two blocks.

        Parameters
        ----------
        start : int
            The first block of the window.
        stop : int, optional
            Its last block (default: the last block of the chain).

        Returns
        -------
        float
            The speed, in units of the sound speed a sqrt(k_c/m).

        Examples
        --------
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> m = bk.disorder.tip_march(0.6, np.ones(400), dx=0.1)
        >>> round(m.speed(200), 9), round(float(bk.front_speed(0.6, dx=0.1)), 9)
        (1.249072905, 1.249072905)
        """
        stop = len(self.slip_times) - 1 if stop is None else stop
        return float(self.dx * (stop - start) / (self.slip_times[stop] - self.slip_times[start]))


#: The smallest dx of the tip marcher (module comment in tip_march)
MIN_MARCH_DX = 1e-4


def tip_march(
    u_plus: float,
    threshold,
    *,
    gamma: float = 0.0,
    dx: float = 0.1,
    behind: int = 64,
    step: float = 0.5,
    order: int = 20,
) -> TipMarch:
    """March a front (v = 0, Coulomb, forward slips) through blocks with thresholds
    ``threshold`` (block i slips when u_i - Lap_i/dx^2 >= threshold[i]) at stress u_plus
    ahead, started as ``bk.chain.front`` starts it (block 0 kicked forward, free left end),
    simulating only the blocks from the tip back to ``behind`` blocks behind it: the cost per
    block does not grow with the distance travelled. Steps of ``step`` dx, Taylor series of
    degree ``order`` (exact to round-off at the defaults); slip times agree with
    ``bk.Chain(..., threshold=...)`` to the chain's own accuracy (docs/disorder.md).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    threshold : array_like
        One slip threshold per block (dimensionless, 1 is the uniform chain's); the
        chain has as many blocks.
    gamma : float, default 0
        Viscous damping, >= 0 (dimensionless).
    dx : float, default 0.1
        Lattice spacing sqrt(k_p/k_c), 1e-4 <= dx < 1 (dimensionless).
    behind : int, default 64
        Blocks simulated behind the tip, >= 4.
    step : float, default 0.5
        Time step in units of dx (so in units of dx sqrt(m/k_p)).
    order : int, default 20
        Degree of the Taylor series, >= 8.

    Returns
    -------
    TipMarch
        The first slip time of every block (units of sqrt(m/k_p)) and the counters.

    Examples
    --------
    A uniform chain marches at the closed-form lattice speed; one stiff block delays the
    front:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> uniform = bk.disorder.tip_march(0.6, np.ones(400), dx=0.1)
    >>> round(uniform.speed(200), 9) == round(float(bk.front_speed(0.6, dx=0.1)), 9)
    True
    >>> th = np.ones(400)
    >>> th[200] = 1.2
    >>> delayed = bk.disorder.tip_march(0.6, th, dx=0.1)
    >>> bool(delayed.slip_times[-1] > uniform.slip_times[-1])
    True
    """
    from ._core import tip_march as _march

    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    # (round-off in the 1/dx^2 couplings: the uniform chain's c off by 1e-9 at dx = 1e-4,
    # 4e-7 at 1e-5, 2e-5 at 1e-6, and no end below 1e-12: campaign finding, issue 27)
    dx = V.number("dx", dx, lo=MIN_MARCH_DX, hi=1.0, hi_open=True)
    th = np.ascontiguousarray(threshold, dtype=float)
    if th.ndim != 1:
        V._fail("threshold", f"an array of shape {th.shape}", "one threshold per block (1-d)")
    for name, x, lo in (("behind", behind, 4), ("order", order, 8)):
        if isinstance(x, bool) or not isinstance(x, int | np.integer) or x < lo:
            V._fail(name, x, f"an integer {name} >= {lo}")
    r = _march(u_plus, th, dx, gamma, behind=int(behind), step=float(step), order=int(order))
    return TipMarch(
        u_plus=u_plus,
        gamma=gamma,
        dx=dx,
        threshold=th,
        slip_times=np.asarray(r["slip_times"]),
        stopped=bool(r["stopped"]),
        behind=int(behind),
        steps=int(r["steps"]),
        events=int(r["events"]),
        max_window=int(r["max_window"]),
    )


#: How :func:`front_speed_ensemble` measures a realisation.
METHODS = {
    "tip": "the tip marched through the thresholds (tip_march): exact to round-off, cost "
    "per block independent of dx and of the distance, the window runs to the last block",
    "chain": "the whole chain simulated (bk.Chain): RK4 step error ~1e-8 in the slip "
    "intervals, the window kept clear of the far end's reflection",
}


@dataclass
class EnsembleFront:
    """What :func:`front_speed_ensemble` returns.

    c: c_eff per realisation, dx (b - a)/(t_b - t_a) from the first slip times of the
    window blocks a..b; c_mean, c_sem (standard error), realisations. c_local: the
    harmonic local-speed prediction of the same realisation, dx (b - a)/sum_{a<i<=b}
    dx/c(u_+/theta_i) (the same thresholds, so its first-order noise is the measurement's);
    excess_mean, excess_sem: c - c_local (paired). window: (a, b) block indices.
    method: ``METHODS``. Speeds are in units of the sound speed a sqrt(k_c/m).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    sigma : float
        Standard deviation of the thresholds (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    blocks : int
        Blocks per chain.
    distribution : str
        The law of the threshold noise (``NOISE``).
    seed : int
        Realisation r was drawn with ``[seed, r]``.
    window : tuple of int
        The blocks (a, b) between which c is measured.
    c : numpy.ndarray
        c_eff per realisation (speed units).
    c_local : numpy.ndarray or None
        The harmonic local-speed prediction per realisation (speed units).
    method : {"tip", "chain"}, default "chain"
        How the fronts were computed.

    Examples
    --------
    >>> import bkwaves as bk
    >>> e = bk.disorder.front_speed_ensemble(0.6, 0.0, 0.05, blocks=400, realisations=2)
    >>> e.realisations, e.window
    (2, (173, 399))
    >>> abs(e.c_mean - 1.2491) < 0.01                  # near the uniform chain's speed
    True
    """

    u_plus: float
    gamma: float
    sigma: float
    dx: float
    blocks: int
    distribution: str
    seed: int
    window: tuple
    c: np.ndarray
    c_local: np.ndarray | None
    method: str = "chain"

    @property
    def realisations(self) -> int:
        """The number of realisations."""
        return len(self.c)

    @property
    def c_mean(self) -> float:
        """The mean of c over the realisations (units of the sound speed)."""
        return float(np.mean(self.c))

    @property
    def c_sem(self) -> float:
        """The standard error of c_mean (units of the sound speed; NaN for one)."""
        n = len(self.c)
        return float(np.std(self.c, ddof=1) / np.sqrt(n)) if n > 1 else float("nan")

    @property
    def excess_mean(self) -> float | None:
        """The mean of c - c_local (units of the sound speed; None without c_local)."""
        return None if self.c_local is None else float(np.mean(self.c - self.c_local))

    @property
    def excess_sem(self) -> float | None:
        """The standard error of excess_mean (paired; None without c_local or for one)."""
        n = len(self.c)
        if self.c_local is None or n < 2:
            return None
        return float(np.std(self.c - self.c_local, ddof=1) / np.sqrt(n))


def front_speed_ensemble(
    u_plus: float,
    gamma: float,
    sigma: float,
    *,
    dx: float = 0.1,
    blocks: int = 2000,
    realisations: int = 8,
    distribution: str = "uniform",
    seed: int = 0,
    local: bool = True,
    method: str = "tip",
) -> EnsembleFront:
    """c_eff of a front in a chain with thresholds theta_i = 1 + sigma xi_i
    (:func:`thresholds`, realisation r seeded by ``[seed, r]``), measured like
    ``bk.chain.front``: v = 0, uniform u_+ on a free chain of ``blocks`` blocks, block 0
    kicked forward, c from the first slip times of a window past the trigger's transient.
    method ``"tip"`` (default, :func:`tip_march`): the window runs to the last block;
    ``"chain"``: the whole chain (bk.Chain), the window as far from the trigger as the far
    end's reflection allows. Every threshold must exceed u_+ (a block with theta_i <= u_+
    would slip spontaneously). local: also the harmonic local-speed prediction of each
    realisation (``bk.front_speed`` at this dx and gamma; None when a local speed
    u_+/theta_i is outside its domain, e.g. a narrow pulse).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    sigma : float
        Standard deviation of the thresholds, >= 0 (dimensionless); every drawn threshold
        must exceed u_plus.
    dx : float, default 0.1
        Lattice spacing sqrt(k_p/k_c), 0 < dx < 1 (dimensionless).
    blocks : int, default 2000
        Blocks per chain, >= 64.
    realisations : int, default 8
        How many chains, >= 1.
    distribution : {"uniform", "normal"}, default "uniform"
        The law of the threshold noise.
    seed : int, default 0
        Realisation r is drawn with ``[seed, r]``.
    local : bool, default True
        Also compute the harmonic local-speed prediction of each realisation.
    method : {"tip", "chain"}, default "tip"
        Marched fronts or whole simulated chains (``METHODS``).

    Returns
    -------
    EnsembleFront
        The speed of each realisation (units of the sound speed) with mean and standard
        error, and the local prediction.

    Examples
    --------
    The measured speed falls below the harmonic local-speed prediction of the same
    thresholds (docs/disorder.md):

    >>> import bkwaves as bk
    >>> e = bk.disorder.front_speed_ensemble(0.6, 0.0, 0.05, blocks=400, realisations=2)
    >>> bool(e.excess_mean < 0), round(e.c_mean, 3)
    (True, 1.248)
    """
    from .chain import Chain, _app_b, _plan
    from .params import Params

    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    sigma = V.number("sigma", sigma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    for name, x, lo in (("blocks", blocks, 64), ("realisations", realisations, 1)):
        if isinstance(x, bool) or not isinstance(x, int | np.integer) or x < lo:
            V._fail(name, x, f"an integer {name} >= {lo}")
    if distribution not in NOISE:
        V._fail("distribution", distribution, "one of " + ", ".join(NOISE))
    if method not in METHODS:
        V._fail("method", method, "one of " + ", ".join(METHODS))
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        V._fail("seed", seed, "an integer seed >= 0")
    n = int(blocks)
    tw = _app_b(u_plus, gamma)
    if tw is not None and tw.regime == "pulse":
        # from the settled distance of bk.chain.front to the far end's reflection
        a, b = _plan(tw.c, tw.w, dx)[1], _plan(tw.c, tw.w, dx, n)[2]
    else:
        a, b = n // 4, 3 * n // 4
    if method == "tip":
        b = n - 1  # no far end to reflect from: the front is marched to the last block
    if b - a < 32:
        V._fail(
            "blocks",
            blocks,
            f"a chain long enough for a window of 32 blocks ({a} + {n - b} needed)",
        )
    params = Params(gamma=gamma, v=0.0, dx=dx)
    speeds, predicted = [], []
    for r in range(int(realisations)):
        theta = thresholds(n, sigma, distribution=distribution, seed=[int(seed), r])
        if np.min(theta) <= u_plus:
            i = int(np.argmin(theta))
            V._fail(
                "sigma",
                sigma,
                f"thresholds above u_plus = {u_plus}: realisation {r} has "
                f"theta[{i}] = {theta[i]:.4g}, a block that slips spontaneously",
            )
        if method == "tip":
            ts = tip_march(u_plus, theta, gamma=gamma, dx=dx).slip_times
        else:
            ch = Chain(n, params, u0=u_plus, threshold=theta)
            ch.kick(0, -2.0)
            res = ch.run(t_end=4.0 * n * dx + 100.0, max_events=1)
            ts = res.first_slip_times()
        if not (np.isfinite(ts[a]) and np.isfinite(ts[b])):
            V._fail("u_plus", u_plus, "a front that crosses the chain (it stopped)")
        speeds.append(float(dx * (b - a) / (ts[b] - ts[a])))
        if local:
            try:
                predicted.append(_harmonic_window(u_plus, gamma, dx, theta[a + 1 : b + 1]))
            except ParameterError:  # a local speed outside bk.front_speed's domain
                local = False
    return EnsembleFront(
        u_plus=u_plus,
        gamma=gamma,
        sigma=sigma,
        dx=dx,
        blocks=n,
        distribution=distribution,
        seed=int(seed),
        window=(a, b),
        c=np.array(speeds),
        c_local=np.array(predicted) if local else None,
        method=method,
    )


def _harmonic_window(u_plus, gamma, dx, theta) -> float:
    """(number of blocks) / sum 1/c(u_+/theta_i), 1/c interpolated (cubic spline on 65
    nodes over the thresholds' range, kept for the next realisation if it covers it)
    from the uniform chain's speeds ``bk.front_speed``."""
    from scipy.interpolate import CubicSpline

    lo, hi = float(theta.min()), float(theta.max())
    key = (u_plus, gamma, dx)
    cached = _SPLINES.get(key)
    if cached is None or lo < cached[0] or hi > cached[1]:
        if cached is not None:
            lo, hi = min(lo, cached[0]), max(hi, cached[1])
        nodes = np.linspace(lo, hi, 65) if hi > lo else np.array([lo - 1e-9, lo, lo + 1e-9])
        cached = (lo, hi, CubicSpline(nodes, 1.0 / local_speed(u_plus, gamma, dx)(nodes)))
        _SPLINES[key] = cached
    return len(theta) / float(np.sum(cached[2](theta)))


_SPLINES: dict = {}


@dataclass
class DefectResponse:
    """The far front's delay D(delta) caused by one block with threshold 1 + delta in a
    uniform chain (``defect_response``): D = a delta + b delta^2 + O(delta^3).
    For iid thresholds 1 + sigma xi (zero mean, unit variance, symmetric) the mean slip
    interval is dx/c0 + b sigma^2 + O(sigma^4) exactly (the cross terms average to zero),
    so c_eff = c0 + k sigma^2 with k = -c0^2 b/dx. a obeys the sum rule a = d(dx/c(u_+/theta))
    /dtheta at theta = 1 (a uniform shift of every threshold: docs/disorder.md).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    c0 : float
        The uniform chain's speed, in units of the sound speed a sqrt(k_c/m).
    a : float
        Linear coefficient of the delay, in units of sqrt(m/k_p) (time per unit delta).
    b : float
        Quadratic coefficient of the delay, in units of sqrt(m/k_p).
    k : float
        sigma^2 coefficient of c_eff, in units of the sound speed.

    Examples
    --------
    >>> import bkwaves as bk
    >>> r = bk.disorder.defect_response(0.6, 0.3, blocks=400)
    >>> round(r.c0, 4), round(r.a, 4)
    (1.2336, 0.0473)
    """

    u_plus: float
    gamma: float
    dx: float
    c0: float
    a: float
    b: float
    k: float


def _first_slips(u_plus, gamma, dx, theta, kick: float = -2.0) -> np.ndarray:
    from .chain import Chain
    from .params import Params

    n = len(theta)
    ch = Chain(n, Params(gamma=gamma, v=0.0, dx=dx), u0=u_plus, threshold=theta)
    ch.kick(0, kick)
    return ch.run(t_end=4.0 * n * dx + 100.0, max_events=1).first_slip_times()


#: defect_response's stated tolerance (relative): its a and b move by less than this when
#: the chain is doubled or delta halved (tests/test_disorder.py; at the defaults).
DEFECT_TOLERANCE = {"a": 1e-4, "b": 1e-3}


def defect_response(
    u_plus: float, gamma: float, *, dx: float = 0.1, delta: float = 0.05, blocks: int = 1500
) -> DefectResponse:
    """a, b and k of :class:`DefectResponse` from five marched fronts (:func:`tip_march`:
    defect 0, +-delta, +-delta/2 at the settled start of ``bk.chain.front``'s window, the
    delay read at its far end), b Richardson-extrapolated to delta -> 0 (its error is
    O(delta^2)). At the defaults a and b are within DEFECT_TOLERANCE of the values with
    the chain doubled or delta halved (measured at u_+ = 0.5, gamma = 0 and 0.7, 0.3:
    at most 3e-7 and 4e-5).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, gamma < u_plus < 1 (dimensionless; a pulse).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    dx : float, default 0.1
        Lattice spacing sqrt(k_p/k_c), 0 < dx < 1 (dimensionless).
    delta : float, default 0.05
        The largest threshold excess of the defect, 0 < delta < 1 - u_plus
        (dimensionless).
    blocks : int, default 1500
        Blocks of the chain, >= 64.

    Returns
    -------
    DefectResponse
        c0, a, b and k (units in :class:`DefectResponse`).

    Examples
    --------
    The linear response obeys the sum rule a = d(dx/c(u_+/theta))/dtheta at theta = 1,
    here against the uniform chain's speed by a centred difference:

    >>> import bkwaves as bk
    >>> r = bk.disorder.defect_response(0.6, 0.3, blocks=400)
    >>> c = lambda th: float(bk.front_speed(0.6 / th, dx=0.1, gamma=0.3))
    >>> h = 1e-4
    >>> slope = (0.1 / c(1 + h) - 0.1 / c(1 - h)) / (2 * h)
    >>> abs(r.a - slope) < 1e-3 * abs(slope)
    True
    """
    from .chain import _app_b, _plan

    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    delta = V.number("delta", delta, lo=0.0, hi=1.0 - u_plus, lo_open=True, hi_open=True)
    if isinstance(blocks, bool) or not isinstance(blocks, int | np.integer) or blocks < 64:
        V._fail("blocks", blocks, "an integer blocks >= 64")
    n = int(blocks)
    tw = _app_b(u_plus, gamma)
    if tw is None or tw.regime != "pulse":
        V._fail("u_plus", u_plus, f"u_plus > gamma = {gamma} (a pulse; creep is not covered)")
    j, far = _plan(tw.c, tw.w, dx)[1], _plan(tw.c, tw.w, dx, n)[2]
    if far - j < 32:
        V._fail("blocks", blocks, "a chain long enough for 32 blocks between defect and end")

    def delay(d):
        theta = np.ones(n)
        theta[j] = 1.0 + d
        return tip_march(u_plus, theta, gamma=gamma, dx=dx).slip_times[far]

    ts0 = tip_march(u_plus, np.ones(n), gamma=gamma, dx=dx).slip_times
    t0 = ts0[far]
    dp, dm, hp, hm = (delay(s * delta) - t0 for s in (1.0, -1.0, 0.5, -0.5))
    a = (4.0 * (hp - hm) / delta - (dp - dm) / (2.0 * delta)) / 3.0
    b_full, b_half = (dp + dm) / (2.0 * delta**2), (hp + hm) / (0.5 * delta**2)
    b = (4.0 * b_half - b_full) / 3.0
    c0 = dx * (far - j) / (ts0[far] - ts0[j])
    return DefectResponse(
        u_plus, gamma, dx, c0=float(c0), a=float(a), b=float(b), k=float(-(c0**2) * b / dx)
    )
