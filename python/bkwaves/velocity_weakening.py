"""Fronts with velocity-weakening friction: the crossover of the paper's eq. (crit).

The law (``velocity_weakening``, docs/chain.md): while a block slides forward at speed
s over the ground, R(s) = 1/(1 + s/v_f) + 2 gamma s. The paper (Sec. VI) argues that it
acts like the Coulomb law when v_f << dx (eq. crit: V_f << (f_r - f_s)/sqrt(k_c m), i.e.
v_f/dx << 1 in the dimensionless units), and that for v_f >> dx fronts run near the
sound speed, a few lattice spacings wide. :func:`front` measures one front of the
``bkwaves front`` experiment (uniform u_+ at v = 0 on a free chain, block 0 kicked
forward) with this law: its speed, whether it is steady, dies or keeps changing, the
width of the slipping zone and of the weakening zone in lattice spacings.
:func:`crossover` sweeps v_f/dx. The derivations and the tables: docs/velocity_weakening.md.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from . import _validate as V
from .chain import DEFAULT_STEP, run_front
from .friction import law
from .params import Params

__all__ = [
    "VWFront",
    "coulomb_gap_bound",
    "crossover",
    "front",
    "min_friction",
    "v_f_existence",
]


def min_friction(gamma: float, v_f: float) -> float:
    """The lowest friction a sliding block can feel, min over s >= 0 of
    R(s) = 1/(1 + s/v_f) + 2 gamma s: 2 sqrt(2 gamma v_f) - 2 gamma v_f at
    s* = sqrt(v_f/(2 gamma)) - v_f when 2 gamma v_f < 1, else R(0) = 1 (no weakening).

    Parameters
    ----------
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    v_f : float
        Characteristic velocity of the law, > 0 (dimensionless, in units of
        (f_r - f_s)/sqrt(k_p m)).

    Returns
    -------
    float
        min R (dimensionless, in units of f_r - f_s).

    Examples
    --------
    >>> import bkwaves as bk
    >>> round(bk.velocity_weakening.min_friction(0.3, 0.5), 6)   # 2 sqrt(0.3) - 0.3
    0.795445
    >>> bk.velocity_weakening.min_friction(2.0, 1.0)               # 2 gamma v_f >= 1
    1.0
    """
    gamma = V.number("gamma", gamma, lo=0.0)
    v_f = V.number("v_f", v_f, lo=0.0, lo_open=True)
    y = 2.0 * gamma * v_f
    return 2.0 * math.sqrt(y) - y if y < 1.0 else 1.0


def v_f_existence(u_plus: float, gamma: float) -> float:
    """The largest v_f at which a block behind the front can slide against less friction
    than the stress u_+ ahead, min R < u_+ (:func:`min_friction`): v_f* =
    (1 - sqrt(1 - u_+))^2/(2 gamma), independent of dx (inf at gamma = 0). Above it no
    front can run (docs/velocity_weakening.md compares it with the chain).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).

    Returns
    -------
    float
        v_f* (dimensionless, in units of (f_r - f_s)/sqrt(k_p m)).

    Examples
    --------
    At v_f* the lowest friction is u_+ itself:

    >>> import bkwaves as bk
    >>> vw = bk.velocity_weakening
    >>> v_star = vw.v_f_existence(0.6, 0.3)
    >>> round(v_star, 6), round(vw.min_friction(0.3, v_star), 12)
    (0.225148, 0.6)
    """
    if gamma == 0.0:
        return math.inf
    return (1.0 - math.sqrt(1.0 - u_plus)) ** 2 / (2.0 * gamma)


def coulomb_gap_bound(c_coulomb: float, ratio: float) -> float:
    """The derived size of c_Coulomb/c - 1 at v_f/dx = ratio << 1: 2 c_C r ln(1/r).

    A Coulomb block starts with unit acceleration (R drops from 1 to 0 at the slip); a
    velocity-weakening one from R(0) = 1, i.e. from zero acceleration. Pushed by its
    sliding neighbour (phi - 1 ~ t/(c dx)) and with R ~ 1 - s/v_f it grows as
    s = v_f^2 (e^{t/v_f} - 1 - t/v_f)/(c dx): it reaches s = v_f after a delay
    v_f ln(c/r) (phase 1). Then R ~ v_f/s leaves a momentum deficit growing as
    v_f ln(s/v_f), worth at most a further delay v_f ln(1/(c r)) by the time the next
    block slips (s ~ dx/c; phase 2). Each slip interval dx/c grows by the delay, so
    c_C/c - 1 = c_C delay/dx <= 2 c_C r ln(1/r) + O(r) (phase 1 alone: c_C r ln(1/r)).
    docs/velocity_weakening.md compares it with the chain.

    Parameters
    ----------
    c_coulomb : float
        The Coulomb front's speed c_C (units of the sound speed a sqrt(k_c/m)).
    ratio : float
        r = v_f/dx, 0 < r << 1 (dimensionless).

    Returns
    -------
    float
        The bound on c_C/c - 1 (dimensionless).

    Examples
    --------
    A chain at v_f/dx = 0.01 (80 blocks, a quick look) stays within the bound:

    >>> import bkwaves as bk
    >>> c_c = float(bk.front_speed(0.6, dx=0.1, gamma=0.3))
    >>> f = bk.velocity_weakening.front(0.6, 0.3, 0.1, 0.001, length=8.0, weakening=False)
    >>> bound = bk.velocity_weakening.coulomb_gap_bound(c_c, 0.01)
    >>> round(bound, 4), bool(0 < c_c / f.c - 1 < bound)
    (0.1136, True)
    """
    return 2.0 * c_coulomb * ratio * math.log(1.0 / ratio)


#: Stated tolerances of :func:`front`: the change of c (relative), of the slipping zone
#: (relative) and of u_- (absolute) when the chain length is doubled. The default
#: measurement doubles the chain until every change is within these.
TOLERANCE = {"c": 1e-6, "zone": 1e-4, "u_minus": 1e-4}
#: The first chain of the default measurement (x units) and the longest it may build.
START_LENGTH = 20.0
MAX_BLOCKS = 2**18
#: The default measurement stops doubling when the next chain would take longer than this
#: (CPU seconds, estimated from the last one: about 4.5x for each doubling at most).
MAX_SECONDS = 30.0


@dataclass(frozen=True)
class VWFront:
    """One front with velocity-weakening friction (:func:`front`).

    status: "steady" (the front crossed, and c, the slipping zone and u_- changed by less
    than ``tolerance`` when the chain was doubled: ``convergence``), "dies" (the front
    stopped at x = ``reached``), or "undecided" (it crossed, but the doubling had not
    converged within the chain the measurement may build; ``reason`` says what moved).
    c: dx (b - a)/(t_b - t_a) over the window, the third quarter of the longest chain
    (NaN if it died). convergence: the changes from the chain half as long to this one
    (c and zone relative, u_minus absolute; None where not measured on both), the
    error estimate of the answer (the approach is exponential in x: the error of the
    longer chain is well below the change). lengths: the chain lengths run.
    unsteadiness: largest |interval c/dx - 1| in the window. trend: c over the window's
    second half over c over its first half, minus 1. zone: the slipping zone in lattice
    spacings, c x (mean time a window block slides)/dx (None if the window blocks still
    slide when the tip reaches the far end); u_minus: their mean u when that slip ends
    (the stress behind the pulse). weakening: the weakening zone in lattice spacings, c/dx
    times the time a block takes from its slip to s = v_f (friction halfway down; the
    first window block, from a second run with dense snapshots). peak: its largest speed
    in the WEAKENING_SPAN slip intervals after its slip, in units of v_f.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_c) (dimensionless).
    v_f : float
        Characteristic velocity of the law (dimensionless, units of
        (f_r - f_s)/sqrt(k_p m)).
    blocks : int
        Blocks of the longest chain.
    status : {"steady", "dies", "undecided"}
        What the front did.
    c : float
        Its speed (units of the sound speed a sqrt(k_c/m); NaN if it died).
    unsteadiness, trend : float or None
        As above (dimensionless).
    zone : float or None
        The slipping zone (lattice spacings).
    u_minus : float or None
        The stress behind the pulse (dimensionless).
    weakening : float or None
        The weakening zone (lattice spacings).
    peak : float or None
        The largest speed after the slip (units of v_f).
    reached : float
        How far the front got (dimensionless x).
    wall_s : float
        Wall time of the measurement (seconds).
    convergence : dict or None
        The changes on doubling (c and zone relative, u_minus absolute).
    lengths : tuple of float
        The chain lengths run (dimensionless x).
    reason : str
        Why the status is "undecided".
    tolerance : dict
        The stated tolerances (``TOLERANCE``).
    slips, backward_slips : int
        Slips of the longest chain, and how many were backward.

    Examples
    --------
    >>> import bkwaves as bk
    >>> f = bk.velocity_weakening.front(0.6, 0.3, 0.1, 0.001, length=8.0, weakening=False)
    >>> f.ratio, f.blocks, f.lengths
    (0.01, 80, (4.0, 8.0))
    """

    u_plus: float
    gamma: float
    dx: float
    v_f: float
    blocks: int
    status: str
    c: float
    unsteadiness: float | None
    trend: float | None
    zone: float | None
    u_minus: float | None
    weakening: float | None
    peak: float | None
    reached: float
    wall_s: float
    convergence: dict | None = None
    lengths: tuple = ()
    reason: str = ""
    tolerance: dict = field(default_factory=lambda: dict(TOLERANCE))
    slips: int = 0
    backward_slips: int = 0

    @property
    def ratio(self) -> float:
        """v_f/dx, the variable of eq. (crit)."""
        return self.v_f / self.dx

    @property
    def converged(self) -> bool:
        """Every change on doubling within the tolerance (False if any is unmeasured)."""
        return _within(self.convergence, self.tolerance)

    def to_dict(self) -> dict:
        """The fields with ``ratio`` and ``converged``, as a dict (for JSON).

        Returns
        -------
        dict
            Field name -> value.

        Examples
        --------
        >>> import bkwaves as bk
        >>> f = bk.velocity_weakening.front(0.6, 0.3, 0.1, 0.001, length=8.0, weakening=False)
        >>> d = f.to_dict()
        >>> d["ratio"], d["status"] == f.status
        (0.01, True)
        """
        return asdict(self) | {"ratio": self.ratio, "converged": self.converged}


def _within(conv: dict | None, tol: dict) -> bool:
    if not conv:
        return False
    # an infinite tolerance: that quantity is not asked for (it may be unmeasured)
    return all(tol[k] == math.inf or (conv.get(k) is not None and conv[k] <= tol[k]) for k in tol)


def _changes(short: dict, long: dict) -> dict:
    """c and zone relative, u_minus absolute (None where either is unmeasured)."""

    def rel(k):
        a, b = short[k], long[k]
        if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
            return None
        return abs(b / a - 1.0)

    um = None
    if short["u_minus"] is not None and long["u_minus"] is not None:
        um = abs(long["u_minus"] - short["u_minus"])
    return {"c": rel("c"), "zone": rel("zone"), "u_minus": um}


def _check_cost(u_plus, gamma, dx, v_f, lengths, step) -> None:
    """Warn (never refuse) when the first two chains are estimated to take over an hour:
    the step is step x min(dx, v_f) (v_f = 1e-9: steps of 5e-11)."""
    from .chain import front_cost
    from .limits import check_wall

    step = V.CHAIN["step"].check(step)
    costs = [front_cost(u_plus, gamma, dx, math.ceil(x / dx), step, law("velocity_weakening",
                        v_f=v_f)) for x in lengths]  # fmt: skip
    work = costs[-1][0]
    check_wall(f"v_f = {v_f:.6g}", sum(c[1] for c in costs), work.notes[0])


def _measure(u_plus, gamma, dx, v_f, length, step, beta=math.inf):
    """One chain ``length`` long: the raw measurement on its third quarter."""
    import time

    n = int(math.ceil(length / dx))
    t0 = time.process_time()
    p = Params(
        gamma=gamma, v=0.0, dx=dx, beta=beta, friction_law=law("velocity_weakening", v_f=v_f)
    )
    ch, first, _ = run_front(u_plus, n, p, step=step)
    a, b = n // 2, (3 * n) // 4
    wall = time.process_time() - t0
    slipped = np.nonzero(np.isfinite(first))[0]
    reached = float(slipped.max() * dx) if slipped.size else 0.0
    slips = ch._engine.slips()
    out = dict(n=n, a=a, b=b, p=p, first=first, reached=reached, wall=wall, length=length)
    out["slips"] = int(len(slips["block"]))
    out["backward_slips"] = int(np.sum(np.asarray(slips["direction"]) < 0))
    if not np.isfinite(first[-1]):
        return out | dict(dies=True, c=math.nan, zone=None, u_minus=None)
    c = dx * (b - a) / (first[b] - first[a])
    intervals = np.diff(first[a : b + 1])
    m = (a + b) // 2
    blocks = np.asarray(slips["block"])
    t_start, t_end = np.asarray(slips["t_start"]), np.asarray(slips["t_end"])
    dur, u_end = np.full(n, np.nan), np.full(n, np.nan)
    for i in range(a, b):
        k = np.nonzero((blocks == i) & (t_start == first[i]))[0]
        if k.size:
            dur[i] = t_end[k[0]] - t_start[k[0]]
            u_end[i] = slips["u_end"][k[0]]
    healed = bool(np.all(np.isfinite(dur[a:b])))
    return out | dict(
        dies=False,
        c=float(c),
        unsteadiness=float(np.max(np.abs(intervals * c / dx - 1.0))),
        trend=float((first[m] - first[a]) / (m - a) / ((first[b] - first[m]) / (b - m)) - 1.0),
        zone=float(c * np.mean(dur[a:b]) / dx) if healed else None,
        u_minus=float(np.mean(u_end[a:b])) if healed else None,
    )


def front(
    u_plus: float,
    gamma: float,
    dx: float,
    v_f: float,
    *,
    length: float | None = None,
    step: float = DEFAULT_STEP,
    weakening: bool = True,
    tolerance: dict | None = None,
    max_seconds: float = MAX_SECONDS,
    beta: float = math.inf,
) -> VWFront:
    """Measure one front with velocity-weakening friction: uniform u_+ on a free chain at
    v = 0, block 0 kicked forward; c, the slipping zone and u_- on the third quarter of the
    chain, and how much they changed from a chain half as long (``convergence``).

    By default (``length=None``) the chain starts START_LENGTH long and is doubled until
    c, zone and u_- change by less than ``tolerance`` (default TOLERANCE) or the next chain
    would cost more than ``max_seconds`` of CPU / MAX_BLOCKS blocks (status "undecided", with the
    reason). A given ``length`` is run once, with the chain half as long for the
    convergence report (status "steady" only if that is within the tolerance).
    weakening=False skips the second run that measures the weakening zone.
    docs/velocity_weakening.md.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    dx : float
        Lattice spacing sqrt(k_p/k_c), 0 < dx < 1 (dimensionless).
    v_f : float
        Characteristic velocity of the law, > 0 (dimensionless, in units of
        (f_r - f_s)/sqrt(k_p m)).
    length : float, optional
        Run one chain this long, 32 dx <= length <= 1e5 (dimensionless x); default the
        doubling described above.
    step : float, default DEFAULT_STEP
        Time step of the chain in units of dx (so of dx sqrt(m/k_p)).
    weakening : bool, default True
        Also measure the weakening zone.
    tolerance : dict, optional
        Tolerances by key (``c``, ``zone``, ``u_minus``); default ``TOLERANCE``.
    max_seconds : float, default MAX_SECONDS
        CPU seconds the next doubled chain may take.
    beta : float, default inf
        f_s/(f_r - f_s), >= 0 (dimensionless; inf: no backward slip).

    Returns
    -------
    VWFront
        The front's status, speed, zones and convergence.

    Examples
    --------
    At v_f/dx = 1 the front runs near the sound speed, well below the Coulomb front's
    c = 1.234 (one chain of 80 blocks, a quick look):

    >>> import bkwaves as bk
    >>> f = bk.velocity_weakening.front(0.6, 0.3, 0.1, 0.1, length=8.0, weakening=False)
    >>> round(f.c, 2), f.ratio
    (0.97, 1.0)
    """
    import time

    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    v_f = V.number("v_f", v_f, lo=0.0, lo_open=True)
    tol = dict(TOLERANCE)
    if tolerance is not None:
        unknown = set(tolerance) - set(TOLERANCE)
        if unknown:
            V._fail("tolerance", sorted(unknown)[0], f"keys among {sorted(TOLERANCE)}")
        for k, x in tolerance.items():
            # inf: that quantity is not asked for
            tol[k] = math.inf if x == math.inf else V.number(f"tolerance[{k}]", x, lo=0.0)
    fixed = length is not None
    if fixed:
        length = V.number("length", length, lo=32 * dx, hi=1e5)
        lengths = [length / 2.0, length]
    else:
        start = max(START_LENGTH, 64 * dx)
        lengths = [start / 2.0, start]
    _check_cost(u_plus, gamma, dx, v_f, lengths, step)
    t0 = time.perf_counter()
    runs = [_measure(u_plus, gamma, dx, v_f, x, step, beta) for x in lengths]
    conv = None
    reason = ""
    while True:
        short, long = runs[-2], runs[-1]
        if long["dies"]:
            break
        conv = None if short["dies"] else _changes(short, long)
        if conv is not None and _within(conv, tol):
            break
        nxt = 2.0 * long["length"]
        wall_next = 4.5 * long["wall"]
        if fixed or nxt / dx > MAX_BLOCKS or wall_next > max_seconds:
            moved = (
                "the chain half as long died"
                if conv is None
                else ", ".join(
                    f"{k} by {conv[k]:.2g}" + (f" > {tol[k]:g}" if conv[k] > tol[k] else "")
                    if conv[k] is not None
                    else f"{k} unmeasured (the window blocks did not re-stick)"
                    for k in tol
                )
            )
            limit = (
                "at the given length"
                if fixed
                else f"and a chain {nxt:g} long would exceed "
                + (
                    f"MAX_BLOCKS = {MAX_BLOCKS}"
                    if nxt / dx > MAX_BLOCKS
                    else f"max_seconds = {max_seconds:g} s of CPU (about {wall_next:.2g} s)"
                )
            )
            reason = (
                f"not converged: doubling the chain from {short['length']:g} to "
                f"{long['length']:g} moved {moved} {limit}"
            )
            break
        runs.append(_measure(u_plus, gamma, dx, v_f, nxt, step, beta))
    last = runs[-1]
    n, a = last["n"], last["a"]
    common = dict(
        u_plus=u_plus,
        gamma=gamma,
        dx=dx,
        v_f=v_f,
        blocks=n,
        reached=last["reached"],
        lengths=tuple(r["length"] for r in runs),
        tolerance=tol,
        slips=last["slips"],
        backward_slips=last["backward_slips"],
    )
    if last["dies"]:
        return VWFront(
            **common,
            status="dies",
            c=math.nan,
            unsteadiness=None,
            trend=None,
            zone=None,
            u_minus=None,
            weakening=None,
            peak=None,
            wall_s=time.perf_counter() - t0,
            reason=f"the front stopped at x = {last['reached']:.4g} on a chain "
            f"{last['length']:g} long",
        )
    status = "steady" if not reason else "undecided"
    if status == "steady":

        def moved(k):
            return "unmeasured" if conv[k] is None else f"{conv[k]:.1e}"

        reason = (
            f"converged: doubling the chain from {runs[-2]['length']:g} to "
            f"{last['length']:g} moved c by {moved('c')}, the zone by {moved('zone')}, "
            f"u_- by {moved('u_minus')}"
        )
    weak = peak = None
    if weakening:
        weak, peak = _weakening(u_plus, n, last["p"], step, a, last["first"][a], last["c"], v_f)
    return VWFront(
        **common,
        status=status,
        c=last["c"],
        unsteadiness=last["unsteadiness"],
        trend=last["trend"],
        zone=last["zone"],
        u_minus=last["u_minus"],
        weakening=weak,
        peak=peak,
        wall_s=time.perf_counter() - t0,
        convergence=conv,
        reason=reason,
    )


#: The weakening zone is looked for within this many slip intervals dx/c of the onset,
#: sampled at WEAKENING_SAMPLES per interval.
WEAKENING_SPAN = 8
WEAKENING_SAMPLES = 64


def _weakening(u_plus, n, p, step, k, t_k, c, v_f):
    """(weakening zone, peak speed/v_f) of block k, which slips at t_k: the same run
    again with dense snapshots after t_k (the front is steady, so every block has the
    same history). The zone is c (t(s = v_f) - t_k)/dx, with t(s = v_f) interpolated
    linearly between samples dx/(c WEAKENING_SAMPLES) apart; None if s stays below v_f."""
    tau = p.dx / c
    times = t_k + tau * np.arange(WEAKENING_SPAN * WEAKENING_SAMPLES + 1) / WEAKENING_SAMPLES
    _, _, (t, u_t) = run_front(u_plus, n, p, step=step, t_end=times[-1], snapshots=times)
    s = -u_t[:, k]
    above = np.nonzero(s >= v_f)[0]
    if not above.size:
        return None, float(np.max(s) / v_f)
    j = int(above[0])
    t_vf = t[j] if j == 0 else t[j - 1] + (t[j] - t[j - 1]) * (v_f - s[j - 1]) / (s[j] - s[j - 1])
    return float((t_vf - t_k) / tau), float(np.max(s) / v_f)


def crossover(u_plus, gamma, dx, ratios, *, length: float | None = None) -> list[VWFront]:
    """:func:`front` at v_f = ratio dx for each ratio (v_f/dx).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    ratios : iterable of float
        The values of v_f/dx (dimensionless).
    length : float, optional
        As in :func:`front` (dimensionless x).

    Returns
    -------
    list of VWFront
        One front per ratio.

    Examples
    --------
    The speed falls from near the Coulomb value towards the sound speed as v_f/dx grows:

    >>> import bkwaves as bk
    >>> fronts = bk.velocity_weakening.crossover(0.6, 0.3, 0.1, [0.01, 1.0], length=8.0)
    >>> [round(f.c, 2) for f in fronts]
    [1.18, 0.97]
    """
    return [front(u_plus, gamma, dx, r * dx, length=length) for r in ratios]
