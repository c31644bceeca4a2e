"""``resonant fatigue``: the damage of the nominal model and rainflow damage of a CSV
history from the command line (cli/fatigue.py, analyses/fatigue.py: ResponseFatigue).

References:

* the narrow-band damage (Bendat 1964) D = nu0 T (sqrt(2) sigma)^k Gamma(1 + k/2) / C from
  the RMS sigma and Rice's rate nu0 of the same density (1e-9: the same moments);
* the command's damage equals ``spectral_fatigue`` of the random response's density
  (1e-12: the same computation, so that the command adds nothing of its own);
* a sine of amplitude S for n cycles: Miner's sum n S^k / C exactly (1e-12), the life
  T C / (n S^k);
* units in ``[fatigue]``: ``amplitude = "100 MPa"``, ``duration = "1 h"`` are 1e8 Pa and
  3600 s (exact); ``--units MPa`` shows a history's ranges in MPa and C in MPa^k.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from conftest import EXAMPLES, run_cli
from resonant.analyses.fatigue import (
    ResponseFatigue,
    SNCurve,
    response_fatigue,
    spectral_fatigue,
)
from resonant.analyses.random_response import random_response
from resonant.model import load, loads
from resonant.system import linear_system

pytest.importorskip("FLife")
pytest.importorskip("rainflow")

BRACKET = EXAMPLES / "bracket_fatigue.toml"


@pytest.fixture(scope="module")
def bracket() -> tuple[int, dict, str]:  # type: ignore[type-arg]
    status, out, err = run_cli(["fatigue", BRACKET, "--json", "--tol", "1e-4"])
    return status, json.loads(out) if status == 0 else {}, err


def test_nominal_damage_equals_the_spectral_methods(bracket) -> None:  # type: ignore
    status, data, err = bracket
    assert status == 0, err
    assert data["names"] == ["stress"] and data["method"] == "dirlik"   # the stresses only
    model = load(BRACKET)
    response = random_response(linear_system(model), names=["stress"], tolerance=1e-4)
    spec = model.fatigue_section
    assert spec is not None
    direct = spectral_fatigue(response.frequency, response.psd["stress"],
                              SNCurve(spec.C, spec.k), spec.duration)
    got = data["results"]["stress"]
    for method, damage in direct.damage.items():   # type: ignore[union-attr]
        assert got["damage"][method] == pytest.approx(damage, rel=1e-12)
    sigma, nu0, k = got["rms"], got["zero_crossing_rate_hz"], spec.k
    bendat = nu0 * spec.duration * (math.sqrt(2) * sigma) ** k * math.gamma(1 + k / 2) / spec.C
    assert got["damage"]["narrowband"] == pytest.approx(bendat, rel=1e-9)


def test_json_round_trip(bracket) -> None:  # type: ignore[no-untyped-def]
    _, data, _ = bracket
    back = ResponseFatigue.from_dict(json.loads(json.dumps(data)))
    assert back.to_dict() == data
    assert "life" in back.summary() and back.chart().panels[0].bars


def test_text_plot_and_methods(tmp_path) -> None:  # type: ignore[no-untyped-def]
    status, out, err = run_cli(["fatigue", BRACKET, "--tol", "1e-3", "--method",
                                "narrowband,dirlik",
                                "--duration", "7200", "--plot", tmp_path / "d.svg"])
    assert status == 0, err
    assert "dirlik *" in out and "tovo" not in out and "exposure 7200 s" in out
    assert (tmp_path / "d.svg").stat().st_size > 1000


def sine_history(tmp_path, amplitude: float = 1e8, cycles: int = 10):  # type: ignore
    t = np.linspace(0.0, cycles, 100 * cycles + 1)
    path = tmp_path / "stress.csv"
    path.write_text("time,stress\n" + "".join(
        f"{float(a)!r},{float(b)!r}\n" for a, b in zip(t, amplitude * np.cos(2 * np.pi * t))))
    return path


def test_rainflow_of_a_csv_history(tmp_path) -> None:  # type: ignore[no-untyped-def]
    path = sine_history(tmp_path)
    status, out, err = run_cli(["fatigue", "--csv", path, "--k", "3", "--C", "1e30",
                                "--json"])
    assert status == 0, err
    data = json.loads(out)
    assert data["damage"] == pytest.approx(10 * 1e8**3 / 1e30, rel=1e-12)
    assert data["life_s"] == pytest.approx(10.0 / data["damage"], rel=1e-12)
    # the model's [fatigue] curve, with its exposure (the history repeated)
    status, out, err = run_cli(["fatigue", BRACKET, "--csv", path])
    assert status == 0, err
    assert "the history repeated 360 times" in out and "Miner's damage 1e-05" in out


def test_rainflow_text_and_plot_honour_units(tmp_path) -> None:  # type: ignore
    """``--units MPa`` shows the history's ranges and the curve's C in MPa (C / 1e6^k),
    as the spectral route does; the damage is the same number; --json stays SI."""
    path = sine_history(tmp_path)
    for model in ([], [BRACKET]):
        status, out, err = run_cli(["fatigue", *model, "--csv", path, "--k", "3", "--C",
                                    "1e30", "--units", "MPa", "--plot", tmp_path / "r.svg"])
        assert status == 0, err
        assert "N S^3 = 1e+12 (S the amplitude in MPa)" in out, out
        assert "range [MPa]" in out and "183.3-200" in out and "Miner's damage 1e-05" in out
        assert "range [MPa]" in (tmp_path / "r.svg").read_text()
    status, out, err = run_cli(["fatigue", "--csv", path, "--k", "3", "--C", "1e30",
                                "--units", "MPa", "--json"])
    assert status == 0, err
    assert max(json.loads(out)["ranges"]) == pytest.approx(2e8, rel=1e-12)


def test_units_in_the_fatigue_section() -> None:
    text = BRACKET.read_text().replace("amplitude = 1e8", 'amplitude = "100 MPa"') \
        .replace("duration = 3600 ", 'duration = "1 h" ')
    spec = loads(text).fatigue_section
    assert spec is not None and spec.duration == 3600.0 and spec.C == 1e6 * 1e8**4


@pytest.mark.parametrize("args, message", [
    (["fatigue"], "give a model file"),
    (["fatigue", "--csv", "{csv}", "--k", "3"], "--k and one of --C"),
    (["fatigue", "--csv", "{csv}"], "no S-N curve"),
    (["fatigue", "--csv", "{csv}", "--k", "3", "--C", "1e30", "--only", "s"], "--only"),
    (["fatigue", "{model}"], "[fatigue]"),
    (["fatigue", BRACKET, "--method", "miner"], "narrowband"),
    (["fatigue", BRACKET, "--only", "nosuch"], "nosuch"),
])
def test_bad_input_is_exit_2(tmp_path, args: list, message: str) -> None:  # type: ignore
    csv = sine_history(tmp_path)
    model = tmp_path / "m.toml"
    model.write_text(BRACKET.read_text().split("[fatigue]")[0])
    status, _, err = run_cli([str(a).format(csv=csv, model=model) for a in args])
    assert status == 2 and message in err, err
    assert "{model}" in args or str(tmp_path) not in err   # the user's own path only


def test_bad_history_names_the_line(tmp_path) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "h.csv"
    path.write_text("t,s\n0,1\n0.1,oops\n")
    status, _, err = run_cli(["fatigue", "--csv", path, "--k", "3", "--C", "1e12"])
    assert status == 2 and "h.csv" in err and "line 3" in err


def test_bad_units_in_the_fatigue_section() -> None:
    from resonant.errors import ModelError
    text = BRACKET.read_text().replace("duration = 3600 ", 'duration = "2 m" ')
    with pytest.raises(ModelError, match=r"\[fatigue\] duration: the unit m is not one of time"):
        loads(text, source="b.toml")


def test_a_name_outside_the_response_is_refused(bracket) -> None:  # type: ignore
    from resonant.errors import AnalysisError
    model = load(BRACKET)
    response = random_response(linear_system(model), names=["stress"], tolerance=1e-4)
    with pytest.raises(AnalysisError, match="'z' is not a response"):
        response_fatigue(response, SNCurve(1e38, 4.0), 3600.0, names=["z"])
