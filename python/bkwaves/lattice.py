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
from .chain import (
    BOUNDARIES,
    DEFAULT_STEP,
    INTEGRATORS,
    UNITS,
    Chain,
    ChainResult,
    _per_block,
)

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
        s = self._slips_of(event)
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
        s = self._slips_of(event)
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
        from .limits import check_memory

        # (before any array of the lattice's size is touched)
        check_memory("shape", "lattice", int(nx) * int(ny), f"({nx}, {ny})")
        self.shape = (int(nx), int(ny))
        dx = float(params.dx) if hasattr(params, "dx") else math.nan
        self.dy = dx if dy is None else V.number("dy", dy, lo=0.0, lo_open=True, hi=1e6)
        bx, by = _pair("boundary", boundary, "a boundary name or a pair (across x, across y)")
        if not isinstance(boundary, str):  # a pair: each side named by its place
            bx, by = (V.choice(f"boundary[{k}]", b, BOUNDARIES) for k, b in enumerate((bx, by)))
        by = V.CHAIN["boundary"].check(by)
        self.boundary_y = by
        flat = [self._flat(k, x) for k, x in (("u0", u0), ("u_t0", u_t0))]
        props = {
            k: self._flat(k, x)
            for k, x in (("threshold", threshold), ("mass", mass), ("loader", loader))
        }
        if fixed is None:
            # the walls default to the mean u of their side: u0 checked first (a NaN in
            # it is an error of u0, not of the wall it would make)
            u = _per_block("u0", flat[0], nx * ny).reshape(ny, nx)
            fx = (float(u[:, 0].mean()), float(u[:, -1].mean()))
            fy = (float(u[0].mean()), float(u[-1].mean()))
        else:
            want = "((x low, x high), (y low, y high)) wall positions"
            fx, fy = _pair("fixed", fixed, want)
            for k, side in enumerate((fx, fy)):
                if isinstance(side, str | bytes) or not (
                    hasattr(side, "__len__") and len(side) == 2
                ):
                    V._fail(f"fixed[{k}]", side, "a pair (low, high) of wall positions")
            fx, fy = tuple(fx), tuple(fy)
            fx = (V.number("fixed[0][0]", fx[0]), V.number("fixed[0][1]", fx[1]))
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
        shown = f"array of shape {a.shape}" if isinstance(a, np.ndarray) else value
        V._fail(name, shown, f"a scalar or an array of shape (ny, nx) = {self.shape[::-1]}")

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
            The checkpoint file (npz). An earlier bkwaves checkpoint there is replaced;
            anything else (a file of yours, a folder) is refused with a ParameterError
            and kept.

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
        return _checkpoint.rebuild(Lattice._from_record, meta, arrays, path, "lattice")

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


# the measurements on the lattice (front, rupture: ``bkwaves._lattice_measure``), under
# their public names here
from ._lattice_measure import (  # noqa: E402 - (after Lattice, which they build)
    FRONT_TOLERANCE,
    PlanarFront,
    Rupture,
    front,
    rupture,
)
