"""The lattice model (``model = "lattice"``): bkwaves.Lattice run from a config.

Its entry in the model registry (``bkwaves._models``): the chain's engine on a grid
(the chain model's run with the lattice's hooks). TOML:

- [domain] ``shape = [nx, ny]`` (blocks along x and y), ``dy`` (the spacing across,
  dimensionless sqrt(k_p/k_y); default params.dx), ``boundary``: one of free, fixed,
  periodic for both axes, or ``[along x, along y]``;
- [initial] uniform, ramp (along x), random (a smooth random field in the plane,
  ``bkwaves.disorder.smooth_field``, its correlation length in units of x), file (.npy
  of shape (ny, nx), or nx ny values row after row); ``velocity`` as the chain's;
- [disorder] threshold, mass, loader: a number, nx ny values (row after row), a drawn
  {distribution, mean, spread} per block or a smooth random field {mean, amplitude,
  correlation_length}; ``coupling_x`` and ``coupling_y``, the per-bond springs along x
  and along y in units of the uniform ones (``bk.Lattice(coupling=(k_x, k_y))``), in the
  same forms per bond (``bonds``: ny rows of the bonds of a row, the bonds of a column
  times nx), each >= 0 (a zero bond cuts the lattice);
- [[triggers]] at ``block = [i, j]``, on a line ``line = [[i0, j0], [i1, j1]]`` or a
  disc ``disc = [[i, j], radius]`` (``bk.Lattice.blocks``); [noise] per block as the
  chain's; [run] as the chain's;
- [output] ``arrivals = true``: the arrivals table, the first slip time of every block
  in every rupture (event, rupture, i, j, x, y, t; ``rupture`` is the ruptures table's
  ``id``).

Outputs: snapshots u, u_t, sliding with dims (t, y, x); the events table with each
event's hypocentre (i, j, x, y), area and moment (int slip dA); the slips table with
i, j, x, y; the ruptures table (``bkwaves._lattice_ruptures``: the events split into
the slip of single nucleations, with hypocentre, area, moment, duration and perimeter),
which `bkwaves stats` reads, as the planar free boundary model's.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..chain import BOUNDARIES
from .chain import ChainModel, check_step

#: The per-block properties a lattice takes.
PROPERTIES = ("threshold", "mass", "loader")
#: Its per-bond springs along x and along y ([disorder] keys; ``bk.Lattice``'s
#: ``coupling = (k_x, k_y)``).
BONDS = ("coupling_x", "coupling_y")
#: Bonds of a line of n blocks beyond n: free sides n - 1, walls n + 1, periodic n.
_EXTRA_BONDS = {"free": -1, "fixed": 1, "periodic": 0}


def bonds(shape, boundary) -> dict:
    """The shapes of the per-bond springs of a lattice of ``shape`` = (nx, ny) blocks
    with ``boundary`` = (along x, along y): {"coupling_x": (ny, bonds of a row),
    "coupling_y": (bonds of a column, nx)}, as ``bk.Lattice(coupling=...)`` takes them."""
    nx, ny = shape
    return {
        "coupling_x": (ny, nx + _EXTRA_BONDS[boundary[0]]),
        "coupling_y": (ny + _EXTRA_BONDS[boundary[1]], nx),
    }


def _pair_of(value, where: str, allowed: tuple[str, ...]) -> tuple[str, str]:
    from .. import _validate as V
    from ..config import _err

    pair = [value, value] if isinstance(value, str) else value
    ok = isinstance(pair, list) and len(pair) == 2 and all(isinstance(b, str) for b in pair)
    if not ok or any(b not in allowed for b in pair):
        names = ", ".join(allowed)
        _err(where, f"expected one of {names}, or [along x, along y] of them; got {V._show(value)}")
    return tuple(pair)


def _shape(d: dict, lo: int) -> tuple[int, int]:
    from .. import _validate as V
    from ..config import _err, _value

    raw = d["shape"]
    if not (isinstance(raw, list) and len(raw) == 2):
        _err("domain.shape", f"expected [nx, ny], two integers >= {lo}; got {V._show(raw)}")
    spec = V.CONFIG["domain"]["shape"]
    nx, ny = (
        _value({f"shape[{k}]": n}, f"shape[{k}]", "domain", spec, lo=lo) for k, n in enumerate(raw)
    )
    return int(nx), int(ny)


def planar_field(cfg, corr: float, seed, x, y, periodic) -> np.ndarray:
    """A smooth random field on the planar grid (x, y), shaped (ny, nx)
    (``bkwaves.disorder.smooth_field``: zero mean, largest |value| 1, Gaussian
    correlation of length ``corr`` in the plane; periodic along a periodic axis)."""
    from ..disorder import smooth_field

    hx = float(x[1] - x[0]) if len(x) > 1 else 1.0
    hy = float(y[1] - y[0]) if len(y) > 1 else hx
    return smooth_field(
        (len(y), len(x)), (hy, hx), corr, periodic=(periodic[1], periodic[0]), seed=seed
    )


def planar_initial(cfg, x, y, periodic) -> np.ndarray:
    """The initial u of a planar model on the nodes (x, y) (shaped (ny, nx)):
    uniform, ramp along x, a smooth random field, or a file (an (ny, nx) .npy array, or
    nx ny values row after row)."""
    from ..config import U_LIMIT, _err, _read_initial_file

    nx, ny = len(x), len(y)
    s = cfg.initial
    if s.kind == "uniform":
        u = np.full((ny, nx), s.value)
    elif s.kind == "ramp":
        span = x[-1] - x[0] if nx > 1 else 1.0
        u = np.broadcast_to(s.start + (s.end - s.start) * (x - x[0]) / span, (ny, nx)).copy()
    elif s.kind == "random":
        u = s.mean + s.amplitude * planar_field(cfg, s.correlation_length, cfg.seed, x, y, periodic)
    else:
        path = Path(s.path)
        if path.suffix == ".npy":
            try:
                shape = np.load(path, mmap_mode="r", allow_pickle=False).shape
            except (OSError, ValueError):
                shape = None  # (the reader below says why)
            if shape is not None and len(shape) == 2 and shape != (ny, nx):
                _err(
                    "initial.path",
                    f"{path} holds an array of shape {shape}; expected (ny, nx) = {(ny, nx)}",
                )
        u = _read_initial_file(path, nx * ny).reshape(ny, nx)
    key = {
        "uniform": "initial.value",
        "ramp": "initial.start/end",
        "random": "initial.mean/amplitude",
        "file": "initial.path",
    }[s.kind]
    if not np.all(np.isfinite(u)) or np.max(np.abs(u)) > U_LIMIT:
        _err(key, f"the initial state has values outside |u| <= {U_LIMIT:g} (or not finite)")
    return u


def planar_property(cfg, k: str, spec, x, y, periodic, what: str = "nx ny"):
    """One [disorder] property on a planar grid of nodes (or bonds) at (x, y): a scalar
    or a (len(y), len(x)) array (``what``: the count in words, for errors)."""
    from .._core import ParameterError
    from ..config import _err
    from ..disorder import draw, property_seed

    nx, ny = len(x), len(y)
    if nx * ny == 0:  # (no bonds: a line of one block along a free axis)
        return None
    if isinstance(spec, dict) and "correlation_length" in spec:
        seed = property_seed(cfg.seed, k)
        field = planar_field(cfg, spec["correlation_length"], seed, x, y, periodic)
        return spec["mean"] + spec["amplitude"] * field
    if isinstance(spec, dict):
        try:
            a = draw(
                spec["distribution"],
                nx * ny,
                mean=spec["mean"],
                spread=spec["spread"],
                seed=property_seed(cfg.seed, k),
            )
        except ParameterError as e:
            _err(f"disorder.{k}", str(e))
        return np.asarray(a).reshape(ny, nx)
    if isinstance(spec, tuple):
        if len(spec) != nx * ny:
            _err(
                f"disorder.{k}", f"{len(spec)} values; expected {what} = {nx * ny} (row after row)"
            )
        return np.array(spec).reshape(ny, nx)
    return float(spec)


class LatticeModel(ChainModel):
    name = "lattice"
    boundaries = BOUNDARIES
    domain_keys = ("shape", "dy", "boundary")
    domain_required = ("shape",)
    size_key = "domain.shape"
    disorder_keys = (*PROPERTIES, *BONDS)
    disorder_zero_ok = BONDS
    correlated_disorder = True
    initial_kinds = ("uniform", "ramp", "random", "file")
    arrivals = True
    summary = "a lattice of blocks in the plane (bkwaves.Lattice)"

    # --- config --------------------------------------------------------------------------
    def parse_domain(self, d, cfg_value):
        shape = _shape(d, 1)
        dy = cfg_value(d, "dy", None)
        boundary = _pair_of(d.get("boundary", "free"), "domain.boundary", self.boundaries)
        return {"shape": shape, "dy": dy, "boundary": boundary}

    def domain_doc(self, cfg):
        doc = {"shape": list(cfg.shape), "boundary": list(cfg.boundary)}
        if cfg.dy is not None:
            doc["dy"] = cfg.dy
        return doc

    def domain_nodes(self, domain):
        nx, ny = domain["shape"]
        return nx * ny

    trigger_places = ("block", "line", "disc")

    def trigger_block(self, tr, where, domain):
        """A block ``[i, j]``, a line ``[[i0, j0], [i1, j1]]`` or a disc ``[[i, j],
        radius]`` (radius in units of x, as dx: ``bk.Lattice.blocks``), as (i, j),
        ("line", (i0, j0), (i1, j1)) or ("disc", (i, j), radius)."""
        from .. import _validate as V
        from ..config import _err

        nx, ny = domain["shape"]
        given = [k for k in self.trigger_places if k in tr]
        if len(given) != 1:
            _err(
                where,
                "give one of block = [i, j], line = [[i0, j0], [i1, j1]] or "
                "disc = [[i, j], radius]",
            )
        (place,) = given
        raw = tr[place]

        def block(b, key):
            ok = isinstance(b, list) and len(b) == 2
            ok = ok and all(V._is_int(k) and not isinstance(k, bool) for k in b)
            if not ok or not (0 <= b[0] < nx and 0 <= b[1] < ny):
                _err(
                    f"{where}.{key}",
                    f"invalid block = {V._show(b)}: allowed [i, j] with 0 <= i < {nx}, "
                    f"0 <= j < {ny}",
                )
            return (int(b[0]), int(b[1]))

        if place == "block":
            return block(raw, "block")
        if not (isinstance(raw, list) and len(raw) == 2):
            want = "[[i0, j0], [i1, j1]]" if place == "line" else "[[i, j], radius]"
            _err(f"{where}.{place}", f"expected {want}, got {V._show(raw)}")
        if place == "line":
            return ("line", block(raw[0], "line[0]"), block(raw[1], "line[1]"))
        r = raw[1]
        if isinstance(r, bool) or not isinstance(r, int | float) or not 0 <= r <= 1e9:
            _err(
                f"{where}.disc[1]",
                f"invalid radius = {V._show(r)}: allowed 0 <= radius <= 1e9 (units of x, as dx)",
            )
        return ("disc", block(raw[0], "disc[0]"), float(r))

    def trigger_doc(self, block) -> dict:
        if isinstance(block, tuple) and block and block[0] == "line":
            return {"line": [list(block[1]), list(block[2])]}
        if isinstance(block, tuple) and block and block[0] == "disc":
            return {"disc": [list(block[1]), block[2]]}
        return {"block": list(block)}

    @staticmethod
    def region(block):
        """A trigger's place as bk.Lattice.kick takes it."""
        if isinstance(block[0], str):
            kind, *spec = block
            return {kind: tuple(spec)}
        return block

    def _dy(self, cfg) -> float:
        return cfg.params.dx if cfg.dy is None else cfg.dy

    def _periodic(self, cfg) -> tuple[bool, bool]:
        return tuple(b == "periodic" for b in cfg.boundary)

    def property_arrays(self, cfg):
        """{property: scalar, (ny, nx) array or None}; the bonds (``BONDS``) shaped as
        ``bonds`` says (a smooth field on the bonds' grid: spaced dx along x and dy
        along y, as the blocks)."""
        out = dict.fromkeys((*PROPERTIES, *BONDS))
        x, y = self.x(cfg), self.y(cfg)
        shapes = bonds(cfg.shape, cfg.boundary)
        words = {
            "coupling_x": "ny x (bonds of a row: nx - 1 free, nx + 1 fixed, nx periodic)",
            "coupling_y": "(bonds of a column: ny - 1 free, ny + 1 fixed, ny periodic) x nx",
        }
        for k, spec in cfg.disorder:
            if k in BONDS:
                rows, cols = shapes[k]
                bx = np.arange(cols) * cfg.params.dx
                by = np.arange(rows) * self._dy(cfg)
                what = f"{words[k]} = {rows} x {cols}"
                out[k] = planar_property(cfg, k, spec, bx, by, self._periodic(cfg), what)
            else:
                out[k] = planar_property(cfg, k, spec, x, y, self._periodic(cfg))
        return out

    def _lattice_properties(self, cfg) -> dict:
        """``property_arrays`` as ``bk.Lattice`` takes them: the bonds as coupling =
        (k_x, k_y) (1: uniform)."""
        props = self.property_arrays(cfg)
        kx, ky = (props.pop(k) for k in BONDS)
        props["coupling"] = (
            None
            if kx is None and ky is None
            else (
                1.0 if kx is None else kx,
                1.0 if ky is None else ky,
            )
        )
        return props

    def initial_state(self, cfg):
        return planar_initial(cfg, self.x(cfg), self.y(cfg), self._periodic(cfg))

    def check(self, cfg):
        dx, dy = cfg.params.dx, self._dy(cfg)
        check_step(
            cfg, min(dx, dy), 4.0 / dx / dx + 4.0 / dy / dy, "1 + 4/dx^2 + 4/dy^2", "the lattice"
        )
        if cfg.initial.kind == "file":
            # the file's shape and values when the config is loaded, not at the run's start
            # (as the planar free boundary model's)
            self.initial_state(cfg)

    # --- grid ----------------------------------------------------------------------------
    def x(self, cfg):
        return np.arange(cfg.shape[0]) * cfg.params.dx

    def y(self, cfg):
        return np.arange(cfg.shape[1]) * self._dy(cfg)

    def nodes(self, cfg):
        return cfg.shape[0] * cfg.shape[1]

    def size_text(self, cfg):
        nx, ny = cfg.shape
        return f"[{nx}, {ny}] ({nx * ny} blocks)"

    def span(self, cfg):
        return max(cfg.shape[0] * cfg.params.dx, cfg.shape[1] * self._dy(cfg))

    def physical_span(self, cfg):
        return max((cfg.shape[0] - 1) * cfg.params.dx, (cfg.shape[1] - 1) * self._dy(cfg))

    def grid_attrs(self, cfg):
        return {"shape": list(cfg.shape), "dy": self._dy(cfg), "boundary": " x ".join(cfg.boundary)}

    # --- run hooks -------------------------------------------------------------------------
    def engine_class(self):
        from ..lattice import Lattice

        return Lattice

    def build(self, cfg):
        from ..lattice import Lattice

        p = cfg.params
        la = Lattice(
            cfg.shape,
            p,
            u0=self.initial_state(cfg),
            u_t0=None if cfg.initial.velocity == 0.0 else p.v - cfg.initial.velocity,
            dy=cfg.dy,
            boundary=cfg.boundary,
            seed=cfg.seed,
            noise=cfg.noise,
            **cfg.chain_integration(),
            **self._lattice_properties(cfg),
        )
        for tr in cfg.triggers:
            if tr.kind == "kick":
                la.kick(self.region(tr.block), -tr.velocity, tr.time)
            else:
                la.release(self.region(tr.block), tr.time)
        return la

    def default_max_event_duration(self, cfg):
        from ..lattice import default_max_event_duration

        return default_max_event_duration(cfg.shape, cfg.params.dx, self._dy(cfg))

    def event_columns(self, cfg, cat):
        from ..lattice import _planar_catalog

        dx = cfg.params.dx
        return _planar_catalog(
            cat, cfg.shape[0], dx, self._dy(cfg), moment_scale=dx * self._dy(cfg)
        )

    def convert_events(self, units, cat):
        from ..lattice import PLANAR_MOMENT
        from ..runner import _SCALES

        cat, cu, cs = units.convert_table(
            cat,
            times=("t_start", "t_end", "duration"),
            xs=("hypocentre_x", "hypocentre_y"),
            moments=("moment",),
        )
        if units.si:  # int slip dA: slip (m) times an area (m^2)
            cat["moment"] = units.x(cat["moment"].to_numpy())
            cat["area"] = units.x(units.x(cat["area"].to_numpy()))
            cu.update(moment="m3", area="m2")
        else:
            cu["area"] = "1"
            cs["area"] = f"(x')^2: blocks slipped x dx dy, {_SCALES['x']}"
            cs["moment"] = f"{PLANAR_MOMENT}; slip in units of (f_r - f_s)/k_p, lengths x'"
        return cat, cu, cs

    def event_descriptions(self):
        from ..lattice import PLANAR_MOMENT

        return {
            "moment": PLANAR_MOMENT,
            "area": "the area that slipped: the event's blocks times dx dy",
            "hypocentre_i": "column of the block that slipped first (x = i dx)",
            "hypocentre_j": "row of the block that slipped first (y = j dy)",
        }

    def slip_columns(self, cfg, sl):
        from ..lattice import _planar_slips

        sl.insert(2, "x", 0.0)
        return _planar_slips(sl, cfg.shape[0], cfg.params.dx, self._dy(cfg))

    def ruptures(self, cfg, eng):
        """The ruptures table (``bkwaves._lattice_ruptures``: the events split into
        the slip of single nucleations), dimensionless, from the whole record of slips."""
        from .._lattice_ruptures import lattice_ruptures
        from ..runner import _frame

        nx, ny = cfg.shape
        sl = _frame(eng.slips())
        return lattice_ruptures(sl, nx, ny, cfg.params.dx, self._dy(cfg), cfg.boundary)

    def write_ruptures(self, writer, units, rup) -> None:
        """The ruptures table in the output units (area, moment, perimeter as the planar
        free boundary model's: SI m^2, m^3, m)."""
        from .._lattice_ruptures import DESCRIPTIONS
        from ..runner import _described
        from ._planar import convert_ruptures

        if writer is None or rup is None:
            return
        rows, ru, rs = convert_ruptures(units, rup, "(x')^2: blocks slipped x dx dy", "int slip dA")
        described = {**_described(rows), **DESCRIPTIONS}
        writer.append_rows("ruptures", rows, ru, scales=rs, descriptions=described)

    def arrivals_table(self, cfg, eng):
        """The first slip time of every block in every rupture (event, rupture, i, j, x, y,
        t; ``rupture`` is the ruptures table's ``id``), dimensionless, from the engine's
        whole record of slips."""
        import pandas as pd

        from .._lattice_ruptures import slip_ruptures
        from ..runner import _frame

        cols = ("event", "rupture", "i", "j", "x", "y", "t")
        sl = _frame(eng.slips())
        if not len(sl):
            return pd.DataFrame({k: [] for k in cols})
        sl = sl.assign(rupture=slip_ruptures(sl, *cfg.shape, cfg.boundary))
        first = sl.groupby(["event", "rupture", "block"], as_index=False)["t_start"].min()
        nx = cfg.shape[0]
        i, j = first["block"] % nx, first["block"] // nx
        return pd.DataFrame(
            {
                "event": first["event"],
                "rupture": first["rupture"],
                "i": i,
                "j": j,
                "x": i * cfg.params.dx,
                "y": j * self._dy(cfg),
                "t": first["t_start"],
            }
        )[list(cols)]

    # --- cost --------------------------------------------------------------------------
    @staticmethod
    def local_events(cfg, run=None) -> bool:
        """Whether a run of ``cfg`` uses local events (``run.events``; not given: where
        they apply, rk4 at a fixed step and no onset sub-steps, as ``bk.Lattice``)."""
        if cfg.events is not None:
            return cfg.events == "local"
        steps = cfg.chain_integration()
        fixed_rk4 = steps["integrator"] == "rk4" and steps["step_tolerance"] is None
        return fixed_rk4 and (run is None or run.onset_per_slip == 0.0)

    def work(self, cfg):
        """The chain's estimate of one row of nx blocks, scaled to ny rows: every block of
        a rupture slides for about w/c as in a chain (a planar front is the chain at dx,
        docs/lattice.md): ny times the row's sliding block-time. The event location (each
        slip and stick redoes a step over every block sliding then) is ny^2 times the
        row's (ny times the switches, each over ny times the sliding blocks) and adds ny
        times the row's located steps. The row's two parts are told apart by their
        dependence on the step h: block-steps = S/h + R (R, the redone ones, does not
        depend on h). With local events (``events``; the lattice's default where they
        apply) a step with switches passes twice over the sliding blocks and redoes a few
        blocks around each switch: ny (2 S/h + R) (measured 0.97-1.5 times the engine's
        count on ruptures of 24 x 18 to 100 x 100 blocks), and the components' sub-steps
        count as steps: about one per switch (two per slip)."""
        from .. import _cost
        from ..config import InitialSpec
        from ..limits import _chain_run, lattice_wall

        nx, ny = cfg.shape
        ini = cfg.initial
        if ini.kind == "file":  # (a row of the file: its largest and its mean)
            try:
                u = self.initial_state(cfg)
                ini = InitialSpec("ramp", start=float(np.mean(u)), end=float(np.max(u)))
            except Exception:  # noqa: BLE001 - an estimate: the run says what is wrong
                ini = InitialSpec("uniform", value=1.0)
        row = dataclasses.replace(
            cfg,
            model="chain",
            blocks=nx,
            shape=(),
            dy=None,
            boundary=cfg.boundary[0],
            initial=ini,
            disorder=(),
        )
        run = _chain_run(row, cfg.t_end, cfg.max_events)
        work = _cost.chain_work(run)
        half = _cost.chain_work(dataclasses.replace(run, h=2.0 * run.h))
        sliding = 2.0 * (work.block_steps - half.block_steps)  # S/h
        redone = max(work.block_steps - sliding, 0.0)  # R
        plain = 2.0 * (work.steps - half.steps)  # T_active/h
        located = max(work.steps - plain, 0.0)
        if self.local_events(cfg, run):
            work.block_steps = ny * (2.0 * sliding + redone)
            work.notes.append("local events: the switches' neighbourhoods redone")
        else:
            work.block_steps = ny * sliding + ny * ny * redone
        work.steps = plain + ny * located
        work.slips *= ny
        if work.onset_block_steps:
            # every row's slips have their onsets (the row's count was per row), at
            # 0.58-0.74x the chain's per slip while a rupture runs (the plane's patch is
            # split into groups of one stiffness class, each on its own sub-steps); the
            # plane's healing after it (hundreds of blocks near rest at once) costs
            # about 2x that per block that sticks, not counted (docs/lattice.md,
            # "Velocity weakening on the lattice")
            work.onset_block_steps *= ny * LATTICE_ONSET_GAIN
            work.notes = [x for x in work.notes if "onsets' sub-steps" not in x]
            work.notes.append(
                f"~{work.onset_block_steps:.2g} block-steps in the onsets' sub-steps, "
                "at least: the healing after a rupture adds about 2x that per block that "
                "sticks (docs/lattice.md)"
            )
        if self.local_events(cfg, run):
            work.steps += 2.0 * work.slips
        work.notes[0] = f"~{work.block_steps:.2g} block-steps in ~{work.steps:.2g} steps"
        return work, work.block_steps, lattice_wall


#: The lattice's onset block-steps per slip over the chain's (``limits.onset_substeps``):
#: 0.58, 0.67 and 0.74 on ruptures of 24 x 16, 34 x 23 and 48 x 32 blocks at v_f = 1e-4
#: (dx = 0.1, gamma = 0.3, step 0.05) while the rupture runs (the onsets' patch split
#: into groups of one stiffness class, each on its own sub-steps, taking the blocks that
#: will be stiff in a step at its start, a redo up to an event seeded by the integration
#: it cuts short; the chain's per-slip count was measured when a patch took the
#: sub-steps of its stiffest block; docs/lattice_vw_cost.json); the healing after it
#: costs about 2x that per block that sticks (docs/lattice.md, "Velocity weakening on
#: the lattice").
LATTICE_ONSET_GAIN = 0.66

MODEL = LatticeModel()
