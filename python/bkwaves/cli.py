"""The ``bkwaves`` command line.

Built on the standard library's argparse, so that ``bkwaves --help`` and the quick queries
start in a few tens of milliseconds above the interpreter: every command is a function of
its parsed options and imports what it needs (numpy, the engines, xarray, matplotlib,
Dask) inside it. A command's options are a table (a list of :class:`Opt`), so adding one is
adding a row; the function reads it as ``args.<dest>``.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import signal
import sys
import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

from . import __version__, _core
from ._core import ConvergenceError, ParameterError

PROG = "bkwaves"
DESCRIPTION = (
    "Traveling slip waves in the Burridge-Knopoff chain with Coulomb friction "
    "(C. B. Muratov, Phys. Rev. E 59, 3847, 1999)."
)


class UsageError(Exception):
    """Bad command-line syntax (unknown option, missing or malformed value): exit status 2."""


class _HelpFormatter(argparse.HelpFormatter):
    """Paragraphs (separated by blank lines) are re-wrapped one by one, not run together;
    a paragraph with indented lines (a table) is kept as written."""

    def _fill_text(self, text, width, indent):
        def fill(p):
            if any(line.startswith(" ") for line in p.splitlines()):
                return textwrap.indent(p, indent)
            return textwrap.fill(
                " ".join(p.split()), width, initial_indent=indent, subsequent_indent=indent
            )

        first, _, rest = text.strip().partition("\n")  # a docstring: the first line flush
        text = f"{first}\n{textwrap.dedent(rest)}".strip()
        return "\n\n".join(fill(p) for p in text.split("\n\n"))


class _Parser(argparse.ArgumentParser):
    # Values such as "-inf", "-1e-3" or "-0.5" are values, not options (argparse's own test
    # knows only "-1" and "-0.5"): no bkwaves option starts with "-" and a digit, ".", i or n.
    _NEGATIVE_NUMBER = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)

    def __init__(self, **kw):
        super().__init__(formatter_class=_HelpFormatter, allow_abbrev=False, **kw)
        self._negative_number_matcher = self._NEGATIVE_NUMBER

    def refuse_unknown_options(self, argv: list[str]) -> None:
        """Name a mistyped option (and the nearest real one) before anything else: argparse
        would first complain about the required option the typo was meant to be."""
        for arg in argv:
            if arg == "--":
                break
            name = arg.split("=", 1)[0]
            if (
                len(arg) > 1
                and arg.startswith("-")
                and not self._negative_number_matcher.match(arg)
                and name not in self._option_string_actions
            ):
                from difflib import get_close_matches

                near = get_close_matches(name, list(self._option_string_actions), 1)
                self.error(
                    f"no such option: {name}" + (f" (did you mean {near[0]}?)" if near else "")
                )

    def error(self, message):
        raise UsageError(
            f"{self.format_usage()}Try '{self.prog} --help' for help.\n\nError: {message}"
        )


class Opt(NamedTuple):
    """One option or argument of a command: argparse's add_argument, with the help text
    extended by [required] / [default: ...] the way the docs show them."""

    flags: tuple[str, ...]
    help: str
    type: Callable[[str], object] | None = None
    default: object = None
    required: bool = False
    flag: bool = False  # an on/off switch (store_true)
    metavar: str | None = None
    nargs: str | None = None
    dest: str | None = None

    def add_to(self, parser: argparse.ArgumentParser) -> None:
        text = self.help
        positional = not self.flags[0].startswith("-")
        if self.required or (positional and self.nargs in (None, "+")):
            text += "  [required]"
        elif self.default is not None and not self.flag:
            text += f"  [default: {self.default}]"
        kw: dict[str, object] = {"help": text.replace("%", "%%")}
        if self.dest is not None:
            kw["dest"] = self.dest
        if self.flag:
            kw["action"] = "store_true"
        else:
            kw.update(type=self.type, default=self.default, metavar=self.metavar)
            if self.nargs is not None:
                kw["nargs"] = self.nargs
            if not positional:
                kw["required"] = self.required
        parser.add_argument(*self.flags, **kw)


def opt(*flags: str, help: str, **kw) -> Opt:
    return Opt(flags, help, **kw)


class Command(NamedTuple):
    name: str
    run: Callable[[argparse.Namespace], int | None]
    summary: str  # one line, in `bkwaves --help`
    description: str  # `bkwaves NAME --help`
    options: list[Opt]

    def parser(self) -> _Parser:
        p = _Parser(prog=f"{PROG} {self.name}", description=self.description)
        for o in self.options:
            o.add_to(p)
        return p


JSON = opt("--json", dest="json_out", flag=True, help="Print one JSON object instead of text.")
PLOT = opt(
    "--plot", type=Path, metavar="FILE", help="Write a picture (.png, .svg or .pdf by suffix)."
)
QUIET = opt("--quiet", flag=True, help="No progress bar.")


def _echo(text: str = "", err: bool = False) -> None:
    print(text, file=sys.stderr if err else sys.stdout, flush=True)


def _json(d, **kw) -> str:
    import json

    return json.dumps(d, **kw)


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one clean line on stderr (no file path or source line)."""
    text = " ".join(str(message).split())
    _echo(f"Warning: {text}", err=True)


def _fail(err: Exception):
    _echo(f"Error: {err}", err=True)
    sys.exit(2)


def _check_plot(plot: Path | None) -> None:
    """Refuse, before any work, a --plot file of a format bkwaves does not write or in a
    place it cannot write."""
    if plot is not None:
        from ._paths import check_writable
        from .plot import check_path

        try:
            check_writable(check_path(plot, "--plot"), "--plot")
        except ParameterError as e:
            _fail(e)


def _check_out(path: Path | None, name: str, *, directory: bool = False) -> None:
    """Refuse, before any work, an output bkwaves cannot write (exit status 2)."""
    if path is not None:
        from ._paths import check_writable

        try:
            check_writable(path, name, directory=directory)
        except ParameterError as e:
            _fail(e)


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _json_value(x):
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


# ---------------------------------------------------------------------------------------
# wave


def wave(args) -> None:
    from .waves import traveling_wave

    _check_plot(args.plot)
    try:
        w = traveling_wave(args.u_plus, args.gamma)
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    d = {k: _json_value(v) for k, v in w.to_dict().items()}
    if args.plot is not None:
        from . import plot as bkplot

        bkplot.save(bkplot.wave_profile(w), args.plot)
    if args.json_out:
        _echo(_json(d))
        return
    _echo(f"u_plus  = {w.u_plus:.6g}   gamma = {w.gamma:.6g}")
    _echo(f"c       = {w.c:.12g}   (exact tip-problem speed 1/sqrt(1 - u_plus^2))")
    uc = "none (gamma >= 1: always creep)" if w.u_c is None else f"{w.u_c:.6g}"
    _echo(f"regime  = {w.regime}   (u_c = {uc})")
    if w.regime == "pulse":
        _echo(f"w       = {w.w:.6g}   (width, eq. w)")
        _echo(f"u_minus = {w.u_minus:.6g}   (stress behind, eq. um)")
        _echo(f"A       = {w.A:.6g}   (total slip, eq. A)")
    else:
        _echo("blocks never re-stick at v = 0: u -> 0 behind the front (w infinite)")
    if args.plot is not None:
        _echo(f"plot    -> {args.plot}")


WAVE = Command(
    "wave",
    wave,
    "The traveling wave behind the front: speed, regime, width, u_-, slip.",
    """The traveling wave behind the front (paper App. B): speed, regime, width, u_-, slip.

    The speed is c = 1/sqrt(1 - u_+^2), the exact solution of the paper's tip problem.""",
    [
        opt(
            "--u-plus",
            type=float,
            required=True,
            metavar="U",
            help="Stress ahead of the wave, 0 < U < 1.",
        ),
        opt("--gamma", type=float, required=True, help="Viscous damping gamma >= 0."),
        JSON,
        PLOT,
    ],
)


# ---------------------------------------------------------------------------------------
# speed


def speed(args) -> None:
    import numpy as np

    from . import theory
    from .waves import front_speed

    u_plus = args.u_plus
    _check_plot(args.plot)
    try:
        c = [float(x) for x in np.atleast_1d(front_speed(u_plus, method=args.method))]
        ci = [float(x) for x in np.atleast_1d(theory.c_interpolation(u_plus))]
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    if args.plot is not None:
        from . import plot as bkplot

        bkplot.save(bkplot.speed_curve(u_plus), args.plot)
    if args.json_out:
        _echo(_json({"u_plus": list(u_plus), "c": c, "c_interpolation": ci}))
        return
    _echo(f"{'u_plus':>10} {'c':>20} {'c (eq. c)':>14} {'rel. diff':>10}")
    for u, a, b in zip(u_plus, c, ci, strict=True):
        _echo(f"{u:>10.6g} {a:>20.15g} {b:>14.8g} {b / a - 1:>10.2e}")
    if args.plot is not None:
        _echo(f"plot -> {args.plot}")


SPEED = Command(
    "speed",
    speed,
    "Front speed c(u_+) from the tip problem, and eq. (c).",
    "Front speed c(u_+) from the tip problem (App. A), with the interpolation formula eq. (c).",
    [
        opt(
            "u_plus",
            type=float,
            nargs="+",
            metavar="U_PLUS",
            help="Stresses ahead, each 0 < U < 1.",
        ),
        opt(
            "--method",
            default="exact",
            metavar="METHOD",
            help="'exact' closed form, or 'tip' to solve the tip problem.",
        ),
        JSON,
        PLOT,
    ],
)


# ---------------------------------------------------------------------------------------
# paper


def _check_dict(check) -> dict:
    return dict(what=check.what, value=check.value, lo=check.lo, hi=check.hi, holds=check.holds)


def paper(args) -> None:
    from . import _signals
    from .paper import reproduce

    _check_out(args.out, "-o", directory=True)
    try:
        rep = reproduce(
            args.out,
            quick=args.quick,
            progress=not args.quiet and not args.json_out,
            overwrite=args.overwrite,
        )
    except ParameterError as e:
        _fail(e)
    except KeyboardInterrupt as e:  # (SIGINT, or SIGTERM as _signals.Terminated)
        sig = "SIGTERM" if isinstance(e, _signals.Terminated) else "SIGINT"
        raise type(e)(
            f"interrupted by {sig}: the figures written so far are kept in {args.out}; "
            "run it again with --overwrite to make them all and the report"
        ) from None
    verdicts = {}
    for c in rep.claims:
        verdicts[c.verdict] = verdicts.get(c.verdict, 0) + 1
    if args.json_out:
        _echo(
            _json(
                {
                    "out": str(args.out),
                    "seconds": rep.seconds,
                    "figures": sorted(rep.figures),
                    "beyond_figures": sorted(rep.beyond),
                    "claims": len(rep.claims),
                    "verdicts": verdicts,
                    "rows": [
                        {
                            "key": c.key,
                            "verdict": c.verdict,
                            "kind": c.kind,
                            "note": c.note,
                            "checks": [_check_dict(k) for k in c.checks],
                            "paper_check": None
                            if c.paper_check is None
                            else _check_dict(c.paper_check),
                            "applies": None if c.applies is None else _check_dict(c.applies),
                            "rounding_check": None
                            if c.rounding_check is None
                            else _check_dict(c.rounding_check),
                        }
                        for c in rep.claims
                    ],
                }
            )
        )
        return
    _echo(
        f"{len(rep.figures)} figures, {len(rep.beyond)} beyond the paper, and "
        f"report.md/report.html in {args.out} ({rep.seconds:.1f} s)"
    )
    _echo(", ".join(f"{n} {k}" for k, n in sorted(verdicts.items())))


PAPER = Command(
    "paper",
    paper,
    "Regenerate the paper's figures and a claim-by-claim validation report in OUT.",
    """Regenerate the paper's figures and a claim-by-claim validation report in OUT.

    OUT gets one PNG and one PDF per figure, report.md, report.html and
    bkwaves-paper.json (what bkwaves wrote there, with checksums). An OUT that already
    holds one of these files is refused unless --overwrite; even then only files bkwaves
    wrote and nobody changed since are replaced, and other files in OUT are never
    touched. An OUT that cannot be written is refused before any work.""",
    [
        opt(
            "-o",
            "--out",
            type=Path,
            default=Path("bkwaves-paper"),
            metavar="OUT",
            help="Output directory.",
        ),
        opt(
            "--overwrite",
            flag=True,
            help="Replace the files an earlier `bkwaves paper` wrote in OUT (only those, "
            "and only if unchanged since).",
        ),
        opt(
            "--quick",
            flag=True,
            help="Smaller, coarser runs for the tests (fewer laps, periods, events and seeds): "
            "about 20 s of CPU against 200 s for the full run, same figures and checks "
            "(docs/benchmarks.md).",
        ),
        QUIET,
        JSON,
    ],
)


# ---------------------------------------------------------------------------------------
# run


def _time_text(summary) -> str:
    """The time a run reached, with its unit: ``2e-06 s``, or ``60 (dimensionless)``."""
    unit = "s" if summary.units == "SI" else "(dimensionless)"
    return f"{summary.t:.6g} {unit}"


def run(args) -> int | None:
    from .io import OutputError
    from .runner import RunNotStarted, _StopRequest

    show = not args.quiet and not args.json_out
    with _StopRequest():  # before anything: a signal from here on keeps what was computed
        from .config import load_config
        from .runner import resume as resume_run
        from .runner import run as run_config

        try:
            if args.resume is not None:
                if args.config is not None or args.out is not None:
                    raise ParameterError(
                        "--resume OUT takes no CONFIG and no -o (the output is OUT)"
                    )
                summary = resume_run(
                    args.resume, progress=show, checkpoint_every=args.checkpoint_every
                )
            else:
                if args.config is None:
                    raise ParameterError("give a CONFIG.toml, or --resume OUT")
                cfg = load_config(args.config)
                target = args.out if args.out is not None else cfg.output_path
                if target is None:
                    raise ParameterError(
                        "no output: give -o OUT (.nc or .zarr) or [output] path in the config"
                    )
                summary = run_config(
                    cfg,
                    target,
                    progress=show,
                    overwrite=args.overwrite,
                    checkpoint_every=args.checkpoint_every,
                )
        except (ParameterError, ConvergenceError) as e:
            _fail(e)
        except OutputError as e:  # a full disk, a folder removed or read-only: one line
            _echo(f"Error: {e.strerror}", err=True)
            return 1
        except RunNotStarted as e:
            _echo(f"bkwaves run: {e}", err=True)
            return 128 + int(e.signal)
    d = summary.to_dict()
    if args.json_out:
        _echo(_json(d, default=str))
    if summary.interrupted:
        name = summary.extra.get("signal") or "SIGINT"
        _echo(
            f"{summary.model}: interrupted by {name} at t = {_time_text(summary)}: kept "
            f"{_count(summary.snapshots, 'snapshot')} and "
            f"{_count(summary.events, 'event')} in {summary.out}.partial; continue with "
            f"`bkwaves run --resume {summary.out}`",
            err=True,
        )
        return 128 + int(getattr(signal, name))
    runaway = summary.extra.get("stop") == "long_event"
    if not args.json_out:
        state = "stopped (an event does not end)" if runaway else "done"
        ruptures = summary.extra.get("ruptures", 0)
        counts = [_count(summary.events, "event")] if summary.events is not None else []
        counts += [_count(ruptures, "rupture")] if ruptures is not None else []
        _echo(
            f"{summary.model}: {state} at t = {_time_text(summary)}, {', '.join(counts)}, "
            f"{_count(summary.snapshots, 'snapshot')}, {summary.wall_s:.2f} s -> {summary.out}"
        )
    if runaway:
        _echo(f"Stopped: {summary.extra['message']}", err=True)
        return 3
    late = summary.extra.get("late_signal")
    if late:  # arrived once the output was complete and published
        _echo(f"{late} arrived after {summary.out} was complete and published", err=True)
        return 128 + int(getattr(signal, late))
    return None


RUN = Command(
    "run",
    run,
    "Run a simulation described by CONFIG.toml (chain, free_boundary, lattice, free_boundary_2d).",
    """Run a simulation described by CONFIG.toml: its model = "chain", "free_boundary",
    "lattice" (blocks on a plane, [domain] shape = [nx, ny]) or "free_boundary_2d" (the
    free boundary problem in the plane, [domain] shape and spacing); planar snapshots have
    dims (t, y, x) and `bkwaves plot` draws their maps.

    Snapshots go to OUT (NetCDF or Zarr by suffix); the event catalog and trajectories to
    OUT.events.parquet/.csv and OUT.slips/shocks.parquet. Until the run is complete they are
    kept in OUT.partial/, then published onto OUT at once; snapshots are written as they
    come (memory does not grow with them). An existing OUT is refused unless --overwrite
    (only files bkwaves wrote are replaced; a file of yours named OUT.lock or inside
    OUT.zarr is never touched). Ctrl-C or SIGTERM stop the run within a second in any
    phase, keep what was computed and leave OUT.checkpoint (exit status 130 or 143): `bkwaves
    run --resume OUT` continues it, bit for bit like an uninterrupted run. Checkpoints are
    also written every 60 s of wall time (see --checkpoint-every), so that a killed run
    resumes. A write that fails (a full disk, a file past `ulimit -f`, a folder made
    read-only or removed) keeps what fits and the last checkpoint and says so in one line
    (exit status 1); a complete run that finds no room to be published is kept whole with
    a checkpoint of its end, and `bkwaves run --resume OUT` publishes it.
    An event that does not end (creep, steady sliding; bounds run.max_event_slips and
    run.max_event_duration) stops the run with everything kept (exit status 3).

    Paths: -o is relative to the working directory; paths written in the config
    ([output] path, [initial] path) are relative to the config file's folder, as in
    `bkwaves sweep`.

    An initial state over the static threshold (e.g. [initial] value = 1.5): the
    chain's blocks where u - Lap u/dx^2 >= 1 slide from t = 0 (a chain can be
    overloaded); the free-boundary model refuses u >= 1, naming the key (its field is the
    stress of stuck blocks). [friction] laws other than coulomb run in the chain and the
    lattice; the free boundary models refuse them, naming the key. Snapshots every dt
    are taken at t_k = k dt, the last one at t_end when t_end is a multiple of dt (to
    1e-9 dt).

    Before any work the run's time, memory and output are estimated from what the engine
    will do: a run that cannot fit (engine state beyond the RAM, output beyond 1 TiB) is
    refused; one estimated to take over an hour, hold over half the RAM or write over
    10 GiB is warned in one line and goes on (docs/usage.md, "Limits").
    See docs/usage.md for the schema.""",
    [
        opt(
            "config",
            type=Path,
            nargs="?",
            metavar="CONFIG",
            help="A run configuration (TOML); omit with --resume.",
        ),
        opt(
            "-o",
            "--out",
            type=Path,
            metavar="OUT",
            help="Output (.nc or .zarr); default: [output] path.",
        ),
        opt(
            "--overwrite",
            flag=True,
            help="Replace an existing output (only files bkwaves wrote; once the new one is "
            "complete).",
        ),
        opt(
            "--resume",
            type=Path,
            metavar="OUT",
            help="Continue the run that wrote this output (.nc/.zarr).",
        ),
        opt(
            "--checkpoint-every",
            type=float,
            metavar="SECONDS",
            help="Checkpoint every this many seconds of wall time (default: every 60 s, "
            "less often when a checkpoint is slow to write, so they cost at most 1/20 of the "
            "run; inf: only when interrupted). A killed run resumes from its last "
            "checkpoint.",
        ),
        QUIET,
        JSON,
    ],
)


# ---------------------------------------------------------------------------------------
# plot


def plot(args) -> None:
    from .plot import plot_run

    _check_out(args.outdir, "-o", directory=True)
    try:
        files = plot_run(args.out, args.outdir, fmt=args.format)
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    for f in files:
        _echo(str(f))


PLOT_COMMAND = Command(
    "plot",
    plot,
    "The standard pictures of a run: space-time diagrams, profiles, trajectories, catalog.",
    "The standard pictures of a run: space-time diagrams, profiles, trajectories, catalog;\n"
    "for a planar run (dims (t, y, x): a lattice, the planar free boundary) the slip map,\n"
    "the arrival-time contours of the largest rupture, the catalog on a map and the\n"
    "stress at the last snapshot (run_slip_map.png, run_arrivals.png,\n"
    "run_catalog_map.png, run_stress.png for run.nc), and the catalog's\n"
    "size-frequency and frequency-magnitude plots.",
    [
        opt("out", type=Path, metavar="OUT", help="A run output (.nc or .zarr)."),
        opt(
            "-o",
            "--outdir",
            type=Path,
            metavar="DIR",
            help="Where to write (default: beside OUT).",
        ),
        opt("--format", default="png", metavar="FORMAT", help="png, svg or pdf."),
    ],
)


# ---------------------------------------------------------------------------------------
# stats


def stats(args) -> None:
    from .catalog import report, report_text

    try:
        rep = report(args.out)
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    _echo(_json(rep, default=str) if args.json_out else report_text(rep))


STATS_COMMAND = Command(
    "stats",
    stats,
    "What a run output holds: counts, magnitudes, b with its interval and Mc, recurrence.",
    """What a run output holds and shows: its model, units, parameters and seed; the counts
    of events and ruptures; over the ruptures (the events for outputs without them) the
    magnitude range (M = (2/3) log10(moment)), the b-value with its 95 % bootstrap
    interval and the magnitude of completeness Mc (maximum curvature + 0.2), or why there
    is none (too few, or all of one size); the recurrence (mean and CV of the times
    between successive starts) and the largest one. See docs/usage.md "Event
    statistics".""",
    [opt("out", type=Path, metavar="OUT", help="A run output (.nc or .zarr)."), JSON],
)


# ---------------------------------------------------------------------------------------
# front


# The friction laws' own parameters as options of `front` (gamma and beta have their
# own): generated from the core's parameter tables, `--v-f` for v_f.
_LAWS = _core.friction_laws()
_LAW_PARAMS: dict[str, list[dict]] = {}
for _law in _LAWS:
    for _p in _law["params"]:
        if _p["name"] not in ("gamma", "beta"):
            _LAW_PARAMS.setdefault(_p["name"], []).append(dict(_p, law=_law["name"]))


def _law_options() -> list[Opt]:
    out = [
        opt(
            "--law",
            default=_core.defaults()["law"],
            metavar="NAME",
            help="Friction law: "
            + "; ".join(f"{d['name']} ({d['doc']})" for d in _LAWS)
            + ". Its other parameters: the options below.",
        )
    ]
    for name, rows in _LAW_PARAMS.items():
        r = rows[0]
        laws = ", ".join(x["law"] for x in rows)
        out.append(
            opt(
                "--" + name.replace("_", "-"),
                type=float,
                dest=f"law_{name}",
                metavar=name.upper(),
                help=f"{r['doc']}; {r['allowed']} (law {laws}).",
            )
        )
    return out


def _front_law(args):
    from .friction import Law

    given = {k: getattr(args, f"law_{k}") for k in _LAW_PARAMS}
    given = {k: x for k, x in given.items() if x is not None}
    own = {d["name"]: {p["name"] for p in d["params"]} for d in _LAWS}
    for k in given:
        if args.law in own and k not in own[args.law]:
            laws = [r["law"] for r in _LAW_PARAMS[k]]
            flag = "--" + k.replace("_", "-")
            now = "" if args.law == _core.defaults()["law"] else f" instead of --law {args.law}"
            raise ParameterError(
                f"{flag} ({k}) is a parameter of the friction law {' or '.join(laws)}, not of "
                f"{args.law}: add --law {laws[0]}{now}"
            )
    return Law(args.law, tuple(given.items()))


def front(args) -> None:
    from .chain import front as measure

    try:
        law = _front_law(args)
        m = measure(args.u_plus, args.gamma, args.dx, args.blocks, beta=args.beta, friction=law)
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    d = {k: _json_value(v) for k, v in m.to_dict().items()}
    d["beta"] = "inf" if math.isinf(m.beta) else m.beta  # JSON has no inf (null: unknown)
    d["law"] = law.name
    d.update(law.params)
    if args.json_out:
        _echo(_json(d))
        return
    _echo(f"u_plus  = {m.u_plus:.6g}   gamma = {m.gamma:.6g}   dx = {m.dx:.6g}")
    own = "".join(f"   {k} = {x:.6g}" for k, x in law.params)
    _echo(f"law     = {law.name}{own}")
    slip = "no backward slip" if math.isinf(m.beta) else "backward slip on"
    _echo(f"beta    = {m.beta:g}   ({slip}; {m.backward_slips} backward slips)")
    _echo(f"blocks  = {m.blocks}   ({m.passes} run{'s' if m.passes > 1 else ''})")
    c_inf = 1.0 / math.sqrt(1.0 - m.u_plus**2)
    measured = f"{m.c:.12g}" if math.isfinite(m.c) else "none (no front)"
    _echo(
        f"c       = {measured}   (measured on the chain; Coulomb continuum "
        f"1/sqrt(1 - u_plus^2) = {c_inf:.6g})"
    )
    if m.front == "dies":
        _echo("front   = dies   (no steady front)")
    else:
        _echo(
            f"front   = {m.front}   (slip intervals agree with dx/c to {m.unsteadiness:.2g} "
            "over the window)"
        )
    _echo(f"regime  = {m.regime}")
    if m.regime == "pulse":
        _echo(f"w       = {m.w:.6g}   (pulse width)")
        _echo(f"u_minus = {m.u_minus:.6g}   (stress behind)")
    steady = "-" if m.steadiness is None else f"{m.steadiness:.2g}"
    xs = "-" if m.settling_length is None else f"{m.settling_length:.4g}"
    if m.front != "dies":
        _echo(
            f"steady  = {steady}   (spread of sliding times and re-stick u over the window "
            f"x = {m.window[0]:.4g}-{m.window[1]:.4g}; settling length x_s = {xs})"
        )
    if m.convergence:
        moved = ", ".join(
            f"{k} {'-' if x is None else f'{x:.1g}'}" for k, x in m.convergence.items()
        )
        against = "the chain half as long" if law.name != "coulomb" else "a window half as far out"
        _echo(f"moved   = {moved}   (u_minus absolute, the others relative, against {against})")
    _echo(f"why     : {m.reason}")
    if m.app_b is not None:
        b = m.app_b
        shape = (
            f"c = {b['c']:.6g}, w = {b['w']:.6g}, u_minus = {b['u_minus']:.6g}"
            if b["regime"] == "pulse"
            else f"c = {b['c']:.6g}"
        )
        coulomb = "" if law.name == "coulomb" else ", Coulomb friction"
        _echo(f"App. B  : {b['regime']}, {shape}   (continuum, dx -> 0{coulomb})")
    _echo(f"wall    = {m.wall_s:.3g} s")


FRONT = Command(
    "front",
    front,
    "One front in a direct simulation of the discrete chain at v = 0.",
    """One front in a direct simulation of the discrete chain at v = 0.

    Uniform u_+ on a free chain, block 0 kicked forward; c from the slip times
    of a window of blocks, w and u_- from their re-sticking. Front: steady (the
    window's slip intervals agree with dx/c to 1e-3), unsteady, or dies (it
    stopped before the far end, as velocity-weakening fronts do at large v_f:
    then regime none and c NaN). Regime: pulse (a steady healing front: sliding
    times and re-stick stresses agree to 1e-3), creep (none), or undecided (the
    reason is printed); "steady" prints the spread, "moved" how much c, w and
    u_- changed against a window half as far out (Coulomb) or the chain half
    as long (velocity weakening): the measurement's convergence.

    Default chain length: the trigger's transient can reach the healing front
    at x only if x < x_s = w v/(c - v) (v: the fastest lattice wave, < 1), so
    the window starts 2 x_s from the trigger (of the cases measured in
    docs/chain.md 9 of 10 are steady to 1e-6 there, a narrow undamped pulse to
    8e-4). The chain is sized from App. B's w and c, then re-run (at most
    twice) from the measured ones, further out while the spread exceeds 1e-6:
    typically 500-5000 blocks and under a second; near u_+ = gamma ~2e4 blocks
    and ~10 s.
    Without an App. B pulse (u_+ <= gamma): 1600 blocks (at least 40 units).
    A measurement estimated to take over an hour (the pulse's blocks times the
    steps it takes to cross the chain) is warned in one line, never refused.""",
    [
        opt("--u-plus", type=float, required=True, metavar="U", help="Stress ahead, 0 < U < 1."),
        opt("--gamma", type=float, required=True, help="Viscous damping gamma >= 0."),
        opt("--dx", type=float, required=True, help="Lattice spacing, 0 < DX < 1."),
        opt(
            "--blocks",
            type=int,
            metavar="N",
            help="Chain length (default: from the pulse's w and c, see above). A given "
            "length is one run, the window as far from the trigger as the end allows.",
        ),
        opt(
            "--beta",
            type=float,
            default=math.inf,
            help="f_s/(f_r - f_s): backward slip when u - Lap u/dx^2 <= -(1 + 2 beta). "
            "Default inf: no backward slip, the paper's model.",
        ),
        *_law_options(),
        JSON,
    ],
)


# ---------------------------------------------------------------------------------------
# sweep


def sweep(args) -> int | None:
    from .sweeps import sweep as run_sweep

    _check_out(args.out, "-o", directory=True)
    try:
        r = run_sweep(
            args.sweep_file,
            args.out,
            scheduler=args.scheduler,
            workers=args.workers,
            processes=args.processes,
            overwrite=args.overwrite,
            retry_failed=args.retry_failed,
            progress=not args.quiet and not args.json_out,
        )
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    except OSError as e:
        from ._paths import os_error_line
        from .io import NO_SPACE

        if e.errno not in NO_SPACE:
            raise
        # (the store holds every point written before; a point's files are whole or absent)
        _echo(
            f"Error: {os_error_line(e)}; the points finished before are kept; free space, "
            "then run the same command again to compute the rest",
            err=True,
        )
        return 1
    d = r.to_dict()
    if args.json_out:
        _echo(_json(d, default=str))
    else:
        _echo(
            f"sweep: {d['points']} points ({r.computed} computed, {r.skipped} already done, "
            f"{r.failed} failed) in {r.wall_s:.1f} s -> {r.out}"
        )
    if r.interrupted:
        _echo(
            "interrupted: finished points are kept; run the same command again to compute the rest",
            err=True,
        )
        return 143 if r.signal == signal.SIGTERM else 130
    return None


SWEEP = Command(
    "sweep",
    sweep,
    "A parameter sweep on Dask: every point of SWEEP.toml's axes is one task.",
    """A parameter sweep on Dask: every point of SWEEP.toml's axes is one task, the
    summaries go into one Zarr store (an xarray Dataset indexed by the axes) as points
    finish (each as soon as it arrives). Re-running computes only the points not yet done,
    after checking that the done ones still hold the values and files they wrote (those
    that do not are computed again); Ctrl-C or SIGTERM keep every finished point (exit
    status 130 or 143), and so does a full disk (one line, exit status 1). A damaged
    store is reported in one line. -o is relative to the
    working directory, [output] path (and the default SWEEP.zarr) to the sweep file's
    folder, as in `bkwaves run`. See docs/sweeps.md for the schema.""",
    [
        opt(
            "sweep_file",
            type=Path,
            metavar="SWEEP",
            help="A sweep description (SWEEP.toml).",
        ),
        opt(
            "-o",
            "--out",
            type=Path,
            metavar="OUT",
            help="Output Zarr store (default: SWEEP.zarr beside the file).",
        ),
        opt(
            "--scheduler",
            metavar="ADDRESS",
            help="Address of a running Dask scheduler (default: a local cluster).",
        ),
        opt(
            "--workers",
            type=int,
            metavar="N",
            help="Workers (threads, or processes with --processes) of the local cluster "
            "(default: one per core).",
        ),
        opt(
            "--processes",
            flag=True,
            help="Local cluster of worker processes instead of threads in this process "
            "(default: threads; the engines release the GIL, docs/benchmarks.md).",
        ),
        opt("--overwrite", flag=True, help="Replace an existing sweep store at OUT."),
        opt("--retry-failed", flag=True, help="Recompute points that failed before."),
        QUIET,
        JSON,
    ],
)


COMMANDS = {c.name: c for c in (WAVE, SPEED, PAPER, RUN, PLOT_COMMAND, STATS_COMMAND, FRONT, SWEEP)}


def _main_parser() -> _Parser:
    width = max(len(name) for name in COMMANDS)
    listing = "\n".join(
        textwrap.fill(
            c.summary,
            79,
            initial_indent=f"  {c.name:<{width}}  ",
            subsequent_indent=" " * (width + 4),
        )
        for c in COMMANDS.values()
    )
    p = _Parser(
        prog=PROG,
        usage=f"{PROG} [--version] [--help] COMMAND [ARGS]...",
        description=DESCRIPTION,
        epilog=f"commands:\n{listing}\n\n`{PROG} COMMAND --help` describes each command.",
    )
    p.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    p.add_argument("command", metavar="COMMAND", choices=list(COMMANDS), help=argparse.SUPPRESS)
    p.add_argument("args", nargs=argparse.REMAINDER, help=argparse.SUPPRESS)
    return p


def main(argv: list[str] | None = None) -> None:
    """The entry point: parse ``argv`` (default: the process's), run the command, exit with
    its status (0 done, 1 a full disk, 2 bad input, 3 an event that does not end (runaway),
    130/143 interrupted by SIGINT/SIGTERM). Called from code (with ``argv``), it leaves
    the process's signal handlers as it found them."""
    from . import _signals

    if argv is None:  # the command line itself
        _main(sys.argv[1:], _signals, process=True)
    saved = _signals.save()
    try:
        _main(list(argv), _signals, process=False)
    finally:
        _signals.restore(saved)


def _main(argv: list[str], _signals, process: bool) -> None:
    _signals.install_early()  # (again: `python -m bkwaves`, or main() called from code)
    if process and hasattr(signal, "SIGXFSZ"):
        # a file past `ulimit -f` is then a failed write (EFBIG: kept, one line), like a
        # full disk, not the death of the process by SIGXFSZ
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    # pictures are written to files: draw off-screen unless the user chose a backend
    os.environ.setdefault("MPLBACKEND", "Agg")
    import warnings

    warnings.showwarning = _show_warning
    top = _main_parser()
    name = "bkwaves"
    try:
        if not argv:
            top.print_help(sys.stderr)
            sys.exit(2)
        ns = top.parse_args(argv)
        command = COMMANDS[ns.command]
        name = f"bkwaves {command.name}"
        # options and arguments in any order, as in `bkwaves speed 0.3 --json 0.6`
        parser = command.parser()
        parser.refuse_unknown_options(ns.args)
        args = parser.parse_intermixed_args(ns.args)
        if _signals.pending is not None:
            _stopped_before_start(name, _signals.pending)
        if command.name != "run":  # (run notes signals and stops between chunks)
            _signals.install_raising()
        status = command.run(args)
    except UsageError as e:
        _echo(str(e), err=True)
        sys.exit(2)
    except KeyboardInterrupt as e:  # commands that do not stop cleanly on their own
        sig = getattr(e, "signal", None)  # (bkwaves.runner.RunNotStarted says which)
        if sig is None:
            sig = signal.SIGTERM if isinstance(e, _signals.Terminated) else signal.SIGINT
        text = str(e) or f"interrupted by {signal.Signals(sig).name}."
        _echo(f"\n{name}: {text}", err=True)
        _exit(128 + sig, process)
    except BrokenPipeError:  # e.g. `bkwaves speed ... | head -1`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(1)
    except OSError as e:  # a file that could not be read or written: one line, no traceback
        from ._paths import os_error_line

        _echo(f"Error: {os_error_line(e)}", err=True)
        sys.exit(2)
    if not status and _signals.pending is not None:  # (noted, never lost)
        sig = signal.Signals(_signals.pending)
        _echo(f"{name}: {sig.name} arrived as it ended; it had finished", err=True)
        status = 128 + sig
    if status in (128 + signal.SIGINT, 128 + signal.SIGTERM):
        _exit(status, process)
    sys.exit(status or 0)


def _exit(status: int, process: bool):
    """Exit interrupted: everything written is closed, so the command line exits at once,
    without the interpreter's teardown (a second on a busy machine, after matplotlib)
    between its answer and its end; called from code, as sys.exit."""
    if process:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    sys.exit(status)


def _stopped_before_start(name: str, signum: int):
    sig = signal.Signals(signum)
    _echo(
        f"{name}: stopped by {sig.name} before it started: nothing was computed or written",
        err=True,
    )
    sys.exit(128 + sig)


if __name__ == "__main__":
    main()
