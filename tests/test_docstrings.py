"""Every public name the API reference documents has a numpydoc entry.

The names walked are the ones docs/api/index.rst renders: ``bkwaves.__all__``, the
``__all__`` of each module it lists (``bkwaves._core`` included), and the public methods
and properties of their classes. numpydoc's own parser and validator decide:

- a callable with parameters beyond ``self`` documents each of them, and only them, under
  Parameters (a class: its constructor's, under Parameters or Attributes);
- a callable that returns something has a Returns section (a generator: Yields); whether
  it returns is read from its source, or for the compiled core from ``_core.pyi``;
- every function, method and class has an Examples section with a ``>>>`` example (the
  ``doctests`` step of .ci/run runs them); a property or an exception has a docstring;
- a parameter or return value that is a physical quantity states its unit
  ("dimensionless", the paper's units, or SI).

``KNOWN_GAPS`` lists the names still short of this; it may only shrink: a listed name that
passes fails the test until it is removed from the list.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import pytest
from numpydoc.docscrape import get_doc_object
from numpydoc.validate import Validator

import bkwaves

ROOT = Path(__file__).resolve().parents[1]
STUB = Path(bkwaves.__file__).with_name("_core.pyi")


def _api_modules() -> list[str]:
    """The modules of the API reference's "Modules" table."""
    index = (ROOT / "docs" / "api" / "index.rst").read_text()
    modules = index.split("\nModules\n", 1)[1]
    return re.findall(r"^   ([a-z_][a-z_0-9]*)$", modules, re.M)


def _stub_returns() -> dict[str, bool]:
    """Qualified name in ``_core`` -> whether its stub returns something (not None)."""
    out = {}

    def walk(body, prefix):
        for node in body:
            if isinstance(node, ast.ClassDef):
                walk(node.body, f"{prefix}{node.name}.")
            elif isinstance(node, ast.FunctionDef):
                ret = node.returns
                none = ret is None or (isinstance(ret, ast.Constant) and ret.value is None)
                out[prefix + node.name] = not none

    walk(ast.parse(STUB.read_text()).body, "")
    return out


STUB_RETURNS = _stub_returns()

# _core's engine classes are the machinery behind bk.Chain, bk.FreeBoundary, bk.Lattice
# and bk.FreeBoundary2D (their docstrings say to use those): the classes are documented,
# their methods are not public names.
ENGINES = {"ChainEngine", "FreeBoundaryEngine", "FreeBoundary2DEngine"}


def _public_names() -> dict[str, object]:
    """Qualified name -> object for every name the API reference documents."""
    names: dict[str, object] = {}

    def add_class(qual, cls):
        names[qual] = cls
        if cls.__name__ in ENGINES or issubclass(cls, BaseException):
            return
        for klass in cls.__mro__:
            if not klass.__module__.startswith("bkwaves"):
                continue
            for attr, value in vars(klass).items():
                if attr.startswith("_") or f"{qual}.{attr}" in names:
                    continue
                if isinstance(value, (staticmethod, classmethod)):
                    value = value.__func__
                if inspect.isfunction(value) or isinstance(value, property):
                    names[f"{qual}.{attr}"] = value

    def add(qual, obj):
        # a name exported twice (bk.Chain is bkwaves.chain.Chain) is checked once
        if inspect.ismodule(obj) or any(o is obj for o in names.values()):
            return
        if inspect.isclass(obj):
            add_class(qual, obj)
        elif callable(obj):
            names[qual] = obj

    for name in bkwaves.__all__:
        if not name.startswith("__"):
            add(f"bkwaves.{name}", getattr(bkwaves, name))

    def add_module(qual):
        module = importlib.import_module(qual)
        public = getattr(module, "__all__", None)
        if public is None:  # autosummary then documents what the module defines
            public = [
                n
                for n, o in vars(module).items()
                if not n.startswith("_") and getattr(o, "__module__", None) == qual
            ]
        for name in public:
            if not name.startswith("__"):
                add(f"{qual}.{name}", getattr(module, name))
        # a package's submodules have pages of their own (the template's "Modules")
        for sub in pkgutil.iter_modules(getattr(module, "__path__", [])):
            if not sub.name.startswith("_"):
                add_module(f"{qual}.{sub.name}")

    for mod in _api_modules():
        add_module(f"bkwaves.{mod}")
    return names


NAMES = _public_names()

#: Names still short of a full entry, with what they lack (D docstring, P parameters,
#: R returns, E examples, U units). May only shrink; empty now. The paper package's
#: figure, claim and shared-run functions are registry plug-ins outside every
#: ``__all__`` (each costs seconds to minutes; ``bkwaves paper --quick`` runs them).
KNOWN_GAPS: dict[str, str] = {}

# A parameter or return of one of these names is a physical quantity: its description
# states its unit.
PHYSICAL = {
    "u_plus", "u_minus", "u0", "u", "dx", "dy", "gamma", "v", "c", "t", "t_end", "t0",
    "dt", "step", "x", "x0", "z", "w", "h", "kick", "beta", "v_f", "phi", "phi0",
    "length", "width", "mass", "threshold", "rate", "velocity", "time", "sigma",
}  # fmt: skip
UNIT = re.compile(
    r"dimensionless|\bunits?\b|\bSI\b|\bseconds?\b|\bmetres?\b|\bbytes\b|\bpaper's\b"
    r"|\[(?:kg|N|N/m|kg/s|m|m/s|s|Pa|1/s)\]",
    re.I,
)


def _returns_something(qual: str, obj, validator: Validator) -> bool:
    if qual.startswith("bkwaves._core."):
        key = qual.removeprefix("bkwaves._core.")
        return STUB_RETURNS.get(key, True)
    try:
        return validator.method_returns_something
    except (OSError, TypeError, SyntaxError):
        return True


def _signature_params(obj) -> list[str]:
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    out = []
    for p in sig.parameters.values():
        if p.name in ("self", "cls") or p.name.startswith("_"):
            continue
        if p.kind is p.VAR_POSITIONAL:
            out.append(f"*{p.name}")
        elif p.kind is p.VAR_KEYWORD:
            out.append(f"**{p.name}")
        else:
            out.append(p.name)
    return out


def _documented(doc, sections) -> dict[str, tuple[str, list[str]]]:
    out = {}
    for section in sections:
        for names, type_, desc in doc[section]:
            for n in names.split(","):
                out[n.strip().replace("\\", "")] = (type_, desc)
    return out


def problems(qual: str, obj) -> list[str]:
    """What the entry of ``qual`` lacks (empty: complete)."""
    out: list[str] = []
    if isinstance(obj, property):
        if not (obj.__doc__ or "").strip():
            return ["D: no docstring"]
        return []
    if not (obj.__doc__ or "").strip():
        return ["D: no docstring"]
    if inspect.isclass(obj) and issubclass(obj, BaseException):
        return []
    # (without the members numpydoc would add to a class's Attributes by itself)
    doc = get_doc_object(obj, config={"show_class_members": False})
    validator = Validator(doc)
    is_class = inspect.isclass(obj)
    sections = ["Parameters", "Other Parameters"] + (["Attributes"] if is_class else [])
    documented = _documented(doc, sections)
    wanted = [] if qual.removeprefix("bkwaves._core.") in ENGINES else _signature_params(obj)
    if missing := [p for p in wanted if p not in documented]:
        out.append(f"P: parameters not documented: {missing}")
    if not is_class and (extra := [p for p in documented if p not in wanted]) and wanted:
        out.append(f"P: documented but not parameters: {extra}")
    if not is_class:
        if inspect.isgeneratorfunction(obj):
            if not doc["Yields"]:
                out.append("R: no Yields section")
        elif not doc["Returns"] and _returns_something(qual, obj, validator):
            out.append("R: no Returns section")
    if not any(line.lstrip().startswith(">>>") for line in doc["Examples"]):
        out.append("E: no Examples section with a >>> example")
    entries = list(documented.items()) + [(n or t, (t, d)) for n, t, d in doc["Returns"]]
    no_unit = [
        name
        for name, (type_, desc) in entries
        if name in PHYSICAL and not UNIT.search(" ".join(desc) + " " + type_)
    ]
    if no_unit:
        out.append(f"U: no unit stated for {no_unit}")
    return out


def test_the_walk_finds_the_reference():
    # the walk reaches the top level, every listed module, methods and the compiled core
    for qual in (
        "bkwaves.front_speed",
        "bkwaves.Chain",
        "bkwaves.Chain.run",
        "bkwaves.theory.u_minus",
        "bkwaves.stats.gutenberg_richter",
        "bkwaves._core.front_speed",
        "bkwaves._core.ChainEngine",
        "bkwaves.paper.figure.panels",
    ):
        assert qual in NAMES, qual
    assert "bkwaves._core.ChainEngine.advance" not in NAMES
    assert len(NAMES) > 200


def test_the_checks_can_fail():
    def bare(a, b):
        return a + b

    def documented(u_plus, n):
        """Add.

        Parameters
        ----------
        u_plus : float
            Stress ahead of the front.
        n : int
            A count.

        Returns
        -------
        float
            The sum.

        Examples
        --------
        >>> 1
        1
        """
        return u_plus + n

    assert [p[0] for p in problems("x.bare", bare)] == ["D"]
    assert [p[0] for p in problems("x.documented", documented)] == ["U"]
    documented.__doc__ = documented.__doc__.replace("front.", "front [kg].")
    assert problems("x.documented", documented) == []
    documented.__doc__ = documented.__doc__.replace("front [kg].", "front (dimensionless).")
    assert problems("x.documented", documented) == []
    documented.__doc__ = documented.__doc__.replace(">>> 1\n        1", "")
    assert [p[0] for p in problems("x.documented", documented)] == ["E"]


def test_known_gaps_are_public_names():
    assert set(KNOWN_GAPS) <= set(NAMES), set(KNOWN_GAPS) - set(NAMES)


@pytest.mark.parametrize("qual", sorted(NAMES))
def test_reference_entry(qual):
    found = problems(qual, NAMES[qual])
    if qual in KNOWN_GAPS:
        lacks = "".join(sorted({p[0] for p in found}))
        if lacks != KNOWN_GAPS[qual]:
            pytest.fail(f"{qual} lacks {lacks or 'nothing'} now: update KNOWN_GAPS")
        pytest.xfail(f"known gap ({lacks})")
    assert found == [], f"{qual}: " + "; ".join(found)


def _misaligned_examples(doc: str) -> list[int]:
    """Lines of a doctest block indented unlike the line before (docutils then ends the
    block there and the documentation build, warnings as errors, fails)."""
    lines = inspect.cleandoc(doc).split("\n")
    out = []
    for i in range(len(lines) - 1):
        a, b = lines[i], lines[i + 1]
        sa, sb = a.lstrip(), b.lstrip()
        if sa.startswith(">>>") and sb.startswith((">>>", "...")):
            if len(a) - len(sa) != len(b) - len(sb):
                out.append(i + 2)
    return out


def test_doctest_blocks_are_aligned():
    assert _misaligned_examples("A.\n\n    >>> 1\n  >>> 2\n") == [4]
    bad = {q: n for q, o in NAMES.items() if (n := _misaligned_examples(o.__doc__ or ""))}
    assert bad == {}, f"doctest lines indented unlike the line before: {bad}"
