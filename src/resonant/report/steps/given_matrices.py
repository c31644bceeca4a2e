"""The steps of a model given by its matrices."""

from __future__ import annotations

from ...expressions.notation import (
    expression_latex,
    matrix_latex,
)
from ..blocks import Block, Heading, paragraph
from .context import MAX_MATRIX, Context, _is_zero, _m
from .energies import coordinates
from .excitation import harmonic_split

# -- matrix models ---------------------------------------------------------------------------

def given_matrices(ctx: Context) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = [Heading("Task 1: the equation of motion")]
    if ctx.model.matrices is not None:
        blocks.append(paragraph("The model gives the matrices of the linearized equation of "
                                "motion directly:"))
    else:  # a large energy model: the energies, then the matrices Lagrange's equations give
        blocks.append(paragraph("The model gives its energies:"))
        for key, label in (("T", "T"), ("D", r"\mathcal{D}"), ("U", "U")):
            if key in ctx.model.energy:
                blocks.append(ctx.equation(
                    f"{label} = {expression_latex(ctx.model.energy[key], ctx.namer)}",
                    label=key))
        blocks.append(paragraph(
            f"With {ctx.n} coordinates the element-by-element derivation is left out; "
            "Lagrange's equations of the second kind at the reference state give"))
    blocks.append(ctx.equation(r"\mathbf{M}\ddot{\mathbf{q}}(t) + \mathbf{C}\dot{\mathbf{q}}(t)"
                               r" + \mathbf{K}\mathbf{q}(t) = \mathbf{Q}(t),", label="eom"))
    blocks.extend(coordinates(ctx, "Generalized coordinates"))
    if ctx.n <= MAX_MATRIX:
        symbolic = any(not e.is_Number for e in [*eom.M, *eom.C, *eom.K])
        for label in ("M", "C", "K"):
            mat = getattr(eom, label)
            if label == "C" and _is_zero(mat):
                continue
            text = rf"\mathbf{{{label}}} = "
            if symbolic:
                text += ctx.tex(mat) + " = "
            text += matrix_latex(getattr(ctx.solution.eom, label))
            blocks.append(ctx.equation(text + ",", label=label))
        if _is_zero(eom.C):
            blocks.append(paragraph("There is no damping: ", _m(r"\mathbf{C} = \mathbf{0}"), "."))
    else:
        blocks.append(paragraph(f"M, C and K are {ctx.n} x {ctx.n} matrices (not shown)."))
    blocks.append(Heading("Excitation", 3))
    if ctx.solution.eom.harmonics:
        blocks.extend(harmonic_split(ctx))
    else:
        blocks.append(paragraph("There is no excitation: the system vibrates freely."))
    return blocks
