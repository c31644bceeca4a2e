"""``resonant exercise`` (variants of a teacher's exercise) and ``resonant grade``."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import resonant.cli.common as common

from ..errors import ModelError, Problem, printable
from ..exercises import FORMATS, generate, grade, grade_text, write
from ..exercises.writing import ExerciseJob
from ..model import Model
from ..studies import engine_for, model_text


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    parser = subparsers.add_parser(
        "exercise", parents=[parent],
        help="exercise variants: statements, worked solutions, answer key, Moodle XML",
        description="Make N variants of the model's [exercise]: each with its own values "
                    "from [variants] (reproducible from --seed), solved before it is written. "
                    "Writes DIR/i/statement.*, DIR/i/solution.*, DIR/key.json and, with "
                    "--format moodle, DIR/moodle.xml (one Cloze question per variant).")
    parser.add_argument("--variants", type=common.integer(1, 10**6), required=True, metavar="N",
                        help="the number of variants")
    parser.add_argument("--seed", type=common.integer(0, 2**63 - 1), default=0, metavar="S",
                        help="the seed of the random choice (default 0); the same model, seed "
                             "and N give the same files")
    parser.add_argument("-o", "--output", required=True, metavar="DIR",
                        help="the folder to write into")
    parser.add_argument("--format", default="html", metavar="LIST",
                        help=f"comma-separated: {','.join(FORMATS)} (default html)")
    parser.add_argument("--no-plots", action="store_true",
                        help="leave the plots out of the worked solutions (much faster)")
    parser.add_argument("--workers", type=common.integer(0, 1024), metavar="N",
                        help="render the variants on N local worker processes (Dask; "
                             "default: this process)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="render them on a running Dask cluster, tcp://HOST:PORT")
    parser.set_defaults(run=run_exercise)
    grader = subparsers.add_parser(
        "grade", help="check a student's answers against a variant of an exercise key",
        description="Compare ANSWERS.json ({\"M\": [[...]], \"amplitude:x2\": 0.045, ...}) with "
                    "variant i of key.json: per answer right / wrong (relative error) / "
                    "missing, matrices entry by entry, and the score.")
    grader.add_argument("key", help="key.json written by `resonant exercise`")
    grader.add_argument("answers", help="the student's answers (JSON object)")
    grader.add_argument("--variant", type=common.integer(1, 10**6), required=True, metavar="I",
                        help="the student's variant (1 to N)")
    grader.add_argument("--json", action="store_true", help="print one JSON object")
    grader.set_defaults(run=run_grade)


def parse_formats(text: str) -> list[str]:
    """``"html,moodle"`` -> ``["html", "moodle"]``; ModelError for an unknown one.

    Examples
    --------
    >>> parse_formats("html, moodle")
    ['html', 'moodle']
    """
    formats = [f.strip().lower() for f in text.split(",") if f.strip()]
    unknown = [f for f in formats if f not in FORMATS]
    if unknown or not formats:
        bad = printable(unknown[0] if unknown else text, limit=40)
        raise ModelError(Problem(f"unknown format '{bad}'; --format takes "
                                 f"{','.join(FORMATS)}", "--format"))
    return list(dict.fromkeys(formats))


def run_exercise(args: argparse.Namespace) -> int:
    formats = parse_formats(args.format)
    folder = Path(args.output)
    if folder.exists() and not folder.is_dir():
        raise ModelError(Problem("-o must name a folder; this is a file", str(folder)))
    if args.workers or args.scheduler is not None:  # the address and the count, before any work
        engine_for(args.workers, args.scheduler)
    deadline = common.deadline(args)
    model = common.load_model(args)
    start = time.perf_counter()
    batch = generate(model, args.variants, args.seed, deadline)
    for r in batch.replaced:
        values = ", ".join(f"{k} = {v:g}" for k, v in r.values.items())
        print(f"replaced the value set {values}: {r.reason}", file=sys.stderr)
    try:
        write(batch, folder, formats, plots=not args.no_plots, **_engine(args, model, formats,
                                                                          folder))
    except OSError as exc:
        raise ModelError(Problem(f"cannot write the exercise: {exc.strerror or 'I/O error'}",
                                 str(folder))) from None
    print(f"wrote {len(batch.variants)} variants to {folder} ({', '.join(formats)}, key.json) "
          f"in {time.perf_counter() - start:.1f} s; {len(batch.replaced)} value set(s) "
          "replaced", file=sys.stderr)
    return 0


def _engine(args: argparse.Namespace, model: Model, formats: list[str], folder: Path
            ) -> dict[str, Any]:
    """The engine and job of ``--workers``/``--scheduler`` (none: this process)."""
    if not args.workers and args.scheduler is None:
        return {}
    text, base_dir = model_text(model)
    overrides = tuple(sorted(common.parse_settings(getattr(args, "set", None)).items()))
    job = ExerciseJob(text, model.source, base_dir, overrides, args.variants, args.seed,
                      tuple(formats), not args.no_plots, str(folder.resolve()),
                      tuple(u.text for u in common.chosen_units(args).values()))
    return {"engine": engine_for(args.workers, args.scheduler, deadline=common.deadline(args)),
            "job": job}


def run_grade(args: argparse.Namespace) -> int:
    result = grade(args.key, args.variant, args.answers)
    if args.json:
        common.emit_json(result)
    else:
        sys.stdout.write(grade_text(result))
    return 0
