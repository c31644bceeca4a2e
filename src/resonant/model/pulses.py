"""The classical shock pulses: each one an entry that carries its meaning.

A pulse is named in the ``[shock]`` section and on the command line (``resonant srs
--pulse``); what it is -- its samples, how the worked solution names it -- is written once,
here, so that a new pulse is one entry of :data:`PULSE_KINDS`.

Examples
--------
>>> import numpy as np
>>> t = np.arange(6) * 0.001
>>> PULSE_KINDS["sawtooth"].samples(t, 2.0, 0.004, 0.001).tolist()
[0.0, 0.5, 1.0, 1.5, 2.0, 0.0]
>>> PULSE_KINDS["impulse"].description
'an impulse'
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

#: the value of a pulse's shape at s = t / tau in [0, 1]
Shape = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Pulse:
    """A classical pulse: a shape over its duration, or a step, or a sampled impulse.

    Parameters
    ----------
    name : str
        Its name in a model file.
    description : str
        How a sentence names it ("a half-sine").
    shape : callable or None
        A / amplitude as a function of s = t / tau on 0 <= s <= 1 (zero after it); None
        for ``step`` (A from t = 0 on) and ``impulse`` (one step of height A / step).
    """

    name: str
    description: str
    shape: Shape | None = None

    def samples(self, t: np.ndarray, amplitude: float, duration: float,
                step: float) -> np.ndarray:
        """The pulse at the sample times ``t`` (tau = ``duration``, sampled every ``step``).

        Parameters
        ----------
        t : ndarray
            Sample times from 0, ``step`` apart.
        amplitude : float
            The peak A (the area for an impulse).
        duration, step : float
            tau and the sampling step (s).

        Returns
        -------
        ndarray

        Examples
        --------
        >>> PULSE_KINDS["step"].samples(np.arange(3) * 0.5, 3.0, 1.0, 0.5).tolist()
        [3.0, 3.0, 3.0]
        """
        a = np.zeros(t.shape)
        if self.name == "step":
            a[:] = amplitude
        elif self.shape is None:   # an impulse: a triangle of one step each side, area A
            a[1] = amplitude / step
        else:
            inside = t <= duration * (1 + 1e-12)
            a[inside] = amplitude * self.shape(t[inside] / duration)
        a[np.abs(a) < 1e-300] = 0.0
        return a


#: name -> pulse, in the order the documentation lists them
PULSE_KINDS: dict[str, Pulse] = {p.name: p for p in (
    Pulse("half-sine", "a half-sine", lambda s: np.sin(np.pi * s)),
    Pulse("haversine", "a haversine", lambda s: np.sin(np.pi * s) ** 2),
    # the terminal-peak sawtooth A t / tau, back to 0 in one step
    Pulse("sawtooth", "a sawtooth", lambda s: s),
    Pulse("rectangular", "a rectangular", np.ones_like),
    Pulse("step", "a step"),
    Pulse("impulse", "an impulse"),
)}
#: the pulses' names
PULSES: tuple[str, ...] = tuple(PULSE_KINDS)

__all__ = ["Pulse", "PULSE_KINDS", "PULSES"]
