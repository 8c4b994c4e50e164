"""The free boundary problem in the plane: ruptures as fronts over a slowly loading field.

Away from fronts u_t = v; a rupture starts where u reaches the threshold (1, or a threshold
field s), spreads along its normal at c(u_+/s) with u_+ the stress ahead when the front
arrives, and leaves ``u_-(u_+)`` behind (the 1D engine's laws, from the same Rust code).
The arrival time T obeys ``|grad T| = 1/c(u_0 + v (T - t_0))``, solved by second-order fast
marching in the Rust engine ``bkwaves._core.FreeBoundary2DEngine``. See
docs/free_boundary_2d.md.

>>> import numpy as np, bkwaves as bk
>>> p = bk.Params(gamma=0.3, v=0.0, dx=1e-2)
>>> fb = bk.FreeBoundary2D(p, (41, 41), 0.25, 0.6, boundary="free", origin=(-5, -5))
>>> fb.trigger(0.0, 0.0, radius=0.5)
0
>>> r = fb.run(max_events=1)
>>> round(float(r.ruptures.loc[0, "area"]), 2)
105.06
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
from .free_boundary import CREEP_RULES, speed_table
from .params import Params

__all__ = ["FreeBoundary2D", "FreeBoundary2DResult", "lattice_curvature", "random_field"]

BOUNDARIES = ("free", "periodic")


def random_field(
    shape, h: float, correlation_length: float, seed: int | None = None, periodic=(True, True)
) -> np.ndarray:
    """A zero-mean Gaussian random field on the grid of ``shape`` = (nx, ny) nodes of
    spacing h (returned as an (ny, nx) array, like the snapshots) with a Gaussian
    correlation of length ``correlation_length``, scaled to a largest absolute value of
    1: white noise filtered in Fourier space by exp(-(k l)^2/4), periodic along an axis where
    ``periodic`` (a pair for x, y, or one flag) says so, else drawn on a grid padded by
    6 l and cut. Use it for correlated random initial stresses,
    ``u0 = mean + amplitude * random_field(...)``, and threshold fields.

    Parameters
    ----------
    shape : tuple of int
        (nx, ny) nodes.
    h : float
        Node spacing, > 0 (dimensionless, the paper's x).
    correlation_length : float
        Correlation length l, > 0 (dimensionless, the paper's x).
    seed : int, optional
        Seed of the generator (None: a fresh one).
    periodic : bool or tuple of bool, default (True, True)
        Periodic along x and y, or along both.

    Returns
    -------
    numpy.ndarray
        The field, shape (ny, nx) (dimensionless: zero mean, largest absolute value 1).

    Examples
    --------
    >>> import numpy as np
    >>> import bkwaves as bk
    >>> f = bk.free_boundary_2d.random_field((64, 32), 0.5, 2.0, seed=1)
    >>> f.shape, float(np.abs(f).max()), abs(float(f.mean())) < 1e-12
    ((32, 64), 1.0, True)
    """
    try:
        nx, ny = shape
    except (TypeError, ValueError):
        V._fail("shape", shape, "a pair (nx, ny) of node counts >= 1")
    nx, ny = V.integer("shape", nx, lo=1), V.integer("shape", ny, lo=1)
    h = V.number("h", h, lo=0.0, lo_open=True)
    corr = V.number("correlation_length", correlation_length, lo=0.0, lo_open=True)
    if isinstance(periodic, bool):
        periodic = (periodic, periodic)
    px, py = (V.flag("periodic", p) for p in periodic)
    extra = int(math.ceil(6 * corr / h))
    pad = [ny if py else ny + extra, nx if px else nx + extra]
    rng = np.random.default_rng(seed)
    white = rng.standard_normal(pad)
    ky = 2 * np.pi * np.fft.fftfreq(pad[0], d=h)
    kx = 2 * np.pi * np.fft.rfftfreq(pad[1], d=h)
    filt = np.exp(-0.25 * corr**2 * (ky[:, None] ** 2 + kx[None, :] ** 2))
    f = np.fft.irfft2(np.fft.rfft2(white) * filt, s=pad)[:ny, :nx]
    f -= f.mean()
    m = np.max(np.abs(f))
    return f / m if m > 0 else f


def _curvature(value):
    """The curvature option as [D_axis, D_diag], or {"theta": [...], "D": [...]} (a table
    over directions), or None."""
    if value is None:
        return None
    allowed = (
        "D >= 0 (finite), a pair (D along the axes, D along the diagonals), or a table "
        '{"theta": [0, ..., pi/4], "D": [...]} over directions (radians, increasing)'
    )
    if isinstance(value, dict):
        if set(value) != {"theta", "D"}:
            V._fail("curvature", sorted(value), allowed)
        theta = np.asarray(value["theta"], dtype=float)
        d = np.asarray(value["D"], dtype=float)
        if theta.ndim != 1 or d.shape != theta.shape or not 2 <= theta.size <= 16:
            V._fail("curvature", value, "2 to 16 directions theta, as many as values D")
        if abs(theta[0]) > 1e-12 or abs(theta[-1] - np.pi / 4) > 1e-12:
            V._fail("curvature.theta", theta.tolist(), "from 0 (an axis) to pi/4 (a diagonal)")
        if not np.all(np.diff(theta) > 1e-6):
            V._fail("curvature.theta", theta.tolist(), "strictly increasing in [0, pi/4]")
        for x in d:
            V.number("curvature.D", x, lo=0.0)
        return {"theta": theta.tolist(), "D": d.tolist()}
    if np.ndim(value) == 0:
        d = V.number("curvature", value, lo=0.0)
        return [d, d]
    if np.ndim(value) != 1 or len(value) != 2:
        V._fail("curvature", value, allowed)
    return [V.number("curvature", value[0], lo=0.0), V.number("curvature", value[1], lo=0.0)]


#: The lattice directions (q, p) of :func:`lattice_curvature`'s table: 0, 18.4, 26.6,
#: 33.7 and 45 degrees.
LATTICE_DIRECTIONS = ((1, 0), (3, 1), (2, 1), (3, 2), (1, 1))


def lattice_curvature(u_plus, gamma, dx, directions=LATTICE_DIRECTIONS) -> dict:
    """The lattice's curvature coefficient D(theta) as the table the ``curvature=``
    option takes: D derived along each lattice direction (q, p) by
    :func:`bkwaves.theory.curvature_coefficient` (kappa -> 0, no fitted constant), at the
    stress ahead ``u_plus``.

    Parameters
    ----------
    u_plus : float
        The stress ahead of the front (dimensionless), where D is derived.
    gamma : float
        Damping (dimensionless).
    dx : float
        The lattice spacing (dimensionless).
    directions : sequence of (int, int), optional
        Lattice directions (q, p) with 0 <= p <= q, from (1, 0) to (1, 1), in increasing
        angle atan2(p, q).

    Returns
    -------
    dict
        ``{"theta": [...], "D": [...]}``: the angles (radians, 0 to pi/4) and D (a length
        in units of the coupling length).

    Examples
    --------
    >>> import bkwaves as bk
    >>> t = bk.free_boundary_2d.lattice_curvature(0.6, 0.45, 0.1, [(1, 0), (1, 1)])
    >>> [round(d, 4) for d in t["D"]]
    [0.021, 0.0451]
    """
    from . import theory

    dirs = [(int(q), int(p)) for q, p in directions]
    theta = [float(np.arctan2(p, q)) for q, p in dirs]
    d = [float(theory.curvature_coefficient(u_plus, gamma, dx, direction=qp)) for qp in dirs]
    return _curvature({"theta": theta, "D": d})


def _field(name, value, xx, yy, hi=None):
    """A number, an (ny, nx) array or a callable f(x, y) on the grid, validated."""
    if callable(value):
        value = value(xx, yy)
    a = V.array(name, np.broadcast_to(np.asarray(value, dtype=float), xx.shape).copy())
    if hi is not None:
        over = np.argwhere(a >= hi)
        if over.size:
            j, i = over[0]
            V._fail(
                name,
                float(a[j, i]),
                f"{name} < the threshold everywhere (at x = {xx[j, i]:.6g}, "
                f"y = {yy[j, i]:.6g} it is {np.broadcast_to(hi, a.shape)[j, i]:.6g})",
            )
    return a


@dataclass
class FreeBoundary2DResult:
    """What a two-dimensional free boundary run recorded.

    ruptures: pandas DataFrame, one row per rupture: id, origin (birth, nucleation,
        trigger), t_start, t_end (last arrival), duration, x_start, y_start, u_start,
        n_nodes, area, moment (integral of ``u_+ - u_-`` over the area), mean_slip,
        perimeter,
        n_stopped (nodes where the front stopped), n_creep, contacts (meetings with other
        live ruptures), complete.
    snapshots: xarray Dataset, u(t, y, x) and live(t) (running ruptures), with the
        threshold field s(y, x) when there is one.

    Times are in units of sqrt(m/k_p), positions and areas in the paper's dimensionless
    x (and x^2), stresses and slips dimensionless.

    Parameters
    ----------
    ruptures : pandas.DataFrame
        The ruptures (above).
    snapshots : xarray.Dataset
        The snapshots (above).
    interrupted : bool, default False
        Whether the run was stopped by Ctrl-C.
    steps : int, default 0
        Engine steps processed.
    meta : dict
        Run metadata written to the outputs' attributes.

    Examples
    --------
    A rupture in uniform u_+ = 0.6 leaves u_- behind: its moment over its area is the
    slip u_+ - u_- of the traveling wave (App. B):

    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=0.0, dx=1e-3)
    >>> fb = bk.FreeBoundary2D(p, (81, 81), 0.5, 0.6, "free")
    >>> _ = fb.trigger(20.0, 20.0, radius=1.0)
    >>> r = fb.run(max_events=1).ruptures
    >>> slip = 0.6 - bk.traveling_wave(0.6, 0.3).u_minus
    >>> round(float(r.moment[0] / r.area[0]), 9), round(slip, 9)
    (0.697820121, 0.697820121)
    """

    ruptures: object
    snapshots: object
    interrupted: bool = False
    steps: int = 0
    meta: dict = field(default_factory=dict)


class FreeBoundary2D:
    """The two-dimensional free boundary engine.

    Fronts move along their normal at c(u_+) and leave u_-(u_+); away from them u loads
    at v; ruptures are born where u reaches the threshold (docs/free_boundary_2d.md).

    Parameters
    ----------
    params : bkwaves.Params
        gamma < 1 and v are used (dimensionless).
    shape : tuple of int
        (nx, ny) nodes, each >= 3.
    h : float
        Their spacing, the same along x and y, > 0 (dimensionless, the paper's x).
    u0 : float or array_like or callable
        The initial stress (dimensionless): a number, an (ny, nx) array or a callable
        u0(x, y) (x, y arrays of shape (ny, nx)); below the threshold everywhere.
    boundary : {"periodic", "free"} or tuple of str, default "periodic"
        For both axes, or a pair (x axis, y axis).
    origin : tuple of float, default (0, 0)
        (x0, y0), the place of node (0, 0) (dimensionless x).
    creep : {"zero", "stop"}, default "zero"
        As in :class:`bkwaves.FreeBoundary`.
    second_order : bool, default True
        Second-order upwind fast marching (else first order).
    record_arrivals : bool, default False
        Keep each rupture's arrival times (:meth:`arrival_time`).
    noise : dict, optional
        As in :class:`bkwaves.FreeBoundary`, but ``rate`` is per unit area and unit time
        (dimensionless).
    seed : int, optional
        Seed of the noise.
    speed : optional
        The front-speed law, as in :class:`bkwaves.FreeBoundary`.
    threshold : float or array_like or callable, optional
        The static threshold field s(x, y) (dimensionless; default 1 everywhere).
    curvature : float or tuple of float or dict, optional
        The lattice's curvature correction c_n = c - D kappa (kappa = 1/R for an
        expanding circle): D >= 0 (dimensionless length) in every direction; a pair
        (D along the axes, D along the diagonals), interpolated as
        D_axis cos^2(2 theta) + D_diag sin^2(2 theta) in the angle theta of the normal;
        or a table ``{"theta": [0, ..., pi/4], "D": [...]}`` over directions (radians),
        interpolated by the polynomial in cos(4 theta) through them (the pair is the
        table of 0 and pi/4); :func:`~bkwaves.free_boundary_2d.lattice_curvature`
        derives it for the lattice (docs/free_boundary_2d.md, "The lattice's front
        shape"). Default: none.
    speed_diagonal : optional
        The planar front speed along the diagonals, in any form of ``speed``; ``speed``
        is then the speed along the axes, and c(theta) = c_axis + (c_diag - c_axis)
        sin^2(2 theta). Default: the same as along the axes (an isotropic front).

    Examples
    --------
    A rupture triggered in uniform u_+ = 0.6 at v = 0 reaches x = 40 along the axis at
    (20 - 1)/c = 15.2 (c = 1.25), to within the grid spacing h/c = 0.4:

    >>> import bkwaves as bk
    >>> p = bk.Params(gamma=0.3, v=0.0, dx=1e-3)
    >>> fb = bk.FreeBoundary2D(p, (81, 81), 0.5, 0.6, "free", record_arrivals=True)
    >>> fb.trigger(20.0, 20.0, radius=1.0)
    0
    >>> res = fb.run(max_events=1)
    >>> round(float(fb.arrival_time(0)[40, 80]), 6)
    15.0
    """

    def __init__(
        self,
        params: Params,
        shape,
        h: float,
        u0,
        boundary="periodic",
        *,
        origin=(0.0, 0.0),
        creep: str = "zero",
        second_order: bool = True,
        record_arrivals: bool = False,
        noise: dict | None = None,
        seed: int | None = None,
        speed=None,
        threshold=None,
        curvature=None,
        speed_diagonal=None,
    ):
        if not isinstance(params, Params):
            V._fail("params", params, "a bkwaves.Params instance")
        if params.gamma >= 1.0:
            V._fail(
                "gamma",
                params.gamma,
                "0 <= gamma < 1 (for gamma >= 1 every wave creeps: no free boundary problem)",
            )
        try:
            nx, ny = shape
        except (TypeError, ValueError):
            V._fail("shape", shape, "a pair (nx, ny) of node counts >= 3")
        self.nx = V.integer("shape", nx, lo=3)
        self.ny = V.integer("shape", ny, lo=3)
        self.h = V.number("h", h, lo=0.0, lo_open=True)
        if isinstance(boundary, str):
            boundary = (boundary, boundary)
        if len(boundary) != 2 or any(b not in BOUNDARIES for b in boundary):
            V._fail("boundary", boundary, '"free" or "periodic", or a pair of them (x, y)')
        self.boundary = tuple(boundary)
        if creep not in CREEP_RULES:
            V._fail("creep", creep, '"zero" or "stop"')
        self.creep = creep
        self.origin = (V.number("origin", origin[0]), V.number("origin", origin[1]))
        self.second_order = V.flag("second_order", second_order)
        self.record_arrivals = V.flag("record_arrivals", record_arrivals)
        self.params = params
        self.x = self.origin[0] + self.h * np.arange(self.nx)
        self.y = self.origin[1] + self.h * np.arange(self.ny)
        xx, yy = np.meshgrid(self.x, self.y)
        self.threshold = None if threshold is None else _field("threshold", threshold, xx, yy)
        if self.threshold is not None and not np.all(self.threshold > 0):
            V._fail("threshold", float(self.threshold.min()), "threshold > 0 everywhere")
        u0 = _field("u0", u0, xx, yy, hi=1.0 if self.threshold is None else self.threshold)
        self.noise = None if noise is None else _noise.check_noise(noise)
        self.seed = _noise.noise_seed(seed, self.noise)
        self.speed = speed_table(speed)
        self.curvature = _curvature(curvature)
        self.speed_diagonal = speed_table(speed_diagonal)
        self._engine = self._new_engine(u0)
        self._set_noise()
        self._snap_t: list[float] = []
        self._snap_u: list[np.ndarray] = []
        self._snap_live: list[int] = []
        self._take_snapshot()

    def _new_engine(self, u0):
        table = self.speed or {}
        diag = self.speed_diagonal
        curv = self.curvature
        ctable = None
        if isinstance(curv, dict):  # a table over directions
            ctable, curv = curv, (curv["D"][0], curv["D"][-1])
        return _core.FreeBoundary2DEngine(
            self.nx,
            self.ny,
            self.h,
            self.origin[0],
            self.origin[1],
            np.ascontiguousarray(u0, dtype=float).ravel(),
            float(self.params.gamma),
            float(self.params.v),
            self.boundary[0],
            self.boundary[1],
            self.creep,
            self.second_order,
            self.record_arrivals,
            speed_u=np.array(table["u_plus"]) if table else None,
            speed_c=np.array(table["c"]) if table else None,
            threshold=None
            if self.threshold is None
            else np.ascontiguousarray(self.threshold).ravel(),
            curvature=None if curv is None else tuple(curv),
            diagonal_u=None if diag is None else np.array(diag["u_plus"]),
            diagonal_c=None if diag is None else np.array(diag["c"]),
            curvature_theta=None if ctable is None else np.array(ctable["theta"], dtype=float),
            curvature_d=None if ctable is None else np.array(ctable["D"], dtype=float),
        )

    def _set_noise(self):
        if self.noise is not None:
            params = {k: v for k, v in self.noise.items() if k not in ("law", "rate")}
            self._engine.set_noise(self.noise["law"], self.noise["rate"], self.seed, **params)

    @property
    def time(self) -> float:
        """Current time of the engine, in units of sqrt(m/k_p)."""
        return self._engine.time

    @property
    def critical_stress(self) -> float:
        """u_c of the front-speed law (gamma for the exact law)."""
        return self._engine.critical_stress

    def u(self) -> np.ndarray:
        """u at the nodes now, shape (ny, nx).

        Returns
        -------
        numpy.ndarray
            u (dimensionless).

        Examples
        --------
        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.0, dx=1e-3), (9, 5), 1.0, 0.6)
        >>> fb.u().shape, float(fb.u().max())
        ((5, 9), 0.6)
        """
        return np.asarray(self._engine.u_nodes()).reshape(self.ny, self.nx)

    def last_arrival(self) -> np.ndarray:
        """The last arrival time of a front at each node, (ny, nx), NaN where none passed.

        Returns
        -------
        numpy.ndarray
            Times in units of sqrt(m/k_p).

        Examples
        --------
        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.0, dx=1e-3), (81, 81), 0.5, 0.6,
        ...                        "free")
        >>> _ = fb.trigger(20.0, 20.0, radius=1.0)
        >>> _ = fb.run(max_events=1)
        >>> round(float(fb.last_arrival()[40, 80]), 6)
        15.0
        """
        return np.asarray(self._engine.last_arrival()).reshape(self.ny, self.nx)

    def trigger(self, x: float, y: float, radius: float = 0.0) -> int:
        """Start a rupture now on the disk of ``radius`` around (x, y) (at least the
        nearest node); returns its id. Refused where a rupture is running.

        Parameters
        ----------
        x, y : float
            The centre (dimensionless, the paper's x).
        radius : float, default 0
            The disk's radius, >= 0 (dimensionless x).

        Returns
        -------
        int
            The rupture's id.

        Examples
        --------
        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.0, dx=1e-3), (41, 41), 1.0, 0.6)
        >>> fb.trigger(10.0, 10.0), fb.trigger(30.0, 30.0)
        (0, 1)
        """
        x, y = V.number("x", x), V.number("y", y)
        radius = V.number("radius", radius, lo=0.0)
        return self._engine.trigger_disk(x, y, radius)

    def arrival_time(self, rupture: int) -> np.ndarray:
        """The arrival time of rupture ``rupture`` at each node, (ny, nx), NaN outside it
        (needs ``record_arrivals=True`` and a complete rupture).

        Parameters
        ----------
        rupture : int
            The rupture's id.

        Returns
        -------
        numpy.ndarray
            Times in units of sqrt(m/k_p).

        Examples
        --------
        Along the diagonal the front needs (sqrt(2) 20 - 1)/c = 21.8 to reach the corner:

        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.0, dx=1e-3), (81, 81), 0.5, 0.6,
        ...                        "free", record_arrivals=True)
        >>> rid = fb.trigger(20.0, 20.0, radius=1.0)
        >>> _ = fb.run(max_events=1)
        >>> round(float(fb.arrival_time(rid)[0, 0]), 1)
        22.0
        """
        if not self.record_arrivals:
            V._fail("record_arrivals", False, "True to keep arrival times (FreeBoundary2D(...))")
        nodes, times = self._engine.arrivals(V.integer("rupture", rupture, lo=0))
        out = np.full(self.nx * self.ny, np.nan)
        out[np.asarray(nodes, dtype=np.int64)] = times
        return out.reshape(self.ny, self.nx)

    def _take_snapshot(self):
        t = self._engine.time
        if self._snap_t and self._snap_t[-1] == t:
            return
        self._snap_t.append(t)
        self._snap_u.append(self.u())
        self._snap_live.append(self._engine.live)

    # ------------------------------------------------------------------ run
    def run(
        self,
        t_end: float | None = None,
        *,
        max_events: int | None = None,
        snapshots=None,
        progress: bool = False,
        chunk: int = 200000,
    ) -> FreeBoundary2DResult:
        """Advance to ``t_end`` or until ``max_events`` more ruptures are complete.
        ``snapshots``: an int n (n evenly spaced times up to a finite t_end) or an array
        of times; the state is recorded at the start and the end too. Ctrl-C returns what
        was computed (``result.interrupted``); ``run`` again continues.

        Parameters
        ----------
        t_end : float, optional
            End time (units of sqrt(m/k_p)).
        max_events : int, optional
            Stop after this many more complete ruptures.
        snapshots : int or array_like, optional
            n evenly spaced snapshot times, or the times (units of sqrt(m/k_p)).
        progress : bool, default False
            Show a progress bar.
        chunk : int, default 200000
            Engine steps between checks for Ctrl-C.

        Returns
        -------
        FreeBoundary2DResult
            Everything since the engine was built.

        Examples
        --------
        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.0, dx=1e-3), (41, 41), 1.0, 0.6)
        >>> _ = fb.trigger(20.0, 20.0)
        >>> res = fb.run(t_end=40.0, snapshots=5)
        >>> res.ruptures.complete.tolist(), res.snapshots.t.values.tolist()
        ([True], [0.0, 10.0, 20.0, 30.0, 40.0])
        """
        from .free_boundary import run_window

        t0 = self.time
        t_end, max_events, times = run_window(t0, t_end, max_events, snapshots, 10**6)
        target = 2**62 if max_events is None else self._engine.completed + max_events
        chunk = V.integer("chunk", chunk, lo=1)
        interrupted = False
        bar = RunProgress(
            V.flag("progress", progress),
            "free boundary 2D",
            t0,
            t_end,
            max_events,
            self._engine.completed,
        )
        try:
            for stop in [*times.tolist(), t_end]:
                while True:
                    status = self._engine.advance(float(stop), chunk, target)
                    bar.advance(self._engine.time, self._engine.completed)
                    if status != "steps":
                        break
                if status == "events":
                    break
                if math.isfinite(stop):
                    self._take_snapshot()
        except KeyboardInterrupt:
            interrupted = True
            warnings.warn(
                f"free boundary 2D run interrupted at t = {self.time:.6g}; "
                "returning the results computed so far",
                RuntimeWarning,
                stacklevel=2,
            )
        finally:
            bar.close()
        self._take_snapshot()
        return self.result(interrupted=interrupted)

    def result(self, interrupted: bool = False) -> FreeBoundary2DResult:
        """The results recorded since the engine was built.

        Parameters
        ----------
        interrupted : bool, default False
            Mark the result as that of an interrupted run.

        Returns
        -------
        FreeBoundary2DResult
            Ruptures and snapshots.

        Examples
        --------
        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.0, dx=1e-3), (41, 41), 1.0, 0.6)
        >>> len(fb.result().ruptures), fb.result().interrupted
        (0, False)
        """
        import pandas as pd
        import xarray as xr

        cat = self._engine.ruptures()
        order = [
            "id",
            "origin",
            "t_start",
            "t_end",
            "duration",
            "x_start",
            "y_start",
            "u_start",
            "n_nodes",
            "area",
            "moment",
            "mean_slip",
            "perimeter",
            "n_stopped",
            "n_creep",
            "contacts",
            "complete",
        ]
        ru = pd.DataFrame({k: cat[k] for k in order})
        meta = {
            "engine": "free_boundary_2d",
            "params": json.dumps(self.params.to_dict(), default=str),
            "units": "dimensionless (paper eq. dimless)",
            "bkwaves_version": _core.__version__,
            "boundary": json.dumps(self.boundary),
            "creep_rule": self.creep,
            "grid_spacing": self.h,
            "stencil": "second order" if self.second_order else "first order",
            "noise": json.dumps(self.noise),
            "seed": -1 if self.seed is None else self.seed,
            "speed": "exact" if self.speed is None else json.dumps(self.speed),
            "threshold": "uniform 1" if self.threshold is None else "field: variable threshold",
        }
        if self.curvature is not None:
            meta["curvature"] = json.dumps(self.curvature)
        if self.speed_diagonal is not None:
            meta["speed_diagonal"] = json.dumps(self.speed_diagonal)
        counters = self._engine.noise_counters
        if counters is not None:
            meta["noise_candidates"], meta["noise_nucleations"] = counters
        data = {
            "u": (("t", "y", "x"), np.array(self._snap_u), {"long_name": "slow field u"}),
            "live": (("t",), np.array(self._snap_live), {"long_name": "running ruptures"}),
        }
        if self.threshold is not None:
            data["threshold"] = (("y", "x"), self.threshold, {"long_name": "static threshold s"})
        ds = xr.Dataset(
            data,
            coords={
                "t": ("t", np.array(self._snap_t), {"long_name": "time", "units": "1"}),
                "y": ("y", self.y, {"long_name": "position across", "units": "1"}),
                "x": ("x", self.x, {"long_name": "position along the slip", "units": "1"}),
            },
            attrs=meta,
        )
        return FreeBoundary2DResult(ru, ds, interrupted, self._engine.steps, meta)

    # ------------------------------------------------------------------ checkpoints
    def _record(self) -> tuple[dict, dict]:
        from ._checkpoint import params_record

        meta = {
            "params": params_record(self.params),
            "shape": [self.nx, self.ny],
            "h": self.h,
            "origin": list(self.origin),
            "boundary": list(self.boundary),
            "creep": self.creep,
            "second_order": self.second_order,
            "record_arrivals": self.record_arrivals,
            "noise": self.noise,
            "seed": self.seed,
            "speed": self.speed,
            "curvature": self.curvature,
            "speed_diagonal": self.speed_diagonal,
        }
        arrays = {
            "engine": np.frombuffer(self._engine.checkpoint(), dtype=np.uint8),
            "snap_t": np.asarray(self._snap_t, dtype=float),
            "snap_u": np.asarray(self._snap_u, dtype=float).reshape(-1, self.ny, self.nx),
            "snap_live": np.asarray(self._snap_live, dtype=np.int64),
            "threshold": np.zeros(0) if self.threshold is None else self.threshold,
        }
        return meta, arrays

    def save(self, path) -> None:
        """Write a checkpoint of the whole state, snapshots included (data only, never a
        pickle). ``FreeBoundary2D.load(path).run(...)`` continues bit for bit like the
        uninterrupted run when it makes the same engine calls.

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file (npz).

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.01, dx=1e-3), (41, 41), 1.0, 0.6)
        >>> _ = fb.run(t_end=10.0)
        >>> path = os.path.join(tempfile.mkdtemp(), "fb2d.npz")
        >>> fb.save(path)
        >>> again = bk.FreeBoundary2D.load(path)
        >>> bool((fb.run(t_end=50.0).snapshots.u == again.run(t_end=50.0).snapshots.u).all())
        True
        """
        from . import _checkpoint

        _checkpoint.write(path, "free_boundary_2d", *self._record())

    @staticmethod
    def load(path) -> FreeBoundary2D:
        """Read a checkpoint written by :meth:`save` (others are refused).

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file.

        Returns
        -------
        FreeBoundary2D
            The engine as saved.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> fb = bk.FreeBoundary2D(bk.Params(gamma=0.3, v=0.01, dx=1e-3), (41, 41), 1.0, 0.6)
        >>> _ = fb.run(t_end=10.0)
        >>> path = os.path.join(tempfile.mkdtemp(), "fb2d.npz")
        >>> fb.save(path)
        >>> bk.FreeBoundary2D.load(path).time
        10.0
        """
        from . import _checkpoint

        meta, arrays = _checkpoint.read(path, "free_boundary_2d", "FreeBoundary2D.save")
        return FreeBoundary2D._from_record(meta, arrays, path)

    @staticmethod
    def _from_record(meta: dict, arrays: dict, source) -> FreeBoundary2D:
        """The engine of a record (:meth:`_record`, read from ``source``)."""
        from ._checkpoint import params_from_record, restore_engine

        fb = FreeBoundary2D.__new__(FreeBoundary2D)
        fb.params = params_from_record(meta["params"])
        fb.nx, fb.ny = (int(n) for n in meta["shape"])
        fb.h = float(meta["h"])
        fb.origin = tuple(float(o) for o in meta["origin"])
        fb.boundary = tuple(meta["boundary"])
        fb.creep = meta["creep"]
        fb.second_order = bool(meta["second_order"])
        fb.record_arrivals = bool(meta["record_arrivals"])
        fb.noise, fb.seed, fb.speed = meta.get("noise"), meta.get("seed"), meta.get("speed")
        # (checkpoints from before the shape options have neither key)
        fb.curvature = meta.get("curvature")
        fb.speed_diagonal = meta.get("speed_diagonal")
        fb.x = fb.origin[0] + fb.h * np.arange(fb.nx)
        fb.y = fb.origin[1] + fb.h * np.arange(fb.ny)
        th = arrays.get("threshold")
        fb.threshold = None if th is None or th.size == 0 else np.array(th, dtype=float)
        u0 = np.zeros((fb.ny, fb.nx)) if fb.threshold is None else 0.5 * fb.threshold
        fb._engine = fb._new_engine(u0)
        fb._set_noise()
        restore_engine(fb._engine, arrays, source)
        fb._snap_t = [float(t) for t in arrays["snap_t"]]
        fb._snap_u = [np.array(u) for u in arrays["snap_u"]]
        fb._snap_live = [int(n) for n in arrays["snap_live"]]
        return fb
