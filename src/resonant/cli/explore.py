"""``resonant explore MODEL -o FILE.html``: the model as an interactive, self-contained page."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import resonant.cli.common as common

from ..analyses.measured_match import match_test_file
from ..errors import ModelError, Problem
from ..views.explore import explore_page


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    parser = subparsers.add_parser(
        "explore", parents=[parent],
        help="write an interactive page of the model (.html, self-contained)",
        description="Write one self-contained HTML page in which the model can be played "
                    "with: a slider and a number field for every parameter and for the "
                    "excitation frequency, the numbers (M, C, K, natural frequencies, "
                    "damping ratios, stability, amplitudes and phases), the frequency "
                    "response, the time history over one period and the mechanism (or a "
                    "bar per coordinate) moving with the response or in a mode shape. The "
                    "page computes in the browser from the model's equations, loads nothing "
                    "and opens from a file or inside an iframe. Slider ranges come from the "
                    "model's [explore] section, else from [variants], else around each "
                    "value; --set changes the starting values.")
    parser.add_argument("-o", "--output", required=True, metavar="FILE",
                        help="the page to write (.html)")
    parser.add_argument("--test", metavar="FILE.uff",
                        help="measured FRFs (a Universal File, as resonant frf --save writes "
                             "them), checked against the model's [measurement] section and "
                             "drawn as points over the page's frequency response")
    parser.set_defaults(run=run_explore)


def run_explore(args: argparse.Namespace) -> int:
    path = Path(args.output)
    if path.suffix.lower() not in (".html", ".htm"):
        raise ModelError(Problem(f"cannot tell the format from '{args.output}': the explore "
                                 "page is HTML, use a file ending in .html", str(args.output)))
    path = common.writable_output(args.output, "the page")  # before any work
    model = common.load_model(args)
    deadline = common.deadline(args)
    test = match_test_file(args.test, model, deadline) if args.test else None
    page = explore_page(model, deadline=deadline, measured=test)
    page.save(path)
    common.warn(page.warnings)
    kind = "computed live in the browser" if page.live else "precomputed curves and modes"
    print(f"wrote {path} ({len(page.html) // 1024} kB, {kind})", file=sys.stderr)
    return 0
