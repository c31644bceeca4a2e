"""The exception and warning hierarchy of resonant.

Every error the command line reports is a :class:`ResonantError`; its
``exit_code`` is the process exit status (2: the model is invalid,
3: the analysis is impossible).  Both concrete families also derive from
:class:`ValueError`, so library users can catch them the ordinary way.
"""

from __future__ import annotations

from dataclasses import dataclass


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
    """

    message: str
    file: str = ""
    section: str = ""
    key: str = ""

    def location(self) -> str:
        where = self.file or "<model>"
        if self.section:
            where += f": [{self.section}]"
        if self.key:
            where += f" {self.key}"
        return where

    def __str__(self) -> str:
        return f"{self.location()}: {self.message}"


class ResonantError(Exception):
    """Base class of all resonant errors."""

    exit_code = 1


class ModelError(ResonantError, ValueError):
    """The model is invalid (exit status 2).

    Collects every problem found, so a user fixes them all in one go.

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

    Examples: an undamped system excited exactly at a natural frequency,
    a singular mass matrix.
    """

    exit_code = 3


__all__ = ["Problem", "ResonantError", "ModelError", "AnalysisError"]
