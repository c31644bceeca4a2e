"""Shared helpers of the benchmarks: timing, power-law fits, subprocess runs.

Examples
--------
>>> exponent, scale = fit_power_law([10, 20, 40], [1.0, 8.0, 64.0])
>>> round(exponent, 6), round(extrapolate((exponent, scale), 80), 3)
(3.0, 512.0)
"""

from __future__ import annotations

import json
import math
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
BENCHMARKS = Path(__file__).resolve().parent


def environment() -> dict[str, str]:
    """The environment for child processes: resonant importable from src/, and bytecode
    caching on, as after ``pip install`` (pip compiles an installed package's modules; a
    source checkout with PYTHONDONTWRITEBYTECODE set would recompile every module of
    resonant on every start, 40-200 ms that no user pays; the first run writes the
    caches, and ``__pycache__`` is ignored by git)."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(SRC), str(BENCHMARKS)] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    return env


def median_time(fn: Callable[[], Any], repeats: int = 3, min_repeats_time: float = 2.0
                ) -> tuple[float, Any, list[float]]:
    """Median wall time of ``fn()`` over up to ``repeats`` calls.

    A call that takes longer than ``min_repeats_time`` seconds is not repeated
    (a slow call is already well above the timer's noise).  Returns
    ``(median, last result, all times)``.
    """
    times: list[float] = []
    result = None
    for _ in range(max(repeats, 1)):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
        if times[-1] > min_repeats_time:
            break
    return statistics.median(times), result, times


def fit_power_law(sizes: Sequence[float], times: Sequence[float]) -> tuple[float, float]:
    """Least-squares fit of log t = p log N + log c; returns ``(p, c)``."""
    if len(sizes) < 2:
        raise ValueError("a power-law fit needs at least two points")
    xs = [math.log(s) for s in sizes]
    ys = [math.log(t) for t in times]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    p = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    return p, math.exp(my - p * mx)


def extrapolate(fit: tuple[float, float], size: float) -> float:
    """The time the fitted power law predicts at ``size``."""
    p, c = fit
    return c * size ** p


def run_child(args: Sequence[str], timeout: float) -> dict[str, Any] | None:
    """Run ``python args`` in a fresh process; return its last stdout line as JSON.

    None when it ran out of time.  A crash raises RuntimeError with its stderr.
    """
    try:
        proc = subprocess.run([sys.executable, *args], capture_output=True, text=True,
                              timeout=timeout, env=environment(), cwd=ROOT)
    except subprocess.TimeoutExpired:
        return None
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def fmt_time(seconds: float | None, extrapolated: bool = False) -> str:
    """Seconds for the table; extrapolated values carry a leading '~' and a trailing '*'."""
    if seconds is None or not math.isfinite(seconds):
        return "n/a"
    text = f"{seconds:.3g} s" if seconds >= 0.01 else f"{seconds * 1e3:.3g} ms"
    return f"~{text}*" if extrapolated else text
