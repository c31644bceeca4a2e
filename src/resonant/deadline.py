"""A cooperative deadline, passed down through every stage of the pipeline.

The command line makes one :class:`Deadline` from ``--timeout`` and hands it to
the loader, the derivation, the evaluation, every analysis and the simulation;
each of them calls :meth:`Deadline.check` between units of work (a node of an
expression, a matrix entry, a frequency, an integrator step).  Nothing is
interrupted from outside: no signals, no threads, no module state.  A single
call into a C library (LAPACK, symengine) finishes before the next check, so
the stages bound such calls by the size checks of the model (see
docs/security.md).

Examples
--------
>>> d = Deadline(None)
>>> d.check("anything")            # no limit: never raises
>>> d.expired
False
>>> import pytest
>>> late = Deadline(1e-9)
>>> import time; time.sleep(0.001)
>>> with pytest.raises(DeadlineExceeded, match="exceeded 1e-09 s while testing"):
...     late.check("while testing")
"""

from __future__ import annotations

import time

from .errors import AnalysisError, ModelError, Problem, ResonantError


class DeadlineExceeded(ResonantError):
    """Base class of the two time-limit errors below (catch this one for both)."""


class DerivationTimeout(DeadlineExceeded, ModelError):
    """The model needs more symbolic work than the time limit allows (exit status 2)."""


class AnalysisTimeout(DeadlineExceeded, AnalysisError):
    """An analysis (sweep, simulation ...) needs more time than the limit (exit status 3)."""


class Deadline:
    """A point in time after which work stops with a clear error.

    Parameters
    ----------
    seconds : float or None
        The time budget from now; None or 0 means no limit.
    source : str
        The model file, named in the error message.

    Notes
    -----
    :meth:`check` costs one monotonic clock read; call it freely between units
    of work, but not inside a tight numeric loop (use :meth:`every`).

    Examples
    --------
    >>> deadline = Deadline(60, "model.toml")
    >>> deadline.expired, Deadline().seconds is None
    (False, True)
    """

    __slots__ = ("seconds", "source", "end", "_count")

    def __init__(self, seconds: float | None = None, source: str = "") -> None:
        self.seconds = seconds if seconds and seconds > 0 else None
        self.source = source
        self.end = time.monotonic() + self.seconds if self.seconds else None
        self._count = 0

    @property
    def expired(self) -> bool:
        """True once the time is up."""
        return self.end is not None and time.monotonic() > self.end

    def remaining(self) -> float | None:
        """Seconds left (never negative), or None without a limit."""
        return None if self.end is None else max(0.0, self.end - time.monotonic())

    def check(self, what: str = "", section: str = "", key: str = "",
              analysis: bool = False) -> None:
        """Raise when the time is up.

        Parameters
        ----------
        what : str
            What was being done, e.g. ``"while expanding 'T'"``; part of the message.
        section, key : str
            Where in the model file (for the error's location).
        analysis : bool
            Raise :class:`AnalysisTimeout` (exit 3) instead of :class:`DerivationTimeout`
            (exit 2): the model is fine, the analysis asked for is too long.

        Raises
        ------
        DerivationTimeout, AnalysisTimeout
        """
        if self.end is None or time.monotonic() <= self.end:
            return
        doing = f" {what}" if what else ""
        if analysis:
            raise AnalysisTimeout(
                f"the analysis exceeded the time limit of {self.seconds:g} s{doing}; ask for "
                "less (fewer points, a shorter duration) or allow more time (timeout, 0 for "
                "none)")
        raise DerivationTimeout(Problem(
            f"the derivation exceeded {self.seconds:g} s{doing}; the expression is too "
            "large to expand in reasonable time (simplify it, or allow more time with "
            "the timeout, 0 for none)", self.source, section, key))

    def every(self, count: int, what: str = "", section: str = "", key: str = "",
              analysis: bool = False) -> None:
        """:meth:`check` on every ``count``-th call only (for hot loops)."""
        self._count += 1
        if self._count % count == 0:
            self.check(what, section, key, analysis)


#: the deadline of callers that give none
NO_DEADLINE = Deadline(None)

__all__ = ["Deadline", "DeadlineExceeded", "DerivationTimeout", "AnalysisTimeout",
           "NO_DEADLINE"]
