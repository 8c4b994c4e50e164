"""Reproduce the paper: every figure and a claim-by-claim validation report.

``bkwaves paper -o DIR`` calls :func:`reproduce`. Each figure is written as PNG and PDF
with a caption; ``DIR/report.md`` and ``DIR/report.html`` list every quantitative claim of
the paper with bkwaves' value, the paper's, and the verdict. Claims are checked against
bkwaves' own engines (tip solver, ODE solutions, and the chain and free-boundary engines),
never against the formulas being checked.

No verdict is written by hand: a :class:`~bkwaves.report.Claim` carries the
:class:`~bkwaves.report.Check` s computed in the run, and its verdict is derived from them
(:attr:`~bkwaves.report.Claim.verdict`); :mod:`bkwaves.report` writes the report. A row
whose content holds by definition or by construction is an ``identity``; it still carries
a check, which only a broken engine can fail.

Where things live: each figure of the paper is one module (``fig3_speed``, ...,
``fig9_sync``; Figs. 1 and 2 and the claims on no figure in ``model``) holding its
drawing function, registered with :func:`~bkwaves.paper.figure.register_figure`, and the
claims it carries, registered with :func:`~bkwaves.paper.figure.register_claims`; the
figures beyond the paper are the modules of :mod:`bkwaves.paper.beyond`. What they share
is public: :mod:`bkwaves.paper.figure` (panels, saving, the registry) and
:mod:`bkwaves.paper.common` (the report's parameters, the cache of one run, the shared
computations). :data:`MODULES` lists the figure modules in report order; importing them
registers their figures and claims, from which :data:`FIGURES`, :data:`BEYOND_FIGURES`
and :data:`CLAIMS` are built.
"""

from __future__ import annotations

import importlib
import time
from collections.abc import Callable
from pathlib import Path

from ..report import VERDICTS, Check, Claim, Report  # noqa: F401 (re-exported)
from . import figure
from .common import (  # noqa: F401 (re-exported: tests and docs/scripts use them)
    CACHE,
    GAMMA_FB,
    PAPER_BETA,
    SYNC_DECIDE,
    SYNC_FIT_FROM,
    V_CHAIN,
    V_FB,
    coarsening_exponent,
    ring_births,
)
from .figure import FIGURE_FORMATS

# Check, Claim, Report and VERDICTS live in bkwaves.report (importable from here too)
__all__ = ["reproduce", "output_files", "CLAIMS", "FIGURES", "BEYOND_FIGURES", "MODULES"]

#: The figure modules in report order (their figures in this order; the claims in the
#: order of their ranks). Importing one registers its figures and claims. A new figure:
#: one module with its ``@register_figure`` (and ``@register_claims``), one name here.
MODULES = (
    "model",
    "fig3_speed",
    "fig4_waves",
    "fig5_train",
    "fig6_source",
    "fig7_map",
    "fig8_statistics",
    "fig9_sync",
    "beyond.disorder_speed",
    "beyond.vw_crossover",
    "beyond.noise_statistics",
    "beyond.plane_ruptures",
    "beyond.lattice_curvature",
)
for _m in MODULES:
    importlib.import_module(f".{_m}", __name__)
from .fig8_statistics import B_CHAIN_REGULAR_CV  # noqa: E402, F401 (re-exported)

#: Figure builders of the paper: name -> builder(out, quick, name) -> (written paths,
#: caption), ``out`` an OwnedFiles (or a folder) handed to :func:`figure.save`.
FIGURES: dict[str, Callable] = figure.registered_figures("paper")
#: Figure builders of the "Beyond the paper" section, same form.
BEYOND_FIGURES: dict[str, Callable] = figure.registered_figures("beyond")
#: Claim groups in report order: functions (quick) -> Claim | list[Claim].
CLAIMS: list[Callable] = figure.registered_claims()
#: The run's shared computations (:data:`bkwaves.paper.common.CACHE`).
_CACHE = CACHE

#: Facts established by the claims above (each with its row); the run adds findings built
#: from its own numbers (:func:`bkwaves.paper.common.found`).
FINDINGS = [
    "The tip problem of App. A has the closed-form solution c(u_+) = 1/sqrt(1 - u_+^2) "
    "(Wiener-Hopf argument in docs/theory.md; rows c, c1, ca, c>1 check the numerical "
    "solver against it).",
    "Consequently the critical stress of eq. (gammac) is exactly u_c = gamma, and "
    "w = pi u_+^2/(sqrt(1 - u_+^2) sqrt(u_+^2 - gamma^2)), "
    "u_- = -u_+ exp(-pi gamma/sqrt(u_+^2 - gamma^2)) (rows gammac, w, um).",
    "The fourth coefficient of eq. (ca) is 35/128, not the paper's value (row ca4).",
    "At finite dx and gamma = 0 the discrete front speed is "
    "c = dx/(2 u_+ asin(dx sqrt(1 - u_+^2)/(2 u_+))), approaching c(u_+) at order dx^2; "
    "damping makes the approach first order in dx (row dx, Fig. 3).",
    "A wave train selects its amplitude: from uniform stress on a ring, the shocks relax to "
    "the train whose wavelength eq. (L) gives (row L); near L_min a train must start close "
    "to its final amplitude, since the stress a strong first pulse leaves behind it is too "
    "low for the next lap (row Lmin).",
    "The Bristol-board gamma and k_p of Sec. VI follow from the paper's rounding of m and "
    "k_c; the unrounded data give other values (rows bristol-k_p, bristol-gamma), and eq. "
    "(crit) holds only marginally (row crit).",
    "Where two pulses annihilate, the direct chain keeps a dip ('scar') that seeds later "
    "events; the free boundary problem, whose annihilation is a point, cannot: the two "
    "engines agree on each rupture but their long event sequences part ways "
    "(docs/validation.md). The scar carries a lattice-scale pattern in which "
    "phi = u - Lap u/dx^2 exceeds u by an amount that does not shrink with dx (about 1.17 "
    "at gamma = 0.3 after pulses at u_+ = 0.79, at dx = 0.1, 0.05 and 0.025); it fires "
    "while the background is still low, and once that is below u_c = gamma the rupture "
    "creeps and never re-sticks: on rings the overdamped chain ends in endless creep, with "
    "or without noise (docs/noise.md).",
]


#: The manifest of what `bkwaves paper` wrote in its folder (file names and SHA-256):
#: `--overwrite` replaces only those files, unchanged since (bkwaves._paths.OwnedFiles).
MANIFEST = "bkwaves-paper.json"

#: What the "Beyond the paper" section is (report.md and report.html).
BEYOND_INTRO = (
    "What Sec. VI of the paper leaves open or names for comparison (quenched disorder, "
    "velocity-weakening friction, noise-triggered slips), computed by bkwaves' engines. "
    "These are bkwaves' results, not claims of the paper."
)


def output_files() -> list[str]:
    """The names of the files :func:`reproduce` writes into its folder.

    Returns
    -------
    list of str
        One PNG and one PDF per registered figure (the paper's, then those beyond it),
        then ``report.md`` and ``report.html``; the manifest (``bkwaves-paper.json``) is not
        among them.

    Examples
    --------
    >>> from bkwaves.paper import FIGURES, BEYOND_FIGURES, output_files
    >>> names = output_files()
    >>> names[:2], names[-2:]
    (['fig1_model.png', 'fig1_model.pdf'], ['report.md', 'report.html'])
    >>> len(names) == 2 * (len(FIGURES) + len(BEYOND_FIGURES)) + 2
    True
    """
    figures = [f"{n}.{ext}" for n in (*FIGURES, *BEYOND_FIGURES) for ext in FIGURE_FORMATS]
    return [*figures, "report.md", "report.html"]


def reproduce(
    outdir, *, quick: bool = False, progress: bool = True, overwrite: bool = False
) -> Report:
    """Regenerate the figures and the validation report in ``outdir``.

    Like ``bkwaves run``, nothing a user owns is replaced: before any work, an ``outdir``
    that cannot be written, or that already holds one of the files this writes
    (``output_files()``), is refused with a ParameterError, unless ``overwrite``; even
    then only files an earlier ``reproduce`` wrote and nobody changed since (recorded
    with their SHA-256 in ``outdir/bkwaves-paper.json``) are replaced. Other files in
    ``outdir`` are never touched. Every file is written whole (beside, then renamed).

    A full run takes minutes (``quick=True``: shorter runs, about a minute);
    ``bkwaves paper`` calls it.

    Parameters
    ----------
    outdir : str or pathlib.Path
        The folder of the figures and the report.
    quick : bool, default False
        Shorter runs and coarser measurements.
    progress : bool, default True
        Show a progress bar.
    overwrite : bool, default False
        Replace the files an earlier ``reproduce`` wrote.

    Returns
    -------
    bkwaves.report.Report
        Every claim with its verdict, the figures and the findings.

    Raises
    ------
    bkwaves.ParameterError
        An ``outdir`` that cannot be written or holds a file it would write.

    Examples
    --------
    A folder holding a file of the user's is refused before any work:

    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> outdir = tempfile.mkdtemp()
    >>> _ = open(os.path.join(outdir, "report.md"), "w").write("my notes")
    >>> bk.paper.reproduce(outdir, quick=True)
    Traceback (most recent call last):
    ...
    bkwaves._core.ParameterError: ...
    >>> open(os.path.join(outdir, "report.md")).read()
    'my notes'
    """
    from .._paths import OwnedFiles

    out = OwnedFiles(outdir, MANIFEST, command="bkwaves paper")
    out.claim(output_files(), overwrite)
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    CACHE.clear()
    report = Report(findings=list(FINDINGS), beyond_intro=BEYOND_INTRO)
    steps = (
        [("figure", n, f) for n, f in FIGURES.items()]
        + [("beyond", n, f) for n, f in BEYOND_FIGURES.items()]
        + [("claims", c.__name__, c) for c in CLAIMS]
    )
    bar = None
    if progress:
        from rich.progress import Progress

        bar = Progress(transient=True)
        bar.start()
        task = bar.add_task("reproducing the paper", total=len(steps))
    try:
        for kind, name, fn in steps:
            if kind == "figure":
                report.figures[name], report.captions[name] = fn(out, quick, name)
            elif kind == "beyond":
                report.beyond[name], report.captions[name] = fn(out, quick, name)
            else:
                res = fn(quick)
                report.claims.extend(res if isinstance(res, list) else [res])
            if bar is not None:
                bar.advance(task)
    finally:
        if bar is not None:
            bar.stop()
    report.findings += CACHE.get("findings", [])
    report.seconds = time.perf_counter() - t0
    md, page = report.to_markdown(), report.to_html()
    out.write("report.md", lambda p: p.write_text(md, encoding="utf-8"))
    out.write("report.html", lambda p: p.write_text(page, encoding="utf-8"))
    return report
