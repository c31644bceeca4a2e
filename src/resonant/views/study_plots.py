"""Pictures of a study: histograms, scatter plots, Sobol indices, a map of a grid.

Each ``plot_*`` function draws on ``ax`` (a new figure without one) and
returns the Figure; :func:`plot_study` writes all that fit a study into a
directory.  Failed samples (NaN) are left out and counted in the titles.

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

from ..errors import AnalysisError
from ..model import Model
from ..model.study import StudySpec
from .plotting import _figure_of, _new_figure, _save, math_name, unit_math

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

#: at most this many points in a scatter plot (an even subsample of the rest)
MAX_SCATTER = 20_000
#: a colour scale is logarithmic where the positive values span this ratio or more
LOG_SPAN = 100.0
#: the hatch of samples without a value (unstable, resonant, failed)
HATCH = "////"
IMPOSSIBLE_COLOR = "0.55"


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
            if kind in ("amplitude", "peak", "nonlinear_amplitude", "rms"):
                out[column] = si(target)
            elif kind == "srs":  # the maximax of an oscillator on the output's history
                out[column] = si(target.partition("@")[0])
            elif kind == "damage":  # Miner's sum
                out[column] = ""
            elif kind == "phase":
                out[column] = "rad"
            elif kind == "natural_frequency":
                out[column] = "rad/s"
            elif kind == "peak_frequency" and spec.band is not None:
                out[column] = si(spec.band.parameter)
            else:
                out[column] = ""
    return out


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
    words = {"amplitude": "amplitude of {}", "peak": "peak of {} over the band",
             "peak_frequency": "frequency of the peak of {}", "phase": "phase of {}",
             "nonlinear_amplitude": "amplitude of {} (nonlinear)"}
    if not target:
        text = math_name(column)
    elif kind in words:
        text = words[kind].format(math_name(target))
    elif kind == "natural_frequency" and target.isdigit():
        text = rf"natural frequency $\omega_{{{target}}}$"
    elif kind == "damping_ratio" and target.isdigit():
        text = rf"damping ratio $\zeta_{{{target}}}$"
    else:
        text = column.replace("$", r"\$")
    unit = (units or {}).get(column, "")
    return text + (f" [{unit_math(unit)}]" if unit and unit != "1" else "")


def _axes(ax: Axes | None, **figure: object) -> tuple[Figure, Axes]:
    if ax is not None:
        return _figure_of(ax), ax
    fig = _new_figure(**figure)
    return fig, fig.add_subplot()


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


def plot_histogram(frame: pd.DataFrame, quantity: str, ax: Axes | None = None,
                   units: Mapping[str, str] | None = None) -> Figure:
    """The distribution of one quantity, with its mean and its 5 % and 95 % quantiles.

    Parameters
    ----------
    frame : pandas.DataFrame
    quantity : str
        A column.
    ax : matplotlib Axes, optional
    units : mapping, optional
        column -> unit (:func:`study_units`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, figsize=(6.4, 4.6), layout="constrained")
    values = _finite(frame, quantity)
    missing = _without_value(frame, quantity)
    count = int(np.clip(np.sqrt(values.size), 10, 100)) if values.size else 10
    log = spans_decades(values)
    bins: Any = np.geomspace(values.min(), values.max(), count + 1) if log else count
    ax.hist(values, bins=bins, color="#4477aa", edgecolor="white", linewidth=0.4)
    if log:
        ax.set_xscale("log")
    if values.size:
        ax.axvline(values.mean(), color="#cc3311", linewidth=1.2, label="mean")
        for k, q in enumerate(np.quantile(values, [0.05, 0.95])):
            ax.axvline(q, color="#cc3311", linewidth=0.8, linestyle="--",
                       label="5 % and 95 % quantiles" if k == 0 else None)
        # under the plot: no line crosses it
        ax.legend(fontsize="small", frameon=False, ncols=2, loc="upper center",
                  bbox_to_anchor=(0.5, -0.16))
    ax.set_xlabel(axis_label(quantity, units) + (" (log scale)" if log else ""))
    ax.set_ylabel("samples")
    ax.set_title(f"{values.size} samples" + (f" ({_counted(missing)}: no value)"
                                              if missing else ""), fontsize="medium")
    return fig


def _cell_edges(centres: np.ndarray) -> np.ndarray:
    """The edges of grid cells centred on sorted ``centres`` (midpoints; the outer
    cells as wide as their neighbours)."""
    if centres.size == 1:
        return np.array([centres[0] - 0.5, centres[0] + 0.5])
    mid = (centres[1:] + centres[:-1]) / 2
    return np.concatenate(([2 * centres[0] - mid[0]], mid, [2 * centres[-1] - mid[-1]]))


def _impossible_handle(missing: Mapping[str, int]) -> Patch:
    from matplotlib.patches import Patch

    return Patch(facecolor="white", edgecolor=IMPOSSIBLE_COLOR, hatch=HATCH,
                 label=f"no value: {_counted(missing)}")


def plot_scatter(frame: pd.DataFrame, quantity: str, parameters: Sequence[str],
                 ax: Axes | None = None, units: Mapping[str, str] | None = None,
                 nominal: Mapping[str, float] | None = None) -> Figure:
    """One quantity against each varied parameter, side by side.

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

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D

    if ax is not None and len(parameters) != 1:
        raise AnalysisError("a scatter plot of several parameters needs its own figure")
    columns = min(len(parameters), 3)
    rows = -(-len(parameters) // 3)
    if ax is not None:
        fig, axes = _figure_of(ax), [ax]
    else:
        fig = _new_figure(figsize=(4.3 * columns + 0.6, 3.9 * rows + 0.7), layout="constrained")
        axes = fig.subplots(rows, columns, squeeze=False).ravel()
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
    handles: list[Artist] = [Line2D([], [], ls="", marker=".", color="#4477aa",
                                    label="sample")]
    for a, name in zip(axes, parameters):
        x = np.asarray(frame[name], dtype=float)[::step]
        a.plot(x[~bad], y[~bad], ".", markersize=3, alpha=0.45, color="#4477aa")
        if log:
            a.set_yscale("log")
        if bad.any():
            a.axhspan(below[0], below[2], facecolor="white", edgecolor=IMPOSSIBLE_COLOR,
                      hatch=HATCH, linewidth=0)
            a.plot(x[bad], np.full(int(bad.sum()), below[1]), "x", markersize=3,
                   color=IMPOSSIBLE_COLOR)
        if nominal and name in nominal:
            a.axvline(nominal[name], color="#cc3311", linewidth=1.0, linestyle="--")
        a.set_xlabel(axis_label(name, units))
        a.set_ylabel(axis_label(quantity, units))
        a.grid(True, alpha=0.3)
    if bad.any():
        handles.append(_impossible_handle(missing))
    if nominal and any(name in nominal for name in parameters):
        handles.append(Line2D([], [], color="#cc3311", ls="--", label="nominal design"))
    for a in axes[len(parameters):]:
        a.set_visible(False)
    if ax is None:
        fig.legend(handles=handles, loc="outside lower center", ncols=len(handles),
                   frameon=False, fontsize="small")
    else:
        ax.legend(handles=handles, fontsize="small")
    return fig


def plot_sobol(indices: Mapping[str, Any], quantity: str, ax: Axes | None = None,
               units: Mapping[str, str] | None = None) -> Figure:
    """First-order and total Sobol indices of one quantity, with 95 % intervals.

    Parameters
    ----------
    indices : mapping
        The entry of :func:`resonant.studies.sobol_indices` for the quantity.
    quantity : str
    ax : matplotlib Axes, optional
    units : mapping, optional
        column -> unit (:func:`study_units`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, figsize=(6.4, 4.4))
    names = list(indices["parameters"])
    x = np.arange(len(names))
    for offset, key, color, label in ((-0.18, "S1", "#4477aa", "first order"),
                                      (0.18, "ST", "#ee7733", "total")):
        ax.bar(x + offset, _numbers(indices[key]), width=0.36,
               yerr=_numbers(indices[f"{key}_conf"]),
               color=color, label=label, capsize=3)
    ax.set_xticks(x, [math_name(n) for n in names])
    ax.set_ylim(min(0.0, ax.get_ylim()[0]), max(1.05, ax.get_ylim()[1]))
    ax.axhline(0, color="black", linewidth=0.6)
    ax.set_ylabel("Sobol index")
    ax.set_title(f"sensitivity of {axis_label(quantity, units)}" + (f" ({indices['note']})"
                                                 if indices.get("note") else ""),
                 fontsize="medium")
    ax.legend(frameon=False, fontsize="small")
    return fig


def _numbers(values: Iterable[float | None]) -> np.ndarray:
    """Indices as numbers, NaN where there are none (None)."""
    return np.array([math.nan if v is None else v for v in values], dtype=float)


def plot_contour(frame: pd.DataFrame, quantity: str, x: str, y: str, ax: Axes | None = None,
                 units: Mapping[str, str] | None = None,
                 nominal: Mapping[str, float] | None = None) -> Figure:
    """A quantity over a two-parameter grid, one coloured cell per grid point.

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
    ax : matplotlib Axes, optional
    units : mapping, optional
        column -> unit (:func:`study_units`).
    nominal : mapping, optional
        parameter -> its nominal value.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import LogNorm
    from matplotlib.lines import Line2D

    fig, ax = _axes(ax, figsize=(6.6, 5.4), layout="constrained")
    table = frame.pivot_table(index=y, columns=x, values=quantity, aggfunc="first",
                              dropna=False)
    grid = np.asarray(table.to_numpy(dtype=float))
    xs, ys = table.columns.to_numpy(dtype=float), table.index.to_numpy(dtype=float)
    positive = grid[np.isfinite(grid) & (grid > 0)]
    log = spans_decades(grid.ravel())
    norm = LogNorm(positive.min(), positive.max()) if log else None
    missing = _without_value(frame, quantity)
    xe, ye = _cell_edges(xs), _cell_edges(ys)
    if missing:  # the hatch shows through the cells without a value
        ax.fill_between([xe[0], xe[-1]], ye[0], ye[-1], facecolor="white",
                        edgecolor=IMPOSSIBLE_COLOR, hatch=HATCH, linewidth=0, zorder=0)
    cells = ax.pcolormesh(xe, ye, np.ma.masked_invalid(grid), cmap="viridis", norm=norm,
                          shading="flat", zorder=1)
    fig.colorbar(cells, ax=ax, label=axis_label(quantity, units)
                 + (" (log scale)" if log else ""))
    handles: list[Artist] = []
    if missing:
        handles.append(_impossible_handle(missing))
    if nominal and x in nominal and y in nominal:
        ax.plot([nominal[x]], [nominal[y]], "*", color="white", markersize=14,
                markeredgecolor="black", zorder=3)
        handles.append(Line2D([], [], ls="", marker="*", color="white", markeredgecolor="black",
                              markersize=11, label="nominal design"))
    ax.set_xlim(xe[0], xe[-1])
    ax.set_ylim(ye[0], ye[-1])
    ax.set_xlabel(axis_label(x, units))
    ax.set_ylabel(axis_label(y, units))
    if handles:  # under the plot: it hides no cell
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.13),
                  ncols=len(handles), frameon=False, fontsize="small")
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

    def save(fig: Figure, kind: str, quantity: str) -> None:
        path = directory / _file_name(kind, quantity)
        _save(fig, path, dpi=110)
        written.append(path)

    for quantity in quantities:
        save(plot_histogram(frame, quantity, units=units), "histogram", quantity)
        save(plot_scatter(frame, quantity, parameters, units=units, nominal=nominal),
             "scatter", quantity)
        if sensitivity and quantity in sensitivity:
            save(plot_sobol(sensitivity[quantity], quantity, units=units), "sobol", quantity)
        if grid and len(parameters) == 2:
            first, second = parameters
            save(plot_contour(frame, quantity, first, second, units=units, nominal=nominal),
                 "contour", quantity)
    return written


__all__ = ["axis_label", "plot_contour", "plot_histogram", "plot_scatter", "plot_sobol",
           "plot_study", "spans_decades", "study_units"]
