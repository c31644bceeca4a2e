"""The one table description a result's text, its HTML and its Markdown are written from.

A result describes its numbers once, as a :class:`ResultTable` (a header, rows of cells
already formatted, each column aligned left or right), and each writer renders that
description: :meth:`ResultTable.text` for the terminal (columns padded to one width),
:meth:`ResultTable.html` for Jupyter and the report (every cell escaped),
:meth:`ResultTable.markdown` (``|`` and other Markdown characters escaped).  The cells are
strings so that every writer shows the same digits; :func:`number_cell` is the one rule
for a number in a table.

Examples
--------
>>> table = ResultTable(("name", "RMS"),
...                     (("x1", number_cell(0.0123456)), ("x2", number_cell(None))), align="lr")
>>> print(table.text())
  name      RMS
  x1    0.01235
  x2          -
>>> print(table.markdown())
| name | RMS |
|:--|--:|
| x1 | 0.01235 |
| x2 | - |
"""

from __future__ import annotations

import html
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

#: what a missing or non-finite number shows in a table
MISSING = "-"

_MARKDOWN_SPECIAL = re.compile(r"([\\`*_{}\[\]<>()#+!|~])")


def number_cell(value: float | None, digits: int = 4) -> str:
    """A number as a table shows it: ``digits`` significant digits, ``-`` for none.

    Parameters
    ----------
    value : float or None
    digits : int
        Significant digits.

    Returns
    -------
    str

    Examples
    --------
    >>> number_cell(1234.5678), number_cell(float("nan")), number_cell(2e-7, 3)
    ('1235', '-', '2e-07')
    """
    if value is None or not math.isfinite(value):
        return MISSING
    return f"{value:.{digits}g}"


def number_column(values: Sequence[float | None], digits: int = 4) -> tuple[str, ...]:
    """A column of numbers in one notation: ``digits`` significant digits where every
    number fits that way, else all in scientific notation (a column never switches from
    ``9999`` to ``1e+04`` half-way down).

    Parameters
    ----------
    values : sequence of float or None
    digits : int
        Significant digits.

    Returns
    -------
    tuple of str

    Examples
    --------
    >>> number_column([1.5, 250.0, 9999.0])
    ('1.5', '250', '9999')
    >>> number_column([1.5, 25000.0])
    ('1.500e+00', '2.500e+04')
    """
    finite = [abs(v) for v in values if v is not None and math.isfinite(v) and v != 0]
    wide = bool(finite) and (max(finite) >= 10.0 ** digits or min(finite) < 1e-3)
    return tuple(MISSING if v is None or not math.isfinite(v) else
                 f"{v:.{digits - 1}e}" if wide else f"{v:.{digits}g}" for v in values)


@dataclass(frozen=True)
class ResultTable:
    """A header and rows of formatted cells.

    Parameters
    ----------
    header : tuple of str
        The column headings.
    rows : tuple of tuple of str
        The cells, one tuple per row, as long as ``header``.
    align : str
        One letter per column, ``l`` (left) or ``r`` (right); left for every column when
        empty.
    title : str
        A caption (HTML ``<caption>``; the text and Markdown writers leave it to the caller).

    Examples
    --------
    >>> ResultTable(("a",), (("<b>",),)).html()
    '<table><tr><th>a</th></tr><tr><td>&lt;b&gt;</td></tr></table>'
    """

    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    align: str = ""
    title: str = ""

    def __post_init__(self) -> None:
        if any(len(row) != len(self.header) for row in self.rows):
            raise ValueError("every row of a table has one cell per column")
        if self.align and (len(self.align) != len(self.header) or set(self.align) - {"l", "r"}):
            raise ValueError("align has one letter, l or r, per column")

    def _alignment(self) -> str:
        return self.align or "l" * len(self.header)

    def text(self, indent: str = "  ") -> str:
        """The table for a terminal: each column padded to its widest cell.

        Parameters
        ----------
        indent : str
            Put before every line.

        Returns
        -------
        str
            The lines, without a final newline.

        Examples
        --------
        >>> print(ResultTable(("n", "value"), (("1", "10"),), align="rr").text(indent=""))
        n  value
        1     10
        """
        widths = [max(len(self.header[i]), *(len(r[i]) for r in self.rows))
                  for i in range(len(self.header))]

        def line(cells: tuple[str, ...]) -> str:
            padded = [c.rjust(w) if a == "r" else c.ljust(w)
                      for c, w, a in zip(cells, widths, self._alignment())]
            return (indent + "  ".join(padded)).rstrip()

        return "\n".join([line(self.header), *(line(r) for r in self.rows)])

    def html(self) -> str:
        """The table as HTML, every cell escaped.

        Returns
        -------
        str

        Examples
        --------
        >>> ResultTable(("x",), (("1",),), align="r").html()
        '<table><tr><th>x</th></tr><tr><td style="text-align:right">1</td></tr></table>'
        """
        def cell(text: str, a: str) -> str:
            style = ' style="text-align:right"' if a == "r" else ""
            return f"<td{style}>{html.escape(text)}</td>"

        caption = f"<caption>{html.escape(self.title)}</caption>" if self.title else ""
        head = "<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in self.header) + "</tr>"
        body = "".join("<tr>" + "".join(cell(c, a) for c, a in zip(row, self._alignment()))
                       + "</tr>" for row in self.rows)
        return f"<table>{caption}{head}{body}</table>"

    def markdown(self) -> str:
        """The table as a Markdown (GitHub) table, Markdown's characters escaped.

        Returns
        -------
        str

        Examples
        --------
        >>> print(ResultTable(("a|b",), (("*x*",),)).markdown())
        | a\\|b |
        |:--|
        | \\*x\\* |
        """
        def escape(text: str) -> str:
            return _MARKDOWN_SPECIAL.sub(r"\\\1", text).replace("\n", " ")

        rule = "|" + "|".join(":--" if a == "l" else "--:" for a in self._alignment()) + "|"
        lines = ["| " + " | ".join(escape(h) for h in self.header) + " |", rule]
        lines += ["| " + " | ".join(escape(c) for c in row) + " |" for row in self.rows]
        return "\n".join(lines)


__all__ = ["ResultTable", "number_cell", "number_column", "MISSING"]
