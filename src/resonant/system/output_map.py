"""The one map from the coordinates (and the signals) to the outputs of a linear system.

An output of ``[outputs]`` is linearized to y = sum_k R_k q^(k) + S s, q^(k) the k-th
derivative of the coordinates and s the signal derivatives it holds.  :func:`output_map`
writes those matrices once; each analysis applies them to what it has: complex
amplitudes at a frequency (:meth:`OutputMap.harmonic`, where d/dt is i w), the samples of
a time history (:meth:`OutputMap.history`), or the rows of a state-space output.

Examples
--------
>>> from resonant.system.base import NumericOutput
>>> outputs = {"stretch": NumericOutput(0.0, {("x2", 0): 1.0, ("x1", 0): -1.0}),
...            "speed": NumericOutput(0.0, {("x2", 1): 1.0})}
>>> y = output_map(outputs, ("x1", "x2"))
>>> y.names, y.R.shape
(('stretch', 'speed'), (2, 2, 2))
>>> y.harmonic(2.0, np.array([1.0, 3.0 + 0j])).tolist()
[(2+0j), 6j]
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .base import NumericOutput

__all__ = ["OutputMap", "output_map"]


@dataclass(frozen=True)
class OutputMap:
    """y = sum_k R[k] q^(k) + S s for the outputs ``names``.

    Attributes
    ----------
    names : tuple of str
        The outputs, in order.
    R : ndarray
        (orders, outputs, coordinates): the coefficient of the k-th derivative of each
        coordinate (k = 0 ... the highest order an output holds; at least 0 and 1).
    signals : tuple of (str, int)
        The signal derivatives the outputs hold, (name, order).
    S : ndarray
        (outputs, signals): their coefficients.
    """

    names: tuple[str, ...]
    R: np.ndarray
    signals: tuple[tuple[str, int], ...]
    S: np.ndarray

    def harmonic(self, w: float, z: np.ndarray,
                 signals: Mapping[tuple[str, int], complex] | None = None) -> np.ndarray:
        """The outputs' complex amplitudes at the frequency w from the coordinates' z
        (d/dt is i w), and the signals' complex amplitudes where given.

        Parameters
        ----------
        w : float
            The frequency (rad/s).
        z : ndarray
            (coordinates,) complex amplitudes.
        signals : mapping, optional
            (name, order) -> the complex amplitude of that signal derivative (zero when
            missing).

        Returns
        -------
        ndarray
            (outputs,) complex.
        """
        y = np.zeros(len(self.names), dtype=complex)
        with np.errstate(all="ignore"):  # an overflow is caught with the result
            for k in range(len(self.R)):
                y += (1j * w) ** k * (self.R[k] @ z)
            if signals:
                s = np.array([signals.get(v, 0.0) for v in self.signals], dtype=complex)
                y += self.S @ s
        return y

    def history(self, derivatives: Sequence[np.ndarray], signals: np.ndarray | None = None
                ) -> np.ndarray:
        """The outputs at samples from the coordinates' derivatives there.

        Parameters
        ----------
        derivatives : sequence of ndarray
            q, q', q'', ... each (coordinates, N): at least as many as :attr:`R` has orders.
        signals : ndarray, optional
            (len(signals), N) the signal derivatives (zero when None).

        Returns
        -------
        ndarray
            (outputs, N).
        """
        count = np.shape(derivatives[0])[1:]
        y = np.zeros((len(self.names), *count))
        for k in range(len(self.R)):
            y += self.R[k] @ derivatives[k]
        if signals is not None and self.signals:
            y += self.S @ signals
        return y

    @property
    def orders(self) -> np.ndarray:
        """(outputs,) the highest derivative of a coordinate each output holds (-1: none)."""
        held = np.any(self.R != 0, axis=2)  # (orders, outputs)
        return np.array([int(np.flatnonzero(held[:, j]).max()) if held[:, j].any() else -1
                         for j in range(len(self.names))], dtype=int)


def output_map(outputs: Mapping[str, NumericOutput], coordinates: Sequence[str],
               names: Sequence[str] | None = None) -> OutputMap:
    """The map of the outputs ``names`` (default all) of a linear system.

    Parameters
    ----------
    outputs : mapping
        name -> :class:`~resonant.system.base.NumericOutput` (a system's ``outputs``).
    coordinates : sequence of str
        The system's coordinates, in order.
    names : sequence of str, optional
        The outputs to map, in this order (names that are no output are left out).

    Returns
    -------
    OutputMap
    """
    chosen = tuple(n for n in (outputs if names is None else names) if n in outputs)
    index = {q: i for i, q in enumerate(coordinates)}
    terms = [outputs[name].terms for name in chosen]
    orders = max([1, *(order for t in terms for (var, order) in t if var in index)])
    signals = tuple(sorted({(var, order) for t in terms for (var, order) in t
                            if var not in index}))
    where = {v: j for j, v in enumerate(signals)}
    R = np.zeros((orders + 1, len(chosen), len(coordinates)))
    S = np.zeros((len(chosen), len(signals)))
    for row, t in enumerate(terms):
        for (var, order), coefficient in t.items():
            if var in index:
                R[order, row, index[var]] += float(coefficient)
            else:
                S[row, where[(var, order)]] += float(coefficient)
    return OutputMap(chosen, R, signals, S)
