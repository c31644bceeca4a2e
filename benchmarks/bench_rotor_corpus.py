"""Benchmark: the sparse ``[rotor]`` code on a corpus of varied rotors, against the dense
route (docs/performance-corpus.md, Rotors).

Each rotor of the corpus (drawn from a seed, so that every run builds the same ones) has
more than ``resonant.model.rotor.SPARSE_STATIONS`` stations, so that it is assembled
sparse and its Campbell diagram takes the sparse eigensolver; the rotors differ in their
station count, their shaft (segments of different diameters and lengths, hollow or not,
Timoshenko or Euler-Bernoulli), their discs (one to four), their bearings (two or three;
isotropic or not, cross coupled, damped, with coefficients that depend on the speed, on a
pedestal) and their coordinates (lateral, or with the axial and torsional ones, then with
a thrust bearing and a torsional support).  For each rotor:

``assembly``
    the largest entry of |A_sparse - A_dense| / max |A_dense| over M, K, C and G (the
    same rotor assembled dense, ``SPARSE_STATIONS`` raised for it);
``modes``
    the lowest ``--modes`` complex modes at rest and at the top speed by the sparse kernel
    (``resonant.modal.lowest_gyroscopic_modes``) against the dense kernel
    (``resonant.modal.gyroscopic_modes``, the whole state matrix): the largest relative
    difference of the eigenvalues;
``campbell``
    ``campbell`` over ``--speeds`` speeds (the sparse route: its tracking, its Brent root
    finder on the branches), its time, and each 1x critical speed checked by the dense
    kernel at that speed: min_j | |Im s_j| - Omega | / Omega.

Run as ``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/bench_rotor_corpus.py
[--rotors 12] [--speeds 9] [--modes 8] [--json]``.

Examples
--------
>>> text = corpus_rotor(np.random.default_rng(0), 0)
>>> "[rotor]" in text and "[[rotor.bearing]]" in text
True
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))


def corpus_rotor(rng: np.random.Generator, index: int) -> str:
    """One rotor of the corpus, as a ``[rotor]`` model, drawn from ``rng``."""
    stations = int(rng.integers(101, 181))
    elements = stations - 1
    segments = int(rng.integers(1, 4))
    cuts = np.sort(rng.choice(np.arange(1, elements), segments - 1, replace=False))
    counts = np.diff(np.concatenate([[0], cuts, [elements]]))
    along = bool(rng.random() < 0.4)
    shear = 'G = "81.2 GPa"\n' if rng.random() < 0.7 or along else ""
    lines = [f'title = "corpus rotor {index}"', "[parameters]", "Omega = 0", "[rotor]",
             'speed = "Omega"', 'E = "211 GPa"', 'rho = "7810 kg/m^3"', shear.strip()]
    if along:
        lines += ["axial = true", "torsional = true"]
    for count in counts:
        outer = float(rng.uniform(0.04, 0.09))
        inner = outer * float(rng.choice([0.0, 0.0, 0.5]))
        lines += ["[[rotor.shaft]]", f"length = {float(rng.uniform(0.4, 1.2)):.4f}",
                  f"diameter = {outer:.4f}", f"inner_diameter = {inner:.4f}",
                  f"count = {int(count)}"]
    for d, station in enumerate(rng.choice(np.arange(5, elements - 4), int(rng.integers(1, 5)),
                                           replace=False)):
        outer = float(rng.uniform(0.15, 0.4))
        lines += ["[[rotor.disc]]", f"station = {int(station)}", f'name = "disc{d}"',
                  f"width = {float(rng.uniform(0.03, 0.09)):.4f}", f"diameter = {outer:.4f}",
                  "inner_diameter = 0.05"]
    places = [0, elements] + ([int(elements // 2)] if rng.random() < 0.3 else [])
    for b, station in enumerate(places):
        k = float(rng.uniform(5e5, 5e7))
        entry = {"station": station, "name": f'"bearing{b}"', "kxx": f"{k:.6g}",
                 "kyy": f"{k * float(rng.choice([1.0, 0.7])):.6g}"}
        if rng.random() < 0.5:
            entry |= {"cxx": f"{float(rng.uniform(100, 3000)):.6g}",
                      "cyy": f"{float(rng.uniform(100, 3000)):.6g}"}
        if rng.random() < 0.3:
            q = float(rng.uniform(10, 100))
            entry |= {"kxy": f'"{q:.4g}*Omega"', "kyx": f'"-{q:.4g}*Omega"'}
        if rng.random() < 0.2:
            entry["kxx"] = f'"{k:.6g} + {k / 1000:.4g}*Omega"'
        if along and b == 0:
            entry |= {"kz": "1e9", "kaz": "1e4"}
        if rng.random() < 0.25:
            entry["pedestal"] = (f'{{ m = {float(rng.uniform(10, 60)):.4g}, kxx = 2e7, '
                                 f'kyy = 2e7, cxx = 800, cyy = 800 }}')
        lines.append("[[rotor.bearing]]")
        lines += [f"{key} = {value}" for key, value in entry.items()]
    return "\n".join(line for line in lines if line) + "\n"


def _dense(a: object) -> np.ndarray:
    return np.asarray(a.toarray() if hasattr(a, "toarray") else a, dtype=float)  # type: ignore[attr-defined]


def run_one(text: str, speeds: np.ndarray, modes: int) -> dict[str, object]:
    from resonant.analyses.campbell import campbell
    from resonant.modal import gyroscopic_modes, lowest_gyroscopic_modes
    from resonant.model import loads, rotor
    from resonant.system import linear_system

    sparse_model = loads(text)
    saved = rotor.SPARSE_STATIONS
    rotor.SPARSE_STATIONS = 10**9
    try:
        dense_model = loads(text)
    finally:
        rotor.SPARSE_STATIONS = saved
    a, b = sparse_model.matrices, dense_model.matrices
    assert a is not None and b is not None
    assembly = max(float(np.max(np.abs(_dense(getattr(a, k)) - getattr(b, k)))) /
                   max(float(np.max(np.abs(getattr(b, k)))), 1.0) for k in ("M", "K", "C", "G"))
    system = linear_system(sparse_model)
    worst = 0.0
    t = time.perf_counter()
    for speed in (float(speeds[0]), float(speeds[-1])):
        point = system.numeric(Omega=speed)
        s_sparse, _ = lowest_gyroscopic_modes(point.M, point.C, point.K, modes)
        s_dense, _ = gyroscopic_modes(point.M, point.C, point.K)
        s_dense = s_dense[:modes]
        worst = max(worst, float(np.max(np.abs(s_sparse - s_dense) / np.abs(s_dense))))
    modes_time = time.perf_counter() - t
    t, cpu = time.perf_counter(), time.process_time()
    result = campbell(system, speeds, modes=modes)
    wall, cpu = time.perf_counter() - t, time.process_time() - cpu
    residual = 0.0
    for c in result.critical_speeds:
        if c.order != 1.0:
            continue
        point = system.numeric(Omega=c.speed)
        s, _ = gyroscopic_modes(point.M, point.C, point.K)
        residual = max(residual, float(np.min(np.abs(np.abs(s.imag) - c.speed)) / c.speed))
    return {"coordinates": system.n, "assembly": assembly, "modes": worst,
            "modes_s": modes_time, "campbell_wall_s": wall, "campbell_cpu_s": cpu,
            "speeds": len(result.speeds), "critical": len(result.critical_speeds),
            "critical_residual": residual, "threshold": result.threshold.verdict}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rotors", type=int, default=12)
    parser.add_argument("--speeds", type=int, default=9)
    parser.add_argument("--modes", type=int, default=8)
    parser.add_argument("--top", type=float, default=4000 * np.pi / 30, help="rad/s")
    parser.add_argument("--seed", type=int, default=48)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    speeds = np.linspace(0.0, args.top, args.speeds)
    rows = []
    for i in range(args.rotors):
        text = corpus_rotor(rng, i)
        row = {"rotor": i, "axial_torsional": "axial = true" in text,
               "pedestal": "pedestal" in text, "cross": "kxy" in text,
               **run_one(text, speeds, args.modes)}
        rows.append(row)
        if not args.json:
            print(" | ".join(f"{v:.3g}" if isinstance(v, float) else str(v)
                             for v in row.values()), flush=True)
    if args.json:
        print(json.dumps(rows, indent=1))
    else:
        print("columns:", " | ".join(rows[0]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
