"""The typed surface cannot slide back.

* parameters annotated bare ``Any`` (``*args``/``**kwargs`` included) in ``src/``: no more
  than :data:`MAX_BARE_ANY` (a ratchet: lower it as annotations are made real, never raise
  it);
* mypy --strict's checks stay switched on for the api, the analyses and the system: the
  ``[[tool.mypy.overrides]]`` section in ``pyproject.toml`` that the one mypy run of
  ``tests/test_architecture.py`` applies (running mypy a second time would double its cost).
"""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "resonant"

#: the most parameters typed bare ``Any`` the package may have
MAX_BARE_ANY = 18

#: mypy --strict's per-module flags (``strict`` itself is global only)
STRICT_FLAGS = ("disallow_any_generics", "disallow_subclassing_any", "disallow_untyped_calls",
                "disallow_untyped_defs", "disallow_incomplete_defs",
                "disallow_untyped_decorators", "warn_return_any", "no_implicit_reexport",
                "strict_equality", "extra_checks")
STRICT_PACKAGES = ("resonant.api", "resonant.analyses", "resonant.system")


def _is_any(annotation: ast.expr | None) -> bool:
    return ((isinstance(annotation, ast.Name) and annotation.id == "Any")
            or (isinstance(annotation, ast.Attribute) and annotation.attr == "Any")
            or (isinstance(annotation, ast.Constant) and annotation.value == "Any"))


def bare_any_parameters(source: str) -> list[str]:
    """The parameters of the functions in ``source`` annotated exactly ``Any``.

    >>> bare_any_parameters("def f(a: Any, b: int, *c: Any, **d: 'Any') -> Any: ...")
    ['f.a', 'f.c', 'f.d']
    """
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            args = node.args
            params = [*args.posonlyargs, *args.args, *args.kwonlyargs,
                      *(p for p in (args.vararg, args.kwarg) if p is not None)]
            found += [f"{node.name}.{p.arg}" for p in params if _is_any(p.annotation)]
    return found


def test_the_counter_sees_every_kind_of_parameter() -> None:
    source = ("def f(a: Any, /, b: typing.Any, *c: Any, d: Any = 1, **e: Any) -> Any:\n"
              "    async def g(x: 'Any', y: list[Any]) -> None: ...\n")
    assert sorted(bare_any_parameters(source)) == ["f.a", "f.b", "f.c", "f.d", "f.e", "g.x"]


def test_bare_any_parameters_stay_few() -> None:
    found = [f"{path.relative_to(PACKAGE)}:{name}" for path in sorted(PACKAGE.rglob("*.py"))
             for name in bare_any_parameters(path.read_text(encoding="utf-8"))]
    assert len(found) <= MAX_BARE_ANY, (
        f"{len(found)} parameters typed bare Any (at most {MAX_BARE_ANY}); give the new ones "
        "a real type (resonant.arrays, numpy.typing, a Protocol):\n" + "\n".join(found))


def test_strict_checks_cover_api_analyses_system() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    overrides = config["tool"]["mypy"].get("overrides", [])
    strict = [o for o in overrides if all(o.get(flag) is True for flag in STRICT_FLAGS)]
    covered = {m for o in strict for m in ([o["module"]] if isinstance(o["module"], str)
                                           else o["module"])}
    for package in STRICT_PACKAGES:
        assert {package, package + ".*"} <= covered, f"{package} lost mypy --strict's checks"
    assert config["tool"]["mypy"]["files"] == ["src/resonant"]
