"""Subcommands ``resonant modes`` and ``resonant sweep``.

``modes MODEL [--count K] [--plot FILE] [--json]`` prints natural frequencies,
mode shapes, damping and stability (:func:`resonant.modes.modes`).

``sweep MODEL --param P --from A --to B [--points N] [--log] [--method M]
[--only NAMES] [--plot FILE] [--csv FILE] [--progress] [--json]`` sweeps a
parameter (:func:`resonant.sweep.sweep`).
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

import resonant.cli.common as cli

from ..analyses.sweep import linspace
from ..errors import AnalysisError


def register(subparsers: Any, parent: argparse.ArgumentParser) -> None:
    modes = subparsers.add_parser(
        "modes", parents=[parent], help="natural frequencies, mode shapes, damping ratios")
    modes.add_argument("--count", type=int, metavar="K",
                       help="only the K lowest modes (sparse Lanczos for large matrix models)")
    modes.add_argument("--plot", metavar="FILE", help="draw the mode shapes (.png, .svg, .pdf)")
    modes.add_argument("--json", action="store_true", help="print one JSON object")
    modes.set_defaults(run=run_modes)

    sweep = subparsers.add_parser(
        "sweep", parents=[parent], help="amplitude and phase against a parameter "
        "(frequency response)")
    sweep.add_argument("--param", required=True, metavar="P",
                       help="the parameter to sweep (usually the excitation frequency)")
    sweep.add_argument("--from", dest="start", required=True, type=float, metavar="A")
    sweep.add_argument("--to", dest="stop", required=True, type=float, metavar="B")
    sweep.add_argument("--points", type=int, default=201, metavar="N",
                       help="number of values (default 201)")
    sweep.add_argument("--log", action="store_true", help="logarithmic spacing")
    sweep.add_argument("--method", default="auto",
                       choices=["auto", "dense", "banded", "sparse", "modal"],
                       help="solution method (default: chosen from the matrix structure)")
    sweep.add_argument("--only", metavar="NAMES",
                       help="comma-separated coordinates to report (default all; outputs "
                            "are always reported)")
    sweep.add_argument("--plot", metavar="FILE", help="draw amplitude and phase "
                       "(.png, .svg, .pdf)")
    sweep.add_argument("--csv", metavar="FILE", help="write the table as CSV")
    sweep.add_argument("--progress", action="store_true",
                       help="show a progress bar on standard error")
    sweep.add_argument("--json", action="store_true", help="print one JSON object")
    sweep.set_defaults(run=run_sweep)


def run_modes(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    result = model.linearize(deadline=deadline).modes(count=args.count, deadline=deadline)
    if args.plot:
        result.plot(args.plot)
    if args.json:
        cli.emit_json(result.to_dict())
    else:
        sys.stdout.write(result.summary())
    cli.warn(result.warnings)
    return 0


def run_sweep(args: argparse.Namespace) -> int:
    if not (math.isfinite(args.start) and math.isfinite(args.stop)):
        raise AnalysisError("--from and --to must be finite numbers")
    model = cli.load_model(args)
    values = linspace(args.start, args.stop, args.points, log=args.log)
    names = None
    if args.only:
        names = [n.strip() for n in args.only.split(",") if n.strip()]
    deadline = cli.deadline(args)
    result = model.linearize(deadline=deadline).sweep(
        args.param, values, method=args.method, names=names,
        progress=True if args.progress else None, log=args.log, deadline=deadline)
    if args.plot:
        result.plot(args.plot)
    if args.csv:
        try:
            result.to_csv(args.csv)
        except OSError as exc:
            raise AnalysisError(f"cannot write '{args.csv}': {exc.strerror or exc}") from None
    if args.json:
        cli.emit_json(result.to_dict())
    else:
        sys.stdout.write(result.summary())
    cli.warn(result.warnings)
    return 0
