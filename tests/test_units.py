"""Physical units (the contract: docs/units.md).

The reference exercise (docs/reference-exercise.md; BME Department of Applied Mechanics,
Vibrations BMEGEMMBXM4, "Practice 12 - 2 DoF forced system": cart + pendulum, data
m1 = 2 kg, m2 = 1 kg, l = 0.5 m, k = 100 N/m, F0 = 5 N, eps = pi/3, r0 = 0.01 m,
omega = 20 rad/s) is solved
with its data in mixed units (g, mm, N/mm, deg, rpm) and must give the numbers of the SI
version to a relative 1e-12 (the conversions are exact rationals and pi: only the last
floating-point bits may differ), and the exercise's own rounded results (Eqs. (42)-(48):
L = [0.00217, -0.03856] m, N = [0.00199, -0.02347] m, X2 = 0.0451 m, phi = 0.090 rad) to
the digits it prints.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import run_cli
from resonant.api import load, loads
from resonant.cli import main
from resonant.errors import ModelError
from resonant.expressions import parse
from resonant.model.dimension_inference import infer_dimensions
from resonant.model.units import (
    ENERGY,
    UNITS,
    Dimension,
    UnitError,
    display_units,
    parse_unit,
    split_value,
)

ROOT = Path(__file__).parents[1]
EXAMPLES = ROOT / "examples"

CART_PENDULUM = """
title = "Cart with pendulum"
[parameters]
m1 = {m1}
m2 = {m2}
l = {l}
k = {k}
g = {g}
F0 = {F0}
eps = {eps}
r0 = {r0}
omega = {omega}
[coordinates]
x1 = {x1}
x2 = {x2}
[signals]
r = "r0*cos(omega*t)"
F = "F0*sin(omega*t + eps)"
[definitions]
phi = "x2/l"
[energy]
T = "m1*x1'^2/2 + m2*(x1'^2 + x2'^2/4 + x1'*x2'*cos(phi))/2 + m2*l^2*phi'^2/24"
U = "k*(x1 - r)^2/2 - m2*g*l/2*cos(phi)"
[[force]]
name = "F at C"
vector = ["F", "0"]
point = ["x1 + x2", "-l*cos(phi)"]
[outputs]
phi = {phi}
"""
SI = dict(m1="2", m2="1", l="0.5", k="100", g="9.81", F0="5", eps='"pi/3"', r0="0.01",
          omega="20", x1='"cart"', x2='"rod end C"', phi='"x2/l"')
MIXED = dict(m1='"2000 g"', m2='"0.001 t"', l='"500 mm"', k='"0.1 N/mm"', g='"9.81 m/s^2"',
             F0='"0.005 kN"', eps='"60 deg"', r0='"10 mm"', omega='"20 rad/s"',
             x1='{ description = "cart", unit = "m" }',
             x2='{ description = "rod end C", unit = "mm" }', phi='"x2/l rad"')


def _write(tmp_path: Path, text: str, name: str = "model.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _solve_json(path: Path, *extra: str, capsys) -> dict:
    assert main(["solve", str(path), "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out)


# -- the reference exercise in mixed units -------------------------------------------------

@pytest.mark.parametrize("omega", ['"20 rad/s"', f'"{600 / math.pi!r} rpm"'])
def test_reference_exercise_in_mixed_units_gives_the_si_numbers(tmp_path, capsys, omega):
    si = _solve_json(_write(tmp_path, CART_PENDULUM.format(**SI), "si.toml"), capsys=capsys)
    mixed = _solve_json(_write(tmp_path, CART_PENDULUM.format(**{**MIXED, "omega": omega}),
                               "mixed.toml"), capsys=capsys)
    for key in ("M", "C", "K", "natural_frequencies"):
        np.testing.assert_allclose(mixed[key], si[key], rtol=1e-12, atol=1e-15)
    for key in ("omega", "F_S", "F_C", "L", "N"):
        np.testing.assert_allclose(mixed["harmonics"][0][key], si["harmonics"][0][key],
                                   rtol=1e-12, atol=1e-15)
    for name in ("x1", "x2", "phi"):
        assert mixed["amplitudes"][name] == pytest.approx(si["amplitudes"][name], rel=1e-12)
        assert mixed["phases"][name] == pytest.approx(si["phases"][name], rel=1e-12)
    assert mixed["symbolic"] == si["symbolic"]
    assert mixed["warnings"] == si["warnings"]
    # the exercise's printed results, Eqs. (42)-(48)
    h = mixed["harmonics"][0]
    assert h["L"] == pytest.approx([0.00217, -0.03856], abs=5e-6)
    assert h["N"] == pytest.approx([0.00199, -0.02347], abs=5e-6)
    assert mixed["amplitudes"]["x2"] == pytest.approx(0.0451, abs=5e-5)
    assert mixed["amplitudes"]["phi"] == pytest.approx(0.090, abs=5e-4)
    # JSON stays SI and says so
    assert mixed["units"]["x1"] == "m" and mixed["units"]["x2"] == "m"
    assert mixed["units"]["phi"] == "rad"
    assert mixed["units"]["M"] == [["kg", "kg"], ["kg", "kg"]]
    assert mixed["units"]["K"][0][0] == "N/m" and mixed["units"]["Q"] == ["N", "N"]
    assert mixed["units"]["natural_frequencies"] == "rad/s"
    assert mixed["parameters"]["l"] == 0.5 and mixed["parameters"]["m1"] == 2.0
    assert "units" not in si  # a model without units: the output as before


def _amplitude_row(text: str, name: str) -> list[str]:
    """The cells after the name of the row of ``name`` in the table of amplitudes and
    phases that ``resonant solve`` prints."""
    lines = text.split("amplitudes (peak deviation)", 1)[1].splitlines()
    return next(line.split()[1:] for line in lines if line.split()[:1] == [name])


def test_reference_exercise_text_output_shows_units(tmp_path, capsys):
    path = _write(tmp_path, CART_PENDULUM.format(**MIXED))
    assert main(["solve", str(path)]) == 0
    text = capsys.readouterr().out
    assert "mass matrix M [kg] =" in text and "stiffness matrix K [N/m] =" in text
    assert "F_S = [2.5, 2.5] N" in text
    assert "cos coefficients L = [0.00216562 m, -38.5616 mm]" in text  # x2 declared in mm
    assert _amplitude_row(text, "x2") == ["45.1413", "mm", "-2.1175", "rad"]
    assert main(["solve", str(path), "--units", "mm,deg,Hz"]) == 0
    text = capsys.readouterr().out
    assert "cos coefficients L = [2.16562, -38.5616] mm" in text
    assert _amplitude_row(text, "phi") == ["5.17281", "deg", "-121.324", "deg", "(output)"]
    assert "omega_1 = 4.56071 rad/s  (0.72586 Hz)" in text
    assert main(["solve", str(path), "--units", "rpm"]) == 0
    assert "omega = 20 rad/s  (190.986 rpm)" in capsys.readouterr().out


def test_display_section_chooses_the_output_units(tmp_path, capsys):
    path = _write(tmp_path, CART_PENDULUM.format(**MIXED) + '[display]\nlength = "cm"\n'
                  'angle = "deg"\n')
    assert main(["solve", str(path)]) == 0
    text = capsys.readouterr().out
    assert _amplitude_row(text, "x1") == ["0.294391", "cm", "47.3603", "deg"]
    # --units wins over [display]
    assert main(["solve", str(path), "--units", "mm"]) == 0
    assert _amplitude_row(capsys.readouterr().out, "x1")[:2] == ["2.94391", "mm"]


def test_display_section_without_units_converts_phases_and_frequencies(tmp_path, capsys):
    path = _write(tmp_path, CART_PENDULUM.format(**SI) + '[display]\nangle = "deg"\n'
                  'frequency = "rpm"\n')
    assert main(["solve", str(path)]) == 0
    text = capsys.readouterr().out
    assert _amplitude_row(text, "x2")[-2:] == ["-121.324", "deg"]
    assert "omega_1 = 4.56071 rad/s  (43.5516 rpm)" in text
    # lengths: no unit known, as given
    assert _amplitude_row(text, "x2") == ["0.0451413", "-121.324", "deg"]


def test_report_data_table_shows_given_and_si_units(tmp_path, capsys):
    path = _write(tmp_path, CART_PENDULUM.format(**MIXED))
    out = tmp_path / "report.md"
    assert main(["report", str(path), "-o", str(out)]) == 0
    md = out.read_text()
    assert r"| $l$ | $500\ \mathrm{mm}$ | $0.5\ \mathrm{m}$ |" in md
    assert r"| $k$ | $0.1\ \mathrm{N/mm}$ | $100\ \mathrm{N/m}$ |" in md
    assert r"0.04514\ \mathrm{m}" in md  # the maximal excursion of C, Eq. (47)


# -- mixed translational and rotational coordinates ------------------------------------------

CART_AND_ANGLE = """
[parameters]
m = "2 kg"
ml = "0.5 kg"
l = "400 mm"
k = "2 kN/m"
g = "9.81 m/s^2"
M0 = "0.3 N*m"
w = "5 rad/s"
[coordinates]
x = { description = "cart", unit = "m" }
phi = { description = "pendulum angle", unit = "rad" }
[signals]
Mt = "M0*sin(w*t)"
[energy]
T = "m*x'^2/2 + ml*((x' + l*phi'*cos(phi))^2 + (l*phi'*sin(phi))^2)/2"
U = "k*x^2/2 - ml*g*l*cos(phi)"
[[force]]
name = "drive torque"
generalized = { phi = "Mt" }
"""


def test_mixed_coordinates_give_units_per_matrix_entry(tmp_path, capsys):
    data = _solve_json(_write(tmp_path, CART_AND_ANGLE), capsys=capsys)
    units = data["units"]
    assert units["M"] == [["kg", "kg*m"], ["kg*m", "kg*m^2"]]
    assert units["K"] == [["N/m", "N"], ["N", "N*m"]]
    assert units["C"] == [["N*s/m", "N*s"], ["N*s", "N*m*s"]]
    assert units["Q"] == ["N", "N*m"]
    assert main(["solve", str(_write(tmp_path, CART_AND_ANGLE)), "--units", "deg"]) == 0
    text = capsys.readouterr().out
    assert "mass matrix M (entries in the units below) =" in text
    assert "[  kg*m  kg*m^2]" in text and "[  N  N*m]" in text


# -- dimension errors ------------------------------------------------------------------------

BASE = """
[parameters]
m = "2 kg"
c = "3 N*s/m"
k = "100 N/m"
l = "0.5 m"
g = "9.81 m/s^2"
F0 = "5 N"
w = "20 rad/s"
[coordinates]
x = { description = "displacement", unit = "m" }
[signals]
F = "F0*sin(w*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
name = "push"
vector = ["F"]
point = ["x"]
"""


def _error(text: str) -> str:
    with pytest.raises(ModelError) as info:
        loads(text, source="m.toml")
    return str(info.value)


@pytest.mark.parametrize(("old", "new", "expected"), [
    # T not an energy
    ('T = "m*x\'^2/2"', 'T = "m*x\'/2"',
     "m.toml: [energy] T: m*x'/2 is N*s but T must be an energy (J)"),
    # a spring term k*x instead of k*x^2/2
    ('U = "k*x^2/2"', 'U = "k*x/2 + m*g*x"',
     "m.toml: [energy] U: k*x/2 is N but m*g*x is J: the terms of a sum must have the same "
     "unit"),
    ('U = "k*x^2/2"', 'U = "k*x^2/2 - m*g"',
     "m.toml: [energy] U: k*x^2/2 is J but m*g is N"),
    # a force given in N*m
    ('F0 = "5 N"', 'F0 = "5 N*m"',
     "m.toml: [force 'push'] vector[0]: F is N*m but its point's position point[0] = x is "
     "m: it must be a force (N)"),
    # sin of a length
    ('T = "m*x\'^2/2"', 'T = "m*x\'^2/2*cos(x)"',
     "m.toml: [energy] T: the argument of cos() must be dimensionless (an angle in rad) but "
     "x is m"),
    # D not a power
    ('D = "c*x\'^2/2"', 'D = "c*x\'*x/2"',
     "m.toml: [energy] D: c*x'*x/2 is J but D must be a power (W)"),
    # a sum in a signal, a function argument in a signal
    ('F = "F0*sin(w*t)"', 'F = "F0*sin(w*t) + m"', "[signals] F: F0*sin(w*t) is N but m is kg"),
    ('F = "F0*sin(w*t)"', 'F = "F0*sin(w)"',
     "[signals] F: the argument of sin() must be dimensionless (an angle in rad) but w is 1/s"),
    # a generalized force that is not a force
    ('vector = ["F"]\npoint = ["x"]', 'generalized = { x = "F*l" }',
     "[force 'push'] generalized.x: F*l is N*m but its coordinate x is m: it must be a force"),
    # an exponent with a unit
    ('T = "m*x\'^2/2"', 'T = "m*x\'^l"', "the exponent l is m: an exponent must be dimensionless"),
])
def test_each_dimension_error_is_named(old, new, expected):
    assert old in BASE
    assert expected in _error(BASE.replace(old, new))


def test_dimension_error_exits_2_with_one_line_per_problem(tmp_path, capsys):
    text = BASE.replace('T = "m*x\'^2/2"', 'T = "m*x\'/2"').replace('D = "c*x\'^2/2"',
                                                                   'D = "c*x\'*x/2"')
    assert main(["check", str(_write(tmp_path, text))]) == 2
    err = capsys.readouterr().err
    assert "[energy] T:" in err and "[energy] D:" in err and "Traceback" not in err


def test_torque_on_an_angle_and_zero_fit_any_unit():
    text = CART_AND_ANGLE.replace('U = "k*x^2/2 - ml*g*l*cos(phi)"',
                                  'U = "k*x^2/2 - ml*g*l*cos(phi) + 0"')
    assert loads(text).units is not None
    assert "must be a moment (N*m)" in _error(CART_AND_ANGLE.replace('M0 = "0.3 N*m"',
                                                                     'M0 = "0.3 N"'))


def test_output_and_equilibrium_units_are_checked():
    assert "[outputs] v: x is m but its unit rad is 1" in _error(BASE + '[outputs]\nv = "x rad"\n')
    assert "[equilibrium] x: m is kg but x must be in the unit of x (m)" in _error(
        BASE.replace("[signals]", '[equilibrium]\nx = "m"\n[signals]'))


# -- partial units, Hz, rpm ------------------------------------------------------------------

def test_partially_united_model_says_once_what_it_could_not_check(tmp_path, capsys):
    """A bare number whose uses leave its dimension open (here only the product a*b is
    fixed by D) is named once in a note; one whose uses fix it is inferred (docs/units.md)."""
    model = loads(BASE.replace('c = "3 N*s/m"', 'a = 3\nb = 1\nc = "a*b"'))
    assert len(model.units.notes) == 1
    assert model.units.notes[0].startswith("units: could not check ")
    assert "a, b have no unit" in model.units.notes[0]
    assert main(["check", str(_write(tmp_path, BASE.replace(
        'c = "3 N*s/m"', 'a = 3\nb = 1\nc = "a*b"')))]) == 0
    err = capsys.readouterr().err
    assert err.count("could not check") == 1


def test_a_bare_number_gets_the_dimension_its_uses_imply():
    """D is a power, so c in D = c*x'^2/2 is N*s/m; so z in c = 2*z*sqrt(k*m) is
    dimensionless; an output adding k*x (N) and c*x (N*s) is then an error."""
    damped = BASE.replace('c = "3 N*s/m"\n', "").replace(
        'k = "100 N/m"\n', 'k = "100 N/m"\nz = 0.1\nc = "2*z*sqrt(k*m)"\n')
    model = loads(damped)
    assert model.units.dimensions["z"].dimensionless
    assert model.units.dimensions["c"].text() == "N*s/m"
    assert model.units.notes == ("units: inferred from their uses: z in 1 (dimensionless)",)
    assert loads(BASE.replace('c = "3 N*s/m"', "c = 3")).units.dimensions["c"].text() \
        == "N*s/m"
    bad = _error(damped + '[outputs]\nF_spring = "k*x + c*x"\n')
    assert "[outputs] F_spring" in bad and "k*x is N but c*x is N*s" in bad
    assert "k*x + c*x'" not in bad
    loads(damped + '[outputs]\nF_spring = "k*x + c*x\'"\n')  # N + N: fine


def test_hz_rpm_and_expressions_convert_as_documented():
    model = loads("""
[parameters]
f = "50 Hz"
Omega = "2*pi*f"
n = "1200 rpm"
eps = "60 deg"
k2 = "150 N/mm"
I = "2 kg*m^2"
c = "2.5 N*s/m"
mt = "(1 + 1) kg"
[coordinates]
x = ""
[energy]
T = "x'^2"
""")
    values, exact = model.parameter_values, model.exact_values
    assert values["f"] == 50.0
    assert values["Omega"] == pytest.approx(314.159265358979, rel=1e-14)
    assert values["n"] == pytest.approx(125.663706143592, rel=1e-14)
    assert exact["eps"] == sympy.pi / 3 and exact["n"] == 40 * sympy.pi
    assert values["k2"] == 150000.0 and values["I"] == 2.0 and values["mt"] == 2.0
    assert model.units.dimensions["Omega"].text() == "1/s"
    assert model.units.dimensions["c"].text() == "N*s/m"


def test_a_value_in_hz_used_as_angular_frequency_is_warned_once():
    text = BASE.replace('w = "20 rad/s"', 'w = "20 Hz"')
    notes = loads(text).units.notes
    assert len(notes) == 1 and "w is given in Hz" in notes[0] and "2*pi*w*t" in notes[0]
    assert loads(text.replace("sin(w*t)", "sin(2*pi*w*t)")).units.notes == ()
    assert loads(BASE).units.notes == ()


def test_names_inside_expressions_are_the_models_own():
    model = loads("""
[parameters]
m = "3 kg"
g = "9.81 m/s^2"
W = "m*g"
[coordinates]
x = { description = "", unit = "m" }
[energy]
T = "m*x'^2/2"
U = "W*x"
""")
    assert model.parameter_values["W"] == pytest.approx(29.43)
    assert model.units.dimensions["W"].text() == "N"


def test_set_accepts_a_unit(tmp_path, capsys):
    path = _write(tmp_path, BASE)
    data = _solve_json(path, "--set", "k=0.2 N/mm", capsys=capsys)
    assert data["K"] == [[200.0]]
    data = _solve_json(path, "--set", "k=300", capsys=capsys)  # a bare number: SI, N/m
    assert data["K"] == [[300.0]]
    assert "could not check" not in capsys.readouterr().err
    assert main(["check", str(path), "--set", "k=0.2 N"]) == 2
    assert "k*x^2/2 is kg*m^3/s^2 but U must be an energy (J)" in capsys.readouterr().err


# -- a model without units -------------------------------------------------------------------

def test_model_without_units_is_unchanged_and_does_not_import_pint(tmp_path):
    path = _write(tmp_path, CART_PENDULUM.format(**SI))
    code = ("import sys; from resonant.model import load; m = load(sys.argv[1]); "
            "assert m.units is None; "
            "m2 = load(sys.argv[2]); assert m2.units is not None; "
            "print('pint' in sys.modules)")
    mixed = _write(tmp_path, CART_PENDULUM.format(**MIXED), "mixed.toml")
    out = subprocess.run([sys.executable, "-c", code, str(path), str(mixed)],
                         capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"  # the usual units need no pint at all


# -- unit text -------------------------------------------------------------------------------

@pytest.mark.parametrize(("text", "expected"), [
    ("2 kg", ("2", "kg")), ("2*pi*f", ("2*pi*f", None)), ("(a + b) N*s/m", ("(a + b)", "N*s/m")),
    ("1e-3 m", ("1e-3", "m")), ("x'^2", ("x'^2", None)), ("60 °", ("60", "°")),
    ("sin(a) m", ("sin(a)", "m")), ("3 1/s", ("3", "1/s")),
])
def test_split_value(text, expected):
    assert split_value(text) == expected


@pytest.mark.parametrize(("text", "message"), [
    ("N/mmm", "unknown unit 'mmm'; did you mean 'mm'?"),
    ("kg m", "unexpected 'm'"),
    ("m^x", "the exponent of a unit must be an integer"),
    ("m^99", "unit exponent too large"),
    ("__import__", "unknown unit"),
    ("m;rm", "unexpected character ';'"),
    ("degC", "offset"),
])
def test_bad_unit_text_is_refused_in_words(text, message):
    with pytest.raises(UnitError, match=None) as info:
        parse_unit(text)
    assert message in str(info.value)


def test_bad_unit_in_a_model_names_file_section_key(tmp_path, capsys):
    path = _write(tmp_path, BASE.replace('k = "100 N/m"', 'k = "100 N/mx"'))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "[parameters] k: unknown unit 'mx'" in err
    path = _write(tmp_path, BASE.replace('unit = "m"', 'unit = "meters please"'))
    assert main(["check", str(path)]) == 2
    assert "[coordinates] x.unit:" in capsys.readouterr().err


def test_unit_names_in_messages_are_escaped(tmp_path, capsys):
    path = _write(tmp_path, BASE.replace('k = "100 N/m"', 'k = "100 N/m\\u001b[2K"'))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "\x1b" not in err and "\\x1b" in err


def test_display_units_classify_and_refuse():
    chosen = display_units(["mm", "deg", "Hz", "kN"])
    assert set(chosen) == {"length", "angle", "frequency", "force"}
    with pytest.raises(UnitError):
        display_units(["N/m"])


@pytest.mark.parametrize("name", sorted(UNITS))
def test_unit_table_agrees_with_pint(name):
    """Every unit resonant knows without pint has pint's factor and dimension."""
    pint = pytest.importorskip("pint")
    ours = parse_unit(name)
    if name in ("°", "Nm", "kNm", "rev", "revolution", "turn", "rps", "dimensionless"):
        aliases = {"°": "degree", "Nm": "N*m", "kNm": "kN*m", "rev": "revolution",
                   "revolution": "revolution", "turn": "turn",
                   "rps": "revolution/second", "dimensionless": "dimensionless"}
        target = aliases[name]
    else:
        target = name
    registry = _pint_registry(pint)
    quantity = registry.Quantity(1, target).to_base_units()
    assert float(quantity.magnitude) == pytest.approx(ours.to_si(), rel=1e-12)
    dims = {k: Fraction(v) for k, v in dict(quantity.dimensionality).items()}
    mine = dict(zip(("[length]", "[mass]", "[time]"), ours.dimension.exponents[:3]))
    assert {k: v for k, v in mine.items() if v} == dims


_REGISTRY: list = []


def _pint_registry(pint):
    if not _REGISTRY:
        _REGISTRY.append(pint.UnitRegistry())
    return _REGISTRY[0]


def test_unit_outside_the_table_comes_from_pint():
    unit = parse_unit("mile")
    assert unit.to_si() == pytest.approx(1609.344) and unit.dimension.text() == "m"


# -- the bundled examples --------------------------------------------------------------------

@pytest.mark.parametrize("path", sorted(EXAMPLES.rglob("*.toml")),
                         ids=lambda p: str(p.relative_to(EXAMPLES)))
def test_every_bundled_example_passes_the_unit_check(path):
    model = load(path)
    assert model.units is not None, "the example gives no units"
    assert model.units.notes == (), model.units.notes
    for q in model.coordinates:
        assert model.units.dimensions[q] is not None
    assert ENERGY.text() == "J"


# -- other commands, plots, the benchmark ------------------------------------------------------

def test_modes_sweep_and_simulate_json_carry_units(tmp_path, capsys):
    path = _write(tmp_path, CART_PENDULUM.format(**MIXED))
    for args in (["modes"], ["sweep", "--param", "omega", "--from", "1", "--to", "30",
                             "--points", "5"], ["simulate", "--duration", "1"]):
        assert main([args[0], str(path), *args[1:], "--json"]) == 0
        data = json.loads(capsys.readouterr().out)
        assert data["units"]["x1"] == "m" and data["units"]["phi"] == "rad", args[0]


def test_plot_axes_are_labelled_with_units(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from resonant.model.units_display import result_units

    model = loads(CART_PENDULUM.format(**MIXED))
    units = result_units(model)
    response = model.linearize().sweep("omega", np.linspace(1, 30, 7))
    figure = response.plot(units=units.si)
    labels = [text.get_text() for text in figure.axes[0].get_legend().get_texts()]
    assert "$x_{1}$ [m]" in labels and "$\\varphi$ (output) [rad]" in labels
    same = response.plot(names=["x1", "x2"], units=units.si)
    assert same.axes[0].get_ylabel().endswith("[m]")
    sim = model.simulate(duration=0.5)
    assert sim.plot(units=units.si).axes[0].get_ylabel().startswith("$x_{1}$ [m]")


def test_units_benchmark_versions_agree():
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import bench_units

    versions = bench_units.texts()
    assert loads(versions["si"]).units is None
    values = [loads(text).parameter_values for text in versions.values()]
    for name in values[0]:
        assert values[1][name] == pytest.approx(values[0][name], rel=1e-14)
        assert values[2][name] == pytest.approx(values[0][name], rel=1e-14)


def test_with_parameters_checks_the_unit_of_a_new_value():
    """A replaced value in a unit of another dimension is an error naming the parameter;
    a value in another unit of the same dimension is converted (the reference exercise's
    k = 100 N/m is 0.1 N/mm)."""
    model = load(EXAMPLES / "cart_pendulum.toml")
    with pytest.raises(ModelError) as info:
        model.with_parameters(k="3 kg")
    assert "[parameters] k: the value is in kg (a mass), but k is in N/m" in str(info.value)
    assert model.with_parameters(k="0.1 N/mm").parameter_values["k"] == pytest.approx(100.0)


def test_modes_text_in_the_chosen_frequency_unit():
    """``modes --units rpm``: the cyclic column in rpm (omega * 60 / 2 pi); JSON stays in
    rad/s. Reference exercise: omega_1 = 4.56071 rad/s = 43.5516 rpm."""
    status, out, err = run_cli(["modes", str(EXAMPLES / "cart_pendulum.toml"), "--units", "rpm"])
    assert status == 0, err
    assert "f [rpm]" in out
    first = next(line for line in out.splitlines() if line.split()[:1] == ["1"]).split()
    assert float(first[1]) == pytest.approx(4.56071, rel=1e-5)
    assert float(first[2]) == pytest.approx(4.56071 * 60 / (2 * math.pi), rel=1e-5)


def test_a_torque_part_in_newton_is_named_as_a_torque(tmp_path):
    """A [[torque]] part's moment in N (not N*m): the error names the torque and its key."""
    text = (EXAMPLES / "parts" / "torsional_chain.toml").read_text().replace(
        'M0 = "2 N*m"', 'M0 = "2 N"')
    assert 'M0 = "2 N"' in text
    message = _error(text)
    assert "[torque 'drive'] moment:" in message and "must be a moment (N*m)" in message


MATRIX_MODEL = """title = "cart and rotor, given by matrices"
[parameters]
k = "100 N/m"
m = "2 kg"
J = "0.5 kg*m^2"
kt = "3 N*m/rad"
F0 = "1 N"
w = "5 rad/s"
[coordinates]
x = { description = "cart", unit = "m" }
phi = { description = "rotor angle", unit = "rad" }
[matrices]
M = [["m", 0], [0, "J"]]
K = [["k", 0], [0, "kt"]]
[[harmonic]]
omega = "w"
F_S = ["F0", 0]
F_C = [0, 0]
"""


@pytest.mark.parametrize(("old", "new", "expected"), [
    ('[0, "J"]]', '[0, "m"]]',
     "[matrices] M[2][2]: m is kg but M[2][2] must be the M entry of (phi, phi) (kg*m^2)"),
    ('K = [["k", 0]', 'K = [["kt", 0]',
     "[matrices] K[1][1]: kt is J but K[1][1] must be the K entry of (x, x) (N/m)"),
    ('F_S = ["F0", 0]', 'F_S = ["J", 0]',
     "[harmonic 1] F_S[1]: J is kg*m^2 but F_S[1] must be the generalized force on x (N)"),
])
def test_matrix_entries_are_checked_against_the_coordinates_units(old, new, expected):
    """An entry (i, j) of M, C, K times q_i q_j is J s^2, J s, J; F_i q_i is J. The
    consistent model loads (and plain numbers, SI of unknown dimension, are not judged)."""
    assert loads(MATRIX_MODEL).units is not None
    assert loads(MATRIX_MODEL.replace('[0, "J"]]', '[0, 0.5]]')).units is not None
    text = MATRIX_MODEL.replace(old, new)
    assert text != MATRIX_MODEL
    assert expected in _error(text)


@settings(max_examples=30, deadline=None)
@given(st.sampled_from(["-1", "-1/2", "0", "1/2", "1", "2"]),
       st.sampled_from(["-1", "-1/2", "0", "1/2", "1"]))
def test_inferred_dimension_is_the_one_a_unit_would_give(a, b):
    """Two routes to one dimension: z bare in c = z*k^a*m^b with D = c*x'^2/2 (a power)
    is inferred as N*s/m / (N/m)^a / kg^b, the dimension that makes c N*s/m."""
    text = BASE.replace('c = "3 N*s/m"\n', "").replace(
        'k = "100 N/m"\n', f'k = "100 N/m"\nz = 2\nc = "z*k^({a})*m^({b})"\n')
    dims = loads(text).units.dimensions
    newton = Dimension.of(kg=1, m=1, s=-2)
    damping = newton * Dimension.of(s=1, m=-1)
    expected = damping / (newton / Dimension.of(m=1)) ** Fraction(a) / \
        Dimension.of(kg=1) ** Fraction(b)
    assert dims["z"] == expected and dims["c"] == damping


def test_inline_matrices_and_harmonics_are_uses_that_fix_a_bare_number():
    """In a model given by matrices, C_ij q_i q_j is J*s and a harmonic's omega a frequency:
    c = 0.4 in C[1][1] on a cart (m) is N*s/m, w = 5 as omega is 1/s, and z in
    ct = 2*z*sqrt(kt*J) on a rotor angle (rad) is dimensionless; an output then adding k*x
    (N) and c*x (N*s) is an error (docs/units.md)."""
    text = MATRIX_MODEL.replace('w = "5 rad/s"', 'w = 5\nc = 0.4\nz = 0.05\n'
                                'ct = "2*z*sqrt(kt*J)"').replace(
        'K = [["k", 0]', 'C = [["c", 0], [0, "ct"]]\nK = [["k", 0]')
    assert text.count("c = 0.4") == 1 and "C = [[" in text
    model = loads(text)
    dims = model.units.dimensions
    assert dims["c"].text() == "N*s/m" and dims["w"].text() == "1/s"
    assert dims["z"].dimensionless
    assert model.units.notes == (
        "units: inferred from their uses: w in 1/s, c in N*s/m, z in 1 (dimensionless)",)
    bad = _error(text + '[outputs]\nF = "k*x + c*x"\n')
    assert "[outputs] F: k*x is N but c*x is N*s" in bad
    loads(text + '[outputs]\nF = "k*x + c*x\'"\n')  # N + N: fine


def test_contradicting_uses_leave_open_only_the_numbers_they_involve():
    """p = 2 used as N*s in T (p*x') and as N in U (p*x) fits no dimension: it stays
    unknown and is named, while z, linked to it by no use, is still inferred
    (dimensionless, from D a power) so that the output adding N and N*s is an error."""
    damped = BASE.replace('c = "3 N*s/m"\n', "").replace(
        'k = "100 N/m"\n', 'k = "100 N/m"\nz = 0.1\nc = "2*z*sqrt(k*m)"\np = 0\n')
    text = damped.replace('T = "m*x\'^2/2"', 'T = "m*x\'^2/2 + p*x\'"').replace(
        'U = "k*x^2/2"', 'U = "k*x^2/2 + p*x"')
    assert text.count("p*x") == 2
    model = loads(text)
    assert model.units.dimensions["z"].dimensionless and model.units.dimensions["p"] is None
    assert "units: inferred from their uses: z in 1 (dimensionless)" in model.units.notes
    assert any(n.startswith("units: the uses of p contradict each other")
               for n in model.units.notes)
    assert "k*x is N but c*x is N*s" in _error(text + '[outputs]\nF = "k*x + c*x"\n')


def test_a_literal_zero_in_a_sum_fixes_no_dimension():
    """0 fits any unit: k = 100 bare in U = k*x^2/2 + 0 is N/m (from U an energy), not
    dimensionless (as if 0 were a dimensionless term of the sum)."""
    text = BASE.replace('k = "100 N/m"', "k = 100").replace('U = "k*x^2/2"',
                                                          'U = "k*x^2/2 + 0"')
    assert "k = 100\n" in text and "+ 0" in text
    assert loads(text).units.dimensions["k"].text() == "N/m"


@settings(max_examples=30, deadline=None)
@given(st.lists(st.integers(-3, 3), min_size=3, max_size=3),
       st.sampled_from(["-1", "1/2", "1", "2"]))
def test_a_contradiction_elsewhere_does_not_change_an_inference(exponents, a):
    """Two routes to one dimension: z in z*k^a = J*s^-1 (a power) inferred alone and next to
    a number p used as both m and s, which contradicts itself and is reported as None."""
    k = Dimension.of(kg=exponents[0], m=exponents[1], s=exponents[2])
    power = ENERGY / Dimension.of(s=1)
    known = {"k": k}
    alone = infer_dimensions(known, ["z"], [], [(parse(f"z*k^({a})"), power)])
    both = infer_dimensions(known, ["z", "p"], [], [
        (parse(f"z*k^({a})"), power), (parse("p"), Dimension.of(m=1)),
        (parse("p"), Dimension.of(s=1))])
    assert alone["z"] == power / k ** Fraction(a) == both["z"]
    assert both["p"] is None and "p" not in alone


KN_TEMPLATE = """
[parameters]
m = "2 kg"
k = "800 kN/m"
[coordinates]
x = { description = "the mass", unit = "m" }
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
"""


@pytest.mark.parametrize("value, written", [(6e5, None), ("600 kN/m", "600 kN/m"),
                                             ("0.6 MN/m", "0.6 MN/m")])
def test_a_replaced_value_is_written_as_it_was_given(value, written, tmp_path):
    """A variant's k replaces the template's "800 kN/m": what the answer sheet shows as
    "given as" is the variant's, never the template's beside the variant's value (9 of 24
    rows of a teacher's sheet read "given as 800 kN/m, value 6e5 N/m")."""
    import resonant

    model = resonant.loads(KN_TEMPLATE).with_parameters(k=value)
    assert model.parameter_values["k"] == pytest.approx(6e5, rel=1e-15)
    given = model.units.given.get("k")
    assert (given is None) if written is None else \
        f"{given[0].text} {given[1].text}" == written
    path = model.report(tmp_path / "r.md", plots=False)
    data = path.read_text().split("## ")[1]   # the data section's table
    assert "800" not in data, data
