"""`bkwaves paper --quick`: every figure written and captioned, every claim checked, every
verdict and note computed in the run, nothing disagrees."""

import ast
import dataclasses
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from figure_checks import figure_problems

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

#: The modules of the paper package (figures, claims, report).
PAPER_PY = sorted(
    (Path(__file__).resolve().parents[1] / "python" / "bkwaves" / "paper").rglob("*.py")
)


#: What :func:`figure_problems` found in each figure of the ``paper`` fixture's run.
FIGURE_PROBLEMS: dict[str, list[str]] = {}


@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    """`bkwaves paper --quick --json`, run once in this process so that every figure is
    also checked by :func:`figure_problems` just before it is saved."""
    import contextlib
    import io

    import bkwaves.paper
    from bkwaves.cli import main
    from bkwaves.paper import figure

    out = tmp_path_factory.mktemp("paper")
    save = figure.save

    def checked_save(fig, where, name):
        FIGURE_PROBLEMS[name] = figure_problems(fig)
        return save(fig, where, name)

    stdout = io.StringIO()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(figure, "save", checked_save)
        with contextlib.redirect_stdout(stdout), pytest.raises(SystemExit) as done:
            main(["paper", "-o", str(out), "--quick", "--json"])
    assert done.value.code in (0, None)
    yield out, json.loads(stdout.getvalue())
    bkwaves.paper.common.CACHE.clear()  # the run's shared computations, not needed past here


def test_figures_readable(paper):
    assert sorted(FIGURE_PROBLEMS) == sorted([*paper[1]["figures"], *paper[1]["beyond_figures"]])
    problems = {k: v for k, v in FIGURE_PROBLEMS.items() if v}
    assert not problems, problems


def _rows(d):
    return {row["key"]: row for row in d["rows"]}


def test_every_figure_written(paper):
    out, d = paper
    assert sorted(d["figures"]) == sorted(FIGURES)
    for name in FIGURES:
        for ext in ("png", "pdf"):
            assert (out / f"{name}.{ext}").stat().st_size > 5_000, name


def test_every_claim_checked_and_none_disagrees(paper):
    out, d = paper
    assert d["claims"] >= 30 and "disagrees" not in d["verdicts"], d["verdicts"]
    md = (out / "report.md").read_text()
    rows = [line for line in md.splitlines() if line.startswith("| ") and "**" in line]
    assert len(rows) == d["claims"]
    verdicts = re.findall(r"\| \*\*(\w[\w ]*)\*\* \|", md)
    assert set(verdicts) <= {
        "confirmed",
        "corrected",
        "refined",
        "identity",
        "rounding",
        "inconclusive",
    }
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


def test_verdicts_follow_from_checks_that_could_fail(paper):
    """Every row carries computed checks, each with a finite bound (it could have failed),
    and its verdict is the one its checks give."""
    _, d = paper
    for row in d["rows"]:
        assert row["checks"], row["key"]
        checks = row["checks"] + [row[k] for k in ("paper_check", "applies", "rounding_check")]
        checks = [c for c in checks if c]
        for c in checks:
            assert math.isfinite(c["lo"]) or math.isfinite(c["hi"]), (row["key"], c)
            assert math.isfinite(c["value"]), (row["key"], c)
            assert c["holds"] == (c["lo"] <= c["value"] <= c["hi"]), (row["key"], c)
        if not all(c["holds"] for c in row["checks"]):
            expected = "disagrees"
        elif row["kind"] == "identity":
            expected = "identity"
        elif row["applies"] and not row["applies"]["holds"]:
            expected = "inconclusive"
        elif row["paper_check"] and not row["paper_check"]["holds"]:
            rounding = row["rounding_check"]
            expected = "rounding" if rounding and rounding["holds"] else "corrected"
        else:
            expected = {"claim": "confirmed", "refinement": "refined"}[row["kind"]]
        assert row["verdict"] == expected, row["key"]


def test_claim_verdict_is_computed_not_given():
    from bkwaves.paper import Check, Claim

    ok, bad = Check("x", 0.5, hi=1.0), Check("x", 2.0, hi=1.0)
    c = Claim("k", "(e)", "s", "p", "b", [ok])
    assert c.verdict == "confirmed"
    assert Claim("k", "(e)", "s", "p", "b", [ok, bad]).verdict == "disagrees"
    assert Claim("k", "(e)", "s", "p", "b", [ok], paper_check=bad).verdict == "corrected"
    assert Claim("k", "(e)", "s", "p", "b", [bad], kind="identity").verdict == "disagrees"
    assert Claim("k", "(e)", "s", "p", "b", [ok], kind="identity").verdict == "identity"
    # a deciding check that cannot apply: inconclusive, whatever the paper check says
    assert Claim("k", "(e)", "s", "p", "b", [ok], paper_check=ok, applies=bad).verdict == (
        "inconclusive"
    )
    assert Claim("k", "(e)", "s", "p", "b", [ok], paper_check=bad, applies=ok).verdict == (
        "corrected"
    )
    # the paper's own rounding explains the difference
    r = Claim("k", "(e)", "s", "p", "b", [ok], paper_check=bad, rounding_check=ok)
    assert r.verdict == "rounding"
    assert Claim("k", "(e)", "s", "p", "b", [ok], paper_check=ok, rounding_check=bad).verdict == (
        "confirmed"
    )
    with pytest.raises(ValueError, match="check"):
        Claim("k", "(e)", "s", "p", "b", [])
    with pytest.raises(TypeError):
        Claim("k", "(e)", "s", "p", "b", [ok], verdict="confirmed")  # no hand-written verdict


def _literal_text(node) -> list[str]:
    """The literal parts of a string expression (constants, f-string text)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.JoinedStr):
        return [v.value for v in node.values if isinstance(v, ast.Constant)]
    if isinstance(node, ast.BinOp):
        return _literal_text(node.left) + _literal_text(node.right)
    return []


def test_no_verdict_or_number_in_a_note_is_written_by_hand():
    """In the paper package no Claim gets a verdict, and no note holds a number typed in (a decimal
    or a number of two or more digits: 'CV ~ 0.7', 'margin 1.26'): numbers come from
    formatted computed values."""
    from bkwaves.paper import Claim

    calls = [
        n
        for path in PAPER_PY
        for n in ast.walk(ast.parse(path.read_text()))
        if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "Claim"
    ]
    assert len(calls) >= 25
    number = re.compile(r"\d\.\d|\d{2,}")
    names = [f.name for f in dataclasses.fields(Claim)]
    for call in calls:
        kw = {k.arg: k.value for k in call.keywords}
        kw.update(zip(names, call.args, strict=False))
        assert "verdict" not in kw, call.lineno
        texts = []
        if "note" in kw:
            texts += _literal_text(kw["note"])
        for t in texts:
            assert not number.search(t), (call.lineno, t)


def test_identities_are_called_identities(paper):
    _, d = paper
    rows = _rows(d)
    assert rows["A"]["verdict"] == "identity"
    assert rows["gr-train"]["verdict"] == "identity"


def test_lmin_trains_simulated_on_both_sides(paper):
    _, d = paper
    row = _rows(d)["Lmin"]
    what = [c["what"] for c in row["checks"]]
    assert any("no train on a ring of 0.9" in w for w in what)
    assert any("a train on a ring of 1.0" in w for w in what)
    assert row["verdict"] == "confirmed"


def test_wave_train_selects_its_amplitude(paper):
    """(L): the run starts from uniform stress, so u_+ comes from the dynamics."""
    out, d = paper
    row = _rows(d)["L"]
    assert row["verdict"] == "confirmed"
    sel = next(c for c in row["checks"] if c["what"].startswith("selected u_+"))
    assert abs(sel["value"]) < 1e-5
    md = (out / "report.md").read_text()
    assert "from uniform u = 0.5" in md


def test_sync_exponent_measured_with_uncertainty(paper):
    from bkwaves.paper import SYNC_DECIDE

    _, d = paper
    row = _rows(d)["sync-R"]
    assert row["paper_check"] is not None and row["applies"] is not None
    # the exponent decides only when settled and known to SYNC_DECIDE; else inconclusive
    if not row["applies"]["holds"]:
        assert row["verdict"] == "inconclusive" and "undecided" in row["note"]
    else:
        z = row["paper_check"]["value"]
        assert row["verdict"] == ("confirmed" if abs(z) <= 2 else "corrected")
    assert "bootstrap" in row["applies"]["what"] and f"{SYNC_DECIDE:g}" in row["applies"]["what"]
    assert _rows(d)["sync"]["verdict"] == "confirmed"
    # the quick run's rings cannot hold regions of the paper's size: no verdict on it
    assert _rows(d)["sync-R-prefactor"]["verdict"] == "inconclusive"


def _rings(p, rings, periods, scatter, seed):
    """Synthetic sites(n) on rings of L = 1600: L / (R0 n^p) with a log-normal scatter per
    ring (the rings' own prefactor) and rounding to whole sources."""
    rng = np.random.default_rng(seed)
    n = np.arange(1, periods + 1)
    res = {}
    for k in range(rings):
        R = 60.0 * np.exp(scatter * rng.standard_normal()) * n**p
        res[f"smooth-{k}"] = {"sites": np.maximum(np.round(1600.0 / R), 1)}
    return dict(res=res, L=1600.0)


def test_coarsening_exponent_bootstrap_over_rings_recovers_a_known_exponent():
    from bkwaves.paper import coarsening_exponent

    # 64 rings, exponent 0.5 and a ring-to-ring scatter: every window finds it within
    # 3 bootstrap errors, the errors honest (the per-ring fit errors would be far smaller)
    f = coarsening_exponent(_rings(0.5, 64, 160, 0.15, 1))
    assert [w["window"] for w in f["local"]] == [(10, 20), (20, 40), (40, 80), (80, 160)]
    for w in f["local"]:
        assert abs(w["p"] - 0.5) <= 3 * w["sigma"] and w["sigma"] < 0.1, w
    # a rising local exponent is seen as drift between the last two windows
    g = _rings(0.5, 64, 160, 0.0, 2)
    n = np.arange(1, 161)
    local = np.interp(n[1:], [10, 40, 160], [0.2, 0.3, 0.7])  # the exponent rises
    logR = np.cumsum(np.r_[0.0, np.diff(np.log(n)) * local])
    for r in g["res"].values():
        r["sites"] = np.maximum(np.round(1600.0 / (30.0 * np.exp(logR))), 1)
    h = coarsening_exponent(g)
    assert h["drift"] > 2 * h["drift_sigma"]
    # three rings: the bootstrap error reflects the few rings, not the fit residuals
    few = coarsening_exponent(_rings(0.5, 3, 160, 0.3, 3))
    many = coarsening_exponent(_rings(0.5, 48, 160, 0.3, 3))
    assert few["local"][0]["sigma"] > 2 * many["local"][0]["sigma"]


def test_bristol_gamma_unrounded_and_how_the_paper_gets_its_value(paper):
    out, d = paper
    row = _rows(d)["bristol-gamma"]
    # the paper's 0.45 is its own rounding of m and k_c: "rounding", both numbers beside
    assert row["verdict"] == "rounding" and _rows(d)["bristol-k_p"]["verdict"] == "rounding"
    md = (out / "report.md").read_text()
    line = next(x for x in md.splitlines() if x.startswith("| Bristol board: gamma |"))
    assert "unrounded" in line and "with the paper's rounded m and k_c" in line
    assert _rows(d)["bristol-m"]["verdict"] == "confirmed"
    assert "0.4443" in row["note"] and "0.4466" in row["note"]
    assert _rows(d)["crit"]["note"].count("1.25") == 1


def test_b_value_row_is_inconclusive_where_its_check_cannot_apply(paper):
    from bkwaves.paper import B_CHAIN_REGULAR_CV

    _, d = paper
    row = _rows(d)["b-chain"]
    cv = row["applies"]["value"]
    assert row["applies"]["hi"] == B_CHAIN_REGULAR_CV
    if cv > B_CHAIN_REGULAR_CV:
        assert row["verdict"] == "inconclusive" and "cannot apply" in row["note"]
    else:
        assert row["verdict"] in ("refined", "corrected")


def test_beyond_the_paper_section(paper):
    """Every registered "beyond the paper" figure is written, captioned from the run and
    placed in its own section after the paper's figures."""
    from bkwaves.paper import BEYOND_FIGURES

    out, d = paper
    assert sorted(d["beyond_figures"]) == sorted(BEYOND_FIGURES)
    md = (out / "report.md").read_text()
    for name in BEYOND_FIGURES:
        for ext in ("png", "pdf"):
            assert (out / f"{name}.{ext}").stat().st_size > 5_000, name
        section = md.split("## Beyond the paper\n", 1)[1]
        block = section.split(f"### {name}\n", 1)[1].split("###", 1)[0]
        assert len(block.split(".png)", 1)[1].strip()) > 80, name


def test_beyond_section_renders_only_when_there_are_figures(tmp_path):
    from bkwaves.paper import Report

    empty = Report()
    assert "Beyond the paper" not in empty.to_markdown() + empty.to_html()
    png = tmp_path / "x.png"
    rep = Report(beyond={"x": [png]}, captions={"x": "a caption from the run"})
    md, page = rep.to_markdown(), rep.to_html()
    assert md.index("## Figures") < md.index("## Beyond the paper") < md.index("### x")
    assert "a caption from the run" in md and "<h2>Beyond the paper</h2>" in page
    assert page.count("<figcaption>") == 1


def test_every_figure_has_a_caption(paper):
    out, _ = paper
    md = (out / "report.md").read_text()
    html = (out / "report.html").read_text()
    from bkwaves.paper import BEYOND_FIGURES

    assert html.count("<figcaption>") == len(FIGURES) + len(BEYOND_FIGURES)
    for name in FIGURES:
        block = md.split(f"### {name}\n", 1)[1].split("###", 1)[0]
        caption = block.split(".png)", 1)[1].strip()
        assert len(caption) > 80, name
        assert "bk." in caption or "schematic" in caption.lower() or "law" in caption, name


def test_paper_help_says_what_quick_saves():
    r = subprocess.run(
        [sys.executable, "-m", "bkwaves", "paper", "--help"], capture_output=True, text=True
    )
    assert r.returncode == 0
    text = " ".join(r.stdout.split())
    assert "minutes -> seconds" not in text
    assert "seeds" in text and "docs/benchmarks.md" in text


def test_plot_gives_no_b_value_for_a_small_catalog():
    from bkwaves import plot

    rng = np.random.default_rng(0)
    ax = plot.size_frequency(10 ** rng.uniform(0, 1, 6))
    assert "b =" not in ax.get_title() and "too few" in ax.get_title()
    ax = plot.size_frequency(10 ** rng.exponential(1.0, 400))
    assert ax.get_title().startswith("b = ")


def _paper_cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "bkwaves", "paper", "--quick", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=900,
    )


def test_paper_refuses_a_users_report(tmp_path):
    """`bkwaves paper -o DIR` never replaces a file it did not write: refused before any
    work without --overwrite, and with it too (no record that bkwaves wrote it)."""
    mine = tmp_path / "report.md"
    mine.write_text("my notes\n")
    (tmp_path / "data.csv").write_text("1,2\n")
    for extra in ([], ["--overwrite"]):
        r = _paper_cli("-o", tmp_path, *extra)
        assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
        line = r.stderr.strip()
        assert line.startswith("Error: ") and "\n" not in line and "report.md" in line
        assert ("--overwrite" in line) != bool(extra)
        assert "not written by bkwaves" in line or not extra
    assert mine.read_text() == "my notes\n" and (tmp_path / "data.csv").read_text() == "1,2\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data.csv", "report.md"]


def test_paper_output_is_recorded_and_guarded(paper):
    """What `bkwaves paper` wrote is in its manifest with checksums; a second run into the
    folder is refused without --overwrite, and a file the user changed since is refused
    with it."""
    import hashlib

    from bkwaves.paper import MANIFEST, output_files

    out, _ = paper
    doc = json.loads((out / MANIFEST).read_text())
    assert sorted(doc["files"]) == sorted(output_files())
    for name, digest in doc["files"].items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == digest
    r = _paper_cli("-o", out)
    assert r.returncode == 2 and "--overwrite" in r.stderr and "Traceback" not in r.stderr
    html = out / "report.html"
    before = html.read_bytes()
    try:
        html.write_bytes(before + b"<!-- my edit -->")
        r = _paper_cli("-o", out, "--overwrite")
        assert r.returncode == 2 and "report.html" in r.stderr and "changed since" in r.stderr
        assert html.read_bytes().endswith(b"<!-- my edit -->")
    finally:
        html.write_bytes(before)


def test_owned_files_replace_only_their_own(tmp_path):
    """The policy behind `bkwaves paper`: a recorded, unchanged file is replaced with
    overwrite; a user's file beside it is untouched; a user's file in the way is not."""
    from bkwaves._core import ParameterError
    from bkwaves._paths import OwnedFiles

    (tmp_path / "notes.txt").write_text("mine")
    a = OwnedFiles(tmp_path, "m.json", command="test")
    a.claim(["f.txt"], overwrite=False)
    a.write("f.txt", lambda p: p.write_text("one"))
    with pytest.raises(ParameterError, match="--overwrite"):
        OwnedFiles(tmp_path, "m.json", command="test").claim(["f.txt"], overwrite=False)
    b = OwnedFiles(tmp_path, "m.json", command="test")
    b.claim(["f.txt", "g.txt"], overwrite=True)
    b.write("f.txt", lambda p: p.write_text("two"))
    assert (tmp_path / "f.txt").read_text() == "two"
    (tmp_path / "g.txt").write_text("the user's")
    with pytest.raises(ParameterError, match="g.txt"):
        OwnedFiles(tmp_path, "m.json", command="test").claim(["f.txt", "g.txt"], True)
    (tmp_path / "m.json").write_text("not a manifest")
    (tmp_path / "g.txt").unlink()
    with pytest.raises(ParameterError, match="m.json"):
        OwnedFiles(tmp_path, "m.json", command="test").claim(["f.txt"], True)
    assert (tmp_path / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.txt", "m.json", "notes.txt"]
