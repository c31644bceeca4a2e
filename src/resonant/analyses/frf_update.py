"""Model updating against measured frequency response functions (docs/testing.md).

Where :mod:`.model_update` fits the identified natural frequencies (and shapes), this fits
the measured FRFs themselves at their spectral lines, so that no identification stands
between the test and the model: damping, residual flexibility and every mode in the band
take part.  The residuals at the lines f_l of each channel c (its FRF H_c to the input):

``"log"`` (the default)
    r = ln |H_c(f_l; p)| - ln |H_c,test(f_l)|: the log-magnitude error, which weighs a
    resonance peak and an antiresonance alike and ignores the phase (robust to a sensor's
    delay or a sign convention); r is the relative magnitude error for small errors.
``"complex"``
    r = (H_c(f_l; p) - H_c,test(f_l)) / s_c, real and imaginary parts, s_c the RMS of the
    channel's measured |H|: the phase counts too, and the peaks dominate.

They are minimized by :func:`scipy.optimize.least_squares` (trust-region reflective,
inside the bounds) over x = ln p.  The sensitivities dr/d ln p are central differences of
the model's FRF (relative step 1e-5 in p; the FRF is a smooth function of p away from an
undamped resonance, so the error is O(1e-10)), each model FRF a kernel solve
(:class:`~resonant.analyses.random_response.Transfer`, method ``"direct"`` so that no
reduced-model tolerance enters the differences).  The fitted values' standard deviations
come from the Jacobian at the solution, cov(ln p) = s^2 (J^T J)^-1, s the residuals' standard
deviation if known (``sigma``: in log magnitude, the relative magnitude noise), else
estimated from the residuals.  The correlation before and after is the FRAC (frequency
response assurance criterion, the MAC of two FRFs over the lines) of each channel and the
RMS of the residuals.

Examples
--------
>>> import numpy as np, resonant
>>> from resonant.model.measurement_spec import ChannelMap
>>> truth = resonant.load("examples/chain3_lab.toml").with_parameters(k1="1100 N/m")
>>> f = np.linspace(1.0, 10.0, 60)
>>> channels = {"d3": ChannelMap("x3")}
>>> test = model_frf(truth.linearize(), "F", f, channels)
>>> system = resonant.load("examples/chain3_lab.toml").linearize()
>>> r = update_to_frf(system, {"k1": ("500 N/m", "2 kN/m")}, f, test, "F", channels)
>>> round(r.fitted["k1"], 3)
1100.0
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import Chart, Charted, Charts, Curve, charts_svg, check_plot_path, draw_figure
from ..charts import save_figure as _save_figure
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..model.measurement_spec import ChannelMap
from ..model.random_spec import RandomInput
from ..system.base import LinearSystem
from .frf_mimo import pair_name
from .frf_sensitivity import frf_with_sensitivities, loads_depend_on
from .model_update import FittedParameters, log_std, parameter_bounds
from .random_response import Transfer, responses_to_solve
from .result_fields import PLAIN_NUMBER, saved
from .results_json import floats_json

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["FRFUpdate", "update_to_frf", "frac", "model_frf", "model_frf_matrix",
           "input_amplitudes", "RESIDUALS", "SENSITIVITIES"]

#: the residuals (module docstring)
RESIDUALS = ("log", "complex")
#: relative step of the FRF's central differences in p
_STEP = 1e-5
#: the Jacobians (:func:`update_to_frf`'s ``sensitivities``)
SENSITIVITIES = ("analytic", "differences")


def frac(measured: np.ndarray, model: np.ndarray) -> float:
    """The frequency response assurance criterion of two FRFs over their lines (1: alike
    up to a complex factor, 0: orthogonal).

    Parameters
    ----------
    measured, model : ndarray
        (lines,) complex.

    Returns
    -------
    float

    Examples
    --------
    >>> h = np.array([1 + 1j, 2.0, -1j])
    >>> frac(h, 3j * h), round(frac(h, np.array([1.0, 0.0, 0.0])), 3)
    (1.0, 0.286)
    """
    a, b = np.asarray(measured).ravel(), np.asarray(model).ravel()
    denominator = float(np.vdot(a, a).real * np.vdot(b, b).real)
    return float(abs(np.vdot(a, b)) ** 2 / denominator) if denominator > 0 else 0.0


def model_frf(system: LinearSystem, signal: str, frequency: np.ndarray,
              channels: Mapping[str, ChannelMap], *, deadline: Deadline = NO_DEADLINE,
              **values: float) -> dict[str, np.ndarray]:
    """The model's FRF of each channel's quantity to one input at a parameter point.

    Parameters
    ----------
    system : LinearSystem
    signal : str
        The input (a signal of the model or a coordinate).
    frequency : ndarray
        Hz.
    channels : mapping
        Channel -> its coordinate or output and derivative.
    deadline : Deadline, optional
    **values : float
        Parameters that differ from the model's (SI).

    Returns
    -------
    dict
        Channel -> the complex FRF (the derivative's (i w)^d included).

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_lab.toml").linearize()
    >>> h = model_frf(system, "F", np.array([0.0]), {"d3": ChannelMap("x3")}, k1=500.0)
    >>> round(float(h["d3"].real[0]), 6)    # 1/k1 + 1/k2 + 1/k3
    0.004
    """
    H = model_frf_matrix(system, [signal], frequency, channels, deadline=deadline, **values)
    return {channel: H[:, j, 0] for j, channel in enumerate(channels)}


def model_frf_matrix(system: LinearSystem, signals: Sequence[str], frequency: np.ndarray,
                     channels: Mapping[str, ChannelMap], *, deadline: Deadline = NO_DEADLINE,
                     **values: float) -> np.ndarray:
    """The model's FRF matrix of the channels' quantities to several inputs (one kernel
    solve per distinct load column, every input at once).

    Parameters
    ----------
    system : LinearSystem
    signals : sequence of str
        The inputs (signals of the model or coordinates).
    frequency : ndarray
        Hz.
    channels : mapping
        Channel -> its coordinate or output and derivative.
    deadline : Deadline, optional
    **values : float
        Parameters that differ from the model's (SI).

    Returns
    -------
    ndarray
        (lines, channels, inputs) complex, the derivatives' (i w)^d included.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_lab.toml").linearize()
    >>> H = model_frf_matrix(system, ["x1", "x3"], np.array([0.0]),
    ...                      {"d1": ChannelMap("x1"), "d3": ChannelMap("x3")})
    >>> np.round(H[0].real * 1000, 6).tolist()     # static flexibilities (reciprocal)
    [[1.0, 1.0], [1.0, 3.0]]
    """
    f = np.asarray(frequency, dtype=float)
    transfer, outputs = _transfer(system, signals, sorted({c.name for c in channels.values()}),
                                  deadline, values)
    num = transfer.num
    keep = transfer.keep
    H = transfer(f, outputs)
    order = [num.coordinates[i] for i in keep] + list(outputs)
    iw = 2j * np.pi * f
    return np.stack([H[:, order.index(c.name), :] * (iw ** c.derivative)[:, None]
                     for c in channels.values()], axis=1)


def _transfer(system: LinearSystem, signals: Sequence[str], names: Sequence[str],
              deadline: Deadline, values: Mapping[str, float]) -> tuple[Transfer, list[str]]:
    """The kernel's transfer from the inputs to the coordinates ``names`` hold, and the
    outputs among them (a ModelError for an input that does not act on the model)."""
    num = system.numeric(deadline, **values)
    keep, outputs = responses_to_solve(num, names)
    transfer = Transfer(system, num, [RandomInput(s, 0, None, None) for s in signals], keep,
                        "direct", deadline)
    if transfer.warnings:
        raise ModelError(Problem("; ".join(transfer.warnings), system.source, "measurement",
                                 "input"))
    return transfer, list(outputs)


def input_amplitudes(system: LinearSystem, signals: Sequence[str], frequency: np.ndarray,
                     loads: np.ndarray, *, along: Mapping[tuple[str, int], np.ndarray]
                     | None = None, deadline: Deadline = NO_DEADLINE
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The complex amplitude of each input in the model's loads at each line, and the part
    of the loads that no input makes (least squares,
    :meth:`resonant.analyses.random_response.Transfer.amplitudes`).

    With them the response to the loads is ``sum_j H_ij u_j`` (the FRFs of
    :func:`model_frf_matrix` to the same inputs) wherever nothing is left.

    Parameters
    ----------
    system : LinearSystem
    signals : sequence of str
        The inputs (signals of the model or coordinates).
    frequency : ndarray
        The lines (Hz), (N,).
    loads : ndarray
        The generalized forces' complex amplitudes at each line, (N, n) or (n,)
        (:attr:`resonant.system.batch.BatchHarmonic.complex_load`).
    along : mapping, optional
        ``(signal, order) -> (N, n)``: excitation columns at each line, where they depend
        on the parameter the lines sweep (default: the columns at the model's values).
    deadline : Deadline, optional

    Returns
    -------
    u : ndarray
        (N, inputs) complex.
    left : ndarray
        (N,): the part of the loads no input makes, relative (2-norms).
    worst : ndarray
        (n,): its largest magnitude on each coordinate over the lines.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_lab.toml").linearize()
    >>> u, left, _ = input_amplitudes(system, ["x1", "F"], np.array([1.0]),
    ...                               np.array([2.0, 0.0, 3j]))
    >>> u.tolist(), left.tolist()
    ([[(2+0j), 3j]], [0.0])
    >>> u, left, worst = input_amplitudes(system, ["F"], np.array([1.0]),
    ...                                   np.array([2.0, 0.0, 3j]))
    >>> worst.tolist()           # the load on x1 is made by no input
    [2.0, 0.0, 0.0]
    """
    transfer, _ = _transfer(system, signals, [], deadline, {})
    return transfer.amplitudes(np.asarray(frequency, dtype=float), loads, along)


@dataclass(frozen=True)
class FRFUpdate(FittedParameters, Charted):
    """Parameters fitted to measured FRFs, with their uncertainty and the FRFs before and
    after.

    Attributes
    ----------
    names : tuple of str
        The parameters.
    start, fitted, std : mapping
        Their values before and after (SI) and the fitted values' standard deviations.
    bounds : mapping
        name -> (low, high).
    frequency : ndarray
        The spectral lines fitted (Hz).
    channels : tuple of str
        The measured channels, in the rows' order.
    measured, before, after : ndarray
        (channels, lines) complex: the test's FRFs and the model's before and after.
    residual : str
        ``"log"`` or ``"complex"`` (:data:`RESIDUALS`).
    units : tuple of str
        The FRFs' units per channel (``"m/N"``; empty when not known).
    cost : float
        Half the sum of the squared residuals at the solution.
    message : str
        The optimizer's.
    warnings : tuple of str
    """

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): one record per
    #: parameter, the FRFs, the FRACs and log errors derived for the reader
    _json_order = ("parameters", "residual", "units", "frequency_hz", "channels", "measured",
                   "before", "after", "frac_before", "frac_after", "log_error_before",
                   "log_error_after", "cost", "message", "warnings")

    frequency: np.ndarray = saved(key="frequency_hz", axes=(None,))
    channels: tuple[str, ...] = saved()
    measured: np.ndarray = saved(axes=("channels", "frequency"))
    before: np.ndarray = saved(axes=("channels", "frequency"))
    after: np.ndarray = saved(axes=("channels", "frequency"))
    residual: str = saved("log")
    units: tuple[str, ...] = saved(())
    cost: float = saved(0.0, codec=PLAIN_NUMBER)
    message: str = saved("")
    warnings: tuple[str, ...] = saved(())

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def frac_before(self) -> np.ndarray:
        """The FRAC of each channel before the update."""
        return np.array([frac(a, b) for a, b in zip(self.measured, self.before)])

    @property
    def frac_after(self) -> np.ndarray:
        """The FRAC of each channel after the update."""
        return np.array([frac(a, b) for a, b in zip(self.measured, self.after)])

    @property
    def log_error_before(self) -> float:
        """The RMS log-magnitude error (natural log) over every channel and line, before."""
        return _log_rms(self.measured, self.before)

    @property
    def log_error_after(self) -> float:
        """The RMS log-magnitude error after."""
        return _log_rms(self.measured, self.after)

    def _derived_json(self) -> dict[str, Any]:
        return {"frac_before": floats_json(self.frac_before),
                "frac_after": floats_json(self.frac_after),
                "log_error_before": self.log_error_before,
                "log_error_after": self.log_error_after}

    def chart(self, channels: Sequence[str] | None = None) -> Charts:
        """The measured |H| of each channel with the model's before and after (log axis).

        Parameters
        ----------
        channels : sequence of str, optional
            The channels drawn (default all).

        Returns
        -------
        Charts
        """
        rows = [self.channels.index(c) for c in channels] if channels else \
            range(len(self.channels))
        f = self.frequency
        charts = []
        for k in rows:
            curves = (Curve(f, np.abs(self.measured[k]), "test", "#000000", marker="point",
                            line=False),
                      Curve(f, np.abs(self.before[k]), "model before", "#7f7f7f",
                            dash="3.7 1.6"),
                      Curve(f, np.abs(self.after[k]), "model after", "#1f77b4"))
            unit = self.units[k] if k < len(self.units) and self.units[k] else ""
            label = f"|H| of {self.channels[k]}" + (f" [{unit}]" if unit else "")
            charts.append(Chart(curves, "frequency [Hz]", label,
                                (float(f[0]), float(f[-1])), ylog=True,
                                title=printable(self.channels[k], limit=40)))
        return Charts(tuple(charts), title="model updated to the measured FRFs")

    def plot(self, path: str | os.PathLike[str] | None = None,
             ax: Axes | Sequence[Axes] | None = None,
             channels: Sequence[str] | None = None) -> Figure:
        """Draw :meth:`chart` (and save it to ``path``).

        Parameters
        ----------
        path : str or PathLike, optional
        ax : Axes or sequence of Axes, optional
        channels : sequence of str, optional

        Returns
        -------
        Figure
        """
        check_plot_path(path)
        fig = draw_figure(self.chart(channels), ax)
        return _save_figure(fig, path)

    def summary(self) -> str:
        """The fitted parameters and the correlation before and after.

        Returns
        -------
        str
        """
        lines = [f"{'parameter':<12} {'start':>12} {'fitted':>12} {'std':>10}"]
        lines += [f"{printable(n, limit=12):<12} {self.start[n]:>12.6g} "
                  f"{self.fitted[n]:>12.6g} {self.std[n]:>10.3g}" for n in self.names]
        lines.append(f"{'channel':<12} {'FRAC before':>12} {'FRAC after':>12}")
        lines += [f"{printable(c, limit=12):<12} {b:>12.4f} {a:>12.4f}" for c, b, a in
                  zip(self.channels, self.frac_before, self.frac_after)]
        lines.append(f"RMS log-magnitude error: {self.log_error_before:.4g} before, "
                     f"{self.log_error_after:.4g} after ({self.residual} residuals, "
                     f"{len(self.frequency)} lines)")
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines) + "\n"

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "frf-update")


def _log_rms(measured: np.ndarray, model: np.ndarray) -> float:
    a, b = np.abs(measured), np.abs(model)
    ok = (a > 0) & (b > 0)
    return float(np.sqrt(np.mean((np.log(b[ok]) - np.log(a[ok])) ** 2))) if ok.any() \
        else math.nan


class _FRFProblem:
    """The residuals and their Jacobian at x = ln p; the rows are the channels (one input)
    or the channel/input pairs of the matrix, channel-major."""

    def __init__(self, system: LinearSystem, names: Sequence[str], frequency: np.ndarray,
                 measured: np.ndarray, signals: Sequence[str],
                 channels: Mapping[str, ChannelMap], residual: str, sensitivities: str,
                 deadline: Deadline) -> None:
        self.system, self.names, self.frequency = system, list(names), frequency
        self.measured, self.signals, self.channels = measured, list(signals), dict(channels)
        self.residual, self.sensitivities, self.deadline = residual, sensitivities, deadline
        self.scale = np.sqrt(np.mean(np.abs(measured) ** 2, axis=1, keepdims=True))
        self.log_measured = np.log(np.abs(measured)) if residual == "log" else measured
        self.used = ""
        self.loads_vary: frozenset[str] | None = None

    def _rows(self, H: np.ndarray) -> np.ndarray:
        """(lines, channels, inputs) -> (rows, lines)."""
        return np.transpose(H, (1, 2, 0)).reshape(-1, H.shape[0])

    def frf(self, p: np.ndarray) -> np.ndarray:
        self.deadline.check("while updating the model to the FRFs", analysis=True)
        return self._rows(model_frf_matrix(self.system, self.signals, self.frequency,
                                           self.channels, deadline=self.deadline,
                                           **dict(zip(self.names, map(float, p)))))

    def _residuals_of(self, H: np.ndarray) -> np.ndarray:
        if self.residual == "log":
            with np.errstate(divide="ignore"):
                r = np.log(np.abs(H)) - self.log_measured
            return np.asarray(np.nan_to_num(r, nan=0.0, posinf=50.0, neginf=-50.0)).ravel()
        d = (H - self.measured) / self.scale
        return np.concatenate([d.real.ravel(), d.imag.ravel()])

    def residuals(self, x: np.ndarray) -> np.ndarray:
        return self._residuals_of(self.frf(np.exp(x)))

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        if self.sensitivities == "analytic":
            J = self.analytic_jacobian(x)
            if J is not None:
                self.used = self.used or "analytic"
                return J
        self.used = "differences"
        return self.difference_jacobian(x)

    def analytic_jacobian(self, x: np.ndarray) -> np.ndarray | None:
        """dr/d ln p from dH/dp (``resonant.analyses.frf_sensitivity``); None where it
        does not apply."""
        p = np.exp(x)
        values = dict(zip(self.names, map(float, p)))
        if self.loads_vary is None:
            self.loads_vary = loads_depend_on(self.system, self.signals, self.names, values,
                                              self.deadline)
        found = frf_with_sensitivities(self.system, self.signals, self.frequency,
                                       self.channels, self.names, values,
                                       loads_vary=self.loads_vary, deadline=self.deadline)
        if found is None:
            return None
        H = self._rows(found[0])
        dH = np.array([self._rows(d) * pk for d, pk in zip(found[1], p)])  # d H / d ln p
        if self.residual == "log":
            with np.errstate(divide="ignore", invalid="ignore"):
                J = np.nan_to_num((np.conj(H)[None] * dH).real / (np.abs(H) ** 2)[None])
            return np.asarray(J.reshape(len(p), -1).T)
        d = dH / self.scale[None]
        return np.asarray(np.concatenate([d.real.reshape(len(p), -1),
                                          d.imag.reshape(len(p), -1)], axis=1).T)

    def difference_jacobian(self, x: np.ndarray) -> np.ndarray:
        """dr/d ln p by central differences of the FRF (relative step :data:`_STEP`)."""
        columns = []
        for k in range(len(x)):
            h = math.log1p(_STEP)
            up, down = x.copy(), x.copy()
            up[k] += h
            down[k] -= h
            columns.append((self.residuals(up) - self.residuals(down)) / (2 * h))
        return np.column_stack(columns)


def _measured_rows(frequency: np.ndarray, measured: Mapping[str, Any],
                   channels: Sequence[str], residual: str, source: str) -> np.ndarray:
    """The measured FRFs as (channels, lines), checked."""
    missing = [c for c in channels if c not in measured]
    if missing:
        raise ModelError(Problem(f"no measured FRF for the channel "
                                 f"'{printable(missing[0], limit=40)}'", source, "measurement",
                                 "channels"))
    rows = np.array([np.asarray(measured[c], dtype=complex).ravel() for c in channels]) \
        if all(np.shape(measured[c]) == frequency.shape for c in channels) else None
    if rows is None:
        raise ModelError(Problem(f"every measured FRF needs one value per line "
                                 f"({len(frequency)} lines)", source, "update"))
    if not np.isfinite(rows).all():
        raise ModelError(Problem("a measured FRF holds NaN or infinite values", source,
                                 "update"))
    if residual == "log" and not (np.abs(rows) > 0).all():
        raise ModelError(Problem("a measured FRF is zero at a line: the log-magnitude "
                                 "residual needs |H| > 0 (leave the line out or use the "
                                 "complex residual)", source, "update"))
    return rows


def update_to_frf(system: LinearSystem, parameters: Mapping[str, tuple[Any, Any]],
                  frequency: Sequence[float] | np.ndarray, measured: Mapping[str, Any],
                  signal: str | Mapping[str, str], channels: Mapping[str, ChannelMap], *,
                  residual: str = "log", sigma: float | None = None,
                  units: Mapping[str, str] | None = None,
                  start: Mapping[str, float] | None = None, sensitivities: str = "analytic",
                  deadline: Deadline = NO_DEADLINE) -> FRFUpdate:
    """Fit parameters within bounds to measured FRFs at their lines.

    Parameters
    ----------
    system : LinearSystem
    parameters : mapping
        name -> (low, high): numbers (SI) or texts with units; the fit starts from the
        model's value (clipped into the bounds).
    frequency : array_like
        The lines (Hz), positive.
    measured : mapping
        Channel -> its measured FRF (complex, one value per line) to ``signal``; with
        several inputs, :func:`resonant.analyses.frf_mimo.pair_name` (channel, input
        label) -> the FRF of the matrix.
    signal : str or mapping
        The model's input the FRFs are measured to (``[measurement] input``); or, for an
        FRF matrix, input label (the excitation channel) -> the model's signal or
        coordinate, every channel fitted to every input (one kernel solve for all).
    channels : mapping
        Channel -> its coordinate or output and derivative.
    residual : {"log", "complex"}
        The residual (module docstring).
    sigma : float, optional
        The residuals' standard deviation (log: the relative magnitude noise).
    units : mapping, optional
        Channel -> its FRF's unit (for the figure's labels).
    start : mapping, optional
        name -> the value (SI) the fit starts from (default the model's), clipped into the
        bounds: one start of a multi-start (:mod:`resonant.studies.multi_start`).
    sensitivities : {"analytic", "differences"}
        The Jacobian: dH/dp analytically (``resonant.analyses.frf_sensitivity``; for FRFs of
        coordinates, else differences) or central differences of the FRF.
    deadline : Deadline, optional

    Returns
    -------
    FRFUpdate

    Raises
    ------
    ModelError
        For an unknown parameter or residual, bounds that are not positive and increasing,
        no lines, a measured FRF missing, of the wrong length, NaN, or zero (log residual).
    """
    from scipy.optimize import least_squares

    source = system.source
    if residual not in RESIDUALS:
        raise ModelError(Problem(f"residual '{printable(residual, limit=20)}' is not one of "
                                 f"{', '.join(RESIDUALS)}", source, "update", "residual"))
    f = np.asarray(frequency, dtype=float).ravel()
    if not len(f) or not (np.isfinite(f).all() and (f > 0).all()):
        raise ModelError(Problem("give one or more positive, finite lines (Hz)", source,
                                 "update"))
    if not channels:
        raise ModelError(Problem("give at least one channel", source, "measurement",
                                 "channels"))
    if sensitivities not in SENSITIVITIES:
        raise ModelError(Problem(f"sensitivities '{printable(sensitivities, limit=20)}' is "
                                 f"not one of {', '.join(SENSITIVITIES)}", source, "update",
                                 "sensitivities"))
    labels = dict(signal) if isinstance(signal, Mapping) else {}
    if isinstance(signal, Mapping) and not labels:
        raise ModelError(Problem("give at least one input", source, "measurement", "input"))
    signals = list(labels.values()) if isinstance(signal, Mapping) else [signal]
    keys = [pair_name(c, i) for c in channels for i in labels] if labels else list(channels)
    channel_of = {pair_name(c, i): c for c in channels for i in labels} if labels else \
        {c: c for c in channels}
    rows = _measured_rows(f, measured, keys, residual, source)
    model_values = dict(system.numeric(deadline).parameters)
    bounds = parameter_bounds(system, parameters, model_values)
    names = list(bounds)
    problem = _FRFProblem(system, names, f, rows, signals, channels, residual, sensitivities,
                          deadline)
    first = {**model_values, **(start or {})}
    start_values = np.array([min(max(float(first[n]), bounds[n][0]), bounds[n][1])
                             for n in names])
    lower = np.log([bounds[n][0] for n in names])
    upper = np.log([bounds[n][1] for n in names])
    before = problem.frf(start_values)
    solution = least_squares(problem.residuals, np.log(start_values), jac=problem.jacobian,
                             bounds=(lower, upper), x_scale=1.0, xtol=1e-12, ftol=1e-12,
                             gtol=1e-12)
    fitted = np.exp(solution.x)
    std = log_std(solution.jac, solution.fun, fitted, sigma, len(solution.fun))
    warnings = [f"{n} ended on its bound {fitted[k]:.6g}" for k, n in enumerate(names)
                if np.isclose(solution.x[k], lower[k]) or np.isclose(solution.x[k], upper[k])]
    return FRFUpdate(tuple(names), dict(zip(names, start_values.tolist())),
                     dict(zip(names, fitted.tolist())), dict(zip(names, std.tolist())),
                     bounds, f, tuple(keys), rows, before, problem.frf(fitted), residual,
                     tuple((units or {}).get(k, (units or {}).get(channel_of[k], ""))
                           for k in keys),
                     float(solution.cost),
                     str(solution.message), tuple(warnings))
