"""Natural frequencies, mode shapes, modal damping and stability."""

from __future__ import annotations

import math

import numpy as np
import sympy

from ...analyses.modes import modes
from ...expressions.notation import (
    number_latex,
    sympy_latex,
    vector_latex,
)
from ...system.stability import undamped_eigen
from ..blocks import Block, Heading, paragraph
from .context import MAX_MATRIX, Context, _m

# -- natural frequencies, modes, stability ---------------------------------------------------

#: above this many operations the characteristic polynomial is not expanded in the report
MAX_CHARACTERISTIC_OPS = 300


def _small_determinant(matrix: sympy.Matrix) -> sympy.Expr | None:
    """The determinant of a 1x1 or 2x2 matrix by its formula, or None where expanding it
    would not help a reader: entries with radicals (sympy's ``det`` and ``expand`` took
    minutes on the elastic pendulum's sqrt((L0 + g*m/k)^2)) or too many operations."""
    if matrix.shape == (1, 1):
        det = matrix[0, 0]
    else:
        det = matrix[0, 0] * matrix[1, 1] - matrix[0, 1] * matrix[1, 0]
    radical = any(not power.exp.is_Integer for power in det.atoms(sympy.Pow))
    if radical or sympy.count_ops(det) > MAX_CHARACTERISTIC_OPS:
        return None
    return det


def _polynomial_latex(poly: sympy.Expr, w: sympy.Symbol,
                      names: dict[sympy.Symbol, str]) -> str:
    """A polynomial in ``w`` term by term in descending powers, coefficients grouped."""
    terms = sorted(sympy.Poly(poly, w).terms(), key=lambda term: -term[0][0])
    out = ""
    for (power,), coefficient in terms:
        sign = "-" if coefficient.could_extract_minus_sign() else "+"
        magnitude = -coefficient if sign == "-" else coefficient
        text = sympy_latex(magnitude, names) if magnitude != 1 or power == 0 else ""
        if isinstance(magnitude, sympy.Add) and power:
            text = rf"\left({text}\right)"
        if power:
            text += " " + sympy_latex(w**power, names)
        out += (f"{sign} " if out or sign == "-" else "") + text.strip() + " "
    return out.strip()


def descending_latex(expr: sympy.Expr, w: sympy.Symbol, names: dict[sympy.Symbol, str]
                     ) -> str:
    """A characteristic polynomial (or a product of them) in descending powers of ``w``,
    as textbooks write it: ``m_1 m_2 \\omega^4 - (...) \\omega^2 + k_1 k_2``.

    Examples
    --------
    >>> m, k, w = sympy.symbols("m k omega")
    >>> print(descending_latex(k**2 - 3*k*m*w**2 + m**2*w**4, w, {}))
    m^{2} \\omega^{4} - 3 k m \\omega^{2} + k^{2}
    >>> print(descending_latex(-w**2*(k - m*w**2), w, {}))
    - \\omega^{2} \\left(- m \\omega^{2} + k\\right)
    """
    if not expr.has(w) or not expr.is_polynomial(w):
        return sympy_latex(expr, names)
    if isinstance(expr, sympy.Mul):
        sign, parts = "", []
        for factor in expr.args:
            if factor == -1:
                sign = "- "
            elif isinstance(factor, sympy.Add) and factor.has(w):
                parts.append(rf"\left({_polynomial_latex(factor, w, names)}\right)")
            elif isinstance(factor, sympy.Pow) and isinstance(factor.base, sympy.Add) \
                    and factor.base.has(w):
                parts.append(rf"\left({_polynomial_latex(factor.base, w, names)}\right)"
                             f"^{{{sympy_latex(factor.exp, names)}}}")
            else:
                parts.append(sympy_latex(factor, names))
        # constants first, then powers of w, then the polynomial factors
        parts.sort(key=lambda s: (r"\left(" in s, names.get(w, r"\omega") in s))
        return sign + " ".join(parts)
    return _polynomial_latex(expr, w, names)


def _characteristic(ctx: Context) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = []
    w = sympy.Symbol("omega_n", positive=True)
    det = _small_determinant(eom.K - w**2 * eom.M) \
        if ctx.n <= 2 and ctx.model.matrices is None else None
    if det is not None:
        det = sympy.collect(sympy.expand(det), w)
        # factored where that is shorter (uncoupled or symmetric systems): the roots show
        factored = sympy.factor(det)
        if isinstance(factored, sympy.Mul) and sympy.count_ops(factored) < sympy.count_ops(det):
            det = factored
        names = dict(ctx.names)
        names[w] = r"\omega_{n}"
        blocks.append(paragraph("The undamped natural frequencies are the roots of the "
                                "characteristic equation"))
        blocks.append(ctx.equation(r"\det\left(\mathbf{K} - \omega_{n}^{2}\mathbf{M}\right) = "
                                   + descending_latex(det, w, names) + " = 0,", label="char"))
    else:
        blocks.append(paragraph("The undamped natural frequencies follow from ",
                                _m(r"\det\left(\mathbf{K} - \omega_{n}^{2}\mathbf{M}\right) = 0"),
                                ":"))
    return blocks


def natural_frequencies(ctx: Context, with_modes: bool = False) -> list[Block]:
    sol = ctx.solution
    heading = ("Task 2: free vibration — natural frequencies and mode shapes" if with_modes
               else "Natural frequencies and stability")
    blocks: list[Block] = [Heading(heading, 2 if with_modes else 2)]
    blocks.extend(_characteristic(ctx))
    freqs = sol.natural_frequencies
    if freqs.size:
        text = r", \quad ".join(
            rf"\omega_{{{i + 1}}} = {number_latex(w)}\ \text{{rad/s}}\ "
            rf"(f_{{{i + 1}}} = {number_latex(w / (2 * math.pi))}\ \text{{Hz}})"
            for i, w in enumerate(freqs))
        blocks.append(ctx.equation(text + ".", label="omega-n"))
    else:
        blocks.append(paragraph("There is no positive eigenvalue: no natural frequency."))
    if ctx.n <= MAX_MATRIX and freqs.size:
        blocks.extend(_modes(ctx))
        blocks.extend(_modal_damping(ctx))
    blocks.extend(_stability(ctx))
    return blocks


def _modal_damping(ctx: Context) -> list[Block]:
    """Modal damping ratios (proportional damping) or those of the complex modes."""
    num = ctx.solution.eom
    if not np.any(num.C):
        return []
    analysis = modes(num)
    zetas = analysis.damping_ratios
    if not zetas.size:
        return []
    how = ("The damping is proportional (the undamped modes decouple it); the modal "
           "damping ratios are" if analysis.proportional_damping else
           "The damping is not proportional; from the complex eigenvalues s of the state "
           "matrix, the damping ratios -Re s/|s| are")
    text = r", \quad ".join(rf"\zeta_{{{i + 1}}} = {number_latex(z)}"
                            for i, z in enumerate(zetas))
    return [paragraph(how), ctx.equation(text + ".", label="zeta")]


def _modes(ctx: Context) -> list[Block]:
    num = ctx.solution.eom
    lam, vectors = undamped_eigen(num.M, num.K)
    blocks: list[Block] = [paragraph("The mode shapes solve ",
                                     _m(r"\left(\mathbf{K} - \omega_{i}^{2}\mathbf{M}\right)"
                                        r"\mathbf{u}_{i} = \mathbf{0}"),
                                     "; normalized so that the largest component is +1 they "
                                     "are")]
    shapes = []
    for i in range(vectors.shape[1]):
        v = np.real(vectors[:, i])
        big = v[int(np.argmax(np.abs(v)))]
        v = v / big if big != 0 else v
        v = np.where(np.abs(v) < 1e-12, 0.0, v)
        shapes.append(rf"\mathbf{{u}}_{{{i + 1}}} = {vector_latex(v)}")
    blocks.append(ctx.equation(r", \quad ".join(shapes) + ".", label="modes"))
    return blocks


def _stability(ctx: Context) -> list[Block]:
    sol = ctx.solution
    eig = sol.eigenvalues
    blocks: list[Block] = []
    if eig.size and ctx.n <= MAX_MATRIX:
        shown = []
        for value in sorted(eig, key=lambda z: (round(z.real, 12), z.imag)):
            re, im = float(value.real), float(value.imag)
            if abs(re) < 1e-9 * max(1.0, abs(value)):
                re = 0.0  # rounding noise of an undamped mode
            if abs(im) < 1e-12 * max(1.0, abs(value)):
                shown.append(number_latex(re))
            elif re == 0:
                shown.append(f"{'-' if im < 0 else ''}{number_latex(abs(im))}\\,i")
            else:
                sign = "+" if im >= 0 else "-"
                shown.append(f"{number_latex(re)} {sign} {number_latex(abs(im))}\\,i")
        blocks.append(paragraph("The eigenvalues of the state matrix ",
                                _m(r"\begin{bmatrix} \mathbf{0} & \mathbf{I} \\ -\mathbf{M}^{-1}"
                                   r"\mathbf{K} & -\mathbf{M}^{-1}\mathbf{C} \end{bmatrix}"),
                                " are"))
        blocks.append(ctx.equation(r"\lambda = " + r",\ ".join(shown) + ","))
    reason = {"asymptotically stable": "every eigenvalue has a negative real part",
              "marginally stable": "no eigenvalue has a positive real part and some lie on "
                                   "the imaginary axis: some modes are undamped",
              "unstable": "an eigenvalue has a positive real part"}.get(sol.stability, "")
    blocks.append(paragraph(f"so the equilibrium is {sol.stability}"
                            + (f" ({reason})." if reason else ".")))
    return blocks
