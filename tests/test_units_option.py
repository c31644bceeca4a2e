"""``--units`` on every command that prints or draws numbers (docs/units.md).

The parser is walked: every subcommand takes ``--units`` and ``--timeout`` (the two that
print no number, ``example`` and ``grade``, are named).  Then each command with numeric
output is run twice in-process, and its output must change unit: mm against m, g against
m/s^2, Hz against rad/s, rpm against Hz.  The conversions themselves are exact factors
(1 mm = 1e-3 m, 1 g = 9.80665 m/s^2 by definition, 1 Hz = 2 pi rad/s), checked on the
printed numbers to their 4-6 printed digits.
"""

from __future__ import annotations

import argparse
import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from conftest import run_cli
from resonant.analyses.identify import identify_modes
from resonant.charts import Chart, Curve, _thinned, chart_svg
from resonant.cli import COMMANDS, build_parser
from resonant.cli.study import _in_display_units
from resonant.exercises.writing import ExerciseJob, render_variants
from resonant.model import loads
from resonant.model.units import display_units
from resonant.model.units_display import ResultUnits, result_units
from resonant.report.steps.loads import _amount, _cell

#: the subcommands that print no number of a model (a list of examples, a grade sheet)
WITHOUT_NUMBERS = {"example", "grade", "import"}  # import: FE files in, a model out


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser([])
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def test_every_command_with_numbers_takes_units_and_timeout():
    commands = _subparsers()
    assert set(commands) == set(COMMANDS)
    for name, sub in commands.items():
        options = {o for action in sub._actions for o in action.option_strings}
        if name in WITHOUT_NUMBERS:
            continue
        assert {"--units", "--timeout"} <= options, name


def _number_after(text: str, label: str) -> float:
    match = re.search(re.escape(label) + r"\s+([-+0-9.e]+)", text)
    assert match, (label, text)
    return float(match.group(1))


#: (arguments, --units of the first run, of the second, a unit the second prints)
CASES = [
    (["solve", "examples/absorber.toml"], "m", "mm", "mm"),
    (["sweep", "examples/absorber.toml", "--param", "omega", "--from", "10", "--to", "30",
      "--points", "41"], "rad/s", "Hz", "omega [Hz]"),
    (["modes", "examples/absorber.toml"], "Hz", "rpm", "[rpm]"),
    (["simulate", "examples/absorber.toml", "--duration", "1"], "m", "mm", "mm"),
    (["random", "examples/shaker_gevs.toml", "--only", "x,a"], "m", "mm,g", " g "),
    (["srs", "--pulse", "half-sine", "--amplitude", "490.3325", "--duration", "0.011",
      "--to", "1000", "--points", "5"], "m/s^2", "g", "maximax [g]"),
    (["campbell", "examples/rotors/jeffcott_rotor.toml", "--points", "9"], "rpm", "Hz",
     "f first [Hz]"),
    (["unbalance", "examples/rotors/jeffcott_rotor.toml", "--points", "9"], "m", "mm",
     "in mm"),
]


@pytest.mark.parametrize("args, first, second, shown", CASES, ids=[c[0][0] for c in CASES])
def test_output_changes_unit(args, first, second, shown):
    status_a, a, err_a = run_cli([*args, "--units", first])
    status_b, b, err_b = run_cli([*args, "--units", second])
    assert status_a == 0 and status_b == 0, err_a + err_b
    assert a != b and shown in b, b


def test_numbers_are_converted():
    """The same amplitude in m and in mm (x2 of the absorber: F0/k2 = 25 mm, Den Hartog
    3.2), and the SRS of a 50 g half-sine above 1/tau tends to its peak: 50 g."""
    _, metres, _ = run_cli(["solve", "examples/absorber.toml"])
    _, millimetres, _ = run_cli(["solve", "examples/absorber.toml", "--units", "mm"])
    assert _number_after(metres, "x2") == pytest.approx(0.025, rel=1e-6)
    assert _number_after(millimetres, "x2") == pytest.approx(25.0, rel=1e-6)
    _, srs, _ = run_cli(["srs", "--pulse", "half-sine", "--amplitude", "490.3325",
                         "--duration", "0.011", "--from", "5000", "--to", "10000",
                         "--points", "2", "--units", "g"])
    assert float(srs.splitlines()[-1].split()[1]) == pytest.approx(50.0, rel=2e-3)


def test_fatigue_shows_stresses_in_mpa():
    """``fatigue --units MPa``: the RMS in MPa (1 MPa = 1e6 Pa), the S-N curve's C for S in
    MPa (N S^k = C, so C / (1e6)^k), the damage and the life unchanged."""
    args = ["fatigue", "examples/bracket_fatigue.toml"]
    status_a, pascal, err_a = run_cli(args)
    status_b, mpa, err_b = run_cli([*args, "--units", "MPa"])
    assert status_a == 0 and status_b == 0, err_a + err_b

    def row(text: str) -> list[str]:
        return next(line.split() for line in text.splitlines() if "dirlik" in line)

    def curve(text: str) -> tuple[float, float]:
        match = re.search(r"N S\^([0-9.]+) = ([-+0-9.e]+)", text)
        assert match, text
        return float(match.group(1)), float(match.group(2))

    si, shown = row(pascal), row(mpa)
    assert si[1] == "Pa" and shown[1] == "MPa"
    assert float(shown[2]) == pytest.approx(float(si[2]) / 1e6, rel=1e-3)
    assert shown[5:] == si[5:]                       # damage, life [s], life [h]
    (k, c_si), (_, c_mpa) = curve(pascal), curve(mpa)
    assert c_mpa == pytest.approx(c_si / 1e6 ** k, rel=1e-3) and "in MPa" in mpa


def test_g_and_stresses_are_display_units():
    """``--units g`` is standard gravity (an acceleration, never the gram), MPa a stress."""
    chosen = display_units(["g", "MPa", "mm/s"])
    assert set(chosen) == {"acceleration", "stress", "velocity"}
    units = ResultUnits(display=chosen)
    assert units.of("m/s^2")(9.80665) == pytest.approx(1.0)
    assert units.of("Pa")(2e6) == pytest.approx(2.0)
    assert units.of("kg").text == "kg"          # nothing chosen for a mass


def test_unknown_display_unit_is_exit_2():
    status, _, err = run_cli(["solve", "examples/absorber.toml", "--units", "kg*m"])
    assert status == 2 and "--units" in err


def test_measured_frequencies_follow_the_frequency_unit():
    """The identified modes in rad/s: 2 pi times their Hz (one mode at 3 Hz, 2 %)."""
    f = np.linspace(0.5, 6.0, 400)
    w, wn, zeta = 2 * np.pi * f, 2 * np.pi * 3.0, 0.02
    frf = 1 / (wn ** 2 - w ** 2 + 2j * zeta * wn * w)
    result = identify_modes(f, {"x": frf}, max_order=20, near=[3.0])
    hz = result.summary()
    rad = result.summary(ResultUnits(display=display_units(["rad/s"])))
    assert "f [Hz]" in hz and "f [rad/s]" in rad
    assert float(rad.splitlines()[1].split()[1]) == pytest.approx(
        2 * math.pi * float(hz.splitlines()[1].split()[1]), rel=1e-4)


def test_long_curves_are_thinned_in_svg():
    """A history of 10^5 samples is written as what its drawing shows (about four points
    per half-point column), not as 10^5 points (the report with random, shock and
    periodic sections was 3.7 MB); its extremes are kept exactly."""
    t = np.linspace(0.0, 1.0, 100_001)
    y = np.sin(2 * np.pi * 7 * t) + 0.3 * np.sin(2 * np.pi * 400 * t)
    svg = chart_svg(Chart((Curve(t, y, "y"),), "t", "y", (0.0, 1.0)), "long")
    assert len(svg) < 120_000
    keep = _thinned(t * 400, y)
    assert y[keep].max() == y.max() and y[keep].min() == y.min()


def test_report_amplitudes_carry_their_units():
    """The shock's amplitude reads 490.3 m/s^2 (50 g), the cells' units are typeset."""
    text = _amount(490.3325, "m/s^2")
    assert r"\mathrm{m/s^{2}}" in text and r"50\ \mathrm{g}" in text
    number, unit = _cell(0.25, "m/s^2")
    assert number == "0.25" and r"s^{2}" in str(unit)


def test_study_pictures_in_display_units():
    """The study's columns drawn in the display units (the file stays SI)."""
    table = pd.DataFrame({"k2": [400.0], "natural_frequency:1": [2 * math.pi]})
    units = {"k2": "N/m", "natural_frequency:1": "rad/s"}
    shown = ResultUnits(display=display_units(["Hz"]))
    converted, texts, nominal = _in_display_units(table, units, {"k2": 400.0}, shown)
    assert texts == {"k2": "N/m", "natural_frequency:1": "Hz"}
    assert converted["natural_frequency:1"].iloc[0] == pytest.approx(1.0)
    assert table["natural_frequency:1"].iloc[0] == pytest.approx(2 * math.pi)
    assert nominal == {"k2": 400.0}


def _key_answers(folder) -> dict:
    key = json.loads((folder / "key.json").read_text(encoding="utf-8"))
    return key["variants"][0]["answers"]


def test_exercise_key_in_display_units(tmp_path):
    """``exercise --units Hz,mm,deg`` writes the key as every command shows its results:
    the natural frequencies divided by 2 pi, the amplitude of C times 1000, the rod's
    angle times 180/pi (exact factors), the matrices unchanged; a worker's solution is
    the one this process writes (both in mm)."""
    model = "examples/teaching/cart_pendulum.toml"
    base = ["exercise", model, "--variants", "1", "--format", "json"]
    assert run_cli([*base, "-o", tmp_path / "si"])[0] == 0
    status, _, err = run_cli([*base, "-o", tmp_path / "shown", "--units", "Hz,mm,deg"])
    assert status == 0, err
    si, shown = _key_answers(tmp_path / "si"), _key_answers(tmp_path / "shown")
    assert si["natural_frequencies"]["unit"] == "rad/s"
    assert shown["natural_frequencies"]["unit"] == "Hz"
    assert np.allclose(np.multiply(shown["natural_frequencies"]["value"], 2 * math.pi),
                       si["natural_frequencies"]["value"], rtol=1e-12)
    assert (shown["amplitude:x2"]["unit"], si["amplitude:x2"]["unit"]) == ("mm", "m")
    assert shown["amplitude:x2"]["value"] == pytest.approx(
        1e3 * si["amplitude:x2"]["value"], rel=1e-12)
    assert shown["amplitude:phi"]["unit"] == "deg"
    assert shown["amplitude:phi"]["value"] == pytest.approx(
        math.degrees(si["amplitude:phi"]["value"]), rel=1e-12)
    assert shown["L"]["unit"] == "mm" and shown["K"] == si["K"]
    text = Path(model).read_text(encoding="utf-8")
    job = ExerciseJob(text, model, "examples/teaching", (), 1, 0, ("md",), False,
                      str(tmp_path / "worker"), ("mm",))
    solution = render_variants(job, 0, 1)[0][1]["solution.md"]
    assert r"\ \mathrm{mm}$ |" in solution  # the amplitudes' table


SHOCK_MODEL = """
[parameters]
m = "1 kg"
k = "1e4 N/m"
[coordinates]
x = { description = "absolute displacement", unit = "m" }
[signals]
y = "0"
[energy]
T = "m*x'^2/2"
U = "k*(x - y)^2/2"
[outputs]
a = "-k*(x - y)/m"
[shock]
signal = "y"
derivative = 2
pulse = "half-sine"
amplitude = 50
duration = 0.011
"""


@pytest.mark.parametrize("extra, shown", [
    ('unit = "g"\n', "g"),                                            # the input in g
    ('unit = "m/s^2"\n', "m/s^2"),                                    # in SI
    ('unit = "g"\n[display]\nacceleration = "m/s^2"\n', "m/s^2"),     # [display] decides
])
def test_accelerations_in_g_where_the_input_is(extra, shown):
    """A pulse (or a spectrum) given in g: accelerations are shown in g unless ``[display]``
    or ``--units`` choose; JSON stays SI."""
    model = loads(SHOCK_MODEL + extra)
    assert result_units(model).of("m/s^2").text == shown
    assert result_units(model).unit("a").text == shown


def test_srs_and_random_of_an_input_in_g_print_g():
    """The 50 g half-sine of examples/shock_half_sine.toml: its SRS above 1/tau tends to
    the pulse's peak, 50 g (rel 2e-3), in g by default; the GEVS spectrum's table RMS is
    14.14 g; ``--units m/s^2`` gives SI back (50 g = 490.3 m/s^2)."""
    args = ["srs", "examples/shock_half_sine.toml", "--from", "5000", "--to", "10000",
            "--points", "2", "--largest"]
    status, out, err = run_cli(args)
    assert status == 0, err
    row = next(line for line in out.splitlines() if line.split()[:1] == ["10000"])
    assert "maximax [g]" in out and float(row.split()[1]) == pytest.approx(50.0, rel=2e-3)
    assert re.search(r"\ba +g ", out), out            # the largest responses in g too
    status, out, err = run_cli([*args, "--units", "m/s^2"])
    row = next(line for line in out.splitlines() if line.split()[:1] == ["10000"])
    assert status == 0 and float(row.split()[1]) == pytest.approx(490.3325, rel=2e-3)
    assert re.search(r"\ba +m/s\^2 ", out), out
