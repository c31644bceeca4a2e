"""The multiple-input H1 matrix (resonant.analyses.frf_mimo), checked on a 2-input simulated
test of the 3-mass chain (examples/chain3_lab.toml: the signal F on mass 3, a force on the
coordinate x1), the responses the exact superposed transient responses
(resonant.analyses.transient) as in tests/test_frf_estimate.py.

References:
* hits on both points, different instants and pulse widths in each of 3 records, decayed
  within the record, rectangular window: H1 matrix = the sampled model's FRF G_d of each
  input (tests/test_frf_estimate.py's docstring: the hold and the aliases) to 1e-6 relative
  at every line of 0.5-12 Hz, and multiple coherence 1 to 1e-9;
* two independent random forces, 2 % noise on the responses: the H1 matrix equals
  G_xx^-1 G_xy of scipy.signal.csd's spectra to 1e-9, and each H_i lies within 5 sigma
  (plus 1 % leakage) of the model's, sigma^2 = G_nn (G_xx^-1)_ii / (2 n) the variance of
  each part of the estimate, G_nn = (1 - g^2) G_yy the noise left by the multiple
  coherence, n the averages / 1.06 (Bendat & Piersol, Random Data, 4th ed., 9.3 and
  Welch 1967); the median error below 1.5 sigma (a Rayleigh variable's median is 1.18);
* one input: the single-input H1 of estimate_frf to 1e-12 (two routes, hypothesis).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import resonant
from conftest import run_cli
from resonant.analyses.frf_estimate import estimate_frf
from resonant.analyses.frf_mimo import MIMOFRF, estimate_frf_matrix
from resonant.analyses.frf_update import model_frf
from resonant.analyses.transient import transient_response
from resonant.errors import ModelError
from resonant.model.measurement_spec import ChannelMap

CHANNELS = {"x1": ChannelMap("x1"), "x2": ChannelMap("x2"), "x3": ChannelMap("x3")}
INPUTS = ("F", "x1")


@pytest.fixture(scope="module")
def system():
    return resonant.load("examples/chain3_lab.toml").linearize()


def sampled_frf(system, source: str, f: np.ndarray, fs: float, aliases: int = 20):
    """G_d: the model's FRF to ``source`` as a sampled test sees it (one kernel solve of
    every alias at once)."""
    g = (f[None, :] + fs * np.arange(-aliases, aliases + 1)[:, None]).ravel()
    h = model_frf(system, source, np.abs(g), CHANNELS)
    weight = np.sinc(g / fs) ** 2
    return {name: np.where(g < 0, np.conj(h[name]), h[name]).__mul__(weight)
            .reshape(2 * aliases + 1, len(f)).sum(axis=0) for name in CHANNELS}


def respond(system, forces: dict[str, np.ndarray], step: float) -> dict[str, np.ndarray]:
    """The responses to both inputs at once (superposition: the model is linear)."""
    total = {name: 0.0 for name in CHANNELS}
    for source, force in forces.items():
        r = transient_response(system, source, force, step, names=list(CHANNELS))
        for name in CHANNELS:
            total[name] = total[name] + np.asarray(r.history[name])
    return total


def _hit(t: np.ndarray, start: float, width: float) -> np.ndarray:
    return np.where((t > start) & (t < start + width),
                    100 * np.sin(np.pi * (t - start) / width), 0.0)


@pytest.fixture(scope="module")
def impact_test(system):
    fs, n = 64.0, 1536                    # 24 s records: the slowest mode decays by exp(-19)
    t = np.arange(n) / fs
    pattern = [((0.10, 0.02), (0.30, 0.015)), ((0.25, 0.012), (0.05, 0.02)),
               ((0.05, 0.018), (0.07, 0.01))]
    forces = {"F": np.concatenate([_hit(t, *a) for a, _ in pattern]),
              "x1": np.concatenate([_hit(t, *b) for _, b in pattern])}
    return fs, n, forces, respond(system, forces, 1 / fs)


def test_two_input_impacts_give_the_model_frf_matrix(system, impact_test):
    fs, n, forces, y = impact_test
    r = estimate_frf_matrix(forces, y, 1 / fs, window="rectangular", segment=n,
                            band=(0.5, 12.0))
    assert r.averages == 3 and r.H.shape == (len(r.frequency), 3, 2)
    for source in INPUTS:
        expected = sampled_frf(system, source, r.frequency, fs)
        for name in CHANNELS:
            error = np.abs(r.frf(name, source) / expected[name] - 1)
            assert error.max() < 1e-6, (source, name, error.max())
    np.testing.assert_allclose(r.coherence, 1.0, atol=1e-9)


def test_two_inputs_from_the_measurement_section(impact_test, tmp_path):
    fs, n, forces, y = impact_test
    text = open("examples/chain3_lab.toml").read().replace(
        'excitation = "hammer"\ninput = "F"',
        'excitation = ["hammer", "shaker"]\ninput = ["F", "x1"]')
    model = tmp_path / "two_inputs.toml"
    model.write_text(text)
    spec = resonant.load(str(model)).measurement_section
    assert spec.references == (("hammer", "F"), ("shaker", "x1"))
    columns = [np.arange(3 * n) / fs, forces["F"], forces["x1"], *(y[c] for c in CHANNELS)]
    csv = tmp_path / "test.csv"
    np.savetxt(csv, np.column_stack(columns), fmt="%.17g", delimiter=",",
               header="time,hammer,shaker,d1,d2,d3", comments="")
    status, out, err = run_cli(["frf", model, csv, "--window", "rectangular", "--segment",
                                str(n), "--from", "0.5", "--to", "12", "--json"])
    assert status == 0, err
    saved = MIMOFRF.from_dict(json.loads(out))
    direct = estimate_frf_matrix(forces, y, 1 / fs, window="rectangular", segment=n,
                                 band=(0.5, 12.0))
    assert saved.inputs == ("hammer", "shaker") and saved.outputs == ("d1", "d2", "d3")
    np.testing.assert_allclose(saved.H, direct.H, rtol=1e-9)
    status, _, err = run_cli(["frf", model, csv, "--estimator", "H2"])
    assert status == 2 and "the H1 matrix" in err
    for bad, match in (('excitation = ["hammer", "shaker"]\ninput = ["F"]',
                        "2 excitation channels for 1 inputs"),
                       ('excitation = ["hammer", "hammer"]\ninput = ["F", "x1"]',
                        "a list of 1 to 16 distinct ones")):
        model.write_text(text.replace('excitation = ["hammer", "shaker"]\ninput = ["F", "x1"]',
                                      bad))
        status, _, err = run_cli(["frf", model, csv])
        assert status == 2 and "[measurement]" in err and match in err, err


def test_two_random_inputs_with_output_noise(system):
    from scipy.signal import csd, welch

    rng = np.random.default_rng(7)
    fs, n = 32.0, 32 * 1600
    forces = {"F": rng.standard_normal(n), "x1": rng.standard_normal(n)}
    y = respond(system, forces, 1 / fs)
    noisy = {k: v + 0.02 * np.std(v) * rng.standard_normal(n) for k, v in y.items()}
    r = estimate_frf_matrix(forces, noisy, 1 / fs, segment=1024, band=(0.5, 12.0))
    assert r.averages == 99 and not r.warnings
    # the cross-spectral matrices by scipy.signal.csd (another route to G_xx and G_xy)
    kw = dict(fs=fs, nperseg=1024, noverlap=512, detrend=False, window="hann")
    f = csd(forces["F"], forces["F"], **kw)[0]
    lines = np.flatnonzero((f >= 0.5) & (f <= 12.0))
    Gxx = np.array([[csd(forces[a], forces[b], **kw)[1][lines] for b in INPUTS]
                    for a in INPUTS]).transpose(2, 0, 1)
    inverse = np.linalg.inv(Gxx)
    expected = {source: sampled_frf(system, source, r.frequency, fs) for source in INPUTS}
    for k, name in enumerate(CHANNELS):
        Gxy = np.array([csd(forces[a], noisy[name], **kw)[1][lines] for a in INPUTS]).T
        np.testing.assert_allclose(r.H[:, k, :], np.linalg.solve(Gxx, Gxy[..., None])[..., 0],
                                   rtol=1e-9)
        noise = (1 - r.coherence[:, k]) * welch(noisy[name], **kw)[1][lines]
        for i, source in enumerate(INPUTS):
            h = expected[source][name]
            # the standard deviation of each part of H_i: G_nn (G_xx^-1)_ii / (2 n)
            sigma = np.sqrt(noise * inverse[:, i, i].real / (2 * r.averages / 1.06)) / np.abs(h)
            error = np.abs(r.frf(name, source) / h - 1)
            assert (error < 5 * sigma + 0.01).all(), (source, name, (error / sigma).max())
            assert np.median(error / sigma) < 1.5, (source, name, np.median(error / sigma))


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 10_000))
def test_one_input_is_the_single_input_h1(seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(2048)
    y = {"y": np.convolve(x, rng.standard_normal(8))[:2048] + 0.1 * rng.standard_normal(2048)}
    mimo = estimate_frf_matrix({"x": x}, y, 0.01, segment=256)
    siso = estimate_frf(x, y, 0.01, segment=256)
    np.testing.assert_allclose(mimo.frf("y", "x"), siso.frf["y"], rtol=1e-12)
    np.testing.assert_allclose(mimo.coherence[:, 0], siso.coherence["y"], rtol=1e-10,
                               atol=1e-12)


def test_round_trip_chart_summary():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((2, 2048))
    r = estimate_frf_matrix({"a": x[0], "b": x[1]}, {"y": x[0] + 2 * x[1]}, 0.01,
                            segment=128)
    back = MIMOFRF.from_dict(json.loads(json.dumps(r.to_dict())))
    np.testing.assert_array_equal(back.H, r.H)
    assert back.inputs == ("a", "b") and len(r.chart().panels) == 3
    assert "2 inputs" in r.chart().title and "H1 matrix: 1 responses x 2 inputs" in r.summary()
    with pytest.raises(ModelError, match="no channel 'c'"):
        r.frf("y", "c")


def test_bad_input():
    rng = np.random.default_rng(2)
    x = rng.standard_normal(1024)
    with pytest.raises(ModelError, match="coherent with each other at every line"):
        estimate_frf_matrix({"a": x, "b": 2 * x}, {"y": x}, 0.01, segment=128)
    with pytest.raises(ModelError, match="1 segments for 2 inputs"):
        estimate_frf_matrix({"a": x, "b": x[::-1]}, {"y": x}, 0.01, segment=1024,
                            window="rectangular")
    with pytest.raises(ModelError, match="has 100 samples, the excitation 1024"):
        estimate_frf_matrix({"a": x, "b": x[:100]}, {"y": x}, 0.01)
    with pytest.raises(ModelError, match="at least one input and one response"):
        estimate_frf_matrix({}, {"y": x}, 0.01)
    bad = x.copy()
    bad[5] = np.nan
    with pytest.raises(ModelError, match="sample 6 is NaN"):
        estimate_frf_matrix({"a": x}, {"y": bad}, 0.01)
