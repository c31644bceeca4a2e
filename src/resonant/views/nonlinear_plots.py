"""Plot and text of a nonlinear steady-state sweep (:class:`NonlinearResponse`).

The plot draws the peak amplitude of each coordinate against the parameter:
stable parts solid, unstable parts dashed, special points marked (fold: circle,
period-doubling: square, Neimark-Sacker: diamond, branch: triangle, the peak of a
curve: a star on that curve), and the linear frequency response dotted beside it.
The curves are the coordinates' and the outputs' (``[outputs]``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .plotting import MAX_CURVES, _figure_of, _new_figure, _save, math_name, unit_math

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..analyses.backbone import Backbones
    from ..analyses.nonlinear_response import NonlinearResponse

MARKERS = {"fold": "o", "period-doubling": "s", "neimark-sacker": "D", "branch": "^",
           "peak": "*"}


def plot_nonlinear_response(response: NonlinearResponse, path: Any = None,
                            names: Sequence[str] | None = None, ax: Any = None,
                            linear: bool = True, units: Mapping[str, str] | None = None) -> Figure:
    """Amplitude against the parameter; returns the Figure (and writes it to ``path``).

    ``units`` (name -> SI unit, ``ResultUnits.si``) labels the curves and the axis."""
    if ax is None:
        fig = _new_figure(figsize=(7.5, 4.8), layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = _figure_of(ax)
    chosen = list(names) if names else list(response.amplitudes)[:MAX_CURVES]
    colors = [f"C{i % 10}" for i in range(len(chosen))]
    v = np.asarray(response.values)
    stable = np.asarray(response.stable)
    for name, color in zip(chosen, colors):
        a = np.asarray(response.amplitudes[name])
        unit = (units or {}).get(name, "")
        shown = math_name(name) + (f" [{unit_math(unit)}]" if unit not in ("", "1") else "")
        if linear and response.linear is not None and name in response.linear.amplitudes:
            ax.plot(response.linear.values, response.linear.amplitudes[name], color=color,
                    lw=1.1, alpha=0.6, ls=":", label=f"{shown} (linear)")
        # draw segments of constant stability, joined at the switching points
        start = 0
        first = True
        for i in range(1, v.size + 1):
            if i == v.size or stable[i] != stable[start]:
                stop = min(i + 1, v.size)
                ax.plot(v[start:stop], a[start:stop], color=color,
                        ls="-" if stable[start] else "--", lw=1.6,
                        label=(f"{shown} (harmonic balance, H = {response.harmonics})"
                               if first else None))
                first = False
                start = i
        for point in response.special_points:
            if name in point.amplitudes and point.quantity in (None, name):
                big = point.kind == "peak"
                ax.plot([point.value], [point.amplitudes[name]], MARKERS.get(point.kind, "x"),
                        color="k", mfc="none", ms=10 if big else 7)
    kinds = sorted({p.kind for p in response.special_points})
    for kind in kinds:
        ax.plot([], [], MARKERS.get(kind, "x"), color="k", mfc="none", label=kind)
    ax.plot([], [], color="0.3", ls="--", label="unstable")
    base = np.asarray(response.base_frequencies, dtype=float)
    frequency = base.shape == v.shape and bool(np.allclose(base, v))  # the parameter is ω
    ax.set_xlabel(("excitation frequency " if frequency else "") + math_name(response.parameter)
                  + (" [rad/s]" if frequency else ""))
    shown_units = sorted({(units or {}).get(n, "") for n in chosen} - {"", "1"})
    ax.set_ylabel("peak amplitude $X$ (deviation)"
                  + (f" [{', '.join(unit_math(u) for u in shown_units)}]" if shown_units else ""))
    ax.set_title(response.title or "nonlinear steady state", fontsize=10)
    top = max((float(np.nanmax(response.amplitudes[n])) for n in chosen), default=1.0)
    if top > 0:
        ax.set_ylim(0, 1.15 * top)
    ax.set_xlim(min(response.start, response.stop), max(response.start, response.stop))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    _save(fig, path)
    return fig


def nonlinear_text(response: NonlinearResponse) -> str:
    """Special points and the peak of the stable branch, as plain text."""
    lines = [f"{response.title or 'model'}: nonlinear steady state (harmonic balance, "
             f"H = {response.harmonics}) against {response.parameter} from "
             f"{response.start:g} to {response.stop:g}",
             f"  {response.values.size} branch points, {int(response.stable.sum())} stable; "
             f"largest residual {response.residual:.3g}; highest harmonics carry up to "
             f"{response.truncation:.3g} of the amplitude"]
    if response.special_points:
        lines.append("  special points:")
        for p in response.special_points:
            amps = ", ".join(f"{k} = {v:.10g}" for k, v in p.amplitudes.items())
            kind = f"peak of {p.quantity}" if p.kind == "peak" else p.kind
            if p.stable is False:
                kind += " (unstable)"
            lines.append(f"    {kind:16s} {response.parameter} = {p.value:.10g}   {amps}")
    else:
        lines.append("  no special points (no fold, no change of stability, no peak)")
    top = response.peak()
    if top is not None:
        value, peak_amps = top
        lines.append(f"  peak of the stable branch at {response.parameter} = {value:.6g}: "
                     + ", ".join(f"{k} = {v:.6g}" for k, v in peak_amps.items()))
        if response.linear is not None:
            first = response.coordinates[0]
            lin = np.asarray(response.linear.amplitudes.get(first, []), dtype=float)
            if lin.size and np.isfinite(lin).any():
                lines.append(f"  linear peak of {first}: {float(np.nanmax(lin)):.6g}")
    else:
        lines.append("  no stable point on the branch")
    return "\n".join(lines) + "\n"


def plot_backbones(backbones: Backbones, path: Any = None, ax: Any = None) -> Figure:
    """Backbone curves: the free-vibration frequency (x) against the amplitude of each mode's
    reference coordinate (y), the linear natural frequencies dotted; returns the Figure."""
    if ax is None:
        fig = _new_figure(figsize=(7.0, 4.6), layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = _figure_of(ax)
    for i, curve in enumerate(backbones.curves):
        color = f"C{i % 10}"
        amp = np.concatenate([[0.0], np.asarray(curve.amplitudes[curve.reference])])
        freq = np.concatenate([[curve.linear_frequency], np.asarray(curve.frequencies)])
        ax.plot(freq, amp, color=color, lw=1.6,
                label=f"mode {curve.mode} (amplitude of {math_name(curve.reference)})")
        ax.axvline(curve.linear_frequency, color=color, ls=":", lw=1.0)
    ax.set_xlabel(r"frequency of free vibration $\omega$ [rad/s]")
    ax.set_ylabel("peak amplitude $X$ (deviation)")
    ax.set_title((backbones.title or "backbone curves")
                 + f" (harmonic balance, H = {backbones.harmonics})", fontsize=10)
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    _save(fig, path)
    return fig


__all__ = ["plot_nonlinear_response", "nonlinear_text", "plot_backbones"]
