"""`simulate` compares like with like.

A pendulum hung from a block on a spring, the pendulum mode nearly undamped
(zeta ~ 1e-5), driven harmonically: started from rest, the transient has not decayed
in any reasonable run, so the difference to the stationary solution is the transient,
not the nonlinearity; the default nonlinear run starts on the periodic solution instead.
"""

from __future__ import annotations

from resonant.api import loads

BLOCK_PENDULUM = """
[parameters]
M = 200
m = 0.5
l = 0.4
k = 30000
c = 20
cp = 2e-5
g = 9.81
F0 = 50
w = 8
[coordinates]
x = "block"
th = "pendulum angle"
[signals]
F = "F0*sin(w*t)"
[definitions]
xp = "x + l*sin(th)"
yp = "-l*cos(th)"
[energy]
T = "M*x'^2/2 + m*(xp'^2 + yp'^2)/2"
U = "k*x^2/2 + m*g*yp"
D = "c*x'^2/2 + cp*th'^2/2"
[[force]]
generalized = { x = "F" }
"""


def test_a_transient_is_not_blamed_on_the_nonlinearity():
    sim = loads(BLOCK_PENDULUM).simulate(duration=20.0, nonlinear=True, start="rest")
    text = " ".join(sim.warnings)
    assert "has not settled" in text and "settling takes about" in text
    assert "small oscillations do not hold" not in text


def test_default_nonlinear_run_starts_on_the_periodic_solution():
    sim = loads(BLOCK_PENDULUM).simulate(nonlinear=True)
    assert sim.start == "periodic"
    assert all(abs(d) < 0.05 for d in sim.relative_difference.values())
    assert not any("small oscillations do not hold" in w for w in sim.warnings)
