"""The condensed balance's step control, relative to the present amplitude.

``condensed_sweep`` follows its branch with ``continuation.follow(..., relative=True)``:
the step's ceiling grows with the amplitude beyond the start point's and the step grows
after four Newton iterations.  Reference: the same branch with the fixed ceiling in units
of the start point's amplitude (``relative=False``, the full balance's control), which
takes several times the points on a lightly damped resonance whose amplitude grows about
90-fold from the start.  Every special point (folds, peak, period doublings) must agree
with the reference's in kind and value to 1e-7 (they are located by regula falsi on the
branch, to about 1e-10 in both), the verdicts of the points between them too.
"""

from __future__ import annotations

import numpy as np
import pytest

from resonant.analyses import condensed
from resonant.system import nonlinear_system
from resonant.analyses.condensed import condensed_sweep
from test_condensed import chain


def light_chain(n: int = 4, alpha: float = 0.004, beta: float = 0.0004,
                force: float = 0.004) -> object:
    """The chain of tests/test_condensed.py (n masses 1/n on springs n, first frequency
    about 1.5, the cubic spring 2 q_n^3 and the force at the tip) with light Rayleigh
    damping C = alpha M + beta K."""
    return chain(n, force=force, alpha=alpha, beta=beta)[0]


def _sweep(model, monkeypatch, relative: bool):
    original = condensed.follow

    def follow(*args, **kwargs):
        return original(*args, **{**kwargs, "relative": relative})

    with monkeypatch.context() as patch:
        patch.setattr(condensed, "follow", follow)
        return condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, harmonics=3, points=50,
                               linear=False)


def test_relative_steps_take_fewer_points_and_find_the_same_special_points(monkeypatch):
    model = light_chain()
    fine = _sweep(model, monkeypatch, relative=False)
    coarse = _sweep(model, monkeypatch, relative=True)
    tip = coarse.amplitudes["q4"]
    assert tip.max() > 50 * tip[0]  # the amplitude grows far beyond the start point's
    # the fixed ceiling: 841 points; the relative one: 275 (measured 2026-11-28)
    assert len(coarse.values) < 0.5 * len(fine.values)
    kinds = sorted((s.kind, s.value) for s in fine.special_points)
    found = sorted((s.kind, s.value) for s in coarse.special_points)
    assert [k for k, _ in found] == [k for k, _ in kinds]
    assert {"fold", "peak", "period-doubling"} <= {k for k, _ in kinds}
    assert [v for _, v in found] == pytest.approx([v for _, v in kinds], rel=1e-7, abs=0)
    amplitude = {(s.kind, round(s.value, 6)): s.amplitudes["q4"] for s in fine.special_points}
    for s in coarse.special_points:
        assert s.amplitudes["q4"] == pytest.approx(amplitude[(s.kind, round(s.value, 6))],
                                                   rel=1e-7)
    # the verdicts: a coarse point is unstable where the fine branch is unstable at the
    # nearest point along the curve (away from the special points themselves)
    cuts = np.array(sorted(s.value for s in fine.special_points))
    fine_p, fine_a = fine.values, fine.amplitudes["q4"]
    for p, a, stable in zip(coarse.values, tip, coarse.stable):
        if np.min(np.abs(cuts - p)) < 1e-3:
            continue
        j = int(np.argmin(np.hypot(fine_p - p, (fine_a - a) / max(fine_a.max(), 1e-300))))
        assert stable == fine.stable[j]
