"""One table of the model language's functions (expressions/functions.py) and every renderer
printing every function from it: the typeset notation of parsed expressions, MathML, sympy's
LaTeX of derived expressions and the page's JavaScript."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import sympy

import resonant
from resonant.expressions import parse
from resonant.expressions.functions import FUNCTIONS, JAVASCRIPT
from resonant.views.js_printer import FUNCTIONS_JS, js_expression
from resonant.expressions.mathml import latex_to_mathml
from resonant.expressions.notation import expression_latex, sympy_latex

ROOT = Path(__file__).parents[1]
x, y = sympy.symbols("x y")


def _call(name: str) -> str:
    return f"{name}(y, x)" if FUNCTIONS[name].arity == 2 else f"{name}(x)"


def _namer(name: str, primes: int = 0) -> str:
    return name + "'" * primes


@pytest.mark.parametrize("name", list(FUNCTIONS))
def test_every_renderer_prints_every_function(name):
    function = FUNCTIONS[name]
    assert function.javascript.startswith("Math.")
    arguments = ["y", "x"] if function.arity == 2 else ["x"]
    # the notation of a parsed expression: the table's form
    latex = expression_latex(parse(_call(name)), _namer)
    assert latex == function.write_latex(*arguments)
    assert function.latex in latex or function.latex_form
    mathml = latex_to_mathml(latex, False)
    assert "<math" in mathml and "merror" not in mathml
    # derived (sympy) expressions: sympy's printer, and the page's JavaScript
    value = function.sympy(y, x) if function.arity == 2 else function.sympy(x + 2 * y)
    assert sympy_latex(value, {x: "x", y: "y"})
    script = js_expression(value, {x: "p[0]", y: "p[1]"})
    assert function.javascript in script


def test_the_printers_take_their_forms_from_the_table():
    assert FUNCTIONS_JS == JAVASCRIPT
    assert set(JAVASCRIPT.values()) | {"Math.sqrt"} == {f.javascript for f in FUNCTIONS.values()}


def test_javascript_names_exist_in_math():
    # JavaScript's Math has the same names as Python's math for these functions
    for function in FUNCTIONS.values():
        member = function.javascript.removeprefix("Math.")
        assert member == function.name or (function.name == "abs" and member == "abs")
        assert function.name == "abs" or hasattr(math, member)


def test_latex_of_a_model_using_abs(tmp_path):
    """A model using abs() in its energies: its LaTeX view used to raise KeyError: 'abs'."""
    text = (ROOT / "examples" / "duffing.toml").read_text()
    text = text.replace('D = "c*x\'^2/2"', 'D = "c*x\'^2/2*(1 + abs(k*x/F))"')
    assert "abs(k*x/F)" in text
    path = tmp_path / "abs.toml"
    path.write_text(text)
    model = resonant.load(path)
    latex = model._repr_latex_()
    assert r"\left|" in latex and r"\right|" in latex
