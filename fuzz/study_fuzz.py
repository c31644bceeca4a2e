"""Hostile input for the newest surfaces: study requests, ``[study]``, ``[explore]``,
``[[nonlinear]]`` and the files ``study --resume`` reads back.

Five generators, each building one case in a fresh folder and running the command line
in-process (``run_fuzz.run_one``, under the per-input budget) with ``--timeout``:

* **request**: ``study`` of a small model with mutated ``--vary`` specifications (numbers,
  units, distributions, lists, ranges, hostile fragments), ``--quantity``, ``--band``,
  ``--design``, ``--samples``, ``--seed``, ``--harmonics``, the same parameter twice,
  outputs of every ending and ``--json``;
* **study_section**: ``examples/absorber_tolerances.toml`` with its ``[study]`` section
  mutated (keys deleted, wrong types, extreme values, hostile strings), studied with a
  small ``--samples``;
* **explore_section**: a model with a mutated ``[explore]`` section through ``explore``;
* **nonlinear**: a ``[matrices]`` model with mutated ``[[nonlinear]]`` elements (kinds,
  keys, coordinates, hostile forces such as ``1/0*q2`` or ``exp(exp(1000*q2))``) through
  ``check`` and ``sweep --nonlinear``;
* **resume**: a finished study's ``.csv`` (with its ``.study.json``) or ``.parquet`` file,
  damaged (byte flips, truncation, edited values and headers, a mutated description,
  rows removed or repeated), then ``study --resume``.

The verdict is ``run_fuzz.verdict``: exit 0, 2 or 3 with a message; never exit 1, a
traceback, NaN in the JSON or a hang.

    PYTHONPATH=src python fuzz/study_fuzz.py --minutes 5 --seed 1 [--budget 30]
"""

from __future__ import annotations

import argparse
import collections
import copy
import json
import random
import shutil
import sys
import tempfile
import time
import tomllib
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
import run_fuzz  # noqa: E402

ROOT = run_fuzz.ROOT
SDOF = """title = "SDOF"
[parameters]
m = "1 kg"
k = "100 N/m"
c = "0.5 N*s/m"
F0 = "1 N"
omega = "8 rad/s"
[coordinates]
x = { description = "displacement", unit = "m" }
[signals]
F = "F0*sin(omega*t)"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2"
D = "c*x'^2/2"
[[force]]
generalized = { x = "F" }
"""
MATRIX = """[parameters]
w = 3
k3 = 2
g = 0.05
kc = 50
mu = 0.3
[coordinates]
q1 = ""
q2 = ""
[matrices]
M = [[1, 0], [0, 1]]
K = [[2, -1], [-1, 2]]
C = [[0.1, 0], [0, 0.1]]
[[harmonic]]
omega = "w"
F_S = [0.05, 0]
"""
PARAMETERS = ["m", "k", "c", "F0", "omega"]
SPECS = ["uniform({a}, {b})", "normal({a}, {s})", "lognormal({a}, {s})", "[{a}, {b}]",
         "{{from={a}, to={b}, step={s}}}", "uniform({a} N/m, {b} N/m)", "{a}",
         "uniform({a})", "normal({a}, -1)", "[]", "uniform({b}, {a})", "lognormal(-1, 1)"]
NUMBERS = ["0", "1", "-1", "90", "110", "1e308", "-1e308", "1e-320", "nan", "inf", "1e999",
           "9^9^9", "2^1000", "0.5", "1/0", "log(0)", "sqrt(-1)", "pi"]
QUANTITIES = ["natural_frequency:1", "natural_frequency:0", "natural_frequency:99",
              "damping_ratio:1", "amplitude:x", "amplitude:y", "phase:x", "peak:x", "stable",
              "nonlinear_amplitude:x", "bogus", "peak:", ":", "amplitude:x:x"]
DESIGNS = ["random", "lhs", "sobol", "grid", "monte", ""]
ENDINGS = [".csv", ".parquet", ".CSV", ".txt", "", ".parquet/", ".csv.part"]
FORCES = ["k3*q2^3", "1/0*q2", "0/0", "log(0)*q2", "exp(exp(1000*q2))", "q2'*abs(q2')",
          "q2''", "q1^3", "t*q2", "nan", "1e308*q2^9", "(q2)^999", "mu*sign(q2')", "", "q2^"]


def _number(rng: random.Random, hostile: float = 0.15) -> str:
    return rng.choice(NUMBERS) if rng.random() < hostile else f"{rng.uniform(0.1, 200):.4g}"


def _spec(rng: random.Random) -> str:
    a, b = sorted(float(_number(rng, 0)) for _ in range(2))
    if rng.random() < 0.5:  # a valid specification
        return rng.choice(SPECS[:5]).format(a=f"{a:.4g}", b=f"{b + 1:.4g}",
                                            s=f"{(b - a) / 4 + 0.1:.4g}")
    text = rng.choice(SPECS).format(a=_number(rng), b=_number(rng), s=_number(rng))
    if rng.random() < 0.1:
        text = run_fuzz.mutate_bytes(text, rng)
    return text


def request_case(rng: random.Random, folder: Path, timeout: float) -> list[str]:
    """A study request on the command line."""
    model = folder / "sdof.toml"
    model.write_text(SDOF, encoding="utf-8")
    args = ["study", str(model), "--timeout", str(timeout), "--workers", "0"]
    for _ in range(rng.choice([0, 1, 1, 2, 3])):
        name = rng.choice(PARAMETERS * 4 + ["x", "t", "", "k k", "zz"])
        args += ["--vary", f"{name}={_spec(rng)}"]
    for _ in range(rng.choice([0, 1, 1, 2])):
        args += ["--quantity", rng.choice(QUANTITIES[:9] * 3 + QUANTITIES)]
    if rng.random() < 0.4:
        args += ["--band", f"omega={_number(rng)}:{_number(rng)}"
                 + (f":{rng.choice(['3', '50', '0', '-1', 'x', '100001'])}"
                    if rng.random() < 0.5 else "")]
    if rng.random() < 0.4:
        args += ["--design", rng.choice(DESIGNS)]
    args += ["--samples", rng.choice(["1", "2", "8", "16", "64"] * 3 + ["0", "-1", "x"])]
    if rng.random() < 0.3:
        args += ["--seed", rng.choice(["0", "1", "7", "2026", "-1", str(2**63), "x"])]
    if rng.random() < 0.1:
        args += ["--harmonics", rng.choice(["1", "3", "5", "0", "41", "150", "x"])]
    if rng.random() < 0.3:
        args.append("--json")
    args += ["-o", str(folder / ("s" + rng.choice(ENDINGS[:2] * 6 + ENDINGS)))]
    return args


def _mutate_value(value: Any, rng: random.Random) -> Any:
    choice = rng.random()
    if choice < 0.3:
        return copy.deepcopy(rng.choice(run_fuzz.NASTY_VALUES))  # never a shared object
    if choice < 0.6 and isinstance(value, str):
        return rng.choice(["({})^999", "log({})", "sqrt(-({}))", "exp(exp({}))", "{} {}",
                           "{}*t"]).format(value, value) if rng.random() < 0.5 else \
            value.replace(rng.choice(value or "x"), rng.choice(run_fuzz.NASTY_TOKENS), 1)
    if choice < 0.8:
        return _spec(rng)
    return value


def _mutate_table(table: dict, rng: random.Random, keys: list[str]) -> None:
    for _ in range(rng.randint(1, 3)):
        action = rng.random()
        if action < 0.2 and table:
            del table[rng.choice(list(table))]
        elif action < 0.4:
            table[rng.choice(keys)] = _mutate_value("", rng)
        elif table:
            key = rng.choice(list(table))
            value = table[key]
            if isinstance(value, dict) and value and rng.random() < 0.6:
                inner = rng.choice(list(value))
                value[inner] = _mutate_value(value[inner], rng)
            elif isinstance(value, list) and value and rng.random() < 0.6:
                value[rng.randrange(len(value))] = _mutate_value(value[0], rng)
            else:
                table[key] = _mutate_value(value, rng)


def study_section_case(rng: random.Random, folder: Path, timeout: float) -> list[str]:
    """``[study]`` of the absorber example, mutated."""
    data = tomllib.loads((ROOT / "examples" / "absorber_tolerances.toml").read_text())
    _mutate_table(data["study"], rng, ["vary", "quantities", "band", "design", "samples",
                                       "seed", "harmonics", "bogus"])
    model = folder / "absorber.toml"
    model.write_text(run_fuzz.dump_toml(data), encoding="utf-8")
    args = ["study", str(model), "--timeout", str(timeout), "--workers", "0",
            "-o", str(folder / rng.choice(["s.csv", "s.parquet"]))]
    if rng.random() < 0.8:
        args += ["--samples", rng.choice(["4", "8", "16"])]
    if rng.random() < 0.3:
        args.append("--json")
    return args


def explore_section_case(rng: random.Random, folder: Path, timeout: float) -> list[str]:
    """``[explore]`` of a small model, mutated."""
    data = tomllib.loads(SDOF)
    data["explore"] = {"k": {"from": 50, "to": 200}, "m": {"from": "500 g", "to": "2 kg"},
                       "c": {"from": 0.1, "to": 100, "scale": "log"}, "show": ["x"],
                       "frequency": "omega"}
    _mutate_table(data["explore"], rng, PARAMETERS + ["show", "frequency", "x", "bogus"])
    model = folder / "page.toml"
    model.write_text(run_fuzz.dump_toml(data), encoding="utf-8")
    return ["explore", str(model), "--timeout", str(timeout), "-o",
            str(folder / rng.choice(["p.html", "p.htm", "p.txt", "sub/p.html"]))]


def nonlinear_case(rng: random.Random, folder: Path, timeout: float) -> list[str]:
    """A ``[matrices]`` model with mutated ``[[nonlinear]]`` elements."""
    elements: list[dict[str, Any]] = []
    for _ in range(rng.choice([1, 1, 2, 3])):
        kind = rng.choice(["force", "gap", "friction", "other", None])
        entry: dict[str, Any] = {"name": rng.choice(["e", "stop", "", "e"]),
                                 "coordinates": rng.choice([["q2"], ["q1", "q2"], ["q2", "q2"],
                                                            ["q9"], "q1", [], ["q1", 3]])}
        if kind is not None:
            entry["kind"] = kind
        if kind in (None, "force"):
            entry["force"] = rng.choice(FORCES)
        if kind == "gap":
            entry.update(gap=rng.choice(["g", "-0.01", "0", "1/0", "-g"]),
                         stiffness=rng.choice(["kc", "-1", "0", "1e308"]))
        if kind == "friction":
            entry.update(stiffness=rng.choice(["kc", "0", "-1"]),
                         slip_force=rng.choice(["mu", "0", "-mu", "nan"]))
        if rng.random() < 0.3:
            _mutate_table(entry, rng, ["force", "gap", "stiffness", "slip_force", "bogus"])
        elements.append(entry)
    text = MATRIX + "".join("[[nonlinear]]\n" + "".join(
        f"{run_fuzz._toml_key(k)} = {run_fuzz._toml_value(v)}\n" for k, v in e.items())
        for e in elements)
    model = folder / "nl.toml"
    model.write_text(text, encoding="utf-8")
    if rng.random() < 0.3:
        return ["check", str(model), "--timeout", str(timeout)]
    return ["sweep", str(model), "--nonlinear", "--param", "w", "--from",
            rng.choice(["0.5", "1", "0"]), "--to", rng.choice(["2", "3"]), "--points",
            rng.choice(["5", "10"]), "--timeout", str(timeout)]


#: finished studies, made once per fuzzer run: ending -> folder holding s.ENDING
_FINISHED: dict[str, Path] = {}
RESUME_REQUEST = ["--vary", "k=uniform(90, 110)", "--vary", "c=[0.5, 1]", "--quantity",
                  "natural_frequency:1", "--quantity", "stable", "--quantity", "amplitude:x",
                  "--samples", "64", "--workers", "0"]


def _finished(ending: str, scratch: Path) -> Path:
    if ending not in _FINISHED:
        folder = scratch / f"finished{ending}"
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "sdof.toml").write_text(SDOF, encoding="utf-8")
        status, _, err = run_fuzz.run_one(["study", str(folder / "sdof.toml"), *RESUME_REQUEST,
                                           "-o", str(folder / f"s{ending}")], 120)
        if status != 0:
            raise RuntimeError(f"the study to damage did not run: {err}")
        _FINISHED[ending] = folder
    return _FINISHED[ending]


def _damage_text(text: str, rng: random.Random) -> str:
    lines = text.split("\n")
    action = rng.random()
    if action < 0.25 and len(lines) > 2:
        i = rng.randrange(len(lines))
        cells = lines[i].split(",")
        cells[rng.randrange(len(cells))] = rng.choice(["abc", "", "nan", "inf", "-1",
                                                       "1e999", "True", "\x00", '"', "9" * 400])
        lines[i] = ",".join(cells)
    elif action < 0.4:
        lines[0] = rng.choice([lines[0].replace("k", "K"), lines[0] + ",extra",
                               ",".join(reversed(lines[0].split(","))), "", "sample"])
    elif action < 0.55 and len(lines) > 3:
        del lines[rng.randrange(1, len(lines) - 1)]
    elif action < 0.7 and len(lines) > 3:
        lines.insert(rng.randrange(1, len(lines)), lines[rng.randrange(1, len(lines) - 1)])
    elif action < 0.85:
        return text[:rng.randrange(len(text) + 1)]
    else:
        return run_fuzz.mutate_bytes(text, rng)
    return "\n".join(lines)


def _damage_bytes(data: bytes, rng: random.Random) -> bytes:
    out = bytearray(data)
    action = rng.random()
    if action < 0.4:  # flips anywhere, or in the data pages (the footer intact)
        end = len(out) if rng.random() < 0.5 else max(9, len(out) * 2 // 3)
        for _ in range(rng.randint(1, 20)):
            out[rng.randrange(min(end, len(out)))] = rng.randrange(256)
    elif action < 0.7:
        del out[rng.randrange(len(out)):]
    elif action < 0.85:
        start = rng.randrange(len(out))
        out[start:start + rng.randint(1, 400)] = bytes(rng.randint(1, 400))
    else:
        out += bytes(rng.randrange(256) for _ in range(rng.randint(1, 100)))
    return bytes(out)


def _damage_description(text: str, rng: random.Random) -> str:
    try:
        data = json.loads(text)
    except ValueError:
        return run_fuzz.mutate_bytes(text, rng)
    action = rng.random()
    if action < 0.5 and isinstance(data, dict) and data:
        key = rng.choice(list(data))
        data[key] = copy.deepcopy(rng.choice(run_fuzz.NASTY_VALUES[:4]
                                             + [None, [], {}, "x", -1, 10**30]))
    elif action < 0.7:
        return rng.choice(["", "null", "[]", "1", '"x"', "{" * 5000, text[: len(text) // 2]])
    else:
        return run_fuzz.mutate_bytes(text, rng)
    return json.dumps(data, default=str)


def resume_case(rng: random.Random, folder: Path, timeout: float) -> list[str]:
    """A finished study's file, damaged, resumed."""
    ending = rng.choice([".csv", ".parquet"])
    source = _finished(ending, folder.parent)  # its model, at the path the file records
    target = folder / f"s{ending}"
    shutil.copy(source / f"s{ending}", target)
    if ending == ".csv":
        side = Path(str(target) + ".study.json")
        shutil.copy(Path(str(source / "s.csv") + ".study.json"), side)
        choice = rng.random()
        if choice < 0.6:
            target.write_text(_damage_text(target.read_text(encoding="utf-8"), rng),
                              encoding="utf-8", errors="surrogateescape")
        elif choice < 0.9:
            side.write_text(_damage_description(side.read_text(encoding="utf-8"), rng),
                            encoding="utf-8", errors="surrogateescape")
        else:
            side.unlink()
    else:
        target.write_bytes(_damage_bytes(target.read_bytes(), rng))
    return ["study", str(source / "sdof.toml"), *RESUME_REQUEST, "--timeout", str(timeout),
            "-o", str(target), "--resume", *(["--json"] if rng.random() < 0.3 else [])]


GENERATORS = {"request": request_case, "study_section": study_section_case,
              "explore_section": explore_section_case, "nonlinear": nonlinear_case,
              "resume": resume_case}


def fuzz_case(rng: random.Random, kind: str, scratch: Path, budget: float, timeout: float
              ) -> tuple[list[str], int | str, str | None, str, float]:
    """One case of ``kind``: (arguments, status, bug or None, stderr, seconds)."""
    folder = scratch / f"case{rng.randrange(10**9)}"
    folder.mkdir(parents=True)
    args = GENERATORS[kind](rng, folder, timeout)
    start = time.monotonic()
    status, out, err = run_fuzz.run_one(args, budget)
    return (args, status, run_fuzz.verdict(status, out, err, "--json" in args), err,
            time.monotonic() - start)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=5.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--budget", type=float, default=30.0, help="seconds per input")
    parser.add_argument("--timeout", type=float, default=5.0,
                        help="--timeout passed to resonant (seconds)")
    parser.add_argument("--generators", default=",".join(GENERATORS))
    args = parser.parse_args(argv)
    kinds = args.generators.split(",")
    rng = random.Random(args.seed)
    crashes = ROOT / "fuzz" / "crashes"
    outcomes: collections.Counter[str] = collections.Counter()
    bugs: collections.Counter[str] = collections.Counter()
    saved: list[str] = []
    slowest = (0.0, "")
    start, tried = time.monotonic(), 0
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp)
        while time.monotonic() - start < 60 * args.minutes:
            tried += 1
            kind = kinds[tried % len(kinds)] if len(kinds) > 1 else kinds[0]
            case, status, bug, err, seconds = fuzz_case(rng, kind, scratch, args.budget,
                                                       args.timeout)
            outcomes[f"{kind} exit {status}"] += 1
            slowest = max(slowest, (round(seconds, 2), f"{kind}: {' '.join(case[:2])}"))
            if bug:
                key = f"{kind}: {bug}: {err.strip().splitlines()[-1][:160] if err.strip() else ''}"
                bugs[key] += 1
                if bugs[key] <= 3:
                    crashes.mkdir(exist_ok=True)
                    target = crashes / f"study_{args.seed}_{tried:06d}_{kind}"
                    output = next((Path(a) for a in case if a.startswith(str(scratch / "case"))),
                                  Path(case[1]))
                    shutil.copytree(output.parent, target, dirs_exist_ok=True)
                    (target / "CASE.txt").write_text(
                        " ".join(case) + f"\n{bug}\n{err[-3000:]}", encoding="utf-8")
                    saved.append(str(target.relative_to(ROOT)))
            for folder in scratch.glob("case*"):
                shutil.rmtree(folder, ignore_errors=True)
    report = {"seed": args.seed, "minutes": round((time.monotonic() - start) / 60, 2),
              "command": "python fuzz/study_fuzz.py " + " ".join(
                  sys.argv[1:] if argv is None else argv),
              "inputs": tried, "outcomes": dict(sorted(outcomes.items())),
              "bugs": dict(bugs), "bug_inputs": saved, "slowest_input_s": slowest[0],
              "slowest_input": slowest[1]}
    print(json.dumps(report, indent=2))
    return 1 if bugs else 0


if __name__ == "__main__":
    sys.exit(main())
