"""The free boundary engine (paper Sec. IV-V, App. C) against theory and known answers."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

import bkwaves as bk
from bkwaves import theory

G, V = 0.3, 1e-2


def params(gamma=G, v=V):
    return bk.Params(gamma=gamma, v=v, dx=1e-3)


def quiet(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bk.NoCreepWarning)
        return bk.FreeBoundary(*args, **kw)


# ----------------------------------------------------------------- wave trains
@pytest.mark.parametrize("teeth", [1, 2])
def test_sawtooth_train_keeps_period_L_and_T(teeth):
    """Eq. (L): a saw-tooth train on a ring stays a train, L = c A / v, T = A / v."""
    up = 0.7
    c = bk.front_speed(up)
    A = theory.amplitude(up, c, G)
    L = theory.wavelength(up, G, V)
    T = theory.train_period(up, G, V)
    assert L == pytest.approx(c * A / V, rel=1e-14)
    n = 150 * teeth
    x = np.arange(n) * (teeth * L / n)
    xf = 0.37 * (x[1] - x[0])
    u0 = theory.sawtooth(x, 0.0, up, G, V, x0=xf)
    fronts = [(xf + k * L, 1) for k in range(teeth)]
    fb = bk.FreeBoundary(params(), x, u0, "periodic", shocks=fronts)
    r = fb.run(t_end=3.3 * T, snapshots=[1.1 * T, 2.7 * T])
    s = r.shocks
    nodes = s[s.kind == "node"]
    # u_+ stays u_+ and u_- stays u_-(u_+)
    assert np.allclose(nodes.u_plus, up, atol=1e-9)
    assert np.allclose(nodes.u_minus, up - A, atol=1e-9)
    # time period at a node
    k = x[n // 3]
    tk = nodes[np.isclose(nodes.x, k)].t.to_numpy()
    assert len(tk) >= 3
    per = np.diff(tk)  # one front passes every T = L / c whatever the number of teeth
    assert np.allclose(per / T, 1.0, rtol=1e-6, atol=0)
    # spatial period: the snapshots are the saw-tooth translated at speed c
    for t in (1.1 * T, 2.7 * T):
        u = r.snapshots.u.sel(t=t).to_numpy()
        exact = theory.sawtooth(x, t, up, G, V, x0=xf)
        # nodes within one cell of a front may sit on either side of the jump
        zf = np.mod(x - xf - c * t, L)
        far = (zf > 2 * (x[1] - x[0])) & (zf < L - 2 * (x[1] - x[0]))
        assert np.max(np.abs(u - exact)[far]) < 1e-6 * A
    assert r.events.n_shocks.sum() == teeth


def test_a_single_shock_on_a_ring_selects_the_train_with_L_equal_c_A_over_v():
    """Beyond a given saw-tooth: from a uniform state one shock on a ring of length L'
    converges to the train whose u_+ solves c(u_+) A(u_+) / v = L' (eq. L)."""
    Lp, n = 150.0, 150
    x = np.arange(n) * Lp / n
    fb = bk.FreeBoundary(params(), x, np.full(n, 0.5), "periodic", shocks=[(0.1, 1)])
    r = fb.run(t_end=8000.0)
    nodes = r.shocks[r.shocks.kind == "node"]
    us = brentq(
        lambda u: bk.front_speed(u) * theory.amplitude(u, bk.front_speed(u), G) / V - Lp,
        G + 1e-6,
        1 - 1e-9,
    )
    late = nodes[nodes.t > 7000]
    assert np.allclose(late.u_plus, us, rtol=1e-6)
    tk = late[np.isclose(late.x, x[40])].t.to_numpy()
    assert np.allclose(np.diff(tk), theory.train_period(us, G, V), rtol=1e-6)


# ----------------------------------------------------------------- sources
def source(a, n=801, X=40.0, x0_frac=0.3, du=1e-3, v=V, gamma=G):
    x = np.linspace(-X, X, n)
    h = x[1] - x[0]
    x0 = x0_frac * h
    return quiet(params(gamma, v), x, 1 - du - a * (x - x0) ** 2), x0, du / v


def test_birth_starts_as_square_root_of_time():
    """Eq. (b): right after the birth the shocks are at x0 +- sqrt(b t)."""
    a = 1e-3
    fb, x0, tb = source(a, n=4001)
    r = fb.run(max_events=1)
    ev = r.events.iloc[0]
    assert ev.t_start == pytest.approx(tb, rel=1e-12)
    assert ev.x_start == pytest.approx(x0, abs=1e-9)
    assert ev.curvature == pytest.approx(a, rel=1e-9)
    b = theory.source_b(a, V)
    s = r.shocks
    errs = []
    for d in (1, -1):
        p = s[(s.dir == d) & (s.kind == "node")]
        dist = np.abs(p.x.to_numpy() - x0)
        tt = p.t.to_numpy() - tb
        errs.append(np.abs(dist / np.sqrt(b * tt) - 1.0))
    for e, d in zip(errs, (1, -1), strict=True):
        p = s[(s.dir == d) & (s.kind == "node")]
        dist = np.abs(p.x.to_numpy() - x0)
        # the relative deviation vanishes as the shock leaves x0 (u_+ -> 1, eq. cc exact)
        assert e[dist < 0.05].max() < 2e-4
        assert e[(dist > 0.5) & (dist < 1)].max() > e[dist < 0.05].max()


def test_curvature_after_passage_is_a_prime_and_follows_the_map():
    """Eq. (ap) and the map a -> a': the curvature at x0 found at each new birth equals
    the iterates of the map (eq. ap is exact for the curvature *at* x0: the Taylor
    expansions of App. C become exact there), with period T (Sec. V)."""
    a = 1e-4
    assert a < theory.a_max(V, G)
    fb, x0, tb = source(a)
    r = fb.run(max_events=8)
    e = r.events
    expect = theory.iterate_map(a, V, G, len(e) - 1)
    assert np.allclose(e.curvature, expect, rtol=1e-5)
    assert np.allclose(e.x_start, x0, atol=1e-6)
    assert np.allclose(np.diff(e.t_start), theory.source_period(V, G), rtol=1e-9)


def test_map_approaches_the_a_n_asymptote():
    """Sec. V: a_n ~ v^2 / (2 n (1 + kappa)) for n >> 1, followed by the engine."""
    a = 1e-4
    fb, x0, tb = source(a, n=401)
    r = fb.run(max_events=41)
    e = r.events
    n = np.arange(len(e))
    ratio = e.curvature.to_numpy()[1:] / theory.a_n_asymptote(n[1:], V, G)
    # the ratio tends to 1 (slowly: corrections ~ log n / n)
    assert abs(ratio[-1] - 1) < 0.1
    assert abs(ratio[-1] - 1) < abs(ratio[4] - 1) < abs(ratio[0] - 1)


def test_above_a_max_the_maximum_at_x0_is_lost():
    """Eq. (amax): for a > a_max the field after the shocks has a minimum at x0 (a' < 0),
    and the next births are elsewhere."""
    a = 4 * theory.a_max(V, G)
    ap = theory.a_prime(a, V, G)
    assert ap < 0
    fb, x0, tb = source(a)
    fb.run(max_events=1)
    near = np.abs(fb.x - x0) < 0.5
    curv = -np.polyfit(fb.x[near] - x0, fb.u()[near], 2)[0]
    assert curv == pytest.approx(ap, rel=1e-3)
    r = fb.run(max_events=1)
    later = r.shocks[(r.shocks.event == 1) & (r.shocks.kind == "birth")]
    assert len(later) >= 2
    assert np.all(np.abs(later.x - x0) > 1.0)


def test_birth_on_a_grid_node_follows_the_same_map():
    """A maximum exactly on a node (a kink-free maximum seen from two cells)."""
    a = 1e-4
    fb, x0, tb = source(a, x0_frac=0.0)
    e = fb.run(max_events=4).events
    assert np.allclose(e.x_start, 0.0, atol=1e-9)
    assert np.allclose(e.curvature, theory.iterate_map(a, V, G, 3), rtol=1e-4)


def test_birth_at_a_free_end_starts_one_shock_as_t_to_the_two_thirds():
    """u reaching 1 at a free end with slope s: one shock runs inward; from
    dy/dt = 1/sqrt(2 (s y - v t)) (eq. cc) its distance is y = (9 t^2 / (8 s))^(1/3)
    as t -> 0 (the analogue of eq. b at a sloped end; not in the paper)."""
    slope = 5e-3
    x = np.linspace(0, 20, 401)
    r = quiet(params(), x, 0.99 - slope * (20 - x)).run(max_events=1)
    ev = r.events.iloc[0]
    assert ev.x_start == pytest.approx(20.0) and (ev.n_shocks, ev.n_exits) == (1, 1)
    s = r.shocks[r.shocks.kind == "node"]
    y = 20 - s.x.to_numpy()
    t = s.t.to_numpy() - ev.t_start
    dev = np.abs(y / (9 * t**2 / (8 * slope)) ** (1 / 3) - 1)
    assert dev[0] < 1e-2
    assert np.all(np.diff(dev[:40]) > 0)  # vanishes as y -> 0 (like sqrt(y))


# ----------------------------------------------------------------- single shocks
def _int_sqrt(w0, w1):
    F = lambda w: 0.5 * (w * np.sqrt(1 - w * w) + np.arcsin(w))  # noqa: E731
    return F(w1) - F(w0)


def test_shock_dies_where_u_plus_reaches_zero():
    """v = 0, gamma = 0: a shock into u = 0.5 - 0.1 x dies at x = 5 at
    t = int sqrt(1 - u^2) dx = 10 int_0^0.5 sqrt(1 - w^2) dw."""
    x = np.linspace(0, 10, 101)
    fb = bk.FreeBoundary(params(0.0, 0.0), x, 0.5 - 0.1 * x, shocks=[(1e-9, 1)])
    r = fb.run(t_end=100.0)
    end = r.shocks[r.shocks.kind == "death"].iloc[0]
    assert end.x == pytest.approx(5.0, abs=1e-9)
    # (the shock starts at x = 1e-9, where u = 0.5 - 1e-10)
    assert end.t == pytest.approx(10 * _int_sqrt(0.0, 0.5 - 1e-10), rel=1e-12)
    # total slip: int_0^5 A dx with A = 2 u (gamma = 0: u_- = -u_+) = 2 * 0.5 * 5 / 2
    ev = r.events.iloc[0]
    assert ev.moment == pytest.approx(2.5, rel=1e-6)  # the moment: int A dx, dx-free
    assert "slip_integral" not in r.events  # one column, one definition
    assert r.events.attrs["descriptions"]["moment"].startswith("int slip dx")
    assert (ev.nucleation, ev.first_block, ev.last_block) == (0, 0, 5000)
    assert ev.n_blocks == 5000 and ev.stress_drop == pytest.approx(0.5, rel=1e-6)


@pytest.mark.parametrize("rule", ["zero", "stop"])
def test_creep_is_recorded_and_follows_the_rule(rule):
    """u_+ < u_c = gamma: outside the paper's theory, handled by a documented rule."""
    x = np.linspace(0, 10, 101)
    with pytest.warns(bk.NoCreepWarning):
        fb = bk.FreeBoundary(params(0.3, 1e-4), x, 0.5 - 0.1 * x, shocks=[(1e-9, 1)], creep=rule)
    r = fb.run(t_end=100.0)
    s = r.shocks
    ev = r.events.iloc[0]
    if rule == "stop":
        end = s[s.kind == "creep_stop"].iloc[0]
        assert end.u_plus == 0.3
        # u_+ = 0.5 - 0.1 x + v t = 0.3 with v t ~ 2e-4: x = 2 + 10 v t
        assert end.x == pytest.approx(2.0 + 10 * 1e-4 * end.t, abs=1e-9)
        assert ev.n_creep == 0
    else:
        crept = s[s.creep & (s.kind == "node")]
        assert len(crept) > 0 and np.all(crept.u_minus == 0.0)
        assert np.all(crept.u_plus <= 0.3)
        assert ev.n_creep == len(crept)
        assert s[s.kind == "death"].x.iloc[0] == pytest.approx(5.0, abs=1e-2)


def test_free_ends_and_annihilation():
    """Two sources: the inner shocks annihilate midway, the outer ones leave."""
    x = np.linspace(-20, 20, 401)
    u0 = 0.9 - 2e-3 * (np.abs(x) - 10.0) ** 2
    r = quiet(params(0.2), x, u0).run(max_events=1)
    ev = r.events.iloc[0]
    assert (ev.n_births, ev.n_annihilations, ev.n_exits) == (2, 1, 2)
    ann = r.shocks[r.shocks.kind == "annihilation"]
    assert np.allclose(ann.x, 0.0, atol=1e-9)
    assert ev.extent == pytest.approx(40.0)
    assert ev.swept == pytest.approx(40.0)


# ----------------------------------------------------------------- API
def test_validation_errors_name_the_parameter():
    x = np.linspace(0, 1, 11)
    u = np.full(11, 0.5)
    p = params()
    cases = [
        (lambda: bk.FreeBoundary(p, x, u, "fixed"), "boundary"),
        (lambda: bk.FreeBoundary(p, x, u, creep="x"), "creep"),
        (lambda: bk.FreeBoundary(params(1.2), x, u), "gamma"),
        (lambda: bk.FreeBoundary(p, x[:4], u[:4]), "x"),
        (lambda: bk.FreeBoundary(p, x**2, u), "x"),
        (lambda: bk.FreeBoundary(p, x, np.full(11, 1.0)), "u0"),
        (lambda: bk.FreeBoundary(p, x, u[:5]), "u0"),
        (lambda: bk.FreeBoundary(p, x, u, shocks=[(0.5, 2)]), "direction"),
        (lambda: bk.FreeBoundary(p, x, u, shocks=[(5.0, 1)]), "shock position"),
        (lambda: bk.FreeBoundary("p", x, u), "params"),
        (lambda: bk.FreeBoundary(p, x, u).run(), "t_end"),
    ]
    for f, name in cases:
        with pytest.raises(bk.ParameterError, match=name):
            f()


def test_no_creep_warning():
    x = np.linspace(0, 10, 101)
    with pytest.warns(bk.NoCreepWarning, match="nocreep"):
        bk.FreeBoundary(params(), x, 0.5 - 0.05 * x)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bk.FreeBoundary(params(), x, 0.5 - 0.005 * x)


def test_run_continues_snapshots_and_ctrl_c(monkeypatch):
    fb, x0, tb = source(1e-4, n=201)
    r1 = fb.run(t_end=50.0, snapshots=5)
    assert list(r1.snapshots.t.values) == pytest.approx(np.linspace(0, 50, 5))
    assert r1.snapshots.attrs["engine"] == "free_boundary"
    assert "gamma" in r1.snapshots.attrs["params"]
    r2 = fb.run(t_end=300.0)
    assert fb.time == 300.0 and r2.snapshots.t.values[-1] == 300.0
    assert len(r2.events) >= 2 and bool(r2.events.complete.iloc[0])

    engine = fb._engine

    class Boom:
        def __getattr__(self, k):
            return getattr(engine, k)

        def advance(self, *a):
            raise KeyboardInterrupt

    monkeypatch.setattr(fb, "_engine", Boom())
    with pytest.warns(RuntimeWarning, match="interrupted"):
        r3 = fb.run(t_end=1000.0, progress=True)
    assert r3.interrupted and len(r3.events) == len(r2.events)


@pytest.mark.parametrize("boundary", ["free", "periodic"])
@pytest.mark.parametrize("gamma", [0.0, 0.3])
def test_random_fields_keep_the_books(boundary, gamma):
    """Many births, collisions of crowded shocks (gamma = 0 synchronises the chain, so
    pairs are born everywhere at once): every shock created is accounted for, no shock
    dies on a node another shock just reset, u_+ never exceeds 1."""
    rng = np.random.default_rng(3)
    x = np.linspace(0, 200.0, 1001)[: (1000 if boundary == "periodic" else 1001)]
    k = np.arange(1, 20)
    ph = rng.uniform(0, 2 * np.pi, k.size)
    u0 = 0.5 + sum(
        0.05 / kk * np.sin(2 * np.pi * kk * x / 200.0 + p) for kk, p in zip(k, ph, strict=True)
    )
    r = quiet(params(gamma, 1e-2), x, np.minimum(u0, 0.99), boundary).run(max_events=20)
    e = r.events[r.events.complete]
    assert len(e) == 20
    assert (e.n_shocks == 2 * e.n_annihilations + e.n_exits + e.n_deaths).all()
    s = r.shocks
    assert (s[s.kind == "death"].u_plus >= -1e-12).all()
    assert s.u_plus.max() <= 1 + 1e-4
    assert (s[s.kind == "node"].u_plus > 0).all()
    assert e.n_births.sum() > 40


def _smooth_random_ring(n, corr, h, rng):
    """Zero-mean Gaussian random field on a ring of n nodes (spacing h), Gaussian
    correlation of length ``corr``, scaled to max |.| = 1."""
    k = 2 * np.pi * np.fft.rfftfreq(n, d=h)
    f = np.fft.irfft(np.fft.rfft(rng.standard_normal(n)) * np.exp(-0.25 * (k * corr) ** 2), n)
    f -= f.mean()
    return f / np.abs(f).max()


def _local_cubic(u, h, xq):
    """The engine's interpolant away from shocks: the cubic through the four nodes around
    each point (ring)."""
    r = xq / h
    j = np.floor(r).astype(int)
    s = r - j
    n = len(u)
    v = [u[(j + o) % n] for o in (-1, 0, 1, 2)]
    return (
        -v[0] * s * (s - 1) * (s - 2) / 6
        + v[1] * (s + 1) * (s - 1) * (s - 2) / 2
        - v[2] * (s + 1) * s * (s - 2) / 2
        + v[3] * (s + 1) * s * (s - 1) / 6
    )


def test_first_cycle_births_are_where_u0_reaches_one():
    """A sharp periodic random field (curvatures ~1e-2 at its maxima, h = 0.2) on a large
    ring (L = 6400): in the first cycle no birth can happen on swept field (u_- < 0 there
    needs ~1/v to reach 1 again), so every birth is where the initial field has reached
    1, u0(x_b) + v t_b = 1, and there is at most one per local maximum of u0. (Spurious
    pairs were born next to every fresh shock before: ~2000 births in half a cycle.)"""
    h, n = 0.2, 32000
    x = np.arange(n) * h
    u0 = 0.5 + 0.3 * _smooth_random_ring(n, 4.0, h, np.random.default_rng(1))
    t_first = (1 - u0.max()) / V
    r = quiet(params(), x, u0, "periodic", record_path=False).run(t_end=t_first + 0.4 / V)
    b = r.shocks[(r.shocks.kind == "birth") & (r.shocks.dir > 0)]
    assert len(b) > 50
    err = np.abs(_local_cubic(u0, h, b.x.to_numpy()) + V * b.t.to_numpy() - 1)
    assert err.max() < 1e-6, err.max()
    maxima = np.sum((u0 > np.roll(u0, 1)) & (u0 >= np.roll(u0, -1)))
    assert len(b) <= maxima


def test_first_event_agrees_with_bk_chain():
    """The same slowly varying state (two bumps on a sinusoidal ramp, ring of length
    0.3/v) run by bk.Chain and bk.FreeBoundary: one rupture, same place, same catalog
    (chain units), fronts and stress left within the tolerances measured in
    docs/validation.md ("Against the direct chain")."""
    v, dx = 1e-3, 0.1
    p = bk.Params(gamma=G, v=v, dx=dx)
    L = 0.3 / v

    def u0(x):
        d = lambda c: np.mod(x - c + L / 2, L) - L / 2  # noqa: E731
        w = 40.0 * L / 300
        return (
            0.9
            + 0.015 * np.sin(2 * np.pi * x / L)
            + 0.03 * np.exp(-((d(0.3 * L) / w) ** 2))
            + 0.025 * np.exp(-((d(0.7 * L) / w) ** 2))
        )

    n = int(round(L / dx))
    cr = bk.Chain(n, p, "periodic", u0(np.arange(n) * dx)).run(max_events=1)
    xg = np.arange(600) * (L / 600)
    fb = quiet(p, xg, u0(xg), "periodic")
    fr = fb.run(max_events=1)
    ce, fe = cr.catalog.iloc[0], fr.events.iloc[0]
    assert abs(int(ce.nucleation) - int(fe.nucleation)) <= 2
    off = ce.t_start - fe.t_start  # the chain slips at u - u_xx = 1: 2a/v earlier
    assert -1e-4 < off * v < 0
    assert ce.n_blocks == fe.n_blocks == n
    assert ce.moment / fe.moment - 1 == pytest.approx(0, abs=2.5 * v)
    # slip fronts: first slip of each block vs the shock passing the grid nodes
    first = cr.first_slip_times(0)
    nodes = fr.shocks[fr.shocks.kind == "node"]
    blocks = np.rint(nodes.x.to_numpy() / dx).astype(int) % n
    dt = first[blocks] - nodes.t.to_numpy() - off
    assert np.max(np.abs(dt)) < 5e-3 * fe.duration
    # stress left, away from the collision zone (where the chain leaves a dip ~0.08)
    xc = fr.shocks[fr.shocks.kind == "annihilation"].x.iloc[0]
    uf = fb.u() + v * (cr.t - fb.time)
    far = np.abs(np.mod(xg - xc + L / 2, L) - L / 2) > 5
    i = np.rint(xg / dx).astype(int) % n
    assert np.max(np.abs(cr.u[i] - uf)[far]) < 5 * v
    assert np.max(np.abs(cr.u[i] - uf)[~far]) > 0.05


def test_chunked_and_continued_runs_equal_one_run_bit_for_bit():
    """Stopping (chunks, snapshots, a second run call) changes nothing in the results."""
    x = np.linspace(0, 200.0, 401)
    u0 = 0.6 + 0.3 * np.exp(-(((x - 70) / 30) ** 2)) + 0.25 * np.exp(-(((x - 150) / 25) ** 2))
    a = quiet(params(), x, u0).run(t_end=300.0)
    fb = quiet(params(), x, u0)
    fb.run(t_end=120.0, snapshots=7, chunk=3)
    b = fb.run(t_end=300.0, snapshots=[150.0, 151.0], chunk=5)
    assert len(a.events) >= 3
    for col in ("t_start", "t_end", "x_start", "moment", "n_births"):
        assert np.array_equal(a.events[col].to_numpy(), b.events[col].to_numpy(), equal_nan=True)
    assert a.shocks.equals(b.shocks)
    assert np.array_equal(a.snapshots.u.isel(t=-1), b.snapshots.u.isel(t=-1))


def test_nothing_to_do_without_loading():
    """v = 0 and no shocks: no event ever happens; the run returns at once."""
    x = np.linspace(0, 10, 11)
    fb = bk.FreeBoundary(params(G, 0.0), x, np.full(11, 0.5))
    r = fb.run(max_events=1)
    assert len(r.events) == 0 and fb.time == 0.0
    assert fb.run(t_end=5.0).snapshots.t.values[-1] == 5.0


@pytest.mark.parametrize("boundary", ["free", "periodic"])
def test_pickled_mid_run_state_continues_bit_for_bit(boundary, tmp_path):
    """A checkpoint (pickle, or save/load) taken inside an event, with live shocks and
    recorded snapshots, continues exactly like the uninterrupted run."""
    import pickle

    x = np.linspace(0, 200.0, 401)[: (400 if boundary == "periodic" else 401)]
    u0 = 0.6 + 0.3 * np.exp(-(((x - 70) / 30) ** 2)) + 0.25 * np.exp(-(((x - 150) / 25) ** 2))
    fb = quiet(params(), x, u0, boundary)
    # stop on the engine's step budget inside the first event, then on a time
    while not fb._engine.n_shocks:
        assert fb._engine.advance(300.0, 7, 2**62) == "steps"
    fb._engine.advance(300.0, 11, 2**62)
    assert fb._engine.n_shocks > 0
    t_cut = fb.time
    fb.run(t_end=t_cut + 1.5, snapshots=[t_cut + 0.5])
    assert fb._engine.n_shocks > 0 and len(fb._snap_t) == 3
    a = quiet(params(), x, u0, boundary).run(t_end=300.0, snapshots=[t_cut + 0.5, t_cut + 1.5])
    fb.save(tmp_path / "fb.pkl")
    for b_fb in (pickle.loads(pickle.dumps(fb)), bk.FreeBoundary.load(tmp_path / "fb.pkl")):
        assert b_fb.time == fb.time and b_fb.tol == fb.tol
        np.testing.assert_array_equal(b_fb.u(), fb.u())
        assert b_fb.current_shocks().equals(fb.current_shocks())
        b = b_fb.run(t_end=300.0)
        assert len(a.events) >= 3
        assert a.events.equals(b.events)
        assert a.shocks.equals(b.shocks)
        assert a.snapshots.equals(b.snapshots) and a.steps == b.steps
        np.testing.assert_array_equal(a.snapshots.u.values, b.snapshots.u.values)


def test_checkpoint_of_another_configuration_is_refused(tmp_path):
    x = np.linspace(0, 20.0, 41)
    fb = quiet(params(), x, np.full(41, 0.5))
    other = quiet(params(0.2), x, np.full(41, 0.5))
    with pytest.raises(bk.ParameterError, match="checkpoint"):
        other._engine.restore(fb._engine.checkpoint())
    with pytest.raises(bk.ParameterError, match="checkpoint"):
        other._engine.restore(b"not a checkpoint")
    (tmp_path / "x.pkl").write_bytes(__import__("pickle").dumps({"a": 1}))
    with pytest.raises(bk.ParameterError, match="FreeBoundary.save"):
        bk.FreeBoundary.load(tmp_path / "x.pkl")
