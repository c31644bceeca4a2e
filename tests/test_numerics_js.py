"""The page's JavaScript numerics (views/explore_assets/numerics.js) against the modal kernel
(resonant.modal), outside the browser: node runs the page's own file on a set of golden
cases (every small bundled example at its parameter values, and constructed cases: rigid-body
modes, an unstable equilibrium, gyroscopic and circulatory terms, repeated frequencies,
non-proportional damping) through tests/js/numerics_cases.js, which loads it with ``require``.

Tolerances: the two sides are different algorithms (cyclic Jacobi and EISPACK's hqr on the page,
LAPACK here), so they agree to rounding, not bit for bit: eigenvalues to 1e-9 of the largest,
mode shapes (largest component +1, simple modes only) and damping ratios to 1e-8.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import resonant
from resonant import modal
from resonant.system.stability import classify

ROOT = Path(__file__).parents[1]
DRIVER = Path(__file__).parent / "js" / "numerics_cases.js"
NODE = shutil.which("node") or shutil.which("nodejs")
EXAMPLES = ["two_dof_free", "cart_pendulum", "absorber", "tuned_mass_damper", "shear_building6",
            "chain3_damped", "pendulum", "base_excitation", "rotating_unbalance",
            "damper_excitation", "two_dof_cubic"]

pytestmark = pytest.mark.skipif(NODE is None, reason="node is not installed")


def _example(name: str) -> dict:
    eom = resonant.load(ROOT / "examples" / f"{name}.toml").linearize().numeric()
    M, C, K = (np.asarray(a.toarray() if hasattr(a, "toarray") else a, dtype=float)
               for a in (eom.M, eom.C, eom.K))
    return {"name": name, "M": M, "C": C, "K": K}


def _constructed() -> list[dict]:
    chain = np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    rng = np.random.default_rng(11)
    a = rng.standard_normal((4, 4))
    spd = a @ a.T + 4 * np.eye(4)
    return [
        {"name": "free-free chain (a rigid-body mode)", "M": np.diag([1.0, 2.0, 1.0]),
         "C": 0.01 * chain, "K": 100 * chain},
        {"name": "inverted pendulum (unstable)", "M": np.eye(2), "C": np.zeros((2, 2)),
         "K": np.array([[-3.0, 1.0], [1.0, 2.0]])},
        {"name": "gyroscopic rotor", "M": np.eye(2), "C": np.array([[0.0, 4.0], [-4.0, 0.0]]),
         "K": np.diag([100.0, 150.0])},
        {"name": "circulatory (follower) force", "M": np.eye(2), "C": 0.05 * np.eye(2),
         "K": np.array([[2.0, -1.5], [-1.0, 1.0]]) * 50},
        {"name": "repeated frequencies", "M": np.eye(3), "C": 0.2 * np.eye(3),
         "K": np.diag([4.0, 4.0, 9.0])},
        {"name": "non-proportional damping", "M": spd, "C": np.diag([0.0, 0.3, 0.0, 1.2]),
         "K": 50 * (spd + np.diag([1.0, 5.0, 9.0, 2.0]))},
        {"name": "wide range of scales", "M": np.diag([1e-3, 1.0, 1e3]),
         "C": np.zeros((3, 3)), "K": np.array([[1e3, -1e2, 0.0], [-1e2, 1e4, -1e3],
                                                  [0.0, -1e3, 1e6]])},
    ]


@pytest.fixture(scope="module")
def cases_and_page():
    cases = [_example(name) for name in EXAMPLES] + _constructed()
    payload = [{"name": c["name"], "n": len(c["M"]), "M": c["M"].ravel().tolist(),
                "C": c["C"].ravel().tolist(), "K": c["K"].ravel().tolist()} for c in cases]
    done = subprocess.run([NODE, str(DRIVER)], input=json.dumps(payload), capture_output=True,
                          text=True, timeout=120, check=True)
    return cases, json.loads(done.stdout)


def _ids():
    return EXAMPLES + [c["name"] for c in _constructed()]


@pytest.mark.parametrize("index", range(len(_ids())), ids=_ids())
def test_page_numerics_agree_with_the_kernel(cases_and_page, index):
    cases, page = cases_and_page
    case, js = cases[index], page[index]
    M, C, K = case["M"], case["C"], case["K"]
    lam, phi = modal.undamped_eigen(M, K)
    scale = max(np.abs(lam).max(initial=0.0), 1e-300)
    assert np.asarray(js["lambdas"]) == pytest.approx(lam, abs=1e-9 * scale)
    omegas = modal.frequencies_from_eigenvalues(lam)
    assert np.asarray(js["frequencies"]) == pytest.approx(omegas, abs=1e-9 * omegas.max(
        initial=1.0))
    # mode shapes of the simple modes, largest component +1
    for j in range(len(lam)):
        gaps = np.abs(np.delete(lam, j) - lam[j])
        if gaps.size and gaps.min() <= 1e-6 * scale:
            continue
        shape = phi[:, j] / phi[np.argmax(np.abs(phi[:, j])), j]
        page_shape = np.asarray(js["shapes"][j])
        if np.sum(np.abs(np.abs(shape) - 1) <= 1e-9) > 1:   # largest component tied: +-1
            page_shape = page_shape * np.sign(page_shape @ shape)
        assert page_shape == pytest.approx(shape, abs=1e-8)
    s = modal.order(modal.state_eigenvalues(M[None], C[None], K[None])[0])
    page_s = modal.order(np.asarray(js["state"]["re"]) + 1j * np.asarray(js["state"]["im"]))
    size = max(1.0, float(np.abs(s).max()))
    # a multiple zero (a rigid-body mode, a Jordan block) is known to sqrt(eps) only
    near_zero = np.abs(s) <= modal.ZERO_STATE * size
    assert np.abs(page_s - s)[~near_zero].max(initial=0.0) <= 1e-9 * size
    assert np.all(np.abs(page_s[near_zero]) <= modal.ZERO_STATE * size)
    assert js["stability"] == classify(s)
    zeta, damped = modal.damping_ratios(s)
    assert np.asarray(js["damping_ratios"]) == pytest.approx(zeta, abs=1e-8)
    assert np.asarray(js["damped_frequencies"]) == pytest.approx(damped, abs=1e-9 * size)


def test_the_cases_cover_every_verdict(cases_and_page):
    _, page = cases_and_page
    assert {p["stability"] for p in page} == {"asymptotically stable", "marginally stable",
                                               "unstable"}


def test_the_driver_loads_the_page_code_without_eval():
    text = DRIVER.read_text() + (ROOT / "src/resonant/views/explore_assets/numerics.js"
                                 ).read_text()
    assert not re.search(r"(?<![\w.])eval\s*\(|new\s+Function\s*\(", text)
