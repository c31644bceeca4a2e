"""Benchmark: loading a model with units against the same model without (docs/units.md).

The target: a model with units costs at most a few ms more to load than the
same model in bare SI numbers, and no analysis pays anything (the numbers are SI
after loading).  Three versions of the reference exercise (cart + pendulum) are
loaded in one process, alternating, ``--repeats`` times each after a warm-up:

* ``si``: bare numbers (``m1 = 2``), no units anywhere;
* ``units``: the bundled ``examples/cart_pendulum.toml``, every value with its unit;
* ``mixed``: the data in g, mm, N/mm, kN, deg, rpm, coordinates in m and mm.

It also loads each once in a fresh process to report whether pint was imported (it
must not be: the usual units are in resonant's own table) and the solve time of the
loaded models (the same for all three: the analyses never see units).
``python benchmarks/bench_units.py [REPEATS]`` prints JSON.

Examples
--------
>>> sorted(texts())
['mixed', 'si', 'units']
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import ROOT, SRC, environment  # noqa: E402

sys.path.insert(0, str(SRC))

EXAMPLE = ROOT / "examples" / "cart_pendulum.toml"

SI_VALUES = {'"2 kg"': "2", '"1 kg"': "1", '"0.5 m"': "0.5", '"100 N/m"': "100",
             '"9.81 m/s^2"': "9.81", '"5 N"': "5", '"pi/3 rad"': '"pi/3"', '"0.01 m"': "0.01",
             '"20 rad/s"': "20", '"x2/l rad"': '"x2/l"'}
MIXED_VALUES = {'"2 kg"': '"2000 g"', '"1 kg"': '"0.001 t"', '"0.5 m"': '"500 mm"',
                '"100 N/m"': '"0.1 N/mm"', '"5 N"': '"0.005 kN"', '"pi/3 rad"': '"60 deg"',
                '"0.01 m"': '"10 mm"', '"20 rad/s"': '"190.98593171027440 rpm"'}


def texts() -> dict[str, str]:
    """The three versions of the model text."""
    units = EXAMPLE.read_text()
    si, mixed = units, units
    for old, new in SI_VALUES.items():
        si = si.replace(f"= {old}", f"= {new}")
    si = si.replace('{ description = "horizontal displacement of the cart\'s centre of '
                    'gravity", unit = "m" }', '"cart"').replace(
        '{ description = "horizontal displacement of the rod\'s lower end C", unit = "m" }',
        '"rod end"')
    for old, new in MIXED_VALUES.items():
        mixed = mixed.replace(f"= {old}", f"= {new}")
    return {"si": si, "units": units, "mixed": mixed}


_CHILD = """
import sys, time
start = time.perf_counter()
from resonant.api import loads
model = loads(sys.stdin.read())
loaded = time.perf_counter()
solution = model.linearize().stationary()
solved = time.perf_counter()
print(model.units is not None, 'pint' in sys.modules, loaded - start, solved - loaded,
      solution.amplitudes['x2'])
"""


def measure(repeats: int = 200) -> dict[str, Any]:
    from resonant.api import loads

    versions = texts()
    assert loads(versions["si"]).units is None
    for text in versions.values():  # warm-up (imports, caches)
        loads(text)
    times: dict[str, list[float]] = {name: [] for name in versions}
    for _ in range(repeats):
        for name, text in versions.items():
            start = time.perf_counter()
            loads(text)
            times[name].append(time.perf_counter() - start)
    out: dict[str, Any] = {"repeats": repeats, "target_extra_ms": "a few"}
    for name, samples in times.items():
        out[f"load_{name}_ms"] = round(1e3 * statistics.median(samples), 3)
    for name in ("units", "mixed"):
        out[f"extra_{name}_ms"] = round(out[f"load_{name}_ms"] - out["load_si_ms"], 3)
    amplitudes = {}
    for name, text in versions.items():
        proc = subprocess.run([sys.executable, "-c", _CHILD], input=text, capture_output=True,
                              text=True, env=environment(), cwd=ROOT, check=True)
        has_units, pint, load_s, solve_s, amplitude = proc.stdout.split()
        out[f"{name}_has_units"] = has_units == "True"
        out[f"{name}_imports_pint"] = pint == "True"
        out[f"{name}_first_load_ms"] = round(1e3 * float(load_s), 1)
        out[f"{name}_solve_ms"] = round(1e3 * float(solve_s), 1)
        amplitudes[name] = float(amplitude)
    spread = max(amplitudes.values()) / min(amplitudes.values()) - 1
    assert spread < 1e-12, amplitudes  # the same answer in every version
    out["same_answer"] = True
    return out


if __name__ == "__main__":
    print(json.dumps(measure(int(sys.argv[1]) if len(sys.argv) > 1 else 200), indent=2))
