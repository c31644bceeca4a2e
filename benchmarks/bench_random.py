"""Benchmark: random response of 2-D grids up to 250,000 DOF (docs/performance.md).

The model: the ``random`` 2-D mass-spring grid of :mod:`bench_reduced` (masses 1-1.3,
springs 1e4-1.2e4 to the four neighbours, edges grounded), its stiffness scaled so that
the lowest natural frequency is :data:`LOWEST` Hz, Rayleigh damping C = alpha M + beta K
with 2 % of critical damping at the lowest frequency and at 2000 Hz (about 40 natural
frequencies lie in the band 20-2000 Hz).  Input: a base acceleration of every mass
(influence vector 1, load -M 1 a(t)) whose one-sided density is a GEVS-shaped table of
:data:`LINES` rows (NASA GSFC-STD-7000B qualification levels, 20-2000 Hz, sampled
log-log); responses: the relative displacements of five masses.

Sides:

``resonant``
    ``random_response(system, spec, names=...)`` on a ``[matrices]`` model (``.npz``
    files; loading not timed), method ``auto``, in a fresh process (its peak resident
    set size is measured): its RMS values and its estimated relative error of each
    mean square;
``scipy modal``
    hand-written modal superposition: the modes below 1.5 x 2000 Hz by ``eigsh``
    (shift-invert about 0), modal damping diag(Phi^T C Phi) (exact: Rayleigh), the
    static residual of the truncated modes (one sparse solve with K), |H|^2 G
    integrated by the trapezoidal rule on 200,000 log-spaced frequencies and the table's
    rows; in a fresh process too.

Both with one BLAS thread (the caller sets OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1).
``--busy`` runs a busy loop on one core during both sides.

Examples
--------
>>> table = gevs_table(5)
>>> table.shape, float(table[0, 0]), float(table[-1, 0])
((5, 2), 20.0, 2000.0)
>>> M, C, K = grid(4)
>>> K.shape
(16, 16)
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_reduced import grid_matrices  # noqa: E402
from common import SRC, environment  # noqa: E402

sys.path.insert(0, str(SRC))

#: the lowest natural frequency of the grid (Hz)
LOWEST = 400.0
#: damping ratio at the lowest frequency and at the band's top
ZETA = 0.02
BAND = (20.0, 2000.0)
#: rows of the density table
LINES = 2000
#: GEVS qualification breakpoints (Hz, g^2/Hz): +6 dB/oct, flat 0.16, -6 dB/oct
GEVS = ((20.0, 0.026), (50.0, 0.16), (800.0, 0.16), (2000.0, 0.026))
G0 = 9.80665
#: modes of the hand-written superposition: below this multiple of the band's top
MODAL_REACH = 1.5
#: frequencies of the hand-written integration
FINE = 200_000


def gevs_table(lines: int = LINES) -> np.ndarray:
    """(lines, 2): frequency (Hz) and density ((m/s^2)^2/Hz) of the GEVS shape,
    log-spaced rows, log-log interpolated between the breakpoints."""
    f = np.geomspace(BAND[0], BAND[1], lines)
    bf, bv = np.log([p[0] for p in GEVS]), np.log([p[1] for p in GEVS])
    return np.column_stack([f, np.exp(np.interp(np.log(f), bf, bv)) * G0 ** 2])


def grid(nx: int) -> tuple[Any, Any, Any]:
    """(M, C, K): the scaled, Rayleigh-damped random grid."""
    import scipy.sparse.linalg as sla

    M, _, K, _ = grid_matrices(nx, kind="random")
    if nx * nx > 1:
        lam = float(sla.eigsh(K, k=1, M=M, sigma=0, return_eigenvectors=False)[0])
    else:
        lam = float(K.diagonal()[0] / M.diagonal()[0])
    K = K * ((2 * np.pi * LOWEST) ** 2 / lam)
    w1, w2 = 2 * np.pi * LOWEST, 2 * np.pi * BAND[1]
    # zeta = alpha / (2 w) + beta w / 2 equal to ZETA at w1 and w2
    alpha = 2 * ZETA * w1 * w2 / (w1 + w2)
    beta = 2 * ZETA / (w1 + w2)
    return M.tocsr(), (alpha * M + beta * K).tocsr(), K.tocsr()


def response_points(nx: int) -> list[int]:
    """Five masses: the centre, two off-centre points and two near the edge."""
    pts = [(nx // 2, nx // 2), (nx // 3, nx // 4), (nx // 4, 2 * nx // 3),
           (1, nx // 2), (nx - 2, nx - 3)]
    return sorted({i * nx + j for i, j in pts})


def write_model(directory: Path, nx: int) -> None:
    import scipy.sparse as sp

    M, C, K = grid(nx)
    for key, a in (("M", M), ("C", C), ("K", K)):
        sp.save_npz(directory / f"{key}.npz", a)
    (directory / "grid.toml").write_text(
        f'title = "random grid {nx}x{nx}"\n\n[matrices]\nM = "M.npz"\nC = "C.npz"\n'
        'K = "K.npz"\n', encoding="utf-8")
    np.save(directory / "table.npy", gevs_table())


def resonant_side(directory: Path, nx: int, tolerance: float) -> dict[str, Any]:
    import resonant.analyses.random_response as rr
    import resonant.model.limits as limits
    from resonant.analyses.random_response import random_response
    from resonant.expressions import parse
    from resonant.model import load
    from resonant.model.random_spec import RandomInput, RandomSpec
    from resonant.system import linear_system

    limits.MAX_MATRIX_DIMENSION = max(limits.MAX_MATRIX_DIMENSION, 10**6)
    system = linear_system(load(directory / "grid.toml"))
    n = nx * nx
    one = parse("1")
    spec = RandomSpec((RandomInput("a", 0, np.load(directory / "table.npy"), None,
                                   base=(one,) * n),), (), BAND, tolerance=tolerance)
    names = [system.coordinates[i] for i in response_points(nx)]
    seen: list[Any] = []
    plain = rr.reduced_model

    def spy(*args: Any, **kwargs: Any) -> Any:  # what the reduced model was
        seen.append(plain(*args, **kwargs))
        return seen[-1]

    rr.reduced_model = spy  # type: ignore[assignment]
    t0, c0 = time.perf_counter(), time.process_time()
    result = random_response(system, spec, names=names)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    return {"seconds": seconds, "cpu": cpu, "rms": [result.rms[q] for q in names],
            "error": [result.error[q] for q in names], "method": result.method,
            "frequencies": len(result.frequency), "warnings": list(result.warnings),
            "reduced": None if not seen else {
                "basis": int(seen[-1].V.shape[1]), "expansion": len(seen[-1].expansion),
                "validations": len(seen[-1].checks), "seconds": seen[-1].seconds,
                "estimated_error": seen[-1].estimated_error.tolist(),
                "adjoint_residuals": seen[-1].adjoint_residuals.tolist()}}


def scipy_side(directory: Path, nx: int) -> dict[str, Any]:
    """The hand-written modal superposition with the static residual."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla

    t0, c0 = time.perf_counter(), time.process_time()
    M, C, K = (sp.load_npz(directory / f"{key}.npz").tocsc() for key in "MCK")
    table = np.load(directory / "table.npy")
    rows = np.array(response_points(nx))
    load = -(M @ np.ones(M.shape[0]))
    reach = (2 * np.pi * MODAL_REACH * BAND[1]) ** 2
    k = 40
    while True:
        lam, phi = sla.eigsh(K, k=min(k, M.shape[0] - 2), M=M, sigma=0, which="LM")
        if lam.max() >= reach or k >= M.shape[0] - 2:
            break
        k *= 2
    keep = lam < reach
    lam, phi = lam[keep], phi[:, keep]
    c = np.einsum("ij,ij->j", phi, C @ phi)
    p = phi.T @ load
    static = sla.splu(K).solve(load)
    residual = static[rows] - phi[rows] @ (p / lam)
    f = np.unique(np.r_[np.geomspace(BAND[0], BAND[1], FINE), table[:, 0]])
    G = np.exp(np.interp(np.log(f), np.log(table[:, 0]), np.log(table[:, 1])))
    parts = []
    for start in range(0, len(f), 20_000):
        w = 2 * np.pi * f[start:start + 20_000, None]
        H = (p / (lam - w ** 2 + 1j * w * c)) @ phi[rows].T + residual
        parts.append(np.abs(H) ** 2)
    S = np.concatenate(parts) * G[:, None]
    ms = np.trapezoid(S, f, axis=0)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    return {"seconds": seconds, "cpu": cpu, "rms": np.sqrt(ms).tolist(),
            "modes": int(len(lam))}


def child(side: str, directory: Path, nx: int, tolerance: float) -> None:
    out = resonant_side(directory, nx, tolerance) if side == "resonant" else \
        scipy_side(directory, nx)
    out["peak_rss"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    (directory / f"{side}.json").write_text(json.dumps(out), encoding="utf-8")


def run_side(side: str, directory: Path, nx: int, tolerance: float) -> dict[str, Any]:
    proc = subprocess.run([sys.executable, __file__, "--child", side, str(directory),
                           str(nx), str(tolerance)], env=environment(), capture_output=True,
                          text=True, check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"the {side} side failed: {proc.stderr[-3000:]}")
    result: dict[str, Any] = json.loads((directory / f"{side}.json").read_text("utf-8"))
    return result


def _spin(stop: Any) -> None:
    x = 0
    while not stop.is_set():
        x += 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 500])
    parser.add_argument("--tolerance", type=float, default=1e-3)
    parser.add_argument("--busy", action="store_true", help="keep one core busy")
    parser.add_argument("--child", nargs=4, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        side, directory, nx, tol = args.child
        child(side, Path(directory), int(nx), float(tol))
        return 0
    stop = multiprocessing.Event()
    spinner = None
    if args.busy:
        spinner = multiprocessing.Process(target=_spin, args=(stop,), daemon=True)
        spinner.start()
    try:
        for nx in args.sizes:
            with tempfile.TemporaryDirectory() as tmp:
                directory = Path(tmp)
                write_model(directory, nx)
                res = run_side("resonant", directory, nx, args.tolerance)
                ref = run_side("scipy", directory, nx, args.tolerance)
            diff = max(abs(a / b - 1) for a, b in zip(res["rms"], ref["rms"]))
            print(json.dumps({"nx": nx, "n": nx * nx, "busy": args.busy, "resonant": res,
                              "scipy": ref, "rms_difference": diff}), flush=True)
            busy = "one core busy" if args.busy else "idle"
            print(f"| {nx}x{nx} | {nx * nx:,} | {busy} | resonant ({res['method']}) | "
                  f"{res['seconds']:.3g} s | {res['cpu']:.3g} s | {diff:.1e} | "
                  f"{max(res['error']):.1e} | {res['frequencies']} | "
                  f"{res['peak_rss'] / 2**30:.2f} GB |", flush=True)
            print(f"| {nx}x{nx} | {nx * nx:,} | {busy} | scipy modal ({ref['modes']} modes "
                  f"+ static residual) | {ref['seconds']:.3g} s | {ref['cpu']:.3g} s | - | - | "
                  f"{FINE} | {ref['peak_rss'] / 2**30:.2f} GB |", flush=True)
    finally:
        stop.set()
        if spinner is not None:
            spinner.join()
    return 0


if __name__ == "__main__":
    sys.exit(main())
