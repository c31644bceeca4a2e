"""Shared helpers for the resonant test suite.

The helpers drive the command line in-process (``resonant.cli.main``), so tests see
exactly what a user sees: the exit status, standard output and standard error.

Plain functions (importable as ``from conftest import run_cli, solve_json``) and
fixtures with the same behaviour (``examples_dir``, ``cli``, ``solve``) are provided.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
from pathlib import Path
from typing import Any, Callable

import pytest

# The suite runs in two worker processes on CI's two cores (pyproject.toml): one BLAS thread
# each, so that neither waits for the other's spinning threads (set before numpy loads;
# resonant.analyses.threads still raises it for a dense call where more threads pay off).
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

#: The directory holding the example model files.
EXAMPLES = Path(__file__).parents[1] / "examples"


def run_cli(args: list[str]) -> tuple[int, str, str]:
    """Run ``resonant.cli.main(args)`` in-process.

    Returns ``(exit_status, stdout, stderr)``.  A ``SystemExit`` (argparse errors,
    ``--help``) is caught and turned into its exit status, as a shell would see it.
    """
    # Imported here so that collecting the tests does not fail while the core is
    # missing or broken: only the tests that run the CLI fail.
    from resonant.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = main([str(a) for a in args])
        except SystemExit as exc:
            code = exc.code
            if code is None:
                status = 0
            elif isinstance(code, int):
                status = code
            else:  # sys.exit("message"): the message goes to stderr, status 1
                print(code, file=err)
                status = 1
    if status is None:  # a main() that forgets to return counts as success
        status = 0
    return int(status), out.getvalue(), err.getvalue()


def run_json(command: str, path: str | Path, *extra: str) -> dict[str, Any]:
    """Run ``resonant COMMAND PATH --json *extra``; assert exit 0; return the JSON."""
    status, out, err = run_cli([command, str(path), "--json", *extra])
    assert status == 0, (
        f"resonant {command} {path} {' '.join(extra)} exited with {status}\n"
        f"stderr:\n{err}\nstdout:\n{out}"
    )
    try:
        return json.loads(out)
    except json.JSONDecodeError as exc:  # pragma: no cover - diagnostic only
        raise AssertionError(f"stdout is not one JSON object ({exc}):\n{out}") from exc


def solve_json(path: str | Path, *extra: str) -> dict[str, Any]:
    """Run ``resonant solve PATH --json *extra``; assert exit 0; return the JSON object."""
    return run_json("solve", path, *extra)


@pytest.fixture
def examples_dir() -> Path:
    """The directory holding the example model files."""
    return EXAMPLES


@pytest.fixture
def cli() -> Callable[[list[str]], tuple[int, str, str]]:
    """The :func:`run_cli` helper as a fixture."""
    return run_cli


@pytest.fixture
def solve() -> Callable[..., dict[str, Any]]:
    """The :func:`solve_json` helper as a fixture."""
    return solve_json


def pendulum_chain_text(links: int) -> str:
    """An N-link planar pendulum chain as a model file: a derivation that takes a while
    (seconds at 300 links with the numeric derivation; 80 links take a
    fraction of a second), for tests of the time budget."""
    lines = ["[parameters]", "g = 9.81"]
    lines += [f"m{i} = 1\nl{i} = 1" for i in range(1, links + 1)]
    lines.append("[coordinates]")
    lines += [f'th{i} = ""' for i in range(1, links + 1)]
    lines.append("[definitions]")
    for i in range(1, links + 1):
        x = f"x{i - 1} + " if i > 1 else ""
        y = f"y{i - 1} " if i > 1 else ""
        lines += [f'x{i} = "{x}l{i}*sin(th{i})"', f'y{i} = "{y}- l{i}*cos(th{i})"']
    lines.append("[energy]")
    lines.append('T = "' + " + ".join(f"m{i}*(x{i}'^2 + y{i}'^2)/2"
                                      for i in range(1, links + 1)) + '"')
    lines.append('U = "' + " + ".join(f"m{i}*g*y{i}" for i in range(1, links + 1)) + '"')
    return "\n".join(lines) + "\n"


def without_units(text: str) -> str:
    """A model text with its units taken out, the same SI values as bare numbers.

    For tests that build variants of the bundled examples whose point is not units (the
    fuzzer's regressions): ``m1 = "2000 g"`` becomes ``m1 = 2.0``, ``x = { description =
    "d", unit = "m" }`` becomes ``x = "d"``, ``phi = "x2/l rad"`` becomes ``phi = "x2/l"``.
    """
    import re

    from resonant.model.units import parse_unit, split_value

    out = []
    section = ""
    for line in text.split("\n"):
        header = re.match(r"^\[+([^\]]+)\]+", line)
        section = header.group(1).strip() if header else section
        if section not in ("parameters", "coordinates", "outputs"):
            out.append(line)
            continue
        coordinate = re.match(r'^(\w+\s*=\s*)\{ description = ("[^"]*"), unit = "[^"]*" \}(.*)$',
                              line)
        if coordinate or section == "coordinates":
            out.append(coordinate.group(1) + coordinate.group(2) + coordinate.group(3)
                       if coordinate else line)
            continue
        valued = re.match(r'^(\w+\s*=\s*)"([^"]*)"(.*)$', line)
        if valued:
            expression, unit = split_value(valued.group(2))
            if unit is not None:
                factor = parse_unit(unit).to_si()
                try:
                    value = expression if factor == 1 and float(expression) == float(
                        expression) else repr(float(expression) * factor)
                except ValueError:
                    value = f'"{expression}"' if factor == 1 else f'"({expression})*{factor!r}"'
                line = valued.group(1) + value + valued.group(3)
        out.append(line)
    return "\n".join(out)


#: the modules that take longest (``pytest --durations``), started first: with two workers
#: taking whole modules (``--dist loadscope``) a long module started last would run alone
LONGEST_FIRST = ("test_docs_site.py", "test_condensed.py", "test_every_plot_option.py",
                 "test_no_machine_paths.py",
                 "test_nonlinear_special_points.py", "test_study_cluster.py",
                 "test_architecture.py", "test_benchmarks_smoke.py", "test_study_nonlinear.py",
                 "test_condensed_steps.py", "test_study.py")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The longest modules first (their tests in their own order), then the others as
    collected."""
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))
