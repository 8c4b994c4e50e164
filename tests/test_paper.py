"""`bkwaves paper --quick`: every figure written, every claim checked, nothing disagrees."""

import json
import subprocess
import sys

from bkwaves.paper import reproduce


def test_reproduce_quick(tmp_path):
    rep = reproduce(tmp_path, quick=True, progress=False)
    for name, paths in rep.figures.items():
        assert {p.suffix for p in paths} == {".png", ".pdf"}, name
        for p in paths:
            assert p.stat().st_size > 5_000, p
    assert len(rep.claims) >= 20
    bad = [c for c in rep.claims if c.verdict not in ("confirmed", "corrected", "refined")]
    assert not bad, bad
    keys = {c.key for c in rep.claims}
    for k in (
        "c",
        "c1",
        "ca",
        "ca4",
        "gammac",
        "w",
        "um",
        "A",
        "Lmin",
        "kappa",
        "amax",
        "an",
        "L",
        "b",
        "ap",
        "Tsource",
        "amax-run",
    ):
        assert k in keys
    md = (tmp_path / "report.md").read_text()
    assert "0.2719" in md and "35/128" in md
    assert (tmp_path / "report.html").read_text().startswith("<!doctype html>")


def test_paper_cli_json(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "bkwaves", "paper", "-o", str(tmp_path), "--quick", "--json"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["claims"] >= 20 and "disagrees" not in d["verdicts"]
    assert (tmp_path / "fig3_speed.png").exists()
