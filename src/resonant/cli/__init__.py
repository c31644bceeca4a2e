"""The ``resonant`` command line: parses arguments, calls the library, maps errors to exit codes.

Exit status: 0 done, 2 invalid model, 3 analysis impossible (and 1 for an
internal error, which is a bug; 141 when the reader of standard output went away).
Errors are one or a few lines on standard error, never a traceback (set
``RESONANT_DEBUG=1`` to see one).
"""

from __future__ import annotations

import argparse
import gc
import os
import re
import sys
import warnings
from collections.abc import Callable, Sequence
from typing import Any, NoReturn

from .. import __version__
from ..deadline import DeadlineExceeded
from ..errors import ResonantError, printable

# The imports below create about a million objects that live as long as the process
# (sympy, numpy): the cyclic garbage collector's passes over them while they are made
# find nothing to free and cost a tenth of a second, so it pauses meanwhile.
_COLLECTING = gc.isenabled()
gc.disable()
try:
    from . import common
finally:
    if _COLLECTING:
        gc.enable()

#: subcommand -> one line of help (for ``resonant --help``)
COMMANDS: dict[str, str] = {
    "solve": "linearized EOM, natural frequencies and the stationary solution",
    "check": "validate a model only",
    "modes": "natural frequencies, mode shapes, damping ratios",
    "sweep": "amplitude and phase against a parameter",
    "simulate": "time simulation, linear or full nonlinear",
    "report": "write the worked solution (.html, .md or .tex)",
    "energies": "T, U, D derived from the parts, per part",
    "draw": "draw a mechanism given by its parts (.svg, .png, .pdf)",
    "exercise": "exercise variants with solutions and answer key",
    "grade": "check a student's answers against the key",
    "study": "parameter study: Monte Carlo, grids, Sobol indices, on Dask",
    "explore": "write an interactive page of the model (.html)",
    "example": "list the bundled example models, or write one to a file",
    "random": "response spectral densities, RMS and Rice's rates under random inputs",
    "srs": "shock response spectrum of a pulse or a CSV history",
    "fatigue": "fatigue damage and life: spectral methods under [random], rainflow of a history",
    "frf": "frequency response functions from measured time histories (H1, H2, Hv)",
    "identify": "modes from measured FRFs (LSCF, stabilization chart, LSFD)",
    "correlate": "identified modes against the model's (MAC, frequency errors)",
    "update": "fit parameters to identified frequencies and mode shapes",
    "campbell": "a rotor's Campbell diagram: tracked modes, critical speeds, stability",
    "unbalance": "a rotor's orbits under its unbalances over the speed",
    "speed-map": "a rotor's undamped critical speeds against its bearings' stiffness",
    "import": "write a model naming the matrices of FE files (OP4, DMIG, .full, Abaqus)",
}

Register = Callable[[Any, argparse.ArgumentParser], None]


def command_registrar(command: str) -> Register:
    """The function that adds ``command``'s parser (and its runner) to the subparsers.

    This is the one place of the package that imports inside a function: only the
    module of the command being run is loaded, so that ``resonant solve`` does not
    pay for the report, exercise, nonlinear and study machinery at start-up.  Each
    import names its module, downward (the command line is the top layer), so
    editors, mypy and import-linter follow it like any other.

    Examples
    --------
    >>> command_registrar("solve").__module__
    'resonant.cli.solve'
    """
    match command:
        case "solve" | "check":
            from . import solve
            return solve.register
        case "modes" | "sweep":
            from . import analyses
            return analyses.register
        case "simulate":
            from . import simulate
            return simulate.register
        case "report":
            from . import report
            return report.register
        case "energies":
            from . import energies
            return energies.register
        case "draw":
            from . import draw
            return draw.register
        case "exercise" | "grade":
            from . import exercise
            return exercise.register
        case "study":
            from . import study
            return study.register
        case "explore":
            from . import explore
            return explore.register
        case "example":
            from . import example
            return example.register
        case "random":
            from . import random
            return random.register
        case "srs":
            from . import srs
            return srs.register
        case "fatigue":
            from . import fatigue
            return fatigue.register
        case "frf" | "identify" | "correlate" | "update":
            from . import testdata
            return testdata.register
        case "campbell" | "unbalance" | "speed-map":
            from . import campbell
            return campbell.register
        case "import":
            from . import fe_import
            return fe_import.register
    raise KeyError(command)


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The argument parser: the full one for the command in ``argv`` (every command's
    without one), one-line entries for the others.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    argparse.ArgumentParser
        The parser of ``resonant``'s command line.

    Examples
    --------
    >>> build_parser(["solve", "model.toml"]).prog
    'resonant'
    """
    parser = argparse.ArgumentParser(
        prog="resonant",
        description="Vibrations of discrete mechanical systems: linearized equations of "
                    "motion, natural frequencies, stationary solutions and more.")
    parser.add_argument("--version", action="version", version=f"resonant {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    parent = common.common_parser()
    chosen = next((a for a in (argv if argv is not None else sys.argv[1:])
                   if not a.startswith("-")), None)
    registrars = [command_registrar(chosen)] if chosen in COMMANDS else \
        list(dict.fromkeys(command_registrar(c) for c in COMMANDS))
    for register in registrars:
        register(sub, parent)
    for command, text in COMMANDS.items():
        if command not in sub.choices:
            sub.add_parser(command, help=text)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 done, 2 invalid input (the model, a file, an option),
        3 the analysis is impossible for this model.

    Examples
    --------
    >>> main(["check", "/nonexistent/model.toml"])  # the message goes to stderr
    2
    """
    parser = build_parser(argv)
    args = parser.parse_args(argv)
    run: Callable[[argparse.Namespace], int] | None = getattr(args, "run", None)
    if run is None:
        parser.print_help(sys.stderr)
        return 2
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            return _run(run, args)
        finally:
            for line in python_warnings(caught):
                print(f"warning: {line}", file=sys.stderr)


def program() -> NoReturn:
    """``resonant`` as a program (the console script and ``python -m resonant``):
    :func:`main`, then exit with its status.

    A command is a short-lived process.  The objects alive when it starts (the
    libraries) and when it ends are moved out of the cyclic garbage collector's
    reach (:func:`gc.freeze`): its passes over them during the run and the full
    collection at exit would free nothing (files are closed and workers stopped
    by the commands themselves) and cost a fifth of a second.

    Raises
    ------
    SystemExit
        Always, with the exit status of :func:`main`.

    Examples
    --------
    >>> import subprocess, sys
    >>> subprocess.run([sys.executable, "-m", "resonant", "check", "/nonexistent/m.toml"],
    ...                capture_output=True).returncode
    2
    """
    gc.freeze()
    status = main()
    gc.freeze()
    sys.exit(status)


def _run(run: Callable[[argparse.Namespace], int], args: argparse.Namespace) -> int:
    """Run one command, mapping its errors to exit statuses and one-line messages."""
    try:
        return run(args)
    except ResonantError as exc:
        label = "error" if exc.exit_code == 2 else "analysis impossible"
        hint = " [--timeout SECONDS sets the limit]" if isinstance(exc, DeadlineExceeded) else ""
        print(f"{label}: {_printable_lines(str(exc))}{hint}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return _reader_gone()
    except Exception as exc:  # a bug: say so in one line, never a traceback
        if os.environ.get("RESONANT_DEBUG"):
            raise
        print(f"internal error ({type(exc).__name__}: {printable(exc)}); this is a bug in "
              "resonant — rerun with RESONANT_DEBUG=1 for details", file=sys.stderr)
        return 1


def _reader_gone() -> int:
    """The reader of standard output went away (``resonant modes m.toml | head``): stop
    quietly with the status of a program ended by SIGPIPE, 141 (it was reported as an
    internal error, "a bug in resonant"); standard output goes to the null device so
    that flushing it at exit does not fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):   # (no file descriptor: nothing to flush)
        pass
    return 141


def _printable_lines(text: str) -> str:
    """An error message safe for the terminal: each line escaped, at most 2000 characters."""
    return "\n".join(printable(line, limit=2000) for line in text.split("\n"))


#: numpy's floating-point messages in words
_NUMPY_EVENTS = {"overflow": "numerical overflow", "invalid value": "invalid value (NaN)",
                 "divide by zero": "division by zero", "underflow": "numerical underflow"}


def python_warnings(caught: Sequence[warnings.WarningMessage]) -> list[str]:
    """Python warnings raised during a command, as resonant's own one-line warnings.

    Deduplicated, in words, never with the file, line or source text of the
    Python code that raised them (a library detail, useless to the user).

    Parameters
    ----------
    caught : sequence of warnings.WarningMessage
        The warnings recorded during the command.

    Returns
    -------
    list of str
        One line per distinct warning.

    Examples
    --------
    >>> w = warnings.WarningMessage(RuntimeWarning("overflow encountered in matmul"),
    ...                             RuntimeWarning, "/x/numpy/core.py", 3)
    >>> python_warnings([w, w])
    ['numerical overflow in matmul (numpy): results may be inaccurate']
    """
    lines: list[str] = []
    for item in caught:
        text = str(item.message).strip().splitlines()[0] if str(item.message).strip() else ""
        category = item.category.__name__
        match = re.match(r"(.*?) encountered in (\w+)", text)
        if match:
            event = _NUMPY_EVENTS.get(match.group(1).strip(), match.group(1).strip())
            line = f"{event} in {match.group(2)} (numpy): results may be inaccurate"
        elif category == "ComplexWarning":
            line = ("complex values were cast to real numbers, discarding the imaginary part "
                    "(numpy): results may be inaccurate")
        elif category in ("DeprecationWarning", "PendingDeprecationWarning", "FutureWarning"):
            continue  # about library versions, not about the model
        else:
            line = f"{printable(text, limit=200)} ({category})"
        if line not in lines:
            lines.append(line)
    return lines


__all__ = ["main", "program", "build_parser", "python_warnings"]
