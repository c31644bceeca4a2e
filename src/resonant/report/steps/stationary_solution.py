"""Task 2: the stationary solution for harmonic excitation, symbolically and with numbers."""

from __future__ import annotations

import math

import numpy as np
import sympy

from ...expressions.notation import (
    number_latex,
    number_text,
    vector_latex,
)
from ...model import symbol
from ..blocks import Block, Heading, Note, paragraph
from .context import (
    MAX_MATRIX,
    MAX_SYMBOLIC_SYSTEM,
    Context,
    _cases,
    _m,
    _numeric_coef,
    _symbolic_coef,
    _vector,
)
from .excitation import _frequencies

# -- Task 2 ---------------------------------------------------------------------------------

def stationary(ctx: Context) -> list[Block]:
    sol = ctx.solution
    blocks: list[Block] = [Heading("Task 2: the stationary solution")]
    if not sol.available:
        blocks.append(Note(("The signals are not sums of harmonics: there is no stationary "
                            "solution of this form (use resonant simulate).",)))
        return blocks
    blocks.append(paragraph("The equation of motion of a harmonically excited linear system "
                            "has the form"))
    blocks.append(ctx.equation(r"\mathbf{M}\ddot{\mathbf{q}}(t) + \mathbf{C}\dot{\mathbf{q}}(t)"
                               r" + \mathbf{K}\mathbf{q}(t) = \mathbf{F}_{S}\sin(\omega t) + "
                               r"\mathbf{F}_{C}\cos(\omega t),", label="eom-harmonic"))
    blocks.append(paragraph("whose stationary (particular) solution is"))
    blocks.append(ctx.equation(r"\mathbf{q}_{p}(t) = \mathbf{L}\cos(\omega t) + "
                               r"\mathbf{N}\sin(\omega t).", label="qp"))
    blocks.append(paragraph("Substituting it and its derivatives into Eq. "
                            + ctx.ref("eom-harmonic") + " and collecting the coefficients of ",
                            _m(r"\cos(\omega t)"), " and ", _m(r"\sin(\omega t)"),
                            " gives the linear algebraic equations"))
    blocks.append(ctx.equation(
        r"\begin{bmatrix} -\omega^{2}\mathbf{M} + \mathbf{K} & \omega\mathbf{C} \\ "
        r"-\omega\mathbf{C} & -\omega^{2}\mathbf{M} + \mathbf{K} \end{bmatrix} "
        r"\begin{bmatrix} \mathbf{L} \\ \mathbf{N} \end{bmatrix} = "
        r"\begin{bmatrix} \mathbf{F}_{C} \\ \mathbf{F}_{S} \end{bmatrix}.", label="LN"))
    freqs = _frequencies(ctx)
    responses = sol.harmonics
    several = len(responses) > 1
    for response in responses:
        if several:
            what = "the static part" if response.omega == 0 else \
                f"the frequency ω = {number_text(response.omega)} rad/s"
            blocks.append(paragraph(f"For {what}:"))
        symbolic_w = _symbolic_frequency(ctx, response.omega, freqs)
        blocks.extend(_symbolic_system(ctx, symbolic_w))
        blocks.extend(_numeric_system(ctx, response))
    blocks.append(paragraph("Finally, the stationary solution reads"))
    terms = []
    for r in responses:
        if r.omega == 0:
            terms.append(vector_latex(r.L))
            continue
        wt = number_latex(r.omega) + "t"
        terms.append(vector_latex(r.L) + rf"\cos({wt}) + " + vector_latex(r.N)
                     + rf"\sin({wt})")
    blocks.append(ctx.equation(r"\mathbf{q}_{p}(t) = " + " + ".join(terms) + ".",
                               label="qp-numeric"))
    return blocks


def _symbolic_frequency(ctx: Context, omega: float, freqs: list[sympy.Expr]) -> sympy.Expr | None:
    values = {symbol(n): v for n, v in ctx.model.parameter_values.items()}
    for w in freqs:
        try:
            if math.isclose(abs(float(w.evalf(subs=values))), omega, rel_tol=1e-9, abs_tol=1e-12):
                return w
        except (TypeError, ValueError):
            continue
    return None


def _symbolic_system(ctx: Context, w: sympy.Expr | None) -> list[Block]:
    eom = ctx.eom
    n = ctx.n
    if w is None or n > MAX_SYMBOLIC_SYSTEM or ctx.model.matrices is not None:
        return []
    A = eom.K - w**2 * eom.M
    B = (w * eom.C).applyfunc(sympy.expand)
    big = sympy.zeros(2 * n, 2 * n)
    big[:n, :n] = A
    big[n:, n:] = A
    big[:n, n:] = B
    big[n:, :n] = -B
    assert eom.harmonics is not None  # a stationary solution exists: the signals are harmonic
    f_s, f_c = eom.harmonics.forcing(eom.excitation, w)
    rhs = sympy.Matrix([*f_c.applyfunc(sympy.factor_terms), *f_s.applyfunc(sympy.factor_terms)])
    unknowns = [f"L_{{{i + 1}}}" for i in range(n)] + [f"N_{{{i + 1}}}" for i in range(n)]
    blocks: list[Block] = [
        paragraph("For our system this yields"),
        ctx.equation(ctx.tex(big) + _vector(unknowns) + " = " + ctx.tex(rhs) + ",",
                     label="LN-symbolic")]
    if all(e == 0 for e in eom.C):
        # no damping: the system splits into one for L and one for N (exercise (40)-(41))
        rows = [[_symbolic_coef(ctx, A[i, j]) for j in range(n)]
                for i in range(n)]
        blocks.append(paragraph("which can be divided into two independent systems of "
                                f"equations with {n} unknowns:"))
        for names, vector, label in ((unknowns[:n], rhs[:n], "L-symbolic"),
                                     (unknowns[n:], rhs[n:], "N-symbolic")):
            blocks.append(ctx.equation(_cases(rows, names, [ctx.tex(v) for v in vector]),
                                       label=label))
    return blocks


def _numeric_system(ctx: Context, response) -> list[Block]:
    num = ctx.solution.eom
    n = ctx.n
    w = response.omega
    blocks: list[Block] = []
    if n > MAX_MATRIX:
        blocks.append(paragraph(f"Solving the {2 * n} equations numerically gives L and N "
                                "(not listed for this many coordinates)."))
        return blocks
    A = num.K - w**2 * num.M
    B = w * num.C
    L_names = [f"L_{{{i + 1}}}" for i in range(n)]
    N_names = [f"N_{{{i + 1}}}" for i in range(n)]
    solution_L = ", ".join(f"{a} = {number_latex(v)}" for a, v in zip(L_names, response.L))
    solution_N = ", ".join(f"{a} = {number_latex(v)}" for a, v in zip(N_names, response.N))
    blocks.append(paragraph("By substituting the numerical data, it yields"))
    if not np.any(B) or w == 0:
        blocks.append(paragraph("two independent systems (the damping terms vanish):")
                      if w != 0 else paragraph("the static system:"))
        rows = [[_numeric_coef(v) for v in row] for row in A]
        blocks.append(ctx.equation(_cases(rows, L_names, [number_latex(v) for v in response.F_C])
                                   + r" \implies " + solution_L + ",", label="L-numeric"))
        if w != 0:
            blocks.append(ctx.equation(_cases(rows, N_names,
                                              [number_latex(v) for v in response.F_S])
                                       + r" \implies " + solution_N + ".", label="N-numeric"))
        return blocks
    big = np.block([[A, B], [-B, A]])
    rhs = np.concatenate([response.F_C, response.F_S])
    rows = [[_numeric_coef(v) for v in row] for row in big]
    blocks.append(ctx.equation(_cases(rows, L_names + N_names, [number_latex(v) for v in rhs]),
                               label="LN-numeric"))
    blocks.append(paragraph("whose solution is"))
    blocks.append(ctx.equation(solution_L + r", \quad " + solution_N + "."))
    return blocks
