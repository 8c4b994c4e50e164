"""Run a configuration (``bkwaves run CONFIG.toml``): build the engine, advance it, and
write self-describing outputs incrementally (see :mod:`bkwaves.io`).

Outputs of a run to ``OUT.nc`` (or ``.zarr``):

- snapshots of the fields on the grid at the configured times / every k events
  (chain: ``u``, ``u_t``, ``mode``; free boundary: ``u``), appended as they are computed;
- ``OUT.events.parquet`` / ``.csv``: the event catalog;
- ``OUT.slips.parquet`` (chain: every slip of every block: the slip-front trajectories) or
  ``OUT.shocks.parquet`` (free boundary: shock trajectories);
- global attributes: the config (TOML as JSON), version, seed, params, units.

Tables are rewritten atomically at least every ``table_every`` seconds of wall time and
at the end, so an interrupted run (Ctrl-C, SIGTERM) keeps every completed snapshot and
the tables; the run then ends normally with ``interrupted = True``. (Ctrl-C and SIGTERM
are noted and acted on between engine chunks of ``chunk`` steps, never inside a write.)
With a physical ([physical]) config the outputs are in SI units unless
``output.units = "dimensionless"``: x in m, t in s, slips in m; u stays the
dimensionless stress (0: kinetic level, 1: static threshold).
"""

from __future__ import annotations

import json
import math
import signal
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import __version__
from ._progress import ProgressBar
from .config import RunConfig, initial_state
from .io import RunWriter

__all__ = [
    "RunResult",
    "RunSummary",
    "run",
    "run_result",
    "simulate",
    "resume",
    "checkpoint_path",
]


def checkpoint_path(out) -> Path:
    """Where the checkpoint of the run writing ``out`` lives: ``OUT.checkpoint``."""
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
    """While active, SIGINT (Ctrl-C) and SIGTERM only set a flag: the run loop checks it
    between engine chunks, so a write is never cut in half and the summary counts exactly
    what is on disk."""

    def __init__(self):
        self.requested = False
        self._old = {}

    def _handler(self, signum, frame):
        self.requested = True

    def __enter__(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self._old[sig] = signal.signal(sig, self._handler)
            except ValueError:  # not in the main thread: leave the defaults
                pass
        return self

    def __exit__(self, *exc):
        for sig, old in self._old.items():
            signal.signal(sig, old)
        return False


class _Units:
    """Conversion of outputs to SI for physical configs."""

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

    def coord_units(self):
        return ("m", "s") if self.si else ("x' (paper eq. dimless)", "t' (paper eq. dimless)")

    def convert_table(self, df, times=(), xs=(), slips=()):
        units = {}
        df = df.copy()
        for c in times:
            if c in df:
                df[c] = self.t(df[c].to_numpy())
                units[c] = "s" if self.si else "t'"
        for c in xs:
            if c in df:
                df[c] = self.x(df[c].to_numpy())
                units[c] = "m" if self.si else "x'"
        for c in slips:
            if c in df:
                df[c] = self.slip(df[c].to_numpy())
                units[c] = "m" if self.si else "(f_r - f_s)/k_p"
        return df, units


def _snapshot_times(cfg: RunConfig) -> np.ndarray:
    if cfg.snapshot_every is None:
        return np.array([], dtype=float)
    if cfg.t_end is None:
        # open-ended by events: snapshot times far enough ahead
        return np.arange(1, 10**6) * cfg.snapshot_every
    n = int(math.floor(cfg.t_end / cfg.snapshot_every * (1 + 1e-12)))
    return cfg.snapshot_every * np.arange(n + 1)


def _attrs(cfg: RunConfig, units: _Units) -> dict:
    p = cfg.params
    return {
        "title": cfg.title or f"bkwaves {cfg.model} run",
        "model": cfg.model,
        "seed": cfg.seed,
        "config": json.dumps(cfg.to_dict(), default=str),
        "params": json.dumps({k: v for k, v in p.to_dict().items() if k != "units"}),
        "friction": p.friction if cfg.model == "chain" else "",
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
    table_every: float = 5.0,
    chunk: int = 20_000,
    checkpoint_every: float | None = None,
    _stop_after_chunks: int | None = None,
    _state: dict | None = None,
    _memory=None,
) -> RunSummary:
    """Run ``cfg`` and write its outputs to ``out`` (default ``cfg.output_path``; None:
    nothing written). Returns a summary; Ctrl-C or SIGTERM end the run cleanly and leave
    a checkpoint ``OUT.checkpoint`` from which :func:`resume` continues. With
    ``checkpoint_every`` (seconds of wall time) checkpoints are also written during the
    run. A resumed run equals the uninterrupted one bit for bit: checkpoints are taken
    between engine chunks, where the engines restart exactly."""
    from ._core import ParameterError

    out = out if out is not None else cfg.output_path
    if checkpoint_every is not None and out is None:
        raise ParameterError("checkpoints need an output path (-o OUT)")
    if checkpoint_every is not None and not checkpoint_every > 0:
        raise ParameterError(
            f"invalid checkpoint_every = {checkpoint_every}: allowed checkpoint_every > 0 (s)"
        )
    ctl = _Control(out, cfg, checkpoint_every, _stop_after_chunks, _state, _memory)
    if cfg.model == "chain":
        return _run_chain(cfg, out, progress, table_every, chunk, ctl)
    return _run_free_boundary(cfg, out, progress, table_every, chunk, ctl)


def resume(
    out,
    *,
    progress: bool = False,
    table_every: float = 5.0,
    chunk: int = 20_000,
    checkpoint_every: float | None = None,
    _stop_after_chunks: int | None = None,
) -> RunSummary:
    """Continue the run that wrote ``out`` from its checkpoint ``OUT.checkpoint``."""
    from .config import parse_config

    state = _read_checkpoint(out)
    base = Path(state["base_dir"]) if state["base_dir"] else None
    cfg = parse_config(state["config"], base_dir=base)
    return run(
        cfg,
        out,
        progress=progress,
        table_every=table_every,
        chunk=chunk,
        checkpoint_every=checkpoint_every,
        _stop_after_chunks=_stop_after_chunks,
        _state=state,
    )


class _MemoryWriter:
    """The writer interface of :class:`bkwaves.io.RunWriter`, keeping everything in
    memory (for :func:`run_result`): tables always, snapshots when asked."""

    def __init__(self, snapshots: bool):
        self.keep_snapshots = snapshots
        self.tables: dict = {}
        self.table_units: dict = {}
        self.times: list = []
        self.fields: dict = {}

    def start(self, x, variables, attrs, coord_units):
        self.x, self.variables, self.attrs, self.coord_units = x, variables, attrs, coord_units

    def append(self, t, **fields):
        if self.keep_snapshots:
            self.times.append(float(t))
            for k, v in fields.items():
                self.fields.setdefault(k, []).append(np.array(v, copy=True))

    def write_table(self, name, df, units=None, csv=True):
        self.tables[name] = df
        self.table_units[name] = dict(units or {})

    def close(self):
        pass

    def dataset(self):
        """The snapshots as an xarray Dataset (dims t, x), as bk.load would read them."""
        import xarray as xr

        x_units, t_units = self.coord_units
        data = {}
        for k, rows in self.fields.items():
            units, long_name, dtype = self.variables[k]
            data[k] = (
                ("t", "x"),
                np.asarray(rows, dtype=dtype),
                {"units": units, "long_name": long_name},
            )
        return xr.Dataset(
            data,
            coords={
                "t": ("t", np.asarray(self.times), {"units": t_units}),
                "x": ("x", np.asarray(self.x), {"units": x_units}),
            },
            attrs=self.attrs,
        )


@dataclass
class RunResult:
    """A run computed in memory (:func:`bkwaves.run`): ``summary`` (the scalars of the run:
    time reached, event counts, event statistics), ``tables`` (``events`` and ``slips`` or
    ``shocks`` as pandas DataFrames, in the output units) and ``snapshots`` (an xarray
    Dataset, or None unless asked)."""

    summary: dict
    tables: dict
    snapshots: object = None
    config: RunConfig | None = None

    @property
    def events(self):
        return self.tables.get("events")


B_VALUE_MIN_EVENTS = 50  # fewer events: no b-value (its error would be ~b/sqrt(n) > 14 %)


def _event_statistics(events) -> dict:
    """Scalars of an event catalog: count, the largest event, the mean recurrence interval
    and, with at least B_VALUE_MIN_EVENTS events of positive moment, the b-value of their
    moment magnitudes (Aki's maximum likelihood above the smallest) with its error."""
    from .stats import b_value, magnitudes

    out = {
        "n_events": 0.0,
        "max_moment": math.nan,
        "mean_interval": math.nan,
        "b_value": math.nan,
        "b_value_err": math.nan,
    }
    if events is None or len(events) == 0:
        return out
    out["n_events"] = float(len(events))
    if "moment" in events:
        m = events["moment"].to_numpy(dtype=float)
        m = m[np.isfinite(m) & (m > 0)]
        if m.size:
            out["max_moment"] = float(m.max())
        if m.size >= B_VALUE_MIN_EVENTS:
            b = b_value(magnitudes(m, "moment"))
            out["b_value"], out["b_value_err"] = b.b, b.sigma_shi_bolt
    if "t_start" in events and len(events) >= 2:
        out["mean_interval"] = float(np.mean(np.diff(np.sort(events["t_start"].to_numpy()))))
    return out


def run_result(cfg: RunConfig, *, snapshots: bool = False, chunk: int = 20_000) -> RunResult:
    """Run ``cfg`` in memory: nothing is written to disk (``cfg.output_path`` is ignored).
    Returns the summary scalars, the tables and, with ``snapshots=True``, the snapshots."""
    mem = _MemoryWriter(snapshots)
    s = run(cfg, None, chunk=chunk, _memory=mem)
    summary = {k: v for k, v in s.to_dict().items() if k not in ("out", "units")}
    summary.pop("counters", None)
    summary.pop("warnings", None)
    summary.update(_event_statistics(mem.tables.get("events")))
    return RunResult(
        summary=summary,
        tables=mem.tables,
        snapshots=mem.dataset() if snapshots else None,
        config=cfg,
    )


def simulate(cfg, out=None, *, snapshots: bool = False, progress: bool = False) -> RunResult:
    """Run a configuration and return its :class:`RunResult` (this is ``bk.run``).

    ``cfg``: a :class:`RunConfig`, a dict of the TOML schema (``RunConfig.to_dict()``) or
    the path of a TOML file. Without ``out`` nothing is written (``[output] path`` is
    ignored); with ``out`` (.nc or .zarr) the outputs are written as ``bkwaves run`` writes
    them and the result is read back from them."""
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
    summary.update(_event_statistics(tables.get("events")))
    return RunResult(
        summary=summary, tables=tables, snapshots=ds if snapshots else None, config=cfg
    )


class _Control:
    """Checkpoint timing, the resume state, and the stop request of a run."""

    def __init__(self, out, cfg, every, stop_after, state, memory=None):
        self.out, self.cfg, self.every = out, cfg, every
        self.memory = memory
        self.stop_after = stop_after
        self.state = state
        self.chunks = 0
        self.last = time.perf_counter()

    @property
    def resuming(self) -> bool:
        return self.state is not None

    def chunk_done(self, stop_request) -> None:
        self.chunks += 1
        if self.stop_after is not None and self.chunks >= self.stop_after:
            stop_request.requested = True

    def due(self) -> bool:
        return self.every is not None and time.perf_counter() - self.last > self.every

    def save(self, engine_obj, written, runner=None):
        if self.out is None:
            return
        _save_checkpoint(self.out, self.cfg, engine_obj, written, runner or {})
        self.last = time.perf_counter()

    def finished(self):
        """The run ended on its own: no checkpoint is needed any more."""
        if self.out is not None:
            checkpoint_path(self.out).unlink(missing_ok=True)


def _open_writer(out, cfg, units, x, variables, ctl):
    """The output writer (None without an output) and the number of snapshots already in
    it (those the checkpoint counts when resuming)."""
    written = ctl.state["written"] if ctl.resuming else 0
    if ctl.memory is not None:  # run_result: everything kept in memory
        ctl.memory.start(units.x(x), variables, _attrs(cfg, units), units.coord_units())
        return written, ctl.memory
    if not out:
        return written, None
    writer = RunWriter(
        out,
        units.x(x),
        variables,
        attrs=_attrs(cfg, units),
        coord_units=units.coord_units(),
        resume_count=written if ctl.resuming else None,
    )
    return written, writer


def _run_chain(cfg, out, progress, table_every, chunk, ctl):
    from .chain import Chain

    p = cfg.params
    if ctl.resuming:
        chain = Chain._from_record(*ctl.state["engine"], ctl.state["path"])
    else:
        u0 = initial_state(cfg)
        u_t0 = (
            None if cfg.initial.velocity == 0.0 else np.full(cfg.blocks, p.v - cfg.initial.velocity)
        )
        chain = Chain(cfg.blocks, p, cfg.boundary, u0, u_t0, seed=cfg.seed)
        for tr in cfg.triggers:
            if tr.kind == "kick":
                chain.kick(tr.block, -tr.velocity, tr.time)
            else:
                chain.release(tr.block, tr.time)
        chain._engine.add_snapshots(_snapshot_times(cfg), int(cfg.snapshot_events or 0))
    eng = chain._engine
    units = _Units(cfg)
    x = np.arange(cfg.blocks) * p.dx
    variables = {
        "u": ("1", "stress u (0: kinetic level, 1: static threshold)", "f8"),
        "u_t": ("(f_r - f_s)/sqrt(k_p m)", "du/dt", "f8"),
        "sliding": ("1", "sliding state: 0 stuck, 1 forward, -1 backward", "i1"),
    }
    written, writer = _open_writer(out, cfg, units, x, variables, ctl)
    t_stop = cfg.t_end if cfg.t_end is not None else 1e300
    max_events = cfg.max_events if cfg.max_events is not None else 2**62
    bar = ProgressBar(progress, cfg.t_end if cfg.t_end else max_events, "chain")
    wall0 = last_tables = time.perf_counter()
    interrupted = False

    def flush_snapshots():
        nonlocal written
        if writer is None:
            return
        ts, us, uts = eng.snapshots()
        for i in range(written, len(ts)):
            # stuck blocks drift with the loader exactly (u_t == v to the bit), so the
            # sign of the speed over the ground v - u_t is the sliding state
            sliding = np.sign(p.v - np.asarray(uts[i])).astype(np.int8)
            writer.append(units.t(ts[i]), u=us[i], u_t=uts[i], sliding=sliding)
        written = len(ts)

    def flush_tables():
        if writer is None:
            return
        import pandas as pd

        cat = pd.DataFrame(eng.catalog())
        cat["duration"] = cat["t_end"] - cat["t_start"]
        cat, cu = units.convert_table(
            cat, times=("t_start", "t_end", "duration"), slips=("moment",)
        )
        writer.write_table("events", cat, cu)
        sl = pd.DataFrame(eng.slips())
        sl.insert(2, "x", sl["block"] * p.dx)
        sl, su = units.convert_table(sl, times=("t_start", "t_end"), xs=("x",), slips=("slip",))
        writer.write_table("slips", sl, su, csv=False)

    try:
        with _StopRequest() as stop_request:
            while True:
                done = eng.events_finished
                stop = eng.advance(t_stop, max(max_events - done, 0), int(chunk))
                flush_snapshots()
                bar.update(chain.t if cfg.t_end else eng.events_finished)
                if time.perf_counter() - last_tables > table_every:
                    flush_tables()
                    last_tables = time.perf_counter()
                if stop != "steps":
                    break
                ctl.chunk_done(stop_request)
                if stop_request.requested:
                    interrupted = True
                    break
                if ctl.due():
                    ctl.save(chain, written)
    finally:
        bar.close()
        flush_snapshots()
        flush_tables()
        if writer is not None:
            writer.close()
    if interrupted:
        ctl.save(chain, written)
    else:
        ctl.finished()
    return RunSummary(
        model="chain",
        out=str(out) if out else None,
        t=float(units.t(chain.t)),
        events=int(eng.events_finished),
        snapshots=written,
        interrupted=interrupted,
        wall_s=time.perf_counter() - wall0,
        units=units.name,
        extra={"blocks": cfg.blocks, "counters": eng.counters()},
    )


def _run_free_boundary(cfg, out, progress, table_every, chunk, ctl):
    import warnings

    from .free_boundary import FreeBoundary

    p = cfg.params
    x = cfg.x()
    notes = []
    if ctl.resuming:
        fb = FreeBoundary._from_record(*ctl.state["engine"], ctl.state["path"])
    else:
        u0 = initial_state(cfg)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fb = FreeBoundary(p, x, u0, cfg.boundary)
        notes = [str(w.message) for w in caught]
        for w in caught:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    eng = fb._engine
    units = _Units(cfg)
    variables = {"u": ("1", "slow field u (0: kinetic level, 1: static threshold)", "f8")}
    written, writer = _open_writer(out, cfg, units, x, variables, ctl)
    t_end = cfg.t_end if cfg.t_end is not None else math.inf
    target_events = cfg.max_events if cfg.max_events is not None else 2**62
    bar = ProgressBar(progress, cfg.t_end if cfg.t_end else target_events, "free boundary")
    wall0 = last_tables = time.perf_counter()
    interrupted = False

    def snap():
        nonlocal written
        if writer is not None:
            writer.append(units.t(eng.time), u=np.asarray(eng.u_nodes()))
            written += 1

    def flush_tables():
        if writer is None:
            return
        import pandas as pd

        ev = pd.DataFrame(eng.events())
        if len(ev):
            ev.insert(3, "duration", ev["t_end"] - ev["t_start"])
        ev, eu = units.convert_table(
            ev,
            times=("t_start", "t_end", "duration"),
            xs=("x_start", "x_min", "x_max", "swept"),
            slips=("moment",),
        )
        writer.write_table("events", ev, eu)
        sh = pd.DataFrame(eng.path())
        sh, su = units.convert_table(sh, times=("t",), xs=("x",))
        writer.write_table("shocks", sh, su, csv=False)

    # The loop state (the next target, the every-k count) goes into checkpoints: the
    # resumed run makes the same engine calls and writes the same snapshots.
    times = _snapshot_times(cfg).tolist()
    if times and times[0] <= 0.0:
        if not ctl.resuming:
            snap()
        times.pop(0)
    wanted = {t for t in times if t <= t_end}
    targets = sorted(wanted | {t_end})
    if ctl.resuming:
        rs = ctl.state["runner"]
        i_target = int(rs["next_target"])
        last_every_k = int(rs["last_every_k"])
    else:
        i_target = 0
        last_every_k = 0

    def runner_state():
        return {"next_target": i_target, "last_every_k": last_every_k}

    saved_written = written
    try:
        with _StopRequest() as stop_request:
            while i_target < len(targets):
                target = targets[i_target]
                status = eng.advance(float(target), int(chunk), int(target_events))
                bar.update(eng.time if cfg.t_end else eng.completed_events)
                k = cfg.snapshot_events
                if k and eng.completed_events // k > last_every_k:
                    last_every_k = eng.completed_events // k
                    snap()
                if status == "time":
                    i_target += 1
                    if target in wanted:
                        snap()
                if time.perf_counter() - last_tables > table_every:
                    flush_tables()
                    last_tables = time.perf_counter()
                if status == "events" or i_target == len(targets):
                    break
                ctl.chunk_done(stop_request)
                if stop_request.requested:
                    interrupted = True
                    break
                if ctl.due():
                    ctl.save(fb, written, runner_state())
        # records written up to here are the ones a resumed run continues after
        saved_written = written
    finally:
        bar.close()
        if writer is not None and (written == 0 or interrupted or cfg.t_end is None):
            snap()
        flush_tables()
        if writer is not None:
            writer.close()
    if interrupted:
        ctl.save(fb, saved_written, runner_state())
    else:
        ctl.finished()
    return RunSummary(
        model="free_boundary",
        out=str(out) if out else None,
        t=float(units.t(eng.time)),
        events=int(eng.completed_events),
        snapshots=written,
        interrupted=interrupted,
        wall_s=time.perf_counter() - wall0,
        units=units.name,
        extra={"grid": len(x), "warnings": notes, "steps": int(eng.steps)},
    )
