"""The nonlinear branch: the model's outputs on every point, each point converged, the peak
of each resonance located.

Checked against (examples/duffing.toml: m = 1, c = 0.1, k = 1, k3 = 0.5, F = 0.2):

* Duffing's one-harmonic frequency-amplitude relation (Nayfeh & Mook, Nonlinear
  Oscillations, 1979, Sect. 4.1.1)
  ``[(k - m w^2 + 3/4 k3 X^2)^2 + (c w)^2] X^2 = F^2``.  With H = 1 harmonic balance solves
  exactly this, so every branch point's reported amplitude satisfies it to rounding:
  1e-12 of F^2 (before, the amplitude was a sampled peak: up to 6e-9).
* The largest amplitude of the resonance, where dX/dw = 0 on the relation, i.e.
  ``k - m w^2 + 3/4 k3 X^2 = c^2 / (2 m)`` with ``X^2 (c^4/(4 m^2) + c^2 w^2) = F^2``
  (solved here with scipy's brentq to 1e-15): the special point of kind ``peak`` gives X
  and w to 1e-9 relative (before, the largest branch point: 1.9e-5 off).
* The cart with pendulum (examples/cart_pendulum.toml) has the output phi = x2/l: its
  amplitude on every branch point and special point is the amplitude of x2 divided by l
  (to 1e-12), so are its harmonics (to 1e-9), and at small forcing its amplitude equals
  the linear sweep's phi to 1e-6.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.optimize

from conftest import EXAMPLES, run_cli
from resonant.analyses.harmonic_balance import NonlinearResponse, nonlinear_sweep
from resonant.analyses.sweep import sweep
from resonant.model import load
from resonant.system import linear_system, nonlinear_system
from resonant.analyses.nonlinear_response import nonlinear_text, plot_nonlinear_response

DUFFING = EXAMPLES / "duffing.toml"
CART = EXAMPLES / "cart_pendulum.toml"
M, C, K, K3, F = 1.0, 0.1, 1.0, 0.5, 0.2


def relation(X: np.ndarray, w: np.ndarray) -> np.ndarray:
    return ((K - M * w ** 2 + 0.75 * K3 * X ** 2) ** 2 + (C * w) ** 2) * X ** 2 - F ** 2


def closed_form_peak() -> tuple[float, float]:
    """(X, w) of the largest amplitude of the one-harmonic relation."""
    D = C ** 2 / (2 * M)

    def g(X: float) -> float:
        w2 = (K + 0.75 * K3 * X * X - D) / M
        return X * X * (D * D + C * C * w2) - F * F

    X = scipy.optimize.brentq(g, 0.1, 10.0, xtol=1e-15, rtol=1e-15)
    return X, math.sqrt((K + 0.75 * K3 * X * X - D) / M)


@pytest.fixture(scope="module")
def duffing_json() -> dict:
    status, out, err = run_cli(["sweep", DUFFING, "--param", "omega", "--from", "0.5",
                                "--to", "2.5", "--nonlinear", "--harmonics", "1", "--json"])
    assert status == 0, err
    return json.loads(out)


def test_every_branch_point_satisfies_the_relation(duffing_json: dict) -> None:
    X = np.array([p["amplitudes"]["x"] for p in duffing_json["branch"]])
    w = np.array([p["value"] for p in duffing_json["branch"]])
    assert X.size > 100
    assert np.max(np.abs(relation(X, w))) / F ** 2 < 1e-12
    assert duffing_json["residual"] < 1e-13


def test_the_peak_is_located_to_1e_9(duffing_json: dict) -> None:
    X, w = closed_form_peak()
    peaks = [p for p in duffing_json["special_points"] if p["kind"] == "peak"]
    assert len(peaks) == 1
    peak = peaks[0]
    assert peak["quantity"] == "x" and peak["stable"] is True
    assert peak["amplitudes"]["x"] == pytest.approx(X, rel=1e-9)
    assert peak["value"] == pytest.approx(w, rel=1e-9)
    # larger than every branch point, and between them in the order of the branch
    assert peak["amplitudes"]["x"] >= max(p["amplitudes"]["x"] for p in duffing_json["branch"])
    kinds = [p["kind"] for p in duffing_json["special_points"]]
    assert kinds == ["peak", "fold", "fold"]


def test_the_peak_in_text_and_plot(tmp_path) -> None:  # type: ignore[no-untyped-def]
    result = nonlinear_sweep(nonlinear_system(load(DUFFING)), "omega", 0.5, 2.5, harmonics=1,
                             points=60, linear=False)
    X, w = closed_form_peak()
    text = nonlinear_text(result)
    row = next(line for line in text.splitlines() if line.strip().startswith("peak of x"))
    assert row.split()[3:5] == [f"{w:.6g}", f"{X:.6g}"], text   # 6 digits, aligned
    assert result.peak() == (pytest.approx(w, rel=1e-9), {"x": pytest.approx(X, rel=1e-9)})
    fig = plot_nonlinear_response(result, tmp_path / "peak.png")
    stars = [line for line in fig.axes[0].lines if line.get_marker() == "*"
             and len(line.get_xdata()) == 1]
    assert len(stars) == 1 and float(stars[0].get_ydata()[0]) == pytest.approx(X, rel=1e-9)


@pytest.fixture(scope="module")
def cart() -> NonlinearResponse:
    model = load(CART).with_parameters(F0="2", r0="0.002")
    return nonlinear_sweep(nonlinear_system(model), "omega", 3.0, 12.0, harmonics=3,
                           points=40, linear=False)


def test_outputs_on_every_branch_point_and_special_point(cart: NonlinearResponse) -> None:
    l = 0.5  # noqa: E741 - the rod's length of the example
    assert list(cart.amplitudes) == ["x1", "x2", "phi"]
    assert np.allclose(cart.amplitudes["phi"], cart.amplitudes["x2"] / l, rtol=1e-12, atol=0)
    assert cart.special_points
    for point in cart.special_points:
        assert point.amplitudes["phi"] == pytest.approx(point.amplitudes["x2"] / l, rel=1e-12)
    data = json.loads(json.dumps(cart.to_dict()))
    assert all(set(p["amplitudes"]) == {"x1", "x2", "phi"} for p in data["branch"])
    for p in data["branch"]:  # the output's harmonics: those of x2 over l
        assert np.allclose(np.concatenate(p["harmonics"]["phi"]),
                           np.concatenate(p["harmonics"]["x2"]) / l, rtol=1e-9, atol=1e-14)
    assert all("phi" in p["amplitudes"] for p in data["special_points"])
    lines = {line.get_label() for line in plot_nonlinear_response(cart).axes[0].lines}
    assert r"$\varphi$ (harmonic balance, H = 3)" in lines


def test_outputs_at_small_forcing_are_the_linear_ones() -> None:
    model = load(CART).with_parameters(F0="0.005", r0="0.00001")
    result = nonlinear_sweep(nonlinear_system(model), "omega", 12.0, 30.0, harmonics=3,
                             points=20, linear=False)
    linear = sweep(linear_system(model), "omega", result.values)
    for name in ("x1", "x2", "phi"):
        assert np.allclose(result.amplitudes[name], linear.amplitudes[name], rtol=1e-6, atol=0)


def test_cli_json_of_the_cart_has_the_outputs() -> None:
    status, out, err = run_cli(["sweep", CART, "--param", "omega", "--from", "12", "--to",
                                "30", "--nonlinear", "--harmonics", "3", "--points", "20",
                                "--json"])
    assert status == 0, err
    data = json.loads(out)
    assert all("phi" in p["amplitudes"] for p in data["branch"])


def test_a_point_whose_residual_stands_out_is_polished() -> None:
    """A branch point off the branch by 1e-7 (residual about 1e-8 against 1e-15 of the
    others) is converged again by Newton's method to the residual the rest reach."""
    from resonant.analyses.harmonic_balance import _branch, _points
    from resonant.deadline import NO_DEADLINE

    system = nonlinear_system(load(DUFFING))
    hb, branch = _branch(system, "omega", 0.5, 2.5, 1, 30, NO_DEADLINE)
    i = len(branch.x) // 2
    branch.x[i] = branch.x[i] * (1 + 1e-7)
    before = float(np.abs(hb.residual(branch.x[i], branch.p[i])).max())
    _, _, amplitudes, residual = _points(hb, branch, NO_DEADLINE)
    assert before > 1e-9 and residual < 1e-13
    X = amplitudes[:, 0]
    assert np.max(np.abs(relation(X, np.array(branch.p)))) / F ** 2 < 1e-12
