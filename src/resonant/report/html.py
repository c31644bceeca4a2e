"""HTML writer: one self-contained page, formulas and plots as inline SVG.

No JavaScript, no web fonts, no external files: the page opens offline in any
modern browser and looks the same whatever fonts the reader has.  Formulas are
drawn as SVG with ``ziamath`` and its bundled STIX Two Math font (stretchy
brackets need an OpenType math font, which a plain system lacks); each glyph is
defined once per page.  A visually hidden MathML copy (``latex2mathml``) is kept
for screen readers, and a formula ziamath cannot draw is shown as MathML.  Wide
display formulas are broken between their top-level pieces, and a piece wider
than the page is scaled down, so nothing is cut on screen or in print.  On a phone
(a screen narrower than 40 em) a display formula is kept on one line and scrolls
sideways inside its own box, as in a textbook, rather than breaking at every operator;
the page itself never scrolls sideways.
"""

from __future__ import annotations

import html

from ..errors import printable
from ..expressions.mathml import SvgMath
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
from .plots import to_svg


def _text(text: str) -> str:
    """Model text for HTML: control and bidi characters shown as escapes, then HTML-escaped."""
    return html.escape(printable(text, limit=None))


CSS = """
:root { color-scheme: light; }
body { margin: 0; background: #f4f2ee; color: #1d1d1f;
  font-family: "STIX Two Text", "Latin Modern Roman", "Computer Modern Serif", Cambria,
    "Times New Roman", "Liberation Serif", Tinos, "Noto Serif", "DejaVu Serif", Georgia, serif;
  font-size: 17px; line-height: 1.55; }
main { max-width: 60rem; margin: 2rem auto; background: #fff; padding: 2.5rem 3.5rem 3rem;
  box-shadow: 0 1px 4px rgba(0,0,0,.12); border-radius: 2px; }
h1 { font-size: 1.7rem; line-height: 1.25; margin: 0 0 .4rem; font-weight: 600; }
h2 { font-size: 1.3rem; margin: 2.2rem 0 .6rem; padding-bottom: .2rem;
  border-bottom: 1px solid #d8d4cc; font-weight: 600; }
h3 { font-size: 1.08rem; margin: 1.6rem 0 .4rem; font-weight: 600; font-style: italic; }
p { margin: .55rem 0; text-align: justify; hyphens: auto; }
math { font-family: "STIX Two Math", "Latin Modern Math", "Cambria Math", "Noto Sans Math",
  math; font-size: 1.06em; }
svg.m { overflow: visible; max-width: 100%; height: auto; }
svg.glyphs { position: absolute; width: 0; height: 0; overflow: hidden; }
.mathml { position: absolute; width: 1px; height: 1px; margin: -1px; padding: 0;
  overflow: hidden; clip-path: inset(50%); white-space: nowrap; }
.mp { display: inline-block; max-width: 100%; }
.g-quad { margin-left: 1.2em; }
.g-space { margin-left: .35em; }
.equation { display: flex; align-items: center; gap: 1rem; margin: .7rem 0; }
.equation .body { flex: 1 1 auto; min-width: 0; text-align: center; padding: .15rem 0;
  line-height: 1.2; }
.equation .body > math { margin: 0 auto; overflow-x: auto; max-width: 100%; }
.equation .number { flex: 0 0 auto; color: #444; min-width: 2.8rem; text-align: right; }
table { border-collapse: collapse; margin: .8rem auto; min-width: 50%; }
th, td { padding: .3rem .9rem; text-align: left; }
thead th { border-top: 2px solid #333; border-bottom: 1px solid #333; font-weight: 600; }
tbody tr:last-child td { border-bottom: 2px solid #333; }
figure { margin: 1.4rem 0; text-align: center; }
figure svg { max-width: 100%; height: auto; }
figcaption { font-size: .92rem; color: #333; margin-top: .3rem; text-align: left; }
.note { border-left: 4px solid #c9822b; background: #fbf4ea; padding: .5rem .9rem;
  margin: .6rem 0; }
.source { color: #555; font-size: .95rem; }
code { font-family: "DejaVu Sans Mono", monospace; font-size: .9em; }
@media screen and (max-width: 40rem) {
  main { margin: 0; padding: 1.2rem 1rem 2rem; border-radius: 0; box-shadow: none; }
  p { text-align: left; }
  .equation { gap: .4rem; }
  .equation .number { min-width: 0; }
  .equation .body { overflow-x: auto; overflow-y: hidden; white-space: nowrap; position: relative;
    text-align: left; padding-bottom: .4rem; }
  .equation .body .mp { max-width: none; }
  .equation .body wbr { display: none; }
  .equation .body svg.m { max-width: none; }
  table { min-width: 0; font-size: .95rem; }
  th, td { padding: .25rem .5rem; }
}
@media print {
  body { background: #fff; font-size: 11pt; }
  main { box-shadow: none; margin: 0; padding: 0; max-width: none; }
  .equation, figure, table { break-inside: avoid; }
  svg.m, figure svg { max-width: 100%; height: auto; }
}
"""


def render_html(report: Report) -> str:
    math = SvgMath()

    def _inline(parts: tuple[Part, ...]) -> str:
        return "".join(math.inline(p.latex) if isinstance(p, Math) else _text(p)
                       for p in parts)

    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           '<meta name="viewport" content="width=device-width, initial-scale=1">',
           f"<title>{_text(report.title)}</title>",
           '<meta name="generator" content="resonant report">',
           f"<style>{CSS}</style>", "</head>", "<body>", "", "<main>",
           f"<h1>{_text(report.title)}</h1>"]
    for block in report.blocks:
        if isinstance(block, Heading):
            level = min(6, block.level)
            out.append(f"<h{level}>{_text(block.text)}</h{level}>")
        elif isinstance(block, Paragraph):
            out.append(f"<p>{_inline(block.parts)}</p>")
        elif isinstance(block, Equation):
            number = f"({block.number})" if block.number is not None else ""
            out.append(f'<div class="equation"><div class="body">{math.display(block.latex)}'
                       f'</div><div class="number">{number}</div></div>')
        elif isinstance(block, Table):
            head = "".join(f"<th>{_inline(c)}</th>" for c in block.header)
            rows = "".join("<tr>" + "".join(f"<td>{_inline(c)}</td>" for c in row) + "</tr>"
                           for row in block.rows)
            out.append(f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>")
        elif isinstance(block, Note):
            out.append(f'<p class="note"><b>Warning:</b> {_inline(block.parts)}</p>')
        elif isinstance(block, Figure):
            out.append(f"<figure>{to_svg(block.plot, block.number)}<figcaption>Figure "
                       f"{block.number}: {_text(block.caption)}</figcaption></figure>")
    out[out.index("<body>") + 1] = math.glyphs()
    out += ["</main>", "</body>", "</html>"]
    return "\n".join(out) + "\n"
