"""The nonlinear steady-state amplitude of every sample (``nonlinear_amplitude:NAME``).

Per sample, the periodic steady state of the full equations of motion at the
sample's value of the band's parameter, reached by a slow upward sweep from the
band's start (:func:`resonant.analyses.slow_sweep.swept_state`: harmonic
balance, continuation, Hill's stability, the jumps by time integration).  The
model is compiled once (its :class:`~resonant.system.NonlinearSystem`); each
sample only changes its numbers (:func:`resonant.system.nonlinear_at`).  The
samples cannot be stacked into one computation: a chunk is a loop over its few
samples (:data:`~resonant.studies.designs.NONLINEAR_CHUNK`), and the chunks run
on the engine's workers.

Examples
--------
>>> import numpy as np, resonant
>>> from resonant.model.study import study_spec
>>> from resonant.system import nonlinear_system
>>> model = resonant.load("examples/duffing.toml")
>>> spec = study_spec({"omega": [1.3]}, ["nonlinear_amplitude:x"], harmonics=1,
...                   band={"parameter": "omega", "from": 0.5, "to": 2.0},
...                   parameters=model.parameters, coordinates=model.coordinates, outputs=[])
>>> values = {**model.parameter_values, "omega": np.array([1.3])}
>>> found = nonlinear_amplitudes(nonlinear_system(model), spec, values, 1)
>>> round(float(found.amplitudes[0, 0]), 6), found.status
(1.41092, ['ok'])
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analyses.slow_sweep import NotConverged, NotPeriodic, swept_state
from ..deadline import NO_DEADLINE, Deadline, DeadlineExceeded
from ..errors import ResonantError
from ..model.study import StudySpec
from ..system.nonlinear import NonlinearSystem
from ..system.nonlinear_at import nonlinear_at

#: the statuses of a sample whose nonlinear steady state is not found
NOT_CONVERGED = "not converged"
NOT_PERIODIC = "not periodic"
FAILED = "failed"


@dataclass
class NonlinearRows:
    """The amplitudes (samples, names), NaN where not found, and each sample's status
    ("ok" or one of NOT_CONVERGED, NOT_PERIODIC, FAILED) and reason."""

    names: list[str]
    amplitudes: np.ndarray
    status: list[str]
    reason: list[str]


def _sample(values: Mapping[str, Any], i: int) -> dict[str, float]:
    return {k: float(v[i]) if isinstance(v, np.ndarray) else float(v)
            for k, v in values.items()}


def _one(system: NonlinearSystem, spec: StudySpec, sample: Mapping[str, float],
         names: Sequence[str], deadline: Deadline) -> tuple[list[float], str, str]:
    """The amplitudes of ``names`` at one sample, its status and reason."""
    band = spec.band
    assert band is not None
    value = sample[band.parameter]
    if not (math.isfinite(value) and band.start <= value <= band.stop):
        return [math.nan] * len(names), FAILED, (
            f"{band.parameter} = {value:.6g} is outside the band {band.start:g} to "
            f"{band.stop:g} (the nonlinear steady state is swept up from its start)")
    try:
        state = swept_state(nonlinear_at(system, sample), band.parameter, band.start, value,
                            harmonics=spec.harmonics, deadline=deadline)
    except DeadlineExceeded:
        raise
    except NotConverged as exc:
        return [math.nan] * len(names), NOT_CONVERGED, str(exc).splitlines()[0]
    except NotPeriodic as exc:
        return [math.nan] * len(names), NOT_PERIODIC, str(exc).splitlines()[0]
    except (ResonantError, np.linalg.LinAlgError, FloatingPointError, OverflowError,
            ZeroDivisionError) as exc:
        return [math.nan] * len(names), FAILED, str(exc).splitlines()[0]
    missing = [name for name in names if name not in state.amplitudes]
    if missing:  # an output with a coordinate's third derivative has no full form
        return [math.nan] * len(names), FAILED, (
            f"the output '{missing[0]}' cannot be evaluated on the full equations of motion")
    return [state.amplitudes[name] for name in names], "ok", ""


def nonlinear_amplitudes(system: NonlinearSystem, spec: StudySpec, values: Mapping[str, Any],
                         count: int, skip: np.ndarray | None = None,
                         deadline: Deadline = NO_DEADLINE) -> NonlinearRows:
    """The ``nonlinear_amplitude:`` quantities of ``spec`` at ``count`` samples.

    Parameters
    ----------
    system : NonlinearSystem
        The model's full equations (compiled once).
    spec : StudySpec
        With a band: its parameter is the one swept, from its start up to each
        sample's value.
    values : mapping
        Every parameter's value: a float, or an array of ``count`` values.
    count : int
    skip : ndarray of bool, optional
        Samples not to compute (failed already).

    Returns
    -------
    NonlinearRows
    """
    names = list(dict.fromkeys(q.target for q in spec.quantities
                               if q.kind == "nonlinear_amplitude"))
    out = NonlinearRows(names, np.full((count, len(names)), np.nan), ["ok"] * count,
                        [""] * count)
    for i in range(count):
        if skip is not None and skip[i]:
            continue
        deadline.check("while computing the study's nonlinear amplitudes", analysis=True)
        amplitudes, out.status[i], out.reason[i] = _one(system, spec, _sample(values, i),
                                                        names, deadline)
        out.amplitudes[i] = amplitudes
    return out


__all__ = ["NonlinearRows", "nonlinear_amplitudes", "NOT_CONVERGED", "NOT_PERIODIC"]
