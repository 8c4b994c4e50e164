"""Pictures of a run (`bkwaves plot`): what a program can check of each figure."""

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from bkwaves.io import RunWriter, load_tables

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

VARS = {
    "u": ("1", "stress u", "f8"),
    "sliding": ("1", "0 stuck, 1 forward, -1 backward", "i1"),
}
ATTRS = {
    "title": "a test run",
    "model": "chain",
    "params": json.dumps({"gamma": 0.3, "v": 0.001, "dx": 0.1, "beta": float("inf")}),
    "units_system": "dimensionless (paper eq. dimless)",
}


def _run(tmp_path, times, sliding_zero=True):
    """A run with sparse snapshots: u drops between the first two, at t = 27 (the event)."""
    out = tmp_path / "run.nc"
    x = 0.1 * np.arange(50)
    with RunWriter(out, x, VARS, attrs=ATTRS, coord_units=("1", "1")) as w:
        for t in times:
            u = np.full(50, 0.6 if t < 27.0 else -0.1)
            s = np.zeros(50, dtype=int) if sliding_zero else (np.arange(50) % 3 - 1)
            w.append(t, u=u, sliding=s)
        w.write_table(
            "events",
            pd.DataFrame(
                {"t_start": [27.0, 40.0], "nucleation": [10, 30], "kind": ["threshold", "noise"]}
            ),
            units={"t_start": "1"},
        )
    return out


def test_spacetime_draws_nothing_before_it_happened(tmp_path):
    from bkwaves.plot import spacetime

    times = [0.0, 42.8, 50.3, 60.0]
    ds, tables = load_tables(_run(tmp_path, times))
    ax = spacetime(ds, "u", events=tables["events"])
    # the time axis is the run's: not half a snapshot gap before the first one
    assert ax.get_ylim()[0] == pytest.approx(0.0)
    assert ax.get_ylim()[1] == pytest.approx(60.0)
    mesh = ax.collections[0]
    coords = mesh.get_coordinates()  # (nt_edges, nx_edges, 2)
    t_edges = coords[:, 0, 1]
    np.testing.assert_allclose(t_edges, times)
    values = np.asarray(mesh.get_array()).reshape(len(times) - 1, -1)
    # snapshot 0 (u = 0.6) is held on [0, 42.8): the drop at t = 27 is never drawn earlier
    assert np.all(values[0] == 0.6) and np.all(values[1] == -0.1)
    # no "[1]" on dimensionless axes; the title names the parameters with mathtext
    assert "[1]" not in ax.get_xlabel() + ax.get_ylabel()
    title = ax.get_title()
    assert r"$\gamma$ = 0.3" in title and "dimensionless" in title
    # both kinds of nucleation are marked and told apart in a legend
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["nucleation (noise)", "nucleation (threshold)"]
    matplotlib.pyplot.close("all")


def test_plot_run_skips_fields_that_never_change(tmp_path):
    from bkwaves.plot import plot_run

    out = _run(tmp_path, [0.0, 42.8, 50.3, 60.0], sliding_zero=True)
    names = {f.name for f in plot_run(out, tmp_path / "a")}
    assert "run_spacetime_sliding.png" not in names  # all zero at every snapshot
    assert "run_spacetime_u.png" in names
    out2 = tmp_path / "b"
    out2.mkdir()
    run2 = _run(out2, [0.0, 42.8, 50.3, 60.0], sliding_zero=False)
    names2 = {f.name for f in plot_run(run2, out2)}
    assert "run_spacetime_sliding.png" in names2


def test_a_real_chain_run_draws_titled_figures(tmp_path):
    """examples/chain_noise.toml, shortened: its slips figure marks the noise-triggered
    slips and every figure carries the run's parameters."""
    import bkwaves as bk
    from bkwaves.config import load_config
    from bkwaves.plot import plot_run

    example = Path(__file__).resolve().parents[1] / "examples" / "chain_noise.toml"
    cfg = load_config(example).to_dict()
    cfg["run"]["t_end"] = 120.0
    cfg["output"]["path"] = str(tmp_path / "noise.nc")
    from bkwaves.config import parse_config
    from bkwaves.runner import run

    run(parse_config(cfg))
    from figure_checks import figure_problems

    import bkwaves.plot

    problems, save = {}, bkwaves.plot.save

    def checked_save(ax, path):
        problems[Path(path).name] = figure_problems(ax.figure)
        return save(ax, path)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(bkwaves.plot, "save", checked_save)
        files = plot_run(tmp_path / "noise.nc", tmp_path)
    # every picture readable: axis labels, legends, tick labels apart, markers in the axes
    assert sorted(problems) == sorted(f.name for f in files)
    assert not {k: v for k, v in problems.items() if v}, problems
    names = {f.name for f in files}
    assert "noise_slips.png" in names and "noise_spacetime_u.png" in names
    ds, tables = bk.io.load_tables(tmp_path / "noise.nc")
    assert (tables["events"]["kind"] == "noise").any()


def test_sweep_plots_results_not_diagnostics_and_use_the_base_dx(tmp_path):
    import xarray as xr

    from bkwaves import plot

    # a sweep-shaped store: c against u_plus at one dx given in [base]
    u = np.array([0.5, 0.7, 0.9])
    import bkwaves as bk

    c = np.array([bk.front_speed(float(x), dx=0.1, gamma=0.3) for x in u])
    ds = xr.Dataset(
        {
            "c": ("u_plus", c),
            "steadiness": ("u_plus", [1e-9, 2e-9, 3e-9]),
            "blocks": ("u_plus", [300.0, 400.0, 500.0]),
            "status": ("u_plus", [1, 1, 1]),
        },
        coords={"u_plus": u},
        attrs={"sweep": json.dumps({"base": {"gamma": 0.3, "dx": 0.1}}), "title": "t"},
    )
    fig, panels = plot._sweep_figure(ds, "c", ["u_plus"])
    plot._sweep_panel(panels[0], ds["c"], ["u_plus"], "c")
    plot._speed_theory(panels, ds, ds["c"], ["u_plus"])
    right = panels[1]
    # the right panel is not empty: the chain's points and the tip solver at the base dx
    assert len(right.lines) >= 3
    labels = [t.get_text() for t in right.get_legend().get_texts()]
    assert any("0.1" in s and "chain" in s for s in labels)
    assert any("tip solver" in s for s in labels)
    # every series in the left panel is in its legend
    assert len(panels[0].get_legend().get_texts()) == len(panels[0].lines)
    assert "steadiness" in plot._SWEEP_DIAGNOSTICS and "blocks" in plot._SWEEP_DIAGNOSTICS
    matplotlib.pyplot.close("all")


def test_figure_checks_catch_each_fault():
    """The picture checks fail where they should: each fault of a bad figure is named."""
    import matplotlib.pyplot as plt
    from figure_checks import figure_problems

    fig, (good, bad) = plt.subplots(1, 2, figsize=(6, 3))
    good.plot([0, 1], [0, 1], "o", label="a")
    good.set_xlabel("x")
    good.set_ylabel("y")
    assert figure_problems(fig)[0].startswith("axes 1")  # only the bad one is faulted
    bad.plot([0, 1], [0, 1], label="a")
    bad.plot([0, 1], [1, 0], "s", label="b")
    bad.set_xlim(0, 0.5)  # the square at x = 1 falls outside
    bad.set_xticks(np.linspace(0, 0.5, 6), [f"label {k} long" for k in range(6)])
    found = " | ".join(figure_problems(fig))
    for fault in ("without a label", "no legend", "overlapping tick labels on x", "outside"):
        assert fault in found, (fault, found)
    plt.close(fig)


def test_plane_arrival_map_picks_the_largest_complete_rupture():
    """The arrival map's rupture: the largest moment among the complete ones (one still
    open at the run's end has arrivals only up to then), the largest of all when none is
    complete or the catalog has no `complete` column, none without a finite moment."""
    from bkwaves._plot_plane import _largest

    cat = pd.DataFrame(
        {"id": [0, 1, 2, 3], "moment": [5.0, 9.0, 7.0, 1.0], "complete": [True, False, True, True]}
    )
    assert _largest(cat)["id"] == 2
    assert _largest(cat.assign(complete=False))["id"] == 1
    assert _largest(cat.drop(columns="complete"))["id"] == 1
    assert _largest(cat.assign(moment=np.nan)) is None
    assert _largest(cat.iloc[:0]) is None


def _plane(nx=20, ny=16, dx=0.5):
    import xarray as xr

    return xr.Dataset(coords={"x": dx * np.arange(nx), "y": dx * np.arange(ny), "t": [0.0]})


@pytest.mark.parametrize("corner", [(0, 0), (19, 0), (0, 15), (19, 15), (18, 14)])
def test_plane_arrival_map_keeps_the_hypocentre_clear_of_its_legend(corner):
    """A rupture that starts in a corner (session 35: the legend sat in the upper right
    and hid the star of a rupture started at (8.2, 7.4) of a 9.4 x 7.8 lattice): the
    legend goes to the corner farthest from the hypocentre, so the star is not under it."""
    from bkwaves._plot_plane import arrival_map

    ds = _plane()
    i0, j0 = corner
    ii, jj = np.meshgrid(np.arange(20), np.arange(16))
    arr = pd.DataFrame(
        {
            "rupture": 0,
            "x": 0.5 * ii.ravel(),
            "y": 0.5 * jj.ravel(),
            "t": np.hypot(ii - i0, jj - j0).ravel() * 0.4,
        }
    )
    ru = pd.DataFrame({"id": [0], "x_start": [0.5 * i0], "y_start": [0.5 * j0], "moment": [1.0]})
    ax = arrival_map(ds, {"ruptures": ru, "arrivals": arr}, "a test run")
    fig = ax.figure
    fig.canvas.draw()
    box = ax.get_legend().get_window_extent()
    star = ax.transData.transform((0.5 * i0, 0.5 * j0))
    assert not box.expanded(1.2, 1.2).contains(*star), (corner, box, star)
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_plane_catalog_map_markers_are_proportional_to_area_and_one_start_has_no_scale():
    """The catalog map says "marker area ~ slipped area": the markers' areas are (above
    the least one) proportional to the ruptures' areas (they were 8 + 160 sqrt(A/A_max),
    a square root); ruptures all starting at t = 0 get no colour bar (its range was made
    up: -0.1 to 0.1) and the time in the title."""
    import matplotlib.pyplot as plt

    from bkwaves._plot_plane import MIN_MARKER, catalog_map

    ds = _plane()
    area = np.array([0.25, 2.0, 8.0, 50.0])
    ru = pd.DataFrame(
        {
            "id": range(4),
            "x_start": [1.0, 3.0, 5.0, 7.0],
            "y_start": [1.0, 2.0, 3.0, 4.0],
            "area": area,
            "t_start": [0.0, 1.0, 2.0, 4.0],
        }
    )
    ax = catalog_map(ds, {"ruptures": ru}, "a test run")
    sizes = ax.collections[0].get_sizes()
    big = sizes > MIN_MARKER
    assert big.sum() >= 2
    ratio = sizes[big] / area[big]
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-12)
    assert len(ax.figure.axes) == 2  # the colour bar of the start times
    plt.close(ax.figure)
    one = ru.iloc[:1].assign(t_start=0.0)
    ax = catalog_map(ds, {"ruptures": one}, "a test run")
    assert len(ax.figure.axes) == 1
    assert "all starting at t = 0" in ax.get_title()
    plt.close(ax.figure)
