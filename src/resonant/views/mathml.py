"""LaTeX formulas as MathML (for the HTML report and the Jupyter views).

Examples
--------
>>> latex_to_mathml(r"\\frac{a}{b}", False).startswith("<math")
True
"""

from __future__ import annotations

import html
import re

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


__all__ = ["latex_to_mathml", "simple_parentheses"]
