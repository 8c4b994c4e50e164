"""What the planar models (lattice, free_boundary_2d) share: their ruptures table in the
output units."""

from __future__ import annotations


def convert_ruptures(units, rup, area: str, moment: str):
    """The ruptures table ``rup`` (dimensionless) in the output units: times, places and
    the perimeter as lengths and times; in SI the area in m^2, the moment (slip times an
    area) in m^3 and the mean slip in m; dimensionless, ``area`` and ``moment`` say what
    the columns are (each followed by its scale). Sets the moment magnitude (an empty
    column for an empty table). Returns (rows, units, scales) as ``units.convert_table``
    does."""
    from ..runner import _SCALES
    from ..stats import moment_magnitude

    rows, ru, rs = units.convert_table(
        rup,
        times=("t_start", "t_end", "duration"),
        xs=("x_start", "y_start", "perimeter"),
        moments=("moment",),
    )
    if units.si:  # int slip dA: slip (m) times an area (m^2)
        rows["moment"] = units.x(rows["moment"].to_numpy())
        rows["area"] = units.x(units.x(rows["area"].to_numpy()))
        rows["mean_slip"] = units.slip(rows["mean_slip"].to_numpy())
        ru.update(moment="m3", area="m2", mean_slip="m")
    else:
        ru.update(area="1", mean_slip="1")
        rs["area"] = f"{area}, {_SCALES['x']}"
        rs["moment"] = f"{moment}: {_SCALES['slip']} times (x')^2"
    if len(rows) or "magnitude" not in rows:
        rows["magnitude"] = moment_magnitude(rows["moment"].to_numpy(dtype=float))
    return rows, ru, rs
