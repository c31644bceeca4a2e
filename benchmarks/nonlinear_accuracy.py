"""Accuracy of the nonlinear branch against Duffing's one-harmonic closed form.

``resonant sweep examples/duffing.toml --param omega --from 0.5 --to 2.5 --nonlinear
--harmonics 1 --json`` (m = 1, c = 0.1, k = 1, k3 = 0.5, F = 0.2).  With H = 1 harmonic
balance solves exactly the frequency-amplitude relation (Nayfeh & Mook, Nonlinear
Oscillations, 1979, Sect. 4.1.1)

    [(k - m w^2 + 3/4 k3 X^2)^2 + (c w)^2] X^2 = F^2,

so every branch point's amplitude satisfies it to rounding, and the largest amplitude of
the resonance is where dX/dw = 0 on it: k - m w^2 + 3/4 k3 X^2 = c^2/(2m) (solved with
brentq).  Printed: the largest |relation| / F^2 over the branch points, the peak's error
(the located ``peak`` special point, and the largest branch point) and the wall time.

Run: ``python benchmarks/nonlinear_accuracy.py``.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time

import scipy.optimize
from bench_nonlinear import ROOT
from common import environment

M, C, K, K3, F = 1.0, 0.1, 1.0, 0.5, 0.2


def relation(X: float, w: float) -> float:
    return abs(((K - M * w * w + 0.75 * K3 * X * X) ** 2 + (C * w) ** 2) * X * X - F * F) / F ** 2


def peak() -> tuple[float, float]:
    D = C * C / (2 * M)
    X = scipy.optimize.brentq(lambda X: X * X * (D * D + C * C * (K + 0.75 * K3 * X * X - D) / M)
                              - F * F, 0.1, 10.0, xtol=1e-15, rtol=1e-15)
    return X, math.sqrt((K + 0.75 * K3 * X * X - D) / M)


def main() -> None:
    command = [sys.executable, "-m", "resonant", "sweep", str(ROOT / "examples" / "duffing.toml"),
               "--param", "omega", "--from", "0.5", "--to", "2.5", "--nonlinear",
               "--harmonics", "1", "--json"]
    start = time.perf_counter()
    out = subprocess.run(command, capture_output=True, text=True, check=True,
                         env=environment(), cwd=ROOT).stdout
    wall = time.perf_counter() - start
    data = json.loads(out)
    worst = max(relation(p["amplitudes"]["x"], p["value"]) for p in data["branch"])
    X, w = peak()
    located = [p for p in data["special_points"] if p["kind"] == "peak"]
    largest = max(p["amplitudes"]["x"] for p in data["branch"])
    print(f"branch points: {len(data['branch'])}; largest |relation| / F^2: {worst:.2g}")
    print(f"closed-form peak X = {X:.15g} at w = {w:.15g}")
    print(f"largest branch point: relative error {abs(largest - X) / X:.2g}")
    for p in located:
        print(f"peak point: X relative error {abs(p['amplitudes']['x'] - X) / X:.2g}, "
              f"w relative error {abs(p['value'] - w) / w:.2g}")
    if not located:
        print("no peak point reported")
    print(f"wall time of the command: {wall:.3f} s")


if __name__ == "__main__":
    main()
