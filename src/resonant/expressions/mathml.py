"""LaTeX formulas as MathML (Jupyter views) and as SVG drawn with a bundled math font.

MathML needs an OpenType math font on the reader's machine for stretchy brackets;
the HTML report therefore draws its formulas as inline SVG with ``ziamath`` (which
ships STIX Two Math), keeps the MathML as a visually hidden accessible copy, and
offers line breaks between the pieces of a wide display formula
(:func:`formula_pieces`) so that nothing is cut at any page width.

Examples
--------
>>> latex_to_mathml(r"\\frac{a}{b}", False).startswith("<math")
True
>>> [p.latex for p in formula_pieces(r"a = b + c, \\quad d = e").children]
['a = b + c,', 'd = e']
"""

from __future__ import annotations

import functools
import html
import re
from dataclasses import dataclass
from typing import Any
from xml.etree import ElementTree

_FENCE = re.compile(r'<mo( stretchy="true" fence="true" form="(?:prefix|postfix)")>')

_PAREN = re.compile(r'<mo stretchy="false">(&#x00028;|&#x00029;)</mo>')
_SIMPLE_FENCE = re.compile(
    r"\\left\(((?:(?!\\left|\\right|\\frac|\\begin|\\sum|\\sqrt|\\int).)*?)\\right\)",
    re.DOTALL)


def simple_parentheses(latex: str) -> str:
    """``\\left( x \\right)`` -> ``(x)`` where nothing tall is inside.

    Stretchy fences are drawn with loose spacing by browsers without a math
    font; plain parentheses look right and still grow around fractions when
    those keep their ``\\left(``.
    """
    while True:
        replaced = _SIMPLE_FENCE.sub(lambda m: "(" + m.group(1).strip() + ")", latex)
        if replaced == latex:
            return latex
        latex = replaced


@functools.lru_cache(maxsize=4096)  # a report asks for the same formula several times
def latex_to_mathml(latex: str, display: bool) -> str:
    """MathML of a LaTeX formula (the LaTeX itself, as code, if it cannot be converted).

    Parameters
    ----------
    latex : str
    display : bool
        Block (display) or inline math.

    Returns
    -------
    str
    """
    from latex2mathml.converter import convert

    latex = simple_parentheses(latex)
    try:
        mathml = convert(latex, display="block" if display else "inline")
    except Exception:  # noqa: BLE001 - any converter failure: show the source instead
        return f"<code>{html.escape(latex)}</code>"
    # \left( ... \right) fences: no operator spacing inside the parentheses
    mathml = _FENCE.sub(r'<mo\1 lspace="0em" rspace="0em">', mathml)
    return _PAREN.sub(r'<mo stretchy="false" lspace="0em" rspace="0em">\1</mo>', mathml)


# --------------------------------------------------------------------------- SVG

#: ziamath's font size (SVG user units per em); sizes are written in em.
_SIZE = 20.0
_NUMBER = r"(-?\d+(?:\.\d+)?)"
_VIEWBOX = re.compile(r'viewBox="' + r"\s+".join([_NUMBER] * 4) + '"')
_SYMBOL = re.compile(r'<symbol id="([^"]+)"[^>]*?(?:/>|>.*?</symbol>)', re.DOTALL)
_ROOT = re.compile(r"^<svg\b[^>]*>|</svg>\s*$")


def _ziamath() -> Any:
    """ziamath, imported on first use, with its row layout made linear in the depth.

    Before drawing a row, ziamath lays out each of its children once more only to
    find the height its stretchy operators (brackets) must cover, and did so again
    inside that measuring pass: the time doubled with every level of nesting (6 s
    for the reference exercise).  The measurement is skipped where its result is
    never used, which leaves every drawing byte-for-byte the same: inside the
    measuring pass (stretchy operators do not count towards the height there) and
    for rows without a stretchy operator (nested rows measure themselves).
    """
    import ziamath
    from ziamath import operators
    from ziamath.nodes.mrow import Mrow

    measure = getattr(Mrow, "_get_height_nostretch", None)
    if measure is None or getattr(measure, "_resonant_linear", False):
        return ziamath
    stretchy = {name for (name, _), params in operators.operators.items()
                if params.get("stretchy", "false") != "false"}

    def may_stretch(element: ElementTree.Element) -> bool:
        if element.tag in ("mrow", "math", "mtd", "mtr", "none"):
            return False  # a row of its own: it measures its own children
        if element.tag in ("mo", "mi"):
            text = (element.text or "").strip()
            flag = element.get("stretchy")
            return flag == "true" or (flag is None and text in stretchy) or (
                "minsize" in element.attrib or "maxsize" in element.attrib)
        return any(may_stretch(child) for child in element)

    def linear(self: Mrow, line: list[ElementTree.Element], **kwargs: object
               ) -> tuple[float, float]:
        if kwargs.get("nostretch") or not any(may_stretch(child) for child in line):
            return 0.0, 0.0
        return measure(self, line, **kwargs)

    linear._resonant_linear = True  # type: ignore[attr-defined]
    Mrow._get_height_nostretch = linear  # type: ignore[method-assign]
    return ziamath


@dataclass(frozen=True)
class SvgFormula:
    """One formula drawn as SVG; lengths in em of the surrounding text.

    ``body`` is the ``<svg>`` element without its glyph ``<symbol>`` definitions,
    which are in ``symbols`` (id, markup) so that a page defines each glyph once.
    """

    body: str
    symbols: tuple[tuple[str, str], ...]
    width: float
    height: float
    depth: float


@functools.lru_cache(maxsize=4096)
def latex_to_svg(latex: str, display: bool) -> SvgFormula | None:
    """The formula drawn with ziamath's own math font; None if it cannot be drawn.

    Parameters
    ----------
    latex : str
    display : bool
        Display style (fractions and limits full size) or inline (text) style.

    Returns
    -------
    SvgFormula or None
    """
    zm = _ziamath()
    latex = simple_parentheses(latex).replace(r"\implies", r"\;\Longrightarrow\;")
    try:
        root = ElementTree.fromstring(zm.tex.tex2mml(latex, inline=not display))
        for element in root.iter():
            element.tag = element.tag.rpartition("}")[2]
        _typeset(root)
        root.set("mathcolor", "currentColor")
        svg = zm.Math(root, size=_SIZE, margin=0).svg()
    except Exception:  # noqa: BLE001 - any conversion or layout failure: caller shows MathML
        return None
    box = _VIEWBOX.search(svg)
    if box is None:
        return None
    x, y, w, h = (float(v) for v in box.groups())
    symbols = tuple((m.group(1), m.group(0)) for m in _SYMBOL.finditer(svg))
    inner = _ROOT.sub("", _SYMBOL.sub("", svg))
    body = (f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{x:g} {y:g} {w:g} {h:g}" '
            f'width="{w / _SIZE:.3f}em" height="{h / _SIZE:.3f}em" '
            f'style="vertical-align:{-(h + y) / _SIZE:.3f}em">{inner}</svg>')
    return SvgFormula(body, symbols, w / _SIZE, h / _SIZE, (h + y) / _SIZE)


_SIGNS = {"\u2212", "+", "\u00b1", "\u2213", "-"}
_CLOSING = {")", "]", "}", "|", "\u2016", "\u27e9", "\u230b", "\u2309"}


def _typeset(root: ElementTree.Element) -> None:
    """Textbook spacing where ziamath's defaults differ.

    A sign after an operator or an opening bracket is a prefix operator (ziamath
    decides the form from the position in the row alone and spaced ``= −2`` as a
    subtraction); matrix columns are 0.8 em apart (0.3 em ran the entries together).
    """
    for parent in root.iter():
        if parent.tag == "mtable":
            parent.attrib.setdefault("columnspacing", "0.8em")
            parent.attrib.setdefault("rowspacing", "0.4em")
        previous: ElementTree.Element | None = None
        for child in parent:
            if (child.tag == "mo" and (child.text or "").strip() in _SIGNS
                    and previous is not None and previous.tag == "mo"
                    and (previous.text or "").strip() not in _CLOSING
                    and "form" not in child.attrib):
                child.set("form", "prefix")
            previous = child


# ---------------------------------------------------------------- line breaking

_TOKEN = re.compile(r"\\(?:[A-Za-z]+|.)|.", re.DOTALL)
_OPEN = {"{", "(", "[", r"\{", r"\langle", r"\lbrace", r"\lvert"}
_CLOSE = {"}", ")", "]", r"\}", r"\rangle", r"\rbrace", r"\rvert"}
_RELATIONS = {"=", r"\approx", r"\equiv", r"\le", r"\ge", r"\leq", r"\geq", "<", ">",
              r"\neq", r"\sim", r"\cong"}
_BINARY = {"+", "-", r"\pm", r"\mp"}
#: tokens after which + and - are signs, not binary operators
_NO_OPERAND = _RELATIONS | _BINARY | {",", ";", r"\quad", r"\qquad", r"\implies", r"\cdot",
                                      r"\times", r"\,", r"\ ", r"\;", "&"}
#: break levels, coarsest first: (separator tokens, separator kept where)
_LEVELS: tuple[tuple[frozenset[str], str], ...] = (
    (frozenset({r"\quad", r"\qquad"}), "drop"),
    (frozenset({r"\implies", r"\iff"}), "next"),
    (frozenset({","}), "previous"),
    (frozenset(_RELATIONS), "next"),
    (frozenset(_BINARY), "next"),
)


@dataclass(frozen=True)
class Pieces:
    """A display formula cut at its top-level break points.

    A leaf has ``latex`` (a formula of its own; a piece that starts with a relation
    or an operator starts with ``{}`` so that the operator keeps its spacing) and no
    children; ``gap`` is the space before the piece (``"quad"``, ``"space"`` or "").
    """

    latex: str
    children: tuple[Pieces, ...] = ()
    gap: str = ""


def _top_level(tokens: list[str]) -> list[int]:
    """Indices of the tokens at nesting depth 0 (outside braces, parentheses, environments)."""
    depth, out, i = 0, [], 0
    while i < len(tokens):
        t = tokens[i]
        if t in (r"\left", r"\right", r"\bigl", r"\bigr", r"\Bigl", r"\Bigr"):
            depth += 1 if t in (r"\left", r"\bigl", r"\Bigl") else -1
            i += 2  # the delimiter belongs to \left / \right
            continue
        if t in (r"\begin", r"\end"):
            depth += 1 if t == r"\begin" else -1
            while i + 1 < len(tokens) and tokens[i + 1] != "}":  # the environment name
                i += 1
            i += 2
            continue
        if t in _OPEN:
            depth += 1
        elif t in _CLOSE:
            depth -= 1
        elif depth == 0:
            out.append(i)
        i += 1
    return out


def _split(tokens: list[str], level: int) -> Pieces:
    text = "".join(tokens).strip()
    if level >= len(_LEVELS):
        return Pieces(text)
    separators, keep = _LEVELS[level]
    cuts: list[int] = []
    top = set(_top_level(tokens))
    previous = ""  # the token before, at any depth: "}" of \end{...} or ")" is an operand
    for i, t in enumerate(tokens):
        if t.isspace():
            continue
        if i in top and t in separators and (
                keep != "next" or t not in _BINARY or (previous and previous not in _NO_OPERAND)):
            cuts.append(i)
        previous = t
    parts: list[tuple[list[str], str]] = []
    start, gap = 0, ""
    for i in cuts:
        end = i + 1 if keep == "previous" else i
        if "".join(tokens[start:end]).strip():
            parts.append((tokens[start:end], gap))
        start = i + 1 if keep in ("previous", "drop") else i
        gap = "quad" if keep == "drop" else "space" if keep == "previous" else ""
    parts.append((tokens[start:], gap))
    parts = [(p, g) for p, g in parts if "".join(p).strip()]
    if len(parts) <= 1:
        return _split(tokens, level + 1)
    children: list[Pieces] = []
    for part, gap in parts:
        while part and (part[0].isspace() or part[0] in (r"\ ", r"\,", r"\;")):
            part = part[1:]
        if level > 0 and keep == "next" and children:
            part = ["{}", *part]
        child = _split(part, level + 1)
        children.append(Pieces(child.latex, child.children, gap))
    return Pieces(text, tuple(children))


def formula_pieces(latex: str) -> Pieces:
    """``latex`` cut, level by level, at \\quad, \\implies, commas, relations and binary
    operators outside any group, so that a page can break a long formula between them."""
    return _split(_TOKEN.findall(latex), 0)


# ------------------------------------------------------------------------- page


class SvgMath:
    """The formulas of one HTML page as inline SVG that share one set of glyphs.

    Each formula is drawn as SVG (in display formulas, one SVG per piece of
    :func:`formula_pieces`, nested in inline blocks so that the browser breaks
    the coarsest level first) next to a visually hidden MathML copy for screen
    readers.  A formula ziamath cannot draw is shown as MathML.  ``glyphs()`` is
    the hidden ``<svg>`` with the ``<symbol>`` of every glyph used, once.
    """

    def __init__(self) -> None:
        self._symbols: dict[str, str] = {}

    def _register(self, formula: SvgFormula) -> str:
        body = formula.body
        for ident, markup in formula.symbols:
            known = self._symbols.get(ident)
            if known is None:
                self._symbols[ident] = markup
            elif known != markup:  # same id, other glyph (ziamath's ids of assembled glyphs)
                n = 1
                while f"{ident}-{n}" in self._symbols and \
                        self._symbols[f"{ident}-{n}"] != _rename(markup, ident, f"{ident}-{n}"):
                    n += 1
                new = f"{ident}-{n}"
                self._symbols[new] = _rename(markup, ident, new)
                body = _rename(body, ident, new)
        return body.replace("<svg ", '<svg class="m" aria-hidden="true" focusable="false" ', 1)

    def _draw(self, pieces: Pieces) -> str | None:
        if not pieces.children:
            formula = latex_to_svg(pieces.latex, True)
            return None if formula is None else self._register(formula)
        out = []
        for child in pieces.children:
            drawn = self._draw(child)
            if drawn is None:
                return None
            gap = f" g-{child.gap}" if child.gap else ""
            out.append(drawn if not child.children and not gap
                       else f'<span class="mp{gap}">{drawn}</span>')
        return "<wbr>".join(out)

    def display(self, latex: str) -> str:
        """A display formula: SVG pieces and the hidden MathML."""
        drawn = self._draw(formula_pieces(latex))
        if drawn is None:
            return latex_to_mathml(latex, True)
        return (f'<span class="svgmath" aria-hidden="true">{drawn}</span>'
                f'<span class="mathml">{latex_to_mathml(latex, True)}</span>')

    def inline(self, latex: str) -> str:
        """An inline formula (text style): one SVG on the text's baseline and the MathML."""
        formula = latex_to_svg(latex, False)
        if formula is None:
            return latex_to_mathml(latex, False)
        return (f'<span class="svgmath" aria-hidden="true">{self._register(formula)}</span>'
                f'<span class="mathml">{latex_to_mathml(latex, False)}</span>')

    def glyphs(self) -> str:
        """The hidden SVG defining every glyph the page's formulas use."""
        return ('<svg xmlns="http://www.w3.org/2000/svg" class="glyphs" aria-hidden="true" '
                'width="0" height="0">' + "".join(self._symbols.values()) + "</svg>")


def _rename(markup: str, old: str, new: str) -> str:
    return markup.replace(f'id="{old}"', f'id="{new}"').replace(f'href="#{old}"',
                                                                f'href="#{new}"')


__all__ = ["Pieces", "SvgFormula", "SvgMath", "formula_pieces", "latex_to_mathml", "latex_to_svg",
           "simple_parentheses"]
