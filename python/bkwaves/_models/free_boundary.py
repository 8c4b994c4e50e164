"""The one-dimensional free boundary model (``model = "free_boundary"``):
bkwaves.FreeBoundary run from a config.

Its entry in the model registry (``bkwaves._models``): [domain] length, grid and
boundary, a threshold field ([disorder] threshold), a [speed] law, noise per unit length;
outputs u on the grid, the events, shocks and ruptures tables.
"""

from __future__ import annotations

import time

import numpy as np

from .._progress import ProgressBar
from . import Model
from ._targets import TargetLoop


def _run_free_boundary(cfg, out, progress, overwrite, flush_every, chunk, ctl):
    import warnings

    from ..config import initial_state, threshold_field
    from ..free_boundary import FreeBoundary
    from ..runner import (
        RunSummary,
        _complete,
        _described,
        _finish,
        _frame,
        _guard_writes,
        _open_writer,
        _Units,
        _write_ruptures,
    )

    p = cfg.params
    x = cfg.x()
    notes = []
    if ctl.resuming:
        fb = FreeBoundary._from_record(*ctl.state["engine"], ctl.state["path"])
    else:
        u0 = initial_state(cfg)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fb = FreeBoundary(
                p,
                x,
                u0,
                cfg.boundary,
                noise=cfg.noise,
                seed=cfg.seed,
                speed=cfg.speed,
                threshold=threshold_field(cfg, x),
            )
        notes = [str(w.message) for w in caught]
        for w in caught:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    eng = fb._engine
    from ..chain import CHUNK_WALL

    eng.set_chunk_wall(CHUNK_WALL)
    units = _Units(cfg)
    variables = {"u": ("1", "slow field u (0: kinetic level, 1: static threshold)", "f8")}
    resume_rows = {"events": eng.completed_events, "shocks": len(eng.path()["t"]), "ruptures": 0}
    writer = _open_writer(out, cfg, units, x, variables, ctl, overwrite, flush_every, resume_rows)
    total = cfg.t_end if cfg.t_end else (cfg.max_events if cfg.max_events is not None else 2**62)
    bar = ProgressBar(progress, total, "free boundary")
    wall0 = time.perf_counter()
    interrupted = False
    snapshots = 0

    def give(final=True):
        """Hand the writer the table rows it does not have yet (``final``: completed
        events only; every shock path point is final when recorded)."""
        if writer is None:
            return
        k = writer.table_rows("events")
        n = eng.completed_events if final else None
        ev = _frame(eng.events(k), None if n is None else max(n - k, 0))
        if len(ev) or not final:  # (at the end: the table even when it is empty)
            ev.insert(3, "duration", ev["t_end"] - ev["t_start"])
            ev["complete"] = _complete(k, len(ev), eng.completed_events)
            ev, eu, es = units.convert_table(
                ev,
                times=("t_start", "t_end", "duration"),
                xs=("x_start", "x_min", "x_max", "swept"),
                moments=("moment",),
            )
            writer.append_rows("events", ev, eu, scales=es, descriptions=_described(ev))
        sh = _frame(eng.path(writer.table_rows("shocks")))
        if len(sh) or not final:
            sh, su, ss = units.convert_table(sh, times=("t",), xs=("x",))
            writer.append_rows("shocks", sh, su, csv=False, scales=ss)

    def snap():
        nonlocal snapshots
        snapshots += 1
        if writer is not None:
            give()  # the catalog rows before the snapshot they belong with
            writer.append(units.t(eng.time), u=np.asarray(eng.u_nodes()))

    # the loop's place goes into checkpoints: a resumed run makes the same engine calls
    # and writes the same snapshots
    loop = TargetLoop(cfg, ctl, snap)
    if ctl.resuming:
        snapshots = int(ctl.state["written"])

    with _guard_writes(bar, writer, cfg, lambda: (eng.completed_events, units.t(eng.time))):
        finished = loop.run(
            eng, cfg, ctl, bar, chunk, lambda: eng.completed_events, snap,
            lambda state: ctl.save(fb, writer, state), after_chunk=give,
        )  # fmt: skip
        interrupted = not finished
        bar.close()
        rup = ruptures(cfg, eng, x)

        def give_all():
            # the state at the end (the cut, when interrupted: a resumed run drops it)
            if snapshots == 0 or interrupted or cfg.t_end is None:
                snap()
            give(final=False)
            _write_ruptures(writer, units, rup)

        if writer is None:
            if snapshots == 0 or interrupted or cfg.t_end is None:
                snapshots += 1
        interrupted = _finish(writer, ctl, fb, loop.state(), give_all, interrupted)
    return RunSummary(
        model="free_boundary",
        out=str(out) if out else None,
        t=float(units.t(eng.time)),
        events=int(eng.completed_events),
        snapshots=writer.count if writer is not None else snapshots,
        interrupted=interrupted,
        wall_s=time.perf_counter() - wall0,
        units=units.name,
        extra={
            "grid": len(x),
            "ruptures": len(rup),
            "warnings": notes,
            "steps": int(eng.steps),
            "signal": ctl.signal_name() if interrupted else None,
        },
    )


def ruptures(cfg, eng, x):
    """The ruptures table of a free boundary run (:func:`bkwaves.catalog.run_ruptures`),
    dimensionless, from the engine's whole record of shock paths."""
    from ..catalog import run_ruptures
    from ..runner import _frame

    h = float(x[1] - x[0])
    return run_ruptures(
        "free_boundary", _frame(eng.path()), n=len(x), dx=h, boundary=cfg.boundary, x0=x[0]
    )


def check_continuum(cfg) -> None:
    """gamma < 1 and dx < 1: the free boundary problem is the chain's continuum limit
    with pulses (both free boundary models)."""
    from ..config import _err

    p = cfg.params
    if p.gamma >= 1.0:
        _err(
            "params.gamma" if not cfg.physical else "physical.alpha",
            f"gamma = {p.gamma:.6g}: the free boundary model needs 0 <= gamma < 1 (for "
            "gamma >= 1 every wave creeps)",
        )
    if p.dx >= 1.0:
        _err(
            "params.dx" if not cfg.physical else "physical.k_c",
            f"dx = {p.dx:.6g}: the free boundary model is the continuum limit, allowed 0 < dx < 1",
        )


class FreeBoundaryModel(Model):
    name = "free_boundary"
    boundaries = ("free", "periodic")
    domain_keys = ("length", "grid", "boundary")
    domain_required = ("length", "grid")
    size_key = "domain.grid"
    disorder_keys = ("threshold",)
    correlated_disorder = True
    threshold_field = True
    speed_law = True
    coulomb_only = True
    noise_kind = "free_boundary"
    noise_per = "unit length"
    noise_si = "1/(m s)"
    noise_length_power = 1
    events_need_loading = True
    bytes_per_node_key = "fb_bytes_per_node"
    snapshot_bytes_per_node = 8
    summary = "the free boundary problem on a line (bkwaves.FreeBoundary)"

    def parse_domain(self, d, cfg_value):
        return {"length": cfg_value(d, "length"), "grid": cfg_value(d, "grid")}

    def domain_doc(self, cfg):
        return {"length": cfg.length, "grid": cfg.grid, "boundary": cfg.boundary}

    def scale_noise(self, noise, ts, ls, vs):
        noise["rate"] *= ls * ts  # per unit length and time
        return noise

    def property_arrays(self, cfg):
        from ..config import threshold_field

        return {"threshold": threshold_field(cfg)}

    def check(self, cfg):
        from .._core import ParameterError
        from ..config import _err
        from ..free_boundary import check_grid

        check_continuum(cfg)
        if not cfg.length / (cfg.grid - 1) > 0:
            _err("domain.length", "the grid spacing length/(grid - 1) underflows to 0")
        try:
            check_grid("domain.length", cfg.length, cfg.length / (cfg.grid - 1), cfg.params.v)
        except ParameterError as e:
            raise ParameterError(f"{e} (domain.length with domain.grid)") from None

    def check_keys(self, cfg):
        from ..config import _err

        # (the chain's noise follows per-block thresholds)
        if cfg.noise is not None and dict(cfg.disorder).get("threshold") is not None:
            _err("noise", "not implemented with a threshold field ([disorder] threshold)")

    def check_initial(self, cfg, u, x, key):
        from ..config import _err, threshold_field

        thr = threshold_field(cfg, x)
        if thr is None and np.max(u) >= 1.0:
            i = int(np.argmax(u))
            _err(
                key,
                f"the initial state reaches u = {u[i]:.6g} >= 1 at x = {x[i]:.6g}: the free "
                "boundary model needs u < 1 (the static threshold) everywhere (its field is "
                "the stress of stuck blocks; a chain over the threshold slides at once: "
                'model = "chain" runs it)',
            )
        if thr is not None and np.any(u >= thr):
            i = int(np.argmax(u - thr))
            _err(
                key,
                f"the initial state reaches u = {u[i]:.6g} >= the threshold {thr[i]:.6g} at "
                f"x = {x[i]:.6g}: the free boundary model needs u < threshold everywhere",
            )

    def scale_domain(self, domain, ls):
        return {**domain, "length": domain["length"] / ls}

    def physical_lengths(self, cfg):
        return (("domain.length", cfg.length),)

    def x(self, cfg):
        end = cfg.length if cfg.boundary == "free" else cfg.length * (1 - 1 / cfg.grid)
        return np.linspace(0.0, end, cfg.grid)

    def nodes(self, cfg):
        return cfg.grid

    def span(self, cfg):
        return cfg.length

    def noise_size(self, cfg):
        return cfg.length

    def check_noise_events(self, cfg, what):
        from ..limits import check_noise_events

        check_noise_events(what, cfg.length, cfg.length, cfg.noise)

    def run(self, cfg, out, progress, overwrite, flush_every, chunk, ctl):
        return _run_free_boundary(cfg, out, progress, overwrite, flush_every, chunk, ctl)

    def work(self, cfg):
        from .. import _cost
        from ..limits import _fb_gap, fb_wall

        work = _cost.fb_work(cfg.grid, cfg.params.v, cfg.t_end, cfg.max_events, _fb_gap(cfg))
        return work, work.crossings, fb_wall


MODEL = FreeBoundaryModel()
