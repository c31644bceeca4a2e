"""Measured FRFs on the explore page: the points the page draws over its frequency response
(``resonant explore MODEL --test FILE.uff``, docs/explore.md).

The page's curve is the amplitude of each coordinate or output against the excitation
frequency's parameter, under the model's own load: at f, the generalized forces' complex
amplitudes b(f) (:attr:`resonant.system.batch.BatchHarmonic.complex_load`, what the
harmonic kernel solves for).  The measured FRFs H_ij of channel i (its quantity's
derivative d, ``[measurement.channels]``) to each input j become the response to that load
at the file's lines:

    x_i(f) = sum_j H_ij(f) / (2 pi i f)^d * u_j(f)

u_j(f) being input j's complex amplitude in the model's load, phases included (for
``F0*sin(omega*t)`` on the input's coordinate, F0 with a phase of -90 degrees; for an
unbalance m e omega^2): the least-squares u of b(f) = sum_j B_j u_j, B_j the load of a
unit input j (:func:`resonant.analyses.frf_update.input_amplitudes`).  An input where the
model puts no load gets u_j = 0 and adds nothing, except a signal that loads no coordinate
and enters outputs only (feedthrough, ``v = x3 + E/2``): its FRFs are the outputs' direct
terms, and its u_j is the signal's own complex amplitude in the model's harmonic
(:attr:`resonant.system.batch.BatchHarmonic.signals`).  An output with a direct term of a
signal that no input is gets no points (the FRFs do not hold that term), and the
``note`` names it; the others are drawn.  With one input this is
|H(f)| / (2 pi f)^d * |x_model(f)| / |H_model(f) / (2 pi f)^d|, the model's amplitude over
its own FRF.  Where the model loads something that no measured input makes (a force on a
coordinate no input covers, another signal), the measured FRFs cannot give the response
to it: no points are drawn and the returned ``note`` (shown in the page's caption) says
which coordinates it loads.  The points stay where they are as the sliders move: the
measurement does not change.

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

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..analyses.frf_sensitivity import loads_depend_on
from ..analyses.frf_update import input_amplitudes
from ..analyses.measured_match import MatchedTest
from ..analyses.sweep import sweep
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem
from ..model import Model
from ..system.base import LinearSystem
from ..system.batch import BatchHarmonic
from ..system.excitation import excitation_columns_along, loaded_coordinates

__all__ = ["measured_overlay", "measured_first"]

#: the part of the model's load that no measured input makes, relative to the load, above
#: which the measured FRFs cannot give the page's response (rounding is some 1e-16)
UNCOVERED = 1e-9
#: the coordinates named in the note of a load no input makes
SHOWN_COORDINATES = 4


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
        amplitude at each line, SI; null where not finite; empty with a ``note``),
        ``channels`` (quantity -> its channel), ``inputs`` (the excitation channels) and
        ``note`` (None, or why no points are drawn: the model loads what no input makes,
        or an output depends directly on a signal no input is -- that output's points
        left out); None without a frequency parameter.
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
    batch = system.batch(frequency, values, deadline)
    harmonic = batch.harmonics[0]
    load = harmonic.complex_load
    along = _moving_columns(system, frequency, values, spec.model_inputs, deadline)
    u, left, worst = input_amplitudes(system, spec.model_inputs, f[keep], load,
                                      along=along or None, deadline=deadline)
    _through_outputs(u, harmonic, spec.model_inputs,
                     loaded_coordinates(system, spec.model_inputs, deadline))
    note = _uncovered(left, worst, load, system.coordinates, test.inputs)
    if note is not None and along is None:
        note = _moving_note(system, frequency, spec.model_inputs, deadline) or note
    # a load no input makes: no points; an output's direct term no input makes: none of it
    direct = _unmeasured_direct(batch.outputs, harmonic, names, spec.model_inputs)
    drawn = [n for n in names if n not in direct] if note is None else []
    note = note or (_direct_note(direct) if direct else None)
    curves: dict[str, list[float | None]] = {}
    for name in drawn:
        r, channel = channels[name]
        iw = (2j * np.pi * f[keep]) ** spec.channels[channel].derivative
        response = np.abs(np.sum(test.measured[keep, r, :] * u, axis=1) / iw)
        curves[name] = [float(y) if np.isfinite(y) else None for y in response]
    return {"source": test.source, "values": values.tolist(), "curves": curves,
            "channels": {n: channels[n][1] for n in names}, "inputs": list(test.inputs),
            "note": note}


def _moving_columns(system: LinearSystem, frequency: str, values: np.ndarray,
                    inputs: Sequence[str], deadline: Deadline
                    ) -> dict[tuple[str, int], np.ndarray] | None:
    """The signal inputs' excitation columns at each line where they depend on the
    frequency parameter (an input's load that grows with omega): {} where none does;
    None where they cannot be had cheaply (a numerically derived system)."""
    signals = {s for s in inputs if s not in system.coordinates}
    if not signals:
        return {}
    columns = excitation_columns_along(system, frequency, values, deadline)
    if columns is None:
        return None
    # a column the same at every line does not depend on the parameter: it is the one at
    # the model's value, which the fixed columns' path uses
    return {var: c for var, c in columns.items() if var[0] in signals
            and not np.array_equal(c, np.broadcast_to(c[:1], c.shape))}


def _moving_note(system: LinearSystem, frequency: str, inputs: Sequence[str],
                 deadline: Deadline) -> str | None:
    """Where the load of an input depends on the frequency parameter and its columns
    could not be had at each line: what the page says instead of the load's rest."""
    signals = [s for s in inputs if s not in system.coordinates
               and frequency in loads_depend_on(system, [s], [frequency], {}, deadline)]
    if not signals:
        return None
    return (f"no measured points: the load of the input{'s' if len(signals) > 1 else ''} "
            f"{', '.join(signals)} depends on {frequency}, the page's frequency parameter, "
            "and this model's load columns (derived numerically) are known at its value "
            f"only, not at each measured line: give the load's dependence on {frequency} "
            "to the signal instead of its force vector")


def _through_outputs(u: np.ndarray, harmonic: BatchHarmonic, inputs: Sequence[str],
                     acts: Mapping[str, tuple[str, ...]]) -> None:
    """Give each signal input that loads no coordinate (it enters outputs only: their
    direct term) its own complex amplitude in the model's harmonic, in place: there is no
    load to find it in, and without it the outputs' direct terms would be left out."""
    omega = np.asarray(harmonic.omega, dtype=float)
    for j, name in enumerate(inputs):
        if acts.get(name):
            continue
        for (signal, order), (S, C) in sorted(harmonic.signals.items()):
            if signal == name:
                # the (signal, order) variable's amplitude is (i omega)^order times the
                # signal's; the lines have omega > 0
                u[:, j] = (np.asarray(C) - 1j * np.asarray(S)) / (1j * omega) ** order
                break


def _unmeasured_direct(outputs: Mapping[str, tuple[np.ndarray, Mapping[Any, Any]]],
                       harmonic: BatchHarmonic, names: Sequence[str], inputs: Sequence[str]
                       ) -> dict[str, list[str]]:
    """The outputs among ``names`` with a direct term of a signal that no input is (not
    zero at the lines): output -> those signals.  The measured FRFs hold no such term, so
    they cannot give these outputs' response."""
    found: dict[str, list[str]] = {}
    for name in names:
        if name not in outputs:
            continue
        signals = set()
        for var, coefficient in outputs[name][1].items():
            if var not in harmonic.signals or var[0] in inputs:
                continue
            S, C = harmonic.signals[var]
            if np.any(np.abs(coefficient) * np.abs(np.asarray(C) - 1j * np.asarray(S)) > 0):
                signals.add(str(var[0]))
        if signals:
            found[name] = sorted(signals)
    return found


def _direct_note(direct: Mapping[str, list[str]]) -> str:
    """What the page says of outputs left without points (:func:`_unmeasured_direct`)."""
    parts = [f"{name} (through {', '.join(signals)})" for name, signals in direct.items()]
    several = len(direct) > 1
    return (f"no measured points for {'; '.join(parts)}: "
            f"{'these outputs depend' if several else 'the output depends'} directly on a "
            "signal that no measured input is, whose term the FRFs do not hold: map an "
            "input to it ([measurement] input)")


def _uncovered(left: np.ndarray, worst: np.ndarray, load: np.ndarray,
               coordinates: tuple[str, ...], inputs: tuple[str, ...]) -> str | None:
    """What the page says of a model load that no measured input makes (None: none above
    :data:`UNCOVERED` of the load at any line)."""
    if not np.any(left > UNCOVERED):
        return None
    largest = float(np.abs(load).max(initial=0.0))
    loaded = [coordinates[i] for i in np.argsort(-worst, kind="stable")
              if worst[i] > UNCOVERED * largest]
    shown = ", ".join(loaded[:SHOWN_COORDINATES]) + (", ..." if len(loaded)
                                                      > SHOWN_COORDINATES else "")
    return (f"no measured points: the model's load acts on {shown} "
            f"({100 * float(left.max()):.3g} % of it at worst), which the test's input"
            f"{'s' if len(inputs) > 1 else ''} ({', '.join(inputs)}) do"
            f"{'' if len(inputs) > 1 else 'es'} not make, so its FRFs cannot give the "
            "response to it: map an input to each loaded coordinate ([measurement] input)")


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
