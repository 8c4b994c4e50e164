"""Type stubs of the compiled module ``bkwaves._core`` (crates/bkwaves-py).

Checked against the extension by ``python -m mypy.stubtest bkwaves._core`` in CI.
Quantities are the paper's dimensionless ones (Muratov 1999, eq. dimless).
"""

from typing import Any, Literal, final

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "__version__",
    "ParameterError",
    "ConvergenceError",
    "ChainEngine",
    "front_measure",
    "friction_laws",
    "friction_resolve",
    "boundaries",
    "integrators",
    "triggers",
    "slip_causes",
    "defaults",
    "FreeBoundaryEngine",
    "FreeBoundary2DEngine",
    "front_speed",
    "u_plus_of_speed",
    "lattice_front_speed",
    "critical_stress",
    "traveling_wave",
    "wave_profile",
    "wave_from_speed",
    "gamma_tilde",
    "tip_march",
    "tip_solve_speed",
    "tip_solve_u_plus",
]

__version__: str

_F = NDArray[np.float64]

class ParameterError(ValueError):
    """A parameter is out of its allowed range or not finite."""

class ConvergenceError(RuntimeError):
    """A numerical method did not reach its tolerance."""

# ---------------------------------------------------------------- closed forms (theory.rs)
def front_speed(u_plus: ArrayLike) -> _F: ...
def lattice_front_speed(u_plus: ArrayLike, dx: float) -> _F: ...
def u_plus_of_speed(c: ArrayLike) -> _F: ...
def critical_stress(gamma: float) -> float | None: ...
def traveling_wave(u_plus: float, gamma: float) -> dict[str, Any]: ...
def wave_profile(u_plus: float, gamma: float, z: ArrayLike, c: float | None = None) -> _F: ...
def gamma_tilde(c: ArrayLike, gamma: float) -> _F: ...
def wave_from_speed(u_plus: ArrayLike, c: ArrayLike, gamma: float) -> tuple[_F, _F]: ...

# ---------------------------------------------------------------- tip problem (tip.rs)
def tip_solve_speed(
    c: float,
    degree: int = 16,
    decay: float = 40.0,
    dx: float = 0.0,
    gamma: float = 0.0,
    chain_domain: bool = True,
) -> dict[str, Any]: ...
def tip_solve_u_plus(
    u_plus: float,
    degree: int = 16,
    decay: float = 40.0,
    dx: float = 0.0,
    gamma: float = 0.0,
    chain_domain: bool = True,
) -> dict[str, Any]: ...
def tip_march(
    u_plus: float,
    threshold: NDArray[np.float64],
    dx: float,
    gamma: float,
    behind: int = 64,
    step: float = 0.5,
    order: int = 20,
) -> dict[str, Any]: ...

# ---------------------------------------------------------------- the chain (chain.rs)
def front_measure(
    u_plus: float,
    dx: float,
    blocks: int,
    step: float = ...,
    law: str = "coulomb",
    friction: dict[str, float] | None = None,
    window: tuple[float, float] = ...,
    heal: bool = True,
) -> dict[str, Any]: ...
def friction_laws() -> list[dict[str, Any]]: ...
def friction_resolve(
    law: str, params: dict[str, float] | None = None, partial: bool = False
) -> dict[str, float]: ...
def boundaries() -> list[dict[str, str]]: ...
def integrators() -> list[dict[str, Any]]: ...
def triggers() -> list[dict[str, str]]: ...
def slip_causes() -> list[dict[str, str]]: ...
def defaults() -> dict[str, Any]: ...

@final
class ChainEngine:
    """A chain of blocks with a registered friction law, advanced event by event."""

    def __new__(
        cls,
        u0: NDArray[np.float64],
        dx: float,
        v: float,
        step: float,
        law: str = "coulomb",
        friction: dict[str, float] | None = None,
        boundary: str = "free",
        fixed: tuple[float, float] = ...,
        u_t0: NDArray[np.float64] | None = None,
        threshold: NDArray[np.float64] | None = None,
        mass: NDArray[np.float64] | None = None,
        loader: NDArray[np.float64] | None = None,
        coupling: NDArray[np.float64] | None = None,
        shape: tuple[int, int] | None = None,
        dy: float | None = None,
        boundary_y: str = "free",
        fixed_y: tuple[float, float] = ...,
        coupling_y: NDArray[np.float64] | None = None,
    ) -> ChainEngine: ...
    def friction(self) -> tuple[str, dict[str, float]]: ...
    def thresholds(self) -> _F: ...
    def set_integrator(self, name: str) -> None: ...
    @property
    def integrator(self) -> str: ...
    def set_step_control(self, step_tolerance: float | None = None) -> None: ...
    @property
    def step_tolerance(self) -> float | None: ...
    def set_events(self, mode: str) -> None: ...
    @property
    def events(self) -> str: ...
    @property
    def local_events_unavailable(self) -> str | None: ...
    def local_stats(self) -> dict[str, int]: ...
    def checkpoint(self) -> bytes: ...
    def restore(self, data: bytes) -> None: ...
    def add_trigger(self, t: float, block: int, kind: str, value: float) -> None: ...
    def set_noise(
        self,
        law: str,
        rate: float,
        seed: int,
        kick: float = 0.0,
        phi0: float = ...,
        exponent: float = ...,
        u: list[float] = ...,
        g: list[float] = ...,
    ) -> None: ...
    @property
    def noise_counters(self) -> tuple[int, int] | None: ...
    def add_snapshots(self, times: NDArray[np.float64], every_events: int) -> None: ...
    def advance(
        self, t_end: float, max_events: int, max_steps: int
    ) -> Literal["time", "events", "steps", "long_event"]: ...
    def set_run_limits(self, event_slips: int, event_duration: float, chunk_work: int) -> None: ...
    def set_chunk_wall(self, seconds: float) -> None: ...
    def take_snapshots(self) -> tuple[_F, _F, _F]: ...
    @property
    def open_event(self) -> tuple[int, float] | None: ...
    @property
    def time(self) -> float: ...
    @property
    def n(self) -> int: ...
    @property
    def shape(self) -> tuple[int, int]: ...
    @property
    def n_sliding(self) -> int: ...
    @property
    def events_finished(self) -> int: ...
    @property
    def slips_final(self) -> int: ...
    @property
    def boundary(self) -> str: ...
    def u(self) -> _F: ...
    def u_t(self) -> _F: ...
    def phi(self) -> _F: ...
    def modes(self) -> NDArray[np.int64]: ...
    def energy(self) -> tuple[float, float, float]: ...
    def ledger(self) -> dict[str, float]: ...
    def counters(self) -> dict[str, int]: ...
    def catalog(self, start: int = 0) -> dict[str, NDArray[Any]]: ...
    def slips(self, start: int = 0, stop: int | None = None) -> dict[str, NDArray[Any]]: ...
    def snapshots(self, start: int = 0) -> tuple[_F, _F, _F]: ...

# ---------------------------------------------------------------- free boundary (free_boundary.rs)
@final
class FreeBoundaryEngine:
    def __new__(
        cls,
        x0: float,
        h: float,
        u0: NDArray[np.float64],
        gamma: float,
        v: float,
        boundary: str = "free",
        creep: str = "zero",
        shock_x: NDArray[np.float64] | None = None,
        shock_dir: NDArray[np.int64] | None = None,
        tol: float = 1e-12,
        record_path: bool = True,
        speed_u: NDArray[np.float64] | None = None,
        speed_c: NDArray[np.float64] | None = None,
        threshold: NDArray[np.float64] | None = None,
    ) -> FreeBoundaryEngine: ...
    def advance(
        self, t_stop: float, max_steps: int, max_events: int
    ) -> Literal["time", "steps", "events"]: ...
    def set_chunk_wall(self, seconds: float) -> None: ...
    def set_noise(
        self,
        law: str,
        rate: float,
        seed: int,
        phi0: float = ...,
        exponent: float = ...,
        u: list[float] = ...,
        g: list[float] = ...,
    ) -> None: ...
    @property
    def noise_counters(self) -> tuple[int, int] | None: ...
    def checkpoint(self) -> bytes: ...
    def restore(self, data: bytes) -> None: ...
    @property
    def critical_stress(self) -> float: ...
    def front_speed(self, u_plus: NDArray[np.float64]) -> _F: ...
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def completed_events(self) -> int: ...
    @property
    def n_shocks(self) -> int: ...
    def u_nodes(self) -> _F: ...
    def shocks(self) -> dict[str, NDArray[Any]]: ...
    def events(self, start: int = 0) -> dict[str, NDArray[Any]]: ...
    def path(self, start: int = 0) -> dict[str, Any]: ...

# ------------------------------------------------ free boundary in the plane (free_boundary_2d.rs)
@final
class FreeBoundary2DEngine:
    def __new__(
        cls,
        nx: int,
        ny: int,
        h: float,
        x0: float,
        y0: float,
        u0: NDArray[np.float64],
        gamma: float,
        v: float,
        boundary_x: str = "periodic",
        boundary_y: str = "periodic",
        creep: str = "zero",
        second_order: bool = True,
        record_arrivals: bool = False,
        speed_u: NDArray[np.float64] | None = None,
        speed_c: NDArray[np.float64] | None = None,
        threshold: NDArray[np.float64] | None = None,
        curvature: tuple[float, float] | None = None,
        diagonal_u: NDArray[np.float64] | None = None,
        diagonal_c: NDArray[np.float64] | None = None,
        curvature_theta: NDArray[np.float64] | None = None,
        curvature_d: NDArray[np.float64] | None = None,
    ) -> FreeBoundary2DEngine: ...
    def curvature_at(self, theta: float) -> float | None: ...
    def advance(
        self, t_stop: float, max_steps: int, max_events: int
    ) -> Literal["time", "steps", "events"]: ...
    def set_noise(
        self,
        law: str,
        rate: float,
        seed: int,
        phi0: float = ...,
        exponent: float = ...,
        u: list[float] = ...,
        g: list[float] = ...,
    ) -> None: ...
    @property
    def noise_counters(self) -> tuple[int, int] | None: ...
    def trigger(self, nodes: NDArray[np.int64], times: NDArray[np.float64]) -> int: ...
    def trigger_disk(self, x: float, y: float, radius: float) -> int: ...
    def checkpoint(self) -> bytes: ...
    def restore(self, data: bytes) -> None: ...
    @property
    def critical_stress(self) -> float: ...
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def completed(self) -> int: ...
    @property
    def live(self) -> int: ...
    def u_nodes(self) -> _F: ...
    def last_arrival(self) -> _F: ...
    def arrivals(self, id: int) -> tuple[NDArray[np.int64], _F]: ...
    def ruptures(self, start: int = 0) -> dict[str, Any]: ...
