"""Backbone curves (``resonant modes --nonlinear``): free vibration of the full equations.

* Duffing (examples/duffing.toml, m = 1, k = 1, k3 = 0.5), H = 1: the classical one-harmonic
  backbone w(X) = sqrt(k/m + 3/4 k3 X^2/m) to rounding (1e-12 relative);
* H = 13: the exact period of the free Duffing oscillator with peak amplitude A,
  T = 4 * int_0^A dx / sqrt(2 (U(A) - U(x)) / m) (scipy quad; x = A sin(theta) removes
  the end singularity), to 1e-11 relative;
* the fictitious damping of the formulation comes out zero (< 1e-12);
* the cart-pendulum's modes soften (the pendulum's frequency falls with amplitude).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.integrate

from conftest import EXAMPLES, run_cli
from resonant.analyses.backbone import Backbones, backbone
from resonant.api import load
from resonant.errors import AnalysisError
from resonant.system import nonlinear_system

DUFFING = EXAMPLES / "duffing.toml"
M, K, K3 = 1.0, 1.0, 0.5


def test_duffing_h1_classical_backbone() -> None:
    result = backbone(nonlinear_system(load(DUFFING)), amplitude=2.0, harmonics=1, points=40)
    (curve,) = result.curves
    X = curve.amplitude
    expected = np.sqrt(K / M + 0.75 * K3 * X ** 2 / M)
    assert np.max(np.abs(curve.frequencies / expected - 1)) < 1e-12
    assert curve.damping < 1e-12 and result.residual < 1e-12
    assert curve.linear_frequency == pytest.approx(1.0)


def _exact_frequency(A: float) -> float:
    def U(x: float) -> float:
        return K * x * x / 2 + K3 * x ** 4 / 4

    def integrand(theta: float) -> float:  # x = A sin(theta)
        x = A * math.sin(theta)
        return A * math.cos(theta) / math.sqrt(2 * (U(A) - U(x)) / M)

    quarter, _ = scipy.integrate.quad(integrand, 0, math.pi / 2, epsabs=1e-14, epsrel=1e-13)
    return 2 * math.pi / (4 * quarter)


def test_duffing_many_harmonics_exact_period() -> None:
    result = backbone(nonlinear_system(load(DUFFING)), amplitude=2.0, harmonics=13, points=10)
    (curve,) = result.curves
    for c, w, peak in zip(curve.coefficients[:, 0], curve.frequencies, curve.amplitudes["x"]):
        A = float(c[0] + c[1::2].sum())  # x(0): the phase condition puts the peak at t = 0
        assert peak == pytest.approx(A, rel=1e-8)
        assert w == pytest.approx(_exact_frequency(A), rel=1e-11)


def test_softening_pendulum_and_views(tmp_path) -> None:  # type: ignore[no-untyped-def]
    result = load(EXAMPLES / "cart_pendulum.toml").backbone(amplitude=0.5, points=10)
    assert isinstance(result, Backbones) and len(result.curves) == 2
    second = result.curves[1]
    assert second.frequencies[-1] < second.linear_frequency  # softening
    assert np.all(np.diff(second.frequencies) < 0)
    data = json.loads(json.dumps(result.to_dict(), allow_nan=False))
    assert len(data["backbones"]) == 2 and "frequencies" in data["backbones"][0]
    with pytest.raises(ValueError):
        second.frequencies[0] = 1.0
    fig = result.plot(tmp_path / "bb.png")
    assert (tmp_path / "bb.png").stat().st_size > 1000 and fig.axes
    assert "mode 2" in result.summary()


def test_cli() -> None:
    status, out, err = run_cli(["modes", DUFFING, "--nonlinear", "--amplitude", "1",
                                "--harmonics", "1", "--points", "4", "--json"])
    assert status == 0, err
    data = json.loads(out)
    assert data["backbones"][0]["frequencies"][-1] == pytest.approx(math.sqrt(1.375),
                                                                     rel=1e-12)
    status, out, err = run_cli(["modes", DUFFING, "--nonlinear", "--points", "5"])
    assert status == 0 and "mode 1" in out
    status, out, err = run_cli(["modes", DUFFING, "--harmonics", "3"])
    assert status == 3 and "--nonlinear" in err


def test_errors() -> None:
    with pytest.raises(AnalysisError, match="amplitude"):
        backbone(nonlinear_system(load(DUFFING)), amplitude=-1.0)
    with pytest.raises(AnalysisError, match="mode 3"):
        backbone(nonlinear_system(load(DUFFING)), amplitude=1.0, modes=[3])


def test_a_halved_step_grows_back(monkeypatch):
    """After Newton fails once and the amplitude step is halved, the step grows again when
    Newton converges: following a backbone takes a few Newton iterations per point, not a
    creep of tiny steps (the two-DOF cubic model: 36,000 iterations before, ~500 now)."""
    from resonant.analyses import backbone as module

    calls = []
    original = module._Free.system

    def counted(self, y, A):
        calls.append(A)
        return original(self, y, A)

    monkeypatch.setattr(module._Free, "system", counted)
    curves = load(EXAMPLES / "two_dof_cubic.toml").backbone(harmonics=3, points=6)
    assert [len(c.frequencies) for c in curves.curves] == [6, 6]
    assert len(calls) < 2000, len(calls)
