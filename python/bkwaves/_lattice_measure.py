"""The measurements on the lattice: a planar front (``front``) and a rupture from a
point (``rupture``, ``Rupture``), public as ``bkwaves.lattice.front``,
``bkwaves.lattice.rupture`` and so on (docs/lattice.md, "Python")."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _validate as V
from .chain import DEFAULT_STEP
from .lattice import Lattice

#: The largest change of a planar front's c (units of the sound speed) when the lattice is
#: doubled that ``front`` accepts as converged (the chain's ``FRONT_TOLERANCE`` for c).
FRONT_TOLERANCE = 1e-6


@dataclass
class PlanarFront:
    """A planar front measured on the lattice (``front``).

    c: the normal speed (lattice units of length per unit time) from the first slip
    times of a window of the normal coordinate; c_check: the same from a lattice twice as
    long (the measurement's convergence: |c - c_check|); spacing: the spacing of the
    chain the front reduces to exactly (dx along an axis, dx/sqrt(2) along the diagonal).
    status: "converged" when |c - c_check| <= tolerance, else "undecided" (``reason``
    says why); lengths: the lattice lengths measured, each twice the last.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx : float
        Lattice spacing (dimensionless).
    angle : {0, 45}
        The front's normal: along x, or along the diagonal.
    blocks : int
        Blocks along the normal.
    c, c_check : float
        Normal speed, and its value on a lattice twice as long (units of the sound
        speed a sqrt(k_c/m)).
    spacing : float
        The spacing of the equivalent chain (dimensionless).
    window : tuple of float
        The window, as fractions of the blocks crossed.
    tolerance : float
        The largest |c - c_check| accepted (units of the sound speed).
    status : {"converged", "undecided"}
        Whether the last doubling moved c by at most ``tolerance``.
    reason : str
        What the last doubling did, in words.
    lengths : tuple of int
        The lengths (blocks along the normal) measured.

    Examples
    --------
    >>> import bkwaves as bk
    >>> f = bk.lattice.front(0.6, 0.3, 0.2, blocks=32)
    >>> f.spacing, f.status, bool(f.convergence <= f.tolerance)
    (0.2, 'converged', True)
    """

    u_plus: float
    gamma: float
    dx: float
    angle: int
    blocks: int
    c: float
    c_check: float
    spacing: float
    window: tuple[float, float]
    tolerance: float = math.inf
    status: str = "converged"
    reason: str = ""
    lengths: tuple = ()

    @property
    def convergence(self) -> float:
        """|c - c_check|: the change of c when the lattice is twice as long (units of the
        sound speed)."""
        return abs(self.c - self.c_check)


def _planar_c(u_plus, gamma, dx, angle, blocks, step, beta, window):
    p = _lattice_params(gamma, dx, beta)
    a, b = (int(round(f * blocks)) for f in window)
    if angle == 0:
        # u depends on i only: two rows periodic in y (the chain at dx, measured here;
        # the global cut, as the chain's: the same slip times to round-off, 1e-12)
        la = Lattice(
            (blocks, 2), p, u0=u_plus, boundary=("free", "periodic"), step=step, events="global"
        )
        for j in range(2):
            la.kick((0, j), -2.0)
        t_end = 2.0 * blocks * dx
        spacing = dx
        res = la.run(t_end=t_end, progress=False)
        t = res.first_slip_times()[0]
        ta, tb = t[a], t[b]
    else:
        # u a function of n = (i + j) mod N on an N x N torus: fronts run both ways from
        # the kicked anti-diagonal and meet at n = N/2; the window is in n in [0, N/2]
        nn = blocks
        # (the global cut: the ring's slip times at dx/sqrt(2) to 1e-10, as the chain's)
        la = Lattice((nn, nn), p, u0=u_plus, boundary="periodic", step=step, events="global")
        for i in range(nn):
            la.kick((i, (nn - i) % nn), -2.0)
        spacing = dx / math.sqrt(2.0)
        a, b = (int(round(f * nn / 2)) for f in window)
        res = la.run(t_end=nn * spacing, progress=False)
        t = res.first_slip_times()
        ta, tb = t[0, a], t[0, b]
    if not (np.isfinite(ta) and np.isfinite(tb) and tb > ta):
        return math.nan, spacing
    return spacing * (b - a) / (tb - ta), spacing


def _lattice_params(gamma, dx, beta):
    from .params import Params

    return Params(gamma=gamma, v=0.0, dx=dx, beta=beta)


def front(
    u_plus: float,
    gamma: float,
    dx: float,
    angle: int = 0,
    blocks: int = 128,
    *,
    step: float = DEFAULT_STEP,
    beta: float = math.inf,
    window: tuple[float, float] = (0.5, 0.75),
    tolerance: float = FRONT_TOLERANCE,
    max_blocks: int | None = None,
) -> PlanarFront:
    """A planar front on the lattice (dx = dy) at uniform u_+, v = 0, and its normal speed.

    angle=0: along x, on a lattice of ``blocks`` x 2 periodic in y, kicked on column 0;
    angle=45: along the diagonal, on a ``blocks`` x ``blocks`` torus kicked on an
    anti-diagonal (the normal coordinate n = i + j; the window is a fraction of the
    blocks/2 rows of n a front crosses before it meets the other one). Both reduce
    exactly to a chain (at dx, at dx/sqrt(2): docs/lattice.md), whose c they must give.
    The measurement is repeated on a lattice twice as long (``c_check``), and the
    lattice doubled again until that moves c by at most ``tolerance`` (status
    "converged") or the length reaches ``max_blocks`` (status "undecided", with the
    reason). The trigger's transient decays over a number of blocks that grows as c -> 1
    (docs/validation.md): at u_+ = 0.3, gamma = 0, dx = 0.1, 128 blocks move by 3e-5.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    dx : float
        Lattice spacing, 0 < dx < 1 (dimensionless; dy = dx).
    angle : {0, 45}, default 0
        Along x, or along the diagonal.
    blocks : int, default 128
        Blocks along the normal, 16 <= blocks <= 4096.
    step : float, default 0.05
        Time step as a fraction of dx (in units of sqrt(m/k_p)).
    beta : float, default inf
        f_s/(f_r - f_s) (dimensionless).
    window : tuple of float, default (0.5, 0.75)
        The measuring window, as fractions of the blocks crossed.
    tolerance : float, default FRONT_TOLERANCE = 1e-6
        The largest change of c (units of the sound speed) when the lattice is doubled,
        > 0 (``math.inf``: measure at ``blocks`` and its double only).
    max_blocks : int, optional
        The longest lattice measured before the double that checks it, >= blocks
        (default 2048 along x, 256 along the diagonal, whose torus has blocks^2 blocks).

    Returns
    -------
    PlanarFront
        c and c_check (units of the sound speed), the equivalent chain's spacing, the
        status ("converged" or "undecided") and its reason.

    Examples
    --------
    The exact reductions: along x the chain at dx, along the diagonal the chain at
    dx/sqrt(2):

    >>> import math
    >>> import bkwaves as bk
    >>> f = bk.lattice.front(0.6, 0.3, 0.2, blocks=32)
    >>> round(float(f.c_check), 5), round(float(bk.front_speed(0.6, dx=0.2, gamma=0.3)), 5)
    (1.21525, 1.21525)
    >>> d = bk.lattice.front(0.6, 0.3, 0.2, angle=45, blocks=64, tolerance=1e-3)
    >>> chain = float(bk.front_speed(0.6, dx=0.2 / math.sqrt(2), gamma=0.3))
    >>> round(float(d.c_check), 3), round(chain, 3)
    (1.226, 1.226)
    """
    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    if angle not in (0, 45):
        V._fail("angle", angle, "0 (along x) or 45 (along the diagonal)")
    blocks = V.integer("blocks", blocks, lo=16, hi=4096)
    if not (isinstance(tolerance, float) and tolerance == math.inf):
        tolerance = V.number("tolerance", tolerance, lo=0.0, lo_open=True)
    top = max(blocks, 2048 if angle == 0 else 256) if max_blocks is None else max_blocks
    top = V.integer("max_blocks", top, lo=blocks, hi=4096)
    c, spacing = _planar_c(u_plus, gamma, dx, angle, blocks, step, beta, window)
    c2, _ = _planar_c(u_plus, gamma, dx, angle, 2 * blocks, step, beta, window)
    lengths = [blocks, 2 * blocks]
    while not abs(c - c2) <= tolerance and 2 * blocks <= top:
        blocks *= 2
        c = c2
        c2, _ = _planar_c(u_plus, gamma, dx, angle, 2 * blocks, step, beta, window)
        lengths.append(2 * blocks)
    moved = abs(c - c2)
    if moved <= tolerance:
        status = "converged"
        reason = f"doubling the lattice from {blocks} to {2 * blocks} blocks moved c by {moved:.1e}"
    else:
        status = "undecided"
        reason = (
            f"doubling the lattice from {blocks} to {2 * blocks} blocks moved c by {moved:.1e}, "
            f"more than the tolerance {tolerance:.1e}, and max_blocks = {top} stops the doubling"
        )
    return PlanarFront(
        u_plus, gamma, dx, angle, blocks, c, c2, spacing, tuple(window),
        tolerance, status, reason, tuple(lengths),
    )  # fmt: skip


@dataclass
class Rupture:
    """An expanding rupture from a point (``rupture``).

    arrival: first slip times of the quadrant, shape (ny, nx) (the rupture's centre is the
    corner (x, y) = (-dx/2, -dy/2): the free edges of the quadrant are mirror planes).
    profiles: for each direction ("x", "y", "diagonal") a dict of the radius ``r`` (from
    the centre, lattice units of length), the arrival time ``t`` and the local speed ``c``
    (central differences of r against t). fits: for each direction (c0, D) of the
    least-squares fit c(R) = c0 - D/R over ``fit_range`` of R (the excitable-media
    eikonal law c_n = c - D kappa with kappa = 1/R). planar: the planar front speeds the
    directions tend to (the chain at dx along x, at dy along y, at dx/sqrt(2) along the
    diagonal when dx = dy: the exact reductions of docs/lattice.md). eikonal: for each
    direction D = (c_planar - c(R)) R with c0 fixed at the planar speed, averaged over
    the lower and the upper half of ``fit_range`` (equal halves: c = c0 - D/R holds).
    check: the fits, eikonal D and ``curvature_limit`` of the same rupture on a quadrant
    twice as large, over the same fractions of it (the measurement's convergence;
    ``convergence`` gives the changes).

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front (dimensionless).
    gamma : float
        Viscous damping (dimensionless).
    dx, dy : float
        Lattice spacings (dimensionless).
    size : tuple of int
        (nx, ny) of the quadrant.
    arrival : numpy.ndarray
        First slip times (units of sqrt(m/k_p)), shape (ny, nx).
    profiles : dict
        Per direction: r (dimensionless x), t (units of sqrt(m/k_p)), c (units of the
        sound speed).
    fits : dict
        Per direction: (c0 in sound speeds, D in sound speeds times x).
    planar : dict
        Per direction: the planar front speed (units of the sound speed).
    fit_range : tuple of float
        The fitted fractions of the quadrant.
    check : dict or None, default None
        The same on a quadrant twice as large.
    eikonal : dict or None, default None
        Per direction: D over the lower and the upper half of the range.

    Examples
    --------
    >>> import bkwaves as bk
    >>> r = bk.lattice.rupture(0.6, 0.3, 0.1, size=32, check=False)
    >>> r.size, r.arrival.shape
    ((32, 32), (32, 32))
    """

    u_plus: float
    gamma: float
    dx: float
    dy: float
    size: tuple[int, int]
    arrival: np.ndarray
    profiles: dict
    fits: dict
    planar: dict
    fit_range: tuple[float, float]
    check: dict | None = None
    eikonal: dict | None = None

    def aspect(self, t: float) -> float:
        """The rupture's extent along x over its extent along y, in blocks, at time t
        (dy/dx for a circle in (x, y) = (i dx, j dy)).

        The extent along an axis is where the front is at time t along that edge of the
        quadrant: the blocks' arrival times interpolated linearly between blocks, in
        blocks from the rupture's centre (half a block before block 0).

        Parameters
        ----------
        t : float
            The time (units of sqrt(m/k_p)).

        Returns
        -------
        float
            The ratio (NaN before the front has passed two blocks along each axis or
            after it has left the quadrant).

        Examples
        --------
        >>> import bkwaves as bk
        >>> r = bk.lattice.rupture(0.6, 0.45, 0.2, size=16, check=False)
        >>> round(r.aspect(1.5), 6)      # dx = dy: a symmetric rupture
        1.0
        """
        a = self.arrival
        ex = _front_at(a[0], t)
        ey = _front_at(a[:, 0], t)
        return ex / ey if ey > 0 else math.nan

    def curvature(self, direction: str = "x") -> dict:
        """The front's local speed and local curvature where it crosses an axis or the
        diagonal, and the local eikonal coefficient D = (c_planar - c)/kappa.

        The curvature is measured, not taken as 1/R: across the front the arrival times
        near the crossing are fitted as T = T0 + (kappa/(2c)) s^2 over the first four
        blocks beside it (s the distance across the direction; the quadrant's edges are
        mirror planes, so s = (j + 1/2) dy beside the x axis and the blocks (d - k, d + k)
        at s = k sqrt(2) dx beside the diagonal). Compare D with
        ``bk.theory.curvature_coefficient``, its kappa -> 0 limit (docs/lattice.md).

        Parameters
        ----------
        direction : {"x", "y", "diagonal"}
            Where the front is measured ("diagonal" needs dx = dy).

        Returns
        -------
        dict
            Arrays ``r`` (radius from the centre, dimensionless length), ``c`` (local
            speed, central differences, units of the sound speed), ``kappa`` (local
            curvature, 1/length) and ``D`` (length), over the blocks from the fourth to
            the sixth before the far edge.

        Examples
        --------
        >>> import bkwaves as bk
        >>> r = bk.lattice.rupture(0.6, 0.45, 0.2, size=24, check=False)
        >>> k = r.curvature("x")
        >>> bool(k["kappa"][-1] < k["kappa"][0])      # flatter as it grows
        True
        """
        a = self.arrival
        if direction == "y":
            a = a.T
            h, hs = self.dy, self.dx
        elif direction == "x":
            h, hs = self.dx, self.dy
        elif direction == "diagonal":
            if self.dx != self.dy:
                raise ValueError("direction 'diagonal' needs dx = dy")
            h = hs = self.dx
        else:
            raise ValueError(f"direction must be 'x', 'y' or 'diagonal', got {direction!r}")
        rows = []
        if direction == "diagonal":
            s2 = (np.arange(4) * math.sqrt(2.0) * h) ** 2
            for d in range(4, min(a.shape) - 8):
                t = np.array([a[d - k, d + k] for k in range(4)])
                dt = a[d + 1, d + 1] - a[d - 1, d - 1]
                rows.append((d, t, dt, math.sqrt(2.0) * h, s2))
        else:
            s2 = ((np.arange(4) + 0.5) * hs) ** 2
            for i in range(4, a.shape[1] - 6):
                rows.append((i, a[:4, i], a[0, i + 1] - a[0, i - 1], h, s2))
        r, c, kappa = [], [], []
        for i, t, dt, step, s2 in rows:
            if not (np.all(np.isfinite(t)) and np.isfinite(dt) and dt > 0):
                continue
            q = np.polyfit(s2, t, 1)[0]
            ci = 2.0 * step / dt
            r.append((i + 0.5) * step)
            c.append(ci)
            kappa.append(2.0 * q * ci)
        r, c, kappa = np.array(r), np.array(c), np.array(kappa)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = (self.planar[direction] - c) / kappa
        return {"r": r, "c": c, "kappa": kappa, "D": d}

    def curvature_limit(self, direction: str = "x") -> tuple[float, float]:
        """The kappa -> 0 limit of the local eikonal coefficient: a line D + E kappa
        through the outer third of ``curvature(direction)``'s local D (the flattest
        points), as in docs/lattice.md "Derived: the curvature coefficient".

        Parameters
        ----------
        direction : {"x", "y", "diagonal"}
            Where the front is measured ("diagonal" needs dx = dy).

        Returns
        -------
        tuple of float
            (D, E): D a length (compare ``bk.theory.curvature_coefficient``), E a length
            squared (the local D's growth with kappa). Doubling the quadrant moves D by
            less than 2 % from 32 to 64 blocks and 0.5 % from 64 to 128 (``check``;
            docs/validation.md).

        Examples
        --------
        >>> import bkwaves as bk
        >>> r = bk.lattice.rupture(0.6, 0.45, 0.2, size=32, check=False)
        >>> d, e = r.curvature_limit("x")
        >>> bool(abs(d / bk.theory.curvature_coefficient(0.6, 0.45, 0.2) - 1) < 0.02)
        True
        """
        m = self.curvature(direction)
        n = m["kappa"].size
        if n < 6:
            return (math.nan, math.nan)
        e, d0 = np.polyfit(m["kappa"][2 * n // 3 :], m["D"][2 * n // 3 :], 1)
        return (float(d0), float(e))

    @property
    def convergence(self) -> dict | None:
        """The change of each measured number when the quadrant is doubled (``check``),
        per direction: ``c0`` (absolute, sound speeds) of the fit c0 - D/R, ``D_fit``,
        ``D_eikonal`` (the mean of the two halves) and ``D_limit`` (``curvature_limit``)
        relative. None without ``check``. The 1/R fits drift by about 10 % per doubling
        (a rupture is not a circle and the local D grows with kappa): only ``D_limit``
        is a converged measurement of D (docs/lattice.md)."""
        if self.check is None:
            return None
        out = {}
        for k in self.fits:
            c0, d = self.fits[k]
            c2, d2 = self.check["fits"][k]
            e1, e2 = np.mean(self.eikonal[k]), np.mean(self.check["eikonal"][k])
            twice = self.check.get("limit", {}).get(k)
            lim = abs(twice[0] / self.curvature_limit(k)[0] - 1) if twice else math.nan
            out[k] = {
                "c0": abs(c2 - c0),
                "D_fit": abs(d2 / d - 1),
                "D_eikonal": abs(e2 / e1 - 1),
                "D_limit": lim,
            }
        return out


def _front_at(arrival: np.ndarray, t: float) -> float:
    """Where the front along a row of blocks is at time t, in blocks from the centre
    (block k at k + 1/2), the arrival times interpolated linearly; NaN outside the blocks
    reached or where the arrival times do not increase."""
    ok = np.isfinite(arrival)
    n = arrival.size if ok.all() else int(np.argmin(ok))  # the reached prefix
    arr = arrival[:n]
    if n < 2 or not (arr[0] <= t <= arr[-1]) or np.any(np.diff(arr) <= 0):
        return math.nan
    return float(np.interp(t, arr, np.arange(n) + 0.5))


def _profile(r: np.ndarray, t: np.ndarray) -> dict:
    ok = np.isfinite(t)
    r, t = r[ok], t[ok]
    c = np.full(r.size, np.nan)
    if r.size > 2:
        c[1:-1] = (r[2:] - r[:-2]) / (t[2:] - t[:-2])
    return {"r": r, "t": t, "c": c}


def _eikonal(prof: dict, c_planar: float, lo: float, hi: float) -> tuple[float, float]:
    """D = (c_planar - c(R)) R over [lo, hi] of R with c0 fixed at the planar speed: its
    means over the lower and the upper half of the range (equal if c = c0 - D/R)."""
    r, c = prof["r"], prof["c"]
    mid = 0.5 * (lo + hi)
    out = []
    for a, b in ((lo, mid), (mid, hi)):
        m = np.isfinite(c) & (r >= a) & (r <= b)
        out.append(float(np.mean((c_planar - c[m]) * r[m])) if m.any() else math.nan)
    return tuple(out)


def _fit(prof: dict, lo: float, hi: float) -> tuple[float, float]:
    r, c = prof["r"], prof["c"]
    m = np.isfinite(c) & (r >= lo) & (r <= hi)
    if m.sum() < 3:
        return (math.nan, math.nan)
    a = np.column_stack([np.ones(m.sum()), 1.0 / r[m]])
    (c0, slope), *_ = np.linalg.lstsq(a, c[m], rcond=None)
    return (float(c0), float(-slope))


def _rupture_once(u_plus, gamma, dx, dy, nx, ny, step, beta, fit):
    p = _lattice_params(gamma, dx, beta)
    la = Lattice((nx, ny), p, u0=u_plus, dy=dy, step=step)
    la.kick((0, 0), -2.0)
    # long enough for the front to reach the far corner (sqrt(2) L at about c(u_+))
    c_est = 1.0 / math.sqrt(1.0 - u_plus * u_plus)
    t_end = 1.6 * max(nx * dx, ny * dy) / c_est
    res = la.run(t_end=t_end, progress=False)
    a = res.first_slip_times()
    i = np.arange(nx)
    j = np.arange(ny)
    m = min(nx, ny)
    d = np.arange(m)
    # leave out the last blocks before the far (free) edges
    cut = 4
    profiles = {
        "x": _profile((i[:-cut] + 0.5) * dx, a[0, :-cut]),
        "y": _profile((j[:-cut] + 0.5) * dy, a[:-cut, 0]),
        "diagonal": _profile((d[:-cut] + 0.5) * math.hypot(dx, dy), a[d[:-cut], d[:-cut]]),
    }
    lo, hi = fit
    size = min(nx * dx, ny * dy)
    rng = (lo * size, hi * size)
    fits = {k: _fit(v, *rng) for k, v in profiles.items()}
    return a, profiles, fits, rng


def _eikonals(profiles, planar, rng) -> dict:
    return {k: _eikonal(profiles[k], planar[k], *rng) for k in profiles}


def rupture(
    u_plus: float,
    gamma: float,
    dx: float,
    size: int = 128,
    *,
    dy: float | None = None,
    step: float = DEFAULT_STEP,
    beta: float = math.inf,
    fit: tuple[float, float] = (0.25, 0.95),
    check: bool = True,
) -> Rupture:
    """An expanding rupture from a point in uniform u_+ (v = 0): its radius against time
    along the axes and the diagonal, and the curvature correction to its speed.

    The lattice is a quadrant of ``size`` blocks along x (and size dx/dy along y) with
    free edges, kicked at its corner block: the free edges are mirror planes, so this is a
    rupture from the four centre blocks of a lattice four times larger. The local speed
    along each direction is fitted as c(R) = c0 - D/R for R in ``fit`` (fractions of the
    quadrant's extent); c0 must tend to the planar speed of that direction (``planar``,
    from ``front``'s exact reductions, measured on chains) and D is the eikonal
    coefficient. With ``check`` the rupture is repeated on a quadrant twice as large.

    Parameters
    ----------
    u_plus : float
        Stress ahead of the front, 0 < u_plus < 1 (dimensionless), at which a planar
        front runs along the axes (refused where the front kicked on the chain of the
        exact reduction stops: the rupture would have no planar speed to tend to).
    gamma : float
        Viscous damping, >= 0 (dimensionless).
    dx : float
        Lattice spacing along x, 0 < dx < 1 (dimensionless).
    size : int, default 128
        Blocks of the quadrant along x, 16 <= size <= 8192.
    dy : float, optional
        Spacing along y (dimensionless); default dx.
    step : float, default 0.05
        Time step as a fraction of min(dx, dy) (in units of sqrt(m/k_p)).
    beta : float, default inf
        f_s/(f_r - f_s) (dimensionless).
    fit : tuple of float, default (0.25, 0.95)
        The fitted range of R, as fractions of the quadrant's extent.
    check : bool, default True
        Repeat on a quadrant twice as large.

    Returns
    -------
    Rupture
        Arrival times, profiles, fits and the planar speeds.

    Examples
    --------
    The fitted c0 along the axes is near the planar speed (a small quadrant):

    >>> import bkwaves as bk
    >>> r = bk.lattice.rupture(0.6, 0.3, 0.1, size=32, check=False)
    >>> [bool(abs(r.fits[k][0] / r.planar[k] - 1) < 1e-3) for k in ("x", "y")]
    [True, True]
    """
    u_plus = V.number("u_plus", u_plus, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    gamma = V.number("gamma", gamma, lo=0.0)
    dx = V.number("dx", dx, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    dy = dx if dy is None else V.number("dy", dy, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    size = V.integer("size", size, lo=16, hi=8192)
    nx, ny = size, max(16, int(round(size * dx / dy)))
    planar = {}
    for k, h in (("x", dx), ("y", dy), ("diagonal", dx / math.sqrt(2.0))):
        # (with dx != dy the diagonal of the lattice is not a direction of exact reduction)
        ok = k != "diagonal" or dx == dy
        c = _planar_c(u_plus, gamma, h, 0, 256, step, beta, (0.5, 0.75))[0] if ok else math.nan
        if ok and not math.isfinite(c):
            # no planar front to tend to: every number of the rupture would be NaN or
            # the kick's transient (a negative D), returned as if measured
            V._fail(
                "u_plus",
                u_plus,
                f"a stress at which a planar front runs (at gamma = {gamma:g}, spacing "
                f"{h:g} along {k} the front kicked on its chain stops within 256 blocks; "
                "bk.lattice.front says whether one runs)",
            )
        planar[k] = c
    a, prof, fits, rng = _rupture_once(u_plus, gamma, dx, dy, nx, ny, step, beta, fit)
    out = Rupture(u_plus, gamma, dx, dy, (nx, ny), a, prof, fits, planar, rng)
    out.eikonal = _eikonals(prof, planar, rng)
    if check:
        a2, prof2, fits2, rng2 = _rupture_once(
            u_plus, gamma, dx, dy, 2 * nx, 2 * ny, step, beta, fit
        )
        twice = Rupture(u_plus, gamma, dx, dy, (2 * nx, 2 * ny), a2, prof2, fits2, planar, rng2)
        dirs = ("x", "y", "diagonal") if dx == dy else ("x", "y")
        out.check = {
            "fits": fits2,
            "eikonal": _eikonals(prof2, planar, rng2),
            "range": rng2,
            "limit": {k: twice.curvature_limit(k) for k in dirs},
        }
    return out


# the public names live in bkwaves.lattice (docs, pickles and reprs say so)
for _obj in (PlanarFront, Rupture, front, rupture):
    _obj.__module__ = "bkwaves.lattice"
del _obj
