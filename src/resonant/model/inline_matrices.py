"""Large inline matrices of number literals, read without the TOML parser's per-value cost.

A ``[matrices]`` model may hold M, C and K inline; at 800 x 800 that is 1.9 million
values, which Python's TOML parser turns into 1.9 million objects (seconds, hundreds of
MB) before the model is even looked at.  :func:`extract_numeric_matrices` finds, in the
text, every ``M``/``C``/``K`` of the ``[matrices]`` table whose array holds nothing but
TOML number literals (checked by one regular expression per row, as strict as TOML: no
``1.``, no ``.5``, no ``_``, no ``inf``), parses each row at once with numpy and puts a
placeholder string in its place.  Anything else — an expression, a comment inside the
array, a row of another length, a small matrix — is left to the TOML parser and the
expression parser, which give their usual messages.

Examples
--------
>>> text = "[matrices]\\nM = [" + ",".join(["[" + ",".join(["0"] * 300) + "]"] * 300) + "]\\n"
>>> rest, arrays = extract_numeric_matrices(text)
>>> rest.startswith('[matrices]\\nM = "'), [a.shape for a in arrays.values()]
(True, [(300, 300)])
"""

from __future__ import annotations

import re
import secrets

import numpy as np

from ..expressions import MAX_NUMBER, MIN_NUMBER

#: a matrix with more rows than this is taken as one array (smaller ones keep exact entries)
INLINE_EXPRESSION_SIZE = 200

_NUMBER = r"[+-]?(?:0|[1-9][0-9]*)(?:\.[0-9]+)?(?:[eE][+-]?[0-9]+)?"
_ROW = re.compile(rf"\s*{_NUMBER}(?:\s*,\s*{_NUMBER})*\s*,?\s*")
_START = re.compile(r"^[ \t]*(M|C|K)[ \t]*=[ \t]*\[[ \t\r\n]*\[", re.MULTILINE)
_TABLE = re.compile(r"^[ \t]*\[([^\[\]\n]+)\][ \t]*(?:#[^\n]*)?$", re.MULTILINE)
_ROW_SPLIT = re.compile(r"\]\s*,\s*\[")
_END = re.compile(r"\][ \t\r\n]*\]")


def within_limits(array: np.ndarray) -> bool:
    """Every entry a number the model language accepts: at most 1e300 in magnitude, and
    zero or at least 1e-300."""
    magnitude = np.abs(array)
    return bool(np.all(magnitude <= MAX_NUMBER)
                and not np.any((magnitude > 0) & (magnitude < MIN_NUMBER)))


def _table_at(text: str, position: int) -> str | None:
    """The name of the ``[table]`` the text at ``position`` belongs to."""
    tables = list(_TABLE.finditer(text, 0, position))
    return tables[-1].group(1).strip() if tables else None


def _rows(body: str) -> np.ndarray | None:
    """The rows of ``[a, b], [c, d]`` as a float array, or None if they are not all plain
    numbers of equal count within the model's limits."""
    parts = _ROW_SPLIT.split(body)
    if len(parts) <= INLINE_EXPRESSION_SIZE or not all(_ROW.fullmatch(p) for p in parts):
        return None
    rows = [np.array(p.rstrip().rstrip(",").split(","), dtype=float) for p in parts]
    if any(row.size != len(rows) for row in rows):
        return None
    array = np.stack(rows)
    if not within_limits(array):
        return None
    array.flags.writeable = False
    return array


def extract_numeric_matrices(text: str) -> tuple[str, dict[str, np.ndarray]]:
    """The model text with its large all-number inline matrices replaced by placeholders.

    Parameters
    ----------
    text : str
        The model file's text.

    Returns
    -------
    tuple
        The text to give the TOML parser, and placeholder -> (n, n) float array (read-only).
    """
    arrays: dict[str, np.ndarray] = {}
    pieces: list[str] = []
    done = 0
    for start in _START.finditer(text):
        if start.start() < done or _table_at(text, start.start()) != "matrices":
            continue
        end = _END.search(text, start.end())
        if end is None:
            break
        array = _rows(text[start.end():end.start()])
        if array is None:
            continue
        token = f"inline-matrix-{secrets.token_hex(8)}"
        arrays[token] = array
        pieces += [text[done:start.start()], f'{start.group(1)} = "{token}"']
        done = end.end()
    pieces.append(text[done:])
    return "".join(pieces), arrays


__all__ = ["extract_numeric_matrices", "within_limits", "INLINE_EXPRESSION_SIZE"]
