"""The text of a variant's statement: its numbers filled in, as HTML, Markdown and LaTeX."""

from __future__ import annotations

import html
import re

from ..errors import printable
from ..model.exercise import Exercise, statement_parts
from ..report.latex import escape as tex_escape
from ..report.markdown import _escape as md_escape
from .variants import Variant

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
    """The teacher's statement with the variant's values (and units) filled in.

    Parameters
    ----------
    variant : Variant
        The variant.
    exercise : Exercise
        The model's ``[exercise]``.

    Returns
    -------
    str
        The statement's text.

    Examples
    --------
    >>> import resonant
    >>> from resonant.exercises import generate
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 2, seed=1)
    >>> "{" in filled_statement(batch.variants[0], batch.exercise)  # every name filled in
    False
    """
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
