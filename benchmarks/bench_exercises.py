"""Benchmark: ``resonant exercise`` -- N variants of the teaching model with HTML solutions.

The target: 100 variants of examples/teaching/cart_pendulum.toml with HTML
solutions in under 30 s (one derivation; numbers substituted per variant).  Runs the
command as a process, with and without the plots of the solutions, and prints the
wall times as JSON.  ``python benchmarks/bench_exercises.py [N]``.

Examples
--------
>>> command(10, Path("out"), plots=False)[-4:]
['--format', 'html', '--no-plots', '--timeout=0']
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import ROOT, environment  # noqa: E402

MODEL = ROOT / "examples" / "teaching" / "cart_pendulum.toml"


def command(count: int, folder: Path, plots: bool) -> list[str]:
    return [sys.executable, "-m", "resonant", "exercise", str(MODEL), "--variants", str(count),
            "--seed", "1", "-o", str(folder), "--format", "html",
            *([] if plots else ["--no-plots"]), "--timeout=0"]


def measure(count: int = 100) -> dict[str, Any]:
    out: dict[str, Any] = {"variants": count, "target_s": 30.0}
    for plots in (False, True):
        with tempfile.TemporaryDirectory() as tmp:
            start = time.perf_counter()
            proc = subprocess.run(command(count, Path(tmp) / "out", plots), capture_output=True,
                                  text=True, env=environment(), cwd=ROOT)
            elapsed = time.perf_counter() - start
        if proc.returncode != 0:
            raise RuntimeError(proc.stderr[-2000:])
        out["with_plots_s" if plots else "no_plots_s"] = round(elapsed, 2)
    return out


if __name__ == "__main__":
    print(json.dumps(measure(int(sys.argv[1]) if len(sys.argv) > 1 else 100), indent=2))
