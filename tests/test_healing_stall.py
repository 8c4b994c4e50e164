"""Where the first healing front stalls (docs/lattice.md, "Derived and measured: where the
first healing stalls"; docs/scripts/healing_stall.py).

The claim: the healing front of a rupture stops where it meets the sound cone of the
collision of two rupture fronts, t = t_m + |x - x_m|; nothing that happens at the collision
reaches a block earlier (the sliding equation's characteristics have speed 1), and inside
the cone the other pulse's slip keeps the blocks sliding past their first backswing. Its
distance from the collision is d = T c/(1 + c) (T the slip duration there, c the fronts'
speed), about w/(1 + c) of the steady pulse at the stress met there. Not set by the
hypocentre: the same bump alone on the ring stalls 10 from it, next to where its own two
fronts meet, instead of 4.2.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "docs" / "scripts"))
import healing_stall as hs  # noqa: E402

DX = 0.0125


@pytest.fixture(scope="module")
def runs():
    return {name: hs.run_case(name, DX, hs.CASES[name])
            for name in ("base", "width 2", "width 4.5", "gamma 0.3", "gamma 0.6",
                         "single bump")}  # fmt: skip


def stalls(run):
    """(collision, side) pairs of the run, each with its stall measurement."""
    return [(c, s) for c in run["collisions"] for s in c["sides"].values()]


def test_the_stall_is_where_the_healing_front_meets_the_collision_s_sound_cone(runs):
    for name in ("base", "width 2", "gamma 0.3", "gamma 0.6", "single bump"):
        for _col, s in stalls(runs[name]):
            # the same place whatever the threshold on the first-stick jump
            ds = list(s["d_by_threshold"].values())
            assert None not in ds and max(ds) - min(ds) < 1e-9, name
            assert s["jump"] > 0.9, name  # a jump, not a steep slope (0.94-1.29 here)
            # measured 0.005-0.035 beyond the cone at this dx (0.004-0.025 at dx/2): the
            # lattice's precursor ahead of the sound cone, shrinking with dx
            assert 0.0 < s["d"] - s["d_cone"] < 0.045, name
            # with the slip duration and the fronts' speed there: d = T c/(1 + c)
            assert s["d"] == pytest.approx(s["d_duration"], rel=0.045), name


def test_the_stall_moves_with_the_collision_not_with_the_hypocentre(runs):
    base = [s for _c, s in stalls(runs["base"])]
    single = [s for _c, s in stalls(runs["single bump"])]
    # two bumps: the fronts meet 6.37 from the higher bump's hypocentre and 5.63 from the
    # lower one's; the stalls are 4.22 and 3.39 from them, but 2.15 and 2.24 from the
    # collision
    from_hypo = sorted(s["hypocentre_distance"] - s["d"] for s in base)
    assert from_hypo[0] == pytest.approx(3.39, abs=0.05)
    assert from_hypo[-1] == pytest.approx(4.22, abs=0.05)
    assert all(2.1 < s["d"] < 2.3 for s in base)
    # one bump: its fronts meet 12 from it, and the stall is 10.1 from it
    for s in single:
        assert s["hypocentre_distance"] == pytest.approx(12.0, abs=0.05)
        assert 10.0 < s["hypocentre_distance"] - s["d"] < 10.3


def test_the_stall_follows_the_bump_width_and_gamma_as_the_cone_predicts(runs):
    # narrower bumps: the fronts meet at a lower stress (0.73 against 0.80), slower fronts
    # and a shorter slip: the stall comes 0.19 nearer the collision; the cone's prediction
    # (from each run's own healing line) moves by the same amount
    for k in range(4):
        s3, s2 = stalls(runs["base"])[k][1], stalls(runs["width 2"])[k][1]
        assert s2["d"] - s3["d"] == pytest.approx(s2["d_cone"] - s3["d_cone"], abs=0.02)
        assert s3["d"] - s2["d"] > 0.15
    # gamma: the steady pulse's w(gamma)/(1 + c) (the same u_+, c) gives the ratio
    col3, s3 = stalls(runs["gamma 0.3"])[0]
    col6, s6 = stalls(runs["gamma 0.6"])[0]
    assert s6["d"] / s3["d"] == pytest.approx(col6["d_pulse"] / col3["d_pulse"], rel=0.04)
    assert s6["d"] / s3["d"] > 1.35  # (measured 1.44; pulse 1.40)


def test_broad_bumps_meet_too_fast_for_a_stall(runs):
    """Bumps of width 4.5 make the fronts meet at u_+ = 0.95 (c = 3.1): the healing is
    delayed where it crosses the cone, by a steep slope of first-stick times, not a jump."""
    for col, s in stalls(runs["width 4.5"]):
        assert col["u_plus"] > 0.93
        assert s["d_by_threshold"]["0.25"] is None
        assert s["max_jump"] < 0.2  # (measured 0.11-0.13; 0.98-1.08 in the base run)


@pytest.mark.parametrize("name", ["base", "width 4.5"])
def test_the_collision_kicks_the_slip_speed_by_the_derived_jump(name):
    """Across the cone s_t = -u_tt jumps by (1/2)|J| (1/c_L + 1/c_R)(1 - 1/c_L)/(1 - 1/c_R)
    exp(-gamma t), J = -c^2 u_+/(c^2 - 1) the fronts' own jump of u_tt; the healing stalls
    when that jump, where the healing line meets the cone, beats a, the rate at which the
    speed over the ground was falling to zero there (base: 0.28 against 0.13), and is only
    delayed when it does not (width 4.5: 0.10 against 0.17)."""
    r = hs.run_case(name, 0.00625, hs.CASES[name], kick=True)
    k = r["kick"]
    # measured 0.449 against 0.461, 0.210 against 0.215 (0.482 at dx = 0.003125 in base)
    assert k["jump_measured"] == pytest.approx(k["jump_predicted"], rel=0.06)
    stalled = r["collisions"][0]["sides"]["-1"].get("d") is not None
    assert stalled == (name == "base")
    assert (k["jump_at_star"] > 1.5 * k["a"]) if stalled else (k["jump_at_star"] < 0.8 * k["a"])
    # the steady pulse's closed form exp(pi gamma/S)/c: 2.14 and 0.56 (measured 2.10, 0.58)
    closed = r["collisions"][0]["kick_over_rate_pulse"]
    assert closed == pytest.approx(k["jump_at_star"] / k["a"], rel=0.1)


@pytest.mark.parametrize("u_plus", [0.6, 0.8, 0.95])
@pytest.mark.parametrize("gamma", [0.3, 0.45])
def test_the_closed_form_kick_over_rate_is_the_pulse_s_own_ratio(u_plus, gamma):
    """K/a = exp(pi gamma/S)/c is u_+ exp(-gamma w/(1 + c))/(c |u_-|) with the pulse's c, w,
    u_- from bk.traveling_wave: the stress cancels."""
    import numpy as np

    import bkwaves as bk

    w = bk.traveling_wave(u_plus, gamma)
    direct = u_plus * np.exp(-gamma * w.w / (1 + w.c)) / (w.c * abs(w.u_minus))
    assert hs.kick_over_rate(w.c, gamma) == pytest.approx(direct, rel=1e-9)


def test_in_the_plane_the_stall_lines_run_beside_the_fronts_meeting_lines():
    """The loaded square of docs/scripts/lattice_later_ruptures.py (seed 0): the stall
    edges lie 2.3 from the meeting lines of the first cycle's fronts (blocks that slipped
    after both neighbours along a row or a column), whatever the threshold, at T c/(1 + c)
    from each edge's own slip duration and front speed, and the stall lines are about two
    per meeting line (one on each side)."""
    import lattice_later_ruptures as llr

    for dx in (0.2, 0.1):
        r = llr.stall_lines(dx, 2.0, 0)
        meet = r["meeting_length_per_area"]
        assert 0.11 < meet < 0.13  # (0.119, 0.121)
        b = r["by_threshold"]
        med = {t: e["distance_10_25_50_75_90"][2] for t, e in b.items()}
        assert all(2.1 < m < 2.6 for m in med.values()), med  # (2.29-2.38)
        assert abs(med["0.5"] - med["1.0"]) < 0.1
        assert 0.97 < b["0.5"]["ratio_50"] < 1.1  # (1.024, 1.034)
        assert 1.6 < b["0.5"]["length_per_area"] / meet < 2.6  # (2.33, 2.09)
