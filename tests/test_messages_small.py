"""One message per mistake (a misspelled section, a failed definition)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import run_cli

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

TYPO = """
[parameter]
m = 1
k = 100
[coordinates]
x = ""
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
"""

FAILED_DEFINITION = """
[parameters]
k = 100
[coordinates]
x = ""
[definitions]
ytip = "2*x + )"
yy = "ytip*3"
[energy]
T = "x'^2/2"
U = "k*x^2/2 + ytip^2 + yy^2"
"""


def test_misspelled_section_is_reported_once_with_a_suggestion(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(TYPO)
    code, _, err = run_cli(["check", path])
    assert code == 2
    assert "did you mean 'parameters'?" in err
    assert "unknown name" not in err  # no follow-on errors for m and k


def test_failed_definition_is_not_reported_again_as_unknown(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(FAILED_DEFINITION)
    code, _, err = run_cli(["check", path])
    assert code == 2 and "[definitions] ytip" in err
    assert "unknown name 'ytip'" not in err


NAMED_LIKE_MATRICES = """
[parameters]
M = 2          # a parameter called M (a mass), C (a damping), L (a length)
C = 0.5
L = 1
k = 50
omega = 3
[coordinates]
x = ""
[signals]
F = "sin(omega*t)"
[energy]
T = "M*x'^2/2"
U = "k*x^2/2 + 0*L"
D = "C*x'^2/2"
[[force]]
generalized = { x = "-F" }
"""


def test_text_output_headings_zeros_and_phases(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(NAMED_LIKE_MATRICES)
    code, out, _ = run_cli(["solve", path])
    assert code == 0
    for heading in ("mass matrix M =", "damping matrix C =", "stiffness matrix K =",
                    "cos coefficients L =", "sin coefficients N ="):
        assert heading in out
    assert "-0 " not in out and "-0]" not in out and "-0," not in out


def test_phases_lie_in_the_half_open_interval():
    """delta = atan2(L, N) in (-pi, pi]: an undamped system below resonance driven by a
    negative force has L = -0 and N < 0, i.e. delta = pi, never -pi."""
    import math

    from resonant.analyses.stationary import phase_angle
    from resonant.api import loads

    sol = loads(NAMED_LIKE_MATRICES.replace('D = "C*x\'^2/2"', "")).linearize().stationary()
    assert math.isclose(sol.phases["x"], math.pi)
    assert phase_angle(-0.0, -1.0) == math.pi and phase_angle(0.0, -1.0) == math.pi


def test_two_coordinates_give_modal_ratios_not_a_rayleigh_fit():
    """With two DOF any commuting C is a M + b K (e.g. a < 0): the text gives zeta_j."""
    from resonant.api import loads

    two = loads("""
[parameters]
m = 1
k = 100
[coordinates]
x1 = ""
x2 = ""
[energy]
T = "m*x1'^2/2 + m*x2'^2/2"
U = "k*x1^2/2 + k*(x2 - x1)^2/2"
D = "(1.9*x1'^2 - 2*x1'*x2' + 0.9*x2'^2)/2"   # C = -0.1 M + 0.01 K
""")
    result = two.linearize().modes()
    assert result.proportional_damping and result.rayleigh is not None
    text = result.summary()
    assert "Rayleigh" not in text and "zeta_1 = " in text and "zeta_2 = " in text


def test_two_frequency_report_shows_the_common_period(tmp_path):
    """sin(2t) + sin(3t) repeats after 2 pi, not after pi (two periods of the slower one)."""
    import math

    from resonant.api import loads
    from resonant.report.plots import time_history

    model = loads("""
[parameters]
k = 100
[coordinates]
x = ""
[signals]
F = "sin(2*t) + 0.5*sin(3*t)"
[energy]
T = "x'^2/2"
U = "k*x^2/2"
D = "x'^2/2"
[[force]]
generalized = { x = "F" }
""")
    history = time_history(model.linearize().stationary())
    assert history is not None and history.periodic
    assert math.isclose(history.period, 2 * math.pi) and math.isclose(history.t[-1], 4 * math.pi)


def test_report_writes_deviations_about_a_nonzero_reference(tmp_path):
    """A spring pendulum with static sag (r0 = l0 + m g/k)."""
    path = tmp_path / "sag.toml"
    path.write_text("""
[parameters]
m = 1
k = 100
g = 9.81
l0 = 0.5
c = 0.5
w = 5
[coordinates]
r = "length of the spring"
[equilibrium]
r = "l0 + m*g/k"
[signals]
F = "sin(w*t)"
[energy]
T = "m*r'^2/2"
U = "k*(r - l0)^2/2 - m*g*r"
D = "c*r'^2/2"
[[force]]
generalized = { r = "F" }
[outputs]
sag = "1000*(r - l0 - m*g/k)"
""")
    out = tmp_path / "sag.md"
    code, _, err = run_cli(["report", path, "-o", out, "--no-plots"])
    assert code == 0, err
    text = out.read_text()
    assert r"\Delta r_{\max} = X_{1}" in text and r"r_{\max} = X" not in text.replace(
        r"\Delta r_{\max}", "")
    assert r"\approx 1000 \Delta r" in text
    assert r"r_{0} = 0.5981" in text


def test_forced_report_shows_mode_shapes_and_modal_damping(tmp_path):
    """Mode shapes and modal damping ratios belong in the report."""
    from conftest import EXAMPLES

    out = tmp_path / "c3.md"
    code, _, err = run_cli(["report", EXAMPLES / "chain3_damped.toml", "-o", out, "--no-plots"])
    assert code == 0, err
    text = out.read_text()
    assert r"\mathbf{u}_{3} = " in text and r"\zeta_{1} = " in text


def test_report_frequency_response_includes_the_outputs():
    """The outputs' frequency responses belong in the report too."""
    from conftest import EXAMPLES

    from resonant.api import load
    from resonant.report.plots import frequency_response

    eom = load(EXAMPLES / "cart_pendulum.toml").linearize()
    frf = frequency_response(eom, eom.stationary())
    assert frf is not None and list(frf.amplitudes) == ["x1", "x2", "phi"]
    # phi = x2/l: its curve is x2's divided by l = 0.5
    import numpy as np
    np.testing.assert_allclose(frf.amplitudes["phi"], frf.amplitudes["x2"] / 0.5, rtol=1e-12)


def test_characteristic_polynomial_is_factored_where_that_is_shorter(tmp_path):
    """Two uncoupled oscillators: (k1 - m1 w^2)(k2 - m2 w^2) = 0."""
    path = tmp_path / "two.toml"
    path.write_text("""
[parameters]
m1 = 1
m2 = 2
k1 = 100
k2 = 300
[coordinates]
x1 = ""
x2 = ""
[energy]
T = "m1*x1'^2/2 + m2*x2'^2/2"
U = "k1*x1^2/2 + k2*x2^2/2"
""")
    out = tmp_path / "two.md"
    code, _, err = run_cli(["report", path, "-o", out, "--no-plots"])
    assert code == 0, err
    line = next(x for x in out.read_text().splitlines() if x.startswith(r"\det"))
    assert line.count(r"\right)") >= 3 and r"\omega_{n}^{4}" not in line


@pytest.mark.parametrize("argv, option", [
    (["sweep", "{m}", "--param", "omega", "--from", "0.5", "--to", "1.5", "--nonlinear",
      "--harmonics", "100000"], "--harmonics"),
    (["sweep", "{m}", "--param", "omega", "--from", "0.5", "--to", "1.5", "--tol", "nan"],
     "--tol"),
    (["sweep", "{m}", "--param", "omega", "--from", "0.5", "--to", "1.5", "--points", "-5"],
     "--points"),
    (["sweep", "{m}", "--param", "omega", "--from", "inf", "--to", "1.5"], "--from"),
    (["solve", "{m}", "--timeout", "nan"], "--timeout"),
    (["modes", "{m}", "--count", "0"], "--count"),
    (["modes", "{m}", "--nonlinear", "--points", "1"], "--points"),
    (["simulate", "{m}", "--duration", "-1"], "--duration"),
])
def test_invalid_option_values_are_invalid_input_naming_the_option(argv, option, capsys):
    """Every invalid value on the command line: exit 2, the message names the option."""
    from resonant.cli import main

    model = str(EXAMPLES / "duffing.toml")
    with pytest.raises(SystemExit) as exit_info:
        main([a.replace("{m}", model) for a in argv])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert f"argument {option}" in err and "Traceback" not in err


def test_a_value_beyond_double_precision_is_an_analysis_error():
    """``sweep("omega", [10**400])`` raised OverflowError; it is an AnalysisError."""
    from resonant.api import load
    from resonant.errors import AnalysisError

    system = load(EXAMPLES / "duffing.toml").linearize()
    with pytest.raises(AnalysisError, match="finite numbers"):
        system.sweep("omega", [10**400])


def _chain(first: str, step: str, count: int) -> str:
    return ("[parameters]\na0 = " + first + "\n"
            + "".join(f'a{i} = "a{i - 1}{step}"\n' for i in range(1, count))
            + '[coordinates]\nx = ""\n[energy]\nT = "x\'^2/2"\n'
            + f'U = "a{count - 1}*x^2/2 + x^2/2"\n')


def test_a_long_parameter_chain_continues_in_floating_point():
    """Exact rationals that outgrow the exact limit (a chain of 200 parameters of about
    0.01, each from the one before) become 30-digit floats instead of an error; the
    last value equals the recurrence evaluated with Python's fractions (rel 1e-15)."""
    from fractions import Fraction

    from resonant.api import loads

    model = loads(_chain("0.01", "*1.01 + 0.0003", 200))
    value = Fraction(1, 100)
    for _ in range(199):
        value = value * Fraction(101, 100) + Fraction(3, 10_000)
    assert model.parameter_values["a199"] == pytest.approx(float(value), rel=1e-15)


def test_an_invalid_parameter_is_one_line_with_the_count_of_its_dependents():
    """A parameter chain whose value underflows: one line for the root cause, one for the
    160 parameters that depend on it (not one line each)."""
    from resonant.api import loads
    from resonant.errors import ModelError

    with pytest.raises(ModelError) as info:
        loads(_chain("1e-200", "*1e-200", 162))
    lines = str(info.value).splitlines()
    assert len(lines) == 2, lines
    assert "[parameters] a1: number too small" in lines[0]
    assert "[parameters] a1: and 160 parameters that depend on it: a2, a3" in lines[1]
