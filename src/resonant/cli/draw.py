"""``resonant draw MODEL -o FILE``: the figure of a mechanism described by its parts."""

from __future__ import annotations

import argparse
import sys

import resonant.cli.common as common

from ..errors import ModelError, Problem
from ..views.drawing import draw_mechanism, drawing_format
from ..views.sketch import sketch


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    parser = subparsers.add_parser(
        "draw", parents=[parent],
        help="draw the mechanism at its reference state (.svg, .png or .pdf)",
        description="Draw a model described by its parts ([[body]], [[spring]], ...) at its "
                    "reference state, like the figure of a textbook exercise: bodies, pins, "
                    "springs, dampers, supports, forces, torques and the generalized "
                    "coordinates, to scale from the parameter values. The format follows "
                    "the file ending: .svg, .png or .pdf.")
    parser.add_argument("-o", "--output", required=True, metavar="FILE",
                        help="the output file: .svg, .png or .pdf")
    parser.set_defaults(run=run_draw)


def run_draw(args: argparse.Namespace) -> int:
    drawing_format(args.output)  # check the ending before any work
    path = common.writable_output(args.output, "the drawing")  # before any work
    model = common.load_model(args)
    data = sketch(model)  # ModelError (exit 2) for a model without parts
    try:
        draw_mechanism(data, path)
    except OSError as exc:
        raise ModelError(Problem(f"cannot write the drawing: {exc.strerror or exc}",
                                 str(args.output))) from None
    if data.undrawn:
        common.warn([f"coordinate {', '.join(data.undrawn)} moves no part of the drawing "
                     "(given in [energy] only): not drawn"])
    print(f"wrote {path}", file=sys.stderr)
    return 0
