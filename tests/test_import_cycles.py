"""The model package imports its sibling modules without passing through the package.

``resonant/model/__init__.py`` imports the loader, which imports every reader; a module of
the package that reads a sibling through the package (``from . import limits``, ``from
resonant.model import limits``) therefore depends on ``__init__`` and closes a cycle in the
import graph.  A sibling whose attributes are read at call time (the limits, which a user
may raise for the rest of the process) is imported as its own module object, ``import
resonant.model.limits as limits``; every other sibling by name (``from .units import ...``).
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).parents[1] / "src"
MODEL = SRC / "resonant" / "model"


def _through_the_package(path: Path) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            package = node.level == 1 and node.module is None
            absolute = node.level == 0 and node.module == "resonant.model"
            if package or absolute:
                found.append(f"{path.name}:{node.lineno}")
        if isinstance(node, ast.Import):
            # ``import resonant.model.limits`` without ``as`` binds the package ``resonant``
            found += [f"{path.name}:{node.lineno}" for alias in node.names
                      if alias.name.startswith("resonant.model") and alias.asname is None]
    return found


def test_no_model_module_imports_a_sibling_through_the_package():
    offending = [hit for path in sorted(MODEL.rglob("*.py")) if path.name != "__init__.py"
                 for hit in _through_the_package(path)]
    assert offending == []


def test_the_scan_sees_the_forms_it_forbids(tmp_path: Path):
    sample = tmp_path / "sample.py"
    sample.write_text("from . import limits\nfrom resonant.model import loader\n"
                      "import resonant.model.limits\nimport resonant.model.limits as limits\n"
                      "from .units import parse_unit\n")
    assert _through_the_package(sample) == ["sample.py:1", "sample.py:2", "sample.py:3"]
