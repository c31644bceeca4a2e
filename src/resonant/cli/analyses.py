"""Subcommands ``resonant modes`` and ``resonant sweep``.

``modes MODEL [--count K] [--plot FILE] [--json]`` prints natural frequencies,
mode shapes, damping and stability (:func:`resonant.analyses.modes.modes`).

``sweep MODEL --param P --from A --to B [--points N] [--log] [--method M] [--tol T]
[--only NAMES] [--plot FILE] [--csv FILE] [--progress] [--json]`` sweeps a
parameter (:func:`resonant.analyses.sweep.sweep`).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from typing import Any

import resonant.cli.common as cli

from ..analyses.backbone import Backbones, backbone, plot_backbones
from ..analyses.harmonic_balance import nonlinear_sweep
from ..analyses.modes import ModalAnalysis, modes, modes_text, plot_modes
from ..analyses.nonlinear_response import NonlinearResponse, nonlinear_text, plot_nonlinear_response
from ..analyses.sweep import (
    MAX_SWEEP_POINTS,
    FrequencyResponse,
    linspace,
    plot_frequency_response,
    sweep,
    sweep_text,
)
from ..deadline import Deadline
from ..errors import AnalysisError
from ..model import Model
from ..model.options import MAX_GIVEN_HARMONICS, SWEEP_METHODS, BalanceOptions, SweepOptions
from ..model.units_display import ResultUnits, result_units
from ..system import linear_system, nonlinear_system

#: the most harmonics a nonlinear analysis takes (the analyses' own limit)
MAX_HARMONICS_OPTION = MAX_GIVEN_HARMONICS


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    modes = subparsers.add_parser(
        "modes", parents=[parent], help="natural frequencies, mode shapes, damping ratios")
    modes.add_argument("--count", type=cli.integer(1, 10**9), metavar="K",
                       help="only the K lowest modes (sparse Lanczos for large matrix models)")
    modes.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                      help="draw the mode shapes (.png, .svg, .pdf)")
    modes.add_argument("--json", action="store_true", help="print one JSON object")
    modes.add_argument("--nonlinear", action="store_true",
                       help="backbone curves: the free-vibration frequency of each mode of the "
                            "full undamped equations against the amplitude (harmonic balance)")
    modes.add_argument("--amplitude", type=cli.number(0, open_low=True), metavar="A",
                       help="with --nonlinear: the largest amplitude (default: until the "
                            "frequency has changed by 20 %%)")
    modes.add_argument("--harmonics", type=cli.integer(1, MAX_HARMONICS_OPTION), metavar="H",
                       help="with --nonlinear: number of harmonics (default 5)")
    modes.add_argument("--points", type=cli.integer(2, MAX_SWEEP_POINTS), default=41, metavar="N",
                       help="with --nonlinear: amplitudes per curve (default 41)")
    modes.set_defaults(run=run_modes)

    sweep = subparsers.add_parser(
        "sweep", parents=[parent], help="amplitude and phase against a parameter "
        "(frequency response)")
    sweep.add_argument("--param", required=True, metavar="P",
                       help="the parameter to sweep (usually the excitation frequency)")
    sweep.add_argument("--from", dest="start", required=True, type=cli.number(), metavar="A")
    sweep.add_argument("--to", dest="stop", required=True, type=cli.number(), metavar="B")
    sweep.add_argument("--points", type=cli.integer(1, MAX_SWEEP_POINTS), default=201, metavar="N",
                       help="number of values (default 201)")
    sweep.add_argument("--log", action="store_true", help="logarithmic spacing")
    sweep.add_argument("--method", default="auto",
                       choices=SWEEP_METHODS,
                       help="solution method (default auto: a reduced-order model for large "
                            "models when its estimated error is below --tol, else the "
                            "cheapest exact method; direct: the cheapest exact method)")
    sweep.add_argument("--tol", type=cli.number(0, 1, open_low=True, open_high=True),
                       default=None, metavar="T",
                       help="relative tolerance of a reduced-order model (default 1e-6)")
    sweep.add_argument("--only", metavar="NAMES",
                       help="comma-separated coordinates to report (default all; outputs "
                            "are always reported)")
    sweep.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                      help="draw amplitude and phase "
                       "(.png, .svg, .pdf)")
    sweep.add_argument("--csv", metavar="FILE", help="write the table as CSV")
    sweep.add_argument("--progress", action="store_true",
                       help="show a progress bar on standard error")
    sweep.add_argument("--json", action="store_true", help="print one JSON object")
    sweep.add_argument("--nonlinear", action="store_true",
                       help="periodic steady state of the full equations (harmonic balance, "
                            "continuation through folds, stability)")
    sweep.add_argument("--harmonics", type=cli.integer(1, MAX_HARMONICS_OPTION), metavar="H",
                       help="with --nonlinear: number of harmonics (default: chosen from "
                            "their decay, at least 7)")
    sweep.set_defaults(run=run_sweep)


def run_modes(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    if args.nonlinear:
        return _run_backbones(args, model, deadline)
    if args.amplitude is not None or args.harmonics is not None:
        raise AnalysisError("--amplitude and --harmonics need --nonlinear")
    result = modes(linear_system(model, deadline), args.count, deadline)
    units = result_units(model)
    return _emit(args, result, lambda: modes_text(result, units),
                 lambda path: plot_modes(result, path), units)


def _run_backbones(args: argparse.Namespace, model: Model, deadline: Deadline) -> int:
    """``modes --nonlinear``: :func:`resonant.analyses.backbone.backbone`."""
    if args.count is not None:
        raise AnalysisError("--count applies to the linear modes, not to --nonlinear")
    result = backbone(nonlinear_system(model, deadline), args.amplitude,
                      harmonics=args.harmonics, points=args.points, deadline=deadline)
    units = cli.shown_units(args, model)
    return _emit(args, result, lambda: result.summary(units),
                 lambda path: plot_backbones(result, path))


def run_sweep(args: argparse.Namespace) -> int:
    if not (math.isfinite(args.start) and math.isfinite(args.stop)):
        raise AnalysisError("--from and --to must be finite numbers")
    model = cli.load_model(args)
    if args.nonlinear:
        return _run_nonlinear(args, model)
    if args.harmonics is not None:
        raise AnalysisError("--harmonics needs --nonlinear")
    values = linspace(args.start, args.stop, args.points, log=args.log)
    names = cli.response_names(args.only, model, outputs=False)
    deadline = cli.deadline(args)
    options = SweepOptions(method=args.method, names=None if names is None else tuple(names),
                           tol=args.tol, log=args.log,
                           progress=True if args.progress else None)
    result = sweep(linear_system(model, deadline), args.param, values, options=options,
                   deadline=deadline)
    units = result_units(model)
    return _emit(args, result, lambda: sweep_text(result, units),
                 lambda path: plot_frequency_response(result, path, units=units), units)


def _run_nonlinear(args: argparse.Namespace, model: Model) -> int:
    """``sweep --nonlinear``: :func:`resonant.analyses.harmonic_balance.nonlinear_sweep`, which
    balances the way the model calls for (in full, or condensed onto ``[[nonlinear]]``
    elements)."""
    if args.log or args.method != "auto":
        raise AnalysisError("--log and --method apply to the linear sweep, not to --nonlinear")
    deadline = cli.deadline(args)
    observe = [n.strip() for n in args.only.split(",") if n.strip()] if args.only else None
    options = BalanceOptions(harmonics=args.harmonics, points=args.points,
                             observe=None if observe is None else tuple(observe), tol=args.tol)
    result = nonlinear_sweep(nonlinear_system(linear_system(model, deadline), deadline),
                             args.param, args.start, args.stop, options=options,
                             deadline=deadline)
    units = result_units(model)
    return _emit(args, result, lambda: nonlinear_text(result, units),
                 lambda path: plot_nonlinear_response(result, path, units=units))


#: the results this module writes
Emitted = ModalAnalysis | Backbones | FrequencyResponse | NonlinearResponse


def _emit(args: argparse.Namespace, result: Emitted, text: Callable[[], str],
          plot: Callable[[str], Any], units: ResultUnits | None = None) -> int:
    """Plot, CSV (sweeps), JSON or text of a result, then its warnings.

    ``text`` and ``plot`` are the result's views; ``units`` (a model with units) adds
    the JSON's ``"units"`` map (the numbers stay SI).
    """
    if args.plot:
        plot(args.plot)
    if getattr(args, "csv", None) and isinstance(result, FrequencyResponse | NonlinearResponse):
        try:
            result.to_csv(args.csv)
        except OSError as exc:
            raise AnalysisError(f"cannot write '{args.csv}': {exc.strerror or exc}") from None
    if args.json:
        data = result.to_dict()
        if units is not None:
            data["units"] = units.to_json()
        cli.emit_json(data)
    else:
        sys.stdout.write(text())
    cli.warn(result.warnings)
    return 0
