"""Time simulation: linear and full nonlinear, against closed forms and the stationary solution.

Tolerances: integrations run at rtol = 1e-9, so closed-form time histories are
compared to 1e-6 of the amplitude; steady amplitudes of damped runs to 0.5%
(the remaining transient); "small oscillations hold" means |difference| < 1%.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES, run_cli
from resonant.errors import AnalysisError, ModelError
from resonant.api import load, loads
from resonant.api import simulate as simulate_system
from resonant.analyses.simulate import Simulation, parse_initial

OSCILLATOR = """
[parameters]
m = {m}
k = {k}
c = {c}
F0 = 2
w = {w}
[coordinates]
x = "displacement"
[signals]
F = "F0*sin(w*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
name = "F"
generalized = {{ x = "F" }}
"""


def simulate(model, *args, **kwargs):
    """The simulation of the model's linear system, as the user calls it (with views)."""
    return simulate_system(model.linearize(), *args, **kwargs)


def test_damped_linear_simulation_converges_to_the_stationary_solution():
    """Rao, Mechanical Vibrations, Sect. 3.6 (base excitation): X = 4.0608e-3 m, Z = 8.7515e-3 m
    (examples/base_excitation.toml); from rest, the transient decays to < 0.5 %."""
    sim = simulate(load(EXAMPLES / "base_excitation.toml"))
    assert sim.start == "rest" and not sim.nonlinear
    assert sim.steady_amplitudes["x"] == pytest.approx(4.0608e-3, rel=5e-3)
    assert sim.steady_amplitudes["z"] == pytest.approx(8.7515e-3, rel=5e-3)
    for name in ("x", "z"):
        assert abs(sim.relative_difference[name]) < 5e-3
    # and it really started from rest: the first samples are far from the prediction
    assert sim.states["x"][0] == 0.0
    assert sim.linear_response["x"][0] != pytest.approx(0.0, abs=1e-4)


@settings(max_examples=5, deadline=None)
@given(m=st.floats(0.5, 5.0), wn=st.floats(5.0, 20.0), zeta=st.floats(0.1, 0.5),
       r=st.floats(0.3, 3.0))
def test_damped_oscillator_amplitude_property(m, wn, zeta, r):
    """X = F0 / sqrt((k - m w^2)^2 + (c w)^2) for every damped 1-DoF oscillator."""
    k, c, w = m * wn**2, 2 * zeta * m * wn, r * wn
    sim = simulate(loads(OSCILLATOR.format(m=repr(m), k=repr(k), c=repr(c), w=repr(w))))
    expected = 2 / math.hypot(k - m * w**2, c * w)
    assert sim.steady_amplitudes["x"] == pytest.approx(expected, rel=5e-3)


def test_undamped_linear_run_starts_stationary_and_reproduces_the_reference():
    """Reference exercise (docs/reference-exercise.md), Eq. (48): X2 = 0.0451 m; X1 from
    Eqs. (42)-(47)."""
    sim = simulate(load(EXAMPLES / "cart_pendulum.toml"), duration=2.0, periods=3)
    assert sim.start == "stationary"
    assert any("stationary solution's initial state" in w for w in sim.warnings)
    assert sim.steady_amplitudes["x2"] == pytest.approx(0.0451, rel=2e-3)
    assert max(abs(d) for d in sim.relative_difference.values()) < 1e-6
    err = np.max(np.abs(sim.states["x2"] - sim.linear_response["x2"]))
    assert err < 1e-6 * sim.linear_amplitudes["x2"]


def test_nonlinear_agrees_for_small_and_differs_for_large_amplitudes():
    small = simulate(load(EXAMPLES / "cart_pendulum.toml"), duration=3.0, nonlinear=True)
    assert small.nonlinear
    assert small.linear_amplitudes["x2"] == pytest.approx(0.0451, rel=2e-3)
    assert abs(small.relative_difference["x2"]) < 0.01
    assert abs(small.relative_difference["phi"]) < 0.01
    large_model = load(EXAMPLES / "cart_pendulum.toml", overrides={"F0": "50", "r0": "0.1"})
    large = simulate(large_model, duration=3.0, nonlinear=True)
    linear = simulate(large_model, duration=3.0)
    assert abs(linear.relative_difference["x2"]) < 1e-6  # the linear model scales exactly
    # undamped: the run starts on the periodic solution of the full equations,
    # whose x2 amplitude is 6.4 % below the linear one; from the linear stationary state
    # the run beats, and its peak (+11 %) is not a steady state
    assert large.start == "periodic"
    assert large.relative_difference["x2"] == pytest.approx(-0.0642, abs=1e-3)
    assert any("small oscillations do not hold" in w for w in large.warnings)
    beating = simulate(large_model, duration=3.0, nonlinear=True, start="stationary")
    assert beating.relative_difference["x2"] > 0.05


def test_nonlinear_equals_linear_for_a_linear_model():
    """Quadratic energies: the full equations are the linear ones (outputs with signals too)."""
    model = load(EXAMPLES / "base_excitation.toml")
    a = simulate(model, duration=2.0, nonlinear=True)
    b = simulate(model, duration=2.0)
    for name in ("x", "z"):
        scale = b.steady_amplitudes[name]
        assert np.max(np.abs(a.states[name] - b.states[name])) < 1e-6 * scale


def test_nonlinear_pendulum_output_with_a_signal():
    """Landau-Lifshitz Sect. 5 Problem 3a / examples/pendulum.toml: X_bob = 0.020395 m."""
    sim = simulate(load(EXAMPLES / "pendulum.toml"), duration=12.0, nonlinear=True)
    assert sim.steady_amplitudes["x_bob"] == pytest.approx(0.020395, rel=5e-3)
    assert sim.steady_amplitudes["theta"] == pytest.approx(0.012994, rel=5e-3)


def test_nonlinear_blow_up_is_reported_with_the_time():
    model = load(EXAMPLES / "cart_pendulum_exact.toml", overrides={"F0": "50", "r0": "0.1"})
    with pytest.raises(AnalysisError, match=r"broke down at t = [0-9.]+ s \(x1 = .*x2 = "):
        simulate(model, duration=2.0, nonlinear=True)
    code, out, err = run_cli(["simulate", EXAMPLES / "cart_pendulum_exact.toml", "--nonlinear",
                              "--set", "F0=50", "--set", "r0=0.1", "--duration", "2"])
    assert code == 3 and "broke down at t =" in err and "Traceback" not in err


def test_non_harmonic_signal_against_the_closed_form():
    """m x'' + k x = F0 exp(-a t) from rest (Duhamel's integral, e.g. Rao Sect. 4.5):
    x = F0/(m (w^2 + a^2)) (exp(-a t) - cos(w t) + (a/w) sin(w t))."""
    model = loads("""
[parameters]
m = 2
k = 50
F0 = 3
a = 1.5
[coordinates]
x = "displacement"
[signals]
F = "F0*exp(-a*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
[[force]]
name = "F"
generalized = { x = "F" }
""")
    sim = simulate(model, duration=4.0)
    assert sim.start == "rest" and sim.linear_amplitudes == {} and sim.relative_difference == {}
    assert any("not sums of harmonics" in w for w in sim.warnings)
    w, t = 5.0, sim.t
    exact = 3 / (2 * (w**2 + 1.5**2)) * (np.exp(-1.5 * t) - np.cos(w * t)
                                         + 1.5 / w * np.sin(w * t))
    assert np.max(np.abs(sim.states["x"] - exact)) < 1e-6 * np.max(np.abs(exact))
    nonlinear = simulate(model, duration=4.0, nonlinear=True)
    assert np.max(np.abs(nonlinear.states["x"] - exact)) < 1e-6 * np.max(np.abs(exact))


def test_free_vibration_from_a_given_initial_state():
    """Rao Sect. 5.3: x1(0) = a, x2(0) = 0 -> x1 = a/2 (cos w1 t + cos w2 t), w1 = 20, w2 = 20 sqrt 3."""
    model = load(EXAMPLES / "two_dof_free.toml")
    sim = simulate(model, duration=1.0, initial={"x1": "0.01", "x2": 0})
    assert sim.start == "given" and sim.initial["x1"] == 0.01 and sim.initial["x1'"] == 0.0
    w1, w2, t = 20.0, 20.0 * math.sqrt(3), sim.t
    assert np.max(np.abs(sim.states["x1"] - 0.005 * (np.cos(w1 * t) + np.cos(w2 * t)))) < 1e-8
    assert np.max(np.abs(sim.states["x2"] - 0.005 * (np.cos(w1 * t) - np.cos(w2 * t)))) < 1e-8


def test_parse_initial_errors_and_velocities():
    model = load(EXAMPLES / "two_dof_free.toml")
    q, v = parse_initial(model.coordinates, model.parameter_values, {"x2'": "k/m/100"})
    assert np.isnan(q).all() and v[1] == pytest.approx(4.0)
    with pytest.raises(ModelError, match="'y' is not a coordinate"):
        parse_initial(model.coordinates, model.parameter_values, {"y": 1})
    with pytest.raises(ModelError, match="unknown name"):
        parse_initial(model.coordinates, model.parameter_values, {"x1": "bogus*2"})


def test_matrix_model_simulates_linear_but_not_nonlinear():
    model = loads("""
[coordinates]
x = "displacement"
[matrices]
M = [[1]]
K = [[4]]
C = [[0.8]]
[[harmonic]]
omega = 3
F_S = [1]
F_C = [0]
""")
    sim = simulate(model, duration=30.0)
    assert sim.steady_amplitudes["x"] == pytest.approx(1 / abs(4 - 9 + 2.4j), rel=5e-3)
    with pytest.raises(AnalysisError, match="matrices"):
        simulate(model, nonlinear=True)


def test_result_is_json_able_and_displays():
    sim = simulate(load(EXAMPLES / "base_excitation.toml"), duration=1.0)
    assert isinstance(sim, Simulation)
    data = json.loads(json.dumps(sim.to_dict(), allow_nan=False))
    assert data["t_end"] == pytest.approx(1.0)
    assert "<table>" in sim._repr_html_() and "z" in sim._repr_html_()
    assert any("shorter than two measurement windows" in w for w in sim.warnings)


# -- command line ------------------------------------------------------------------------

def test_cli_json_keys():
    code, out, err = run_cli(["simulate", EXAMPLES / "cart_pendulum.toml", "--json",
                              "--duration", "1.5", "--nonlinear"])
    assert code == 0, err
    data = json.loads(out)
    for key in ("t_end", "steady_amplitudes", "linear_amplitudes", "relative_difference",
                "nonlinear", "warnings"):
        assert key in data
    assert data["nonlinear"] is True and data["t_end"] == pytest.approx(1.5)
    assert set(data["steady_amplitudes"]) == {"x1", "x2", "phi"}
    assert data["linear_amplitudes"]["x2"] == pytest.approx(0.0451, rel=2e-3)
    assert abs(data["relative_difference"]["x2"]) < 0.01


def test_cli_writes_plot_and_csv(tmp_path):
    png, svg, table = tmp_path / "sim.png", tmp_path / "sim.svg", tmp_path / "sim.csv"
    code, out, err = run_cli(["simulate", EXAMPLES / "base_excitation.toml", "--duration", "1",
                              "--plot", png, "--csv", table])
    assert code == 0, err
    assert "steady amplitudes" in out and f"wrote {png}" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    lines = table.read_text().splitlines()
    assert lines[0] == "t,x,z,x (linear stationary),z (linear stationary)"
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert rows.shape[0] > 1000 and rows[-1, 0] == pytest.approx(1.0)
    assert np.ptp(rows[:, 1]) > 1e-3  # the motion is there, not zeros
    code, _, err = run_cli(["simulate", EXAMPLES / "base_excitation.toml", "--duration", "0.5",
                            "--plot", svg])
    assert code == 0, err
    assert "<svg" in svg.read_text()[:500]


@pytest.mark.parametrize("args, message", [
    (["--plot", "out.txt"], "--plot needs"),
    (["--initial", "nope=1"], "not a coordinate"),
    (["--initial", "x"], "NAME=VALUE"),
])
def test_cli_bad_input_exits_2(args, message):
    code, out, err = run_cli(["simulate", EXAMPLES / "base_excitation.toml", *args])
    assert code == 2 and message in err and "Traceback" not in err


def test_cli_negative_duration_is_refused():
    code, _, err = run_cli(["simulate", EXAMPLES / "base_excitation.toml", "--duration", "-1"])
    assert code == 2 and "positive" in err


def test_cli_choices_are_the_options_record():
    """The command line offers exactly the values the library's record accepts."""
    import argparse

    import resonant.cli.simulate as cli_simulate
    from resonant.model.options import INTEGRATORS, START_MODES, SimulationOptions

    parser = argparse.ArgumentParser()
    cli_simulate.register(parser.add_subparsers(), argparse.ArgumentParser(add_help=False))
    sub = parser._subparsers._group_actions[0].choices["simulate"]  # type: ignore[union-attr]
    choices = {a.dest: a.choices for a in sub._actions if a.choices}
    assert tuple(choices["start"]) == START_MODES and tuple(choices["method"]) == INTEGRATORS
    for start in START_MODES:
        SimulationOptions(start=start)
    with pytest.raises(AnalysisError, match="start must be one of"):
        SimulationOptions(start="middle")
