"""What every subcommand shares: the common options, loading, JSON and warnings output."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path

from ..deadline import Deadline
from ..errors import AnalysisError, ModelError, Problem, name_list, printable
from ..model import Model, load
from ..model.units import Unit, UnitError, display_units
from ..model.units_display import (
    ResultUnits,
    frequency_shown,
    result_units,
    with_display,
)

#: default time limit of a command (``--timeout``), in seconds
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


def deadline(args: argparse.Namespace) -> Deadline:
    """The deadline of this run (``--timeout``), made once per command."""
    if not hasattr(args, "_deadline"):
        args._deadline = Deadline(getattr(args, "timeout", None) or None, args.model)
    return args._deadline


def load_model(args: argparse.Namespace) -> Model:
    """Load ``args.model`` with the ``--set`` overrides applied.

    A model with units says once what it could not check (and where a value in Hz
    is used as an angular frequency), on standard error.
    """
    model = load(args.model, overrides=parse_settings(getattr(args, "set", None)),
                 allow_paths=getattr(args, "allow_path", None) or ())
    if model.units is not None:
        warn(model.units.notes)
    return with_display(model, chosen_units(args))


def chosen_units(args: argparse.Namespace) -> dict[str, Unit]:
    """The display units of ``--units`` (quantity -> unit; empty without the option),
    checked: exit 2 naming the option for a unit that is none of a displayed quantity's.

    Examples
    --------
    >>> sorted(chosen_units(argparse.Namespace(units="mm,Hz")))
    ['frequency', 'length']
    """
    chosen = getattr(args, "units", None)
    if not chosen:
        return {}
    try:
        return display_units(t for t in chosen.split(",") if t.strip())
    except UnitError as exc:
        raise ModelError(Problem(f"{exc} (--units takes units of length, angle, "
                                 "frequency, acceleration, ... like mm,deg,Hz or g)",
                                 "--units")) from None


def shown_units(args: argparse.Namespace, model: Model | None = None) -> ResultUnits | None:
    """The units a command shows its numbers in: the model's (with ``--units``, as
    :func:`load_model` applied them), or for a command without a model the ``--units``
    alone (None when neither gives any).

    Examples
    --------
    >>> shown_units(argparse.Namespace(units="g")).of("m/s^2").text
    'g'
    """
    if model is not None:
        return result_units(model)
    display = chosen_units(args)
    return ResultUnits(display=display, frequency=frequency_shown(display)) \
        if display else None


def response_names(text: str | None, model: Model, *, outputs: bool = True,
                   option: str = "--only") -> list[str] | None:
    """The comma-separated coordinates (and outputs) of ``option`` (None when not given),
    each checked against the model before any work: exit 2 naming the file and option.

    Examples
    --------
    >>> from resonant.model import loads
    >>> model = loads('[matrices]\\nM = [[1]]\\nK = [[4]]\\n')
    >>> response_names(" q1, ", model)
    ['q1']
    """
    if text is None:
        return None
    names = [n.strip() for n in text.split(",") if n.strip()]
    known = [*model.coordinates, *(model.outputs if outputs else ())]
    what = "coordinate or output" if outputs else "coordinate"
    if not names:
        plural = "coordinates or outputs" if outputs else "coordinates"
        raise ModelError(Problem(f"give one or more {plural}, separated by commas (of "
                                 f"{name_list(known, 20)})", model.source, key=option))
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ModelError(Problem(f"unknown {what} '{printable(unknown[0], 40)}'; known: "
                                 f"{name_list(known, 20)}", model.source, key=option))
    return names


def writable_output(name: str, what: str) -> Path:
    """The output file ``name``, checked once before any work: its folder exists and is
    writable, and it is not a folder itself.

    Parameters
    ----------
    name : str
        The path given with ``-o``.
    what : str
        What is written ("the report", "the page" ...), for the message.

    Returns
    -------
    Path

    Raises
    ------
    ModelError
        Naming the file (exit status 2).

    Examples
    --------
    >>> writable_output("/nope/r.html", "the page")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    resonant.errors.ModelError: /nope/r.html: cannot write the page: the folder '/nope' ...
    """
    path = Path(name)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        problem = f"the folder '{folder}' does not exist"
    elif not os.access(folder, os.W_OK | os.X_OK):
        problem = f"the folder '{folder}' is not writable"
    elif path.is_dir():
        problem = "it is a folder"
    elif path.exists() and not path.is_file():
        problem = "it exists and is not a regular file"
    else:
        return path
    raise ModelError(Problem(f"cannot write {what}: {problem}", name))


#: the files a plot is written to
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


def plot_file(text: str) -> str:
    """The ``--plot FILE`` of a command, checked when the arguments are read (exit 2 before
    any work): a .png, .svg or .pdf file in a writable folder.

    Examples
    --------
    >>> plot_file("fr.png")
    'fr.png'
    """
    if Path(text).suffix.lower() not in PLOT_SUFFIXES:
        raise argparse.ArgumentTypeError("--plot needs a file ending in .png, .svg or .pdf, "
                                         f"got '{printable(text, 80)}'")
    try:
        writable_output(text, "the plot")
    except ModelError as exc:
        raise argparse.ArgumentTypeError(str(exc.problems[0].message)) from None
    return text


def emit_json(data: Mapping[str, object]) -> None:
    try:
        text = json.dumps(data, indent=2, allow_nan=False)
    except ValueError:
        raise AnalysisError("the result holds NaN or infinity and cannot be written as "
                            "JSON; check the parameter values") from None
    sys.stdout.write(text + "\n")


def emit_json_streamed(head: Mapping[str, object],
                       streamed: Mapping[str, Iterable[Iterable[tuple[str, object]]]]) -> None:
    """Print one JSON object whose large members are written piece by piece.

    ``head`` gives the keys in order and the small values (written as :func:`emit_json`
    writes them); a key of ``streamed`` is an object written from its chunks of (name,
    value) items, each item on one line, so that the memory held is one chunk's and the
    output grows with the numbers asked for, not with an indentation per number.

    Raises
    ------
    AnalysisError
        For NaN or infinity (found before anything of that chunk is written).

    Examples
    --------
    >>> emit_json_streamed({"a": 1, "b": None}, {"b": [[("x", [1.0, 2.0])]]})
    {
      "a": 1,
      "b": {
        "x": [1.0, 2.0]
      }
    }
    """
    def dumps(value: object, indent: int | None) -> str:
        try:
            return json.dumps(value, indent=indent, allow_nan=False)
        except ValueError:
            raise AnalysisError("the result holds NaN or infinity and cannot be written as "
                                "JSON; check the parameter values") from None

    write = sys.stdout.write
    write("{")
    for k, key in enumerate(head):
        write(("," if k else "") + f"\n  {json.dumps(key)}: ")
        if key not in streamed:
            value = head[key]   # a list (of numbers: a frequency grid) on one line
            write(dumps(value, None if isinstance(value, list) else 2).replace("\n", "\n  "))
            continue
        first = True
        write("{")
        for chunk in streamed[key]:
            lines = [f"\n    {json.dumps(name)}: {dumps(value, None)}" for name, value in chunk]
            if lines:
                write(("" if first else ",") + ",".join(lines))
                first = False
        write("\n  }" if not first else "}")
    write("\n}\n")


def warn(messages: Sequence[str]) -> None:
    for message in messages:
        print(f"warning: {printable(message, limit=2000)}", file=sys.stderr)


def common_parser() -> argparse.ArgumentParser:
    """The options every subcommand of a model file takes: the model and
    :func:`option_parser`'s."""
    common = argparse.ArgumentParser(add_help=False, parents=[option_parser()])
    common.add_argument("model", help="the model file (TOML)")
    return common


def option_parser() -> argparse.ArgumentParser:
    """The options every subcommand takes (``--set``, ``--timeout``, ``--units``,
    ``--allow-path``), for a command whose model file is optional."""
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                        help="override a parameter (the value may be an expression)")
    common.add_argument("--timeout", type=_seconds, default=DEFAULT_TIMEOUT, metavar="SECONDS",
                        help="time limit of the whole command (default "
                             f"{DEFAULT_TIMEOUT:g}; 0 for none)")
    common.add_argument("--units", metavar="UNITS", default=None,
                        help="units of the text output, e.g. mm,deg,Hz (one per quantity: "
                             "length, angle, frequency, mass, force, ...; JSON stays SI)")
    common.add_argument("--allow-path", action="append", metavar="DIR", default=[],
                        help="also read [matrices] files from DIR (repeatable; by default "
                             "only files inside the model file's folder are read)")
    return common


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"expected a number of seconds >= 0, got '{text}'")
    return value


# -- option values: each checked where it is parsed, so that its message names the option
# (argparse prefixes "argument --points: ") and the exit status is 2 (invalid input)

def integer(low: int, high: int) -> Callable[[str], int]:
    """An argparse type: a whole number in [low, high].

    Examples
    --------
    >>> integer(1, 200)("7")
    7
    >>> integer(1, 200)("0")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: expected a whole number from 1 to 200, got '0'
    """
    def parse(text: str) -> int:
        try:
            value = int(text.strip(), 10)
        except ValueError:
            value = None
        if value is None or not low <= value <= high:
            raise argparse.ArgumentTypeError(
                f"expected a whole number from {low} to {high}, got '{printable(text, 40)}'")
        return value
    return parse


def number(low: float = -math.inf, high: float = math.inf, *, open_low: bool = False,
           open_high: bool = False) -> Callable[[str], float]:
    """An argparse type: a finite number in the interval from ``low`` to ``high``
    (ends excluded where ``open_low``/``open_high``).

    Examples
    --------
    >>> number(0, 1, open_low=True, open_high=True)("1e-6")
    1e-06
    >>> number(0, 1, open_low=True, open_high=True)("nan")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: expected a number > 0 and < 1, got 'nan'
    """
    bounds = [f"{'>' if open_low else '>='} {low:g}"] if math.isfinite(low) else []
    bounds += [f"{'<' if open_high else '<='} {high:g}"] if math.isfinite(high) else []
    wanted = "a finite number" + (" " + " and ".join(bounds) if bounds else "")

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        inside = math.isfinite(value) and (value > low if open_low else value >= low) and \
            (value < high if open_high else value <= high)
        if not inside:
            raise argparse.ArgumentTypeError(
                f"expected {wanted.replace('a finite number ', 'a number ')}, "
                f"got '{printable(text, 40)}'")
        return value
    return parse


