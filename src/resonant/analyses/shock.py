"""Shock pulses and the shock response spectrum (SRS), by the exact ramp-invariant method.

A shock is given as samples of a base acceleration (or force) a(t) at a constant step;
between samples it is taken as linear, the oscillators start at rest at the first sample.
Every response here is then *exact*: a linear
system driven by a piecewise-linear input is integrated with its state-transition matrix
(the first-order hold, "ramp invariant" discretization), not by a numerical integrator.
For a single-DOF oscillator this is Smallwood's recursive filter (Smallwood, "An improved
recursive formula for calculating shock response spectra", Shock and Vibration Bulletin 51,
1981), the digital method of ISO 18431-4:2007 (Mechanical vibration and shock -- Signal
processing -- Part 4: Shock-response spectrum analysis).

The SRS at a natural frequency f_n with damping ratio zeta (or Q = 1/(2 zeta)) is the
largest |response| of the oscillator z'' + 2 zeta w z' + w^2 z = -a(t) (w = 2 pi f_n, z the
relative displacement, zero initial state):

* ``"absolute acceleration"``: z'' + a = -(2 zeta w z' + w^2 z);
* ``"pseudo-velocity"``: w z;
* ``"relative displacement"``: z.

The spectra are ISO 18431-4's (section 3): ``primary`` is the largest |response| while
the excitation lasts (0 <= t <= tau: a pulse's duration, or the record's end T for a
history unless its ``excitation_end`` is given), ``residual`` the largest after it (t >
tau: the samples up to T and the free vibration from the state at T, whose extrema are
found exactly; when the signal is zero after tau, the free vibration from the state at
tau, exact, and likewise from the sample on which the signal stays zero before T: a long
quiet record costs no more than its excitation), ``maximax`` the larger of the two;
``positive`` and ``negative`` are the largest positive response and the magnitude of
the largest negative one over all time (maximax is the larger of these too).  Each
extremum of the samples is refined by evaluating the exact response at 64 points within
the two steps around it.

Examples
--------
>>> import numpy as np
>>> t, a = pulse("half-sine", 1.0, 0.01, 1e-5)
>>> round(float(np.trapezoid(a, t)), 6)      # area 2 A tau / pi
0.006366
>>> srs = shock_response_spectrum(a, 1e-5, [1.0, 80.0, 10000.0], damping=0.0)
>>> srs.maximax.round(3).tolist()   # 4 A tau f_n at low f_n, 1.77 A near 0.8/tau, then A
[0.04, 1.768, 1.005]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..arrays import freeze_fields
from ..charts import (
    COLORS,
    Chart,
    Charts,
    Curve,
    PathArg,
    axes_list,
    check_plot_path,
    draw_figure,
    save_figure,
    unit_text,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError
from ..model.pulses import PULSE_KINDS, PULSES
from ..model.units import TIME, UnitError, parse_unit
from ..model.units_display import ResultUnits, Shown, shown_unit
from ..tables import ResultTable, number_column
from .result_fields import FieldsJSON, Framed, saved

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: the responses an SRS can be of
QUANTITIES = ("absolute acceleration", "pseudo-velocity", "relative displacement")
#: most samples of a signal (a few arrays of this length are held per oscillator)
MAX_SAMPLES = 10_000_000
#: most samples x natural frequencies of one spectrum (each oscillator filters the signal)
MAX_WORK = 500_000_000
#: points evaluated between samples around the largest sample (peak refinement)
REFINE = 64


def pulse(kind: str, amplitude: float, duration: float, step: float,
          total: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Samples of a classical shock pulse, starting at t = 0.

    Parameters
    ----------
    kind : {"half-sine", "haversine", "sawtooth", "rectangular", "step", "impulse"}
        ``half-sine`` A sin(pi t / tau); ``haversine`` A sin^2(pi t / tau);
        ``sawtooth`` the terminal-peak sawtooth A t / tau, then back to 0 in one step;
        ``rectangular`` A for tau (rising and falling in one step); ``step`` A from t = 0
        on (rising in one step); ``impulse`` a triangle of one step on each side whose
        area is ``amplitude`` (units of the signal times s): an ideal impulse as far as
        the sampling resolves it.
    amplitude : float
        The peak value A (the area for ``impulse``).
    duration : float
        The pulse's duration tau (s); for ``step``, how long it is sampled.
    step : float
        The sampling step (s).
    total : float, optional
        The length of the record (default: the pulse's duration plus one step).

    Returns
    -------
    t, a : ndarray
        The sample times and values.

    Raises
    ------
    AnalysisError
        For an unknown kind, a step not below the duration, or too many samples.

    Examples
    --------
    >>> t, a = pulse("sawtooth", 2.0, 0.004, 0.001)
    >>> a.tolist()
    [0.0, 0.5, 1.0, 1.5, 2.0, 0.0]
    """
    if kind not in PULSES:
        raise AnalysisError(f"unknown pulse '{kind}'; the pulses are {', '.join(PULSES)}")
    if not (math.isfinite(duration) and math.isfinite(step) and 0 < step < duration):
        raise AnalysisError(f"the step ({step:g} s) must be positive and below the pulse's "
                            f"duration ({duration:g} s)")
    if not math.isfinite(amplitude):
        raise AnalysisError(f"the pulse's amplitude {amplitude:g} must be a finite number")
    end = duration + step if total is None else total
    ratio = end / step
    if not ratio <= MAX_SAMPLES:
        raise AnalysisError(f"{ratio:.3g} samples (duration / step); a signal is limited to "
                            f"{MAX_SAMPLES}: a larger step or a shorter duration")
    count = int(round(ratio)) + 1
    t = np.arange(count) * step
    a = PULSE_KINDS[kind].samples(t, amplitude, duration, step)
    return t, a


def pulse_end(kind: str, duration: float, step: float) -> float | None:
    """Where the excitation of a sampled classical pulse ends (ISO 18431-4's primary
    spectrum is of the response until then): its duration; two steps for an impulse (the
    triangle of :func:`pulse`); None for a step, which lasts the whole record.

    Parameters
    ----------
    kind : str
        One of :data:`PULSES`.
    duration, step : float
        The pulse's duration and its sampling step (s).

    Returns
    -------
    float or None

    Examples
    --------
    >>> pulse_end("half-sine", 0.011, 1e-5), pulse_end("impulse", 0.01, 1e-4)
    (0.011, 0.0002)
    """
    if kind == "step":
        return None
    return 2 * step if kind == "impulse" else duration


def _phi(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """e^z, (e^z - 1)/z and (e^z - 1 - z)/z^2, accurate also for small |z|."""
    E = np.exp(z)
    small = np.abs(z) < 1e-3
    zs = np.where(small, 1.0, z)
    phi1 = np.where(small, 1 + z / 2 + z**2 / 6 + z**3 / 24, (E - 1) / zs)
    phi2 = np.where(small, 0.5 + z / 6 + z**2 / 24 + z**3 / 120, (E - 1 - z) / zs**2)
    return E, phi1, phi2


def ramp_invariant(poles: np.ndarray, step: float
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The exact first-order-hold recursion of modes z' = s z + u (u linear in each step).

    z[k+1] = E z[k] + g0 u[k] + g1 u[k+1] with E = e^(sT), g1 = T phi2(sT) and
    g0 = T (phi1(sT) - phi2(sT)).

    Parameters
    ----------
    poles : ndarray
        The modes' eigenvalues s (complex).
    step : float
        The sampling step T.

    Returns
    -------
    E, g0, g1 : ndarray

    Examples
    --------
    >>> E, g0, g1 = ramp_invariant(np.array([0j]), 0.5)    # an integrator: trapezoid rule
    >>> E.real.tolist(), g0.real.tolist(), g1.real.tolist()
    ([1.0], [0.25], [0.25])
    """
    E, phi1, phi2 = _phi(np.asarray(poles, dtype=complex) * step)
    return E, step * (phi1 - phi2), step * phi2


def _oscillator(f: float, zeta: float) -> tuple[complex, complex]:
    """The pole s (positive imaginary part) and the input weight c of the SRS oscillator.

    z'' = -w^2 z - 2 zeta w z' - a is z = 2 Re(q) for the mode q' = s q + c a with
    c = -1 / (s - conj(s)) (imaginary, so that z' = 2 Re(s q) has no direct term in a).
    """
    w = 2 * math.pi * f
    if not 0 <= zeta < 1:
        raise AnalysisError(f"the damping ratio {zeta:g} must lie in [0, 1) (Q > 0.5)")
    s = complex(-zeta * w, w * math.sqrt(1 - zeta * zeta))
    return s, -1 / (s - s.conjugate())


def _lfilter(b: npt.ArrayLike, a: npt.ArrayLike, x: np.ndarray, zi: npt.ArrayLike | None
             ) -> np.ndarray:
    from scipy.signal import lfilter

    result: np.ndarray = lfilter(b, a, x) if zi is None else lfilter(b, a, x, zi=zi)[0]
    return result


def _output(q: np.ndarray, s: complex, w: float, zeta: float, quantity: str) -> np.ndarray:
    """The response from the modal coordinate: z = 2 Re q, z' = 2 Re(s q)."""
    z = 2 * q.real
    if quantity == "relative displacement":
        return z
    if quantity == "pseudo-velocity":
        return w * z
    v = 2 * (s * q).real
    return -(2 * zeta * w * v + w * w * z)


@dataclass(frozen=True)
class ShockSpectrum(FieldsJSON, Framed):
    """The shock response spectrum of a signal.

    Attributes
    ----------
    frequency : ndarray
        Natural frequencies (Hz).
    maximax, primary, residual : ndarray
        The largest |response| overall, while the excitation lasts (t <= excitation_end),
        and after it (ISO 18431-4).
    positive, negative : ndarray
        The largest positive response and the magnitude of the largest negative one, over
        all time.
    quantity : str
        The response (see :data:`QUANTITIES`).
    damping : float
        The damping ratio zeta (Q = 1/(2 zeta)).
    duration : float
        The signal's length T (s).
    excitation_end : float
        tau (s): where primary ends and residual starts (a sample time).

    Examples
    --------
    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`, the JSON of
    ``resonant srs``) and read back:

    >>> import json
    >>> t, a = pulse("half-sine", 1.0, 0.01, 1e-5)
    >>> srs = shock_response_spectrum(a, 1e-5, [1.0, 80.0, 10000.0])
    >>> back = ShockSpectrum.from_dict(json.loads(json.dumps(srs.to_dict())))
    >>> back.to_dict() == srs.to_dict(), (back.maximax == srs.maximax).all()
    (True, np.True_)
    """

    #: the columns of to_frame() (resonant.analyses.result_fields.Framed)
    _frame = (("frequency", "frequency_hz"), ("maximax", "maximax"), ("primary", "primary"),
              ("residual", "residual"), ("positive", "positive"), ("negative", "negative"))

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON)
    _json_order = ("frequency_hz", "maximax", "primary", "residual", "positive", "negative",
                   "quantity", "damping_ratio", "Q", "duration_s", "excitation_end_s",
                   "warnings")

    frequency: np.ndarray = saved(key="frequency_hz")
    maximax: np.ndarray = saved(axes=("frequency",))
    primary: np.ndarray = saved(axes=("frequency",))
    residual: np.ndarray = saved(axes=("frequency",))
    positive: np.ndarray = saved(axes=("frequency",))
    negative: np.ndarray = saved(axes=("frequency",))
    quantity: str = saved()
    damping: float = saved(key="damping_ratio")
    duration: float = saved(key="duration_s")
    excitation_end: float = saved(key="excitation_end_s")
    warnings: tuple[str, ...] = saved(default=())

    def __post_init__(self) -> None:
        freeze_fields(self)

    def _derived_json(self) -> dict[str, Any]:
        return {"Q": None if self.damping == 0 else 1 / (2 * self.damping)}

    def table(self, unit: str = "", units: ResultUnits | None = None) -> ResultTable:
        """The spectrum's numbers (:func:`srs_table`).

        Parameters
        ----------
        unit : str
            The signal's SI unit, for the headings.
        units : ResultUnits, optional
            The display units (``--units``).

        Returns
        -------
        resonant.tables.ResultTable
        """
        return srs_table(self, unit, units)

    def summary(self, unit: str = "", units: ResultUnits | None = None) -> str:
        """The text ``resonant srs`` prints (:func:`srs_text`).

        Parameters
        ----------
        unit : str
            The signal's SI unit, for the headings.
        units : ResultUnits, optional
            The display units (``--units``).

        Returns
        -------
        str
        """
        return srs_text(self, unit, units)

    def chart(self, time: npt.ArrayLike | None = None, signal: npt.ArrayLike | None = None,
              unit: str = "") -> Charts:
        """The figure's description (:func:`srs_chart`), under the input's history where
        it is given.

        Parameters
        ----------
        time, signal : array_like, optional
            The input's history.
        unit : str
            The signal's unit, for the labels.

        Returns
        -------
        resonant.charts.Charts
        """
        return srs_chart(self, time, signal, unit)

    def plot(self, path: PathArg = None, ax: Axes | Sequence[Axes] | None = None,
             unit: str = "") -> Figure:
        """The spectrum drawn with matplotlib (:func:`plot_srs`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        ax : matplotlib Axes, optional
            Draw into the caller's axes.
        unit : str
            The signal's unit, for the labels.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return plot_srs(self, path=path, ax=ax, unit=unit)


def _weight(s: complex, w: float, zeta: float, quantity: str) -> complex:
    """p with response = 2 Re(p q) when the input is zero (the free vibration)."""
    if quantity == "relative displacement":
        return 1.0 + 0j
    if quantity == "pseudo-velocity":
        return complex(w)
    return -(2 * zeta * w * s + w * w)


def _free_extremes(q_start: complex, s: complex, w: float, zeta: float, quantity: str
                   ) -> tuple[float, float]:
    """The largest and the smallest response of the free vibration from the modal state
    ``q_start`` on (t >= 0), exact: its value at 0 and its first extrema."""
    r = _weight(s, w, zeta, quantity) * q_start
    alpha, wd = -s.real, s.imag
    # y(t) = 2 |r| e^(-alpha t) cos(wd t + arg r): extrema where tan(wd t + arg r) = -alpha/wd;
    # they alternate in sign and shrink, so the first of each sign is its largest
    base = math.atan2(-alpha, wd) - math.atan2(r.imag, r.real)
    times = [0.0] + [(base + k * math.pi) / wd for k in range(-2, 4)
                     if (base + k * math.pi) / wd > 0]
    values = [float(2 * (r * np.exp(s * t)).real) for t in times]
    return max(values), min(values)


def _split(excitation_end: float | None, step: float, samples: int) -> int:
    """The sample where the excitation ends: tau / step where tau is a sample time (to
    1e-9 of a step), else the last sample before tau; the record's last without a tau."""
    if excitation_end is None:
        return samples - 1
    if not (math.isfinite(excitation_end) and excitation_end > 0):
        raise AnalysisError(f"the end of the excitation {excitation_end:g} s must be a "
                            "positive time")
    ratio = excitation_end / step
    index = round(ratio) if abs(ratio - round(ratio)) <= 1e-9 * max(1.0, ratio) else \
        math.floor(ratio)
    if index > samples - 1:
        raise AnalysisError(f"the end of the excitation ({excitation_end:g} s) lies beyond "
                            f"the signal ({step * (samples - 1):g} s)")
    return max(int(index), 1)


def shock_response_spectrum(signal: Sequence[float] | np.ndarray, step: float,
                            frequencies: Sequence[float] | np.ndarray, *,
                            damping: float | None = None, Q: float | None = None,
                            quantity: str = "absolute acceleration",
                            excitation_end: float | None = None,
                            deadline: Deadline = NO_DEADLINE) -> ShockSpectrum:
    """The shock response spectrum (maximax, primary, residual, positive, negative) of a
    sampled base input, as ISO 18431-4 defines them.

    Parameters
    ----------
    signal : array_like
        The base acceleration at the times 0, step, 2 step, ... (linear in between).
    step : float
        The sampling step (s).
    frequencies : array_like
        The oscillators' natural frequencies (Hz, positive).
    damping : float, optional
        The damping ratio zeta (default 0.05, Q = 10).
    Q : float, optional
        Instead of ``damping``: Q = 1 / (2 zeta) > 0.5.
    quantity : str
        One of :data:`QUANTITIES`.
    excitation_end : float, optional
        tau (s): the primary spectrum is of 0 <= t <= tau, the residual of t > tau (a
        pulse's duration; default: the signal's last sample).  A tau between samples
        ends the primary part at the sample before it.
    deadline : Deadline, optional
        Checked at every natural frequency.

    Returns
    -------
    ShockSpectrum

    Raises
    ------
    AnalysisError
        For an invalid signal, step, frequency, damping or quantity.
    """
    a = np.asarray(signal, dtype=float).ravel()
    f = np.asarray(frequencies, dtype=float).ravel()
    if quantity not in QUANTITIES:
        raise AnalysisError(f"unknown SRS quantity '{quantity}'; one of "
                            f"{', '.join(QUANTITIES)}")
    if damping is not None and Q is not None:
        raise AnalysisError("give the damping ratio or Q, not both")
    if Q is not None:
        if not (math.isfinite(Q) and Q > 0.5):
            raise AnalysisError(f"Q = {Q:g} must be above 0.5 (an underdamped oscillator)")
        damping = 1 / (2 * Q)
    zeta = 0.05 if damping is None else float(damping)
    if len(a) < 2 or not np.isfinite(a).all():
        raise AnalysisError("the signal needs at least two finite samples")
    if len(a) > MAX_SAMPLES:
        raise AnalysisError(f"{len(a)} samples; a signal is limited to {MAX_SAMPLES}")
    if not (math.isfinite(step) and step > 0):
        raise AnalysisError(f"the sampling step {step:g} s must be positive")
    if not len(f) or not np.isfinite(f).all() or (f <= 0).any():
        raise AnalysisError("the SRS frequencies must be positive numbers")
    end = _split(excitation_end, step, len(a))
    quiet = not a[end + 1:].any()   # the signal is zero after the excitation: free vibration
    # only the samples up to where the signal stays zero are filtered: the response after
    # them is the free vibration, whose extremes _free_extremes finds exactly
    filtered = a[:_last_input(a, end) + 1]
    if len(filtered) * len(f) > MAX_WORK:
        raise AnalysisError(f"{len(filtered)} samples x {len(f)} natural frequencies; a "
                            f"spectrum is limited to {MAX_WORK:.3g}: fewer frequencies "
                            "(points) or a shorter or coarser signal")
    warnings = []
    if f.max() * step > 0.1:
        warnings.append(f"{1 / (f.max() * step):.3g} samples per cycle at {f.max():g} Hz: "
                        "the response is exact for the signal linear between samples, but "
                        "that signal may differ from the real one (ISO 18431-4 asks for "
                        "at least 10)")
    # the largest and smallest response while the excitation lasts and after it
    extremes = np.empty((len(f), 4))
    for i, fi in enumerate(f):
        deadline.check("while computing the shock response spectrum", analysis=True)
        s, c = _oscillator(float(fi), zeta)
        w = 2 * math.pi * float(fi)
        z, v = _displacement_and_velocity(filtered, s, c, step)
        y = _combine(z, v, w, zeta, quantity)
        oscillator = (filtered, z, v, y, s, c, w, zeta, quantity, step)
        extremes[i, :2] = _sampled_extremes(oscillator, 0, end)
        free = _free_extremes(_mode(z[-1], v[-1], s), s, w, zeta, quantity)
        after = free if quiet else _sampled_extremes(oscillator, end, len(filtered) - 1)
        extremes[i, 2:] = max(after[0], free[0]), min(after[1], free[1])
    if not np.isfinite(extremes).all():
        bad = float(f[~np.isfinite(extremes).all(axis=1)][0])
        raise AnalysisError(f"the oscillator's response at {bad:g} Hz overflows: the signal "
                            f"(up to {np.abs(a).max():.3g}), its step ({step:g} s) or the "
                            "frequency span too many orders of magnitude; rescale the signal "
                            "or choose frequencies nearer to 1/step")
    primary = np.maximum(extremes[:, 0], -extremes[:, 1])
    residual = np.maximum(np.maximum(extremes[:, 2], -extremes[:, 3]), 0.0)
    positive = np.maximum(np.maximum(extremes[:, 0], extremes[:, 2]), 0.0)
    negative = np.maximum(-np.minimum(extremes[:, 1], extremes[:, 3]), 0.0)
    return ShockSpectrum(f.copy(), np.maximum(primary, residual), primary, residual,
                         positive, negative, quantity, zeta, step * (len(a) - 1),
                         step * end, tuple(warnings))


def _last_input(a: np.ndarray, end: int) -> int:
    """The last sample the oscillators are stepped to: the excitation's ``end`` where the
    signal is zero after it; else the first sample from which the signal stays zero (the
    input, linear between samples, is zero from there on), or the record's last."""
    if not a[end + 1:].any():
        return end
    last = end + 1 + int(np.flatnonzero(a[end + 1:])[-1])
    return min(last + 1, len(a) - 1)


def _sampled_extremes(oscillator: tuple[Any, ...], first: int, last: int
                      ) -> tuple[float, float]:
    """The largest and smallest response from sample ``first`` to ``last``, each refined
    within the steps around it that lie in that range."""
    a, z, v, y, s, c, w, zeta, quantity, step = oscillator
    part = y[first:last + 1]
    found = []
    for k, pick in ((first + int(np.argmax(part)), max), (first + int(np.argmin(part)), min)):
        found.append(pick(float(y[k]), _refine(a, _mode(z[k], v[k], s), k, s, c, w, zeta,
                                               quantity, step, first, last, pick)))
    return found[0], found[1]


def _displacement_and_velocity(a: np.ndarray, s: complex, c: complex, step: float
                               ) -> tuple[np.ndarray, np.ndarray]:
    """z = 2 Re q and z' = 2 Re(s q) at every sample, by two real second-order filters.

    q[k+1] = E q[k] + c (g0 a[k] + g1 a[k+1]), q[0] = 0; y = 2 Re(p q) is then the real
    filter with the denominator 1 - 2 Re(E) z^-1 + |E|^2 z^-2 and the numerator
    2 Re(alpha) + 2 Re(beta - alpha conj E) z^-1 - 2 Re(beta conj E) z^-2
    (alpha = p c g1, beta = p c g0): Smallwood's form of the ramp-invariant filter.
    """
    E, g0, g1 = (x[0] for x in ramp_invariant(np.array([s]), step))
    den = [1.0, -2 * E.real, abs(E) ** 2]
    out = []
    for p in (1.0, s):
        alpha, beta = p * c * g1, p * c * g0
        num = [2 * alpha.real, 2 * (beta - alpha * E.conjugate()).real,
               -2 * (beta * E.conjugate()).real]
        # the filter alone has q[0] = c g1 a[0]; its initial state adds the free vibration
        # h[n] = -2 Re(alpha a[0] E^n) (a solution of the recursion) so that q[0] = 0
        h0, h1 = -2 * (alpha * a[0]).real, -2 * (alpha * a[0] * E).real
        y = _lfilter(num, den, a, [h0, h1 + den[1] * h0])
        out.append(y)
    return out[0], out[1]


def _mode(z: float, v: float, s: complex) -> complex:
    """q with 2 Re q = z and 2 Re(s q) = v."""
    real = z / 2
    return complex(real, (s.real * real - v / 2) / s.imag)


def _combine(z: np.ndarray, v: np.ndarray, w: float, zeta: float, quantity: str
             ) -> np.ndarray:
    if quantity == "relative displacement":
        return z
    if quantity == "pseudo-velocity":
        return w * z
    return -(2 * zeta * w * v + w * w * z)


def _refine(a: np.ndarray, q: complex, k: int, s: complex, c: complex, w: float,
            zeta: float, quantity: str, step: float, first: int, last: int,
            pick: Callable[..., float]) -> float:
    """The largest (``pick = max``) or smallest (``min``) response within the steps on
    both sides of sample ``k`` (its modal state ``q``) that lie between the samples
    ``first`` and ``last``, exact for the input linear between samples."""
    sub = step / REFINE
    E, g0, g1 = (x[0] for x in ramp_invariant(np.array([s]), sub))
    best = float(_output(np.array([q]), s, w, zeta, quantity)[0])
    for start in (k - 1, k):
        if start < first or start + 1 > last:
            continue
        if start == k - 1:   # back one step: q[k] = E q[k-1] + c (g0 a[k-1] + g1 a[k])
            Es, h0, h1 = (x[0] for x in ramp_invariant(np.array([s]), step))
            origin = (q - c * (h0 * a[k - 1] + h1 * a[k])) / Es
        else:
            origin = q
        u = np.linspace(a[start], a[start + 1], REFINE + 1)
        qs = _lfilter([c * g1, c * g0], [1.0, -E], u[1:], [E * origin + c * g0 * u[0]])
        best = pick(best, float(pick(_output(qs, s, w, zeta, quantity))))
    return best


#: at most this many rows in the text table (evenly picked)
MAX_ROWS = 40


#: the power of time by which each response's unit differs from the signal's
_TIME_POWER = {"absolute acceleration": 0, "pseudo-velocity": 1, "relative displacement": 2}


def spectrum_unit(spectrum: ShockSpectrum, unit: str, units: ResultUnits | None = None
                  ) -> Shown:
    """The display unit of the spectrum's values, from the signal's SI unit ``unit``: the
    signal's own for the absolute acceleration, times s for the pseudo-velocity, times s^2
    for the relative displacement; in the unit ``units`` chooses for that quantity.

    Examples
    --------
    >>> from resonant.model.units import display_units
    >>> t, a = pulse("half-sine", 100.0, 0.011, 1e-5)
    >>> srs = shock_response_spectrum(a, 1e-5, [100.0], quantity="relative displacement")
    >>> spectrum_unit(srs, "m/s^2").text, spectrum_unit(srs, "m/s^2",
    ...     ResultUnits(display=display_units(["mm"]))).text
    ('m', 'mm')
    """
    if not unit:
        return Shown("")
    try:
        dimension = parse_unit(unit).dimension * TIME ** _TIME_POWER[spectrum.quantity]
    except UnitError:
        return Shown(unit)
    return shown_unit(units, dimension.text())


def srs_table(spectrum: ShockSpectrum, unit: str = "",
              units: ResultUnits | None = None) -> ResultTable:
    """The spectrum as a table: natural frequency, maximax, primary, residual (at most
    :data:`MAX_ROWS` frequencies, spread over the range), each column in one notation.

    Parameters
    ----------
    spectrum : ShockSpectrum
    unit : str
        The signal's SI unit (``m/s^2``), for the headings.
    units : ResultUnits, optional
        The display units (``--units``: ``g``, ``mm``, ...; default SI).

    Returns
    -------
    resonant.tables.ResultTable
    """
    rows = np.unique(np.linspace(0, len(spectrum.frequency) - 1,
                                 min(MAX_ROWS, len(spectrum.frequency))).round().astype(int))
    shown = spectrum_unit(spectrum, unit, units)
    suffix = f" [{shown.text}]" if shown.text else ""
    frequency = [float(spectrum.frequency[i]) for i in rows]
    columns = [number_column(frequency, digits=5)] + [
        number_column([float(shown(v[i])) for i in rows])
        for v in (spectrum.maximax, spectrum.primary, spectrum.residual, spectrum.positive,
                  spectrum.negative)]
    return ResultTable(("f_n [Hz]", f"maximax{suffix}", f"primary{suffix}", f"residual{suffix}",
                        f"positive{suffix}", f"negative{suffix}"),
                       tuple(zip(*columns)), align="rrrrrr")


def srs_text(spectrum: ShockSpectrum, unit: str = "", units: ResultUnits | None = None) -> str:
    """The spectrum as text: what it is, its table (:func:`srs_table`), its warnings.

    Parameters
    ----------
    spectrum : ShockSpectrum
    unit : str
        The signal's SI unit, for the headings.
    units : ResultUnits, optional
        The display units (``--units``; default SI).

    Returns
    -------
    str
    """
    zeta = spectrum.damping
    q = "inf" if zeta == 0 else f"{1 / (2 * zeta):.4g}"
    time = _time_unit(spectrum.duration, units)
    lines = [f"Shock response spectrum: {spectrum.quantity}, zeta = {zeta:.4g} (Q = {q}), "
             f"signal {time(spectrum.duration):.4g} {time.text}",
             f"  (ISO 18431-4) primary: 0 <= t <= {time(spectrum.excitation_end):.4g} "
             f"{time.text} (the excitation), residual: after it; positive, negative: the "
             "largest response of each sign", srs_table(spectrum, unit, units).text()]
    shown = min(MAX_ROWS, len(spectrum.frequency))
    if shown < len(spectrum.frequency):
        lines.append(f"  ({shown} of {len(spectrum.frequency)} frequencies; the JSON form "
                     "holds all)")
    lines += [f"warning: {w}" for w in spectrum.warnings]
    return "\n".join(lines) + "\n"


def _time_unit(duration: float, units: ResultUnits | None) -> Shown:
    """The unit a shock's times are shown in: the one chosen, else ms for a history
    shorter than a second (an 11 ms pulse reads 0 to 40 ms, not 0 to 0.04 s)."""
    chosen = shown_unit(units, "s")
    return chosen if chosen.text != "s" or not 0 < duration < 1 else Shown("ms", 1e-3)


def srs_chart(spectrum: ShockSpectrum, time: npt.ArrayLike | None = None,
              signal: npt.ArrayLike | None = None, unit: str = "",
              reference: ShockSpectrum | None = None, reference_label: str = "input",
              units: ResultUnits | None = None, signal_label: str = "input") -> Charts:
    """What the figure of a shock response spectrum shows: the maximax, primary and
    residual spectra on log-log axes, under the input's history where it is given, and
    beside another spectrum (the input's own, for a response's) where given.

    Parameters
    ----------
    spectrum : ShockSpectrum
    time, signal : array_like, optional
        The input's history, drawn in a panel above the spectrum.
    unit : str
        The signal's SI unit (``m/s^2``), for the labels.
    reference : ShockSpectrum, optional
        A spectrum to draw beside (its maximax in grey).
    reference_label : str
        Its name in the legend (``input``: "maximax of the input").
    units : ResultUnits, optional
        The display units (``--units``: ``g``, ``ms``, ...; default SI, times of a history
        shorter than a second in ms).
    signal_label : str
        What the history is (``input``, or the response whose spectrum this is).

    Returns
    -------
    Charts

    Examples
    --------
    >>> from resonant.analyses.shock import pulse, shock_response_spectrum
    >>> t, a = pulse("half-sine", 100.0, 0.011, 1e-5)
    >>> srs = shock_response_spectrum(a, 1e-5, [10.0, 100.0, 1000.0])
    >>> charts = srs_chart(srs, t, a, "m/s^2")
    >>> [p.xlog for p in charts.panels], [c.label for c in charts.panels[1].curves]
    ([False, True], ['maximax', 'primary', 'residual'])
    >>> charts.panels[0].xlabel, charts.panels[1].ylabel
    ('time $t$ [ms]', 'absolute acceleration [m/s$^{2}$]')
    """
    panels = []
    if time is not None and signal is not None:
        t = np.asarray(time, dtype=float)
        shown_t = _time_unit(float(t[-1] - t[0]) if t.size > 1 else 0.0, units)
        t = shown_t(t)
        xlim = (float(t[0]), float(t[-1])) if t.size > 1 and t[-1] > t[0] else (0.0, 1.0)
        value = shown_unit(units, unit)
        label = f" [{unit_text(value.text)}]" if value.text else ""
        panels.append(Chart((Curve(t, value(np.asarray(signal, dtype=float)), signal_label,
                                   width=1.0),),
                            f"time $t$ [{shown_t.text}]", f"{signal_label}{label}", xlim,
                            title=f"{signal_label} history", legend="none"))
    f = np.asarray(spectrum.frequency, dtype=float)
    shown = spectrum_unit(spectrum, unit, units)
    label = f" [{unit_text(shown.text)}]" if shown.text else ""
    curves = [Curve(f, shown(np.asarray(spectrum.maximax)), "maximax", COLORS[0], 1.6),
              Curve(f, shown(np.asarray(spectrum.primary)), "primary", COLORS[1], 1.0,
                    "3.7 1.6"),
              Curve(f, shown(np.asarray(spectrum.residual)), "residual", COLORS[2], 1.0,
                    "1 1.65")]
    if reference is not None:
        curves.append(Curve(np.asarray(reference.frequency, dtype=float),
                            shown(np.asarray(reference.maximax)),
                            f"maximax of the {reference_label}", "#7f7f7f", 1.2))
    zeta = spectrum.damping
    q = "inf" if zeta == 0 else f"{1 / (2 * zeta):.3g}"
    positive = f[f > 0]
    xlim = (float(positive.min()), float(positive.max())) if positive.size > 1 else (1.0, 10.0)
    panels.append(Chart(tuple(curves), "natural frequency $f_n$ [Hz]",
                        f"{spectrum.quantity}{label}", xlim, ylog=True, xlog=True,
                        title=f"shock response spectrum ({spectrum.quantity}, Q = {q})"))
    return Charts(tuple(panels), size=(7.5, 6.4 if len(panels) > 1 else 4.2), sharex=False)


def plot_srs(spectrum: ShockSpectrum, time: npt.ArrayLike | None = None,
             signal: npt.ArrayLike | None = None, path: PathArg = None,
             ax: Axes | Sequence[Axes] | None = None, unit: str = "",
             units: ResultUnits | None = None, signal_label: str = "input") -> Figure:
    """The SRS (maximax, primary, residual) on log-log axes, with the input's history: the
    chart of :func:`srs_chart`, drawn with matplotlib.

    Parameters
    ----------
    spectrum : ShockSpectrum
    time, signal : array_like, optional
        The input's history, drawn in a panel above the spectrum.
    path : str or Path, optional
        Also write the figure there (``.png``, ``.svg`` or ``.pdf``).
    ax : Axes or pair of Axes, optional
        Draw into the caller's axes (the spectrum's, or (history's, spectrum's)).
    unit : str
        The signal's SI unit, for the labels.
    units : ResultUnits, optional
        The display units (``--units``).
    signal_label : str
        What the history is (``input``, or the response whose spectrum this is).

    Returns
    -------
    matplotlib.figure.Figure
    """
    check_plot_path(path)
    charts = srs_chart(spectrum, time, signal, unit, units=units, signal_label=signal_label)
    axes = None if ax is None else axes_list(ax)
    if axes is not None and len(axes) < len(charts.panels):
        charts = replace(charts, panels=charts.panels[-len(axes):])  # the spectrum's
    fig = draw_figure(charts, axes)
    save_figure(fig, path)
    return fig


__all__ = ["PULSES", "QUANTITIES", "pulse", "pulse_end", "ramp_invariant", "ShockSpectrum",
           "shock_response_spectrum"]
