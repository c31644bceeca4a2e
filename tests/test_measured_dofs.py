"""The node and direction of each FRF that ``resonant frf --save`` writes
(resonant.model.measurement_spec.measurement_dofs, docs/testing.md "The report").

On a model whose coordinates are named by node and direction (``n1_uz``, the FE imports'
names) with its channels listed in another order than the nodes, the saved Universal File
must carry each channel's node and direction in its dataset 58 records (pyuff's rsp_node,
rsp_dir, ref_node, ref_dir, read here with pyuff itself), so that the file goes back into
``report --test``, ``explore --test`` and ``identify`` without a refusal; a file whose
response names another coordinate is still refused (exit 2).  A model of other names gets
the channels' positions past every node it names.
"""

from __future__ import annotations

import dataclasses
import json

import pytest

import resonant
from conftest import run_cli
from resonant.analyses.virtual_test import simulated_test
from resonant.model.measured import MeasuredData, read_uff, write_uff
from resonant.model.measurement_spec import ChannelMap, MeasurementSpec, measurement_dofs
from test_testdata_cli import IMPACT  # the same hammer test's processing options

pyuff = pytest.importorskip("pyuff")

# the 3-mass chain of examples/chain3_lab.toml (k = 1000 N/m, m = 1 kg, c = 8 N s/m) with
# the masses named as nodes 1-3 in +Z, the hammer on node 3; the channels are listed
# 3, 1, 2: their positions are not their nodes
FE_CHAIN = """
[coordinates]
n1_uz = "displacement of mass 1"
n2_uz = "displacement of mass 2"
n3_uz = "displacement of mass 3"
[parameters]
omega = 10.0
[matrices]
M = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
K = [[2000.0, -1000.0, 0.0], [-1000.0, 2000.0, -1000.0], [0.0, -1000.0, 1000.0]]
C = [[16.0, -8.0, 0.0], [-8.0, 16.0, -8.0], [0.0, -8.0, 8.0]]
[[harmonic]]
omega = "omega"
F_C = { n3_uz = 1.0 }
[measurement]
excitation = "hammer"
input = "n3_uz"
[measurement.channels]
top = "n3_uz"
bottom = "n1_uz"
middle = "n2_uz"
"""


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """The simulated impact test of the FE-named chain, and the FRFs frf --save wrote."""
    folder = tmp_path_factory.mktemp("fe_lab")
    model_file = folder / "fe_chain.toml"
    model_file.write_text(FE_CHAIN)
    model = resonant.load(model_file)
    data = simulated_test(model.linearize(), model.measurement_section, records=4,
                          duration=16.0, step=1 / 256, seed=5)
    write_uff(folder / "impact.uff", data, binary=True)
    status, _, err = run_cli(["frf", model_file, folder / "impact.uff", *IMPACT, "--save",
                              folder / "frf.uff"])
    assert status == 0, err
    return model_file, folder / "frf.uff"


def test_records_carry_the_channels_nodes_and_directions(saved):
    _, frfs = saved
    records = pyuff.UFF(str(frfs)).read_sets()
    fields = {r["id1"].strip(): (r["rsp_node"], r["rsp_dir"], r["ref_node"], r["ref_dir"])
              for r in records if r["type"] == 58 and r["func_type"] == 4}
    assert fields == {"top": (3, 3, 3, 3), "bottom": (1, 3, 3, 3), "middle": (2, 3, 3, 3)}


def test_saved_file_goes_back_into_report_explore_and_identify(saved, tmp_path):
    model_file, frfs = saved
    status, _, err = run_cli(["report", model_file, "-o", tmp_path / "report.html", "--test",
                              frfs, "--no-plots"])
    assert status == 0, err
    assert "Measured against model FRFs" in (tmp_path / "report.html").read_text()
    status, _, err = run_cli(["explore", model_file, "-o", tmp_path / "page.html", "--test",
                              frfs])
    assert status == 0, err
    status, out, err = run_cli(["identify", model_file, frfs, "--order", "30", "--json"])
    assert status == 0, err
    found = [m["frequency_hz"] for m in json.loads(out)["modes"]]
    # the chain's undamped 2.2399, 6.2760, 9.0690 Hz (examples/chain3_lab.toml), shifted by
    # the damping and the exponential window's added decay: within 2 %
    assert found == pytest.approx([2.2399, 6.2760, 9.0690], rel=0.02)


def test_a_response_that_names_another_coordinate_is_still_refused(saved, tmp_path):
    model_file, frfs = saved
    data = read_uff(frfs)
    moved = tuple(dataclasses.replace(f, response=(2, 3)) if f.name == "bottom" else f
                  for f in data.functions)
    wrong = tmp_path / "wrong.uff"
    write_uff(wrong, MeasuredData(wrong.name, moved), binary=True)
    for command in (["report", model_file, "-o", tmp_path / "r.html"],
                    ["explore", model_file, "-o", tmp_path / "p.html"]):
        status, _, err = run_cli([*command, "--test", wrong])
        assert status == 2, err
        assert ("[measurement.channels] bottom: wrong.uff: the response of FRF 'bottom' is "
                "node 2 direction 3, the model's coordinate n2_uz; [measurement] maps it to "
                "n1_uz") in err


def test_several_inputs_carry_each_inputs_node():
    spec = MeasurementSpec("hammer", "n3_uz", {"a": ChannelMap("n1_uz", 2)},
                           (("hammer", "n3_uz"), ("shaker", "F")))
    assert measurement_dofs(spec, ["n1_uz", "n3_uz"]) == {
        "a": (1, 3), "hammer": (3, 3), "shaker": (4, 0)}


def test_other_names_get_positions_past_the_named_nodes():
    """Positions never name a coordinate (n4 is a scalar point: node 4), and a driving
    point's response and reference share the node of their coordinate."""
    spec = MeasurementSpec("hammer", "x1", {"d1": ChannelMap("x1"), "d9": ChannelMap("n9_rx"),
                                            "y": ChannelMap("y")})
    assert measurement_dofs(spec, ["x1", "n4", "n9_rx"]) == {
        "d1": (10, 0), "d9": (9, 4), "y": (11, 0), "hammer": (10, 0)}
    chain = resonant.load("examples/chain3_lab.toml")
    assert measurement_dofs(chain.measurement_section, chain.coordinates) == {
        "d1": (1, 0), "d2": (2, 0), "d3": (3, 0), "hammer": (4, 0)}
