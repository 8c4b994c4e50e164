"""What a careless user meets (issue 27): messages they read, one policy for the same input
in both models, and no result that is wrong without a word."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves.config import load_config, parse_config
from bkwaves.runner import checkpoint_path, run

BK = [sys.executable, "-m", "bkwaves"]
EXAMPLES = Path(__file__).parent.parent / "examples"


def cli(*args, cwd=None):
    return subprocess.run(
        [*BK, *map(str, args)], capture_output=True, text=True, timeout=600, cwd=cwd
    )


def chain_doc(**over):
    doc = {
        "model": "chain",
        "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        "domain": {"blocks": 20},
        "initial": {"kind": "uniform", "value": 0.5},
        "run": {"t_end": 0.3},
        "output": {"snapshot_every": 0.1},
    }
    doc.update(over)
    return doc


def fb_doc(**over):
    doc = {
        "model": "free_boundary",
        "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
        "domain": {"length": 20.0, "grid": 41},
        "initial": {"kind": "uniform", "value": 0.5},
        "run": {"t_end": 0.3},
        "output": {"snapshot_every": 0.1},
    }
    doc.update(over)
    return doc


def toml(doc: dict) -> str:
    """A config document as TOML (tables of scalars, arrays of tables)."""

    def val(x):
        if isinstance(x, str):
            return f'"{x}"'
        if isinstance(x, bool):
            return "true" if x else "false"
        if isinstance(x, list):
            return "[" + ", ".join(val(v) for v in x) + "]"
        return repr(x)

    lines = [f"{k} = {val(v)}" for k, v in doc.items() if not isinstance(v, dict | list)]
    for k, v in doc.items():
        if isinstance(v, dict):
            lines += [f"[{k}]", *(f"{a} = {val(b)}" for a, b in v.items())]
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                lines += [f"[[{k}]]", *(f"{a} = {val(b)}" for a, b in item.items())]
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- messages


def test_cli_warnings_are_one_clean_line(tmp_path):
    """A warning in the command line is `Warning: ...` on one line: no file path, no
    warning class, no source line."""
    cfg = tmp_path / "c.toml"
    doc = fb_doc(initial={"kind": "ramp", "start": 0.0, "end": 0.9})  # steep: no-creep
    doc["params"]["v"] = 1e-3
    cfg.write_text(toml(doc))
    r = cli("run", cfg, "-o", tmp_path / "o.nc", "--quiet")
    assert r.returncode == 0, r.stderr
    lines = r.stderr.strip().splitlines()
    assert lines and all(line.startswith("Warning: ") for line in lines), r.stderr
    assert any("no-creep condition" in line for line in lines)
    assert ".py:" not in r.stderr and "NoCreepWarning" not in r.stderr


def test_summary_line_names_the_units_once(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(toml(chain_doc()))
    r = cli("run", cfg, "-o", tmp_path / "o.nc", "--quiet")
    assert r.returncode == 0, r.stderr
    assert "at t = 0.3 (dimensionless)," in r.stdout and "((" not in r.stdout, r.stdout
    r = cli("run", EXAMPLES / "bristol_board.toml", "-o", tmp_path / "b.nc", "--quiet")
    assert r.returncode == 0, r.stderr
    assert "at t = 2e-06 s," in r.stdout, r.stdout


def test_exists_message_offers_resume_only_when_it_can_work(tmp_path):
    doc = chain_doc(run={"t_end": 40.0}, output={"snapshot_every": 1.0})
    doc["triggers"] = [{"block": 0, "kind": "kick", "velocity": 2.0}]
    doc["params"]["dx"] = 0.05
    doc["domain"]["blocks"] = 400
    doc["initial"]["value"] = 0.6
    cfg = parse_config(doc)
    done = tmp_path / "done.nc"
    run(cfg, done)
    with pytest.raises(bk.ParameterError) as e:
        run(cfg, done)
    assert "--overwrite" in str(e.value) and "--resume" not in str(e.value)
    cut = tmp_path / "cut.nc"
    assert run(cfg, cut, chunk=200, _stop_after_chunks=2).interrupted
    assert checkpoint_path(cut).exists()
    with pytest.raises(bk.ParameterError, match="--resume") as e:
        run(cfg, cut)
    # a crash before any checkpoint: the unfinished run cannot be resumed
    checkpoint_path(cut).unlink()
    with pytest.raises(bk.ParameterError) as e:
        run(cfg, cut)
    assert "--resume" not in str(e.value) and "no checkpoint" in str(e.value)


def test_law_parameter_without_its_law_says_which_law():
    r = cli("front", "--u-plus", "0.6", "--gamma", "0.3", "--dx", "0.05", "--v-f", "0.1")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "add --law velocity_weakening" in r.stderr, r.stderr
    assert "gamma, beta" not in r.stderr


def test_si_kick_beyond_the_engine_names_the_trigger():
    doc = {
        "model": "chain",
        "physical": {"preset": "bristol_board", "V": 1e-6},
        "domain": {"blocks": 50},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [{"block": 0, "kind": "kick", "velocity": 1e5}],
        "run": {"t_end": 1e-7},
    }
    with pytest.raises(bk.ParameterError, match=r"^triggers\[0\]\.velocity: ") as e:
        parse_config(doc)
    assert "du_t" not in str(e.value) and "m/s" in str(e.value)
    # within the limit: m/s over the velocity scale, for kicks and the initial velocity
    doc["triggers"][0]["velocity"] = 0.03
    doc["initial"]["velocity"] = 0.01
    cfg = parse_config(doc)
    vs = cfg.params.units.velocity_scale
    assert cfg.triggers[0].velocity == 0.03 / vs
    assert cfg.initial.velocity == 0.01 / vs
    doc["initial"]["velocity"] = 1e5
    with pytest.raises(bk.ParameterError, match=r"^initial\.velocity: "):
        parse_config(doc)


# --------------------------------------------------------------------------- one policy


def test_over_threshold_initial_state_one_policy():
    """u >= 1 at t = 0: the chain's blocks slide from t = 0 (all of them, for a uniform
    1.5 on free ends, where u - Lap u/dx^2 = u); the free-boundary model refuses it,
    naming the key and pointing to the chain."""
    res = bk.run(parse_config(chain_doc(initial={"kind": "uniform", "value": 1.5})))
    ev = res.tables["events"]
    assert ev["t_start"].iloc[0] == 0.0
    slips = res.tables["slips"]
    first = slips[slips["event"] == ev["event"].iloc[0]]
    assert sorted(set(first["block"])) == list(range(20))
    assert (first["t_start"] == 0.0).all()
    with pytest.raises(bk.ParameterError, match=r"^initial\.value: .*model = \"chain\""):
        bk.run(parse_config(fb_doc(initial={"kind": "uniform", "value": 1.5})))


def test_paths_in_a_config_are_relative_to_its_folder(tmp_path):
    """[output] path, like [initial] path and a sweep's [output] path, is relative to the
    config file's folder; -o is relative to the working directory."""
    sub = tmp_path / "configs"
    sub.mkdir()
    doc = chain_doc(output={"path": "o.nc", "snapshot_every": 0.1})
    (sub / "c.toml").write_text(toml(doc))
    assert load_config(sub / "c.toml").output_path == str(sub / "o.nc")
    r = cli("run", "configs/c.toml", "--quiet", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (sub / "o.nc").exists() and not (tmp_path / "o.nc").exists()
    r = cli("run", "configs/c.toml", "-o", "here.nc", "--quiet", cwd=tmp_path)
    assert r.returncode == 0 and (tmp_path / "here.nc").exists()
    from bkwaves.sweeps import load_sweep

    (sub / "s.toml").write_text('task = "speed"\n[axes.u_plus]\nvalues = [0.5]\n')
    assert load_sweep(sub / "s.toml").output_path == str(sub / "s.zarr")
    (sub / "t.toml").write_text(
        'task = "speed"\n[axes.u_plus]\nvalues = [0.5]\n[output]\npath = "x.zarr"\n'
    )
    assert load_sweep(sub / "t.toml").output_path == str(sub / "x.zarr")


# --------------------------------------------------------------------------- no silent error


def test_free_boundary_refuses_other_friction_laws():
    doc = fb_doc(friction={"law": "velocity_weakening", "v_f": 0.1})
    with pytest.raises(bk.ParameterError, match=r"^friction\.law: .*Coulomb"):
        parse_config(doc)
    doc = fb_doc(friction={"law": "coulomb", "gamma": 0.3})
    del doc["params"]["gamma"]
    assert parse_config(doc).params.gamma == 0.3  # Coulomb's own table is used
    law = bk.friction.law("velocity_weakening", v_f=0.1)
    p = bk.Params(gamma=0.3, v=1e-2, dx=1e-3, friction_law=law)
    x = np.linspace(0.0, 20.0, 41)
    with pytest.raises(bk.ParameterError, match="Coulomb"):
        bk.FreeBoundary(p, x, np.full(41, 0.5))


@pytest.mark.parametrize("doc", [chain_doc, fb_doc], ids=["chain", "free_boundary"])
def test_every_snapshot_through_t_end(doc):
    """t_end = 0.3 with a snapshot every 0.1: 3 x 0.1 = 0.30000000000000004 > 0.3, and the
    snapshot at t_end was lost; t_k = k dt with a tolerance keeps it."""
    res = bk.run(parse_config(doc()), snapshots=True)
    np.testing.assert_allclose(res.snapshots.t.values, [0.0, 0.1, 0.2, 0.3], rtol=0, atol=0)
    d = doc(run={"t_end": 0.7}, output={"snapshot_every": 0.1})  # 7 x 0.1 < 0.7: kept too
    assert bk.run(parse_config(d), snapshots=True).snapshots.sizes["t"] == 8
    d = doc(run={"t_end": 0.35}, output={"snapshot_every": 0.1})  # not a multiple: no 0.35
    np.testing.assert_array_equal(
        bk.run(parse_config(d), snapshots=True).snapshots.t.values[-1:], [0.30000000000000004]
    )


def test_bristol_board_keeps_its_last_snapshot(tmp_path):
    cfg = load_config(EXAMPLES / "bristol_board.toml")
    out = tmp_path / "b.nc"
    run(cfg, out)
    ds, _ = bk.load(out)
    assert ds.sizes["t"] == 21  # t = 0, 0.1 us, ..., 2 us
    assert ds.t.values[-1] == pytest.approx(2e-6, rel=1e-12)
    np.testing.assert_allclose(np.diff(ds.t.values), 1e-7, rtol=1e-9)


def test_rate_density_refuses_what_is_not_a_stress():
    law = {"law": "exponential", "rate": 2.0, "phi0": 0.5}
    for bad in (None, "0.5", [0.5, None], float("nan")):
        with pytest.raises(bk.ParameterError, match="u"):
            bk.noise.rate_density(bad, law)
    assert bk.noise.rate_density(1.0, law) == 2.0
    assert bk.noise.rate_density([0.5], law)[0] == pytest.approx(2.0 * math.exp(-1.0))


def test_float_seeds_are_refused_not_truncated():
    from bkwaves import disorder

    for seed in (1.5, 2.0, -1, True, "3", [1, 2.5], []):
        with pytest.raises(bk.ParameterError, match="seed"):
            disorder.draw("uniform", 4, spread=0.1, seed=seed)
        with pytest.raises(bk.ParameterError, match="seed"):
            disorder.thresholds(4, 0.1, seed=seed)
    with pytest.raises(bk.ParameterError, match="seed"):
        disorder.property_seed(1.5, "threshold")
    a = disorder.draw("uniform", 4, spread=0.1, seed=[7, 1])
    b = np.random.default_rng([7, 1]).uniform(0.9, 1.1, 4)
    np.testing.assert_array_equal(a, b)
    assert disorder.property_seed(7, "threshold") == [7, 1]
