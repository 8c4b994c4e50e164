"""Input checks shared by the Python package: every message names the parameter,
its value and the allowed range, and raises :class:`bkwaves.ParameterError`."""

from __future__ import annotations

import math

import numpy as np

from ._core import ParameterError


def _fail(name: str, value, allowed: str):
    raise ParameterError(f"invalid {name} = {value!r}: allowed {allowed}")


def number(name: str, value, *, lo=None, hi=None, lo_open=False, hi_open=False) -> float:
    """A finite real scalar inside [lo, hi] (ends open when asked)."""
    allowed = _range_text(name, lo, hi, lo_open, hi_open)
    if isinstance(value, bool):
        _fail(name, value, allowed)
    try:
        x = float(value)
    except (TypeError, ValueError):
        _fail(name, value, allowed)
    if not math.isfinite(x):
        _fail(name, value, allowed)
    if lo is not None and (x < lo or (lo_open and x == lo)):
        _fail(name, value, allowed)
    if hi is not None and (x > hi or (hi_open and x == hi)):
        _fail(name, value, allowed)
    return x


def array(name: str, value, *, lo=None, hi=None, lo_open=False, hi_open=False) -> np.ndarray:
    """A float array whose every element is finite and inside the range."""
    allowed = _range_text(name, lo, hi, lo_open, hi_open)
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        _fail(name, value, allowed)
    bad = ~np.isfinite(a)
    if lo is not None:
        bad |= (a <= lo) if lo_open else (a < lo)
    if hi is not None:
        bad |= (a >= hi) if hi_open else (a > hi)
    if np.any(bad):
        _fail(name, a[bad].flat[0].item(), allowed)
    return a


def _range_text(name, lo, hi, lo_open, hi_open) -> str:
    if lo is not None and hi is not None:
        return f"{lo} {'<' if lo_open else '<='} {name} {'<' if hi_open else '<='} {hi}"
    if lo is not None:
        return f"{name} {'>' if lo_open else '>='} {lo}"
    if hi is not None:
        return f"{name} {'<' if hi_open else '<='} {hi}"
    return "a finite number"
