"""A ``[matrices]`` model with ``[[nonlinear]]`` elements is a NonlinearSystem.

Two routes to one answer: the same 2-DOF system with a cubic spring between the masses,
once as ``[matrices]`` with a ``[[nonlinear]]`` force, once by its energies (Lagrange's
equations derived by resonant): their full equations agree at random states, and so do
the time integration, the backbone curves and the harmonic balance; on the matrix model
the full balance agrees with the balance condensed onto the element's coordinates.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from resonant.analyses.backbone import backbone
from resonant.analyses.condensed import condensed_sweep
from resonant.analyses.harmonic_balance import full_sweep, nonlinear_sweep
from resonant.analyses.simulate import simulate
from resonant.api import loads
from resonant.errors import AnalysisError
from resonant.system import ElementSystem, EnergySystem, nonlinear_system
from test_condensed import DUFFING_ENERGY, DUFFING_MATRICES

# the same 2-DOF system twice (tests/test_condensed.py)
MATRICES, ENERGY = DUFFING_MATRICES, DUFFING_ENERGY


@pytest.fixture(scope="module")
def systems() -> tuple[ElementSystem, EnergySystem]:
    matrix, energy = nonlinear_system(loads(MATRICES)), nonlinear_system(loads(ENERGY))
    assert isinstance(matrix, ElementSystem) and isinstance(energy, EnergySystem)
    return matrix, energy


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(-2, 2), min_size=6, max_size=6), st.floats(0, 20),
       st.sampled_from([0.0, 1.0]))
def test_equations_equal_those_of_the_energy_model(systems, state, t, damping):
    """E and its three derivatives at a random state, time and dissipation factor (1e-12)."""
    matrix, energy = systems
    q, qd, qdd = (np.array(state[i:i + 2])[:, None] for i in (0, 2, 4))
    pvals = matrix.parameter_values
    mine = matrix.equations(q, qd, qdd, matrix.forcing(np.array([t]), pvals), pvals, damping)
    theirs = energy.equations(q, qd, qdd, energy.forcing(np.array([t]), pvals), pvals,
                              damping)
    for a, b in zip(mine, theirs):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)


def test_simulation_equals_that_of_the_energy_model():
    """The nonlinear time integration of both models: the same steady amplitudes (1e-6)."""
    options = dict(duration=60.0, nonlinear=True, start="rest")
    mine = simulate(loads(MATRICES).linearize(), **options)
    theirs = simulate(loads(ENERGY).linearize(), **options)
    for name in ("q1", "q2"):
        assert mine.steady_amplitudes[name] == pytest.approx(theirs.steady_amplitudes[name],
                                                             rel=1e-6)


def test_backbones_equal_those_of_the_energy_model():
    """The free-vibration backbone curves of both models (1e-8)."""
    mine = backbone(nonlinear_system(loads(MATRICES)), 0.5, harmonics=3, points=8)
    theirs = backbone(nonlinear_system(loads(ENERGY)), 0.5, harmonics=3, points=8)
    assert len(mine.curves) == len(theirs.curves) == 2
    for a, b in zip(mine.curves, theirs.curves):
        np.testing.assert_allclose(a.frequencies, b.frequencies, rtol=1e-8)


def test_full_balance_equals_the_condensed_one():
    """Harmonic balance of the matrix model's full equations against the balance
    condensed onto the element's coordinates: the same folds (1e-8 relative)."""
    model = loads(MATRICES)
    full = full_sweep(nonlinear_system(model.linearize()), "w", 0.4, 2.2, harmonics=5, points=60,
                      linear=False)
    condensed = condensed_sweep(nonlinear_system(model), "w", 0.4, 2.2, harmonics=5, points=60,
                                observe=["q1"], linear=False)
    folds = [sorted(s.value for s in r.special_points if s.kind == "fold")
             for r in (full, condensed)]
    assert len(folds[0]) == len(folds[1]) >= 2
    np.testing.assert_allclose(folds[0], folds[1], rtol=1e-8)


def _chain(n: int) -> str:
    """n unit masses in a fixed-free chain of unit springs, damping 0.02, a cubic spring
    from the last to the ground, the load at the last."""
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    rows = lambda A: str(A.tolist())  # noqa: E731
    load = [0.0] * (n - 1) + [0.03]
    return (f"[parameters]\nw = 0.5\n[matrices]\nM = {rows(np.eye(n))}\nK = {rows(K)}\n"
            f"C = {rows(0.02 * np.eye(n))}\n[[harmonic]]\nomega = \"w\"\nF_C = {load}\n"
            f"[[nonlinear]]\nname = \"cubic\"\ncoordinates = [\"q{n}\"]\n"
            f"force = \"0.5*q{n}^3\"\n")


@pytest.mark.parametrize("text, band, H", [
    (MATRICES, (0.4, 2.2), 5),
    (_chain(3), (0.3, 0.7), 3),
])
def test_both_balances_of_a_matrix_model_give_one_branch(text, band, H):
    """The route :func:`~resonant.analyses.harmonic_balance.nonlinear_sweep` takes for a
    matrix model (the balance condensed onto the element's coordinates) against the full
    balance of every coordinate (docs/nonlinear.md, "Which balance"): the same folds
    (1e-7 relative) and bifurcations (1e-3: located between points by the multipliers,
    measured 6e-5 apart for the Neimark-Sacker point near 0.676), the same peak of the
    element's coordinate (1e-7), and the same stability verdict at every point of one branch that lies on the other (amplitude
    within 1e-6 at the same parameter value) away from the folds and bifurcations."""
    system = nonlinear_system(loads(text))
    full = full_sweep(system, "w", *band, harmonics=H, points=50, linear=False)
    chosen = nonlinear_sweep(system, "w", *band, harmonics=H, points=50, linear=False)
    q = chosen.coordinates[0]
    special = [[s for s in r.special_points if s.kind != "peak"] for r in (full, chosen)]
    assert [s.kind for s in special[0]] == [s.kind for s in special[1]]
    assert any(s.kind == "fold" for s in special[0])
    for a, b in zip(*special):  # a fold by the tangent, a bifurcation by the multipliers
        assert a.value == pytest.approx(b.value, rel=1e-7 if a.kind == "fold" else 1e-3)
    peaks = [max(s.value for s in r.special_points if s.kind == "peak" and s.quantity == q)
             for r in (full, chosen)]
    assert peaks[0] == pytest.approx(peaks[1], rel=1e-7)
    assert (~chosen.stable).any()
    near = np.array([s.value for s in special[0]])
    compared = 0
    for p, a, ok in zip(chosen.values, chosen.amplitudes[q], chosen.stable):
        if np.min(np.abs(near - p)) < 0.01 * abs(p):
            continue
        # the full branch's amplitude at p on each of its pieces through p
        v, b = full.values, full.amplitudes[q]
        for i in np.flatnonzero((v[:-1] - p) * (v[1:] - p) <= 0):
            t = (p - v[i]) / (v[i + 1] - v[i]) if v[i + 1] != v[i] else 0.0
            if abs(b[i] + t * (b[i + 1] - b[i]) - a) <= 1e-3 * a and full.stable[i] == \
                    full.stable[i + 1]:
                assert full.stable[i] == ok, f"w = {p}"
                compared += 1
    assert compared >= 20


def _full_equations(system):
    q = np.zeros((system.n, 1))
    pvals = system.parameter_values
    return system.equations(q, q, q, system.forcing(np.zeros(1), pvals), pvals)


def test_friction_element_is_refused_with_its_name():
    """A friction element's system is its local elements (the condensed balance takes
    it); its full equations, which the time integration and the backbones need, are
    refused with the element's name."""
    text = MATRICES.replace('force = "2*(q2 - q1)^3"',
                            'kind = "friction"\nstiffness = 10\nslip_force = 0.1')
    system = nonlinear_system(loads(text))
    assert system.local_elements is not None
    with pytest.raises(AnalysisError, match="nonlinear 'hardening'.*history"):
        _full_equations(system)
    with pytest.raises(AnalysisError, match="nonlinear 'hardening'.*history"):
        loads(text).simulate(1.0, nonlinear=True)


def test_a_large_model_is_sent_to_the_condensed_balance():
    n = 401
    text = (f"[matrices]\nM = {np.eye(n).tolist()}\nK = {(2 * np.eye(n)).tolist()}\n"
            "[[nonlinear]]\ncoordinates = [\"q1\"]\nforce = \"q1^3\"\n")
    system = nonlinear_system(loads(text))
    assert system.local_elements is not None
    with pytest.raises(AnalysisError, match="up to 400 coordinates.*condensed"):
        _full_equations(system)


def test_a_matrix_model_without_elements_has_no_nonlinear_equations():
    text = MATRICES.split("[[nonlinear]]")[0]
    with pytest.raises(AnalysisError, match="without \\[\\[nonlinear\\]\\] elements"):
        nonlinear_system(loads(text))


def test_study_nonlinear_amplitude_equals_that_of_the_energy_model():
    """``nonlinear_amplitude:`` in a study (the slow sweep at each sample's values) of both
    models: the same numbers (1e-9)."""
    from resonant.studies import StudyJob, collect, engine_for, request

    tables = []
    for text in (MATRICES, ENERGY):
        text = text.replace("w = 0.5", "w = 0.5\nk3 = 2").replace("2*(q2 - q1)",
                                                                   "k3*(q2 - q1)")
        model = loads(text)
        spec = request(model, {"k3": [1.0, 2.0]}, ["nonlinear_amplitude:q1"], design="grid",
                       band={"parameter": "w", "from": 0.4, "to": 2.2})
        tables.append(collect(StudyJob.of(model, spec, text=text), engine_for(0)).table)
    assert list(tables[0]["status"]) == ["ok", "ok"]
    np.testing.assert_allclose(tables[0]["nonlinear_amplitude:q1"],
                               tables[1]["nonlinear_amplitude:q1"], rtol=1e-9)
