"""Benchmark 6: reduced-order frequency response of 2-D mass-spring grids (docs/performance.md).

The model: an ``nx x nx`` grid of masses, each joined to its four neighbours by
springs, the edge masses grounded by a spring 1e4; a unit force F_C at one interior
mass.  Numbered row by row, so the band is nx (100 x 100: n = 10,000, band 100).
Three kinds (``--kinds``):

``random``
    masses 1 ... 1.3 and springs 1e4 ... 1.2e4 (random), Rayleigh damping
    C = 0.1 M + 1e-3 K;
``uniform``
    unit masses, every spring 1e4, the same Rayleigh damping;
``uniform-mass``
    unit masses, every spring 1e4, mass-proportional damping C = 0.1 M: at
    s^2 = mean(diag K) / mean(diag M) the diagonal of K - s^2 M + i s C is 0.1 s i
    against off-diagonal springs of 1e4 (a cost probe there leaves the diagonal:
    what ``auto`` once did).

Frequencies: ``n_f`` evenly spaced from 0.5 x the lowest to the 40th natural
frequency (40 resonances in the band).

Sides, on the same frequencies:

``resonant auto``
    ``sweep(model.linearize(), "w", omegas, names=...)`` on a ``[matrices]`` model
    file (``.mtx``; loading not timed), in a fresh process whose peak resident set
    size is measured (``getrusage(RUSAGE_SELF).ru_maxrss`` after the sweep): the
    reduced model when its estimated error is below 1e-6, an exact solve otherwise;
``resonant direct``
    the same with ``method="direct"`` (the cheapest exact method by its cost model);
``sparse LU loop``
    hand-written: ``scipy.sparse.linalg.splu(K - w^2 M + i w C).solve(f)`` per
    frequency (scipy's defaults); its solves at the check frequencies are the
    reference of the errors;
``modal, 50 modes``
    hand-written truncated modal superposition: the 50 lowest modes by
    ``eigsh(K, 50, M, sigma=0)`` (timed), modal damping diag(Phi^T C Phi), no
    residual correction.

The direct sides cost the same at every frequency; they run on ``direct_subset``
frequencies spread over the band (the check frequencies among them) and their
time is scaled to n_f (marked ``~ *``).  Errors: against the LU loop's solves at 20
check frequencies spread over the band (8 beyond 50,000 DOF), per frequency
max_j |z_j - z_ref,j| / max_j |z_ref,j| over the reported coordinates (100 spread
over the grid and the loaded one), then the maximum over the checks.  Beyond
50,000 DOF only ``auto`` and the LU loop (at the check frequencies) run.

Examples
--------
>>> M, C, K, f = grid_matrices(3)
>>> K.shape, float(f.sum()), bool(K.diagonal().min() > 0)
((9, 9), 1.0, True)
>>> M, C, K, f = grid_matrices(3, kind="uniform-mass")
>>> float(M.diagonal().max()), float(abs(C - 0.1 * M).max())
(1.0, 0.0)
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import SRC, environment, fmt_time  # noqa: E402

sys.path.insert(0, str(SRC))  # this checkout's resonant, in this process as in the child

ALPHA, BETA = 0.1, 1e-3
RESONANCES = 40
MODES = 50
CHECKS = 20
#: check frequencies (exact LU solves) of the largest grids
CHECKS_LARGE = 8
#: beyond this many DOF only auto and the LU loop at the checks run
LARGE = 50_000
TARGET_TIME, TARGET_ERROR = 2.0, 1e-6
#: auto's time as a fraction of the sparse LU loop's at 10,000 DOF
TARGET_RATIO = 0.02
#: the largest grid: seconds and peak resident set size (bytes)
TARGET_LARGE_TIME, TARGET_LARGE_RSS = 60.0, 4 * 2**30
KINDS = {
    "random": "random masses 1-1.3 and springs 1e4-1.2e4, C = 0.1 M + 1e-3 K",
    "uniform": "unit masses, springs 1e4, C = 0.1 M + 1e-3 K",
    "uniform-mass": "unit masses, springs 1e4, C = 0.1 M",
}
#: the report's description of the benchmark
DESCRIPTION = (
    "2-D mass-spring grids nx x nx, edges grounded, a unit force at one interior mass, "
    "numbered row by row (band nx), of three kinds: `random` (" + KINDS["random"] + "), "
    "`uniform` (" + KINDS["uniform"] + ") and `uniform-mass` (" + KINDS["uniform-mass"] +
    "); n_f frequencies evenly spaced from 0.5 x the lowest to the 40th natural frequency. "
    "resonant: `sweep(model.linearize(), 'w', omegas, names=...)` on a `[matrices]` model "
    "file (`.mtx`, loading not timed), `method='auto'` (in a fresh process: its peak RSS "
    "is measured) and `method='direct'`; hand-written: scipy `splu` per frequency (scipy's "
    "defaults), and truncated modal superposition of the 50 lowest modes (`eigsh` "
    "shift-invert, timed; no residual correction). Errors against the LU loop's solves at "
    "20 check frequencies spread over the band (8 beyond 50,000 DOF, where only auto and "
    "the LU loop run): max_j |z_j - z_ref,j| / max_j |z_ref,j| over 101 coordinates spread "
    "over the grid (the loaded one among them), maximum over the checks. 'estimated "
    "error' is what resonant reports with the result. See `benchmarks/bench_reduced.py`.")


def grid_matrices(nx: int, seed: int = 0, kind: str = "random"
                  ) -> tuple[Any, Any, Any, np.ndarray]:
    """(M, C, K, f) of the nx x nx grid of ``kind`` (scipy.sparse CSR, f the load)."""
    import scipy.sparse as sp

    n = nx * nx
    idx = np.arange(n).reshape(nx, nx)
    rows = np.concatenate([idx[:, :-1].ravel(), idx[:-1, :].ravel()])
    cols = np.concatenate([idx[:, 1:].ravel(), idx[1:, :].ravel()])
    rng = np.random.default_rng(seed)
    uniform = kind != "random"
    k = 1e4 * (np.ones(len(rows)) if uniform else 1 + 0.2 * rng.random(len(rows)))
    springs = sp.coo_matrix((k, (rows, cols)), shape=(n, n))
    springs = springs + springs.T
    edge = np.zeros((nx, nx), dtype=bool)
    edge[0, :] = edge[-1, :] = edge[:, 0] = edge[:, -1] = True
    K = (sp.diags(np.asarray(springs.sum(axis=1)).ravel() + 1e4 * edge.ravel())
         - springs).tocsr()
    M = sp.diags(np.ones(n) if uniform else 1 + 0.3 * rng.random(n)).tocsr()
    C = (ALPHA * M + (0.0 if kind == "uniform-mass" else BETA) * K).tocsr()
    C.eliminate_zeros()
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


def child(directory: Path) -> None:
    """The auto side in this (fresh) process: sweep the model in ``directory`` at the
    frequencies saved there; write the time, the peak RSS, what the reduced model was
    and the responses at the check frequencies."""
    import resonant.analyses.kernel as kernel
    import resonant.analyses.sweep as rsweep
    import resonant.model.limits as limits
    from resonant.api import load

    # matrices beyond the model layer's default limit of 200,000 DOF: raised for this
    # process, as docs/security.md says
    limits.MAX_MATRIX_DIMENSION = max(limits.MAX_MATRIX_DIMENSION, 10**6)
    omegas = np.load(directory / "omegas.npy")
    checks = np.load(directory / "checks.npy")
    names = json.loads((directory / "names.json").read_text(encoding="utf-8"))
    model = load(directory / "grid.toml").linearize()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    seen: list[Any] = []
    plain = kernel.reduced_response

    def spy(*args: Any, **kwargs: Any) -> Any:  # what the reduced model was (not timed)
        seen.append(plain(*args, **kwargs))
        return seen[-1]

    kernel.reduced_response = spy  # type: ignore[assignment]
    t0 = time.perf_counter()
    result = rsweep.sweep(model, "w", omegas, names=names, method="auto", progress=False)
    elapsed = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    np.save(directory / "z.npy", from_sweep(result, names)[checks])
    red = seen[-1] if seen else None
    (directory / "out.json").write_text(json.dumps({
        "time": elapsed, "method": result.method, "estimated_error": result.estimated_error,
        "peak_rss": peak, "rss_before": before,
        "reduced": None if red is None else {
            "basis": red.basis_size, "expansion_points": len(red.expansion),
            "validations": len(red.checks), "estimated_error": red.estimated_error,
            "seconds": red.seconds, "converged": red.converged}}), encoding="utf-8")


def auto_in_child(directory: Path, omegas: np.ndarray, checks: np.ndarray,
                  names: list[str]) -> tuple[dict[str, Any], np.ndarray]:
    """Run :func:`child` in a fresh Python process; its report and responses."""
    np.save(directory / "omegas.npy", omegas)
    np.save(directory / "checks.npy", checks)
    (directory / "names.json").write_text(json.dumps(names), encoding="utf-8")
    proc = subprocess.run([sys.executable, __file__, "--child", str(directory)],
                          env=environment(), capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"the auto side failed: {proc.stderr[-2000:]}")
    report = json.loads((directory / "out.json").read_text(encoding="utf-8"))
    return report, np.load(directory / "z.npy")


def run_case(nx: int, n_f: int = 1000, direct_subset: int = 100, full: bool = False,
             log: Any = None, kind: str = "random") -> dict[str, Any]:
    """Every side on the nx x nx grid of ``kind``; times (s) and errors against the
    exact solves."""
    import scipy.sparse.linalg as sla

    say = log or (lambda message: None)
    M, C, K, f = grid_matrices(nx, kind=kind)
    n = nx * nx
    large = n > LARGE
    lam = np.sort(sla.eigsh(K, k=RESONANCES, M=M, sigma=0, return_eigenvectors=False))
    omegas = np.linspace(0.5 * np.sqrt(lam[0]), np.sqrt(lam[RESONANCES - 1]), n_f)
    checks = np.unique(np.linspace(0, n_f - 1, CHECKS_LARGE if large else CHECKS)
                       .round().astype(int))
    loaded = int(np.argmax(f))
    keep = np.unique(np.r_[np.linspace(0, n - 1, 100).round().astype(int), loaded])
    row: dict[str, Any] = {"nx": nx, "n": n, "n_f": n_f, "kind": kind,
                           "band": [float(omegas[0]), float(omegas[-1])]}
    subset = np.arange(n_f) if full else np.unique(np.r_[checks, np.linspace(
        0, n_f - 1, 0 if large else max(direct_subset, len(checks))).round().astype(int)])
    scale = n_f / len(subset)
    at_checks = np.searchsorted(subset, checks)
    t0 = time.perf_counter()
    z = lu_loop(M, C, K, f, omegas[subset], keep)
    row["lu_loop"] = {"time": (time.perf_counter() - t0) * scale, "extrapolated": scale != 1,
                      "error": 0.0}
    ref = z[at_checks]  # the exact reference: SuperLU with partial pivoting per point
    say(f"  grid {nx}x{nx} {kind} sparse LU loop: {fmt_time(row['lu_loop']['time'])}")
    with tempfile.TemporaryDirectory() as tmp:
        path = write_model(Path(tmp), M, C, K, f)
        names = [f"q{i + 1}" for i in keep]
        report, z_auto = auto_in_child(Path(tmp), omegas, checks, names)
        row["auto"] = {"time": report["time"], "extrapolated": False,
                       "method": report["method"], "error": agreement(z_auto, ref),
                       "estimated_error": report["estimated_error"],
                       "peak_rss": report["peak_rss"], "rss_before": report["rss_before"]}
        row["reduced"] = report["reduced"]
        say(f"  grid {nx}x{nx} {kind} resonant auto: {fmt_time(report['time'])} "
            f"({report['method']}), error {row['auto']['error']:.1e}, peak RSS "
            f"{report['peak_rss'] / 2**30:.2f} GB")
        if not large:
            row["direct"] = _direct_side(path, omegas[subset], names, scale, ref, at_checks)
            say(f"  grid {nx}x{nx} {kind} resonant direct: "
                f"{fmt_time(row['direct']['time'])}")
    if not large:
        t0 = time.perf_counter()
        z = modal_loop(M, C, K, f, omegas, keep)
        row["modal"] = {"time": time.perf_counter() - t0, "extrapolated": False,
                        "error": agreement(z[checks], ref)}
    return row


def _direct_side(path: Path, values: np.ndarray, names: list[str], scale: float,
                 ref: np.ndarray, at_checks: np.ndarray) -> dict[str, Any]:
    import resonant.analyses.sweep as rsweep
    from resonant.api import load

    model = load(path).linearize()
    t0 = time.perf_counter()
    result = rsweep.sweep(model, "w", values, names=names, method="direct", progress=False)
    elapsed = time.perf_counter() - t0
    z = from_sweep(result, names)[at_checks]
    return {"time": elapsed * scale, "extrapolated": scale != 1, "method": result.method,
            "error": agreement(z, ref), "estimated_error": None}


SIDES = (("auto", "resonant auto"), ("direct", "resonant direct"),
         ("lu_loop", "sparse LU loop (splu per frequency)"),
         ("modal", "modal, 50 modes, no residual"))


def table(rows: list[dict[str, Any]]) -> list[str]:
    """Markdown table of the rows."""
    lines = ["| grid | kind | n | n_f | side | method | time | vs sparse LU loop | max error "
             "| estimated error | peak RSS |",
             "|:---|:---|---:|---:|:---|:---|---:|---:|---:|---:|---:|"]
    for r in rows:
        for key, label in SIDES:
            if key not in r:
                continue
            s = r[key]
            est = s.get("estimated_error")
            approx = s["extrapolated"] or r["lu_loop"]["extrapolated"]
            ratio = s["time"] / r["lu_loop"]["time"]
            rss = s.get("peak_rss")
            lines.append(
                f"| {r['nx']}x{r['nx']} | {r.get('kind', 'random')} | {r['n']:,} | "
                f"{r['n_f']} | {label} | {s.get('method', '-')} | "
                f"{fmt_time(s['time'], s['extrapolated'])} | {'~' if approx else ''}"
                f"{ratio:.3g}x | {s['error']:.1e} | {'-' if est is None else f'{est:.1e}'} | "
                f"{'-' if rss is None else f'{rss / 2**30:.2f} GB'} |")
    described = [r for r in rows if r.get("reduced")]
    lines += ["", "The reduced models of the auto side: " + "; ".join(
        f"{r['nx']}x{r['nx']} {r.get('kind', 'random')}: {r['reduced']['basis']} basis "
        f"vectors from {r['reduced']['expansion_points']} expansion points, "
        f"{r['reduced']['validations']} validation solves" for r in described) + ".",
        "", "`~ ... *` = the side ran on a subset of the frequencies (spread over the band, "
        "the check frequencies among them) and its time was scaled to n_f (its cost per "
        "frequency does not depend on the frequency). Peak RSS: of the fresh process that "
        "loaded the model and ran the sweep."]
    return lines


def target(rows: list[dict[str, Any]]) -> tuple[str, bool] | None:
    """(text, met) of the time target at 10,000 DOF (random grid)."""
    for r in rows:
        if r["n"] == 10_000 and r.get("kind", "random") == "random":
            a = r["auto"]
            ok = a["time"] <= TARGET_TIME and a["error"] <= TARGET_ERROR
            return (f"{fmt_time(a['time'])} ({a['method']}), error {a['error']:.1e} "
                    f"(estimated {a['estimated_error'] or 0:.1e})", ok)
    return None


def targets(rows: list[dict[str, Any]]) -> list[tuple[str, str, bool]]:
    """(target, measured, met) of every row: 10,000 DOF within TARGET_RATIO of the LU
    loop at TARGET_ERROR; the largest grids within TARGET_LARGE_TIME and _RSS."""
    out = []
    for r in rows:
        a, lu = r["auto"], r["lu_loop"]
        name = f"{r['nx']}x{r['nx']} {r.get('kind', 'random')}, n_f = {r['n_f']}"
        if r["n"] <= LARGE:
            ratio = a["time"] / lu["time"]
            out.append((f"{name}: auto <= {TARGET_RATIO:g}x the LU loop, error <= "
                        f"{TARGET_ERROR:g}",
                        f"{ratio:.3g}x ({fmt_time(a['time'])} vs "
                        f"{fmt_time(lu['time'], lu['extrapolated'])}), error {a['error']:.1e}",
                        ratio <= TARGET_RATIO and a["error"] <= TARGET_ERROR))
        else:
            rss = a["peak_rss"]
            out.append((f"{name}: auto <= {TARGET_LARGE_TIME:g} s and <= "
                        f"{TARGET_LARGE_RSS / 2**30:g} GB, error <= {TARGET_ERROR:g}",
                        f"{fmt_time(a['time'])}, {rss / 2**30:.2f} GB, error "
                        f"{a['error']:.1e}",
                        a["time"] <= TARGET_LARGE_TIME and rss <= TARGET_LARGE_RSS
                        and a["error"] <= TARGET_ERROR))
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 200])
    parser.add_argument("--kinds", nargs="+", default=["random"], choices=sorted(KINDS))
    parser.add_argument("--n-f", type=int, default=1000)
    parser.add_argument("--direct-subset", type=int, default=100,
                        help="frequencies the direct sides run on (scaled to n_f)")
    parser.add_argument("--full", action="store_true",
                        help="run the direct sides on every frequency")
    parser.add_argument("--json", type=Path, help="write the rows here")
    parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(args.child)
        return 0
    rows = []
    for nx in args.sizes:
        for kind in args.kinds:
            rows.append(run_case(nx, args.n_f, args.direct_subset, args.full,
                                 log=lambda m: print(m, file=sys.stderr, flush=True),
                                 kind=kind))
            if args.json:  # after every case: a long run keeps what it has
                args.json.write_text(json.dumps(rows, indent=1), encoding="utf-8")
    print("\n".join(table(rows)))
    print("\n| target | measured | met? |\n|:---|:---|:---:|")
    for goal, measured, met in targets(rows):
        print(f"| {goal} | {measured} | {'yes' if met else '**no**'} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
