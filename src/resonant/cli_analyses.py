"""Subcommands ``resonant modes`` and ``resonant sweep``.

``modes MODEL [--count K] [--plot FILE] [--json]`` prints natural frequencies,
mode shapes, damping and stability (:func:`resonant.modes.modes`).

``sweep MODEL --param P --from A --to B [--points N] [--log] [--method M]
[--only NAMES] [--plot FILE] [--csv FILE] [--progress] [--json]`` sweeps a
parameter (:func:`resonant.sweep.sweep`).
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

from . import cli
from .errors import AnalysisError


def register(subparsers: Any, common: argparse.ArgumentParser) -> None:
    modes = subparsers.add_parser(
        "modes", parents=[common], help="natural frequencies, mode shapes, damping ratios")
    modes.add_argument("--count", type=int, metavar="K",
                       help="only the K lowest modes (sparse Lanczos for large matrix models)")
    modes.add_argument("--plot", metavar="FILE", help="draw the mode shapes (.png, .svg, .pdf)")
    modes.add_argument("--json", action="store_true", help="print one JSON object")
    modes.set_defaults(run=run_modes)

    sweep = subparsers.add_parser(
        "sweep", parents=[common], help="amplitude and phase against a parameter "
        "(frequency response)")
    sweep.add_argument("--param", required=True, metavar="P",
                       help="the parameter to sweep (usually the excitation frequency)")
    sweep.add_argument("--from", dest="start", required=True, type=float, metavar="A")
    sweep.add_argument("--to", dest="stop", required=True, type=float, metavar="B")
    sweep.add_argument("--points", type=int, default=201, metavar="N",
                       help="number of values (default 201)")
    sweep.add_argument("--log", action="store_true", help="logarithmic spacing")
    sweep.add_argument("--method", default="auto",
                       choices=["auto", "dense", "banded", "sparse", "modal"],
                       help="solution method (default: chosen from the matrix structure)")
    sweep.add_argument("--only", metavar="NAMES",
                       help="comma-separated coordinates to report (default all; outputs "
                            "are always reported)")
    sweep.add_argument("--plot", metavar="FILE", help="draw amplitude and phase "
                       "(.png, .svg, .pdf)")
    sweep.add_argument("--csv", metavar="FILE", help="write the table as CSV")
    sweep.add_argument("--progress", action="store_true",
                       help="show a progress bar on standard error")
    sweep.add_argument("--json", action="store_true", help="print one JSON object")
    sweep.set_defaults(run=run_sweep)


def run_modes(args: argparse.Namespace) -> int:
    from .modes import modes

    model = cli.load_model(args)
    result = modes(model, count=args.count)
    if args.plot:
        result.plot(args.plot)
    if args.json:
        cli.emit_json(result.to_dict())
    else:
        sys.stdout.write(modes_text(result))
    cli.warn(result.warnings)
    return 0


def modes_text(result: Any) -> str:
    """The human-readable table of ``resonant modes``."""
    out = [result.title or "modes", ""]
    names = result.coordinates
    shown = names[:8]
    out.append(f"{'mode':>4}  {'omega [rad/s]':>14}  {'f [Hz]':>12}  {'zeta':>8}   "
               f"shape (largest component +1): {', '.join(shown)}{' ...' if len(names) > 8 else ''}")
    per_mode = result.proportional_damping
    for j, w in enumerate(result.natural_frequencies):
        zeta = f"{result.damping_ratios[j]:8.4g}" if per_mode and j < len(
            result.damping_ratios) else " " * 8
        shape = ", ".join(f"{v: .4g}" for v in result.mode_shapes[:8, j])
        out.append(f"{j + 1:>4}  {w:14.6g}  {w / (2 * math.pi):12.6g}  {zeta}   [{shape}]")
    if result.damped:
        out.append("")
        if result.rayleigh is not None:
            a, b = result.rayleigh
            out.append(f"proportional (Rayleigh) damping: C = {a:.6g} M + {b:.6g} K")
        elif result.proportional_damping:
            out.append("proportional damping (K M^-1 C = C M^-1 K): the modes decouple C")
        else:
            out.append("non-proportional damping: eigenvalues s of the state matrix")
            out.append(f"{'Re s':>14}  {'Im s':>14}  {'zeta':>8}")
            for s in result.eigenvalues[:2 * 20]:
                if s.imag >= 0:
                    zeta = -s.real / abs(s) if abs(s) else 0.0
                    out.append(f"{s.real:14.6g}  {s.imag:14.6g}  {zeta:8.4g}")
    out.append("")
    out.append(f"stability: {result.stability}   (method: {result.method})")
    return "\n".join(out) + "\n"


def run_sweep(args: argparse.Namespace) -> int:
    from .sweep import linspace, sweep

    if not (math.isfinite(args.start) and math.isfinite(args.stop)):
        raise AnalysisError("--from and --to must be finite numbers")
    model = cli.load_model(args)
    values = linspace(args.start, args.stop, args.points, log=args.log)
    names = None
    if args.only:
        names = [n.strip() for n in args.only.split(",") if n.strip()]
    result = sweep(model, args.param, values, method=args.method, names=names,
                   progress=True if args.progress else None, log=args.log)
    if args.plot:
        result.plot(args.plot)
    if args.csv:
        try:
            result.to_csv(args.csv)
        except OSError as exc:
            raise AnalysisError(f"cannot write '{args.csv}': {exc.strerror or exc}") from None
    if args.json:
        cli.emit_json(result.to_dict())
    else:
        sys.stdout.write(sweep_text(result))
    cli.warn(result.warnings)
    return 0


def sweep_text(result: Any) -> str:
    """The human-readable summary of ``resonant sweep``."""
    unit = f" {result.unit}" if result.unit else ""
    out = [result.title or "sweep",
           f"{result.parameter} from {result.values[0]:.6g} to {result.values[-1]:.6g}{unit}, "
           f"{len(result.values)} values, method {result.method}", ""]
    if result.natural_frequencies is not None and result.frequency_sweep:
        inside = [w for w in result.natural_frequencies
                  if result.values.min() <= w <= result.values.max()]
        if inside:
            out.append("natural frequencies in range: " +
                       ", ".join(f"{w:.6g}" for w in inside[:20]) + unit)
    for title, items in (("resonance peaks", result.peaks),
                         ("antiresonances", result.antiresonances)):
        out.append(f"{title}:")
        if not items:
            out.append("  none")
        for p in items[:50]:
            out.append(f"  {p.name:>12}  at {result.parameter} = {p.value:.6g}{unit}   "
                       f"amplitude {p.amplitude:.6g}")
        if len(items) > 50:
            out.append(f"  ... {len(items) - 50} more (use --json)")
    return "\n".join(out) + "\n"
