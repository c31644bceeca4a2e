"""Units and arithmetic in the keys of a physical quantity, as ``[parameters]`` takes them
(model/study.py ``srs:NAME@f``, model/load_spec.py ``quantity_value``).

References: the unit conversions themselves (0.1 kHz = 100 Hz, 2 pi 50 rad/s = 50 Hz,
41.4 ms = 0.0414 s, 11 ms = 0.011 s: exact or to rounding, 1e-12); a unit of another
quantity is a problem naming the file, the section and the key.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import resonant
from conftest import run_cli
from resonant.errors import ModelError
from resonant.model import loads
from resonant.studies import request

SHAKER = "examples/shaker_gevs.toml"


@pytest.fixture(scope="module")
def shaker():  # type: ignore[no-untyped-def]
    return resonant.load(SHAKER)


@pytest.mark.parametrize("written, column", [
    ("srs:a@100", "srs:a@100"), ("srs:a@0.1 kHz", "srs:a@100"), ("srs:a@2*50", "srs:a@100"),
    ("srs:a@2*pi*50 rad/s", "srs:a@50"), ("srs:a@6000 rpm", "srs:a@100"),
])
def test_srs_frequency_takes_units_and_arithmetic(shaker, written: str,  # type: ignore
                                                  column: str) -> None:
    spec = request(shaker, {"k": [1e6]}, [written], design="grid")
    (quantity,) = spec.quantities
    assert quantity.text == column
    assert quantity.frequency == pytest.approx(float(column.split("@")[1]), rel=1e-12)


@pytest.mark.parametrize("bad", ["srs:a@3 m", "srs:a@x", "srs:a@-2 Hz", "srs:a@1/0"])
def test_srs_frequency_of_another_quantity_is_refused(shaker, bad: str) -> None:  # type: ignore
    with pytest.raises(ModelError, match="natural frequency in Hz after '@'"):
        request(shaker, {"k": [1e6]}, [bad], design="grid")


def test_time_keys_of_the_load_sections_take_units() -> None:
    base = ("[parameters]\nm = 1\nk = 100\nc = 1\ny0 = 0\n[coordinates]\nx = {}\n"
            "[signals]\nF = \"y0\"\n[energy]\nT = \"m*x'^2/2\"\nU = \"k*(x - F)^2/2\"\n"
            "D = \"c*x'^2/2\"\n")
    periodic = loads(base + '[periodic]\nsignal = "F"\nshape = "square"\namplitude = 1\n'
                            'period = "41.4 ms"\n').periodic_section
    assert periodic is not None and periodic.period == pytest.approx(0.0414, rel=1e-12)
    shock = loads(base + '[shock]\nsignal = "F"\npulse = "half-sine"\namplitude = 1\n'
                         'duration = "11 ms"\nstep = "5 us"\ntotal = "0.03 s"\n').shock_section
    assert shock is not None and shock.duration == pytest.approx(0.011, rel=1e-12)
    assert shock.step == pytest.approx(5e-6, rel=1e-12) and shock.total == 0.03
    with pytest.raises(ModelError, match=r"m.toml: \[shock\] duration: the unit kg is not one "
                                         "of time"):
        loads(base + '[shock]\nsignal = "F"\npulse = "half-sine"\namplitude = 1\n'
                     'duration = "11 kg"\n', source="m.toml")


# -- every number key of the load sections: one table ----------------------------------------

BASE = ("[parameters]\nm = 1\nk = 100\nc = 1\ny0 = 0\nw = 3\n[coordinates]\nx = {}\n"
        "[signals]\nF = \"y0\"\n[energy]\nT = \"m*x'^2/2\"\nU = \"k*(x - F)^2/2\"\n"
        "D = \"c*x'^2/2\"\n")
SECTIONS = {
    "periodic": 'signal = "F"\nshape = "square"\namplitude = 1\nperiod = 0.5\n',
    "periodic-expression": 'signal = "F"\nexpression = "t"\nperiod = 0.5\n',
    "shock": 'signal = "F"\npulse = "half-sine"\namplitude = 1\nduration = 0.01\n',
    "fatigue": 'k = 4\namplitude = 1e8\ncycles = 1e6\nduration = 60\n',
    "random": 'band = [10, 100]\n[random.psd.F]\nvalues = [[10, 1], [100, 1]]\n',
}


def _loaded(section: str, extra: str):  # type: ignore[no-untyped-def]
    """The model with the section of ``section`` where ``extra`` replaces its keys."""
    name = section.split("-")[0]
    body = SECTIONS[section]
    for line in [] if "[random.psd" in extra else extra.splitlines():
        key = line.split("=")[0].strip()
        body = "".join(f"{line}\n" if old.split("=")[0].strip() == key else f"{old}\n"
                       for old in body.splitlines()) if f"\n{key} =" in f"\n{body}" \
            else f"{line}\n{body}"
    text = BASE + f"[{name}]\n" + (extra + "\n" if "[random.psd" in extra else body)
    if name == "fatigue":   # [fatigue] needs a random input and a stress output
        text += "[outputs]\nS = \"x\"\n" + f"[random]\n{SECTIONS['random']}"
    return loads(text, source="m.toml")


# (section, keys as written, the spec's attribute, its SI value); the references are the
# unit conversions themselves (exact or to rounding, 1e-12): 1 g = 9.80665 m/s^2 (CGPM
# 1901), 1 rpm = 1/60 Hz, 1 percent = 0.01
VALUES = [
    ("periodic", 'amplitude = "2*1"', "amplitude", 2.0),
    ("periodic", 'amplitude = "2 mm"', "amplitude", 2e-3),
    ("periodic", 'amplitude = "50 g"', "amplitude", 490.3325),
    ("periodic", 'unit = "g"\namplitude = "2*5"', "amplitude", 98.0665),
    ("periodic", 'unit = "g"\namplitude = "3 m/s^2"', "amplitude", 3.0),
    ("periodic", 'tolerance = "1 percent"', "tolerance", 0.01),
    ("periodic", 'period = "2*pi/4 s"', "period", 3.141592653589793 / 2),
    ("periodic-expression", 'amplitude = "2 mm"', "amplitude", 2e-3),
    ("shock", 'amplitude = "100 g"', "amplitude", 980.665),
    ("shock", 'Q = "2*5"', "Q", 10.0),
    ("fatigue", 'k = "2*2"', "k", 4.0),
    ("fatigue", 'amplitude = "100 MPa"', "C", 1e6 * 1e8 ** 4),
    ("fatigue", 'cycles = "2*5e5"', "C", 1e6 * 1e8 ** 4),
    ("fatigue", 'duration = "2 min"', "duration", 120.0),
    ("random", 'band = ["20 Hz", "0.1 kHz"]', "band", (20.0, 100.0)),
    ("random", 'band = ["1200 rpm", "2*pi*100 rad/s"]', "band", (20.0, 100.0)),
    ("random", 'lines = "2*500"', "lines", 1000),
    ("random", 'tolerance = "1e-3*2"', "tolerance", 2e-3),
]


@pytest.mark.parametrize("section, keys, attribute, expected", VALUES)
def test_number_keys_take_units_and_arithmetic(section: str, keys: str, attribute: str,
                                               expected: object) -> None:
    model = _loaded(section, keys)
    spec = getattr(model, f"{section.split('-')[0]}_section")
    assert getattr(spec, attribute) == pytest.approx(expected, rel=1e-12)


def test_table_rows_take_frequencies_with_units() -> None:
    model = _loaded("random", 'band = [20, 2000]\n[random.psd.F]\n'
                    'values = [["20 Hz", 1], ["2 kHz", "2*0.5"]]')
    (spec,) = model.random_section.inputs
    assert spec.table.tolist() == [[20.0, 1.0], [2000.0, 1.0]]


def test_table_densities_take_a_unit_of_the_key_units_quantity() -> None:
    """A density in g^2/Hz or per rad/s in a table whose key unit is (m/s^2)^2/Hz:
    1 g^2/Hz = 9.80665^2 (m/s^2)^2/Hz, 1 per rad/s = 2 pi per Hz (to rounding, 1e-12)."""
    model = _loaded("random", 'band = [20, 2000]\n[random.psd.F]\nunit = "(m/s^2)^2/Hz"\n'
                    'values = [[20, "1 g^2/Hz"], [2000, "1 m^2/s^4/(rad/s)"]]')
    (spec,) = model.random_section.inputs
    assert spec.table[:, 1] == pytest.approx([9.80665 ** 2, 2 * math.pi], rel=1e-12)


# (section, keys as written, the message): a unit of another quantity names the key and
# the quantity expected; a parameter or another name is refused as such
REFUSED = [
    ("periodic", 'unit = "g"\namplitude = "3 kg"',
     "[periodic] amplitude: the unit kg is not one of acceleration (m/s^2); give it in m/s^2 "
     "or g, as the key unit says"),
    ("periodic", 'period = "2*pi/w"',
     "[periodic] period: 'w' is a parameter: these keys take numbers with units, not "
     "parameters"),
    ("periodic", 'tolerance = "1 s"',
     "[periodic] tolerance: the unit s is not one of a dimensionless quantity; give a number "
     "without a unit"),
    ("shock", 'Q = "10 Hz"', "[shock] Q: the unit Hz is not one of a dimensionless quantity"),
    ("shock", 'amplitude = "2*zz"', "[shock] amplitude: 'zz' is not a number"),
    ("shock", 'duration = "1/0 s"', "[shock] duration: '1/0 s' is not a finite number"),
    ("fatigue", 'amplitude = "100 m"', "[fatigue] amplitude: the unit m is not one of "
     "stress (Pa); give it in Pa, MPa or GPa"),
    ("fatigue", 'cycles = "1e6 s"', "[fatigue] cycles: the unit s is not one of a "
     "dimensionless quantity"),
    ("fatigue", 'k = "k"', "[fatigue] k: 'k' is a parameter"),
    ("random", 'band = ["20 Hz", "2 m"]', "[random] band: the unit m is not one of frequency "
     "(Hz); give it in Hz, kHz, rad/s or rpm"),
    ("random", 'band = [10, 100]\n[random.psd.F]\nvalues = [[10, "1 g^2/Hz"], [100, 1]]',
     r"\[random.psd.F\] values: '1 g\^2/Hz': a density with a unit needs the input's key "
     "unit"),
    ("random", 'band = [10, 100]\n[random.psd.F]\nunit = "g^2/Hz"\n'
     'values = [[10, "1 N^2/Hz"], [100, 1]]',
     r"\[random.psd.F\] values: '1 N\^2/Hz': a density of N, but the key unit is one of "
     r"m/s\^2; give it in a unit of that quantity"),
    ("random", 'band = [10, 100]\n[random.psd.F]\nvalues = "0.01 g^2/Hz"',
     r"\[random.psd.F\] values: '0.01 g\^2/Hz': a density takes no unit of its own"),
    ("random", 'band = [10, 100]\n[random.psd.F]\nvalues = [["10 s", 1], [100, 1]]',
     r"\[random.psd.F\] values: the unit s is not one of frequency"),
]


@pytest.mark.parametrize("section, keys, message", REFUSED)
def test_number_keys_refuse_other_quantities(section: str, keys: str, message: str) -> None:
    with pytest.raises(ModelError) as caught:
        _loaded(section, keys)
    pattern = message if message.startswith(r"\[") else message.replace("[", r"\[").replace(
        "]", r"\]").replace("(", r"\(").replace(")", r"\)").replace("^", r"\^")
    assert caught.value.problems and any(
        re.search(pattern, str(p)) for p in caught.value.problems), \
        [str(p) for p in caught.value.problems]


def test_an_amplitude_in_g_shows_accelerations_in_g() -> None:
    """``amplitude = "100 g"`` counts as an input given in g, like ``unit = "g"``."""
    assert _loaded("shock", 'amplitude = "100 g"').units.display["acceleration"].text == "g"
    assert _loaded("shock", "amplitude = 5").units is None


@settings(max_examples=40, deadline=None)
@given(st.floats(min_value=1e-6, max_value=1e3, allow_nan=False, allow_infinity=False))
def test_a_number_and_its_text_give_one_value(x: float) -> None:
    """Two routes, one answer: ``duration = x`` and ``duration = "x"`` bit for bit; and
    ``"x ms"`` is x / 1000 to rounding (1e-15)."""
    plain = _loaded("shock", f"duration = {x!r}\nstep = {x / 20!r}\namplitude = {x!r}")
    text = _loaded("shock", f'duration = "{x!r}"\nstep = {x / 20!r}\namplitude = "{x!r}"')
    milli = _loaded("shock", f'duration = "{x!r} ms"\nstep = "{x / 20!r} ms"')
    assert text.shock_section.duration == plain.shock_section.duration == x
    assert text.shock_section.amplitude == plain.shock_section.amplitude == x
    assert math.isclose(milli.shock_section.duration, x / 1000, rel_tol=1e-15)


def test_the_command_line_refuses_a_wrong_unit_with_exit_2(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(BASE + "[shock]\n" + SECTIONS["shock"].replace(
        "amplitude = 1", 'amplitude = "2*pi/w"'))
    status, _, err = run_cli(["check", str(path)])
    assert status == 2 and "Traceback" not in err
    assert "[shock] amplitude: 'w' is a parameter: these keys take numbers with units" in err


@pytest.mark.parametrize("written, speed", [
    ("6000 rpm", 200 * math.pi), ("2*3000 rpm", 200 * math.pi), ("100 rev/s", 200 * math.pi),
    ("2*pi*100 rad/s", 200 * math.pi), ("2*pi*100", 200 * math.pi),
])
def test_campbell_speeds_take_arithmetic_and_units(written: str, speed: float) -> None:
    """A speed is rad/s; rpm and rev/s hold their 2 pi (docs/units.md), to rounding."""
    text = ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nspeed = "W"\n'
            f'[campbell]\nto = "{written}"\n')
    assert loads(text).campbell_section.stop == pytest.approx(speed, rel=1e-12)


def test_a_campbell_speed_refuses_a_parameter() -> None:
    text = ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nspeed = "W"\n'
            '[campbell]\nto = "2*W"\n')
    with pytest.raises(ModelError, match=r"\[campbell\] to: 'W' is a parameter: these keys"):
        loads(text)
