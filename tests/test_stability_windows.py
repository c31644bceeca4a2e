"""A window of instability narrower than a step of the branch is found all the same.

A 6-mass chain (masses 1/6 on springs 6, C = 0.002 M + 0.0002 K, the cubic spring
2 q6^3 and the force 0.008 at the tip, H = 5) has a period-doubling window 2e-3 wide at
w = 1.438 on its rising branch.  Reference: the same branch over 1.42 ... 1.46 with the
fixed step ceiling (``relative=False``, 40 points asked: 75 points, two inside the
window); the condensed balance's relative control with 8 asked takes 28 points, none
inside, and the search between the points around the sampled maximum of the growth rate
(``special_points.WINDOW_FACTOR``) must find its two changes of stability, of the same
kinds and to 1e-8 of the reference's values (both located by regula falsi on the rate's
zero; measured 2026-11-28: equal to 1e-15).  Without that search the coarse branch
reports none.
"""

from __future__ import annotations

import numpy as np
import pytest

from resonant.analyses import condensed
from resonant.system import nonlinear_system
from resonant.analyses.condensed import condensed_sweep
from test_condensed_steps import light_chain


def chain(n: int = 6) -> object:
    """The light chain with less damping and twice the force: a narrow window."""
    return light_chain(n, alpha=0.002, beta=0.0002, force=0.008)


def _sweep(monkeypatch, relative: bool, points: int):
    original = condensed.follow

    def follow(*args, **kwargs):
        return original(*args, **{**kwargs, "relative": relative})

    with monkeypatch.context() as patch:
        patch.setattr(condensed, "follow", follow)
        return condensed_sweep(nonlinear_system(chain()), "w", 1.42, 1.46, harmonics=5, points=points,
                               linear=False)


def _changes(result) -> list[tuple[str, float]]:
    return sorted((s.kind, s.value) for s in result.special_points if s.kind != "peak")


def test_a_window_between_two_points_of_the_coarse_branch_is_found(monkeypatch):
    fine = _sweep(monkeypatch, relative=False, points=40)
    coarse = _sweep(monkeypatch, relative=True, points=8)
    expected = _changes(fine)
    values = sorted({v for _, v in expected})
    assert len(values) == 2 and 1e-3 < values[1] - values[0] < 3e-3  # the window
    # the coarse branch has no point inside the window (else this test tests nothing)
    assert not np.any((coarse.values > values[0]) & (coarse.values < values[1]))
    assert np.all(coarse.stable)
    assert not np.all(fine.stable)
    found = _changes(coarse)
    assert [k for k, _ in found] == [k for k, _ in expected]
    assert "period-doubling" in {k for k, _ in found}
    assert [v for _, v in found] == pytest.approx([v for _, v in expected], rel=0, abs=1e-8)
