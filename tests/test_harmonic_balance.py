"""Nonlinear steady state: harmonic balance, continuation through folds, stability.

Checked against (examples/duffing.toml: m = 1, c = 0.1, k = 1, k3 = 0.5, F = 0.2):

* Duffing's one-harmonic amplitude relation (Nayfeh & Mook, Nonlinear Oscillations,
  1979, Sect. 4.1.1) [(k - m w^2 + 3/4 k3 X^2)^2 + (c w)^2] X^2 = F^2: with H = 1 the
  harmonic balance solves exactly this, so it holds to rounding (1e-10 relative) at
  every branch point; its two folds (dw/dX = 0 of the relation, solved here with
  scipy) are located to 1e-8.
* resonant's own nonlinear simulation (rtol 1e-9, 240 s of decay from the harmonic
  balance solution): the stable branches agree to 1e-6 of the amplitude with H chosen
  automatically (the neglected harmonics are below 1e-6); a run started on the
  middle branch leaves it (unstable).
* Floquet multipliers from the monodromy matrix of the variational equation
  y'' + c y' + (k + 3 k3 x(t)^2) y = 0 integrated over one period (scipy, rtol 1e-12)
  agree with Hill's method to 1e-6.
* Small forcing (F = 1e-6): the branch equals the linear sweep to 1e-6 relative, and its
  peak lies at the linear resonance sqrt(k/m - c^2/(2 m^2)).

Since the peaks are special points (kind "peak", one per resonance of x), the lists of
special points expected here include them (changed on purpose with the peak points).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.integrate
import scipy.optimize

from conftest import EXAMPLES, run_cli
from resonant.analyses.harmonic_balance import NonlinearResponse, nonlinear_sweep
from resonant.analyses.sweep import sweep
from resonant.api import load, loads
from resonant.errors import AnalysisError
from resonant.system import nonlinear_system

DUFFING = EXAMPLES / "duffing.toml"
M, C, K, K3, F = 1.0, 0.1, 1.0, 0.5, 0.2


def relation(X: np.ndarray, w: np.ndarray, F: float = F) -> np.ndarray:
    return ((K - M * w ** 2 + 0.75 * K3 * X ** 2) ** 2 + (C * w) ** 2) * X ** 2 - F ** 2


def analytic_folds(F: float = F) -> list[tuple[float, float]]:
    def equations(v: np.ndarray) -> list[float]:
        X, w = v
        a = K - M * w * w + 0.75 * K3 * X * X
        return [float(relation(X, w, F)),
                2 * a * 1.5 * K3 * X ** 3 + 2 * (a * a + (C * w) ** 2) * X]
    return [tuple(scipy.optimize.fsolve(equations, guess, xtol=1e-13))  # type: ignore
            for guess in ([1.47, 1.35], [0.66, 1.20])]


@pytest.fixture(scope="module")
def model():  # type: ignore[no-untyped-def]
    return load(DUFFING)


@pytest.fixture(scope="module")
def h1(model) -> NonlinearResponse:  # type: ignore[no-untyped-def]
    return model.nonlinear_sweep("omega", 0.5, 2.5, harmonics=1, points=101)


@pytest.fixture(scope="module")
def auto(model) -> NonlinearResponse:  # type: ignore[no-untyped-def]
    return model.nonlinear_sweep("omega", 0.5, 2.5, points=101)


def test_h1_satisfies_the_classical_amplitude_relation(h1: NonlinearResponse) -> None:
    c = h1.coefficients[:, 0]
    X = np.hypot(c[:, 1], c[:, 2])
    assert np.max(np.abs(relation(X, h1.values)) / F ** 2) < 1e-10
    assert np.max(np.abs(c[:, 0])) < 1e-12          # no constant part for an odd spring
    assert h1.residual < 1e-12
    assert h1.values[0] == 0.5 and h1.values[-1] == 2.5


def test_h1_folds_match_the_relation(h1: NonlinearResponse) -> None:
    folds = [p for p in h1.special_points if p.kind == "fold"]
    # and one peak (of x: tests/test_nonlinear_outputs_and_peaks.py checks it)
    assert len(folds) == 2 and [p.kind for p in h1.special_points].count("peak") == 1
    assert len(h1.special_points) == 3
    for point, (X, w) in zip(folds, analytic_folds()):
        assert point.value == pytest.approx(w, abs=1e-8)
        assert point.amplitudes["x"] == pytest.approx(X, abs=1e-6)
    # the branch overhangs: the parameter goes back between the folds
    assert np.any(np.diff(h1.values) < 0)
    # stable - unstable (middle branch) - stable
    changes = np.flatnonzero(np.diff(h1.stable.astype(int)))
    assert len(changes) == 2
    middle = h1.stable[changes[0] + 1:changes[1] + 1]
    assert not middle.any()


def test_harmonics_chosen_from_their_decay(auto: NonlinearResponse) -> None:
    assert auto.harmonics >= 7
    assert auto.truncation < 1e-6
    assert auto.residual < 1e-12
    kinds = [p.kind for p in auto.special_points]
    assert kinds == ["peak", "fold", "fold"]  # the peak of x just before the upper fold


def _initial(result: NonlinearResponse, i: int) -> dict[str, str]:
    c = result.coefficients[i, 0]
    k = np.arange(1, result.harmonics + 1)
    q0 = c[0] + c[1::2].sum()
    v0 = result.base_frequencies[i] * (k * c[2::2]).sum()
    return {"x": repr(float(q0)), "x'": repr(float(v0))}


@pytest.mark.parametrize("omega", [1.25, 1.3])
def test_stable_branches_agree_with_simulation(model, auto: NonlinearResponse,  # type: ignore
                                               omega: float) -> None:
    """Inside the overhang: three solutions; the outer two stable and confirmed by a long
    simulation started on them (1e-6), the middle one unstable (the run leaves it)."""
    crossing = [i for i in range(auto.values.size - 1)
                if (auto.values[i] - omega) * (auto.values[i + 1] - omega) <= 0]
    assert len(crossing) == 3
    assert [bool(auto.stable[i]) for i in crossing] == [True, False, True]
    for i in crossing:
        at = model.with_parameters(omega=repr(float(auto.values[i])))
        sim = at.simulate(nonlinear=True, initial=_initial(auto, i), progress=False)
        hb = float(auto.amplitudes["x"][i])
        difference = abs(sim.steady_amplitudes["x"] / hb - 1)
        if auto.stable[i]:
            assert difference < 1e-6
        else:
            assert difference > 1e-4


def test_hill_agrees_with_floquet_integration(auto: NonlinearResponse) -> None:
    H = auto.harmonics
    k = np.arange(1, H + 1)
    for i in (10, int(np.argmax(auto.amplitudes["x"])) + 3, auto.values.size - 10):
        c = auto.coefficients[i, 0]
        W = auto.base_frequencies[i]

        def rhs(t: float, y: np.ndarray, c: np.ndarray = c, W: float = W) -> np.ndarray:
            x = float(c[0] + c[1::2] @ np.cos(k * W * t) + c[2::2] @ np.sin(k * W * t))
            A = np.array([[0.0, 1.0], [-(K + 3 * K3 * x ** 2) / M, -C / M]])
            return (A @ y.reshape(2, 2)).ravel()

        sol = scipy.integrate.solve_ivp(rhs, (0, 2 * np.pi / W), np.eye(2).ravel(),
                                        rtol=1e-12, atol=1e-14, method="DOP853")
        mu = np.linalg.eigvals(sol.y[:, -1].reshape(2, 2))
        assert np.sort(np.abs(mu)) == pytest.approx(np.sort(np.abs(auto.multipliers[i])),
                                                    abs=1e-6)
        assert bool(np.all(np.abs(mu) <= 1 + 1e-6)) == bool(auto.stable[i])


def test_small_forcing_gives_the_linear_sweep(model) -> None:  # type: ignore[no-untyped-def]
    small = model.with_parameters(F="1e-6")
    result = small.nonlinear_sweep("omega", 0.5, 2.5, harmonics=3, points=60)
    linear = sweep(small.linearize(), "omega", result.values)
    assert np.max(np.abs(result.amplitudes["x"] / linear.amplitudes["x"] - 1)) < 1e-6
    # the one special point is the peak of the linear resonance, sqrt(k/m - c^2/(2 m^2))
    assert result.stable.all() and [p.kind for p in result.special_points] == ["peak"]
    assert result.special_points[0].value == pytest.approx(math.sqrt(K / M - C ** 2 / 2 / M ** 2),
                                                           abs=1e-6)


def test_any_parameter_forcing_amplitude(model) -> None:  # type: ignore[no-untyped-def]
    """Continuation in F at omega = 1.3: the jump (hysteresis) in the forcing amplitude."""
    at = model.with_parameters(omega="1.3")
    result = at.nonlinear_sweep("F", 0.01, 0.4, harmonics=1, points=80)
    c = result.coefficients[:, 0]
    X = np.hypot(c[:, 1], c[:, 2])
    w = 1.3
    lhs = ((K - M * w ** 2 + 0.75 * K3 * X ** 2) ** 2 + (C * w) ** 2) * X ** 2
    assert np.max(np.abs(lhs / result.values ** 2 - 1)) < 1e-10
    assert [p.kind for p in result.special_points] == ["fold", "fold"]


def test_result_is_frozen_and_serializes(h1: NonlinearResponse, tmp_path) -> None:  # type: ignore
    with pytest.raises(ValueError):
        h1.values[0] = 1.0
    with pytest.raises(ValueError):
        h1.amplitudes["x"][0] = 1.0
    data = json.loads(json.dumps(h1.to_dict(), allow_nan=False))
    for key in ("branch", "special_points", "harmonics", "residual", "values", "amplitudes"):
        assert key in data
    point = data["branch"][0]
    assert set(point) == {"value", "amplitudes", "stable", "harmonics"}
    assert len(point["harmonics"]["x"]) == 2 and len(point["harmonics"]["x"][1]) == 2
    assert [p["kind"] for p in data["special_points"]] == ["peak", "fold", "fold"]
    assert "fold" in h1.summary() and "peak of the stable branch" in h1.summary()
    h1.to_csv(tmp_path / "branch.csv")
    assert (tmp_path / "branch.csv").read_text().splitlines()[0] == "omega,stable,x"
    fig = h1.plot(tmp_path / "curve.png")
    assert (tmp_path / "curve.png").stat().st_size > 1000
    assert fig.axes[0].get_xlabel() == r"excitation frequency $\omega$ [rad/s]"


def test_cli(tmp_path) -> None:  # type: ignore[no-untyped-def]
    status, out, err = run_cli(["sweep", DUFFING, "--param", "omega", "--from", "0.5",
                                "--to", "2.5", "--nonlinear", "--harmonics", "3",
                                "--points", "40", "--json", "--csv", tmp_path / "b.csv",
                                "--plot", tmp_path / "b.svg"])
    assert status == 0, err
    data = json.loads(out)
    assert data["harmonics"] == 3 and [p["kind"] for p in data["special_points"]] == \
        ["peak", "fold", "fold"]
    assert (tmp_path / "b.svg").exists() and (tmp_path / "b.csv").exists()
    status, out, err = run_cli(["sweep", DUFFING, "--param", "omega", "--from", "0.5",
                                "--to", "2.5", "--nonlinear", "--harmonics", "3",
                                "--points", "40"])
    assert status == 0 and "fold" in out and "peak of the stable branch" in out
    status, out, err = run_cli(["sweep", DUFFING, "--param", "omega", "--from", "0.5",
                                "--to", "2.5", "--harmonics", "3"])
    assert status == 3 and "--nonlinear" in err


def test_errors(model) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(AnalysisError, match="not a parameter"):
        model.nonlinear_sweep("zeta", 0.5, 1.0)
    free = loads('[parameters]\nk = 1\n[coordinates]\nx = ""\n[signals]\nr = "exp(-t)"\n'
                 '[energy]\nT = "x\'^2/2"\nU = "k*x^2/2"\n[[force]]\ngeneralized = { x = "r" }')
    with pytest.raises(AnalysisError, match="periodic"):
        nonlinear_sweep(nonlinear_system(free.linearize()), "k", 1.0, 2.0)
    assert math.isfinite(model.parameter_values["omega"])


def test_dependent_parameter_follows() -> None:
    """A parameter defined from the swept one (W = omega) follows it along the branch."""
    # the example gives units: W = "omega" then takes rad/s from omega
    text = DUFFING.read_text().replace('omega = "1 rad/s"\n', 'omega = "1 rad/s"\nW = "omega"\n') \
        .replace("F*cos(omega*t)", "F*cos(W*t)")
    result = loads(text).nonlinear_sweep("omega", 0.5, 2.5, harmonics=1, points=60,
                                         linear=False)
    folds = [p for p in result.special_points if p.kind != "peak"]
    for point, (_, w) in zip(folds, analytic_folds(), strict=True):
        assert point.kind == "fold" and point.value == pytest.approx(w, abs=1e-8)


def test_the_steps_follow_the_amplitude_across_a_resonance() -> None:
    """The response of the cubic absorber grows 200-fold from the start of the range to its
    resonance; the step's ceiling follows the present amplitude, so the branch takes a
    few hundred points for the 150 asked (4,640 when the ceiling stayed in units of the
    start point's amplitude).  Its folds are those of the same balance (H = 3) asked for
    1,500 points (1,963 taken), to 1e-9: located by refinement, not by the step."""
    model = load(EXAMPLES / "two_dof_cubic.toml")
    low = 0.8725959346977146
    branch = nonlinear_sweep(nonlinear_system(model), "omega", 0.5 * low, 2.5 * low, harmonics=3,
                             points=150)
    assert len(branch.values) < 600
    folds = sorted(p.value for p in branch.special_points if p.kind == "fold")
    assert folds == pytest.approx([0.9556022338876, 0.9693761728603], rel=1e-9)
