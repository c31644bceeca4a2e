"""Text, LaTeX and HTML views of results (reads results, computes nothing new)."""

from __future__ import annotations

import html
import math
from typing import TYPE_CHECKING

import numpy as np
import sympy

if TYPE_CHECKING:  # pragma: no cover
    from .linearize import LinearEOM
    from .stationary import StationarySolution


def _matrix_text(matrix: np.ndarray, indent: str = "    ") -> str:
    rows = [[f"{v: .6g}" for v in row] for row in np.atleast_2d(matrix)]
    width = max((len(c) for row in rows for c in row), default=1)
    return "\n".join(indent + "[" + "  ".join(c.rjust(width) for c in row) + "]"
                     for row in rows)


def _vector_text(vector: np.ndarray) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in vector) + "]"


def _pretty(expr: sympy.Basic, indent: str = "    ") -> str:
    text = sympy.pretty(expr, use_unicode=True, wrap_line=False)
    return "\n".join(indent + line for line in text.splitlines())


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


def eom_latex(eom: "LinearEOM") -> str:
    """The equation of motion as one LaTeX display (Jupyter ``_repr_latex_``)."""
    q = sympy.Matrix([sympy.Symbol(c) for c in eom.coordinates])
    parts = []
    for mat, dots in ((eom.M, r"\ddot{\mathbf{q}}"), (eom.C, r"\dot{\mathbf{q}}"),
                      (eom.K, r"\mathbf{q}")):
        if any(e != 0 for e in mat):
            parts.append(sympy.latex(mat) + dots)
    lhs = " + ".join(parts) or "0"
    return (rf"$\displaystyle {lhs} = {sympy.latex(eom.Q)},\quad "
            rf"\mathbf{{q}} = {sympy.latex(q)}$")


def stationary_html(sol: "StationarySolution") -> str:
    """A compact HTML table of amplitudes and phases (Jupyter ``_repr_html_``)."""
    rows = "".join(
        f"<tr><td>{html.escape(n)}</td><td>{a:.6g}</td>"
        f"<td>{'' if sol.phases.get(n) is None else format(sol.phases[n], '.6g')}</td></tr>"
        for n, a in sol.amplitudes.items())
    freqs = ", ".join(f"{w:.6g}" for w in sol.natural_frequencies)
    warn = "".join(f"<p><b>warning:</b> {html.escape(w)}</p>" for w in sol.warnings)
    return (f"<p>natural frequencies: {freqs} rad/s; {html.escape(sol.stability)}</p>"
            f"<table><tr><th>quantity</th><th>amplitude</th><th>phase [rad]</th></tr>{rows}"
            f"</table>{warn}")
