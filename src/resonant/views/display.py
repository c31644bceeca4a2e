"""Text, LaTeX and HTML views of models and results (reads results, computes nothing new).

The LaTeX views use the notation of the worked-solution report
(:mod:`resonant.report.notation`): ``x1'`` is shown as a dotted symbol,
``eps`` as varepsilon, matrices as ``bmatrix``.  They back the Jupyter reprs
``_repr_latex_`` / ``_repr_html_`` of Model, LinearEOM and StationarySolution.

Examples
--------
>>> from resonant.api import loads
>>> model = loads('''
... [parameters]
... m = 2
... k = 800
... [coordinates]
... x1 = "displacement"
... [energy]
... T = "m*x1'^2/2"
... U = "k*x1^2/2"
... ''')
>>> print(model_latex(model))
$\\displaystyle \\begin{aligned} \\mathbf{q} &= \\begin{bmatrix} x_{1} \\end{bmatrix} \\\\ T &= \\frac{m \\dot{x}_{1}^{2}}{2} \\\\ U &= \\frac{k x_{1}^{2}}{2} \\end{aligned}$
>>> print(model.linearize()._repr_latex_())
$\\displaystyle \\begin{bmatrix} m \\end{bmatrix}\\begin{bmatrix} \\ddot{x}_{1} \\end{bmatrix} + \\begin{bmatrix} k \\end{bmatrix}\\begin{bmatrix} x_{1} \\end{bmatrix} = \\begin{bmatrix} 0 \\end{bmatrix}$
"""  # noqa: E501 - doctest expected output is one line and cannot be wrapped

from __future__ import annotations

import html
from pathlib import Path
from typing import TYPE_CHECKING

from ..expressions.mathml import latex_to_mathml
from ..expressions.notation import (
    column_latex,
    expression_latex,
    sympy_latex,
)
from ..model import Model
from ..system.build import linear_system
from ..system.latex import model_namer

if TYPE_CHECKING:  # pragma: no cover
    from ..analyses.modes import ModalAnalysis  # noqa: F401
    from ..analyses.simulate import Simulation  # noqa: F401
    from ..analyses.stationary import StationarySolution  # noqa: F401


def model_latex(model: Model) -> str:
    """The coordinates, energies (as given) or matrices of a model (``_repr_latex_``)."""
    namer, _ = model_namer(model)
    lines = [r"\mathbf{q} &= " + column_latex([namer(c) for c in model.coordinates])]
    for name, expression in model.definitions.items():
        lines.append(f"{namer(name)} &= {expression_latex(expression, namer)}")
    for key in ("T", "D", "U"):
        if key in model.energy:
            label = r"\mathcal{D}" if key == "D" else key
            lines.append(f"{label} &= {expression_latex(model.energy[key], namer)}")
    for name, expression in model.signals.items():
        lines.append(f"{namer(name)} &= {expression_latex(expression, namer)}")
    if model.matrices is not None:
        eom = linear_system(model)
        for label in ("M", "C", "K"):
            lines.append(rf"\mathbf{{{label}}} &= {sympy_latex(getattr(eom, label), {})}")
    return r"$\displaystyle \begin{aligned} " + r" \\ ".join(lines) + r" \end{aligned}$"


def _mathml(latex: str) -> str:
    return latex_to_mathml(latex, True)


def model_html(model: Model) -> str:
    """The model as HTML with MathML (``_repr_html_``)."""
    body = model_latex(model).removeprefix(r"$\displaystyle ").removesuffix("$")
    title = html.escape(model.title or Path(model.source or "model").name)
    return f"<p><b>{title}</b></p>{_mathml(body)}"


