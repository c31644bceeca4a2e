"""Frequency (and parameter) sweeps of the stationary response.

:func:`sweep` evaluates the stationary amplitude and phase of every coordinate
and output while one parameter runs through an array of values: usually the
excitation frequency, but any parameter works (an absorber stiffness changes
K, a mass changes M).  The equation of motion is derived once; its symbolic
entries are compiled once (:func:`resonant.numeric.compile_expressions`) and
evaluated for all values at once, and the complex systems

    (K - w^2 M + i w C) (L - i N) = F_C - i F_S

are solved by the cheapest exact method for their structure:

``"dense"``
    a stack of complex matrices, one ``numpy.linalg.solve`` per chunk of points;
``"banded"``
    LAPACK ``gbsv`` (``gtsv`` for tridiagonal) per point, when M, C, K do not
    depend on the parameter and their bandwidth is small;
``"sparse"``
    a sparse LU (SuperLU) per point, for large sparse matrices with a wide band;
``"modal"``
    superposition of *all* undamped modes, exact only when the damping is
    proportional (``K M^-1 C = C M^-1 K``); its accuracy is checked against a
    direct solve at a few points, and the sweep falls back to a direct method
    when the check fails.

``method="auto"`` picks one of these (see :func:`choose_method`); the result
says which.  Amplitudes and phases mean exactly what they mean for
:func:`resonant.stationary.stationary`: for one frequency X = sqrt(L^2 + N^2)
and delta = atan2(L, N); for several, the peak of the summed time history.

An undamped system swept exactly through a natural frequency has no bounded
stationary solution there.  Such a point is not an error: its amplitude and
phase are NaN in the arrays (``null`` in JSON, a gap in the plot), its value is
listed in ``skipped`` and a warning names it.

Examples
--------
>>> from resonant.model import load
>>> from resonant.sweep import sweep
>>> import numpy as np, resonant.model
>>> model = resonant.model.loads('''
... [parameters]
... m = 1
... k = 100
... c = 2
... omega = 5
... [coordinates]
... x = "displacement"
... [signals]
... F = "sin(omega*t)"
... [energy]
... T = "m*x'^2/2"
... U = "k*x^2/2"
... D = "c*x'^2/2"
... [[force]]
... generalized = { x = "F" }
... ''')
>>> fr = sweep(model, "omega", np.linspace(1, 20, 191))
>>> [round(p.value, 2) for p in fr.peaks]     # sqrt(k/m - c^2/(2 m^2)) = 9.899
[9.9]
"""

from __future__ import annotations

import csv
import math
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .errors import AnalysisError, ModelError, Problem

if TYPE_CHECKING:  # pragma: no cover
    from .model import Model

METHODS = ("auto", "dense", "banded", "sparse", "modal")
#: a point whose estimated condition number exceeds this is an exact resonance (as in solve)
SINGULAR_CONDITION = 1e13
#: agreement required of modal superposition with a direct solve at the check points
MODAL_TOLERANCE = 1e-10
#: bytes of complex matrices built at once by the dense method
CHUNK_BYTES = 64 * 2**20
#: above this many coordinates only the loaded ones are reported unless names are given
MAX_DEFAULT_NAMES = 2000
#: largest n for which the dense natural frequencies are computed with every sweep
EAGER_EIGEN = 400


class Extremum(NamedTuple):
    """A resonance peak or antiresonance of one response curve.

    ``value`` is the refined parameter value (parabolic interpolation through
    the three grid points around the extremum: on log amplitude for peaks, on
    amplitude squared for antiresonances); ``amplitude`` the interpolated value.
    (A named tuple: a long sweep of a large model has tens of thousands.)
    """

    name: str
    value: float
    amplitude: float

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "value": self.value, "amplitude": self.amplitude}


@dataclass(frozen=True)
class ExtremaTable:
    """Extrema as arrays (built into :class:`Extremum` tuples only when asked for)."""

    names: tuple[str, ...] = ()
    index: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    amplitudes: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __len__(self) -> int:
        return len(self.index)

    def entries(self) -> tuple[Extremum, ...]:
        names = self.names
        return tuple(map(Extremum, [names[i] for i in self.index.tolist()],
                         self.values.tolist(), self.amplitudes.tolist()))

    def to_list(self) -> list[dict[str, Any]]:
        names = self.names
        return [{"name": names[i], "value": v, "amplitude": a} for i, v, a in
                zip(self.index.tolist(), self.values.tolist(), self.amplitudes.tolist())]


@dataclass(frozen=True)
class FrequencyResponse:
    """Amplitudes and phases of coordinates and outputs against one parameter.

    Attributes
    ----------
    parameter : str
        The swept parameter.
    values : ndarray
        Its values, shape (N,).
    amplitudes, phases : mapping
        ``name -> ndarray (N,)``; NaN at skipped points (and phases also where
        there are several frequencies or the amplitude is zero).
    peaks, antiresonances : tuple of Extremum
    method : str
        The solution method used (``dense``, ``banded``, ``sparse``, ``modal``).
    frequency_sweep : bool
        True when the parameter is the excitation frequency (unit rad/s; M, C,
        K stay fixed); then ``natural_frequencies`` are those of the system.
    skipped : tuple of float
        Values where the stationary solution does not exist (undamped resonance).
    """

    parameter: str
    values: np.ndarray
    quantities: tuple[str, ...]
    #: complex responses z = L - i N, shape (harmonics, values, quantities)
    response: np.ndarray
    #: the excitation frequency of each harmonic at each value, shape (harmonics, values)
    harmonic_omegas: np.ndarray
    method: str
    frequency_sweep: bool = False
    natural_frequencies: np.ndarray | None = None
    skipped: tuple[float, ...] = ()
    warnings: tuple[str, ...] = ()
    log: bool = False
    title: str = ""
    coordinates: tuple[str, ...] = ()

    # Amplitudes, phases and extrema are derived on first use: the solve is the
    # sweep's job, and a caller who only needs the responses of a large model
    # should not pay for a million amplitudes and their peaks.
    @cached_property
    def _amplitude_phase(self) -> tuple[np.ndarray, np.ndarray]:
        N, m = len(self.values), len(self.quantities)
        if self.response.shape[0] == 0:
            return np.zeros((N, m)), np.full((N, m), np.nan)
        amplitude, phase = _amplitude_phase(self.harmonic_omegas, self.response)
        skipped = np.isin(self.values, np.asarray(self.skipped, dtype=float))
        amplitude[skipped] = np.nan
        phase[skipped] = np.nan
        return amplitude, phase

    @cached_property
    def amplitudes(self) -> Mapping[str, np.ndarray]:
        amplitude = self._amplitude_phase[0]
        return MappingProxyType({n: amplitude[:, j] for j, n in enumerate(self.quantities)})

    @cached_property
    def phases(self) -> Mapping[str, np.ndarray]:
        phase = self._amplitude_phase[1]
        return MappingProxyType({n: phase[:, j] for j, n in enumerate(self.quantities)})

    @cached_property
    def _extrema(self) -> tuple[ExtremaTable, ExtremaTable]:
        if not np.all(np.diff(self.values) > 0):
            return ExtremaTable(self.quantities), ExtremaTable(self.quantities)
        single = self.response[0] if self.response.shape[0] == 1 else None
        return _extrema(self.quantities, self.values, self._amplitude_phase[0], self.log,
                        single)

    @property
    def peak_table(self) -> ExtremaTable:
        return self._extrema[0]

    @property
    def antiresonance_table(self) -> ExtremaTable:
        return self._extrema[1]

    @property
    def names(self) -> tuple[str, ...]:
        return self.quantities

    @cached_property
    def peaks(self) -> tuple[Extremum, ...]:
        return self.peak_table.entries()

    @cached_property
    def antiresonances(self) -> tuple[Extremum, ...]:
        return self.antiresonance_table.entries()

    @property
    def unit(self) -> str:
        """The unit of the parameter where known ("rad/s" for the excitation frequency)."""
        return "rad/s" if self.frequency_sweep else ""

    def to_dict(self) -> dict[str, Any]:
        def clean(a: np.ndarray) -> list[float | None]:
            return [float(v) if math.isfinite(v) else None for v in a]

        data: dict[str, Any] = {
            "title": self.title,
            "parameter": self.parameter,
            "unit": self.unit,
            "values": self.values.tolist(),
            "amplitudes": {k: clean(v) for k, v in self.amplitudes.items()},
            "phases": {k: clean(v) for k, v in self.phases.items()},
            "peaks": self.peak_table.to_list(),
            "antiresonances": self.antiresonance_table.to_list(),
            "method": self.method,
            "skipped": list(self.skipped),
            "warnings": list(self.warnings),
        }
        if self.natural_frequencies is not None:
            data["natural_frequencies"] = self.natural_frequencies.tolist()
        return data

    def to_csv(self, path: Any) -> None:
        """Write one row per value: the parameter, then amplitude and phase of each name."""
        with open(path, "w", newline="", encoding="utf-8") as handle:
            writer = csv.writer(handle)
            writer.writerow([self.parameter] + [f"{kind}_{name}" for name in self.names
                                                for kind in ("amplitude", "phase")])
            for i, value in enumerate(self.values):
                row = [repr(float(value))]
                for name in self.names:
                    for series in (self.amplitudes[name], self.phases[name]):
                        v = float(series[i])
                        row.append(repr(v) if math.isfinite(v) else "")
                writer.writerow(row)

    def plot(self, path: Any = None, names: Sequence[str] | None = None) -> Any:
        """Amplitude (log axis) and phase against the parameter; see :mod:`resonant.plotting`."""
        from .plotting import plot_frequency_response

        return plot_frequency_response(self, path=path, names=names)

    def _repr_html_(self) -> str:
        import html

        rows = "".join(
            f"<tr><td>{html.escape(p.name)}</td><td>{p.value:.6g}</td>"
            f"<td>{p.amplitude:.6g}</td></tr>" for p in self.peaks[:50])
        unit = f" [{self.unit}]" if self.unit else ""
        return (f"<p><b>Sweep of {html.escape(self.parameter)}</b>{unit}: {len(self.values)} "
                f"values from {self.values[0]:.6g} to {self.values[-1]:.6g} "
                f"(method {self.method})</p><table><tr><th>name</th>"
                f"<th>peak at {html.escape(self.parameter)}</th><th>amplitude</th></tr>"
                f"{rows}</table>")


# -- the batch: everything evaluated for all values at once ------------------------------

@dataclass
class _Harmonic:
    omega: np.ndarray                   # (N,)
    F_S: np.ndarray                     # (N, n) or (n,)
    F_C: np.ndarray
    signals: dict = field(default_factory=dict)   # var -> (S (N,), C (N,))


@dataclass
class _Batch:
    coordinates: tuple[str, ...]
    M: Any                              # (n, n) dense or sparse, or (N, n, n)
    C: Any
    K: Any
    harmonics: list[_Harmonic]
    outputs: dict                       # name -> {var: coef (N,)}
    title: str = ""

    @property
    def constant(self) -> bool:
        return all(hasattr(a, "tocsr") or np.ndim(a) == 2 for a in (self.M, self.C, self.K))


def _model_of(source: Any) -> tuple["Model | None", Any]:
    """(model, eom) for a Model, LinearEOM, NumericEOM or MatrixSystem."""
    from .linearize import LinearEOM
    from .model import Model
    from .numeric import NumericEOM

    if isinstance(source, Model):
        return source, None
    if isinstance(source, LinearEOM):
        return source.model, source
    if isinstance(source, NumericEOM):
        if source.symbolic is None:
            return None, source
        model = source.symbolic.model
        changed = {k: v for k, v in source.parameters.items()
                   if model.parameter_values.get(k) != v}
        return (model.with_parameters(**{k: repr(float(v)) for k, v in changed.items()})
                if changed else model), source.symbolic
    if hasattr(source, "harmonics") and hasattr(source, "K"):
        return None, source
    raise TypeError(f"sweep() takes a Model, LinearEOM, NumericEOM or MatrixSystem, "
                    f"not {type(source).__name__}")


def parameter_values(model: "Model", param: str, values: np.ndarray) -> dict[str, Any]:
    """Every parameter's value with ``param`` set to the array ``values``.

    Parameters defined by expressions of ``param`` follow it (evaluated
    elementwise); the others keep the model's values exactly.
    """
    from .matrices import numeric_value

    if param not in model.parameters:
        import difflib

        close = difflib.get_close_matches(param, list(model.parameters), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else \
            f"; the parameters are {', '.join(model.parameters) or 'none'}"
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
            out[name] = model.parameter_values[name]
    return out


def _batch(source: Any, param: str, values: np.ndarray) -> _Batch:
    model, eom = _model_of(source)
    if model is None:
        return _numeric_batch(eom, param, values)
    params = parameter_values(model, param, values)
    if model.is_matrix_model:
        return _matrix_batch(model, params, values)
    if eom is None:
        eom = model.linearize()
    return _symbolic_batch(eom, model, params, values)


def _numeric_batch(eom: Any, param: str, values: np.ndarray) -> _Batch:
    """A NumericEOM/MatrixSystem without its model: only the excitation frequency can vary."""
    moving = [h for h in eom.harmonics if h.omega > 0]
    if param != "omega" or len(moving) != 1:
        raise AnalysisError(
            "without its model, a numeric equation of motion can only be swept over the "
            "excitation frequency 'omega' of a single harmonic; pass the Model to sweep "
            "other parameters")
    h = moving[0]
    static = [_Harmonic(np.zeros_like(values), np.zeros(eom.n), s.F_C)
              for s in eom.harmonics if s.omega == 0]
    return _Batch(tuple(eom.coordinates), eom.M, eom.C, eom.K,
                  [*static, _Harmonic(values.copy(), h.F_S, h.F_C)],
                  {name: _output_terms_numeric(out) for name, out in
                   getattr(eom, "outputs", {}).items()}, getattr(eom, "title", ""))


def _output_terms_numeric(out: Any) -> dict:
    return {var: np.asarray(coef, dtype=float) for var, coef in out.terms.items()}


def _matrix_batch(model: "Model", params: dict, values: np.ndarray) -> _Batch:
    from .matrices import harmonic_values, matrix_values

    N = values.shape[0]
    M, C, K = (matrix_values(model, key, params) for key in ("M", "C", "K"))
    harmonics = []
    for j, (omega, f_s, f_c) in enumerate(harmonic_values(model, params), start=1):
        omega = np.broadcast_to(omega, (N,)).astype(float)
        sign = np.where(omega < 0, -1.0, 1.0)
        static = omega == 0
        omega = np.abs(omega)
        f_s = np.where(static[:, None], 0.0, sign[:, None] * f_s) if \
            (sign < 0).any() or static.any() else f_s
        signals = {}
        if np.any(f_s):
            signals[(f"harmonic{j}_s", 0)] = (np.where(static, 0.0, sign), np.zeros(N))
        if np.any(f_c):
            signals[(f"harmonic{j}_c", 0)] = (np.zeros(N), np.ones(N))
        harmonics.append(_Harmonic(omega, f_s, f_c, signals))
    return _Batch(model.coordinates, M, C, K, harmonics, {}, model.title)


def _symbolic_batch(eom: Any, model: "Model", params: dict, values: np.ndarray) -> _Batch:
    from .model import symbol
    from .numeric import FlatReader, compile_expressions, expression_layout

    N, n = values.shape[0], len(eom.coordinates)
    names = list(model.parameters)
    symbols = [symbol(name) for name in names]
    args = [params[name] for name in names]
    layout = expression_layout(eom)
    exprs = layout.expressions
    flat = compile_expressions(exprs, symbols)(*args)
    flat = np.broadcast_to(flat.reshape(len(exprs), -1), (len(exprs), N))
    bad = ~np.isfinite(flat) | (np.abs(flat.imag) > 1e-9 * (1 + np.abs(flat.real)))
    if bad.any():
        point = int(np.argmax(bad.any(axis=0)))
        raise ModelError(Problem(
            f"the equation of motion is not finite (or not real) at {values[point]:.6g} "
            "(a zero mass or length?)", model.source, "parameters"))
    take = FlatReader(flat.real).take

    def matrix() -> np.ndarray:
        a = take(n * n).T.reshape(N, n, n)
        return a[0].copy() if np.all(a == a[:1]) else a

    M, C, K = matrix(), matrix(), matrix()
    batch_harmonics = []
    for variables in layout.frequencies:
        omega = take(1)[0]
        f_s, f_c = take(n).T, take(n).T
        sig = take(2 * len(variables)).reshape(len(variables), 2, N)
        sign = np.where(omega < 0, -1.0, 1.0)
        static = omega == 0
        f_s = np.where(static[:, None], 0.0, sign[:, None] * f_s)
        signals = {var: (np.where(static, 0.0, sign * sig[k, 0]), sig[k, 1].copy())
                   for k, var in enumerate(variables)}
        batch_harmonics.append(_Harmonic(np.abs(omega), _squeeze(f_s), _squeeze(f_c), signals))
    outputs = {}
    for name, variables in layout.outputs:
        take(1)  # the output's value at the reference state: not part of a response
        coefs = take(len(variables))
        outputs[name] = dict(zip(variables, coefs))
    return _Batch(eom.coordinates, M, C, K, batch_harmonics, outputs, model.title)


def _squeeze(vectors: np.ndarray) -> np.ndarray:
    """(N, n) -> (n,) when every row is the same (a constant force vector)."""
    return vectors[0].copy() if np.all(vectors == vectors[:1]) else vectors


# -- solvers ------------------------------------------------------------------------------

def _bandwidths(*matrices: Any) -> tuple[int, int]:
    lower = upper = 0
    for a in matrices:
        if hasattr(a, "tocoo"):
            coo = a.tocoo()
            rows, cols = coo.row[coo.data != 0], coo.col[coo.data != 0]
        else:
            rows, cols = np.nonzero(a)
        if rows.size:
            lower = max(lower, int((rows - cols).max()))
            upper = max(upper, int((cols - rows).max()))
    return lower, upper


def _is_proportional(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> bool:
    """C M^-1 K = K M^-1 C (Caughey & O'Kelly): the undamped modes diagonalize C."""
    if not np.any(C):
        return True
    minv_k = np.linalg.solve(M, K)
    minv_c = np.linalg.solve(M, C)
    lhs, rhs = C @ minv_k, K @ minv_c
    scale = np.linalg.norm(C) * np.linalg.norm(minv_k) + 1e-300
    return bool(np.linalg.norm(lhs - rhs) <= 1e-9 * scale)


def choose_method(batch_or_matrices: Any, n_points: int = 1) -> str:
    """The method ``method="auto"`` uses for a sweep.

    Matrices that change with the parameter: ``dense`` (stacked solve).
    Fixed matrices: ``dense`` for n <= 40 (one batched LAPACK call beats a
    Python loop); ``banded`` when the total bandwidth is at most n/10 (cost
    n * bandwidth^2 per point, exact); ``sparse`` for other sparse matrices
    with few nonzeros; ``modal`` for dense symmetric, proportionally damped
    systems with n <= 3000 (one eigendecomposition, then n^2 per point);
    ``dense`` otherwise.
    """
    b = batch_or_matrices
    if not b.constant:
        return "dense"
    n = len(b.coordinates)
    if n <= 40:
        return "dense"
    lower, upper = _bandwidths(b.M, b.C, b.K)
    if lower + upper + 1 <= max(3, n // 10):
        return "banded"
    sparse = any(hasattr(a, "tocsr") for a in (b.M, b.C, b.K))
    if sparse:
        nnz = sum(a.nnz if hasattr(a, "nnz") else np.count_nonzero(a) for a in (b.M, b.C, b.K))
        if nnz < 0.05 * n * n or n > 3000:
            return "sparse"
    if n <= 3000:
        M, C, K = (_dense(a) for a in (b.M, b.C, b.K))
        if _symmetric(M) and _symmetric(K) and _symmetric(C) and _is_proportional(M, C, K):
            return "modal"
    return "dense" if n <= 3000 else "sparse"


def _dense(a: Any) -> np.ndarray:
    return a.toarray() if hasattr(a, "toarray") else np.asarray(a)


def _symmetric(a: np.ndarray) -> bool:
    return bool(np.allclose(a, a.T, rtol=1e-12, atol=1e-12 * (np.abs(a).max() if a.size else 0)))


class _Progress:
    """A plain text progress bar on standard error (no dependency)."""

    def __init__(self, total: int, enabled: bool, label: str = "sweep") -> None:
        self.total, self.enabled, self.label = max(total, 1), enabled, label
        self.last = 0.0
        self.done = 0

    def advance(self, count: int = 1) -> None:
        self.done += count
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self.last < 0.2 and self.done < self.total:
            return
        self.last = now
        frac = min(1.0, self.done / self.total)
        bar = "#" * int(30 * frac)
        sys.stderr.write(f"\r{self.label} [{bar:<30}] {100 * frac:5.1f}%")
        if self.done >= self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


class _Store:
    """The responses kept from the solves: only the columns ``keep`` (memory stays
    bounded for large models), plus the largest |component| of every full solution."""

    def __init__(self, N: int, keep: np.ndarray) -> None:
        self.keep = keep
        self.values = np.empty((N, len(keep)), dtype=complex)
        self.largest = np.zeros(N)

    def __setitem__(self, index: Any, x: Any) -> None:
        x = np.asarray(x, dtype=complex)
        if x.ndim == 0:
            self.values[index] = x
            self.largest[index] = abs(x)
            return
        self.values[index] = x[..., self.keep]
        with np.errstate(invalid="ignore"):
            self.largest[index] = np.abs(x).max(axis=-1)

    def __getitem__(self, index: Any) -> np.ndarray:
        return self.values[index]


def _solve_harmonic(batch: _Batch, h: _Harmonic, method: str, progress: _Progress,
                    warnings: list[str], keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Complex responses Z = L - i N of the columns ``keep``, shape (N, len(keep)), and a
    per-point "singular" mask."""
    w = h.omega
    N = w.shape[0]
    rhs = np.asarray(h.F_C, dtype=complex) - 1j * np.asarray(h.F_S, dtype=float)
    if not np.any(rhs):
        progress.advance(N)
        return np.zeros((N, len(keep)), dtype=complex), np.zeros(N, dtype=bool)
    store = _Store(N, keep)
    if method == "dense":
        singular = _solve_dense(batch, w, rhs, progress, store)
    elif method == "banded":
        singular = _solve_banded(batch, w, rhs, progress, store)
    elif method == "sparse":
        singular = _solve_sparse(batch, w, rhs, progress, store)
    else:
        singular = _solve_modal(batch, w, rhs, progress, warnings, store)
    Z = store.values
    # a lower bound of the condition number: ||A|| ||Z|| / ||rhs|| (exact resonance: huge)
    norms = [_norm_inf(a) for a in (batch.K, batch.M, batch.C)]
    a_norm = norms[0] + w**2 * norms[1] + w * norms[2]
    b_norm = np.abs(rhs).max(axis=-1) * np.ones(N)
    with np.errstate(all="ignore"):
        estimate = a_norm * store.largest / np.where(b_norm > 0, b_norm, np.inf)
    singular |= ~np.isfinite(store.largest) | ~(estimate <= SINGULAR_CONDITION)
    singular &= b_norm > 0
    Z[singular] = np.nan
    return Z, singular


def _norm_inf(a: Any) -> Any:
    if hasattr(a, "tocsr"):
        return float(abs(a).sum(axis=1).max()) if a.nnz else 0.0
    return np.abs(a).sum(axis=-1).max(axis=-1)


def _solve_dense(batch: _Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                 Z: _Store) -> np.ndarray:
    N, n = w.shape[0], len(batch.coordinates)
    M, C, K = (a.toarray() if hasattr(a, "toarray") else a for a in (batch.M, batch.C, batch.K))
    chunk = max(1, int(CHUNK_BYTES // (16 * n * n)))
    singular = np.zeros(N, dtype=bool)
    for start in range(0, N, chunk):
        sl = slice(start, min(N, start + chunk))
        ww = w[sl, None, None]
        pick = (lambda a: a[sl] if a.ndim == 3 else a)  # noqa: E731
        A = pick(K) - ww**2 * pick(M) + 1j * ww * pick(C)
        b = np.broadcast_to(rhs[sl] if rhs.ndim == 2 else rhs, (A.shape[0], n))
        try:
            Z[sl] = np.linalg.solve(A, b[..., None])[..., 0]
        except np.linalg.LinAlgError:  # an exactly singular point: solve point by point
            for i in range(A.shape[0]):
                try:
                    Z[start + i] = np.linalg.solve(A[i], b[i])
                except np.linalg.LinAlgError:
                    Z[start + i] = np.nan
                    singular[start + i] = True
        if n <= 64:  # cheap exact condition numbers, the same test as `resonant solve`
            with np.errstate(all="ignore"):
                cond = np.linalg.cond(A)
            singular[sl] |= ~(cond <= SINGULAR_CONDITION)
        progress.advance(A.shape[0])
    return singular


def _band_storage(a: Any, lower: int, upper: int, rows: int, offset: int) -> np.ndarray:
    """LAPACK band storage: ab[offset + upper + i - j, j] = a[i, j]."""
    n = a.shape[0]
    ab = np.zeros((rows, n))
    coo = a.tocoo() if hasattr(a, "tocoo") else None
    if coo is not None:
        i, j, v = coo.row, coo.col, coo.data
    else:
        i, j = np.nonzero(a)
        v = a[i, j]
    np.add.at(ab, (offset + upper + i - j, j), v)
    return ab


def _solve_banded(batch: _Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                  Z: _Store) -> np.ndarray:
    from scipy.linalg import lapack

    N = w.shape[0]
    lower, upper = _bandwidths(batch.M, batch.C, batch.K)
    singular = np.zeros(N, dtype=bool)
    varying_rhs = rhs.ndim == 2
    if lower == upper == 1:  # tridiagonal: LAPACK gtsv (partial pivoting)
        storage = [_band_storage(a, 1, 1, 3, 0) for a in (batch.M, batch.C, batch.K)]
        gtsv = lapack.get_lapack_funcs("gtsv", (np.zeros(1, complex),))

        def solve(ab: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, int]:
            _, _, _, x, info = gtsv(ab[2, :-1], ab[1], ab[0, 1:], b)
            return x, info
    else:
        rows = 2 * lower + upper + 1  # gbsv needs lower extra rows for the LU fill-in
        storage = [_band_storage(a, lower, upper, rows, lower)
                   for a in (batch.M, batch.C, batch.K)]
        gbsv = lapack.get_lapack_funcs("gbsv", (np.zeros(1, complex),))

        def solve(ab: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, int]:
            _, _, x, info = gbsv(lower, upper, ab, b, overwrite_ab=True)
            return x, info
    Mb, Cb, Kb = storage
    for i in range(N):
        wi = w[i]
        x, info = solve(Kb - (wi * wi) * Mb + (1j * wi) * Cb, rhs[i] if varying_rhs else rhs)
        if info != 0:
            singular[i] = True
            x = np.nan
        Z[i] = x
        if i % 64 == 63:
            progress.advance(64)
    progress.advance(N % 64)
    return singular


def _solve_sparse(batch: _Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                  Z: _Store) -> np.ndarray:
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    N = w.shape[0]
    M, C, K = (sp.csc_matrix(a) for a in (batch.M, batch.C, batch.K))
    singular = np.zeros(N, dtype=bool)
    for i in range(N):
        wi = w[i]
        A = (K - (wi * wi) * M + (1j * wi) * C).tocsc()
        b = rhs[i] if rhs.ndim == 2 else rhs
        try:
            Z[i] = splu(A).solve(np.asarray(b, dtype=complex))
        except RuntimeError:  # "Factor is exactly singular"
            Z[i] = np.nan
            singular[i] = True
        progress.advance()
    return singular


def _solve_modal(batch: _Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                 warnings: list[str], store: _Store) -> np.ndarray:
    """Superposition of all undamped modes (exact for proportional damping), checked."""
    import scipy.linalg

    M, C, K = (_dense(a).astype(float) for a in (batch.M, batch.C, batch.K))
    if not (_symmetric(M) and _symmetric(K) and _symmetric(C)):
        raise AnalysisError("method 'modal' needs symmetric M, C and K (no gyroscopic or "
                            "circulatory terms); use 'dense', 'banded' or 'sparse'")
    try:
        lam, phi = scipy.linalg.eigh(K, M)
    except np.linalg.LinAlgError:
        raise AnalysisError("method 'modal' needs a positive definite mass matrix") from None
    modal_c = phi.T @ C @ phi
    diag_c = np.diag(modal_c).copy()
    off = modal_c - np.diag(diag_c)
    if np.abs(off).max(initial=0.0) > 1e-9 * max(np.abs(diag_c).max(initial=0.0), 1e-300):
        raise AnalysisError("method 'modal' needs proportional damping (C M^-1 K = K M^-1 C): "
                            "the undamped modes do not decouple C; use 'dense', 'banded' or "
                            "'sparse'")
    N, n = w.shape[0], len(batch.coordinates)
    forces = (rhs @ phi) if rhs.ndim == 2 else np.broadcast_to(rhs @ phi, (N, n))

    def modal(sl: Any) -> np.ndarray:
        ww = w[sl, None]
        with np.errstate(all="ignore"):
            return (forces[sl] / (lam - ww**2 + 1j * ww * diag_c)) @ phi.T

    chunk = max(1, int(CHUNK_BYTES // (16 * n)))
    for start in range(0, N, chunk):
        sl = slice(start, min(N, start + chunk))
        store[sl] = modal(sl)
        progress.advance(sl.stop - sl.start)
    singular = ~np.isfinite(store.largest)
    # check: the same as a direct solve at the largest response and both ends
    check = sorted({0, N - 1, int(np.argmax(np.where(singular, -np.inf, store.largest)))})
    for i in check:
        if singular[i]:
            continue
        b = rhs[i] if rhs.ndim == 2 else rhs
        try:
            direct = np.linalg.solve(K - w[i]**2 * M + 1j * w[i] * C, b)
        except np.linalg.LinAlgError:
            continue
        error = np.abs(modal(slice(i, i + 1))[0] - direct).max() / max(
            np.abs(direct).max(), 1e-300)
        if error > MODAL_TOLERANCE:
            warnings.append(f"modal superposition differs from the direct solve by {error:.2g} "
                            f"at {w[i]:.6g} rad/s; solved directly instead")
            banded = sum(_bandwidths(M, C, K)) + 1 <= max(3, n // 10)
            return (_solve_banded if banded else _solve_dense)(batch, w, rhs,
                                                              _Progress(N, False), store)
    return singular


# -- amplitudes, phases, extrema ------------------------------------------------------------

def _kept_names(batch: _Batch, names: Sequence[str]) -> list[str]:
    """The coordinates whose responses are kept: those reported and those outputs use."""
    wanted = set(names)
    for terms in batch.outputs.values():
        wanted |= {var for var, _ in terms}
    return [q for q in batch.coordinates if q in wanted]


def _responses(batch: _Batch, responses: list[np.ndarray], names: Sequence[str]
               ) -> tuple[list[str], np.ndarray]:
    """The selected coordinates and every output: names and Z, shape (H, N, m)."""
    index = {q: k for k, q in enumerate(_kept_names(batch, names))}
    columns = [index[q] for q in names]
    out_names = list(names) + list(batch.outputs)
    if not batch.outputs and len(responses) == 1 and columns == list(range(len(index))):
        return out_names, responses[0][None]  # all kept coordinates in order: no copy
    N = responses[0].shape[0] if responses else 0
    Z = np.empty((len(responses), N, len(out_names)), dtype=complex)
    for k, (h, R) in enumerate(zip(batch.harmonics, responses)):
        Z[k, :, :len(columns)] = R[:, columns]
        for m, terms in enumerate(batch.outputs.values(), start=len(columns)):
            z = np.zeros(N, dtype=complex)
            for (var, order), coef in terms.items():
                if var in index:
                    z = z + coef * (1j * h.omega) ** order * R[:, index[var]]
                else:
                    s, c = h.signals.get((var, order), (0.0, 0.0))
                    z = z + coef * (np.asarray(c) - 1j * np.asarray(s))
            Z[k, :, m] = z
    return out_names, Z


def _amplitude_phase(omegas: np.ndarray, Z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude and phase, shape (N, m), with the semantics of :func:`stationary.peak`.

    ``omegas`` (H, N) are the harmonics' frequencies, ``Z`` (H, N, m) the responses.
    """
    from .stationary import peak

    H, N, m = Z.shape
    bad = ~np.isfinite(Z).all(axis=0)
    if H == 1:
        L, Nn = Z[0].real, -Z[0].imag
        static = (omegas[0] == 0)[:, None]
        amplitude = np.where(static, np.abs(L), np.hypot(L, Nn))
        with np.errstate(invalid="ignore"):
            phase = np.where(~static & (amplitude > 0), np.arctan2(L, Nn), np.nan)
    else:
        amplitude = np.full((N, m), np.nan)
        phase = np.full((N, m), np.nan)
        for i in range(N):
            # merge harmonics that coincide at this point (superposition)
            groups: dict[float, list[int]] = {}
            for k, w in enumerate(omegas[:, i]):
                key = next((g for g in groups if math.isclose(g, w, rel_tol=1e-12,
                                                              abs_tol=0.0)), float(w))
                groups.setdefault(key, []).append(k)
            freqs = list(groups)
            merged = np.array([Z[ks, i, :].sum(axis=0) for ks in groups.values()])
            active = [k for k, f in enumerate(freqs) if f > 0]
            for j in range(m):
                if bad[i, j]:
                    continue
                pairs = tuple((float(z.real), float(-z.imag)) for z in merged[:, j])
                amplitude[i, j] = peak(freqs, pairs)
                if len(active) == 1 and math.hypot(*pairs[active[0]]) > 0:
                    phase[i, j] = math.atan2(*pairs[active[0]])
    amplitude[bad] = np.nan
    phase[bad] = np.nan
    return amplitude, phase


def _vertices(u: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices of the parabolas through point triples (any spacing), kept in [u0, u2].

    ``u`` and ``y`` have shape (3, m): one triple per column.
    """
    (u0, u1, u2), (y0, y1, y2) = u, y
    with np.errstate(all="ignore"):
        d01, d12 = (y1 - y0) / (u1 - u0), (y2 - y1) / (u2 - u1)
        a = (d12 - d01) / (u2 - u0)
        b = d01 - a * (u0 + u1)
        x = np.clip(-b / (2 * a), u0, u2)
        value = y0 + d01 * (x - u0) + a * (x - u0) * (x - u1)
    flat = ~np.isfinite(x) | (a == 0)
    return np.where(flat, u1, x), np.where(flat, y1, value)


#: a grid point is an extremum only if it differs from a neighbour by more than this
#: (relative): rounding noise on a flat curve is not a peak
EXTREMUM_RELATIVE = 1e-10


def _extrema(names: Sequence[str], values: np.ndarray, amplitude: np.ndarray, log: bool,
             response: np.ndarray | None = None) -> tuple[ExtremaTable, ExtremaTable]:
    """Peaks and antiresonances of every column of ``amplitude`` (N, m), in name order.

    ``response`` (N, m), the complex response of a single-frequency sweep, refines deep
    antiresonances (a zero of the response between grid points): with the local linear
    model z(u) = z1 + beta (u - u1), beta = (z2 - z0)/(u2 - u0), |z| is least at
    u = u1 - Re(conj(beta) z1)/|beta|^2 (exact where z is linear in u).
    """
    N, m = amplitude.shape
    names = tuple(names)
    if N < 3 or m == 0:
        return ExtremaTable(names), ExtremaTable(names)
    finite = np.isfinite(amplitude)
    top = np.where(finite, amplitude, -np.inf).max(axis=0)
    u = np.log(values) if log else values
    a0, a1, a2 = amplitude[:-2], amplitude[1:-1], amplitude[2:]
    ok = finite[:-2] & finite[1:-1] & finite[2:] & (top > 0)
    margin = EXTREMUM_RELATIVE * np.maximum(np.maximum(a0, a1), a2)
    with np.errstate(invalid="ignore"):
        is_peak = ok & (a1 >= a0) & (a1 >= a2) & (a1 - np.minimum(a0, a2) > margin) & \
            (a1 > 1e-9 * top) & (a0 > 0) & (a2 > 0)
        is_dip = ok & (a1 <= a0) & (a1 <= a2) & (np.maximum(a0, a2) - a1 > margin) & \
            (np.maximum(a0, a2) > 1e-9 * top)
    out = []
    for mask, transform, back in ((is_peak, np.log, np.exp),
                                  (is_dip, np.square, lambda y: np.sqrt(np.maximum(y, 0)))):
        cols, rows = np.nonzero(mask.T)      # name-major order
        rows = rows + 1
        triples = np.stack([rows - 1, rows, rows + 1])
        with np.errstate(all="ignore"):
            x, y = _vertices(u[triples], transform(amplitude[triples, cols]))
        y = back(y)
        if response is not None and mask is is_dip and cols.size:
            z0, z1, z2 = response[triples, cols]
            u0, u1, u2 = u[triples]
            deep = np.abs(z1) < 0.1 * np.maximum(np.abs(z0), np.abs(z2))
            with np.errstate(all="ignore"):
                beta = (z2 - z0) / (u2 - u0)
                step = -(np.conj(beta) * z1).real / np.abs(beta) ** 2
                linear_x = np.clip(u1 + np.where(np.isfinite(step), step, 0.0), u0, u2)
            x = np.where(deep, np.exp(linear_x) if log else linear_x, np.exp(x) if log else x)
            y = np.where(deep, np.abs(z1 + beta * (linear_x - u1)), y)
            out.append(ExtremaTable(names, cols, x, y))
            continue
        out.append(ExtremaTable(names, cols, np.exp(x) if log else x, y))
    return out[0], out[1]


# -- the public function ------------------------------------------------------------------

def sweep(source: Any, param: str, values: Sequence[float] | np.ndarray, *,
          method: str = "auto", names: Sequence[str] | None = None,
          progress: bool | None = None, log: bool | None = None) -> FrequencyResponse:
    """Stationary amplitude and phase of every coordinate and output against a parameter.

    Parameters
    ----------
    source : Model, LinearEOM, NumericEOM or MatrixSystem
        The system; with a NumericEOM or MatrixSystem that does not carry its
        model, only ``param="omega"`` (the excitation frequency) is possible.
    param : str
        The parameter to vary (parameters defined from it follow it).
    values : array_like
        Its values (at least one; finite).
    method : {"auto", "dense", "banded", "sparse", "modal"}
        How to solve; see the module docstring.  ``auto`` picks with
        :func:`choose_method`.
    names : sequence of str, optional
        The coordinates to report (default all; outputs are always reported).
    progress : bool, optional
        Show a text progress bar on standard error (default: when standard
        error is a terminal and the sweep is long).
    log : bool, optional
        Whether the values are logarithmically spaced (for peak refinement
        and plots); detected from the values when omitted.

    Returns
    -------
    FrequencyResponse

    Raises
    ------
    ModelError
        For an unknown parameter or values that make the model invalid.
    AnalysisError
        For a method that does not fit the system (``modal`` with
        non-proportional damping, ``banded`` with matrices that change).
    """
    if method not in METHODS:
        raise AnalysisError(f"unknown method '{method}'; choose one of {', '.join(METHODS)}")
    values = np.asarray(values, dtype=float).ravel()
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise AnalysisError("the sweep needs at least one finite parameter value")
    batch = _batch(source, param, values)
    n = len(batch.coordinates)
    if names is None:
        names = list(batch.coordinates)
        if n > MAX_DEFAULT_NAMES:
            # a full table of a huge model is neither wanted nor storable: report the
            # loaded coordinates (select others with names=/--only)
            loaded = set()
            for h in batch.harmonics:
                for f in (h.F_S, h.F_C):
                    loaded |= set(np.nonzero(np.atleast_2d(f).any(axis=0))[0].tolist())
            names = [batch.coordinates[i] for i in sorted(loaded)] or [batch.coordinates[-1]]
            default_note = (f"{n} coordinates: only the loaded ones ({', '.join(names[:5])}"
                            f"{' ...' if len(names) > 5 else ''}) are reported; choose others "
                            "with names= (--only)")
        else:
            default_note = ""
    else:
        default_note = ""
    known = set(batch.coordinates)
    unknown = [q for q in names if q not in known]
    if unknown:
        raise AnalysisError(f"unknown coordinate(s) {', '.join(unknown)}; the coordinates are "
                            f"{', '.join(batch.coordinates[:20])}"
                            f"{' ...' if n > 20 else ''}")
    if method == "auto":
        method = choose_method(batch, len(values))
    elif method in ("banded", "sparse", "modal") and not batch.constant:
        raise AnalysisError(f"method '{method}' needs M, C and K that do not depend on "
                            f"'{param}'; use 'dense'")
    _check_mass(batch)
    warnings: list[str] = [default_note] if default_note else []
    if progress is None:
        progress = sys.stderr.isatty() and len(values) * n * max(n, 1) > 5e7
    bar = _Progress(len(values) * max(len(batch.harmonics), 1), bool(progress))
    responses, skipped_mask = [], np.zeros(len(values), dtype=bool)
    position = {q: i for i, q in enumerate(batch.coordinates)}
    keep = np.array([position[q] for q in _kept_names(batch, names)], dtype=int)
    for h in batch.harmonics:
        Z, singular = _solve_harmonic(batch, h, method, bar, warnings, keep)
        responses.append(Z)
        skipped_mask |= singular
    if not batch.harmonics:
        warnings.append("the model has no harmonic excitation: every amplitude is zero")
    if log is None:
        log = bool(len(values) > 2 and np.all(values > 0) and
                   np.allclose(np.diff(np.log(values)), np.log(values[1] / values[0]),
                               rtol=1e-6) and not np.allclose(np.diff(values),
                                                              values[1] - values[0], rtol=1e-9))
    if batch.harmonics:
        all_names, Z = _responses(batch, responses, names)
    else:
        all_names = list(names) + list(batch.outputs)
        Z = np.zeros((0, len(values), len(all_names)), dtype=complex)
    omegas = np.array([np.broadcast_to(h.omega, values.shape) for h in batch.harmonics],
                      dtype=float).reshape(len(batch.harmonics), len(values))
    skipped = tuple(float(v) for v in values[skipped_mask])
    if skipped:
        shown = ", ".join(f"{v:.6g}" for v in skipped[:5])
        warnings.append(
            f"no stationary solution at {param} = {shown}{' ...' if len(skipped) > 5 else ''} "
            "(undamped resonance: the amplitude is unbounded); these points are skipped "
            "(NaN, null in JSON)")
    frequency_sweep = batch.constant and any(
        np.ptp(h.omega) > 0 for h in batch.harmonics)
    natural = None
    if batch.constant and n <= EAGER_EIGEN:
        from .stability import natural_frequencies

        try:
            natural = natural_frequencies(_dense(batch.M), _dense(batch.K))
        except (np.linalg.LinAlgError, ValueError):
            natural = None
    return FrequencyResponse(
        parameter=param, values=values, quantities=tuple(all_names), response=Z,
        harmonic_omegas=omegas, method=method, frequency_sweep=bool(frequency_sweep), natural_frequencies=natural,
        skipped=skipped, warnings=tuple(dict.fromkeys(warnings)), log=bool(log),
        title=batch.title, coordinates=tuple(batch.coordinates))


def _check_mass(batch: _Batch) -> None:
    """A singular mass matrix is an error (exit 3), as for ``resonant solve``."""
    M = batch.M
    if hasattr(M, "tocsr"):
        if (abs(M).sum(axis=1) == 0).any():
            row = int(np.argmax(np.asarray(abs(M).sum(axis=1)).ravel() == 0))
            raise AnalysisError(f"the mass matrix M is singular ({batch.coordinates[row]} "
                                "has no inertia)")
        return
    from .stability import check_mass_matrix

    if np.ndim(M) == 2 and M.shape[0] <= EAGER_EIGEN:
        check_mass_matrix(M, tuple(batch.coordinates))
    elif np.ndim(M) == 3:
        check_mass_matrix(M[0], tuple(batch.coordinates))


def linspace(start: float, stop: float, points: int, log: bool = False) -> np.ndarray:
    """The sweep values: evenly spaced, or logarithmically (``log=True``, positive ends)."""
    if points < 1:
        raise AnalysisError("--points must be at least 1")
    if log:
        if start <= 0 or stop <= 0:
            raise AnalysisError("a logarithmic sweep needs positive --from and --to")
        return np.geomspace(start, stop, points)
    return np.linspace(start, stop, points)


__all__ = ["sweep", "FrequencyResponse", "Extremum", "ExtremaTable", "choose_method", "parameter_values",
           "linspace", "METHODS"]
