"""Markdown writer: ``$$`` display math with ``\\tag``, ``$...$`` inline, pipe tables.

Renders on GitHub, GitLab, VS Code and Jupyter (MathJax/KaTeX).  Figures are
written as SVG files next to the Markdown file and linked relatively.
"""

from __future__ import annotations

import re
from pathlib import Path

from ..errors import printable
from .blocks import (
    Equation,
    Figure,
    Heading,
    Math,
    Note,
    Paragraph,
    Part,
    Report,
    Table,
)
from .plots import save

_SPECIAL = re.compile(r"([\\`*_\[\]<>#|$])")


def _escape(text: str) -> str:
    return _SPECIAL.sub(r"\\\1", printable(text, limit=None))


#: a power in a unit (m/s^2, (m/s^2)^2/Hz, s^-1), after a letter or ")"
_POWER = re.compile(r"(?<=[A-Za-z)])\^(?:\((-?[0-9]+)\)|(-?[0-9]+))")
_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def unit_text(text: str) -> str:
    """A table cell's units typeset as text: powers raised, products dotted.

    Examples
    --------
    >>> unit_text("219.7 m/s^2"), unit_text("(m/s^2)^2/Hz"), unit_text("N*s/m")
    ('219.7 m/s²', '(m/s²)²/Hz', 'N·s/m')
    """
    text = re.sub(r"(?<=[A-Za-z])\*(?=[A-Za-z])", "\u00b7", text)
    return _POWER.sub(lambda m: (m.group(1) or m.group(2)).translate(_SUPERSCRIPT), text)


def _inline(parts: tuple[Part, ...], cell: bool = False) -> str:
    out = []
    for part in parts:
        if isinstance(part, Math):
            out.append("$" + part.latex + "$")
        else:
            out.append(_escape(unit_text(part) if cell else part))
    return "".join(out)


def _one_line(latex: str) -> str:
    return " ".join(latex.split())


def render_markdown(report: Report, figure_path: Path | None = None) -> str:
    lines = [f"# {_escape(report.title)}", ""]
    for block in report.blocks:
        if isinstance(block, Heading):
            lines += ["#" * (block.level) + " " + _escape(block.text), ""]
        elif isinstance(block, Paragraph):
            lines += [_inline(block.parts), ""]
        elif isinstance(block, Equation):
            tag = rf" \tag{{{block.number}}}" if block.number is not None else ""
            lines += ["$$", _one_line(block.latex) + tag, "$$", ""]
        elif isinstance(block, Table):
            lines.append("| " + " | ".join(_inline(c, True) for c in block.header) + " |")
            lines.append("|" + "---|" * len(block.header))
            for row in block.rows:
                lines.append("| " + " | ".join(_inline(c, True) for c in row) + " |")
            lines.append("")
        elif isinstance(block, Note):
            lines += ["> **Warning:** " + _inline(block.parts), ""]
        elif isinstance(block, Figure):
            if figure_path is None:
                continue
            name = f"{figure_path.stem}-fig{block.number}.svg"
            save(block.plot, figure_path.with_name(name), block.number)
            lines += [f"![Figure {block.number}]({name})", "",
                      f"*Figure {block.number}: {_escape(block.caption)}*", ""]
    return "\n".join(lines).rstrip() + "\n"
