"""The chain model (``model = "chain"``): bkwaves.Chain run from a config.

Its entry in the model registry (``bkwaves._models``): [domain] blocks and boundary,
per-block [disorder] (threshold, mass, loader, coupling), triggers, an initial velocity,
the chain's integration keys of [run], noise per block; outputs u, u_t and sliding on
the blocks, the events, slips and ruptures tables.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .._progress import ProgressBar
from ..chain import BOUNDARIES, PROPERTIES
from . import Model


def chain_from_config(cfg):
    """The :class:`bkwaves.Chain` a chain config describes, at t = 0: initial state,
    per-block properties, noise, integration settings (run.step, run.integrator,
    run.step_tolerance) and triggers (no snapshots scheduled).

    Parameters
    ----------
    cfg : bkwaves.config.RunConfig
        A chain config.

    Returns
    -------
    bkwaves.Chain
        The chain, ready to run.

    Examples
    --------
    The chain run by hand ends where the config's run ends:

    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 20.0}})
    >>> out = os.path.join(tempfile.mkdtemp(), "front.nc")
    >>> _ = bk.runner.run(cfg, out)
    >>> chain = bk.runner.chain_from_config(cfg)
    >>> bool((chain.run(t_end=20.0).u == bk.load(out)[0].u.values[-1]).all())
    True
    """
    from ..chain import Chain
    from ..config import disorder_arrays, initial_state

    p = cfg.params
    u_t0 = None if cfg.initial.velocity == 0.0 else np.full(cfg.blocks, p.v - cfg.initial.velocity)
    chain = Chain(
        cfg.blocks,
        p,
        cfg.boundary,
        initial_state(cfg),
        u_t0,
        seed=cfg.seed,
        noise=cfg.noise,
        **cfg.chain_integration(),
        **disorder_arrays(cfg),
    )
    for tr in cfg.triggers:
        if tr.kind == "kick":
            chain.kick(tr.block, -tr.velocity, tr.time)
        else:
            chain.release(tr.block, tr.time)
    return chain


def _check_resumed_integration(cfg, chain, path) -> None:
    """A resumed chain integrates as its config says (the checkpoint's engine record and
    config are written together; a checkpoint whose two disagree was altered)."""
    from .._core import ParameterError

    for key, want in cfg.chain_integration().items():
        have = getattr(chain, key)
        if want is None and key == "events":
            continue  # (not given: the checkpoint's, which its config chose)
        if have != want:
            raise ParameterError(
                f"cannot resume from {path}: its engine runs with {key} = {have!r}, its "
                f"config says run.{key} = {want!r}; a resumed run keeps the settings it "
                "started with"
            )


def _run_chain(model, cfg, out, progress, overwrite, flush_every, chunk, ctl):
    """The run of a model on the chain's engine (the chain, the lattice): ``model``'s
    hooks build or restore the engine and shape the grid and the tables."""
    from ..chain import (
        CHUNK_WALL,
        CHUNK_WORK,
        default_max_event_slips,
        runaway_message,
    )
    from ..runner import (
        RunSummary,
        _complete,
        _described,
        _finish,
        _frame,
        _guard_writes,
        _open_writer,
        _snapshot_times,
        _Units,
    )

    p = cfg.params
    if ctl.resuming:
        chain = model.engine_class()._from_record(*ctl.state["engine"], ctl.state["path"])
        _check_resumed_integration(cfg, chain, ctl.state["path"])
    else:
        chain = model.build(cfg)
        times = _snapshot_times(cfg)
        if cfg.snapshot_events and (times.size == 0 or times[0] > chain.t):
            # every-k-events snapshots start with the initial state, like timed ones
            times = np.concatenate([[chain.t], times])
        chain._engine.add_snapshots(times, int(cfg.snapshot_events or 0))
    eng = chain._engine
    slip_limit = cfg.max_event_slips or default_max_event_slips(model.nodes(cfg))
    duration_limit = cfg.max_event_duration or model.default_max_event_duration(cfg)
    eng.set_run_limits(slip_limit, duration_limit, CHUNK_WORK)
    eng.set_chunk_wall(CHUNK_WALL)
    if ctl.resuming:
        # snapshots a checkpoint of an earlier version still holds were all written
        eng.take_snapshots()
    units = _Units(cfg)
    x, y = model.x(cfg), model.y(cfg)
    rate_units, rate_attrs = units.rate_spec()
    variables = {
        "u": ("1", "stress u (0: kinetic level, 1: static threshold)", "f8"),
        "u_t": (rate_units, "du/dt", "f8", rate_attrs),
        "sliding": ("1", "sliding state: 0 stuck, 1 forward, -1 backward", "i1"),
    }
    # the ruptures and arrivals tables are written once, at the end, from the whole
    # record (an interrupted run wrote them too: a resumed one writes them again whole)
    resume_rows = {
        "events": eng.events_finished,
        "slips": eng.slips_final,
        "ruptures": 0,
        "arrivals": 0,
    }
    writer = _open_writer(
        out,
        cfg,
        units,
        x,
        variables,
        ctl,
        overwrite,
        flush_every,
        resume_rows,
        {**chain.integration_attrs(), **model.grid_attrs(cfg)},
        y=y,
    )
    t_stop = cfg.t_end if cfg.t_end is not None else 1e300
    max_events = cfg.max_events if cfg.max_events is not None else 2**62
    bar = ProgressBar(progress, cfg.t_end if cfg.t_end else max_events, "chain")
    wall0 = time.perf_counter()
    interrupted = False

    def give(final=True):
        """Hand the writer the rows and snapshots it does not have yet (with ``final``:
        only rows that never change again: events that ended and their slips)."""
        if writer is None:
            return
        k = writer.table_rows("events")
        n = eng.events_finished if final else None
        cat = _frame(eng.catalog(k), None if n is None else max(n - k, 0))
        if len(cat) or not final:  # (at the end: the table even when it is empty)
            cat["duration"] = cat["t_end"] - cat["t_start"]
            cat["complete"] = _complete(k, len(cat), eng.events_finished)
            cat = model.event_columns(cfg, cat)
            cat, cu, cs = model.convert_events(units, cat)
            described = {**_described(cat), **model.event_descriptions()}
            writer.append_rows("events", cat, cu, scales=cs, descriptions=described)
        k = writer.table_rows("slips")
        sl = _frame(eng.slips(k, eng.slips_final if final else None))
        if len(sl) or not final:
            sl = model.slip_columns(cfg, sl)
            sl, su, ss = units.convert_table(
                sl, times=("t_start", "t_end"), xs=("x", "y"), slips=("slip",)
            )
            writer.append_rows("slips", sl, su, csv=False, scales=ss)
        # the snapshots last: a commit they trigger writes their catalog rows first
        # (handed over and dropped by the engine: memory stays bounded on long runs)
        ts, us, uts = eng.take_snapshots()
        if len(ts):
            # stuck blocks drift with the loader exactly (u_t == v to the bit), so the
            # sign of the speed over the ground v - u_t is the sliding state
            sliding = np.sign(p.v - np.asarray(uts)).astype(np.int8)
            writer.append_block(units.t(np.asarray(ts)), u=us, u_t=units.rate(uts), sliding=sliding)

    stop = "steps"
    with _guard_writes(bar, writer, cfg, lambda: (eng.events_finished, units.t(chain.t))):
        finished = False
        while not ctl.stop:
            done = eng.events_finished
            stop = eng.advance(t_stop, max(max_events - done, 0), int(chunk))
            give()
            bar.update(chain.t if cfg.t_end else eng.events_finished)
            if stop != "steps":
                finished = True
                break
            ctl.chunk_done()
            if not ctl.stop and ctl.due():
                ctl.save(chain, writer)
        interrupted = not finished
        bar.close()
        rup = model.ruptures(cfg, eng)

        def give_all():
            give(final=False)
            model.write_ruptures(writer, units, rup)
            if cfg.arrivals and writer is not None:
                _write_arrivals(writer, units, model.arrivals_table(cfg, eng))
            if writer is not None and writer.records == 0:
                # no snapshot was asked for: the state at the end, as the free boundary
                # run writes it (an output always holds a state; a resumed run drops it)
                uts = np.asarray(chain.u_t)
                writer.append_block(
                    units.t(np.array([chain.t])),
                    u=np.asarray(chain.u)[None, :],
                    u_t=units.rate(uts)[None, :],
                    sliding=np.sign(p.v - uts).astype(np.int8)[None, :],
                )

        interrupted = _finish(writer, ctl, chain, None, give_all, interrupted)
    extra = {
        "blocks": model.nodes(cfg),
        "ruptures": None if rup is None else len(rup),
        "counters": chain._counters(),
        "signal": ctl.signal_name() if interrupted else None,
        "stop": stop,
    }
    if stop == "long_event":
        # the chain slides on without re-sticking: stopped, what was computed is kept
        extra["message"] = runaway_message(
            chain, slip_limit, duration_limit, ("run.max_event_slips", "run.max_event_duration")
        )
    return RunSummary(
        model=cfg.model,
        out=str(out) if out else None,
        t=float(units.t(chain.t)),
        events=int(eng.events_finished),
        snapshots=writer.count if writer is not None else len(eng.snapshots()[0]),
        interrupted=interrupted,
        wall_s=time.perf_counter() - wall0,
        units=units.name,
        extra=extra,
    )


def _write_arrivals(writer, units, table) -> None:
    """Write the arrivals table (event or rupture, i, j, x, y, t) in the output units."""
    table, tu, ts = units.convert_table(table, times=("t",), xs=("x", "y"))
    writer.append_rows("arrivals", table, tu, csv=False, scales=ts)


def ruptures(cfg, eng):
    """The ruptures table of a chain run (:func:`bkwaves.catalog.run_ruptures`),
    dimensionless, from the engine's whole record of slips."""
    from ..catalog import run_ruptures
    from ..runner import _frame

    p = cfg.params
    sl = _frame(eng.slips())
    if len(sl):
        sl.insert(2, "x", sl["block"] * p.dx)
    return run_ruptures("chain", sl, n=cfg.blocks, dx=p.dx, boundary=cfg.boundary)


#: The largest bound on the midpoint iteration's contraction factor the engine accepts
#: (the core's MIDPOINT_CONTRACTION: its 200 passes then reach round-off).
MIDPOINT_CONTRACTION = 0.8


def check_step(
    cfg, dx: float, coupling: float, shown: str = "1 + 4/dx^2", what: str = "the chain"
) -> None:
    """RK4 stability and the midpoint rule's contraction of the engine's time step h =
    step dx for alike Coulomb blocks (the engine's tests), named by the key to change.
    ``dx``: the smallest spacing (the lattice's min(dx, dy)); ``coupling``: the springs'
    share of the fastest rate squared (``shown``), 4/dx^2 on a chain, 4/dx^2 + 4/dy^2 on
    a lattice; ``what``: the chain or the lattice."""
    from ..config import _err

    p = cfg.params
    # RK4 stability of the chain's time step h = step dx (the engine's test, for
    # alike Coulomb blocks): h (sqrt(1 + 4/dx^2) + 2 gamma) <= 2.5
    step = cfg.chain_integration()["step"]
    h = step * dx
    sound = math.sqrt(1.0 + coupling)
    if not math.isfinite(sound):  # (dx = 1e-310: the coupling 1/dx^2 overflows)
        _err(
            "params.dx" if not cfg.physical else "physical.k_c",
            f"dx = {dx:.6g}: the coupling 1/dx^2 overflows; allowed dx >= 1e-150",
        )
    rate = sound + 2.0 * p.gamma
    if h * rate > 2.5:
        g_max = 0.5 * (2.5 / h - sound)
        gamma_key = "params.gamma" if not cfg.physical else "physical.alpha"
        if cfg.step is not None:
            # the step the user chose is the one to lower
            also = f" (or lower {gamma_key} to gamma <= {g_max:.6g})" if g_max > 0 else ""
            _err(
                "run.step",
                f"step = {step:.6g} is too large for RK4 stability with gamma = "
                f"{p.gamma:.6g} and dx = {dx:.6g} (step dx (sqrt({shown}) + 2 gamma) "
                f"<= 2.5): allowed 0 < step <= {2.5 / (dx * rate):.6g}{also}",
            )
        if g_max > 0:
            _err(
                gamma_key,
                f"gamma = {p.gamma:.6g} is too strong a damping for {what}'s time step "
                f"(RK4 stability at step = {step} dx): allowed gamma <= {g_max:.6g} "
                "(or a smaller run.step)",
            )
        key = "params.dx" if not cfg.physical else "physical.k_c"
        _err(key, f"dx = {dx:.6g} is too large for {what}'s time step")
    # the midpoint rule's fixed-point solve must contract (the engine's test, for alike
    # Coulomb blocks): (h/2)^2 (1 + 4/dx^2) + h gamma <= 0.8
    if cfg.chain_integration()["integrator"] == "midpoint":
        q = 0.25 * h * h * sound * sound + h * p.gamma
        if q > MIDPOINT_CONTRACTION:
            key = "run.step" if cfg.step is not None else "run.integrator"
            _err(
                key,
                f"the midpoint integrator's fixed-point solve does not contract at step = "
                f"{step:.6g}, gamma = {p.gamma:.6g}, dx = {dx:.6g}: (h/2)^2 ({shown}) "
                f"+ h gamma = {q:.3g} > {MIDPOINT_CONTRACTION} (h = step dx); a smaller "
                "run.step, or run.integrator = 'rk4'",
            )


class ChainModel(Model):
    name = "chain"
    boundaries = BOUNDARIES
    domain_keys = ("blocks", "boundary")
    domain_required = ("blocks",)
    size_key = "domain.blocks"
    disorder_keys = PROPERTIES
    discrete = True
    triggers = True
    initial_velocity = True
    chain_run_keys = True
    noise_kind = "chain"
    bytes_per_node_key = "chain_bytes_per_block"
    snapshot_bytes_per_node = 17  # u, u_t (f8), sliding (i1)
    summary = "a chain of blocks (bkwaves.Chain)"

    def parse_domain(self, d, cfg_value):
        return {"blocks": cfg_value(d, "blocks")}

    def domain_doc(self, cfg):
        return {"blocks": cfg.blocks, "boundary": cfg.boundary}

    def property_arrays(self, cfg):
        from ..config import disorder_arrays

        return disorder_arrays(cfg)

    def check(self, cfg):
        dx = cfg.params.dx
        check_step(cfg, dx, 4.0 / dx / dx)

    def x(self, cfg):
        return np.arange(cfg.blocks) * cfg.params.dx

    def nodes(self, cfg):
        return cfg.blocks

    def physical_span(self, cfg):
        return (cfg.blocks - 1) * cfg.params.dx

    def span(self, cfg):
        return cfg.blocks * cfg.params.dx

    def run(self, cfg, out, progress, overwrite, flush_every, chunk, ctl):
        return _run_chain(self, cfg, out, progress, overwrite, flush_every, chunk, ctl)

    # --- the run's hooks (the lattice overrides them) -----------------------------------
    def engine_class(self):
        from ..chain import Chain

        return Chain

    def build(self, cfg):
        """The engine at t = 0 (``chain_from_config``)."""
        return chain_from_config(cfg)

    def y(self, cfg):
        """Positions across (None: a line)."""
        return None

    def grid_attrs(self, cfg) -> dict:
        """Global attributes of the output describing the grid."""
        return {}

    def default_max_event_duration(self, cfg) -> float:
        from ..chain import default_max_event_duration

        return default_max_event_duration(cfg.blocks, cfg.params.dx)

    def event_columns(self, cfg, cat):
        """The engine's catalog as the output's events table (dimensionless)."""
        cat["moment"] = cat["moment"] * cfg.params.dx  # int slip dx (the core sums slips)
        return cat

    def convert_events(self, units, cat):
        return units.convert_table(cat, times=("t_start", "t_end", "duration"), moments=("moment",))

    def event_descriptions(self) -> dict:
        """Definitions of the events table's columns besides the shared ones
        (``bkwaves.catalog.DESCRIPTIONS``)."""
        return {}

    def slip_columns(self, cfg, sl):
        """The engine's slips as the output's slips table (dimensionless)."""
        sl.insert(2, "x", sl["block"] * cfg.params.dx)
        return sl

    def ruptures(self, cfg, eng):
        """The ruptures table (None: the model has none)."""
        return ruptures(cfg, eng)

    def write_ruptures(self, writer, units, rup) -> None:
        """Write the ruptures table (dimensionless) in the output units."""
        from ..runner import _write_ruptures

        _write_ruptures(writer, units, rup)

    def work(self, cfg):
        from .. import _cost
        from ..limits import _chain_run, chain_wall

        work = _cost.chain_work(_chain_run(cfg, cfg.t_end, cfg.max_events))
        return work, work.block_steps, chain_wall


MODEL = ChainModel()
