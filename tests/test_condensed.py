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

from resonant.analyses.condensed import condensed_sweep
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.analyses.sweep import sweep
from resonant.errors import ModelError
from resonant.api import loads


def _rows(A: np.ndarray) -> str:
    return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in r) + "]" for r in A) + "]"


def chain(n: int, force: float = 0.01, element: str = 'force = "k3*q{n}^3"',
          k3: float = 2.0) -> tuple[object, np.ndarray, np.ndarray, np.ndarray]:
    """A chain of n masses 1/n, springs n (tip stiffness 1, first frequency about 1.57),
    grounded at q1, Rayleigh damping, a harmonic force at the free tip q_n, and one
    nonlinear element at the tip."""
    K = (np.diag(np.r_[2 * np.ones(n - 1), 1.0]) - np.diag(np.ones(n - 1), 1)
         - np.diag(np.ones(n - 1), -1)) * n
    M = np.eye(n) / n
    C = 0.02 * M + 0.002 * K
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
    r = condensed_sweep(model.linearize(), "w", 1.0, 2.4, harmonics=H, points=60,
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
