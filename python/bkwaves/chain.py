"""The discrete chain simulated event by event (paper eqs. rest, slide, slip).

A front started at the left end of a chain at rest under u = 0.6 reaches block 248
(x = 24.8) by t = 20, close to c(0.6) = 1.25 of the continuum, and leaves behind it a
stress near the App. B value u_- = -0.098 (at dx = 0.1 the chain's own is -0.094):

>>> import bkwaves as bk
>>> p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
>>> ch = bk.Chain(400, p, u0=0.6)
>>> ch = ch.kick(0, -2.0)                # start a front at the left end
>>> res = ch.run(t_end=20.0)
>>> int(res.catalog.loc[0, "last_block"])   # the catalog: one row per event (pandas)
248
>>> round(float(ch.u[100]), 3), round(bk.traveling_wave(0.6, 0.3).u_minus, 3)
(-0.094, -0.098)

Dimensionless variables (``Params``): a stuck block drifts with the loader, u_t = v; a
sliding one obeys u_tt = Lap u/dx^2 - u - 2 gamma (u_t - v) (- 2 beta when sliding
backward, u_t > v). phi = u - Lap u/dx^2: a stuck block slips forward at phi >= 1,
backward at phi <= -(1 + 2 beta); a sliding block whose u_t returns to v sticks if
-(1 + 2 beta) < phi < 1, else it goes on sliding in the direction of the force. The
default beta = inf is the paper's model: no backward slip (a block slides until its
speed over the ground returns to zero; backward kicks and releases are refused).
Boundaries: ``"free"`` (no spring beyond the ends), ``"fixed"`` (the end blocks are
joined to walls fixed to the ground: ghost u = u_wall + v t, ``fixed=(left, right)``
gives u_wall at t = 0, default: the end blocks' initial u), ``"periodic"`` (a ring).
See docs/chain.md.
"""

from __future__ import annotations

import json
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from . import _core
from . import _validate as V
from .catalog import MOMENT_SCALE, describe
from .params import Params

__all__ = [
    "BOUNDARIES",
    "DEFAULT_STEP",
    "Chain",
    "ChainResult",
    "FrontMeasurement",
    "LoadedPulse",
    "RunawayEventWarning",
    "front",
    "loaded_pulse",
    "smooth_random_stress",
]

#: Boundary conditions by name (the core's registry; the first is the default).
BOUNDARIES = tuple(b["name"] for b in _core.boundaries())
#: Integrators by name (the core's registry): classical RK4 (order 4, default) and the
#: implicit midpoint rule (order 2, energy books closed to round-off).
INTEGRATORS = tuple(m["name"] for m in _core.integrators())
#: How slips and sticks are located: the global cut (every sliding block redone up to a
#: switch; the chain's default) or local events (the switch's neighbourhood only; the
#: lattice's default where they apply).
EVENTS = ("global", "local")
#: Trigger kinds by name (the core's registry).
TRIGGERS = tuple(k["name"] for k in _core.triggers())
#: What starts a slip (the ``kind`` of slips and catalog rows): a block at its threshold,
#: the initial state, then the event sources of the core's registry.
SLIP_CAUSES = tuple(k["name"] for k in _core.slip_causes())
#: Default time step as a fraction of dx (front speeds converged to ~1e-8 at fixed dx).
DEFAULT_STEP = _core.defaults()["step"]
#: The largest step (a fraction of dx) the core takes with the midpoint integrator (its
#: fixed-point iteration contracts by about step^2 + h gamma per sweep); the core refuses
#: larger ones, and config files are checked against this (tests/test_run_keys.py).
MIDPOINT_MAX_STEP = 0.5
#: Per-block properties a chain can carry (docs/chain.md): ``coupling`` has one value per
#: bond (n - 1 free, n + 1 fixed, n periodic), the others one per block; default 1.
PROPERTIES = ("threshold", "mass", "loader", "coupling")
#: Work per engine call (steps plus sliding-block steps plus the values of the snapshots
#: taken, each about 0.1-0.25 us; ~0.25 s): Ctrl-C, SIGTERM and progress reports are
#: handled between calls, so this bounds their latency, and the snapshots one call hands
#: over (at most ~17 MB to write).
CHUNK_WORK = 1_000_000
#: Wall time per engine call in seconds (the engine checks it every few steps): with
#: CHUNK_WORK (which counts the values of the snapshots taken too), the bound on the
#: latency of Ctrl-C and SIGTERM whatever a step costs.
CHUNK_WALL = 0.25


def default_max_event_slips(n: int) -> int:
    """The runaway bound on the slips of one event: 100 slips per block on average (the
    events of examples/chain_loading.toml have at most 7), at least 10**4."""
    return max(100 * int(n), 10_000)


def default_max_event_duration(n: int, dx: float) -> float:
    """The runaway bound on the duration of one event: 100 times the time sound takes to
    cross the chain (n dx; +1 for short chains). The longest event of
    examples/chain_loading.toml lasts 2.4 crossings."""
    return 100.0 * (n * dx + 1.0)


class RunawayEventWarning(RuntimeWarning):
    """A chain run stopped because one event exceeded its slip bound (``max_event_slips``):
    the chain slides on without re-sticking (creep, steady sliding, a circling pulse)."""


def runaway_message(chain, slips_limit: int, duration_limit: float, keys=None) -> str:
    """One message naming the regime of an event that does not end."""
    keys = keys or ("max_event_slips", "max_event_duration")
    eng = chain._engine
    slips, duration = eng.open_event or (0, 0.0)
    p = chain.params
    if p.gamma >= 1.0:
        regime = f"creep (gamma = {p.gamma:g} >= 1: sliding blocks never re-stick)"
    elif chain.boundary == "periodic":
        regime = "steady sliding, or a pulse circling the ring and re-exciting reloaded blocks"
    else:
        regime = "steady sliding or creep (blocks keep sliding without re-sticking)"
    return (
        f"event {eng.events_finished} has not ended after {slips} slips and a duration of "
        f"{duration:.6g} ({keys[0]} = {slips_limit}, {keys[1]} = {duration_limit:.6g}) at "
        f"t = {chain.t:.6g}: {regime}. The run stopped there and kept everything computed; "
        f"raise {keys[0]} / {keys[1]} to go on."
    )


#: Units of the dimensionless chain variables (paper eq. dimless).
UNITS = {
    "t": "sqrt(m/k_p)",
    "x": "a sqrt(k_c/k_p)",
    "u": "(f_r - f_s)/k_p, u = -(k_p X + f_s)/(f_r - f_s)",
    "u_t": "(f_r - f_s)/sqrt(k_p m)",
    "slip": "(f_r - f_s)/k_p",
    "energy": "(f_r - f_s)^2/k_p",
}


@dataclass
class ChainResult:
    """What :meth:`Chain.run` returns. Units: ``UNITS`` (the paper's, eq. dimless).

    Attributes
    ----------
    params : bkwaves.Params
        The chain's parameters.
    t : float
        Time reached, in units of sqrt(m/k_p).
    catalog : pandas.DataFrame
        One row per event (first slip to last re-stick): t_start, t_end, duration,
        nucleation block, first/last block slipped, n_blocks, n_slips, moment (int slip
        dx = dx times the sum of the block slips, :mod:`bkwaves.catalog`), stress_drop,
        kind (what started its first slip: ``SLIP_CAUSES``, e.g. "threshold",
        "trigger"); ``catalog.attrs["units"]``.
    slips : pandas.DataFrame
        Every slip interval of every block (the slip-front trajectories): event, block,
        x, direction, t_start, t_end, u_start, u_end, slip, kind.
    snapshots : xarray.Dataset
        u(t, x) and u_t(t, x) with attrs (params, units, version, seed).
    energy : dict
        Initial and final energy, the flows and the balance residual.
    counters : dict
        The engine's work counters (steps, events, ...).
    interrupted : bool
        True when the run was stopped by Ctrl-C (everything up to then is kept).
    stop : {"time", "events", "interrupted", "long_event"}
        Why the run ended ("long_event": an event exceeded ``max_event_slips`` or
        ``max_event_duration``, see :class:`~bkwaves.chain.RunawayEventWarning`).
    wall_s : float
        Wall time of the run [s].
    seed : int or None
        The seed recorded with the chain.
    u, u_t : numpy.ndarray
        The final state (dimensionless).
    boundary : str
        The chain's boundary condition (one of ``BOUNDARIES``).

    Examples
    --------
    >>> import bkwaves as bk
    >>> res = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0).run(
    ...     t_end=20.0)
    >>> res.t, len(res.catalog), res.stop, res.u.shape
    (20.0, 1, 'time', (400,))
    """

    params: Params
    t: float
    energy: dict
    counters: dict
    interrupted: bool = False
    stop: str = "time"
    wall_s: float = 0.0
    seed: int | None = None
    u: np.ndarray = field(default=None, repr=False)
    u_t: np.ndarray = field(default=None, repr=False)
    boundary: str | None = None
    #: the builders of catalog, slips and snapshots (pandas, xarray), called on first use
    #: so that a run that reads neither does not import them (docs/benchmarks.md)
    _build: dict = field(default_factory=dict, repr=False, compare=False)
    _built: dict = field(default_factory=dict, repr=False, compare=False)

    def _get(self, name: str):
        if name not in self._built:
            self._built[name] = self._build[name]()
        return self._built[name]

    @property
    def catalog(self):
        """One row per event (pandas DataFrame; units in ``catalog.attrs["units"]``)."""
        return self._get("catalog")

    @property
    def slips(self):
        """Every slip interval of every block (pandas DataFrame)."""
        return self._get("slips")

    @property
    def snapshots(self):
        """u(t, x), u_t(t, x) at the snapshot times (xarray Dataset, with attrs)."""
        return self._get("snapshots")

    def _slips_of(self, event):
        """The slips of one event of this run (all of them for None); an event that is
        not in the catalog is a one-line ValueError naming the run's events."""
        if event is None:
            return self.slips
        ids = self.catalog["event"].to_numpy()
        if len(ids) == 0:
            V._fail("event", event, "None (this run has no events)")
        lo, hi = int(ids.min()), int(ids.max())
        k = V.integer("event", event, lo=lo, hi=hi)
        if k not in set(ids.tolist()):
            V._fail("event", event, f"one of this run's events ({lo}..{hi}) or None")
        return self.slips[self.slips["event"] == k]

    def first_slip_times(self, event: int | None = None) -> np.ndarray:
        """First slip time of every block: the slip-front trajectory x(t).

        Parameters
        ----------
        event : int, optional
            Only the slips of this event (catalog row); default: all.

        Returns
        -------
        numpy.ndarray
            One time per block (units of sqrt(m/k_p)), NaN for a block that did not slip.

        Examples
        --------
        The front's speed from its trajectory is the lattice front speed:

        >>> import bkwaves as bk
        >>> ch = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6)
        >>> t = ch.kick(0, -2.0).run(t_end=20.0).first_slip_times()
        >>> c = 0.1 * 100 / float(t[200] - t[100])          # blocks 100 to 200
        >>> round(c, 3), round(bk.front_speed(0.6, dx=0.1, gamma=0.3), 3)
        (1.234, 1.234)
        """
        n = len(self.u)
        out = np.full(n, np.nan)
        s = self._slips_of(event)
        first = s.groupby("block")["t_start"].min()
        out[first.index.to_numpy()] = first.to_numpy()
        return out


class Chain:
    """A chain of ``n`` blocks with Coulomb friction and viscous damping (Sec. II).

    Simulated event by event: stuck blocks drift with the loader exactly, sliding blocks
    obey eq. (slide), and every stick and slip is located in time. Variables are the
    paper's dimensionless ones (eq. dimless; ``UNITS``), SI through ``params.units``
    when ``params`` was built by :meth:`bkwaves.Params.from_physical`.

    Parameters
    ----------
    n : int
        Number of blocks (>= 2).
    params : bkwaves.Params
        gamma, v, dx, beta and the friction law.
    boundary : {"free", "fixed", "periodic"}
        The ends (``BOUNDARIES``): no spring beyond them, springs to walls, or a ring.
    u0 : float or array_like
        Initial stress u of every block (scalar or n values; dimensionless).
    u_t0 : float or array_like, optional
        Initial velocities du/dt (default v: all stuck; blocks with u_t != v start
        sliding).
    step : float, default 0.05
        Time step as a fraction of dx (h = step dx, in units of sqrt(m/k_p)).
    fixed : (float, float), optional
        ``"fixed"`` boundary: the walls' u at t = 0 (default: the end blocks' initial u).
    seed : int, optional
        Recorded in the outputs (use it to build u0, e.g.
        :func:`~bkwaves.chain.smooth_random_stress`); the noise generator's seed (default
        with noise: drawn at random and recorded).
    integrator : {"rk4", "midpoint"}
        ``"rk4"`` (default, error ~ step^4) or ``"midpoint"`` (error ~ step^2, energy
        balance exact to round-off).
    step_tolerance : float, optional
        Step-size control (rk4 only; default None: the fixed step): the step grows above
        ``step`` dx, up to RK4's stability limit, where the step's error indicator stays
        below it; 1e-12 matches the default step's accuracy (docs/chain.md, "Step-size
        control"). It pays where the whole chain creeps (e.g. loading runs at
        gamma = 0.45).
    events : {"global", "local"}, optional
        How slips and sticks are located (``EVENTS``). "global" (the chain's default):
        at each switch the step of every sliding block is redone up to it. "local": only
        the switching block's neighbourhood is redone (the same order in the step;
        docs/lattice.md, "Local events"); it needs the rk4 integrator at a fixed step and
        a law whose onset takes no sub-steps, and is refused otherwise (ParameterError
        naming ``events``).
    noise : dict, optional
        Spontaneous slips of stuck blocks, a ``[noise]`` table as a dict: ``law``
        ("constant", "exponential" with ``phi0``, "power" with ``exponent``, "table" with
        nodes ``u`` and values ``g``, piecewise linear in x), ``rate`` (slips per block
        and unit time at the threshold: each stuck block slips at rate g(x),
        x = 1 - (threshold - phi)), ``kick`` (forward speed over the ground; default 0:
        a release). Their slips and events have kind "noise" (docs/noise.md).
    threshold, mass, loader, coupling : float or array_like, optional
        Per-block properties (``PROPERTIES``), each a scalar or an array (one per block;
        ``coupling`` one per bond: n - 1 free, n + 1 fixed, n periodic), in units of the
        reference values of ``params``; default 1 (the paper's chain, bit for bit). See
        docs/chain.md for the equations.

    Raises
    ------
    bkwaves.ParameterError
        A parameter out of range, named with the allowed range.

    See Also
    --------
    bkwaves.chain.front : the standard front experiment.
    bkwaves.run : a run described by a config, with outputs.

    Examples
    --------
    A front through a chain at rest under u = 0.6 (v = 0), started by kicking block 0:

    >>> import bkwaves as bk
    >>> ch = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6)
    >>> res = ch.kick(0, -2.0).run(t_end=20.0)
    >>> int(res.catalog.loc[0, "last_block"]), res.stop
    (248, 'time')
    """

    def __init__(
        self,
        n: int,
        params: Params,
        boundary: str = "free",
        u0=0.0,
        u_t0=None,
        *,
        step: float = DEFAULT_STEP,
        fixed: tuple[float, float] | None = None,
        seed: int | None = None,
        integrator: str = INTEGRATORS[0],
        step_tolerance: float | None = None,
        noise: dict | None = None,
        threshold=None,
        mass=None,
        loader=None,
        coupling=None,
        events: str | None = None,
    ):
        spec = V.CHAIN
        n = spec["n"].check(n)
        from .limits import check_memory

        check_memory("n", "chain", n)
        if not isinstance(params, Params):
            V._fail("params", params, "a bkwaves.Params")
        if params.units is not None and not math.isfinite(
            (n - 1) * params.dx * params.units.length_scale
        ):
            V._fail(
                "spacing",
                params.units.spacing,
                f"a spacing for which the {n} blocks' positions are finite",
            )
        boundary = spec["boundary"].check(boundary)
        integrator = spec["integrator"].check(integrator)
        if step_tolerance is not None:
            step_tolerance = spec["step_tolerance"].check(step_tolerance)
            if integrator != "rk4":
                V._fail(
                    "step_tolerance",
                    step_tolerance,
                    f"None with integrator = {integrator!r} (step-size control is for rk4)",
                )
        self.n = int(n)
        self.params = params
        self.boundary = boundary
        from . import noise as _noise

        self.noise = None if noise is None else _noise.check_noise(noise, model="chain")
        self.seed = (
            V.seed("seed", seed) if self.noise is None else _noise.noise_seed(seed, self.noise)
        )
        self.step = spec["step"].check(step)
        u0 = _per_block("u0", u0, self.n)
        if u_t0 is not None:
            u_t0 = _per_block("u_t0", u_t0, self.n)
        if fixed is None:
            fixed = (float(u0[0]), float(u0[-1]))
        if isinstance(fixed, str | bytes) or not hasattr(fixed, "__len__") or len(fixed) != 2:
            V._fail("fixed", fixed, "a pair (left, right) of wall positions u_wall, or None")
        fixed = (V.number("fixed[0]", fixed[0]), V.number("fixed[1]", fixed[1]))
        self.fixed = fixed
        given = {"threshold": threshold, "mass": mass, "loader": loader, "coupling": coupling}
        self.properties = {k: self._property(k, x, boundary) for k, x in given.items()}
        self._engine = _core.ChainEngine(
            u0,
            params.dx,
            params.v,
            self.step,
            law=params.law.name,
            friction=params.law_values(),
            boundary=boundary,
            fixed=fixed,
            u_t0=u_t0,
            **self.properties,
            **self._geometry(),
        )
        self._engine.set_integrator(integrator)
        self.integrator = integrator
        self._engine.set_step_control(step_tolerance)
        self.step_tolerance = step_tolerance
        self._set_events(events)
        if self.noise is not None:
            params = {k: v for k, v in self.noise.items() if k not in ("law", "rate")}
            self._engine.set_noise(self.noise["law"], self.noise["rate"], self.seed, **params)
        self._e0 = sum(self._engine.energy())

    def _geometry(self) -> dict:
        """The engine's layout beyond a line of blocks (the lattice adds its shape)."""
        return {}

    #: The event location when ``events`` is not given.
    default_events = "global"

    def _set_events(self, events) -> None:
        """Choose the event location (``events``; None: ``default_events``, or "global"
        where local events cannot apply)."""
        if events is None:
            mode = self.default_events
            if mode == "local" and self._engine.local_events_unavailable is not None:
                mode = "global"
        else:
            mode = V.CHAIN["events"].check(events)
        self._engine.set_events(mode)
        self.events = mode

    def _property(self, name, value, boundary):
        """A per-block property (``coupling``: per bond) as the engine takes it."""
        bonds = {"free": self.n - 1, "fixed": self.n + 1, "periodic": self.n}.get(boundary)
        return _property(name, value, bonds if name == "coupling" else self.n)

    def integration_attrs(self) -> dict:
        """The integration settings as output attributes: step, integrator and
        step_tolerance ("none": the fixed step; NetCDF has no None).

        Returns
        -------
        dict
            ``step`` (fraction of dx), ``integrator`` and ``step_tolerance``.

        Examples
        --------
        >>> import bkwaves as bk
        >>> bk.Chain(10, bk.Params(gamma=0.3, v=0.0, dx=0.1)).integration_attrs()
        {'step': 0.05, 'integrator': 'rk4', 'step_tolerance': 'none', 'events': 'global'}
        """
        return {
            "step": self.step,
            "integrator": self.integrator,
            "step_tolerance": "none" if self.step_tolerance is None else self.step_tolerance,
            "events": self.events,
        }

    # --- checkpoints -----------------------------------------------------------------
    def _record(self) -> tuple[dict, dict]:
        """The whole state as (JSON-able meta, plain arrays): what checkpoints store."""
        from ._checkpoint import params_record

        meta = {
            "n": self.n,
            "params": params_record(self.params),
            "boundary": self.boundary,
            "fixed": list(self.fixed),
            "step": self.step,
            "integrator": self.integrator,
            "step_tolerance": self.step_tolerance,
            "events": self.events,
            "seed": self.seed,
            "noise": self.noise,
            "e0": self._e0,
        }
        arrays = {"engine": np.frombuffer(self._engine.checkpoint(), dtype=np.uint8)}
        for k, x in self.properties.items():
            if x is not None:
                arrays[f"property_{k}"] = x
        return meta, arrays

    def _restore(self, meta: dict, arrays: dict, source="the checkpoint") -> None:
        from ._checkpoint import params_from_record, restore_engine

        Chain.__init__(
            self,
            int(meta["n"]),
            params_from_record(meta["params"]),
            boundary=meta["boundary"],
            fixed=tuple(meta["fixed"]),
            step=meta["step"],
            integrator=meta["integrator"],
            step_tolerance=meta.get("step_tolerance"),
            # (checkpoints written before the choice existed ran the global cut)
            events=meta.get("events", "global"),
            seed=meta["seed"],
            noise=meta.get("noise"),
            **{k: arrays[f"property_{k}"] for k in PROPERTIES if f"property_{k}" in arrays},
        )
        restore_engine(self._engine, arrays, source)
        self._e0 = meta["e0"]

    @classmethod
    def _from_record(cls, meta: dict, arrays: dict, source="the checkpoint") -> Chain:
        chain = cls.__new__(cls)
        chain._restore(meta, arrays, source)
        return chain

    def __getstate__(self):
        return self._record()

    def __setstate__(self, state):
        self._restore(*state)

    def save(self, path) -> None:
        """Write a checkpoint: data only (npz with JSON metadata and the engine's bytes,
        see ``bkwaves._checkpoint``), never a pickle. ``Chain.load(path).run(...)``
        continues bit for bit like the uninterrupted run when the checkpoint was taken
        where a run stopped on ``max_events``, on Ctrl-C or on its step budget (a ``t_end``
        inside an event cuts a step short, which an uninterrupted run would not do).

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file (npz). An earlier bkwaves checkpoint there is replaced;
            anything else (a file of yours, a folder) is refused with a ParameterError
            and kept.

        Examples
        --------
        A chain saved mid-run and loaded again continues bit for bit:

        >>> import os, tempfile
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> path = os.path.join(tempfile.mkdtemp(), "chain.npz")
        >>> a = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0)
        >>> _ = a.run(t_end=5.0)
        >>> a.save(path)
        >>> b = bk.Chain.load(path)
        >>> np.array_equal(a.run(t_end=20.0).u, b.run(t_end=20.0).u)
        True
        """
        from . import _checkpoint

        _checkpoint.write(path, "chain", *self._record())

    @staticmethod
    def load(path) -> Chain:
        """Read a checkpoint written by :meth:`save`. Pickles, other files and checkpoints
        of another format version are refused (:class:`bkwaves.ParameterError`).

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file.

        Returns
        -------
        Chain
            The chain as saved, ready to run on.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> path = os.path.join(tempfile.mkdtemp(), "chain.npz")
        >>> ch = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0)
        >>> _ = ch.run(t_end=5.0)
        >>> ch.save(path)
        >>> bk.Chain.load(path).t
        5.0
        """
        from . import _checkpoint

        meta, arrays = _checkpoint.read(path, "chain", "Chain.save")
        return _checkpoint.rebuild(Chain._from_record, meta, arrays, path, "chain")

    # --- triggers ------------------------------------------------------------------
    def kick(self, block: int, du_t: float, t: float = 0.0) -> Chain:
        """Schedule a kick: add du_t to the block's u_t at time t.

        Parameters
        ----------
        block : int
            The block, 0 <= block < n.
        du_t : float
            Change of du/dt, in units of (f_r - f_s)/sqrt(k_p m); negative is a forward
            kick (u falls as the block moves forward).
        t : float, default 0
            When (>= the chain's time), in units of sqrt(m/k_p).

        Returns
        -------
        Chain
            The chain itself, so calls chain: ``ch.kick(0, -2.0).run(...)``.

        Examples
        --------
        >>> import bkwaves as bk
        >>> ch = bk.Chain(50, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0)
        >>> ch.run(t_end=1.0).slips["kind"].iloc[0]
        'trigger'
        """
        block = self._block(block)
        du_t = V.number("du_t", du_t, lo=-1e6, hi=1e6)
        t = V.number("t", t, lo=self.t)
        self._engine.add_trigger(t, block, "kick", du_t)
        self._pending = [*getattr(self, "_pending", []), t]  # (for the run-cost estimate)
        return self

    def release(self, block: int, t: float = 0.0, direction: int = 1) -> Chain:
        """Schedule a release: the block starts sliding at time t with no kick.

        Parameters
        ----------
        block : int
            The block, 0 <= block < n.
        t : float, default 0
            When (>= the chain's time), in units of sqrt(m/k_p).
        direction : {1, -1}
            Forward (+1) or backward (-1, needs a finite ``params.beta``).

        Returns
        -------
        Chain
            The chain itself.

        Examples
        --------
        Above the release stress (0.509 here) a block let go starts fronts both ways:

        >>> import bkwaves as bk
        >>> ch = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.95)
        >>> ev = ch.release(200).run(t_end=10.0).catalog
        >>> int(ev.first_block[0]), int(ev.last_block[0]), ev.kind[0]
        (0, 399, 'trigger')
        """
        block = self._block(block)
        t = V.number("t", t, lo=self.t)
        direction = V.direction("direction", direction)
        self._engine.add_trigger(t, block, "release", float(direction))
        self._pending = [*getattr(self, "_pending", []), t]
        return self

    def _block(self, block) -> int:
        if not V._is_int(block) or not 0 <= int(block) < self.n:
            V._fail("block", block, f"an integer 0 <= block < {self.n}")
        return int(block)

    # --- state ---------------------------------------------------------------------
    @property
    def t(self) -> float:
        """The chain's time, in units of sqrt(m/k_p)."""
        return self._engine.time

    @property
    def u(self) -> np.ndarray:
        """The stress u of every block (dimensionless), a copy."""
        return self._engine.u()

    @property
    def u_t(self) -> np.ndarray:
        """du/dt of every block (dimensionless, in units of (f_r - f_s)/sqrt(k_p m)), a copy."""
        return self._engine.u_t()

    @property
    def phi(self) -> np.ndarray:
        """u - Lap u/dx^2 (the elastic force offset by f_s, in units of f_r - f_s)."""
        return self._engine.phi()

    @property
    def modes(self) -> np.ndarray:
        """0 stuck, +1 sliding forward, -1 sliding backward."""
        return self._engine.modes()

    # --- running -------------------------------------------------------------------
    def run(
        self,
        t_end: float = math.inf,
        max_events: int | None = None,
        *,
        snapshots=None,
        snapshot_every: int = 0,
        progress: bool | None = None,
        chunk_steps: int = 20_000,
        max_event_slips: int | None = None,
        max_event_duration: float | None = None,
    ) -> ChainResult:
        """Advance to ``t_end`` or until ``max_events`` more events have finished.

        Ctrl-C stops the run and returns what was computed (``interrupted=True``).
        An event may never end (creep at gamma >= 1; steady sliding; a pulse circulating
        on a ring, re-exciting the reloaded blocks): when the running event exceeds
        ``max_event_slips`` slips or lasts longer than ``max_event_duration`` the run
        stops with ``stop="long_event"``, a :class:`~bkwaves.chain.RunawayEventWarning`
        naming the regime, and everything computed so far.

        Parameters
        ----------
        t_end : float, default inf
            End time (dimensionless, >= now); inf needs ``max_events``.
        max_events : int, optional
            Stop once this many more events have finished.
        snapshots : array_like, optional
            Times (>= now) at which u and u_t are recorded (from the integrator's dense
            output, exact for stuck blocks). Times past ``t_end`` stay scheduled and are
            taken by a later ``run``; a result holds every snapshot taken so far.
        snapshot_every : int, default 0
            Also a snapshot at the end of every k-th event (0: none).
        progress : bool, optional
            A progress bar (default: on when stderr is a terminal).
        chunk_steps : int, default 20000
            Engine steps between checks for Ctrl-C and progress.
        max_event_slips : int, optional
            Slips after which a running event counts as runaway (default 100 per block).
        max_event_duration : float, optional
            Duration after which it does (default 100 sound crossings of the chain; of a
            lattice's longer side, ``bkwaves.lattice.default_max_event_duration``).

        Returns
        -------
        ChainResult
            Catalog, slips, snapshots, energy books, and why the run stopped.

        Examples
        --------
        A front with snapshots; the energy books close (energy injected by the kick and
        the loader = energy change + dissipation) to the integrator's accuracy, here
        about 1e-7 of energies of order 10 (``integrator="midpoint"``: to round-off):

        >>> import bkwaves as bk
        >>> ch = bk.Chain(200, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0)
        >>> res = ch.run(t_end=10.0, snapshots=[5.0, 10.0])
        >>> res.snapshots["u"].shape, abs(res.energy["residual"]) < 1e-6
        ((2, 200), True)
        """
        spec = V.CHAIN
        if t_end is None or (V._is_real(t_end) and t_end == math.inf):
            t_end = math.inf
        else:
            t_end = V.number("t_end", t_end, lo=self.t)
        max_events = V.optional_integer("max_events", max_events, lo=1)
        if max_events is None and not math.isfinite(t_end):
            V._fail("t_end", t_end, "a finite t_end or a max_events limit")
        snapshot_every = spec["snapshot_every"].check(snapshot_every)
        chunk_steps = spec["chunk_steps"].check(chunk_steps)
        if progress is not None:
            progress = V.flag("progress", progress)
        limit = (
            default_max_event_slips(self.n)
            if max_event_slips is None
            else spec["max_event_slips"].check(max_event_slips)
        )
        max_duration = (
            self._max_event_duration()
            if max_event_duration is None
            else V.number("max_event_duration", max_event_duration, lo=0.0, lo_open=True)
        )
        times = np.sort(V.array("snapshots", [] if snapshots is None else snapshots).ravel())
        if times.size and times[0] < self.t:
            V._fail("snapshots", float(times[0]), f"times >= current time {self.t}")
        from .limits import check_memory_use, check_wall, noise_key, noise_work

        span = t_end - self.t if math.isfinite(t_end) else None
        work, wall, mem = self._estimate(span, max_events, max_duration, times.size)
        noise_cost = noise_work(
            "chain", self.n, self.n, work.horizon, self.params.v, self.noise, work.sliding_fraction
        )
        what = f"t_end = {t_end:.6g}" if span is not None else f"max_events = {max_events}"
        check_wall(what, wall, work.notes[0], noise_key(self.noise, "chain"), noise_cost)
        check_memory_use(what, mem)
        self._engine.add_snapshots(times, int(snapshot_every))
        self._engine.set_run_limits(limit, max_duration, CHUNK_WORK)
        self._engine.set_chunk_wall(CHUNK_WALL)
        t_stop = t_end if math.isfinite(t_end) else 1e300
        events_left = max_events if max_events is not None else 2**62
        start_events = self._engine.events_finished
        bar = _progress(progress, t_end, max_events, self.t, start_events)
        t_wall = _time.perf_counter()
        interrupted = False
        stop = "steps"
        try:
            while True:
                done = self._engine.events_finished - start_events
                stop = self._engine.advance(t_stop, max(events_left - done, 0), chunk_steps)
                bar.advance(self.t, self._engine.events_finished)
                if stop != "steps":
                    break
        except KeyboardInterrupt:
            from . import _signals

            if _signals.propagate:  # a command line stopping: not a result to draw from
                raise
            interrupted = True
            stop = "interrupted"
        finally:
            bar.close()
        if stop == "long_event":
            import warnings

            warnings.warn(
                runaway_message(self, limit, max_duration), RunawayEventWarning, stacklevel=2
            )
        return self._result(stop, interrupted, _time.perf_counter() - t_wall)

    def _estimate(self, span, max_events, max_duration, snapshots):
        """(work, wall seconds, memory bytes) of a run from the current state over
        ``span`` (None: until ``max_events``): bkwaves._cost, docs/usage.md "Limits"."""
        from ._cost import ChainRun, chain_work
        from .limits import LIMITS, chain_step, chain_wall, memory_bytes, onset_substeps

        thr = np.asarray(self._engine.thresholds(), dtype=float)
        mass = self.properties.get("mass")
        m_min = 1.0 if mass is None else float(np.min(mass))
        substeps = self.integrator == "rk4" and self.step_tolerance is None
        h = chain_step(
            self.params.dx, self.step, self.params.law, float(thr.max()), m_min, substeps
        )
        onset = onset_substeps(
            self.params.law, self.params.dx, self.step, float(thr.max()), m_min, substeps
        )
        # flat, block by block as the engine numbers them (a Lattice shapes them (ny, nx))
        phi, modes, u = (np.ravel(a) for a in (self.phi, self.modes, self.u))
        stuck = modes == 0
        pending = [t - self.t for t in getattr(self, "_pending", []) if t >= self.t]
        run = ChainRun(
            n=self.n,
            dx=self.params.dx,
            h=h,
            v=self.params.v,
            gamma=self.params.gamma,
            u_ahead=float(u[stuck].mean()) if stuck.any() else float(u.mean()),
            phi_max=float(np.max(phi - thr)) + 1.0,
            started=bool((~stuck).any()),
            trigger_times=tuple(pending),
            uniform=bool(np.ptp(u) == 0 and np.ptp(thr) == 0 and self.noise is None),
            t_span=span,
            max_events=max_events,
            event_duration=max_duration,
            step_bound=self.step_tolerance is not None,
            open_sources=self.noise is not None,
            onset_per_slip=onset,
        )
        work = chain_work(run)
        wall = chain_wall(work, self.n, snapshots, output=False)
        mem = (
            memory_bytes("chain", self.n)
            + work.slips * LIMITS["chain_bytes_per_slip"]
            + snapshots * self.n * 16.0
        )
        return work, wall, mem

    # --- outputs -------------------------------------------------------------------
    def _result(self, stop, interrupted, wall) -> ChainResult:
        eng = self._engine
        p = self.params
        # the engine's records now (the chain may run on); tables and Dataset on first use
        raw_catalog, raw_slips = eng.catalog(), eng.slips()
        snapshots = self._snapshots_builder()

        def catalog():
            import pandas as pd

            cat = pd.DataFrame(raw_catalog)
            cat["duration"] = cat["t_end"] - cat["t_start"]
            cat["moment"] = cat["moment"] * p.dx  # int slip dx (the core sums block slips)
            describe(cat)
            cat.attrs["units"] = {
                "t_start": UNITS["t"],
                "t_end": UNITS["t"],
                "duration": UNITS["t"],
                "moment": "1",  # scaled as attrs["scales"] says, as in every route's catalog
                "stress_drop": "f_r - f_s (mean over slipped blocks)",
            }
            cat.attrs["scales"] = {"moment": MOMENT_SCALE}
            return cat

        def slips():
            import pandas as pd

            df = pd.DataFrame(raw_slips)
            df.insert(2, "x", df["block"] * p.dx)
            df.attrs["units"] = {k: UNITS["t"] for k in ("t_start", "t_end")} | {
                "x": UNITS["x"],
                "u_start": UNITS["u"],
                "u_end": UNITS["u"],
                "slip": UNITS["slip"],
            }
            return df

        kin, coup, load = eng.energy()
        led = eng.ledger()
        e1 = kin + coup + load
        flows = (
            led["loader_work"]
            - led["friction_work"]
            - led["viscous_work"]
            - led["stick_projection"]
            + led["injected"]
        )
        energy = {
            "initial": self._e0,
            "final": e1,
            "kinetic": kin,
            "coupling_springs": coup,
            "loader_springs": load,
            **led,
            "residual": (e1 - self._e0) - flows,
            "units": UNITS["energy"],
        }
        return ChainResult(
            params=p,
            t=self.t,
            energy=energy,
            counters=self._counters(),
            interrupted=interrupted,
            stop=stop,
            wall_s=wall,
            seed=self.seed,
            u=eng.u(),
            u_t=eng.u_t(),
            boundary=self.boundary,
            _build={"catalog": catalog, "slips": slips, "snapshots": snapshots},
        )

    def _max_event_duration(self) -> float:
        """The default runaway bound on one event's duration (``run``)."""
        return default_max_event_duration(self.n, self.params.dx)

    def _counters(self) -> dict:
        """The engine's work counters, with the noise's candidates and spontaneous slips."""
        c = self._engine.counters()
        noise = self._engine.noise_counters
        if noise is not None:
            c["noise_candidates"], c["noise_slips"] = noise
        return c

    def _snapshots_builder(self):
        """A function building the snapshots Dataset from the records and settings of now
        (the chain may go on running): xarray is imported when it is called."""
        from . import __version__

        t, u, ut = self._engine.snapshots()
        p = self.params
        x = np.arange(self.n) * p.dx
        params = {k: v for k, v in p.to_dict().items() if k != "units"}
        law, law_values = self._engine.friction()
        attrs = {
            "params": repr(params),
            "gamma": p.gamma,
            "v": p.v,
            "dx": p.dx,
            "beta": p.beta,
            "friction": p.friction,
            "friction_law": law,
            **{f"friction_{k}": x for k, x in law_values.items()},
            "properties": ", ".join(k for k, x in self.properties.items() if x is not None)
            or "uniform",
            "boundary": self.boundary,
            **self.integration_attrs(),
            "units": repr(UNITS),
            "version": __version__,
            "seed": "none" if self.seed is None else int(self.seed),
            "noise": json.dumps(self.noise),
        }
        return lambda: _snapshot_dataset(t, u, ut, x, self.n, p, attrs)


def _snapshot_dataset(t, u, ut, x, n, p, attrs):
    """The snapshots as an xarray Dataset (see ChainResult.snapshots)."""
    import xarray as xr

    ds = xr.Dataset(
        {
            "u": (("t", "x"), u, {"units": UNITS["u"], "long_name": "stress u"}),
            "u_t": (("t", "x"), ut, {"units": UNITS["u_t"], "long_name": "du/dt"}),
        },
        coords={
            "t": ("t", t, {"units": UNITS["t"]}),
            "x": ("x", x, {"units": UNITS["x"]}),
            "block": ("x", np.arange(n)),
        },
    )
    ds.attrs.update(attrs)
    if p.units is not None:
        un = p.units
        ds = ds.assign_coords(
            t_si=("t", un.time(t), {"units": "s"}),
            x_si=("x", un.length(x), {"units": "m"}),
        )
        ds["X"] = (("t", "x"), un.displacement(u), {"units": "m"})
        ds.attrs["physical"] = repr(un)
    return ds


def _property(name, value, n):
    """A per-block property as the engine takes it: None (all 1: the uniform engine) or
    n positive values (a scalar is broadcast). Bad values name the block."""
    if value is None:
        return None
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        V._fail(name, value, f"a scalar or {n} values > 0")
    if a.ndim == 0:
        if a == 1.0:
            return None
        a = np.full(n, float(a))
    if a.ndim != 1 or a.size != n:
        V._fail(name, f"array of shape {a.shape}", f"a scalar or {n} values")
    bad = np.flatnonzero(~(np.isfinite(a) & (a > 0)))
    if bad.size:
        i = int(bad[0])
        V._fail(f"{name}[{i}]", float(a[i]), f"{name} > 0")
    return np.ascontiguousarray(a, dtype=float)


def _per_block(name, value, n) -> np.ndarray:
    a = V.array(name, value, lo=-1e6, hi=1e6)
    if a.ndim > 1 or (a.ndim == 1 and a.size not in (1, n)):
        V._fail(name, f"array of shape {a.shape}", f"a scalar or {n} values (one per block)")
    return np.broadcast_to(a.reshape(-1) if a.ndim else a, (n,)).astype(float).copy()


def _progress(progress, t_end, max_events, t0, events0):
    import sys

    from ._progress import RunProgress

    if progress is None:
        progress = sys.stderr.isatty()
    return RunProgress(bool(progress), "chain", t0, t_end, max_events, events0)


def smooth_random_stress(
    n: int, dx: float, *, mean=0.6, amplitude=0.1, correlation=1.0, seed=0
) -> np.ndarray:
    """A smooth random stress profile: Gaussian-filtered white noise with correlation
    length ``correlation`` (units of x), scaled to the given mean and std amplitude.

    Parameters
    ----------
    n : int
        Blocks, >= 1.
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    mean : float, default 0.6
        Mean stress (dimensionless).
    amplitude : float, default 0.1
        Standard deviation of the stress, >= 0 (dimensionless).
    correlation : float, default 1
        Correlation length, >= 0 (dimensionless, the paper's x).
    seed : int, default 0
        Seed of the generator.

    Returns
    -------
    numpy.ndarray
        u of the n blocks (dimensionless).

    Examples
    --------
    >>> import bkwaves as bk
    >>> u = bk.chain.smooth_random_stress(1000, 0.1, correlation=2.0, seed=1)
    >>> round(float(u.mean()), 6), round(float(u.std()), 6)
    (0.6, 0.1)
    """
    n = V.integer("n", n, lo=1)
    from .limits import check_memory

    check_memory("n", "chain", n)
    dx = V.PARAMS["dx"].check(dx)
    mean = V.number("mean", mean, lo=-1e6, hi=1e6)
    amplitude = V.number("amplitude", amplitude, lo=0.0, hi=1e6)
    correlation = V.number("correlation", correlation, lo=0.0)
    seed = V.seed("seed", seed)
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal(n)
    k = np.fft.rfftfreq(n, d=dx)
    f = np.fft.irfft(np.fft.rfft(noise) * np.exp(-0.5 * (2 * np.pi * k * correlation) ** 2), n)
    f = (f - f.mean()) / (f.std() or 1.0)
    return mean + amplitude * f


@dataclass(frozen=True)
class FrontMeasurement:
    """One front measured in the chain (``bkwaves front``).

    regime: "pulse" (a steady healing front in a settled window), "creep" (no steady
    healing front, as App. B predicts for u_+ <= gamma), or "undecided" (``reason`` says
    why). steadiness: largest relative deviation of a window block's sliding time from
    their mean, or of its u at re-stick from theirs relative to the slip u_+ - u_- (None
    when some window block never re-stuck). window: [x_a, x_b) where
    c, w and u_- are measured; settling_length: x_s = w v/(c - v), the distance from the
    trigger beyond which the trigger's transient cannot reach the healing front (v: the
    fastest lattice wave); the window is settled when x_a >= SETTLE_MARGIN x_s. app_b:
    the continuum traveling wave (App. B: regime, c, w, u_minus) for comparison; the
    chain differs by O(dx) (w), O(gamma dx) (u_-) and O(dx^2) at gamma = 0 (c).
    front: whether a steady front exists: "steady" (the window's slip intervals agree
    with dx/c to STEADY_TOL; ``unsteadiness`` is their largest relative deviation),
    "unsteady" (they do not: the front speeds up or slows down), or "dies" (the front
    stopped before the far end, as velocity-weakening fronts do at large v_f; regime
    "none", c NaN, ``reason`` says where).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    blocks : int
        Blocks of the chain.
    c : float
        Front speed (units of the sound speed a sqrt(k_c/m)).
    regime : {"pulse", "creep", "undecided", "none"}
        As above.
    u_minus : float or None
        Stress behind the pulse (dimensionless).
    w : float or None
        Pulse width (dimensionless x).
    wall_s : float
        Wall time [s].
    unsteadiness : float
        Largest relative deviation of the window's slip intervals from dx/c.
    slips, backward_slips : int
        Slips of the run, and how many were backward.
    beta : float, default inf
        f_s/(f_r - f_s) (dimensionless).
    steadiness : float or None
        As above (relative).
    window : tuple of float
        [x_a, x_b) (dimensionless x).
    settling_length : float or None
        x_s (dimensionless x).
    settled : bool
        Whether x_a >= SETTLE_MARGIN x_s.
    reason : str
        Why the regime is undecided or the front died.
    passes : int
        Chains run (a longer one when the first did not settle).
    app_b : dict or None
        The continuum traveling wave (c in sound speeds, w in x, u_minus dimensionless).
    front : {"steady", "unsteady", "dies"}
        As above.
    convergence : dict or None
        The changes of c, w and u_- with the chain length, when measured.

    Examples
    --------
    >>> import bkwaves as bk
    >>> m = bk.chain.front(0.6, 0.3, 0.1, blocks=400)
    >>> m.regime, m.front, round(m.c, 5), round(float(bk.front_speed(0.6, dx=0.1, gamma=0.3)), 5)
    ('pulse', 'steady', 1.23362, 1.23362)
    """

    u_plus: float
    gamma: float
    dx: float
    blocks: int
    c: float
    regime: str
    u_minus: float | None
    w: float | None
    wall_s: float
    unsteadiness: float
    slips: int
    backward_slips: int
    beta: float = math.inf
    steadiness: float | None = None
    window: tuple[float, float] = (math.nan, math.nan)
    settling_length: float | None = None
    settled: bool = False
    reason: str = ""
    passes: int = 1
    app_b: dict | None = None
    front: str = "steady"
    convergence: dict | None = None

    def to_dict(self) -> dict:
        """The measurement as a dict: what ``bkwaves front --json`` prints.

        Returns
        -------
        dict
            Name -> value (units as in the class).

        Examples
        --------
        >>> import bkwaves as bk
        >>> d = bk.chain.front(0.6, 0.3, 0.1, blocks=400).to_dict()
        >>> d["regime"], d["blocks"]
        ('pulse', 400)
        """
        d = {
            k: getattr(self, k)
            for k in ("u_plus", "gamma", "dx", "blocks", "c", "regime", "u_minus", "w", "wall_s")
        }
        d.update(
            beta=self.beta,
            backward_slips=self.backward_slips,
            steadiness=self.steadiness,
            window=list(self.window) if all(map(math.isfinite, self.window)) else None,
            settling_length=self.settling_length,
            settled=self.settled,
            reason=self.reason,
            passes=self.passes,
            app_b=self.app_b,
            front=self.front,
            convergence=self.convergence,
        )
        return d


#: The measurement window starts this many settling lengths from the trigger (at 2 x_s the
#: sliding times of all cases in docs/chain.md are steady to 3e-6 or better).
SETTLE_MARGIN = 2.0
#: A steady healing front: the window's sliding times (and u at re-stick, relative to the
#: slip u_+ - u_-) agree to this relative spread.
STEADY_TOL = 1e-3
#: A pulse steady to less than this is measured again further from the trigger (if the
#: chain may still grow: MAX_PASSES, WORK_LIMIT).
STEADY_GOAL = 1e-6
#: Default chain when App. B has no pulse (creep): this many blocks, at least 40 units long.
CREEP_BLOCKS = 1600
#: The default chain grows (from the measured w and c) while its estimated cost stays below
#: this many sliding-block updates (~5 s) and at most MAX_PASSES runs are made.
WORK_LIMIT = 5e8
MAX_PASSES = 3


#: The front experiment's trigger: block 0 kicked forward to this speed over the ground
#: (the core's; a release alone does not start a front at coarse dx).
FRONT_KICK = _core.defaults()["front_kick"]


def run_front(
    u_plus: float,
    n: int,
    params: Params,
    *,
    step: float = DEFAULT_STEP,
    t_end=None,
    snapshots=(),
    step_tolerance: float | None = None,
):
    """The front experiment run step by step in Python: n blocks at uniform u_+ (free
    ends, v = 0), block 0 kicked forward at t = 0, run until the tip reaches the far end
    or nothing slides any more (the front died), at most 4 crossings at unit speed, or
    until ``t_end``. Returns (chain, first slip time of every block (NaN: never slipped),
    (t, u_t[k, i]) at the times ``snapshots`` reached). ``step_tolerance``: the chain's
    opt-in step-size control (bkwaves.Chain; with it a velocity-weakening chain steps every
    block at step min(dx, v_f/theta), without onset sub-steps)."""
    ch = Chain(n, params, "free", u0=u_plus, step=step, step_tolerance=step_tolerance)
    ch.kick(0, -FRONT_KICK)
    dx = params.dx
    t_max = 4.0 * n * dx if t_end is None else float(t_end)
    first = np.full(n, np.nan)
    # the engine directly (Chain.run builds pandas and xarray outputs at every piece)
    eng = ch._engine
    eng.set_run_limits(default_max_event_slips(n), default_max_event_duration(n, dx), CHUNK_WORK)
    eng.set_chunk_wall(CHUNK_WALL)
    eng.add_snapshots(np.sort(np.asarray(snapshots, dtype=float)), 0)
    while (t_end is not None or not np.isfinite(first[-1])) and ch.t < t_max:
        t_stop = min(ch.t + 0.05 * n * dx, t_max)
        stop = "steps"
        while stop == "steps":
            stop = eng.advance(t_stop, 2**62, 20_000)
        slips = eng.slips()
        blocks, starts = np.asarray(slips["block"]), np.asarray(slips["t_start"])
        order = np.argsort(starts)[::-1]  # each block's earliest start is written last
        first = np.full(n, np.nan)
        first[blocks[order]] = starts[order]
        if stop == "long_event" or not np.any(ch.u_t != params.v):
            break
    t, _, u_t = eng.snapshots(0)
    return ch, first, (t, u_t)


def lattice_wave_speed(dx: float) -> float:
    """Fastest group velocity of linear waves on a run of sliding blocks,
    u_tt = Lap u/dx^2 - u (- 2 gamma u_t): omega^2 = 1 + 4 sin^2(q/2)/dx^2, so
    v_g^2 = 4 y (1 - y)/(dx^2 + 4 y) with y = sin^2(q/2), largest at
    y = (sqrt(dx^4 + 4 dx^2) - dx^2)/4. Tends to 1 (the continuum sound speed) as dx -> 0."""
    d = dx * dx
    y = (math.sqrt(d * d + 4.0 * d) - d) / 4.0
    return math.sqrt(4.0 * y * (1.0 - y) / (d + 4.0 * y))


def settling_length(c: float, w: float, dx: float) -> float:
    """Distance from the trigger beyond which the healing front is out of reach of the
    trigger's transient: a block at x re-sticks at (x + w)/c, a wave from the trigger gets
    there at x/v at the earliest (v = :func:`lattice_wave_speed`), so x_s = w v/(c - v)
    (inf when c <= v: a subsonic pulse never outruns the transient)."""
    v = lattice_wave_speed(dx)
    return w * v / (c - v) if c > v else math.inf


def _plan(c: float, w: float, dx: float, blocks: int | None = None, margin=None):
    """Chain length and window [a, b) (block indices) for a pulse of speed c, width w,
    the window ``margin`` (default SETTLE_MARGIN) settling lengths from the trigger."""
    margin = SETTLE_MARGIN if margin is None else margin
    v = lattice_wave_speed(dx)
    # planned with 15% to spare: the measured w and c differ a little from the estimate
    x_a = max(1.15 * margin * settling_length(c, w, dx), 2.0 * w, 100 * dx)
    length = max(w, 100 * dx)
    # the far end's reflection reaches a block at distance d from the end after it healed
    # when d > w v/(c + v); twice that, plus a few blocks
    tail = 2.0 * w * v / (c + v) + 20 * dx
    if blocks is None:
        if not math.isfinite(x_a):
            return None
        blocks = int(math.ceil((x_a + length + tail) / dx))
        a = int(round(x_a / dx))
        return blocks, a, a + int(math.ceil(length / dx))
    # a given chain: the window as far from the trigger as the end allows
    b = blocks - int(math.ceil(tail / dx))
    a = b - int(math.ceil(length / dx))
    if a < blocks // 2:
        a, b = blocks // 2, (3 * blocks) // 4
    return blocks, a, b


def default_blocks(u_plus: float, gamma: float, dx: float) -> int:
    """Length of the first default chain: sized from App. B's c and w (the window starts
    SETTLE_MARGIN settling lengths from the trigger); CREEP_BLOCKS (at least 40 units)
    when App. B has no pulse. ``front`` lengthens it from the measured w and c if needed."""
    tw = _app_b(u_plus, gamma)
    creep = max(CREEP_BLOCKS, int(math.ceil(40.0 / dx)))
    if tw is None or tw.regime != "pulse":
        return creep
    plan = _plan(tw.c, tw.w, dx)
    return creep if plan is None else plan[0]


def _app_b(u_plus, gamma):
    """App. B's traveling wave (None if it cannot be computed)."""
    from .waves import traveling_wave

    try:
        tw = traveling_wave(u_plus, gamma)
    except Exception:  # noqa: BLE001 - no estimate only changes the first chain length
        return None
    if tw.regime == "pulse" and (tw.w is None or not math.isfinite(tw.w)):
        return None
    return tw


def _fmt(x: float) -> str:
    return f"{x:.3g}"


#: The longest default chain of a front measurement
MAX_FRONT_BLOCKS = 1e9


def front_cost(u_plus, gamma, dx, blocks, step=DEFAULT_STEP, friction=None):
    """(work, wall seconds) estimated for one front measurement on ``blocks`` blocks
    (bkwaves._cost: the front's pulse slides, not the whole chain)."""
    from ._cost import ChainRun, chain_work
    from .friction import Law
    from .limits import chain_step, chain_wall, onset_substeps

    law = Law(friction) if isinstance(friction, str) else (friction or Law())
    run = ChainRun(
        n=int(blocks),
        dx=dx,
        h=chain_step(dx, step, law),
        v=0.0,
        gamma=gamma,
        u_ahead=u_plus,
        phi_max=u_plus,
        started=True,
        trigger_times=(0.0,),
        t_span=None,
        max_events=1,
        event_duration=default_max_event_duration(int(blocks), dx),
        onset_per_slip=onset_substeps(law, dx, step),
    )
    work = chain_work(run)
    return work, chain_wall(work, int(blocks), 0, output=False)


def _front_estimate(u_plus, gamma, dx, blocks, step, friction, fixed) -> None:
    from .limits import check_wall

    work, wall = front_cost(u_plus, gamma, dx, blocks, step, friction)
    what = f"blocks = {blocks}" if fixed else f"dx = {dx:.6g} (a chain of {blocks} blocks)"
    check_wall(what, wall, work.notes[0])


def front(
    u_plus: float,
    gamma: float,
    dx: float,
    blocks: int | None = None,
    *,
    step: float = DEFAULT_STEP,
    beta: float = math.inf,
    friction=None,
) -> FrontMeasurement:
    """Measure one front at v = 0: uniform u_+ on a free chain, block 0 kicked forward.

    c = dx (b - a)/(t_b - t_a) from the first slip times of a window of blocks a..b; w =
    c x (their sliding time) and u_- (their u when they first re-stick) if they re-stick
    behind a steady healing front. The default chain puts the window SETTLE_MARGIN
    settling lengths x_s = w v/(c - v) from the trigger (sized first from App. B, then
    from the measured w and c, up to MAX_PASSES runs within WORK_LIMIT); a given
    ``blocks`` is one run with the window as far from the trigger as the far end allows.
    See docs/chain.md.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_c), 0 < dx < 1 (dimensionless).
    blocks : int, optional
        Chain length; default: sized so the measurement has settled (see above).
    step : float, default 0.05
        Time step as a fraction of dx (h = step dx, in units of sqrt(m/k_p)).
    beta : float, default inf
        f_s/(f_r - f_s); inf is the paper's model, no backward slip.
    friction : bkwaves.friction.Law or str, optional
        A law (``bk.friction.law(name, **params)`` or a name; default: the default law),
        whose gamma and beta, if it has them, are the arguments of those names.

    Returns
    -------
    FrontMeasurement
        c (units of the sound speed), regime, u_-, w (units of a sqrt(k_c/k_p)), the
        window, the settling diagnostics and App. B's values for comparison.

    Examples
    --------
    >>> import bkwaves as bk
    >>> m = bk.chain.front(0.6, 0.3, 0.05)
    >>> round(m.c, 7), round(bk.front_speed(0.6, dx=0.05, gamma=0.3), 7)
    (1.2420474, 1.2420474)
    >>> m.regime, round(m.u_minus, 4), m.app_b["u_minus"] < m.u_minus
    ('pulse', -0.0953, True)
    """
    from .params import check_beta

    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    beta = check_beta(beta)
    step = V.CHAIN["step"].check(step)
    fixed = blocks is not None
    if fixed:
        blocks = V.integer("blocks", blocks, lo=16)
        from .limits import check_memory

        check_memory("blocks", "chain", blocks)
    if not 40.0 / dx <= MAX_FRONT_BLOCKS:  # (the shortest default chain is 40 units)
        V._fail("dx", dx, f"dx >= {40.0 / MAX_FRONT_BLOCKS:g} (a chain of 40 units in at most "
                f"{MAX_FRONT_BLOCKS:g} blocks)")  # fmt: skip
    tw = _app_b(u_plus, gamma)
    theory = (tw.c, tw.w, tw.u_minus) if tw is not None and tw.regime == "pulse" else None
    creep_n = max(CREEP_BLOCKS, int(math.ceil(40.0 / dx)))
    if fixed:
        n = int(blocks)
        plan = _plan(theory[0], theory[1], dx, n) if theory else (n, n // 2, 3 * n // 4)
    else:
        plan = _plan(theory[0], theory[1], dx) if theory else None
        if plan is None:
            plan = (creep_n, creep_n // 2, 3 * creep_n // 4)
    # one engine call: the front crosses the chain at c, a pulse of w/dx blocks sliding
    # behind it (in creep all behind it slide); warned when long (never refused on an
    # estimate alone)
    _front_estimate(u_plus, gamma, dx, plan[0], step, friction, fixed)
    t0 = _time.perf_counter()
    from types import SimpleNamespace

    from .friction import Law

    law = Law(friction) if isinstance(friction, str) else (friction or Law())
    values = law.values(SimpleNamespace(gamma=gamma, beta=beta))
    if law.name == "velocity_weakening":
        # no settling length applies to a subsonic front (the trigger's transient follows
        # it for ever): the converged measurement doubles the chain instead
        return _vw_front(u_plus, gamma, dx, blocks, beta, values, step, tw, t0)
    passes = 0
    while True:
        passes += 1
        n, a, b = plan
        try:
            r = _core.front_measure(
                u_plus,
                dx,
                n,
                step=step,
                law=law.name,
                friction=values,
                window=((a + 0.5) / n, (b + 0.5) / n),
            )
        except _core.ConvergenceError:
            died = _died(u_plus, gamma, dx, n, beta, law, step, tw, t0, passes)
            if died is None:
                raise
            return died
        a, b = r["window"]
        c = float(r["c"])
        dur = (r["stick_times"] - r["slip_times"])[a:b]
        healed = bool(np.all(np.isfinite(dur)))
        steadiness = w = x_s = None
        if healed:
            mean = float(np.mean(dur))
            # sliding times, and u at re-stick relative to the slip u_+ - u_- (the
            # latter settles more slowly in narrow undamped pulses)
            u_stick = r["stick_u"][a:b]
            slip = u_plus - float(np.mean(u_stick))
            steadiness = float(np.max(np.abs(dur - mean)) / mean)
            if slip > 0:
                u_spread = float(np.max(np.abs(u_stick - np.mean(u_stick)))) / slip
                steadiness = max(steadiness, u_spread)
            w = c * mean
            x_s = settling_length(c, w, dx)
        settled = x_s is not None and a * dx >= SETTLE_MARGIN * x_s * (1 - 1e-12)
        # (the core applies the same test to the same window to report u_-)
        steady = healed and steadiness <= STEADY_TOL and bool(r["pulse"])
        if steady and settled and steadiness > STEADY_GOAL and not fixed:
            # a pulse, not yet steady to STEADY_GOAL: one window further out if affordable
            nxt = None if passes >= MAX_PASSES else _plan(c, w, dx, margin=1.5 * a * dx / x_s)
            if nxt is not None and nxt[0] * (w / c) / (step * dx) <= WORK_LIMIT:
                plan = nxt
                continue
        if steady and settled:
            regime = "pulse"
            reason = (
                f"steady healing front: sliding times and re-stick stresses agree to "
                f"{_fmt(steadiness)} over the window, which starts {_fmt(a * dx / x_s)} "
                f"settling lengths from the trigger"
            )
            if theory is None:
                reason += " (App. B, the continuum, has creep here: a lattice pulse)"
            break
        margin = SETTLE_MARGIN
        if healed and settled:
            # a settling pulse or a stationary scatter? The same test on a window half as
            # far from the trigger: a settling healing front is much less steady there
            # (the deviation falls exponentially with x beyond x_s), creep is not.
            d_all = r["stick_times"] - r["slip_times"]
            early = d_all[a // 2 : a // 2 + (b - a)]
            early_spread = float(np.max(np.abs(early - mean)) / mean)
            if steadiness > 0.3 * early_spread:
                regime = "creep"
                reason = (
                    f"no steady healing front: the window blocks re-stick at scattered "
                    f"times (sliding times spread by {_fmt(steadiness)} > {STEADY_TOL:g}, "
                    f"{_fmt(early_spread)} half as far from the trigger) "
                    f"{_fmt(a * dx / x_s)} settling lengths of a pulse as wide from the trigger"
                )
                reason += (
                    " (App. B: creep)"
                    if theory is None
                    else f" (App. B, the continuum, has a pulse with u_- = {theory[2]:.3g} here)"
                )
                break
            # still settling: a window twice as far out
            margin = 2.0 * a * dx / x_s
        if theory is None and not steady:
            regime = "creep"
            reason = (
                f"no steady healing front (sliding times spread by {_fmt(steadiness)})"
                if healed
                else "the window blocks were still sliding when the run ended, long "
                "after the front had passed"
            ) + ", and App. B predicts creep (u_+ <= gamma)"
            break
        # not settled: grow the chain from the measurement (or, with no re-stick to
        # measure, from twice the width the chain has ruled out)
        if healed:
            est = (c, w)
        else:
            slid = float(np.nanmin(r["t_end"] - r["slip_times"][a:b]))
            est = (c, max(2.0 * c * slid, 2.0 * (theory[1] if theory else 0.0)))
        nxt = None if fixed or passes >= MAX_PASSES else _plan(*est, dx, margin=margin)
        if nxt is not None and nxt[0] > n:
            work = nxt[0] * (est[1] / est[0]) / (step * dx)
            if work <= WORK_LIMIT:
                plan = nxt
                continue
        regime = "undecided"
        need = _plan(*est, dx, margin=margin)
        more = f"; about {need[0]} blocks would settle it" if need is not None else ""
        if healed and settled:
            reason = (
                f"the healing front is still settling {_fmt(a * dx / x_s)} settling lengths "
                f"x_s = {_fmt(x_s)} from the trigger: sliding times spread by "
                f"{_fmt(steadiness)} there, {_fmt(early_spread)} half as far out{more}"
            )
        elif healed and x_s is not None and math.isfinite(x_s):
            reason = (
                f"the window starts {_fmt(a * dx / x_s)} settling lengths x_s = "
                f"{_fmt(x_s)} from the trigger (needs {SETTLE_MARGIN:g}); sliding times "
                f"spread by {_fmt(steadiness)}{more}"
            )
        elif healed:
            reason = (
                f"c = {c:.6g} is below the lattice wave speed {lattice_wave_speed(dx):.6g}: "
                f"the trigger's transient follows the pulse (sliding times spread by "
                f"{_fmt(steadiness)})"
            )
        else:
            reason = (
                "window blocks were still sliding when the run ended and App. B predicts a "
                f"pulse (w = {_fmt(theory[1])}): the chain is too short{more}"
            )
        break
    wall = _time.perf_counter() - t0
    pulse = regime == "pulse"
    return FrontMeasurement(
        convergence=_window_change(r, a, b, dx, u_plus) if pulse else None,
        u_plus=u_plus,
        gamma=gamma,
        dx=dx,
        blocks=int(n),
        c=c,
        regime=regime,
        u_minus=float(r["u_minus"]) if pulse else None,
        w=w if pulse else None,
        wall_s=wall,
        unsteadiness=float(r["unsteadiness"]),
        slips=int(r["slips"]),
        backward_slips=int(r["backward_slips"]),
        beta=beta,
        steadiness=steadiness,
        window=(a * dx, b * dx),
        settling_length=x_s if x_s is not None and math.isfinite(x_s) else None,
        settled=settled,
        reason=reason,
        passes=passes,
        app_b=_app_b_dict(tw),
        front="steady" if float(r["unsteadiness"]) <= STEADY_TOL else "unsteady",
    )


def _vw_front(u_plus, gamma, dx, blocks, beta, values, step, tw, t0):
    """:func:`front` with velocity-weakening friction: ``bk.velocity_weakening.front``
    (doubling the chain until c, w and u_- have converged; a given ``blocks`` is one chain,
    reported against the chain half as long) as a FrontMeasurement."""
    from . import velocity_weakening as vw

    length = None if blocks is None else blocks * dx
    f = vw.front(
        u_plus, gamma, dx, values["v_f"], length=length, step=step, weakening=False, beta=beta
    )
    n = f.blocks
    a, b = n // 2, (3 * n) // 4
    pulse = f.status == "steady" and f.zone is not None
    if f.status == "dies":
        regime, front_state = "none", "dies"
    elif pulse:
        regime, front_state = "pulse", "steady"
    else:
        regime, front_state = "undecided", "unsteady" if f.status == "undecided" else "steady"
    reason = f.reason
    if f.status == "dies":
        reason = f"no steady front: the front died ({f.reason})"
    elif f.status == "steady" and f.zone is None:
        reason = "the window blocks had not re-stuck when the run ended; " + f.reason
    elif pulse:
        reason = f"steady healing front, {f.reason}"
    return FrontMeasurement(
        u_plus=u_plus,
        gamma=gamma,
        dx=dx,
        blocks=n,
        c=f.c,
        regime=regime,
        u_minus=f.u_minus if pulse else None,
        w=f.zone * dx if pulse else None,
        wall_s=_time.perf_counter() - t0,
        unsteadiness=math.nan if f.unsteadiness is None else f.unsteadiness,
        slips=f.slips,
        backward_slips=f.backward_slips,
        beta=beta,
        window=(a * dx, b * dx) if f.status != "dies" else (math.nan, math.nan),
        reason=reason,
        passes=len(f.lengths),
        app_b=_app_b_dict(tw),
        front=front_state,
        convergence=f.convergence,
    )


#: The stated tolerance of the Coulomb chain's default front (``bk.chain.front``): c
#: (relative), w (relative) and u_- (absolute) move by less than this when the chain is
#: doubled (tests/test_chain.py doubles it). ``FrontMeasurement.convergence`` reports the
#: change from a window half as far from the trigger, in the same run (larger: the
#: approach to the steady pulse is exponential beyond the settling length).
FRONT_TOLERANCE = {"c": 1e-6, "w": 1e-4, "u_minus": 1e-4}


def _window_change(r, a, b, dx, u_plus) -> dict | None:
    """c, w (relative) and u_- (absolute) on the window [a, b) against the window as long
    half as far from the trigger, from one front_measure result (None if that window's
    blocks did not all re-stick)."""
    a2 = a // 2
    b2 = a2 + (b - a)
    slip, stick, u_stick = r["slip_times"], r["stick_times"], r["stick_u"]

    def measure(lo, hi):
        dur = (stick - slip)[lo:hi]
        if hi - lo < 2 or not np.all(np.isfinite(dur)):
            return None
        c = dx * (hi - 1 - lo) / (slip[hi - 1] - slip[lo])
        return c, c * float(np.mean(dur)), float(np.mean(u_stick[lo:hi]))

    far, near = measure(a, b), measure(a2, b2)
    if far is None or near is None:
        return None
    return {
        "c": float(abs(far[0] / near[0] - 1.0)),
        "w": float(abs(far[1] / near[1] - 1.0)),
        "u_minus": float(abs(far[2] - near[2])),
    }


def _app_b_dict(tw):
    return (
        None if tw is None else {"regime": tw.regime, "c": tw.c, "w": tw.w, "u_minus": tw.u_minus}
    )


def _died(u_plus, gamma, dx, n, beta, law, step, tw, t0, passes):
    """The measurement of a front that stops before the far end (the core's measurement
    raised): the same experiment run in Python to see where it stopped; None if it did
    cross (the error was something else)."""
    p = Params(gamma=gamma, v=0.0, dx=dx, beta=beta, friction_law=law)
    ch, first, _ = run_front(u_plus, n, p, step=step)
    if np.isfinite(first[-1]):
        return None
    slipped = np.nonzero(np.isfinite(first))[0]
    k = int(slipped.max()) if slipped.size else 0
    return FrontMeasurement(
        u_plus=u_plus,
        gamma=gamma,
        dx=dx,
        blocks=n,
        c=math.nan,
        regime="none",
        u_minus=None,
        w=None,
        wall_s=_time.perf_counter() - t0,
        unsteadiness=math.nan,
        slips=int(len(ch._engine.slips()["block"])),
        backward_slips=int(np.sum(np.asarray(ch._engine.slips()["direction"]) < 0)),
        beta=beta,
        reason=(
            f"no steady front: the front died, its last slip at block {k} (x = {k * dx:.4g}) "
            f"of {n}; nothing slides after t = {ch.t:.4g}"
        ),
        passes=passes,
        app_b=_app_b_dict(tw),
        front="dies",
    )


@dataclass(frozen=True)
class LoadedPulse:
    """One steady pulse in a loaded chain (:func:`loaded_pulse`): the window blocks' u at
    their first slip and how long they slid (NaN: not re-stuck by the end of the run).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the pulse (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    v : float
        Loading rate (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    c : float
        The chain's front speed at v = 0 (units of the sound speed).
    x_window : float
        Where the window starts (dimensionless x).
    backswing : float
        2 pi/omega_d, the end of a block's first backswing (units of sqrt(m/k_p)).
    u_start : numpy.ndarray
        The window blocks' u at their first slip (dimensionless).
    sliding : numpy.ndarray
        How long each slid (units of sqrt(m/k_p); NaN: not re-stuck).
    stress : {"arrival", "ramp"}, default "arrival"
        How the initial stress was laid out.

    Examples
    --------
    >>> import bkwaves as bk
    >>> p = bk.chain.loaded_pulse(0.6, 0.3, 0.01, 0.2, window=10)
    >>> p.u_start.shape, bool(abs(p.bias) < 1e-3)
    ((10,), True)
    """

    u_plus: float
    gamma: float
    v: float
    dx: float
    c: float  # the chain's front speed at v = 0 (tip problem at this dx), used for the stress
    x_window: float  # where the window starts (two settling lengths from the kick)
    backswing: float  # 2 pi/omega_d: the end of a block's first backswing (theory.py)
    u_start: np.ndarray
    sliding: np.ndarray
    stress: str = "arrival"

    @property
    def bias(self) -> float:
        """Mean u of the window blocks at their slip minus u_+: how far the trigger moved
        the stress the front meets (LOADED_PULSE_BIAS_TOL for the default stress)."""
        return float(np.mean(self.u_start) - self.u_plus)

    @property
    def resticks(self) -> bool:
        """True when most window blocks re-stuck within their first backswing."""
        return bool(np.mean(self.sliding < self.backswing) > 0.5)


#: The longest chain :func:`loaded_pulse` builds (a pulse that settles slowly, u_+ near
#: gamma, or a fine dx, needs a long one).
MAX_LOADED_PULSE_BLOCKS = 10**6
#: The kick that starts a loaded pulse (forward, in u_t; the noise's default kick).
LOADED_PULSE_KICK = 0.5
#: The window blocks of the default loaded pulse slip at u_+ to within this (|bias|) for
#: v <= 0.01, far below what moves v_c by 0.1 % (docs/theory.md, section 6).
LOADED_PULSE_BIAS_TOL = 1e-5
_ARRIVALS: dict = {}


def _arrival_times(u_plus, gamma, dx, n, t_end):
    """First slip time of every block of the loaded pulse's chain at v = 0 (uniform u_+,
    the same kick): where the front is when. Blocks it does not reach by t_end continue
    at the speed of the last 100 it did. Cached (a bisection in v reuses it)."""
    key = (u_plus, gamma, dx, n, t_end)
    if key not in _ARRIVALS:
        ch = Chain(n, Params(gamma=gamma, v=0.0, dx=dx, beta=math.inf), "free", u0=u_plus)
        ch.kick(0, -LOADED_PULSE_KICK, 0.0)
        res = ch.run(t_end=t_end, progress=False, max_event_duration=1e9)
        first = res.slips.groupby("block").t_start.min()
        t = np.full(n, np.nan)
        t[first.index.to_numpy()] = first.to_numpy()
        last = int(np.max(np.nonzero(np.isfinite(t))[0]))
        k = max(last - 100, 0)
        rate = (t[last] - t[k]) / max(last - k, 1)
        t[last + 1 :] = t[last] + rate * np.arange(1, n - last)
        if len(_ARRIVALS) > 32:
            _ARRIVALS.clear()
        _ARRIVALS[key] = t
    return _ARRIVALS[key]


def loaded_pulse(
    u_plus: float,
    gamma: float,
    v: float,
    dx: float,
    *,
    window: int = 100,
    stress="arrival",
    settle: float = 2.0,
) -> LoadedPulse:
    """Run one steady pulse in a chain loaded at rate v, to see whether the blocks behind it
    re-stick (docs/theory.md, section 6; compare ``bk.theory.restick_velocity``).

    A free chain with the stress u_i = u_+ - v t_i (stress="arrival", the default; t_i:
    when the front reaches block i in the same chain at v = 0, same kick), block 0 kicked
    forward by LOADED_PULSE_KICK: every block reaches u_+ as the front arrives, up to the
    O(v) change of the front by the loading itself (``bias``, the measured miss: within
    LOADED_PULSE_BIAS_TOL near the v_c of docs/theory.md's table except at v ~ 0.1, where
    it is 4e-4 and moves v_c by 0.1 %), so the pulse is steady although the chain loads.
    stress="ramp" is u = u_+ - v x/c (c: the chain's front speed at this dx), which the
    kick biases: the front runs ahead of x/c, and the blocks slip at u_+ - v (its lead).
    The ``window`` blocks start ``settle`` settling lengths from the kick (at least 10
    units; doubling it moves the sliding times near v_c by < 1e-3 relative and leaves
    whether they re-stick unchanged 1 % from v_c, tests/test_restick.py); the chain ends where
    the free end's reflection (at most the sound speed) cannot reach them before they have
    passed their first backswing, and the run stops then. Needs a pulse (u_+ > gamma) and
    0 <= v < 1 (a plate slower than the slip speed scale); beta = inf (no backward slip).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the pulse, gamma < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    v : float
        Loading rate V sqrt(k_p m)/(f_r - f_s), 0 <= v < 1 (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_c), > 0 (dimensionless).
    window : int, default 100
        Blocks whose slips are recorded.
    stress : {"arrival", "ramp"}, default "arrival"
        The initial stress (above).
    settle : float, default 2
        Where the window starts, in settling lengths x_s from the kick, >= 1.

    Returns
    -------
    LoadedPulse
        The window blocks' u at their slip and how long they slid.

    Examples
    --------
    The blocks re-stick below the re-stick velocity v_c = 0.074 of this chain and keep
    sliding above it (docs/theory.md, section 6):

    >>> import bkwaves as bk
    >>> c = float(bk.front_speed(0.6, dx=0.2, gamma=0.3))
    >>> round(float(bk.theory.restick_velocity(0.6, 0.3, c=c)), 3)
    0.074
    >>> [bk.chain.loaded_pulse(0.6, 0.3, v, 0.2, window=10).resticks for v in (0.01, 0.3)]
    [True, False]
    """
    from . import theory
    from .limits import check_memory, check_wall
    from .waves import front_speed, traveling_wave

    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    if u_plus <= gamma:
        V._fail("u_plus", u_plus, f"u_plus > gamma = {gamma} (a pulse; below it creeps)")
    v = V.number("v", v, lo=0.0, hi=1.0, hi_open=True)
    dx = V.number("dx", dx, lo=0.0, lo_open=True)
    window = V.integer("window", window, lo=1)
    settle = V.number("settle", settle, lo=1.0)
    if 10.0 / dx + window > MAX_LOADED_PULSE_BLOCKS:  # the shortest chain it would build
        V._fail(
            "dx", dx, f"a chain of at most {MAX_LOADED_PULSE_BLOCKS} blocks with window = {window}"
        )
    c = float(front_speed(u_plus, dx=dx, gamma=gamma))
    backswing = 2.0 * float(theory.restick_time(u_plus, gamma, 0.0, c=c))
    if not math.isfinite(backswing):
        V._fail("u_plus", u_plus, f"a pulse of the chain's front (c = {c:.6g} creeps)")
    x_s = settling_length(c, traveling_wave(u_plus, gamma).w, dx)
    if not math.isfinite(x_s):
        V._fail("u_plus", u_plus, f"a pulse faster than the lattice waves (c = {c:.6g})")
    x_w = max(settle * x_s, 10.0)
    x_end = x_w + window * dx
    t_end = x_end / c + 1.2 * backswing
    length = x_end + 1.2 * backswing / (1.0 + 1.0 / c) + 5.0
    blocks = length / dx
    what = f"loaded_pulse(dx = {dx:.6g}, window = {window})"
    if blocks > MAX_LOADED_PULSE_BLOCKS:
        V._fail(
            "dx",
            dx,
            f"a chain of at most {MAX_LOADED_PULSE_BLOCKS} blocks ({what} needs {blocks:.3g})",
        )
    n = int(math.ceil(blocks))
    check_memory("dx", "chain", n)
    work, wall = front_cost(u_plus, gamma, dx, n)  # one pulse across the chain
    check_wall(what, wall, work.notes[0])
    if stress not in ("arrival", "ramp"):
        V._fail("stress", stress, "'arrival' or 'ramp'")
    params = Params(gamma=gamma, v=v, dx=dx, beta=math.inf)
    if stress == "ramp":
        u0 = u_plus - v * dx * np.arange(n) / c
    else:
        u0 = u_plus - v * _arrival_times(u_plus, gamma, dx, n, t_end)
    ch = Chain(n, params, "free", u0)
    ch.kick(0, -LOADED_PULSE_KICK, 0.0)
    res = ch.run(t_end=t_end, progress=False, max_event_duration=1e9)
    first = res.slips.groupby("block").first()
    i0 = int(round(x_w / dx))
    win = first.loc[i0 : i0 + window - 1]
    if len(win) != window:
        raise RuntimeError(f"the front did not cross the window (blocks {i0}..{i0 + window - 1})")
    return LoadedPulse(
        u_plus,
        gamma,
        v,
        dx,
        c,
        i0 * dx,
        backswing,
        win.u_start.to_numpy(),
        (win.t_end - win.t_start).to_numpy(),
        stress,
    )
