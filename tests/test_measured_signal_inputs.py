"""Measured references that are signals of the model, not coordinates (docs/testing.md,
"Inputs that are signals"): traced through the excitation's load columns to the
coordinates they load, so that the file's reference nodes are checked, the saved files
carry the coordinate's node, the report names what each input loads, and the explore
page's points are the sweep's amplitude.

The model: the chain of tests/test_explore_measured_inputs.py (F0 sin on mass 1, 0.6 F0
cos on mass 3) with its masses named as nodes 1-3 in +Z (``n1_uz``, the FE imports'
names), so that a reference node names a coordinate.  Its test is its own FRF matrix to
the two signals written as a binary Universal File (every bit kept): the overlay must be
the sweep's amplitude at every line to 1e-9 relative (two kernel solves of the same
equations; the rest is rounding), as for coordinate inputs.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import resonant
from conftest import run_cli
from resonant.analyses.frf_mimo import frf_matrix_from_measurement, pair_name
from resonant.analyses.frf_update import model_frf_matrix
from resonant.analyses.measured_match import MatchedTest, match_test, saved_dofs
from resonant.analyses.sweep import sweep
from resonant.analyses.virtual_test import simulated_test
from resonant.model.measured import MeasuredData, MeasuredFunction, read_uff, write_uff
from resonant.system.excitation import excitation_columns_along, loaded_coordinates
from resonant.views import explore_measured
from resonant.views.explore_measured import measured_overlay
from test_explore_measured_inputs import two_loads_text

pytest.importorskip("pyuff")

LINES = np.linspace(0.5, 12.0, 47)
NODES = {"x1": "n1_uz", "x2": "n2_uz", "x3": "n3_uz"}


def fe_text(excitation: list[str], inputs: list[str]) -> str:
    """The two-load chain with node-named coordinates."""
    text = two_loads_text(excitation, inputs)
    for old, new in NODES.items():
        text = text.replace(old, new)
    return text


def write_test(path, model: resonant.Model, excitation: list[str],
               references: list[tuple[int, int]]) -> tuple[np.ndarray, object]:
    """The model's own FRF matrix as a binary Universal File, input j's reference at
    ``references[j]`` (node, direction); each response at its coordinate's node, +Z."""
    spec = model.measurement_section
    H = model_frf_matrix(model.linearize(), spec.model_inputs, LINES, spec.channels)
    functions = tuple(MeasuredFunction(pair_name(c, e), "frf", LINES, H[:, k, j], "Hz", "m/N",
                                       (k + 1, 3), ref)
                      for j, (e, ref) in enumerate(zip(excitation, references, strict=True))
                      for k, c in enumerate(spec.channels))
    write_uff(path, MeasuredData(path.name, functions), binary=True)
    return H, path


@pytest.fixture()
def fe_model(tmp_path):
    path = tmp_path / "fe_two.toml"
    path.write_text(fe_text(["shaker1", "shaker3"], ["F1", "F3"]))
    return path, resonant.load(path)


def test_a_signal_is_traced_to_the_coordinates_it_loads(fe_model):
    _, model = fe_model
    system = model.linearize()
    assert loaded_coordinates(system, ["F1", "F3", "n2_uz"]) == {
        "F1": ("n1_uz",), "F3": ("n3_uz",), "n2_uz": ("n2_uz",)}
    # a saved file's reference is the node of the coordinate the signal loads
    dofs = saved_dofs(model.measurement_section, system)
    assert dofs["shaker1"] == (1, 3) and dofs["shaker3"] == (3, 3)
    chain = resonant.load("examples/chain3_lab.toml")
    data = simulated_test(chain.linearize(), chain.measurement_section, records=1,
                          duration=1.0, step=1 / 64)
    # the hammer's F acts on x3: a driving point, one node with channel d3
    assert data.function("hammer").response == data.function("d3").response == (3, 0)


def test_a_reference_node_that_names_another_coordinate_is_refused(fe_model, tmp_path):
    path, model = fe_model
    _, test = write_test(tmp_path / "swapped.uff", model, ["shaker1", "shaker3"],
                         [(3, 3), (1, 3)])
    status, _, err = run_cli(["report", path, "-o", tmp_path / "r.html", "--test", test,
                              "--no-plots"])
    assert status == 2 and "Traceback" not in err, err
    assert ("[measurement] input: swapped.uff: the reference of FRF 'd1/shaker1' is node 3 "
            "direction 3, the model's coordinate n3_uz; [measurement] maps it to F1, whose "
            "load acts on n1_uz (map the input to n3_uz, or correct the file's node)") in err


def test_signal_references_are_named_and_give_the_sweep(fe_model, tmp_path):
    path, model = fe_model
    H, test = write_test(tmp_path / "two.uff", model, ["shaker1", "shaker3"],
                         [(1, 3), (3, 3)])
    system = model.linearize()
    matched = match_test(read_uff(test), model.measurement_section, system, model.source)
    assert matched.model_inputs == ("F1", "F3") and matched.acts_on == ("n1_uz", "n3_uz")
    assert [p.title for p in matched.chart().panels] == [
        "input shaker1 (the model's F1, on n1_uz)", "input shaker3 (the model's F3, on n3_uz)"]
    data = measured_overlay(matched, model, system, "omega")
    assert data["note"] is None
    swept = sweep(system, "omega", 2 * np.pi * LINES, method="direct")
    for name in NODES.values():
        assert np.allclose(data["curves"][name], swept.amplitudes[name], rtol=1e-9, atol=0)
    status, _, err = run_cli(["report", path, "-o", tmp_path / "r.html", "--test", test,
                              "--no-plots"])
    assert status == 0, err
    section = (tmp_path / "r.html").read_text().split("Measured against model FRFs</h2>")[1]
    assert ("3 response channels to 2 inputs (shaker1: the model&#x27;s F1, on n1_uz; "
            "shaker3: the model&#x27;s F3, on n3_uz)") in section


def test_a_position_reference_is_not_checked(fe_model, tmp_path):
    """A reference node past the model's nodes (direction 0) names no coordinate."""
    _, model = fe_model
    _, test = write_test(tmp_path / "positions.uff", model, ["shaker1", "shaker3"],
                         [(4, 0), (5, 0)])
    data = read_uff(test)
    matched = match_test(data, model.measurement_section, model.linearize(), model.source)
    assert matched.acts_on == ("n1_uz", "n3_uz")
    moved = MeasuredData(data.source, tuple(dataclasses.replace(f, reference=(2, 3))
                                            if f.name == "d2/shaker3" else f
                                            for f in data.functions))
    with pytest.raises(resonant.errors.ModelError, match="maps it to F3, whose load acts on "
                       "n3_uz"):
        match_test(moved, model.measurement_section, model.linearize(), model.source)


def feedthrough_text(excitation: list[str], inputs: list[str]) -> str:
    """The two-load chain with a sensor channel v = x3 + E/2 that picks up the signal E
    (e0 cos: crosstalk), which loads no mass: E acts through the output only."""
    text = two_loads_text(excitation, inputs)
    text = text.replace('omega = "30 rad/s"', 'omega = "30 rad/s"\ne0 = "0.002 m"')
    text = text.replace('F3 = "0.6*F0*cos(omega*t)"',
                        'F3 = "0.6*F0*cos(omega*t)"\nE = "e0*cos(omega*t)"')
    text = text.replace("[measurement]\n", '[outputs]\nv = "x3 + 0.5*E"\n\n[measurement]\n')
    return text.replace('d3 = "x3"', 'd3 = "x3"\nv = "v"')


def own_test(model: resonant.Model, excitation: list[str]):
    """The model's own FRF matrix as a measured test (MatchedTest by hand)."""
    spec = model.measurement_section
    H = model_frf_matrix(model.linearize(), spec.model_inputs, LINES, spec.channels)
    return MatchedTest("crosstalk.uff", LINES, H, H, tuple(spec.channels), tuple(excitation),
                       ("m/N",) * len(spec.channels), (2.24, 9.07))


def test_an_input_through_outputs_only_gives_its_direct_term(tmp_path):
    """E's FRF to v is the direct term 1/2 (to every mass 0); its amplitude in the model's
    harmonic, e0, is its u: v's points are the sweep's |x3 + E/2| to 1e-9."""
    excitation = ["shaker1", "shaker3", "pickup"]
    model = resonant.loads(feedthrough_text(excitation, ["F1", "F3", "E"]), "crosstalk.toml")
    system = model.linearize()
    assert loaded_coordinates(system, ["E"]) == {"E": ()}
    _, path = write_test(tmp_path / "crosstalk.uff", model, excitation,
                         [(5, 0), (6, 0), (7, 0)])
    test = match_test(read_uff(path), model.measurement_section, system, model.source)
    assert test.acts_on == ("x1", "x3", "")
    assert test.chart().panels[2].title == "input pickup (the model's E, through outputs only)"
    assert np.allclose(test.measured[:, 3, 2], 0.5, rtol=1e-14)
    data = measured_overlay(test, model, system, "omega")
    assert data["note"] is None and set(data["curves"]) == {"x1", "x2", "x3", "v"}
    swept = sweep(system, "omega", 2 * np.pi * LINES, method="direct")
    for name in ("x1", "x2", "x3", "v"):
        assert np.allclose(data["curves"][name], swept.amplitudes[name], rtol=1e-9,
                           atol=0), name
    assert np.max(np.abs(np.asarray(swept.amplitudes["v"])
                         / np.asarray(swept.amplitudes["x3"]) - 1)) > 0.1   # E counts


def test_an_output_through_a_signal_no_input_is_gets_no_points():
    excitation = ["shaker1", "shaker3"]
    model = resonant.loads(feedthrough_text(excitation, ["F1", "F3"]), "crosstalk.toml")
    system = model.linearize()
    data = measured_overlay(own_test(model, excitation), model, system, "omega")
    assert set(data["curves"]) == {"x1", "x2", "x3"}
    assert data["note"].startswith("no measured points for v (through E): the output "
                                   "depends directly on a signal that no measured input is")
    swept = sweep(system, "omega", 2 * np.pi * LINES, method="direct")
    assert np.allclose(data["curves"]["x3"], swept.amplitudes["x3"], rtol=1e-9, atol=0)


def moving_text(shape: bool = False) -> str:
    """The two-load chain whose force on mass 1 grows as (omega/w0)^2 (the signal F1 times
    a column that depends on the frequency parameter); with ``shape``, F1 also pushes mass
    2 with a constant 0.5 (so that the column's shape, not only its size, moves)."""
    text = two_loads_text(["shaker1", "shaker3"], ["F1", "F3"])
    text = text.replace('omega = "30 rad/s"', 'omega = "30 rad/s"\nw0 = "30 rad/s"')
    text = text.replace('vector = ["F1"]', 'vector = ["F1*(omega/w0)^2"]')
    if shape:
        text = text.replace("[measurement]\n", '[[force]]\nname = "F1 on mass 2"\n'
                            'vector = ["0.5*F1"]\npoint = ["x2"]\n\n[measurement]\n')
    return text


def lab_test(model: resonant.Model, excitation: list[str]) -> MatchedTest:
    """What a lab measures: at each line, the response per unit of each input with the
    model's load columns at that line's omega (a kernel solve per line)."""
    spec = model.measurement_section
    system = model.linearize()
    H = np.concatenate([model_frf_matrix(system, spec.model_inputs, [f], spec.channels,
                                         omega=float(2 * np.pi * f)) for f in LINES])
    return MatchedTest("lab.uff", LINES, H, H, tuple(spec.channels), tuple(excitation),
                       ("m/N",) * len(spec.channels), (2.24, 9.07))


@pytest.mark.parametrize("shape", [False, True])
def test_a_load_that_depends_on_the_frequency_is_taken_at_each_line(shape):
    """u_j from the columns at each line: the sweep's amplitude to 1e-9 (with the columns
    at the model's omega the points were (omega/w0)^2 off, or not drawn at all)."""
    model = resonant.loads(moving_text(shape), "moving.toml")
    system = model.linearize()
    along = excitation_columns_along(system, "omega", 2 * np.pi * LINES[:2])
    assert np.allclose(along[("F1", 0)][:, 0], (2 * np.pi * LINES[:2] / 30.0) ** 2,
                       rtol=1e-14)
    data = measured_overlay(lab_test(model, ["shaker1", "shaker3"]), model, system, "omega")
    assert data["note"] is None
    swept = sweep(system, "omega", 2 * np.pi * LINES, method="direct")
    for name in ("x1", "x2", "x3"):
        assert np.allclose(data["curves"][name], swept.amplitudes[name], rtol=1e-9,
                           atol=0), name


def test_columns_not_had_at_each_line_give_a_specific_note(monkeypatch):
    """A numerically derived system has its columns at the model's values only: the note
    says that the input's load depends on the frequency parameter."""
    model = resonant.loads(moving_text(True), "moving.toml")
    monkeypatch.setattr(explore_measured, "excitation_columns_along",
                        lambda *args, **kwargs: None)
    data = measured_overlay(lab_test(model, ["shaker1", "shaker3"]), model,
                            model.linearize(), "omega")
    assert data["curves"] == {}
    assert data["note"].startswith("no measured points: the load of the input F1 depends "
                                   "on omega, the page's frequency parameter")


def test_a_simulated_random_test_with_two_references(fe_model, tmp_path):
    """simulated_test with two inputs (independent random forces on F1 and F3, all at
    once), the H1 matrix of its histories saved as a Universal File, read back and
    matched: the references carry the nodes of the masses F1 and F3 load, and the page's
    points follow the sweep.  Tolerances: the simulated force is linear between samples,
    so the response is the sweep's times sinc^2(f step) (the hold's spectrum; 11 % at
    12 Hz, taken out here); what is left is the H1 estimate's error over 8 records of
    64 s in 64 s segments (measured: median 0.09-0.15 %, 3.6-3.9 % at worst, at 2.20 Hz
    next to the 2.24 Hz peak): median under 1 %, worst under 8 %."""
    _, model = fe_model
    system = model.linearize()
    spec = model.measurement_section
    step = 1 / 64
    data = simulated_test(system, spec, records=8, duration=64.0, step=step, random=True,
                          seed=1)
    assert data.names == ("shaker1", "shaker3", "d1", "d2", "d3")
    assert data.function("shaker1").response == (1, 3)
    matrix = frf_matrix_from_measurement(data, spec, model.source, segment=4096)
    write_uff(tmp_path / "h1.uff", matrix.to_measured("h1.uff", {c: "m/N" for c in
                                                                   spec.channels},
                                                      saved_dofs(spec, system)), binary=True)
    frfs = read_uff(tmp_path / "h1.uff")
    assert {f.reference for f in frfs.functions if f.name.endswith("/shaker3")} == {(3, 3)}
    matched = match_test(frfs, spec, system, model.source)
    data = measured_overlay(matched, model, system, "omega")
    assert data["note"] is None
    f = matched.frequency[matched.frequency > 0]
    swept = sweep(system, "omega", 2 * np.pi * f, method="direct")
    band = (f >= 0.5) & (f <= 12.0)
    for name in NODES.values():
        error = np.abs(np.asarray(data["curves"][name]) / (
            np.asarray(swept.amplitudes[name]) * np.sinc(f * step) ** 2) - 1)[band]
        assert np.median(error) < 0.01 and error.max() < 0.08, (name, error.max())


def test_frf_save_writes_a_signal_reference_at_its_coordinate(tmp_path):
    """``resonant frf --save`` on examples/chain3_lab.toml: the hammer's F loads x3, so
    every FRF's reference is node 3, the node of channel d3's response (a driving point);
    it was node 4, a position of its own."""
    chain = resonant.load("examples/chain3_lab.toml")
    data = simulated_test(chain.linearize(), chain.measurement_section, records=2,
                          duration=16.0, step=1 / 256, seed=2)
    write_uff(tmp_path / "impact.uff", data, binary=True)
    status, _, err = run_cli(["frf", "examples/chain3_lab.toml", tmp_path / "impact.uff",
                              "--window", "rectangular", "--segment", "4096",
                              "--force-window", "0.05", "--exponential", "0.01",
                              "--save", tmp_path / "frf.uff"])
    assert status == 0, err
    frfs = [f for f in read_uff(tmp_path / "frf.uff").functions if f.kind == "frf"]
    assert {f.reference for f in frfs} == {(3, 0)}
    assert {f.name: f.response for f in frfs} == {"d1": (1, 0), "d2": (2, 0), "d3": (3, 0)}
