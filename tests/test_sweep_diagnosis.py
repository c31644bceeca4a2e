"""What ``sweep`` says where its solves lose their digits (analyses/sweep.py): the
conditioning, never "undamped resonance" on a damped model.

References (closed forms of the 2-DOF models below, no library):

* two unit masses joined by a stiff spring K = 1e12 and held by soft ones k = 1, damped
  by 0.01 each: the dynamic stiffness's eigenvalues are about 1 - w^2 and 2e12, so its
  condition number is about 2e12 / |1 - w^2| (at w = 0.5: 2.7e12); the rounding of the
  terms of order 1e12 reaches the soft mode at about 1e-4, four digits left (with 1.7e15
  instead, none);
* a damper on one of two uncoupled oscillators: the undamped one's resonance (w = 2) is
  singular although the model has damping: its message names both causes.
"""

from __future__ import annotations

import pytest

from resonant.analyses.sweep import sweep
from resonant.model import loads
from resonant.system import linear_system

STIFF = """
[parameters]
omega = 0.5
[matrices]
M = [[1, 0], [0, 1]]
K = [[1000000000001, -1000000000000], [-1000000000000, 1000000000001]]
C = [[0.01, 0], [0, 0.01]]
[[harmonic]]
omega = "omega"
F_S = [1, 0]
"""

PARTLY_DAMPED = """
[parameters]
omega = 1
[matrices]
M = [[1, 0], [0, 1]]
K = [[1, 0], [0, 4]]
C = [[0.1, 0], [0, 0]]
[[harmonic]]
omega = "omega"
F_S = [1, 1]
"""


def test_digits_lost_to_the_condition_number_alone_are_not_reported() -> None:
    """The condition number says 12 digits may go; the estimated forward error of the
    solves (tests/test_forward_error.py) finds 4 left, so nothing is said."""
    result = sweep(linear_system(loads(STIFF)), "omega", [0.3, 0.5, 0.7])
    assert not any("ill-conditioned" in w or "correct digits" in w for w in result.warnings)
    assert not any("undamped" in w for w in result.warnings)


def test_digits_really_lost_are_named() -> None:
    text = STIFF.replace("1000000000001", "1700000000000001").replace("1000000000000",
                                                                      "1700000000000000")
    result = sweep(linear_system(loads(text)), "omega", [0.3, 0.7])
    (said,) = [w for w in result.warnings if "correct digits" in w]
    assert "2 of 2 points" in said and "not a resonance" in said


def test_a_damped_model_is_not_called_undamped() -> None:
    result = sweep(linear_system(loads(PARTLY_DAMPED)), "omega", [1.5, 2.0, 2.5])
    (said,) = [w for w in result.warnings if "no stationary solution" in w]
    assert "omega = 2" in said and "although the model is damped" in said
    assert "undamped resonance" not in said
    assert "not reached by the damping" in said


def test_an_undamped_model_is_still_called_undamped() -> None:
    text = PARTLY_DAMPED.replace("C = [[0.1, 0], [0, 0]]\n", "")
    result = sweep(linear_system(loads(text)), "omega", [1.5, 2.0, 2.5])
    assert any("undamped resonance" in w for w in result.warnings)


@pytest.mark.parametrize("values", [[0.3], [10.0, 20.0]])
def test_well_conditioned_points_say_nothing(values: list) -> None:  # type: ignore
    text = STIFF.replace("1000000000001", "3").replace("1000000000000", "1")
    result = sweep(linear_system(loads(text)), "omega", values)
    assert not any("ill-conditioned" in w for w in result.warnings)
