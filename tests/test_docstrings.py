"""Every public name has a complete numpydoc docstring, checked by numpydoc's own validator.

The public API is the ``__all__`` of ``resonant`` and of each of its subpackages (the
functions and classes listed there).  The error codes that fail the test
(:data:`CHECKED`, see https://numpydoc.readthedocs.io/en/latest/validation.html):

* GL08 no docstring; SS01-SS03 no summary, or one that is not a sentence;
* PR01/PR02 a parameter missing from, or unknown to, the Parameters section;
* RT01 no Returns section where the function returns something;
* EX01 no Examples section (they run as doctests with the suite).

A dataclass (a result, a model's data) documents its fields either as Parameters or as
Attributes — a result is read, rarely constructed — so for a dataclass PR01 is replaced
by "every field is in Parameters or Attributes".  The conventions are in
docs/architecture.md.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil

import pytest

import resonant

numpydoc_validate = pytest.importorskip("numpydoc.validate")
docscrape = pytest.importorskip("numpydoc.docscrape")

CHECKED = {"GL08", "SS01", "SS02", "SS03", "PR01", "PR02", "RT01", "EX01"}


def public_objects() -> dict[str, object]:
    """Functions and classes in ``__all__`` of resonant and its subpackages, by full name."""
    modules = ["resonant"] + [info.name for info in
                              pkgutil.iter_modules(resonant.__path__, "resonant.")
                              if info.ispkg]
    found: dict[str, object] = {}
    for name in modules:
        module = importlib.import_module(name)
        for attribute in getattr(module, "__all__", ()):
            obj = getattr(module, attribute)
            if inspect.isfunction(obj) or inspect.isclass(obj):
                found[f"{obj.__module__}.{obj.__qualname__}"] = obj
    return found


PUBLIC = public_objects()


def undocumented_fields(obj: type) -> list[str]:
    """The fields of a dataclass that neither Parameters nor Attributes describe."""
    doc = docscrape.ClassDoc(obj)
    entries = [*doc["Parameters"], *doc["Attributes"]]
    # "M, C, K : ndarray" documents three fields at once
    documented = {name.strip() for p in entries for name in p.name.split(",")}
    return [f.name for f in dataclasses.fields(obj)
            if f.init and not f.name.startswith("_") and f.name not in documented]


def test_the_public_api_is_found() -> None:
    assert "resonant.model.types.Model" in PUBLIC and "resonant.model.loader.loads" in PUBLIC
    assert len(PUBLIC) > 80


@pytest.mark.parametrize("name", sorted(PUBLIC))
def test_numpydoc(name: str) -> None:
    obj = PUBLIC[name]
    errors = [(code, message) for code, message in numpydoc_validate.validate(name)["errors"]
              if code in CHECKED]
    if inspect.isclass(obj) and dataclasses.is_dataclass(obj):
        errors = [(c, m) for c, m in errors if c != "PR01"]
        missing = undocumented_fields(obj)
        if missing:
            errors.append(("PR01", f"fields not documented: {', '.join(missing)}"))
    assert not errors, f"{name}: " + "; ".join(f"{c} {m}" for c, m in errors)
