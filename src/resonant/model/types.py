"""The validated model: names, parsed expressions and parameter values.

These are the model layer's types; :mod:`resonant.model.loader` builds them
from a TOML file.

Examples
--------
>>> from resonant.model import loads
>>> m = loads('[parameters]\\nk = 1\\n[coordinates]\\nx = ""\\n'
...           '[energy]\\nT = "x\\'^2/2"\\nU = "k*x^2/2"')
>>> m.coordinates, m.parameter_values["k"]
(('x',), 1.0)
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import TYPE_CHECKING

import sympy

from ..errors import ModelError, Problem, name_list
from ..expressions import Expression, ExpressionError, primed_names
from .matrix_spec import Harmonic, MatrixSpec
from .parts import check_values as check_part_values
from .study import StudySpec
from .units import ModelUnits, parse_with_unit

if TYPE_CHECKING:
    from .campbell_spec import CampbellSpec, Unbalance
    from .exercise import Exercise
    from .explore import ExploreSpec
    from .load_spec import FatigueSpec, PeriodicSpec, ShockSpec
    from .measurement_spec import MeasurementSpec
    from .parts import DerivedEnergies
    from .random_spec import RandomSpec

TIME = sympy.Symbol("t")


def symbol(name: str) -> sympy.Symbol:
    """The sympy symbol of a model name (parameters, signals, coordinates).

    Parameters
    ----------
    name : str
        A name of the model.

    Returns
    -------
    sympy.Symbol
        The symbol every stage uses for it.

    Examples
    --------
    >>> symbol("m1")
    m1
    """
    return sympy.Symbol(name)


@dataclass(frozen=True)
class Force:
    """A ``[[force]]`` entry: a force vector acting on a point, or generalized forces.

    ``kind`` is ``"torque"`` for a ``[[torque]]`` part (a moment acting on a body's angle,
    given as a one-component vector at the angle): messages name it as such.

    Parameters
    ----------
    name : str
        The entry's name (or its number), used in messages.
    vector : tuple of Expression
        The force's components (empty for generalized forces).
    point : tuple of Expression
        The position of the point it acts on.
    generalized : mapping
        coordinate -> generalized force, when given that way.
    kind : str
        ``"force"`` or ``"torque"``.

    Examples
    --------
    >>> from resonant.expressions import parse
    >>> Force("push", generalized={"x": parse("F0")}).kind
    'force'
    """

    name: str
    vector: tuple[Expression, ...] = ()
    point: tuple[Expression, ...] = ()
    generalized: Mapping[str, Expression] = field(default_factory=dict)
    kind: str = "force"


@dataclass(frozen=True)
class Model:
    """A validated model: names, parsed expressions and parameter values.

    Build it with :func:`load` or :func:`loads`.  This is the data: nothing here computes
    with a layer above.  What ``resonant.load`` returns is :class:`resonant.api.Model`,
    this class with the analyses as methods (``linearize()``, ``simulate()``, ...).

    Attributes
    ----------
    title : str
        The model's title (``title = "..."``), may be empty.
    source : str
        The file it was read from (``"<string>"`` for text).
    parameters : mapping
        name -> parsed :class:`~resonant.expressions.Expression`, in file order.
    parameter_values : mapping
        name -> float (SI): every parameter evaluated.
    exact_values : mapping
        name -> exact sympy value (rationals where the text is exact).
    coordinates : tuple of str
        The generalized coordinates, in order.
    descriptions : mapping
        coordinate -> the description given in ``[coordinates]``.
    equilibrium : mapping
        coordinate -> the reference state (``[equilibrium]``; 0 if not given).
    signals : mapping
        name -> prescribed function of t (``[signals]``).
    definitions : mapping
        name -> expression (``[definitions]``), usable in energies and outputs.
    energy : mapping
        ``"T"``, ``"U"``, ``"D"`` -> expression (the totals for a model with parts).
    forces : tuple of Force
        The ``[[force]]`` entries (and the parts' forces and torques).
    outputs : mapping
        name -> expression of a quantity to report (``[outputs]``).
    matrices : MatrixSpec or None
        The ``[matrices]`` section (None for a model given by energies or parts).
    exercise : Exercise or None
        The teacher's ``[exercise]`` and ``[variants]``.
    parts : DerivedEnergies or None
        The mechanism's parts and the energies derived from them.
    units : ModelUnits or None
        Physical units (None for a model without units: every number SI).
    study_section : StudySpec or None
        The ``[study]`` section.
    explore_section : ExploreSpec or None
        The ``[explore]`` section: the ranges of the explore page's sliders.
    random_section : RandomSpec or None
        The ``[random]`` section: the spectral densities of random inputs.
    shock_section : ShockSpec or None
        The ``[shock]`` section: a classical pulse on one input.
    fatigue_section : FatigueSpec or None
        The ``[fatigue]`` section: an S-N curve, a spectral method and the exposure.
    periodic_section : PeriodicSpec or None
        The ``[periodic]`` section: a periodic, non-harmonic load on one input.
    measurement_section : MeasurementSpec or None
        The ``[measurement]`` section: the measured channels' coordinates and outputs.
    campbell_section : CampbellSpec or None
        The ``[campbell]`` section: a rotor's speed range, branches and orders.
    unbalances : tuple of Unbalance
        The ``[[unbalance]]`` tables (resonant.model.campbell_spec).

    Examples
    --------
    >>> from resonant.model import loads
    >>> m = loads('[parameters]\\nm = 3\\nk = "2*m"\\n[coordinates]\\nx = ""\\n'
    ...           '[energy]\\nT = "m*x\\'^2/2"\\nU = "k*x^2/2"')
    >>> m.coordinates, m.parameter_values["k"]
    (('x',), 6.0)
    """

    title: str
    source: str
    parameters: Mapping[str, Expression]
    parameter_values: Mapping[str, float]
    exact_values: Mapping[str, sympy.Expr]
    coordinates: tuple[str, ...]
    descriptions: Mapping[str, str]
    equilibrium: Mapping[str, Expression]
    signals: Mapping[str, Expression]
    definitions: Mapping[str, Expression]
    energy: Mapping[str, Expression]
    forces: tuple[Force, ...]
    outputs: Mapping[str, Expression]
    matrices: MatrixSpec | None = None
    #: the teacher's ``[exercise]`` and ``[variants]`` (None without them)
    exercise: Exercise | None = None
    #: parts -> energies (``[[body]]``, ``[[spring]]``, ...; None without parts);
    #: ``energy`` then holds the totals, ``parts.written`` what ``[energy]`` gives
    parts: DerivedEnergies | None = None
    #: physical units (resonant.model.units): what was given, the dimensions, the
    #: display units; None for a model without units (every number SI, nothing checked)
    units: ModelUnits | None = None
    #: the ``[study]`` section (resonant.model.study); None without one
    study_section: StudySpec | None = None
    #: the ``[explore]`` section (resonant.model.explore): slider ranges, the names the
    #: frequency response shows, the excitation frequency's parameter; None without it
    explore_section: ExploreSpec | None = None
    #: the ``[random]`` section (resonant.model.random_spec); None without one
    random_section: RandomSpec | None = None
    #: the ``[shock]`` section (resonant.model.load_spec); None without one
    shock_section: ShockSpec | None = None
    #: the ``[fatigue]`` section (resonant.model.load_spec); None without one
    fatigue_section: FatigueSpec | None = None
    #: the ``[periodic]`` section (resonant.model.load_spec); None without one
    periodic_section: PeriodicSpec | None = None
    #: the ``[measurement]`` section (resonant.model.measurement_spec); None without one
    measurement_section: MeasurementSpec | None = None
    #: the ``[campbell]`` section (resonant.model.campbell_spec); None without one
    campbell_section: CampbellSpec | None = None
    #: the ``[[unbalance]]`` tables (resonant.model.campbell_spec)
    unbalances: tuple[Unbalance, ...] = ()

    def symbols(self) -> dict[str, sympy.Symbol]:
        """The parameter symbols by name."""
        return {name: symbol(name) for name in self.parameters}

    def with_parameters(self, **values: float | str) -> Model:
        """A copy with some parameters replaced (values are parsed, not evaluated).

        Examples
        --------
        >>> from resonant.model import loads
        >>> m = loads('[parameters]\\nk = 1\\n[coordinates]\\nx = ""\\n'
        ...           '[energy]\\nT = "x\\'^2/2"\\nU = "k*x^2/2"')
        >>> m.with_parameters(k=4).parameter_values["k"]
        4.0
        """
        params = dict(self.parameters)
        problems: list[Problem] = []
        written = dict(self.units.given) if self.units is not None else {}
        for name, value in values.items():
            if name not in params:
                problems.append(unknown_parameter(name, self.source, params))
                continue
            try:
                params[name], given = parse_with_unit(value, list(params), self.source,
                                                      "parameters", name)
            except ExpressionError as exc:
                problems.extend(exc.problems)
                continue
            # what the value was written as follows the value ("800 kN/m" is the template's)
            if given is not None:
                written[name] = given
            else:
                written.pop(name, None)
            mismatch = self.units.replacement_problem(name, *given) \
                if given is not None and self.units is not None else None
            if mismatch:
                problems.append(Problem(mismatch, self.source, "parameters", name))
        if problems:
            raise ModelError(problems)
        exact, floats = evaluate_parameters(params, self.source)
        if self.parts is not None:  # a mass or inertia of a part may have turned negative
            negative = check_part_values(self.parts.parts, exact, self.source)
            if negative:
                raise ModelError(negative)
        units = None if self.units is None else \
            replace(self.units, given=MappingProxyType(written))
        return replace(self, parameters=MappingProxyType(params),
                        exact_values=MappingProxyType(exact),
                        parameter_values=MappingProxyType(floats), units=units)


def unknown_parameter(name: str, source: str, params: Iterable[str]) -> Problem:
    close = difflib.get_close_matches(name, list(params), n=1)
    hint = f"; did you mean '{close[0]}'?" if close else f"; known: {', '.join(params) or 'none'}"
    return Problem(f"cannot set unknown parameter '{name}'{hint}", source, "parameters", name)



# -- parameters ---------------------------------------------------------------------------

def constant_prime_message(primed: Sequence[str]) -> str:
    """Why ``k'`` is refused where only parameters (constants) are allowed."""
    return (f"{primed[0]} is the time derivative of a parameter; parameters are constants "
            "and have no time derivative here (remove the prime)")


def evaluate_parameters(params: Mapping[str, Expression], source: str
                         ) -> tuple[dict[str, sympy.Expr], dict[str, float]]:
    """Exact and floating values of the parameters, in declaration order."""
    exact: dict[str, sympy.Expr] = {}
    floats: dict[str, float] = {}
    problems: list[Problem] = []
    root_of: dict[str, str] = {}  # failed parameter -> the invalid one it comes from
    dependents: dict[str, list[str]] = {}

    def resolve(n: str, p: int) -> sympy.Expr:
        return exact[n] if p == 0 else sympy.Integer(0)

    for name, expression in params.items():
        primed = primed_names(expression)
        if primed:
            problems.append(Problem(constant_prime_message(primed), source, "parameters", name))
            continue
        try:
            value = expression.to_sympy(resolve)
        except ExpressionError as exc:
            problems.extend(exc.problems)
            continue
        except KeyError as exc:  # refers to a parameter that failed itself
            root = root_of.get(exc.args[0], exc.args[0])
            root_of[name] = root
            dependents.setdefault(root, []).append(name)
            continue
        try:
            number = complex(value.evalf(30))
        except (TypeError, ValueError):
            problems.append(Problem(f"'{expression.text}' is not a number", source,
                                    "parameters", name))
            continue
        except (ArithmeticError, RecursionError):  # exp(cosh(1e300)): beyond any precision
            number = complex(math.inf)
        if abs(number.imag) > 1e-12 * max(1.0, abs(number.real)):
            problems.append(Problem(f"'{expression.text}' is not a real number ({number})",
                                    source, "parameters", name))
            continue
        if not math.isfinite(number.real) or abs(number.real) > 1e300:
            problems.append(Problem(
                f"'{expression.text}' is not a finite number; use a value below 1e300",
                source, "parameters", name))
            continue
        exact[name] = value
        floats[name] = float(number.real)
    if problems or dependents:
        raise ModelError(_with_dependents(problems, dependents, source))
    return exact, floats


def _with_dependents(problems: list[Problem], dependents: Mapping[str, list[str]],
                     source: str) -> list[Problem]:
    """One line per invalid parameter, followed by the parameters that depend on it."""
    last = {p.key: i for i, p in enumerate(problems) if p.section == "parameters"}
    out: list[Problem] = []
    for i, problem in enumerate(problems):
        out.append(problem)
        if last.get(problem.key) == i and problem.key in dependents:
            out.append(_dependents_line(dependents[problem.key], source, problem.key))
    for root, names in dependents.items():
        if root not in last:  # its own problem was reported elsewhere
            out.append(Problem(f"depends on the invalid parameter '{root}'", source,
                               "parameters", names[0]))
            if names[1:]:
                out.append(_dependents_line(names[1:], source, names[0]))
    return out


def _dependents_line(names: Sequence[str], source: str, key: str) -> Problem:
    many = len(names) > 1
    return Problem(f"and {len(names)} parameter{'s' if many else ''} that "
                   f"depend{'' if many else 's'} on it: {name_list(names)}", source,
                   "parameters", key)



__all__ = ["Model", "Force", "Harmonic", "MatrixSpec", "symbol", "TIME", "evaluate_parameters",
           "constant_prime_message",
           "unknown_parameter"]
