"""Running a study: samples chunk by chunk on an engine, rows streamed to a file.

:func:`run_study` cuts the study into chunks (:mod:`.designs`), has the
engine (:mod:`.engine`) evaluate them (:func:`evaluate_chunk`, the batched
quantities of :mod:`.quantities`) and writes the rows in chunk order
(:mod:`.files`).  A task carries the model's *text* (with its source, the
directory its matrix files are read from, and the overrides), never derived
objects: each worker process derives the model once and keeps it for every
chunk it is given.

Examples
--------
>>> import resonant
>>> model = resonant.load("examples/cart_pendulum.toml")
>>> job = StudyJob.of(model, request(model, {"k": "uniform(90, 110)"},
...                                 ["natural_frequency:1"], samples=8))
>>> rows = evaluate_chunk(job, 0, 8)
>>> sorted(rows)[:3], len(rows["sample"])
(['k', 'natural_frequency:1', 'reason'], 8)
"""

from __future__ import annotations

import hashlib
import math
import os
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..deadline import NO_DEADLINE, Deadline, DeadlineExceeded
from ..errors import ModelError, Problem
from ..model import Model, loads
from ..model.files import open_regular_file, read_bounded
from ..model.limits import MAX_FILE_BYTES
from ..model.study import RESERVED_COLUMNS, StudySpec, rotor_problems, study_spec
from ..system.base import LinearSystem
from ..system.build import linear_system, nonlinear_system
from ..system.nonlinear import NonlinearSystem
from .designs import chunk_size, chunk_values, chunks
from .engine import Engine, engine_for, ordered_map
from .files import ResultWriter, check_output, check_rows, completed_rows, read_description
from .quantities import empty_rows, evaluate_samples
from .result import StudyResult, sobol_indices

if TYPE_CHECKING:
    from dask.distributed import Client

#: the default engine: this process, or local workers when the work pays for them
AUTO = Engine()
#: derived systems of this process, by job key: a worker derives each model once
_SYSTEMS: dict[str, LinearSystem] = {}
_NONLINEAR: dict[str, NonlinearSystem] = {}


def model_text(model: Model) -> tuple[str, str]:
    """The text of a model's file and its directory (what travels to the workers).

    Parameters
    ----------
    model : Model

    Returns
    -------
    tuple of str

    Raises
    ------
    ModelError
        For a model that was not loaded from a file.

    Examples
    --------
    >>> import resonant
    >>> text, folder = model_text(resonant.load("examples/cart_pendulum.toml"))
    >>> "[energy]" in text
    True
    """
    path = Path(model.source)
    if not path.is_file():
        raise ModelError("workers need the model's text: this model was not loaded from a "
                         "file (give text=)")
    with open_regular_file(path, follow_symlinks=True, max_bytes=MAX_FILE_BYTES) as handle:
        text = read_bounded(handle, MAX_FILE_BYTES).decode("utf-8")
    return text, str(path.resolve().parent)


@dataclass(frozen=True)
class StudyJob:
    """What every task of a study needs: the model as text, and the request.

    Parameters
    ----------
    text : str
        The model file's text.
    source : str
        Its name (for messages; relative matrix files are found from ``base_dir``).
    base_dir : str
        The directory of the model file.
    overrides : tuple of (str, str)
        Parameter values replacing the file's (``--set``).
    spec : StudySpec
    allow_paths : tuple of str
        Further folders matrix files may be read from (absolute).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> job = StudyJob.of(model, request(model, {"k": [90, 110]}, ["stable"]))
    >>> job.spec.vary["k"].arguments, len(job.key)
    ((90.0, 110.0), 64)
    """

    text: str
    source: str
    base_dir: str
    overrides: tuple[tuple[str, str], ...]
    spec: StudySpec
    allow_paths: tuple[str, ...] = ()

    @classmethod
    def of(cls, model: Model, spec: StudySpec, text: str | None = None,
           overrides: Mapping[str, Any] | None = None,
           allow_paths: Sequence[str | os.PathLike[str]] = ()) -> StudyJob:
        """The job of a loaded model (its file is read again for the text).

        Parameters
        ----------
        model : Model
        spec : StudySpec
        text : str, optional
            The model's text, for a model that was not loaded from a file.
        overrides : mapping, optional
        allow_paths : sequence of paths, optional
            Further folders the model's matrix files may be read from.

        Returns
        -------
        StudyJob
        """
        if text is None:
            text, base_dir = model_text(model)
        else:
            base_dir = os.getcwd()
        pairs = tuple(sorted((str(k), str(v)) for k, v in (overrides or {}).items()))
        return cls(text, model.source, base_dir, pairs, spec,
                   tuple(str(Path(p).resolve()) for p in allow_paths))

    @property
    def key(self) -> str:
        """A digest of the model's text, source and overrides."""
        digest = hashlib.sha256(self.text.encode())
        digest.update(repr((self.source, self.base_dir, self.overrides)).encode())
        if self.allow_paths:
            digest.update(repr(self.allow_paths).encode())
        return digest.hexdigest()


def request(model: Model, vary: Mapping[str, Any] | None = None,
            quantities: Sequence[str] | None = None, *, design: str | None = None,
            samples: int | None = None, seed: int | None = None,
            band: Mapping[str, Any] | None = None, harmonics: int | None = None) -> StudySpec:
    """A study of ``model``: the arguments given, the rest from its ``[study]`` section.

    Parameters
    ----------
    model : Model
    vary : mapping, optional
        parameter -> specification (see :mod:`resonant.model.study`).
    quantities : sequence of str, optional
    design, samples, seed, band, harmonics : optional
        The study's options (docs/studies.md; ``band`` a mapping with ``parameter``,
        ``from``, ``to``); None: the ``[study]`` section's, or the default.

    Returns
    -------
    StudySpec

    Raises
    ------
    ModelError
        For an invalid request, or none at all (no arguments and no ``[study]``).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/absorber_tolerances.toml")
    >>> request(model, samples=10).design, request(model, samples=10).samples
    ('random', 10)
    """
    base = model.study_section.to_request() if model.study_section is not None else {}
    given = {k: v for k, v in {"vary": vary, "quantities": quantities, "design": design,
                               "samples": samples, "seed": seed, "band": band,
                               "harmonics": harmonics}.items() if v is not None}
    merged = {**base, **given}
    if "vary" not in merged or "quantities" not in merged:
        raise ModelError(Problem("a study needs the parameters to vary and the quantities "
                                 "(or a [study] section in the model)", model.source))
    spec = study_spec(merged.pop("vary"), merged.pop("quantities"), **merged,
                      parameters=model.parameters, coordinates=model.coordinates,
                      outputs=model.outputs, units=model.units, source=model.source,
                      section="study")
    rotor = model.campbell_section
    problems = rotor_problems(spec, rotor is not None, (rotor is not None and rotor.speed
                                                       is not None) or
                              (model.matrices is not None and model.matrices.speed is not None),
                              model.source)
    if problems:
        raise ModelError(problems)
    return spec


def system_of(job: StudyJob) -> LinearSystem:
    """The job's linear system, derived once per process.

    Parameters
    ----------
    job : StudyJob

    Returns
    -------
    LinearSystem
    """
    system = _SYSTEMS.get(job.key)
    if system is None:
        model = loads(job.text, source=job.source, base_dir=job.base_dir,
                      overrides=dict(job.overrides), allow_paths=job.allow_paths)
        system = _SYSTEMS[job.key] = linear_system(model)
    return system


def nonlinear_of(job: StudyJob) -> NonlinearSystem | None:
    """The job's full equations of motion, compiled once per process (None when no
    quantity needs them).

    Parameters
    ----------
    job : StudyJob

    Returns
    -------
    NonlinearSystem or None

    Raises
    ------
    AnalysisError
        For a model that has no full equations (a ``[matrices]`` model).
    """
    if not any(q.kind == "nonlinear_amplitude" for q in job.spec.quantities):
        return None
    system = _NONLINEAR.get(job.key)
    if system is None:
        system = _NONLINEAR[job.key] = nonlinear_system(system_of(job))
    return system


def evaluate_chunk(job: StudyJob, k: int, size: int, seconds: float | None = None
                   ) -> dict[str, np.ndarray]:
    """The rows of chunk ``k``: sample number, varied parameters, quantities, status.

    Parameters
    ----------
    job : StudyJob
    k : int
        The chunk.
    size : int
        Samples per chunk.
    seconds : float, optional
        The time left to the command when the chunk was handed out: the quantities
        computed sample by sample stop with :class:`~resonant.deadline.AnalysisTimeout`
        when it passes (a number travels to a worker, a clock does not).

    Returns
    -------
    dict
        column -> array.

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> job = StudyJob.of(model, request(model, {"k": [90, 110]}, ["stable"], design="grid"))
    >>> evaluate_chunk(job, 1, 1)["k"].tolist()
    [110.0]
    """
    varied = chunk_values(job.spec, k, size)
    count = len(next(iter(varied.values())))
    rows: dict[str, np.ndarray] = {"sample": np.arange(k * size, k * size + count,
                                                       dtype=np.int64)}
    rows.update(varied)
    rows.update(evaluate_samples(system_of(job), job.spec, varied, nonlinear_of(job),
                                 Deadline(seconds, job.source)))
    return rows


class _Bar:
    """A one-line progress bar on standard error."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.enabled, self.done = total, enabled, 0
        self.start = time.perf_counter()

    def advance(self, rows: int) -> None:
        self.done += rows
        if not self.enabled:
            return
        elapsed = time.perf_counter() - self.start
        left = elapsed * (self.total - self.done) / max(self.done, 1)
        filled = int(30 * self.done / max(self.total, 1))
        sys.stderr.write(f"\rstudy [{'#' * filled}{'.' * (30 - filled)}] "
                         f"{self.done}/{self.total} samples, {left:.0f} s left ")
        if self.done >= self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def description(job: StudyJob, size: int) -> dict[str, Any]:
    """What a result file records of its study (checked on resume).

    Parameters
    ----------
    job : StudyJob
    size : int
        Samples per chunk.

    Returns
    -------
    dict
    """
    return {"model": Path(job.source).name,
            "model_sha256": hashlib.sha256(job.text.encode()).hexdigest(),
            "overrides": dict(job.overrides), "study": job.spec.to_dict(), "chunk_size": size,
            "rows": job.spec.size}


def _resume_rows(path: Path, expected: dict[str, Any], size: int, spec: StudySpec) -> int:
    """Rows of complete chunks of an earlier run of the same study at ``path``, checked
    (the file is read back as untrusted input)."""
    if not path.is_file():
        return 0
    found = read_description(path)
    if found != expected:
        raise ModelError(Problem("the file holds a different study (model, request or seed); "
                                 "write to a new file or remove it to start afresh",
                                 str(path)))
    rows = completed_rows(path)
    if rows > expected["rows"]:
        raise ModelError(Problem(f"cannot resume from this file: it holds {rows} rows, more "
                                 f"than the study's {expected['rows']}; remove it to start "
                                 "afresh", str(path)))
    keep = rows if rows == expected["rows"] else (rows // size) * size
    check_rows(path, ["sample", *spec.vary, *spec.columns, *RESERVED_COLUMNS[1:]],
               RESERVED_COLUMNS[1:], keep)
    return keep


@dataclass(frozen=True)
class RunSummary:
    """What :func:`run_study` did.

    Parameters
    ----------
    path : Path
        The result file.
    rows : int
        Rows in it.
    resumed_rows : int
        Rows kept from an earlier run.
    where : str
        Where the chunks ran.
    seconds : float
    description : dict
    table : pandas.DataFrame or None
        The rows' ``keep`` columns as written (Parquet), or None.

    Examples
    --------
    >>> import resonant, tempfile, os
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> job = StudyJob.of(model, request(model, {"k": [90, 110]}, ["stable"], design="grid"))
    >>> run_study(job, os.path.join(tempfile.mkdtemp(), "r.csv"), Engine("process")).rows
    2
    """

    path: Path
    rows: int
    resumed_rows: int
    where: str
    seconds: float
    description: dict[str, Any]
    table: Any = None


def run_study(job: StudyJob, output: str | os.PathLike[str], engine: Engine = AUTO, *,
              resume: bool = False, progress: bool | None = None,
              deadline: Deadline = NO_DEADLINE,
              on_chunk: Callable[[dict[str, np.ndarray]], None] | None = None,
              keep: list[str] | None = None) -> RunSummary:
    """Run a study and stream its rows to ``output`` (.parquet or .csv).

    Parameters
    ----------
    job : StudyJob
    output : str or path
    engine : Engine
        Where the chunks run.
    resume : bool
        Keep the complete chunks of an interrupted earlier run and continue.
    progress : bool, optional
        A progress bar on standard error (default: when it is a terminal).
    deadline : Deadline, optional
        Checked between chunks; when it passes, the file keeps the rows so far.
    on_chunk : callable, optional
        Also given every chunk's rows, in order.
    keep : list of str, optional
        Columns of a Parquet file's rows to return in ``RunSummary.table`` as written
        (the file is not read back for them).

    Returns
    -------
    RunSummary

    Examples
    --------
    >>> import resonant, tempfile, os
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> job = StudyJob.of(model, request(model, {"k": "uniform(90, 110)"}, ["stable"],
    ...                                  samples=5))
    >>> run_study(job, os.path.join(tempfile.mkdtemp(), "r.parquet"), Engine("process")).rows
    5
    """
    path = check_output(output)
    size = chunk_size(job.spec, system_of(job).n)
    nonlinear_of(job)  # a model without full equations fails here, before any file
    expected = description(job, size)
    kept = _resume_rows(path, expected, size, job.spec) if resume else 0
    bar = _Bar(job.spec.size, sys.stderr.isatty() if progress is None else progress)
    bar.advance(kept)
    where = ["this process"]
    writer = ResultWriter(path, expected, kept, empty_rows(job.spec), keep)
    start = time.perf_counter()
    stopped = False  # by an interrupt or the time limit: the file is left for a resume
    try:
        tasks = ((job, k, size, deadline.remaining())
                 for k, _, _ in chunks(job.spec, size, math.ceil(kept / size)))
        for rows in ordered_map(evaluate_chunk, tasks, engine,
                                on_start=lambda w: where.__setitem__(0, w)):
            writer.write(rows)
            bar.advance(len(rows["sample"]))
            if on_chunk is not None:
                on_chunk(rows)
            deadline.check("while running the study", analysis=True)
    except (KeyboardInterrupt, DeadlineExceeded):
        stopped = True
        raise
    finally:
        writer.close(stopped)
    return RunSummary(path, writer.rows, kept, where[0], time.perf_counter() - start, expected,
                      writer.kept_rows())


def collect(job: StudyJob, engine: Engine = AUTO,
            output: str | os.PathLike[str] | None = None, *, resume: bool = False,
            progress: bool | None = None, deadline: Deadline = NO_DEADLINE,
            columns: list[str] | None = None) -> StudyResult:
    """Run a study and return its result (the rows also written to ``output`` if given).

    Parameters
    ----------
    job : StudyJob
    engine : Engine
    output : str or path, optional
        A .parquet or .csv file.
    resume : bool
        Continue an interrupted run of ``output``.
    progress : bool, optional
    deadline : Deadline, optional
    columns : list of str, optional
        The columns to read back from ``output`` (default all; fewer keep the memory
        of a huge study small).

    Returns
    -------
    StudyResult

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> job = StudyJob.of(model, request(model, {"k": [90, 110]}, ["stable"], design="grid"))
    >>> collect(job, Engine("process")).table["stable"].tolist()
    [True, True]
    """
    import pandas as pd

    parts: list[dict[str, np.ndarray]] = []
    if output is not None:
        # the rows as written (Parquet) instead of reading the file back
        summary = run_study(job, output, engine, resume=resume, progress=progress,
                            deadline=deadline, keep=columns or list(empty_rows(job.spec)))
        table = summary.table if summary.table is not None else read_table(summary.path,
                                                                            columns)
        where, found = summary.where, summary.description
    else:
        size = chunk_size(job.spec, system_of(job).n)
        nonlinear_of(job)
        found = description(job, size)
        places = ["this process"]
        bar = _Bar(job.spec.size, sys.stderr.isatty() if progress is None else progress)
        for rows in ordered_map(evaluate_chunk, ((job, k, size, deadline.remaining())
                                                 for k, _, _ in chunks(job.spec, size)),
                                engine,
                                on_start=lambda w: places.__setitem__(0, w)):
            parts.append(rows)
            bar.advance(len(rows["sample"]))
            deadline.check("while running the study", analysis=True)
        table = pd.concat([pd.DataFrame(p) for p in parts], ignore_index=True)
        where = places[0]
    sensitivity = sobol_indices(table, job.spec) if job.spec.design == "sobol" else None
    return StudyResult(table, job.spec, found, sensitivity, where)


def read_table(path: str | os.PathLike[str], columns: list[str] | None = None) -> Any:
    """The rows of a result file as a DataFrame (status and reason as categories).

    Parameters
    ----------
    path : str or path
    columns : list of str, optional
        Only these columns.

    Returns
    -------
    pandas.DataFrame

    Examples
    --------
    >>> import resonant, tempfile, os
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> job = StudyJob.of(model, request(model, {"k": [90, 110]}, ["stable"], design="grid"))
    >>> path = os.path.join(tempfile.mkdtemp(), "r.parquet")
    >>> list(read_table(run_study(job, path, Engine("process")).path).columns)
    ['sample', 'k', 'stable', 'status', 'reason']
    """
    import pandas as pd

    p = Path(path)
    if p.suffix.lower() == ".parquet":
        return pd.read_parquet(p, columns=columns)
    frame = pd.read_csv(p, usecols=columns, keep_default_na=False,
                        na_values=["", "NaN", "nan"],
                        dtype={"status": "category", "reason": "category"})
    if "reason" in frame:
        frame["reason"] = frame["reason"].cat.add_categories([""]).fillna("") \
            if "" not in frame["reason"].cat.categories else frame["reason"].fillna("")
    return frame


__all__ = ["collect", "model_text", "read_table", "RunSummary", "StudyJob", "evaluate_chunk",
           "request", "run_study", "system_of", "nonlinear_of"]


def study_of(model: Model, vary: Mapping[str, Any] | None = None,
             quantities: Sequence[str] | None = None, *,
             output: str | os.PathLike[str] | None = None, workers: int | None = None,
             scheduler: str | None = None, client: Client | None = None, resume: bool = False,
             progress: bool | None = None, design: str | None = None,
             samples: int | None = None, seed: int | None = None,
             band: Mapping[str, Any] | None = None, harmonics: int | None = None
             ) -> StudyResult:
    """A parameter study of ``model`` (docs/studies.md): the arguments given, the rest from
    its ``[study]`` section (:func:`request`), run on the engine the arguments choose
    (:func:`resonant.studies.engine.engine_for`) and collected (:func:`collect`).

    Parameters
    ----------
    model : Model
    vary : mapping, optional
        parameter -> ``"uniform(a, b)"``, ``"normal(mean, sd)"``, ``"lognormal(mean, sd)"``,
        a list or ``{"from":, "to":, "step":}``.
    quantities : sequence of str, optional
        ``natural_frequency:I``, ``damping_ratio:I``, ``amplitude:NAME``, ``phase:NAME``,
        ``peak:NAME``, ``stable``, ``nonlinear_amplitude:NAME``, ...
    output : str or Path, optional
        Also write the rows there (.parquet or .csv).
    workers : int, optional
        Local worker processes (0: this process; default: chosen by the work).
    scheduler : str, optional
        A Dask scheduler's address.
    client : distributed.Client, optional
        A Dask client of yours.
    resume : bool
        Continue an interrupted study of ``output``.
    progress : bool, optional
        A progress bar on standard error.
    design, samples, seed, band, harmonics
        The study's options (docs/studies.md); None: the ``[study]`` section's or the
        default.

    Returns
    -------
    StudyResult

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> result = study_of(model, {"k": "uniform(90, 110)"}, ["natural_frequency:1"],
    ...                   samples=200, seed=1, workers=0)
    >>> round(float(result.summary().loc["natural_frequency:1", "mean"]), 2)
    4.56
    """
    spec = request(model, vary, quantities, design=design, samples=samples, seed=seed,
                   band=band, harmonics=harmonics)
    return collect(StudyJob.of(model, spec), engine_for(workers, scheduler, client), output,
                   resume=resume, progress=progress)
