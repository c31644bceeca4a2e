"""Task 1, the excitation: generalized forces, their harmonic split, the equation of motion."""

from __future__ import annotations

import sympy

from ...expressions.notation import (
    matrix_latex,
    number_latex,
    vector_latex,
)
from ..blocks import Block, Heading, paragraph
from .context import MAX_MATRIX, Context, _is_zero, _linear_vector, _m, _source_labels, _vector
from .energies import _join_math


def forces(ctx: Context) -> list[Block]:
    d = ctx.derived
    blocks: list[Block] = [Heading("Excitation forces", 3)]
    labels = _source_labels(ctx)
    parts_shown = [(labels[k], k) for k in ("T", "D", "U") if k in labels]
    if parts_shown:
        blocks.append(paragraph("One part of the excitation, ",
                                *_join_math([rf"\mathbf{{Q}}^{{{lab}}}(t)"
                                             for lab, _ in parts_shown]),
                                ", was found above."))
    qdots = ctx.q_symbols(1)
    for i, force in enumerate(d.forces):
        label = labels.get(f"F{i}", rf"F_{{{i + 1}}}" if len(d.forces) > 1 else "F")
        if force.given:
            blocks.append(paragraph("The force ", f"“{force.name}”", " is given by its "
                                    "generalized components:"))
            blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}} = "
                                       + ctx.tex(sympy.Matrix(force.generalized))
                                       + " (given directly).", label=f"F{i}"))
        else:
            vec = ctx.tex(sympy.Matrix(force.vector))
            vel = ctx.tex(sympy.Matrix(force.velocity))
            blocks.append(paragraph("The power of the force ", f"“{force.name}”",
                                    " is the force times the velocity of the point where "
                                    "it acts:"))
            blocks.append(ctx.equation(
                rf"P = \mathbf{{F}} \cdot \mathbf{{v}} = {vec} \cdot {vel} = "
                + ctx.tex(force.power) + r" \equiv \sum_{k=1}^{n} Q_{k} \dot{q}_{k},",
                label=f"P{i}"))
            blocks.append(paragraph("from which (the coefficients of ",
                                    *_join_math(qdots), ")"))
            blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}} = "
                                       + ctx.tex(sympy.Matrix(force.generalized)) + ".",
                                       label=f"F{i}"))
        part = force.part
        if not (_is_zero(part.M) and _is_zero(part.C) and _is_zero(part.K)):
            blocks.append(paragraph("Linearized, the force depends on the motion; those terms "
                                    "belong to the left side of Eq. " + ctx.ref("eom") + ":"))
            blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}} \approx "
                                       + ctx.tex(-_linear_vector(ctx, part)) + "."))
    blocks.extend(total_excitation(ctx, labels))
    return blocks


def total_excitation(ctx: Context, labels: dict[str, str]) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = []
    if not eom.excitation:
        blocks.append(paragraph("There is no excitation: ", _m(r"\mathbf{Q}(t) = \mathbf{0}"),
                                ", the system vibrates freely."))
        return blocks
    names = [rf"\mathbf{{Q}}^{{{lab}}}(t)" for lab in labels.values()]
    head = r"\mathbf{Q}(t) = " + (" + ".join(names) + " = " if len(names) > 1 else "")
    text = head + ctx.tex(eom.Q_signals) if len(names) > 1 else head + ctx.tex(eom.Q_signals)
    q_t = eom.Q
    if q_t != eom.Q_signals:
        text += " = " + ctx.tex(q_t)
    blocks.append(paragraph("Finally, the excitation force is"))
    blocks.append(ctx.equation(text + ".", label="Q"))
    blocks.extend(harmonic_split(ctx))
    return blocks


def _frequencies(ctx: Context) -> list[sympy.Expr]:
    h = ctx.eom.harmonics
    return list(h.frequencies) if h is not None else []


def harmonic_split(ctx: Context) -> list[Block]:
    eom = ctx.eom
    h = eom.harmonics
    if h is None:
        return [paragraph("The signals are not sums of harmonics, so there is no "
                          "stationary solution of the form of Eq. (37); the equation of "
                          "motion holds for any signals.")]
    blocks: list[Block] = [paragraph("For the stationary solution the excitation is written "
                                     "in the form")]
    freqs = _frequencies(ctx)
    terms = []
    for i, w in enumerate(freqs):
        sub = "" if len(freqs) == 1 else f",{i + 1}"
        if w == 0:
            terms.append(rf"\mathbf{{F}}_{{C{sub}}}")
        else:
            wt = ctx.tex(w * sympy.Symbol("t"))
            terms.append(rf"\mathbf{{F}}_{{S{sub}}} \sin\left({wt}\right) + "
                         rf"\mathbf{{F}}_{{C{sub}}} \cos\left({wt}\right)")
    blocks.append(ctx.equation(r"\mathbf{Q}(t) = " + " + ".join(terms) + ",", label="QSC"))
    blocks.append(paragraph("where, using trigonometric identities,"))
    for i, w in enumerate(freqs):
        sub = "" if len(freqs) == 1 else f",{i + 1}"
        f_s, f_c = h.forcing(eom.excitation, w)
        f_s = f_s.applyfunc(sympy.factor_terms)
        f_c = f_c.applyfunc(sympy.factor_terms)
        text = rf"\mathbf{{F}}_{{S{sub}}} = {ctx.tex(f_s)}, \quad " if w != 0 else ""
        text += rf"\mathbf{{F}}_{{C{sub}}} = {ctx.tex(f_c)}"
        blocks.append(ctx.equation(text + ("," if len(freqs) > 1 else "."), label=f"FSC{i}"))
    num_lines = []
    for x in ctx.solution.eom.harmonics:
        sub = "" if len(freqs) == 1 else rf",\,\omega = {number_latex(x.omega)}"
        line = (rf"\mathbf{{F}}_{{S{sub}}} = {vector_latex(x.F_S)}, \quad " if x.omega else "")
        num_lines.append(line + rf"\mathbf{{F}}_{{C{sub}}} = {vector_latex(x.F_C)}")
    if num_lines:
        blocks.append(paragraph("With the data:"))
        for line in num_lines:
            blocks.append(ctx.equation(line + "."))
    return blocks


def equation_of_motion(ctx: Context) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = [Heading("The linearized equation of motion", 3)]
    refs = [f"the {what} {ctx.ref(label)}" for what, label in
            (("mass matrix", "M"), ("damping matrix", "C"), ("stiffness matrix", "K"),
             ("excitation", "FSC0")) if ctx.ref(label)]
    listed = ", ".join(refs[:-1]) + " and " + refs[-1] if len(refs) > 1 else "".join(refs)
    blocks.append(paragraph("Substituting " + listed + " into Eq. " + ctx.ref("eom")
                            + " gives the equation of motion:" if refs else
                            "The equation of motion is"))
    lhs = []
    for mat, order in ((eom.M, 2), (eom.C, 1), (eom.K, 0)):
        if not _is_zero(mat):
            lhs.append(ctx.tex(mat) + _vector(ctx.q_symbols(order)))
    rhs = _rhs_latex(ctx)
    blocks.append(ctx.equation(" + ".join(lhs) + " = " + rhs + ".", label="EOM"))
    if _is_zero(eom.C):
        blocks.append(paragraph("Note that there is no damping in the system, i.e. ",
                                _m(r"\mathbf{C} = \mathbf{0}"), "."))
    if ctx.n <= MAX_MATRIX:
        num = ctx.solution.eom
        blocks.append(paragraph("With the data, the matrices are"))
        text = rf"\mathbf{{M}} = {matrix_latex(num.M)}, \quad "
        if not _is_zero(eom.C):
            text += rf"\mathbf{{C}} = {matrix_latex(num.C)}, \quad "
        text += rf"\mathbf{{K}} = {matrix_latex(num.K)}."
        blocks.append(ctx.equation(text, label="MCK"))
    return blocks


def _rhs_latex(ctx: Context) -> str:
    eom = ctx.eom
    h = eom.harmonics
    if not eom.excitation:
        return ctx.tex(sympy.zeros(ctx.n, 1))
    if h is None:
        return ctx.tex(eom.Q)
    terms = []
    for w in _frequencies(ctx):
        f_s, f_c = h.forcing(eom.excitation, w)
        f_s = f_s.applyfunc(sympy.factor_terms)
        f_c = f_c.applyfunc(sympy.factor_terms)
        wt = ctx.tex(w * sympy.Symbol("t"))
        if w == 0:
            terms.append(ctx.tex(f_c))
            continue
        if not _is_zero(f_s):
            terms.append(ctx.tex(f_s) + rf" \sin\left({wt}\right)")
        if not _is_zero(f_c):
            terms.append(ctx.tex(f_c) + rf" \cos\left({wt}\right)")
    return " + ".join(terms)
