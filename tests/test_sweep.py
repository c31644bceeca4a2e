"""Frequency and parameter sweeps (resonant.sweep, ``resonant sweep``).

Reference values:
- single-DOF forced response X = F0 / sqrt((k - m w^2)^2 + (c w)^2), peak at
  w = sqrt(k/m - c^2/(2 m^2)) (Rao, Mechanical Vibrations, Sect. 3.4; Inman, Sect. 2.2);
- undamped absorber: x1 = 0 when k2 = m2 omega^2 (Den Hartog, Mechanical Vibrations,
  Sect. 3.2);
- every other check compares two computations that must agree: a sweep at the model's own
  value with ``resonant solve`` (rel 1e-12) and the solution methods with each other
  (modal / banded / sparse vs a dense direct solve, rel 1e-9 per frequency).
"""

from __future__ import annotations

import csv
import json
import math
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES, run_cli

from resonant.errors import AnalysisError, ModelError
from resonant.api import load, loads
from resonant.analyses.sweep import choose_method

sys.path.insert(0, str(EXAMPLES))
from make_chain import write_chain  # noqa: E402

SDOF = """
[parameters]
m = {m}
k = {k}
c = {c}
F0 = {F0}
omega = 3
[coordinates]
x = "displacement"
[signals]
F = "F0*sin(omega*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
generalized = {{ x = "F" }}
[outputs]
v = "x'"
"""


def sweep(model, *args, **kwargs):
    """The sweep of the model's linear system, as the user calls it (a result with views)."""
    return model.linearize().sweep(*args, **kwargs)


def sdof(m=1.0, k=100.0, c=2.0, F0=1.0):
    return loads(SDOF.format(m=m, k=k, c=c, F0=F0))


@pytest.mark.parametrize("name", ["tuned_mass_damper", "chain3_damped", "cart_pendulum",
                                  "rotating_unbalance", "base_excitation", "damper_excitation"])
def test_sweep_at_model_value_equals_solve(name):
    """The sweep at the model's own excitation frequency equals `resonant solve` (rel 1e-12)."""
    model = load(EXAMPLES / f"{name}.toml")
    solution = model.linearize().stationary()
    param = "omega" if "omega" in model.parameters else next(iter(model.parameters))
    value = model.parameter_values[param]
    result = sweep(model, param, [value * 0.9, value, value * 1.1])
    for key, amplitude in solution.amplitudes.items():
        assert result.amplitudes[key][1] == pytest.approx(amplitude, rel=1e-12, abs=1e-300)
    for key, phase in solution.phases.items():
        diff = (result.phases[key][1] - phase + math.pi) % (2 * math.pi) - math.pi
        assert abs(diff) < 1e-12


def test_cli_sweep_equals_cli_solve():
    code, out, err = run_cli(["sweep", EXAMPLES / "tuned_mass_damper.toml", "--param", "omega",
                              "--from", "31.6227766016838", "--to", "31.6227766016838",
                              "--points", "1", "--json"])
    assert code == 0, err
    swept = json.loads(out)
    code, out, err = run_cli(["solve", EXAMPLES / "tuned_mass_damper.toml", "--json",
                              "--set", "omega=31.6227766016838"])
    solved = json.loads(out)
    for key in ("parameter", "values", "amplitudes", "phases", "peaks", "antiresonances",
                "method"):
        assert key in swept
    for key, amplitude in solved["amplitudes"].items():
        assert swept["amplitudes"][key][0] == pytest.approx(amplitude, rel=1e-12)


@settings(max_examples=30, deadline=None)
@given(m=st.floats(0.1, 10), k=st.floats(1, 1e4), zeta=st.floats(0.001, 0.9),
       F0=st.floats(0.1, 100))
def test_sdof_closed_form_property(m, k, zeta, F0):
    """X = F0/sqrt((k - m w^2)^2 + (c w)^2), delta = -atan2(c w, k - m w^2) (rel 1e-10)."""
    c = 2 * zeta * math.sqrt(k * m)
    wn = math.sqrt(k / m)
    w = np.linspace(0.05 * wn, 3 * wn, 40)
    result = sweep(sdof(m, k, c, F0), "omega", w)
    expected = F0 / np.hypot(k - m * w**2, c * w)
    np.testing.assert_allclose(result.amplitudes["x"], expected, rtol=1e-10)
    np.testing.assert_allclose(result.amplitudes["v"], w * expected, rtol=1e-10)
    np.testing.assert_allclose(np.sin(result.phases["x"]),
                               np.sin(-np.arctan2(c * w, k - m * w**2)), atol=1e-10)


def test_sdof_peak_refined():
    """Peak of X at w = sqrt(k/m - c^2/(2m^2)) = sqrt(98) (Rao Sect. 3.4): grid step 0.05,
    parabolic refinement on log amplitude (error O(step^3)), rel 1e-4."""
    result = sweep(sdof(), "omega", np.arange(1, 20, 0.05))
    peaks = [p for p in result.peaks if p.name == "x"]
    assert len(peaks) == 1
    assert peaks[0].value == pytest.approx(math.sqrt(98), rel=1e-4)
    assert peaks[0].amplitude == pytest.approx(1 / (2 * math.sqrt(99)), rel=1e-5)
    assert result.frequency_sweep and result.unit == "rad/s"
    np.testing.assert_allclose(result.natural_frequencies, [10.0], rtol=1e-12)


def test_absorber_stiffness_sweep_finds_antiresonance():
    """Den Hartog Sect. 3.2: x1 vanishes at k2 = m2 omega^2 = 400 N/m (rel 1e-4)."""
    model = load(EXAMPLES / "absorber.toml")
    result = sweep(model, "k2", np.linspace(150, 950, 161))
    dips = [p for p in result.antiresonances if p.name == "x1"]
    assert len(dips) == 1
    assert dips[0].value == pytest.approx(1 * 20.0**2, rel=1e-4)
    assert dips[0].amplitude < 1e-4 * np.nanmax(result.amplitudes["x1"])
    assert not result.frequency_sweep and result.method == "dense"
    # x2 = -F0/k2 ... constant F0/(m2 w^2) here: no spurious extrema on a flat curve
    assert not [p for p in result.peaks + result.antiresonances if p.name == "x2"]


def test_dependent_parameters_follow():
    """Sweeping m1 of the TMD moves m2 = mu m1, k2, c2 too (same as --set m1=...)."""
    model = load(EXAMPLES / "tuned_mass_damper.toml")
    result = sweep(model, "m1", [80.0, 120.0])
    for value, i in ((80.0, 0), (120.0, 1)):
        solution = model.with_parameters(m1=value).linearize().stationary()
        for key, amplitude in solution.amplitudes.items():
            assert result.amplitudes[key][i] == pytest.approx(amplitude, rel=1e-12)


def test_several_frequencies_use_peak():
    """Two harmonics: amplitude = peak of the summed history, as in `solve`; no phase."""
    model = loads(SDOF.format(m=1, k=100, c=2, F0=1).replace(
        'F = "F0*sin(omega*t)"', 'F = "F0*sin(omega*t) + 0.5*cos(2*omega*t) + 0.1"'))
    result = sweep(model, "omega", [2.0, 3.0])
    solution = model.linearize().stationary()
    assert result.amplitudes["x"][1] == pytest.approx(solution.amplitudes["x"], rel=1e-9)
    assert np.all(np.isnan(result.phases["x"]))


def test_undamped_resonance_point_is_skipped():
    """An exact undamped resonance (k - m w^2 = 0) is marked, not fatal; JSON holds null."""
    model = sdof(m=1.0, k=4.0, c=0.0)
    result = sweep(model, "omega", [1.0, 1.5, 2.0, 2.5, 3.0])
    assert result.skipped == (2.0,)
    assert math.isnan(result.amplitudes["x"][2]) and result.amplitudes["x"][1] > 0
    assert any("undamped resonance" in w for w in result.warnings)
    data = result.to_dict()
    assert data["amplitudes"]["x"][2] is None and data["skipped"] == [2.0]
    json.dumps(data, allow_nan=False)


def proportional_chain(tmp_path, n):
    """A Rayleigh-damped fixed-free chain as a file-based (sparse) matrix model."""
    return load(write_chain(tmp_path, n))


def test_methods_agree_on_proportional_chain(tmp_path):
    """modal (all modes), banded, sparse and dense agree to 1e-9 per frequency, quasi-static
    points included (n = 120, C = 0.1 M + 1e-4 K)."""
    model = proportional_chain(tmp_path, 120)
    w = np.concatenate([[1e-3, 0.05], np.linspace(1, 260, 150)])
    results = {method: sweep(model, "omega", w, method=method)
               for method in ("dense", "banded", "sparse", "modal")}
    reference = results["dense"]
    for method, result in results.items():
        assert result.method == method
        for i in range(len(w)):
            ref = np.array([reference.amplitudes[q][i] for q in reference.coordinates])
            got = np.array([result.amplitudes[q][i] for q in result.coordinates])
            assert np.abs(got - ref).max() <= 1e-9 * np.abs(ref).max(), (method, w[i])
    assert choose_method_for(model, w) == "banded"
    assert results["modal"].warnings == ()


def choose_method_for(model, w):

    return choose_method(model.linearize().batch("omega", np.asarray(w)), len(w))


def test_modal_refuses_non_proportional_damping():
    with pytest.raises(AnalysisError, match="proportional"):
        sweep(load(EXAMPLES / "tuned_mass_damper.toml"), "omega", [30.0, 31.0], method="modal")


def test_sparse_and_dense_agree_with_wide_band(tmp_path):
    """A dense, non-banded symmetric system: auto picks modal; sparse/dense agree (1e-9)."""
    rng = np.random.default_rng(1)
    n = 60
    A = rng.normal(size=(n, n))
    K = A @ A.T + n * np.eye(n)
    M = np.eye(n) + 0.01 * (lambda B: B @ B.T)(rng.normal(size=(n, n)))
    C = 0.05 * M + 1e-3 * K
    np.save(tmp_path / "M.npy", M)
    np.save(tmp_path / "K.npy", K)
    np.save(tmp_path / "C.npy", C)
    force = ", ".join(["1"] + ["0"] * (n - 1))
    (tmp_path / "wide.toml").write_text(
        '[parameters]\nomega = 1\n[matrices]\nM = "M.npy"\nK = "K.npy"\nC = "C.npy"\n'
        f'[[harmonic]]\nomega = "omega"\nF_S = [{force}]\n')
    model = load(tmp_path / "wide.toml")
    w = np.linspace(0.1, 30, 40)
    auto = sweep(model, "omega", w)
    assert auto.method == "modal"
    for method in ("sparse", "dense"):
        other = sweep(model, "omega", w, method=method)
        for q in model.coordinates:
            np.testing.assert_allclose(other.amplitudes[q], auto.amplitudes[q], rtol=1e-9,
                                       atol=1e-9 * np.abs(auto.amplitudes["q1"]).max())


def test_large_chain_auto_is_banded_and_exact(tmp_path):
    """1000-mass chain, 200 frequencies: auto = banded, equal to SuperLU (rel 1e-9)."""
    model = proportional_chain(tmp_path, 1000)
    w = np.linspace(0.01, 250, 200)
    result = sweep(model, "omega", w, names=["q1", "q500", "q1000"])
    assert result.method == "banded"
    reference = sweep(model, "omega", w, names=["q1", "q500", "q1000"], method="sparse")
    for q in ("q1", "q500", "q1000"):
        np.testing.assert_allclose(result.amplitudes[q], reference.amplitudes[q], rtol=1e-9,
                                   atol=1e-300)
    assert set(result.amplitudes) == {"q1", "q500", "q1000"}


def test_plots_png_and_svg(tmp_path):
    import matplotlib.image

    result = sweep(load(EXAMPLES / "tuned_mass_damper.toml"), "omega",
                   np.linspace(20, 45, 201))
    png, svg = tmp_path / "fr.png", tmp_path / "fr.svg"
    result.plot(png)
    result.plot(svg)
    assert png.stat().st_size > 20_000 and svg.stat().st_size > 20_000
    pixels = matplotlib.image.imread(str(png))
    assert pixels.std() > 0.05  # not blank
    text = svg.read_text()
    assert "rad/s" in text or "rad" in text


def test_cli_sweep_outputs_and_csv(tmp_path):
    out_csv, out_png = tmp_path / "s.csv", tmp_path / "s.png"
    code, out, err = run_cli(["sweep", EXAMPLES / "chain3_damped.toml", "--param", "omega",
                              "--from", "1", "--to", "100", "--points", "300", "--log",
                              "--csv", out_csv, "--plot", out_png])
    assert code == 0, err
    assert "resonance peaks" in out and "rad/s" in out
    rows = list(csv.reader(out_csv.open()))
    assert len(rows) == 301 and rows[0][:3] == ["omega", "amplitude_x1", "phase_x1"]
    assert out_png.stat().st_size > 20_000


def test_sweep_text_lists_as_resonances_only_the_peaks_the_plot_marks():
    # The six-storey building's roof drift has a local maximum of 1.27 mm at 1.49 Hz, between
    # the antiresonances on either side of it and 17 % from the nearest natural frequency
    # (1.808 Hz; examples/shear_building6.toml): the plot leaves it unmarked, so the text
    # must not call it a resonance peak either.
    code, out, err = run_cli(["sweep", EXAMPLES / "shear_building6.toml", "--param", "omega",
                              "--from", "0.5", "--to", "25", "--units", "mm,Hz"])
    assert code == 0, err
    resonances, _, rest = out.partition("other local maxima")
    roof = [float(line.split()[1]) for line in resonances.splitlines()
            if line.strip().startswith("roof")]
    assert len(roof) == 5 and all(abs(f - 1.49) > 0.1 for f in roof), roof
    bumps = rest.split("antiresonances:")[0]
    assert "roof" in bumps and "1.492" in bumps


def test_cli_sweep_errors():
    path = EXAMPLES / "tuned_mass_damper.toml"
    code, _, err = run_cli(["sweep", path, "--param", "omgea", "--from", "1", "--to", "2"])
    assert code == 2 and "omgea" in err and "omega" in err
    code, _, err = run_cli(["sweep", path, "--param", "omega", "--from", "1", "--to", "2",
                            "--method", "modal"])
    assert code == 3 and "proportional" in err
    code, _, err = run_cli(["sweep", path, "--param", "omega", "--from", "-1", "--to", "2",
                            "--log"])
    assert code == 3 and "positive" in err
    code, _, err = run_cli(["sweep", path, "--param", "m1", "--from", "0", "--to", "1",
                            "--points", "3"])
    assert code in (2, 3) and "Traceback" not in err


def test_unknown_names_and_bad_method():
    model = sdof()
    with pytest.raises(AnalysisError, match="unknown coordinate"):
        sweep(model, "omega", [1.0], names=["y"])
    with pytest.raises(AnalysisError, match="unknown method"):
        sweep(model, "omega", [1.0], method="fast")
    with pytest.raises(ModelError, match="unknown parameter"):
        sweep(model, "nope", [1.0])


def test_progress_bar_and_only(tmp_path):
    """--progress draws a text bar on stderr; --only limits the reported coordinates."""
    path = write_chain(tmp_path, 50)
    code, out, err = run_cli(["sweep", path, "--param", "omega", "--from", "1", "--to", "100",
                              "--points", "50", "--progress", "--only", "q1,q50", "--json"])
    assert code == 0, err
    assert "sweep [" in err and "100.0%" in err
    data = json.loads(out)
    assert set(data["amplitudes"]) == {"q1", "q50"} and data["method"] == "banded"
