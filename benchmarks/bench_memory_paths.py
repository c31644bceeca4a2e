"""Bounded memory on the paths whose arrays grow with the request (docs/performance.md,
section "Memory bounded by design").

Two measurements, one BLAS thread, each in a child process so that its peak resident
memory is its own:

* the exact transient response of a 60-coordinate chain to a sampled history of 2 10^5
  samples, one history asked for, against the same ramp-invariant recursion written by
  hand in numpy (which holds samples x states, as resonant did before);
* the condensed balance of a 3-coordinate model with one light, heavily damped
  coordinate and 25 harmonics (its monodromy's step count, 4 T |A|, is 2 10^6): time and
  peak memory (before: 9.5 GiB asked for, a MemoryError).

    python benchmarks/bench_memory_paths.py
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

TRANSIENT = """
import json, resource, sys, time
import numpy as np
import resonant
from resonant.analyses.transient import _discretize, _state_space, transient_response
n, samples = 60, 200_000
K = 1e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)); K[-1, -1] = 1e4
rows = lambda A: "[" + ", ".join("[" + ", ".join(f"{v:.17g}" for v in r) + "]" for r in A) + "]"
model = resonant.loads(f"[matrices]\\nM = {rows(np.eye(n))}\\nK = {rows(K)}\\n"
                       f"C = {rows(0.01 * np.eye(n) + 1e-4 * K)}\\n")
eom = model.linearize()
u = np.zeros(samples); u[:100] = 1.0
if sys.argv[1] == "resonant":
    t = time.perf_counter()
    y = transient_response(eom, "q1", u, 1e-5, names=["q60"]).history["q60"]
else:   # the recursion by hand, holding every state
    num, A, B = _state_space(eom, "q1", 0, resonant.Deadline())
    Phi, F0, F1 = _discretize(A, B, 1e-5)
    t = time.perf_counter()
    X = np.zeros((samples, len(A)))
    state = np.zeros(len(A))
    for j in range(samples - 1):
        state = Phi @ state + (F0 - F1) * u[j] + F1 * u[j + 1]
        X[j + 1] = state
    y = X[:, n - 1]
seconds = time.perf_counter() - t
print(json.dumps({"seconds": seconds, "peak_mib": resource.getrusage(
    resource.RUSAGE_SELF).ru_maxrss / 1024, "last": float(y[-1])}))
"""

#: three coordinates, the third light (1e-4) and heavily damped (C = 10), a cubic spring
#: at the first: the monodromy's step count 4 T |A| is about 2 10^6 (tests use it too)
LIGHT_MODEL = """[parameters]
w = 1.0
[matrices]
M = [[1, 0, 0], [0, 1, 0], [0, 0, 1e-4]]
K = [[2, -1, 0], [-1, 2, -1], [0, -1, 1]]
C = [[0.02, 0, 0], [0, 0.02, 0], [0, 0, 10]]
[[harmonic]]
omega = "w"
F_C = [0.1, 0, 0]
F_S = [0, 0, 0]
[[nonlinear]]
coordinates = ["q1"]
force = "0.5*q1^3"
"""

LIGHT = """
import json, resource, sys, time
import resonant
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.system import nonlinear_system
model = nonlinear_system(resonant.loads(sys.argv[1]))
t = time.perf_counter()
r = nonlinear_sweep(model, "w", 0.8, 1.2, harmonics=25, points=12, linear=False)
print(json.dumps({"seconds": time.perf_counter() - t, "points": len(r.values),
                  "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def child(code: str, *args: str) -> dict[str, float]:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                         env=env, timeout=900, check=True).stdout
    result: dict[str, float] = json.loads(out.strip().splitlines()[-1])
    return result


def main() -> None:
    ours, hand = child(TRANSIENT, "resonant"), child(TRANSIENT, "numpy")
    print(f"transient, 60 coordinates x 200,000 samples, one history: resonant "
          f"{ours['seconds']:.2f} s, {ours['peak_mib']:.0f} MiB peak; by hand (every state "
          f"kept) {hand['seconds']:.2f} s, {hand['peak_mib']:.0f} MiB; ratio "
          f"{ours['seconds'] / hand['seconds']:.2f}x; same last value: "
          f"{ours['last'] == hand['last']}")
    light = child(LIGHT, LIGHT_MODEL)
    print(f"condensed balance, light coordinate, H = 25: {light['points']:.0f} points in "
          f"{light['seconds']:.2f} s, {light['peak_mib']:.0f} MiB peak")


if __name__ == "__main__":
    main()
