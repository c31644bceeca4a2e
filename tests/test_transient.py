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
import scipy.linalg

from conftest import EXAMPLES
from resonant.analyses.shock import pulse, shock_response_spectrum
from resonant.analyses.transient import transient_response
from resonant.api import load
from resonant.deadline import Deadline
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


def _stepped(M: np.ndarray, C: np.ndarray, K: np.ndarray, load: np.ndarray, u: np.ndarray,
             step: float) -> np.ndarray:
    """The coordinates' histories by the plain first-order-hold recursion, one step at a
    time (the march as it was written before it went in blocks), its matrices from Van
    Loan's exponential written out here."""
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    B = np.concatenate([np.zeros(n), np.linalg.solve(M, load)])
    big = np.zeros((2 * n + 2, 2 * n + 2))
    big[:2 * n, :2 * n], big[:2 * n, 2 * n], big[2 * n, 2 * n + 1] = A, B, 1 / step
    E = scipy.linalg.expm(big * step)
    Phi, F0, F1 = E[:2 * n, :2 * n], E[:2 * n, 2 * n], E[:2 * n, 2 * n + 1]
    X = np.zeros((len(u), 2 * n))
    for j in range(1, len(u)):
        X[j] = Phi @ X[j - 1] + (F0 - F1) * u[j - 1] + F1 * u[j]
    return X[:, :n]


FREE = TWO.replace("k1 = 1000", "k1 = 0").replace("c1 = 0.8", "c1 = 0")


@pytest.mark.parametrize("text", [TWO, FREE], ids=["anchored", "free"])
@pytest.mark.parametrize("samples", [2, 3, 127, 128, 129, 1000, 5001])
def test_the_march_in_blocks_is_the_step_by_step_recursion(text: str, samples: int) -> None:
    """The march in blocks (analyses/transient.py, _march) against the plain recursion it
    unrolls, with blocks of 1 to 128 samples (by the history's length and the names
    asked for), histories that end inside a block and at its end, and with a rigid-body
    mode (the free chain, whose Phi^k grow): the same numbers to 1e-12 of the
    largest |value| (rounding; both are exact for the input linear between samples)."""
    step = 1e-3
    u = 20 * np.sin(37 * step * np.arange(samples)) + 5
    k1 = 1000.0 if text is TWO else 0.0
    M = np.diag([1.0, 0.5])
    K = np.array([[k1 + 600.0, -600.0], [-600.0, 600.0]])
    C = np.array([[0.3 + (0.8 if k1 else 0.0), -0.3], [-0.3, 0.3]])
    reference = _stepped(M, C, K, np.array([0.0, 1.0]), u, step)
    system = linear_system(loads(text))
    for names in (None, ["x2"]):             # three histories, or one: other block lengths
        result = transient_response(system, "F", u, step, names=names)
        for k, q in enumerate(("x1", "x2")):
            if names is None or q in names:
                scale = np.abs(reference[:, k]).max() or 1.0
                assert np.abs(result.history[q] - reference[:, k]).max() <= 1e-12 * scale
        if names is None:
            assert np.abs(result.history["stretch"] - (reference[:, 1] - reference[:, 0])
                          ).max() <= 1e-12 * np.abs(reference).max()


SDOF = """
[parameters]
m = 2
k = 197392.088
c = 1.25
[coordinates]
x = ""
[signals]
F = "0"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2 - F*x"
D = "c*x'^2/2"
"""


def test_a_step_force_over_many_blocks_is_the_closed_form() -> None:
    """A lightly damped oscillator (f_n = 50 Hz, zeta = 1e-3) under a step force F from
    t = 0, 2 10^5 samples (1000 cycles, 1563 blocks of the march): the closed form
    x = F/k (1 - e^(-zeta w t) (cos w_d t + zeta w / w_d sin w_d t)) (any vibration text,
    e.g. Rao, Mechanical Vibrations, sec. 4.5) to 1e-11 of F/k -- the input is linear
    between samples, so the march is exact up to rounding."""
    m, k, c, F, step = 2.0, 197392.088, 1.25, 3.0, 1e-4
    t = np.arange(200_000) * step
    result = transient_response(linear_system(loads(SDOF)), "F", np.full(len(t), F), step)
    w = math.sqrt(k / m)
    zeta = c / (2 * math.sqrt(k * m))
    wd = w * math.sqrt(1 - zeta**2)
    exact = F / k * (1 - np.exp(-zeta * w * t) * (np.cos(wd * t)
                                                  + zeta * w / wd * np.sin(wd * t)))
    assert np.abs(result.history["x"] - exact).max() < 1e-11 * F / k


def test_the_march_checks_its_deadline_every_10000_samples_or_so() -> None:
    """The march in blocks still checks the time limit as it goes (every 78 blocks of
    128 samples here), not only before it starts."""
    seen: list[str] = []

    class Recorder(Deadline):
        def check(self, what: str = "", *args: object, **kwargs: object) -> None:
            seen.append(what)

    u = np.ones(200_000)
    transient_response(linear_system(loads(SDOF)), "F", u, 1e-4, deadline=Recorder())
    marching = seen.count("while marching the transient response")
    assert 200_000 // 10_000 <= marching <= 3 * 200_000 // 10_000, seen
