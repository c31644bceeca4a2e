"""The architecture and static checks, run as part of the normal suite (they are the CI check).

* ``lint-imports``: the layers contract in ``pyproject.toml`` (each layer imports only from
  the layers below it);
* ``ruff check src`` and ``mypy`` (configured in ``pyproject.toml``);
* an ``ast`` scan of every module: no function-local import of the package's own modules
  (an import inside a function hides a dependency and may hide a cycle) except in the
  command line's :func:`resonant.cli.command_registrar`, which loads only the chosen
  command's module (docs/architecture.md), and no ``TYPE_CHECKING`` import from a higher
  layer (it would hide an upward dependency);
* no string table of providers: the package has no ``hooks`` module and no module calls
  ``importlib.import_module`` with a name of its own modules but the package's lazy
  re-export of :mod:`resonant.api`.
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "resonant"
BIN = Path(sys.executable).parent


def _run(args: list[str], timeout: float = 300) -> None:
    env = dict(os.environ)
    env["PATH"] = str(BIN) + os.pathsep + env.get("PATH", "")
    proc = subprocess.run(args, cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=timeout)
    if proc.returncode != 0:
        print(proc.stdout)
        print(proc.stderr, file=sys.stderr)
    assert proc.returncode == 0, f"{' '.join(args)} failed:\n{proc.stdout}\n{proc.stderr}"


def _script(name: str) -> str:
    path = BIN / (name + (".exe" if os.name == "nt" else ""))
    if not path.exists():
        pytest.fail(f"{name} is not installed next to {sys.executable} "
                    "(pip install -e '.[test]')")
    return str(path)


def test_import_layers() -> None:
    _run([_script("lint-imports")])


def test_ruff() -> None:
    _run([sys.executable, "-m", "ruff", "check", "src"])


def test_mypy() -> None:
    _run([sys.executable, "-m", "mypy"])


# -- the ast scan ----------------------------------------------------------------------------

def _layers() -> list[tuple[str, ...]]:
    """The contract's layers, top first; each a tuple of sibling modules."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    (contract,) = [c for c in config["tool"]["importlinter"]["contracts"]
                   if c["type"] == "layers"]
    return [tuple(m.strip() for m in layer.replace(":", "|").split("|"))
            for layer in contract["layers"]]


def _layer_of(module: str, layers: list[tuple[str, ...]]) -> tuple[int, str] | None:
    for index, siblings in enumerate(layers):
        for sibling in siblings:
            if module == sibling or module.startswith(sibling + "."):
                return index, sibling
    return None


def _modules() -> list[tuple[str, Path]]:
    out = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out.append((".".join(parts), path))
    return out


def _targets(node: ast.Import | ast.ImportFrom, module: str, is_package: bool) -> list[str]:
    """The modules (of this package or not) an import statement names."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if node.level == 0:
        return [node.module or ""]
    package = module if is_package else module.rpartition(".")[0]
    base = package.split(".")
    if node.level > 1:
        base = base[:-(node.level - 1)]
    prefix = ".".join(base)
    if node.module:
        return [f"{prefix}.{node.module}"]
    return [f"{prefix}.{alias.name}" for alias in node.names]


def _own(name: str) -> bool:
    return name == "resonant" or name.startswith("resonant.")


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


MODULES = _modules()

#: (module, function) allowed to import the package's own modules inside a function
LAZY_LOADERS = {("resonant.cli", "command_registrar")}


@pytest.mark.parametrize("module, path", MODULES, ids=[m for m, _ in MODULES])
def test_no_local_or_upward_type_checking_imports(module: str, path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    is_package = path.name == "__init__.py"
    layers = _layers()
    problems: list[str] = []

    for func in ast.walk(tree):
        if not isinstance(func, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            continue
        if (module, getattr(func, "name", "")) in LAZY_LOADERS:
            continue
        for node in ast.walk(func):
            if isinstance(node, ast.Import | ast.ImportFrom):
                own = [t for t in _targets(node, module, is_package) if _own(t)]
                if own:
                    problems.append(f"line {node.lineno}: function-local import of "
                                    f"{', '.join(own)}")

    here = _layer_of(module, layers)
    for block in ast.walk(tree):
        if not (isinstance(block, ast.If) and _is_type_checking(block.test)):
            continue
        for stmt in block.body:
            for node in ast.walk(stmt):
                if not isinstance(node, ast.Import | ast.ImportFrom):
                    continue
                for target in _targets(node, module, is_package):
                    there = _layer_of(target, layers) if _own(target) else None
                    if here is None or there is None:
                        continue
                    if there[0] < here[0] or (there[0] == here[0] and there[1] != here[1]):
                        problems.append(f"line {node.lineno}: TYPE_CHECKING import of "
                                        f"{target} (layer {there[1]}) from layer {here[1]}")
    assert not problems, f"{module}:\n" + "\n".join(problems)


def test_scan_finds_the_layers() -> None:
    """The scan above is not vacuous: every layer in the contract names a real module."""
    names = {m for m, _ in MODULES}
    for siblings in _layers():
        for sibling in siblings:
            assert sibling in names, sibling


def test_no_string_table_of_providers() -> None:
    """Calls are followed by a reader: no hooks table, no import of our modules by name."""
    assert not (PACKAGE / "hooks.py").exists()
    offenders = []
    for module, path in MODULES:
        text = path.read_text(encoding="utf-8")
        if "import_module(" in text and module != "resonant":
            offenders.append(module)
        if "hooks.call(" in text or "hooks.provides(" in text:
            offenders.append(module)
    assert not offenders, offenders


def test_lazy_loaders_import_downward_only() -> None:
    """The command line's lazy imports name modules of the command line or below it."""
    layers = _layers()
    tree = ast.parse((PACKAGE / "cli" / "__init__.py").read_text(encoding="utf-8"))
    (func,) = [f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef)
               and f.name == "command_registrar"]
    imported = [t for node in ast.walk(func) if isinstance(node, ast.ImportFrom)
                for t in _targets(node, "resonant.cli", True)]
    assert imported and all(_layer_of(t, layers) == (0, "resonant.cli") for t in imported)


#: the longest function body (without its docstring) of one idea, in lines
MAX_FUNCTION_LINES = 80


def test_functions_of_one_idea() -> None:
    """No function of the package runs past MAX_FUNCTION_LINES (docs/architecture.md)."""
    long = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            lines = (node.end_lineno or node.lineno) - node.lineno + 1
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) \
                    and isinstance(first.value.value, str):
                lines -= (first.end_lineno or first.lineno) - first.lineno + 1
            if lines > MAX_FUNCTION_LINES:
                long.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name} ({lines})")
    assert not long, "functions longer than one idea: " + "; ".join(long)
