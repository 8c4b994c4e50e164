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
    """One row of a law's parameter table (the core's, ``_core.friction_laws()``).

    Parameters
    ----------
    name : str
        The parameter's name.
    lo, hi : float
        Its allowed range (dimensionless, in the paper's units, as the parameter).
    lo_closed, hi_closed : bool
        Whether the range includes lo, hi.
    default : float or None
        Its default (dimensionless); None: required.
    doc : str
        What it is, with its unit.
    allowed : str
        The range in words, as error messages say it.

    Examples
    --------
    >>> import bkwaves as bk
    >>> beta = bk.friction.LAWS["coulomb"].param("beta")
    >>> beta.allowed, beta.default, beta.required
    ('0 <= beta <= inf', inf, False)
    """

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
        """Whether the parameter has no default."""
        return self.default is None


@dataclass(frozen=True)
class LawInfo:
    """A registered friction law: name, one line of doc and its parameter table.

    Parameters
    ----------
    name : str
        The law's name (``LAWS``).
    doc : str
        One line on the law.
    params : tuple of ParamInfo
        Its parameter table, in order.

    Examples
    --------
    >>> import bkwaves as bk
    >>> [p.name for p in bk.friction.LAWS["velocity_weakening"].params]
    ['gamma', 'v_f', 'beta']
    """

    name: str
    doc: str
    params: tuple[ParamInfo, ...]

    def param(self, name: str) -> ParamInfo | None:
        """The row of parameter ``name``, or None if the law has none of that name.

        Parameters
        ----------
        name : str
            The parameter's name.

        Returns
        -------
        ParamInfo or None
            Its row.

        Examples
        --------
        >>> import bkwaves as bk
        >>> bk.friction.LAWS["coulomb"].param("v_f") is None
        True
        """
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
    table when built; the rest come from :class:`bkwaves.Params` or their defaults).

    Parameters
    ----------
    name : str, default "coulomb"
        The law's name (``LAWS``).
    params : tuple of (str, float)
        Some of its parameters by name (dimensionless, in the paper's units: ``v_f`` is
        V_f sqrt(k_p m)/(f_r - f_s)).

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.friction.Law("velocity_weakening", (("v_f", 0.5),)).params
    (('v_f', 0.5),)
    >>> bk.friction.Law("velocity_weakening", (("v_f", -1.0),))
    Traceback (most recent call last):
    ...
    bkwaves._core.ParameterError: invalid v_f = -1: allowed 0 < v_f < inf
    """

    name: str = DEFAULT
    params: tuple[tuple[str, float], ...] = ()

    def __post_init__(self):
        if not isinstance(self.name, str):  # (an unknown name: the core lists the known)
            V._fail("name", self.name, "a law's name, one of " + ", ".join(LAWS))
        given = {k: V.number(k, x) for k, x in dict(self.params).items()}
        checked = _core.friction_resolve(self.name, given, partial=True)
        object.__setattr__(self, "params", tuple(checked.items()))

    def values(self, fallback=None) -> dict[str, float]:
        """Every parameter of the law (table order), validated by the core.

        Each is the given one, else the attribute of ``fallback`` of that name, else the
        default.

        Parameters
        ----------
        fallback : bkwaves.Params, optional
            Where the parameters not given come from (``gamma``, ``beta``).

        Returns
        -------
        dict
            Name -> value (dimensionless).

        Examples
        --------
        >>> import bkwaves as bk
        >>> vw = bk.friction.law("velocity_weakening", v_f=0.5)
        >>> vw.values(bk.Params(gamma=0.3, v=0.0, dx=0.1))
        {'gamma': 0.3, 'v_f': 0.5, 'beta': inf}
        """
        given = dict(self.params)
        for p in LAWS[self.name].params:
            if p.name not in given and fallback is not None and hasattr(fallback, p.name):
                given[p.name] = getattr(fallback, p.name)
        return _core.friction_resolve(self.name, given)


def law(name: str = DEFAULT, **params: float) -> Law:
    """The friction law ``name`` with the given parameters.

    Parameters
    ----------
    name : str, default "coulomb"
        The law's name (``LAWS``).
    **params : float
        Some of its parameters (dimensionless, in the paper's units).

    Returns
    -------
    Law
        The law, its parameters checked against its table.

    Raises
    ------
    bkwaves.ParameterError
        An unknown law or parameter (the message names the known ones), or a value out of
        range.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.friction.law("velocity_weakening", v_f=0.5)
    Law(name='velocity_weakening', params=(('v_f', 0.5),))
    """
    return Law(name, tuple(params.items()))


def _num(x) -> str:
    if x is None:
        return "required"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return f"{x:g}"


def markdown() -> str:
    """The laws and their parameter tables as Markdown.

    docs/chain.md embeds this text; a test keeps the two equal.

    Returns
    -------
    str
        One section per law with its table.

    Examples
    --------
    >>> import bkwaves as bk
    >>> print(bk.friction.markdown().splitlines()[0])
    ### `coulomb`
    """
    out = []
    for info in LAWS.values():
        out.append(f"### `{info.name}`\n\n{info.doc}.\n")
        out.append("| parameter | allowed | default | meaning |")
        out.append("|---|---|---|---|")
        for p in info.params:
            out.append(f"| `{p.name}` | {p.allowed} | {_num(p.default)} | {p.doc} |")
        out.append("")
    return "\n".join(out)
