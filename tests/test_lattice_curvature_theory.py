"""The derived curvature coefficient of the lattice's eikonal law (docs/theory.md,
section 7): an independent chain, the gamma route along the axes, and the lattice's
ruptures measured with their local curvature."""

import math

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import _curved_chain


@pytest.mark.parametrize("u,g,h", [(0.6, 0.45, 0.1), (0.7, 0.3, 0.1 / math.sqrt(2))])
def test_the_independent_chain_is_the_tip_solver_when_flat(u, g, h):
    c, change = _curved_chain.front_speed(u, g, h)
    assert abs(change) < 1e-9  # steady over the window
    assert abs(c - bk.front_speed(u, dx=h, gamma=g)) < 1e-8


def test_along_an_axis_curvature_is_extra_drag_gamma_plus_kappa_over_2c():
    # the chain with the drag kappa/c against the tip solver's dc/dgamma
    u, g, dx, eps = 0.6, 0.45, 0.1, 0.05
    c0 = bk.front_speed(u, dx=dx, gamma=g)
    cp = _curved_chain.front_speed(u, g, dx, drag=eps / c0)[0]
    cm = _curved_chain.front_speed(u, g, dx, drag=-eps / c0)[0]
    d_chain = -(cp - cm) / (2 * eps)
    d_gamma = bk.theory.curvature_coefficient(u, g, dx, "x")
    assert abs(d_chain / d_gamma - 1) < 2e-3
    assert 0.019 < d_gamma < 0.023  # the value of docs/lattice.md (0.0210)


@pytest.fixture(scope="module")
def rupture():
    return bk.lattice.rupture(0.6, 0.45, 0.1, size=64, check=False)


@pytest.mark.parametrize("direction,tol", [("x", 0.04), ("diagonal", 0.015)])
def test_the_lattice_rupture_tends_to_the_derived_coefficient(rupture, direction, tol):
    d_theory = bk.theory.curvature_coefficient(0.6, 0.45, 0.1, direction)
    m = rupture.curvature(direction)
    n = m["kappa"].size
    # the local D at the flattest point is within tol of the kappa -> 0 value ...
    assert abs(m["D"][-1] / d_theory - 1) < tol
    # ... and approaches it as the front flattens (the difference is linear in kappa)
    gap = np.abs(m["D"] / d_theory - 1)
    assert gap[-1] < gap[n // 2] < gap[n // 4]
    e, d0 = np.polyfit(m["kappa"][2 * n // 3 :], m["D"][2 * n // 3 :], 1)
    assert abs(d0 / d_theory - 1) < 5e-3
    # kappa is the front's curvature: near 1/R, not equal (the rupture is not a circle)
    assert 0.85 < m["kappa"][-1] * m["r"][-1] < 1.15


def test_the_coefficient_is_proportional_to_dx():
    a1 = bk.theory.curvature_coefficient(0.6, 0.3, 0.1, "x") / 0.1
    a2 = bk.theory.curvature_coefficient(0.6, 0.3, 0.05, "x") / 0.05
    assert abs(a2 / a1 - 1) < 0.03
    assert bk.theory.curvature_coefficient(0.6, 0.3, 0.1, "y", dy=0.05) == pytest.approx(
        bk.theory.curvature_coefficient(0.6, 0.3, 0.05, "x"), rel=1e-12
    )


@pytest.mark.parametrize(
    "kwargs,match",
    [
        ({"direction": "z"}, "direction"),
        ({"direction": "diagonal", "dy": 0.05}, "dy = dx"),
        ({"dx": 1.5}, "dx"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, match):
    args = {"u_plus": 0.6, "gamma": 0.3, "dx": 0.1} | kwargs
    with pytest.raises(ValueError, match=match):
        bk.theory.curvature_coefficient(**args)
