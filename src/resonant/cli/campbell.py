"""``resonant campbell MODEL [--from S] [--to S] [--points N] [--modes K] [--orders R,...]
[--plot FILE] [--json]``: a rotor's Campbell diagram, critical speeds and stability
threshold; ``resonant unbalance MODEL [--from S] [--to S] [--points N] [--plot FILE]
[--json]``: its stations' orbits under the ``[[unbalance]]``; ``resonant speed-map MODEL
[--stiffness FROM:TO:N] [--modes K] [--orders R,...] [--damped] [--plot FILE] [--json]``:
the undamped (or damped) critical speed map against the bearings' stiffness
(docs/rotors.md)."""

from __future__ import annotations

import argparse
import sys

import numpy as np

import resonant.cli.common as cli

from ..analyses.campbell import campbell
from ..analyses.rotor_map import MAP_MODES, MAP_STIFFNESS, critical_speed_map
from ..analyses.unbalance import unbalance_response
from ..errors import ModelError
from ..model.campbell_spec import parse_speed
from ..system import linear_system


def speed_value(text: str) -> float:
    """A speed on the command line: a number (rad/s) or ``"3000 rpm"``."""
    problems: list = []
    value = parse_speed(text, "", "campbell", "speed", problems)
    if value is None:
        raise argparse.ArgumentTypeError(problems[0].message if problems else "not a speed")
    return value


def orders_value(text: str) -> tuple[float, ...]:
    """Comma-separated positive excitation orders (``1,2``)."""
    try:
        orders = tuple(float(part) for part in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a list of numbers: {text!r}") from None
    if not orders or not all(np.isfinite(r) and r > 0 for r in orders):
        raise argparse.ArgumentTypeError("the orders must be positive numbers")
    return orders


def _speed_options(command: argparse.ArgumentParser) -> None:
    command.add_argument("--from", dest="start", type=speed_value, metavar="SPEED",
                         help="lowest speed (rad/s, or with a unit: '0 rpm'; default "
                              "[campbell] from)")
    command.add_argument("--to", dest="stop", type=speed_value, metavar="SPEED",
                         help="highest speed (default [campbell] to)")
    command.add_argument("--points", type=cli.integer(2, 100_000), metavar="N",
                         help="speeds of the grid (default [campbell] points, else 41)")
    command.add_argument("--speed", metavar="NAME",
                         help="the speed parameter (default [matrices] speed)")
    command.add_argument("--json", action="store_true", help="print one JSON object")


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    command = subparsers.add_parser(
        "campbell", parents=[parent],
        help="a rotor's modes tracked over its speed, critical speeds, stability threshold")
    _speed_options(command)
    command.add_argument("--modes", type=cli.integer(1, 10_000), metavar="K",
                         help="branches followed (default [campbell] modes, else 6)")
    command.add_argument("--orders", type=orders_value, metavar="R,...",
                         help="excitation orders of the critical speeds (default 1)")
    command.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                         help="draw the Campbell diagram and the log decrements")
    command.set_defaults(run=run_campbell)
    command = subparsers.add_parser(
        "unbalance", parents=[parent],
        help="a rotor's orbits under its [[unbalance]] over the speed (0-pk and pk-pk)")
    _speed_options(command)
    command.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                         help="draw the major semi-axes and the phase against speed")
    command.set_defaults(run=run_unbalance)
    command = subparsers.add_parser(
        "speed-map", parents=[parent],
        help="a [rotor]'s undamped critical speeds against its bearings' stiffness")
    low, high, count = MAP_STIFFNESS
    command.add_argument("--stiffness", type=stiffness_value, default=MAP_STIFFNESS,
                         metavar="FROM:TO:N",
                         help="bearing stiffness values, N/m, spaced logarithmically "
                              f"(default {_power(low)}:{_power(high)}:{count})")
    command.add_argument("--modes", type=cli.integer(1, 1000), default=MAP_MODES, metavar="K",
                         help=f"critical speeds per order (default {MAP_MODES})")
    command.add_argument("--orders", type=orders_value, metavar="R,...", default=(1.0,),
                         help="excitation orders (default 1)")
    command.add_argument("--damped", action="store_true",
                         help="keep the bearings' damping and cross coupling: the damped "
                              "critical speeds, on the [campbell] speed range")
    command.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                         help="draw the map (log-log)")
    command.add_argument("--json", action="store_true", help="print one JSON object")
    command.set_defaults(run=run_speed_map)


def _power(value: float) -> str:
    """A power of ten as 1e5."""
    return f"{value:.0e}".replace("e+0", "e").replace("e+", "e")


def stiffness_value(text: str) -> tuple[float, float, int]:
    """``FROM:TO:N``: N stiffness values (N/m) from FROM to TO, logarithmically spaced."""
    parts = text.split(":")
    try:
        low, high, count = float(parts[0]), float(parts[1]), int(parts[2])
    except (ValueError, IndexError):
        raise argparse.ArgumentTypeError(f"not FROM:TO:N: {text!r}") from None
    if len(parts) != 3 or not (0 < low < high < float("inf")) or not 1 < count <= 10_000:
        raise argparse.ArgumentTypeError("FROM:TO:N needs 0 < FROM < TO and 2 to 10000 "
                                         "values")
    return low, high, count


def _speeds(args: argparse.Namespace, model: object) -> np.ndarray:
    """The speeds of the options, else of the [campbell] section."""
    spec = getattr(model, "campbell_section", None)
    start = args.start if args.start is not None else (spec.start if spec else 0.0)
    stop = args.stop if args.stop is not None else (spec.stop if spec else None)
    if stop is None:
        raise ModelError("no speed range: give --to (and --from), or a [campbell] section")
    points = args.points or (spec.points if spec else 41)
    if stop <= start:
        raise ModelError(f"the highest speed ({stop:g} rad/s) must be above the lowest "
                         f"({start:g} rad/s)")
    return np.linspace(start, stop, points)


def run_unbalance(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    result = unbalance_response(linear_system(model, deadline), _speeds(args, model),
                                speed=args.speed, deadline=deadline)
    if args.plot:
        result.plot(args.plot)
    if args.json:
        cli.emit_json(result.to_dict())
        cli.warn(result.warnings)
    else:
        # the summary ends with the warnings
        sys.stdout.write(result.summary(cli.shown_units(args, model)))
    return 0


def run_campbell(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    result = campbell(linear_system(model, deadline), _speeds(args, model),
                      modes=args.modes, orders=args.orders, speed=args.speed,
                      deadline=deadline)
    if args.plot:
        result.plot(args.plot)
    if args.json:
        cli.emit_json(result.to_dict())
        cli.warn(result.warnings)
    else:
        # the summary ends with the warnings
        sys.stdout.write(result.summary(cli.shown_units(args, model)))
    return 0


def run_speed_map(args: argparse.Namespace) -> int:
    model = cli.load_model(args)
    low, high, count = args.stiffness
    result = critical_speed_map(linear_system(model, cli.deadline(args)),
                                np.geomspace(low, high, count), modes=args.modes,
                                orders=args.orders, damped=args.damped,
                                deadline=cli.deadline(args))
    if args.plot:
        result.plot(args.plot)
    if args.json:
        cli.emit_json(result.to_dict())
    else:
        sys.stdout.write(result.summary())
    return 0
