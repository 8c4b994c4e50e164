"""What the figures and claims of ``bkwaves paper`` share: the model's parameters of the
report, the cache of one run's computations, and the computations themselves.

Every run of :func:`bkwaves.paper.reproduce` empties :data:`CACHE`; a computation used by
several figures or claims (a wave train on a ring, a source, the chain's fronts, the long
catalogs, the synchronisation rings) is made once per run and kept there under its
arguments. Figures beyond the paper import from here, never from the figure modules.
The computations (``fb_train``, ``fb_trains``, ``fb_source``, ``chain_fronts``,
``long_catalogs``, ``ring_births``, ``sync_chaos``) are for figure modules and stay outside
``__all__``: each costs seconds to minutes, and their arguments follow the report.
"""

from __future__ import annotations

import math

import numpy as np

from .. import theory

__all__ = [
    "CACHE",
    "GAMMA_FB",
    "V_FB",
    "V_CHAIN",
    "PAPER_BETA",
    "fb_params",
    "found",
    "rel",
    "selected_u_plus",
    "train_summary",
    "coarsening_exponent",
    "SYNC_RINGS",
    "SHARP_RING",
    "SYNC_BOOTSTRAP",
    "SYNC_DECIDE",
    "SYNC_PREFACTOR_FACTOR",
    "SYNC_FIT_FROM",
]

#: One run's shared computations (emptied by each :func:`bkwaves.paper.reproduce`), and
#: under "findings" the sentences :func:`found` collected.
CACHE: dict = {}

#: gamma and v of the free-boundary runs of the report.
GAMMA_FB, V_FB = 0.3, 1e-2
#: The loading speed of the chain's long catalog.
V_CHAIN = 1e-3


def rel(a, b):
    """|a/b - 1|: the relative difference of a from b.

    Parameters
    ----------
    a, b : float
        Two numbers of one unit.

    Returns
    -------
    float
        |a/b - 1| (dimensionless).

    Examples
    --------
    >>> from bkwaves.paper.common import rel
    >>> round(rel(1.01, 1.0), 12)
    0.01
    """
    return abs(a / b - 1.0)


def found(text: str) -> None:
    """A finding of this run (a sentence built from computed values) for the report.

    Parameters
    ----------
    text : str
        The sentence.

    Examples
    --------
    >>> from bkwaves.paper.common import CACHE, found
    >>> found("c = 1.25 at u_+ = 0.6")
    >>> CACHE["findings"][-1]
    'c = 1.25 at u_+ = 0.6'
    >>> _ = CACHE["findings"].pop()
    """
    CACHE.setdefault("findings", []).append(text)


def fb_params():
    """The free-boundary runs' parameters: gamma = GAMMA_FB, v = V_FB (dx is not used by
    the free boundary engine).

    Returns
    -------
    bkwaves.Params
        gamma, v (dimensionless) and dx = 1e-3.

    Examples
    --------
    >>> from bkwaves.paper.common import fb_params
    >>> p = fb_params()
    >>> p.gamma, p.v
    (0.3, 0.01)
    """
    from ..params import Params

    return Params(gamma=GAMMA_FB, v=V_FB, dx=1e-3)


def selected_u_plus(L: float) -> float:
    """The u_+ of the train of wavelength L: the root of eq. (L), L = c(u_+) A(u_+)/v.

    Parameters
    ----------
    L : float
        The wavelength (dimensionless x).

    Returns
    -------
    float
        u_+ (dimensionless), at gamma = GAMMA_FB and v = V_FB.

    Examples
    --------
    The inverse of ``bk.theory.wavelength``:

    >>> import bkwaves as bk
    >>> from bkwaves.paper.common import GAMMA_FB, V_FB, selected_u_plus
    >>> L = float(bk.theory.wavelength(0.7, GAMMA_FB, V_FB))
    >>> round(selected_u_plus(L), 9)
    0.7
    """
    from scipy.optimize import brentq

    uc = theory.critical_stress(GAMMA_FB)
    return float(
        brentq(lambda u: float(theory.wavelength(u, GAMMA_FB, V_FB)) - L, uc + 1e-12, 1 - 1e-12)
    )


def _passages(r, x, node):
    """Shock passages at grid node ``node``: times, u_+, u_-."""
    nodes = r.shocks[r.shocks.kind == "node"]
    at = nodes[np.isclose(nodes.x, x[node])].sort_values("t")
    return at.t.to_numpy(), at.u_plus.to_numpy(), at.u_minus.to_numpy()


def fb_train(quick: bool, ring: float | None = None, teeth: int = 3, u0: float = 0.5):
    """A wave train that selects itself: a ring (default three wavelengths of the u_+ = 0.7
    train, eq. L) at uniform stress u0 with ``teeth`` equally spaced right-moving shocks.
    Nothing of the answer is put in but the ring length: the first lap sees u_+ = u0 + v t
    and leaves a field that is not a saw-tooth; the run shows what the train becomes.

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).
    ring : float, optional
        The ring's length (dimensionless x).
    teeth : int, default 3
        Shocks on the ring.
    u0 : float, default 0.5
        The uniform initial stress (dimensionless).

    Returns
    -------
    result : bkwaves.FreeBoundaryResult
        The run (cached in ``CACHE``).
    train : dict
        L and the grid (dimensionless x), and the passages at one node: times t (units
        of sqrt(m/k_p)), u_+ and u_- (dimensionless).
    """
    if ring is None:
        ring = teeth * float(theory.wavelength(0.7, GAMMA_FB, V_FB))
    key = ("train", quick, ring, teeth, u0)
    if key not in CACHE:
        from ..free_boundary import FreeBoundary

        L = ring / teeth
        n = (60 if quick else 200) * teeth
        h = ring / n
        x = np.arange(n) * h
        xf = 0.37 * h
        t_end = (25 if quick else 40) * L
        fb = FreeBoundary(
            fb_params(),
            x,
            np.full(n, u0),
            "periodic",
            shocks=[(xf + k * L, 1) for k in range(teeth)],
        )
        # dense snapshots over the first laps (the selection), and the end
        # (800: a shock crosses about one node between two, so u(x, t) shows no staircase)
        r = fb.run(t_end=t_end, snapshots=np.r_[np.linspace(0, 8 * L, 800), t_end])
        tp, up, um = _passages(r, x, n // (2 * teeth))
        CACHE[key] = (r, dict(L=L, x=x, xf=xf, teeth=teeth, u0=u0, t=tp, up=up, um=um))
    return CACHE[key]


def train_summary(m):
    """The train at the end of a run: u_+, A, period and speed from the last passages at
    one node, and how far u_+ still moved over the last two.

    Parameters
    ----------
    m : dict
        The passages of ``fb_train``: ``t``, ``up``, ``um`` and the wavelength ``L``.

    Returns
    -------
    dict
        up and A (dimensionless), period (units of sqrt(m/k_p)), c (units of the sound
        speed), drift (dimensionless) and the number of passages.

    Examples
    --------
    >>> import numpy as np
    >>> from bkwaves.paper.common import train_summary
    >>> m = {"t": np.array([0.0, 100.0, 200.5]), "up": np.array([0.6, 0.7, 0.7001]),
    ...      "um": np.array([-0.1, -0.1, -0.1]), "L": 120.0}
    >>> s = train_summary(m)
    >>> s["period"], round(s["c"], 6), round(s["A"], 4)
    (100.5, 1.19403, 0.8001)
    """
    t, up, um = m["t"], m["up"], m["um"]
    period = float(t[-1] - t[-2])
    return dict(
        up=float(up[-1]),
        A=float(up[-1] - um[-1]),
        period=period,
        c=m["L"] / period,
        drift=float(abs(up[-1] - up[-2])),
        passages=len(t),
    )


def fb_source(quick: bool, a: float = 1e-4, events: int | None = None):
    """A source: u = 1 - 1e-3 - a (x - x0)^2 on a free segment, several cycles.

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).
    a : float, default 1e-4
        The curvature of the maximum (dimensionless, 1/x^2).
    events : int, optional
        Events to run (default 6, or 12 in the full run).

    Returns
    -------
    result : bkwaves.FreeBoundaryResult
        The run (cached in ``CACHE``).
    source : dict
        a, the maximum's place x0 (dimensionless x) and the period T (units of
        sqrt(m/k_p)).
    """
    import warnings

    key = ("source", quick, a, events)
    if key not in CACHE:
        from ..free_boundary import FreeBoundary, NoCreepWarning

        h = 0.2 if quick else 0.1
        x = np.arange(-60.0, 60.0 + h / 2, h)
        x0 = 0.3 * h
        nev = events or (6 if quick else 12)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NoCreepWarning)  # the far ends creep; recorded
            fb = FreeBoundary(fb_params(), x, 1 - 1e-3 - a * (x - x0) ** 2)
        T = theory.source_period(V_FB, GAMMA_FB)
        # every T/40, and every 0.25 over the first birth (Fig. 6 zooms into it)
        snaps = np.union1d(np.linspace(0, (nev - 0.5) * T, 40 * nev), np.arange(0.0, 30.0, 0.25))
        r = fb.run(max_events=nev, snapshots=snaps)
        CACHE[key] = (r, dict(a=a, x0=x0, T=T))
    return CACHE[key]


# ------------------------------------------------------------- chain runs
#: The paper's chain has no backward slip (a block slides until its speed returns to zero):
#: beta = inf. Passed explicitly to every chain run of the report, whatever the library's
#: default.
PAPER_BETA = math.inf


def chain_fronts(quick: bool):
    """Fronts measured in the direct chain: c at gamma = 0 for two dx (Fig. 3), and c, u_-,
    w at gamma = 0.3 for three dx (Richardson towards dx -> 0).

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    dict
        ``us`` (dimensionless), ``fig3`` (dx -> c at each u, units of the sound speed),
        ``dxs`` and ``pulse`` (dx -> bkwaves.chain.FrontMeasurement). Cached in ``CACHE``.
    """
    key = ("fronts", quick)
    if key not in CACHE:
        from ..chain import front

        us = [0.3, 0.5, 0.7, 0.9]
        fig3 = {dx: [front(u, 0.0, dx, beta=PAPER_BETA).c for u in us] for dx in (0.1, 0.05)}
        dxs = [0.1, 0.05, 0.025] if quick else [0.1, 0.05, 0.025, 0.0125]
        pulse = {dx: front(0.7, 0.3, dx, beta=PAPER_BETA) for dx in dxs}
        CACHE[key] = dict(us=us, fig3=fig3, dxs=dxs, pulse=pulse)
    return CACHE[key]


# ------------------------------------------------------------- statistics
def fb_trains(quick: bool):
    """Wave trains of several amplitudes, each selected by a ring (one wavelength of the
    u_+ train, eq. L) started at uniform stress with one shock: u_+, A and the frequency at
    a point at the end of the run.

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    numpy.ndarray
        One row per train: the ring's u_+, the slip A, the frequency (per unit of
        sqrt(m/k_p)) and the u_+ selected (dimensionless).
    """
    rows = []
    for up in (0.4, 0.55, 0.7, 0.85, 0.95):
        r, m = fb_train(quick, ring=float(theory.wavelength(up, GAMMA_FB, V_FB)), teeth=1)
        s = train_summary(m)
        rows.append((up, s["A"], 1.0 / s["period"], s["up"]))
    return np.array(rows)


def long_catalogs(quick: bool):
    """Event catalogs of long runs: the free boundary engine on a ring from a rough random
    stress (the paper's a > a_max regime), and the chain under loading.

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    dict
        ``fb`` (bkwaves.FreeBoundaryResult), ``chain`` (bkwaves.ChainResult), the source
        period ``T`` (units of sqrt(m/k_p)) and the ring's length ``L`` (dimensionless x).
        Cached in ``CACHE``.
    """
    import warnings

    key = ("catalogs", quick)
    if key not in CACHE:
        from ..chain import Chain, smooth_random_stress
        from ..config import _smooth_random
        from ..free_boundary import FreeBoundary, NoCreepWarning
        from ..params import Params

        L = 400.0 if quick else 1600.0
        n = int(L / 0.2)
        x = np.arange(n) * (L / n)
        u0 = 0.5 + 0.3 * _smooth_random(x, 4.0, np.random.default_rng(1), True)
        T = theory.source_period(V_FB, GAMMA_FB)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NoCreepWarning)
            fb = FreeBoundary(fb_params(), x, u0, "periodic", record_path=False)
        r = fb.run(t_end=(20 if quick else 60) * T)
        nb = 400 if quick else 1000
        p = Params(gamma=0.3, v=V_CHAIN, dx=0.05, beta=PAPER_BETA)
        u0c = smooth_random_stress(nb, p.dx, mean=0.5, amplitude=0.15, correlation=2.0, seed=1)
        # walls at the ends (on a ring a pulse can circulate for ever: an event that
        # never ends); a time limit as well as an event limit
        ch = Chain(nb, p, "fixed", u0c, seed=1)
        rc = ch.run(t_end=1500.0 if quick else 8000.0, max_events=400, progress=False)
        CACHE[key] = dict(fb=r, chain=rc, T=T, L=L)
    return CACHE[key]


def ring_births(L: float, u0, periods: int):
    """A free-boundary ring from u0, run for ``periods`` source periods: per period, the
    births, the fraction of them within 1 of a birth of the previous period, and the sites
    (births closer than 1 counted once; one source can fire at two points 2h apart in a
    very flat field, docs/free_boundary.md).

    Parameters
    ----------
    L : float
        The ring's length (dimensionless x).
    u0 : numpy.ndarray
        The initial stress on the ring's grid (dimensionless).
    periods : int
        Source periods to run.

    Returns
    -------
    dict
        ``births``, ``recurrent`` (fractions) and ``sites``, one value per period.
    """
    import warnings

    from ..free_boundary import FreeBoundary, NoCreepWarning

    x = np.arange(u0.size) * (L / u0.size)
    T = theory.source_period(V_FB, GAMMA_FB)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NoCreepWarning)
        fb = FreeBoundary(fb_params(), x, u0, "periodic", record_path=False)
    r = fb.run(t_end=periods * T)
    b = r.shocks[(r.shocks.kind == "birth") & (r.shocks.dir > 0)]
    tb, xb = b.t.to_numpy(), b.x.to_numpy()
    births, recurrent, sites, prev = [], [], [], np.array([])
    for k in range(periods):
        xs = np.sort(xb[(tb >= k * T) & (tb < (k + 1) * T)])
        births.append(xs.size)
        if xs.size and prev.size:
            d = np.abs(xs[:, None] - prev[None, :])
            d = np.minimum(d, L - d).min(axis=1)
            recurrent.append(float(np.mean(d < 1.0)))
        else:
            recurrent.append(np.nan)
        gaps = np.diff(np.r_[xs, xs[:1] + L]) if xs.size else np.array([])
        sites.append(max(int(np.sum(gaps > 1.0)), 1) if xs.size else 0)
        prev = xs
    return dict(births=np.array(births), recurrent=np.array(recurrent), sites=np.array(sites))


#: The smooth rings of the coarsening measurement, (rings, L, periods): many independent
#: rings, since one ring holds only ~L/100 sources (an integer step function of n), and
#: enough periods for three doublings of the fitting window from SYNC_FIT_FROM.
SYNC_RINGS = {True: (6, 800.0, 40), False: (16, 1600.0, 160)}
#: The sharp ring (chaos rows): (L, periods).
SHARP_RING = {True: (800.0, 30), False: (1600.0, 80)}
#: Bootstrap resamples over rings.
SYNC_BOOTSTRAP = 2000
#: The exponent decides only when known to this (one bootstrap standard error: the local
#: exponents of the early windows, ~0.35, then lie 3 errors from 1/2) and no longer
#: drifting between the last two fitting windows (within 2 standard errors).
SYNC_DECIDE = 0.05
#: "R ~ a_n^(-1/2)" read as an order of magnitude: R a_n^(1/2) within this factor of 1.
SYNC_PREFACTOR_FACTOR = 3.0


def sync_chaos(quick: bool):
    """Rings from random stresses with maxima below (smooth, SYNC_RINGS seeds) and far
    above (sharp, one seed) a_max: births per source period, the fraction of them that
    recur at a birth site of the previous period (docs/validation.md, "Synchronisation or
    chaos"), and the size R = L / sites of the synchronised regions.

    Parameters
    ----------
    quick : bool
        Shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    dict
        ``res`` (ring name -> ``ring_births`` with the maxima's curvatures ``a``),
        the rings' length ``L`` (dimensionless x), ``periods``, ``rings`` and ``sharp``.
        Cached in ``CACHE``.
    """
    key = ("sync", quick)
    if key not in CACHE:
        from ..config import _smooth_random

        rings, L, periods = SYNC_RINGS[quick]
        L_sharp, periods_sharp = SHARP_RING[quick]
        h = 0.2
        res = {}
        cases = [("smooth", 0.02, 25.0, seed, L, periods) for seed in range(1, rings + 1)]
        cases.append(("sharp", 0.3, 4.0, 1, L_sharp, periods_sharp))
        for name, amp, corr, seed, length, per in cases:
            n = int(round(length / h))
            x = np.arange(n) * h
            u0 = 0.5 + amp * _smooth_random(x, corr, np.random.default_rng(seed), True)
            out = ring_births(length, u0, per)
            um, up = np.roll(u0, 1), np.roll(u0, -1)
            top = (u0 > um) & (u0 >= up)
            out["a"] = -(um[top] - 2 * u0[top] + up[top]) / (2 * h * h)
            out["L"], out["periods"] = length, per
            res[name if seed == 1 else f"{name}-{seed}"] = out
        sharp = (L_sharp, periods_sharp)
        CACHE[key] = dict(res=res, L=L, periods=periods, rings=rings, sharp=sharp)
    return CACHE[key]


#: Periods skipped before the coarsening fit (the first ones: every maximum fires).
SYNC_FIT_FROM = 10


def coarsening_exponent(m, seed: int = 0) -> dict:
    """R(n) = L / (mean sites over the smooth rings at period n), fitted as R ~ n^p on
    doubling windows [SYNC_FIT_FROM 2^k, SYNC_FIT_FROM 2^(k+1)] and on the whole run, each
    with its bootstrap standard error over rings (rings resampled with replacement,
    SYNC_BOOTSTRAP times): the exponent against the fitting window. Also the drift of the
    local exponent between the last two windows, and the paper's prefactor R a_n^(1/2)
    (a_n ~ v^2/(2 n (1 + kappa)), Sec. V) at the first window, with theirs.

    Parameters
    ----------
    m : dict
        What ``sync_chaos`` returns (``res`` with the rings' ``sites``, and ``L``).
    seed : int, default 0
        Seed of the bootstrap.

    Returns
    -------
    dict
        The exponent ``p`` with its ``sigma``, the ``local`` exponents per window, the
        drift between the last two, R per period (dimensionless x) and the prefactor.

    Examples
    --------
    Sites falling as n^(-1/2) on four rings give p = 1/2:

    >>> import numpy as np
    >>> from bkwaves.paper.common import coarsening_exponent
    >>> n = np.arange(1, 81)
    >>> rng = np.random.default_rng(0)
    >>> res = {f"smooth-{k}": {"sites": 400 * n**-0.5 * (1 + 0.01 * rng.standard_normal(80))}
    ...        for k in range(4)}
    >>> out = coarsening_exponent({"res": res, "L": 800.0})
    >>> round(out["p"], 3), [w["window"] for w in out["local"]]
    (0.5, [(10, 20), (20, 40), (40, 80)])
    """
    S = np.array([r["sites"] for k, r in m["res"].items() if k.startswith("smooth")], float)
    K, P = S.shape
    n = np.arange(1, P + 1)
    boot = np.random.default_rng(seed).integers(0, K, size=(SYNC_BOOTSTRAP, K))
    means = np.vstack([S.mean(axis=0), S[boot].mean(axis=1)])  # row 0: the rings as run
    R = m["L"] / np.maximum(means, 1e-300)

    def slope(lo, hi):
        sel = (n >= lo) & (n <= hi)
        p = np.polyfit(np.log(n[sel]), np.log(R[:, sel]).T, 1)[0]
        return p  # p[0] measured, p[1:] bootstrap

    windows, lo = [], SYNC_FIT_FROM
    while 2 * lo <= P:
        windows.append((lo, 2 * lo))
        lo *= 2
    local = []
    for lo, hi in windows:
        p = slope(lo, hi)
        sigma = float(np.std(p[1:], ddof=1))
        local.append(dict(window=(lo, hi), p=float(p[0]), sigma=sigma, boot=p[1:]))
    whole = slope(SYNC_FIT_FROM, P)
    out = dict(
        rings=K,
        periods=P,
        p=float(whole[0]),
        sigma=float(np.std(whole[1:], ddof=1)),
        local=[{k: v for k, v in w.items() if k != "boot"} for w in local],
        R=R[0],
    )
    if len(local) >= 2:
        d = local[-1]["boot"] - local[-2]["boot"]
        out["drift"] = local[-1]["p"] - local[-2]["p"]
        out["drift_sigma"] = float(np.std(d, ddof=1))
    # the paper's size estimate R ~ a_n^(-1/2), at the first window (the ring holds it best)
    lo, hi = windows[0] if windows else (SYNC_FIT_FROM, P)
    sel = (n >= lo) & (n <= hi)
    a_n = theory.a_n_asymptote(n[sel], V_FB, GAMMA_FB)
    ratio = np.exp(np.mean(np.log(R[:, sel] * np.sqrt(a_n)), axis=1))
    out["prefactor"] = float(ratio[0])
    out["prefactor_sigma"] = float(np.std(ratio[1:], ddof=1))
    out["prefactor_window"] = (lo, hi)
    lr, sl = math.log(out["prefactor"]), out["prefactor_sigma"] / out["prefactor"]
    out["prefactor_near"] = math.exp(math.copysign(max(abs(lr) - 2.0 * sl, 0.0), lr))
    out["paper_R"] = float(np.exp(np.mean(np.log(a_n**-0.5))))  # geometric mean
    return out
