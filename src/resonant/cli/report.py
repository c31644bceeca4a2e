"""``resonant report MODEL -o FILE``: the worked solution as HTML, Markdown or LaTeX."""

from __future__ import annotations

import argparse
import json
import os
import sys

import resonant.cli.common as common

from ..analyses.correlate import Correlation
from ..analyses.measured_match import check_correlation, match_test_file
from ..errors import AnalysisError, ModelError, Problem
from ..model.files import FileRefused, open_regular_file, read_bounded
from ..model.measured import UFF_SUFFIXES
from ..report import build_report, render, report_format
from ..system.build import linear_system

#: the largest correlation file read (a JSON of a few modes)
MAX_TEST_BYTES = 16 * 2**20


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    parser = subparsers.add_parser(
        "report", parents=[parent],
        help="write the worked solution (.html, .md or .tex)",
        description="Write the solution of the model as a worked example, in the order and "
                    "notation of a textbook exercise: energies, derivatives, M, C, K, Q(t), "
                    "the stationary solution, amplitudes, natural frequencies and plots. "
                    "The format follows the file ending: .html (self-contained, MathML and "
                    "SVG), .md (Markdown with $$ LaTeX; figures as SVG files beside it) or "
                    ".tex (LaTeX for pdflatex; figures as PDF files beside it).")
    parser.add_argument("-o", "--output", required=True, metavar="FILE",
                        help="the output file: .html, .md or .tex")
    parser.add_argument("--no-plots", action="store_true",
                        help="leave out the frequency response and time history plots")
    parser.add_argument("--nonlinear", action="store_true",
                        help="add the section 'Beyond small oscillations': the periodic steady "
                             "state of the full equations (harmonic balance), its frequency-"
                             "response curve and the operating point on it")
    parser.add_argument("--test", metavar="FILE", action="append", default=[],
                        help="measured data: a Universal File of FRFs (.uff, .unv; checked "
                             "against the model's [measurement] section, then drawn over "
                             "the model's FRFs) or the JSON of resonant correlate --json "
                             "(the section 'Test against model': MAC, pairs); repeatable, "
                             "one of each")
    parser.set_defaults(run=run_report)


def _cannot_write(path: str, exc: OSError) -> ModelError:
    return ModelError(Problem(f"cannot write the report: {exc.strerror or type(exc).__name__}",
                              str(path)))


def read_correlation(path: str) -> Correlation:
    """The saved correlation of ``resonant correlate --json`` (an untrusted file).

    Parameters
    ----------
    path : str

    Returns
    -------
    Correlation

    Raises
    ------
    ModelError
        For a file that cannot be read, is not JSON or not a saved correlation (exit 2).
    """
    name = os.path.basename(path)
    try:
        with open_regular_file(path, follow_symlinks=True, max_bytes=MAX_TEST_BYTES) as handle:
            data = json.loads(read_bounded(handle, MAX_TEST_BYTES).decode("utf-8"))
        return Correlation.from_dict(data)
    except (OSError, FileRefused) as exc:
        raise ModelError(Problem(f"cannot read the test: {exc}", name)) from None
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise ModelError(Problem(f"not JSON ({type(exc).__name__})", name)) from None
    except (AnalysisError, TypeError, AttributeError) as exc:
        raise ModelError(Problem(f"not the JSON of resonant correlate --json: {exc}",
                                 name)) from None


def _is_uff(path: str) -> bool:
    return os.path.splitext(path)[1].lower() in UFF_SUFFIXES


def _split_tests(given: list[str]) -> tuple[str | None, str | None]:
    """The correlation JSON and the Universal File of ``--test`` (at most one of each)."""
    uff = [p for p in given if _is_uff(p)]
    json_files = [p for p in given if not _is_uff(p)]
    for files, what in ((uff, "Universal File of FRFs"), (json_files, "correlation JSON")):
        if len(files) > 1:
            raise ModelError(Problem(f"--test takes one {what}, got {len(files)}", "--test"))
    return (json_files[0] if json_files else None), (uff[0] if uff else None)


def run_report(args: argparse.Namespace) -> int:
    fmt = report_format(args.output)  # check the ending before any work
    path = common.writable_output(args.output, "the report")  # before any work
    json_file, uff_file = _split_tests(args.test)
    correlation = read_correlation(json_file) if json_file else None
    model = common.load_model(args)
    deadline = common.deadline(args)
    if correlation is not None and json_file is not None:
        check_correlation(correlation, linear_system(model, deadline),
                          os.path.basename(json_file), deadline=deadline)
    measured = match_test_file(uff_file, model, deadline) if uff_file else None
    report = build_report(model, plots=not args.no_plots, nonlinear=args.nonlinear,
                          correlation=correlation, measured=measured)
    try:
        text = render(report, fmt, path)  # writes the figures of .md and .tex beside it
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise _cannot_write(args.output, exc) from None
    print(f"wrote {path}", file=sys.stderr)
    return 0
