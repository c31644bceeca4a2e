"""Pictures of a study: histograms, scatter plots, Sobol indices, a contour map.

Each ``plot_*`` function draws on ``ax`` (a new figure without one) and
returns the Figure; :func:`plot_study` writes all that fit a study into a
directory.  Failed samples (NaN) are left out and counted in the titles.

Examples
--------
>>> import numpy as np, pandas as pd
>>> frame = pd.DataFrame({"k": np.linspace(1, 2, 50), "f": np.linspace(1, 2, 50) ** 0.5})
>>> fig = plot_histogram(frame, "f")
>>> fig.axes[0].get_xlabel()
'f'
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import AnalysisError
from .plotting import _figure_of, _new_figure, _save

#: at most this many points in a scatter plot (an even subsample of the rest)
MAX_SCATTER = 20_000


def _axes(ax: Any, **figure: Any) -> tuple[Any, Any]:
    if ax is not None:
        return _figure_of(ax), ax
    fig = _new_figure(**figure)
    return fig, fig.add_subplot()


def _finite(frame: Any, name: str) -> np.ndarray:
    values = np.asarray(frame[name], dtype=float)
    return values[np.isfinite(values)]


def plot_histogram(frame: Any, quantity: str, ax: Any = None) -> Any:
    """The distribution of one quantity.

    Parameters
    ----------
    frame : pandas.DataFrame
    quantity : str
        A column.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, figsize=(6, 4))
    values = _finite(frame, quantity)
    missing = len(frame) - values.size
    bins = int(np.clip(np.sqrt(values.size), 10, 100)) if values.size else 10
    ax.hist(values, bins=bins, color="#4477aa", edgecolor="white", linewidth=0.4)
    if values.size:
        ax.axvline(values.mean(), color="#cc3311", linewidth=1.2, label="mean")
        for q in np.quantile(values, [0.05, 0.95]):
            ax.axvline(q, color="#cc3311", linewidth=0.8, linestyle="--")
        ax.legend(["mean", "5 % and 95 %"], fontsize="small", frameon=False)
    ax.set_xlabel(quantity)
    ax.set_ylabel("samples")
    ax.set_title(f"{quantity}: {values.size} samples"
                 + (f" ({missing} without a value)" if missing else ""), fontsize="medium")
    return fig


def plot_scatter(frame: Any, quantity: str, parameters: Sequence[str], ax: Any = None) -> Any:
    """One quantity against each varied parameter, side by side.

    Parameters
    ----------
    frame : pandas.DataFrame
    quantity : str
    parameters : sequence of str
        The varied parameters (one panel each).
    ax : matplotlib Axes, optional
        Used for a single parameter only.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if ax is not None and len(parameters) != 1:
        raise AnalysisError("a scatter plot of several parameters needs its own figure")
    if ax is not None:
        fig, axes = _figure_of(ax), [ax]
    else:
        fig = _new_figure(figsize=(3.2 * min(len(parameters), 4) + 0.8,
                                   2.8 * -(-len(parameters) // 4)))
        axes = fig.subplots(-(-len(parameters) // 4), min(len(parameters), 4),
                            squeeze=False).ravel()
    step = max(1, len(frame) // MAX_SCATTER)
    y = np.asarray(frame[quantity], dtype=float)[::step]
    for a, name in zip(axes, parameters):
        x = np.asarray(frame[name], dtype=float)[::step]
        a.plot(x, y, ".", markersize=2, alpha=0.5, color="#4477aa")
        a.set_xlabel(name)
        a.set_ylabel(quantity)
    for a in axes[len(parameters):]:
        a.set_visible(False)
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.18, top=0.92, wspace=0.45,
                        hspace=0.5)
    return fig


def plot_sobol(indices: Mapping[str, Any], quantity: str, ax: Any = None) -> Any:
    """First-order and total Sobol indices of one quantity, with 95 % intervals.

    Parameters
    ----------
    indices : mapping
        The entry of :func:`resonant.studies.sobol_indices` for the quantity.
    quantity : str
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, figsize=(6, 4))
    names = list(indices["parameters"])
    x = np.arange(len(names))
    for offset, key, color, label in ((-0.18, "S1", "#4477aa", "first order"),
                                      (0.18, "ST", "#ee7733", "total")):
        ax.bar(x + offset, _numbers(indices[key]), width=0.36,
               yerr=_numbers(indices[f"{key}_conf"]),
               color=color, label=label, capsize=3)
    ax.set_xticks(x, names)
    ax.set_ylim(min(0.0, ax.get_ylim()[0]), max(1.05, ax.get_ylim()[1]))
    ax.axhline(0, color="black", linewidth=0.6)
    ax.set_ylabel("Sobol index")
    ax.set_title(f"sensitivity of {quantity}" + (f" ({indices['note']})"
                                                 if indices.get("note") else ""),
                 fontsize="medium")
    ax.legend(frameon=False, fontsize="small")
    return fig


def _numbers(values: Any) -> np.ndarray:
    """Indices as numbers, NaN where there are none (None)."""
    return np.array([math.nan if v is None else v for v in values], dtype=float)


def plot_contour(frame: Any, quantity: str, x: str, y: str, ax: Any = None) -> Any:
    """A quantity over a two-parameter grid, as filled contours.

    Parameters
    ----------
    frame : pandas.DataFrame
        The rows of a grid design over ``x`` and ``y``.
    quantity, x, y : str
        Columns.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, figsize=(6, 4.6))
    table = frame.pivot_table(index=y, columns=x, values=quantity, aggfunc="first",
                              dropna=False)
    grid = np.asarray(table.to_numpy(dtype=float))
    filled = ax.contourf(table.columns.to_numpy(dtype=float), table.index.to_numpy(dtype=float),
                         np.ma.masked_invalid(grid), levels=20, cmap="viridis")
    fig.colorbar(filled, ax=ax, label=quantity)
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.set_title(quantity, fontsize="medium")
    return fig


def _file_name(kind: str, quantity: str) -> str:
    return f"{kind}-{re.sub(r'[^A-Za-z0-9_.-]+', '_', quantity)}.png"


def plot_study(frame: Any, parameters: Sequence[str], quantities: Sequence[str],
               directory: str | Path, sensitivity: Mapping[str, Any] | None = None,
               grid: bool = False) -> list[Path]:
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
        A grid design (a contour map for two parameters).

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

    def save(fig: Any, kind: str, quantity: str) -> None:
        path = directory / _file_name(kind, quantity)
        _save(fig, path, dpi=110)
        written.append(path)

    for quantity in quantities:
        save(plot_histogram(frame, quantity), "histogram", quantity)
        save(plot_scatter(frame, quantity, parameters), "scatter", quantity)
        if sensitivity and quantity in sensitivity:
            save(plot_sobol(sensitivity[quantity], quantity), "sobol", quantity)
        if grid and len(parameters) == 2:
            save(plot_contour(frame, quantity, *parameters), "contour", quantity)
    return written


__all__ = ["plot_contour", "plot_histogram", "plot_scatter", "plot_sobol", "plot_study"]
