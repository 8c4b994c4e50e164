"""Parameters, physical units and the paper's Bristol-board example (Sec. VI)."""

import dataclasses
import math

import pytest

import bkwaves as bk


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(gamma=-0.1, v=0.0, dx=0.1), "gamma"),
        (dict(gamma=math.nan, v=0.0, dx=0.1), "gamma"),
        (dict(gamma=0.3, v=-1e-3, dx=0.1), "v"),
        (dict(gamma=0.3, v=math.inf, dx=0.1), "v"),
        (dict(gamma=0.3, v=0.0, dx=0.0), "dx"),
        (dict(gamma=0.3, v=0.0, dx=-0.1), "dx"),
        (dict(gamma=0.3, v=0.0, dx=0.1, beta=-1.0), "beta"),
        (dict(gamma=0.3, v=0.0, dx=0.1, beta=math.nan), "beta"),
        (dict(gamma=0.3, v=0.0, dx=0.1, beta=-math.inf), "beta"),
        (dict(gamma="a lot", v=0.0, dx=0.1), "gamma"),
    ],
)
def test_params_reject_bad_values_naming_parameter_and_range(kwargs, name):
    with pytest.raises(bk.ParameterError) as e:
        bk.Params(**kwargs)
    msg = str(e.value)
    assert msg.startswith(f"invalid {name} =") and "allowed" in msg


def test_params_frozen_and_equal_by_value():
    p = bk.Params(gamma=0.3, v=1e-3, dx=0.05, beta=2.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.gamma = 0.4
    assert p == bk.Params(0.3, 1e-3, 0.05, 2.0)
    assert p.to_dict() == {"gamma": 0.3, "v": 1e-3, "dx": 0.05, "beta": 2.0}


def test_default_is_the_papers_model_without_backward_slip():
    # the paper's chain has no backward slip: beta = f_s/(f_r - f_s) = inf by default
    p = bk.Params(gamma=0.3, v=0.0, dx=0.1)
    assert p.beta == math.inf and not p.backward_slip
    assert "no backward slip" in p.friction
    q = bk.Params(gamma=0.3, v=0.0, dx=0.1, beta=5.0)
    assert q.backward_slip and "-11" in q.friction  # threshold -(1 + 2 beta)
    assert bk.Params(gamma=0.3, v=0.0, dx=0.1, beta=math.inf) == p
    with pytest.raises(bk.ParameterError, match="inf for no backward slip"):
        bk.Params(gamma=0.3, v=0.0, dx=0.1, beta=-1.0)


SI = dict(mass=2.0, k_c=800.0, k_p=8.0, f_static=3.0, f_kinetic=1.0, alpha=1.6, V=0.5, spacing=0.1)


def test_from_physical_dimensionless_groups():
    p = bk.Params.from_physical(**SI)
    # gamma = alpha/(2 sqrt(k_p m)) = 1.6/(2*4); v = V sqrt(k_p m)/(f_r - f_s) = 0.5*4/2
    assert p.gamma == pytest.approx(0.2)
    assert p.v == pytest.approx(1.0)
    assert p.dx == pytest.approx(0.1)  # sqrt(8/800)
    assert p.beta == pytest.approx(0.5)  # f_s/(f_r - f_s)


def test_from_physical_velocity_weakening():
    # v_f = V_f sqrt(k_p m)/(f_r - f_s): the velocity unit is (f_r - f_s)/sqrt(k_p m) = 0.5
    p = bk.Params.from_physical(**SI, V_f=0.01)
    assert p.friction_law.name == "velocity_weakening"
    assert dict(p.friction_law.params)["v_f"] == pytest.approx(0.02)
    assert p.friction_law.params and p.v == pytest.approx(0.5 * 4 / 2)
    # the same speed in both: V_f = V gives v_f = v
    q = bk.Params.from_physical(**{**SI, "V_f": SI["V"]})
    assert dict(q.friction_law.params)["v_f"] == pytest.approx(q.v)
    assert bk.Params.from_physical(**SI).friction_law is None
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(bk.ParameterError, match="V_f"):
            bk.Params.from_physical(**SI, V_f=bad)


def test_unit_conversions_round_trip_and_are_consistent():
    u = bk.Params.from_physical(**SI).units
    assert u.time_scale == pytest.approx(0.5)  # sqrt(m/k_p)
    assert u.length_scale == pytest.approx(1.0)  # a sqrt(k_c/k_p)
    # unit dimensionless speed is the sound speed a sqrt(k_c/m)
    assert u.length_scale / u.time_scale == pytest.approx(u.sound_speed)
    for f, g, x in [
        (u.length, u.length_to_dimless, 3.7),
        (u.time, u.time_to_dimless, 12.5),
        (u.displacement, u.displacement_to_dimless, 0.42),
        (u.velocity, u.velocity_to_dimless, -0.3),
        (u.force, u.force_to_dimless, 0.9),
    ]:
        assert g(f(x)) == pytest.approx(x, rel=1e-14)
    # phi = 1 is the static threshold, phi = 0 the kinetic level
    assert u.force(1.0) == pytest.approx(SI["f_static"])
    assert u.force(0.0) == pytest.approx(SI["f_kinetic"])
    # a stuck block (u_t = v) moves at -V relative to the loader (paper eq. rest0)
    p = bk.Params.from_physical(**SI)
    assert u.velocity(p.v) == pytest.approx(-SI["V"])
    # u = 0 is the kinetic force balance k_p X = -f_s
    assert SI["k_p"] * u.displacement(0.0) == pytest.approx(-SI["f_kinetic"])


@pytest.mark.parametrize(
    "change, name",
    [
        (dict(f_kinetic=3.0), "f_kinetic"),
        (dict(f_kinetic=4.0), "f_kinetic"),
        (dict(mass=-1.0), "mass"),
        (dict(mass=0.0), "mass"),
        (dict(k_c=0.0), "k_c"),
        (dict(k_p=-2.0), "k_p"),
        (dict(alpha=-0.1), "alpha"),
        (dict(V=math.nan), "V"),
        (dict(spacing=0.0), "spacing"),
    ],
)
def test_from_physical_rejects_unphysical_input(change, name):
    with pytest.raises(bk.ParameterError, match=f"invalid {name} ="):
        bk.Params.from_physical(**{**SI, **change})


def _paper_precision(x, printed):
    """True when x rounds to the printed value (its last printed digit +- one half)."""
    mant, exp = f"{printed:e}".split("e")
    digits = len(mant.rstrip("0").split(".")[1]) if "." in mant.rstrip("0") else 0
    half = 0.5 * 10 ** (int(exp) - digits)
    return abs(x - printed) <= half * (1 + 1e-9)


def test_bristol_board_reproduces_the_papers_numbers():
    p = bk.presets.bristol_board(V=1e-6)
    u = p.units
    assert _paper_precision(u.mass, 2.4e-12)
    assert _paper_precision(u.k_c, 3.8e7)
    assert _paper_precision(u.k_p, 2.3e1)
    assert _paper_precision(u.force_scale, 1.2e-7)
    assert _paper_precision(u.velocity_scale, 1.6e-2)  # 1.6 cm/s
    assert _paper_precision(u.slip(2.0), 1e-8)  # Delta X = 2 (f_r - f_s)/k_p
    assert _paper_precision(p.gamma, 0.45)
    # eq. (crit): V_f = 1e-5 m/s must lie below (f_r - f_s)/sqrt(k_c m)
    assert bk.presets.BRISTOL_BOARD["V_f"] < u.crit_velocity
    assert u.crit_velocity == pytest.approx(1.26e-5, rel=0.01)
    # the sound speed the example starts from
    assert u.sound_speed == pytest.approx(4000.0, rel=0.02)


def test_bristol_board_without_rounding():
    """Keeping every digit (k_c = 3.84e7) gives k_p = 23.7 and gamma = 0.444: the
    paper's 2.3e1 and 0.45 come from rounding k_c to 3.8e7 first."""
    p = bk.presets.bristol_board(V=1e-6, paper_rounding=False)
    assert p.units.k_c == pytest.approx(3.84e7)
    assert p.units.k_p == pytest.approx(23.69, rel=1e-3)
    assert p.gamma == pytest.approx(0.444, abs=1e-3)
    assert p.dx == pytest.approx(math.pi * 1e-6 / 4e-3)  # k_p/k_c = (pi a / 2h)^2
