"""The options of the analyses as records: one definition of each option, its default and
its check, shared by the Python interface, the command line and the ``[study]`` section.

An analysis takes its options either as keywords (``eom.sweep("omega", values,
method="dense")``) or as one record (``eom.sweep("omega", values,
options=SweepOptions(method="dense"))``), never both; the command line builds the record
from its arguments, and the record checks every value where it is made, so a wrong value
gets the same message whichever way it came in.

* :class:`SweepOptions`: the linear frequency response (``sweep``).
* :class:`BalanceOptions`: the periodic steady state by harmonic balance
  (``nonlinear_sweep``, its condensed form, and the ``[study]`` key ``harmonics``).
* :class:`SimulationOptions`: the time integration (``simulate``).

Examples
--------
>>> SweepOptions(method="dense").method
'dense'
>>> BalanceOptions(harmonics=0)
Traceback (most recent call last):
...
resonant.errors.AnalysisError: harmonics must be between 1 and 200, not 0
>>> chosen(None, SimulationOptions(rtol=1e-8)).rtol
1e-08
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import TypeVar

from ..errors import AnalysisError


@dataclass(frozen=True)
class SolveMethod:
    """One way to solve (K - w^2 M + i w C) z = F: an entry of ``SOLVE_METHODS``.

    Parameters
    ----------
    name : str
        What a user writes (``method="banded"``, ``--method banded``).
    does : str
        What it does, in one sentence (the table of docs/sweeps.md).
    exact : str
        How exact its answer is (``"yes"``, ``"to the tolerance"``, ...).
    chooses : bool
        Whether it picks another method of the table by cost (``auto``, ``direct``)
        instead of solving itself.
    constant_only : bool
        Whether it needs M, C and K that do not depend on the swept parameter (it
        factorizes or reduces one matrix triple for every frequency).
    """

    name: str
    does: str
    exact: str
    chooses: bool = False
    constant_only: bool = False


#: the solution methods of the harmonic kernel, each with its meaning (``auto``, the
#: default, first); a new method is one entry here and its solver in
#: :func:`resonant.analyses.kernel.solve_harmonic`
SOLVE_METHODS: Mapping[str, SolveMethod] = MappingProxyType({m.name: m for m in (
    SolveMethod("auto", "`reduced` where it pays and meets `--tol`, otherwise the exact "
                "method `direct` would pick", "to the tolerance, or exact", chooses=True),
    SolveMethod("direct", "the cheapest of `dense`, `banded`, `sparse` by their estimated "
                "cost", "yes", chooses=True),
    SolveMethod("dense", "a stack of complex matrices, one LAPACK solve per chunk of "
                "frequencies", "yes"),
    SolveMethod("banded", "LAPACK `gbsv` (`gtsv` for three diagonals) per frequency, for a "
                "narrow band — in the coordinates' reverse Cuthill-McKee order where that is "
                "narrower than the order given (an assembler's numbering can hide a beam's "
                "band: a Timoshenko beam's 2,003 becomes 5)", "yes", constant_only=True),
    SolveMethod("sparse", "a SuperLU factorization per frequency (fill-reducing ordering)",
                "yes", constant_only=True),
    SolveMethod("modal", "superposition of *all* undamped modes; checked against a direct "
                "solve", "yes, for proportional damping", constant_only=True),
    SolveMethod("reduced", "a reduced-order model accurate to `--tol` (below)",
                "to the tolerance", constant_only=True),
)})
#: the names of the solution methods, ``auto`` (the default) first
SWEEP_METHODS = tuple(SOLVE_METHODS)
#: the integrators of a simulation (:func:`scipy.integrate.solve_ivp` methods)
INTEGRATORS = ("DOP853", "RK45", "LSODA", "Radau", "BDF")
#: where a simulation started (``Simulation.start``) -> how its text and plots say it
START_KINDS = {"rest": "from rest",
               "stationary": "from the stationary initial state",
               "periodic": "from the periodic solution of the full equations",
               "given": "from the given initial state"}
#: where a simulation may be asked to start (``given``: by giving ``initial`` values)
START_MODES = ("auto", *(kind for kind in START_KINDS if kind != "given"))
#: the most harmonics an analysis takes when they are given (every nonlinear analysis, the
#: command line's ``--harmonics`` and the ``[study]`` key ``harmonics`` share it)
MAX_GIVEN_HARMONICS = 200
#: the fewest points of a continued branch
MIN_BRANCH_POINTS = 3


def _number(value: float | None) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value)


def _whole(value: int | None) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _check_tolerance(tol: float | None) -> None:
    if tol is not None and not (_number(tol) and 0 < tol < 1):
        raise AnalysisError(f"the tolerance must be a number between 0 and 1, not {tol}")


def check_harmonics(harmonics: int | None) -> None:
    """Raise AnalysisError unless ``harmonics`` is None or 1 ... MAX_GIVEN_HARMONICS.

    Examples
    --------
    >>> check_harmonics(7)
    """
    if harmonics is not None and not (_whole(harmonics) and
                                      1 <= harmonics <= MAX_GIVEN_HARMONICS):
        raise AnalysisError(f"harmonics must be between 1 and {MAX_GIVEN_HARMONICS}, not "
                            f"{harmonics}")


@dataclass(frozen=True)
class SweepOptions:
    """How a linear frequency response is computed (:func:`resonant.analyses.sweep.sweep`).

    Parameters
    ----------
    method : {"auto", "direct", "dense", "banded", "sparse", "modal", "reduced"}
        How to solve (docs/sweeps.md).
    names : tuple of str, optional
        The coordinates to report (default all; outputs are always reported).
    tol : float, optional
        Relative tolerance of a reduced model (0 < tol < 1; default 1e-6).
    log : bool, optional
        Whether the values are logarithmically spaced (default: detected).
    progress : bool, optional
        A progress bar on standard error (default: for long sweeps on a terminal).

    Raises
    ------
    AnalysisError
        For an unknown method or a tolerance outside (0, 1).

    Examples
    --------
    >>> SweepOptions(method="fast")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    resonant.errors.AnalysisError: unknown method 'fast'; choose one of auto, direct, ...
    """

    method: str = "auto"
    names: tuple[str, ...] | None = None
    tol: float | None = None
    log: bool | None = None
    progress: bool | None = None

    def __post_init__(self) -> None:
        if self.method not in SWEEP_METHODS:
            raise AnalysisError(f"unknown method '{self.method}'; choose one of "
                                f"{', '.join(SWEEP_METHODS)}")
        _check_tolerance(self.tol)
        if self.names is not None:
            object.__setattr__(self, "names", tuple(self.names))


@dataclass(frozen=True)
class BalanceOptions:
    """How a periodic steady state is continued by harmonic balance
    (:func:`resonant.analyses.harmonic_balance.nonlinear_sweep`).

    Parameters
    ----------
    harmonics : int, optional
        H, 1 ... :data:`MAX_GIVEN_HARMONICS` (default: chosen from the truncation).
    points : int
        About this many steps across the range (at least 3).
    linear : bool
        Also compute the linear sweep over the range, for comparison.
    observe : tuple of str, optional
        The coordinates recovered along the branch (balance condensed onto
        ``[[nonlinear]]`` elements; default the elements' and the loaded ones).
    samples : int, optional
        Time samples per period of the element forces (condensed balance).
    exact : bool, optional
        Solve the linear part exactly instead of by a reduced model (condensed balance).
    tol : float, optional
        Tolerance of the reduced linear part (condensed balance; 0 < tol < 1).

    Raises
    ------
    AnalysisError
        For a value out of its range.

    Examples
    --------
    >>> BalanceOptions(points=2)
    Traceback (most recent call last):
    ...
    resonant.errors.AnalysisError: points must be at least 3
    """

    harmonics: int | None = None
    points: int = 101
    linear: bool = True
    observe: tuple[str, ...] | None = None
    samples: int | None = None
    exact: bool | None = None
    tol: float | None = None

    def __post_init__(self) -> None:
        check_harmonics(self.harmonics)
        if not _whole(self.points) or self.points < MIN_BRANCH_POINTS:
            raise AnalysisError(f"points must be at least {MIN_BRANCH_POINTS}")
        if self.samples is not None and not (_whole(self.samples) and
                                             self.samples >= 1):
            raise AnalysisError(f"samples must be a positive whole number, not "
                                f"{self.samples}")
        _check_tolerance(self.tol)
        if self.observe is not None:
            object.__setattr__(self, "observe", tuple(self.observe))


@dataclass(frozen=True)
class SimulationOptions:
    """How a time integration runs (:func:`resonant.analyses.simulate.simulate`).

    Parameters
    ----------
    duration : float, optional
        End time in s (default: chosen from the system's time scales).
    nonlinear : bool, optional
        Integrate the full equations instead of the linearized ones.
    initial : mapping, optional
        Initial deviations and velocities (``{"x1": 0.01, "x2'": 0}``; values may be
        expressions of parameters).
    start : {"auto", "rest", "stationary", "periodic"}
        Where the motion starts.
    periods : float, optional
        The measurement window in periods of the lowest excitation frequency.
    method : str, optional
        A :func:`scipy.integrate.solve_ivp` method (:data:`INTEGRATORS`).
    rtol : float
        Relative tolerance of the integrator (0 < rtol < 1).
    progress : bool, optional
        Progress on standard error.

    Raises
    ------
    AnalysisError
        For a value out of its range.

    Examples
    --------
    >>> SimulationOptions(start="middle")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    resonant.errors.AnalysisError: start must be one of auto, rest, ... not 'middle'
    """

    duration: float | None = None
    nonlinear: bool | None = None
    initial: Mapping[str, float | str] | None = None
    start: str = "auto"
    periods: float | None = None
    method: str | None = None
    rtol: float = 1e-9
    progress: bool | None = None

    def __post_init__(self) -> None:
        if self.start not in START_MODES:
            raise AnalysisError(f"start must be one of {', '.join(START_MODES)}, not "
                                f"'{self.start}'")
        if self.method is not None and self.method not in INTEGRATORS:
            raise AnalysisError(f"method must be one of {', '.join(INTEGRATORS)}, not "
                                f"'{self.method}'")
        if self.duration is not None and not (_number(self.duration) and self.duration > 0):
            raise AnalysisError(f"the duration must be a positive number of seconds, not "
                                f"{self.duration}")
        if self.periods is not None and not (_number(self.periods) and self.periods > 0):
            raise AnalysisError(f"periods must be positive, not {self.periods}")
        if not (_number(self.rtol) and 0 < self.rtol < 1):
            raise AnalysisError(f"rtol must be a number between 0 and 1, not {self.rtol}")
        if self.initial is not None:
            object.__setattr__(self, "initial", MappingProxyType(dict(self.initial)))


Options = TypeVar("Options", SweepOptions, BalanceOptions, SimulationOptions)


def chosen(options: Options | None, keywords: Options) -> Options:
    """The options of a call: the record given, or the one made of the keywords.

    Parameters
    ----------
    options : SweepOptions, BalanceOptions or SimulationOptions, optional
        The ``options=`` argument.
    keywords : the same type
        The record of the call's keywords (all at their defaults when ``options`` is given).

    Raises
    ------
    AnalysisError
        If both a record and keywords that differ from the defaults are given.

    Examples
    --------
    >>> chosen(SweepOptions(method="dense"), SweepOptions()).method
    'dense'
    >>> chosen(SweepOptions(method="dense"), SweepOptions(method="sparse"))
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    resonant.errors.AnalysisError: give the options either as options= or as keywords, ...
    """
    if options is None:
        return keywords
    if not isinstance(options, type(keywords)):
        raise AnalysisError(f"options must be a {type(keywords).__name__}, not "
                            f"{type(options).__name__}")
    default = type(keywords)()
    both = [name for name in keywords.__dataclass_fields__
            if getattr(keywords, name) != getattr(default, name)]
    if both:
        raise AnalysisError("give the options either as options= or as keywords, not both "
                            f"({', '.join(both)})")
    return options


def names_tuple(names: Sequence[str] | None) -> tuple[str, ...] | None:
    """``names`` as a tuple (None stays None).

    Examples
    --------
    >>> names_tuple(["x1", "x2"])
    ('x1', 'x2')
    """
    return None if names is None else tuple(names)


__all__ = ["SweepOptions", "BalanceOptions", "SimulationOptions", "chosen", "check_harmonics",
           "names_tuple", "SolveMethod", "SOLVE_METHODS", "SWEEP_METHODS", "INTEGRATORS",
           "START_MODES", "START_KINDS", "MAX_GIVEN_HARMONICS", "MIN_BRANCH_POINTS"]
