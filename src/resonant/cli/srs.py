"""``resonant srs``: the shock response spectrum of a classical pulse or a CSV history.

``resonant srs --pulse half-sine --amplitude 100 --duration 0.011 [--step DT]``,
``resonant srs --csv FILE`` or ``resonant srs MODEL [--output NAME]`` (the model's
``[shock]`` pulse, or the history of one of its outputs under it), with
``--from F1 --to F2 --points N`` (Hz, log spaced),
``--Q Q`` or ``--damping ZETA``, ``--quantity``, ``--plot FILE``, ``--json``
(docs/random.md, section Shock).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

import resonant.cli.common as cli

from ..analyses.shock import (
    PULSES,
    QUANTITIES,
    plot_srs,
    pulse,
    pulse_end,
    shock_response_spectrum,
    srs_text,
)
from ..analyses.transient import ShockPeaks, shock_peaks, shock_response
from ..deadline import Deadline
from ..errors import ModelError, Problem, name_list, printable
from ..model import Model
from ..model.load_spec import ShockSpec
from ..model.time_series import read_time_series
from ..model.units import ENERGY, TIME, Dimension
from ..model.units_display import ResultUnits, result_units
from ..system.build import linear_system


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    srs = subparsers.add_parser("srs", parents=[cli.option_parser()],
                                description="A --pulse or --csv history is a base "
                                "acceleration in m/s^2 (SI; --units g shows it and the "
                                "spectrum in g); a model's [shock] pulse has its own unit.",
                                help="shock response spectrum of a pulse or a CSV history "
                                "(maximax, primary, residual)")
    srs.add_argument("model", nargs="?", default=None,
                     help="a model file with a [shock] section (instead of --pulse/--csv)")
    srs.add_argument("--output", metavar="NAME",
                     help="with MODEL: the SRS of this coordinate's or output's history under "
                          "the [shock] pulse (default: of the pulse itself)")
    srs.add_argument("--pulse", choices=PULSES, help="a classical pulse")
    srs.add_argument("--amplitude", type=cli.number(), default=1.0, metavar="A",
                     help="the pulse's peak in m/s^2 (its area for an impulse); default 1")
    srs.add_argument("--duration", type=cli.number(0, open_low=True), metavar="TAU",
                     help="the pulse's duration (s)")
    srs.add_argument("--step", type=cli.number(0, open_low=True), metavar="DT",
                     help="the pulse's sampling step (default: duration/2000)")
    srs.add_argument("--csv", metavar="FILE", help="a history: time (s), value per line")
    srs.add_argument("--pulse-end", dest="pulse_end", type=cli.number(0, open_low=True),
                     metavar="TAU", help="with --csv: where the excitation ends (s from the "
                     "first sample): primary before, residual after (default: the record's "
                     "end; a pulse's or [shock]'s own duration otherwise)")
    srs.add_argument("--largest", action="store_true",
                     help="with MODEL: also the largest response of every coordinate and "
                          "output under the [shock] pulse (JSON: 'response')")
    srs.add_argument("--only", metavar="NAMES",
                     help="with MODEL: the coordinates and outputs of --largest "
                          "(comma-separated; implies --largest)")
    srs.add_argument("--from", dest="start", type=cli.number(0, open_low=True), default=10.0,
                     metavar="F1", help="lowest natural frequency (Hz, default 10)")
    srs.add_argument("--to", dest="stop", type=cli.number(0, open_low=True), default=10000.0,
                     metavar="F2", help="highest natural frequency (Hz, default 10000)")
    srs.add_argument("--points", type=cli.integer(1, 100_000), default=100, metavar="N",
                     help="natural frequencies, log spaced (default 100)")
    damping = srs.add_mutually_exclusive_group()
    damping.add_argument("--Q", type=cli.number(0.5, open_low=True), default=None,
                         help="Q = 1/(2 zeta) (default 10)")
    damping.add_argument("--damping", type=cli.number(0, 1, open_high=True), default=None,
                         metavar="ZETA", help="the damping ratio")
    srs.add_argument("--quantity", choices=QUANTITIES, default=QUANTITIES[0],
                     help="the response (default absolute acceleration)")
    srs.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                    help="draw the SRS and the history")
    srs.add_argument("--json", action="store_true", help="print one JSON object")
    srs.set_defaults(run=run_srs)


#: the SI unit of a --pulse or --csv history: a base acceleration
PULSE_UNIT = "m/s^2"


def _signal_unit(model: Model, name: str, derivative: int) -> str:
    """The SI unit of a signal's derivative (a force for a coordinate), "" without units."""
    found = model.units.dimensions.get(name) if model.units is not None else None
    if found is None:
        return ""
    dim = (ENERGY / found if name in model.coordinates else found / TIME ** derivative)
    return dim.text()


#: the quantity of the SRS oscillators' input (a base acceleration)
ACCELERATION = Dimension.of(m=1, s=-2)


def _input_quantity(model: Model, spec: ShockSpec, output: str | None) -> list[str]:
    """Whether the SRS's input is an acceleration: exit 2 for an output whose unit is
    known to be another quantity, a warning where the unit is unknown or the pulse is not
    an acceleration (the oscillators take the history as their base's acceleration)."""
    units = model.units
    if output is not None:
        dimension = units.dimensions.get(output) if units is not None else None
        if dimension is not None and dimension != ACCELERATION:
            raise ModelError(Problem(
                f"'{printable(output, 40)}' is in {dimension.text() or '1'}, not an "
                "acceleration: a shock response spectrum is of a base acceleration (its "
                "oscillators' support); give an output that is an acceleration (such as "
                f"{printable(output, 40)}'' as an [outputs] entry)", model.source,
                key="--output"))
        return [] if dimension is not None else [
            f"the model has no unit for {printable(output, 40)}: its history is taken as a "
            "base acceleration (the SRS of a displacement or a force means nothing)"]
    signal = units.dimensions.get(spec.signal) if units is not None else None
    if spec.signal in model.coordinates:
        return [f"the [shock] pulse is a force on {printable(spec.signal, 40)}: its SRS "
                "takes it as a base acceleration"]
    if signal is not None and signal / Dimension.of(s=spec.derivative) != ACCELERATION:
        return [f"the [shock] pulse is of {printable(spec.signal, 40)}" + "'" * spec.derivative
                + f" in {(signal / Dimension.of(s=spec.derivative)).text() or '1'}, not an "
                "acceleration: its SRS takes it as a base acceleration"]
    return []


def _from_model(args: argparse.Namespace, deadline: Deadline
                ) -> tuple[float, np.ndarray, float, float | None, ShockPeaks | None,
                           list[str], str, ResultUnits | None]:
    """(step, history, Q, the pulse's end, the largest responses where asked for, notes,
    the history's SI unit, the display units) of the model's [shock] pulse or of an
    output under it."""
    model = cli.load_model(args)
    shown = cli.shown_units(args, model)
    spec = model.shock_section
    if spec is None:
        raise ModelError(Problem("the model has no [shock] section: add one with the pulse, "
                                 "its signal, amplitude and duration (docs/model-format.md)",
                                 model.source, "shock"))
    notes = _input_quantity(model, spec, args.output)
    names = cli.response_names(args.only, model)
    largest = args.largest or names is not None
    if args.output is not None and args.output not in (*model.coordinates, *model.outputs):
        known = (*model.coordinates, *model.outputs)
        raise ModelError(Problem(f"'{printable(args.output, 40)}' is not a coordinate or "
                                 "output; they are " + name_list(known, 20), "--output"))
    peaks = response = None
    if largest or args.output is not None:
        wanted = None if largest and names is None else \
            list(dict.fromkeys([*(names or []), *([args.output] if args.output else [])]))
        response = shock_response(linear_system(model, deadline), names=wanted,
                                  deadline=deadline)
    if largest:
        assert response is not None
        units = result_units(model)
        peaks = shock_peaks(response, spec, dict(units.si) if units is not None else {},
                            names=names)
    if args.output is None:
        _, values = pulse(spec.pulse, spec.amplitude, spec.duration, spec.step,
                          total=spec.total)
        unit = _signal_unit(model, spec.signal, spec.derivative)
    else:
        assert response is not None
        values = response.history[args.output]
        unit = shown.si.get(args.output, "") if shown is not None else ""
    return spec.step, values, spec.Q, pulse_end(spec.pulse, spec.duration, spec.step), peaks, \
        notes, unit, shown


def run_srs(args: argparse.Namespace) -> int:
    given = sum(x is not None for x in (args.pulse, args.csv, args.model))
    if given != 1:
        raise ModelError(Problem("give one of --pulse (with --duration), --csv FILE or a "
                                 "model file with a [shock] section", "srs"))
    for option, value in (("--output", args.output), ("--largest", args.largest or None),
                          ("--only", args.only)):
        if value is not None and args.model is None:
            raise ModelError(Problem(f"{option} needs a model file", "srs"))
    if args.pulse_end is not None and args.csv is None:
        raise ModelError(Problem("--pulse-end is for a --csv history (a pulse ends at its "
                                 "duration)", "srs"))
    if args.stop <= args.start:
        raise ModelError(Problem("--to must be above --from", "srs"))
    Q = 10.0
    deadline = cli.deadline(args)
    peaks: ShockPeaks | None = None
    notes: list[str] = []
    end: float | None
    unit, units = PULSE_UNIT, cli.shown_units(args)
    if args.model is not None:
        step, values, Q, end, peaks, notes, unit, units = _from_model(args, deadline)
    elif args.csv is not None:
        step, values = read_time_series(args.csv)
        end = args.pulse_end
    else:
        if args.duration is None:
            raise ModelError(Problem("--pulse needs --duration (s)", "srs"))
        step = args.step or args.duration / 2000
        _, values = pulse(args.pulse, args.amplitude, args.duration, step)
        end = pulse_end(args.pulse, args.duration, step)
    frequencies = np.geomspace(args.start, args.stop, args.points)
    spectrum = shock_response_spectrum(values, step, frequencies, damping=args.damping,
                                       Q=args.Q if args.Q is not None or args.damping
                                       is not None else Q, quantity=args.quantity,
                                       excitation_end=end, deadline=deadline)
    if args.plot:
        plot_srs(spectrum, np.arange(len(values)) * step, values, args.plot, unit=unit,
                 units=units, signal_label=args.output or "input")
    if args.json:
        cli.emit_json({**spectrum.to_dict(), **({} if peaks is None else
                                                {"response": peaks.to_dict()})})
    else:
        sys.stdout.write(srs_text(spectrum, unit, units))
        if peaks is not None:
            sys.stdout.write(f"Largest responses under the [shock] pulse (over "
                             f"{peaks.shock.total:.4g} s):\n{peaks.table(units).text()}\n")
    cli.warn([*notes, *spectrum.warnings, *(peaks.warnings if peaks is not None else ())])
    return 0
