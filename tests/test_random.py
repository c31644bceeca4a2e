"""Random excitation: the ``[random]`` section and the response spectral densities.

Reference values, each from the literature:

* a single-DOF system m x'' + c x' + k x = F under white-noise force: with the two-sided
  density S0 per rad/s, E[x^2] = pi S0 / (k c) (Crandall & Mark, *Random Vibration in
  Mechanical Systems*, 1963, Eq. 2.39; Newland, *Random Vibrations*, Eq. 7.24).  resonant's
  inputs are one-sided per Hz, G(f) = 4 pi S0 (G df = 2 S dw over w >= 0), so
  E[x^2] = G / (4 k c).  Its rate of zero up-crossings is f_n (Rice: sqrt(m2/m0), and
  E[x'^2] / E[x^2] = k / m for white noise).  Band [0, 10^3 f_n]: truncation below 1e-9.
* a 2-DOF system with non-proportional damping under two correlated white-noise forces:
  the exact covariance of the state from the Lyapunov equation A P + P A^T + B W B^T = 0
  with W = G_u / 2 (Newland, Ch. 7; the same white noise as above), to 1e-6.
* Miles' equation (Miles 1954) for the absolute acceleration of a lightly damped SDOF on a
  base under white acceleration: RMS^2 = (pi/2) f_n Q G.  The exact value over [0, inf)
  is (pi/2) f_n Q G (1 + 1/Q^2) (the integral of the transmissibility squared), so Miles
  is low by the factor sqrt(1 + 1/Q^2): checked to 1e-4 for Q = 10.
* NASA GSFC-STD-7000B (GEVS) Table 2.4-3, the component qualification spectrum, 14.1 Grms
  (the standard's rounded value; its exact log-log area is checked to 1e-8).
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES, run_cli
from resonant.analyses.random_response import random_response
from resonant.errors import ModelError
from resonant.model import loads
from resonant.model.random_spec import STANDARD_GRAVITY
from resonant.system import linear_system

GEVS = EXAMPLES / "shaker_gevs.toml"
GEVS_TABLE = [(20, 0.026), (50, 0.16), (800, 0.16), (2000, 0.026)]

SDOF = """
[parameters]
m = {m}
k = {k}
c = {c}
[coordinates]
x = ""
[signals]
F = "0"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2 - F*x"
D = "c*x'^2/2"
[outputs]
v = "x'"
[random]
band = [0, {high}]
tolerance = 1e-6
[random.psd.F]
values = {G}
"""


def loglog_area(table: list[tuple[float, float]]) -> float:
    """The exact area under a table interpolated linearly in log f, log S."""
    area = 0.0
    for (f1, s1), (f2, s2) in zip(table, table[1:]):
        n = math.log(s2 / s1) / math.log(f2 / f1)
        area += s1 * f1 * math.log(f2 / f1) if n == -1 else \
            s1 * f1 / (n + 1) * ((f2 / f1) ** (n + 1) - 1)
    return area


def sdof(m: float, k: float, c: float, G: float) -> object:
    fn = math.sqrt(k / m) / (2 * math.pi)
    return random_response(linear_system(loads(SDOF.format(m=m, k=k, c=c, G=G,
                                                           high=1000 * fn))))


def test_sdof_white_noise_force() -> None:
    m, k, c, G = 2.0, 800.0, 1.6, 0.5
    result = sdof(m, k, c, G)
    assert result.rms["x"] ** 2 == pytest.approx(G / (4 * k * c), rel=1e-6)
    # the velocity: E[x'^2] = G / (4 m c) less the tail above the band, where
    # |H_v|^2 -> 1/(m w)^2: G / (4 pi^2 m^2 f_high) (relative 2.5e-5 here)
    fn = math.sqrt(k / m) / (2 * math.pi)
    tail = G / (4 * math.pi**2 * m**2 * 1000 * fn)
    assert result.rms["v"] ** 2 == pytest.approx(G / (4 * m * c) - tail, rel=1e-6)
    m2 = result.rms["v"] ** 2 / (2 * math.pi) ** 2       # m2 = integral of f^2 G_x df
    assert result.zero_crossing_rate["x"] == pytest.approx(
        math.sqrt(m2) / result.rms["x"], rel=1e-7)
    assert result.zero_crossing_rate["x"] == pytest.approx(fn, rel=2e-5)
    assert result.error["x"] < 1e-6
    # Miles' estimate is exact for the displacement under a white force
    assert result.miles is not None
    assert result.miles["x"] == pytest.approx(result.rms["x"], rel=1e-5)
    assert result.three_sigma["x"] == 3 * result.rms["x"]


@settings(max_examples=8, deadline=None)
@given(st.floats(0.1, 10), st.floats(10, 1e4), st.floats(0.005, 0.3))
def test_sdof_white_noise_any_parameters(m: float, k: float, zeta: float) -> None:
    c = 2 * zeta * math.sqrt(k * m)
    result = sdof(m, k, c, 1.0)
    assert result.rms["x"] ** 2 == pytest.approx(1 / (4 * k * c), rel=1e-6)


TWO_DOF = """
[parameters]
m1 = 1.5
m2 = 0.7
k1 = 900
k2 = 400
c1 = 1.2
c2 = 3.0
[coordinates]
x1 = ""
x2 = ""
[signals]
F1 = "0"
F2 = "0"
[energy]
T = "m1*x1'^2/2 + m2*x2'^2/2"
U = "k1*x1^2/2 + k2*(x2 - x1)^2/2 - F1*x1 - F2*x2"
D = "c1*x1'^2/2 + c2*(x2' - x1')^2/2"
[outputs]
stretch = "x2 - x1"
v2 = "x2'"
[random]
band = [0, 5000]
tolerance = 1e-6
[random.psd.F1]
values = 0.3
[random.psd.F2]
values = 0.8
[[random.coherence]]
inputs = ["F1", "F2"]
value = 0.5
"""


def test_two_dof_against_lyapunov() -> None:
    result = random_response(linear_system(loads(TWO_DOF)))
    M = np.diag([1.5, 0.7])
    K = np.array([[1300.0, -400.0], [-400.0, 400.0]])
    C = np.array([[4.2, -3.0], [-3.0, 3.0]])
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ K, -Minv @ C]])
    B = np.vstack([np.zeros((2, 2)), Minv])
    cross = math.sqrt(0.5 * 0.3 * 0.8)
    W = np.array([[0.3, cross], [cross, 0.8]]) / 2     # one-sided per Hz -> intensity
    P = scipy.linalg.solve_continuous_lyapunov(A, -B @ W @ B.T)
    assert result.rms["x1"] ** 2 == pytest.approx(P[0, 0], rel=1e-6)
    assert result.rms["x2"] ** 2 == pytest.approx(P[1, 1], rel=1e-6)
    assert result.rms["stretch"] ** 2 == pytest.approx(P[0, 0] + P[1, 1] - 2 * P[0, 1],
                                                       rel=1e-6)
    # less the tail above 5000 Hz, where |H_v2|^2 -> 1/(m2 w)^2 (relative 3e-5)
    tail = 0.8 / (4 * math.pi**2 * 0.7**2 * 5000)
    assert result.rms["v2"] ** 2 == pytest.approx(P[3, 3] - tail, rel=1e-6)
    assert result.miles is None                  # two DOF: no Miles estimate


def test_uncorrelated_inputs_add() -> None:
    text = TWO_DOF.replace("value = 0.5", "value = 0")
    both = random_response(linear_system(loads(text)))
    one = random_response(linear_system(loads(text.replace("values = 0.8", "values = 0"))))
    two = random_response(linear_system(loads(text.replace("values = 0.3", "values = 0"))))
    for name in both.names:
        assert both.rms[name] ** 2 == pytest.approx(one.rms[name] ** 2 + two.rms[name] ** 2,
                                                    rel=1e-7)


MILES = """
[parameters]
m = 1
k = "(2*pi*100)^2"
c = "2*0.05*sqrt(k*m)"
[coordinates]
x = ""
[signals]
y = "0"
[energy]
T = "m*x'^2/2"
U = "k*(x - y)^2/2"
D = "c*(x' - y')^2/2"
[outputs]
a = "(k*(y - x) + c*(y' - x'))/m"
[random]
band = [0.01, 100000]
tolerance = 1e-6
[random.psd.y]
derivative = 2
unit = "g^2/Hz"
values = 0.1
"""


def test_miles_equation() -> None:
    result = random_response(linear_system(loads(MILES)))
    G = 0.1 * STANDARD_GRAVITY ** 2
    Q = 10.0
    miles = math.sqrt(math.pi / 2 * 100 * Q * G)
    assert result.natural_frequency == pytest.approx(100, rel=1e-12)
    assert result.quality == pytest.approx(Q, rel=1e-12)
    assert result.miles is not None
    assert result.miles["a"] == pytest.approx(miles, rel=1e-7)
    assert result.rms["a"] == pytest.approx(miles * math.sqrt(1 + 1 / Q**2), rel=1e-4)


def test_gevs_table_integrates_to_14_1_grms() -> None:
    area = loglog_area(GEVS_TABLE)
    assert math.sqrt(area) == pytest.approx(14.1, abs=0.05)
    result = random_response(linear_system(loads(GEVS.read_text(), source=str(GEVS))))
    # the output "table" is y'' itself: its RMS is the spectrum's overall level
    assert result.rms["table"] / STANDARD_GRAVITY == pytest.approx(math.sqrt(area), rel=1e-8)
    # the table is interpolated log-log: at 35 Hz, 0.026 (35/20)^n
    n = math.log(0.16 / 0.026) / math.log(50 / 20)
    f = result.frequency
    i = int(np.argmin(abs(f - 35)))
    assert result.input_psd["y"][i] / STANDARD_GRAVITY**2 == pytest.approx(
        0.026 * (f[i] / 20) ** n, rel=1e-10)
    assert result.units["a"] == "m/s^2"
    assert result.miles is not None and "table" not in result.miles
    # Miles with the 0.16 g^2/Hz plateau at f_n = 200 Hz, Q = 10
    assert result.miles["a"] / STANDARD_GRAVITY == pytest.approx(
        math.sqrt(math.pi / 2 * 200 * 10 * 0.16), rel=1e-6)


def test_units_of_densities() -> None:
    base = MILES.replace("[random]", "[random]\n").replace("tolerance = 1e-6", "")
    g = random_response(linear_system(loads(base)))
    si = random_response(linear_system(loads(base.replace(
        'unit = "g^2/Hz"', 'unit = "(m/s^2)^2/Hz"').replace(
        "values = 0.1", f"values = {0.1 * STANDARD_GRAVITY**2!r}"))))
    per_rad = random_response(linear_system(loads(base.replace(
        'unit = "g^2/Hz"', 'unit = "g^2/(rad/s)"').replace(
        "values = 0.1", f"values = {0.1 / (2 * math.pi)!r}"))))
    assert si.rms["a"] == pytest.approx(g.rms["a"], rel=1e-12)
    assert per_rad.rms["a"] == pytest.approx(g.rms["a"], rel=1e-12)


@pytest.mark.parametrize("change, message", [
    (("band = [0.01, 100000]", "band = [0, 100000]"), "starts at 0 Hz"),
])
def test_analysis_errors(change: tuple[str, str], message: str) -> None:
    with pytest.raises(ModelError, match=message):
        random_response(linear_system(loads(MILES.replace(*change))))


@pytest.mark.parametrize("change, message", [
    (("derivative = 2", "derivative = 3"), "derivative must be 0, 1 or 2"),
    (('unit = "g^2/Hz"', 'unit = "g^2"'), "not a density per frequency"),
    (('unit = "g^2/Hz"', 'unit = "N/mmm"'), "unknown unit"),
    (("[random.psd.y]", "[random.psd.yy]"), "did you mean 'y'"),
    (("values = 0.1", "values = [[10, 1], [5, 2]]"), "must increase"),
    (("values = 0.1", "values = [[10, 1], [20, -2]]"), "must be positive"),
    (("values = 0.1", 'values = "q*f"'), "unknown name 'q'"),
    (("tolerance = 1e-6", "tolerance = 2"), "tolerance must be"),
    (("tolerance = 1e-6", "tolerance = 1e-9\nspeed = 3"), "unknown key 'speed'"),
    (("band = [0.01, 100000]", "band = [5, 1]"), "0 <= low < high"),
    (("band = [0.01, 100000]\n", ""), "band = \\[low, high\\]"),
])
def test_section_errors(change: tuple[str, str], message: str) -> None:
    with pytest.raises(ModelError, match=message) as info:
        loads(MILES.replace(*change), source="m.toml")
    assert "m.toml: [random" in str(info.value)


def test_band_beyond_table() -> None:
    text = GEVS.read_text().replace("tolerance = 1e-6", "tolerance = 1e-6\nband = [10, 2000]")
    with pytest.raises(ModelError, match="goes beyond the table of y"):
        loads(text, source="m.toml")


def test_dimension_of_density_checked() -> None:
    text = SDOF.format(m='"1 kg"', k='"100 N/m"', c='"1 N*s/m"', G=1, high=100).replace(
        'F = "0"', 'F = "F0*sin(w*t)"').replace(
        "[parameters]", '[parameters]\nF0 = "1 N"\nw = "1 rad/s"')
    assert loads(text.replace("values = 1", 'values = 1\nunit = "N^2/Hz"')).random_section
    with pytest.raises(ModelError, match="a density of m, but F is in N"):
        loads(text.replace("values = 1", 'values = 1\nunit = "m^2/Hz"'), source="m.toml")


def test_no_random_section() -> None:
    text = MILES.split("[random]")[0]
    with pytest.raises(ModelError, match="no \\[random\\] section"):
        random_response(linear_system(loads(text)))


def test_matrix_model_base_acceleration() -> None:
    """A shear frame under ground acceleration: M z'' + C z' + K z = -M r a_g, against
    the Lyapunov covariance (relative coordinates)."""
    text = (EXAMPLES / "matrices" / "frame.toml").read_text().split("[explore]")[0]
    text += ("[random]\nband = [0.001, 500]\ntolerance = 1e-6\n[random.psd.ground]\n"
             "base = [1, 1, 1]\nunit = \"(m/s^2)^2/Hz\"\nvalues = 0.01\n")
    result = random_response(linear_system(loads(text)))
    m, k, c = 2000.0, 2e5, 800.0
    M = m * np.eye(3)
    K = k * np.array([[2, -1, 0], [-1, 2, -1], [0, -1, 1.0]])
    C = c / k * K
    A = np.block([[np.zeros((3, 3)), np.eye(3)], [-K / m, -C / m]])
    B = np.concatenate([np.zeros(3), -np.ones(3)])[:, None]
    P = scipy.linalg.solve_continuous_lyapunov(A, -B @ B.T * 0.01 / 2)
    # the band's low end leaves out a flat density of about 1e-3 Hz: relative 1e-5
    for i, name in enumerate(("x1", "x2", "x3")):
        assert result.rms[name] ** 2 == pytest.approx(P[i, i], rel=1e-4)
    assert np.allclose(M, M.T)


def test_to_dict_and_read_only() -> None:
    result = sdof(1.0, 100.0, 0.2, 1.0)
    data = json.loads(json.dumps(result.to_dict()))
    assert data["responses"]["x"]["rms"] == result.rms["x"]
    assert data["convention"] == "one-sided spectral densities per Hz"
    with pytest.raises(ValueError):
        result.frequency[0] = 1.0


def test_cli_text_json_and_plot(tmp_path) -> None:  # type: ignore[no-untyped-def]
    status, out, err = run_cli(["random", GEVS])
    assert status == 0, err
    assert re.search(r"table +g +14\.14 ", out)  # the spectrum is in g^2/Hz: the output in g
    status, out, err = run_cli(["random", GEVS, "--units", "m/s^2"])
    assert status == 0, err
    assert "table  m/s^2" in out and "14.14 g RMS" in out
    assert "Miles RMS" in out
    status, out, err = run_cli(["random", GEVS, "--json", "--only", "a,z"])
    assert status == 0, err
    data = json.loads(out)
    assert set(data["responses"]) == {"z", "a"}
    assert data["inputs"]["y"] == {"unit": "m/s^2", "derivative": 2}
    assert data["responses"]["a"]["miles_rms"] / STANDARD_GRAVITY == pytest.approx(22.42,
                                                                                 abs=0.01)
    assert str(tmp_path) not in out
    plot = tmp_path / "psd.png"
    status, _, err = run_cli(["random", GEVS, "--plot", plot])
    assert status == 0, err
    assert plot.stat().st_size > 10_000


def test_cli_errors(tmp_path) -> None:  # type: ignore[no-untyped-def]
    status, _, err = run_cli(["random", EXAMPLES / "base_excitation.toml"])
    assert status == 2 and "no [random] section" in err
    status, _, err = run_cli(["random", GEVS, "--only", "nothing"])
    assert status == 2 and "unknown coordinate or output 'nothing'" in err
    # a plot file that cannot be written is refused before the work (exit 2; was 3 after it)
    status, _, err = run_cli(["random", GEVS, "--plot", tmp_path / "p.txt"])
    assert status == 2 and ".png, .svg or .pdf" in err
    undamped = tmp_path / "undamped.toml"
    undamped.write_text(GEVS.read_text().replace('c = "125.6637 N*s/m"', 'c = "0 N*s/m"'))
    status, _, err = run_cli(["random", undamped])
    assert status == 3 and "undamped resonance" in err
    assert "Traceback" not in err


COHERENT = """
[parameters]
m = 1
k = 400
c = 2
[coordinates]
x = ""
[matrices]
M = [["m"]]
K = [["k"]]
C = [["c"]]
[random]
band = [0.5, 50]
tolerance = 1e-8
[random.psd.x]
values = 2.0
[random.psd.push]
load = ["2"]
values = "0.5*(1 + f/50)"
[[random.coherence]]
inputs = ["x", "push"]
value = "{gamma2}"
phase = "{phase}"
"""


@pytest.mark.parametrize("gamma2, phase", [(1.0, 0.0), (1.0, 2.0), (0.3, 1.0), (0.0, 0.0)])
def test_coherence_and_phase(gamma2: float, phase: float) -> None:
    """Two inputs on one coordinate (a force on x and a load vector 2 x push):
    G_x = |H|^2 (G1 + 4 G2 + 2 * 2 sqrt(gamma^2 G1 G2) cos(phase))."""
    result = random_response(linear_system(loads(COHERENT.format(gamma2=gamma2,
                                                                 phase=phase))))
    f = result.frequency
    w = 2 * np.pi * f
    H2 = 1 / np.abs(400 - w**2 + 2j * w) ** 2
    G1, G2 = 2.0, 0.5 * (1 + f / 50)
    expected = H2 * (G1 + 4 * G2 + 4 * np.sqrt(gamma2 * G1 * G2) * np.cos(phase))
    assert np.allclose(result.psd["x"], expected, rtol=1e-12, atol=0)
    assert result.input_psd["push"] == pytest.approx(G2, rel=1e-12)


def test_coherence_out_of_range() -> None:
    with pytest.raises(ModelError, match="must lie in \\[0, 1\\]"):
        random_response(linear_system(loads(COHERENT.format(gamma2="2", phase=0))))


@pytest.mark.slow
def test_large_chain_against_modal_superposition(tmp_path) -> None:  # type: ignore
    """A 600-DOF fixed-free chain (sparse matrix files, Rayleigh damping: the modes
    decouple) under a white force at its free end: the free end's RMS against a
    hand-written modal superposition (scipy's tridiagonal eigensolver, all 600 modes,
    |H|^2 on a fine grid of 200,001 frequencies), to the section's tolerance."""
    import scipy.sparse

    n, k, a, b = 600, 1e4, 0.1, 1e-4
    K = scipy.sparse.diags([np.full(n - 1, -k), np.r_[np.full(n - 1, 2 * k), k],
                            np.full(n - 1, -k)], [-1, 0, 1], format="csr")
    M = scipy.sparse.identity(n, format="csr")
    scipy.sparse.save_npz(tmp_path / "K.npz", K)
    scipy.sparse.save_npz(tmp_path / "M.npz", M)
    scipy.sparse.save_npz(tmp_path / "C.npz", (a * M + b * K).tocsr())
    model = tmp_path / "chain.toml"
    model.write_text('[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
                     f'[random]\nband = [0.5, 40]\ntolerance = 1e-4\n[random.psd.q{n}]\n'
                     'values = 1.0\n')
    result = random_response(linear_system(loads(model.read_text(), source=str(model),
                                                 base_dir=tmp_path)), names=[f"q{n}"])
    w2, phi = scipy.linalg.eigh_tridiagonal(np.r_[np.full(n - 1, 2 * k), k],
                                            np.full(n - 1, -k))
    f = np.linspace(0.5, 40, 200_001)
    w = 2 * np.pi * f
    H = np.zeros(len(f), dtype=complex)
    for j in range(n):
        H += phi[-1, j] ** 2 / (w2[j] - w**2 + 1j * w * (a + b * w2[j]))
    reference = math.sqrt(np.trapezoid(np.abs(H) ** 2, f))
    assert result.rms[f"q{n}"] == pytest.approx(reference, rel=2e-4)
    assert result.error[f"q{n}"] < 1e-4


def test_study_quantity_rms_equals_the_random_response_at_each_sample(tmp_path):
    """``rms:NAME`` in a study: at every sample, the RMS value of ``random_response`` of the
    model with that sample's values (exactly: the same computation)."""
    import resonant
    from resonant.studies import StudyJob, collect, engine_for, request

    from pathlib import Path

    path = Path(__file__).parents[1] / "examples" / "shaker_gevs.toml"
    model = resonant.load(path)
    spec = request(model, {"k": [1.0e6, 2.0e6]}, ["rms:x", "rms:a"], design="grid")
    table = collect(StudyJob.of(model, spec), engine_for(0)).table
    assert list(table["status"]) == ["ok", "ok"]
    for i, k in enumerate((1.0e6, 2.0e6)):
        direct = resonant.load(path, {"k": k}).random_response(names=["x", "a"])
        assert table["rms:x"][i] == pytest.approx(direct.rms["x"], rel=1e-12)
        assert table["rms:a"][i] == pytest.approx(direct.rms["a"], rel=1e-12)
