"""Untrusted input (docs/security.md): limits on every command, exit codes and one-line
messages instead of internal errors, and no terminal injection from a model file.

Heavy cases run in a subprocess under ``RLIMIT_AS`` (a memory bound) and a wall-clock
bound; the others through ``resonant.cli.main`` in-process (``run_cli``).
"""

from __future__ import annotations

import os
import textwrap
import time
from pathlib import Path

import pytest

from conftest import EXAMPLES, run_cli
from limited_runner import run_resonant
from resonant.analyses import stationary as stationary_module
from resonant.analyses import sweep as sweep_module
from resonant.analyses import time_integration
from resonant.api import loads
from resonant.errors import ModelError, Problem, name_list, printable
from resonant.model import limits

CHAIN = EXAMPLES / "chain3_damped.toml"
MEMORY = 1500 * 2**20  # bytes of address space for a heavy subprocess


def run_limited(args: list[str], seconds: float = 90, memory: int = MEMORY
                ) -> tuple[int, str, str, float]:
    """``resonant ARGS`` in a child process under RLIMIT_AS (tests/limited_runner.py);
    (status, stdout, stderr, seconds)."""
    started = time.monotonic()
    proc = run_resonant(list(map(str, args)), memory=memory, timeout=seconds,
                        env={**os.environ, "PYTHONWARNINGS": ""})
    return proc.returncode, proc.stdout, proc.stderr, time.monotonic() - started


def write(tmp_path: Path, text: str, name: str = "m.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


OSCILLATOR = """
[parameters]
m = 1
k = 1
c = 0.1
[coordinates]
x = ""
[signals]
F = "{signal}"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
name = "F"
generalized = {{ x = "F" }}
{extra}
"""

STIFF = """
[parameters]
m = 1
k1 = 1
k2 = 1e8
c = 0.1
[coordinates]
x1 = ""
x2 = ""
[signals]
F = "sin(t)"
[energy]
T = "m*(x1'^2 + x2'^2)/2"
U = "k1*x1^2/2 + k2*(x2-x1)^2/2"
D = "c*(x1'^2+x2'^2)/2"
[[force]]
name = "F"
generalized = { x1 = "F" }
"""


def oscillator(tmp_path: Path, signal: str = "sin(2*t)", extra: str = "") -> Path:
    return write(tmp_path, OSCILLATOR.format(signal=signal, extra=extra))


def one_line(err: str) -> None:
    assert "internal error" not in err and "Traceback" not in err, err
    assert "\x1b" not in err


# -- 1. simulate -------------------------------------------------------------------------------

def test_simulate_absurd_duration_is_refused_up_front():
    started = time.monotonic()
    status, _, err = run_cli(["simulate", CHAIN, "--duration", "1e12"])
    assert status == 3 and "limited to 1e+06 periods" in err and "--duration" in err
    assert time.monotonic() - started < 20
    one_line(err)


def test_simulate_step_budget_gives_exit_3_with_the_time_reached(monkeypatch):
    monkeypatch.setattr(time_integration, "MAX_RHS_CALLS", 20_000)  # the integration budget
    started = time.monotonic()
    status, _, err = run_cli(["simulate", CHAIN, "--duration", "1e5"])
    assert status == 3, err
    assert "stopped at t = " in err and "evaluations" in err and "shorter --duration" in err
    assert time.monotonic() - started < 30


def test_simulate_stiff_explicit_method_falls_back_to_implicit(tmp_path):
    path = write(tmp_path, STIFF)
    status, _, err, seconds = run_limited(["simulate", path, "--method", "DOP853",
                                           "--duration", "300"])
    assert status == 0, err
    assert "stiff" in err and "LSODA" in err
    assert seconds < 60


def test_simulate_huge_initial_value(tmp_path):
    status, _, err = run_cli(["simulate", CHAIN, "--initial", "x1=1e300"])
    assert status == 2 and "--initial x1" in err and "at most 1e+100" in err
    one_line(err)


def test_simulate_initial_with_a_primed_parameter_is_refused():
    status, _, err = run_cli(["simulate", CHAIN, "--initial", "x1=k'"])
    assert status == 2 and "k' is the time derivative of a parameter" in err


def test_parameter_with_a_prime_is_refused():
    with pytest.raises(ModelError, match="time derivative of a parameter"):
        loads('[parameters]\nm = 1\nk = "m\'"\n[coordinates]\nx = ""\n'
              '[energy]\nT = "m*x\'^2/2"\nU = "k*x^2/2"')


@pytest.mark.parametrize("nonlinear", [False, True])
def test_simulate_signal_undefined_at_t0(tmp_path, nonlinear):
    path = oscillator(tmp_path, "1/t", '[outputs]\ns = "F"')
    status, _, err = run_cli(["simulate", path, *(["--nonlinear"] if nonlinear else [])])
    assert status == 3 and "cannot be evaluated" in err and "t = 0" in err
    one_line(err)


def test_simulate_output_that_is_a_signal_nonlinear(tmp_path):
    path = oscillator(tmp_path, "sin(2*t)", '[outputs]\ns = "F"')
    status, out, err = run_cli(["simulate", path, "--nonlinear", "--duration", "20"])
    assert status == 0, err
    assert "s " in out


# -- 2. sweep ------------------------------------------------------------------------------------

def test_sweep_points_are_bounded():
    status, _, err, seconds = run_limited(["sweep", CHAIN, "--param", "omega", "--from", "1",
                                           "--to", "2", "--points", "3000000"])
    # refused where the option is parsed: invalid input (exit 2), the option named
    assert status == 2 and "--points" in err and str(sweep_module.MAX_SWEEP_POINTS) in err
    assert seconds < 30


def test_sweep_results_are_bounded(monkeypatch):
    monkeypatch.setattr(sweep_module, "MAX_SWEEP_RESULTS", 100)
    status, _, err = run_cli(["sweep", CHAIN, "--param", "omega", "--from", "1", "--to", "2",
                              "--points", "50"])
    assert status == 3 and "reported quantities" in err and "--only" in err


def test_sweep_overflowing_frequencies():
    status, _, err = run_cli(["sweep", CHAIN, "--param", "omega", "--from", "1e200",
                              "--to", "1e201"])
    assert status == 3 and "numerical overflow" in err
    one_line(err)


def test_peak_of_several_frequencies_is_cheap_and_accurate():
    started = time.monotonic()
    value = stationary_module.peak([1.0, 83_400.0], ((0.3, 0.4), (0.01, 0.02)))
    assert time.monotonic() - started < 1.0
    assert value == pytest.approx(0.5 + 0.02236068, rel=1e-6)


# -- 3. model size -------------------------------------------------------------------------------

def test_too_many_parameters_refused_quickly():
    n = limits.MAX_PARAMETERS + 1
    text = ("[parameters]\n" + "\n".join(f"p{i} = {i}" for i in range(n))
            + '\n[coordinates]\nx = ""\n[energy]\nT = "x\'^2/2"\nU = "p1*x^2/2"\n')
    started = time.monotonic()
    with pytest.raises(ModelError, match=f"limited to {limits.MAX_PARAMETERS}"):
        loads(text)
    assert time.monotonic() - started < 5


def test_too_many_outputs_refused(tmp_path):
    outputs = "\n".join(f"y{i} = \"x\"" for i in range(limits.MAX_OUTPUTS + 1))
    path = oscillator(tmp_path, extra="[outputs]\n" + outputs)
    status, _, err = run_cli(["solve", path])
    assert status == 2 and "[outputs]" in err and f"limited to {limits.MAX_OUTPUTS}" in err


# -- 4. internal errors become exit 2/3 ----------------------------------------------------------

@pytest.mark.parametrize("command", ["solve", "simulate"])
def test_huge_integer_in_a_signal(tmp_path, command):
    path = oscillator(tmp_path, "cos(2*t + 123456789012345678901234567)")
    status, _, err = run_cli([command, path, "--json",
                              *(["--duration", "20"] if command == "simulate" else [])])
    assert status == 0, err
    one_line(err)


def test_parameter_beyond_any_precision(tmp_path):
    path = write(tmp_path, '[parameters]\nm = 1\nk = "exp(cosh(1e300))"\n[coordinates]\n'
                           'x = ""\n[energy]\nT = "m*x\'^2/2"\nU = "k*x^2/2"\n')
    status, _, err = run_cli(["solve", path])
    assert status == 2 and "[parameters] k" in err and "not a finite number" in err


def test_overflowing_output_coefficient(tmp_path):
    path = oscillator(tmp_path, extra='[outputs]\ny = "((1e299)^2)^2*x"')
    status, _, err = run_cli(["solve", path])
    assert status == 2 and "not finite" in err
    one_line(err)


def test_report_into_a_missing_folder():
    status, _, err = run_cli(["report", CHAIN, "-o", "/nonexistent/r.md"])
    assert status == 2 and "cannot write the report" in err and "does not exist" in err


def test_loads_none():
    with pytest.raises(ModelError, match="text"):
        loads(None)  # type: ignore[arg-type]


# -- 5. Python warnings --------------------------------------------------------------------------

def test_python_warnings_are_resonants_own(tmp_path):
    import warnings

    from resonant.cli import python_warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.warn_explicit("overflow encountered in matmul", RuntimeWarning,
                               "/x/numpy/linalg.py", 12)
        warnings.warn_explicit("overflow encountered in matmul", RuntimeWarning,
                               "/x/numpy/linalg.py", 12)
    assert python_warnings(caught) == [
        "numerical overflow in matmul (numpy): results may be inaccurate"]


def test_no_python_warning_lines_reach_the_terminal(tmp_path):
    path = oscillator(tmp_path, "1e299*sin(2*t)", '[outputs]\ny = "1e299*x"')
    for command in (["solve", "--json"], ["modes"], ["simulate", "--duration", "5"],
                    ["sweep", "--param", "k", "--from", "1", "--to", "2", "--points", "5"]):
        status, out, err = run_cli([command[0], path, *command[1:]])
        assert "Warning:" not in err and ".py:" not in err, (command, err)
        one_line(err)


# -- 6. terminal injection -----------------------------------------------------------------------

def test_printable_escapes_controls_bidi_and_shortens():
    assert printable("\x1b[2K\rvalid model") == "\\x1b[2K\\rvalid model"
    assert printable("a\u202eb\u2066c\x85\x7f") == "a\\u202eb\\u2066c\\x85\\x7f"
    assert printable("é ü 漢") == "é ü 漢"
    assert printable("x" * 1000, limit=20).endswith("...")
    assert len(printable("x" * 1000, limit=20)) == 20
    assert name_list([f"x{i}" for i in range(12)]) == "x0, x1, x2, x3, x4 ... and 7 more"


def test_problem_location_is_escaped():
    text = str(Problem("bad", "f\x1b.toml", "parameters", "\x1b[2K\rvalid model"))
    assert "\x1b" not in text and "\r" not in text and "\\x1b[2K\\rvalid model" in text


def test_name_with_escape_codes_cannot_erase_the_error(tmp_path):
    path = write(tmp_path, '[parameters]\nm = 1\n"\\u001b[2K\\rvalid model" = 1\n'
                           '[coordinates]\nx = ""\n[energy]\nT = "m*x\'^2/2"\nU = "x^2/2"\n')
    status, _, err = run_cli(["solve", path])
    assert status == 2 and "\\x1b[2K\\rvalid model" in err
    assert "\x1b" not in err and "\r" not in err


def test_title_with_escape_codes_and_bidi(tmp_path):
    path = oscillator(tmp_path, extra="")
    text = path.read_text()
    path.write_text('title = "\\u001b[31mRED\\u001b[0m \\u202e"\n' + text)
    status, out, err = run_cli(["modes", path])
    assert status == 0, err
    assert "\x1b" not in out and "\u202e" not in out and "\\x1b[31mRED" in out
    report = tmp_path / "r.html"
    status, _, err = run_cli(["report", path, "-o", report, "--no-plots"])
    assert status == 0, err
    html = report.read_text()
    assert "\x1b" not in html and "\u202e" not in html


# -- 7. negative mass matrix ---------------------------------------------------------------------

NEGATIVE_MASS = """
[matrices]
M = [[-1, 0], [0, -1]]
K = [[2, -1], [-1, 2]]
[[harmonic]]
omega = 0.5
F_S = [1, 0]
"""


@pytest.mark.parametrize("command", ["solve", "modes"])
def test_negative_mass_matrix_is_named(tmp_path, command):
    path = write(tmp_path, NEGATIVE_MASS)
    status, _, err = run_cli([command, path, "--json"])
    assert status == 0
    assert "the mass matrix M is negative definite" in err
    assert "K is not positive definite" not in err


def test_subnormal_mass_is_a_clean_analysis_error(tmp_path):
    """Found by fuzz campaign 2 (seed 2027, docs/fuzzing.md): M = 1e-320 I from a .npy made the
    equilibration overflow (2^1063) and the SVD fail (internal error); now exit 3."""
    import numpy as np

    np.save(tmp_path / "M.npy", np.eye(3) * 1e-320)
    (tmp_path / "m.toml").write_text('[parameters]\nw = 3\n[matrices]\nM = "M.npy"\n'
                                     'K = [[2, -1, 0], [-1, 2, -1], [0, -1, 2]]\n'
                                     '[[harmonic]]\nomega = "w"\nF_S = [1, 0, 0]\n')
    code, _, err = run_cli(["solve", tmp_path / "m.toml"])
    assert code == 3 and "internal error" not in err


#: the subcommands that read no model file (a bundled example's name; a key and answers)
#: ``import`` reads FE files and writes the model (docs/interop.md): no model to set or time yet
NO_MODEL_COMMANDS = {"example", "grade", "import"}


def test_every_command_of_a_model_takes_the_common_options():
    """Every subcommand that reads a model (or a history) takes --timeout, --allow-path,
    --units and --set (docs/security.md): ``srs`` took none of them."""
    import argparse

    from resonant.cli import COMMANDS, build_parser

    (sub,) = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
    assert set(sub.choices) == set(COMMANDS)
    for name, parser in sub.choices.items():
        if name in NO_MODEL_COMMANDS:
            continue
        options = {o for action in parser._actions for o in action.option_strings}
        missing = {"--timeout", "--allow-path", "--units", "--set"} - options
        assert not missing, f"resonant {name} lacks {sorted(missing)}"


def test_srs_keeps_its_time_limit(tmp_path):
    """``resonant srs MODEL --output NAME`` ran 27 s with no limit: now --timeout holds."""
    path = tmp_path / "m.toml"
    # (the SRS is of an acceleration: x1'' as an output; x1 itself is refused, exit 2)
    path.write_text(CHAIN.read_text() + '\n[shock]\nsignal = "F"\npulse = "half-sine"\n'
                    "amplitude = 1\nduration = 0.01\nstep = 1e-6\ntotal = 2\n")
    text = path.read_text()
    path.write_text(text.replace("[outputs]\n", "[outputs]\na1 = \"x1''\"\n") if "[outputs]"
                    in text else text + "\n[outputs]\na1 = \"x1''\"\n")
    started = time.perf_counter()
    code, _, err = run_cli(["srs", str(path), "--output", "a1", "--timeout", "1"])
    assert code == 3 and "time limit" in err, err
    assert time.perf_counter() - started < 20
