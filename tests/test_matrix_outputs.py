"""Outputs (``[outputs]``) of ``[matrices]`` models: linearized for the linear analyses,
in full on the branches of the condensed harmonic balance (docs/model-format.md,
"Matrix models").

Two routes to one answer: the same system as a matrix model and as an energy model
(whose outputs go through Lagrange's equations and the full harmonic balance) gives
the same output amplitudes and phases.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import run_cli
from resonant import loads
from resonant.analyses.condensed import condensed_sweep
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.errors import ModelError
from resonant.system import nonlinear_system

MATRICES = '''
[parameters]
w = 0.5
k3 = 2
c1 = 0.04
[matrices]
M = [[1, 0], [0, 1]]
K = [[2, -1], [-1, 1]]
C = [["c1", 0], [0, 0.04]]
[[harmonic]]
omega = "w"
F_C = [0, 0.1]
[outputs]
spring = "k3*(q2 - q1)^3 + (q2 - q1)"
power = "c1*q1'*q1'"
accel = "q2''"
{nonlinear}
'''

ELEMENT = '''
[[nonlinear]]
name = "hardening"
coordinates = ["q2", "q1"]
force = "k3*(q2 - q1)^3"
'''

ENERGY = '''
[parameters]
w = 0.5
k3 = 2
c1 = 0.04
[coordinates]
q1 = ""
q2 = ""
[signals]
F = "0.1*cos(w*t)"
[energy]
T = "q1'^2/2 + q2'^2/2"
U = "q1^2/2 + (q2 - q1)^2/2 + {cubic}*(q2 - q1)^4/4"
D = "c1*q1'^2/2 + 0.04*q2'^2/2"
[[force]]
generalized = {{ q2 = "F" }}
[outputs]
spring = "k3*(q2 - q1)^3 + (q2 - q1)"
power = "c1*q1'*q1'"
accel = "q2''"
'''


def test_linear_outputs_of_a_matrix_model_equal_the_energy_model():
    """solve: amplitudes and phases of every output (linearized at rest: the cubic term
    drops, ``power`` is of second order so zero, ``accel`` = -w^2 q2) equal those of the
    same system given by its energies (1e-12 relative)."""
    matrix = loads(MATRICES.format(nonlinear="")).linearize().stationary()
    energy = loads(ENERGY.format(cubic="k3")).linearize().stationary()
    for name in ("q1", "q2", "spring", "power", "accel"):
        assert matrix.amplitudes[name] == pytest.approx(energy.amplitudes[name], rel=1e-12,
                                                        abs=1e-300)
    assert matrix.amplitudes["power"] == 0.0
    z = np.linalg.solve(np.array([[2, -1], [-1, 1]]) - 0.25 * np.eye(2)
                        + 0.5j * np.diag([0.04, 0.04]), [0.0, 0.1])
    assert matrix.amplitudes["spring"] == pytest.approx(abs(z[1] - z[0]), rel=1e-12)
    assert matrix.amplitudes["accel"] == pytest.approx(0.25 * abs(z[1]), rel=1e-12)


@settings(max_examples=25, deadline=None)
@given(a=st.floats(-3, 3).map(lambda v: round(v, 9)), b=st.floats(-3, 3).map(lambda v: round(v, 9)),
       c=st.floats(0.1, 4), w=st.floats(0.2, 2.5))
def test_linear_output_is_the_combination_of_the_coordinates(a, b, c, w):
    """A linear output a q1 + b q2' / c at any frequency: its complex amplitude is the
    same combination of the coordinates' (1e-12 of the largest term)."""
    text = MATRICES.format(nonlinear="").replace("w = 0.5", f"w = {w!r}").replace(
        'accel = "q2\'\'"', f'mix = "{a!r}*q1 + {b!r}*q2\'/{c!r}"')
    r = loads(text).linearize().stationary()
    z1, z2, zmix = (complex(L, -N) for L, N in (r.output_harmonics[name][0]
                                                 for name in ("q1", "q2", "mix")))
    expected = a * z1 + b * 1j * w * z2 / c
    scale = abs(a * z1) + abs(b * w * z2 / c) + 1e-300
    assert abs(zmix - expected) <= 1e-12 * scale


def test_condensed_branch_carries_the_outputs_in_full():
    """Condensed harmonic balance of the matrix model with a cubic spring against the full
    harmonic balance of the energy model: every output's amplitude (in full: the cubic
    term, the quadratic power, the acceleration) along the branch's ends, at the folds and
    at the outputs' peaks (1e-8 relative); the outputs' coordinates are recovered without
    being asked for."""
    H = 5
    condensed = condensed_sweep(nonlinear_system(loads(MATRICES.format(nonlinear=ELEMENT))), "w",
                                0.4, 2.2, harmonics=H, points=60, linear=False)
    full = nonlinear_sweep(nonlinear_system(loads(ENERGY.format(cubic="k3")).linearize()), "w",
                           0.4, 2.2, harmonics=H, points=60, linear=False)
    assert condensed.outputs == ("spring", "power", "accel")
    for name in ("q1", "q2", "spring", "power", "accel"):
        for end in (0, -1):
            assert condensed.amplitudes[name][end] == pytest.approx(
                full.amplitudes[name][end], rel=1e-8)
    for kind in ("fold", "peak"):
        mine = sorted((s for s in condensed.special_points if s.kind == kind),
                      key=lambda s: (s.value, str(s.quantity)))
        theirs = sorted((s for s in full.special_points if s.kind == kind),
                        key=lambda s: (s.value, str(s.quantity)))
        assert [s.quantity for s in mine] == [s.quantity for s in theirs]
        if kind == "peak":
            assert {s.quantity for s in mine} >= {"spring", "power", "accel"}
        for a, b in zip(mine, theirs):
            assert a.value == pytest.approx(b.value, rel=1e-8)
            for name in ("spring", "power", "accel"):
                assert a.amplitudes[name] == pytest.approx(b.amplitudes[name], rel=1e-8)
    assert condensed.output_coefficients is not None
    mine = condensed.output_coefficients[-1]
    theirs = full.output_coefficients[-1]
    assert np.allclose(mine, theirs, rtol=0, atol=1e-8 * np.abs(theirs).max())


def test_cli_json_has_the_outputs_on_every_branch_point(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(MATRICES.format(nonlinear=ELEMENT), encoding="utf-8")
    code, out, _ = run_cli(["sweep", str(path), "--param", "w", "--from", "0.4", "--to",
                            "1.0", "--points", "20", "--nonlinear", "--harmonics", "3",
                            "--json"])
    assert code == 0
    data = json.loads(out)
    assert all(set(p["amplitudes"]) == {"q1", "q2", "spring", "power", "accel"}
               for p in data["branch"])
    assert "spring" in data["branch"][0]["harmonics"]


@pytest.mark.parametrize("output, message", [
    ('x = "q3"', "unknown name 'q3'"),
    ('x = "abs(q1)"', "no first-order expansion"),
    ('x = "t*q1"', "time 't' may only appear in \\[signals\\]"),
])
def test_bad_outputs_of_a_matrix_model_are_named(output, message):
    text = ("[matrices]\nM = [[1, 0], [0, 1]]\nK = [[2, -1], [-1, 1]]\n"
            "[[harmonic]]\nomega = 1\nF_C = [0, 1]\n[outputs]\n" + output + "\n")
    with pytest.raises(ModelError, match=message) as info:
        loads(text).linearize().stationary()
    assert "[outputs]" in str(info.value) or "outputs" in str(info.value)


def test_a_third_rate_is_linear_but_not_on_a_branch():
    """A jerk (third rate) is a linear output, w^3 |z1|; the outputs in full on a branch
    read up to second rates, and the error says so."""
    text = MATRICES.format(nonlinear=ELEMENT).replace("accel = \"q2''\"",
                                                      "jerk = \"q1'''\"")
    eom = loads(text).linearize()
    r = eom.stationary()
    assert r.amplitudes["jerk"] == pytest.approx(0.125 * r.amplitudes["q1"], rel=1e-12)
    with pytest.raises(ModelError, match="up to the second rate") as info:
        condensed_sweep(nonlinear_system(eom), "w", 0.4, 0.6, harmonics=3, points=10,
                        linear=False)
    assert "[outputs] jerk" in str(info.value)


STRONG = '''
[parameters]
omega = 0.3
[matrices]
M = [[1, 0], [0, 1]]
K = [[2, -1], [-1, 1]]
C = [[0.05, 0], [0, 0.05]]
[[harmonic]]
omega = "omega"
F_C = [0, 1]
[[nonlinear]]
name = "cubic"
coordinates = ["q2"]
force = "0.1*q2^3"
[outputs]
stretch = "q2 - q1"
'''


def test_a_start_far_from_the_linear_response_is_reached_by_raising_the_loads():
    """At omega = 0.3 the cubic spring (q2 ~ 1.9, strong third harmonic) moves the response
    too far from the linear one for Newton's method: the start point is found with the
    loads raised step by step, and equals the point the branch reaches when it is followed
    there from omega = 0.05 (two routes; 1e-12 relative).  The linear sweep compared with
    the branch reports the outputs too (no warning but the truncation's: H = 7 given, as
    the automatic choice would take different H on the two ranges)."""
    system = nonlinear_system(loads(STRONG))
    direct = condensed_sweep(system, "omega", 0.3, 0.31, points=5, harmonics=7)
    followed = condensed_sweep(system, "omega", 0.05, 0.3, points=40, linear=False,
                               harmonics=7)
    assert followed.values[-1] == pytest.approx(0.3, abs=1e-14)
    for name in ("q1", "q2", "stretch"):
        assert direct.amplitudes[name][0] == pytest.approx(followed.amplitudes[name][-1],
                                                           rel=1e-12)
    assert direct.amplitudes["q2"][0] > 1.5
    assert not [w for w in direct.warnings if "highest harmonics" not in w]
    assert direct.linear is not None and "stretch" in direct.linear.amplitudes
