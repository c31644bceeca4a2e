"""Backbone curves: the amplitude-dependent free-vibration frequency of each mode.

The undamped, unforced system (the model's signals set to zero, its dissipation
function D = 0) has, near each linear mode, a family of periodic solutions (a
nonlinear normal mode) whose frequency depends on the amplitude.  They are
computed by harmonic balance (:mod:`resonant.analyses.hb_solver`: the same
compiled full equations of the :class:`~resonant.system.NonlinearSystem`, with
the forcing zero and the dissipation off, the alternating frequency-time
residual and the exact Jacobian) with the frequency W as an unknown, and two
more conditions:

* the phase: the sine coefficient b_1 of the mode's reference coordinate (its
  largest component) is zero;
* the amplitude: its cosine coefficient a_1 is the continuation parameter A.

The system is made square by the usual fictitious damping term ``xi M q'``
(Krack & Gross, Harmonic Balance for Nonlinear Vibration Problems, 2019, Sect.
4.5): xi is an unknown that comes out zero (to rounding) for a conservative
system, and its value is reported.  The Jacobian with respect to x, W and xi is
exact.  A is continued from small amplitude (the linear mode shape and natural
frequency) to the given amplitude, with step halving when Newton fails.

Examples
--------
>>> from resonant.api import loads
>>> model = loads('''
... [parameters]
... k3 = 0.5
... [coordinates]
... x = ""
... [energy]
... T = "x'^2/2"
... U = "x^2/2 + k3*x^4/4"
... ''')
>>> from resonant.system import nonlinear_system
>>> b = backbone(nonlinear_system(model), amplitude=1.0, harmonics=1, points=11)
>>> abs(float(b.curves[0].frequencies[-1]) - (1 + 0.75 * 0.5) ** 0.5) < 1e-12
True
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import (
    COLORS,
    Chart,
    Charts,
    Curve,
    PathArg,
    Rule,
    check_plot_path,
    draw_figure,
    save_figure,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, printable
from ..expressions.notation import dollar_name
from ..model.options import check_harmonics
from ..model.units_display import NO_UNIT, ResultUnits, angular_shown
from ..system.nonlinear import NonlinearSystem, nonlinear_only
from ..system.stability import undamped_eigen
from .hb_solver import NEWTON_MAX, NEWTON_TOL, HarmonicBalance
from .result_fields import FieldsJSON, saved
from .results_json import Saved

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

DEFAULT_HARMONICS = 5
DEFAULT_POINTS = 41
#: without an amplitude, continue until the frequency has changed by this fraction
DEFAULT_SHIFT = 0.2


@dataclass(frozen=True)
class BackboneCurve(FieldsJSON):
    """One mode's backbone: frequency against amplitude.

    ``amplitude`` is the continuation parameter A (the first-harmonic cosine coefficient of
    ``reference``); ``amplitudes`` the peak |deviation| of every coordinate over a period.
    """

    mode: int
    reference: str
    linear_frequency: float
    amplitude: np.ndarray
    frequencies: np.ndarray = saved(axes=("amplitude",))
    amplitudes: Mapping[str, np.ndarray] = saved(axes=("amplitude",))
    coefficients: np.ndarray = saved()
    damping: float = saved(key="fictitious_damping")

    def __post_init__(self) -> None:
        object.__setattr__(self, "amplitudes", MappingProxyType(dict(self.amplitudes)))
        freeze_fields(self)

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        if values["coefficients"].ndim != 3 and values["coefficients"].size:
            raise reader.error(f"has {values['coefficients'].ndim} dimension(s), not 3",
                               "coefficients")

@dataclass(frozen=True)
class Backbones(FieldsJSON):
    """The backbone curves of the modes of a model (``resonant modes --nonlinear``).

    Attributes
    ----------
    title, coordinates
        The model's title and its coordinates.
    harmonics : int
        The harmonics H of the balance.
    curves : tuple of BackboneCurve
        One per followed mode: amplitude against the free periodic frequency.
    residual : float
        The largest harmonic-balance residual of the curves.
    warnings : tuple of str
        What the user should know (a curve that stopped early).

    Examples
    --------
    See :func:`backbone`.
    """

    title: str
    coordinates: tuple[str, ...]
    harmonics: int
    curves: tuple[BackboneCurve, ...] = saved(key="backbones")
    residual: float = saved()
    warnings: tuple[str, ...] = ()

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        if values["harmonics"] < 1:
            raise reader.error(f"is {values['harmonics']}, less than 1", "harmonics")

    def summary(self, units: ResultUnits | None = None) -> str:
        """The text ``resonant modes --nonlinear`` prints: a few points of each curve.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``: amplitudes, frequencies; default SI, rad/s).

        Returns
        -------
        str
        """
        lines = [f"{self.title or 'model'}: backbone curves (free vibration of the full "
                 f"undamped equations, harmonic balance, H = {self.harmonics}; largest "
                 f"residual {self.residual:.3g})"]
        w = angular_shown(units)
        for c in self.curves:
            a = units.unit(c.reference) if units is not None else NO_UNIT
            lines.append(f"  mode {c.mode} (amplitude of {c.reference}): linear "
                         f"{w(c.linear_frequency):.6g} {w.text}")
            picks = sorted({0, c.amplitude.size // 4, c.amplitude.size // 2,
                            3 * c.amplitude.size // 4, c.amplitude.size - 1})
            for i in picks:
                amplitude = f"{a(c.amplitudes[c.reference][i]):.6g} {a.text}".rstrip()
                lines.append(f"    {c.reference} = {amplitude:<14} "
                             f"omega = {w(c.frequencies[i]):.6g} {w.text} "
                             f"({100 * (c.frequencies[i] / c.linear_frequency - 1):+.3g}%)")
        return "\n".join(lines) + "\n"

    def chart(self) -> Chart:
        """The figure's description: each backbone curve, the linear natural frequencies
        dotted (:func:`backbones_chart`).

        Returns
        -------
        resonant.charts.Chart
        """
        return backbones_chart(self)

    def plot(self, path: str | os.PathLike[str] | None = None, ax: Axes | None = None
             ) -> Figure:
        """Frequency against amplitude, one curve per mode
        (:func:`resonant.analyses.backbone.plot_backbones`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        ax : matplotlib.axes.Axes, optional
            Draw into the caller's axes.

        Returns
        -------
        matplotlib.figure.Figure

        Examples
        --------
        >>> import resonant
        >>> b = resonant.load("examples/duffing.toml").backbone(harmonics=1, points=10)
        >>> len(b.plot().axes)
        1
        """
        return plot_backbones(self, path, ax)


class _Free:
    """Residual and exact Jacobian in y = [x, W, xi] with the phase and amplitude rows."""

    def __init__(self, hb: HarmonicBalance, M: np.ndarray, ref: int) -> None:
        self.hb, self.M, self.ref = hb, M, ref
        self.n, self.m = hb.n, hb.m
        self.pv = hb.system.parameter_values

    def system(self, y: np.ndarray, A: float) -> tuple[np.ndarray, np.ndarray]:
        hb, n, m = self.hb, self.n, self.m
        x, W, xi = y[:-2], float(y[-2]), float(y[-1])
        X = x.reshape(n, m)
        v1 = X @ hb.dphi.T            # dq/dtau
        v2 = X @ hb.d2phi.T           # d2q/dtau2
        E, G0, G1, G2 = hb.evaluate(X, W, self.pv, damping=0.0)
        Mv = self.M @ v1
        R = hb.project(E + xi * W * Mv)
        G1d = G1 + xi * self.M[:, :, None]
        J = hb.galerkin((G0, hb.phi), (G1d, W * hb.dphi), (G2, W * W * hb.d2phi))
        dW = hb.project(np.einsum("ijk,jk->ik", G1d, v1)
                        + 2 * W * np.einsum("ijk,jk->ik", G2, v2))
        dxi = hb.project(W * Mv)
        size = n * m
        full = np.zeros((size + 2, size + 2))
        full[:size, :size] = J
        full[:size, size] = dW
        full[:size, size + 1] = dxi
        a1, b1 = self.ref * m + 1, self.ref * m + 2
        full[size, b1] = 1.0
        full[size + 1, a1] = 1.0
        res = np.concatenate([R, [x[b1], x[a1] - A]])
        return res, full

    def newton(self, y: np.ndarray, A: float) -> tuple[np.ndarray, bool]:
        for _ in range(NEWTON_MAX):
            res, J = self.system(y, A)
            try:
                dy = np.linalg.solve(J, -res)
            except np.linalg.LinAlgError:
                return y, False
            y = y + dy
            if not np.all(np.isfinite(y)) or y[-2] <= 0:
                return y, False
            if np.linalg.norm(dy) <= NEWTON_TOL * max(float(np.linalg.norm(y)), abs(A)):
                return y, True
        return y, False


def _follow(free: _Free, y0: np.ndarray, A0: float, targets: np.ndarray, deadline: Deadline
            ) -> tuple[list[np.ndarray], str | None]:
    """Solve at every target amplitude in turn from the solution y0 at A0 (secant
    predictor, step halving)."""
    out: list[np.ndarray] = []
    y_prev, A_prev = y0, A0
    slope = np.zeros_like(y0)
    for A in targets:
        deadline.check(f"while following a backbone curve (amplitude {A:.4g})", analysis=True)
        A_now, y_now = A_prev, y_prev
        step = A - A_prev
        while A_now < A:
            trial = min(A, A_now + step)
            y, ok = free.newton(y_now + slope * (trial - A_now), trial)
            if ok:
                if trial > A_now:
                    slope = (y - y_now) / (trial - A_now)
                A_now, y_now = trial, y
                step *= 2   # a halved step grows back once Newton converges again
            else:
                step /= 2
                if step < 1e-9 * max(A, 1e-300):
                    return out, f"no converged solution beyond amplitude {A_now:.6g}"
        out.append(y_now)
        y_prev, A_prev = y_now, A
    return out, None


def _check(system: NonlinearSystem, amplitude: float | None, harmonics: int | None,
           points: int) -> None:
    check_harmonics(harmonics)
    if points < 2:
        raise AnalysisError("points must be at least 2")
    if amplitude is not None and not (math.isfinite(amplitude) and amplitude > 0):
        raise AnalysisError(f"the amplitude must be a positive number, not {amplitude}")
    if not system.parameters:
        raise AnalysisError("backbone curves need a model with parameters")


def _top(free: _Free, y0: np.ndarray, small: float, w0: float, deadline: Deadline) -> float:
    """The amplitude where the frequency has moved by DEFAULT_SHIFT (doubled from 1e-3)."""
    A, y, A_prev = 1e-3, y0, small
    for _ in range(31):
        got, _ = _follow(free, y, A_prev, np.array([A]), deadline)
        if not got:
            return A / 2
        y, A_prev = got[0], A
        if abs(y[-2] / w0 - 1) >= DEFAULT_SHIFT:
            break
        A *= 2
    return A


def _curve(hb: HarmonicBalance, M: np.ndarray, mode: int, w0: float, shape: np.ndarray,
           amplitude: float | None, points: int, warnings: list[str], deadline: Deadline
           ) -> tuple[BackboneCurve | None, float]:
    """One mode's backbone and its largest residual."""
    n, system = hb.n, hb.system
    ref = int(np.argmax(np.abs(shape)))
    shape = shape / shape[ref]
    free = _Free(hb, M, ref)
    small = 1e-6 * (amplitude or 1.0)
    x = np.zeros((n, hb.m))
    x[:, 1] = small * shape
    y0, ok = free.newton(np.concatenate([x.ravel(), [w0, 0.0]]), small)
    if not ok:
        raise AnalysisError(f"harmonic balance did not converge near mode {mode}'s "
                            "linear solution")
    top = amplitude if amplitude is not None else _top(free, y0, small, w0, deadline)
    targets = np.linspace(top / points, top, points)
    solutions, stopped = _follow(free, y0, small, targets, deadline)
    if stopped:
        warnings.append(f"mode {mode}: {stopped}; the curve ends there")
    if not solutions:
        return None, 0.0
    Y = np.array(solutions)
    coeffs = Y[:, :-2].reshape(len(solutions), n, hb.m)
    amps = hb.amplitudes_of([y[:-2] for y in solutions], [math.nan] * len(solutions),
                            outputs=False)
    residual = max(float(np.abs(free.system(y, A)[0][:-2]).max())
                   for y, A in zip(solutions, targets))
    return BackboneCurve(
        mode=mode, reference=system.coordinates[ref], linear_frequency=w0,
        amplitude=targets[:len(solutions)], frequencies=Y[:, -2],
        amplitudes=MappingProxyType({c: amps[:, j] for j, c in enumerate(system.coordinates)}),
        coefficients=coeffs, damping=float(np.abs(Y[:, -1]).max())), residual


def backbone(system: NonlinearSystem, amplitude: float | None = None, *,
             harmonics: int | None = None, points: int | None = None,
             modes: list[int] | None = None, deadline: Deadline = NO_DEADLINE) -> Backbones:
    """Backbone curves of the modes: frequency of free vibration against amplitude.

    Parameters
    ----------
    system : NonlinearSystem
        The full equations, compiled (:func:`resonant.system.nonlinear_system`;
        ``model.backbone(...)`` compiles them for you).
    amplitude : float, optional
        The largest amplitude A (first-harmonic amplitude of each mode's reference
        coordinate).  Default: doubled from 1e-3 of the unit until the frequency has
        changed by 20 % (at most 2^30 times).
    harmonics : int, optional
        H (default 5).
    points : int, optional
        Amplitudes from A/points to A, evenly spaced (default 41).
    modes : list of int, optional
        1-based mode numbers (default all modes with a positive natural frequency).
    deadline : Deadline, optional

    Returns
    -------
    Backbones
    """
    system = nonlinear_only(system, "backbone")
    points = DEFAULT_POINTS if points is None else points
    _check(system, amplitude, harmonics, points)
    num = system.linear.numeric(deadline).dense()
    lam, shapes = undamped_eigen(num.M, num.K)
    H = harmonics or DEFAULT_HARMONICS
    hb = HarmonicBalance(system, system.parameters[0], H, free=True)
    chosen = modes or [k + 1 for k in range(hb.n) if lam[k] > 0]
    curves = []
    warnings: list[str] = []
    residual = 0.0
    for mode in chosen:
        if not 1 <= mode <= hb.n or lam[mode - 1] <= 0:
            raise AnalysisError(f"mode {mode} has no positive natural frequency")
        curve, worst = _curve(hb, num.M, mode, math.sqrt(float(lam[mode - 1])),
                              shapes[:, mode - 1].real, amplitude, points, warnings, deadline)
        residual = max(residual, worst if math.isfinite(worst) else math.inf)
        if curve is not None:
            curves.append(curve)
    return Backbones(title=system.title, coordinates=system.coordinates, harmonics=H,
                     curves=tuple(curves), residual=residual, warnings=tuple(warnings))


def backbones_chart(backbones: Backbones) -> Chart:
    """What the figure of backbone curves shows: the free-vibration frequency (x) against
    the amplitude of each mode's reference coordinate (y), the linear natural frequencies
    dotted."""
    curves, rules = [], []
    for i, curve in enumerate(backbones.curves):
        color = COLORS[i % len(COLORS)]
        amp = np.concatenate([[0.0], np.asarray(curve.amplitudes[curve.reference])])
        freq = np.concatenate([[curve.linear_frequency], np.asarray(curve.frequencies)])
        curves.append(Curve(freq, amp, f"mode {curve.mode} (amplitude of "
                            f"{dollar_name(curve.reference)})", color, 1.6))
        rules.append(Rule(float(curve.linear_frequency), color=color, dash="1 1.65"))
    finite = np.concatenate([c.x for c in curves] + [np.empty(0)])
    finite = finite[np.isfinite(finite)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    pad = 0.05 * (high - low) if high > low else max(abs(high) * 0.1, 1.0)
    top = max((float(np.nanmax(c.y)) for c in curves if np.isfinite(c.y).any()), default=0.0)
    return Chart(tuple(curves), r"frequency of free vibration $\omega$ [rad/s]",
                 "peak amplitude $X$ (deviation)", (low - pad, high + pad), rules=tuple(rules),
                 ylim=(0.0, 1.05 * top) if top > 0 else None,
                 title=printable(backbones.title or "backbone curves", limit=80)
                 + f" (harmonic balance, H = {backbones.harmonics})")


def plot_backbones(backbones: Backbones, path: PathArg = None, ax: Axes | None = None) -> Figure:
    """Backbone curves (the chart of :func:`backbones_chart`, drawn with matplotlib);
    returns the Figure."""
    check_plot_path(path)
    fig = draw_figure(Charts((backbones_chart(backbones),), size=(7.0, 4.6)), ax)
    save_figure(fig, path)
    return fig


__all__ = ["Backbones", "BackboneCurve", "backbone"]
