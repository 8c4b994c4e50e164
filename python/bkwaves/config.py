"""Run configurations: one TOML schema for every run model (``bkwaves._models``).

Every key is checked when the file is read: unknown keys, wrong types and out-of-range
values raise :class:`bkwaves.ParameterError` with the key's path (``initial.kind``) and
the allowed values. See ``examples/`` for one file per use case.

Schema (all sections optional except those marked)::

    model = "chain" | "free_boundary" | "lattice" | "free_boundary_2d"   # required: one entry
                                               # of bkwaves._models: what it takes below
    seed = 0                                   # random initial states, [disorder], [noise]
                                               # (none given: a fresh seed is drawn when
                                               # something is random, and recorded)
    title = "..."                              # free text

    [params]    gamma, v, dx, beta              # dimensionless  (exactly one of
                (beta default inf: no backward slip, the paper's model; beta = 5.0:
                 backward slip at phi <= -11; [physical] sets beta = f_s/(f_r - f_s))
    [physical]  mass, k_c, k_p, f_static, f_kinetic, alpha, V, spacing   # these two)
                or  preset = "bristol_board" with V
                optional V_f [m/s]: velocity-weakening friction, v_f = V_f sqrt(k_p m)/(f_r - f_s)

    [friction]  law = "coulomb" (default; the laws of bk.friction.LAWS) and the law's
                parameters (dimensionless; gamma and beta here or in [params], not both)
                e.g. law = "velocity_weakening", v_f = 0.01

    [disorder]  chain: threshold, mass, loader, coupling: each a number, an array
                (one per block; coupling one per bond: n - 1 free, n + 1 fixed, n
                periodic) or {distribution = "uniform" | "normal" | "lognormal", mean,
                spread} drawn with the config's seed (bk.disorder)
                lattice: threshold, mass, loader per block, coupling_x and coupling_y
                per bond along x and y (>= 0), each also a smooth random field {mean,
                amplitude, correlation_length} (docs/lattice.md)
                free boundary: threshold only, the static threshold field s(x) on the
                grid: a number, an array (one per grid node), {distribution, mean,
                spread} drawn per node, or a smooth random field {mean, amplitude,
                correlation_length} (like initial kind "random"; lengths in metres
                with [physical]); docs/free_boundary.md, "Threshold field"

    [noise]     law = "constant" | "exponential" (phi0) | "power" (exponent) |
                "table" (u = [...], g = [...]: piecewise linear, g >= 0),
                rate; seeded by the config's seed (bk.noise, docs/noise.md).
                free boundary: spontaneous pair nucleation at Lambda(u) = rate g(u)
                (rate: Lambda at u = 1, per unit length and time; 1/(m s) with [physical]);
                chain: spontaneous slips of stuck blocks at rate g(x) each,
                x = 1 - (threshold - phi) (rate per block and unit time, 1/s with
                [physical]), kick = forward speed over the ground (m/s with [physical];
                default 0: a release)

    [speed]     (free boundary) the front-speed law as a table: u_plus = [...] (strictly
                increasing in (0, 1)), c = [...] (> 1, strictly increasing), e.g. the
                renormalised c_eff of a disordered medium; default: c = 1/sqrt(1 - u^2)
                (bk.free_boundary.speed_table, docs/free_boundary.md); free_boundary_2d
                also: curvature = D, [D_axis, D_diag] or {theta = [...], D = [...]}
                (c_n = c - D kappa) and
                [speed.diagonal] u_plus, c (the planar speed along the diagonals; the
                lattice's front shape, docs/free_boundary_2d.md)

    [domain]    blocks (chain) | length + grid (free boundary) |
                shape = [nx, ny], dy (lattice) | shape, spacing (free_boundary_2d),
                boundary (planar models: one name or [along x, along y])

    [initial]   kind = "uniform" (value) | "ramp" (start, end) |
                "random" (mean, amplitude, correlation_length) |
                "bumps" (base, slope, bumps = [{center, width, height}, ...]) |
                "file" (path: .npy or .txt with one value per node)
                velocity = 0.0   (chain only: initial forward speed of every block over
                                  the ground; 0 = all stuck)

    [[triggers]] time, block, kind = "kick" (velocity: forward speed added, default 1) |
                 "release"   (chain; lattice: block = [i, j]); free_boundary_2d:
                 time, x, y, radius (default 0): a rupture started on that disk

    [run]       t_end and/or max_events; chain: max_event_slips, max_event_duration
                (runaway bounds of one event; see docs/usage.md); step (time step /
                dx, default 0.05), integrator ("rk4" default, "midpoint": step <= 0.5),
                step_tolerance (rk4 step-size control; default none: the fixed step),
                events ("global" | "local": local events redo only a switch's
                neighbourhood; rk4 at a fixed step), as bkwaves.Chain takes them
                (docs/chain.md, "Algorithm"; docs/lattice.md, "Local events")
    [output]    path, snapshot_every (time) or snapshot_events (every k events),
                units = "native" | "dimensionless", arrivals (planar models: the
                arrival time of every node in every event or rupture, a table)

Units: with [params] everything is dimensionless (the paper's x', t', u). With [physical]
times (t_end, snapshot_every, trigger times) are in seconds, lengths (domain.length, bump
centers and widths, correlation_length) in metres and kick velocities (forward block
speed) in m/s; stresses u stay dimensionless (u = 0: kinetic level, u = 1: static
threshold). A :class:`RunConfig` always holds dimensionless values; outputs go back to
SI unless ``output.units = "dimensionless"``.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import _core, _models
from . import _validate as V
from . import friction as laws
from ._core import ParameterError
from .chain import PROPERTIES, TRIGGERS
from .disorder import DISTRIBUTIONS, draw, property_seed
from .params import Params

__all__ = ["RunConfig", "load_config", "parse_config", "initial_state"]

MODELS = _models.NAMES
BOUNDARIES = {name: _models.get(name).boundaries for name in MODELS}
INITIAL_KINDS = ("uniform", "ramp", "random", "bumps", "file")
TRIGGER_KINDS = TRIGGERS


def _err(path: str, msg: str):
    raise ParameterError(f"{path}: {msg}")


def _models_with(attr: str) -> str:
    """The models whose entry has ``attr``, in words: "the chain model only (and the
    lattice model)"."""
    names = [n for n in _models.NAMES if getattr(_models.get(n), attr)]
    rest = f" (and the {', '.join(names[1:])} model{'s' if len(names) > 2 else ''})"
    return f"the {names[0]} model only" + (rest if names[1:] else "")


def _table(d: Any, path: str) -> dict:
    if not isinstance(d, dict):
        _err(path, f"expected a table, got {V._show(d)}")
    return d


def _keys(d: dict, path: str, allowed: tuple[str, ...], required: tuple[str, ...] = ()):
    for k in d:
        if k not in allowed:
            where = f"{path}.{k}" if path else k
            _err(where, f"unknown key; valid keys here: {', '.join(allowed)}")
    for k in required:
        if k not in d:
            where = f"{path}.{k}" if path else k
            _err(where, "missing required key")


_REQUIRED = object()


def _value(d: dict, key: str, path: str, spec: V.Spec, default=_REQUIRED, **override):
    """d[key] checked against ``spec`` (range overrides allowed) with the key path in the
    message, or ``default`` when the key is absent."""
    where = f"{path}.{key}" if path else key
    if key not in d:
        if default is _REQUIRED:
            _err(where, "missing required key" + (
                f"; {spec.allowed(key)}" if spec.kind == "choice" else ""))  # fmt: skip
        return default
    if override:
        spec = V.Spec(**{**spec.__dict__, **override})
    x = d[key]
    if spec.kind in ("real", "int") and (isinstance(x, bool) or not isinstance(x, int | float)):
        kind = "a number" if spec.kind == "real" else "an integer"
        _err(where, f"expected {kind}, got {V._show(x)} ({spec.allowed(key)})")
    try:
        return spec.check(x, key)
    except ParameterError as e:
        _err(where, str(e))


_NO_BACKWARD = (
    "a backward speed needs backward slip: allowed velocity >= 0 unless params.beta is "
    "finite (the default beta = inf is the paper's model, no backward slip)"
)


def _num(d: dict, key: str, path: str, default=_REQUIRED, **rng) -> float:
    return _value(d, key, path, V.Spec(key, "real", **rng), default)


def _choice(d: dict, key: str, path: str, choices, default=_REQUIRED) -> str:
    return _value(d, key, path, V.Spec(key, "choice", choices=tuple(choices)), default)


def _cfg(d: dict, key: str, section: str, default=_REQUIRED, **override):
    """A config key checked against its entry in the parameter table ``V.CONFIG``."""
    return _value(d, key, section, V.CONFIG[section][key], default, **override)


#: Initial stress values are dimensionless (1: the static threshold); beyond this size
#: they have no meaning for the model (and overflow the outputs' conversions).
U_LIMIT = 1e6


@dataclass(frozen=True)
class Bump:
    center: float
    width: float
    height: float


@dataclass(frozen=True)
class InitialSpec:
    kind: str
    value: float = 0.0
    start: float = 0.0
    end: float = 0.0
    mean: float = 0.0
    amplitude: float = 0.0
    correlation_length: float = 1.0
    base: float = 0.0
    slope: float = 0.0
    bumps: tuple[Bump, ...] = ()
    path: str = ""
    velocity: float = 0.0


@dataclass(frozen=True)
class Trigger:
    time: float
    block: int | tuple  # a chain's block, a lattice's (i, j); free_boundary_2d: (x, y, radius)
    kind: str  # kick, release; free_boundary_2d: rupture
    velocity: float = 0.0


@dataclass(frozen=True)
class RunConfig:
    """A validated run description (frozen), built by :func:`parse_config`.

    The fields are the TOML keys (docs/usage.md lists them with their units); every
    quantity is in the paper's dimensionless units (a config given in SI through
    ``[physical]`` is converted when parsed, and ``params.units`` keeps the SI description).

    Parameters
    ----------
    model : {"chain", "free_boundary", "lattice", "free_boundary_2d"}
        The engine.
    params : bkwaves.Params
        gamma, v, dx, beta (dimensionless).
    boundary : str or tuple of str
        The boundary condition (a planar model's: (along x, along y)).
    initial : InitialSpec
        The initial state (``[initial]``).
    blocks : int, default 0
        Blocks of a chain.
    length : float, default 0
        Length of a free boundary domain (dimensionless x).
    grid : int, default 0
        Nodes of a free boundary grid.
    shape : tuple of int, default ()
        A planar model's (nx, ny): blocks or grid nodes along x and y.
    dy : float, optional
        The lattice's spacing across, sqrt(k_p/k_y) (dimensionless; None: dx).
    spacing : float, default 0
        The planar free boundary grid's node spacing h (dimensionless x).
    triggers : tuple of Trigger, default ()
        Kicks and releases (times in units of sqrt(m/k_p)).
    t_end : float, optional
        End of the run (units of sqrt(m/k_p)).
    max_events : int, optional
        End after this many events.
    max_event_slips : int, optional
        The most slips one event may take.
    max_event_duration : float, optional
        The longest an event may last (units of sqrt(m/k_p)).
    step : float, optional
        The chain's time step as a fraction of dx (in units of sqrt(m/k_p)).
    integrator : str, optional
        The chain's integrator.
    step_tolerance : float, optional
        Error per step of the adaptive step control.
    events : {"global", "local"}, optional
        How the chain's engine locates slips and sticks (None: the model's default).
    output_path : str, optional
        ``[output] path``.
    snapshot_every : float, optional
        Snapshot interval (units of sqrt(m/k_p)).
    snapshot_events : int, optional
        A snapshot every this many events.
    output_units : {"native", "physical"}, default "native"
        Units of the outputs.
    arrivals : bool, default False
        A planar model writes the arrivals table (``[output] arrivals``).
    seed : int, optional
        The seed of every random draw.
    title : str, default ""
        A title written into the outputs.
    disorder : tuple, default ()
        Per-block properties (``[disorder]``).
    noise : dict, optional
        The ``[noise]`` table.
    speed : dict, optional
        The free boundary's front-speed law (``[speed]``).
    base_dir : pathlib.Path, optional
        The folder relative paths are read from.

    Examples
    --------
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> cfg.model, cfg.blocks, cfg.t_end, cfg.params.gamma
    ('chain', 200, 20.0, 0.3)
    """

    model: str
    params: Params
    boundary: str | tuple[str, str]  # a planar model's: (along x, along y)
    initial: InitialSpec
    blocks: int = 0
    length: float = 0.0
    grid: int = 0
    shape: tuple[int, int] | tuple = ()  # a planar model's (nx, ny)
    dy: float | None = None  # the lattice's spacing across (None: dx)
    spacing: float = 0.0  # the planar free boundary's grid spacing
    triggers: tuple[Trigger, ...] = ()
    t_end: float | None = None
    max_events: int | None = None
    max_event_slips: int | None = None
    max_event_duration: float | None = None
    step: float | None = None
    integrator: str | None = None
    step_tolerance: float | None = None
    events: str | None = None
    output_path: str | None = None
    snapshot_every: float | None = None
    snapshot_events: int | None = None
    output_units: str = "native"
    arrivals: bool = False
    seed: int | None = None
    title: str = ""
    disorder: tuple = ()
    noise: dict | None = None
    speed: dict | None = None
    base_dir: Path | None = field(default=None, compare=False, repr=False)

    @property
    def physical(self) -> bool:
        """Whether the config carries an SI description (``[physical]``)."""
        return self.params.units is not None

    @property
    def random(self) -> bool:
        """Whether the run draws random numbers (a random initial state, drawn [disorder],
        [noise])."""
        drawn = any(isinstance(spec, dict) for _, spec in self.disorder)
        return self.initial.kind == "random" or drawn or self.noise is not None

    def seeded(self) -> RunConfig:
        """This config with a seed: its own, or for a random run without one a fresh seed
        drawn from the operating system's entropy (recorded in the outputs, so the run can
        be repeated).

        Returns
        -------
        RunConfig
            This config, or a copy with a seed.

        Examples
        --------
        >>> import bkwaves as bk
        >>> cfg = bk.config.parse_config({
        ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
        ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
        ...     "run": {"t_end": 20.0}})
        >>> cfg.seeded() is cfg                 # nothing random: no seed needed
        True
        """
        if self.seed is not None or not self.random:
            return self
        import dataclasses

        fresh = int(np.random.SeedSequence().entropy % (2**63 - 1))
        return dataclasses.replace(self, seed=fresh)

    def to_dict(self) -> dict:
        """This config as a document of the TOML schema, in the paper's dimensionless
        units (``input_units = "dimensionless"`` when the config carries an SI
        description in [physical]): ``RunConfig.from_dict(cfg.to_dict()) == cfg``
        exactly. A config changed in code (``dataclasses.replace``) writes what it holds.

        Returns
        -------
        dict
            The document (dimensionless values).

        Examples
        --------
        >>> import bkwaves as bk
        >>> cfg = bk.config.parse_config({
        ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
        ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
        ...     "run": {"t_end": 20.0}})
        >>> cfg.to_dict()["params"]
        {'gamma': 0.3, 'v': 0.0, 'dx': 0.1, 'beta': inf}
        >>> bk.config.RunConfig.from_dict(cfg.to_dict()) == cfg
        True
        """
        return _to_doc(self)

    @classmethod
    def from_dict(cls, doc: dict, *, base_dir: Path | None = None) -> RunConfig:
        """Validate a document of the TOML schema (see :meth:`to_dict`).

        Parameters
        ----------
        doc : dict
            The document.
        base_dir : pathlib.Path, optional
            The folder relative paths are read from.

        Returns
        -------
        RunConfig
            The validated config (:func:`parse_config`).

        Examples
        --------
        >>> import bkwaves as bk
        >>> doc = {"model": "free_boundary", "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
        ...        "domain": {"length": 10.0, "grid": 11},
        ...        "initial": {"kind": "uniform", "value": 0.5}, "run": {"t_end": 10.0}}
        >>> bk.config.RunConfig.from_dict(doc).grid
        11
        """
        return parse_config(doc, base_dir=base_dir)

    def chain_integration(self) -> dict:
        """The chain's integration settings, bkwaves.Chain's ``step``, ``integrator`` and
        ``step_tolerance``, with the defaults (DEFAULT_STEP, rk4, none) for keys not given.

        Returns
        -------
        dict
            ``step`` (a fraction of dx), ``integrator`` and ``step_tolerance``.

        Examples
        --------
        >>> import bkwaves as bk
        >>> cfg = bk.config.parse_config({
        ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
        ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
        ...     "run": {"t_end": 20.0}})
        >>> cfg.chain_integration()
        {'step': 0.05, 'integrator': 'rk4', 'step_tolerance': None, 'events': None}
        """
        from .chain import DEFAULT_STEP, INTEGRATORS

        return {
            "step": DEFAULT_STEP if self.step is None else self.step,
            "integrator": INTEGRATORS[0] if self.integrator is None else self.integrator,
            "step_tolerance": self.step_tolerance,
            "events": self.events,
        }

    def x(self) -> np.ndarray:
        """Node positions in dimensionless units (blocks at i*dx for the chain).

        Returns
        -------
        numpy.ndarray
            The positions (dimensionless x).

        Examples
        --------
        >>> import bkwaves as bk
        >>> cfg = bk.config.parse_config({
        ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
        ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
        ...     "run": {"t_end": 20.0}})
        >>> cfg.x()[:3], len(cfg.x())
        (array([0. , 0.1, 0.2]), 200)
        """
        return _models.get(self.model).x(self)


def _friction(doc: dict) -> tuple[laws.Law, dict]:
    """The [friction] table: the law and its parameters; those that are Params fields
    (gamma, beta) come back separately, to go to Params."""
    t = _table(doc.get("friction", {}), "friction")
    name = _choice(t, "law", "friction", tuple(laws.LAWS), laws.DEFAULT)
    info = laws.LAWS[name]
    _keys(t, "friction", ("law", *(p.name for p in info.params)))
    own, shared = {}, {}
    for k, x in t.items():
        if k == "law":
            continue
        if isinstance(x, bool) or not isinstance(x, int | float):
            _err(f"friction.{k}", f"expected a number, got {x!r}")
        try:
            _core.friction_resolve(name, {k: float(x)}, partial=True)
        except ParameterError as e:
            _err(f"friction.{k}", str(e))
        (shared if k in Params.__dataclass_fields__ else own)[k] = float(x)
    for p in info.params:
        if p.required and p.name not in t and p.name not in Params.__dataclass_fields__:
            _err(f"friction.{p.name}", f"missing required key of law {name}")
    return laws.Law(name, tuple(own.items())), shared


def _params(doc: dict) -> Params:
    has_p, has_phys = "params" in doc, "physical" in doc
    if has_p == has_phys:
        _err("params", "give exactly one of [params] (dimensionless) or [physical] (SI)")
    law, shared = _friction(doc)
    if has_phys and shared:
        k = next(iter(shared))
        _err(f"friction.{k}", "set by [physical] (alpha, f_static, f_kinetic); remove it here")
    if has_p:
        t = _table(doc["params"], "params")
        _keys(t, "params", tuple(V.PARAMS), ("v", "dx"))
        for k in shared:
            if k in t:
                _err(f"friction.{k}", f"given in [params] too; give {k} in one place")
        if "gamma" not in t and "gamma" not in shared:
            _err("params.gamma", "missing required key (or give it in [friction])")
        vals = {k: _value(t, k, "params", V.PARAMS[k]) for k in t}
        try:
            return Params(**vals, **shared, friction_law=law if "friction" in doc else None)
        except ParameterError as e:
            _err("params", str(e))
    t = _table(doc["physical"], "physical")
    if "preset" in t:
        _keys(t, "physical", ("preset", "V"), ("preset", "V"))
        _value(t, "preset", "physical", V.Spec("preset", "choice", choices=("bristol_board",)))
        from .presets import bristol_board

        p = bristol_board(V=_value(t, "V", "physical", V.PHYSICAL["V"]))
    else:
        names = tuple(V.PHYSICAL)
        _keys(t, "physical", (*names, "preset", "V_f"))
        for k in names:
            if k not in t:
                _err(
                    f"physical.{k}",
                    f"missing required key; give all of {', '.join(names)}, or "
                    'preset = "bristol_board" with V',
                )
        vals = {k: _value(t, k, "physical", V.PHYSICAL[k]) for k in names}
        if "V_f" in t:
            if "friction" in doc:
                _err("physical.V_f", "selects velocity_weakening; remove the [friction] table")
            vals["V_f"] = t["V_f"]  # checked by Params.from_physical (V_f > 0)
        try:
            p = Params.from_physical(**vals)
        except ParameterError as e:
            _err("physical", str(e))
    if "friction" not in doc:
        return p
    try:
        return dataclasses.replace(p, friction_law=law)
    except ParameterError as e:
        _err("friction", str(e))


def _disorder(doc: dict, model: _models.Model) -> tuple:
    """The [disorder] table as ((property, spec), ...): spec a float, a tuple of
    floats or a dict {distribution, mean, spread} (or, where the model has them, a
    smooth random field {mean, amplitude, correlation_length})."""
    if "disorder" not in doc:
        return ()
    t = _table(doc["disorder"], "disorder")
    _keys(t, "disorder", model.disorder_keys)
    out = []
    for k, x in t.items():
        q = f"disorder.{k}"
        if isinstance(x, dict) and model.correlated_disorder and "correlation_length" in x:
            _keys(x, q, ("mean", "amplitude", "correlation_length"), ("amplitude",))
            spec = {
                "mean": _num(x, "mean", q, 1.0, lo=0.0, lo_open=True),
                "amplitude": _num(x, "amplitude", q, lo=0.0),
                "correlation_length": _num(x, "correlation_length", q, lo=0.0, lo_open=True),
            }
            if spec["amplitude"] >= spec["mean"]:
                _err(
                    f"{q}.amplitude",
                    f"invalid amplitude = {spec['amplitude']}: allowed 0 <= amplitude < mean "
                    f"= {spec['mean']} (a positive threshold)",
                )
            out.append((k, spec))
        elif isinstance(x, dict):
            _keys(x, q, ("distribution", "mean", "spread"), ("distribution", "spread"))
            spec = {
                "distribution": _choice(x, "distribution", q, tuple(DISTRIBUTIONS)),
                "mean": _num(x, "mean", q, 1.0, lo=0.0, lo_open=True),
                "spread": _num(x, "spread", q, lo=0.0),
            }
            out.append((k, spec))
        elif isinstance(x, list):
            if not all(isinstance(y, int | float) and not isinstance(y, bool) for y in x):
                _err(q, "expected an array of numbers")
            out.append((k, tuple(float(y) for y in x)))
        elif isinstance(x, int | float) and not isinstance(x, bool):
            zero_ok = k in model.disorder_zero_ok
            out.append((k, _num(t, k, "disorder", lo=0.0, lo_open=not zero_ok)))
        else:
            _err(
                q,
                f"expected a number, an array or a table {{distribution, mean, spread}}, got {x!r}",
            )
    return tuple(out)


def _noise(doc: dict, model: _models.Model, ts: float, ls: float, vs: float) -> dict | None:
    """The [noise] table, dimensionless (``model.scale_noise``). Free boundary: rate per
    unit x' and t' (an SI rate, 1/(m s), times ls ts); chain: rate per block and unit t'
    (1/s times ts) and the kick speed in u_t units (m/s divided by vs)."""
    if "noise" not in doc:
        return None
    from . import noise as _noise_laws

    noise = _noise_laws.check_noise(_table(doc["noise"], "noise"), model=model.noise_kind)
    return model.scale_noise(noise, ts, ls, vs)


def _speed_table_keys(t: dict, path: str, required: bool) -> dict | None:
    """The {u_plus, c} arrays of a [speed] table (or None when both are absent and not
    required), validated."""
    if not required and "u_plus" not in t and "c" not in t:
        return None
    for k in ("u_plus", "c"):
        if k not in t:
            _err(f"{path}.{k}", "missing required key")
        x = t[k]
        if not (
            isinstance(x, list)
            and x
            and all(isinstance(y, int | float) and not isinstance(y, bool) for y in x)
        ):
            _err(f"{path}.{k}", f"expected a non-empty array of numbers, got {V._show(x)}")
    from .free_boundary import speed_table

    return speed_table({"u_plus": t["u_plus"], "c": t["c"]})


def _speed(doc: dict, model: _models.Model, ls: float = 1.0) -> dict | None:
    """The [speed] table (free boundary): the front-speed law {u_plus, c}, validated; for
    the plane also the lattice's front shape, curvature = D, [D_axis, D_diag] or a table
    {theta, D} over directions (D a length:
    metres with [physical], divided here by the length unit ls) and [speed.diagonal]
    {u_plus, c} (then u_plus and c may be absent: the exact law)."""
    if "speed" not in doc:
        return None
    if not model.speed_law:
        _err("speed", f"a front-speed law applies to {_models_with('speed_law')}")
    t = _table(doc["speed"], "speed")
    shape = getattr(model, "front_shape", False)
    extra = ("curvature", "diagonal") if shape else ()
    _keys(t, "speed", ("u_plus", "c", *extra))
    out = _speed_table_keys(t, "speed", required=not any(k in t for k in extra))
    out = dict(out) if out is not None else {}
    if "curvature" in t:
        from .free_boundary_2d import _curvature

        try:
            curv = _curvature(t["curvature"])
            if isinstance(curv, dict):
                curv["D"] = [d / ls for d in curv["D"]]
                out["curvature"] = curv
            else:
                out["curvature"] = [d / ls for d in curv]
        except V.ParameterError as e:
            _err("speed.curvature", str(e))
    if "diagonal" in t:
        d = _table(t["diagonal"], "speed.diagonal")
        _keys(d, "speed.diagonal", ("u_plus", "c"), ("u_plus", "c"))
        out["diagonal"] = _speed_table_keys(d, "speed.diagonal", required=True)
    return out


def _scaled_disorder(disorder: tuple, ls: float) -> tuple:
    """[disorder] with the correlation lengths of smooth fields in the paper's units."""
    return tuple(
        (k, {**x, "correlation_length": x["correlation_length"] / ls})
        if isinstance(x, dict) and "correlation_length" in x
        else (k, x)
        for k, x in disorder
    )


def threshold_field(cfg: RunConfig, x: np.ndarray | None = None) -> np.ndarray | None:
    """The static threshold at the grid nodes of a free boundary config (None: uniform 1),
    from [disorder] threshold (drawn ones with the config's seed, the threshold's stream)."""
    spec = dict(cfg.disorder).get("threshold")
    if not _models.get(cfg.model).threshold_field or spec is None:
        return None
    x = cfg.x() if x is None else x
    n = len(x)
    if isinstance(spec, dict) and "correlation_length" in spec:
        rng = np.random.default_rng(property_seed(cfg.seed, "threshold"))
        smooth = _smooth_random(x, spec["correlation_length"], rng, cfg.boundary == "periodic")
        return spec["mean"] + spec["amplitude"] * smooth
    if isinstance(spec, dict):
        try:
            return draw(
                spec["distribution"],
                n,
                mean=spec["mean"],
                spread=spec["spread"],
                seed=property_seed(cfg.seed, "threshold"),
            )
        except ParameterError as e:
            _err("disorder.threshold", str(e))
    if isinstance(spec, tuple):
        if len(spec) != n:
            _err("disorder.threshold", f"{len(spec)} values; expected {n} (one per grid node)")
        return np.array(spec)
    return np.full(n, float(spec))


def disorder_arrays(cfg: RunConfig) -> dict:
    """The per-block properties of a chain config: {property: scalar, array or None}
    (drawn ones with the config's seed, each property from its own stream)."""
    n = cfg.blocks
    out = dict.fromkeys(PROPERTIES)
    bonds = {"free": n - 1, "fixed": n + 1, "periodic": n}.get(cfg.boundary, n)
    for k, spec in cfg.disorder:
        size = bonds if k == "coupling" else n
        if isinstance(spec, dict):
            try:
                out[k] = draw(
                    spec["distribution"],
                    size,
                    mean=spec["mean"],
                    spread=spec["spread"],
                    seed=property_seed(cfg.seed, k),
                )
            except ParameterError as e:
                _err(f"disorder.{k}", str(e))
        elif isinstance(spec, tuple):
            if len(spec) != size:
                _err(f"disorder.{k}", f"{len(spec)} values; expected {size}")
            out[k] = np.array(spec)
        else:
            out[k] = spec
    return out


def _u(t: dict, key: str, path: str, default=_REQUIRED) -> float:
    """A stress value of the initial state (dimensionless, |u| <= U_LIMIT)."""
    return _num(t, key, path, default, lo=-U_LIMIT, hi=U_LIMIT)


def _initial(doc: dict, model: _models.Model) -> InitialSpec:
    p = "initial"
    t = _table(doc.get("initial", {"kind": "uniform", "value": 0.0}), p)
    kind = _value(t, "kind", p, V.Spec("kind", "choice", choices=model.initial_kinds))
    common = ("kind", "velocity") if model.initial_velocity else ("kind",)
    velocity = _num(t, "velocity", p, 0.0, lo=-U_LIMIT, hi=U_LIMIT) if common[1:] else 0.0
    if kind == "uniform":
        _keys(t, p, (*common, "value"), ("value",))
        return InitialSpec(kind, value=_u(t, "value", p), velocity=velocity)
    if kind == "ramp":
        _keys(t, p, (*common, "start", "end"), ("start", "end"))
        return InitialSpec(kind, start=_u(t, "start", p), end=_u(t, "end", p), velocity=velocity)
    if kind == "random":
        _keys(t, p, (*common, "mean", "amplitude", "correlation_length"), ("mean", "amplitude"))
        return InitialSpec(
            kind,
            mean=_u(t, "mean", p),
            amplitude=_num(t, "amplitude", p, lo=0.0, hi=U_LIMIT),
            correlation_length=_num(t, "correlation_length", p, 1.0, lo=0.0, lo_open=True),
            velocity=velocity,
        )
    if kind == "bumps":
        _keys(t, p, (*common, "base", "slope", "bumps"), ("bumps",))
        raw = t["bumps"]
        if not isinstance(raw, list) or not raw:
            _err(f"{p}.bumps", "expected a non-empty array of tables {center, width, height}")
        bumps = []
        for i, b in enumerate(raw):
            q = f"{p}.bumps[{i}]"
            b = _table(b, q)
            _keys(b, q, ("center", "width", "height"), ("center", "width", "height"))
            bumps.append(
                Bump(
                    _num(b, "center", q),
                    _num(b, "width", q, lo=0.0, lo_open=True),
                    _u(b, "height", q),
                )
            )
        return InitialSpec(
            kind,
            base=_u(t, "base", p, 0.0),
            slope=_num(t, "slope", p, 0.0),
            bumps=tuple(bumps),
            velocity=velocity,
        )
    _keys(t, p, (*common, "path"), ("path",))
    path = t["path"]
    if not isinstance(path, str) or not path or "\x00" in path:
        _err(f"{p}.path", f"expected a file name, got {V._show(path)}")
    return InitialSpec(kind, path=path, velocity=velocity)


TOP_KEYS = (
    "model",
    "seed",
    "title",
    "params",
    "physical",
    "friction",
    "disorder",
    "noise",
    "speed",
    "domain",
    "initial",
    "triggers",
    "run",
    "output",
    "input_units",
)


def parse_config(doc: dict, *, base_dir: Path | None = None) -> RunConfig:
    """Validate a parsed TOML document and build a :class:`RunConfig`. Every key is
    checked against the parameter tables of ``bkwaves._validate`` (type, range),
    and so are the sizes that follow from them (:func:`bkwaves.limits.check_sizes`),
    before any work.

    Parameters
    ----------
    doc : dict
        The document (docs/usage.md lists the keys, their units and allowed values).
    base_dir : pathlib.Path, optional
        The folder relative paths are read from.

    Returns
    -------
    RunConfig
        The validated config, in the paper's dimensionless units.

    Raises
    ------
    bkwaves.ParameterError
        An unknown key (the message lists the valid ones) or a value out of range.

    Examples
    --------
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> cfg.triggers[0].kind, cfg.triggers[0].velocity
    ('kick', 2.0)
    >>> bk.config.parse_config({**cfg.to_dict(), "params": {"gamma": 0.3, "gama": 1.0}})
    Traceback (most recent call last):
    ...
    bkwaves._core.ParameterError: params.gama: unknown key; valid keys here: gamma, v, dx, beta
    """
    doc = _table(doc, "(top level)")
    _keys(doc, "", TOP_KEYS, ("model",))
    model = _cfg(doc, "model", "")
    entry = _models.get(model)
    seed = _cfg(doc, "seed", "", None)
    title = _cfg(doc, "title", "", "")
    params = _params(doc)
    if entry.coulomb_only:
        for where in ("params", "friction"):
            t = doc.get(where)
            if isinstance(t, dict) and "beta" in t and params.beta != math.inf:
                _err(
                    f"{where}.beta",
                    f"invalid beta = {t['beta']}: the {model} model has no backward slip "
                    "(its fronts leave u_-(u_+) behind and nothing slips backward): allowed "
                    "beta = inf or no beta (a finite beta applies to the chain and lattice)",
                )
    if entry.coulomb_only and params.law.name != "coulomb":
        phys = doc.get("physical")
        key = "physical.V_f" if isinstance(phys, dict) and "V_f" in phys else "friction.law"
        _err(
            key,
            f"friction law {params.law.name!r}: the free boundary model is the continuum "
            "limit of the chain with Coulomb friction (its front speed c(u_+) is the Coulomb "
            'tip problem\'s); other laws run in the chain model (model = "chain")',
        )

    d = _table(doc.get("domain", {}), "domain")
    _keys(d, "domain", entry.domain_keys, entry.domain_required)
    domain = entry.parse_domain(d, lambda t, key, *default: _cfg(t, key, "domain", *default))
    if "boundary" not in domain:
        domain["boundary"] = _cfg(d, "boundary", "domain", "free", choices=entry.boundaries)

    initial = _initial(doc, entry)
    if initial.kind == "file" and base_dir is not None and not Path(initial.path).is_absolute():
        initial = InitialSpec("file", path=str(base_dir / initial.path), velocity=initial.velocity)

    triggers = []
    raw = doc.get("triggers", [])
    if not entry.triggers and raw:
        _err("triggers", f"triggers apply to {_models_with('triggers')}")
    if not isinstance(raw, list):
        _err("triggers", "expected an array of tables [[triggers]]")
    for i, tr in enumerate(raw):
        q = f"triggers[{i}]"
        tr = _table(tr, q)
        own = entry.parse_trigger(tr, q, domain)
        if own is not None:
            triggers.append(own)
            continue
        kind = _value(tr, "kind", q, V.CONFIG["triggers"]["kind"])
        places = entry.trigger_places
        allowed = ("time", *places, "kind", *(("velocity",) if kind == "kick" else ()))
        _keys(tr, q, allowed, places if len(places) == 1 else ())
        block = entry.trigger_block(tr, q, domain)
        triggers.append(
            Trigger(
                time=_value(tr, "time", q, V.CONFIG["triggers"]["time"], 0.0),
                block=block,
                kind=kind,
                velocity=(
                    _value(
                        tr,
                        "velocity",
                        q,
                        V.CONFIG["triggers"]["velocity"],
                        1.0,
                        lo=-U_LIMIT,
                        hi=U_LIMIT,
                    )  # fmt: skip
                    if kind == "kick"
                    else 0.0
                ),
            )
        )
        if triggers[-1].velocity < 0 and not params.backward_slip:
            _err(f"{q}.velocity", _NO_BACKWARD)
    if entry.initial_velocity and initial.velocity < 0 and not params.backward_slip:
        _err("initial.velocity", _NO_BACKWARD)

    r = _table(doc.get("run", {}), "run")
    _keys(r, "run", tuple(V.CONFIG["run"]))
    t_end = _cfg(r, "t_end", "run", None)
    max_events = _cfg(r, "max_events", "run", None)
    max_event_slips = _cfg(r, "max_event_slips", "run", None)
    max_event_duration = _cfg(r, "max_event_duration", "run", None)
    step = _cfg(r, "step", "run", None)
    integrator = _cfg(r, "integrator", "run", None)
    step_tolerance = _cfg(r, "step_tolerance", "run", None)
    events = _cfg(r, "events", "run", None)
    if t_end is None and max_events is None:
        _err("run", "give t_end, max_events or both")
    for key in CHAIN_RUN_KEYS:
        if key in r and not entry.chain_run_keys:
            _err(f"run.{key}", f"applies to {_models_with('chain_run_keys')}")
    _check_integration(step, integrator, step_tolerance, events)

    o = _table(doc.get("output", {}), "output")
    _keys(o, "output", tuple(V.CONFIG["output"]))
    if "snapshot_every" in o and "snapshot_events" in o:
        _err("output", "give at most one of snapshot_every or snapshot_events")
    if "arrivals" in o and not entry.arrivals:
        _err("output.arrivals", f"applies to {_models_with('arrivals')}")
    out_path = _cfg(o, "path", "output", None)
    if out_path is not None and not out_path:
        _err("output.path", "expected a file name, got ''")
    if out_path is not None and base_dir is not None and not Path(out_path).is_absolute():
        # like initial.path (and a sweep's output.path): relative to the config's folder
        out_path = str(base_dir / out_path)
    # physical configs: convert times and lengths to the paper's units (unless the
    # document says its values are dimensionless already, as RunConfig.to_dict writes)
    input_units = _cfg(
        doc, "input_units", "", "SI" if params.units is not None else "dimensionless"
    )
    if params.units is None and input_units != "dimensionless":
        _err("input_units", "'SI' needs a [physical] table; with [params] values are dimensionless")
    ts = ls = vs = 1.0
    if params.units is not None and input_units == "SI":
        ts, ls, vs = params.units.time_scale, params.units.length_scale, params.units.velocity_scale
        initial = InitialSpec(
            **{
                **initial.__dict__,
                "correlation_length": (
                    initial.correlation_length / ls
                    if initial.kind == "random"
                    else initial.correlation_length
                ),
                "bumps": tuple(Bump(b.center / ls, b.width / ls, b.height) for b in initial.bumps),
                "velocity": _speed_units(initial.velocity, vs, "initial.velocity"),
            }
        )
        triggers = [
            Trigger(
                t.time / ts,
                entry.scale_trigger_place(t.block, ls),
                t.kind,
                _speed_units(t.velocity, vs, f"triggers[{i}].velocity"),
            )
            for i, t in enumerate(triggers)
        ]
        domain = entry.scale_domain(domain, ls)
        t_end = None if t_end is None else t_end / ts
        if max_event_duration is not None:
            max_event_duration /= ts
    snapshot_every = _cfg(o, "snapshot_every", "output", None)
    cfg = RunConfig(
        model=model,
        params=params,
        initial=initial,
        **domain,
        triggers=tuple(triggers),
        t_end=t_end,
        max_events=max_events,
        max_event_slips=max_event_slips,
        max_event_duration=max_event_duration,
        step=step,
        integrator=integrator,
        step_tolerance=step_tolerance,
        events=events,
        output_path=out_path,
        snapshot_every=None if snapshot_every is None else snapshot_every / ts,
        snapshot_events=_cfg(o, "snapshot_events", "output", None),
        output_units=_cfg(o, "units", "output", "native"),
        arrivals=_cfg(o, "arrivals", "output", False),
        seed=seed,
        title=title,
        disorder=_scaled_disorder(_disorder(doc, entry), ls),
        noise=_noise(doc, entry, ts, ls, vs),
        speed=_speed(doc, entry, ls),
        base_dir=base_dir,
    )
    # a random config without a seed gets a fresh one now: the drawn properties checked
    # here are the ones the run uses, and cfg.to_dict() records the seed
    cfg = cfg.seeded()
    from .limits import check_memory

    # (before any field of the domain's size is drawn)
    check_memory(entry.size_key, model, entry.nodes(cfg), entry.size_text(cfg))
    entry.check_keys(cfg)
    _check_field_lengths(cfg)  # (before a field is drawn: its size follows from them)
    arrays = entry.property_arrays(cfg)
    for k, a in arrays.items() if cfg.disorder else ():
        if a is not None:
            a = np.atleast_1d(np.asarray(a, dtype=float)).ravel()
            zero_ok = k in entry.disorder_zero_ok
            bad = np.flatnonzero(~(np.isfinite(a) & ((a >= 0) if zero_ok else (a > 0))))
            if bad.size:
                i = int(bad[0])
                rel = ">=" if zero_ok else ">"
                _err(f"disorder.{k}[{i}]", f"invalid value {a[i]}: allowed {k} {rel} 0")
    _check_derived(cfg)
    from .limits import check_sizes

    check_sizes(cfg)
    return cfg


#: The largest bound on the midpoint iteration's contraction factor the engine accepts
#: (the core's MIDPOINT_CONTRACTION: its 200 passes then reach round-off).
MIDPOINT_CONTRACTION = _models.chain.MIDPOINT_CONTRACTION

#: [run] keys of the chain model only.
CHAIN_RUN_KEYS = (
    "max_event_slips",
    "max_event_duration",
    "step",
    "integrator",
    "step_tolerance",
    "events",
)


def _speed_units(value: float, scale: float, key: str) -> float:
    """A block speed given in m/s as the chain's u_t units (value / scale), within the
    engine's range |u_t| <= U_LIMIT; else an error naming ``key`` with both values."""
    x = value / scale
    if not abs(x) <= U_LIMIT:
        _err(
            key,
            f"invalid {key.rsplit('.', 1)[-1]} = {value:.6g} m/s: that is {x:.6g} in the "
            f"chain's speed units ({scale:.6g} m/s each), beyond the engine's |u_t| <= "
            f"{U_LIMIT:g}: allowed |{key.rsplit('.', 1)[-1]}| <= {U_LIMIT * scale:.6g} m/s",
        )
    return x


def _check_integration(step, integrator, step_tolerance, events=None) -> None:
    """run.step, run.integrator, run.step_tolerance and run.events together, as
    bkwaves.Chain checks them: the midpoint rule takes steps up to MIDPOINT_MAX_STEP and
    no step-size control; local events need rk4 at a fixed step."""
    from .chain import MIDPOINT_MAX_STEP

    if events == "local" and (integrator == "midpoint" or step_tolerance is not None):
        why = (
            "run.integrator = 'midpoint'"
            if integrator == "midpoint"
            else f"run.step_tolerance = {step_tolerance}"
        )
        _err(
            "run.events",
            f"invalid events = 'local' with {why}: local events need the rk4 integrator at "
            "a fixed step; give events = 'global' (or leave it out)",
        )
    if integrator != "midpoint":
        return
    if step is not None and step > MIDPOINT_MAX_STEP:
        _err(
            "run.step",
            f"invalid step = {step}: allowed 0 < step <= {MIDPOINT_MAX_STEP} with "
            "run.integrator = 'midpoint' (its fixed-point iteration must contract)",
        )
    if step_tolerance is not None:
        _err(
            "run.step_tolerance",
            f"invalid step_tolerance = {step_tolerance}: step-size control is for "
            "run.integrator = 'rk4' only; with 'midpoint' give no step_tolerance "
            "(the fixed step)",
        )


#: The longest correlation length of a smooth random field, in domain lengths: beyond it
#: the field is a constant plus a slope (its filter pads the domain by 6 lengths).
MAX_CORRELATION_DOMAINS = 100.0


def _check_field_lengths(cfg: RunConfig) -> None:
    """The correlation lengths of smooth random fields: at most MAX_CORRELATION_DOMAINS
    times the domain (a threshold field of correlation_length 1e8 allocated 8.9 GiB,
    1e300 overflowed inside numpy)."""
    span = _models.get(cfg.model).span(cfg)
    fields = [("initial.correlation_length", cfg.initial.correlation_length)]
    fields = fields if cfg.initial.kind == "random" else []
    for k, spec in cfg.disorder:
        if isinstance(spec, dict) and "correlation_length" in spec:
            fields.append((f"disorder.{k}.correlation_length", spec["correlation_length"]))
    for key, corr in fields:
        if not corr <= MAX_CORRELATION_DOMAINS * span:
            _err(
                key,
                f"invalid correlation_length = {corr:.6g}: allowed 0 < correlation_length <= "
                f"{MAX_CORRELATION_DOMAINS:g} x the domain = {MAX_CORRELATION_DOMAINS * span:.6g} "
                "length units (beyond it the field is a constant plus a slope)",
            )


def _check_derived(cfg: RunConfig) -> None:
    """Quantities derived from several keys: finite, and meaningful for the model."""
    p = cfg.params
    entry = _models.get(cfg.model)
    if cfg.physical:
        u = p.units
        ls, ts = u.length_scale, u.time_scale
        span = entry.physical_span(cfg) * ls
        if not math.isfinite(span):
            _err("physical.spacing", f"the {cfg.model} spans {span} m: positions overflow")
        for key, value in (("run.t_end", cfg.t_end), ("output.snapshot_every", cfg.snapshot_every)):
            if value is not None and not (math.isfinite(value) and value > 0):
                _err(key, f"is {value} time units sqrt(m/k_p) = {ts:.3g} s: out of range")
        for key, value in entry.physical_lengths(cfg):
            if not (math.isfinite(value) and value > 0):
                _err(key, f"is {value} length units: out of range")
    entry.check(cfg)


def _to_doc(cfg: RunConfig) -> dict:
    p = cfg.params
    doc: dict = {"model": cfg.model}
    if cfg.seed is not None:
        doc["seed"] = cfg.seed
    if cfg.title:
        doc["title"] = cfg.title
    if p.units is not None:
        doc["input_units"] = "dimensionless"
        doc["physical"] = dict(p.units.__dict__)
    else:
        doc["params"] = {k: v for k, v in p.to_dict().items() if k not in ("units", "friction")}
    if p.friction_law is not None:
        doc["friction"] = {"law": p.friction_law.name, **dict(p.friction_law.params)}
    if cfg.noise is not None:
        doc["noise"] = dict(cfg.noise)
    if cfg.speed is not None:
        doc["speed"] = {
            k: {q: list(w) for q, w in v.items()} if isinstance(v, dict) else list(v)
            for k, v in cfg.speed.items()
        }
    if cfg.disorder:
        doc["disorder"] = {k: list(x) if isinstance(x, tuple) else x for k, x in cfg.disorder}
    doc["domain"] = _models.get(cfg.model).domain_doc(cfg)
    s = cfg.initial
    ini: dict = {"kind": s.kind}
    if s.kind == "uniform":
        ini["value"] = s.value
    elif s.kind == "ramp":
        ini.update(start=s.start, end=s.end)
    elif s.kind == "random":
        ini.update(mean=s.mean, amplitude=s.amplitude, correlation_length=s.correlation_length)
    elif s.kind == "bumps":
        ini.update(
            base=s.base,
            slope=s.slope,
            bumps=[{"center": b.center, "width": b.width, "height": b.height} for b in s.bumps],
        )
    else:
        ini["path"] = s.path
    if _models.get(cfg.model).initial_velocity:
        ini["velocity"] = s.velocity
    doc["initial"] = ini
    if cfg.triggers:
        doc["triggers"] = [
            {"time": t.time, **_models.get(cfg.model).trigger_doc(t.block)}
            | ({"kind": t.kind} if t.kind in ("kick", "release") else {})
            | ({"velocity": t.velocity} if t.kind == "kick" else {})
            for t in cfg.triggers
        ]
    run = {}
    if cfg.t_end is not None:
        run["t_end"] = cfg.t_end
    if cfg.max_events is not None:
        run["max_events"] = cfg.max_events
    if cfg.max_event_slips is not None:
        run["max_event_slips"] = cfg.max_event_slips
    if cfg.max_event_duration is not None:
        run["max_event_duration"] = cfg.max_event_duration
    for key in ("step", "integrator", "step_tolerance", "events"):
        if getattr(cfg, key) is not None:
            run[key] = getattr(cfg, key)
    doc["run"] = run
    out: dict = {"units": cfg.output_units}
    if cfg.output_path is not None:
        out["path"] = cfg.output_path
    if cfg.snapshot_every is not None:
        out["snapshot_every"] = cfg.snapshot_every
    if cfg.snapshot_events is not None:
        out["snapshot_events"] = cfg.snapshot_events
    if cfg.arrivals:
        out["arrivals"] = True
    doc["output"] = out
    return doc


def load_config(path) -> RunConfig:
    """Read and validate a TOML run configuration (UTF-8).

    Parameters
    ----------
    path : str or pathlib.Path
        The TOML file (keys, units and allowed values: docs/usage.md); relative paths in
        it are relative to its folder.

    Returns
    -------
    RunConfig
        The validated configuration, in the paper's dimensionless units.

    Raises
    ------
    bkwaves.ParameterError
        A missing file, a TOML error, an unknown key or a value out of range, named by
        its key path (``params.gama: unknown key; valid keys here: ...``).

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> path = os.path.join(tempfile.mkdtemp(), "front.toml")
    >>> with open(path, "w") as f:
    ...     _ = f.write('''
    ... model = "chain"
    ... [params]
    ... gamma = 0.3
    ... v = 0.0
    ... dx = 0.05
    ... [domain]
    ... blocks = 100
    ... [initial]
    ... kind = "uniform"
    ... value = 0.6
    ... [run]
    ... t_end = 10.0
    ... ''')
    >>> cfg = bk.config.load_config(path)
    >>> cfg.model, cfg.blocks, cfg.params.gamma
    ('chain', 100, 0.3)
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise ParameterError(f"config file not found: {path}") from None
    except OSError as e:
        raise ParameterError(f"cannot read config file {path}: {e.strerror or e}") from None
    try:
        doc = tomllib.loads(data.decode("utf-8"))
    except UnicodeDecodeError as e:
        raise ParameterError(
            f"{path}: not UTF-8 text (byte {e.start}: {data[e.start : e.start + 1]!r}); "
            "TOML files must be UTF-8"
        ) from None
    except tomllib.TOMLDecodeError as e:
        raise ParameterError(f"{path}: not valid TOML: {e}") from None
    return parse_config(doc, base_dir=path.parent)


def _read_initial_file(p: Path, n: int) -> np.ndarray:
    """One value per node from a .npy (numbers, no pickles) or a text file."""
    try:
        raw = np.load(p, allow_pickle=False) if p.suffix == ".npy" else np.loadtxt(p, ndmin=1)
    except (OSError, ValueError, UnicodeDecodeError, EOFError) as e:
        reason = getattr(e, "strerror", None) or str(e).splitlines()[0][:200]
        what = "a .npy array" if p.suffix == ".npy" else "text numbers"
        raise ParameterError(f"initial.path: cannot read {p} as {what} ({reason})") from None
    raw = np.asarray(raw)
    if raw.dtype.kind not in "iuf":
        _err("initial.path", f"{p} holds {raw.dtype} values; expected real numbers")
    u = raw.astype(float).ravel()
    if len(u) != n:
        _err("initial.path", f"{p} has {len(u)} values; the domain has {n} nodes")
    return u


def _smooth_random(x: np.ndarray, corr: float, rng: np.random.Generator, periodic: bool):
    """Zero-mean, unit-max-amplitude Gaussian random field with a Gaussian correlation of
    length ``corr``, made by filtering white noise in Fourier space."""
    n = len(x)
    span = (x[-1] - x[0]) if n > 1 else 1.0
    pad = n if periodic else n + int(math.ceil(6 * corr / max(span / max(n - 1, 1), 1e-300)))
    h = span / max(n - 1, 1)
    noise = rng.standard_normal(pad)
    k = 2 * np.pi * np.fft.rfftfreq(pad, d=h)
    field_ = np.fft.irfft(np.fft.rfft(noise) * np.exp(-0.25 * (k * corr) ** 2), n=pad)[:n]
    field_ -= field_.mean()
    m = np.max(np.abs(field_))
    return field_ / m if m > 0 else field_


def initial_state(cfg: RunConfig) -> np.ndarray:
    """The initial u at the nodes ``cfg.x()`` (dimensionless; a planar model's shaped
    (ny, nx)).

    Parameters
    ----------
    cfg : RunConfig
        The run.

    Returns
    -------
    numpy.ndarray
        u at the nodes (dimensionless; shaped (ny, nx) on a plane).

    Examples
    --------
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> bk.config.initial_state(cfg)[:3]
    array([0.6, 0.6, 0.6])
    """
    return _models.get(cfg.model).initial_state(cfg)


def initial_line(cfg: RunConfig) -> np.ndarray:
    """The initial u of a model on a line, at the nodes ``cfg.x()``."""
    x = cfg.x()
    s = cfg.initial
    if s.kind == "uniform":
        u = np.full(len(x), s.value)
    elif s.kind == "ramp":
        span = x[-1] - x[0] if len(x) > 1 else 1.0
        u = s.start + (s.end - s.start) * (x - x[0]) / span
    elif s.kind == "random":
        rng = np.random.default_rng(cfg.seed)
        u = s.mean + s.amplitude * _smooth_random(
            x, s.correlation_length, rng, cfg.boundary == "periodic"
        )
    elif s.kind == "bumps":
        u = s.base + s.slope * x
        for b in s.bumps:
            u = u + b.height * np.exp(-0.5 * ((x - b.center) / b.width) ** 2)
    else:
        u = _read_initial_file(Path(s.path), len(x))
    key = {
        "uniform": "initial.value",
        "ramp": "initial.start/end",
        "random": "initial.mean/amplitude",
        "bumps": "initial.base/slope/bumps",
        "file": "initial.path",
    }[s.kind]
    if not np.all(np.isfinite(u)) or np.max(np.abs(u)) > U_LIMIT:
        _err(key, f"the initial state has values outside |u| <= {U_LIMIT:g} (or not finite)")
    _models.get(cfg.model).check_initial(cfg, u, x, key)
    return u
