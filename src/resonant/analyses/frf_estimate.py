"""Frequency response functions estimated from measured time histories (docs/testing.md).

One input x (a hammer's or a shaker's force) and responses y_j, cut into segments of
``segment`` samples overlapping by ``overlap``, each multiplied by its window and
transformed: Welch's averaged auto- and cross-spectra G_xx, G_yy, G_xy = E[X* Y] (the same
numbers as :func:`scipy.signal.csd` and :func:`scipy.signal.welch` with ``detrend=False``,
``tests/test_frf_estimate.py`` checks it; the input's transform is computed once for all
channels).  Then

* H1 = G_xy / G_xx: unbiased by noise on the output (the usual choice);
* H2 = G_yy / G_yx: unbiased by noise on the input (better at resonances);
* Hv (total least squares, equal noise on both): (G_yy - G_xx + sqrt((G_xx - G_yy)^2 +
  4 |G_xy|^2)) / (2 G_yx), between H1 and H2;
* the coherence gamma^2 = |G_xy|^2 / (G_xx G_yy), with H1 = gamma^2 H2.

Windows: ``hann`` (random excitation) or ``rectangular`` on both signals; for impact tests a
force window (the input kept over the first ``force_window`` of each segment, zero after)
and an exponential window exp(-t / tau) on both, tau such that it falls to ``exponential``
at the segment's end.  The exponential window adds the damping 1 / tau (s^-1) to every mode
(``added_decay``: subtract it from an identified pole's real part).

Warnings: coherence below ``coherence_limit`` near a peak of |H|, a signal that looks
clipped (several samples at its largest value: an overload), a second impact within a
segment of an impact test.

Examples
--------
>>> import numpy as np
>>> rng = np.random.default_rng(1)
>>> x = rng.standard_normal(8192)
>>> y = 2.0 * x                                     # a pure gain
>>> r = estimate_frf(x, {"y": y}, 1e-3, segment=1024)
>>> r.averages, round(float(abs(r.frf["y"]).mean()), 12), round(float(r.coherence["y"].min()), 12)
(15, 2.0, 1.0)
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..arrays import freeze_fields
from ..charts import (
    COLORS,
    Chart,
    Charts,
    Curve,
    charts_svg,
    check_plot_path,
    draw_figure,
    save_figure,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem, printable
from ..memory import require
from ..model.measured import MeasuredData, MeasuredFunction
from ..model.measurement_spec import ChannelMap, MeasurementSpec, match_channels, position_dofs
from ..model.random_spec import RandomInput
from ..model.units_display import ResultUnits, cyclic_shown
from ..system.base import LinearSystem
from .random_response import Transfer, responses_to_solve
from .result_fields import FieldsJSON, saved
from .results_json import Saved

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: the estimators
ESTIMATORS = ("H1", "H2", "Hv")
#: the windows on both signals
WINDOWS = ("hann", "rectangular")
#: coherence below which a peak is warned about
COHERENCE_LIMIT = 0.9
#: samples at the largest |value| from which a signal counts as clipped
CLIPPED_SAMPLES = 3

__all__ = ["MeasuredFRF", "estimate_frf", "frf_from_measurement", "model_frf", "ESTIMATORS",
           "WINDOWS"]


@dataclass(frozen=True)
class MeasuredFRF(FieldsJSON):
    """Frequency response functions estimated from time histories, with their coherence.

    Attributes
    ----------
    frequency : ndarray
        The spectral lines (Hz).
    frf : mapping
        Channel -> the complex FRF at ``frequency`` (response unit per input unit).
    coherence : mapping
        Channel -> the ordinary coherence (0 to 1).
    estimator : str
        ``"H1"``, ``"H2"`` or ``"Hv"``.
    window : str
        The window's description.
    averages : int
        The number of segments averaged.
    segment : int
        Samples per segment.
    step : float
        The sampling step (s).
    units : mapping
        Channel -> the FRF's unit (``"m/s^2/N"``; ``""`` when not known).
    added_decay : float
        The decay rate 1 / tau (s^-1) the exponential window adds to every mode (0 without).
    warnings : tuple of str

    Examples
    --------
    >>> import numpy as np
    >>> from resonant.analyses.frf_estimate import estimate_frf
    >>> x = np.random.default_rng(0).standard_normal(2048)
    >>> r = estimate_frf(x, {"y": 3 * x}, 0.01, segment=256)     # y = 3 x: H = 3
    >>> r.estimator, round(float(abs(r.frf["y"][10])), 9), round(float(r.coherence["y"][10]), 9)
    ('H1', 3.0, 1.0)
    >>> import json                                  # saved by its fields (FieldsJSON)
    >>> MeasuredFRF.from_dict(json.loads(json.dumps(r.to_dict()))).to_dict() == r.to_dict()
    True
    """

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): one record per
    #: channel (its FRF, coherence and unit)
    _json_order = ("frequency_hz", "estimator", "window", "averages", "segment", "step_s",
                   "added_decay_per_s", "channels", "warnings")
    _by_name = {"channels": ("frf", ("frf", "coherence", "unit"))}

    frequency: np.ndarray = saved(key="frequency_hz", axes=(None,))
    frf: dict[str, np.ndarray] = saved(by_name="channels")
    coherence: dict[str, np.ndarray] = saved(by_name="channels")
    estimator: str = saved()
    window: str = saved()
    averages: int = saved()
    segment: int = saved()
    step: float = saved(key="step_s")
    units: dict[str, str] = saved(by_name="channels", key="unit", missing="",
                                  default_factory=dict)
    added_decay: float = saved(0.0, key="added_decay_per_s", required=True)
    warnings: tuple[str, ...] = saved(())

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def names(self) -> tuple[str, ...]:
        """The channels in order."""
        return tuple(self.frf)

    @classmethod
    def _check_saved(cls, values: dict[str, Any], saved_data: Saved) -> None:
        lines = np.shape(values["frequency"])
        for key in ("frf", "coherence"):
            for name, value in values[key].items():
                if np.shape(value) != lines:
                    raise saved_data.error(f"has shape {np.shape(value)}, not {lines}",
                                           f"channels.{name}.{key}")

    def to_measured(self, source: str = "frf", dofs: Mapping[str, tuple[int, int]] | None = None,
                    excitation: str = "") -> MeasuredData:
        """The FRFs as measured functions (for :func:`resonant.model.measured.write_uff`).

        Parameters
        ----------
        source : str
            The name the data carries.
        dofs : mapping, optional
            Channel -> its (node, direction): each FRF's response, and under the name of
            the excitation channel their reference
            (:func:`resonant.model.measurement_spec.measurement_dofs`; default the
            channels' positions, the reference after them,
            :func:`resonant.model.measurement_spec.position_dofs`).
        excitation : str, optional
            The excitation channel (the key of the reference in ``dofs``).

        Returns
        -------
        MeasuredData
            One ``"frf"`` function per channel, then one ``"coherence"`` function each.

        Examples
        --------
        >>> x = np.random.default_rng(0).standard_normal(2048)
        >>> frfs = estimate_frf(x, {"y": 3 * x}, 0.01, segment=256).to_measured()
        >>> frfs.names, frfs.functions[0].response, frfs.functions[0].reference
        (('y', 'y coherence'), (1, 0), (2, 0))
        """
        f = np.asarray(self.frequency)
        places = dict(dofs) if dofs is not None else position_dofs([*self.frf, excitation])
        reference = places[excitation]
        frfs = [MeasuredFunction(k, "frf", f, np.asarray(h), "Hz", self.units.get(k, ""),
                                 places[k], reference) for k, h in self.frf.items()]
        coherences = [MeasuredFunction(f"{k} coherence", "coherence", f,
                                       np.asarray(self.coherence[k]), "Hz", "", places[k],
                                       reference) for k in self.frf]
        return MeasuredData(source, tuple(frfs + coherences))

    def chart(self, names: Sequence[str] | None = None,
              model: Mapping[str, np.ndarray] | None = None) -> Charts:
        """Magnitude, phase and coherence of the FRFs, the model's beside them.

        Parameters
        ----------
        names : sequence of str, optional
            The channels to draw (default all).
        model : mapping, optional
            Channel -> the model's FRF at :attr:`frequency` (:func:`model_frf`), dashed.

        Returns
        -------
        Charts
        """
        names = list(names) if names is not None else list(self.frf)
        f = np.asarray(self.frequency)
        xlim = (float(f[0]), float(f[-1]))
        magnitude, phase, coherence = [], [], []
        for k, name in enumerate(names):
            color = COLORS[k % len(COLORS)]
            h = np.asarray(self.frf[name])
            label = f"{name} ({self.estimator})"
            magnitude.append(Curve(f, np.abs(h), label, color))
            phase.append(Curve(f, np.degrees(np.angle(h)), label, color))
            coherence.append(Curve(f, np.asarray(self.coherence[name]), name, color))
            if model is not None and name in model:
                g = np.asarray(model[name])
                magnitude.append(Curve(f, np.abs(g), f"{name} (model)", color, dash="3.7 1.6"))
                phase.append(Curve(f, np.degrees(np.angle(g)), f"{name} (model)", color,
                                   dash="3.7 1.6"))
        unit = next((self.units.get(n, "") for n in names if self.units.get(n)), "")
        panels = (Chart(tuple(magnitude), "frequency [Hz]",
                        f"|H| [{unit}]" if unit else "|H|", xlim, ylog=True),
                  Chart(tuple(phase), "frequency [Hz]", "phase [deg]", xlim,
                        ylim=(-180.0, 180.0), legend="none"),
                  Chart(tuple(coherence), "frequency [Hz]", "coherence", xlim,
                        ylim=(0.0, 1.05), legend="none"))
        return Charts(panels, title=f"{self.estimator}, {self.window}, {self.averages} "
                                    "averages", heights=(2.0, 1.0, 1.0), size=(7.0, 6.0))

    def plot(self, path: str | os.PathLike[str] | None = None,
             names: Sequence[str] | None = None,
             model: Mapping[str, np.ndarray] | None = None,
             ax: Axes | Sequence[Axes] | None = None) -> Figure:
        """Draw :meth:`chart` with matplotlib (saved to ``path`` when given).

        Parameters
        ----------
        path : str or PathLike, optional
        names : sequence of str, optional
        model : mapping, optional
            The model's FRFs, drawn dashed.
        ax : matplotlib axes, optional
            Three axes to draw into.

        Returns
        -------
        matplotlib.figure.Figure
        """
        check_plot_path(path)
        fig = draw_figure(self.chart(names, model), ax)
        return save_figure(fig, path)

    def summary(self, units: ResultUnits | None = None) -> str:
        """A text table: each channel's peak and its coherence.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``: frequencies in the unit chosen; default Hz).

        Returns
        -------
        str

        Examples
        --------
        >>> x = np.random.default_rng(0).standard_normal(2048)
        >>> print(estimate_frf(x, {"y": 3 * x}, 0.01, segment=256).summary().splitlines()[0])
        H1 from 15 averages of 256 samples (hann, step 0.01 s, lines 0 to 50 Hz)
        """
        hz = cyclic_shown(units)
        f = hz(np.asarray(self.frequency, dtype=float))
        lines = [f"{self.estimator} from {self.averages} averages of {self.segment} samples "
                 f"({self.window}, step {self.step:.6g} s, lines {f[0]:.6g} to {f[-1]:.6g} "
                 f"{hz.text})",
                 f"{'channel':<16} {f'peak [{hz.text}]':>10} {'|H| peak':>12} {'unit':<10} "
                 f"{'coherence':>9}"]
        for name, h in self.frf.items():
            k = int(np.argmax(np.abs(h)))
            lines.append(f"{printable(name, limit=16):<16} {f[k]:>10.4g} {abs(h[k]):>12.4g} "
                         f"{printable(self.units.get(name, ''), limit=10):<10} "
                         f"{self.coherence[name][k]:>9.3f}")
        if self.added_decay:
            lines.append(f"the exponential window added the decay {self.added_decay:.6g} 1/s "
                         "to every mode (identify: added_decay)")
        lines.extend(f"warning: {w}" for w in self.warnings)
        return "\n".join(lines) + "\n"

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "measured-frf")


@dataclass(frozen=True)
class _Windows:
    """The input's and the responses' windows over one segment, and what they mean."""

    input: np.ndarray
    response: np.ndarray
    text: str
    decay: float


def _windows(window: str, segment: int, step: float, force_window: float | None,
             exponential: float | None) -> _Windows:
    from scipy.signal import get_window

    if window not in WINDOWS:
        raise ModelError(Problem(f"unknown window '{printable(window, limit=20)}'; choose "
                                 f"{', '.join(WINDOWS)}", "", "", "window"))
    base = get_window("hann" if window == "hann" else "boxcar", segment, fftbins=True)
    inp, resp = base.copy(), base.copy()
    text, decay = window, 0.0
    if force_window is not None:
        if not 0 < force_window <= 1:
            raise ModelError(Problem("the force window is the fraction of the segment kept, "
                                     "above 0 and at most 1", "", "", "force_window"))
        inp[int(math.ceil(force_window * segment)):] = 0.0
        text += f", force window {force_window:g}"
    if exponential is not None:
        if not 0 < exponential < 1:
            raise ModelError(Problem("the exponential window's final value must lie between "
                                     "0 and 1", "", "", "exponential"))
        tau = segment * step / -math.log(exponential)
        decay = 1.0 / tau
        ramp = np.exp(-np.arange(segment) * step / tau)
        inp, resp = inp * ramp, resp * ramp
        text += f", exponential to {exponential:g}"
    return _Windows(inp, resp, text, decay)


def _frames(x: np.ndarray, segment: int, hop: int) -> np.ndarray:
    """The segments of x as rows (a view; no copy)."""
    return np.lib.stride_tricks.sliding_window_view(x, segment)[::hop]


def _spectra(x: np.ndarray, y: np.ndarray, windows: _Windows, segment: int, hop: int,
             X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """G_yy and G_xy (unscaled averages over the segments) of one response."""
    Y = np.fft.rfft(_frames(y, segment, hop) * windows.response, axis=1)
    return (np.abs(Y) ** 2).mean(axis=0), (np.conj(X) * Y).mean(axis=0)


def _estimate(estimator: str, Gxx: np.ndarray, Gyy: np.ndarray, Gxy: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """The FRF by ``estimator`` and the coherence from the averaged spectra."""
    with np.errstate(divide="ignore", invalid="ignore"):
        coherence = np.abs(Gxy) ** 2 / (Gxx * Gyy)
        if estimator == "H1":
            H = Gxy / Gxx
        elif estimator == "H2":
            H = Gyy / np.conj(Gxy)
        else:
            root = np.sqrt((Gxx - Gyy) ** 2 + 4 * np.abs(Gxy) ** 2)
            # G_yy - G_xx + root cancels where G_yy << G_xx (a small FRF in SI): its
            # rationalized form 4 |G_xy|^2 / (G_xx - G_yy + root) there
            top = np.where(Gxx > Gyy, 4 * np.abs(Gxy) ** 2 / (Gxx - Gyy + root),
                           Gyy - Gxx + root)
            H = top / (2 * np.conj(Gxy))
    return H, np.clip(np.nan_to_num(coherence), 0.0, 1.0)


def estimate_frf(excitation: np.ndarray | Sequence[float],
                 responses: Mapping[str, np.ndarray | Sequence[float]], step: float, *,
                 estimator: str = "H1", window: str = "hann", segment: int | None = None,
                 overlap: float | None = None, force_window: float | None = None,
                 exponential: float | None = None, units: Mapping[str, str] | None = None,
                 band: tuple[float, float] | None = None,
                 coherence_limit: float = COHERENCE_LIMIT,
                 deadline: Deadline = NO_DEADLINE) -> MeasuredFRF:
    """FRFs of every response to one input, by Welch's averaged spectra.

    Parameters
    ----------
    excitation : array_like
        The input's samples.
    responses : mapping
        Channel -> its samples (as many as the input's).
    step : float
        The sampling step (s).
    estimator : {"H1", "H2", "Hv"}
    window : {"hann", "rectangular"}
        The window on both signals (before the impact windows).
    segment : int, optional
        Samples per segment (default: an eighth of the record; the whole record with an
        impact window).
    overlap : float, optional
        The segments' overlap, 0 to below 1 (default 0.5 with ``hann``, else 0).
    force_window : float, optional
        Keep the input over this first fraction of each segment only (impact tests).
    exponential : float, optional
        The exponential window's value at the end of the segment (impact tests).
    units : mapping, optional
        Channel -> the FRF's unit, carried to the result.
    band : (float, float), optional
        The lines kept (Hz).
    coherence_limit : float
        Peaks where the coherence falls below are warned about.
    deadline : Deadline, optional
        Checked between channels.

    Returns
    -------
    MeasuredFRF

    Raises
    ------
    ModelError
        For an unknown estimator or window, histories of different lengths, NaN samples, a
        segment or overlap out of range, or a band without a line.
    """
    if estimator not in ESTIMATORS:
        raise ModelError(Problem(f"unknown estimator '{printable(estimator, limit=20)}'; "
                                 f"choose {', '.join(ESTIMATORS)}", "", "", "estimator"))
    x = _samples(excitation, "the excitation")
    if not (math.isfinite(step) and step > 0):
        raise ModelError(Problem("the sampling step must be a positive number", "", "",
                                 "step"))
    impact = force_window is not None or exponential is not None
    segment = int(segment) if segment is not None else (len(x) if impact else len(x) // 8)
    overlap = (0.5 if window == "hann" and not impact else 0.0) if overlap is None \
        else float(overlap)
    if not 16 <= segment <= len(x) or not 0 <= overlap < 1:
        raise ModelError(Problem(f"the segment must hold 16 to {len(x)} samples and the "
                                 "overlap lie in [0, 1)", "", "", "segment"))
    hop = max(1, int(round(segment * (1 - overlap))))
    windows = _windows(window, segment, step, force_window, exponential)
    frequency = np.fft.rfftfreq(segment, step)
    lines = _band_lines(frequency, band)
    averages = (len(x) - segment) // hop + 1
    require(16.0 * averages * len(frequency) * 2, f"the spectra of {averages} segments",
            "use longer segments or fewer samples")
    X = np.fft.rfft(_frames(x, segment, hop) * windows.input, axis=1)
    Gxx = (np.abs(X) ** 2).mean(axis=0)
    empty = np.flatnonzero(~(Gxx[lines] > 1e-300 * max(float(Gxx.max()), 1e-300)))
    if len(empty) or not Gxx.max() > 0:
        where = frequency[lines][empty[0]] if len(empty) else 0.0
        raise ModelError(Problem(f"the excitation has no energy at {max(len(empty), 1)} "
                                 f"spectral lines (the first at {where:.6g} Hz): no FRF "
                                 "there; narrow the band", "", "", "band"))
    warnings = _clipping("the excitation", x)
    if force_window is not None:
        warnings += _double_impacts(_frames(x, segment, hop), step)
    frf, coherence = {}, {}
    for name, values in responses.items():
        deadline.check("while estimating the frequency responses", analysis=True)
        y = _samples(values, f"channel '{printable(name, limit=40)}'", len(x))
        Gyy, Gxy = _spectra(x, y, windows, segment, hop, X)
        H, gamma = _estimate(estimator, Gxx, Gyy, Gxy)
        frf[name], coherence[name] = H[lines], gamma[lines]
        warnings += _clipping(f"channel '{printable(name, limit=40)}'", y)
        warnings += _low_coherence(name, frequency[lines], frf[name], coherence[name],
                                   coherence_limit)
    return MeasuredFRF(frequency[lines], frf, coherence, estimator, windows.text, averages,
                       segment, float(step), dict(units or {}), windows.decay,
                       tuple(warnings))


def _samples(values: npt.ArrayLike, what: str, length: int | None = None) -> np.ndarray:
    array = np.asarray(values, dtype=float).ravel()
    if length is not None and len(array) != length:
        raise ModelError(Problem(f"{what} has {len(array)} samples, the excitation {length}: "
                                 "the channels must be sampled together"))
    bad = np.flatnonzero(~np.isfinite(array))
    if len(bad):
        raise ModelError(Problem(f"{what}: sample {bad[0] + 1} is NaN or infinite"))
    if len(array) < 16:
        raise ModelError(Problem(f"{what} has {len(array)} samples; at least 16 are needed"))
    return array


def _band_lines(frequency: np.ndarray, band: tuple[float, float] | None) -> np.ndarray:
    if band is None:
        return np.arange(len(frequency))
    lines = np.flatnonzero((frequency >= band[0]) & (frequency <= band[1]))
    if len(lines) < 2:
        raise ModelError(Problem(f"the band {band[0]:g} to {band[1]:g} Hz holds "
                                 f"{len(lines)} spectral lines (lines every "
                                 f"{frequency[1]:.6g} Hz up to {frequency[-1]:.6g} Hz)", "",
                                 "", "band"))
    return lines


def _clipping(what: str, x: np.ndarray) -> list[str]:
    """An overload: several samples at the signal's largest |value| (a flat top)."""
    top = float(np.abs(x).max())
    if top == 0:
        return [f"{what} is zero throughout"]
    at_top = np.abs(x) >= top * (1 - 1e-9)
    count = int(at_top.sum())
    runs = int(np.count_nonzero(at_top[1:] & at_top[:-1]))
    if count >= CLIPPED_SAMPLES and runs >= 1:
        return [f"{what} looks clipped: {count} samples at its largest value {top:.6g} "
                "(an overload of the acquisition; the FRF is wrong near it)"]
    return []


def _double_impacts(frames: np.ndarray, step: float) -> list[str]:
    """A second hit: the force rises above 10 % of its peak after falling below 5 %."""
    warnings = []
    for k, force in enumerate(frames):
        peak = float(np.abs(force).max())
        if peak == 0:
            continue
        first = int(np.argmax(np.abs(force)))
        below = np.flatnonzero(np.abs(force[first:]) < 0.05 * peak)
        if not len(below):
            continue
        rest = force[first + below[0]:]
        again = np.flatnonzero(np.abs(rest) > 0.1 * peak)
        if len(again):
            at = (first + below[0] + again[0]) * step
            warnings.append(f"segment {k + 1}: a double impact (a second hit at {at:.4g} s "
                            "into the segment); repeat that hit")
    return warnings


def _low_coherence(name: str, f: np.ndarray, h: np.ndarray, gamma: np.ndarray,
                   limit: float) -> list[str]:
    """Peaks of |H| (by prominence on a log scale) where the coherence is below ``limit``."""
    from scipy.signal import find_peaks

    magnitude = np.log(np.maximum(np.abs(h), 1e-300))
    peaks, _ = find_peaks(magnitude, prominence=1.0)
    warnings = []
    for p in peaks:
        near = gamma[max(0, p - 2):p + 3]
        if near.min() < limit:
            warnings.append(f"channel '{printable(name, limit=40)}': coherence "
                            f"{near.min():.2f} near the peak at {f[p]:.4g} Hz (below "
                            f"{limit:g}: noise, leakage or a nonlinearity there)")
    return warnings


def frf_from_measurement(data: MeasuredData, spec: MeasurementSpec, source: str = "", *,
                         estimator: str = "H1", window: str = "hann",
                         segment: int | None = None, overlap: float | None = None,
                         force_window: float | None = None,
                         exponential: float | None = None,
                         band: tuple[float, float] | None = None,
                         deadline: Deadline = NO_DEADLINE) -> MeasuredFRF:
    """The FRFs of the channels a model's ``[measurement]`` section names.

    Parameters
    ----------
    data : MeasuredData
        Time histories (:func:`~resonant.model.measured.read_uff`,
        :func:`~resonant.model.measured.read_histories`).
    spec : MeasurementSpec
        The excitation channel and the response channels.
    source : str
        The model file (for the messages).
    estimator, window, segment, overlap, force_window, exponential, band, deadline
        As :func:`estimate_frf`.

    Returns
    -------
    MeasuredFRF
        One FRF per response channel of the section, in its order.

    Raises
    ------
    ModelError
        When a channel is missing, is not a time history, or as :func:`estimate_frf`.
    """
    match_channels(spec, data.names, source, data.source)
    if not spec.excitation:
        raise ModelError(Problem("name the excitation channel to estimate FRFs from time "
                                 "histories", source, "measurement", "excitation"))
    x = data.function(spec.excitation)
    responses, units = {}, {}
    for channel in spec.channels:
        f = data.function(channel)
        if f.kind != "time" or x.kind != "time":
            raise ModelError(Problem(f"channel '{printable(channel, limit=40)}' is a "
                                     f"{f.kind} function, not a time history", data.source))
        responses[channel] = f.ordinate
        if f.ordinate_unit and x.ordinate_unit:
            units[channel] = f"{f.ordinate_unit}/{x.ordinate_unit}"
    return estimate_frf(x.ordinate, responses, x.step, estimator=estimator, window=window,
                        segment=segment, overlap=overlap, force_window=force_window,
                        exponential=exponential, units=units, band=band, deadline=deadline)


def model_frf(system: LinearSystem, signal: str, frequency: np.ndarray,
              channels: Mapping[str, ChannelMap], *,
              deadline: Deadline = NO_DEADLINE) -> dict[str, np.ndarray]:
    """The model's own FRF of each channel's quantity to one input, through the kernel.

    Parameters
    ----------
    system : LinearSystem
    signal : str
        The input: a signal of the model or a coordinate (a force on it).
    frequency : ndarray
        Hz.
    channels : mapping
        Channel -> its coordinate or output and derivative (``[measurement.channels]``).
    deadline : Deadline, optional

    Returns
    -------
    dict
        Channel -> the complex FRF (the derivative's factor (i w)^d included).

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_damped.toml").linearize()
    >>> h = model_frf(system, "F", np.array([0.0]), {"x3": ChannelMap("x3", 0)})
    >>> round(float(h["x3"].real[0]), 9)    # static flexibility 3/k
    0.003
    """
    f = np.asarray(frequency, dtype=float)
    num = system.numeric(deadline)
    names = sorted({c.name for c in channels.values()})
    keep, outputs = responses_to_solve(num, names)
    transfer = Transfer(system, num, [RandomInput(signal, 0, None, None)], keep, "auto",
                        deadline)
    H = transfer(f, outputs)[:, :, 0]
    order = [num.coordinates[i] for i in keep] + list(outputs)
    if transfer.warnings and not any(c.name in order for c in channels.values()):
        raise AnalysisError("; ".join(transfer.warnings))
    iw = 2j * np.pi * f
    return {channel: H[:, order.index(c.name)] * iw ** c.derivative
            for channel, c in channels.items()}
