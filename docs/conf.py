"""Sphinx configuration of resonant's documentation site.

Build it with ``python -m sphinx -W --keep-going -b html docs docs/_build/html``
(warnings are errors).  Sphinx, because numpydoc — the docstring standard of the
scientific Python stack that resonant's docstrings follow, and whose validator the test
suite runs — is a Sphinx extension; the user guide stays Markdown (MyST).  The gallery
of the bundled examples is made while the site builds (``_ext/gallery.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))
sys.path.insert(0, str(HERE / "_ext"))

project = "resonant"
author = "the resonant developers"
copyright = "2026, the resonant developers"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.viewcode",
    "numpydoc",
    "gallery",
    "offline_math",
    "public_names",
    "doc_paths",
]
#: every reference must resolve (docs/_ext/public_names.py maps the docstrings' module
#: paths to the public pages)
nitpicky = True
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "_ext", "_static", "_templates"]
templates_path = ["_templates"]
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath", "amsmath"]
# formulas drawn as SVG at build time (_ext/offline_math.py): no MathJax, no network
html_math_renderer = "offline_svg"
# one page per public object (api.rst), with its source ([source], sphinx.ext.viewcode)
autosummary_generate = True
autodoc_default_options = {"members": True, "undoc-members": False}
# the guide links to files of the repository (benchmarks, examples); they are not pages
myst_url_schemes = ["http", "https", "mailto"]
numpydoc_show_class_members = False
numpydoc_validation_checks: set[str] = set()  # validated by tests/test_docstrings.py
autodoc_member_order = "bysource"
autodoc_typehints = "none"
# the theme of numpy's and scipy's sites; its assets are bundled (nothing from a CDN)
html_theme = "pydata_sphinx_theme"
html_title = "resonant"
html_static_path = ["_static"]
html_css_files = ["resonant.css"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 3,
    "secondary_sidebar_items": ["page-toc", "sourcelink"],
}
