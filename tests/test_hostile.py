"""Inputs from the hostile-input campaign (issue 27; benchmarks/hostile.py,
docs/reliability.md): runs that never ended, lengths without a range, and a fixed-seed
slice of the campaign itself."""

import dataclasses
import math
import os
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import pytest

import bkwaves as bk
from bkwaves.config import parse_config
from bkwaves.runner import chain_from_config


def _disordered_random_chain(t_end: float) -> dict:
    return {
        "model": "chain",
        "seed": 3,
        "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.1},
        "disorder": {"threshold": {"distribution": "uniform", "mean": 1.0, "spread": 0.1}},
        "domain": {"blocks": 200},
        "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.6},
        "run": {"t_end": t_end},
    }


@pytest.mark.parametrize("t_end", [1e-5, 1e-30, 1e-100, 1e-300, 1e-310])
def test_a_chain_reaches_a_tiny_t_end(t_end):
    # blocks over their thresholds slip at t = 0 with u_t = v; a step of 1e-30 changes
    # u_t by less than ulp(v), and the engine halved it for ever (t -> t_end, never there)
    cfg = parse_config(_disordered_random_chain(t_end))
    ch = chain_from_config(cfg)
    stop = "steps"
    for _ in range(50):  # 50 chunks of 1000 steps: far more than the run needs
        stop = ch._engine.advance(cfg.t_end, 2**62, 1000)
        if stop != "steps":
            break
    assert stop == "time"
    assert ch.t == cfg.t_end
    assert ch._engine.counters()["steps"] < 1000
    assert (ch.modes != 0).sum() > 10  # the blocks over threshold slide (the case tested)


@pytest.mark.parametrize("corr", [1e8, 1e300])
def test_a_threshold_field_correlation_length_has_a_range(corr):
    """1e8 allocated 8.9 GiB (the filter pads the domain by 6 lengths), 1e300 gave a numpy
    traceback: at most 100 domains, a one-line error naming the key."""
    path = Path(__file__).parents[1] / "examples" / "free_boundary_disordered.toml"
    doc = tomllib.loads(path.read_text())
    doc["disorder"]["threshold"]["correlation_length"] = corr
    with pytest.raises(bk.ParameterError) as e:
        parse_config(doc)
    msg = str(e.value)
    assert msg.startswith("disorder.threshold.correlation_length") and "\n" not in msg, msg
    assert "100 x the domain" in msg
    doc["disorder"]["threshold"]["correlation_length"] = 100 * 2000.0  # the largest allowed
    parse_config(doc)


def test_a_fixed_seed_slice_of_the_campaign_finds_nothing():
    """benchmarks/hostile.py with a fixed seed, 24 configs and 24 API calls (the full
    campaign: docs/reliability.md): no traceback, crash, hang or error that does not name
    its parameter."""
    import sys

    sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
    import hostile

    results = hostile.campaign(seed=2027, n_configs=24, n_calls=24, timeout=20.0)
    s = hostile.summary(results)
    bad = [r for r in results if r["class"] in hostile.CLASSES[2:6] + ("silent-wrong",)]
    assert not bad, bad
    assert s["config"]["total"] == 24 and s["call"]["total"] == 24
    assert s["config"]["ok"] > 0 and s["config"]["error"] > 0  # both kinds exercised


@pytest.mark.parametrize("length", [1e6, 1e308])
def test_a_free_boundary_grid_spacing_has_a_range(length):
    """Campaign findings: length = 1e6 on 201 nodes (v h = 50) ended in a ConvergenceError
    after 1e6 trajectory steps in one cell, 1e308 never ended; v h <= 1 and |x| <= 1e12,
    named: domain.length in a config, x in the API."""
    import numpy as np

    doc = {
        "model": "free_boundary",
        "params": {"gamma": 0.3, "v": 1e-2, "dx": 1e-3},
        "domain": {"length": length, "grid": 201},
        "initial": {"kind": "uniform", "value": 0.5},
        "run": {"max_events": 2},
    }
    with pytest.raises(bk.ParameterError) as e:
        parse_config(doc)
    assert str(e.value).startswith("invalid domain.length"), str(e.value)
    x = np.linspace(0.0, length, 201)
    with pytest.raises(bk.ParameterError, match="invalid x"):
        bk.FreeBoundary(bk.Params(gamma=0.3, v=1e-2, dx=1e-3), x, np.full(201, 0.5))
    doc["domain"]["length"] = 20000.0  # v h = 1: the largest allowed
    parse_config(doc)


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda: bk.friction.law(1e-12), "invalid name"),
        (lambda: bk.disorder.thresholds(10, 0.1, seed=1e-6), "invalid seed"),
        (lambda: bk.disorder.thresholds(10**30, 0.1), "invalid n"),
        (lambda: bk.disorder.thresholds(10, 0.1, distribution=[]), "invalid distribution"),
        (lambda: bk.disorder.draw("uniform", 10, spread=0.1, seed=1e-300), "invalid seed"),
        (lambda: bk.disorder.draw("uniform", 0.5, spread=0.1, seed=1), "invalid n"),
        (lambda: bk.disorder.draw([1], 10, spread=0.1, seed=1), "invalid distribution"),
        (lambda: bk.disorder.draw("uniform", 10, spread=0.1, seed=[-1]), "invalid seed"),
        (lambda: bk.stats.recurrence_times(3.0), "invalid times"),
        (lambda: bk.theory.profile({}, 0.6, 0.3), "invalid z"),
        (lambda: bk.velocity_weakening.min_friction(0.3, "x"), "invalid v_f"),
        (lambda: bk.velocity_weakening.min_friction(-1.0, 0.01), "invalid gamma"),
        (lambda: bk.friction.law("velocity_weakening", gamma={}), "invalid gamma"),
        (lambda: __import__("bkwaves.chain").chain.front(0.6, 0.3, 5e-324), "invalid dx"),
        # round-off in 1/dx^2: c off by 2e-5 at dx = 1e-6 (silent), no end at 1e-300
        (lambda: bk.disorder.marched_speed(0.5, dx=1e-6), "invalid dx"),
        (
            lambda: bk.Params.from_physical(
                mass=1e-310,
                k_c=1e3,
                k_p=10.0,
                f_static=1.0,
                f_kinetic=0.5,
                alpha=0.01,
                V=1e-9,
                spacing=1e-3,
            ),  # fmt: skip
            r"alpha/\(2 sqrt\(k_p mass\)\)",
        ),
    ],
)
def test_api_calls_the_campaign_found_name_their_argument(call, words):
    """Tracebacks from inside numpy and the core (TypeError), and a derived gamma whose
    message named alpha alone when mass was the absurd one."""
    with pytest.raises(bk.ParameterError, match=words):
        call()


def _warned(doc, *words):
    import warnings

    from bkwaves.limits import LongRunWarning

    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        with pytest.raises(LongRunWarning) as e:
            parse_config(doc)
    msg = str(e.value)
    assert all(w in msg for w in words) and "\n" not in msg, msg
    return msg


def test_a_snapshot_schedule_beyond_the_limit_is_refused_before_it_is_allocated():
    """t_end = 2**64 with a snapshot every 50 (and max_events, which may end the run
    sooner): the runner would schedule 3.7e17 times (a MemoryError of 2.6 EiB)."""
    doc = {
        "model": "free_boundary",
        "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
        "domain": {"length": 40.0, "grid": 201},
        "initial": {"kind": "uniform", "value": 0.5},
        "run": {"t_end": 2**64, "max_events": 2},
        "output": {"snapshot_every": 50.0},
    }
    with pytest.raises(bk.ParameterError, match="output.snapshot_every with run.t_end"):
        parse_config(doc)


def test_velocity_weakening_front_with_a_tiny_v_f_is_cheap_and_near_coulomb():
    """velocity_weakening.front(v_f = 1e-9): steps of 5e-11 once, hours of work (warned
    since the campaign hang); now the chain keeps step dx and only each block's onset takes
    sub-steps (chain/onset.rs): no warning, about a second, and the front within the
    derived 2 c_C r ln(1/r) of the Coulomb chain's at r = v_f/dx = 1e-8."""
    import warnings

    from bkwaves.limits import LongRunWarning

    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        only_c = {"c": 1e-6, "zone": math.inf, "u_minus": math.inf}
        f = bk.velocity_weakening.front(0.6, 0.3, 0.1, 1e-9, tolerance=only_c)
    assert f.status == "steady", f
    cc = float(bk.front_speed(0.6, dx=0.1, gamma=0.3))
    assert 0.0 < cc / f.c - 1.0 < bk.velocity_weakening.coulomb_gap_bound(cc, 1e-8)


def test_campaign_configs_that_ran_for_ever_or_overflowed_are_warned():
    """A noise rate of 1e308 (inf x 0 = nan in the estimate: no warning), a free-boundary
    ring whose noise nucleates faster than ruptures cross it with only max_events (events
    merge and never complete: it ran for ever), a v = 0 chain bounded by more events than
    can happen with snapshots every 1.0 (it ran on to t = 1e300 through 10**6 of them)."""
    chain = {
        "model": "chain",
        "params": {"gamma": 0.3, "v": 1e-3, "dx": 0.1},
        "domain": {"blocks": 20, "boundary": "periodic"},
        "initial": {"kind": "ramp", "start": 0.4, "end": 0.7},
        "noise": {"law": "exponential", "rate": 1e308, "phi0": 0.05},
        "run": {"t_end": 5.0},
    }
    _warned(chain, "noise.rate = 1e+308", "inf")
    ring = {
        "model": "free_boundary",
        "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
        "domain": {"length": 40.0, "grid": 201, "boundary": "periodic"},
        "initial": {"kind": "random", "mean": 0.5, "amplitude": 0.2, "correlation_length": 2.0},
        "noise": {"law": "constant", "rate": 0.1},
        "run": {"max_events": 2},
        "seed": 1,
    }
    _warned(ring, "run.max_events = 2", "never complete")
    ring["noise"]["rate"] = 1e-4  # 0.16 nucleations per crossing: no word
    parse_config(ring)
    quiet = {
        "model": "chain",
        "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        "domain": {"blocks": 50, "boundary": "periodic"},
        "initial": {"kind": "uniform", "value": 0.6},
        "triggers": [{"time": 0.0, "block": 0, "kind": "kick", "velocity": 2.0}],
        "run": {"max_events": 2},
        "output": {"snapshot_every": 1.0},
    }
    _warned(quiet, "output.snapshot_every with run.max_events", "v = 0", "1e300")


def test_a_vanishing_correlation_length_is_estimated():
    """correlation_length = 5e-324 divided by zero in the estimate (a traceback)."""
    doc = _disordered_random_chain(5.0)
    doc["initial"]["correlation_length"] = 5e-324
    parse_config(doc)


def test_second_seed_findings_are_clean_errors_or_warnings(monkeypatch):
    """Seed 5: snapshot_every = 1e-310 overflowed the estimate's count (OverflowError),
    dx = 1e-310 divided by zero in the stability check, and a v = 0 chain of 10^5 blocks
    with noise bounded by events ran unwarned (its first noise slip starts a rupture)."""
    import warnings

    from bkwaves.limits import LongRunWarning

    doc = _disordered_random_chain(5.0)
    doc["output"] = {"snapshot_every": 1e-310}
    with pytest.raises(bk.ParameterError, match="output.snapshot_every with run.t_end"):
        parse_config(doc)
    doc = _disordered_random_chain(5.0)
    doc["params"]["dx"] = 1e-310
    doc["initial"] = {"kind": "uniform", "value": 0.5}
    with pytest.raises(bk.ParameterError, match="params.dx.*overflows"):
        parse_config(doc)
    doc = {
        "model": "chain",
        "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        "friction": {"law": "velocity_weakening", "v_f": 0.01},
        "domain": {"blocks": 100000},
        "initial": {"kind": "uniform", "value": 0.5},
        "noise": {"law": "constant", "rate": 1e-3, "kick": 0.05},
        "run": {"max_events": 2},
        "seed": 1,
    }
    monkeypatch.setitem(bk.limits.LIMITS, "warn_wall_s", 2.0)  # (the campaign's bound)
    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        with pytest.raises(LongRunWarning, match="run.max_events = 2"):
            parse_config(doc)


def _hostile():
    sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
    import hostile

    return hostile


@pytest.mark.parametrize("sizes", [[], [3.0]])
def test_a_power_law_of_too_few_sizes_names_sizes(sizes):
    """Campaign finding (seed 1127, call 910): power_law_exponent(sizes=[]) raised numpy's
    'zero-size array to reduction operation minimum' ValueError."""
    with pytest.raises(bk.ParameterError) as e:
        bk.stats.power_law_exponent(sizes)
    assert str(e.value).startswith("invalid sizes") and "at least 2" in str(e.value)


def test_the_campaign_sees_a_run_that_is_not_what_its_config_asked(tmp_path):
    """The silent-wrong class: a run read back against its config finds nothing; against
    a config that asks for what the run did not do (another snapshot cadence, a t_end it
    did not reach, another initial value, another friction law or gamma) it says so."""
    from bkwaves.runner import run

    hostile = _hostile()
    doc = {
        "model": "chain",
        "params": {"gamma": 0.3, "v": 0.0, "dx": 0.1},
        "domain": {"blocks": 50},
        "initial": {"kind": "uniform", "value": 0.6},
        "triggers": [{"block": 0, "kind": "kick", "velocity": 2.0}],
        "run": {"t_end": 0.3},
        "output": {"snapshot_every": 0.1},  # 3 x 0.1 > 0.3: the case that lost t_end's
    }
    cfg = parse_config(doc)
    out = tmp_path / "r.nc"
    s = run(cfg, out)
    assert hostile.check_config_run(cfg, doc, s, out) is None
    other = {
        "snapshot_every": dataclasses.replace(cfg, snapshot_every=0.05),
        "t_end": dataclasses.replace(cfg, t_end=0.4),
        "[initial]": dataclasses.replace(cfg, initial=dataclasses.replace(cfg.initial, value=0.61)),
        "gamma": dataclasses.replace(cfg, params=bk.Params(gamma=0.31, v=0.0, dx=0.1)),
    }
    for what, c in other.items():
        found = hostile.check_config_run(c, doc, s, out)
        assert found and what in found, (what, found)
    law = {**doc, "friction": {"law": "velocity_weakening"}}
    assert "friction" in hostile.check_config_run(cfg, law, s, out)
    # the API: a snapshot time asked and not taken
    ch = bk.Chain(40, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0)
    r = ch.run(t_end=3.0, snapshots=[1.0, 2.0], progress=False)
    assert hostile.check_call("Chain.run", {"snapshots": [1.0, 2.0]}, r) is None
    assert "1.5" in hostile.check_call("Chain.run", {"snapshots": [1.0, 1.5]}, r)
    assert "t_end" in hostile.check_call("Chain.run", {"t_end": 4.0}, r)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG: Linux")
def test_the_campaign_worker_dies_with_the_campaign():
    """SIGKILL to the campaign while its worker is busy (here: asked to sleep 60 s)
    leaves no worker behind (it ran on, in a session of its own, until its case ended)."""
    bench = str(Path(__file__).parents[1] / "benchmarks")
    code = (
        f"import sys; sys.path.insert(0, {bench!r}); import hostile\n"
        "w = hostile._Worker(27, 20.0)\n"
        "print(w.p.pid, flush=True)\n"
        "w.ask('sleep', 60, 120.0)\n"
    )
    parent = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    worker = int(parent.stdout.readline())
    time.sleep(3.0)  # the worker is up, asked to sleep
    os.kill(parent.pid, signal.SIGKILL)
    parent.wait()
    deadline = time.time() + 20
    while time.time() < deadline:
        try:
            state = Path(f"/proc/{worker}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except FileNotFoundError:
            break
        if state == "Z":  # dead, not yet reaped
            break
        time.sleep(0.05)
    else:
        os.kill(worker, signal.SIGKILL)
        raise AssertionError("the worker outlived the campaign")
