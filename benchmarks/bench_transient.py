"""The exact transient response of a chain to a long shock: the march in blocks.

Usage::

    python benchmarks/bench_transient.py [--n 60] [--total 30] [--reference]

The model of ``tests/test_memory_limit_all.py`` (``SHOCKED``): a Rayleigh-damped chain of
``--n`` unit masses (springs 1e4, C = 0.01 M + 1e-4 K) under a 10 ms half-sine force on its
last mass, sampled every 1e-5 s for ``--total`` s (3,000,001 samples at 30 s).  Timed, in
one process after a first run (the derivation and the numbers once): the history of q1
(``shock_response(system, names=["q1"])``), wall and CPU time.  ``--reference`` also runs
the step-by-step first-order-hold recursion in Python (the march before it went in
blocks; about 17 s of CPU at 3 10^6 samples) and prints the largest difference of the two
histories relative to the largest |q1|.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp

import resonant
from resonant.analyses import transient
from resonant.analyses.shock import pulse
from resonant.deadline import NO_DEADLINE
from resonant.model.load_spec import ShockSpec
from resonant.system.base import LinearSystem


def chain_model(folder: Path, n: int, total: float) -> Path:
    K = sp.diags([2e4 * np.ones(n), -1e4 * np.ones(n - 1), -1e4 * np.ones(n - 1)],
                 [0, 1, -1], format="csr")
    M = sp.identity(n, format="csr")
    for name, matrix in (("K", K), ("M", M), ("C", 0.01 * M + 1e-4 * K)):
        sp.save_npz(folder / f"{name}.npz", matrix.tocsr())
    path = folder / "chain.toml"
    path.write_text('[matrices]\nM = "M.npz"\nK = "K.npz"\nC = "C.npz"\n'
                    f'[shock]\nsignal = "q{n}"\npulse = "half-sine"\namplitude = 1\n'
                    f"duration = 0.01\nstep = 1e-5\ntotal = {total}\n")
    return path


def step_by_step(system: LinearSystem, spec: ShockSpec, name: str) -> np.ndarray:
    """The one-sample-at-a-time recursion X[j+1] = Phi X[j] + G0 u[j] + G1 u[j+1]."""
    _, u = pulse(spec.pulse, spec.amplitude, spec.duration, spec.step, total=spec.total)
    num, A, B = transient._state_space(system, spec.signal, spec.derivative, NO_DEADLINE)
    _, R, D = transient._output_map(num, A, B, spec.signal, spec.derivative, [name])
    Phi, F0, F1 = transient._discretize(A, B, spec.step)
    G0, r, state = F0 - F1, R[0], np.zeros(len(Phi))
    y = np.empty(len(u))
    y[0] = D[0] * u[0]
    for j in range(1, len(u)):
        state = Phi @ state + G0 * u[j - 1] + F1 * u[j]
        y[j] = r @ state + D[0] * u[j]
    return y


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=60)
    parser.add_argument("--total", type=float, default=30.0)
    parser.add_argument("--reference", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as name:
        model = resonant.load(chain_model(Path(name), args.n, args.total))
        system = model.linearize()
        transient.shock_response(system, names=["q1"])
        wall, cpu = time.perf_counter(), time.process_time()
        q1 = transient.shock_response(system, names=["q1"]).history["q1"]
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        print(f"chain of {args.n}, {len(q1)} samples, the history of q1 in blocks: "
              f"{wall:.2f} s wall, {cpu:.2f} s CPU")
        if args.reference:
            wall, cpu = time.perf_counter(), time.process_time()
            reference = step_by_step(system, model.shock_section, "q1")
            wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
            difference = np.abs(q1 - reference).max() / np.abs(reference).max()
            print(f"step by step: {wall:.2f} s wall, {cpu:.2f} s CPU; largest difference "
                  f"{difference:.2g} of max |q1|")


if __name__ == "__main__":
    main()
