"""The free boundary problem (paper Sec. IV): shocks over a slowly loading field.

For v << 1 and slowly varying u the Burridge-Knopoff chain reduces to moving shocks
(dx_i/dt = s_i c(u_+), eq. fast, with the exact c(u) = 1/sqrt(1 - u^2)) that reset u from
u_+ to u_-(u_+) (eqs. slow, um) over a field loading at rate v; pairs are born where u
reaches 1, facing shocks annihilate. The engine (Rust, ``bkwaves._core``) is event-driven
with no time step, and independent of the lattice spacing dx: the cost of an event is set
by the grid of the slow field, not by the number of blocks. See docs/free_boundary.md.

>>> import numpy as np, bkwaves as bk
>>> p = bk.Params(gamma=0.3, v=1e-2, dx=1e-2)
>>> x = np.linspace(-4, 4, 81)
>>> fb = bk.FreeBoundary(p, x, 0.99 - 1e-3 * x**2)
>>> r = fb.run(max_events=1)
>>> r.events[["t_start", "x_start", "n_exits"]].round(6).values.tolist()
[[1.0, 0.0, 2.0]]
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from . import _core
from . import _validate as V
from . import noise as _noise
from ._progress import RunProgress
from .catalog import MOMENT_SCALE, describe
from .params import Params

__all__ = ["FreeBoundary", "FreeBoundaryResult", "NoCreepWarning", "speed_table", "threshold_field"]

BOUNDARIES = ("free", "periodic")
CREEP_RULES = ("zero", "stop")


class NoCreepWarning(UserWarning):
    """The initial state violates the no-creep condition |u_x| < v / c(u_c) (eq. nocreep):
    shocks may reach u_+ < u_c, outside the paper's theory (the creep rule then applies)."""


def _version() -> str:
    return _core.__version__


#: Nodes at which a callable speed law is sampled: u_+ = sqrt(k/(n + 1)), k = 1..n
#: (uniform in X = u_+^2, the variable the table is interpolated in).
SPEED_SAMPLES = 256


def speed_table(speed) -> dict | None:
    """A front-speed law as the table ``{"u_plus": [...], "c": [...]}`` the engine
    interpolates (docs/free_boundary.md, "Front-speed law"), or None for the exact law.

    speed: None (c = 1/sqrt(1 - u_+^2)); a dict ``{"u_plus": [...], "c": [...]}`` (the
    TOML ``[speed]`` table); a pair of arrays ``(u_plus, c)``; a callable c(u_+) (sampled at
    ``SPEED_SAMPLES`` nodes uniform in u_+^2 over (0, 1)); one
    :class:`bkwaves.disorder.EnsembleFront` or a list of them (their ``u_plus`` and
    ``c_mean``: the renormalised c_eff of a disordered medium). The table must have
    0 < u_plus < 1 strictly increasing and c > 1 strictly increasing; it is closed by
    c = 1 at u_+ = 0 and c = infinity at u_+ = 1.

    Parameters
    ----------
    speed : None or dict or tuple or callable or EnsembleFront or list of EnsembleFront
        The law, in one of the forms above (u_plus dimensionless, c in units of the sound
        speed a sqrt(k_c/m)).

    Returns
    -------
    dict or None
        ``{"u_plus": [...], "c": [...]}`` (dimensionless stresses, speeds in sound
        speeds), or None for the exact law.

    Examples
    --------
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> bk.free_boundary.speed_table({"u_plus": [0.3, 0.6], "c": [1.05, 1.25]})
    {'u_plus': [0.3, 0.6], 'c': [1.05, 1.25]}
    >>> table = bk.free_boundary.speed_table(lambda u: 1 / np.sqrt(1 - u * u))
    >>> len(table["c"]) == bk.free_boundary.SPEED_SAMPLES
    True
    """
    from .disorder import EnsembleFront

    if speed is None:
        return None
    if isinstance(speed, EnsembleFront):
        speed = [speed]
    if isinstance(speed, dict):
        unknown = sorted(set(speed) - {"u_plus", "c"})
        if unknown or not {"u_plus", "c"} <= set(speed):
            V._fail("speed", sorted(speed), 'a table with exactly the keys "u_plus" and "c"')
        u, c = speed["u_plus"], speed["c"]
    elif callable(speed):
        k = np.arange(1, SPEED_SAMPLES + 1)
        u = np.sqrt(k / (SPEED_SAMPLES + 1.0))
        try:
            c = np.asarray(speed(u), dtype=float)
            if c.shape != u.shape:
                raise ValueError
        except (TypeError, ValueError):
            c = np.array([float(speed(float(q))) for q in u])
    elif (
        isinstance(speed, list | tuple)
        and speed
        and all(isinstance(e, EnsembleFront) for e in speed)
    ):
        order = sorted(speed, key=lambda e: e.u_plus)
        u = [e.u_plus for e in order]
        c = [e.c_mean for e in order]
    elif isinstance(speed, list | tuple) and len(speed) == 2:
        u, c = speed
    else:
        V._fail(
            "speed",
            speed,
            'None, {"u_plus": [...], "c": [...]}, a pair (u_plus, c), a callable c(u_plus) '
            "or bk.disorder.front_speed_ensemble results",
        )
    u = np.atleast_1d(V.array("speed.u_plus", u, lo=0.0, hi=1.0, lo_open=True, hi_open=True))
    c = np.atleast_1d(V.array("speed.c", c, lo=1.0, lo_open=True))
    if u.ndim != 1 or c.shape != u.shape:
        V._fail("speed.c", f"array of shape {c.shape}", f"one speed per node u_plus {u.shape}")
    for name, a, what in (
        ("speed.u_plus", u, "strictly increasing nodes"),
        ("speed.c", c, "c strictly increasing with u_plus (a front is faster in a more "
                       "stressed medium)"),
    ):  # fmt: skip
        bad = np.flatnonzero(np.diff(a) <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            V._fail(f"{name}[{i}]", float(a[i]), what)
    return {"u_plus": [float(q) for q in u], "c": [float(q) for q in c]}


#: The largest |x| of a free-boundary grid (x' units; the Bristol board's 1.3 mm per
#: unit makes it 1.3e9 m): beyond it midpoints and crossing times lose their digits.
MAX_GRID_X = 1e12


def check_grid(name: str, x_max: float, h: float, v: float) -> None:
    """A grid the shock solver can cross: |x| <= MAX_GRID_X, and a spacing h with v h <= 1
    (the field rises by at most 1 while a shock, at a speed >= 1, crosses a cell: the
    slow-field assumption of Sec. IV; beyond it the cell's trajectory solve grows without
    bound, at L = 1e6 on 201 nodes it gave up after 1e6 steps, at 1e308 it never ended)."""
    if not x_max <= MAX_GRID_X:
        V._fail(name, x_max, f"grid positions |x| <= {MAX_GRID_X:g}")
    if not v * h <= 1.0:
        V._fail(
            name,
            f"a spacing h = {h:.6g} at v = {v:.6g}",
            f"v h <= 1 (a spacing h <= {1.0 / v:.6g}: more grid nodes or a shorter domain)",
        )


def threshold_field(threshold, x) -> np.ndarray | None:
    """The static threshold s at the grid nodes ``x``, or None for the uniform threshold 1.

    threshold: None or 1 (uniform, the default); a number s > 0 (uniform s: the model at
    u/s, v/s scaled by s); an array of one value per node; or a callable s(x) evaluated at
    the nodes. Block x slips when u - u_xx >= s(x); the free boundary problem assumes s
    varies on scales much longer than dx and the pulse width (docs/free_boundary.md,
    "Threshold field").

    Parameters
    ----------
    threshold : None or float or array_like or callable
        The threshold in one of the forms above (dimensionless, in units of the uniform
        chain's static threshold).
    x : array_like
        The grid nodes (dimensionless, the paper's x).

    Returns
    -------
    numpy.ndarray or None
        s at the nodes (dimensionless), or None for the uniform threshold 1.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> bk.free_boundary.threshold_field(lambda x: 1 + 0.1 * np.sin(x), [0.0, math.pi / 2])
    array([1. , 1.1])
    >>> bk.free_boundary.threshold_field(1, [0.0, 1.0]) is None
    True
    """
    if threshold is None:
        return None
    if callable(threshold):
        s = threshold(np.asarray(x, dtype=float))
    elif V._is_real(threshold):
        s = np.full(np.shape(x), float(threshold))
    else:
        s = threshold
    s = V.array("threshold", s, lo=0.0, lo_open=True)
    if s.shape != np.shape(x):
        V._fail("threshold", f"array of shape {s.shape}", f"one value per grid node {np.shape(x)}")
    return None if np.all(s == 1.0) else s


def run_window(t0, t_end, max_events, snapshots, max_snapshots: int):
    """The checked end of a free-boundary run from time ``t0`` (both engines): ``t_end``
    (inf when only ``max_events`` bounds it), ``max_events`` (None or >= 1) and the
    snapshot times (a count spread over [t0, t_end], at most ``max_snapshots``, or given
    times at or after t0, those past t_end dropped)."""
    if t_end is None and max_events is None:
        V._fail("t_end", None, "a finite end time, or max_events")
    t_end = math.inf if t_end is None else V.number("t_end", t_end, lo=t0)
    max_events = V.optional_integer("max_events", max_events, lo=1)
    if snapshots is None:
        times = np.array([], dtype=float)
    elif V._is_int(snapshots):
        n = V.integer("snapshots", snapshots, lo=1, hi=max_snapshots)
        if not math.isfinite(t_end):
            V._fail("snapshots", snapshots, "an array of times when t_end is not given")
        times = np.linspace(t0, t_end, n)
    else:
        times = np.sort(V.array("snapshots", snapshots, lo=t0).ravel())
        if math.isfinite(t_end):
            times = times[times <= t_end]
    return t_end, max_events, times


@dataclass
class FreeBoundaryResult:
    """What :meth:`FreeBoundary.run` returns (everything since the engine was built).

    Attributes
    ----------
    events : pandas.DataFrame
        One row per event (first birth to the disappearance of the last shock):
        ``id, t_start, t_end, duration, x_start, nucleation, curvature, x_min, x_max,
        extent, moment, swept, stress_drop, n_births, n_nucleations, spontaneous,
        n_shocks, n_annihilations, n_exits, n_deaths, n_creep, complete, first_block,
        last_block, n_blocks`` (n_births: at u = 1; n_nucleations: pairs started by
        noise; spontaneous: the event began with one). ``moment`` = int A dx over the
        ruptured length, the moment of every catalog (:mod:`bkwaves.catalog`: the
        chain's is dx times its sum of block slips); ``nucleation``, ``first_block``,
        ``last_block``, ``n_blocks`` are the chain's, for blocks at x[0] + i dx;
        ``stress_drop`` = moment / swept (mean A). Times and positions in the paper's
        dimensionless units; ``events.attrs`` hold the columns' descriptions, units and
        scales.
    shocks : pandas.DataFrame
        Shock path points: ``shock, event, t, x, dir, u_plus, u_minus, kind, creep``
        (kind: initial, birth, nucleation, node, annihilation, exit, death, creep_stop;
        ``creep`` marks resets done with u_+ < u_c under the creep rule).
    snapshots : xarray.Dataset
        ``u(t, x)`` on the grid, with ``n_shocks(t)``; attrs hold params, units, version,
        boundary, creep rule.
    interrupted : bool
        True when the run was stopped by Ctrl-C (the result is what was computed).
    steps : int
        Engine events (births, node crossings, collisions) processed.
    meta : dict
        Run metadata written to the outputs' attributes.

    Examples
    --------
    One maximum of u on a ring: a pair is born where u reaches 1 and sweeps the ring.

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> x = np.arange(200) * 0.2                           # a ring of length 40
    >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x,
    ...                      0.999 - 1e-4 * (x - 20) ** 2, "periodic")
    >>> res = fb.run(max_events=1)
    >>> res.events[["x_start", "n_shocks", "complete"]].values.tolist()
    [[20.0, 2, True]]
    """

    events: object
    shocks: object
    snapshots: object
    interrupted: bool = False
    steps: int = 0
    meta: dict = field(default_factory=dict)


class FreeBoundary:
    """The free boundary engine (Sec. IV): shocks over a slowly loading stress field.

    Parameters
    ----------
    params : bkwaves.Params
        gamma < 1 and v are used; the model is the dx -> 0 continuum, so dx only matters
        for comparisons with the chain.
    x : array_like
        The grid: uniform and increasing (dimensionless positions).
    u0 : array_like
        The initial stress on the grid (dimensionless), below 1 (below the threshold
        field) everywhere.
    boundary : {"free", "periodic"}
        ``"free"``: shocks leave at the ends; ``"periodic"``: a ring of length n h, node
        n coinciding with node 0.
    shocks : list of (float, int), optional
        Initial shocks as ``[(x, direction), ...]`` with direction +1 / -1 (e.g. the front
        of a saw-tooth train).
    creep : {"zero", "stop"}
        What a shock does where u_+ < u_c = gamma (outside the paper's theory):
        ``"zero"`` keeps it running and leaves u_- = 0 (the v -> 0 limit of the creep
        profile), ``"stop"`` ends it at u_+ = u_c. Either way it is recorded.
    tol : float
        Local error per integration step (relative to the grid spacing).
    record_path : bool
        Record every node crossing in ``result.shocks`` (else births and ends).
    noise : dict, optional
        Spontaneous pair nucleation, a ``[noise]`` table as a dict: ``law``
        (``"constant"``, ``"exponential"`` with ``phi0``, ``"power"`` with ``exponent``,
        ``"table"`` with node lists ``u`` and ``g``: piecewise linear, divided by g(1)) and
        ``rate``, the rate density Lambda(u = 1) per unit length and time
        (:mod:`bkwaves.noise`, docs/noise.md). Pairs nucleate where no shock is and
        u > 0 (u > u_c with ``creep="stop"``); they are rows of ``result.shocks`` with
        kind ``nucleation`` and counted in ``events.n_nucleations``.
    seed : int, optional
        The noise generator's seed (>= 0; default: drawn at random and recorded in
        ``fb.seed`` and the result's attrs).
    speed : dict or tuple or callable, optional
        The front-speed law c(u_+) (default None: the exact 1/sqrt(1 - u_+^2)): a table
        ``{"u_plus": [...], "c": [...]}``, a pair of arrays, a callable, or the output of
        :func:`bkwaves.disorder.front_speed_ensemble` (one or a list), e.g. the
        renormalised c_eff of a disordered medium
        (:func:`~bkwaves.free_boundary.speed_table`). u_- and the critical stress u_c
        follow the law (docs/free_boundary.md, "Front-speed law").
    threshold : float or array_like or callable, optional
        The static threshold field s(x) (dimensionless; default None: 1 everywhere): a
        number, an array on the grid or a callable s(x)
        (:func:`~bkwaves.free_boundary.threshold_field`).
        Block x slips when u - u_xx >= s(x); for s varying on scales much longer than dx
        and the pulse width, shocks move at c(u_+/s), leave u_- = -u_+ E(c) (eq. um with
        that c), creep where u_+ <= s u_c, and pairs are born where u reaches s
        (docs/free_boundary.md, "Threshold field"). u0 must stay below s. Not with noise.

    Raises
    ------
    bkwaves.ParameterError
        A parameter out of its range (named, with the allowed range).

    Examples
    --------
    One shock running right into u_+ = 0.6 moves at c = 1/sqrt(1 - 0.6^2) = 1.25 and
    leaves u_- of App. B behind it:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=1e-6, dx=0.01)
    >>> x = np.linspace(0.0, 50.0, 501)
    >>> fb = bk.FreeBoundary(p, x, np.full_like(x, 0.6), shocks=[(1.0, +1)])
    >>> res = fb.run(t_end=20.0)
    >>> round(float(fb.current_shocks()["x"].iloc[0]), 2)   # 1 + 1.25 t
    26.0
    >>> round(float(fb.u()[100]), 4), round(bk.traveling_wave(0.6, 0.3).u_minus, 4)
    (-0.0978, -0.0978)
    """

    def __init__(
        self,
        params: Params,
        x,
        u0,
        boundary: str = "free",
        *,
        shocks=None,
        creep: str = "zero",
        tol: float = 1e-12,
        record_path: bool = True,
        noise: dict | None = None,
        seed: int | None = None,
        speed=None,
        threshold=None,
    ):
        if not isinstance(params, Params):
            V._fail("params", params, "a bkwaves.Params instance")
        if params.gamma >= 1.0:
            V._fail(
                "gamma",
                params.gamma,
                "0 <= gamma < 1 (for gamma >= 1 every wave creeps: no free boundary problem)",
            )
        if params.dx >= 1.0:
            V._fail(
                "dx",
                params.dx,
                "0 < dx < 1 (the free boundary model is the continuum limit dx -> 0 of the "
                "chain; dx maps its results to blocks)",
            )
        if params.law.name != "coulomb":
            V._fail(
                "params",
                f"friction law {params.law.name!r}",
                "Coulomb friction: the free boundary model is the continuum limit of the "
                "chain with Coulomb friction (its front speed is the Coulomb tip problem's); "
                "other laws run in bkwaves.Chain",
            )
        spec = V.FREE_BOUNDARY
        boundary = spec["boundary"].check(boundary)
        creep = spec["creep"].check(creep)
        x = V.array("x", x)
        if x.ndim != 1 or x.size < 5:
            V._fail("x", f"array of shape {x.shape}", "a 1-d grid of at least 5 nodes")
        dxs = np.diff(x)
        h = (x[-1] - x[0]) / (x.size - 1)
        if not (h > 0 and np.all(np.abs(dxs - h) <= 1e-9 * h)):
            V._fail("x", "non-uniform grid", "uniformly spaced, increasing nodes")
        check_grid("x", float(np.max(np.abs(x[[0, -1]]))), float(h), params.v)
        threshold = threshold_field(threshold, x)
        # (below the threshold field, checked below, when there is one)
        u0 = V.array("u0", u0, lo=-1e6, hi=1.0 if threshold is None else None, hi_open=True)
        if u0.shape != x.shape:
            V._fail("u0", f"array of shape {u0.shape}", f"the shape of x, {x.shape}")
        if shocks is not None and (
            isinstance(shocks, str | bytes) or not hasattr(shocks, "__iter__")
        ):
            V._fail("shocks", shocks, "a list of pairs (x, direction)")
        sx, sd = [], []
        for item in shocks if shocks is not None else []:
            try:
                xs, d = item
            except (TypeError, ValueError):
                V._fail("shocks", item, "pairs (x, direction) with direction +1 or -1")
            sx.append(V.number("shock position", xs))
            sd.append(V.direction("shock direction", d))
        tol = spec["tol"].check(tol)
        record_path = spec["record_path"].check(record_path)
        self.params = params
        self.x = x
        self.h = float(h)
        self.boundary = boundary
        self.creep = creep
        self.tol = float(tol)
        self.record_path = bool(record_path)
        self.noise = None if noise is None else _noise.check_noise(noise)
        self.seed = _noise.noise_seed(seed, self.noise)
        self.speed = speed_table(speed)
        self.threshold = threshold
        if self.threshold is not None:
            over = np.flatnonzero(u0 >= self.threshold)
            if over.size:
                i = int(over[0])
                V._fail(
                    "u0",
                    float(u0[i]),
                    f"u0 < threshold everywhere (at x = {x[i]:.6g} the threshold is "
                    f"{self.threshold[i]:.6g}: a slip at t = 0)",
                )
        self._engine = self._new_engine(
            u0,
            np.array(sx, dtype=float) if sx else None,
            np.array(sd, dtype=np.int64) if sd else None,
        )
        self._check_no_creep(u0, np.array(sx, dtype=float))
        self._set_noise()
        self._snap_t: list[float] = []
        self._snap_u: list[np.ndarray] = []
        self._snap_n: list[int] = []
        self._take_snapshot()

    def _new_engine(self, u0, shock_x=None, shock_dir=None):
        """The Rust engine of this configuration with initial field u0 and shocks."""
        table = self.speed or {}
        return _core.FreeBoundaryEngine(
            float(self.x[0]),
            self.h,
            np.ascontiguousarray(u0, dtype=float),
            float(self.params.gamma),
            float(self.params.v),
            self.boundary,
            self.creep,
            shock_x,
            shock_dir,
            self.tol,
            self.record_path,
            speed_u=np.array(table["u_plus"]) if table else None,
            speed_c=np.array(table["c"]) if table else None,
            threshold=None if self.threshold is None else np.ascontiguousarray(self.threshold),
        )

    @property
    def critical_stress(self) -> float:
        """u_c of the front-speed law: c(u_c) = 1/sqrt(1 - gamma^2) (gamma for the exact
        law); waves with u_+ <= u_c creep."""
        return self._engine.critical_stress

    def front_speed(self, u_plus):
        """c(u_+) of the engine's front-speed law (vectorised).

        Parameters
        ----------
        u_plus : float or array_like
            Stress ahead of the front, 0 < u_plus < 1 (dimensionless).

        Returns
        -------
        float or numpy.ndarray
            c, in units of the sound speed a sqrt(k_c/m).

        Examples
        --------
        The default law is the exact c = 1/sqrt(1 - u_+^2):

        >>> import numpy as np
        >>> import bkwaves as bk
        >>> x = np.arange(200) * 0.2                           # a ring of length 40
        >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x,
        ...                      0.999 - 1e-4 * (x - 20) ** 2, "periodic")
        >>> fb.front_speed([0.6, 0.8])
        array([1.25      , 1.66666667])
        """
        u = np.atleast_1d(V.array("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True))
        c = np.asarray(self._engine.front_speed(np.ascontiguousarray(u.ravel())))
        return c.reshape(np.shape(u_plus)) if np.ndim(u_plus) else float(c[0])

    def _set_noise(self):
        if self.noise is not None:
            params = {k: v for k, v in self.noise.items() if k not in ("law", "rate")}
            self._engine.set_noise(self.noise["law"], self.noise["rate"], self.seed, **params)

    # ------------------------------------------------------------------ checks
    def _check_no_creep(self, u0, shock_x):
        """Warn when |u0_x| >= v / c(u_c) somewhere (eq. nocreep; |(u0 - u_c s)_x| with a
        threshold field s), away from given shocks."""
        v, g = self.params.v, self.params.gamma
        if v <= 0 or g <= 0:
            return
        bound = v * math.sqrt(1.0 - g * g)  # v / c(u_c), c(u_c) = 1/sqrt(1 - gamma^2)
        # with a threshold field the creep boundary is u = s u_c: |(u - u_c s)_x| counts
        g = u0 if self.threshold is None else u0 - self.critical_stress * self.threshold
        slope = np.abs(np.diff(g)) / self.h
        mid = 0.5 * (self.x[:-1] + self.x[1:])
        if shock_x.size:
            near = np.min(np.abs(mid[:, None] - shock_x[None, :]), axis=1) < self.h
            slope = np.where(near, 0.0, slope)
        # only where u is below u_c can the condition matter; the paper states it globally
        worst = float(slope.max()) if slope.size else 0.0
        if worst >= bound:
            i = int(np.argmax(slope))
            warnings.warn(
                f"the initial state violates the no-creep condition |u_x| < v/c(u_c) = "
                f"{bound:.4g} (eq. nocreep): |u_x| = {worst:.4g} at x = {mid[i]:.4g}; shocks "
                f"may reach u_+ < u_c = {self.critical_stress:.6g} (creep rule "
                f"{self.creep!r} applies, recorded "
                f"in the results)",
                NoCreepWarning,
                stacklevel=3,
            )

    # ------------------------------------------------------------------ checkpoints
    def _record(self) -> tuple[dict, dict]:
        """The whole state, snapshots included, as (JSON-able meta, plain arrays)."""
        from ._checkpoint import params_record

        meta = {
            "params": params_record(self.params),
            "boundary": self.boundary,
            "creep": self.creep,
            "tol": self.tol,
            "record_path": self.record_path,
            "noise": self.noise,
            "seed": self.seed,
            "speed": self.speed,
        }
        arrays = {
            "x": self.x,
            "engine": np.frombuffer(self._engine.checkpoint(), dtype=np.uint8),
            "snap_t": np.asarray(self._snap_t, dtype=float),
            "snap_u": np.asarray(self._snap_u, dtype=float).reshape(-1, self.x.size),
            "snap_n": np.asarray(self._snap_n, dtype=np.int64),
            # (empty: the uniform threshold 1)
            "threshold": np.zeros(0) if self.threshold is None else self.threshold,
        }
        return meta, arrays

    def _restore(self, meta: dict, arrays: dict, source="the checkpoint") -> None:
        from ._checkpoint import params_from_record, restore_engine

        x = np.asarray(arrays["x"], dtype=float)
        self.params = params_from_record(meta["params"])
        self.x = x
        self.h = float((x[-1] - x[0]) / (x.size - 1))
        self.boundary = meta["boundary"]
        self.creep = meta["creep"]
        self.tol = float(meta["tol"])
        self.record_path = bool(meta["record_path"])
        self.noise = meta.get("noise")
        self.seed = meta.get("seed")
        self.speed = meta.get("speed")
        th = arrays.get("threshold")
        self.threshold = None if th is None or th.size == 0 else np.array(th, dtype=float)
        # an engine of the same configuration; its field is replaced by the checkpoint's
        self._engine = self._new_engine(
            np.zeros_like(x) if self.threshold is None else 0.5 * self.threshold
        )
        self._set_noise()
        restore_engine(self._engine, arrays, source)
        self._snap_t = [float(t) for t in arrays["snap_t"]]
        self._snap_u = [np.array(u) for u in arrays["snap_u"]]
        self._snap_n = [int(n) for n in arrays["snap_n"]]

    @classmethod
    def _from_record(cls, meta: dict, arrays: dict, source="the checkpoint") -> FreeBoundary:
        fb = cls.__new__(cls)
        fb._restore(meta, arrays, source)
        return fb

    def __getstate__(self):
        return self._record()

    def __setstate__(self, state):
        self._restore(*state)

    def save(self, path) -> None:
        """Write a checkpoint of the whole state, snapshots included: data only (npz with
        JSON metadata and the engine's bytes, see ``bkwaves._checkpoint``), never a pickle.
        ``FreeBoundary.load(path).run(...)`` continues bit for bit like the uninterrupted
        run when it makes the same engine calls (e.g. the checkpoint was taken where a run
        stopped on ``max_events`` or Ctrl-C, and the continuation asks for the same end).

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file (npz).

        Examples
        --------
        >>> import os, tempfile
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> x = np.arange(200) * 0.2                           # a ring of length 40
        >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x,
        ...                      0.999 - 1e-4 * (x - 20) ** 2, "periodic")
        >>> _ = fb.run(t_end=50.0)
        >>> path = os.path.join(tempfile.mkdtemp(), "fb.npz")
        >>> fb.save(path)
        >>> again = bk.FreeBoundary.load(path)
        >>> fb.run(max_events=2).events.equals(again.run(max_events=2).events)
        True
        """
        from . import _checkpoint

        _checkpoint.write(path, "free_boundary", *self._record())

    @staticmethod
    def load(path) -> FreeBoundary:
        """Read a checkpoint written by :meth:`save`. Pickles, other files and checkpoints
        of another format version are refused (:class:`bkwaves.ParameterError`).

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file.

        Returns
        -------
        FreeBoundary
            The engine as saved, ready to run on.

        Examples
        --------
        >>> import os, tempfile
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> x = np.arange(200) * 0.2                           # a ring of length 40
        >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x,
        ...                      0.999 - 1e-4 * (x - 20) ** 2, "periodic")
        >>> _ = fb.run(t_end=50.0)
        >>> path = os.path.join(tempfile.mkdtemp(), "fb.npz")
        >>> fb.save(path)
        >>> bk.FreeBoundary.load(path).time
        50.0
        """
        from . import _checkpoint

        meta, arrays = _checkpoint.read(path, "free_boundary", "FreeBoundary.save")
        return FreeBoundary._from_record(meta, arrays, path)

    # ------------------------------------------------------------------ state
    @property
    def time(self) -> float:
        """Current time of the engine, in units of sqrt(m/k_p)."""
        return self._engine.time

    def u(self) -> np.ndarray:
        """u at the grid nodes now.

        Returns
        -------
        numpy.ndarray
            u (dimensionless), one value per node.

        Examples
        --------
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> x = np.arange(200) * 0.2                           # a ring of length 40
        >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x,
        ...                      0.999 - 1e-4 * (x - 20) ** 2, "periodic")
        >>> round(float(fb.u().max()), 4)                      # loading at v = 0.01
        0.999
        """
        return self._engine.u_nodes()

    def current_shocks(self):
        """Live shocks now, as a DataFrame (id, event, x, dir, u_plus).

        Returns
        -------
        pandas.DataFrame
            One row per live shock: position x (dimensionless), direction (+1, -1) and
            the stress u_plus ahead of it (dimensionless).

        Examples
        --------
        Half a time unit after the birth at x = 20 the pair runs apart symmetrically:

        >>> import numpy as np
        >>> import bkwaves as bk
        >>> x = np.arange(200) * 0.2                           # a ring of length 40
        >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x,
        ...                      0.999 - 1e-4 * (x - 20) ** 2, "periodic")
        >>> _ = fb.run(t_end=0.5)
        >>> s = fb.current_shocks()
        >>> s.dir.tolist(), round(float(s.x[0] + s.x[1]) / 2, 9)
        ([1, -1], 20.0)
        """
        import pandas as pd

        return pd.DataFrame(self._engine.shocks())

    def _take_snapshot(self):
        t = self._engine.time
        if self._snap_t and self._snap_t[-1] == t:
            return
        self._snap_t.append(t)
        self._snap_u.append(np.asarray(self._engine.u_nodes()))
        self._snap_n.append(self._engine.n_shocks)

    # ------------------------------------------------------------------ run
    def run(
        self,
        t_end: float | None = None,
        *,
        max_events: int | None = None,
        snapshots=None,
        progress: bool = False,
        chunk: int = 20000,
    ) -> FreeBoundaryResult:
        """Advance to ``t_end`` or until ``max_events`` more events are complete.

        Whichever comes first. Ctrl-C stops the run and returns what was computed
        (``result.interrupted``). Calling ``run`` again continues the run.

        Parameters
        ----------
        t_end : float, optional
            End time (dimensionless, units of sqrt(m/k_p)); give it or ``max_events``.
        max_events : int, optional
            Stop once this many more events are complete.
        snapshots : int or array_like, optional
            An int n (n evenly spaced times up to a finite t_end) or an array of times;
            the state is always recorded at the start and the end.
        progress : bool, default False
            Show a progress bar.
        chunk : int, default 20000
            Engine events between checks for Ctrl-C and progress.

        Returns
        -------
        FreeBoundaryResult
            Events, shock paths and snapshots since the engine was built.

        Examples
        --------
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> x = np.linspace(0.0, 50.0, 501)
        >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-6, dx=0.01), x,
        ...                      np.full_like(x, 0.6), shocks=[(1.0, +1)])
        >>> fb.run(t_end=10.0, snapshots=3).snapshots["u"].shape
        (3, 501)
        """
        spec = V.FREE_BOUNDARY
        t0 = self.time
        t_end, max_events, times = run_window(t0, t_end, max_events, snapshots, 10**7)
        target_events = 2**62 if max_events is None else self._engine.completed_events + max_events
        chunk = spec["chunk"].check(chunk)
        progress = V.flag("progress", progress)
        self._check_cost(t_end, max_events, times)
        interrupted = False
        bar = RunProgress(
            progress, "free boundary", t0, t_end, max_events, self._engine.completed_events
        )
        from .chain import CHUNK_WALL

        self._engine.set_chunk_wall(CHUNK_WALL)
        try:
            for target in [*times.tolist(), t_end]:
                while True:
                    status = self._engine.advance(float(target), chunk, target_events)
                    bar.advance(self._engine.time, self._engine.completed_events)
                    if status != "steps":
                        break
                if status == "events":
                    break
                if math.isfinite(target):
                    self._take_snapshot()
        except KeyboardInterrupt:
            from . import _signals

            if _signals.propagate:  # a command line stopping: not a result to draw from
                raise
            interrupted = True
            warnings.warn(
                f"free boundary run interrupted at t = {self.time:.6g}; returning the "
                "results computed so far",
                RuntimeWarning,
                stacklevel=2,
            )
        finally:
            bar.close()
        self._take_snapshot()
        return self.result(interrupted=interrupted)

    def _check_cost(self, t_end, max_events, times) -> None:
        """Warn (never refuse) about a run estimated to take long or hold much memory
        (bkwaves._cost.fb_work; docs/usage.md, "Limits")."""
        from ._cost import fb_work
        from .limits import (
            check_memory_use,
            check_noise_events,
            check_wall,
            fb_wall,
            noise_key,
            noise_work,
        )

        t0, v = self.time, self.params.v
        span = t_end - t0 if math.isfinite(t_end) else None
        u = np.asarray(self._engine.u_nodes())
        thr = self.threshold if getattr(self, "threshold", None) is not None else 1.0
        gap = float(np.min(np.asarray(thr) - u))
        work = fb_work(self.x.size, v, span, max_events, gap)
        wall = fb_wall(work, self.x.size, times.size, output=False)
        length = self.x[-1] - self.x[0] + (self.h if self.boundary == "periodic" else 0.0)
        noise_cost = noise_work(
            "free_boundary", length, self.x.size, work.horizon, v, self.noise, work.sliding_fraction
        )
        what = f"t_end = {t_end:.6g}" if span is not None else f"max_events = {max_events}"
        if span is None:
            what += f" (estimated to end near t = {t0 + work.horizon:.3g})"
        check_wall(what, wall, work.notes[0], noise_key(self.noise, "free_boundary"), noise_cost)
        check_memory_use(what, (times.size + 2) * self.x.size * 8.0)
        if span is None:
            check_noise_events(what, length, length, self.noise)

    # ------------------------------------------------------------------ results
    def result(self, interrupted: bool = False) -> FreeBoundaryResult:
        """The results recorded since the engine was built.

        Parameters
        ----------
        interrupted : bool, default False
            Mark the result as that of an interrupted run.

        Returns
        -------
        FreeBoundaryResult
            Events, shock paths and snapshots.

        Examples
        --------
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> x = np.arange(200) * 0.2                           # a ring of length 40
        >>> fb = bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x,
        ...                      0.999 - 1e-4 * (x - 20) ** 2, "periodic")
        >>> _ = fb.run(max_events=1)
        >>> res = fb.result()
        >>> len(res.events), res.interrupted
        (1, False)
        """
        import pandas as pd
        import xarray as xr

        ev = pd.DataFrame(self._engine.events())
        ev["complete"] = np.isfinite(ev["t_end"]) if len(ev) else np.array([], dtype=bool)
        ev.insert(3, "duration", ev["t_end"] - ev["t_start"])
        ev.insert(ev.columns.get_loc("x_max") + 1, "extent", ev["x_max"] - ev["x_min"])
        # moment = int A dx, as in every catalog (bkwaves.catalog); the chain's columns
        # for blocks at x[0] + i dx (params.dx)
        dx = self.params.dx
        blocks = int(round((self.x[-1] - self.x[0]) / dx)) + (self.boundary == "free")

        def block(xx):
            i = np.rint((np.asarray(xx, dtype=float) - self.x[0]) / dx).astype(np.int64)
            return np.mod(i, blocks) if self.boundary == "periodic" else np.clip(i, 0, blocks - 1)

        ev.insert(ev.columns.get_loc("x_start") + 1, "nucleation", block(ev["x_start"]))
        ev["first_block"] = block(ev["x_min"])
        ev["last_block"] = block(ev["x_max"])
        ev["n_blocks"] = np.rint(ev["swept"] / dx).astype(np.int64)
        describe(ev, units={"moment": "1"}, scales={"moment": MOMENT_SCALE})
        sh = pd.DataFrame(self._engine.path())
        meta = {
            "engine": "free_boundary",
            "params": json.dumps(self.params.to_dict(), default=str),
            "units": "dimensionless (paper eq. dimless)"
            if self.params.units is None
            else json.dumps(self.params.units.__dict__),
            "bkwaves_version": _version(),
            "boundary": self.boundary,
            "creep_rule": self.creep,
            "grid_spacing": self.h,
            "record_path": int(self.record_path),
            "noise": json.dumps(self.noise),
            "seed": -1 if self.seed is None else self.seed,
            # the front-speed law: "exact" (1/sqrt(1 - u^2)) or the table
            "speed": "exact" if self.speed is None else json.dumps(self.speed),
            # the static threshold: "uniform 1", else the variable threshold(x)
            "threshold": "uniform 1" if self.threshold is None else "field: variable threshold",
        }
        counters = self._engine.noise_counters
        if counters is not None:
            meta["noise_candidates"], meta["noise_nucleations"] = counters
        data = {
            "u": (("t", "x"), np.array(self._snap_u), {"long_name": "slow field u"}),
            "n_shocks": (("t",), np.array(self._snap_n), {"long_name": "live shocks"}),
        }
        if self.threshold is not None:
            data["threshold"] = (("x",), self.threshold, {"long_name": "static threshold s"})
        ds = xr.Dataset(
            data,
            coords={
                "t": ("t", np.array(self._snap_t), {"long_name": "time", "units": "1"}),
                "x": ("x", self.x, {"long_name": "position", "units": "1"}),
            },
            attrs=meta,
        )
        return FreeBoundaryResult(
            events=ev,
            shocks=sh,
            snapshots=ds,
            interrupted=interrupted,
            steps=self._engine.steps,
            meta=meta,
        )
