"""bkwaves: traveling slip waves in the Burridge-Knopoff chain with Coulomb friction.

>>> import bkwaves as bk
>>> bk.front_speed(0.6)
1.25

``import bkwaves`` loads only the compiled core: every other name (``bk.Chain``,
``bk.run``, ``bk.config``, ...) imports its module on first use (PEP 562), so the
command line and scripts that need one function do not pay for the rest.
"""

from __future__ import annotations

import sys as _sys

_cmd = getattr(_sys, "orig_argv", [])
if (_sys.argv and _sys.argv[0].replace("\\", "/").rsplit("/", 1)[-1] == "bkwaves") or (
    "-m" in _cmd and _cmd[_cmd.index("-m") + 1 :][:1] == ["bkwaves"]
):
    # the command line: a signal from its first line on is answered (bkwaves._signals)
    from . import _signals

    _signals.install_early()

import importlib  # noqa: E402
from typing import TYPE_CHECKING  # noqa: E402

from . import _core  # noqa: E402
from ._core import ConvergenceError, ParameterError  # noqa: E402

__version__ = _core.__version__

# public name -> (submodule, attribute in it); a submodule itself is reached as bk.NAME
_LAZY = {
    "Chain": ("chain", "Chain"),
    "ChainResult": ("chain", "ChainResult"),
    "FreeBoundary": ("free_boundary", "FreeBoundary"),
    "FreeBoundaryResult": ("free_boundary", "FreeBoundaryResult"),
    "FreeBoundary2D": ("free_boundary_2d", "FreeBoundary2D"),
    "FreeBoundary2DResult": ("free_boundary_2d", "FreeBoundary2DResult"),
    "NoCreepWarning": ("free_boundary", "NoCreepWarning"),
    "Lattice": ("lattice", "Lattice"),
    "LatticeResult": ("lattice", "LatticeResult"),
    "load": ("io", "load"),
    "Params": ("params", "Params"),
    "PhysicalUnits": ("params", "PhysicalUnits"),
    "RunResult": ("runner", "RunResult"),
    "run": ("runner", "simulate"),
    "sweep": ("sweeps", "sweep"),
    "sweep_result": ("sweeps", "load_sweep_result"),
    "TravelingWave": ("waves", "TravelingWave"),
    "front_speed": ("waves", "front_speed"),
    "tip_solve": ("waves", "tip_solve"),
    "traveling_wave": ("waves", "traveling_wave"),
}

__all__ = [
    "Chain",
    "ChainResult",
    "ConvergenceError",
    "FreeBoundary",
    "FreeBoundaryResult",
    "FreeBoundary2D",
    "FreeBoundary2DResult",
    "Lattice",
    "LatticeResult",
    "NoCreepWarning",
    "ParameterError",
    "Params",
    "PhysicalUnits",
    "RunResult",
    "TravelingWave",
    "__version__",
    "config",
    "disorder",
    "friction",
    "front_speed",
    "io",
    "lattice",
    "load",
    "noise",
    "plot",
    "presets",
    "run",
    "stats",
    "sweep",
    "sweep_result",
    "theory",
    "tip_solve",
    "traveling_wave",
    "velocity_weakening",
]


def __getattr__(name: str):
    if name in _LAZY:
        module, attr = _LAZY[name]
        value = getattr(importlib.import_module(f".{module}", __name__), attr)
        globals()[name] = value  # later look-ups do not come back here
        return value
    if name.isidentifier() and not name.startswith("__"):
        # any submodule (bk.chain, bk.runner, bk.sweeps, ...): importing it binds it here
        try:
            return importlib.import_module(f".{name}", __name__)
        except ModuleNotFoundError as e:
            if e.name != f"{__name__}.{name}":
                raise  # the submodule exists but one of its own imports is missing
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # what the names are, for type checkers and editors
    from . import (
        config,
        disorder,
        friction,
        io,
        lattice,
        noise,
        plot,
        presets,
        stats,
        theory,
        velocity_weakening,
    )
    from .chain import Chain, ChainResult
    from .free_boundary import FreeBoundary, FreeBoundaryResult, NoCreepWarning
    from .io import load
    from .lattice import Lattice, LatticeResult
    from .params import Params, PhysicalUnits
    from .runner import RunResult
    from .runner import simulate as run
    from .sweeps import load_sweep_result as sweep_result
    from .sweeps import sweep
    from .waves import TravelingWave, front_speed, tip_solve, traveling_wave
