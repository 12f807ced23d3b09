"""Sphinx configuration of the clutchlab documentation (MyST Markdown pages, numpydoc docstrings,
the PyData theme). The parameter, output, config and API reference pages are generated from the
code (clutchlab.reference_docs) before the sources are read."""

import sys
from pathlib import Path

DOCS = Path(__file__).parent
sys.path.insert(0, str(DOCS.parent / "src"))

import clutchlab  # noqa: E402
from clutchlab import reference_docs  # noqa: E402

project = "clutchlab"
author = "clutchlab developers"
release = clutchlab.__version__
version = release

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build"]
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

autosummary_generate = False
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
# a References section lists its sources without citing each in the text
suppress_warnings = ["ref.citation"]

intersphinx_mapping = {}  # no network at build time

html_theme = "pydata_sphinx_theme"
html_title = f"clutchlab {release}"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}

# link check: internal links and anchors only (the build runs without network)
linkcheck_ignore = [r"https?://.*"]
linkcheck_anchors = True


def _generate(app):
    reference_docs.write_pages(DOCS / "reference", DOCS / "api")


def setup(app):
    app.connect("builder-inited", _generate)
