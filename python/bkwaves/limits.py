"""What a run will need, estimated before it starts: snapshots and output size, memory,
work and wall time. Runs that cannot fit (an engine state beyond the machine's RAM, an
output beyond ``max_output_bytes``) are refused with a :class:`bkwaves.ParameterError`
naming the config key and the figure; a run is never refused on its estimated time
alone: one estimated to take long (``warn_wall_s``), to hold much memory or to write a
large output gets one :class:`LongRunWarning` line. The limits are documented in
docs/usage.md ("Limits") and can be changed in :data:`LIMITS`.

The work is what the engines really do (``bkwaves._cost``: the chain steps only its
sliding blocks, a front's pulse of width w, and jumps over quiet stretches; the friction
law's own time scale shortens the step; a max_events-only run gets a time horizon), times
the per-unit costs of :data:`LIMITS`, measured as CPU seconds on one core of the
development machine (benchmarks/bench_estimate.py; docs/benchmarks.md, "Run-cost
estimate"). The estimate is an order of magnitude: within 10x of the measured cost on
every example and on the cases of tests/test_estimate.py.

Memory and output size: the engine (``chain_bytes_per_block``, ``fb_bytes_per_node``) and
the snapshots. A run with an output streams them to disk: it holds at most
``stream_snapshot_copies`` snapshots at once however many it writes (:func:`snapshot_memory`;
a 1e7-block front with 61 snapshots peaked at 2.1 GB, docs/reliability.md); ``Chain.run``
and ``bk.run(cfg, snapshots=True)`` without an output hold them all. The output size is
every snapshot's values uncompressed (u, u_t and sliding: 17 bytes a block; the free
boundary's u: 8 a node): a NetCDF file's size, an upper bound for a Zarr store, which
compresses.

Noise (a ``[noise]`` table; docs/noise.md, "The thinning envelope"): both engines draw
candidates under the envelope G, the running maximum of g (g(1) = 1, so G(1) >= 1:
more for a table peaking below the threshold). The chain's candidates fall at the
rate n rate G(1) while any block slides and at n rate G(X(t)) in quiet stretches
(X <= 1 the largest stress from the threshold, rising at v); the free boundary's at
L rate G(U(t)) (L the domain length, U <= 1 the largest stuck u). So
N rate G(1) t_end (N = n or L) is a bound (up to a quiet bound passing 1 by a hair);
the estimate is

    candidates ~ N rate t_end [b G(1) + (1 - b) <G>],   <G> = int_0^1 G(u) du,

<G> the mean of G over a loading from 0 to the threshold and b the fraction of the
time at the bound G(1): for the chain the time with any block sliding, b = min(1, n f +
n rate <G> pi) (f the fraction of the block-time spent sliding, from the work estimate;
the second term the blocks the noise sets sliding, for about pi each), for the free
boundary b = f. For an activated law (exponential, phi0 = 0.01) <G> = phi0 is small and
b G(1) dominates; for a table peaking below 1, <G> ~ G(1). Measured against the
engines' counters: 1.1 and 1.0 on the chain example (exponential, and a table peaking
at 100), 1.4 and 3.6 on the free boundary example; a ring where ruptures sweep
everything and noise starts each before the threshold (docs/noise.md, long runs) is
overestimated up to 80 times (chain) and 400 times (free boundary): the estimate is on
the high side. Wall time: chain, candidates x ``chain_seconds_per_candidate`` plus one
more step over the sliding blocks per candidate while they slide (the candidate cuts it
short): N rate G(1) f n t_end block-steps x ``chain_seconds_per_split_block_step``; free
boundary, candidates x ``fb_seconds_per_candidate``. Accepted candidates (slips, pairs)
cost what the engines' own work costs. When the noise costs more than the rest the
warning names ``noise.rate`` (``noise.g`` for a table whose peak below u = 1 exceeds
g(1)), else ``run.t_end`` (or ``run.max_events``).
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass, field

import numpy as np

from . import _models
from ._core import ParameterError

__all__ = [
    "LIMITS",
    "Estimate",
    "LongRunWarning",
    "estimate",
    "check_sizes",
    "memory_bytes",
    "snapshot_memory",
]

#: Documented limits and calibration constants (change them to override). Costs are CPU
#: seconds on one core of the development machine (benchmarks/bench_estimate.py).
LIMITS = {
    # warn when the estimated wall time exceeds this (s); a run is never refused on it
    "warn_wall_s": 3600.0,
    # refuse an output larger than this (bytes), whatever the free space
    "max_output_bytes": 2**40,
    # warn when the output is larger than this (bytes)
    "warn_output_bytes": 10 * 2**30,
    # warn when the run's memory exceeds this fraction of the machine's RAM
    "warn_memory_fraction": 0.5,
    # engine memory per chain block and per free-boundary grid node (bytes, measured)
    "chain_bytes_per_block": 400,
    "fb_bytes_per_node": 200,
    # a slip record held by the chain (engine catalog and its table) (bytes)
    "chain_bytes_per_slip": 128,
    # chain: one sliding block over one step (RK4, event tests); one step (its fixed
    # work: runs of sliding blocks, event location); one slip or stick (location,
    # record, table row). Fitted on fronts of 2e4 to 1e5 blocks at dx = 0.05 and 0.5
    "chain_seconds_per_block_step": 3.7e-9,
    "chain_seconds_per_step": 1.7e-7,
    "chain_seconds_per_slip": 5e-7,
    # chain: one block of a velocity-weakening onset's patch over one of its sub-steps
    # (scalar RK4 with neighbour look-ups, the rest test, the dense output): 13x a chain
    # block-step on the benchmark front (docs/benchmarks.md, "Onset": 0.12 s of CPU for
    # 1.06e6 patch block-steps, the chain's 8 ns per block-step in the same run)
    "chain_seconds_per_onset_block_step": 5e-8,
    # the lattice: one sliding block over one step (four neighbours, sliding blocks in
    # short runs of a row): examples/lattice_rupture.toml, 3.4e7 block-steps in 1.35 s
    # of CPU (bkwaves._models.lattice's estimate)
    "lattice_seconds_per_block_step": 4e-8,
    # free boundary: shock-node crossings per second, and one event beyond its crossings
    "fb_crossings_per_s": 1e6,
    "fb_seconds_per_event": 4e-3,
    # snapshots streamed to an output (bkwaves run, bk.run(cfg, OUT)) are handed to the
    # writer chunk by chunk and committed in blocks: the run holds at most this many
    # snapshots at once, however many it writes (peak RSS above a one-snapshot run:
    # 7.3 snapshots at 1e7 blocks to Zarr, 8.8 at 3e6 to NetCDF; docs/reliability.md)
    "stream_snapshot_copies": 10,
    # a snapshot in memory: its fixed cost and one node's values (chain: u and u_t)
    "seconds_per_snapshot": 2e-5,
    "seconds_per_snapshot_node": 2e-8,
    # ... and written to an output: per snapshot (chain, free boundary) and per node
    # (measured on chains of 300 and 3000 blocks with 6 to 5001 snapshots, and on a
    # free-boundary grid of 500 and 5000 nodes with 326 and 3246 snapshots)
    "chain_output_seconds_per_snapshot": 4e-5,
    "fb_output_seconds_per_snapshot": 7e-4,
    "output_seconds_per_snapshot_node": 1.1e-7,
    # fixed cost of a run (results, tables) and of writing an output file
    "seconds_per_run": 0.02,
    "seconds_per_output": 0.1,
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
    # refuse a tip solve (bkwaves.tip_solve) whose banded system exceeds this (bytes)
    "max_solver_bytes": 2 * 2**30,
}


class LongRunWarning(UserWarning):
    """A run is estimated to take long, to hold much memory or to write a large output."""


@dataclass
class Estimate:
    """What a run needs: snapshots (None: not known in advance), output and memory bytes,
    work (chain block-steps or free-boundary crossings; None: not known) and wall time
    (None: not known), which includes the noise's candidates (their number and their
    share of the wall time: ``noise_candidates``, ``noise_wall_s``). ``horizon``: the
    run's time span (estimated for a run bounded only by max_events); ``detail``: the
    engine work behind it (``bkwaves._cost.Work``).

    Parameters
    ----------
    snapshots : int or None
        Snapshots the run will write.
    output_bytes : float
        Bytes of the output's snapshots.
    memory_bytes : float
        Bytes of memory: the engine and the snapshots.
    work : float or None
        Chain block-steps or free-boundary crossings.
    wall_s : float or None
        Estimated wall time [s] (CPU seconds on one core).
    notes : list of str
        What the estimate assumed.
    noise_candidates : float, default 0
        Noise candidates drawn.
    noise_wall_s : float, default 0
        Their share of ``wall_s`` [s].
    horizon : float or None
        The run's time span (dimensionless, units of sqrt(m/k_p)).
    detail : object
        The engine work behind it.

    Examples
    --------
    Two snapshots of 200 blocks at 17 bytes per block, beside the engine's 400 bytes per
    block:

    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 30.0}})
    >>> e = bk.limits.estimate(cfg)
    >>> e.snapshots, e.output_bytes, e.memory_bytes, e.horizon
    (2, 6800.0, 86800.0, 30.0)
    """

    snapshots: int | None
    output_bytes: float
    memory_bytes: float
    work: float | None
    wall_s: float | None
    notes: list[str] = field(default_factory=list)
    noise_candidates: float = 0.0
    noise_wall_s: float = 0.0
    horizon: float | None = None
    detail: object = None


def physical_memory() -> float:
    """Bytes of RAM of this machine (inf when unknown)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return math.inf


def memory_bytes(model: str, nodes: int) -> float:
    """Engine memory of ``nodes`` blocks or grid nodes of ``model`` (its registry entry
    names the figure of ``LIMITS``: a chain block, a free-boundary grid node).

    Parameters
    ----------
    model : str
        The model (one of ``bkwaves._models.NAMES``).
    nodes : int
        Blocks or grid nodes.

    Returns
    -------
    float
        Bytes (``LIMITS``' per-block or per-node figure times ``nodes``).

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.limits.memory_bytes("chain", 1000) == 1000 * bk.limits.LIMITS["chain_bytes_per_block"]
    True
    """
    per = LIMITS[_models.get(model).bytes_per_node_key]
    return float(per) * nodes


def snapshot_memory(total: float, one: float, streamed: bool) -> float:
    """Bytes a run's snapshots take in memory: all of them when the run keeps them;
    streamed to an output, at most ``LIMITS["stream_snapshot_copies"]`` snapshots at
    once, however many are written.

    Parameters
    ----------
    total : float
        Bytes of all the run's snapshots.
    one : float
        Bytes of one snapshot.
    streamed : bool
        The snapshots go to an output as they are taken (``bkwaves run``,
        ``bk.run(cfg, OUT)``); False: the run keeps them (``Chain.run``).

    Returns
    -------
    float
        Bytes.

    Examples
    --------
    >>> import bkwaves as bk
    >>> one = 10**7 * 17  # u, u_t and sliding of 1e7 blocks
    >>> bk.limits.snapshot_memory(61 * one, one, True) / one
    10.0
    >>> bk.limits.snapshot_memory(61 * one, one, False) / one
    61.0
    """
    if not streamed:
        return float(total)
    return min(float(total), LIMITS["stream_snapshot_copies"] * float(one))


def check_memory(name: str, model: str, nodes: int, shown: str | None = None) -> None:
    """Refuse a chain or grid whose engine state cannot fit in this machine's RAM
    (``shown``: the value of the key ``name``, default ``nodes``)."""
    need = memory_bytes(model, nodes)
    have = physical_memory()
    if need > have:
        raise ParameterError(
            f"{name} = {nodes if shown is None else shown}: the engine state needs about "
            f"{_bytes(need)}, more than the "
            f"{_bytes(have)} of RAM of this machine"
        )


#: The runner's snapshot schedule of a run bounded only by events (runner._snapshot_times)
OPEN_SNAPSHOTS = 10**6


def snapshot_count(snapshot_every, snapshot_events, t_span, events, open_ended=False):
    """Snapshots of a run (the initial state included): every ``snapshot_every`` up to
    ``t_span`` (``open_ended``: a run bounded by events, t_span its estimated horizon;
    the runner schedules at most OPEN_SNAPSHOTS ahead), or one per ``snapshot_events``
    events."""
    if snapshot_every is not None:
        if t_span is None or not math.isfinite(t_span):
            return OPEN_SNAPSHOTS
        count = t_span / snapshot_every * (1 + 1e-12) + 1  # (inf for 1e-310: capped)
        return int(min(count, OPEN_SNAPSHOTS if open_ended else 2**62))
    if snapshot_events is not None:
        return None if events is None else int(events // snapshot_events + 1)
    return 2


#: The onset's sub-steps (crates/bkwaves-core/src/chain/onset.rs): a velocity-weakening
#: chain whose law's step m_min v_f/theta_max is shorter than dx/ONSET_GAIN (the engine's
#: chain::ONSET_GAIN) keeps step dx for its runs and integrates each block's onset (the
#: block and its sliding neighbours, the patch) with sub-steps of its own. Their work per
#: slip, in patch block-steps (sub-steps times patch blocks, every pass counted, as the
#: engine's block_steps counter does), is ONSET_BLOCK_STEPS step^(-1/2): measured 1600-3700
#: at step 0.1, 2000-4300 at 0.05, 3200-6800 at 0.025 on fronts at u_+ = 0.5, 0.7,
#: gamma = 0.3, dx = 0.025-0.1, v_f/dx = 2e-2 ... 2e-5 (docs/benchmarks.md, "Onset"; within
#: 2x of the fit everywhere; tests/test_estimate.py counts them). It does not grow as
#: v_f falls.
ONSET_BLOCK_STEPS = 630.0
ONSET_GAIN = 50.0


def onset_substeps(
    law, dx: float, step: float, threshold_max=1.0, mass_min=1.0, substeps: bool = True
) -> float:
    """The onset's patch block-steps per slip (``ONSET_BLOCK_STEPS`` step^(-1/2)) where
    the engine gives the onsets sub-steps (RK4 at its fixed step, ``substeps``, and a
    velocity-weakening law whose step m_min v_f/theta_max is shorter than
    dx/ONSET_GAIN), else 0."""
    values = dict(law.params) if law is not None else {}
    v_f = values.get("v_f")
    if not substeps or v_f is None or getattr(law, "name", "") != "velocity_weakening":
        return 0.0
    h_law = step * mass_min * v_f / max(threshold_max, 1e-300)
    if h_law * ONSET_GAIN < step * dx:
        return ONSET_BLOCK_STEPS / math.sqrt(step)
    return 0.0


def chain_step(
    dx: float,
    step: float,
    law=None,
    threshold_max: float = 1.0,
    mass_min=1.0,
    substeps: bool = True,
):
    """The chain's time step. RK4 at its fixed step (``substeps``) keeps step dx for
    every law and resolves a velocity-weakening block's onset with sub-steps of its own
    when m_min v_f/theta_max < dx/ONSET_GAIN (their work: :func:`onset_substeps`).
    Otherwise, and for the midpoint rule and RK4 under step-size control, every block
    steps at step m_min v_f/theta_max if that is shorter than step dx (the engine's rule)."""
    h = step * dx
    values = dict(law.params) if law is not None else {}
    v_f = values.get("v_f")
    if v_f is not None and getattr(law, "name", "") == "velocity_weakening":
        h_law = step * mass_min * v_f / max(threshold_max, 1e-300)
        if h_law < h and not (substeps and h_law * ONSET_GAIN < h):
            h = h_law
    return max(h, 1e-300)  # (v_f = 5e-324: no division by zero, an enormous estimate)


def _snapshot_wall(model: str, snapshots: int | None, nodes: int, output: bool) -> float:
    snaps = snapshots or 0
    per = LIMITS["seconds_per_snapshot"] + nodes * LIMITS["seconds_per_snapshot_node"]
    if output:
        per += LIMITS[f"{model}_output_seconds_per_snapshot"]
        per += nodes * LIMITS["output_seconds_per_snapshot_node"]
    fixed = LIMITS["seconds_per_run"] + (LIMITS["seconds_per_output"] if output else 0.0)
    return snaps * per + fixed


def chain_wall(work, n: int, snapshots: int | None, output: bool) -> float:
    """Wall seconds of a chain run's work (a ``bkwaves._cost.Work``)."""
    return (
        work.block_steps * LIMITS["chain_seconds_per_block_step"]
        + work.steps * LIMITS["chain_seconds_per_step"]
        + work.slips * LIMITS["chain_seconds_per_slip"]
        + work.onset_block_steps * LIMITS["chain_seconds_per_onset_block_step"]
        + _snapshot_wall("chain", snapshots, n, output)
    )


def lattice_wall(work, n: int, snapshots: int | None, output: bool) -> float:
    """Wall seconds of a lattice run's work (the chain's, at the lattice's cost of a
    block-step)."""
    per = LIMITS["lattice_seconds_per_block_step"] - LIMITS["chain_seconds_per_block_step"]
    return chain_wall(work, n, snapshots, output) + work.block_steps * per


def fb_wall(work, grid: int, snapshots: int | None, output: bool) -> float:
    """Wall seconds of a free-boundary run's work."""
    return (
        work.crossings / LIMITS["fb_crossings_per_s"]
        + work.events * LIMITS["fb_seconds_per_event"]
        + _snapshot_wall("fb", snapshots, grid, output)
    )


def _initial_facts(cfg) -> tuple[float, float, bool]:
    """(mean, max, uniform?) of a config's initial u, from its spec (no arrays of the
    size of the chain: random fields peak at mean + amplitude by construction, plus
    their curvature a/l^2 in phi = u - u_xx)."""
    s = cfg.initial
    if s.kind == "uniform":
        return s.value, s.value, True
    if s.kind == "ramp":
        return 0.5 * (s.start + s.end), max(s.start, s.end), s.start == s.end
    if s.kind == "random":
        # (u_xx of the field, amplitude / l^2, at most the lattice's 4 amplitude/dx^2
        # in phi = u - Lap u/dx^2: counted up to 1)
        corr = max(s.correlation_length, 1e-100)
        bend = min(s.amplitude / corr / corr, 1.0)
        return s.mean, s.mean + s.amplitude + bend, s.amplitude == 0
    from .config import initial_state

    try:
        u = initial_state(cfg)
    except ParameterError:  # (an unreadable file: the run says so; assume a slip now)
        return 0.5, 1.0, False
    return float(np.mean(u)), float(np.max(u)), bool(np.ptp(u) == 0)


#: Chains up to this many blocks get their initial phi computed for the estimate
EXACT_PHI_BLOCKS = 2 * 10**6


def _chain_phi_max(cfg, thr) -> float:
    """max(phi - threshold) + 1 of a chain config's initial state (phi = u - Lap u/dx^2,
    the ends free or held at the end blocks' values, a ring wrapped; uniform bonds)."""
    from .config import initial_state

    try:
        u = initial_state(cfg)
    except ParameterError:  # (an unreadable file: the run says so; assume a slip now)
        return 1.0
    if cfg.boundary == "periodic":
        lap = np.roll(u, 1) + np.roll(u, -1) - 2.0 * u
    else:
        ext = np.concatenate([[u[0]], u, [u[-1]]])
        lap = ext[2:] + ext[:-2] - 2.0 * ext[1:-1]
    with np.errstate(all="ignore"):
        phi = u - lap / cfg.params.dx**2
        top = float(np.max(phi - thr)) + 1.0
    return top if math.isfinite(top) else math.inf


def _chain_run(cfg, t_span, max_events):
    """The ``bkwaves._cost.ChainRun`` of a chain config."""
    from ._cost import ChainRun
    from .config import disorder_arrays

    p = cfg.params
    mean, top, uniform = _initial_facts(cfg)
    props = disorder_arrays(cfg) if cfg.disorder else {}
    thr = props.get("threshold")
    mass = props.get("mass")
    thr_min = 1.0 if thr is None else float(np.min(thr))
    thr_max = 1.0 if thr is None else float(np.max(thr))
    m_min = 1.0 if mass is None else float(np.min(mass))
    steps = cfg.chain_integration()
    substeps = steps["integrator"] == "rk4" and steps["step_tolerance"] is None
    h = chain_step(p.dx, steps["step"], p.law, thr_max, m_min, substeps)
    onset = onset_substeps(p.law, p.dx, steps["step"], thr_max, m_min, substeps)
    phi_max = top - thr_min + 1.0
    if cfg.blocks <= EXACT_PHI_BLOCKS:  # phi = u - Lap u/dx^2 itself (ends, curvature)
        phi_max = _chain_phi_max(cfg, 1.0 if thr is None else np.asarray(thr))
    from .chain import default_max_event_duration

    duration = cfg.max_event_duration or default_max_event_duration(cfg.blocks, p.dx)
    return ChainRun(
        n=cfg.blocks,
        dx=p.dx,
        h=h,
        v=p.v,
        gamma=p.gamma,
        u_ahead=mean,
        phi_max=phi_max,
        # (v = 0 with noise: its first slip starts a rupture at any time; counted now)
        started=phi_max >= 1.0
        or abs(cfg.initial.velocity) > 0
        or (cfg.noise is not None and p.v == 0.0),
        trigger_times=tuple(t.time for t in cfg.triggers),
        uniform=uniform and not cfg.disorder and cfg.noise is None,
        t_span=t_span,
        max_events=max_events,
        event_duration=duration,
        step_bound=steps["step_tolerance"] is not None,
        open_sources=cfg.noise is not None,
        onset_per_slip=onset,
    )


def _fb_gap(cfg) -> float:
    """threshold - max u of a free-boundary config (from the spec)."""
    from .config import threshold_field

    _, top, _ = _initial_facts(cfg)
    thr = threshold_field(cfg) if cfg.disorder else None
    return (1.0 if thr is None else float(np.min(thr))) - top


def estimate(cfg, output: bool = True) -> Estimate:
    """Estimate what the run described by ``cfg`` needs (the module's docs say how).

    Parameters
    ----------
    cfg : bkwaves.config.RunConfig
        The run.
    output : bool, default True
        Whether the run writes a file.

    Returns
    -------
    Estimate
        Snapshots, bytes, work and wall time [s].

    Examples
    --------
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 30.0}})
    >>> e = bk.limits.estimate(cfg)
    >>> e.snapshots, e.output_bytes
    (2, 6800.0)
    """

    p = cfg.params
    entry = _models.get(cfg.model)
    nodes = entry.nodes(cfg)
    work, count, wall_of = entry.work(cfg)
    # (snapshot_every with t_end: the runner schedules every one up to t_end, also when
    # max_events may end the run sooner: t_end = 2**64 at every 50 allocated 2.6 EiB)
    span = cfg.t_end if cfg.t_end is not None and cfg.snapshot_every else work.horizon
    snaps = snapshot_count(
        cfg.snapshot_every, cfg.snapshot_events, span, work.events, cfg.t_end is None
    )
    if cfg.max_events is not None and cfg.snapshot_events is not None:
        snaps = cfg.max_events // cfg.snapshot_events + 1
    one = nodes * entry.snapshot_bytes_per_node
    out = float(snaps or 0) * one
    wall = wall_of(work, nodes, snaps, output)
    # the engine, and the snapshots: streamed to the output, or all held without one
    mem = memory_bytes(cfg.model, nodes) + snapshot_memory(out, one, output)
    notes = list(work.notes)
    size = entry.noise_size(cfg)
    candidates, noise_wall = noise_work(
        cfg.model, size, nodes, work.horizon, p.v, cfg.noise, work.sliding_fraction
    )
    if candidates > 0:
        notes.append(f"~{candidates:.2g} noise candidates")
    return Estimate(
        snaps, out, mem, count, wall + noise_wall, notes, candidates, noise_wall, work.horizon, work
    )


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
    model: str,
    size: float,
    n: int,
    t_span: float,
    v: float,
    noise: dict | None,
    frac: float | None = None,
) -> tuple[float, float]:
    """Estimated noise candidates and their wall seconds over ``t_span`` (module docs):
    ``size`` is the number of blocks (chain) or the domain length (free boundary), ``n``
    the chain's blocks (unused for the free boundary), ``frac`` the fraction of the
    block-time spent sliding (default min(1, v / 0.1), 1 at v = 0). (0, 0) without noise."""
    if noise is None or noise["rate"] == 0.0 or not t_span:
        return 0.0, 0.0
    g_top, g_mean = noise_envelope(noise)
    if frac is None:
        frac = 1.0 if v == 0 else min(1.0, v / 0.1)
    # the fraction of the time the bound is rate G(1): the chain's time with any block
    # sliding is at most n frac (each block sliding alone); the free boundary's U(t)
    # near the threshold: frac
    # (chain: plus the blocks the noise itself sets sliding, each for ~pi: accepted
    # candidates at about n rate <G>)
    blocks = _models.get(model).noise_kind == "chain"
    own = n * noise["rate"] * g_mean * math.pi
    busy = min(1.0, n * frac + own) if blocks else frac
    per_g = size * noise["rate"] * t_span  # candidates per unit of the envelope G
    candidates = per_g * (busy * g_top + (1.0 - busy) * g_mean)
    wall = candidates * LIMITS[f"{'chain' if blocks else 'fb'}_seconds_per_candidate"]
    if blocks:
        # a candidate while blocks slide cuts a step short: one more step over the blocks
        # sliding then, whose block-time is frac n t_span
        if frac > 0:
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
        entry = _models.get(model)
        per, si = entry.noise_per, entry.noise_si
        scale = units.time_scale * units.length_scale**entry.noise_length_power
        rate = (
            f"noise.rate = {noise['rate'] / scale:.6g} {si} (= {noise['rate']:.3g} per {per} "
            "and time unit)"
        )
    if noise["law"] == "table" and g_top > 1.0:
        return f"noise.g (its peak below u = 1 is G(1) = {g_top:.3g} times g(1); {rate})"
    return rate


def check_wall(
    what: str, wall: float, work_text: str, noise_what: str | None = None, noise_cost=(0.0, 0.0)
) -> None:
    """Warn (one :class:`LongRunWarning`) beyond ``warn_wall_s``; never refuse: ``what``
    names the key. ``noise_cost``: the noise's (candidates, wall seconds) of
    :func:`noise_work`, added; when they cost more than the rest the message names
    ``noise_what`` (the noise's key, :func:`noise_key`) first."""
    candidates, noise_wall = noise_cost
    wall = math.inf if math.isnan(wall) else wall  # (inf x 0 of an overflowing input)
    noise_wall = math.inf if math.isnan(noise_wall) else noise_wall
    if noise_what is not None and candidates > 0:
        work_text = f"~{candidates:.2g} noise candidates and {work_text}"
        if noise_wall > wall or math.isinf(noise_wall):
            what = f"{noise_what} with {what}"
        wall += noise_wall
    if wall > LIMITS["warn_wall_s"]:
        warnings.warn(
            f"{what}: estimated {work_text}, about {_duration(wall)} of computation "
            "(an estimate: the run goes on; Ctrl-C stops it and keeps what it computed)",
            LongRunWarning,
            stacklevel=4,
        )


def check_noise_events(what: str, size: float, crossing: float, noise: dict | None) -> None:
    """A free-boundary run bounded only by events, with noise: when about one nucleation
    or more falls within the time a rupture takes to cross the domain (``size`` rate <G>
    x ``crossing``), ruptures merge into one event that never completes (a free-boundary
    ring of length 40 at rate 0.1 ran for ever with no event complete): warn."""
    if noise is None or noise["rate"] == 0.0:
        return
    _, g_mean = noise_envelope(noise)
    overlap = size * noise["rate"] * g_mean * crossing
    if overlap >= 1.0:
        warnings.warn(
            f"{what}: about {overlap:.3g} noise nucleations fall within one rupture's "
            f"crossing of the domain (~{crossing:.3g} time units): events may merge and "
            "never complete; give run.t_end",
            LongRunWarning,
            stacklevel=4,
        )


def check_memory_use(what: str, need: float) -> None:
    """Warn when a run will hold more than ``warn_memory_fraction`` of the RAM."""
    have = physical_memory()
    if need > LIMITS["warn_memory_fraction"] * have:
        warnings.warn(
            f"{what}: the run will hold about {_bytes(need)} in memory, of the "
            f"{_bytes(have)} of RAM of this machine",
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


def _events_text(cfg) -> str:
    what = f"run.max_events = {cfg.max_events}"
    if cfg.t_end is None:
        return what
    return f"{_t_end_text(cfg)} with {what}" if cfg.max_events is not None else what


def check_sizes(cfg) -> Estimate:
    """Refuse a config that cannot fit (memory, output size beyond ``LIMITS``) with the
    key and the figure in the message; warn (:class:`LongRunWarning`, one line each)
    about one that will take long, hold much memory or write a large output.

    ``bkwaves.config.parse_config`` calls it on every config it builds.

    Parameters
    ----------
    cfg : bkwaves.config.RunConfig
        The run.

    Returns
    -------
    Estimate
        What the run needs.

    Raises
    ------
    bkwaves.ParameterError
        A run that cannot fit, naming the config key and the figure.

    Examples
    --------
    >>> import bkwaves as bk
    >>> cfg = bk.config.parse_config({
    ...     "model": "chain", "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
    ...     "domain": {"blocks": 200}, "initial": {"kind": "uniform", "value": 0.6},
    ...     "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
    ...     "run": {"t_end": 30.0}})
    >>> bk.limits.check_sizes(cfg).output_bytes
    6800.0
    >>> bk.config.parse_config({**cfg.to_dict(), "domain": {"blocks": 10**11}})
    Traceback (most recent call last):
    ...
    bkwaves._core.ParameterError: domain.blocks = 100000000000: the engine state needs...
    """
    entry = _models.get(cfg.model)
    nodes = entry.nodes(cfg)
    check_memory(entry.size_key, cfg.model, nodes, entry.size_text(cfg))
    if entry.events_need_loading and cfg.params.v == 0 and cfg.t_end is None:
        raise ParameterError(
            "run.max_events: with v = 0 nothing loads the field, so no event can start and "
            "the run would end at once with none; give run.t_end"
        )
    est = estimate(cfg)
    if cfg.snapshot_every is not None:
        snap_key = "output.snapshot_every"
        snap_key += " with run.t_end" if cfg.t_end is not None else " with run.max_events"
    else:
        snap_key = "output.snapshot_events with run.max_events"
    # (refused only where the snapshot count is exact; an estimated one warns below)
    exact = cfg.t_end is not None if cfg.snapshot_every is not None else cfg.max_events
    if est.output_bytes > LIMITS["max_output_bytes"] and exact:
        raise ParameterError(
            f"{snap_key}: {est.snapshots:.3g} snapshots of {nodes} nodes make "
            f"about {_bytes(est.output_bytes)} of output, more than the limit "
            f"{_bytes(LIMITS['max_output_bytes'])} (bkwaves.limits.LIMITS['max_output_bytes'])"
        )
    what = _t_end_text(cfg) if cfg.t_end is not None else _events_text(cfg)
    if cfg.t_end is None:
        what += f" (estimated to end near t = {est.horizon:.3g})"
    check_wall(
        what,
        est.wall_s - est.noise_wall_s,
        est.notes[0],
        noise_key(cfg.noise, cfg.model, cfg.params.units),
        (est.noise_candidates, est.noise_wall_s),
    )
    if est.output_bytes > LIMITS["warn_output_bytes"]:
        warnings.warn(
            f"{snap_key}: {est.snapshots:.3g} snapshots of {nodes} nodes make about "
            f"{_bytes(est.output_bytes)} of output",
            LongRunWarning,
            stacklevel=3,
        )
    check_memory_use(what, est.memory_bytes)
    if cfg.t_end is None:  # (the chain's noise slips end on their own: no check)
        entry.check_noise_events(cfg, what)
    if cfg.t_end is None and cfg.snapshot_every is not None and est.horizon:
        wanted = est.horizon / cfg.snapshot_every
        if wanted > OPEN_SNAPSHOTS:
            end = (
                f"the run is estimated to end near t = {est.horizon:.3g}"
                if est.horizon < 1e300
                else f"with v = 0 fewer events than run.max_events = {cfg.max_events} are "
                "estimated to happen, and the run then goes on to t = 1e300"
            )
            warnings.warn(
                f"{snap_key}: {end}, {wanted:.3g} snapshots; it takes the first "
                f"{OPEN_SNAPSHOTS} (to t = "
                f"{OPEN_SNAPSHOTS * cfg.snapshot_every:.3g}; give run.t_end or a longer "
                "output.snapshot_every)",
                LongRunWarning,
                stacklevel=3,
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
