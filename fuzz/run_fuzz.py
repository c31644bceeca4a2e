"""Mutation fuzzer for the model loader and ``resonant solve`` / ``check`` / ``modes``.

Mutates the bundled examples (``examples/*.toml``) at four levels -- bytes, tokens,
TOML structure and expressions -- and runs the command line in-process on each
mutant under a per-input time budget.  Every outcome must be exit 0, 2 or 3 with a
message; exit 1 (internal error), a traceback, NaN in the JSON or a hang is a bug,
and the input is saved under ``fuzz/crashes/``.

A second generator (``fuzz/matrix_fuzz.py``) builds hostile ``[matrices]``
models -- ``.npy``/``.npz``/``.mtx`` files, hand-built zip archives, FIFOs, symbolic
links, directories, escaping paths -- and runs each in a forked child (or a fresh
interpreter, ``--isolation subprocess``) under ``RLIMIT_AS`` and the time budget, so a
signal (SIGSEGV), a hang or a memory blow-up is recorded, not suffered.

    PYTHONPATH=src python fuzz/run_fuzz.py --minutes 5 [--seed 1] [--budget 10]
        [--generators text,matrix] [--matrix-share 0.5] [--memory 1.5] [--rss-bound 1.0]

The mutators are also used by ``tests/test_fuzz.py`` (a short run in CI).
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import copy
import io
import json
import math
import random
import signal
import sys
import time
import tomllib
from pathlib import Path
from typing import Any, Callable

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))  # matrix_fuzz
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))

#: hostile or awkward fragments spliced into expressions and values
NASTY_TOKENS = [
    "0", "-1", "1e308", "1e-320", "nan", "inf", "9^9^9", "2^1000", "(x1+x2)^50", "1/0",
    "__import__('os').system('touch /tmp/resonant-fuzz-canary')", "exec", "eval", "lambda",
    "t", "pi", "x'''", "sin(", ")", "((((", "'", '"', "\\", "*", "^", "**", ",", "atan2(0,0)",
    "log(0)", "sqrt(-1)", "exp(exp(exp(10)))", "é", "\x00", "\u202e", " ", "m1", "x1", "r",
]
NASTY_VALUES: list[Any] = [
    0, -1, 1e308, 1e-320, float("nan"), float("inf"), True, [], {}, [[1, 2], [3]], "",
    "9^9^9", "__class__", "x1'", "t", 10**400, -0.0, "1e999", {"a": "b"}, [1, "x"],
]


def _toml_key(key: str) -> str:
    return key if key and all(c.isalnum() or c in "_-" for c in key) else json.dumps(key)


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if value != value else ("inf" if value > 0 else "-inf") \
            if math.isinf(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(v)}"
                               for k, v in value.items()) + "}"
    return json.dumps(str(value))


def dump_toml(data: dict) -> str:
    """A small TOML writer (tables, arrays of tables, inline values) for mutated data."""
    lines = []
    for key, value in data.items():
        if not isinstance(value, (dict, list)) or (isinstance(value, list) and not all(
                isinstance(v, dict) for v in value)) or value == []:
            lines.append(f"{_toml_key(key)} = {_toml_value(value)}")
    for key, value in data.items():
        if isinstance(value, dict):
            lines.append(f"\n[{_toml_key(key)}]")
            lines.extend(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items())
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for entry in value:
                lines.append(f"\n[[{_toml_key(key)}]]")
                lines.extend(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in entry.items())
    return "\n".join(lines) + "\n"


# -- mutators: (text, rng) -> text ------------------------------------------------------------

def mutate_bytes(text: str, rng: random.Random) -> str:
    data = bytearray(text.encode("utf-8"))
    for _ in range(rng.randint(1, 8)):
        if not data:
            break
        i = rng.randrange(len(data))
        op = rng.random()
        if op < 0.4:
            data[i] = rng.randrange(256)
        elif op < 0.7:
            del data[i]
        else:
            data[i:i] = bytes([rng.choice(b"[]{}=\"'#\n\\^*()-+.,0123456789")])
    return data.decode("utf-8", errors="replace")


def mutate_tokens(text: str, rng: random.Random) -> str:
    import re

    tokens = re.findall(r"[A-Za-z_][A-Za-z0-9_]*'*|[0-9.]+(?:[eE][-+]?[0-9]+)?|\s+|.", text)
    words = [t for t in tokens if t.strip()]
    for _ in range(rng.randint(1, 4)):
        i = rng.randrange(len(tokens))
        choice = rng.random()
        if choice < 0.5:
            tokens[i] = rng.choice(NASTY_TOKENS)
        elif choice < 0.8:
            tokens[i] = rng.choice(words)
        else:
            tokens[i] = ""
    return "".join(tokens)


def _expression_slots(data: dict) -> list[tuple[dict | list, Any]]:
    slots: list[tuple[dict | list, Any]] = []

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            for key, value in node.items():
                if isinstance(value, (str, int, float)) and not isinstance(value, bool):
                    slots.append((node, key))
                walk(value)
        elif isinstance(node, list):
            for i, value in enumerate(node):
                if isinstance(value, (str, int, float)) and not isinstance(value, bool):
                    slots.append((node, i))
                walk(value)
    walk(data)
    return slots


def mutate_structure(text: str, rng: random.Random) -> str:
    data = tomllib.loads(text)
    for _ in range(rng.randint(1, 3)):
        tables = [data] + [v for v in data.values() if isinstance(v, dict)] + [
            e for v in data.values() if isinstance(v, list) for e in v if isinstance(e, dict)]
        table = rng.choice(tables)
        op = rng.random()
        if op < 0.3 and table:
            del table[rng.choice(list(table))]
        elif op < 0.6 and table:
            table[rng.choice(list(table))] = copy.deepcopy(rng.choice(NASTY_VALUES))
        elif op < 0.8:
            name = rng.choice(["x1", "m", "T", "__init__", "q", "t", "sin", "a b", "1x",
                               "force", "matrices", "harmonic", "signals", "é"])
            table[name] = copy.deepcopy(rng.choice(NASTY_VALUES + ["x1", "m*x1'^2/2", "0"]))
        else:  # swap two values
            slots = _expression_slots(data)
            if len(slots) >= 2:
                (a, i), (b, j) = rng.sample(slots, 2)
                a[i], b[j] = b[j], a[i]
    return dump_toml(data)


def mutate_expressions(text: str, rng: random.Random) -> str:
    data = tomllib.loads(text)
    slots = _expression_slots(data)
    if not slots:
        return text
    names = sorted({k for v in data.values() if isinstance(v, dict) for k in v})
    for _ in range(rng.randint(1, 3)):
        node, key = rng.choice(slots)
        value = str(node[key])
        op = rng.random()
        if op < 0.2:
            value = f"({value})^{rng.choice([2, 3, 50, 999, -1, 0.5])}"
        elif op < 0.4:
            value = f"{value} {rng.choice('+-*/^')} {rng.choice(names + NASTY_TOKENS)}"
        elif op < 0.55:
            value = f"{rng.choice(['sin', 'cos', 'exp', 'log', 'sqrt', 'atan', 'tanh'])}({value})"
        elif op < 0.7 and names:
            value = value.replace(rng.choice(names), rng.choice(names + ["t", "pi", "q"]))
        elif op < 0.85:
            i = rng.randrange(len(value) + 1)
            value = value[:i] + rng.choice(NASTY_TOKENS) + value[i:]
        else:
            value = rng.choice(NASTY_TOKENS)
        node[key] = value
    return dump_toml(data)


MUTATORS: dict[str, Callable[[str, random.Random], str]] = {
    "bytes": mutate_bytes, "tokens": mutate_tokens, "structure": mutate_structure,
    "expressions": mutate_expressions,
}


def mutant(rng: random.Random) -> tuple[str, str, str]:
    """(example name, mutator name, mutated text), chosen and built from ``rng``."""
    path = rng.choice(EXAMPLES)
    kind = rng.choice(sorted(MUTATORS))
    text = path.read_text()
    for _ in range(rng.randint(1, 2)):
        try:
            text = MUTATORS[kind](text, rng)
        except (tomllib.TOMLDecodeError, RecursionError, ValueError):
            text = mutate_bytes(text, rng)  # an earlier round broke the TOML: go on by bytes
    return path.name, kind, text


# -- running -----------------------------------------------------------------------------------

class Hang(BaseException):
    """The per-input time budget ran out."""


def _expired(signum: int, frame: Any) -> None:
    raise Hang


def run_one(args: list[str], budget: float) -> tuple[int | str, str, str]:
    """Run the CLI in-process under ``budget`` seconds: (status or 'hang', stdout, stderr)."""
    from resonant.cli import main

    out, err = io.StringIO(), io.StringIO()
    previous = signal.signal(signal.SIGALRM, _expired)
    signal.setitimer(signal.ITIMER_REAL, budget)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status: int | str = main(args)
            except SystemExit as exc:  # argparse
                status = exc.code if isinstance(exc.code, int) else 2
    except Hang:
        status = "hang"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    return status, out.getvalue(), err.getvalue()


def _reject_constant(name: str) -> Any:
    raise ValueError(f"JSON holds {name}")


def verdict(status: int | str, out: str, err: str, json_expected: bool) -> str | None:
    """Why this outcome is a bug, or None if it is acceptable."""
    if status == "hang":
        return "hang"
    if status not in (0, 2, 3):
        return f"exit status {status}"
    if "Traceback" in err or "Traceback" in out:
        return "traceback"
    if status != 0 and not err.strip():
        return "failure without a message"
    if status == 0 and json_expected:
        try:
            json.loads(out, parse_constant=_reject_constant)
        except ValueError as exc:
            return f"bad JSON: {exc}"
    return None


COMMANDS = (["solve", "--json"], ["check"], ["solve"], ["modes", "--json"])


def fuzz_one(rng: random.Random, workdir: Path, budget: float, derivation_budget: float,
             isolate: bool = False) -> tuple[str, str, str, int | str, str | None, str]:
    """One mutant through one command: (example, mutator, command, status, bug, stderr).

    ``isolate`` runs it in a forked child (``matrix_fuzz.run_forked``) instead of
    in-process, so that a crash by a signal is recorded instead of ending the fuzzer."""
    example, kind, text = mutant(rng)
    path = workdir / f"fuzz_{example}"
    path.write_text(text, encoding="utf-8", errors="surrogateescape")
    command = rng.choice(COMMANDS)
    args = [command[0], str(path), "--timeout", str(derivation_budget), *command[1:]]
    if isolate:
        import matrix_fuzz

        status, out, err, _, _ = matrix_fuzz.run_forked(args, budget)
    else:
        status, out, err = run_one(args, budget)
    return example, kind, command[0], status, verdict(status, out, err, "--json" in command), err


def main(argv: list[str] | None = None) -> int:
    import resource
    import shutil
    import tempfile

    import matrix_fuzz

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=5.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--budget", type=float, default=20.0, help="seconds per input")
    parser.add_argument("--derivation-budget", type=float, default=5.0,
                        help="--timeout passed to resonant (seconds)")
    parser.add_argument("--generators", default="text,matrix",
                        help="comma-separated: text (mutated examples, in-process), matrix "
                             "(hostile [matrices] files and special files, one forked child "
                             "per input)")
    parser.add_argument("--matrix-share", type=float, default=0.5,
                        help="fraction of inputs from the matrix generator when both run")
    parser.add_argument("--isolation", choices=("fork", "subprocess"), default="fork",
                        help="matrix inputs: forked child or fresh interpreter")
    parser.add_argument("--isolate-text", action="store_true",
                        help="run the text mutants in forked children too (default: "
                             "in-process, faster; a crash by a signal would end the run)")
    parser.add_argument("--memory", type=float, default=1.5,
                        help="RLIMIT_AS of each matrix child, GiB")
    parser.add_argument("--rss-bound", type=float, default=1.0,
                        help="peak RSS of a matrix child above this (GiB) is a bug")
    args = parser.parse_args(argv)
    generators = set(args.generators.split(","))
    rng = random.Random(args.seed)
    crashes = ROOT / "fuzz" / "crashes"
    outcomes: collections.Counter[str] = collections.Counter()
    by_kind: collections.Counter[str] = collections.Counter()
    bugs: collections.Counter[str] = collections.Counter()
    bug_inputs: list[str] = []
    canary = Path("/tmp/resonant-fuzz-canary")
    canary.unlink(missing_ok=True)
    memory = int(args.memory * 2**30)
    rss_bound = int(args.rss_bound * 2**30)
    start, tried, slowest, peak = time.monotonic(), 0, (0.0, ""), (0, "")
    hangs = signals = internal = 0
    with tempfile.TemporaryDirectory() as tmp:
        while time.monotonic() - start < 60 * args.minutes:
            tried += 1
            use_matrix = "matrix" in generators and (
                "text" not in generators or rng.random() < args.matrix_share)
            t0 = time.monotonic()
            if use_matrix:
                folder = Path(tmp) / f"case{tried}"
                result = matrix_fuzz.fuzz_case(rng, folder, args.budget, memory, args.isolation,
                                               rss_bound)
                kind, command, status, bug, err = (f"matrix/{result['kind']}", result["command"],
                                                   result["status"], result["bug"],
                                                   result["stderr"])
                label = f"{kind}/{command}"
                if result["rss"] > peak[0]:
                    peak = (result["rss"], label)
            else:
                example, kind, command, status, bug, err = fuzz_one(
                    rng, Path(tmp), args.budget, args.derivation_budget, args.isolate_text)
                kind = f"text/{kind}"
                label = f"{example}/{kind}/{command}"
            elapsed = time.monotonic() - t0
            slowest = max(slowest, (elapsed, label))
            outcomes[f"{command} exit {status}"] += 1
            by_kind[kind] += 1
            if bug:
                hangs += bug == "hang"
                signals += bug.startswith("signal")
                internal += bug in ("internal error", "traceback") or bug.startswith("exit status")
                key = f"{bug}: {err.strip().splitlines()[-1][:160] if err.strip() else ''}"
                bugs[key] += 1
                crashes.mkdir(exist_ok=True)
                if bugs[key] > 3:  # the same bug again: count it, keep three inputs
                    pass
                elif use_matrix:
                    target = crashes / f"{args.seed}_{tried:06d}_{result['kind']}"
                    if target.exists():
                        shutil.rmtree(target)
                    matrix_fuzz.save_case(folder, target, f"{command}: {bug}\n{err[-2000:]}")
                else:
                    target = crashes / f"{args.seed}_{tried:06d}_{example}"
                    target.write_bytes((Path(tmp) / f"fuzz_{example}").read_bytes())
                bug_inputs.append(str(target.relative_to(ROOT)))
            if use_matrix:
                shutil.rmtree(folder, ignore_errors=True)
    self_rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    report = {
        "seed": args.seed, "minutes": round((time.monotonic() - start) / 60, 2),
        "command": "python fuzz/run_fuzz.py " + " ".join(sys.argv[1:] if argv is None else argv),
        "inputs": tried, "outcomes": dict(sorted(outcomes.items())),
        "generators": dict(sorted(by_kind.items())),
        "generator_totals": dict(sorted(collections.Counter(
            k.split("/")[0] for k in by_kind.elements()).items())),
        "internal_errors": internal, "hangs": hangs, "crashes_by_signal": signals,
        "bugs": dict(bugs), "bug_inputs": bug_inputs,
        "slowest_input_s": round(slowest[0], 2), "slowest_input": slowest[1],
        "peak_rss_matrix_child_mib": round(peak[0] / 2**20, 1), "peak_rss_input": peak[1],
        "peak_rss_fuzzer_mib": round(self_rss / 2**20, 1),
        "canary_created": canary.exists(),
    }
    print(json.dumps(report, indent=2))
    return 1 if bugs or canary.exists() else 0


if __name__ == "__main__":
    sys.exit(main())
