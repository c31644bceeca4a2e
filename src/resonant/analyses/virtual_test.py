"""A simulated vibration test of a model: the histories a lab would record (docs/testing.md).

Hammer hits (half-sine pulses at random instants, one per record) or a random force on the
model's ``[measurement]`` input (with several inputs, an independent one on each, all at
once: the data of the H1 matrix, :func:`resonant.analyses.frf_mimo.frf_matrix_from_measurement`),
the exact response of every mapped channel
(:func:`resonant.analyses.transient.transient_response`), and noise on the channels: the
data that :func:`resonant.analyses.frf_estimate.frf_from_measurement` turns back into the
model's FRFs, written as Universal Files by :func:`resonant.model.measured.write_uff`.
The channels are coordinates or outputs without a derivative (a derivative of the response
is not a history the transient response reports).

Examples
--------
>>> import resonant
>>> model = resonant.load("examples/chain3_lab.toml")
>>> data = simulated_test(model.linearize(), model.measurement_section, records=1,
...                       duration=4.0, step=1 / 128)
>>> data.names, data.functions[0].samples
(('hammer', 'd1', 'd2', 'd3'), 512)
"""

from __future__ import annotations

import numpy as np

from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..model.measured import MeasuredData, MeasuredFunction
from ..model.measurement_spec import MeasurementSpec
from ..system.base import LinearSystem
from .measured_match import saved_dofs
from .transient import transient_response

__all__ = ["simulated_test", "hammer_force"]


def hammer_force(count: int, samples: int, step: float, *, amplitude: float = 100.0,
                 width: float = 0.01, seed: int = 0) -> np.ndarray:
    """``count`` records of ``samples``, each with one half-sine hit early in the record.

    Parameters
    ----------
    count, samples : int
    step : float
        s.
    amplitude : float
        N, each hit's peak (varied by 10 % from hit to hit).
    width : float
        s, each hit's duration.
    seed : int
        The random generator's seed.

    Returns
    -------
    ndarray
        The force, ``count * samples`` values.

    Examples
    --------
    >>> f = hammer_force(2, 100, 0.001, width=0.005)
    >>> f.shape, bool(f.max() > 80)
    ((200,), True)
    """
    rng = np.random.default_rng(seed)
    t = np.arange(samples) * step
    force = np.zeros(count * samples)
    for k in range(count):
        start = rng.uniform(0.02, 0.05) * samples * step
        hit = (t >= start) & (t <= start + width)
        force[k * samples:(k + 1) * samples] = np.where(
            hit, amplitude * rng.uniform(0.9, 1.1) * np.sin(np.pi * (t - start) / width), 0.0)
    return force


def simulated_test(system: LinearSystem, spec: MeasurementSpec | None, *, records: int = 4,
                   duration: float = 16.0, step: float = 1 / 256, noise: float = 0.0,
                   input_noise: float = 0.0, random: bool = False, seed: int = 0,
                   deadline: Deadline = NO_DEADLINE) -> MeasuredData:
    """The recorded histories of a simulated impact (or random) test of the model.

    Parameters
    ----------
    system : LinearSystem
    spec : MeasurementSpec
        The model's ``[measurement]``: its input (or inputs: one independent force on
        each, all at once, the responses summed) and channels.
    records : int
        Hits (one per record of ``duration`` on each input), or segments of a random test.
    duration : float
        s, each record.
    step : float
        s, the sampling step.
    noise, input_noise : float
        White noise on the responses and the force, relative to each channel's RMS.
    random : bool
        A Gaussian random force instead of hammer hits.
    seed : int
    deadline : Deadline, optional

    Returns
    -------
    MeasuredData
        The excitation channel (each, in the section's order), then the response
        channels (SI).

    Raises
    ------
    ModelError
        Without a ``[measurement]`` section or for a channel with a derivative.
    """
    if spec is None or not spec.input:
        raise ModelError(Problem("a simulated test needs the [measurement] section's input "
                                 "and channels", system.source, "measurement"))
    for channel, c in spec.channels.items():
        if c.derivative:
            raise ModelError(Problem(f"channel '{printable(channel, limit=40)}' is a "
                                     "derivative; a simulated test records coordinates and "
                                     "outputs", system.source, "measurement.channels", channel))
    samples = int(round(duration / step))
    rng = np.random.default_rng(seed)
    references = list(spec.references) or [(spec.excitation, spec.input)]
    # one independent force per input (input j's hits drawn with seed + j); the response
    # to all of them is the sum of the responses to each (the model is linear)
    forces = [rng.standard_normal(records * samples) if random else
              hammer_force(records, samples, step, seed=seed + j)
              for j in range(len(references))]
    names = sorted({c.name for c in spec.channels.values()})
    histories: dict[str, np.ndarray] = {}
    for (_, name), force in zip(references, forces, strict=True):
        response = transient_response(system, name, force, step, names=names,
                                      deadline=deadline)
        for quantity in names:
            y = np.asarray(response.history[quantity], dtype=float)
            histories[quantity] = histories[quantity] + y if quantity in histories else y
    time = np.arange(records * samples) * step
    dofs = saved_dofs(spec, system, deadline)
    functions = []
    for (channel, _), force in zip(references, forces, strict=True):
        measured = force + input_noise * np.std(force) * rng.standard_normal(len(force))
        functions.append(MeasuredFunction(channel or "force", "time", time, measured, "s",
                                          "N", dofs[channel], (0, 0)))
    for channel, c in spec.channels.items():
        y = histories[c.name]
        y = y + noise * np.std(y) * rng.standard_normal(len(y))
        functions.append(MeasuredFunction(channel, "time", time, y, "s", "m", dofs[channel],
                                          (0, 0)))
    return MeasuredData("simulated test", tuple(functions))
