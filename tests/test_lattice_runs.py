"""The lattice model run from a config (issue 25): per-bond springs in [disorder], the
ruptures table, the limits on an event's duration and the initial file's shape.

Each capability is checked against an exact reduction or an independent computation:
uniform bonds given explicitly are the uniform lattice bit for bit, a lattice without y
bonds is ny chains, a config's bonds are those of bk.Lattice built by hand, and the
ruptures of a hand-built slip record are counted by hand.
"""

from __future__ import annotations

import copy

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
