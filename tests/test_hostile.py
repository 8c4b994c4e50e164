"""Inputs from the hostile-input campaign (issue 27; benchmarks/hostile.py,
docs/reliability.md): runs that never ended, lengths without a range, and a fixed-seed
slice of the campaign itself."""

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
