"""Every picture `bkwaves plot` draws is readable (tests/figure_checks.py): of the output
of every example config in examples/, run as it is, and of every example sweep, shrunk
to a few points. Whatever `bkwaves plot` writes is checked, so a new picture (or a new
model with its example) is checked without a change here."""

import contextlib
import io
import tomllib
from pathlib import Path

import pytest
from figure_checks import figure_problems

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
RUNS = sorted(p for p in EXAMPLES.glob("*.toml") if not p.name.startswith("sweep_"))
SWEEPS = sorted(EXAMPLES.glob("sweep_*.toml"))
#: Every example sweep as written (the product of its axes, unless it says otherwise) and,
#: where it has two axes or more, zipped: the two shapes of store `bkwaves plot` draws.
SWEEP_CASES = [(p, None) for p in SWEEPS] + [
    (p, "zip") for p in SWEEPS if len(tomllib.loads(p.read_text())["axes"]) > 1
]


def _plot_checked(out, outdir) -> tuple[list[str], dict[str, list[str]]]:
    """`bkwaves plot OUT -o OUTDIR` in this process, each figure checked by
    :func:`figure_problems` just before it is saved: the files it printed, and the problems
    found in each figure saved (by file name)."""
    import bkwaves.plot
    from bkwaves.cli import main

    problems, save = {}, bkwaves.plot.save

    def checked_save(ax, path):
        problems[Path(path).name] = figure_problems(ax.figure)
        return save(ax, path)

    stdout = io.StringIO()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(bkwaves.plot, "save", checked_save)
        with contextlib.redirect_stdout(stdout), pytest.raises(SystemExit) as done:
            main(["plot", str(out), "-o", str(outdir)])
    assert done.value.code in (0, None)
    printed = [Path(line).name for line in stdout.getvalue().split()]
    return printed, problems


def _assert_readable(printed, problems, outdir):
    assert printed, "bkwaves plot drew nothing"
    # every file written went through the checks, and only those
    assert sorted(problems) == sorted(printed) == sorted(p.name for p in outdir.iterdir())
    bad = {k: v for k, v in problems.items() if v}
    assert not bad, bad


@pytest.mark.parametrize("example", RUNS, ids=lambda p: p.stem)
def test_every_picture_of_an_example_run_is_readable(example, tmp_path):
    from bkwaves.config import load_config
    from bkwaves.runner import run

    out = tmp_path / f"{example.stem}.nc"
    run(load_config(example), out)
    pictures = tmp_path / "pictures"
    pictures.mkdir()
    printed, problems = _plot_checked(out, pictures)
    _assert_readable(printed, problems, pictures)


def _shrunk(doc: dict) -> dict:
    """The sweep ``doc`` on at most 3 values per axis (3 seeds): a few runs, and still
    a mean and an error over seeds, a line per value of the second axis."""
    for axis in doc["axes"].values():
        if "values" in axis:
            axis["values"] = axis["values"][:3]
        for kind in ("linspace", "logspace"):
            if kind in axis:
                axis[kind]["num"] = min(axis[kind]["num"], 3)
        if "seeds" in axis:
            axis["seeds"] = min(axis["seeds"], 3)
    return doc


@pytest.mark.parametrize(
    ("example", "combine"), SWEEP_CASES, ids=lambda c: c.stem if isinstance(c, Path) else c
)
def test_every_picture_of_an_example_sweep_is_readable(example, combine, tmp_path):
    from bkwaves.sweeps import parse_sweep, sweep

    doc = _shrunk(tomllib.loads(example.read_text()))
    if combine:
        doc["combine"] = combine
    if combine == "zip":  # axes of one length: the shortest
        n = min(len(a.values) for a in parse_sweep({**doc, "combine": "product"}).axes)
        for axis in doc["axes"].values():
            if "values" in axis:
                axis["values"] = axis["values"][:n]
            for kind in ("linspace", "logspace"):
                if kind in axis:
                    axis[kind]["num"] = n
            if "seeds" in axis:
                axis["seeds"] = n
    doc.get("output", {}).pop("path", None)
    out = tmp_path / f"{example.stem}.zarr"
    result = sweep(doc, out, workers=1)
    assert result.failed == 0 and result.computed > 1
    pictures = tmp_path / "pictures"
    pictures.mkdir()
    printed, problems = _plot_checked(out, pictures)
    _assert_readable(printed, problems, pictures)
