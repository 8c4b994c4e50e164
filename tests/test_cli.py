"""The command line: JSON keys of DESIGN.md, exit status 2 and no traceback on bad input."""

import json
import subprocess
import sys

import pytest

BK = [sys.executable, "-m", "bkwaves.cli"]


def run(*args):
    return subprocess.run([*BK, *args], capture_output=True, text=True, timeout=120)


def test_help_and_version():
    r = run("--help")
    assert r.returncode == 0 and "wave" in r.stdout and "speed" in r.stdout
    r = run("--version")
    assert r.returncode == 0 and r.stdout.startswith("bkwaves ")


def test_wave_json_keys_and_values():
    r = run("wave", "--u-plus", "0.6", "--gamma", "0.3", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert set(d) == {"u_plus", "gamma", "c", "regime", "u_c", "w", "u_minus", "A"}
    assert d["regime"] == "pulse"
    assert d["c"] == pytest.approx(1.25, rel=1e-14)
    assert d["A"] == pytest.approx(d["u_plus"] - d["u_minus"], rel=1e-14)


def test_wave_creep_has_nulls():
    d = json.loads(run("wave", "--u-plus", "0.2", "--gamma", "0.3", "--json").stdout)
    assert d["regime"] == "creep"
    assert d["w"] is None and d["u_minus"] is None and d["A"] is None
    d = json.loads(run("wave", "--u-plus", "0.9", "--gamma", "1.5", "--json").stdout)
    assert d["regime"] == "creep" and d["u_c"] is None


def test_wave_plot_written(tmp_path):
    out = tmp_path / "w.png"
    r = run("wave", "--u-plus", "0.6", "--gamma", "0.3", "--plot", str(out))
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 10_000


def test_speed_json(tmp_path):
    out = tmp_path / "cf.pdf"
    r = run("speed", "0.1", "0.5", "0.9", "--json", "--plot", str(out))
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert set(d) == {"u_plus", "c", "c_interpolation"}
    assert d["u_plus"] == [0.1, 0.5, 0.9]
    for u, c, ci in zip(d["u_plus"], d["c"], d["c_interpolation"], strict=True):
        assert c == pytest.approx((1 - u * u) ** -0.5, rel=1e-14)
        assert abs(ci / c - 1) < 0.03  # "a few per cent"
    assert out.stat().st_size > 5_000


def test_speed_tip_method_agrees():
    d = json.loads(run("speed", "0.3", "0.7", "--method", "tip", "--json").stdout)
    for u, c in zip(d["u_plus"], d["c"], strict=True):
        assert c == pytest.approx((1 - u * u) ** -0.5, rel=1e-11)


@pytest.mark.parametrize(
    "args, name",
    [
        (["wave", "--u-plus", "1.5", "--gamma", "0.3"], "u_plus"),
        (["wave", "--u-plus", "0", "--gamma", "0.3"], "u_plus"),
        (["wave", "--u-plus", "nan", "--gamma", "0.3"], "u_plus"),
        (["wave", "--u-plus", "0.5", "--gamma", "-0.1"], "gamma"),
        (["wave", "--u-plus", "0.5", "--gamma", "inf"], "gamma"),
        (["speed", "0.5", "1.0"], "u_plus"),
        (["speed", "0.5", "--method", "magic"], "method"),
    ],
)
def test_bad_input_exit_2_names_parameter(args, name):
    r = run(*args)
    assert r.returncode == 2
    assert name in r.stderr and "allowed" in r.stderr
    assert "Traceback" not in r.stderr + r.stdout


def test_typo_in_option_is_exit_2():
    r = run("wave", "--u-plus", "0.5", "--gama", "0.3")
    assert r.returncode == 2 and "Traceback" not in r.stderr


def test_plot_command(tmp_path):
    import numpy as np

    from bkwaves.io import RunWriter

    out = tmp_path / "r.zarr"
    with RunWriter(out, np.linspace(0, 1, 5), {"u": ("1", "u", "f8")}) as w:
        for k in range(3):
            w.append(float(k), u=np.full(5, 0.1 * k))
    r = run("plot", str(out), "--format", "svg")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "r_spacetime_u.svg").exists() and (tmp_path / "r_profiles.svg").exists()
    r = run("plot", str(tmp_path / "missing.nc"))
    assert r.returncode == 2 and "not found" in r.stderr and "Traceback" not in r.stderr
    r = run("plot", str(out), "--format", "bmp")
    assert r.returncode == 2 and "fmt" in r.stderr
