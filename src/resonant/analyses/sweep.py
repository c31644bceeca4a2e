"""Frequency (and parameter) sweeps of the stationary response.

:func:`sweep` evaluates the stationary amplitude and phase of every coordinate
and output while one parameter runs through an array of values: usually the
excitation frequency, but any parameter works (an absorber stiffness changes
K, a mass changes M).  The equation of motion is derived once; its symbolic
entries are compiled once (:func:`resonant.system.batch.compile_expressions`) and
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
    when the check fails;
``"reduced"``
    a reduced-order model of a large model (:mod:`resonant.analyses.reduced`),
    accurate to the relative tolerance ``tol`` (default 1e-6) by an a
    posteriori error estimate, with adaptive enrichment.

``method="direct"`` picks the cheapest exact one of dense, banded and sparse by
their estimated costs; ``method="auto"`` uses a reduced model where the direct
solves would be long and the model meets ``tol``, an exact method otherwise
(see :func:`resonant.analyses.kernel.solve_harmonic`); the result says which
(``method``) and, for a reduced model, its estimated error (``estimated_error``).
Amplitudes and phases mean exactly what they mean for
:func:`resonant.analyses.stationary.stationary`: for one frequency X = sqrt(L^2 + N^2)
and delta = atan2(L, N); for several, the peak of the summed time history.

An undamped system swept exactly through a natural frequency has no bounded
stationary solution there.  Such a point is not an error: its amplitude and
phase are NaN in the arrays (``null`` in JSON, a gap in the plot), its value is
listed in ``skipped`` and a warning names it.

Examples
--------
>>> from resonant.analyses.sweep import sweep
>>> import numpy as np, resonant.api
>>> model = resonant.api.loads('''
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
>>> fr = sweep(model.linearize(), "omega", np.linspace(1, 20, 191))
>>> [round(p.value, 2) for p in fr.peaks]     # sqrt(k/m - c^2/(2 m^2)) = 9.899
[9.9]
"""

from __future__ import annotations

import csv
import math
import os
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
import numpy.typing as npt

from ..arrays import Matrix, freeze_fields, frozen_array
from ..charts import (
    COLORS,
    MAX_CURVES,
    Annotation,
    Chart,
    Charts,
    Curve,
    Marker,
    PathArg,
    Rule,
    check_plot_path,
    draw_figure,
    save_figure,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, name_list, printable
from ..expressions.notation import dollar_name
from ..memory import dense_matrix
from ..model.options import SOLVE_METHODS, SweepOptions, chosen, names_tuple
from ..model.units_display import (
    NO_UNIT,
    ResultUnits,
    Shown,
    curve_units,
    frequency_axis,
    unit_math,
)
from ..system.base import LinearSystem
from ..system.batch import Batch, group_frequencies
from ..system.stability import natural_frequencies as _natural_frequencies
from ..tables import ResultTable, number_cell
from .forward_error import accuracy_warning
from .kernel import (
    DEFAULT_TOL,
    METHODS,
    SINGULAR_CONDITION,
    KernelResult,
    _Progress,
    check_batch_mass,
    choose_method,
    solve_harmonic,
)
from .result_fields import FieldsJSON, Framed, saved
from .results_json import Saved, floats_json
from .stationary import peak, phase_angle

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: above this many coordinates only the loaded ones are reported unless names are given
MAX_DEFAULT_NAMES = 2000
#: largest n for which the dense natural frequencies are computed with every sweep
EAGER_EIGEN = 400
#: most values of one sweep (3 million took 3.7 GB)
MAX_SWEEP_POINTS = 100_000
#: most complex results of one sweep: values x reported quantities x harmonics (memory
#: is a few hundred bytes per result, all intermediate arrays included)
MAX_SWEEP_RESULTS = 20_000_000


class Extremum(NamedTuple):
    """A resonance peak or antiresonance of one response curve.

    ``value`` is the refined parameter value (parabolic interpolation through
    the three grid points around the extremum: on log amplitude for peaks, on
    amplitude squared for antiresonances); ``amplitude`` the interpolated value.
    (A named tuple: a long sweep of a large model has tens of thousands.)  Its JSON
    record, ``{"name": ..., "value": ..., "amplitude": ...}``, is ``_asdict()``; a
    sweep's are written by :meth:`ExtremaTable.to_list`.
    """

    name: str
    value: float
    amplitude: float


@dataclass(frozen=True)
class ExtremaTable:
    """Extrema as arrays (built into :class:`Extremum` tuples only when asked for)."""

    names: tuple[str, ...] = ()
    index: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    amplitudes: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        freeze_fields(self)

    def __len__(self) -> int:
        return len(self.index)

    def entries(self) -> tuple[Extremum, ...]:
        names = self.names
        return tuple(map(Extremum, [names[i] for i in self.index.tolist()],
                         self.values.tolist(), self.amplitudes.tolist()))

    def to_list(self) -> list[dict[str, Any]]:
        """The JSON records of the extrema, each an :class:`Extremum`'s ``_asdict()``
        (written from the arrays: no tuple is built)."""
        names = self.names
        return [{"name": names[i], "value": v, "amplitude": a} for i, v, a in
                zip(self.index.tolist(), self.values.tolist(), self.amplitudes.tolist())]


@dataclass(frozen=True)
class FrequencyResponse(Framed, FieldsJSON):
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
        The solution method used (``dense``, ``banded``, ``sparse``, ``modal``,
        ``reduced``; several joined by ", " when the harmonics differ).
    estimated_error : float or None
        The estimated largest relative error of a reduced model (normwise, per
        value): an estimate, not a bound, seen at least as large as the true
        largest error in every model tried (docs/sweeps.md); None for the exact
        methods.
    tolerance : float or None
        The tolerance asked of a reduced model (None for the exact methods).
    frequency_sweep : bool
        True when the parameter is the excitation frequency in rad/s (M, C, K
        stay fixed and omega = value).
    frequency_scale : float or None
        omega = frequency_scale * value for the (lowest) moving excitation when
        M, C, K stay fixed (1 for omega itself, 2 pi for a frequency in Hz,
        anything for e.g. a vehicle speed); None when the parameter changes the
        system or no excitation frequency is proportional to it.
    skipped : tuple of float
        Values where the stationary solution does not exist (undamped resonance).
    quantities : tuple of str
        The coordinates and outputs computed, in the order of ``response``.
    response : ndarray
        (harmonics, N, quantities) complex amplitudes L - iN per frequency.
    harmonic_omegas : ndarray
        (harmonics, N) the excitation frequencies at every value.
    natural_frequencies : ndarray or None
        The undamped natural frequencies when M, C, K do not change along the sweep.
    warnings : tuple of str
        What the user should know (skipped points, a coarse grid near a peak).
    log : bool or None
        Whether the values are spaced logarithmically (the plot's axis).
    title, coordinates
        The model's title and its coordinates.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> r = sweep(eom, "omega", [5.0, 10.0])
    >>> r.parameter, r.values.tolist(), r.frequency_sweep
    ('omega', [5.0, 10.0], True)
    """

    #: the columns of to_frame() (resonant.analyses.result_fields.Framed)
    _frame = (("values", "{parameter}"), ("amplitudes", "amplitude:{key}"),
              ("phases", "phase:{key}"))

    parameter: str
    values: np.ndarray
    quantities: tuple[str, ...]
    #: complex responses z = L - i N, shape (harmonics, values, quantities)
    response: np.ndarray = saved(axes=("harmonic_omegas", "values", "quantities"))
    #: the excitation frequency of each harmonic at each value, shape (harmonics, values)
    harmonic_omegas: np.ndarray = saved(axes=(None, "values"))
    method: str = saved()
    frequency_sweep: bool = saved(False, required=True)
    natural_frequencies: np.ndarray | None = saved(None, omit_none=True)
    frequency_scale: float | None = None
    skipped: tuple[float, ...] = ()
    warnings: tuple[str, ...] = ()
    log: bool = saved(False, required=True)
    title: str = ""
    coordinates: tuple[str, ...] = ()
    estimated_error: float | None = None
    tolerance: float | None = None

    def __post_init__(self) -> None:
        freeze_fields(self)

    # Amplitudes, phases and extrema are derived on first use: the solve is the
    # sweep's job, and a caller who only needs the responses of a large model
    # should not pay for a million amplitudes and their peaks.
    @cached_property
    def _amplitude_phase(self) -> tuple[np.ndarray, np.ndarray]:
        N, m = len(self.values), len(self.quantities)
        if self.response.shape[0] == 0:
            return frozen_array(np.zeros((N, m))), frozen_array(np.full((N, m), np.nan))
        amplitude, phase = amplitude_and_phase(self.harmonic_omegas, self.response)
        skipped = np.isin(self.values, np.asarray(self.skipped, dtype=float))
        amplitude[skipped] = np.nan
        phase[skipped] = np.nan
        return frozen_array(amplitude), frozen_array(phase)

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

    def _derived_json(self) -> dict[str, Any]:
        """What readers of the JSON want beside the result itself (derived from it)."""
        data: dict[str, Any] = {
            "unit": self.unit,
            "amplitudes": {k: floats_json(v) for k, v in self.amplitudes.items()},
            "phases": {k: floats_json(v) for k, v in self.phases.items()},
            "peaks": self.peak_table.to_list(),
            "antiresonances": self.antiresonance_table.to_list(),
        }
        if self.natural_values is not None:
            data["natural_values"] = self.natural_values.tolist()
        return data

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        if values["values"].ndim != 1:
            raise reader.error("is not a list of numbers", "values")

    @property
    def unit(self) -> str:
        """The unit of the parameter where known: "rad/s" for the excitation frequency,
        "Hz" for a parameter f with omega = 2 pi f, else ""."""
        if self.frequency_scale is None:
            return ""
        if math.isclose(self.frequency_scale, 1.0, rel_tol=1e-9):
            return "rad/s"
        if math.isclose(self.frequency_scale, 2 * math.pi, rel_tol=1e-9):
            return "Hz"
        return ""

    @property
    def natural_values(self) -> np.ndarray | None:
        """The parameter values at which the excitation meets a natural frequency
        (natural frequency / ``frequency_scale``), or None."""
        if self.frequency_scale is None or self.natural_frequencies is None:
            return None
        values: np.ndarray = frozen_array(self.natural_frequencies / self.frequency_scale)
        return values

    def to_csv(self, path: str | os.PathLike[str]) -> None:
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

    def chart(self, names: Sequence[str] | None = None,
              units: Mapping[str, str] | None = None, phase: bool = True) -> Charts:
        """The figure's description: amplitudes (log axis) above phases, the natural
        frequencies and the extrema marked (:func:`frequency_response_chart`); what
        :meth:`plot`, the report and the page draw.

        Parameters
        ----------
        names : sequence of str, optional
            The quantities to draw.
        units : mapping, optional
            quantity -> unit text for the axis labels.
        phase : bool
            With the phase panel.

        Returns
        -------
        resonant.charts.Charts
        """
        return frequency_response_chart(self, names, units, phase=phase)

    def plot(self, path: str | os.PathLike[str] | None = None,
             names: Sequence[str] | None = None, ax: Axes | None = None,
             units: Mapping[str, str] | None = None) -> Figure:
        """Amplitude and phase against the swept parameter
        (:func:`resonant.analyses.sweep.plot_frequency_response`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        names : sequence of str, optional
            The quantities to draw.
        ax : matplotlib.axes.Axes, optional
            Draw the amplitudes into the caller's axes.
        units : mapping, optional
            quantity -> unit text for the axis labels.

        Returns
        -------
        matplotlib.figure.Figure

        Examples
        --------
        >>> import resonant
        >>> r = resonant.load("examples/cart_pendulum.toml").linearize().sweep("omega", [5, 10])
        >>> len(r.plot().axes) >= 2
        True
        """
        return plot_frequency_response(self, path=path, names=names, ax=ax, units=units)

    def summary(self) -> str:
        """The text ``resonant sweep`` prints (:func:`resonant.analyses.sweep.sweep_text`).

        Returns
        -------
        str
        """
        return sweep_text(self)


# -- amplitudes, phases, extrema ------------------------------------------------------------

def kept_coordinates(batch: Batch, names: Sequence[str]) -> list[str]:
    """The coordinates whose responses are kept: those reported and those outputs use."""
    wanted = set(names)
    for _, terms in batch.outputs.values():
        wanted |= {var for var, _ in terms}
    return [q for q in batch.coordinates if q in wanted]


def harmonic_responses(batch: Batch, responses: list[np.ndarray], names: Sequence[str]
               ) -> tuple[list[str], np.ndarray]:
    """The selected coordinates and every output: names and Z, shape (H, N, m)."""
    index = {q: k for k, q in enumerate(kept_coordinates(batch, names))}
    columns = [index[q] for q in names]
    out_names = list(names) + list(batch.outputs)
    if not batch.outputs and len(responses) == 1 and columns == list(range(len(index))):
        return out_names, responses[0][None]  # all kept coordinates in order: no copy
    N = responses[0].shape[0] if responses else 0
    Z = np.empty((len(responses), N, len(out_names)), dtype=complex)
    for k, (h, R) in enumerate(zip(batch.harmonics, responses)):
        Z[k, :, :len(columns)] = R[:, columns]
        for m, (_, terms) in enumerate(batch.outputs.values(), start=len(columns)):
            z = np.zeros(N, dtype=complex)
            for (var, order), coef in terms.items():
                if var in index:
                    z = z + coef * (1j * h.omega) ** order * R[:, index[var]]
                else:
                    s, c = h.signals.get((var, order), (0.0, 0.0))
                    z = z + coef * (np.asarray(c) - 1j * np.asarray(s))
            Z[k, :, m] = z
    return out_names, Z


def amplitude_and_phase(omegas: np.ndarray, Z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude and phase, shape (N, m), with the semantics of :func:`stationary.peak`.

    ``omegas`` (H, N) are the harmonics' frequencies, ``Z`` (H, N, m) the responses.
    """
    H, N, m = Z.shape
    bad = ~np.isfinite(Z).all(axis=0)
    if H == 1:
        L, Nn = Z[0].real, -Z[0].imag
        static = (omegas[0] == 0)[:, None]
        amplitude = amplitudes(omegas, Z)
        with np.errstate(invalid="ignore"):
            phase = np.where(~static & (amplitude > 0), np.arctan2(L, Nn) + 0.0, np.nan)
            phase = np.where(phase <= -np.pi, np.pi, phase)  # (-pi, pi], as phase_angle
    else:
        amplitude = np.full((N, m), np.nan)
        phase = np.full((N, m), np.nan)
        for i in range(N):
            # merge harmonics that coincide at this point (superposition)
            groups = group_frequencies(omegas[:, i].tolist())
            freqs = [float(omegas[ks[0], i]) for ks in groups]
            merged = np.array([Z[ks, i, :].sum(axis=0) for ks in groups])
            active = [k for k, f in enumerate(freqs) if f > 0]
            for j in range(m):
                if bad[i, j]:
                    continue
                pairs = tuple((float(z.real), float(-z.imag)) for z in merged[:, j])
                amplitude[i, j] = peak(freqs, pairs)
                if len(active) == 1 and math.hypot(*pairs[active[0]]) > 0:
                    phase[i, j] = phase_angle(*pairs[active[0]])
    amplitude[bad] = np.nan
    phase[bad] = np.nan
    return amplitude, phase


def amplitudes(omegas: np.ndarray, Z: np.ndarray) -> np.ndarray:
    """The amplitudes of :func:`amplitude_and_phase` alone, shape (N, m).

    Examples
    --------
    >>> amplitudes(np.array([[0.0, 2.0]]), np.array([[[-3.0 + 0j], [3.0 - 4.0j]]])).tolist()
    [[3.0], [5.0]]
    """
    if Z.shape[0] != 1:
        return amplitude_and_phase(omegas, Z)[0]
    L, Nn = Z[0].real, Z[0].imag
    static = omegas[0] == 0
    amplitude: np.ndarray = np.hypot(L, Nn) if not static.any() else \
        np.where(static[:, None], np.abs(L), np.hypot(L, Nn))
    # NaN wherever a component is not finite (hypot(inf, nan) is inf)
    amplitude[~(np.isfinite(L) & np.isfinite(Nn))] = np.nan
    return amplitude


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


#: a dip is an antiresonance when the response comes this close (relative to its
#: neighbours) to zero: a zero of the transfer function, not a minimum between peaks
TRUE_ZERO = 1e-6
#: a grid point is an extremum only if it differs from a neighbour by more than this
#: (relative): rounding noise on a flat curve is not a peak
EXTREMUM_RELATIVE = 1e-10


def _extrema(names: Sequence[str], values: np.ndarray, amplitude: np.ndarray, log: bool,
             response: np.ndarray | None = None) -> tuple[ExtremaTable, ExtremaTable]:
    """Peaks and antiresonances of every column of ``amplitude`` (N, m), in name order.

    An antiresonance is a true zero of the response, not any minimum between two
    peaks: ``response`` (N, m), the complex response of a single-frequency sweep, is
    modelled near a dip as z(u) = z1 + beta (u - u1), beta = (z2 - z0)/(u2 - u0), whose
    modulus is least at u = u1 - Re(conj(beta) z1)/|beta|^2; the dip is an
    antiresonance when z passes through zero there (|z| below :data:`TRUE_ZERO` of its
    neighbours: real and imaginary parts change sign together).  Without a single
    frequency's response there are no antiresonances.
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
        # a parabola through an uneven triple can overflow: the grid point is then the extremum
        wild = ~np.isfinite(y)
        x, y = np.where(wild, u[rows], x), np.where(wild, amplitude[rows, cols], y)
        if mask is is_dip:
            if response is None or not cols.size:
                out.append(ExtremaTable(names))
                continue
            z0, z1, z2 = response[triples, cols]
            u0, u1, u2 = u[triples]
            with np.errstate(all="ignore"):
                beta = (z2 - z0) / (u2 - u0)
                step = -(np.conj(beta) * z1).real / np.abs(beta) ** 2
                linear_x = np.clip(u1 + np.where(np.isfinite(step), step, 0.0), u0, u2)
                closest = np.abs(z1 + beta * (linear_x - u1))
                zero = closest <= TRUE_ZERO * np.maximum(np.abs(z0), np.abs(z2))
            x = np.exp(linear_x) if log else linear_x
            out.append(ExtremaTable(names, cols[zero], x[zero], closest[zero]))
            continue
        out.append(ExtremaTable(names, cols, np.exp(x) if log else x, y))
    return out[0], out[1]


# -- the public function ------------------------------------------------------------------

def swept_values(values: Sequence[float] | np.ndarray) -> np.ndarray:
    """The swept values as a flat float array: at least one, every one a finite number.

    Raises
    ------
    AnalysisError
        For a value that is not a number or is beyond double precision (``10**400``),
        NaN or infinite, and for no values at all.

    Examples
    --------
    >>> swept_values([1, 2.5]).tolist()
    [1.0, 2.5]
    >>> swept_values([10**400])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    resonant.errors.AnalysisError: the swept values must be finite numbers: int too large ...
    """
    try:
        array = np.asarray(values, dtype=float).ravel()
    except (OverflowError, ValueError, TypeError) as exc:
        raise AnalysisError(f"the swept values must be finite numbers: {exc}") from None
    if array.size == 0 or not np.all(np.isfinite(array)):
        raise AnalysisError("the sweep needs at least one finite parameter value")
    return array


def sweep(system: LinearSystem, param: str, values: Sequence[float] | np.ndarray, *,
          method: str = "auto", names: Sequence[str] | None = None,
          progress: bool | None = None, log: bool | None = None,
          deadline: Deadline = NO_DEADLINE, tol: float | None = None,
          options: SweepOptions | None = None) -> FrequencyResponse:
    """Stationary amplitude and phase of every coordinate and output against a parameter.

    Parameters
    ----------
    system : LinearSystem
        The system; a NumericEOM that does not carry its model can only be
        swept over ``param="omega"`` (the excitation frequency).
    param : str
        The parameter to vary (parameters defined from it follow it).
    values : array_like
        Its values (at least one; finite).
    method : {"auto", "direct", "dense", "banded", "sparse", "modal", "reduced"}
        How to solve; see the module docstring.  ``direct`` is the cheapest exact
        method, ``auto`` a reduced model where it pays and meets ``tol``, else
        the exact method of :func:`choose_method`.
    names : sequence of str, optional
        The coordinates to report (default all; outputs are always reported).
    progress : bool, optional
        Show a text progress bar on standard error (default: when standard
        error is a terminal and the sweep is long).
    log : bool, optional
        Whether the values are logarithmically spaced (for peak refinement
        and plots); detected from the values when omitted.
    deadline : Deadline, optional
        Checked between the points.
    tol : float, optional
        Relative tolerance of a reduced model (default
        :data:`resonant.analyses.reduced.DEFAULT_TOL`, 1e-6).
    options : SweepOptions, optional
        ``method``, ``names``, ``tol``, ``log`` and ``progress`` as one record (then not
        as keywords): :class:`resonant.model.options.SweepOptions`.

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

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> sweep(eom, "omega", [10.0, 20.0]).values.tolist()
    [10.0, 20.0]
    """
    chosen_options = chosen(options, SweepOptions(method, names_tuple(names), tol, log, progress))
    method, names = chosen_options.method, chosen_options.names
    progress, log = chosen_options.progress, chosen_options.log
    tol = DEFAULT_TOL if chosen_options.tol is None else chosen_options.tol
    values = swept_values(values)
    check_points(values.size)
    batch = system.batch(param, values, deadline)
    names, default_note = _reported_names(batch, names)
    _check_request(batch, names, values, method, param)
    warnings: list[str] = [default_note] if default_note else []
    check_batch_mass(batch, values, param, warnings)
    n = len(batch.coordinates)
    if progress is None:
        progress = sys.stderr.isatty() and len(values) * n * max(n, 1) > 5e7
    bar = _Progress(len(values) * max(len(batch.harmonics), 1), bool(progress))
    position = {q: i for i, q in enumerate(batch.coordinates)}
    keep = np.array([position[q] for q in kept_coordinates(batch, names)], dtype=int)
    results = [solve_harmonic(batch, h, method, progress=bar, warnings=warnings, keep=keep,
                              deadline=deadline, tol=tol) for h in batch.harmonics]
    skipped_mask = np.zeros(len(values), dtype=bool)
    for result in results:
        skipped_mask |= result.singular
    if not batch.harmonics:
        warnings.append("the model has no harmonic excitation: every amplitude is zero")
    if batch.harmonics:
        all_names, Z = harmonic_responses(batch, [r.Z for r in results], names)
    else:
        all_names = list(names) + list(batch.outputs)
        Z = np.zeros((0, len(values), len(all_names)), dtype=complex)
    omegas = np.array([np.broadcast_to(h.omega, values.shape) for h in batch.harmonics],
                      dtype=float).reshape(len(batch.harmonics), len(values))
    skipped_mask = _without_overflow(skipped_mask, omegas, values, param, warnings)
    skipped = tuple(float(v) for v in values[skipped_mask])
    damped = _has_damping(batch.C)
    if skipped:
        warnings.append(_skipped_warning(param, skipped, damped))
    warnings.extend(_conditioning_warning(results, values, skipped_mask, param))
    scale = _frequency_scale(batch, values)
    natural = _natural_frequencies_of(batch)
    if natural is not None and scale is not None and not np.any(dense_matrix(batch.C)):
        warnings.extend(_undamped_warning(natural / scale, values, param))
    errors = [r.error for r in results if r.error is not None]
    used = [r.method for r in results]
    return FrequencyResponse(  # values copied: the caller's array may change later
        parameter=param, values=values.copy(), quantities=tuple(all_names), response=Z,
        harmonic_omegas=omegas,
        method=", ".join(dict.fromkeys(used)) or (
            choose_method(batch, len(values)) if method == "auto" else method),
        estimated_error=max(errors) if errors else None,
        tolerance=tol if errors else None,
        frequency_sweep=scale is not None and math.isclose(scale, 1.0, rel_tol=1e-9),
        natural_frequencies=natural, frequency_scale=scale,
        skipped=skipped, warnings=tuple(dict.fromkeys(warnings)),
        log=_is_log(values) if log is None else bool(log),
        title=batch.title, coordinates=tuple(batch.coordinates))


def _reported_names(batch: Batch, names: Sequence[str] | None) -> tuple[list[str], str]:
    """The coordinates to report and, when a huge model's default was narrowed, why."""
    if names is not None:
        return list(names), ""
    n = len(batch.coordinates)
    if n <= MAX_DEFAULT_NAMES:
        return list(batch.coordinates), ""
    # a full table of a huge model is neither wanted nor storable: report the loaded
    # coordinates (select others with names=/--only)
    loaded: set[int] = set()
    for h in batch.harmonics:
        for f in (h.F_S, h.F_C):
            loaded |= set(np.nonzero(np.atleast_2d(f).any(axis=0))[0].tolist())
    names = [batch.coordinates[i] for i in sorted(loaded)] or [batch.coordinates[-1]]
    return names, (f"{n} coordinates: only the loaded ones ({', '.join(names[:5])}"
                   f"{' ...' if len(names) > 5 else ''}) are reported; choose others "
                   "with names= (--only)")


def _check_request(batch: Batch, names: Sequence[str], values: np.ndarray, method: str,
                   param: str) -> None:
    """Known names, a bounded number of results, a method that fits the batch."""
    n = len(batch.coordinates)
    known = set(batch.coordinates)
    unknown = [q for q in names if q not in known]
    if unknown:
        raise AnalysisError(f"unknown coordinate(s) {', '.join(unknown)}; the coordinates are "
                            f"{name_list(batch.coordinates, 20)}"
                            f"{' ...' if n > 20 else ''}")
    quantities = len(kept_coordinates(batch, names)) + len(batch.outputs)
    results = len(values) * max(quantities, 1) * max(len(batch.harmonics), 1)
    if results > MAX_SWEEP_RESULTS:
        raise AnalysisError(
            f"{len(values)} values x {quantities} reported quantities x "
            f"{max(len(batch.harmonics), 1)} harmonic(s) = {results:.3g} results; a sweep is "
            f"limited to {MAX_SWEEP_RESULTS:.0e}: use fewer --points or report fewer "
            "quantities (--only)")
    if SOLVE_METHODS[method].constant_only and not batch.constant:
        raise AnalysisError(f"method '{method}' needs M, C and K that do not depend on "
                            f"'{param}'; use 'dense'")


def _is_log(values: np.ndarray) -> bool:
    """Whether the values are spaced logarithmically (and not also linearly)."""
    return bool(len(values) > 2 and np.all(values > 0) and
                np.allclose(np.diff(np.log(values)), np.log(values[1] / values[0]),
                            rtol=1e-6) and not np.allclose(np.diff(values),
                                                           values[1] - values[0], rtol=1e-9))


def _without_overflow(skipped: np.ndarray, omegas: np.ndarray, values: np.ndarray,
                      param: str, warnings: list[str]) -> np.ndarray:
    """The skipped points less those where omega^2 overflowed (said in a warning; an
    AnalysisError when every point did)."""
    with np.errstate(all="ignore"):  # omega^2 beyond the floating-point range
        overflow = skipped & ~np.all(np.isfinite(omegas ** 2), axis=0)
    if not overflow.any():
        return skipped
    first = ", ".join(f"{v:.6g}" for v in values[overflow][:5])
    message = (f"numerical overflow at {param} = {first}"
               f"{' ...' if overflow.sum() > 5 else ''}: the excitation frequency squared "
               "exceeds the floating-point range (about 1e308); use units nearer to 1")
    if overflow.all():
        raise AnalysisError(message)
    warnings.append(message + "; these points are skipped (NaN, null in JSON)")
    return np.asarray(skipped & ~overflow)


def _has_damping(C: Matrix | np.ndarray) -> bool:
    """Whether the damping matrix (or stack of them) has a nonzero entry."""
    if hasattr(C, "count_nonzero"):
        return bool(C.count_nonzero())
    return bool(np.any(np.asarray(C)))


def _skipped_warning(param: str, skipped: Sequence[float], damped: bool = False) -> str:
    """The points without a solution: an undamped resonance only where the system has no
    damping; a damped system singular to double precision has lost every digit to its
    conditioning (or has a mode its damping does not reach)."""
    shown = ", ".join(f"{v:.6g}" for v in skipped[:5])
    where = f"no stationary solution at {param} = {shown}{' ...' if len(skipped) > 5 else ''}"
    if not damped:
        return (f"{where} (undamped resonance: the amplitude is unbounded); these points are "
                "skipped (NaN, null in JSON)")
    return (f"{where}: the dynamic stiffness is singular to double precision there "
            f"(condition number above {SINGULAR_CONDITION:.0e}) although the model is damped: "
            "either no digit is left to its conditioning (a fine mesh, stiffnesses or units "
            "many orders of magnitude apart: coarsen the mesh or rescale the units) or a "
            "mode there is not reached by the damping; these points are skipped (NaN, null "
            "in JSON)")


def _conditioning_warning(results: Sequence[KernelResult], values: np.ndarray,
                          skipped: np.ndarray, param: str) -> list[str]:
    """Where the kernel's estimated forward error leaves fewer than three digits
    (:func:`resonant.analyses.forward_error.accuracy_warning`: the points, the range, the
    worst point and the cause); the largest estimate over the harmonics at each point."""
    estimated = [np.asarray(r.forward_error, dtype=float) for r in results
                 if r.forward_error is not None]
    if not estimated:
        return []
    with np.errstate(invalid="ignore"):
        errors = np.fmax.reduce(estimated, axis=0)
    said = accuracy_warning(errors, values, f"{param} = {{:.6g}}", skipped)
    return [] if said is None else [said]


def _natural_frequencies_of(batch: Batch) -> np.ndarray | None:
    """The undamped natural frequencies when M, K are fixed and small enough to ask."""
    if not (batch.constant and len(batch.coordinates) <= EAGER_EIGEN):
        return None
    try:
        return _natural_frequencies(dense_matrix(batch.M), dense_matrix(batch.K))
    except (np.linalg.LinAlgError, ValueError):
        return None


def _undamped_warning(resonances: np.ndarray, values: np.ndarray, param: str) -> list[str]:
    """The warning of an undamped system whose resonances lie in the swept range."""
    hit = [v for v in resonances if values.min() <= v <= values.max()]
    if not hit:
        return []
    return ["the system has no damping: the response is unbounded at " + ", ".join(
        f"{param} = {v:.6g}" for v in hit[:5]) + (" ..." if len(hit) > 5 else "")
        + "; the peaks shown are the values on the grid, not the true (infinite) peaks"]


def _frequency_scale(batch: Batch, values: np.ndarray) -> float | None:
    """c with omega = c * value for the lowest moving excitation, when M, C, K are fixed."""
    if not batch.constant or values.size < 2:
        return None
    moving = [h.omega for h in batch.harmonics if np.ptp(h.omega) > 0]
    if not moving or np.any(values == 0):
        return None
    lowest = min(moving, key=lambda w: float(np.abs(w).min()))
    ratio = lowest / values
    if np.allclose(ratio, ratio[0], rtol=1e-9, atol=0.0) and ratio[0] > 0:
        return float(ratio[0])
    return None


def check_points(points: int) -> None:
    """Refuse more than :data:`MAX_SWEEP_POINTS` values, before anything is allocated."""
    if points > MAX_SWEEP_POINTS:
        raise AnalysisError(f"{points} points; a sweep is limited to {MAX_SWEEP_POINTS} "
                            "(the curves are refined between the points: a few hundred "
                            "suffice)")


def linspace(start: float, stop: float, points: int, log: bool = False) -> np.ndarray:
    """The sweep values: evenly spaced, or logarithmically (``log=True``, positive ends)."""
    if points < 1:
        raise AnalysisError(f"a sweep needs at least 1 point, not {points}")
    check_points(points)
    if log:
        if start <= 0 or stop <= 0:
            raise AnalysisError("a logarithmic sweep needs positive start and end values")
        return np.geomspace(start, stop, points)
    return np.linspace(start, stop, points)


#: amplitudes below this fraction of the largest one are drawn at the curve's floor
FLOOR = 1e-9


#: at most this many natural frequencies are drawn as vertical lines
MAX_LINES = 30


def response_axes(parameter: str, names: Sequence[str], *, coordinates: Sequence[str] = (),
                  units: Mapping[str, str] | None = None, unit: str = "",
                  frequency_sweep: bool = True, log: bool = False) -> Chart:
    """The axes and curve styles of a frequency response's amplitude chart, without data:
    what :func:`frequency_response_chart` fills with a sweep and the explore page (its JSON)
    with the curve it computes live.

    Parameters
    ----------
    parameter : str
        The swept parameter.
    names : sequence of str
        The curves, in order (each its colour of the cycle).
    coordinates : sequence of str
        The names that are coordinates (the others are labelled as outputs).
    units : mapping, optional
        name -> unit of the amplitudes: on the axis, or on each curve where they differ.
    unit : str
        The parameter's unit.
    frequency_sweep : bool
        Whether the parameter is the excitation frequency.
    log : bool
        A logarithmic parameter axis.

    Returns
    -------
    Chart
        Curves without points, labels, scales (amplitudes on a log axis).

    Examples
    --------
    >>> c = response_axes("omega", ["x1", "phi"], coordinates=["x1"],
    ...                   units={"x1": "m", "phi": "rad"}, unit="rad/s")
    >>> print(c.xlabel, "|", c.ylabel)
    excitation frequency $\\omega$ [rad/s] | amplitude $X$ [m, rad]
    >>> print(", ".join(k.label for k in c.curves))
    $x_{1}$ [m], $\\varphi$ (output) [rad]
    """
    amplitude_units = {units.get(n, "") for n in names} if units else set()
    per_curve = units if len(amplitude_units) > 1 else None
    curves = []
    for k, name in enumerate(names):
        kind = "" if name in coordinates else " (output)"
        if per_curve and per_curve.get(name) not in (None, "", "1"):
            kind += f" [{unit_math(per_curve[name])}]"
        # past the colour cycle, dashes: every curve stays distinguishable
        dash = (None, "3.7 1.6", "1 1.65", "6.4 1.6 1 1.6")[(k // len(COLORS)) % 4]
        curves.append(Curve(np.empty(0), np.empty(0), f"{dollar_name(name)}{kind}",
                            COLORS[k % len(COLORS)], 1.5, dash))
    shown_units = [unit_math(u) if u not in ("", "1") else "1" for u in sorted(amplitude_units)]
    xlabel = (("excitation frequency " if frequency_sweep else "") + dollar_name(parameter)
              + (f" [{unit}]" if unit else ""))
    ylabel = "amplitude $X$" + (f" [{', '.join(shown_units)}]"
                                if shown_units and shown_units != ["1"] else "")
    return Chart(tuple(curves), xlabel, ylabel, (0.0, 1.0), ylog=True, xlog=log,
                 legend="beside")


def frequency_response_chart(response: FrequencyResponse, names: Sequence[str] | None = None,
                             units: Mapping[str, str] | ResultUnits | None = None, *,
                             phase: bool = True,
                             extrema: bool = True, title: bool = True,
                             operating: float | None = None) -> Charts:
    """What the figure of a frequency response shows: amplitudes (log axis) above phases.

    Resonance peaks are marked with triangles (their values noted above the curves),
    antiresonances with circles; natural frequencies in the range of a frequency sweep
    are dotted vertical lines.  Skipped points (undamped resonance) are gaps.

    Parameters
    ----------
    response : FrequencyResponse
    names : sequence of str, optional
        The coordinates and outputs to draw (default: all, at most :data:`MAX_CURVES`,
        outputs included).
    units : ResultUnits or mapping, optional
        The display units (amplitudes converted to them; a frequency sweep's axis in the
        frequency unit chosen, ``--units Hz``), or name -> SI unit of the amplitudes: the
        amplitude axis is labelled with the unit, or each curve where the units differ.
    phase : bool
        Draw the phase panel under the amplitudes.
    extrema : bool
        Mark the peaks and antiresonances.
    title : bool
        Give the figure the model's title.
    operating : float, optional
        The operating value of the parameter: a dashed line there and a dot on each curve.

    Returns
    -------
    Charts

    Raises
    ------
    AnalysisError
        For an unknown name.

    Examples
    --------
    >>> import resonant
    >>> r = resonant.load("examples/cart_pendulum.toml").linearize().sweep(
    ...     "omega", np.linspace(1.0, 20.0, 50))
    >>> charts = frequency_response_chart(r, ["x1"])
    >>> len(charts.panels), charts.panels[0].ylabel, charts.panels[0].ylog
    (2, 'amplitude $X$', True)
    """
    given = names
    names = _curve_names(response, names)
    shown_units = curve_units(units, names)
    along, scale = frequency_axis(units, response.frequency_scale, response.unit)
    # an angular frequency shown in Hz is the cyclic frequency f = omega / (2 pi)
    parameter = "f" if response.frequency_sweep and along.text in ("Hz", "kHz") \
        and response.unit == "rad/s" else response.parameter
    axes = response_axes(parameter, names, coordinates=response.coordinates,
                         units={n: s.text for n, s in shown_units.items()} if units else None,
                         unit=along.text, frequency_sweep=response.frequency_sweep,
                         log=bool(response.log))
    floor, top = _amplitude_floor(response, names, shown_units)
    x = along(np.asarray(response.values, dtype=float) * scale)
    amp_curves: list[Curve] = []
    phase_curves: list[Curve] = []
    markers: list[Marker] = []
    notes: list[Annotation] = []
    labelled: list[float] = []
    for name, style in zip(names, axes.curves):
        color = style.color or COLORS[0]
        amplitude = shown_units[name](np.array(response.amplitudes[name], dtype=float))
        with np.errstate(invalid="ignore"):
            shown = np.where(amplitude > 0, np.maximum(amplitude, floor), np.nan)  # log: no 0
        amp_curves.append(replace(style, x=x, y=shown))
        phase_curves.append(Curve(x, unwrapped_degrees(response.phases[name]), "", color, 1.2))
        if operating is not None and x.size > 1 and np.all(np.diff(x) > 0):
            at = float(np.interp(along(operating * scale), x, amplitude))
            if at > 0:
                markers.append(Marker(along(operating * scale), at, color))
        if extrema:
            markers += _extrema_marks(response, name, color, floor, notes, labelled,
                                      _Axis(lambda v: along(v * scale), along.text,
                                            _axis_span(x, bool(response.log)),
                                            bool(response.log), _resonances(response)),
                                      shown_units[name])
    rules: list[Rule] = []
    natural = response.natural_values
    if natural is not None and x.size:
        lo, hi = float(np.min(x)), float(np.max(x))
        what = "natural frequency" if response.frequency_sweep else \
            "excitation at a natural frequency"
        rules += [Rule(along(float(w) * scale), color="#737373", dash="1 1.65", label=what)
                  for w in natural if lo <= along(w * scale) <= hi][:MAX_LINES]
    if operating is not None:
        rules.append(Rule(along(float(operating) * scale), color="#404040", dash="3.7 1.6",
                          label="operating point"))
    ylim = None
    if extrema and floor > 0 and top > 0:  # clipped to the data, room above for the notes
        ylim = (floor / 1.5, top * (top / floor) ** 0.12 * 1.5)
    xlim = (float(np.nanmin(x)), float(np.nanmax(x))) if x.size else (0.0, 1.0)
    xlabel, log = axes.xlabel, axes.xlog
    any_positive = any(np.isfinite(c.y).any() for c in amp_curves)
    amplitude_chart = replace(axes, curves=tuple(amp_curves), xlim=xlim, ylog=any_positive,
                              markers=tuple(markers), rules=tuple(rules), ylim=ylim,
                              notes=tuple(notes))
    heading = ""
    if title:
        heading = (printable(response.title or "frequency response", limit=80)
                   + "\n" + r"$x = X \sin(\omega t + \delta)$")
        left_out = len(response.names) - len(names)
        if left_out > 0 and given is None:  # said, never dropped without a word
            heading += (f" — {len(names)} of {len(response.names)} responses drawn "
                        "(choose them with names=, --only)")
    if not phase:
        return Charts((amplitude_chart,), heading)
    phase_rules = tuple(replace(r, label="") for r in rules)
    return Charts((amplitude_chart,
                   Chart(tuple(phase_curves), xlabel, r"phase $\delta$ [°]", xlim,
                         rules=phase_rules, xlog=log, yticks=_phase_ticks(phase_curves),
                         ylim=_phase_limits(phase_curves), legend="none")),
                  heading, heights=(2.2, 1.0), size=(9.5, 6.5))


def _phase_limits(curves: Sequence[Curve]) -> tuple[float, float]:
    """The phase axis: whole quarter turns around the data (at least a half turn) and
    10 degrees of margin."""
    values = np.concatenate([np.asarray(c.y, dtype=float) for c in curves]) if curves else \
        np.empty(0)
    values = values[np.isfinite(values)]
    low, high = (float(values.min()), float(values.max())) if values.size else (-90.0, 0.0)
    first, last = 90 * math.floor(low / 90), 90 * math.ceil(high / 90)
    if last - first < 180:
        first, last = first - 90, last + 90
    return first - 10.0, last + 10.0


def _phase_ticks(curves: Sequence[Curve]) -> tuple[float, ...]:
    low, high = _phase_limits(curves)
    first, last = low + 10.0, high - 10.0
    step = 90 * max(1, math.ceil((last - first) / 90 / 8))
    return tuple(float(v) for v in np.arange(first, last + 1, step))


#: a peak's note needs this fraction of the axis's width to itself (its text's width)
NOTE_WIDTH = 0.06
#: a peak farther than this (relative) from every natural frequency is a local bump of the
#: curve between two resonances: it is not marked as one
RESONANCE_BAND = 0.12


@dataclass(frozen=True)
class _Axis:
    """The parameter axis as the chart draws it: the map of a value onto it, its unit, its
    span (in decades on a log axis), and the parameter values of the resonances."""

    at: Callable[[float], float]
    unit: str
    span: float
    log: bool
    resonances: np.ndarray | None

    def apart(self, a: float, b: float) -> bool:
        """Whether two notes at ``a`` and ``b`` (on the axis) do not overlap."""
        if self.log and a > 0 and b > 0:
            return abs(math.log10(a / b)) > NOTE_WIDTH * self.span
        return abs(a - b) > NOTE_WIDTH * self.span

    def resonant(self, value: float) -> bool:
        """Whether a peak at ``value`` (the parameter's) is near a natural frequency (every
        peak is, where the sweep knows none)."""
        if self.resonances is None or self.resonances.size == 0:
            return True
        return bool(np.any(np.abs(self.resonances - value) <= RESONANCE_BAND
                           * np.abs(self.resonances)))


def _resonance_peaks(response: FrequencyResponse,
                     axis: _Axis | None = None) -> list[Extremum]:
    """The peaks that are resonances: near a natural frequency (:data:`RESONANCE_BAND`),
    and each curve's highest (never left out); the others are local bumps between two
    resonances.  The plot marks these and the text lists them as resonance peaks."""
    if axis is None:
        axis = _Axis(float, "", 1.0, bool(response.log), _resonances(response))
    highest: dict[str, Extremum] = {}
    for p in response.peaks:
        if p.name not in highest or p.amplitude > highest[p.name].amplitude:
            highest[p.name] = p
    return [p for p in response.peaks if p is highest[p.name] or axis.resonant(p.value)]


def _axis_span(x: np.ndarray, log: bool) -> float:
    finite = x[np.isfinite(x) & ((x > 0) if log else True)]
    if finite.size < 2:
        return 1.0
    low, high = float(finite.min()), float(finite.max())
    return (math.log10(high / low) if log else high - low) or 1.0


def _resonances(response: FrequencyResponse) -> np.ndarray | None:
    """The parameter values at the natural frequencies (None where the sweep is not of a
    frequency: every peak counts)."""
    return response.natural_values if response.frequency_sweep else None


def _extrema_marks(response: FrequencyResponse, name: str, color: str, floor: float,
                   notes: list[Annotation], labelled: list[float], axis: _Axis,
                   unit: Shown) -> list[Marker]:
    """Triangles on the resonance peaks (each resonance's value noted once, with its unit,
    where its note does not overlap another), circles on the antiresonances (at the drawn
    floor for a true zero); ``unit`` shows an amplitude."""
    marks = []
    peaks = [p for p in _resonance_peaks(response, axis) if p.name == name]
    for p in peaks[:20]:
        value = axis.at(p.value)
        marks.append(Marker(value, unit(p.amplitude), color, "peak", "resonance peak"))
        # one note per resonance: curves peaking at nearly the same value share it
        if all(axis.apart(value, v) for v in labelled):
            labelled.append(value)
            text = f"{value:.4g}" + (f" {axis.unit}" if axis.unit and not labelled[1:] else "")
            notes.append(Annotation(value, text, color))
    for p in [p for p in response.antiresonances if p.name == name][:20]:
        marks.append(Marker(axis.at(p.value), max(unit(p.amplitude), floor), color, "ring",
                            "antiresonance (zero)"))
    return marks


def plot_frequency_response(response: FrequencyResponse, path: PathArg = None,
                            names: Sequence[str] | None = None, ax: Axes | None = None,
                            units: Mapping[str, str] | ResultUnits | None = None) -> Figure:
    """Amplitude (log axis) above phase, against the swept parameter: the chart of
    :func:`frequency_response_chart`, drawn with matplotlib.

    Parameters
    ----------
    response : FrequencyResponse
        The sweep to draw.
    path : str or Path, optional
        Also write the figure there; the format follows the suffix (``.png``,
        ``.svg`` or ``.pdf``, anything else raises :class:`AnalysisError`).
    names : sequence of str, optional
        The coordinates and outputs to draw (default: all, at most
        :data:`MAX_CURVES`, outputs included).
    ax : pair of matplotlib.axes.Axes, or Axes, optional
        Draw into the caller's figure: ``(amplitude_axes, phase_axes)`` for both
        panels, or a single Axes for the amplitude panel alone.  The axes are
        drawn into as they are (no layout change); by default a new figure with
        the two panels stacked is made.
    units : ResultUnits or mapping, optional
        The display units (:func:`resonant.model.units_display.result_units`: amplitudes
        and a frequency axis converted), or name -> SI unit of the amplitudes
        (``ResultUnits.si``): the amplitude axis is labelled with the unit, or each curve
        where the units differ.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the one ``ax`` belongs to.

    Raises
    ------
    AnalysisError
        For an unknown name or an unsupported file suffix.
    """
    check_plot_path(path)
    axes = _response_axes(ax)
    charts = frequency_response_chart(response, names, units,
                                      phase=axes is None or len(axes) == 2)
    fig = draw_figure(charts, axes)
    save_figure(fig, path, bbox_inches="tight")
    return fig


def _curve_names(response: FrequencyResponse, names: Sequence[str] | None) -> list[str]:
    """The names to draw: the given ones (checked), else all, at most MAX_CURVES."""
    if names is None:
        names = list(response.names)
        if len(names) > MAX_CURVES:
            outputs = [n for n in names if n not in response.coordinates]
            names = (names[:MAX_CURVES - len(outputs[:MAX_CURVES // 2])]
                     + outputs[:MAX_CURVES // 2])
    unknown = [n for n in names if n not in response.amplitudes]
    if unknown:
        raise AnalysisError(f"nothing to plot named {', '.join(unknown)}")
    return list(names)


def _response_axes(ax: Axes | None) -> list[Any] | None:
    """The caller's ``ax=`` as a list of Axes (amplitude, phase), or None for a new figure."""
    if ax is None:
        return None
    if isinstance(ax, (tuple, list)) or (isinstance(ax, np.ndarray) and ax.ndim == 1):
        if len(ax) != 2:
            raise AnalysisError("ax= takes a pair of Axes (amplitude, phase) or one Axes "
                                "(amplitude only)")
        return list(ax)
    return [ax]


def _amplitude_floor(response: FrequencyResponse, names: Sequence[str],
                     shown: Mapping[str, Shown] | None = None) -> tuple[float, float]:
    """(floor, top) of the plotted amplitudes (in their display units ``shown``).

    True zeros (antiresonances of undamped systems, 1e-19 and less) are drawn at the
    floor instead of stretching the log axis over many decades.
    """
    sampled = np.array([(shown[name] if shown else NO_UNIT)(
        np.asarray(response.amplitudes[name], dtype=float)) for name in names], dtype=float)
    top = float(np.nanmax(sampled, initial=0.0)) if np.isfinite(sampled).any() else 0.0
    meaningful = sampled[np.isfinite(sampled) & (sampled > FLOOR * top)]
    floor = float(meaningful.min()) if meaningful.size else 0.0
    return floor, top


def unwrapped_degrees(phase: npt.ArrayLike) -> np.ndarray:
    """A phase curve in degrees made continuous: jumps of a full turn removed (each run
    between gaps on its own), so that a phase passing -180 degrees goes on to -270
    instead of jumping to +90; a jump of half a turn (the sign change at an undamped
    resonance) is taken as a growing lag.

    Examples
    --------
    >>> unwrapped_degrees(np.radians([170.0, 179.0, -178.0, -170.0])).round(6).tolist()
    [170.0, 179.0, 182.0, 190.0]
    """
    radians = np.array(phase, dtype=float)
    out = np.full(radians.shape, np.nan)
    finite = np.isfinite(radians)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], finite.astype(int), [0]))))
    for start, stop in zip(edges[::2], edges[1::2]):
        run = radians[start:stop]
        step = np.diff(run)
        wrapped = np.mod(step + math.pi, 2 * math.pi) - math.pi
        # a jump of half a turn (an undamped resonance or antiresonance: the sign flips) is
        # taken as a growing lag, as textbooks draw it, whatever side rounding puts it on
        wrapped[np.abs(np.abs(wrapped) - math.pi) < 0.05] = -math.pi
        out[start:stop] = np.degrees(run + np.concatenate(([0.0], np.cumsum(wrapped - step))))
    return out


def extrema_table(result: FrequencyResponse, items: Sequence[Extremum],
                  units: ResultUnits | None = None) -> ResultTable:
    """The peaks (or antiresonances) as a table: the quantity, where (in the parameter's
    unit) and the amplitude (in the quantity's display unit where the model gives one).

    Parameters
    ----------
    result : FrequencyResponse
    items : sequence of Extremum
        ``result.peaks`` or ``result.antiresonances``.
    units : ResultUnits, optional
        The model's display units.

    Returns
    -------
    resonant.tables.ResultTable
    """
    rows = []
    along, scale = frequency_axis(units, result.frequency_scale, result.unit)
    for p in items:
        unit = units.unit(p.name) if units is not None else None
        rows.append((printable(p.name, limit=40), number_cell(along(p.value * scale), 6),
                     number_cell(unit(p.amplitude) if unit is not None else p.amplitude, 6),
                     unit.text if unit is not None else ""))
    where = f"{printable(result.parameter, limit=40)}" + (f" [{along.text}]" if along.text
                                                          else "")
    return ResultTable(("name", where, "amplitude", "unit"), tuple(rows), align="lrrl")


def sweep_text(result: FrequencyResponse, units: ResultUnits | None = None) -> str:
    """The human-readable summary of ``resonant sweep``; the amplitudes in the display units
    of ``units`` where given."""
    along, scale = frequency_axis(units, result.frequency_scale, result.unit)
    unit = f" {along.text}" if along.text else ""
    out = [printable(result.title or "sweep"),
           f"{result.parameter} from {along(result.values[0] * scale):.6g} to "
           f"{along(result.values[-1] * scale):.6g}{unit}, "
           f"{len(result.values)} values, method {result.method}" + (
               f" (estimated error {result.estimated_error:.2g}, tolerance "
               f"{result.tolerance:.2g})" if getattr(result, "estimated_error", None) is not None
               else ""), ""]
    natural = result.natural_values
    if natural is not None:
        inside = [w for w in natural if result.values.min() <= w <= result.values.max()]
        if inside and result.frequency_sweep:
            out.append("natural frequencies in range: " +
                       ", ".join(f"{along(w * scale):.6g}" for w in inside[:20]) + unit)
        elif inside:
            out.append(f"the excitation meets a natural frequency at {result.parameter} = " +
                       ", ".join(f"{along(w * scale):.6g}" for w in inside[:20]) + unit)
    resonances = _resonance_peaks(result)
    bumps = [p for p in result.peaks if p not in resonances]
    for title, items in (("resonance peaks", resonances),
                         ("other local maxima (between resonances, away from every natural "
                          "frequency)", bumps),
                         ("antiresonances", result.antiresonances)):
        if not items and title.startswith("other"):
            continue
        out.append(f"{title}:")
        if not items:
            out.append("  none")
        else:
            out.append(extrema_table(result, items[:50], units).text())
        if len(items) > 50:
            out.append(f"  ... {len(items) - 50} more (use --json)")
    return "\n".join(out) + "\n"


__all__ = ["extrema_table", "sweep_text", "plot_frequency_response", "frequency_response_chart",
           "response_axes", "unwrapped_degrees", "MAX_LINES", "sweep", "FrequencyResponse",
           "Extremum", "ExtremaTable", "choose_method", "linspace", "METHODS", "MAX_SWEEP_POINTS",
           "MAX_SWEEP_RESULTS", "check_points"]
