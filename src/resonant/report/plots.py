"""The report's figures: its data computed first, described by the views' chart functions
(:mod:`resonant.charts`, the same descriptions the library's plots draw), written
as SVG text for HTML or drawn with matplotlib for files.

:func:`frequency_response` sweeps the excitation frequency through the model:
when the frequency is a parameter (``omega``), every parameter-dependent
excitation amplitude follows it (a rotating unbalance grows with Omega^2);
otherwise the force amplitudes are held at their operating values.  It returns the
library's :class:`~resonant.analyses.sweep.FrequencyResponse` (the response at the
excitation frequency alone), which :func:`response_chart` describes with
:func:`resonant.analyses.sweep.frequency_response_chart`.

Examples
--------
>>> from resonant.api import load
>>> from resonant.report.plots import (frequency_response, operating_frequency,
...                                    response_chart, to_svg)
>>> import resonant, pathlib
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples" / "cart_pendulum.toml"
>>> eom = load(path).linearize()
>>> solution = eom.stationary()
>>> frf = frequency_response(eom, solution)
>>> frf.parameter, operating_frequency(solution)
('omega', 20.0)
>>> chart = response_chart(frf, 20.0)
>>> [round(m.y, 4) for m in chart.markers][1], chart.xlog, chart.ylog
(0.0451, False, True)
>>> to_svg(chart, 1).startswith("<svg")
True
"""

from __future__ import annotations

import io
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from dataclasses import replace as dataclass_replace
from typing import TYPE_CHECKING, Protocol

import numpy as np
import sympy

from ..analyses.simulate import history_chart
from ..analyses.stationary import common_period
from ..analyses.sweep import frequency_response_chart, sweep
from ..charts import (
    Chart,
    Charts,
    chart_svg,
    charts_svg,
    draw_chart,
    draw_figure,
    save_figure,
)
from ..model.units_display import result_units
from ..system.base import LinearSystem

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analyses.stationary import StationarySolution
    from ..analyses.sweep import FrequencyResponse
    from ..system.latex import SymbolicEquations

MAX_PLOT_COORDINATES = 12
#: subplot margins of the report's 7.0 x 3.6 in figures (room for the axis labels)
MARGINS = {"right": 0.98, "bottom": 0.14, "top": 0.97}


@dataclass(frozen=True)
class TimeHistory:
    """The stationary response of each coordinate over two periods."""

    t: np.ndarray
    values: Mapping[str, np.ndarray]
    period: float
    #: whether ``period`` is the common period of every excitation frequency
    periodic: bool = True
    #: name -> SI unit of the values (a model with units; empty without)
    units: Mapping[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"t": self.t.tolist(), "values": {k: v.tolist() for k, v in self.values.items()}}


class DrawnPlot(Protocol):
    """Plot data of another step that draws itself (the nonlinear frequency-response curve of
    :mod:`resonant.report.nonlinear`)."""

    def draw(self, figure: Figure) -> None: ...  # pragma: no cover

    def to_dict(self) -> dict: ...  # pragma: no cover


class ChartedPlot(Protocol):
    """Plot data of another step that describes its figure as a chart (the nonlinear
    frequency-response curve of :mod:`resonant.report.nonlinear`)."""

    def chart(self) -> Chart | Charts: ...  # pragma: no cover

    def to_dict(self) -> dict: ...  # pragma: no cover


#: what a report figure holds: a chart description (drawn as SVG text or with matplotlib),
#: plot data that describes itself as one, or plot data that draws itself
PlotData = Chart | Charts | ChartedPlot | DrawnPlot


def described(plot: PlotData) -> Chart | Charts | None:
    """The chart description of a figure's plot data (None: it draws itself)."""
    if isinstance(plot, Chart | Charts):
        return plot
    chart = getattr(plot, "chart", None)
    return chart() if callable(chart) else None


# -- data ----------------------------------------------------------------------------------

def _dependents(model, name: str) -> set[str]:
    """Parameters whose value depends (transitively) on parameter ``name``."""
    found = {name}
    for other, expression in model.parameters.items():
        if any(n in found for n, _ in expression.names()):
            found.add(other)
    return found - {name}


def operating_frequency(solution: StationarySolution) -> float | None:
    """The excitation frequency of a solution with one moving harmonic (else None)."""
    moving = [h for h in solution.harmonics if h.omega > 0]
    return float(moving[0].omega) if len(moving) == 1 else None


def frequency_response(model_system: LinearSystem, solution: StationarySolution,
                       points: int = 500) -> FrequencyResponse | None:
    """Amplitudes of the coordinates (and the outputs the sweep gives) at excitation
    frequencies from 0 to ~1.6x the highest natural frequency (or the excitation): the
    response at the excitation frequency alone (a static load does not count), as one
    harmonic; None unless there is one excitation frequency (or no equations in symbols)."""
    w0 = operating_frequency(solution)
    eom = model_system.symbolic()
    if eom is None:
        return None
    n = len(eom.coordinates)
    if w0 is None or n > MAX_PLOT_COORDINATES or eom.harmonics is None:
        return None
    top = max([w0, *solution.natural_frequencies.tolist()])
    grid = np.linspace(top * 1.6 / points, top * 1.6, points)
    grid = np.union1d(grid, [w0])
    parameter = _swept_parameter(eom, w0)
    if parameter is not None:
        # the model swept over its frequency parameter: amplitudes that depend on it follow
        system: LinearSystem = model_system
    else:
        # the force amplitudes held at their operating values: the numeric system with only
        # the moving harmonic, swept over its frequency
        nm = solution.eom
        h = next(h for h in nm.harmonics if h.omega > 0)
        system = replace(nm, harmonics=(h,), outputs={}, system=None)
    result = sweep(system, parameter or "omega", grid, names=list(eom.coordinates),
                   progress=False)
    # the response at the excitation frequency alone: the sum over the harmonics running
    # with the grid (the frequency p and -p, signs folded)
    follows = [k for k, w in enumerate(result.harmonic_omegas)
               if np.allclose(w, grid, rtol=1e-9, atol=0.0)]
    # the coordinates, and the outputs where the sweep gives them (the model's own sweep)
    names = [*eom.coordinates, *(q for q in result.quantities if q not in eom.coordinates)]
    columns = [result.quantities.index(c) for c in names]
    X = np.zeros((grid.size, len(names)), dtype=complex)
    for k in follows:
        X = X + result.response[k][:, columns]
    return replace(result, quantities=tuple(names), response=X[None], harmonic_omegas=grid[None],
                   frequency_sweep=True, frequency_scale=1.0,
                   natural_frequencies=np.asarray(solution.natural_frequencies, dtype=float),
                   coordinates=tuple(eom.coordinates))


def follows_frequency(eom: SymbolicEquations, solution: StationarySolution) -> str | None:
    """The parameter the report's frequency response sweeps (the excitation amplitudes
    that depend on it follow), or None when they are held at their operating values."""
    w0 = operating_frequency(solution)
    return None if w0 is None else _swept_parameter(eom, w0)


def response_chart(frf: FrequencyResponse, operating: float | None,
                   units: Mapping[str, str] | None = None) -> Chart:
    """The report's figure of a frequency response: the amplitudes (the library's chart
    without the phase panel and the peaks), the operating point marked."""
    chart = frequency_response_chart(frf, list(frf.names), units or None, phase=False,
                                     extrema=False, title=False, operating=operating)
    return dataclass_replace(chart.panels[0], legend="best",
                             xlim=(0.0, chart.panels[0].xlim[1]))


def history_figure(history: TimeHistory) -> Chart:
    """The report's figure of a time history (:func:`resonant.analyses.simulate.history_chart`)."""
    return history_chart(history.t, history.values, history.units)


def _swept_parameter(eom: SymbolicEquations, w0: float) -> str | None:
    """The parameter that is the excitation frequency, if the sweep can vary it alone."""
    model = eom.model
    if model.matrices is not None:
        candidates = [h.omega.text.strip() for h in model.matrices.harmonics]
    else:
        frequencies = eom.harmonics.frequencies if eom.harmonics is not None else ()
        candidates = [str(w) for w in frequencies if isinstance(w, sympy.Symbol)]
    for name in candidates:
        if name in model.parameter_values and math.isclose(
                abs(model.parameter_values[name]), w0, rel_tol=1e-9) \
                and not _dependents(model, name):
            return name
    return None


def time_history(solution: StationarySolution, points: int = 600) -> TimeHistory | None:
    """Two periods of the excitation (the common period of all its frequencies; of the
    slowest one when they are incommensurate); None without a harmonic excitation."""
    moving = [h.omega for h in solution.harmonics if h.omega > 0]
    n = len(solution.eom.coordinates)
    if not moving or n > MAX_PLOT_COORDINATES:
        return None
    common = common_period(moving)
    period = common if common is not None else 2 * math.pi / min(moving)
    fastest = max(moving)
    points = int(min(20_000, max(points, 60 * 2 * period * fastest / (2 * math.pi))))
    t = np.linspace(0.0, 2 * period, points)
    response = solution.response(t)
    units = result_units(solution.eom.model)
    return TimeHistory(t, {c: response[c] for c in solution.eom.coordinates}, period,
                       common is not None, units.si if units is not None else {})


# -- drawing ---------------------------------------------------------------------------------

def draw(plot: PlotData, figure) -> None:
    """Draw ``plot`` on a matplotlib figure."""
    chart = described(plot)
    if isinstance(chart, Charts):
        draw_figure(chart, [figure.add_subplot(len(chart.panels), 1, k + 1)
                            for k in range(len(chart.panels))])
        return
    if chart is None:
        plot.draw(figure)  # type: ignore[union-attr]
        return
    ax = draw_chart(chart, figure)
    # margins from the tick labels' lengths: tight_layout measured every text (half the
    # time of a figure)
    figure.subplots_adjust(left=_left_margin(ax), **MARGINS)


def _left_margin(ax: Axes) -> float:
    """Room for the y tick labels and the y label, from the labels' lengths (a character
    of the 10 pt tick font is about 1/80 of the 7 in figure's width)."""
    labels = ax.yaxis.get_major_formatter().format_ticks(ax.get_yticks().tolist())
    visible = [re.sub(r"\\mathdefault|\\times|[{}$^\\]", "", label) for label in labels]
    return min(0.3, 0.05 + 0.0125 * max((len(v) for v in visible), default=1))


def _figure(plot: PlotData):
    from matplotlib.figure import Figure

    chart = described(plot)
    if isinstance(chart, Charts):
        return draw_figure(chart)
    figure = Figure(figsize=(7.0, 3.6))
    draw(plot, figure)
    return figure


def to_svg(plot: PlotData, number: int) -> str:
    """The plot as an ``<svg>`` element for inline HTML (no XML prolog): chart descriptions
    written directly (:func:`resonant.charts.chart_svg`, about a millisecond each),
    other plots by matplotlib."""
    chart = described(plot)
    if isinstance(chart, Chart):
        return chart_svg(chart, f"resonant-figure-{number}")
    if isinstance(chart, Charts):
        return charts_svg(chart, f"resonant-figure-{number}")
    import matplotlib

    buffer = io.StringIO()
    # unique, reproducible ids: several SVGs share one HTML document
    with matplotlib.rc_context({"svg.hashsalt": f"resonant-figure-{number}",
                                "svg.fonttype": "path"}):
        _figure(plot).savefig(buffer, format="svg", metadata={"Date": None})
    text = buffer.getvalue()
    text = re.sub(r"<metadata>.*?</metadata>\s*", "", text[text.find("<svg"):], flags=re.S)
    return text.strip()


def save(plot: PlotData, path, number: int) -> None:
    """Write the plot to a file (format from the suffix: .svg, .pdf, .png)."""
    import matplotlib

    with matplotlib.rc_context({"svg.hashsalt": f"resonant-figure-{number}"}):
        metadata = {"Date": None} if str(path).endswith(".svg") else None
        save_figure(_figure(plot), path, metadata=metadata)


__all__ = ["TimeHistory", "DrawnPlot", "ChartedPlot", "PlotData", "described",
           "frequency_response", "follows_frequency", "operating_frequency", "response_chart",
           "history_figure", "time_history", "draw", "to_svg", "save"]
