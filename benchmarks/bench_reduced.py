"""Benchmark 6: reduced-order frequency response of 2-D mass-spring grids (docs/performance.md).

The model: an ``nx x nx`` grid of masses (1 ... 1.3, random), each joined to its four
neighbours by springs 1e4 ... 1.2e4 (random), the edge masses grounded by a spring
1e4; Rayleigh damping C = 0.1 M + 1e-3 K; a unit force F_C at one interior mass.
Numbered row by row, so the band is nx (100 x 100: n = 10,000, band 100).
Frequencies: ``n_f`` evenly spaced from 0.5 x the lowest to the 40th natural
frequency (40 resonances in the band).

Sides, on the same frequencies:

``resonant auto``
    ``sweep(model.linearize(), "w", omegas, names=...)`` on a ``[matrices]`` model
    file (``.mtx``; loading not timed): the reduced model when its estimated error
    is below 1e-6, an exact solve otherwise;
``resonant direct``
    the same with ``method="direct"`` (the cheapest exact method by its cost model);
``sparse LU loop``
    hand-written: ``scipy.sparse.linalg.splu(K - w^2 M + i w C).solve(f)`` per
    frequency (scipy's defaults);
``modal, 50 modes``
    hand-written truncated modal superposition: the 50 lowest modes by
    ``eigsh(K, 50, M, sigma=0)`` (timed), modal damping diag(Phi^T C Phi), no
    residual correction.

The direct sides cost the same at every frequency; they run on ``direct_subset``
frequencies spread over the band (the 20 check frequencies among them) and their
time is scaled to n_f (marked ``~ *``).  Errors: against an exact SuperLU solve at 20
check frequencies spread over the band, per frequency
max_j |z_j - z_ref,j| / max_j |z_ref,j| over the reported coordinates (100 spread over
the grid and the loaded one), then the maximum over the 20.

Examples
--------
>>> M, C, K, f = grid_matrices(3)
>>> K.shape, float(f.sum()), bool(K.diagonal().min() > 0)
((9, 9), 1.0, True)
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import fmt_time  # noqa: E402

ALPHA, BETA = 0.1, 1e-3
RESONANCES = 40
MODES = 50
CHECKS = 20
TARGET_TIME, TARGET_ERROR = 2.0, 1e-6
#: the report's description of the benchmark
DESCRIPTION = (
    "2-D mass-spring grids nx x nx (random masses 1-1.3 and springs 1e4-1.2e4, edges "
    "grounded, C = 0.1 M + 1e-3 K, a unit force at one interior mass; numbered row by row, "
    "so the band is nx), n_f frequencies evenly spaced from 0.5 x the lowest to the 40th "
    "natural frequency. resonant: `sweep(model.linearize(), 'w', omegas, names=...)` on a "
    "`[matrices]` model file (`.mtx`, loading not timed), `method='auto'` and "
    "`method='direct'`; hand-written: scipy `splu` per frequency, and truncated modal "
    "superposition of the 50 lowest modes (`eigsh` shift-invert, timed; no residual "
    "correction). Errors against exact SuperLU solves at 20 check frequencies spread over "
    "the band: max_j |z_j - z_ref,j| / max_j |z_ref,j| over 101 coordinates spread over "
    "the grid (the loaded one among them), maximum over the 20. 'estimated error' is what "
    "resonant reports with the result. See `benchmarks/bench_reduced.py`.")


def grid_matrices(nx: int, seed: int = 0) -> tuple[Any, Any, Any, np.ndarray]:
    """(M, C, K, f) of the nx x nx grid (scipy.sparse CSR, f the load vector)."""
    import scipy.sparse as sp

    n = nx * nx
    idx = np.arange(n).reshape(nx, nx)
    rows = np.concatenate([idx[:, :-1].ravel(), idx[:-1, :].ravel()])
    cols = np.concatenate([idx[:, 1:].ravel(), idx[1:, :].ravel()])
    rng = np.random.default_rng(seed)
    springs = sp.coo_matrix((1e4 * (1 + 0.2 * rng.random(len(rows))), (rows, cols)),
                            shape=(n, n))
    springs = springs + springs.T
    edge = np.zeros((nx, nx), dtype=bool)
    edge[0, :] = edge[-1, :] = edge[:, 0] = edge[:, -1] = True
    K = (sp.diags(np.asarray(springs.sum(axis=1)).ravel() + 1e4 * edge.ravel())
         - springs).tocsr()
    M = sp.diags(1 + 0.3 * rng.random(n)).tocsr()
    C = (ALPHA * M + BETA * K).tocsr()
    f = np.zeros(n)
    f[idx[nx // 3, nx // 4]] = 1.0
    return M, C, K, f


def write_model(directory: Path, M: Any, C: Any, K: Any, f: np.ndarray) -> Path:
    import scipy.io

    for key, a in (("M", M), ("C", C), ("K", K)):
        scipy.io.mmwrite(str(directory / f"{key}.mtx"), a)
    force = ", ".join("1" if v else "0" for v in f)
    path = directory / "grid.toml"
    path.write_text(f'title = "grid, n = {len(f)}"\n\n[parameters]\nw = 1\n\n[matrices]\n'
                    'M = "M.mtx"\nC = "C.mtx"\nK = "K.mtx"\n\n[[harmonic]]\nomega = "w"\n'
                    f"F_C = [{force}]\n", encoding="utf-8")
    return path


def modal_loop(M: Any, C: Any, K: Any, f: np.ndarray, omegas: np.ndarray, keep: np.ndarray
               ) -> np.ndarray:
    """Truncated modal superposition: 50 lowest modes, no residual correction."""
    from scipy.sparse.linalg import eigsh

    lam, phi = eigsh(K, k=MODES, M=M, sigma=0, which="LM")
    c = np.einsum("ij,ij->j", phi, C @ phi)       # modal damping (Rayleigh: exact diagonal)
    forces = phi.T @ f
    q = forces / (lam - omegas[:, None] ** 2 + 1j * omegas[:, None] * c)
    return q @ phi[keep].T


def lu_loop(M: Any, C: Any, K: Any, f: np.ndarray, omegas: np.ndarray, keep: np.ndarray
            ) -> np.ndarray:
    """One scipy ``splu`` (default options) per frequency."""
    from scipy.sparse.linalg import splu

    b = f.astype(complex)
    return np.array([splu((K - w * w * M + 1j * w * C).tocsc()).solve(b)[keep]
                     for w in omegas])


def from_sweep(result: Any, names: list[str]) -> np.ndarray:
    X = np.stack([np.asarray(result.amplitudes[q]) for q in names], axis=1)
    d = np.nan_to_num(np.stack([np.asarray(result.phases[q]) for q in names], axis=1))
    return X * np.sin(d) - 1j * X * np.cos(d)


def agreement(z: np.ndarray, ref: np.ndarray) -> float:
    """max over frequencies of max_j |z_j - ref_j| / max_j |ref_j|."""
    return float(np.max(np.max(np.abs(z - ref), axis=1) / np.max(np.abs(ref), axis=1)))


def run_case(nx: int, n_f: int = 1000, direct_subset: int = 100, full: bool = False,
             log: Any = None) -> dict[str, Any]:
    """Every side on the nx x nx grid; times (s) and errors against the exact solves."""
    import scipy.sparse.linalg as sla

    import resonant.analyses.sweep as rsweep
    from resonant.api import load

    say = log or (lambda message: None)
    M, C, K, f = grid_matrices(nx)
    n = nx * nx
    lam = np.sort(sla.eigsh(K, k=RESONANCES, M=M, sigma=0, return_eigenvectors=False))
    omegas = np.linspace(0.5 * np.sqrt(lam[0]), np.sqrt(lam[RESONANCES - 1]), n_f)
    checks = np.unique(np.linspace(0, n_f - 1, CHECKS).round().astype(int))
    loaded = int(np.argmax(f))
    keep = np.unique(np.r_[np.linspace(0, n - 1, 100).round().astype(int), loaded])
    row: dict[str, Any] = {"nx": nx, "n": n, "n_f": n_f, "band": [float(omegas[0]),
                                                                  float(omegas[-1])]}
    start = time.perf_counter()
    ref = lu_loop(M, C, K, f, omegas[checks], keep)  # exact reference (SuperLU per point)
    row["reference_time"] = time.perf_counter() - start
    subset = np.arange(n_f) if full else np.unique(np.r_[checks, np.linspace(
        0, n_f - 1, max(direct_subset, len(checks))).round().astype(int)])
    scale = n_f / len(subset)
    at_checks = np.searchsorted(subset, checks)
    with tempfile.TemporaryDirectory() as tmp:
        model = load(write_model(Path(tmp), M, C, K, f)).linearize()
        names = [model.coordinates[i] for i in keep]
        for side, method, values in (("auto", "auto", omegas),
                                     ("direct", "direct", omegas[subset])):
            t0 = time.perf_counter()
            result = rsweep.sweep(model, "w", values, names=names, method=method,
                                  progress=False)
            elapsed = time.perf_counter() - t0
            z = from_sweep(result, names)
            z_checks = z[checks] if side == "auto" else z[at_checks]
            row[side] = {"time": elapsed * (1 if side == "auto" else scale),
                         "extrapolated": side != "auto" and scale != 1,
                         "method": result.method, "error": agreement(z_checks, ref),
                         "estimated_error": result.estimated_error}
            say(f"  grid {nx}x{nx} resonant {side}: {fmt_time(row[side]['time'])} "
                f"({result.method}), error {row[side]['error']:.1e}")
    t0 = time.perf_counter()
    z = lu_loop(M, C, K, f, omegas[subset], keep)
    row["lu_loop"] = {"time": (time.perf_counter() - t0) * scale, "extrapolated": scale != 1,
                      "error": agreement(z[at_checks], ref)}
    say(f"  grid {nx}x{nx} sparse LU loop: {fmt_time(row['lu_loop']['time'])}")
    t0 = time.perf_counter()
    z = modal_loop(M, C, K, f, omegas, keep)
    row["modal"] = {"time": time.perf_counter() - t0, "extrapolated": False,
                    "error": agreement(z[checks], ref)}
    say(f"  grid {nx}x{nx} modal (50 modes): {fmt_time(row['modal']['time'])}, error "
        f"{row['modal']['error']:.1e}")
    # what the reduced model was: basis, expansion points (one more run, not timed)
    from resonant.analyses.reduced import reduced_response

    red = reduced_response(M, C, K, f.astype(complex), omegas, keep=keep[:1])
    row["reduced"] = {"basis": red.basis_size, "expansion_points": len(red.expansion),
                      "validations": len(red.checks), "estimated_error": red.estimated_error,
                      "seconds": red.seconds}
    return row


SIDES = (("auto", "resonant auto"), ("direct", "resonant direct"),
         ("lu_loop", "sparse LU loop (splu per frequency)"),
         ("modal", "modal, 50 modes, no residual"))


def table(rows: list[dict[str, Any]]) -> list[str]:
    """Markdown table of the rows."""
    lines = ["| grid | n | n_f | side | method | time | vs resonant auto | max error (20 checks) "
             "| estimated error |", "|:---|---:|---:|:---|:---|---:|---:|---:|---:|"]
    for r in rows:
        for key, label in SIDES:
            s = r[key]
            est = s.get("estimated_error")
            ratio = s["time"] / r["auto"]["time"]
            lines.append(
                f"| {r['nx']}x{r['nx']} | {r['n']:,} | {r['n_f']} | {label} | "
                f"{s.get('method', '-')} | {fmt_time(s['time'], s['extrapolated'])} | "
                f"{'~' if s['extrapolated'] else ''}{ratio:.3g}x | {s['error']:.1e} | "
                f"{'-' if est is None else f'{est:.1e}'} |")
    lines += ["", "The reduced models (`method='reduced'`, run once more, not timed): " + "; ".join(
        f"{r['nx']}x{r['nx']}: {r['reduced']['basis']} basis vectors from "
        f"{r['reduced']['expansion_points']} expansion points, {r['reduced']['validations']} "
        f"validation solves, estimated error {r['reduced']['estimated_error']:.1e}"
        for r in rows) + ".",
        "", "`~ ... *` = the direct side ran on a subset of the frequencies (spread over the "
        "band, the 20 check frequencies among them) and its time was scaled to n_f (its cost "
        "per frequency does not depend on the frequency)."]
    return lines


def target(rows: list[dict[str, Any]]) -> tuple[str, bool] | None:
    """(text, met) of the issue's target at 10,000 DOF."""
    for r in rows:
        if r["n"] == 10_000:
            a = r["auto"]
            ok = a["time"] <= TARGET_TIME and a["error"] <= TARGET_ERROR
            return (f"{fmt_time(a['time'])} ({a['method']}), error {a['error']:.1e} "
                    f"(estimated {a['estimated_error'] or 0:.1e})", ok)
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 200])
    parser.add_argument("--n-f", type=int, default=1000)
    parser.add_argument("--direct-subset", type=int, default=100,
                        help="frequencies the direct sides run on (scaled to n_f)")
    parser.add_argument("--full", action="store_true",
                        help="run the direct sides on every frequency")
    parser.add_argument("--json", type=Path, help="write the rows here")
    args = parser.parse_args(argv)
    rows = []
    for nx in args.sizes:
        rows.append(run_case(nx, args.n_f, args.direct_subset, args.full,
                             log=lambda m: print(m, file=sys.stderr, flush=True)))
    print("\n".join(table(rows)))
    met = target(rows)
    if met:
        print(f"\ntarget (auto <= {TARGET_TIME} s, error <= {TARGET_ERROR:g} at 10,000 DOF): "
              f"{met[0]}: {'met' if met[1] else 'NOT met'}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
