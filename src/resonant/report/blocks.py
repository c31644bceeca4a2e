"""The pieces a report is made of; every writer (HTML, Markdown, LaTeX) renders these.

Text is a tuple of parts: plain strings (escaped by each writer) and
:class:`Math` (inline LaTeX).  Model text (titles, descriptions) is always a
plain part, so a ``$`` or ``<`` in a model file cannot break the output.

Examples
--------
>>> p = paragraph("the mass ", Math("m_{1}"), " of the cart")
>>> [type(part).__name__ for part in p.parts]
['str', 'Math', 'str']
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from .plots import PlotData


@dataclass(frozen=True)
class Math:
    """Inline math (LaTeX)."""

    latex: str


Part = str | Math


@dataclass(frozen=True)
class Heading:
    text: str
    level: int = 2


@dataclass(frozen=True)
class Paragraph:
    parts: tuple[Part, ...]


@dataclass(frozen=True)
class Equation:
    """Display math; ``number`` is the equation number, or None."""

    latex: str
    number: int | None = None


@dataclass(frozen=True)
class Table:
    header: tuple[tuple[Part, ...], ...]
    rows: tuple[tuple[tuple[Part, ...], ...], ...]


@dataclass(frozen=True)
class Figure:
    """A plot (data, drawn by each writer) with its caption and figure number."""

    plot: PlotData
    caption: str
    number: int


@dataclass(frozen=True)
class Note:
    """A highlighted remark (warnings)."""

    parts: tuple[Part, ...]


Block = Heading | Paragraph | Equation | Table | Figure | Note


def paragraph(*parts: Part) -> Paragraph:
    return Paragraph(tuple(p for p in parts if p != ""))


def cell(*parts: Part) -> tuple[Part, ...]:
    return tuple(parts)


@dataclass(frozen=True)
class Report:
    """A worked solution: a title and its blocks, in reading order.

    Parameters
    ----------
    title : str
        The report's title.
    blocks : tuple of Block
        Headings, paragraphs, equations, tables, figures and notes.

    Examples
    --------
    >>> Report("Solution", (Heading("Data"),)).headings()
    ['Data']
    """

    title: str
    blocks: tuple[Block, ...]

    def headings(self) -> list[str]:
        return [b.text for b in self.blocks if isinstance(b, Heading)]


__all__ = ["Math", "Part", "Heading", "Paragraph", "Equation", "Table", "Figure", "Note",
           "Block", "paragraph", "cell", "Report"]
