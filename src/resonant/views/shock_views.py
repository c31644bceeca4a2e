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

from typing import Any

import numpy as np

from ..analyses.shock import ShockSpectrum
from .plotting import _figure_of, _new_figure, _save

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


def plot_srs(spectrum: ShockSpectrum, time: Any = None, signal: Any = None, path: Any = None,
             ax: Any = None, unit: str = "") -> Any:
    """The SRS (maximax, primary, residual) on log-log axes, with the input's history.

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
    with_signal = time is not None and signal is not None
    if ax is None:
        fig = _new_figure(figsize=(7.5, 6.4 if with_signal else 4.2), layout="constrained")
        axes = list(np.atleast_1d(fig.subplots(2 if with_signal else 1, 1)))
    else:
        axes = list(np.atleast_1d(ax))
        fig = _figure_of(axes[0])
    label = f" [{unit}]" if unit else ""
    if with_signal and len(axes) > 1:
        axes[0].plot(np.asarray(time), np.asarray(signal), lw=1.0)
        axes[0].set_xlabel("time [s]")
        axes[0].set_ylabel(f"input{label}")
        axes[0].set_title("input history", fontsize=10)
        axes[0].grid(True, lw=0.3)
    target = axes[-1]
    f = spectrum.frequency
    target.loglog(f, spectrum.maximax, lw=1.6, label="maximax")
    target.loglog(f, spectrum.primary, lw=1.0, ls="--", label="primary")
    target.loglog(f, spectrum.residual, lw=1.0, ls=":", label="residual")
    zeta = spectrum.damping
    q = "inf" if zeta == 0 else f"{1 / (2 * zeta):.3g}"
    target.set_title(f"shock response spectrum ({spectrum.quantity}, Q = {q})", fontsize=10)
    target.set_xlabel("natural frequency [Hz]")
    target.set_ylabel(f"{spectrum.quantity}{label}")
    target.grid(True, which="both", lw=0.3)
    target.legend(fontsize=8)
    _save(fig, path, dpi=150)
    return fig


__all__ = ["srs_text", "plot_srs"]
