"""Beyond the paper: figures of what Sec. VI leaves open, in ``bkwaves paper``.

The paper closes by naming what it does not answer: blocks that are not all alike
(quenched disorder and the renormalised front speed), velocity-weakening friction and its
continuum limit (eq. crit), and noise-triggered slips. bkwaves answers these with its own
engines; the answers are bkwaves' results, not claims of the paper, so they are reported
in their own section of ``report.md``/``report.html`` ("Beyond the paper"), after the
paper's figures.

A figure is one module here: a drawing function ``draw(axes[, quick]) -> caption``
registered with ``@register_figure(name, panels, beyond=True)``
(:func:`bkwaves.paper.figure.register_figure`), using only the public helpers of
:mod:`bkwaves.paper.common` and :mod:`bkwaves.paper.figure`, and its name in
:data:`bkwaves.paper.MODULES`. Its caption is computed from the data drawn (no literal
numbers), and ``quick=True`` must keep ``bkwaves paper --quick`` fast (CI runs it).
"""
