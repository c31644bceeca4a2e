"""The export to the control tools (resonant.analyses.state_space, docs/interop.md).

References: the exported system's frequency response against resonant's own sweep (the
harmonic kernel, a different route: (K - w^2 M + i w C) z = F solved directly) to 1e-10 of
the largest amplitude; its step and impulse responses (python-control's exact
discretization of x' = A x + B u) against ``simulate`` (DOP853 at rtol 1e-9) to 1e-8 of the
peak; a closed loop in python-control against the closed form of velocity feedback.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import resonant
from resonant.analyses.simulate import simulate
from resonant.analyses.state_space import (
    MAX_STATE_SPACE_COORDINATES,
    state_space,
    to_state_space,
)
from resonant.errors import AnalysisError, ModelError

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _sweep_complex(system, omegas, name):
    """The sweep's response of ``name`` as X e^{i delta} (x = X sin(w t + delta))."""
    result = system.sweep("omega", omegas)
    return result.amplitudes[name] * np.exp(1j * result.phases[name])


@pytest.mark.parametrize("example, amplitude", [("tuned_mass_damper", "F0"),
                                                ("base_excitation", "Y"),
                                                ("chain3_damped", "F0")])
def test_frequency_response_equals_the_sweep(example: str, amplitude: str) -> None:
    """A signal s = S sin(w t) gives x = S |H| sin(w t + arg H): H S equals the sweep's
    complex amplitude of every coordinate and output to 1e-10 (the base excitation's
    signal rate y' folded into the realization, its output z = x - y through D)."""
    model = resonant.load(EXAMPLES / f"{example}.toml")
    system = model.linearize()
    exported = state_space(system)
    assert len(exported.inputs) == 1
    omegas = np.linspace(5.0, 60.0, 23)
    H = exported.frequency_response(omegas)[:, :, 0] * model.parameter_values[amplitude]
    for k, name in enumerate(exported.outputs):
        swept = _sweep_complex(system, omegas, name)
        scale = np.max(np.abs(swept))
        assert np.max(np.abs(H[:, k] - swept)) <= 1e-10 * scale, name


def test_frequency_response_of_a_matrix_model_with_named_forces() -> None:
    """A [matrices] model: the default input is the force on the loaded coordinate
    (``Q_q2``); F_C cos(w t) gives x = |H| F cos(w t + arg H)."""
    text = """
[parameters]
omega = 1
[matrices]
M = [[2, 0, 0], [0, 1, 0], [0, 0, 1]]
K = [[300, -100, 0], [-100, 200, -100], [0, -100, 100]]
C = "0.02*M + 0.001*K"
[[harmonic]]
omega = "omega"
F_C = { q2 = 3 }
[outputs]
stretch = "q3 - q2"
"""
    system = resonant.loads(text).linearize()
    exported = state_space(system)
    assert exported.inputs == ("Q_q2",)
    assert exported.outputs == ("q1", "q2", "q3", "stretch")
    omegas = np.linspace(1.0, 25.0, 31)
    H = 3.0 * exported.frequency_response(omegas)[:, :, 0] * 1j  # cos = sin shifted by pi/2
    for k, name in enumerate(exported.outputs):
        swept = _sweep_complex(system, omegas, name)
        assert np.max(np.abs(H[:, k] - swept)) <= 1e-10 * np.max(np.abs(swept)), name


def test_control_state_space_has_the_names_and_the_same_response() -> None:
    control = pytest.importorskip("control")
    system = resonant.load(EXAMPLES / "tuned_mass_damper.toml").linearize()
    exported = to_state_space(system, library="control")
    assert isinstance(exported, control.StateSpace)
    assert exported.input_labels == ["F"]
    assert exported.output_labels == ["x1", "x2", "stroke"]
    assert exported.state_labels == ["x1", "x2", "x1'", "x2'"]
    omegas = np.array([20.0, 31.6, 45.0])
    ours = state_space(system).frequency_response(omegas)[:, :, 0]
    theirs = np.array([exported(1j * w)[:, 0] for w in omegas])
    assert np.allclose(ours, theirs, rtol=1e-12, atol=0)


def test_scipy_state_space_without_names() -> None:
    import scipy.signal

    system = resonant.load(EXAMPLES / "base_excitation.toml").linearize()
    exported = to_state_space(system, library="scipy")
    assert isinstance(exported, scipy.signal.StateSpace)
    model = state_space(system)
    for key in "ABCD":
        assert np.array_equal(getattr(exported, key), getattr(model, key))


def _step_model() -> resonant.Model:
    text = (EXAMPLES / "tuned_mass_damper.toml").read_text(encoding="utf-8")
    return resonant.loads(text.replace('F = "F0*sin(omega*t)"', 'F = "F0"'))


def test_step_response_equals_simulate() -> None:
    """A constant signal switched on at t = 0 from rest is F0 times the step response."""
    control = pytest.importorskip("control")
    system = _step_model().linearize()
    run = simulate(system, 0.5, start="rest")
    exported = to_state_space(system)
    response = control.step_response(exported * 100.0, T=run.t)
    for k, name in enumerate(exported.output_labels):
        history = np.asarray(run.states[name])
        error = np.max(np.abs(response.outputs[k, 0] - history))
        assert error <= 1e-8 * np.max(np.abs(history)), name


def test_impulse_response_equals_simulate_from_the_impulse_velocity() -> None:
    """An impulse I on x1 leaves the system at rest with q'(0+) = M^-1 [I, 0]."""
    control = pytest.importorskip("control")
    text = (EXAMPLES / "tuned_mass_damper.toml").read_text(encoding="utf-8")
    model = resonant.loads(text.replace('F0 = "100 N"', 'F0 = "0 N"'))
    system = model.linearize()
    run = simulate(system, 0.5, start="rest",
                   initial={"x1'": 1.0 / model.parameter_values["m1"]})
    response = control.impulse_response(to_state_space(system, outputs=["x1", "x2"]), T=run.t)
    for k, name in enumerate(("x1", "x2")):
        history = np.asarray(run.states[name])
        error = np.max(np.abs(response.outputs[k, 0] - history))
        assert error <= 1e-8 * np.max(np.abs(history)), name


def test_parameter_values_and_rates_as_outputs() -> None:
    system = resonant.load(EXAMPLES / "base_excitation.toml").linearize()
    stiff = state_space(system, parameters={"k": 16000.0}, outputs=["x", "x'", "z"])
    assert stiff.A[1, 0] == -1600.0
    w = np.array([7.0, 35.0])
    H = stiff.frequency_response(w)[:, :, 0]
    assert np.allclose(H[:, 1], 1j * w * H[:, 0], rtol=1e-12)
    assert np.allclose(H[:, 2], H[:, 0] - 1.0, rtol=1e-12)
    # x'' = (k (y - x) + c (y' - x'))/m follows the base velocity y': no proper form
    with pytest.raises(AnalysisError, match="x''"):
        state_space(system, outputs=["x''"])
    forced = resonant.load(EXAMPLES / "tuned_mass_damper.toml").linearize()
    H2 = state_space(forced, outputs=["x1", "x1''"]).frequency_response(w)[:, :, 0]
    assert np.allclose(H2[:, 1], -(w**2) * H2[:, 0], rtol=1e-12)


def test_closed_loop_velocity_feedback_in_python_control() -> None:
    """The tuned-mass-damper's main mass with an active force -g x1' (closed by
    control.feedback): at omega1 its receptance is the closed form of the loop."""
    control = pytest.importorskip("control")
    model = resonant.load(EXAMPLES / "tuned_mass_damper.toml")
    system = model.linearize()
    plant = to_state_space(system, outputs=["x1'", "x1"])
    gain = 200.0
    # u = r - [g, 0] y, y = [x1', x1]: control.feedback closes the loop
    closed = control.feedback(plant, np.array([[gain, 0.0]]), sign=-1)
    w = model.parameter_values["omega1"]
    num = system.numeric()
    M, C, K = (np.asarray(a, dtype=float) for a in (num.M, num.C, num.K))
    C_active = C.copy()
    C_active[0, 0] += gain
    expected = np.linalg.solve(K - w**2 * M + 1j * w * C_active, [1.0, 0.0])[0]
    assert abs(complex(closed(1j * w)[1, 0]) - expected) <= 1e-10 * abs(expected)


def test_unknown_input_and_output_are_model_errors() -> None:
    system = resonant.load(EXAMPLES / "tuned_mass_damper.toml").linearize()
    with pytest.raises(ModelError, match="neither a signal"):
        state_space(system, inputs=["G"])
    with pytest.raises(ModelError, match="'speed' is not an output"):
        state_space(system, outputs=["speed"])
    with pytest.raises(ModelError, match="library"):
        to_state_space(system, library="matlab")


def test_force_inputs_on_coordinates_of_an_energy_model() -> None:
    system = resonant.load(EXAMPLES / "tuned_mass_damper.toml").linearize()
    exported = state_space(system, inputs=["F", "Q_x2"])
    assert exported.inputs == ("F", "Q_x2")
    assert exported.B[:, 0].tolist() == pytest.approx([0, 0, 0.01, 0])
    assert exported.B[:, 1].tolist() == pytest.approx([0, 0, 0, 0.2])


def test_a_large_model_gets_a_clear_message() -> None:
    import scipy.sparse as sp

    from resonant.system.base import NumericEOM

    n = MAX_STATE_SPACE_COORDINATES + 1
    eye = sp.identity(n, format="csr")
    system = NumericEOM(tuple(f"q{i}" for i in range(n)), eye, 0 * eye, eye)
    with pytest.raises(AnalysisError, match="sparse model has 2001 coordinates.*reduced"):
        state_space(system, inputs=["q1"])


def test_an_output_that_follows_an_input_rate_is_refused() -> None:
    """A load on the signal's second rate (base acceleration in absolute coordinates
    through the kinetic energy) makes x' follow u': refused by name."""
    text = """
[parameters]
m = 1
k = 100
[coordinates]
x = "x"
[signals]
y = "sin(t)"
[energy]
T = "m*(x' + y')^2/2"
U = "k*x^2/2"
"""
    system = resonant.loads(text).linearize()
    exported = state_space(system, outputs=["x"])
    assert exported.D.tolist() == [[-1.0]]  # x = -y + (a strictly proper part)
    with pytest.raises(AnalysisError, match="'x'' follows the rate"):
        state_space(system, outputs=["x'"])
    H = exported.frequency_response([3.0])[0, 0, 0]
    assert H == pytest.approx(9.0 / (100.0 - 9.0), rel=1e-12)  # -m s^2 / (m s^2 + k)


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 4), st.integers(0, 2**32 - 1))
def test_random_matrix_models_agree_with_the_harmonic_kernel(n: int, seed: int) -> None:
    """Property: H(i w) from the state space equals (K - w^2 M + i w C)^-1 for random
    symmetric positive definite M, K and a damping matrix C."""
    rng = np.random.default_rng(seed)
    a, b, c = (rng.standard_normal((n, n)) for _ in range(3))
    M, K, C = a @ a.T + n * np.eye(n), b @ b.T + np.eye(n), 0.1 * (c @ c.T)
    from resonant.system.base import NumericEOM

    system = NumericEOM(tuple(f"q{i}" for i in range(n)), M, C, K)
    exported = state_space(system)
    w = float(rng.uniform(0.1, 3.0))
    H = exported.frequency_response([w])[0]
    expected = np.linalg.inv(K - w**2 * M + 1j * w * C)
    assert np.allclose(H, expected, rtol=1e-9, atol=1e-12 * np.max(np.abs(expected)))
