"""Units and arithmetic in the keys of a physical quantity, as ``[parameters]`` takes them
(model/study.py ``srs:NAME@f``, model/load_spec.py ``quantity_value``).

References: the unit conversions themselves (0.1 kHz = 100 Hz, 2 pi 50 rad/s = 50 Hz,
41.4 ms = 0.0414 s, 11 ms = 0.011 s: exact or to rounding, 1e-12); a unit of another
quantity is a problem naming the file, the section and the key.
"""

from __future__ import annotations

import pytest

import resonant
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
