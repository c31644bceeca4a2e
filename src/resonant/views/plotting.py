"""Plots of analysis results (matplotlib, imported only when drawing).

Analyses return data; these functions draw it.  Each returns the matplotlib
``Figure`` and, given a ``path``, also writes it (the format follows the
suffix: ``.png``, ``.svg``, ``.pdf``).

Only matplotlib's object API is used: a :class:`matplotlib.figure.Figure` is
made directly (an Agg canvas is attached only to write a file), never through
``pyplot``, and the backend is never switched, so drawing here neither changes
the caller's backend nor registers figures in pyplot's figure manager (nothing
to close, no memory kept).  Given ``ax=`` (``axes=`` for simulations) the
functions draw into the caller's figure instead and return that figure.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..charts import (
    COLORS,
    Annotation,
    Bar,
    Chart,
    Charts,
    Curve,
    Marker,
    PathArg,
    Rule,
    Span,
    check_plot_path,
    draw_figure,
    figure_of,
    save_figure,
    unit_text,
)
from ..errors import AnalysisError, printable
from ..expressions.notation import name_latex
from ..model.options import START_KINDS
from ..model.units_display import unit_latex

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analyses.modes import ModalAnalysis
    from ..analyses.simulate import Simulation
    from ..analyses.sweep import FrequencyResponse

#: at most this many curves are drawn (a 1000-coordinate sweep shows the first ones)
MAX_CURVES = 8
#: amplitudes below this fraction of the largest one are drawn at the curve's floor
FLOOR = 1e-9
#: at most this many natural frequencies are drawn as vertical lines
MAX_LINES = 30


def math_name(name: str) -> str:
    """A model name typeset for matplotlib (``x1`` -> ``$x_{1}$``, ``phi`` -> ``$\\varphi$``),
    or the name as plain text where mathtext cannot set it.

    Examples
    --------
    >>> print(math_name("x1"), math_name("omega"), math_name("F0"))
    $x_{1}$ $\\omega$ $F_{0}$
    """
    from matplotlib.mathtext import MathTextParser

    text = f"${name_latex(name)}$"
    try:
        MathTextParser("path").parse(text)
    except ValueError:
        return printable(name, limit=40).replace("$", r"\$")
    return text


def unit_math(unit: str) -> str:
    """A unit for a matplotlib label: ``N*s/m`` and ``m/s^2`` typeset (a product's dot,
    a power's superscript), a plain one (``m``, ``rad/s``) as it is.

    Examples
    --------
    >>> print(unit_math("m"), unit_math("N*s/m"))
    m $\\mathrm{N\\,s/m}$
    """
    if not any(c in unit for c in "*^"):
        return unit.replace("$", r"\$")
    return "$" + unit_latex(unit).removeprefix("\\ ") + "$"


#: the figure an Axes belongs to (kept under its old name for the other views)
_figure_of = figure_of


def _name(name: str) -> str:
    """A model name as a chart label (math between dollar signs)."""
    return f"${name_latex(name)}$"


def response_axes(parameter: str, names: Sequence[str], *, coordinates: Sequence[str] = (),
                  units: Mapping[str, str] | None = None, unit: str = "",
                  frequency_sweep: bool = True, log: bool = False) -> Chart:
    """The axes and curve styles of a frequency response's amplitude chart, without data:
    what :func:`frequency_response_chart` fills with a sweep and the explore page (its JSON)
    with the curve it computes live.

    Parameters
    ----------
    parameter : str
        The swept parameter.
    names : sequence of str
        The curves, in order (each its colour of the cycle).
    coordinates : sequence of str
        The names that are coordinates (the others are labelled as outputs).
    units : mapping, optional
        name -> unit of the amplitudes: on the axis, or on each curve where they differ.
    unit : str
        The parameter's unit.
    frequency_sweep : bool
        Whether the parameter is the excitation frequency.
    log : bool
        A logarithmic parameter axis.

    Returns
    -------
    Chart
        Curves without points, labels, scales (amplitudes on a log axis).

    Examples
    --------
    >>> c = response_axes("omega", ["x1", "phi"], coordinates=["x1"],
    ...                   units={"x1": "m", "phi": "rad"}, unit="rad/s")
    >>> print(c.xlabel, "|", c.ylabel)
    excitation frequency $\\omega$ [rad/s] | amplitude $X$ [m, rad]
    >>> print(", ".join(k.label for k in c.curves))
    $x_{1}$ [m], $\\varphi$ (output) [rad]
    """
    amplitude_units = {units.get(n, "") for n in names} if units else set()
    per_curve = units if len(amplitude_units) > 1 else None
    curves = []
    for k, name in enumerate(names):
        kind = "" if name in coordinates else " (output)"
        if per_curve and per_curve.get(name) not in (None, "", "1"):
            kind += f" [{unit_math(per_curve[name])}]"
        # past the colour cycle, dashes: every curve stays distinguishable
        dash = (None, "3.7 1.6", "1 1.65", "6.4 1.6 1 1.6")[(k // len(COLORS)) % 4]
        curves.append(Curve(np.empty(0), np.empty(0), f"{_name(name)}{kind}",
                            COLORS[k % len(COLORS)], 1.5, dash))
    shown_units = [unit_math(u) if u not in ("", "1") else "1" for u in sorted(amplitude_units)]
    xlabel = (("excitation frequency " if frequency_sweep else "") + _name(parameter)
              + (f" [{unit}]" if unit else ""))
    ylabel = "amplitude $X$" + (f" [{', '.join(shown_units)}]"
                                if shown_units and shown_units != ["1"] else "")
    return Chart(tuple(curves), xlabel, ylabel, (0.0, 1.0), ylog=True, xlog=log,
                 legend="beside")


def frequency_response_chart(response: FrequencyResponse, names: Sequence[str] | None = None,
                             units: Mapping[str, str] | None = None, *, phase: bool = True,
                             extrema: bool = True, title: bool = True,
                             operating: float | None = None) -> Charts:
    """What the figure of a frequency response shows: amplitudes (log axis) above phases.

    Resonance peaks are marked with triangles (their values noted above the curves),
    antiresonances with circles; natural frequencies in the range of a frequency sweep
    are dotted vertical lines.  Skipped points (undamped resonance) are gaps.

    Parameters
    ----------
    response : FrequencyResponse
    names : sequence of str, optional
        The coordinates and outputs to draw (default: all, at most :data:`MAX_CURVES`,
        outputs included).
    units : mapping, optional
        name -> SI unit of the amplitudes: the amplitude axis is labelled with the unit,
        or each curve where the units differ.
    phase : bool
        Draw the phase panel under the amplitudes.
    extrema : bool
        Mark the peaks and antiresonances.
    title : bool
        Give the figure the model's title.
    operating : float, optional
        The operating value of the parameter: a dashed line there and a dot on each curve.

    Returns
    -------
    Charts

    Raises
    ------
    AnalysisError
        For an unknown name.

    Examples
    --------
    >>> import resonant
    >>> r = resonant.load("examples/cart_pendulum.toml").linearize().sweep(
    ...     "omega", np.linspace(1.0, 20.0, 50))
    >>> charts = frequency_response_chart(r, ["x1"])
    >>> len(charts.panels), charts.panels[0].ylabel, charts.panels[0].ylog
    (2, 'amplitude $X$', True)
    """
    names = _curve_names(response, names)
    axes = response_axes(response.parameter, names, coordinates=response.coordinates,
                         units=units, unit=response.unit,
                         frequency_sweep=response.frequency_sweep, log=bool(response.log))
    floor, top = _amplitude_floor(response, names)
    x = np.asarray(response.values, dtype=float)
    amp_curves: list[Curve] = []
    phase_curves: list[Curve] = []
    markers: list[Marker] = []
    notes: list[Annotation] = []
    labelled: list[float] = []
    for name, style in zip(names, axes.curves):
        color = style.color or COLORS[0]
        amplitude = np.array(response.amplitudes[name], dtype=float)
        with np.errstate(invalid="ignore"):
            shown = np.where(amplitude > 0, np.maximum(amplitude, floor), np.nan)  # log: no 0
        amp_curves.append(replace(style, x=x, y=shown))
        phase_curves.append(Curve(x, unwrapped_degrees(response.phases[name]), "", color, 1.2))
        if operating is not None and x.size > 1 and np.all(np.diff(x) > 0):
            at = float(np.interp(operating, x, amplitude))
            if at > 0:
                markers.append(Marker(float(operating), at, color))
        if extrema:
            markers += _extrema_marks(response, name, color, floor, notes, labelled)
    rules: list[Rule] = []
    natural = response.natural_values
    if natural is not None and x.size:
        lo, hi = float(np.min(x)), float(np.max(x))
        what = "natural frequency" if response.frequency_sweep else \
            "excitation at a natural frequency"
        rules += [Rule(float(w), color="#737373", dash="1 1.65", label=what)
                  for w in natural if lo <= w <= hi][:MAX_LINES]
    if operating is not None:
        rules.append(Rule(float(operating), color="#404040", dash="3.7 1.6",
                          label="operating point"))
    ylim = None
    if extrema and floor > 0 and top > 0:  # clipped to the data, room above for the notes
        ylim = (floor / 1.5, top * (top / floor) ** 0.12 * 1.5)
    xlim = (float(np.nanmin(x)), float(np.nanmax(x))) if x.size else (0.0, 1.0)
    xlabel, log = axes.xlabel, axes.xlog
    any_positive = any(np.isfinite(c.y).any() for c in amp_curves)
    amplitude_chart = replace(axes, curves=tuple(amp_curves), xlim=xlim, ylog=any_positive,
                              markers=tuple(markers), rules=tuple(rules), ylim=ylim,
                              notes=tuple(notes))
    heading = ""
    if title:
        heading = (printable(response.title or "frequency response", limit=80)
                   + "\n" + r"$x = X \sin(\omega t + \delta)$")
    if not phase:
        return Charts((amplitude_chart,), heading)
    phase_rules = tuple(replace(r, label="") for r in rules)
    return Charts((amplitude_chart,
                   Chart(tuple(phase_curves), xlabel, r"phase $\delta$ [°]", xlim,
                         rules=phase_rules, xlog=log, yticks=_phase_ticks(phase_curves),
                         ylim=_phase_limits(phase_curves), legend="none")),
                  heading, heights=(2.2, 1.0), size=(9.5, 6.5))


def _phase_limits(curves: Sequence[Curve]) -> tuple[float, float]:
    """The phase axis: whole quarter turns around the data (at least a half turn) and
    10 degrees of margin."""
    values = np.concatenate([np.asarray(c.y, dtype=float) for c in curves]) if curves else \
        np.empty(0)
    values = values[np.isfinite(values)]
    low, high = (float(values.min()), float(values.max())) if values.size else (-90.0, 0.0)
    first, last = 90 * math.floor(low / 90), 90 * math.ceil(high / 90)
    if last - first < 180:
        first, last = first - 90, last + 90
    return first - 10.0, last + 10.0


def _phase_ticks(curves: Sequence[Curve]) -> tuple[float, ...]:
    low, high = _phase_limits(curves)
    first, last = low + 10.0, high - 10.0
    step = 90 * max(1, math.ceil((last - first) / 90 / 8))
    return tuple(float(v) for v in np.arange(first, last + 1, step))


def _extrema_marks(response: FrequencyResponse, name: str, color: str, floor: float,
                   notes: list[Annotation], labelled: list[float]) -> list[Marker]:
    """Triangles on the resonance peaks (each resonance's value noted once), circles on
    the antiresonances (at the drawn floor for a true zero)."""
    marks = []
    for p in [p for p in response.peaks if p.name == name][:20]:
        marks.append(Marker(p.value, p.amplitude, color, "peak", "resonance peak"))
        # one note per resonance: curves peaking at nearly the same value share it
        if all(abs(p.value - v) > 0.06 * abs(v) for v in labelled):
            labelled.append(p.value)
            notes.append(Annotation(p.value, f"{p.value:.4g}", color))
    for p in [p for p in response.antiresonances if p.name == name][:20]:
        marks.append(Marker(p.value, max(p.amplitude, floor), color, "ring",
                            "antiresonance (zero)"))
    return marks


def plot_frequency_response(response: FrequencyResponse, path: PathArg = None,
                            names: Sequence[str] | None = None, ax: Axes | None = None,
                            units: Mapping[str, str] | None = None) -> Figure:
    """Amplitude (log axis) above phase, against the swept parameter: the chart of
    :func:`frequency_response_chart`, drawn with matplotlib.

    Parameters
    ----------
    response : FrequencyResponse
        The sweep to draw.
    path : str or Path, optional
        Also write the figure there; the format follows the suffix (``.png``,
        ``.svg`` or ``.pdf``, anything else raises :class:`AnalysisError`).
    names : sequence of str, optional
        The coordinates and outputs to draw (default: all, at most
        :data:`MAX_CURVES`, outputs included).
    ax : pair of matplotlib.axes.Axes, or Axes, optional
        Draw into the caller's figure: ``(amplitude_axes, phase_axes)`` for both
        panels, or a single Axes for the amplitude panel alone.  The axes are
        drawn into as they are (no layout change); by default a new figure with
        the two panels stacked is made.
    units : mapping, optional
        name -> SI unit of the amplitudes (``ResultUnits.si`` of
        :mod:`resonant.model.units_display`): the amplitude axis is labelled with the
        unit, or each curve where the units differ.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the one ``ax`` belongs to.

    Raises
    ------
    AnalysisError
        For an unknown name or an unsupported file suffix.
    """
    check_plot_path(path)
    axes = _response_axes(ax)
    charts = frequency_response_chart(response, names, units,
                                      phase=axes is None or len(axes) == 2)
    fig = draw_figure(charts, axes)
    save_figure(fig, path, dpi=150, bbox_inches="tight")
    return fig


def _curve_names(response: FrequencyResponse, names: Sequence[str] | None) -> list[str]:
    """The names to draw: the given ones (checked), else all, at most MAX_CURVES."""
    if names is None:
        names = list(response.names)
        if len(names) > MAX_CURVES:
            outputs = [n for n in names if n not in response.coordinates]
            names = (names[:MAX_CURVES - len(outputs[:MAX_CURVES // 2])]
                     + outputs[:MAX_CURVES // 2])
    unknown = [n for n in names if n not in response.amplitudes]
    if unknown:
        raise AnalysisError(f"nothing to plot named {', '.join(unknown)}")
    return list(names)


def _response_axes(ax: Axes | None) -> list[Any] | None:
    """The caller's ``ax=`` as a list of Axes (amplitude, phase), or None for a new figure."""
    if ax is None:
        return None
    if isinstance(ax, (tuple, list)) or (isinstance(ax, np.ndarray) and ax.ndim == 1):
        if len(ax) != 2:
            raise AnalysisError("ax= takes a pair of Axes (amplitude, phase) or one Axes "
                                "(amplitude only)")
        return list(ax)
    return [ax]


def _amplitude_floor(response: FrequencyResponse, names: Sequence[str]) -> tuple[float, float]:
    """(floor, top) of the plotted amplitudes.

    True zeros (antiresonances of undamped systems, 1e-19 and less) are drawn at the
    floor instead of stretching the log axis over many decades.
    """
    sampled = np.array([response.amplitudes[name] for name in names], dtype=float)
    top = float(np.nanmax(sampled, initial=0.0)) if np.isfinite(sampled).any() else 0.0
    meaningful = sampled[np.isfinite(sampled) & (sampled > FLOOR * top)]
    floor = float(meaningful.min()) if meaningful.size else 0.0
    return floor, top


def unwrapped_degrees(phase: npt.ArrayLike) -> np.ndarray:
    """A phase curve in degrees made continuous: jumps of a full turn removed (each run
    between gaps on its own), so that a phase passing -180 degrees goes on to -270
    instead of jumping to +90; a jump of half a turn (the sign change at an undamped
    resonance) is taken as a growing lag.

    Examples
    --------
    >>> unwrapped_degrees(np.radians([170.0, 179.0, -178.0, -170.0])).round(6).tolist()
    [170.0, 179.0, 182.0, 190.0]
    """
    radians = np.array(phase, dtype=float)
    out = np.full(radians.shape, np.nan)
    finite = np.isfinite(radians)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], finite.astype(int), [0]))))
    for start, stop in zip(edges[::2], edges[1::2]):
        run = radians[start:stop]
        step = np.diff(run)
        wrapped = np.mod(step + math.pi, 2 * math.pi) - math.pi
        # a jump of half a turn (an undamped resonance or antiresonance: the sign flips) is
        # taken as a growing lag, as textbooks draw it, whatever side rounding puts it on
        wrapped[np.abs(np.abs(wrapped) - math.pi) < 0.05] = -math.pi
        out[start:stop] = np.degrees(run + np.concatenate(([0.0], np.cumsum(wrapped - step))))
    return out


def modes_chart(analysis: ModalAnalysis, count: int | None = 6) -> Charts:
    """What the figure of the mode shapes shows: each mode (largest component +1) in a
    panel of its own, bars for up to 24 coordinates (positive blue, negative red) under
    the coordinates' names, a line for more.

    Parameters
    ----------
    analysis : ModalAnalysis
        The modes (those with omega^2 >= 0).
    count : int, optional
        How many modes, lowest first (default 6; None: all).

    Returns
    -------
    Charts

    Raises
    ------
    AnalysisError
        Without modes to draw.
    """
    shapes = analysis.mode_shapes
    total = shapes.shape[1]
    if total == 0:
        raise AnalysisError("there are no modes with omega^2 >= 0 to plot")
    count = total if count is None else max(1, min(count, total))
    panels = []
    for j in range(count):
        shape = np.asarray(shapes[:, j], dtype=float)
        n = shape.shape[0]
        positions = np.arange(1, n + 1, dtype=float)
        w = analysis.natural_frequencies[j]
        text = (f"mode {j + 1}: $\\omega_{{{j + 1}}}$ = {w:.5g} rad/s "
                f"($f_{{{j + 1}}}$ = {w / (2 * math.pi):.4g} Hz)")
        if analysis.proportional_damping and analysis.damped and \
                j < len(analysis.damping_ratios):
            text += f", $\\zeta_{{{j + 1}}}$ = {analysis.damping_ratios[j]:.3g}"
        zero = Rule(0.0, vertical=False, color="#000000", width=0.6)
        if n <= 24:
            colors = tuple(COLORS[0] if v >= 0 else COLORS[3] for v in shape)
            panels.append(Chart((), "", "", (0.4, n + 0.6), rules=(zero,), ylim=(-1.15, 1.15),
                                title=text, legend="none",
                                bars=(Bar(positions, shape, colors),),
                                xticks=tuple((float(p), _name(c)) for p, c in
                                             zip(positions, analysis.coordinates))))
        else:
            panels.append(Chart((Curve(positions, shape, "", COLORS[0], 1.2),),
                                "coordinate number", "", (1.0, float(n)), rules=(zero,),
                                ylim=(-1.15, 1.15), title=text, legend="none"))
    columns = 2 if count > 1 else 1
    rows = math.ceil(count / columns)
    return Charts(tuple(panels), printable(analysis.title or "mode shapes", limit=80)
                  + " (largest component +1)", size=(4.9 * columns, 2.5 * rows),
                  sharex=False, columns=columns)


def plot_modes(analysis: ModalAnalysis, path: PathArg = None, count: int | None = 6,
               ax: Axes | None = None) -> Figure:
    """The mode shapes (largest component +1): the chart of :func:`modes_chart` (bars for
    few coordinates, lines for many), drawn with matplotlib.

    Parameters
    ----------
    analysis : ModalAnalysis
        The modes to draw (those with omega^2 >= 0).
    path : str or Path, optional
        Also write the figure there; the format follows the suffix (``.png``,
        ``.svg`` or ``.pdf``, anything else raises :class:`AnalysisError`).
    count : int, optional
        How many modes to draw, lowest first (default 6; None: all).
    ax : matplotlib.axes.Axes or sequence of Axes, optional
        Draw into the caller's figure: one mode per Axes (a single Axes shows
        the first mode), at most ``count``.  By default a new figure with a
        grid of two columns is made.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the one ``ax`` belongs to.

    Raises
    ------
    AnalysisError
        Without modes to draw, or for an unsupported file suffix.
    """
    check_plot_path(path)
    charts = modes_chart(analysis, count)
    axes = None
    if ax is not None:
        axes = list(np.ravel(np.asarray(ax, dtype=object)))
        if not axes:
            raise AnalysisError("ax= takes an Axes or a non-empty sequence of Axes")
    fig = draw_figure(charts, axes)
    save_figure(fig, path, dpi=150, bbox_inches="tight")
    return fig


def simulation_chart(sim: Simulation, units: Mapping[str, str] | None = None) -> Charts:
    """What the figure of a simulation shows: each coordinate's and output's deviation
    against time in a panel of its own, the linear stationary prediction dashed, the
    window the steady amplitude is read in shaded.

    Parameters
    ----------
    sim : Simulation
    units : mapping, optional
        name -> SI unit (``ResultUnits.si``), shown in each panel's label.

    Returns
    -------
    Charts
    """
    kind = "nonlinear" if sim.nonlinear else "linear"
    t = np.asarray(sim.t, dtype=float)
    xlim = (float(t[0]), float(t[-1])) if t.size > 1 and t[-1] > t[0] else (0.0, 1.0)
    panels = []
    for name in sim.names:
        curves = [Curve(t, np.asarray(sim.states[name], dtype=float), f"{kind} simulation",
                        COLORS[0], 1.0)]
        if name in sim.linear_response:
            curves.append(Curve(t, np.asarray(sim.linear_response[name], dtype=float),
                                "linear stationary prediction", COLORS[3], 1.0, "3.7 1.6"))
        steady = sim.steady_amplitudes.get(name)
        text = f"steady amplitude {steady:.4g}" if steady is not None else ""
        if name in sim.linear_amplitudes:
            text += f", linear {sim.linear_amplitudes[name]:.4g}"
        if name in sim.relative_difference:
            text += f" ({100 * sim.relative_difference[name]:+.3g}%)"
        kindof = "coordinate" if name in sim.coordinates else "output"
        unit = (units or {}).get(name, "")
        unit = f" [{unit}]" if unit not in ("", "1") else ""
        panels.append(Chart(tuple(curves), "time $t$ [s]",
                            f"{_name(name)}{unit} ({kindof}, deviation)", xlim,
                            spans=(Span(float(sim.window[0]), float(sim.window[1]), "#e6e6e6",
                                        "amplitude window"),),
                            title=f"{_name(name)}: {text}"))
    start = START_KINDS[sim.start]
    title = printable(sim.title or "simulation", limit=80)
    return Charts(tuple(panels), f"{title} — {kind}, {start}",
                  size=(9.0, 1.2 + 2.1 * len(panels)), legend="below")


def history_chart(t: npt.ArrayLike, values: Mapping[str, Any],
                  units: Mapping[str, str] | None = None,
                  ylabel: str = "stationary response $q_p(t)$") -> Chart:
    """What the figure of responses against time shows: every curve in one chart, the
    unit on the axis (or each curve's where they differ), a line at zero.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> c = history_chart(t, {"x1": t, "x2": -t}, {"x1": "m", "x2": "rad"})
    >>> c.ylabel, [k.label for k in c.curves]
    ('stationary response $q_p(t)$ [m, rad]', ['$x_{1}$ [m]', '$x_{2}$ [rad]'])
    """
    t = np.asarray(t, dtype=float)
    suffix, per_curve = unit_suffix(list(values), units or {})
    curves = tuple(Curve(t, np.asarray(y, dtype=float), name_label(name, per_curve))
                   for name, y in values.items())
    return Chart(curves, "time $t$ [s]", ylabel + suffix, (float(t[0]), float(t[-1])),
                 rules=(Rule(0.0, vertical=False, color="#999999", width=0.8),))


def name_label(name: str, units: Mapping[str, str] | None = None) -> str:
    """A curve's label: the name typeset, and its unit where given (``$x_{1}$ [m]``)."""
    unit = (units or {}).get(name, "")
    return _name(name) + (f" [{unit_text(unit)}]" if unit and unit != "1" else "")


def unit_suffix(names: Sequence[str], units: Mapping[str, str]) -> tuple[str, Mapping[str, str]]:
    """`` [m]`` for the y axis when every curve has that unit (and no per-curve units),
    else `` [m, rad]`` (in the order of the curves) and the units for each curve's label.

    Examples
    --------
    >>> unit_suffix(["x", "y"], {"x": "m", "y": "m"})
    (' [m]', {})
    """
    shown = {units.get(n, "") for n in names}
    if len(shown) <= 1:
        unit = next(iter(shown), "")
        return (f" [{unit_text(unit)}]" if unit and unit != "1" else ""), {}
    named = [unit_text(u) if u and u != "1" else "1"
             for u in dict.fromkeys(units.get(n, "") for n in names)]
    return f" [{', '.join(named)}]", units


def plot_simulation(sim: Simulation, path: PathArg = None, axes: Sequence[Axes] | None = None,
                    units: Mapping[str, str] | None = None) -> Figure:
    """Deviations vs time, one panel per coordinate/output, the linear prediction dashed:
    the chart of :func:`simulation_chart`, drawn with matplotlib.

    Parameters
    ----------
    sim : Simulation
        The simulation to draw.
    path : str or Path, optional
        Also write the figure there; the format follows the suffix (``.png``,
        ``.svg`` or ``.pdf``, anything else raises :class:`AnalysisError`).
    axes : matplotlib.axes.Axes or sequence of Axes, optional
        Draw into the caller's figure: one Axes per coordinate/output in the
        order of ``sim.names`` (fewer Axes draw the first names only; a single
        Axes shows the first).  By default a new figure with one panel per
        name is made.
    units : mapping, optional
        name -> SI unit (``ResultUnits.si``), shown in each panel's label.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the one ``axes`` belong to.

    Raises
    ------
    AnalysisError
        For an unsupported file suffix.
    """
    check_plot_path(path)
    if axes is not None and not list(np.ravel(np.asarray(axes, dtype=object))):
        raise AnalysisError("axes= takes an Axes or a non-empty sequence of Axes")
    fig = draw_figure(simulation_chart(sim, units), axes)
    save_figure(fig, path, dpi=120)
    return fig


__all__ = ["plot_frequency_response", "plot_modes", "plot_simulation", "math_name",
           "unit_math", "unwrapped_degrees", "frequency_response_chart", "simulation_chart",
           "history_chart", "modes_chart", "name_label", "response_axes", "unit_suffix",
           "MAX_CURVES", "MAX_LINES"]
