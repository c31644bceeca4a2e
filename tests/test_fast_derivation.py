"""The numeric derivation of large energy models agrees with the symbolic one.

A model of 12 or more coordinates is linearized numerically (float jets at the
parameter point, :func:`resonant.derivation.lagrange.linearize_numeric`); its
symbolic matrices are derived only when asked for (:class:`DeferredEOM`).  Here
random small mechanisms -- chains of sliders on springs and pendulums, with
dampers, a moving base, a force, outputs, nonlinear springs and sometimes a
static deflection in ``[equilibrium]`` -- are put through both paths
(``LinearEOM.of_model(model, numeric=True / False)``): every number of
``numeric()`` (M, C, K, the harmonics, the outputs) at the model's values and
at other values, and a sweep, must agree to 1e-12 relative.  The cases the numbers leave
to the symbolic derivation, the deadline, and the faster conversion of products to
sympy's canonical form are checked too.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
import symengine as se
import sympy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import resonant
from resonant.deadline import Deadline, DerivationTimeout
from resonant.derivation.jet import to_sympy
from resonant.derivation.lagrange import linearize_numeric
from resonant.system import LinearEOM, symbolic
from resonant.system import batch as batch_module
from resonant.system.symbolic import NUMERIC_MIN_COORDINATES, DeferredEOM

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from pendulum_chain import pendulum_chain_toml  # noqa: E402

TOLERANCE = 1e-12

value = st.floats(0.3, 3.0).map(lambda v: round(v, 3))


@st.composite
def mechanisms(draw: st.DrawFn) -> str:
    """The text of a random planar mechanism (1-5 coordinates)."""
    n = draw(st.integers(1, 5))
    kinds = draw(st.lists(st.sampled_from(["slider", "pendulum", "vertical"]),
                          min_size=n, max_size=n))
    base = draw(st.booleans())
    damped = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    force = draw(st.booleans())
    # a nonlinear spring on q1 (not on a deflected one: it would move the equilibrium)
    stiff = draw(st.sampled_from(["", "sqrt", "cosh"])) if kinds[0] != "vertical" else ""
    params = {"g": 9.81, "w": draw(value), "s0": draw(value), "s1": draw(value),
              "F0": draw(value), "L": draw(value), "k3": draw(value)}
    lines_def, T, U, D, eq = [], [], [], [], []
    x_prev, y_prev = ("s" if base else "0"), "0"
    for i, kind in enumerate(kinds, start=1):
        for p in ("m", "k", "l", "c"):
            params[f"{p}{i}"] = draw(value)
        q = f"q{i}"
        if kind == "pendulum":
            x, y = f"{x_prev} + l{i}*sin({q})", f"{y_prev} - l{i}*cos({q})"
            U.append(f"m{i}*g*Y{i}")
        elif kind == "slider":
            x, y = f"{x_prev} + {q}", y_prev
            U.append(f"k{i}*{q}^2/2")
        else:  # a vertical spring: gravity deflects it by m g / k (in [equilibrium])
            x, y = x_prev, f"{y_prev} + {q}"
            U.append(f"k{i}*{q}^2/2 + m{i}*g*{q}")
            eq.append(f'{q} = "-m{i}*g/k{i}"')
        lines_def += [f'X{i} = "{x}"', f'Y{i} = "{y}"']
        T.append(f"m{i}*(X{i}'^2 + Y{i}'^2)/2")
        if damped[i - 1]:
            D.append(f"c{i}*{q}'^2/2")
    if stiff == "sqrt":
        U.append("k3*(sqrt(L^2 + q1^2) - L)^2")
    elif stiff == "cosh":
        U.append("k3*(cosh(q1/L) - 1)")
    out = ["[parameters]", *(f"{k} = {v!r}" for k, v in params.items()), "",
           "[coordinates]", *(f'q{i} = "coordinate {i}"' for i in range(1, n + 1)), ""]
    signals = []
    if base:
        signals.append('s = "s0*cos(w*t) + s1*sin(2*w*t)"')
    if force:
        signals.append('F = "F0*sin(w*t)"')
    if signals:
        out += ["[signals]", *signals, ""]
    if eq:
        out += ["[equilibrium]", *eq, ""]
    out += ["[definitions]", *lines_def, "", "[energy]", f'T = "{" + ".join(T)}"',
            f'U = "{" + ".join(U)}"']
    if D:
        out.append(f'D = "{" + ".join(D)}"')
    out += ["", "[outputs]", f'tip = "X{n} + Y{n}"', 'first = "q1*l1 + X1"', ""]
    if force:
        out += ["[[force]]", 'name = "F at the tip"', 'vector = ["F", "0"]',
                f'point = ["X{n}", "Y{n}"]', ""]
    return "\n".join(out)


def _close(a: np.ndarray, b: np.ndarray, what: str) -> None:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, what
    scale = max(float(np.abs(b).max()) if b.size else 0.0, 1e-300)
    assert float(np.abs(a - b).max(initial=0.0)) <= TOLERANCE * scale, what


def _same_numbers(fast, slow) -> None:
    _close(fast.M, slow.M, "M")
    _close(fast.C, slow.C, "C")
    _close(fast.K, slow.K, "K")
    assert fast.harmonic == slow.harmonic
    assert [h.omega for h in fast.harmonics] == pytest.approx(
        [h.omega for h in slow.harmonics], rel=TOLERANCE)
    for hf, hs in zip(fast.harmonics, slow.harmonics):
        _close(np.concatenate([hf.F_S, hf.F_C]), np.concatenate([hs.F_S, hs.F_C]), "F")
        assert set(hf.signals) == set(hs.signals)
        for var in hs.signals:
            _close(np.array(hf.signals[var]), np.array(hs.signals[var]), f"signal {var}")
    assert set(fast.outputs) == set(slow.outputs)
    for name, out in slow.outputs.items():
        mine = fast.outputs[name]
        assert mine.value == pytest.approx(out.value, rel=TOLERANCE, abs=TOLERANCE)
        terms = set(mine.terms) | set(out.terms)
        _close(np.array([mine.terms.get(v, 0.0) for v in sorted(terms)]),
               np.array([out.terms.get(v, 0.0) for v in sorted(terms)]), f"output {name}")


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=mechanisms(), other=value)
def test_numeric_path_agrees_with_symbolic_path(text: str, other: float) -> None:
    model = resonant.loads(text)
    fast = LinearEOM.of_model(model, numeric=True)
    slow = LinearEOM.of_model(model, numeric=False)
    assert type(slow) is LinearEOM
    # nothing for the numbers to leave undecided (a static deflection's residual, rounding
    # noise in floats, is judged against the size of its terms)
    assert isinstance(fast, DeferredEOM)
    _same_numbers(fast.numeric(), slow.numeric())
    # another parameter point (a new numeric derivation), and a sweep over the frequency
    _same_numbers(fast.numeric(m1=other, w=other), slow.numeric(m1=other, w=other))
    omegas = np.linspace(0.5, 3.0, 4)
    bf, bs = fast.batch("w", omegas), slow.batch("w", omegas)
    for key in ("M", "C", "K"):
        _close(getattr(bf, key), getattr(bs, key), key)
    for hf, hs in zip(bf.harmonics, bs.harmonics):
        _close(hf.omega, hs.omega, "omega")
        _close(hf.F_S, hs.F_S, "F_S")
        _close(hf.F_C, hs.F_C, "F_C")
    # the symbolic matrices, derived when asked for, are the symbolic path's
    assert fast.M == slow.M and fast.K == slow.K and fast.C == slow.C
    assert dict(fast.excitation) == dict(slow.excitation)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=mechanisms(), other=value)
def test_compiled_path_agrees_with_symbolic_path(text: str, other: float) -> None:
    """A batch in which a parameter of the matrices varies is compiled from symengine's
    coefficients directly (for 300 expressions and more; here forced for small models)."""
    model = resonant.loads(text)
    fast = LinearEOM.of_model(model, numeric=True)
    slow = LinearEOM.of_model(model, numeric=False)
    masses = np.array([other, 1.0, 2.5])
    with mock.patch.object(symbolic, "SYMENGINE_MIN_EXPRESSIONS", 0), \
            mock.patch.object(batch_module, "SYMENGINE_MIN_EXPRESSIONS", 0):
        bf = fast.batch("m1", masses)
    bs = slow.batch("m1", masses)
    for key in ("M", "C", "K"):
        _close(getattr(bf, key), getattr(bs, key), key)
    assert len(bf.harmonics) == len(bs.harmonics)
    for hf, hs in zip(bf.harmonics, bs.harmonics):
        _close(hf.omega, hs.omega, "omega")
        _close(hf.F_S, hs.F_S, "F_S")
        _close(hf.F_C, hs.F_C, "F_C")
    for name, (value, terms) in bs.outputs.items():
        _close(bf.outputs[name][0], value, name)
        for var, coefficient in terms.items():
            _close(bf.outputs[name][1][var], coefficient, f"{name} {var}")
    if isinstance(fast, DeferredEOM):  # the symbolic view reuses that derivation
        assert "_raw" in fast.__dict__ and fast.M == slow.M


@settings(max_examples=8, deadline=None)
@given(n=st.integers(2, 7), m1=value)
def test_pendulum_chain_numeric_and_symbolic(n: int, m1: float) -> None:
    model = resonant.loads(pendulum_chain_toml(n))
    fast = LinearEOM.of_model(model, numeric=True)
    slow = LinearEOM.of_model(model, numeric=False)
    assert isinstance(fast, DeferredEOM)
    _same_numbers(fast.numeric(), slow.numeric())
    _same_numbers(fast.numeric(m1=m1), slow.numeric(m1=m1))
    # a sweep over a mass varies the matrices: it is compiled from the symbolic ones
    masses = np.linspace(1.0, 2.0, 3)
    _close(fast.batch("m1", masses).M, slow.batch("m1", masses).M, "M(m1)")


def test_large_models_take_the_numeric_path_and_small_ones_do_not() -> None:
    big = resonant.loads(pendulum_chain_toml(NUMERIC_MIN_COORDINATES)).linearize()
    small = resonant.loads(pendulum_chain_toml(NUMERIC_MIN_COORDINATES - 1)).linearize()
    assert isinstance(big, DeferredEOM) and isinstance(small, LinearEOM) \
        and not isinstance(small, DeferredEOM)
    assert "linearization" not in big.__dict__  # no symbolic work until asked for
    big.modes()
    assert "linearization" not in big.__dict__


@pytest.mark.parametrize("text, why", [
    ('[parameters]\nm = 1\nk = 0\n[coordinates]\nx = "x"\n[energy]\n'
     'T = "m*x\'^2/2"\nU = "x^2/(2*k)"', "division by a parameter that is zero"),
    ('[parameters]\nm = 1\nk = 1\n[coordinates]\nx = "x"\n[energy]\n'
     'T = "m*x\'^2/2"\nU = "k*sqrt(x^2 + 1e-30)"', "sqrt near its singular point"),
    ('[parameters]\nm = 1\nk = 1\n[coordinates]\nx = "x"\n[energy]\n'
     'T = "m*x\'^2/2"\nU = "k*(x - 1)^2/2"', "not an equilibrium"),
])
def test_the_numbers_leave_undecided_cases_to_the_symbolic_derivation(text: str, why: str
                                                                       ) -> None:
    model = resonant.loads(text)
    assert linearize_numeric(model, dict(model.parameter_values)) is None, why


def test_a_deadline_stops_the_numeric_derivation() -> None:
    model = resonant.loads(pendulum_chain_toml(60))
    late = Deadline(1e-9)
    with pytest.raises(DerivationTimeout):
        LinearEOM.of_model(model, late)


names = st.sampled_from(["a", "b", "g", "l1", "l10", "l2", "m1", "m12", "m2", "th_1"])


@st.composite
def products(draw: st.DrawFn) -> object:
    """A random symengine product of symbols, integer powers, a rational and a cosine."""
    factors = []
    for _ in range(draw(st.integers(2, 6))):
        name = se.Symbol(draw(names))
        kind = draw(st.sampled_from(["symbol", "power", "number", "function"]))
        if kind == "symbol":
            factors.append(name)
        elif kind == "power":
            factors.append(name ** draw(st.sampled_from([2, 3, -1, -2])))
        elif kind == "number":
            factors.append(se.Rational(draw(st.integers(-5, 5).filter(bool)),
                                       draw(st.integers(1, 4))))
        else:
            factors.append(se.cos(name))
    return se.Mul(*factors)


@settings(max_examples=200, deadline=None)
@given(product=products())
def test_symengine_products_convert_to_sympys_canonical_form(product: object) -> None:
    """The conversion sorts the factors by a plain key where it can: the result must be
    the product sympy itself builds (same arguments in the same order)."""
    converted = to_sympy(product)
    reference = sympy.sympify(str(product))
    assert converted == reference
    assert converted.args == reference.args


def test_a_sweep_over_a_length_of_a_large_chain_is_compiled_from_symengine() -> None:
    text = pendulum_chain_toml(NUMERIC_MIN_COORDINATES).replace(
        'x1 = "l1*sin(th1)"', 'x1 = "s + l1*sin(th1)"').replace(
        "[parameters]\n", "[parameters]\ns0 = 0.01\nw = 2.5\n").replace(
        "[coordinates]", '[signals]\ns = "s0*cos(w*t)"\n\n[coordinates]')
    model = resonant.loads(text)
    fast, slow = model.linearize(), LinearEOM.of_model(model, numeric=False)
    assert isinstance(fast, DeferredEOM)
    lengths = np.linspace(0.4, 0.9, 5)
    bf, bs = fast.batch("l3", lengths), slow.batch("l3", lengths)
    assert "_raw_compiled" in fast.__dict__ and "linearization" not in fast.__dict__
    for key in ("M", "C", "K"):
        _close(getattr(bf, key), getattr(bs, key), key)
    _close(bf.harmonics[0].F_C, bs.harmonics[0].F_C, "F_C")
    _close(bf.harmonics[0].F_S, bs.harmonics[0].F_S, "F_S")


def vertical_chain_toml(n: int, off: float = 1.0) -> str:
    """n masses hanging on springs one below the other, each at its static deflection
    (``off`` != 1 moves them away from it)."""
    lines = ["[parameters]", "g = 9.81"]
    lines += [f"m{i} = {1 + 0.1 * (i % 7):g}\nk{i} = {1000 + 37 * (i % 5):g}"
              for i in range(1, n + 1)]
    lines += ["[coordinates]", *(f'x{i} = ""' for i in range(1, n + 1)), "[equilibrium]"]
    for i in range(1, n + 1):
        springs = " + ".join(f"({' + '.join(f'm{j}' for j in range(a, n + 1))})/k{a}"
                             for a in range(1, i + 1))
        lines.append(f'x{i} = "-{off!r}*g*({springs})"')
    kinetic = " + ".join(f"m{i}*x{i}'^2/2" for i in range(1, n + 1))
    potential = " + ".join(f"k{i}*(x{i}{f' - x{i - 1}' if i > 1 else ''})^2/2 + m{i}*g*x{i}"
                           for i in range(1, n + 1))
    return "\n".join([*lines, "[energy]", f'T = "{kinetic}"', f'U = "{potential}"', ""])


def test_a_static_deflection_is_judged_by_the_size_of_its_terms() -> None:
    """The residual of a deflected chain is rounding noise in floats: judged against the
    size of the terms forming it (residual.Sized), the numbers accept it."""
    model = resonant.loads(vertical_chain_toml(NUMERIC_MIN_COORDINATES + 3))
    fast = model.linearize()
    assert isinstance(fast, DeferredEOM)
    _same_numbers(fast.numeric(), LinearEOM.of_model(model, numeric=False).numeric())


def test_a_wrong_static_deflection_is_reported_by_the_symbolic_check() -> None:
    model = resonant.loads(vertical_chain_toml(NUMERIC_MIN_COORDINATES, off=1.001))
    assert linearize_numeric(model, dict(model.parameter_values)) is None
    with pytest.raises(resonant.ModelError, match="not an equilibrium"):
        model.linearize()


def test_the_deferred_symbolic_derivation_has_the_time_limit_afresh() -> None:
    """The symbolic matrices, asked for after the time limit of the derivation ran out,
    are derived under the same limit counted afresh; a huge model still times out."""
    model = resonant.loads(pendulum_chain_toml(NUMERIC_MIN_COORDINATES))
    eom = model.linearize(deadline=Deadline(2.0))
    time.sleep(2.1)
    assert eom.M.shape == (NUMERIC_MIN_COORDINATES, NUMERIC_MIN_COORDINATES)
    big = resonant.loads(pendulum_chain_toml(80))
    values = dict(big.parameter_values)
    found = linearize_numeric(big, values)
    assert found is not None
    with pytest.raises(DerivationTimeout):
        DeferredEOM(big, found, values, Deadline(0.2)).M  # noqa: B018


def test_a_copy_with_another_model_is_a_symbolic_system() -> None:
    """dataclasses.replace (resonant.exercises shares a system this way) gives a LinearEOM
    with the symbolic fields, derived once, and the same numbers."""
    model = resonant.loads(pendulum_chain_toml(NUMERIC_MIN_COORDINATES))
    eom = model.linearize()
    copy = dataclasses.replace(eom, model=model)
    assert type(copy) is LinearEOM and copy.M == eom.M
    _same_numbers(copy.numeric(), eom.numeric())
