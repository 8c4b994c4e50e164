"""FreeBoundary2D against the lattice in a loaded run (issue 26): the sequence of
ruptures (births, expansion, collisions) on the problem of
docs/scripts/free_boundary_2d_loaded.py at the coarse spacing dx = 0.2, its first cycle.

Three bumps of a smooth stress field reach the threshold one after the other under the
loading, the ruptures born there expand and annihilate where they meet. Checked: the
ruptures match one to one; their start times and places are the same (the same field on
the same nodes under the same loading: a wrong loading rate moves them); their areas,
set by where the fronts meet, agree within 0.6 % with the chain's speed law at this dx
(and not with the exact law, whose fronts are 2-4 % too fast here: the test tells them
apart); their moments within the stated 15 % (the lattice slips more: the nucleation
zones and the meeting lines, docs/free_boundary_2d.md)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "docs" / "scripts"))
import free_boundary_2d_loaded as loaded  # noqa: E402
import free_boundary_2d_loaded_dx as loaded_dx  # noqa: E402

DX, T_END = 0.2, 12.0


@pytest.fixture(scope="module")
def lattice():
    return loaded.run_lattice(DX, t_end=T_END)


def _compare(lattice, speed, v=loaded.V_LOAD):
    fb = loaded.run_fb2d(DX, lattice["phi"], speed, t_end=T_END, v=v)
    return loaded.compare(lattice, fb)


def test_the_loaded_sequence_matches_the_lattice(lattice):
    pairs, s = _compare(lattice, loaded.speed_at(DX))
    # three births, matched one to one, nothing else in FreeBoundary2D; what the lattice
    # has besides (slips left at the meeting lines) is small
    assert s["fb_ruptures"] == s["matched"] == 3
    assert sum(r["area"] for r in s["lattice_unmatched"]) < 0.01 * loaded.L**2
    for q in pairs:
        assert abs(q["dt"]) < 1e-9 and q["dplace"] < 1e-9
    # the areas: where the fronts met
    assert s["max_abs_darea_rel"] < 0.006
    total = sum(q["area_fb"] for q in pairs)
    assert total == pytest.approx(loaded.L**2, rel=1e-12)  # the whole square, once
    # the moments: the lattice slips more, by a stated amount
    assert 0.0 < min(q["dmoment_rel"] for q in pairs)
    assert s["max_abs_dmoment_rel"] < 0.15


def test_the_comparison_tells_a_wrong_speed_law_and_loading_rate(lattice):
    # the exact law (the continuum's c, faster than the lattice's at this dx): the
    # meeting lines move by more than the tolerance
    _, s = _compare(lattice, None)
    assert s["max_abs_darea_rel"] > 0.006
    # a loading rate 2 % off: the births move
    pairs, s = _compare(lattice, loaded.speed_at(DX), v=1.02 * loaded.V_LOAD)
    assert max(abs(q["dt"]) for q in pairs) > 0.05


# --- dx -> 0 at a fixed field (docs/scripts/free_boundary_2d_loaded_dx.py) -------------
CONVERGENCE_VARIANTS = ("exact", "chain", "chain_curv")


@pytest.fixture(scope="module")
def first_cycle_by_dx():
    """The first cycle (to t = 12) at dx = 0.2 and 0.1 on the same field in x units (the
    lattice with local events: its first slips within 2e-6 of the global cut's)."""
    return {
        dx: loaded_dx.one_dx(dx, 1.0, "local", variants=CONVERGENCE_VARIANTS)["variants"]
        for dx in (0.2, 0.1)
    }


def test_the_first_cycle_converges_at_first_order_in_dx(first_cycle_by_dx):
    coarse, fine = first_cycle_by_dx[0.2], first_cycle_by_dx[0.1]
    for name in CONVERGENCE_VARIANTS:
        a, b = coarse[name], fine[name]
        # the births: the same three, at the same node and time, at both dx
        for q in (a, b):
            assert q["births_matched"] == q["fb_ruptures"] == 3
            assert q["birth_max_abs_dt"] < 1e-9 and q["birth_max_dplace"] < 1e-9
        # the arrival times over the whole square: the lattice's c(u_+, dx), its
        # curvature slowdown D kappa (D ~ dx) and its anisotropy are all first order in
        # dx, so halving dx halves the difference (a factor 1.7-2.1 measured; second
        # order, a factor 4, or none would fail)
        for key in ("rms", "max_abs"):
            ratio = a["arrival"][key] / b["arrival"][key]
            assert 1.5 < ratio < 2.8, (name, key, ratio)
        # the partition of the square by first arrival: the meeting lines move with the
        # arrival times
        ratio = a["partition_mismatch"] / b["partition_mismatch"]
        assert 1.5 < ratio < 2.8, (name, ratio)
        # what does not shrink: the moments, +10-12 % at both dx (the pulse's slip is
        # not local on a field varying on its width; the free boundary problem twice as
        # large halves it, docs/free_boundary_2d.md)
        assert 0.08 < a["total_moment_rel"] < 0.13 and 0.08 < b["total_moment_rel"] < 0.13
        assert abs(a["total_moment_rel"] - b["total_moment_rel"]) < 0.01


def test_the_lattice_s_speed_and_curvature_improve_the_agreement(first_cycle_by_dx):
    # at each dx: the chain's planar speed at dx brings the arrival times closer than
    # the continuum's c, and the derived curvature coefficient closer still
    for v in first_cycle_by_dx.values():
        exact, chain, curv = (v[k]["arrival"]["rms"] for k in CONVERGENCE_VARIANTS)
        assert curv < 0.75 * chain and chain < 0.85 * exact, (exact, chain, curv)
        assert v["chain_curv"]["partition_mismatch"] < 0.6 * v["chain"]["partition_mismatch"]


def test_the_moments_excess_scales_like_the_pulse_width_over_the_field(first_cycle_by_dx):
    # the moments do not converge with dx but with the field's scale: the same problem
    # twice as large (side 24, bumps of width 3, v = 0.01, to t = 20) halves the
    # lattice's excess over FreeBoundary2D's local slip (+11 % -> +5.5 %; w/sigma)
    small = first_cycle_by_dx[0.2]["chain"]["total_moment_rel"]
    large = loaded_dx.one_dx(0.2, 2.0, "local", variants=("chain",))["variants"]["chain"]
    assert large["births_matched"] == 3
    ratio = small / large["total_moment_rel"]
    assert 1.7 < ratio < 2.3, (small, large["total_moment_rel"])
