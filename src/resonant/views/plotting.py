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
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import AnalysisError, printable
from .notation import name_latex
from .units_display import unit_latex

if TYPE_CHECKING:  # pragma: no cover
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


def _new_figure(**options: Any) -> Any:
    """A figure of its own, without pyplot (no backend switch, no figure manager)."""
    from matplotlib.figure import Figure

    return Figure(**options)


def _figure_of(ax: Any) -> Any:
    """The figure an Axes belongs to (the top-level one for a subfigure)."""
    fig = ax.figure
    root = getattr(fig, "get_figure", None)
    if root is not None:
        try:
            return root(root=True)
        except TypeError:  # matplotlib < 3.8: no ``root`` argument
            pass
    return getattr(fig, "figure", fig)


def _check_path(path: Any) -> Path | None:
    if path is None:
        return None
    path = Path(path)
    if path.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise AnalysisError(f"cannot write a plot to '{path}': use a .png, .svg or .pdf file")
    return path


def _save(fig: Any, path: Any, **options: Any) -> None:
    """Write ``fig`` to ``path`` (nothing for None), attaching an Agg canvas if it has none."""
    path = _check_path(path)
    if path is None:
        return
    from matplotlib.backend_bases import FigureCanvasBase
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if type(fig.canvas) is FigureCanvasBase:  # a bare Figure: give it a canvas to print on
        FigureCanvasAgg(fig)
    try:
        fig.savefig(path, **options)
    except OSError as exc:
        raise AnalysisError(f"cannot write the plot '{path}': {exc.strerror or exc}") from None


def plot_frequency_response(response: FrequencyResponse, path: Any = None,
                            names: Sequence[str] | None = None, ax: Any = None,
                            units: Mapping[str, str] | None = None) -> Figure:
    """Amplitude (log axis) above phase, against the swept parameter.

    Resonance peaks are marked with triangles, antiresonances with circles;
    natural frequencies in the range of a frequency sweep are dashed vertical
    lines.  Skipped points (undamped resonance) are gaps.

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
        :mod:`resonant.views.units_display`): the amplitude axis is labelled with the
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
    import matplotlib

    _check_path(path)
    names = _curve_names(response, names)
    fig, ax_amp, ax_phase = _response_axes(ax)
    panels = [a for a in (ax_amp, ax_phase) if a is not None]
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key().get("color", ["C0"])
    amplitude_units = {units.get(n, "") for n in names} if units else set()
    per_curve = units if len(amplitude_units) > 1 else None
    floor, top = _amplitude_floor(response, names)
    labelled: list[float] = []
    any_positive = False
    for k, name in enumerate(names):
        color = colors[k % len(colors)]
        any_positive |= _draw_curve(response, name, color, floor, ax_amp, ax_phase, per_curve)
        _mark_peaks(response, name, color, floor, ax_amp, labelled)
    _mark_natural(response, panels, ax_amp)
    if any_positive:
        ax_amp.set_yscale("log")
        if floor > 0 and top > 0:  # clipped to the sampled data, room above for the labels
            ax_amp.set_ylim(floor / 1.5, top * (top / floor) ** 0.12 * 1.5)
    _label_response_axes(response, panels, ax_amp, ax_phase, amplitude_units, own=ax is None)
    if ax is None:
        fig.tight_layout()
    _save(fig, path, dpi=150, bbox_inches="tight")
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


def _response_axes(ax: Any) -> tuple[Any, Any, Any]:
    """(figure, amplitude axes, phase axes or None): new, or the caller's ``ax=``."""
    if ax is None:
        fig = _new_figure(figsize=(9.5, 6.5))
        ax_amp, ax_phase = fig.subplots(2, 1, sharex=True,
                                        gridspec_kw={"height_ratios": [2.2, 1]})
        return fig, ax_amp, ax_phase
    if isinstance(ax, (tuple, list)) or (isinstance(ax, np.ndarray) and ax.ndim == 1):
        if len(ax) != 2:
            raise AnalysisError("ax= takes a pair of Axes (amplitude, phase) or one Axes "
                                "(amplitude only)")
        return _figure_of(ax[0]), ax[0], ax[1]
    return _figure_of(ax), ax, None


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


def _draw_curve(response: FrequencyResponse, name: str, color: str, floor: float,
                ax_amp: Any, ax_phase: Any, units: Mapping[str, str] | None) -> bool:
    """One name's amplitude (and phase) curve; True if it has a positive amplitude."""
    x = response.values
    amplitude = np.array(response.amplitudes[name], dtype=float)
    shown = np.where(amplitude > 0, np.maximum(amplitude, floor), np.nan)  # log: no zeros
    kind = "" if name in response.coordinates else " (output)"
    if units and units.get(name) not in (None, "", "1"):
        kind += f" [{unit_math(units[name])}]"
    ax_amp.plot(x, shown, color=color, lw=1.5, label=f"{math_name(name)}{kind}")
    if ax_phase is not None:
        ax_phase.plot(x, unwrapped_degrees(response.phases[name]), color=color, lw=1.2)
    return bool(np.any(np.isfinite(shown)))


def unwrapped_degrees(phase: Any) -> np.ndarray:
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


def _mark_peaks(response: FrequencyResponse, name: str, color: str, floor: float,
                ax_amp: Any, labelled: list[float]) -> None:
    """Triangles on the resonance peaks (labelled once per resonance), circles on the
    antiresonances (at the plotted floor for a true zero)."""
    for p in [p for p in response.peaks if p.name == name][:20]:
        ax_amp.plot([p.value], [p.amplitude], "v", color=color, ms=7, mec="black", mew=0.6)
        # one label per resonance: curves peaking at nearly the same value share it
        if all(abs(p.value - v) > 0.06 * abs(v) for v in labelled):
            labelled.append(p.value)
            # above the curves (in the headroom the axis leaves over the highest peak),
            # on a white ground: no curve crosses it
            ax_amp.annotate(f"{p.value:.4g}", (p.value, 1.0), xycoords=("data", "axes fraction"),
                            textcoords="offset points", xytext=(0, -3), ha="center", va="top",
                            fontsize=8, color=color, zorder=5,
                            bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none",
                                  "alpha": 0.9})
    for p in [p for p in response.antiresonances if p.name == name][:20]:
        ax_amp.plot([p.value], [max(p.amplitude, floor)], "o", mfc="white", color=color, ms=6)


def _mark_natural(response: FrequencyResponse, panels: Sequence[Any], ax_amp: Any) -> None:
    """Dashed vertical lines at the natural frequencies inside the range."""
    natural = response.natural_values
    if natural is None:
        return
    x = response.values
    lo, hi = float(np.min(x)), float(np.max(x))
    inside = [w for w in natural if lo <= w <= hi][:MAX_LINES]
    what = "natural frequency" if response.frequency_sweep else \
        "excitation at a natural frequency"
    for j, w in enumerate(inside):
        for panel in panels:
            panel.axvline(w, color="0.45", lw=0.9, ls="--",
                          label=what if (j == 0 and panel is ax_amp) else None)


def _label_response_axes(response: FrequencyResponse, panels: Sequence[Any], ax_amp: Any,
                         ax_phase: Any, amplitude_units: set[str], own: bool = False) -> None:
    """Axis labels, grids, the legend (with the marker kinds) and the title."""
    from matplotlib.lines import Line2D

    shown_units = [unit_math(u) if u not in ("", "1") else "1" for u in sorted(amplitude_units)]
    ax_amp.set_ylabel("amplitude $X$" + (f" [{', '.join(shown_units)}]"
                                         if shown_units and shown_units != ["1"] else ""))
    ax_amp.grid(True, which="both", alpha=0.3)
    marker_handles = [Line2D([], [], ls="", marker="v", color="0.3", mec="black",
                             label="resonance peak")] if response.peaks else []
    if response.antiresonances:
        marker_handles.append(Line2D([], [], ls="", marker="o", mfc="white", color="0.3",
                                     label="antiresonance (zero)"))
    handles, labels = ax_amp.get_legend_handles_labels()
    # beside the plot (own figure): it never hides a curve or a peak's label
    beside = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0} \
        if own else {"loc": "best"}
    ax_amp.legend(handles + marker_handles, labels + [h.get_label() for h in marker_handles],
                  fontsize=8, ncol=1, **beside)
    if ax_phase is not None:
        ax_phase.set_ylabel(r"phase $\delta$ [°]")
        low, high = ax_phase.get_ylim()
        first, last = 90 * math.floor(low / 90), 90 * math.ceil(high / 90)
        if last - first < 180:
            first, last = first - 90, last + 90
        step = 90 * max(1, math.ceil((last - first) / 90 / 8))
        ax_phase.set_yticks(np.arange(first, last + 1, step))
        ax_phase.set_ylim(first - 10, last + 10)
        ax_phase.grid(True, alpha=0.3)
    unit = f" [{response.unit}]" if response.unit else ""
    panels[-1].set_xlabel(("excitation frequency " if response.frequency_sweep else "")
                          + f"{math_name(response.parameter)}{unit}")
    if response.log:
        for panel in panels:
            panel.set_xscale("log")
    title = printable(response.title or "frequency response", limit=80)
    ax_amp.set_title(f"{title}\n" + r"$x = X \sin(\omega t + \delta)$", fontsize=10)


def plot_modes(analysis: ModalAnalysis, path: Any = None, count: int | None = 6,
               ax: Any = None) -> Figure:
    """The mode shapes (largest component +1): bars for few coordinates, lines for many.

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
    _check_path(path)
    shapes = analysis.mode_shapes
    total = shapes.shape[1]
    if total == 0:
        raise AnalysisError("there are no modes with omega^2 >= 0 to plot")
    count = total if count is None else max(1, min(count, total))
    if ax is None:
        columns = 2 if count > 1 else 1
        rows = math.ceil(count / columns)
        fig = _new_figure(figsize=(4.9 * columns, 2.5 * rows))
        panels = list(fig.subplots(rows, columns, squeeze=False).ravel())
        for extra in panels[count:]:
            extra.set_visible(False)
        panels = panels[:count]
    else:
        panels = list(np.ravel(np.asarray(ax, dtype=object)))[:count]
        if not panels:
            raise AnalysisError("ax= takes an Axes or a non-empty sequence of Axes")
        fig = _figure_of(panels[0])
    for j, panel in enumerate(panels):
        _draw_mode(panel, analysis, j)
    if ax is None:
        fig.suptitle(printable(analysis.title or "mode shapes", limit=80)
                     + " (largest component +1)",
                     fontsize=10)
        fig.tight_layout()
    _save(fig, path, dpi=150, bbox_inches="tight")
    return fig


def _draw_mode(ax: Any, analysis: ModalAnalysis, j: int) -> None:
    """Mode ``j`` (0-based) on one Axes: bars for up to 24 coordinates, else a line."""
    shape = analysis.mode_shapes[:, j]
    n = shape.shape[0]
    positions = np.arange(1, n + 1)
    if n <= 24:
        ax.bar(positions, shape, color=np.where(shape >= 0, "C0", "C3"), width=0.6)
        ax.set_xticks(positions)
        ax.set_xticklabels([math_name(c) for c in analysis.coordinates], fontsize=10,
                           rotation=0 if n <= 8 else 90)
    else:
        ax.plot(positions, shape, color="C0", lw=1.2)
        ax.set_xlabel("coordinate number", fontsize=10)
    ax.axhline(0, color="black", lw=0.6)
    ax.set_ylim(-1.15, 1.15)
    w = analysis.natural_frequencies[j]
    text = (f"mode {j + 1}: $\\omega_{{{j + 1}}}$ = {w:.5g} rad/s "
            f"($f_{{{j + 1}}}$ = {w / (2 * math.pi):.4g} Hz)")
    if analysis.proportional_damping and analysis.damped and j < len(analysis.damping_ratios):
        text += f", $\\zeta_{{{j + 1}}}$ = {analysis.damping_ratios[j]:.3g}"
    ax.set_title(text, fontsize=10)
    ax.tick_params(axis="y", labelsize=10)
    ax.grid(True, axis="y", alpha=0.3)


def plot_simulation(sim: Simulation, path: Any = None, axes: Any = None,
                    units: Mapping[str, str] | None = None) -> Figure:
    """Deviations vs time, one panel per coordinate/output, the linear prediction dashed.

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
    _check_path(path)
    names = sim.names
    own = axes is None
    if own:
        fig = _new_figure(figsize=(9, 1.2 + 2.1 * len(names)), layout="constrained")
        panels = list(fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0])
    else:
        panels = list(np.ravel(np.asarray(axes, dtype=object)))
        if not panels:
            raise AnalysisError("axes= takes an Axes or a non-empty sequence of Axes")
        fig = _figure_of(panels[0])
    kind = "nonlinear" if sim.nonlinear else "linear"
    for ax, name in zip(panels, names):
        ax.plot(sim.t, sim.states[name], lw=1.0, color="C0", label=f"{kind} simulation")
        if name in sim.linear_response:
            ax.plot(sim.t, sim.linear_response[name], "--", lw=1.0, color="C3",
                    label="linear stationary prediction")
        ax.axvspan(*sim.window, color="0.9", zorder=0, label="amplitude window")
        steady = sim.steady_amplitudes.get(name)
        text = f"steady amplitude {steady:.4g}" if steady is not None else ""
        if name in sim.linear_amplitudes:
            text += f", linear {sim.linear_amplitudes[name]:.4g}"
        if name in sim.relative_difference:
            text += f" ({100 * sim.relative_difference[name]:+.3g}%)"
        ax.set_title(f"{math_name(name)}: {text}", fontsize=9, loc="left")
        kindof = "coordinate" if name in sim.coordinates else "output"
        unit = (units or {}).get(name, "")
        unit = f" [{unit}]" if unit not in ("", "1") else ""
        ax.set_ylabel(f"{math_name(name)}{unit} ({kindof}, deviation)", fontsize=9)
        ax.grid(True, lw=0.4, alpha=0.6)
    panels[min(len(panels), len(names)) - 1].set_xlabel("time $t$ [s]")
    if own:
        handles, labels = panels[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside lower center", fontsize=9, ncols=3,
                   frameon=False)
        start = {"rest": "from rest", "stationary": "from the stationary initial state",
                 "given": "from the given initial state"}[sim.start]
        title = printable(sim.title or "simulation", limit=80)
        fig.suptitle(f"{title} — {kind}, {start}", fontsize=11)
    else:
        panels[0].legend(fontsize=8, loc="best")
    _save(fig, path, dpi=120)
    return fig


__all__ = ["plot_frequency_response", "plot_modes", "plot_simulation", "math_name",
           "unit_math", "unwrapped_degrees", "MAX_CURVES", "MAX_LINES"]
