"""Modal analysis (resonant.modes, ``resonant modes``) against closed-form results.

Sources of the reference values:
- two equal masses between three equal springs: Rao, Mechanical Vibrations, 6th ed.,
  Sect. 5.3 (Example 5.1 with m1 = m2, k1 = k2 = k3): omega = sqrt(k/m), sqrt(3k/m),
  modes [1, 1] and [1, -1];
- double pendulum, equal point masses m and lengths l, absolute angles: Meirovitch,
  Fundamentals of Vibrations, Sect. 7 (also Thomson & Dahleh, Theory of Vibration,
  Sect. 6.2): omega^2 = (2 -+ sqrt 2) g/l, amplitude ratios phi2/phi1 = +-sqrt 2;
- fixed-free chain of n equal masses and springs: Rao, Sect. 6 / Meirovitch, Sect. 8:
  omega_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2n + 1)));
- Rayleigh damping C = a M + b K: zeta_j = a/(2 omega_j) + b omega_j/2 (Rao, Sect. 6.13).
Tolerances are stated per test; they are rounding-level (1e-9 .. 1e-12 relative) since
every reference is exact.
"""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES, run_cli

from resonant.api import load, loads
from resonant.analyses.modes import modal_damping_ratios
from resonant.analyses.modes import modes as _modes

sys.path.insert(0, str(EXAMPLES))
from make_chain import chain_matrices, write_chain  # noqa: E402


def modes(model, *args, **kwargs):
    """The analysis takes the model's linear system (analyses take a LinearSystem)."""
    return _modes(model.linearize(), *args, **kwargs)


def chain_frequencies(n: int, k: float, m: float) -> np.ndarray:
    j = np.arange(1, n + 1)
    return 2 * math.sqrt(k / m) * np.sin((2 * j - 1) * math.pi / (2 * (2 * n + 1)))


def chain_model(n: int, m: float, k: float, damping: tuple[float, float] | None = None) -> str:
    """A fixed-free chain as an energy model (TOML text)."""
    coords = "\n".join(f'x{i} = "mass {i}"' for i in range(1, n + 1))
    springs = " + ".join(["x1^2"] + [f"(x{i} - x{i - 1})^2" for i in range(2, n + 1)])
    T = " + ".join(f"x{i}'^2" for i in range(1, n + 1))
    text = f'[parameters]\nm = {m}\nk = {k}\n[coordinates]\n{coords}\n[energy]\n' \
           f'T = "m*({T})/2"\nU = "k*({springs})/2"\n'
    if damping:
        # Rayleigh dissipation of C = a M + b K: a m sum x'^2/2 + b k (springs in x')/2
        a, b = damping
        velocities = " + ".join(f"x{i}'^2" for i in range(1, n + 1))
        spring_rates = " + ".join(["x1'^2"] + [f"(x{i}' - x{i - 1}')^2" for i in range(2, n + 1)])
        text += f'D = "{a}*m*({velocities})/2 + {b}*k*({spring_rates})/2"\n'
    return text


def test_two_dof_free_closed_form():
    """Rao Sect. 5.3: omega = sqrt(k/m), sqrt(3k/m); shapes [1, 1], [1, -1] (rel 1e-12)."""
    result = modes(load(EXAMPLES / "two_dof_free.toml"))
    k, m = 2000.0, 5.0
    np.testing.assert_allclose(result.natural_frequencies,
                               [math.sqrt(k / m), math.sqrt(3 * k / m)], rtol=1e-12)
    np.testing.assert_allclose(result.mode_shapes.T, [[1, 1], [1, -1]], atol=1e-12)
    # mass-normalised: phi^T M phi = I
    phi = result.mass_normalised_modes
    np.testing.assert_allclose(phi.T @ (m * np.eye(2)) @ phi, np.eye(2), atol=1e-12)
    assert result.stability == "marginally stable"
    assert result.proportional_damping and not result.damped
    np.testing.assert_allclose(result.frequencies_hz, result.natural_frequencies / (2 * math.pi))


DOUBLE_PENDULUM = """
title = "double pendulum, absolute angles"
[parameters]
m = 1.5
l = 0.8
g = 9.81
[coordinates]
phi1 = "angle of the upper rod to the vertical"
phi2 = "angle of the lower rod to the vertical"
[definitions]
x2 = "l*sin(phi1) + l*sin(phi2)"
y2 = "-l*cos(phi1) - l*cos(phi2)"
[energy]
T = "m*l^2*phi1'^2/2 + m*(x2'^2 + y2'^2)/2"
U = "-m*g*l*cos(phi1) + m*g*y2"
"""


def test_double_pendulum_closed_form():
    """Meirovitch Sect. 7: omega^2 = (2 -+ sqrt 2) g/l, phi2/phi1 = +-sqrt 2 (rel 1e-10)."""
    result = modes(loads(DOUBLE_PENDULUM))
    g, l = 9.81, 0.8
    expected = np.sqrt([(2 - math.sqrt(2)) * g / l, (2 + math.sqrt(2)) * g / l])
    np.testing.assert_allclose(result.natural_frequencies, expected, rtol=1e-10)
    np.testing.assert_allclose(result.mode_shapes.T,
                               [[1 / math.sqrt(2), 1], [-1 / math.sqrt(2), 1]], atol=1e-10)


def test_fixed_free_chain_energy_model():
    """Rao Sect. 6: omega_j = 2 sqrt(k/m) sin((2j-1) pi/(2(2n+1))), n = 6 (rel 1e-10)."""
    n, m, k = 6, 2.0, 500.0
    result = modes(loads(chain_model(n, m, k)))
    np.testing.assert_allclose(result.natural_frequencies, chain_frequencies(n, k, m),
                               rtol=1e-10)
    # mode j of the fixed-free chain: x_i proportional to sin(i (2j-1) pi/(2n+1))
    i = np.arange(1, n + 1)
    for j in range(n):
        exact = np.sin(i * (2 * j + 1) * math.pi / (2 * n + 1))
        exact = exact / exact[np.argmax(np.abs(exact))]
        np.testing.assert_allclose(result.mode_shapes[:, j], exact, atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(n=st.integers(2, 12), m=st.floats(0.1, 10.0), k=st.floats(1.0, 1e5))
def test_chain_matrix_model_property(n, m, k):
    """The closed form holds for any n, m, k (inline matrix model; rel 1e-9)."""
    M, _, K = chain_matrices(n, m, k)
    rows = lambda a: "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in r) + "]"  # noqa
                                     for r in a.toarray()) + "]"
    result = modes(loads(f"[matrices]\nM = {rows(M)}\nK = {rows(K)}\n"))
    np.testing.assert_allclose(result.natural_frequencies, chain_frequencies(n, k, m),
                               rtol=1e-9)
    phi = result.mass_normalised_modes
    np.testing.assert_allclose(phi.T @ M.toarray() @ phi, np.eye(n), atol=1e-9)
    assert np.all(np.abs(result.mode_shapes).max(axis=0) == 1.0)


def test_rayleigh_damped_chain_damping_ratios():
    """Rao Sect. 6.13: zeta_j = a/(2 w_j) + b w_j/2; a, b recovered (rel 1e-9)."""
    n, m, k, a, b = 5, 1.0, 1e4, 0.3, 2e-4
    result = modes(loads(chain_model(n, m, k, damping=(a, b))))
    w = chain_frequencies(n, k, m)
    assert result.damped and result.proportional_damping
    np.testing.assert_allclose(result.rayleigh, (a, b), rtol=1e-9)
    np.testing.assert_allclose(result.damping_ratios, a / (2 * w) + b * w / 2, rtol=1e-9)
    np.testing.assert_allclose(result.damping_ratios, modal_damping_ratios((a, b), w),
                               rtol=1e-12)
    # the modal eigenvalues are those of the state matrix
    from resonant.modal import point_state_eigenvalues

    eom = loads(chain_model(n, m, k, damping=(a, b))).linearize().numeric()
    dense = np.sort_complex(point_state_eigenvalues(eom.M, eom.C, eom.K))
    np.testing.assert_allclose(np.sort_complex(result.eigenvalues), dense, rtol=1e-9)
    assert result.stability == "asymptotically stable"


def test_non_proportional_damping():
    """Tuned mass damper: C = c2 on the absorber only; not proportional; zeta from eigenvalues."""
    result = modes(load(EXAMPLES / "tuned_mass_damper.toml"))
    assert result.damped and not result.proportional_damping and result.rayleigh is None
    s = result.eigenvalues[result.eigenvalues.imag > 0]
    s = s[np.argsort(np.abs(s))]
    np.testing.assert_allclose(result.damping_ratios, -s.real / np.abs(s), rtol=1e-12)
    np.testing.assert_allclose(result.damped_frequencies, s.imag, rtol=1e-12)
    assert len(result.eigenvalues) == 4 and result.stability == "asymptotically stable"


def test_gyroscopic_system():
    """M = I, K = k I, C = [[0, g], [-g, 0]]: s = +-i (sqrt(k + g^2/4) +- g/2) (exact)."""
    k, g = 9.0, 4.0
    result = modes(loads(f"[parameters]\nk = {k}\ng = {g}\n[matrices]\nM = [[1, 0], [0, 1]]\n"
                         'K = [["k", 0], [0, "k"]]\nC = [[0, "g"], ["-g", 0]]\n'))
    root = math.sqrt(k + g * g / 4)
    np.testing.assert_allclose(np.sort(result.eigenvalues.imag[result.eigenvalues.imag > 0]),
                               [root - g / 2, root + g / 2], rtol=1e-10)
    assert np.all(np.abs(result.eigenvalues.real) < 1e-9)
    assert not result.proportional_damping
    assert result.stability == "marginally stable"
    assert any("not symmetric" in w for w in result.warnings)


def test_lanczos_on_large_sparse_chain(tmp_path):
    """1000-mass chain from files, lowest 6 modes by shift-invert Lanczos (rel 1e-9)."""
    path = write_chain(tmp_path, 1000)
    result = modes(load(path), count=6)
    assert result.method == "shift-invert Lanczos"
    w = chain_frequencies(1000, 1e4, 1.0)[:6]
    np.testing.assert_allclose(result.natural_frequencies, w, rtol=1e-9)
    np.testing.assert_allclose(result.rayleigh, (0.1, 1e-4), rtol=1e-9)
    np.testing.assert_allclose(result.damping_ratios, 0.1 / (2 * w) + 1e-4 * w / 2, rtol=1e-8)
    assert result.mode_shapes.shape == (1000, 6)
    assert result.stability == "asymptotically stable"


def test_count_limits_dense_result():
    result = modes(load(EXAMPLES / "chain3_damped.toml"), count=2)
    assert len(result.natural_frequencies) == 2 and result.mode_shapes.shape == (3, 2)
    assert len(result.eigenvalues) == 4 and len(result.damping_ratios) == 2


def test_cli_modes_json_keys():
    code, out, err = run_cli(["modes", EXAMPLES / "two_dof_free.toml", "--json"])
    assert code == 0, err
    data = json.loads(out)
    for key in ("coordinates", "natural_frequencies", "mode_shapes", "eigenvalues",
                "damping_ratios", "stability", "frequencies_hz", "mass_normalised_modes",
                "proportional_damping"):
        assert key in data
    np.testing.assert_allclose(data["natural_frequencies"], [20, math.sqrt(3) * 20], rtol=1e-12)
    assert data["mode_shapes"][1] == pytest.approx([1, -1], abs=1e-12)
    assert all(len(pair) == 2 for pair in data["eigenvalues"])


def test_cli_modes_text_set_and_plot(tmp_path):
    plot = tmp_path / "modes.png"
    code, out, err = run_cli(["modes", EXAMPLES / "chain3_damped.toml", "--set", "k=4000",
                              "--plot", plot])
    assert code == 0, err
    assert "Rayleigh" in out and "28.1" in out  # 2 sqrt(4000) sin(pi/14) = 28.147
    assert plot.stat().st_size > 10_000
    import matplotlib.image

    pixels = matplotlib.image.imread(str(plot))
    assert pixels.std() > 0.05  # not a blank image


def test_cli_modes_errors():
    code, _, err = run_cli(["modes", EXAMPLES / "two_dof_free.toml", "--count", "0"])
    assert code == 2 and "--count" in err
    code, _, err = run_cli(["modes", "/nonexistent/model.toml"])
    assert code == 2
    singular = loads('[matrices]\nM = [[1, 0], [0, 0]]\nK = [[1, 0], [0, 1]]\n')
    from resonant.errors import AnalysisError

    with pytest.raises(AnalysisError, match="singular"):
        modes(singular)


def test_html_and_latex_repr():
    result = modes(load(EXAMPLES / "chain3_damped.toml"))
    assert "<table>" in result._repr_html_() and "rad/s" in result._repr_latex_()
    json.dumps(result.to_dict(), allow_nan=False)


#: two unit masses joined by a stiff link (1e13 N/m), the first tied to the ground by a soft
#: spring k0, a dashpot 1e-3 on each: the pair moves as one mass 2 on k0,
#: omega_1^2 = k0 / 2 (1 + O(k0 / 1e13)), zeta_1 = (2e-3) / (2 * 2 * omega_1)
STIFF_LINK = """
title = "stiff link"
[parameters]
w = 0.5
[matrices]
M = [[1, 0], [0, 1]]
K = [[{k}, -1e13], [-1e13, 1e13]]
C = [[1e-3, 0], [0, 1e-3]]
[[harmonic]]
omega = "w"
F_S = [1, 0]
"""


@pytest.mark.parametrize("k0", [1.0, 1e3])
def test_a_soft_mode_beside_a_stiff_link(k0, tmp_path):
    """omega_1 = sqrt(k0/2) was shown as a rigid-body mode of 0 rad/s (k0 = 1: below 1e-12
    of the stiff mode's omega^2) and both systems as marginally stable, though M, C and K are
    positive definite (Re s = -5e-4 is below 1e-9 of the largest |s|): now the mode's
    frequency with the conditioning's warning, and asymptotically stable, in `modes` and in
    `solve`.  Tolerance: 2 % for k0 = 1 (the residual's bound on its accuracy: 0.013 rad/s
    of 0.707), 1e-6 for k0 = 1e3."""
    path = tmp_path / "m.toml"
    path.write_text(STIFF_LINK.format(k=1e13 + k0))
    omega = math.sqrt(k0 / 2)
    tol = 0.02 if k0 == 1 else 1e-6
    code, out, err = run_cli(["modes", str(path), "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["natural_frequencies"][0] == pytest.approx(omega, rel=tol)
    assert data["damping_ratios"][0] == pytest.approx(2e-3 / (4 * omega), rel=tol)
    assert data["stability"] == "asymptotically stable"
    if k0 == 1:
        assert "limits the accuracy of 1 natural frequency" in " ".join(data["warnings"])
    code, out, err = run_cli(["solve", str(path), "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["natural_frequencies"][0] == pytest.approx(omega, rel=tol)
    assert data["stability"] == "asymptotically stable"


def test_a_rigid_body_mode_of_a_stiff_free_system_stays_zero(tmp_path):
    """The same pair without the ground spring is free: its rigid-body mode stays at 0 rad/s
    and the system marginally stable (K is singular; the round-off of its zero eigenvalue,
    of the order of eps 1e13, is no mode)."""
    path = tmp_path / "m.toml"
    path.write_text(STIFF_LINK.format(k=1e13).replace("F_S = [1, 0]", "F_S = [0, 0]"))
    for command in ("modes", "solve"):
        code, out, err = run_cli([command, str(path), "--json"])
        assert code == 0, err
        data = json.loads(out)
        assert data["natural_frequencies"][0] == 0.0
        assert data["stability"] == "marginally stable"
