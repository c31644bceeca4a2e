"""The exact transient response (analyses/transient.py).

* A single-DOF component on a base under a half-sine base acceleration is the SRS
  oscillator itself: the largest absolute acceleration and relative displacement of the
  model (its state-transition march) equal the shock response spectrum at its f_n and
  zeta (the ramp-invariant filter, tests/test_shock.py) to 1e-5 (the SRS refines its peak
  between samples; 500 samples per cycle here).
* A 2-DOF chain under a force history linear between samples: scipy's solve_ivp (DOP853,
  rtol 1e-11) on the same piecewise-linear force agrees to 1e-7 of the largest value.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate

from conftest import EXAMPLES
from resonant.analyses.shock import pulse, shock_response_spectrum
from resonant.analyses.transient import transient_response
from resonant.api import load
from resonant.errors import AnalysisError
from resonant.model import loads
from resonant.system import linear_system


def test_sdof_on_base_is_the_srs_oscillator() -> None:
    system = load(EXAMPLES / "shaker_gevs.toml").linearize()
    step = 1e-5
    _, a = pulse("half-sine", 100.0, 0.011, step, total=0.011)
    result = transient_response(system, "y", a, step, derivative=2)
    k, m, c = 1579136.704, 1.0, 125.6637
    fn = math.sqrt(k / m) / (2 * math.pi)
    zeta = c / (2 * math.sqrt(k * m))
    acc = shock_response_spectrum(a, step, [fn], damping=zeta)
    rel = shock_response_spectrum(a, step, [fn], damping=zeta, quantity="relative displacement")
    assert result.largest["a"] == pytest.approx(acc.primary[0], rel=1e-5)
    assert result.largest["z"] == pytest.approx(rel.primary[0], rel=1e-5)
    assert result.largest["table"] == pytest.approx(100.0, rel=1e-12)


TWO = """
[parameters]
m1 = 1
m2 = 0.5
k1 = 1000
k2 = 600
c1 = 0.8
c2 = 0.3
[coordinates]
x1 = ""
x2 = ""
[signals]
F = "0"
[energy]
T = "m1*x1'^2/2 + m2*x2'^2/2"
U = "k1*x1^2/2 + k2*(x2 - x1)^2/2 - F*x2"
D = "c1*x1'^2/2 + c2*(x2' - x1')^2/2"
[outputs]
stretch = "x2 - x1"
"""


def test_two_dof_against_solve_ivp() -> None:
    step = 1e-3
    t = np.arange(0, 1.0 + step / 2, step)
    force = np.where(t < 0.2, 50 * t, 10.0) * (1 + 0.3 * np.sin(37 * t))
    result = transient_response(linear_system(loads(TWO)), "F", force, step)
    M = np.diag([1.0, 0.5])
    K = np.array([[1600.0, -600.0], [-600.0, 600.0]])
    C = np.array([[1.1, -0.3], [-0.3, 0.3]])

    def rhs(time: float, y: np.ndarray) -> np.ndarray:
        f = np.interp(time, t, force)
        q, v = y[:2], y[2:]
        return np.concatenate([v, np.linalg.solve(M, np.array([0.0, f]) - C @ v - K @ q)])

    reference = scipy.integrate.solve_ivp(rhs, (0, t[-1]), np.zeros(4), method="DOP853",
                                          t_eval=t, rtol=1e-11, atol=1e-14, max_step=step)
    scale = np.abs(reference.y[1]).max()
    assert np.abs(result.history["x2"] - reference.y[1]).max() < 1e-7 * scale
    assert np.abs(result.history["stretch"] - (reference.y[1] - reference.y[0])).max() \
        < 1e-7 * scale


def test_errors() -> None:
    system = linear_system(loads(TWO))
    with pytest.raises(AnalysisError, match="neither a signal nor a coordinate"):
        transient_response(system, "G", [0, 1], 1e-3)
    with pytest.raises(AnalysisError, match="finite samples"):
        transient_response(system, "F", [0, np.nan], 1e-3)
    base = load(EXAMPLES / "shaker_gevs.toml").linearize()
    with pytest.raises(AnalysisError, match="higher derivative"):
        transient_response(base, "y", [0, 1, 0], 1e-3, derivative=0)
