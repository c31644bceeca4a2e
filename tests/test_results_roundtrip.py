"""Results saved as JSON come back: ``from_dict(to_dict())`` gives the same result, and the
tabular results are tables (``to_frame()``) holding the same numbers as the result."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

import numpy as np
import pytest

import resonant
from resonant.analyses.backbone import Backbones
from resonant.analyses.fatigue import (
    RainflowDamage,
    SNCurve,
    SpectralFatigue,
    rainflow_damage,
    spectral_fatigue,
)
from resonant.analyses.modes import ModalAnalysis
from resonant.analyses.nonlinear_response import NonlinearResponse
from resonant.analyses.periodic import PeriodicSolution, periodic_solution
from resonant.analyses.periodic_load import PeriodicResponse, periodic_load_response
from resonant.analyses.random_response import RandomResponse
from resonant.analyses.shock import QUANTITIES, ShockSpectrum, pulse, shock_response_spectrum
from resonant.analyses.simulate import Simulation
from resonant.analyses.slow_sweep import SweptState, swept_state
from resonant.analyses.special_points import SpecialPoint
from resonant.analyses.stationary import StationarySolution
from resonant.analyses.sweep import FrequencyResponse
from resonant.analyses.transient import TransientResponse, shock_response
from resonant.errors import AnalysisError
from resonant.model.load_spec import PeriodicSpec, ShockSpec
from resonant.system import NumericEOM, NumericHarmonic, nonlinear_system

EXAMPLES = Path(__file__).parents[1] / "examples"
MODELS = ["two_dof_free", "chain3_damped", "tuned_mass_damper", "cart_pendulum", "pendulum"]


#: a model excited at two frequencies (omega and 3 omega): two harmonics per value
TWO_HARMONICS = """
[parameters]
m = 1
k = 100
c = 0.5
omega = 3
[coordinates]
x = "displacement"
[signals]
F = "sin(omega*t) + 0.3*cos(3*omega*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
generalized = { x = "F" }
[outputs]
v = "x'"
"""

#: undamped: no stationary solution at omega = 10 (the natural frequency), a skipped point
UNDAMPED = TWO_HARMONICS.replace("c = 0.5", "c = 0")


def _through_json(data: dict) -> dict:
    # allow_nan=False: the saved result must be valid JSON (no NaN, no Infinity)
    return json.loads(json.dumps(data, allow_nan=False))


def _reduced_sweep():
    """A reduced-order sweep of a damped chain of 8 masses (an estimated error, a tolerance)."""
    n = 8
    K = (np.diag(np.r_[2 * np.ones(n - 1), 1.0]) - np.diag(np.ones(n - 1), 1)
         - np.diag(np.ones(n - 1), -1)) * 100
    force = np.zeros(n)
    force[-1] = 1.0
    eom = NumericEOM(tuple(f"q{i + 1}" for i in range(n)), np.eye(n), 0.01 * K + 0.1 * np.eye(n),
                     K, (NumericHarmonic(1.0, force, np.zeros(n)),))
    return eom.sweep("omega", np.linspace(0.5, 30, 80), method="reduced")


def _sweeps():
    """(id, sweep) of several bundled examples, two harmonics and a sweep with skipped points."""
    for name in ["cart_pendulum", "tuned_mass_damper", "chain3_damped", "duffing",
                 "two_dof_cubic"]:
        yield name, lambda name=name: resonant.load(EXAMPLES / f"{name}.toml").linearize().sweep(
            "omega", np.linspace(0.5, 40, 80))
    yield "absorber-k2", lambda: resonant.load(EXAMPLES / "absorber.toml").linearize().sweep(
        "k2", np.linspace(50, 400, 36))
    yield "log", lambda: resonant.load(EXAMPLES / "chain3_damped.toml").linearize().sweep(
        "omega", np.geomspace(1, 100, 50))
    yield "two-harmonics", lambda: resonant.loads(TWO_HARMONICS).linearize().sweep(
        "omega", np.linspace(1, 12, 45))
    yield "skipped", lambda: resonant.loads(UNDAMPED).linearize().sweep(
        "omega", np.linspace(5, 15, 21))
    yield "one-value", lambda: resonant.load(EXAMPLES / "cart_pendulum.toml").linearize().sweep(
        "omega", [7.0])
    yield "reduced", lambda: _reduced_sweep()
    yield "no-excitation", lambda: resonant.load(EXAMPLES / "two_dof_free.toml").linearize(
        ).sweep("k", [1000.0, 2000.0])


#: each computed once, on first use (the results are frozen: the tests share them)
SWEEPS = {name: cache(make) for name, make in _sweeps()}


def _assert_same_sweep(back: FrequencyResponse, sweep: FrequencyResponse) -> None:
    assert back.to_dict() == sweep.to_dict()
    for name in ("values", "response", "harmonic_omegas"):
        np.testing.assert_array_equal(getattr(back, name), getattr(sweep, name))
        assert getattr(back, name).dtype == getattr(sweep, name).dtype
    for name in sweep.quantities:
        np.testing.assert_array_equal(back.amplitudes[name], sweep.amplitudes[name])
        np.testing.assert_array_equal(back.phases[name], sweep.phases[name])
    for name in ("parameter", "quantities", "method", "frequency_sweep", "frequency_scale",
                 "skipped", "warnings", "log", "title", "coordinates", "estimated_error",
                 "tolerance", "peaks", "antiresonances", "unit"):
        assert getattr(back, name) == getattr(sweep, name), name
    if sweep.natural_frequencies is None:
        assert back.natural_frequencies is None
    else:
        np.testing.assert_array_equal(back.natural_frequencies, sweep.natural_frequencies)
    assert back.summary() == sweep.summary()


#: a square-wave force: the equation of motion without a stationary solution
SQUARE = TWO_HARMONICS.replace('"sin(omega*t) + 0.3*cos(3*omega*t)"', '"abs(sin(omega*t))"')


@pytest.mark.parametrize("source", [*(f"{name}.toml" for name in [*MODELS, "absorber",
                                                                  "base_excitation"]),
                                    TWO_HARMONICS, SQUARE])
def test_stationary_round_trip(source):
    """The stationary solution back from JSON: every number bit for bit, the outputs'
    responses (``output_harmonics``) and the text ``resonant solve`` prints."""
    if source.endswith(".toml"):
        model = resonant.load(EXAMPLES / source)
    else:
        model = resonant.loads(source)
    solution = model.linearize().stationary()
    saved = _through_json(solution.to_dict())
    back = StationarySolution.from_dict(saved)
    again = back.to_dict()
    del saved["symbolic"]  # the symbolic form is text for a reader, not read back
    assert "symbolic" not in again
    assert again == saved
    assert back.output_harmonics == solution.output_harmonics
    assert back.available == solution.available
    np.testing.assert_array_equal(back.eigenvalues, solution.eigenvalues)
    for t in (0.0, 0.37, 2.0):
        for name, value in back.response(t).items():
            assert value == solution.response(t)[name], name
    title = solution.summary().splitlines()[0].split("  (")[0]  # the file name is not saved
    assert back.summary().splitlines()[0] == title


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


def test_modes_and_backbones_from_dict_name_what_is_missing():
    data = _through_json(resonant.load(EXAMPLES / "two_dof_free.toml").linearize().modes(
        ).to_dict())
    with pytest.raises(AnalysisError, match="ModalAnalysis has no key 'mode_shapes'"):
        ModalAnalysis.from_dict({k: v for k, v in data.items() if k != "mode_shapes"})
    with pytest.raises(AnalysisError, match="'mode_shapes' has shape"):
        ModalAnalysis.from_dict({**data, "mode_shapes": data["mode_shapes"][:1]})
    with pytest.raises(AnalysisError, match="'eigenvalues' is not a list of"):
        ModalAnalysis.from_dict({**data, "eigenvalues": [[1.0, 2.0, 3.0]]})
    with pytest.raises(AnalysisError, match="'damped' is a number, not true or false"):
        ModalAnalysis.from_dict({**data, "damped": 1})
    with pytest.raises(AnalysisError, match="Backbones has no key 'fictitious_damping' at "
                                            r"'backbones\[0\]'"):
        Backbones.from_dict({"title": "", "coordinates": ["x"], "harmonics": 1, "residual": 0,
                             "backbones": [{"mode": 1, "reference": "x",
                                            "linear_frequency": 1.0, "amplitude": [0.1],
                                            "frequencies": [1.0], "amplitudes": {"x": [0.1]},
                                            "coefficients": [[[0.1, 0.0, 0.0]]]}]})


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


@pytest.mark.parametrize("case", list(SWEEPS))
def test_sweep_round_trip(case):
    """Every field of a sweep survives JSON, the complex responses bit for bit."""
    sweep = SWEEPS[case]()
    back = FrequencyResponse.from_dict(_through_json(sweep.to_dict()))
    _assert_same_sweep(back, sweep)
    # and again: the saved form of the copy is the saved form of the original
    assert FrequencyResponse.from_dict(_through_json(back.to_dict())).to_dict() == \
        sweep.to_dict()


def test_extrema_are_written_as_their_records():
    """The peaks and antiresonances a sweep saves are its Extremum tuples' records (one
    writer, ExtremaTable.to_list, for both)."""
    absorber = resonant.load(EXAMPLES / "absorber.toml").linearize().sweep(
        "k2", np.linspace(150, 950, 161))   # an antiresonance of x1 (tests/test_sweep.py)
    sweeps = [SWEEPS["cart_pendulum"](), absorber]
    assert sweeps[0].peaks and absorber.antiresonances
    for sweep in sweeps:
        data = _through_json(sweep.to_dict())
        assert data["peaks"] == [e._asdict() for e in sweep.peaks]
        assert data["antiresonances"] == [e._asdict() for e in sweep.antiresonances]


def test_sweep_cases_cover_what_they_claim():
    """The cases above hold what they are named for (else the round trip tests less)."""
    assert SWEEPS["two-harmonics"]().response.shape[0] == 2
    skipped = SWEEPS["skipped"]()
    assert skipped.skipped == (10.0,)
    assert np.isnan(skipped.response[0, 10]).all()  # the harmonic at omega
    assert SWEEPS["log"]().log
    assert SWEEPS["absorber-k2"]().frequency_scale is None
    assert SWEEPS["no-excitation"]().response.shape == (0, 2, 2)
    reduced = SWEEPS["reduced"]()
    assert reduced.method == "reduced" and reduced.estimated_error is not None


def test_sweep_from_dict_names_what_is_missing():
    data = _through_json(SWEEPS["cart_pendulum"]().to_dict())
    for key in ("response", "quantities", "harmonic_omegas", "values", "log"):
        broken = {k: v for k, v in data.items() if k != key}
        with pytest.raises(AnalysisError, match=f"no key '{key}'"):
            FrequencyResponse.from_dict(broken)
    with pytest.raises(AnalysisError, match="no key 'imag' at 'response'"):
        FrequencyResponse.from_dict({**data, "response": {"real": data["response"]["real"]}})
    with pytest.raises(AnalysisError, match="'response.real' has shape"):
        FrequencyResponse.from_dict({**data, "response": {"real": [[1.0]], "imag": [[0.0]]}})
    with pytest.raises(AnalysisError, match="'values' is a string"):
        FrequencyResponse.from_dict({**data, "values": "1, 2"})
    with pytest.raises(AnalysisError, match="not a mapping"):
        FrequencyResponse.from_dict([1, 2])  # type: ignore[arg-type]


#: a [matrices] model with a nonlinear element and outputs: the condensed balance
CONDENSED = """
[parameters]
w = 0.5
k3 = 2
c1 = 0.04
[matrices]
M = [[1, 0], [0, 1]]
K = [[2, -1], [-1, 1]]
C = [["c1", 0], [0, 0.04]]
[[harmonic]]
omega = "w"
F_C = [0, 0.1]
[outputs]
spring = "k3*(q2 - q1)^3 + (q2 - q1)"
accel = "q2''"
[[nonlinear]]
name = "hardening"
coordinates = ["q2", "q1"]
force = "k3*(q2 - q1)^3"
"""

BRANCHES = {name: cache(make) for name, make in {
    # folds and a change of stability (the jump of the Duffing oscillator)
    "duffing": lambda: resonant.load(EXAMPLES / "duffing.toml").nonlinear_sweep(
        "omega", 0.8, 1.6, harmonics=3, points=40),
    "duffing-no-linear": lambda: resonant.load(EXAMPLES / "duffing.toml").nonlinear_sweep(
        "omega", 0.8, 1.2, harmonics=1, points=15, linear=False),
    "two_dof_cubic": lambda: resonant.load(EXAMPLES / "two_dof_cubic.toml").nonlinear_sweep(
        "omega", 0.5, 2.0, harmonics=3, points=30),
    "condensed-outputs": lambda: resonant.loads(CONDENSED).nonlinear_sweep(
        "w", 0.5, 2.0, harmonics=3, points=25),
}.items()}


@pytest.mark.parametrize("case", list(BRANCHES))
def test_nonlinear_round_trip(case):
    """The branch, its multipliers, special points, output harmonics and linear sweep survive
    JSON bit for bit."""
    branch = BRANCHES[case]()
    back = NonlinearResponse.from_dict(_through_json(branch.to_dict()))
    assert back.to_dict() == branch.to_dict()
    for name in ("values", "coefficients", "base_frequencies", "stable", "multipliers"):
        np.testing.assert_array_equal(getattr(back, name), getattr(branch, name))
        assert getattr(back, name).dtype == getattr(branch, name).dtype, name
    assert list(back.amplitudes) == list(branch.amplitudes)
    for name, a in branch.amplitudes.items():
        np.testing.assert_array_equal(back.amplitudes[name], a)
    for name in ("title", "parameter", "coordinates", "outputs", "harmonics", "residual",
                 "truncation", "start", "stop", "warnings", "special_points"):
        assert getattr(back, name) == getattr(branch, name), name
    if branch.output_coefficients is None:
        assert back.output_coefficients is None
    else:
        np.testing.assert_array_equal(back.output_coefficients, branch.output_coefficients)
    if branch.linear is None:
        assert back.linear is None
    else:
        _assert_same_sweep(back.linear, branch.linear)
    assert back.summary() == branch.summary()
    assert back.peak() == branch.peak()


def test_nonlinear_cases_cover_what_they_claim():
    duffing = BRANCHES["duffing"]()
    assert {"fold", "peak"} <= {p.kind for p in duffing.special_points}
    assert not duffing.stable.all()
    assert np.iscomplexobj(duffing.multipliers) and np.any(duffing.multipliers.imag != 0)
    condensed = BRANCHES["condensed-outputs"]()
    assert condensed.output_coefficients is not None and condensed.outputs
    assert BRANCHES["duffing-no-linear"]().linear is None


def test_nonlinear_from_dict_names_what_is_missing():
    data = _through_json(BRANCHES["duffing-no-linear"]().to_dict())
    with pytest.raises(AnalysisError, match="no key 'continuation'"):
        NonlinearResponse.from_dict({k: v for k, v in data.items() if k != "continuation"})
    rest = {k: v for k, v in data["continuation"].items() if k != "multipliers"}
    with pytest.raises(AnalysisError, match="no key 'multipliers' at 'continuation'"):
        NonlinearResponse.from_dict({**data, "continuation": rest})
    branch = [dict(p) for p in data["branch"]]
    branch[3] = {**branch[3], "harmonics": {"x": [[0.0], [1.0]]}}
    with pytest.raises(AnalysisError, match=r"'branch\[3\].harmonics.x' has shape"):
        NonlinearResponse.from_dict({**data, "branch": branch})
    with pytest.raises(AnalysisError, match="SpecialPoint has no key 'kind'"):
        SpecialPoint.from_dict({"value": 1.0, "amplitudes": {"x": 1.0}, "index": 2})


SIMULATIONS = {
    # linear, started on the stationary solution, with the linear prediction and outputs
    "tuned_mass_damper": lambda: resonant.load(EXAMPLES / "tuned_mass_damper.toml").simulate(
        0.5),
    "cart_pendulum-nonlinear": lambda: resonant.load(EXAMPLES / "cart_pendulum.toml").simulate(
        1.0, nonlinear=True),
    "duffing-nonlinear": lambda: resonant.load(EXAMPLES / "duffing.toml").simulate(
        20.0, nonlinear=True),
    "two_dof_free-given": lambda: resonant.load(EXAMPLES / "two_dof_free.toml").simulate(
        0.2, initial={"x1": 0.01}),
    "chain3_damped": lambda: resonant.load(EXAMPLES / "chain3_damped.toml").simulate(0.3),
}


@pytest.mark.parametrize("case", list(SIMULATIONS))
def test_simulation_round_trip(case):
    """With its history, a simulation survives JSON bit for bit."""
    sim = SIMULATIONS[case]()
    back = Simulation.from_dict(_through_json(sim.to_dict(history=True)))
    assert back.to_dict(history=True) == sim.to_dict(history=True)
    assert back.to_dict() == sim.to_dict()
    np.testing.assert_array_equal(back.t, sim.t)
    for field in ("states", "linear_response"):
        original = getattr(sim, field)
        assert list(getattr(back, field)) == list(original)
        for name, y in original.items():
            np.testing.assert_array_equal(getattr(back, field)[name], y)
    for field in ("title", "coordinates", "steady_amplitudes", "linear_amplitudes",
                  "relative_difference", "window", "nonlinear", "start", "method", "initial",
                  "warnings", "t_end", "names"):
        assert getattr(back, field) == getattr(sim, field), field
    assert back.summary() == sim.summary()


def test_simulation_json_leaves_the_history_out_unless_asked():
    sim = SIMULATIONS["two_dof_free-given"]()
    assert "history" not in sim.to_dict()
    assert len(sim.to_dict(history=True)["history"]["t"]) == sim.t.size
    with pytest.raises(AnalysisError, match=r"no time history: save it with to_dict\(history"):
        Simulation.from_dict(_through_json(sim.to_dict()))
    data = _through_json(sim.to_dict(history=True))
    data["history"]["states"]["x1"] = data["history"]["states"]["x1"][:-1]
    with pytest.raises(AnalysisError, match="'history.states.x1' has shape"):
        Simulation.from_dict(data)


RANDOM = {"shaker_gevs": EXAMPLES / "shaker_gevs.toml",
          # a single-DOF model: Miles' estimate, natural frequency and quality factor
          "miles_shaker": EXAMPLES / "teaching" / "miles_shaker.toml"}


@pytest.mark.parametrize("case", list(RANDOM))
def test_random_round_trip(case):
    result = resonant.load(RANDOM[case]).random_response()
    back = RandomResponse.from_dict(_through_json(result.to_dict()))
    assert back.to_dict() == result.to_dict()
    np.testing.assert_array_equal(back.frequency, result.frequency)
    for field in ("psd", "input_psd"):
        assert list(getattr(back, field)) == list(getattr(result, field))
        for name, y in getattr(result, field).items():
            np.testing.assert_array_equal(getattr(back, field)[name], y)
    for field in ("title", "names", "inputs", "rms", "error", "band", "input_derivatives",
                  "natural_frequency", "quality", "method", "warnings"):
        assert getattr(back, field) == getattr(result, field), field
    for field in ("zero_crossing_rate", "peak_rate"):  # NaN where undefined
        np.testing.assert_array_equal(list(getattr(back, field).values()),
                                      list(getattr(result, field).values()))
    if result.miles is None:
        assert back.miles is None
    else:
        np.testing.assert_array_equal(list(back.miles.values()), list(result.miles.values()))
        assert list(back.miles) == list(result.miles)
    assert back.summary() == result.summary()
    if case == "miles_shaker":
        assert result.miles and result.natural_frequency is not None


def test_random_from_dict_names_what_is_missing():
    data = _through_json(resonant.load(RANDOM["shaker_gevs"]).random_response().to_dict())
    name = next(iter(data["responses"]))
    del data["responses"][name]["rms"]
    with pytest.raises(AnalysisError, match=f"no key 'rms' at 'responses.{name}'"):
        RandomResponse.from_dict(data)


PERIODIC = {name: cache(make) for name, make in {
    "fourier_square": lambda: periodic_load_response(
        resonant.load(EXAMPLES / "teaching" / "fourier_square.toml").linearize()),
    # the table displacement as a sawtooth (no mean) on a model with outputs
    "shaker-sawtooth": lambda: periodic_load_response(
        resonant.load(EXAMPLES / "shaker_gevs.toml").linearize(),
        PeriodicSpec("y", 0, "sawtooth", 1e-3, 0.01, tolerance=0.05)),
    # a mean (the rectified sine's a0 > 0): a static part in every response
    "chain-rectified-sine": lambda: periodic_load_response(
        resonant.load(EXAMPLES / "chain3_damped.toml").linearize(),
        PeriodicSpec("x3", 0, "rectified-sine", 5.0, 0.3)),
}.items()}


@pytest.mark.parametrize("case", list(PERIODIC))
def test_periodic_round_trip(case):
    result = PERIODIC[case]()
    back = PeriodicResponse.from_dict(_through_json(result.to_dict()))
    assert back.to_dict() == result.to_dict()
    assert back.series.harmonics == result.series.harmonics > 1
    for field in ("a", "b"):
        np.testing.assert_array_equal(getattr(back.series, field),
                                      getattr(result.series, field))
    for field in ("period", "a0", "remainder", "shape"):
        assert getattr(back.series, field) == getattr(result.series, field)
    np.testing.assert_array_equal(back.time, result.time)
    assert back.names == result.names
    for name in result.names:
        np.testing.assert_array_equal(back.harmonics[name], result.harmonics[name])
        np.testing.assert_array_equal(back.history[name], result.history[name])
    assert back.mean == result.mean and back.largest == result.largest
    assert back.warnings == result.warnings
    if case == "chain-rectified-sine":
        assert all(m != 0 for m in result.mean.values())


@pytest.mark.parametrize("quantity", QUANTITIES)
@pytest.mark.parametrize(("kind", "damping"), [("half-sine", 0.05), ("sawtooth", 0.0)])
def test_shock_spectrum_round_trip(kind, damping, quantity):
    _, a = pulse(kind, 100.0, 0.011, 1e-5)
    srs = shock_response_spectrum(a, 1e-5, np.geomspace(1.0, 5000.0, 40), damping=damping,
                                  quantity=quantity)
    back = ShockSpectrum.from_dict(_through_json(srs.to_dict()))
    assert back.to_dict() == srs.to_dict()
    for field in ("frequency", "maximax", "primary", "residual"):
        np.testing.assert_array_equal(getattr(back, field), getattr(srs, field))
    for field in ("quantity", "damping", "duration", "warnings"):
        assert getattr(back, field) == getattr(srs, field)


@pytest.mark.parametrize("duration", [None, 3600.0])
def test_spectral_fatigue_round_trip(duration):
    pytest.importorskip("FLife")
    f = np.linspace(10, 300, 300)
    psd = 40.0 * np.exp(-(((f - 120) / 15) ** 2)) + 2.0  # a resonance over a floor (MPa^2/Hz)
    result = spectral_fatigue(f, psd, SNCurve.from_range(2e12, 3.0), duration)
    back = SpectralFatigue.from_dict(_through_json(result.to_dict()))
    assert back == result  # a dataclass of numbers and maps: equal field by field
    assert back.to_dict() == result.to_dict()


def test_rainflow_round_trip():
    pytest.importorskip("rainflow")
    stress = np.random.default_rng(1).normal(0.0, 50.0, 2000).cumsum() % 400 - 200
    result = rainflow_damage(stress, SNCurve(1e12, 3.0))
    back = RainflowDamage.from_dict(_through_json(result.to_dict()))
    assert back.to_dict() == result.to_dict()
    np.testing.assert_array_equal(back.ranges, result.ranges)
    np.testing.assert_array_equal(back.counts, result.counts)
    assert (back.damage, back.sn, back.warnings) == (result.damage, result.sn, result.warnings)
    assert len(result.ranges) > 100


def test_fatigue_from_dict_names_what_is_missing():
    with pytest.raises(AnalysisError, match="no key 'sn_curve'"):
        RainflowDamage.from_dict({"ranges": [1.0], "counts": [0.5], "damage": 0.1})
    with pytest.raises(AnalysisError, match="'sn_curve.C' is a string, not a number"):
        RainflowDamage.from_dict({"ranges": [1.0], "counts": [0.5], "damage": 0.1,
                                  "sn_curve": {"C": "big", "k": 3}})
    with pytest.raises(AnalysisError, match="S-N curve needs C > 0"):
        RainflowDamage.from_dict({"ranges": [1.0], "counts": [0.5], "damage": 0.1,
                                  "sn_curve": {"C": -1.0, "k": 3}})


@pytest.mark.parametrize("names", [None, ["table"]])
def test_transient_round_trip(names):
    system = resonant.load(EXAMPLES / "shaker_gevs.toml").linearize()
    result = shock_response(system, ShockSpec("y", 2, "half-sine", 100.0, 0.011, 1e-4, 0.05),
                            names=names)
    back = TransientResponse.from_dict(_through_json(result.to_dict(history=True)))
    assert back.to_dict(history=True) == result.to_dict(history=True)
    np.testing.assert_array_equal(back.time, result.time)
    np.testing.assert_array_equal(back.input, result.input)
    assert back.names == result.names and list(back.history) == list(result.history)
    for name in result.names:
        np.testing.assert_array_equal(back.history[name], result.history[name])
    assert (back.largest, back.warnings) == (result.largest, result.warnings)
    assert "history" not in result.to_dict()
    with pytest.raises(AnalysisError, match="no time history: save it with to_dict"):
        TransientResponse.from_dict(_through_json(result.to_dict()))


def _saved(name):
    """(class, saved form) of one result of every class that comes back from JSON."""
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    shaker = resonant.load(EXAMPLES / "shaker_gevs.toml").linearize()
    _, a = pulse("half-sine", 100.0, 0.011, 1e-4)
    results = {
        "sweep": lambda: (FrequencyResponse, SWEEPS["two-harmonics"]().to_dict()),
        "stationary": lambda: (StationarySolution, model.linearize().stationary().to_dict()),
        "nonlinear": lambda: (NonlinearResponse, BRANCHES["duffing-no-linear"]().to_dict()),
        "simulation": lambda: (Simulation, model.simulate(0.1, initial={"x1": 0.01}).to_dict(
            history=True)),
        "modes": lambda: (ModalAnalysis, model.linearize().modes().to_dict()),
        "backbones": lambda: (Backbones, resonant.load(EXAMPLES / "duffing.toml").backbone(
            harmonics=1, points=4).to_dict()),
        "random": lambda: (RandomResponse, resonant.load(RANDOM["miles_shaker"]
                                                          ).random_response().to_dict()),
        "periodic": lambda: (PeriodicResponse, PERIODIC["fourier_square"]().to_dict()),
        "shock": lambda: (ShockSpectrum, shock_response_spectrum(a, 1e-4, [10.0, 100.0]
                                                                 ).to_dict()),
        "transient": lambda: (TransientResponse, shock_response(
            shaker, ShockSpec("y", 2, "half-sine", 100.0, 0.011, 1e-4, 0.02)).to_dict(
                history=True)),
        "rainflow": lambda: (RainflowDamage, rainflow_damage([0.0, 10.0, -5.0, 8.0, 0.0],
                                                             SNCurve(1e9, 3.0)).to_dict()),
        "periodic-solution": lambda: (PeriodicSolution, periodic_solution(
            nonlinear_system(resonant.load(EXAMPLES / "two_dof_cubic.toml")), 2).to_dict()),
        "swept-state": lambda: (SweptState, swept_state(
            nonlinear_system(resonant.load(EXAMPLES / "duffing.toml")), "omega", 0.5, 2.0,
            harmonics=3).to_dict()),
    }
    return results[name]()


SAVED = ["stationary", "sweep", "nonlinear", "simulation", "modes", "backbones", "random",
         "periodic", "shock", "transient", "rainflow", "periodic-solution", "swept-state"]
#: values of the wrong kind put in place of each key
WRONG = [None, "text", 1.5, -1, True, [], [[1.0], [2.0, 3.0]], {}, {"real": [1.0]}]


def _paths(data, path=()):
    """The path of every mapping key in a saved result (inside nested mappings and the
    mappings in the first two entries of lists)."""
    if isinstance(data, dict):
        for key, value in data.items():
            yield path + (key,)
            yield from _paths(value, path + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data[:2]):
            yield from _paths(value, path + (i,))


def _replaced(data, path, value):
    """``data`` with the key at ``path`` removed (value ``_paths``) or set to ``value``: the
    containers along the path copied, the rest shared (from_dict does not change its
    input)."""
    data = list(data) if isinstance(data, list) else dict(data)
    if len(path) > 1:
        data[path[0]] = _replaced(data[path[0]], path[1:], value)
    elif value is _paths:
        del data[path[0]]
    else:
        data[path[0]] = value
    return data


@pytest.mark.parametrize("name", SAVED)
def test_malformed_saved_results_raise_analysis_errors(name):
    """Every key removed, and every value replaced by one of the wrong kind: from_dict gives
    the result back or raises an AnalysisError (a ValueError) -- never a KeyError, TypeError
    or IndexError."""
    cls, data = _saved(name)
    data = _through_json(data)
    cls.from_dict(data)
    tried = refused = 0
    for path in _paths(data):
        for value in [_paths, *WRONG]:  # _paths: the key removed
            tried += 1
            try:
                cls.from_dict(_replaced(data, path, value))
            except AnalysisError:
                refused += 1
    assert refused > tried / 4, (tried, refused)


def test_arrays_survive_json_bit_for_bit():
    """Property: every finite double of a real or complex array of any shape comes back from
    JSON with the same bits (-0.0, subnormals and the extremes included); NaN and the
    infinities come back as NaN, and the text is valid JSON (no NaN, no Infinity)."""
    hypothesis = pytest.importorskip("hypothesis")
    from hypothesis.extra import numpy as hnp

    from resonant.analyses.results_json import Saved, complex_json, floats_json

    shapes = hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)

    def same(back, original):
        finite = np.isfinite(original)
        assert np.array_equal(back[finite].view(np.uint64), original[finite].view(np.uint64))
        assert np.isnan(back[~finite]).all()

    @hypothesis.settings(max_examples=150, deadline=None)
    @hypothesis.given(hnp.arrays(np.float64, shapes), hnp.arrays(np.complex128, shapes))
    def check(real, z):
        text = json.dumps({"x": floats_json(real), "z": complex_json(z)}, allow_nan=False)
        saved = Saved(json.loads(text), "Example")
        same(saved.floats("x", shape=real.shape), real)
        back = saved.complex("z", shape=z.shape)
        same(back.real, z.real)
        same(back.imag, z.imag)

    check()


def test_load_tables_hold_the_results_numbers():
    """The shock spectrum, the transient and periodic histories and the rainflow cycles as
    tables: the same numbers, one row per sample."""
    pytest.importorskip("pandas")
    _, a = pulse("half-sine", 100.0, 0.011, 1e-4)
    srs = shock_response_spectrum(a, 1e-4, np.geomspace(10, 1000, 7))
    frame = srs.to_frame()
    np.testing.assert_array_equal(frame["frequency_hz"], srs.frequency)
    np.testing.assert_array_equal(frame["residual"], srs.residual)
    transient = shock_response(resonant.load(EXAMPLES / "shaker_gevs.toml").linearize(),
                               ShockSpec("y", 2, "half-sine", 100.0, 0.011, 1e-4, 0.02))
    frame = transient.to_frame()
    assert list(frame.columns) == ["time", "input", *transient.names]
    for name in transient.names:
        np.testing.assert_array_equal(frame[name], transient.history[name])
    periodic = PERIODIC["shaker-sawtooth"]()
    frame = periodic.to_frame()
    assert len(frame) == periodic.time.size
    for name in periodic.names:
        np.testing.assert_array_equal(frame[name], periodic.history[name])
    cycles = rainflow_damage(np.sin(np.linspace(0, 20, 400)) * 50, SNCurve(1e12, 3.0))
    frame = cycles.to_frame()
    np.testing.assert_array_equal(frame["range"], cycles.ranges)
    np.testing.assert_array_equal(frame["count"], cycles.counts)


@pytest.mark.parametrize(("name", "harmonics"), [("duffing", 3), ("two_dof_cubic", 5),
                                                 ("cart_pendulum", None)])
def test_periodic_solution_round_trip(name, harmonics):
    solution = periodic_solution(nonlinear_system(resonant.load(EXAMPLES / f"{name}.toml")),
                                 harmonics)
    back = PeriodicSolution.from_dict(_through_json(solution.to_dict()))
    assert back.to_dict() == solution.to_dict()
    np.testing.assert_array_equal(back.coefficients, solution.coefficients)
    np.testing.assert_array_equal(back.multipliers, solution.multipliers)
    for field in ("title", "coordinates", "harmonics", "base_frequency", "initial",
                  "amplitudes", "linear_amplitudes", "relative_difference", "stable",
                  "residual", "truncation", "warnings"):
        assert getattr(back, field) == getattr(solution, field), field
    assert back.summary() == solution.summary()


def test_swept_state_round_trip():
    """The state a slow sweep reaches past the Duffing oscillator's jump (one jump)."""
    state = swept_state(nonlinear_system(resonant.load(EXAMPLES / "duffing.toml")), "omega",
                        0.5, 2.0, harmonics=3)
    assert state.jumps
    back = SweptState.from_dict(_through_json(state.to_dict()))
    assert back.to_dict() == state.to_dict()
    np.testing.assert_array_equal(back.coefficients, state.coefficients)
    for field in ("parameter", "start", "value", "amplitudes", "harmonics", "jumps",
                  "residual", "truncation"):
        assert getattr(back, field) == getattr(state, field), field


#: two masses on springs, excited at omega and 3 omega: the property test below changes
#: the parameters of the one derivation
TWO_MASSES = """
[parameters]
m = 1
k1 = 10
k2 = 10
c = 0
a3 = 0.2
omega = 1
[coordinates]
x1 = "displacement"
x2 = "displacement"
[signals]
F = "sin(omega*t) + a3*cos(3*omega*t)"
[energy]
T = "m*x1'^2/2 + x2'^2/2"
U = "k1*x1^2/2 + k2*(x2 - x1)^2/2"
D = "c*(k1*x1'^2 + k2*(x2' - x1')^2)/2"
[[force]]
generalized = { x2 = "F" }
[outputs]
stretch = "x2 - x1"
"""


@cache
def _two_masses():
    return resonant.loads(TWO_MASSES).linearize()


def test_any_two_mass_sweep_round_trips():
    """Property: the sweep of any two-mass chain (damped or not, its 3 omega load zero or
    not, swept exactly through the lowest natural frequency -- skipped when undamped -- or
    not) comes back from JSON bit for bit."""
    hypothesis = pytest.importorskip("hypothesis")
    st = hypothesis.strategies
    positive = st.floats(0.1, 100.0)

    @hypothesis.settings(max_examples=40, deadline=None)
    @hypothesis.given(m=positive, k1=positive, k2=positive,
                      c=st.sampled_from([0.0, 1e-3, 0.1]), a3=st.sampled_from([0.0, 0.5]),
                      through=st.booleans(), points=st.integers(1, 12))
    def check(m, k1, k2, c, a3, through, points):
        system = _two_masses().numeric(m=m, k1=k1, k2=k2, c=c, a3=a3)
        values = np.linspace(0.1, 20.0, points)
        if through:  # a value exactly at the lowest natural frequency (skipped when undamped)
            M, K = np.asarray(system.M), np.asarray(system.K)
            lowest = float(np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K)).real.min()))
            values = np.unique(np.r_[values, lowest])
        sweep = system.sweep("omega", values)
        _assert_same_sweep(FrequencyResponse.from_dict(_through_json(sweep.to_dict())), sweep)

    check()


def test_a_peak_refined_on_an_uneven_triple_stays_finite():
    """Found by the property above: values 0.1, the lowest natural frequency (0.158) and 20
    rad/s of a lightly damped chain; the parabola through the log amplitudes of that uneven
    triple overflowed, so the peak's amplitude was infinity (and the JSON invalid). The grid
    point is the peak then."""
    system = _two_masses().numeric(m=40.0, k1=1.0, k2=1.0, c=0.001, a3=0.0)
    M, K = np.asarray(system.M), np.asarray(system.K)
    lowest = float(np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K)).real.min()))
    sweep = system.sweep("omega", np.unique([0.1, lowest, 20.0]))
    assert sweep.peaks and all(np.isfinite(p.amplitude) for p in sweep.peaks)
    json.dumps(sweep.to_dict(), allow_nan=False)


def test_every_result_saved_by_its_fields_has_a_saved_form_for_each_field():
    """A result class that inherits result_fields.FieldsJSON is checked here, not when a
    user first saves one: every field's annotation names a saved form (or its codec)."""
    import importlib
    import pkgutil

    import resonant.analyses
    from resonant.analyses.result_fields import FieldsJSON

    for module in pkgutil.iter_modules(resonant.analyses.__path__):
        importlib.import_module(f"resonant.analyses.{module.name}")
    seen, stack = [], list(FieldsJSON.__subclasses__())
    while stack:
        kind = stack.pop()
        seen.append(kind.__name__)
        kind._saved_fields()  # raises TypeError naming the field without a saved form
        stack += kind.__subclasses__()
    assert {"FrequencyResponse", "ModalAnalysis", "SpecialPoint", "Backbones"} <= set(seen)


def test_tables_are_written_once_from_the_declared_columns():
    """No result writes its own ``to_frame``: each declares its columns (``_frame``) and
    :class:`~resonant.analyses.result_fields.Framed` builds the table; a table whose columns
    differ in length is refused."""
    import ast
    from dataclasses import dataclass

    from resonant.analyses.result_fields import Framed

    own = [f"{path.name}:{node.lineno}"
           for path in sorted((Path(resonant.__file__).parent).rglob("*.py"))
           if path.name != "result_fields.py"
           for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
           if isinstance(node, ast.FunctionDef) and node.name == "to_frame"]
    assert own == []

    @dataclass(frozen=True)
    class Ragged(Framed):
        _frame = (("a", "a"), ("b", "b"))
        a: np.ndarray
        b: np.ndarray

    with pytest.raises(AnalysisError, match="lengths"):
        Ragged(np.zeros(2), np.zeros(3)).frame_columns()
