"""What a run will need, estimated before it starts: snapshots and output size, memory,
work and wall time. Runs that cannot be done are refused with a
:class:`bkwaves.ParameterError` naming the config key and the estimate; runs that will
take very long get a :class:`LongRunWarning`. The limits are documented in
docs/usage.md ("Limits") and can be changed in :data:`LIMITS`.

The work estimates are order-of-magnitude figures, not promises:

- chain: integration block-steps ~ blocks x (t_end / h) x f with the time step
  h = step dx and f the fraction of blocks sliding: in a steady stick-slip cycle every
  block slides off what the loader adds, so f ~ v / s with s ~ 0.1 the typical slip
  speed (measured on examples/chain_loading.toml); f = 1 when v = 0 (nothing sets the
  time scale; a creeping or sliding chain slides all the time).
- free boundary: shock-node crossings ~ 10 v t_end x grid (each node is reset about once
  per reload of u by A ~ 0.1), plus ~ v t_end events of a few ms each (measured: 0.7
  events per unit of v t_end on a parabola of 81 nodes and on a ring of 2000).
Rates (per second of wall time, one core of the development machine): ``LIMITS``.
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass, field

from ._core import ParameterError

__all__ = ["LIMITS", "Estimate", "LongRunWarning", "estimate", "check_sizes", "memory_bytes"]

#: Documented limits and calibration constants (change them to override).
LIMITS = {
    # refuse a run whose estimated wall time exceeds this (s): one year
    "max_wall_s": 3.2e7,
    # warn when the estimated wall time exceeds this (s)
    "warn_wall_s": 3600.0,
    # refuse an output larger than this (bytes), whatever the free space
    "max_output_bytes": 2**40,
    # warn when the output is larger than this (bytes)
    "warn_output_bytes": 10 * 2**30,
    # engine memory per chain block and per free-boundary grid node (bytes, measured)
    "chain_bytes_per_block": 400,
    "fb_bytes_per_node": 200,
    # throughput: chain block-steps per second, free boundary shock-node crossings per s
    "chain_block_steps_per_s": 4e6,
    "fb_crossings_per_s": 1e6,
    # free boundary: cost of one event beyond its crossings (s; ~4 ms measured)
    "fb_seconds_per_event": 4e-3,
    # the typical slip speed in the chain's work estimate (units of u per t')
    "chain_slip_speed": 0.1,
    # refuse a single uninterruptible engine call (bkwaves front) estimated longer (s)
    "max_call_s": 3600.0,
    # refuse a tip solve (bkwaves.tip_solve) whose banded system exceeds this (bytes)
    "max_solver_bytes": 2 * 2**30,
}


class LongRunWarning(UserWarning):
    """A run is estimated to take very long or to write a very large output."""


@dataclass
class Estimate:
    """What a run needs: snapshots (None: not known in advance), output and memory bytes,
    work (chain block-steps or free-boundary crossings; None: not known) and wall time."""

    snapshots: int | None
    output_bytes: float
    memory_bytes: float
    work: float | None
    wall_s: float | None
    notes: list[str] = field(default_factory=list)


def physical_memory() -> float:
    """Bytes of RAM of this machine (inf when unknown)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return math.inf


def memory_bytes(model: str, nodes: int) -> float:
    """Engine memory for a chain of ``nodes`` blocks or a free-boundary grid of ``nodes``."""
    per = LIMITS["chain_bytes_per_block" if model == "chain" else "fb_bytes_per_node"]
    return float(per) * nodes


def check_memory(name: str, model: str, nodes: int) -> None:
    """Refuse a chain or grid whose engine state cannot fit in this machine's RAM."""
    need = memory_bytes(model, nodes)
    have = physical_memory()
    if need > have:
        raise ParameterError(
            f"{name} = {nodes}: the engine state needs about {_bytes(need)}, more than the "
            f"{_bytes(have)} of RAM of this machine"
        )


def _snapshot_count(cfg) -> int | None:
    if cfg.snapshot_every is not None:
        if cfg.t_end is None:
            return 10**6  # open-ended by events: the runner schedules 10**6 times ahead
        return int(math.floor(cfg.t_end / cfg.snapshot_every)) + 1
    if cfg.snapshot_events is not None and cfg.max_events is not None:
        return cfg.max_events // cfg.snapshot_events + 1
    return None if cfg.snapshot_events is not None else 2


def estimate(cfg) -> Estimate:
    """Estimate what the run described by ``cfg`` (a RunConfig) needs."""
    p = cfg.params
    chain = cfg.model == "chain"
    nodes = cfg.blocks if chain else cfg.grid
    snaps = _snapshot_count(cfg)
    per_snapshot = nodes * (17 if chain else 8)  # chain: u, u_t (f8), sliding (i1)
    out = float(snaps or 0) * per_snapshot
    mem = memory_bytes(cfg.model, nodes)
    work = wall = None
    notes = []
    if cfg.t_end is not None:
        if chain:
            from .chain import DEFAULT_STEP

            work, wall = chain_work(nodes, cfg.t_end, DEFAULT_STEP, p.dx, p.v)
            notes.append(f"~{work:.2g} block-steps")
        else:
            work, wall = fb_work(nodes, cfg.t_end, p.v)
            notes.append(f"~{work:.2g} shock-node crossings")
    return Estimate(snaps, out, mem, work, wall, notes)


def chain_work(n: int, t_span: float, step: float, dx: float, v: float) -> tuple[float, float]:
    """Estimated block-steps and wall seconds of a chain run over ``t_span``."""
    frac = 1.0 if v == 0 else min(1.0, v / LIMITS["chain_slip_speed"])
    work = n * (t_span / (step * dx)) * frac
    return work, work / LIMITS["chain_block_steps_per_s"]


def fb_work(grid: int, t_span: float, v: float) -> tuple[float, float]:
    """Estimated shock-node crossings and wall seconds of a free-boundary run."""
    work = 10.0 * v * t_span * grid
    events = v * t_span  # about one event per unit of loading (measured: 0.7)
    return work, work / LIMITS["fb_crossings_per_s"] + events * LIMITS["fb_seconds_per_event"]


def check_wall(what: str, wall: float, work_text: str) -> None:
    """Refuse beyond ``max_wall_s``, warn beyond ``warn_wall_s``; ``what`` names the key."""
    if wall > LIMITS["max_wall_s"]:
        raise ParameterError(
            f"{what} cannot be done: estimated {work_text}, about {_duration(wall)} of "
            f"computation (limit {_duration(LIMITS['max_wall_s'])}, "
            "bkwaves.limits.LIMITS['max_wall_s'])"
        )
    if wall > LIMITS["warn_wall_s"]:
        warnings.warn(
            f"{what}: estimated {work_text}, about {_duration(wall)} of computation",
            LongRunWarning,
            stacklevel=4,
        )


def _bytes(n: float) -> str:
    for unit, size in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n:.0f} B"


def _duration(s: float) -> str:
    for unit, size in (("years", 3.156e7), ("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if s >= size:
            return f"{s / size:.3g} {unit}"
    return f"{s:.3g} s"


def _t_end_text(cfg) -> str:
    units = cfg.params.units
    if units is None:
        return f"run.t_end = {cfg.t_end:.6g}"
    return (
        f"run.t_end = {units.time(cfg.t_end):.6g} s (= {cfg.t_end:.3g} time units "
        f"sqrt(m/k_p) = {units.time_scale:.3g} s)"
    )


def check_sizes(cfg) -> Estimate:
    """Refuse a config that cannot be done (memory, output size, wall time beyond
    ``LIMITS``) with the key and the estimate in the message; warn
    (:class:`LongRunWarning`) about one that will take very long. Returns the estimate."""
    chain = cfg.model == "chain"
    check_memory("domain.blocks" if chain else "domain.grid", cfg.model, cfg.blocks or cfg.grid)
    if cfg.model == "free_boundary" and cfg.params.v == 0 and cfg.t_end is None:
        raise ParameterError(
            "run.max_events: with v = 0 nothing loads the field, so no event can start and "
            "the run would end at once with none; give run.t_end"
        )
    est = estimate(cfg)
    if cfg.snapshot_every is not None:
        snap_key = "output.snapshot_every"
        if cfg.t_end is not None:
            snap_key += " with run.t_end"
    else:
        snap_key = "output.snapshot_events with run.max_events"
    if est.output_bytes > LIMITS["max_output_bytes"]:
        raise ParameterError(
            f"{snap_key}: {est.snapshots:.3g} snapshots of {cfg.blocks or cfg.grid} nodes make "
            f"about {_bytes(est.output_bytes)} of output, more than the limit "
            f"{_bytes(LIMITS['max_output_bytes'])} (bkwaves.limits.LIMITS['max_output_bytes'])"
        )
    if est.memory_bytes > physical_memory():
        raise ParameterError(
            f"{snap_key}: {est.snapshots:.3g} snapshots of {cfg.blocks} blocks need about "
            f"{_bytes(est.memory_bytes)} of memory during the run, more than the "
            f"{_bytes(physical_memory())} of RAM of this machine"
        )
    if est.wall_s is not None:
        check_wall(_t_end_text(cfg), est.wall_s, est.notes[0])
    if est.output_bytes > LIMITS["warn_output_bytes"]:
        warnings.warn(
            f"{snap_key}: about {_bytes(est.output_bytes)} of output", LongRunWarning, stacklevel=3
        )
    return est


def check_free_space(out, output_bytes: float) -> None:
    """Warn when the output will not fit in the free space of its file system (a full
    disk during the run keeps what was written and says so; the space may be freed)."""
    from pathlib import Path

    parent = Path(out).resolve().parent
    try:
        st = os.statvfs(parent)
    except OSError:
        return
    free = st.f_bavail * st.f_frsize
    if output_bytes > free:
        warnings.warn(
            f"output: about {_bytes(output_bytes)} of snapshots, {_bytes(free)} free at "
            f"{parent} (reduce output.snapshot_every/snapshot_events or the domain)",
            LongRunWarning,
            stacklevel=4,
        )
