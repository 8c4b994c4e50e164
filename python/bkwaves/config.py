"""Run configurations: one TOML schema for chain and free-boundary runs.

Every key is checked when the file is read: unknown keys, wrong types and out-of-range
values raise :class:`bkwaves.ParameterError` with the key's path (``initial.kind``) and
the allowed values. See ``examples/`` for one file per use case.

Schema (all sections optional except those marked)::

    model = "chain" | "free_boundary"          # required
    seed = 0                                   # for random initial states
    title = "..."                              # free text

    [params]    gamma, v, dx, beta              # dimensionless  (exactly one of
                (beta default inf: no backward slip, the paper's model; beta = 5.0:
                 backward slip at phi <= -11; [physical] sets beta = f_s/(f_r - f_s))
    [physical]  mass, k_c, k_p, f_static, f_kinetic, alpha, V, spacing   # these two)
                or  preset = "bristol_board" with V

    [friction]  law = "coulomb" (default; the laws of bk.friction.LAWS) and the law's
                parameters (dimensionless; gamma and beta here or in [params], not both)

    [disorder]  (chain only) threshold, mass, loader, coupling: each a number, an array
                (one per block; coupling one per bond: n - 1 free, n + 1 fixed, n
                periodic) or {distribution = "uniform" | "normal" | "lognormal", mean,
                spread} drawn with the config's seed (bk.disorder)

    [domain]    blocks (chain) | length + grid (free boundary), boundary

    [initial]   kind = "uniform" (value) | "ramp" (start, end) |
                "random" (mean, amplitude, correlation_length) |
                "bumps" (base, slope, bumps = [{center, width, height}, ...]) |
                "file" (path: .npy or .txt with one value per node)
                velocity = 0.0   (chain only: initial forward speed of every block over
                                  the ground; 0 = all stuck)

    [[triggers]] time, block, kind = "kick" (velocity: forward speed added, default 1) |
                 "release"   (chain only)

    [run]       t_end and/or max_events
    [output]    path, snapshot_every (time) or snapshot_events (every k events),
                units = "native" | "dimensionless"

Units: with [params] everything is dimensionless (the paper's x', t', u). With [physical]
times (t_end, snapshot_every, trigger times) are in seconds, lengths (domain.length, bump
centers and widths, correlation_length) in metres and kick velocities (forward block
speed) in m/s; stresses u stay dimensionless (u = 0: kinetic level, u = 1: static
threshold). A :class:`RunConfig` always holds dimensionless values; outputs go back to
SI unless ``output.units = "dimensionless"``.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import _core
from . import _validate as V
from . import friction as laws
from ._core import ParameterError
from .chain import BOUNDARIES as CHAIN_BOUNDARIES
from .chain import PROPERTIES, TRIGGERS
from .disorder import DISTRIBUTIONS, draw, property_seed
from .params import Params, check_beta

__all__ = ["RunConfig", "load_config", "parse_config", "initial_state"]

MODELS = ("chain", "free_boundary")
BOUNDARIES = {"chain": CHAIN_BOUNDARIES, "free_boundary": ("free", "periodic")}
INITIAL_KINDS = ("uniform", "ramp", "random", "bumps", "file")
TRIGGER_KINDS = TRIGGERS


def _err(path: str, msg: str):
    raise ParameterError(f"{path}: {msg}")


def _table(d: Any, path: str) -> dict:
    if not isinstance(d, dict):
        _err(path, f"expected a table, got {type(d).__name__}")
    return d


def _keys(d: dict, path: str, allowed: tuple[str, ...], required: tuple[str, ...] = ()):
    for k in d:
        if k not in allowed:
            where = f"{path}.{k}" if path else k
            _err(where, f"unknown key; valid keys here: {', '.join(allowed)}")
    for k in required:
        if k not in d:
            where = f"{path}.{k}" if path else k
            _err(where, "missing required key")


def _num(d: dict, key: str, path: str, default=None, **rng) -> float:
    where = f"{path}.{key}" if path else key
    if key not in d:
        if default is None:
            _err(where, "missing required key")
        return default
    x = d[key]
    if isinstance(x, bool) or not isinstance(x, int | float):
        _err(where, f"expected a number, got {x!r}")
    try:
        return V.number(key, x, **rng)
    except ParameterError as e:
        _err(where, str(e))


_NO_BACKWARD = (
    "a backward speed needs backward slip: allowed velocity >= 0 unless params.beta is "
    "finite (the default beta = inf is the paper's model, no backward slip)"
)


def _beta(x) -> float:
    if isinstance(x, bool) or not isinstance(x, int | float):
        _err("params.beta", f"expected a number (or inf), got {x!r}")
    try:
        return check_beta(x)
    except ParameterError as e:
        _err("params.beta", str(e))


def _int(d: dict, key: str, path: str, default=None, lo=None) -> int:
    where = f"{path}.{key}" if path else key
    if key not in d:
        if default is None:
            _err(where, "missing required key")
        return default
    x = d[key]
    if isinstance(x, bool) or not isinstance(x, int):
        _err(where, f"expected an integer, got {x!r}")
    if lo is not None and x < lo:
        _err(where, f"invalid {key} = {x}: allowed {key} >= {lo}")
    return x


def _choice(d: dict, key: str, path: str, choices, default=None) -> str:
    where = f"{path}.{key}" if path else key
    if key not in d:
        if default is None:
            _err(where, f"missing required key; one of: {', '.join(choices)}")
        return default
    x = d[key]
    if x not in choices:
        _err(where, f"invalid value {x!r}; one of: {', '.join(choices)}")
    return x


@dataclass(frozen=True)
class Bump:
    center: float
    width: float
    height: float


@dataclass(frozen=True)
class InitialSpec:
    kind: str
    value: float = 0.0
    start: float = 0.0
    end: float = 0.0
    mean: float = 0.0
    amplitude: float = 0.0
    correlation_length: float = 1.0
    base: float = 0.0
    slope: float = 0.0
    bumps: tuple[Bump, ...] = ()
    path: str = ""
    velocity: float = 0.0


@dataclass(frozen=True)
class Trigger:
    time: float
    block: int
    kind: str
    velocity: float = 0.0


@dataclass(frozen=True)
class RunConfig:
    """A validated run description (frozen)."""

    model: str
    params: Params
    boundary: str
    initial: InitialSpec
    blocks: int = 0
    length: float = 0.0
    grid: int = 0
    triggers: tuple[Trigger, ...] = ()
    t_end: float | None = None
    max_events: int | None = None
    output_path: str | None = None
    snapshot_every: float | None = None
    snapshot_events: int | None = None
    output_units: str = "native"
    seed: int = 0
    title: str = ""
    disorder: tuple = ()
    base_dir: Path | None = field(default=None, compare=False, repr=False)

    @property
    def physical(self) -> bool:
        return self.params.units is not None

    def to_dict(self) -> dict:
        """This config as a document of the TOML schema, in the paper's dimensionless
        units (``input_units = "dimensionless"`` when the config carries an SI
        description in [physical]): ``RunConfig.from_dict(cfg.to_dict()) == cfg``
        exactly. A config changed in code (``dataclasses.replace``) writes what it holds."""
        return _to_doc(self)

    @classmethod
    def from_dict(cls, doc: dict, *, base_dir: Path | None = None) -> RunConfig:
        """Validate a document of the TOML schema (see :meth:`to_dict`)."""
        return parse_config(doc, base_dir=base_dir)

    def x(self) -> np.ndarray:
        """Node positions in dimensionless units (blocks at i*dx for the chain)."""
        if self.model == "chain":
            return np.arange(self.blocks) * self.params.dx
        end = self.length if self.boundary == "free" else self.length * (1 - 1 / self.grid)
        return np.linspace(0.0, end, self.grid)


def _friction(doc: dict) -> tuple[laws.Law, dict]:
    """The [friction] table: the law and its parameters; those that are Params fields
    (gamma, beta) come back separately, to go to Params."""
    t = _table(doc.get("friction", {}), "friction")
    name = _choice(t, "law", "friction", tuple(laws.LAWS), laws.DEFAULT)
    info = laws.LAWS[name]
    _keys(t, "friction", ("law", *(p.name for p in info.params)))
    own, shared = {}, {}
    for k, x in t.items():
        if k == "law":
            continue
        if isinstance(x, bool) or not isinstance(x, int | float):
            _err(f"friction.{k}", f"expected a number, got {x!r}")
        try:
            _core.friction_resolve(name, {k: float(x)}, partial=True)
        except ParameterError as e:
            _err(f"friction.{k}", str(e))
        (shared if k in Params.__dataclass_fields__ else own)[k] = float(x)
    return laws.Law(name, tuple(own.items())), shared


def _params(doc: dict) -> Params:
    has_p, has_phys = "params" in doc, "physical" in doc
    if has_p == has_phys:
        _err("params", "give exactly one of [params] (dimensionless) or [physical] (SI)")
    law, shared = _friction(doc)
    if has_phys and shared:
        k = next(iter(shared))
        _err(f"friction.{k}", "set by [physical] (alpha, f_static, f_kinetic); remove it here")
    if has_p:
        t = _table(doc["params"], "params")
        _keys(t, "params", ("gamma", "v", "dx", "beta"), ("v", "dx"))
        for k in shared:
            if k in t:
                _err(f"friction.{k}", f"given in [params] too; give {k} in one place")
        if "gamma" not in t and "gamma" not in shared:
            _err("params.gamma", "missing required key (or give it in [friction])")
        vals = {k: _num(t, k, "params") for k in t if k != "beta"}
        if "beta" in t:
            vals["beta"] = _beta(t["beta"])
        try:
            return Params(**vals, **shared, friction_law=law if "friction" in doc else None)
        except ParameterError as e:
            _err("params", str(e))
    t = _table(doc["physical"], "physical")
    if "preset" in t:
        _keys(t, "physical", ("preset", "V"), ("preset", "V"))
        _choice(t, "preset", "physical", ("bristol_board",))
        from .presets import bristol_board

        p = bristol_board(V=_num(t, "V", "physical", lo=0.0))
    else:
        names = ("mass", "k_c", "k_p", "f_static", "f_kinetic", "alpha", "V", "spacing")
        _keys(t, "physical", names, names)
        vals = {k: _num(t, k, "physical") for k in names}
        try:
            p = Params.from_physical(**vals)
        except ParameterError as e:
            _err("physical", str(e))
    if "friction" not in doc:
        return p
    try:
        return dataclasses.replace(p, friction_law=law)
    except ParameterError as e:
        _err("friction", str(e))


def _disorder(doc: dict, model: str) -> tuple:
    """The [disorder] table as ((property, spec), ...): spec a float, a tuple of
    floats or a dict {distribution, mean, spread}."""
    if "disorder" not in doc:
        return ()
    if model != "chain":
        _err("disorder", "per-block properties apply to the chain model only")
    t = _table(doc["disorder"], "disorder")
    _keys(t, "disorder", PROPERTIES)
    out = []
    for k, x in t.items():
        q = f"disorder.{k}"
        if isinstance(x, dict):
            _keys(x, q, ("distribution", "mean", "spread"), ("distribution", "spread"))
            spec = {
                "distribution": _choice(x, "distribution", q, tuple(DISTRIBUTIONS)),
                "mean": _num(x, "mean", q, 1.0, lo=0.0, lo_open=True),
                "spread": _num(x, "spread", q, lo=0.0),
            }
            out.append((k, spec))
        elif isinstance(x, list):
            if not all(isinstance(y, int | float) and not isinstance(y, bool) for y in x):
                _err(q, "expected an array of numbers")
            out.append((k, tuple(float(y) for y in x)))
        elif isinstance(x, int | float) and not isinstance(x, bool):
            out.append((k, _num(t, k, "disorder", lo=0.0, lo_open=True)))
        else:
            _err(
                q,
                f"expected a number, an array or a table {{distribution, mean, spread}}, got {x!r}",
            )
    return tuple(out)


def disorder_arrays(cfg: RunConfig) -> dict:
    """The per-block properties of a chain config: {property: scalar, array or None}
    (drawn ones with the config's seed, each property from its own stream)."""
    n = cfg.blocks
    out = dict.fromkeys(PROPERTIES)
    bonds = {"free": n - 1, "fixed": n + 1, "periodic": n}.get(cfg.boundary, n)
    for k, spec in cfg.disorder:
        size = bonds if k == "coupling" else n
        if isinstance(spec, dict):
            try:
                out[k] = draw(
                    spec["distribution"],
                    size,
                    mean=spec["mean"],
                    spread=spec["spread"],
                    seed=property_seed(cfg.seed, k),
                )
            except ParameterError as e:
                _err(f"disorder.{k}", str(e))
        elif isinstance(spec, tuple):
            if len(spec) != size:
                _err(f"disorder.{k}", f"{len(spec)} values; expected {size}")
            out[k] = np.array(spec)
        else:
            out[k] = spec
    return out


def _initial(doc: dict, model: str) -> InitialSpec:
    p = "initial"
    t = _table(doc.get("initial", {"kind": "uniform", "value": 0.0}), p)
    kind = _choice(t, "kind", p, INITIAL_KINDS)
    common = ("kind", "velocity") if model == "chain" else ("kind",)
    velocity = _num(t, "velocity", p, 0.0) if model == "chain" else 0.0
    if kind == "uniform":
        _keys(t, p, (*common, "value"), ("value",))
        return InitialSpec(kind, value=_num(t, "value", p), velocity=velocity)
    if kind == "ramp":
        _keys(t, p, (*common, "start", "end"), ("start", "end"))
        return InitialSpec(
            kind, start=_num(t, "start", p), end=_num(t, "end", p), velocity=velocity
        )
    if kind == "random":
        _keys(t, p, (*common, "mean", "amplitude", "correlation_length"), ("mean", "amplitude"))
        return InitialSpec(
            kind,
            mean=_num(t, "mean", p),
            amplitude=_num(t, "amplitude", p, lo=0.0),
            correlation_length=_num(t, "correlation_length", p, 1.0, lo=0.0, lo_open=True),
            velocity=velocity,
        )
    if kind == "bumps":
        _keys(t, p, (*common, "base", "slope", "bumps"), ("bumps",))
        raw = t["bumps"]
        if not isinstance(raw, list) or not raw:
            _err(f"{p}.bumps", "expected a non-empty array of tables {center, width, height}")
        bumps = []
        for i, b in enumerate(raw):
            q = f"{p}.bumps[{i}]"
            b = _table(b, q)
            _keys(b, q, ("center", "width", "height"), ("center", "width", "height"))
            bumps.append(
                Bump(
                    _num(b, "center", q),
                    _num(b, "width", q, lo=0.0, lo_open=True),
                    _num(b, "height", q),
                )
            )
        return InitialSpec(
            kind,
            base=_num(t, "base", p, 0.0),
            slope=_num(t, "slope", p, 0.0),
            bumps=tuple(bumps),
            velocity=velocity,
        )
    _keys(t, p, (*common, "path"), ("path",))
    path = t["path"]
    if not isinstance(path, str) or not path:
        _err(f"{p}.path", f"expected a file name, got {path!r}")
    return InitialSpec(kind, path=path, velocity=velocity)


def parse_config(doc: dict, *, base_dir: Path | None = None) -> RunConfig:
    """Validate a parsed TOML document and build a :class:`RunConfig`."""
    doc = _table(doc, "(top level)")
    top = (
        "model",
        "seed",
        "title",
        "params",
        "physical",
        "friction",
        "disorder",
        "domain",
        "initial",
        "triggers",
        "run",
        "output",
        "input_units",
    )
    _keys(doc, "", top, ("model",))
    model = _choice(doc, "model", "", MODELS)
    seed = _int(doc, "seed", "", 0, lo=0)
    title = doc.get("title", "")
    if not isinstance(title, str):
        _err("title", "expected a string")
    params = _params(doc)

    d = _table(doc.get("domain", {}), "domain")
    if model == "chain":
        _keys(d, "domain", ("blocks", "boundary"), ("blocks",))
        blocks = _int(d, "blocks", "domain", lo=2)
        length, grid = 0.0, 0
    else:
        _keys(d, "domain", ("length", "grid", "boundary"), ("length", "grid"))
        length = _num(d, "length", "domain", lo=0.0, lo_open=True)
        grid = _int(d, "grid", "domain", lo=4)
        blocks = 0
    boundary = _choice(d, "boundary", "domain", BOUNDARIES[model], "free")

    initial = _initial(doc, model)
    if initial.kind == "file" and base_dir is not None and not Path(initial.path).is_absolute():
        initial = InitialSpec("file", path=str(base_dir / initial.path), velocity=initial.velocity)

    triggers = []
    raw = doc.get("triggers", [])
    if model != "chain" and raw:
        _err("triggers", "triggers apply to the chain model only")
    if not isinstance(raw, list):
        _err("triggers", "expected an array of tables [[triggers]]")
    for i, tr in enumerate(raw):
        q = f"triggers[{i}]"
        tr = _table(tr, q)
        kind = _choice(tr, "kind", q, TRIGGER_KINDS)
        allowed = (
            ("time", "block", "kind", "velocity") if kind == "kick" else ("time", "block", "kind")
        )
        _keys(tr, q, allowed, ("block",))
        block = _int(tr, "block", q, lo=0)
        if block >= blocks:
            _err(f"{q}.block", f"invalid block = {block}: allowed 0 <= block < {blocks}")
        triggers.append(
            Trigger(
                time=_num(tr, "time", q, 0.0, lo=0.0),
                block=block,
                kind=kind,
                velocity=_num(tr, "velocity", q, 1.0) if kind == "kick" else 0.0,
            )
        )
        if triggers[-1].velocity < 0 and not params.backward_slip:
            _err(f"{q}.velocity", _NO_BACKWARD)
    if model == "chain" and initial.velocity < 0 and not params.backward_slip:
        _err("initial.velocity", _NO_BACKWARD)

    r = _table(doc.get("run", {}), "run")
    _keys(r, "run", ("t_end", "max_events"))
    t_end = _num(r, "t_end", "run", lo=0.0, lo_open=True) if "t_end" in r else None
    max_events = _int(r, "max_events", "run", lo=1) if "max_events" in r else None
    if t_end is None and max_events is None:
        _err("run", "give t_end, max_events or both")

    o = _table(doc.get("output", {}), "output")
    _keys(o, "output", ("path", "snapshot_every", "snapshot_events", "units"))
    if "snapshot_every" in o and "snapshot_events" in o:
        _err("output", "give at most one of snapshot_every or snapshot_events")
    out_path = o.get("path")
    if out_path is not None and (not isinstance(out_path, str) or not out_path):
        _err("output.path", f"expected a file name, got {out_path!r}")
    # physical configs: convert times and lengths to the paper's units (unless the
    # document says its values are dimensionless already, as RunConfig.to_dict writes)
    input_units = _choice(
        doc,
        "input_units",
        "",
        ("SI", "dimensionless"),
        "SI" if params.units is not None else "dimensionless",
    )
    if params.units is None and input_units != "dimensionless":
        _err("input_units", "'SI' needs a [physical] table; with [params] values are dimensionless")
    ts = ls = vs = 1.0
    if params.units is not None and input_units == "SI":
        ts, ls, vs = params.units.time_scale, params.units.length_scale, params.units.velocity_scale
        initial = InitialSpec(
            **{
                **initial.__dict__,
                "correlation_length": (
                    initial.correlation_length / ls
                    if initial.kind == "random"
                    else initial.correlation_length
                ),
                "bumps": tuple(Bump(b.center / ls, b.width / ls, b.height) for b in initial.bumps),
            }
        )
        triggers = [Trigger(t.time / ts, t.block, t.kind, t.velocity / vs) for t in triggers]
        length /= ls
        t_end = None if t_end is None else t_end / ts
    snapshot_every = (
        _num(o, "snapshot_every", "output", lo=0.0, lo_open=True) / ts
        if "snapshot_every" in o
        else None
    )
    cfg = RunConfig(
        model=model,
        params=params,
        boundary=boundary,
        initial=initial,
        blocks=blocks,
        length=length,
        grid=grid,
        triggers=tuple(triggers),
        t_end=t_end,
        max_events=max_events,
        output_path=out_path,
        snapshot_every=snapshot_every,
        snapshot_events=(
            _int(o, "snapshot_events", "output", lo=1) if "snapshot_events" in o else None
        ),
        output_units=_choice(o, "units", "output", ("native", "dimensionless"), "native"),
        seed=seed,
        title=title,
        disorder=_disorder(doc, model),
        base_dir=base_dir,
    )
    for k, a in disorder_arrays(cfg).items() if cfg.disorder else ():
        if a is not None:
            a = np.atleast_1d(np.asarray(a, dtype=float))
            bad = np.flatnonzero(~(np.isfinite(a) & (a > 0)))
            if bad.size:
                i = int(bad[0])
                _err(f"disorder.{k}[{i}]", f"invalid value {a[i]}: allowed {k} > 0")
    return cfg


def _to_doc(cfg: RunConfig) -> dict:
    p = cfg.params
    doc: dict = {"model": cfg.model, "seed": cfg.seed}
    if cfg.title:
        doc["title"] = cfg.title
    if p.units is not None:
        doc["input_units"] = "dimensionless"
        doc["physical"] = dict(p.units.__dict__)
    else:
        doc["params"] = {k: v for k, v in p.to_dict().items() if k not in ("units", "friction")}
    if p.friction_law is not None:
        doc["friction"] = {"law": p.friction_law.name, **dict(p.friction_law.params)}
    if cfg.disorder:
        doc["disorder"] = {k: list(x) if isinstance(x, tuple) else x for k, x in cfg.disorder}
    if cfg.model == "chain":
        doc["domain"] = {"blocks": cfg.blocks, "boundary": cfg.boundary}
    else:
        doc["domain"] = {"length": cfg.length, "grid": cfg.grid, "boundary": cfg.boundary}
    s = cfg.initial
    ini: dict = {"kind": s.kind}
    if s.kind == "uniform":
        ini["value"] = s.value
    elif s.kind == "ramp":
        ini.update(start=s.start, end=s.end)
    elif s.kind == "random":
        ini.update(mean=s.mean, amplitude=s.amplitude, correlation_length=s.correlation_length)
    elif s.kind == "bumps":
        ini.update(
            base=s.base,
            slope=s.slope,
            bumps=[{"center": b.center, "width": b.width, "height": b.height} for b in s.bumps],
        )
    else:
        ini["path"] = s.path
    if cfg.model == "chain":
        ini["velocity"] = s.velocity
    doc["initial"] = ini
    if cfg.triggers:
        doc["triggers"] = [
            {"time": t.time, "block": t.block, "kind": t.kind}
            | ({"velocity": t.velocity} if t.kind == "kick" else {})
            for t in cfg.triggers
        ]
    run = {}
    if cfg.t_end is not None:
        run["t_end"] = cfg.t_end
    if cfg.max_events is not None:
        run["max_events"] = cfg.max_events
    doc["run"] = run
    out: dict = {"units": cfg.output_units}
    if cfg.output_path is not None:
        out["path"] = cfg.output_path
    if cfg.snapshot_every is not None:
        out["snapshot_every"] = cfg.snapshot_every
    if cfg.snapshot_events is not None:
        out["snapshot_events"] = cfg.snapshot_events
    doc["output"] = out
    return doc


def load_config(path) -> RunConfig:
    """Read and validate a TOML run configuration."""
    path = Path(path)
    try:
        doc = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise ParameterError(f"config file not found: {path}") from None
    except tomllib.TOMLDecodeError as e:
        raise ParameterError(f"{path}: not valid TOML: {e}") from None
    return parse_config(doc, base_dir=path.parent)


def _smooth_random(x: np.ndarray, corr: float, rng: np.random.Generator, periodic: bool):
    """Zero-mean, unit-max-amplitude Gaussian random field with a Gaussian correlation of
    length ``corr``, made by filtering white noise in Fourier space."""
    n = len(x)
    span = (x[-1] - x[0]) if n > 1 else 1.0
    pad = n if periodic else n + int(math.ceil(6 * corr / max(span / max(n - 1, 1), 1e-300)))
    h = span / max(n - 1, 1)
    noise = rng.standard_normal(pad)
    k = 2 * np.pi * np.fft.rfftfreq(pad, d=h)
    field_ = np.fft.irfft(np.fft.rfft(noise) * np.exp(-0.25 * (k * corr) ** 2), n=pad)[:n]
    field_ -= field_.mean()
    m = np.max(np.abs(field_))
    return field_ / m if m > 0 else field_


def initial_state(cfg: RunConfig) -> np.ndarray:
    """The initial u at the nodes ``cfg.x()`` (dimensionless)."""
    x = cfg.x()
    s = cfg.initial
    if s.kind == "uniform":
        u = np.full(len(x), s.value)
    elif s.kind == "ramp":
        span = x[-1] - x[0] if len(x) > 1 else 1.0
        u = s.start + (s.end - s.start) * (x - x[0]) / span
    elif s.kind == "random":
        rng = np.random.default_rng(cfg.seed)
        u = s.mean + s.amplitude * _smooth_random(
            x, s.correlation_length, rng, cfg.boundary == "periodic"
        )
    elif s.kind == "bumps":
        u = s.base + s.slope * x
        for b in s.bumps:
            u = u + b.height * np.exp(-0.5 * ((x - b.center) / b.width) ** 2)
    else:
        p = Path(s.path)
        try:
            u = np.load(p) if p.suffix == ".npy" else np.loadtxt(p)
        except OSError as e:
            raise ParameterError(f"initial.path: cannot read {p}: {e}") from None
        u = np.asarray(u, dtype=float).ravel()
        if len(u) != len(x):
            _err("initial.path", f"{p} has {len(u)} values; the domain has {len(x)} nodes")
    if not np.all(np.isfinite(u)):
        _err("initial", "the initial state has non-finite values")
    return u
