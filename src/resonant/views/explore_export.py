"""A model's linear system as a JavaScript program, for the explore page.

The page recomputes everything when a slider moves, so it needs the model's
symbolic results as functions of the parameters.  :func:`export_system` prints
them with resonant's own printer (:mod:`resonant.views.js_printer`):

* ``resonantParameters(v, o)`` -- every parameter from the controls' values ``v``;
  a parameter the file defines from others follows its formula unless ``o[i]``
  says it was set (like ``--set``);
* ``resonantMatrices(p)`` -- M, C, K (row-major) in one flat array, and
  ``resonantLoads(p)`` -- per excitation frequency its value, F_S, F_C and the (S, C)
  pair of every signal derivative the outputs use, then per output its value and
  coefficients (the order of :attr:`ExportedSystem.layout`; the same quantities as the
  system layer's evaluation);
* ``resonantMotion(p, q, s)`` and ``resonantSignals(p)`` -- for a model with parts,
  the position and angle of every body and point of the drawing, and the harmonic
  parts of the signals that move the drawing.

Examples
--------
>>> import resonant
>>> from resonant.system import linear_system
>>> model = resonant.load("examples/cart_pendulum.toml")
>>> exported = export_system(linear_system(model))
>>> exported.layout["n"], exported.layout["parameters"][:3]
(2, ['m1', 'm2', 'l'])
>>> "function resonantMatrices(p)" in exported.program
True
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import sympy

from ..derivation import decompose_signals
from ..derivation.lagrange import signal_derivatives
from ..model import Model, symbol
from ..system.base import LinearSystem
from .js_printer import NotPrintable, js_function, js_number
from .sketch import SketchMotion

Var = tuple[str, int]


@dataclass(frozen=True)
class ExportedSystem:
    """The JavaScript program of a model's linear system and the layout of its results.

    Parameters
    ----------
    program : str
        The functions ``resonantParameters``, ``resonantMatrices``, ``resonantLoads``
        (and, with a drawing,
        ``resonantMotion`` and ``resonantSignals``), as JavaScript source.
    layout : dict
        JSON-ready: ``parameters`` (names in order), ``derived`` (the indices of the
        parameters defined from others), ``n``, ``frequencies`` (how many symbolic
        excitation frequencies), ``variables`` (the signal derivatives whose (S, C)
        pairs follow each frequency), ``outputs`` (per output its ``name`` and ``terms``
        ``[name, order, coordinate index or -1, variable index or -1]``) and
        ``harmonic`` (False when a signal is not a sum of harmonics), ``matrix_parameters``
        (:func:`matrix_parameters`).

    Examples
    --------
    >>> ExportedSystem("", {"n": 1}).layout["n"]
    1
    """

    program: str
    layout: dict[str, Any]


def _names(model: Model, coordinates: Sequence[str] = ()) -> dict[sympy.Basic, str]:
    """The JavaScript text of every parameter (``p[i]``), coordinate (``q[i]``) and
    signal (``s[i]``) symbol."""
    names: dict[sympy.Basic, str] = {symbol(n): f"p[{i}]" for i, n in enumerate(model.parameters)}
    names.update({symbol(n): f"q[{i}]" for i, n in enumerate(coordinates)})
    names.update({symbol(n): f"s[{i}]" for i, n in enumerate(model.signals)})
    return names


def derived_parameters(model: Model) -> list[int]:
    """The indices of the parameters the file defines from other parameters.

    Parameters
    ----------
    model : Model

    Returns
    -------
    list of int

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/tuned_mass_damper.toml")
    >>> [list(model.parameters)[i] for i in derived_parameters(model)][:3]
    ['m2', 'omega1', 'f_opt']
    """
    return [i for i, expression in enumerate(model.parameters.values()) if expression.names()]


def parameters_function(model: Model) -> str:
    """``resonantParameters(v, o)``: the parameters in order, derived ones following
    their formulas unless set (``o[i]`` true).

    Parameters
    ----------
    model : Model

    Returns
    -------
    str
        JavaScript source.

    Examples
    --------
    >>> from resonant.model import loads
    >>> model = loads('[parameters]\\nm = 2\\nk = "4*m"\\n[coordinates]\\nx = ""\\n'
    ...               '[energy]\\nT = "m*x\\'^2/2"\\nU = "k*x^2/2"')
    >>> print(parameters_function(model))
    function resonantParameters(v, o) {
      const p = v.slice();
      if (!o[1]) p[1] = (4*p[0]);
      return p;
    }
    """
    names = _names(model)
    resolve = lambda name, primes: symbol(name)  # noqa: E731
    lines = ["function resonantParameters(v, o) {", "  const p = v.slice();"]
    expressions = list(model.parameters.values())
    for i in derived_parameters(model):
        text = js_function("f", [expressions[i].to_sympy(resolve)], names)
        body = text.splitlines()[1:-1]
        if len(body) == 1:  # no shared parts: the value itself
            value = body[0].strip()[len("return ["):-len("];")]
            lines.append(f"  if (!o[{i}]) p[{i}] = {value};")
        else:
            lines.append(f"  if (!o[{i}]) p[{i}] = (() => {{")
            lines += ["  " + line for line in body[:-1]]
            lines.append("    " + body[-1].strip().replace("return [", "return ")
                         .removesuffix("];") + ";")
            lines.append("  })();")
    lines += ["  return p;", "}"]
    return "\n".join(lines)


def _frequency_block(system: Any, harmonics: Any, w: sympy.Expr, variables: Sequence[Var]
                     ) -> list[sympy.Expr]:
    """omega, F_S, F_C and the signal pairs at one symbolic frequency."""
    n = system.n
    f_s, f_c = harmonics.forcing(system.excitation, w)
    if len(f_s) != n or len(f_c) != n:  # no excitation column at all: Q = 0
        f_s = f_c = [sympy.Integer(0)] * n
    out: list[sympy.Expr] = [w, *f_s, *f_c]
    for var in variables:
        s, c = harmonics.parts[var].get(w, (0, 0))
        out += [sympy.sympify(s), sympy.sympify(c)]
    return out


def system_expressions(system: LinearSystem) -> tuple[list[sympy.Expr], dict[str, Any]]:
    """Every quantity of ``resonantMatrices`` and ``resonantLoads`` as sympy, and the layout.

    Parameters
    ----------
    system : LinearSystem
        A system with symbolic matrices (a :class:`~resonant.system.LinearEOM` or
        :class:`~resonant.system.MatrixEOM`).

    Returns
    -------
    tuple
        (expressions, layout) -- see :class:`ExportedSystem`.

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import linear_system
    >>> exprs, layout = system_expressions(linear_system(resonant.load(
    ...     "examples/cart_pendulum.toml")))
    >>> exprs[:4], layout["frequencies"], layout["outputs"][0]["terms"]
    ([m1 + m2, m2/2, m2/2, m2/3], 1, [['x2', 0, 1, -1]])
    """
    eom: Any = system
    model = system.model
    assert model is not None
    exprs: list[sympy.Expr] = [*eom.M, *eom.C, *eom.K]
    harmonics = eom.harmonics
    variables: list[Var] = list(harmonics.parts) if harmonics is not None else []
    frequencies = list(harmonics.frequencies) if harmonics is not None else []
    for w in frequencies:
        exprs += _frequency_block(eom, harmonics, w, variables)
    index = {q: i for i, q in enumerate(system.coordinates)}
    outputs = []
    for name, out in dict(eom.outputs).items():
        exprs += [out.value, *out.terms.values()]
        outputs.append({"name": name, "terms": [
            [var, order, index.get(var, -1),
             variables.index((var, order)) if (var, order) in variables else -1]
            for var, order in out.terms]})
    layout = {"parameters": list(model.parameters), "derived": derived_parameters(model),
              "n": system.n, "frequencies": len(frequencies),
              "variables": [list(v) for v in variables], "outputs": outputs,
              "harmonic": harmonics is not None,
              "matrix_parameters": matrix_parameters(model, exprs[:3 * system.n ** 2])}
    return exprs, layout


def matrix_parameters(model: Model, entries: Sequence[sympy.Expr]) -> list[int]:
    """The indices of the parameters M, C, K depend on, directly or through the formulas
    of other parameters (the page keeps M, C, K along a sweep of any other parameter).

    Parameters
    ----------
    model : Model
    entries : sequence of sympy.Expr
        The entries of M, C and K.

    Returns
    -------
    list of int

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import linear_system
    >>> model = resonant.load("examples/tuned_mass_damper.toml")
    >>> exprs, _ = system_expressions(linear_system(model))
    >>> [list(model.parameters)[i] for i in matrix_parameters(model, exprs[:12])]
    ['m1', 'k1', 'mu', 'm2', 'omega1', 'f_opt', 'zeta_opt', 'k2', 'c2']
    """
    names = list(model.parameters)
    used: set[str] = set()
    for entry in entries:
        used |= {str(s) for s in sympy.sympify(entry).free_symbols}
    pending = [n for n in used if n in model.parameters]
    found: set[str] = set()
    while pending:
        name = pending.pop()
        if name in found:
            continue
        found.add(name)
        pending += [n for n, _ in model.parameters[name].names() if n in model.parameters]
    return [i for i, name in enumerate(names) if name in found]


def motion_functions(model: Model, motion: SketchMotion) -> tuple[str, int]:
    """``resonantMotion(p, q, s)`` (x, y, angle of every owner of the drawing) and
    ``resonantSignals(p)`` (per frequency of the drawing's signals: omega and the (S, C)
    pair of every signal, in the model's order), and the number of those frequencies.

    Parameters
    ----------
    model : Model
    motion : SketchMotion

    Returns
    -------
    tuple
        (JavaScript source, number of signal frequencies).

    Examples
    --------
    >>> import pathlib, resonant
    >>> from resonant.views.sketch import sketch_motion
    >>> path = pathlib.Path(resonant.__file__).parents[2] / "examples/parts/pendulum.toml"
    >>> model = resonant.load(path)
    >>> source, count = motion_functions(model, sketch_motion(model))
    >>> count, "function resonantMotion(p, q, s)" in source
    (1, True)
    """
    names = _names(model, model.coordinates)
    flat = [e for position in motion.positions for e in position]
    source = js_function("resonantMotion", flat, names, ("p", "q", "s"))
    signals = list(model.signals)
    harmonics = decompose_signals(signal_derivatives(model, {(s, 0) for s in signals})) \
        if signals else None
    parts: list[sympy.Expr] = []
    count = 0
    if harmonics is not None:
        for w in harmonics.frequencies:
            parts.append(w)
            for s in signals:
                pair = harmonics.parts[(s, 0)].get(w, (0, 0))
                parts += [sympy.sympify(pair[0]), sympy.sympify(pair[1])]
            count += 1
    source += "\n" + js_function("resonantSignals", parts, names)
    return source, count


def periodic_columns(system: LinearSystem, name: str, derivative: int
                     ) -> tuple[list[sympy.Expr], list[int]]:
    """The load of a periodic input per unit of its series: the generalized-force column
    of every derivative of the signal ``name`` (n expressions each) and the power of
    (i omega) each is multiplied by (its order less ``derivative``); for a coordinate, its
    unit column (a force on it), power 0.

    Parameters
    ----------
    system : LinearSystem
    name : str
        A signal of the model or a coordinate (the ``[periodic]`` section's ``signal``).
    derivative : int
        The series is of this derivative of the signal.

    Returns
    -------
    tuple
        (the columns, flattened; the powers).

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import linear_system
    >>> system = linear_system(resonant.load("examples/base_excitation.toml"))
    >>> columns, powers = periodic_columns(system, "y", 0)
    >>> len(columns) == system.n * len(powers), powers
    (True, [0, 1])
    """
    excitation: Mapping[Var, Any] = getattr(system, "excitation", None) or {}
    n = system.n
    columns: list[sympy.Expr] = []
    powers: list[int] = []
    for (var, order), column in sorted(excitation.items()):
        if var == name:
            columns += [sympy.sympify(column[i]) for i in range(n)]
            powers.append(order - derivative)
    if not powers and name in system.coordinates:
        columns = [sympy.Integer(int(q == name)) for q in system.coordinates]
        powers = [0]
    return columns, powers


def export_system(system: LinearSystem, motion: SketchMotion | None = None
                  ) -> ExportedSystem:
    """The JavaScript program of a system (and of its drawing's motion).

    Parameters
    ----------
    system : LinearSystem
        A system with a model and symbolic matrices.
    motion : SketchMotion, optional
        The drawing of its parts, to move with the response.

    Returns
    -------
    ExportedSystem

    Raises
    ------
    resonant.views.js_printer.NotPrintable
        If an expression is outside the model language.

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import linear_system
    >>> exported = export_system(linear_system(resonant.load("examples/absorber.toml")))
    >>> exported.layout["n"], "resonantMotion" in exported.program
    (2, False)
    """
    model = system.model
    assert model is not None
    exprs, layout = system_expressions(system)
    names = _names(model)
    size = 3 * system.n ** 2
    program = [parameters_function(model), js_function("resonantMatrices", exprs[:size], names),
               js_function("resonantLoads", exprs[size:], names)]
    periodic = model.periodic_section
    if periodic is not None:
        columns, powers = periodic_columns(system, periodic.signal, periodic.derivative)
        program.append(js_function("resonantPeriodic", columns, names))
        layout["periodic_powers"] = powers
    if motion is not None:
        source, count = motion_functions(model, motion)
        program.append(source)
        layout["signal_frequencies"] = count
        layout["signals"] = list(model.signals)
    bearings = model.matrices.bearings if model.matrices is not None else ()
    if bearings:
        program.append(js_function("resonantBearings", bearing_expressions(bearings), names))
    return ExportedSystem("\n".join(program), layout)


#: the coefficients of a bearing the force it transmits takes, in the order the page reads
BEARING_KEYS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


def bearing_expressions(bearings: Sequence[Any]) -> list[sympy.Expr]:
    """Every bearing's :data:`BEARING_KEYS` as expressions of the parameters (0 where not
    given), for the page's bearing forces at the sliders' values
    (:func:`resonant.analyses.unbalance.bearing_force` is the same force).

    Raises
    ------
    resonant.views.js_printer.NotPrintable
        For a coefficient tabulated in speed (the page refuses such a rotor before).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/rotors/friswell_5_9_1.toml")
    >>> bearing_expressions(model.matrices.bearings)[:4]
    [1000000.00000000, 0, 0, 1000000.00000000]
    """
    resolve = lambda name, primes: symbol(name)  # noqa: E731
    out: list[sympy.Expr] = []
    for bearing in bearings:
        given = dict(bearing.coefficients)
        for key in BEARING_KEYS:
            value = given.get(key, 0.0)
            if isinstance(value, (int, float)):
                out.append(sympy.Float(value) if value else sympy.Integer(0))
            elif hasattr(value, "to_sympy"):
                out.append(value.to_sympy(resolve))
            else:
                raise NotPrintable(f"the bearing coefficient {bearing.name} {key} is a table")
    return out


def equilibrium_values(model: Model) -> list[float]:
    """The reference state of every coordinate (``[equilibrium]``, else 0) as numbers.

    Parameters
    ----------
    model : Model

    Returns
    -------
    list of float

    Examples
    --------
    >>> import resonant
    >>> equilibrium_values(resonant.load("examples/cart_pendulum.toml"))
    [0.0, 0.0]
    """
    values: Mapping[str, float] = model.parameter_values
    out = []
    for q in model.coordinates:
        expression = model.equilibrium.get(q)
        out.append(0.0 if expression is None else float(
            expression.to_sympy(lambda name, primes: sympy.Float(values[name], 17))))
    return out


__all__ = ["ExportedSystem", "export_system", "system_expressions", "parameters_function",
           "motion_functions", "derived_parameters", "equilibrium_values", "matrix_parameters",
           "js_number", "bearing_expressions", "BEARING_KEYS"]
