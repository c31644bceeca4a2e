"""The ``resonant`` command line.

Exit status: 0 done, 2 invalid model, 3 analysis impossible (and 1 for an
internal error, which is a bug). Errors are one or a few lines on standard
error, never a traceback (set ``RESONANT_DEBUG=1`` to see one).
"""

from __future__ import annotations

import argparse
import importlib
import json
import math
import os
import sys
from collections.abc import Callable, Sequence
from typing import Any

from .errors import AnalysisError, ModelError, Problem, ResonantError

#: modules that add subcommands: each has ``register(subparsers, common)``
COMMAND_MODULES = ("resonant.cli_analyses", "resonant.cli_simulate", "resonant.cli_report")
#: default time budget of the symbolic derivation (``--timeout``), in seconds
DEFAULT_TIMEOUT = 120.0


def parse_settings(items: Sequence[str] | None) -> dict[str, str]:
    """``["k=200", "omega=2*pi"]`` -> ``{"k": "200", "omega": "2*pi"}`` (values stay text).

    Examples
    --------
    >>> parse_settings(["k=200", "w = 2*pi"])
    {'k': '200', 'w': '2*pi'}
    """
    out: dict[str, str] = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ModelError(Problem(f"--set expects NAME=VALUE, got '{item}'", "--set"))
        out[name.strip()] = value.strip()
    return out


def load_model(args: argparse.Namespace) -> Any:
    """Load ``args.model`` with the ``--set`` overrides applied."""
    from .model import load

    return load(args.model, overrides=parse_settings(getattr(args, "set", None)))


def emit_json(data: Any) -> None:
    try:
        text = json.dumps(data, indent=2, allow_nan=False)
    except ValueError:
        raise AnalysisError("the result holds NaN or infinity and cannot be written as "
                            "JSON; check the parameter values") from None
    sys.stdout.write(text + "\n")


def warn(messages: Sequence[str]) -> None:
    for message in messages:
        print(f"warning: {message}", file=sys.stderr)


def common_parser() -> argparse.ArgumentParser:
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("model", help="the model file (TOML)")
    common.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                        help="override a parameter (the value may be an expression)")
    common.add_argument("--timeout", type=_seconds, default=DEFAULT_TIMEOUT, metavar="SECONDS",
                        help="time budget of the symbolic derivation (default "
                             f"{DEFAULT_TIMEOUT:g}; 0 for none)")
    return common


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"expected a number of seconds >= 0, got '{text}'")
    return value


# -- solve / check ---------------------------------------------------------------------------

def run_solve(args: argparse.Namespace) -> int:
    from .model import time_budget

    model = load_model(args)
    eom = model.linearize()
    # the harmonic split of the signals and the compilation are symbolic work too
    with time_budget(getattr(args, "timeout", None), model.source):
        solution = eom.stationary()
    if args.json:
        emit_json(solution.to_dict())
        warn(solution.warnings)
    else:
        from .display import solution_text

        sys.stdout.write(solution_text(solution))
    return 0


def run_check(args: argparse.Namespace) -> int:
    from .model import time_budget

    model = load_model(args)
    eom = model.linearize()
    with time_budget(getattr(args, "timeout", None), model.source):
        eom.numeric()
    print(f"{args.model}: valid model, {len(model.coordinates)} coordinate(s): "
          f"{', '.join(model.coordinates)}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="resonant",
        description="Vibrations of discrete mechanical systems: linearized equations of "
                    "motion, natural frequencies, stationary solutions and more.")
    parser.add_argument("--version", action="version", version=f"resonant {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    common = common_parser()
    solve = sub.add_parser("solve", parents=[common], help="linearized EOM, natural "
                           "frequencies and the stationary solution")
    solve.add_argument("--json", action="store_true", help="print one JSON object")
    solve.set_defaults(run=run_solve)
    check = sub.add_parser("check", parents=[common], help="validate a model only")
    check.set_defaults(run=run_check)
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name != name:
                raise
            continue
        module.register(sub, common)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    run: Callable[[argparse.Namespace], int] | None = getattr(args, "run", None)
    if run is None:
        parser.print_help(sys.stderr)
        return 2
    from . import model as model_module

    saved_timeout = model_module.DERIVATION_TIMEOUT
    model_module.DERIVATION_TIMEOUT = getattr(args, "timeout", None) or None
    try:
        return run(args)
    except ResonantError as exc:
        label = "error" if exc.exit_code == 2 else "analysis impossible"
        print(f"{label}: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: say so in one line, never a traceback
        if os.environ.get("RESONANT_DEBUG"):
            raise
        print(f"internal error ({type(exc).__name__}: {exc}); this is a bug in resonant — "
              "rerun with RESONANT_DEBUG=1 for details", file=sys.stderr)
        return 1
    finally:
        model_module.DERIVATION_TIMEOUT = saved_timeout


def entry_point() -> None:  # pragma: no cover - console script
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    entry_point()
