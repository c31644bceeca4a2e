"""Parameter studies: resonant study against hand-written numpy, worker speed-up, memory.

Usage::

    python benchmarks/bench_study.py [--samples 1000000] [--big-n 10000] [--memory 10000000]
                                     [--rounds 3]

1. The reference exercise (examples/cart_pendulum.toml), the stationary amplitude of x2
   for ``--samples`` values of k ~ uniform(80, 120) N/m, each as a whole process that
   writes its results to Parquet: ``resonant study`` (derivation, sample generation, the
   batched kernel with its stability and condition checks, the file) against a
   hand-written vectorized numpy script doing the same 2x2 complex solves with M, K and
   the load typed in from the exercise.  Best of ``--rounds`` (3), alternating; wall and
   CPU (user + system) times, the CPU ratio being the steadier on a loaded machine.
2. Speed-up from 1 to 2 local workers on a fixed-free chain of ``--big-n`` masses (a
   ``[matrices]`` model, examples/make_chain.py): 100 samples of F0 and the peak of the
   free end over a band of 200 frequencies.  Three pairs of runs, each pair back to back
   (the order alternating): the median of the pairs' ratios, which a machine whose speed
   drifts between pairs does not move, and the ratio of the best times.
3. Peak memory (max RSS of the process and its workers' largest) of ``resonant study`` at
   ``--memory`` samples, streaming to Parquet.
4. ``--nonlinear N``: the nonlinear steady state (``nonlinear_amplitude:x`` of
   examples/duffing.toml, omega and k3 random, swept up from 0.5) for N samples, in this
   process and on 2 local workers.
5. ``--grid NX``: the peak of one sample of an NX x NX mass-spring grid (a sparse model
   whose direct solves are expensive) on one reduced model of the band against the direct
   solves of every refinement round (in this process, seconds per sample).

Prints a markdown table for docs/performance.md.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from common import ROOT, environment

NUMPY_SCRIPT = r'''
import sys, numpy as np, pyarrow as pa, pyarrow.parquet as pq
n = int(sys.argv[1]); out = sys.argv[2]
m1, m2, l, g, F0, eps, r0, w = 2.0, 1.0, 0.5, 9.81, 5.0, np.pi / 3, 0.01, 20.0
k = 80.0 + 40.0 * np.random.default_rng(1).random(n)
M = np.array([[m1 + m2, m2 / 2], [m2 / 2, m2 / 3]])
A = np.zeros((n, 2, 2), dtype=complex)
A[:, 0, 0] = k
A[:, 1, 1] = g * m2 / (2 * l)
A -= w**2 * M
F_C = np.stack([F0 * np.sin(eps) + k * r0, np.full(n, F0 * np.sin(eps))], axis=1)
F_S = np.full((n, 2), F0 * np.cos(eps))
z = np.linalg.solve(A, (F_C - 1j * F_S)[..., None])[..., 0]
pq.write_table(pa.table({"k": k, "amplitude:x2": np.abs(z[:, 1])}), out)
'''


def timed(args: list[str]) -> tuple[float, int]:
    """Wall time and the largest max-RSS (kB) of a child process (and its children)."""
    elapsed, _, rss = timed_cpu(args)
    return elapsed, rss


def timed_cpu(args: list[str]) -> tuple[float, float, int]:
    """Wall time, CPU time (user + system) and the largest max-RSS (kB) of a child
    process (and its children): on a loaded machine the CPU time is the steadier one."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(args, capture_output=True, text=True, env=environment(),
                            timeout=3600)
    elapsed = time.perf_counter() - start
    if result.returncode != 0:
        raise RuntimeError(result.stderr)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return elapsed, cpu, after.ru_maxrss


def study(model: Path, out: Path, *options: str) -> list[str]:
    return [sys.executable, "-m", "resonant", "study", str(model), "-o", str(out), *options]


def against_numpy(samples: int, tmp: Path, rounds: int = 3
                  ) -> tuple[tuple[float, float], tuple[float, float]]:
    """The best (wall, CPU) times of resonant and of the numpy script, alternating."""
    script = tmp / "by_hand.py"
    script.write_text(NUMPY_SCRIPT)
    ours, theirs = [], []
    for _ in range(rounds):
        ours.append(timed_cpu(study(ROOT / "examples" / "cart_pendulum.toml",
                                    tmp / "r.parquet", "--vary", "k=uniform(80 N/m, 120 N/m)",
                                    "--quantity", "amplitude:x2", "--samples",
                                    str(samples)))[:2])
        theirs.append(timed_cpu([sys.executable, str(script), str(samples),
                                 str(tmp / "n.parquet")])[:2])
    return ((min(t[0] for t in ours), min(t[1] for t in ours)),
            (min(t[0] for t in theirs), min(t[1] for t in theirs)))


def speed_up(n: int, tmp: Path) -> tuple[float, float, float]:
    sys.path.insert(0, str(ROOT / "examples"))
    from make_chain import write_chain

    model = write_chain(tmp / "chain", n)
    options = ["--vary", "F0=uniform(0.5, 1.5)", "--quantity", f"peak:q{n}", "--band",
               "omega=1:60:200", "--samples", "100"]
    one, two = [], []
    for k in range(3):  # pairs run back to back, in alternating order
        for workers in (("1", "2") if k % 2 == 0 else ("2", "1")):
            runs = one if workers == "1" else two
            runs.append(timed(study(model, tmp / f"w{workers}.parquet", *options,
                                    "--workers", workers))[0])
    ratios = sorted(a / b for a, b in zip(one, two))
    print(f"runs: 1 worker {', '.join(f'{t:.1f}' for t in one)} s; 2 workers "
          f"{', '.join(f'{t:.1f}' for t in two)} s; pairs "
          f"{', '.join(f'{a / b:.2f}x' for a, b in zip(one, two))}", file=sys.stderr)
    return min(one), min(two), ratios[len(ratios) // 2]


def memory(samples: int, tmp: Path) -> tuple[float, int]:
    return timed(study(ROOT / "examples" / "cart_pendulum.toml", tmp / "big.parquet",
                       "--vary", "k=uniform(80 N/m, 120 N/m)", "--quantity", "amplitude:x2",
                       "--samples", str(samples), "--workers", "0"))


def nonlinear(samples: int, tmp: Path) -> tuple[float, float]:
    options = ["--vary", "omega=uniform(0.8, 2)", "--vary", "k3=uniform(0.3, 0.7)",
               "--quantity", "nonlinear_amplitude:x", "--band", "omega=0.5:2.5",
               "--samples", str(samples)]
    model = ROOT / "examples" / "duffing.toml"
    here = timed(study(model, tmp / "nl0.parquet", *options, "--workers", "0"))[0]
    there = timed(study(model, tmp / "nl2.parquet", *options, "--workers", "2"))[0]
    return here, there


def grid_peak(nx: int, tmp: Path) -> dict[str, float]:
    """Seconds per sample of the peak search: on one reduced model of the band (now), the
    kernel called anew for the band and each refinement round (before: a reduced model for
    the band's grid, direct solves for the rounds), and direct solves only."""
    from bench_reduced import grid_matrices, write_model

    sys.path.insert(0, str(ROOT / "src"))  # this checkout's resonant, in this process
    import resonant
    from resonant.analyses import kernel
    from resonant.studies import StudyJob, quantities, request
    from resonant.studies.run import evaluate_chunk, system_of

    M, C, K, f = grid_matrices(nx)
    path = write_model(tmp, M, C, K, f)  # the matrix files; the model with a force F0:
    force = ", ".join('"F0"' if v else "0" for v in f)
    path.write_text('[parameters]\nw = 1\nF0 = 1\n[matrices]\nM = "M.mtx"\nC = "C.mtx"\n'
                    f'K = "K.mtx"\n[[harmonic]]\nomega = "w"\nF_C = [{force}]\n')
    model = resonant.load(path)
    q = model.coordinates[int(np.argmax(f))]
    spec = request(model, {"F0": "uniform(0.5, 1.5)"}, [f"peak:{q}"], samples=3,
                   band={"parameter": "w", "from": 5, "to": 40, "points": 200})
    job = StudyJob.of(model, spec)
    system_of(job)
    shared, worth = quantities.reduced_band, kernel.REDUCED_WORTH
    times = {}
    for case in ("shared", "per round", "direct"):
        quantities.reduced_band = shared if case == "shared" else (lambda *a, **k: None)
        kernel.REDUCED_WORTH = float("inf") if case == "direct" else worth
        start = time.perf_counter()
        for k in range(3):
            evaluate_chunk(job, k, 1)
        times[case] = (time.perf_counter() - start) / 3
    quantities.reduced_band, kernel.REDUCED_WORTH = shared, worth
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--big-n", type=int, default=10_000)
    parser.add_argument("--memory", type=int, default=10_000_000)
    parser.add_argument("--nonlinear", type=int, default=40)
    parser.add_argument("--grid", type=int, default=50)
    parser.add_argument("--rounds", type=int, default=3,
                        help="alternating rounds of the numpy case (best of them)")
    parser.add_argument("--only", choices=("numpy", "speed-up", "memory", "nonlinear", "grid"))
    args = parser.parse_args()

    def wanted(case: str) -> bool:
        return args.only in (None, case)

    print(subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    with tempfile.TemporaryDirectory() as name:
        tmp = Path(name)
        print("| case | resonant | reference | ratio |\n|---|---|---|---|")
        if wanted("numpy"):
            (ours, our_cpu), (theirs, their_cpu) = against_numpy(args.samples, tmp,
                                                                 args.rounds)
            print(f"| amplitude of x2, {args.samples:,} samples, whole process to Parquet | "
                  f"{ours:.2f} s ({our_cpu:.2f} s CPU) | numpy by hand {theirs:.2f} s "
                  f"({their_cpu:.2f} s CPU) | {ours / theirs:.2f}x (CPU "
                  f"{our_cpu / their_cpu:.2f}x) |")
        if wanted("speed-up"):
            one, two, median = speed_up(args.big_n, tmp)
            print(f"| chain of {args.big_n:,} DOF, 100 samples x 200 frequencies (peak) | "
                  f"2 workers {two:.1f} s (best) | 1 worker {one:.1f} s (best) | speed-up "
                  f"{median:.2f}x (median of 3 pairs; {one / two:.2f}x of the best) |")
        if wanted("memory"):
            seconds, rss = memory(args.memory, tmp)
            print(f"| {args.memory:,} samples streamed to Parquet | {seconds:.1f} s | peak "
                  f"memory {rss / 1024:.0f} MB | |")
        if wanted("nonlinear"):
            here, there = nonlinear(args.nonlinear, tmp)
            print(f"| nonlinear steady state, {args.nonlinear} samples (Duffing) | 2 workers "
                  f"{there:.1f} s | this process {here:.1f} s | speed-up {here / there:.2f}x |")
        if wanted("grid"):
            t = grid_peak(args.grid, tmp)
            print(f"| peak of one sample, {args.grid}x{args.grid} grid, 200 frequencies | "
                  f"one reduced model {t['shared']:.2f} s | kernel per round "
                  f"{t['per round']:.2f} s, direct only {t['direct']:.2f} s | "
                  f"{t['per round'] / t['shared']:.1f}x, {t['direct'] / t['shared']:.1f}x |")


if __name__ == "__main__":
    main()
