"""The nonlinear-system type: the full equations of motion, compiled once.

Every analysis beyond small oscillations (``simulate(..., nonlinear=True)``,
harmonic balance, the periodic solution, backbone curves, the report's
section) takes one :class:`NonlinearSystem`.  It holds the equations of
motion in full (not linearized), written as a residual of the absolute
coordinates ``q`` and their derivatives::

    E(q, q', q'', s; p, d) = 0,

``s`` the excitation terms (the forcing), ``p`` the parameter values and
``d`` a factor on the dissipation (1 for the model, 0 for the undamped
system of backbone curves).  Explicit time enters only through ``s``.

The interface (all arrays float; ``N`` samples in the last axis):

* ``coordinates``, ``outputs``, ``parameters`` (names), ``parameter_values``
  (the model's), ``title``, ``model`` (the :class:`~resonant.model.Model`);
* ``linear``: the :class:`~resonant.system.LinearSystem` at the reference state
  (small oscillations: ``M q'' + C q' + K q = Q``);
* ``reference(pvals)``: the reference state ``q_ref`` (``[equilibrium]``);
* ``parameter_point(param, value)``: all parameter values with one changed
  (parameters defined by expressions of it follow);
* ``forcing(t, pvals)``: ``s`` at the times ``t``, shape ``(forcing_size, N)``
  (free vibration: zeros of that shape; a scalar t gives ``(forcing_size,)``);
* ``equations(q, qd, qdd, s, pvals, damping=1.0)``: ``E`` (n, N) and its
  partial derivatives ``dE/dq``, ``dE/dq'``, ``dE/dq''`` (n, n, N); the
  equations are linear in ``q''``, so ``dE/dq''`` is the mass matrix;
* ``dynamics(t, q, qd, pvals)``: the forced equations at time t as ``mass q'' + rest``
  for the time integration (a default from ``forcing`` and ``equations``; a system may
  compile a cheaper kernel);
* ``output_values(q, qd, qdd, s, pvals)``: ``name -> (N,)`` deviation of every
  output from its value at the reference state;
* ``base_frequency(pvals)``: the base frequency W of a periodic forcing (the
  largest common divisor of its frequencies), or :class:`AnalysisError`.

:class:`EnergySystem` implements it for a model given by its energies (the
full Lagrange equations of :func:`resonant.derivation.nonlinear_equations`).
A system of linear matrices with a few local nonlinear element forces
implements the same methods (``E = M q'' + d C q' + K q + f(q, q') - Q(t)``).
:func:`nonlinear_system` builds the system of a model or of its linear system;
the compilation (:func:`sympy.lambdify`, common subexpressions, numpy) happens
there, once per system.

Examples
--------
>>> from resonant.model import loads
>>> from resonant.system import nonlinear_system
>>> system = nonlinear_system(loads('''
... [parameters]
... k3 = 0.5
... [coordinates]
... x = ""
... [energy]
... T = "x'^2/2"
... U = "x^2/2 + k3*x^4/4"
... '''))
>>> q, zero = np.array([[2.0]]), np.zeros((1, 1))
>>> E, dq, dqd, dqdd = system.equations(q, zero, zero, system.forcing(zero[0],
...     system.parameter_values), system.parameter_values)
>>> float(E[0, 0]), float(dq[0, 0, 0]), float(dqdd[0, 0, 0])
(6.0, 7.0, 1.0)
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import reduce
from typing import Any

import numpy as np
import sympy

from ..derivation import NonlinearEquations, nonlinear_equations
from ..derivation.harmonics import NotHarmonic, decompose
from ..errors import AnalysisError
from ..expressions import compilable
from ..model import TIME, Model, symbol
from ..model.nonlinear_elements import NonlinearElement
from .base import LinearSystem, parameter_values
from .matrix_outputs import OutputSeries
from .nonlinear_elements import ElementForces

#: the dissipation factor symbol of the compiled equations (1: damped, 0: undamped)
_DAMPING = sympy.Symbol("_resonant_damping")


@dataclass(frozen=True)
class LocalElements:
    """A system's nonlinear forces as local elements between fixed linear matrices, what
    the balance condensed onto the elements' coordinates takes
    (:func:`resonant.analyses.condensed.condensed_sweep`).

    Attributes
    ----------
    linear : LinearSystem
        The linear part M q'' + C q' + K q = Q(t).
    elements : tuple of NonlinearElement
        The ``[[nonlinear]]`` elements (their kinds, coordinates and laws).
    forces : callable
        ``pvals -> ElementForces``: the elements' forces and tangents at parameter values.
    frequencies : callable
        ``pvals -> ndarray``: the angular frequency of each harmonic load.
    outputs : OutputSeries or None
        The model's outputs in full over a sampled motion (None without outputs).
    """

    linear: LinearSystem
    elements: tuple[NonlinearElement, ...]
    forces: Callable[[np.ndarray], ElementForces]
    frequencies: Callable[[np.ndarray], np.ndarray]
    outputs: OutputSeries | None


class NonlinearSystem(ABC):
    """The full equations of motion of a model, compiled (see the module docstring).

    Subclasses set the attributes in ``__init__`` and implement the abstract methods.

    Attributes
    ----------
    model : Model
        The model the equations come from.
    coordinates : tuple of str
        The generalized coordinates q, in the order of the vector q.
    outputs : tuple of str
        The model's outputs that can be evaluated along a motion.
    parameters : tuple of str
        The parameter names, in the order of the ``pvals`` arrays the methods take.
    parameter_values : numpy.ndarray
        The model's own values of :attr:`parameters`.
    linear : LinearSystem
        The linearization about the reference state (small oscillations).
    forcing_size : int
        The number of forcing terms (rows of :meth:`forcing`).
    unsupported_outputs : tuple of str
        Outputs that cannot be evaluated (a coordinate's derivative of order above 2).

    See Also
    --------
    nonlinear_system : the system of a model.
    LinearSystem : the small-oscillation equations.

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import nonlinear_system
    >>> system = nonlinear_system(resonant.load("examples/duffing.toml"))
    >>> isinstance(system, NonlinearSystem), system.linear.coordinates
    (True, ('x',))
    """

    model: Model
    coordinates: tuple[str, ...]
    outputs: tuple[str, ...]
    parameters: tuple[str, ...]
    parameter_values: np.ndarray
    linear: LinearSystem
    #: number of forcing terms (rows of :meth:`forcing`)
    forcing_size: int
    #: outputs that cannot be evaluated (a coordinate's derivative of order > 2)
    unsupported_outputs: tuple[str, ...] = ()
    #: the nonlinear forces as local elements between linear matrices, where they are
    #: (a [matrices] model's [[nonlinear]] elements; None for a model given by energies)
    local_elements: LocalElements | None = None

    @property
    def n(self) -> int:
        """Number of coordinates."""
        return len(self.coordinates)

    @property
    def title(self) -> str:
        return self.model.title

    @abstractmethod
    def reference(self, pvals: np.ndarray) -> np.ndarray:
        """The reference state q_ref (absolute coordinates) at the parameter values.

        Parameters
        ----------
        pvals : numpy.ndarray
            The values of :attr:`parameters`, in that order.

        Returns
        -------
        numpy.ndarray
            (n,) the coordinates of the reference state (``[equilibrium]``, else 0).
        """

    @abstractmethod
    def forcing(self, t: np.ndarray, pvals: np.ndarray) -> np.ndarray:
        """The excitation terms s at the times ``t``.

        Parameters
        ----------
        t : numpy.ndarray
            (N,) times in s.
        pvals : numpy.ndarray
            The values of :attr:`parameters`.

        Returns
        -------
        numpy.ndarray
            (forcing_size, N); what each row means is the system's own business (for an
            energy model: the signals and their time derivatives the equations contain).
        """

    @abstractmethod
    def equations(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                  pvals: np.ndarray, damping: float = 1.0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The residual of the full equations and its partial derivatives at N samples.

        Parameters
        ----------
        q, qd, qdd : numpy.ndarray
            (n, N) absolute coordinates, velocities and accelerations.
        s : numpy.ndarray
            (forcing_size, N) the forcing (:meth:`forcing`; zeros for free vibration).
        pvals : numpy.ndarray
            The values of :attr:`parameters`.
        damping : float
            Factor on the dissipation (1: the model; 0: undamped).

        Returns
        -------
        tuple of numpy.ndarray
            E (n, N), dE/dq, dE/dq', dE/dq'' (n, n, N each; ``[i, j]`` = dE_i/dq_j).
        """

    @abstractmethod
    def output_values(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                      pvals: np.ndarray) -> dict[str, np.ndarray]:
        """The outputs at N samples, as deviations from their value at the reference state.

        Parameters
        ----------
        q, qd, qdd, s, pvals : numpy.ndarray
            As for :meth:`equations`.

        Returns
        -------
        dict
            ``name -> (N,)`` for every name of :attr:`outputs`.
        """

    @abstractmethod
    def base_frequency(self, pvals: np.ndarray) -> float:
        """The base frequency W (rad/s) of the periodic forcing.

        Parameters
        ----------
        pvals : numpy.ndarray
            The values of :attr:`parameters`.

        Returns
        -------
        float
            The largest common divisor of the forcing's frequencies.

        Raises
        ------
        AnalysisError
            When the forcing is not periodic (not harmonic, incommensurate, absent).
        """

    def dynamics(self, t: float | np.ndarray, q: np.ndarray, qd: np.ndarray,
                 pvals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The forced equations at time(s) t as ``mass q'' + rest = 0`` (for time integration).

        The default takes both from :meth:`forcing` and :meth:`equations` (the mass matrix
        is dE/dq'', the rest E at q'' = 0); a system may compile a cheaper kernel.

        Parameters
        ----------
        t : float or numpy.ndarray
            One time, or (N,) times.
        q, qd : numpy.ndarray
            (n,) at one time, or (n, N).
        pvals : numpy.ndarray
            The values of :attr:`parameters`.

        Returns
        -------
        tuple of numpy.ndarray
            mass (n, n) or (n, n, N), rest (n,) or (n, N).
        """
        one = np.ndim(q) == 1
        s = np.reshape(self.forcing(np.atleast_1d(t), pvals), (self.forcing_size, -1))
        q2, qd2 = np.reshape(q, (self.n, -1)), np.reshape(qd, (self.n, -1))
        E, _, _, mass = self.equations(q2, qd2, np.zeros_like(q2), s, pvals)
        return (mass[:, :, 0], E[:, 0]) if one else (mass, E)

    def parameter_point(self, param: str, value: float) -> np.ndarray:
        """All parameter values with ``param = value`` (its dependents follow).

        Parameters
        ----------
        param : str
            A name of :attr:`parameters`.
        value : float

        Returns
        -------
        numpy.ndarray
            The values of :attr:`parameters`, in that order.
        """
        if param not in self._dependent:
            probe = parameter_values(self.model, param, np.array([1.0, 2.0]))
            self._dependent[param] = any(
                np.ndim(v) and np.ptp(np.asarray(v, dtype=float)) != 0
                for k, v in probe.items() if k != param)
        if self._dependent[param]:
            values = parameter_values(self.model, param, np.array([value]))
            return np.array([float(np.asarray(values[k], dtype=float).ravel()[0])
                             for k in self.parameters])
        pvals = np.array(self.parameter_values, dtype=float)
        pvals[self.parameters.index(param)] = value
        return pvals

    @property
    def _dependent(self) -> dict[str, bool]:
        cache: dict[str, bool] | None = self.__dict__.get("_dependent_cache")
        if cache is None:
            cache = self.__dict__["_dependent_cache"] = {}
        return cache


def nonlinear_only(system: object, analysis: str) -> NonlinearSystem:
    """``system`` itself when it is a :class:`NonlinearSystem`, else the error that says how
    to make one: the analyses beyond small oscillations take the compiled system and
    nothing else (compiled once by :func:`resonant.system.nonlinear_system`, or by the
    model's own method, ``model.nonlinear_sweep(...)``, ``model.backbone(...)``).

    Parameters
    ----------
    system : object
        What the caller gave.
    analysis : str
        The analysis, for the message.

    Returns
    -------
    NonlinearSystem

    Raises
    ------
    AnalysisError
        For anything else (a model, its linear system).

    Examples
    --------
    >>> nonlinear_only(None, "backbone")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    resonant.errors.AnalysisError: backbone takes a NonlinearSystem, not NoneType: ...
    """
    if isinstance(system, NonlinearSystem):
        return system
    raise AnalysisError(f"{analysis} takes a NonlinearSystem, not {type(system).__name__}: "
                        "make it with resonant.system.nonlinear_system(model) (or call the "
                        "model's own method)")


def _stack_at(values: Sequence[Any], shape: tuple[int, ...]) -> np.ndarray:
    """Values of a lambdified list at one instant (shape ()) or at samples of ``shape``."""
    if not shape:  # one instant: every value is a scalar (the integrator's hot path)
        return np.array(values, dtype=float)
    return _stack(values, int(np.prod(shape))).reshape(len(values), *shape)


def _stack(values: Sequence[Any], count: int) -> np.ndarray:
    """Values of a lambdified list (scalars where an entry is constant) as (len, count)."""
    out = np.empty((len(values), count))
    for i, v in enumerate(values):  # scalars broadcast on assignment
        out[i] = v
    return out


def reference_values(model: Model, pvals: Mapping[str, float] | None = None) -> np.ndarray:
    """The ``[equilibrium]`` values of the coordinates (0 where not given)."""
    values = model.parameter_values if pvals is None else pvals
    out = []
    for c in model.coordinates:
        if c in model.equilibrium:
            out.append(float(model.equilibrium[c].to_sympy(
                lambda n, p: sympy.Float(float(values[n])) if p == 0 else 0)))
        else:
            out.append(0.0)
    return np.array(out, dtype=float)


def signal_function(model: Model, name: str, order: int) -> sympy.Expr:
    """d^order s/dt^order of a declared signal as a function of t and the parameters."""
    base = model.signals[name].to_sympy(lambda n, p: TIME if n == "t" else symbol(n))
    return sympy.diff(base, TIME, order) if order else base


def _base_frequency(model: Model) -> Callable[[np.ndarray], float]:
    """W(parameter values) = the largest common divisor of the signals' frequencies."""
    frequencies: list[sympy.Expr] = []
    for name, expression in model.signals.items():
        expr = expression.to_sympy(lambda n, p: TIME if n == "t" else symbol(n))
        try:
            parts = decompose(sympy.expand(expr))
        except NotHarmonic:
            message = (f"signal '{name}' is not a sum of harmonics: the excitation must be "
                       "periodic for a nonlinear steady state")
            return _raiser(message)
        frequencies.extend(w for w in parts if w != 0)
    if not frequencies:
        return _raiser("nothing excites the model periodically (no harmonic signal): there "
                       "is no forced periodic steady state to follow")
    params = [symbol(n) for n in model.parameters]
    compiled = sympy.lambdify(params, [compilable(w) for w in frequencies], modules="numpy")

    ratio: list[tuple[int, int]] = []  # (index of the lowest, denominator), at first use

    def base(pvals: np.ndarray) -> float:
        if not ratio:
            values = np.abs(np.array(compiled(*pvals), dtype=float))
            lowest = float(values.min())
            if not lowest > 0:
                raise AnalysisError("an excitation frequency is zero at the start value")
            fractions = [Fraction(v / lowest).limit_denominator(1000) for v in values]
            if any(abs(float(f) - v / lowest) > 1e-9 * v / lowest
                   for f, v in zip(fractions, values)):
                raise AnalysisError("the excitation frequencies are not commensurate: the "
                                    "excitation is not periodic")
            ratio.append((int(np.argmin(values)),
                          reduce(math.lcm, (f.denominator for f in fractions), 1)))
        index, denominator = ratio[0]
        return abs(float(compiled(*pvals)[index])) / denominator
    return base


def _raiser(message: str) -> Callable[[np.ndarray], float]:
    def base(pvals: np.ndarray) -> float:
        raise AnalysisError(message)
    return base


class EnergySystem(NonlinearSystem):
    """The full Lagrange equations of a model given by its energies, compiled once.

    Parameters
    ----------
    model : Model
        A model given by its energies.
    linear : LinearSystem
        Its linear system at the reference state.

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import nonlinear_system
    >>> system = nonlinear_system(resonant.load("examples/duffing.toml"))
    >>> type(system).__name__, system.coordinates
    ('EnergySystem', ('x',))
    """

    def __init__(self, model: Model, linear: LinearSystem) -> None:
        self.model, self.linear = model, linear
        self.coordinates = tuple(model.coordinates)
        self.parameters = tuple(model.parameters)
        self.parameter_values = np.array([float(model.parameter_values[k])
                                          for k in self.parameters])
        eq = nonlinear_equations(model)
        params = [symbol(k) for k in self.parameters]
        outputs, unsupported = self._fold_outputs(eq)
        # folding the outputs may register more signal derivatives: collect them last
        signal_keys = sorted({v for v in eq.ops.registry.values() if v[0] in model.signals})
        signals = [eq.ops.dvar(name, order) for name, order in signal_keys]
        self.forcing_size = len(signals)
        dissipation = eq.dissipation if eq.dissipation is not None else \
            sympy.zeros(len(self.coordinates), 1)
        E = eq.mass * sympy.Matrix(eq.qdd) + eq.rest + (_DAMPING - 1) * dissipation
        exprs = [*E, *E.jacobian(eq.q), *E.jacobian(eq.qd), *E.jacobian(eq.qdd)]
        self._equations = sympy.lambdify(
            [*eq.q, *eq.qd, *eq.qdd, *params, *signals, _DAMPING],
            [compilable(e) for e in exprs], modules="numpy", cse=True)
        forced = {symbol_: signal_function(model, name, order)
                  for symbol_, (name, order) in zip(signals, signal_keys)}
        self._dynamics = sympy.lambdify(
            [TIME, *eq.q, *eq.qd, *params],
            [compilable(sympy.sympify(e).xreplace(forced)) for e in [*eq.mass, *eq.rest]],
            modules="numpy", cse=True)
        self._forcing = sympy.lambdify(
            [TIME, *params], [compilable(signal_function(model, name, order))
                              for name, order in signal_keys] or [0], modules="numpy",
            cse=True)
        self.outputs = tuple(outputs)
        self.unsupported_outputs = tuple(unsupported)
        self._outputs = sympy.lambdify(
            [*eq.q, *eq.qd, *eq.qdd, *params, *signals],
            [compilable(e) for e in outputs.values()] or [0], modules="numpy", cse=True)
        self._base = _base_frequency(model)
        self._reference = reference_values(model)
        self._output_reference = self._outputs_at_rest()

    def _fold_outputs(self, eq: NonlinearEquations) -> tuple[dict[str, sympy.Expr], list[str]]:
        """The outputs in full; those with a coordinate derivative of order > 2 apart."""
        model = self.model
        coordinates = set(model.coordinates)
        outputs: dict[str, sympy.Expr] = {}
        unsupported: list[str] = []
        for name, expression in model.outputs.items():
            if any(v in coordinates and p > 2 for v, p in expression.names()):
                unsupported.append(name)
                continue
            full = sympy.sympify(eq.ops.expr(expression))
            if any(s in eq.ops.registry and eq.ops.registry[s][0] in coordinates
                   and eq.ops.registry[s][1] > 2 for s in full.free_symbols):
                unsupported.append(name)
                continue
            outputs[name] = full
        return outputs, unsupported

    def _outputs_at_rest(self) -> dict[str, float]:
        """Each output at the reference state, velocities and signals zero."""
        q = self._reference[:, None]
        zero = np.zeros((self.n, 1))
        s = np.zeros((self.forcing_size, 1))
        with np.errstate(all="ignore"):
            raw = self._outputs(*q, *zero, *zero, *self.parameter_values, *s)
        values = _stack(raw, 1)[:, 0]
        return {name: float(v) for name, v in zip(self.outputs, values)}

    def reference(self, pvals: np.ndarray) -> np.ndarray:
        if np.array_equal(pvals, self.parameter_values):
            return self._reference.copy()
        return reference_values(self.model, dict(zip(self.parameters, map(float, pvals))))

    def forcing(self, t: np.ndarray, pvals: np.ndarray) -> np.ndarray:
        if not self.forcing_size:
            return np.zeros((0, *np.shape(t)))
        return _stack_at(self._forcing(t, *pvals), np.shape(t))

    def dynamics(self, t: float | np.ndarray, q: np.ndarray, qd: np.ndarray, pvals: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
        n, shape = self.n, np.shape(q)[1:]
        with np.errstate(all="ignore"):
            values = _stack_at(self._dynamics(t, *q, *qd, *pvals), shape)
        return values[:n * n].reshape(n, n, *shape), values[n * n:]

    def equations(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                  pvals: np.ndarray, damping: float = 1.0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        n, count = self.n, q.shape[1]
        with np.errstate(all="ignore"):
            raw = self._equations(*q, *qd, *qdd, *pvals, *s, damping)
        values = _stack(raw, count)
        G = values[n:].reshape(3, n, n, count)
        return values[:n], G[0], G[1], G[2]

    def output_values(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                      pvals: np.ndarray) -> dict[str, np.ndarray]:
        if not self.outputs:
            return {}
        with np.errstate(all="ignore"):
            values = _stack(self._outputs(*q, *qd, *qdd, *pvals, *s), q.shape[1])
        return {name: values[i] - self._output_reference[name]
                for i, name in enumerate(self.outputs)}

    def base_frequency(self, pvals: np.ndarray) -> float:
        return self._base(pvals)


__all__ = ["LocalElements", "NonlinearSystem", "EnergySystem", "reference_values",
           "signal_function"]
