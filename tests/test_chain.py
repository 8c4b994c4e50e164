"""The chain simulator against theory: the finite-dx tip solver (the exact steady front),
the gamma = 0 lattice closed form, App. B (u_-, w), energy balance, symmetry, SI units,
the result objects, the command line."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import _core
from bkwaves.chain import default_blocks, smooth_random_stress


def front_c(u, g, dx, n=1600, **kw):
    return _core.front_measure(u, dx, n, friction={"gamma": g}, heal=False, **kw)["c"]


@pytest.mark.parametrize(
    "u,g,dx",
    [(0.5, 0.3, 0.1), (0.7, 0.45, 0.05), (0.9, 0.3, 0.025), (0.3, 0.45, 0.05), (0.5, 0.0, 0.05)],
)
def test_front_speed_equals_finite_dx_tip_solver(u, g, dx):
    # the tip problem at finite dx is exact for the chain's steady front at v = 0
    # (gamma = 0: every block behind the front keeps slipping, so a shorter chain;
    # the trigger's transient has decayed to 1e-8 after 200 blocks at u = 0.5)
    n = 800 if g == 0 else 1600
    c = front_c(u, g, dx, n)
    tip = bk.tip_solve(u, dx=dx, gamma=g)["c"]
    assert c == pytest.approx(tip, rel=1e-7)
    # and the error is the time step's: a finer step gets closer (4th order)
    fine = front_c(u, g, dx, n, step=0.025)
    assert abs(fine / tip - 1) < abs(c / tip - 1) / 4 or abs(fine / tip - 1) < 1e-12


def test_gamma_zero_matches_the_lattice_closed_form():
    for dx in (0.1, 0.025):
        c = front_c(0.5, 0.0, dx, 800)
        assert c == pytest.approx(float(_core.lattice_front_speed(np.array(0.5), dx)), rel=1e-7)


def test_richardson_extrapolation_reaches_the_continuum_speed():
    # c(dx) = c0 + a1 dx + a2 dx^2 + ...: eliminate dx and dx^2 from three spacings
    u, g = 0.6, 0.3
    c1, c2, c3 = (front_c(u, g, dx) for dx in (0.05, 0.025, 0.0125))
    r1a, r1b = 2 * c2 - c1, 2 * c3 - c2
    r2 = (4 * r1b - r1a) / 3
    assert abs(r2 - bk.front_speed(u)) < 1e-5
    # first order in dx at gamma > 0 (the -2 gamma dx w' term of the tip problem)
    order = np.log2((c1 - c2) / (c2 - c3))
    assert 0.8 < order < 1.2


def test_pulse_u_minus_and_w_approach_app_b():
    u, g = 0.7, 0.45
    tw = bk.traveling_wave(u, g)
    res = []
    for dx in (0.05, 0.025):
        m = bk.chain.front(u, g, dx)
        assert m.regime == "pulse"
        res.append((m.u_minus, m.w))
    # first-order convergence: one Richardson step is within 1e-3 of App. B
    um = 2 * res[1][0] - res[0][0]
    w = 2 * res[1][1] - res[0][1]
    assert um == pytest.approx(tw.u_minus, abs=1e-3)
    assert w == pytest.approx(tw.w, abs=1e-2 * tw.w)
    # the raw values are off by O(dx), so the check can fail
    assert abs(res[0][0] - tw.u_minus) > 1e-4


@pytest.mark.parametrize("g,u,dx", [(0.3, 0.4, 0.025), (0.0, 0.3, 0.025), (0.45, 0.7, 0.05)])
def test_default_front_measures_a_pulse_as_a_pulse(g, u, dx):
    # the first two were "creep" with the old default chain (1600 blocks, window in the
    # trigger's transient); the third was not tuned for. The chain's w and u_- differ
    # from App. B by O(dx) and O(gamma dx); c equals the finite-dx tip solution.
    m = bk.chain.front(u, g, dx)
    tw = bk.traveling_wave(u, g)
    assert m.regime == "pulse", m.reason
    assert m.settled and m.window[0] >= 2 * m.settling_length
    assert m.steadiness < 1e-6
    assert m.backward_slips == 0
    assert abs(m.w - tw.w) < 2 * dx
    assert abs(m.u_minus - tw.u_minus) < g * dx + 1e-6
    assert m.c == pytest.approx(bk.tip_solve(u, dx=dx, gamma=g)["c"], rel=1e-6)
    assert m.app_b == {"regime": "pulse", "c": tw.c, "w": tw.w, "u_minus": tw.u_minus}


def test_pulse_w_and_u_minus_converge_to_app_b_at_first_order():
    # a case no default was tuned for: halving dx halves the error of w and u_-
    u, g = 0.8, 0.15
    tw = bk.traveling_wave(u, g)
    m1, m2 = (bk.chain.front(u, g, dx) for dx in (0.04, 0.02))
    assert m1.regime == m2.regime == "pulse"
    for k, exact in (("w", tw.w), ("u_minus", tw.u_minus)):
        e1, e2 = abs(getattr(m1, k) - exact), abs(getattr(m2, k) - exact)
        assert 1.6 < e1 / e2 < 2.5, (k, e1, e2)


def test_narrow_pulses_at_gamma_zero():
    # u_+ = 0.1, gamma = 0: App. B's pulse is 0.316 wide, 13 lattice spacings at dx =
    # 0.025; the lattice slows the front (c - 1 is half the continuum value) and widens
    # the pulse by ~5 dx. Still a steady pulse; c converges as dx^2, w as dx, u_- = -u_+.
    u = 0.1
    tw = bk.traveling_wave(u, 0.0)
    ms = [bk.chain.front(u, 0.0, dx) for dx in (0.025, 0.0125)]
    for m in ms:
        assert m.regime == "pulse", m.reason
        assert m.steadiness < 1e-5 and m.settled
        # (u at re-stick settles more slowly than the sliding time: part of steadiness)
        assert m.u_minus == pytest.approx(-u, abs=1e-5)
    ec = [abs(m.c - tw.c) for m in ms]
    ew = [abs(m.w - tw.w) for m in ms]
    assert 3.0 < ec[0] / ec[1] < 5.0, ec
    assert 1.6 < ew[0] / ew[1] < 2.5, ew
    assert ew[0] > 3 * 0.025  # the check can fail: several lattice spacings off


def test_u_plus_near_one():
    m = bk.chain.front(0.99, 0.3, 0.05)
    tw = bk.traveling_wave(0.99, 0.3)
    assert m.regime == "pulse" and m.settled
    assert abs(m.w - tw.w) < 2 * 0.05 and abs(m.u_minus - tw.u_minus) < 0.3 * 0.05
    assert m.c == pytest.approx(bk.tip_solve(0.99, dx=0.05, gamma=0.3)["c"], rel=1e-6)


def test_near_the_pulse_creep_boundary_no_pulse_is_claimed_without_a_steady_front():
    # u_+ just above gamma: App. B has a pulse with u_- = -1e-8 (a tail creeping to 0);
    # the chain at dx = 0.1 re-sticks that tail at scattered times, a few % apart, in a
    # window beyond twice the settling length (the finite dx moves the boundary up)
    m = bk.chain.front(0.305, 0.3, 0.1)
    assert m.regime == "creep" and m.w is None and m.u_minus is None
    assert m.steadiness > 10 * bk.chain.STEADY_TOL and m.settled
    assert "App. B" in m.reason and "pulse" in m.reason
    # just below gamma App. B and the chain agree
    m = bk.chain.front(0.29, 0.3, 0.05)
    assert m.regime == "creep" and "App. B predicts creep" in m.reason


def test_a_chain_too_short_is_undecided_not_creep():
    m = bk.chain.front(0.4, 0.3, 0.025, blocks=400)
    assert m.regime == "undecided" and m.w is None and not m.settled
    assert "blocks would settle it" in m.reason
    assert m.blocks == 400 and m.passes == 1


def test_the_settling_length_is_where_the_healing_front_becomes_steady():
    # what the default window rests on, measured: the sliding time of block x deviates
    # from its steady value by > 1e-3 at half the settling length x_s = w v/(c - v) and
    # by < 1e-5 beyond 2 x_s (v: the fastest lattice wave)
    for u, g, dx in ((0.4, 0.3, 0.025), (0.3, 0.0, 0.025)):
        m = bk.chain.front(u, g, dx)
        n = int(4 * m.settling_length / dx)
        r = _core.front_measure(u, dx, n, friction={"gamma": g}, window=(0.8, 0.9))
        dur = r["stick_times"] - r["slip_times"]
        ref = dur[int(0.8 * n)]
        dev = np.abs(dur / ref - 1)
        xs = int(m.settling_length / dx)
        assert dev[xs // 2 : xs].max() > 1e-3
        assert dev[2 * xs : int(0.8 * n)].max() < 1e-5
        # the window's sliding time is the long chain's
        assert m.w == pytest.approx(r["c"] * ref, rel=1e-6)


def test_a_settling_front_is_followed_further_not_called_creep(monkeypatch):
    # with the window at only ~1 settling length, the narrow undamped pulse (gamma = 0,
    # u_+ = 0.1) is still settling there (spread ~5e-3, falling exponentially with x):
    # the default chain is lengthened until it is steady; a given chain is undecided
    monkeypatch.setattr(bk.chain, "SETTLE_MARGIN", 1.0)
    m = bk.chain.front(0.1, 0.0, 0.025)
    assert m.regime == "pulse" and m.passes >= 2, m.reason
    # a given chain whose window (100 blocks, 37 before the end) starts at 1.1 x_s
    n = int(1.1 * m.settling_length / 0.025) + 137
    m = bk.chain.front(0.1, 0.0, 0.025, blocks=n)
    assert m.settled and m.steadiness > bk.chain.STEADY_TOL
    assert m.regime == "undecided" and "still settling" in m.reason, m.reason


def test_lattice_wave_speed():
    for dx in (0.2, 0.05, 0.01):
        q = np.linspace(1e-6, np.pi, 400001)
        vg = np.sin(q) / (dx * np.sqrt(1 + 4 * np.sin(q / 2) ** 2 / dx**2))
        assert bk.chain.lattice_wave_speed(dx) == pytest.approx(vg.max(), rel=1e-9)
    assert 1 - bk.chain.lattice_wave_speed(1e-4) < 1e-3


def test_front_has_no_backward_slip_by_default():
    # with beta = 0 (f_s = 0) about half the slips at gamma = 0 go backward
    m = bk.chain.front(0.5, 0.0, 0.1)
    assert m.beta == math.inf and m.backward_slips == 0
    m0 = bk.chain.front(0.5, 0.0, 0.1, beta=0.0)
    assert m0.backward_slips > 0.3 * m0.slips
    assert m0.regime == m.regime == "pulse" and m0.w != pytest.approx(m.w, rel=1e-3)
    with pytest.raises(bk.ParameterError, match="beta"):
        bk.chain.front(0.5, 0.0, 0.1, beta=-1.0)


def test_chain_default_has_no_backward_slip_and_says_so():
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
    ch = bk.Chain(10, p, u0=0.6)
    with pytest.raises(bk.ParameterError, match="trigger"):
        ch.kick(0, 0.5)  # backward
    with pytest.raises(bk.ParameterError, match="trigger"):
        ch.release(0, direction=-1)
    with pytest.raises(bk.ParameterError, match="u_t0"):
        bk.Chain(10, p, u_t0=0.1)
    ch.kick(0, -2.0)
    res = ch.run(t_end=5.0, snapshots=[5.0])
    assert (res.slips["direction"] > 0).all()
    assert res.snapshots.attrs["beta"] == math.inf
    assert "no backward slip" in res.snapshots.attrs["friction"]
    # beta-free books (the closure itself is tested in the core, both integrators)
    assert res.energy["friction_work"] == 0.0
    assert abs(res.energy["residual"]) < 1e-6 * res.energy["injected"]
    q = bk.Params(gamma=0.3, v=0.0, dx=0.1, beta=0.5)
    bk.Chain(10, q).kick(0, 0.5)  # allowed with backward slip


def test_below_u_c_blocks_creep():
    m = bk.chain.front(0.2, 0.45, 0.05)
    assert m.regime == "creep" and m.u_minus is None and m.w is None
    assert bk.chain.front(0.6, 0.45, 0.05).regime == "pulse"


def test_mirror_symmetry():
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
    n = 150
    a = bk.Chain(n, p, u0=0.6).kick(0, -2.0).run(t_end=12.0)
    b = bk.Chain(n, p, u0=0.6).kick(n - 1, -2.0).run(t_end=12.0)
    ta, tb = a.first_slip_times(), b.first_slip_times()
    assert np.isfinite(ta).sum() > 100
    np.testing.assert_allclose(ta, tb[::-1], rtol=0, atol=1e-12)


@pytest.mark.parametrize("boundary", ["free", "fixed", "periodic"])
def test_loading_cycles_energy_balance_and_catalog(boundary):
    p = bk.Params(gamma=0.3, v=1e-2, dx=0.2, beta=0.5)
    u0 = smooth_random_stress(60, 0.2, mean=0.6, amplitude=0.12, correlation=1.5, seed=3)
    ch = bk.Chain(60, p, boundary=boundary, u0=u0, step=0.02, seed=3)
    res = ch.run(t_end=150.0)
    e = res.energy
    diss = e["friction_work"] + e["viscous_work"]
    assert diss > 0.1 and e["loader_work"] > 0
    assert abs(e["residual"]) < 1e-9 * diss
    cat = res.catalog
    assert len(cat) >= 3
    for col in (
        "t_start",
        "t_end",
        "duration",
        "nucleation",
        "first_block",
        "last_block",
        "n_blocks",
        "moment",
        "stress_drop",
    ):
        assert col in cat.columns
    done = cat.dropna(subset=["t_end"])
    assert (done["first_block"] <= done["nucleation"]).all()
    assert (done["nucleation"] <= done["last_block"]).all()
    # the moment is int slip dx: dx times the sum of the slips of the event's intervals
    s = res.slips
    for _, row in done.iterrows():
        total = s[s["event"] == row["event"]]["slip"].sum()
        assert res.params.dx * total == pytest.approx(row["moment"], rel=1e-12)
    assert cat.attrs["units"]["moment"] == "1"
    assert cat.attrs["scales"]["moment"].startswith("slip (f_r - f_s)/k_p times length")
    assert cat.attrs["descriptions"]["moment"].startswith("int slip dx")


@pytest.mark.parametrize("boundary", ["free", "fixed", "periodic"])
def test_midpoint_integrator_closes_the_energy_books_to_round_off(boundary):
    p = bk.Params(gamma=0.3, v=1e-2, dx=0.2, beta=0.5)
    u0 = smooth_random_stress(60, 0.2, mean=0.6, amplitude=0.12, correlation=1.5, seed=3)
    ch = bk.Chain(60, p, boundary=boundary, u0=u0, step=0.1, integrator="midpoint")
    res = ch.run(t_end=150.0)
    e = res.energy
    diss = e["friction_work"] + e["viscous_work"]
    assert len(res.catalog) >= 3
    assert abs(e["residual"]) < 1e-12 * diss
    assert res.snapshots.attrs["integrator"] == "midpoint"
    with pytest.raises(bk.ParameterError, match="integrator"):
        bk.Chain(10, p, integrator="euler")


def test_snapshots_every_k_events_and_release_trigger():
    p = bk.Params(gamma=0.3, v=1e-2, dx=0.2)
    u0 = smooth_random_stress(60, 0.2, mean=0.5, amplitude=0.1, correlation=1.5, seed=5)
    ch = bk.Chain(60, p, u0=u0).release(30, t=1.0)
    res = ch.run(max_events=6, snapshot_every=2)
    cat = res.catalog
    # the released block starts the first event at t = 1 exactly
    assert cat["t_start"][0] == 1.0 and cat["nucleation"][0] == 30
    assert len(cat) == 6 and res.stop == "events"
    # a snapshot at the end of events 2, 4, 6, when everything is stuck
    np.testing.assert_allclose(res.snapshots["t"], cat["t_end"][[1, 3, 5]], rtol=0, atol=0)
    np.testing.assert_allclose(res.snapshots["u_t"], p.v)


def test_quiet_jump_is_exact_for_one_block():
    # one block loaded at v from u0: slips exactly at (1 - u0)/v, no steps in between
    p = bk.Params(gamma=0.3, v=0.01, dx=0.1)
    res = bk.Chain(1, p, u0=0.2).run(max_events=1)
    assert res.slips["t_start"][0] == pytest.approx(80.0, rel=1e-14)
    assert res.counters["jumps"] >= 1


def test_snapshots_dataset_and_attrs():
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
    ch = bk.Chain(100, p, u0=0.6, seed=11).kick(0, -2.0)
    res = ch.run(t_end=5.0, snapshots=[0.0, 1.0, 2.5, 5.0])
    ds = res.snapshots
    assert ds["u"].shape == (4, 100)
    np.testing.assert_allclose(ds["t"], [0.0, 1.0, 2.5, 5.0])
    np.testing.assert_allclose(ds["x"], np.arange(100) * 0.1)
    for k in ("params", "units", "version", "seed", "boundary"):
        assert k in ds.attrs
    assert ds.attrs["seed"] == 11 and ds.attrs["version"] == bk.__version__
    # the last snapshot equals the state at the end
    np.testing.assert_allclose(ds["u"][-1], res.u, atol=1e-14)
    # blocks the front has not reached are untouched
    assert float(ds["u"][1, -1]) == 0.6


def test_si_run_reproduces_the_dimensionless_one():
    si = bk.Params.from_physical(
        mass=2.4e-12,
        k_c=3.8e7,
        k_p=23.0,
        f_static=1.5e-7,
        f_kinetic=0.3e-7,
        alpha=6.7e-6,
        V=1e-4,
        spacing=1e-6,
    )
    plain = bk.Params(gamma=si.gamma, v=si.v, dx=si.dx, beta=si.beta)
    n = 80
    u0 = smooth_random_stress(n, si.dx, mean=0.9, amplitude=0.05, correlation=0.02, seed=1)
    times = np.linspace(0.0, 0.5, 6)
    a = bk.Chain(n, si, u0=u0).run(t_end=0.5, snapshots=times)
    b = bk.Chain(n, plain, u0=u0).run(t_end=0.5, snapshots=times)
    np.testing.assert_array_equal(a.snapshots["u"].values, b.snapshots["u"].values)
    un = si.units
    ds = a.snapshots
    np.testing.assert_allclose(ds["t_si"], un.time(times))
    np.testing.assert_allclose(ds["X"], un.displacement(ds["u"].values))
    assert len(a.catalog) >= 1


def test_ctrl_c_returns_what_was_computed(monkeypatch):
    p = bk.Params(gamma=0.3, v=0.0, dx=0.05)
    ch = bk.Chain(800, p, u0=0.6).kick(0, -2.0)
    eng = ch._engine
    calls = []

    class Interrupting:
        def __getattr__(self, name):
            return getattr(eng, name)

        def advance(self, *a):
            calls.append(1)
            if len(calls) == 2:
                raise KeyboardInterrupt
            return eng.advance(*a)

    ch._engine = Interrupting()
    res = ch.run(t_end=30.0, chunk_steps=200)
    assert res.interrupted and res.stop == "interrupted"
    assert 0 < res.t < 30.0 and len(res.slips) > 0


def test_checkpoint_restart_is_bit_for_bit(tmp_path, monkeypatch):
    p = bk.Params(gamma=0.3, v=1e-2, dx=0.2, beta=0.5)
    u0 = smooth_random_stress(80, 0.2, mean=0.6, amplitude=0.12, correlation=1.5, seed=9)

    def make():
        return bk.Chain(80, p, boundary="periodic", u0=u0, seed=9).kick(3, -0.5, t=5.0)

    whole = make().run(t_end=150.0, snapshots=[50.0, 100.0], chunk_steps=500)
    # interrupt (Ctrl-C between chunks), save, load, continue
    ch = make()
    eng = ch._engine
    calls = []

    class Interrupting:
        def __getattr__(self, name):
            return getattr(eng, name)

        def advance(self, *a):
            calls.append(1)
            if len(calls) == 3:
                raise KeyboardInterrupt
            return eng.advance(*a)

    ch._engine = Interrupting()
    part = ch.run(t_end=150.0, snapshots=[50.0, 100.0], chunk_steps=500)
    assert part.interrupted and part.t < 150.0
    ch._engine = eng
    ch.save(tmp_path / "chain.ckpt")
    rest = bk.Chain.load(tmp_path / "chain.ckpt").run(t_end=150.0, chunk_steps=500)
    np.testing.assert_array_equal(rest.u, whole.u)
    np.testing.assert_array_equal(rest.u_t, whole.u_t)
    assert rest.slips.equals(whole.slips) and rest.catalog.equals(whole.catalog)
    np.testing.assert_array_equal(rest.snapshots["u"].values, whole.snapshots["u"].values)
    assert rest.energy == whole.energy
    # a checkpoint of another configuration is refused
    other = bk.Chain(80, bk.Params(gamma=0.31, v=1e-2, dx=0.2, beta=0.5), boundary="periodic")
    with pytest.raises(bk.ParameterError, match="checkpoint"):
        other._engine.restore(eng.checkpoint())


def test_bad_input_names_the_parameter():
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
    with pytest.raises(bk.ParameterError, match="boundary"):
        bk.Chain(10, p, boundary="open")
    with pytest.raises(bk.ParameterError, match="n"):
        bk.Chain(0, p)
    with pytest.raises(bk.ParameterError, match="step"):
        bk.Chain(10, p, step=0.99 * 50)
    with pytest.raises(bk.ParameterError, match="block"):
        bk.Chain(10, p).kick(10, -1.0)
    with pytest.raises(bk.ParameterError, match="u0"):
        bk.Chain(10, p, u0=np.zeros(7))
    with pytest.raises(bk.ParameterError, match="u_t0"):
        bk.Chain(10, p, u_t0=[0.0, np.nan])
    with pytest.raises(bk.ParameterError, match="t_end"):
        bk.Chain(10, p).run()
    with pytest.raises(bk.ParameterError, match="u_plus"):
        bk.chain.front(1.5, 0.3, 0.1)


def cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "bkwaves.cli", *args], capture_output=True, text=True, timeout=120
    )


SETTLED_KEYS = ["u_plus", "gamma", "dx", "blocks", "c", "regime", "u_minus", "w", "wall_s"]


def test_cli_front_json():
    r = cli("front", "--u-plus", "0.6", "--gamma", "0.3", "--dx", "0.05", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    # the settled keys first, in their order; then the new ones
    assert list(d)[:9] == SETTLED_KEYS
    for k in ("beta", "steadiness", "window", "settling_length", "settled", "reason", "app_b"):
        assert k in d
    assert d["beta"] == "inf" and d["backward_slips"] == 0 and d["settled"] is True
    assert d["steadiness"] < 1e-6 and d["window"][0] >= 2 * d["settling_length"]
    assert d["regime"] == "pulse" and d["blocks"] == default_blocks(0.6, 0.3, 0.05)
    assert d["c"] == pytest.approx(bk.tip_solve(0.6, dx=0.05, gamma=0.3)["c"], rel=1e-7)
    r = cli("front", "--u-plus", "0.2", "--gamma", "0.3", "--dx", "0.05", "--json")
    d = json.loads(r.stdout)
    assert d["regime"] == "creep" and d["w"] is None and d["u_minus"] is None


def test_cli_front_text_says_how_steady_and_takes_beta():
    r = cli("front", "--u-plus", "0.5", "--gamma", "0", "--dx", "0.1", "--beta", "0")
    assert r.returncode == 0, r.stderr
    out = r.stdout
    assert "regime  = pulse" in out and "steady  = " in out and "why     : " in out
    assert "backward slip on" in out and " 0 backward slips" not in out
    assert "App. B  : pulse" in out
    # its convergence (issue 22): the change against a window half as far out
    moved = next(line for line in out.splitlines() if line.startswith("moved   = "))
    assert "c " in moved and "u_minus " in moved and "half as far out" in moved
    r = cli("front", "--u-plus", "0.5", "--gamma", "0", "--dx", "0.1")
    assert "no backward slip; 0 backward slips" in r.stdout


def test_cli_front_takes_the_law_and_its_parameters():
    base = ["front", "--u-plus", "0.6", "--gamma", "0.3", "--dx", "0.1", "--blocks", "120"]
    vw = ["--law", "velocity_weakening", "--v-f", "0.01"]
    r = cli(*base, *vw, "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["law"] == "velocity_weakening" and d["v_f"] == 0.01
    law = bk.friction.law("velocity_weakening", v_f=0.01)
    m = bk.chain.front(0.6, 0.3, 0.1, 120, friction=law)
    assert d["c"] == m.c and d["regime"] == m.regime
    # weakening slows the front (docs/chain.md: c = 1.072 against Coulomb's 1.234)
    assert d["c"] < bk.chain.front(0.6, 0.3, 0.1, 120).c - 0.1
    out = cli(*base, *vw).stdout
    assert "law     = velocity_weakening   v_f = 0.01" in out and "regime  = " in out
    assert "Coulomb friction" in out
    assert "--v-f" in cli("front", "--help").stdout
    for extra, words in (
        (["--v-f", "0.01"], "v_f"),  # coulomb has no v_f
        (["--law", "colomb"], "velocity_weakening"),
        (["--law", "velocity_weakening"], "v_f"),
        (["--law", "velocity_weakening", "--v-f", "0"], "0 < v_f"),
    ):
        r = cli(*base, *extra, "--json")
        assert r.returncode == 2 and words in r.stderr and "Traceback" not in r.stderr, r.stderr


@pytest.mark.parametrize(
    "args,name",
    [
        (["--u-plus", "0.5", "--gamma", "0.3", "--dx", "0.1", "--beta", "-1"], "beta"),
        (["--u-plus", "1.5", "--gamma", "0.3", "--dx", "0.1"], "u_plus"),
        (["--u-plus", "0.5", "--gamma", "-1", "--dx", "0.1"], "gamma"),
        (["--u-plus", "0.5", "--gamma", "0.3", "--dx", "0"], "dx"),
        (["--u-plus", "0.5", "--gamma", "0.3", "--dx", "0.1", "--blocks", "3"], "blocks"),
    ],
)
def test_cli_front_bad_input(args, name):
    r = cli("front", *args, "--json")
    assert r.returncode == 2
    assert name in r.stderr and "Traceback" not in r.stderr


def test_catalog_rows_say_what_started_them():
    """kind: a trigger's event, then events of blocks reaching their threshold."""
    p = bk.Params(gamma=0.3, v=1e-3, dx=0.1)
    ch = bk.Chain(40, p, u0=0.5)
    ch.kick(5, -1.0, t=1.0)
    r = ch.run(max_events=3, t_end=1e4)
    assert list(r.catalog["kind"]) == ["trigger", "threshold", "threshold"]
    first = r.slips[r.slips["event"] == 0]
    assert first["kind"].iloc[0] == "trigger" and set(first["kind"].iloc[1:]) == {"threshold"}
    ch = bk.Chain(10, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.2, u_t0=[-0.5] + [0.0] * 9)
    assert ch.run(t_end=50.0).catalog["kind"].tolist() == ["initial"]


@pytest.mark.parametrize("u, g, dx", [(0.6, 0.3, 0.1), (0.5, 0.0, 0.1)])
def test_front_reports_its_convergence_and_doubling_the_chain_stays_within_tolerance(u, g, dx):
    # the default front reports how much c, w and u_- moved from a window half as far
    # from the trigger; doubling the chain moves them by less than the stated tolerance
    # and less than that report (the approach to the steady pulse is exponential)
    from bkwaves.chain import FRONT_TOLERANCE

    m = bk.chain.front(u, g, dx)
    assert m.regime == "pulse" and m.convergence is not None
    m2 = bk.chain.front(u, g, dx, blocks=2 * m.blocks)
    moved = {
        "c": abs(m2.c / m.c - 1),
        "w": abs(m2.w / m.w - 1),
        "u_minus": abs(m2.u_minus - m.u_minus),
    }
    for k, tol in FRONT_TOLERANCE.items():
        assert moved[k] <= tol, (k, moved[k])
        assert moved[k] <= max(m.convergence[k], 1e-12), (k, moved[k], m.convergence[k])
    assert "convergence" in m.to_dict()
