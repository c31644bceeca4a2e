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
>>> print(eom_latex(model.linearize()))
$\\displaystyle \\begin{bmatrix} m \\end{bmatrix}\\begin{bmatrix} \\ddot{x}_{1} \\end{bmatrix} + \\begin{bmatrix} k \\end{bmatrix}\\begin{bmatrix} x_{1} \\end{bmatrix} = \\begin{bmatrix} 0 \\end{bmatrix}$
"""  # noqa: E501 - doctest expected output is one line and cannot be wrapped

from __future__ import annotations

import html
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import sympy

from ..derivation import derivative_symbol
from ..errors import printable
from ..expressions.mathml import latex_to_mathml
from ..expressions.notation import (
    Namer,
    column_latex,
    expression_latex,
    matrix_latex,
    name_latex,
    number_latex,
    sympy_latex,
    vector_latex,
)
from ..model import Model, symbol
from ..model.units_display import (
    HZ,
    ResultUnits,
    result_units,
    shown_vector,
    uniform,
    units_grid,
)
from ..system.base import NumericEOM
from ..system.build import linear_system
from ..system.matrix import MatrixEOM
from ..system.symbolic import LinearEOM

if TYPE_CHECKING:  # pragma: no cover
    from ..analyses.modes import ModalAnalysis  # noqa: F401
    from ..analyses.simulate import Simulation  # noqa: F401
    from ..analyses.stationary import StationarySolution  # noqa: F401
    from ..analyses.sweep import FrequencyResponse


def _matrix_text(matrix: np.ndarray, indent: str = "    ") -> str:
    rows = [[f"{v + 0.0: .6g}" for v in row] for row in np.atleast_2d(matrix)]  # no -0
    width = max((len(c) for row in rows for c in row), default=1)
    return "\n".join(indent + "[" + "  ".join(c.rjust(width) for c in row) + "]"
                     for row in rows)


def _vector_text(vector: np.ndarray) -> str:
    return "[" + ", ".join(f"{v + 0.0:.6g}" for v in vector) + "]"  # -0 printed as 0


def _pretty(expr: sympy.Basic, indent: str = "    ") -> str:
    """A symbolic matrix as an aligned grid of its entries (cheap: no 2-D pretty-printer)."""
    matrix = sympy.Matrix(expr)
    rows = [[sympy.sstr(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)]
    widths = [max(len(rows[i][j]) for i in range(matrix.rows)) for j in range(matrix.cols)]
    return "\n".join(indent + "[" + "   ".join(c.ljust(w) for c, w in zip(row, widths)) + "]"
                     for row in rows)


def _coordinate_units(coordinates: tuple[str, ...], units: ResultUnits | None) -> str:
    """`` in m`` or `` in [m, rad]`` after the coordinates (their SI units), or ''."""
    if units is None or not any(units.si.get(q) for q in coordinates):
        return ""
    texts = [units.si.get(q) or "?" for q in coordinates]
    return f" in {texts[0]}" if len(set(texts)) == 1 else f" in [{', '.join(texts)}]"


def _load_units(units: ResultUnits | None) -> str:
    """The unit(s) of the rows of F_S and F_C (N, or N*m for a rotation), or ''."""
    rows = units.matrices.get("Q") if units is not None else None
    if not rows:
        return ""
    one = uniform(rows)
    return f" {one}" if one else f"  ([{', '.join(rows)}])"




#: matrices of more coordinates are summarized in the text of ``solve`` (their entries, numeric
#: and symbolic, are in ``to_dict()``/JSON and the report): a 100-link chain printed 15 MB of
#: symbolic entries and spent 30 s deriving them for the screen
PRINTED_MATRIX_SIZE = 12


def _matrices_in_brief(e: NumericEOM, units: ResultUnits | None) -> list[str]:
    out = []
    for key, label, numeric in (("M", "mass matrix M", e.M), ("C", "damping matrix C", e.C),
                                ("K", "stiffness matrix K", e.K)):
        entry_units = units.matrices.get(key) if units is not None else None
        one = uniform(entry_units) if entry_units else None
        out.append(f"  {label}: {e.n} x {e.n}, {np.count_nonzero(numeric)} nonzero entries"
                   + (f" [{one}]" if one else ""))
    out.append(f"  (matrices of more than {PRINTED_MATRIX_SIZE} coordinates are not printed "
               "entry by entry; the JSON output and the report hold them, numeric and "
               "symbolic)")
    return out


def _matrices_in_full(e: NumericEOM, units: ResultUnits | None) -> list[str]:
    out = []
    # the symbolic form where it says more than the numbers (energies, not given matrices)
    sym = e.system if isinstance(e.system, LinearEOM) else None
    # headings say what the matrix is: a parameter may be called M, C or L too
    for key, label, numeric in (("M", "mass matrix M", e.M), ("C", "damping matrix C", e.C),
                                ("K", "stiffness matrix K", e.K)):
        entry_units = units.matrices.get(key) if units is not None else None
        one = uniform(entry_units) if entry_units else None
        out.append(f"  {label}" + (f" [{one}]" if one else
                                   " (entries in the units below)" if entry_units else "") + " =")
        if sym is not None:
            out.append(_pretty(getattr(sym, key)))
            out.append("    =")
        out.append(_matrix_text(numeric))
        if entry_units and not one:
            out.append("    units:")
            out.append(units_grid(entry_units))
    if sym is not None:
        out.append("  excitation Q(t) =")
        out.append(_pretty(sym.Q))
    return out


def solution_text(sol: StationarySolution) -> str:
    """The human-readable report of ``resonant solve``."""
    e = sol.eom
    out: list[str] = []
    title = printable(e.title or "model")
    out.append(f"{title}" + (f"  ({printable(Path(e.source).name)})" if e.source else ""))
    out.append("=" * min(78, len(out[0])))
    units = result_units(e.model)
    out.append(f"generalized coordinates q = [{', '.join(e.coordinates)}]"
               + _coordinate_units(e.coordinates, units))
    out.append("")
    out.append("linearized equation of motion:  M q'' + C q' + K q = Q(t)")
    if e.n > PRINTED_MATRIX_SIZE:
        out.extend(_matrices_in_brief(e, units))
    else:
        out.extend(_matrices_in_full(e, units))
    out.append("")
    freqs = sol.natural_frequencies
    out.append("natural frequencies (undamped):")
    if freqs.size:
        for i, w in enumerate(freqs, start=1):
            shown = units.frequency if units is not None else HZ
            out.append(f"  omega_{i} = {w:.6g} rad/s"
                       + (f"  ({shown(w):.6g} {shown.text})" if shown.text != "rad/s" else ""))
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
            if units is not None and h.omega and units.frequency.text not in ("rad/s", "Hz"):
                head += f"  ({units.frequency(h.omega):.6g} {units.frequency.text})"
            out.append(f"  {head}")
            load = _load_units(units)
            out.append(f"    F_S = {_vector_text(h.F_S)}{load}")
            out.append(f"    F_C = {_vector_text(h.F_C)}{load}")
            if units is None:
                out.append(f"    cos coefficients L = {_vector_text(h.L)}")
                out.append(f"    sin coefficients N = {_vector_text(h.N)}")
            else:
                out.append(f"    cos coefficients L = {shown_vector(h.L, e.coordinates, units)}")
                out.append(f"    sin coefficients N = {shown_vector(h.N, e.coordinates, units)}")
        out.append("  amplitudes (peak deviation) and phases delta = atan2(L, N):")
        width = max(len(n) for n in sol.amplitudes)
        for name, amp in sol.amplitudes.items():
            phase = sol.phases.get(name)
            kind = "" if name in e.coordinates else "  (output)"
            if units is None:
                extra = f"   delta = {phase: .6g} rad" if phase is not None else ""
                out.append(f"    {name.ljust(width)}  X = {amp:.6g}{extra}{kind}")
                continue
            unit = units.unit(name)
            extra = f"   delta = {units.phase(phase): .6g} {units.phase.text}" \
                if phase is not None else ""
            out.append(f"    {name.ljust(width)}  X = {unit(amp):.6g}"
                       f"{' ' + unit.text if unit.text else ''}{extra}{kind}")
    if sol.warnings:
        out.append("")
        for w in sol.warnings:
            out.append(f"warning: {w}")
    return "\n".join(out) + "\n"


def _namer(model: Model) -> tuple[Namer, dict]:
    namer = Namer(frozenset(model.signals))
    symbols = [symbol(p) for p in model.parameters]
    for name in [*model.coordinates, *model.signals]:
        symbols.extend(derivative_symbol(name, order) for order in range(4))
    return namer, namer.symbol_names(symbols)


def eom_latex(eom: LinearEOM | MatrixEOM) -> str:
    """The equation of motion as one LaTeX display (Jupyter ``_repr_latex_``)."""
    namer, names = _namer(eom.model)
    parts = []
    for mat, order in ((eom.M, 2), (eom.C, 1), (eom.K, 0)):
        if any(e != 0 for e in mat):
            parts.append(sympy_latex(mat, names)
                         + column_latex([namer(c, order) for c in eom.coordinates]))
    lhs = " + ".join(parts) or "0"
    return rf"$\displaystyle {lhs} = {sympy_latex(eom.Q, names)}$"


def numeric_eom_latex(eom: NumericEOM) -> str:
    """M q'' + C q' + K q = Q with numbers (Jupyter ``_repr_latex_`` of a NumericEOM)."""
    if eom.n > 12:
        return rf"$\text{{{eom.n} coordinates}}$"
    q = [name_latex(c) for c in eom.coordinates]
    parts = [matrix_latex(getattr(eom.dense(), key)) + column_latex(
        [rf"\{dots}{{{c}}}" if dots else c for c in q])
        for key, dots in (("M", "ddot"), ("C", "dot"), ("K", ""))
        if np.any(getattr(eom.dense(), key))]
    terms = []
    for h in eom.harmonics:
        wt = number_latex(h.omega) + "t"
        terms += [rf"{vector_latex(h.F_S)}\sin({wt})" if np.any(h.F_S) else "",
                  rf"{vector_latex(h.F_C)}\cos({wt})" if np.any(h.F_C) and h.omega else "",
                  vector_latex(h.F_C) if np.any(h.F_C) and not h.omega else ""]
    rhs = " + ".join(t for t in terms if t) or r"\mathbf{0}"
    return rf"$\displaystyle {' + '.join(parts) or '0'} = {rhs}$"


def model_latex(model: Model) -> str:
    """The coordinates, energies (as given) or matrices of a model (``_repr_latex_``)."""
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


def stationary_latex(sol: StationarySolution) -> str:
    """q_p(t) = sum of L cos(w t) + N sin(w t) with numbers (``_repr_latex_``)."""
    terms = []
    for h in sol.harmonics:
        if h.omega == 0:
            terms.append(vector_latex(h.L))
        else:
            wt = number_latex(h.omega) + "t"
            terms.append(rf"{vector_latex(h.L)}\cos({wt}) + {vector_latex(h.N)}\sin({wt})")
    rhs = " + ".join(terms) or r"\mathbf{0}"
    return rf"$\displaystyle \mathbf{{q}}_{{p}}(t) = {rhs}$"


def stationary_html(sol: StationarySolution) -> str:
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


def modes_text(result: ModalAnalysis, units: ResultUnits | None = None) -> str:
    """The human-readable table of ``resonant modes``; the second frequency column is in
    the display unit of frequencies (``units.frequency``, Hz by default)."""
    out = [printable(result.title or "modes"), ""]
    names = result.coordinates
    shown = ", ".join(names[:8]) + (" ..." if len(names) > 8 else "")
    frequency = units.frequency if units is not None and units.frequency.text != "rad/s" \
        else HZ
    column = f"f [{frequency.text}]"
    out.append(f"{'mode':>4}  {'omega [rad/s]':>14}  {column:>12}  {'zeta':>8}   "
               f"shape (largest component +1): {shown}")
    per_mode = result.proportional_damping
    for j, w in enumerate(result.natural_frequencies):
        zeta = f"{result.damping_ratios[j]:8.4g}" if per_mode and j < len(
            result.damping_ratios) else " " * 8
        shape = ", ".join(f"{v: .4g}" for v in result.mode_shapes[:8, j])
        out.append(f"{j + 1:>4}  {w:14.6g}  {frequency(w):12.6g}  {zeta}   [{shape}]")
    if result.damped:
        out.append("")
        if result.rayleigh is not None and len(names) <= 2:
            # with two coordinates every C that commutes with M^-1 K is some a M + b K:
            # the fit says nothing about the damping, the modal ratios do
            out.append("proportional damping: the modes decouple C (with two coordinates "
                       "every such C is a M + b K); modal damping ratios: " + ", ".join(
                           f"zeta_{j + 1} = {z:.4g}"
                           for j, z in enumerate(result.damping_ratios)))
        elif result.rayleigh is not None:
            a, b = result.rayleigh
            out.append(f"proportional (Rayleigh) damping: C = {a:.6g} M + {b:.6g} K")
        elif result.proportional_damping:
            out.append("proportional damping (K M^-1 C = C M^-1 K): the modes decouple C")
        else:
            out.append("non-proportional damping: eigenvalues s of the state matrix")
            out.append(f"{'Re s':>14}  {'Im s':>14}  {'zeta':>8}")
            for s in result.eigenvalues[:2 * 20]:
                if s.imag >= 0:
                    ratio = -s.real / abs(s) if abs(s) else 0.0
                    out.append(f"{s.real:14.6g}  {s.imag:14.6g}  {ratio:8.4g}")
    out.append("")
    out.append(f"stability: {result.stability}   (method: {result.method})")
    return "\n".join(out) + "\n"


def sweep_text(result: FrequencyResponse) -> str:
    """The human-readable summary of ``resonant sweep``."""
    unit = f" {result.unit}" if result.unit else ""
    out = [printable(result.title or "sweep"),
           f"{result.parameter} from {result.values[0]:.6g} to {result.values[-1]:.6g}{unit}, "
           f"{len(result.values)} values, method {result.method}" + (
               f" (estimated error {result.estimated_error:.2g}, tolerance "
               f"{result.tolerance:.2g})" if getattr(result, "estimated_error", None) is not None
               else ""), ""]
    natural = result.natural_values
    if natural is not None:
        inside = [w for w in natural if result.values.min() <= w <= result.values.max()]
        if inside and result.frequency_sweep:
            out.append("natural frequencies in range: " +
                       ", ".join(f"{w:.6g}" for w in inside[:20]) + unit)
        elif inside:
            out.append(f"the excitation meets a natural frequency at {result.parameter} = " +
                       ", ".join(f"{w:.6g}" for w in inside[:20]) + unit)
    for title, items in (("resonance peaks", result.peaks),
                         ("antiresonances", result.antiresonances)):
        out.append(f"{title}:")
        if not items:
            out.append("  none")
        for p in items[:50]:
            out.append(f"  {p.name:>12}  at {result.parameter} = {p.value:.6g}{unit}   "
                       f"amplitude {p.amplitude:.6g}")
        if len(items) > 50:
            out.append(f"  ... {len(items) - 50} more (use --json)")
    return "\n".join(out) + "\n"


def simulation_text(sim: Simulation) -> str:
    """A short plain-text report of a :class:`~resonant.analyses.simulate.Simulation`."""
    kind = "nonlinear" if sim.nonlinear else "linear"
    lines = [printable(sim.title),
             f"{kind} simulation, t = 0 ... {sim.t_end:.6g} s ({sim.method}, start: "
             f"{sim.start})",
             f"steady amplitudes (peak |deviation| over t = {sim.window[0]:.6g} ... "
             f"{sim.window[1]:.6g} s):",
             f"  {'name':<12} {'simulated':>14} {'linear':>14} {'difference':>11}"]
    for name, value in sim.steady_amplitudes.items():
        linear = sim.linear_amplitudes.get(name)
        diff = sim.relative_difference.get(name)
        lines.append(f"  {name:<12} {value:>14.6g} "
                     f"{'-' if linear is None else format(linear, '.6g'):>14} "
                     f"{'-' if diff is None else format(100 * diff, '+.3g') + '%':>11}")
    return "\n".join(line for line in lines if line) + "\n"
