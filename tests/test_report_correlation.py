"""The report's section "Test against model" (resonant.report.steps.correlation) and
``resonant report --test FILE``: the pairs, frequency errors and MACs of a saved correlation,
its figure, the notes on a poor pair; a file that is not a saved correlation, or one made
with another model, is exit 2."""

from __future__ import annotations

import json

import numpy as np
import pytest

import resonant
from conftest import run_cli
from resonant.analyses.correlate import correlate_shapes, model_shapes
from resonant.report import build_report, render

EXAMPLE = "examples/chain3_lab.toml"


@pytest.fixture(scope="module")
def model():
    return resonant.load(EXAMPLE)


@pytest.fixture(scope="module")
def correlation(model):
    system = model.linearize()
    channels = model.measurement_section.channels
    f, shapes = model_shapes(system, channels)
    test = shapes.copy()
    test[:, 2] = [1.0, 1.0, 1.0]                   # the third test shape is not the model's
    return correlate_shapes(f * np.array([1.02, 0.99, 1.01]), test, f, shapes)


def test_section_in_the_report(model, correlation):
    report = build_report(model, plots=True, correlation=correlation)
    assert "Test against model" in report.headings()
    text = render(report, "md")
    assert r"\mathrm{MAC}_{jk}" in text and "| 1 | 2.2" in text.replace("  ", " ")
    assert "Test mode 3: no model mode of MAC above 0.9" in text
    assert "Test against model" not in build_report(model, plots=False).headings()


def test_report_command_reads_the_saved_correlation(model, correlation, tmp_path):
    saved = tmp_path / "test.json"
    saved.write_text(json.dumps(correlation.to_dict()))
    out = tmp_path / "report.html"
    status, _, err = run_cli(["report", EXAMPLE, "-o", out, "--test", saved, "--no-plots"])
    assert status == 0, err
    assert "Test against model" in out.read_text()
    # made with another model (its three frequencies are not this model's two): refused
    status, _, err = run_cli(["report", "examples/two_dof_free.toml", "-o", out, "--test",
                              saved, "--no-plots"])
    assert status == 2 and "test.json: made with a model of 3 modes" in err, err
    assert "run resonant correlate --json with this model" in err
    # the same number of modes at other frequencies: the first that differs is named
    stiffer = tmp_path / "stiffer.toml"
    stiffer.write_text(open(EXAMPLE).read().replace('k1 = "1000 N/m"', 'k1 = "1100 N/m"'))
    status, _, err = run_cli(["report", stiffer, "-o", out, "--test", saved, "--no-plots"])
    assert status == 2 and "made with another model: its mode 1 is at 2.23986 Hz, this model's at 2.29696" in err, err
    for content, match in (("{", "not JSON"), ('{"pairs": []}', "not the JSON of resonant "
                                                                "correlate")):
        saved.write_text(content)
        status, _, err = run_cli(["report", EXAMPLE, "-o", out, "--test", saved])
        assert status == 2 and "test.json" in err and match in err, err
        assert "Traceback" not in err
