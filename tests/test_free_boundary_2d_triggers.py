"""Scheduled [[triggers]] of model = "free_boundary_2d" (issue 26): a rupture started at
(time, x, y, radius) through bkwaves run / bk.run / checkpoints.

Checked against the engine driven by hand (bk.FreeBoundary2D run to the trigger's time,
then FreeBoundary2D.trigger): the same ruptures bit for bit; a run interrupted before or
after a trigger and resumed equals the uninterrupted one bit for bit and fires each
trigger once."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import bkwaves as bk
from bkwaves.config import parse_config
from bkwaves.runner import checkpoint_path, resume, run

DOC = {
    "model": "free_boundary_2d",
    "seed": 3,
    "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
    "domain": {"shape": [40, 32], "spacing": 0.5, "boundary": ["periodic", "free"]},
    "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.3, "correlation_length": 1.0},
    "triggers": [
        {"time": 0.0, "x": 3.0, "y": 4.0},
        {"time": 4.5, "x": 15.2, "y": 11.9, "radius": 1.2},
    ],
    "run": {"t_end": 250.0},
    "output": {"snapshot_every": 20.0, "arrivals": True},
}


def _with(doc, path, value):
    out = copy.deepcopy(doc)
    *head, last = path.split(".")
    d = out
    for k in head:
        d = d[int(k)] if isinstance(d, list) else d.setdefault(k, {})
    if value is None:
        d.pop(last, None)
    else:
        d[last] = value
    return out


def _by_hand():
    u0 = 0.5 + 0.3 * bk.disorder.smooth_field(
        (32, 40), (0.5, 0.5), 1.0, periodic=(False, True), seed=3
    )
    p = bk.Params(gamma=0.3, v=0.01, dx=0.001)
    fb = bk.FreeBoundary2D(p, (40, 32), 0.5, u0, ("periodic", "free"), record_arrivals=True)
    fb.trigger(3.0, 4.0)
    fb.run(t_end=4.5)
    fb.trigger(15.2, 11.9, 1.2)
    return fb, fb.run(t_end=250.0)


def test_triggers_run_as_the_engine_triggered_by_hand():
    cfg = parse_config(DOC)
    assert parse_config(cfg.to_dict()) == cfg
    assert [t.block for t in cfg.triggers] == [(3.0, 4.0, 0.0), (15.2, 11.9, 1.2)]
    res = bk.run(cfg)
    rup = res.tables["ruptures"]
    fb, ref = _by_hand()
    assert len(rup) == len(ref.ruptures) >= 4
    for col in ("origin", "t_start", "t_end", "x_start", "y_start", "area", "moment"):
        np.testing.assert_array_equal(rup[col], ref.ruptures[col])
    trig = rup[rup["origin"] == "trigger"]
    # each trigger fired once, at its time and place; the two ruptures met, births followed
    assert trig["t_start"].tolist() == [0.0, 4.5]
    assert trig["x_start"].tolist() == [3.0, 15.2] and trig["y_start"].tolist() == [4.0, 11.9]
    assert (trig["contacts"] > 0).all() and (rup["origin"] == "birth").sum() >= 3
    # the second one started on its disk of radius 1.2: the nodes in it arrived at 4.5,
    # those outside later
    arr = res.tables["arrivals"]
    second = arr[arr["rupture"] == int(trig["id"].iloc[1])]
    near = np.hypot(second["x"] - 15.2, second["y"] - 11.9) <= 1.2
    gx, gy = np.meshgrid(np.arange(40) * 0.5, np.arange(32) * 0.5)
    assert near.sum() == np.sum(np.hypot(gx - 15.2, gy - 11.9) <= 1.2) >= 12
    assert (second.loc[near, "t"] == 4.5).all()
    assert (second.loc[~near, "t"] > 4.5).all()
    # without the triggers the sequence differs (the test can fail)
    plain = bk.run(_with(DOC, "triggers", None)).tables["ruptures"]
    assert not (plain["origin"] == "trigger").any() and len(plain) != len(rup)


@pytest.mark.parametrize("suffix", [".nc"])
def test_triggers_resume_bit_for_bit_and_fire_once(tmp_path, suffix):
    cfg = parse_config(DOC)
    ref = run(cfg, tmp_path / f"ref{suffix}", chunk=40)
    a, ta = bk.io.load_tables(tmp_path / f"ref{suffix}")
    assert (ta["ruptures"]["origin"] == "trigger").sum() == 2
    cuts = set()
    for k in range(1, ref.extra["steps"] // 40, 2):
        out = tmp_path / f"cut{k}{suffix}"
        first = run(cfg, out, chunk=40, _stop_after_chunks=k)
        if not first.interrupted:
            continue
        assert checkpoint_path(out).exists()
        cuts.add(first.t < 4.5)
        last = resume(out, chunk=40)
        assert not last.interrupted and last.events == ref.events
        b, tb = bk.io.load_tables(out)
        np.testing.assert_array_equal(a["u"].values, b["u"].values)
        for name in ("ruptures", "arrivals"):
            assert ta[name].equals(tb[name])
        if cuts == {True, False}:
            break
    assert cuts == {True, False}  # cut before and after the second trigger


def test_a_trigger_on_a_running_rupture_is_not_fired_and_said(tmp_path):
    doc = _with(DOC, "triggers", [{"time": 0.0, "x": 3.0, "y": 4.0},
                                  {"time": 0.5, "x": 3.0, "y": 4.5}])  # fmt: skip
    with pytest.warns(RuntimeWarning, match=r"trigger at t = 0\.5 at \(3, 4\.5\) not fired"):
        res = bk.run(doc)
    assert (res.tables["ruptures"]["origin"] == "trigger").sum() == 1
    with pytest.warns(RuntimeWarning, match="not fired"):
        summary = run(parse_config(doc), tmp_path / "out.nc")
    assert any("not fired" in w for w in summary.extra["warnings"])


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        ("triggers.0.x", 20.0, r"triggers\[0\]\.x: invalid x = 20: allowed 0 <= x < 20 "),
        ("triggers.0.y", 15.6, r"triggers\[0\]\.y: invalid y = 15\.6: allowed 0 <= y <= 15\.5 "),
        ("triggers.0.y", -1.0, r"triggers\[0\]\.y: invalid y = -1"),
        ("triggers.0.x", None, r"triggers\[0\]\.x: missing required key"),
        ("triggers.1.radius", -0.5, r"triggers\[1\]\.radius: invalid radius = -0\.5: allowed 0 <="),
        ("triggers.0.time", -1.0, r"triggers\[0\]\.time: .*time >= 0"),
        ("triggers.0.kind", "kick", r"triggers\[0\]\.kind: unknown key; valid keys here: time"),
        ("triggers.0.block", [1, 1], r"triggers\[0\]\.block: unknown key"),
    ],
)
def test_trigger_errors_name_the_key_and_the_range(path, value, message):
    with pytest.raises(bk.ParameterError, match=message) as e:
        parse_config(_with(DOC, path, value))
    assert "\n" not in str(e.value)


def test_triggers_in_physical_units():
    """[physical]: the place and radius in metres, the time in seconds."""
    doc = copy.deepcopy(DOC)
    doc.pop("params")
    doc["physical"] = {"preset": "bristol_board", "V": 1e-4}
    p = bk.presets.bristol_board(V=1e-4)
    ls, ts = p.units.length_scale, p.units.time_scale
    doc["domain"]["spacing"] = 0.5 * ls
    doc["triggers"] = [{"time": 2.0 * ts, "x": 3.0 * ls, "y": 4.0 * ls, "radius": 1.0 * ls}]
    doc["run"] = {"t_end": 10.0 * ts}
    doc["output"] = {}
    cfg = parse_config(doc)
    (tr,) = cfg.triggers
    assert tr.time == pytest.approx(2.0)
    np.testing.assert_allclose(tr.block, (3.0, 4.0, 1.0), rtol=1e-12)
    assert parse_config(cfg.to_dict()) == cfg
    rup = bk.run(cfg).tables["ruptures"]
    trig = rup[rup["origin"] == "trigger"]
    assert len(trig) == 1
    assert trig["x_start"].iloc[0] == pytest.approx(3.0 * ls, rel=1e-12)
    assert trig["t_start"].iloc[0] == pytest.approx(2.0 * ts, rel=1e-12)
