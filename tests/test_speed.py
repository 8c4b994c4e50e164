"""The front speed c(u_+): tip solver (App. A) vs closed form, convergence, the paper's limits,
and an independent time-marching simulation of the tip lattice."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import bkwaves as bk
from bkwaves import theory as th


def closed(u):
    return 1.0 / np.sqrt(1.0 - np.asarray(u) ** 2)


def test_tip_solver_matches_closed_form_across_the_range():
    for u in np.linspace(0.05, 0.95, 19):
        c = bk.tip_solve(u)["c"]
        assert abs(c / closed(u) - 1) < 1e-9, u


def test_tip_solver_converged_in_degree_and_lattice_length():
    for u in (0.3, 0.8):
        ref = bk.tip_solve(u, degree=24, decay=60.0)["c"]
        for deg, decay in [(12, 40.0), (16, 40.0), (16, 25.0), (20, 50.0)]:
            assert bk.tip_solve(u, degree=deg, decay=decay)["c"] == pytest.approx(ref, rel=1e-12)
    # coarse settings do show errors (the checks above can fail)
    assert abs(bk.tip_solve(c=1.2, degree=6)["theta"] / bk.tip_solve(c=1.2)["theta"] - 1) > 1e-9


@pytest.mark.parametrize("u", [0.02, 0.999])
def test_error_estimates_near_both_ends(u):
    """Differences between settings bound the error where the problem is hardest:
    c -> 1 (u -> 0, slow transients, long lattice) and c -> infinity (u -> 1)."""
    a = bk.tip_solve(u, degree=12)
    b = bk.tip_solve(u, degree=20, decay=60.0)
    est = abs(a["c"] - b["c"]) / b["c"]
    err = abs(b["c"] / closed(u) - 1)
    assert est < 1e-9 and err < 1e-9
    assert a["intervals"] > 0 and b["decay_rate"] > 0


def test_c_above_one_and_diverging():
    u = np.linspace(0.01, 0.999, 60)
    c = np.array([bk.tip_solve(x)["c"] for x in u])
    assert np.all(c > 1) and np.all(np.diff(c) > 0)
    assert bk.tip_solve(0.99999)["c"] > 200


def test_small_u_limit_eq_c1():
    u = np.linspace(0.02, 0.08, 7)
    c = np.array([bk.tip_solve(x)["c"] for x in u])
    # (c - 1)/u^2 = a0 + a1 u^2 + ...
    coef = np.polyfit(u**2, (c - 1) / u**2, 2)
    assert coef[-1] == pytest.approx(0.5, abs=1e-3)


def test_large_c_series_eq_ca_and_its_fourth_coefficient():
    c = np.linspace(2.5, 40.0, 80)
    theta = np.array([bk.tip_solve(c=x)["theta"] for x in c])
    x = 1.0 / c**2
    # theta = a1 x + a2 x^2 + ... : least squares with 8 terms
    A = np.vstack([x**k for k in range(1, 9)]).T
    a = np.linalg.lstsq(A, theta, rcond=None)[0]
    assert a[0] == pytest.approx(1 / 2, abs=1e-4)
    assert a[1] == pytest.approx(3 / 8, abs=1e-4)
    assert a[2] == pytest.approx(5 / 16, abs=1e-4)
    # the fourth coefficient is the binomial 35/128 = 0.27344, not the quoted 0.2719
    assert a[3] == pytest.approx(35 / 128, abs=1e-3)
    assert abs(a[3] - th.PAPER_FOURTH_COEFFICIENT) > 1e-3


def test_interpolation_and_formal_continuum():
    u = np.linspace(0.05, 0.95, 19)
    c = bk.front_speed(u)
    assert np.max(np.abs(th.c_interpolation(u) / c - 1)) < 0.03
    assert np.max(np.abs(th.c_formal_continuum(u) / c - 1)) > 0.3
    assert bk.tip_solve(0.6)["c"] != pytest.approx(float(th.c_formal_continuum(0.6)), rel=0.1)


def test_front_speed_vectorised_and_methods_agree():
    u = np.array([[0.1, 0.2], [0.6, 0.9]])
    c = bk.front_speed(u)
    assert c.shape == (2, 2)
    np.testing.assert_allclose(bk.front_speed(u, method="tip"), c, rtol=1e-11)
    assert isinstance(bk.front_speed(0.6), float) and bk.front_speed(0.6) == 1.25
    with pytest.raises(bk.ParameterError, match="u_plus"):
        bk.front_speed([0.5, np.nan])
    with pytest.raises(bk.ParameterError, match="method"):
        bk.front_speed(0.5, method="guess")
    with pytest.raises(bk.ParameterError):
        bk.tip_solve(0.5, c=1.2)


def march_tip_lattice(u_plus, nblocks):
    """Independent check: simulate the rescaled tip lattice (continuum limit) from a kick.
    Sliding blocks: w'' = w_{i+1} + w_{i-1} - 2 w_i + 1 (free left end); stuck blocks w = 0;
    block k slips when w_{k-1} reaches theta. Returns the slip times."""
    theta = (1 - u_plus) / u_plus
    w = np.zeros(nblocks)
    wd = np.zeros(nblocks)
    wd[0] = 10.0  # kick
    t, times = 0.0, [0.0]
    for k in range(1, nblocks):

        def rhs(_t, y, k=k):
            ww = y[:k]
            left = np.concatenate([[ww[0]], ww[:-1]])
            right = np.concatenate([ww[1:], [0.0]])
            return np.concatenate([y[k:], left + right - 2 * ww + 1])

        def slip(_t, y, k=k):
            return y[k - 1] - theta

        slip.terminal = True
        slip.direction = 1
        sol = solve_ivp(
            rhs,
            (t, t + 100),
            np.concatenate([w[:k], wd[:k]]),
            method="DOP853",
            rtol=1e-12,
            atol=1e-12,
            events=slip,
        )
        t = sol.t_events[0][0]
        y = sol.y_events[0][0]
        w[:k], wd[:k] = y[:k], y[k:]
        times.append(t)
    return np.array(times)


@pytest.mark.parametrize("u", [0.6, 0.85])
def test_time_marching_converges_to_the_tip_solution(u):
    times = march_tip_lattice(u, 70)
    c_measured = 1.0 / np.diff(times)[-1]
    assert c_measured == pytest.approx(bk.tip_solve(u)["c"], rel=1e-8)


def test_finite_dx_approaches_the_continuum_with_its_order():
    """c(u_+; dx, gamma) -> c(u_+) as dx -> 0: order 2 without damping, order 1 with it
    (the damping term enters the tip problem at order dx)."""
    for gamma, order in [(0.0, 2.0), (0.3, 1.0)]:
        dxs = [0.1, 0.05, 0.025]
        err = [bk.tip_solve(0.7, dx=h, gamma=gamma)["c"] - closed(0.7) for h in dxs]
        p = np.log2(err[1] / err[2])
        assert p == pytest.approx(order, abs=0.05)


def test_lattice_speed_closed_form_at_gamma_zero():
    """Wiener-Hopf closed form for the discrete chain without damping vs the numerical
    finite-dx tip solver (two independent routes)."""
    for u, dx in [(0.45, 0.1), (0.7, 0.3), (0.95, 0.05)]:
        c = bk.front_speed(u, dx=dx)
        assert c == pytest.approx(bk.tip_solve(u, dx=dx)["c"], rel=1e-11)
        assert c == pytest.approx(bk.front_speed(u, dx=dx, method="tip"), rel=1e-11)
        assert c < bk.front_speed(u)  # the lattice slows the front
    # with damping the numerical tip solver is used
    assert bk.front_speed(0.6, dx=0.05, gamma=0.3) == pytest.approx(
        bk.tip_solve(0.6, dx=0.05, gamma=0.3)["c"], rel=1e-14
    )
    with pytest.raises(bk.ParameterError, match="u_plus"):
        bk.front_speed(0.01, dx=1.0)
    with pytest.raises(bk.ParameterError, match="dx"):
        bk.front_speed(0.5, dx=-0.1)


@pytest.mark.parametrize("u", [1 - 1e-12, 1 - 1e-8, 5e-4, 1e-3])
def test_tip_solve_outside_its_range_is_an_error_naming_u_plus_and_the_range(u):
    """Beyond c = 1000 the collocation round-off grows like c^2 (1 - 1e-12 gave c 16 % too
    high and u_plus = 4.5e-68); below c - 1 = 5e-5 it grows like 1/(c - 1)^2 and the lattice
    behind the tip without bound (5e-4 failed with a negative theta, 1e-3 took 26 s)."""
    with pytest.raises(bk.ParameterError, match="u_plus") as e:
        bk.tip_solve(u)
    msg = str(e.value)
    assert "1000" in msg and "front_speed" in msg


@pytest.mark.parametrize("u", [0.01, 0.0137, 0.99999, 0.99999949])
def test_tip_solve_at_the_edges_of_its_range(u):
    """0.0137 and 0.99999 are not range ends: untuned points near them."""
    s = bk.tip_solve(u)
    assert s["c"] == pytest.approx(closed(u), rel=1e-10)
    assert s["u_plus"] == pytest.approx(u, rel=1e-5)  # the solved u_+, = 1/(1 + theta)
    with pytest.raises(bk.ParameterError, match="c"):
        bk.tip_solve(c=2000.0)


def _lattice_formula(u, dx):
    return dx / (2 * u * np.arcsin(dx * np.sqrt(1 - u * u) / (2 * u)))


def _chain_c(u, dx, blocks, steady=1e-9, gamma=0.0, step=0.0125):
    import math

    from bkwaves import _core

    r = _core.front_measure(
        u, dx, blocks, step=step, friction={"gamma": gamma, "beta": math.inf}, heal=False
    )
    assert r["unsteadiness"] < steady
    return r["c"]


@pytest.mark.parametrize("u, dx", [(0.1, 0.1), (0.2, 0.1), (0.25, 0.1), (0.3, 0.2)])
def test_lattice_closed_form_refuses_narrow_pulses(u, dx):
    """The closed form lets every block slide for ever; in the chain blocks re-stick ~w/dx
    spacings behind the tip and that feeds back on c: (0.1, 0.1) runs at 0.97527, not 0.96023,
    (0.2, 0.1) is 2.6e-4 off. Outside its domain front_speed names u_plus and dx and points to
    the chain instead of returning a wrong number."""
    chain = _chain_c(u, dx, 2400, steady=1e-7)
    assert abs(_lattice_formula(u, dx) / chain - 1) > 1e-6  # the formula is wrong here
    for method in ("exact", "tip"):
        with pytest.raises(bk.ParameterError, match="u_plus") as e:
            bk.front_speed(u, dx=dx, method=method)
        assert "dx" in str(e.value) and "bk.chain.front" in str(e.value)


@pytest.mark.parametrize("u, dx", [(0.45, 0.1), (0.35, 0.025)])
def test_lattice_closed_form_is_the_chains_speed_inside_its_domain(u, dx):
    """Untuned points inside the domain (X = 26 and 59): the chain agrees to its precision."""
    assert bk.front_speed(u, dx=dx) == pytest.approx(_chain_c(u, dx, 2400), rel=2e-10)


def _names_the_chain(e):
    msg = str(e.value)
    for word in ("u_plus", "dx", "gamma", "bk.chain.front(u_plus, gamma, dx)"):
        assert word in msg, msg


@pytest.mark.parametrize(
    "u, gamma, dx, off",
    [
        (0.3, 0.1, 0.2, 2.5e-4),
        (0.25, 0.1, 0.1, 1.4e-5),
        (0.4, 0.2, 0.3, 7.8e-5),
        (0.45, 0.15, 0.25, 1.8e-6),
    ],
)
def test_damped_tip_solver_refuses_narrow_pulses(u, gamma, dx, off):
    """With damping too the finite-dx tip problem lets every block slide for ever, while the
    chain re-sticks them w/dx spacings behind the tip: its speed is `off` (relative) below the
    chain's, ~a e^-X with X = lambda w/(c dx) = 5.5, 7.7, 7.5, 11.0 (the last point chosen
    after the rule, untuned). front_speed and tip_solve refuse with one error naming u_plus,
    dx, gamma and the chain; the linear problem stays available (chain_domain=False)."""
    chain = _chain_c(u, dx, 2400, gamma=gamma, step=0.00625)
    linear = bk.tip_solve(u, dx=dx, gamma=gamma, chain_domain=False)["c"]
    assert linear / chain - 1 == pytest.approx(-off, rel=0.1)  # the tip value is wrong here
    with pytest.raises(bk.ParameterError) as e:
        bk.front_speed(u, dx=dx, gamma=gamma)
    _names_the_chain(e)
    with pytest.raises(bk.ParameterError) as e:
        bk.tip_solve(u, dx=dx, gamma=gamma)
    _names_the_chain(e)
    with pytest.raises(bk.ParameterError) as e:  # given c: the solved u_+ is checked
        bk.tip_solve(c=linear, dx=dx, gamma=gamma)
    _names_the_chain(e)


@pytest.mark.parametrize(
    "u, gamma, dx",
    [
        (0.55, 0.2, 0.15),  # pulse, X = 31 (untuned)
        (0.65, 0.25, 0.3),  # pulse, X = 25 (untuned)
        (0.45, 0.45, 0.2),  # creep: u_+ = gamma, the critically damped wave
        (0.6, 0.7, 0.2),  # creep
    ],
)
def test_damped_tip_solver_is_the_chains_speed_inside_its_domain(u, gamma, dx):
    """Inside the domain, and in creep (App. B's wave never re-sticks), the tip solver's
    speed is the chain's to the chain's precision (~3e-11 at step 0.00625)."""
    chain = _chain_c(u, dx, 2400, steady=2e-10, gamma=gamma, step=0.00625)
    assert bk.front_speed(u, dx=dx, gamma=gamma) == pytest.approx(chain, rel=1e-10)
    assert bk.tip_solve(u, dx=dx, gamma=gamma)["c"] == pytest.approx(chain, rel=1e-10)


def test_resticking_exponent_is_one_rule_for_every_gamma():
    """The gamma = 0 closed form and the damped tip solver share the domain check: the
    same refusal at gamma = 0 whichever route, and the damped boundary moves with the pulse
    width w(u_+, gamma) (wider pulses, X larger: (0.5, 0.3, 0.2) is inside while
    (0.5, 0.1, 0.2), X = 17, is outside)."""
    for method in ("exact", "tip"):
        with pytest.raises(bk.ParameterError) as e:
            bk.front_speed(0.3, dx=0.1, method=method)
        _names_the_chain(e)
    assert bk.front_speed(0.5, dx=0.2, gamma=0.3) > 1
    with pytest.raises(bk.ParameterError):
        bk.front_speed(0.5, dx=0.2, gamma=0.1)


def test_a_lattice_spacing_the_tip_solver_cannot_reach_is_named():
    # dx >> 1 with damping: the finite-dx tip problem's collocation system is singular;
    # the error names dx (found by the fuzz test: it was a ConvergenceError traceback)
    with pytest.raises(bk.ParameterError, match=r"invalid dx = .*bk\.chain\.front"):
        bk.front_speed(0.5, dx=24058.0, gamma=1.0)
