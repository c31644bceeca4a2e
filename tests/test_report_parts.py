"""The report of a model with parts (docs/parts.md) starts from its figure ("Fig. 1") and
derives the energies part by part, as the reference exercise does (its Eqs. (8)-(14))."""

from __future__ import annotations

from pathlib import Path

import pytest
import sympy

import resonant
from conftest import EXAMPLES, run_cli
from resonant.derivation import derivative_symbol
from resonant.report import build_report, render
from resonant.report.blocks import Equation, Figure, Paragraph
from resonant.report.derivation import derive
from resonant.report.parts import MechanismFigure

PARTS = EXAMPLES / "parts"


@pytest.fixture(scope="module")
def cart_pendulum() -> resonant.Model:
    return resonant.load(PARTS / "cart_pendulum.toml")


@pytest.fixture(scope="module")
def report(cart_pendulum: resonant.Model):
    return build_report(cart_pendulum)


def _equations(report) -> list[str]:
    return [b.latex for b in report.blocks if isinstance(b, Equation)]


def test_figure_one_comes_first(report) -> None:
    figures = [b for b in report.blocks if isinstance(b, Figure)]
    assert figures[0].number == 1 and isinstance(figures[0].plot, MechanismFigure)
    assert "Mechanical model" in figures[0].caption
    # before the data, as in the exercise ("In Fig. 1, a 2 DoF system is shown")
    first = report.blocks.index(figures[0])
    assert first < report.blocks.index(next(b for b in report.blocks
                                            if getattr(b, "text", "") == "Data"))
    text = " ".join(p for b in report.blocks[:first] if isinstance(b, Paragraph)
                    for p in b.parts if isinstance(p, str))
    assert "In Fig. 1" in text


def test_kinetic_energy_part_by_part(report) -> None:
    eqs = _equations(report)
    assert any(e.startswith(r"T = T_{\mathrm{cart}} + T_{\mathrm{rod}}") for e in eqs)
    # v_S = v_B + omega x r_BS as vectors (the exercise's Eq. (12)), then v_S^2 (Eq. (13))
    (vs,) = [e for e in eqs if e.startswith(r"\mathbf{v}_{S,\mathrm{rod}}")]
    assert r"\times" in vs and r"\boldsymbol{\omega}_{\mathrm{rod}}" in vs
    assert r"\frac{l \sin{\left(\varphi \right)}}{2}" in vs
    (square,) = [e for e in eqs if e.startswith(r"v_{S,\mathrm{rod}}^{2}")]
    assert r"l \dot{\varphi} \dot{x}_{1} \cos{\left(\varphi \right)}" in square
    assert any(e.startswith(r"\omega_{\mathrm{rod}} = \dot{\varphi} = \frac{\dot{x}_{2}}{l}")
               for e in eqs)
    assert any(e.startswith(r"\theta_{S,\mathrm{rod}} = \frac{m_{2} l^{2}}{12}") for e in eqs)
    # the spring's elongation and potential, the gravity potential
    assert any(e.startswith(r"\Delta l_{1} =") and e.rstrip(",").endswith("x_{1} - r(t)")
               for e in eqs)
    assert any(e.startswith("U_{g} = m_{2} g") for e in eqs)
    # equations numbered in reading order
    numbers = [b.number for b in report.blocks if isinstance(b, Equation) and b.number]
    assert numbers == sorted(numbers)


def test_derived_T_equals_the_reference(cart_pendulum: resonant.Model) -> None:
    """T from the parts is the exercise's Eq. (14)."""
    d = derive(cart_pendulum.linearize())
    m1, m2, length = sympy.symbols("m1 m2 l")
    x2 = sympy.Symbol("x2")
    v1, v2 = derivative_symbol("x1", 1), derivative_symbol("x2", 1)
    reference = (m1 * v1**2 / 2 + m2 / 2 * (v1**2 + v2**2 / 4 + v1 * v2 * sympy.cos(x2 / length))
                 + m2 * length**2 / 24 * (v2 / length) ** 2)
    assert sympy.simplify(d.energies["T"] - reference) == 0
    energy_form = derive(resonant.load(EXAMPLES / "cart_pendulum.toml").linearize())
    assert sympy.simplify(d.energies["T"] - energy_form.energies["T"]) == 0


def test_writers_embed_the_figure(cart_pendulum: resonant.Model, report,
                                  tmp_path: Path) -> None:
    html = render(report, "html")
    assert html.count("<figure>") >= 1 and "Figure 1: Mechanical model" in html
    md = render(report, "md", tmp_path / "r.md")
    assert "![Figure 1](r-fig1.svg)" in md
    assert (tmp_path / "r-fig1.svg").read_text().lstrip().startswith(("<?xml", "<svg"))
    tex = render(report, "tex", tmp_path / "r.tex")
    assert r"\includegraphics[width=\linewidth]{r-fig1.pdf}" in tex
    assert (tmp_path / "r-fig1.pdf").stat().st_size > 1000


@pytest.mark.parametrize("name", ["quarter_car", "double_pendulum", "rolling_disc",
                                  "slider_spring", "torsional_chain", "elastic_pendulum"])
def test_other_examples_report(name: str, tmp_path: Path) -> None:
    status, _, err = run_cli(["report", PARTS / f"{name}.toml", "-o", tmp_path / "r.md",
                              "--no-plots"])
    assert status == 0, err
    text = (tmp_path / "r.md").read_text()
    assert "kinetic energies of its" in text
    if name in ("quarter_car", "rolling_disc"):
        assert "dissipation function is the sum over the dampers" in text
    if name == "slider_spring":
        assert "exact geometry" in text
    if name == "elastic_pendulum":
        # its K holds sqrt((L0 + g*m/k)^2): sympy's det/expand of it took minutes, so the
        # report states the characteristic equation without expanding it
        assert "follow from" in text


def test_model_text_is_escaped(tmp_path: Path) -> None:
    """Names of springs are model text: escaped by every writer."""
    model = resonant.loads(r"""
[parameters]
m = 1
k = 1
[coordinates]
x = ""
[[point]]
name = "wall"
position = ["-1", "0"]
[[body]]
name = "b"
mass = "m"
position = ["x", "0"]
[[spring]]
name = "<script>$\\x$ & %"
between = ["wall", "b"]
stiffness = "k"
along = ["1", "0"]
""", source="t.toml")
    report = build_report(model)
    html = render(report, "html")
    assert "<script>" not in html and "&lt;script&gt;" in html
    tex = render(report, "tex", tmp_path / "t.tex")
    assert r"\textless{}script\textgreater{}\$\textbackslash{}x\$ \& \%" in tex
