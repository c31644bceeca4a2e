"""Intersphinx to numpy, scipy and matplotlib without the network: inventories made here.

``sphinx.ext.intersphinx`` links a name such as ``numpy.ndarray`` to another project's
site by reading that project's ``objects.inv``, which it downloads while the site builds.
This site builds with no network (PyPI only), and the projects' inventories are neither
shipped in their wheels nor small enough to commit.  So the inventories are written here,
before intersphinx reads them, from the libraries installed beside Sphinx: every public
function and class of numpy, of scipy's submodules and of matplotlib's figure, axes and
pyplot, at the address where that project's reference puts its page (numpy and scipy:
``reference/generated/NAME.html``; matplotlib: ``api/_as_gen/NAME.html``).  A name that
is not installed is simply not linked (intersphinx then leaves it to
``public_names.py`` or to the nitpicky warning).
"""

from __future__ import annotations

import importlib
import inspect
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

#: project -> (its site, the modules whose public names it documents, the page of a name)
PROJECTS: dict[str, tuple[str, tuple[str, ...], str]] = {
    "numpy": ("https://numpy.org/doc/stable/",
              ("numpy", "numpy.linalg", "numpy.fft", "numpy.polynomial"),
              "reference/generated/{name}.html#{name}"),
    "scipy": ("https://docs.scipy.org/doc/scipy/",
              ("scipy.linalg", "scipy.signal", "scipy.integrate", "scipy.sparse",
               "scipy.sparse.linalg", "scipy.optimize", "scipy.interpolate", "scipy.fft",
               "scipy.special", "scipy.stats"),
              "reference/generated/{name}.html#{name}"),
    "matplotlib": ("https://matplotlib.org/stable/",
                   ("matplotlib.figure", "matplotlib.axes", "matplotlib.pyplot"),
                   "api/_as_gen/{name}.html#{name}"),
}
#: (project, name, domain:role, page) of the names not at the generated address: Python's
#: builtins and glossary terms (numpydoc's default links of "float", "sequence", ...)
SPECIAL: tuple[tuple[str, str, str, str], ...] = (
    ("numpy", "numpy.typing.ArrayLike", "py:data", "reference/typing.html#$"),
    ("numpy", "numpy.typing.NDArray", "py:data", "reference/typing.html#$"),
    ("numpy", "numpy.random.Generator", "py:class", "reference/random/generator.html#$"),
    ("numpy", "array_like", "std:term", "glossary.html#term-array-like"),
    ("python", "None", "py:data", "library/constants.html#$"),
    ("python", "True", "py:data", "library/constants.html#$"),
    ("python", "False", "py:data", "library/constants.html#$"),
    *(("python", name, "py:class", "library/stdtypes.html#$")
      for name in ("list", "tuple", "str", "dict", "set", "frozenset", "bytes")),
    *(("python", name, "py:class", "library/functions.html#$")
      for name in ("float", "int", "complex", "bool", "object")),
    ("python", "callable", "py:function", "library/functions.html#$"),
    ("python", "pathlib.Path", "py:class", "library/pathlib.html#$"),
    ("python", "contextlib.contextmanager", "py:function", "library/contextlib.html#$"),
    ("python", "collections.namedtuple", "py:function", "library/collections.html#$"),
    ("python", "bltin-boolean-values", "std:label", "library/stdtypes.html#$"),
    *(("python", term, "std:term", f"glossary.html#term-{term.replace(' ', '-')}")
      for term in ("iterable", "sequence", "generator", "mapping", "path-like object")),
)
#: the projects without modules of their own here (only SPECIAL names)
SITES = {"python": "https://docs.python.org/3/"}


def _public(module_name: str) -> Iterator[tuple[str, str]]:
    """(dotted name, role) of the public functions and classes of one module."""
    try:
        module = importlib.import_module(module_name)
    except ImportError:
        return
    names = getattr(module, "__all__", None) or [n for n in dir(module)
                                                 if not n.startswith("_")]
    for name in names:
        obj = getattr(module, name, None)
        if inspect.isclass(obj):
            yield f"{module_name}.{name}", "class"
        elif callable(obj):
            yield f"{module_name}.{name}", "function"


def _entries(project: str) -> list[str]:
    _, modules, page = PROJECTS.get(project, ("", (), ""))
    lines = {f"{module} py:module 1 {page.format(name=module)} -" for module in modules}
    for module in modules:
        for name, role in _public(module):
            lines.add(f"{name} py:{role} 1 {page.format(name=name)} -")
    for owner, name, role, uri in SPECIAL:
        if owner == project:
            priority = "-1" if role.startswith("std:") else "1"
            lines.add(f"{name} {role} {priority} {uri} -")
    return sorted(lines)


def write_inventory(project: str, path: Path) -> tuple[Path, list[str]]:
    """Write the Sphinx inventory (version 2) of ``project``'s public names to ``path``;
    the path and the dotted Python names it holds."""
    version = "3" if project == "python" else \
        getattr(importlib.import_module(project), "__version__", "")
    header = (f"# Sphinx inventory version 2\n# Project: {project}\n# Version: {version}\n"
              "# The remainder of this file is compressed using zlib.\n")
    entries = _entries(project)
    body = "\n".join(entries) + "\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(header.encode() + zlib.compress(body.encode()))
    return path, [line.split()[0] for line in entries
                  if " py:" in line and "." in line.split()[0]]


def _configure(app: Any, config: Any) -> None:
    """Before intersphinx reads its mapping: the inventories, in the doctree folder."""
    folder = Path(app.doctreedir) / "inventories"
    sites = {**{project: site for project, (site, _, _) in PROJECTS.items()}, **SITES}
    mapping = {}
    for project, site in sites.items():
        path, names = write_inventory(project, folder / f"{project}.inv")
        mapping[project] = (site, str(path))
        # numpydoc links a type's dotted name ("matplotlib.figure.Figure") it knows (as a
        # role: an alias to itself would be left as text with numpydoc_xref_ignore="all")
        config.numpydoc_xref_aliases = {**{name: f":obj:`{name}`" for name in names},
                                        **config.numpydoc_xref_aliases}
    config.intersphinx_mapping = mapping


def setup(app: Any) -> dict[str, Any]:
    """Register the inventories (before ``sphinx.ext.intersphinx`` checks its mapping)."""
    app.setup_extension("sphinx.ext.intersphinx")
    app.connect("config-inited", _configure, priority=100)
    return {"parallel_read_safe": True, "version": "1"}
