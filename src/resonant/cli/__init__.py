"""The ``resonant`` command line: parses arguments, calls the library, maps errors to exit codes.

Exit status: 0 done, 2 invalid model, 3 analysis impossible (and 1 for an
internal error, which is a bug). Errors are one or a few lines on standard
error, never a traceback (set ``RESONANT_DEBUG=1`` to see one).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence

from .. import __version__
from ..deadline import DeadlineExceeded
from ..errors import ResonantError
from . import analyses, common, report, simulate, solve

#: the modules that add subcommands: each has ``register(subparsers, parent)``
COMMANDS = (solve, analyses, simulate, report)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(
        prog="resonant",
        description="Vibrations of discrete mechanical systems: linearized equations of "
                    "motion, natural frequencies, stationary solutions and more.")
    parser.add_argument("--version", action="version", version=f"resonant {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    parent = common.common_parser()
    for module in COMMANDS:
        module.register(sub, parent)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    run: Callable[[argparse.Namespace], int] | None = getattr(args, "run", None)
    if run is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        return run(args)
    except ResonantError as exc:
        label = "error" if exc.exit_code == 2 else "analysis impossible"
        hint = " [--timeout SECONDS sets the limit]" if isinstance(exc, DeadlineExceeded) else ""
        print(f"{label}: {exc}{hint}", file=sys.stderr)
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


__all__ = ["main", "build_parser"]
