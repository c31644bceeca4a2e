"""The explore page without a browser: the ``[explore]`` section, the slider ranges, the
JavaScript printer, the page's data and safety, the command and ``model.explore()``.

The page in a browser (its numbers against ``resonant solve``) is tested in
tests/test_explore_browser.py.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest
import sympy
from hypothesis import given
from hypothesis import strategies as st

import resonant
from conftest import EXAMPLES, run_cli
from resonant.errors import ModelError
from resonant.model import loads
from resonant.system import linear_system
from resonant.views.explore import (
    LIVE_LIMIT,
    controls,
    default_range,
    explore_data,
    explore_page,
    frequency_parameter,
    script_json,
)
from resonant.views.explore_export import export_system, parameters_function
from resonant.views.js_printer import NotPrintable, js_expression, js_function, js_number

BASE = """
title = "one mass"
[parameters]
m = "2 kg"
k = "800 N/m"
c = "4 N*s/m"
F0 = "10 N"
omega = "15 rad/s"
[coordinates]
x = { description = "displacement", unit = "m" }
[signals]
F = "F0*sin(omega*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
name = "F"
vector = ["F"]
point = ["x"]
[outputs]
v = "x'"
"""


def _problems(section: str) -> str:
    with pytest.raises(ModelError) as info:
        loads(BASE + section, source="m.toml")
    return str(info.value)


# -- the [explore] section ------------------------------------------------------------------

def test_explore_section_is_read_with_units_and_scales() -> None:
    model = loads(BASE + """
[explore]
k = { from = "0.2 N/mm", to = 2000, scale = "log" }
m = { from = 1, to = 3 }
show = ["v", "x"]
frequency = "omega"
""")
    spec = model.explore_section
    assert spec is not None
    assert (spec.ranges["k"].start, spec.ranges["k"].stop, spec.ranges["k"].log) == \
        (200.0, 2000.0, True)
    assert spec.show == ("v", "x") and spec.frequency == "omega"


@pytest.mark.parametrize("section, expected", [
    ('[explore]\nkk = { from = 1, to = 2 }',
     "m.toml: [explore] kk: 'kk' is not one of the model's parameters; did you mean 'k'?"),
    ('[explore]\nk = { from = 3, to = 2 }', "[explore] k: 'from' (3) must be below 'to' (2)"),
    ('[explore]\nk = { from = 1 }', "[explore] k: the range needs 'to'"),
    ('[explore]\nk = { from = 1, to = 2, step = 1 }', "[explore] k: unknown key 'step'"),
    ('[explore]\nk = { from = "1 kg", to = 2 }', "[explore] k: 'from': the value is in kg"),
    ('[explore]\nk = { from = -1, to = 2, scale = "log" }',
     "[explore] k: a logarithmic range needs positive ends"),
    ('[explore]\nk = { from = 1, to = 2, scale = "cubic" }', "[explore] k: scale must be"),
    ('[explore]\nk = { from = true, to = 2 }', "[explore] k: 'from' must be a number"),
    ('[explore]\nk = 5', "[explore] k: expected a range { from = ..., to = ... }, got int"),
    ('[explore]\nshow = ["y"]', "[explore] show: 'y' is not one of the model's coordinates"),
    ('[explore]\nshow = "x"', "[explore] show: show must be a list"),
    ('[explore]\nfrequency = "w"', "[explore] frequency: 'w' is not one of the model's"),
    ('[explore]\nk = { from = "1 +", to = 2 }', "[explore] k"),
    ('explore = 3\n', "[explore] must be a table"),
])
def test_explore_section_problems_name_file_section_and_key(section: str, expected: str
                                                            ) -> None:
    text = BASE + section if not section.startswith("explore =") else section + BASE
    with pytest.raises(ModelError) as info:
        loads(text, source="m.toml")
    assert expected in str(info.value)


# -- ranges and choices ---------------------------------------------------------------------

def test_ranges_come_from_explore_then_variants_then_around_the_value() -> None:
    model = resonant.load(EXAMPLES / "teaching" / "cart_pendulum.toml")
    system = linear_system(model)
    sliders = {c["name"]: c for c in controls(model, system, "omega")}
    variants = {v.name: v.values for v in model.exercise.variants}
    assert "k" in variants and (sliders["k"]["from"], sliders["k"]["to"]) == \
        (min(variants["k"]), max(variants["k"]))
    plain = [name for name in model.parameters if name not in variants and name != "omega"]
    for name in plain:
        value = model.parameter_values[name]
        assert (sliders[name]["from"], sliders[name]["to"], sliders[name]["log"]) == \
            default_range(value)
    explored = resonant.load(EXAMPLES / "matrices" / "frame.toml")
    frame = {c["name"]: c for c in controls(explored, linear_system(explored), "omega")}
    assert (frame["k"]["from"], frame["k"]["to"]) == (1e5, 4e5)
    assert (frame["omega"]["from"], frame["omega"]["to"]) == (0.0, 25.0)


def test_the_frequency_range_reaches_past_the_highest_natural_frequency() -> None:
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    omega = next(c for c in controls(model, linear_system(model), "omega")
                 if c["name"] == "omega")
    assert omega["from"] == 0.0 and omega["to"] >= 1.5 * 7.93 and omega["frequency"]


def test_the_excitation_frequency_is_found() -> None:
    for path, expected in ((EXAMPLES / "cart_pendulum.toml", "omega"),
                           (EXAMPLES / "rotating_unbalance.toml", "Omega"),
                           (EXAMPLES / "two_dof_free.toml", None),
                           (EXAMPLES / "matrices" / "frame.toml", "omega")):
        model = resonant.load(path)
        assert frequency_parameter(model, linear_system(model)) == expected, path


def test_units_of_the_controls_are_those_of_the_file() -> None:
    model = loads(BASE.replace('k = "800 N/m"', 'k = "0.8 N/mm"'))
    k = next(c for c in controls(model, linear_system(model), "omega") if c["name"] == "k")
    assert (k["value"], k["unit"], k["factor"]) == (800.0, "N/mm", 1000.0)


# -- the JavaScript printer ---------------------------------------------------------------------

def test_the_printer_writes_the_model_language_only() -> None:
    x, y = sympy.symbols("x y")
    names = {x: "p[0]", y: "p[1]"}
    assert js_expression(sympy.Rational(1, 3) * x, names) == "(p[0]/3)"
    assert js_expression(sympy.atan2(y, x) + sympy.E, names) == "(Math.E + Math.atan2(p[1], p[0]))"
    assert js_expression(x ** sympy.Rational(3, 2), names) == "Math.pow(p[0], (3/2))"
    assert js_expression(sympy.Integer(2) ** 60 * x, names) == "(1.152921504606847e+18*p[0])"
    for bad in (sympy.Heaviside(x), sympy.zoo, sympy.nan, sympy.Symbol("z"), sympy.gamma(x)):
        with pytest.raises(NotPrintable):
            js_expression(bad, names)


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_printed_numbers_read_back_exactly(value: float) -> None:
    text = js_number(value)
    assert float(text.strip("()")) == value
    assert re.fullmatch(r"\(?-?[0-9.e+-]+\)?|\(?-?inf\)?", text)


def test_a_shared_subexpression_is_computed_once() -> None:
    x = sympy.Symbol("x")
    shared = sympy.sin(x) * sympy.cos(x)
    text = js_function("f", [shared + 1, shared * 2], {x: "p[0]"})
    assert text.count("Math.sin") == 1 and "const t0" in text


def test_parameters_follow_their_formulas_unless_set() -> None:
    model = resonant.load(EXAMPLES / "tuned_mass_damper.toml")
    text = parameters_function(model)
    names = list(model.parameters)
    assert f"if (!o[{names.index('m2')}]) p[{names.index('m2')}] = " in text
    assert f"o[{names.index('m1')}]" not in text  # a plain value is never computed


def test_the_exported_system_never_holds_model_text(tmp_path: Path) -> None:
    model = resonant.load(EXAMPLES / "parts" / "cart_pendulum.toml")
    exported = export_system(linear_system(model))
    for name in [*model.parameters, *model.coordinates, *model.signals]:
        assert not re.search(rf"\b{re.escape(name)}\b", exported.program), name
    assert set(re.findall(r"Math\.(\w+)", exported.program)) <= {
        "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "exp",
        "log", "sqrt", "pow", "abs", "PI", "E"}


# -- the page -------------------------------------------------------------------------------

def test_the_page_is_one_self_contained_file() -> None:
    page = explore_page(resonant.load(EXAMPLES / "cart_pendulum.toml"))
    html = page.html
    assert page.live and html.startswith("<!DOCTYPE html>")
    assert "Content-Security-Policy" in html and "default-src 'none'" in html
    assert "unsafe-eval" not in html
    for bad in ("http://", "https://", "src=", "href=", "@import", "url(", "eval(",
                "new Function", "import("):
        assert bad not in html, bad
    assert len(html.encode("utf-8")) < 1_500_000
    data = json.loads(re.search(r'id="resonant-data">(.*?)</script>', html, re.S).group(1))
    assert data["coordinates"][0]["name"] == "x1" and data["frequency"] == "omega"


def test_strings_of_the_model_cannot_leave_their_json() -> None:
    text = script_json({"t": "</script><script>alert(1)</script> & \u2028"})
    assert "<" not in text and ">" not in text and "&" not in text and "\u2028" not in text
    assert json.loads(text)["t"] == "</script><script>alert(1)</script> & \u2028"
    hostile = BASE.replace('title = "one mass"', "title = '</title><script>x()</script>'")
    page = explore_page(loads(hostile))
    assert "<script>x()" not in page.html
    assert page.html.count("</script>") == page.html.count("<script")


def test_a_model_too_large_for_the_browser_is_precomputed(tmp_path: Path) -> None:
    n = LIVE_LIMIT + 1
    rows = ", ".join("[" + ", ".join(("2" if i == j else "-1" if abs(i - j) == 1 else "0")
                                     for j in range(n)) + "]" for i in range(n))
    eye = ", ".join("[" + ", ".join("1" if i == j else "0" for j in range(n)) + "]"
                    for i in range(n))
    force = ", ".join(["0"] * (n - 1) + ['"F0"'])
    model = loads(f"[parameters]\nF0 = 1\nomega = 0.5\n[matrices]\nM = [{eye}]\nK = [{rows}]\n"
                  f"[[harmonic]]\nomega = \"omega\"\nF_S = [{force}]\n")
    data, program = explore_data(model)
    assert not data["live"] and program == "" and f"{n} coordinates" in data["note"]
    solution = data["precomputed"]["solution"]
    assert "M" not in solution and len(solution["natural_frequencies"]) == n
    curve = data["precomputed"]["curve"]
    assert len(curve["values"]) == 400 and len(curve["omegas"]) == 400
    assert math.isclose(max(curve["values"]), data["parameters"][1]["to"])


# -- the command and the api --------------------------------------------------------------------

def test_the_command_writes_the_page(tmp_path: Path) -> None:
    target = tmp_path / "page.html"
    status, _, err = run_cli(["explore", EXAMPLES / "cart_pendulum.toml", "-o", target,
                              "--set", "k=120"])
    assert status == 0, err
    assert "wrote" in err and "computed live" in err
    html = target.read_text(encoding="utf-8")
    data = json.loads(re.search(r'id="resonant-data">(.*?)</script>', html, re.S).group(1))
    assert next(p for p in data["parameters"] if p["name"] == "k")["value"] == 120.0


@pytest.mark.parametrize("output, message", [
    ("page.pdf", "use a file ending in .html"),
    ("missing/page.html", "the folder"),
])
def test_the_command_refuses_what_it_cannot_write(tmp_path: Path, output: str, message: str
                                                  ) -> None:
    status, _, err = run_cli(["explore", EXAMPLES / "cart_pendulum.toml", "-o",
                              tmp_path / output])
    assert status == 2 and message in err


def test_model_explore_shows_the_page_in_jupyter(tmp_path: Path) -> None:
    model = resonant.load(EXAMPLES / "absorber.toml")
    page = model.explore(tmp_path / "absorber.html")
    assert (tmp_path / "absorber.html").read_text(encoding="utf-8") == page.html
    frame = page._repr_html_()
    assert frame.startswith("<iframe") and 'sandbox="allow-scripts"' in frame
    assert "<script" not in frame  # the page is inside srcdoc, escaped
