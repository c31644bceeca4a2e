"""``resonant study``: a parameter study of a model (docs/studies.md).

``study MODEL --vary NAME=SPEC ... [--design grid|random|lhs|sobol] [--samples N]
[--seed S] --quantity Q ... [--band P=FROM:TO[:POINTS]] [--harmonics H] -o FILE.parquet|.csv
[--plot DIR] [--workers N | --scheduler ADDRESS] [--resume] [--progress] [--json]``;
without ``--vary`` and ``--quantity`` the model's ``[study]`` section is used
(options given on the command line replace its entries).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import resonant.cli.common as cli

from ..deadline import AnalysisTimeout, DeadlineExceeded
from ..errors import ModelError, Problem, printable
from ..model.study import DESIGNS, MAX_HARMONICS, MAX_SAMPLES, MAX_SEED
from ..model.units_display import ResultUnits, shown_unit
from ..studies import StudyJob, StudyResult, collect, engine_for, request
from ..studies.files import check_output, completed_rows
from ..studies.study_charts import plot_study, study_units

if TYPE_CHECKING:
    import pandas as pd


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    study = subparsers.add_parser(
        "study", parents=[parent], help="a parameter study: Monte Carlo, grids, Sobol "
        "indices, on local workers or a Dask cluster")
    study.add_argument("--vary", action="append", metavar="NAME=SPEC",
                       help="a parameter and how it varies: uniform(a, b), normal(mean, sd), "
                       "lognormal(mean, sd), [v1, v2, ...] or {from=..., to=..., step=...}")
    study.add_argument("--quantity", action="append", metavar="Q",
                       help="natural_frequency:I, damping_ratio:I, amplitude:NAME, "
                       "phase:NAME, peak:NAME, stable, nonlinear_amplitude:NAME, rms:NAME, "
                       "srs:NAME@F, damage:NAME, critical_speed:K[@R], "
                       "stability_threshold, log_decrement:K@SPEED (rotors)")
    study.add_argument("--design", choices=DESIGNS)
    study.add_argument("--samples", type=cli.integer(1, MAX_SAMPLES), metavar="N")
    study.add_argument("--seed", type=cli.integer(0, MAX_SEED), metavar="S")
    study.add_argument("--band", metavar="P=FROM:TO[:POINTS]",
                       help="the band of peak: quantities, e.g. omega=1:30:400 (and where "
                       "nonlinear_amplitude: is swept up from)")
    study.add_argument("--harmonics", type=cli.integer(1, MAX_HARMONICS), metavar="H",
                       help="harmonics of nonlinear_amplitude: (default: chosen, as sweep "
                       "--nonlinear)")
    study.add_argument("-o", "--output", required=True, metavar="FILE",
                       help="the rows, .parquet or .csv")
    study.add_argument("--plot", metavar="DIR", help="write the pictures into DIR")
    where = study.add_mutually_exclusive_group()
    where.add_argument("--workers", type=cli.integer(0, 1024), metavar="N",
                       help="local worker processes (0: this process; default: chosen)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="a running Dask scheduler, tcp://HOST:PORT")
    study.add_argument("--resume", action="store_true",
                       help="continue an interrupted study of the same file")
    study.add_argument("--progress", action="store_true", help="a progress bar")
    study.add_argument("--json", action="store_true", help="print one JSON object")
    study.set_defaults(run=run_study, timeout=None)


def _pairs(items: list[str] | None, option: str) -> dict[str, str] | None:
    if not items:
        return None
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ModelError(Problem(f"{option} expects NAME=SPEC, got '{item}'", option))
        if name.strip() in out:
            raise ModelError(Problem(f"{option} names '{printable(name.strip(), 64)}' twice; "
                                     "give each parameter once", option))
        out[name.strip()] = value.strip()
    return out


def _band(text: str | None) -> dict[str, Any] | None:
    if text is None:
        return None
    name, sep, rest = text.partition("=")
    parts = rest.split(":")
    if not sep or len(parts) not in (2, 3) or not all(p.strip() for p in parts):
        raise ModelError(Problem(f"--band expects P=FROM:TO or P=FROM:TO:POINTS, got "
                                 f"'{text}'", "--band"))
    band: dict[str, Any] = {"parameter": name.strip(), "from": parts[0].strip(),
                            "to": parts[1].strip()}
    if len(parts) == 3:
        if not parts[2].strip().isdigit():
            raise ModelError(Problem(f"POINTS must be a whole number, got "
                                     f"'{parts[2]}'", "--band"))
        band["points"] = int(parts[2])
    return band


def run_study(args: argparse.Namespace) -> int:
    # the options that need no model first: the output, the engine (before any work)
    check_output(args.output)
    if args.plot and Path(args.plot).exists() and not Path(args.plot).is_dir():
        raise ModelError(Problem("cannot write the pictures: it is not a folder", args.plot))
    engine = engine_for(args.workers, args.scheduler, deadline=cli.deadline(args))
    model = cli.load_model(args)
    spec = request(model, _pairs(args.vary, "--vary"), args.quantity, design=args.design,
                   samples=args.samples, seed=args.seed, band=_band(args.band),
                   harmonics=args.harmonics)
    job = StudyJob.of(model, spec, overrides=cli.parse_settings(getattr(args, "set", None)),
                      allow_paths=args.allow_path)
    try:
        result = collect(job, engine, args.output, resume=args.resume,
                         progress=args.progress or None, deadline=cli.deadline(args),
                         columns=[*(spec.vary if args.plot else ()), *spec.columns, "status"])
    except (KeyboardInterrupt, DeadlineExceeded) as exc:
        line = _stopped(args.output)
        if isinstance(exc, KeyboardInterrupt):
            sys.stderr.write(line + "\n")  # the one line of an interrupt
            return 130
        if isinstance(exc, AnalysisTimeout):
            raise AnalysisTimeout(f"{exc}; {line}") from None
        raise
    units = study_units(model, spec)
    if args.plot:
        nominal = {name: float(model.parameter_values[name]) for name in spec.vary}
        table, shown, nominal = _in_display_units(result.table, units, nominal,
                                                  cli.shown_units(args, model))
        plot_study(table, list(spec.vary), list(spec.columns), args.plot,
                   result.sensitivity, grid=spec.design == "grid", units=shown,
                   nominal=nominal)
    if args.json:
        # the SI unit of every varied parameter and quantity ("" for a pure number)
        cli.emit_json({**result.to_dict(), "units": units})
    else:
        sys.stdout.write(_text(result, args.output, units, cli.shown_units(args, model)))
    return 0


def _in_display_units(table: pd.DataFrame, units: dict[str, str], nominal: dict[str, float],
                      shown: ResultUnits | None
                      ) -> tuple[pd.DataFrame, dict[str, str], dict[str, float]]:
    """The study's columns, units and nominal values in the display units (``--units``:
    MPa for a stress, Hz for a frequency; the file itself stays SI)."""
    if shown is None or not units:
        return table, units, nominal
    display = {column: shown_unit(shown, unit) for column, unit in units.items()}
    converted = table.copy()
    for column, unit in display.items():
        if column in converted.columns and unit.factor != 1.0:
            converted[column] = converted[column] / unit.factor
    return (converted, {c: u.text for c, u in display.items()},
            {n: display[n](v) if n in display else v for n, v in nominal.items()})


def _stopped(output: str) -> str:
    """What an interrupted study leaves: the file it names exists (with the study's
    description and no rows when it stopped before its first samples), or there is none
    (it stopped before the study began)."""
    if not Path(output).is_file():
        return (f"the study stopped before it began; {printable(output)} was not written")
    done = ("holds the samples done so far" if completed_rows(output) else
            "holds the study's description and no samples yet")
    return (f"the study stopped: {printable(output)} {done}; run the same command with "
            "--resume to complete it")


def _index(value: float | None) -> str:
    return "none" if value is None else f"{value:.3f}"


def _text(result: StudyResult, output: str, units: dict[str, str] | None = None,
          shown: ResultUnits | None = None) -> str:
    lines = [f"{len(result.table)} samples ({result.spec.design}) of "
             f"{', '.join(result.spec.vary)} in {printable(output)}, run in {result.where}"]
    lines.append("status: " + ", ".join(f"{k} {v}" for k, v in result.failures().items()))
    table = result.summary()
    if units:  # each quantity's own unit (a peak's frequency: the band parameter's)
        display = [shown_unit(shown, units.get(str(name), "")) for name in table.index]
        values = [c for c in table.columns if c != "count"]  # statistics scale with the unit
        table[values] = table[values].astype(float).div([d.factor for d in display], axis=0)
        table.insert(0, "unit", [d.text for d in display])
    lines.append(table.to_string(float_format=lambda v: f"{v:.6g}"))
    for name, entry in (result.sensitivity or {}).items():
        indices = ", ".join(
            f"{p} S1 {_index(s1)} ± {_index(c1)}, ST {_index(st)} ± {_index(ct)}"
            for p, s1, c1, st, ct in zip(entry["parameters"], entry["S1"], entry["S1_conf"],
                                         entry["ST"], entry["ST_conf"]))
        if all(v is None for v in entry["S1"]):
            indices = ""
        lines.append(f"Sobol indices of {name}: " + "; ".join(
            part for part in (indices, entry["note"]) if part))
    return "\n".join(lines) + "\n"
