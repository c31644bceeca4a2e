"""One linear-system type, one set of checks at every swept value, a deadline on
every command.  (Layering itself is checked in tests/test_architecture.py.)"""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import EXAMPLES, run_cli

import resonant
from resonant.deadline import AnalysisTimeout, Deadline
from resonant.errors import AnalysisError
from resonant.api import loads
from resonant.system import LinearEOM, LinearSystem, MatrixEOM, NumericEOM

SDOF = """
[parameters]
m = 1
k = 100
c = 2
omega = 5
[coordinates]
x = "displacement"
[signals]
F = "sin(omega*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
generalized = { x = "F" }
"""

MATRIX = """
[parameters]
w = 3
[matrices]
M = [[1, 0], [0, 2]]
K = [[200, -100], [-100, 100]]
C = [[0.2, 0], [0, 0.1]]
[[harmonic]]
omega = "w"
F_S = [0, 1]
"""


def test_both_kinds_are_one_type_with_json_and_reprs():
    energy, matrix = loads(SDOF).linearize(), loads(MATRIX).linearize()
    assert isinstance(energy, LinearEOM) and isinstance(matrix, MatrixEOM)
    for eom in (energy, matrix):
        assert isinstance(eom, LinearSystem)
        data = eom.to_dict()
        assert data["coordinates"] == list(eom.coordinates) and len(data["M"]) == eom.n
        json.dumps(data)
        assert eom._repr_latex_().startswith("$")
        assert isinstance(eom.numeric(), NumericEOM)
        # the conveniences are delegates of the analyses, for both kinds alike
        assert eom.stationary().amplitudes and eom.modes().natural_frequencies.size == eom.n


def test_numeric_system_is_a_linear_system_too():
    num = loads(SDOF).linearize().numeric()
    assert num.numeric() is num
    # with its model it can still be swept over any parameter, e.g. the stiffness
    result = num.sweep("k", [100.0, 400.0])
    assert result.amplitudes["x"][1] < result.amplitudes["x"][0]


def test_sweep_checks_the_mass_matrix_at_every_value():
    """A sweep of m through 0 stops at m = 0 as `solve --set m=0` does (exit 3)."""
    eom = loads(SDOF).linearize()
    with pytest.raises(AnalysisError, match=r"singular at m = 0"):
        eom.sweep("m", np.linspace(-1, 1, 5))
    code, _, err = run_cli(["solve", EXAMPLES / "chain3_damped.toml", "--set", "m=0"])
    assert code == 3 and "singular" in err
    code, _, err = run_cli(["sweep", EXAMPLES / "chain3_damped.toml", "--param", "m",
                            "--from", "-1", "--to", "1", "--points", "5"])
    assert code == 3 and "singular at m = 0" in err


def test_sweep_warns_of_a_negative_mass():
    result = loads(SDOF).linearize().sweep("m", np.array([-2.0, -1.0, 1.0]))
    assert any("not positive definite at m = -2" in w for w in result.warnings)


def test_deadline_covers_the_analyses():
    eom = loads(SDOF).linearize()
    eom.numeric()  # derived and compiled: what remains is the analysis itself
    with pytest.raises(AnalysisTimeout, match="while solving the harmonic systems"):
        eom.sweep("omega", np.linspace(1, 20, 90_000), method="banded",
                  deadline=Deadline(0.5))
    with pytest.raises(AnalysisTimeout):
        loads(SDOF).simulate(duration=1e5, deadline=Deadline(2.0))


def test_simulate_honours_the_command_line_timeout(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(SDOF)
    code, _, err = run_cli(["simulate", path, "--duration", "1e5", "--timeout", "0.5"])
    assert code == 3 and "exceeded the time limit of 0.5 s" in err and "--timeout" in err


def test_public_names_are_stable():
    """Every name the package exports is the same object on every access."""
    for name in resonant.__all__:
        if name != "__version__":
            assert getattr(resonant, name) is getattr(resonant, name)
    assert callable(resonant.sweep) and callable(resonant.linear_system)
