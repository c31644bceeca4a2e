"""Floquet exponents of the condensed balance from the monodromy matrix equal Hill's.

Two routes to the stability of one branch: Hill's eigenvalue problem (used where it has
at most ``condensed.MONODROMY_ROWS`` rows) and the monodromy matrix (used above; here
forced everywhere with ``MONODROMY_ROWS = 0``), on the models of
``tests/test_condensed.py``'s stability tests, whose Hill verdicts that file checks
against time simulations of the full equations.
"""

from __future__ import annotations

import numpy as np
import pytest

from resonant.analyses import condensed
from resonant.system import nonlinear_system
from resonant.analyses.condensed import condensed_sweep

from test_condensed import chain


def _growth(r) -> np.ndarray:
    """The largest growth rate of each branch point, log|mu|_max / T."""
    return np.log(np.abs(r.multipliers)).max(axis=1) * r.base_frequencies / (2 * np.pi)


@pytest.mark.parametrize("n, H, every", [
    (10, 9, False),  # test_stability_agrees_with_time_simulation: 2 of 10 modes dynamic
    (8, 7, True),    # test_fast_modes_static...: every mode dynamic, 16 exponents
])
def test_monodromy_gives_hills_verdicts(monkeypatch, n, H, every):
    """The same verdict at every branch point, the same special points (kinds and values
    to 1e-10) and the largest growth rates to 1e-6 W_max (2e-7 seen: Hill's truncation
    and the Magnus steps' error; a verdict flips only for |mu| within that of 1)."""
    if every:
        monkeypatch.setattr(condensed, "SMALL_HILL", 10**6)
    model, *_ = chain(n)
    kwargs = dict(harmonics=H, points=40, linear=False)
    hill = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, **kwargs)
    monkeypatch.setattr(condensed, "MONODROMY_ROWS", 0)
    mono = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, **kwargs)
    assert len(hill.values) == len(mono.values)
    np.testing.assert_array_equal(mono.stable, hill.stable)
    assert (~hill.stable).any() and hill.stable.any()
    assert [s.kind for s in mono.special_points] == [s.kind for s in hill.special_points]
    np.testing.assert_allclose([s.value for s in mono.special_points],
                               [s.value for s in hill.special_points], rtol=1e-10)
    np.testing.assert_allclose(_growth(mono), _growth(hill), atol=1e-6 * 2.4)


def test_real_coordinates_give_the_complex_multipliers():
    """A real periodic system eta' = A(t) eta written in complex modal coordinates (poles
    in conjugate pairs and real ones): the monodromy matrix in the real coordinates of
    ``_real_coordinates`` (real arithmetic) has the multipliers of the complex route (to
    1e-12 in the same coordinates, 1e-10 against the modal ones)."""
    rng = np.random.default_rng(3)
    mu = np.array([-0.02 + 1.3j, -0.3, -0.05 - 2.1j, -0.02 - 1.3j, -0.05 + 2.1j, -0.7])
    s, H, W = mu.size, 3, 1.1
    pairs = condensed._real_coordinates(mu)
    assert pairs is not None
    Q, Qinv = pairs
    # a real A(t) in the real coordinates: C_{-d} = conj(C_d), the mean real
    half = 0.01 * (rng.normal(size=(2 * H + 1, s, s)) + 1j * rng.normal(size=(2 * H + 1, s, s)))
    real = np.zeros((4 * H + 1, s, s), dtype=complex)
    real[2 * H + 1:] = half[1:]
    real[:2 * H] = np.conj(half[1:][::-1])
    real[2 * H] = half[0].real + (Qinv @ np.diag(mu) @ Q).real
    modal = Q @ real @ Qinv   # the same system in the modal coordinates eta = Q y
    back = Qinv @ modal @ Q
    T = 2 * np.pi / W

    def multipliers(coef: np.ndarray, real: bool = False) -> np.ndarray:
        return np.exp(condensed._monodromy(coef, W, H, s, real) * T)

    def farthest(a: np.ndarray, b: np.ndarray) -> float:
        """The largest distance from a multiplier of a to the nearest of b."""
        return float(np.abs(a[:, None] - b[None, :]).min(axis=1).max())

    modal_route = multipliers(modal)
    complex_route = multipliers(back)     # the real coordinates, complex arithmetic
    real_route = multipliers(back, True)  # the same steps, real arithmetic
    assert farthest(real_route, complex_route) < 1e-12
    assert farthest(complex_route, real_route) < 1e-12
    # the Magnus steps commute with a constant change of coordinates: with the same step
    # count (the least, 128: A is small here) the modal route's multipliers too
    assert farthest(real_route, modal_route) < 1e-10
    assert farthest(modal_route, real_route) < 1e-10
    # poles that do not pair: the complex route stays
    assert condensed._real_coordinates(np.array([-0.1 + 1j, -0.1 - 1.2j])) is None
