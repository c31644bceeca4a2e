"""The lab's commands (docs/testing.md), each on a model with a ``[measurement]`` section:

* ``resonant frf MODEL DATA``: FRFs (H1, H2, Hv) of the channels from time histories
  (a Universal File, CSV, .npy or .npz), beside the model's; ``--save FILE.uff`` writes them;
  with several inputs in ``[measurement]``, the H1 matrix (saved as one FRF per
  response/input pair, :func:`resonant.analyses.frf_mimo.pair_name`);
* ``resonant identify MODEL FRFS``: modes by LSCF and LSFD from the FRFs of a Universal
  File, with the stabilization chart (from the whole FRF matrix where ``[measurement]``
  names several inputs: poles shared by every input);
* ``resonant correlate MODEL FRFS``: the identified modes against the model's (MAC, pairs,
  frequency errors);
* ``resonant update MODEL FRFS --vary NAME=LOW:HIGH ...``: parameters fitted to the
  identified frequencies and shapes, or (``--fit frf``) to the measured FRFs themselves.

Each takes ``--json`` and ``--plot FILE``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Mapping
from pathlib import Path

import numpy as np

import resonant.cli.common as cli

from ..analyses.correlate import correlate
from ..analyses.frf_estimate import ESTIMATORS, WINDOWS, frf_from_measurement, model_frf
from ..analyses.frf_mimo import frf_matrix_from_measurement, frf_matrix_of, pair_name
from ..analyses.frf_update import RESIDUALS, update_to_frf
from ..analyses.identify import ModalIdentification, identify_modes, identify_modes_matrix
from ..analyses.measured_match import saved_dofs
from ..analyses.model_update import update_parameters
from ..deadline import Deadline
from ..errors import ModelError, Problem, printable
from ..model.measured import (
    UFF_SUFFIXES,
    MeasuredData,
    read_histories,
    read_uff,
    write_uff,
)
from ..model.measurement_spec import MeasurementSpec, match_channels, measurement_dofs
from ..model.types import Model
from ..studies.engine import engine_for
from ..studies.multi_start import MAX_STARTS, multi_start_update
from ..system.build import linear_system


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    frf = subparsers.add_parser("frf", parents=[parent],
                                help="frequency response functions from measured time "
                                     "histories (H1, H2, Hv), beside the model's")
    frf.add_argument("data", help="the measured histories: .uff/.unv (dataset 58), .csv, "
                                  ".npy or .npz (docs/testing.md)")
    frf.add_argument("--estimator", choices=ESTIMATORS, default="H1")
    frf.add_argument("--window", choices=WINDOWS, default="hann")
    frf.add_argument("--segment", type=cli.integer(16, 1 << 26), metavar="N",
                     help="samples per segment (default: an eighth of the record; with an "
                          "impact window the whole record)")
    frf.add_argument("--overlap", type=cli.number(0, 1, open_high=True), metavar="R")
    frf.add_argument("--force-window", type=cli.number(0, 1, open_low=True), metavar="R",
                     help="keep the force over this first fraction of each segment")
    frf.add_argument("--exponential", type=cli.number(0, 1, open_low=True, open_high=True),
                     metavar="E", help="exponential window falling to E at the segment's end")
    _band(frf)
    frf.add_argument("--save", metavar="FILE", help="write the FRFs as a Universal File "
                                                    "(dataset 58; .uff)")
    _outputs(frf)
    frf.set_defaults(run=run_frf)
    for name, text, run in (
            ("identify", "modes from measured FRFs: LSCF poles with a stabilization chart, "
                         "LSFD shapes", run_identify),
            ("correlate", "identified modes against the model's: MAC, pairs, frequency "
                          "errors", run_correlate),
            ("update", "fit parameters to the identified frequencies and shapes",
             run_update)):
        command = subparsers.add_parser(name, parents=[parent], help=text)
        command.add_argument("frfs", help="a Universal File of FRFs (dataset 58, function "
                                          "type 4), e.g. from resonant frf --save")
        command.add_argument("--order", type=cli.integer(2, 200), default=40, metavar="N",
                             help="the highest LSCF order (default 40)")
        command.add_argument("--near", metavar="F1,F2,...",
                             help="take the poles nearest these frequencies (Hz)")
        command.add_argument("--added-decay", type=cli.number(0), default=0.0, metavar="RATE",
                             help="the decay (1/s) an exponential window added to the FRFs "
                                  "(resonant frf prints it); removed from the poles")
        _band(command)
        if name == "update":
            command.add_argument("--vary", action="append", default=[], metavar="NAME=LO:HI",
                                 help="a parameter and its bounds, e.g. 'k1=500 N/m:2 kN/m' "
                                      "(repeatable)")
            command.add_argument("--sigma", type=cli.number(0, open_low=True), metavar="S",
                                 help="the measured frequencies' relative standard deviation "
                                      "(with --fit frf: the FRFs' relative magnitude noise)")
            command.add_argument("--fit", choices=("modes", "frf"), default="modes",
                                 help="fit the identified modes (default) or the measured "
                                      "FRFs themselves at their lines")
            command.add_argument("--residual", choices=RESIDUALS, default="log",
                                 help="with --fit frf: log-magnitude or complex residuals")
            command.add_argument("--starts", type=cli.integer(1, MAX_STARTS), default=1,
                                 metavar="N", help="start from the model's values and N - 1 "
                                 "further points in the bounds (on the study engine), keep "
                                 "the best")
            where = command.add_mutually_exclusive_group()
            where.add_argument("--workers", type=cli.integer(0, 1024), metavar="N",
                               help="with --starts: local worker processes (0: this one)")
            where.add_argument("--scheduler", metavar="ADDRESS",
                               help="with --starts: a running Dask scheduler, tcp://HOST:PORT")
        _outputs(command)
        command.set_defaults(run=run)


def _band(command: argparse.ArgumentParser) -> None:
    command.add_argument("--from", dest="start", type=cli.number(0), metavar="F1",
                         help="lowest frequency kept (Hz)")
    command.add_argument("--to", dest="stop", type=cli.number(0, open_low=True), metavar="F2",
                         help="highest frequency kept (Hz)")


def _outputs(command: argparse.ArgumentParser) -> None:
    command.add_argument("--plot", metavar="FILE", type=cli.plot_file,
                         help="draw the result (.png, .svg, .pdf)")
    command.add_argument("--json", action="store_true", help="print one JSON object")


def _spec(model: Model) -> MeasurementSpec:
    spec = model.measurement_section
    if spec is None:
        raise ModelError(Problem("the model has no [measurement] section: add one naming "
                                 "the excitation channel, the input and the response "
                                 "channels (docs/testing.md)", model.source, "measurement"))
    return spec


def _read(path: str) -> MeasuredData:
    return read_uff(path) if Path(path).suffix.lower() in UFF_SUFFIXES else \
        read_histories(path)


def _band_of(args: argparse.Namespace) -> tuple[float, float] | None:
    if args.start is None and args.stop is None:
        return None
    return (args.start or 0.0, args.stop if args.stop is not None else float("inf"))


def _emit(result: object, args: argparse.Namespace, text: str, warnings: tuple[str, ...]
          ) -> int:
    if args.json:
        cli.emit_json(result.to_dict())  # type: ignore[attr-defined]
    else:
        sys.stdout.write(text)
    cli.warn(warnings)
    return 0


def _run_frf_matrix(args: argparse.Namespace, model: Model, spec: MeasurementSpec,
                    data: MeasuredData, deadline: Deadline) -> int:
    """``resonant frf`` with several inputs: the H1 matrix."""
    if args.estimator != "H1":
        raise ModelError(Problem("with several inputs, resonant frf estimates the H1 matrix "
                                 "(leave out --estimator)", model.source, "measurement",
                                 "excitation"))
    result = frf_matrix_from_measurement(
        data, spec, model.source, window=args.window, segment=args.segment,
        overlap=args.overlap, force_window=args.force_window, exponential=args.exponential,
        band=_band_of(args), deadline=deadline)
    if args.save:
        force = data.function(result.inputs[0]).ordinate_unit
        units = {c: f"{data.function(c).ordinate_unit}/{force}" if force and
                 data.function(c).ordinate_unit else "" for c in result.outputs}
        write_uff(cli.writable_output(args.save, "the FRF matrix"),
                  result.to_measured(Path(args.save).name, units,
                                     _saved_dofs(model, spec, deadline)))
    if args.plot:
        result.plot(args.plot)
    return _emit(result, args, result.summary(), result.warnings)


def _saved_dofs(model: Model, spec: MeasurementSpec, deadline: Deadline
                ) -> dict[str, tuple[int, int]]:
    """The nodes and directions ``--save`` writes; the system is built only where an input
    is a signal, to trace it to the coordinate it loads (a large import's coordinate inputs
    need none)."""
    if all(name in model.coordinates for name in spec.model_inputs):
        return measurement_dofs(spec, model.coordinates)
    return saved_dofs(spec, linear_system(model, deadline), deadline)


def run_frf(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    spec = _spec(model)
    data = _read(args.data)
    if len(spec.references) > 1:
        return _run_frf_matrix(args, model, spec, data, deadline)
    result = frf_from_measurement(data, spec, model.source, estimator=args.estimator,
                                  window=args.window, segment=args.segment,
                                  overlap=args.overlap, force_window=args.force_window,
                                  exponential=args.exponential, band=_band_of(args),
                                  deadline=deadline)
    if args.save:
        write_uff(cli.writable_output(args.save, "the FRFs"),
                  result.to_measured(Path(args.save).name,
                                     _saved_dofs(model, spec, deadline),
                                     spec.excitation))
    if args.plot:
        own = model_frf(linear_system(model, deadline), spec.input, result.frequency,
                        spec.channels, deadline=deadline) if spec.input else None
        result.plot(args.plot, model=own)
    return _emit(result, args, result.summary(cli.shown_units(args, model)), ())


def _identified(args: argparse.Namespace, model: Model, deadline: Deadline
                ) -> tuple[MeasurementSpec, ModalIdentification]:
    spec = _spec(model)
    data = _read(args.frfs)
    derivatives = {c.derivative for c in spec.channels.values()}
    if len(derivatives) > 1:
        raise ModelError(Problem("identify the channels of one kind at a time (all "
                                 "displacements, velocities or accelerations)", model.source,
                                 "measurement.channels"))
    band = _band_of(args) or (0.0, float("inf"))
    near = [float(x) for x in args.near.split(",") if x.strip()] if args.near else None
    if len(spec.references) > 1:
        f, H, _ = frf_matrix_of(data, list(spec.channels), [r[0] for r in spec.references])
        lines = (f >= band[0]) & (f <= band[1])
        return spec, identify_modes_matrix(
            f[lines], H[lines], list(spec.channels), [r[0] for r in spec.references],
            max_order=args.order, derivative=derivatives.pop(), near=near,
            added_decay=args.added_decay, deadline=deadline)
    frfs = {f.name: f for f in data.functions if f.kind == "frf"}
    if not frfs:
        raise ModelError(Problem("the file holds no FRF (dataset 58, function type 4)",
                                 data.source))
    match_channels(MeasurementSpec("", spec.input, spec.channels), list(frfs), model.source,
                   data.source)
    f = np.asarray(frfs[next(iter(spec.channels))].abscissa)
    lines = (f >= band[0]) & (f <= band[1])
    try:
        chosen = {c: np.asarray(frfs[c].ordinate)[lines] for c in spec.channels}
    except IndexError:
        raise ModelError(Problem("the FRFs of the channels have different lines",
                                 data.source)) from None
    return spec, identify_modes(f[lines], chosen, max_order=args.order,
                                derivative=derivatives.pop(), near=near,
                                added_decay=args.added_decay, deadline=deadline)


def run_identify(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    _, result = _identified(args, model, deadline)
    if args.plot:
        result.plot(args.plot)
    return _emit(result, args, result.summary(cli.shown_units(args, model)), result.warnings)


def run_correlate(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    spec, identified = _identified(args, model, deadline)
    result = correlate(identified, linear_system(model, deadline), spec.channels,
                       deadline=deadline)
    if args.plot:
        result.plot(args.plot)
    return _emit(result, args, result.summary(cli.shown_units(args, model)), identified.warnings)


def _bounds(items: list[str]) -> Mapping[str, tuple[str, str]]:
    bounds = {}
    for item in items:
        name, _, rest = item.partition("=")
        low, _, high = rest.partition(":")
        if not name.strip() or not low.strip() or not high.strip():
            raise ModelError(Problem(f"--vary takes NAME=LOW:HIGH, got "
                                     f"'{printable(item, limit=60)}'", "--vary"))
        bounds[name.strip()] = (low.strip(), high.strip())
    if not bounds:
        raise ModelError(Problem("give at least one parameter to fit: --vary NAME=LOW:HIGH",
                                 "--vary"))
    return bounds


def _measured_frfs(args: argparse.Namespace, model: Model
                   ) -> tuple[MeasurementSpec, np.ndarray, dict[str, np.ndarray],
                              dict[str, str], str | dict[str, str]]:
    """The spec, the lines (within the band, above 0 Hz), each channel's measured FRF (each
    response/input pair's, with several inputs), their units and the input(s) they are
    measured to."""
    spec = _spec(model)
    if not spec.input:
        raise ModelError(Problem("fitting FRFs needs the input they are measured to",
                                 model.source, "measurement", "input"))
    data = _read(args.frfs)
    band = _band_of(args) or (0.0, float("inf"))
    if len(spec.references) > 1:
        labels = dict(spec.references)
        f, H, units = frf_matrix_of(data, list(spec.channels), list(labels))
        lines = (f >= band[0]) & (f <= band[1]) & (f > 0)
        if not lines.any():
            raise ModelError(Problem("no spectral line in the band", data.source))
        measured = {pair_name(c, i): H[lines, r, k] for r, c in enumerate(spec.channels)
                    for k, i in enumerate(labels)}
        return spec, f[lines], measured, units, labels
    frfs = {f.name: f for f in data.functions if f.kind == "frf"}
    if not frfs:
        raise ModelError(Problem("the file holds no FRF (dataset 58, function type 4)",
                                 data.source))
    match_channels(MeasurementSpec("", spec.input, spec.channels), list(frfs), model.source,
                   data.source)
    f = np.asarray(frfs[next(iter(spec.channels))].abscissa)
    lines = (f >= band[0]) & (f <= band[1]) & (f > 0)
    if not lines.any():
        raise ModelError(Problem("no spectral line in the band", data.source))
    if any(len(frfs[c].ordinate) != len(f) for c in spec.channels):
        raise ModelError(Problem("the FRFs of the channels have different lines",
                                 data.source))
    return spec, f[lines], {c: np.asarray(frfs[c].ordinate)[lines] for c in spec.channels}, \
        {c: frfs[c].ordinate_unit for c in spec.channels}, spec.input


def _run_multi_start(args: argparse.Namespace, model: Model,
                     bounds: Mapping[str, tuple[str, str]], deadline: Deadline) -> int:
    data: dict[str, object]
    if args.fit == "frf":
        spec, lines, measured, units, signal = _measured_frfs(args, model)
        data = {"frequency": lines, "measured": measured, "signal": signal,
                "channels": spec.channels, "residual": args.residual, "sigma": args.sigma,
                "units": units}
        warnings: tuple[str, ...] = ()
    else:
        spec, identified = _identified(args, model, deadline)
        data = {"target_frequency": identified.frequency, "target_shapes": identified.shapes,
                "channels": spec.channels, "sigma": args.sigma}
        warnings = identified.warnings
    result = multi_start_update(model, bounds, args.fit, data, starts=args.starts,
                                engine=engine_for(args.workers, args.scheduler,
                                                  deadline=deadline), deadline=deadline)
    if args.plot:
        result.best.plot(args.plot)
    return _emit(result, args, result.summary(), warnings + result.warnings)


def run_update(args: argparse.Namespace) -> int:
    deadline = cli.deadline(args)
    model = cli.load_model(args)
    bounds = _bounds(args.vary)
    if args.starts > 1:
        return _run_multi_start(args, model, bounds, deadline)
    if args.fit == "frf":
        spec, lines, measured, units, signal = _measured_frfs(args, model)
        fitted = update_to_frf(linear_system(model, deadline), bounds, lines, measured,
                               signal, spec.channels, residual=args.residual,
                               sigma=args.sigma, units=units, deadline=deadline)
        if args.plot:
            fitted.plot(args.plot)
        return _emit(fitted, args, fitted.summary(), fitted.warnings)
    spec, identified = _identified(args, model, deadline)
    result = update_parameters(linear_system(model, deadline), bounds, identified.frequency,
                               target_shapes=identified.shapes, channels=spec.channels,
                               sigma=args.sigma, deadline=deadline)
    if args.plot:
        result.plot(args.plot)
    return _emit(result, args, result.summary(cli.shown_units(args, model)),
                 identified.warnings + result.warnings)
