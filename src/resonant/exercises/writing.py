"""Writing a set of variants: statements, solutions, ``key.json`` and ``moodle.xml``."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import AnalysisError
from ..model import loads
from ..model.units import display_units
from ..model.units_display import with_display
from ..report.derivation import derive
from ..report.html import render_html
from ..report.latex import render_latex
from ..report.markdown import render_markdown
from ..studies.engine import Engine, ordered_map
from .key import key_data
from .moodle import moodle_feedback, moodle_xml
from .solutions import solution_report
from .statements import statement_html, statement_md, statement_tex
from .variants import MAX_DERIVED, ExerciseSet, Variant, generate

#: the formats of ``write``
FORMATS = ("html", "md", "tex", "moodle", "json")

# -- writing ------------------------------------------------------------------------------

@dataclass(frozen=True)
class ExerciseJob:
    """What a worker needs to render variants: the model's text and the draw.

    Parameters
    ----------
    text, source, base_dir : str
        The model file's text, its name and its directory.
    overrides : tuple of (str, str)
        Parameter values replacing the file's.
    count, seed : int
        The draw of :func:`~resonant.exercises.generate`.
    formats : tuple of str
    plots : bool
    folder : str
        Where the variants' folders are (figures are written there by the renderer).
    display : tuple of str
        The units the results are shown in (``("mm", "Hz")``), over the model's
        ``[display]``.
    """

    text: str
    source: str
    base_dir: str
    overrides: tuple[tuple[str, str], ...]
    count: int
    seed: int
    formats: tuple[str, ...]
    plots: bool
    folder: str
    display: tuple[str, ...] = ()


#: rendered sets of this process, by job: a worker draws and derives once
_RENDERERS: dict[ExerciseJob, tuple[ExerciseSet, Any]] = {}


def _derivation(batch: ExerciseSet, formats: Sequence[str]) -> Any:
    solutions = any(f in formats for f in ("html", "md", "tex", "moodle"))
    eom = batch.eom
    equations = eom.symbolic()
    derived = eom.derived_matrices() is not None
    return derive(equations) if solutions and equations is not None and derived \
        and eom.n <= MAX_DERIVED else None


def render_variants(job: ExerciseJob, start: int, stop: int) -> list[Rendered]:
    """Variants ``start`` to ``stop - 1`` of the job, rendered (a task of the engine).

    Parameters
    ----------
    job : ExerciseJob
    start, stop : int
        Indices into the variants.

    Returns
    -------
    list
        Per variant: its number, file name -> text, and its Moodle feedback.
    """
    if job not in _RENDERERS:
        model = with_display(loads(job.text, source=job.source, base_dir=job.base_dir,
                                   overrides=dict(job.overrides)), display_units(job.display))
        batch = generate(model, job.count, job.seed)
        _RENDERERS[job] = (batch, _derivation(batch, job.formats))
    batch, derivation = _RENDERERS[job]
    title = batch.model.title or Path(batch.model.source).stem or "Exercise"
    return [_render(v, batch, derivation, job.formats, job.plots, title,
                    Path(job.folder) / str(v.number)) for v in batch.variants[start:stop]]


Rendered = tuple[int, dict[str, str], Any]


def _render(v: Variant, batch: ExerciseSet, derivation: Any, formats: Sequence[str],
            plots: bool, title: str, sub: Path) -> Rendered:
    """One variant's files (figures written into ``sub`` by the renderers)."""
    ex = batch.exercise
    sub.mkdir(parents=True, exist_ok=True)
    solutions = any(f in formats for f in ("html", "md", "tex", "moodle"))
    report = solution_report(v, derivation, plots) if solutions else None
    texts: dict[str, str] = {}
    if "html" in formats and report is not None:
        texts["statement.html"] = statement_html(v, ex, title)
        texts["solution.html"] = render_html(report)
    if "md" in formats and report is not None:
        texts["statement.md"] = statement_md(v, ex, title)
        texts["solution.md"] = render_markdown(report, sub / "solution.md")
    if "tex" in formats and report is not None:
        texts["statement.tex"] = statement_tex(v, ex, title)
        texts["solution.tex"] = render_latex(report, sub / "solution.tex")
    if "json" in formats:
        texts["solution.json"] = _json(v.solution.to_dict())
    feedback = moodle_feedback(report) if "moodle" in formats and report is not None else None
    return v.number, texts, feedback


#: variants per task when rendering on workers
VARIANTS_PER_TASK = 4


def write(batch: ExerciseSet, folder: str | Path, formats: Sequence[str] = ("html",),
          plots: bool = True, engine: Engine | None = None, job: ExerciseJob | None = None
          ) -> list[Path]:
    """Write every variant's statement and solution, ``key.json`` and (format ``moodle``)
    ``moodle.xml`` into ``folder``.

    Parameters
    ----------
    batch : ExerciseSet
        The variants.
    folder : str or Path
        Where to write (one subfolder per variant).
    formats : sequence of str
        Any of :data:`FORMATS`.
    plots : bool
        Whether the solutions include figures.
    engine : Engine, optional
        Render the variants on Dask workers (:mod:`resonant.studies.engine`); needs
        ``job``, from which each worker draws the same variants again.
    job : ExerciseJob, optional

    Returns
    -------
    list of Path
        The files written (figures excluded).

    Examples
    --------
    >>> import resonant, tempfile
    >>> from resonant.exercises import generate
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 1, seed=1)
    >>> [p.name for p in write(batch, tempfile.mkdtemp(), ["json"], plots=False)]
    ['solution.json', 'key.json']
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    if engine is not None and job is not None and engine.mode != "process":
        tasks = ((job, i, i + VARIANTS_PER_TASK)
                 for i in range(0, len(batch.variants), VARIANTS_PER_TASK))
        rendered = [r for part in ordered_map(render_variants, tasks, engine) for r in part]
    else:
        derivation = _derivation(batch, formats)
        title = batch.model.title or Path(batch.model.source).stem or "Exercise"
        rendered = [_render(v, batch, derivation, formats, plots, title,
                            folder / str(v.number)) for v in batch.variants]
    written: list[Path] = []
    for number, texts, _ in rendered:
        for name, text in texts.items():
            (folder / str(number) / name).write_text(text, encoding="utf-8")
            written.append(folder / str(number) / name)
    key = folder / "key.json"
    key.write_text(_json(key_data(batch)), encoding="utf-8")
    written.append(key)
    if "moodle" in formats:
        path = folder / "moodle.xml"
        path.write_text(moodle_xml(batch, [f for _, _, f in rendered if f is not None]),
                        encoding="utf-8")
        written.append(path)
    return written


def _json(data: object) -> str:
    try:
        return json.dumps(data, indent=2, allow_nan=False) + "\n"
    except ValueError:
        raise AnalysisError("a result holds NaN or infinity and cannot be written as "
                            "JSON; check the parameter values") from None
