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
import re
from collections.abc import Callable

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


#: a power in a unit of a table cell (m/s^2, (m/s^2)^2/Hz, s^-1), after a letter or ")"
POWER = re.compile(r"(?<=[A-Za-z)])\^(?:\((-?[0-9]+)\)|(-?[0-9]+))")


def _cell_text(text: str) -> str:
    """A table cell's text for HTML: escaped, a unit's powers raised (``m/s^2`` ->
    m/s<sup>2</sup>) and its products dotted (``N*s/m`` -> N·s/m)."""
    escaped = _text(text)
    escaped = re.sub(r"(?<=[A-Za-z])\*(?=[A-Za-z])", "\u00b7", escaped)
    return POWER.sub(lambda m: f"<sup>{m.group(1) or m.group(2)}</sup>", escaped)


_WIDTH = re.compile(r'<svg class="m"[^>]*? width="([0-9.]+)em"')


def display_width(drawn: str) -> float:
    """The width of a drawn display formula in em: its pieces side by side, with the
    spaces between them (what a phone's CSS scales it by, ``--w``).

    Examples
    --------
    >>> display_width('<svg class="m" width="2.5em"></svg><svg class="m" width="1em">')
    3.5
    """
    pieces = sum(float(w) for w in _WIDTH.findall(drawn))
    return pieces + 1.2 * drawn.count("g-quad") + 0.35 * drawn.count("g-space")


#: the smallest figure text a reader is shown (px)
LEGIBLE_TEXT = 9.0
_VIEWBOX = re.compile(r'viewBox="[-0-9.]+ [-0-9.]+ ([0-9.]+) [0-9.]+"')
_TEXT_SIZE = re.compile(r'<text [^>]*?font-size="([0-9.]+)"')


def legible_width(svg: str) -> float:
    """The width (px) at which a drawn chart's smallest text is :data:`LEGIBLE_TEXT`
    high: its viewBox width scaled by 9 over its smallest text size (0 if none).

    Examples
    --------
    >>> legible_width('<svg viewBox="0 0 504 300"><text x="1" font-size="10">a</text></svg>')
    453.6
    """
    box = _VIEWBOX.search(svg)
    sizes = [float(size) for size in _TEXT_SIZE.findall(svg)]
    if box is None or not sizes:
        return 0.0
    return float(box.group(1)) * LEGIBLE_TEXT / min(sizes)


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
.table-scroll { max-width: 100%; overflow-x: auto; }
th, td { padding: .3rem .9rem; text-align: left; }
td { white-space: nowrap; }  /* a number stays on one line with its unit */
th svg.m, td svg.m { max-width: none; }  /* a unit in a narrow column keeps its size */
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
  /* a formula wider than the phone is set smaller to fit (its width in em is --w), down
     to 0.7 of the text; one wider still scrolls in its own box, and shadows at the edges
     where more of it lies show that it does (the page itself never scrolls sideways) */
  .equation .body { overflow-x: auto; overflow-y: hidden; white-space: nowrap; position: relative;
    text-align: left; padding-bottom: .4rem;
    font-size: clamp(0.7em, calc((100vw - 5.2rem) / var(--w, 1)), 1em);
    background:
      linear-gradient(to right, #fff 40%, rgba(255,255,255,0)) left / 1.5rem 100% no-repeat local,
      linear-gradient(to left, #fff 40%, rgba(255,255,255,0)) right / 1.5rem 100% no-repeat local,
      radial-gradient(farthest-side at 0 50%, rgba(0,0,0,.4), rgba(0,0,0,0))
        left / .9rem 100% no-repeat scroll,
      radial-gradient(farthest-side at 100% 50%, rgba(0,0,0,.4), rgba(0,0,0,0))
        right / .9rem 100% no-repeat scroll; }
  .equation .body .mp { max-width: none; }
  .equation .body wbr { display: none; }
  .equation .body svg.m { max-width: none; }
  table { min-width: 0; font-size: .95rem; }
  th, td { padding: .25rem .5rem; }
  /* a figure is never drawn so small that its text is below 9 px (--legible, the width
     at which it is, from html.py); narrower than that it scrolls in its own box, with
     shadows at the edges where more of it lies */
  figure .plot { overflow-x: auto; overflow-y: hidden;
    background:
      linear-gradient(to right, #fff 40%, rgba(255,255,255,0)) left / 1.5rem 100% no-repeat local,
      linear-gradient(to left, #fff 40%, rgba(255,255,255,0)) right / 1.5rem 100% no-repeat local,
      radial-gradient(farthest-side at 0 50%, rgba(0,0,0,.4), rgba(0,0,0,0))
        left / .9rem 100% no-repeat scroll,
      radial-gradient(farthest-side at 100% 50%, rgba(0,0,0,.4), rgba(0,0,0,0))
        right / .9rem 100% no-repeat scroll, #fff; }
  /* the chart's own white ground would hide the shadows: multiplied, white lets them show */
  figure .plot svg { min-width: var(--legible, 0); mix-blend-mode: multiply; }
  .table-scroll {
    background:
      linear-gradient(to right, #fff 40%, rgba(255,255,255,0)) left / 1.5rem 100% no-repeat local,
      linear-gradient(to left, #fff 40%, rgba(255,255,255,0)) right / 1.5rem 100% no-repeat local,
      radial-gradient(farthest-side at 0 50%, rgba(0,0,0,.4), rgba(0,0,0,0))
        left / .9rem 100% no-repeat scroll,
      radial-gradient(farthest-side at 100% 50%, rgba(0,0,0,.4), rgba(0,0,0,0))
        right / .9rem 100% no-repeat scroll; }
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

    def _inline(parts: tuple[Part, ...], text: Callable[[str], str] = _text) -> str:
        return "".join(math.inline(p.latex) if isinstance(p, Math) else text(p)
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
            drawn = math.display(block.latex)
            out.append(f'<div class="equation"><div class="body" style="--w: '
                       f'{display_width(drawn):.2f}">{drawn}</div><div class="number">'
                       f"{number}</div></div>")
        elif isinstance(block, Table):
            head = "".join(f"<th>{_inline(c, _cell_text)}</th>" for c in block.header)
            rows = "".join("<tr>" + "".join(f"<td>{_inline(c, _cell_text)}</td>" for c in row)
                           + "</tr>" for row in block.rows)
            # a table wider than a phone scrolls in its own box, with a visible cue
            out.append(f'<div class="table-scroll"><table><thead><tr>{head}</tr></thead>'
                       f"<tbody>{rows}</tbody></table></div>")
        elif isinstance(block, Note):
            out.append(f'<p class="note"><b>Warning:</b> {_inline(block.parts)}</p>')
        elif isinstance(block, Figure):
            svg = to_svg(block.plot, block.number)
            out.append(f'<figure><div class="plot" style="--legible: {legible_width(svg):.0f}px">'
                       f"{svg}</div><figcaption>Figure {block.number}: "
                       f"{_text(block.caption)}</figcaption></figure>")
    out[out.index("<body>") + 1] = math.glyphs()
    out += ["</main>", "</body>", "</html>"]
    return "\n".join(out) + "\n"
