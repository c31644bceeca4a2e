"""A Sphinx extension: the site's mathematics as MathML, written when the site is built.

Sphinx's default renders ``$...$`` and ``$$...$$`` (MyST's dollar math) with MathJax
loaded from a CDN; this site loads nothing from the network.  Each formula is converted by
resonant's own LaTeX-to-MathML route (:func:`resonant.views.mathml.latex_to_mathml`, the
same as the reports' screen-reader copy), which every current browser draws natively.
"""

from __future__ import annotations

from typing import Any

from docutils import nodes

from resonant.views.mathml import latex_to_mathml


def _inline(self: Any, node: Any) -> None:
    self.body.append(f'<span class="math">{latex_to_mathml(node.astext(), False)}</span>')
    raise nodes.SkipNode


def _display(self: Any, node: Any) -> None:
    number = node.get("number")
    label = f'<span class="eqno">({number})</span>' if number else ""
    self.body.append(f'<div class="math-display">{latex_to_mathml(node.astext(), True)}'
                     f"{label}</div>")
    raise nodes.SkipNode


def setup(app: Any) -> dict[str, Any]:
    """Register the renderer (chosen in conf.py by ``html_math_renderer``)."""
    app.add_html_math_renderer("offline_mathml", (_inline, None), (_display, None))
    return {"parallel_read_safe": True, "version": "1"}
