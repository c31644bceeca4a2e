"""Benchmark 5: the nonlinear frequency-response curve of Duffing's oscillator, resonant
against pyHarm, in one run.

The curve: examples/duffing.toml (m = 1, c = 0.1, k = 1, k3 = 0.5, F = 0.2 cos(omega t)),
omega from 0.5 to 2.5 through the hardening overhang (two folds), H = 9 harmonics.

resonant: ``model.nonlinear_sweep("omega", 0.5, 2.5, harmonics=9, points=150,
linear=False)`` -- harmonic balance of the full Lagrange equations derived from the
energies (AFT with 40 time samples, exact Jacobian), pseudo-arclength continuation,
the Floquet multipliers of **every** point (Hill's method) and the folds located.

pyHarm (``pip install pyHarm-os``): ``Maestro`` with a ``Base`` system (nh = 9, nti =
128), the linear M, C, K as a substructure, a ``CubicSpring`` (k = 0.5) and a
``CosinusForcing`` (0.2) connector; study ``frf`` from 0.5 to 2.5 with tangent predictor,
arc-length corrector, ``acceptance`` step sizer (ds0 = 0.02, ds_max = 0.03), solver
``scipyroot``.  pyHarm computes no stability here.

Measured, each side in its own fresh process, median of ``--repeats`` runs, alternating:

* **whole process**: ``python -c`` that imports, sets up and computes the curve (wall time
  of the child process, interpreter start-up included);
* **continuation**: inside that process, the computation of the curve once the system is
  set up: pyHarm's ``Maestro.operate()`` (its set-up in ``Maestro(...)`` not counted);
  resonant's ``nonlinear_sweep`` from the start of its continuation to its return, i.e.
  the continuation, the stability of every point and the location of the folds (the
  derivation of the equations from the energies and their compilation not counted, but
  reported as ``call``: the whole ``nonlinear_sweep`` call).

Both curves are checked: the same number of folds (2) at the same frequencies (to 1e-3)
and the largest amplitude within 1e-3.

Run: ``python benchmarks/bench_nonlinear.py [--repeats 5] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

from common import environment

ROOT = Path(__file__).resolve().parents[1]
DUFFING = ROOT / "examples" / "duffing.toml"

RESONANT = f"""
import time, json
t0 = time.perf_counter()
from resonant.api import load
import numpy as np
import resonant.analyses.harmonic_balance as hb
model = load({str(DUFFING)!r})
started = []
follow = hb._continue

def timed(*args, **kwargs):  # the continuation starts here (derivation, compilation done)
    started.append(time.perf_counter())
    return follow(*args, **kwargs)

hb._continue = timed
t1 = time.perf_counter()
r = model.nonlinear_sweep("omega", 0.5, 2.5, harmonics=9, points=150, linear=False)
t2 = time.perf_counter()
folds = [p.value for p in r.special_points if p.kind == "fold"]
print(json.dumps({{"continuation": t2 - started[0], "call": t2 - t1,
                  "points": int(r.values.size),
                  "stability": True, "folds": folds,
                  "peak": float(np.max(r.amplitudes["x"])),
                  "unstable": int((~r.stable).sum())}}))
"""

PYHARM = """
import time, json, logging
t0 = time.perf_counter()
import numpy as np
import pyHarm
logging.disable(logging.CRITICAL)
lin = {"M": np.array([[1.0]]), "C": np.array([[0.1]]), "K": np.array([[1.0]]),
       "G": np.array([[0.0]])}
INP = {
    "analysis": {"FRF": {"study": "frf", "puls_inf": 0.5, "puls_sup": 2.5, "ds0": 2e-2,
                         "ds_min": 1e-8, "ds_max": 3e-2, "sign_ds": 1, "verbose": False,
                         "stepsizer": "acceptance", "predictor": "tangent",
                         "corrector": "arc_length", "stopper": "bounds",
                         "solver": "scipyroot"}},
    "system": {"type": "Base", "nh": 9, "nti": 128},
    "substructures": {"sub1": {"matrix": lin, "ndofs": 1}},
    "connectors": {
        "loading": {"type": "CosinusForcing", "connect": {"sub1": [0]}, "dirs": [0],
                    "amp": 0.2},
        "cubic": {"type": "CubicSpring", "connect": {"sub1": [0]}, "dirs": [0], "k": 0.5},
    },
}
M = pyHarm.Maestro(INP)
t1 = time.perf_counter()
M.operate()
t2 = time.perf_counter()
sols = [s for s in M.nls["FRF"].SolList if s.flag_accepted]
om = np.array([s.x[-1] for s in sols])
X = np.array([s.x[:-1] for s in sols])
nh = 9
# peak over one period from the harmonic coefficients (pyHarm orders them
# [a0, a1, b1, a2, b2, ...]); sampled finely
tau = np.linspace(0, 2 * np.pi, 2048, endpoint=False)
basis = [np.ones_like(tau)]
for k in range(1, nh + 1):
    basis += [np.cos(k * tau), np.sin(k * tau)]
series = X @ np.array(basis)
peak = float(np.abs(series).max())
d = np.diff(om)
folds = [float(om[i + 1]) for i in range(len(d) - 1) if d[i] * d[i + 1] < 0]
print(json.dumps({"continuation": t2 - t1, "points": len(sols), "stability": False,
                  "folds": folds, "peak": peak}))
"""


def _run(code: str) -> tuple[float, dict]:
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=environment(), cwd=ROOT, timeout=600)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    return wall, json.loads(proc.stdout.strip().splitlines()[-1])


def pyharm_available() -> bool:
    proc = subprocess.run([sys.executable, "-c", "import pyHarm"], capture_output=True,
                          env=environment())
    return proc.returncode == 0


def measure(repeats: int = 5) -> dict:
    sides = {"resonant": RESONANT}
    if pyharm_available():
        sides["pyHarm"] = PYHARM
    walls: dict[str, list[float]] = {k: [] for k in sides}
    conts: dict[str, list[float]] = {k: [] for k in sides}
    calls: dict[str, list[float]] = {k: [] for k in sides}
    last: dict[str, dict] = {}
    for _ in range(repeats):
        for name, code in sides.items():  # alternating, so both see the same machine load
            wall, data = _run(code)
            walls[name].append(wall)
            conts[name].append(data["continuation"])
            if "call" in data:
                calls[name].append(data["call"])
            last[name] = data
    out: dict = {"repeats": repeats, "sides": {}}
    for name in sides:
        out["sides"][name] = {
            "whole_process_s": statistics.median(walls[name]),
            "continuation_s": statistics.median(conts[name]),
            "whole_process_all": walls[name], "continuation_all": conts[name],
            **({"call_s": statistics.median(calls[name])} if calls[name] else {}),
            **{k: last[name][k] for k in ("points", "stability", "folds", "peak")}}
    if "pyHarm" in out["sides"]:
        r, p = out["sides"]["resonant"], out["sides"]["pyHarm"]
        out["ratio_whole_process"] = r["whole_process_s"] / p["whole_process_s"]
        out["ratio_continuation"] = r["continuation_s"] / p["continuation_s"]
        out["folds_agree"] = (len(r["folds"]) == len(p["folds"]) == 2 and all(
            abs(a - b) < 1e-3 for a, b in zip(sorted(r["folds"]), sorted(p["folds"]))))
        out["peak_agrees"] = abs(r["peak"] / p["peak"] - 1) < 1e-3
    else:
        out["note"] = "pyHarm is not installed (pip install pyHarm-os): resonant alone"
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    result = measure(args.repeats)
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    print(f"Duffing curve, omega 0.5 .. 2.5, H = 9; median of {args.repeats} alternating runs")
    print(f"{'':10s} {'points':>7s} {'stability':>9s} {'continuation s':>15s} "
          f"{'whole process s':>16s}  folds")
    for name, s in result["sides"].items():
        print(f"{name:10s} {s['points']:7d} {str(s['stability']):>9s} "
              f"{s['continuation_s']:15.3f} {s['whole_process_s']:16.3f}  "
              + ", ".join(f"{f:.5f}" for f in s["folds"]))
    if "call_s" in result["sides"]["resonant"]:
        print(f"(resonant's whole nonlinear_sweep call, with the derivation and compilation "
              f"of the equations: {result['sides']['resonant']['call_s']:.3f} s)")
    if "ratio_continuation" in result:
        print(f"resonant / pyHarm: continuation {result['ratio_continuation']:.2f}x, "
              f"whole process {result['ratio_whole_process']:.2f}x; folds agree: "
              f"{result['folds_agree']}, peak agrees: {result['peak_agrees']}")
    else:
        print(result["note"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
