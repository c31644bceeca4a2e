"""The periodic load shapes of ``[periodic]``: each one an entry that carries its meaning.

A shape is named in a model file (``shape = "square"``); what it is -- its Fourier
coefficients in closed form, its mean square (for Parseval's remainder), how the worked
solution names it and writes its coefficients -- is written once, here, so that a new
shape is one entry of :data:`FOURIER_SHAPES`.  Each is a signal of amplitude A and period
T = 2 pi / Omega, ``a_0 + sum_n (a_n cos n Omega t + b_n sin n Omega t)``.

Examples
--------
>>> import numpy as np
>>> a0, a, b = FOURIER_SHAPES["square"].coefficients(1.0, np.arange(1, 4))
>>> (a0, a.tolist(), (b * np.pi).round(12).tolist())
(0.0, [0.0, 0.0, 0.0], [4.0, 0.0, 1.333333333333])
>>> FOURIER_SHAPES["triangle"].description, FOURIER_SHAPES["triangle"].mean_square(3.0)
('a triangle wave', 3.0)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

#: (A, n) -> (a_0, a_n, b_n) for the harmonics n = 1, 2, ...
Coefficients = Callable[[float, np.ndarray], tuple[float, np.ndarray, np.ndarray]]


@dataclass(frozen=True)
class FourierShape:
    """A periodic shape with closed-form Fourier coefficients.

    Parameters
    ----------
    name : str
        Its name in a model file.
    description : str
        How a sentence names it ("a square wave").
    coefficients : callable
        (A, n) -> (a_0, a_n, b_n).
    mean_square : callable
        A -> the mean square of the signal over a period.
    latex : str
        Its coefficients as the worked solution writes them.
    """

    name: str
    description: str
    coefficients: Coefficients
    mean_square: Callable[[float], float]
    latex: str


def _odd(n: np.ndarray) -> np.ndarray:
    return np.asarray(n % 2 == 1)


def _square(A: float, n: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    return 0.0, np.zeros(len(n)), np.where(_odd(n), 4 * A / (n * np.pi), 0.0)


def _sawtooth(A: float, n: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    return 0.0, np.zeros(len(n)), -2 * A / (n * np.pi)


def _triangle(A: float, n: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    return 0.0, np.where(_odd(n), 8 * A / (n * np.pi) ** 2, 0.0), np.zeros(len(n))


def _rectified_sine(A: float, n: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    return 2 * A / np.pi, -4 * A / (np.pi * (4 * n**2 - 1)), np.zeros(len(n))


#: every shape, by its name in a model file
FOURIER_SHAPES: dict[str, FourierShape] = {shape.name: shape for shape in (
    FourierShape("square", "a square wave", _square, lambda A: A * A,
                 r"b_{n} = \frac{4A}{n\pi}\ (n\ \text{odd}),\quad a_{0} = a_{n} = 0"),
    FourierShape("sawtooth", "a sawtooth", _sawtooth, lambda A: A * A / 3,
                 r"b_{n} = -\frac{2A}{n\pi},\quad a_{0} = a_{n} = 0"),
    FourierShape("triangle", "a triangle wave", _triangle, lambda A: A * A / 3,
                 r"a_{n} = \frac{8A}{(n\pi)^{2}}\ (n\ \text{odd}),\quad a_{0} = b_{n} = 0"),
    FourierShape("rectified-sine", "a full-wave rectified sine", _rectified_sine,
                 lambda A: A * A / 2,
                 r"a_{0} = \frac{2A}{\pi},\quad a_{n} = -\frac{4A}{\pi(4n^{2} - 1)},"
                 r"\quad b_{n} = 0"),
)}

#: the names of :data:`FOURIER_SHAPES`, in their order
SHAPES = tuple(FOURIER_SHAPES)

__all__ = ["FOURIER_SHAPES", "FourierShape", "SHAPES"]
