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
    "numpydoc",
    "gallery",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "_ext"]
myst_heading_anchors = 3
# the guide links to files of the repository (benchmarks, examples); they are not pages
myst_url_schemes = ["http", "https", "mailto"]
numpydoc_show_class_members = False
numpydoc_validation_checks: set[str] = set()  # validated by tests/test_docstrings.py
autodoc_member_order = "bysource"
autodoc_typehints = "none"
html_theme = "alabaster"
html_title = "resonant"
html_static_path: list[str] = []
html_theme_options = {"description": "Vibrations of discrete mechanical systems",
                      "fixed_sidebar": True, "page_width": "1100px"}
