"""Modes and updating from an FRF matrix (several inputs), the matrix in Universal Files, and
the analytic FRF sensitivities against finite differences.

References and tolerances:
* FRF matrices written from known modes (receptance of a proportionally damped system,
  H_oi = sum_r phi_o phi_i / (w_r^2 - w^2 + 2 i zeta_r w_r w); Ewins, Modal Testing, 2nd ed.,
  eq. 2.72): the frequencies to 1e-6 (relative), the damping ratios to 1e-5, the MAC of the
  shapes with phi above 0.99999 and the participation factors L_ir = phi_i,r / phi_i*,r to
  1e-6 (i* the input of the largest |phi|), also for a mode with a node at one input, which
  that input's FRFs alone do not show;
* the 3-mass chain (examples/chain3_lab.toml, k = 1000 N/m, m = 1 kg, c = 8 N s/m: C = c/k K)
  driven at mass 3 and mass 1 through the kernel: omega_j = 2 sqrt(k/m) sin((2j-1) pi / 14),
  zeta_j = c omega_j / (2 k), to 3e-6 and 1e-5 (the third mode's LSCF pole moves by up to
  2e-6 with the model order and the BLAS build: measured 8e-7 to 2.1e-6 at orders 24-40 on
  one machine, 1.2e-6 at order 30 on another; the first two to 1e-7);
* updating to a 2-input FRF matrix of the chain at k1 = 1100, k2 = 950 N/m: both recovered to
  1e-6 (no noise), with analytic and with differenced sensitivities;
* the analytic Jacobian (dH/dp = -H dZ/dp H) equals central differences of the FRF to 1e-6
  relative (their truncation error is O(1e-10), the difference of rounding O(1e-9)), for
  log and complex residuals, displacement and acceleration channels, one and two inputs
  (hypothesis over the parameter point); the eigenvalue sensitivities of the frequency
  update (Fox & Kapoor) equal differences of the frequencies to 1e-6;
* the matrix through a Universal File: binary 58b bit for bit, ASCII 58 to 1e-10 (pyuff's
  12 significant digits).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import resonant
from conftest import run_cli
from resonant.analyses.frf_mimo import estimate_frf_matrix, frf_matrix_of, pair_name
from resonant.analyses.frf_update import (
    FRFUpdate,
    _FRFProblem,
    model_frf_matrix,
    update_to_frf,
)
from resonant.analyses.identify import (
    ModalIdentification,
    identify_modes,
    identify_modes_matrix,
    modal_assurance,
)
from resonant.api import loads
from resonant.deadline import NO_DEADLINE
from resonant.errors import ModelError
from resonant.model.measured import MeasuredData, MeasuredFunction, read_uff, write_uff
from resonant.model.measurement_spec import ChannelMap

FN = np.array([10.0, 16.0, 25.0])
ZETA = np.array([0.05, 0.02, 0.03])
PHI = np.array([[1.0, 0.0, 0.5], [0.7, -0.9, 1.0], [0.4, 1.0, -0.8], [0.9, 0.2, 0.3]])
REFERENCES = (0, 2)                 # mode 2 has a node at the first reference
CHANNELS = {"d1": ChannelMap("x1"), "d2": ChannelMap("x2"), "d3": ChannelMap("x3")}
CHAIN = "examples/chain3_lab.toml"


def modal_matrix(f: np.ndarray) -> np.ndarray:
    w = 2 * np.pi * f[:, None, None, None]
    wr = 2 * np.pi * FN
    refs = PHI[list(REFERENCES)]
    terms = PHI[None, :, None, :] * refs[None, None, :, :] / (
        wr ** 2 - w ** 2 + 2j * ZETA * wr * w)
    return terms.sum(axis=3)                                   # (lines, outputs, inputs)


@pytest.fixture(scope="module")
def chain():
    return resonant.load(CHAIN).linearize()


def test_matrix_finds_every_mode_with_shared_poles():
    f = np.linspace(2.0, 40.0, 600)
    H = modal_matrix(f)
    outputs, inputs = [f"p{k}" for k in range(len(PHI))], ["u", "v"]
    r = identify_modes_matrix(f, H, outputs, inputs, max_order=30)
    assert len(r.frequency) == 3, r.summary()
    np.testing.assert_allclose(r.frequency, FN, rtol=1e-6)
    np.testing.assert_allclose(r.damping, ZETA, atol=1e-5)
    assert (np.diag(modal_assurance(r.shapes, PHI)) > 0.99999).all()
    refs = PHI[list(REFERENCES)]
    expected = refs / refs[np.argmax(np.abs(refs), axis=0), np.arange(3)]
    np.testing.assert_allclose(r.participation, expected, atol=1e-6)
    assert r.inputs == ("u", "v") and r.channels == tuple(outputs) and not r.warnings
    assert set(r.errors) == {pair_name(o, i) for o in outputs for i in inputs}
    assert max(r.errors.values()) < 1e-6
    # the first input's FRFs alone miss the mode with a node there
    alone = identify_modes(f, {o: H[:, k, 0] for k, o in enumerate(outputs)}, max_order=30)
    assert not np.isclose(alone.frequency, FN[1], rtol=1e-3).any()
    back = ModalIdentification.from_dict(json.loads(json.dumps(r.to_dict())))
    np.testing.assert_allclose(back.participation, r.participation)
    assert back.inputs == r.inputs and set(back.measured) == set(r.measured)
    assert len(r.chart().panels[1].curves) == 16        # 8 pairs, measured and fitted


def test_one_input_matrix_is_the_single_reference_identification():
    f = np.linspace(2.0, 40.0, 400)
    H = modal_matrix(f)[:, :, 1:]
    names = [f"p{k}" for k in range(len(PHI))]
    matrix = identify_modes_matrix(f, H, names, ["v"], max_order=24)
    single = identify_modes(f, {n: H[:, k, 0] for k, n in enumerate(names)}, max_order=24)
    np.testing.assert_allclose(matrix.poles, single.poles, rtol=1e-12)
    np.testing.assert_allclose(matrix.shapes, single.shapes, rtol=0,
                               atol=1e-9 * np.abs(single.shapes).max())
    with pytest.raises(ModelError, match="the FRF matrix must be"):
        identify_modes_matrix(f, H, names[:2], ["v"])


def test_chain_matrix_from_the_kernel(chain):
    f = np.linspace(0.5, 15.0, 600)
    H = model_frf_matrix(chain, ["F", "x1"], f, CHANNELS)
    r = identify_modes_matrix(f, H, list(CHANNELS), ["hammer", "shaker"], max_order=30)
    omega = 2 * np.sqrt(1000.0) * np.sin((2 * np.arange(1, 4) - 1) * np.pi / 14)
    np.testing.assert_allclose(r.frequency, omega / (2 * np.pi), rtol=3e-6)
    np.testing.assert_allclose(r.frequency[:2], omega[:2] / (2 * np.pi), rtol=1e-7)
    np.testing.assert_allclose(r.damping, 8 * omega / 2000, atol=1e-5)
    # the residue matrix of a mode is reciprocal: L (to x3 and x1) ~ the shape at x3, x1
    shapes = np.asarray(r.shapes)
    ratio = r.participation[1] / r.participation[0]
    np.testing.assert_allclose(ratio, shapes[0] / shapes[2], rtol=1e-6)


def test_matrix_through_universal_files(tmp_path):
    rng = np.random.default_rng(0)
    x = rng.standard_normal((2, 4096))
    y = {"d1": x[0] + 0.3 * np.roll(x[1], 2), "d2": x[1] - np.roll(x[0], 1)}
    r = estimate_frf_matrix({"u": x[0], "v": x[1]}, y, 0.01, segment=256)
    for binary, tolerance in ((True, 0.0), (False, 1e-10)):
        path = tmp_path / f"matrix{int(binary)}.uff"
        write_uff(path, r.to_measured(path.name, {"d1": "m/N", "d2": "m/N"}), binary=binary)
        data = read_uff(path)
        f, H, units = frf_matrix_of(data, ["d1", "d2"], ["u", "v"])
        np.testing.assert_array_equal(f, r.frequency)
        assert np.abs(H - r.H).max() <= tolerance * np.abs(r.H).max()
        assert units == {"d1": "m/N", "d2": "m/N"}
        assert data.function("d2/v").reference == (2, 0)
    with pytest.raises(ModelError, match="no FRF 'd3/u'"):
        frf_matrix_of(data, ["d1", "d3"], ["u", "v"])


def _two_input_model(tmp_path):
    text = open(CHAIN).read().replace('excitation = "hammer"\ninput = "F"',
                                      'excitation = ["hammer", "shaker"]\ninput = ["F", "x1"]')
    path = tmp_path / "two_inputs.toml"
    path.write_text(text)
    return path


def _matrix_file(system, path, **values):
    f = 0.5 + 0.05 * np.arange(231)         # a step the file's header holds exactly
    H = model_frf_matrix(system, ["F", "x1"], f, CHANNELS, **values)
    functions = [MeasuredFunction(pair_name(c, i), "frf", f, H[:, r, k], "Hz", "m/N",
                                  (r + 1, 0), (k + 1, 0))
                 for r, c in enumerate(CHANNELS) for k, i in enumerate(("hammer", "shaker"))]
    write_uff(path, MeasuredData(path.name, tuple(functions)), binary=True)
    return f, H


def test_update_to_the_frf_matrix(chain):
    f = np.linspace(0.5, 12.0, 160)
    H = model_frf_matrix(chain, ["F", "x1"], f, CHANNELS, k1=1100.0, k2=950.0)
    measured = {pair_name(c, i): H[:, r, k] for r, c in enumerate(CHANNELS)
                for k, i in enumerate(("hammer", "shaker"))}
    inputs = {"hammer": "F", "shaker": "x1"}
    bounds = {"k1": ("500 N/m", "2 kN/m"), "k2": ("500 N/m", "2 kN/m")}
    for how in ("analytic", "differences"):
        r = update_to_frf(chain, bounds, f, measured, inputs, CHANNELS, sensitivities=how)
        assert r.fitted["k1"] == pytest.approx(1100.0, rel=1e-6)
        assert r.fitted["k2"] == pytest.approx(950.0, rel=1e-6)
    assert r.channels[:2] == ("d1/hammer", "d1/shaker") and r.units == ("",) * 6
    assert FRFUpdate.from_dict(json.loads(json.dumps(r.to_dict()))).channels == r.channels
    with pytest.raises(ModelError, match="no measured FRF for the channel 'd1/shaker'"):
        update_to_frf(chain, bounds, f, {"d1/hammer": H[:, 0, 0]}, inputs,
                      {"d1": ChannelMap("x1")})
    with pytest.raises(ModelError, match="sensitivities 'exact'"):
        update_to_frf(chain, bounds, f, measured, inputs, CHANNELS, sensitivities="exact")


@settings(max_examples=6, deadline=None)
@given(k1=st.floats(600.0, 1800.0), c=st.floats(2.0, 20.0), m=st.floats(0.5, 2.0),
       residual=st.sampled_from(["log", "complex"]), inputs=st.sampled_from([1, 2]))
def test_analytic_jacobian_equals_differences(k1, c, m, residual, inputs):
    system = resonant.load(CHAIN).linearize()
    f = np.linspace(0.5, 12.0, 60)
    channels = {"d1": ChannelMap("x1"), "a3": ChannelMap("x3", 2)}
    signals = ["F", "x1"][:inputs]
    H = model_frf_matrix(system, signals, f, channels, k1=1000.0)
    measured = np.transpose(H, (1, 2, 0)).reshape(-1, len(f))
    problem = _FRFProblem(system, ["k1", "c", "m"], f, measured, signals, channels,
                          residual, "analytic", NO_DEADLINE)
    x = np.log([k1, c, m])
    analytic, differences = problem.analytic_jacobian(x), problem.difference_jacobian(x)
    assert analytic is not None
    scale = np.abs(differences).max(axis=0)
    assert (np.abs(analytic - differences).max(axis=0) <= 1e-6 * scale).all()


def test_frequency_sensitivities_equal_differences():
    from resonant.analyses.model_update import _Problem

    system = resonant.load(CHAIN).linearize()
    target = np.array([2.3, 6.4, 9.2])
    problem = _Problem(system, ["k1", "k2", "m"], target, None, [], 0.0, NO_DEADLINE)
    x = np.log([1100.0, 900.0, 1.1])
    J = problem.jacobian(x)
    h = 1e-6
    differences = np.column_stack([(problem.residuals(x + h * e) - problem.residuals(x - h * e))
                                   / (2 * h) for e in np.eye(3)])
    np.testing.assert_allclose(J, differences, rtol=1e-6, atol=1e-9)


def test_commands_identify_and_update_from_a_matrix_file(chain, tmp_path):
    model = _two_input_model(tmp_path)
    frfs = tmp_path / "matrix.uff"
    _matrix_file(chain, frfs, k1=1100.0)
    status, out, err = run_cli(["identify", model, frfs, "--order", "24", "--json"])
    assert status == 0, err
    found = ModalIdentification.from_dict(json.loads(out))
    assert found.inputs == ("hammer", "shaker") and len(found.frequency) == 3
    status, out, err = run_cli(["correlate", model, frfs, "--order", "24", "--json"])
    assert status == 0, err
    status, out, err = run_cli(["update", model, frfs, "--fit", "frf", "--vary",
                                "k1=500 N/m:2 kN/m", "--json"])
    assert status == 0, err
    fitted = FRFUpdate.from_dict(json.loads(out))
    assert fitted.fitted["k1"] == pytest.approx(1100.0, rel=1e-6)
    assert fitted.units == ("m/N",) * 6
    status, _, err = run_cli(["update", model, frfs, "--vary", "k1=500 N/m:2 kN/m",
                              "--order", "24"])
    assert status == 0, err
    (tmp_path / "half.uff").write_bytes(b"")
    write_uff(tmp_path / "half.uff", MeasuredData("half.uff", tuple(
        g for g in read_uff(frfs).functions if not g.name.endswith("shaker"))), binary=True)
    status, _, err = run_cli(["identify", model, tmp_path / "half.uff"])
    assert status == 2 and "no FRF 'd1/shaker'" in err, err


def test_frf_saves_the_matrix(tmp_path):
    model = _two_input_model(tmp_path)
    rng = np.random.default_rng(3)
    n, fs = 4096, 64.0
    x = rng.standard_normal((2, n))
    y = {"d1": x[0] + 0.5 * x[1], "d2": np.roll(x[1], 1), "d3": x[0] - x[1]}
    csv = tmp_path / "test.csv"
    np.savetxt(csv, np.column_stack([np.arange(n) / fs, x[0], x[1], *y.values()]),
               fmt="%.17g", delimiter=",", header="time,hammer,shaker,d1,d2,d3", comments="")
    saved = tmp_path / "matrix.uff"
    status, _, err = run_cli(["frf", model, csv, "--segment", "512", "--save", saved])
    assert status == 0, err
    f, H, _ = frf_matrix_of(read_uff(saved), list(y), ["hammer", "shaker"])
    direct = estimate_frf_matrix({"hammer": x[0], "shaker": x[1]}, y, 1 / fs, segment=512)
    np.testing.assert_allclose(H, direct.H, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(f, direct.frequency)


def _matrix_chain(n: int) -> str:
    """An n-mass chain given by its matrices, k1 its first spring (tridiagonal)."""
    def spring(i: int) -> str:
        return "k1" if i == 0 else "k"

    K = [[0] * n for _ in range(n)]
    for i in range(n):
        K[i][i] = f"{spring(i)} + k" if i < n - 1 else spring(i)
        if i:
            K[i][i - 1] = K[i - 1][i] = "-k"
    M = [["m" if i == j else 0 for j in range(n)] for i in range(n)]
    C = [["2*sqrt(k*m)/100" if i == j else 0 for j in range(n)] for i in range(n)]
    coordinates = "\n".join(f'x{i + 1} = {{ unit = "m" }}' for i in range(n))
    return (f'title = "chain"\n[parameters]\nm = "1 kg"\nk1 = "1000 N/m"\nk = "1000 N/m"\n'
            f'[coordinates]\n{coordinates}\n[matrices]\nM = {json.dumps(M)}\n'
            f'K = {json.dumps(K)}\nC = {json.dumps(C)}\n')


@pytest.mark.parametrize("n, stacked", [(16, 0), (3, 0), (16, 24)])
def test_banded_dense_and_stacked_routes_agree(monkeypatch, n, stacked):
    from resonant.analyses import frf_sensitivity

    monkeypatch.setattr(frf_sensitivity, "STACKED_LIMIT", stacked)
    system = loads(_matrix_chain(n)).linearize()
    f = np.linspace(0.5, 12.0, 50)
    channels = {"d1": ChannelMap("x1"), "v": ChannelMap(f"x{n}", 1)}
    signals = ["x1", f"x{n}"]
    H = model_frf_matrix(system, signals, f, channels, k1=1200.0)
    problem = _FRFProblem(system, ["k1", "k", "m"], f, np.transpose(H, (1, 2, 0)).reshape(
        -1, len(f)), signals, channels, "complex", "analytic", NO_DEADLINE)
    x = np.log([1000.0, 900.0, 1.2])
    analytic, differences = problem.analytic_jacobian(x), problem.difference_jacobian(x)
    scale = np.abs(differences).max(axis=0)
    assert (np.abs(analytic - differences).max(axis=0) <= 1e-6 * scale).all()
    found = frf_sensitivities_at(system, signals, f, channels)
    np.testing.assert_allclose(found, H, rtol=1e-9)


def frf_sensitivities_at(system, signals, f, channels):
    from resonant.analyses.frf_sensitivity import frf_with_sensitivities

    return frf_with_sensitivities(system, signals, f, channels, [], {"k1": 1200.0})[0]
