"""The ``[shock]`` and ``[fatigue]`` sections and the study quantities ``srs:NAME@f`` and
``damage:NAME`` (docs/studies.md, docs/random.md, docs/model-format.md)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import resonant
from resonant.analyses.fatigue import SNCurve, spectral_fatigue
from resonant.analyses.shock import pulse, shock_response_spectrum
from resonant.analyses.transient import transient_response
from resonant.errors import ModelError

GEVS = (Path(__file__).parents[1] / "examples" / "shaker_gevs.toml").read_text()
#: the bracket's stress: its force over a 1 cm^2 section (Pa)
STRESS = 'table = "y\'\'"'
SHOCK = """
[shock]
signal = "y"
derivative = 2
pulse = "half-sine"
amplitude = 50
unit = "g"
duration = 0.011
step = 1e-5
total = 0.04
Q = 10
"""
FATIGUE = """
[fatigue]
k = 4
amplitude = 1e8        # 100 MPa
cycles = 1e6
method = "{method}"
duration = 3600
"""


def _model(tmp_path: Path, method: str = "dirlik", extra: str = "") -> Path:
    text = GEVS.replace(STRESS, STRESS + '\nsigma = "k*(x - y)/1e-4"') + SHOCK \
        + FATIGUE.format(method=method) + extra
    path = tmp_path / "shaker.toml"
    path.write_text(text)
    return path


def _study(path: Path, quantities: list[str], ks: tuple[float, ...] = (1.0e6, 2.0e6)):
    from resonant.studies import StudyJob, collect, engine_for, request
    model = resonant.load(path)
    spec = request(model, {"k": list(ks)}, quantities, design="grid")
    return collect(StudyJob.of(model, spec), engine_for(0)).table


def test_srs_of_the_input_itself_is_the_pulses_srs(tmp_path: Path) -> None:
    """``srs:table@f``: the output ``table`` is y'', the half-sine itself, so the study's
    value is the SRS of the pulse (Q = 10) at f, as resonant.analyses.shock computes it
    (validated there against the analytic maximax spectrum); rel 1e-9 (same samples)."""
    table = _study(_model(tmp_path), ["srs:table@100", "srs:table@1000"])
    _, a = pulse("half-sine", 50 * 9.80665, 0.011, 1e-5, total=0.04)
    direct = shock_response_spectrum(a, 1e-5, [100.0, 1000.0], Q=10).maximax
    assert list(table["status"]) == ["ok", "ok"]
    for i in range(2):
        assert table["srs:table@100"][i] == pytest.approx(direct[0], rel=1e-9)
        assert table["srs:table@1000"][i] == pytest.approx(direct[1], rel=1e-9)
    # a 1000 Hz oscillator under an 11 ms half-sine sees about the pulse's peak
    assert direct[1] == pytest.approx(50 * 9.80665, rel=0.1)


def test_srs_of_an_output_equals_the_transient_then_the_srs(tmp_path: Path) -> None:
    """``srs:a@f`` at each sample: the SRS of the component's acceleration history, the
    exact transient response of the model with that sample's k (rel 1e-9)."""
    path = _model(tmp_path)
    table = _study(path, ["srs:a@300"])
    _, u = pulse("half-sine", 50 * 9.80665, 0.011, 1e-5, total=0.04)
    for i, k in enumerate((1.0e6, 2.0e6)):
        system = resonant.load(path, {"k": k}).linearize()
        history = transient_response(system, "y", u, 1e-5, derivative=2, names=["a"])
        direct = shock_response_spectrum(history.history["a"], 1e-5, [300.0], Q=10)
        assert table["srs:a@300"][i] == pytest.approx(direct.maximax[0], rel=1e-9)
    assert table["srs:a@300"][0] != pytest.approx(table["srs:a@300"][1], rel=1e-3)


@pytest.mark.parametrize("method", ["narrowband", "dirlik"])
def test_damage_equals_the_spectral_fatigue_of_the_stress_response(tmp_path: Path,
                                                                    method: str) -> None:
    """``damage:sigma``: Miner's damage over the [fatigue] duration of the stress density of
    random_response, by FLife through resonant.analyses.fatigue (rel 1e-12, the same
    computation); the narrow-band value also against its closed form (Bendat 1964,
    D = nu0 T (sqrt(2) sigma)^k Gamma(1 + k/2) / C) from the RMS and Rice's rate (1e-3:
    the moments of the same density)."""
    path = _model(tmp_path, method)
    table = _study(path, ["damage:sigma", "rms:sigma"])
    assert list(table["status"]) == ["ok", "ok"]
    sn = SNCurve.from_point(1e8, 1e6, 4)
    for i, k in enumerate((1.0e6, 2.0e6)):
        result = resonant.load(path, {"k": k}).random_response(names=["sigma"])
        direct = spectral_fatigue(result.frequency, result.psd["sigma"], sn, 3600.0,
                                  methods=[method]).damage[method]
        assert table["damage:sigma"][i] == pytest.approx(direct, rel=1e-12)
        if method == "narrowband":
            s = result.rms["sigma"]
            closed = result.zero_crossing_rate["sigma"] * 3600 * (math.sqrt(2) * s) ** 4 \
                * math.gamma(3.0) / sn.C
            assert table["damage:sigma"][i] == pytest.approx(closed, rel=1e-3)
    assert np.all(table["damage:sigma"] > 0)


def test_units_of_the_new_columns(tmp_path: Path) -> None:
    from resonant.studies import request
    from resonant.studies.study_charts import study_units
    model = resonant.load(_model(tmp_path))
    spec = request(model, {"k": [1e6]}, ["srs:a@100", "damage:sigma"], design="grid")
    units = study_units(model, spec)
    assert units["srs:a@100"] == "m/s^2" and units["damage:sigma"] == ""


def test_quantity_text_is_checked() -> None:
    from resonant.studies import request
    model = resonant.load("examples/shaker_gevs.toml")
    for bad, said in (("srs:a", "natural frequency in Hz after '@'"),
                      ("srs:a@-3", "natural frequency in Hz after '@'"),
                      ("srs:nope@100", "'nope' is not a coordinate or output"),
                      ("damage:nope", "'nope' is not a coordinate or output")):
        with pytest.raises(ModelError, match=said):
            request(model, {"k": [1e6]}, [bad], design="grid")


def test_a_sample_without_the_sections_fails_with_the_reason(tmp_path: Path) -> None:
    path = tmp_path / "plain.toml"
    path.write_text(GEVS)
    table = _study(path, ["srs:a@100", "damage:a"], ks=(1e6,))
    assert list(table["status"]) == ["failed"]
    assert "[shock]" in table["reason"][0] or "[fatigue]" in table["reason"][0]
    assert math.isnan(table["srs:a@100"][0]) and math.isnan(table["damage:a"][0])


@pytest.mark.parametrize(("section", "key", "said"), [
    ('[shock]\nsignal = "w"\npulse = "half-sine"\namplitude = 1\nduration = 0.01', "signal",
     "neither a signal nor a coordinate"),
    ('[shock]\nsignal = "y"\npulse = "square"\namplitude = 1\nduration = 0.01', "pulse",
     "must be one of half-sine"),
    ('[shock]\nsignal = "y"\npulse = "half-sine"\namplitude = 1\nduration = -1', "duration",
     "positive finite number"),
    ('[shock]\nsignal = "y"\npulse = "half-sine"\namplitude = 1\nduration = 0.01\n'
     'step = 1e-9\ntotal = 100', "step", "at most"),
    ('[shock]\nsignal = "y"\npulse = "half-sine"\namplitude = 1\nduration = 0.01\nQ = 0.2',
     "Q", "above 0.5"),
    ('[shock]\nsignal = "y"\npulse = "half-sine"\namplitude = 1\nduration = 0.01\n'
     'unit = "zorg"', "unit", "zorg"),
    ('[shock]\nsignal = "y"\npulse = "half-sine"\namplitude = 1\nduration = 0.01\nfoo = 1',
     "foo", "unknown key"),
    ('[fatigue]\nk = 4\nduration = 10', "C", "one of: C, C_range"),
    ('[fatigue]\nk = 4\nC = 1e40\nC_range = 1e41\nduration = 10', "C_range", "one of"),
    ('[fatigue]\nk = 4\nC = 1e40\nduration = 10\nmethod = "rainflow"', "method",
     "narrowband, dirlik"),
    ('[fatigue]\nk = "four"\nC = 1e40\nduration = 10', "k", "'four' is not a number"),
])
def test_bad_sections_name_file_section_and_key(tmp_path: Path, section: str, key: str,
                                                said: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(GEVS + "\n" + section + "\n")
    with pytest.raises(ModelError) as info:
        resonant.load(path)
    text = str(info.value)
    name = section.split("]")[0][1:]
    assert f"bad.toml: [{name}] {key}:" in text and said in text


def test_srs_command_on_a_model(tmp_path: Path) -> None:
    """``resonant srs MODEL [--output NAME] --json``: the model's pulse, or an output's
    history under it, with the section's Q; the same numbers as the study (rel 1e-9)."""
    import json

    from conftest import run_cli
    path = _model(tmp_path)
    code, out, err = run_cli(["srs", str(path), "--output", "a", "--from", "300", "--to",
                              "301", "--points", "2", "--json"])
    assert code == 0, err
    maximax = json.loads(out)["maximax"][0]
    assert maximax == pytest.approx(_study(path, ["srs:a@300"], ks=(1579136.704,))
                                    ["srs:a@300"][0], rel=1e-9)
    code, out, err = run_cli(["srs", str(path), "--from", "1000", "--to", "1001", "--json"])
    assert code == 0, err
    _, a = pulse("half-sine", 50 * 9.80665, 0.011, 1e-5, total=0.04)
    assert json.loads(out)["maximax"][0] == pytest.approx(
        shock_response_spectrum(a, 1e-5, [1000.0], Q=10).maximax[0], rel=1e-9)


@pytest.mark.parametrize("args, said", [
    (["--output", "nope"], "'nope' is not a coordinate or output"),
    (["--pulse", "half-sine"], "give one of --pulse"),
])
def test_srs_command_errors(tmp_path: Path, args: list[str], said: str) -> None:
    from conftest import run_cli
    code, out, err = run_cli(["srs", str(_model(tmp_path)), *args])
    assert code == 2 and said in err and "Traceback" not in err


def test_srs_command_without_a_shock_section(tmp_path: Path) -> None:
    from conftest import run_cli
    path = tmp_path / "plain.toml"
    path.write_text(GEVS)
    code, out, err = run_cli(["srs", str(path)])
    assert code == 2 and "[shock]" in err and "plain.toml" in err


def test_solve_rejects_a_bad_section_with_exit_2(tmp_path: Path) -> None:
    from conftest import run_cli
    path = tmp_path / "bad.toml"
    path.write_text(GEVS + '\n[fatigue]\nk = 4\nC = -1\nduration = 10\n')
    code, out, err = run_cli(["solve", str(path)])
    assert code == 2 and "[fatigue] C:" in err and "Traceback" not in err


PERIODIC = """
[periodic]
signal = "y"
{body}
period = 0.004          # 250 Hz, above the 200 Hz natural frequency
tolerance = 1e-2
"""


def test_periodic_section_equals_the_series_route(tmp_path: Path) -> None:
    """``[periodic]`` with a shape: periodic_load_response is fourier_series then
    periodic_response (rel 1e-12); the same sawtooth given as an expression of t (sampled,
    FFT) gives the same largest excursion of the deflection: 1e-4 (measured 1e-5; each series
    keeps a remainder of 1e-2 relative RMS, but in the harmonics above 5 kHz, which the
    200 Hz oscillator's deflection attenuates by their frequency squared)."""
    from resonant.analyses.periodic_load import (
        fourier_series,
        periodic_load_response,
        periodic_response,
    )
    shaped = tmp_path / "shape.toml"
    shaped.write_text(GEVS + PERIODIC.format(body='shape = "sawtooth"\namplitude = 1\n'
                                             'unit = "mm"'))
    model = resonant.load(shaped)
    spec = model.periodic_section
    assert spec is not None and spec.amplitude == pytest.approx(1e-3)
    system = model.linearize()
    result = periodic_load_response(system, names=["z", "a"])
    direct = periodic_response(system, "y", fourier_series("sawtooth", 1e-3, 0.004,
                                                           tolerance=1e-2), names=["z", "a"])
    assert result.largest["z"] == pytest.approx(direct.largest["z"], rel=1e-12)
    written = tmp_path / "expression.toml"
    written.write_text(GEVS + PERIODIC.format(body='expression = "1e-3*(2*t/0.004 - 1)"'))
    other = periodic_load_response(resonant.load(written).linearize(), names=["z"])
    assert other.largest["z"] == pytest.approx(result.largest["z"], rel=1e-4)


@pytest.mark.parametrize(("body", "key", "said"), [
    ('shape = "wave"\namplitude = 1', "shape", "must be one of square"),
    ('shape = "square"\namplitude = 0', "amplitude", "non-zero"),
    ('expression = "sin(w*t)"', "expression", "w"),
    ('shape = "square"\namplitude = 1\nexpression = "t"', "expression", "not both"),
])
def test_bad_periodic_section(tmp_path: Path, body: str, key: str, said: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(GEVS + PERIODIC.format(body=body))
    with pytest.raises(ModelError) as info:
        resonant.load(path)
    assert "bad.toml: [periodic] " + key in str(info.value) and said in str(info.value)


def test_report_shows_the_periodic_and_random_responses(tmp_path: Path) -> None:
    """The worked solution of a model with [periodic] and [random]: the series, the
    harmonics' table, the summed largest excursion (the numbers of periodic_load_response)
    and the RMS table with Miles beside the exact value (those of random_response)."""
    from resonant.analyses.periodic_load import periodic_load_response
    from resonant.report import build_report, render
    from resonant.report.blocks import Table

    path = tmp_path / "loads.toml"
    path.write_text(GEVS + PERIODIC.format(body='shape = "triangle"\namplitude = 0.5\n'
                                           'unit = "mm"'))
    model = resonant.load(path)
    report = build_report(model, plots=False)
    headings = report.headings()
    assert "Periodic load: Fourier series and superposition" in headings
    assert "Random load: spectral densities and RMS values" in headings
    text = render(report, "md")
    periodic = periodic_load_response(model.linearize())
    random = model.random_response()
    tables = [b for b in report.blocks if isinstance(b, Table)]
    # the number as text, its unit typeset (m/s², not m/s^2)
    cells = [" ".join(p if isinstance(p, str) else p.latex for p in c) for t in tables
             for r in t.rows for c in r]
    # the spectrum is given in g^2/Hz: accelerations in g (1 g = 9.80665 m/s^2, exact)
    metre, g = r" \ \mathrm{m}", r" \ \mathrm{g}"
    assert f"{periodic.largest['z']:.4g}{metre}" in cells
    assert f"{random.rms['a'] / 9.80665:.4g}{g}" in cells
    assert random.miles is not None and f"{random.miles['a'] / 9.80665:.4g}{g}" in cells
    assert "Miles" in text and "Parseval" in text


def test_solve_shows_the_periodic_response(tmp_path: Path) -> None:
    """``resonant solve`` on a model with [periodic]: the text and the JSON carry the
    periodic response, the same numbers as periodic_load_response (rel 1e-12)."""
    import json

    from conftest import run_cli
    from resonant.analyses.periodic_load import periodic_load_response
    path = Path(__file__).parents[1] / "examples" / "teaching" / "fourier_square.toml"
    code, out, err = run_cli(["solve", str(path), "--json"])
    assert code == 0, err
    data = json.loads(out)["periodic"]
    direct = periodic_load_response(resonant.load(path).linearize())
    assert data["responses"]["x"]["largest"] == pytest.approx(direct.largest["x"], rel=1e-12)
    assert data["harmonics"] == direct.series.harmonics
    code, out, err = run_cli(["solve", str(path)])
    assert code == 0 and "Periodic load: square, period 0.5 s" in out
