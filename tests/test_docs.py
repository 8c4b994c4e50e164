"""The documentation's promises that can be checked: the compiled core's docstring
examples run (pytest --doctest-modules cannot collect an extension module), the public
names converted to numpydoc keep their Parameters, Returns and Examples sections in step
with their signatures, and the API reference lists every public module."""

from __future__ import annotations

import doctest
import importlib
import pkgutil
import re
from pathlib import Path

import pytest

import bkwaves
from bkwaves import _core, theory

ROOT = Path(__file__).resolve().parents[1]

#: Names whose docstrings are numpydoc with Parameters, Returns and Examples (the API
#: reference's entry points); every function of bkwaves._core joins them below.
NUMPYDOC = [
    "bkwaves.waves.front_speed",
    "bkwaves.waves.tip_solve",
    "bkwaves.waves.traveling_wave",
    "bkwaves.waves.TravelingWave.profile",
    "bkwaves.params.Params.from_physical",
    "bkwaves.chain.Chain.run",
    "bkwaves.chain.Chain.kick",
    "bkwaves.chain.front",
    "bkwaves.config.load_config",
    "bkwaves.free_boundary.FreeBoundary.run",
    "bkwaves.runner.simulate",
    "bkwaves.io.load",
    "bkwaves.sweeps.sweep",
    "bkwaves.sweeps.load_sweep_result",
]
NUMPYDOC += [f"bkwaves.theory.{n}" for n in theory.__all__]  # every formula of the paper
#: Classes: Parameters (of the constructor) and Examples.
NUMPYDOC_CLASSES = ["bkwaves.params.Params", "bkwaves.chain.Chain", "bkwaves.FreeBoundary"]

CORE_FUNCTIONS = sorted(
    n
    for n in _core.__all__
    if callable(getattr(_core, n)) and not isinstance(getattr(_core, n), type)
)


def test_core_docstring_examples_run():
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    tested = set()
    for test in finder.find(_core):
        if test.examples:
            runner.run(test)
            tested.add(test.name.rsplit(".", 1)[1])
    assert runner.failures == 0
    # every function has an example (the engine classes too, besides)
    assert set(CORE_FUNCTIONS) <= tested, set(CORE_FUNCTIONS) - tested


def _errors(name: str, codes: set[str]) -> list:
    validate = pytest.importorskip("numpydoc.validate").validate
    out = []
    for code, message in validate(name)["errors"]:
        if code not in codes:
            continue
        if code == "PR01":  # private arguments (leading underscore) stay undocumented
            missing = re.findall(r"'([^']+)'", message)
            if all(m.startswith("_") for m in missing):
                continue
        out.append((code, message))
    return out


@pytest.mark.parametrize("name", NUMPYDOC + [f"bkwaves._core.{n}" for n in CORE_FUNCTIONS])
def test_numpydoc_functions(name):
    # PR01/PR02: parameters missing or unknown; RT01: no Returns; EX01: no Examples;
    # SS03: summary without a full stop; GL08: no docstring
    assert _errors(name, {"PR01", "PR02", "RT01", "EX01", "SS03", "GL08"}) == []


@pytest.mark.parametrize("name", NUMPYDOC_CLASSES)
def test_numpydoc_classes(name):
    assert _errors(name, {"PR01", "PR02", "EX01", "GL08"}) == []


def test_api_reference_lists_every_public_module():
    index = (ROOT / "docs" / "api" / "index.rst").read_text()
    listed = set(re.findall(r"^   ([a-z_][a-z_0-9]*)$", index, re.M))
    modules = {
        m.name
        for m in pkgutil.iter_modules(bkwaves.__path__)
        if not m.name.startswith("_") and m.name not in ("cli", "sweeps_adaptive")
    }
    public = {m for m in modules if hasattr(importlib.import_module(f"bkwaves.{m}"), "__all__")}
    assert public - listed == set(), f"modules missing from docs/api/index.rst: {public - listed}"
    assert "_core" in listed
