"""The stability of one point of the condensed balance: Hill's matrix or the monodromy matrix.

    python benchmarks/bench_condensed_stability.py [--modes 40] [--harmonics 7,11,15]

For s first-order modes kept dynamic (poles -0.01 + i w_j, w_j spread over 1 ... 7 W,
W = 1) and H harmonics, the periodic system eta' = A(t) eta with A's Fourier
coefficients up to 2H of size 0.01 / 2^|offset| (a seeded random linearization whose
harmonics decay like those of a smooth element's stiffness): the time of
``condensed._hill`` (the eigenvalues of its s(2H+1)-row matrix) and of
``condensed._monodromy`` (fourth-order Magnus steps over one period), one BLAS thread,
and the difference of their largest growth rates (Hill's truncation to H harmonics
mostly: the monodromy matrix does not change with more steps).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "src"))


def measure(s: int, H: int, repeat: int = 3) -> dict[str, float]:
    import numpy as np

    from resonant.analyses import condensed

    rng = np.random.default_rng(0)
    decay = 0.5 ** np.abs(np.arange(-2 * H, 2 * H + 1))[:, None, None]
    coef = 0.01 * decay * (rng.standard_normal((4 * H + 1, s, s))
                           + 1j * rng.standard_normal((4 * H + 1, s, s)))
    coef[2 * H] += np.diag(-0.01 + 1j * np.linspace(1.0, 7.0, s))
    times = {}
    growth = {}
    for name, method in (("hill", condensed._hill), ("monodromy", condensed._monodromy)):
        best = np.inf
        for _ in range(repeat):
            start = time.perf_counter()
            lam = method(coef, 1.0, H, s)
            best = min(best, time.perf_counter() - start)
        times[name] = best
        growth[name] = float(lam.real.max())
    return {"modes": s, "harmonics": H, "hill_s": times["hill"],
            "monodromy_s": times["monodromy"],
            "growth_difference": abs(growth["hill"] - growth["monodromy"])}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, default=40)
    parser.add_argument("--harmonics", default="7,11,15")
    args = parser.parse_args(argv)
    print("| s | H | Hill rows | Hill | monodromy | growth rates differ by |")
    print("| --- | --- | --- | --- | --- | --- |")
    for H in (int(h) for h in args.harmonics.split(",")):
        r = measure(args.modes, H)
        print(f"| {r['modes']} | {H} | {r['modes'] * (2 * H + 1)} | {r['hill_s']:.3f} s | "
              f"{r['monodromy_s']:.3f} s | {r['growth_difference']:.1e} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
