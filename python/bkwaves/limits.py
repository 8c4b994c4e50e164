"""What a run will need, estimated before it starts: snapshots and output size, memory,
work and wall time. Runs that cannot be done are refused with a
:class:`bkwaves.ParameterError` naming the config key and the estimate; runs that will
take very long get a :class:`LongRunWarning`. The limits are documented in
docs/usage.md ("Limits") and can be changed in :data:`LIMITS`.

The work estimates are order-of-magnitude figures, not promises:

- chain: integration block-steps ~ blocks x (t_end / h) x f with the time step
  h = step dx (``run.step``, default 0.05; with ``run.step_tolerance`` the step only grows
  above it, so the estimate at that floor is an upper bound) and f the fraction of
  blocks sliding: in a steady stick-slip cycle every
  block slides off what the loader adds, so f ~ v / s with s ~ 0.1 the typical slip
  speed (measured on examples/chain_loading.toml); f = 1 when v = 0 (nothing sets the
  time scale; a creeping or sliding chain slides all the time).
- free boundary: shock-node crossings ~ 10 v t_end x grid (each node is reset about once
  per reload of u by A ~ 0.1), plus ~ v t_end events of a few ms each (measured: 0.7
  events per unit of v t_end on a parabola of 81 nodes and on a ring of 2000).
- noise (a ``[noise]`` table; docs/noise.md, "The thinning envelope"): both engines draw
  candidates under the envelope G, the running maximum of g (g(1) = 1, so G(1) >= 1:
  more for a table peaking below the threshold). The chain's candidates fall at the
  rate n rate G(1) while any block slides and at n rate G(X(t)) in quiet stretches
  (X <= 1 the largest stress from the threshold, rising at v); the free boundary's at
  L rate G(U(t)) (L the domain length, U <= 1 the largest stuck u). So
  N rate G(1) t_end (N = n or L) is a bound (up to a quiet bound passing 1 by a hair);
  the estimate is

      candidates ~ N rate t_end [b G(1) + (1 - b) <G>],   <G> = int_0^1 G(u) du,

  <G> the mean of G over a loading from 0 to the threshold and b the fraction of the
  time at the bound G(1): for the chain the time with any block sliding, b = min(1, n f)
  (f the sliding fraction above; n f is its bound, each block sliding alone), for the
  free boundary b = f. For an activated law (exponential, phi0 = 0.01) <G> = phi0 is
  small and b G(1) dominates; for a table peaking below 1, <G> ~ G(1). Measured against
  the engines' counters: 1.1 and 1.0 on the chain example (exponential, and a table
  peaking at 100), 1.4 and 3.6 on the free boundary example; a ring where ruptures
  sweep everything and noise starts each before the threshold (docs/noise.md, long runs)
  is overestimated up to 80 times (chain) and 400 times (free boundary): the estimate
  is on the high side. Wall time: chain, candidates x ``chain_seconds_per_candidate``
  plus one more step over the sliding blocks per candidate while they slide (the
  candidate cuts it short): N rate G(1) f n t_end block-steps x
  ``chain_seconds_per_split_block_step``; free boundary, candidates x
  ``fb_seconds_per_candidate``. Accepted candidates (slips, pairs) cost what the
  engines' own work costs; their sliding is not estimated from the noise (a law that
  keeps every block sliding costs more than the estimate says).

Rates (per second of wall time, one core of the development machine): ``LIMITS``.
A run beyond ``max_wall_s`` is refused, beyond ``warn_wall_s`` warned, naming
``run.t_end`` or, when the noise costs more than the rest, ``noise.rate`` (``noise.g``
for a table whose peak below u = 1 exceeds g(1)).
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass, field

import numpy as np

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
    # noise: seconds per candidate, measured on this machine as (CPU time with noise -
    # without) / the engine's noise_counters candidates, under a table law g = 1e5 (or
    # 1e6) at u <= -5, 0 at -4, rising to 1 at 1 (almost every candidate rejected, the
    # dynamics the noiseless one): chain 7e-8 in quiet stretches (v = 0, 100 and 1000
    # blocks: one jump each); free boundary 1.2e-7 to 1.5e-7 (quiet, during an event, while
    # loading; grids of 100 to 20000 nodes; examples/free_boundary_noise.toml to t = 1000:
    # 1.5e-7)
    "chain_seconds_per_candidate": 7e-8,
    "fb_seconds_per_candidate": 1.5e-7,
    # chain: a candidate while blocks slide ends a step early, one more step over the
    # sliding blocks (examples/chain_noise.toml to t = 1000 under the same law: 7.1e6
    # more block-steps for 1.2e6 candidates, 0.21 s more, i.e. 3e-8 s per block-step as
    # the run's own steps; a ring where all 100 or 1000 blocks creep: 3e-9)
    "chain_seconds_per_split_block_step": 3e-8,
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
    work (chain block-steps or free-boundary crossings; None: not known) and wall time
    (None: not known), which includes the noise's candidates (their number and their
    share of the wall time: ``noise_candidates``, ``noise_wall_s``)."""

    snapshots: int | None
    output_bytes: float
    memory_bytes: float
    work: float | None
    wall_s: float | None
    notes: list[str] = field(default_factory=list)
    noise_candidates: float = 0.0
    noise_wall_s: float = 0.0


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
    candidates = noise_wall = 0.0
    if cfg.t_end is not None:
        if chain:
            steps = cfg.chain_integration()
            work, wall = chain_work(nodes, cfg.t_end, steps["step"], p.dx, p.v)
            if steps["step_tolerance"] is None:
                notes.append(f"~{work:.2g} block-steps")
            else:  # the controlled step only grows above run.step dx: a bound
                notes.append(f"at most ~{work:.2g} block-steps (run.step_tolerance)")
        else:
            work, wall = fb_work(nodes, cfg.t_end, p.v)
            notes.append(f"~{work:.2g} shock-node crossings")
        size = nodes if chain else cfg.length
        candidates, noise_wall = noise_work(cfg.model, size, nodes, cfg.t_end, p.v, cfg.noise)
        wall += noise_wall
        if candidates > 0:
            notes.append(f"~{candidates:.2g} noise candidates")
    return Estimate(snaps, out, mem, work, wall, notes, candidates, noise_wall)


def sliding_fraction(v: float) -> float:
    """The fraction of a chain's blocks sliding, min(1, v / s) (s: ``chain_slip_speed``);
    1 at v = 0 (nothing sets the time scale)."""
    return 1.0 if v == 0 else min(1.0, v / LIMITS["chain_slip_speed"])


def chain_work(n: int, t_span: float, step: float, dx: float, v: float) -> tuple[float, float]:
    """Estimated block-steps and wall seconds of a chain run over ``t_span``."""
    frac = sliding_fraction(v)
    work = n * (t_span / (step * dx)) * frac
    return work, work / LIMITS["chain_block_steps_per_s"]


def _table_envelope(noise: dict) -> tuple[np.ndarray, np.ndarray]:
    """A table law's running maximum G(u) = max_{y <= u} g(y), normalised to g(1) = 1, as
    nodes of a piecewise-linear function (constant outside them), like the core's."""
    u = np.asarray(noise["u"], dtype=float)
    g = np.asarray(noise["g"], dtype=float)
    g = g / np.interp(1.0, u, g)
    nu, ng, m = [u[0]], [g[0]], g[0]
    for k in range(len(u) - 1):
        a, b = g[k], g[k + 1]
        if b > m > a:  # the rising piece crosses the plateau m
            x = u[k] + (m - a) / (b - a) * (u[k + 1] - u[k])
            if nu[-1] < x < u[k + 1]:
                nu.append(x)
                ng.append(m)
        m = max(m, b)
        nu.append(u[k + 1])
        ng.append(m)
    return np.array(nu), np.array(ng)


def noise_envelope(noise: dict) -> tuple[float, float]:
    """(G(1), mean of G over 0 <= u <= 1) of a ``[noise]`` table's law, G(u) = max_{y <= u}
    g(y) its running maximum (the engines' thinning envelope, g(1) = 1; G = g for the
    closed-form laws). G(1) >= 1 bounds the candidates' rate where a stress is only known
    to be below the threshold; the mean is that of a bound loading from 0 to 1."""
    law = noise["law"]
    if law == "constant":
        return 1.0, 1.0
    if law == "exponential":
        phi0 = noise["phi0"]
        return 1.0, phi0 * -math.expm1(-1.0 / phi0)
    if law == "power":
        return 1.0, 1.0 / (noise["exponent"] + 1.0)
    nu, ng = _table_envelope(noise)
    at_one = float(np.interp(1.0, nu, ng))
    inside = (nu > 0.0) & (nu < 1.0)
    x = np.concatenate([[0.0], nu[inside], [1.0]])
    y = np.interp(x, nu, ng)
    return at_one, float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def noise_work(
    model: str, size: float, n: int, t_span: float, v: float, noise: dict | None
) -> tuple[float, float]:
    """Estimated noise candidates and their wall seconds over ``t_span`` (module docs):
    ``size`` is the number of blocks (chain) or the domain length (free boundary), ``n``
    the chain's blocks (unused for the free boundary). (0, 0) without noise."""
    if noise is None or noise["rate"] == 0.0:
        return 0.0, 0.0
    g_top, g_mean = noise_envelope(noise)
    frac = sliding_fraction(v)
    # the fraction of the time the bound is rate G(1): the chain's time with any block
    # sliding is at most n frac (each block sliding alone); the free boundary's U(t)
    # near the threshold: frac
    busy = min(1.0, n * frac) if model == "chain" else frac
    per_g = size * noise["rate"] * t_span  # candidates per unit of the envelope G
    candidates = per_g * (busy * g_top + (1.0 - busy) * g_mean)
    wall = candidates * LIMITS[f"{'chain' if model == 'chain' else 'fb'}_seconds_per_candidate"]
    if model == "chain":
        # a candidate while blocks slide cuts a step short: one more step over the blocks
        # sliding then, whose block-time is frac n t_span (chain_work)
        wall += per_g * g_top * frac * n * LIMITS["chain_seconds_per_split_block_step"]
    return candidates, wall


def noise_key(noise: dict | None, model: str = "chain", units=None) -> str | None:
    """The ``[noise]`` key that sets the candidates' rate, with its value: ``noise.g`` for
    a table that peaks above g(1) below the threshold, else ``noise.rate`` (in 1/s, or
    1/(m s) for the free boundary, with ``units``: the config's physical units). None
    without noise."""
    if noise is None:
        return None
    g_top, _ = noise_envelope(noise)
    rate = f"noise.rate = {noise['rate']:.6g}"
    if units is not None:
        per = "block" if model == "chain" else "unit length"
        scale = units.time_scale * (1.0 if model == "chain" else units.length_scale)
        si = "1/s" if model == "chain" else "1/(m s)"
        rate = (
            f"noise.rate = {noise['rate'] / scale:.6g} {si} (= {noise['rate']:.3g} per {per} "
            "and time unit)"
        )
    if noise["law"] == "table" and g_top > 1.0:
        return f"noise.g (its peak below u = 1 is G(1) = {g_top:.3g} times g(1); {rate})"
    return rate


def fb_work(grid: int, t_span: float, v: float) -> tuple[float, float]:
    """Estimated shock-node crossings and wall seconds of a free-boundary run."""
    work = 10.0 * v * t_span * grid
    events = v * t_span  # about one event per unit of loading (measured: 0.7)
    return work, work / LIMITS["fb_crossings_per_s"] + events * LIMITS["fb_seconds_per_event"]


def check_wall(
    what: str, wall: float, work_text: str, noise_what: str | None = None, noise_cost=(0.0, 0.0)
) -> None:
    """Refuse beyond ``max_wall_s``, warn beyond ``warn_wall_s``; ``what`` names the key.
    ``noise_cost``: the noise's (candidates, wall seconds) of :func:`noise_work`, added;
    when they cost more than the rest the message names ``noise_what`` (the noise's key,
    :func:`noise_key`) first."""
    candidates, noise_wall = noise_cost
    if noise_what is not None and candidates > 0:
        work_text = f"~{candidates:.2g} noise candidates and {work_text}"
        if noise_wall > wall:
            what = f"{noise_what} with {what}"
        wall += noise_wall
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
        check_wall(
            _t_end_text(cfg),
            est.wall_s - est.noise_wall_s,
            est.notes[0],
            noise_key(cfg.noise, cfg.model, cfg.params.units),
            (est.noise_candidates, est.noise_wall_s),
        )
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
