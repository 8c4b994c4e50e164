"""Run a configuration (``bkwaves run CONFIG.toml``): build the engine, advance it, and
write self-describing outputs (see :mod:`bkwaves.io`).

Outputs of a run to ``OUT.nc`` (or ``.zarr``):

- snapshots of the fields on the grid at the configured times / every k events
  (chain: ``u``, ``u_t``, ``sliding``; free boundary: ``u``), the first one the initial
  state;
- ``OUT.events.parquet`` / ``.csv``: the event catalog;
- ``OUT.slips.parquet`` (chain: every slip of every block: the slip-front trajectories) or
  ``OUT.shocks.parquet`` (free boundary: shock trajectories);
- global attributes: the config (TOML as JSON), version, run id, seed, params, units.

Records are buffered and committed in blocks (every ``flush_every`` seconds of wall time
or 8 MB, before every checkpoint and at the end): the rows of the tables that are final
(events that ended and their slips) first, then the snapshots. Until the run is complete
they live in ``OUT.partial/``; a complete run is published onto ``OUT`` atomically. The
signal handlers are installed before anything else: Ctrl-C (SIGINT) and SIGTERM are noted
and acted on between engine chunks of ``chunk`` steps, never inside a write; the run then
commits what was computed, leaves ``OUT.checkpoint`` and ends with ``interrupted = True``
(``bkwaves run`` exits 130 or 143). A full disk keeps what was committed and raises
:class:`OutputFull` with one line saying what was kept and what was needed.
With a physical ([physical]) config the outputs are in SI units unless
``output.units = "dimensionless"``: x in m, t in s, slips in m, u_t in 1/s; u stays the
dimensionless stress (0: kinetic level, 1: static threshold).
"""

from __future__ import annotations

import contextlib
import json
import math
import shutil
import signal
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import __version__, _models
from ._models.chain import chain_from_config
from .catalog import DESCRIPTIONS, MOMENT_SCALE, MOMENT_SI
from .config import RunConfig
from .io import NO_SPACE, OutputError, RunWriter, partial_path

__all__ = [
    "OutputFull",
    "RunResult",
    "RunSummary",
    "run",
    "run_result",
    "simulate",
    "resume",
    "chain_from_config",
    "checkpoint_path",
]


class OutputFull(OutputError):
    """The disk filled up during a run: what was committed is kept in ``OUT.partial/``;
    the message (one line) says what was kept and how much space the output needs."""


class RunNotStarted(KeyboardInterrupt):
    """A signal (SIGINT, SIGTERM) arrived before the run started: nothing was computed
    and nothing written. ``signal`` is its number. (A KeyboardInterrupt: no ``except
    Exception`` on the way swallows it.)"""

    def __init__(self, signum: int):
        self.signal = signum
        name = signal.Signals(signum).name
        super().__init__(
            f"stopped by {name} before the run started: nothing was computed or written"
        )


def checkpoint_path(out) -> Path:
    """Where the checkpoint of the run writing ``out`` lives: ``OUT.checkpoint``.

    Parameters
    ----------
    out : str or pathlib.Path
        The run's output.

    Returns
    -------
    pathlib.Path
        ``OUT.checkpoint``.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.runner.checkpoint_path("run.zarr").name
    'run.zarr.checkpoint'
    """
    out = Path(out)
    return out.with_name(out.name + ".checkpoint")


def _save_checkpoint(out, cfg: RunConfig, engine_obj, written: int, runner: dict):
    """A data-only checkpoint (``bkwaves._checkpoint``): the config, the loop state and
    the engine's record."""
    from . import _checkpoint

    engine_meta, arrays = engine_obj._record()
    meta = {
        "model": cfg.model,
        "config": cfg.to_dict(),
        "base_dir": str(cfg.base_dir) if cfg.base_dir else "",
        "engine": engine_meta,
        "written": int(written),
        "runner": runner,
    }
    _checkpoint.write(checkpoint_path(out), "run", meta, arrays)


def _read_checkpoint(out) -> dict:
    """The state of ``OUT.checkpoint``; its ``engine`` is the engine's (meta, arrays)."""
    from . import _checkpoint
    from ._core import ParameterError

    path = checkpoint_path(out)
    if not path.exists():
        raise ParameterError(
            f"cannot resume {out}: no checkpoint {path} (runs write one when interrupted, "
            "and every --checkpoint-every seconds)"
        )
    meta, arrays = _checkpoint.read(path, "run", "bkwaves run")
    state = dict(meta)
    state["engine"] = (meta["engine"], arrays)
    state["path"] = str(path)
    return state


@dataclass
class RunSummary:
    """What :func:`run` and :func:`resume` return: the scalars of a run written to disk.

    Parameters
    ----------
    model : str
        The engine.
    out : str or None
        The output written.
    t : float
        Time reached (in the output's units; the paper's sqrt(m/k_p) by default).
    events : int
        Events recorded.
    snapshots : int
        Snapshots written.
    interrupted : bool
        Whether Ctrl-C or SIGTERM stopped the run (a checkpoint was left).
    wall_s : float
        Wall time [s].
    units : str
        The units of the outputs.
    extra : dict
        More scalars (blocks, ruptures, the signal, event statistics, ...).

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> s = bk.runner.run(cfg, out)
    >>> s.model, s.t, s.interrupted, s.units
    ('chain', 20.0, False, 'dimensionless (paper eq. dimless)')
    """

    model: str
    out: str | None
    t: float
    events: int
    snapshots: int
    interrupted: bool
    wall_s: float
    units: str
    extra: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The summary as one flat dict (what ``bkwaves run --json`` prints).

        Returns
        -------
        dict
            The fields, ``extra`` merged in.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> cfg = bk.config.parse_config({
        ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
        ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
        ...     "run": {"t_end": 20.0}})
        >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
        >>> d = bk.runner.run(cfg, out).to_dict()
        >>> d["t"], d["blocks"]
        (20.0, 200)
        """
        return {
            "model": self.model,
            "out": self.out,
            "t": self.t,
            "events": self.events,
            "snapshots": self.snapshots,
            "interrupted": self.interrupted,
            "wall_s": self.wall_s,
            "units": self.units,
            **self.extra,
        }


class _StopRequest:
    """While active, SIGINT (Ctrl-C) and SIGTERM only set a flag (and note the signal):
    the run loop checks it between engine chunks, so a write is never cut in half and the
    summary counts exactly what is on disk. Nested uses share the outermost one (the
    command line installs it before it reads the config)."""

    active: _StopRequest | None = None

    def __init__(self):
        self.requested = False
        self.signal: int | None = None
        # until the run begins to write, a signal stops it at once (nothing to keep)
        self.raising = True
        self._old = {}
        self._outer = None

    def _handler(self, signum, frame):
        self.requested = True
        self.signal = signum
        if self.raising:
            raise RunNotStarted(signum)

    def __enter__(self):
        if _StopRequest.active is not None:
            self._outer = _StopRequest.active
            return self._outer
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self._old[sig] = signal.signal(sig, self._handler)
            except ValueError:  # not in the main thread: leave the defaults
                pass
        from . import _signals

        _StopRequest.active = self
        if _signals.pending is not None:  # noted while the command line started
            self.requested, self.signal = True, _signals.pending
            self.__exit__()
            raise RunNotStarted(self.signal)
        return self

    def __exit__(self, *exc):
        if self._outer is not None:
            return False
        for sig, old in self._old.items():
            signal.signal(sig, old)
        _StopRequest.active = None
        return False


_SCALES = {
    "t": "t' = t sqrt(k_p/m) (paper eq. dimless)",
    "x": "x' = (x/a) sqrt(k_p/k_c) (paper eq. dimless)",
    # a planar model's across (the lattice's y' = j dy, dy = sqrt(k_p/k_y))
    "y": "y' = (y/a) sqrt(k_p/k_y) (paper eq. dimless; k_y the spring across, k_c unless dy "
    "is given)",
    "slip": "displacement in units of (f_r - f_s)/k_p",
    "u_t": "du/dt' (t' = t sqrt(k_p/m), paper eq. dimless)",
    "moment": MOMENT_SCALE,
}


class _Units:
    """Conversion of outputs to SI for physical configs. Dimensionless quantities carry
    the UDUNITS unit "1" and say how they are scaled in their own ``scale`` attribute."""

    def __init__(self, cfg: RunConfig):
        self.si = cfg.physical and cfg.output_units == "native"
        self.u = cfg.params.units

    @property
    def name(self) -> str:
        return "SI" if self.si else "dimensionless (paper eq. dimless)"

    def t(self, t):
        return self.u.time(t) if self.si else t

    def x(self, x):
        return self.u.length(x) if self.si else x

    def slip(self, s):
        return self.u.slip(s) if self.si else s

    def rate(self, u_t):
        """du/dt: per second in SI."""
        return np.asarray(u_t) / self.u.time_scale if self.si else u_t

    def coord_units(self):
        return ("m", "s") if self.si else ("1", "1")

    def coord_attrs(self):
        """More attributes of x, t and y (how each is scaled)."""
        if self.si:
            return ({}, {}, {})
        return ({"scale": _SCALES["x"]}, {"scale": _SCALES["t"]}, {"scale": _SCALES["y"]})

    def rate_spec(self):
        """Units and extra attributes of u_t."""
        return ("s-1", {}) if self.si else ("1", {"scale": _SCALES["u_t"]})

    def moment(self, m):
        """int slip dx: slip (m) times length (m) in SI (bkwaves.catalog)."""
        return self.u.slip(self.u.length(np.asarray(m))) if self.si else m

    def convert_table(self, df, times=(), xs=(), slips=(), moments=()):
        """(df in output units, {column: units}, {column: scale})."""
        units, scales = {}, {}
        df = df.copy()
        for cols, conv, si_unit, key in (
            (times, self.t, "s", "t"),
            (xs, self.x, "m", "x"),
            (slips, self.slip, "m", "slip"),
            (moments, self.moment, MOMENT_SI, "moment"),
        ):
            for c in cols:
                if c in df:
                    df[c] = conv(df[c].to_numpy())
                    units[c] = si_unit if self.si else "1"
                    if not self.si:
                        scales[c] = _SCALES[key]
        return df, units, scales


#: Relative tolerance (in units of output.snapshot_every) within which the last snapshot
#: time k dt is taken to be t_end: 3 x 0.1 is 0.30000000000000004 > 0.3.
SNAPSHOT_TOLERANCE = 1e-9


def _snapshot_times(cfg: RunConfig) -> np.ndarray:
    """t_k = k dt (never accumulated), k = 0, 1, ..., through t_end: a t_k within
    SNAPSHOT_TOLERANCE dt of t_end (rounding: 3 x 0.1 > 0.3) is t_end itself."""
    if cfg.snapshot_every is None:
        return np.array([], dtype=float)
    dt = cfg.snapshot_every
    if cfg.t_end is None:
        # open-ended by events: snapshot times far enough ahead, from the initial state
        return np.arange(0, 10**6) * dt
    n = int(math.floor(cfg.t_end / dt + SNAPSHOT_TOLERANCE))
    times = dt * np.arange(n + 1)
    return np.minimum(times, cfg.t_end)


def _attrs(cfg: RunConfig, units: _Units) -> dict:
    p = cfg.params
    return {
        "title": cfg.title or f"bkwaves {cfg.model} run",
        "model": cfg.model,
        # the seed of the run's random numbers: "" when nothing in it is random
        "seed": cfg.seed if cfg.random or cfg.seed is not None else "",
        "config": json.dumps(cfg.to_dict(), default=str),
        "params": json.dumps({k: v for k, v in p.to_dict().items() if k != "units"}),
        "friction": p.friction if _models.get(cfg.model).discrete else "",
        "friction_law": json.dumps({"law": p.law.name, **p.law_values()}),
        "physical_units": json.dumps(p.units.__dict__) if p.units is not None else "",
        "units_system": units.name,
        "u_units": "dimensionless stress: u = -(k_p X + f_s)/(f_r - f_s)",
        "bkwaves_version": __version__,
    }


def run(
    cfg: RunConfig,
    out=None,
    *,
    progress: bool = False,
    overwrite: bool = False,
    flush_every: float = 5.0,
    chunk: int = 20_000,
    checkpoint_every: float | None = None,
    _stop_after_chunks: int | None = None,
    _state: dict | None = None,
    _memory=None,
) -> RunSummary:
    """Run ``cfg`` and write its outputs to ``out`` (default ``cfg.output_path``; None:
    nothing written). An existing output is refused unless ``overwrite`` (then only files
    bkwaves wrote are replaced, once the new output is complete). Returns a summary;
    Ctrl-C or SIGTERM end the run cleanly, keep what was computed in ``OUT.partial/`` and
    leave a checkpoint ``OUT.checkpoint`` from which :func:`resume` continues (the
    summary's ``signal`` names the signal). Checkpoints are also written during the run:
    by default every DEFAULT_CHECKPOINT_S = 60 s of wall time (longer when a checkpoint
    is expensive: at most 1/20 of the wall time goes into them), so that a killed run
    (SIGKILL, a crash) can be resumed; ``checkpoint_every`` (seconds of wall time) sets
    the cadence, ``inf`` turns them off. A resumed run equals the
    uninterrupted one bit for bit: checkpoints are taken between engine chunks, where the
    engines restart exactly. A full disk raises :class:`OutputFull`.

    ``bk.run(cfg, out)`` (:func:`simulate`) runs and reads the result back; this is the
    runner behind it and behind ``bkwaves run``.

    Parameters
    ----------
    cfg : bkwaves.config.RunConfig
        The run.
    out : str or pathlib.Path, optional
        The output (.nc or .zarr); default ``cfg.output_path``.
    progress : bool, default False
        Show a progress bar.
    overwrite : bool, default False
        Replace an existing output (only files bkwaves wrote).
    flush_every : float, default 5
        Commit buffered records at least this often [s].
    chunk : int, default 20000
        Engine steps between checks for a signal and a checkpoint.
    checkpoint_every : float, optional
        Seconds of wall time between checkpoints (inf: only when interrupted).

    Returns
    -------
    RunSummary
        What was written, with the time reached and the counts.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> s = bk.runner.run(cfg, out)
    >>> s.t, s.snapshots, sorted(p for p in os.listdir(os.path.dirname(out)))[:2]
    (20.0, 1, ['front.nc', 'front.nc.events.csv'])
    """
    from ._core import ParameterError

    with _StopRequest() as stop_request:  # first: a signal from here on is never lost
        out = out if out is not None else cfg.output_path
        cfg = cfg.seeded()  # a random run without a seed gets a fresh one, recorded
        if checkpoint_every is not None and out is None:
            raise ParameterError("checkpoints need an output path (-o OUT)")
        if checkpoint_every is not None and not checkpoint_every > 0:
            raise ParameterError(
                f"invalid checkpoint_every = {checkpoint_every}: allowed checkpoint_every > 0 (s)"
            )
        ctl = _Control(
            out, cfg, checkpoint_every, _stop_after_chunks, _state, stop_request, _memory
        )
        if out is not None:
            _check_output(out, cfg)
        _import_writers(out)
        # from here on a signal is noted and acted on between engine chunks
        stop_request.raising = False
        if stop_request.requested:  # (before anything is written: nothing to keep)
            raise RunNotStarted(stop_request.signal or signal.SIGINT)
        model = _models.get(cfg.model)
        summary = model.run(cfg, out, progress, overwrite, flush_every, chunk, ctl)
        if not summary.interrupted and stop_request.requested:
            # a signal after the output was published: it is complete; said, not lost
            summary.extra["late_signal"] = ctl.signal_name()
        return summary


def _import_writers(out) -> None:
    """Import what writing the outputs needs now, while a signal still stops the run at
    once: later, an import (seconds on a busy machine) would delay the answer."""
    import pandas  # noqa: F401

    if out is None:
        return
    import pyarrow.parquet  # noqa: F401

    if Path(out).suffix == ".zarr":
        import zarr  # noqa: F401  (written by zarr directly: no xarray, no dask)
    else:
        import h5netcdf  # noqa: F401


def _check_output(out, cfg: RunConfig) -> None:
    """Before any work: the output path can be written, and the output fits."""
    from ._core import ParameterError
    from .io import SUFFIXES
    from .limits import check_free_space, estimate

    text = str(out)
    if "\x00" in text or not text.strip():
        raise ParameterError(f"invalid output path = {text!r}: allowed a file name (no NUL)")
    p = Path(out)
    if p.suffix not in SUFFIXES:
        raise ParameterError(
            f"invalid output path = {text!r}: allowed suffixes .nc (NetCDF) or .zarr (Zarr)"
        )
    parent = p.resolve().parent
    if not parent.is_dir():
        raise ParameterError(f"output path {text!r}: the directory {parent} does not exist")
    import tempfile

    try:
        with tempfile.NamedTemporaryFile(dir=parent, prefix=".bkwaves-probe-"):
            pass
    except OSError as e:
        raise ParameterError(
            f"output path {text!r}: cannot write in {parent} ({e.strerror or e})"
        ) from None
    check_free_space(p, estimate(cfg).output_bytes)


def resume(
    out,
    *,
    progress: bool = False,
    flush_every: float = 5.0,
    chunk: int = 20_000,
    checkpoint_every: float | None = None,
    _stop_after_chunks: int | None = None,
) -> RunSummary:
    """Continue the run that wrote ``out`` from its checkpoint ``OUT.checkpoint``.

    Parameters
    ----------
    out : str or pathlib.Path
        The interrupted run's output.
    progress : bool, default False
        Show a progress bar.
    flush_every : float, default 5
        Commit buffered records at least this often [s].
    chunk : int, default 20000
        Engine steps between checks for a signal and a checkpoint.
    checkpoint_every : float, optional
        Seconds of wall time between checkpoints.

    Returns
    -------
    RunSummary
        The summary of the whole run.

    Examples
    --------
    A run stopped after its first chunk (as Ctrl-C stops it) and resumed has the slips
    of an uninterrupted run, bit for bit:

    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> cut = bk.runner.run(cfg, out, chunk=200, _stop_after_chunks=1)   # stands for Ctrl-C
    >>> cut.interrupted, os.path.exists(bk.runner.checkpoint_path(out))
    (True, True)
    >>> bk.runner.resume(out).t
    20.0
    >>> whole = bk.run(cfg).tables["slips"]
    >>> bk.io.load_tables(out)[1]["slips"].t_start.equals(whole.t_start)
    True
    """
    from .config import parse_config

    with _StopRequest():
        state = _read_checkpoint(out)
        # the recorded config holds its paths resolved against its folder already
        # (state["base_dir"]): joined again, a relative one would point elsewhere
        cfg = parse_config(state["config"])
        return run(
            cfg,
            out,
            progress=progress,
            flush_every=flush_every,
            chunk=chunk,
            checkpoint_every=checkpoint_every,
            _stop_after_chunks=_stop_after_chunks,
            _state=state,
        )


class _MemoryWriter:
    """The writer interface of :class:`bkwaves.io.RunWriter`, keeping everything in
    memory (for :func:`run_result`): tables always, snapshots when asked."""

    path = None
    record_bytes = 0

    def __init__(self, snapshots: bool):
        self.keep_snapshots = snapshots
        self.tables: dict = {}
        self.table_units: dict = {}
        self.times: list = []
        self.fields: dict = {}
        self.count = 0
        self.closed = False
        self._rows: dict = {}
        self._attrs: dict = {}

    def start(self, x, variables, attrs, coord_units, y=None):
        self.x, self.variables, self.attrs, self.coord_units = x, variables, attrs, coord_units
        self.y = y
        self.record_shape = (len(x),) if y is None else (len(y), len(x))

    @property
    def records(self) -> int:
        return self.count

    def append(self, t, **fields):
        self.append_block([t], **{k: np.asarray(v)[None, ...] for k, v in fields.items()})

    def append_block(self, t, **fields):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self.keep_snapshots:
            self.times.extend(t.tolist())
            for k, v in fields.items():
                rows = np.array(v, copy=True).reshape(len(t), *self.record_shape)
                self.fields.setdefault(k, []).append(rows)
        self.count += len(t)

    def append_rows(self, name, df, units=None, csv=None, scales=None, descriptions=None):
        self._rows.setdefault(name, []).append(df)
        attrs = self._attrs.setdefault(name, {"units": {}, "scales": {}, "descriptions": {}})
        for key, given in (("units", units), ("scales", scales), ("descriptions", descriptions)):
            if given:
                attrs[key] = dict(given)
        if units:
            self.table_units[name] = dict(units)

    def table_rows(self, name) -> int:
        return sum(len(d) for d in self._rows.get(name, []))

    def commit(self):
        pass

    def close(self, publish=True, remove=()):
        import pandas as pd

        for name, dfs in self._rows.items():
            df = pd.concat(dfs, ignore_index=True)
            df.attrs = {k: dict(v) for k, v in self._attrs[name].items()}  # as bk.load
            self.tables[name] = df
        self.closed = True

    def abandon(self):
        self.closed = True

    def dataset(self):
        """The snapshots as an xarray Dataset (dims t, x; t, y, x on a plane), as bk.load
        would read them."""
        import xarray as xr

        x_units, t_units = self.coord_units
        space = ("x",) if self.y is None else ("y", "x")
        data = {}
        for k, rows in self.fields.items():
            units, long_name, dtype, *_ = self.variables[k]
            data[k] = (
                ("t", *space),
                np.concatenate(rows).astype(dtype),
                {"units": units, "long_name": long_name},
            )
        coords = {
            "t": ("t", np.asarray(self.times), {"units": t_units}),
            "x": ("x", np.asarray(self.x), {"units": x_units}),
        }
        if self.y is not None:
            coords["y"] = ("y", np.asarray(self.y), {"units": x_units})
        return xr.Dataset(data, coords=coords, attrs=self.attrs)


@dataclass
class RunResult:
    """A run computed by :func:`bkwaves.run`.

    Attributes
    ----------
    summary : dict
        The scalars of the run: time reached, event counts, event statistics (b-value
        and its interval where the catalog is large enough, recurrence).
    tables : dict of pandas.DataFrame
        ``events`` and ``slips`` (chain) or ``shocks`` (free boundary), and
        ``ruptures``, in the output units.
    snapshots : xarray.Dataset or None
        The snapshots, when asked for (``snapshots=True``) or read back from ``out``.
    config : bkwaves.config.RunConfig
        The validated configuration that ran.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> res = bk.run(cfg)
    >>> res.summary["t"], len(res.events), res.events is res.tables["events"]   # one front
    (20.0, 1, True)
    """

    summary: dict
    tables: dict
    snapshots: object = None
    config: RunConfig | None = None

    @property
    def events(self):
        """The event catalog (``tables["events"]``)."""
        return self.tables.get("events")


def _event_statistics(events, ruptures=None) -> dict:
    """The summary scalars of a run's catalogs (:func:`bkwaves.catalog.statistics`: over
    the complete ruptures when there are, else the complete events)."""
    from .catalog import statistics, summary_scalars

    return summary_scalars(statistics(events, ruptures))


def run_result(cfg: RunConfig, *, snapshots: bool = False, chunk: int = 20_000) -> RunResult:
    """Run ``cfg`` in memory: nothing is written to disk (``cfg.output_path`` is ignored).
    Returns the summary scalars, the tables and, with ``snapshots=True``, the snapshots.

    Parameters
    ----------
    cfg : bkwaves.config.RunConfig
        The run.
    snapshots : bool, default False
        Keep the snapshots in memory.
    chunk : int, default 20000
        Engine steps between checks for a signal.

    Returns
    -------
    RunResult
        The summary, the tables and the snapshots if asked.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> res = bk.runner.run_result(cfg, snapshots=True)
    >>> res.summary["t"], sorted(res.tables), res.snapshots.u.shape
    (20.0, ['events', 'ruptures', 'slips'], (1, 200))
    """
    mem = _MemoryWriter(snapshots)
    s = run(cfg, None, chunk=chunk, _memory=mem)
    summary = {k: v for k, v in s.to_dict().items() if k not in ("out", "units")}
    summary.pop("counters", None)
    summary.pop("warnings", None)
    summary.update(_event_statistics(mem.tables.get("events"), mem.tables.get("ruptures")))
    return RunResult(
        summary=summary,
        tables=mem.tables,
        snapshots=mem.dataset() if snapshots else None,
        config=cfg,
    )


def simulate(cfg, out=None, *, snapshots: bool = False, progress: bool = False) -> RunResult:
    """Run a configuration and return its result (this is ``bk.run``).

    Parameters
    ----------
    cfg : bkwaves.config.RunConfig or dict or str or pathlib.Path
        A :class:`~bkwaves.config.RunConfig`, a dict of the TOML schema
        (``RunConfig.to_dict()``) or the path of a TOML file (docs/usage.md lists the
        keys, their units and allowed values).
    out : str or pathlib.Path, optional
        Without it nothing is written (``[output] path`` is ignored); with a path ending
        in .nc or .zarr the outputs are written as ``bkwaves run`` writes them (snapshots,
        and the tables as Parquet and CSV beside them) and the result is read back from
        them.
    snapshots : bool, default False
        Keep the snapshots in memory (``result.snapshots``).
    progress : bool, default False
        Show a progress bar.

    Returns
    -------
    RunResult
        The summary scalars, the tables and (if asked) the snapshots.

    Examples
    --------
    A source of counter-propagating waves (Sec. V): a stress maximum of curvature
    a = 1e-4 < a_max; its events recur at the source period (1 + exp(-pi gamma /
    sqrt(1 - gamma^2)))/v = 137.23:

    >>> import numpy as np
    >>> import bkwaves as bk
    >>> cfg = {"model": "free_boundary", "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
    ...        "domain": {"length": 90.0, "grid": 451},
    ...        "initial": {"kind": "bumps", "base": 0.499,
    ...                    "bumps": [{"center": 45.0, "width": 50.0, "height": 0.5}]},
    ...        "run": {"max_events": 3}}
    >>> result = bk.run(cfg)
    >>> result.summary["events"]
    3
    >>> np.round(np.diff(result.events["t_start"]), 2)
    array([137.23, 137.23])
    """
    from .config import RunConfig, load_config

    if isinstance(cfg, str | Path):
        cfg = load_config(cfg)
    elif isinstance(cfg, dict):
        cfg = RunConfig.from_dict(cfg)
    elif not isinstance(cfg, RunConfig):
        from ._core import ParameterError

        raise ParameterError(f"invalid cfg = {cfg!r}: a RunConfig, a dict or a TOML path")
    if out is None:
        return run_result(cfg, snapshots=snapshots)
    from .io import load_tables

    s = run(cfg, out, progress=progress)
    ds, tables = load_tables(out)
    summary = {k: v for k, v in s.to_dict().items() if k not in ("units", "counters", "warnings")}
    summary.update(_event_statistics(tables.get("events"), tables.get("ruptures")))
    return RunResult(
        summary=summary, tables=tables, snapshots=ds if snapshots else None, config=cfg
    )


#: Checkpoints by default (a run with an output and no ``checkpoint_every``): every
#: DEFAULT_CHECKPOINT_S seconds of wall time, or CHECKPOINT_COST_RATIO times as long as
#: the last checkpoint took to write if that is longer (so they cost at most 1/20 of
#: the run), and when a run is interrupted.
DEFAULT_CHECKPOINT_S = 60.0
CHECKPOINT_COST_RATIO = 20.0


class _Control:
    """Checkpoint timing, the resume state, and the stop request of a run."""

    def __init__(self, out, cfg, every, stop_after, state, stop_request, memory=None):
        self.out, self.cfg = out, cfg
        # None: the default cadence (by wall time and by the cost of a checkpoint)
        self.every = every
        self.memory = memory
        self.stop_after = stop_after
        self.state = state
        self.stop_request = stop_request
        self.chunks = 0
        self.last = time.perf_counter()
        self.cost = 0.0  # seconds the last checkpoint took

    @property
    def resuming(self) -> bool:
        return self.state is not None

    @property
    def stop(self) -> bool:
        return self.stop_request.requested

    def chunk_done(self) -> None:
        self.chunks += 1
        if self.stop_after is not None and self.chunks >= self.stop_after:
            self.stop_request.requested = True

    def interval(self) -> float:
        """Seconds of wall time between checkpoints."""
        if self.every is not None:
            return self.every
        return max(DEFAULT_CHECKPOINT_S, CHECKPOINT_COST_RATIO * self.cost)

    def due(self) -> bool:
        if self.out is None or self.memory is not None:
            return False
        return time.perf_counter() - self.last > self.interval()

    def save(self, engine_obj, writer, runner=None):
        """Commit what is buffered, then checkpoint: the checkpoint never counts records
        that are not on disk."""
        if self.out is None:
            return
        t0 = time.perf_counter()
        writer.commit()
        _save_checkpoint(self.out, self.cfg, engine_obj, writer.count, runner or {})
        self.last = time.perf_counter()
        self.cost = self.last - t0

    def signal_name(self) -> str | None:
        sig = self.stop_request.signal
        return None if sig is None else signal.Signals(sig).name


def _open_writer(
    out,
    cfg,
    units,
    x,
    variables,
    ctl,
    overwrite,
    flush_every,
    resume_rows,
    engine_attrs=None,
    y=None,
):
    """The output writer (None without an output); when resuming it continues after the
    records and table rows the checkpoint counts. ``engine_attrs``: the engine's own
    attributes (the chain's step, integrator and step_tolerance); ``y``: the positions
    across of a planar model (its snapshots then have dims t, y, x)."""
    attrs = {**_attrs(cfg, units), **(engine_attrs or {})}
    y = None if y is None else units.x(y)
    if ctl.memory is not None:  # run_result: everything kept in memory
        ctl.memory.start(units.x(x), variables, attrs, units.coord_units(), y=y)
        return ctl.memory
    if not out:
        return None
    return RunWriter(
        out,
        units.x(x),
        variables,
        y=y,
        attrs=attrs,
        coord_units=units.coord_units(),
        coord_attrs=units.coord_attrs(),
        overwrite=overwrite,
        resume_count=ctl.state["written"] if ctl.resuming else None,
        resume_rows=resume_rows if ctl.resuming else None,
        flush_every=flush_every,
    )


def _finish(writer, ctl, engine_obj, runner_state, give_all, interrupted) -> bool:
    """End a run: a complete one is checkpointed at its end, then published (a failed
    publication keeps it whole, to publish with ``--resume``); an interrupted one
    commits, checkpoints, then adds the rows of the running event (dropped again when
    resuming). A signal
    that arrives after the last engine chunk, or while the output is being merged, stops
    the publication before anything is renamed: the run is kept in ``OUT.partial/`` with
    a checkpoint of its end, and ``--resume`` publishes it. Returns whether the run
    ended interrupted."""
    if writer is None:
        return interrupted
    if ctl.memory is not None:
        give_all()
        writer.close()
        return interrupted
    if interrupted or ctl.stop:
        ctl.save(engine_obj, writer, runner_state)
        give_all()
        writer.close(publish=False)
        return True
    give_all()
    # the checkpoint of its end first: whatever befalls the publication (a full disk,
    # HDF5 failing, a signal), the run is kept whole and --resume publishes it
    writer.commit()  # (a full disk here keeps the records that fit: one line)
    ck = checkpoint_path(ctl.out)
    try:
        ctl.save(engine_obj, writer, runner_state)
        spare = [ck]
    except OSError as e:
        if e.errno not in NO_SPACE:
            raise
        # no room for the checkpoint (an earlier one is kept): published all the same,
        # the output may fit; if not, the committed records are kept, as ever
        spare = []
    # (the end checkpoint is given up and the publication tried again if the output
    # lacks its room: a disk that held the output before still does)
    published = writer.close(publish=True, remove=[ck], stop=lambda: ctl.stop, spare=spare)
    return not published


@contextlib.contextmanager
def _guard_writes(bar, writer, cfg, where):
    """Around a run loop: a full disk keeps what was written and raises OutputFull
    (``where()`` gives the events finished and the time reached); any other failure
    closes the progress bar and leaves the partial output unpublished."""
    try:
        yield
    except OutputError:
        bar.close()
        raise
    except OSError as err:
        bar.close()
        if writer is None or isinstance(writer, _MemoryWriter):
            raise
        events, t_now = where()
        if err.errno not in NO_SPACE:
            raise _write_failed(err, writer, events, t_now) from err
        raise _disk_full(err, writer, cfg, events, t_now) from err
    except BaseException:
        bar.close()
        if writer is not None and not writer.closed:
            writer.close(publish=False)
        raise


def _continue_hint(writer) -> str:
    ck = checkpoint_path(writer.path)
    if ck.exists():
        return f"then continue with `bkwaves run --resume {writer.path}` (from its checkpoint)"
    return "then run again with --overwrite (or publish what was kept: bkwaves.io.finalize)"


def _write_failed(err, writer, events, t_now) -> OutputError:
    """The one-line report of a write that failed other than for space (a folder
    removed or made read-only): the committed records and the last checkpoint stay."""
    writer.abandon()
    partial = partial_path(writer.path)
    where = f" ({err.filename})" if getattr(err, "filename", None) else ""
    if partial.is_dir():
        kept = f"kept {writer.count} snapshots and the catalog of {events} events in {partial}"
        then = _continue_hint(writer)
    else:  # (its checkpoint, if any, counts records that are gone: no resuming)
        kept = f"{partial} is gone, nothing written there is kept"
        then = "then run again with --overwrite"
    return OutputError(
        err.errno,
        f"cannot write {writer.path}: {err.strerror or err}{where} (the run reached "
        f"t = {t_now:.6g}); {kept}; fix the folder, {then}",
    )


def _disk_full(err, writer, cfg, events, t_now) -> OutputFull:
    """The one-line report of a full disk (the committed records stay in OUT.partial/;
    when the publication of a complete run failed, every record and its checkpoint)."""
    writer.abandon()
    partial = partial_path(writer.path)
    import warnings

    from .limits import _bytes, estimate

    kept = sum(f.stat().st_size for f in partial.rglob("*") if f.is_file())
    free = shutil.disk_usage(partial).free
    then = _continue_hint(writer)
    import errno

    # (EFBIG: a file past the size limit of `ulimit -f`: no SIGXFSZ, bkwaves ignores it)
    full = "file size limit reached" if err.errno == errno.EFBIG else "disk full"
    free_it = "raise the limit" if err.errno == errno.EFBIG else "free space"
    if getattr(err, "publishing", False):
        # the run is complete: only the merged output did not fit
        need = getattr(err, "need", None)
        need = f"publishing needs up to {_bytes(need)}" if need else "publishing needs more room"
        if checkpoint_path(writer.path).exists():
            then = f"then `bkwaves run --resume {writer.path}` publishes it"
        else:
            # (no checkpoint to resume from: every record is there, finalize publishes it)
            then = (
                'then publish it with bkwaves.io.finalize: python -c "import bkwaves; '
                f"bkwaves.io.finalize('{writer.path}')\""
            )
        return OutputFull(
            err.errno,
            f"{full} publishing {writer.path} (the run is complete, t = {t_now:.6g}): "
            f"kept all {writer.count} snapshots and the catalog of {events} events in "
            f"{partial} ({_bytes(kept)}); {need}, {_bytes(free)} free; {free_it}, {then}",
        )
    # the figure of the warning before the run (bk.limits.check_free_space): the
    # snapshots' bytes, not the kept files extrapolated (their headers and catalog would
    # count once per snapshot)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        planned = estimate(cfg).output_bytes
    need = f"the output needs about {_bytes(planned)} of snapshots"
    return OutputFull(
        err.errno,
        f"{full} writing {writer.path} (the run reached t = {t_now:.6g}): kept "
        f"{writer.count} snapshots and the catalog of {events} events in {partial} "
        f"({_bytes(kept)}); {need}, {_bytes(free)} free; {free_it}, {then}",
    )


def _described(df) -> dict:
    """The definitions of the columns of ``df`` that every catalog shares."""
    return {c: DESCRIPTIONS[c] for c in df.columns if c in DESCRIPTIONS}


def _write_ruptures(writer, units, rup) -> None:
    """Write the ruptures table in the output units (the magnitude of the moment there)."""
    from .stats import moment_magnitude

    if writer is None or rup is None:
        return
    rup, ru, rs = units.convert_table(
        rup, times=("t_start", "t_end", "duration"), xs=("x_start", "swept"), moments=("moment",)
    )
    rup["magnitude"] = moment_magnitude(rup["moment"].to_numpy(dtype=float))
    writer.append_rows("ruptures", rup, ru, scales=rs, descriptions=_described(rup))


def _complete(first: int, rows: int, finished: int) -> np.ndarray:
    """The ``complete`` column of catalog rows ``first .. first + rows``: the engines finish
    events in order, so the rows before ``finished`` are complete; the one after (at most
    one, written only at the end of a run) is the event still running when the run
    stopped, cut at that time."""
    return np.arange(first, first + rows) < finished


def _frame(cols: dict, stop: int | None = None):
    import pandas as pd

    df = pd.DataFrame(cols)
    return df if stop is None else df.iloc[:stop]
