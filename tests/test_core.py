"""The core pipeline: model -> linearized EOM -> stationary solution.

Property tests (hypothesis) on random systems, plus the behaviours the
core promises: equilibrium check, harmonic decomposition, resonance, exit codes.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import sympy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import resonant
from resonant.errors import AnalysisError, ModelError
from resonant.derivation.harmonics import decompose
from resonant.api import loads
from resonant.model import TIME, symbol
from resonant.derivation.nonlinear import derivative_symbol, nonlinear_equations

from conftest import run_cli

FAST = settings(max_examples=25, deadline=None,
                suppress_health_check=[HealthCheck.too_slow])


# -- helpers --------------------------------------------------------------------------

def chain_model(masses, springs, dampers=None, force_amplitude=1.0, omega=1.0):
    """A fixed-free chain written as energies, one force on the last mass."""
    n = len(masses)
    lines = ["[parameters]"]
    lines += [f"m{i + 1} = {m!r}" for i, m in enumerate(masses)]
    lines += [f"k{i + 1} = {k!r}" for i, k in enumerate(springs)]
    if dampers:
        lines += [f"c{i + 1} = {c!r}" for i, c in enumerate(dampers)]
    lines += [f"F0 = {force_amplitude!r}", f"w = {omega!r}", "[coordinates]"]
    lines += [f'x{i + 1} = "mass {i + 1}"' for i in range(n)]
    lines += ["[signals]", 'F = "F0*sin(w*t)"', "[energy]"]
    lines.append('T = "' + " + ".join(f"m{i + 1}*x{i + 1}'^2/2" for i in range(n)) + '"')
    rel = ["x1"] + [f"(x{i + 1} - x{i})" for i in range(1, n)]
    lines.append('U = "' + " + ".join(f"k{i + 1}*{r}^2/2" for i, r in enumerate(rel)) + '"')
    if dampers:
        relv = ["x1'"] + [f"(x{i + 1}' - x{i}')" for i in range(1, n)]
        lines.append('D = "' + " + ".join(f"c{i + 1}*{r}^2/2" for i, r in enumerate(relv))
                     + '"')
    lines += ["[[force]]", 'name = "F"', 'vector = ["F"]', f'point = ["x{n}"]']
    return "\n".join(lines)


positive = st.floats(min_value=0.5, max_value=5.0, allow_nan=False)


# -- property tests ---------------------------------------------------------------------

@FAST
@given(st.integers(min_value=1, max_value=6).flatmap(
    lambda n: st.tuples(st.lists(positive, min_size=n, max_size=n),
                        st.lists(positive, min_size=n, max_size=n))))
def test_chain_energies_give_tridiagonal_matrices(data):
    """A random n-DOF spring-mass chain as energies gives the textbook M, K (exact).

    Source: Rao, Mechanical Vibrations, 6th ed., Sect. 6.3 (influence of springs in a chain):
    M = diag(m_i), K tridiagonal with k_i + k_{i+1} on the diagonal. Tolerance: exact (symbolic).
    """
    masses, springs = data
    n = len(masses)
    eom = loads(chain_model(masses, springs)).linearize()
    m = [symbol(f"m{i + 1}") for i in range(n)]
    k = [symbol(f"k{i + 1}") for i in range(n)]
    K = sympy.zeros(n, n)
    for i in range(n):
        K[i, i] = k[i] + (k[i + 1] if i + 1 < n else 0)
        if i + 1 < n:
            K[i, i + 1] = K[i + 1, i] = -k[i + 1]
    assert sympy.simplify(eom.M - sympy.diag(*m)) == sympy.zeros(n, n)
    assert sympy.simplify(eom.K - K) == sympy.zeros(n, n)
    assert eom.C == sympy.zeros(n, n)


@FAST
@given(st.integers(min_value=1, max_value=5).flatmap(
    lambda n: st.tuples(st.lists(positive, min_size=n, max_size=n),
                        st.lists(positive, min_size=n, max_size=n),
                        st.lists(st.one_of(st.just(0.0), st.floats(1e-3, 0.5)), min_size=n, max_size=n),
                        st.floats(0.2, 20.0))))
def test_stationary_solution_satisfies_the_equation_of_motion(data):
    """q_p(t) = L cos wt + N sin wt makes M q'' + C q' + K q - Q(t) vanish (rel 1e-9).

    Checked in the time domain against the symbolic Q(t), at several instants.
    """
    masses, springs, dampers, omega = data
    model = loads(chain_model(masses, springs, dampers, omega=omega))
    eom = model.linearize()
    try:
        sol = eom.stationary()
    except AnalysisError:
        return  # exactly at an undamped resonance: correctly refused
    n = len(masses)
    num = sol.eom
    Q = sympy.lambdify(TIME, eom.Q.subs({symbol(n): v for n, v in model.parameter_values.items()}), "numpy")
    for t in np.linspace(0.0, 3.0, 7):
        q = np.zeros(n)
        qd = np.zeros(n)
        qdd = np.zeros(n)
        for h in sol.harmonics:
            w = h.omega
            c, s = math.cos(w * t), math.sin(w * t)
            q += h.L * c + h.N * s
            qd += w * (-h.L * s + h.N * c)
            qdd += -w * w * (h.L * c + h.N * s)
        lhs = num.M @ qdd + num.C @ qd + num.K @ q
        rhs = np.array(Q(t), dtype=float).ravel()
        scale = np.abs(num.M @ qdd).sum() + np.abs(num.K @ q).sum() + np.abs(rhs).sum()
        assert np.abs(lhs - rhs).max() <= 1e-9 * scale


coefficient = st.integers(min_value=-3, max_value=3).filter(lambda v: v != 0)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(coefficient, min_size=8, max_size=8), st.sampled_from(["sin", "cos"]))
def test_jet_linearization_equals_full_lagrange_equations(c, trig):
    """Symbolic and numeric paths agree: the second-order jets give exactly the
    Jacobian of the full Lagrange equations at rest (symbolic, exact).

    A random 2-DOF system with configuration-dependent inertia, a moving support,
    a velocity-dependent dissipation and a signal inside T (unbalance-like).
    """
    text = f"""
[parameters]
a = 2
b = 3
[coordinates]
x = ""
y = ""
[signals]
s = "sin(3*t)"
[definitions]
g = "{trig}({c[0]}*x + {c[1]}*y)"
[energy]
T = "a*x'^2/2 + b*(y' + {c[2]}*s')^2/2 + {c[3]}*x'*y'*g/10 + (x' + s')^2*(2 + cos(y))/4"
U = "a*(x - {c[4]}*s)^2/2 + b*y^2 + {c[5]}*x*y/10 + (1 - cos(x + y))*{abs(c[6])}"
D = "(x' - s')^2*(1 + y^2)/2 + {abs(c[7])}*y'^2/2"
"""
    model = loads(text)
    eom = model.linearize()
    full = nonlinear_equations(model)
    E = full.mass * sympy.Matrix(full.qdd) + full.rest
    small = [*full.q, *full.qd, *full.qdd]
    signals = [derivative_symbol("s", k) for k in range(3)]
    at_rest = {v: 0 for v in small + signals}
    for order, mat in ((2, eom.M), (1, eom.C), (0, eom.K)):
        var = [derivative_symbol(q, order) for q in model.coordinates]
        J = E.jacobian(var).subs(at_rest)
        assert sympy.simplify(J - mat) == sympy.zeros(2, 2)
    for (name, order), column in eom.excitation.items():
        J = -E.jacobian([derivative_symbol(name, order)]).subs(at_rest)
        assert sympy.simplify(J - column) == sympy.zeros(2, 1)
    assert sympy.simplify(E.subs(at_rest)) == sympy.zeros(2, 1)


# -- behaviours of the core -------------------------------------------------------------

def test_harmonic_decomposition_expands_phases_products_and_constants():
    """sin(w t + e) = cos e sin wt + sin e cos wt; sin^2 = (1 - cos 2wt)/2 (exact)."""
    w, e, a = sympy.symbols("w e a")
    parts = decompose(a * sympy.sin(w * TIME + e) ** 2 + 3 * sympy.cos(2 * w * TIME) + 5)
    assert parts[0] == (0, a / 2 + 5)
    assert sympy.simplify(parts[2 * w][1] - (3 - a * sympy.cos(2 * e) / 2)) == 0
    assert sympy.simplify(parts[2 * w][0] - a * sympy.sin(2 * e) / 2) == 0


def test_two_frequencies_peak_sampled_over_the_common_period():
    """Two commensurate frequencies: the peak is the true maximum of the sum (rel 1e-9)."""
    text = chain_model([1.0], [4.0]).replace('F = "F0*sin(w*t)"',
                                              'F = "sin(t) + 0.5*cos(3*t) + 0.1"')
    sol = loads(text).linearize().stationary()
    assert [round(h.omega, 12) for h in sol.harmonics] == [0.0, 1.0, 3.0]
    t = np.linspace(0, 2 * np.pi, 200001)
    x = sol.response(t)["x1"]
    assert sol.amplitudes["x1"] == pytest.approx(np.abs(x).max(), rel=1e-9)
    assert "x1" not in sol.phases  # several frequencies: no single phase


def test_not_an_equilibrium_reports_residual_and_nearby_equilibrium():
    """A pendulum (m l^2 th'' + m g l sin th = F l cos th) under a constant horizontal
    force is not in equilibrium at th = 0; the nearby one is atan(F/(m g)) (rel 1e-6)."""
    text = """
[parameters]
m = 1
l = 1
g = 9.81
F = 2
[coordinates]
th = "angle"
[energy]
T = "m*l^2*th'^2/2"
U = "-m*g*l*cos(th)"
[[force]]
vector = ["F", "0"]
point = ["l*sin(th)", "-l*cos(th)"]
"""
    with pytest.raises(ModelError) as info:
        loads(text, source="pend.toml").linearize()
    message = str(info.value)
    assert "not an equilibrium" in message and "residual" in message and "th" in message
    expected = math.atan(2 / 9.81)
    assert f"th = {expected:.10g}" in message
    # putting it in [equilibrium] makes the model valid, with K = m g l cos + F l sin
    fixed = text.replace("[energy]", "[equilibrium]\nth = \"atan(F/(m*g))\"\n[energy]")
    num = loads(fixed).linearize().numeric()
    assert num.K[0, 0] == pytest.approx(math.hypot(9.81, 2.0), rel=1e-12)


def test_non_harmonic_signal_derives_eom_but_no_stationary_solution():
    text = chain_model([1.0], [4.0]).replace('F = "F0*sin(w*t)"', 'F = "exp(-t)"')
    sol = loads(text).linearize().stationary()
    assert not sol.available and sol.harmonics == ()
    assert any("harmonics" in w for w in sol.warnings)


def test_undamped_resonance_is_exit_3_naming_the_mode(tmp_path):
    path = tmp_path / "res.toml"
    path.write_text(chain_model([1.0], [4.0], omega=2.0))
    code, out, err = run_cli(["solve", str(path)])
    assert code == 3
    assert "resonance" in err and "natural frequency 1" in err and "Traceback" not in err


def test_near_resonance_warns(tmp_path):
    path = tmp_path / "near.toml"
    path.write_text(chain_model([1.0], [4.0], dampers=[0.01], omega=2.01))
    data = json.loads(run_cli(["solve", str(path), "--json"])[1])
    assert any("near resonance" in w for w in data["warnings"])


def test_singular_mass_matrix_is_exit_3(tmp_path):
    path = tmp_path / "massless.toml"
    path.write_text(chain_model([1.0, 0.0], [4.0, 1.0]))
    code, out, err = run_cli(["solve", str(path)])
    assert code == 3 and "mass matrix" in err and "x2" in err


def test_unstable_equilibrium_is_reported():
    """An inverted pendulum (U = +m g l cos th) is unstable."""
    text = """
[parameters]
m = 1
l = 1
g = 9.81
[coordinates]
th = "angle from the upright"
[signals]
F = "0.1*sin(2*t)"
[energy]
T = "m*l^2*th'^2/2"
U = "m*g*l*cos(th)"
[[force]]
generalized = { th = "F" }
"""
    sol = loads(text).linearize().stationary()
    assert sol.stability == "unstable"
    assert any("never reached" in w for w in sol.warnings)


def test_set_overrides_parameters_and_dependents(tmp_path):
    """--set changes a parameter; parameters defined from it follow (exact)."""
    text = chain_model([1.0], [4.0]).replace("w = 1.0", "w = 1.0\nw2 = \"2*w\"")
    model = loads(text, overrides={"F0": "2*3"})
    assert model.parameter_values["F0"] == 6.0
    model = model.with_parameters(w="0.5")
    assert model.parameter_values["w2"] == 1.0


def test_api_results_are_frozen_and_serialisable():
    model = resonant.load("examples/cart_pendulum.toml")
    sol = model.linearize().stationary()
    with pytest.raises(AttributeError):
        sol.stability = "x"  # type: ignore[misc]
    data = sol.to_dict()
    json.dumps(data, allow_nan=False)
    assert data["symbolic"]["M"] == [["m1 + m2", "m2/2"], ["m2/2", "m2/3"]]


def test_check_command_validates_only():
    code, out, err = run_cli(["check", "examples/cart_pendulum.toml"])
    assert code == 0 and "valid model" in out


@pytest.mark.parametrize("example", ["cart_pendulum", "cart_pendulum_exact", "chain3_damped",
                                     "rotating_unbalance", "tuned_mass_damper"])
def test_sympy_and_symengine_jets_agree(example):
    """Both algebra backends give identical symbolic M, C, K, Q and outputs (exact)."""
    from resonant.derivation import linearize as derive
    from resonant.system import LinearEOM

    model = resonant.load(f"examples/{example}.toml")
    a, b = (LinearEOM.from_linearization(derive(model, cas=cas))
            for cas in ("sympy", "symengine"))
    for name in ("M", "C", "K", "Q"):
        assert sympy.simplify(getattr(a, name) - getattr(b, name)) == sympy.zeros(
            *getattr(a, name).shape)
    for name in a.outputs:
        for var in set(a.outputs[name].terms) | set(b.outputs[name].terms):
            diff = a.outputs[name].terms.get(var, 0) - b.outputs[name].terms.get(var, 0)
            assert sympy.simplify(diff) == 0


def test_a_constant_signal_with_a_damper_on_it_has_a_stationary_solution():
    """A support at rest (a constant signal whose rate enters D): the rate is 0, not a
    signal that is no sum of harmonics; the stationary solution exists: x follows the
    support statically (x = y0)."""
    model = loads('[parameters]\nk = 100\nc = 2\ny0 = 0.01\n[coordinates]\nx = ""\n'
                  '[signals]\ny = "y0"\n[energy]\nT = "x\'^2/2"\nU = "k*(x - y)^2/2"\n'
                  'D = "c*(x\' - y\')^2/2"')
    solution = model.linearize().stationary()
    assert solution.available and not solution.warnings
    assert solution.amplitudes["x"] == pytest.approx(0.01, rel=1e-12)
