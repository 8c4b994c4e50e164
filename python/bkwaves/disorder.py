"""Quenched disorder: per-block properties drawn from a distribution with a seed.

>>> import bkwaves as bk
>>> th = bk.disorder.draw("uniform", 400, mean=1.0, spread=0.1, seed=3)
>>> ch = bk.Chain(400, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6, threshold=th)

A property (``threshold``, ``mass``, ``loader``, ``coupling``: ``bk.chain.PROPERTIES``) is
a scalar, an array (one value per block; ``coupling`` one per bond) or drawn here. In a
TOML config the ``[disorder]`` table gives each property as a number, an array or a table
``{distribution = "uniform", mean = 1.0, spread = 0.1}`` drawn with the config's ``seed``
(each property from its own stream, so adding one does not change the others).
"""

from __future__ import annotations

import numpy as np

from . import _validate as V

__all__ = ["DISTRIBUTIONS", "draw", "property_seed"]

#: Distributions by name: what ``mean`` and ``spread`` mean for each.
DISTRIBUTIONS = {
    "uniform": "uniform on [mean - spread, mean + spread] (0 <= spread < mean)",
    "normal": "normal with this mean and standard deviation spread (every value must be > 0)",
    "lognormal": "log-normal with this mean and log-standard-deviation spread",
}


def draw(distribution: str, n: int, *, mean: float = 1.0, spread: float, seed) -> np.ndarray:
    """n values drawn from ``distribution`` (``DISTRIBUTIONS``) with ``numpy``'s default
    generator seeded by ``seed`` (an int or a sequence of ints)."""
    if distribution not in DISTRIBUTIONS:
        V._fail("distribution", distribution, "one of " + ", ".join(DISTRIBUTIONS))
    mean = V.number("mean", mean, lo=0.0, lo_open=True)
    spread = V.number("spread", spread, lo=0.0)
    rng = np.random.default_rng(seed)
    if distribution == "uniform":
        if spread >= mean:
            V._fail("spread", spread, f"0 <= spread < mean = {mean} (positive values)")
        return rng.uniform(mean - spread, mean + spread, n)
    if distribution == "normal":
        return mean + spread * rng.standard_normal(n)
    return mean * np.exp(spread * rng.standard_normal(n) - 0.5 * spread**2)


def property_seed(seed: int, name: str) -> list[int]:
    """The seed of property ``name`` in a config with ``seed``: its own stream."""
    from .chain import PROPERTIES

    return [int(seed), 1 + PROPERTIES.index(name)]
