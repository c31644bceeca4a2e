"""The opening steps of the worked solution: title, data, the method (Lagrange's equations)."""

from __future__ import annotations

from pathlib import Path

from ...expressions.notation import (
    expression_latex,
    number_latex,
)
from ...model.units_display import unit_latex
from ..blocks import Block, Heading, Table, cell, paragraph
from .context import Context, _at_reference, _m
from .energies import _energy_name

# -- steps -------------------------------------------------------------------------------

def title(ctx: Context) -> list[Block]:
    blocks: list[Block] = []
    if ctx.model.source:
        blocks.append(paragraph("Worked solution of the model ", f"“{Path(ctx.model.source).name}”",
                                ", derived by resonant in the order and notation of a "
                                "textbook exercise: the linearized equation of motion, "
                                "the stationary solution and the maximal excursions."))
    return blocks


def data(ctx: Context) -> list[Block]:
    model = ctx.model
    blocks: list[Block] = [Heading("Data")]
    rows = []
    units = model.units
    for name, expression in model.parameters.items():
        value = model.parameter_values[name]
        given = expression_latex(expression, ctx.namer)
        shown = number_latex(value, 6)
        if units is not None:  # "500 mm" given, 0.5 m the (SI) value
            written = units.given.get(name)
            if written is not None:
                given = expression_latex(written[0], ctx.namer) + unit_latex(written[1].text)
            dim = units.dimensions.get(name)
            same = written is not None and written[1].factor == 1 and not written[1].pi_power
            shown += unit_latex(written[1].text if same and written is not None
                                else dim.text() if dim is not None and not dim.dimensionless
                                else "rad" if written is not None and written[1].angle else "")
        rows.append((cell(_m(ctx.namer(name))),
                     cell(_m(given)) if given != shown else cell(""),
                     cell(_m(shown))))
    if rows:
        blocks.append(Table((cell("parameter"), cell("given as"), cell("value")), tuple(rows)))
    if model.signals:
        blocks.append(paragraph("The prescribed excitations (signals, small of first order) "
                                "are"))
        for name, expression in model.signals.items():
            blocks.append(ctx.equation(ctx.namer(name) + " = "
                                       + expression_latex(expression, ctx.namer),
                                       label=f"signal:{name}"))
    return blocks


def method(ctx: Context) -> list[Block]:
    blocks: list[Block] = [Heading("Task 1: the linearized equation of motion"),
                           paragraph("The matrix formulation of the linearized equation of "
                                     "motion is")]
    blocks.append(ctx.equation(r"\mathbf{M}\ddot{\mathbf{q}}(t) + \mathbf{C}\dot{\mathbf{q}}(t)"
                               r" + \mathbf{K}\mathbf{q}(t) = \mathbf{Q}(t),", label="eom"))
    blocks.append(paragraph(
        "where ", _m(r"\mathbf{M}"), " is the mass matrix, ", _m(r"\mathbf{C}"),
        " the damping matrix, ", _m(r"\mathbf{K}"), " the stiffness matrix, ",
        _m(r"\mathbf{Q}(t)"), " contains the excitations and ", _m(r"\mathbf{q}"),
        f" is the vector of the generalized coordinates (n = {ctx.n}). The elements of the "
        "matrices are the second derivatives of the kinetic energy T, the Rayleigh "
        "dissipation function ", _m(r"\mathcal{D}"), " and the potential function U at the "
        "equilibrium:"))
    ref = _at_reference(ctx)
    for label, energy, dotted in (("mij", "T", True), ("cij", r"\mathcal{D}", True),
                                  ("kij", "U", False)):
        letter = label[0]
        q = r"\dot{q}" if dotted else "q"
        blocks.append(ctx.equation(
            rf"{letter}_{{ij}} = \left.\frac{{\partial^{{2}} {energy}}}{{\partial {q}_{{i}}"
            rf" \partial {q}_{{j}}}}\right|_{{{ref}}},", label=label))
    d = ctx.derivation
    dependent = [k for k in ("T", "D", "U") if d is not None and d.parts[k].Q]
    blocks.append(paragraph("The vector ", _m(r"\mathbf{Q}"), " follows from the power of the "
                            "active forces that have no potential or dissipation function."))
    if dependent:
        which = ", ".join(_energy_name(k) for k in dependent)
        blocks.append(paragraph(
            f"Here the {which} depend{'s' if len(dependent) == 1 else ''} explicitly on time "
            "through the prescribed signals, so the corresponding parts of Lagrange's "
            "equation of the second kind,"))
        blocks.append(ctx.equation(
            r"\frac{\mathrm{d}}{\mathrm{d}t}\frac{\partial T}{\partial \dot{q}_{k}} - "
            r"\frac{\partial T}{\partial q_{k}} + \frac{\partial \mathcal{D}}{\partial "
            r"\dot{q}_{k}} + \frac{\partial U}{\partial q_{k}} = Q_{k}^{*}, \quad "
            r"k = 1, \dots, n,", label="lagrange"))
        blocks.append(paragraph(
            "are linearized as well: besides ", _m(r"\mathbf{M}\ddot{\mathbf{q}}"), ", ",
            _m(r"\mathbf{C}\dot{\mathbf{q}}"), " and ", _m(r"\mathbf{K}\mathbf{q}"),
            " they give a part of ", _m(r"-\mathbf{Q}(t)"), "."))
    return blocks
