"""Fronts with velocity-weakening friction against v_f/dx: the crossover of the paper's
eq. (crit) (bkwaves.velocity_weakening, docs/velocity_weakening.md). The cases here were
not used to tune anything: u_+ = 0.5 and 0.7 are not in the docs' tables."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

import bkwaves as bk
from bkwaves import velocity_weakening as vw


def cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "bkwaves.cli", *args], capture_output=True, text=True, timeout=120
    )


#: Only c is asked for (its doubling change within 1e-4: the gaps below are >= 1e-2), not
#: zone or u_-.
C_ONLY = {"c": 1e-4, "zone": math.inf, "u_minus": math.inf}


def gap(u, gamma, dx, ratio, **kw):
    """c_Coulomb/c - 1 at v_f = ratio dx (Coulomb: the finite-dx tip problem); c from a
    chain 20 long, within 1e-4 of the chain 10 long."""
    f = vw.front(u, gamma, dx, ratio * dx, length=20.0, weakening=False, tolerance=C_ONLY, **kw)
    assert f.status == "steady", f
    return float(bk.front_speed(u, dx=dx, gamma=gamma)) / f.c - 1.0


def test_small_v_f_over_dx_tends_to_the_coulomb_finite_dx_speed():
    # eq. (crit): v_f << dx is the Coulomb chain at the same dx. The gap is positive
    # (friction above Coulomb's at every speed) and within the derived 2 c_C r ln(1/r)
    u, gamma, dx = 0.5, 0.3, 0.1
    c_c = float(bk.front_speed(u, dx=dx, gamma=gamma))
    gaps = {r: gap(u, gamma, dx, r) for r in (0.03, 0.01, 0.003)}
    for r, g in gaps.items():
        assert 0.0 < g < vw.coulomb_gap_bound(c_c, r), (r, g)
    # the gap vanishes like r ln(1/r) (ratio 0.38 from r = 0.01 to 0.003), far faster
    # than sqrt(r) (0.55); the ratio approaches r ln(1/r)'s from above as r -> 0
    steps = [(0.03, 0.01), (0.01, 0.003)]
    ratios = [gaps[b] / gaps[a] for a, b in steps]
    expect = [b * math.log(1 / b) / (a * math.log(1 / a)) for a, b in steps]
    assert ratios[1] < ratios[0] and expect[1] < ratios[1] < math.sqrt(0.3)
    assert gaps[0.003] < 0.02


def test_the_crossover_variable_is_v_f_over_dx():
    # the tip scaling: in units of the tip the law depends on v_f/dx (and u_+) only, so
    # c/c_Coulomb at fixed v_f/dx is the same at every dx up to O(gamma dx); at fixed
    # v_f it is not
    u, gamma = 0.7, 0.3

    def ratio_to_coulomb(dx, v_f):
        f = vw.front(u, gamma, dx, v_f, weakening=False, tolerance=C_ONLY)
        assert f.status == "steady", f
        return f.c / float(bk.front_speed(u, dx=dx, gamma=gamma))

    same_r = [ratio_to_coulomb(dx, 0.1 * dx) for dx in (0.1, 0.05)]
    same_v_f = [ratio_to_coulomb(dx, 0.005) for dx in (0.1, 0.025)]
    assert abs(same_r[0] - same_r[1]) < 0.1 * 0.3 * 0.1  # O(gamma dx), coefficient 0.1
    assert abs(same_v_f[0] - same_v_f[1]) > 0.03


def test_v_f_above_dx_gives_sound_speed_fronts_a_few_lattice_spacings_wide():
    # the paper (Sec. VI): for v_f >> dx the front runs near the sound speed and its
    # slipping zone is a few lattice spacings, whatever u_+ (gamma = 0, as in its argument)
    dx = 0.05
    fronts = {r: vw.front(0.5, 0.0, dx, r * dx, length=20.0) for r in (0.01, 0.3, 3.0)}
    cs = [fronts[r].c for r in (0.01, 0.3, 3.0)]
    assert cs[0] > cs[1] > cs[2]  # monotone in v_f
    assert abs(cs[2] - 1.0) < 0.02 < float(bk.front_speed(0.5, dx=dx)) - 1.0
    zones = [fronts[r].zone for r in (0.01, 0.3, 3.0)]
    assert zones[0] > zones[1] > zones[2] and zones[2] < 15
    assert zones[0] > 0.8 * bk.traveling_wave(0.5, 0.0).w / dx  # the Coulomb pulse
    # the tip stays sharp: friction is halfway down within ~1 slip interval
    assert all(f.weakening < 2.0 for f in fronts.values())


@pytest.mark.parametrize("dx", [0.1, 0.05])
def test_no_front_above_the_v_f_where_friction_cannot_drop_below_u_plus(dx):
    # min over s of R(s) = 1/(1 + s/v_f) + 2 gamma s is below u_+ only for
    # v_f < v_f* = (1 - sqrt(1 - u_+))^2/(2 gamma), whatever dx
    u, gamma = 0.5, 0.3
    star = vw.v_f_existence(u, gamma)
    assert vw.min_friction(gamma, star) == pytest.approx(u, rel=1e-12)
    assert vw.front(u, gamma, dx, 1.25 * star, weakening=False).status == "dies"
    assert vw.front(u, gamma, dx, 0.5 * star, weakening=False).status == "steady"


def test_min_friction():
    assert vw.min_friction(0.0, 5.0) == 0.0
    assert vw.min_friction(0.5, 2.0) == 1.0  # 2 gamma v_f >= 1: R rises from R(0) = 1
    g, v_f = 0.3, 0.1
    s = [i * 1e-4 for i in range(20000)]
    assert vw.min_friction(g, v_f) == pytest.approx(
        min(1 / (1 + x / v_f) + 2 * g * x for x in s), abs=1e-7
    )
    assert vw.v_f_existence(0.5, 0.0) == math.inf


def test_cli_front_reports_whether_a_steady_front_exists():
    base = ["front", "--u-plus", "0.6", "--gamma", "0.3", "--dx", "0.1"]
    vw_law = ["--law", "velocity_weakening", "--v-f"]
    r = cli(*base, *vw_law, "1.0", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["front"] == "dies" and d["regime"] == "none" and d["c"] is None
    assert "died" in d["reason"] and d["window"] is None
    out = cli(*base, *vw_law, "1.0").stdout
    assert "front   = dies   (no steady front)" in out and "why     : no steady front" in out
    # no measured speed is printed for a front that died; the continuum value is labelled
    assert "c       = none (no front)" in out and "= 1.25)" in out and "nan" not in out
    d = json.loads(cli(*base, *vw_law, "0.01", "--json").stdout)
    assert d["front"] == "steady" and d["regime"] == "pulse"
    assert "front   = steady" in cli(*base).stdout  # Coulomb
    m = bk.chain.front(0.6, 0.3, 0.1, friction=bk.friction.law("velocity_weakening", v_f=1.0))
    assert m.front == "dies" and math.isnan(m.c) and m.regime == "none"


def test_fixed_v_f_as_dx_goes_to_zero_sound_speed_whatever_u_plus():
    # the paper's continuum limit for v_f >> dx: fronts at the sound speed, whatever the
    # stress ahead (Coulomb: c = 1.40 and 2.29 at u_+ = 0.7, 0.9). What it does not say:
    # the slipping zone is not a few lattice spacings for ever; in lattice spacings it
    # grows (~ dx^-1/2 measured), its width in x shrinks
    gamma, v_f = 0.3, 0.1  # v_f far below v_f* (0.2, 0.8): away from where fronts die
    for u in (0.7, 0.9):
        f = [vw.front(u, gamma, dx, v_f, weakening=False) for dx in (0.05, 0.025)]
        assert all(x.status == "steady" for x in f), f
        excess = [abs(x.c - 1.0) for x in f]
        coulomb = float(bk.front_speed(u, dx=0.025, gamma=gamma)) - 1.0
        # closer to the sound speed on the finer lattice; there within 5 % of the
        # Coulomb chain's excess speed c - 1
        assert excess[1] < excess[0] + 1e-3 and excess[1] < 0.05 * coulomb, (excess, coulomb)
        growth = f[1].zone / f[0].zone  # in lattice spacings, dx halved
        assert 1.2 < growth < 1.8, growth


def test_default_front_is_converged_and_doubling_moves_it_within_the_tolerance():
    # the default measurement doubles the chain until c, zone and u_- stop moving; one
    # more doubling must stay within the stated tolerance (the approach is exponential
    # in x, so the change it reports bounds the error)
    f = vw.front(0.6, 0.3, 0.1, 0.1, weakening=False)
    assert f.status == "steady" and f.converged, f
    assert all(f.convergence[k] <= vw.TOLERANCE[k] for k in vw.TOLERANCE)
    g = vw.front(0.6, 0.3, 0.1, 0.1, length=2 * f.lengths[-1], weakening=False)
    assert abs(g.c / f.c - 1) <= vw.TOLERANCE["c"]
    assert abs(g.zone / f.zone - 1) <= vw.TOLERANCE["zone"]
    assert abs(g.u_minus - f.u_minus) <= vw.TOLERANCE["u_minus"]
    # a chain 20 long (the old default) is not converged, and says so
    short = vw.front(0.6, 0.3, 0.1, 0.1, length=20.0, weakening=False)
    assert short.status == "undecided" and "not converged" in short.reason
    assert short.convergence["zone"] > vw.TOLERANCE["zone"]


def test_converged_fronts_of_the_outside_audit():
    # an outside audit (its own chain codes, agreeing with this engine to 3e-8 on chains
    # 110 long) found these converged values; the chain 20 long gave zone 20.97 dx,
    # u_- = 0.290 and c = 0.99815297
    f = vw.front(0.5, 0.3, 0.025, 0.025, weakening=False)
    assert f.status == "steady", f
    assert f.zone == pytest.approx(28.4, abs=0.05) and f.u_minus == pytest.approx(0.224, abs=1e-3)
    f = vw.front(0.8, 0.3, 0.025, 0.25, weakening=False)
    assert f.status == "steady" and f.c == pytest.approx(0.99837024, abs=2e-8), f


def test_front_tolerance_and_length_are_checked():
    with pytest.raises(bk.ParameterError, match="tolerance"):
        vw.front(0.6, 0.3, 0.1, 0.1, tolerance={"w": 1e-3})
    with pytest.raises(bk.ParameterError, match="tolerance"):
        vw.front(0.6, 0.3, 0.1, 0.1, tolerance={"c": -1.0})
    with pytest.raises(bk.ParameterError, match="length"):
        vw.front(0.6, 0.3, 0.1, 0.1, length=1.0)
    # only c asked for: the zone may be unmeasured on the short chains (the window blocks
    # still slide at the end), and the report says so
    f = vw.front(
        0.8, 0.3, 0.1, 0.003, weakening=False, tolerance={"zone": math.inf, "u_minus": math.inf}
    )
    assert f.status == "steady" and f.convergence["c"] <= vw.TOLERANCE["c"]
    assert f.convergence["zone"] is None and "unmeasured" in f.reason


def test_cli_front_velocity_weakening_subsonic_is_converged_and_reports_the_pulse():
    # the default chain used to give c = 0.9692172 (regime undecided for every subsonic
    # front: the settling length of a Coulomb pulse does not apply); converged: 0.9689767
    r = cli(
        "front", "--u-plus", "0.6", "--gamma", "0.3", "--dx", "0.05",
        "--law", "velocity_weakening", "--v-f", "0.15", "--json",
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["c"] == pytest.approx(0.9689767, abs=3e-7) and d["c"] < 1.0
    assert d["regime"] == "pulse" and d["front"] == "steady"
    assert d["w"] > 0 and d["u_minus"] == pytest.approx(0.49378, abs=1e-4)
    assert all(d["convergence"][k] <= vw.TOLERANCE[k] for k in vw.TOLERANCE)


def test_death_threshold_needs_converged_chains():
    # near the threshold a front fades slowly and dies far out: at u_+ = 0.6, gamma = 0.3,
    # dx = 0.1 the converged threshold is 0.72 v_f* (docs/velocity_weakening.md; an outside
    # audit found the same); a chain 40 long called the front at 0.74 v_f* steady
    u, gamma, dx = 0.6, 0.3, 0.1
    star = vw.v_f_existence(u, gamma)
    c6 = {"zone": math.inf, "u_minus": math.inf}  # c to TOLERANCE["c"] = 1e-6
    fading = vw.front(u, gamma, dx, 0.74 * star, weakening=False, tolerance=c6)
    assert fading.status == "dies" and fading.reached > 40.0, fading
    assert vw.front(u, gamma, dx, 0.70 * star, weakening=False, tolerance=c6).status == "steady"


def _c_of_front(u, gamma, dx, v_f, n, step, step_tolerance=None):
    """c over blocks n/2 .. 3n/4 of one front on n blocks (bkwaves.chain.run_front)."""
    from bkwaves.chain import run_front

    law = bk.friction.law("velocity_weakening", v_f=v_f)
    p = bk.Params(gamma=gamma, v=0.0, dx=dx, friction_law=law)
    _, first, _ = run_front(u, n, p, step=step, step_tolerance=step_tolerance)
    a, b = n // 2, (3 * n) // 4
    return dx * (b - a) / (first[b] - first[a])


def test_onset_sub_steps_converge_at_fourth_order_and_match_the_global_step():
    """The onset of a block at v_f/dx = 1e-4 is 1e4 times faster than the lattice: the
    chain keeps step dx and gives the block in its onset its own sub-steps
    (chain/onset.rs). c converges at fourth order in the step (the changes fall by 16 per
    halving at order 4: here >= 8), the default step within 2e-8 of step 0.0125 (the
    Coulomb chain's own error at this step and dx: 3.4e-9); and at v_f/dx = 1e-2, where it
    is affordable, the same c as the chain that steps every block at step v_f/theta (the
    engine before sub-steps, here through the step-size control with a tolerance no step
    can meet)."""
    u, gamma, dx = 0.55, 0.3, 0.05
    cs = [_c_of_front(u, gamma, dx, 1e-4 * dx, 200, s) for s in (0.1, 0.05, 0.025, 0.0125)]
    d = [abs(cs[k] - cs[k + 1]) for k in range(3)]
    assert d[0] / d[1] > 8 and d[1] / d[2] > 8, (cs, d)
    assert abs(cs[1] / cs[3] - 1) < 2e-8, cs
    sub = _c_of_front(u, gamma, dx, 1e-2 * dx, 100, 0.05)
    glob = _c_of_front(u, gamma, dx, 1e-2 * dx, 100, 0.05, step_tolerance=1e-300)
    assert abs(sub / glob - 1) < 1e-8, (sub, glob)


def test_the_front_tends_to_the_coulomb_chain_as_v_f_over_dx_goes_to_zero():
    """eq. (crit): as r = v_f/dx -> 0 the front tends to the Coulomb chain's at the same
    dx, slowly: each slip is delayed by ~ v_f ln(1/r) (docs/velocity_weakening.md), so
    g = c_C/c - 1 ~ r ln(1/r) (0 < g < 2 c_C r ln(1/r)), and so do the changes of the
    pulse behind (width, u_-): down to r = 1e-5, which costs about what r = 1e-2 does
    now that the onset has its own sub-steps."""
    u, gamma, dx = 0.7, 0.3, 0.1
    cf = bk.chain.front(u, gamma, dx)
    assert cf.regime == "pulse"
    rs = (1e-3, 1e-4, 1e-5)
    fronts = {r: vw.front(u, gamma, dx, r * dx) for r in rs}
    for r, f in fronts.items():
        assert f.status == "steady", (r, f)
        g = cf.c / f.c - 1.0
        assert 0.0 < g < vw.coulomb_gap_bound(cf.c, r), (r, g)
        # g/(c_C r ln(1/r)) between 0.5 and 2 at every r: the rate, not just the limit
        assert 0.5 < g / (cf.c * r * math.log(1 / r)) < 2.0, (r, g)
    for a, b in ((1e-3, 1e-4), (1e-4, 1e-5)):
        shrink = b * math.log(1 / b) / (a * math.log(1 / a))
        for key, coulomb in (("zone", cf.w / dx), ("u_minus", cf.u_minus)):
            da = abs(getattr(fronts[a], key) - coulomb)
            db = abs(getattr(fronts[b], key) - coulomb)
            assert db < 2.5 * shrink * da, (key, a, b, da, db)


def test_onset_work_does_not_grow_as_v_f_falls_and_the_default_step_is_converged():
    """The onset's sub-steps are sized by the time shift RK4 makes in the block's motion
    (chain/onset.rs): their number per onset falls as v_f does (the whole onset shifts a
    block by a time of order v_f), so the front's work (block-steps, a count: no timing)
    does not grow from v_f/dx = 2e-3 to 2e-5 and stays within 5 Coulomb fronts' (with a
    fixed sub-step h nu = step it grew like ln(1/r): 2.6e6 to 3.6e6, 8.2 Coulomb fronts).
    At v_f/dx = 2e-5 c at the default step is within 3e-9 of step 0.0125 (measured 2.0e-9,
    below the Coulomb chain's own 4.0e-9 on this front; the fixed sub-step left 3.4e-9)."""
    from bkwaves import _core

    def run(law, step=0.05, **kw):
        return _core.front_measure(
            0.5, 0.05, 400, step=step, law=law, friction={"gamma": 0.3, **kw}
        )

    coulomb = run("coulomb")["block_steps"]
    work = {v: run("velocity_weakening", v_f=v)["block_steps"] for v in (1e-4, 1e-6)}
    assert work[1e-6] <= work[1e-4], work
    assert work[1e-6] < 5 * coulomb, (work, coulomb)
    c = [run("velocity_weakening", step=s, v_f=1e-6)["c"] for s in (0.05, 0.0125)]
    assert abs(c[0] / c[1] - 1) < 3e-9, c


def test_energy_books_close_with_the_onset_sub_steps():
    """Loader work = elastic and kinetic energy change + friction and viscous work, with
    every onset integrated by its own sub-steps (v_f/dx = 5e-5 and 5e-3, both below 1/50)
    and the loose first pass of a coupled patch: the books close at the integration's
    level (residual/dissipated 1.6e-9 and 3.4e-9 at step 0.05, the Coulomb chain's own
    1.2e-8) and tighten as the step is halved (by 4-5x: the patch's power is integrated by
    the same RK4 weights as its motion)."""
    u0 = bk.chain.smooth_random_stress(60, 0.2, mean=0.6, amplitude=0.12, correlation=1.5, seed=3)
    for v_f in (1e-3, 1e-5):
        law = bk.friction.law("velocity_weakening", v_f=v_f)
        p = bk.Params(gamma=0.3, v=1e-2, dx=0.2, friction_law=law)
        rel = []
        for step in (0.05, 0.025):
            res = bk.Chain(60, p, u0=u0, step=step, seed=3).run(t_end=150.0)
            e = res.energy
            diss = e["friction_work"] + e["viscous_work"]
            assert diss > 10 and len(res.catalog) >= 5, (v_f, diss)
            rel.append(abs(e["residual"]) / diss)
        assert rel[0] < 1e-8 and rel[1] < rel[0] / 2, (v_f, rel)
