"""The exception and warning hierarchy of resonant.

Every error the command line reports is a :class:`ResonantError`; its
``exit_code`` is the process exit status (2: the model is invalid,
3: the analysis is impossible).  Both concrete families also derive from
:class:`ValueError`, so library users can catch them the ordinary way.
"""

from __future__ import annotations

import unicodedata
from collections.abc import Iterable
from dataclasses import dataclass

#: longest string from a model file shown in a message (longer ones end in "...")
PRINTABLE_LIMIT = 200
#: names listed in one message before "... and N more"
LISTED_NAMES = 5


def _escape(char: str) -> str:
    code = ord(char)
    if code < 0x100:
        return f"\\x{code:02x}"
    if code < 0x10000:
        return f"\\u{code:04x}"
    return f"\\U{code:08x}"


def printable(text: object, limit: int | None = PRINTABLE_LIMIT) -> str:
    """``text`` safe to print on a terminal: control characters escaped, long text shortened.

    C0 and C1 control characters, DEL, and the Unicode format characters
    (bidirectional overrides and isolates, zero-width characters, ...) and
    separators other than the space are shown as ``\\x1b``/``\\u202e`` escapes, so a
    string from a model file can neither move the cursor, erase a line, change
    colours nor reorder what follows it.  More than ``limit`` characters (after
    escaping) are cut, ending in ``...``.

    Examples
    --------
    >>> printable("\\x1b[2K\\rvalid model")
    '\\\\x1b[2K\\\\rvalid model'
    >>> printable("abc\\u202edef")
    'abc\\\\u202edef'
    >>> printable("x" * 30, limit=10)
    'xxxxxxx...'
    """
    text = str(text)
    if not text.isprintable() or any(unicodedata.category(c) == "Cf" for c in text):
        out = []
        for char in text:
            if char == "\r":
                out.append("\\r")
            elif char == "\n":
                out.append("\\n")
            elif char == "\t":
                out.append("\\t")
            elif (char != " " and not char.isprintable()) or unicodedata.category(char) == "Cf":
                out.append(_escape(char))
            else:
                out.append(char)
        text = "".join(out)
    if limit is not None and len(text) > limit:
        text = text[:max(limit - 3, 1)] + "..."
    return text


def name_list(names: Iterable[object], limit: int = LISTED_NAMES) -> str:
    """``a, b, c, d, e ... and 7 more``: names (made printable) for a one-line message.

    Examples
    --------
    >>> name_list(["a", "b"])
    'a, b'
    >>> name_list([f"x{i}" for i in range(8)])
    'x0, x1, x2, x3, x4 ... and 3 more'
    """
    items = [printable(n, limit=64) for n in names]
    shown = ", ".join(items[:limit])
    return shown + (f" ... and {len(items) - limit} more" if len(items) > limit else "")


@dataclass(frozen=True)
class Problem:
    """One problem found in a model file.

    Parameters
    ----------
    message : str
        What is wrong and, where possible, how to fix it.
    file : str
        The model file (or ``"<string>"``).
    section : str
        TOML section, e.g. ``"energy"``; empty for the top level.
    key : str
        The key inside the section, e.g. ``"T"``; may be empty.

    Examples
    --------
    >>> print(Problem("unknown name 'q'", "m.toml", "energy", "T"))
    m.toml: [energy] T: unknown name 'q'
    """

    message: str
    file: str = ""
    section: str = ""
    key: str = ""

    def location(self) -> str:
        where = printable(self.file) if self.file else "<model>"
        if self.section:
            where += f": [{printable(self.section, limit=64)}]"
        if self.key:
            where += f" {printable(self.key, limit=64)}"
        return where

    def __str__(self) -> str:
        # the message may quote the file (names, expressions): escape it but keep its lines
        message = "\n".join(printable(line, limit=None) for line in self.message.split("\n"))
        return f"{self.location()}: {message}"


class ResonantError(Exception):
    """Base class of all resonant errors.

    Its subclasses carry the command line's exit status as ``exit_code``.

    Attributes
    ----------
    exit_code : int
        The exit status of the command line for this error (1 here: an error without a
        more specific kind).

    See Also
    --------
    ModelError : the model is invalid (exit status 2).
    AnalysisError : the analysis is impossible (exit status 3).

    Examples
    --------
    >>> issubclass(ModelError, ResonantError), ResonantError.exit_code
    (True, 1)
    """

    exit_code = 1


class ModelError(ResonantError, ValueError):
    """The model is invalid (exit status 2).

    Collects every problem found, so a user fixes them all in one go.

    Parameters
    ----------
    problems : list of Problem, Problem or str
        The problems (a plain message becomes a problem without a location).

    Attributes
    ----------
    problems : tuple of Problem
        Every problem found, in the order found; ``str(error)`` lists them one a line.
    exit_code : int
        2.

    See Also
    --------
    Problem : one problem with its file, section and key.

    Examples
    --------
    >>> err = ModelError([Problem("unknown name 'q'", "m.toml", "energy", "T")])
    >>> str(err)
    "m.toml: [energy] T: unknown name 'q'"
    """

    exit_code = 2

    def __init__(self, problems: list[Problem] | Problem | str) -> None:
        if isinstance(problems, (str, Problem)):
            problems = [problems if isinstance(problems, Problem) else Problem(problems)]
        self.problems: tuple[Problem, ...] = tuple(problems)
        super().__init__("\n".join(str(p) for p in self.problems))


class AnalysisError(ResonantError, ValueError):
    """The analysis is impossible for this (valid) model (exit status 3).

    For example an undamped system excited exactly at a natural frequency, or a
    singular mass matrix.

    The message (the exception's one argument) says what makes the analysis impossible
    and, where possible, what to change.

    Attributes
    ----------
    exit_code : int
        3.

    See Also
    --------
    ModelError : the model itself is invalid.

    Examples
    --------
    >>> err = AnalysisError("the mass matrix is singular")
    >>> isinstance(err, ValueError), err.exit_code
    (True, 3)
    """

    exit_code = 3


__all__ = ["printable", "name_list", "PRINTABLE_LIMIT", "LISTED_NAMES",
           "Problem", "ResonantError", "ModelError", "AnalysisError"]
