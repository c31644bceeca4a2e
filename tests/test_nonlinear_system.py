"""The nonlinear-system type (resonant.system.NonlinearSystem): compiled once, and its
small-oscillation limit is its linear system.

* Compiled once: building the system derives the full equations once and compiles them
  (equations with their three Jacobians, mass and rest for the time integration, the
  forcing, the outputs, the base frequency);
  a nonlinear simulation, a harmonic-balance sweep, a periodic solution and backbone
  curves on that one system compile nothing more (every ``sympy.lambdify`` call is
  counted, with the module that makes it).
* Two routes agree (hypothesis): at random parameter values of the cart with pendulum
  (examples/cart_pendulum.toml, the reference exercise) and a random small state, the
  full residual E(q_ref + e z, e z', e z'', forcing scaled by e) / e equals the linear
  system's M z'' + C z' + K z - Q(t) (the jets of resonant.derivation.lagrange, an
  independent derivation) to 1e-6 of the size of the terms (the neglected terms are of
  relative order e = 1e-7), and the system's Jacobians at the reference state equal M, C, K to
  1e-9 relative.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

import resonant.system.nonlinear as nonlinear_module
from conftest import EXAMPLES
from resonant.analyses.backbone import backbone
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.analyses.periodic import periodic_solution
from resonant.analyses.simulate import simulate
from resonant.errors import AnalysisError
from resonant.model import load, loads
from resonant.system import EnergySystem, NonlinearSystem, linear_system, nonlinear_system

DUFFING = EXAMPLES / "duffing.toml"
CART = EXAMPLES / "cart_pendulum.toml"


def test_the_full_equations_are_compiled_once(monkeypatch: pytest.MonkeyPatch) -> None:
    compiled: list[str] = []
    lambdify = sympy.lambdify

    def counting(*args, **kwargs):  # type: ignore[no-untyped-def]
        compiled.append(sys._getframe(1).f_globals["__name__"])
        return lambdify(*args, **kwargs)

    derived: list[str] = []
    derive = nonlinear_module.nonlinear_equations

    def counting_derivation(model):  # type: ignore[no-untyped-def]
        derived.append(model.title)
        return derive(model)

    monkeypatch.setattr(sympy, "lambdify", counting)
    monkeypatch.setattr(nonlinear_module, "nonlinear_equations", counting_derivation)
    model = load(DUFFING).with_parameters(F="0.01")
    system = nonlinear_system(model)
    assert isinstance(system, NonlinearSystem) and len(derived) == 1
    # equations + Jacobians, mass + rest (time integration), forcing, outputs, base
    # frequency: five compilations
    assert compiled.count("resonant.system.nonlinear") == 5
    compiled.clear()

    simulate(system, duration=30.0, progress=False)
    nonlinear_sweep(system, "omega", 0.5, 2.0, harmonics=3, points=30, linear=False)
    periodic_solution(system, harmonics=3)
    backbone(system, amplitude=0.5, harmonics=3, points=5)
    ours = [name for name in compiled if name.startswith("resonant.analyses")
            or name == "resonant.system.nonlinear"]
    assert ours == [] and len(derived) == 1
    # a system given to nonlinear_system is returned as it is
    assert nonlinear_system(system) is system


def test_matrices_model_has_no_nonlinear_system() -> None:
    model = loads("[matrices]\nM = [[1]]\nC = [[0.1]]\nK = [[4]]\n"
                  "[[harmonic]]\nomega = 1\nF_S = [0]\nF_C = [1]\n")
    for source in (model, linear_system(model)):
        with pytest.raises(AnalysisError, match=r"\[matrices\] model without \[\[nonlinear\]\] "
                                                r"elements has no nonlinear"):
            nonlinear_system(source)


@pytest.fixture(scope="module")
def cart() -> EnergySystem:
    system = nonlinear_system(load(CART))
    assert isinstance(system, EnergySystem)
    return system


positive = st.floats(0.5, 2.0)


@settings(max_examples=25, deadline=None)
@given(scale=st.tuples(positive, positive, positive, positive, positive),
       state=st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6),
       t=st.floats(0.0, 2.0))
def test_small_amplitude_residual_is_the_linear_system(
        cart: EnergySystem, scale: tuple[float, ...], state: list[float], t: float) -> None:
    base = dict(zip(cart.parameters, cart.parameter_values))
    values = dict(base)
    for name, factor in zip(("m1", "m2", "l", "k", "omega"), scale):
        values[name] = base[name] * factor
    num = cart.linear.numeric(**{k: repr(float(v)) for k, v in values.items()}).dense()
    e = 1e-7
    small = dict(values, F0=values["F0"] * e, r0=values["r0"] * e)
    pvals = np.array([small[k] for k in cart.parameters])
    z, v, a = (np.array(state[i:i + 2]) for i in (0, 2, 4))
    q_ref = cart.reference(pvals)
    s = cart.forcing(np.array([t]), pvals)
    E, G0, G1, G2 = cart.equations((q_ref + e * z)[:, None], e * v[:, None], e * a[:, None],
                                   s, pvals)
    Q = sum((h.F_S * np.sin(h.omega * t) + h.F_C * np.cos(h.omega * t)
             for h in num.harmonics), np.zeros(2))
    linear = num.M @ a + num.C @ v + num.K @ z - Q
    size = (np.abs(num.M) @ np.abs(a) + np.abs(num.C) @ np.abs(v) + np.abs(num.K) @ np.abs(z)
            + np.abs(Q))
    assert np.all(np.abs(E[:, 0] / e - linear) <= 1e-6 * size.max())
    # the Jacobians at the reference state, at rest and without forcing: K, C, M
    rest = np.zeros((2, 1))
    _, K, C, M = cart.equations(q_ref[:, None], rest, rest, np.zeros_like(s), pvals)
    for got, want in ((K, num.K), (C, num.C), (M, num.M)):
        assert np.allclose(got[:, :, 0], want, rtol=1e-9, atol=1e-9 * np.abs(want).max())
