"""Sphinx configuration of the bkwaves documentation.

Build: ``pip install .[docs] && sphinx-build -W -n docs docs/_build/html`` (warnings are
errors, every cross-reference must resolve, the tutorials are executed).
"""

from __future__ import annotations

import datetime
import os
import re

import bkwaves

project = "bkwaves"
author = "The bkwaves developers"
copyright = f"{datetime.date.today().year}, {author}"  # noqa: A001
release = bkwaves.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",  # also loads myst_parser for the Markdown pages
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = [
    "_build",
    "scripts",
    "jupyter_execute",
    "**.ipynb_checkpoints",
    "README.md",
]

# -- API reference ---------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = False
autodoc_typehints = "none"  # numpydoc's Parameters/Returns carry the types
numpydoc_show_class_members = False  # the class templates list members themselves
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_attributes_as_param_list = False

# No network at build time, so no intersphinx: references into other projects' docs
# (numpy, xarray, pandas, ...) cannot resolve and are not checked; every reference into
# bkwaves must resolve (nitpicky).
_OTHERS = (
    "numpy|np|xarray|xr|pandas|pd|pyarrow|pa|matplotlib|mpl|plt|scipy|distributed|dask"
    "|zarr|adaptive|rich|pathlib|os|typing|collections|dataclasses|datetime|enum|numbers"
)
nitpick_ignore_regex = [(r"py:.*", rf"({_OTHERS})(\..*)?")]

# -- MyST and the executed tutorials ---------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = os.environ.get("BKWAVES_DOCS_EXECUTE", "force")
nb_execution_timeout = 120  # per cell; each tutorial is written to run in under a minute
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# -- HTML ------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"bkwaves {release}"
html_static_path: list[str] = []
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version", "theme-version"],
}
html_context = {"default_mode": "light"}
autosummary_ignore_module_all = False


# -- Plain-text mathematics in docstrings ----------------------------------------------
# The docstrings write the paper's symbols in ASCII as the terminal shows them (u_+, u_-,
# |u_x|); in reStructuredText a word followed by "_" is a link and |...| a substitution.
# Escape those two outside literals, doctests and roles, so help() and the site read alike.
_LITERAL = re.compile(r"(``.*?``|:\w+:`[^`]*`|`[^`]*`_?_?)")
_TRAILING_UNDERSCORE = re.compile(r"(?<=\w)_(?=[^\w`]|$)")


def _escape_segment(text: str) -> str:
    text = _TRAILING_UNDERSCORE.sub(r"\\_", text)
    return re.sub(r"(?<=\S)\||\|(?=\S)", r"\\|", text)


def _escape_ascii_math(app, what, name, obj, options, lines):
    literal_indent = None
    for k, line in enumerate(lines):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if literal_indent is not None:
            if stripped and indent <= literal_indent:
                literal_indent = None
            else:
                continue
        if stripped.startswith((">>>", "...", "..")):
            continue
        parts = _LITERAL.split(line)
        lines[k] = "".join(p if i % 2 else _escape_segment(p) for i, p in enumerate(parts))
        if stripped.endswith("::"):
            literal_indent = indent


def setup(app):
    app.connect("autodoc-process-docstring", _escape_ascii_math, priority=600)
