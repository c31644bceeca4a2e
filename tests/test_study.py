"""Parameter studies (docs/studies.md): the request, the batched quantities against the
single-point analyses, reference statistics, Sobol indices, files, resume, failures."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import resonant
from resonant.analyses.modes import modes
from resonant.analyses.stationary import stationary
from resonant.errors import ModelError
from resonant.model.study import study_spec
from resonant.studies import StudyJob, engine_for, read_table, request, run_study
from resonant.studies.designs import chunk_values
from resonant.studies.files import read_description
from resonant.studies.quantities import evaluate_samples, undamped_lambdas

pytest.importorskip("pandas")
pytest.importorskip("pyarrow")
pytest.importorskip("SALib")

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

SDOF = """
title = "SDOF"
[parameters]
m = 1
k = 100
c = 0.5
F0 = 1
omega = 8
[coordinates]
x = ""
[signals]
F = "F0*sin(omega*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
generalized = { x = "F" }
"""


def sdof(tmp_path: Path, extra: str = "") -> resonant.Model:
    path = tmp_path / "sdof.toml"
    path.write_text(SDOF + extra)
    return resonant.load(path)


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "resonant", *args], capture_output=True,
                          text=True, timeout=300)


# -- the request ---------------------------------------------------------------------------

@pytest.mark.parametrize("vary, quantities, options, message", [
    ({"k": "uniform(120, 80)"}, ["stable"], {}, "[study] k: uniform(a, b) needs a < b"),
    ({"k": "normal(100, -1)"}, ["stable"], {}, "standard deviation"),
    ({"k": "lognormal(-1, 1)"}, ["stable"], {}, "mean of lognormal"),
    ({"k": "beta(1, 2)"}, ["stable"], {}, "unknown distribution 'beta'"),
    ({"k": "uniform(1)"}, ["stable"], {}, "takes 2 values"),
    ({"kk": "uniform(1, 2)"}, ["stable"], {}, "'kk' is not a parameter"),
    ({"k": "[]"}, ["stable"], {}, "the list of values is empty"),
    ({"k": {"from": 1, "to": 0, "step": 1}}, ["stable"], {}, "to >= from"),
    ({"k": {"from": 0, "to": 1e9, "step": 1e-9}}, ["stable"], {}, "at most"),
    ({"k": "uniform(1, 2)"}, ["peak:x"], {}, "need a band"),
    ({"k": "uniform(1, 2)"}, ["amplitude:y"], {}, "'y' is not a coordinate"),
    ({"k": "uniform(1, 2)"}, ["natural_frequency:0"], {}, "mode number counted from 1"),
    ({"k": "uniform(1, 2)"}, ["natural_frequency:2"], {}, "the model has 1 modes"),
    ({"k": "uniform(1, 2)"}, ["frequency"], {}, "unknown quantity 'frequency'"),
    ({"k": "uniform(1, 2)"}, ["stable"], {"design": "halton"}, "unknown design"),
    ({"k": "uniform(1, 2)"}, ["stable"], {"samples": 0}, "samples must be"),
    ({"k": "uniform(1, 2)"}, ["stable"], {"seed": -1}, "seed must be"),
    ({"k": "normal(1, 2)"}, ["stable"], {"design": "grid"}, "a grid needs"),
    ({"k": "uniform(1, 1e300*1e300)"}, ["stable"], {}, "not a finite number"),
    ({"k": "uniform(1, 2)"}, ["peak:x"], {"band": {"parameter": "omega", "from": 5, "to": 1}},
     "0 <= from < to"),
    ({"k": "uniform(1, 2)"}, "stable", {}, "quantities is a list"),
])
def test_bad_requests_are_named(tmp_path, vary, quantities, options, message):
    model = sdof(tmp_path)
    with pytest.raises(ModelError) as err:
        request(model, vary, quantities, **options)
    assert message in str(err.value)
    assert "Traceback" not in str(err.value)


def test_study_section_errors_name_file_section_key(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(SDOF + '[study]\nvary = { k = "uniform(1 kg, 2 kg)" }\n'
                    'quantities = ["stable"]\nbogus = 1\n')
    result = run_cli("check", str(path))
    assert result.returncode == 2
    assert "[study] bogus: unknown key 'bogus'" in result.stderr
    path.write_text(SDOF.replace("k = 100", 'k = "100 N/m"').replace("m = 1", 'm = "1 kg"')
                    + '[study]\nvary = { k = "uniform(1 kg, 2 kg)" }\nquantities = ["stable"]\n')
    result = run_cli("check", str(path))
    assert result.returncode == 2, result.stderr
    assert "[study] k: the value is in kg (a mass), but k is in N/m" in result.stderr


def test_cli_bad_values_exit_2(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(SDOF)
    out = str(tmp_path / "r.parquet")
    for args, text in ((["--vary", "k"], "--vary expects NAME=SPEC"),
                       (["--vary", "k=uniform(1,2)", "--quantity", "stable", "--band", "omega"],
                        "--band expects"),
                       (["--vary", "k=uniform(1,2)", "--quantity", "stable", "--samples", "x"],
                        "--samples"),
                       (["--vary", "k=uniform(1,2)", "--quantity", "stable",
                         "--scheduler", "localhost:1"], "tcp://HOST:PORT")):
        result = run_cli("study", str(path), "-o", out, *args)
        assert result.returncode == 2, (args, result.stderr)
        assert text in result.stderr and "Traceback" not in result.stderr
    result = run_cli("study", str(path), "-o", str(tmp_path / "r.txt"), "--vary",
                     "k=uniform(1,2)", "--quantity", "stable")
    assert result.returncode == 2 and ".parquet or .csv" in result.stderr


def test_spec_with_units_and_lists(tmp_path):
    spec = study_spec({"k": "uniform(80 N/mm, 120 N/mm)", "m": "[1, 2 kg, 3]",
                       "c": {"from": 1, "to": 2, "step": 0.25}}, ["stable"],
                      parameters=["k", "m", "c"], coordinates=["x"], outputs=[])
    assert spec.vary["k"].arguments == (80000.0, 120000.0)
    assert spec.vary["m"].arguments == (1.0, 2.0, 3.0)
    assert spec.vary["c"].arguments == (1.0, 1.25, 1.5, 1.75, 2.0)


# -- two routes: the batched quantities against the single-point analyses -----------------

@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(k=st.floats(20, 4000), m2=st.floats(0.2, 5.0), omega=st.floats(1.0, 40.0))
def test_batched_quantities_equal_single_point_analyses(k, m2, omega):
    """The cart-pendulum at random parameters: natural frequencies, damping, stability,
    amplitudes and phases of the batched study equal `modes` and `stationary` at the
    same point (1e-9 relative)."""
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    system = model.linearize()
    spec = study_spec({"k": [k], "m2": [m2], "omega": [omega]},
                      ["natural_frequency:1", "natural_frequency:2", "amplitude:x1",
                       "amplitude:x2", "phase:x2", "stable"],
                      parameters=model.parameters, coordinates=model.coordinates,
                      outputs=model.outputs)
    values = {"k": np.array([k, k]), "m2": np.array([m2, m2]), "omega": np.array([omega, omega])}
    rows = evaluate_samples(system, spec, values)
    point = system.numeric(k=k, m2=m2, omega=omega)
    single = stationary(point)
    analysis = modes(point)
    assert rows["natural_frequency:1"][0] == pytest.approx(analysis.natural_frequencies[0],
                                                           rel=1e-9)
    assert rows["natural_frequency:2"][1] == pytest.approx(analysis.natural_frequencies[1],
                                                           rel=1e-9)
    assert bool(rows["stable"][0]) == (analysis.stability != "unstable")
    if rows["status"][0] == "ok":
        for name in ("x1", "x2"):
            assert rows[f"amplitude:{name}"][0] == pytest.approx(single.amplitudes[name],
                                                                 rel=1e-9, abs=1e-300)
        assert math.cos(rows["phase:x2"][0] - single.phases["x2"]) == pytest.approx(1, abs=1e-9)


def test_damping_ratios_equal_modes():
    model = resonant.load(EXAMPLES / "chain3_damped.toml")
    system = model.linearize()
    name = next(iter(model.parameters))
    value = model.parameter_values[name]
    spec = study_spec({name: [value]}, ["damping_ratio:1", "damping_ratio:2", "damping_ratio:3"],
                      parameters=model.parameters, coordinates=model.coordinates,
                      outputs=model.outputs)
    rows = evaluate_samples(system, spec, {name: np.array([value])})
    expected = modes(system).damping_ratios
    for i in range(3):
        assert rows[f"damping_ratio:{i + 1}"][0] == pytest.approx(expected[i], rel=1e-8)


def test_peak_equals_closed_form(tmp_path):
    """SDOF: the largest amplitude F0/(k 2 zeta sqrt(1 - zeta^2)) at
    omega_n sqrt(1 - 2 zeta^2) (e.g. Rao, Mechanical Vibrations, Sect. 3.4); 1e-9 relative
    for the peak, 1e-7 for its frequency (the amplitude is flat there)."""
    model = sdof(tmp_path)
    k = np.array([50.0, 100.0, 400.0])
    c = np.array([0.5, 2.0, 8.0])
    spec = request(model, {"k": "uniform(1, 2)", "c": "uniform(1, 2)"}, ["peak:x"],
                   band={"parameter": "omega", "from": 0.5, "to": 40, "points": 100})
    rows = evaluate_samples(model.linearize(), spec, {"k": k, "c": c})
    zeta = c / (2 * np.sqrt(k))
    np.testing.assert_allclose(rows["peak:x"], 1 / (k * 2 * zeta * np.sqrt(1 - zeta**2)),
                               rtol=1e-9)
    np.testing.assert_allclose(rows["peak_frequency:x"], np.sqrt(k) * np.sqrt(1 - 2 * zeta**2),
                               rtol=1e-7)


def test_grid_rows_do_not_depend_on_the_chunking(tmp_path):
    """A sample's quantities are the same whatever else is in its batch (bitwise)."""
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    spec = request(model, {"k": {"from": 50, "to": 150, "step": 10}, "omega": [5, 10, 20]},
                   ["amplitude:x2", "natural_frequency:2", "stable"], design="grid")
    system = model.linearize()
    whole = evaluate_samples(system, spec, chunk_values(spec, 0, spec.size))
    for size in (1, 4, 7):
        parts = [evaluate_samples(system, spec, chunk_values(spec, k, size))
                 for k in range(-(-spec.size // size))]
        for column in whole:
            joined = np.concatenate([p[column] for p in parts])
            nan_ok = joined.dtype.kind == "f"
            assert np.array_equal(joined, whole[column], equal_nan=nan_ok), column


# -- references ----------------------------------------------------------------------------

def test_monte_carlo_natural_frequency_against_closed_form(tmp_path):
    """m = 1, k uniform on [a, b]: omega_n = sqrt(k) has mean (2/3)(b^1.5 - a^1.5)/(b - a)
    and q-quantile sqrt(a + q (b - a)).  Tolerance: 4 standard errors of the estimate
    (mean: sd/sqrt(N); quantile: sqrt(q (1 - q)/N) / f(x_q), f(x) = 2x/(b - a))."""
    a, b, n = 80.0, 120.0, 20_000
    model = sdof(tmp_path)
    result = model.study({"k": f"uniform({a}, {b})"}, ["natural_frequency:1"], samples=n,
                         seed=11, workers=0)
    values = result.table["natural_frequency:1"].to_numpy()
    mean = 2 / 3 * (b**1.5 - a**1.5) / (b - a)
    sd = math.sqrt((a + b) / 2 - mean**2)
    assert abs(values.mean() - mean) < 4 * sd / math.sqrt(n)
    assert values.std(ddof=1) == pytest.approx(sd, rel=0.05)
    for q in (0.05, 0.5, 0.95):
        x = math.sqrt(a + q * (b - a))
        error = math.sqrt(q * (1 - q) / n) / (2 * x / (b - a))
        assert abs(np.quantile(values, q) - x) < 4 * error
    summary = result.summary()
    assert summary.loc["natural_frequency:1", "count"] == n


def test_sobol_of_a_quantity_of_one_parameter(tmp_path):
    """The undamped natural frequency depends on k only: S1(k) = ST(k) = 1 within the
    confidence interval SALib gives, and exactly 0 for c."""
    model = sdof(tmp_path)
    result = model.study({"k": "uniform(80, 120)", "c": "uniform(0.1, 1)"},
                         ["natural_frequency:1"], design="sobol", samples=1024, seed=3,
                         workers=0)
    s = result.sensitivity["natural_frequency:1"]
    assert s["parameters"] == ["k", "c"]
    assert abs(s["S1"][0] - 1) <= s["S1_conf"][0]
    assert abs(s["ST"][0] - 1) <= s["ST_conf"][0]
    assert s["S1"][1] == pytest.approx(0, abs=1e-12) and s["ST"][1] == pytest.approx(0,
                                                                                      abs=1e-12)
    assert len(result.table) == 1024 * 4


# -- failures, files, resume ----------------------------------------------------------------

def test_impossible_samples_get_a_status_and_the_study_goes_on(tmp_path):
    model = sdof(tmp_path)
    spec = request(model, {"m": [1.0, 0.0, 1.0, 1.0], "k": [100.0, 100.0, -50.0, 64.0],
                           "c": [0.5, 0.5, 0.5, 0.0]},
                   ["amplitude:x", "natural_frequency:1", "stable"], design="random",
                   samples=4)
    values = {"m": np.array([1.0, 0.0, 1.0, 1.0]), "k": np.array([100.0, 100.0, -50.0, 64.0]),
              "c": np.array([0.5, 0.5, 0.5, 0.0])}
    rows = evaluate_samples(model.linearize(), spec, values)
    assert list(rows["status"]) == ["ok", "singular mass", "unstable", "resonance"]
    assert "mass matrix M is singular" in rows["reason"][1]
    assert "unstable" in rows["reason"][2]
    assert "unbounded" in rows["reason"][3]
    assert np.isfinite(rows["amplitude:x"][0]) and np.isnan(rows["amplitude:x"][1:]).all()
    assert rows["natural_frequency:1"][3] == pytest.approx(8.0)


def test_a_dependent_parameter_that_fails_marks_its_sample(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(SDOF.replace("c = 0.5", 'z = 0.01\nc = "2*z*sqrt(k*m)/log(k - 98)"'))
    model = resonant.load(path)
    spec = request(model, {"k": [100.0, 99.0]}, ["amplitude:x"])
    rows = evaluate_samples(model.linearize(), spec, {"k": np.array([101.0, 99.0])})
    assert list(rows["status"]) == ["ok", "failed"]
    assert "c = " in rows["reason"][1]


@pytest.mark.parametrize("suffix", [".parquet", ".csv"])
def test_interrupted_study_leaves_a_valid_file_and_resume_completes_it(tmp_path, suffix):
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    spec = request(model, {"k": "uniform(80, 120)"}, ["amplitude:x2", "stable"],
                   samples=600, seed=5)
    job = StudyJob.of(model, spec)
    full = tmp_path / f"full{suffix}"
    run_study(job, full, engine_for(0))
    calls = []

    def stop_after_two(rows):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt

    part = tmp_path / f"part{suffix}"
    spec_small_chunks = job
    import resonant.studies.run as run_module

    original = run_module.chunk_size
    run_module.chunk_size = lambda spec, n: 100
    try:
        run_study(spec_small_chunks, full, engine_for(0))
        with pytest.raises(KeyboardInterrupt):
            run_study(job, part, engine_for(0), on_chunk=stop_after_two)
        assert len(read_table(part)) == 200
        assert read_description(part)["rows"] == 600
        summary = run_study(job, part, engine_for(0), resume=True)
    finally:
        run_module.chunk_size = original
    assert summary.resumed_rows == 200 and summary.rows == 600
    assert part.read_bytes() == full.read_bytes()


def test_resume_refuses_another_study(tmp_path):
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    out = tmp_path / "r.parquet"
    run_study(StudyJob.of(model, request(model, {"k": "uniform(80, 120)"}, ["stable"],
                                         samples=10, seed=1)), out, engine_for(0))
    other = StudyJob.of(model, request(model, {"k": "uniform(80, 120)"}, ["stable"],
                                       samples=10, seed=2))
    with pytest.raises(ModelError, match="holds a different study"):
        run_study(other, out, engine_for(0), resume=True)


def test_cli_study_writes_rows_plots_and_json(tmp_path):
    out = tmp_path / "r.csv"
    plots = tmp_path / "plots"
    result = run_cli("study", str(EXAMPLES / "absorber_tolerances.toml"), "-o", str(out),
                     "--samples", "64", "--design", "sobol", "--quantity", "peak:x1",
                     "--band", "omega=10:30:100", "--plot", str(plots), "--json",
                     "--workers", "0")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["rows"] == 64 * 4 and data["status"] == {"ok": 256}
    assert set(data["sensitivity"]) == {"peak:x1", "peak_frequency:x1"}
    table = read_table(out)
    assert list(table.columns) == ["sample", "k2", "c2", "peak:x1", "peak_frequency:x1",
                                   "status", "reason"]
    names = sorted(p.name for p in plots.iterdir())
    assert "sobol-peak_x1.png" in names and "histogram-peak_x1.png" in names
    assert "scatter-peak_frequency_x1.png" in names


def test_grid_study_draws_a_contour(tmp_path):
    model = resonant.load(EXAMPLES / "absorber_tolerances.toml")
    result = model.study(quantities=["amplitude:x1"], design="grid", samples=6, workers=0)
    assert len(result.table) == 36
    files = result.plot(tmp_path)
    assert (tmp_path / "contour-amplitude_x1.png") in files


def test_same_seed_same_bytes_in_process_and_on_two_local_workers(tmp_path):
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    spec = request(model, {"k": "normal(100, 5)", "m2": "lognormal(1, 0.1)"},
                   ["amplitude:x2", "natural_frequency:1"], samples=300_000, seed=9)
    job = StudyJob.of(model, spec)
    here, there = tmp_path / "here.parquet", tmp_path / "there.parquet"
    run_study(job, here, engine_for(0))
    summary = run_study(job, there, engine_for(2))
    assert summary.where == "2 local workers"
    assert here.read_bytes() == there.read_bytes()


def test_exercise_variants_on_two_workers_equal_those_of_one_process(tmp_path):
    model = str(EXAMPLES / "teaching" / "cart_pendulum.toml")
    here, there = tmp_path / "here", tmp_path / "there"
    for folder, extra in ((here, []), (there, ["--workers", "2"])):
        result = run_cli("exercise", model, "--variants", "6", "--seed", "3", "-o", str(folder),
                         "--format", "html,json,moodle", "--no-plots", *extra)
        assert result.returncode == 0, result.stderr
        assert "warning" not in result.stderr
    files = sorted(p.relative_to(here) for p in here.rglob("*") if p.is_file())
    assert len(files) == 6 * 3 + 2
    for name in files:
        assert (here / name).read_bytes() == (there / name).read_bytes(), name


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-3, 3), min_size=7, max_size=7),
       st.floats(-6, 6), st.floats(1e-2, 1.0))
def test_two_by_two_pencil_in_closed_form_equals_the_cholesky_route(entries, exponent, tilt):
    """The closed-form omega^2 of a 2 x 2 symmetric pencil (used for 2-DOF studies) equals
    the batched Cholesky + eigvalsh route of larger models: same order, agreement to
    1e-10 of the largest |omega^2| times cond(M) (both are backward stable in that sense),
    over stiffness scales 1e-6 ... 1e6 and indefinite K."""
    a, b, c, k11, k12, k22, shift = entries
    L = np.array([[1.0 + abs(a), 0.0], [b, tilt + abs(c)]])
    M = (L @ L.T)[None]
    K = (10.0 ** exponent * np.array([[k11, k12], [k12, k22 + shift]]))[None]
    closed = undamped_lambdas(M, K)
    Linv = np.linalg.inv(np.linalg.cholesky(M[0]))
    reference = np.linalg.eigvalsh(Linv @ K[0] @ Linv.T)
    scale = max(np.abs(reference).max(), 1e-300) * np.linalg.cond(M[0])
    assert np.all(np.abs(closed[0] - reference) <= 1e-10 * scale + 1e-300)
