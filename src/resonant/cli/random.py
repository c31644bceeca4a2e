"""``resonant random MODEL [--plot FILE] [--json] [--only NAMES]``: the response to the
random inputs of the model's ``[random]`` section (docs/random.md)."""

from __future__ import annotations

import argparse
import sys

import resonant.cli.common as cli

from ..analyses.random_response import plot_random, random_response, random_text
from ..system import linear_system


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    command = subparsers.add_parser(
        "random", parents=[parent],
        help="response spectral densities, RMS, 3-sigma and Rice's rates under the "
             "[random] inputs")
    command.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                         help="draw the spectral densities on log-log axes (.png, .svg, .pdf)")
    command.add_argument("--json", action="store_true", help="print one JSON object")
    command.add_argument("--only", metavar="NAMES",
                         help="comma-separated coordinates and outputs to report (default all)")
    command.add_argument("--tol", type=cli.number(0, 1, open_low=True, open_high=True),
                         default=None, metavar="T",
                         help="relative error of the mean squares (default: the section's "
                              "tolerance, else 1e-4)")
    command.set_defaults(run=run_random)


def run_random(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    names = cli.response_names(args.only, model)
    result = random_response(linear_system(model, deadline), deadline=deadline, names=names,
                             tolerance=args.tol)
    units = cli.shown_units(args, model)
    if args.plot:
        plot_random(result, args.plot, units=units)
    if args.json:
        cli.emit_json(result.to_dict())
    else:
        sys.stdout.write(random_text(result, warnings=False, units=units))
    cli.warn(result.warnings)
    return 0
