"""Benchmark 3: ``resonant solve examples/cart_pendulum.toml`` as a whole process.

Against the floor ``python -c "import sympy, numpy, scipy.linalg"``: the runs
alternate (floor, resonant, floor, ...) so that a change in the machine's load
hits both sides alike; the medians and their ratio are reported.  The profile
comes from ``python -X importtime`` (imports) and cProfile (the rest).

Examples
--------
>>> top = parse_importtime("import time: self [us] | cumulative | imported package\\n"
...                        "import time:       150 |        250 | numpy\\n")
>>> top[0]["module"], top[0]["cumulative_ms"]
('numpy', 0.25)
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import ROOT, environment  # noqa: E402

MODEL = ROOT / "examples" / "cart_pendulum.toml"
FLOOR = [sys.executable, "-c", "import sympy, numpy, scipy.linalg"]
SOLVE = [sys.executable, "-m", "resonant", "solve", str(MODEL)]


def _wall(cmd: list[str]) -> float:
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=environment(),
                          cwd=ROOT)
    elapsed = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {proc.returncode}:\n{proc.stderr[-2000:]}")
    return elapsed


def measure(runs: int = 7) -> dict[str, Any]:
    """Median wall times of the floor and of ``resonant solve``, alternating."""
    _wall(FLOOR)  # warm the file cache (both sides read the same packages)
    _wall(SOLVE)
    floor, solve = [], []
    for _ in range(runs):
        floor.append(_wall(FLOOR))
        solve.append(_wall(SOLVE))
    f, s = statistics.median(floor), statistics.median(solve)
    return {"floor": f, "solve": s, "ratio": s / f, "floor_times": floor,
            "solve_times": solve, "runs": runs}


def parse_importtime(stderr: str, top: int = 12) -> list[dict[str, Any]]:
    """The modules with the largest cumulative import time (ms), outermost first."""
    rows = []
    for line in stderr.splitlines():
        if not line.startswith("import time:") or "imported package" in line:
            continue
        self_us, cumulative_us, name = line.split(":", 1)[1].split("|")
        rows.append({"module": name.strip(), "self_ms": int(self_us) / 1000,
                     "cumulative_ms": int(cumulative_us) / 1000,
                     "depth": (len(name) - len(name.lstrip())) // 2})
    rows.sort(key=lambda r: -r["cumulative_ms"])
    return rows[:top]


def import_profile() -> list[dict[str, Any]]:
    proc = subprocess.run([sys.executable, "-X", "importtime", *SOLVE[1:]], capture_output=True,
                          text=True, env=environment(), cwd=ROOT)
    return parse_importtime(proc.stderr, top=40)


def run_profile(top: int = 12) -> list[dict[str, Any]]:
    """cProfile of ``resonant.cli.main(["solve", MODEL])`` in a fresh process, after
    importing the modules it uses (the import profile covers those)."""
    code = ("import cProfile, pstats, io, contextlib, json, sys\n"
            "import sympy, numpy, scipy.linalg\n"
            "import resonant.cli, resonant.model, resonant.derivation, resonant.system, "
            "resonant.analyses.stationary, resonant.views.display\n"
            "from resonant.cli import main\n"
            "pr = cProfile.Profile(); pr.enable()\n"
            "with contextlib.redirect_stdout(io.StringIO()): main(['solve', sys.argv[1]])\n"
            "pr.disable(); st = pstats.Stats(pr); rows = []\n"
            "for (f, l, fn), (cc, nc, tt, ct, callers) in st.stats.items():\n"
            "    rows.append({'function': f'{f.split(\"site-packages/\")[-1]}:{l}({fn})',"
            " 'calls': nc, 'tottime': tt, 'cumtime': ct})\n"
            "rows.sort(key=lambda r: -r['cumtime'])\n"
            "print(json.dumps(rows[:80]))\n")
    proc = subprocess.run([sys.executable, "-c", code, str(MODEL)], capture_output=True,
                          text=True, env=environment(), cwd=ROOT)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    import json

    rows = json.loads(proc.stdout.strip().splitlines()[-1])
    # Keep the informative rows: resonant's own functions and the big library calls,
    # not the import machinery's frames (those are in the import-time profile).
    skip = ("<frozen importlib", "builtins.exec", "builtins.__import__", "_imp.",
            "(<module>)", "marshal.loads", "__build_class__")
    keep = [r for r in rows if not any(s in r["function"] for s in skip)]
    return keep[:top]


if __name__ == "__main__":
    import json

    print(json.dumps(measure(3), indent=1))
    for r in import_profile()[:10]:
        print(r)
    for r in run_profile():
        print(r)
