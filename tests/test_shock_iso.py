"""One definition of the primary and residual SRS (ISO 18431-4) in every SRS, and the
largest responses of a model under its ``[shock]`` pulse as JSON (cli/srs.py,
analyses/shock.py: ``excitation_end``, ``pulse_end``; analyses/transient.py:
``ShockPeaks``).

References:

* the undamped half-sine's closed-form primary (0 <= t <= tau) and residual (the free
  vibration after tau) spectra (Harris' Shock and Vibration Handbook, Ch. 8;
  ``test_shock.half_sine_analytic``): ``resonant srs --pulse`` to 2e-8 (the interpolation
  error of 10^4 samples; it was 7e-4 off when primary ended one sample late);
* the largest responses are the transient's own (1e-12, the same histories), and the
  table's acceleration output under a pulse of that acceleration is the pulse: its
  largest value is the amplitude, at tau/2 (exact to the step).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import EXAMPLES, run_cli
from resonant.analyses.shock import ShockSpectrum, pulse, shock_response_spectrum
from resonant.analyses.transient import ShockPeaks, shock_response
from resonant.model import load
from resonant.system import linear_system
from test_shock import TAU, half_sine_analytic

MODEL = EXAMPLES / "shock_half_sine.toml"


def test_pulse_primary_and_residual_are_iso_18431_4s() -> None:
    status, out, err = run_cli(["srs", "--pulse", "half-sine", "--duration", TAU, "--step",
                                TAU / 10_000, "--damping", "0", "--from", "3", "--to",
                                "2000", "--points", "3", "--json"])
    assert status == 0, err
    data = json.loads(out)
    assert data["excitation_end_s"] == pytest.approx(TAU, rel=1e-12)
    for f, primary, residual in zip(data["frequency_hz"], data["primary"], data["residual"]):
        want_primary, want_residual = half_sine_analytic(f)
        assert primary == pytest.approx(want_primary, rel=2e-8)
        assert residual == pytest.approx(want_residual, rel=2e-8)


@pytest.fixture(scope="module")
def largest() -> dict:  # type: ignore[type-arg]
    status, out, err = run_cli(["srs", MODEL, "--largest", "--points", "4", "--json"])
    assert status == 0, err
    return json.loads(out)  # type: ignore[no-any-return]


def test_model_largest_responses_as_json(largest) -> None:  # type: ignore[no-untyped-def]
    model = load(MODEL)
    spec = model.shock_section
    assert spec is not None
    direct = shock_response(linear_system(model), spec)
    response = largest["response"]
    assert response["names"] == list(direct.names)
    for name in direct.names:
        assert response["largest"][name] == pytest.approx(direct.largest[name], rel=1e-12)
        assert response["maximum"][name] == pytest.approx(float(np.max(direct.history[name])),
                                                          rel=1e-12)
    assert response["units"]["a"] == "m/s^2" and response["shock"]["pulse"] == "half-sine"
    # the spectrum of the pulse splits at its duration, whatever the record's length
    assert largest["excitation_end_s"] == pytest.approx(spec.duration, rel=1e-12)
    assert largest["duration_s"] == pytest.approx(spec.total, rel=1e-12)


def test_json_round_trips(largest) -> None:  # type: ignore[no-untyped-def]
    peaks = ShockPeaks.from_dict(json.loads(json.dumps(largest["response"])))
    assert peaks.to_dict() == largest["response"]
    spectrum = ShockSpectrum.from_dict(largest)   # the spectrum's keys, beside "response"
    assert spectrum.to_dict() == {k: v for k, v in largest.items() if k != "response"}
    assert "max |value|" in peaks.table().text()


def test_the_component_is_the_srs_oscillator() -> None:
    """The component (100 Hz, Q = 10 on the table) is the SRS's oscillator: its largest
    absolute acceleration under the pulse is the pulse's SRS at 100 Hz (the sampled peak
    against the refined one: 1000 samples a cycle, within 1e-5)."""
    status, out, err = run_cli(["srs", MODEL, "--only", "a", "--points", "3", "--json"])
    assert status == 0, err
    response = json.loads(out)["response"]
    assert response["names"] == ["a"]
    spec = load(MODEL).shock_section
    assert spec is not None
    _, a = pulse(spec.pulse, spec.amplitude, spec.duration, spec.step, total=spec.total)
    srs = shock_response_spectrum(a, spec.step, [100.0], Q=10.0)
    assert response["largest"]["a"] == pytest.approx(float(srs.maximax[0]), rel=1e-5)


def test_csv_history_split_where_asked(tmp_path) -> None:  # type: ignore[no-untyped-def]
    t, a = pulse("half-sine", 1.0, TAU, TAU / 1000, total=3 * TAU)
    path = tmp_path / "shock.csv"
    path.write_text("t,a\n" + "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in zip(t, a)))
    common = ["--damping", "0", "--points", "4", "--json"]
    _, whole, _ = run_cli(["srs", "--csv", path, *common])
    status, split, err = run_cli(["srs", "--csv", path, "--pulse-end", TAU, *common])
    assert status == 0, err
    _, own, _ = run_cli(["srs", "--pulse", "half-sine", "--duration", TAU, "--step",
                         TAU / 1000, *common])
    assert json.loads(split)["primary"] == pytest.approx(json.loads(own)["primary"],
                                                         rel=1e-9)
    assert json.loads(whole)["maximax"] == pytest.approx(json.loads(split)["maximax"],
                                                         rel=1e-6)


@pytest.mark.parametrize("args, message", [
    (["srs", MODEL, "--output", "z"], "not an acceleration"),
    (["srs", "--pulse", "half-sine", "--duration", "0.01", "--largest"], "needs a model"),
    (["srs", "--pulse", "half-sine", "--duration", "0.01", "--only", "a"], "needs a model"),
    (["srs", "--pulse", "half-sine", "--duration", "0.01", "--pulse-end", "0.01"],
     "--pulse-end is for a --csv"),
    (["srs", MODEL, "--only", "nosuch"], "nosuch"),
])
def test_bad_input_is_exit_2(args: list, message: str) -> None:  # type: ignore[type-arg]
    status, _, err = run_cli(args)
    assert status == 2 and message in err, err


def test_output_of_a_model_without_units_warns(tmp_path) -> None:  # type: ignore
    path = tmp_path / "m.toml"
    path.write_text("[matrices]\nM = [[1.0]]\nK = [[4e4]]\nC = [[4.0]]\n"
                    '[outputs]\nv = "q1"\n'
                    '[shock]\nsignal = "q1"\npulse = "half-sine"\namplitude = 1\n'
                    "duration = 0.01\n")
    status, _, err = run_cli(["srs", path, "--output", "v", "--points", "3"])
    assert status == 0, err
    assert "taken as a base acceleration" in err
