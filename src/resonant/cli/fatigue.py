"""``resonant fatigue``: fatigue damage and life from an S-N curve (docs/random.md, Fatigue).

``resonant fatigue MODEL [--only NAMES] [--method M,...] [--duration T]``: the damage of
the model's stress responses under its ``[random]`` inputs over the exposure, by the
spectral methods (narrow-band, Dirlik, Tovo-Benasciutti), with the ``[fatigue]``
section's S-N curve; ``resonant fatigue [MODEL] --csv FILE``: rainflow counting and
Miner's damage of a stress history (time, value per line), with the section's curve or
``--k K --C C`` (or ``--C-range``).  ``--json`` prints one JSON object, ``--plot FILE``
draws the damage by method (or the cycles by range).
"""

from __future__ import annotations

import argparse
import math
import sys

import resonant.cli.common as cli

from ..analyses.fatigue import (
    METHODS,
    SNCurve,
    fatigue_text,
    rainflow_damage,
    rainflow_text,
    response_fatigue,
)
from ..analyses.random_response import random_response
from ..errors import ModelError, Problem, printable
from ..model import Model
from ..model.load_spec import STRESS
from ..model.time_series import read_time_series
from ..system.build import linear_system


def _methods(text: str) -> list[str]:
    """``--method``: comma-separated spectral methods, or ``all``."""
    names = [m.strip() for m in text.split(",") if m.strip()]
    if text.strip() == "all":
        return list(METHODS)
    unknown = [m for m in names if m not in METHODS]
    if not names or unknown:
        raise argparse.ArgumentTypeError(
            f"expected some of {', '.join(METHODS)} (comma-separated) or all, got "
            f"'{printable(text, 40)}'")
    return list(dict.fromkeys(names))


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    command = subparsers.add_parser(
        "fatigue", parents=[cli.option_parser()],
        help="fatigue damage and life: spectral methods under [random], or rainflow of a "
             "CSV history")
    command.add_argument("model", nargs="?", default=None,
                         help="a model file with a [fatigue] section (and [random], unless "
                              "--csv)")
    command.add_argument("--csv", metavar="FILE",
                         help="a stress history (time in s, value per line): rainflow "
                              "counting and Miner's rule instead of the spectral methods")
    command.add_argument("--only", metavar="NAMES",
                         help="comma-separated stress outputs (default: every output)")
    command.add_argument("--method", type=_methods, default=list(METHODS), metavar="M",
                         help="spectral methods, comma-separated: narrowband, dirlik, "
                              "tovo-benasciutti or all (default all)")
    command.add_argument("--duration", type=cli.number(0, open_low=True), metavar="T",
                         help="the exposure (s; default: the [fatigue] section's)")
    command.add_argument("--k", type=cli.number(0, open_low=True), metavar="K",
                         help="the S-N curve's inverse slope (instead of [fatigue]'s)")
    curve = command.add_mutually_exclusive_group()
    curve.add_argument("--C", type=cli.number(0, open_low=True), metavar="C",
                       help="N S^k = C with S the stress amplitude (SI: Pa)")
    curve.add_argument("--C-range", dest="C_range", type=cli.number(0, open_low=True),
                       metavar="C", help="N S^k = C with S the stress range")
    command.add_argument("--tol", type=cli.number(0, 1, open_low=True, open_high=True),
                         default=None, metavar="T",
                         help="relative error of the random response's mean squares")
    command.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                         help="draw the damage by method (or the cycles by range)")
    command.add_argument("--json", action="store_true", help="print one JSON object")
    command.set_defaults(run=run_fatigue)


def _curve(args: argparse.Namespace, model: Model | None) -> tuple[SNCurve, float | None,
                                                                    str]:
    """The S-N curve, the exposure (s, None where none is given) and the section's method:
    from the options where given, else from the model's ``[fatigue]`` section."""
    spec = model.fatigue_section if model is not None else None
    given = args.C is not None or args.C_range is not None
    if args.k is not None or given:
        if args.k is None or not given:
            raise ModelError(Problem("--k and one of --C, --C-range go together (the S-N "
                                     "curve N S^k = C)", "--k" if args.k is None else "--C"))
        sn = SNCurve(args.C, args.k) if args.C is not None else \
            SNCurve.from_range(args.C_range, args.k)
    elif spec is None:
        source = model.source if model is not None else "fatigue"
        raise ModelError(Problem("no S-N curve: add a [fatigue] section (k, C, duration; "
                                 "docs/random.md) or give --k with --C", source, "fatigue"))
    else:
        sn = SNCurve(spec.C, spec.k)
    if not (math.isfinite(sn.C) and sn.C > 0):
        raise ModelError(Problem(f"the S-N curve's C = {sn.C:g} is not a positive finite "
                                 "number", "--C-range"))
    duration = args.duration if args.duration is not None else \
        (spec.duration if spec is not None else None)
    return sn, duration, spec.method if spec is not None else "dirlik"


def _stresses(model: Model) -> list[str]:
    """The responses whose fatigue is asked for by default: the outputs that are stresses
    where the model's units say so, else every output (else every coordinate)."""
    if model.units is not None:
        stresses = [n for n in model.outputs if model.units.dimensions.get(n) == STRESS]
        if stresses:
            return stresses
    return list(model.outputs or model.coordinates)


def _spectral(args: argparse.Namespace, model: Model) -> int:
    """The damage of the stress responses under the [random] inputs."""
    deadline = cli.deadline(args)
    sn, duration, method = _curve(args, model)
    if duration is None:
        raise ModelError(Problem("the exposure is missing: give --duration (s) or the "
                                 "[fatigue] section's duration", model.source, "fatigue",
                                 "duration"))
    names = cli.response_names(args.only, model) or _stresses(model)
    response = random_response(linear_system(model, deadline), deadline=deadline,
                               names=names, tolerance=args.tol)
    result = response_fatigue(response, sn, duration, names=names, methods=args.method,
                              method=method)
    if args.plot:
        result.plot(args.plot)
    if args.json:
        cli.emit_json(result.to_dict())
    else:
        sys.stdout.write(fatigue_text(result, warnings=False, units=cli.shown_units(args, model)))
    cli.warn(result.warnings)
    return 0


def _rainflow(args: argparse.Namespace, model: Model | None) -> int:
    """Rainflow counting and Miner's damage of the CSV history."""
    sn, duration, _ = _curve(args, model)
    step, values = read_time_series(args.csv)
    length = step * (len(values) - 1)
    result = rainflow_damage(values, sn)
    # the history is in Pa where units are known (the model's or --units), as C is
    units = cli.shown_units(args, model)
    unit = units.of("Pa") if units is not None else ""
    if args.plot:
        result.plot(args.plot, unit=unit)
    repeats = duration / length if duration is not None else 1.0
    if args.json:
        life = result.life(length)
        cli.emit_json({**result.to_dict(), "history_s": length,
                       "life_s": life if math.isfinite(life) else None,
                       "exposure_s": length * repeats, "exposure_damage": result.damage * repeats})
    else:
        text = rainflow_text(result, unit, duration=length, warnings=False)
        if duration is not None:
            text += (f"  over the exposure of {duration:.4g} s (the history repeated "
                     f"{repeats:.4g} times): damage {result.damage * repeats:.4g}\n")
        sys.stdout.write(text)
    cli.warn(result.warnings)
    return 0


def run_fatigue(args: argparse.Namespace) -> int:
    if args.model is None and args.csv is None:
        raise ModelError(Problem("give a model file with [random] and [fatigue] sections, "
                                 "or a stress history with --csv FILE", "fatigue"))
    model = cli.load_model(args) if args.model is not None else None
    if args.csv is not None:
        if args.only is not None:
            raise ModelError(Problem("--only names responses of the model's random response; "
                                     "a --csv history is one stress", "--only"))
        return _rainflow(args, model)
    assert model is not None
    return _spectral(args, model)
