"""The full (nonlinear) Lagrange equations and the equilibrium finder.

Symbolic checks are exact (``simplify(a - b) == 0``); numeric equilibria are
compared with closed forms to 1e-9 relative.
"""

from __future__ import annotations

import math

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES
from resonant.api import load, loads
from resonant.model import symbol
from resonant.derivation.nonlinear import (derivative_symbol, find_equilibrium, linearized_matrices,
                                nonlinear_equations)

PENDULUM = """
[parameters]
m = 0.7
l = 1.3
g = 9.81
[coordinates]
th = "angle from the downward vertical"
[energy]
T = "m*l^2*th'^2/2"
U = "-m*g*l*cos(th)"
"""

#: a pendulum pushed sideways by a constant horizontal force F0 at the bob
TILTED = """
[parameters]
m = {m}
l = 0.8
g = 9.81
F0 = {F0}
[coordinates]
th = "angle from the downward vertical"
[energy]
T = "m*l^2*th'^2/2"
U = "-m*g*l*cos(th)"
[[force]]
name = "horizontal push"
vector = ["F0", "0"]
point = ["l*sin(th)", "-l*cos(th)"]
"""


def _zero(expr: sympy.Expr) -> bool:
    return sympy.simplify(expr) == 0


def test_simple_pendulum_equation_is_m_l2_thdd_plus_m_g_l_sin_th():
    eq = nonlinear_equations(loads(PENDULUM))
    m, l, g = symbol("m"), symbol("l"), symbol("g")
    th, thdd = derivative_symbol("th", 0), derivative_symbol("th", 2)
    full = (eq.mass * sympy.Matrix(eq.qdd) + eq.rest)[0]
    assert _zero(full - (m * l**2 * thdd + m * g * l * sympy.sin(th)))


def test_pendulum_with_moving_pivot_keeps_the_exact_coupling():
    # bob at (s + l sin th, -l cos th): m l^2 th'' + m l cos(th) s'' + m g l sin(th) = 0
    eq = nonlinear_equations(load(EXAMPLES / "pendulum.toml"))
    m, l, g = symbol("m"), symbol("l"), symbol("g")
    th = derivative_symbol("theta", 0)
    sdd = derivative_symbol("s", 2)
    full = (eq.mass * sympy.Matrix(eq.qdd) + eq.rest)[0]
    expected = (m * l**2 * derivative_symbol("theta", 2) + m * l * sympy.cos(th) * sdd
                + m * g * l * sympy.sin(th))
    assert _zero(full - expected)
    assert {name for name, _ in eq.signal_symbols.values()} == {"s"}


@pytest.mark.parametrize("name", ["cart_pendulum", "cart_pendulum_exact", "pendulum",
                                  "rotating_unbalance", "base_excitation", "chain3_damped"])
def test_jacobians_at_rest_equal_the_jet_linearization(name):
    """Two independent routes (full equations + Jacobian vs second-order jets) agree."""
    model = load(EXAMPLES / f"{name}.toml")
    eom = model.linearize()
    eq = nonlinear_equations(model)
    M, C, K = linearized_matrices(eq)
    for mine, theirs in ((M, eom.M), (C, eom.C), (K, eom.K)):
        assert all(_zero(d) for d in (mine - sympy.Matrix(theirs)))
    # the excitation columns: Q = -(dE/ds) s for every signal derivative s
    equations = eq.mass * sympy.Matrix(eq.qdd) + eq.rest
    rest = {s: 0 for s, (n, o) in eq.ops.registry.items() if n in model.signals or o > 0}
    assert not model.equilibrium  # so the reference state is q = 0
    rest.update({q: 0 for q in eq.q})
    for (signal, order), column in eom.excitation.items():
        dE = equations.diff(derivative_symbol(signal, order)).xreplace(rest)
        assert all(_zero(d) for d in (dE + sympy.Matrix(column)))


def test_cart_pendulum_mass_matrix_in_full():
    """Reference exercise, Eq. (13): the rod's coupling term carries cos(phi) = cos(x2/l)."""
    eq = nonlinear_equations(load(EXAMPLES / "cart_pendulum.toml"))
    m1, m2, l = symbol("m1"), symbol("m2"), symbol("l")
    x2 = derivative_symbol("x2", 0)
    expected = sympy.Matrix([[m1 + m2, m2 * sympy.cos(x2 / l) / 2],
                             [m2 * sympy.cos(x2 / l) / 2, m2 / 3]])
    assert all(_zero(d) for d in (eq.mass - expected))


def test_find_equilibrium_tilted_pendulum():
    """Constant horizontal force F0: tan(th) = F0/(m g), i.e. th = atan(F0/(m g))."""
    found = find_equilibrium(loads(TILTED.format(m=0.5, F0=2.0)))
    assert found is not None
    assert found["th"] == pytest.approx(math.atan(2.0 / (0.5 * 9.81)), rel=1e-9)
    # the same angle from acos: cos(th) = m g / sqrt((m g)^2 + F0^2)
    assert found["th"] == pytest.approx(math.acos(0.5 * 9.81 / math.hypot(0.5 * 9.81, 2.0)),
                                        rel=1e-9)


@settings(max_examples=10, deadline=None)
@given(m=st.floats(0.1, 10.0), ratio=st.floats(-2.0, 2.0).map(lambda r: round(r, 6)))
def test_find_equilibrium_tilted_pendulum_property(m, ratio):
    F0 = ratio * m * 9.81
    found = find_equilibrium(loads(TILTED.format(m=repr(m), F0=repr(F0))))
    assert found is not None
    assert found["th"] == pytest.approx(math.atan(ratio), rel=1e-8, abs=1e-12)


def test_find_equilibrium_none_when_there_is_none():
    model = loads("""
[parameters]
m = 1
F0 = 3
[coordinates]
x = "free mass"
[energy]
T = "m*x'^2/2"
[[force]]
name = "push"
generalized = { x = "F0" }
""")
    assert find_equilibrium(model) is None


def test_linearize_suggests_the_tilted_equilibrium():
    from resonant.errors import ModelError

    with pytest.raises(ModelError, match="nearby equilibrium: th = 0.3"):
        loads(TILTED.format(m=1.0, F0=1.0 * 9.81 * math.tan(0.3))).linearize()
