"""Task 3: the maximal excursions of the coordinates and outputs."""

from __future__ import annotations

import sympy

from ...derivation import derivative_symbol
from ...expressions import numeric_value
from ...expressions.notation import (
    expression_latex,
    number_latex,
    with_subscript,
)
from ...model.units_display import NO_UNIT, RAD, result_units, unit_latex
from ..blocks import Block, Heading, Table, cell, paragraph
from .context import MAX, Context, _m

# -- Task 3 ---------------------------------------------------------------------------------

def _reference_values(ctx: Context) -> dict[str, float]:
    """The numeric reference state q0 of every coordinate ([equilibrium], else 0)."""
    values = ctx.model.parameter_values
    out = {}
    for c in ctx.eom.coordinates:
        expression = ctx.model.equilibrium.get(c)
        out[c] = float(numeric_value(expression, values)) if expression is not None else 0.0
    return out


def excursions(ctx: Context) -> list[Block]:
    """Task 3: the amplitude (and phase) of every coordinate and output, and a summary."""
    sol = ctx.solution
    if not sol.available or not sol.harmonics:
        return []
    blocks: list[Block] = [Heading("Task 3: the maximal excursions")]
    moving = [r for r in sol.harmonics if r.omega > 0]
    single = len(sol.harmonics) == 1 and len(moving) == 1
    blocks += _excursions_intro(ctx, single)
    units = result_units(ctx.model)
    si = {name: unit_latex(text) for name, text in units.si.items() if text != "1"} \
        if units is not None else {}
    shifted = {c: q0 for c, q0 in _reference_values(ctx).items() if q0 != 0}
    if shifted:
        blocks.append(paragraph(
            "The coordinates " + ", ".join(ctx.namer(c) for c in shifted) + " oscillate "
            "about their reference values, so their excursions are deviations from them, "
            "written with a Δ:"))
    for k, c in enumerate(ctx.eom.coordinates):
        blocks += _coordinate_excursion(ctx, k, c, single, shifted, si)
    if ctx.eom.outputs:
        blocks.append(paragraph("The outputs of the model are linearized like everything "
                                "else:"))
    deviation = {c: sympy.Symbol(f"Delta_{c}") for c in shifted}
    for c, s in deviation.items():
        ctx.names[s] = r"\Delta " + ctx.namer(c)
    for name in ctx.eom.outputs:
        blocks += _output_excursion(ctx, name, single, deviation, si)
    blocks.append(paragraph("Summary of the stationary response:"))
    blocks.append(_summary_table(ctx, shifted))
    return blocks


def _excursions_intro(ctx: Context, single: bool) -> list[Block]:
    if not single:
        return [paragraph("With several frequencies, the maximal excursion is the peak "
                          "of the sum over the common period:")]
    return [paragraph("Each coordinate of Eq. " + ctx.ref("qp-numeric")
                      + " is a harmonic function,"),
            ctx.equation(r"q_{k}(t) = L_{k}\cos(\omega t) + N_{k}\sin(\omega t) = "
                         r"X_{k}\sin(\omega t + \delta_{k}), \quad X_{k} = "
                         r"\sqrt{L_{k}^{2} + N_{k}^{2}}, \quad \delta_{k} = "
                         r"\mathrm{atan2}(L_{k}, N_{k}),", label="X"),
            paragraph("so the maximal excursions are")]


def _coordinate_excursion(ctx: Context, k: int, c: str, single: bool,
                          shifted: dict[str, float], si: dict[str, str]) -> list[Block]:
    """X_k (and delta_k) of coordinate ``c``; its range about a nonzero reference value."""
    sol = ctx.solution
    amp = sol.amplitudes[c]
    name = (r"\Delta " + ctx.namer(c)) if c in shifted else ctx.namer(c)
    blocks: list[Block] = []
    if single:
        phase = sol.phases.get(c)
        text = (rf"{with_subscript(name, MAX)} = X_{{{k + 1}}} = \sqrt{{L_{{{k + 1}}}^{{2}} + "
                rf"N_{{{k + 1}}}^{{2}}}} = {number_latex(amp)}{si.get(c, '')}")
        if phase is not None:
            text += rf", \quad \delta_{{{k + 1}}} = {number_latex(phase)}\ \text{{rad}}"
        blocks.append(ctx.equation(text + ",", label=f"X:{c}"))
    else:
        blocks.append(ctx.equation(rf"\max_{{t}} \left|{name}(t)\right| = "
                                   f"{number_latex(amp)},", label=f"X:{c}"))
    if c in shifted:  # the absolute values a reader expects
        q0 = shifted[c]
        plain = ctx.namer(c)
        blocks.append(ctx.equation(
            rf"{plain}_{{0}} = {number_latex(q0)}, \quad {plain}(t) \in "
            rf"[{number_latex(q0 - amp)},\ {number_latex(q0 + amp)}],",
            label=f"range:{c}"))
    return blocks


def _output_excursion(ctx: Context, name: str, single: bool,
                      deviation: dict[str, sympy.Symbol], si: dict[str, str]) -> list[Block]:
    """An output linearized (in the deviations from nonzero reference values) and its
    amplitude."""
    sol = ctx.solution
    out = ctx.eom.outputs[name]
    lin = out.value + sum((coef * (deviation[v] if order == 0 and v in deviation
                                   else derivative_symbol(v, order))
                           for (v, order), coef in out.terms.items()), sympy.Integer(0))
    given = expression_latex(ctx.model.outputs[name], ctx.namer)
    pretty = ctx.namer(name)
    blocks: list[Block] = [ctx.equation(f"{pretty} = {given} \\approx {ctx.tex(lin)},",
                                        label=f"out:{name}")]
    amp = sol.amplitudes[name]
    if single:
        L, N = sol.output_harmonics[name][0]
        text = (rf"{with_subscript(pretty, MAX)} = "
                rf"\sqrt{{L_{{{pretty}}}^{{2}} + N_{{{pretty}}}^{{2}}}} = "
                rf"\sqrt{{({number_latex(L)})^{{2}} + ({number_latex(N)})^{{2}}}} = "
                f"{number_latex(amp)}{si.get(name, '')}")
        phase = sol.phases.get(name)
        if phase is not None:
            text += rf", \quad \delta_{{{pretty}}} = {number_latex(phase)}\ \text{{rad}}"
    else:
        text = rf"\max_{{t}} \left|{pretty}(t)\right| = {number_latex(amp)}"
    blocks.append(ctx.equation(text + ".", label=f"X:{name}"))
    return blocks


def _summary_table(ctx: Context, shifted: dict[str, float]) -> Table:
    """Amplitude and phase of every coordinate and output, in the display units."""
    sol = ctx.solution
    units = result_units(ctx.model)
    phase_unit = units.phase if units is not None else RAD
    header = (cell("quantity"), cell("amplitude"), cell(f"phase δ [{phase_unit.text}]"))
    rows = []
    for name in [*ctx.eom.coordinates, *ctx.eom.outputs]:
        phase = sol.phases.get(name)
        label = (r"\Delta " + ctx.namer(name)) if name in shifted else ctx.namer(name)
        shown = units.unit(name) if units is not None else NO_UNIT
        rows.append((cell(_m(label)), cell(_m(number_latex(shown(sol.amplitudes[name]))
                                              + unit_latex(shown.text))),
                     cell(_m(number_latex(phase_unit(phase)))) if phase is not None
                     else cell("")))
    return Table(header, tuple(rows))
