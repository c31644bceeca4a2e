"""The architecture and static checks, run as part of the normal suite (they are the CI check).

* ``lint-imports``: the layers contract in ``pyproject.toml`` (each layer imports only from
  the layers below it);
* ``ruff check src`` and ``mypy`` (configured in ``pyproject.toml``);
* an ``ast`` scan of every module: no function-local import of the package's own modules
  (an import inside a function hides a dependency and may hide a cycle) except in the
  command line's :func:`resonant.cli.command_registrar`, which loads only the chosen
  command's module, and in the one-line methods by which a class reaches the analysis or
  view of a higher layer (``Model.linearize``, ``FrequencyResponse.plot``, ...): a method
  whose body is one import and one ``return`` of a call, each such edge listed in the
  layers contract's ``ignore_imports`` and every listed edge used (docs/architecture.md).
  No ``TYPE_CHECKING`` import from a higher layer but of those same edges (the methods'
  return types);
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
MODULE_NAMES = {m for m, _ in MODULES}


def _edges(node: ast.Import | ast.ImportFrom, module: str, is_package: bool) -> list[str]:
    """The modules of this package an import names, down to the submodule imported
    (``from ..views import display`` -> ``resonant.views.display``), as import-linter
    records them."""
    targets = _targets(node, module, is_package)
    if isinstance(node, ast.ImportFrom) and node.module:
        subs = [f"{targets[0]}.{alias.name}" for alias in node.names]
        targets = [t for t in subs if t in MODULE_NAMES] or targets
    return [t for t in targets if _own(t)]


def _lazy_edges() -> set[str]:
    """The upward edges the layers contract allows (``ignore_imports``)."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    (contract,) = [c for c in config["tool"]["importlinter"]["contracts"]
                   if c["type"] == "layers"]
    return {e.replace(" ", "") for e in contract.get("ignore_imports", [])}


def _is_lazy_method(func: ast.AST, parents: dict[ast.AST, ast.AST]) -> bool:
    """A method whose body (docstring aside) is one import and one ``return`` of a call."""
    if not isinstance(func, ast.FunctionDef) or not isinstance(parents.get(func), ast.ClassDef):
        return False
    body = list(func.body)
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    return (len(body) == 2 and isinstance(body[0], ast.ImportFrom)
            and isinstance(body[1], ast.Return) and isinstance(body[1].value, ast.Call))


def _parents(tree: ast.AST) -> dict[ast.AST, ast.AST]:
    return {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}


def _upward_type_checking_edges(tree: ast.AST, module: str, is_package: bool) -> set[str]:
    here = _layer_of(module, _layers())
    edges = set()
    for block in ast.walk(tree):
        if isinstance(block, ast.If) and _is_type_checking(block.test):
            for node in ast.walk(block):
                if isinstance(node, ast.Import | ast.ImportFrom):
                    for target in _edges(node, module, is_package):
                        there = _layer_of(target, _layers())
                        if here and there and (there[0] < here[0] or (
                                there[0] == here[0] and there[1] != here[1])):
                            edges.add(f"{module}->{target}")
    return edges


def _used_lazy_edges() -> tuple[set[str], list[str]]:
    """The edges the lazy methods take (and, in a module that has such methods, the
    TYPE_CHECKING imports of the types they return), and the methods."""
    edges: set[str] = set()
    methods: list[str] = []
    for module, path in MODULES:
        tree = ast.parse(path.read_text(encoding="utf-8"))
        parents = _parents(tree)
        before = len(methods)
        for func in ast.walk(tree):
            if _is_lazy_method(func, parents):
                assert isinstance(func, ast.FunctionDef)
                node = func.body[-2]
                assert isinstance(node, ast.ImportFrom)
                for target in _edges(node, module, path.name == "__init__.py"):
                    edges.add(f"{module}->{target}")
                    methods.append(f"{module}.{parents[func].name}.{func.name} -> {target}")
        if len(methods) > before:
            edges |= _upward_type_checking_edges(tree, module, path.name == "__init__.py")
    return edges, methods

#: (module, function) allowed to import the package's own modules inside a function
LAZY_LOADERS = {("resonant.cli", "command_registrar")}


@pytest.mark.parametrize("module, path", MODULES, ids=[m for m, _ in MODULES])
def test_no_local_or_upward_type_checking_imports(module: str, path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    is_package = path.name == "__init__.py"
    layers = _layers()
    problems: list[str] = []

    allowed = _lazy_edges()
    parents = _parents(tree)
    for func in ast.walk(tree):
        if not isinstance(func, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            continue
        if (module, getattr(func, "name", "")) in LAZY_LOADERS:
            continue
        lazy = _is_lazy_method(func, parents)
        for node in ast.walk(func):
            if isinstance(node, ast.Import | ast.ImportFrom):
                own = _edges(node, module, is_package)
                if lazy and all(f"{module}->{t}" in allowed for t in own):
                    continue
                if own:
                    problems.append(f"line {node.lineno}: function-local import of "
                                    f"{', '.join(own)}" + (" (not in ignore_imports)"
                                                           if lazy else ""))

    here = _layer_of(module, layers)
    for block in ast.walk(tree):
        if not (isinstance(block, ast.If) and _is_type_checking(block.test)):
            continue
        for stmt in block.body:
            for node in ast.walk(stmt):
                if not isinstance(node, ast.Import | ast.ImportFrom):
                    continue
                for target in _edges(node, module, is_package):
                    there = _layer_of(target, layers)
                    if here is None or there is None or f"{module}->{target}" in allowed:
                        continue
                    if there[0] < here[0] or (there[0] == here[0] and there[1] != here[1]):
                        problems.append(f"line {node.lineno}: TYPE_CHECKING import of "
                                        f"{target} (layer {there[1]}) from layer {here[1]}")
    assert not problems, f"{module}:\n" + "\n".join(problems)


def test_lazy_edges_are_exactly_the_methods_ones() -> None:
    """Every upward edge the contract ignores is taken by a one-line method, and every
    one-line method's edge is listed: the list in ``pyproject.toml`` is the whole truth."""
    used, methods = _used_lazy_edges()
    listed = _lazy_edges()
    assert methods, "the scan found no lazy method"
    assert used <= listed, f"lazy methods whose edge is not listed: {sorted(used - listed)}"
    assert listed <= used, f"listed edges no lazy method takes: {sorted(listed - used)}"


def test_lazy_method_rule_is_not_vacuous() -> None:
    """The rule refuses a method that does more than import and return a call."""
    tree = ast.parse("class A:\n    def f(self):\n        from . import x\n"
                     "        y = 1\n        return x.g(y)\n"
                     "    def g(self):\n        from . import x\n        return x.g(self)\n")
    parents = _parents(tree)
    verdicts = {f.name: _is_lazy_method(f, parents) for f in ast.walk(tree)
                if isinstance(f, ast.FunctionDef)}
    assert verdicts == {"f": False, "g": True}


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


#: classes of the api that add methods (no data) to the class of the same name below:
#: the model's analyses, at the top so that the model layer reaches up for none of them
API_METHOD_CLASSES = {"Model": ("resonant.api.model", "resonant.model.types")}


def test_one_class_per_concept() -> None:
    """No public class name is defined in two modules: a concept is written once (but the
    api's classes that only add methods to the data class of their concept)."""
    where: dict[str, list[str]] = {}
    for module, path in MODULES:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                where.setdefault(node.name, []).append(module)
    twice = {name: modules for name, modules in where.items() if len(modules) > 1
             and tuple(sorted(modules)) != API_METHOD_CLASSES.get(name)}
    assert not twice, twice


def test_api_method_classes_add_no_data() -> None:
    """An api class of :data:`API_METHOD_CLASSES` subclasses the data class and adds no
    field: the concept's data is written once."""
    from dataclasses import fields
    from importlib import import_module

    for name, (api_module, data_module) in API_METHOD_CLASSES.items():
        api_class = getattr(import_module(api_module), name)
        data_class = getattr(import_module(data_module), name)
        assert api_class.__mro__[1] is data_class
        assert [f.name for f in fields(api_class)] == [f.name for f in fields(data_class)]


def test_the_methods_users_call_are_on_the_one_class() -> None:
    """What ``resonant.load`` returns, what it derives and what the analyses return are the
    classes of the layers that define them, with their analyses and views as methods."""
    import resonant
    from resonant.analyses.stationary import StationarySolution
    from resonant.api.model import Model
    from resonant.system import NumericEOM

    model = resonant.load(ROOT / "examples" / "two_dof_free.toml")
    assert type(model) is Model and resonant.Model is Model
    assert type(model.with_parameters()) is Model
    numeric = model.linearize().numeric()
    assert type(numeric) is NumericEOM
    assert numeric.modes().natural_frequencies.round(3).tolist() == [20.0, 34.641]
    solution = model.linearize().stationary()
    assert type(solution) is StationarySolution and solution.summary()


#: the modules that hold the package's eigen-solves and sparse factorizations: the modal
#: kernel, the harmonic kernel and its reduced models (docs/architecture.md)
KERNEL_MODULES = {"resonant.modal", "resonant.analyses.kernel", "resonant.analyses.reduced"}
EIGENSOLVERS = {"eig", "eigh", "eigvals", "eigvalsh", "eigs", "eigsh", "eig_banded",
                "eigvals_banded", "lobpcg"}
FACTORIZATIONS = {"splu", "factorized", "spilu", "lu_factor", "cho_factor", "spsolve"}


def _kernel_calls(tree: ast.AST, text: str) -> list[str]:
    """Eigen-solves, sparse factorizations and hand-made state matrices (a block matrix
    with an identity block) in a module's source."""
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
        if name in EIGENSOLVERS or name in FACTORIZATIONS:
            found.append(f"line {node.lineno}: {name}")
        if name in {"block", "bmat"} and "eye" in (ast.get_source_segment(text, node) or ""):
            found.append(f"line {node.lineno}: a state matrix written by hand ({name})")
    return found


@pytest.mark.parametrize("module, path", MODULES, ids=[m for m, _ in MODULES])
def test_eigen_solves_and_factorizations_only_in_the_kernels(module: str, path: Path) -> None:
    """Every eigen-solve and sparse factorization goes through the modal or the harmonic
    kernel: one ordering rule, one threshold, one place to make each faster."""
    if module in KERNEL_MODULES:
        return
    text = path.read_text(encoding="utf-8")
    found = _kernel_calls(ast.parse(text), text)
    assert not found, f"{module} (use resonant.modal or resonant.analyses.kernel):\n" + \
        "\n".join(found)


def test_the_kernel_scan_is_not_vacuous() -> None:
    """The scan finds an eigen-solve, a factorization and a state matrix written by hand."""
    text = ("import numpy as np\nnp.linalg.eigvals(A)\nsplu(A)\n"
            "np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])\n")
    assert len(_kernel_calls(ast.parse(text), text)) == 3
    assert all(m in MODULE_NAMES for m in KERNEL_MODULES)


def _reaches_past_the_system(tree: ast.AST) -> list[str]:
    """Where a module reads a model's ``matrices`` or calls a system's private
    ``_model()``: what it needs of a system belongs on the system's interface."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr == "matrices" and \
                isinstance(node.ctx, ast.Load) and not isinstance(node.value, ast.Call):
            base = node.value
            name = base.attr if isinstance(base, ast.Attribute) else getattr(base, "id", "")
            if name in {"model", "m", "source_model"}:
                found.append(f"line {node.lineno}: {name}.matrices")
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                node.func.attr == "_model":
            found.append(f"line {node.lineno}: _model()")
    return found


ANALYSES = [(m, p) for m, p in MODULES if m.startswith("resonant.analyses")]


@pytest.mark.parametrize("module, path", ANALYSES, ids=[m for m, _ in ANALYSES])
def test_analyses_take_the_system_not_its_model(module: str, path: Path) -> None:
    """An analysis asks its system (the given matrices, the speed, the bearings, the
    parameters along a sweep), never the model behind it (docs/architecture.md)."""
    found = _reaches_past_the_system(ast.parse(path.read_text(encoding="utf-8")))
    assert not found, f"{module} (ask the LinearSystem / NonlinearSystem):\n" + \
        "\n".join(found)


def test_the_model_reach_scan_is_not_vacuous() -> None:
    """The scan finds a model's matrices read and a private ``_model()`` call."""
    text = "spec = system.model.matrices\nm = system._model()\n"
    assert len(_reaches_past_the_system(ast.parse(text))) == 2
    assert len(ANALYSES) > 40


#: the results of resonant.analyses that still write their own to_dict / from_dict, each
#: with why the fields-generic one (resonant.analyses.result_fields.FieldsJSON) does not
#: save it yet (none now); every other result declares its fields and inherits both
OWN_JSON: dict[str, str] = {}


def _own_json_classes() -> dict[str, str]:
    """class name -> module of every class in resonant.analyses that defines its own
    ``to_dict`` or ``from_dict``."""
    found = {}
    for path in sorted((PACKAGE / "analyses").glob("*.py")):
        if path.name == "result_fields.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef) and any(
                    isinstance(item, ast.FunctionDef) and item.name in ("to_dict", "from_dict")
                    for item in node.body):
                found[node.name] = path.stem
    return found


def test_results_are_saved_by_their_fields() -> None:
    """No result of the analyses writes its own to_dict / from_dict but the few listed in
    OWN_JSON (each with its reason); the list names no class that no longer does."""
    own = _own_json_classes()
    assert sorted(set(own) - set(OWN_JSON)) == [], (
        "declare the fields (resonant.analyses.result_fields.saved) instead of writing "
        "to_dict/from_dict by hand")
    assert sorted(set(OWN_JSON) - set(own)) == [], "stale entries in OWN_JSON"
    assert {"Simulation", "TransientResponse", "ShockSpectrum", "Correlation",
            "StationarySolution", "RandomResponse", "ModelUpdate", "FRFUpdate",
            "MeasuredFRF", "PeriodicResponse", "StateSpaceModel",
            "MatrixChecks", "NonlinearResponse", "ModalIdentification"}.isdisjoint(own)
