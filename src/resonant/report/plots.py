"""Plot data of the report (computed first) and its drawing with matplotlib (separately).

:func:`frequency_response` sweeps the excitation frequency through the model:
when the frequency is a parameter (``omega``), every parameter-dependent
excitation amplitude follows it (a rotating unbalance grows with Omega^2);
otherwise the force amplitudes are held at their operating values.

Examples
--------
>>> from resonant.api import load
>>> from resonant.report.plots import frequency_response, to_svg
>>> import resonant, pathlib
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples" / "cart_pendulum.toml"
>>> eom = load(path).linearize()
>>> frf = frequency_response(eom, eom.stationary())
>>> frf.parameter, round(frf.operating, 6), round(float(frf.operating_amplitudes["x2"]), 4)
('omega', 20.0, 0.0451)
>>> to_svg(frf, 1).startswith("<svg")
True
"""

from __future__ import annotations

import io
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import sympy

from ..analyses.stationary import common_period
from ..analyses.sweep import sweep
from ..system import LinearSystem
from ..views.charts import COLORS, Chart, Curve, Marker, Rule, chart_svg, draw_chart
from ..views.notation import name_latex
from ..views.units_display import result_units

if TYPE_CHECKING:  # pragma: no cover
    from ..analyses.stationary import StationarySolution
    from ..system import LinearEOM

MAX_PLOT_COORDINATES = 12
#: subplot margins of the report's 7.0 x 3.6 in figures (room for the axis labels)
MARGINS = {"right": 0.98, "bottom": 0.14, "top": 0.97}


@dataclass(frozen=True)
class ResponseCurves:
    """Amplitude of each coordinate against the excitation frequency."""

    omega: np.ndarray
    amplitudes: Mapping[str, np.ndarray]
    operating: float
    operating_amplitudes: Mapping[str, float]
    natural_frequencies: np.ndarray
    #: the swept parameter, or None when the force amplitudes are held fixed
    parameter: str | None
    #: name -> SI unit of the amplitudes (a model with units; empty without)
    units: Mapping[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"omega": self.omega.tolist(), "parameter": self.parameter,
                "amplitudes": {k: v.tolist() for k, v in self.amplitudes.items()},
                "operating": self.operating}


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

    def draw(self, figure: Any) -> None: ...  # pragma: no cover

    def to_dict(self) -> dict: ...  # pragma: no cover


PlotData = ResponseCurves | TimeHistory | DrawnPlot


# -- data ----------------------------------------------------------------------------------

def _dependents(model, name: str) -> set[str]:
    """Parameters whose value depends (transitively) on parameter ``name``."""
    found = {name}
    for other, expression in model.parameters.items():
        if any(n in found for n, _ in expression.names()):
            found.add(other)
    return found - {name}


def frequency_response(eom: LinearEOM, solution: StationarySolution,
                       points: int = 500) -> ResponseCurves | None:
    """Amplitudes of the coordinates for excitation frequencies from 0 to ~1.6x the highest
    natural frequency (or the excitation); None unless there is one excitation frequency."""
    moving = [h for h in solution.harmonics if h.omega > 0]
    n = len(eom.coordinates)
    if len(moving) != 1 or n > MAX_PLOT_COORDINATES or eom.harmonics is None:
        return None
    w0 = moving[0].omega
    top = max([w0, *solution.natural_frequencies.tolist()])
    grid = np.linspace(top * 1.6 / points, top * 1.6, points)
    grid = np.union1d(grid, [w0])
    parameter = _swept_parameter(eom, w0)
    if parameter is not None:
        # the model swept over its frequency parameter: amplitudes that depend on it follow
        system: LinearSystem = eom
    else:
        # the force amplitudes held at their operating values: the numeric system with only
        # the moving harmonic, swept over its frequency
        nm = solution.eom
        h = next(h for h in nm.harmonics if h.omega > 0)
        system = replace(nm, harmonics=(h,), outputs={}, system=None)
    result = sweep(system, parameter or "omega", grid, names=list(eom.coordinates),
                   progress=False)
    # the response at the excitation frequency alone (a static load does not count): the
    # sum over the harmonics running with the grid (the frequency p and -p, signs folded)
    follows = [k for k, w in enumerate(result.harmonic_omegas)
               if np.allclose(w, grid, rtol=1e-9, atol=0.0)]
    # the coordinates, and the outputs where the sweep gives them (the model's own sweep)
    names = [*eom.coordinates, *(q for q in result.quantities if q not in eom.coordinates)]
    columns = [result.quantities.index(c) for c in names]
    X = np.zeros((grid.size, len(names)), dtype=complex)
    for k in follows:
        X = X + result.response[k][:, columns]
    skipped = np.isin(grid, np.asarray(result.skipped, dtype=float))
    X[skipped] = np.nan  # exactly at an undamped resonance: left out of the curve
    amplitudes = {c: np.abs(X[:, i]) for i, c in enumerate(names)}
    at = int(np.argmin(np.abs(grid - w0)))
    units = result_units(eom.model)
    return ResponseCurves(grid, amplitudes, w0,
                             {c: float(a[at]) for c, a in amplitudes.items()},
                             solution.natural_frequencies, parameter,
                             units.si if units is not None else {})


def _swept_parameter(eom: LinearEOM, w0: float) -> str | None:
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

def _label(name: str, units: Mapping[str, str] | None = None) -> str:
    unit = (units or {}).get(name, "")
    return "$" + name_latex(name) + "$" + (f" [{unit}]" if unit and unit != "1" else "")


def _unit_suffix(plot: ResponseCurves | TimeHistory) -> tuple[str, Mapping[str, str]]:
    """`` [m]`` for the y axis when every curve has that unit, else `` [m, rad]`` and
    per-curve units in the legend."""
    shown = {plot.units.get(n, "") for n in (plot.amplitudes if isinstance(
        plot, ResponseCurves) else plot.values)}
    if len(shown) == 1:
        unit = next(iter(shown))
        return (f" [{unit}]" if unit and unit != "1" else ""), {}
    # several units: all of them on the axis (in the order of the curves), each in the legend
    named = [u if u and u != "1" else "1" for u in dict.fromkeys(
        plot.units.get(n, "") for n in (plot.amplitudes if isinstance(
            plot, ResponseCurves) else plot.values))]
    return f" [{', '.join(named)}]", plot.units


def chart_of(plot: ResponseCurves | TimeHistory) -> Chart:
    """What the figure of a frequency response or a time history shows."""
    suffix, per_curve = _unit_suffix(plot)
    if isinstance(plot, ResponseCurves):
        curves = tuple(Curve(plot.omega, amp, _label(name, per_curve), COLORS[i % len(COLORS)])
                       for i, (name, amp) in enumerate(plot.amplitudes.items()))
        markers = tuple(Marker(plot.operating, value, c.color or "#000")
                        for c, value in zip(curves, plot.operating_amplitudes.values())
                        if value > 0)
        rules = tuple(Rule(float(w), color="#999999", dash="1 1.65")
                      for w in plot.natural_frequencies if 0 < w <= plot.omega[-1])
        rules += (Rule(plot.operating, color="#404040", dash="3.7 1.6"),)
        return Chart(curves, r"excitation frequency $\omega$ [rad/s]", "amplitude $X$" + suffix,
                     (0.0, float(plot.omega[-1])), ylog=True, markers=markers, rules=rules)
    curves = tuple(Curve(plot.t, y, _label(name, per_curve))
                   for name, y in plot.values.items())
    return Chart(curves, "time $t$ [s]", "stationary response $q_p(t)$" + suffix,
                 (float(plot.t[0]), float(plot.t[-1])),
                 rules=(Rule(0.0, vertical=False, color="#999999", width=0.8),))


def draw(plot: PlotData, figure) -> None:
    """Draw ``plot`` on a matplotlib figure."""
    if not isinstance(plot, ResponseCurves | TimeHistory):
        plot.draw(figure)
        return
    ax = draw_chart(chart_of(plot), figure)
    # margins from the tick labels' lengths: tight_layout measured every text (half the
    # time of a figure)
    figure.subplots_adjust(left=_left_margin(ax), **MARGINS)


def _left_margin(ax: Any) -> float:
    """Room for the y tick labels and the y label, from the labels' lengths (a character
    of the 10 pt tick font is about 1/80 of the 7 in figure's width)."""
    labels = ax.yaxis.get_major_formatter().format_ticks(ax.get_yticks())
    visible = [re.sub(r"\\mathdefault|\\times|[{}$^\\]", "", label) for label in labels]
    return min(0.3, 0.05 + 0.0125 * max((len(v) for v in visible), default=1))


def _figure(plot: PlotData):
    from matplotlib.figure import Figure

    figure = Figure(figsize=(7.0, 3.6))
    draw(plot, figure)
    return figure


def to_svg(plot: PlotData, number: int) -> str:
    """The plot as an ``<svg>`` element for inline HTML (no XML prolog): frequency
    responses and time histories written directly (:func:`resonant.views.charts.chart_svg`,
    about a millisecond each), other plots by matplotlib."""
    if isinstance(plot, ResponseCurves | TimeHistory):
        return chart_svg(chart_of(plot), f"resonant-figure-{number}")
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
        _figure(plot).savefig(path, metadata=metadata)


__all__ = ["ResponseCurves", "TimeHistory", "DrawnPlot", "PlotData", "frequency_response",
           "time_history", "chart_of", "draw", "to_svg", "save"]
