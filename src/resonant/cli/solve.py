"""``resonant solve`` and ``resonant check``."""

from __future__ import annotations

import argparse
import sys

import resonant.cli.common as common

from ..analyses.fe_checks import check_matrices
from ..analyses.periodic_load import periodic_load_response, periodic_text
from ..analyses.stationary import solution_text, stationary
from ..errors import name_list
from ..model.units_display import result_units
from ..system import linear_system


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    solve = subparsers.add_parser("solve", parents=[parent], help="linearized EOM, natural "
                                  "frequencies and the stationary solution")
    solve.add_argument("--json", action="store_true", help="print one JSON object")
    solve.set_defaults(run=run_solve)
    check = subparsers.add_parser("check", parents=[parent], help="validate a model only")
    check.add_argument("--matrices", action="store_true",
                       help="also check M and K as read from FE files (symmetry, "
                       "definiteness, rigid-body modes, mass by direction; docs/interop.md); "
                       "exit 2 when something is wrong")
    check.set_defaults(run=run_check)


def run_solve(args: argparse.Namespace) -> int:
    deadline = common.deadline(args)
    model = common.load_model(args)
    system = linear_system(model, deadline)
    solution = stationary(system, deadline)
    # a [periodic] load: its stationary response by Fourier series (docs/random.md)
    periodic = periodic_load_response(system, deadline=deadline) \
        if model.periodic_section is not None else None
    if args.json:
        data = solution.to_dict()
        units = result_units(model)
        if units is not None:  # JSON stays SI; the units say which
            data["units"] = units.to_json()
        if periodic is not None:
            data["periodic"] = periodic.to_dict()
        common.emit_json(data)
        common.warn(solution.warnings)
    else:
        sys.stdout.write(solution_text(solution))
        if periodic is not None:
            sys.stdout.write(periodic_text(periodic, result_units(model)))
    return 0


#: coordinates named by `resonant check` before "... and N more"
CHECK_LISTED = 12


def run_check(args: argparse.Namespace) -> int:
    deadline = common.deadline(args)
    model = common.load_model(args)
    system = linear_system(model, deadline)
    system.numeric(deadline)
    print(f"{args.model}: valid model, {len(model.coordinates)} coordinate(s): "
          f"{name_list(model.coordinates, limit=CHECK_LISTED)}")
    if getattr(args, "matrices", False):
        checks = check_matrices(system)
        print(checks.summary())
        return 0 if checks.ok else 2
    return 0
