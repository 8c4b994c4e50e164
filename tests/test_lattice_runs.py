"""The lattice model run from a config (issue 25): per-bond springs in [disorder], the
ruptures table, the limits on an event's duration and the initial file's shape.

Each capability is checked against an exact reduction or an independent computation:
uniform bonds given explicitly are the uniform lattice bit for bit, a lattice without y
bonds is ny chains, a config's bonds are those of bk.Lattice built by hand, and the
ruptures of a hand-built slip record are counted by hand.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves import _models as models
from bkwaves.config import parse_config

LOADING = {
    "model": "lattice",
    "seed": 5,
    "params": {"gamma": 0.45, "v": 0.01, "dx": 0.2},
    "domain": {"shape": [16, 12], "boundary": ["free", "periodic"]},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 0.8},
    "run": {"t_end": 40.0},
    "output": {"snapshot_every": 10.0},
}


def _with(doc: dict, path: str, value) -> dict:
    """``doc`` with the key at ``path`` (a.b.c) set (None: removed)."""
    out = copy.deepcopy(doc)
    *head, last = path.split(".")
    d = out
    for k in head:
        d = d.setdefault(k, {})
    if value is None:
        d.pop(last, None)
    else:
        d[last] = value
    return out


def _final_u(res) -> np.ndarray:
    return res.snapshots["u"].values[-1]


# --- [disorder] coupling_x, coupling_y -----------------------------------------------------
@pytest.mark.parametrize(
    "boundary", [["free", "periodic"], ["fixed", "free"], ["periodic", "fixed"]]
)
def test_uniform_bonds_given_explicitly_are_the_uniform_lattice_bit_for_bit(boundary):
    doc = _with(LOADING, "domain.boundary", boundary)
    nx, ny = doc["domain"]["shape"]
    shapes = models.lattice.bonds((nx, ny), boundary)
    ones = {k: [1.0] * (r * c) for k, (r, c) in shapes.items()}
    cfg = parse_config(_with(doc, "disorder", ones))
    # the springs reach the engine as arrays (not the uniform default)
    la = models.get("lattice").build(cfg)
    assert la.properties["coupling"] is not None and la.properties["coupling_y"] is not None
    assert la.properties["coupling"].size == shapes["coupling_x"][0] * shapes["coupling_x"][1]
    ref, res = bk.run(doc, snapshots=True), bk.run(cfg, snapshots=True)
    assert len(ref.tables["slips"]) > 50  # blocks slipped and stuck again
    np.testing.assert_array_equal(_final_u(res), _final_u(ref))
    for col in ("t_start", "t_end", "slip", "block"):
        np.testing.assert_array_equal(res.tables["slips"][col], ref.tables["slips"][col])


def test_config_bonds_are_bk_lattice_bonds():
    """A drawn k_x and a smooth random k_y from the config are what bk.disorder draws on
    the bonds' grids (bit for bit through the run)."""
    doc = _with(LOADING, "domain.boundary", ["periodic", "free"])
    doc["disorder"] = {
        "coupling_x": {"distribution": "uniform", "mean": 1.0, "spread": 0.3},
        "coupling_y": {"mean": 1.0, "amplitude": 0.5, "correlation_length": 0.6},
    }
    cfg = parse_config(doc)
    assert parse_config(cfg.to_dict()) == cfg
    res = bk.run(cfg, snapshots=True)
    nx, ny = 16, 12
    kx = bk.disorder.draw(
        "uniform", ny * nx, mean=1.0, spread=0.3, seed=bk.disorder.property_seed(5, "coupling_x")
    ).reshape(ny, nx)  # periodic along x: nx bonds a row
    seed_y = bk.disorder.property_seed(5, "coupling_y")
    ky = 1.0 + 0.5 * bk.disorder.smooth_field(
        (ny - 1, nx), (0.2, 0.2), 0.6, periodic=(False, True), seed=seed_y
    )
    assert seed_y != bk.disorder.property_seed(5, "coupling_x")
    assert kx.std() > 0.05 and ky.std() > 0.05
    p = bk.Params(gamma=0.45, v=0.01, dx=0.2)
    u0 = bk.config.initial_state(cfg)
    la = bk.Lattice((nx, ny), p, u0=u0, boundary=("periodic", "free"), coupling=(kx, ky))
    ref = la.run(t_end=40.0, snapshots=[0.0, 10.0, 20.0, 30.0, 40.0], progress=False)
    np.testing.assert_array_equal(res.tables["slips"]["t_start"], ref.slips["t_start"])
    np.testing.assert_array_equal(_final_u(res), ref.u)
    # and the springs matter: the uniform lattice differs
    assert not np.array_equal(_final_u(bk.run(_with(doc, "disorder", None), snapshots=True)), ref.u)


@pytest.mark.parametrize("boundary", ["free", "periodic"])
def test_a_lattice_without_y_bonds_is_ny_chains(tmp_path, boundary):
    """coupling_y = 0 through the config route: each row is the chain config of its own
    initial stress. Not to the bit (the lattice cuts its steps at every row's events, a
    chain at its own) but to the integrator's accuracy, while a chain given another row's
    stress is far away."""
    doc = _with(LOADING, "domain.boundary", [boundary, "free"])
    doc = _with(doc, "disorder", {"coupling_y": 0.0})
    cfg = parse_config(doc)
    u0 = bk.config.initial_state(cfg)
    lat = _final_u(bk.run(cfg, snapshots=True))
    nx, ny = 16, 12
    errs, other = [], []
    for j in range(ny):
        np.savetxt(tmp_path / f"row{j}.txt", u0[j])
    for j in range(ny):
        chain = {
            "model": "chain",
            "params": LOADING["params"],
            "domain": {"blocks": nx, "boundary": boundary},
            "initial": {"kind": "file", "path": str(tmp_path / f"row{j}.txt")},
            "run": LOADING["run"],
            "output": LOADING["output"],
        }
        u = _final_u(bk.run(chain, snapshots=True))
        errs.append(np.max(np.abs(lat[j] - u)) / np.max(np.abs(u)))
        other.append(np.max(np.abs(lat[(j + 1) % ny] - u)) / np.max(np.abs(u)))
    assert max(errs) < 1e-4, errs
    assert min(other) > 1e-2, other


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (
            {"coupling_x": [1.0] * 5},
            r"disorder\.coupling_x: 5 values; expected ny x \(bonds of a row: nx - 1 free, "
            r"nx \+ 1 fixed, nx periodic\) = 18 x 23 = 414 \(row after row\)",
        ),
        ({"coupling_y": -0.5}, r"disorder\.coupling_y: invalid coupling_y = -0\.5: allowed "),
        (
            {"coupling_y": [1.0] * 300 + [-1.0] + [1.0] * 107},
            r"disorder\.coupling_y\[300\]: invalid value -1\.0: allowed coupling_y >= 0",
        ),
        ({"coupling": 1.0}, r"disorder\.coupling: unknown key; valid keys here: .*coupling_x"),
        ({"threshold": 0.0}, r"disorder\.threshold: invalid threshold = 0(\.0)?: allowed"),
        (
            {"coupling_x": {"mean": 1.0, "amplitude": 1.0, "correlation_length": 0.3}},
            r"disorder\.coupling_x\.amplitude: invalid amplitude = 1\.0: allowed 0 <= ",
        ),
    ],
)
def test_bond_errors_name_the_key_and_the_range(value, message):
    doc = {
        "model": "lattice",
        "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
        "domain": {"shape": [24, 18]},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [{"time": 0.0, "block": [12, 9], "kind": "kick", "velocity": 2.0}],
        "run": {"t_end": 4.0},
        "disorder": value,
    }
    with pytest.raises(bk.ParameterError, match=message) as e:
        parse_config(doc)
    assert "\n" not in str(e.value)


# --- the ruptures table --------------------------------------------------------------------
def _slips(rows):
    import pandas as pd

    cols = ("event", "block", "t_start", "t_end", "slip", "u_start", "kind")
    return pd.DataFrame(rows, columns=cols)


def _crofton(dx, dy, n_x, n_y, n_diag):
    """The Crofton perimeter from crossings counted by hand (docs/lattice.md)."""
    theta = math.atan2(dy, dx)
    diag = dx * dy / math.hypot(dx, dy)
    return 0.5 * (
        theta * dy * n_x + (0.5 * math.pi - theta) * dx * n_y + 0.25 * math.pi * diag * n_diag
    )


def test_ruptures_of_a_hand_built_record():
    """Two events on a 5 x 4 free lattice (block k = i + 5 j), ruptures found by hand:
    event 0 holds a kicked rupture A (a re-slip included) and a noise rupture B that
    grows beside it; event 1 a threshold slip C and a line of two blocks kicked at once
    (D), which a later slip next to both C and D joins (D's is the later start)."""
    from bkwaves._lattice_ruptures import lattice_ruptures

    nx, ny, dx, dy = 5, 4, 0.1, 0.2

    def b(i, j):
        return i + nx * j

    rows = [
        (0, b(1, 1), 0.0, 1.0, 0.5, 0.9, "trigger"),  # A
        (0, b(2, 1), 0.1, 1.1, 0.4, 0.8, "threshold"),  # A (from (1, 1))
        (0, b(2, 2), 0.2, 1.2, 0.3, 0.8, "threshold"),  # A (from (2, 1))
        (0, b(4, 3), 0.15, 1.0, 0.2, 0.95, "noise"),  # B
        (0, b(3, 3), 0.25, 1.3, 0.1, 0.8, "threshold"),  # B (from (4, 3))
        (0, b(3, 2), 0.3, 2.0, 0.1, 0.8, "threshold"),  # B: (3, 3) at 0.25 after (2, 2) at 0.2
        (0, b(1, 1), 0.4, 1.5, 0.05, 0.7, "threshold"),  # A again: its neighbour (2, 1)
        (1, b(0, 0), 5.0, 5.5, 0.2, 1.0, "threshold"),  # C
        (1, b(3, 0), 6.0, 7.0, 0.3, 0.7, "trigger"),  # D
        (1, b(2, 0), 6.0, 7.5, 0.3, 0.7, "trigger"),  # D (kicked with (3, 0))
        (1, b(1, 0), 6.5, 7.2, 0.1, 0.7, "threshold"),  # D: (2, 0) at 6 after (0, 0) at 5
    ]
    ru = lattice_ruptures(_slips(rows), nx, ny, dx, dy, ("free", "free"))
    assert list(ru.columns) == list(bkwaves_columns())
    assert ru["t_start"].tolist() == [0.0, 0.15, 5.0, 6.0]
    assert ru["kind"].tolist() == ["trigger", "noise", "threshold", "trigger"]
    assert ru["spontaneous"].tolist() == [False, True, False, False]
    assert ru["event"].tolist() == [0, 0, 1, 1]
    assert ru["n_blocks"].tolist() == [3, 3, 1, 3]
    assert ru[["i_start", "j_start"]].values.tolist() == [[1, 1], [4, 3], [0, 0], [2, 0]]
    np.testing.assert_allclose(ru["x_start"], [0.1, 0.4, 0.0, 0.2])
    np.testing.assert_allclose(ru["y_start"], [0.2, 0.6, 0.0, 0.0])
    np.testing.assert_allclose(ru["t_end"], [1.5, 2.0, 5.5, 7.5])
    np.testing.assert_allclose(ru["duration"], [1.5, 1.85, 0.5, 1.5])
    np.testing.assert_allclose(ru["area"], np.array([3, 3, 1, 3]) * dx * dy)
    np.testing.assert_allclose(ru["moment"], np.array([1.25, 0.4, 0.2, 0.7]) * dx * dy)
    np.testing.assert_allclose(ru["mean_slip"], ru["moment"] / ru["area"])
    np.testing.assert_allclose(ru["magnitude"], bk.stats.moment_magnitude(ru["moment"]))
    assert ru["complete"].all()
    # C, alone in the corner of a free lattice: one crossing along x, one along y, one
    # diagonal (the other neighbours lie beyond the free sides)
    assert ru.loc[2, "perimeter"] == pytest.approx(_crofton(dx, dy, 1, 1, 1), rel=1e-14)
    # D, the blocks (1, 0), (2, 0), (3, 0) along the free bottom edge: x crossings at both
    # ends, three y crossings above, diagonals: (0, 1) and (4, 1) once, (1..3, 1) twice
    # less the ones inside: (1,0)->(2,1), (2,0)->(1,1), (2,0)->(3,1), (3,0)->(2,1) -> 2 + 4
    assert ru.loc[3, "perimeter"] == pytest.approx(_crofton(dx, dy, 2, 3, 6), rel=1e-14)
    # a slip still running at the end: its rupture is incomplete, its slip not counted
    cut = _slips([*rows[:7], (0, b(0, 1), 0.45, math.nan, math.nan, 0.7, "threshold")])
    ru = lattice_ruptures(cut, nx, ny, dx, dy, ("free", "free"))
    assert ru["complete"].tolist() == [False, True]
    assert np.isnan(ru.loc[0, "t_end"]) and ru.loc[0, "n_blocks"] == 4
    np.testing.assert_allclose(ru["moment"], np.array([1.25, 0.4]) * dx * dy)


def bkwaves_columns():
    from bkwaves._lattice_ruptures import COLUMNS

    return COLUMNS


def test_rupture_links_wrap_across_periodic_sides():
    """On a lattice periodic in x, block (0, 0) neighbours (nx - 1, 0): a slip there
    joins the rupture across the side; on a free lattice it starts one."""
    from bkwaves._lattice_ruptures import lattice_ruptures

    rows = [(0, 4, 0.0, 1.0, 0.5, 0.9, "trigger"), (0, 0, 0.2, 1.0, 0.5, 0.9, "threshold")]
    per = lattice_ruptures(_slips(rows), 5, 2, 0.1, 0.1, ("periodic", "free"))
    free = lattice_ruptures(_slips(rows), 5, 2, 0.1, 0.1, ("free", "free"))
    assert len(per) == 1 and len(free) == 2
    # a single block of a doubly periodic lattice: every one of its 8 neighbours is out
    one = lattice_ruptures(_slips(rows[:1]), 5, 4, 0.1, 0.2, ("periodic", "periodic"))
    assert one.loc[0, "perimeter"] == pytest.approx(_crofton(0.1, 0.2, 2, 2, 4), rel=1e-14)


@pytest.mark.parametrize("dy", [0.1, 0.15])
def test_rupture_perimeter_of_a_disc_is_its_circumference(dy):
    """The Crofton estimate of the blocks within R of a centre, a circle in the plane
    (x, y) = (i dx, j dy) (an ellipse in blocks when dy != dx): 2 pi R to 2 %."""
    from bkwaves._lattice_ruptures import perimeter

    dx, nx, ny = 0.1, 120, int(round(12.0 / dy))
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    for radius in (2.0, 5.0):
        inside = np.hypot((i - nx // 2) * dx, (j - ny // 2) * dy) <= radius
        blk = (i + nx * j)[inside]
        p = perimeter(np.zeros(blk.size, dtype=np.int64), blk, 1, nx, ny, dx, dy, (False, False))
        assert p[0] == pytest.approx(2 * math.pi * radius, rel=0.02)


def test_lattice_runs_write_ruptures_and_stats_reads_them(tmp_path):
    """Through the config route: two kicks far apart in one event are two ruptures whose
    moments add up to the event's; a disc kicked at once is one rupture; bkwaves stats
    and the run summary use the ruptures, as for the planar free boundary model."""
    import json
    import subprocess
    import sys

    doc = {
        "model": "lattice",
        "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
        "domain": {"shape": [24, 18], "dy": 0.12},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [
            {"time": 0.0, "block": [2, 2], "kind": "kick", "velocity": 2.0},
            {"time": 0.1, "disc": [[19, 13], 0.35], "kind": "kick", "velocity": 2.0},
        ],
        "run": {"t_end": 6.0},
    }
    out = tmp_path / "la.nc"
    res = bk.run(doc, out)
    ev, ru = res.tables["events"], res.tables["ruptures"]
    assert len(ev) == 1 and len(ru) == 2 and ru["complete"].all()
    assert ru["moment"].sum() == pytest.approx(ev.loc[0, "moment"], rel=1e-12)
    # every block slipped; where the two met, blocks slipped again for the other one
    assert ev.loc[0, "n_blocks"] == 24 * 18 <= ru["n_blocks"].sum() < 1.2 * 24 * 18
    assert ru["n_blocks"].min() > 0.3 * 24 * 18
    assert ru[["i_start", "j_start"]].values.tolist()[0] == [2, 2]
    assert ru.loc[1, "kind"] == "trigger" and ru.loc[1, "t_start"] == 0.1
    assert res.summary["statistics_catalog"] == "ruptures" and res.summary["n_ruptures"] == 2
    # bk.Lattice by hand: its result's ruptures() is the same table, bit for bit
    la = bk.Lattice((24, 18), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7, dy=0.12)
    la.kick((2, 2), -2.0, 0.0).kick({"disc": ((19, 13), 0.35)}, -2.0, 0.1)
    by_hand = la.run(t_end=6.0, progress=False).ruptures()
    pd_testing = pytest.importorskip("pandas.testing")
    pd_testing.assert_frame_equal(by_hand, ru, check_dtype=False)
    _, tables = bk.io.load_tables(out)
    pd_testing.assert_frame_equal(tables["ruptures"], ru, check_dtype=False)
    assert tables["ruptures"].attrs["units"]["area"] == "1"
    stats = subprocess.run(
        [sys.executable, "-m", "bkwaves", "stats", str(out), "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    rep = json.loads(stats.stdout)
    assert rep["catalog"] == "ruptures" and rep["ruptures"] == 2
    assert rep["largest"]["moment"] == pytest.approx(ru["moment"].max(), rel=1e-12)
    assert {"y_start", "area", "perimeter"} <= set(rep["largest"])


def test_lattice_arrivals_are_per_rupture_and_plot_draws_the_largest(tmp_path):
    """Two ruptures in one event: the arrivals table holds the first slip of each block in
    each rupture (its rows per rupture are the ruptures table's n_blocks), and
    bkwaves plot's arrival map is the largest rupture's (its blocks only), not the
    event's."""
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    from bkwaves import _plot_plane

    doc = {
        "model": "lattice",
        "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
        "domain": {"shape": [24, 18]},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [
            {"time": 0.0, "block": [3, 3], "kind": "kick", "velocity": 2.0},
            {"time": 0.6, "block": [20, 14], "kind": "kick", "velocity": 2.0},
        ],
        "run": {"t_end": 6.0},
        "output": {"arrivals": True},
    }
    out = tmp_path / "la.nc"
    res = bk.run(doc, out)
    ev, ru, arr = res.tables["events"], res.tables["ruptures"], res.tables["arrivals"]
    assert len(ev) == 1 and len(ru) == 2 and ru["id"].tolist() == [0, 1]
    counts = arr.groupby("rupture").size()
    np.testing.assert_array_equal(counts.loc[ru["id"]].to_numpy(), ru["n_blocks"].to_numpy())
    assert not arr.duplicated(["rupture", "i", "j"]).any()
    assert len(arr.groupby(["i", "j"])) == 24 * 18  # every block, each in its ruptures
    # the first rupture started 0.6 earlier and is the larger: the map draws its blocks
    big = int(ru.loc[ru["moment"].idxmax(), "id"])
    assert big == 0
    ds, tables = bk.io.load_tables(out)
    ax = _plot_plane.arrival_map(ds, tables, "t")
    assert ax.get_title().endswith(f"(rupture {big})")
    mine = tables["arrivals"][tables["arrivals"]["rupture"] == big]
    grid = _plot_plane._grid_of(ds, mine, "t")
    assert np.isfinite(grid).sum() == ru.loc[big, "n_blocks"] < 24 * 18
    # without the arrivals table the map falls back to the largest event
    del tables["arrivals"]
    ax = _plot_plane.arrival_map(ds, tables, "t")
    assert ax.get_title().endswith("(event 0)")


# --- an event's duration, the initial file --------------------------------------------------
def test_the_default_duration_bound_stops_creep_and_spares_ruptures():
    """gamma >= 1: sliding blocks never re-stick, the event never ends; the default bound
    (100 crossings of the longer side, + 1) stops it there, after about bound/h steps,
    with everything kept. A rupture across the same lattice at gamma = 0.45 ends after
    ~2 crossings, far below the bound (docs/lattice.md, "An event's duration")."""
    n, dx = 12, 0.1
    bound = bk.lattice.default_max_event_duration((n, n), dx)
    assert bound == 100.0 * (n * dx + 1.0)
    creep = bk.Lattice((n, n), bk.Params(gamma=1.5, v=0.0, dx=dx), u0=0.7)
    assert creep._max_event_duration() == bound
    creep.kick((6, 6), -2.0)
    with pytest.warns(bk.chain.RunawayEventWarning, match="max_event_duration"):
        res = creep.run(t_end=1e9, progress=False)
    assert res.stop == "long_event" and bound <= res.t < 1.01 * bound
    steps = res.counters["steps"]
    assert bound / (0.05 * dx) <= steps < 1.1 * bound / (0.05 * dx)
    # every block slipped, and every one is still sliding (creeping) at the end
    assert res.slips["block"].nunique() == n * n == res.slips["t_end"].isna().sum()
    rupture = bk.Lattice((n, n), bk.Params(gamma=0.45, v=0.0, dx=dx), u0=0.7).kick((6, 6), -2.0)
    r = rupture.run(t_end=1e9, max_events=1, progress=False)
    assert r.stop == "events" and r.catalog["n_blocks"].iloc[0] == n * n
    assert r.catalog["duration"].iloc[0] < 0.05 * bound
    # the config route: the same bound, the run stopped and kept, the key named
    doc = {
        "model": "lattice",
        "params": {"gamma": 1.5, "v": 0.0, "dx": dx},
        "domain": {"shape": [n, n]},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [{"time": 0.0, "block": [6, 6], "kind": "kick", "velocity": 2.0}],
        "run": {"max_events": 1},
    }
    cfg = parse_config(doc)
    assert models.get("lattice").default_max_event_duration(cfg) == bound
    summary = bk.runner.run(cfg, None)
    assert summary.extra["stop"] == "long_event" and bound <= summary.t < 1.01 * bound
    assert "run.max_event_duration" in summary.extra["message"]


def test_initial_file_shape_is_checked_when_the_config_is_loaded(tmp_path):
    u = np.full((18, 24), 0.7)
    np.save(tmp_path / "bad.npy", u.T.copy())
    np.savetxt(tmp_path / "short.txt", u.ravel()[:-1])
    doc = {
        "model": "lattice",
        "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
        "domain": {"shape": [24, 18]},
        "triggers": [{"time": 0.0, "block": [12, 9], "kind": "kick", "velocity": 2.0}],
        "run": {"t_end": 4.0},
    }
    cases = {
        "bad.npy": r"^initial\.path: .*bad\.npy holds an array of shape \(24, 18\); expected "
        r"\(ny, nx\) = \(18, 24\)$",
        "short.txt": r"^initial\.path: .*short\.txt has 431 values; the domain has 432 nodes$",
    }
    for name, message in cases.items():
        bad = _with(doc, "initial", {"kind": "file", "path": str(tmp_path / name)})
        with pytest.raises(bk.ParameterError, match=message):
            parse_config(bad)  # (no run needed)


# --- the checks not tested elsewhere ----------------------------------------------
def test_quiet_loading_costs_no_steps():
    """A loaded lattice whose blocks are all stuck is not stepped: the loading to the first
    slip (t = 43.6, where phi = u - Lap u first reaches 1 at the corner block) is one
    jump; the steps of the run to the end of the first event are those of the event
    (its duration over h, and the located steps of its slips and sticks), not the 4360
    that stepping the loading would take). With local events (the lattice's default)
    the steps count the components' sub-steps too (the two halves of the step and one
    more per event in them: 2072, above the global cut's bound of 1751 here),
    still far below the loading's 4360."""
    nx, ny = 20, 16
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    u0 = 0.5 + 0.001 * i + 0.0005 * j
    p = bk.Params(gamma=0.45, v=0.01, dx=0.2)
    la = bk.Lattice((nx, ny), p, u0=u0)
    t_slip = (1.0 - la.phi.max()) / 0.01
    assert t_slip == pytest.approx(43.6, rel=1e-9)  # free edges: phi = u + 0.025 + 0.0125
    quiet = la.run(t_end=40.0, progress=False)
    assert quiet.counters["steps"] == 0 == quiet.counters["block_steps"]
    assert quiet.counters["jumps"] >= 1 and len(quiet.catalog) == 0
    np.testing.assert_allclose(la.u, u0 + 0.01 * 40.0, rtol=0, atol=1e-12)  # loaded exactly
    res = la.run(t_end=1e5, max_events=1, progress=False)
    ev = res.catalog.iloc[0]
    assert ev["t_start"] == pytest.approx(t_slip, rel=1e-9) and ev["n_blocks"] == nx * ny
    h = 0.05 * 0.2
    c = res.counters
    assert la.events == "local"
    assert c["steps"] <= ev["duration"] / h + 4 * c["switches"] + 10 < t_slip / h
    # the global cut: each slip and stick redoes at most two steps
    glob = bk.Lattice((nx, ny), p, u0=u0, events="global")
    res = glob.run(t_end=1e5, max_events=1, progress=False)
    assert glob._engine.counters()["jumps"] >= 1
    c = res.counters
    assert c["steps"] <= res.catalog.iloc[0]["duration"] / h + 2 * c["switches"] + 10


def test_energy_books_close_on_a_kicked_rupture():
    """A rupture kicked at a block (the energy injected by the kick, the viscous work,
    the springs at the end): the residual of the books over the work dissipated falls
    with the step at about RK4's order (measured 1.1e-7, 1.5e-9, 4.3e-10, 3.9e-11 at
    steps 0.1, 0.05, 0.025, 0.0125: a factor 2800 over three halvings, order 3.8)."""
    res = []
    for step in (0.1, 0.05, 0.025, 0.0125):
        la = bk.Lattice(
            (24, 24),
            bk.Params(gamma=0.45, v=0.0, dx=0.2),
            u0=0.7,
            step=step,
            boundary=("free", "periodic"),
        )
        e = la.kick((3, 5), -2.0).run(t_end=12.0, progress=False).energy
        assert e["injected"] == 2.0 and e["viscous_work"] > 100.0
        res.append(abs(e["residual"]) / e["viscous_work"])
    assert all(b < a / 3.0 for a, b in zip(res, res[1:], strict=False)), res
    assert res[-1] < res[0] / 1e3 and res[-1] < 1e-10, res


def _aspect_excess(dx, kick, t=1.0):
    """A rupture from the corner of a quadrant 4 units of x wide at dy = dx/1.5 (as
    docs/scripts/lattice_anisotropy.py), kicked by ``kick``: its deviation from the circle
    at t, aspect dx/dy - 1, and the planar part c(dx)/c(dy) - 1."""
    dy = dx / 1.5
    nx = int(round(4.0 / dx))
    la = bk.Lattice((nx, int(round(1.5 * nx))), bk.Params(gamma=0.45, v=0.0, dx=dx), 0.6, dy=dy)
    la.kick((0, 0), -kick)
    a = la.run(t_end=2.6, progress=False).first_slip_times()
    r = bk.lattice.Rupture(0.6, 0.45, dx, dy, (nx, 0), a, {}, {}, {}, (0, 0))
    planar = bk.front_speed(0.6, dx=dx, gamma=0.45) / bk.front_speed(0.6, dx=dy, gamma=0.45)
    return r.aspect(t) * dx / dy - 1.0, planar - 1.0


def test_the_anisotropy_is_a_start_up_excess_over_the_planar_deficit():
    """docs/lattice.md, "Measured: the anisotropy": the deviation from the circle is the
    planar deficit (the chain at dx slower than at dy: negative, linear in dx) plus an
    excess of the point kick's start-up, positive, which grows with the kick like its
    logarithm (by 0.0073, 0.0070 per doubling at dx = 0.1, t = 1) and falls with dx
    at a fixed kick."""
    dev, planar = _aspect_excess(0.1, 2.0)
    assert -0.0068 < planar < -0.0066  # c(0.1)/c(0.0667) - 1 = -0.00669
    assert dev == pytest.approx(0.018467, abs=1e-5)  # the docs' table
    excess = {k: _aspect_excess(0.1, k)[0] - planar for k in (1.0, 2.0, 4.0)}
    steps = (excess[2.0] - excess[1.0], excess[4.0] - excess[2.0])
    assert 0.006 < min(steps) and max(steps) < 0.008, excess
    fine, planar_fine = _aspect_excess(0.05, 2.0)
    assert planar_fine == pytest.approx(planar / 2, rel=0.05)
    assert 0.5 < (fine - planar_fine) / excess[2.0] < 0.65  # 0.0148 / 0.0252


def _start_up_e(dx, tau, k_kick):
    """E = excess t/dx of a corner-kicked rupture at dy = dx/1.5 (as
    docs/scripts/lattice_anisotropy.py --collapse) at t = tau dx with the kick k_kick dx:
    the time and the kick in the lattice's own units held fixed as dx changes."""
    dy, t = dx / 1.5, tau * dx
    nx = int(round((1.3 * (t + 4 * dx) + 8 * dx) / dx))
    la = bk.Lattice((nx, int(round(1.5 * nx))), bk.Params(gamma=0.45, v=0.0, dx=dx), 0.6, dy=dy)
    la.kick((0, 0), -k_kick * dx)
    a = la.run(t_end=t + 4 * dx, progress=False).first_slip_times()
    r = bk.lattice.Rupture(0.6, 0.45, dx, dy, (nx, 0), a, {}, {}, {}, (0, 0))
    planar = bk.front_speed(0.6, dx=dx, gamma=0.45) / bk.front_speed(0.6, dx=dy, gamma=0.45)
    return (r.aspect(t) * dx / dy - planar) * t / dx


def test_the_start_up_is_the_lattice_problem_in_its_own_units():
    """docs/lattice.md, "The start-up in the lattice's units": with u = u_+ + dx^2 U and
    t = dx tau the lattice's equations lose dx but for the loader (dx^2 U) and the drag
    (gamma dx U_tau) terms, so E = excess t/dx is a function G(tau, K) of tau = t/dx and
    the kick K = kick/dx, plus O(dx): at fixed (tau, K) E moves by half as much at each
    halving of dx (0.2516, 0.2437, 0.2400 at tau = 10, K = 20), while with the kick held
    in the model's units (K doubling at each halving) it would move by ~0.07 per halving
    (G's slope 0.10 per e-fold of K)."""
    e = [_start_up_e(dx, 10, 20) for dx in (0.1, 0.05, 0.025)]
    d1, d2 = e[0] - e[1], e[1] - e[2]
    assert 0.005 < d1 < 0.011 and 0.35 < d2 / d1 < 0.6, e
    # the kick's own law: doubling K at fixed tau and dx raises E by 0.06-0.08
    up = _start_up_e(0.05, 10, 40) - e[1]
    assert 0.06 < up < 0.08, up
    # and tau's: doubling tau at fixed K lowers it (the eikonal's -(D_x - D_y)/c^2 per
    # e-fold at large tau; -0.034 per e-fold between tau = 10 and 20 at K = 20)
    down = _start_up_e(0.05, 20, 20) - e[1]
    assert -0.03 < down < -0.02, down


@pytest.mark.parametrize("suffix", [".nc", ".zarr"])
def test_the_y_coordinate_says_how_it_is_scaled_across(tmp_path, suffix):
    """y = j dy with dy = sqrt(k_p/k_y): the output's y says so, not x's scale (session
    35: the y coordinate carried "x' = (x/a) sqrt(k_p/k_c)", wrong for dy != dx); the
    coordinates are the blocks' positions i dx and j dy."""
    xr = pytest.importorskip("xarray")
    doc = _with(_with(LOADING, "domain.dy", 0.3), "run.t_end", 1.0)
    out = tmp_path / f"la{suffix}"
    bk.run(doc, out)
    ds = xr.open_dataset(out, engine="zarr" if suffix == ".zarr" else None)
    assert ds["u"].dims == ("t", "y", "x")
    assert ds["x"].attrs["scale"].startswith("x' = (x/a) sqrt(k_p/k_c)")
    assert ds["y"].attrs["scale"].startswith("y' = (y/a) sqrt(k_p/k_y)")
    assert ds["y"].attrs["long_name"] == "position across" and ds["y"].attrs["units"] == "1"
    np.testing.assert_allclose(ds["x"].values, 0.2 * np.arange(16), rtol=0, atol=1e-15)
    np.testing.assert_allclose(ds["y"].values, 0.3 * np.arange(12), rtol=0, atol=1e-15)
    ds.close()


def test_the_help_says_what_the_lattice_runs_and_draws(tmp_path):
    """`bkwaves run --help` said friction laws other than Coulomb run in the chain only,
    and `bkwaves plot --help` named no planar picture (session 35): a lattice config with
    velocity weakening runs with that law, and the help says so and names the maps."""
    import subprocess
    import sys
    import textwrap

    def helptext(cmd):
        p = subprocess.run(
            [sys.executable, "-m", "bkwaves", cmd, "--help"], capture_output=True, text=True
        )
        assert p.returncode == 0, p.stderr
        return " ".join(p.stdout.split())

    doc = _with(
        _with(LOADING, "friction", {"law": "velocity_weakening", "v_f": 1.0}), "run.t_end", 1.0
    )
    bk.run(doc, tmp_path / "vw.nc")
    ds, _ = bk.io.load_tables(tmp_path / "vw.nc")
    assert '"velocity_weakening"' in ds.attrs["friction_law"]
    text = helptext("run")
    assert "chain only" not in text
    assert "run in the chain and the lattice" in text
    plot = helptext("plot")
    for name in ("slip map", "arrival-time contours", "catalog on a map"):
        assert name in plot, textwrap.shorten(plot, 300)


@pytest.mark.parametrize("shape", [[1, 12], [12, 1], [2, 2]])
def test_plot_draws_a_lattice_of_one_row_or_column(tmp_path, shape):
    """`bkwaves plot` of a lattice of a single row or column (session 35: the arrival map's
    contours raised "TypeError: Input z must be at least a (2, 2) shaped array" and no
    picture was written): its four maps, each readable (figure_checks), the arrival map
    the blocks' arrival times themselves."""
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    from figure_checks import figure_problems

    import bkwaves.plot

    doc = {
        "model": "lattice",
        "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
        "domain": {"shape": shape},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [{"time": 0.0, "block": [0, 0], "kind": "kick", "velocity": 2.0}],
        "run": {"t_end": 3.0},
        "output": {"snapshot_every": 1.0, "arrivals": True},
    }
    out = tmp_path / "la.nc"
    bk.run(doc, out)
    problems, save, drawn = {}, bkwaves.plot.save, {}

    def checked_save(ax, path):
        problems[Path(path).name] = figure_problems(ax.figure)
        drawn[Path(path).name] = ax
        return save(ax, path)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(bkwaves.plot, "save", checked_save)
        files = bkwaves.plot.plot_run(out, tmp_path)
    names = {f.name for f in files}
    for kind in ("slip_map", "arrivals", "catalog_map", "stress"):
        assert f"la_{kind}.png" in names, names
    assert not {k: v for k, v in problems.items() if v}, problems
    # the arrival map colours each block by its first slip time (the arrivals table)
    arr = bk.io.load_tables(out)[1]["arrivals"]
    mesh = drawn["la_arrivals.png"].collections[0]
    values = np.sort(np.ma.compressed(mesh.get_array()))
    if min(shape) == 1:
        np.testing.assert_array_equal(values, np.sort(arr["t"].to_numpy()))


@pytest.mark.parametrize("dy", [100.0, 1e-3])
def test_plot_of_a_plane_of_extreme_spacings_shows_every_block_that_slipped(tmp_path, dy):
    """dy = 1e3 dx and 1e-2 dx (session 35): drawn to scale the maps were a line (x tick
    labels on top of each other), and at dy = 100 the rupture runs along its kicked row
    only, which the arrival map's filled contours did not draw at all (an empty frame).
    Now a map far from square is stretched and its y label says so, and the arrival map
    colours every block that slipped with its arrival time."""
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    from figure_checks import figure_problems
    from matplotlib.collections import QuadMesh

    from bkwaves import _plot_plane

    doc = {
        "model": "lattice",
        "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
        "domain": {"shape": [10, 10], "dy": dy},
        "initial": {"kind": "uniform", "value": 0.7},
        "triggers": [{"time": 0.0, "block": [5, 5], "kind": "kick", "velocity": 2.0}],
        "run": {"t_end": 1.0},
        "output": {"snapshot_every": 0.5, "arrivals": True},
    }
    out = tmp_path / "la.nc"
    bk.run(doc, out)
    ds, tables = bk.io.load_tables(out)
    arr = tables["arrivals"]
    ax = _plot_plane.arrival_map(ds, tables, "a test run")
    fig = ax.figure
    fig.canvas.draw()
    assert not figure_problems(fig)
    box = ax.get_window_extent()
    assert 1 / 6 <= box.height / box.width <= 6
    assert "not to the scale of x" in ax.get_ylabel()
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    shown = np.ma.compressed(mesh.get_array())
    np.testing.assert_array_equal(np.sort(shown), np.sort(arr["t"].to_numpy()))
    if dy == 100.0:  # the rupture along the kicked row: the filled contours drew nothing
        assert set(arr["j"]) == {5} and len(arr) == 10


def test_plot_draws_no_slip_map_where_nothing_slipped(tmp_path):
    """A lattice at rest (no trigger, v = 0; session 35): the slip map was a uniform 0
    under a colour bar from -0.1 to 0.1 (made-up slips); now it is left out, as bkwaves
    plot leaves out a blank space-time panel, and the stress map is drawn."""
    pytest.importorskip("matplotlib").use("Agg")
    import bkwaves.plot

    doc = {
        "model": "lattice",
        "params": {"gamma": 0.45, "v": 0.0, "dx": 0.1},
        "domain": {"shape": [8, 6]},
        "initial": {"kind": "uniform", "value": 0.7},
        "run": {"t_end": 1.0},
        "output": {"snapshot_every": 0.5},
    }
    out = tmp_path / "rest.nc"
    bk.run(doc, out)
    names = {f.name for f in bkwaves.plot.plot_run(out, tmp_path)}
    assert names == {"rest_stress.png"}, names
