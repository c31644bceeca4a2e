"""The special points of a 2-DOF system with a cubic spring, confirmed by long simulations.

examples/two_dof_cubic.toml (NLvib's 2-DOF example type: masses 1 and 0.05, a cubic
spring between them, forcing on the primary mass).  Harmonic balance (H = 11) finds two
folds of a hardening overhang and points where the upper branch loses stability.
Checked against resonant's own nonlinear simulation (DOP853, rtol 1e-10) started on the
harmonic-balance solution with x2(0) disturbed by 1e-3 and run for 120 periods (300 on
the middle branch), where a largest |multiplier| above 1.05 grows the disturbance more
than 300 times:

* a stable point just before the stability is lost stays on the branch (peak amplitude
  to 1e-3, the truncation of the series being below 1e-3);
* a point just past the loss of stability (largest |multiplier| above 1.05) leaves it
  (the amplitude differs by more than 1 %);
* a point on the middle branch just past a fold leaves it likewise.
"""

from __future__ import annotations

import numpy as np
import pytest

from conftest import EXAMPLES
from resonant.analyses.harmonic_balance import NonlinearResponse
from resonant.api import load
from resonant.model import Model

TWO_DOF = EXAMPLES / "two_dof_cubic.toml"


@pytest.fixture(scope="module")
def model() -> Model:
    return load(TWO_DOF)


@pytest.fixture(scope="module")
def branch(model: Model) -> NonlinearResponse:
    return model.nonlinear_sweep("omega", 0.9, 1.05, harmonics=11, points=60, linear=False)


def _initial(result: NonlinearResponse, i: int) -> dict[str, str]:
    out = {}
    k = np.arange(1, result.harmonics + 1)
    for j, name in enumerate(result.coordinates):
        c = result.coefficients[i, j]
        out[name] = repr(float(c[0] + c[1::2].sum()))
        out[name + "'"] = repr(float(result.base_frequencies[i] * (k * c[2::2]).sum()))
    return out


def _departure(model: Model, result: NonlinearResponse, i: int, periods: int = 120) -> float:
    """Relative difference of the simulated peak amplitude of x1 after ``periods``, started
    on the branch point with x2(0) disturbed by 1e-3 of its amplitude (so that every
    Floquet mode, also a symmetry-breaking one, is present)."""
    at = model.with_parameters(omega=repr(float(result.values[i])))
    period = 2 * np.pi / result.base_frequencies[i]
    initial = _initial(result, i)
    initial["x2"] = repr(float(initial["x2"]) + 1e-3 * float(result.amplitudes["x2"][i]))
    sim = at.simulate(duration=periods * period, nonlinear=True, initial=initial,
                      periods=3, rtol=1e-10, progress=False)
    return abs(sim.steady_amplitudes["x1"] / result.amplitudes["x1"][i] - 1)


def test_folds_and_loss_of_stability_found(branch: NonlinearResponse) -> None:
    kinds = [p.kind for p in branch.special_points]
    assert kinds.count("fold") == 2
    assert branch.truncation < 1e-3 and branch.residual < 1e-10
    # the overhang: the parameter goes back between the folds, the middle branch unstable
    assert np.any(np.diff(branch.values) < 0)
    folds = [p for p in branch.special_points if p.kind == "fold"]
    assert folds[0].value > folds[1].value  # hardening: the upper fold at the higher omega
    assert folds[0].amplitudes["x1"] > folds[1].amplitudes["x1"]
    # the stable branch loses stability somewhere on the way up
    losses = np.flatnonzero(branch.stable[:-1] & ~branch.stable[1:])
    assert losses.size >= 1


def test_long_simulation_confirms_loss_of_stability(model: Model,
                                                    branch: NonlinearResponse) -> None:
    """The first loss of stability: the last stable point stays, a point past it leaves."""
    losses = np.flatnonzero(branch.stable[:-1] & ~branch.stable[1:])
    first = int(losses[0])
    assert _departure(model, branch, first) < 1e-3
    growth = np.abs(branch.multipliers).max(axis=1)
    past = next(i for i in range(first + 1, branch.values.size)
                if growth[i] > 1.05 and not branch.stable[i])
    assert not branch.stable[first + 1:past + 1].any()
    assert _departure(model, branch, past) > 1e-2


def test_long_simulation_confirms_the_middle_branch_is_unstable(
        model: Model, branch: NonlinearResponse) -> None:
    folds = [p for p in branch.special_points if p.kind == "fold"]
    upper = folds[0].index
    growth = np.abs(branch.multipliers).max(axis=1)
    middle = next(i for i in range(upper + 1, branch.values.size)
                  if growth[i] > 1.05 and not branch.stable[i])
    assert branch.values[middle] < folds[0].value
    # the middle branch's growth is slower: it leaves within 300 periods
    assert _departure(model, branch, middle, periods=300) > 1e-2
