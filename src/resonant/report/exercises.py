"""Exercise variants for teachers: one model, N sets of numbers, solutions, key, Moodle.

:func:`generate` draws N distinct value sets from the model's ``[variants]``
(reproducibly: ``numpy.random.Generator(PCG64(seed))``), derives the model
once and substitutes each variant's numbers into the shared symbolic system,
solves it, and replaces a variant that is not an equilibrium, is unstable or
lies within 5 % of a natural frequency.  :func:`write` writes the statements,
the worked solutions, ``key.json`` and ``moodle.xml``; :func:`grade` checks a
student's answers against the key.

Examples
--------
>>> import pathlib, resonant
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples/teaching/cart_pendulum.toml"
>>> batch = generate(resonant.load(path), 3, seed=1)
>>> len(batch.variants), sorted(batch.variants[0].answers)[:2]
(3, ['C', 'K'])
"""

from __future__ import annotations

import base64
import dataclasses
import html
import json
import math
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..analyses.stationary import StationarySolution, stationary
from ..deadline import NO_DEADLINE, Deadline, DeadlineExceeded
from ..derivation.residual import is_zero
from ..errors import AnalysisError, ModelError, Problem, printable
from ..model import Model, symbol
from ..model.exercise import Exercise, statement_parts
from ..system import LinearEOM, LinearSystem, linear_system
from ..system.stability import UNSTABLE
from .blocks import Equation, Figure, Heading, Math, Note, Paragraph, Part, Report, Table
from .derivation import Derivation, derive
from .html import render_html
from .latex import escape as tex_escape
from .latex import render_latex
from .markdown import _escape as md_escape
from .markdown import render_markdown
from .plots import to_svg
from .steps import Context, step_order

#: an excitation frequency within this relative distance of a natural one is refused
RESONANCE_MARGIN = 0.05
#: most variants of one run
MAX_VARIANTS = 10_000
#: most candidates tried before giving up (a multiple of the variants asked for)
ATTEMPTS_PER_VARIANT = 20
#: largest energy model whose derivation the solutions show (as resonant report)
MAX_DERIVED = 12
FORMATS = ("html", "md", "tex", "moodle", "json")
KEY_FORMAT = "resonant-exercise-key"

_LABELS = {"M": "mass matrix M", "C": "damping matrix C", "K": "stiffness matrix K",
           "L": "cosine coefficients L of the stationary solution",
           "N": "sine coefficients N of the stationary solution",
           "F_S": "sine amplitudes F_S of the excitation",
           "F_C": "cosine amplitudes F_C of the excitation",
           "natural_frequencies": "natural frequencies (ascending)"}


@dataclass(frozen=True)
class Answer:
    """One answer of a variant: a number, a vector or a matrix (nested lists)."""

    key: str
    label: str
    value: Any
    unit: str | None


@dataclass(frozen=True)
class Variant:
    """One student's exercise: the varied values, the model with them, the solution."""

    number: int
    values: Mapping[str, float]
    texts: Mapping[str, str]
    model: Model
    eom: LinearSystem
    solution: StationarySolution
    answers: Mapping[str, Answer]


@dataclass(frozen=True)
class Replacement:
    """A drawn value set that was not used, and why."""

    values: Mapping[str, float]
    reason: str


@dataclass(frozen=True)
class ExerciseSet:
    """The variants of one run (``seed``), the replaced value sets, the shared derivation."""

    model: Model
    exercise: Exercise
    seed: int
    variants: tuple[Variant, ...]
    replaced: tuple[Replacement, ...]
    eom: LinearSystem


# -- generation ----------------------------------------------------------------------------

def _candidates(exercise: Exercise, rng: np.random.Generator) -> Iterator[tuple[int, ...]]:
    """Distinct index tuples (one index per varied parameter), in a seeded random order."""
    sizes = [len(v.values) for v in exercise.variants]
    total = math.prod(sizes)
    if total <= 1_000_000:
        for flat in rng.permutation(total):
            digits, rest = [], int(flat)
            for size in reversed(sizes):
                rest, i = divmod(rest, size)
                digits.append(i)
            yield tuple(reversed(digits))
        return
    seen: set[tuple[int, ...]] = set()
    while True:
        index = tuple(int(rng.integers(size)) for size in sizes)
        if index not in seen:
            seen.add(index)
            yield index


def _shared(eom: LinearSystem, model: Model) -> LinearSystem:
    """The system of ``model`` (same equations, other numbers) without a new derivation:
    the symbolic system and its compiled form are shared."""
    names = {f.name for f in dataclasses.fields(eom)}  # type: ignore[arg-type]
    copy = dataclasses.replace(eom, model=model)  # type: ignore[type-var]
    for key, value in eom.__dict__.items():
        if key not in names:  # cached symbolic work (harmonics, compiled layout, ...)
            copy.__dict__[key] = value
    return copy


def _not_equilibrium(eom: LinearSystem, model: Model) -> str | None:
    residual = getattr(eom, "residual", None)
    if residual is None:
        return None
    subs = {symbol(n): v for n, v in model.exact_values.items()}
    for k, expr in enumerate(residual):
        if expr == 0:
            continue
        zero, value = is_zero(expr, subs)
        if not zero:
            return (f"not an equilibrium (residual {value.real:.3g} in the equation of "
                    f"{eom.coordinates[k]})")
    return None


def _rejection(eom: LinearSystem, model: Model, deadline: Deadline
               ) -> tuple[str | None, StationarySolution | None]:
    reason = _not_equilibrium(eom, model)
    if reason:
        return reason, None
    try:
        solution = stationary(eom, deadline)
    except DeadlineExceeded:
        raise
    except (AnalysisError, ModelError) as exc:
        return f"cannot be solved ({printable(str(exc), limit=200)})", None
    if solution.stability == UNSTABLE:
        return "the equilibrium is unstable", None
    for h in solution.harmonics:
        for i, wn in enumerate(solution.natural_frequencies):
            if h.omega > 0 and wn > 0 and abs(h.omega - wn) <= RESONANCE_MARGIN * wn:
                return (f"the excitation frequency {h.omega:.6g} rad/s is within "
                        f"{100 * abs(h.omega - wn) / wn:.2g} % of natural frequency {i + 1} "
                        f"({wn:.6g} rad/s)"), None
    return None, solution


def _coordinate_unit(exercise: Exercise, coordinates: Sequence[str]) -> str | None:
    units = exercise.units or {}
    found = {units.get(c) for c in coordinates}
    return found.pop() if len(found) == 1 else None


def _answers(exercise: Exercise, solution: StationarySolution, model: Model
             ) -> dict[str, Answer]:
    units = exercise.units or {}
    e = solution.eom
    q = _coordinate_unit(exercise, e.coordinates)
    metre = q == "m"
    out: dict[str, Answer] = {}
    for key in exercise.answers:
        kind, _, name = key.partition(":")
        value: Any
        unit: str | None = None
        if key in ("M", "C", "K"):
            value = np.asarray(getattr(e, key), dtype=float).tolist()
            unit = {"M": "kg", "C": "N*s/m", "K": "N/m"}[key] if metre else None
        elif key in ("L", "N", "F_S", "F_C"):
            if not solution.harmonics:
                raise ModelError(Problem(f"the answer '{key}' needs a harmonic excitation; "
                                         "this model has none", model.source, "exercise",
                                         "answers"))
            rows = [np.asarray(getattr(h, key), dtype=float).tolist()
                    for h in solution.harmonics]
            value = rows[0] if len(rows) == 1 else rows
            unit = q if key in ("L", "N") else ("N" if metre else None)
        elif key == "natural_frequencies":
            value = solution.natural_frequencies.tolist()
            unit = "rad/s"
        elif kind == "amplitude":
            if name not in solution.amplitudes:
                raise ModelError(Problem(f"the answer '{key}' is not defined: the model has no "
                                         "stationary solution", model.source, "exercise",
                                         "answers"))
            value = float(solution.amplitudes[name])
            unit = units.get(name)
        else:  # phase
            if name not in solution.phases:
                raise ModelError(Problem(f"the answer '{key}' is not defined (a phase needs "
                                         "one excitation frequency and a non-zero amplitude)",
                                         model.source, "exercise", "answers"))
            value = float(solution.phases[name])
            unit = "rad"
        label = _LABELS.get(key) or (f"amplitude of {name}" if kind == "amplitude"
                                     else f"phase of {name}")
        out[key] = Answer(key, label, value, unit)
    return out


def generate(model: Model, count: int, seed: int, deadline: Deadline = NO_DEADLINE
             ) -> ExerciseSet:
    """``count`` distinct, solved variants of the model's exercise.

    Raises
    ------
    ModelError
        No ``[exercise]``; fewer acceptable value sets than ``count``.
    """
    exercise = model.exercise
    if exercise is None:
        raise ModelError(Problem("the model has no [exercise] section (statement, answers) "
                                 "and [variants]; see docs/exercises.md", model.source,
                                 "exercise"))
    if not 1 <= count <= MAX_VARIANTS:
        raise ModelError(Problem(f"--variants must be between 1 and {MAX_VARIANTS}, got "
                                 f"{count}", "--variants"))
    if not 0 <= seed < 2**63:
        raise ModelError(Problem(f"--seed must be between 0 and 2^63 - 1, got {seed}", "--seed"))
    if count > exercise.combinations:
        raise ModelError(Problem(f"{count} variants asked for, but [variants] allows only "
                                 f"{exercise.combinations} distinct value sets", model.source,
                                 "variants"))
    eom = linear_system(model, deadline)
    eom.numeric(deadline)  # the harmonic split and the compilation, once, for all variants
    rng = np.random.Generator(np.random.PCG64(seed))
    variants: list[Variant] = []
    replaced: list[Replacement] = []
    attempts = 0
    for index in _candidates(exercise, rng):
        if len(variants) == count:
            break
        attempts += 1
        if attempts > ATTEMPTS_PER_VARIANT * count + 100:
            break
        deadline.check("while generating the exercise variants", analysis=True)
        values = {v.name: v.values[i] for v, i in zip(exercise.variants, index)}
        texts = {v.name: v.texts[i] for v, i in zip(exercise.variants, index)}
        try:
            vmodel = model.with_parameters(**texts)
            veom = _shared(eom, vmodel)
            reason, solution = _rejection(veom, vmodel, deadline)
        except DeadlineExceeded:
            raise
        except ModelError as exc:
            reason, solution = f"invalid ({printable(str(exc), limit=200)})", None
        if reason is not None or solution is None:
            replaced.append(Replacement(values, reason or "no solution"))
            continue
        variants.append(Variant(len(variants) + 1, values, texts, vmodel, veom, solution,
                                _answers(exercise, solution, vmodel)))
    if len(variants) < count:
        raise ModelError(Problem(
            f"only {len(variants)} of the {count} variants could be made: {len(replaced)} "
            "value sets were refused (not an equilibrium, unstable or near a resonance); "
            "widen [variants]", model.source, "variants"))
    return ExerciseSet(model, exercise, seed, tuple(variants), tuple(replaced), eom)


# -- text of the statement -------------------------------------------------------------------

def _value_text(variant: Variant, name: str) -> str:
    if name in variant.texts:
        return variant.texts[name]
    given = variant.model.units.given.get(name) if variant.model.units is not None else None
    if given is not None:  # "2 kg": the number here, the unit from _unit
        return given[0].text.strip()
    return variant.model.parameters[name].text.strip()


def _unit(variant: Variant, exercise: Exercise, name: str) -> str | None:
    """The unit shown after a value: [exercise.units], else the unit the value was given in."""
    units = exercise.units or {}
    if name in units or name in variant.texts:
        return units.get(name)
    given = variant.model.units.given.get(name) if variant.model.units is not None else None
    return given[1].text if given is not None else None


def _with_unit(text: str, unit: str | None) -> str:
    return f"{text} {unit}" if unit else text


def filled_statement(variant: Variant, exercise: Exercise) -> str:
    """The teacher's statement with the variant's values (and units) filled in."""
    return "".join(_with_unit(_value_text(variant, name), _unit(variant, exercise, name))
                   if name else text
                   for text, name in statement_parts(exercise.statement))


def _data_rows(variant: Variant, exercise: Exercise) -> list[tuple[str, str, str]]:
    rows = []
    for name in variant.model.parameters:
        given = _value_text(variant, name)
        value = variant.model.parameter_values[name]
        shown = format(value, ".6g")
        unit = _unit(variant, exercise, name) or ""
        units = variant.model.units
        written = units.given.get(name) if units is not None and name not in variant.texts \
            else None
        if units is not None and written is not None and \
                (written[1].factor != 1 or written[1].pi_power):  # "500 mm = 0.5" m
            given, dim = f"{given} {written[1].text}", units.dimensions.get(name)
            unit = dim.text() if dim is not None else ""
        rows.append((name, given if given == shown else f"{given} = {shown}", unit))
    return rows


def _paragraphs(text: str) -> list[str]:
    return [" ".join(p.split()) for p in re.split(r"\n\s*\n", text.strip()) if p.strip()]


def _h(text: str) -> str:
    return html.escape(printable(text, limit=None))


def statement_html_body(variant: Variant, exercise: Exercise, braces: bool = False) -> str:
    """The statement and data table as an HTML fragment; ``braces`` writes { } as entities
    (Moodle's Cloze parser must not see them)."""
    def esc(text: str) -> str:
        out = _h(text)
        return out.replace("{", "&#123;").replace("}", "&#125;") if braces else out

    parts = [f"<p>{esc(p)}</p>" for p in _paragraphs(filled_statement(variant, exercise))]
    rows = "".join(f"<tr><td>{esc(n)}</td><td>{esc(v)}</td><td>{esc(u)}</td></tr>"
                   for n, v, u in _data_rows(variant, exercise))
    parts.append("<table class=\"data\"><thead><tr><th>parameter</th><th>value</th>"
                 f"<th>unit</th></tr></thead><tbody>{rows}</tbody></table>")
    return "\n".join(parts)


_PAGE_CSS = ("body{font-family:serif;max-width:46rem;margin:2rem auto;line-height:1.5;"
             "padding:0 1rem}table{border-collapse:collapse}th,td{padding:.2rem .8rem;"
             "text-align:left}thead th{border-bottom:1px solid #333}")


def statement_html(variant: Variant, exercise: Exercise, title: str) -> str:
    heading = f"{title} — variant {variant.number}"
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{_h(heading)}</title>\n<style>{_PAGE_CSS}</style>\n</head>\n<body>\n"
            f"<h1>{_h(heading)}</h1>\n{statement_html_body(variant, exercise)}\n"
            "</body>\n</html>\n")


def statement_md(variant: Variant, exercise: Exercise, title: str) -> str:
    lines = [f"# {md_escape(title)} — variant {variant.number}", ""]
    for p in _paragraphs(filled_statement(variant, exercise)):
        lines += [md_escape(p).replace("&", "&amp;"), ""]
    lines += ["| parameter | value | unit |", "|---|---|---|"]
    lines += [f"| {md_escape(n)} | {md_escape(v)} | {md_escape(u)} |"
              for n, v, u in _data_rows(variant, exercise)]
    return "\n".join(lines) + "\n"


def statement_tex(variant: Variant, exercise: Exercise, title: str) -> str:
    out = [r"\documentclass[11pt,a4paper]{article}", r"\usepackage[utf8]{inputenc}",
           r"\usepackage[T1]{fontenc}", r"\usepackage{lmodern}", r"\begin{document}",
           rf"\section*{{{tex_escape(title)} --- variant {variant.number}}}"]
    out += [tex_escape(p) + "\n" for p in _paragraphs(filled_statement(variant, exercise))]
    out += [r"\begin{tabular}{lll}", r"\hline", r"parameter & value & unit \\", r"\hline"]
    out += [f"{tex_escape(n)} & {tex_escape(v)} & {tex_escape(u)} \\\\"
            for n, v, u in _data_rows(variant, exercise)]
    out += [r"\hline", r"\end{tabular}", r"\end{document}"]
    return "\n".join(out) + "\n"


# -- solutions ----------------------------------------------------------------------------

def solution_report(variant: Variant, derivation: Derivation | None, plots: bool) -> Report:
    """The worked solution of one variant (the report of ``resonant report``), built on the
    shared derivation."""
    d = dataclasses.replace(derivation, model=variant.model) if derivation is not None \
        else None
    ctx = Context(variant.model, variant.eom, variant.solution, d,  # type: ignore[arg-type]
                  plots=plots)
    blocks = []
    for step in step_order(ctx):
        blocks.extend(step(ctx))
    title = variant.model.title or Path(variant.model.source).stem or "Worked solution"
    return Report(f"{title} — variant {variant.number}", tuple(blocks))


def _tex_html(latex: str) -> str:
    return html.escape(latex, quote=False)


def moodle_feedback(report: Report) -> tuple[str, list[tuple[str, bytes]]]:
    """The report as HTML for Moodle (TeX in \\( \\) and \\[ \\] for its MathJax filter) and
    its figures as files (name, SVG bytes) referenced by ``@@PLUGINFILE@@``."""
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


# -- key and Moodle -----------------------------------------------------------------------------

def key_data(batch: ExerciseSet) -> dict[str, Any]:
    """The answer key as JSON data."""
    ex = batch.exercise
    return {
        "format": KEY_FORMAT, "version": 1,
        "model": batch.model.source, "title": batch.model.title,
        "seed": batch.seed, "tolerance": ex.tolerance, "tolerance_kind": "relative",
        "answers": list(ex.answers),
        "variants": [{
            "variant": v.number,
            "varied": dict(v.values),
            "parameters": dict(v.model.parameter_values),
            "answers": {a.key: {"label": a.label, "value": a.value, "tolerance": ex.tolerance,
                                "unit": a.unit} for a in v.answers.values()},
        } for v in batch.variants],
        "replaced": [{"varied": dict(r.values), "reason": r.reason} for r in batch.replaced],
    }


def _number(value: float) -> str:
    text = repr(float(value))
    if not math.isfinite(value):
        raise AnalysisError(f"an answer is not finite ({text}); it cannot be a Moodle answer")
    return text


def cloze(value: float, tolerance: float) -> str:
    """One NUMERICAL sub-question: ``{1:NUMERICAL:=value:absolute tolerance}``.

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
    """A Moodle XML question bank: one category, one Cloze question per variant."""
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


# -- writing ------------------------------------------------------------------------------

def write(batch: ExerciseSet, folder: str | Path, formats: Sequence[str] = ("html",),
          plots: bool = True) -> list[Path]:
    """Write every variant's statement and solution, ``key.json`` and (format ``moodle``)
    ``moodle.xml`` into ``folder``; returns the files written (figures excluded)."""
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


__all__ = ["generate", "write", "key_data", "moodle_xml", "cloze", "filled_statement",
           "solution_report", "ExerciseSet", "Variant", "Answer", "Replacement",
           "RESONANCE_MARGIN", "FORMATS"]
