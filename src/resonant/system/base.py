"""The one linear-system type that every analysis takes.

:class:`LinearSystem` is M q'' + C q' + K q = Q(t) about the reference state of
a model, with three implementations:

* :class:`~resonant.system.symbolic.LinearEOM` -- derived from energies, entries in
  the model's own symbols;
* :class:`~resonant.system.matrix.MatrixEOM` -- a ``[matrices]`` model (inline
  expressions or matrix files, dense or sparse);
* :class:`~resonant.system.base.NumericEOM` -- numbers at one parameter point
  (what :meth:`LinearSystem.numeric` returns; also a system in its own right).

Every analysis asks the system for numbers in one of two ways:
:meth:`numeric` (one parameter point) or :meth:`batch` (a parameter running
through an array of values, for sweeps).  The analyses never look at which
kind of system they hold.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import Matrix, frozen_array
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem
from ..expressions import numeric_value
from ..expressions.notation import (
    column_latex,
    matrix_latex,
    name_latex,
    number_latex,
    vector_latex,
)
from ..memory import dense_matrix, require
from ..model import Model
from ..model.matrix_spec import MatrixSpec
from ..model.options import SweepOptions
from ..model.rotor import Bearing
from .batch import Batch, BatchHarmonic, Var, group_frequencies
from .latex import SymbolicEquations

if TYPE_CHECKING:
    from ..analyses.modes import ModalAnalysis
    from ..analyses.random_response import RandomResponse
    from ..analyses.state_space import StateSpaceModel
    from ..analyses.stationary import StationarySolution
    from ..analyses.sweep import FrequencyResponse
    from ..model.random_spec import RandomSpec


class LinearSystem(ABC):
    """M q'' + C q' + K q = Q(t): the interface every analysis uses.

    Attributes
    ----------
    coordinates : tuple of str
        The generalized coordinates, in order.
    model : Model or None
        The model it comes from (None for a bare :class:`NumericEOM`).

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> isinstance(eom, LinearSystem), eom.coordinates
    (True, ('x1', 'x2'))
    """

    coordinates: tuple[str, ...]
    model: Model | None

    @property
    def n(self) -> int:
        """The number of coordinates."""
        return len(self.coordinates)

    @property
    def title(self) -> str:
        """The model's title ("" without a model)."""
        return self.model.title if self.model is not None else ""

    @property
    def source(self) -> str:
        """The model file ("" without a model)."""
        return self.model.source if self.model is not None else ""

    @property
    def speed(self) -> str | None:
        """The parameter that is a rotor's spin speed, as its ``[matrices]`` (or the
        ``[rotor]`` it assembles) names it (docs/rotors.md); None where it names none."""
        spec = self.given_matrices
        return spec.speed if spec is not None else None

    @property
    def given_matrices(self) -> MatrixSpec | None:
        """The ``[matrices]`` as given (M, C, K, G and the speed's terms before any
        parameter is set), for an analysis that solves for a parameter inside them (the
        undamped critical speed map solves for the speed); None for a system derived from
        energies or made of numbers."""
        return self.model.matrices if self.model is not None else None

    @property
    def bearings(self) -> tuple[Bearing, ...]:
        """A ``[rotor]``'s bearings, each with its stiffness and damping at the speed
        (:class:`resonant.model.rotor.Bearing`); () for a system without them."""
        spec = self.given_matrices
        return tuple(spec.bearings) if spec is not None else ()

    # -- numbers ---------------------------------------------------------------------------
    @abstractmethod
    def evaluate(self, values: Mapping[str, Any], count: int,
                 deadline: Deadline = NO_DEADLINE) -> Batch:
        """Every matrix, load and output coefficient for the parameter ``values``.

        Parameters
        ----------
        values : mapping
            Every parameter's value: a float, or an array of ``count`` values.
        count : int
            The number of parameter points.
        deadline : Deadline, optional

        Returns
        -------
        Batch
        """

    def numeric(self, deadline: Deadline = NO_DEADLINE, **overrides: float | str
                ) -> NumericEOM:
        """The equation of motion with the parameter values substituted.

        Parameters
        ----------
        deadline : Deadline, optional
        **overrides
            Parameter values replacing the model's (numbers or expression text).

        Returns
        -------
        NumericEOM
        """
        model = self._model()
        if overrides:
            model = model.with_parameters(**overrides)
        values = dict(model.parameter_values)
        return numeric_point(self.evaluate(values, 1, deadline), 0, self, values)

    def batch(self, param: str, values: np.ndarray, deadline: Deadline = NO_DEADLINE
              ) -> Batch:
        """The system while ``param`` runs through ``values`` (parameters defined from it
        follow it).

        Parameters
        ----------
        param : str
            A parameter of the model.
        values : ndarray
            Its values, shape (N,).
        deadline : Deadline, optional

        Returns
        -------
        Batch
        """
        values = np.asarray(values, dtype=float)
        return self.evaluate(parameter_values(self._model(), param, values), len(values),
                             deadline)

    def parameters_along(self, param: str, values: np.ndarray) -> dict[str, Any]:
        """Every parameter's value with ``param`` set to the array ``values``
        (:func:`parameter_values` of the model), for what is evaluated beside the matrices
        (a bearing's speed-dependent coefficients).

        Parameters
        ----------
        param : str
        values : ndarray

        Returns
        -------
        dict of str to float or ndarray
        """
        return parameter_values(self._model(), param, values)

    def parameter_samples(self, varied: Mapping[str, np.ndarray | float], count: int
                          ) -> tuple[dict[str, Any], np.ndarray, list[str]]:
        """Every parameter's values at ``count`` points with ``varied`` set, the parameters
        defined from them following (:func:`sample_parameters`).

        Parameters
        ----------
        varied : mapping
            parameter -> an array of ``count`` values, or a number shared by all.
        count : int
            The number of points.

        Returns
        -------
        tuple
            The values (name -> float or array), the mask of the points where a dependent
            parameter is not finite, and a reason for each such point.
        """
        return sample_parameters(self._model(), varied, count)

    def random_response(self, spec: RandomSpec | None = None, deadline: Deadline = NO_DEADLINE,
                        *, names: Sequence[str] | None = None, method: str = "auto",
                        tolerance: float | None = None) -> RandomResponse:
        """The response spectral densities, RMS values and Rice's rates under random inputs
        (:func:`resonant.analyses.random_response.random_response`; docs/random.md).

        Parameters
        ----------
        spec : RandomSpec, optional
            The random inputs (default: the model's ``[random]`` section).
        deadline : Deadline, optional
            The run's time limit.
        names : sequence of str, optional
            The coordinates and outputs to report (default all).
        method : str
            The harmonic solve's method (as for :meth:`sweep`).
        tolerance : float, optional
            Relative accuracy of the RMS values.

        Returns
        -------
        RandomResponse

        Examples
        --------
        >>> import resonant
        >>> eom = resonant.load("examples/shaker_gevs.toml").linearize()
        >>> result = eom.random_response()
        >>> all(value > 0 for value in result.rms.values())
        True
        """
        from ..analyses.random_response import random_response
        return random_response(self, spec, deadline, names=names, method=method,
                                               tolerance=tolerance)

    def state_space(self, *, inputs: Sequence[str] | None = None,
                    outputs: Sequence[str] | None = None,
                    parameters: Mapping[str, float | str] | None = None,
                    deadline: Deadline = NO_DEADLINE) -> StateSpaceModel:
        """The first-order form x' = A x + B u, y = C x + D u with named inputs and outputs
        (:func:`resonant.analyses.state_space.state_space`; docs/interop.md).

        Parameters
        ----------
        inputs : sequence of str, optional
            Signals, or coordinates a generalized force acts on (default: the signals).
        outputs : sequence of str, optional
            Coordinates, their rates (``x1'``) and outputs (default: coordinates and outputs).
        parameters : mapping, optional
            Parameter values replacing the model's.
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        StateSpaceModel

        Examples
        --------
        >>> import resonant
        >>> eom = resonant.load("examples/base_excitation.toml").linearize()
        >>> eom.state_space().inputs
        ('y',)
        """
        from ..analyses.state_space import state_space
        return state_space(self, inputs=inputs, outputs=outputs, parameters=parameters,
                           deadline=deadline)

    def to_state_space(self, *, inputs: Sequence[str] | None = None,
                       outputs: Sequence[str] | None = None,
                       parameters: Mapping[str, float | str] | None = None,
                       library: str = "auto", deadline: Deadline = NO_DEADLINE) -> Any:
        """The system as a python-control ``StateSpace`` with named inputs, states and
        outputs, or a ``scipy.signal.StateSpace``
        (:func:`resonant.analyses.state_space.to_state_space`; docs/interop.md).

        Parameters
        ----------
        inputs : sequence of str, optional
            Signals, or coordinates a generalized force acts on (default: the signals).
        outputs : sequence of str, optional
            Coordinates, their rates (``x1'``) and outputs (default: coordinates and outputs).
        parameters : mapping, optional
            Parameter values replacing the model's.
        library : {"auto", "control", "scipy"}
            Which library's system (``"auto"``: python-control where installed).
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        control.StateSpace or scipy.signal.StateSpace

        Examples
        --------
        >>> import resonant
        >>> eom = resonant.load("examples/base_excitation.toml").linearize()
        >>> eom.to_state_space(library="scipy").B.shape
        (2, 1)
        """
        from ..analyses.state_space import to_state_space
        return to_state_space(self, inputs=inputs, outputs=outputs, parameters=parameters,
                              library=library, deadline=deadline)

    def _model(self) -> Model:
        if self.model is None:
            raise ModelError("this system has no model: its parameters cannot change")
        return self.model

    def to_dict(self) -> dict[str, Any]:
        """The JSON form of the equation of motion (coordinates, M, C, K, Q as text).

        Returns
        -------
        dict
        """
        return {}

    def symbolic_dict(self) -> dict[str, Any] | None:
        """The symbolic form for the JSON of a solution, where it says more than the
        numbers (derived equations); None for given matrices.

        Returns
        -------
        dict or None
        """
        return None

    def symbolic(self) -> SymbolicEquations | None:
        """This system's equations in symbols (M, C, K, Q(t), the excitation's columns, the
        signals as functions of time, the outputs), or None for a system of numbers only.

        Returns
        -------
        SymbolicEquations or None
        """
        return None

    def derived_matrices(self) -> tuple[Any, Any, Any, Any] | None:
        """The symbolic M, C, K and Q(t) where Lagrange's equations derived them (a model
        given by its energies), for a text that shows where the numbers come from; None for
        given matrices and for numbers.

        Returns
        -------
        tuple of sympy.ImmutableMatrix, or None
        """
        return None

    def stationary(self, deadline: Deadline = NO_DEADLINE, **overrides: float | str
                   ) -> StationarySolution:
        """The stationary solution for harmonic excitation
        (:func:`resonant.analyses.stationary.stationary`).

        Parameters
        ----------
        deadline : Deadline, optional
            The run's time limit.
        **overrides
            Parameter values replacing the model's (numbers or expression text).

        Returns
        -------
        StationarySolution

        Examples
        --------
        >>> import resonant
        >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
        >>> round(eom.stationary().amplitudes["x2"], 5), round(eom.stationary(k=120).amplitudes[
        ...     "x2"], 5) != 0.04514
        (0.04514, True)
        """
        from ..analyses.stationary import stationary
        return stationary(self, deadline, **overrides)

    def modes(self, count: int | None = None, deadline: Deadline = NO_DEADLINE
              ) -> ModalAnalysis:
        """Natural frequencies, mode shapes, damping ratios
        (:func:`resonant.analyses.modes.modes`).

        Parameters
        ----------
        count : int, optional
            Only the ``count`` lowest modes.
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        ModalAnalysis

        Examples
        --------
        >>> import resonant
        >>> eom = resonant.load("examples/two_dof_free.toml").linearize()
        >>> eom.modes().natural_frequencies.round(3).tolist()
        [20.0, 34.641]
        """
        from ..analyses.modes import modes
        return modes(self, count, deadline)

    def sweep(self, param: str, values: Sequence[float] | np.ndarray, *, method: str = "auto",
              names: Sequence[str] | None = None, progress: bool | None = None,
              log: bool | None = None, deadline: Deadline = NO_DEADLINE,
              tol: float | None = None, options: SweepOptions | None = None
              ) -> FrequencyResponse:
        """Amplitudes and phases against a parameter (:func:`resonant.analyses.sweep.sweep`,
        where the options are described).

        Parameters
        ----------
        param : str
            The parameter to vary.
        values : array_like
            Its values.
        method : {"auto", "direct", "dense", "banded", "sparse", "modal", "reduced"}
            How to solve.
        names : sequence of str, optional
            The coordinates to report (default all).
        progress : bool, optional
            A progress bar on standard error.
        log : bool, optional
            Whether the values are logarithmically spaced.
        deadline : Deadline, optional
            The run's time limit.
        tol : float, optional
            Relative tolerance of a reduced model.
        options : SweepOptions, optional
            The options above (but ``deadline``) as one record, instead of keywords.

        Returns
        -------
        FrequencyResponse

        Examples
        --------
        >>> import resonant
        >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
        >>> eom.sweep("omega", [10.0, 20.0]).values.tolist()
        [10.0, 20.0]
        """
        from ..analyses.sweep import sweep
        return sweep(self, param, values, method=method, names=names, progress=progress,
                           log=log, deadline=deadline, tol=tol, options=options)


def sample_parameters(model: Model, varied: Mapping[str, np.ndarray | float], count: int
                      ) -> tuple[dict[str, Any], np.ndarray, list[str]]:
    """Every parameter's values with ``varied`` set (arrays of ``count``, or numbers shared
    by all); parameters defined from them follow.

    Returns the values, the mask of samples where a dependent parameter is not
    finite, and a reason for each such sample.

    Examples
    --------
    >>> from resonant.model import loads
    >>> model = loads('[parameters]\\nk = 1\\nk2 = "2*k"\\n[matrices]\\nM = [[1]]\\n'
    ...               'K = [["k2"]]\\n')
    >>> values, bad, _ = sample_parameters(model, {"k": np.array([1.0, 3.0])}, 2)
    >>> values["k2"].tolist(), bad.tolist()
    ([2.0, 6.0], [False, False])
    """
    out: dict[str, Any] = {}
    bad = np.zeros(count, dtype=bool)
    reasons = [""] * count
    for name, expression in model.parameters.items():
        if name in varied:  # a value shared by every point stays a number
            given = np.asarray(varied[name], dtype=float)
            out[name] = given if given.ndim else float(given)
        elif any(n in varied or isinstance(out.get(n), np.ndarray)
                 for n, _ in expression.names()):
            with np.errstate(all="ignore"):
                raw = np.asarray(numeric_value(expression, out), dtype=float)
            value = np.broadcast_to(raw, (count,)).copy()
            wrong = ~np.isfinite(value) & ~bad
            for i in np.flatnonzero(wrong):
                reasons[i] = f"{name} = {expression.text} is not finite"
            bad |= wrong
            value[wrong] = model.parameter_values[name]
            out[name] = value if raw.ndim else float(value[0])
        else:
            out[name] = model.parameter_values[name]
    return out, bad, reasons


def parameter_values(model: Model, param: str, values: np.ndarray,
                     base: Mapping[str, float] | None = None) -> dict[str, Any]:
    """Every parameter's value with ``param`` set to the array ``values``.

    Parameters defined by expressions of ``param`` follow it (evaluated
    elementwise); the others keep the model's values exactly.

    Parameters
    ----------
    model : Model
    param : str
        The parameter that varies.
    values : ndarray
        Its values.
    base : mapping, optional
        The values of the other parameters (default: the model's).

    Returns
    -------
    dict
        name -> float or ndarray.

    Raises
    ------
    ModelError
        For an unknown parameter, or a dependent parameter that is not finite.

    Examples
    --------
    >>> import numpy as np, resonant
    >>> model = resonant.load("examples/two_dof_free.toml")
    >>> parameter_values(model, "k", np.array([1.0, 2.0]))["k2"].tolist()
    [1.0, 2.0]
    """
    if param not in model.parameters:
        import difflib

        close = difflib.get_close_matches(param, list(model.parameters), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else \
            f"; the parameters are {', '.join(list(model.parameters)[:20]) or 'none'}"
        raise ModelError(Problem(f"cannot sweep unknown parameter '{param}'{hint}",
                                 model.source, "parameters", param))
    out: dict[str, Any] = {}
    varying = {param}
    for name, expression in model.parameters.items():
        if name == param:
            out[name] = values
        elif any(n in varying for n, _ in expression.names()):
            value = np.broadcast_to(np.asarray(numeric_value(expression, out), dtype=float),
                                    values.shape)
            bad = ~np.isfinite(value)
            if bad.any():
                raise ModelError(Problem(
                    f"{name} = {expression.text} is not finite for {param} = "
                    f"{values[np.argmax(bad)]:.6g}", model.source, "parameters", name))
            out[name] = value
            varying.add(name)
        else:
            out[name] = (base or model.parameter_values)[name]
    return out



@dataclass(frozen=True)
class NumericHarmonic:
    """One excitation frequency: Q = F_S sin(omega t) + F_C cos(omega t).

    ``signals`` holds the (S, C) pair of every signal derivative at this
    frequency (needed for outputs that depend on signals). ``omega = 0`` is a
    static load (F_C only).

    Parameters
    ----------
    omega : float
        The circular frequency (rad/s).
    F_S, F_C : ndarray
        Sine and cosine amplitudes of the generalized forces, shape (n,).
    signals : mapping
        ``(signal, order)`` -> (S, C) at this frequency.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> eom.numeric().harmonics[-1].omega
    20.0
    """

    omega: float
    F_S: np.ndarray
    F_C: np.ndarray
    signals: Mapping[Var, tuple[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "F_S", frozen_array(np.asarray(self.F_S, dtype=float)))
        object.__setattr__(self, "F_C", frozen_array(np.asarray(self.F_C, dtype=float)))


@dataclass(frozen=True)
class NumericOutput:
    """A linearized output y = value + sum coefficient * (coordinate or signal derivative).

    Parameters
    ----------
    value : float
        The output at the reference state.
    terms : mapping
        ``(name, order)`` -> coefficient.

    Examples
    --------
    >>> NumericOutput(0.0, {("x2", 0): 2.0}).terms[("x2", 0)]
    2.0
    """

    value: float
    terms: Mapping[Var, float]


@dataclass(frozen=True, eq=False)
class NumericEOM(LinearSystem):
    """M q'' + C q' + K q = Q(t) with numbers (dense arrays or scipy sparse matrices).

    Attributes
    ----------
    coordinates : tuple of str
        The generalized coordinates, in order.
    M, C, K : ndarray or sparse matrix
        Mass, damping and stiffness, (n, n).
    title_, source_ : str
        The model's title and file (``title`` and ``source`` read them).
    harmonics : tuple of NumericHarmonic
        The excitation, grouped by frequency (ascending).
    harmonic : bool
        False when some signal is not a sum of harmonics (no stationary solution).
    outputs : mapping
        name -> NumericOutput.
    parameters : mapping
        The parameter values these numbers are for.
    system : LinearSystem or None
        The system these numbers were evaluated from.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> num = eom.numeric()
    >>> num.M.tolist(), num.K.tolist()
    ([[3.0, 0.5], [0.5, 0.3333333333333333]], [[100.0, 0.0], [0.0, 9.81]])
    """

    coordinates: tuple[str, ...]
    M: Matrix
    C: Matrix
    K: Matrix
    harmonics: tuple[NumericHarmonic, ...] = ()
    harmonic: bool = True
    outputs: Mapping[str, NumericOutput] = field(default_factory=dict)
    parameters: Mapping[str, float] = field(default_factory=dict)
    title_: str = ""
    source_: str = ""
    system: LinearSystem | None = None

    def __post_init__(self) -> None:
        for key in ("M", "C", "K"):
            object.__setattr__(self, key, frozen_array(getattr(self, key)))

    @property
    def model(self) -> Model | None:  # type: ignore[override]
        return self.system.model if self.system is not None else None

    @property
    def title(self) -> str:
        return self.title_ or (self.system.title if self.system is not None else "")

    @property
    def source(self) -> str:
        return self.source_ or (self.system.source if self.system is not None else "")

    @property
    def sparse(self) -> bool:
        """True when M, C or K is a scipy sparse matrix."""
        return any(hasattr(a, "tocsr") for a in (self.M, self.C, self.K))

    def dense(self) -> NumericEOM:
        """The same system with dense M, C, K (itself when they are dense); refused
        (AnalysisError) where the three would be above the memory budget."""
        if not self.sparse:
            return self
        n = len(self.coordinates)
        require(3.0 * 8 * n * n, f"dense M, C and K of {n} coordinates",
                "this analysis works on dense matrices; modes (with a count), sweep and "
                "random take the sparse ones, or reduce the model")
        return replace(self, M=dense_matrix(self.M), C=dense_matrix(self.C), K=dense_matrix(self.K))

    def evaluate(self, values: Mapping[str, Any], count: int,
                 deadline: Deadline = NO_DEADLINE) -> Batch:
        return self.constant_batch(count)

    def numeric(self, deadline: Deadline = NO_DEADLINE, **overrides: float | str
                ) -> NumericEOM:
        if not overrides:
            return self
        if self.system is None:
            raise ModelError("a numeric system without its model cannot change its parameters")
        return self.system.numeric(deadline, **{**dict(self.parameters), **overrides})

    def batch(self, param: str, values: np.ndarray, deadline: Deadline = NO_DEADLINE
              ) -> Batch:
        values = np.asarray(values, dtype=float)
        if self.system is not None and self.system.model is not None:
            return self.system.evaluate(parameter_values(self.system.model, param, values,
                                                         base=self.parameters),
                                        len(values), deadline)
        moving = [h for h in self.harmonics if h.omega > 0]
        if param != "omega" or len(moving) != 1:
            raise AnalysisError(
                "without its model, a numeric equation of motion can only be swept over the "
                "excitation frequency 'omega' of a single harmonic; pass the model's system "
                "to sweep other parameters")
        batch = self.constant_batch(len(values))
        h = moving[0]
        static = [BatchHarmonic(np.zeros_like(values), np.zeros(self.n), s.F_C)
                  for s in self.harmonics if s.omega == 0]
        return Batch(batch.coordinates, batch.M, batch.C, batch.K,
                     [*static, BatchHarmonic(values.copy(), h.F_S, h.F_C)], batch.outputs,
                     batch.title)

    def to_dict(self) -> dict[str, Any]:
        return self.system.to_dict() if self.system is not None else {}

    def symbolic_dict(self) -> dict[str, Any] | None:
        return self.system.symbolic_dict() if self.system is not None else None

    def constant_batch(self, count: int) -> Batch:
        """A batch of ``count`` copies of this system (the same numbers at every point).

        Parameters
        ----------
        count : int

        Returns
        -------
        Batch
        """
        return Batch(tuple(self.coordinates), self.M, self.C, self.K,
                     [BatchHarmonic(np.full(count, h.omega), h.F_S, h.F_C,
                                    {v: (np.full(count, s), np.full(count, c))
                                     for v, (s, c) in h.signals.items()})
                      for h in self.harmonics],
                     {name: (np.full(count, out.value),
                             {v: np.full(count, c) for v, c in out.terms.items()})
                      for name, out in self.outputs.items()},
                     self.title, self.harmonic, count)

    def _repr_latex_(self) -> str:
        return numeric_eom_latex(self)


def numeric_point(batch: Batch, i: int, system: LinearSystem | None = None,
          parameters: Mapping[str, Any] | None = None) -> NumericEOM:
    """The numeric system at point ``i``, its excitations merged by frequency."""
    n = len(batch.coordinates)
    entries = []
    for h in batch.harmonics:
        f_s = np.asarray(h.F_S, dtype=float)
        f_c = np.asarray(h.F_C, dtype=float)
        entries.append((float(h.omega[i]), f_s[i] if f_s.ndim == 2 else f_s,
                        f_c[i] if f_c.ndim == 2 else f_c,
                        {v: (float(s[i]), float(c[i])) for v, (s, c) in h.signals.items()}))
    harmonics = []
    for members in group_frequencies([e[0] for e in entries]):
        f_s, f_c = np.zeros(n), np.zeros(n)
        sig: dict[Var, tuple[float, float]] = {}
        for k in members:
            f_s = f_s + entries[k][1]
            f_c = f_c + entries[k][2]
            for var, (s, c) in entries[k][3].items():
                old = sig.get(var, (0.0, 0.0))
                sig[var] = (old[0] + s, old[1] + c)
        harmonics.append(NumericHarmonic(entries[members[0]][0], f_s, f_c,
                                         MappingProxyType(sig)))
    harmonics.sort(key=lambda h: h.omega)
    outputs = {name: NumericOutput(float(value[i]), MappingProxyType(
        {v: float(c[i]) for v, c in terms.items()}))
        for name, (value, terms) in batch.outputs.items()}
    params = {k: float(np.asarray(v).ravel()[i] if np.ndim(v) else v)
              for k, v in (parameters or {}).items()}
    return NumericEOM(
        coordinates=tuple(batch.coordinates), M=batch.matrix("M", i), C=batch.matrix("C", i),
        K=batch.matrix("K", i), harmonics=tuple(harmonics), harmonic=batch.harmonic,
        outputs=MappingProxyType(outputs), parameters=MappingProxyType(params),
        system=system)


def numeric_eom_latex(eom: NumericEOM) -> str:
    """M q'' + C q' + K q = Q with numbers (Jupyter ``_repr_latex_`` of a NumericEOM)."""
    if eom.n > 12:
        return rf"$\text{{{eom.n} coordinates}}$"
    q = [name_latex(c) for c in eom.coordinates]
    parts = [matrix_latex(getattr(eom.dense(), key)) + column_latex(
        [rf"\{dots}{{{c}}}" if dots else c for c in q])
        for key, dots in (("M", "ddot"), ("C", "dot"), ("K", ""))
        if np.any(getattr(eom.dense(), key))]
    terms = []
    for h in eom.harmonics:
        wt = number_latex(h.omega) + "t"
        terms += [rf"{vector_latex(h.F_S)}\sin({wt})" if np.any(h.F_S) else "",
                  rf"{vector_latex(h.F_C)}\cos({wt})" if np.any(h.F_C) and h.omega else "",
                  vector_latex(h.F_C) if np.any(h.F_C) and not h.omega else ""]
    rhs = " + ".join(t for t in terms if t) or r"\mathbf{0}"
    return rf"$\displaystyle {' + '.join(parts) or '0'} = {rhs}$"


__all__ = ["LinearSystem", "parameter_values", "NumericEOM", "NumericHarmonic", "NumericOutput",
           "numeric_point"]
