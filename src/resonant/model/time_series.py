"""Reading a sampled history (a measured shock, a load record) from a CSV file.

Two columns, time (s) and value, one sample a line; a first line that is not numbers is
a header; ``#`` starts a comment.  The times must start anywhere, increase and be equally
spaced (to 1e-6 of the step): the analyses take the signal as linear between samples at a
constant step.  The file is untrusted: a regular file of at most :data:`MAX_BYTES`, every
problem named with its line.

Examples
--------
>>> import os, tempfile
>>> with tempfile.TemporaryDirectory() as folder:
...     path = os.path.join(folder, "shock.csv")
...     _ = open(path, "w").write("t,a\\n0,0\\n0.001,5\\n0.002,0\\n")
...     step, values = read_time_series(path)
>>> step, values.tolist()
(0.001, [0.0, 5.0, 0.0])
"""

from __future__ import annotations

import math
import os
from array import array
from collections.abc import Iterator

import numpy as np

from ..errors import ModelError, Problem, printable
from .files import FileRefused, open_regular_file, read_bounded

#: the largest CSV history read
MAX_BYTES = 200 * 2**20
#: the most samples read (the shock response spectrum's own limit)
MAX_SAMPLES = 10_000_000
#: relative spread of the steps accepted as one constant step
STEP_TOLERANCE = 1e-6


def _lines(data: bytes) -> Iterator[bytes]:
    """The lines of ``data`` one at a time (no list of them all: a file may hold millions)."""
    start = 0
    while start < len(data):
        end = data.find(b"\n", start)
        end = len(data) if end < 0 else end
        yield data[start:end]
        start = end + 1


def read_time_series(path: str | os.PathLike[str]) -> tuple[float, np.ndarray]:
    """The constant step and the values of a two-column CSV history.

    Parameters
    ----------
    path : str or PathLike
        The file.

    Returns
    -------
    step : float
    values : ndarray

    Raises
    ------
    ModelError
        For an unreadable file, a line that is not two numbers, fewer than two samples,
        or times that do not increase by a constant step.
    """
    name = os.path.basename(os.fspath(path))
    try:
        with open_regular_file(path, follow_symlinks=True, max_bytes=MAX_BYTES) as handle:
            data = read_bounded(handle, MAX_BYTES)
    except (OSError, FileRefused) as exc:
        raise ModelError(Problem(f"cannot read the history: {exc}", name)) from None
    times, values = array("d"), array("d")
    header = True   # the first line that is neither empty nor a comment may be a header
    for number, raw in enumerate(_lines(data.removeprefix(b"\xef\xbb\xbf")), start=1):
        line = raw.decode("utf-8", errors="replace").split("#", 1)[0].strip()
        if not line:
            continue
        parts = [p.strip() for p in line.replace(";", ",").split(",")]
        try:
            t, v = (float(p) for p in parts) if len(parts) == 2 else (math.nan, math.nan)
        except ValueError:
            if header:
                header = False
                continue
            t = v = math.nan
        header = False
        if not (math.isfinite(t) and math.isfinite(v)):
            raise ModelError(Problem(f"line {number}: expected two numbers, time and value, "
                                     f"got '{printable(line, limit=60)}'", name))
        if len(times) == MAX_SAMPLES:
            raise ModelError(Problem(f"line {number}: more than {MAX_SAMPLES} samples; "
                                     "resample the history at a larger step", name))
        times.append(t)
        values.append(v)
    del data
    if len(times) < 2:
        raise ModelError(Problem("a history needs at least two samples", name))
    with np.errstate(over="ignore", invalid="ignore"):
        steps = np.diff(np.frombuffer(times))
        step = float(steps.mean())
        if not (math.isfinite(step) and step > 0) or \
                np.abs(steps - step).max() > STEP_TOLERANCE * step:
            worst = int(np.nanargmax(np.abs(steps - step))) + 2 \
                if np.isfinite(steps - step).any() else 2
            raise ModelError(Problem(f"the times must increase by a constant step (sample "
                                     f"{worst} breaks it; the step must be a finite number); "
                                     "resample the history", name))
    return step, np.array(values)


__all__ = ["read_time_series", "MAX_BYTES", "MAX_SAMPLES"]
