"""``resonant random MODEL [--plot FILE] [--json [--densities auto|all|none]] [--only NAMES]``:
the response to the random inputs of the model's ``[random]`` section (docs/random.md).

The output grows with what is asked for, not with the model: without ``--only``, the text
of a model of more than :data:`MAX_TEXT_ROWS` responses shows the :data:`TEXT_ROWS` of
largest RMS, and the JSON leaves the densities out above :data:`MAX_JSON_NUMBERS` numbers
(saying so); what it writes is streamed, a chunk of responses at a time.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from dataclasses import replace

import resonant.cli.common as cli

from ..analyses.random_response import RandomResponse, plot_random, random_response, random_text
from ..model.units_display import ResultUnits
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
    command.add_argument("--densities", choices=DENSITIES, default="auto",
                         help="the JSON's spectral densities: auto (every response's where "
                              f"they hold at most {MAX_JSON_NUMBERS:.0e} numbers, else none), "
                              "all (streamed), none (the RMS and rates only)")
    command.add_argument("--tol", type=cli.number(0, 1, open_low=True, open_high=True),
                         default=None, metavar="T",
                         help="relative error of the mean squares (default: the section's "
                              "tolerance, else 1e-4)")
    command.set_defaults(run=run_random)


#: what ``--densities`` chooses
DENSITIES = ("auto", "all", "none")
#: the most density values ``--densities auto`` writes (about 22 bytes each: 110 MB)
MAX_JSON_NUMBERS = 5_000_000
#: responses per piece of the streamed JSON (the memory held: their densities as lists)
CHUNK = 64
#: the members of the JSON that hold one entry per response
PER_RESPONSE = ("responses", "psd")
#: more responses than this, without --only: the text shows the largest ones
MAX_TEXT_ROWS = 100
#: how many of the largest it shows
TEXT_ROWS = 40


def _emit(result: RandomResponse, densities: str) -> list[str]:
    """The JSON of ``result.to_dict()``, its per-response members written a chunk of
    responses at a time (a model of 3,168 responses: its densities are not all held as
    Python lists at once, and each density is one line); without the densities (``psd``
    empty) where ``densities`` says so or, for ``auto``, where they are too many.  Returns
    the warning that says they were left out."""
    numbers = len(result.names) * len(result.frequency)
    keep = densities == "all" or (densities == "auto" and numbers <= MAX_JSON_NUMBERS)
    head = replace(result, names=()).to_dict()

    def pieces(key: str) -> Iterator[list[tuple[str, object]]]:
        for start in range(0, len(result.names), CHUNK):
            part = replace(result, names=result.names[start:start + CHUNK]).to_dict()[key]
            yield list(part.items())

    streamed = {key: pieces(key) for key in PER_RESPONSE if key in head and
                (keep or key != "psd")}
    cli.emit_json_streamed(head, streamed)
    if keep or not result.names:
        return []
    return [f"the JSON holds no spectral densities ('psd' is empty): {len(result.names)} "
            f"responses x {len(result.frequency)} frequencies are {numbers:.3g} numbers"
            + (f", more than {MAX_JSON_NUMBERS:.0e}" if densities == "auto" else "")
            + "; --only NAMES for some, --densities all for every one (streamed)"]


def _text(result: RandomResponse, chosen: bool, units: ResultUnits | None = None) -> str:
    """The text table: every response, or, for more than :data:`MAX_TEXT_ROWS` of them
    not chosen with ``--only``, the :data:`TEXT_ROWS` of largest RMS (in the model's
    order), said in a last line."""
    if chosen or len(result.names) <= MAX_TEXT_ROWS:
        return random_text(result, warnings=False, units=units)
    ranked = sorted(result.names, key=lambda n: -result.rms[n])[:TEXT_ROWS]
    shown = tuple(n for n in result.names if n in set(ranked))
    return random_text(replace(result, names=shown), warnings=False, units=units) + (
        f"  ({len(shown)} of {len(result.names)} responses: those of largest RMS in SI "
        "numbers; --only NAMES for others, --json for all)\n")


def run_random(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    names = cli.response_names(args.only, model)
    result = random_response(linear_system(model, deadline), deadline=deadline, names=names,
                             tolerance=args.tol)
    units = cli.shown_units(args, model)
    if args.plot:
        plot_random(result, args.plot, units=units)
    notes: list[str] = []
    if args.json:
        notes = _emit(result, args.densities)
    else:
        sys.stdout.write(_text(result, names is not None, units))
    cli.warn([*result.warnings, *notes])
    return 0
