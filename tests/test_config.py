"""TOML run configurations: validation with key paths, units, initial states."""

import math
import tomllib

import numpy as np
import pytest

import bkwaves as bk
from bkwaves.config import initial_state, load_config, parse_config

BASE = {
    "model": "chain",
    "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.05},
    "domain": {"blocks": 200, "boundary": "free"},
    "initial": {"kind": "uniform", "value": 0.6},
    "run": {"t_end": 10.0},
}


def cfg(**changes):
    doc = {k: (dict(v) if isinstance(v, dict) else v) for k, v in BASE.items()}
    for path, value in changes.items():
        keys = path.split("__")
        d = doc
        for k in keys[:-1]:
            d = d.setdefault(k, {})
        if value is None:
            d.pop(keys[-1], None)
        else:
            d[keys[-1]] = value
    return doc


def test_valid_config_and_defaults():
    c = parse_config(cfg())
    assert c.model == "chain" and c.blocks == 200 and c.boundary == "free"
    assert c.params == bk.Params(0.3, 1e-3, 0.05)
    assert c.t_end == 10.0 and c.max_events is None and c.output_units == "native"
    np.testing.assert_allclose(c.x(), np.arange(200) * 0.05)
    np.testing.assert_allclose(initial_state(c), 0.6)


def test_params_beta_defaults_to_no_backward_slip():
    assert parse_config(cfg()).params.beta == math.inf
    assert parse_config(cfg(params__beta=5.0)).params.beta == 5.0
    assert parse_config(cfg(params__beta=math.inf)).params.beta == math.inf
    text = 'model = "chain"\n[params]\ngamma = 0.3\nv = 0.0\ndx = 0.1\nbeta = inf\n'
    text += "[domain]\nblocks = 10\n[run]\nt_end = 1.0\n"
    assert parse_config(tomllib.loads(text)).params.beta == math.inf


@pytest.mark.parametrize(
    "changes, where, words",
    [
        ({"params__beta": -1.0}, "params.beta", "inf for no backward slip"),
        ({"params__beta": "inf"}, "params.beta", "expected a number"),
        ({"initial__velocity": -0.5}, "initial.velocity", "backward slip"),
        (
            {"triggers": [{"block": 1, "kind": "kick", "velocity": -1.0}]},
            "triggers[0].velocity",
            "backward slip",
        ),
        ({"params__gama": 0.3}, "params.gama", "unknown key"),
        ({"modle": "chain"}, "modle", "unknown key"),
        ({"model": "chains"}, "model", "chain, free_boundary"),
        ({"params__gamma": -1.0}, "params", "gamma"),
        ({"params__gamma": "high"}, "params.gamma", "expected a number"),
        ({"params__dx": None}, "params.dx", "missing"),
        ({"domain__blocks": 1}, "domain.blocks", ">= 2"),
        ({"domain__blocks": 2.5}, "domain.blocks", "integer"),
        ({"domain__boundary": "open"}, "domain.boundary", "free, fixed, periodic"),
        ({"initial__kind": "sine"}, "initial.kind", "uniform, ramp"),
        ({"initial__value": float("nan")}, "initial.value", "value"),
        ({"run": {}}, "run", "t_end, max_events"),
        ({"run": {"t_end": -1.0}}, "run.t_end", "t_end"),
        ({"physical": {"preset": "bristol_board", "V": 1e-6}}, "params", "exactly one"),
        ({"output": {"units": "cgs"}}, "output.units", "native, dimensionless"),
        ({"triggers": [{"block": 500, "kind": "kick"}]}, "triggers[0].block", "< 200"),
        ({"triggers": [{"block": 1, "kind": "push"}]}, "triggers[0].kind", "kick, release"),
    ],
)
def test_errors_name_the_key_path(changes, where, words):
    with pytest.raises(bk.ParameterError) as e:
        parse_config(cfg(**changes))
    msg = str(e.value)
    assert msg.startswith(where) and words in msg, msg


def test_physical_config_converts_to_dimensionless_units():
    doc = cfg(params=None, physical={"preset": "bristol_board", "V": 1e-6})
    doc["run"] = {"t_end": 1e-3}
    doc["initial"] = {
        "kind": "bumps",
        "base": 0.2,
        "bumps": [{"center": 1e-4, "width": 2e-5, "height": 0.5}],
    }
    c = parse_config(doc)
    u = c.params.units
    assert c.physical
    assert c.t_end == pytest.approx(1e-3 / u.time_scale)
    assert c.initial.bumps[0].center == pytest.approx(1e-4 / u.length_scale)
    # the bump sits at the block nearest 1e-4 m = 100 blocks of 1 um
    u0 = initial_state(c)
    assert np.argmax(u0) == 100 and u0.max() == pytest.approx(0.7)


def test_initial_kinds(tmp_path):
    c = parse_config(cfg(initial={"kind": "ramp", "start": 0.1, "end": 0.5}))
    u = initial_state(c)
    assert u[0] == pytest.approx(0.1) and u[-1] == pytest.approx(0.5)
    assert np.allclose(np.diff(u), np.diff(u)[0])
    r = {"kind": "random", "mean": 0.5, "amplitude": 0.2, "correlation_length": 1.0}
    a = initial_state(parse_config(cfg(initial=r, seed=3)))
    b = initial_state(parse_config(cfg(initial=r, seed=3)))
    d = initial_state(parse_config(cfg(initial=r, seed=4)))
    assert np.array_equal(a, b) and not np.array_equal(a, d)
    assert np.max(np.abs(a - 0.5)) == pytest.approx(0.2)
    # smooth: neighbouring blocks (dx = 0.05 << correlation length 1) differ little
    assert np.max(np.abs(np.diff(a))) < 0.05 * 0.2 * 5
    np.save(tmp_path / "u0.npy", np.linspace(0, 0.9, 200))
    (tmp_path / "run.toml").write_text(
        'model = "chain"\n[params]\ngamma = 0.3\nv = 0.0\ndx = 0.05\n'
        "[domain]\nblocks = 200\n"
        '[initial]\nkind = "file"\npath = "u0.npy"\n[run]\nmax_events = 5\n'
    )
    c = load_config(tmp_path / "run.toml")
    assert initial_state(c)[-1] == pytest.approx(0.9)
    np.save(tmp_path / "u0.npy", np.zeros(10))
    with pytest.raises(bk.ParameterError, match="initial.path"):
        initial_state(load_config(tmp_path / "run.toml"))


def test_free_boundary_domain():
    doc = cfg(model="free_boundary", domain={"length": 50.0, "grid": 101, "boundary": "periodic"})
    c = parse_config(doc)
    x = c.x()
    assert len(x) == 101 and x[1] - x[0] == pytest.approx(50.0 / 101)
    with pytest.raises(bk.ParameterError, match="domain.blocks"):
        parse_config(cfg(model="free_boundary", domain={"blocks": 10, "length": 5.0, "grid": 9}))


def test_bad_toml_file(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("model = chain\n")
    with pytest.raises(bk.ParameterError, match="not valid TOML"):
        load_config(p)
    with pytest.raises(bk.ParameterError, match="not found"):
        load_config(tmp_path / "missing.toml")
