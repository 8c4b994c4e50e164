"""Dimensionless parameters of the model and their physical units (paper eq. dimless):
x' = (x/a) sqrt(k_p/k_c), t' = t sqrt(k_p/m), u = -(k_p X + f_s)/(f_r - f_s), and
gamma = alpha / (2 sqrt(k_p m)), v = V sqrt(k_p m)/(f_r - f_s), dx = sqrt(k_p/k_c).
``beta = f_s/(f_r - f_s)`` sets the backward-slip threshold u - Lap u/dx^2 <= -(1 + 2 beta).
The default ``beta = inf`` is the paper's model: no backward slip (a block slides until its
speed over the ground returns to zero). The forward law does not contain beta, so a chain
that only slides forward moves the same for every beta (see docs/chain.md).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from . import _validate as V
from ._validate import PARAMS as _PARAMS
from ._validate import ParameterError
from .friction import Law

_number = V.number  # from_physical's argument V shadows the module

__all__ = ["NO_BACKWARD_SLIP", "Params", "PhysicalUnits", "check_beta", "friction_note"]

#: The value of beta that means "no backward slip" (the paper's model, the default).
NO_BACKWARD_SLIP = math.inf


def check_beta(value, name: str = "beta") -> float:
    """Check beta = f_s/(f_r - f_s): a number >= 0 or inf, never a string, bytes or bool.

    Parameters
    ----------
    value : float
        beta (dimensionless): >= 0, a block slips backward at phi <= -(1 + 2 beta); inf,
        no backward slip (the paper's model).
    name : str, default "beta"
        The name error messages give it.

    Returns
    -------
    float
        beta.

    Raises
    ------
    bkwaves.ParameterError
        A value that is not a number >= 0.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.params.check_beta(2), bk.params.check_beta(float("inf"))
    (2.0, inf)
    """
    return V.PARAMS["beta"].check(value, name)


def friction_note(beta: float) -> str:
    """One line saying which friction model a beta gives (written into outputs).

    Parameters
    ----------
    beta : float
        f_s/(f_r - f_s), >= 0 or inf (dimensionless).

    Returns
    -------
    str
        The line.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.params.friction_note(2.0)
    'beta = 2: backward slip when u - Lap u/dx^2 <= -(1 + 2 beta) = -5'
    """
    if math.isinf(beta):
        return (
            "beta = inf: no backward slip (the paper's model; a block slides until its speed "
            "over the ground returns to zero)"
        )
    return (
        f"beta = {beta:g}: backward slip when u - Lap u/dx^2 <= -(1 + 2 beta) = {-(1 + 2 * beta):g}"
    )


@dataclass(frozen=True)
class PhysicalUnits:
    """SI description of a chain and the scales that convert to and from the
    dimensionless variables of the paper (eq. dimless).

    Made by :meth:`Params.from_physical` (``p.units``); the fields are its SI inputs:
    mass [kg], k_c and k_p [N/m], f_static and f_kinetic [N], alpha [kg/s], V [m/s],
    spacing [m].

    Conversions (prime = dimensionless):
    ``x = x' * length_scale`` with ``length_scale = spacing / dx``;
    ``t = t' * time_scale`` with ``time_scale = sqrt(mass / k_p)``;
    ``X = -(f_kinetic + (f_static - f_kinetic) u) / k_p`` (block displacement, affine);
    a slip or any displacement *difference* ``dX = -displacement_scale * du``;
    block velocity ``dX/dt = -velocity_scale * du/dt'``;
    force ``F = f_kinetic + force_scale * phi`` with ``phi = u - Lap u / dx^2``
    (slip at phi = 1, i.e. F = f_static).

    Parameters
    ----------
    mass : float
        Block mass m [kg].
    k_c : float
        Coupling spring constant between neighbours [N/m].
    k_p : float
        Loader spring constant [N/m].
    f_static : float
        Static friction force per block f_r [N].
    f_kinetic : float
        Kinetic friction force per block, 0 <= f_kinetic < f_static [N].
    alpha : float
        Viscous coefficient [kg/s].
    V : float
        Loader speed [m/s].
    spacing : float
        Block spacing a [m].

    Examples
    --------
    The paper's Bristol board (Sec. VI): a sliding speed of 1.6 cm/s and a slip of
    1e-8 m per wave (A = 2):

    >>> import bkwaves as bk
    >>> units = bk.presets.bristol_board().units
    >>> round(units.velocity_scale, 4), float(f"{units.slip(2.0):.2g}")
    (0.016, 1e-08)
    """

    mass: float
    k_c: float
    k_p: float
    f_static: float
    f_kinetic: float
    alpha: float
    V: float
    spacing: float

    def __post_init__(self):
        for name, spec in V.PHYSICAL.items():
            object.__setattr__(self, name, spec.check(getattr(self, name)))
        if not self.f_kinetic < self.f_static:
            V._fail(
                "f_kinetic",
                self.f_kinetic,
                f"0 <= f_kinetic < f_static = {self.f_static} (static friction exceeds kinetic)",
            )
        # every scale must be a finite, nonzero number (1e308 m spacings would write x = inf)
        for scale, inputs in (
            ("time_scale", "mass, k_p"),
            ("length_scale", "spacing, k_c, k_p"),
            ("force_scale", "f_static, f_kinetic"),
            ("velocity_scale", "f_static, f_kinetic, k_p, mass"),
            ("displacement_scale", "f_static, f_kinetic, k_p"),
        ):
            value = getattr(self, scale)
            if not (math.isfinite(value) and value > 0.0 and math.isfinite(1.0 / value)):
                raise ParameterError(
                    f"invalid {inputs.split(', ')[0]} = {getattr(self, inputs.split(', ')[0])!r}: "
                    f"the {scale.replace('_', ' ')} derived from {inputs} is {value!r}; allowed "
                    "values whose scales are finite and nonzero"
                )

    # --- scales -----------------------------------------------------------------
    @property
    def force_scale(self) -> float:
        """f_r - f_s [N]: the friction drop, unit of dimensionless force."""
        return self.f_static - self.f_kinetic

    @property
    def time_scale(self) -> float:
        """sqrt(m / k_p) [s]."""
        return math.sqrt(self.mass / self.k_p)

    @property
    def length_scale(self) -> float:
        """Distance along the chain per unit x' [m]: a sqrt(k_c / k_p)."""
        return self.spacing * math.sqrt(self.k_c / self.k_p)

    @property
    def displacement_scale(self) -> float:
        """(f_r - f_s)/k_p [m]: block displacement per unit u."""
        return self.force_scale / self.k_p

    @property
    def velocity_scale(self) -> float:
        """(f_r - f_s)/sqrt(k_p m) [m/s]: the characteristic sliding speed (Sec. VI)."""
        return self.force_scale / math.sqrt(self.k_p * self.mass)

    @property
    def sound_speed(self) -> float:
        """a sqrt(k_c/m) [m/s]; equals length_scale/time_scale (unit speed in x', t')."""
        return self.spacing * math.sqrt(self.k_c / self.mass)

    @property
    def crit_velocity(self) -> float:
        """(f_r - f_s)/sqrt(k_c m) [m/s], eq. (crit): a velocity-weakening law with
        characteristic velocity V_f behaves like Coulomb friction when V_f << this."""
        return self.force_scale / math.sqrt(self.k_c * self.mass)

    # --- conversions ------------------------------------------------------------
    def length(self, x):
        """Dimensionless position x' -> metres.

        Parameters
        ----------
        x : float or array_like
            Position x' (dimensionless).

        Returns
        -------
        float or numpy.ndarray
            Position [m].

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> round(float(units.length(1.0)) / units.length_scale, 12)
        1.0
        """
        return x * self.length_scale

    def length_to_dimless(self, x_m):
        """Position in metres -> dimensionless x'.

        Parameters
        ----------
        x_m : float or array_like
            Position [m].

        Returns
        -------
        float or numpy.ndarray
            Position x' (dimensionless).

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> round(float(units.length_to_dimless(units.length(2.5))), 12)
        2.5
        """
        return x_m / self.length_scale

    def time(self, t):
        """Dimensionless time t' -> seconds.

        Parameters
        ----------
        t : float or array_like
            Time t' (dimensionless, units of sqrt(m/k_p)).

        Returns
        -------
        float or numpy.ndarray
            Time [s].

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> float(f"{units.time(1.0):.3g}")                     # sqrt(m/k_p)
        3.2e-07
        """
        return t * self.time_scale

    def time_to_dimless(self, t_s):
        """Time in seconds -> dimensionless t'.

        Parameters
        ----------
        t_s : float or array_like
            Time [s].

        Returns
        -------
        float or numpy.ndarray
            Time t' (dimensionless, units of sqrt(m/k_p)).

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> round(float(units.time_to_dimless(units.time(2.5))), 12)
        2.5
        """
        return t_s / self.time_scale

    def displacement(self, u):
        """Dimensionless u -> block displacement X [m] relative to its loader spring.

        Parameters
        ----------
        u : float or array_like
            Stress u (dimensionless).

        Returns
        -------
        float or numpy.ndarray
            Displacement X [m].

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> bool(units.displacement(0.0) == -units.f_kinetic / units.k_p)  # u = 0: f_s
        True
        """
        return -(self.f_kinetic + self.force_scale * u) / self.k_p

    def displacement_to_dimless(self, X):
        """Block displacement X [m] -> dimensionless u.

        Parameters
        ----------
        X : float or array_like
            Displacement [m] relative to the loader spring.

        Returns
        -------
        float or numpy.ndarray
            Stress u (dimensionless).

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> round(float(units.displacement_to_dimless(units.displacement(0.6))), 12)
        0.6
        """
        return -(self.k_p * X + self.f_kinetic) / self.force_scale

    def slip(self, du):
        """A change of u (e.g. a total slip A = u_+ - u_-) -> forward block motion [m].

        Parameters
        ----------
        du : float or array_like
            Change of u (dimensionless).

        Returns
        -------
        float or numpy.ndarray
            Forward motion [m].

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> float(f"{units.slip(2.0):.2g}")                     # the paper: 1e-8 m per wave
        1e-08
        """
        return du * self.displacement_scale

    def velocity(self, u_t):
        """du/dt' -> block velocity dX/dt [m/s] in the loader frame.

        Parameters
        ----------
        u_t : float or array_like
            du/dt' (dimensionless).

        Returns
        -------
        float or numpy.ndarray
            Velocity [m/s].

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> round(float(units.velocity(-1.0)), 4)               # the paper: 1.6 cm/s
        0.016
        """
        return -u_t * self.velocity_scale

    def velocity_to_dimless(self, Xdot):
        """Block velocity dX/dt [m/s] -> dimensionless du/dt'.

        Parameters
        ----------
        Xdot : float or array_like
            Velocity [m/s] in the loader frame.

        Returns
        -------
        float or numpy.ndarray
            du/dt' (dimensionless).

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> round(float(units.velocity_to_dimless(units.velocity(0.25))), 12)
        0.25
        """
        return -Xdot / self.velocity_scale

    def force(self, phi):
        """Dimensionless phi = u - Lap u/dx^2 -> elastic force on a block [N].

        Parameters
        ----------
        phi : float or array_like
            phi (dimensionless; the slip threshold is 1).

        Returns
        -------
        float or numpy.ndarray
            Force [N].

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> bool(units.force(1.0) == units.f_static)            # phi = 1: static friction
        True
        """
        return self.f_kinetic + self.force_scale * phi

    def force_to_dimless(self, F):
        """Elastic force on a block [N] -> dimensionless phi.

        Parameters
        ----------
        F : float or array_like
            Force [N].

        Returns
        -------
        float or numpy.ndarray
            phi (dimensionless).

        Examples
        --------
        >>> import bkwaves as bk
        >>> units = bk.presets.bristol_board().units          # the paper's Sec. VI
        >>> round(float(units.force_to_dimless(units.f_kinetic)), 12)
        0.0
        """
        return (F - self.f_kinetic) / self.force_scale


@dataclass(frozen=True)
class Params:
    """Dimensionless parameters of the Burridge-Knopoff chain (frozen, validated).

    The paper's scaling (eq. dimless): positions in units of a sqrt(k_c/k_p), times in
    units of sqrt(m/k_p), stress u = -(k_p X + f_s)/(f_r - f_s).

    Parameters
    ----------
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), >= 0 (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_c) in units of x', > 0.
    beta : float, default inf
        f_s/(f_r - f_s) >= 0, the backward-slip threshold (a stuck block slips backward at
        phi <= -(1 + 2 beta)); inf: no backward slip, the paper's model
        (:meth:`from_physical` sets the finite f_s/(f_r - f_s)).
    units : PhysicalUnits, optional
        The SI description when built by :meth:`from_physical`, else None.
    friction_law : bkwaves.friction.Law or str, optional
        The friction law (``bk.friction.law(name, **its_params)`` or a law's name); None:
        the default law (Coulomb). Its parameters named like a field here (gamma, beta)
        are taken from these fields.

    Raises
    ------
    bkwaves.ParameterError
        A value out of its range, named with the allowed range.

    Examples
    --------
    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=1e-3, dx=0.05)
    >>> p.gamma, p.v, p.dx, p.beta
    (0.3, 0.001, 0.05, inf)
    >>> bk.Params(gamma=-1.0, v=0.0, dx=0.05)
    Traceback (most recent call last):
    ...
    bkwaves._core.ParameterError: invalid gamma = -1.0: allowed 0 <= gamma <= 1000000
    """

    gamma: float
    v: float
    dx: float
    beta: float = NO_BACKWARD_SLIP
    units: PhysicalUnits | None = field(default=None, compare=True)
    friction_law: Law | None = None

    def __post_init__(self):
        for name, spec in V.PARAMS.items():
            object.__setattr__(self, name, spec.check(getattr(self, name)))
        if self.units is not None and not isinstance(self.units, PhysicalUnits):
            V._fail("units", self.units, "a PhysicalUnits instance or None")
        if isinstance(self.friction_law, str):
            object.__setattr__(self, "friction_law", Law(self.friction_law))
        if self.friction_law is not None and not isinstance(self.friction_law, Law):
            V._fail(
                "friction_law", self.friction_law, "a bk.friction.law(...), a law's name or None"
            )
        if self.friction_law is not None:
            for k, _ in self.friction_law.params:
                if k in self.__dataclass_fields__:
                    V._fail(
                        f"friction.{k}",
                        dict(self.friction_law.params)[k],
                        f"{k} given on Params ({k}=...), not in the friction law",
                    )
        self.law_values()  # the law's table checks the combination

    @property
    def law(self) -> Law:
        """The friction law (the default one when none was given)."""
        return self.friction_law if self.friction_law is not None else Law()

    def law_values(self) -> dict:
        """Every parameter of the friction law, validated by its table (table order).

        Returns
        -------
        dict
            Name -> value (dimensionless); ``gamma`` and ``beta`` from these Params.

        Examples
        --------
        >>> import bkwaves as bk
        >>> bk.Params(gamma=0.3, v=0.0, dx=0.1).law_values()
        {'gamma': 0.3, 'beta': inf}
        """
        return self.law.values(self)

    @classmethod
    def from_physical(
        cls,
        *,
        mass: float,
        k_c: float,
        k_p: float,
        f_static: float,
        f_kinetic: float,
        alpha: float,
        V: float,
        spacing: float,
        V_f: float | None = None,
    ) -> Params:
        """Build the dimensionless parameters from a chain described in SI units.

        Parameters
        ----------
        mass : float
            Block mass m [kg].
        k_c : float
            Coupling spring constant between neighbours [N/m].
        k_p : float
            Loader spring constant [N/m].
        f_static : float
            Static friction force per block f_r [N].
        f_kinetic : float
            Kinetic friction force per block f_s < f_r [N].
        alpha : float
            Viscous coefficient [kg/s].
        V : float
            Loader speed [m/s].
        spacing : float
            Block spacing a [m].
        V_f : float, optional
            Velocity-weakening speed scale [m/s] (> 0): friction
            f = f_s + (f_r - f_s)/(1 + V/V_f) + alpha V, with
            v_f = V_f sqrt(k_p m)/(f_r - f_s); None: Coulomb friction.

        Returns
        -------
        Params
            gamma, v, dx and beta = f_s/(f_r - f_s), with ``units`` holding the SI
            description and its conversions (:class:`PhysicalUnits`).

        Examples
        --------
        The paper's Bristol-board example (Sec. VI):

        >>> import bkwaves as bk
        >>> p = bk.Params.from_physical(mass=2.4e-12, k_c=3.8e7, k_p=23.4, f_static=7.4e-7,
        ...                             f_kinetic=6.2e-7, alpha=6.7e-6, V=1e-6, spacing=1e-6)
        >>> round(p.gamma, 3), round(p.dx, 6)
        (0.447, 0.000785)
        >>> round(p.units.time(10.0), 9)               # ten time units in seconds
        3.203e-06
        """
        u = PhysicalUnits(mass, k_c, k_p, f_static, f_kinetic, alpha, V, spacing)
        df = u.force_scale
        sq = math.sqrt(u.k_p) * math.sqrt(u.mass)
        derived = {
            "gamma": (u.alpha / (2.0 * sq), "alpha", "alpha/(2 sqrt(k_p mass))"),
            "v": (u.V * (sq / df), "V", "V sqrt(k_p mass)/(f_static - f_kinetic)"),
            "dx": (math.sqrt(u.k_p) / math.sqrt(u.k_c), "k_c", "sqrt(k_p/k_c)"),
            "beta": (u.f_kinetic / df, "f_kinetic", "f_kinetic/(f_static - f_kinetic)"),
        }
        for name, (value, key, formula) in derived.items():
            try:
                _PARAMS[name].check(value)
            except ParameterError:
                raise ParameterError(
                    f"invalid {key} = {getattr(u, key)!r}: the dimensionless {name} = "
                    f"{formula} = {value!r}; allowed values giving {_PARAMS[name].allowed()}"
                ) from None
        law = None
        if V_f is not None:
            _number("V_f", V_f, lo=0.0, lo_open=True)
            law = Law("velocity_weakening", (("v_f", V_f * (sq / df)),))
        return cls(**{k: v for k, (v, _, _) in derived.items()}, units=u, friction_law=law)

    @property
    def backward_slip(self) -> bool:
        """True when blocks can slip backward (finite beta)."""
        return math.isfinite(self.beta)

    @property
    def friction(self) -> str:
        """The friction model in words (see :func:`~bkwaves.params.friction_note`)."""
        return friction_note(self.beta)

    def to_dict(self) -> dict:
        """The parameters as a dict (the TOML ``[params]`` table, with ``units`` if any).

        Returns
        -------
        dict
            gamma, v, dx, beta (dimensionless), ``units`` (SI inputs) and ``friction``
            where set.

        Examples
        --------
        >>> import bkwaves as bk
        >>> bk.Params(gamma=0.3, v=0.01, dx=0.1).to_dict()
        {'gamma': 0.3, 'v': 0.01, 'dx': 0.1, 'beta': inf}
        """
        d = asdict(self)
        if self.units is None:
            d.pop("units")
        d.pop("friction_law")
        if self.friction_law is not None:
            d["friction"] = {"law": self.friction_law.name, **dict(self.friction_law.params)}
        return d
