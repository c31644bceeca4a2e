"""A swept parameter that is not the excitation frequency is
labelled as itself; antiresonances are true zeros; undamped peaks are said to be unbounded.

Models of our own: a quarter-car on a road of wavelength lam driven at speed v
(omega = 2 pi v / lam), a machine driven at f Hz (omega = 2 pi f), an undamped absorber.
"""

from __future__ import annotations

import math

import numpy as np

from resonant.api import loads

ROAD = """
[parameters]
m = 250
k = 16000
c = 1000
lam = 5          # m, wavelength of the road
v = 10           # m/s
h = 0.01         # m, road amplitude
omega = "2*pi*v/lam"
[coordinates]
z = "vertical displacement of the body"
[signals]
r = "h*sin(omega*t)"
[energy]
T = "m*z'^2/2"
U = "k*(z - r)^2/2"
D = "c*(z' - r')^2/2"
"""

HZ = """
[parameters]
m = 1
k = 3947.8417604357433   # (2 pi 10)^2: natural frequency 10 Hz
c = 2
f = 5
[coordinates]
x = ""
[signals]
F = "sin(2*pi*f*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
generalized = { x = "F" }
"""

ABSORBER = """
[parameters]
m1 = 10
k1 = 4000
m2 = 1
k2 = 400
omega = 10
[coordinates]
x1 = "main mass"
x2 = "absorber"
[signals]
F = "10*sin(omega*t)"
[energy]
T = "m1*x1'^2/2 + m2*x2'^2/2"
U = "k1*x1^2/2 + k2*(x2 - x1)^2/2"
[[force]]
generalized = { x1 = "F" }
"""


def test_speed_sweep_is_not_labelled_as_a_frequency():
    result = loads(ROAD).linearize().sweep("v", np.linspace(1, 40, 391))
    wn = math.sqrt(16000 / 250)
    assert not result.frequency_sweep and result.unit == ""
    assert math.isclose(result.frequency_scale, 2 * math.pi / 5, rel_tol=1e-12)
    np.testing.assert_allclose(result.natural_values, [wn * 5 / (2 * math.pi)], rtol=1e-12)
    text = result.summary()
    assert "rad/s" not in text.split("\n")[1]
    assert "the excitation meets a natural frequency at v = 6.3662" in text
    assert "natural frequencies in range" not in text
    # the resonance peak of the body lies near the speed where omega = wn
    assert any(abs(p.value - 6.37) < 0.6 for p in result.peaks if p.name == "z")
    fig = result.plot()
    assert fig.axes[-1].get_xlabel() == "$v$"


def test_frequency_in_hz_is_labelled_hz():
    result = loads(HZ).linearize().sweep("f", np.linspace(1, 20, 191))
    assert result.unit == "Hz" and not result.frequency_sweep
    np.testing.assert_allclose(result.natural_values, [10.0], rtol=1e-12)
    assert result.to_dict()["natural_values"] == [result.natural_values[0]]


def test_omega_sweep_keeps_rad_per_second():
    result = loads(HZ.replace('"sin(2*pi*f*t)"', '"sin(w*t)"').replace("f = 5", "w = 5")
                   ).linearize().sweep("w", np.linspace(10, 100, 10))
    assert result.frequency_sweep and result.unit == "rad/s"


def test_minimum_between_peaks_is_not_an_antiresonance():
    """A damped absorber has a dip, not a zero, between its two peaks."""
    damped = ABSORBER.replace('U = "k1', 'D = "0.5*(x2\' - x1\')^2"\nU = "k1')
    result = loads(damped).linearize().sweep("omega", np.linspace(5, 40, 351))
    assert len([p for p in result.peaks if p.name == "x1"]) == 2
    assert result.antiresonances == ()


def test_true_zero_is_an_antiresonance_drawn_at_the_floor():
    result = loads(ABSORBER).linearize().sweep("omega", np.linspace(5, 40, 351))
    zeros = [p for p in result.antiresonances if p.name == "x1"]
    assert len(zeros) == 1 and math.isclose(zeros[0].value, 20.0, rel_tol=1e-9)
    assert zeros[0].amplitude < 1e-12
    # the undamped peaks are said to be unbounded
    assert any("no damping" in w and "unbounded" in w for w in result.warnings)
    fig = result.plot(names=["x1"])
    low, high = fig.axes[0].get_ylim()
    sampled = result.amplitudes["x1"]
    assert low > 1e-6 * high  # not stretched to the 1e-19 of the exact zero
    assert low <= np.nanmin(sampled[sampled > 1e-9 * np.nanmax(sampled)])
