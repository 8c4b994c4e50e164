"""TOML run configurations: validation with key paths, units, initial states."""

import math
import tomllib
import warnings
from pathlib import Path

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
        ({"domain__blocks": 0}, "domain.blocks", ">= 1"),
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


# ----------------------------------------------------------------- issue 12: bad input
FB = {
    "model": "free_boundary",
    "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
    "domain": {"length": 20.0, "grid": 41},
    "initial": {"kind": "uniform", "value": 0.5},
    "run": {"t_end": 10.0},
}


def fb_cfg(**changes):
    doc = {k: (dict(v) if isinstance(v, dict) else v) for k, v in FB.items()}
    for path, value in changes.items():
        sec, key = path.split("__")
        doc[sec][key] = value
    return doc


def refused(doc, where, *words):
    with pytest.raises(bk.ParameterError) as e:
        parse_config(doc)
    msg = str(e.value)
    assert where in msg and all(w in msg for w in words), msg
    return msg


def test_file_level_errors_are_clean(tmp_path):
    p = tmp_path / "c.toml"
    p.write_bytes(b'model = "chain"\ntitle = "caf\xe9"\n')  # Latin-1, not UTF-8
    with pytest.raises(bk.ParameterError, match="not UTF-8"):
        load_config(p)
    p.write_text('model = "chain"\ntitle = "a\\u0000b"\n')
    with pytest.raises(bk.ParameterError, match="title"):
        load_config(p)
    with pytest.raises(bk.ParameterError, match="cannot read config"):
        load_config(tmp_path)  # a directory


@pytest.mark.parametrize(
    "changes, where, words",
    [
        ({"run": {"max_events": 1e30}}, "run.max_events", ["integer"]),
        ({"run": {"t_end": "10"}}, "run.t_end", ["expected a number"]),
        ({"params__gamma": "0.3"}, "params.gamma", ["expected a number"]),
        ({"seed": "x"}, "seed", ["integer"]),
        ({"seed": 1.5}, "seed", ["integer"]),
        ({"title": "a\x00b"}, "title", ["NUL"]),
        ({"initial__value": 1e300}, "initial.value", ["<= 1000000"]),
        ({"params__v": 1e293}, "params.v", ["<= 1000000"]),
        ({"params__gamma": 1e5}, "params.gamma", ["gamma <="]),  # derived step: named gamma
        ({"output": {"path": 5}}, "output.path", ["string"]),
        ({"run": {"t_end": 10.0, "max_event_slips": 0}}, "run.max_event_slips", [">= 1"]),
    ],
)
def test_bad_values_name_the_key_the_user_wrote(changes, where, words):
    refused(cfg(**changes), where, *words)


def test_physical_scales_that_overflow_are_refused():
    phys = dict(
        mass=1.0, k_c=1.0, k_p=1.0, f_static=1.0, f_kinetic=0.5, alpha=0.0, V=0.0, spacing=1e308
    )
    doc = cfg(params=None, physical=phys)
    refused(doc, "spacing")
    with pytest.raises(bk.ParameterError, match="spacing"):
        bk.Chain(10, bk.Params.from_physical(**phys))  # would write x = inf


def test_free_boundary_keys_that_make_no_sense_are_named():
    refused(fb_cfg(params__dx=1.5), "params.dx", "continuum")
    refused(fb_cfg(params__gamma=1.2), "params.gamma")
    c = parse_config(fb_cfg(initial__value=1.2))
    with pytest.raises(bk.ParameterError) as e:
        initial_state(c)
    assert str(e.value).startswith("initial.value") and "u < 1" in str(e.value)


def test_initial_files_that_cannot_be_read(tmp_path):
    np.save(tmp_path / "pickled.npy", np.array([{"a": 1}] * 200, dtype=object))
    (tmp_path / "junk.npy").write_bytes(b"\x93NUMPY junk" * 5)
    np.save(tmp_path / "words.npy", np.array(["a"] * 200))
    (tmp_path / "words.txt").write_text("hello world\n")
    (tmp_path / "dir.npy").mkdir()
    for name in ("pickled.npy", "junk.npy", "words.npy", "words.txt", "dir.npy"):
        c = parse_config(cfg(initial={"kind": "file", "path": str(tmp_path / name)}))
        with pytest.raises(bk.ParameterError) as e:
            initial_state(c)
        assert str(e.value).startswith("initial.path"), (name, str(e.value))


# ----------------------------------------------------------------- issue 12: never run away
def test_configs_that_cannot_be_done_are_refused_naming_key_and_estimate():
    # (issue 27: an estimated time alone never refuses a run; it warns, in one line)
    with warnings.catch_warnings():
        warnings.simplefilter("error", bk.limits.LongRunWarning)
        with pytest.raises(bk.limits.LongRunWarning, match="run.t_end = 1e.30.*block-steps"):
            parse_config(cfg(run={"t_end": 1e30}))
    msg = refused(cfg(output={"snapshot_every": 1e-9}), "output.snapshot_every", "TiB")
    assert "snapshots" in msg
    refused(cfg(domain__blocks=2**50), "domain.blocks", "RAM")
    refused(cfg(domain__blocks=2**63 - 1), "domain.blocks", "2**62")
    doc = fb_cfg(params__v=0.0)
    doc["run"] = {"max_events": 3}
    refused(doc, "run.max_events", "v = 0", "run.t_end")


def test_a_long_physical_run_is_warned_with_its_time_units():
    doc = cfg(params=None, physical={"preset": "bristol_board", "V": 1e-6})
    # 600 s = 1.9e9 time units sqrt(m/k_p): ~1.2e5 reloads of the uniform chain, each
    # 200 blocks sliding ~3 time units at steps of 3.9e-5 (about 2.5 h)
    doc["run"] = {"t_end": 600.0}
    with pytest.warns(bk.limits.LongRunWarning) as w:
        c = parse_config(doc)
    msg = str(w[0].message)
    assert "run.t_end = 600 s" in msg and "time units" in msg, msg
    assert c.t_end == pytest.approx(600.0 / c.params.units.time_scale)
    assert 1e9 < c.t_end < 1e10


def test_unwritable_output_is_refused_before_any_work(tmp_path):
    from bkwaves.runner import run

    c = parse_config(cfg())
    for out, words in [
        (tmp_path / "missing" / "o.nc", "does not exist"),
        (Path("/proc/o.nc"), "cannot write"),
        (tmp_path / "o.txt", "suffixes"),
    ]:
        with pytest.raises(bk.ParameterError, match=words):
            run(c, out)
    assert not list(tmp_path.iterdir())


def test_a_runaway_event_stops_the_run_with_the_regime_named(tmp_path):
    """examples/chain_loading.toml run on: event 76 is a pulse circling the ring that
    never ends (12.3 M slips in 3.5 min before). The run stops on the slip bound, names
    the regime and keeps everything computed."""
    from bkwaves.runner import run

    doc = tomllib.loads((Path(__file__).parents[1] / "examples" / "chain_loading.toml").read_text())
    doc = {**doc, "run": {"max_events": 150, "max_event_slips": 20_000}}
    doc["output"] = {"snapshot_events": 1}
    s = run(parse_config(doc), tmp_path / "o.nc")
    assert s.extra["stop"] == "long_event" and not s.interrupted
    assert s.events == 76 and s.snapshots == 1 + 76  # the initial state, then one per event
    msg = s.extra["message"]
    assert "event 76" in msg and "run.max_event_slips = 20000" in msg and "ring" in msg
    cat = bk.io.load_tables(tmp_path / "o.nc")[1]["events"]
    assert len(cat) == 77 and 20_000 < cat.n_slips.iloc[-1] <= 20_400


def test_docs_carry_the_parameter_tables():
    """docs/usage.md lists every key of the validation tables as the code checks it."""
    from bkwaves._validate import schema_markdown

    docs = (Path(__file__).parents[1] / "docs" / "usage.md").read_text()
    assert schema_markdown() in docs
