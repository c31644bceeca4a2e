"""FRF updating: the analytic sensitivities (dH/dp = -H dZ/dp H) against central differences
of the FRF.

``python benchmarks/bench_frf_sensitivity.py [--sizes 3,20,60] [--lines 400] [--repeat 5]``

An n-mass chain given by its energies (springs k1, k2 and k for the rest, masses m, one
dashpot c per spring; the force F on the last mass), its receptance at ``lines`` lines of
0.5-12 Hz measured at the first and the last mass.  Timed, for the four parameters
k1, k2, m and c:

* one Jacobian of the log residuals: ``_FRFProblem.analytic_jacobian`` (one batch of
  matrices per parameter, one stacked solve for the FRF and every derivative) against
  ``_FRFProblem.difference_jacobian`` (two kernel FRFs per parameter), and their largest
  relative difference;
* the whole update (``update_to_frf``, k1 and k2 from 1000 N/m to the truth 1100 and
  950 N/m) with ``sensitivities="analytic"`` and ``"differences"``.

Reported: median times and their ratio.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from resonant.analyses.frf_update import _FRFProblem, model_frf_matrix, update_to_frf
from resonant.api import loads
from resonant.deadline import NO_DEADLINE
from resonant.model.measurement_spec import ChannelMap


def chain_text(n: int) -> str:
    """An n-mass chain in energies, k1 and k2 its first springs."""
    springs = ["k1", "k2"] + ["k"] * (n - 2)
    coords = "\n".join(f'x{i} = {{ unit = "m" }}' for i in range(1, n + 1))
    stretch = ["x1"] + [f"(x{i} - x{i - 1})" for i in range(2, n + 1)]
    rate = ["x1'"] + [f"(x{i}' - x{i - 1}')" for i in range(2, n + 1)]
    T = " + ".join(f"x{i}'^2" for i in range(1, n + 1))
    U = " + ".join(f"{s}*{d}^2" for s, d in zip(springs, stretch))
    D = " + ".join(f"{d}^2" for d in rate)
    return f'''title = "{n}-mass chain"
[parameters]
m = "1 kg"
k1 = "1000 N/m"
k2 = "1000 N/m"
k = "1000 N/m"
c = "2 N*s/m"
F0 = "1 N"
omega = "10 rad/s"
[coordinates]
{coords}
[signals]
F = "F0*sin(omega*t)"
[energy]
T = "m*({T})/2"
U = "({U})/2"
D = "c*({D})/2"
[[force]]
name = "F"
vector = ["F"]
point = ["x{n}"]
'''


def _median(fn, repeat: int) -> float:
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def bench(n: int, lines: int, repeat: int) -> str:
    system = loads(chain_text(n)).linearize()
    f = np.linspace(0.5, 12.0, lines)
    channels = {"d1": ChannelMap("x1"), "dn": ChannelMap(f"x{n}")}
    H = model_frf_matrix(system, ["F"], f, channels, k1=1100.0, k2=950.0)
    rows = np.transpose(H, (1, 2, 0)).reshape(-1, lines)
    names = ["k1", "k2", "m", "c"]
    problem = _FRFProblem(system, names, f, rows, ["F"], channels, "log", "analytic",
                          NO_DEADLINE)
    x = np.log([1000.0, 1000.0, 1.0, 2.0])
    analytic = problem.analytic_jacobian(x)
    differences = problem.difference_jacobian(x)
    assert analytic is not None
    error = float(np.max(np.abs(analytic - differences)) / np.max(np.abs(differences)))
    ta = _median(lambda: problem.analytic_jacobian(x), repeat)
    td = _median(lambda: problem.difference_jacobian(x), repeat)
    measured = {"d1": H[:, 0, 0], "dn": H[:, 1, 0]}
    bounds = {"k1": (500.0, 2000.0), "k2": (500.0, 2000.0)}
    fits = {}
    for how in ("analytic", "differences"):
        fits[how] = _median(lambda how=how: update_to_frf(system, bounds, f, measured, "F",
                                                          channels, sensitivities=how),
                            max(1, repeat // 2))
    return (f"n = {n:>3}, {lines} lines, 4 parameters: Jacobian analytic {1e3 * ta:8.2f} ms, "
            f"differences {1e3 * td:8.2f} ms, ratio {td / ta:5.1f}x (largest difference "
            f"{error:.1e}); update of k1, k2: analytic {1e3 * fits['analytic']:8.1f} ms, "
            f"differences {1e3 * fits['differences']:8.1f} ms, ratio "
            f"{fits['differences'] / fits['analytic']:4.1f}x")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="3,20,60")
    parser.add_argument("--lines", type=int, default=400)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(1):
        for n in (int(s) for s in args.sizes.split(",")):
            print(bench(n, args.lines, args.repeat), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
