"""`bkwaves paper --quick`: every figure written, every claim checked, nothing disagrees."""

import json
import re
import subprocess
import sys

import pytest

FIGURES = [
    "fig1_model",
    "fig2_friction",
    "fig3_speed",
    "fig4_waves",
    "fig5_wave_train",
    "fig6_source",
    "fig7_source_map",
    "fig8_statistics",
    "fig9_sync_chaos",
]


@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper")
    r = subprocess.run(
        [sys.executable, "-m", "bkwaves", "paper", "-o", str(out), "--quick", "--json"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    return out, json.loads(r.stdout)


def test_every_figure_written(paper):
    out, d = paper
    assert sorted(d["figures"]) == sorted(FIGURES)
    for name in FIGURES:
        for ext in ("png", "pdf"):
            assert (out / f"{name}.{ext}").stat().st_size > 5_000, name


def test_every_claim_checked_and_none_disagrees(paper):
    out, d = paper
    assert d["claims"] >= 25 and "disagrees" not in d["verdicts"]
    md = (out / "report.md").read_text()
    rows = [line for line in md.splitlines() if line.startswith("| ") and "**" in line]
    assert len(rows) == d["claims"]
    verdicts = re.findall(r"\*\*(\w[\w ]*)\*\*", md)
    assert set(verdicts) <= {"confirmed", "corrected", "refined"}
    for eq in (
        "(c)",
        "(c1)",
        "(ca)",
        "(gammac)",
        "(w)",
        "(um)",
        "(A)",
        "(L)",
        "(Lmin)",
        "(b)",
        "(ap)",
        "(kappa)",
        "(amax)",
        "(crit)",
    ):
        assert f"| {eq} |" in md or f"| {eq}, " in md, eq
    assert "0.2719" in md and "35/128" in md and "Bristol board" in md
    assert (out / "report.html").read_text().startswith("<!doctype html>")
