"""The validation report's writer (bkwaves.report): checks a reader understands, verdicts
that stand out, maths set, alt text on every figure."""

from bkwaves.report import Check, Claim, Report, pretty_math, yes_no


def test_checks_read_as_statements_not_internal_bounds():
    assert str(Check("c - 1", 0.02, lo=1e-300)) == "c - 1 = 0.02 > 0"
    assert str(Check("a'", -0.3, hi=-1e-300)) == "a' = -0.3 < 0"
    assert str(Check("kappa", 0.4, 1e-300, 1 - 1e-300)) == "kappa = 0.4, between 0 and 1"
    assert str(Check("err", 1e-9, hi=1e-6)) == "err = 1e-09 <= 1e-06"
    assert str(Check("x", 2.0)) == "x = 2"
    assert str(yes_no("a source forms", True)) == "a source forms: yes"
    assert str(yes_no("a source forms", False)) == "a source forms: no"
    assert yes_no("ok", True).holds and not yes_no("ok", False).holds
    # no pseudo-inequality of the old format survives in any of them
    for c in (Check("c - 1", 0.02, lo=1e-300), yes_no("ok", True)):
        assert "1e-300" not in str(c) and "1 <= 1" not in str(c)


def test_pretty_math_sets_symbols_and_leaves_words():
    assert pretty_math("c = 1/sqrt(1 - u_+^2)") == "c = 1/\u221a(1 - u\u208a\u00b2)"
    assert pretty_math("u_- at gamma = 0.3, dx -> 0") == "u\u208b at \u03b3 = 0.3, \u0394x \u2192 0"
    assert pretty_math("eq. (gammac), dxs, gammas") == "eq. (gammac), dxs, gammas"
    assert pretty_math("b = 1 +- 0.1, sigma^2 <= 1") == "b = 1 \u00b1 0.1, \u03c3\u00b2 \u2264 1"


def _report(tmp_path):
    ok = Check("c - 1", 0.1, lo=1e-300)
    bad = Check("paper's c", 1.3, hi=1.2)
    claims = [
        Claim("a", "(c)", "c(u_+) rises", "1/sqrt(1 - u_+)", "1/sqrt(1 - u_+^2)", [ok]),
        Claim("b", "(ca)", "series", "0.2719", "35/128", [ok], paper_check=bad),
        Claim("d", "(x)", "b = 1", "1", "n/a", [ok], applies=yes_no("CV < 0.3", False)),
    ]
    png = tmp_path / "fig3.png"
    return Report(
        claims=claims,
        figures={"fig3": [png, tmp_path / "fig3.pdf"]},
        captions={"fig3": "Front speed c(u_+) against u_+. The rest of the caption."},
        seconds=1.0,
    )


def test_html_badges_verdicts_sets_maths_and_gives_alt_text(tmp_path):
    page = _report(tmp_path).to_html()
    for verdict in ("confirmed", "corrected", "inconclusive"):
        assert "class='verdict'" in page and f">{verdict}</span>" in page
    assert "class='v-corrected'" in page
    assert "MathJax" in page
    assert "u\u208a\u00b2" in page  # u_+^2 set, not left as ASCII
    assert "alt='Front speed c(u\u208a) against u\u208a'" in page
    assert "1e-300" not in page and "(holds)" not in page
    assert "applies if:" in page and "&#10007; fails" in page


def test_markdown_keeps_every_claim_and_its_evidence(tmp_path):
    md = _report(tmp_path).to_markdown()
    assert md.count("| **") == 3
    assert "c - 1 = 0.1 > 0 (holds)" in md
    assert "CV < 0.3: no (fails)" in md
