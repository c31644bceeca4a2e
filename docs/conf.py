"""Sphinx configuration of resonant's documentation site.

Build it with ``python -m sphinx -W --keep-going -b html docs docs/_build/html``
(warnings are errors).  Sphinx, because numpydoc — the docstring standard of the
scientific Python stack that resonant's docstrings follow, and whose validator the test
suite runs — is a Sphinx extension; the user guide stays Markdown (MyST).  The gallery
of the bundled examples is made while the site builds (``_ext/gallery.py``).
"""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))
sys.path.insert(0, str(HERE / "_ext"))

import public_names  # noqa: E402

import resonant  # noqa: E402

project = "resonant"
#: the version on every page (the header's switcher-free label) and in the title
release = version = resonant.__version__
#: the repository, from pyproject.toml's [project.urls] "Source" (no address is made up
#: here: without one the header has no repository link, the pages keep "Show source")
REPOSITORY = tomllib.loads((HERE.parent / "pyproject.toml").read_text(encoding="utf-8"))[
    "project"].get("urls", {}).get("Source")
author = "the resonant developers"
copyright = "2026, the resonant developers"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.viewcode",
    "docstring_bars",
    "numpydoc",
    "sphinx_copybutton",
    "local_inventories",
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
# the pages autosummary writes are rebuilt on every build: a page left from an object
# that moved (a result now under ``resonant.NAME``) would otherwise be an orphan warning
for _stale in (HERE / "generated").glob("*.rst"):
    _stale.unlink()
autodoc_default_options = {"members": True, "undoc-members": False}
# the guide links to files of the repository (benchmarks, examples); they are not pages
myst_url_schemes = ["http", "https", "mailto"]
numpydoc_show_class_members = False
numpydoc_validation_checks: set[str] = set()  # validated by tests/test_docstrings.py
# "Returns: RandomResponse", "ndarray", "float" as links: the types of Parameters and
# Returns are cross-referenced where a name is known (resonant's public names, numpy's and
# matplotlib's types, Python's builtins through the offline inventories of
# _ext/local_inventories.py); other words of a type ("of", "optional") stay text
numpydoc_xref_param_type = True
numpydoc_xref_ignore = "all"
numpydoc_xref_aliases = {
    **{name: f"{module}.{name}" for module, names in public_names.HOME_PAGES.items()
       for name in names},
    **{name: f"resonant.{name}" for name in resonant.__all__ if not name.startswith("_")},
    "Figure": "matplotlib.figure.Figure",
    "Axes": "matplotlib.axes.Axes",
    "numpy.ndarray": "numpy.ndarray",
    "ArrayLike": "numpy.typing.ArrayLike",
    "Path": "pathlib.Path",
}
# copy buttons leave the prompts out ("$ " of console blocks, ">>> " of doctests)
copybutton_prompt_text = r"\$ |>>> |\.\.\. "
copybutton_prompt_is_regexp = True
autodoc_member_order = "bysource"
autodoc_typehints = "none"
# the theme of numpy's and scipy's sites; its assets are bundled (nothing from a CDN)
html_theme = "pydata_sphinx_theme"
html_title = "resonant"
html_static_path = ["_static"]
html_css_files = ["resonant.css"]
# the header: the six short entries of index.md's toctree (install, first model, guide,
# gallery, API, reference), none hidden under "More"; the left sidebar lists the pages
# of the current section (guide.md, reference.md, the gallery, the API)
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
    "navbar_align": "left",
    "navbar_end": ["version", "theme-switcher", "navbar-icon-links"],
    "navbar_persistent": ["search-button"],
    "secondary_sidebar_items": {"**": ["page-toc", "sourcelink"], "index": []},
    "icon_links": [{"name": "Source repository", "url": REPOSITORY,
                    "icon": "fa-brands fa-git-alt", "type": "fontawesome"}] if REPOSITORY else [],
    "show_nav_level": 1,
    "navigation_depth": 2,
}
# follow the reader's system; unset, the theme logs "Got invalid theme mode" as a console
# error on a first visit (no mode stored yet)
html_context = {"repository": REPOSITORY, "default_mode": "auto"}
html_sidebars = {"index": [], "install": [], "first-model": []}
