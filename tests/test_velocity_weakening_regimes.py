"""Issue 22: "subsonic for v_f >~ dx" does not hold; converged fronts at v_f = dx are on
either side of the sound speed (docs/velocity_weakening.md, point 3)."""

import pytest

from bkwaves import velocity_weakening as vw


@pytest.mark.parametrize(
    "u_plus, dx, c, side",
    [(0.8, 0.1, 1.035230, 1), (0.8, 0.05, 1.051758, 1), (0.6, 0.1, 0.970334, -1)],
)
def test_v_f_equal_to_dx_does_not_decide_the_side_of_the_sound_speed(u_plus, dx, c, side):
    # the converged fronts of docs/velocity_weakening.md (an outside audit found 1.035 and
    # 1.052 at u_+ = 0.8), each to vw.TOLERANCE by doubling the chain
    f = vw.front(u_plus, 0.3, dx, dx, weakening=False)
    assert f.status == "steady" and f.converged, f
    assert f.c == pytest.approx(c, abs=2e-6)
    assert side * (f.c - 1.0) > 0.02
