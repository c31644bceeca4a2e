"""Benchmark: a slider move on the explore page, measured in the browser.

A slider move recomputes everything the page shows -- the parameters, M, C, K, the
natural frequencies and modes (Cholesky + Jacobi), the state matrix's eigenvalues
(Hessenberg QR), the stationary solution, amplitudes and phases, the 400-point
frequency response -- and redraws the tables, the curve, the time history and the
mechanism.  The page's ``input`` handler does all of it synchronously, so the time
from dispatching the event to its return, taken with ``performance.now()`` inside the
page, is the whole update.

Targets (docs/explore.md): at most 30 ms for the reference exercise and 150 ms for a
20-DOF chain, and a page of at most 1.5 MB.  Models: the reference exercise
(2 DOF), the six-storey shear building (6 DOF), damped chains of 20 and 40 masses (40 is
the page's live limit, ``resonant.views.explore.LIVE_LIMIT``).  Side by side, what a
Python user would run for the same numbers, warm and in-process: ``stationary`` (the
solution with its eigenvalues) plus a 400-point ``sweep`` of the excitation frequency
with resonant's library; the ratio is page / library.

``python benchmarks/bench_explore.py [MOVES]`` prints JSON and the Markdown table of
docs/performance.md (section "Explore page").

Examples
--------
>>> "x20" in chain_model(20)
True
"""

from __future__ import annotations

import json
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import ROOT, SRC  # noqa: E402

sys.path.insert(0, str(SRC))

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TARGETS = {"reference exercise (2 DOF)": 30.0, "chain of 20 masses": 150.0}
PAGE_LIMIT = 1_500_000

MOVE = """([name, positions]) => {
  const slider = document.querySelector(`input[type=range][data-name="${name}"]`);
  const times = [];
  for (const pos of positions) {
    slider.value = String(pos);
    const start = performance.now();
    slider.dispatchEvent(new Event("input"));
    times.push(performance.now() - start);
  }
  return times;
}"""


def chain_model(n: int) -> str:
    """A damped fixed-free chain of ``n`` masses given by its energies, force at the end."""
    xs = [f"x{i + 1}" for i in range(n)]
    kinetic = " + ".join(f"m*{x}'^2/2" for x in xs)
    potential = "k*x1^2/2 + " + " + ".join(f"k*({xs[i]} - {xs[i - 1]})^2/2"
                                           for i in range(1, n))
    dissipation = "c*x1'^2/2 + " + " + ".join(f"c*({xs[i]}' - {xs[i - 1]}')^2/2"
                                              for i in range(1, n))
    coordinates = "\n".join(f'{x} = {{ description = "mass {i + 1}", unit = "m" }}'
                            for i, x in enumerate(xs))
    return f'''title = "Damped chain of {n} masses"
[parameters]
m = "1 kg"
k = "1000 N/m"
c = "0.5 N*s/m"
F0 = "10 N"
omega = "20 rad/s"
[coordinates]
{coordinates}
[signals]
F = "F0*sin(omega*t)"
[energy]
T = "{kinetic}"
U = "{potential}"
D = "{dissipation}"
[[force]]
name = "F"
vector = ["F"]
point = ["{xs[-1]}"]
'''


def models(folder: Path) -> dict[str, tuple[Path, str]]:
    """name -> (model file, the parameter whose slider moves besides omega)."""
    out = {"reference exercise (2 DOF)": (ROOT / "examples" / "cart_pendulum.toml", "k"),
           "shear building (6 DOF)": (ROOT / "examples" / "shear_building6.toml", "k")}
    for n in (20, 40):
        path = folder / f"chain{n}.toml"
        path.write_text(chain_model(n), encoding="utf-8")
        out[f"chain of {n} masses"] = (path, "k")
    return out


def library_time(path: Path, param: str, moves: int) -> float:
    """Median ms of what a Python user runs for the same numbers: the stationary solution
    (with its eigenvalues) and a 400-point sweep of the excitation frequency."""
    import numpy as np

    import resonant
    from resonant.analyses.stationary import stationary
    from resonant.analyses.sweep import sweep

    model = resonant.load(path)
    system = model.linearize()
    value = model.parameter_values[param]
    top = 2.0 * max(stationary(system).natural_frequencies)
    times = []
    for j in range(moves):
        start = time.perf_counter()
        point = system.numeric(**{param: value * (1 + 0.01 * (j % 5))})
        stationary(point)
        sweep(point, "omega", np.linspace(0.0, top, 400), method="direct")
        times.append(1000 * (time.perf_counter() - start))
    return statistics.median(times)


def measure(path: Path, param: str, moves: int, browser: Any) -> dict[str, Any]:
    """Write the page, open it, move two sliders; the times in ms (median, worst)."""
    import resonant
    from resonant.views.explore import explore_page

    start = time.perf_counter()
    page = explore_page(resonant.load(path))
    written = time.perf_counter() - start
    with tempfile.TemporaryDirectory() as folder:
        target = Path(folder) / "page.html"
        page.save(target)
        tab = browser.new_page(viewport={"width": 1280, "height": 900})
        try:
            tab.goto(target.resolve().as_uri())
            tab.wait_for_function("window.resonant !== undefined")
            tab.evaluate("resonant.pause()")
            tab.evaluate(MOVE, [param, [400, 600, 450, 550]])  # warm-up (compilation)
            positions = [300 + (37 * j) % 400 for j in range(moves)]
            times = tab.evaluate(MOVE, [param, positions])
            times += tab.evaluate(MOVE, ["omega", positions])
        finally:
            tab.close()
    return {"bytes": len(page.html.encode("utf-8")), "live": page.live,
            "coordinates": page.html.count('"description"'),
            "write_s": written, "median_ms": statistics.median(times), "max_ms": max(times),
            "moves": len(times)}


def run(moves: int = 20, only: tuple[str, ...] = ()) -> dict[str, Any]:
    """Every model: the page's times and the library's, the ratio and the verdicts."""
    from playwright.sync_api import sync_playwright

    results: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as folder, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            for name, (path, param) in models(Path(folder)).items():
                if only and name not in only:
                    continue
                row = measure(path, param, moves, browser)
                row["library_ms"] = library_time(path, param, max(3, moves // 4))
                row["ratio"] = row["median_ms"] / row["library_ms"]
                target = TARGETS.get(name)
                row["target_ms"] = target
                row["met"] = (target is None or row["median_ms"] <= target) and \
                    row["bytes"] <= PAGE_LIMIT
                results[name] = row
        finally:
            browser.close()
    return results


def table(results: dict[str, Any]) -> str:
    """The Markdown table of docs/performance.md."""
    lines = ["| model | page | slider move, median (worst) | target | library: stationary + "
             "400-point sweep | page / library |", "|---|---|---|---|---|---|"]
    for name, r in results.items():
        target = f"≤ {r['target_ms']:.0f} ms {'met' if r['met'] else 'MISSED'}" \
            if r["target_ms"] else "–"
        lines.append(f"| {name} | {r['bytes'] / 1024:.0f} kB | {r['median_ms']:.1f} ms "
                     f"({r['max_ms']:.1f}) | {target} | {r['library_ms']:.1f} ms | "
                     f"{r['ratio']:.2f} |")
    return "\n".join(lines)


if __name__ == "__main__":
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    found = run(count)
    print(json.dumps(found, indent=2))
    print(table(found))
