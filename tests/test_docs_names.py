"""The code names the guide mentions exist: every `resonant.DOTTED.NAME` set as code in
docs/*.md is a module of resonant or an attribute of one (a renamed or removed function
leaves no stale name in the contracts)."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
NAME = re.compile(r"`(resonant(?:\.[A-Za-z_][A-Za-z0-9_]*)+)`")


def _exists(dotted: str) -> bool:
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj: object = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for attribute in parts[cut:]:
                obj = getattr(obj, attribute)
        except AttributeError:
            return False
        return True
    return False


MENTIONS = sorted({(page.name, name) for page in DOCS.glob("*.md")
                   for name in NAME.findall(page.read_text(encoding="utf-8"))})


def test_the_guide_mentions_code_names():
    assert len(MENTIONS) > 20  # the scan sees the guide's names
    assert _exists("resonant.analyses.sweep.sweep")
    assert not _exists("resonant.hooks.PROVIDERS") and not _exists("resonant.sweep.nothing")


@pytest.mark.parametrize("page, name", MENTIONS)
def test_every_code_name_in_the_guide_exists(page, name):
    assert _exists(name), f"docs/{page} names {name}, which does not exist"
