"""The report of a mechanism described by its parts: its figure and its energies, part by part.

For a model with parts the worked solution starts, as the reference
exercise does, from the figure of the system ("Fig. 1": :mod:`resonant.views.drawing`)
and derives the energies the way its Eqs. (8)-(14) do: T as the sum over the
bodies, the velocity of each centre of gravity (``v_S = v_B + omega x r_BS`` for
a body turning about B, as vectors, then squared), the angular velocities; each
spring's elongation and potential, the gravity potential; each damper's rate of
elongation and dissipation.  The geometry is the model layer's own
(:class:`resonant.model.part_energies.Mechanism`), so the report shows what the
solver uses.  :func:`resonant.report.steps.step_order` inserts these steps.

Examples
--------
>>> import pathlib, resonant
>>> from resonant.report import build_report
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples" / "parts" / "pendulum.toml"
>>> report = build_report(resonant.load(path), plots=False)
>>> any("centre of gravity" in str(b) for b in report.blocks)
True
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

import sympy
from sympy.core.function import AppliedUndef

from ..derivation import derivative_symbol
from ..errors import ModelError
from ..expressions import ExpressionError, parse
from ..expressions.notation import Namer, column_latex, expression_latex, name_latex
from ..model import Model
from ..model.part_energies import TIME, Mechanism
from ..model.parts import Body, Contribution, Link
from ..views.drawing import draw_sketch
from ..views.sketch import Sketch, sketch
from .blocks import Block, Equation, Figure, Heading, Math, paragraph

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure as MplFigure


class PartsContext(Protocol):
    """What these steps use of :class:`resonant.report.steps.Context` (which inserts them:
    a protocol, so that this module does not import ``steps``)."""

    model: Model
    namer: Namer
    names: dict[sympy.Symbol, str]
    figures: int

    def equation(self, latex: str, label: str | None = None) -> Equation: ...

    def figure(self, plot: Any, caption: str) -> Figure: ...

#: above this many operations a velocity squared is shown unsimplified
MAX_SIMPLIFY = 400


class MechanismFigure:
    """The figure of the mechanism as report plot data (draws itself, like
    :class:`resonant.report.plots.DrawnPlot`)."""

    def __init__(self, data: Sketch) -> None:
        self.sketch = data

    def draw(self, figure: MplFigure) -> None:
        xmin, xmax, ymin, ymax = self.sketch.bounds()
        u = self.sketch.scale
        ratio = (ymax - ymin + 0.3 * u) / max(xmax - xmin + 0.3 * u, 1e-12)
        figure.set_size_inches(5.6, min(6.5, max(2.4, 5.6 * ratio)))
        # room around the axes for the labels beyond the parts (no tight bounding box here)
        draw_sketch(self.sketch, figure.add_axes((0.08, 0.04, 0.84, 0.92)))

    def to_dict(self) -> dict[str, Any]:
        return self.sketch.to_dict()


# -- sympy of the mechanism -> the report's symbols --------------------------------------------

class _Parts:
    """The mechanism's geometry (functions of time) in the report's symbols."""

    def __init__(self, ctx: PartsContext) -> None:
        model: Model = ctx.model
        assert model.parts is not None
        self.ctx = ctx
        self.parts = model.parts.parts
        self.mechanism = Mechanism(self.parts, list(model.parameters), list(model.coordinates),
                                   list(model.signals), model.definitions, model.equilibrium,
                                   model.source)
        symbols: list[sympy.Symbol] = []
        for name in model.definitions:
            symbols.extend(derivative_symbol(name, order) for order in range(3))
        self.names = {**ctx.names, **ctx.namer.symbol_names(symbols)}

    def display(self, expr: sympy.Expr) -> sympy.Expr:
        """``x1(t)`` -> ``x1``, its derivative -> ``x1'`` (the report's symbols)."""
        expr = sympy.sympify(expr)
        derivatives = {d: derivative_symbol(d.expr.func.__name__, int(d.derivative_count))
                       for d in expr.atoms(sympy.Derivative)
                       if isinstance(d.expr, AppliedUndef)}
        expr = expr.xreplace(derivatives)
        functions = {f: sympy.Symbol(f.func.__name__) for f in expr.atoms(AppliedUndef)}
        return expr.xreplace(functions)

    def tex(self, expr: sympy.Expr) -> str:
        return sympy.latex(self.display(expr), symbol_names=self.names, order="none")

    def vector(self, entries: Sequence[sympy.Expr]) -> str:
        return column_latex([self.tex(e) for e in entries])

    def rate(self, expr: sympy.Expr) -> sympy.Expr:
        return sympy.diff(expr, TIME)

    def substituted(self, expr: sympy.Expr) -> sympy.Expr:
        """The definitions replaced by what they stand for."""
        return expr.xreplace(self.mechanism.inlined)


def _simplify(expr: sympy.Expr) -> sympy.Expr:
    expanded = sympy.expand(expr)
    if sympy.count_ops(expanded) > MAX_SIMPLIFY:
        return expanded
    try:
        return sympy.trigsimp(expanded)
    except (TypeError, ValueError, RecursionError):  # pragma: no cover - sympy's own limits
        return expanded


def _contribution(ctx: PartsContext, item: Contribution) -> str:
    """A part's T, U or D as LaTeX, in the order it was derived."""
    try:
        return expression_latex(parse(item.text), ctx.namer)
    except ExpressionError:  # pragma: no cover - the loader parsed the same text
        return r"	ext{(see the total)}"


def _label(name: str) -> str:
    """A body's name as a subscript (names of bodies are identifiers)."""
    return name_latex(name)


def _pin_label(pin: str) -> str:
    return name_latex(pin.rsplit(".", 1)[-1])


def _contributions(ctx: PartsContext, kind: str, energy: str) -> dict[str, Contribution]:
    assert ctx.model.parts is not None
    return {c.name: c for c in ctx.model.parts.contributions
            if c.kind == kind and c.energy == energy}


# -- the steps -----------------------------------------------------------------------------------

def figure(ctx: PartsContext) -> list[Block]:
    """"In Fig. 1 the system is shown": the figure drawn from the parts."""
    if ctx.model.parts is None:  # part of the statement: also with --no-plots
        return []
    try:
        data = sketch(ctx.model)
    except ModelError:
        return []
    blocks: list[Block] = [paragraph(
        f"In Fig. {ctx.figures + 1}, the mechanical model of the system is shown at its "
        "reference state, drawn from its parts to scale: the bodies, the springs and "
        "dampers between their points, the supports, the forces (red) and the generalized "
        "coordinates (blue).")]
    blocks.append(ctx.figure(MechanismFigure(data), "Mechanical model of the system (drawn "
                             "from its parts at the reference state)."))
    return blocks


def kinetic(ctx: PartsContext) -> list[Block]:
    """T as the sum over the bodies; each centre of gravity's velocity; the angular
    velocities (the reference exercise's Eqs. (8)-(14))."""
    if ctx.model.parts is None:
        return []
    parts = _Parts(ctx)
    terms = _contributions(ctx, "body", "T")
    bodies = [b for b in parts.parts.bodies if b.name in terms]
    if not bodies:
        return []
    blocks: list[Block] = []
    pieces = [f"T_{{{_label(b.name)}}}" for b in bodies]
    blocks.append(paragraph(
        "The kinetic energy of the system is the sum of the kinetic energies of its "
        f"bod{'ies' if len(bodies) > 1 else 'y'}, each ", Math(r"\frac{1}{2} m v_{S}^{2} + "
                                                              r"\frac{1}{2} \theta_{S}"
                                                              r" \omega^{2}"),
        " with ", Math("v_{S}"), " the speed of its centre of gravity S, ",
        Math(r"\theta_{S}"), " its mass moment of inertia about S and ", Math(r"\omega"),
        " its angular velocity:"))
    blocks.append(ctx.equation("T = " + " + ".join(pieces) + ".", label="parts:T"))
    for body in bodies:
        blocks.extend(_body(ctx, parts, body, terms[body.name]))
    return blocks


def _body(ctx: PartsContext, parts: _Parts, body: Body, term: Contribution) -> list[Block]:
    mech = parts.mechanism
    name = _label(body.name)
    blocks: list[Block] = []
    xs, ys = mech.centre(body)
    xo, yo = mech.origin(body)
    angle = mech.angle(body)
    omega = parts.rate(angle)
    mass = expression_latex(body.mass, ctx.namer)
    v_s = rf"\mathbf{{v}}_{{S,{name}}}"
    offset = (sympy.expand(xs - xo), sympy.expand(ys - yo))
    turning = omega != 0 and (offset[0] != 0 or offset[1] != 0)
    how = "translates" if omega == 0 else "translates and turns" if body.pin is None \
        else f"turns about the point {body.pin}"
    intro: list[Any] = [f"The body “{body.name}” (mass ", Math(mass), f") {how}"]
    if body.inertia is not None:
        blocks.append(paragraph(*intro, "; its mass moment of inertia about its centre of "
                                "gravity S is"))
        blocks.append(ctx.equation(rf"\theta_{{S,{name}}} = "
                                   + expression_latex(body.inertia, ctx.namer) + "."))
        intro = []
    if omega != 0:
        text = rf"\omega_{{{name}}} = {parts.tex(omega)}"
        plain = parts.rate(parts.substituted(angle))
        if sympy.simplify(parts.display(plain) - parts.display(omega)) != 0:
            text += f" = {parts.tex(plain)}"
        blocks.append(paragraph(*intro, "; its angular velocity is" if intro
                                else "Its angular velocity is"))
        blocks.append(ctx.equation(text + "."))
        intro = []
    if intro:
        intro.append(". ")
    vx, vy = parts.rate(xs), parts.rate(ys)
    if turning:
        origin = _pin_label(body.pin) if body.pin is not None else name
        v_o = rf"\mathbf{{v}}_{{{origin}}}"
        r_os = rf"\mathbf{{r}}_{{{origin}S}}"
        vox, voy = parts.rate(xo), parts.rate(yo)
        blocks.append(paragraph(
            *intro, "The velocity of its centre of gravity S follows from that of the point ",
            Math(origin), " it turns about:"))
        blocks.append(ctx.equation(
            rf"{v_s} = {v_o} + \boldsymbol{{\omega}}_{{{name}}} \times {r_os} = "
            + parts.vector([vox, voy, sympy.Integer(0)]) + r" + "
            + parts.vector([sympy.Integer(0), sympy.Integer(0), omega]) + r" \times "
            + parts.vector([offset[0], offset[1], sympy.Integer(0)]) + " = "
            + parts.vector([vox - omega * offset[1], voy + omega * offset[0],
                            sympy.Integer(0)]) + ",", label=f"vS:{body.name}"))
    else:
        blocks.append(paragraph(*intro, "The velocity of its centre of gravity S is"))
        blocks.append(ctx.equation(f"{v_s} = " + parts.vector([vx, vy]) + ",",
                                   label=f"vS:{body.name}"))
    square = _simplify(parts.display(vx) ** 2 + parts.display(vy) ** 2)
    blocks.append(paragraph("from which"))
    blocks.append(ctx.equation(rf"v_{{S,{name}}}^{{2}} = "
                               + sympy.latex(square, symbol_names=parts.names, order="none")
                               + ","))
    formula = rf"\frac{{1}}{{2}} {_group(mass)} v_{{S,{name}}}^{{2}}"
    energy = mech.expr(body.mass) * square / 2
    if body.inertia is not None:
        formula += rf" + \frac{{1}}{{2}} \theta_{{S,{name}}} \omega_{{{name}}}^{{2}}"
        energy += mech.expr(body.inertia) * parts.display(omega) ** 2 / 2
    blocks.append(paragraph("and its kinetic energy is"))
    shown = sympy.latex(energy, symbol_names=parts.names, order="none") \
        if sympy.count_ops(energy) <= MAX_SIMPLIFY else _contribution(ctx, term)
    blocks.append(ctx.equation(rf"T_{{{name}}} = {formula} = {shown}."))
    return blocks


_ATOM = re.compile(r"(\\mathrm\{\w+\}|\\?[A-Za-z]+|[0-9.]+)(_\{[\w\\{}]*\})?")


def _group(latex: str) -> str:
    """A factor in parentheses unless it is one symbol (``m_{1}``, ``\\mathrm{ct}``)."""
    return latex if _ATOM.fullmatch(latex) else rf"\left({latex}\right)"


def _link_intro(link: Link, index: int, what: str, coefficient: str) -> list[Any]:
    named = link.name if link.name != str(index) else ""
    return [f"The {what}{f' “{named}”' if named else ''} between {link.between[0]} and "
            f"{link.between[1]} ({'stiffness' if what == 'spring' else 'damping'} ",
            Math(coefficient), ")"]


def _elongation(ctx: PartsContext, parts: _Parts, link: Link, symbol: str, intro: list[Any]
                ) -> list[Block]:
    """Δl of a spring or damper, from its points as docs/parts.md defines it."""
    mech = parts.mechanism
    stretch = mech.elongation(link)
    (xa, ya), (xb, yb) = mech.point(link.between[0]), mech.point(link.between[1])
    a, b = (name_latex(p.replace(".", "_")) for p in link.between)
    if link.mode == "elongation":
        how: list[Any] = [" is elongated by (as given)"]
        text = f"{symbol} = {parts.tex(stretch)}"
    elif link.mode == "along":
        assert link.along is not None
        e = column_latex([expression_latex(c, ctx.namer) for c in link.along])
        how = [" stays parallel to ", Math(rf"\mathbf{{e}} = {e}"), "; its elongation "
               "is the change of the distance of its ends along it from the reference state"]
        d = rf"\left(\mathbf{{r}}_{{{b}}} - \mathbf{{r}}_{{{a}}}\right) \cdot \mathbf{{e}}"
        text = (rf"{symbol} = {d} - \left.{d}\right|_{{0}} = {parts.tex(stretch)}")
    else:
        free = expression_latex(link.length, ctx.namer) if link.length is not None else \
            parts.tex(mech.reference_distance(link))
        how = [" is elongated by the change of the distance of its ends (exact geometry), "
               "its free length being ", Math(free)]
        text = (rf"{symbol} = \left|\mathbf{{r}}_{{{b}}} - \mathbf{{r}}_{{{a}}}\right| - "
                f"{free} = " + rf"\left|{parts.vector([xb - xa, yb - ya])}\right| - {free}")
    return [paragraph(*intro, *how, ":"), ctx.equation(text + ",")]


def potential(ctx: PartsContext) -> list[Block]:
    """U as the sum of the springs' potentials and the gravity potential of the bodies."""
    if ctx.model.parts is None:
        return []
    parts = _Parts(ctx)
    springs = _contributions(ctx, "spring", "U")
    weights = _contributions(ctx, "body", "U")
    if not springs and not weights:
        return []
    blocks: list[Block] = []
    pieces = [f"U_{{{i}}}" for i, link in enumerate(parts.parts.springs, start=1)
              if link.name in springs]
    if weights:
        pieces.append(r"U_{g}")
    gravity_part: list[str | Math] = [", and of gravity, ", Math(r"\sum m g y_{S}")]
    if springs:
        blocks.append(paragraph("The potential function is the sum of the potentials of the "
                                "springs, each ", Math(r"\frac{1}{2} k \Delta l^{2}"),
                                " with its elongation ", Math(r"\Delta l"),
                                *(gravity_part if weights else []), ":"))
    else:
        blocks.append(paragraph("The potential function is that of gravity, ",
                                Math(r"\sum m g y_{S}"), " over the bodies:"))
    blocks.append(ctx.equation("U = " + " + ".join(pieces) + ".", label="parts:U"))
    for i, link in enumerate(parts.parts.springs, start=1):
        if link.name not in springs:
            continue
        k = expression_latex(link.coefficient, ctx.namer)
        symbol = rf"\Delta l_{{{i}}}"
        blocks.extend(_elongation(ctx, parts, link, symbol, _link_intro(link, i, "spring", k)))
        blocks.append(paragraph("so its potential is"))
        blocks.append(ctx.equation(rf"U_{{{i}}} = \frac{{1}}{{2}} {_group(k)} {symbol}^{{2}} = "
                                   + _contribution(ctx, springs[link.name]) + "."))
    if weights:
        gravity = expression_latex(parts.parts.gravity, ctx.namer) \
            if parts.parts.gravity is not None else "g"
        terms = []
        for body in parts.parts.bodies:
            if body.name in weights:
                _, ys = parts.mechanism.centre(body)
                terms.append(rf"{_group(expression_latex(body.mass, ctx.namer))} {gravity} "
                             rf"\, {_group(parts.tex(ys))}")
        blocks.append(paragraph("With gravity ", Math(gravity), " along -y, the heights of "
                                "the centres of gravity give"))
        blocks.append(ctx.equation("U_{g} = " + " + ".join(terms) + "."))
    return blocks


def dissipation(ctx: PartsContext) -> list[Block]:
    """D as the sum over the dampers, each with its rate of elongation."""
    if ctx.model.parts is None:
        return []
    parts = _Parts(ctx)
    dampers = _contributions(ctx, "damper", "D")
    if not dampers:
        return []
    blocks: list[Block] = []
    indices = [i for i, link in enumerate(parts.parts.dampers, start=1) if link.name in dampers]
    blocks.append(paragraph("The dissipation function is the sum over the dampers, each ",
                            Math(r"\frac{1}{2} c \Delta \dot{l}^{2}"), " with its rate of "
                            "elongation ", Math(r"\Delta \dot{l}"), ":"))
    blocks.append(ctx.equation(r"\mathcal{D} = " + " + ".join(
        rf"\mathcal{{D}}_{{{i}}}" for i in indices) + ".", label="parts:D"))
    for i, link in enumerate(parts.parts.dampers, start=1):
        if link.name not in dampers:
            continue
        c = expression_latex(link.coefficient, ctx.namer)
        symbol = rf"\Delta l_{{{i}}}"
        blocks.extend(_elongation(ctx, parts, link, symbol, _link_intro(link, i, "damper", c)))
        rate = parts.rate(parts.mechanism.elongation(link))
        blocks.append(paragraph("at the rate"))
        blocks.append(ctx.equation(rf"\Delta \dot{{l}}_{{{i}}} = {parts.tex(rate)},"))
        blocks.append(paragraph("so its dissipation function is"))
        blocks.append(ctx.equation(
            rf"\mathcal{{D}}_{{{i}}} = \frac{{1}}{{2}} {_group(c)} \Delta \dot{{l}}_{{{i}}}^{{2}}"
            " = " + _contribution(ctx, dampers[link.name]) + "."))
    return blocks


StepContext = TypeVar("StepContext", bound=PartsContext)


def after_heading(step: Callable[[StepContext], list[Block]],
                  extra: Callable[[StepContext], list[Block]]
                  ) -> Callable[[StepContext], list[Block]]:
    """``step`` with the blocks of ``extra`` after its first heading (a section of the
    solution that, for a model with parts, first derives its energy from the parts)."""
    def combined(ctx: StepContext) -> list[Block]:
        first = extra(ctx)  # first: its equations are numbered before the step's
        blocks = step(ctx)
        if not blocks:
            return first
        at = next((i + 1 for i, b in enumerate(blocks) if isinstance(b, Heading)), 0)
        return blocks[:at] + first + blocks[at:]

    combined.__name__ = getattr(step, "__name__", "step")
    return combined


__all__ = ["MechanismFigure", "figure", "kinetic", "potential", "dissipation", "after_heading"]
