"""A Moodle XML question bank: one Cloze question per variant, the worked solution as its
feedback (TeX for Moodle's MathJax filter, figures as files)."""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Sequence
from pathlib import Path

from ..errors import AnalysisError, printable
from ..report.blocks import Equation, Figure, Heading, Math, Note, Paragraph, Part, Report, Table
from ..report.plots import to_svg
from .statements import _h, statement_html_body
from .variants import Answer, ExerciseSet


def _tex_html(latex: str) -> str:
    return html.escape(latex, quote=False)


def moodle_feedback(report: Report) -> tuple[str, list[tuple[str, bytes]]]:
    """The report as HTML for Moodle (TeX in \\( \\) and \\[ \\] for its MathJax filter) and
    its figures as files (name, SVG bytes) referenced by ``@@PLUGINFILE@@``.

    Parameters
    ----------
    report : Report
        A variant's worked solution.

    Returns
    -------
    tuple
        The HTML text and the list of (file name, SVG bytes).

    Examples
    --------
    >>> from resonant.report.blocks import Heading, Report
    >>> moodle_feedback(Report("t", (Heading("Data", 1),)))
    ('<h2>Data</h2>', [])
    """
    def inline(parts: tuple[Part, ...]) -> str:
        return "".join(r"\(" + _tex_html(p.latex) + r"\)" if isinstance(p, Math) else _h(p)
                       for p in parts)

    out: list[str] = []
    files: list[tuple[str, bytes]] = []
    for block in report.blocks:
        if isinstance(block, Heading):
            level = min(6, block.level + 1)
            out.append(f"<h{level}>{_h(block.text)}</h{level}>")
        elif isinstance(block, Paragraph):
            out.append(f"<p>{inline(block.parts)}</p>")
        elif isinstance(block, Equation):
            tag = rf" \tag{{{block.number}}}" if block.number is not None else ""
            out.append(r"<p>\[" + _tex_html(" ".join(block.latex.split())) + tag + r"\]</p>")
        elif isinstance(block, Table):
            head = "".join(f"<th>{inline(c)}</th>" for c in block.header)
            rows = "".join("<tr>" + "".join(f"<td>{inline(c)}</td>" for c in row) + "</tr>"
                           for row in block.rows)
            out.append(f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>")
        elif isinstance(block, Note):
            out.append(f"<p><b>Warning:</b> {inline(block.parts)}</p>")
        elif isinstance(block, Figure):
            name = f"figure{block.number}.svg"
            svg = to_svg(block.plot, block.number)
            files.append((name, ('<?xml version="1.0" encoding="utf-8"?>\n' + svg).encode()))
            out.append(f'<p><img src="@@PLUGINFILE@@/{name}" alt="Figure {block.number}" '
                       f'style="max-width:100%"></p><p>Figure {block.number}: '
                       f"{_h(block.caption)}</p>")
    return "\n".join(out), files


def _number(value: float) -> str:
    text = repr(float(value))
    if not math.isfinite(value):
        raise AnalysisError(f"an answer is not finite ({text}); it cannot be a Moodle answer")
    return text


def cloze(value: float, tolerance: float) -> str:
    """One NUMERICAL sub-question: ``{1:NUMERICAL:=value:absolute tolerance}``.

    Parameters
    ----------
    value : float
        The right answer.
    tolerance : float
        The relative tolerance.

    Returns
    -------
    str
        The Cloze text.

    Examples
    --------
    >>> cloze(-0.5, 0.01)
    '{1:NUMERICAL:=-0.5:0.005}'
    """
    return f"{{1:NUMERICAL:={_number(value)}:{_number(tolerance * abs(value))}}}"


def _cloze_answer(answer: Answer, tolerance: float) -> str:
    value = answer.value
    if isinstance(value, list) and value and isinstance(value[0], list):
        rows = "".join("<tr>" + "".join(f"<td>{cloze(x, tolerance)}</td>" for x in row)
                       + "</tr>" for row in value)
        return f"<table class=\"matrix\">{rows}</table>"
    if isinstance(value, list):
        return "<table class=\"vector\">" + "".join(
            f"<tr><td>{cloze(x, tolerance)}</td></tr>" for x in value) + "</table>"
    return cloze(value, tolerance)


def _cdata(text: str) -> str:
    return "<![CDATA[" + text.replace("]]>", "]]]]><![CDATA[>") + "]]>"


def _xml(text: str) -> str:
    return html.escape(printable(text, limit=None), quote=True)


def moodle_xml(batch: ExerciseSet, feedback: Sequence[tuple[str, list[tuple[str, bytes]]]]
               ) -> str:
    """A Moodle XML question bank: one category, one Cloze question per variant.

    Parameters
    ----------
    batch : ExerciseSet
        The variants.
    feedback : sequence
        Per variant the feedback of :func:`moodle_feedback`.

    Returns
    -------
    str
        The XML document.

    Examples
    --------
    >>> import resonant
    >>> from resonant.exercises import generate
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 2, seed=1)
    >>> xml = moodle_xml(batch, [("", [])] * 2)
    >>> xml.count('<question type="cloze">')
    2
    """
    ex = batch.exercise
    title = batch.model.title or Path(batch.model.source).stem or "exercise"
    category = "$course$/top/resonant/" + title.replace("/", "-")
    out = ['<?xml version="1.0" encoding="UTF-8"?>', "<quiz>",
           '  <question type="category">',
           f"    <category><text>{_xml(category)}</text></category>",
           f'    <info format="html"><text>{_xml("Variants of " + title)}</text></info>',
           "  </question>"]
    tol = f"{100 * ex.tolerance:g} %"
    for v, (text, files) in zip(batch.variants, feedback):
        parts = [statement_html_body(v, ex, braces=True),
                 f"<p>Answers (relative tolerance {_h(tol)}):</p>", "<ol>"]
        for a in v.answers.values():
            unit = f" [{_h(a.unit)}]" if a.unit else ""
            label = (_h(a.label) + unit).replace("{", "&#123;").replace("}", "&#125;")
            parts.append(f"<li>{label}: {_cloze_answer(a, ex.tolerance)}</li>")
        parts.append("</ol>")
        question = "\n".join(parts)
        name = f"{title} — variant {v.number}"
        out += ['  <question type="cloze">',
                f"    <name><text>{_xml(name)}</text></name>",
                f'    <questiontext format="html"><text>{_cdata(question)}</text>'
                "</questiontext>",
                f'    <generalfeedback format="html"><text>{_cdata(text)}</text>']
        for file_name, data in files:
            out.append(f'      <file name="{_xml(file_name)}" path="/" encoding="base64">'
                       f"{base64.b64encode(data).decode('ascii')}</file>")
        out += ["    </generalfeedback>", "    <penalty>0.3333333</penalty>",
                "    <hidden>0</hidden>",
                f"    <idnumber>{_xml(f'resonant-{batch.seed}-{v.number}')}</idnumber>",
                "  </question>"]
    out.append("</quiz>")
    return "\n".join(out) + "\n"
