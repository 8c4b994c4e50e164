"""Parameter sweeps on Dask: ``bkwaves sweep SWEEP.toml`` and :func:`bkwaves.sweep`.

A sweep is a task (what one point computes), a base input and axes. Each point of the
grid (the product of the axes, or their zip) is one call of the task, run on a Dask
cluster (an embedded :class:`distributed.LocalCluster` by default, or any running
scheduler). The scalars a point reports (its summary: c, w, u_minus, event counts,
b-value, ...) are gathered into one :class:`xarray.Dataset` indexed by the axes and
written to a Zarr store as points finish, so an interrupted sweep keeps every finished
point and a re-run computes only the missing ones.

Schema of SWEEP.toml (see ``examples/sweep_*.toml``)::

    title = "..."                 # free text
    task = "front"                # front | speed | wave | tip | run   (see TASKS)
    combine = "product"           # product (grid) | zip (axes of equal length)
    [base]                        # the task's inputs; for task = "run" a whole run config
    gamma = 0.3                   #   (model = ..., [base.params], [base.run], ...)
    [axes.u_plus]                 # one table per axis; the name is the input's key path
    values = [0.3, 0.5, 0.7]      #   ("params.gamma" for nested keys); exactly one of:
    [axes.dx]                     #   values = [...]
    logspace = {start = 0.0125, stop = 0.1, num = 4}   # linspace / logspace {start, stop, num}
    [axes.seed]                   #   range = {start, stop, step} (stop excluded)
    seeds = 8                     #   seeds = N (the integers 0 .. N-1)
    [adaptive]                    # optional, instead of a grid: refine 1 or 2 axes given as
    output = "w"                  #   bounds = [lo, hi] where `output` changes fastest
    npoints = 40                  #   (the `adaptive` package with the Dask executor)
    [output]
    path = "sweep.zarr"           # default: SWEEP.zarr beside the file
    catalogs = false              # task = "run": write each point's tables (Parquet)
    snapshots = false             # task = "run": write each point's snapshots (NetCDF)

The store: one variable per summary scalar (float, or string for text), plus ``status``
(0 pending, 1 done, 2 failed), ``error`` (the failure's message), ``key`` (a hash of the
point's full input, the task and the bkwaves version: a point is done only if its stored
key equals the key it would have now) and ``wall_s``. A point's values are written before
its status, so a store killed mid-write never shows a half-written point as done.
"""

from __future__ import annotations

import copy
import hashlib
import inspect
import json
import math
import signal
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from ._core import ParameterError

__all__ = ["Axis", "SweepSpec", "SweepResult", "TASKS", "load_sweep", "parse_sweep", "sweep"]

STORE_MARKER = "bkwaves-sweep-1"
PENDING, DONE, FAILED = 0, 1, 2
COMBINES = ("product", "zip")
FLUSH_POINTS = 256  # points written at once at most (those that arrived together)


# --------------------------------------------------------------------------- tasks
# A task is a pure function of a JSON-able dict (the point's full input) that returns a
# flat dict of scalars (its summary). Tasks run on the workers; `check` runs on the
# client before anything is submitted and raises ParameterError for bad input.


@dataclass(frozen=True)
class Task:
    name: str
    doc: str
    run: Any  # callable(point: dict, keep: tuple) -> dict of scalars (+ files for "run")
    check: Any  # callable(point: dict) -> None, raises ParameterError


def _kwargs_of(fn, point: dict, task: str, required: tuple[str, ...]) -> dict:
    names = [
        p.name
        for p in inspect.signature(fn).parameters.values()
        if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
    ]
    for k in point:
        if k not in names:
            raise ParameterError(
                f"base.{k}: unknown input of task {task!r}; valid: {', '.join(names)}"
            )
    for k in required:
        if k not in point:
            raise ParameterError(f"base.{k}: task {task!r} needs {k} (in [base] or an axis)")
    return dict(point)


def _scalars(d: dict) -> dict:
    out = {}
    for k, v in d.items():
        if isinstance(v, bool | np.bool_):
            out[k] = float(v)
        elif isinstance(v, int | float | np.integer | np.floating):
            out[k] = float(v)
        elif v is None:
            out[k] = math.nan
        elif isinstance(v, str):
            out[k] = v
    return out


def _front(point: dict, keep=()) -> dict:
    from .chain import front

    kw = _kwargs_of(front, point, "front", ("u_plus", "gamma", "dx"))
    return _scalars(front(**kw).to_dict())


def _front_check(point: dict) -> None:
    from .chain import front

    _kwargs_of(front, point, "front", ("u_plus", "gamma", "dx"))


def _speed(point: dict, keep=()) -> dict:
    from .waves import front_speed

    kw = _kwargs_of(front_speed, point, "speed", ("u_plus",))
    return {"c": float(front_speed(kw.pop("u_plus"), **kw))}


def _speed_check(point: dict) -> None:
    from .waves import front_speed

    _kwargs_of(front_speed, point, "speed", ("u_plus",))


def _wave(point: dict, keep=()) -> dict:
    from .waves import traveling_wave

    kw = _kwargs_of(traveling_wave, point, "wave", ("u_plus", "gamma"))
    return _scalars(traveling_wave(**kw).to_dict())


def _wave_check(point: dict) -> None:
    from .waves import traveling_wave

    _kwargs_of(traveling_wave, point, "wave", ("u_plus", "gamma"))


def _tip(point: dict, keep=()) -> dict:
    from .waves import tip_solve

    kw = _kwargs_of(tip_solve, point, "tip", ())
    return _scalars(tip_solve(**kw))


def _tip_check(point: dict) -> None:
    from .waves import tip_solve

    _kwargs_of(tip_solve, point, "tip", ())


def _run(point: dict, keep=()) -> dict:
    from .runner import run_result

    res = run_result(_run_config(point), snapshots="snapshots" in keep)
    out = _scalars(res.summary)
    if "catalogs" in keep:
        out["__tables__"] = res.tables
    if "snapshots" in keep:
        out["__snapshots__"] = res.snapshots
    return out


def _run_config(point: dict):
    from .config import parse_config

    doc = copy.deepcopy(point)
    doc.setdefault("output", {})
    if isinstance(doc["output"], dict):
        doc["output"].pop("path", None)
    return parse_config(doc)


def _run_check(point: dict) -> None:
    _run_config(point)


TASKS: dict[str, Task] = {
    "front": Task(
        "front",
        "one front in the direct chain (bk.chain.front): c, w, u_minus",
        _front,
        _front_check,
    ),
    "speed": Task("speed", "front speed c (bk.front_speed)", _speed, _speed_check),
    "wave": Task("wave", "traveling wave of App. B (bk.traveling_wave)", _wave, _wave_check),
    "tip": Task("tip", "the tip problem solved numerically (bk.tip_solve)", _tip, _tip_check),
    "run": Task("run", "a run of any model (bk.run): its summary", _run, _run_check),
}


def run_point(task: str, point: dict, keep: tuple = ()) -> dict:
    """Compute one point (what a worker runs): the task's summary plus ``wall_s``; with
    ``keep`` ("catalogs", "snapshots"; task "run") also the point's tables/snapshots."""
    t0 = time.perf_counter()
    out = TASKS[task].run(point, tuple(keep))
    out["wall_s"] = time.perf_counter() - t0
    return out


# --------------------------------------------------------------------------- the spec


@dataclass(frozen=True)
class Axis:
    """One axis: ``path`` is the key path in the task's input (``("params", "gamma")``),
    ``name`` its last part (the dimension name in the result).

    Parameters
    ----------
    path : tuple of str
        The key path.
    values : tuple, default ()
        The values (in the unit of the key: the paper's dimensionless ones, or SI where
        the task's input is SI).
    bounds : tuple of float, optional
        The interval of an adaptive axis (same unit).

    Examples
    --------
    >>> import bkwaves as bk
    >>> axis = bk.sweeps.Axis(("params", "gamma"), (0.3, 0.5))
    >>> axis.name, axis.key
    ('gamma', 'params.gamma')
    """

    path: tuple[str, ...]
    values: tuple = ()
    bounds: tuple[float, float] | None = None

    @property
    def name(self) -> str:
        """The last key of the path: the dimension's name in the result."""
        return self.path[-1]

    @property
    def key(self) -> str:
        """The path joined by dots, as the sweep file writes it."""
        return ".".join(self.path)


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep (frozen). ``to_dict()``/``from_dict()`` round-trip it.

    Parameters
    ----------
    task : str
        What each point computes (``TASKS``).
    base : dict
        The input every point shares (its values in the task's units: the paper's
        dimensionless ones unless the task takes SI).
    axes : tuple of Axis
        The swept keys.
    combine : {"product", "zip"}, default "product"
        Every combination of the axes' values, or their values side by side.
    title : str, default ""
        A title written into the store.
    adaptive : dict, optional
        The adaptive sampler's settings.
    output_path : str, optional
        The store.
    catalogs, snapshots : bool, default False
        What task "run" hands back besides the summary.

    Examples
    --------
    >>> import bkwaves as bk
    >>> spec = bk.sweeps.parse_sweep({"task": "speed", "axes": {
    ...     "u_plus": {"values": [0.6, 0.8]}, "dx": {"values": [0.0, 0.1]}}})
    >>> spec.shape, spec.dims
    ((2, 2), ('u_plus', 'dx'))
    """

    task: str
    base: dict
    axes: tuple[Axis, ...]
    combine: str = "product"
    title: str = ""
    adaptive: dict | None = None
    output_path: str | None = None
    catalogs: bool = False
    snapshots: bool = False

    @property
    def keep(self) -> tuple[str, ...]:
        """What besides the summary each point hands back (task "run")."""
        return tuple(k for k in ("catalogs", "snapshots") if getattr(self, k))

    @property
    def shape(self) -> tuple[int, ...]:
        """Points along each dimension of the result."""
        if self.combine == "zip":
            return (len(self.axes[0].values),)
        return tuple(len(a.values) for a in self.axes)

    @property
    def dims(self) -> tuple[str, ...]:
        """The result's dimensions: the axes' names (``("point",)`` when zipped)."""
        return ("point",) if self.combine == "zip" else tuple(a.name for a in self.axes)

    def point(self, index: tuple[int, ...]) -> dict:
        """The full input of the point at ``index`` (base with the axes' values set).

        Parameters
        ----------
        index : tuple of int
            One index per dimension.

        Returns
        -------
        dict
            The task's input (values in the task's units).

        Examples
        --------
        >>> import bkwaves as bk
        >>> spec = bk.sweeps.parse_sweep({"task": "speed", "axes": {
        ...     "u_plus": {"values": [0.6, 0.8]}, "dx": {"values": [0.0, 0.1]}}})
        >>> spec.point((1, 0))
        {'u_plus': 0.8, 'dx': 0.0}
        """
        values = (
            [a.values[index[0]] for a in self.axes]
            if self.combine == "zip"
            else [a.values[i] for a, i in zip(self.axes, index, strict=True)]
        )
        return self.point_at(values)

    def point_at(self, values) -> dict:
        """The full input with the axes set to ``values`` (one per axis).

        Parameters
        ----------
        values : sequence
            One value per axis, in the axes' order (the task's units).

        Returns
        -------
        dict
            The task's input.

        Examples
        --------
        >>> import bkwaves as bk
        >>> spec = bk.sweeps.parse_sweep({"task": "speed", "axes": {
        ...     "u_plus": {"values": [0.6, 0.8]}, "dx": {"values": [0.0, 0.1]}}})
        >>> spec.point_at([0.8, 0.1])
        {'u_plus': 0.8, 'dx': 0.1}
        """
        p = copy.deepcopy(self.base)
        for a, v in zip(self.axes, values, strict=True):
            d = p
            for k in a.path[:-1]:
                d = d.setdefault(k, {})
                if not isinstance(d, dict):
                    raise ParameterError(f"axes.{a.key}: {k} in [base] is not a table")
            d[a.path[-1]] = v
        return p

    def indices(self):
        """Every point's index, in order.

        Returns
        -------
        list of tuple of int
            The indices.

        Examples
        --------
        >>> import bkwaves as bk
        >>> spec = bk.sweeps.parse_sweep({"task": "speed", "axes": {
        ...     "u_plus": {"values": [0.6, 0.8]}, "dx": {"values": [0.0, 0.1]}}})
        >>> spec.indices()
        [(0, 0), (0, 1), (1, 0), (1, 1)]
        """
        return list(np.ndindex(*self.shape))

    def key(self, point: dict) -> str:
        """The hash under which a point's result is stored (task, input and version).

        Parameters
        ----------
        point : dict
            The point's input.

        Returns
        -------
        str
            24 hexadecimal digits; equal inputs give equal keys.

        Examples
        --------
        >>> import bkwaves as bk
        >>> spec = bk.sweeps.parse_sweep({"task": "speed", "axes": {
        ...     "u_plus": {"values": [0.6, 0.8]}, "dx": {"values": [0.0, 0.1]}}})
        >>> k = spec.key(spec.point((0, 0)))
        >>> len(k), k == spec.key({"u_plus": 0.6, "dx": 0.0}), k == spec.key(spec.point((0, 1)))
        (24, True, False)
        """
        return point_key(self.task, point)

    def to_dict(self) -> dict:
        """The sweep as a document of the SWEEP.toml schema.

        Returns
        -------
        dict
            The document; ``SweepSpec.from_dict`` reads it back.

        Examples
        --------
        >>> import bkwaves as bk
        >>> spec = bk.sweeps.parse_sweep({"task": "speed", "axes": {
        ...     "u_plus": {"values": [0.6, 0.8]}, "dx": {"values": [0.0, 0.1]}}})
        >>> spec.to_dict()["axes"]
        {'u_plus': {'values': [0.6, 0.8]}, 'dx': {'values': [0.0, 0.1]}}
        """
        axes = {}
        for a in self.axes:
            axes[a.key] = {"bounds": list(a.bounds)} if a.bounds else {"values": list(a.values)}
        d = {
            "task": self.task,
            "combine": self.combine,
            "title": self.title,
            "base": copy.deepcopy(self.base),
            "axes": axes,
            "output": {"catalogs": self.catalogs, "snapshots": self.snapshots},
        }
        if self.output_path:
            d["output"]["path"] = self.output_path
        if self.adaptive:
            d["adaptive"] = dict(self.adaptive)
        return d

    @classmethod
    def from_dict(cls, d: dict, *, base_dir: Path | None = None) -> SweepSpec:
        """Validate a document of the SWEEP.toml schema (:func:`parse_sweep`).

        Parameters
        ----------
        d : dict
            The document.
        base_dir : pathlib.Path, optional
            The folder relative paths are read from.

        Returns
        -------
        SweepSpec
            The validated sweep.

        Examples
        --------
        >>> import bkwaves as bk
        >>> spec = bk.sweeps.parse_sweep({"task": "speed", "axes": {
        ...     "u_plus": {"values": [0.6, 0.8]}, "dx": {"values": [0.0, 0.1]}}})
        >>> bk.sweeps.SweepSpec.from_dict(spec.to_dict()) == spec
        True
        """
        return parse_sweep(d, base_dir=base_dir)


def point_key(task: str, point: dict) -> str:
    """A hash of everything that determines a point's result."""
    text = json.dumps(
        {"task": task, "input": point, "version": __version__}, sort_keys=True, default=str
    )
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def _fail(path: str, msg: str):
    raise ParameterError(f"{path}: {msg}")


def _num(x, path: str) -> float:
    if isinstance(x, bool) or not isinstance(x, int | float) or not math.isfinite(x):
        _fail(path, f"expected a finite number, got {x!r}")
    return float(x)


def _count(x, path: str, lo: int = 1, hi: int = 100_000) -> int:
    if isinstance(x, bool) or not isinstance(x, int) or not lo <= x <= hi:
        _fail(path, f"expected an integer {lo} <= n <= {hi}, got {x!r}")
    return x


def _axis(key: str, t: Any) -> Axis:
    q = f"axes.{key}"
    if not isinstance(key, str) or not key or any(not k for k in key.split(".")):
        _fail(q, "an axis name is a key path like u_plus or params.gamma")
    if not isinstance(t, dict):
        _fail(q, "expected a table with one of values, linspace, logspace, range, seeds, bounds")
    kinds = ("values", "linspace", "logspace", "range", "seeds", "bounds")
    given = [k for k in t if k in kinds]
    for k in t:
        if k not in kinds:
            _fail(f"{q}.{k}", f"unknown key; valid: {', '.join(kinds)}")
    if len(given) != 1:
        _fail(q, f"give exactly one of {', '.join(kinds)}")
    kind = given[0]
    v = t[kind]
    path = tuple(key.split("."))
    if kind == "values":
        if not isinstance(v, list) or not v:
            _fail(f"{q}.values", "expected a non-empty array")
        for i, x in enumerate(v):
            if not isinstance(x, int | float | str) or isinstance(x, bool):
                _fail(f"{q}.values[{i}]", f"expected a number or a string, got {x!r}")
            if isinstance(x, float) and not math.isfinite(x):
                _fail(f"{q}.values[{i}]", f"expected a finite number, got {x!r}")
        if len({json.dumps(x) for x in v}) != len(v):
            _fail(f"{q}.values", "values repeat")
        return Axis(path, tuple(v))
    if kind == "seeds":
        return Axis(path, tuple(range(_count(v, f"{q}.seeds"))))
    if kind == "bounds":
        if not isinstance(v, list) or len(v) != 2:
            _fail(f"{q}.bounds", "expected [lo, hi]")
        lo, hi = _num(v[0], f"{q}.bounds[0]"), _num(v[1], f"{q}.bounds[1]")
        if not lo < hi:
            _fail(f"{q}.bounds", f"expected lo < hi, got {v!r}")
        return Axis(path, (), (lo, hi))
    if not isinstance(v, dict):
        _fail(f"{q}.{kind}", "expected a table")
    names = ("start", "stop", "step") if kind == "range" else ("start", "stop", "num")
    for k in v:
        if k not in names:
            _fail(f"{q}.{kind}.{k}", f"unknown key; valid: {', '.join(names)}")
    for k in names:
        if k not in v:
            _fail(f"{q}.{kind}.{k}", "missing required key")
    start, stop = _num(v["start"], f"{q}.{kind}.start"), _num(v["stop"], f"{q}.{kind}.stop")
    if kind == "range":
        step = _num(v["step"], f"{q}.range.step")
        if step == 0 or (stop - start) / step <= 0:
            _fail(f"{q}.range", f"empty range from {start} to {stop} by {step}")
        n = math.ceil((stop - start) / step - 1e-9)
        _count(n, f"{q}.range (number of values)")
        ints = all(isinstance(v[k], int) for k in names)
        vals = [start + i * step for i in range(n)]
        return Axis(path, tuple(int(x) if ints else x for x in vals))
    num = _count(v["num"], f"{q}.{kind}.num")
    if kind == "logspace":
        if not (start > 0 and stop > 0):
            _fail(f"{q}.logspace", "start and stop must be > 0")
        vals = np.geomspace(start, stop, num)
    else:
        vals = np.linspace(start, stop, num)
    return Axis(path, tuple(float(x) for x in vals))


def parse_sweep(doc: dict, *, base_dir: Path | None = None) -> SweepSpec:
    """Validate a parsed SWEEP.toml document (or ``SweepSpec.to_dict()``).

    Parameters
    ----------
    doc : dict
        The document (docs/sweeps.md lists the keys).
    base_dir : pathlib.Path, optional
        The folder relative paths are read from.

    Returns
    -------
    SweepSpec
        The validated sweep.

    Raises
    ------
    bkwaves.ParameterError
        An unknown key or task, or a value out of range.

    Examples
    --------
    Zipped axes give one point per value pair:

    >>> import bkwaves as bk
    >>> spec = bk.sweeps.parse_sweep({"task": "wave", "combine": "zip", "axes": {
    ...     "u_plus": {"values": [0.6, 0.8]}, "gamma": {"values": [0.3, 0.5]}}})
    >>> spec.shape, spec.dims, spec.point((1,))
    ((2,), ('point',), {'u_plus': 0.8, 'gamma': 0.5})
    """
    if not isinstance(doc, dict):
        _fail("(top level)", "expected a table")
    top = ("title", "task", "combine", "base", "axes", "adaptive", "output")
    for k in doc:
        if k not in top:
            _fail(k, f"unknown key; valid keys here: {', '.join(top)}")
    task = doc.get("task")
    if task not in TASKS:
        _fail("task", f"invalid value {task!r}; one of: {', '.join(TASKS)}")
    combine = doc.get("combine", "product")
    if combine not in COMBINES:
        _fail("combine", f"invalid value {combine!r}; one of: {', '.join(COMBINES)}")
    title = doc.get("title", "")
    if not isinstance(title, str):
        _fail("title", "expected a string")
    base = doc.get("base", {})
    if not isinstance(base, dict):
        _fail("base", "expected a table")
    base = copy.deepcopy(base)
    if task == "run" and base_dir is not None:
        ini = base.get("initial")
        if isinstance(ini, dict) and isinstance(ini.get("path"), str):
            if not Path(ini["path"]).is_absolute():
                ini["path"] = str(Path(base_dir) / ini["path"])
    raw_axes = doc.get("axes")
    if not isinstance(raw_axes, dict) or not raw_axes:
        _fail("axes", "expected at least one axis table [axes.NAME]")
    axes = tuple(_axis(k, v) for k, v in raw_axes.items())
    names = [a.name for a in axes]
    if len(set(names)) != len(names):
        _fail("axes", f"two axes end in the same name: {', '.join(names)}")
    if "point" in names:
        _fail("axes.point", "'point' is reserved (the dimension of zip sweeps)")
    adaptive = doc.get("adaptive")
    bounded = [a for a in axes if a.bounds is not None]
    if adaptive is not None:
        if not isinstance(adaptive, dict):
            _fail("adaptive", "expected a table")
        for k in adaptive:
            if k not in ("output", "npoints", "loss_goal"):
                _fail(f"adaptive.{k}", "unknown key; valid: output, npoints, loss_goal")
        if not isinstance(adaptive.get("output"), str):
            _fail("adaptive.output", "the summary scalar to refine on, e.g. 'c' or 'w'")
        if "npoints" not in adaptive and "loss_goal" not in adaptive:
            _fail("adaptive", "give npoints, loss_goal or both")
        if "npoints" in adaptive:
            _count(adaptive["npoints"], "adaptive.npoints", lo=2)
        if "loss_goal" in adaptive:
            lg = _num(adaptive["loss_goal"], "adaptive.loss_goal")
            if not lg > 0:
                _fail("adaptive.loss_goal", "expected > 0")
        if len(bounded) != len(axes) or len(axes) not in (1, 2):
            _fail("axes", "an adaptive sweep has 1 or 2 axes, each given as bounds = [lo, hi]")
    elif bounded:
        _fail(f"axes.{bounded[0].key}.bounds", "bounds need an [adaptive] table")
    if combine == "zip" and adaptive is None:
        lens = {len(a.values) for a in axes}
        if len(lens) != 1:
            _fail("axes", f"zip needs axes of equal length, got {[len(a.values) for a in axes]}")
    out = doc.get("output", {})
    if not isinstance(out, dict):
        _fail("output", "expected a table")
    for k in out:
        if k not in ("path", "catalogs", "snapshots"):
            _fail(f"output.{k}", "unknown key; valid: path, catalogs, snapshots")
    path = out.get("path")
    if path is not None and (not isinstance(path, str) or not path.endswith(".zarr")):
        _fail("output.path", f"expected a path ending in .zarr, got {path!r}")
    if path is not None and base_dir is not None and not Path(path).is_absolute():
        path = str(Path(base_dir) / path)
    files = {}
    for k in ("catalogs", "snapshots"):
        files[k] = out.get(k, False)
        if not isinstance(files[k], bool):
            _fail(f"output.{k}", f"expected true or false, got {files[k]!r}")
        if files[k] and task != "run":
            _fail(f"output.{k}", f"only task = 'run' has {k}")
    spec = SweepSpec(
        task=task,
        base=base,
        axes=axes,
        combine=combine,
        title=title,
        adaptive=dict(adaptive) if adaptive else None,
        output_path=path,
        catalogs=files["catalogs"],
        snapshots=files["snapshots"],
    )
    # the base and one point must be valid before anything runs
    probe = (
        spec.point_at([a.bounds[0] for a in axes]) if adaptive else spec.point(spec.indices()[0])
    )
    TASKS[task].check(probe)
    return spec


def load_sweep(path) -> SweepSpec:
    """Read and validate a SWEEP.toml.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    SweepSpec
        The validated sweep.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> path = os.path.join(tempfile.mkdtemp(), "speed.toml")
    >>> lines = ['task = "speed"', "[axes.u_plus]", "values = [0.6, 0.8]"]
    >>> _ = open(path, "w").write(chr(10).join(lines))
    >>> bk.sweeps.load_sweep(path).shape
    (2,)
    """
    path = Path(path)
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ParameterError(f"sweep file not found: {path}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise ParameterError(f"{path}: not valid TOML: {e}") from None
    spec = parse_sweep(doc, base_dir=path.parent)
    if spec.output_path is None:
        spec = SweepSpec(**{**spec.__dict__, "output_path": str(path.with_suffix(".zarr"))})
    return spec


# --------------------------------------------------------------------------- the store


class SweepRepairWarning(UserWarning):
    """A re-run found done points that no longer hold what they wrote (a lost chunk, a
    missing per-point file): they are computed again."""


class _Store:
    """The Zarr store of a grid sweep, written by the client as points finish."""

    def __init__(self, path: Path, spec: SweepSpec, *, overwrite: bool):
        import zarr

        self.path, self.spec = Path(path), spec
        self.signature = json.dumps(
            {
                "task": spec.task,
                "dims": spec.dims,
                "shape": spec.shape,
                "base": spec.base,
                "axes": spec.to_dict()["axes"],
                "combine": spec.combine,
            },
            sort_keys=True,
            default=str,
        )
        if self.path.exists():
            g = self._open_existing()
            if g is None:
                raise ParameterError(
                    f"-o {self.path}: exists and is not a bkwaves sweep store; "
                    "bkwaves will not touch it (choose another output)"
                )
            same = g.attrs.get("signature") == self.signature
            if not same and not overwrite:
                raise ParameterError(
                    f"-o {self.path}: holds a different sweep (other task, base or axes); "
                    "give another output, or --overwrite to replace it"
                )
            if not overwrite:
                self.g = zarr.open_group(str(self.path), mode="r+", use_consolidated=False)
                return
            import shutil

            shutil.rmtree(self.path)  # a bkwaves sweep store (marker checked above)
        self._create()
        self.g = zarr.open_group(str(self.path), mode="r+", use_consolidated=False)

    def _open_existing(self):
        import zarr

        try:
            g = zarr.open_group(str(self.path), mode="r")
        except Exception:  # noqa: BLE001 - anything unreadable is not ours
            return None
        return g if g.attrs.get("bkwaves_sweep") == STORE_MARKER else None

    def _create(self):
        import warnings

        import xarray as xr

        spec = self.spec
        shape, dims = spec.shape, spec.dims
        coords = {}
        if spec.combine == "zip":
            coords["point"] = np.arange(shape[0])
            for a in spec.axes:
                coords[a.name] = ("point", np.asarray(a.values))
        else:
            for a in spec.axes:
                coords[a.name] = np.asarray(a.values)
        ds = xr.Dataset(
            {
                "status": (dims, np.zeros(shape, np.int8)),
                "error": (dims, np.full(shape, "", dtype=object)),
                "key": (dims, np.full(shape, "", dtype=object)),
                "wall_s": (dims, np.full(shape, np.nan)),
                "check": (dims, np.full(shape, "", dtype=object)),
            },
            coords=coords,
        )
        ds["status"].attrs["doc"] = "0 pending, 1 done, 2 failed"
        ds["check"].attrs["doc"] = (
            "what a done point wrote: a digest of its values, then its per-point files "
            "(verified before a re-run skips it)"
        )
        ds["key"].attrs["doc"] = "hash of the point's input, task and bkwaves version"
        ds["wall_s"].attrs["units"] = "s"
        for a in spec.axes:
            ds[a.name].attrs["input_key"] = a.key
        ds.attrs.update(store_attrs(spec, STORE_MARKER, self.signature))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ds.to_zarr(str(self.path), mode="w-", consolidated=True)

    def status(self) -> np.ndarray:
        return self._read("status")

    def keys(self) -> np.ndarray:
        return self._read("key")

    def _variable(self, name: str, value):
        """The array of summary scalar ``name``, created at its first value."""
        if name in self.g:
            return self.g[name]

        dims = list(self.spec.dims)
        if isinstance(value, str):
            arr = self.g.create_array(
                name, shape=self.spec.shape, dtype=str, fill_value="", dimension_names=dims
            )
        else:
            arr = self.g.create_array(
                name,
                shape=self.spec.shape,
                dtype="f8",
                fill_value=float("nan"),
                dimension_names=dims,
            )
        _consolidate(self.path)
        return arr

    def write(self, records) -> None:
        """Write finished points ``(index, key, summary or None, error or None[, files])``:
        each variable is read, updated and written once for the whole batch; then the
        check (a digest of the values as stored, and the point's files), the status
        last, so a point is done only once all its values are on disk."""
        if not records:
            return
        reserved = {*self.spec.dims, *(a.name for a in self.spec.axes)}
        columns: dict[str, list] = {}
        stored: dict[tuple, dict] = {}
        for index, _key, summary, _error, *_files in records:
            idx = tuple(int(i) for i in index)
            stored[idx] = {}
            for name, value in (summary or {}).items():
                if name.startswith("__") or name in reserved:
                    continue  # inputs echoed back by the task are the coordinates
                columns.setdefault(name, []).append((idx, value))
        for name, cells in columns.items():
            arr = self._variable(name, cells[0][1])
            for idx, value in self._update(arr, cells, name):
                stored[idx][name] = value
        self._update(self.g["error"], [(tuple(r[0]), r[3] or "") for r in records], "error")
        self._update(self.g["key"], [(tuple(r[0]), r[1]) for r in records], "key")
        if "check" in self.g:
            checks = []
            for r in records:
                idx = tuple(int(i) for i in r[0])
                files = r[4] if len(r) > 4 else []
                checks.append((idx, " ".join([_digest(stored[idx]), *files])))
            self._update(self.g["check"], checks, "check")
        status = [(tuple(r[0]), FAILED if r[3] else DONE) for r in records]
        self._update(self.g["status"], status, "status")

    def verify(self, done: np.ndarray) -> tuple[np.ndarray, list[str]]:
        """Which of the ``done`` points (a boolean mask) hold what they wrote: their values
        (the digest of the stored values, so a lost chunk, whose values read as NaN, is
        seen) and their per-point files. Returns (mask of the points that do, notes).
        A store written before checks existed is trusted as it is."""
        if "check" not in self.g or not done.any():
            return done, []
        check = self._read("check")
        reserved = {"status", "error", "key", "check", *self.spec.dims}
        reserved |= {a.name for a in self.spec.axes}
        values = {
            name: self._read(name)
            for name, a in self.g.arrays()
            if name not in reserved and tuple(a.shape) == tuple(self.spec.shape)
        }
        pdir = points_dir(self.path)
        good = done.copy()
        lost_values = lost_files = 0
        for idx in zip(*np.nonzero(done), strict=True):
            digest, *files = str(check[idx]).split(" ") if check[idx] else ("",)
            have = {}
            for name, arr in values.items():
                v = arr[idx]
                if arr.dtype.kind not in "fiub":
                    if str(v) != "":
                        have[name] = str(v)
                elif not math.isnan(float(v)):
                    have[name] = float(v)
            if _digest(have) != digest:
                good[idx] = False
                lost_values += 1
            elif any(not (pdir / f).is_file() for f in files):
                good[idx] = False
                lost_files += 1
        notes = []
        if lost_values:
            notes.append(
                f"{lost_values} done points of {self.path} no longer hold the values they "
                "wrote (a chunk of the store lost or changed): computed again"
            )
        if lost_files:
            notes.append(f"{lost_files} done points miss their files in {pdir}: computed again")
        return good, notes

    def _read(self, name: str) -> np.ndarray:
        try:
            return np.asarray(self.g[name][...])
        except Exception as e:  # noqa: BLE001 - a damaged chunk (codec, JSON): one line
            raise ParameterError(
                f"-o {self.path}: the sweep store is damaged (variable {name!r} cannot be "
                f"read: {type(e).__name__}: {' '.join(str(e).split())[:160]}); run the "
                "sweep again with --overwrite, or into another store"
            ) from None

    def _update(self, arr, cells, name):
        """Set the cells of ``arr`` (read, updated, written whole); returns
        ``[(index, value as stored)]``."""
        values = self._read(name)
        text = arr.dtype.kind != "f" and arr.dtype.kind not in "iu"
        out = []
        for idx, value in cells:
            if isinstance(value, str) != text:
                value = math.nan if not text else str(value)
            values[idx] = value
            out.append((idx, values[idx]))
        arr[...] = values
        return [
            (idx, str(v) if text else float(v))
            for idx, v in out
            if (v != "" if text else not math.isnan(float(v)))
        ]


def _digest(values: dict) -> str:
    """A digest of a point's stored values (name -> float or str, fill values left out):
    exact (floats by their bits)."""
    items = sorted((k, v.hex() if isinstance(v, float) else f"s:{v}") for k, v in values.items())
    return hashlib.sha256(json.dumps(items).encode()).hexdigest()[:24]


def store_attrs(spec: SweepSpec, marker: str, signature: str) -> dict:
    """The attributes every sweep store carries (grid or adaptive)."""
    kind = "adaptive sweep" if spec.adaptive else "sweep"
    return {
        "bkwaves_sweep": marker,
        "title": spec.title or f"bkwaves {kind} of task {spec.task}",
        "task": spec.task,
        "sweep": json.dumps(spec.to_dict(), default=str),
        "signature": signature,
        "bkwaves_version": __version__,
    }


def _consolidate(path: Path):
    """Refresh the consolidated metadata (xarray opens the store without a warning)."""
    import warnings

    import zarr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        zarr.consolidate_metadata(str(path))


# --------------------------------------------------------------------------- running


@dataclass
class SweepResult:
    """What :func:`sweep` did: the dataset and the counts.

    Attributes
    ----------
    dataset : xarray.Dataset
        Every point's outputs indexed by the axes (also in the store ``out``).
    out : str
        The Zarr store.
    computed, skipped, failed : int
        Points computed now, found done in the store, and failed (their errors are in
        ``dataset["error"]``).
    wall_s : float
        Wall time [s].
    dashboard : str or None
        The Dask dashboard's address.
    interrupted : bool
        True when Ctrl-C or SIGTERM stopped the sweep (finished points are kept).
    workers : int
        Points computed at once (worker threads over all workers).
    extra : dict
        Task-specific information (adaptive sweeps: the learner's state).
    signal : int or None
        The signal that interrupted the sweep.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> out = os.path.join(tempfile.mkdtemp(), "speed.zarr")
    >>> spec = {"task": "speed", "axes": {"u_plus": {"values": [0.6, 0.8]}}}
    >>> r = bk.sweep(spec, out, workers=1)
    >>> r.computed, r.skipped, r.failed, r.dataset["c"].values.round(6).tolist()
    (2, 0, 0, [1.25, 1.666667])
    """

    dataset: Any
    out: str
    computed: int
    skipped: int
    failed: int
    wall_s: float
    dashboard: str | None = None
    interrupted: bool = False
    workers: int = 0  # points computed at once (worker threads over all workers)
    extra: dict = field(default_factory=dict)
    signal: int | None = None  # the signal that interrupted the sweep (SIGINT, SIGTERM)

    def to_dict(self) -> dict:
        """The counts as a dict (what ``bkwaves sweep --json`` prints).

        Returns
        -------
        dict
            out, points, computed, skipped, failed, wall_s [s], dashboard, interrupted,
            workers.

        Examples
        --------
        >>> import numpy as np
        >>> import xarray as xr
        >>> import bkwaves as bk
        >>> ds = xr.Dataset({"status": ("u_plus", np.ones(3, dtype=np.int8))})
        >>> d = bk.sweeps.SweepResult(ds, "s.zarr", computed=3, skipped=0, failed=0,
        ...                           wall_s=1.0).to_dict()
        >>> d["points"], d["computed"]
        (3, 3)
        """
        return {
            "out": self.out,
            "points": int(np.prod(self.dataset["status"].shape)),
            "computed": self.computed,
            "skipped": self.skipped,
            "failed": self.failed,
            "wall_s": self.wall_s,
            "dashboard": self.dashboard,
            "interrupted": self.interrupted,
            "workers": self.workers,
        }


def _slots(client) -> int:
    """Points the cluster computes at once: its worker threads, over all workers."""
    info = client.scheduler_info().get("workers", {})
    return int(sum(w.get("nthreads", 1) for w in info.values()))


def _client(scheduler: str | None, workers: int | None, processes: bool):
    """A distributed.Client: to ``scheduler`` if given, else to an embedded
    LocalCluster of ``workers`` threads in this process (default: one per core) or, with
    ``processes``, of ``workers`` single-threaded worker processes (benchmarks: threads
    are as fast here, the engines release the GIL, and start in 10 ms instead of 0.4 s)."""
    import os

    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="10s"), None
        except OSError as e:
            raise ParameterError(f"--scheduler {scheduler}: cannot connect ({e})") from None
    n = workers or os.cpu_count() or 1
    if processes:
        cluster = LocalCluster(
            n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
    else:
        cluster = LocalCluster(
            n_workers=1, threads_per_worker=n, processes=False, dashboard_address=":0"
        )
    return Client(cluster), cluster


def sweep(
    spec,
    out=None,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    processes: bool = False,
    overwrite: bool = False,
    retry_failed: bool = False,
    progress: bool = False,
    client=None,
    _stop_after: int | None = None,
) -> SweepResult:
    """Run a sweep on Dask (this is ``bk.sweep``; docs/sweeps.md).

    Finished points are written as they arrive; a point already done in ``out`` (same
    input, task and bkwaves version) is not recomputed; a point that fails records its
    error and the sweep goes on (``retry_failed`` recomputes failed points). Ctrl-C stops
    the sweep and keeps every finished point.

    Parameters
    ----------
    spec : SweepSpec or dict or str or pathlib.Path
        The sweep: a :class:`~bkwaves.sweeps.SweepSpec`, a dict of the SWEEP.toml schema
        (``task``, ``base``, ``axes``, ``combine``, ``output``) or the path of a
        SWEEP.toml file.
    out : str or pathlib.Path, optional
        The Zarr store (default: ``[output] path``, or SWEEP.zarr beside the file).
    scheduler : str, optional
        A running Dask scheduler's address (``tcp://HOST:8786``); default: a local
        cluster started and stopped here.
    workers : int, optional
        Workers of the local cluster (default: one per core).
    processes : bool, default False
        Local workers as processes (default: threads in this process).
    overwrite : bool, default False
        Replace a store that holds a different sweep.
    retry_failed : bool, default False
        Recompute the points that failed before.
    progress : bool, default False
        Show a progress bar.
    client : distributed.Client, optional
        Use this client (and its cluster) instead of making one.

    Returns
    -------
    SweepResult
        The dataset indexed by the axes and the counts of computed, skipped and failed
        points.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> spec = {"task": "speed", "axes": {"u_plus": {"values": [0.6, 0.8]}}}
    >>> out = os.path.join(tempfile.mkdtemp(), "speed.zarr")
    >>> result = bk.sweep(spec, out, workers=1)
    >>> result.dataset["c"].values, result.computed
    (array([1.25      , 1.66666667]), 2)
    >>> bk.sweep(spec, out, workers=1).skipped          # done points are not recomputed
    2
    >>> bk.sweep_result(out)["c"].sel(u_plus=0.8).item()
    1.6666666666666667
    """
    if isinstance(spec, str | Path):
        spec = load_sweep(spec)
    elif isinstance(spec, dict):
        spec = parse_sweep(spec)
    elif not isinstance(spec, SweepSpec):
        raise ParameterError(f"invalid spec = {spec!r}: a SweepSpec, a dict or a SWEEP.toml path")
    out = out if out is not None else spec.output_path
    if out is None:
        raise ParameterError("no output: give out (a .zarr path) or [output] path")
    out = Path(out)
    if out.suffix != ".zarr":
        raise ParameterError(f"invalid out = {str(out)!r}: a path ending in .zarr")
    from ._paths import check_writable

    check_writable(out, "out", directory=True)
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 1
    ):
        raise ParameterError(f"invalid workers = {workers!r}: allowed an integer >= 1")
    if spec.adaptive:
        from .sweeps_adaptive import run_adaptive

        return run_adaptive(
            spec,
            out,
            scheduler=scheduler,
            workers=workers,
            processes=processes,
            overwrite=overwrite,
            progress=progress,
            client=client,
        )
    t0 = time.perf_counter()
    store = _Store(out, spec, overwrite=overwrite)
    status, keys = store.status(), store.keys()
    points = [(idx, spec.point(idx)) for idx in spec.indices()]
    points = [(idx, spec.key(point), point) for idx, point in points]
    claimed = np.zeros(spec.shape, dtype=bool)
    for idx, k, _ in points:
        claimed[idx] = status[idx] == DONE and keys[idx] == k
    # verify what a re-run would skip: values as written, per-point files present
    verified, notes = store.verify(claimed)
    for note in notes:
        import warnings

        warnings.warn(note, SweepRepairWarning, stacklevel=2)
    todo, skipped = [], 0
    for idx, k, point in points:
        failed_before = status[idx] == FAILED and not retry_failed and keys[idx] == k
        if verified[idx] or failed_before:
            skipped += 1
            continue
        todo.append((idx, k, point))
    computed = failed = 0
    interrupted = False
    dashboard = None
    nworkers = 0
    own = None
    made_client = False  # a client made here (for a scheduler address or an own cluster)
    if todo:
        if client is None:
            client, own = _client(scheduler, workers, processes)
            made_client = True
        dashboard = getattr(client, "dashboard_link", None)
        nworkers = _slots(client)
        try:
            with _Signals() as signals:
                computed, failed, interrupted = _execute(
                    client, spec, store, todo, progress, dashboard, _stop_after, signals
                )
        finally:
            if made_client:
                client.close()
            if own is not None:
                own.close()
    ds = load_sweep_result(out)
    return SweepResult(
        dataset=ds,
        out=str(out),
        computed=computed,
        skipped=skipped,
        failed=failed,
        wall_s=time.perf_counter() - t0,
        dashboard=dashboard,
        interrupted=interrupted,
        workers=nworkers,
        signal=signals.received if todo else None,
    )


class _Signals:
    """While active (in the main thread), SIGINT (Ctrl-C) and SIGTERM interrupt the
    sweep: the finished points are flushed and the pending ones cancelled. A signal
    breaks the wait for the next point (KeyboardInterrupt) only while ``waiting``; during
    a write it is noted and acted on after it, so no chunk of the store is cut in half.
    ``received`` is the signal number."""

    def __init__(self):
        self.received = None
        self.waiting = False
        self._old = {}

    def _handler(self, signum, frame):
        self.received = signum
        if self.waiting:
            self.waiting = False
            raise KeyboardInterrupt

    def __enter__(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self._old[sig] = signal.signal(sig, self._handler)
            except ValueError:  # not the main thread: the defaults stay
                pass
        return self

    def __exit__(self, *exc):
        for sig, old in self._old.items():
            signal.signal(sig, old)
        return False


def _execute(client, spec, store, todo, progress, dashboard, stop_after, signals=None):
    """Submit the points, write them as they finish: every point that has arrived is in
    the store before the loop waits again (so within the time one batch takes to write,
    well under a second), and a signal is answered once the batch in hand is written."""
    from distributed import as_completed

    signals = signals if signals is not None else _Signals()
    futures = {}
    for idx, k, point in todo:
        fut = client.submit(
            run_point, spec.task, point, spec.keep, key=f"bkwaves-point-{k}", pure=False
        )
        futures[fut.key] = (idx, k, fut)
    bar = None
    if progress:
        from rich.console import Console
        from rich.progress import Progress

        Console(stderr=True).print(f"dashboard: {dashboard}")
        bar = Progress(transient=True)
        bar.start()
        task_id = bar.add_task(f"sweep ({spec.task})", total=len(todo))
    computed = failed = 0
    interrupted = False
    batch: list = []

    def flush():
        store.write(batch)
        batch.clear()

    ready = as_completed([f for _, _, f in futures.values()])
    try:
        while True:
            signals.waiting = True
            try:
                if signals.received is not None:
                    raise KeyboardInterrupt
                arrived = ready.next_batch(block=True)
            except StopIteration:
                arrived = None
            finally:
                signals.waiting = False
            if arrived is None:
                break
            for fut in arrived:
                idx, k, _ = futures[fut.key]
                try:
                    # result() also waits for a point whose result was lost with a killed
                    # worker and is being recomputed elsewhere
                    summary = fut.result()
                except Exception as exc:  # noqa: BLE001 - the point's own failure, recorded
                    batch.append((idx, k, None, f"{type(exc).__name__}: {exc}"))
                    failed += 1
                else:
                    files = _write_point_files(store.path, k, summary)
                    batch.append((idx, k, summary, None, files))
                    computed += 1
                fut.release()
                if len(batch) >= FLUSH_POINTS:
                    flush()
                if stop_after is not None and computed + failed >= stop_after:
                    interrupted = True
                    break
            flush()  # every point that arrived is written before waiting again
            if bar is not None:
                bar.update(task_id, completed=computed + failed)
            if interrupted or signals.received is not None:
                interrupted = True
                break
    except KeyboardInterrupt:
        interrupted = True
    finally:
        flush()
        if bar is not None:
            bar.stop()
        if interrupted:
            client.cancel([f for _, _, f in futures.values()])
    return computed, failed, interrupted


def points_dir(out) -> Path:
    """Where the per-point files of a sweep stored in ``out`` go: ``OUT.points/``, named
    by the point's key: ``KEY.events.parquet`` (and the other tables), ``KEY.nc``."""
    out = Path(out)
    return out.with_name(out.name + ".points")


def _write_point_files(out: Path, key: str, summary: dict) -> list[str]:
    """A point's tables and snapshots (popped from its summary), each written to a
    temporary name and renamed, before the point is marked done. Returns their names
    (recorded in the store's ``check``: a re-run verifies they are there)."""
    tables = summary.pop("__tables__", None) or {}
    snapshots = summary.pop("__snapshots__", None)
    if not tables and snapshots is None:
        return []
    from .io import _write_bytes

    d = points_dir(out)
    d.mkdir(exist_ok=True)
    names = []
    for name, df in tables.items():
        tmp = d / f".{key}.{name}.parquet.tmp"
        try:
            df.to_parquet(tmp)
            tmp.replace(d / f"{key}.{name}.parquet")
        except BaseException:  # (a full disk): no torn file left behind
            tmp.unlink(missing_ok=True)
            raise
        names.append(f"{key}.{name}.parquet")
    if snapshots is not None:
        # built in memory, written by Python: HDF5 meeting a full disk ends the process
        # (SIGSEGV), a failed Python write is an OSError
        _write_bytes(d / f"{key}.nc", snapshots.to_netcdf(engine="h5netcdf"))
        names.append(f"{key}.nc")
    return names


def load_sweep_result(out):
    """Open a sweep store (grid or adaptive) as an xarray Dataset (this is
    ``bk.sweep_result``).

    Parameters
    ----------
    out : str or pathlib.Path
        The sweep's Zarr store.

    Returns
    -------
    xarray.Dataset
        Every point's outputs indexed by the sweep's axes, loaded into memory, with
        ``status`` and ``error`` per point.

    See Also
    --------
    sweep : run a sweep.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> out = os.path.join(tempfile.mkdtemp(), "wave.zarr")
    >>> spec = {"task": "wave", "base": {"gamma": 0.3},
    ...         "axes": {"u_plus": {"values": [0.2, 0.6]}}}
    >>> _ = bk.sweep(spec, out, workers=1)
    >>> ds = bk.sweep_result(out)
    >>> [str(r) for r in ds["regime"].values]
    ['creep', 'pulse']
    """
    import warnings

    import xarray as xr
    import zarr

    try:
        g = zarr.open_group(str(out), mode="r", use_consolidated=False)
        marker = g.attrs.get("bkwaves_sweep")
    except Exception as e:  # noqa: BLE001 - reported as not a sweep store
        raise ParameterError(f"{out}: not a bkwaves sweep store ({e})") from None
    if marker == STORE_MARKER + "-adaptive":
        from .sweeps_adaptive import load_adaptive_result

        return load_adaptive_result(out)
    if marker != STORE_MARKER:
        raise ParameterError(f"{out}: not a bkwaves sweep store")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return xr.open_zarr(str(out), consolidated=True).load()
    except Exception as e:  # noqa: BLE001 - a damaged chunk (codec, JSON): one line
        raise ParameterError(
            f"{out}: the sweep store is damaged ({type(e).__name__}: "
            f"{' '.join(str(e).split())[:160]}); run the sweep again with --overwrite"
        ) from None
