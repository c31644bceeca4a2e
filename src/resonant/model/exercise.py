"""The ``[exercise]`` and ``[variants]`` sections: a teacher's exercise made from a model.

``[exercise]`` holds the statement (with ``{name}`` placeholders for parameter
values), the answers that are asked and checked, and the relative tolerance;
``[variants]`` says which values each parameter may take (a list, or a range
``{ from, to, step }``).  Both are validated here (file, section, key of every
problem) and stored on the :class:`~resonant.model.types.Model`; generating the
variants is the exercises layer's work (:mod:`resonant.exercises`).

Examples
--------
>>> problems = []
>>> ex = parse_exercise({"statement": "A mass {m}.", "answers": ["M", "amplitude:x"]},
...                     {"m": [1, 2]}, ["m", "k"], ["x"], [], "f.toml", problems)
>>> ex.answers, ex.variants[0].values, problems
(('M', 'amplitude:x'), (1.0, 2.0), [])
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import Any

from ..errors import Problem
from ..expressions import ExpressionError, numeric_value, parse

#: answers that name a whole matrix or vector of the solution
PLAIN_ANSWERS = ("M", "C", "K", "L", "N", "F_S", "F_C", "natural_frequencies")
#: answers of the form ``kind:name`` (name a coordinate or an output)
NAMED_ANSWERS = ("amplitude", "phase", "rms", "miles", "largest")
#: most values one parameter may take (a list or a range)
MAX_VALUES = 10_000
#: most answers of one exercise
MAX_ANSWERS = 200
#: longest statement, in characters
MAX_STATEMENT = 100_000
DEFAULT_TOLERANCE = 0.01

_PLACEHOLDER = re.compile(r"\{\{|\}\}|\{([^{}]*)\}|[{}]")


@dataclass(frozen=True)
class VariantValues:
    """The values one parameter may take in the variants (in the teacher's order)."""

    name: str
    values: tuple[float, ...]
    #: how each value is written (the list entry, or the range value): used in the statement
    texts: tuple[str, ...]


@dataclass(frozen=True)
class Exercise:
    """A model's ``[exercise]`` and ``[variants]``."""

    statement: str
    answers: tuple[str, ...]
    tolerance: float = DEFAULT_TOLERANCE
    variants: tuple[VariantValues, ...] = ()
    #: units of parameters, coordinates and outputs, where the teacher gives them
    units: Mapping[str, str] | None = None

    @property
    def combinations(self) -> int:
        """The number of distinct value sets."""
        return math.prod(len(v.values) for v in self.variants)


def statement_parts(text: str) -> list[tuple[str, str | None]]:
    """The statement split into (literal text, None) and (placeholder name, name) parts.

    ``{{`` and ``}}`` stand for literal braces; a lone brace or ``{}`` gives name "".

    Examples
    --------
    >>> statement_parts("m = {m1} {{kg}}")
    [('m = ', None), ('m1', 'm1'), (' ', None), ('{', None), ('kg', None), ('}', None)]
    """
    parts: list[tuple[str, str | None]] = []
    pos = 0
    for match in _PLACEHOLDER.finditer(text):
        if match.start() > pos:
            parts.append((text[pos:match.start()], None))
        token = match.group(0)
        if token in ("{{", "}}"):
            parts.append((token[0], None))
        elif token in ("{", "}"):
            parts.append((token, ""))  # a lone brace: name "", reported by the validation
        else:
            name = match.group(1).strip()
            parts.append((name, name))
        pos = match.end()
    if pos < len(text):
        parts.append((text[pos:], None))
    return parts


def _number_text(value: float) -> str:
    return format(value, ".12g")


def _range(spec: Mapping[str, Any], where: tuple[str, str, str], problems: list[Problem]
           ) -> tuple[list[float], list[str]]:
    source, section, key = where
    unknown = sorted(set(spec) - {"from", "to", "step"})
    if unknown:
        problems.append(Problem(f"unknown key '{unknown[0]}' in the range; a range is "
                                "{ from = ..., to = ..., step = ... }", source, section, key))
        return [], []
    numbers: dict[str, Decimal] = {}
    for part in ("from", "to", "step"):
        value = spec.get(part)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            problems.append(Problem(f"the range needs '{part}' as a number", source, section,
                                    key))
            return [], []
        if not math.isfinite(value):
            problems.append(Problem(f"'{part}' must be finite", source, section, key))
            return [], []
        try:
            numbers[part] = Decimal(repr(value)) if isinstance(value, float) else Decimal(value)
        except InvalidOperation:  # pragma: no cover - finite floats always convert
            problems.append(Problem(f"'{part}' is not a number", source, section, key))
            return [], []
    start, stop, step = numbers["from"], numbers["to"], numbers["step"]
    if step <= 0:
        problems.append(Problem(f"step must be > 0, got {spec['step']}", source, section, key))
        return [], []
    if stop < start:
        problems.append(Problem(f"'to' ({spec['to']}) is below 'from' ({spec['from']})",
                                source, section, key))
        return [], []
    count = int((stop - start) / step) + 1
    if count > MAX_VALUES:
        problems.append(Problem(f"the range has {count} values; at most {MAX_VALUES}", source,
                                section, key))
        return [], []
    exact = [start + i * step for i in range(count)]
    texts = [_decimal_text(d) for d in exact]
    return [float(d) for d in exact], texts


def _decimal_text(d: Decimal) -> str:
    text = format(d.normalize(), "f")
    return text if "." not in text else text.rstrip("0").rstrip(".")


def _values(raw: object, where: tuple[str, str, str], problems: list[Problem]
            ) -> tuple[list[float], list[str]]:
    source, section, key = where
    if isinstance(raw, dict):
        return _range(raw, where, problems)
    if not isinstance(raw, list):
        problems.append(Problem("expected a list of values [1, 2, 3] or a range "
                                "{ from = 1, to = 3, step = 1 }, got "
                                f"{type(raw).__name__}", source, section, key))
        return [], []
    if not raw:
        problems.append(Problem("the list of values is empty", source, section, key))
        return [], []
    if len(raw) > MAX_VALUES:
        problems.append(Problem(f"{len(raw)} values; at most {MAX_VALUES}", source, section, key))
        return [], []
    values: list[float] = []
    texts: list[str] = []
    for i, item in enumerate(raw):
        if isinstance(item, bool) or not isinstance(item, (int, float, str)):
            problems.append(Problem(f"value {i + 1} must be a number or an expression of "
                                    f"constants, got {type(item).__name__}", source, section,
                                    key))
            continue
        try:
            expression = parse(item, allowed=(), file=source, section=section, key=key)
        except ExpressionError as exc:
            problems.extend(exc.problems)
            continue
        value = float(numeric_value(expression, {}))
        if not math.isfinite(value):
            problems.append(Problem(f"value {i + 1} ('{item}') is not a finite number", source,
                                    section, key))
            continue
        if value in values:
            problems.append(Problem(f"value {i + 1} ({item}) is listed twice", source, section,
                                    key))
            continue
        values.append(value)
        texts.append(_number_text(float(item)) if not isinstance(item, str) else item.strip())
    return values, texts


def parse_exercise(exercise: object, variants: object, parameters: Sequence[str],
                   coordinates: Sequence[str], outputs: Sequence[str], source: str,
                   problems: list[Problem]) -> Exercise | None:
    """Validate the two sections; append every problem to ``problems``.

    Parameters
    ----------
    exercise, variants : the TOML tables (``None`` when absent)
    parameters, coordinates, outputs : the model's names
    source : the model file, for the messages
    problems : where the problems go

    Returns
    -------
    Exercise or None
        None when ``[exercise]`` is absent or invalid.
    """
    count = len(problems)
    if exercise is None:
        if variants is not None:
            problems.append(Problem("[variants] needs an [exercise] section (statement, "
                                    "answers)", source, "variants"))
        return None
    if not isinstance(exercise, dict):
        problems.append(Problem("[exercise] must be a table", source, "exercise"))
        return None
    for key in sorted(set(exercise) - {"statement", "answers", "tolerance", "units"}):
        problems.append(Problem(f"unknown key '{key}'; [exercise] takes statement, answers, "
                                "tolerance and units", source, "exercise", key))
    statement = exercise.get("statement", "")
    if not isinstance(statement, str):
        problems.append(Problem("statement must be a string", source, "exercise", "statement"))
        statement = ""
    elif len(statement) > MAX_STATEMENT:
        problems.append(Problem(f"the statement has {len(statement)} characters; at most "
                                f"{MAX_STATEMENT}", source, "exercise", "statement"))
        statement = ""
    for text, name in statement_parts(statement):
        if name == "":
            problems.append(Problem(f"a lone or empty '{text}' in the statement; write {{name}} "
                                    "for a "
                                    "parameter's value, {{ and }} for braces", source,
                                    "exercise", "statement"))
        elif name is not None and name not in parameters:
            problems.append(Problem(f"the placeholder {{{name}}} names no parameter; known: "
                                    f"{', '.join(parameters) or 'none'}", source, "exercise",
                                    "statement"))
    answers = _answers(exercise.get("answers"), coordinates, outputs, source, problems)
    tolerance = exercise.get("tolerance", DEFAULT_TOLERANCE)
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) \
            or not math.isfinite(tolerance) or not 0 < tolerance < 1:
        problems.append(Problem(f"tolerance must be a relative tolerance between 0 and 1 "
                                f"(0.01 = 1 %), got {tolerance!r}", source, "exercise",
                                "tolerance"))
        tolerance = DEFAULT_TOLERANCE
    units = _units(exercise.get("units"), [*parameters, *coordinates, *outputs], source,
                   problems)
    declared = _variants(variants, parameters, source, problems)
    if len(problems) > count:
        return None
    return Exercise(statement, tuple(answers), float(tolerance), tuple(declared), units)


def _answers(raw: object, coordinates: Sequence[str], outputs: Sequence[str], source: str,
             problems: list[Problem]) -> list[str]:
    if raw is None:
        problems.append(Problem("answers is missing: list what is asked, e.g. answers = "
                                "[\"M\", \"K\", \"amplitude:x1\"]", source, "exercise",
                                "answers"))
        return []
    if not isinstance(raw, list) or not raw:
        problems.append(Problem("answers must be a non-empty list of strings", source,
                                "exercise", "answers"))
        return []
    if len(raw) > MAX_ANSWERS:
        problems.append(Problem(f"{len(raw)} answers; at most {MAX_ANSWERS}", source,
                                "exercise", "answers"))
        return []
    names = [*coordinates, *outputs]
    out: list[str] = []
    for i, item in enumerate(raw):
        key = f"answers[{i}]"
        if not isinstance(item, str):
            problems.append(Problem(f"an answer must be a string, got {type(item).__name__}",
                                    source, "exercise", key))
            continue
        kind, sep, name = item.partition(":")
        if not sep and item in PLAIN_ANSWERS:
            pass
        elif sep and kind in NAMED_ANSWERS and name in names:
            pass
        elif sep and kind in NAMED_ANSWERS:
            problems.append(Problem(f"'{item}': '{name}' is neither a coordinate nor an output "
                                    f"({', '.join(names) or 'none'})", source, "exercise", key))
            continue
        else:
            problems.append(Problem(
                f"unknown answer '{item}'; answers are {', '.join(PLAIN_ANSWERS)}, "
                "amplitude:NAME, phase:NAME, rms:NAME and miles:NAME (under [random]) and "
                "largest:NAME (under [periodic]) (NAME a coordinate or output)", source,
                "exercise", key))
            continue
        if item in out:
            problems.append(Problem(f"the answer '{item}' is listed twice", source, "exercise",
                                    key))
            continue
        out.append(item)
    return out


def _units(raw: object, names: Sequence[str], source: str, problems: list[Problem]
           ) -> Mapping[str, str] | None:
    if raw is None:
        return None
    if not isinstance(raw, dict):
        problems.append(Problem("units must be a table { name = \"unit\" }", source, "exercise",
                                "units"))
        return None
    out = {}
    for name, unit in raw.items():
        if name not in names:
            problems.append(Problem(f"units names '{name}', which is not a parameter, "
                                    "coordinate or output", source, "exercise",
                                    f"units.{name}"))
        elif not isinstance(unit, str) or len(unit) > 40:
            problems.append(Problem("a unit must be a short string", source, "exercise",
                                    f"units.{name}"))
        else:
            out[name] = unit
    return out


def _variants(raw: object, parameters: Sequence[str], source: str, problems: list[Problem]
              ) -> list[VariantValues]:
    if raw is None:
        problems.append(Problem("[variants] is missing: say which values the parameters may "
                                "take, e.g. k = { from = 80, to = 120, step = 10 }", source,
                                "variants"))
        return []
    if not isinstance(raw, dict):
        problems.append(Problem("[variants] must be a table", source, "variants"))
        return []
    if not raw:
        problems.append(Problem("[variants] is empty: vary at least one parameter", source,
                                "variants"))
    out = []
    for name, spec in raw.items():
        if name not in parameters:
            problems.append(Problem(f"'{name}' is not a parameter; [variants] varies "
                                    f"parameters ({', '.join(parameters) or 'none'})", source,
                                    "variants", name))
            continue
        values, texts = _values(spec, (source, "variants", name), problems)
        if values:
            out.append(VariantValues(name, tuple(values), tuple(texts)))
    # declaration order of the parameters: the sampling does not depend on the TOML order
    order = {name: i for i, name in enumerate(parameters)}
    return sorted(out, key=lambda v: order[v.name])


__all__ = ["Exercise", "VariantValues", "parse_exercise", "statement_parts", "PLAIN_ANSWERS",
           "NAMED_ANSWERS", "DEFAULT_TOLERANCE", "MAX_VALUES"]
