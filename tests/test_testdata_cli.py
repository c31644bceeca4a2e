"""``resonant frf``, ``identify``, ``correlate`` and ``update`` on a simulated impact test
written as a Universal File (the lab workflow of docs/testing.md), and their bad input
(file, record or key named, exit 2)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

import resonant
from conftest import run_cli
from resonant.analyses.virtual_test import simulated_test
from resonant.model.measured import write_uff

pytest.importorskip("pyuff")
EXAMPLE = Path("examples/chain3_lab.toml")
IMPACT = ["--window", "rectangular", "--segment", "4096", "--force-window", "0.05",
          "--exponential", "0.01", "--from", "0.5", "--to", "15"]


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lab")
    model = folder / "chain3_lab.toml"
    shutil.copy(EXAMPLE, model)
    truth = resonant.load(str(EXAMPLE)).with_parameters(k1="1100 N/m", k2="950 N/m")
    data = simulated_test(truth.linearize(), truth.measurement_section, records=4,
                          duration=16.0, step=1 / 256, noise=0.0, seed=5)
    write_uff(folder / "impact.uff", data, binary=True)
    status, out, err = run_cli(["frf", model, folder / "impact.uff", *IMPACT, "--save",
                                folder / "frf.uff", "--json"])
    assert status == 0, err
    return folder, model, json.loads(out)


def test_frf_json_and_plot(lab, tmp_path):
    folder, model, frf = lab
    assert frf["averages"] == 4 and set(frf["channels"]) == {"d1", "d2", "d3"}
    assert frf["added_decay_per_s"] > 0
    status, out, err = run_cli(["frf", model, folder / "impact.uff", *IMPACT, "--plot",
                                tmp_path / "frf.svg"])
    assert status == 0, err
    assert "added the decay" in out and (tmp_path / "frf.svg").stat().st_size > 1000


def test_identify_correlate_update(lab, tmp_path):
    folder, model, frf = lab
    decay = ["--order", "30", "--added-decay", str(frf["added_decay_per_s"])]
    status, out, err = run_cli(["identify", model, folder / "frf.uff", *decay, "--json",
                                "--plot", tmp_path / "stab.png"])
    assert status == 0, err
    modes = json.loads(out)["modes"]
    assert [round(m["frequency_hz"], 3) for m in modes] == [2.275, 6.369, 8.995]
    status, out, err = run_cli(["correlate", model, folder / "frf.uff", *decay, "--json"])
    assert status == 0, err
    assert json.loads(out)["pairs"] == [0, 1, 2]
    status, out, err = run_cli(["update", model, folder / "frf.uff", *decay,
                                "--vary", "k1=500 N/m:2 kN/m", "--vary", "k2=500 N/m:2 kN/m",
                                "--vary", "k3=500 N/m:2 kN/m", "--json"])
    assert status == 0, err
    fitted = {k: v["fitted"] for k, v in json.loads(out)["parameters"].items()}
    assert fitted == pytest.approx({"k1": 1100.0, "k2": 950.0, "k3": 1000.0}, rel=1e-3)


def test_bad_input_exit_2(lab, tmp_path):
    folder, model, _ = lab
    truncated = tmp_path / "cut.uff"
    truncated.write_bytes((folder / "impact.uff").read_bytes()[:-5000])
    status, _, err = run_cli(["frf", model, truncated, *IMPACT])
    assert status == 2 and "cut.uff: record" in err and "truncated" in err
    other = tmp_path / "other.toml"
    other.write_text(EXAMPLE.read_text().replace('d3 = "x3"', 'acc3 = "x3"'))
    status, _, err = run_cli(["frf", other, folder / "impact.uff", *IMPACT])
    assert status == 2 and "[measurement.channels] acc3: impact.uff has no channel" in err
    status, _, err = run_cli(["identify", model, folder / "impact.uff"])
    assert status == 2 and "holds no FRF" in err
    status, _, err = run_cli(["frf", model, folder / "impact.uff", "--from", "200",
                              "--to", "300"])
    assert status == 2 and "holds 0 spectral lines" in err, err
    status, _, err = run_cli(["update", model, folder / "frf.uff", "--vary", "k1"])
    assert status == 2 and "--vary takes NAME=LOW:HIGH" in err
    bare = tmp_path / "bare.toml"
    bare.write_text(EXAMPLE.read_text().split("\n[measurement]\n")[0])
    status, _, err = run_cli(["frf", bare, folder / "impact.uff"])
    assert status == 2 and "no [measurement] section" in err
