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
    hill = condensed_sweep(model.linearize(), "w", 1.0, 2.4, **kwargs)
    monkeypatch.setattr(condensed, "MONODROMY_ROWS", 0)
    mono = condensed_sweep(model.linearize(), "w", 1.0, 2.4, **kwargs)
    assert len(hill.values) == len(mono.values)
    np.testing.assert_array_equal(mono.stable, hill.stable)
    assert (~hill.stable).any() and hill.stable.any()
    assert [s.kind for s in mono.special_points] == [s.kind for s in hill.special_points]
    np.testing.assert_allclose([s.value for s in mono.special_points],
                               [s.value for s in hill.special_points], rtol=1e-10)
    np.testing.assert_allclose(_growth(mono), _growth(hill), atol=1e-6 * 2.4)
