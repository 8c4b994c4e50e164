"""What the engines will do in a run, estimated from the physics before it starts
(docs/usage.md, "Limits"; calibrated per unit of work in ``bkwaves.limits.LIMITS``).

The chain engine steps only its sliding blocks (step h = step dx, or step times the
friction law's own time scale m v_f / theta for velocity weakening, if shorter and not
below dx/50, where the onsets get sub-steps of their own instead: a number per slip,
``bkwaves.limits.onset_substeps``) and jumps over quiet stretches where every block is
stuck. So its work is

- block-steps = S / h, S the sliding block-time (the integral over the run of the number
  of sliding blocks);
- steps = T_active / h, T_active the time during which any block slides;
- slips (a record each), snapshots (n values each), and a fixed cost per run.

S and T_active follow from what a rupture does (paper Sec. III, App. B): a front at
u_+ ahead moves at c = 1/sqrt(1 - u_+^2) and, for a pulse (gamma < u_+ < 1), each block
slides for about w/c (w the pulse width of App. B, ``bk.traveling_wave``); in creep
(u_+ <= gamma, or gamma >= 1) blocks never re-stick and slide until the run or the event
ends (``run.max_event_duration``); below u_+ = 0 a front dies at once. Where nothing
starts a rupture (no trigger, nothing over its threshold, v = 0) nothing slides. Under
loading (v > 0) the chain is quiet until the stress nearest its threshold gets there,
t_1 = (theta_min - phi_max)/v; then, on average, every block slips off what the loader
adds (mean slip rate = v), once per reload A/v (A ~ 1, the slip of a pulse near the
threshold: App. B's A at u_+ = 0.9), each slip a rupture as above. A run bounded only
by ``max_events`` = K: K system-wide ruptures for a uniform chain (every loading event
spans it), else sqrt(K) of them: the truth lies between one system-wide rupture
followed by small ones (a random start, examples/chain_loading.toml) and K system-wide
ones, and sqrt(K) is within sqrt(K) of both (within 10x for K <= 100). Its time horizon
(for snapshots and noise): t_1 plus one reload per further system-wide rupture (uniform),
else t_1 plus about one reload (small events between the big ones come fast).

The free-boundary engine is event-driven: quiet time costs nothing, a shock costs one
engine event per node it crosses. Over a loading v T each node is crossed ~10 v T times
and ~0.7 v T events start (measured: ``fb_work``); K events alone cost ~14 K crossings
of the grid, and start after t_1 = (threshold - max u)/v.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

#: App. B's slip A of a pulse near the threshold (u_+ = 0.9, gamma 0.3: 1.2): the
#: reload between two system-wide ruptures under loading is A/v
RELOAD_SLIP = 1.0

#: Where a chain run bounded only by events ends when no more can happen (runner t_stop)
RUN_END = 1e300


@dataclass
class ChainRun:
    """The facts of a chain run the estimate needs (from a config or a live chain)."""

    n: int
    dx: float
    h: float  # the time step
    v: float
    gamma: float
    u_ahead: float  # the typical stress ahead of a rupture (mean of the initial u)
    phi_max: float  # the largest u - Lap u/dx^2 - threshold + 1 now (>= 1: slips at once)
    started: bool  # something slides now or a trigger is pending at t = 0
    trigger_times: tuple = ()  # pending triggers (times from now)
    uniform: bool = True  # every loading event spans the chain (uniform u, no disorder)
    t_span: float | None = None  # run time (None: bounded only by max_events)
    max_events: int | None = None
    event_duration: float = math.inf  # the runaway-event limit (run.max_event_duration)
    step_bound: bool = False  # run.step_tolerance: h is the floor, the work a bound
    open_sources: bool = False  # noise: events may start at any time
    onset_per_slip: float = 0.0  # the onset's patch block-steps per slip (limits.onset_substeps)


@dataclass
class Work:
    """The estimated work of a run: engine units, time horizon and notes."""

    block_steps: float = 0.0
    onset_block_steps: float = 0.0  # the onsets' sub-steps times their patch blocks
    steps: float = 0.0
    slips: float = 0.0
    crossings: float = 0.0  # free boundary: shock-node crossings
    events: float = 0.0
    horizon: float = 0.0  # the run's time span (estimated for max_events-only runs)
    sliding_fraction: float = 0.0  # S / (n horizon): for the noise's estimate
    notes: list = field(default_factory=list)


def _wave(u_plus: float, gamma: float) -> tuple[float, float, bool]:
    """(c, sliding time per block, pulse?) of a front at u_+ (App. B)."""
    u = min(max(u_plus, 1e-6), 0.999)
    c = 1.0 / math.sqrt(1.0 - u * u)
    if gamma >= 1.0 or u <= gamma:
        return c, math.inf, False
    try:
        from .waves import traveling_wave

        tw = traveling_wave(u, gamma)
        if tw.regime == "pulse" and tw.w is not None and math.isfinite(tw.w):
            return tw.c, tw.w / tw.c, True
    except Exception:  # noqa: BLE001 - an estimate: fall back on the oscillator
        pass
    return c, math.pi / math.sqrt(max(1.0 - gamma * gamma, 1e-12)), True


def _rupture(r: ChainRun, u_plus: float, span: float, at_once: bool = False) -> tuple[float, float]:
    """(S, T_active) of one rupture over the chain at stress u_plus ahead, cut at span;
    ``at_once``: every block starts together (a uniform chain loaded to its threshold).

    Both include the event location: each slip or stick of a block is located in time
    and the step redone up to it over every block sliding then, one more step of them
    (added as h x those blocks to S, h to T_active). A pulse of m = c tau/dx blocks: 2 m
    per block; a uniform chain re-sticking block by block (round-off spreads the
    instants): n^2/2; a creep front: the blocks behind it, reached^2/2."""
    n, dx, h = r.n, r.dx, r.h
    if u_plus <= 0.0:  # the front dies at once: the triggered block alone
        return min(math.pi, span), min(math.pi, span)
    c, tau, pulse = _wave(u_plus, r.gamma)
    cross = 0.0 if at_once else n * dx / c  # the front crosses the chain
    reached = float(n) if span >= cross else max(1.0, c * span / dx)
    if pulse:
        sliding = reached if at_once else min(reached, max(1.0, c * tau / dx))
        redo = reached * sliding * (0.5 if at_once else 2.0)
        return reached * min(tau, span) + redo * h, min(span, cross + tau) + 2 * reached * h
    # creep: every block reached slides to the end of the run or of the event
    end = min(span, r.event_duration)
    redo = 0.5 * reached * reached
    return reached * max(end - min(cross, end) / 2.0, 0.0) + redo * h, end + reached * h


def chain_work(r: ChainRun) -> Work:
    """Sliding block-time, steps and slips of a chain run (module docs)."""
    w = Work()
    span = math.inf if r.t_span is None else r.t_span
    cap = math.inf
    if r.max_events is not None:
        cap = float(r.max_events) if r.uniform else math.sqrt(r.max_events)
    ruptures = s_total = active = 0.0
    horizon = 0.0
    # a rupture running now, or started by a pending trigger
    start = 0.0 if r.started else (min(r.trigger_times) if r.trigger_times else math.inf)
    if start < span:
        s, a = _rupture(r, r.u_ahead, span - start, at_once=r.uniform and r.phi_max >= 1.0)
        s_total, active, ruptures = s, a, 1.0
        horizon = start + a
    if r.v > 0.0:
        # loading: the first loaded rupture when the stress nearest its threshold gets
        # there (or a reload after the one above), then one per reload A/v
        reload = RELOAD_SLIP / r.v
        first = reload if ruptures else max(0.0, (1.0 - r.phi_max) / r.v)
        loaded = max(0.0, (span - first) / reload + 1.0) if span > first else 0.0
        loaded = min(loaded, max(cap - ruptures, 0.0))
        if loaded > 0:
            u_near = min(max(r.u_ahead, 0.0) + 0.3, 0.9)  # loaded near the threshold
            s, a = _rupture(r, u_near, min(span - first, reload), at_once=r.uniform)
            s_total += loaded * s
            active += loaded * a
            ruptures += loaded
            # (not uniform: sqrt(K) ruptures' work, but the events between them are
            # small and quick: about one reload in all)
            spread = 1.0 if r.uniform else 1.0 / max(loaded, 1.0)
            horizon = first + max(loaded - 1.0, 0.0) * reload * spread + a
    if r.v == 0.0 and r.t_span is None and ruptures < cap and not r.open_sources:
        # v = 0 and fewer ruptures than max_events: after the last one nothing loads the
        # chain, and the run jumps to the end of time (the runner's t_stop, 1e300)
        horizon = RUN_END
    w.horizon = float(span if math.isfinite(span) else horizon)
    if r.max_events is not None and ruptures >= cap:
        w.horizon = min(w.horizon, horizon)
    w.block_steps = s_total / r.h
    w.steps = active / r.h
    w.slips = r.n * ruptures
    w.onset_block_steps = w.slips * r.onset_per_slip
    w.events = ruptures
    w.sliding_fraction = min(1.0, s_total / (r.n * w.horizon)) if w.horizon > 0 else 0.0
    bound = "at most " if r.step_bound else ""
    w.notes.append(f"{bound}~{w.block_steps:.2g} block-steps in ~{w.steps:.2g} steps")
    if w.onset_block_steps:
        w.notes.append(f"~{w.onset_block_steps:.2g} block-steps in the onsets' sub-steps")
    return w


def fb_work(grid: int, v: float, t_span: float | None, max_events: int | None, gap: float) -> Work:
    """Crossings and events of a free-boundary run: ``gap`` = threshold - max u now."""
    w = Work()
    t1 = max(gap, 0.0) / v if v > 0 else math.inf
    if t_span is not None:
        load = v * max(t_span - t1, 0.0) if math.isfinite(t1) else 0.0
        if load > 0:
            load = max(load, 1.0)  # a started event runs its course
        w.crossings, w.events, w.horizon = 10.0 * load * grid, 0.7 * load, t_span
    if max_events is not None and (t_span is None or w.events > max_events):
        k = float(max_events)
        horizon = t1 + k / (0.7 * v) if v > 0 else 0.0
        w.crossings, w.events = 14.0 * k * grid, k
        w.horizon = horizon if t_span is None else min(t_span, horizon)
    w.sliding_fraction = min(1.0, v / 0.1) if v > 0 else 0.0
    w.notes.append(f"~{w.crossings:.2g} shock-node crossings, ~{w.events:.2g} events")
    return w
