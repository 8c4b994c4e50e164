"""Physical examples from the paper.

:func:`bristol_board` is the example of Sec. VI: a Bristol board of thickness
h = 2 mm on the same material (Heslot et al. 1994) with memory length a = 1 um,
density 1.2 g/cm^3, sound speed 4000 m/s, mu_r = 0.37, mu_s = 0.31, pressure
p = 2e6 Pa and alpha = 6.7e-6 kg/s. The paper rounds k_c to 3.8e7 N/m before
computing k_p = k_c (pi a / 2h)^2 = 23 N/m; ``paper_rounding=False`` keeps every
digit (k_c = 3.84e7, k_p = 23.7, gamma = 0.444 instead of 0.45): see docs/theory.md.
"""

from __future__ import annotations

import math

from .params import Params

__all__ = ["BRISTOL_BOARD", "bristol_board"]

#: Material data of the Bristol-board example (SI units).
BRISTOL_BOARD = {
    "thickness": 2e-3,
    "spacing": 1e-6,
    "density": 1.2e3,
    "sound_speed": 4000.0,
    "mu_static": 0.37,
    "mu_kinetic": 0.31,
    "pressure": 2e6,
    "alpha": 6.7e-6,
    "V_f": 1e-5,
}


def bristol_board(V: float = 1e-6, *, paper_rounding: bool = True) -> Params:
    """Params of the paper's Bristol-board example at loader speed V [m/s].

    Parameters
    ----------
    V : float, default 1e-6
        Loader speed [m/s].
    paper_rounding : bool, default True
        Round m and k_c as the paper does (k_c = 3.8e7 N/m); False keeps every digit.

    Returns
    -------
    bkwaves.Params
        gamma, v, dx and beta (dimensionless) with ``units``, the SI description.

    Examples
    --------
    The paper's numbers (Sec. VI): k_p = 23 N/m and gamma = 0.45:

    >>> import bkwaves as bk
    >>> p = bk.presets.bristol_board()
    >>> round(p.units.k_p), round(p.gamma, 2)
    (23, 0.45)
    >>> round(bk.presets.bristol_board(paper_rounding=False).gamma, 3)
    0.444
    """
    d = BRISTOL_BOARD
    a, h = d["spacing"], d["thickness"]
    mass = d["density"] * a * a * h
    k_c = mass * d["sound_speed"] ** 2 / a**2
    if paper_rounding:
        mass = float(f"{mass:.1e}")
        k_c = float(f"{k_c:.1e}")
    k_p = k_c * (math.pi * a / (2.0 * h)) ** 2
    area = a * a * d["pressure"]
    return Params.from_physical(
        mass=mass,
        k_c=k_c,
        k_p=k_p,
        f_static=d["mu_static"] * area,
        f_kinetic=d["mu_kinetic"] * area,
        alpha=d["alpha"],
        V=V,
        spacing=a,
    )
