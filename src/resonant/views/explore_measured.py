"""Measured FRFs on the explore page: the points the page draws over its frequency response
(``resonant explore MODEL --test FILE.uff``, docs/explore.md).

The page's curve is the amplitude of each coordinate or output against the excitation
frequency's parameter, under the model's own load.  A measured FRF H of a channel (its
quantity's derivative d, ``[measurement.channels]``) becomes the amplitude of that
quantity under the same load at the file's parameter values:

    |x(f)| = |H(f)| / (2 pi f)^d * |x_model(f)| / |H_model(f) / (2 pi f)^d|

the model's amplitude over its own FRF being the load's amplitude at f (F0 for
``F0*sin(omega*t)``; m e omega^2 for an unbalance).  Lines where the model's FRF is zero
(below 1e-12 of its largest) or the response has no amplitude are left out.  This
supposes that the model's load is the measured input; with several inputs the FRFs to the
first are drawn.  The points stay where they are as the sliders move: the measurement does
not change.

Examples
--------
>>> import resonant
>>> from resonant.analyses.frf_update import model_frf_matrix
>>> from resonant.analyses.measured_match import MatchedTest
>>> model = resonant.load("examples/chain3_lab.toml")
>>> system = model.linearize()
>>> f = np.array([1.0, 3.0])
>>> H = model_frf_matrix(system, ["F"], f, model.measurement_section.channels)
>>> test = MatchedTest("lab.uff", f, 2 * H, H, ("d1", "d2", "d3"), ("hammer",),
...                    ("m/N",) * 3, (2.24, 9.07))
>>> data = measured_overlay(test, model, system, "omega")
>>> data["values"] == [2 * np.pi, 6 * np.pi], data["channels"]["x3"]
(True, 'd3')
>>> ratio = np.array(data["curves"]["x3"]) / np.abs(H[:, 2, 0])   # 2 |H| F0, F0 = 10 N
>>> [round(float(r), 9) for r in ratio]
[20.0, 20.0]
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analyses.measured_match import MatchedTest
from ..analyses.sweep import sweep
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem
from ..model import Model
from ..system.base import LinearSystem

__all__ = ["measured_overlay", "measured_first"]

#: the model's |H| below this fraction of its largest: an antiresonance, no scale there
ZERO_FRF = 1e-12


def _omega_per_value(system: LinearSystem, frequency: str, value: float,
                     deadline: Deadline) -> float:
    """The excitation's angular frequency per unit of the frequency parameter (the page's
    abscissa), from the model's harmonic at its value."""
    probe = sweep(system, frequency, [value if value > 0 else 1.0], deadline=deadline)
    omegas = np.asarray(probe.harmonic_omegas)[:, 0]
    if omegas.size != 1 or not omegas[0] > 0:
        raise ModelError(Problem("measured FRFs are drawn over the frequency response of one "
                                 f"excitation frequency; this model has {omegas.size}",
                                 system.source, "measurement"))
    return float(omegas[0]) / (value if value > 0 else 1.0)


def measured_overlay(test: MatchedTest, model: Model, system: LinearSystem,
                     frequency: str | None, deadline: Deadline = NO_DEADLINE
                     ) -> dict[str, Any] | None:
    """The measured points of the page's frequency response (JSON-ready).

    Parameters
    ----------
    test : MatchedTest
        Measured FRFs checked against the model
        (:func:`resonant.analyses.measured_match.match_test`).
    model : Model
    system : LinearSystem
    frequency : str or None
        The page's excitation frequency parameter (None: the page has no curve).
    deadline : Deadline, optional

    Returns
    -------
    dict or None
        ``source``, ``values`` (the parameter at each line, SI), ``curves`` (quantity ->
        amplitude at each line, SI; null where left out), ``channels`` (quantity -> its
        channel) and ``input``; None without a frequency parameter.
    """
    if frequency is None:
        return None
    spec = model.measurement_section
    if spec is None:
        return None
    per_value = _omega_per_value(system, frequency, float(model.parameter_values[frequency]),
                                 deadline)
    f = np.asarray(test.frequency, dtype=float)
    keep = f > 0
    values = 2 * np.pi * f[keep] / per_value
    channels: dict[str, tuple[int, str]] = {}
    for r, channel in enumerate(test.responses):
        channels.setdefault(spec.channels[channel].name, (r, channel))
    names = [n for n in channels if n in (*system.coordinates, *model.outputs)]
    response = sweep(system, frequency, values, names=[n for n in names
                                                       if n in system.coordinates],
                     deadline=deadline)
    curves = {}
    for name in names:
        r, channel = channels[name]
        derivative = spec.channels[channel].derivative
        iw = (2 * np.pi * f[keep]) ** derivative
        measured = np.abs(test.measured[keep, r, 0]) / iw
        own = np.abs(test.model[keep, r, 0]) / iw
        amplitude = np.asarray(response.amplitudes[name], dtype=float)
        good = (own > ZERO_FRF * own.max(initial=0.0)) & np.isfinite(amplitude)
        scaled = np.where(good, measured * amplitude / np.where(good, own, 1.0), np.nan)
        curves[name] = [float(y) if np.isfinite(y) else None for y in scaled]
    return {"source": test.source, "values": values.tolist(), "curves": curves,
            "channels": {n: channels[n][1] for n in names}, "input": test.inputs[0]}


def measured_first(test: MatchedTest, model: Model, shown: list[str], most: int) -> list[str]:
    """The page's curves with the measured quantities first (so that their points have a
    curve to be drawn over, the precomputed page's too), then the others shown, at most
    ``most`` or as many as are measured.

    Parameters
    ----------
    test : MatchedTest
    model : Model
        The model, with its ``[measurement]`` section.
    shown : list of str
        The names the page would show.
    most : int

    Returns
    -------
    list of str

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/chain3_lab.toml")
    >>> f = np.array([1.0])
    >>> test = MatchedTest("lab.uff", f, np.ones((1, 1, 1)), np.ones((1, 1, 1)), ("d3",),
    ...                    ("hammer",), ("m/N",), (2.24, 9.07))
    >>> measured_first(test, model, ["x1", "x2", "x3"], 2)
    ['x3', 'x1']
    """
    spec = model.measurement_section
    first = list(dict.fromkeys(spec.channels[c].name for c in test.responses)) \
        if spec is not None else []
    rest = [n for n in shown if n not in first]
    return (first + rest)[:max(most, len(first))]
