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
    assert "Error: " in r.stderr and "--gama" in r.stderr
    for args in (["wave", "--u-plus", "abc", "--gamma", "0.3"], ["nope"], ["speed"]):
        r = run(*args)
        assert r.returncode == 2 and "Error: " in r.stderr and "Traceback" not in r.stderr
    r = run()  # no command: the help, on stderr
    assert r.returncode == 2 and "speed" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.parametrize(
    "args, name",
    [
        (["speed", "-0.5"], "u_plus"),
        (["wave", "--u-plus", "0.5", "--gamma", "-1e-3"], "gamma"),
        (["wave", "--u-plus", "-inf", "--gamma", "0.3"], "u_plus"),
    ],
)
def test_negative_values_are_values_not_options(args, name):
    """A negative number, also with an exponent or -inf, reaches the range check that
    names the parameter (it is not taken for an unknown option)."""
    r = run(*args)
    assert r.returncode == 2, r.stderr
    assert name in r.stderr and "allowed" in r.stderr and "Traceback" not in r.stderr


def test_options_and_arguments_in_any_order():
    r = run("speed", "0.3", "--json", "0.6", "--method", "tip")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["u_plus"] == [0.3, 0.6]


def test_interrupted_command_exits_130_without_traceback(monkeypatch, capsys):
    from bkwaves import cli

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setitem(cli.COMMANDS, "speed", cli.SPEED._replace(run=interrupted))
    with pytest.raises(SystemExit) as e:
        cli.main(["speed", "0.5"])
    assert e.value.code == 130 and "interrupted by SIGINT" in capsys.readouterr().err


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


def _modules_after(code):
    """The top-level modules loaded by a fresh interpreter after running ``code``."""
    probe = code + "\nimport sys; print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))"
    r = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return set(r.stdout.split())


HEAVY = {"matplotlib", "xarray", "pandas", "pyarrow", "zarr", "h5netcdf", "h5py", "scipy", "tqdm"}


def test_import_bkwaves_loads_no_plotting_or_io_libraries():
    """`import bkwaves` is fast: plotting and heavy I/O load only when used."""
    loaded = _modules_after("import bkwaves as bk; bk.front_speed(0.5); bk.Params(0.3, 0.0, 0.1)")
    assert not loaded & HEAVY, sorted(loaded & HEAVY)


def _modules_after_cli(argv):
    code = (
        "from bkwaves.cli import main\n"
        f"try:\n    main({argv!r})\nexcept SystemExit as e:\n"
        "    assert e.code in (0, None), e.code"
    )
    return _modules_after(code)


@pytest.mark.parametrize("argv", [["--help"], ["speed", "0.5", "--json"], ["run", "--help"]])
def test_cli_commands_that_need_no_plotting_do_not_import_it(argv):
    loaded = _modules_after_cli(argv)
    assert not loaded & HEAVY, sorted(loaded & HEAVY)


# a command-line framework (typer/click/pydantic), rich's help panels, or numpy on
# `--help` cost more start-up than the rest of bkwaves together (docs/benchmarks.md)
FRAMEWORKS = {"typer", "click", "pydantic", "pydantic_core", "rich"}


@pytest.mark.parametrize(
    "argv",
    [["--help"], ["--version"], *([name, "--help"] for name in ("wave", "speed", "run", "front"))],
)
def test_help_imports_neither_numpy_nor_a_cli_framework(argv):
    loaded = _modules_after_cli(argv)
    assert not loaded & (FRAMEWORKS | {"numpy"}), sorted(loaded & (FRAMEWORKS | {"numpy"}))


def test_speed_imports_only_numpy_and_the_core():
    loaded = _modules_after_cli(["speed", "0.5", "0.7", "--json"])
    assert "numpy" in loaded
    assert not loaded & (HEAVY | FRAMEWORKS), sorted(loaded & (HEAVY | FRAMEWORKS))


def test_import_bkwaves_loads_only_the_core_until_a_name_is_used():
    code = (
        "import sys, bkwaves as bk\n"
        "print(' '.join(sorted(m for m in sys.modules if m.startswith('bkwaves'))))\n"
        "assert 'numpy' not in sys.modules\n"
        "bk.front_speed(0.5)\n"
        "assert 'bkwaves.waves' in sys.modules and 'bkwaves.runner' not in sys.modules\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["bkwaves", "bkwaves._core"]


def test_every_public_name_resolves_lazily():
    import bkwaves as bk

    names = set(bk.__all__)
    assert set(bk._LAZY) <= names and len(names) == len(bk.__all__)
    for name in bk.__all__:
        assert getattr(bk, name) is not None, name
        assert name in dir(bk)
    assert bk.run is bk.runner.simulate and bk.sweep_result is bk.sweeps.load_sweep_result
    assert bk.chain.front is not None  # submodules are attributes as before
    with pytest.raises(AttributeError, match="no_such_name"):
        bk.no_such_name  # noqa: B018
    ns = {}
    exec("from bkwaves import *", ns)
    assert names <= set(ns)


def test_plot_module_leaves_matplotlib_global_state_alone():
    """Importing bkwaves.plot (and drawing with it) changes neither the backend nor the
    rcParams of the user's session."""
    code = (
        "import matplotlib; matplotlib.use('svg')\n"
        "before = dict(matplotlib.rcParams)\n"
        "import bkwaves as bk, bkwaves.plot as bp\n"
        "ax = bp.speed_curve([0.5])\n"
        "after = dict(matplotlib.rcParams)\n"
        "changed = sorted(k for k in before if before[k] != after[k])\n"
        "assert matplotlib.get_backend() == 'svg', matplotlib.get_backend()\n"
        "assert not changed, changed\n"
        "assert not ax.spines['top'].get_visible()  # the bkwaves style still applies\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr


def test_plot_with_unknown_suffix_is_a_clear_error(tmp_path):
    r = run("wave", "--u-plus", "0.6", "--gamma", "0.3", "--plot", str(tmp_path / "w.bmpx"))
    assert r.returncode == 2
    assert "Traceback" not in r.stderr + r.stdout
    assert "--plot" in r.stderr and ".png" in r.stderr and ".pdf" in r.stderr
    assert not (tmp_path / "w.bmpx").exists()
    r = run("speed", "0.5", "--plot", str(tmp_path / "noext"))
    assert r.returncode == 2 and "--plot" in r.stderr and "Traceback" not in r.stderr


def _help(*cmd):
    r = run(*cmd, "--help")
    assert r.returncode == 0, r.stderr
    return " ".join(r.stdout.replace("│", " ").split())


def test_help_texts_show_brackets_and_plain_flags():
    text = _help("run")
    assert "[output] path" in text
    # --quick's help states the measured saving (docs/benchmarks.md), not "minutes -> seconds"
    text = _help("paper")
    assert "minutes -> seconds" not in text and "docs/benchmarks.md" in text
    for cmd in (("run",), ("wave",), ("speed",), ("paper",), ("front",)):
        text = _help(*cmd)
        assert "<bool>" not in text and "BOOLEAN" not in text, cmd
        assert "--json" in text


def test_run_summary_pluralises_events(tmp_path):
    cfg = tmp_path / "one.toml"
    cfg.write_text(
        'model = "chain"\n[params]\ngamma = 0.3\nv = 0.0\ndx = 0.1\n'
        '[domain]\nblocks = 60\n[initial]\nkind = "uniform"\nvalue = 0.6\n'
        '[[triggers]]\ntime = 0.0\nblock = 0\nkind = "kick"\nvelocity = 2.0\n'
        "[run]\nt_end = 40.0\n"
    )
    r = run("run", str(cfg), "-o", str(tmp_path / "one.nc"), "--quiet")
    assert r.returncode == 0, r.stderr
    assert " 1 event," in r.stdout and "1 events" not in r.stdout


def test_one_progress_bar_library_for_both_engines():
    """Both engines draw their progress bar with rich (on stderr), and tqdm is not used."""
    code = (
        "import numpy as np, bkwaves as bk\n"
        "p = bk.Params(gamma=0.3, v=0.0, dx=0.1)\n"
        "bk.Chain(40, p, u0=0.6).kick(0, -2.0).run(t_end=5.0, progress=True)\n"
        "x = np.linspace(0.0, 10.0, 41)\n"
        "bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-3, dx=0.1), x, 0.5 + 5e-4 * x)"
        ".run(t_end=1.0, progress=True)\n"
    )
    loaded = _modules_after(code)
    assert "rich" in loaded and "tqdm" not in loaded


def test_every_declared_dependency_is_used():
    """pyproject's runtime dependencies are the libraries bkwaves imports (no dead ones)."""
    import re
    import tomllib
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    deps = tomllib.loads((root / "pyproject.toml").read_text())["project"]["dependencies"]
    names = {re.match(r"[A-Za-z0-9_.-]+", d).group(0).lower().replace("-", "_") for d in deps}
    source = "\n".join(p.read_text() for p in (root / "python" / "bkwaves").glob("*.py"))
    imported = set(re.findall(r"^\s*(?:import|from)\s+([A-Za-z0-9_]+)", source, re.M))
    # h5netcdf and zarr are reached through xarray's engine names
    engines = set(re.findall(r"engine=\"([a-z0-9_]+)\"", source)) | {
        "zarr" for _ in re.findall(r"open_zarr|to_zarr", source)
    }
    unused = sorted(names - imported - engines)
    assert not unused, f"declared in pyproject.toml but never imported: {unused}"
