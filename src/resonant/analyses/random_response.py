"""The stationary response to random excitation given by spectral densities.

For inputs u_j with the one-sided cross-spectral density matrix G_u(f) (per Hz), every
coordinate and output y has the one-sided density (Newland, *An Introduction to Random
Vibrations*, Ch. 7; Bendat & Piersol, *Random Data*, Ch. 6)::

    G_y(f) = sum_jl H_yj(f) G_u,jl(f) conj(H_yl(f))

where H_yj is the complex frequency response of y to u_j.  H comes from the one harmonic
kernel (:func:`resonant.analyses.kernel.solve_harmonic`): one solve of
(K - w^2 M + i w C) z = E per load column E of the inputs, at every frequency of the
grid, w = 2 pi f; a signal's derivative of order k seen by an input given as the density
of its derivative of order m contributes (i w)^(k - m).

From G_y: the mean square m0 = integral of G_y df (the RMS about the reference state; no
mean value is included), the spectral moments m_k = integral of f^k G_y df, Rice's rates of
zero up-crossings sqrt(m2/m0) and of peaks sqrt(m4/m2) (Hz), and 3-sigma = 3 RMS.

The frequency grid starts from ``lines`` logarithmically spaced frequencies of the band,
the table breakpoints and the damped natural frequencies (with points at their half-power
width), and is refined pair by pair: each pair of intervals is integrated by Simpson's rule
and its error estimated by Richardson's (fine - coarse)/3 of the composite trapezoid; pairs
are halved until the estimated error of every mean square is below the tolerance.

Where the kernel would take a reduced model (large sparse matrices), one reduced model of
the band (:func:`resonant.analyses.reduced.reduced_model`) serves every refinement round
(:meth:`Transfer.reduce`), and a bound of its error, from its estimated normwise error
and the adjoint residuals of the response coordinates, is integrated beside each density
and added to the quadrature's estimate (docs/random.md).

For a single-DOF model driven by one input, ``miles`` holds the estimate of Miles' equation
RMS^2 = (pi/2) f_n Q G_u(f_n) g^2 beside the exact value, for every response that has a
static gain g (|H| flat below f_n/100, extrapolated to f = 0) and resonates
(|H(f_n)| > g Q/2): for the absolute acceleration under a base acceleration g = 1 and this
is Miles' equation (Miles 1954).  Responses without a static gain (an absolute
displacement under a base acceleration, a velocity) have no entry.

Examples
--------
>>> import resonant
>>> from resonant.model import loads
>>> model = loads('''
... [parameters]
... m = 1
... k = 400
... c = 0.4
... [coordinates]
... x = ""
... [signals]
... F = "0"
... [energy]
... T = "m*x'^2/2"
... U = "k*x^2/2 - F*x"
... D = "c*x'^2/2"
... [random]
... band = [0, 1000]
... [random.psd.F]
... values = 1e-2
... ''')
>>> result = random_response(resonant.system.linear_system(model))
>>> round(result.rms["x"] ** 2 / (1e-2 / (4 * 400 * 0.4)), 4)   # G0 / (4 k c)
1.0
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import Matrix, freeze_fields
from ..charts import (
    MAX_CURVES,
    Chart,
    Charts,
    Curve,
    PathArg,
    Rule,
    axes_list,
    check_plot_path,
    draw_figure,
    save_figure,
    unit_text,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem, name_list, printable
from ..expressions import numeric_value
from ..memory import chunk_rows
from ..modal import point_state_eigenvalues
from ..model.random_spec import STANDARD_GRAVITY, RandomInput, RandomSpec
from ..model.units import Dimension
from ..model.units_display import ResultUnits, Shown, density_unit, shown_unit
from ..system.base import LinearSystem, NumericEOM
from ..system.batch import Batch, BatchHarmonic
from ..system.excitation import excitation_columns
from ..system.output_map import output_map
from ..system.stability import UNSTABLE, classify
from ..tables import ResultTable, number_cell
from .forward_error import accuracy_warning
from .kernel import reduced_budget, require_kept, solve_harmonic
from .reduced import FactorizationsAhead, ReducedModel, probe_frequency, reduced_model
from .result_fields import FieldsJSON, saved
from .results_json import optional_float
from .threads import blas_threads

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: most frequency points of the refined grid
MAX_POINTS = 400_000
#: most refinement rounds
MAX_ROUNDS = 60
#: damped natural frequencies are located for systems up to this many coordinates
MODES_LIMIT = 400
#: the band's reduced model is asked for this fraction of the quadrature's tolerance ...
REDUCED_TOLERANCE = 1e-1
#: ... within these bounds (its residual has a rounding floor near 1e-10)
REDUCED_TOLERANCE_RANGE = (1e-8, 1e-4)
#: the reduced model's basis also holds the adjoint (a unit load) of each response
#: coordinate, for up to this many coordinates: its residual bounds their errors far
#: below the normwise estimate
ADJOINT_LIMIT = 16
#: ``auto`` keeps the band's reduced model only when its estimated error is below this
#: (else the kernel solves each round's frequencies itself)
REDUCED_ACCEPT = 1e-3


@dataclass(frozen=True)
class RandomResponse(FieldsJSON):
    """The response spectral densities, RMS values and Rice's rates of every coordinate
    and output.

    Attributes
    ----------
    title : str
        The model's title.
    names : tuple of str
        The responses: the coordinates, then the outputs.
    inputs : tuple of str
        The random inputs.
    frequency : ndarray
        The frequency grid (Hz), shape (N,).
    psd : mapping
        name -> one-sided spectral density per Hz (SI unit squared per Hz), shape (N,).
    input_psd : mapping
        input -> its one-sided density per Hz (SI) on the grid.
    rms : mapping
        name -> RMS value (SI) about the reference state.
    zero_crossing_rate : mapping
        name -> expected rate of zero up-crossings sqrt(m2/m0) (Hz; NaN for RMS 0).
    peak_rate : mapping
        name -> expected rate of peaks sqrt(m4/m2) (Hz; NaN where m2 = 0).
    error : mapping
        name -> estimated relative error of the mean square's quadrature.
    units : mapping
        name -> SI unit of the response ("" where the model has no units).
    input_units : mapping
        input -> SI unit of the quantity whose density it is ("" where unknown).
    input_derivatives : mapping
        input -> the order of the signal's derivative whose density it is.
    band : tuple of float
        The band (Hz).
    miles : mapping or None
        name -> Miles' RMS estimate of each resonant response (single-DOF model, one
        input), else None.
    natural_frequency, quality : float or None
        f_n (Hz) and Q = 1/(2 zeta) of a single-DOF model.
    method : str
        The kernel's method.
    warnings : tuple of str

    Examples
    --------
    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`: the JSON of
    ``resonant random``, one record per input and per response) and read back:

    >>> import json, resonant
    >>> r = resonant.load("examples/shaker_gevs.toml").random_response()
    >>> sorted(r.to_dict()["responses"]["x"])[:3]
    ['miles_rms', 'peak_rate_hz', 'relative_error']
    >>> back = RandomResponse.from_dict(json.loads(json.dumps(r.to_dict())))
    >>> back.to_dict() == r.to_dict()
    True
    """

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): SI numbers,
    #: frequencies in Hz, densities one-sided per Hz; one record per input and response
    _json_order = ("title", "convention", "band_hz", "inputs", "responses",
                   "natural_frequency_hz", "quality_factor", "frequency_hz", "psd",
                   "input_psd", "method", "warnings", "miles")
    _by_name = {"inputs": ("inputs", ("unit", "derivative")),
                "responses": ("names", ("unit", "rms", "three_sigma", "zero_crossing_rate_hz",
                                        "peak_rate_hz", "relative_error", "miles_rms"))}

    title: str = saved()
    names: tuple[str, ...] = saved(keys_of="responses")
    inputs: tuple[str, ...] = saved(keys_of="inputs")
    frequency: np.ndarray = saved(key="frequency_hz", axes=(None,))
    psd: Mapping[str, np.ndarray] = saved(axes=("frequency",), rows_by="names")
    input_psd: Mapping[str, np.ndarray] = saved(axes=("frequency",), rows_by="inputs")
    rms: Mapping[str, float] = saved(by_name="responses")
    zero_crossing_rate: Mapping[str, float] = saved(by_name="responses",
                                                    key="zero_crossing_rate_hz")
    peak_rate: Mapping[str, float] = saved(by_name="responses", key="peak_rate_hz")
    error: Mapping[str, float] = saved(by_name="responses", key="relative_error")
    units: Mapping[str, str] = saved(by_name="responses", key="unit", missing="")
    band: tuple[float, float] = saved(key="band_hz")
    input_units: Mapping[str, str] = saved(by_name="inputs", key="unit", missing="",
                                           default_factory=dict)
    input_derivatives: Mapping[str, int] = saved(by_name="inputs", key="derivative",
                                                 missing=0, default_factory=dict)
    miles: Mapping[str, float] | None = saved(None)
    natural_frequency: float | None = saved(None, key="natural_frequency_hz")
    quality: float | None = saved(None, key="quality_factor")
    method: str = saved("")
    warnings: tuple[str, ...] = saved(())

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def three_sigma(self) -> dict[str, float]:
        """name -> 3 RMS (the level exceeded with probability 0.27 % for a Gaussian)."""
        return {name: 3 * value for name, value in self.rms.items()}

    def _derived_json(self) -> dict[str, Any]:
        return {"convention": "one-sided spectral densities per Hz"}

    def _derived_record(self, group: str, name: str) -> dict[str, Any]:
        if group != "responses":
            return {}
        return {"three_sigma": 3 * self.rms[name],
                "miles_rms": None if self.miles is None else optional_float(
                    self.miles.get(name))}

    def summary(self, units: ResultUnits | None = None) -> str:
        """The text ``resonant random`` prints (:func:`random_text`).

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``; default SI).

        Returns
        -------
        str
        """
        return random_text(self, units=units)

    def table(self, units: ResultUnits | None = None) -> ResultTable:
        """The RMS, 3-sigma and Rice's rates of every response (:func:`random_table`).

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (default SI).

        Returns
        -------
        resonant.tables.ResultTable
        """
        return random_table(self, units)

    def chart(self, names: Sequence[str] | None = None,
              units: ResultUnits | None = None) -> Charts:
        """The figure's description: the inputs' and the responses' densities
        (:func:`random_chart`).

        Parameters
        ----------
        names : sequence of str, optional
            The responses to draw.
        units : ResultUnits, optional
            The display units (default SI).

        Returns
        -------
        resonant.charts.Charts
        """
        return random_chart(self, names, units)

    def plot(self, path: str | os.PathLike[str] | None = None,
             names: Sequence[str] | None = None, ax: Axes | None = None,
             units: ResultUnits | None = None) -> Figure:
        """The inputs' and the responses' spectral densities on log-log axes
        (:func:`resonant.analyses.random_response.plot_random`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        names : sequence of str, optional
            The responses to draw.
        ax : matplotlib.axes.Axes, optional
            Draw into the caller's axes.
        units : ResultUnits, optional
            The display units (default SI).

        Returns
        -------
        matplotlib.figure.Figure
        """
        return plot_random(self, path, names, ax, units)


@dataclass(frozen=True)
class _Load:
    """One load column of an input: the rhs and the power of (i w) it is multiplied by."""

    column: np.ndarray
    power: int
    #: the (signal, order) whose excitation column it is (None: a coordinate's unit load,
    #: or a given load or base vector)
    var: tuple[str, int] | None = None


class Transfer:
    """H(f) of every response (kept coordinates, then outputs) to every input, through the
    kernel (also the periodic loads' superposition, :mod:`.periodic_load`).

    Parameters
    ----------
    system : LinearSystem
    num : NumericEOM
        Its numbers at the parameter point.
    inputs : sequence of RandomInput
        The inputs: a signal (and the order of the derivative the input is), a coordinate,
        or a ``load``/``base`` vector; their densities are not used here.
    keep : ndarray of int
        The coordinates to solve for.
    method : str
        The kernel's method.
    deadline : Deadline
    """

    def __init__(self, system: LinearSystem, num: NumericEOM, inputs: Sequence[RandomInput],
                 keep: np.ndarray, method: str, deadline: Deadline) -> None:
        self.num, self.inputs, self.keep, self.method = num, tuple(inputs), keep, method
        self.deadline = deadline
        self.warnings: list[str] = []
        #: the frequencies solved so far and the kernel's estimated forward error at each
        self._errors: tuple[np.ndarray, np.ndarray] = (np.zeros(0), np.zeros(0))
        self._accuracy_text: str | None = None
        values = dict(num.parameters) or dict(system.model.parameter_values
                                              if system.model is not None else {})
        self.values = values
        columns = excitation_columns(system, values, deadline)
        self.loads = [self._loads(u, columns) for u in self.inputs]
        for u, loads in zip(self.inputs, self.loads):
            if not loads and not self._in_outputs(u.name):
                self.warnings.append(f"the input {u.name} does not act on the model (no "
                                     "generalized force and no output depends on it)")
        # distinct columns, one kernel solve each
        self.columns: list[np.ndarray] = []
        self.index: list[list[tuple[int, int]]] = []
        for loads in self.loads:
            entry = []
            for load in loads:
                same = [k for k, c in enumerate(self.columns)
                        if c.shape == load.column.shape and np.array_equal(c, load.column)]
                if not same:
                    self.columns.append(load.column)
                entry.append((same[0] if same else len(self.columns) - 1, load.power))
            self.index.append(entry)
        self.used_method = ""
        self.reduced: ReducedModel | None = None
        self.adjoint = np.ones(len(keep))

    def reduce(self, f: np.ndarray, tol: float) -> None:
        """Build one reduced model of the band for every load column, where the kernel
        would take a reduced model (``auto``: :func:`resonant.analyses.kernel.reduced_budget`
        says it pays; ``reduced``: always), and use it for every later call.

        Parameters
        ----------
        f : ndarray
            The frequencies (Hz) where the reduced model's error is estimated.
        tol : float
            Its relative tolerance (normwise, per load and frequency).
        """
        if self.method not in ("auto", "reduced") or not self.columns:
            return
        num = self.num
        w = 2 * np.pi * np.asarray(f, dtype=float)
        B = np.column_stack(self.columns).astype(complex)
        adjoint = len(self.keep) <= ADJOINT_LIMIT and _symmetric(num.M, num.C, num.K)
        unit = None
        if adjoint:
            unit = np.zeros((num.n, len(self.keep)), dtype=complex)
            unit[self.keep, np.arange(len(self.keep))] = 1.0
        budget = None
        probe: dict[float, Any] = {}
        # the model's other first expansion points are factorized during the cost probe
        ahead = FactorizationsAhead(num.M, num.C, num.K, w, (
            probe_frequency(w),) if self.method == "auto" else ())
        try:
            if self.method == "auto":
                batch = Batch(tuple(num.coordinates), num.M, num.C, num.K,
                              [BatchHarmonic(w, np.zeros(num.n), self.columns[0])], {},
                              num.title, True, len(w))
                # (one BLAS thread while the helper factorizes: a core each)
                with blas_threads(0.0) if ahead.futures else contextlib.nullcontext():
                    budget = reduced_budget(batch, w, np.asarray(B[:, 0]), probe)
                if budget is None:
                    return
            probe.update(ahead.futures)
            rom = reduced_model(num.M, num.C, num.K, B, w, tol=tol, deadline=self.deadline,
                                budget=budget, adjoints=unit, factorizations=probe)
        except AnalysisError:
            if self.method == "reduced":
                raise
            return
        finally:
            probe.clear()   # first: the helper's factors are then freed in its thread
            ahead.stop()
        worst = float(np.max(rom.estimated_error, initial=0.0))
        if self.method == "auto" and not worst <= REDUCED_ACCEPT:
            return
        if not rom.converged:
            self.warnings.append(f"the band's reduced model reached the estimated error "
                                 f"{worst:.2g}, not its tolerance {tol:.2g} ({rom.reason}); "
                                 "its error is included in the estimate of each mean square")
        self.reduced = rom
        # the adjoints' largest relative residuals (||e_i|| = 1)
        residuals = np.asarray(rom.adjoint_residuals)
        self.adjoint = (np.minimum(1.0, residuals) if len(residuals) == len(self.keep)
                        else np.ones(len(self.keep)))

    def _in_outputs(self, name: str) -> bool:
        return any(v[0] == name for out in self.num.outputs.values() for v in out.terms)

    def _vector(self, expressions: Sequence[Any]) -> np.ndarray:
        """The values of one expression per coordinate, each distinct expression evaluated
        once (a base vector of 250,000 ones is one expression)."""
        known: dict[Any, float] = {}
        out = np.empty(len(expressions))
        for i, e in enumerate(expressions):
            try:
                value = known.get(e)
            except TypeError:   # (an expression that cannot be hashed: evaluated each time)
                out[i] = float(numeric_value(e, self.values))
                continue
            if value is None:
                value = known[e] = float(numeric_value(e, self.values))
            out[i] = value
        return out

    def _finite(self, vector: np.ndarray, u: RandomInput, key: str) -> np.ndarray:
        """``vector``, or a ModelError naming its first entry that is not a finite number."""
        bad = np.flatnonzero(~np.isfinite(vector))
        if bad.size:
            i = int(bad[0])
            raise ModelError(Problem(
                f"entry {i + 1} (coordinate {self.num.coordinates[i]}) is {vector[i]}: the "
                f"{key} vector needs finite numbers", self.num.source, f"random.psd.{u.name}",
                key))
        return vector

    def _loads(self, u: RandomInput, columns: Mapping[Any, np.ndarray]) -> list[_Load]:
        n = self.num.n
        if u.load:
            return [_Load(self._finite(self._vector(u.load), u, "load"), 0)]
        if u.base:
            r = self._finite(self._vector(u.base), u, "base")
            return [_Load(-np.asarray(self.num.M @ r, dtype=float).ravel(), 0)]
        found = [_Load(np.asarray(c, dtype=float), order - u.derivative, (name, order))
                 for (name, order), c in sorted(columns.items()) if name == u.name]
        if found or u.name in (self.num.model.signals if self.num.model is not None else ()):
            return found
        if u.name in self.num.coordinates:
            column = np.zeros(n)
            column[self.num.coordinates.index(u.name)] = 1.0
            return [_Load(column, 0)]
        return found

    def amplitudes(self, f: np.ndarray, loads: np.ndarray,
                   along: Mapping[tuple[str, int], np.ndarray] | None = None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The inputs' complex amplitudes u that make up given loads, and what is left.

        At each line, the least-squares u of ``loads = sum_j B_j(w) u_j``, B_j the load of a
        unit input j (the sum of its columns times (i w)^power): the loads that the inputs
        make are made exactly (to rounding) by their u, an input whose columns the loads do
        not hold getting 0.  The columns are orthonormalized once (QR), so that a line
        costs a solve of (columns x inputs); the rest ``loads - sum_j B_j u_j`` is formed a
        chunk of lines at a time (:func:`resonant.memory.chunk_rows`).

        Parameters
        ----------
        f : ndarray
            The lines (Hz), (N,).
        loads : ndarray
            Complex generalized forces, (N, n) or (n,) for all lines
            (:attr:`resonant.system.batch.BatchHarmonic.complex_load`).
        along : mapping, optional
            ``(signal, order) -> (N, n)``: excitation columns that differ from line to
            line (they depend on the parameter the lines sweep,
            :func:`resonant.system.excitation.excitation_columns_along`), used in place
            of the fixed ones; then each line solves its own least squares.

        Returns
        -------
        u : ndarray
            (N, inputs) complex.
        left : ndarray
            (N,): the 2-norm of the rest, the part of the loads no input makes, over the
            loads' (0 where there is no load).
        worst : ndarray
            (n,): the largest |rest| of each coordinate over the lines.
        """
        w = 2 * np.pi * np.asarray(f, dtype=float).ravel()
        N, n, J = len(w), self.num.n, len(self.inputs)
        b = np.broadcast_to(np.asarray(loads, dtype=complex), (N, n))
        if along:
            return self._amplitudes_along(w, b, along)
        u = np.zeros((N, J), dtype=complex)
        left, worst = np.zeros(N), np.zeros(n)
        C = np.column_stack(self.columns) if self.columns else np.zeros((n, 0))
        Q, R = np.linalg.qr(C)
        P = np.zeros((N, C.shape[1], J), dtype=complex)
        for j, entry in enumerate(self.index):
            for k, power in entry:
                P[:, k, j] += (1j * w) ** power
        step = chunk_rows(16.0 * n, N)
        for start in range(0, N, step):
            rows = slice(start, start + step)
            if C.shape[1]:
                c = b[rows] @ Q                 # the loads in the columns' basis
                u[rows] = np.einsum("lji,li->lj", np.linalg.pinv(R @ P[rows], rcond=1e-12),
                                    c)
                rest = b[rows] - np.einsum("lkj,lj->lk", P[rows], u[rows]) @ C.T
            else:
                rest = np.array(b[rows])
            size = np.linalg.norm(b[rows], axis=1)
            left[rows] = np.linalg.norm(rest, axis=1) / np.where(size > 0, size, 1.0)
            worst = np.maximum(worst, np.abs(rest).max(axis=0, initial=0.0))
        return u, left, worst

    def _amplitudes_along(self, w: np.ndarray, b: np.ndarray,
                          along: Mapping[tuple[str, int], np.ndarray]
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`amplitudes` with columns that change from line to line: the unit load
        of each input at each line, B (lines, n, inputs), and a least squares per line."""
        N, n, J = len(w), self.num.n, len(self.inputs)
        u = np.zeros((N, J), dtype=complex)
        left, worst = np.zeros(N), np.zeros(n)
        step = chunk_rows(16.0 * n * (J + 2), N)
        for start in range(0, N, step):
            rows = slice(start, start + step)
            B = np.zeros((len(w[rows]), n, J), dtype=complex)
            for j, loads in enumerate(self.loads):
                for load in loads:
                    moving = along.get(load.var) if load.var is not None else None
                    column = moving[rows] if moving is not None else load.column
                    B[:, :, j] += (1j * w[rows])[:, None] ** load.power * column
            u[rows] = np.einsum("lji,li->lj", np.linalg.pinv(B, rcond=1e-12), b[rows])
            rest = b[rows] - np.einsum("lij,lj->li", B, u[rows])
            size = np.linalg.norm(b[rows], axis=1)
            left[rows] = np.linalg.norm(rest, axis=1) / np.where(size > 0, size, 1.0)
            worst = np.maximum(worst, np.abs(rest).max(axis=0, initial=0.0))
        return u, left, worst

    def __call__(self, f: np.ndarray, outputs: Sequence[str]) -> np.ndarray:
        """H (len(f), responses, inputs): the kept coordinates, then ``outputs``."""
        return self.with_bound(f, outputs)[0]

    def with_bound(self, f: np.ndarray, outputs: Sequence[str]
                   ) -> tuple[np.ndarray, np.ndarray | None]:
        """H as :meth:`__call__`, and a bound of |H - H_exact| of the same shape from the
        band's reduced model (None without one, the kernel's solves being exact).

        The reduced model's estimated normwise error eps_k of load column k gives
        |z_i - z_i,exact| <= ||z - z_exact|| <= eps_k ||z_k|| for every coordinate i.
        Where the model also holds the adjoint of coordinate i (a unit load e_i; A is
        symmetric, A^T = A), the Galerkin orthogonality V^T A (z - z_exact) = 0 gives
        e_i^T (z - z_exact) = r_i^T (z - z_exact) with r_i the adjoint's residual, so
        the bound is multiplied by its largest relative residual over the band
        (Becker & Rannacher's dual-weighted residual; computed, not estimated).  An output
        sum_t c_t (i w)^p_t q_t errs by at most sum_t |c_t| w^p_t times its coordinates'
        bounds.
        """
        w = 2 * np.pi * np.asarray(f, dtype=float)
        if self.reduced is not None:
            Zs, norms = self.reduced.responses(w, self.keep, len(self.columns))
            bad = ~np.all(np.isfinite(Zs), axis=(1, 2))
            if bad.any():
                where = float(f[int(np.argmax(bad))])
                raise AnalysisError(f"the system is singular at {where:.6g} Hz (an undamped "
                                    "resonance): the response there is unbounded; add "
                                    "damping")
            self.used_method = "reduced"
            Z = [Zs[:, :, k] for k in range(Zs.shape[2])]
            errors = norms * np.asarray(self.reduced.estimated_error)[None, :]
            return self._assemble(w, outputs, Z, errors)
        return self._assemble(w, outputs, self._solve(f, w), None)

    def _solve(self, f: np.ndarray, w: np.ndarray) -> list[np.ndarray]:
        """The kernel's z of every load column at the kept coordinates, (len(f), keep)."""
        num = self.num
        n = num.n
        Z = []
        errors = np.zeros(len(w))
        for column in self.columns:
            batch = Batch(tuple(num.coordinates), num.M, num.C, num.K,
                          [BatchHarmonic(w, np.zeros(n), column)], {}, num.title, True,
                          len(w))
            result = solve_harmonic(batch, batch.harmonics[0], self.method,
                                    warnings=self.warnings, keep=self.keep,
                                    deadline=self.deadline, exact_condition=False)
            if result.singular.any():
                where = float(f[int(np.argmax(result.singular))])
                raise AnalysisError(_singular_message(where, num.C))
            self.used_method = result.method
            if result.forward_error is not None:
                errors = np.fmax(errors, result.forward_error)
            Z.append(result.Z)
        self._accuracy(np.asarray(f, dtype=float), errors)
        return Z

    def _accuracy(self, f: np.ndarray, errors: np.ndarray) -> None:
        """One warning over every frequency solved so far (the band is refined in several
        calls) where the kernel's estimated forward error leaves fewer than three digits."""
        f_all, first = np.unique(np.concatenate([self._errors[0], f]), return_index=True)
        e_all = np.concatenate([self._errors[1], errors])[first]
        self._errors = (f_all, e_all)
        if self._accuracy_text is not None and self._accuracy_text in self.warnings:
            self.warnings.remove(self._accuracy_text)
        said = accuracy_warning(e_all, f_all, "f = {:.6g} Hz", what="frequency lines")
        self._accuracy_text = said
        if said is not None:
            self.warnings.append(said)

    def _assemble(self, w: np.ndarray, outputs: Sequence[str], Z: list[np.ndarray],
                  errors: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
        """H from the load columns' responses Z; with ``errors`` (len(w), columns), the
        bounds eps_k ||z_k|| of their coordinates' errors, the bound of |H - H_exact|."""
        num = self.num
        iw = 1j * w
        shape = (len(w), len(self.keep) + len(outputs), len(self.loads))
        D = None if errors is None else np.zeros(shape)
        with np.errstate(divide="ignore", invalid="ignore"):
            H = np.zeros(shape, complex)
            for j, entry in enumerate(self.index):
                for k, power in entry:
                    H[:, :len(self.keep), j] += iw[:, None] ** power * Z[k]
                    if D is not None and errors is not None:
                        D[:, :len(self.keep), j] += (np.abs(w) ** power * errors[:, k]
                                                     )[:, None] * self.adjoint[None, :]
            nk = len(self.keep)
            y = output_map(num.outputs, num.coordinates, outputs)
            for k, R in enumerate(y.R[:, :, self.keep]):
                H[:, nk:, :] += iw[:, None, None] ** k * (R @ H[:, :nk, :])
                if D is not None:
                    D[:, nk:, :] += np.abs(w)[:, None, None] ** k * (np.abs(R) @ D[:, :nk, :])
            for s, (var, order) in enumerate(y.signals):
                for j, u in enumerate(self.inputs):
                    if u.name == var:
                        H[:, nk:, j] += y.S[:, s] * iw[:, None] ** (order - u.derivative)
        return H, D


def _singular_message(where: float, C: Matrix) -> str:
    """Why the kernel found no response at ``where`` Hz: an undamped resonance only where
    the model has no damping; a damped model singular to double precision has lost every
    digit to its conditioning (or has a mode its damping does not reach)."""
    damped = bool(C.count_nonzero()) if hasattr(C, "count_nonzero") else bool(np.any(C))
    if not damped:
        return (f"the system is singular at {where:.6g} Hz (an undamped resonance): the "
                "response there is unbounded; add damping")
    return (f"the dynamic stiffness is singular to double precision at {where:.6g} Hz "
            "although the model is damped: either no digit is left to its conditioning (a "
            "fine mesh, stiffnesses or units many orders of magnitude apart: coarsen the mesh "
            "or rescale the units) or a mode there is not reached by the damping")


def _input_matrix(spec: RandomSpec, f: np.ndarray, values: Mapping[str, Any]) -> np.ndarray:
    """G_u (len(f), J, J): the inputs' one-sided (cross) densities per Hz."""
    J = len(spec.inputs)
    G = np.zeros((len(f), J, J), dtype=complex)
    diag = [u.density(f, values) for u in spec.inputs]
    for u, d in zip(spec.inputs, diag):
        bad = ~(np.isfinite(d) & (d >= 0))
        if bad.any():
            raise ModelError(Problem(
                f"the density is {'negative' if np.isfinite(d[bad][0]) else 'not finite'} "
                f"at {f[bad][0]:.6g} Hz: a spectral density is a finite number >= 0 over the "
                "band", spec.source, f"random.psd.{u.name}", "values"))
    for j in range(J):
        G[:, j, j] = diag[j]
    names = [u.name for u in spec.inputs]
    for c in spec.coherences:
        a, b = names.index(c.first), names.index(c.second)
        gamma2 = np.broadcast_to(np.asarray(numeric_value(c.value, {**values, "f": f}),
                                            dtype=float), f.shape)
        if not (np.all(gamma2 >= 0) and np.all(gamma2 <= 1)):
            raise ModelError(Problem(f"the coherence of {c.first} and {c.second} must lie in "
                                     "[0, 1] over the band", spec.source, "random.coherence"))
        phase = float(numeric_value(c.phase, values))
        if not math.isfinite(phase):
            raise ModelError(Problem(f"the phase of {c.first} and {c.second} is not a finite "
                                     "number", spec.source, "random.coherence"))
        cross = np.sqrt(gamma2 * diag[a] * diag[b]) * np.exp(1j * phase)
        G[:, a, b] = cross
        G[:, b, a] = np.conj(cross)
    return G


def _response_density(H: np.ndarray, G: np.ndarray) -> np.ndarray:
    """G_y (len(f), responses) = diag(H G H^*)."""
    result: np.ndarray = np.einsum("frj,fjl,frl->fr", H, G, H.conj()).real
    return result


def _density_bound(H: np.ndarray, D: np.ndarray, G: np.ndarray) -> np.ndarray:
    """A bound of |G_y - G_y,exact| (len(f), responses) where |H - H_exact| <= D:
    sum_jl |G_jl| (2 |H_j| D_l + D_j D_l)."""
    A, B = np.abs(H), np.abs(G)
    result: np.ndarray = (2 * np.einsum("frj,fjl,frl->fr", A, B, D)
                          + np.einsum("frj,fjl,frl->fr", D, B, D))
    return result


def _modal_points(num: NumericEOM, band: tuple[float, float]) -> list[float]:
    """Damped natural frequencies in the band and their half-power points (Hz)."""
    if num.n > MODES_LIMIT or num.sparse:
        return []
    M, C, K = (np.asarray(a, dtype=float) for a in (num.M, num.C, num.K))
    try:
        s = point_state_eigenvalues(M, C, K)
    except (np.linalg.LinAlgError, AnalysisError):
        return []
    out = []
    for root in s[s.imag > 0]:
        wn = abs(root)
        zeta = -root.real / wn if wn > 0 else 0.0
        fn = wn / (2 * np.pi)
        for a in (-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0):
            out.append(fn * (1 + a * max(zeta, 1e-6)))
    return [f for f in out if band[0] < f < band[1]]


def _initial_grid(spec: RandomSpec, num: NumericEOM) -> np.ndarray:
    low, high = spec.band
    start = low if low > 0 else high * 1e-6
    points = list(np.geomspace(start, high, spec.lines))
    for u in spec.inputs:
        if u.table is not None:
            points += [f for f in u.table[:, 0] if low < f < high]
    points += _modal_points(num, spec.band)
    if low == 0:
        points.append(0.0)
    return np.unique(np.array(points))


class _Quadrature:
    """Pairs of intervals (a, m, b): Simpson's rule, Richardson's error estimate.

    ``refined``: the leading columns of the integrands the refinement looks at (default
    all; the others, bounds of the integrands' errors, are integrated on the same grid).
    """

    def __init__(self, evaluate: Any, grid: np.ndarray, refined: int | None = None) -> None:
        self.evaluate = evaluate
        self.refined = refined
        a, b = grid[:-1], grid[1:]
        m = _middle(a, b)
        values = evaluate(np.concatenate([grid, m]))
        self.f = np.concatenate([grid, m])
        self.S = values
        k = len(grid)
        self.pairs = np.stack([np.arange(k - 1), k + np.arange(k - 1), np.arange(1, k)], 1)

    def add(self, f: np.ndarray) -> np.ndarray:
        start = len(self.f)
        self.f = np.concatenate([self.f, f])
        self.S = np.concatenate([self.S, self.evaluate(f)])
        return start + np.arange(len(f))

    def _pieces(self, columns: slice, power: int = 0
                ) -> Iterator[tuple[int, np.ndarray, np.ndarray]]:
        """(first pair, Simpson's integrals of f^power S (pairs, columns), Richardson's
        errors) a chunk of pairs at a time: the temporaries of a whole grid were six times
        the kept densities (2.3 GB for 3,168 responses; :func:`resonant.memory.chunk_rows`)."""
        width = len(range(*columns.indices(self.S.shape[1])))
        step = chunk_rows(80.0 * max(width, 1), len(self.pairs))
        for start in range(0, len(self.pairs), step):
            a, m, b = self.pairs[start:start + step].T
            fa, fm, fb = self.f[a], self.f[m], self.f[b]
            Sa, Sm, Sb = (self.S[i, columns] * (f[:, None] ** power if power else 1.0)
                          for i, f in ((a, fa), (m, fm), (b, fb)))
            h1, h2 = (fm - fa)[:, None], (fb - fm)[:, None]
            coarse = (Sa + Sb) / 2 * (h1 + h2)
            fine = (Sa + Sm) / 2 * h1 + (Sm + Sb) / 2 * h2
            yield start, fine + (fine - coarse) / 3, np.abs(fine - coarse) / 3

    def totals(self, columns: slice = slice(None)) -> tuple[np.ndarray, np.ndarray]:
        """(Simpson's integral over the band (columns,), the sum of Richardson's errors)."""
        value = error = np.zeros(len(range(*columns.indices(self.S.shape[1]))))
        for _, v, e in self._pieces(columns):
            value, error = value + v.sum(axis=0), error + e.sum(axis=0)
        return value, error

    def shares(self, scale: np.ndarray, failing: np.ndarray) -> np.ndarray:
        """Each pair's largest error relative to ``scale`` over the ``failing`` columns of
        the refined ones (pairs,)."""
        out = np.empty(len(self.pairs))
        for start, _, e in self._pieces(slice(0, self.refined)):
            out[start:start + len(e)] = (e[:, failing] / scale[failing]).max(axis=1)
        return out

    def split(self, chosen: np.ndarray) -> None:
        a, m, b = (self.pairs[chosen, i] for i in range(3))
        new = self.add(np.concatenate([_middle(self.f[a], self.f[m]),
                                       _middle(self.f[m], self.f[b])]))
        k = len(a)
        left = np.stack([a, new[:k], m], 1)
        right = np.stack([m, new[k:], b], 1)
        keep = np.ones(len(self.pairs), dtype=bool)
        keep[chosen] = False
        self.pairs = np.concatenate([self.pairs[keep], left, right])

    def moments(self, powers: Sequence[int], columns: slice = slice(None)
                ) -> list[np.ndarray]:
        """Simpson's integral of f^p S for each power (columns,)."""
        width = len(range(*columns.indices(self.S.shape[1])))
        out = []
        for p in powers:
            total = np.zeros(width)
            for _, v, _ in self._pieces(columns, p):
                total = total + v.sum(axis=0)
            out.append(total)
        return out


def _symmetric(*matrices: Matrix) -> bool:
    """Whether every matrix equals its transpose (dense or sparse)."""
    for a in matrices:
        difference = a - a.T
        largest = abs(difference).max() if hasattr(difference, "tocsr") else \
            np.abs(difference).max(initial=0.0)
        if largest != 0:
            return False
    return True


def _checked_frequencies(grid: np.ndarray) -> np.ndarray:
    """The first grid with its middles and quarter points: the frequencies of the first
    evaluation and of the first refinement round, where a band's reduced model is
    checked."""
    f = np.unique(grid)
    for _ in range(2):
        f = np.unique(np.concatenate([f, _middle(f[:-1], f[1:])]))
    return f


def _middle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The geometric middle where both ends are positive (log grids), else the mean."""
    with np.errstate(invalid="ignore"):
        result: np.ndarray = np.where(a > 0, np.sqrt(np.abs(a * b)), (a + b) / 2)
        return result


def _out_of_range(spec: RandomSpec) -> ModelError:
    """The error for responses whose densities or spectral moments (m0, m2, m4) leave the
    floating-point range although the inputs and the transfer are finite."""
    names = ", ".join(u.name for u in spec.inputs)
    return ModelError(Problem(
        "the response's spectral density or its moments (the mean square, and its moments "
        "of f^2 and f^4 for Rice's rates) leave the floating-point range: the input densities "
        "(or load and base vectors) are too large for double precision; give them in units "
        "that keep the numbers nearer 1", spec.source, "random.psd", names))


def _refine(quad: _Quadrature, tolerance: float, deadline: Deadline
            ) -> tuple[np.ndarray, np.ndarray, bool]:
    """Halve the pairs until every mean square's estimated error is below ``tolerance``."""
    refined = slice(0, quad.refined)
    for _ in range(MAX_ROUNDS):
        deadline.check("while refining the frequency grid of the random response", analysis=True)
        total, error = quad.totals(refined)
        scale = np.where(total > 0, total, np.inf)
        relative = error / scale
        if np.all(relative <= tolerance):
            return total, relative, True
        failing = relative > tolerance
        share = quad.shares(scale, failing)
        chosen = np.flatnonzero(share > tolerance / (2 * len(quad.pairs)))
        if len(quad.f) + 2 * len(chosen) > MAX_POINTS or not len(chosen):
            return total, relative, False
        quad.split(chosen)
    total, error = quad.totals(refined)
    return total, error / np.where(total > 0, total, np.inf), False


def _input_units(system: LinearSystem, spec: RandomSpec) -> dict[str, str]:
    model = system.model
    units = model.units if model is not None else None
    out = {}
    for u in spec.inputs:
        dim: Dimension | None = None
        if u.base:
            dim = Dimension.of(m=1, s=-2)
        elif units is not None and u.load == ():
            found = units.dimensions.get(u.name)
            if found is not None and u.name in system.coordinates:
                dim = Dimension.of(kg=1, m=2, s=-2) / found
            elif found is not None:
                dim = found / Dimension.of(s=u.derivative)
        out[u.name] = "" if dim is None else (dim.text() or "1")
    return out


def _units(system: LinearSystem, names: Sequence[str]) -> dict[str, str]:
    model = system.model
    if model is None or model.units is None:
        return {name: "" for name in names}
    out = {}
    for name in names:
        dim = model.units.dimensions.get(name)
        out[name] = "" if dim is None else (dim.text() or "1")
    return out


def responses_to_solve(num: NumericEOM, names: Sequence[str] | None
                       ) -> tuple[np.ndarray, list[str]]:
    """The coordinates to solve for (those named, and those the named outputs use) and the
    outputs to report.

    Parameters
    ----------
    num : NumericEOM
    names : sequence of str or None
        Coordinates and outputs (None: all).

    Returns
    -------
    keep : ndarray of int
    outputs : list of str

    Raises
    ------
    ModelError
        For an unknown name.
    """
    outputs = [o for o in num.outputs if names is None or o in names]
    if names is not None:
        unknown = [x for x in names if x not in num.coordinates and x not in num.outputs]
        if unknown:
            raise ModelError(f"unknown coordinate or output '{unknown[0]}'; known: "
                             f"{name_list([*num.coordinates, *num.outputs], 20)}")
    wanted = set(names) if names is not None else set(num.coordinates)
    for o in outputs:
        wanted |= {v for v, _ in num.outputs[o].terms if v in num.coordinates}
    keep = np.array([i for i, q in enumerate(num.coordinates) if q in wanted], dtype=int)
    return keep, outputs


#: the stability of systems up to this many coordinates is checked before a random
#: response (the state eigenvalues, dense: 0.1 s at this size)
STABILITY_CHECK_SIZE = 300


def _require_stable(num: NumericEOM) -> None:
    """A stationary random response exists only where free vibrations die out or stay
    bounded: an unstable system (negative damping, a negative stiffness) has none, and its
    RMS values would be numbers without meaning."""
    if num.n > STABILITY_CHECK_SIZE:
        return
    dense = num.dense()
    eigenvalues = point_state_eigenvalues(np.asarray(dense.M), np.asarray(dense.C),
                                          np.asarray(dense.K))
    if classify(eigenvalues) == UNSTABLE:
        worst = eigenvalues[np.argmax(eigenvalues.real)]
        raise AnalysisError(f"the system is unstable (a state eigenvalue s = {worst.real:.4g}"
                            f" {'+' if worst.imag >= 0 else '-'} {abs(worst.imag):.4g}i has a "
                            "positive real part): a stationary random response does not "
                            "exist; check the damping and stiffness at these parameter values")


def random_response(system: LinearSystem, spec: RandomSpec | None = None,
                    deadline: Deadline = NO_DEADLINE, *, names: Sequence[str] | None = None,
                    method: str = "auto", tolerance: float | None = None) -> RandomResponse:
    """The response spectral densities, RMS values and Rice's rates under random inputs.

    Parameters
    ----------
    system : LinearSystem
        The system (at the model's parameter values).
    spec : RandomSpec, optional
        The inputs (default: the model's ``[random]`` section).
    deadline : Deadline, optional
        Checked between the kernel's points and the refinement rounds.
    names : sequence of str, optional
        The coordinates and outputs to report (default: all).
    method : str
        The kernel's method (:func:`resonant.analyses.kernel.solve_harmonic`).
    tolerance : float, optional
        Relative error of the mean squares' quadrature (default: the section's).

    Returns
    -------
    RandomResponse

    Raises
    ------
    ModelError
        Without a ``[random]`` section, for an unknown name or a band that starts at 0 Hz
        under the density of a derivative.
    AnalysisError
        For an undamped resonance in the band.
    """
    model = system.model
    if spec is None:
        spec = model.random_section if model is not None else None
        if spec is None:
            raise ModelError(Problem("the model has no [random] section: add one with the "
                                     "spectral densities of its random inputs "
                                     "(docs/random.md)", system.source, "random"))
    num = system.numeric(deadline)
    _require_stable(num)
    keep, outputs = responses_to_solve(num, names)
    transfer = Transfer(system, num, spec.inputs, keep, method, deadline)
    if spec.band[0] == 0 and any(load.power < 0 for loads in transfer.loads for load in loads):
        raise ModelError(Problem("the band starts at 0 Hz, where a density of a derivative "
                                 "(a velocity or acceleration) gives an infinite displacement; "
                                 "start the band above 0", spec.source, "random", "band"))
    responses = [num.coordinates[i] for i in keep] + outputs

    def evaluate(f: np.ndarray) -> np.ndarray:
        H, D = transfer.with_bound(f, outputs)
        G = _input_matrix(spec, f, transfer.values)
        with np.errstate(over="ignore", invalid="ignore"):
            S = _response_density(H, G)
        if np.all(np.isfinite(H)) and np.all(np.isfinite(G)) and not np.all(np.isfinite(S)):
            raise _out_of_range(spec)
        return S if D is None else np.hstack([S, _density_bound(H, D, G)])

    tol = spec.tolerance if tolerance is None else tolerance
    grid = _initial_grid(spec, num)
    require_kept(len(grid), np.asarray(keep))   # every line's responses, before any reduction
    low, high = REDUCED_TOLERANCE_RANGE
    transfer.reduce(_checked_frequencies(grid), min(high, max(low, REDUCED_TOLERANCE * tol)))
    R = len(responses)
    quad = _Quadrature(evaluate, grid, R)
    m0, error, converged = _refine(quad, tol, deadline)
    warnings = list(transfer.warnings)
    if not converged:
        warnings.append(f"the quadrature reached {len(quad.f)} frequencies with the estimated "
                        f"relative error {np.nanmax(error):.2g} above the tolerance {tol:.2g}")
    if quad.S.shape[1] > R:   # the reduced model's part of each mean square's error
        bound = quad.totals(slice(R, None))[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            error = error + np.where(m0 > 0, bound / m0, 0.0)
        if converged and np.nanmax(error) > tol:
            warnings.append(f"the estimated relative error {np.nanmax(error):.2g} of a mean "
                            f"square (quadrature and reduced model) is above the tolerance "
                            f"{tol:.2g}")
    with np.errstate(over="ignore", invalid="ignore"):
        m2, m4 = quad.moments((2, 4), slice(0, R))
    if not (np.all(np.isfinite(m0)) and np.all(np.isfinite(m2)) and np.all(np.isfinite(m4))):
        raise _out_of_range(spec)
    order = np.argsort(quad.f)
    f, S = quad.f[order], quad.S[order][:, :R]
    with np.errstate(divide="ignore", invalid="ignore"):
        nu0 = np.sqrt(m2 / m0)
        nup = np.sqrt(m4 / m2)
    miles, fn, quality = _miles(num, spec, transfer, outputs, responses)
    G = _input_matrix(spec, f, transfer.values)
    if names is not None:   # the coordinates solved only for an output are not reported
        shown = [r for r, name in enumerate(responses) if name in names]
        responses = [responses[r] for r in shown]
        S, m0, error, nu0, nup = S[:, shown], m0[shown], error[shown], nu0[shown], nup[shown]
        if miles is not None:
            miles = {k: v for k, v in miles.items() if k in responses}
    return RandomResponse(
        title=num.title, names=tuple(responses), inputs=tuple(u.name for u in spec.inputs),
        frequency=f, psd={name: S[:, r].copy() for r, name in enumerate(responses)},
        input_psd={u.name: G[:, j, j].real.copy() for j, u in enumerate(spec.inputs)},
        rms={name: float(np.sqrt(max(m0[r], 0.0))) for r, name in enumerate(responses)},
        zero_crossing_rate={name: float(nu0[r]) for r, name in enumerate(responses)},
        peak_rate={name: float(nup[r]) for r, name in enumerate(responses)},
        error={name: float(error[r]) if np.isfinite(error[r]) else 0.0
               for r, name in enumerate(responses)},
        units=_units(system, responses), band=spec.band,
        input_units=_input_units(system, spec),
        input_derivatives={u.name: u.derivative for u in spec.inputs}, miles=miles,
        natural_frequency=fn, quality=quality, method=transfer.used_method,
        warnings=tuple(warnings))


def _miles(num: NumericEOM, spec: RandomSpec, transfer: Transfer, outputs: Sequence[str],
           responses: Sequence[str]) -> tuple[dict[str, float] | None, float | None,
                                              float | None]:
    """Miles' estimate of every response of a single-DOF model under one input."""
    if num.n != 1 or len(spec.inputs) != 1 or len(transfer.keep) != 1:
        return None, None, None
    m, c, k = (float(np.asarray(a.toarray() if hasattr(a, "toarray") else a).ravel()[0])
               for a in (num.M, num.C, num.K))
    if not (m > 0 and k > 0 and c > 0):
        return None, None, None
    fn = math.sqrt(k / m) / (2 * math.pi)
    zeta = c / (2 * math.sqrt(k * m))
    quality = 1 / (2 * zeta)
    if not spec.band[0] < fn < spec.band[1] or zeta >= 0.5:
        return None, fn, quality
    level = float(spec.inputs[0].density(np.array([fn]), transfer.values)[0])
    # the gain below resonance: |H|^2 = g^2 (1 + a r^2 + ...) at r = 1e-2 and 5e-3,
    # extrapolated to r = 0 (Richardson); lower frequencies lose digits to cancellation
    H = np.abs(transfer(np.array([fn * 1e-2, fn * 5e-3, fn]), outputs)[:, :, 0])
    out = {}
    for r, name in enumerate(responses):
        flat = H[1, r] > 0 and abs(H[0, r] / H[1, r] - 1) < 1e-3
        if not flat or H[2, r] < 0.5 * quality * H[1, r]:
            continue    # no static gain, or not resonant (the input itself)
        gain = math.sqrt(max(4 * H[1, r] ** 2 - H[0, r] ** 2, 0.0) / 3)
        out[name] = math.sqrt(math.pi / 2 * fn * quality * level) * float(gain)
    return out, fn, quality


#: at most this many response panels (one per unit)
MAX_PANELS = 4


def random_table(result: RandomResponse, units: ResultUnits | None = None) -> ResultTable:
    """The RMS, 3-sigma, Rice's rates (and Miles' estimate) of every response, as a table.

    Parameters
    ----------
    result : RandomResponse
    units : ResultUnits, optional
        The display units (``--units``: ``mm``, ``g``, ...; default SI).

    Returns
    -------
    resonant.tables.ResultTable
    """
    rows = []
    for name in result.names:
        miles = None if result.miles is None else result.miles.get(name)
        shown = shown_unit(units, result.units.get(name, ""))
        rms = shown(result.rms[name])
        rows.append((printable(name, limit=40), shown.text or "SI",
                     number_cell(rms), number_cell(3 * rms),
                     number_cell(result.zero_crossing_rate[name]),
                     number_cell(result.peak_rate[name]),
                     number_cell(None if miles is None else shown(miles)),
                     f"{result.error[name]:.1e}"))
    return ResultTable(("name", "unit", "RMS", "3-sigma", "nu0+ [Hz]", "peaks [Hz]", "Miles RMS",
                  "rel. error"), tuple(rows))


def random_text(result: RandomResponse, warnings: bool = True,
                units: ResultUnits | None = None) -> str:
    """The RMS, 3-sigma, Rice's rates (and Miles' estimate) of every response, as text.

    Parameters
    ----------
    result : RandomResponse
    warnings : bool
        End with the result's warnings (the command line writes them to standard error).
    units : ResultUnits, optional
        The display units (``--units``; default SI, accelerations also in g).

    Returns
    -------
    str
    """
    lines = [f"Random response: {printable(result.title) or '(untitled)'}",
             f"  band {result.band[0]:g}-{result.band[1]:g} Hz; one-sided spectral densities "
             f"per Hz; {len(result.frequency)} frequencies; inputs: "
             f"{', '.join(result.inputs)}"]
    if result.natural_frequency is not None:
        lines.append(f"  single DOF: f_n = {result.natural_frequency:.6g} Hz, "
                     f"Q = {result.quality:.4g}")
    lines.append(random_table(result, units).text())
    accelerations = [n for n in result.names if result.units.get(n) == "m/s^2"]
    if accelerations and shown_unit(units, "m/s^2").text == "m/s^2":
        lines.append("  in g (9.80665 m/s^2): " + ", ".join(
            f"{printable(n, limit=40)} {result.rms[n] / STANDARD_GRAVITY:.4g} g RMS"
            for n in accelerations))
    lines.append("  RMS about the reference state; 3-sigma = 3 RMS; Rice's rates of zero "
                 "up-crossings sqrt(m2/m0) and of peaks sqrt(m4/m2).")
    lines += [f"warning: {w}" for w in result.warnings] if warnings else []
    return "\n".join(lines) + "\n"


def random_chart(result: RandomResponse, names: Sequence[str] | None = None,
                 units: ResultUnits | None = None) -> Charts:
    """What the figure of a random response shows: the inputs' spectral densities above
    the responses', one panel per unit, on log-log axes with the units on the axes and
    each curve's RMS value in its label.

    Parameters
    ----------
    result : RandomResponse
    names : sequence of str, optional
        The responses to draw (default: all, at most :data:`MAX_CURVES` per panel).
    units : ResultUnits, optional
        The display units (``--units``: ``mm``, ``g``, ...; default SI).

    Returns
    -------
    Charts

    Raises
    ------
    AnalysisError
        For an unknown name.
    """
    chosen = list(result.names if names is None else names)
    unknown = [n for n in chosen if n not in result.names]
    if unknown:
        raise AnalysisError(f"no response named '{unknown[0]}'; the responses are "
                            f"{', '.join(result.names)}")
    groups: dict[str, list[str]] = {}
    for name in chosen:
        if np.any(result.psd[name] > 0):
            groups.setdefault(result.units.get(name, ""), []).append(name)
    f = np.asarray(result.frequency, dtype=float)
    positive = f > 0
    xlim = (float(f[positive].min()), float(f[positive].max())) if positive.any() else \
        (1.0, 10.0)
    xlabel = "frequency $f$ [Hz]"
    inputs = []
    for name in result.inputs:
        shown = shown_unit(units, result.input_units.get(name, ""))
        density = density_unit(shown)(np.asarray(result.input_psd[name], dtype=float))
        rms = math.sqrt(max(float(np.trapezoid(density, f)), 0.0))
        label = name + "'" * result.input_derivatives.get(name, 0)
        inputs.append(Curve(f[positive], density[positive],
                            f"{label} (RMS {rms:.3g} {unit_text(shown.text)})"
                            .replace(" )", ")")))
    input_units = {result.input_units.get(n, "") for n in result.inputs}
    unit = shown_unit(units, input_units.pop() if len(input_units) == 1 else "").text
    panels = [Chart(tuple(inputs), xlabel, f"input [{unit_text(density_unit(Shown(unit)).text)}]",
                    xlim, ylog=True, xlog=True, title="input spectral densities (one-sided)")]
    rules = () if result.natural_frequency is None else (
        Rule(float(result.natural_frequency), color="#999999", dash="3.7 1.6", width=0.8,
             label="natural frequency"),)
    for si, members in list(groups.items())[:MAX_PANELS]:
        shown = shown_unit(units, si)
        curves = tuple(Curve(f[positive],
                             density_unit(shown)(np.asarray(result.psd[name], dtype=float))[
                                 positive],
                             f"{name} (RMS {shown(result.rms[name]):.3g} {unit_text(shown.text)})"
                             .replace(" )", ")"))
                       for name in members[:MAX_CURVES])
        panels.append(Chart(curves, xlabel,
                            f"response [{unit_text(density_unit(shown).text)}]",
                            xlim, ylog=True, xlog=True, rules=rules))
    return Charts(tuple(panels), size=(7.5, 2.6 * len(panels) + 0.6))


def plot_random(result: RandomResponse, path: PathArg = None, names: Sequence[str] | None = None,
                ax: Axes | Sequence[Axes] | None = None,
                units: ResultUnits | None = None) -> Figure:
    """The inputs' and the responses' spectral densities on log-log axes, with units: the
    chart of :func:`random_chart`, drawn with matplotlib.

    The inputs are drawn in the first panel, the responses below, one panel per unit;
    each curve is labelled with its RMS value.

    Parameters
    ----------
    result : RandomResponse
    path : str or Path, optional
        Also write the figure there (``.png``, ``.svg`` or ``.pdf``).
    names : sequence of str, optional
        The responses to draw (default: all, at most :data:`MAX_CURVES` per panel).
    ax : matplotlib.axes.Axes or sequence of Axes, optional
        Draw into the caller's axes (one per panel: inputs, then each unit).
    units : ResultUnits, optional
        The display units (default SI).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    AnalysisError
        For an unknown name or an unsupported file suffix.
    """
    check_plot_path(path)
    charts = random_chart(result, names, units)
    count = len(charts.panels)
    axes = None if ax is None else axes_list(ax)
    if axes is not None and len(axes) < count:
        raise AnalysisError(f"the plot needs {count} axes (inputs and one per unit)")
    fig = draw_figure(charts, axes)
    save_figure(fig, path)
    return fig


__all__ = ["RandomResponse", "random_response", "Transfer", "responses_to_solve"]
