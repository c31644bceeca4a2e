"""``resonant report --test FILE.uff``: measured FRFs checked against the model they are said
to test (resonant.analyses.measured_match, docs/testing.md "The report") and drawn over the
model's.  A file that matches gives the section "Measured against model FRFs" with a FRAC
of 1 (the model's own FRFs, to 1e-9: the binary Universal File keeps every bit); each kind
of mismatch -- a channel missing, one too many, two references for one input, a response
node that names another coordinate, lines outside the model's band, no [measurement] --
is exit 2 naming the file and what does not match."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import resonant
from conftest import run_cli
from resonant.analyses.frf_mimo import pair_name
from resonant.analyses.frf_update import model_frf_matrix
from resonant.analyses.measured_match import match_test
from resonant.model.measured import MeasuredData, MeasuredFunction, write_uff
from test_explore_measured_inputs import two_loads_text

pytest.importorskip("pyuff")

EXAMPLE = "examples/chain3_lab.toml"
LINES = np.linspace(0.5, 12.0, 47)          # 0.25 Hz apart; the chain's modes: 2.24-9.07 Hz


@pytest.fixture(scope="module")
def model():
    return resonant.load(EXAMPLE)


def _functions(model, lines=LINES, names=("d1", "d2", "d3")):
    system = model.linearize()
    H = model_frf_matrix(system, ["F"], lines, model.measurement_section.channels)
    return [MeasuredFunction(name, "frf", lines, H[:, k, 0], "Hz", "m/N", (k + 1, 3), (3, 3))
            for k, name in enumerate(names)]


def _write(path, functions):
    write_uff(path, MeasuredData(path.name, tuple(functions)), binary=True)
    return path


def _report(model_file, test, tmp_path, *extra):
    out = tmp_path / "report.html"
    status, _, err = run_cli(["report", model_file, "-o", out, "--test", test, *extra])
    assert "Traceback" not in err
    return status, err, out


def test_matching_file_is_drawn_over_the_model(model, tmp_path):
    test = _write(tmp_path / "lab.uff", _functions(model))
    status, err, out = _report(EXAMPLE, test, tmp_path, "--no-plots")
    assert status == 0, err
    page = out.read_text()
    assert "Measured against model FRFs" in page and "FRAC to hammer" in page
    # the input named from the result: the model's signal and the coordinate it loads
    assert "3 response channels to 1 input (hammer: the model&#x27;s F, on x3)" in page
    assert "<td>1</td>" in page.replace(" ", "")
    matched = match_test(resonant.model.measured.read_uff(test), model.measurement_section,
                         model.linearize(), model.source)
    assert np.allclose(matched.frac, 1.0, atol=1e-9)
    assert np.allclose(matched.measured, matched.model, rtol=1e-9)
    assert matched.band == pytest.approx((2.2399, 9.0690), abs=1e-4)
    # the figure: each response's measured |H| solid and the model's dashed
    curves = matched.chart().panels[0].curves
    assert [c.label for c in curves[:2]] == ["d1 (measured)", "d1 (model)"]
    assert matched.model_inputs == ("F",) and matched.acts_on == ("x3",)
    assert matched.chart().title == ("measured (lab.uff) and model FRFs to hammer (the "
                                     "model's F, on x3)")
    assert curves[1].dash and np.allclose(curves[0].y, np.abs(matched.measured[:, 0, 0]))
    # saved by its fields: read back equal, with the FRAC written for the reader
    saved = json.loads(json.dumps(matched.to_dict()))
    assert list(saved) == ["source", "frequency_hz", "measured", "model", "responses",
                           "inputs", "model_inputs", "acts_on", "units", "band_hz", "frac"]
    again = type(matched).from_dict(saved)
    assert np.array_equal(again.measured, matched.measured) and again.band == matched.band
    assert (again.model_inputs, again.acts_on) == (("F",), ("x3",))


@pytest.mark.parametrize("case, expected", [
    ("missing", "[measurement.channels] d3: lab.uff has no channel 'd3'"),
    ("extra", "lab.uff holds 4 FRFs, the model's [measurement] maps 3 responses x 1 input: "
              "d4 is not in it"),
    ("references", "lab.uff holds FRFs to 2 references (node 1 direction 3, node 3 direction "
                   "3) and [measurement] names one input"),
    ("band", "lab.uff's lines, 100 to 200 Hz, do not overlap the model's natural "
             "frequencies, 2.23986 to 9.06901 Hz"),
    ("histories", "lab.uff: the file holds no FRF (dataset 58, function type 4)"),
])
def test_mismatching_files_are_refused(model, tmp_path, case, expected):
    functions = _functions(model)
    if case == "missing":
        functions = functions[:2]
    elif case == "extra":
        functions.append(dataclasses.replace(functions[0], name="d4", response=(4, 3)))
    elif case == "references":
        functions[0] = dataclasses.replace(functions[0], reference=(1, 3))
    elif case == "band":
        functions = _functions(model, lines=np.linspace(100.0, 200.0, 11))
    elif case == "histories":
        t = np.arange(64) / 64.0
        functions = [MeasuredFunction(name, "time", t, np.sin(7 * t), "s", "m")
                     for name in ("hammer", "d1", "d2", "d3")]
    status, err, _ = _report(EXAMPLE, _write(tmp_path / "lab.uff", functions), tmp_path)
    assert status == 2 and expected in err, err


def test_response_node_that_names_another_coordinate(tmp_path):
    """FE-named coordinates (node and direction): the file's node 12 +Z is n12_uz, which the
    section does not map the channel to."""
    (tmp_path / "fe.toml").write_text("""
[coordinates]
n11_uz = "displacement"
n12_uz = "displacement"
[parameters]
omega = 10.0
[matrices]
M = [[1.0, 0.0], [0.0, 1.0]]
K = [[2000.0, -1000.0], [-1000.0, 1000.0]]
C = [[2.0, -1.0], [-1.0, 1.0]]
[[harmonic]]
omega = "omega"
F_C = { n12_uz = 1.0 }
[measurement]
excitation = "hammer"
input = "n12_uz"
[measurement.channels]
a = "n11_uz"
b = "n12_uz"
""")
    fe = resonant.load(tmp_path / "fe.toml")
    H = model_frf_matrix(fe.linearize(), ["n12_uz"], LINES, fe.measurement_section.channels)
    good = [MeasuredFunction(name, "frf", LINES, H[:, k, 0], "Hz", "m/N", (node, 3), (12, 3))
            for k, (name, node) in enumerate((("a", 11), ("b", 12)))]
    status, err, _ = _report(tmp_path / "fe.toml", _write(tmp_path / "lab.uff", good),
                             tmp_path, "--no-plots")
    assert status == 0, err
    swapped = [dataclasses.replace(good[0], response=(12, -3)), good[1]]
    status, err, _ = _report(tmp_path / "fe.toml", _write(tmp_path / "lab.uff", swapped),
                             tmp_path, "--no-plots")
    assert status == 2, err
    assert ("[measurement.channels] a: lab.uff: the response of FRF 'a' is node 12 direction "
            "-3, the model's coordinate n12_uz; [measurement] maps it to n11_uz") in err


def test_model_without_measurement_section(model, tmp_path):
    test = _write(tmp_path / "lab.uff", _functions(model))
    status, err, _ = _report("examples/chain3_damped.toml", test, tmp_path, "--no-plots")
    assert status == 2 and "[measurement]" in err and "add one" in err, err
    status, _, err = run_cli(["report", EXAMPLE, "-o", tmp_path / "r.html", "--test", test,
                              "--test", test])
    assert status == 2 and "--test takes one Universal File of FRFs, got 2" in err, err


def test_two_references_are_named_and_drawn_once_each(tmp_path):
    """A test of the chain loaded on masses 1 and 3 with a shaker at each: the section names
    both references with the model's input each measures, gives a FRAC column to each and
    a panel per reference (its title), the panels' one legend drawn once."""
    (tmp_path / "two.toml").write_text(two_loads_text(["shaker1", "shaker3"], ["x1", "x3"]))
    two = resonant.load(tmp_path / "two.toml")
    H = model_frf_matrix(two.linearize(), ["x1", "x3"], LINES, two.measurement_section.channels)
    functions = [MeasuredFunction(pair_name(name, shaker), "frf", LINES, H[:, k, j], "Hz",
                                  "m/N", (k + 1, 3), (node, 3))
                 for j, (shaker, node) in enumerate((("shaker1", 1), ("shaker3", 3)))
                 for k, name in enumerate(("d1", "d2", "d3"))]
    status, err, out = _report(tmp_path / "two.toml", _write(tmp_path / "two.uff", functions),
                               tmp_path)
    assert status == 0, err
    section = out.read_text().split("Measured against model FRFs</h2>")[1]
    assert ("3 response channels to 2 inputs (shaker1: the model&#x27;s x1; shaker3: the "
            "model&#x27;s x3)") in section
    assert "<th>FRAC to shaker1</th><th>FRAC to shaker3</th>" in section
    assert section.count("<td>1</td>") == 6
    figure = section.split("<figure>")[1]
    assert "input shaker1" in figure and "input shaker3" in figure
    matched = match_test(resonant.model.measured.read_uff(tmp_path / "two.uff"),
                         two.measurement_section, two.linearize(), two.source)
    chart = matched.chart()
    assert [p.title for p in chart.panels] == ["input shaker1 (the model's x1)",
                                               "input shaker3 (the model's x3)"]
    assert [p.legend for p in chart.panels] == ["best", "none"] and chart.legend == "below"
    assert np.allclose(chart.panels[1].curves[4].y, np.abs(H[:, 2, 1]), rtol=1e-12)
