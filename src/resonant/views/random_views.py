"""Views of a random response: its text summary and its spectral densities on log-log axes.

Examples
--------
>>> import resonant
>>> from resonant.analyses.random_response import random_response
>>> result = random_response(resonant.load("examples/shaker_gevs.toml").linearize())
>>> print(random_text(result).splitlines()[0])
Random response: Component on a shaker under the GEVS qualification spectrum
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..analyses.periodic_load import PeriodicResponse
from ..analyses.random_response import RandomResponse
from ..charts import (
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
from ..errors import AnalysisError, printable
from ..model.random_spec import STANDARD_GRAVITY

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: at most this many curves per panel
MAX_CURVES = 8
#: at most this many response panels (one per unit)
MAX_PANELS = 4


def _number(value: float | None) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{value:.4g}"


def random_text(result: RandomResponse, warnings: bool = True) -> str:
    """The RMS, 3-sigma, Rice's rates (and Miles' estimate) of every response, as text.

    Parameters
    ----------
    result : RandomResponse
    warnings : bool
        End with the result's warnings (the command line writes them to standard error).

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
    header = ("name", "unit", "RMS", "3-sigma", "nu0+ [Hz]", "peaks [Hz]", "Miles RMS",
              "rel. error")
    rows = []
    for name in result.names:
        miles = None if result.miles is None else result.miles.get(name)
        rows.append((printable(name, limit=40), result.units.get(name, "") or "SI",
                     _number(result.rms[name]), _number(3 * result.rms[name]),
                     _number(result.zero_crossing_rate[name]), _number(result.peak_rate[name]),
                     _number(miles), f"{result.error[name]:.1e}"))
    widths = [max(len(header[i]), *(len(r[i]) for r in rows)) for i in range(len(header))]
    lines.append("  " + "  ".join(h.ljust(w) for h, w in zip(header, widths)))
    lines += ["  " + "  ".join(c.ljust(w) for c, w in zip(row, widths)) for row in rows]
    accelerations = [n for n in result.names if result.units.get(n) == "m/s^2"]
    if accelerations:
        lines.append("  in g (9.80665 m/s^2): " + ", ".join(
            f"{printable(n, limit=40)} {result.rms[n] / STANDARD_GRAVITY:.4g} g RMS"
            for n in accelerations))
    lines.append("  RMS about the reference state; 3-sigma = 3 RMS; Rice's rates of zero "
                 "up-crossings sqrt(m2/m0) and of peaks sqrt(m4/m2).")
    lines += [f"warning: {w}" for w in result.warnings] if warnings else []
    return "\n".join(lines) + "\n"


#: harmonics listed by :func:`periodic_text`
SHOWN_HARMONICS = 5


def periodic_text(result: PeriodicResponse) -> str:
    """The periodic load's series and the response: per harmonic, the mean and the
    largest excursion of the sum, as text.

    Parameters
    ----------
    result : PeriodicResponse

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
    header = ("name", "mean", "largest", *(f"|z_{n + 1}|" for n in range(shown)))
    rows = [(printable(name, limit=40), _number(result.mean[name]),
             _number(result.largest[name]),
             *(_number(abs(result.harmonics[name][n])) for n in range(shown)))
            for name in result.names]
    widths = [max(len(header[i]), *(len(r[i]) for r in rows)) for i in range(len(header))]
    lines.append("  " + "  ".join(h.ljust(w) for h, w in zip(header, widths)))
    lines += ["  " + "  ".join(c.ljust(w) for c, w in zip(row, widths)) for row in rows]
    lines.append("  the sum of the harmonics' stationary responses (SI): mean, largest "
                 "|excursion| over a period, amplitudes of the first harmonics")
    lines += [f"warning: {w}" for w in result.warnings]
    return "\n".join(lines) + "\n"


def _density_unit(unit: str) -> str:
    if not unit:
        return "SI^2/Hz"
    return f"({unit})^2/Hz" if any(c in unit for c in "*/^") else f"{unit}^2/Hz"


def random_chart(result: RandomResponse, names: Sequence[str] | None = None) -> Charts:
    """What the figure of a random response shows: the inputs' spectral densities above
    the responses', one panel per unit, on log-log axes with the units on the axes and
    each curve's RMS value in its label.

    Parameters
    ----------
    result : RandomResponse
    names : sequence of str, optional
        The responses to draw (default: all, at most :data:`MAX_CURVES` per panel).

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
        density = np.asarray(result.input_psd[name], dtype=float)
        rms = math.sqrt(max(float(np.trapezoid(density, f)), 0.0))
        unit = result.input_units.get(name, "")
        label = name + "'" * result.input_derivatives.get(name, 0)
        inputs.append(Curve(f[positive], density[positive],
                            f"{label} (RMS {rms:.3g} {unit_text(unit)})".replace(" )", ")")))
    units = {result.input_units.get(n, "") for n in result.inputs}
    unit = units.pop() if len(units) == 1 else ""
    panels = [Chart(tuple(inputs), xlabel, f"input [{unit_text(_density_unit(unit))}]", xlim,
                    ylog=True, xlog=True, title="input spectral densities (one-sided)")]
    rules = () if result.natural_frequency is None else (
        Rule(float(result.natural_frequency), color="#999999", dash="3.7 1.6", width=0.8,
             label="natural frequency"),)
    for unit, members in list(groups.items())[:MAX_PANELS]:
        curves = tuple(Curve(f[positive], np.asarray(result.psd[name], dtype=float)[positive],
                             f"{name} (RMS {result.rms[name]:.3g} {unit_text(unit)})"
                             .replace(" )", ")"))
                       for name in members[:MAX_CURVES])
        panels.append(Chart(curves, xlabel, f"response [{unit_text(_density_unit(unit))}]",
                            xlim, ylog=True, xlog=True, rules=rules))
    return Charts(tuple(panels), size=(7.5, 2.6 * len(panels) + 0.6))


def plot_random(result: RandomResponse, path: PathArg = None, names: Sequence[str] | None = None,
                ax: Axes | Sequence[Axes] | None = None) -> Figure:
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

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    AnalysisError
        For an unknown name or an unsupported file suffix.
    """
    check_plot_path(path)
    charts = random_chart(result, names)
    count = len(charts.panels)
    axes = None if ax is None else axes_list(ax)
    if axes is not None and len(axes) < count:
        raise AnalysisError(f"the plot needs {count} axes (inputs and one per unit)")
    fig = draw_figure(charts, axes)
    save_figure(fig, path, dpi=150)
    return fig


__all__ = ["random_text", "plot_random", "random_chart"]
