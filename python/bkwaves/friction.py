"""Friction laws of the chain, read from the core's registry (nothing is repeated here).

>>> import bkwaves as bk
>>> sorted(bk.friction.LAWS)                      # the registered laws
['coulomb', ...]
>>> bk.friction.LAWS["coulomb"].params[0].name    # its parameter table
'gamma'
>>> p = bk.Params(gamma=0.3, v=0.0, dx=0.1, friction_law=bk.friction.law("coulomb"))

Every law declares its parameters once, in its Rust file (name, allowed range, default,
doc); validation, messages, checkpoints, output attributes, the TOML ``[friction]`` table
and the docs read that table. A parameter that is also a field of :class:`bkwaves.Params`
(``gamma``, ``beta``) is taken from the Params; the others are given to :func:`law`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from . import _core
from . import _validate as V

__all__ = ["DEFAULT", "LAWS", "Law", "LawInfo", "ParamInfo", "law", "markdown"]


@dataclass(frozen=True)
class ParamInfo:
    """One row of a law's parameter table."""

    name: str
    lo: float
    lo_closed: bool
    hi: float
    hi_closed: bool
    default: float | None
    doc: str
    allowed: str

    @property
    def required(self) -> bool:
        return self.default is None


@dataclass(frozen=True)
class LawInfo:
    """A registered friction law: name, one line of doc and its parameter table."""

    name: str
    doc: str
    params: tuple[ParamInfo, ...]

    def param(self, name: str) -> ParamInfo | None:
        return next((p for p in self.params if p.name == name), None)


#: The registered friction laws by name (the core's registry, in its order).
LAWS: dict[str, LawInfo] = {
    d["name"]: LawInfo(d["name"], d["doc"], tuple(ParamInfo(**p) for p in d["params"]))
    for d in _core.friction_laws()
}
#: The default law's name.
DEFAULT: str = _core.defaults()["law"]


@dataclass(frozen=True)
class Law:
    """A friction law chosen by name with some of its parameters (checked against its
    table when built; the rest come from :class:`bkwaves.Params` or their defaults)."""

    name: str = DEFAULT
    params: tuple[tuple[str, float], ...] = ()

    def __post_init__(self):
        if not isinstance(self.name, str):  # (an unknown name: the core lists the known)
            V._fail("name", self.name, "a law's name, one of " + ", ".join(LAWS))
        given = {k: V.number(k, x) for k, x in dict(self.params).items()}
        checked = _core.friction_resolve(self.name, given, partial=True)
        object.__setattr__(self, "params", tuple(checked.items()))

    def values(self, fallback=None) -> dict[str, float]:
        """Every parameter of the law (table order): the given ones, else the attribute
        of ``fallback`` (a Params) of that name, else the default; validated by the core."""
        given = dict(self.params)
        for p in LAWS[self.name].params:
            if p.name not in given and fallback is not None and hasattr(fallback, p.name):
                given[p.name] = getattr(fallback, p.name)
        return _core.friction_resolve(self.name, given)


def law(name: str = DEFAULT, **params: float) -> Law:
    """The friction law ``name`` with the given parameters; an unknown law or parameter
    raises :class:`bkwaves.ParameterError` naming the known ones."""
    return Law(name, tuple(params.items()))


def _num(x) -> str:
    if x is None:
        return "required"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return f"{x:g}"


def markdown() -> str:
    """The laws and their parameter tables as Markdown (docs/chain.md embeds this text;
    a test keeps the two equal)."""
    out = []
    for info in LAWS.values():
        out.append(f"### `{info.name}`\n\n{info.doc}.\n")
        out.append("| parameter | allowed | default | meaning |")
        out.append("|---|---|---|---|")
        for p in info.params:
            out.append(f"| `{p.name}` | {p.allowed} | {_num(p.default)} | {p.doc} |")
        out.append("")
    return "\n".join(out)
