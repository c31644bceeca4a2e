"""Plot and text of a nonlinear steady-state sweep (:class:`NonlinearResponse`).

The plot draws the peak amplitude of each coordinate against the parameter:
stable parts solid, unstable parts dashed, special points marked (fold: circle,
period-doubling: square, Neimark-Sacker: diamond, branch: triangle, the peak of a
curve: a star on that curve), and the linear frequency response dotted beside it.
The curves are the coordinates' and the outputs' (``[outputs]``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..charts import (
    COLORS,
    MAX_CURVES,
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
from ..errors import printable
from ..expressions.notation import dollar_name
from ..model.units_display import unit_math

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analyses.backbone import Backbones
    from ..analyses.nonlinear_response import NonlinearResponse

MARKERS = {"fold": "o", "period-doubling": "s", "neimark-sacker": "D", "branch": "^",
           "peak": "*"}
#: the chart's marker shape of each kind of special point (as :data:`MARKERS`)
SHAPES = {"fold": "circle", "period-doubling": "square", "neimark-sacker": "diamond",
          "branch": "triangle", "peak": "star"}


def _segments(values: np.ndarray, amplitudes: np.ndarray, stable: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, stable y, unstable y): the branch as two curves broken by NaN, each running on
    to the point where the stability changes (the two join there)."""
    n = values.size
    keep = np.zeros((2, n), dtype=bool)  # [stable, unstable]
    for i in range(n):
        k = 0 if stable[i] else 1
        keep[k, i] = True
        if i + 1 < n and stable[i + 1] != stable[i]:
            keep[k, i + 1] = True  # the segment reaches the switching point
    with np.errstate(invalid="ignore"):
        return (values.astype(float), np.where(keep[0], amplitudes, np.nan),
                np.where(keep[1], amplitudes, np.nan))


def nonlinear_response_chart(response: NonlinearResponse, names: Sequence[str] | None = None,
                             linear: bool = True, units: Mapping[str, str] | None = None, *,
                             title: bool = True,
                             operating: tuple[float, Mapping[str, float]] | None = None
                             ) -> Chart:
    """What the figure of a nonlinear steady-state sweep shows: the peak amplitude of each
    coordinate and output against the parameter, stable parts solid, unstable dashed,
    special points marked, the linear frequency response dotted beside it.

    Parameters
    ----------
    response : NonlinearResponse
    names : sequence of str, optional
        The curves (default: the first :data:`MAX_CURVES`).
    linear : bool
        Draw the linear frequency response beside.
    units : mapping, optional
        name -> SI unit, on the curves and the axis.
    title : bool
        Give the chart the model's title.
    operating : (value, amplitudes), optional
        The operating point: a dashed line at the value and a star on each curve.

    Returns
    -------
    Chart
    """
    chosen = list(names) if names else list(response.amplitudes)[:MAX_CURVES]
    v = np.asarray(response.values, dtype=float)
    stable = np.asarray(response.stable, dtype=bool)
    curves: list[Curve] = []
    markers: list[Marker] = []
    for k, name in enumerate(chosen):
        color = COLORS[k % len(COLORS)]
        a = np.asarray(response.amplitudes[name], dtype=float)
        unit = (units or {}).get(name, "")
        shown = dollar_name(name) + (f" [{unit_math(unit)}]" if unit not in ("", "1") else "")
        if linear and response.linear is not None and name in response.linear.amplitudes:
            curves.append(Curve(np.asarray(response.linear.values, dtype=float),
                                np.asarray(response.linear.amplitudes[name], dtype=float),
                                f"{shown} (linear)", color, 1.1, "1 1.65"))
        x, on, off = _segments(v, a, stable)
        curves.append(Curve(x, on, f"{shown} (harmonic balance, H = {response.harmonics})",
                            color, 1.6))
        if np.isfinite(off).any():
            curves.append(Curve(x, off, "", color, 1.6, "3.7 1.6"))
        for point in response.special_points:
            if name in point.amplitudes and point.quantity in (None, name):
                markers.append(Marker(point.value, point.amplitudes[name], "#000000",
                                      SHAPES.get(point.kind, "circle"), point.kind,
                                      filled=False))
    if not stable.all():
        curves.append(Curve(np.empty(0), np.empty(0), "unstable", "#4d4d4d", 1.6, "3.7 1.6"))
    rules: tuple[Rule, ...] = ()
    if operating is not None:
        value, amplitudes = operating
        markers += [Marker(value, amplitudes[name], COLORS[k % len(COLORS)], "star",
                           f"{dollar_name(name)} at the operating point")
                    for k, name in enumerate(chosen) if name in amplitudes]
        rules = (Rule(float(value), color="#404040", dash="3.7 1.6"),)
    base = np.asarray(response.base_frequencies, dtype=float)
    frequency = base.shape == v.shape and bool(np.allclose(base, v))  # the parameter is ω
    xlabel = (("excitation frequency " if frequency else "") + dollar_name(response.parameter)
              + (" [rad/s]" if frequency else ""))
    shown_units = sorted({(units or {}).get(n, "") for n in chosen} - {"", "1"})
    ylabel = ("peak amplitude $X$ (deviation)"
              + (f" [{', '.join(unit_math(u) for u in shown_units)}]" if shown_units else ""))
    top = max((float(np.nanmax(response.amplitudes[n])) for n in chosen), default=1.0)
    return Chart(tuple(curves), xlabel, ylabel,
                 (min(response.start, response.stop), max(response.start, response.stop)),
                 markers=tuple(markers), rules=rules,
                 ylim=(0.0, 1.15 * top) if top > 0 else None,
                 title=printable(response.title or "nonlinear steady state", limit=80)
                 if title else "")


def plot_nonlinear_response(response: NonlinearResponse, path: PathArg = None,
                            names: Sequence[str] | None = None, ax: Axes | None = None,
                            linear: bool = True, units: Mapping[str, str] | None = None) -> Figure:
    """Amplitude against the parameter (the chart of :func:`nonlinear_response_chart`, drawn
    with matplotlib); returns the Figure (and writes it to ``path``).

    ``units`` (name -> SI unit, ``ResultUnits.si``) labels the curves and the axis."""
    check_plot_path(path)
    chart = nonlinear_response_chart(response, names, linear, units)
    fig = draw_figure(Charts((chart,), size=(7.5, 4.8)), ax)
    save_figure(fig, path)
    return fig


def nonlinear_text(response: NonlinearResponse) -> str:
    """Special points and the peak of the stable branch, as plain text."""
    lines = [f"{response.title or 'model'}: nonlinear steady state (harmonic balance, "
             f"H = {response.harmonics}) against {response.parameter} from "
             f"{response.start:g} to {response.stop:g}",
             f"  {response.values.size} branch points, {int(response.stable.sum())} stable; "
             f"largest residual {response.residual:.3g}; highest harmonics carry up to "
             f"{response.truncation:.3g} of the amplitude"]
    if response.special_points:
        lines.append("  special points:")
        for p in response.special_points:
            amps = ", ".join(f"{k} = {v:.10g}" for k, v in p.amplitudes.items())
            kind = f"peak of {p.quantity}" if p.kind == "peak" else p.kind
            if p.stable is False:
                kind += " (unstable)"
            lines.append(f"    {kind:16s} {response.parameter} = {p.value:.10g}   {amps}")
    else:
        lines.append("  no special points (no fold, no change of stability, no peak)")
    top = response.peak()
    if top is not None:
        value, peak_amps = top
        lines.append(f"  peak of the stable branch at {response.parameter} = {value:.6g}: "
                     + ", ".join(f"{k} = {v:.6g}" for k, v in peak_amps.items()))
        if response.linear is not None:
            first = response.coordinates[0]
            lin = np.asarray(response.linear.amplitudes.get(first, []), dtype=float)
            if lin.size and np.isfinite(lin).any():
                lines.append(f"  linear peak of {first}: {float(np.nanmax(lin)):.6g}")
    else:
        lines.append("  no stable point on the branch")
    return "\n".join(lines) + "\n"


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


__all__ = ["plot_nonlinear_response", "nonlinear_text", "plot_backbones",
           "nonlinear_response_chart", "backbones_chart"]
