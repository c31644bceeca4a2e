"""A Sphinx extension: the site's mathematics drawn at build time, as the reports draw it.

Sphinx's default renders ``$...$`` and ``$$...$$`` (MyST's dollar math) with MathJax
loaded from a CDN; this site loads nothing from the network.  Each formula is drawn as
SVG by resonant's own route (:class:`resonant.expressions.mathml.SvgMath`: ziamath with its
bundled STIX Two Math font, so brackets stretch whatever fonts the reader has), with a
visually hidden MathML copy for screen readers; each page defines its glyphs once.
"""

from __future__ import annotations

from typing import Any

from docutils import nodes

from resonant.expressions.mathml import SvgMath

#: docname -> the formulas of that page (their shared glyphs)
_PAGES: dict[str, SvgMath] = {}


def _math(self: Any) -> SvgMath:
    return _PAGES.setdefault(self.builder.current_docname, SvgMath())


def _inline(self: Any, node: Any) -> None:
    self.body.append(f'<span class="math">{_math(self).inline(node.astext())}</span>')
    raise nodes.SkipNode


def _display(self: Any, node: Any) -> None:
    number = node.get("number")
    label = f'<span class="eqno">({number})</span>' if number else ""
    self.body.append(f'<div class="math-display"><div class="math-body">'
                     f"{_math(self).display(node.astext())}</div>{label}</div>")
    raise nodes.SkipNode


def _glyphs(app: Any, pagename: str, templatename: str, context: dict[str, Any],
            doctree: Any) -> None:
    """The page's glyph definitions, once, at the end of its body."""
    math = _PAGES.pop(pagename, None)
    if math is not None and "body" in context:
        context["body"] += math.glyphs()


def setup(app: Any) -> dict[str, Any]:
    """Register the renderer (chosen in conf.py by ``html_math_renderer``)."""
    app.add_html_math_renderer("offline_svg", (_inline, None), (_display, None))
    app.connect("html-page-context", _glyphs)
    return {"parallel_read_safe": True, "parallel_write_safe": False, "version": "1"}
