"""Views of a shock response spectrum: a text table and the SRS beside the input's history.

Examples
--------
>>> from resonant.analyses.shock import pulse, shock_response_spectrum
>>> t, a = pulse("half-sine", 100.0, 0.011, 1e-5)
>>> srs = shock_response_spectrum(a, 1e-5, [10.0, 100.0, 1000.0])
>>> print(srs_text(srs).splitlines()[0])
Shock response spectrum: absolute acceleration, zeta = 0.05 (Q = 10), signal 0.01101 s
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..analyses.shock import ShockSpectrum
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

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: at most this many rows in the text table (evenly picked)
MAX_ROWS = 40


def srs_text(spectrum: ShockSpectrum) -> str:
    """The spectrum as a table: frequency, maximax, primary, residual.

    Parameters
    ----------
    spectrum : ShockSpectrum

    Returns
    -------
    str
    """
    zeta = spectrum.damping
    q = "inf" if zeta == 0 else f"{1 / (2 * zeta):.4g}"
    lines = [f"Shock response spectrum: {spectrum.quantity}, zeta = {zeta:.4g} (Q = {q}), "
             f"signal {spectrum.duration:.4g} s",
             f"  {'f [Hz]':>10}  {'maximax':>11}  {'primary':>11}  {'residual':>11}"]
    rows = np.unique(np.linspace(0, len(spectrum.frequency) - 1,
                                 min(MAX_ROWS, len(spectrum.frequency))).round().astype(int))
    for i in rows:
        lines.append(f"  {spectrum.frequency[i]:>10.4g}  {spectrum.maximax[i]:>11.4g}  "
                     f"{spectrum.primary[i]:>11.4g}  {spectrum.residual[i]:>11.4g}")
    if len(rows) < len(spectrum.frequency):
        lines.append(f"  ({len(rows)} of {len(spectrum.frequency)} frequencies; --json "
                     "for all)")
    lines += [f"warning: {w}" for w in spectrum.warnings]
    return "\n".join(lines) + "\n"


def srs_chart(spectrum: ShockSpectrum, time: npt.ArrayLike | None = None,
              signal: npt.ArrayLike | None = None, unit: str = "",
              reference: ShockSpectrum | None = None, reference_label: str = "input") -> Charts:
    """What the figure of a shock response spectrum shows: the maximax, primary and
    residual spectra on log-log axes, under the input's history where it is given, and
    beside another spectrum (the input's own, for a response's) where given.

    Parameters
    ----------
    spectrum : ShockSpectrum
    time, signal : array_like, optional
        The input's history, drawn in a panel above the spectrum.
    unit : str
        The signal's unit, for the labels.
    reference : ShockSpectrum, optional
        A spectrum to draw beside (its maximax in grey).
    reference_label : str
        Its name in the legend (``input``: "maximax of the input").

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
    """
    label = f" [{unit_text(unit)}]" if unit else ""
    panels = []
    if time is not None and signal is not None:
        t = np.asarray(time, dtype=float)
        xlim = (float(t[0]), float(t[-1])) if t.size > 1 and t[-1] > t[0] else (0.0, 1.0)
        panels.append(Chart((Curve(t, np.asarray(signal, dtype=float), "input", width=1.0),),
                            "time $t$ [s]", f"input{label}", xlim, title="input history",
                            legend="none"))
    f = np.asarray(spectrum.frequency, dtype=float)
    curves = [Curve(f, np.asarray(spectrum.maximax), "maximax", COLORS[0], 1.6),
              Curve(f, np.asarray(spectrum.primary), "primary", COLORS[1], 1.0, "3.7 1.6"),
              Curve(f, np.asarray(spectrum.residual), "residual", COLORS[2], 1.0, "1 1.65")]
    if reference is not None:
        curves.append(Curve(np.asarray(reference.frequency, dtype=float),
                            np.asarray(reference.maximax), f"maximax of the {reference_label}",
                            "#7f7f7f", 1.2))
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
             ax: Axes | Sequence[Axes] | None = None, unit: str = "") -> Figure:
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
        The signal's unit, for the labels.

    Returns
    -------
    matplotlib.figure.Figure
    """
    check_plot_path(path)
    charts = srs_chart(spectrum, time, signal, unit)
    axes = None if ax is None else axes_list(ax)
    if axes is not None and len(axes) < len(charts.panels):
        charts = replace(charts, panels=charts.panels[-len(axes):])  # the spectrum's
    fig = draw_figure(charts, axes)
    save_figure(fig, path, dpi=150)
    return fig


__all__ = ["srs_text", "plot_srs", "srs_chart"]
