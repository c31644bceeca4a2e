"""Periodic, non-harmonic loads: Fourier series and the superposed stationary response.

References:

* the Fourier coefficients of the square wave (4A/(n pi), odd n), the sawtooth
  (-2A/(n pi)), the triangle (8A/(n pi)^2, odd n) and the full-wave rectified sine
  (a0 = 2A/pi, a_n = -4A/(pi (4n^2 - 1))) (Kreyszig, Advanced Engineering Mathematics,
  Sect. 11.1-11.2; Rao, Mechanical Vibrations, Sect. 4.2): the FFT route of a function of
  t agrees with them to 1e-6 (5e-4 for the shapes with jumps, sampled on 16384 points);
* a long time simulation: a damped single-DOF system under a square-wave force, marched
  exactly from rest with its state-transition matrix over 400 half periods of constant
  force (scipy's expm; no integrator error) until the transient has decayed below 1e-12;
  its last period agrees with the superposition of the series' harmonic responses to
  1e-4 of the largest excursion (the series truncated at a remainder of 1e-2 RMS: 4053 harmonics);
  and scipy's solve_ivp (DOP853, rtol 1e-10) over the same time agrees as well.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg

from resonant.analyses.periodic_load import fourier_series, periodic_response
from resonant.errors import AnalysisError
from resonant.model import loads
from resonant.system import linear_system

SDOF = """
[parameters]
m = 2
k = 800
c = 4
[coordinates]
x = ""
[signals]
F = "0"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2 - F*x"
D = "c*x'^2/2"
[outputs]
spring = "k*x"
"""


@pytest.mark.parametrize("shape, expression", [
    ("square", lambda t: np.where(t < 0.5, 1.0, -1.0) * np.where(t == 0, 0, 1)),
    ("sawtooth", lambda t: 2 * t - 1),
    ("triangle", lambda t: 1 - 4 * np.minimum(t, 1 - t)),
    ("rectified-sine", lambda t: np.abs(np.sin(np.pi * t))),
])
def test_coefficients_closed_form_and_fft(shape: str, expression) -> None:  # type: ignore
    closed = fourier_series(shape, 1.0, 1.0, tolerance=1e-2)
    sampled = fourier_series(shape, 1.0, 1.0, tolerance=1e-2, function=expression)
    k = min(closed.harmonics, 50)
    # a jump sampled on a grid of N points moves the coefficients by O(1/N) (N = 16384)
    atol = 5e-4 if shape in ("square", "sawtooth") else 1e-6
    assert np.allclose(sampled.a[:k], closed.a[:k], atol=atol)
    assert np.allclose(sampled.b[:k], closed.b[:k], atol=atol)
    assert closed.remainder <= 1e-2
    n = np.arange(1, 6)
    if shape == "square":
        assert closed.b[:5] == pytest.approx(np.where(n % 2, 4 / (n * np.pi), 0))
    if shape == "rectified-sine":
        assert closed.a0 == pytest.approx(2 / np.pi)
        assert closed.a[:5] == pytest.approx(-4 / (np.pi * (4 * n**2 - 1)))


def exact_square_wave_history(period: float, amplitude: float, periods: int, samples: int
                              ) -> tuple[np.ndarray, np.ndarray]:
    """x over the last period, from rest, marched exactly half period by half period."""
    m, k, c = 2.0, 800.0, 4.0
    A = np.array([[0, 1], [-k / m, -c / m]])
    B = np.array([0, 1 / m])
    h = period / 2 / samples
    Phi = scipy.linalg.expm(A * h)
    Gamma = np.linalg.solve(A, (Phi - np.eye(2)) @ B)   # the step response over h
    state = np.zeros(2)
    history = []
    for half in range(2 * periods):
        force = amplitude if half % 2 == 0 else -amplitude
        for _ in range(samples):
            if half >= 2 * periods - 2:
                history.append(state[0])
            state = Phi @ state + Gamma * force
    t = np.arange(2 * samples) * h
    return t, np.array(history)


def test_square_wave_against_long_simulation() -> None:
    period, amplitude = 0.3, 10.0
    system = linear_system(loads(SDOF))
    series = fourier_series("square", amplitude, period, tolerance=1e-2)
    result = periodic_response(system, "F", series)
    t, exact = exact_square_wave_history(period, amplitude, 200, 500)
    ours = series_response_at(result, t)
    scale = np.abs(exact).max()
    assert np.abs(ours - exact).max() < 1e-4 * scale
    assert result.largest["x"] == pytest.approx(scale, rel=1e-3)
    assert result.largest["spring"] == pytest.approx(800 * result.largest["x"], rel=1e-12)
    assert result.mean["x"] == 0.0


def series_response_at(result, t: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    n = np.arange(1, result.series.harmonics + 1)
    phase = np.exp(1j * 2 * np.pi / result.series.period * np.multiply.outer(t, n))
    return result.mean["x"] + (phase @ result.harmonics["x"]).real


def test_against_solve_ivp() -> None:
    period, amplitude = 0.3, 10.0
    series = fourier_series("square", amplitude, period, tolerance=1e-2)
    result = periodic_response(linear_system(loads(SDOF)), "F", series)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        force = amplitude if (t % period) < period / 2 else -amplitude
        return np.array([y[1], (force - 800 * y[0] - 4 * y[1]) / 2])

    end = 200 * period
    solution = scipy.integrate.solve_ivp(rhs, (0, end), [0.0, 0.0], method="DOP853",
                                         rtol=1e-10, atol=1e-13, max_step=period / 50,
                                         dense_output=True)
    t = end - period + np.linspace(0, period, 301)
    ours = series_response_at(result, t - (end - period))
    assert np.abs(solution.sol(t)[0] - ours).max() < 1e-3 * result.largest["x"]


def test_rectified_sine_mean_and_base_acceleration() -> None:
    system = linear_system(loads(SDOF))
    series = fourier_series("rectified-sine", 5.0, 0.1, tolerance=1e-4)
    result = periodic_response(system, "F", series)
    assert result.mean["x"] == pytest.approx(2 * 5.0 / math.pi / 800, rel=1e-12)
    with pytest.raises(AnalysisError, match="nonzero mean"):
        periodic_response(system, "F", series, derivative=2)


def test_errors() -> None:
    with pytest.raises(AnalysisError, match="unknown periodic shape"):
        fourier_series("zigzag", 1, 1)
    with pytest.raises(AnalysisError, match="period"):
        fourier_series("square", 1, -1)
    with pytest.raises(AnalysisError, match="more than 10 harmonics"):
        fourier_series("square", 1, 1, tolerance=1e-3, max_harmonics=10)
    with pytest.raises(AnalysisError, match="not finite"):
        fourier_series("f", 1, 1, function=lambda t: np.where(t > 0, np.inf, 0.0))
