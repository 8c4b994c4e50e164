"""Beyond the paper: ruptures in the plane at long times (issue 26, docs/free_boundary_2d.md):
frequency-size statistics with noise nucleation, and the sources of Sec. V
(synchronisation or chaos) on periodic squares, against the ring."""

from __future__ import annotations

#: Not an API: the functions below are plug-ins of the registry
#: (:mod:`bkwaves.paper.figure`) and the runs they share with docs/scripts/
#: free_boundary_2d_gr.py and free_boundary_2d_sync.py; each costs seconds to minutes.
__all__: list[str] = []

import numpy as np

from ..common import CACHE, GAMMA_FB, V_FB
from ..figure import register_figure

#: The noisy squares (docs/free_boundary_2d.md, "Gutenberg-Richter in the plane?"):
#: gamma, v, the transient discarded, the Hill exponent's lower cut of the areas.
GR_GAMMA, GR_V, GR_T0, GR_A_MIN = 0.3, 1e-3, 5000.0, 25.0
#: The initial fields of the sources (as the 1D scripts): (amplitude, correlation length).
SYNC_FIELDS = {"smooth": (0.02, 25.0), "sharp": (0.3, 4.0)}
#: The grid on which the sources' initial fields are drawn; on a finer grid they are
#: interpolated exactly (Fourier: the fields are band-limited), so runs with different h
#: start from the same field.
FIELD_H = 2.0
#: Births of one period closer than this are one site (a source in a flat field can
#: fire at neighbouring nodes).
D_SITE = 3.0
#: Periods skipped before the coarsening fit (every maximum fires in the first ones).
FIT_FROM = 10
#: Bootstrap resamples over squares (or rings).
BOOT = 2000


def gr_catalog(rate: float, side: float, h: float, t_end: float, seed: int, v: float = GR_V):
    """A noisy periodic square: u0 = 0.3 x a random field (correlation length 3), creep
    rule "stop", noise law power (g = u^8) at ``rate`` per unit area and time, seeds
    ``seed`` (field) and 1000 + seed (noise).

    Parameters
    ----------
    rate : float
        Noise rate per unit area and time at u = 1 (dimensionless).
    side : float
        The square's side (dimensionless x).
    h : float
        Grid spacing (dimensionless x).
    t_end : float
        End of the run (units of sqrt(m/k_p)).
    seed : int
        Seed of the field (the noise's is 1000 + seed).
    v : float, default GR_V
        Loading rate; the transient discarded is GR_T0 GR_V / v (the same loadings).

    Returns
    -------
    tuple
        (complete ruptures with t_start > GR_T0 GR_V / v as a pandas.DataFrame, CPU
        seconds).
    """
    import time

    from ... import Params
    from ...free_boundary_2d import FreeBoundary2D, random_field

    n = int(round(side / h))
    u0 = 0.3 * random_field((n, n), h, 3.0, seed=seed)
    fb = FreeBoundary2D(
        Params(gamma=GR_GAMMA, v=v, dx=1e-2),
        (n, n),
        h,
        u0,
        "periodic",
        creep="stop",
        noise={"law": "power", "rate": rate, "exponent": 8.0},
        seed=1000 + seed,
    )
    t = time.process_time()
    r = fb.run(t_end=t_end)
    cpu = time.process_time() - t
    ru = r.ruptures
    return ru[ru.complete & (ru.n_nodes > 0) & (ru.t_start > GR_T0 * GR_V / v)], cpu


def torus_clusters(p: np.ndarray, L: float, d: float) -> int:
    """The number of single-linkage clusters of the points ``p`` (k, 2) on the L x L
    torus, points closer than ``d`` linked.

    Parameters
    ----------
    p : numpy.ndarray
        Points, shape (k, 2) (dimensionless x).
    L : float
        The torus's side.
    d : float
        Linking distance.

    Returns
    -------
    int
        The clusters (0 for no point).
    """
    k = len(p)
    if k == 0:
        return 0
    dd = np.abs(p[:, None, :] - p[None, :, :])
    dd = np.minimum(dd, L - dd)
    adj = np.hypot(dd[..., 0], dd[..., 1]) < d
    seen = np.zeros(k, bool)
    n = 0
    for i in range(k):
        if seen[i]:
            continue
        n += 1
        seen[i] = True
        stack = [i]
        while stack:
            nb = np.nonzero(adj[stack.pop()] & ~seen)[0]
            seen[nb] = True
            stack.extend(nb.tolist())
    return n


def maxima_curvatures(u0: np.ndarray, h: float) -> np.ndarray:
    """The principal curvatures a_1 >= a_2 (u = u_max - a_1 xi^2 - a_2 eta^2) at the strict
    local maxima of a periodic field on nodes of spacing h (second differences).

    Parameters
    ----------
    u0 : numpy.ndarray
        The field, shape (ny, nx).
    h : float
        Node spacing.

    Returns
    -------
    numpy.ndarray
        Shape (maxima, 2).
    """

    def r(a, s, ax):
        return np.roll(a, s, axis=ax)

    top = np.ones(u0.shape, bool)
    for s in (-1, 1):
        for ax in (0, 1):
            top &= u0 > r(u0, s, ax)
    uxx = (r(u0, 1, 1) - 2 * u0 + r(u0, -1, 1)) / h**2
    uyy = (r(u0, 1, 0) - 2 * u0 + r(u0, -1, 0)) / h**2
    xp, xm = r(u0, -1, 1), r(u0, 1, 1)  # u at i + 1, i - 1
    uxy = (r(xp, -1, 0) - r(xp, 1, 0) - r(xm, -1, 0) + r(xm, 1, 0)) / (4 * h**2)
    H = np.stack([np.stack([uxx, uxy], -1), np.stack([uxy, uyy], -1)], -1)[top]
    return -np.linalg.eigvalsh(H) / 2  # eigvalsh ascending: a_1 first


def period_series(xy: np.ndarray, tb: np.ndarray, L: float, T: float, periods: int) -> dict:
    """Per source period: the births, the sites (births closer than D_SITE counted once)
    and the fraction of births within D_SITE of a birth of the previous period.

    Parameters
    ----------
    xy : numpy.ndarray
        Birth places, shape (k, 2) (dimensionless x).
    tb : numpy.ndarray
        Birth times (units of sqrt(m/k_p)).
    L : float
        The square's side.
    T : float
        The source period.
    periods : int
        Periods to count.

    Returns
    -------
    dict
        ``births``, ``sites`` and ``recurrent`` (NaN where undefined), one value per period.
    """
    births, sites, recurrent, prev = [], [], [], np.zeros((0, 2))
    for k in range(periods):
        p = xy[(tb >= k * T) & (tb < (k + 1) * T)]
        births.append(len(p))
        sites.append(torus_clusters(p, L, D_SITE))
        if len(p) and len(prev):
            dd = np.abs(p[:, None, :] - prev[None, :, :])
            dd = np.minimum(dd, L - dd)
            recurrent.append(float(np.mean(np.hypot(dd[..., 0], dd[..., 1]).min(1) < D_SITE)))
        else:
            recurrent.append(float("nan"))
        prev = p
    return dict(births=births, sites=sites, recurrent=recurrent)


def sync_field(field: str, L: float, h: float, seed: int) -> np.ndarray:
    """The initial stress 0.5 + A f of a square (SYNC_FIELDS), f the ``random_field`` drawn
    on the grid of spacing FIELD_H, interpolated in Fourier space onto spacing h (a
    divisor of FIELD_H, or FIELD_H itself).

    Parameters
    ----------
    field : {"smooth", "sharp"}
        The initial field.
    L : float
        Side (dimensionless x).
    h : float
        Grid spacing.
    seed : int
        Seed of the field.

    Returns
    -------
    numpy.ndarray
        u0, shape (L/h, L/h).
    """
    from ...free_boundary_2d import random_field

    amp, corr = SYNC_FIELDS[field]
    nc, n = int(round(L / FIELD_H)), int(round(L / h))
    f = random_field((nc, nc), FIELD_H, corr, seed=seed)
    if n != nc:
        F = np.fft.fftshift(np.fft.fft2(f))
        pad = (n - nc) // 2
        F = np.pad(F, ((pad, n - nc - pad), (pad, n - nc - pad)))
        f = np.real(np.fft.ifft2(np.fft.ifftshift(F))) * (n / nc) ** 2
    return 0.5 + amp * f


def sync_square(field: str, L: float, h: float, seed: int, periods: int) -> dict:
    """A periodic L x L square from u0 = 0.5 + A f (f: ``random_field`` of the field's
    correlation length, max |f| = 1), gamma and v of the report's free-boundary runs,
    creep rule "zero", no noise, run for ``periods`` source periods.

    Parameters
    ----------
    field : {"smooth", "sharp"}
        The initial field (SYNC_FIELDS).
    L : float
        Side (dimensionless x).
    h : float
        Grid spacing.
    seed : int
        Seed of the field.
    periods : int
        Source periods to run.

    Returns
    -------
    dict
        ``period_series`` plus the ruptures and the largest one's area / L^2 per
        period, the maxima's curvatures (the fraction with both below a_max) and the
        moments of the complete ruptures after FIT_FROM periods.
    """
    import time

    from ... import Params, theory
    from ...free_boundary_2d import FreeBoundary2D

    n = int(round(L / h))
    u0 = sync_field(field, L, h, seed)
    a = maxima_curvatures(u0, h)
    T = theory.source_period(V_FB, GAMMA_FB)
    fb = FreeBoundary2D(Params(gamma=GAMMA_FB, v=V_FB, dx=1e-3), (n, n), h, u0, "periodic")
    t0 = time.process_time()
    r = fb.run(t_end=periods * T)
    cpu = time.process_time() - t0
    ru = r.ruptures
    b = ru[ru.origin == "birth"]
    out = period_series(b[["x_start", "y_start"]].to_numpy(), b.t_start.to_numpy(), L, T, periods)
    k = np.minimum((ru.t_start.to_numpy() / T).astype(int), periods - 1)
    big = np.zeros(periods)
    np.maximum.at(big, k, ru.area.to_numpy() / L**2)
    done = ru[ru.complete & (ru.t_start > FIT_FROM * T)]
    out.update(
        dim=2,
        field=field,
        L=L,
        h=h,
        seed=seed,
        periods=periods,
        n_maxima=int(len(a)),
        a_below_a_max=float(np.mean(a[:, 0] < theory.a_max(V_FB, GAMMA_FB))),
        a_median=float(np.median(a[:, 0])),
        ruptures=np.bincount(k, minlength=periods)[:periods].tolist(),
        largest=big.tolist(),
        moments=done.moment.to_list(),
        xy=b[["x_start", "y_start"]].to_numpy().tolist(),
        tb=b.t_start.to_list(),
        cpu_s=cpu,
    )
    return out


def sync_ring(field: str, L: float, h: float, seed: int, periods: int) -> dict:
    """The ring with the same recipe (``_smooth_random`` of the 1D scripts, same A, l,
    gamma, v, creep rule, grid), ``bkwaves.paper.common.ring_births``.

    Parameters
    ----------
    field : {"smooth", "sharp"}
        The initial field (SYNC_FIELDS).
    L : float
        Length (dimensionless x).
    h : float
        Grid spacing.
    seed : int
        Seed of the field.
    periods : int
        Source periods to run.

    Returns
    -------
    dict
        ``births``, ``sites``, ``recurrent`` per period, with ``dim`` = 1 and the run's
        parameters.
    """
    import time

    from ...config import _smooth_random
    from ..common import ring_births

    amp, corr = SYNC_FIELDS[field]
    x = np.arange(int(round(L / h))) * h
    u0 = 0.5 + amp * _smooth_random(x, corr, np.random.default_rng(seed), True)
    t0 = time.process_time()
    out = ring_births(L, u0, periods)
    return dict(
        dim=1,
        field=field,
        L=L,
        h=h,
        seed=seed,
        periods=periods,
        births=out["births"].tolist(),
        sites=out["sites"].tolist(),
        recurrent=out["recurrent"].tolist(),
        cpu_s=time.process_time() - t0,
    )


def coarsening(runs: list[dict], seed: int = 0) -> dict:
    """R(n) = L / (mean sites over the runs)^(1/d) (d = 1 ring, 2 square), fitted as
    R ~ n^p on doubling windows of periods from FIT_FROM and on the whole run, each with
    its bootstrap standard error over runs (runs resampled with replacement BOOT times);
    and the paper's R a_n^(1/2) (a_n ~ v^2/(2 n (1 + kappa))) over the first window.

    Parameters
    ----------
    runs : list of dict
        What ``sync_square`` or ``sync_ring`` return, one dimension, one L.
    seed : int, default 0
        Seed of the bootstrap.

    Returns
    -------
    dict
        ``p``, ``sigma``, ``local`` (window, p, sigma), ``R`` per period, ``sites_mean``,
        ``prefactor`` and ``prefactor_sigma``.
    """
    from ... import theory

    P = min(r["periods"] for r in runs)
    S = np.array([r["sites"][:P] for r in runs], float)
    d, L = runs[0]["dim"], runs[0]["L"]
    K = S.shape[0]
    n = np.arange(1, P + 1)
    boot = np.random.default_rng(seed).integers(0, K, size=(BOOT, K))
    means = np.vstack([S.mean(axis=0), S[boot].mean(axis=1)])
    R = L / np.maximum(means, 1e-300) ** (1.0 / d)

    def slope(lo, hi):
        sel = (n >= lo) & (n <= hi)
        return np.polyfit(np.log(n[sel]), np.log(R[:, sel]).T, 1)[0]

    local, lo = [], FIT_FROM
    while 2 * lo <= P:
        p = slope(lo, 2 * lo)
        local.append(dict(window=[lo, 2 * lo], p=float(p[0]), sigma=float(np.std(p[1:], ddof=1))))
        lo *= 2
    whole = slope(FIT_FROM, P)
    sel = (n >= FIT_FROM) & (n <= 2 * FIT_FROM)
    a_n = theory.a_n_asymptote(n[sel], V_FB, GAMMA_FB)
    ratio = np.exp(np.mean(np.log(R[:, sel] * np.sqrt(a_n)), axis=1))
    return dict(
        runs=K,
        periods=P,
        p=float(whole[0]),
        sigma=float(np.std(whole[1:], ddof=1)),
        local=local,
        R=R[0].tolist(),
        sites_mean=S.mean(axis=0).tolist(),
        prefactor=float(ratio[0]),
        prefactor_sigma=float(np.std(ratio[1:], ddof=1)),
    )


#: The figures' runs: quick (seconds) and full (about two minutes of CPU).
PLANE_GR_RUNS = {
    True: dict(sides=(32.0, 64.0), rates=(0.1, 1.0, 10.0), rate_side=32.0, seeds=1, t_end=2e4),
    False: dict(sides=(64.0, 128.0), rates=(0.1, 1.0, 10.0), rate_side=64.0, seeds=2, t_end=35e3),
}
PLANE_SYNC_RUNS = {
    True: dict(L=200.0, h=2.0, seeds=2, periods=20, sharp=(60.0, 1.0, 12), ring=(400.0, 0.4, 2)),
    False: dict(L=400.0, h=2.0, seeds=4, periods=80, sharp=(200.0, 1.0, 40), ring=(1600.0, 0.2, 6)),
}


def plane_gr(quick: bool) -> dict:
    """The figure's noisy squares (``gr_catalog``, h = 0.5): per (rate, side) the
    areas and moments pooled over seeds and each seed's b.

    Parameters
    ----------
    quick : bool
        Smaller squares and shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    dict
        ``runs`` ((rate, side) -> dict of ``area``, ``moment`` and ``b``), and the
        settings of PLANE_GR_RUNS. Cached in ``CACHE``.
    """
    from ... import stats

    key = ("plane_gr", quick)
    if key not in CACHE:
        cfg = PLANE_GR_RUNS[quick]
        cases = {(1.0, s) for s in cfg["sides"]} | {(r, cfg["rate_side"]) for r in cfg["rates"]}
        runs = {}
        for rate, side in sorted(cases):
            area, moment, b = [], [], []
            for seed in range(1, cfg["seeds"] + 1):
                ru, _ = gr_catalog(rate, side, 0.5, cfg["t_end"], seed)
                area.append(ru.area.to_numpy())
                moment.append(ru.moment.to_numpy())
                b.append(stats.gutenberg_richter(ru.moment.to_numpy(), n_boot=200))
            runs[(rate, side)] = dict(area=np.concatenate(area), moment=np.concatenate(moment), b=b)
        CACHE[key] = dict(cfg, runs=runs)
    return CACHE[key]


@register_figure("beyond_plane_gr", 2, beyond=True)
def fig_plane_gr(axes, quick):
    """Frequency-size of ruptures in noisy periodic squares (issue 26): the areas against
    the system's, and against the noise rate.

    Parameters
    ----------
    axes : numpy.ndarray of matplotlib.axes.Axes
        The two panels.
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    str
        The caption, with the numbers computed for the figure.
    """
    from ... import stats

    m = plane_gr(quick)
    ax = axes[0]
    notes = []
    for k, side in enumerate(m["sides"]):
        r = m["runs"][(1.0, side)]
        s, cc = stats.size_frequency(r["area"])
        ax.loglog(s, cc, "-", color=f"C{k}", lw=1.2, label=f"side $L = {side:g}$")
        ax.axvline(side**2, color=f"C{k}", ls=":", lw=1)  # the system's area
        top = float(s[0] / side**2)
        bs = ", ".join(f"{g.b:.1f}" if g.ok else "none" for g in r["b"])
        notes.append(f"side {side:g}: {len(s)} ruptures, largest {top:.2f} of the square, b {bs}")
    ax.set_xlabel(r"rupture area $A$ (dotted: the square's $L^2$)")
    ax.set_ylabel(r"fraction of ruptures $\geq A$")
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title(r"noise rate $\Lambda = 1$: sizes against the system", fontsize=9)
    ax = axes[1]
    side = m["rate_side"]
    rate_notes = []
    for k, rate in enumerate(m["rates"]):
        r = m["runs"][(rate, side)]
        s, cc = stats.size_frequency(r["area"])
        ax.loglog(s, cc, "-", color=f"C{k + 3}", lw=1.2, label=rf"$\Lambda = {rate:g}$")
        rate_notes.append(f"rate {rate:g}: mean area {np.mean(r['area']):.3g}")
    ax.set_xlabel(r"rupture area $A$")
    ax.set_ylabel(r"fraction of ruptures $\geq A$")
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title(f"side {side:g}: sizes against the noise rate", fontsize=9)
    return (
        f"Ruptures in noisy periodic squares (issue 26; FreeBoundary2D, h = 0.5, gamma = "
        f"{GR_GAMMA}, v = {GR_V:g}, creep rule 'stop', u0 = 0.3 x a random field, noise g = "
        f"u^8 at a rate Lambda per unit area and time, {m['seeds']} seed(s), t = "
        f"{GR_T0:g}-{m['t_end']:g}). Left: areas at Lambda = 1, the squares' areas dotted ("
        + "; ".join(notes)
        + "; b of moment magnitudes by bk.stats.gutenberg_richter, per seed). Right: side "
        f"{side:g} at three rates (" + "; ".join(rate_notes) + "). docs/free_boundary_2d.md "
        "has the converged numbers (squares to 256, three seeds)."
    )


def plane_sync(quick: bool) -> dict:
    """The figure's sources: smooth squares and a sharp one (``sync_square``), and
    rings with the same recipe (``sync_ring``), with the coarsening fits.

    Parameters
    ----------
    quick : bool
        Smaller squares and shorter runs (``bkwaves paper --quick``).

    Returns
    -------
    dict
        ``smooth``, ``sharp``, ``rings``, ``ring_sharp`` (lists of runs), the coarsening
        fits ``fit2``, ``fit1`` and the settings of PLANE_SYNC_RUNS. Cached in ``CACHE``.
    """
    key = ("plane_sync", quick)
    if key not in CACHE:
        c = PLANE_SYNC_RUNS[quick]
        P = c["periods"]
        smooth = [sync_square("smooth", c["L"], c["h"], s, P) for s in range(1, c["seeds"] + 1)]
        Ls, hs, Ps = c["sharp"]
        sharp = [sync_square("sharp", Ls, hs, 1, Ps)]
        Lr, hr, nr = c["ring"]
        rings = [sync_ring("smooth", Lr, hr, s, P) for s in range(1, nr + 1)]
        ring_sharp = [sync_ring("sharp", Lr, hr, 1, Ps)]
        out = dict(c, sharp_cfg=c["sharp"], ring_cfg=c["ring"])
        out.update(smooth=smooth, sharp=sharp, rings=rings, ring_sharp=ring_sharp)
        if P >= 2 * FIT_FROM:
            out["fit2"], out["fit1"] = coarsening(smooth), coarsening(rings)
        CACHE[key] = out
    return CACHE[key]


@register_figure("beyond_plane_sync", 3, beyond=True)
def fig_plane_sync(axes, quick):
    """Sources in the plane (issue 26, paper Sec. V): where births recur, the size of the
    synchronised regions against time in the plane and on the ring, and the fraction of
    births that recur.

    Parameters
    ----------
    axes : numpy.ndarray of matplotlib.axes.Axes
        The three panels.
    quick : bool
        Shorter computations (``bkwaves paper --quick``).

    Returns
    -------
    str
        The caption, with the numbers computed for the figure.
    """
    import warnings

    from ... import theory

    m = plane_sync(quick)
    P, L = m["periods"], m["L"]
    ax = axes[0]
    r0 = m["smooth"][0]
    sc = ax.scatter(
        np.asarray(r0["xy"])[:, 0],
        np.asarray(r0["xy"])[:, 1],
        c=np.asarray(r0["tb"]) / theory.source_period(V_FB, GAMMA_FB),
        s=4,
        cmap="viridis",
    )
    cb = ax.figure.colorbar(sc, ax=ax)
    cb.set_label(r"period $n = t/T$ of the birth")
    ax.set_xlim(0, L)
    ax.set_ylim(0, L)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x$")
    ax.set_ylabel(r"$y$")
    ax.set_title("births of one smooth square", fontsize=9)
    ax = axes[1]
    n = np.arange(1, P + 1)
    fits = []
    for key, lab, col in (("fit2", "plane", "C0"), ("fit1", "ring", "C3")):
        f = m.get(key)
        if f is None:
            continue
        ax.loglog(n, f["R"], "o", ms=2.5, color=col, label=f"{lab}: $p = {f['p']:.2f}$")
        fits.append(f"{lab} p = {f['p']:.2f} +- {f['sigma']:.2f}")
    if fits:
        f = m["fit2"]
        ref = f["R"][FIT_FROM - 1] * (n / FIT_FROM) ** 0.5
        ax.loglog(n, ref, "k--", lw=0.8, label=r"$\propto n^{1/2}$")
    ax.set_xlabel(r"source period $n = t/T$")
    ax.set_ylabel(r"region size $R = L/N^{1/d}$")
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title("coarsening of the sources", fontsize=9)
    ax = axes[2]
    recs = []
    for key, lab, col, ls in (
        ("smooth", "plane, smooth", "C0", "-"),
        ("sharp", "plane, sharp", "C1", "-"),
        ("rings", "ring, smooth", "C3", ":"),
        ("ring_sharp", "ring, sharp", "C2", ":"),
    ):
        rec = np.array([r["recurrent"] for r in m[key]], float)[:, 1:]  # from period 2
        with warnings.catch_warnings():  # a period without births in every run: a gap
            warnings.simplefilter("ignore", RuntimeWarning)
            y = np.nanmean(rec, axis=0)
        ax.plot(np.arange(2, y.size + 2), y, ls, color=col, lw=1.2, label=lab)
        recs.append(f"{lab} {np.nanmean(y[-5:]):.2f}")
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel(r"source period $n = t/T$")
    ax.set_ylabel("fraction of births recurring")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title("fixed sources or wandering births", fontsize=9)
    s0 = np.mean([r["sites"][0] for r in m["smooth"]])
    s1 = np.mean([r["sites"][-1] for r in m["smooth"]])
    Ls, hs, Ps = m["sharp_cfg"]
    return (
        f"Sources in the plane (issue 26, paper Sec. V): FreeBoundary2D on periodic squares, "
        f"gamma = {GAMMA_FB}, v = {V_FB}, no noise, u0 = 0.5 + A f (f a random field, max "
        f"|f| = 1). Smooth: A = 0.02, correlation 25, {len(m['smooth'])} squares of side "
        f"{L:g} (h = {m['h']:g}); sharp: A = 0.3, correlation 4, side {Ls:g} (h = {hs:g}); "
        f"rings of length {m['ring_cfg'][0]:g} from the same recipe. Left: births of the first "
        f"square, coloured by period (sites {s0:.0f} in the first period, {s1:.0f} in "
        f"period {P}). Middle: R = L / N^(1/d), N the birth sites per period averaged over "
        "runs (births closer than 3 counted once), fitted as n^p from period 10 with a "
        "bootstrap over runs: "
        + ("; ".join(fits) if fits else "too short to fit")
        + ". Right: fraction of births within 3 of a birth of the previous period, over the "
        "last 5 periods: " + "; ".join(recs) + ". docs/free_boundary_2d.md has the converged "
        "numbers."
    )
