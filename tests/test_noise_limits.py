"""The noise candidates in the run-cost estimate (bkwaves.limits, docs/noise.md, "The
thinning envelope"; docs/usage.md, "Limits"): a fuzz finding, a valid config with a huge
rate or a table peaking far above g(1) below the threshold ran for hours without a word."""

import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves.config import initial_state, parse_config
from bkwaves.limits import LIMITS, LongRunWarning, estimate, noise_envelope, noise_work

EXAMPLES = Path(__file__).parents[1] / "examples"

#: the peaked table of docs/noise.md's thinning test: rises to 3, falls to 0.5, rises
#: through the plateau (G(1) = 3 > g(1) = 1), with a zero stretch
PEAKED = {"law": "table", "u": [0.0, 0.1, 0.35, 0.6, 0.7, 0.9, 1.0], "g": [0, 0, 3, 0.5, 0, 2, 1]}


def example(name: str, t_end: float, noise: dict | None = None) -> dict:
    doc = tomllib.loads((EXAMPLES / f"{name}.toml").read_text())
    doc.pop("output", None)
    doc["run"] = {"t_end": t_end}
    if noise is not None:
        doc["noise"] = noise
    return doc


def chain_doc(t_end, noise):
    return example("chain_noise", t_end, {"kick": 0.05, **noise})


def fb_doc(t_end, noise):
    return example("free_boundary_noise", t_end, noise)


def warned_first(doc, *words):
    """The warning, raised as an error: before any work (issue 27: an estimate alone never
    refuses a run; it warns)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        with pytest.raises(LongRunWarning) as e:
            parse_config(doc)
    msg = str(e.value)
    assert all(w in msg for w in words), msg
    return msg


def warned(doc, *words):
    with pytest.warns(LongRunWarning) as w:
        parse_config(doc)
    msg = " ".join(str(x.message) for x in w)
    assert all(w in msg for w in words), msg
    return msg


def test_the_envelope_is_the_running_maximum_of_the_law():
    """G(1) and the mean of G over [0, 1] against the running maximum of g on a fine grid
    (np.maximum.accumulate), and the closed forms of the other laws."""
    u = np.linspace(-1.0, 1.0, 2_000_001)
    g = np.interp(u, PEAKED["u"], PEAKED["g"])
    running = np.maximum.accumulate(g)
    g_top, g_mean = noise_envelope({**PEAKED, "rate": 1.0})
    assert g_top == pytest.approx(3.0, rel=1e-12) == running[-1]
    inside = u >= 0
    assert g_mean == pytest.approx(np.trapezoid(running[inside], u[inside]), rel=1e-6)
    # a table normalised by g(1) = 2, and one whose maximum is beyond the threshold
    top, _ = noise_envelope({"law": "table", "u": [0.0, 0.5, 1.0, 2.0], "g": [0, 8, 2, 50]})
    assert top == pytest.approx(4.0)
    assert noise_envelope({"law": "exponential", "phi0": 0.01}) == pytest.approx((1.0, 0.01))
    assert noise_envelope({"law": "power", "exponent": 3.0}) == (1.0, 0.25)
    assert noise_envelope({"law": "constant"}) == (1.0, 1.0)


def test_a_huge_noise_rate_is_warned_naming_noise_rate():
    """Both engines: a rate that makes the candidates cost more than an hour is warned,
    naming noise.rate (fails without the noise estimate: the configs were accepted in
    silence)."""
    for doc_of in (chain_doc, fb_doc):
        warned_first(
            doc_of(100.0, {"law": "exponential", "phi0": 0.05, "rate": 1e12}), "noise.rate", "years"
        )
        msg = warned(doc_of(100.0, {"law": "constant", "rate": 1e7}), "noise.rate")
        assert "noise candidates" in msg, msg
        # an ordinary rate: no word
        with warnings.catch_warnings():
            warnings.simplefilter("error", LongRunWarning)
            parse_config(doc_of(100.0, {"law": "constant", "rate": 1e-2}))


def test_a_physical_noise_rate_is_named_in_its_si_units():
    """[physical]: the message gives the rate as written (1/s) and in time units."""
    doc = chain_doc(1e-3, {"law": "exponential", "phi0": 0.05, "rate": 1e12, "kick": 1e-3})
    doc.pop("params")
    doc["physical"] = {"preset": "bristol_board", "V": 1e-6}
    doc["initial"] = {"kind": "uniform", "value": 0.5}
    doc["run"] = {"t_end": 1e-3}  # s: 3.1e3 time units of 3.2e-7 s
    msg = warned(doc, "noise.rate = 1e+12 1/s (= 3.2e+05 per block and time unit)")
    assert "run.t_end = 0.001 s" in msg, msg


def test_a_table_peaking_far_above_g1_below_the_threshold_names_noise_g():
    """g(1) = 1 and a peak of 1e10 at u = 0.3: the candidates fall at rate x G(1) while
    blocks slide (chain) and once the bound passes 0.3; warned naming noise.g. A peak of
    1e6 warns too; the same rate with the peak at g(1) does not."""
    peak = {"law": "table", "u": [0.0, 0.3, 0.5, 1.0], "g": [0.0, 1e10, 0.5, 1.0], "rate": 1.0}
    for doc_of in (chain_doc, fb_doc):
        warned_first(doc_of(1e3, peak), "noise.g", "G(1) = 1e+10")
        warned(doc_of(1e3, {**peak, "g": [0.0, 1e6, 0.5, 1.0]}), "noise.g")
        with warnings.catch_warnings():
            warnings.simplefilter("error", LongRunWarning)
            parse_config(doc_of(1e3, {**peak, "g": [0.0, 1.0, 0.5, 1.0]}))


def test_the_engines_run_calls_count_the_candidates_too(monkeypatch):
    """bk.Chain.run and bk.FreeBoundary.run check their t_end with the noise. With the
    warning lowered to 5 s, runs whose candidates (almost all rejected) take tens of
    seconds are warned before any work (before the estimate counted them, these ran them
    in silence; the warning raised as an error here stops them)."""
    monkeypatch.setitem(LIMITS, "warn_wall_s", 5.0)
    warnings.simplefilter("error", LongRunWarning)
    # a chain sliding all the time (gamma > 1 creep): every candidate falls on a sliding
    # block, at the rate 100 x rate
    p = bk.Params(gamma=1.5, v=0.5, dx=0.05)
    noise = {"law": "exponential", "phi0": 0.01, "rate": 1.5e4}
    ch = bk.Chain(100, p, "periodic", u0=0.99, u_t0=p.v - 1.0, noise=noise, seed=1)
    cand, wall = noise_work("chain", 100, 100, 20.0, p.v, ch.noise)
    assert cand == pytest.approx(3e7) and wall > 5.0
    with pytest.raises(LongRunWarning, match="noise.rate = 15000 with t_end = 20"):
        ch.run(t_end=20.0)
    assert ch.t == 0.0
    # a free boundary ring at u = 0.65 under a table peaking at 2e4 g(1) at u = 0.35
    p = bk.Params(gamma=0.3, v=1e-3, dx=0.05)
    x = np.linspace(0.0, 100.0, 500, endpoint=False)
    noise = {**PEAKED, "g": [0, 0, 2e4, 0.5, 0, 2, 1], "rate": 1.0}
    fb = bk.FreeBoundary(p, x, np.full(x.size, 0.65), "periodic", noise=noise, seed=1)
    with pytest.raises(LongRunWarning, match=r"noise.g \(its peak below u = 1 is G\(1\) = 2e\+04"):
        fb.run(t_end=100.0)
    assert fb.time == 0.0


def run_counts(doc):
    """The noise candidates of a real run of the config ``doc``, and the estimate's."""
    cfg = parse_config(doc)
    if cfg.model == "chain":
        ch = bk.Chain(
            cfg.blocks, cfg.params, cfg.boundary, initial_state(cfg), seed=cfg.seed, noise=cfg.noise
        )
        measured = ch.run(t_end=cfg.t_end).counters["noise_candidates"]
    else:
        fb = bk.FreeBoundary(
            cfg.params,
            cfg.x(),
            initial_state(cfg),
            cfg.boundary,
            noise=cfg.noise,
            seed=cfg.seed,
            record_path=False,
        )
        fb.run(t_end=cfg.t_end)
        measured = fb._engine.noise_counters[0]
    est = estimate(cfg)
    size = cfg.blocks if cfg.model == "chain" else cfg.length
    n = cfg.blocks or cfg.grid
    assert (
        est.noise_candidates
        == noise_work(cfg.model, size, n, cfg.t_end, cfg.params.v, cfg.noise)[0]
    )
    return measured, est.noise_candidates


@pytest.mark.parametrize(
    "doc",
    [
        chain_doc(600.0, {"law": "exponential", "phi0": 0.05, "rate": 1e-2}),
        chain_doc(200.0, {**PEAKED, "g": [0, 0, 100, 0.5, 0, 2, 1], "rate": 1e-2}),
        fb_doc(1000.0, {"law": "exponential", "phi0": 0.05, "rate": 1e-2}),
        fb_doc(300.0, {**PEAKED, "g": [0, 0, 100, 0.5, 0, 2, 1], "rate": 1e-2}),
    ],
    ids=["chain-exponential", "chain-table", "fb-exponential", "fb-table"],
)
def test_the_estimate_of_candidates_is_within_an_order_of_magnitude_of_a_run(doc):
    """The examples' rings (random start, loading through many events) with the examples'
    law and a table peaking at 100 g(1) below the threshold."""
    measured, est = run_counts(doc)
    assert measured > 100
    print(f"candidates: measured {measured}, estimated {est:.4g}, ratio {est / measured:.3g}")
    assert 0.1 < est / measured < 10, (measured, est)


NOISY_EXAMPLES = [
    p for p in sorted(EXAMPLES.glob("*.toml")) if "noise" in tomllib.loads(p.read_text())
]


@pytest.mark.parametrize("path", NOISY_EXAMPLES, ids=lambda p: p.stem)
def test_the_examples_noise_runs_are_not_warned(path):
    """Every example with a [noise] table, as it is and run on to 100 loadings of its
    field (t_end = 100 / v): no LongRunWarning, and the noise costs under a minute."""
    assert len(NOISY_EXAMPLES) >= 2
    doc = tomllib.loads(path.read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("error", LongRunWarning)
        parse_config(doc)
        doc["run"] = {"t_end": 100.0 / doc["params"]["v"]}
        est = estimate(parse_config(doc))
    assert 0 < est.noise_wall_s < 60.0, est
