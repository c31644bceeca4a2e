"""Formulas drawn as SVG for the HTML report (expressions.mathml): pieces, glyphs, fallbacks."""

from __future__ import annotations

import re

import pytest

from resonant.expressions import mathml
from resonant.expressions.mathml import SvgMath, formula_pieces, latex_to_svg

pytest.importorskip("ziamath")


def _leaves(pieces: mathml.Pieces) -> list[str]:
    if not pieces.children:
        return [pieces.latex]
    return [leaf for child in pieces.children for leaf in _leaves(child)]


def test_pieces_break_only_at_the_top_level():
    latex = (r"\begin{bmatrix} a + b & c = d \end{bmatrix}\begin{bmatrix} x \end{bmatrix} + "
             r"\left(e - f\right) g = \frac{h + i}{2} - (j, k), \quad l = -m")
    pieces = formula_pieces(latex)
    assert [p.gap for p in pieces.children] == ["", "quad"]
    leaves = _leaves(pieces)
    assert leaves == [
        r"\begin{bmatrix} a + b & c = d \end{bmatrix}\begin{bmatrix} x \end{bmatrix}",
        r"{}+ \left(e - f\right) g",
        r"{}= \frac{h + i}{2}",
        r"{}- (j, k),",
        "l",
        "{}= -m",  # a sign after a relation is not a break
    ]


def test_pieces_of_a_list_and_a_short_formula():
    pieces = formula_pieces(r"\lambda = -1 - 2\,i,\ -1 + 2\,i,")
    assert [p.gap for p in pieces.children] == ["", "space"]
    assert _leaves(pieces) == [r"\lambda", "{}= -1", r"{}- 2\,i,", "-1", r"{}+ 2\,i,"]
    assert formula_pieces("x_{1}").children == ()
    assert formula_pieces(r"\frac{a}{b}").latex == r"\frac{a}{b}"


def test_svg_sizes_in_em_and_baseline():
    low = latex_to_svg("x", True)
    frac = latex_to_svg(r"\frac{a}{b}", True)
    assert low is not None and frac is not None
    assert 0.2 < low.width < 1 and 0.2 < low.height < 1 and 0 <= low.depth < 0.1
    assert frac.height > 1.5 * low.height and frac.depth > 0.3  # below the baseline
    assert 'width="' in frac.body and "em" in frac.body and "vertical-align:-" in frac.body
    assert "<symbol" not in frac.body and frac.symbols
    assert 'fill="currentColor"' in frac.body  # the text colour


def test_page_defines_each_glyph_once_and_keeps_uses():
    page = SvgMath()
    first = page.display(r"a\ \text{rad} = b")  # \ draws an empty glyph: <symbol .../>
    second = page.display(r"a + b")
    glyphs = page.glyphs()
    ids = re.findall(r'<symbol id="([^"]+)"', glyphs)
    assert len(ids) == len(set(ids))
    used = set(re.findall(r'href="#([^"]+)"', first + second))
    assert used and used <= set(ids)
    assert first.count("<use") >= 6  # a, r, a, d, =, b: nothing swallowed by an empty glyph
    assert '<span class="mathml"><math' in first  # the accessible copy
    assert 'aria-hidden="true"' in first


def test_glyph_id_collision_is_renamed():
    page = SvgMath()
    a = mathml.SvgFormula('<svg x><use href="#g_1" /></svg>', (("g_1", '<symbol id="g_1">A'
                                                                          '</symbol>'),), 1, 1, 0)
    b = mathml.SvgFormula('<svg x><use href="#g_1" /></svg>', (("g_1", '<symbol id="g_1">B'
                                                                          '</symbol>'),), 1, 1, 0)
    assert 'href="#g_1"' in page._register(a)
    assert 'href="#g_1-1"' in page._register(b)
    assert 'href="#g_1-1"' in page._register(b)  # the same other glyph again: same new id
    assert page.glyphs().count("<symbol") == 2


def test_fallback_to_mathml(monkeypatch):
    monkeypatch.setattr(mathml, "latex_to_svg", lambda latex, display: None)
    page = SvgMath()
    assert page.display("a = b").startswith("<math")
    assert page.inline("a").startswith("<math")


def test_linear_layout_draws_the_same():
    """The speed-up of ziamath's row layout leaves every drawing unchanged."""
    zm = mathml._ziamath()
    from ziamath.nodes.mrow import Mrow

    linear = Mrow._get_height_nostretch
    original = next(c.cell_contents for c in linear.__closure__
                    if getattr(c.cell_contents, "__name__", "") == "_get_height_nostretch")
    formulas = [r"\begin{bmatrix} \frac{a}{\left(b + \frac{c}{d}\right)} & 0 \\ 0 & "
                r"\left.\frac{\partial^{2} T}{\partial x^{2}}\right|_{q=0} \end{bmatrix}",
                r"\begin{cases} \left(k - \omega^{2} \left(m_{1} + m_{2}\right)\right) L_{1} "
                r"= F, \\ x = \sqrt{L^{2} + N^{2}} \end{cases}"]
    fast = [zm.Latex(f, size=20).svg() for f in formulas]
    try:
        Mrow._get_height_nostretch = original
        slow = [zm.Latex(f, size=20).svg() for f in formulas]
    finally:
        Mrow._get_height_nostretch = linear
    assert fast == slow
