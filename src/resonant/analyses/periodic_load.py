"""The stationary response to a periodic, non-harmonic load: Fourier series, superposition.

A periodic signal s(t) = s(t + T) is expanded in its Fourier series

    s(t) = a0 + sum_{n=1..H} a_n cos(n W t) + b_n sin(n W t),   W = 2 pi / T,

with H the fewest harmonics whose remainder has a relative RMS (Parseval) below the
tolerance.  The stationary response of the linear system is the sum of the responses to
the harmonics -- exact for the linear system, up to the truncation -- each from the one
harmonic kernel (:func:`resonant.analyses.kernel.solve_harmonic`, through
:class:`~resonant.analyses.random_response.Transfer`), the constant a0 from K q0 = load.

The shapes with closed-form coefficients (period T, amplitude A):

``"square"``
    A for 0 < t < T/2, -A for T/2 < t < T: b_n = 4 A / (n pi) for odd n.
``"sawtooth"``
    A (2 t / T - 1) on 0 <= t < T (rising, then dropping back): b_n = -2 A / (n pi).
``"triangle"``
    A at t = 0 down to -A at T/2 and back (even): a_n = 8 A / (n pi)^2 for odd n.
``"rectified-sine"``
    |A sin(pi t / T)| (a full-wave rectified sine of period T): a0 = 2 A / pi,
    a_n = -4 A / (pi (4 n^2 - 1)).

Any other shape is an expression of ``t`` over one period, sampled and transformed (FFT)
with enough samples that the coefficients have settled (docs/random.md).

Examples
--------
>>> series = fourier_series("square", 1.0, 2.0, tolerance=0.1)
>>> series.b[:3].round(6).tolist()         # 4/pi, 0, 4/(3 pi)
[1.27324, 0.0, 0.424413]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem, printable
from ..expressions import numeric_value
from ..model.fourier_shapes import FOURIER_SHAPES, SHAPES
from ..model.load_spec import PeriodicSpec
from ..model.random_spec import RandomInput
from ..model.units_display import NO_UNIT, ResultUnits
from ..system.base import LinearSystem
from ..tables import ResultTable, number_cell
from .random_response import Transfer, responses_to_solve
from .result_fields import PLAIN_NUMBER, FieldsJSON, Framed, saved
from .results_json import Saved

#: most harmonics of a series
MAX_HARMONICS = 200_000
#: samples per period of the response, per harmonic (for the largest excursion)
SAMPLES_PER_HARMONIC = 16


@dataclass(frozen=True)
class FourierSeries:
    """s(t) = a0 + sum a_n cos(n W t) + b_n sin(n W t), n = 1..H, W = 2 pi / period.

    Attributes
    ----------
    period : float
        T (s).
    a0 : float
        The mean.
    a, b : ndarray
        The cosine and sine coefficients of harmonics 1..H.
    remainder : float
        The relative RMS of what the truncation leaves out (Parseval).
    shape : str
        The shape's name, or the expression.
    """

    period: float
    a0: float
    a: np.ndarray
    b: np.ndarray
    remainder: float
    shape: str

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def harmonics(self) -> int:
        """H, the number of harmonics."""
        return len(self.a)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """The truncated series at the times ``t``."""
        t = np.asarray(t, dtype=float)
        n = np.arange(1, self.harmonics + 1)
        phase = 2 * np.pi / self.period * np.multiply.outer(t, n)
        result: np.ndarray = self.a0 + np.cos(phase) @ self.a + np.sin(phase) @ self.b
        return result


def _remainders(a0: float, a: np.ndarray, b: np.ndarray, mean_square: float) -> np.ndarray:
    """Relative RMS of the remainder after 1, 2, ... harmonics (Parseval)."""
    kept = a0 * a0 + np.cumsum((a * a + b * b) / 2)
    return np.sqrt(np.maximum(mean_square - kept, 0.0) / mean_square) if mean_square > 0 \
        else np.zeros(len(a))


def fourier_series(shape: str, amplitude: float, period: float, *, tolerance: float = 1e-2,
                   function: Callable[[np.ndarray], np.ndarray] | None = None,
                   max_harmonics: int = MAX_HARMONICS) -> FourierSeries:
    """The Fourier series of a periodic signal, truncated where its remainder's relative
    RMS falls below ``tolerance``.

    Parameters
    ----------
    shape : str
        One of :data:`SHAPES`, or a name for ``function``.
    amplitude : float
        A (ignored for ``function``).
    period : float
        T (s).
    tolerance : float
        The largest relative RMS of the remainder.
    function : callable, optional
        s(t) on one period (vectorized); sampled and transformed by FFT, with the number
        of samples doubled until the kept coefficients change by less than
        ``tolerance / 10`` of the RMS and the remainder is within the tolerance.
    max_harmonics : int
        The largest H.

    Returns
    -------
    FourierSeries

    Raises
    ------
    AnalysisError
        For an unknown shape, a period or tolerance out of range, a signal that is not
        finite, or a series that needs more than ``max_harmonics`` harmonics.
    """
    if not (math.isfinite(period) and period > 0):
        raise AnalysisError(f"the period {period:g} s must be positive")
    if not 0 < tolerance < 1:
        raise AnalysisError(f"the tolerance {tolerance:g} must lie in (0, 1)")
    if function is None:
        if shape not in SHAPES:
            raise AnalysisError(f"unknown periodic shape '{shape}'; the shapes are "
                                f"{', '.join(SHAPES)} (or give the signal as a function)")
        n = np.arange(1, max_harmonics + 1)
        known = FOURIER_SHAPES[shape]
        a0, a, b = known.coefficients(float(amplitude), n)
        mean_square = known.mean_square(float(amplitude))
    else:
        a0, a, b, mean_square = _sampled(function, period, tolerance, max_harmonics)
    if not math.isfinite(mean_square):
        raise AnalysisError(f"the periodic signal '{shape}' is too large: its mean square "
                            "overflows the floating-point range; rescale it (other units)")
    remainder = _remainders(a0, a, b, mean_square)
    within = np.flatnonzero(remainder <= tolerance)
    if not len(within):
        raise AnalysisError(f"the series of '{shape}' needs more than {max_harmonics} "
                            f"harmonics for the tolerance {tolerance:g}")
    H = max(int(within[0]) + 1, 1)
    return FourierSeries(float(period), float(a0), a[:H].copy(), b[:H].copy(),
                         float(remainder[H - 1]), shape)


def _sampled(function: Callable[[np.ndarray], np.ndarray], period: float, tolerance: float,
             max_harmonics: int) -> tuple[float, np.ndarray, np.ndarray, float]:
    """Coefficients by FFT, the sampling doubled until they settle."""
    previous = None
    samples = 1024
    while True:
        t = np.arange(samples) * period / samples
        values = np.broadcast_to(np.asarray(function(t), dtype=float), t.shape)
        if not np.isfinite(values).all():
            raise AnalysisError("the periodic signal is not finite over its period")
        spectrum = np.fft.rfft(values) / samples
        a0 = float(spectrum[0].real)
        a = 2 * spectrum[1:samples // 4].real
        b = -2 * spectrum[1:samples // 4].imag
        with np.errstate(over="ignore"):
            mean_square = float(np.mean(values**2))
        if not math.isfinite(mean_square):
            return a0, a, b, mean_square
        scale = math.sqrt(mean_square) or 1.0
        if previous is not None:
            k = len(previous[0])
            change = max(np.abs(a[:k] - previous[0]).max(), np.abs(b[:k] - previous[1]).max())
            reached = _remainders(a0, a, b, mean_square)[-1] <= tolerance
            if (change <= tolerance / 10 * scale and reached) or samples >= 4 * max_harmonics:
                return a0, a, b, mean_square
        previous = (a, b)
        samples *= 2


@dataclass(frozen=True)
class PeriodicResponse(FieldsJSON, Framed):
    """The stationary response to a periodic load, harmonic by harmonic and summed.

    Attributes
    ----------
    series : FourierSeries
        The load's series.
    names : tuple of str
        The responses (kept coordinates, then outputs).
    mean : mapping
        name -> the constant part (response to a0).
    harmonics : mapping
        name -> complex amplitudes z_n of harmonics 1..H: response =
        mean + Re(sum z_n e^(i n W t)).
    time : ndarray
        One period, sampled.
    history : mapping
        name -> the summed response at ``time``.
    largest : mapping
        name -> the largest |response| over the period (on the samples).

    Examples
    --------
    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`: the
    ``periodic`` of ``resonant solve --json``); the history over the period is summed again
    from the harmonics on reading, as the analysis sums it, so it is the same numbers:

    >>> import json, resonant
    >>> r = periodic_load_response(
    ...     resonant.load("examples/teaching/fourier_square.toml").linearize())
    >>> back = PeriodicResponse.from_dict(json.loads(json.dumps(r.to_dict())))
    >>> back.to_dict() == r.to_dict(), (back.history["x"] == r.history["x"]).all()
    (True, np.True_)
    """

    #: the columns of to_frame() (resonant.analyses.result_fields.Framed)
    _frame = (("time", "time"), ("history", "{key}"))

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): the series, one
    #: record per response (the first 50 harmonics' amplitudes and phases for the reader,
    #: every complex amplitude); the history is summed again from them on reading
    _json_order = ("period_s", "harmonics", "remainder", "shape", "responses", "warnings",
                   "series")
    _by_name = {"responses": ("names", ("mean", "largest", "amplitudes", "phases",
                                        "coefficients"))}

    series: FourierSeries = saved()
    names: tuple[str, ...] = saved(keys_of="responses")
    mean: dict[str, float] = saved(by_name="responses", codec=PLAIN_NUMBER)
    harmonics: dict[str, np.ndarray] = saved(by_name="responses", key="coefficients")
    time: np.ndarray = saved(written=False)
    history: dict[str, np.ndarray] = saved(written=False)
    largest: dict[str, float] = saved(by_name="responses", codec=PLAIN_NUMBER)
    warnings: tuple[str, ...] = saved(())

    def __post_init__(self) -> None:
        freeze_fields(self)

    def _derived_json(self) -> dict[str, Any]:
        s = self.series
        return {"period_s": s.period, "harmonics": s.harmonics, "remainder": s.remainder,
                "shape": s.shape}

    def _derived_record(self, group: str, name: str) -> dict[str, Any]:
        shown = self.harmonics[name][:min(50, self.series.harmonics)]
        return {"amplitudes": np.abs(shown).tolist(), "phases": np.angle(shown).tolist()}

    @classmethod
    def _check_saved(cls, values: dict[str, Any], saved_data: Saved) -> None:
        """The history over the period summed again from the harmonics, as the analysis
        sums it (the same numbers)."""
        series, names = values["series"], values["names"]
        if np.shape(series.b) != np.shape(series.a) or np.ndim(series.a) != 1:
            raise saved_data.error("has a and b of different lengths", "series")
        for name in names:
            if np.shape(values["harmonics"][name]) != (series.harmonics,):
                raise saved_data.error(f"does not hold {series.harmonics} harmonics",
                                       f"responses.{name}.coefficients")
        Z = np.empty((series.harmonics, len(names)), dtype=complex)
        for i, name in enumerate(names):
            Z[:, i] = values["harmonics"][name]
        summed = _summed(series, names, Z, np.array([values["mean"][n] for n in names]),
                         values.get("warnings", ()))
        values.update(time=summed.time, history=summed.history, largest=summed.largest,
                      mean=summed.mean, harmonics=summed.harmonics)



def periodic_response(system: LinearSystem, signal: str, series: FourierSeries, *,
                      derivative: int = 0, names: Sequence[str] | None = None,
                      method: str = "auto", deadline: Deadline = NO_DEADLINE
                      ) -> PeriodicResponse:
    """The stationary response when a signal of the model (or a force on a coordinate)
    follows a periodic series.

    Parameters
    ----------
    system : LinearSystem
    signal : str
        A signal of the model, or a coordinate (a generalized force on it).
    series : FourierSeries
        The signal's (or its derivative's) series.
    derivative : int
        The series is of this derivative of the signal (2: an acceleration).
    names : sequence of str, optional
        The coordinates and outputs to report (default all).
    method : str
        The kernel's method.
    deadline : Deadline, optional

    Returns
    -------
    PeriodicResponse

    Raises
    ------
    AnalysisError
        For a mean load on a system without static stiffness, or a singular harmonic.
    """
    num = system.numeric(deadline)
    keep, outputs = responses_to_solve(num, names)
    load = RandomInput(signal, derivative, None, None)
    transfer = Transfer(system, num, [load], keep, method, deadline)
    n = np.arange(1, series.harmonics + 1)
    frequencies = n / series.period
    H = transfer(frequencies, outputs)[:, :, 0]                   # (H, responses)
    c = series.a - 1j * series.b                                  # s = Re(c e^(i n W t))
    Z = H * c[:, None]
    responses = [num.coordinates[i] for i in keep] + outputs
    mean = _mean(transfer, outputs, series.a0, derivative, len(responses))
    return _summed(series, tuple(responses), Z, mean, tuple(transfer.warnings))


def _summed(series: FourierSeries, responses: tuple[str, ...], Z: np.ndarray,
            mean: np.ndarray, warnings: tuple[str, ...]) -> PeriodicResponse:
    """The result from the harmonics Z (H, responses) and the means: the history over one
    period summed by an inverse FFT, and its largest excursions."""
    count = max(SAMPLES_PER_HARMONIC * series.harmonics, 4096)
    spectrum = np.zeros((count // 2 + 1, len(responses)), dtype=complex)
    spectrum[1:series.harmonics + 1] = Z * count / 2
    samples = np.fft.irfft(spectrum, n=count, axis=0) + mean[None, :]
    time = np.arange(count) * series.period / count
    return PeriodicResponse(
        series, responses, {r: float(mean[i]) for i, r in enumerate(responses)},
        {r: Z[:, i].copy() for i, r in enumerate(responses)}, time,
        {r: samples[:, i].copy() for i, r in enumerate(responses)},
        {r: float(np.abs(samples[:, i]).max()) for i, r in enumerate(responses)},
        warnings)


def _mean(transfer: Transfer, outputs: Sequence[str], a0: float, derivative: int,
          count: int) -> np.ndarray:
    """The response to the constant a0 (a static load; zero for a derivative's mean)."""
    if a0 == 0:
        return np.zeros(count)
    if derivative > 0:
        raise AnalysisError("the series of a derivative (a velocity or an acceleration) has "
                            "a nonzero mean: the displacement would grow without bound")
    try:
        H0 = transfer(np.array([0.0]), outputs)[0, :, 0]
    except AnalysisError:
        raise AnalysisError("the periodic load has a mean, but the system has no static "
                            "stiffness (a rigid-body mode): there is no stationary "
                            "response") from None
    return (H0 * a0).real


def periodic_load_response(system: LinearSystem, spec: PeriodicSpec | None = None, *,
                           names: Sequence[str] | None = None, method: str = "auto",
                           deadline: Deadline = NO_DEADLINE) -> PeriodicResponse:
    """The stationary response to the model's ``[periodic]`` load: its series, then
    :func:`periodic_response`.

    Parameters
    ----------
    system : LinearSystem
    spec : PeriodicSpec, optional
        The load (default: the model's ``[periodic]`` section).
    names : sequence of str, optional
    method : str
    deadline : Deadline, optional

    Returns
    -------
    PeriodicResponse

    Raises
    ------
    ModelError
        Without a ``[periodic]`` section.
    AnalysisError
        As :func:`fourier_series` and :func:`periodic_response`.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/shaker_gevs.toml").linearize()
    >>> spec = PeriodicSpec("y", 0, "triangle", 1e-3, 0.01)    # the table: 1 mm, 100 Hz
    >>> result = periodic_load_response(system, spec, names=["z"])
    >>> result.series.harmonics, round(result.largest["z"] * 1e3, 3)
    (11, 0.34)
    """
    if spec is None:
        spec = system.model.periodic_section if system.model is not None else None
        if spec is None:
            raise ModelError(Problem("the model has no [periodic] section: add one with the "
                                     "signal, its shape and period (docs/model-format.md)",
                                     system.source, "periodic"))
    return periodic_response(system, spec.signal, load_series(system, spec),
                             derivative=spec.derivative, names=names, method=method,
                             deadline=deadline)


def load_series(system: LinearSystem, spec: PeriodicSpec) -> FourierSeries:
    """The Fourier series of a ``[periodic]`` load: the closed form of its shape, or its
    expression at the model's parameter values sampled and transformed.

    Parameters
    ----------
    system : LinearSystem
        The model's system (its parameter values enter an expression).
    spec : PeriodicSpec

    Returns
    -------
    FourierSeries

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/teaching/fourier_square.toml").linearize()
    >>> load_series(system, system.model.periodic_section).harmonics
    4053
    """
    function = None
    if spec.expression is not None:
        expression, scale = spec.expression, spec.amplitude
        values = dict(system.model.parameter_values) if system.model is not None else {}

        def function(t: np.ndarray) -> np.ndarray:
            value = scale * np.asarray(numeric_value(expression, {**values, "t": t}),
                                       dtype=float)
            return np.broadcast_to(value, t.shape).copy()
    return fourier_series(spec.shape, spec.amplitude, spec.period, tolerance=spec.tolerance,
                          function=function)


#: harmonics listed by :func:`periodic_text`
SHOWN_HARMONICS = 5


def periodic_text(result: PeriodicResponse, units: ResultUnits | None = None) -> str:
    """The periodic load's series and the response: per harmonic, the mean and the
    largest excursion of the sum, as text.

    Parameters
    ----------
    result : PeriodicResponse
    units : ResultUnits, optional
        The display units (the coordinates' declared ones, ``--units``; default SI).

    Returns
    -------
    str

    Examples
    --------
    >>> import resonant
    >>> from resonant.analyses.periodic_load import fourier_series, periodic_response
    >>> system = resonant.load("examples/shaker_gevs.toml").linearize()
    >>> result = periodic_response(system, "y", fourier_series("triangle", 1e-3, 0.01),
    ...                            names=["z"])
    >>> print(periodic_text(result).splitlines()[0])
    Periodic load: triangle, period 0.01 s, 11 harmonics (remainder 0.0097 of the RMS)
    """
    series = result.series
    lines = [f"Periodic load: {series.shape}, period {series.period:.6g} s, "
             f"{series.harmonics} harmonics (remainder {series.remainder:.2g} of the RMS)"]
    shown = min(SHOWN_HARMONICS, series.harmonics)
    header = ("name", "unit", "mean", "largest", *(f"|z_{n + 1}|" for n in range(shown)))
    each = {n: units.unit(n) if units is not None else NO_UNIT for n in result.names}
    rows = tuple((printable(name, limit=40), each[name].text or "SI",
                  number_cell(each[name](result.mean[name])),
                  number_cell(each[name](result.largest[name])),
                  *(number_cell(each[name](abs(result.harmonics[name][n])))
                    for n in range(shown)))
                 for name in result.names)
    lines.append(ResultTable(header, rows).text())
    lines.append("  the sum of the harmonics' stationary responses: mean, largest "
                 "|excursion| over a period, amplitudes of the first harmonics")
    lines += [f"warning: {w}" for w in result.warnings]
    return "\n".join(lines) + "\n"


__all__ = ["SHAPES", "FourierSeries", "fourier_series", "PeriodicResponse",
           "periodic_load_response", "periodic_response", "load_series"]
