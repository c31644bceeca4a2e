"""Text, LaTeX and HTML views of models and results (reads results, computes nothing new).

The LaTeX views use the notation of the worked-solution report
(:mod:`resonant.report.notation`): ``x1'`` is shown as a dotted symbol,
``eps`` as varepsilon, matrices as ``bmatrix``.  They back the Jupyter hooks
``_repr_latex_`` / ``_repr_html_`` of Model, LinearEOM and StationarySolution.

Examples
--------
>>> from resonant.model import loads
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
>>> print(eom_latex(model.linearize()))
$\\displaystyle \\begin{bmatrix} m \\end{bmatrix}\\begin{bmatrix} \\ddot{x}_{1} \\end{bmatrix} + \\begin{bmatrix} k \\end{bmatrix}\\begin{bmatrix} x_{1} \\end{bmatrix} = \\begin{bmatrix} 0 \\end{bmatrix}$
"""

from __future__ import annotations

import html
import math
from typing import TYPE_CHECKING

import numpy as np
import sympy

if TYPE_CHECKING:  # pragma: no cover
    from .linearize import LinearEOM
    from .model import Model
    from .stationary import StationarySolution


def _matrix_text(matrix: np.ndarray, indent: str = "    ") -> str:
    rows = [[f"{v: .6g}" for v in row] for row in np.atleast_2d(matrix)]
    width = max((len(c) for row in rows for c in row), default=1)
    return "\n".join(indent + "[" + "  ".join(c.rjust(width) for c in row) + "]"
                     for row in rows)


def _vector_text(vector: np.ndarray) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in vector) + "]"


def _pretty(expr: sympy.Basic, indent: str = "    ") -> str:
    """A symbolic matrix as an aligned grid of its entries (cheap: no 2-D pretty-printer)."""
    matrix = sympy.Matrix(expr)
    rows = [[sympy.sstr(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)]
    widths = [max(len(rows[i][j]) for i in range(matrix.rows)) for j in range(matrix.cols)]
    return "\n".join(indent + "[" + "   ".join(c.ljust(w) for c, w in zip(row, widths)) + "]"
                     for row in rows)


def solution_text(sol: "StationarySolution") -> str:
    """The human-readable report of ``resonant solve``."""
    e = sol.eom
    out: list[str] = []
    title = e.title or "model"
    out.append(f"{title}" + (f"  ({e.source})" if e.source else ""))
    out.append("=" * min(78, len(out[0])))
    out.append(f"generalized coordinates q = [{', '.join(e.coordinates)}]")
    out.append("")
    out.append("linearized equation of motion:  M q'' + C q' + K q = Q(t)")
    sym = e.symbolic if e.symbolic is not None and not e.symbolic.model.is_matrix_model \
        else None
    for label, numeric in (("M", e.M), ("C", e.C), ("K", e.K)):
        out.append(f"  {label} =")
        if sym is not None:
            out.append(_pretty(getattr(sym, label)))
            out.append("    =")
        out.append(_matrix_text(numeric))
    if sym is not None:
        out.append("  Q(t) =")
        out.append(_pretty(sym.Q))
    out.append("")
    freqs = sol.natural_frequencies
    out.append("natural frequencies (undamped):")
    if freqs.size:
        for i, w in enumerate(freqs, start=1):
            out.append(f"  omega_{i} = {w:.6g} rad/s  ({w / (2 * math.pi):.6g} Hz)")
    else:
        out.append("  none (no positive eigenvalue of K q = lambda M q)")
    out.append(f"stability: {sol.stability}")
    out.append("")
    if not sol.available:
        out.append("stationary solution: not available (signals are not harmonic)")
    elif not sol.harmonics:
        out.append("stationary solution: none (no excitation: free vibration)")
    else:
        out.append("stationary solution  q_p = sum of L cos(omega t) + N sin(omega t):")
        for h in sol.harmonics:
            head = "static load" if h.omega == 0 else f"omega = {h.omega:.6g} rad/s"
            out.append(f"  {head}")
            out.append(f"    F_S = {_vector_text(h.F_S)}")
            out.append(f"    F_C = {_vector_text(h.F_C)}")
            out.append(f"    L   = {_vector_text(h.L)}")
            out.append(f"    N   = {_vector_text(h.N)}")
        out.append("  amplitudes (peak deviation) and phases delta = atan2(L, N):")
        width = max(len(n) for n in sol.amplitudes)
        for name, amp in sol.amplitudes.items():
            phase = sol.phases.get(name)
            extra = f"   delta = {phase: .6g} rad" if phase is not None else ""
            kind = "" if name in e.coordinates else "  (output)"
            out.append(f"    {name.ljust(width)}  X = {amp:.6g}{extra}{kind}")
    if sol.warnings:
        out.append("")
        for w in sol.warnings:
            out.append(f"warning: {w}")
    return "\n".join(out) + "\n"


def _namer(model: "Model"):
    from .model import symbol
    from .nonlinear import derivative_symbol
    from .report.notation import Namer

    namer = Namer(frozenset(model.signals))
    symbols = [symbol(p) for p in model.parameters]
    for name in [*model.coordinates, *model.signals]:
        symbols.extend(derivative_symbol(name, order) for order in range(4))
    return namer, namer.symbol_names(symbols)


def eom_latex(eom: "LinearEOM") -> str:
    """The equation of motion as one LaTeX display (Jupyter ``_repr_latex_``)."""
    from .report.notation import column_latex, sympy_latex

    namer, names = _namer(eom.model)
    parts = []
    for mat, order in ((eom.M, 2), (eom.C, 1), (eom.K, 0)):
        if any(e != 0 for e in mat):
            parts.append(sympy_latex(mat, names)
                         + column_latex([namer(c, order) for c in eom.coordinates]))
    lhs = " + ".join(parts) or "0"
    return rf"$\displaystyle {lhs} = {sympy_latex(eom.Q, names)}$"


def model_latex(model: "Model") -> str:
    """The coordinates, energies (as given) or matrices of a model (``_repr_latex_``)."""
    from .report.notation import column_latex, expression_latex

    namer, _ = _namer(model)
    lines = [r"\mathbf{q} &= " + column_latex([namer(c) for c in model.coordinates])]
    for name, expression in model.definitions.items():
        lines.append(f"{namer(name)} &= {expression_latex(expression, namer)}")
    for key in ("T", "D", "U"):
        if key in model.energy:
            label = r"\mathcal{D}" if key == "D" else key
            lines.append(f"{label} &= {expression_latex(model.energy[key], namer)}")
    for name, expression in model.signals.items():
        lines.append(f"{namer(name)} &= {expression_latex(expression, namer)}")
    if model.is_matrix_model:
        eom = model.linearize()
        from .report.notation import sympy_latex

        for label in ("M", "C", "K"):
            lines.append(rf"\mathbf{{{label}}} &= {sympy_latex(getattr(eom, label), {})}")
    return r"$\displaystyle \begin{aligned} " + r" \\ ".join(lines) + r" \end{aligned}$"


def _mathml(latex: str) -> str:
    try:
        from .report.html import _math
    except ImportError:  # pragma: no cover - latex2mathml missing
        return f"<pre>{html.escape(latex)}</pre>"
    return _math(latex, True)


def model_html(model: "Model") -> str:
    """The model as HTML with MathML (``_repr_html_``)."""
    body = model_latex(model).removeprefix(r"$\displaystyle ").removesuffix("$")
    title = html.escape(model.title or model.source or "model")
    return f"<p><b>{title}</b></p>{_mathml(body)}"


def stationary_latex(sol: "StationarySolution") -> str:
    """q_p(t) = sum of L cos(w t) + N sin(w t) with numbers (``_repr_latex_``)."""
    from .report.notation import number_latex, vector_latex

    terms = []
    for h in sol.harmonics:
        if h.omega == 0:
            terms.append(vector_latex(h.L))
        else:
            wt = number_latex(h.omega) + "t"
            terms.append(rf"{vector_latex(h.L)}\cos({wt}) + {vector_latex(h.N)}\sin({wt})")
    rhs = " + ".join(terms) or r"\mathbf{0}"
    return rf"$\displaystyle \mathbf{{q}}_{{p}}(t) = {rhs}$"


def stationary_html(sol: "StationarySolution") -> str:
    """A compact HTML table of amplitudes and phases (Jupyter ``_repr_html_``)."""
    rows = "".join(
        f"<tr><td>{html.escape(n)}</td><td>{a:.6g}</td>"
        f"<td>{'' if sol.phases.get(n) is None else format(sol.phases[n], '.6g')}</td></tr>"
        for n, a in sol.amplitudes.items())
    freqs = ", ".join(f"{w:.6g}" for w in sol.natural_frequencies)
    warn = "".join(f"<p><b>warning:</b> {html.escape(w)}</p>" for w in sol.warnings)
    solution = _mathml(stationary_latex(sol).removeprefix(r"$\displaystyle ").removesuffix("$")) \
        if sol.harmonics else ""
    return (f"{solution}<p>natural frequencies: {freqs} rad/s; {html.escape(sol.stability)}</p>"
            f"<table><tr><th>quantity</th><th>amplitude</th><th>phase [rad]</th></tr>{rows}"
            f"</table>{warn}")
