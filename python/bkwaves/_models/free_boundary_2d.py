"""The planar free boundary model (``model = "free_boundary_2d"``): bkwaves.FreeBoundary2D
run from a config.

Its entry in the model registry (``bkwaves._models``). TOML:

- [domain] ``shape = [nx, ny]`` (grid nodes, each >= 3), ``spacing`` (the node spacing
  h along x and y; metres with [physical]), ``boundary``: free or periodic for both
  axes, or ``[along x, along y]``;
- [initial] uniform, ramp (along x), random (a smooth random field in the plane), file
  (.npy of shape (ny, nx), or nx ny values row after row): below the threshold
  everywhere;
- [disorder] threshold: the static threshold field s(x, y): a number, nx ny values, a
  drawn {distribution, mean, spread} per node, or a smooth random field {mean,
  amplitude, correlation_length};
- [speed] the front-speed law as the 1D model's; [noise] pair nucleation at Lambda(u) =
  rate g(u) per unit area and time (1/(m^2 s) with [physical]), the 1D model's laws;
- [output] ``arrivals = true``: the arrivals table, the arrival time of every node in
  every complete rupture (rupture, i, j, x, y, t).

- [[triggers]] ``time``, ``x``, ``y``, ``radius`` (default 0): a rupture started at that
  time on the disk of that radius around (x, y) (at least the nearest node; the place in
  metres with [physical]), as ``FreeBoundary2D.trigger`` does; a trigger whose disk
  touches a running rupture is not fired (that place is breaking already) and the run
  says so in a warning. Otherwise ruptures start where the loading brings u to the
  threshold, or by noise.
Outputs: snapshots u with dims (t, y, x); the ruptures table (the engine's catalog:
nucleation time and place, area, moment = the integral of u_+ - u_- over the area,
duration, perimeter, ...). `bkwaves stats` reads the ruptures.
"""

from __future__ import annotations

import time

import numpy as np

from . import Model
from ._targets import TargetLoop
from .free_boundary import check_continuum
from .lattice import _pair_of, _shape, planar_initial, planar_property

#: The ruptures table's columns, in order (the engine's catalog and the magnitude).
RUPTURE_COLUMNS = (
    "id",
    "origin",
    "t_start",
    "t_end",
    "duration",
    "x_start",
    "y_start",
    "u_start",
    "n_nodes",
    "area",
    "moment",
    "magnitude",
    "mean_slip",
    "perimeter",
    "n_stopped",
    "n_creep",
    "contacts",
    "complete",
)

DESCRIPTIONS = {
    "origin": "what started the rupture: birth (the loading reached the threshold), "
    "nucleation (noise) or trigger",
    "x_start": "where the rupture started (x)",
    "y_start": "where the rupture started (y)",
    "u_start": "the stress where it started",
    "n_nodes": "grid nodes the rupture swept",
    "area": "the area swept: n_nodes h^2",
    "moment": "the rupture's moment: the integral of u_+ - u_- (the slip) over its area",
    "mean_slip": "moment / area",
    "perimeter": "length of the rupture's boundary",
    "n_stopped": "nodes where the front stopped (u_+ below the critical stress)",
    "n_creep": "nodes left creeping",
    "contacts": "meetings with other running ruptures",
    "complete": "whether the rupture ended before the run stopped",
}


def _run_free_boundary_2d(model, cfg, out, progress, overwrite, flush_every, chunk, ctl):
    import warnings

    from .._progress import ProgressBar
    from ..free_boundary_2d import FreeBoundary2D
    from ..runner import (
        RunSummary,
        _finish,
        _guard_writes,
        _open_writer,
        _Units,
    )

    x, y = model.x(cfg), model.y(cfg)
    notes = []
    if ctl.resuming:
        fb = FreeBoundary2D._from_record(*ctl.state["engine"], ctl.state["path"])
    else:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fb = model.build(cfg)
        notes = [str(w.message) for w in caught]
        for w in caught:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    eng = fb._engine
    units = _Units(cfg)
    variables = {"u": ("1", "slow field u (0: kinetic level, 1: static threshold)", "f8")}
    resume_rows = {"ruptures": 0, "arrivals": 0}
    writer = _open_writer(
        out, cfg, units, x, variables, ctl, overwrite, flush_every, resume_rows,
        model.grid_attrs(cfg), y=y,
    )  # fmt: skip
    total = cfg.t_end if cfg.t_end else (cfg.max_events if cfg.max_events is not None else 2**62)
    bar = ProgressBar(progress, total, "free boundary 2D")
    wall0 = time.perf_counter()
    snapshots = 0

    def snap():
        nonlocal snapshots
        snapshots += 1
        if writer is not None:
            writer.append(units.t(eng.time), u=np.asarray(eng.u_nodes()))

    def fire(tr):
        x, y, radius = tr.block
        try:
            fb.trigger(x, y, radius)
        except ValueError as e:
            if "live rupture" not in str(e):
                raise
            msg = (
                f"trigger at t = {units.t(tr.time):.6g} at ({x:.6g}, {y:.6g}) not fired: "
                "its disk touches a running rupture"
            )
            notes.append(msg)
            warnings.warn(msg, RuntimeWarning, stacklevel=2)

    # the loop's place goes into checkpoints (as the 1D model's); a resumed run fires
    # the triggers after its place only
    actions = [(tr.time, lambda tr=tr: fire(tr)) for tr in cfg.triggers]
    loop = TargetLoop(cfg, ctl, snap, actions=actions)
    if ctl.resuming:
        snapshots = int(ctl.state["written"])

    with _guard_writes(bar, writer, cfg, lambda: (eng.completed, units.t(eng.time))):
        finished = loop.run(
            eng, cfg, ctl, bar, chunk, lambda: eng.completed, snap,
            lambda state: ctl.save(fb, writer, state),
        )  # fmt: skip
        interrupted = not finished
        bar.close()
        rup = model.ruptures_table(cfg, eng)

        def give_all():
            # the state at the end (the cut, when interrupted: a resumed run drops it)
            if snapshots == 0 or interrupted or cfg.t_end is None:
                snap()
            rows, ru, rs = model.convert_ruptures(units, rup)
            writer.append_rows("ruptures", rows, ru, scales=rs, descriptions=DESCRIPTIONS)
            if cfg.arrivals:
                arr = model.arrivals_table(cfg, eng, rup)
                arr, au, ascales = units.convert_table(arr, times=("t",), xs=("x", "y"))
                writer.append_rows("arrivals", arr, au, csv=False, scales=ascales)

        if writer is None and (snapshots == 0 or interrupted or cfg.t_end is None):
            snapshots += 1
        interrupted = _finish(writer, ctl, fb, loop.state(), give_all, interrupted)
    return RunSummary(
        model=cfg.model,
        out=str(out) if out else None,
        t=float(units.t(eng.time)),
        events=int(eng.completed),
        snapshots=writer.count if writer is not None else snapshots,
        interrupted=interrupted,
        wall_s=time.perf_counter() - wall0,
        units=units.name,
        extra={
            "grid": model.nodes(cfg),
            "ruptures": len(rup),
            "warnings": notes,
            "steps": int(eng.steps),
            "signal": ctl.signal_name() if interrupted else None,
        },
    )


def _speed_args(speed: dict | None) -> dict:
    """The [speed] table as FreeBoundary2D's speed, curvature and speed_diagonal."""
    speed = dict(speed or {})
    out = {"curvature": speed.pop("curvature", None)}
    out["speed_diagonal"] = speed.pop("diagonal", None)
    out["speed"] = speed or None
    return out


class FreeBoundary2DModel(Model):
    name = "free_boundary_2d"
    boundaries = ("free", "periodic")
    domain_keys = ("shape", "spacing", "boundary")
    domain_required = ("shape", "spacing")
    size_key = "domain.shape"
    disorder_keys = ("threshold",)
    correlated_disorder = True
    speed_law = True
    front_shape = True
    coulomb_only = True
    noise_kind = "free_boundary"
    noise_per = "unit area"
    noise_si = "1/(m^2 s)"
    noise_length_power = 2
    events_need_loading = True
    arrivals = True
    initial_kinds = ("uniform", "ramp", "random", "file")
    triggers = True
    trigger_places = ("x", "y", "radius")
    bytes_per_node_key = "fb_bytes_per_node"
    snapshot_bytes_per_node = 8
    summary = "the free boundary problem in the plane (bkwaves.FreeBoundary2D)"

    # --- config --------------------------------------------------------------------------
    def parse_domain(self, d, cfg_value):
        return {
            "shape": _shape(d, 3),
            "spacing": cfg_value(d, "spacing"),
            "boundary": _pair_of(d.get("boundary", "free"), "domain.boundary", self.boundaries),
        }

    def domain_doc(self, cfg):
        return {"shape": list(cfg.shape), "spacing": cfg.spacing, "boundary": list(cfg.boundary)}

    def scale_domain(self, domain, ls):
        return {**domain, "spacing": domain["spacing"] / ls}

    def scale_noise(self, noise, ts, ls, vs):
        noise["rate"] *= ls * ls * ts  # per unit area and time
        return noise

    def physical_lengths(self, cfg):
        return (("domain.spacing", cfg.spacing),)

    def check_keys(self, cfg):
        from ..config import _err

        # (as in 1D: the rate laws are written for the threshold 1)
        if cfg.noise is not None and dict(cfg.disorder).get("threshold") is not None:
            _err("noise", "not implemented with a threshold field ([disorder] threshold)")

    def parse_trigger(self, tr, where, domain):
        """A rupture started at ``time`` on the disk of ``radius`` (default 0) around
        (``x``, ``y``), the place within the grid (a periodic axis: up to n h)."""
        from .. import _validate as V
        from ..config import Trigger, _err, _keys, _value

        spec = V.CONFIG["triggers"]
        _keys(tr, where, ("time", "x", "y", "radius"), ("x", "y"))
        place = []
        for axis, n, b in zip("xy", domain["shape"], domain["boundary"], strict=True):
            z = _value(tr, axis, where, spec[axis])
            h = domain["spacing"]
            hi, close = ((n - 1) * h, "<=") if b == "free" else (n * h, "<")
            if not (0.0 <= z <= hi and (b == "free" or z < hi)):
                _err(
                    f"{where}.{axis}",
                    f"invalid {axis} = {z:.6g}: allowed 0 <= {axis} {close} {hi:.6g} "
                    f"(the grid along {axis}, {b})",
                )
            place.append(float(z))
        radius = _value(tr, "radius", where, spec["radius"], 0.0, hi=1e9)
        time = _value(tr, "time", where, spec["time"], 0.0)
        return Trigger(time=time, block=(*place, float(radius)), kind="rupture")

    def scale_trigger_place(self, block, ls):
        return tuple(z / ls for z in block)

    def trigger_doc(self, block):
        x, y, radius = block
        return {"x": x, "y": y, "radius": radius}

    def _periodic(self, cfg):
        return tuple(b == "periodic" for b in cfg.boundary)

    def threshold(self, cfg):
        """The threshold field, (ny, nx) or a number (None: uniform 1)."""
        spec = dict(cfg.disorder).get("threshold")
        if spec is None:
            return None
        return planar_property(
            cfg, "threshold", spec, self.x(cfg), self.y(cfg), self._periodic(cfg)
        )

    def property_arrays(self, cfg):
        return {"threshold": self.threshold(cfg)}

    def initial_state(self, cfg):
        return planar_initial(cfg, self.x(cfg), self.y(cfg), self._periodic(cfg))

    def check_initial(self, cfg, u, x, key):
        from ..config import _err

        thr = self.threshold(cfg)
        s = np.broadcast_to(1.0 if thr is None else thr, u.shape)
        if np.any(u >= s):
            j, i = np.unravel_index(int(np.argmax(u - s)), u.shape)
            _err(
                key,
                f"the initial state reaches u = {u[j, i]:.6g} >= the threshold {s[j, i]:.6g} "
                f"at (x, y) = ({i * cfg.spacing:.6g}, {j * cfg.spacing:.6g}): the free "
                "boundary model needs u < threshold everywhere (its field is the stress of "
                'stuck blocks; model = "lattice" runs blocks over the threshold)',
            )

    def check(self, cfg):
        from ..config import _err
        from ..free_boundary import MAX_GRID_X

        check_continuum(cfg)
        h, v = cfg.spacing, cfg.params.v
        if not v * h <= 1.0:
            # (the field rises by at most 1 while a front, at a speed >= 1, crosses a cell)
            _err(
                "domain.spacing",
                f"invalid spacing h = {h:.6g} (x' units) at v = {v:.6g}: allowed v h <= 1, "
                f"h <= {1.0 / v:.6g} (the slow field may rise by at most 1 while a front "
                "crosses a cell)",
            )
        if not self.span(cfg) <= MAX_GRID_X:
            _err(
                "domain.spacing",
                f"the grid spans {self.span(cfg):.6g} x' units: allowed at most {MAX_GRID_X:g}",
            )
        # (the initial state against the threshold: checked when it is built)
        self.check_initial(cfg, self.initial_state(cfg), None, _initial_key(cfg))

    # --- grid ----------------------------------------------------------------------------
    def x(self, cfg):
        return np.arange(cfg.shape[0]) * cfg.spacing

    def y(self, cfg):
        return np.arange(cfg.shape[1]) * cfg.spacing

    def nodes(self, cfg):
        return cfg.shape[0] * cfg.shape[1]

    def size_text(self, cfg):
        nx, ny = cfg.shape
        return f"[{nx}, {ny}] ({nx * ny} nodes)"

    def span(self, cfg):
        return max(cfg.shape) * cfg.spacing

    def physical_span(self, cfg):
        return (max(cfg.shape) - 1) * cfg.spacing

    def noise_size(self, cfg):
        nx, ny = cfg.shape
        return nx * ny * cfg.spacing**2

    def check_noise_events(self, cfg, what):
        from ..limits import check_noise_events

        check_noise_events(what, self.noise_size(cfg), self.span(cfg), cfg.noise)

    def grid_attrs(self, cfg):
        return {
            "shape": list(cfg.shape),
            "grid_spacing": cfg.spacing,
            "boundary": " x ".join(cfg.boundary),
        }

    # --- run -----------------------------------------------------------------------------
    def build(self, cfg):
        from ..free_boundary_2d import FreeBoundary2D

        return FreeBoundary2D(
            cfg.params,
            cfg.shape,
            cfg.spacing,
            self.initial_state(cfg),
            cfg.boundary,
            record_arrivals=cfg.arrivals,
            noise=cfg.noise,
            seed=cfg.seed,
            **_speed_args(cfg.speed),
            threshold=self.threshold(cfg),
        )

    def run(self, cfg, out, progress, overwrite, flush_every, chunk, ctl):
        return _run_free_boundary_2d(self, cfg, out, progress, overwrite, flush_every, chunk, ctl)

    def ruptures_table(self, cfg, eng):
        """The engine's rupture catalog (dimensionless) with each moment's magnitude."""
        import pandas as pd

        from ..stats import moment_magnitude

        cat = eng.ruptures()
        df = pd.DataFrame({k: cat[k] for k in RUPTURE_COLUMNS if k != "magnitude"})
        df.insert(
            df.columns.get_loc("moment") + 1,
            "magnitude",
            moment_magnitude(df["moment"].to_numpy(dtype=float)),
        )
        return df

    def convert_ruptures(self, units, rup):
        """The ruptures table in the output units (moment: slip times an area)."""
        from ._planar import convert_ruptures

        return convert_ruptures(units, rup, "(x')^2", "int (u_+ - u_-) dA")

    def arrivals_table(self, cfg, eng, rup):
        """The arrival time of every node in every complete rupture (rupture, i, j, x, y,
        t), dimensionless."""
        import pandas as pd

        nx = cfg.shape[0]
        parts = []
        for rid in rup.loc[rup["complete"].to_numpy(dtype=bool), "id"]:
            nodes, times = eng.arrivals(int(rid))
            nodes = np.asarray(nodes, dtype=np.int64)
            i, j = nodes % nx, nodes // nx
            parts.append(
                pd.DataFrame(
                    {
                        "rupture": np.full(len(nodes), int(rid)),
                        "i": i,
                        "j": j,
                        "x": i * cfg.spacing,
                        "y": j * cfg.spacing,
                        "t": np.asarray(times, dtype=float),
                    }
                )
            )
        if not parts:
            return pd.DataFrame({k: [] for k in ("rupture", "i", "j", "x", "y", "t")})
        return pd.concat(parts, ignore_index=True)

    # --- cost --------------------------------------------------------------------------
    def work(self, cfg):
        """The 1D free boundary's estimate over the nx ny nodes: under a loading v T each
        node is swept ~10 v T times, ~0.7 v T ruptures start (``bkwaves._cost.fb_work``),
        a node swept at the 1D engine's rate of crossings (fast marching: log of the
        front's length more, not counted)."""
        from .. import _cost
        from ..limits import fb_wall

        u = self.initial_state(cfg)
        thr = self.threshold(cfg)
        gap = float(np.min(1.0 if thr is None else thr) - np.max(u))
        work = _cost.fb_work(self.nodes(cfg), cfg.params.v, cfg.t_end, cfg.max_events, gap)
        return work, work.crossings, fb_wall


def _initial_key(cfg) -> str:
    return {
        "uniform": "initial.value",
        "ramp": "initial.start/end",
        "random": "initial.mean/amplitude",
        "file": "initial.path",
    }[cfg.initial.kind]


MODEL = FreeBoundary2DModel()
