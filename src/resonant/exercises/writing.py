"""Writing a set of variants: statements, solutions, ``key.json`` and ``moodle.xml``."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..errors import AnalysisError
from ..report.derivation import derive
from ..report.html import render_html
from ..report.latex import render_latex
from ..report.markdown import render_markdown
from ..system import LinearEOM
from .key import key_data
from .moodle import moodle_feedback, moodle_xml
from .solutions import solution_report
from .statements import statement_html, statement_md, statement_tex
from .variants import MAX_DERIVED, ExerciseSet

#: the formats of ``write``
FORMATS = ("html", "md", "tex", "moodle", "json")

# -- writing ------------------------------------------------------------------------------

def write(batch: ExerciseSet, folder: str | Path, formats: Sequence[str] = ("html",),
          plots: bool = True) -> list[Path]:
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
    ex = batch.exercise
    title = batch.model.title or Path(batch.model.source).stem or "Exercise"
    eom = batch.eom
    solutions = any(f in formats for f in ("html", "md", "tex", "moodle"))
    derivation = derive(eom) if solutions and isinstance(eom, LinearEOM) \
        and eom.n <= MAX_DERIVED else None
    written: list[Path] = []
    feedback: list[tuple[str, list[tuple[str, bytes]]]] = []
    folder.mkdir(parents=True, exist_ok=True)
    for v in batch.variants:
        sub = folder / str(v.number)
        sub.mkdir(exist_ok=True)
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
        for name, text in texts.items():
            (sub / name).write_text(text, encoding="utf-8")
            written.append(sub / name)
        if "moodle" in formats and report is not None:
            feedback.append(moodle_feedback(report))
    key = folder / "key.json"
    key.write_text(_json(key_data(batch)), encoding="utf-8")
    written.append(key)
    if "moodle" in formats:
        path = folder / "moodle.xml"
        path.write_text(moodle_xml(batch, feedback), encoding="utf-8")
        written.append(path)
    return written


def _json(data: Any) -> str:
    try:
        return json.dumps(data, indent=2, allow_nan=False) + "\n"
    except ValueError:
        raise AnalysisError("a result holds NaN or infinity and cannot be written as "
                            "JSON; check the parameter values") from None
