"""The exact linear time response to a sampled transient (a shock, a measured history).

One signal of the model -- a support motion, a force -- or a force on a coordinate
follows a sampled history u(t) of its derivative of order m (m = 2: a base acceleration),
linear between the samples.  The system M q'' + C q' + K q = sum_k E_k s^(k) is written in
the state X = [q, q', s, s', ..., s^(m-1)] with s^(m) = u, and marched with its exact
first-order-hold (ramp-invariant) discretization (the state-transition matrix and its
integrals from one matrix exponential, Van Loan 1978):

    X[j+1] = Phi X[j] + (F0 - F1) u[j] + F1 u[j+1],

exact for the piecewise-linear input: not a numerical integrator.  The model starts at
rest in its reference state.  For a single-DOF oscillator on a base this is the SRS
filter of :mod:`.shock`; the output histories can be given to
:func:`~resonant.analyses.shock.shock_response_spectrum` (the shock a mounted part sees).

Examples
--------
>>> import resonant
>>> from resonant.analyses.shock import pulse
>>> system = resonant.load("examples/shaker_gevs.toml").linearize()
>>> t, a = pulse("half-sine", 100.0, 0.011, 1e-5, total=0.05)
>>> result = transient_response(system, "y", a, 1e-5, derivative=2)
>>> round(result.largest["table"], 9)          # the output y'' is the input itself
100.0
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem, printable
from ..memory import CHUNK_BYTES, chunk_rows, dense_matrix, require
from ..model.load_spec import ShockSpec
from ..model.units_display import ResultUnits, shown_unit
from ..system.base import LinearSystem, NumericEOM
from ..system.excitation import excitation_columns
from ..system.output_map import output_map
from ..tables import ResultTable, number_cell
from .result_fields import FieldsJSON, Framed, saved
from .shock import pulse

#: most state variables marched (dense matrices)
MAX_STATES = 2000
#: most samples
MAX_SAMPLES = 5_000_000


@dataclass(frozen=True)
class TransientResponse(FieldsJSON, Framed):
    """The response histories of every coordinate and output to a sampled input.

    Attributes
    ----------
    time : ndarray
        The sample times (s).
    input : ndarray
        The input at those times.
    history : mapping
        name -> the response at ``time`` (about the reference state).
    largest : mapping
        name -> the largest |response| on the samples.
    names : tuple of str
        The coordinates, then the outputs.
    """

    #: the columns of to_frame() (resonant.analyses.result_fields.Framed)
    _frame = (("time", "time"), ("input", "input"), ("history", "{key}"))
    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): the largest
    #: values, then the histories (only by ``to_dict(history=True)``, which from_dict needs)
    _json_order = ("duration_s", "samples", "largest", "warnings", "history")

    time: np.ndarray = saved(history=True)
    input: np.ndarray = saved(history=True, axes=("time",))
    history: dict[str, np.ndarray] = saved(history=True, key="responses", axes=("time",))
    largest: dict[str, float] = saved()
    names: tuple[str, ...] = saved(keys_of="history")
    warnings: tuple[str, ...] = saved(default=())

    def __post_init__(self) -> None:
        freeze_fields(self)

    def _derived_json(self) -> dict[str, Any]:
        return {"duration_s": float(self.time[-1]), "samples": len(self.time)}


@dataclass(frozen=True)
class ShockPeaks(FieldsJSON):
    """The largest responses of a model under its ``[shock]`` pulse: what a mounted part,
    a clearance or a stress sees, per coordinate and output.

    Attributes
    ----------
    names : tuple of str
        The coordinates, then the outputs.
    largest : mapping
        name -> the largest |response| on the samples.
    maximum, minimum : mapping
        name -> the largest and the smallest response (signed).
    time : mapping
        name -> when the largest |response| happens (s from the pulse's start).
    units : mapping
        name -> the response's SI unit ("" where the model has no units).
    shock : ShockSpec
        The pulse (SI), saved as its section's keys.
    warnings : tuple of str

    Examples
    --------
    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`; the
    ``response`` of ``resonant srs MODEL --largest --json``) and read back:

    >>> import json, resonant
    >>> system = resonant.load("examples/shaker_gevs.toml").linearize()
    >>> spec = ShockSpec("y", 2, "half-sine", 100.0, 0.011, 1e-4, 0.02)
    >>> peaks = shock_peaks(shock_response(system, spec, names=["table"]), spec)
    >>> peaks.to_dict()["shock"]["pulse"]
    'half-sine'
    >>> ShockPeaks.from_dict(json.loads(json.dumps(peaks.to_dict()))) == peaks
    True
    """

    names: tuple[str, ...]
    largest: Mapping[str, float]
    maximum: Mapping[str, float]
    minimum: Mapping[str, float]
    time: Mapping[str, float]
    units: Mapping[str, str]
    shock: ShockSpec
    warnings: tuple[str, ...] = ()

    def table(self, units: ResultUnits | None = None) -> ResultTable:
        """The largest |response|, the largest of each sign and when (:func:`peaks_table`).

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``mm``, ``g``, ...; default SI).

        Returns
        -------
        resonant.tables.ResultTable
        """
        return peaks_table(self, units)


def shock_peaks(response: TransientResponse, spec: ShockSpec,
                units: Mapping[str, str] | None = None,
                names: Sequence[str] | None = None) -> ShockPeaks:
    """The largest responses of a :func:`shock_response` under the pulse ``spec``.

    Parameters
    ----------
    response : TransientResponse
        The response to the pulse.
    spec : ShockSpec
        The pulse.
    units : mapping, optional
        name -> SI unit of each response.
    names : sequence of str, optional
        The responses (default all of ``response``).

    Returns
    -------
    ShockPeaks

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/shaker_gevs.toml").linearize()
    >>> spec = ShockSpec("y", 2, "half-sine", 100.0, 0.011, 1e-5, 0.05)
    >>> peaks = shock_peaks(shock_response(system, spec, names=["table"]), spec)
    >>> round(peaks.largest["table"], 9), round(peaks.time["table"], 6)   # the pulse's peak
    (100.0, 0.0055)
    """
    names = tuple(response.names if names is None else names)
    history = {n: np.asarray(response.history[n]) for n in names}
    return ShockPeaks(
        names, {n: response.largest[n] for n in names}, {n: float(history[n].max()) for n in names},
        {n: float(history[n].min()) for n in names},
        {n: float(response.time[int(np.argmax(np.abs(history[n])))]) for n in names},
        {n: (units or {}).get(n, "") for n in names}, spec, response.warnings)


def peaks_table(peaks: ShockPeaks, units: ResultUnits | None = None) -> ResultTable:
    """Each response's largest |value| under the pulse, its largest and smallest value and
    the time of the largest |value|, in the display units.

    Parameters
    ----------
    peaks : ShockPeaks
    units : ResultUnits, optional
        The display units (``mm``, ``g``, ...; default SI).

    Returns
    -------
    resonant.tables.ResultTable

    Examples
    --------
    >>> from resonant.model.units import display_units
    >>> peaks = ShockPeaks(("a",), {"a": 98.0665}, {"a": 98.0665}, {"a": -9.80665},
    ...                    {"a": 0.0055}, {"a": "m/s^2"},
    ...                    ShockSpec("y", 2, "half-sine", 98.0665, 0.011, 1e-5, 0.03))
    >>> print(peaks_table(peaks, ResultUnits(display=display_units(["g"]))).text())
      name  unit  max |value|  max  min  at t [s]
      a     g              10   10   -1    0.0055
    """
    rows = []
    for n in peaks.names:
        shown = shown_unit(units, peaks.units.get(n, ""))
        rows.append((printable(n, limit=40), shown.text or "SI",
                     number_cell(shown(peaks.largest[n])), number_cell(shown(peaks.maximum[n])),
                     number_cell(shown(peaks.minimum[n])), number_cell(peaks.time[n])))
    return ResultTable(("name", "unit", "max |value|", "max", "min", "at t [s]"), tuple(rows),
                       align="llrrrr")


def _state_space(system: LinearSystem, signal: str, derivative: int,
                 deadline: Deadline) -> tuple[Any, ...]:
    """A, B (state), and the rows giving q'' = Pq X + pu u, for X = [q, q', w]."""
    num = system.numeric(deadline)
    n, m = num.n, derivative
    M, C, K = (dense_matrix(a) for a in (num.M, num.C, num.K))
    columns = excitation_columns(system, dict(num.parameters), deadline)
    loads = {order: c for (name, order), c in columns.items() if name == signal}
    if not loads and signal in num.coordinates:
        unit = np.zeros(n)
        unit[num.coordinates.index(signal)] = 1.0
        loads = {0: unit}
    elif not loads and (num.model is None or signal not in num.model.signals):
        known = list(num.model.signals) if num.model is not None else []
        raise AnalysisError(f"'{signal}' is neither a signal nor a coordinate of the model "
                            f"(signals: {', '.join(known) or 'none'})")
    if any(order > m for order in loads):
        raise AnalysisError(f"the model's load uses {signal}" + "'" * max(loads) + ", a "
                            f"higher derivative than the history's ({m}); give the history "
                            f"of {signal}" + "'" * max(loads))
    size = 2 * n + m
    if size > MAX_STATES:
        raise AnalysisError(f"{size} states; the exact transient response is limited to "
                            f"{MAX_STATES} (dense state-transition matrices)")
    Minv = np.linalg.inv(M)
    A = np.zeros((size, size))
    B = np.zeros(size)
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -Minv @ K
    A[n:2 * n, n:2 * n] = -Minv @ C
    for order, column in loads.items():
        if order < m:
            A[n:2 * n, 2 * n + order] += Minv @ column
        else:
            B[n:2 * n] += Minv @ column
    for i in range(m):
        if i + 1 < m:
            A[2 * n + i, 2 * n + i + 1] = 1.0
        else:
            B[2 * n + i] = 1.0
    return num, A, B


def _discretize(A: np.ndarray, B: np.ndarray, step: float
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Phi, F0, F1 of the first-order hold, from one matrix exponential (Van Loan)."""
    from scipy.linalg import expm

    size = len(A)
    big = np.zeros((size + 2, size + 2))
    big[:size, :size] = A
    big[:size, size] = B
    big[size, size + 1] = 1.0 / step
    E = expm(big * step)
    return E[:size, :size], E[:size, size], E[:size, size + 1]


def transient_response(system: LinearSystem, signal: str, values: Sequence[float] | np.ndarray,
                       step: float, *, derivative: int = 0, names: Sequence[str] | None = None,
                       deadline: Deadline = NO_DEADLINE) -> TransientResponse:
    """The exact response from rest to a sampled history of a signal's derivative.

    Parameters
    ----------
    system : LinearSystem
    signal : str
        A signal of the model, or a coordinate (a generalized force on it).
    values : array_like
        The history of the signal's ``derivative``-th derivative at 0, step, 2 step, ...
        (linear in between; a pulse from :func:`~resonant.analyses.shock.pulse`, a CSV
        column).
    step : float
        The sampling step (s).
    derivative : int
        0 (the signal itself, a force), 1 or 2 (a support's acceleration).
    names : sequence of str, optional
        The coordinates and outputs to report (default all).
    deadline : Deadline, optional
        Checked every 10,000 steps.

    Returns
    -------
    TransientResponse

    Raises
    ------
    AnalysisError
        For an unknown signal, a load in a higher derivative than the history's, too many
        states or samples, or an invalid history.
    """
    u = np.asarray(values, dtype=float).ravel()
    if len(u) < 2 or not np.isfinite(u).all() or len(u) > MAX_SAMPLES:
        raise AnalysisError(f"the history needs 2 to {MAX_SAMPLES} finite samples")
    if not (np.isfinite(step) and step > 0) or derivative not in (0, 1, 2):
        raise AnalysisError("the step must be positive and the derivative 0, 1 or 2")
    num, A, B = _state_space(system, signal, derivative, deadline)
    rows, R, D = _output_map(num, A, B, signal, derivative, names)
    require(8.0 * len(u) * (len(rows) + 2), f"the response histories ({len(u)} samples x "
            f"{len(rows)} coordinates and outputs)", "ask for fewer names, a longer step or a "
            "shorter history")
    Phi, F0, F1 = _discretize(A, B, step)
    Y = _march(Phi, F0 - F1, F1, u, R, D, deadline)
    history = {name: Y[:, k] for k, name in enumerate(rows)}
    time = np.arange(len(u)) * step
    return TransientResponse(time, u, history,
                             {k: float(np.abs(v).max()) for k, v in history.items()},
                             tuple(history))


def _output_map(num: NumericEOM, A: np.ndarray, B: np.ndarray, signal: str, derivative: int,
                names: Sequence[str] | None) -> tuple[list[str], np.ndarray, np.ndarray]:
    """The names reported and the map y = R X + D u from the state X = [q, q', s, ...,
    s^(m-1)] and the input u = s^(m) to them (a coordinate, or an output's terms in q, q',
    q'' = A[q''] X + B[q''] u and the signal's derivatives)."""
    n, size = num.n, len(A)
    rows = [q for q in num.coordinates if names is None or q in names]
    R = [np.eye(size)[num.coordinates.index(q)] for q in rows]
    D = [0.0] * len(rows)
    outputs = output_map(num.outputs, num.coordinates,
                         [o for o in num.outputs if names is None or o in names])
    for j, name in enumerate(outputs.names):
        if outputs.orders[j] > 2:
            raise AnalysisError(f"the output {name} holds a rate of order "
                                f"{outputs.orders[j]} of a coordinate; a transient gives "
                                "rates up to 2")
        r, d = np.zeros(size), 0.0
        r[:n] += outputs.R[0][j]
        r[n:2 * n] += outputs.R[1][j]
        if len(outputs.R) > 2:
            r += outputs.R[2][j] @ A[n:2 * n]
            d += float(outputs.R[2][j] @ B[n:2 * n])
        for (var, order), coefficient in zip(outputs.signals, outputs.S[j]):
            if var != signal or coefficient == 0:
                continue
            if order < derivative:
                r[2 * n + order] += coefficient
            elif order == derivative:
                d += coefficient
            else:
                raise AnalysisError(f"the output {name} uses {var}" + "'" * order + ", a "
                                    "higher derivative than the history's")
        rows.append(name)
        R.append(r)
        D.append(d)
    return rows, np.array(R).reshape(len(rows), size), np.array(D)


def _block_length(size: int, outputs: int, samples: int) -> int:
    """Samples per block of :func:`_march`: up to 128, fewer where the block's operators
    (outputs x block x (states + block) numbers) would pass a chunk's memory, or where
    their set-up -- block x (outputs + 2) x states^2 multiply-adds for R Phi^k and Phi^k G,
    log2(block) x states^3 for Phi^L -- would pass a quarter of what the step-by-step
    march costs (samples x states^2): a short history of a large model keeps L = 1, the
    plain recursion."""
    length = 128
    while length > 1 and (8.0 * length * outputs * (size + length + 1) > CHUNK_BYTES
                          or 4 * (length * (outputs + 2) + size * (length.bit_length() - 1))
                          > samples):
        length //= 2
    return length


def _block_operators(Phi: np.ndarray, G0: np.ndarray, G1: np.ndarray, R: np.ndarray,
                     D: np.ndarray, length: int) -> tuple[np.ndarray, ...]:
    """The exact maps of one block of L = ``length`` samples from its first state X_b and
    its L + 1 inputs w = u[bL], ..., u[bL + L]: the outputs y[bL + k] = (R Phi^k) X_b +
    sum_m T[m, k] w[m] (k < L) and the next block's state X_{b+1} = Phi^L X_b + S^T w,
    unrolled from X[j+1] = Phi X[j] + G0 u[j] + G1 u[j+1].  Returns (R Phi^k) as a
    states x (L outputs) matrix, T as (L + 1) x (L outputs), S and Phi^L."""
    size, r = len(Phi), len(R)
    RP = np.empty((length, r, size))   # R Phi^k
    PG = np.empty((length, 2, size))   # Phi^p G0, Phi^p G1
    RP[0], PG[0] = R, (G0, G1)
    for k in range(1, length):
        RP[k] = RP[k - 1] @ Phi
        PG[k] = PG[k - 1] @ Phi.T
    a = np.vstack([np.zeros((1, r)), RP @ G0])   # a[p + 1] = R Phi^p G0
    b = RP @ G1                                  # b[p] = R Phi^p G1
    m = np.arange(length + 1)[:, None]
    d = np.arange(length)[None, :] - m           # k - m
    ahead = d >= 0
    T = np.where(ahead[..., None], a[np.clip(d, 0, length)], 0.0)
    T += np.where((ahead & (m >= 1))[..., None], b[np.clip(d, 0, length - 1)], 0.0)
    T[np.arange(length), np.arange(length)] += D
    S = np.zeros((length + 1, size))
    S[:length] += PG[::-1, 0]                    # m < L: Phi^(L-1-m) G0
    S[1:] += PG[::-1, 1]                         # m >= 1: Phi^(L-m) G1
    return (np.ascontiguousarray(RP.reshape(length * r, size).T),
            T.reshape(length + 1, length * r), S, np.linalg.matrix_power(Phi, length))


def _march(Phi: np.ndarray, G0: np.ndarray, G1: np.ndarray, u: np.ndarray, R: np.ndarray,
           D: np.ndarray, deadline: Deadline) -> np.ndarray:
    """y[j] = R X[j] + D u[j] along X[j+1] = Phi X[j] + G0 u[j] + G1 u[j+1], X[0] = 0.

    The recursion is unrolled over blocks of L samples (:func:`_block_operators`): only
    the blocks' first states are stepped one after the other (Phi^L), every output of a
    block is two matrix products -- the same numbers to rounding, a step in a few
    multiply-adds instead of a Python iteration.  A chunk of blocks is held at a time
    (memory: the outputs only)."""
    samples, size, r = len(u), len(Phi), len(R)
    length = _block_length(size, r, samples)
    blocks = -(-samples // length)
    RP, T, S, PhiL = _block_operators(Phi, G0, G1, R, D, length)
    padded = np.zeros(blocks * length + 1)
    padded[:samples] = u
    inputs = np.lib.stride_tricks.sliding_window_view(padded, length + 1)[::length]
    Y = np.empty((blocks * length, r))
    chunk = chunk_rows(8.0 * (2 * size + 2 * length * r), blocks)
    every = max(1, 10_000 // length)
    state = np.zeros(size)
    for start in range(0, blocks, chunk):
        stop = min(start + chunk, blocks)
        W = inputs[start:stop]
        F = W @ S
        X = np.empty((stop - start, size))
        for i in range(stop - start):
            if (start + i) % every == 0:
                deadline.check("while marching the transient response", analysis=True)
            X[i] = state
            state = PhiL @ state + F[i]
        Y[start * length:stop * length] = (X @ RP + W @ T).reshape(-1, r)
    return Y[:samples]


def shock_response(system: LinearSystem, spec: ShockSpec | None = None, *,
                   names: Sequence[str] | None = None,
                   deadline: Deadline = NO_DEADLINE) -> TransientResponse:
    """The exact response to the model's ``[shock]`` pulse (docs/random.md, section Shock).

    Parameters
    ----------
    system : LinearSystem
    spec : ShockSpec, optional
        The pulse (default: the model's ``[shock]`` section).
    names : sequence of str, optional
        The coordinates and outputs to report (default all).
    deadline : Deadline, optional

    Returns
    -------
    TransientResponse
        Sampled every ``spec.step`` over ``spec.total``.

    Raises
    ------
    ModelError
        Without a ``[shock]`` section.
    AnalysisError
        As :func:`transient_response`.

    Examples
    --------
    >>> import resonant
    >>> from resonant.model.load_spec import ShockSpec
    >>> system = resonant.load("examples/shaker_gevs.toml").linearize()
    >>> spec = ShockSpec("y", 2, "half-sine", 100.0, 0.011, 1e-5, 0.05)
    >>> round(shock_response(system, spec, names=["table"]).largest["table"], 9)
    100.0
    """
    if spec is None:
        spec = system.model.shock_section if system.model is not None else None
        if spec is None:
            raise ModelError(Problem("the model has no [shock] section: add one with the "
                                     "pulse, its signal, amplitude and duration "
                                     "(docs/model-format.md)", system.source, "shock"))
    _, values = pulse(spec.pulse, spec.amplitude, spec.duration, spec.step, total=spec.total)
    return transient_response(system, spec.signal, values, spec.step,
                              derivative=spec.derivative, names=names, deadline=deadline)


__all__ = ["TransientResponse", "ShockPeaks", "shock_peaks", "shock_response",
           "transient_response"]
