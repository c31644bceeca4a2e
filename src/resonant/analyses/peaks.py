"""The peak absolute value of a sampled or periodic signal (the amplitude of every analysis).

:func:`sampled_peak` refines the largest sample by a parabola through its
neighbours (finely sampled smooth data, the time simulation);
:func:`periodic_peak` locates the maximum of |y(tau)| of a 2 pi-periodic
signal that can be evaluated anywhere (a Fourier series, an output of one)
to rounding: a fine grid, then parabolic steps on shrinking spacings.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

#: grid of the first search over one period, and the parabolic refinement steps
GRID = 512
REFINEMENTS = 7
SHRINK = 8.0


def sampled_peak(y: np.ndarray) -> float:
    """max |y| of finely sampled smooth data, refined by a parabola through the top 3 samples.

    Examples
    --------
    >>> t = np.linspace(0, 1, 50)
    >>> round(sampled_peak(np.sin(2 * np.pi * t + 0.1)), 6)
    1.0
    """
    a = np.abs(y)
    i = int(np.argmax(a))
    top = float(a[i])
    if 0 < i < a.size - 1:
        left, right = float(a[i - 1]), float(a[i + 1])
        curvature = 2 * top - left - right
        if curvature > 0:
            try:
                refined = top + (right - left) ** 2 / (8 * curvature)
            except (OverflowError, ZeroDivisionError):  # Python floats raise
                return top
            return refined if math.isfinite(refined) else top
    return top


def periodic_peak(evaluate: Callable[[np.ndarray], np.ndarray], count: int,
                  grid: np.ndarray | None = None) -> np.ndarray:
    """max over tau of |y_j(tau)| for ``count`` 2 pi-periodic signals y_j.

    Parameters
    ----------
    evaluate : callable
        ``tau (k,) -> (count, k)`` values of the signals.
    count : int
        Number of signals.
    grid : numpy.ndarray, optional
        The times of the first search (default: GRID points over one period).

    Returns
    -------
    numpy.ndarray
        (count,) peaks; each the value at a parabolic vertex when that beats the samples.

    Examples
    --------
    >>> f = lambda tau: np.array([0.3 + np.cos(tau + 0.123), 2 * np.sin(3 * tau)])
    >>> periodic_peak(f, 2).tolist()
    [1.3, 2.0]
    """
    tau = 2 * np.pi * np.arange(GRID) / GRID if grid is None else grid
    values = np.abs(evaluate(tau))
    index = np.argmax(values, axis=1)
    best = tau[index]
    top = values[np.arange(count), index]
    h = 2 * np.pi / tau.size
    for _ in range(REFINEMENTS):
        points = np.concatenate([best - h, best, best + h])
        # signal j at its own three points: columns j, count + j, 2 count + j
        y = np.abs(evaluate(points)).reshape(count, 3, count)[np.arange(count), :,
                                                              np.arange(count)]
        left, mid, right = y[:, 0], y[:, 1], y[:, 2]
        curvature = left - 2 * mid + right
        with np.errstate(all="ignore"):
            shift = np.where(curvature < 0, 0.5 * h * (left - right) / curvature, 0.0)
        shift = np.clip(np.nan_to_num(shift), -h, h)
        best = best + shift
        top = np.maximum(top, np.maximum(mid, np.maximum(left, right)))
        h /= SHRINK
    final = np.abs(evaluate(best))[np.arange(count), np.arange(count)]
    return np.asarray(np.maximum(top, final))


def series_peaks(coefficients: np.ndarray, grid: int = GRID,
                 iterations: int = 4) -> np.ndarray:
    """max over tau of |c_0 + sum_k a_k cos k tau + b_k sin k tau| for many series at once.

    The largest of ``grid`` samples, then Newton's method on the derivative of the series
    (exact derivatives), which converges quadratically from the grid's spacing.

    Parameters
    ----------
    coefficients : numpy.ndarray
        (..., 2H+1): ``[c_0, a_1, b_1, ..., a_H, b_H]`` along the last axis.

    Returns
    -------
    numpy.ndarray
        The peaks, shape ``coefficients.shape[:-1]``.

    Examples
    --------
    >>> float(series_peaks(np.array([0.0, 0.3, -0.4]))) == 0.5
    True
    """
    c = np.asarray(coefficients, dtype=float)
    m = c.shape[-1]
    H = (m - 1) // 2
    k = np.arange(1, H + 1)
    tau = 2 * np.pi * np.arange(grid) / grid
    basis = np.ones((m, grid))
    basis[1::2], basis[2::2] = np.cos(np.outer(k, tau)), np.sin(np.outer(k, tau))
    values = np.abs(c @ basis)
    best = tau[np.argmax(values, axis=-1)]
    top = values.max(axis=-1)
    a, b = c[..., 1::2], c[..., 2::2]
    for _ in range(iterations):
        ck, sk = np.cos(best[..., None] * k), np.sin(best[..., None] * k)
        d1 = np.sum(k * (b * ck - a * sk), axis=-1)
        d2 = -np.sum(k ** 2 * (a * ck + b * sk), axis=-1)
        y = c[..., 0] + np.sum(a * ck + b * sk, axis=-1)
        with np.errstate(all="ignore"):
            step = np.where(d2 * np.sign(y) < 0, d1 / d2, 0.0)
        best = best - np.clip(np.nan_to_num(step), -np.pi / grid, np.pi / grid)
    ck, sk = np.cos(best[..., None] * k), np.sin(best[..., None] * k)
    final = np.abs(c[..., 0] + np.sum(a * ck + b * sk, axis=-1))
    return np.asarray(np.maximum(top, final))


__all__ = ["sampled_peak", "periodic_peak", "series_peaks"]
