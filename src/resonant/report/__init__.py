"""Worked-solution reports: the solution of a model in the order of a textbook exercise.

:func:`build_report` runs the steps of :mod:`resonant.report.steps` and returns
a :class:`~resonant.report.blocks.Report` (headings, paragraphs, numbered
equations, tables, figures); the writers turn it into a self-contained HTML
page (MathML + inline SVG), Markdown (``$$`` LaTeX) or a LaTeX document.

Examples
--------
>>> import pathlib, resonant
>>> from resonant.report import build_report, render
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples" / "two_dof_free.toml"
>>> report = build_report(resonant.load(path))
>>> report.headings()[:2]
['Data', 'Task 1: the linearized equation of motion']
>>> "\\\\omega_{1} = 20" in render(report, "md")
True
"""

from __future__ import annotations

from pathlib import Path

from ..analyses.correlate import Correlation
from ..analyses.measured_match import MatchedTest
from ..analyses.stationary import stationary
from ..errors import AnalysisError, ModelError, Problem
from ..model import Model
from ..system.build import linear_system
from .blocks import Report
from .derivation import derive
from .html import render_html
from .latex import render_latex
from .markdown import render_markdown
from .nonlinear import beyond_small_oscillations
from .steps import Context, step_order

#: largest energy model whose derivation the report shows step by step
MAX_DERIVED = 12

FORMATS = {".html": "html", ".htm": "html", ".md": "md", ".markdown": "md", ".tex": "tex"}


def build_report(model: Model, plots: bool = True, nonlinear: bool = False,
                 correlation: Correlation | None = None,
                 measured: MatchedTest | None = None) -> Report:
    """The worked solution of ``model`` as a list of blocks.

    Parameters
    ----------
    model : Model
        A validated model.
    plots : bool
        Whether to include the figures.
    nonlinear : bool
        Add the section beyond small oscillations (see below).
    correlation : Correlation, optional
        Identified modes against the model's (:func:`resonant.analyses.correlate.correlate`):
        adds the section "Test against model" (pairs, frequency errors, MAC).
    measured : MatchedTest, optional
        Measured FRFs checked against the model
        (:func:`resonant.analyses.measured_match.match_test`): adds the section "Measured
        against model FRFs" (FRAC, the figure of both).

    Returns
    -------
    Report
        The blocks of the worked solution, in the reference exercise's order.

    ``nonlinear=True`` adds the section "Beyond small oscillations" (the periodic steady
    state of the full equations by harmonic balance, :mod:`resonant.report.nonlinear`)
    for a forced model, before the warnings.

    Raises
    ------
    ModelError, AnalysisError
        As ``resonant solve`` does (invalid model; resonance, singular M).

    Examples
    --------
    >>> import resonant
    >>> build_report(resonant.load("examples/two_dof_free.toml"), plots=False).headings()[0]
    'Data'
    """
    eom = linear_system(model)
    solution = stationary(eom)
    # the source-by-source derivation (a second, independent one, checked against the
    # solver's) is shown element by element only for small models: above MAX_DERIVED
    # coordinates it would cost what a full symbolic Lagrange derivation costs
    equations = eom.symbolic()
    if equations is None:
        raise AnalysisError("a report needs the system's equations in symbols; this one is "
                            "given by numbers only")
    derived = eom.derived_matrices() is not None
    derivation = derive(equations) if derived and eom.n <= MAX_DERIVED else None
    ctx = Context(model, eom, equations, solution, derivation, plots=plots,
                  correlation=correlation, measured=measured)
    steps = step_order(ctx)
    if nonlinear and ctx.eom.excitation:
        steps.insert(len(steps) - 1, beyond_small_oscillations)  # before the warnings
    blocks = []
    for step in steps:
        blocks.extend(step(ctx))
    return Report(model.title or Path(model.source).stem or "Worked solution", tuple(blocks))


def render(report: Report, fmt: str, figure_path: Path | None = None) -> str:
    """The report as text: ``fmt`` is ``"html"``, ``"md"`` or ``"tex"``.

    Parameters
    ----------
    report : Report
        What :func:`build_report` returns.
    fmt : str
        ``"html"``, ``"md"`` or ``"tex"``.
    figure_path : Path, optional
        The output file, next to which figures are written (Markdown, LaTeX).

    Returns
    -------
    str
        The document.

    Markdown and LaTeX figures are written next to ``figure_path`` (the
    output file) as ``<stem>-figN.svg`` / ``.pdf``; without it they are left out.

    Examples
    --------
    >>> import resonant
    >>> report = build_report(resonant.load("examples/two_dof_free.toml"), plots=False)
    >>> render(report, "md").startswith("# ")
    True
    """
    if fmt == "html":
        return render_html(report)
    if fmt == "md":
        return render_markdown(report, figure_path)
    if fmt == "tex":
        return render_latex(report, figure_path)
    raise ValueError(f"unknown report format '{fmt}'")


def report_format(path: str | Path) -> str:
    """The format of an output file from its ending.

    Parameters
    ----------
    path : str or Path
        The output file.

    Returns
    -------
    str
        ``"html"``, ``"md"`` or ``"tex"``.

    Raises
    ------
    ModelError
        For an ending that is none of these.

    Examples
    --------
    >>> report_format("solution.markdown")
    'md'
    """
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ModelError(Problem(f"cannot tell the report format from '{path}': use a file "
                                 "ending in .html, .md or .tex", "-o"))
    return FORMATS[suffix]


def write_report(model: Model, path: str | Path, plots: bool = True) -> Path:
    """Write the worked solution of ``model`` to ``path`` (.html, .md or .tex).

    Parameters
    ----------
    model : Model
        A validated model.
    path : str or Path
        The output file; its ending gives the format.
    plots : bool
        Whether to include the figures.

    Returns
    -------
    Path
        The file written.

    Examples
    --------
    >>> import pathlib, tempfile, resonant
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "solution.md"
    >>> write_report(resonant.load("examples/two_dof_free.toml"), out, plots=False).name
    'solution.md'
    """
    path = Path(path)
    fmt = report_format(path)
    text = render(build_report(model, plots=plots), fmt, path)
    path.write_text(text, encoding="utf-8")
    return path


__all__ = ["build_report", "render", "write_report", "report_format", "Report"]
