"""The code names the guide mentions exist: every `resonant.DOTTED.NAME` set as code in
docs/*.md is a module of resonant or an attribute of one (a renamed or removed function
leaves no stale name in the contracts)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
sys.path.insert(0, str(DOCS / "_ext"))
import public_names  # noqa: E402

NAME = re.compile(r"`(resonant(?:\.[A-Za-z_][A-Za-z0-9_]*)+)`")


def _exists(dotted: str) -> bool:
    """Whether the name denotes a module of resonant or an attribute of one (the site's
    resolver, docs/_ext/public_names.py, finds objects the same way)."""
    return public_names._find(dotted, None) is not None


MENTIONS = sorted({(page.name, name) for page in DOCS.glob("*.md")
                   for name in NAME.findall(page.read_text(encoding="utf-8"))})


def test_the_guide_mentions_code_names():
    assert len(MENTIONS) > 20  # the scan sees the guide's names
    assert _exists("resonant.analyses.sweep.sweep")
    assert not _exists("resonant.hooks.PROVIDERS") and not _exists("resonant.sweep.nothing")


@pytest.mark.parametrize("page, name", MENTIONS)
def test_every_code_name_in_the_guide_exists(page, name):
    assert _exists(name), f"docs/{page} names {name}, which does not exist"
