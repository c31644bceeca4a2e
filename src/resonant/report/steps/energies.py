"""Task 1, the energies: coordinates, kinetic energy and M, dissipation and C, potential
energy and K."""

from __future__ import annotations

from collections.abc import Sequence

import sympy

from ...expressions.notation import (
    expression_latex,
)
from ..blocks import Block, Heading, paragraph
from .context import (
    MAX_ELEMENTS,
    Context,
    _at_reference,
    _energy_symbol,
    _is_zero,
    _linear_vector,
    _m,
    _matrix_terms,
    _partial,
    _q_with_functions,
    _source_labels,
    _vector,
)


def _energy_name(key: str) -> str:
    return {"T": "kinetic energy T", "D": "dissipation function D",
            "U": "potential function U"}[key]


def coordinates(ctx: Context, heading: str = "Kinetic energy and mass matrix") -> list[Block]:
    coords = ctx.eom.coordinates
    blocks: list[Block] = [Heading(heading, 3)]
    blocks.append(paragraph(f"The system has {ctx.n} degree{'s' if ctx.n != 1 else ''} of "
                            "freedom, therefore the vector of generalized coordinates is"))
    generic = [f"q_{{{i + 1}}}" for i in range(ctx.n)]
    blocks.append(ctx.equation(r"\mathbf{q} = " + _vector(generic) + " = "
                               + _vector(ctx.q_symbols()) + ",", label="q"))
    described = [(c, ctx.model.descriptions.get(c, "")) for c in coords]
    described = [(c, text) for c, text in described if text]
    if described:
        parts: list = ["where "]
        for i, (c, text) in enumerate(described):
            if i:
                parts.append("; " if i < len(described) - 1 else " and ")
            parts.extend([_m(ctx.namer(c)), " is the " + text])
        parts.append(".")
        blocks.append(paragraph(*parts))
    model = ctx.model
    if model.equilibrium and any(model.equilibrium.values()):
        blocks.append(paragraph("The reference state (equilibrium) is"))
        blocks.append(ctx.equation(r"\mathbf{q}_{0} = " + _vector(
            [expression_latex(model.equilibrium[c], ctx.namer) if c in model.equilibrium
             else "0" for c in coords]) + "."))
    if model.definitions:
        blocks.append(paragraph("The model uses the definitions"))
        for name, expression in model.definitions.items():
            blocks.append(ctx.equation(ctx.namer(name) + " = "
                                       + expression_latex(expression, ctx.namer) + ","))
    return blocks


def _uses_definitions(ctx: Context, key: str) -> bool:
    return any(n in ctx.model.definitions for n, _ in ctx.model.energy[key].names())


def _energy_statement(ctx: Context, key: str, intro: str) -> list[Block]:
    """The energy as given and, if it uses definitions, in the coordinates."""
    d = ctx.derived
    symbol_ = _energy_symbol(key)
    blocks: list[Block] = [paragraph(intro)]
    given = expression_latex(ctx.model.energy[key], ctx.namer)
    if _uses_definitions(ctx, key):
        blocks.append(ctx.equation(f"{symbol_} = {given},"))
        blocks.append(paragraph("and with the definitions substituted"))
        blocks.append(ctx.equation(f"{symbol_} = {ctx.tex(d.energies[key])}.", label=key))
    else:
        blocks.append(ctx.equation(f"{symbol_} = {given}.", label=key))
    return blocks


def _derivatives(ctx: Context, key: str, dotted: bool, letter: str) -> list[Block]:
    """First derivatives, the second derivatives element by element and their values."""
    d = ctx.derived
    order = 1 if dotted else 0
    names = ctx.q_symbols(order)
    energy = _energy_symbol(key)
    blocks: list[Block] = []
    if ctx.n > MAX_ELEMENTS:
        blocks.append(paragraph(f"(With {ctx.n} coordinates, the derivatives are not listed "
                                "element by element.)"))
        return blocks
    blocks.append(paragraph("The first derivatives with respect to the generalized "
                            + ("velocities" if dotted else "coordinates") + " are"))
    for k in range(ctx.n):
        blocks.append(ctx.equation(_partial(energy, [names[k]]) + " = "
                                   + ctx.tex(d.first[key][k]) + ","))
    entries = d.second[key]
    if not entries:
        return blocks
    ref = _at_reference(ctx)
    at = f"Eq. {ctx.ref(letter + 'ij')}" if ctx.ref(letter + 'ij') else ""
    blocks.append(paragraph("and the second derivatives, taken at the equilibrium "
                            f"({at}), give the nonzero elements"))
    for (i, j), (full, value) in entries.items():
        element = f"{letter}_{{{i + 1}{j + 1}}}"
        if i != j:
            element += f" = {letter}_{{{j + 1}{i + 1}}}"
        derivative = _partial(energy, [names[i], names[j]])
        text = rf"{element} = \left.{derivative}\right|_{{{ref}}}"
        if sympy.simplify(full - value) != 0 if sympy.count_ops(full) < 40 else True:
            text += rf" = \left.{ctx.tex(full)}\right|_{{{ref}}}"
        blocks.append(ctx.equation(text + f" = {ctx.tex(value)},"))
    return blocks


def _time_part(ctx: Context, key: str, lhs: str, matrix_labels: dict[str, str],
               label: str) -> list[Block]:
    """The linearized part of Lagrange's equation of one energy that holds signals."""
    d = ctx.derived
    part = d.parts[key]
    if not part.Q and _is_zero(part.C if key == "T" else sympy.zeros(1)) and \
            (key != "T" or _is_zero(part.K)):
        return []
    blocks: list[Block] = []
    linear = _linear_vector(ctx, part)
    blocks.append(paragraph("By the linearization of these around the equilibrium we obtain "
                            "the terms of the linearized equation of motion:"))
    blocks.append(ctx.equation(lhs + r" \approx " + ctx.tex(linear) + r" \equiv "
                               + _matrix_terms(part, matrix_labels, label) + ","))
    if part.Q:
        q_sym = part.Q_vector(ctx.n)
        q_fun = _q_with_functions(ctx, part.Q)
        text = rf"\mathbf{{Q}}^{{{label}}}(t) = {ctx.tex(q_sym)}"
        if sympy.simplify(q_fun - q_sym) != sympy.zeros(ctx.n, 1):
            text += f" = {ctx.tex(q_fun)}"
        blocks.append(paragraph("from where the generalized force of the signals in "
                                + _energy_symbol_text(key) + " is"))
        blocks.append(ctx.equation(text + ".", label=f"Q:{key}"))
    return blocks


def _energy_symbol_text(key: str) -> str:
    return "D" if key == "D" else key


def kinetic(ctx: Context) -> list[Block]:
    d = ctx.derived
    blocks = _energy_statement(ctx, "T", "The kinetic energy of the system is")
    if d.time_dependent("T"):
        blocks.append(paragraph("The kinetic energy depends explicitly on time through the "
                                "signals, so its part of Lagrange's equation is computed "
                                f"({'Eq. ' + ctx.ref('lagrange')})."))
    else:
        blocks.append(paragraph("The kinetic energy does not depend explicitly on time, so "
                                "the mass matrix follows directly from Eq. "
                                + ctx.ref("mij") + "."))
    blocks.extend(_derivatives(ctx, "T", True, "m"))
    lhs = (_vector([rf"\frac{{\mathrm{{d}}}}{{\mathrm{{d}}t}}{_partial('T', [v])} - "
                    f"{_partial('T', [c])}" for v, c in zip(ctx.q_symbols(1), ctx.q_symbols())])
           if ctx.n <= MAX_ELEMENTS else r"\frac{\mathrm{d}}{\mathrm{d}t}\frac{\partial T}"
           r"{\partial \dot{\mathbf{q}}} - \frac{\partial T}{\partial \mathbf{q}}")
    labels = {"C": r"\mathbf{C}^{T}", "K": r"\mathbf{K}^{T}"}
    blocks.extend(_time_part(ctx, "T", lhs, labels, _source_labels(ctx).get("T", "T")))
    blocks.append(paragraph("The mass matrix is"))
    blocks.append(ctx.equation(r"\mathbf{M} = " + ctx.tex(ctx.eom.M) + ".", label="M"))
    return blocks


def dissipation(ctx: Context) -> list[Block]:
    d = ctx.derived
    if "D" not in ctx.model.energy or d.energies["D"] == 0:
        return []
    blocks: list[Block] = [Heading("Dissipation function and damping matrix", 3)]
    blocks.extend(_energy_statement(ctx, "D", "Rayleigh's dissipation function is"))
    blocks.extend(_derivatives(ctx, "D", True, "c"))
    lhs = _vector([_partial(r"\mathcal{D}", [v]) for v in ctx.q_symbols(1)]) \
        if ctx.n <= MAX_ELEMENTS else r"\frac{\partial \mathcal{D}}{\partial \dot{\mathbf{q}}}"
    blocks.extend(_time_part(ctx, "D", lhs, {"C": r"\mathbf{C}", "K": r"\mathbf{K}^{D}"},
                             _source_labels(ctx).get("D", r"\mathcal{D}")))
    return blocks


def potential(ctx: Context) -> list[Block]:
    d = ctx.derived
    blocks: list[Block] = [Heading("Potential energy function and stiffness matrix", 3)]
    if "U" not in ctx.model.energy or d.energies["U"] == 0:
        blocks.append(paragraph("There is no potential energy: U = 0."))
    else:
        blocks.extend(_energy_statement(ctx, "U", "The potential function is"))
        if d.time_dependent("U"):
            signals = sorted({s.name.rstrip("'") for s in d.energies["U"].free_symbols
                              if s.name.rstrip("'") in ctx.model.signals})
            blocks.append(paragraph(
                "The potential function depends explicitly on time through ",
                *_join_math([ctx.namer(s) for s in signals]),
                ", so the stiffness matrix and the related excitation are calculated from "
                "its part of Lagrange's equation" + (f" (Eq. {ctx.ref('lagrange')})"
                                                     if ctx.ref("lagrange") else "") + "."))
        names = ctx.q_symbols()
        if ctx.n <= MAX_ELEMENTS:
            blocks.append(paragraph("The first derivatives of the potential function with "
                                    "respect to the generalized coordinates are"))
            for k in range(ctx.n):
                blocks.append(ctx.equation(_partial("U", [names[k]]) + " = "
                                           + ctx.tex(d.first["U"][k]) + ","))
            if d.parts["U"].Q:
                lhs = _vector([_partial("U", [c]) for c in names])
                label = _source_labels(ctx).get("U", "U")
                blocks.append(paragraph("By the linearization of these around the "
                                        "equilibrium, we obtain the terms ",
                                        _m(r"\mathbf{K}\mathbf{q}"), " and ",
                                        _m(rf"-\mathbf{{Q}}^{{{label}}}(t)"), ":"))
                blocks.append(ctx.equation(lhs + r" \approx " + ctx.tex(_linear_vector(
                    ctx, d.parts["U"])) + r" \equiv \mathbf{K}\mathbf{q} - "
                    rf"\mathbf{{Q}}^{{{label}}}(t),"))
                q_sym = d.parts["U"].Q_vector(ctx.n)
                q_fun = _q_with_functions(ctx, d.parts["U"].Q)
                blocks.append(paragraph("from where the generalized force related to the "
                                        "signals in U is"))
                blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}}(t) = {ctx.tex(q_sym)}"
                                           f" = {ctx.tex(q_fun)},", label="Q:U"))
    others = _other_stiffness(ctx)
    blocks.append(paragraph("and the stiffness matrix is" + others))
    blocks.append(ctx.equation(r"\mathbf{K} = " + ctx.tex(ctx.eom.K) + ".", label="K"))
    if "U" in ctx.model.energy and d.energies["U"] != 0 and ctx.n <= MAX_ELEMENTS \
            and d.second["U"]:
        ref = _at_reference(ctx)
        blocks.append(paragraph("The elements of the stiffness matrix from Eq. "
                                + ctx.ref("kij") + " are"))
        for (i, j), (full, value) in d.second["U"].items():
            element = f"k_{{{i + 1}{j + 1}}}" + (f" = k_{{{j + 1}{i + 1}}}" if i != j else "")
            text = rf"{element} = \left.{_partial('U', [names[i], names[j]])}\right|_{{{ref}}}"
            if full != value:
                text += rf" = \left.{ctx.tex(full)}\right|_{{{ref}}}"
            blocks.append(ctx.equation(text + f" = {ctx.tex(value)},"))
    return blocks


def _other_stiffness(ctx: Context) -> str:
    d = ctx.derived
    sources = []
    if not _is_zero(d.parts["T"].K):
        sources.append("the kinetic energy")
    if not _is_zero(d.parts["D"].K):
        sources.append("the dissipation function")
    if any(not _is_zero(f.part.K) for f in d.forces):
        sources.append("the forces")
    return f" (including the terms from {' and '.join(sources)})" if sources else ""


def _join_math(items: Sequence[str]) -> list:
    out: list = []
    for i, item in enumerate(items):
        if i:
            out.append(", " if i < len(items) - 1 else " and ")
        out.append(_m(item))
    return out
