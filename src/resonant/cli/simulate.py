"""``resonant simulate``: time simulation, linear or full nonlinear.

    resonant simulate MODEL [--duration T] [--nonlinear] [--initial x1=0.01,x2'=0 ...]
                      [--start auto|rest|stationary|periodic] [--periods P] [--method M]
                      [--plot FILE.png|svg|pdf] [--csv FILE] [--json] [--set NAME=VALUE ...]
"""

from __future__ import annotations

import argparse
import sys
from functools import partial

import resonant.cli.common as common

from ..analyses.simulate import DEFAULT_PERIODS, plot_simulation, simulate, simulation_text
from ..errors import AnalysisError, ModelError, Problem
from ..model.options import INTEGRATORS, START_MODES, SimulationOptions
from ..model.units_display import result_units
from ..system import linear_system


def parse_initial_items(items: list[str] | None) -> dict[str, str]:
    """``["x1=0.01,x2=0", "x1'=1"]`` -> ``{"x1": "0.01", "x2": "0", "x1'": "1"}``.

    Examples
    --------
    >>> parse_initial_items(["x1=0.01, x2=0", "x1'=l/10"])
    {'x1': '0.01', 'x2': '0', "x1'": 'l/10'}
    """
    out: dict[str, str] = {}
    for item in items or ():
        for part in item.split(","):
            if not part.strip():
                continue
            name, sep, value = part.partition("=")
            if not sep or not name.strip() or not value.strip():
                raise ModelError(Problem(f"--initial expects NAME=VALUE[,NAME=VALUE...], got "
                                         f"'{item}'", "--initial"))
            out[name.strip()] = value.strip()
    return out


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got '{text}'") from None
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive number, got '{text}'")
    return value


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    parser = subparsers.add_parser(
        "simulate", parents=[parent],
        help="time simulation (linearized or --nonlinear) compared with the stationary "
             "solution",
        description="Integrate the equations of motion in time and compare the steady-state "
                    "amplitudes (peak absolute deviation over the last periods) with the "
                    "linear stationary prediction.")
    parser.add_argument("--duration", type=_positive, metavar="T",
                        help="end time in s (default: until the transient has decayed, or "
                             "15 periods + the window for undamped systems)")
    parser.add_argument("--nonlinear", action="store_true",
                        help="integrate the full (not linearized) Lagrange equations")
    parser.add_argument("--initial", action="append", default=[], metavar="NAME=VALUE,...",
                        help="initial deviation from the reference state (x1=0.01) or "
                             "velocity (x1'=0.1); the others start as --start says")
    parser.add_argument("--start", choices=START_MODES, default="auto",
                        help="initial state: rest, the linear stationary solution's q_p(0), "
                             "q_p'(0), periodic (with --nonlinear: the periodic solution of "
                             "the full equations, harmonic balance), or auto (periodic or "
                             "stationary for undamped systems, else rest)")
    parser.add_argument("--periods", type=_positive, default=None, metavar="P",
                        help="measurement window in periods of the lowest excitation "
                             "frequency (default 5)")
    parser.add_argument("--method", choices=INTEGRATORS, default=None,
                        help="integrator (default DOP853, LSODA for stiff systems)")
    parser.add_argument("--plot", metavar="FILE", type=common.plot_file,
                       help="write a plot (.png, .svg or .pdf)")
    parser.add_argument("--csv", metavar="FILE", help="write the time history as CSV")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(run=run_simulate)


def run_simulate(args: argparse.Namespace) -> int:
    initial = parse_initial_items(args.initial)
    model = common.load_model(args)
    deadline = common.deadline(args)
    options = SimulationOptions(duration=args.duration, nonlinear=args.nonlinear,
                                initial=initial or None, start=args.start,
                                periods=args.periods or DEFAULT_PERIODS, method=args.method)
    sim = simulate(linear_system(model, deadline), options=options, deadline=deadline)
    written = []
    units = result_units(model)
    plot = partial(plot_simulation, sim, units=units)
    for path, write in ((args.csv, sim.to_csv), (args.plot, plot)):
        if not path:
            continue
        try:
            write(path)
        except OSError as exc:
            raise AnalysisError(f"cannot write '{path}': {exc.strerror or exc}") from None
        written.append(path)
    if args.json:
        data = sim.to_dict()
        if units is not None:  # JSON stays SI; the units say which
            data["units"] = units.to_json()
        common.emit_json(data)
    else:
        sys.stdout.write(simulation_text(sim, units))
        for path in written:
            print(f"wrote {path}")
    common.warn(sim.warnings)
    return 0
