"""bkwaves: traveling slip waves in the Burridge-Knopoff chain with Coulomb friction.

>>> import bkwaves as bk
>>> bk.front_speed(0.6)
1.25
"""

from . import _core
from ._core import ConvergenceError, ParameterError

__version__ = _core.__version__

from . import config, disorder, friction, io, plot, presets, stats, theory  # noqa: E402
from .chain import Chain, ChainResult  # noqa: E402
from .free_boundary import FreeBoundary, FreeBoundaryResult, NoCreepWarning  # noqa: E402
from .io import load  # noqa: E402
from .params import Params, PhysicalUnits  # noqa: E402
from .runner import RunResult  # noqa: E402
from .runner import simulate as run  # noqa: E402
from .sweeps import load_sweep_result as sweep_result  # noqa: E402
from .sweeps import sweep  # noqa: E402
from .waves import TravelingWave, front_speed, tip_solve, traveling_wave  # noqa: E402

__all__ = [
    "Chain",
    "ChainResult",
    "ConvergenceError",
    "FreeBoundary",
    "FreeBoundaryResult",
    "NoCreepWarning",
    "ParameterError",
    "Params",
    "PhysicalUnits",
    "TravelingWave",
    "__version__",
    "config",
    "disorder",
    "friction",
    "io",
    "load",
    "plot",
    "stats",
    "sweep",
    "sweep_result",
    "front_speed",
    "presets",
    "run",
    "RunResult",
    "theory",
    "tip_solve",
    "traveling_wave",
]
