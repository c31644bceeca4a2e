"""A ``[matrices]`` model with ``[[nonlinear]]`` elements as a :class:`NonlinearSystem`.

The full equations of such a model are its matrices plus the elements' local forces::

    E = M q'' + d C q' + K q + f_nl(q, q') - Q(t) = 0,

``Q(t)`` the load of its harmonics at the parameter values, ``d`` the factor on the
dissipation (0 for backbone curves: it scales C; an element's own velocity dependence
is the element's and is kept).  :class:`ElementSystem` implements the
:class:`~resonant.system.nonlinear.NonlinearSystem` interface with them, so that the
time integration, the periodic solution, the backbone curves and the slow sweep take
a matrix model with elements as they take a model given by its energies.  Harmonic
balance chooses the condensation onto the elements' coordinates for it
(:func:`resonant.analyses.harmonic_balance.nonlinear_sweep`); the full interface works
with dense (n, n, N) derivatives and is bounded to :data:`MAX_FULL_COORDINATES`.

A friction (Jenkins) element's force depends on the history of the motion, not on the
state at one instant: it has no such equations, and only the condensed balance takes it.

Examples
--------
>>> import numpy as np
>>> from resonant.model import loads
>>> from resonant.system import nonlinear_system
>>> system = nonlinear_system(loads('''
... [parameters]
... k3 = 2
... [matrices]
... M = [[1]]
... K = [[4]]
... [[nonlinear]]
... coordinates = ["q1"]
... force = "k3*q1^3"
... '''))
>>> q, zero = np.array([[0.5]]), np.zeros((1, 1))
>>> E, dq, _, mass = system.equations(q, zero, zero, zero, system.parameter_values)
>>> float(E[0, 0]), float(dq[0, 0, 0]), float(mass[0, 0, 0])
(2.25, 5.5, 1.0)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from functools import reduce

import numpy as np

from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError
from ..expressions import numeric_value
from ..model.nonlinear_elements import NonlinearElement
from .base import LinearSystem, NumericEOM, numeric_point
from .matrix_outputs import MAX_RATE, OutputSeries
from .nonlinear import LocalElements, NonlinearSystem
from .nonlinear_elements import ElementForces

#: the full equations keep dense (n, n, N) derivatives: larger models take the condensed
#: balance (docs/nonlinear.md)
MAX_FULL_COORDINATES = 400
#: parameter points whose matrices are kept (a continuation revisits the last few)
CACHED_POINTS = 4


class ElementSystem(NonlinearSystem):
    """The full equations of a ``[matrices]`` model with ``[[nonlinear]]`` elements.

    Parameters
    ----------
    linear : LinearSystem
        The model's linear system (its matrices and load).
    deadline : Deadline, optional
        Checked while the matrices are evaluated.

    Raises
    ------
    AnalysisError
        For a friction element (its force has a history) or more than
        :data:`MAX_FULL_COORDINATES` coordinates.

    Examples
    --------
    See the module docstring.
    """

    def __init__(self, linear: LinearSystem, deadline: Deadline = NO_DEADLINE) -> None:
        model = linear._model()
        assert model.matrices is not None
        self.model, self.linear = model, linear
        self.coordinates = linear.coordinates
        self.parameters = tuple(model.parameters)
        self.parameter_values = np.array([model.parameter_values[p] for p in self.parameters])
        self.forcing_size = linear.n
        series = OutputSeries(model.outputs, self.coordinates, model.source)
        self.outputs, self._series = series.names, series
        self._forces = ElementForces(model.matrices.nonlinear, model.parameter_values)
        self._dofs = np.array(self._forces.dofs, dtype=int)
        self._cache: dict[tuple[float, ...], NumericEOM] = {}
        self._points: dict[tuple[float, ...], NumericEOM] = {}
        self._harmonics = model.matrices.harmonics
        self.local_elements = LocalElements(linear, tuple(model.matrices.nonlinear),
                                            self.element_forces, self.harmonic_frequencies,
                                            series if model.outputs else None)
        self._full = _full_equations_problem(linear.n, model.matrices.nonlinear)
        if self._full is None:
            self._numbers(self.parameter_values, deadline)
        else:
            self._point(self.parameter_values, deadline)

    def _require_full(self) -> None:
        if self._full is not None:
            raise AnalysisError(self._full)

    def _point(self, pvals: np.ndarray, deadline: Deadline = NO_DEADLINE) -> NumericEOM:
        """The matrices (as given: sparse stays sparse) and the load at the parameter
        values (cached)."""
        key = tuple(float(v) for v in pvals)
        num = self._points.pop(key, None)
        if num is None:  # the values as they are (no parsing): every parameter is given
            values = dict(zip(self.parameters, key))
            num = numeric_point(self.linear.evaluate(values, 1, deadline), 0, self.linear,
                                values)
        self._points[key] = num  # the most recent last; a sweep keeps the last few only
        while len(self._points) > CACHED_POINTS:
            del self._points[next(iter(self._points))]
        return num

    def _numbers(self, pvals: np.ndarray, deadline: Deadline = NO_DEADLINE) -> NumericEOM:
        """The matrices and the load at the parameter values, dense (cached): the full
        equations' (bounded to :data:`MAX_FULL_COORDINATES`)."""
        self._require_full()
        key = tuple(float(v) for v in pvals)
        num = self._cache.pop(key, None)
        if num is None:
            num = self._point(pvals, deadline).dense()
        self._cache[key] = num
        while len(self._cache) > CACHED_POINTS:
            del self._cache[next(iter(self._cache))]
        return num

    def element_forces(self, pvals: np.ndarray) -> ElementForces:
        """The elements' forces and tangents at the parameter values."""
        return self._forces.with_parameters(dict(zip(self.parameters, (float(v)
                                                                      for v in pvals))))

    def harmonic_frequencies(self, pvals: np.ndarray) -> np.ndarray:
        """The angular frequency of each ``[[harmonic]]`` load at the parameter values
        (their expressions alone: no matrix is evaluated)."""
        values = dict(zip(self.parameters, (float(v) for v in pvals)))
        return np.array([float(numeric_value(h.omega, values)) for h in self._harmonics])

    def reference(self, pvals: np.ndarray) -> np.ndarray:
        return np.zeros(self.n)

    def forcing(self, t: np.ndarray, pvals: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        out = np.zeros((self.n, *t.shape))
        for h in self._point(pvals).harmonics:
            phase = h.omega * t
            out = out + np.multiply.outer(h.F_C, np.cos(phase)) \
                + np.multiply.outer(h.F_S, np.sin(phase))
        return out

    def equations(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                  pvals: np.ndarray, damping: float = 1.0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        num = self._numbers(pvals)
        M, C, K = (np.asarray(a, dtype=float) for a in (num.M, num.C, num.K))
        count = q.shape[1]
        E = M @ qdd + damping * (C @ qd) + K @ q - s
        dq = np.repeat(K[:, :, None], count, axis=2)
        dqd = np.repeat(damping * C[:, :, None], count, axis=2)
        mass = np.repeat(M[:, :, None], count, axis=2)
        forces = self.element_forces(pvals)
        F, G0, G1 = forces.forces_and_tangent(q[self._dofs], qd[self._dofs])
        E[self._dofs] += F
        block = np.ix_(self._dofs, self._dofs)
        dq[block] += G0
        dqd[block] += G1
        return E, dq, dqd, mass

    def output_values(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                      pvals: np.ndarray) -> dict[str, np.ndarray]:
        if not self.outputs:
            return {}
        index = [self.coordinates.index(c) for c in self._series.coordinates]
        samples = np.stack([q[index], qd[index], qdd[index]])[:MAX_RATE + 1]
        values = dict(zip(self.parameters, (float(v) for v in pvals)))
        at = self._series(samples, values)
        rest = self._series(np.zeros((*samples.shape[:2], 1)), values)
        return {name: at[i] - rest[i, 0] for i, name in enumerate(self.outputs)}

    def base_frequency(self, pvals: np.ndarray) -> float:
        omegas = [abs(h.omega) for h in self._point(pvals).harmonics if h.omega != 0]
        if not omegas:
            raise AnalysisError("nothing excites the model periodically (no harmonic load): "
                                "there is no forced periodic steady state to follow")
        lowest = min(omegas)
        fractions = [Fraction(w / lowest).limit_denominator(1000) for w in omegas]
        if any(abs(float(f) - w / lowest) > 1e-9 * w / lowest
               for f, w in zip(fractions, omegas)):
            raise AnalysisError("the excitation frequencies are not commensurate: the "
                                "excitation is not periodic")
        return lowest / reduce(math.lcm, (f.denominator for f in fractions), 1)



def _full_equations_problem(n: int, elements: Sequence[NonlinearElement]) -> str | None:
    """Why a matrix model with these elements has no full equations of motion (None: it
    has them): too many coordinates for dense derivatives, or a friction element."""
    if n > MAX_FULL_COORDINATES:
        return (f"the full equations of a [matrices] model with [[nonlinear]] elements are "
                f"kept for up to {MAX_FULL_COORDINATES} coordinates, not {n}: its periodic "
                "response is computed by the balance condensed onto the elements")
    friction = [e.name for e in elements if e.kind == "friction"]
    if friction:
        return (f"[nonlinear '{friction[0]}'] the force of a friction element depends on the "
                "history of the motion: only the harmonic balance condensed onto the "
                "elements takes it (not the time integration nor the backbone curves)")
    return None


__all__ = ["ElementSystem", "MAX_FULL_COORDINATES"]
