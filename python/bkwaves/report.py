"""Claims, checks, verdicts and the validation report of ``bkwaves paper``.

No verdict is written by hand: a :class:`Claim` carries the :class:`Check` s computed in
the run, and its verdict is derived from them (:attr:`Claim.verdict`). :class:`Report`
holds every claim with the figures and writes ``report.md`` and ``report.html``.

In the HTML report the verdicts are coloured badges, the pseudo-maths of the texts
(``u_+``, ``gamma``, ``sqrt(1 - u_+^2)``) is typeset with MathJax where it is loaded and
falls back to readable Unicode offline, every figure carries alt text, and each check is
printed as a reader would state it (``c - 1 > 0``, ``a source forms: yes``) rather than as
its internal bounds.
"""

from __future__ import annotations

import html
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from . import __version__

__all__ = ["VERDICTS", "Check", "Claim", "Report", "yes_no", "pretty_math"]

#: Every verdict a claim can get, and what it means.
VERDICTS = {
    "confirmed": "bkwaves' computation agrees with the paper",
    "refined": "right, and bkwaves sharpens it (exact form, order, domain)",
    "corrected": "bkwaves' computation holds and the paper's number is off",
    "rounding": "the paper's number differs from the unrounded data only by the paper's own "
    "rounding of intermediate values (both numbers beside)",
    "inconclusive": "the check that would decide cannot apply to what was measured (its "
    "condition fails, or the measurement's uncertainty is too large to decide)",
    "identity": "holds by definition or by construction; the check only tests the engine",
    "disagrees": "a check of bkwaves' own computation failed",
}

#: Badge colours of the verdicts in report.html (background, text).
VERDICT_COLOURS = {
    "confirmed": ("#1a7f37", "#fff"),
    "refined": ("#0969da", "#fff"),
    "corrected": ("#bc4c00", "#fff"),
    "rounding": ("#6e7781", "#fff"),
    "inconclusive": ("#d4a72c", "#000"),
    "identity": ("#d0d7de", "#000"),
    "disagrees": ("#cf222e", "#fff"),
}

#: Bounds this small stand for "strictly positive" (or negative): printed as > 0.
_TINY = 1e-200


@dataclass(frozen=True)
class Check:
    """One computed quantity and the range it must lie in (bounds included).

    ``boolean`` marks a yes/no check (value 1 when it holds, see :func:`yes_no`).

    Parameters
    ----------
    what : str
        The quantity, as the report prints it.
    value : float
        Its computed value (in the unit the claim states; the paper's dimensionless ones
        unless the claim says SI).
    lo, hi : float, default -inf, inf
        The range it must lie in (same unit).
    boolean : bool, default False
        A yes/no check.

    Examples
    --------
    >>> from bkwaves.report import Check
    >>> c = Check("c - 1", 0.25, lo=1e-300)     # a tiny bound prints as "> 0"
    >>> str(c), c.holds
    ('c - 1 = 0.25 > 0', True)
    """

    what: str
    value: float
    lo: float = -math.inf
    hi: float = math.inf
    boolean: bool = False

    @property
    def holds(self) -> bool:
        """Whether lo <= value <= hi."""
        return bool(self.lo <= self.value <= self.hi)

    def __str__(self) -> str:
        """The check as a reader states it: ``what = value <= bound``, ``what > 0``,
        ``what: yes``."""
        if self.boolean:
            return f"{self.what}: {'yes' if self.value >= 1 else 'no'}"
        v = f"{self.value:.6g}"
        lo, hi = self.lo, self.hi
        lo_txt = "0" if 0 < lo <= _TINY else f"{lo:.3g}"
        hi_txt = "0" if -_TINY <= hi < 0 else f"{hi:.3g}"
        lo_op = ">" if 0 < lo <= _TINY else ">="
        hi_op = "<" if -_TINY <= hi < 0 else "<="
        if lo == -math.inf and hi == math.inf:
            return f"{self.what} = {v}"
        if lo == -math.inf:
            return f"{self.what} = {v} {hi_op} {hi_txt}"
        if hi == math.inf:
            return f"{self.what} = {v} {lo_op} {lo_txt}"
        return f"{self.what} = {v}, between {lo_txt} and {hi_txt}"


def yes_no(what: str, ok: bool) -> Check:
    """A yes/no check (value 1 when it holds).

    Parameters
    ----------
    what : str
        What is checked.
    ok : bool
        Whether it holds.

    Returns
    -------
    Check
        value 1 or 0, holding when 1.

    Examples
    --------
    >>> from bkwaves.report import yes_no
    >>> str(yes_no("a source forms", True)), yes_no("a source forms", False).holds
    ('a source forms: yes', False)
    """
    return Check(what, float(bool(ok)), lo=1.0, boolean=True)


@dataclass
class Claim:
    """One quantitative statement of the paper and bkwaves' verdict on it.

    ``checks`` test bkwaves' own computation (any failure: ``disagrees``); ``applies``
    is the condition under which the deciding check can decide (it fails: ``inconclusive``,
    e.g. a check that only applies to regular recurrence, or an uncertainty too large);
    ``paper_check`` compares the paper's number with bkwaves' (failure: ``corrected``, or
    ``rounding`` when ``rounding_check`` holds: the paper's number is reproduced by its own
    rounding of intermediate values); ``kind`` is ``"claim"`` (``confirmed``),
    ``"refinement"`` (``refined``) or ``"identity"``.

    Parameters
    ----------
    key : str
        Short name of the claim.
    equation : str
        The paper's equation label.
    statement : str
        The claim in words.
    paper : str
        The paper's number.
    bkwaves : str
        bkwaves' number.
    checks : list of Check
        Checks of bkwaves' own computation (at least one).
    paper_check : Check, optional
        The paper's number against bkwaves'.
    kind : {"claim", "refinement", "identity"}, default "claim"
        What kind of statement it is.
    note : str, default ""
        A remark printed beside it.
    applies : Check, optional
        The condition under which the deciding check can decide.
    rounding_check : Check, optional
        Whether the paper's own rounding explains a difference.

    Examples
    --------
    >>> from bkwaves.report import Check, Claim, Report
    >>> claim = Claim("c-small", "c1", "c ~ 1 + u_+^2/2 for small u_+", "1.18", "1.1808",
    ...               [Check("c - 1", 0.1808, lo=1e-300)],
    ...               paper_check=Check("|c - 1.18|", 0.0008, hi=0.005))
    >>> claim.verdict
    'confirmed'
    """

    key: str
    equation: str
    statement: str
    paper: str
    bkwaves: str
    checks: list[Check]
    paper_check: Check | None = None
    kind: str = "claim"
    note: str = ""
    applies: Check | None = None
    rounding_check: Check | None = None

    def __post_init__(self):
        if not self.checks:
            raise ValueError(f"claim {self.key!r}: a verdict needs at least one check")
        if self.kind not in ("claim", "refinement", "identity"):
            raise ValueError(f"claim {self.key!r}: kind {self.kind!r}")

    @property
    def verdict(self) -> str:
        """The verdict derived from the checks (a key of ``VERDICTS``)."""
        if not all(c.holds for c in self.checks):
            return "disagrees"
        if self.kind == "identity":
            return "identity"
        if self.applies is not None and not self.applies.holds:
            return "inconclusive"
        if self.paper_check is not None and not self.paper_check.holds:
            if self.rounding_check is not None and self.rounding_check.holds:
                return "rounding"
            return "corrected"
        return "refined" if self.kind == "refinement" else "confirmed"

    def evidence_items(self) -> list[tuple[str, str, bool]]:
        """(role, check as text, holds) for every check behind the verdict, in the order
        the verdict reads them.

        Returns
        -------
        list of tuple of (str, str, bool)
            One per check.

        Examples
        --------
        >>> from bkwaves.report import Check, Claim, Report
        >>> claim = Claim("c-small", "c1", "c ~ 1 + u_+^2/2 for small u_+", "1.18", "1.1808",
        ...               [Check("c - 1", 0.1808, lo=1e-300)],
        ...               paper_check=Check("|c - 1.18|", 0.0008, hi=0.005))
        >>> claim.evidence_items()[1]
        ('against the paper', '|c - 1.18| = 0.0008 <= 0.005', True)
        """
        out = []
        if self.applies:
            out.append(("applies if", str(self.applies), self.applies.holds))
        out += [("engine", str(c), c.holds) for c in self.checks]
        if self.paper_check:
            out.append(("against the paper", str(self.paper_check), self.paper_check.holds))
        if self.rounding_check:
            out.append(("rounding", str(self.rounding_check), self.rounding_check.holds))
        return out

    @property
    def evidence(self) -> str:
        """The checks behind the verdict, as printed in the report."""
        return "; ".join(
            f"{text} ({'holds' if ok else 'fails'})" for _, text, ok in self.evidence_items()
        )


# ----------------------------------------------------------------- maths in the HTML text

_GREEK = {
    "gamma": ("\\gamma", "\u03b3"),
    "beta": ("\\beta", "\u03b2"),
    "kappa": ("\\kappa", "\u03ba"),
    "sigma": ("\\sigma", "\u03c3"),
    "theta": ("\\theta", "\u03b8"),
    "lambda": ("\\lambda", "\u03bb"),
    "Lambda": ("\\Lambda", "\u039b"),
    "omega": ("\\omega", "\u03c9"),
    "nu": ("\\nu", "\u03bd"),
    "phi": ("\\phi", "\u03c6"),
}
_SUB = {"+": "\u208a", "-": "\u208b"}
_SUP = {"2": "\u00b2", "3": "\u00b3", "4": "\u2074"}
_TOKEN = re.compile(
    r"(?<![A-Za-z_])(?:(?P<var>[uv])_(?P<sub>[+\-c]|max|min|f|s)(?:\^(?P<pow1>[234]))?"
    r"|(?P<greek>" + "|".join(sorted(_GREEK, key=len, reverse=True)) + r")(?![A-Za-z])"
    r"(?:\^(?P<pow2>[234]))?"
    r"|dx(?![A-Za-z]))"
)


def pretty_math(text: str) -> str:
    """Set the ASCII pseudo-maths of a claim or caption in Unicode (u_+ -> u\u208a, gamma ->
    \u03b3, u_+^2 -> u\u208a\u00b2, sqrt -> \u221a, dx -> \u0394x, <= -> \u2264): readable
    offline, without a maths renderer. Words are left alone ("gammac" stays).

    Parameters
    ----------
    text : str
        The text.

    Returns
    -------
    str
        It with the symbols set.

    Examples
    --------
    >>> from bkwaves.report import pretty_math
    >>> pretty_math("c = 1/sqrt(1 - u_+^2), gamma <= 1, gammac")
    'c = 1/\u221a(1 - u\u208a\u00b2), \u03b3 \u2264 1, gammac'
    """

    def sub(m):
        if m.group("var"):
            s = m.group("sub")
            out = m.group("var") + _SUB.get(s, f"_{s}")
            if m.group("pow1"):
                out += _SUP[m.group("pow1")]
            return out
        if m.group("greek"):
            out = _GREEK[m.group("greek")][1]
            if m.group("pow2"):
                out += _SUP[m.group("pow2")]
            return out
        return "\u0394x"

    t = _TOKEN.sub(sub, text)
    t = t.replace("sqrt(", "\u221a(").replace("<=", "\u2264").replace(">=", "\u2265")
    t = t.replace("+-", "\u00b1").replace("->", "\u2192")
    return t


@dataclass
class Report:
    """What :func:`bkwaves.paper.reproduce` returns: the verdict on every claim and the
    figures written.

    Attributes
    ----------
    claims : list of Claim
        Every claim of the paper checked, with its verdict and evidence.
    figures : dict
        Figure name -> the files written (PNG and PDF).
    beyond : dict
        The same for the figures of what the paper leaves open.
    captions : dict
        Figure name -> caption.
    findings : list of str
        What bkwaves finds that the paper does not state.
    seconds : float
        Wall time of the reproduction.
    beyond_intro : str
        The paragraph that opens the "Beyond the paper" section.

    Examples
    --------
    >>> from bkwaves.report import Check, Claim, Report
    >>> claim = Claim("c-small", "c1", "c ~ 1 + u_+^2/2 for small u_+", "1.18", "1.1808",
    ...               [Check("c - 1", 0.1808, lo=1e-300)],
    ...               paper_check=Check("|c - 1.18|", 0.0008, hi=0.005))
    >>> report = Report([claim], seconds=1.0)
    >>> report.counts(), report.to_markdown().splitlines()[0]
    ({'confirmed': 1}, '# bkwaves validation report')
    """

    claims: list[Claim] = field(default_factory=list)
    figures: dict[str, list[Path]] = field(default_factory=dict)
    #: Figures of what the paper leaves open (:mod:`bkwaves.paper.beyond`), same format.
    beyond: dict[str, list[Path]] = field(default_factory=dict)
    captions: dict[str, str] = field(default_factory=dict)
    findings: list[str] = field(default_factory=list)
    seconds: float = 0.0
    beyond_intro: str = ""

    def counts(self) -> dict[str, int]:
        """Number of claims per verdict (only verdicts that occur).

        Returns
        -------
        dict
            Verdict -> count.

        Examples
        --------
        >>> from bkwaves.report import Check, Claim, Report
        >>> ok = Claim("a", "", "", "", "", [Check("x", 1.0, lo=0.0)])
        >>> bad = Claim("b", "", "", "", "", [Check("x", -1.0, lo=0.0)])
        >>> Report([ok, bad, ok]).counts()
        {'confirmed': 2, 'disagrees': 1}
        """
        out: dict[str, int] = {}
        for c in self.claims:
            out[c.verdict] = out.get(c.verdict, 0) + 1
        return out

    def to_markdown(self) -> str:
        """The report as Markdown (``report.md``): verdicts, claims, figures, findings.

        Returns
        -------
        str
            The Markdown text.

        Examples
        --------
        >>> from bkwaves.report import Check, Claim, Report
        >>> claim = Claim("c-small", "c1", "c ~ 1", "1.18", "1.1808", [Check("c", 1.18)])
        >>> [row for row in Report([claim]).to_markdown().splitlines() if "1.1808" in row]
        ['| c ~ 1 | c1 | 1.18 | 1.1808 | **confirmed** |  | c = 1.18 (holds) |']
        """
        lines = [
            "# bkwaves validation report",
            "",
            f"C. B. Muratov, Phys. Rev. E 59, 3847 (1999), reproduced by bkwaves {__version__} "
            f"in {self.seconds:.1f} s.",
            "",
            "Verdicts: " + "; ".join(f"**{k}**: {v}" for k, v in VERDICTS.items()) + ".",
            "",
            "## Claims",
            "",
            "| claim | eq. | the paper | bkwaves | verdict | note | checks |",
            "|---|---|---|---|---|---|---|",
        ]

        def cell(text: str) -> str:
            return text.replace("|", "\\|")

        for c in self.claims:
            cells = [cell(x) for x in (c.statement, c.equation, c.paper, c.bkwaves)]
            lines.append(
                "| "
                + " | ".join(cells)
                + f" | **{c.verdict}** | {cell(c.note)} | {cell(c.evidence)} |"
            )
        lines += ["", "## What bkwaves found that the paper does not say", ""]
        lines += [f"- {f}" for f in self.findings]

        def figures_md(figures: dict[str, list[Path]]) -> list[str]:
            return [
                f"### {name}\n\n![{name}]({png[0].name})\n\n{self.captions.get(name, '')}\n"
                for name, paths in figures.items()
                if (png := [p for p in paths if p.suffix == ".png"])
            ]

        lines += ["", "## Figures", ""] + figures_md(self.figures)
        if self.beyond:
            lines += ["## Beyond the paper", "", self.beyond_intro, ""] + figures_md(self.beyond)
        return "\n".join(lines) + "\n"

    def to_html(self) -> str:
        """The report as one HTML page (``report.html``), verdicts as coloured badges.

        Returns
        -------
        str
            The HTML text.

        Examples
        --------
        >>> from bkwaves.report import Check, Claim, Report
        >>> claim = Claim("c-small", "c1", "c ~ 1", "1.18", "1.1808", [Check("c", 1.18)])
        >>> page = Report([claim]).to_html()
        >>> page.startswith("<!doctype html>"), "confirmed</span>" in page
        (True, True)
        """

        def esc(text) -> str:
            return html.escape(pretty_math(str(text)))

        def badge(verdict: str) -> str:
            bg, fg = VERDICT_COLOURS.get(verdict, ("#fff", "#000"))
            return (
                f"<span class='verdict' style='background:{bg};color:{fg}'>"
                f"{html.escape(verdict)}</span>"
            )

        def checks(c: Claim) -> str:
            items = "".join(
                f"<li class='{'ok' if ok else 'fail'}'><span class='role'>{esc(role)}:</span> "
                f"{esc(text)} {'&#10003;' if ok else '&#10007; fails'}</li>"
                for role, text, ok in c.evidence_items()
            )
            return f"<ul class='checks'>{items}</ul>"

        rows = "\n".join(
            f"<tr class='v-{html.escape(c.verdict)}'>"
            + "".join(f"<td>{esc(x)}</td>" for x in (c.statement, c.equation, c.paper, c.bkwaves))
            + f"<td>{badge(c.verdict)}</td><td>{esc(c.note)}</td><td>{checks(c)}</td></tr>"
            for c in self.claims
        )
        summary = ", ".join(f"{badge(k)} {n}" for k, n in self.counts().items())
        finds = "\n".join(f"<li>{esc(f)}</li>" for f in self.findings)
        legend = "".join(f"<li>{badge(k)} {html.escape(v)}</li>" for k, v in VERDICTS.items())

        def figures_html(figures: dict[str, list[Path]]) -> str:
            out = []
            for n, ps in figures.items():
                for p in ps:
                    if p.suffix != ".png":
                        continue
                    cap = self.captions.get(n, "")
                    alt = cap.split(". ")[0] if cap else n
                    out.append(
                        f"<figure><h3>{html.escape(n)}</h3><img src='{html.escape(p.name)}' "
                        f"alt='{esc(alt)}' style='max-width:100%'>"
                        f"<figcaption>{esc(cap)}</figcaption></figure>"
                    )
            return "\n".join(out)

        figs = figures_html(self.figures)
        if self.beyond:
            figs += f"<h2>Beyond the paper</h2><p>{esc(self.beyond_intro)}</p>" + figures_html(
                self.beyond
            )
        return (
            "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
            "<title>bkwaves validation report</title>"
            # MathJax typesets any TeX (\\( ... \\)) where it can load; the texts are set in
            # Unicode already, so the page reads the same offline
            "<script>window.MathJax={tex:{inlineMath:[['\\\\(','\\\\)']]}};</script>"
            "<script async src='https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-chtml.js'>"
            "</script>"
            "<style>body{font-family:sans-serif;max-width:1200px;margin:auto;line-height:1.4}"
            "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px 8px;"
            "font-size:13px;vertical-align:top}figcaption{font-size:14px;margin-bottom:2em}"
            ".verdict{border-radius:4px;padding:1px 6px;font-weight:bold;white-space:nowrap}"
            "ul.checks{margin:0;padding-left:1.1em}ul.checks li.fail{color:#cf222e}"
            ".role{color:#57606a}"
            "</style></head><body>"
            f"<h1>bkwaves validation report</h1><p>C. B. Muratov, Phys. Rev. E 59, 3847 "
            f"(1999), reproduced by bkwaves {html.escape(__version__)} in "
            f"{self.seconds:.1f} s.</p><p>{summary}</p><ul>{legend}</ul><h2>Claims</h2>"
            "<table><tr><th>claim</th><th>eq.</th><th>the paper</th><th>bkwaves</th>"
            f"<th>verdict</th><th>note</th><th>checks</th></tr>{rows}</table>"
            "<h2>What bkwaves found that the paper does not say</h2>"
            f"<ul>{finds}</ul><h2>Figures</h2>{figs}</body></html>"
        )
