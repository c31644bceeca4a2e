"""Plots of analysis results (matplotlib, Agg backend, imported only when drawing).

Analyses return data; these functions draw it.  Each returns the matplotlib
``Figure`` and, given a ``path``, also writes it (the format follows the
suffix: ``.png``, ``.svg``, ``.pdf``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import hooks
from ..errors import AnalysisError

if TYPE_CHECKING:  # pragma: no cover
    from ..analyses import FrequencyResponse, ModalAnalysis, Simulation

#: at most this many curves are drawn (a 1000-coordinate sweep shows the first ones)
MAX_CURVES = 8
#: at most this many natural frequencies are drawn as vertical lines
MAX_LINES = 30


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: Any) -> None:
    if path is None:
        return
    path = Path(path)
    if path.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise AnalysisError(f"cannot write a plot to '{path}': use a .png, .svg or .pdf file")
    try:
        fig.savefig(path, dpi=150, bbox_inches="tight")
    except OSError as exc:
        raise AnalysisError(f"cannot write the plot '{path}': {exc.strerror or exc}") from None


@hooks.provides("plot_frequency_response")
def plot_frequency_response(response: "FrequencyResponse", path: Any = None,
                            names: Sequence[str] | None = None) -> Any:
    """Amplitude (log axis) above phase, against the swept parameter.

    Resonance peaks are marked with triangles, antiresonances with circles;
    natural frequencies in the range of a frequency sweep are dashed vertical
    lines.  Skipped points (undamped resonance) are gaps.
    """
    plt = _pyplot()
    if names is None:
        names = list(response.names)
        if len(names) > MAX_CURVES:
            outputs = [n for n in names if n not in response.coordinates]
            names = (names[:MAX_CURVES - len(outputs[:MAX_CURVES // 2])]
                     + outputs[:MAX_CURVES // 2])
    unknown = [n for n in names if n not in response.amplitudes]
    if unknown:
        raise AnalysisError(f"nothing to plot named {', '.join(unknown)}")
    x = response.values
    fig, (ax_amp, ax_phase) = plt.subplots(
        2, 1, sharex=True, figsize=(8, 6.5), gridspec_kw={"height_ratios": [2.2, 1]})
    unit = f" [{response.unit}]" if response.unit else ""
    label_x = ("excitation frequency " if response.frequency_sweep else "") + \
        f"{response.parameter}{unit}"
    colors = plt.rcParams["axes.prop_cycle"].by_key().get("color", ["C0"])
    peaks_by_name: dict[str, list] = {}
    for p in response.peaks:
        peaks_by_name.setdefault(p.name, []).append(p)
    dips_by_name: dict[str, list] = {}
    for p in response.antiresonances:
        dips_by_name.setdefault(p.name, []).append(p)
    any_positive = False
    labelled: list[float] = []
    for k, name in enumerate(names):
        color = colors[k % len(colors)]
        amplitude = np.array(response.amplitudes[name], dtype=float)
        shown = np.where(amplitude > 0, amplitude, np.nan)  # log axis: no zeros
        any_positive = any_positive or bool(np.any(np.isfinite(shown)))
        kind = "" if name in response.coordinates else " (output)"
        ax_amp.plot(x, shown, color=color, lw=1.5, label=f"{name}{kind}")
        phase = np.degrees(np.array(response.phases[name], dtype=float))
        # break the curve where the phase wraps from -180 to +180 degrees
        wraps = np.nonzero(np.abs(np.diff(phase)) > 180)[0] + 1
        ax_phase.plot(np.insert(x, wraps, np.nan), np.insert(phase, wraps, np.nan),
                      color=color, lw=1.2)
        for p in peaks_by_name.get(name, [])[:20]:
            ax_amp.plot([p.value], [p.amplitude], "v", color=color, ms=7, mec="black", mew=0.6)
            # one label per resonance: curves peaking at nearly the same value share it
            if all(abs(p.value - v) > 0.06 * abs(v) for v in labelled):
                labelled.append(p.value)
                ax_amp.annotate(f"{p.value:.4g}", (p.value, p.amplitude),
                                textcoords="offset points", xytext=(0, 7), ha="center",
                                fontsize=8, color=color)
        for p in dips_by_name.get(name, [])[:20]:
            if p.amplitude > 0:
                ax_amp.plot([p.value], [p.amplitude], "o", mfc="white", color=color, ms=6)
            else:
                ax_amp.axvline(p.value, color=color, lw=0.8, ls=":")
    if response.frequency_sweep and response.natural_frequencies is not None:
        lo, hi = float(np.min(x)), float(np.max(x))
        inside = [w for w in response.natural_frequencies if lo <= w <= hi][:MAX_LINES]
        for j, w in enumerate(inside):
            for ax in (ax_amp, ax_phase):
                ax.axvline(w, color="0.45", lw=0.9, ls="--",
                           label="natural frequency" if (j == 0 and ax is ax_amp) else None)
    if any_positive:
        ax_amp.set_yscale("log")
    ax_amp.set_ylabel("amplitude (peak of the stationary response)")
    ax_amp.grid(True, which="both", alpha=0.3)
    marker_handles = [plt.Line2D([], [], ls="", marker="v", color="0.3", mec="black",
                                 label="resonance peak"),
                      plt.Line2D([], [], ls="", marker="o", mfc="white", color="0.3",
                                 label="antiresonance")]
    handles, labels = ax_amp.get_legend_handles_labels()
    ax_amp.legend(handles + marker_handles, labels + [h.get_label() for h in marker_handles],
                  fontsize=8, loc="best", ncol=2)
    ax_phase.set_ylabel("phase delta [deg]")
    ax_phase.set_yticks([-180, -90, 0, 90, 180])
    ax_phase.set_ylim(-190, 190)
    ax_phase.grid(True, alpha=0.3)
    ax_phase.set_xlabel(label_x)
    if response.log:
        ax_phase.set_xscale("log")
    title = response.title or "frequency response"
    ax_amp.set_title(f"{title}\nx = X sin({'omega' if response.frequency_sweep else 'w'} t "
                     "+ delta)", fontsize=10)
    fig.tight_layout()
    _save(fig, path)
    return fig


@hooks.provides("plot_modes")
def plot_modes(analysis: "ModalAnalysis", path: Any = None, count: int | None = 6) -> Any:
    """The mode shapes (largest component +1): bars for few coordinates, lines for many."""
    plt = _pyplot()
    shapes = analysis.mode_shapes
    total = shapes.shape[1]
    if total == 0:
        raise AnalysisError("there are no modes with omega^2 >= 0 to plot")
    count = total if count is None else max(1, min(count, total))
    columns = 2 if count > 1 else 1
    rows = math.ceil(count / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 2.4 * rows), squeeze=False)
    n = shapes.shape[0]
    positions = np.arange(1, n + 1)
    for j in range(rows * columns):
        ax = axes[j // columns][j % columns]
        if j >= count:
            ax.set_visible(False)
            continue
        shape = shapes[:, j]
        if n <= 24:
            ax.bar(positions, shape, color=np.where(shape >= 0, "C0", "C3"), width=0.6)
            ax.set_xticks(positions)
            ax.set_xticklabels(analysis.coordinates, fontsize=8,
                               rotation=0 if n <= 8 else 90)
        else:
            ax.plot(positions, shape, color="C0", lw=1.2)
            ax.set_xlabel("coordinate number", fontsize=8)
        ax.axhline(0, color="black", lw=0.6)
        ax.set_ylim(-1.15, 1.15)
        w = analysis.natural_frequencies[j]
        text = f"mode {j + 1}: omega = {w:.5g} rad/s ({w / (2 * math.pi):.4g} Hz)"
        if analysis.proportional_damping and analysis.damped and j < len(analysis.damping_ratios):
            text += f", zeta = {analysis.damping_ratios[j]:.3g}"
        ax.set_title(text, fontsize=9)
        ax.grid(True, axis="y", alpha=0.3)
    fig.suptitle((analysis.title or "mode shapes") + " (largest component +1)", fontsize=10)
    fig.tight_layout()
    _save(fig, path)
    return fig


@hooks.provides("plot_simulation")
def plot_simulation(sim: "Simulation", path: Any = None) -> Any:
    """Deviations vs time, one panel per coordinate/output, the linear prediction dashed.

    Parameters
    ----------
    sim : Simulation
    path : str or Path, optional
        Save the figure there (format from the suffix).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    names = sim.names
    fig = Figure(figsize=(9, 1.2 + 2.1 * len(names)), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
    kind = "nonlinear" if sim.nonlinear else "linear"
    for ax, name in zip(axes, names):
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
        ax.set_title(f"{name}: {text}", fontsize=9, loc="left")
        kindof = "coordinate" if name in sim.coordinates else "output"
        ax.set_ylabel(f"{name} ({kindof}, deviation)", fontsize=9)
        ax.grid(True, lw=0.4, alpha=0.6)
    axes[-1].set_xlabel("t (s)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", fontsize=9, ncols=3,
               frameon=False)
    start = {"rest": "from rest", "stationary": "from the stationary initial state",
             "given": "from the given initial state"}[sim.start]
    fig.suptitle(f"{sim.title or 'simulation'} — {kind}, {start}", fontsize=11)
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig

__all__ = ["plot_frequency_response", "plot_modes"]
