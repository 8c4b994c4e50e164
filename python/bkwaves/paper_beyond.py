"""Beyond the paper: figures of what Sec. VI leaves open, in ``bkwaves paper``.

The paper closes by naming what it does not answer: blocks that are not all alike
(quenched disorder and the renormalised front speed), velocity-weakening friction and its
continuum limit (eq. crit), and noise-triggered slips. bkwaves answers these with its own
engines; the answers are bkwaves' results, not claims of the paper, so they are reported
in their own section of ``report.md``/``report.html`` ("Beyond the paper"), after the
paper's figures.

A figure is one builder plus one line in :data:`BEYOND_FIGURES`. A builder has the
signature of the paper's figures, ``builder(outdir, quick, name) -> (paths, caption)``;
:func:`bkwaves.paper._panels` turns a function ``draw(axes[, quick]) -> caption`` into one.
Its caption is computed from the data drawn (no literal numbers), and ``quick=True`` must
keep ``bkwaves paper --quick`` fast (CI runs it).
"""

from __future__ import annotations

from collections.abc import Callable

__all__ = ["BEYOND_FIGURES"]

#: Figure builders of the "Beyond the paper" section: name -> builder(outdir, quick, name).
BEYOND_FIGURES: dict[str, Callable] = {}
