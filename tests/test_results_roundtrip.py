"""Results saved as JSON come back: ``from_dict(to_dict())`` gives the same result, and the
tabular results are tables (``to_frame()``) holding the same numbers as the result."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import resonant
from resonant.analyses.backbone import Backbones
from resonant.analyses.modes import ModalAnalysis

EXAMPLES = Path(__file__).parents[1] / "examples"
MODELS = ["two_dof_free", "chain3_damped", "tuned_mass_damper", "cart_pendulum", "pendulum"]


def _through_json(data: dict) -> dict:
    return json.loads(json.dumps(data))


@pytest.mark.parametrize("name", MODELS)
def test_modes_round_trip(name):
    """Every field of the modal analysis survives JSON (eigenvalues complex, shapes (n, m))."""
    analysis = resonant.load(EXAMPLES / f"{name}.toml").linearize().modes()
    back = ModalAnalysis.from_dict(_through_json(analysis.to_dict()))
    assert back.to_dict() == analysis.to_dict()
    np.testing.assert_array_equal(back.eigenvalues, analysis.eigenvalues)
    np.testing.assert_array_equal(back.mode_shapes, analysis.mode_shapes)
    assert back.summary() == analysis.summary()


def test_backbones_round_trip():
    curves = resonant.load(EXAMPLES / "two_dof_cubic.toml").backbone(harmonics=3, points=6)
    back = Backbones.from_dict(_through_json(curves.to_dict()))
    assert back.to_dict() == curves.to_dict()
    for a, b in zip(back.curves, curves.curves):
        np.testing.assert_array_equal(a.coefficients, b.coefficients)


def test_tables_hold_the_results_numbers():
    pytest.importorskip("pandas")
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    sweep = model.linearize().sweep("omega", np.linspace(1, 30, 12))
    frame = sweep.to_frame()
    assert len(frame) == 12
    np.testing.assert_array_equal(frame["amplitude:x2"], sweep.amplitudes["x2"])
    np.testing.assert_array_equal(frame["phase:x1"], sweep.phases["x1"])
    sim = model.simulate(0.2, initial={"x1": 0.01})
    np.testing.assert_array_equal(sim.to_frame()["x1"], sim.states["x1"])
    branch = resonant.load(EXAMPLES / "duffing.toml").nonlinear_sweep("omega", 0.8, 1.2,
                                                                       harmonics=1, points=15)
    table = branch.to_frame()
    assert table["stable"].tolist() == branch.stable.tolist()
    np.testing.assert_array_equal(table["amplitude:x"], branch.amplitudes["x"])
