"""Measured FRFs to several inputs over the explore page's frequency response
(resonant.views.explore_measured.measured_overlay, docs/explore.md).

The page's curve is the response to all of the model's loads at once, so the points of a
test with several references are sum_j H_ij u_j, u_j the complex amplitude of the model's
load at input j.  Two routes to one answer: a simulated test whose FRFs are the model's
own (both columns of model_frf_matrix) must give back the sweep's amplitude at every line
to 1e-9 relative (both are kernel solves of the same equations; the rest is rounding), for
a chain loaded at two coordinates with different phases (F0 sin on mass 1, 0.6 F0 cos on
mass 3).  A load that no measured input makes gives no points and a note; an input that the
model does not load adds nothing; one input gives the single-input scaling of before
(|H| |x_model| / |H_model|) to 1e-12.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import resonant
from conftest import run_cli
from resonant.analyses import random_response
from resonant.analyses.frf_mimo import pair_name
from resonant.analyses.frf_update import input_amplitudes, model_frf_matrix
from resonant.analyses.measured_match import MatchedTest
from resonant.analyses.sweep import sweep
from resonant.model.measured import MeasuredData, MeasuredFunction, write_uff
from resonant.views.explore_measured import measured_overlay

EXAMPLE = Path(__file__).parents[1] / "examples" / "chain3_lab.toml"
LINES = np.linspace(0.5, 12.0, 47)

TWO_LOADS = """
title = "3-mass chain with forces on masses 1 and 3"

[parameters]
m = "1 kg"
k = "1000 N/m"
c = "8 N*s/m"
F0 = "10 N"
omega = "30 rad/s"

[coordinates]
x1 = { unit = "m" }
x2 = { unit = "m" }
x3 = { unit = "m" }

[signals]
F1 = "F0*sin(omega*t)"
F3 = "0.6*F0*cos(omega*t)"

[energy]
T = "m*(x1'^2 + x2'^2 + x3'^2)/2"
U = "k*(x1^2 + (x2 - x1)^2 + (x3 - x2)^2)/2"
D = "c*(x1'^2 + (x2' - x1')^2 + (x3' - x2')^2)/2"

[[force]]
name = "shaker on mass 1"
vector = ["F1"]
point = ["x1"]

[[force]]
name = "shaker on mass 3"
vector = ["F3"]
point = ["x3"]

[measurement]
excitation = {excitation}
input = {input}

[measurement.channels]
d1 = "x1"
d2 = "x2"
d3 = "x3"
"""


def two_loads_text(excitation: list[str], inputs: list[str]) -> str:
    """The chain loaded on masses 1 and 3, its [measurement] of these excitation channels
    and inputs (one named as a string, several as lists)."""
    def toml(names: list[str]) -> str:
        return json.dumps(names if len(names) > 1 else names[0])
    return TWO_LOADS.replace("{excitation}", toml(excitation)).replace("{input}", toml(inputs))


def _model(excitation: list[str], inputs: list[str]) -> resonant.Model:
    return resonant.loads(two_loads_text(excitation, inputs), "two_loads.toml")


def _test(model: resonant.Model, excitation: list[str], factor: float = 1.0) -> MatchedTest:
    """The model's own FRF matrix as a measured test (times ``factor``)."""
    spec = model.measurement_section
    H = model_frf_matrix(model.linearize(), spec.model_inputs, LINES, spec.channels)
    return MatchedTest("two_refs.uff", LINES, factor * H, H, tuple(spec.channels),
                       tuple(excitation), ("m/N",) * 3, (2.24, 9.07))


def _swept(model: resonant.Model) -> dict[str, np.ndarray]:
    response = sweep(model.linearize(), "omega", 2 * np.pi * LINES, method="direct")
    return {name: np.asarray(response.amplitudes[name]) for name in ("x1", "x2", "x3")}


@pytest.mark.parametrize("inputs", [["x1", "x3"], ["F1", "F3"]])
def test_two_references_give_the_sweep(inputs):
    model = _model(["shaker1", "shaker3"], inputs)
    system = model.linearize()
    data = measured_overlay(_test(model, ["shaker1", "shaker3"]), model, system, "omega")
    assert data["note"] is None and data["inputs"] == ["shaker1", "shaker3"]
    assert np.allclose(data["values"], 2 * np.pi * LINES, rtol=1e-12)
    for name, amplitude in _swept(model).items():
        assert np.allclose(data["curves"][name], amplitude, rtol=1e-9, atol=0), name


def test_the_phases_count():
    """The loads' phases enter the sum: the magnitudes alone give another curve."""
    model = _model(["shaker1", "shaker3"], ["x1", "x3"])
    system = model.linearize()
    test = _test(model, ["shaker1", "shaker3"])
    load = system.batch("omega", 2 * np.pi * LINES).harmonics[0].complex_load
    u, left, worst = input_amplitudes(system, ["x1", "x3"], LINES, load)
    assert np.allclose(u, np.broadcast_to([-10j, 6.0], u.shape), rtol=1e-14)
    assert float(left.max()) == 0.0 and float(worst.max()) == 0.0
    magnitudes = np.abs(np.sum(test.measured[:, 2, :] * np.abs(u), axis=1))
    drawn = np.array(measured_overlay(test, model, system, "omega")["curves"]["x3"])
    assert np.max(np.abs(magnitudes / drawn - 1)) > 0.1


def test_an_input_the_model_does_not_load_adds_nothing():
    model = _model(["shaker1", "shaker2", "shaker3"], ["x1", "x2", "x3"])
    system = model.linearize()
    data = measured_overlay(_test(model, ["shaker1", "shaker2", "shaker3"]), model, system,
                            "omega")
    assert data["note"] is None
    for name, amplitude in _swept(model).items():
        assert np.allclose(data["curves"][name], amplitude, rtol=1e-9, atol=0), name


@pytest.mark.parametrize("inputs", [["x1"], ["F3"], ["x1", "x2"]])
def test_a_load_no_input_makes_draws_no_points(inputs):
    excitation = [f"shaker{k}" for k in range(len(inputs))]
    model = _model(excitation, inputs)
    data = measured_overlay(_test(model, excitation), model, model.linearize(), "omega")
    assert data["curves"] == {}
    missing = "x3" if "x1" in inputs else "x1"
    assert data["note"].startswith(f"no measured points: the model's load acts on {missing} ")
    assert "cannot give the response" in data["note"]


def test_one_input_is_the_single_input_scaling():
    """The sum with one input is |H| |x_model| / |H_model| (the scaling of one input)."""
    model = resonant.load(EXAMPLE)
    system = model.linearize()
    H = model_frf_matrix(system, ["F"], LINES, model.measurement_section.channels)
    rng = np.random.default_rng(3)
    measured = H * (1 + 0.2 * rng.standard_normal(H.shape)) * np.exp(1j * rng.uniform(
        -1, 1, H.shape))
    test = MatchedTest("lab.uff", LINES, measured, H, ("d1", "d2", "d3"), ("hammer",),
                       ("m/N",) * 3, (2.24, 9.07))
    data = measured_overlay(test, model, system, "omega")
    swept = sweep(system, "omega", 2 * np.pi * LINES, method="direct")
    assert data["note"] is None and data["inputs"] == ["hammer"]
    for r, name in enumerate(("x1", "x2", "x3")):
        before = np.abs(measured[:, r, 0]) * np.asarray(swept.amplitudes[name]) \
            / np.abs(H[:, r, 0])
        assert np.allclose(data["curves"][name], before, rtol=1e-12, atol=0), name


def two_reference_file(path: Path, model: resonant.Model, excitation: list[str],
                       nodes: list[int]) -> Path:
    """The model's own FRF matrix as a binary Universal File, ``RESPONSE/INPUT`` (one
    input: by the response channel), the reference of input j on ``nodes[j]``, +Z."""
    pytest.importorskip("pyuff")
    test = _test(model, excitation)
    functions = tuple(MeasuredFunction(pair_name(c, e) if len(excitation) > 1 else c, "frf",
                                       LINES, test.measured[:, k, j], "Hz", "m/N", (k + 1, 3),
                                       (node, 3))
                      for j, (e, node) in enumerate(zip(excitation, nodes, strict=True))
                      for k, c in enumerate(test.responses))
    write_uff(path, MeasuredData(path.name, functions), binary=True)
    return path


def test_the_command_line_says_why_no_points_are_drawn(tmp_path):
    (tmp_path / "one.toml").write_text(two_loads_text(["shaker1"], ["x1"]))
    model = resonant.load(tmp_path / "one.toml")
    test = two_reference_file(tmp_path / "one.uff", model, ["shaker1"], [1])
    status, _, err = run_cli(["explore", tmp_path / "one.toml", "-o", tmp_path / "p.html",
                              "--test", test])
    assert status == 0, err
    # 6 N of the load's |(-10i, 0, 6)| N on x3: 6 / sqrt(136) = 51.4 %
    assert ("warning: --test: no measured points: the model's load acts on x3 (51.4 % of it "
            "at worst), which the test's input (shaker1) does not make") in err, err
    (tmp_path / "two.toml").write_text(two_loads_text(["shaker1", "shaker3"], ["x1", "x3"]))
    test = two_reference_file(tmp_path / "two.uff", resonant.load(tmp_path / "two.toml"),
                              ["shaker1", "shaker3"], [1, 3])
    status, _, err = run_cli(["explore", tmp_path / "two.toml", "-o", tmp_path / "p.html",
                              "--test", test])
    assert status == 0 and "warning" not in err, err


def test_the_rest_is_formed_by_chunks_of_lines(monkeypatch):
    """Chunks of 5 lines give what one chunk gives (the amplitudes, what is left and where)."""
    model = _model(["shaker1"], ["x1"])
    system = model.linearize()
    load = system.batch("omega", 2 * np.pi * LINES).harmonics[0].complex_load
    whole = input_amplitudes(system, ["x1"], LINES, load)
    monkeypatch.setattr(random_response, "chunk_rows", lambda row_bytes, total: 5)
    chunked = input_amplitudes(system, ["x1"], LINES, load)
    for a, b in zip(whole, chunked, strict=True):
        assert np.array_equal(a, b)
    assert np.allclose(whole[0][:, 0], -10j) and np.allclose(whole[1], 6 / np.sqrt(136))
    assert whole[2].tolist() == [0.0, 0.0, 6.0]
