"""Grading a student's answers against a variant of an exercise key (``key.json``).

Both files are untrusted: they are read with a size limit, and every value is
checked for its type and shape before it is compared.  A problem is a
:class:`~resonant.errors.ModelError` (exit status 2) naming the file and key.

Examples
--------
>>> key = {"format": "resonant-exercise-key", "tolerance": 0.01, "variants": [
...     {"variant": 1, "answers": {"amplitude:x": {"value": 0.5, "tolerance": 0.01}}}]}
>>> result = grade_data(key, 1, {"amplitude:x": 0.503})
>>> result["score"], result["answers"][0]["status"]
(100.0, 'right')
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from ..errors import ModelError, Problem, printable
from .key import KEY_FORMAT

#: largest key.json read
MAX_KEY_BYTES = 200_000_000
#: largest answers file read
MAX_ANSWERS_BYTES = 2_000_000
#: most entries of one answer (a matrix of the largest size an exercise has)
MAX_ENTRIES = 1_000_000


def read_json(path: str | Path, limit: int, what: str) -> Any:
    """A JSON file, at most ``limit`` bytes; ModelError for anything else."""
    name = str(path)
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)
    except OSError as exc:
        raise ModelError(Problem(f"cannot read the {what}: {exc.strerror or 'I/O error'}",
                                 name)) from None
    if len(data) > limit:
        raise ModelError(Problem(f"the {what} is larger than {limit} bytes", name))
    try:
        return json.loads(data.decode("utf-8"), parse_constant=_no_constant)
    except UnicodeDecodeError:
        raise ModelError(Problem(f"the {what} is not UTF-8 text", name)) from None
    except (ValueError, RecursionError) as exc:
        raise ModelError(Problem(f"the {what} is not valid JSON: "
                                 f"{printable(str(exc), limit=200)}", name)) from None


def _no_constant(text: str) -> Any:
    raise ValueError(f"{text} is not a number JSON allows")


def _shape(value: object, where: str, source: str, key: str) -> tuple[list[float], tuple[int, ...]]:
    """The entries (row-major) and shape of a number, a vector or a matrix."""
    def number(x: object) -> float:
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
            raise ModelError(Problem(f"{where}: expected a finite number, got "
                                     f"{printable(repr(x), limit=40)}", source, "", key))
        return float(x)

    if not isinstance(value, list):
        return [number(value)], ()
    if len(value) > MAX_ENTRIES:
        raise ModelError(Problem(f"{where}: too many entries", source, "", key))
    if value and all(isinstance(row, list) for row in value):
        width = len(value[0])
        if any(len(row) != width for row in value) or width * len(value) > MAX_ENTRIES:
            raise ModelError(Problem(f"{where}: the rows of the matrix differ in length",
                                     source, "", key))
        return [number(x) for row in value for x in row], (len(value), width)
    return [number(x) for x in value], (len(value),)


def _index(shape: tuple[int, ...], k: int) -> str:
    if len(shape) == 2:
        return f"[{k // shape[1] + 1},{k % shape[1] + 1}]"
    return f"[{k + 1}]" if shape else ""


def grade_data(key: object, variant: int, answers: object, key_source: str = "key.json",
               answers_source: str = "answers") -> dict[str, Any]:
    """Compare ``answers`` (name -> number / list / nested list) with the key's variant.

    Parameters
    ----------
    key : object
        The key's JSON data.
    variant : int
        The variant to grade against.
    answers : object
        The answers' JSON data.
    key_source, answers_source : str
        The names used in messages.

    Returns
    -------
    dict
        ``score`` (percent) and ``answers``: per key its status (``right``,
        ``wrong``, ``missing``), the expected and the given value.

    Examples
    --------
    >>> key = {"format": "resonant-exercise-key", "tolerance": 0.01, "variants": [
    ...     {"variant": 1, "answers": {"K": {"value": [[1.0, 0.0], [0.0, 2.0]]}}}]}
    >>> grade_data(key, 1, {"K": [[1.0, 0.0], [0.0, 2.1]]})["answers"][0]["status"]
    'wrong'
    """
    if not isinstance(key, dict) or key.get("format") != KEY_FORMAT \
            or not isinstance(key.get("variants"), list):
        raise ModelError(Problem("not an exercise key written by `resonant exercise` "
                                 f"(format \"{KEY_FORMAT}\")", key_source))
    found = [v for v in key["variants"] if isinstance(v, dict) and v.get("variant") == variant]
    if not found:
        count = len(key["variants"])
        raise ModelError(Problem(f"the key has no variant {variant} (variants 1 to {count})",
                                 key_source, "", "variants"))
    expected = found[0].get("answers")
    if not isinstance(expected, dict) or not expected:
        raise ModelError(Problem(f"variant {variant} of the key has no answers", key_source))
    if not isinstance(answers, dict):
        raise ModelError(Problem("the answers must be a JSON object { \"name\": value, ... }",
                                 answers_source))
    results = []
    total = 0.0
    for name, spec in expected.items():
        if not isinstance(spec, dict) or "value" not in spec:
            raise ModelError(Problem(f"the key's answer '{printable(name, limit=40)}' has no "
                                     "value", key_source, "", str(name)[:40]))
        tol = spec.get("tolerance", key.get("tolerance", 0.01))
        if isinstance(tol, bool) or not isinstance(tol, (int, float)) \
                or not 0 <= tol < 1:
            raise ModelError(Problem("the key's tolerance must be a number in [0, 1)",
                                     key_source, "", str(name)[:40]))
        want, shape = _shape(spec["value"], f"key answer '{name}'", key_source, str(name))
        entry: dict[str, Any] = {"answer": name, "unit": spec.get("unit")
                                 if isinstance(spec.get("unit"), str) else None,
                                 "tolerance": float(tol)}
        if name not in answers:
            entry.update(status="missing", score=0.0)
            results.append(entry)
            continue
        try:
            got, got_shape = _shape(answers[name], f"answer '{name}'", answers_source,
                                    str(name))
        except ModelError as exc:
            entry.update(status="wrong", score=0.0, reason=exc.problems[0].message)
            results.append(entry)
            continue
        if got_shape != shape:
            entry.update(status="wrong", score=0.0, reason=(
                f"expected shape {list(shape) or 'a number'}, got {list(got_shape) or 'a number'}"))
            results.append(entry)
            continue
        scale = max((abs(x) for x in want), default=0.0)
        wrong, worst = [], 0.0
        for k, (a, v) in enumerate(zip(got, want)):
            error = abs(a - v)
            relative = error / abs(v) if v != 0 else (0.0 if error == 0 else math.inf)
            if error > tol * abs(v) + 1e-12 * scale:
                wrong.append({"entry": _index(shape, k), "expected": v, "given": a,
                              "relative_error": relative if math.isfinite(relative) else None,
                              "absolute_error": error})
            worst = max(worst, relative if math.isfinite(relative) else error)
        share = 1.0 - len(wrong) / len(want)
        entry.update(status="right" if not wrong else "wrong", score=share,
                     relative_error=worst)
        if wrong and shape:
            entry["wrong_entries"] = wrong
        total += share
        results.append(entry)
    extra = sorted(str(k)[:40] for k in answers if k not in expected)
    right = sum(1 for r in results if r["status"] == "right")
    return {"variant": variant, "score": round(100.0 * total / len(results), 2),
            "right": right, "wrong": sum(1 for r in results if r["status"] == "wrong"),
            "missing": sum(1 for r in results if r["status"] == "missing"),
            "total": len(results), "answers": results, "unknown_answers": extra[:20]}


def grade(key_path: str | Path, variant: int, answers_path: str | Path) -> dict[str, Any]:
    """Grade the answers file against variant ``variant`` of the key file.

    Parameters
    ----------
    key_path : str or Path
        The ``key.json`` written by :func:`resonant.exercises.write`.
    variant : int
        The student's variant number.
    answers_path : str or Path
        The student's answers: a JSON object name -> number, list or nested list.

    Returns
    -------
    dict
        As :func:`grade_data`.

    Raises
    ------
    ModelError
        For a file that cannot be read or is not of the expected form.

    Examples
    --------
    >>> import json, tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> key = {"format": "resonant-exercise-key", "tolerance": 0.01, "variants": [
    ...     {"variant": 1, "answers": {"amplitude:x": {"value": 0.5, "tolerance": 0.01}}}]}
    >>> _ = (folder / "key.json").write_text(json.dumps(key))
    >>> _ = (folder / "a.json").write_text('{"amplitude:x": 0.499}')
    >>> grade(folder / "key.json", 1, folder / "a.json")["score"]
    100.0
    """
    key = read_json(key_path, MAX_KEY_BYTES, "key")
    answers = read_json(answers_path, MAX_ANSWERS_BYTES, "answers file")
    return grade_data(key, variant, answers, str(key_path), str(answers_path))


def grade_text(result: dict[str, Any]) -> str:
    """The grading result for the terminal.

    Parameters
    ----------
    result : dict
        What :func:`grade_data` returns.

    Returns
    -------
    str
        One line per answer and the score.

    Examples
    --------
    >>> key = {"format": "resonant-exercise-key", "tolerance": 0.01, "variants": [
    ...     {"variant": 1, "answers": {"amplitude:x": {"value": 0.5, "tolerance": 0.01}}}]}
    >>> print(grade_text(grade_data(key, 1, {"amplitude:x": 0.6})).splitlines()[0])
    variant 1: score 0 % (0 right, 1 wrong, 0 missing of 1)
    """
    lines = [f"variant {result['variant']}: score {result['score']:g} % "
             f"({result['right']} right, {result['wrong']} wrong, {result['missing']} missing "
             f"of {result['total']})"]
    for r in result["answers"]:
        name = printable(str(r["answer"]), limit=60)
        if r["status"] == "missing":
            lines.append(f"  {name:<24} missing")
            continue
        if "reason" in r:
            lines.append(f"  {name:<24} wrong: {printable(r['reason'], limit=200)}")
            continue
        error = f"relative error {r['relative_error']:.3g}"
        lines.append(f"  {name:<24} {r['status']:<6} ({error}, tolerance {r['tolerance']:g})")
        for w in r.get("wrong_entries", [])[:20]:
            rel = (f"relative error {w['relative_error']:.3g}" if w["relative_error"] is not None
                   else f"absolute error {w['absolute_error']:.3g}")
            lines.append(f"      entry {w['entry']}: {w['given']:.6g} instead of "
                         f"{w['expected']:.6g} ({rel})")
    for name in result["unknown_answers"]:
        lines.append(f"  note: '{printable(name, limit=40)}' is not asked in this exercise")
    return "\n".join(lines) + "\n"


__all__ = ["grade", "grade_data", "grade_text", "read_json"]
