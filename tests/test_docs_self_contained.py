"""The package and its docs stand on their own: no pointer outside the project.

A user of resonant sees the package, its docs/, examples/, tests/ and benchmarks/, never
the folder of specifications the project started from nor its tracker's numbering.  So no
file may refer to that folder (a ``shared`` folder beside the project, its ``spec`` or
``reference`` subfolders) or cite a numbered issue or work session of this project: the
contracts live in docs/ (model-format.md, parts.md, units.md, nonlinear.md,
exercises.md, errors.md), the reference exercise and its numbers in
docs/reference-exercise.md, and a comment says what and why, not who asked.

Allowed: links (``https://...``) to third-party issue trackers, e.g. a scipy or
matplotlib bug, since those are public and stable; the word "issue" without a number;
CSS colours such as ``#333``.  The patterns are built from pieces so that this file does
not match itself, and ``test_patterns_catch_what_they_should`` shows each can fail.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: what is scanned (the brief of a user: code, docs, tests, examples, benchmarks, fuzzers)
SCANNED = ("src", "docs", "tests", "examples", "benchmarks", "fuzz", "README.md",
           "pyproject.toml")
#: never scanned: saved hostile fuzz inputs (data, not documentation) and caches
SKIPPED_PARTS = {"crashes", "__pycache__", ".hypothesis", ".pytest_cache", ".mypy_cache"}
TEXT_SUFFIXES = {".py", ".md", ".toml", ".txt", ".rst", ".cfg", ".ini", ".json", ".csv",
                 ".html", ".js", ".css", ".tex", ".svg", ".xml", ".yaml", ".yml", ".mtx"}

_SHARED = "sha" + "red"
_ISSUE = "iss" + "ues?"
#: (name, pattern): each names one kind of pointer outside the project
PATTERNS = (
    ("the shared folder beside the project",
     re.compile(r"\.\./" + _SHARED + r"\b|/work/" + _SHARED + r"\b")),
    ("the shared specification or reference folder",
     re.compile(r"\b" + _SHARED + r"/(?:spec|reference)\b")),
    ("a numbered issue",
     re.compile(r"(?i)\b" + _ISSUE + r"[ _-]?(?:#|no\.? ?)?\d+")),
    ("an issue number in parentheses", re.compile(r"\(#\d+\)")),
    ("a numbered work session",
     re.compile(r"(?:\(|\b(?:of|since|in|after|before|from) )(?:the )?" + "st" + r"op \d+\b")),
)
#: links are allowed (third-party trackers: github.com/<project>/issues/<n> and the like)
URL = re.compile(r"https?://[^\s)>\]\"'`]+")


def _files() -> list[Path]:
    """The scanned files: tracked by git where this is a checkout, else every file."""
    try:
        listed = subprocess.run(["git", "ls-files", "-z", "--", *SCANNED], cwd=ROOT,
                                capture_output=True, check=True, timeout=60).stdout
        paths = [ROOT / p for p in listed.decode("utf-8").split("\0") if p]
    except (OSError, subprocess.SubprocessError):
        paths = []
    if not paths:  # not a git checkout (an unpacked source archive): every file
        paths = [p for name in SCANNED for p in
                 ([ROOT / name] if (ROOT / name).is_file() else (ROOT / name).rglob("*"))]
    return [p for p in paths if p.is_file() and p.suffix in TEXT_SUFFIXES
            and not SKIPPED_PARTS & set(p.relative_to(ROOT).parts)]


def findings(text: str) -> list[tuple[int, str, str]]:
    """(line number, kind, the matched text) of every pointer outside the project."""
    found = []
    for number, line in enumerate(text.splitlines(), start=1):
        line = URL.sub("<link>", line)
        for kind, pattern in PATTERNS:
            found += [(number, kind, m.group(0)) for m in pattern.finditer(line)]
    return found


def test_no_file_points_outside_the_project() -> None:
    """Every scanned file: no pointer to the shared folder, to an issue or a session."""
    files = _files()
    assert len(files) > 100, "the scan found too few files: is the project layout intact?"
    problems = []
    for path in files:
        text = path.read_text(encoding="utf-8", errors="replace")
        problems += [f"{path.relative_to(ROOT)}:{n}: {kind}: {hit!r}"
                     for n, kind, hit in findings(text)]
    assert not problems, ("refer to the docs/ page (or the test, example) that holds the "
                          "contract instead:\n" + "\n".join(problems))


BAD = [
    "see ../" + _SHARED + "/spec/units.md",
    "(contract " + _SHARED + "/reference/practice-12-2dof-forced.md)",
    "/work/" + _SHARED + "/spec/model-format.md",
    "Is" + "sue 12, item 3: the drawing",
    "asked for by is" + "sue #7",
    "the is" + "sue-5 fix",
    "fixed the same day (" + "#12)",
    "the fuzz campaigns of st" + "op 17",
    "Campaign 4 (st" + "op 18, seed 2029)",
]
GOOD = [
    "see https://github.com/scipy/scipy/is" + "sues/12345 (a scipy bug)",
    "<https://github.com/matplotlib/matplotlib/is" + "sues/27001>",
    "thead th { border-bottom: 1px solid #333 }",
    "an is" + "sue of the model file: exit 2",
    "the contract lives in docs/parts.md",
    "a body may be " + _SHARED + " by two springs",
    "nonlinear_sweep('omega', start=0.5, st" + "op=2.5)",
]


@pytest.mark.parametrize("text", BAD)
def test_patterns_catch_what_they_should(text: str) -> None:
    assert findings(text), text


@pytest.mark.parametrize("text", GOOD)
def test_patterns_allow_links_and_plain_words(text: str) -> None:
    assert not findings(text), findings(text)
