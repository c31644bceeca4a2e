"""LaTeX writer: an ``article`` that compiles with pdflatex (amsmath, amssymb, graphicx).

Figures are written as PDF files next to the ``.tex`` file and included with
``\\includegraphics``; without an output path they are left out.
"""

from __future__ import annotations

import re
from pathlib import Path

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

_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#",
            "_": r"\_", "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}",
            "^": r"\textasciicircum{}", "<": r"\textless{}", ">": r"\textgreater{}",
            "“": "``", "”": "''", "‘": "`", "’": "'", "—": "---", "–": "--",
            "δ": r"$\delta$", "ω": r"$\omega$", "φ": r"$\varphi$", "…": r"\dots{}"}

PREAMBLE = r"""\documentclass[11pt,a4paper]{article}
\usepackage[utf8]{inputenc}
\usepackage[T1]{fontenc}
\usepackage{lmodern}
\usepackage{amsmath,amssymb}
\usepackage{graphicx}
\usepackage[margin=2.2cm]{geometry}
\setlength{\parindent}{0pt}
\setlength{\parskip}{0.5em}
\allowdisplaybreaks
"""


def escape(text: str) -> str:
    """Text for LaTeX: specials escaped; characters pdflatex cannot typeset replaced by ?."""
    out = []
    for ch in text:
        if ch in _SPECIAL:
            out.append(_SPECIAL[ch])
        elif ord(ch) < 256 and (ch.isprintable() or ch == " "):
            out.append(ch)
        else:
            out.append("?")
    return "".join(out)


#: a power in a unit (m/s^2, (m/s^2)^2/Hz, s^-1), after a letter or ")"
_POWER = re.compile(r"(?<=[A-Za-z)])\^(?:\((-?[0-9]+)\)|(-?[0-9]+))")


def cell_text(text: str) -> str:
    r"""A table cell's text for LaTeX: escaped, a unit's powers raised and its products
    dotted (``m/s^2`` -> ``m/s\textsuperscript{2}``, ``N*s/m`` -> ``N$\cdot$s/m``).

    Examples
    --------
    >>> print(cell_text("219.7 m/s^2"), cell_text("N*s/m"), cell_text("a_b"))
    219.7 m/s\textsuperscript{2} N$\cdot$s/m a\_b
    """
    out, last = [], 0
    for match in _POWER.finditer(text):
        out.append(_dotted(text[last:match.start()]))
        out.append(rf"\textsuperscript{{{match.group(1) or match.group(2)}}}")
        last = match.end()
    out.append(_dotted(text[last:]))
    return "".join(out)


def _dotted(text: str) -> str:
    """Escaped, a product of units (``N*s``) with a centred dot."""
    return r"$\cdot$".join(escape(piece) for piece in re.split(r"(?<=[A-Za-z])\*(?=[A-Za-z])",
                                                               text))


def _inline(parts: tuple[Part, ...], cell: bool = False) -> str:
    text = cell_text if cell else escape
    return "".join("$" + p.latex + "$" if isinstance(p, Math) else text(p) for p in parts)


def render_latex(report: Report, figure_path: Path | None = None) -> str:
    out = [PREAMBLE, rf"\title{{{escape(report.title)}}}", r"\date{}",
           r"\begin{document}", r"\maketitle"]
    for block in report.blocks:
        if isinstance(block, Heading):
            command = "section*" if block.level <= 2 else "subsection*"
            out.append(rf"\{command}{{{escape(block.text)}}}")
        elif isinstance(block, Paragraph):
            out.append(_inline(block.parts) + "\n")
        elif isinstance(block, Equation):
            tag = rf" \tag{{{block.number}}}" if block.number is not None else ""
            out.append(r"\begin{equation*}" + "\n" + block.latex + tag + "\n"
                       + r"\end{equation*}")
        elif isinstance(block, Table):
            columns = "l" * len(block.header)
            lines = [r"\begin{center}", rf"\begin{{tabular}}{{{columns}}}", r"\hline",
                     " & ".join(_inline(c, True) for c in block.header) + r" \\", r"\hline"]
            lines += [" & ".join(_inline(c, True) for c in row) + r" \\" for row in block.rows]
            lines += [r"\hline", r"\end{tabular}", r"\end{center}"]
            out.append("\n".join(lines))
        elif isinstance(block, Note):
            out.append(r"\fbox{\parbox{0.95\linewidth}{\textbf{Warning:} "
                       + _inline(block.parts) + "}}\n")
        elif isinstance(block, Figure):
            if figure_path is None:
                continue
            name = f"{figure_path.stem}-fig{block.number}.pdf"
            save(block.plot, figure_path.with_name(name), block.number)
            out.append("\n".join([r"\begin{figure}[ht]", r"\centering",
                                  rf"\includegraphics[width=\linewidth]{{{name}}}",
                                  rf"\caption{{{escape(block.caption)}}}", r"\end{figure}"]))
    out.append(r"\end{document}")
    return "\n".join(out) + "\n"
