"""The error catalogue (docs/errors.md), one test per entry, plus malicious and malformed inputs.

Each case writes a model file, runs ``resonant solve`` in-process and checks the exact
exit status (2: invalid model, 3: analysis impossible), the key words of the message,
that the message points at the file (and section/key where it has one) and that no
traceback is printed.  The ids are the catalogue's entry names.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from conftest import pendulum_chain_text, run_cli

BASE = """title = "oscillator"
[parameters]
m = 2
k = 800
c = 4
F0 = 1
w = 10
[coordinates]
x = "displacement"
[signals]
F = "F0*sin(w*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
name = "drive"
vector = ["F"]
point = ["x"]
"""

MATRIX = """[parameters]
k = 100
[matrices]
M = [[1, 0], [0, 1]]
K = [["2*k", "-k"], ["-k", "k"]]
[[harmonic]]
omega = 3
F_S = [0, 1]
"""


def edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def run_model(tmp_path: Path, text: str | bytes, *extra: str, command: str = "solve"
              ) -> tuple[int, str, str, Path]:
    path = tmp_path / "model.toml"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    code, out, err = run_cli([command, str(path), *extra])
    return code, out, err, path


# (id, model text, extra CLI args, exit status, key words of the message, section/key shown)
CASES: list[tuple[str, str | bytes, tuple[str, ...], int, tuple[str, ...], str]] = [
    # -- file and TOML ---------------------------------------------------------------------
    ("not-utf8", b"title = \"\xff\"\n", (), 2, ("not UTF-8",), ""),
    ("invalid-toml", "title = \n", (), 2, ("invalid TOML",), ""),
    ("toml-nested-too-deeply", "a = " + "[" * 3000 + "]" * 3000, (), 2,
     ("nested too deeply",), ""),
    ("unknown-section", BASE + "[energie]\nT = \"0\"\n", (), 2,
     ("unknown section", "did you mean 'energy'"), "[energie]"),
    ("title-not-string", "title = 5\n" + BASE.split("\n", 1)[1], (), 2,
     ("title must be a string",), "[title]"),
    ("section-not-table", "parameters = 5\n" + BASE.split("\n", 1)[1].replace(
        "[parameters]\nm = 2\nk = 800\nc = 4\nF0 = 1\nw = 10\n", ""), (), 2,
     ("[parameters] must be a table",), "[parameters]"),
    # -- names ---------------------------------------------------------------------------------
    ("coordinates-missing", edit(BASE, '[coordinates]\nx = "displacement"\n', ""), (), 2,
     ("[coordinates] is missing",), "[coordinates]"),
    ("coordinates-empty", edit(BASE, 'x = "displacement"\n', ""), (), 2,
     ("[coordinates] is empty",), "[coordinates]"),
    ("coordinates-not-table", edit(BASE, '[coordinates]\nx = "displacement"\n', "")
     .replace("title = \"oscillator\"", "title = \"o\"\ncoordinates = 5"), (), 2,
     ("[coordinates] must be a table",), "[coordinates]"),
    ("too-many-coordinates", edit(BASE, 'x = "displacement"\n', 'x = "displacement"\n' + "".join(
        f'y{i} = ""\n' for i in range(2001))), (), 2, ("limited to 2000",), "[coordinates]"),
    ("invalid-name", edit(BASE, 'x = "displacement"', 'x = "displacement"\n"a b" = ""'), (), 2,
     ("cannot be used as a name", "not a valid name"), "[coordinates] a b"),
    ("reserved-name", edit(BASE, "w = 10", "sin = 10"), (), 2, ("'sin' is reserved",),
     "[parameters] sin"),
    ("dunder-name", edit(BASE, "w = 10", "__class__ = 10"), (), 2,
     ("names starting with '__' are not allowed",), "[parameters] __class__"),
    ("long-name", edit(BASE, "w = 10", "w" * 65 + " = 10"), (), 2, ("name too long",),
     "[parameters]"),
    ("duplicate-name", edit(BASE, 'x = "displacement"', 'x = "displacement"\nk = ""'), (), 2,
     ("already declared in [parameters]",), "[coordinates] k"),
    ("value-not-expression", edit(BASE, "w = 10", "w = true"), (), 2,
     ("expected a number or an expression string, got bool",), "[parameters] w"),
    # -- expressions (with a caret under the culprit) -------------------------------------------
    ("unknown-name", edit(BASE, 'U = "k*x^2/2"', 'U = "k*q^2/2"'), (), 2,
     ("unknown name 'q'", "^"), "[energy] U"),
    ("time-outside-signals", edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2/2*t"'), (), 2,
     ("time 't' may only appear in [signals]",), "[energy] U"),
    ("unexpected-character", edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2/2 $ 1"'), (), 2,
     ("unexpected character '$'",), "[energy] U"),
    ("misplaced-prime", edit(BASE, 'U = "k*x^2/2"', "U = \"k*(x)'^2/2\""), (), 2,
     ("a prime (') may only directly follow a name",), "[energy] U"),
    ("unclosed-parenthesis", edit(BASE, 'U = "k*x^2/2"', 'U = "k*(x^2/2"'), (), 2,
     ("unclosed '('",), "[energy] U"),
    ("unmatched-parenthesis", edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2)/2"'), (), 2,
     ("unmatched ')'",), "[energy] U"),
    ("missing-operator", edit(BASE, 'U = "k*x^2/2"', 'U = "k x^2/2"'), (), 2,
     ("missing operator", "write k*x"), "[energy] U"),
    ("empty-expression", edit(BASE, 'U = "k*x^2/2"', 'U = " "'), (), 2,
     ("empty expression",), "[energy] U"),
    ("expression-too-long", edit(BASE, 'U = "k*x^2/2"', 'U = "' + "x+" * 10001 + 'x"'), (), 2,
     ("expression too long",), "[energy] U"),
    ("expression-too-deep", edit(BASE, 'U = "k*x^2/2"', 'U = "' + "(" * 150 + "x" + ")" * 150
                                 + '"'), (), 2, ("nested too deeply",), "[energy] U"),
    ("exponent-too-large", edit(BASE, "w = 10", 'w = "9^9^9"'), (), 2,
     ("exponent too large",), "[parameters] w"),
    ("number-too-large", edit(BASE, "w = 10", "w = 1e301"), (), 2,
     ("number too large",), "[parameters] w"),
    ("huge-integer", edit(BASE, "w = 10", "w = " + "9" * 400), (), 2,
     ("number too large",), "[parameters] w"),
    ("number-too-small", edit(BASE, "w = 10", 'w = "1e-301"'), (), 2,
     ("number too small",), "[parameters] w"),
    ("too-many-digits", edit(BASE, "w = 10", 'w = "' + "1" * 290 + "." + "1" * 20 + '"'), (),
     2, ("too many digits",), "[parameters] w"),
    ("malformed-number", edit(BASE, "w = 10", 'w = "1.2.3"'), (), 2,
     ("malformed number",), "[parameters] w"),
    ("function-arity", edit(BASE, 'U = "k*x^2/2"', 'U = "k*atan2(x)^2"'), (), 2,
     ("atan2() takes 2 arguments, got 1",), "[energy] U"),
    ("unknown-function", edit(BASE, 'U = "k*x^2/2"', 'U = "k*foo(x)"'), (), 2,
     ("unknown function 'foo'",), "[energy] U"),
    ("function-not-called", edit(BASE, 'U = "k*x^2/2"', 'U = "k*sin"'), (), 2,
     ("'sin' is a function",), "[energy] U"),
    ("constant-with-prime", edit(BASE, 'U = "k*x^2/2"', "U = \"k*x^2/2*pi'\""), (), 2,
     ("'pi' is a constant",), "[energy] U"),
    ("unexpected-token", edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2/2 + *"'), (), 2,
     ("expected a number, a name or '('",), "[energy] U"),
    ("unexpected-end", edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2/2 +"'), (), 2,
     ("unexpected end of expression",), "[energy] U"),
    ("non-finite-toml-float", edit(BASE, "m = 2", "m = nan"), (), 2,
     ("expected a finite number, got nan",), "[parameters] m"),
    # -- parameters and --set ---------------------------------------------------------------
    ("parameter-not-real", edit(BASE, "w = 10", 'w = "sqrt(-1)"'), (), 2,
     ("is not a real number",), "[parameters] w"),
    ("parameter-not-finite", edit(BASE, "w = 10", 'w = "1/0"'), (), 2,
     ("is not a finite number",), "[parameters] w"),
    ("set-format", BASE, ("--set", "k"), 2, ("--set expects NAME=VALUE",), ""),
    ("set-unknown-parameter", BASE, ("--set", "kk=1"), 2,
     ("cannot set unknown parameter 'kk'", "did you mean 'k'"), "[parameters] kk"),
    ("set-invalid-value", BASE, ("--set", "k=__import__('os')"), 2,
     ("a prime (') may only directly follow a name",), "--set k"),
    # -- sections -------------------------------------------------------------------------------
    ("signal-with-prime", edit(BASE, 'F = "F0*sin(w*t)"', 'F = "F0*sin(w*t)"\nG = "sin(w\'*t)"'), (),
     2, ("a signal may not contain primes",), "[signals] G"),
    ("equilibrium-not-coordinate", BASE + "[equilibrium]\ny = 0\n", (), 2,
     ("'y' is not a coordinate",), "[equilibrium] y"),
    ("definition-cycle", BASE + '[definitions]\na = "b"\nb = "a"\n', (), 2,
     ("cycle", "a -> b -> a"), "[definitions]"),
    ("definition-explodes", BASE + "[definitions]\n" + 'd1 = "sin(x)"\n' + "".join(
        f'd{i} = "sin(d{i - 1})*cos(d{i - 1})"\n' for i in range(2, 31)), (), 2,
     ("grows to about", "terms", "exponentially"), "[definitions] d"),
    ("definition-degree", BASE + "[definitions]\n" + 'd1 = "x + 1"\n' + "".join(
        f'd{i} = "d{i - 1}*d{i - 1}"\n' for i in range(2, 31)), (), 2,
     ("polynomial degree",), "[definitions] d15"),
    ("unknown-energy", edit(BASE, 'D = "c*x\'^2/2"', 'V = "0"'), (), 2,
     ("unknown energy 'V'",), "[energy] V"),
    ("kinetic-energy-missing", edit(BASE, 'T = "m*x\'^2/2"\n', ""), (), 2,
     ("the kinetic energy T is missing",), "[energy] T"),
    ("energy-missing", edit(BASE, "[energy]", "[energyx]").replace("[energyx]", "[definitions]"),
     (), 2, ("the section [energy] is missing",), "[energy]"),
    ("potential-depends-on-velocity", edit(BASE, 'U = "k*x^2/2"', "U = \"k*x'^2/2\""), (), 2,
     ("U may not depend on velocities",), "[energy] U"),
    ("kinetic-depends-on-acceleration", edit(BASE, 'T = "m*x\'^2/2"', "T = \"m*x'^2/2 + x*x''\""),
     (), 2, ("T may not depend on accelerations",), "[energy] T"),
    # -- forces -------------------------------------------------------------------------------
    ("force-not-table", "force = 5\n" + BASE.split("[[force]]")[0], (), 2,
     ("[[force]] entries must be tables",), "[force]"),
    ("force-entry-not-table", "force = [5]\n" + BASE.split("[[force]]")[0], (), 2,
     ("each [[force]] must be a table",), "[force 1]"),
    ("force-name-not-string", edit(BASE, 'name = "drive"', "name = 5"), (), 2,
     ("name must be a string",), "name"),
    ("force-unknown-key", BASE + 'colour = "red"\n', (), 2, ("unknown key 'colour'",),
     "[force 'drive'] colour"),
    ("force-both-kinds", BASE + 'generalized = { x = "F" }\n', (), 2,
     ("either vector + point or generalized",), "[force 'drive']"),
    ("force-generalized-not-table", edit(BASE, 'vector = ["F"]\npoint = ["x"]',
                                         'generalized = "F"'), (), 2,
     ("generalized must be a table",), "[force 'drive'] generalized"),
    ("force-generalized-not-coordinate", edit(BASE, 'vector = ["F"]\npoint = ["x"]',
                                              'generalized = { y = "F" }'), (), 2,
     ("'y' is not a coordinate",), "[force 'drive'] generalized.y"),
    ("force-needs-vector-and-point", edit(BASE, 'point = ["x"]', ""), (), 2,
     ("needs both vector and point",), "[force 'drive']"),
    ("force-lengths", edit(BASE, 'point = ["x"]', 'point = ["x", "0"]'), (), 2,
     ("same length",), "[force 'drive']"),
    ("force-point-velocity", edit(BASE, 'point = ["x"]', "point = [\"x + x'\"]"), (), 2,
     ("the point depends on a velocity",), "[force 'drive'] point"),
    ("force-third-derivative", edit(BASE, 'vector = ["F"]', "vector = [\"F + x'''\"]"), (), 2,
     ("first two derivatives only",), "[force]"),
    # -- derivation -------------------------------------------------------------------------------
    ("not-differentiable", edit(BASE, 'U = "k*x^2/2"', 'U = "k*sqrt(x)"'), (), 2,
     ("sqrt() is not differentiable at the reference state",), "[energy] U"),
    ("division-by-zero-at-reference", edit(BASE, 'U = "k*x^2/2"', 'U = "k/x"'), (), 2,
     ("division by a quantity that is zero at the reference state",), "[energy] U"),
    ("atan2-at-origin", edit(BASE, 'U = "k*x^2/2"', 'U = "k*atan2(x, x)"'), (), 2,
     ("atan2(0, 0)",), "[energy] U"),
    ("not-an-equilibrium", edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2/2 + 3*x"'), (), 2,
     ("not an equilibrium", "residual", "x = -0.00375"), "[equilibrium]"),
    ("derivation-timeout", pendulum_chain_text(300),
     ("--timeout", "0.5"), 2, ("the derivation exceeded 0.5 s", "--timeout"), ""),
    ("overflow", edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2/2 + exp(exp(exp(exp(x + 10))))"'),
     (), 2, ("a number overflowed",), ""),
    ("entry-not-finite", edit(BASE, 'U = "k*x^2/2"', 'U = "(k*x^2/2 + 10)^999"'), (), 2,
     ("K[1,1]", "is not finite for the given parameter values"), "[parameters]"),
    ("output-not-finite", BASE + "[outputs]\ny = \"log((k*x + c*x')^3)\"\n", (), 2,
     ("an output is not finite",), "[parameters]"),
    # -- matrix models --------------------------------------------------------------------------
    ("matrices-not-table", "matrices = 5\n[parameters]\nk = 1\n", (), 2,
     ("[matrices] must be a table",), "[matrices]"),
    ("matrices-unknown-key", edit(MATRIX, "[matrices]", "[matrices]\nL = 1"), (), 2,
     ("unknown key 'L'",), "[matrices] L"),
    ("matrices-missing", edit(MATRIX, "M = [[1, 0], [0, 1]]\n", ""), (), 2,
     ("M is missing",), "[matrices] M"),
    ("matrix-not-square", edit(MATRIX, "M = [[1, 0], [0, 1]]", "M = [[1, 0], [0]]"), (), 2,
     ("M must be square",), "[matrices] M"),
    ("matrix-wrong-type", edit(MATRIX, "M = [[1, 0], [0, 1]]", "M = 5"), (), 2,
     ("must be an array of rows",), "[matrices] M"),
    ("matrix-sizes-differ", edit(MATRIX, "M = [[1, 0], [0, 1]]", "M = [[1]]"), (), 2,
     ("must have the same size",), "[matrices]"),
    ("matrix-entry-type", edit(MATRIX, "M = [[1, 0], [0, 1]]", "M = [[1, true], [0, 1]]"),
     (), 2, ("expected a number or an expression, got bool",), "[matrices] M[1][2]"),
    ("matrix-file-unreadable", edit(MATRIX, "M = [[1, 0], [0, 1]]", 'M = "missing.npy"'), (),
     2, ("cannot read 'missing.npy'",), "[matrices] M"),
    ("matrix-coordinates-count", edit(MATRIX, "[matrices]", '[coordinates]\na = ""\n[matrices]'),
     (), 2, ("1 coordinates for 2x2 matrices",), "[coordinates]"),
    ("harmonic-needs-omega", edit(MATRIX, "omega = 3\n", ""), (), 2,
     ("a harmonic needs omega",), "[harmonic 1]"),
    ("harmonic-unknown-key", edit(MATRIX, "omega = 3", "omega = 3\nphase = 1"), (), 2,
     ("unknown keys ['phase']",), "[harmonic 1]"),
    ("harmonic-length", edit(MATRIX, "F_S = [0, 1]", "F_S = [1]"), (), 2,
     ("F_S must be a list of 2 entries",), "[harmonic 1] F_S"),
    ("energy-and-matrices", MATRIX + '[energy]\nT = "0"\n', (), 2,
     ("either [energy] (and [[force]]) or [matrices]",), "[matrices]"),
    ("matrix-entry-not-finite", edit(MATRIX, "K = [[\"2*k\"", "K = [[\"2*k/(k-100)\""), (), 2,
     ("not finite",), ""),
    # -- analysis impossible (exit 3) -----------------------------------------------------------
    ("singular-mass-matrix", edit(BASE, "m = 2", "m = 0"), (), 3,
     ("mass matrix M is singular", "x has no inertia"), ""),
    ("resonance", edit(edit(BASE, "c = 4", "c = 0"), "w = 10", "w = 20"), (), 3,
     ("resonance", "natural frequency 1", "add damping"), ""),
    ("static-load-on-rigid-body-mode", edit(edit(BASE, "k = 800", "k = 0"), 'F = "F0*sin(w*t)"',
                                            'F = "F0"'), (), 3,
     ("static load", "rigid-body"), ""),
    ("overflowing-state-matrix", edit(edit(BASE, "m = 2", "m = 1e-299"), "k = 800",
                                      "k = 1e299"), (), 3, ("is not finite",), ""),
    # -- command line -----------------------------------------------------------------------------
    ("missing-file", None, (), 2, ("cannot read the model file",), ""),  # type: ignore[list-item]
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_catalogue_entry(case, tmp_path):
    name, text, extra, status, words, where = case
    if text is None:
        code, out, err = run_cli(["solve", str(tmp_path / "absent.toml"), *extra])
        path = tmp_path / "absent.toml"
    else:
        code, out, err, path = run_model(tmp_path, text, *extra)
    assert code == status, f"{name}: exit {code}, stderr:\n{err}"
    assert "Traceback" not in err and "internal error" not in err
    for word in words:
        assert word in err, f"{name}: {word!r} not in stderr:\n{err}"
    if status == 2 and not name.startswith("set-format"):
        assert str(path) in err or "--set" in err, f"{name}: the file is not named:\n{err}"
    if where:
        assert where in err, f"{name}: {where!r} not in stderr:\n{err}"
    label = "error:" if status == 2 else "analysis impossible:"
    assert err.startswith(label)


def test_signal_that_is_no_finite_sum_of_harmonics_is_said_at_once(tmp_path):
    """sin((F0 sin(w t))^999) used to run the harmonic split into the time limit (exit 2
    after 0.5 s, or a hang inside sympy); it is recognised as not harmonic without
    expanding anything: the equation of motion is derived, the stationary solution is not
    available, and the command says so in a second."""
    import time

    start = time.monotonic()
    code, out, err, _ = run_model(
        tmp_path, edit(BASE, 'F = "F0*sin(w*t)"', 'F = "sin((F0*sin(w*t))^999)"'),
        "--timeout", "5")
    assert code == 0 and "sums of harmonics" in out + err
    assert time.monotonic() - start < 5


def test_caret_points_at_the_culprit(tmp_path):
    code, _, err, _ = run_model(tmp_path, edit(BASE, 'U = "k*x^2/2"', 'U = "k*x^2/2 + q"'))
    assert code == 2
    lines = err.splitlines()
    expression, caret = lines[-2], lines[-1]
    assert expression.strip() == "k*x^2/2 + q"
    assert expression[caret.index("^")] == "q"


# -- warnings (exit 0, printed on stderr with --json, listed in the JSON) ---------------------

WARNING_CASES = [
    ("near-resonance", edit(BASE, "w = 10", "w = 20.1"), ("near resonance", "within")),
    ("ill-conditioned", edit(edit(edit(edit(MATRIX, "omega = 3", "omega = 0.61"), '["-k", "k"]]',
                                           '["-k", "k + 1"]]\nC = [[0.01, 0], [0, 0.01]]'),
                                      '"2*k"', '"k + 1"'), "k = 100", "k = 1.7e15"),
     ("ill-conditioned", "fewer than 3 correct digits", "not a resonance")),
    ("not-positive-definite", edit(BASE, "k = 800", "k = -800"),
     ("K is not positive definite",)),
    ("unstable", edit(BASE, "k = 800", "k = -800"), ("the equilibrium is unstable",)),
    ("not-harmonic", edit(BASE, 'F = "F0*sin(w*t)"', 'F = "F0*t^2"'),
     ("sums of harmonics", "resonant simulate")),
]


@pytest.mark.parametrize("case", WARNING_CASES, ids=[c[0] for c in WARNING_CASES])
def test_warning_entry(case, tmp_path):
    name, text, words = case
    code, out, err, _ = run_model(tmp_path, text, "--json")
    assert code == 0, err
    data = json.loads(out)
    joined = "\n".join(data["warnings"])
    for word in words:
        assert word in joined and word in err, f"{name}: {word!r} missing: {joined}"
    assert all(line.startswith("warning: ") for line in err.splitlines() if line)


# -- malicious and malformed model files -------------------------------------------------------

CANARY_COMMAND = "__import__('os').system('touch {canary}')"


def injection_models(canary: Path) -> list[tuple[str, str, tuple[str, ...]]]:
    payload = CANARY_COMMAND.format(canary=canary)
    quoted = json.dumps(payload)
    return [
        ("parameter-value", edit(BASE, "w = 10", f"w = {quoted}"), ()),
        ("title", edit(BASE, 'title = "oscillator"', f"title = {quoted}"), ()),
        ("coordinate-name", edit(BASE, 'x = "displacement"', f'x = "d"\n{quoted} = "d"'), ()),
        ("description", edit(BASE, 'x = "displacement"', f"x = {quoted}"), ()),
        ("signal-name", edit(BASE, 'F = "F0*sin(w*t)"', f'F = "F0*sin(w*t)"\n{quoted} = "t"'), ()),
        ("signal-value", edit(BASE, 'F = "F0*sin(w*t)"', f"F = {quoted}"), ()),
        ("force-name", edit(BASE, 'name = "drive"', f"name = {quoted}"), ()),
        ("energy", edit(BASE, 'U = "k*x^2/2"', f"U = {quoted}"), ()),
        ("section-key", BASE + f"[{quoted}]\na = 1\n", ()),
        ("definition", BASE + f"[definitions]\nd = {quoted}\n", ()),
        ("output-name", BASE + f"[outputs]\n{quoted} = \"x\"\n", ()),
        ("matrix-entry", edit(MATRIX, '"2*k"', quoted), ()),
        ("matrix-file", edit(MATRIX, "M = [[1, 0], [0, 1]]", f"M = {json.dumps(payload + '.npy')}"),
         ()),
        ("set-name", BASE, ("--set", f"{payload}=1")),
        ("set-value", BASE, ("--set", f"k={payload}")),
        ("sympy-style", edit(BASE, "w = 10", 'w = "Symbol(\'w\').__class__"'), ()),
        ("lambda", edit(BASE, "w = 10", 'w = "(lambda: 1)()"'), ()),
    ]


@pytest.mark.parametrize("index", range(17))
def test_code_injection_is_rejected_and_never_run(index, tmp_path):
    canary = tmp_path / "canary"
    name, text, extra = injection_models(canary)[index]
    code, out, err, _ = run_model(tmp_path, text, "--json", *extra)
    assert not canary.exists(), f"{name}: the payload ran!"
    assert code in (0, 2), f"{name}: exit {code}: {err}"
    if name in ("title", "description", "force-name", "output-name", "coordinate-name",
                "signal-name", "section-key", "set-name"):
        # free text is inert; names must be identifiers
        assert code == 0 if name in ("title", "description", "force-name") else code == 2, err
    else:
        assert code == 2, f"{name}: {err}"
    assert "Traceback" not in err
    if code == 2:
        assert len(err.splitlines()) <= 12, err


@pytest.mark.parametrize("text, words", [
    (edit(BASE, "w = 10", 'w = "' + "-" * 5000 + '1"'), ("nested too deeply",)),
    (edit(BASE, "w = 10", 'w = "' + "sin(" * 200 + "1" + ")" * 200 + '"'),
     ("nested too deeply",)),
    (edit(BASE, "w = 10", 'w = "2^2^2^2^2^2^2^2"'), ("exponent too large",)),
    (edit(BASE, "w = 10", 'w = "10^300*10^300"'), ("number too large",)),
    (edit(BASE, "w = 10", 'w = "exp(1000)"'), ("not a finite number",)),
    (edit(BASE, "w = 10", "w = inf"), ("expected a finite number",)),
    (edit(BASE, 'F = "F0*sin(w*t)"', 'F = "F0*sin(w*t)"\nG = "H"\nH = "G"'), ("unknown name",)),
    (BASE + '[definitions]\na = "a + 1"\n', ("cycle", "a -> a")),
    (edit(BASE, 'U = "k*x^2/2"', 'U = "k*y^2/2"'), ("unknown name 'y'",)),
    ("\x00\x01\x02", ("invalid TOML",)),
    ("", ("[coordinates] is missing",)),
])
def test_malformed_models_exit_2(text, words, tmp_path):
    code, _, err, _ = run_model(tmp_path, text)
    assert code == 2, err
    assert "Traceback" not in err
    for word in words:
        assert word in err, err


@pytest.mark.parametrize("override", ["m=0", "m=0*pi", "m=sin(pi)^2*0"])
def test_zero_mass_from_set_is_exit_3(override, tmp_path):
    code, _, err, _ = run_model(tmp_path, BASE, "--set", override)
    assert code == 3, err
    assert "mass matrix M is singular" in err


def test_npy_pickle_is_never_loaded(tmp_path):
    """A pickled object array in a matrix file would run code on load: refused."""
    np.save(tmp_path / "M.npy", np.array([[object()]], dtype=object), allow_pickle=True)
    text = "[matrices]\nM = \"M.npy\"\nK = [[1]]\n"
    code, _, err, _ = run_model(tmp_path, text)
    assert code == 2 and "cannot read 'M.npy'" in err, err


def test_huge_file_is_refused_before_reading(tmp_path):
    path = tmp_path / "model.toml"
    with open(path, "wb") as handle:
        handle.truncate(5_000_001)  # sparse: costs no disk or time
    code, _, err = run_cli(["solve", str(path)])
    assert code == 2 and "limited to 5000000" in err


def test_bad_timeout_is_a_usage_error(tmp_path):
    code, _, err, _ = run_model(tmp_path, BASE, "--timeout", "-1")
    assert code == 2 and "expected a number of seconds" in err


def test_debug_switch_is_the_only_way_to_a_traceback(tmp_path, monkeypatch):
    monkeypatch.delenv("RESONANT_DEBUG", raising=False)
    code, _, err, _ = run_model(tmp_path, BASE)
    assert code == 0 and "Traceback" not in err
    assert os.environ.get("RESONANT_DEBUG") is None
