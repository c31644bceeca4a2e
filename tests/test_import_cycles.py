"""No module imports its own package by absolute name (``import resonant.model.limits`` inside
resonant/model/): the package's ``__init__`` imports the module, so such an import is a cycle
package <-> module that only works while the package is half initialised.  A sibling is
imported relatively (``from . import limits``), which needs nothing of the package."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).parents[1] / "src"


def _own_package_imports(path: Path) -> list[str]:
    parts = path.relative_to(SRC).with_suffix("").parts
    packages = {".".join(parts[:i]) for i in range(2, len(parts))}   # below resonant itself
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
            [node.module] if isinstance(node, ast.ImportFrom) and node.level == 0 and \
            node.module else []
        found += [f"{path.relative_to(SRC)}: {name}" for name in names
                  if any(name == p or name.startswith(p + ".") for p in packages)]
    return found


def test_no_module_imports_its_own_package_by_absolute_name():
    offending = [hit for path in sorted((SRC / "resonant").rglob("*.py"))
                 for hit in _own_package_imports(path)]
    assert [hit for hit in offending if hit.startswith("resonant/model/")] == []
