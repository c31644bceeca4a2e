"""How honest is the reduced sweep's error estimate?  True error against estimate.

For many small models of several kinds the reduced response
(:func:`resonant.analyses.reduced.reduced_response`) is compared with an exact
sparse LU solve at *every* frequency: the true relative error
err(w) = ||z_red - z|| / ||z|| against the reported estimate ``error[w]`` and,
over the band, max err against ``estimated_error``.

Kinds of models (:func:`model`):

* ``chain-uniform``: a fixed-free chain of unit masses and equal springs 1e4;
* ``chain-random``: masses 1 ... 2 and springs 1e4 ... 2e4, random;
* ``grid-uniform``: a 2-D grid of unit masses and equal springs 1e4, edges grounded;
* ``grid-random``: the grid with random masses and springs;

each with one of four dampings: ``rayleigh`` C = 0.1 M + 1e-3 K, ``mass`` C = 0.1 M,
``nonprop`` C = 1e-5 K plus five discrete dampers 5 ... 10 between neighbours
(not proportional), ``light`` C = 1e-3 M + 1e-6 K (lightly damped; up to 60
resonances in the band).  The band runs from half the lowest natural frequency
to the k-th (k random), the load is a unit force at one mass and -0.5 i at another.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_reduced_estimate.py --cases 240

prints, per kind and damping and over all, the largest ratio true / estimate
per frequency, the same where the true error is above the rounding level (both
1e-10, the residual's rounding floor, and 100 eps kappa, kappa =
||A(w)||_F ||z|| / ||b|| a lower bound of the condition number), the range of the
band's ratio max err / estimated_error, and whether the tolerance was met
wherever the result says ``converged``.

Examples
--------
>>> M, C, K, b, w = model("chain-uniform", "mass", seed=1)
>>> bool(M.diagonal().min() == M.diagonal().max() == 1.0), bool(abs(C - 0.1 * M).max() == 0)
(True, True)
>>> row = compare(M, C, K, b, w, tol=1e-6)
>>> row["converged"], row["true_max"] <= 1e-6
(True, True)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from resonant.analyses.reduced import reduced_response  # noqa: E402

KINDS = ("chain-uniform", "chain-random", "grid-uniform", "grid-random")
DAMPINGS = ("rayleigh", "mass", "nonprop", "light")
TOLERANCES = (1e-3, 1e-6, 1e-8)
#: rounding level of a double-precision solve, in units of eps * kappa
ROUNDING = 100.0
#: relative errors below this are rounding of the residual (of its QR factorization)
FLOOR = 1e-10


def _springs(kind: str, rng: np.random.Generator, size: int
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    """(rows, cols, stiffness, grounded spring per node, n) of a chain or a grid."""
    uniform = kind.endswith("uniform")
    if kind.startswith("chain"):
        n = size
        rows, cols = np.arange(n - 1), np.arange(1, n)
        ground = np.r_[1e4, np.zeros(n - 1)]
    else:
        nx = size
        n = nx * nx
        idx = np.arange(n).reshape(nx, nx)
        rows = np.concatenate([idx[:, :-1].ravel(), idx[:-1, :].ravel()])
        cols = np.concatenate([idx[:, 1:].ravel(), idx[1:, :].ravel()])
        edge = np.zeros((nx, nx), dtype=bool)
        edge[0, :] = edge[-1, :] = edge[:, 0] = edge[:, -1] = True
        ground = 1e4 * edge.ravel()
    k = 1e4 * (np.ones(len(rows)) if uniform else 1 + rng.random(len(rows)))
    return rows, cols, k, ground, n


def model(kind: str, damping: str, seed: int = 0, size: int | None = None,
          resonances: int | None = None, points: int | None = None
          ) -> tuple[Any, Any, Any, np.ndarray, np.ndarray]:
    """(M, C, K, b, w) of one test model (see the module docstring); ``size``: masses of
    the chain or nodes per side of the grid, ``resonances`` in the band, ``points``
    frequencies (random when not given)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla

    rng = np.random.default_rng(seed)
    if size is None:
        size = int(rng.integers(40, 250)) if kind.startswith("chain") else \
            int(rng.integers(6, 16))
    rows, cols, k, ground, n = _springs(kind, rng, size)

    def pairs(values: np.ndarray, i: np.ndarray, j: np.ndarray) -> Any:
        return sp.coo_matrix((np.concatenate([values, values, -values, -values]),
                              (np.concatenate([i, j, i, j]), np.concatenate([i, j, j, i]))),
                             shape=(n, n)).tocsr()

    K = (pairs(k, rows, cols) + sp.diags(ground)).tocsr()
    M = sp.diags(np.ones(n) if kind.endswith("uniform") else 1 + rng.random(n)).tocsr()
    if damping == "rayleigh":
        C = 0.1 * M + 1e-3 * K
    elif damping == "mass":
        C = 0.1 * M
    elif damping == "light":
        C = 1e-3 * M + 1e-6 * K
    else:
        pick = rng.choice(len(rows), 5, replace=False)
        C = 1e-5 * K + pairs(5.0 * (1 + rng.random(5)), rows[pick], cols[pick])
    top = resonances or int(rng.integers(3, 60 if damping == "light" else 30))
    top = min(top, n - 3)
    lam = np.sort(sla.eigsh(K.tocsc(), k=top + 1, M=M.tocsc(), sigma=0, v0=np.ones(n),
                            return_eigenvectors=False))  # v0: the same band every run
    w = np.linspace(0.5 * np.sqrt(lam[0]), np.sqrt(lam[top]),
                    points or int(rng.integers(100, 300)))
    b = np.zeros(n, dtype=complex)
    b[rng.integers(n)] = 1.0
    b[rng.integers(n)] -= 0.5j
    return M, sp.csr_matrix(C), K, b, w


def exact(M: Any, C: Any, K: Any, b: np.ndarray, w: np.ndarray) -> np.ndarray:
    """z(w) by one SuperLU (partial pivoting) per frequency, shape (N, n)."""
    from scipy.sparse.linalg import splu

    return np.array([splu((K - x * x * M + 1j * x * C).tocsc()).solve(b) for x in w])


def compare(M: Any, C: Any, K: Any, b: np.ndarray, w: np.ndarray, tol: float
            ) -> dict[str, Any]:
    """The reduced response against the exact one at every frequency."""
    import scipy.sparse.linalg as sla

    red = reduced_response(M, C, K, b, w, tol=tol)
    ref = exact(M, C, K, b, w)
    true = np.linalg.norm(red.Z - ref, axis=1) / np.linalg.norm(ref, axis=1)
    a_norm = sla.norm(K) + w ** 2 * sla.norm(M) + w * sla.norm(C)
    rounding = ROUNDING * np.finfo(float).eps * a_norm * np.linalg.norm(ref, axis=1) \
        / np.linalg.norm(b)
    above = red.error > rounding
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = true / red.error
    return {"tol": tol, "converged": red.converged, "true": true, "error": red.error,
            "rounding": rounding, "true_max": float(true.max()),
            "estimated_error": red.estimated_error,
            "ratio_max": float(np.nanmax(ratio)),
            "ratio_above": float(np.max(ratio[above], initial=0.0)),
            "ratio_floor": float(np.max(ratio[true > np.maximum(rounding, FLOOR)],
                                        initial=0.0)),
            "band_ratio": float(true.max() / red.estimated_error),
            "tol_met": bool(true.max() <= tol), "basis": red.basis_size}


def run(cases: int, log: Any = None) -> list[dict[str, Any]]:
    """``cases`` models cycling through kinds, dampings and tolerances."""
    rows = []
    for seed in range(cases):
        kind = KINDS[seed % len(KINDS)]
        damping = DAMPINGS[(seed // len(KINDS)) % len(DAMPINGS)]
        tol = TOLERANCES[seed % len(TOLERANCES)]
        M, C, K, b, w = model(kind, damping, seed)
        row = compare(M, C, K, b, w, tol)
        row.update(kind=kind, damping=damping, n=K.shape[0], points=len(w), seed=seed)
        rows.append(row)
        if log:
            log(f"{seed:4d} {kind:13s} {damping:8s} n={row['n']:4d} tol {tol:.0e} "
                f"converged {row['converged']!s:5s} true {row['true_max']:.1e} estimate "
                f"{row['estimated_error']:.1e} max true/est {row['ratio_max']:.2g} "
                f"(true error above rounding {row['ratio_floor']:.2g})")
    return rows


def summary(rows: list[dict[str, Any]]) -> list[str]:
    """Markdown table: per kind and damping, and over all."""
    groups: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault(f"{r['kind']}, {r['damping']}", []).append(r)
    groups["all"] = rows
    lines = ["| models | cases | frequencies | max true/estimate per frequency | ... where "
             "the true error is above rounding (1e-10 and 100 eps kappa) | max error / "
             "estimated_error over the band (min - max) | converged | tol met where "
             "converged |",
             "|:---|---:|---:|---:|---:|---:|---:|---:|"]
    for name, group in groups.items():
        conv = [r for r in group if r["converged"]]
        lines.append(
            f"| {name} | {len(group)} | {sum(r['points'] for r in group):,} | "
            f"{max(r['ratio_max'] for r in group):.2g} | "
            f"{max(r['ratio_floor'] for r in group):.2g} | "
            f"{min(r['band_ratio'] for r in group):.1e} - "
            f"{max(r['band_ratio'] for r in group):.2g} | {len(conv)}/{len(group)} | "
            f"{sum(r['tol_met'] for r in conv)}/{len(conv)} |")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=240)
    args = parser.parse_args(argv)
    rows = run(args.cases, log=lambda m: print(m, file=sys.stderr, flush=True))
    print("\n".join(summary(rows)))
    worst = max(rows, key=lambda r: r["ratio_max"])
    print(f"\nlargest true/estimate at one frequency: {worst['ratio_max']:.2g} "
          f"({worst['kind']}, {worst['damping']}, seed {worst['seed']}; the true error "
          f"there is {worst['true'][np.nanargmax(worst['true'] / worst['error'])]:.1e})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
