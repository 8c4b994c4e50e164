"""How a figure of ``bkwaves paper`` is drawn, saved and registered.

A figure is a drawing function ``draw(axes[, quick]) -> caption``: it draws into the
panels it is handed (one axes, or a row of them) and returns its caption, computed from
what it drew. :func:`register_figure` turns it into a builder (:func:`panels`: a row of
panels, saved as PNG and PDF by :func:`save`) and records it under its file name, in the
paper's section or the "Beyond the paper" one; :func:`register_claims` records a function
``claims(quick) -> Claim | list[Claim]`` with its place in the report. The package
:mod:`bkwaves.paper` builds ``FIGURES``, ``BEYOND_FIGURES`` and ``CLAIMS`` from these
records.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

__all__ = [
    "FIGURE_FORMATS",
    "save",
    "panels",
    "register_figure",
    "register_claims",
    "registered_figures",
    "registered_claims",
]

#: The formats every figure is written in.
FIGURE_FORMATS = ("png", "pdf")

#: Registered figure builders by section ("paper", "beyond"): name -> builder, in the
#: order they were registered.
_FIGURES: dict[str, dict[str, Callable]] = {"paper": {}, "beyond": {}}
#: Registered claim groups: rank -> function(quick).
_CLAIMS: dict[int, Callable] = {}


def save(fig, out, name: str) -> list[Path]:
    """Write ``fig`` as ``name``.png and .pdf into ``out`` (an OwnedFiles, or a folder),
    each file whole (written beside, then renamed); the figure is closed.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    out : str or pathlib.Path or OwnedFiles
        The folder (or the owned-files record of ``reproduce``).
    name : str
        The file name without extension.

    Returns
    -------
    list of pathlib.Path
        The files written, one per ``FIGURE_FORMATS``.

    Examples
    --------
    >>> import tempfile
    >>> import matplotlib.pyplot as plt
    >>> from bkwaves.paper.figure import save
    >>> fig, ax = plt.subplots()
    >>> [p.name for p in save(fig, tempfile.mkdtemp(), "sketch")]
    ['sketch.png', 'sketch.pdf']
    """
    from .._paths import OwnedFiles, write_atomic

    paths = []
    try:
        for ext in FIGURE_FORMATS:

            def draw(p, ext=ext):
                fig.savefig(p, dpi=150, format=ext)

            fname = f"{name}.{ext}"
            if isinstance(out, OwnedFiles):
                paths.append(out.write(fname, draw))
            else:
                paths.append(write_atomic(Path(out) / fname, draw))
    finally:
        plt.close(fig)
    return paths


def panels(draw: Callable, n: int = 1) -> Callable:
    """A figure builder ``make(out, quick, name) -> (written paths, caption)``: ``n``
    panels side by side handed to ``draw(ax_or_axes[, quick])``, which returns the
    caption; saved by :func:`save` (looked up when the figure is made, so that a test
    can wrap it).

    Parameters
    ----------
    draw : callable
        ``draw(ax_or_axes[, quick]) -> caption``.
    n : {1, 2, 3}, default 1
        Panels side by side.

    Returns
    -------
    callable
        ``make(out, quick, name) -> (paths, caption)``.

    Examples
    --------
    >>> import os, tempfile
    >>> from bkwaves.paper.figure import panels
    >>> make = panels(lambda axes: f"{len(axes)} panels", n=2)
    >>> paths, caption = make(tempfile.mkdtemp(), True, "pair")
    >>> caption, [p.name for p in paths]
    ('2 panels', ['pair.png', 'pair.pdf'])
    """
    if n not in (1, 2, 3):
        raise ValueError(f"panels: n = {n!r}, must be 1, 2 or 3")

    def make(out, quick, name):
        width = {1: 6.0, 2: 11.0, 3: 15.5}[n]
        fig, axes = plt.subplots(
            1, n, figsize=(width, 4.0 if n == 1 else 4.2), constrained_layout=True
        )
        if "quick" in draw.__code__.co_varnames:
            caption = draw(axes, quick)
        else:
            caption = draw(axes)
        return save(fig, out, name), caption

    make.draw = draw  # the drawing function, for readers and tests
    return make


def register_figure(name: str, n: int = 1, *, beyond: bool = False) -> Callable:
    """Decorator: record ``draw(axes[, quick]) -> caption`` as the figure ``name`` (its
    file name without extension) of ``n`` panels, in the paper's section or, with
    ``beyond=True``, in "Beyond the paper". Returns ``draw`` unchanged.

    Parameters
    ----------
    name : str
        The figure's file name without extension (unique).
    n : {1, 2, 3}, default 1
        Panels side by side.
    beyond : bool, default False
        Register it in "Beyond the paper".

    Returns
    -------
    callable
        The decorator.

    Examples
    --------
    A name can be registered once:

    >>> import bkwaves.paper
    >>> from bkwaves.paper.figure import register_figure
    >>> register_figure("fig3_speed")(lambda ax: "again")
    Traceback (most recent call last):
    ...
    ValueError: register_figure: a figure named 'fig3_speed' is already registered
    """
    section = _FIGURES["beyond" if beyond else "paper"]

    def record(draw: Callable) -> Callable:
        if any(name in s for s in _FIGURES.values()):
            raise ValueError(f"register_figure: a figure named {name!r} is already registered")
        section[name] = panels(draw, n)
        return draw

    return record


def register_claims(rank: int) -> Callable:
    """Decorator: record ``claims(quick) -> Claim | list[Claim]``; its rows appear in the
    report in increasing ``rank`` (the groups of the paper: 10, 20, ..., 140). Returns the
    function unchanged.

    Parameters
    ----------
    rank : int
        The group's place in the report (unique).

    Returns
    -------
    callable
        The decorator.

    Examples
    --------
    >>> import bkwaves.paper
    >>> from bkwaves.paper.figure import register_claims
    >>> register_claims(10)(lambda quick: [])
    Traceback (most recent call last):
    ...
    ValueError: register_claims: rank 10 is taken by claim_speed_interpolation; choose another
    """

    def record(fn: Callable) -> Callable:
        if rank in _CLAIMS:
            raise ValueError(
                f"register_claims: rank {rank} is taken by {_CLAIMS[rank].__name__}; choose another"
            )
        _CLAIMS[rank] = fn
        return fn

    return record


def registered_figures(section: str = "paper") -> dict[str, Callable]:
    """The figure builders of ``section`` ("paper" or "beyond"), in registration order.

    Parameters
    ----------
    section : {"paper", "beyond"}, default "paper"
        Which section.

    Returns
    -------
    dict
        Figure name -> builder (:func:`panels`).

    Examples
    --------
    >>> import bkwaves.paper
    >>> from bkwaves.paper.figure import registered_figures
    >>> list(registered_figures())[:3], list(registered_figures("beyond"))[:1]
    (['fig1_model', 'fig2_friction', 'fig3_speed'], ['beyond_disorder_speed'])
    """
    if section not in _FIGURES:
        raise ValueError(f"registered_figures: section = {section!r}, must be 'paper' or 'beyond'")
    return dict(_FIGURES[section])


def registered_claims() -> list[Callable]:
    """The claim groups in report order (increasing rank).

    Returns
    -------
    list of callable
        ``claims(quick) -> Claim | list[Claim]``, in report order.

    Examples
    --------
    >>> import bkwaves.paper
    >>> from bkwaves.paper.figure import registered_claims
    >>> [f.__name__ for f in registered_claims()][:2]
    ['claim_speed_interpolation', 'claim_c1']
    """
    return [_CLAIMS[k] for k in sorted(_CLAIMS)]
