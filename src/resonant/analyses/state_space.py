"""A linear system in first-order form, for the control tools: x' = A x + B u, y = C x + D u.

:func:`state_space` builds the four matrices of any :class:`LinearSystem` (a model given
by its energies or parts, or by ``[matrices]``) at given parameter values, with named
inputs, states and outputs (:class:`StateSpaceModel`); :func:`to_state_space` hands them
to python-control (``control.StateSpace`` with the names) or, where python-control is not
installed, to ``scipy.signal.StateSpace``.  The state matrix is the modal kernel's
(:func:`resonant.modal.state_matrix`): the one place the first-order form is written.

Inputs are named by the model: a signal (``F``, the base motion ``y``: the signal itself,
its rates folded into the realization) or a coordinate (a generalized force ``Q_x1`` on
it, for ``[matrices]`` models).  With loads ``Q = B0 u + B1 u' + B2 u''`` the states are
``z1 = q - M^-1 B2 u`` and ``z2 = z1' - E1 u`` (``E1 = M^-1 (B1 - C M^-1 B2)``), which
makes the realization proper without differentiating an input; without signal rates in
the loads (forces, a ``[matrices]`` model) they are q and q' exactly.  Outputs are the
coordinates (``x1``), their rates (``x1'``, ``x1''``) and the model's ``[outputs]``; an
output that needs the rate of an input (a velocity under a base-acceleration input) is
refused by name.

The exported system is dense (2n x 2n): python-control has no sparse or second-order
model.  Above :data:`MAX_STATE_SPACE_COORDINATES` coordinates the export is refused with
what to do instead (a reduced model, the harmonic kernel's sweep).

Examples
--------
>>> import resonant
>>> system = resonant.load("examples/tuned_mass_damper.toml").linearize()
>>> model = state_space(system)
>>> model.inputs, model.outputs
(('F',), ('x1', 'x2', 'stroke'))
>>> model.A.shape, model.B.shape, model.C.shape, model.D.shape
((4, 4), (4, 1), (3, 4), (3, 1))
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem
from ..memory import dense_matrix, require
from ..modal import state_matrix
from ..system.base import LinearSystem, NumericEOM, NumericOutput
from ..system.excitation import excitation_columns
from ..system.output_map import output_map
from ..system.stability import check_mass_matrix
from .result_fields import FieldsJSON, saved

#: largest model exported: its dense state matrix (2n)^2 holds 128 MB of float64 at 2000
MAX_STATE_SPACE_COORDINATES = 2000
#: the libraries :func:`to_state_space` can return a system of
LIBRARIES = ("auto", "control", "scipy")
#: the prefix of a generalized-force input on a coordinate (``Q_x1``)
FORCE_PREFIX = "Q_"
#: the default inputs of a model without signals: all its coordinates, up to this many
MAX_DEFAULT_FORCE_INPUTS = 50


@dataclass(frozen=True)
class StateSpaceModel(FieldsJSON):
    """A system in state-space form, x' = A x + B u, y = C x + D u, with named inputs,
    states and outputs.

    Parameters
    ----------
    A, B, C, D : ndarray
        The state, input, output and feedthrough matrices, (2n, 2n), (2n, m), (p, 2n),
        (p, m).
    inputs : tuple of str
        The inputs u: signal names, or ``Q_<coordinate>`` for a generalized force.
    states : tuple of str
        The states: the coordinates, then their rates (``x1'``).
    outputs : tuple of str
        The outputs y: coordinates, their rates (``x1'``, ``x1''``) and model outputs.
    parameters : mapping
        The parameter values the numbers are for.
    title : str
        The model's title.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/base_excitation.toml").linearize()
    >>> state_space(system).states
    ('x', "x'")
    >>> sorted(state_space(system).to_dict())       # saved by its fields (FieldsJSON)
    ['A', 'B', 'C', 'D', 'inputs', 'outputs', 'parameters', 'states', 'title']
    >>> StateSpaceModel.from_dict(state_space(system).to_dict()).A.shape
    (2, 2)
    """

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): the names, then
    #: the matrices as lists of rows
    _json_order = ("title", "inputs", "states", "outputs", "parameters", "A", "B", "C", "D")

    A: np.ndarray = saved(axes=("states", "states"))
    B: np.ndarray = saved(axes=("states", "inputs"))
    C: np.ndarray = saved(axes=("outputs", "states"))
    D: np.ndarray = saved(axes=("outputs", "inputs"))
    inputs: tuple[str, ...] = saved()
    states: tuple[str, ...] = saved()
    outputs: tuple[str, ...] = saved()
    parameters: Mapping[str, float] = saved()
    title: str = saved("")

    def __post_init__(self) -> None:
        freeze_fields(self)

    def frequency_response(self, omega: Sequence[float] | np.ndarray) -> np.ndarray:
        """H(i omega) = C (i omega I - A)^-1 B + D at each circular frequency.

        Parameters
        ----------
        omega : array_like
            Circular frequencies in rad/s, shape (N,).

        Returns
        -------
        ndarray
            Complex, (N, outputs, inputs).

        Examples
        --------
        >>> import resonant
        >>> system = resonant.load("examples/base_excitation.toml").linearize()
        >>> H = state_space(system).frequency_response([0.0])
        >>> H[0].real.round(12).tolist()
        [[1.0], [0.0]]
        """
        w = np.asarray(omega, dtype=float).reshape(-1)
        size = self.A.shape[0]
        out = np.empty((w.size, self.C.shape[0], self.B.shape[1]), dtype=complex)
        for k, value in enumerate(w):
            out[k] = self.C @ np.linalg.solve(1j * value * np.eye(size) - self.A, self.B) \
                + self.D
        return out


def state_space(system: LinearSystem, *, inputs: Sequence[str] | None = None,
                outputs: Sequence[str] | None = None,
                parameters: Mapping[str, float | str] | None = None,
                deadline: Deadline = NO_DEADLINE) -> StateSpaceModel:
    """The first-order form of a linear system at parameter values, with named signals.

    Parameters
    ----------
    system : LinearSystem
        Any linear system (energies, parts or ``[matrices]``).
    inputs : sequence of str, optional
        Signals of the model, or coordinates (a generalized force on each, input
        ``Q_<coordinate>``).  Default: the model's signals; for a model without signals
        the coordinates its ``[[harmonic]]`` loads act on (all coordinates of a small
        model without loads).  Signals not listed are held at zero.
    outputs : sequence of str, optional
        Coordinates, their rates (``x1'``, ``x1''``) and ``[outputs]`` names.  Default:
        every coordinate and output.
    parameters : mapping, optional
        Parameter values replacing the model's (numbers or expression text).
    deadline : Deadline, optional
        The run's time limit.

    Returns
    -------
    StateSpaceModel

    Raises
    ------
    ModelError
        For an input or output that the model does not have.
    AnalysisError
        For a singular mass matrix, a model above :data:`MAX_STATE_SPACE_COORDINATES`
        coordinates or the memory budget, a load on a signal's third rate, or an output
        that needs an input's rate.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/base_excitation.toml").linearize()
    >>> model = state_space(system, outputs=["z", "x'"])
    >>> model.A.tolist()
    [[0.0, 1.0], [-400.0, -4.0]]
    """
    num = system.numeric(deadline, **dict(parameters or {}))
    n = num.n
    _check_size(num)
    M, C, K = (dense_matrix(a) for a in (num.M, num.C, num.K))
    check_mass_matrix(M, num.coordinates)
    columns = excitation_columns(num, deadline=deadline)
    chosen = _inputs(num, columns, inputs)
    rates = _load_rates(num, columns, chosen)
    Minv = np.linalg.solve(M, np.concatenate([K, C, *rates], axis=1))
    minv_k, minv_c = Minv[:, :n], Minv[:, n:2 * n]
    count = len(chosen)
    minv_b0, minv_b1, d0 = (Minv[:, 2 * n + k * count:2 * n + (k + 1) * count]
                            for k in range(3))
    # z1 = q - D0 u with D0 = M^-1 B2 leaves M z1'' + C z1' + K z1 = B0' u + B1' u'
    b0 = minv_b0 - minv_k @ d0
    e1 = minv_b1 - minv_c @ d0
    A = state_matrix(minv_k, minv_c)
    B = np.concatenate([e1, b0 - minv_c @ e1], axis=0)
    quantities = _quantities(A, B, e1, d0)
    names = tuple(outputs) if outputs is not None else (*num.coordinates, *num.outputs)
    C_out, D_out = _output_rows(num, names, quantities, chosen)
    return StateSpaceModel(
        A=A, B=B, C=C_out, D=D_out,
        inputs=tuple(_input_name(num, name) for name in chosen),
        states=(*num.coordinates, *(f"{q}'" for q in num.coordinates)),
        outputs=names, parameters=dict(num.parameters), title=num.title)


def to_state_space(system: LinearSystem, *, inputs: Sequence[str] | None = None,
                   outputs: Sequence[str] | None = None,
                   parameters: Mapping[str, float | str] | None = None,
                   library: str = "auto", deadline: Deadline = NO_DEADLINE) -> Any:
    """The system as a python-control ``StateSpace`` with named signals (or scipy's).

    Parameters
    ----------
    system : LinearSystem
        Any linear system.
    inputs, outputs, parameters, deadline
        As for :func:`state_space`.
    library : {"auto", "control", "scipy"}
        ``"control"``: ``control.StateSpace`` with the inputs, outputs and states named;
        ``"scipy"``: ``scipy.signal.StateSpace`` (no names: they are in the order of
        :func:`state_space`'s); ``"auto"``: python-control where it is installed.

    Returns
    -------
    control.StateSpace or scipy.signal.StateSpace

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/base_excitation.toml").linearize()
    >>> to_state_space(system, library="scipy").A.shape
    (2, 2)
    """
    if library not in LIBRARIES:
        raise ModelError(f"library must be one of {', '.join(LIBRARIES)}; got '{library}'")
    model = state_space(system, inputs=inputs, outputs=outputs, parameters=parameters,
                        deadline=deadline)
    if library != "scipy":
        try:
            import control
        except ImportError:
            if library == "control":
                raise AnalysisError("python-control is not installed (pip install control, or "
                                    "pip install 'resonant[control]')") from None
        else:
            return control.ss(model.A, model.B, model.C, model.D, inputs=list(model.inputs),
                              outputs=list(model.outputs), states=list(model.states))
    import scipy.signal

    return scipy.signal.StateSpace(model.A, model.B, model.C, model.D)


# -- the pieces ---------------------------------------------------------------------------------

def _check_size(num: NumericEOM) -> None:
    n = num.n
    if n > MAX_STATE_SPACE_COORDINATES:
        kind = "sparse " if num.sparse else ""
        raise AnalysisError(
            f"the {kind}model has {n} coordinates: its state-space form is a dense "
            f"{2 * n} x {2 * n} matrix, and python-control has no sparse, descriptor or "
            "second-order model; the export is limited to "
            f"{MAX_STATE_SPACE_COORDINATES} coordinates "
            "(resonant.analyses.state_space.MAX_STATE_SPACE_COORDINATES). Export a reduced "
            "model (its few lowest modes, or the coordinates the controller sees), or sweep "
            "the full model with the harmonic kernel")
    require(8.0 * (4 * (2 * n) ** 2 + 6 * n * n), f"the state-space form of {n} coordinates",
            "export a reduced model")


def _inputs(num: NumericEOM, columns: Mapping[tuple[str, int], np.ndarray],
            given: Sequence[str] | None) -> list[str]:
    """The input names: signals, or coordinates (a force on each)."""
    signals = list(dict.fromkeys(name for name, _ in columns))
    if given is None:
        if signals:
            return signals
        loaded = [q for i, q in enumerate(num.coordinates)
                  if any(h.F_S[i] or h.F_C[i] for h in num.harmonics)]
        if loaded:
            return loaded
        if num.n <= MAX_DEFAULT_FORCE_INPUTS:
            return list(num.coordinates)
        raise ModelError(Problem(
            f"the model has no signals and no loads and {num.n} coordinates: name the "
            "coordinates the inputs act on (inputs=[...])", num.source))
    known = set(signals) | set(num.coordinates)
    declared = set(num.model.signals) if num.model is not None else set()
    chosen = []
    for name in given:
        if name.startswith(FORCE_PREFIX) and name not in known:
            name = name[len(FORCE_PREFIX):]
        if name in declared and name not in signals:
            raise ModelError(Problem(f"the signal '{name}' loads no coordinate: it cannot be "
                                     "an input", num.source, "signals", name))
        if name not in known:
            raise ModelError(Problem(
                f"'{name}' is neither a signal that loads the model nor a coordinate (the "
                f"inputs are {_listed(signals + list(num.coordinates))})", num.source))
        chosen.append(name)
    if len(set(chosen)) != len(chosen):
        raise ModelError(Problem("an input is named twice", num.source))
    return chosen


def _input_name(num: NumericEOM, name: str) -> str:
    return FORCE_PREFIX + name if name in num.coordinates else name


def _listed(names: Sequence[str]) -> str:
    return ", ".join(names[:6]) + (", ..." if len(names) > 6 else "")


def _load_rates(num: NumericEOM, columns: Mapping[tuple[str, int], np.ndarray],
                chosen: Sequence[str]) -> list[np.ndarray]:
    """B0, B1, B2: the loads of the inputs, of their first and of their second rates."""
    n, count = num.n, len(chosen)
    rates = [np.zeros((n, count)) for _ in range(3)]
    position = {q: i for i, q in enumerate(num.coordinates)}
    for j, name in enumerate(chosen):
        if name in position:
            rates[0][position[name], j] = 1.0
            continue
        for (signal, order), column in columns.items():
            if signal != name:
                continue
            if order > 2:
                raise AnalysisError(f"the loads hold the rate of order {order} of the signal "
                                    f"'{name}': a state-space input takes rates up to 2")
            rates[order][:, j] += column
    return rates


def _quantities(A: np.ndarray, B: np.ndarray, e1: np.ndarray, d0: np.ndarray
                ) -> list[tuple[np.ndarray, list[np.ndarray]]]:
    """q, q', q'' as (rows over the states, [feedthrough of u, of u', of u''])."""
    n, count = d0.shape
    zero = np.zeros((n, count))
    eye, none = np.eye(n), np.zeros((n, n))
    return [(np.hstack([eye, none]), [d0, zero, zero]),
            (np.hstack([none, eye]), [e1, d0, zero]),
            (A[n:], [B[n:], e1, d0])]


def _output_terms(num: NumericEOM, name: str) -> NumericOutput:
    """An output of the export: a coordinate or its rate (``x1'``), or an ``[outputs]`` one."""
    base = name.rstrip("'")
    order = len(name) - len(base)
    if base in num.coordinates and order <= 2:
        return NumericOutput(0.0, {(base, order): 1.0})
    if name in num.outputs:
        return num.outputs[name]
    raise ModelError(Problem(
        f"'{name}' is not an output: the outputs are the coordinates, their rates "
        f"(x', x'') and [outputs] ({_listed([*num.coordinates, *num.outputs])})",
        num.source, "outputs"))


def _output_rows(num: NumericEOM, names: Sequence[str],
                 quantities: Sequence[tuple[np.ndarray, list[np.ndarray]]],
                 chosen: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """C and D of the outputs ``names``; refused where one needs an input's rate."""
    y = output_map({name: _output_terms(num, name) for name in names}, num.coordinates,
                   names)
    for name, order in zip(y.names, y.orders):
        if order > 2:
            raise AnalysisError(f"the output '{name}' holds a rate of order {order} of a "
                                "coordinate: a state-space output takes rates up to 2")
    size, count = quantities[0][0].shape[1], len(chosen)
    C, feed = np.zeros((len(names), size)), np.zeros((3, len(names), count))
    for R, (states, through) in zip(y.R, quantities):
        C += R @ states
        feed += np.array([R @ t for t in through])
    signal_at = {s: j for j, s in enumerate(chosen) if s not in num.coordinates}
    for column, (variable, rate) in enumerate(y.signals):
        if variable in signal_at:
            if rate > 2:
                raise AnalysisError(f"an output holds a rate of order {rate} of the signal "
                                    f"'{variable}'")
            feed[rate][:, signal_at[variable]] += y.S[:, column]
    rated = np.any(feed[1:] != 0, axis=(0, 2))
    if rated.any():
        name = y.names[int(np.flatnonzero(rated)[0])]
        raise AnalysisError(f"the output '{name}' follows the rate of an input (through the "
                            "signal rates the loads hold): it has no proper state-space "
                            "form; export its integral or choose other outputs")
    return C, feed[0]


__all__ = ["StateSpaceModel", "state_space", "to_state_space", "MAX_STATE_SPACE_COORDINATES",
           "LIBRARIES"]
