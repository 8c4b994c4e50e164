"""The ``bkwaves`` command line."""

from __future__ import annotations

import json
import math
import os
import signal
from pathlib import Path
from typing import Annotated

import typer

from . import __version__
from ._core import ConvergenceError, ParameterError

# Plain (click-style) help: rich's help panels cost a tenth of a second of imports on every
# call, show boolean flags as "--json <bool>" and read "[...]" in help texts as markup.
app = typer.Typer(
    name="bkwaves",
    help="Traveling slip waves in the Burridge-Knopoff chain with Coulomb friction "
    "(C. B. Muratov, Phys. Rev. E 59, 3847, 1999).",
    no_args_is_help=True,
    rich_markup_mode=None,
    add_completion=False,
    pretty_exceptions_enable=False,
)

JsonOpt = Annotated[bool, typer.Option("--json", help="Print one JSON object instead of text.")]
PlotOpt = Annotated[
    Path | None, typer.Option("--plot", help="Write a picture (.png, .svg or .pdf by suffix).")
]


def _fail(err: Exception) -> None:
    typer.echo(f"Error: {err}", err=True)
    raise typer.Exit(2)


def _check_plot(plot: Path | None) -> None:
    """Refuse a --plot file of a format bkwaves does not write, before any work."""
    if plot is not None:
        from .plot import check_path

        try:
            check_path(plot, "--plot")
        except ParameterError as e:
            _fail(e)


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _json_value(x):
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def _version(value: bool):
    if value:
        typer.echo(f"bkwaves {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version, is_eager=True, help="Show the version."),
    ] = False,
):
    """Simulate and analyse Burridge-Knopoff traveling waves."""


@app.command(short_help="The traveling wave behind the front: speed, regime, width, u_-, slip.")
def wave(
    u_plus: Annotated[float, typer.Option("--u-plus", help="Stress ahead of the wave, 0 < U < 1.")],
    gamma: Annotated[float, typer.Option("--gamma", help="Viscous damping gamma >= 0.")],
    json_out: JsonOpt = False,
    plot: PlotOpt = None,
):
    """The traveling wave behind the front (paper App. B): speed, regime, width, u_-, slip.

    The speed is c = 1/sqrt(1 - u_+^2), the exact solution of the paper's tip problem.
    """
    from .waves import traveling_wave

    _check_plot(plot)
    try:
        w = traveling_wave(u_plus, gamma)
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    d = {k: _json_value(v) for k, v in w.to_dict().items()}
    if plot is not None:
        from . import plot as bkplot

        bkplot.save(bkplot.wave_profile(w), plot)
    if json_out:
        typer.echo(json.dumps(d))
        return
    typer.echo(f"u_plus  = {w.u_plus:.6g}   gamma = {w.gamma:.6g}")
    typer.echo(f"c       = {w.c:.12g}   (exact tip-problem speed 1/sqrt(1 - u_plus^2))")
    uc = "none (gamma >= 1: always creep)" if w.u_c is None else f"{w.u_c:.6g}"
    typer.echo(f"regime  = {w.regime}   (u_c = {uc})")
    if w.regime == "pulse":
        typer.echo(f"w       = {w.w:.6g}   (width, eq. w)")
        typer.echo(f"u_minus = {w.u_minus:.6g}   (stress behind, eq. um)")
        typer.echo(f"A       = {w.A:.6g}   (total slip, eq. A)")
    else:
        typer.echo("blocks never re-stick at v = 0: u -> 0 behind the front (w infinite)")
    if plot is not None:
        typer.echo(f"plot    -> {plot}")


@app.command(short_help="Front speed c(u_+) from the tip problem, and eq. (c).")
def speed(
    u_plus: Annotated[list[float], typer.Argument(help="Stresses ahead, each 0 < U < 1.")],
    method: Annotated[
        str, typer.Option(help="'exact' closed form, or 'tip' to solve the tip problem.")
    ] = "exact",
    json_out: JsonOpt = False,
    plot: PlotOpt = None,
):
    """Front speed c(u_+) from the tip problem (App. A), with the interpolation formula eq. (c)."""
    from . import theory
    from .waves import front_speed

    _check_plot(plot)
    try:
        c = [float(x) for x in __import__("numpy").atleast_1d(front_speed(u_plus, method=method))]
        ci = [float(x) for x in __import__("numpy").atleast_1d(theory.c_interpolation(u_plus))]
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    if plot is not None:
        from . import plot as bkplot

        bkplot.save(bkplot.speed_curve(u_plus), plot)
    if json_out:
        typer.echo(json.dumps({"u_plus": list(u_plus), "c": c, "c_interpolation": ci}))
        return
    typer.echo(f"{'u_plus':>10} {'c':>20} {'c (eq. c)':>14} {'rel. diff':>10}")
    for u, a, b in zip(u_plus, c, ci, strict=True):
        typer.echo(f"{u:>10.6g} {a:>20.15g} {b:>14.8g} {b / a - 1:>10.2e}")
    if plot is not None:
        typer.echo(f"plot -> {plot}")


@app.command()
def paper(
    out: Annotated[Path, typer.Option("-o", "--out", help="Output directory.")] = Path(
        "bkwaves-paper"
    ),
    quick: Annotated[
        bool,
        typer.Option(
            "--quick",
            help="Smaller, coarser runs: about 40% of the full run's CPU time, same figures "
            "and claims (docs/benchmarks.md).",
        ),
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", help="No progress bar.")] = False,
    json_out: JsonOpt = False,
):
    """Regenerate the paper's figures and a claim-by-claim validation report in OUT."""
    from .paper import reproduce

    rep = reproduce(out, quick=quick, progress=not quiet and not json_out)
    verdicts = {}
    for c in rep.claims:
        verdicts[c.verdict] = verdicts.get(c.verdict, 0) + 1
    if json_out:
        typer.echo(
            json.dumps(
                {
                    "out": str(out),
                    "seconds": rep.seconds,
                    "figures": sorted(rep.figures),
                    "claims": len(rep.claims),
                    "verdicts": verdicts,
                }
            )
        )
        return
    typer.echo(
        f"{len(rep.figures)} figures and report.md/report.html in {out} ({rep.seconds:.1f} s)"
    )
    typer.echo(", ".join(f"{n} {k}" for k, n in sorted(verdicts.items())))


@app.command("run")
def run_cmd(
    config: Annotated[
        Path | None, typer.Argument(help="A run configuration (TOML); omit with --resume.")
    ] = None,
    out: Annotated[
        Path | None,
        typer.Option("-o", "--out", help="Output (.nc or .zarr); default: [output] path."),
    ] = None,
    overwrite: Annotated[
        bool,
        typer.Option(
            "--overwrite",
            help="Replace an existing output (only files bkwaves wrote; once the new one is "
            "complete).",
        ),
    ] = False,
    resume: Annotated[
        Path | None,
        typer.Option("--resume", help="Continue the run that wrote this output (.nc/.zarr)."),
    ] = None,
    checkpoint_every: Annotated[
        float | None,
        typer.Option("--checkpoint-every", help="Also checkpoint every this many seconds."),
    ] = None,
    quiet: Annotated[bool, typer.Option("--quiet", help="No progress bar.")] = False,
    json_out: JsonOpt = False,
):
    """Run a chain or free-boundary simulation described by CONFIG.toml.

    Snapshots go to OUT (NetCDF or Zarr by suffix); the event catalog and trajectories to
    OUT.events.parquet/.csv and OUT.slips/shocks.parquet. Until the run is complete they are
    kept in OUT.partial/, then published onto OUT at once. An existing OUT is refused unless
    --overwrite. Ctrl-C or SIGTERM stop the run, keep what was computed and leave
    OUT.checkpoint (exit status 130 or 143): `bkwaves run --resume OUT` continues it, bit
    for bit like an uninterrupted run. A full disk keeps what was written (exit status 1).
    See docs/usage.md for the schema.
    """
    from .runner import OutputFull, _StopRequest

    show = not quiet and not json_out
    with _StopRequest():  # before anything: a signal from here on keeps what was computed
        from .config import load_config
        from .runner import resume as resume_run
        from .runner import run

        try:
            if resume is not None:
                if config is not None or out is not None:
                    raise ParameterError(
                        "--resume OUT takes no CONFIG and no -o (the output is OUT)"
                    )
                summary = resume_run(resume, progress=show, checkpoint_every=checkpoint_every)
            else:
                if config is None:
                    raise ParameterError("give a CONFIG.toml, or --resume OUT")
                cfg = load_config(config)
                target = out if out is not None else cfg.output_path
                if target is None:
                    raise ParameterError(
                        "no output: give -o OUT (.nc or .zarr) or [output] path in the config"
                    )
                summary = run(
                    cfg,
                    target,
                    progress=show,
                    overwrite=overwrite,
                    checkpoint_every=checkpoint_every,
                )
        except (ParameterError, ConvergenceError) as e:
            _fail(e)
        except OutputFull as e:
            typer.echo(f"Error: {e.strerror}", err=True)
            raise typer.Exit(1) from None
    d = summary.to_dict()
    if json_out:
        typer.echo(json.dumps(d, default=str))
    if summary.interrupted:
        name = summary.extra.get("signal") or "SIGINT"
        typer.echo(
            f"{summary.model}: interrupted by {name} at t = {summary.t:.6g} "
            f"({summary.units}): kept {_count(summary.snapshots, 'snapshot')} and "
            f"{_count(summary.events, 'event')} in {summary.out}.partial; continue with "
            f"`bkwaves run --resume "
            f"{summary.out}`",
            err=True,
        )
        raise typer.Exit(128 + int(getattr(signal, name)))
    if json_out:
        return
    typer.echo(
        f"{summary.model}: done at t = {summary.t:.6g} ({summary.units}), "
        f"{_count(summary.events, 'event')}, {_count(summary.snapshots, 'snapshot')}, "
        f"{summary.wall_s:.2f} s -> {summary.out}"
    )


@app.command("plot")
def plot_cmd(
    out: Annotated[Path, typer.Argument(help="A run output (.nc or .zarr).")],
    outdir: Annotated[
        Path | None, typer.Option("-o", "--outdir", help="Where to write (default: beside OUT).")
    ] = None,
    fmt: Annotated[str, typer.Option("--format", help="png, svg or pdf.")] = "png",
):
    """The standard pictures of a run: space-time diagrams, profiles, trajectories, catalog."""
    from .plot import plot_run

    try:
        files = plot_run(out, outdir, fmt=fmt)
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    for f in files:
        typer.echo(str(f))


@app.command()
def front(
    u_plus: Annotated[float, typer.Option("--u-plus", help="Stress ahead, 0 < U < 1.")],
    gamma: Annotated[float, typer.Option("--gamma", help="Viscous damping gamma >= 0.")],
    dx: Annotated[float, typer.Option("--dx", help="Lattice spacing, 0 < DX < 1.")],
    blocks: Annotated[
        int | None,
        typer.Option(
            "--blocks",
            help="Chain length (default: from the pulse's w and c, see above). A given "
            "length is one run, the window as far from the trigger as the end allows.",
        ),
    ] = None,
    beta: Annotated[
        float,
        typer.Option(
            "--beta",
            help="f_s/(f_r - f_s): backward slip when u - Lap u/dx^2 <= -(1 + 2 beta). "
            "Default inf: no backward slip, the paper's model.",
        ),
    ] = math.inf,
    json_out: JsonOpt = False,
):
    """One front in a direct simulation of the discrete chain at v = 0.

    Uniform u_+ on a free chain, block 0 kicked forward; c from the slip times
    of a window of blocks, w and u_- from their re-sticking. Regime: pulse (a
    steady healing front: sliding times and re-stick stresses agree to 1e-3),
    creep (none), or undecided (the reason is printed); "steady" prints the
    spread.

    Default chain length: the trigger's transient can reach the healing front
    at x only if x < x_s = w v/(c - v) (v: the fastest lattice wave, < 1), so
    the window starts 2 x_s from the trigger (of the cases measured in
    docs/chain.md 9 of 10 are steady to 1e-6 there, a narrow undamped pulse to
    8e-4). The chain is sized from App. B's w and c, then re-run (at most
    twice) from the measured ones, further out while the spread exceeds 1e-6:
    typically 500-5000 blocks and under a second; near u_+ = gamma ~2e4 blocks
    and ~10 s.
    Without an App. B pulse (u_+ <= gamma): 1600 blocks (at least 40 units).
    """
    from .chain import front as measure

    try:
        m = measure(u_plus, gamma, dx, blocks, beta=beta)
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    d = {k: _json_value(v) for k, v in m.to_dict().items()}
    d["beta"] = "inf" if math.isinf(m.beta) else m.beta  # JSON has no inf (null: unknown)
    if json_out:
        typer.echo(json.dumps(d))
        return
    typer.echo(f"u_plus  = {m.u_plus:.6g}   gamma = {m.gamma:.6g}   dx = {m.dx:.6g}")
    slip = "no backward slip" if math.isinf(m.beta) else "backward slip on"
    typer.echo(f"beta    = {m.beta:g}   ({slip}; {m.backward_slips} backward slips)")
    typer.echo(f"blocks  = {m.blocks}   ({m.passes} run{'s' if m.passes > 1 else ''})")
    typer.echo(f"c       = {m.c:.12g}   (measured; continuum 1/sqrt(1 - u_plus^2))")
    typer.echo(f"regime  = {m.regime}")
    if m.regime == "pulse":
        typer.echo(f"w       = {m.w:.6g}   (pulse width)")
        typer.echo(f"u_minus = {m.u_minus:.6g}   (stress behind)")
    steady = "-" if m.steadiness is None else f"{m.steadiness:.2g}"
    xs = "-" if m.settling_length is None else f"{m.settling_length:.4g}"
    typer.echo(
        f"steady  = {steady}   (spread of sliding times and re-stick u over the window x = "
        f"{m.window[0]:.4g}-{m.window[1]:.4g}; settling length x_s = {xs})"
    )
    typer.echo(f"why     : {m.reason}")
    if m.app_b is not None:
        b = m.app_b
        shape = (
            f"c = {b['c']:.6g}, w = {b['w']:.6g}, u_minus = {b['u_minus']:.6g}"
            if b["regime"] == "pulse"
            else f"c = {b['c']:.6g}"
        )
        typer.echo(f"App. B  : {b['regime']}, {shape}   (continuum, dx -> 0)")
    typer.echo(f"wall    = {m.wall_s:.3g} s")


@app.command("sweep")
def sweep_cmd(
    sweep_file: Annotated[Path, typer.Argument(help="A sweep description (SWEEP.toml).")],
    out: Annotated[
        Path | None,
        typer.Option(
            "-o", "--out", help="Output Zarr store (default: SWEEP.zarr beside the file)."
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler", help="Address of a running Dask scheduler (default: a local cluster)."
        ),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option("--workers", help="Workers of the local cluster (default: one per core)."),
    ] = None,
    threads: Annotated[
        bool,
        typer.Option(
            "--threads",
            help="Local cluster of threads in this process instead of worker processes.",
        ),
    ] = False,
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="Replace an existing sweep store at OUT.")
    ] = False,
    retry_failed: Annotated[
        bool, typer.Option("--retry-failed", help="Recompute points that failed before.")
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", help="No progress bar.")] = False,
    json_out: JsonOpt = False,
):
    """A parameter sweep on Dask: every point of SWEEP.toml's axes is one task, the
    summaries go into one Zarr store (an xarray Dataset indexed by the axes) as points
    finish. Re-running computes only the points not yet done; Ctrl-C keeps every
    finished point. See docs/sweeps.md for the schema."""
    from .sweeps import sweep

    try:
        r = sweep(
            sweep_file,
            out,
            scheduler=scheduler,
            workers=workers,
            processes=not threads,
            overwrite=overwrite,
            retry_failed=retry_failed,
            progress=not quiet and not json_out,
        )
    except (ParameterError, ConvergenceError) as e:
        _fail(e)
    d = r.to_dict()
    if json_out:
        typer.echo(json.dumps(d, default=str))
    else:
        typer.echo(
            f"sweep: {d['points']} points ({r.computed} computed, {r.skipped} already done, "
            f"{r.failed} failed) in {r.wall_s:.1f} s -> {r.out}"
        )
    if r.interrupted:
        typer.echo(
            "interrupted: finished points are kept; run the same command again to compute the rest",
            err=True,
        )
        raise typer.Exit(143 if r.signal == signal.SIGTERM else 130)


def main():  # entry point
    # pictures are written to files: draw off-screen unless the user chose a backend
    os.environ.setdefault("MPLBACKEND", "Agg")
    app()


if __name__ == "__main__":
    main()
