"""Large energy models: the N-link pendulum chain end to end.

What a user does with a large model given by its energies, each stage timed in
a fresh process (imports and a 4-link warm-up outside the clock):

* **derive** -- ``resonant.load(path).linearize()``;
* **numbers** -- ``eom.numeric()`` (the numeric M, C, K and the load: with the
  symbolic path this is where the matrices are compiled);
* **first solve** -- ``eom.stationary()`` (the pivot of the chain moves
  horizontally, ``s = s0 cos(w t)``, so that there is a load);
* **symbolic M, K** -- then ``eom.M``, ``eom.K`` as sympy matrices (what
  ``bench_derivation.py`` times; derived only when asked for).

``--sweeps`` times instead, after the derivation, a batch over a mass (50 values, M
changes), then a sweep over the load's frequency (200 values).

``--baseline DIR`` runs the same children against another copy of the package
(``DIR`` holds ``resonant/``), e.g. the previous release extracted with
``git archive <commit> src | tar -x -C /tmp/base`` -> ``--baseline /tmp/base/src``.
Each measurement is repeated and the best time kept (the machine is shared).

Examples
--------
>>> "s + l1*sin(th1)" in forced_chain_toml(2)
True
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import BENCHMARKS, SRC  # noqa: E402
from pendulum_chain import pendulum_chain_toml  # noqa: E402


def forced_chain_toml(n: int) -> str:
    """The ``n``-link chain of :mod:`pendulum_chain` with a moving pivot (a load)."""
    text = pendulum_chain_toml(n)
    text = text.replace('x1 = "l1*sin(th1)"', 'x1 = "s + l1*sin(th1)"')
    text = text.replace("[parameters]\n", "[parameters]\ns0 = 0.01\nw = 2.5\n")
    return text.replace("[coordinates]", '[signals]\ns = "s0*cos(w*t)"\n\n[coordinates]')


def child(n: int) -> dict[str, Any]:
    """In a fresh process: time the stages of one run."""
    import numpy as np

    import resonant

    with tempfile.TemporaryDirectory() as tmp:
        warm = Path(tmp) / "warm.toml"
        warm.write_text(forced_chain_toml(4), encoding="utf-8")
        resonant.load(warm).linearize().stationary()
        path = Path(tmp) / f"chain_{n}.toml"
        path.write_text(forced_chain_toml(n), encoding="utf-8")
        times = {}
        start = time.perf_counter()
        eom = resonant.load(path).linearize()
        times["derive"] = time.perf_counter() - start
        start = time.perf_counter()
        numbers = eom.numeric()
        times["numbers"] = time.perf_counter() - start
        start = time.perf_counter()
        solution = eom.stationary()
        times["solve"] = time.perf_counter() - start
        start = time.perf_counter()
        M, K = eom.M, eom.K
        times["symbolic"] = time.perf_counter() - start
    amplitudes = np.array([solution.amplitudes[q] for q in eom.coordinates], dtype=float)
    return {"n": n, "times": times, "M": np.asarray(numbers.M).tolist(),
            "K": np.asarray(numbers.K).tolist(), "amplitudes": amplitudes.tolist(),
            "symbolic_entries": int(sum(1 for e in [*M, *K] if e != 0))}


def sweeps_child(n: int) -> dict[str, Any]:
    """In a fresh process: after the derivation, a batch over a mass (50 values, M
    changes), then a sweep over the load's frequency (200 values)."""
    import numpy as np

    import resonant

    with tempfile.TemporaryDirectory() as tmp:
        warm = Path(tmp) / "warm.toml"
        warm.write_text(forced_chain_toml(4), encoding="utf-8")
        resonant.load(warm).linearize().stationary()
        path = Path(tmp) / f"chain_{n}.toml"
        path.write_text(forced_chain_toml(n), encoding="utf-8")
        eom = resonant.load(path).linearize()
        times = {}
        start = time.perf_counter()
        eom.batch("m1", np.linspace(1.0, 2.0, 50))
        times["batch_m1"] = time.perf_counter() - start
        start = time.perf_counter()
        eom.sweep("w", np.linspace(0.5, 3.0, 200))
        times["sweep_w"] = time.perf_counter() - start
    return {"n": n, "times": times}


def run_child(n: int, src: Path, timeout: float, mode: str = "--child"
              ) -> dict[str, Any] | None:
    """One child run against the package in ``src``; None when it ran out of time."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(src), str(BENCHMARKS)])
    for key in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        env[key] = "1"  # one BLAS thread on either side (the machine is shared)
    try:
        proc = subprocess.run([sys.executable, __file__, mode, str(n)],
                              capture_output=True, text=True, timeout=timeout, env=env,
                              cwd="/")
    except subprocess.TimeoutExpired:
        return None
    if proc.returncode != 0:
        raise RuntimeError(f"N = {n} failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def difference(a: list, b: list) -> float:
    """max |a - b| / max |b|."""
    import numpy as np

    a, b = np.asarray(a), np.asarray(b)
    return float(np.abs(a - b).max() / np.abs(b).max())


def run(sizes: list[int], baseline: Path | None, repeats: int, timeout: float) -> list[dict]:
    """Best of ``repeats`` runs per size and side; the sides agree to the last bits."""
    rows = []
    sides = [("now", SRC)] + ([("baseline", baseline)] if baseline else [])
    for n in sizes:
        row: dict[str, Any] = {"n": n}
        for side, src in sides:
            results = [r for r in (run_child(n, src, timeout) for _ in range(repeats)) if r]
            if not results:
                row[side] = None
                continue
            best = {k: min(r["times"][k] for r in results) for k in results[0]["times"]}
            row[side] = {"times": best, "M": results[0]["M"], "K": results[0]["K"],
                         "amplitudes": results[0]["amplitudes"]}
            print(f"N={n} {side}: " + ", ".join(f"{k} {v:.3f} s" for k, v in best.items()),
                  flush=True)
        if row.get("baseline") and row.get("now"):
            row["agreement"] = max(difference(row["now"][k], row["baseline"][k])
                                   for k in ("M", "K", "amplitudes"))
            print(f"N={n}: largest relative difference {row['agreement']:.2e}", flush=True)
        rows.append(row)
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--child", type=int, metavar="N")
    parser.add_argument("--sweeps-child", type=int, metavar="N")
    parser.add_argument("--sweeps", action="store_true",
                        help="time a sweep over w and a batch over m1 instead")
    parser.add_argument("--sizes", default="50,100,200")
    parser.add_argument("--baseline", type=Path, help="src directory of another version")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=600.0)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args.child)))
    elif args.sweeps_child:
        print(json.dumps(sweeps_child(args.sweeps_child)))
    elif args.sweeps:
        for n in (int(s) for s in args.sizes.split(",")):
            for side, src in [("now", SRC)] + ([("baseline", args.baseline)]
                                               if args.baseline else []):
                runs = [run_child(n, src, args.timeout, "--sweeps-child")
                        for _ in range(args.repeats)]
                best = {k: min(r["times"][k] for r in runs if r) for k in ("batch_m1", "sweep_w")}
                print(f"N={n} {side}: " + ", ".join(f"{k} {v:.3f} s" for k, v in best.items()),
                      flush=True)
    else:
        result = run([int(s) for s in args.sizes.split(",")], args.baseline, args.repeats,
                     args.timeout)
        print(json.dumps([{k: (v["times"] if isinstance(v, dict) else v) for k, v in r.items()}
                          for r in result]))
