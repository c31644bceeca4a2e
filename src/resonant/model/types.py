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
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import sympy

from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, name_list
from ..expressions import Expression, ExpressionError
from .options import BalanceOptions, SimulationOptions
from .parts import check_values as check_part_values
from .study import StudySpec
from .units import ModelUnits, parse_with_unit

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analyses.backbone import Backbones
    from ..analyses.nonlinear_response import NonlinearResponse
    from ..analyses.random_response import RandomResponse
    from ..analyses.simulate import Simulation
    from ..studies.result import StudyResult
    from ..system import LinearSystem
    from ..views.explore import ExplorePage
    from .exercise import Exercise
    from .explore import ExploreSpec
    from .load_spec import FatigueSpec, PeriodicSpec, ShockSpec
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
class Harmonic:
    """One harmonic excitation of a matrix model: Q = F_S sin(omega t) + F_C cos(omega t).

    Parameters
    ----------
    omega : Expression
        The circular frequency (rad/s).
    F_S, F_C : tuple of Expression
        The sine and cosine amplitudes, one per coordinate.

    Examples
    --------
    >>> from resonant.expressions import parse
    >>> Harmonic(parse("w"), (parse("1"),), (parse("0"),)).omega.text
    'w'
    """

    omega: Expression
    F_S: tuple[Expression, ...]
    F_C: tuple[Expression, ...]


@dataclass(frozen=True)
class MatrixSpec:
    """The ``[matrices]`` section: M, K, optional C, given directly.

    Parameters
    ----------
    M, K : array_like or sparse matrix
        Mass and stiffness (numbers, or expressions for inline matrices).
    C : array_like or sparse matrix, optional
        Damping (None: undamped).
    harmonics : tuple of Harmonic
        The ``[[harmonic]]`` loads.
    nonlinear : tuple of NonlinearElement
        The ``[[nonlinear]]`` elements (:mod:`resonant.model.nonlinear_elements`).

    Examples
    --------
    >>> from resonant.model import loads
    >>> m = loads('[matrices]\\nM = [[1]]\\nK = [[4]]\\n')
    >>> m.matrices.C is None, len(m.matrices.harmonics)
    (True, 0)
    """

    M: Any
    K: Any
    C: Any = None
    harmonics: tuple[Harmonic, ...] = ()
    nonlinear: tuple[Any, ...] = ()


@dataclass(frozen=True)
class Model:
    """A validated model: names, parsed expressions and parameter values.

    Build it with :func:`load` or :func:`loads`.  The data, and every analysis as a
    method (``linearize()``, ``simulate()``, ``nonlinear_sweep()``, ``backbone()``,
    ``study()``, ``draw()``, ``explore()``, ``report()``): each a one-line call of the
    function that does the work in a higher layer, imported when the method runs.

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
        return replace(self, parameters=MappingProxyType(params),
                        exact_values=MappingProxyType(exact),
                        parameter_values=MappingProxyType(floats))

    def linearize(self, timeout: float | None = None, deadline: Deadline | None = None
                  ) -> LinearSystem:
        """The linearized equation of motion M q'' + C q' + K q = Q(t)
        (:func:`resonant.system.linear_system`).

        Parameters
        ----------
        timeout : float, optional
            Time limit of the derivation in seconds (used when no ``deadline`` is given).
        deadline : Deadline, optional
            The cooperative deadline of the whole run.

        Returns
        -------
        LinearSystem
            A :class:`~resonant.system.LinearEOM` for a model given by its energies, a
            :class:`~resonant.system.MatrixEOM` for ``[matrices]``, with
            ``stationary()``, ``modes()`` and ``sweep()``.

        Raises
        ------
        ModelError
            If the derivation fails, exceeds the time limit, overflows or nests
            too deeply; the message names the expression being worked on.

        Examples
        --------
        >>> import resonant
        >>> resonant.load("examples/two_dof_free.toml").linearize().n
        2
        """
        from .. import system
        return system.linear_system(self, deadline or Deadline(timeout, self.source))

    def simulate(self, duration: float | None = None, nonlinear: bool | None = None,
                 initial: Mapping[str, float | str] | None = None, *, start: str = "auto",
                 periods: float | None = None, method: str | None = None,
                 rtol: float = 1e-9, progress: bool | None = None,
                 deadline: Deadline | None = None, options: SimulationOptions | None = None
                 ) -> Simulation:
        """Time integration, linear or of the full nonlinear equations
        (:func:`resonant.analyses.simulate.simulate`, where the options are described).

        Parameters
        ----------
        duration : float, optional
            End time in s (default: chosen from the system's time scales).
        nonlinear : bool, optional
            Integrate the full Lagrange equations instead of the linearized ones.
        initial : mapping, optional
            coordinate -> initial value.
        start : {"auto", "rest", "stationary", "given"}
            Where the motion starts.
        periods : float, optional
            Forcing periods to integrate when no ``duration`` is given.
        method : str, optional
            The integrator.
        rtol : float
            Relative tolerance of the integrator.
        progress : bool, optional
            A progress bar on standard error.
        deadline : Deadline, optional
            The run's time limit.
        options : SimulationOptions, optional
            The options above (but ``deadline``) as one record, instead of keywords.

        Returns
        -------
        Simulation

        Examples
        --------
        >>> import resonant
        >>> sim = resonant.load("examples/two_dof_free.toml").simulate(0.05, initial={"x1": 0.01})
        >>> sim.start
        'given'
        """
        from ..analyses import simulate
        return simulate.simulate(self.linearize(deadline=deadline), duration, nonlinear, initial,
                                 start=start, periods=periods, method=method, rtol=rtol,
                                 progress=progress, deadline=deadline or NO_DEADLINE,
                                 options=options)

    def nonlinear_sweep(self, param: str, start: float, stop: float, *,
                        harmonics: int | None = None, points: int = 101, linear: bool = True,
                        observe: Sequence[str] | None = None, samples: int | None = None,
                        exact: bool | None = None, tol: float | None = None,
                        deadline: Deadline | None = None, options: BalanceOptions | None = None
                        ) -> NonlinearResponse:
        """The periodic steady state against a parameter: harmonic balance, continuation,
        stability (:func:`resonant.analyses.harmonic_balance.nonlinear_sweep`, which chooses
        the balance the model calls for).

        Parameters
        ----------
        param : str
            The parameter to vary (usually the excitation frequency).
        start, stop : float
            The range.
        harmonics : int, optional
            H (default: chosen from the truncation).
        points : int
            About this many steps across the range.
        linear : bool
            Also compute the linear sweep.
        observe, samples, exact, tol : optional
            Options of the balance condensed onto ``[[nonlinear]]`` elements.
        deadline : Deadline, optional
            The run's time limit.
        options : BalanceOptions, optional
            The options above (but ``deadline``) as one record, instead of keywords.

        Returns
        -------
        NonlinearResponse

        Examples
        --------
        >>> import resonant
        >>> r = resonant.load("examples/duffing.toml").nonlinear_sweep(
        ...     "omega", 0.8, 1.2, harmonics=1, points=20)
        >>> r.parameter, r.harmonics
        ('omega', 1)
        """
        from ..analyses import harmonic_balance
        return harmonic_balance.nonlinear_sweep(
            self.linearize(deadline=deadline), param, start, stop, harmonics=harmonics,
            points=points, linear=linear, observe=observe, samples=samples, exact=exact,
            tol=tol, deadline=deadline or NO_DEADLINE, options=options)

    def backbone(self, amplitude: float | None = None, *, harmonics: int | None = None,
                 points: int | None = None, modes: list[int] | None = None,
                 deadline: Deadline | None = None) -> Backbones:
        """The backbone curves: free-vibration frequency against amplitude
        (:func:`resonant.analyses.backbone.backbone`).

        Parameters
        ----------
        amplitude : float, optional
            The largest amplitude to follow.
        harmonics : int, optional
            H (default: chosen).
        points : int, optional
            Points per curve.
        modes : list of int, optional
            The modes to follow (1-based; default all).
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        Backbones

        Examples
        --------
        >>> import resonant
        >>> b = resonant.load("examples/duffing.toml").backbone(harmonics=1, points=10)
        >>> len(b.curves) >= 1
        True
        """
        from ..analyses import backbone
        return backbone.backbone(self, amplitude, harmonics=harmonics, points=points,
                                 modes=modes, deadline=deadline or NO_DEADLINE)

    def study(self, vary: Mapping[str, Any] | None = None,
              quantities: Sequence[str] | None = None, *,
              output: str | os.PathLike[str] | None = None, workers: int | None = None,
              scheduler: str | None = None, client: Any = None, resume: bool = False,
              progress: bool | None = None, design: str | None = None,
              samples: int | None = None, seed: int | None = None,
              band: Mapping[str, Any] | None = None, harmonics: int | None = None
              ) -> StudyResult:
        """A parameter study (docs/studies.md; :func:`resonant.studies.run.study_of`, where
        the arguments are described): the arguments given, the rest from the model's
        ``[study]`` section.

        Returns
        -------
        StudyResult

        Examples
        --------
        >>> import resonant
        >>> model = resonant.load("examples/cart_pendulum.toml")
        >>> study = model.study({"k": "uniform(90, 110)"}, ["natural_frequency:1"],
        ...                     samples=200, seed=1, workers=0)
        >>> round(float(study.summary().loc["natural_frequency:1", "mean"]), 2)
        4.56
        """
        from ..studies import run
        return run.study_of(self, vary, quantities, output=output, workers=workers,
                            scheduler=scheduler, client=client, resume=resume,
                            progress=progress, design=design, samples=samples, seed=seed,
                            band=band, harmonics=harmonics)

    def draw(self, path: str | Path | None = None, ax: Axes | None = None
             ) -> Figure:
        """The mechanism drawn from its parts (:func:`resonant.views.drawing.draw_mechanism`).

        Parameters
        ----------
        path : str or Path, optional
            Also write the figure there (``.svg``, ``.png`` or ``.pdf``).
        ax : matplotlib.axes.Axes, optional
            Draw into the caller's axes.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..views import drawing
        return drawing.draw_mechanism(self, path, ax)

    def explore(self, path: str | Path | None = None,
                timeout: float | None = None) -> ExplorePage:
        """The interactive page of the model (:func:`resonant.views.explore.explore_page`);
        shown inline in Jupyter.

        Parameters
        ----------
        path : str or Path, optional
            Also write the page there (``.html``).
        timeout : float, optional
            Seconds for the derivation (default: no limit).

        Returns
        -------
        ExplorePage
            With ``html``, ``save(path)`` and ``_repr_html_`` (an iframe).
        """
        from ..views import explore
        return explore.explore_page(self, deadline=Deadline(timeout, self.source)).saved(path)

    def report(self, path: str | Path, plots: bool = True) -> Path:
        """Write the worked solution (:func:`resonant.report.write_report`).

        Parameters
        ----------
        path : str or Path
            ``.html``, ``.md`` or ``.tex``.
        plots : bool
            Include the figures.

        Returns
        -------
        Path
        """
        from .. import report
        return report.write_report(self, path, plots)

    def random_response(self, *, names: Sequence[str] | None = None, method: str = "auto",
                        tolerance: float | None = None, deadline: Deadline | None = None
                        ) -> RandomResponse:
        """The response to the ``[random]`` section's inputs: spectral densities, RMS values,
        Rice's rates (:func:`resonant.analyses.random_response.random_response`).

        Parameters
        ----------
        names : sequence of str, optional
            The coordinates and outputs to report (default all).
        method : str
            The harmonic solve's method.
        tolerance : float, optional
            Relative accuracy of the RMS values.
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        RandomResponse

        Examples
        --------
        >>> import resonant
        >>> result = resonant.load("examples/shaker_gevs.toml").random_response()
        >>> all(v > 0 for v in result.rms.values())
        True
        """
        from ..analyses import random_response
        return random_response.random_response(
            self.linearize(deadline=deadline), self.random_section, deadline or NO_DEADLINE,
            names=names, method=method, tolerance=tolerance)

    def _repr_latex_(self) -> str:
        from ..views import display
        return display.model_latex(self)

    def _repr_html_(self) -> str:
        from ..views import display
        return display.model_html(self)


def unknown_parameter(name: str, source: str, params: Iterable[str]) -> Problem:
    close = difflib.get_close_matches(name, list(params), n=1)
    hint = f"; did you mean '{close[0]}'?" if close else f"; known: {', '.join(params) or 'none'}"
    return Problem(f"cannot set unknown parameter '{name}'{hint}", source, "parameters", name)



# -- parameters ---------------------------------------------------------------------------

def primed_names(expression: Expression) -> list[str]:
    """The time derivatives (``k'``) in an expression that may only use constants."""
    return sorted(name + "'" * primes for name, primes in expression.names() if primes)


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
           "primed_names", "constant_prime_message",
           "unknown_parameter"]
