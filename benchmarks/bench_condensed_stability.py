"""The stability of one point of the condensed balance: Hill's matrix or the monodromy matrix.

    python benchmarks/bench_condensed_stability.py [--modes 40] [--harmonics 7,11,15]
    python benchmarks/bench_condensed_stability.py --plate 100
    python benchmarks/bench_condensed_stability.py --friction 4

For s first-order modes kept dynamic (poles -0.01 + i w_j, w_j spread over 1 ... 7 W,
W = 1) and H harmonics, the periodic system eta' = A(t) eta with A's Fourier
coefficients up to 2H of size 0.01 / 2^|offset| (a seeded random linearization whose
harmonics decay like those of a smooth element's stiffness): the time of
``condensed._hill`` (the eigenvalues of its s(2H+1)-row matrix) and of
``condensed._monodromy`` (fourth-order Magnus steps over one period), one BLAS thread,
and the difference of their largest growth rates (Hill's truncation to H harmonics
mostly: the monodromy matrix does not change with more steps).

With ``--plate N``: the branch of ``bench_nonlinear_fe.py``'s plate of about N
coordinates (H = 7, omega 1.0 ... 2.4, 100 points asked), once with Hill's matrix at
every point and once as ``condensed.py`` chooses (the monodromy matrix above
``MONODROMY_ROWS`` rows): CPU seconds of the sweep and of its exponents, and whether
the verdicts and special points agree.

With ``--friction N``: a chain of N masses with a Jenkins element at its tip that slips
each period (omega 1.5 ... 1.6, H = 9): CPU per point of the exponents by the sliders'
monodromy over the samples (``condensed._slider_monodromy``) and by the instantaneous
tangent alone (the sliders left out: what the stability analysis did before, a
different and wrong linear system), and the largest multiplier of each.
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


def plate(n: int) -> None:
    import tempfile

    import numpy as np

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench_nonlinear_fe import write_model

    import resonant
    from resonant.analyses import condensed
    from resonant.system import nonlinear_system

    with tempfile.TemporaryDirectory() as tmp:
        path, _ = write_model("plate", Path(tmp), n)
        system = nonlinear_system(resonant.load(path))
    original = condensed.CondensedBalance.exponents
    spent = [0.0]

    def timed(self, J, blocks):
        start = time.process_time()
        lam = original(self, J, blocks)
        spent[0] += time.process_time() - start
        return lam

    condensed.CondensedBalance.exponents = timed
    chosen = condensed.MONODROMY_ROWS
    results = []
    print("| route | coordinates | points | unstable | sweep CPU | exponents CPU | a point |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for name, rows in (("Hill everywhere", 10**9), ("as chosen (monodromy)", chosen)):
        condensed.MONODROMY_ROWS = rows
        spent[0] = 0.0
        start = time.process_time()
        r = condensed.condensed_sweep(system, "omega", 1.0, 2.4, harmonics=7, points=100,
                                      linear=False)
        total = time.process_time() - start
        results.append(r)
        print(f"| {name} | {system.n} | {r.values.size} | {int((~r.stable).sum())} | "
              f"{total:.1f} s | {spent[0]:.1f} s | {1e3 * spent[0] / r.values.size:.1f} ms |")
    condensed.MONODROMY_ROWS = chosen
    condensed.CondensedBalance.exponents = original
    hill, mono = results
    same = hill.values.size == mono.values.size and np.array_equal(hill.stable, mono.stable)
    points = [[(p.kind, round(p.value, 9)) for p in r.special_points] for r in results]
    print(f"\nsame verdicts at every point: {same}; same special points: "
          f"{points[0] == points[1]}")


def friction(n: int) -> None:
    import numpy as np

    import resonant
    from resonant.analyses import condensed
    from resonant.system import nonlinear_system
    from resonant.system.nonlinear_elements import ElementForces

    K = (np.diag(np.r_[2 * np.ones(n - 1), 1.0]) - np.diag(np.ones(n - 1), 1)
         - np.diag(np.ones(n - 1), -1)) * n
    M = np.eye(n) / n
    C = 0.02 * M + 0.002 * K

    def rows(A: np.ndarray) -> str:
        return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in r) + "]"
                               for r in A) + "]"

    force = [0.0] * n
    force[-1] = 0.02
    system = nonlinear_system(resonant.loads(
        f"[parameters]\nw = 1\n[matrices]\nM = {rows(M)}\nK = {rows(K)}\nC = {rows(C)}\n"
        f'[[harmonic]]\nomega = "w"\nF_C = {force}\n[[nonlinear]]\nname = "joint"\n'
        f'coordinates = ["q{n}"]\nkind = "friction"\nstiffness = 3.0\n'
        "slip_force = 0.004\n"))
    original, sliders = condensed.CondensedBalance.exponents, ElementForces.sliders
    spent = [0.0, 0]

    def timed(self, J, blocks):
        start = time.process_time()
        lam = original(self, J, blocks)
        spent[0] += time.process_time() - start
        spent[1] += 1
        return lam

    condensed.CondensedBalance.exponents = timed
    print("| route | coordinates | points | exponents a point | largest multiplier |")
    print("| --- | ---: | ---: | ---: | ---: |")
    try:
        for name, patch in (("sliders' monodromy", False), ("tangent alone (before)", True)):
            if patch:
                ElementForces.sliders = lambda self, U: []
            spent[:] = [0.0, 0]
            r = condensed.condensed_sweep(system, "w", 1.5, 1.6, harmonics=9, points=10,
                                          linear=False)
            print(f"| {name} | {n} | {r.values.size} | {1e3 * spent[0] / spent[1]:.1f} ms | "
                  f"{float(np.abs(r.multipliers).max()):.4f} |")
    finally:
        condensed.CondensedBalance.exponents, ElementForces.sliders = original, sliders


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, default=40)
    parser.add_argument("--harmonics", default="7,11,15")
    parser.add_argument("--plate", type=int, default=0,
                        help="the plate of about this many coordinates instead")
    parser.add_argument("--friction", type=int, default=0,
                        help="the chain of this many masses with a Jenkins element instead")
    args = parser.parse_args(argv)
    if args.friction:
        friction(args.friction)
        return 0
    if args.plate:
        plate(args.plate)
        return 0
    print("| s | H | Hill rows | Hill | monodromy | growth rates differ by |")
    print("| --- | --- | --- | --- | --- | --- |")
    for H in (int(h) for h in args.harmonics.split(",")):
        r = measure(args.modes, H)
        print(f"| {r['modes']} | {H} | {r['modes'] * (2 * H + 1)} | {r['hill_s']:.3f} s | "
              f"{r['monodromy_s']:.3f} s | {r['growth_difference']:.1e} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
