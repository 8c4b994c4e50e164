"""The one validation layer of the package: parameter tables (name, type, allowed range,
meaning) and the checks built on them. The TOML config loader, :class:`bkwaves.Params`,
:class:`bkwaves.Chain`, :class:`bkwaves.FreeBoundary` and the public functions all check
their inputs here, before any work, and every failure is a
:class:`bkwaves.ParameterError` whose message names the parameter the user wrote (the
config key path, e.g. ``run.t_end``, or the argument name), its value and what is allowed.

Types are strict: a string or bytes is never read as a number, a bool is not a number, a
float is not an integer (``max_events = 1e30`` is refused, not truncated), and every real
must be finite. ``docs/usage.md`` lists the tables (``schema_markdown()`` renders them).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass

import numpy as np

from . import _core
from ._core import ParameterError

#: The largest count accepted anywhere (events, blocks, steps): the engines count in 64 bits.
MAX_COUNT = 2**62


def _fail(name: str, value, allowed: str):
    raise ParameterError(f"invalid {name} = {_show(value)}: allowed {allowed}")


def _show(value) -> str:
    text = " ".join(repr(value).split())  # (one line: an array's repr spans several)
    return text if len(text) <= 80 else text[:77] + "..."


def _is_real(value) -> bool:
    if isinstance(value, bool | np.bool_):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and value.dtype.kind in "iuf"
    return isinstance(value, numbers.Real)


def _is_int(value) -> bool:
    if isinstance(value, bool | np.bool_):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and value.dtype.kind in "iu"
    return isinstance(value, numbers.Integral)


@dataclass(frozen=True)
class Spec:
    """One parameter: its name, type (``real``, ``int``, ``choice``, ``text``, ``bool``,
    ``reals``: an array of reals), allowed range or choices, unit and meaning."""

    name: str
    kind: str
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple = ()
    unit: str = ""
    doc: str = ""
    #: +inf is a value of its own (beta = inf: no backward slip), outside the range
    inf_ok: str = ""

    def allowed(self, name: str | None = None) -> str:
        name = name or self.name
        if self.kind == "choice":
            return "one of " + ", ".join(str(c) for c in self.choices)
        if self.kind == "text":
            return "a string without NUL characters"
        if self.kind == "bool":
            return "true or false"
        what = {"real": "a number", "int": "an integer", "reals": "numbers"}[self.kind]
        hi = None if self.hi == MAX_COUNT else self.hi
        rng = _range_text(name, self.lo, hi, self.lo_open, self.hi_open)
        text = f"{what} {rng}" if rng else f"{what} (finite)"
        return f"{text}, or inf {self.inf_ok}" if self.inf_ok else text

    def check(self, value, name: str | None = None):
        """The value converted (float, int, str, bool or float array), or ParameterError
        naming ``name`` (default: the spec's name)."""
        name = name or self.name
        if self.kind == "real" and self.inf_ok:
            if _is_real(value) and value == math.inf:
                return math.inf
            try:
                return number(name, value, lo=self.lo, hi=self.hi)
            except ParameterError:
                what = "expected a number, " if not _is_real(value) else ""
                raise ParameterError(
                    f"invalid {name} = {_show(value)}: {what}allowed {self.allowed(name)}"
                ) from None
        if self.kind == "real":
            return number(name, value, lo=self.lo, hi=self.hi, lo_open=self.lo_open,
                          hi_open=self.hi_open)  # fmt: skip
        if self.kind == "int":
            return integer(name, value, lo=self.lo, hi=self.hi)
        if self.kind == "reals":
            return array(name, value, lo=self.lo, hi=self.hi, lo_open=self.lo_open,
                         hi_open=self.hi_open)  # fmt: skip
        if self.kind == "choice":
            return choice(name, value, self.choices)
        if self.kind == "text":
            return text(name, value)
        if self.kind == "bool":
            return flag(name, value)
        raise AssertionError(self.kind)


def table(*specs: Spec) -> dict[str, Spec]:
    return {s.name: s for s in specs}


def number(name: str, value, *, lo=None, hi=None, lo_open=False, hi_open=False) -> float:
    """A finite real scalar inside [lo, hi] (ends open when asked); never a string,
    bytes, bool or complex."""
    allowed = _range_text(name, lo, hi, lo_open, hi_open) or "a finite number"
    if not _is_real(value):
        raise ParameterError(
            f"invalid {name} = {_show(value)}: expected a number"
            + (f", allowed {allowed}" if allowed != "a finite number" else "")
        )
    x = float(value)
    if not math.isfinite(x):
        _fail(name, value, allowed)
    if lo is not None and (x < lo or (lo_open and x == lo)):
        _fail(name, value, allowed)
    if hi is not None and (x > hi or (hi_open and x == hi)):
        _fail(name, value, allowed)
    return x


def integer(name: str, value, *, lo=None, hi=MAX_COUNT) -> int:
    """An integer (Python or numpy, never a float, bool or string) inside [lo, hi]."""
    hi = MAX_COUNT if hi is None else hi
    allowed = "an integer " + _range_text(name, lo, None if hi == MAX_COUNT else hi, False, False)
    if not _is_int(value):
        _fail(name, value, allowed)
    n = int(value)
    if (lo is not None and n < lo) or n > hi:
        _fail(name, value, allowed + (" and <= 2**62" if n > hi == MAX_COUNT else ""))
    return n


def optional_integer(name: str, value, *, lo=None, hi=MAX_COUNT) -> int | None:
    return None if value is None else integer(name, value, lo=lo, hi=hi)


def choice(name: str, value, choices) -> str:
    if not isinstance(value, str) or value not in choices:
        _fail(name, value, "one of " + ", ".join(str(c) for c in choices))
    return value


def text(name: str, value) -> str:
    if not isinstance(value, str) or "\x00" in value:
        _fail(name, value, "a string without NUL characters")
    return value


def flag(name: str, value) -> bool:
    if not isinstance(value, bool | np.bool_):
        _fail(name, value, "True or False")
    return bool(value)


def direction(name: str, value) -> int:
    """+1 or -1 (an integer or an integral float)."""
    if not _is_real(value) or float(value) not in (1.0, -1.0):
        _fail(name, value, "+1 (forward) or -1 (backward)")
    return int(value)


def seed(name: str, value) -> int | None:
    """A random seed: None or an integer 0 <= seed < 2**63."""
    if value is None:
        return None
    return integer(name, value, lo=0, hi=2**63 - 1)


def array(name: str, value, *, lo=None, hi=None, lo_open=False, hi_open=False) -> np.ndarray:
    """A float array whose every element is finite and inside the range (numbers only:
    no strings, bytes, bools, complex or objects)."""
    allowed = _range_text(name, lo, hi, lo_open, hi_open) or "finite numbers"
    if isinstance(value, str | bytes | bytearray):
        _fail(name, value, allowed)
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        _fail(name, value, allowed)
    if raw.dtype.kind not in "iuf" and not (raw.dtype.kind == "O" and raw.size == 0):
        if raw.dtype.kind == "O" and all(_is_real(v) for v in raw.flat):
            raw = raw.astype(float)
        else:
            _fail(name, value, f"numbers, {allowed}" if allowed != "finite numbers" else allowed)
    a = raw.astype(float)
    bad = ~np.isfinite(a)
    if lo is not None:
        bad |= (a <= lo) if lo_open else (a < lo)
    if hi is not None:
        bad |= (a >= hi) if hi_open else (a > hi)
    if np.any(bad):
        _fail(name, a[bad].flat[0].item(), allowed)
    return a


def _fmt(x) -> str:
    if isinstance(x, float) and x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    return str(x)


def _range_text(name, lo, hi, lo_open, hi_open) -> str:
    hi_text = None if hi is None else _fmt(hi)
    if lo is not None and hi is not None:
        return f"{_fmt(lo)} {'<' if lo_open else '<='} {name} {'<' if hi_open else '<='} {hi_text}"
    if lo is not None:
        return f"{name} {'>' if lo_open else '>='} {_fmt(lo)}"
    if hi is not None:
        return f"{name} {'<' if hi_open else '<='} {hi_text}"
    return ""


# --------------------------------------------------------------------------- tables
#: Dimensionless model parameters (bkwaves.Params, config [params]).
PARAMS = table(
    Spec("gamma", "real", lo=0.0, hi=1e6, doc="viscous damping alpha/(2 sqrt(k_p m))"),
    Spec("v", "real", lo=0.0, hi=1e6, doc="loading rate V sqrt(k_p m)/(f_r - f_s)"),
    Spec("dx", "real", lo=0.0, hi=1e6, lo_open=True, doc="lattice spacing sqrt(k_p/k_c)"),
    Spec(
        "beta",
        "real",
        lo=0.0,
        hi=1e6,
        inf_ok="for no backward slip (the paper's model, the default)",
        doc="f_s/(f_r - f_s): backward slip at phi <= -(1 + 2 beta)",
    ),  # fmt: skip
)

#: SI description of a chain (Params.from_physical, config [physical]).
PHYSICAL = table(
    Spec("mass", "real", lo=0.0, lo_open=True, unit="kg", doc="block mass"),
    Spec("k_c", "real", lo=0.0, lo_open=True, unit="N/m", doc="coupling spring constant"),
    Spec("k_p", "real", lo=0.0, lo_open=True, unit="N/m", doc="loader spring constant"),
    Spec("f_static", "real", lo=0.0, lo_open=True, unit="N", doc="static friction force"),
    Spec("f_kinetic", "real", lo=0.0, unit="N", doc="kinetic friction force, < f_static"),
    Spec("alpha", "real", lo=0.0, unit="kg/s", doc="viscous coefficient"),
    Spec("V", "real", lo=0.0, unit="m/s", doc="loader speed"),
    Spec("spacing", "real", lo=0.0, lo_open=True, unit="m", doc="block spacing a"),
)

#: bkwaves.Chain and Chain.run arguments.
CHAIN = table(
    Spec("n", "int", lo=1, doc="number of blocks"),
    Spec("boundary", "choice", choices=("free", "fixed", "periodic")),
    Spec(
        "step",
        "real",
        lo=0.0,
        hi=1.0,
        lo_open=True,
        hi_open=True,
        doc="time step as a fraction of dx",
    ),  # fmt: skip
    Spec("integrator", "choice", choices=tuple(m["name"] for m in _core.integrators())),
    Spec(
        "step_tolerance",
        "real",
        lo=0.0,
        hi=math.inf,
        lo_open=True,
        hi_open=True,
        doc="step-size control: largest error indicator of one step (None: the fixed step)",
    ),  # fmt: skip
    Spec(
        "events",
        "choice",
        choices=("global", "local"),
        doc="event location: global (every sliding block redone up to a switch) or local "
        "(the switch's neighbourhood only)",
    ),  # fmt: skip
    Spec("t_end", "real", lo=0.0, doc="end time (dimensionless)"),
    Spec("max_events", "int", lo=1, hi=MAX_COUNT, doc="events to finish"),
    Spec("snapshot_every", "int", lo=0, doc="snapshot at the end of every k-th event (0: never)"),
    Spec("chunk_steps", "int", lo=1, doc="integration steps per engine call"),
    Spec("max_event_slips", "int", lo=1, doc="runaway bound: slips in one event"),
)

#: bkwaves.FreeBoundary and FreeBoundary.run arguments.
FREE_BOUNDARY = table(
    Spec("boundary", "choice", choices=("free", "periodic")),
    Spec("creep", "choice", choices=("zero", "stop")),
    Spec(
        "tol",
        "real",
        lo=0.0,
        hi=1e-3,
        lo_open=True,
        hi_open=True,
        doc="local error per step (relative to the grid spacing)",
    ),  # fmt: skip
    Spec("record_path", "bool"),
    Spec("t_end", "real", lo=0.0, doc="end time (dimensionless)"),
    Spec("max_events", "int", lo=1, doc="events to complete"),
    Spec("chunk", "int", lo=1, doc="engine steps per call"),
)

#: The chain's integration settings as [run] keys: the ranges of bkwaves.Chain's arguments.
_DEFAULT_STEP = _core.defaults()["step"]
_INTEGRATOR_DOCS = "; ".join(f"{m['name']}: {m['doc']}" for m in _core.integrators())
_RUN_STEP = dataclasses.replace(
    CHAIN["step"],
    doc=f"chain: time step as a fraction of dx (h = step dx); default {_DEFAULT_STEP}; "
    "the floor of the step with step_tolerance",
)
_RUN_INTEGRATOR = dataclasses.replace(
    CHAIN["integrator"], doc=f"chain: the integrator; {_INTEGRATOR_DOCS}"
)
_RUN_STEP_TOLERANCE = dataclasses.replace(
    CHAIN["step_tolerance"],
    doc="chain, rk4 only: step-size control, the largest error indicator of one step "
    "(in units of u, also with [physical]; 1e-12 keeps the default step's accuracy; "
    'docs/chain.md, "Step-size control"); default none: the fixed step',
)

_RUN_EVENTS = dataclasses.replace(
    CHAIN["events"],
    doc="chain and lattice: how slips and sticks are located, global (every sliding block "
    "redone up to a switch) or local (the switch's neighbourhood only; rk4 at a fixed step "
    'and a law whose onset takes no sub-steps; docs/lattice.md, "Local events"); default '
    "global for the chain, local for the lattice where it applies",
)

from ._models import NAMES as MODEL_NAMES  # noqa: E402 - (after the tables it reuses)

#: Config keys: top level, [domain], [run], [output], [[triggers]].
CONFIG = {
    "": table(
        Spec("model", "choice", choices=MODEL_NAMES, doc="the run model (bkwaves._models)"),
        Spec("seed", "int", lo=0, hi=2**63 - 1, doc="seed of random initial states"),
        Spec("title", "text", doc="free text"),
        Spec(
            "input_units",
            "choice",
            choices=("SI", "dimensionless"),
            doc="units of the values: SI with [physical] (default), else dimensionless",
        ),  # fmt: skip
    ),
    "domain": table(
        Spec("blocks", "int", lo=1, doc="chain: number of blocks"),
        Spec(
            "length",
            "real",
            lo=0.0,
            lo_open=True,
            unit="x' (m with [physical])",
            doc="free boundary: domain length",
        ),  # fmt: skip
        Spec("grid", "int", lo=5, doc="free boundary: grid nodes"),
        Spec(
            "shape",
            "int",
            lo=1,
            doc="lattice, free_boundary_2d: [nx, ny], blocks (grid nodes) along x and y, "
            "each as allowed here (free_boundary_2d: >= 3)",
        ),  # fmt: skip
        Spec(
            "dy",
            "real",
            lo=0.0,
            lo_open=True,
            hi=1e6,
            doc="lattice: spacing across, sqrt(k_p/k_y) (dimensionless; default params.dx)",
        ),  # fmt: skip
        Spec(
            "spacing",
            "real",
            lo=0.0,
            lo_open=True,
            unit="x' (m with [physical])",
            doc="free_boundary_2d: grid spacing h (along x and y)",
        ),  # fmt: skip
        Spec(
            "boundary",
            "choice",
            choices=("free", "fixed", "periodic"),
            doc="chain: free, fixed, periodic; free boundary: free, periodic; lattice: one of "
            "the chain's or [along x, along y]; free_boundary_2d: free, periodic or "
            "[along x, along y]",
        ),  # fmt: skip
    ),
    "run": table(
        Spec(
            "t_end", "real", lo=0.0, lo_open=True, unit="t' (s with [physical])", doc="end time"
        ),  # fmt: skip
        Spec("max_events", "int", lo=1, doc="stop after this many events"),
        Spec(
            "max_event_slips",
            "int",
            lo=1,
            doc="chain: stop when one event exceeds this many slips (steady sliding or "
            "creep); default 100 x blocks, at least 10**4",
        ),  # fmt: skip
        Spec(
            "max_event_duration",
            "real",
            lo=0.0,
            lo_open=True,
            unit="t' (s with [physical])",
            doc="chain: stop when one event lasts longer; default 100 (blocks dx + 1), "
            "100 sound crossings of the chain",
        ),  # fmt: skip
        _RUN_STEP,
        _RUN_INTEGRATOR,
        _RUN_STEP_TOLERANCE,
        _RUN_EVENTS,
    ),
    "output": table(
        Spec(
            "path",
            "text",
            doc="output file (.nc or .zarr); relative: to the config file's folder",
        ),
        Spec(
            "snapshot_every",
            "real",
            lo=0.0,
            lo_open=True,
            unit="t' (s with [physical])",
            doc="time between snapshots",
        ),  # fmt: skip
        Spec("snapshot_events", "int", lo=1, doc="a snapshot every k events"),
        Spec("units", "choice", choices=("native", "dimensionless")),
        Spec(
            "arrivals",
            "bool",
            doc="lattice, free_boundary_2d: write the arrivals table, the arrival (first "
            "slip) time of every node in every rupture (default false)",
        ),  # fmt: skip
    ),
    "noise": table(
        Spec(
            "law",
            "choice",
            choices=("constant", "exponential", "power", "table"),
            doc="free boundary: spontaneous pair nucleation at Lambda(u) = rate g(u); chain: "
            "spontaneous slips of stuck blocks at rate g(x), x = 1 - (threshold - phi); g(1) = 1; "
            "g = 1, exp(-(1 - u)/phi0), max(u, 0)^exponent, or a table: "
            "piecewise linear through (u, g), constant outside, divided by g(1) "
            "(bk.noise, docs/noise.md)",
        ),  # fmt: skip
        Spec(
            "rate",
            "real",
            lo=0.0,
            unit="free boundary 1/(x' t') (1/(m s) with [physical]); chain 1/t' (1/s)",
            doc="the rate at the threshold: free boundary, pairs per unit length and time; "
            "chain, slips per block and unit time",
        ),  # fmt: skip
        Spec("phi0", "real", lo=0.0, lo_open=True, doc="exponential law only: stress scale"),
        Spec("exponent", "real", lo=0.0, doc="power law only: the exponent"),
        Spec(
            "u",
            "reals",
            doc="table law only: the nodes, strictly increasing, |u| <= 1000 (stress u; chain: x)",
        ),
        Spec(
            "g",
            "reals",
            lo=0.0,
            doc="table law only: g at the nodes (>= 0, > 0 at u = 1)",
        ),
        Spec(
            "kick",
            "real",
            lo=0.0,
            hi=1e6,
            unit="u_t units (m/s with [physical])",
            doc="chain only: forward speed of a spontaneous kick over the ground; "
            "0 (default): the block is released",
        ),  # fmt: skip
    ),
    "triggers": table(
        Spec("time", "real", lo=0.0, unit="t' (s with [physical])", doc="when"),
        Spec("block", "int", lo=0, doc="which block (0-based, < blocks; lattice: [i, j])"),
        Spec("kind", "choice", choices=("kick", "release")),
        Spec(
            "velocity",
            "real",
            unit="u_t units (m/s with [physical])",
            doc="kick: forward speed added",
        ),  # fmt: skip
        Spec(
            "x",
            "real",
            unit="x' (m with [physical])",
            doc="free_boundary_2d: where the rupture starts, within the grid",
        ),
        Spec(
            "y",
            "real",
            unit="x' (m with [physical])",
            doc="free_boundary_2d: where the rupture starts, within the grid",
        ),
        Spec(
            "radius",
            "real",
            lo=0.0,
            unit="x' (m with [physical])",
            doc="free_boundary_2d: the disk started at once (default 0: the nearest node)",
        ),
    ),  # fmt: skip
}


def schema_markdown() -> str:
    """The parameter tables as Markdown (docs/usage.md carries this text)."""
    sections = [("[params]", PARAMS), ("[physical]", PHYSICAL)]
    sections += [(f"[{k}]" if k else "top level", t) for k, t in CONFIG.items()]
    lines = []
    for title, tab in sections:
        lines += [f"**{title}**", "", "| key | allowed | unit | meaning |", "|---|---|---|---|"]
        for s in tab.values():
            lines.append(f"| `{s.name}` | {s.allowed()} | {s.unit} | {s.doc} |")
        lines.append("")
    return "\n".join(lines)
