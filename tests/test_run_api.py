"""A run as a function of its config: RunConfig.to_dict()/from_dict() round trips, and
bk.run(cfg) returns in memory what `bkwaves run` writes."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import bkwaves as bk
from bkwaves.config import RunConfig, load_config

EXAMPLES = sorted(
    p
    for p in (Path(__file__).parents[1] / "examples").glob("*.toml")
    if not p.name.startswith("sweep_")
)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_config_round_trips_exactly(path):
    cfg = load_config(path)
    doc = cfg.to_dict()
    again = RunConfig.from_dict(json.loads(json.dumps(doc)), base_dir=cfg.base_dir)
    assert again == cfg
    assert again.to_dict() == doc


def test_a_config_changed_in_code_writes_what_it_holds(tmp_path):
    cfg = load_config(Path(__file__).parents[1] / "examples" / "free_boundary_source.toml")
    changed = dataclasses.replace(
        cfg, max_events=2, params=dataclasses.replace(cfg.params, gamma=0.2)
    )
    out = tmp_path / "c.nc"
    bk.runner.run(changed, out)
    ds, _tables = bk.load(out)
    stored = RunConfig.from_dict(json.loads(ds.attrs["config"]))
    assert stored == changed
    assert json.loads(ds.attrs["params"])["gamma"] == 0.2
    assert ds.attrs["model"] == "free_boundary"


def test_run_in_memory_equals_the_written_run(tmp_path):
    cfg = load_config(Path(__file__).parents[1] / "examples" / "free_boundary_random.toml")
    cfg = dataclasses.replace(cfg, t_end=800.0)
    mem = bk.run(cfg, snapshots=True)
    assert mem.summary["model"] == "free_boundary" and mem.summary["t"] == 800.0
    assert mem.summary["n_events"] == len(mem.events) > 0
    out = tmp_path / "r.nc"
    disk = bk.run(cfg, out, snapshots=True)
    pd.testing.assert_frame_equal(
        mem.events.reset_index(drop=True),
        disk.events.reset_index(drop=True),
        check_dtype=False,
    )
    np.testing.assert_array_equal(mem.snapshots["u"].values, disk.snapshots["u"].values)
    np.testing.assert_array_equal(mem.snapshots["t"].values, disk.snapshots["t"].values)
    assert mem.summary["events"] == disk.summary["events"]
    # nothing was written by the in-memory run
    assert not Path(cfg.output_path).exists()


def test_run_accepts_dicts_and_paths_and_names_bad_input():
    cfg = load_config(Path(__file__).parents[1] / "examples" / "chain_front.toml")
    cfg = dataclasses.replace(cfg, t_end=20.0, blocks=200)
    a = bk.run(cfg.to_dict())
    b = bk.run(cfg)
    pd.testing.assert_frame_equal(a.events, b.events)
    with pytest.raises(bk.ParameterError, match="cfg"):
        bk.run(42)
    with pytest.raises(bk.ParameterError, match="input_units"):
        RunConfig.from_dict({**cfg.to_dict(), "input_units": "SI"})


def test_event_statistics_b_value_only_with_enough_events():
    from bkwaves.runner import _event_statistics
    from bkwaves.stats import MIN_EVENTS as B_VALUE_MIN_EVENTS

    rng = np.random.default_rng(1)
    # moments with a pure power law: P(M0 > m) ~ m^(-2/3 b) with b = 1
    n = 4000
    m0 = (1 - rng.random(n)) ** (-1.0 / (2.0 / 3.0))
    ev = pd.DataFrame({"moment": m0, "t_start": np.arange(n, dtype=float)})
    s = _event_statistics(ev)
    assert s["n_events"] == n and s["mean_interval"] == 1.0
    assert s["b_value_lo"] < 1.0 < s["b_value_hi"] and s["b_value_note"] == ""
    assert s["m_c"] == pytest.approx(0.2)  # maximum curvature (bin [0, 0.1)) + 0.2
    few = _event_statistics(ev.iloc[: B_VALUE_MIN_EVENTS - 1])
    assert np.isnan(few["b_value"]) and few["n_events"] == B_VALUE_MIN_EVENTS - 1
    assert few["b_value_note"].startswith("too few events")


def test_every_k_events_snapshots_start_with_the_initial_state():
    """A chain run with only snapshot_events: its first snapshot is the initial state at
    t = 0 (as for timed snapshots), then one per event."""
    from bkwaves.config import initial_state

    cfg = load_config(Path(__file__).parents[1] / "examples" / "chain_loading.toml")
    assert cfg.snapshot_events == 1 and cfg.snapshot_every is None
    cfg = dataclasses.replace(cfg, max_events=3)
    r = bk.run(cfg, snapshots=True)
    t = r.snapshots["t"].values
    assert t[0] == 0.0 and len(t) == 1 + 3
    np.testing.assert_array_equal(r.snapshots["u"].values[0], initial_state(cfg))
    np.testing.assert_array_equal(t[1:], r.events["t_end"].values[:3])


def test_seed_is_recorded_only_when_given_or_drawn(tmp_path):
    """No seed in a config: a deterministic run records none (not 0); a random run draws a
    fresh seed and records it, so that the file repeats the run exactly."""
    root = Path(__file__).parents[1] / "examples"
    det = load_config(root / "free_boundary_source.toml")
    assert det.seed is None and not det.random and det.seeded() is det
    out = tmp_path / "d.nc"
    bk.runner.run(dataclasses.replace(det, max_events=1), out)
    ds, _ = bk.load(out)
    assert ds.attrs["seed"] == "" and "seed" not in json.loads(ds.attrs["config"])
    doc = load_config(root / "free_boundary_random.toml").to_dict()
    doc.pop("seed")
    a, b = RunConfig.from_dict(doc), RunConfig.from_dict(doc)
    assert a.seed is not None and a.seed != b.seed  # drawn when read, then kept
    assert RunConfig.from_dict(a.to_dict()) == a
    rnd = dataclasses.replace(
        load_config(root / "free_boundary_random.toml"), seed=None, t_end=100.0
    )
    assert rnd.random
    a, b = rnd.seeded(), rnd.seeded()
    assert a.seed is not None and a.seed != b.seed
    out = tmp_path / "r.nc"
    bk.runner.run(rnd, out)
    ds, _ = bk.load(out)
    seed = int(ds.attrs["seed"])
    stored = RunConfig.from_dict(json.loads(ds.attrs["config"]))
    assert stored.seed == seed
    again = bk.run(stored, snapshots=True)
    np.testing.assert_array_equal(again.snapshots["u"].values[0], ds["u"].values[0])


@pytest.mark.parametrize("example", ["chain_loading.toml", "free_boundary_random.toml"])
def test_a_run_that_ends_mid_event_marks_that_event_incomplete(example, tmp_path):
    """The event still running at t_end is written (cut at t_end) but marked complete =
    False, and neither the event count nor the event statistics count it."""
    cfg = load_config(Path(__file__).parents[1] / "examples" / example)
    first = bk.run(dataclasses.replace(cfg, max_events=3, t_end=None, snapshot_events=None))
    ev = first.events
    assert len(ev) == 3 and ev["complete"].all()
    t_cut = 0.5 * (ev["t_start"].iloc[2] + ev["t_end"].iloc[2])
    cut_cfg = dataclasses.replace(cfg, max_events=None, t_end=float(t_cut), snapshot_events=None)
    for res in (bk.run(cut_cfg), bk.run(cut_cfg, tmp_path / "cut.nc")):
        assert res.summary["events"] == 2 == res.summary["n_events"]
        assert list(res.events["complete"]) == [True, True, False]
        pd.testing.assert_frame_equal(
            res.events.iloc[:2].reset_index(drop=True),
            ev.iloc[:2].reset_index(drop=True),
            check_dtype=False,
        )
    ds, _ = bk.load(tmp_path / "cut.nc")
    if cut_cfg.snapshot_every is None:
        # no snapshot was asked for: the output still holds the state at the end
        assert ds.sizes["t"] == 1 and ds.t.values[-1] == t_cut
