"""Pictures of a study: histograms, scatter plots, Sobol indices, a map of a grid.

Each ``*_chart`` function describes a picture as a chart
(:class:`~resonant.charts.Charts`: drawn with matplotlib or written as SVG text);
each ``plot_*`` function draws that description on ``ax`` (a new figure without one) and
returns the Figure; :func:`plot_study` writes all that fit a study into a directory
(:func:`study_charts` lists them).  Failed samples (NaN) are left out and counted in the
titles.

Examples
--------
>>> import numpy as np, pandas as pd
>>> frame = pd.DataFrame({"k": np.linspace(1, 2, 50), "f": np.linspace(1, 2, 50) ** 0.5})
>>> fig = plot_histogram(frame, "f")
>>> fig.axes[0].get_xlabel()
'$f$'
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..charts import (
    HATCH,
    HATCH_COLOR,
    Bar,
    Chart,
    Charts,
    Curve,
    Field,
    Marker,
    PathArg,
    Rule,
    Span,
    draw_figure,
    save_figure,
)
from ..errors import AnalysisError
from ..expressions.notation import math_name
from ..model import Model
from ..model.study import DERIVED_COLUMNS, QUANTITY_KINDS, QuantityKind, StudySpec
from ..model.units_display import unit_math

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: at most this many points in a scatter plot (an even subsample of the rest)
MAX_SCATTER = 20_000
#: a colour scale is logarithmic where the positive values span this ratio or more
LOG_SPAN = 100.0
#: the hatch of samples without a value (unstable, resonant, failed)
IMPOSSIBLE_COLOR = HATCH_COLOR
#: the samples' colour, and that of the marks over them (mean, quantiles, nominal design)
SAMPLE_COLOR = "#4477aa"
MARK_COLOR = "#cc3311"
#: matplotlib's dashes, in line widths
DASHED = "3.7 1.6"


def study_units(model: Model, spec: StudySpec) -> dict[str, str]:
    """The SI unit of every column of a study: its varied parameters and its quantities
    (a peak's frequency is in the unit of the band's parameter).  Empty without units.

    Parameters
    ----------
    model : Model
    spec : StudySpec

    Returns
    -------
    dict
        column -> unit text (``m``, ``rad/s``, ``N/m``; "" for a pure number).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/absorber_tolerances.toml")
    >>> units = study_units(model, model.study_section)
    >>> units["k2"], units["peak:x1"], units["natural_frequency:1"], units["peak_frequency:x1"]
    ('N/m', 'm', 'rad/s', 'rad/s')
    """
    if model.units is None:
        return {}
    dims = model.units.dimensions
    declared = {**model.units.coordinates, **model.units.outputs,
                **{name: unit for name, (_, unit) in model.units.given.items()}}

    def si(name: str) -> str:
        dim = dims.get(name)
        unit = declared.get(name)
        if dim is None:
            return ""
        if unit is not None and unit.angle and dim.dimensionless:
            return "rad"
        text = dim.text()
        if text == "1/s" and unit is not None:  # a frequency: as the model gives it
            return "Hz" if unit.cyclic else "rad/s"
        return "" if text == "1" else text

    out = {name: si(name) for name in spec.vary}
    for quantity in spec.quantities:
        for column in quantity.columns:
            kind, _, target = column.partition(":")
            unit = _kind_of(kind).unit
            if unit == "target":    # srs: the output before the oscillator's '@frequency'
                unit = si(target.partition("@")[0])
            elif unit == "band":
                unit = si(spec.band.parameter) if spec.band is not None else ""
            out[column] = unit
    return out


def _kind_of(kind: str) -> QuantityKind:
    """The meaning of a column's kind (a quantity's, or a derived column's)."""
    return QUANTITY_KINDS.get(kind) or DERIVED_COLUMNS.get(kind) or QuantityKind(kind, "", "")


def axis_label(column: str, units: Mapping[str, str] | None = None) -> str:
    """A column as an axis title: its name typeset, its unit in brackets.

    Examples
    --------
    >>> axis_label("peak:x1", {"peak:x1": "m"})
    'peak of $x_{1}$ over the band [m]'
    >>> print(axis_label("natural_frequency:2", {"natural_frequency:2": "rad/s"}))
    natural frequency $\\omega_{2}$ [rad/s]
    >>> axis_label("k2", {"k2": "N/m"})
    '$k_{2}$ [N/m]'
    """
    kind, _, target = column.partition(":")
    label = _kind_of(kind).label
    if not target:
        text = math_name(column)
    elif label and _kind_of(kind).target == "name":
        text = label.format(math_name(target))
    elif label and _kind_of(kind).target == "index" and target.isdigit():
        text = label.format(target)
    else:
        text = column.replace("$", r"\$")
    unit = (units or {}).get(column, "")
    return text + (f" [{unit_math(unit)}]" if unit and unit != "1" else "")


def _finite(frame: pd.DataFrame, name: str) -> np.ndarray:
    values = np.asarray(frame[name], dtype=float)
    return values[np.isfinite(values)]


def spans_decades(values: np.ndarray) -> bool:
    """Whether positive values span :data:`LOG_SPAN` or more (a logarithmic scale then).

    Examples
    --------
    >>> spans_decades(np.array([0.01, 5.0])), spans_decades(np.array([1.0, 5.0]))
    (True, False)
    """
    finite = values[np.isfinite(values)]
    return bool(finite.size and np.all(finite > 0) and finite.max() >= LOG_SPAN * finite.min())


def _without_value(frame: pd.DataFrame, quantity: str) -> dict[str, int]:
    """Samples without a value of ``quantity``, counted by their status."""
    values = np.asarray(frame[quantity], dtype=float)
    missing = ~np.isfinite(values)
    if not missing.any():
        return {}
    if "status" in frame:
        status = np.asarray(frame["status"], dtype=object)[missing]
        kinds, counts = np.unique(np.where(status == "ok", "no value", status).astype(str),
                                  return_counts=True)
        return {str(k): int(c) for k, c in zip(kinds, counts)}
    return {"no value": int(missing.sum())}


def _counted(missing: Mapping[str, int]) -> str:
    return ", ".join(f"{count} {kind}" for kind, count in missing.items())


def _name_label(name: str) -> str:
    """A varied parameter's name as a tick label under its bars."""
    return math_name(name)


def _padded(low: float, high: float, log: bool = False) -> tuple[float, float]:
    """A range with 5 % margins (in decades on a log axis), as matplotlib's autoscale."""
    if log:
        lo, hi = _padded(math.log10(low), math.log10(high))
        return 10.0 ** lo, 10.0 ** hi
    pad = 0.05 * (high - low) if high > low else (0.05 * abs(low) or 0.5)
    return low - pad, high + pad


def histogram_chart(frame: pd.DataFrame, quantity: str,
                    units: Mapping[str, str] | None = None) -> Charts:
    """What the histogram of one quantity shows: its samples in bins (geometric ones where
    the values span :data:`LOG_SPAN` or more, on a log axis), its mean and its 5 % and 95 %
    quantiles; the samples without a value counted in the title.

    Parameters
    ----------
    frame : pandas.DataFrame
    quantity : str
        A column.
    units : mapping, optional
        column -> unit (:func:`study_units`).

    Returns
    -------
    Charts

    Examples
    --------
    >>> import pandas as pd
    >>> chart = histogram_chart(pd.DataFrame({"f": [1.0, 2.0, 2.0, np.nan]}), "f")
    >>> panel = chart.panels[0]
    >>> int(panel.bars[0].heights.sum()), panel.title
    (3, '3 samples (1 no value: no value)')
    """
    values = _finite(frame, quantity)
    missing = _without_value(frame, quantity)
    count = int(np.clip(np.sqrt(values.size), 10, 100)) if values.size else 10
    log = spans_decades(values)
    bars: tuple[Bar, ...] = ()
    rules: tuple[Rule, ...] = ()
    xlim, ylim = (0.0, 1.0), (0.0, 1.0)
    if values.size:
        edges = (np.geomspace(values.min(), values.max(), count + 1) if log else
                 np.histogram_bin_edges(values, bins=count))
        heights, edges = np.histogram(values, bins=edges)
        bars = (Bar((edges[1:] + edges[:-1]) / 2, heights.astype(float), (SAMPLE_COLOR,),
                    width=np.diff(edges), edge="#ffffff"),)
        low, high = np.quantile(values, [0.05, 0.95])
        rules = (Rule(float(values.mean()), color=MARK_COLOR, width=1.2, label="mean"),
                 Rule(float(low), color=MARK_COLOR, width=0.8, dash=DASHED,
                      label="5 % and 95 % quantiles"),
                 Rule(float(high), color=MARK_COLOR, width=0.8, dash=DASHED,
                      label="5 % and 95 % quantiles"))
        xlim = _padded(float(edges[0]), float(edges[-1]), log)
        ylim = (0.0, 1.05 * float(max(heights.max(), 1)))
    title = f"{values.size} samples" + (f" ({_counted(missing)}: no value)" if missing else "")
    chart = Chart((), axis_label(quantity, units) + (" (log scale)" if log else ""), "samples",
                  xlim, xlog=log, ylim=ylim, bars=bars, rules=rules, title=title,
                  legend="below")
    return Charts((chart,), size=(6.4, 4.6))


def plot_histogram(frame: pd.DataFrame, quantity: str, ax: Axes | None = None,
                   units: Mapping[str, str] | None = None, path: PathArg = None) -> Figure:
    """The distribution of one quantity, with its mean and its 5 % and 95 % quantiles: the
    chart of :func:`histogram_chart`, drawn with matplotlib.

    Parameters
    ----------
    frame : pandas.DataFrame
    quantity : str
        A column.
    ax : matplotlib Axes, optional
    units : mapping, optional
        column -> unit (:func:`study_units`).
    path : str or Path, optional
        Also write the figure there (``.png``, ``.svg`` or ``.pdf``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = draw_figure(histogram_chart(frame, quantity, units), None if ax is None else [ax])
    save_figure(fig, path)
    return fig


def _cell_edges(centres: np.ndarray) -> np.ndarray:
    """The edges of grid cells centred on sorted ``centres`` (midpoints; the outer
    cells as wide as their neighbours)."""
    if centres.size == 1:
        return np.array([centres[0] - 0.5, centres[0] + 0.5])
    mid = (centres[1:] + centres[:-1]) / 2
    return np.concatenate(([2 * centres[0] - mid[0]], mid, [2 * centres[-1] - mid[-1]]))


def scatter_chart(frame: pd.DataFrame, quantity: str, parameters: Sequence[str],
                  units: Mapping[str, str] | None = None,
                  nominal: Mapping[str, float] | None = None) -> Charts:
    """What the scatter plots of one quantity show: a panel per varied parameter (three to
    a row), every sample a dot (at most :data:`MAX_SCATTER`, an even subsample); samples
    without a value as grey crosses on a hatched band under the lowest value; the nominal
    design (the model's values) as a dashed line.

    Parameters
    ----------
    frame : pandas.DataFrame
    quantity : str
    parameters : sequence of str
        The varied parameters (one panel each).
    units : mapping, optional
        column -> unit (:func:`study_units`).
    nominal : mapping, optional
        parameter -> its nominal value, marked.

    Returns
    -------
    Charts

    Examples
    --------
    >>> import pandas as pd
    >>> frame = pd.DataFrame({"k": [1.0, 2.0, 3.0], "f": [1.0, np.nan, 3.0]})
    >>> panel = scatter_chart(frame, "f", ["k"]).panels[0]
    >>> [(c.label, c.marker, c.line, len(c.x)) for c in panel.curves]
    [('sample', 'point', False, 2), ('', 'cross', False, 1)]
    >>> panel.spans[0].label
    'no value: 1 no value'
    """
    step = max(1, len(frame) // MAX_SCATTER)
    y = np.asarray(frame[quantity], dtype=float)[::step]
    bad = ~np.isfinite(y)
    missing = _without_value(frame, quantity)
    finite = y[~bad]
    log = spans_decades(finite)
    shown = np.log10(finite) if log else finite
    low, high = (float(shown.min()), float(shown.max())) if finite.size else (0.0, 1.0)
    span = (high - low) or abs(high) or 1.0
    # the band of the samples without a value, under the lowest value (in the axis' scale)
    below = [10 ** v if log else v for v in (low - 0.18 * span, low - 0.12 * span,
                                              low - 0.06 * span)]
    ylim = None
    if bad.any():
        bottom, top = low - 0.18 * span - 0.06 * span, high + 0.06 * span
        ylim = (10 ** bottom, 10 ** top) if log else (bottom, top)
    panels = []
    for name in parameters:
        x = np.asarray(frame[name], dtype=float)[::step]
        curves = [Curve(x[~bad], y[~bad], "sample", SAMPLE_COLOR, marker="point", line=False,
                        opacity=0.45)]
        spans: tuple[Span, ...] = ()
        if bad.any():
            curves.append(Curve(x[bad], np.full(int(bad.sum()), below[1]), "", IMPOSSIBLE_COLOR,
                                marker="cross", line=False))
            spans = (Span(below[0], below[2], "#ffffff", f"no value: {_counted(missing)}",
                          vertical=False, hatch=IMPOSSIBLE_COLOR),)
        rules: tuple[Rule, ...] = ()
        marks = x[np.isfinite(x)]
        if nominal and name in nominal:
            rules = (Rule(float(nominal[name]), color=MARK_COLOR, dash=DASHED,
                          label="nominal design"),)
            marks = np.append(marks, float(nominal[name]))
        xlim = _padded(float(marks.min()), float(marks.max())) if marks.size else (0.0, 1.0)
        panels.append(Chart(tuple(curves), axis_label(name, units), axis_label(quantity, units),
                            xlim, ylog=log, ylim=ylim, rules=rules, spans=spans))
    columns = max(1, min(len(parameters), 3))
    rows = -(-len(parameters) // 3)
    return Charts(tuple(panels), size=(4.3 * columns + 0.6, 3.9 * rows + 0.7), sharex=False,
                  legend="below", columns=columns)


def plot_scatter(frame: pd.DataFrame, quantity: str, parameters: Sequence[str],
                 ax: Axes | None = None, units: Mapping[str, str] | None = None,
                 nominal: Mapping[str, float] | None = None, path: PathArg = None) -> Figure:
    """One quantity against each varied parameter, side by side: the chart of
    :func:`scatter_chart`, drawn with matplotlib.

    Samples without a value (unstable, resonant) are drawn as grey crosses on a hatched
    band under the axis, the nominal design (the model's values) as a dashed line.

    Parameters
    ----------
    frame : pandas.DataFrame
    quantity : str
    parameters : sequence of str
        The varied parameters (one panel each).
    ax : matplotlib Axes, optional
        Used for a single parameter only.
    units : mapping, optional
        column -> unit (:func:`study_units`).
    nominal : mapping, optional
        parameter -> its nominal value, marked.
    path : str or Path, optional
        Also write the figure there (``.png``, ``.svg`` or ``.pdf``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    if ax is not None and len(parameters) != 1:
        raise AnalysisError("a scatter plot of several parameters needs its own figure")
    # in the caller's axes, the legend inside them
    fig = draw_figure(scatter_chart(frame, quantity, parameters, units, nominal),
                      None if ax is None else [ax])
    save_figure(fig, path)
    return fig


def sobol_chart(indices: Mapping[str, Any], quantity: str,
                units: Mapping[str, str] | None = None) -> Charts:
    """What the Sobol indices of one quantity show: the first-order and the total index of
    each varied parameter side by side, with their 95 % intervals.

    Parameters
    ----------
    indices : mapping
        The entry of :func:`resonant.studies.sobol_indices` for the quantity.
    quantity : str
    units : mapping, optional
        column -> unit (:func:`study_units`).

    Returns
    -------
    Charts

    Examples
    --------
    >>> entry = {"parameters": ["k", "c"], "S1": [0.7, None], "S1_conf": [0.1, None],
    ...          "ST": [0.8, 0.1], "ST_conf": [0.1, 0.05]}
    >>> panel = sobol_chart(entry, "f").panels[0]
    >>> [b.label for b in panel.bars], panel.bars[0].heights.tolist()
    (['first order', 'total'], [0.7, nan])
    """
    names = list(indices["parameters"])
    x = np.arange(len(names), dtype=float)
    bars = tuple(Bar(x + offset, _numbers(indices[key]), (color,), width=0.36, label=label,
                     errors=_numbers(indices[f"{key}_conf"]))
                 for offset, key, color, label in ((-0.18, "S1", "#4477aa", "first order"),
                                                   (0.18, "ST", "#ee7733", "total")))
    with np.errstate(all="ignore"):
        ends = np.concatenate([_numbers(indices[key]) + sign * np.nan_to_num(
            _numbers(indices[f"{key}_conf"])) for key in ("S1", "ST") for sign in (-1, 1)])
    ends = ends[np.isfinite(ends)]
    low, high = _padded(float(min(ends.min(), 0.0)) if ends.size else 0.0,
                        float(max(ends.max(), 0.0)) if ends.size else 1.0)
    low = low if ends.size and ends.min() < 0 else 0.0  # bars stand on the axis
    note = f" ({indices['note']})" if indices.get("note") else ""
    chart = Chart((), "", "Sobol index", _padded(-0.36, len(names) - 1 + 0.36),
                  ylim=(min(0.0, low), max(1.05, high)),
                  rules=(Rule(0.0, vertical=False, color="#000000", width=0.6),),
                  title=f"sensitivity of {axis_label(quantity, units)}{note}", bars=bars,
                  xticks=tuple((float(k), _name_label(n)) for k, n in enumerate(names)))
    return Charts((chart,), size=(6.4, 4.4))


def plot_sobol(indices: Mapping[str, Any], quantity: str, ax: Axes | None = None,
               units: Mapping[str, str] | None = None, path: PathArg = None) -> Figure:
    """First-order and total Sobol indices of one quantity, with 95 % intervals: the chart
    of :func:`sobol_chart`, drawn with matplotlib.

    Parameters
    ----------
    indices : mapping
        The entry of :func:`resonant.studies.sobol_indices` for the quantity.
    quantity : str
    ax : matplotlib Axes, optional
    units : mapping, optional
        column -> unit (:func:`study_units`).
    path : str or Path, optional
        Also write the figure there (``.png``, ``.svg`` or ``.pdf``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = draw_figure(sobol_chart(indices, quantity, units), None if ax is None else [ax])
    save_figure(fig, path)
    return fig


def _numbers(values: Iterable[float | None]) -> np.ndarray:
    """Indices as numbers, NaN where there are none (None)."""
    return np.array([math.nan if v is None else v for v in values], dtype=float)


def contour_chart(frame: pd.DataFrame, quantity: str, x: str, y: str,
                  units: Mapping[str, str] | None = None,
                  nominal: Mapping[str, float] | None = None) -> Charts:
    """What the map of a quantity over a two-parameter grid shows: one coloured cell per
    grid point (a :class:`~resonant.charts.Field`).

    Cells, not contours: a jump (a peak's frequency moving from one resonance to the
    other) stays a sharp edge instead of being smeared into colours that do not occur.
    Cells without a value (unstable, resonant) are hatched; the colour scale is
    logarithmic where the values span :data:`LOG_SPAN` or more; the nominal design is a
    star.

    Parameters
    ----------
    frame : pandas.DataFrame
        The rows of a grid design over ``x`` and ``y``.
    quantity, x, y : str
        Columns.
    units : mapping, optional
        column -> unit (:func:`study_units`).
    nominal : mapping, optional
        parameter -> its nominal value.

    Returns
    -------
    Charts

    Examples
    --------
    >>> import pandas as pd
    >>> frame = pd.DataFrame({"a": [1.0, 2.0, 1.0, 2.0], "b": [0.0, 0.0, 1.0, 1.0],
    ...                       "f": [1.0, 2.0, 3.0, np.nan]})
    >>> field = contour_chart(frame, "f", "a", "b").panels[0].fields[0]
    >>> field.x.tolist(), field.z.tolist(), field.missing
    ([0.5, 1.5, 2.5], [[1.0, 2.0], [3.0, nan]], 'no value: 1 no value')
    """
    table = frame.pivot_table(index=y, columns=x, values=quantity, aggfunc="first",
                              dropna=False)
    grid = np.asarray(table.to_numpy(dtype=float))
    xs, ys = table.columns.to_numpy(dtype=float), table.index.to_numpy(dtype=float)
    log = spans_decades(grid.ravel())
    missing = _without_value(frame, quantity)
    xe, ye = _cell_edges(xs), _cell_edges(ys)
    field = Field(xe, ye, grid, axis_label(quantity, units) + (" (log scale)" if log else ""),
                  log=log, missing=f"no value: {_counted(missing)}" if missing else "")
    markers: tuple[Marker, ...] = ()
    if nominal and x in nominal and y in nominal:
        markers = (Marker(float(nominal[x]), float(nominal[y]), "#ffffff", "star",
                          "nominal design"),)
    chart = Chart((), axis_label(x, units), axis_label(y, units),
                  (float(xe[0]), float(xe[-1])), ylim=(float(ye[0]), float(ye[-1])),
                  markers=markers, fields=(field,), legend="below")
    return Charts((chart,), size=(6.6, 5.4))


def plot_contour(frame: pd.DataFrame, quantity: str, x: str, y: str, ax: Axes | None = None,
                 units: Mapping[str, str] | None = None,
                 nominal: Mapping[str, float] | None = None, path: PathArg = None) -> Figure:
    """A quantity over a two-parameter grid, one coloured cell per grid point: the chart
    of :func:`contour_chart`, drawn with matplotlib.

    Parameters
    ----------
    frame : pandas.DataFrame
        The rows of a grid design over ``x`` and ``y``.
    quantity, x, y : str
        Columns.
    ax : matplotlib Axes, optional
    units : mapping, optional
        column -> unit (:func:`study_units`).
    nominal : mapping, optional
        parameter -> its nominal value.
    path : str or Path, optional
        Also write the figure there (``.png``, ``.svg`` or ``.pdf``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = draw_figure(contour_chart(frame, quantity, x, y, units, nominal),
                      None if ax is None else [ax])
    save_figure(fig, path)
    return fig


def _file_name(kind: str, quantity: str) -> str:
    return f"{kind}-{re.sub(r'[^A-Za-z0-9_.-]+', '_', quantity)}.png"


def plot_study(frame: pd.DataFrame, parameters: Sequence[str], quantities: Sequence[str],
               directory: str | Path, sensitivity: Mapping[str, Any] | None = None,
               grid: bool = False, units: Mapping[str, str] | None = None,
               nominal: Mapping[str, float] | None = None) -> list[Path]:
    """Write every picture of a study into ``directory`` (created if missing).

    Parameters
    ----------
    frame : pandas.DataFrame
    parameters, quantities : sequence of str
        The varied parameters and the quantities' columns.
    directory : str or path
    sensitivity : mapping, optional
        Sobol indices per quantity.
    grid : bool
        A grid design (a map of cells for two parameters).
    units : mapping, optional
        column -> unit (:func:`study_units`), shown on the axes.
    nominal : mapping, optional
        parameter -> its nominal value (the model's), marked.

    Returns
    -------
    list of Path
        The files written.
    """
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise AnalysisError(f"cannot create the plot directory '{directory}': "
                            f"{exc.strerror or exc}") from None
    written: list[Path] = []

    def save(charts: Charts, kind: str, quantity: str) -> None:
        path = directory / _file_name(kind, quantity)
        save_figure(draw_figure(charts), path)
        written.append(path)

    for quantity, kind, charts in study_charts(frame, parameters, quantities, sensitivity,
                                               grid, units, nominal):
        save(charts, kind, quantity)
    return written


def study_charts(frame: pd.DataFrame, parameters: Sequence[str], quantities: Sequence[str],
                 sensitivity: Mapping[str, Any] | None = None, grid: bool = False,
                 units: Mapping[str, str] | None = None,
                 nominal: Mapping[str, float] | None = None) -> list[tuple[str, str, Charts]]:
    """Every chart of a study that fits it: (quantity, kind, chart) with kind
    ``histogram``, ``scatter``, ``sobol`` (with its Sobol indices) and ``contour`` (a grid
    over two parameters); the arguments as :func:`plot_study`'s.

    Examples
    --------
    >>> import pandas as pd
    >>> frame = pd.DataFrame({"k": np.linspace(1, 2, 20), "f": np.linspace(1, 2, 20)})
    >>> [kind for _, kind, _ in study_charts(frame, ["k"], ["f"])]
    ['histogram', 'scatter']
    """
    out = []
    for quantity in quantities:
        out.append((quantity, "histogram", histogram_chart(frame, quantity, units)))
        out.append((quantity, "scatter", scatter_chart(frame, quantity, parameters, units,
                                                       nominal)))
        if sensitivity and quantity in sensitivity:
            out.append((quantity, "sobol", sobol_chart(sensitivity[quantity], quantity, units)))
        if grid and len(parameters) == 2:
            first, second = parameters
            out.append((quantity, "contour", contour_chart(frame, quantity, first, second,
                                                           units, nominal)))
    return out


__all__ = ["axis_label", "contour_chart", "histogram_chart", "plot_contour", "plot_histogram",
           "plot_scatter", "plot_sobol", "plot_study", "scatter_chart", "sobol_chart",
           "spans_decades", "study_charts", "study_units", "HATCH"]
