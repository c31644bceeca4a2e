"""The periodic solution at a fixed frequency (one Newton solve) and the "periodic" start.

The undamped cart-pendulum (examples/cart_pendulum.toml, F0 = 50, r0 = 0.1, omega = 20):

* the harmonic-balance solution agrees to 1e-4 with a shooting solution of the full
  equations: Newton's method on y(T) - y(0) = 0 with the flow of resonant's own
  nonlinear equations (scipy DOP853, rtol 1e-12), started from the harmonic-balance state;
* a simulation started on it stays on it (its peak amplitude equals the harmonic-balance
  amplitude to 1e-6, and the state after one period equals the initial state to 1e-6);
* its amplitude differs from the linear amplitude (x2: about -6 %, x1: about -38 %),
  while a run from rest beats (its peak is not a steady state).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.integrate

from conftest import EXAMPLES, run_cli
from resonant.analyses.periodic import PeriodicSolution, periodic_solution
from resonant.analyses.simulate import _periodic_start
from resonant.analyses.time_integration import NonlinearDynamics
from resonant.api import load
from resonant.deadline import NO_DEADLINE
from resonant.errors import AnalysisError
from resonant.model import Model
from resonant.system import nonlinear_system
from resonant.system.nonlinear import reference_values

CART = EXAMPLES / "cart_pendulum.toml"


@pytest.fixture(scope="module")
def model() -> Model:
    return load(CART).with_parameters(F0="50", r0="0.1")


@pytest.fixture(scope="module")
def periodic(model: Model) -> PeriodicSolution:
    return periodic_solution(nonlinear_system(model))


def _flow(model: Model, y0: np.ndarray, T: float) -> np.ndarray:
    system = NonlinearDynamics(nonlinear_system(model))
    sol = scipy.integrate.solve_ivp(system.rhs, (0.0, T), y0, method="DOP853", rtol=1e-12,
                                    atol=1e-13)
    return np.asarray(sol.y[:, -1])


def _shooting(model: Model, y0: np.ndarray, T: float) -> np.ndarray:
    """Newton on y(T; y0) - y0 = 0 (finite-difference monodromy matrix)."""
    y = y0.copy()
    for _ in range(8):
        r = _flow(model, y, T) - y
        J = np.empty((y.size, y.size))
        for j in range(y.size):
            h = 1e-7 * max(1.0, abs(y[j]))
            e = np.zeros(y.size)
            e[j] = h
            J[:, j] = (_flow(model, y + e, T) - (y + e) - r) / h
        dy = np.linalg.solve(J, -r)
        y = y + dy
        if np.linalg.norm(dy) < 1e-12 * np.linalg.norm(y):
            break
    return y


def test_harmonic_balance_agrees_with_shooting(model: Model,
                                               periodic: PeriodicSolution) -> None:
    assert periodic.residual < 1e-12 and periodic.truncation < 1e-6
    assert periodic.period == pytest.approx(2 * np.pi / 20)
    names = periodic.coordinates
    hb = np.array([periodic.initial[c] for c in names]
                  + [periodic.initial[c + "'"] for c in names])
    y0 = hb + np.concatenate([reference_values(model), np.zeros(len(names))])
    shot = _shooting(model, y0, periodic.period)
    shot[:len(names)] -= reference_values(model)
    # displacements to 1e-4 of the amplitude, velocities to 1e-4 of amplitude * omega
    scale = np.array([periodic.amplitudes[c] for c in names] * 2)
    scale[len(names):] *= 20
    assert np.max(np.abs(shot - hb) / scale) < 1e-4
    # and the orbit closes: y(T) = y(0)
    assert np.max(np.abs(_flow(model, y0, periodic.period) - y0) / scale) < 1e-6


def test_difference_to_the_linear_amplitude(periodic: PeriodicSolution) -> None:
    assert periodic.linear_amplitudes["x2"] == pytest.approx(0.451413, rel=1e-5)
    assert periodic.amplitudes["x2"] == pytest.approx(0.422422, rel=1e-5)
    assert periodic.relative_difference["x2"] == pytest.approx(-0.0642, abs=1e-3)
    assert periodic.relative_difference["x1"] == pytest.approx(-0.383, abs=1e-3)
    # undamped: the multipliers lie on the unit circle
    assert np.allclose(np.abs(periodic.multipliers), 1.0, atol=1e-6) and periodic.stable
    data = json.loads(json.dumps(periodic.to_dict(), allow_nan=False))
    assert data["harmonics"] == periodic.harmonics
    assert len(data["coefficients"]["x1"]) == periodic.harmonics + 1
    assert "-6.42%" in periodic.summary()


def test_simulation_starts_on_the_periodic_solution(model: Model,
                                                    periodic: PeriodicSolution) -> None:
    sim = model.simulate(nonlinear=True, progress=False)
    assert sim.start == "periodic"
    assert any("periodic solution" in w for w in sim.warnings)
    for c in periodic.coordinates:
        assert sim.steady_amplitudes[c] == pytest.approx(periodic.amplitudes[c], rel=1e-6)
    # the response stays on the harmonic-balance orbit over the whole run
    predicted = periodic.response(sim.t)
    for c in periodic.coordinates:
        assert np.max(np.abs(sim.states[c] - predicted[c])) < 1e-6 * periodic.amplitudes[c]
    # from rest the undamped run beats: its peak is not the periodic amplitude
    rest = model.simulate(nonlinear=True, start="rest", progress=False)
    assert abs(rest.steady_amplitudes["x2"] / periodic.amplitudes["x2"] - 1) > 1e-2
    # the linear run keeps the linear stationary start
    assert model.simulate(progress=False).start == "stationary"


def test_periodic_start_errors_and_cli(model: Model) -> None:
    with pytest.raises(AnalysisError, match="nonlinear"):
        model.simulate(start="periodic", progress=False)
    status, out, err = run_cli(["simulate", CART, "--set", "F0=50", "--set", "r0=0.1",
                                "--nonlinear", "--start", "periodic", "--json"])
    assert status == 0, err
    assert json.loads(out)["start"] == "periodic"


def test_no_periodic_solution_is_said(model: Model) -> None:
    """Far from linear (Newton diverges): the run says there is no steady state to measure."""
    far = model.with_parameters(F0="400", omega="4")
    try:
        periodic_solution(nonlinear_system(far))
    except AnalysisError:
        pass
    else:
        pytest.skip("harmonic balance converged here")
    sim = far.simulate(nonlinear=True, duration=2.0, progress=False)
    assert sim.start == "stationary"
    assert any("no steady state to measure" in w for w in sim.warnings)


def test_unstable_periodic_solution_is_not_started_on() -> None:
    """The exact rod kinematics (asin): the periodic solution at omega = 20 is unstable (a
    real Floquet multiplier of about 15), so "auto" does not start on it and says that
    there is no steady state to measure."""
    exact = load(EXAMPLES / "cart_pendulum_exact.toml").with_parameters(F0="50", r0="0.1")
    periodic = periodic_solution(nonlinear_system(exact))
    assert not periodic.stable and np.abs(periodic.multipliers).max() > 10
    warnings: list[str] = []
    assert _periodic_start(nonlinear_system(exact), "auto", False, "marginally stable",
                           exact.linearize().stationary(), warnings, NO_DEADLINE) is None
    assert any("unstable" in w and "no steady state to measure" in w for w in warnings)
    with pytest.raises(AnalysisError, match="broke down"):  # from the linear stationary state
        exact.simulate(nonlinear=True, duration=0.5, progress=False)
    on = exact.simulate(nonlinear=True, duration=0.5, start="periodic", progress=False)
    assert on.start == "periodic"
