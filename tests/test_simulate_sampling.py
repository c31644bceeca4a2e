"""The sampling of the simulation's dense output (docs/performance.md, "Simulation sampling").

Two claims: ``dense_values`` gives exactly (bit for bit) what scipy's ``OdeSolution`` gives,
for every integrator the simulation uses; and the number of samples follows what the
integrator resolved, so that a model at rest with a stiff mode (a rotor: 8.3 kHz) is not
sampled at 2000 points per period of that mode, while a model whose steps follow its
highest mode keeps the grid of that mode.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate

from conftest import EXAMPLES
from resonant.analyses import simulate as simulate_module
from resonant.analyses.simulate import MAX_WINDOW_SAMPLES, simulate
from resonant.analyses.time_integration import (
    DENSE_CHUNK,
    dense_values,
    resolved_frequency,
)
from resonant.api import load


def _oscillators(t: float, y: np.ndarray) -> np.ndarray:
    # two undamped oscillators, 1 and 30 rad/s, and a cubic spring on the first
    q, v = y[:2], y[2:]
    return np.concatenate([v, [-q[0] - 0.3 * q[0] ** 3, -900.0 * q[1]]])


@pytest.mark.parametrize("method", ["DOP853", "RK45", "LSODA", "BDF", "Radau"])
def test_dense_values_are_scipys_values_bit_for_bit(method):
    result = scipy.integrate.solve_ivp(_oscillators, (0.0, 3.0), [1.0, 0.01, 0.0, 0.2],
                                       method=method, rtol=1e-8, atol=1e-10,
                                       dense_output=True)
    ts = result.sol.ts
    # a dense grid (more points in a step than one chunk), the step ends themselves
    # (the ties scipy sends to the earlier step) and the two ends of the run
    t = np.sort(np.concatenate([np.linspace(0.0, 3.0, 3 * DENSE_CHUNK + 7), ts,
                                [0.0, 3.0]]))
    values = dense_values(result.sol, t)
    assert values.shape == (4, t.size)
    assert np.array_equal(values, result.sol(t))


def test_dense_values_of_a_long_step_span_several_chunks():
    result = scipy.integrate.solve_ivp(lambda t, y: -y, (0.0, 1.0), [1.0], method="DOP853",
                                       dense_output=True, rtol=1e-3)
    t = np.linspace(0.0, 1.0, 5 * DENSE_CHUNK + 1)
    assert np.array_equal(dense_values(result.sol, t), result.sol(t))


def _window_samples(monkeypatch, path, duration):
    """simulate's result and the number of window samples its amplitudes were taken on."""
    sizes: list[int] = []
    peak = simulate_module.sampled_peak

    def counting(y):
        sizes.append(len(y))
        return peak(y)

    monkeypatch.setattr(simulate_module, "sampled_peak", counting)
    sim = simulate(load(path).linearize(), duration)
    return sim, sizes[0]


def test_a_rotor_at_rest_is_not_sampled_at_its_stiffest_mode(monkeypatch):
    # Friswell et al. (2010), Example 5.9.1: the highest natural frequency is 5.2e4 rad/s;
    # at rest the integrator takes 6 steps of 0.017-0.09 s.  The old rule asked for
    # 0.05 s * 8268 Hz * 2000 = 8.3e5 window samples (capped at MAX_WINDOW_SAMPLES).
    sim, samples = _window_samples(monkeypatch, EXAMPLES / "rotors" / "friswell_5_9_1.toml",
                                   0.1)
    assert samples < MAX_WINDOW_SAMPLES / 20
    assert max(sim.steady_amplitudes.values()) == 0.0  # at rest: nothing to miss


def test_a_model_whose_steps_follow_its_highest_mode_keeps_its_grid(monkeypatch):
    # the 6-storey building: its steps span 0.04-0.18 periods of its highest mode, so the
    # window grid is the one of that mode (2000 samples per period), as before
    path = EXAMPLES / "shear_building6.toml"
    sim, samples = _window_samples(monkeypatch, path, 60.0)
    highest = max(abs(np.linalg.eigvals(_state(path)).imag))
    length = sim.window[1] - sim.window[0]
    assert samples == int(max(5001, length * highest / (2 * math.pi) * 2000 + 1))


def _state(path):
    num = load(path).linearize().numeric().dense()
    n = len(num.coordinates)
    minv = np.linalg.inv(num.M)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ num.K, -minv @ num.C]])


def test_resolved_frequency_is_bounded_by_the_steps():
    result = scipy.integrate.solve_ivp(lambda t, y: -y, (0.0, 10.0), [1.0], method="DOP853",
                                       dense_output=True, rtol=1e-3)
    longest_allowed = 2 * math.pi * 8.0 / float(np.diff(result.sol.ts).min())
    assert resolved_frequency(result.sol, 1e9) == pytest.approx(longest_allowed)
    assert resolved_frequency(result.sol, 1e-3) == 1e-3  # the system's own bound wins
