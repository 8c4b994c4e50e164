"""The plane: the Burridge-Knopoff lattice simulated exactly (docs/lattice.md).

>>> import bkwaves as bk
>>> p = bk.Params(gamma=0.45, v=0.0, dx=0.1)
>>> la = bk.Lattice((40, 30), p, u0=0.7)
>>> la = la.kick((20, 15), -2.0)        # a rupture from a block near the centre
>>> res = la.run(t_end=1.0, progress=False)
>>> res.first_slip_times().shape        # arrival times, shaped (ny, nx)
(30, 40)

Blocks (i, j) on a square lattice, one scalar displacement each, springs along x at
spacing dx = sqrt(k_p/k_x) (``params.dx``) and across at dy = sqrt(k_p/k_y) (default dx):
phi = u - (u_{i+1,j} + u_{i-1,j} - 2 u)/dx^2 - (u_{i,j+1} + u_{i,j-1} - 2 u)/dy^2, with
stick, slip, sliding and loading as in the chain (``bkwaves.chain``): the same engine,
on a geometry where a block has four neighbours. Arrays of the lattice are shaped
(ny, nx): row j, column i; block number k = i + nx j in the slip records.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _validate as V
from .chain import DEFAULT_STEP, INTEGRATORS, UNITS, Chain, ChainResult

__all__ = [
    "FRONT_TOLERANCE",
    "Lattice",
    "LatticeResult",
    "PlanarFront",
    "Rupture",
    "default_max_event_duration",
    "front",
    "rupture",
]


#: The largest change of a planar front's c (units of the sound speed) when the lattice is
#: doubled that ``front`` accepts as converged (the chain's ``FRONT_TOLERANCE`` for c).
FRONT_TOLERANCE = 1e-6


def default_max_event_duration(shape, dx: float, dy: float | None = None) -> float:
    """The runaway bound on the duration of one event of a lattice (``Lattice.run``,
    ``run.max_event_duration`` of a lattice config): 100 times the time sound takes to
    cross the lattice's longer side (+1 for small lattices), as the chain's bound is of
    the chain (docs/lattice.md, "An event's duration").

    Parameters
    ----------
    shape : tuple of int
        (nx, ny) blocks.
    dx : float
        Spacing along x (dimensionless).
    dy : float, optional
        Spacing along y (dimensionless); default dx.

    Returns
    -------
    float
        The bound, in units of sqrt(m/k_p) (the speed of sound is 1).

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.lattice.default_max_event_duration((200, 100), 0.1)
    2100.0
    """
    nx, ny = shape
    dy = dx if dy is None else dy
    return 100.0 * (max(nx * dx, ny * dy) + 1.0)


@dataclass
class LatticeResult(ChainResult):
    """What ``Lattice.run`` returns: a ``bkwaves.chain.ChainResult`` whose
    arrays are shaped like the lattice, (ny, nx), whose slips carry the block's column i,
    row j and position (x, y) = (i dx, j dy), whose catalog has each event's hypocentre
    (the block that slipped first: i, j, x, y), ``area`` (blocks slipped x dx dy),
    ``moment`` (the integral of slip over the area: dx dy x the sum of the blocks' slips)
    and ``duration``, and whose snapshots are
    an xarray Dataset with dims (t, y, x).

    Parameters
    ----------
    params, t, energy, counters, interrupted, stop, wall_s, seed, u, u_t, boundary
        As in ``bkwaves.chain.ChainResult`` (t and wall_s: units of sqrt(m/k_p) and
        seconds; u, u_t dimensionless, here of shape (ny, nx)).
    shape : tuple of int
        (nx, ny).
    dy : float
        The spacing across (dimensionless).

    Examples
    --------
    >>> import bkwaves as bk
    >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
    >>> res = la.kick((20, 15), -2.0).run(t_end=1.0)
    >>> res.shape, res.u.shape, res.first_slip_times().shape
    ((40, 30), (30, 40), (30, 40))
    """

    shape: tuple[int, int] = (0, 0)
    dy: float = math.nan

    def first_slip_times(self, event: int | None = None) -> np.ndarray:
        """First slip time of every block, shape (ny, nx) (NaN if it did not slip),
        optionally within one event: the arrival times of a rupture.

        Parameters
        ----------
        event : int, optional
            Only the slips of this event (catalog row); default all.

        Returns
        -------
        numpy.ndarray
            Times in units of sqrt(m/k_p), shape (ny, nx).

        Examples
        --------
        The kicked block slips first, its neighbours along x and along y (dx = dy) at
        the same time:

        >>> import bkwaves as bk
        >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
        >>> t = la.kick((20, 15), -2.0).run(t_end=1.0).first_slip_times()
        >>> float(t[15, 20]), bool(t[15, 21] == t[16, 20] > 0)
        (0.0, True)
        """
        nx, ny = self.shape
        out = np.full(nx * ny, np.nan)
        s = self.slips if event is None else self.slips[self.slips["event"] == event]
        first = s.groupby("block")["t_start"].min()
        out[first.index.to_numpy()] = first.to_numpy()
        return out.reshape(ny, nx)

    def slip_map(self, event: int | None = None) -> np.ndarray:
        """Total slip of every block (finished slips), shape (ny, nx), optionally within
        one event.

        Parameters
        ----------
        event : int, optional
            Only the slips of this event (catalog row); default all.

        Returns
        -------
        numpy.ndarray
            Slip (dimensionless, a change of u; 0 where none), shape (ny, nx).

        Examples
        --------
        >>> import bkwaves as bk
        >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
        >>> s = la.kick((20, 15), -2.0).run(t_end=3.0).slip_map()
        >>> s.shape, bool(s[15, 20] > 0), float(s[0, 0])
        ((30, 40), True, 0.0)
        """
        nx, ny = self.shape
        s = self.slips if event is None else self.slips[self.slips["event"] == event]
        total = s.groupby("block")["slip"].sum(min_count=1)
        out = np.zeros(nx * ny)
        out[total.index.to_numpy()] = np.nan_to_num(total.to_numpy())
        return out.reshape(ny, nx)

    def ruptures(self):
        """The ruptures of the run: its events split into the slip of single nucleations
        (docs/lattice.md, "Ruptures"), as the config route's ruptures table.

        Returns
        -------
        pandas.DataFrame
            One row per rupture (``bkwaves._lattice_ruptures.COLUMNS``): start, end and
            duration (units of sqrt(m/k_p)), hypocentre (x_start, y_start, i_start,
            j_start), u_start, n_blocks, area (dimensionless x'^2), moment (int slip dA),
            magnitude, mean_slip, perimeter, kind, spontaneous, event, complete.

        Examples
        --------
        Two blocks kicked far apart: one event, two ruptures whose moments add up to it:

        >>> import bkwaves as bk
        >>> la = bk.Lattice((24, 18), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
        >>> res = la.kick((2, 2), -2.0).kick((20, 15), -2.0, 0.1).run(t_end=6.0)
        >>> ru = res.ruptures()
        >>> len(res.catalog), len(ru), round(float(ru.moment.sum() / res.catalog.moment[0]), 12)
        (1, 2, 1.0)
        """
        from ._lattice_ruptures import lattice_ruptures

        nx, ny = self.shape
        boundary = tuple(self.boundary.split(" x "))
        return lattice_ruptures(self.slips, nx, ny, self.params.dx, self.dy, boundary)


#: What the moment of an event on the lattice is.
PLANAR_MOMENT = (
    "the event's moment: the integral of slip over the area, dx dy times the sum of its "
    "blocks' slips"
)


def _planar_slips(s, nx: int, dx: float, dy: float):
    """The chain engine's slip records of a lattice of ``nx`` columns with each block's
    column i, row j and position (x, y) = (i dx, j dy) (block k = i + nx j)."""
    i, j = s["block"] % nx, s["block"] // nx
    s["x"] = i * dx
    s.insert(3, "y", j * dy)
    s.insert(2, "i", i)
    s.insert(3, "j", j)
    return s


def _planar_catalog(cat, nx: int, dx: float, dy: float, moment_scale: float):
    """The chain engine's event catalog of a lattice of ``nx`` columns: the hypocentre
    (i, j, x, y) of each event (its nucleation block), its area (blocks slipped x dx dy),
    and its moment times ``moment_scale`` (the engine sums block slips: dx dy for int
    slip dA; dy for a chain catalog whose moment is int slip dx already); the chain's
    first and last block dropped (no extent along a line)."""
    c = cat.drop(columns=["first_block", "last_block"])
    c["moment"] = c["moment"] * moment_scale
    hi, hj = c["nucleation"] % nx, c["nucleation"] // nx
    c.insert(4, "hypocentre_i", hi)
    c.insert(5, "hypocentre_j", hj)
    c.insert(6, "hypocentre_x", hi * dx)
    c.insert(7, "hypocentre_y", hj * dy)
    c["area"] = c["n_blocks"] * dx * dy
    return c


def _bonds(name, value, shape) -> np.ndarray | None:
    """Per-bond springs (a scalar or an array of ``shape``) as the engine takes them, row
    after row: None for all 1, finite values >= 0 (a zero bond cuts the lattice)."""
    if value is None:
        return None
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        V._fail(name, value, f"a scalar or an array of shape {shape}")
    if a.ndim == 0:
        if a == 1.0:
            return None
        a = np.full(shape, float(a))
    if a.shape != tuple(shape):
        V._fail(name, f"array of shape {a.shape}", f"a scalar or an array of shape {shape}")
    bad = np.argwhere(~(np.isfinite(a) & (a >= 0)))
    if bad.size:
        at = tuple(int(x) for x in bad[0])
        V._fail(f"{name}[{at[0]}, {at[1]}]", float(a[at]), "finite springs >= 0")
    return np.ascontiguousarray(a.ravel(), dtype=float)


def _pair(name, value, allowed) -> tuple:
    if isinstance(value, str):
        return (value, value)
    if isinstance(value, tuple | list) and len(value) == 2:
        return tuple(value)
    V._fail(name, value, allowed)


class Lattice(Chain):
    """A lattice of nx x ny blocks with the chain's friction, loading and sources.

    ``kick`` and ``release`` take a block (i, j), a line or a disc of blocks (``blocks``).

    Parameters
    ----------
    shape : tuple of int
        (nx, ny) blocks, each >= 1.
    params : bkwaves.Params
        gamma, v and beta (dimensionless); its dx is the spacing along x.
    u0 : float or array_like, default 0
        Initial stress (dimensionless), a scalar or an array shaped (ny, nx).
    u_t0 : float or array_like, optional
        Initial du/dt (dimensionless), a scalar or (ny, nx) values; default v.
    dy : float, optional
        The spacing across, sqrt(k_p/k_y) (dimensionless); default dx.
    boundary : str or tuple of str, default "free"
        One of ``BOUNDARIES`` for both axes, or a pair (across x, across y).
    step : float, default 0.05
        Time step as a fraction of min(dx, dy) (in units of sqrt(m/k_p)).
    fixed : tuple, optional
        Wall positions u_wall at t = 0 of fixed sides, ((x low, x high), (y low, y
        high)) (dimensionless; default the mean initial u of the blocks along that side).
    seed, integrator, step_tolerance, noise
        As for ``bkwaves.Chain``.
    events : {"local", "global"}, optional
        How slips and sticks are located, as for ``bkwaves.Chain``: "local" redoes only
        the neighbourhood of a switch (a rupture over N x N blocks costs ~N^2
        block-steps instead of ~N^3; the same order in the step; docs/lattice.md, "Local
        events"), "global" the step of every sliding block. Default: "local" where it
        applies (rk4 at a fixed step, a law whose onset takes no sub-steps), else
        "global"; "local" asked for where it cannot apply is refused.
    threshold, mass, loader : float or array_like, optional
        Per-block properties, a scalar or (ny, nx) values, in units of the reference
        values of ``params``.
    coupling : tuple, optional
        Per-bond springs (k_x, k_y) in units of the uniform ones (dimensionless; dx and
        dy stay the spacings), each a scalar or an array: k_x shaped (ny, bonds of a row
        along x), k_y (bonds of a column along y, nx). A line of n blocks has n - 1 bonds
        between free sides (bond b joins blocks b and b + 1), n + 1 with walls (the first
        joins the wall and block 0) and n periodic (the last joins block n - 1 and block
        0); values >= 0 (a zero bond cuts the lattice).

    Examples
    --------
    A rupture from a block near the centre; along the axes (dx = dy) the front reaches
    the same distance at the same time:

    >>> import bkwaves as bk
    >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
    >>> res = la.kick((20, 15), -2.0).run(t_end=1.0)
    >>> t = res.first_slip_times()
    >>> bool(t[15, 25] == t[20, 20])
    True
    """

    def __init__(
        self,
        shape,
        params,
        u0=0.0,
        u_t0=None,
        *,
        dy: float | None = None,
        boundary="free",
        step: float = DEFAULT_STEP,
        fixed=None,
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
        if not (isinstance(shape, tuple | list) and len(shape) == 2):
            V._fail("shape", shape, "a pair (nx, ny) of block counts >= 1")
        nx = V.integer("shape[0]", shape[0], lo=1)
        ny = V.integer("shape[1]", shape[1], lo=1)
        self.shape = (int(nx), int(ny))
        dx = float(params.dx) if hasattr(params, "dx") else math.nan
        self.dy = dx if dy is None else V.number("dy", dy, lo=0.0, lo_open=True, hi=1e6)
        bx, by = _pair("boundary", boundary, "a boundary name or a pair (across x, across y)")
        by = V.CHAIN["boundary"].check(by)
        self.boundary_y = by
        flat = [self._flat(k, x) for k, x in (("u0", u0), ("u_t0", u_t0))]
        props = {
            k: self._flat(k, x)
            for k, x in (("threshold", threshold), ("mass", mass), ("loader", loader))
        }
        u = np.broadcast_to(np.asarray(flat[0], dtype=float), (nx * ny,)).reshape(ny, nx)
        if fixed is None:
            fx = (float(u[:, 0].mean()), float(u[:, -1].mean()))
            fy = (float(u[0].mean()), float(u[-1].mean()))
        else:
            fx, fy = _pair("fixed", fixed, "((x low, x high), (y low, y high)) wall positions")
            fx, fy = tuple(fx), tuple(fy)
        self.fixed_y = (V.number("fixed[1][0]", fy[0]), V.number("fixed[1][1]", fy[1]))
        super().__init__(
            nx * ny,
            params,
            boundary=bx,
            u0=flat[0],
            u_t0=flat[1],
            step=step,
            fixed=fx,
            seed=seed,
            integrator=integrator,
            step_tolerance=step_tolerance,
            noise=noise,
            coupling=coupling,
            events=events,
            **props,
        )
        if self._coupling_y is not None:
            self.properties["coupling_y"] = self._coupling_y

    #: Local events where they apply (``events``): a rupture's cost grows like its area.
    default_events = "local"

    def _property(self, name, value, boundary):
        """Per-block properties as the chain's; ``coupling`` a pair (k_x, k_y) of per-bond
        springs: the engine's x bonds (returned) and y bonds (kept for ``_geometry``)."""
        if name != "coupling":
            return super()._property(name, value, boundary)
        self._coupling_y = None
        if value is None:
            return None
        if not (isinstance(value, tuple | list) and len(value) == 2):
            V._fail("coupling", value, "a pair (k_x, k_y) of per-bond springs (or None)")
        nx, ny = self.shape
        count = {"free": -1, "fixed": 1, "periodic": 0}
        kx = _bonds("coupling[0]", value[0], (ny, nx + count[boundary]))
        self._coupling_y = _bonds("coupling[1]", value[1], (ny + count[self.boundary_y], nx))
        return kx

    def _flat(self, name, value):
        """A scalar, or (ny, nx) values as the engine's block order (row after row)."""
        if value is None:
            return None
        a = np.asarray(value, dtype=float) if not isinstance(value, str) else value
        if isinstance(a, np.ndarray) and a.ndim == 2:
            nx, ny = self.shape
            if a.shape != (ny, nx):
                want = f"a scalar or shape (ny, nx) = {(ny, nx)}"
                V._fail(name, f"array of shape {a.shape}", want)
            return a.ravel()
        if isinstance(a, np.ndarray) and a.ndim == 0:
            return float(a)
        V._fail(name, value, f"a scalar or an array of shape (ny, nx) = {self.shape[::-1]}")

    def _max_event_duration(self) -> float:
        return default_max_event_duration(self.shape, self.params.dx, self.dy)

    def _geometry(self) -> dict:
        return {
            "coupling_y": self._coupling_y,
            "shape": self.shape,
            "dy": self.dy,
            "boundary_y": self.boundary_y,
            "fixed_y": self.fixed_y,
        }

    # --- checkpoints -----------------------------------------------------------------
    def _record(self) -> tuple[dict, dict]:
        meta, arrays = super()._record()
        meta.update(
            shape=list(self.shape),
            dy=self.dy,
            boundary_y=self.boundary_y,
            fixed_y=list(self.fixed_y),
        )
        return meta, arrays

    def _restore(self, meta: dict, arrays: dict, source="the checkpoint") -> None:
        from ._checkpoint import params_from_record, restore_engine

        props = {
            k: arrays[f"property_{k}"]
            for k in ("threshold", "mass", "loader")
            if f"property_{k}" in arrays
        }
        nx, ny = meta["shape"]
        nx, ny = int(nx), int(ny)
        bonds = [arrays.get(f"property_{k}") for k in ("coupling", "coupling_y")]
        count = {"free": -1, "fixed": 1, "periodic": 0}
        coupling = None
        if any(b is not None for b in bonds):
            kx, ky = (1.0 if b is None else np.asarray(b) for b in bonds)
            if bonds[0] is not None:
                kx = kx.reshape(ny, nx + count[meta["boundary"]])
            if bonds[1] is not None:
                ky = ky.reshape(ny + count[meta["boundary_y"]], nx)
            coupling = (kx, ky)
        Lattice.__init__(
            self,
            (int(nx), int(ny)),
            params_from_record(meta["params"]),
            dy=meta["dy"],
            boundary=(meta["boundary"], meta["boundary_y"]),
            fixed=(tuple(meta["fixed"]), tuple(meta["fixed_y"])),
            step=meta["step"],
            integrator=meta["integrator"],
            step_tolerance=meta.get("step_tolerance"),
            # (checkpoints written before the choice existed ran the global cut)
            events=meta.get("events", "global"),
            seed=meta["seed"],
            noise=meta.get("noise"),
            coupling=coupling,
            **{k: np.asarray(x).reshape(ny, nx) for k, x in props.items()},
        )
        restore_engine(self._engine, arrays, source)
        self._e0 = meta["e0"]

    def save(self, path) -> None:
        """Write a checkpoint (as ``bkwaves.Chain.save``, of kind "lattice").

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file (npz).

        Examples
        --------
        >>> import os, tempfile
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
        >>> _ = la.kick((20, 15), -2.0).run(t_end=0.5)
        >>> path = os.path.join(tempfile.mkdtemp(), "lattice.npz")
        >>> la.save(path)
        >>> again = bk.Lattice.load(path)
        >>> np.array_equal(la.run(t_end=1.0).u, again.run(t_end=1.0).u)
        True
        """
        from . import _checkpoint

        _checkpoint.write(path, "lattice", *self._record())

    @staticmethod
    def load(path) -> Lattice:
        """Read a checkpoint written by ``save``.

        Parameters
        ----------
        path : str or pathlib.Path
            The checkpoint file.

        Returns
        -------
        Lattice
            The lattice as saved.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
        >>> path = os.path.join(tempfile.mkdtemp(), "lattice.npz")
        >>> la.save(path)
        >>> bk.Lattice.load(path).shape
        (40, 30)
        """
        from . import _checkpoint

        meta, arrays = _checkpoint.read(path, "lattice", "Lattice.save")
        return Lattice._from_record(meta, arrays, path)

    # --- triggers --------------------------------------------------------------------
    def kick(self, block, du_t: float, t: float = 0.0) -> Lattice:
        """Schedule a kick (``bkwaves.Chain.kick``) of one block (i, j), of the blocks on
        a line, ``{"line": ((i0, j0), (i1, j1))}``, or of those in a disc,
        ``{"disc": ((i, j), radius)}`` (``blocks`` gives the set): each gets du_t at
        time t.

        Parameters
        ----------
        block : tuple of int or dict
            A block (i, j), a line or a disc (above).
        du_t : float
            The change of du/dt (dimensionless; negative: a forward kick).
        t : float, default 0
            When (>= the lattice's time), in units of sqrt(m/k_p).

        Returns
        -------
        Lattice
            The lattice itself.

        Examples
        --------
        >>> import bkwaves as bk
        >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
        >>> res = la.kick({"line": ((0, 0), (0, 29))}, -2.0).run(t_end=2.0)
        >>> t = res.first_slip_times()        # a planar front from the left edge
        >>> bool((t[:, 10] == t[0, 10]).all())
        True
        """
        du_t = V.number("du_t", du_t, lo=-1e6, hi=1e6)
        t = V.number("t", t, lo=self.t)
        for k in self._region(block):
            self._engine.add_trigger(t, k, "kick", du_t)
        self._pending = [*getattr(self, "_pending", []), t]  # (for the run-cost estimate)
        return self

    def release(self, block, t: float = 0.0, direction: int = 1) -> Lattice:
        """Schedule a release (``bkwaves.Chain.release``) of one block (i, j), of a line
        or of a disc (as ``kick``).

        Parameters
        ----------
        block : tuple of int or dict
            A block (i, j), a line or a disc.
        t : float, default 0
            When (>= the lattice's time), in units of sqrt(m/k_p).
        direction : {1, -1}
            Forward (+1) or backward (-1, needs a finite ``params.beta``).

        Returns
        -------
        Lattice
            The lattice itself.

        Examples
        --------
        >>> import numpy as np
        >>> import bkwaves as bk
        >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.95)
        >>> t = la.release((20, 15)).run(t_end=1.0).first_slip_times()
        >>> int(np.isfinite(t).sum())                  # every block has slipped
        1200
        """
        t = V.number("t", t, lo=self.t)
        direction = V.direction("direction", direction)
        for k in self._region(block):
            self._engine.add_trigger(t, k, "release", float(direction))
        self._pending = [*getattr(self, "_pending", []), t]
        return self

    def blocks(self, region) -> np.ndarray:
        """The blocks (i, j) of a trigger region, shape (m, 2), in block order (row after
        row): a block (i, j); ``{"line": ((i0, j0), (i1, j1))}``, the blocks nearest to
        the segment, one per step along its longer axis (a row, a column or a diagonal
        exactly); ``{"disc": ((i, j), radius)}``, the blocks whose centres are within
        ``radius`` of block (i, j)'s in (x, y) = (i dx, j dy) (radius in units of x, as
        dx; a circle in the plane, an ellipse of axes radius/dx, radius/dy in blocks).

        Parameters
        ----------
        region : tuple of int or dict
            A block, a line or a disc (radius dimensionless, the paper's x).

        Returns
        -------
        numpy.ndarray
            The blocks' (i, j), shape (m, 2).

        Examples
        --------
        >>> import bkwaves as bk
        >>> la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
        >>> la.blocks({"disc": ((20, 15), 0.1)}).tolist()      # radius dx: 4 neighbours
        [[20, 14], [19, 15], [20, 15], [21, 15], [20, 16]]
        >>> la.blocks({"line": ((0, 0), (3, 3))}).tolist()
        [[0, 0], [1, 1], [2, 2], [3, 3]]
        """
        k = np.asarray(self._region(region))
        nx = self.shape[0]
        return np.column_stack([k % nx, k // nx])

    def _region(self, region) -> list[int]:
        nx, ny = self.shape
        if not isinstance(region, dict):
            return [self._block(region)]
        if len(region) != 1 or next(iter(region)) not in ("line", "disc"):
            V._fail(
                "block",
                region,
                'a block (i, j), {"line": ((i0, j0), (i1, j1))} or {"disc": ((i, j), radius)}',
            )
        ((kind, spec),) = region.items()
        if not (isinstance(spec, tuple | list) and len(spec) == 2):
            want = "((i0, j0), (i1, j1))" if kind == "line" else "((i, j), radius)"
            V._fail(kind, spec, f"a pair {want}")
        if kind == "line":
            a, b = (self._block(e) for e in spec)
            (i0, j0), (i1, j1) = (a % nx, a // nx), (b % nx, b // nx)
            m = max(abs(i1 - i0), abs(j1 - j0))
            s = np.arange(m + 1) / max(m, 1)
            # (rint depends on the value only: a segment gives the same blocks either way)
            ii = np.rint(i0 + s * (i1 - i0)).astype(int)
            jj = np.rint(j0 + s * (j1 - j0)).astype(int)
            return sorted(set((ii + nx * jj).tolist()))
        c = self._block(spec[0])
        ic, jc = c % nx, c // nx
        r = V.number("radius", spec[1], lo=0.0, hi=1e9)
        dx, dy = self.params.dx, self.dy
        j, i = np.mgrid[0:ny, 0:nx]
        inside = ((i - ic) * dx) ** 2 + ((j - jc) * dy) ** 2 <= r * r
        return np.flatnonzero(inside.ravel()).tolist()

    # --- blocks and state ------------------------------------------------------------
    def _block(self, block) -> int:
        nx, ny = self.shape
        if (
            isinstance(block, tuple | list)
            and len(block) == 2
            and all(V._is_int(b) for b in block)
            and 0 <= int(block[0]) < nx
            and 0 <= int(block[1]) < ny
        ):
            return int(block[0]) + nx * int(block[1])
        V._fail("block", block, f"a pair (i, j) with 0 <= i < {nx}, 0 <= j < {ny}")

    def _grid(self, a: np.ndarray) -> np.ndarray:
        nx, ny = self.shape
        return np.asarray(a).reshape(ny, nx)

    @property
    def u(self) -> np.ndarray:
        """The stress u of every block, shape (ny, nx) (dimensionless)."""
        return self._grid(self._engine.u())

    @property
    def u_t(self) -> np.ndarray:
        """du/dt of every block, shape (ny, nx) (dimensionless)."""
        return self._grid(self._engine.u_t())

    @property
    def phi(self) -> np.ndarray:
        """u - (x and y Laplacians)/(dx^2, dy^2), shape (ny, nx) (dimensionless)."""
        return self._grid(self._engine.phi())

    @property
    def modes(self) -> np.ndarray:
        """0 stuck, +1 sliding forward, -1 sliding backward, shape (ny, nx)."""
        return self._grid(self._engine.modes())

    # --- outputs ---------------------------------------------------------------------
    def _result(self, stop, interrupted, wall) -> LatticeResult:
        r = super()._result(stop, interrupted, wall)
        nx, ny = self.shape
        dx, dy = self.params.dx, self.dy
        chain_catalog, chain_slips = r._build["catalog"], r._build["slips"]
        chain_snapshots = r._build["snapshots"]
        boundary = f"{self.boundary} x {self.boundary_y}"

        def slips():
            s = _planar_slips(chain_slips(), nx, dx, dy)
            s.attrs["units"]["y"] = UNITS["x"]
            return s

        def catalog():
            cat = chain_catalog()
            # the chain's moment is int slip dx; the plane's is int slip dA = dx dy sum
            c = _planar_catalog(cat, nx, dx, dy, moment_scale=dy)
            c.attrs = {k: dict(v) for k, v in cat.attrs.items()}
            c.attrs.setdefault("descriptions", {})["moment"] = PLANAR_MOMENT
            c.attrs["units"] = c.attrs.get("units", {}) | {
                "hypocentre_x": UNITS["x"],
                "hypocentre_y": UNITS["x"],
                "area": f"({UNITS['x']})^2 (blocks slipped x dx dy)",
            }
            return c

        def snapshots():
            import xarray as xr

            ds1 = chain_snapshots()
            nt = ds1.sizes["t"]
            ds = xr.Dataset(
                {
                    k: (("t", "y", "x"), ds1[k].values.reshape(nt, ny, nx), ds1[k].attrs)
                    for k in ("u", "u_t")
                },
                coords={
                    "t": ds1["t"],
                    "x": ("x", np.arange(nx) * dx, {"units": UNITS["x"]}),
                    "y": ("y", np.arange(ny) * dy, {"units": UNITS["x"]}),
                },
            )
            ds.attrs.update(ds1.attrs)
            ds.attrs.update(boundary=boundary, dy=dy, shape=list(self.shape))
            return ds

        fields = {f: getattr(r, f) for f in r.__dataclass_fields__ if f not in ("_built",)}
        fields.update(
            u=self._grid(r.u),
            u_t=self._grid(r.u_t),
            boundary=boundary,
            _build={"catalog": catalog, "slips": slips, "snapshots": snapshots},
        )
        return LatticeResult(**fields, shape=self.shape, dy=self.dy)


# --- measurements ----------------------------------------------------------------------


@dataclass
class PlanarFront:
    """A planar front measured on the lattice (``front``).

    c: the normal speed (lattice units of length per unit time) from the first slip
    times of a window of the normal coordinate; c_check: the same from a lattice twice as
    long (the measurement's convergence: |c - c_check|); spacing: the spacing of the
    chain the front reduces to exactly (dx along an axis, dx/sqrt(2) along the diagonal).
    status: "converged" when |c - c_check| <= tolerance, else "undecided" (``reason``
    says why); lengths: the lattice lengths measured, each twice the last.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    angle : {0, 45}
        The front's normal: along x, or along the diagonal.
    blocks : int
        Blocks along the normal.
    c, c_check : float
        Normal speed, and its value on a lattice twice as long (units of the sound
        speed a sqrt(k_c/m)).
    spacing : float
        The spacing of the equivalent chain (dimensionless).
    window : tuple of float
        The window, as fractions of the blocks crossed.
    tolerance : float
        The largest |c - c_check| accepted (units of the sound speed).
    status : {"converged", "undecided"}
        Whether the last doubling moved c by at most ``tolerance``.
    reason : str
        What the last doubling did, in words.
    lengths : tuple of int
        The lengths (blocks along the normal) measured.

    Examples
    --------
    >>> import bkwaves as bk
    >>> f = bk.lattice.front(0.6, 0.3, 0.2, blocks=32)
    >>> f.spacing, f.status, bool(f.convergence <= f.tolerance)
    (0.2, 'converged', True)
    """

    u_plus: float
    gamma: float
    dx: float
    angle: int
    blocks: int
    c: float
    c_check: float
    spacing: float
    window: tuple[float, float]
    tolerance: float = math.inf
    status: str = "converged"
    reason: str = ""
    lengths: tuple = ()

    @property
    def convergence(self) -> float:
        """|c - c_check|: the change of c when the lattice is twice as long (units of the
        sound speed)."""
        return abs(self.c - self.c_check)


def _planar_c(u_plus, gamma, dx, angle, blocks, step, beta, window):
    p = _lattice_params(gamma, dx, beta)
    a, b = (int(round(f * blocks)) for f in window)
    if angle == 0:
        # u depends on i only: two rows periodic in y (the chain at dx, measured here;
        # the global cut, as the chain's: the same slip times to round-off, 1e-12)
        la = Lattice(
            (blocks, 2), p, u0=u_plus, boundary=("free", "periodic"), step=step, events="global"
        )
        for j in range(2):
            la.kick((0, j), -2.0)
        t_end = 2.0 * blocks * dx
        spacing = dx
        res = la.run(t_end=t_end, progress=False)
        t = res.first_slip_times()[0]
        ta, tb = t[a], t[b]
    else:
        # u a function of n = (i + j) mod N on an N x N torus: fronts run both ways from
        # the kicked anti-diagonal and meet at n = N/2; the window is in n in [0, N/2]
        nn = blocks
        # (the global cut: the ring's slip times at dx/sqrt(2) to 1e-10, as the chain's)
        la = Lattice((nn, nn), p, u0=u_plus, boundary="periodic", step=step, events="global")
        for i in range(nn):
            la.kick((i, (nn - i) % nn), -2.0)
        spacing = dx / math.sqrt(2.0)
        a, b = (int(round(f * nn / 2)) for f in window)
        res = la.run(t_end=nn * spacing, progress=False)
        t = res.first_slip_times()
        ta, tb = t[0, a], t[0, b]
    if not (np.isfinite(ta) and np.isfinite(tb) and tb > ta):
        return math.nan, spacing
    return spacing * (b - a) / (tb - ta), spacing


def _lattice_params(gamma, dx, beta):
    from .params import Params

    return Params(gamma=gamma, v=0.0, dx=dx, beta=beta)


def front(
    u_plus: float,
    gamma: float,
    dx: float,
    angle: int = 0,
    blocks: int = 128,
    *,
    step: float = DEFAULT_STEP,
    beta: float = math.inf,
    window: tuple[float, float] = (0.5, 0.75),
    tolerance: float = FRONT_TOLERANCE,
    max_blocks: int | None = None,
) -> PlanarFront:
    """A planar front on the lattice (dx = dy) at uniform u_+, v = 0, and its normal speed.

    angle=0: along x, on a lattice of ``blocks`` x 2 periodic in y, kicked on column 0;
    angle=45: along the diagonal, on a ``blocks`` x ``blocks`` torus kicked on an
    anti-diagonal (the normal coordinate n = i + j; the window is a fraction of the
    blocks/2 rows of n a front crosses before it meets the other one). Both reduce
    exactly to a chain (at dx, at dx/sqrt(2): docs/lattice.md), whose c they must give.
    The measurement is repeated on a lattice twice as long (``c_check``), and the
    lattice doubled again until that moves c by at most ``tolerance`` (status
    "converged") or the length reaches ``max_blocks`` (status "undecided", with the
    reason). The trigger's transient decays over a number of blocks that grows as c -> 1
    (docs/validation.md): at u_+ = 0.3, gamma = 0, dx = 0.1, 128 blocks move by 3e-5.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    dx : float
        Lattice spacing, 0 < dx < 1 (dimensionless; dy = dx).
    angle : {0, 45}, default 0
        Along x, or along the diagonal.
    blocks : int, default 128
        Blocks along the normal, 16 <= blocks <= 4096.
    step : float, default 0.05
        Time step as a fraction of dx (in units of sqrt(m/k_p)).
    beta : float, default inf
        f_s/(f_r - f_s) (dimensionless).
    window : tuple of float, default (0.5, 0.75)
        The measuring window, as fractions of the blocks crossed.
    tolerance : float, default FRONT_TOLERANCE = 1e-6
        The largest change of c (units of the sound speed) when the lattice is doubled,
        > 0 (``math.inf``: measure at ``blocks`` and its double only).
    max_blocks : int, optional
        The longest lattice measured before the double that checks it, >= blocks
        (default 2048 along x, 256 along the diagonal, whose torus has blocks^2 blocks).

    Returns
    -------
    PlanarFront
        c and c_check (units of the sound speed), the equivalent chain's spacing, the
        status ("converged" or "undecided") and its reason.

    Examples
    --------
    The exact reductions: along x the chain at dx, along the diagonal the chain at
    dx/sqrt(2):

    >>> import math
    >>> import bkwaves as bk
    >>> f = bk.lattice.front(0.6, 0.3, 0.2, blocks=32)
    >>> round(float(f.c_check), 5), round(float(bk.front_speed(0.6, dx=0.2, gamma=0.3)), 5)
    (1.21525, 1.21525)
    >>> d = bk.lattice.front(0.6, 0.3, 0.2, angle=45, blocks=64, tolerance=1e-3)
    >>> chain = float(bk.front_speed(0.6, dx=0.2 / math.sqrt(2), gamma=0.3))
    >>> round(float(d.c_check), 3), round(chain, 3)
    (1.226, 1.226)
    """
    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    if angle not in (0, 45):
        V._fail("angle", angle, "0 (along x) or 45 (along the diagonal)")
    blocks = V.integer("blocks", blocks, lo=16, hi=4096)
    if not (isinstance(tolerance, float) and tolerance == math.inf):
        tolerance = V.number("tolerance", tolerance, lo=0.0, lo_open=True)
    top = max(blocks, 2048 if angle == 0 else 256) if max_blocks is None else max_blocks
    top = V.integer("max_blocks", top, lo=blocks, hi=4096)
    c, spacing = _planar_c(u_plus, gamma, dx, angle, blocks, step, beta, window)
    c2, _ = _planar_c(u_plus, gamma, dx, angle, 2 * blocks, step, beta, window)
    lengths = [blocks, 2 * blocks]
    while not abs(c - c2) <= tolerance and 2 * blocks <= top:
        blocks *= 2
        c = c2
        c2, _ = _planar_c(u_plus, gamma, dx, angle, 2 * blocks, step, beta, window)
        lengths.append(2 * blocks)
    moved = abs(c - c2)
    if moved <= tolerance:
        status = "converged"
        reason = f"doubling the lattice from {blocks} to {2 * blocks} blocks moved c by {moved:.1e}"
    else:
        status = "undecided"
        reason = (
            f"doubling the lattice from {blocks} to {2 * blocks} blocks moved c by {moved:.1e}, "
            f"more than the tolerance {tolerance:.1e}, and max_blocks = {top} stops the doubling"
        )
    return PlanarFront(
        u_plus, gamma, dx, angle, blocks, c, c2, spacing, tuple(window),
        tolerance, status, reason, tuple(lengths),
    )  # fmt: skip


@dataclass
class Rupture:
    """An expanding rupture from a point (``rupture``).

    arrival: first slip times of the quadrant, shape (ny, nx) (the rupture's centre is the
    corner (x, y) = (-dx/2, -dy/2): the free edges of the quadrant are mirror planes).
    profiles: for each direction ("x", "y", "diagonal") a dict of the radius ``r`` (from
    the centre, lattice units of length), the arrival time ``t`` and the local speed ``c``
    (central differences of r against t). fits: for each direction (c0, D) of the
    least-squares fit c(R) = c0 - D/R over ``fit_range`` of R (the excitable-media
    eikonal law c_n = c - D kappa with kappa = 1/R). planar: the planar front speeds the
    directions tend to (the chain at dx along x, at dy along y, at dx/sqrt(2) along the
    diagonal when dx = dy: the exact reductions of docs/lattice.md). eikonal: for each
    direction D = (c_planar - c(R)) R with c0 fixed at the planar speed, averaged over
    the lower and the upper half of ``fit_range`` (equal halves: c = c0 - D/R holds).
    check: the fits, eikonal D and ``curvature_limit`` of the same rupture on a quadrant
    twice as large, over the same fractions of it (the measurement's convergence;
    ``convergence`` gives the changes).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx, dy : float
        Lattice spacings (dimensionless).
    size : tuple of int
        (nx, ny) of the quadrant.
    arrival : numpy.ndarray
        First slip times (units of sqrt(m/k_p)), shape (ny, nx).
    profiles : dict
        Per direction: r (dimensionless x), t (units of sqrt(m/k_p)), c (units of the
        sound speed).
    fits : dict
        Per direction: (c0 in sound speeds, D in sound speeds times x).
    planar : dict
        Per direction: the planar front speed (units of the sound speed).
    fit_range : tuple of float
        The fitted fractions of the quadrant.
    check : dict or None, default None
        The same on a quadrant twice as large.
    eikonal : dict or None, default None
        Per direction: D over the lower and the upper half of the range.

    Examples
    --------
    >>> import bkwaves as bk
    >>> r = bk.lattice.rupture(0.6, 0.3, 0.1, size=32, check=False)
    >>> r.size, r.arrival.shape
    ((32, 32), (32, 32))
    """

    u_plus: float
    gamma: float
    dx: float
    dy: float
    size: tuple[int, int]
    arrival: np.ndarray
    profiles: dict
    fits: dict
    planar: dict
    fit_range: tuple[float, float]
    check: dict | None = None
    eikonal: dict | None = None

    def aspect(self, t: float) -> float:
        """The rupture's extent along x over its extent along y, in blocks, at time t
        (dy/dx for a circle in (x, y) = (i dx, j dy)).

        The extent along an axis is where the front is at time t along that edge of the
        quadrant: the blocks' arrival times interpolated linearly between blocks, in
        blocks from the rupture's centre (half a block before block 0).

        Parameters
        ----------
        t : float
            The time (units of sqrt(m/k_p)).

        Returns
        -------
        float
            The ratio (NaN before the front has passed two blocks along each axis or
            after it has left the quadrant).

        Examples
        --------
        >>> import bkwaves as bk
        >>> r = bk.lattice.rupture(0.6, 0.45, 0.2, size=16, check=False)
        >>> round(r.aspect(1.5), 6)      # dx = dy: a symmetric rupture
        1.0
        """
        a = self.arrival
        ex = _front_at(a[0], t)
        ey = _front_at(a[:, 0], t)
        return ex / ey if ey > 0 else math.nan

    def curvature(self, direction: str = "x") -> dict:
        """The front's local speed and local curvature where it crosses an axis or the
        diagonal, and the local eikonal coefficient D = (c_planar - c)/kappa.

        The curvature is measured, not taken as 1/R: across the front the arrival times
        near the crossing are fitted as T = T0 + (kappa/(2c)) s^2 over the first four
        blocks beside it (s the distance across the direction; the quadrant's edges are
        mirror planes, so s = (j + 1/2) dy beside the x axis and the blocks (d - k, d + k)
        at s = k sqrt(2) dx beside the diagonal). Compare D with
        ``bk.theory.curvature_coefficient``, its kappa -> 0 limit (docs/lattice.md).

        Parameters
        ----------
        direction : {"x", "y", "diagonal"}
            Where the front is measured ("diagonal" needs dx = dy).

        Returns
        -------
        dict
            Arrays ``r`` (radius from the centre, dimensionless length), ``c`` (local
            speed, central differences, units of the sound speed), ``kappa`` (local
            curvature, 1/length) and ``D`` (length), over the blocks from the fourth to
            the sixth before the far edge.

        Examples
        --------
        >>> import bkwaves as bk
        >>> r = bk.lattice.rupture(0.6, 0.45, 0.2, size=24, check=False)
        >>> k = r.curvature("x")
        >>> bool(k["kappa"][-1] < k["kappa"][0])      # flatter as it grows
        True
        """
        a = self.arrival
        if direction == "y":
            a = a.T
            h, hs = self.dy, self.dx
        elif direction == "x":
            h, hs = self.dx, self.dy
        elif direction == "diagonal":
            if self.dx != self.dy:
                raise ValueError("direction 'diagonal' needs dx = dy")
            h = hs = self.dx
        else:
            raise ValueError(f"direction must be 'x', 'y' or 'diagonal', got {direction!r}")
        rows = []
        if direction == "diagonal":
            s2 = (np.arange(4) * math.sqrt(2.0) * h) ** 2
            for d in range(4, min(a.shape) - 8):
                t = np.array([a[d - k, d + k] for k in range(4)])
                dt = a[d + 1, d + 1] - a[d - 1, d - 1]
                rows.append((d, t, dt, math.sqrt(2.0) * h, s2))
        else:
            s2 = ((np.arange(4) + 0.5) * hs) ** 2
            for i in range(4, a.shape[1] - 6):
                rows.append((i, a[:4, i], a[0, i + 1] - a[0, i - 1], h, s2))
        r, c, kappa = [], [], []
        for i, t, dt, step, s2 in rows:
            if not (np.all(np.isfinite(t)) and np.isfinite(dt) and dt > 0):
                continue
            q = np.polyfit(s2, t, 1)[0]
            ci = 2.0 * step / dt
            r.append((i + 0.5) * step)
            c.append(ci)
            kappa.append(2.0 * q * ci)
        r, c, kappa = np.array(r), np.array(c), np.array(kappa)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = (self.planar[direction] - c) / kappa
        return {"r": r, "c": c, "kappa": kappa, "D": d}

    def curvature_limit(self, direction: str = "x") -> tuple[float, float]:
        """The kappa -> 0 limit of the local eikonal coefficient: a line D + E kappa
        through the outer third of ``curvature(direction)``'s local D (the flattest
        points), as in docs/lattice.md "Derived: the curvature coefficient".

        Parameters
        ----------
        direction : {"x", "y", "diagonal"}
            Where the front is measured ("diagonal" needs dx = dy).

        Returns
        -------
        tuple of float
            (D, E): D a length (compare ``bk.theory.curvature_coefficient``), E a length
            squared (the local D's growth with kappa). Doubling the quadrant moves D by
            less than 2 % from 32 to 64 blocks and 0.5 % from 64 to 128 (``check``;
            docs/validation.md).

        Examples
        --------
        >>> import bkwaves as bk
        >>> r = bk.lattice.rupture(0.6, 0.45, 0.2, size=32, check=False)
        >>> d, e = r.curvature_limit("x")
        >>> bool(abs(d / bk.theory.curvature_coefficient(0.6, 0.45, 0.2) - 1) < 0.02)
        True
        """
        m = self.curvature(direction)
        n = m["kappa"].size
        if n < 6:
            return (math.nan, math.nan)
        e, d0 = np.polyfit(m["kappa"][2 * n // 3 :], m["D"][2 * n // 3 :], 1)
        return (float(d0), float(e))

    @property
    def convergence(self) -> dict | None:
        """The change of each measured number when the quadrant is doubled (``check``),
        per direction: ``c0`` (absolute, sound speeds) of the fit c0 - D/R, ``D_fit``,
        ``D_eikonal`` (the mean of the two halves) and ``D_limit`` (``curvature_limit``)
        relative. None without ``check``. The 1/R fits drift by about 10 % per doubling
        (a rupture is not a circle and the local D grows with kappa): only ``D_limit``
        is a converged measurement of D (docs/lattice.md)."""
        if self.check is None:
            return None
        out = {}
        for k in self.fits:
            c0, d = self.fits[k]
            c2, d2 = self.check["fits"][k]
            e1, e2 = np.mean(self.eikonal[k]), np.mean(self.check["eikonal"][k])
            twice = self.check.get("limit", {}).get(k)
            lim = abs(twice[0] / self.curvature_limit(k)[0] - 1) if twice else math.nan
            out[k] = {
                "c0": abs(c2 - c0),
                "D_fit": abs(d2 / d - 1),
                "D_eikonal": abs(e2 / e1 - 1),
                "D_limit": lim,
            }
        return out


def _front_at(arrival: np.ndarray, t: float) -> float:
    """Where the front along a row of blocks is at time t, in blocks from the centre
    (block k at k + 1/2), the arrival times interpolated linearly; NaN outside the blocks
    reached or where the arrival times do not increase."""
    ok = np.isfinite(arrival)
    n = arrival.size if ok.all() else int(np.argmin(ok))  # the reached prefix
    arr = arrival[:n]
    if n < 2 or not (arr[0] <= t <= arr[-1]) or np.any(np.diff(arr) <= 0):
        return math.nan
    return float(np.interp(t, arr, np.arange(n) + 0.5))


def _profile(r: np.ndarray, t: np.ndarray) -> dict:
    ok = np.isfinite(t)
    r, t = r[ok], t[ok]
    c = np.full(r.size, np.nan)
    if r.size > 2:
        c[1:-1] = (r[2:] - r[:-2]) / (t[2:] - t[:-2])
    return {"r": r, "t": t, "c": c}


def _eikonal(prof: dict, c_planar: float, lo: float, hi: float) -> tuple[float, float]:
    """D = (c_planar - c(R)) R over [lo, hi] of R with c0 fixed at the planar speed: its
    means over the lower and the upper half of the range (equal if c = c0 - D/R)."""
    r, c = prof["r"], prof["c"]
    mid = 0.5 * (lo + hi)
    out = []
    for a, b in ((lo, mid), (mid, hi)):
        m = np.isfinite(c) & (r >= a) & (r <= b)
        out.append(float(np.mean((c_planar - c[m]) * r[m])) if m.any() else math.nan)
    return tuple(out)


def _fit(prof: dict, lo: float, hi: float) -> tuple[float, float]:
    r, c = prof["r"], prof["c"]
    m = np.isfinite(c) & (r >= lo) & (r <= hi)
    if m.sum() < 3:
        return (math.nan, math.nan)
    a = np.column_stack([np.ones(m.sum()), 1.0 / r[m]])
    (c0, slope), *_ = np.linalg.lstsq(a, c[m], rcond=None)
    return (float(c0), float(-slope))


def _rupture_once(u_plus, gamma, dx, dy, nx, ny, step, beta, fit):
    p = _lattice_params(gamma, dx, beta)
    la = Lattice((nx, ny), p, u0=u_plus, dy=dy, step=step)
    la.kick((0, 0), -2.0)
    # long enough for the front to reach the far corner (sqrt(2) L at about c(u_+))
    c_est = 1.0 / math.sqrt(1.0 - u_plus * u_plus)
    t_end = 1.6 * max(nx * dx, ny * dy) / c_est
    res = la.run(t_end=t_end, progress=False)
    a = res.first_slip_times()
    i = np.arange(nx)
    j = np.arange(ny)
    m = min(nx, ny)
    d = np.arange(m)
    # leave out the last blocks before the far (free) edges
    cut = 4
    profiles = {
        "x": _profile((i[:-cut] + 0.5) * dx, a[0, :-cut]),
        "y": _profile((j[:-cut] + 0.5) * dy, a[:-cut, 0]),
        "diagonal": _profile((d[:-cut] + 0.5) * math.hypot(dx, dy), a[d[:-cut], d[:-cut]]),
    }
    lo, hi = fit
    size = min(nx * dx, ny * dy)
    rng = (lo * size, hi * size)
    fits = {k: _fit(v, *rng) for k, v in profiles.items()}
    return a, profiles, fits, rng


def _eikonals(profiles, planar, rng) -> dict:
    return {k: _eikonal(profiles[k], planar[k], *rng) for k in profiles}


def rupture(
    u_plus: float,
    gamma: float,
    dx: float,
    size: int = 128,
    *,
    dy: float | None = None,
    step: float = DEFAULT_STEP,
    beta: float = math.inf,
    fit: tuple[float, float] = (0.25, 0.95),
    check: bool = True,
) -> Rupture:
    """An expanding rupture from a point in uniform u_+ (v = 0): its radius against time
    along the axes and the diagonal, and the curvature correction to its speed.

    The lattice is a quadrant of ``size`` blocks along x (and size dx/dy along y) with
    free edges, kicked at its corner block: the free edges are mirror planes, so this is a
    rupture from the four centre blocks of a lattice four times larger. The local speed
    along each direction is fitted as c(R) = c0 - D/R for R in ``fit`` (fractions of the
    quadrant's extent); c0 must tend to the planar speed of that direction (``planar``,
    from ``front``'s exact reductions, measured on chains) and D is the eikonal
    coefficient. With ``check`` the rupture is repeated on a quadrant twice as large.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    dx : float
        Lattice spacing along x, 0 < dx < 1 (dimensionless).
    size : int, default 128
        Blocks of the quadrant along x, 16 <= size <= 8192.
    dy : float, optional
        Spacing along y (dimensionless); default dx.
    step : float, default 0.05
        Time step as a fraction of min(dx, dy) (in units of sqrt(m/k_p)).
    beta : float, default inf
        f_s/(f_r - f_s) (dimensionless).
    fit : tuple of float, default (0.25, 0.95)
        The fitted range of R, as fractions of the quadrant's extent.
    check : bool, default True
        Repeat on a quadrant twice as large.

    Returns
    -------
    Rupture
        Arrival times, profiles, fits and the planar speeds.

    Examples
    --------
    The fitted c0 along the axes is near the planar speed (a small quadrant):

    >>> import bkwaves as bk
    >>> r = bk.lattice.rupture(0.6, 0.3, 0.1, size=32, check=False)
    >>> [bool(abs(r.fits[k][0] / r.planar[k] - 1) < 1e-3) for k in ("x", "y")]
    [True, True]
    """
    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    dy = dx if dy is None else V.number("dy", dy, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    size = V.integer("size", size, lo=16, hi=8192)
    nx, ny = size, max(16, int(round(size * dx / dy)))
    a, prof, fits, rng = _rupture_once(u_plus, gamma, dx, dy, nx, ny, step, beta, fit)
    planar = {}
    for k, h in (("x", dx), ("y", dy), ("diagonal", dx / math.sqrt(2.0))):
        # (with dx != dy the diagonal of the lattice is not a direction of exact reduction)
        ok = k != "diagonal" or dx == dy
        c = _planar_c(u_plus, gamma, h, 0, 256, step, beta, (0.5, 0.75))[0] if ok else math.nan
        planar[k] = c
    out = Rupture(u_plus, gamma, dx, dy, (nx, ny), a, prof, fits, planar, rng)
    out.eikonal = _eikonals(prof, planar, rng)
    if check:
        a2, prof2, fits2, rng2 = _rupture_once(
            u_plus, gamma, dx, dy, 2 * nx, 2 * ny, step, beta, fit
        )
        twice = Rupture(u_plus, gamma, dx, dy, (2 * nx, 2 * ny), a2, prof2, fits2, planar, rng2)
        dirs = ("x", "y", "diagonal") if dx == dy else ("x", "y")
        out.check = {
            "fits": fits2,
            "eikonal": _eikonals(prof2, planar, rng2),
            "range": rng2,
            "limit": {k: twice.curvature_limit(k) for k in dirs},
        }
    return out
