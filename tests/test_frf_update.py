"""Model updating against measured FRFs (resonant.analyses.frf_update).

Reference: the model itself.  The "test" FRFs are the model's own (kernel solve) at known
stiffnesses k1 = 1100 N/m, k2 = 950 N/m, k3 = 1000 N/m (examples/chain3_lab.toml, 3-mass chain);
the update starts from 1000 N/m each and must recover them:
* noise-free, both residuals: to 1e-6 relative (the optimizer's tolerance, 1e-12 in cost);
* 2 % multiplicative complex noise on every line: to 2 % relative, each within 4 of its
  standard deviations from the Jacobian (sigma = 0.02 given).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import resonant
from resonant.analyses.frf_update import FRFUpdate, frac, model_frf, update_to_frf
from resonant.errors import ModelError
from resonant.model.measurement_spec import ChannelMap

EXAMPLE = "examples/chain3_lab.toml"
TRUTH = {"k1": 1100.0, "k2": 950.0, "k3": 1000.0}
BOUNDS = {k: ("500 N/m", "2 kN/m") for k in TRUTH}
CHANNELS = {"d1": ChannelMap("x1"), "d3": ChannelMap("x3")}
LINES = np.linspace(0.5, 12.0, 120)


@pytest.fixture(scope="module")
def system():
    return resonant.load(EXAMPLE).linearize()


@pytest.fixture(scope="module")
def test_frf(system):
    return model_frf(system, "F", LINES, CHANNELS, **TRUTH)


@pytest.mark.parametrize("residual", ["log", "complex"])
def test_noise_free_update_recovers_the_stiffnesses(system, test_frf, residual):
    r = update_to_frf(system, BOUNDS, LINES, test_frf, "F", CHANNELS, residual=residual)
    assert r.fitted == pytest.approx(TRUTH, rel=1e-6)
    assert r.frac_before.min() < 0.99 and r.frac_after.min() > 1 - 1e-9
    assert r.log_error_after < 1e-6 < r.log_error_before
    assert not r.warnings


def test_noisy_update_within_its_uncertainty(system, test_frf):
    rng = np.random.default_rng(3)
    noisy = {c: h * (1 + 0.02 * (rng.standard_normal(len(h)) + 1j *
                                 rng.standard_normal(len(h))) / np.sqrt(2))
             for c, h in test_frf.items()}
    r = update_to_frf(system, BOUNDS, LINES, noisy, "F", CHANNELS, sigma=0.02)
    for name, value in TRUTH.items():
        assert r.fitted[name] == pytest.approx(value, rel=0.02)
        assert abs(r.fitted[name] - value) < 4 * r.std[name], (name, r.fitted, r.std)
        assert 0 < r.std[name] < 0.02 * value


def test_json_round_trip_summary_and_chart(system, test_frf, tmp_path):
    r = update_to_frf(system, {"k1": ("500 N/m", "2 kN/m")}, LINES[:30],
                      {c: h[:30] for c, h in test_frf.items()}, "F", CHANNELS)
    back = FRFUpdate.from_dict(json.loads(json.dumps(r.to_dict())))
    assert back.fitted == r.fitted and np.array_equal(back.after, r.after)
    assert "FRAC before" in r.summary() and "d3" in r.summary()
    assert len(r.chart().panels) == 2 and r.chart().panels[0].ylog
    assert "<svg" in r._repr_html_()


def test_frac():
    h = np.array([1.0, 2j, 3.0])
    assert frac(h, -2 * h) == pytest.approx(1.0)
    assert frac(h, np.zeros(3)) == 0.0


@pytest.mark.parametrize("change, match", [
    (dict(parameters={"kk": (1, 2)}), r"\[update\] kk: 'kk' is not a parameter"),
    (dict(parameters={"k1": (2, 1)}), "the lower bound must be below"),
    (dict(residual="phase"), "residual 'phase' is not one of log, complex"),
    (dict(measured={"d1": np.ones(3)}), "no measured FRF for the channel 'd3'"),
    (dict(measured={"d1": np.ones(3), "d3": np.ones(3)}), "one value per line"),
    (dict(measured={"d1": np.full(120, np.nan), "d3": np.ones(120)}), "NaN"),
    (dict(measured={"d1": np.zeros(120), "d3": np.ones(120)}), "is zero at a line"),
    (dict(frequency=np.array([-1.0])), "positive, finite lines"),
])
def test_bad_input(system, test_frf, change, match):
    kwargs = dict(parameters=BOUNDS, frequency=LINES, measured=test_frf)
    kwargs.update(change)
    with pytest.raises(ModelError, match=match):
        update_to_frf(system, kwargs["parameters"], kwargs["frequency"], kwargs["measured"],
                      "F", CHANNELS, residual=kwargs.get("residual", "log"))


def test_cli_update_to_frfs(test_frf, tmp_path):
    pytest.importorskip("pyuff")
    from conftest import run_cli
    from resonant.model.measured import MeasuredData, MeasuredFunction, write_uff

    node = {"d1": 1, "d3": 3}
    functions = tuple(MeasuredFunction(c, "frf", LINES, h, "Hz", "m/N", (node[c], 3), (3, 3))
                      for c, h in test_frf.items())
    path = tmp_path / "frf.uff"
    write_uff(path, MeasuredData("frf.uff", functions), binary=True)
    model = tmp_path / "chain.toml"
    text = open(EXAMPLE).read().replace('d2 = "x2"\n', "")
    model.write_text(text)
    vary = [a for k in TRUTH for a in ("--vary", f"{k}=500 N/m:2 kN/m")]
    status, out, err = run_cli(["update", model, path, "--fit", "frf", *vary, "--json"])
    assert status == 0, err
    fitted = {k: v["fitted"] for k, v in json.loads(out)["parameters"].items()}
    # 1e-5: dataset 58 writes the line step with 6 digits (E13.5), so the lines read back
    # are off by up to 1e-6 relative
    assert fitted == pytest.approx(TRUTH, rel=1e-5)
    status, out, err = run_cli(["update", model, path, "--fit", "frf", *vary, "--from", "50"])
    assert status == 2 and "no spectral line in the band" in err
