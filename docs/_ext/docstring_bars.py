"""Absolute values in docstrings (``|response|``, ``|H|``) as text, not substitutions.

The docstrings write an absolute value as mathematics does, between bars; reStructuredText
reads ``|word|`` as a substitution reference and fails the build on an undefined one.
Before numpydoc and autodoc parse a docstring, a bar pair that encloses no defined
substitution is escaped, so the page shows the bars the code's reader sees.
"""

from __future__ import annotations

import re
from typing import Any

#: |x| not inside ``literal`` text; the bars hug the text as a substitution's would
BARS = re.compile(r"(?<![\\|`])\|(?=\S)([^|`\n]*?\S)\|(?![|`_])")


def escape_bars(line: str) -> str:
    """The line with each ``|text|`` outside inline literals escaped to ``\\|text\\|``."""
    pieces = re.split(r"(``.*?``|`[^`]*`)", line)
    return "".join(piece if piece.startswith("`") else BARS.sub(r"\\|\1\\|", piece)
                   for piece in pieces)


def _escape(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    lines[:] = [escape_bars(line) for line in lines]


def setup(app: Any) -> dict[str, Any]:
    """Register the escape (before numpydoc's own docstring processing)."""
    app.connect("autodoc-process-docstring", _escape, priority=100)
    return {"parallel_read_safe": True, "version": "1"}
