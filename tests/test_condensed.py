"""Condensed harmonic balance of [matrices] models with [[nonlinear]] elements.

References: an independent full harmonic balance of the whole chain (every
coordinate's harmonics unknown, dense Newton), the existing harmonic balance of a
model given by its energies (:func:`resonant.analyses.harmonic_balance.nonlinear_sweep`),
the single-harmonic equivalent stiffness and damping of the bilinear hysteresis loop
(Caughey, T. K. (1960), "Sinusoidal excitation of a system with bilinear hysteresis",
J. Appl. Mech. 27, 640-643), the linear response (a gap that never closes) and time
simulations of the full equations (scipy ``solve_ivp``).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.sparse.linalg import spsolve

from resonant.analyses import condensed
from resonant.analyses.condensed import condensed_sweep
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.analyses.sweep import sweep
from resonant.api import loads
from resonant.errors import ModelError
from resonant.system import nonlinear_system


def _rows(A: np.ndarray) -> str:
    return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in r) + "]" for r in A) + "]"


def chain(n: int, force: float = 0.01, element: str = 'force = "k3*q{n}^3"',
          k3: float = 2.0, alpha: float = 0.02, beta: float = 0.002
          ) -> tuple[object, np.ndarray, np.ndarray, np.ndarray]:
    """A chain of n masses 1/n, springs n (tip stiffness 1, first frequency about 1.57),
    grounded at q1, Rayleigh damping C = alpha M + beta K, a harmonic force at the free
    tip q_n, and one nonlinear element at the tip."""
    K = (np.diag(np.r_[2 * np.ones(n - 1), 1.0]) - np.diag(np.ones(n - 1), 1)
         - np.diag(np.ones(n - 1), -1)) * n
    M = np.eye(n) / n
    C = alpha * M + beta * K
    f = [0.0] * n
    f[-1] = force
    text = f"""
[parameters]
w = 1
k3 = {k3}
[matrices]
M = {_rows(M)}
K = {_rows(K)}
C = {_rows(C)}
[[harmonic]]
omega = "w"
F_C = {f}
[[nonlinear]]
name = "tip"
coordinates = ["q{n}"]
{element.format(n=n)}
"""
    return loads(text), M, C, K


def _full_residual(M, C, K, F, w, Z, H, tip, k3, N=64):
    """The full harmonic balance residual D_k Z_k + G_k - F_k of every coordinate (complex
    Z, shape (H+1, n)), the cubic force of the tip by its own FFT."""
    tau = 2 * np.pi * np.arange(N) / N
    u = np.real(sum(Z[k, tip] * np.exp(1j * k * tau) for k in range(H + 1)))
    g = np.fft.rfft(k3 * u ** 3) / N
    G = np.zeros_like(Z)
    G[0, tip] = g[0].real
    G[1:, tip] = 2 * g[1:H + 1]
    R = np.empty_like(Z)
    for k in range(H + 1):
        R[k] = (K - (k * w) ** 2 * M + 1j * k * w * C) @ Z[k] + G[k] - (F if k == 1 else 0)
    return R


def _pack(Z: np.ndarray) -> np.ndarray:
    return np.concatenate([Z.real.ravel(), Z.imag.ravel()])


def _full_jacobian(M, C, K, F, w, y, shape, H, tip, k3):
    """The real Jacobian of the full residual (sparse): the linear blocks exactly, the
    tip's columns by central differences."""
    import scipy.sparse as sp

    blocks = [sp.csr_matrix(K - (k * w) ** 2 * M + 1j * k * w * C) for k in range(H + 1)]
    D = sp.block_diag(blocks, format="csr")
    J = sp.bmat([[D.real, -D.imag], [D.imag, D.real]], format="csc")
    n, size = shape[1], y.size // 2
    res = lambda y: _pack(_full_residual(M, C, K, F, w, _unpack(y, shape), H, tip, k3))  # noqa
    rows, cols, data = [], [], []
    for k in range(H + 1):
        for j in (k * n + tip, size + k * n + tip):
            h = 1e-7 * max(1.0, abs(y[j]))
            e = np.zeros(y.size)
            e[j] = h
            delta = (res(y + e) - res(y - e)) / (2 * h) - J[:, [j]].toarray().ravel()
            nz = np.nonzero(np.abs(delta) > 1e-9 * np.abs(delta).max(initial=1e-300))[0]
            rows += nz.tolist()
            cols += [j] * nz.size
            data += delta[nz].tolist()
    return (J + sp.csc_matrix((data, (rows, cols)), shape=J.shape)).tocsc(), res


def _unpack(y: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    half = y.size // 2
    return (y[:half] + 1j * y[half:]).reshape(shape)


def _full_newton(M, C, K, F, w, Z, H, tip, k3):
    """Newton on the full harmonic balance (real unknowns: Re and Im of every Z_k) from Z;
    returns the solution and the relative smallest singular value of the Jacobian there."""
    y = _pack(Z)
    for _ in range(12):
        J, res = _full_jacobian(M, C, K, F, w, y, Z.shape, H, tip, k3)
        dy = spsolve(J, -res(y))
        y = y + dy
        if np.linalg.norm(dy) <= 1e-12 * np.linalg.norm(y):
            break
    return _unpack(y, Z.shape)


def _smallest_singular(J) -> float:
    """sigma_min / ||J||_1 of a sparse J (inverse iteration on J^T J with one LU)."""
    from scipy.sparse.linalg import norm, splu

    lu = splu(J)
    v = np.random.default_rng(0).standard_normal(J.shape[0])
    for _ in range(30):
        v = lu.solve(lu.solve(v, trans="T"))
        v /= np.linalg.norm(v)
    return float(np.linalg.norm(J @ v) / norm(J, 1))


def _complex(coeffs: np.ndarray, H: int) -> np.ndarray:
    """(rows, 2H+1) real coefficients -> (H+1, rows) complex a_k - i b_k."""
    Z = np.empty((H + 1, coeffs.shape[0]), dtype=complex)
    Z[0] = coeffs[:, 0]
    Z[1:] = (coeffs[:, 1::2] - 1j * coeffs[:, 2::2]).T
    return Z


def test_condensed_equals_full_harmonic_balance_on_a_200_dof_chain():
    """Every coordinate recovered from the condensed branch solves the full harmonic
    balance of the 200-DOF chain (independent dense Newton, started 1e-3 away): 1e-8
    relative on points spread over the whole branch, folds included; at each fold the
    full Jacobian is singular (its relative smallest singular value 1e-5 of the one at the start)."""
    H = 3
    model, M, C, K = chain(200)
    n = 200
    r = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, harmonics=H, points=60,
                        observe=[f"q{i}" for i in range(1, n + 1)], linear=False)
    folds = [s for s in r.special_points if s.kind == "fold"]
    assert len(folds) == 2
    order = [r.coordinates.index(f"q{i}") for i in range(1, n + 1)]
    F = np.zeros(n, dtype=complex)
    F[-1] = 0.01
    rng = np.random.default_rng(1)
    fold_points = [fold.index for fold in folds] + [fold.index + 1 for fold in folds]
    picks = sorted(set(np.linspace(0, len(r.values) - 1, 5).astype(int)) | set(fold_points))
    for i in picks:
        Z = _complex(r.coefficients[i][order], H)
        start = Z * (1 + 1e-3 * rng.standard_normal(Z.shape))
        full = _full_newton(M, C, K, F, float(r.values[i]), start, H, n - 1, 2.0)
        assert np.abs(full - Z).max() <= 1e-8 * np.abs(Z).max()
    # at each refined fold the full harmonic balance's Jacobian is singular: its relative
    # smallest singular value is far below the one at the start of the branch
    def relative_sigma(Z, w):
        J, _ = _full_jacobian(M, C, K, F, w, _pack(Z), Z.shape, H, n - 1, 2.0)
        return _smallest_singular(J)

    regular = relative_sigma(_complex(r.coefficients[0][order], H), float(r.values[0]))
    for fold in folds:
        # the fold's own point, recovered on request: continue a short sweep onto it
        near = _complex(r.coefficients[fold.index][order], H)
        Z = _full_newton(M, C, K, F, fold.value, near, H, n - 1, 2.0)
        assert relative_sigma(Z, fold.value) < 1e-5 * regular


DUFFING_MATRICES = '''
[parameters]
w = 0.5
[matrices]
M = [[1, 0], [0, 1]]
K = [[2, -1], [-1, 1]]
C = [[0.04, 0], [0, 0.04]]
[[harmonic]]
omega = "w"
F_C = [0, 0.1]
[[nonlinear]]
name = "hardening"
coordinates = ["q2", "q1"]
force = "2*(q2 - q1)^3"
'''

DUFFING_ENERGY = '''
[parameters]
w = 0.5
[coordinates]
q1 = ""
q2 = ""
[signals]
F = "0.1*cos(w*t)"
[energy]
T = "q1'^2/2 + q2'^2/2"
U = "q1^2/2 + (q2 - q1)^2/2 + 2*(q2 - q1)^4/4"
D = "0.04*q1'^2/2 + 0.04*q2'^2/2"
[[force]]
generalized = { q2 = "F" }
'''


def test_folds_and_peaks_equal_the_harmonic_balance_of_the_energy_model():
    """The same 2-DOF system with a cubic spring between the masses, once as [matrices]
    with a [[nonlinear]] force between two coordinates, once by its energies: the folds
    and the peaks of the condensed balance equal those of resonant's full harmonic
    balance (1e-8 relative, amplitudes too), and so do the amplitudes at the branch's end."""
    H = 5
    condensed = condensed_sweep(nonlinear_system(loads(DUFFING_MATRICES)), "w", 0.4, 2.2,
                                harmonics=H, points=60, observe=["q1"], linear=False)
    full = nonlinear_sweep(nonlinear_system(loads(DUFFING_ENERGY).linearize()), "w", 0.4, 2.2,
                           harmonics=H, points=60, linear=False)
    for kind in ("fold", "peak"):
        mine = sorted((s for s in condensed.special_points if s.kind == kind),
                      key=lambda s: s.value)
        theirs = sorted((s for s in full.special_points if s.kind == kind),
                        key=lambda s: s.value)
        assert len(mine) == len(theirs) >= 2
        for a, b in zip(mine, theirs):
            assert a.value == pytest.approx(b.value, rel=1e-8)
            assert a.quantity == b.quantity
            for name in ("q1", "q2"):
                assert a.amplitudes[name] == pytest.approx(b.amplitudes[name], rel=1e-8)
    for name in ("q1", "q2"):
        assert condensed.amplitudes[name][-1] == pytest.approx(full.amplitudes[name][-1],
                                                               rel=1e-8)
    assert np.array_equal(condensed.stable[[0, -1]], [True, True])


def test_a_gap_that_never_closes_gives_the_linear_response():
    """A gap far beyond the motion: the branch is the linear sweep's curve (1e-9)."""
    model, *_ = chain(30, element='kind = "gap"\ngap = 10\nstiffness = 1e4')
    r = condensed_sweep(nonlinear_system(model), "w", 0.5, 3.0, harmonics=3, points=30)
    assert {s.kind for s in r.special_points} == {"peak"} and r.stable.all()
    linear = sweep(model.linearize(), "w", r.values, names=["q30"])
    np.testing.assert_allclose(r.amplitudes["q30"], linear.amplitudes["q30"], rtol=1e-9)


def _caughey(a: float, kt: float, fs: float) -> complex:
    """The single-harmonic describing function of the Jenkins element (Caughey 1960):
    equivalent stiffness and (as imaginary part) the dissipation, G = (k_eq + i h) z."""
    xy = fs / kt
    if a <= xy:
        return complex(kt)
    beta = np.arccos(1 - 2 * xy / a)
    k_eq = kt / np.pi * (beta - np.sin(2 * beta) / 2)
    h = 4 * fs * (a - xy) / (np.pi * a * a)
    return complex(k_eq, h)


def test_jenkins_element_with_one_harmonic_equals_caughey():
    """A mass on a spring and a Jenkins element (kt, slip force fs), H = 1: at every
    branch point the amplitude solves |k - w^2 m + i w c + N(a)| a = F with Caughey's
    equivalent stiffness and damping of the bilinear loop, to 1e-8 relative (the
    alternating frequency-time march with 2^17 samples: its error falls as 1/N^2, 6e-9
    at 2^16, from the kink where the element starts to slip)."""
    kt, fs, force = 2.0, 0.3, 1.0
    model = loads(f'''
[parameters]
w = 0.3
[matrices]
M = [[1]]
K = [[1]]
C = [[0.02]]
[[harmonic]]
omega = "w"
F_C = [{force}]
[[nonlinear]]
name = "joint"
coordinates = ["q1"]
kind = "friction"
stiffness = {kt}
slip_force = {fs}
''')
    for start in (0.5, 1.1, 1.6):  # below, at and above the resonance: stick-slip each
        r = condensed_sweep(nonlinear_system(model), "w", start, start + 0.02, harmonics=1,
                            points=3, samples=2**17, linear=False)
        assert len(r.values) >= 3
        for w, c in zip(r.values, r.coefficients[:, 0]):
            a = float(np.hypot(c[1], c[2]))

            def gap(a: float, w: float = float(w)) -> float:
                return abs(1 - w * w + 1j * w * 0.02 + _caughey(a, kt, fs)) * a - force

            expected = brentq(gap, 1e-6, 100.0, xtol=1e-15)
            assert expected > 2 * fs / kt  # the element slips
            assert a == pytest.approx(expected, rel=1e-8)
            assert abs(c[0]) < 1e-10


def _simulate(M, C, K, F, w, tip, k3, q0, v0, periods):
    """The full equations M q'' + C q' + K q + k3 q_tip^3 e_tip = F cos(w t) (DOP853)."""
    Minv = np.linalg.inv(M)
    n = M.shape[0]

    def rhs(t, s):
        q, v = s[:n], s[n:]
        f = F * np.cos(w * t) - C @ v - K @ q
        f[tip] -= k3 * q[tip] ** 3
        return np.concatenate([v, Minv @ f])

    T = 2 * np.pi / w
    sol = solve_ivp(rhs, (0, periods * T), np.concatenate([q0, v0]), method="DOP853",
                    rtol=1e-10, atol=1e-12, t_eval=[periods * T])
    return sol.y[:n, -1]


def test_stability_agrees_with_time_simulation():
    """A 10-DOF chain with a cubic spring at its tip, H = 9 (the highest harmonic carries
    < 1e-4 of the amplitude): stable points on the upper and the lower branch are
    reproduced by simulations of the full equations started on them (1e-4 relative after
    200 periods); unstable points of the middle branch are left (the state moves away by
    more than 1e-2); stability changes exactly at the folds."""
    n, H, k3 = 10, 9, 2.0
    model, M, C, K = chain(n, k3=k3)
    r = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, harmonics=H, points=60,
                        observe=[f"q{i}" for i in range(1, n)], linear=False)
    folds = sorted(s.index for s in r.special_points if s.kind == "fold")
    assert len(folds) == 2 and r.truncation < 1e-4
    assert r.stable[:folds[0] + 1].all() and r.stable[folds[1] + 1:].all()
    assert not r.stable[folds[0] + 1:folds[1] + 1].any()
    order = [r.coordinates.index(f"q{i}") for i in range(1, n + 1)]
    F = np.zeros(n)
    F[-1] = 0.01
    k = np.arange(1, H + 1)
    middle = (folds[0] + folds[1]) // 2
    for i in (folds[0] - 3, folds[0] - 20, folds[1] + 15, middle, (middle + folds[1]) // 2):
        c = r.coefficients[i][order]
        w = float(r.values[i])
        q0 = c[:, 0] + c[:, 1::2].sum(axis=1)
        v0 = w * (c[:, 2::2] @ k)
        end = _simulate(M, C, K, F, w, n - 1, k3, q0, v0, 200)
        deviation = np.abs(end - q0).max() / np.abs(q0).max()
        assert (deviation < 1e-4) if r.stable[i] else (deviation > 1e-2), (i, deviation)


def _jenkins_chain(n: int = 4):
    """The chain with a Jenkins element (kt 3, slip force 0.004) at its tip instead of
    the cubic spring, forced hard enough (0.02) to slip through much of each period."""
    return chain(n, force=0.02, element='kind = "friction"\nstiffness = 3.0\n'
                                          'slip_force = 0.004')


def _jenkins_multipliers(M, C, K, w, q0, v0, f0, kt, fs, steps=4096):
    """The Floquet multipliers of the full equations with the Jenkins element at the tip
    from time simulations: the one-period map of the state (q, q', slider force f) by
    velocity Verlet (the force marched f = clip(f + kt du, -fs, fs) after each position
    step), its Jacobian by central differences at (q0, v0, f0), its eigenvalues."""
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    dt = 2 * np.pi / w / steps
    F = np.zeros(n)
    F[-1] = 0.02

    def acc(q, v, f, t):
        g = F * np.cos(w * t) - C @ v - K @ q
        g[-1] -= f
        return Minv @ g

    def period(y):
        q, v, f = y[:n], y[n:2 * n], y[-1]
        for step in range(steps):
            t = step * dt
            a = acc(q, v, f, t)
            half = v + 0.5 * dt * a
            new = q + dt * half
            f = float(np.clip(f + kt * (new[-1] - q[-1]), -fs, fs))
            v = half + 0.5 * dt * acc(new, half + 0.5 * dt * a, f, t + dt)
            q = new
        return np.concatenate([q, v, [f]])

    y0 = np.concatenate([q0, v0, [f0]])
    h = 1e-7 * np.abs(y0).max()
    jac = np.array([(period(y0 + h * e) - period(y0 - h * e)) / (2 * h)
                    for e in np.eye(y0.size)]).T
    return np.linalg.eigvals(jac)


def test_friction_stability_agrees_with_time_simulation():
    """A 4-DOF chain with a Jenkins element at its tip that sticks and slips each period:
    the Floquet multipliers at w = 1.6 equal those of the full equations' one-period map
    by time simulations (to 1e-2; 1.6e-3 measured, 2048 samples per period against 4096
    Verlet steps), whatever H (9 or 15, whose Hill matrix would keep 2 of the 8 modes
    dynamic: 1e-3).  The
    linearization must carry the slider's memory (the force kt (du - dz) while it sticks
    again); the instantaneous tangent kt du alone gave 1.9 here, unstable."""
    model, M, C, K = _jenkins_chain()
    n = 4
    multipliers = []
    for H in (15, 9):
        r = condensed_sweep(nonlinear_system(model), "w", 1.6, 1.62, harmonics=H, points=3,
                            observe=[f"q{i}" for i in range(1, n)], linear=False)
        multipliers.append(float(np.abs(r.multipliers[0]).max()))
    assert r.stable[0]
    order = [r.coordinates.index(f"q{i}") for i in range(1, n + 1)]
    c = r.coefficients[0][order]
    k = np.arange(1, r.harmonics + 1)
    q0, v0 = c[:, 0] + c[:, 1::2].sum(axis=1), 1.6 * (c[:, 2::2] @ k)
    tau = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    tip = c[-1, 0] + np.cos(np.outer(tau, k)) @ c[-1, 1::2] + np.sin(np.outer(tau, k)) @ \
        c[-1, 2::2]
    f0 = 0.0
    for du in np.diff(np.r_[tip, tip, tip[0]]):  # the slider's force at t = 0
        f0 = float(np.clip(f0 + 3.0 * du, -0.004, 0.004))
    simulated = np.sort(np.abs(_jenkins_multipliers(M, C, K, 1.6, q0, v0, f0, 3.0, 0.004)))
    assert simulated[0] < 1e-6  # the slider's reset
    np.testing.assert_allclose(np.sort(np.abs(r.multipliers[0])), simulated[1:], rtol=1e-2)
    assert multipliers[1] == pytest.approx(multipliers[0], rel=1e-3)


def test_friction_verdict_does_not_depend_on_where_the_sweep_starts():
    """The same chain swept to w = 1.6 from 1.3 and from 1.5 (H fixed at 9): the same
    multipliers at the common end (1e-6), stable at every point of both branches (the
    response of a linear chain with a friction joint is unique; the instantaneous
    tangent's exponents, their parity matched to the start, said stable from 1.3 and
    unstable from 1.5)."""
    model, *_ = _jenkins_chain()
    ends = []
    for start in (1.3, 1.5):
        r = condensed_sweep(nonlinear_system(model), "w", start, 1.6, harmonics=9,
                            points=12, linear=False)
        assert r.values[-1] == pytest.approx(1.6) and r.stable.all()
        ends.append(np.sort(np.abs(r.multipliers[-1])))
    np.testing.assert_allclose(ends[0], ends[1], rtol=1e-6)


def test_friction_points_keep_the_modes_of_their_own_frequency():
    """A 30-DOF chain with the Jenkins element (60 first-order modes, more than 40): each
    point keeps the modes up to 3 W of its own W, so the second mode (|Im mu| 4.7) is
    kept above W = 1.57 and not below; the points with fewer are padded with multipliers
    0, not 1 (a padded exponent 0 read as a multiplier on the unit circle)."""
    model, *_ = _jenkins_chain(30)
    r = condensed_sweep(nonlinear_system(model), "w", 1.5, 1.6, harmonics=9, points=10,
                        linear=False)
    kept = (np.abs(r.multipliers) > 0).sum(axis=1)
    assert set(kept) == {2, 4} and kept[0] == 2 and kept[-1] == 4
    assert r.stable.all() and np.abs(r.multipliers).max() < 0.96


def _grid_model(tmp_path, force: float):
    """The irregular 15 x 15 mass-spring grid of ``tests/test_reduced.py`` (225
    coordinates, first frequency 26.8) with a stiff cubic mount (1e8 q^3) where its force
    acts."""
    import scipy.sparse as sp

    from test_reduced import grid

    M, C, K, f = grid(15)
    for key, a in (("M", M), ("C", C), ("K", K)):
        sp.save_npz(tmp_path / f"{key}.npz", a)
    q = f"q{int(np.flatnonzero(f)[0]) + 1}"
    (tmp_path / "grid.toml").write_text(
        '[parameters]\nw = 1\n[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
        f'[[harmonic]]\nomega = "w"\nF_C = {{ {q} = "{force!r}" }}\n'
        f'[[nonlinear]]\nname = "mount"\ncoordinates = ["{q}"]\nforce = "1e8*{q}^3"\n')
    from resonant.api import load
    return load(tmp_path / "grid.toml"), q


@pytest.mark.parametrize("structure", ["grid", "chain"])
def test_small_forcing_gives_the_linear_response(structure, tmp_path):
    """At small forcing the branch is the linear response (the exact sparse sweep at the
    branch's values) to 1e-6 relative, on a 225-DOF grid through a reduced linear part
    (its default tolerance, 1e-6) and on the 200-DOF chain through the full matrices;
    what differs is the cubic's own effect: a tenth of the force, a hundredth of the
    difference (measured: grid 9.2e-8 and 9.2e-10 at forces 1e-2 and 1e-3, chain 7.0e-8
    and 7.8e-10 at 1e-6 and 1e-7; on the 10^4-DOF corpus grid and plate at a millionth
    of their benchmark force, 5e-13 and 1.3e-11)."""
    rel = []
    for force in ((1e-2, 1e-3) if structure == "grid" else (1e-6, 1e-7)):
        if structure == "grid":
            model, q = _grid_model(tmp_path, force)
            band, kwargs = (25.0, 29.0), {"exact": False}
        else:
            model, *_ = chain(200, force=force)
            q, band, kwargs = "q200", (1.3, 1.8), {}
        r = condensed_sweep(nonlinear_system(model), "w", *band, harmonics=3, points=12,
                            linear=False, **kwargs)
        linear = sweep(model.linearize(), "w", r.values, names=[q], method="sparse")
        rel.append(float(np.max(np.abs(r.amplitudes[q] / linear.amplitudes[q] - 1))))
    assert rel[0] < 1e-6
    assert 70 < rel[0] / rel[1] < 130, rel


def test_fast_modes_static_in_the_stability_give_the_same_verdicts(monkeypatch):
    """An 8-DOF chain with H = 7: Hill's matrix of every mode would have 240 rows, so the
    modes above 3 W_max enter as their static flexibility (2 of 8 modes stay dynamic).
    The stability of every branch point equals that with every mode dynamic (two routes),
    and the largest growth rates agree to 5e-3 W_max (0.009 at most seen, near the folds:
    the static modes are an approximation, the verdicts are not changed by it)."""
    model, *_ = chain(8)
    kwargs = dict(harmonics=7, points=40, linear=False)
    cut = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, **kwargs)
    monkeypatch.setattr(condensed, "SMALL_HILL", 10**6)
    every = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, **kwargs)
    assert len(cut.values) == len(every.values)
    np.testing.assert_array_equal(cut.stable, every.stable)
    assert (~cut.stable).any() and cut.stable.any()
    log_cut = np.log(np.abs(cut.multipliers)).max(axis=1)
    log_every = np.log(np.abs(every.multipliers)).max(axis=1)
    period = 2 * np.pi / cut.base_frequencies
    np.testing.assert_allclose(log_cut / period, log_every / period, atol=5e-3 * 2.4)


def test_tangent_jacobian_equals_the_derivative_pushed_through_the_elements(monkeypatch):
    """Two routes to the Jacobian of the element forces' harmonics: from the tangent
    stiffness and damping (used for elements without memory) and from the motion's
    derivative along every unknown pushed through the elements sample by sample (used
    for friction), at every Newton step of a branch with a cubic spring and a rate-
    dependent damper at the tip and a gap between two inner masses: equal to 1e-12."""
    element = ('force = "k3*q{n}^3 + 0.05*q{n}\'*abs(q{n}\')"\n[[nonlinear]]\n'
               'name = "stop"\ncoordinates = ["q4", "q3"]\nkind = "gap"\ngap = 0.002\n'
               'stiffness = 5')
    model, *_ = chain(6, element=element)
    tangent = condensed.CondensedBalance.force_derivatives_by_tangent
    seen, closed = [], []

    def both(self, forces, U, Ud, W):
        fast = tangent(self, forces, U, Ud, W)
        slow = self.force_derivatives_by_directions(forces, U, Ud, W)
        assert np.array_equal(fast[0], slow[0])  # the forces themselves, bit for bit
        seen.append(np.abs(fast[1] - slow[1]).max() / max(np.abs(slow[1]).max(), 1e-300))
        closed.append(bool((forces.stiffness(U, Ud)[0] >= 5).any()))  # the gap's kc
        return fast

    monkeypatch.setattr(condensed.CondensedBalance, "force_derivatives_by_tangent", both)
    r = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, harmonics=5, points=20,
                        samples=256, linear=False)
    assert len(seen) > 50 and max(seen) < 1e-12
    assert any(closed) and not all(closed)  # the gap opens and closes along the branch
    assert len(r.values) > 20


def test_reduced_linear_part_equals_the_full_matrices():
    """The linear part from a reduced model (tol 1e-9) gives the branch of the full
    matrices to 1e-7 relative."""
    model, *_ = chain(120)
    kwargs = dict(harmonics=3, points=30, linear=False)
    exact = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, exact=True, **kwargs)
    reduced = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, exact=False, tol=1e-9,
                              **kwargs)
    assert len(exact.values) == len(reduced.values)
    np.testing.assert_allclose(reduced.values, exact.values, rtol=1e-7)
    np.testing.assert_allclose(reduced.amplitudes["q120"], exact.amplitudes["q120"],
                               rtol=1e-7)
    assert any("linear part: reduced model" in w and "estimate" in w
               for w in reduced.warnings)


def _stalled(monkeypatch, floor: float = 0.0) -> None:
    """The reduced model of the linear part stops short of its tolerance, as on a plate
    whose enrichment stalled at 1.5e-5 with exact solves accurate to far less (the
    rounding floor ``floor``), and no basis of modes and Ritz vectors meets it."""
    import dataclasses

    real = condensed.reduced_model

    def stalled(*args, **kwargs):
        return dataclasses.replace(real(*args, **kwargs), converged=False, floor=floor,
                                   reason="the residual stopped decreasing at 1.5e-05")

    monkeypatch.setattr(condensed, "reduced_model", stalled)
    monkeypatch.setattr(condensed, "modal_ritz_basis", lambda *args: None)


def test_a_reduced_linear_part_short_of_its_tolerance_falls_back_to_exact_receptances(
        monkeypatch):
    """The balance then takes the exact receptances (sparse solves) and gives the branch
    of the full matrices, its stability included, to 1e-7 relative (both exact: they
    differ by the rounding of the full matrices' eigenvectors, 1e-9 here), and says what
    it did and what it cost."""
    model, *_ = chain(40)
    kwargs = dict(harmonics=2, points=12, linear=False)
    exact = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, exact=True, **kwargs)
    _stalled(monkeypatch)
    fallback = condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, exact=False,
                               **kwargs)
    assert len(fallback.values) == len(exact.values)
    np.testing.assert_allclose(fallback.values, exact.values, rtol=1e-7)
    np.testing.assert_allclose(fallback.amplitudes["q40"], exact.amplitudes["q40"],
                               rtol=1e-7)
    assert (fallback.stable == exact.stable).all()
    said = [w for w in fallback.warnings if "exact receptances" in w]
    assert len(said) == 1 and "did not reach the tolerance 1e-06" in said[0]
    assert "sparse LU solves" in said[0] and "--tol" in said[0]


def test_exact_receptances_are_smooth_in_the_frequency(monkeypatch):
    """On an ill-conditioned beam (20 Hermite elements, floor about 1e-8) a plain sparse
    LU rounds differently at each frequency: its central difference over 1e-6 w misses
    dH/dw = -H (-2 w M + i C) H (dense, exact to its rounding) by about 3e-5, which
    stops the continuation; refined in extended precision it meets it to 1e-6."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))
    import make_beam

    M, C, K = make_beam.beam_matrices(20)
    tip = M.shape[0] - 2
    B = np.zeros((M.shape[0], 1), dtype=complex)
    B[tip] = 1.0
    Md, Cd, Kd = (a.toarray() for a in (M, C, K))

    def worst() -> float:
        exact = condensed.ExactTransfers(M, C, K, B, [tip], "")
        errors = []
        for w in np.linspace(15.0, 40.0, 6):
            h = 1e-6 * w
            difference = (exact(w + h) - exact(w - h))[0, 0] / (2 * h)
            A = Kd - w * w * Md + 1j * w * Cd
            derivative = -np.linalg.solve(A, (-2 * w * Md + 1j * Cd) @ np.linalg.solve(A, B))
            errors.append(abs(difference - derivative[tip, 0]) / abs(derivative[tip, 0]))
        return max(errors)

    assert worst() < 1e-6
    monkeypatch.setattr(condensed, "EXACT_REFINEMENTS", 0)
    assert worst() > 1e-6


def test_a_reduced_linear_part_at_its_rounding_floor_is_refused(monkeypatch):
    """Where the model's conditioning rounds every solve, exact ones included, above the
    tolerance, exact receptances would be no better: exit 3 naming a tolerance to ask."""
    model, *_ = chain(40)
    _stalled(monkeypatch, floor=1e-4)
    with pytest.raises(condensed.AnalysisError, match="round off as much: a tolerance above 0.0001 with --tol"):
        condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, exact=False, harmonics=2,
                        points=12, linear=False)


def test_exact_receptances_out_of_time_name_the_tolerance():
    """Where the exact solves would run past the time limit the balance refuses (exit 3)
    and names the options that help."""
    import scipy.sparse as sp

    from resonant.deadline import AnalysisTimeout, Deadline

    late = Deadline(1e-9)
    exact = condensed.ExactTransfers(sp.identity(2), None, sp.diags([4.0, 9.0]), np.eye(2),
                                     [0, 1], "the reduced model did not reach 1e-06", late)
    while not late.expired:
        pass
    with pytest.raises(AnalysisTimeout, match="exceeded, after 0 sparse solves.*--tol.*--timeout"):
        exact(1.0)


def test_exact_receptances_that_cannot_fit_the_time_are_refused_early(monkeypatch):
    """A branch that needs more exact solves than the time left allows is refused after
    the first few solves, with the estimate, not at the end of the time."""
    model, *_ = chain(40)
    _stalled(monkeypatch)
    monkeypatch.setattr(condensed, "EXACT_SOLVES", 10**9)
    from resonant.deadline import AnalysisTimeout, Deadline

    with pytest.raises(AnalysisTimeout, match=r"need at least \d+ sparse solves.*--tol"):
        condensed_sweep(nonlinear_system(model), "w", 1.0, 2.4, exact=False,
                        harmonics=2, points=12, linear=False, deadline=Deadline(60))


@pytest.mark.parametrize("entry, message", [
    ('coordinates = ["q9"]\nforce = "q9^3"', "unknown coordinate"),
    ('coordinates = ["q1"]\nkind = "gap"\ngap = 0.1', "stiffness is missing"),
    ('coordinates = ["q1"]\nkind = "spring"', "unknown kind"),
    ('coordinates = ["q1"]\nforce = "q2^3"', "unknown name 'q2'"),
    ('coordinates = ["q1"]\nkind = "friction"\nstiffness = 1\nslip_force = 1\nforce = "1"',
     "unknown key 'force'"),
    ('coordinates = ["q1", "q1"]\nforce = "q1"', "must differ"),
    ('coordinates = "q1"\nforce = "q1\'\'"', "first rates"),
])
def test_bad_nonlinear_entries_are_named(entry, message):
    text = f'''
[matrices]
M = [[1]]
K = [[1]]
[[nonlinear]]
name = "el"
{entry}
'''
    with pytest.raises(ModelError) as info:
        loads(text, source="model.toml")
    assert message in str(info.value)
    assert "model.toml: [nonlinear" in str(info.value)


def test_nonlinear_entries_need_a_matrix_model():
    with pytest.raises(ModelError, match="belong to a \\[matrices\\] model"):
        loads('''
[coordinates]
x = ""
[energy]
T = "x'^2/2"
U = "x^2/2"
[[nonlinear]]
coordinates = ["x"]
force = "x^3"
''')


def test_beam_example_reduced_equals_exact(tmp_path):
    """examples/make_beam.py: the cantilever's first natural frequency approaches the
    Euler-Bernoulli value 1.8751^2 sqrt(EI / (rho A L^4)) (Rao, Sect. 8.5; 1e-4 with 20
    elements), and its branch with a cubic spring at the tip from the linear part's modal
    and Ritz basis equals the one from the full matrices (1e-6), folds included."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))
    import make_beam

    from resonant.api import load

    path = make_beam.write_beam(tmp_path, 20, "cubic")
    model = load(path)
    EI = make_beam.YOUNG * make_beam.WIDTH * make_beam.THICKNESS ** 3 / 12
    rho_A = make_beam.DENSITY * make_beam.WIDTH * make_beam.THICKNESS
    expected = 1.875104068711961 ** 2 * np.sqrt(EI / (rho_A * make_beam.LENGTH ** 4))
    first = float(np.sqrt(model.linearize().modes().omega_squared[0]))
    assert first == pytest.approx(expected, rel=1e-4) and first >= expected
    kwargs = dict(harmonics=3, points=30, linear=False)
    exact = condensed_sweep(nonlinear_system(model), "omega", 20.0, 40.0, exact=True, **kwargs)
    reduced = condensed_sweep(nonlinear_system(model), "omega", 20.0, 40.0, exact=False, **kwargs)
    folds = [[s.value for s in r.special_points if s.kind == "fold"] for r in (exact, reduced)]
    assert len(folds[0]) == 2
    np.testing.assert_allclose(folds[1], folds[0], rtol=1e-6)
    tip = exact.coordinates[0]
    assert max(reduced.amplitudes[tip]) == pytest.approx(max(exact.amplitudes[tip]), rel=1e-6)
