"""Results as JSON and back: the array forms of ``to_dict()`` and the checked reading of
``from_dict()``.

JSON has neither NaN, infinities nor complex numbers, so a result's arrays are written as

* real arrays: nested lists with ``None`` (``null``) for every non-finite entry
  (:func:`floats_json`), read back as NaN (:meth:`Saved.floats`);
* complex arrays: ``{"real": nested lists, "imag": nested lists}``, the two parts written as
  real arrays (:func:`complex_json`, :meth:`Saved.complex`).

Finite numbers survive bit for bit (Python's JSON writes the shortest repr of a float,
which reads back as the same double).  A NaN comes back as NaN; an infinity also comes back
as NaN (the results hold none: a point without a bounded response is NaN).

:class:`Saved` reads a saved result: every missing key, wrong type or array of the wrong
shape raises an :class:`~resonant.errors.AnalysisError` (a ``ValueError``) that names the
result, the key and its place, never a ``KeyError``.

Examples
--------
>>> import json, numpy as np
>>> z = np.array([[1 + 2j, np.nan], [0.5j, -3.0]])
>>> text = json.dumps({"z": complex_json(z)})
>>> text
'{"z": {"real": [[1.0, null], [0.0, -3.0]], "imag": [[2.0, 0.0], [0.5, 0.0]]}}'
>>> Saved(json.loads(text), "Example").complex("z", shape=(2, 2))[0]
array([ 1.+2.j, nan+0.j])
>>> Saved({}, "Example").floats("values")
Traceback (most recent call last):
resonant.errors.AnalysisError: the saved Example has no key 'values' (Example.to_dict() writes \
it)
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from ..errors import AnalysisError, printable

__all__ = ["Saved", "floats_json", "complex_json", "optional_float"]

#: the default of a key that must be there
_MISSING = object()


def floats_json(a: npt.ArrayLike) -> Any:
    """A real array (or number) as nested lists of floats, ``None`` for NaN and infinities.

    Examples
    --------
    >>> floats_json(np.array([1.0, np.nan, np.inf]))
    [1.0, None, None]
    """
    array = np.asarray(a, dtype=float)
    if array.ndim == 0:
        return _finite(float(array))
    if np.all(np.isfinite(array)):
        return array.tolist()
    out = array.astype(object)
    out[~np.isfinite(array)] = None
    return out.tolist()


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def optional_float(value: float | None) -> float | None:
    """A number for JSON: ``None`` stays, NaN and infinities become ``None``."""
    return None if value is None else _finite(float(value))


def complex_json(a: npt.ArrayLike) -> dict[str, Any]:
    """A complex array as ``{"real": nested lists, "imag": nested lists}`` (:func:`floats_json`
    of each part)."""
    array = np.asarray(a, dtype=complex)
    return {"real": floats_json(array.real), "imag": floats_json(array.imag)}


class Saved:
    """The checked reader of a saved result (what ``to_dict()`` gave, read back from JSON).

    Parameters
    ----------
    data : mapping
        The saved result.
    kind : str
        The name of the result class, for the messages.
    where : str, optional
        The place of ``data`` inside the saved result (``"linear"``, ``"points[3]"``).

    Raises
    ------
    AnalysisError
        When ``data`` is not a mapping.
    """

    def __init__(self, data: object, kind: str, where: str = "") -> None:
        self.kind = kind
        self.where = where
        if not isinstance(data, Mapping):
            raise self.error(f"is {_type(data)}, not a mapping (a JSON object)")
        self.data = data

    # -- messages ------------------------------------------------------------------------

    def _place(self, key: str | None = None) -> str:
        path = ".".join(p for p in (self.where, key) if p)
        return f"'{printable(path, limit=80)}'" if path else ""

    def error(self, message: str, key: str | None = None) -> AnalysisError:
        """An error about ``key`` (or the whole result) with the result's name and place."""
        place = self._place(key)
        return AnalysisError(f"the saved {self.kind}" + (f" {place}" if place else "") +
                             f" {message}")

    # -- keys ----------------------------------------------------------------------------

    def __contains__(self, key: str) -> bool:
        return key in self.data

    def value(self, key: str, default: object = _MISSING) -> Any:
        """The raw value of ``key`` (``default`` when missing; an error without default)."""
        if key in self.data:
            return self.data[key]
        if default is _MISSING:
            where = f" at '{printable(self.where, limit=80)}'" if self.where else ""
            raise AnalysisError(f"the saved {self.kind} has no key '{printable(key, 80)}'"
                                f"{where} ({self.kind}.to_dict() writes it)")
        return default

    def string(self, key: str, default: object = _MISSING) -> str:
        """A string."""
        value = self.value(key, default)
        if not isinstance(value, str):
            raise self.error(f"is {_type(value)}, not a string", key)
        return value

    def strings(self, key: str, default: object = _MISSING) -> tuple[str, ...]:
        """A list of strings, as a tuple."""
        value = self.value(key, default)
        if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
            raise self.error("is not a list of strings", key)
        return tuple(value)

    def boolean(self, key: str, default: object = _MISSING) -> bool:
        """true or false (not a number)."""
        value = self.value(key, default)
        if not isinstance(value, bool):
            raise self.error(f"is {_type(value)}, not true or false", key)
        return value

    def integer(self, key: str, default: object = _MISSING, *, minimum: int | None = None) -> int:
        """An integer (not a boolean), at least ``minimum`` when given."""
        value = self.value(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(f"is {_type(value)}, not an integer", key)
        if minimum is not None and value < minimum:
            raise self.error(f"is {value}, less than {minimum}", key)
        return value

    def number(self, key: str, default: object = _MISSING) -> float:
        """A float; ``None`` (a non-finite number in JSON) reads as NaN."""
        value = self.value(key, default)
        if value is None:
            return math.nan
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(f"is {_type(value)}, not a number", key)
        try:
            return float(value)
        except OverflowError:   # a JSON whole number beyond the floating-point range
            raise self.error("is a number beyond the floating-point range", key) from None

    def optional_number(self, key: str) -> float | None:
        """A float or None (a missing key is None)."""
        value = self.value(key, None)
        return None if value is None else self.number(key)

    def numbers(self, key: str, default: object = _MISSING) -> tuple[float, ...]:
        """A list of numbers (``None`` read as NaN), as a tuple of floats."""
        return tuple(self.floats(key, default=default, ndim=1).tolist())

    def floats(self, key: str, default: object = _MISSING, *, shape: Sequence[int] | None = None,
               ndim: int | None = None) -> np.ndarray:
        """A real array (``None`` entries read as NaN) of the given shape or dimension.

        An empty list takes the shape asked for (JSON's ``[]`` cannot say it).
        """
        return self.array_of(self.value(key, default), key, shape, ndim)

    def optional_floats(self, key: str, *, shape: Sequence[int] | None = None,
                        ndim: int | None = None) -> np.ndarray | None:
        """:meth:`floats`, or None when the key is missing or null."""
        return None if self.value(key, None) is None else \
            self.floats(key, shape=shape, ndim=ndim)

    def complex(self, key: str, *, shape: Sequence[int] | None = None,
                ndim: int | None = None) -> np.ndarray:
        """A complex array saved by :func:`complex_json`."""
        parts = self.mapping(key)
        real = parts.array_of(parts.value("real"), "real", shape, ndim)
        imag = parts.array_of(parts.value("imag"), "imag", real.shape, None)
        out = np.empty(real.shape, dtype=complex)
        out.real = real
        out.imag = imag
        return out

    def mapping(self, key: str, default: object = _MISSING) -> Saved:
        """The nested mapping under ``key``, as a reader."""
        return Saved(self.value(key, default), self.kind, self._path(key))

    def records(self, key: str, default: object = _MISSING) -> list[Saved]:
        """The list of mappings under ``key``, each as a reader."""
        value = self.value(key, default)
        if not isinstance(value, (list, tuple)):
            raise self.error(f"is {_type(value)}, not a list", key)
        return [Saved(v, self.kind, f"{self._path(key)}[{i}]") for i, v in enumerate(value)]

    def arrays(self, key: str, *, shape: Sequence[int] | None = None, ndim: int | None = None,
               default: object = _MISSING) -> dict[str, np.ndarray]:
        """A mapping name -> real array (each :meth:`floats`)."""
        inner = self.mapping(key, default)
        return {str(k): inner.array_of(v, str(k), shape, ndim) for k, v in inner.data.items()}

    def numbers_of(self, key: str, default: object = _MISSING) -> dict[str, float]:
        """A mapping name -> number (each :meth:`number`)."""
        inner = self.mapping(key, default)
        return {str(k): inner.number(k) for k in inner.data}

    def _path(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def array_of(self, value: object, key: str, shape: Sequence[int] | None = None,
                 ndim: int | None = None) -> np.ndarray:
        """``value`` (the value of ``key``) as a real array, checked as :meth:`floats`."""
        if value is None and (ndim == 0 or (shape is not None and len(shape) == 0)):
            return np.array(math.nan)  # a 0-d array that held NaN or an infinity
        if not isinstance(value, (list, tuple, int, float)) or isinstance(value, bool):
            raise self.error(f"is {_type(value)}, not an array of numbers", key)
        try:
            array = np.array(value, dtype=float)  # None -> NaN
        except (TypeError, ValueError) as exc:
            raise self.error(f"is not an array of numbers: {exc}", key) from None
        except OverflowError:   # a JSON whole number beyond the floating-point range
            raise self.error("holds a number beyond the floating-point range", key) from None
        if shape is not None:
            shape = tuple(int(s) for s in shape)
            if array.size == 0 and math.prod(shape) == 0:
                array = array.reshape(shape)
            if array.shape != shape:
                raise self.error(f"has shape {array.shape}, not {shape}", key)
        if ndim is not None and array.ndim != ndim:
            if array.size == 0:
                array = array.reshape((0,) * ndim)
            else:
                raise self.error(f"has {array.ndim} dimension(s), not {ndim}", key)
        return array


def _type(value: object) -> str:
    if value is None:
        return "null"
    names = {bool: "a boolean", str: "a string", int: "a number", float: "a number",
             list: "a list", tuple: "a list", dict: "a mapping"}
    return names.get(type(value), f"a {type(value).__name__}")
