"""Hostile input to the loads: ``[random]``, ``[shock]``, ``[periodic]``, ``[fatigue]``, CSV
histories and the command line of ``resonant srs`` and ``resonant random``.

Each case used to end in an internal error (exit 1), a misleading message, a silently
wrong result or a hang (the "before" of each entry); each must end as docs/errors.md says:
exit 2 (invalid input) or 3 (analysis impossible), one message naming the file, the
section and the key, never a traceback, quickly and in bounded memory.  What
tests/test_fuzz.py and tests/test_security_files.py cover (mutated examples, matrix and
vector files) is not repeated here.
"""

from __future__ import annotations

import math
import os
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import run_cli
from resonant.errors import ModelError, Problem
from resonant.model import time_series
from resonant.model.random_spec import parse_random

SRC = str(Path(__file__).resolve().parents[1] / "src")
#: a TOML whole number beyond the floating-point range (tomllib reads it as a Python int)
HUGE = "1" + "0" * 400

SDOF = """
title = "sdof"
[parameters]
m = 1
k = 1000
c = 2
y0 = 0
[coordinates]
x = "x"
[signals]
y = "y0"
[energy]
T = "m*x'^2/2"
U = "k*(x - y)^2/2"
D = "c*(x' - y')^2/2"
[outputs]
z = "x - y"
"""
TWO_INPUTS = 'band = [1, 100]\n[random.psd.y]\nvalues = 1\n[random.psd.x]\nvalues = 1\n' \
             '[[random.coherence]]\ninputs = ["y", "x"]\nvalue = 0.5\n'
SHOCK = 'signal = "y"\nderivative = 2\npulse = "half-sine"\namplitude = 10\nduration = 0.01\n'
SQUARE = 'signal = "y"\nshape = "square"\namplitude = 1\n'
FATIGUE_HEAD = '[random]\nband = [1, 100]\n[random.psd.y]\nvalues = 1\n[fatigue]\n'


def _check(code: int, err: str, status: int, words: tuple[str, ...]) -> None:
    assert code == status, err
    assert "Traceback" not in err and "internal error" not in err, err
    assert "warning:" not in err, err   # no numpy overflow leaks into the terminal
    for word in words:
        assert word in err, err


# before -> after, per entry: (section text, command, exit, words of the message)
RANDOM_CASES = {
    # OverflowError: int too large to convert to float
    "table-huge-integer": (f"[random.psd.y]\nvalues = [[1, 1], [100, {HUGE}]]", 2,
                           ("[random.psd.y] values", "positive numbers")),
    "table-huge-frequency": (f"[random.psd.y]\nvalues = [[1, 1], [{HUGE}, 1]]", 2,
                             ("[random.psd.y] values",)),
    "band-huge-integer": (f"band = [1, {HUGE}]\n[random.psd.y]\nvalues = 1", 2,
                          ("[random] band", "finite")),
    # 1e307 g^2/Hz is infinite in SI: NaN in the quadrature, internal error
    "table-overflows-in-si": ('[random.psd.y]\nderivative = 2\nunit = "g^2/Hz"\n'
                              'values = [[1, 1e307], [100, 1e307]]', 2,
                              ("[random.psd.y] values", "floating-point range")),
    # a TOML true was read as the density 1
    "table-bool": ("[random.psd.y]\nvalues = [[1, true], [100, 1]]", 2,
                   ("[random.psd.y] values", "numbers")),
    # expressions: internal errors (math domain error, zero-size array to reduction)
    "expression-infinite": ('band = [1, 1000]\n[random.psd.y]\nvalues = "exp(f)"', 2,
                            ("[random.psd.y] values", "not finite at")),
    "expression-negative": ('band = [1, 100]\n[random.psd.y]\nvalues = "-1"', 2,
                            ("[random.psd.y] values", "negative at 1 Hz")),
    "expression-pole": ('band = [1, 100]\n[random.psd.y]\nvalues = "1/(f - 50)"', 2,
                        ("[random.psd.y] values", "density is")),
    "expression-nan": ('band = [1, 100]\n[random.psd.y]\nvalues = "sqrt(50 - f)"', 2,
                       ("[random.psd.y] values", "not finite at")),
    "expression-log": ('band = [1, 100]\n[random.psd.y]\nvalues = "log(f - 50)"', 2,
                       ("[random.psd.y] values",)),
    # an input's name went unchecked into the report's LaTeX (\\input{...}), its Markdown
    # (raw HTML) and the terminal (escape sequences), and was printed whole
    "name-latex": ('band = [1, 100]\n[random.psd."W}\\\\input{/etc/passwd}"]\nload = [1]\n'
                   'values = 1', 2, ("[random.psd]", "is not a valid name")),
    "name-html": ('band = [1, 100]\n[random.psd."<img src=x onerror=alert(1)>"]\nload = [1]\n'
                  'values = 1', 2, ("[random.psd]", "is not a valid name")),
    "name-escapes": ('band = [1, 100]\n[random.psd."\\u001b[2J\\u202eW"]\nload = [1]\n'
                     'values = 1', 2, ("[random.psd] \\x1b[2J\\u202eW", "is not a valid name")),
    "name-long": (f'band = [1, 100]\n[random.psd.{"W" * 500}]\nload = [1]\nvalues = 1', 2,
                  ("[random.psd] WWW", "name too long (500 characters")),
    "name-reserved": ('band = [1, 100]\n[random.psd.sin]\nload = [1]\nvalues = 1', 2,
                      ("[random.psd] sin", "'sin' is reserved")),
    # densities (or load and base vectors) whose responses overflow: an internal error
    # ("zero-size array to reduction operation maximum") or RMS values with numpy warnings
    "density-overflows-response": ("band = [1, 100]\n[random.psd.y]\nvalues = 1e300", 2,
                                   ("[random.psd] y", "floating-point range")),
    "load-overflows-response": ('band = [1, 100]\n[random.psd.W]\nload = ["1e300"]\n'
                                'values = 1', 2, ("[random.psd] W", "floating-point range")),
    "base-overflows-response": ('band = [1, 100]\n[random.psd.W]\nbase = ["1e200"]\n'
                                'values = 1', 2, ("[random.psd] W", "floating-point range")),
    # a frequency beyond the dynamic stiffness' range was called "an undamped resonance"
    "band-beyond-the-frequency-range": ("band = [0, 1e300]\n[random.psd.y]\nvalues = 1", 2,
                                        ("[random] band", "above 1e+15 Hz")),
    "table-beyond-the-frequency-range": ("[random.psd.y]\nvalues = [[1, 1], [1e308, 1]]", 2,
                                         ("[random] band", "the tables' span")),
    # a time derivative was read as a zero: RMS 0 with status ok
    "density-primed-f": ('band = [1, 100]\n[random.psd.y]\nvalues = "f\'"', 2,
                         ("[random.psd.y] values", "f': a time derivative")),
    "density-primed-parameter": ('band = [1, 100]\n[random.psd.y]\nvalues = "k\'"', 2,
                                 ("[random.psd.y] values", "k': a time derivative")),
    "load-primed": ('band = [1, 100]\n[random.psd.W]\nload = ["k\'"]\nvalues = 1', 2,
                    ("[random.psd.W] load", "k': a time derivative")),
    "coherence-primed": (TWO_INPUTS.replace("value = 0.5", "value = \"c'\""), 2,
                         ("[random.coherence] #1", "c': a time derivative")),
    # "30 furlongs" was taken as a phase of 6035 rad
    "phase-not-an-angle": (TWO_INPUTS + 'phase = "30 furlongs"', 2,
                           ("[random.coherence] #1", "not an angle")),
    # NaN in the cross density: internal error
    "phase-infinite": (TWO_INPUTS + 'phase = "1/0"', 2,
                       ("[random.coherence]", "phase of y and x is not a finite")),
    # a load vector that is not finite was called "an undamped resonance" (exit 3)
    "load-vector-infinite": ('band = [1, 100]\n[random.psd.W]\nunit = "N^2/Hz"\n'
                             'load = ["1/0"]\nvalues = 1', 2,
                             ("[random.psd.W] load", "entry 1 (coordinate x) is inf")),
    "base-vector-infinite": ('band = [1, 100]\n[random.psd.W]\nunit = "(m/s^2)^2/Hz"\n'
                             'base = ["exp(1000)"]\nvalues = 1', 2,
                             ("[random.psd.W] base", "finite numbers")),
    # "m^2/rad" (per radian) was taken as a density per rad/s
    "unit-per-radian": ('[random.psd.y]\nunit = "m^2/rad"\nvalues = [[1, 1], [100, 1]]', 2,
                        ("[random.psd.y] unit", "not a density per frequency")),
    # already right: kept as regressions of the table's checks
    "table-unsorted": ("[random.psd.y]\nvalues = [[100, 1.0], [1, 1.0]]", 2, ("increase",)),
    "table-duplicate": ("[random.psd.y]\nvalues = [[1, 1], [1, 1], [100, 1]]", 2,
                        ("increase",)),
    "table-one-row": ("[random.psd.y]\nvalues = [[1, 1.0]]", 2, ("at least two",)),
    "table-nan": ("[random.psd.y]\nvalues = [[1, nan], [100, 1.0]]", 2, ("positive",)),
    "table-zero-frequency": ("[random.psd.y]\nvalues = [[0, 1], [100, 1]]", 2, ("positive",)),
    "unit-garbage": ('[random.psd.y]\nunit = "((("\nvalues = [[1, 1], [100, 1]]', 2,
                     ("[random.psd.y] unit",)),
    "coherence-above-one": (TWO_INPUTS.replace("value = 0.5", 'value = "f"'), 2,
                            ("[random.coherence]", "[0, 1]")),
    "coherence-unknown-input": ('band = [1, 100]\n[random.psd.y]\nvalues = 1\n'
                                '[[random.coherence]]\ninputs = ["y", "q"]', 2,
                                ("[random.coherence] #1", "known: y")),
    # the same pair twice with two values: the second silently won
    "coherence-pair-twice": (TWO_INPUTS + '[[random.coherence]]\ninputs = ["x", "y"]\n'
                             'value = 0.9\n', 2,
                             ("[random.coherence] #2", "given twice", "#1 and #2")),
}


@pytest.mark.parametrize("case", sorted(RANDOM_CASES))
def test_hostile_random_sections(case, tmp_path):
    section, status, words = RANDOM_CASES[case]
    path = tmp_path / "m.toml"
    path.write_text(SDOF + "\n[random]\n" + section)
    code, _, err = run_cli(["random", str(path), "--json"])
    _check(code, err, status, ("m.toml",) + words)


SECTION_CASES = {
    # [shock]: OverflowError (int too large); an infinite amplitude was reported as
    # "6001 samples; a signal is limited to 50000000"
    "shock-huge-amplitude": ("shock", SHOCK.replace("amplitude = 10", f"amplitude = {HUGE}"),
                             ("[shock] amplitude", "got 10000")),
    "shock-huge-duration": ("shock", SHOCK.replace("duration = 0.01", f"duration = {HUGE}"),
                            ("[shock] duration",)),
    "shock-huge-Q": ("shock", SHOCK + f"Q = {HUGE}", ("[shock] Q",)),
    "shock-amplitude-overflows-in-si": (
        "shock", SHOCK.replace("amplitude = 10", 'amplitude = 1e308\nunit = "g"'),
        ("[shock] amplitude", "floating-point range")),
    "shock-step-underflows": ("shock", SHOCK + "step = 5e-324", ("[shock] step", "samples")),
    # a base frequency of 1e300 Hz was called "an undamped resonance"
    "periodic-period-underflows": ("periodic", SQUARE + "period = 1e-300",
                                   ("[periodic] period", "above 1e+15 Hz")),
    # [periodic]: OverflowError; an infinite amplitude was reported as "needs more than
    # 200000 harmonics"
    "periodic-huge-period": ("periodic", SQUARE + f"period = {HUGE}", ("[periodic] period",)),
    "periodic-huge-amplitude": ("periodic", SQUARE.replace("amplitude = 1", f"amplitude = {HUGE}")
                                + "period = 0.5", ("[periodic] amplitude",)),
    "periodic-amplitude-overflows-in-si": (
        "periodic", SQUARE.replace("amplitude = 1", 'amplitude = 1e308\nunit = "km"')
        + "period = 0.5", ("[periodic] amplitude", "floating-point range")),
    "periodic-period-zero": ("periodic", SQUARE + "period = 0", ("[periodic] period",)),
    "periodic-period-nan": ("periodic", SQUARE + "period = nan", ("[periodic] period",)),
    "periodic-tolerance-zero": ("periodic", SQUARE + "period = 0.5\ntolerance = 0",
                                ("[periodic] tolerance",)),
    # a 401-digit number was echoed whole in the message
    "periodic-huge-tolerance": ("periodic", SQUARE + f"period = 0.5\ntolerance = {HUGE}",
                                ("[periodic] tolerance", "...")),
    # [fatigue]: OverflowError (int too large; (34, 'Numerical result out of range'))
    "fatigue-huge-k": ("fatigue", f"k = {HUGE}\nC = 1e12\nduration = 10", ("[fatigue] k",)),
    "fatigue-k-overflows-C_range": ("fatigue", "k = 1e308\nC_range = 1e12\nduration = 10",
                                    ("[fatigue] C_range", "not a positive finite")),
    "fatigue-curve-overflows": ("fatigue", "k = 100\namplitude = 1e100\ncycles = 1e6\n"
                                "duration = 10", ("[fatigue] amplitude", "C = inf")),
    "fatigue-negative-k": ("fatigue", "k = -4\nC = 1e12\nduration = 10", ("[fatigue] k",)),
    "fatigue-zero-C": ("fatigue", "k = 4\nC = 0\nduration = 10", ("[fatigue] C",)),
    # total / step = 5e6 passed the check, and its 5e6 + 1 samples then failed in srs
    "shock-one-sample-too-many": ("shock", SHOCK + "step = 1e-8\ntotal = 0.05",
                                  ("[shock] step", "5e+06 samples")),
    "periodic-expression-zero-amplitude": (
        "periodic", 'signal = "y"\nexpression = "t"\namplitude = 0\nperiod = 0.5\n',
        ("[periodic] amplitude", "factor on the expression")),
}


@pytest.mark.parametrize("case", sorted(SECTION_CASES))
def test_hostile_load_sections(case, tmp_path):
    section, body, words = SECTION_CASES[case]
    head = FATIGUE_HEAD if section == "fatigue" else f"[{section}]\n"
    path = tmp_path / "m.toml"
    path.write_text(SDOF + "\n" + head + body)
    code, _, err = run_cli(["check", str(path)])
    _check(code, err, 2, ("m.toml",) + words)
    assert len(err) < 1000, err


def test_shock_without_duration_names_only_the_duration(tmp_path):
    """Before: a bad duration also gave 'step: missing' and 'total: missing'."""
    path = tmp_path / "m.toml"
    path.write_text(SDOF + "\n[shock]\n" + SHOCK.replace("duration = 0.01", "duration = -1"))
    code, _, err = run_cli(["check", str(path)])
    _check(code, err, 2, ("[shock] duration",))
    assert "step" not in err and "total" not in err


@pytest.mark.parametrize("expression", ["exp(1000*t)", "1e300*t"])
def test_periodic_expression_that_overflows(expression, tmp_path):
    """Before: 'the series needs more than 200000 harmonics' and numpy overflow warnings."""
    path = tmp_path / "m.toml"
    path.write_text(SDOF + f'\n[periodic]\nsignal = "y"\nexpression = "{expression}"\n'
                    "period = 0.5\n")
    code, _, err = run_cli(["solve", str(path)])
    _check(code, err, 3, ("too large", "overflows"))


# -- CSV histories (model/time_series.py) through `resonant srs --csv` --------------------

GOOD = "t,a\n" + "".join(f"{i * 1e-4:.4f},{i % 7}\n" for i in range(50))

CSV_CASES = {
    "empty": (b"", 2, ("at least two samples",)),
    "header-only": (b"t,a\n", 2, ("at least two samples",)),
    "one-sample": (b"0,1\n", 2, ("at least two samples",)),
    "not-monotonic": (b"0,1\n0.002,2\n0.001,3\n", 2, ("constant step", "sample 2")),
    "nan": (b"0,1\n0.001,nan\n", 2, ("line 2",)),
    "three-columns": (b"0,1,2\n0.001,2,3\n", 2, ("line 1", "two numbers")),
    "decimal-commas": (b"0;1,5\n0,001;2\n", 2, ("line 1",)),
    "binary": (bytes(range(256)) * 50, 2, ("line 1",)),
    "utf-16": ("t,a\n0,1\n0.001,2\n".encode("utf-16"), 2, ("line",)),
    # before: the step overflowed to inf and srs said "the sampling step inf s must be
    # positive" (exit 3)
    "huge-times": (b"-1.7e308,1\n1.7e308,2\n", 2, ("constant step", "sample 2")),
    "huge-times-three": (b"-1.7e308,1\n0,2\n1.7e308,2\n", 2, ("constant step", "sample 2")),
}


@pytest.mark.parametrize("case", sorted(CSV_CASES))
def test_hostile_csv_histories(case, tmp_path):
    data, status, words = CSV_CASES[case]
    path = tmp_path / "h.csv"
    path.write_bytes(data)
    code, _, err = run_cli(["srs", "--csv", str(path), "--points", "3"])
    _check(code, err, status, ("h.csv",) + words)
    assert str(tmp_path) not in err


@pytest.mark.parametrize("prefix", ["\ufeff", "# a shock\n\n", "\ufeff# a shock\nt,a\n"])
def test_csv_bom_and_comment_before_the_header_keep_every_sample(prefix, tmp_path):
    """Before: a byte-order mark made the first sample look like a header (silently
    dropped), and a header after a comment line was an error."""
    path = tmp_path / "h.csv"
    path.write_text(prefix + "0,5\n0.001,0\n0.002,1\n", encoding="utf-8")
    step, values = time_series.read_time_series(path)
    assert step == pytest.approx(1e-3) and values.tolist() == [5.0, 0.0, 1.0]


def test_csv_with_semicolons_and_crlf(tmp_path):
    path = tmp_path / "h.csv"
    path.write_bytes(b"t;a\r\n0;1\r\n0.5;2\r\n1;3\r\n")
    assert time_series.read_time_series(path)[1].tolist() == [1.0, 2.0, 3.0]


@pytest.mark.parametrize("target", ["folder", "/dev/zero", "fifo", "missing"])
def test_csv_that_is_not_a_regular_file(target, tmp_path):
    if target == "folder":
        path = tmp_path / "dir.csv"
        path.mkdir()
    elif target == "fifo":
        path = tmp_path / "f.csv"
        os.mkfifo(path)
    elif target == "missing":
        path = tmp_path / "nope.csv"
    else:
        path = Path(target)
    code, _, err = run_cli(["srs", "--csv", str(path)])
    _check(code, err, 2, ("cannot read the history",))
    assert str(tmp_path) not in err


def test_csv_sample_count_is_bounded(tmp_path, monkeypatch):
    """Before: a 190 MB CSV of 18 million samples took 3 GB (a Python float list and a
    list of lines); now the lines are read one at a time into an array of doubles, up to
    MAX_SAMPLES (here lowered, so that the test is quick)."""
    monkeypatch.setattr(time_series, "MAX_SAMPLES", 100)
    path = tmp_path / "h.csv"
    path.write_text("".join(f"{i},{i % 3}\n" for i in range(101)))
    with pytest.raises(ModelError, match="line 101: more than 100 samples"):
        time_series.read_time_series(path)
    path.write_text("".join(f"{i},{i % 3}\n" for i in range(100)))
    assert len(time_series.read_time_series(path)[1]) == 100


@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=400) | st.lists(
    st.tuples(st.one_of(st.floats(), st.integers(), st.text(max_size=4)),
              st.one_of(st.floats(), st.integers(), st.text(max_size=4))),
    max_size=6).map(lambda rows: "".join(f"{a},{b}\n" for a, b in rows).encode()))
def test_csv_reader_gives_a_history_or_a_model_error(data, tmp_path):
    path = tmp_path / "h.csv"
    path.write_bytes(data)
    try:
        step, values = time_series.read_time_series(path)
    except ModelError as exc:
        assert str(exc).startswith("h.csv: ")
        return
    assert math.isfinite(step) and step > 0
    assert len(values) >= 2 and np.isfinite(values).all()


# -- the table of [random.psd.NAME] under arbitrary TOML values ---------------------------

_toml_value = st.one_of(st.floats(), st.integers(min_value=-10**400, max_value=10**400),
                        st.booleans(), st.text(max_size=3), st.just([1]))


@settings(max_examples=200, deadline=None, derandomize=True)
@given(rows=st.lists(st.lists(_toml_value, min_size=1, max_size=3), max_size=5),
       unit=st.sampled_from([None, "g^2/Hz", "N^2/(rad/s)", "m^2/Hz"]))
def test_random_table_is_a_valid_table_or_a_problem(rows, unit):
    table = {"values": rows, **({"unit": unit} if unit else {})}
    problems: list[Problem] = []
    spec = parse_random({"psd": {"F": table}}, [], ["F"], ["x"], "m.toml", problems)
    if spec is None:
        assert problems and all(p.file == "m.toml" and p.section.startswith("random")
                                for p in problems)
        return
    values = spec.inputs[0].table
    assert values is not None and np.isfinite(values).all() and (values > 0).all()
    assert (np.diff(values[:, 0]) > 0).all()


# -- the command line: values that would allocate or run for ever ------------------------

SRS_CASES = {
    # OverflowError: cannot convert float infinity to integer
    "pulse-infinitely-many-samples": (["--pulse", "half-sine", "--duration", "1e300",
                                       "--step", "1e-300"], 3, ("samples", "limited")),
    "pulse-1e8-samples": (["--pulse", "half-sine", "--duration", "1", "--step", "1e-8"], 3,
                          ("1e+08 samples",)),
    # a hang: 10^7 samples x 10^5 oscillators
    "pulse-times-points": (["--pulse", "step", "--duration", "1", "--step", "1e-6",
                            "--points", "100000"], 3, ("natural frequencies", "limited")),
    # NaN in the printed spectrum (exit 0), numpy warnings
    "frequencies-overflow": (["--pulse", "half-sine", "--duration", "0.01", "--from",
                              "1e-300", "--to", "1e308"], 3, ("overflows",)),
    "from-nan": (["--pulse", "half-sine", "--duration", "0.01", "--from", "nan"], 2,
                 ("--from",)),
    "points-huge": (["--pulse", "half-sine", "--duration", "0.01", "--points",
                     "99999999999999999999"], 2, ("--points",)),
    "to-below-from": (["--pulse", "half-sine", "--duration", "0.01", "--from", "100",
                       "--to", "10"], 2, ("--to must be above --from",)),
}


@pytest.mark.parametrize("case", sorted(SRS_CASES))
def test_hostile_srs_options(case):
    args, status, words = SRS_CASES[case]
    code, _, err = run_cli(["srs", *args])
    assert code == status, err
    assert "Traceback" not in err and "internal error" not in err, err
    for word in words:
        assert word in err, err


def _limited(memory: int) -> None:
    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))


@pytest.mark.parametrize("args", [
    ["srs", "--pulse", "half-sine", "--duration", "10", "--step", "1e-7"],
    ["srs", "--pulse", "step", "--duration", "1", "--step", "2e-7", "--points", "100000"],
])
def test_allocations_are_refused_before_they_happen(args):
    """In a process limited to 1 GiB of address space: refused with a message within
    seconds, not a MemoryError or a machine swapping."""
    env = {**os.environ, "PYTHONPATH": SRC, "OMP_NUM_THREADS": "1",
           "OPENBLAS_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, "-m", "resonant", *args], capture_output=True,
                          text=True, timeout=60, env=env, preexec_fn=lambda: _limited(2**30))
    assert done.returncode == 3, done.stderr
    assert "limited" in done.stderr and "Traceback" not in done.stderr


# -- saved results read back (analyses/results_json.py) ----------------------------------

@pytest.mark.parametrize("data, words", [
    # before: OverflowError (int too large to convert to float)
    ({"frequency_hz": [10**400], "maximax": [1], "primary": [1], "residual": [1]},
     "'frequency_hz' holds a number beyond the floating-point range"),
    ({"frequency_hz": [1.0], "maximax": [1.0], "primary": [1.0], "residual": [1.0],
      "quantity": "z", "damping_ratio": 10**400, "duration_s": 1.0},
     "'damping_ratio' is a number beyond the floating-point range"),
    ({**{key: [1.0] * 10 for key in ("frequency_hz", "primary", "residual", "positive",
                                      "negative")}, "maximax": [1.0] * 1_000_000,
      "quantity": "absolute acceleration", "damping_ratio": 0.05, "Q": 10.0,
      "duration_s": 1.0, "excitation_end_s": 0.5, "warnings": []},
     "has shape (1000000,)"),
    ({"frequency_hz": "abc"}, "is a string"),
])
def test_saved_spectrum_with_hostile_values(data, words):
    from resonant.analyses.shock import ShockSpectrum
    from resonant.errors import AnalysisError

    with pytest.raises(AnalysisError, match=None) as caught:
        ShockSpectrum.from_dict(data)
    assert words in str(caught.value)


#: the shaker example's model (units: y in m) without its [random] section
SHAKER = (Path(__file__).resolve().parents[1] / "examples" / "shaker_gevs.toml").read_text(
    encoding="utf-8").split("\n[random]")[0] + "\n"


@pytest.mark.parametrize("section, status, words", [
    # a [shock] or [periodic] unit of another dimension than the signal's was accepted
    ('[shock]\nsignal = "y"\nderivative = 2\npulse = "half-sine"\namplitude = 100\n'
     'unit = "kg"\nduration = 0.011', 2,
     ("[shock] unit", "the unit is kg, but y'' is in m/s^2")),
    ('[periodic]\nsignal = "y"\nshape = "square"\namplitude = 1\nunit = "s"\nperiod = 0.1',
     2, ("[periodic] unit", "but y is in m; give it in m")),
    ('[shock]\nsignal = "y"\nderivative = 2\npulse = "half-sine"\namplitude = 100\n'
     'unit = "g"\nduration = 0.011', 0, ()),
    ('[periodic]\nsignal = "y"\nshape = "square"\namplitude = 1\nunit = "mm"\n'
     'period = 0.1', 0, ()),
])
def test_load_units_against_the_signals_dimension(section, status, words, tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(SHAKER + section, encoding="utf-8")
    code, _, err = run_cli(["check", str(path)])
    _check(code, err, status, words)


@pytest.mark.parametrize("args, words", [
    # TypeError: 'int' object is not iterable
    (["random", "--only", ",,,"], ("m.toml --only", "give one or more coordinates")),
    # named neither the file nor the option
    (["random", "--only", "nosuch"], ("m.toml --only", "unknown coordinate or output 'nosuch'")),
    (["sweep", "--param", "k", "--from", "1", "--to", "2", "--only", "z"],
     ("m.toml --only", "unknown coordinate 'z'; known: x")),
])
def test_only_names_are_checked_before_the_work(args, words, tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(SDOF + "\n[random]\nband = [1, 100]\n[random.psd.y]\nvalues = 1\n")
    code, _, err = run_cli([args[0], str(path), *args[1:]])
    _check(code, err, 2, words)


@pytest.mark.parametrize("C, k", [(1e-300, 4.0), (1e300, 300.0), (1e12, 1e6)])
def test_a_fatigue_life_without_a_digit_is_said(C, k):
    """Before: ZeroDivisionError for a life of 0, or an empty damage marked ok."""
    from resonant.analyses.fatigue import SNCurve, spectral_fatigue
    from resonant.errors import AnalysisError

    f = np.linspace(90, 110, 201)
    with pytest.raises(AnalysisError, match="no digit left in double precision"):
        spectral_fatigue(f, np.full(201, 50.0), SNCurve(C, k), 3600.0)


def test_periodic_expression_takes_its_amplitude_and_unit():
    """An ``expression`` ignored ``amplitude`` and ``unit``: the load "t" given with
    amplitude 2 in mm has 2e-3 times the series of the bare "t" (rel 1e-12)."""
    from resonant.analyses.periodic_load import load_series
    from resonant.api import loads

    bare = SDOF + '[periodic]\nsignal = "y"\nexpression = "t"\nperiod = 0.5\n'
    scaled = bare.replace('expression = "t"', 'expression = "t"\namplitude = 2\nunit = "mm"')
    series = []
    for text in (bare, scaled):
        model = loads(text)
        series.append(load_series(model.linearize(), model.periodic_section))
    for part in ("a", "b"):
        np.testing.assert_allclose(getattr(series[1], part), 2e-3 * getattr(series[0], part),
                                   rtol=1e-12, atol=1e-18)


def test_random_response_of_an_unstable_system_is_refused(tmp_path):
    """Negative damping: the RMS table came out with no warning; a stationary random
    response does not exist (exit 3, the eigenvalue named)."""
    path = tmp_path / "m.toml"
    path.write_text(SDOF.replace("c = 2", "c = -2") + "\n[random]\n"
                    "band = [1, 100]\n[random.psd.y]\nvalues = 1\n")
    code, out, err = run_cli(["random", str(path)])
    _check(code, err, 3, ("unstable", "positive real part", "does not exist"))
    assert out == ""


def test_a_long_list_of_names_says_how_many_it_leaves_out() -> None:
    """A section without its signal on a 30-coordinate model lists 20 names and says how
    many more there are (it listed the first 20 as if they were all)."""
    from resonant.model.load_spec import parse_shock

    problems: list[Problem] = []
    coordinates = [f"q{i}" for i in range(1, 31)]
    parse_shock({"pulse": "half-sine", "amplitude": 1, "duration": 0.01, "step": 1e-4,
                 "total": 0.1}, [], coordinates, "m.toml", problems)
    message = next(str(p) for p in problems if "signal" in str(p))
    assert "q1, q2" in message and "q20 ... and 10 more" in message, message
