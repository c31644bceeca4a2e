"""A frozen result's ``to_dict()``, ``from_dict()`` and ``to_frame()``, written once from its
dataclass fields.

A result class inherits :class:`FieldsJSON`; each of its fields is saved under its name
(or the ``key`` given by :func:`saved`), in the form its annotation says:

==============================  ==============================================================
annotation                      JSON
==============================  ==============================================================
``str``, ``bool``, ``int``      the same
``float``                       a number, ``null`` for NaN and infinities
``tuple[str, ...]``             a list of strings
``tuple[float, ...]``           a list of numbers
``tuple[int, ...]``             a list of whole numbers
``np.ndarray``                  nested lists (real) or ``{"real": ..., "imag": ...}`` (complex)
``ComplexArray``                ``{"real": ..., "imag": ...}`` (also when the values are real)
``Mapping[str, float]``         an object of numbers
``Mapping[str, np.ndarray]``    an object of nested lists
``Mapping[str, ComplexArray]``  an object of ``{"real": ..., "imag": ...}``
``Mapping[str, str]``           an object of strings
``Mapping[str, tuple[tuple[float, float], ...]]`` an object of lists of pairs
a result class                  its ``to_dict()``
``tuple[<result class>, ...]``  a list of them
``Mapping[str, <result class>]`` an object of them
another dataclass               an object of its compared fields (by these rules)
``X | None``                    ``null`` or X
==============================  ==============================================================

A field whose saved form is none of these names its :class:`Codec` in :func:`saved`;
``axes`` there gives an array's shape by the lengths of other fields (or numbers), checked on
reading, so that a hand-edited file is refused with the key and the shapes, not half read.
What a class writes beside its fields (numbers derived for the reader of the JSON) comes
from its ``_derived_json()``; ``from_dict`` reads the fields only, so the derived numbers are
computed again, bit for bit.  The keys come in the order of the fields (the derived ones
first), or in the order the class lists in ``_json_order`` (``"..."`` there: the keys it
does not list, in their order).  More ways of saving a field, for the formats the
command line's outputs fix:

* ``saved(history=True)``: written inside ``"history"``, and only by ``to_dict(history=True)``
  (a time history can be long); ``from_dict`` then needs it;
* ``saved(rows_by="names")``: an array written as an object, row ``i`` under the ``i``-th name
  of the field ``names`` (a mapping: its entries of those names, in their order);
* ``saved(keys_of="other")``: not written; read back as the keys of the saved object of
  the field ``other``;
* ``saved(records="modes")``: one value per index; the fields of one ``records`` group are
  written together as the list ``"modes"`` of one object per index (the fields' keys in
  their order, or in the class's ``_group_order``),
  ``{"modes": [{"frequency_hz": ..., "pole": ...}, ...]}``; the value of a mapping
  field at an index is an object of its entries there, of an array field with
  ``rows_by`` an object of its rows there by name (fields of one key merge these objects);
* ``saved(inside="continuation")``: written inside the object ``"continuation"`` with the
  other fields saved there (and the derived keys put there), in the order of the
  ``_group_order`` of ``"continuation"``;
* ``saved(only_with="inputs")``: written only when the field ``inputs`` is not empty (and
  then needed by ``from_dict``; without it read as the default).

Examples
--------
>>> import json
>>> from dataclasses import dataclass
>>> import numpy as np
>>> @dataclass(frozen=True)
... class Peak(FieldsJSON):
...     name: str
...     frequency: np.ndarray = saved(key="frequency_hz")
...     level: np.ndarray = saved(axes=("frequency",))
...     warnings: tuple[str, ...] = ()
>>> p = Peak("x", np.array([1.0, 2.0]), np.array([0.5, np.nan]))
>>> p.to_dict()
{'name': 'x', 'frequency_hz': [1.0, 2.0], 'level': [0.5, None], 'warnings': []}
>>> Peak.from_dict(json.loads(json.dumps(p.to_dict()))).level
array([0.5, nan])
>>> Peak.from_dict({"name": "x", "frequency_hz": [1.0, 2.0], "level": [1.0]})
Traceback (most recent call last):
resonant.errors.AnalysisError: the saved Peak 'level' has shape (1,), not (2,)
"""

from __future__ import annotations

import dataclasses
import re
import sys
from collections import Counter
from collections.abc import Callable, Mapping, Sequence, Sized
from dataclasses import dataclass
from typing import Any, ClassVar, TypeVar

import numpy as np
import numpy.typing as npt

from ..errors import AnalysisError
from .results_json import Saved, complex_json, floats_json, optional_float

__all__ = ["Codec", "FieldsJSON", "Framed", "saved", "COMPLEX_NUMBER", "COMPLEX_PAIRS",
           "COUNT", "HARMONIC_LISTS", "PLAIN_NUMBER", "PLAIN_NUMBERS", "ROWS", "Shape",
           "frame_of"]

T = TypeVar("T", bound="FieldsJSON")

#: the shape asked of a saved array (None entries: any length), or None (unchecked)
Shape = tuple[int | None, ...] | None

#: the shape of an array field: other fields' names (their lengths), numbers, or None
#: (any length)
Axes = tuple[str | int | None, ...]


@dataclass(frozen=True)
class Codec:
    """How one field is written to JSON and read back.

    Parameters
    ----------
    write : callable
        value -> JSON value.
    read : callable
        (reader, key, shape or None) -> value; the reader raises on a wrong entry (a None
        in the shape is any length).
    """

    write: Callable[[Any], Any]
    read: Callable[[Saved, str, Shape], Any]


def _number_write(value: float) -> float | None:
    return optional_float(value)


def _array_write(value: npt.ArrayLike) -> Any:
    array = np.asarray(value)
    if np.iscomplexobj(array):
        return complex_json(array)
    if array.dtype.kind in "iub":
        return array.tolist()
    return floats_json(array)


def _fixed(shape: Shape) -> tuple[int, ...] | None:
    """``shape`` when every length is given (else None: checked by :func:`_free_shape`)."""
    if shape is None or None in shape:
        return None
    return tuple(int(s) for s in shape if s is not None)


def _array_read(saved: Saved, key: str, shape: Shape, complex_only: bool = False
                ) -> np.ndarray:
    fixed = _fixed(shape)
    if complex_only or isinstance(saved.value(key), Mapping):
        array = saved.complex(key, shape=fixed)
    else:
        array = saved.floats(key, shape=fixed)
    return array if fixed is not None or shape is None else _free_shape(saved, key, array, shape)


def _complex_read(saved: Saved, key: str, shape: Shape) -> np.ndarray:
    return _array_read(saved, key, shape, complex_only=True)


def _free_shape(saved: Saved, key: str, array: np.ndarray, shape: tuple[int | None, ...]
                ) -> np.ndarray:
    """``array`` checked against ``shape`` whose None entries take any length."""
    if array.size == 0:
        return array.reshape(tuple(0 if s is None else s for s in shape))
    if array.ndim != len(shape) or any(s is not None and s != a
                                       for s, a in zip(shape, array.shape)):
        wanted = tuple("any" if s is None else s for s in shape)
        raise saved.error(f"has shape {array.shape}, not {wanted}".replace("'", ""), key)
    return array


def _arrays_read(saved: Saved, key: str, shape: Shape) -> dict[str, Any]:
    inner = saved.mapping(key)
    return {str(k): _array_read(inner, str(k), shape) for k in inner.data}


def _complex_arrays_read(saved: Saved, key: str, shape: Shape) -> dict[str, Any]:
    inner = saved.mapping(key)
    return {str(k): _complex_read(inner, str(k), shape) for k in inner.data}


def _complex_number_read(saved: Saved, key: str, shape: Shape) -> complex:
    parts = saved.mapping(key)
    return complex(parts.number("real"), parts.number("imag"))


def _pairs_write(value: npt.ArrayLike) -> list[list[float | None]]:
    array = np.asarray(value, dtype=complex).ravel()
    return [[optional_float(s.real), optional_float(s.imag)] for s in array.tolist()]


def _pairs_read(saved: Saved, key: str, shape: Shape) -> np.ndarray:
    pairs = saved.floats(key, ndim=2)
    if pairs.size == 0:
        pairs = pairs.reshape(0, 2)
    if pairs.shape[1] != 2:
        raise saved.error("is not a list of [real, imaginary] pairs", key)
    out = np.empty(len(pairs), dtype=complex)
    out.real, out.imag = pairs[:, 0], pairs[:, 1]   # bit for bit, signed zeros included
    if shape is not None and out.shape != shape:
        raise saved.error(f"has shape {out.shape}, not {shape}", key)
    return out


def _rows_read(saved: Saved, key: str, shape: Shape) -> np.ndarray:
    fixed = _fixed(shape)
    transposed = None if fixed is None else fixed[::-1]
    return saved.floats(key, shape=transposed, ndim=None if transposed else 2).T


def _number_pairs_read(saved: Saved, key: str, shape: Shape
                       ) -> tuple[tuple[float, float], ...]:
    pairs = saved.floats(key, ndim=2)
    if pairs.size == 0:
        pairs = pairs.reshape(0, 2)
    if pairs.shape[1] != 2:
        raise saved.error("is not a list of pairs of numbers", key)
    if shape is not None and None not in shape and pairs.shape != shape:
        raise saved.error(f"has shape {pairs.shape}, not {shape}", key)
    return tuple((float(a), float(b)) for a, b in pairs)


def _harmonics_write(value: npt.ArrayLike) -> list[list[float | None]]:
    c = np.asarray(value, dtype=float).tolist()
    return [[optional_float(c[0])]] + [[optional_float(a), optional_float(b)]
                                       for a, b in zip(c[1::2], c[2::2])]


def _harmonics_read(saved: Saved, key: str, shape: Shape) -> np.ndarray:
    lists = saved.value(key)
    flat = [c for pair in lists for c in pair] if isinstance(lists, list) and all(
        isinstance(pair, list) for pair in lists) else lists
    return saved.array_of(flat, key, shape=_fixed(shape), ndim=1)


#: a complex vector as a list of [real, imaginary] pairs
COMPLEX_PAIRS = Codec(_pairs_write, _pairs_read)
#: a number as Python's JSON writes it (NaN as ``NaN``: the formats that wrote it so)
PLAIN_NUMBER = Codec(float, lambda s, k, shape: s.number(k))
#: Fourier coefficients ``[a_0, a_1, b_1, ..., a_H, b_H]`` as ``[[a_0], [a_1, b_1], ...]``
#: (a flat list is read too)
HARMONIC_LISTS = Codec(_harmonics_write, _harmonics_read)
#: a real matrix saved transposed: one column (a mode, a point) a row
ROWS = Codec(lambda value: floats_json(np.asarray(value, dtype=float).T), _rows_read)
#: one complex number as ``{"real": ..., "imag": ...}`` (NaN as ``NaN``, as Python writes it)
COMPLEX_NUMBER = Codec(lambda value: {"real": float(value.real), "imag": float(value.imag)},
                       _complex_number_read)
#: a whole number, 0 or more
COUNT = Codec(int, lambda s, k, shape: s.integer(k, minimum=0))
#: an object of numbers as Python's JSON writes them (NaN as ``NaN``)
PLAIN_NUMBERS = Codec(dict, lambda s, k, shape: s.numbers_of(k))

_TEXT = Codec(str, lambda s, k, shape: s.string(k))
_FLAG = Codec(bool, lambda s, k, shape: s.boolean(k))
_WHOLE = Codec(int, lambda s, k, shape: s.integer(k))
_NUMBER = Codec(_number_write, lambda s, k, shape: s.number(k))
_TEXTS = Codec(list, lambda s, k, shape: s.strings(k))
_NUMBERS = Codec(lambda v: [optional_float(x) for x in v], lambda s, k, shape: s.numbers(k))
_WHOLES = Codec(lambda v: [int(x) for x in v],
                lambda s, k, shape: tuple(int(x) for x in s.numbers(k)))
_ARRAY = Codec(_array_write, _array_read)
_NUMBERS_BY_NAME = Codec(lambda v: {k: optional_float(x) for k, x in v.items()},
                         lambda s, k, shape: s.numbers_of(k))
_ARRAYS_BY_NAME = Codec(lambda v: {k: _array_write(x) for k, x in v.items()}, _arrays_read)
_COMPLEX = Codec(complex_json, _complex_read)
_COMPLEX_BY_NAME = Codec(lambda v: {k: complex_json(x) for k, x in v.items()},
                         _complex_arrays_read)
_TEXTS_BY_NAME = Codec(dict, lambda s, k, shape: {
    str(name): s.mapping(k).string(str(name)) for name in s.mapping(k).data})

_PAIRS_BY_NAME = Codec(
    lambda v: {k: [[optional_float(a), optional_float(b)] for a, b in x] for k, x in v.items()},
    lambda s, k, shape: {str(name): _number_pairs_read(s.mapping(k), str(name), shape)
                         for name in s.mapping(k).data})

_BY_ANNOTATION: dict[str, Codec] = {
    "str": _TEXT, "bool": _FLAG, "int": _WHOLE, "float": _NUMBER,
    "tuple[str,...]": _TEXTS, "tuple[float,...]": _NUMBERS, "tuple[int,...]": _WHOLES,
    "tuple[float,float]": _NUMBERS, "tuple[float,float,float]": _NUMBERS,
    "tuple[tuple[float,float],...]": Codec(lambda v: [[optional_float(a), optional_float(b)]
                                                      for a, b in v], _number_pairs_read),
    "np.ndarray": _ARRAY, "FloatArray": _ARRAY, "ComplexArray": _COMPLEX,
    "Mapping[str,float]": _NUMBERS_BY_NAME, "dict[str,float]": _NUMBERS_BY_NAME,
    "Mapping[str,np.ndarray]": _ARRAYS_BY_NAME, "dict[str,np.ndarray]": _ARRAYS_BY_NAME,
    "Mapping[str,ComplexArray]": _COMPLEX_BY_NAME, "dict[str,ComplexArray]": _COMPLEX_BY_NAME,
    "Mapping[str,str]": _TEXTS_BY_NAME, "dict[str,str]": _TEXTS_BY_NAME,
    "Mapping[str,tuple[tuple[float,float],...]]": _PAIRS_BY_NAME,
}


@dataclass(frozen=True)
class _Saving:
    """What :func:`saved` put in a field's metadata."""

    key: str | None = None
    codec: Codec | None = None
    axes: Axes | None = None
    omit_none: bool = False
    required: bool = False
    history: bool = False
    rows_by: str | None = None
    keys_of: str | None = None
    inline: bool = False
    written: bool = True
    by_name: str | None = None
    missing: tuple[object, ...] = ()   # (the value written for a name the mapping lacks,)
    records: str | None = None
    only_with: str | None = None
    inside: str | None = None


def saved(default: object = dataclasses.MISSING, *, key: str | None = None,
          codec: Codec | None = None, axes: Axes | None = None, omit_none: bool = False,
          required: bool = False, default_factory: Callable[[], object] | None = None,
          history: bool = False, rows_by: str | None = None, keys_of: str | None = None,
          inline: bool = False, written: bool = True, by_name: str | None = None,
          missing: object = dataclasses.MISSING, records: str | None = None,
          only_with: str | None = None, inside: str | None = None) -> Any:
    """A dataclass field with the way it is saved (see the module's table).

    Parameters
    ----------
    default, default_factory
        As for :func:`dataclasses.field`.
    key : str, optional
        The JSON key (default: the field's name).
    codec : Codec, optional
        How it is written and read, when the annotation does not say it.
    axes : tuple, optional
        The array's shape by other fields' lengths (names) or numbers, checked on reading.
    omit_none : bool
        Leave the key out when the value is None (instead of writing ``null``).
    required : bool
        The key must be in a saved result even though the field has a default (a missing
        key of a field with a default otherwise reads as the default).
    history : bool
        Written inside ``"history"``, only when ``to_dict(history=True)`` is asked for.
    rows_by : str, optional
        The field whose names key the array's rows (an object of rows); of a mapping, the
        names whose entries are written, in that order.
    keys_of : str, optional
        Not written: the keys of the saved object of that field.
    inline : bool
        The codec writes an object whose keys go beside the other fields' (and reads them
        from there).
    written : bool
        False: not saved (a field with a default, read back as the default).
    by_name : str, optional
        A mapping name -> value saved in the object ``by_name`` of one record per name
        (the class's ``_by_name`` says which field lists the names and the records' key
        order), under ``key``: ``{"responses": {"x": {"rms": ...}}}``.
    missing : optional
        With ``by_name``: written for a name the mapping lacks (else every name is there).
    records : str, optional
        A sequence (a tuple or an array) saved one value per index in the list ``records``
        of one object per index, under ``key``, beside the other fields of that group (all
        of one length); its ``codec`` (or, of a ``tuple[X, ...]``, X's form) saves one
        value, ``axes`` gives one value's shape.
    only_with : str, optional
        Written only when the field ``only_with`` (this one's own name: itself) is not
        empty; read as the default when that field is empty.
    inside : str, optional
        Written under ``key`` inside the object ``inside`` (beside the other fields saved
        there).

    Returns
    -------
    dataclasses.Field
    """
    metadata = {"saved": _Saving(key, codec, axes, omit_none, required, history, rows_by,
                                 keys_of, inline, written, by_name,
                                 () if missing is dataclasses.MISSING else (missing,),
                                 records, only_with, inside)}
    if default_factory is not None:
        return dataclasses.field(default_factory=default_factory, metadata=metadata)
    return dataclasses.field(default=default, metadata=metadata)


def _optional(codec: Codec) -> Codec:
    return Codec(lambda v: None if v is None else codec.write(v),
                 lambda s, k, shape: None if s.value(k) is None else codec.read(s, k, shape))


def _nested(kind: type[FieldsJSON]) -> Codec:
    return Codec(lambda v: v.to_dict(),
                 lambda s, k, shape: kind.read_saved(s.mapping(k)))


def _nested_list(kind: type[FieldsJSON]) -> Codec:
    return Codec(lambda v: [x.to_dict() for x in v],
                 lambda s, k, shape: tuple(kind.read_saved(r) for r in s.records(k)))


def _codec_of(owner: type, field: dataclasses.Field[Any]) -> Codec:
    """The codec of ``field`` of the class ``owner``: given, or from its annotation."""
    saving: _Saving = field.metadata.get("saved", _Saving())
    if saving.codec is not None:
        return saving.codec
    text = re.sub(r"\s+", "", field.type if isinstance(field.type, str)
                  else getattr(field.type, "__name__", str(field.type)))
    text = re.sub(r"^npt\.NDArray\[.*\]$", "np.ndarray", text)
    optional = text.endswith("|None")
    inner = text[:-len("|None")] if optional else text
    codec = _BY_ANNOTATION.get(inner) or _result_codec(owner, inner)
    if codec is None:
        raise TypeError(f"{owner.__name__}.{field.name}: no saved form for '{field.type}'; "
                        "give one with saved(codec=...)")
    return _optional(codec) if optional else codec


def _nested_by_name(kind: type[FieldsJSON]) -> Codec:
    def read(saved_data: Saved, key: str, shape: Shape) -> dict[str, Any]:
        inner = saved_data.mapping(key)
        return {str(k): kind.read_saved(inner.mapping(str(k))) for k in inner.data}
    return Codec(lambda v: {k: x.to_dict() for k, x in v.items()}, read)


def _record(kind: type) -> Codec:
    """A dataclass that is no result: an object of its fields, each by its annotation; a
    field outside its comparison (``compare=False``: where it was read from) is not saved."""
    compared = {f.name for f in dataclasses.fields(kind) if f.compare}
    entries = tuple(e for e in _entries(kind) if e.name in compared)

    def read(saved_data: Saved, key: str, shape: Shape) -> Any:
        inner = saved_data.mapping(key)
        values = {e.name: e.codec.read(inner, e.key, None) for e in entries
                  if e.key in inner or not e.has_default}
        try:
            return kind(**values)
        except (TypeError, ValueError) as exc:
            raise saved_data.error(f"does not make a {kind.__name__}: {exc}", key) from None
    return Codec(lambda v: {e.key: e.codec.write(getattr(v, e.name)) for e in entries}, read)


def _result_codec(owner: type, text: str) -> Codec | None:
    """The codec of a nested result (``Name``, ``tuple[Name, ...]`` or ``Mapping[str,
    Name]``) or dataclass (``Name``), looked up among the names of the module that defines
    ``owner``."""
    listed = re.fullmatch(r"tuple\[(\w+),\.\.\.\]", text)
    named = re.fullmatch(r"(?:Mapping|dict)\[str,(\w+)\]", text)
    found = listed or named
    name = found.group(1) if found else text
    kind = vars(sys.modules[owner.__module__]).get(name)
    if not isinstance(kind, type):
        return None
    if issubclass(kind, FieldsJSON):
        return _nested_list(kind) if listed else _nested_by_name(kind) if named \
            else _nested(kind)
    if dataclasses.is_dataclass(kind) and not (listed or named):
        return _record(kind)
    return None


@dataclass(frozen=True)
class _Entry:
    name: str
    key: str
    codec: Codec
    axes: Axes | None
    has_default: bool
    omit_none: bool
    history: bool = False
    rows_by: str | None = None
    keys_of: str | None = None
    inline: bool = False
    by_name: str | None = None
    missing: tuple[object, ...] = ()
    mapping: bool = False   # a mapping field (rows_by: the entries of those names)
    records: str | None = None
    only_with: str | None = None
    listed: bool = False    # a tuple field (records: read back as a tuple, else an array)
    inside: str | None = None


def _element_codec(owner: type, field: dataclasses.Field[Any]) -> Codec:
    """The codec of one value of a ``Mapping[str, X]`` field (``saved(by_name=...)``) or of
    a ``tuple[X, ...]`` field (``saved(records=...)``)."""
    saving: _Saving = field.metadata["saved"]
    if saving.codec is not None:
        return saving.codec
    text = re.sub(r"\s+", "", str(field.type))
    pattern = r"tuple\[(.+),\.\.\.\]" if saving.records else r"(?:Mapping|dict)\[str,(.+)\]"
    match = re.fullmatch(pattern, text)
    codec = _BY_ANNOTATION.get(match.group(1)) if match else None
    if codec is None:
        how = "in records" if saving.records else "by name"
        raise TypeError(f"{owner.__name__}.{field.name}: saved {how}, but '{field.type}' "
                        "has no saved form of one value: give saved(codec=...)")
    return codec


def _entries(cls: type) -> tuple[_Entry, ...]:
    out = []
    for f in dataclasses.fields(cls):
        saving = f.metadata.get("saved", _Saving())
        if not f.init or not saving.written:
            continue
        has_default = not saving.required and (f.default is not dataclasses.MISSING
                                                or f.default_factory is not dataclasses.MISSING)
        codec = _TEXTS if saving.keys_of is not None else _element_codec(cls, f) \
            if saving.by_name is not None or saving.records is not None else _codec_of(cls, f)
        out.append(_Entry(f.name, saving.key or f.name, codec, saving.axes, has_default,
                          saving.omit_none, saving.history, saving.rows_by, saving.keys_of,
                          saving.inline, saving.by_name, saving.missing,
                          bool(re.match(r"(Mapping|dict)\[", str(f.type))), saving.records,
                          saving.only_with, str(f.type).startswith("tuple["),
                          saving.inside))
    return tuple(out)


def _length(value: Sized | np.ndarray) -> int:
    return int(np.shape(value)[0]) if isinstance(value, np.ndarray) else len(value)


def _empty(value: Sized | np.ndarray | None) -> bool:
    """No value at all (None, or no entry: an array of size 0, an empty sequence)."""
    return value is None or (np.size(value) == 0 if isinstance(value, np.ndarray)
                             else len(value) == 0)


def _other(entry: _Entry) -> str | None:
    """The field that says whether ``entry`` is written (``only_with``), if another."""
    return None if entry.only_with in (None, entry.name) else entry.only_with


class FieldsJSON:
    """``to_dict()`` and ``from_dict()`` of a frozen result, from its dataclass fields.

    Subclasses are dataclasses; ``_derived_json()`` adds the keys written for readers only.
    """

    _saved_entries: ClassVar[dict[type, tuple[_Entry, ...]]] = {}

    @classmethod
    def _saved_fields(cls) -> tuple[_Entry, ...]:
        entries = FieldsJSON._saved_entries.get(cls)
        if entries is None:
            entries = FieldsJSON._saved_entries[cls] = _entries(cls)
        return entries

    def _derived_json(self) -> dict[str, Any]:
        """Keys written beside the fields, for the reader of the JSON (none by default)."""
        return {}

    _json_order: ClassVar[tuple[str, ...]] = ()
    #: record group -> (the field listing its names, the records' keys in order)
    _by_name: ClassVar[Mapping[str, tuple[str, tuple[str, ...]]]] = {}
    #: group (``saved(records=...)``: its records; ``saved(inside=...)``: the object) ->
    #: its keys in order, where that is not the order of the fields
    _group_order: ClassVar[Mapping[str, tuple[str, ...]]] = {}

    def _derived_record(self, group: str, name: str) -> dict[str, Any]:
        """Keys written in the record of ``name`` in ``group`` for the reader (none)."""
        return {}

    def to_dict(self, history: bool = False) -> dict[str, Any]:
        """The JSON form: the derived keys, then every field (see :mod:`result_fields`).

        Parameters
        ----------
        history : bool, optional
            Also write the fields saved in ``"history"`` (time histories, which can be
            long, and which :meth:`from_dict` needs); a result without any has none.

        Returns
        -------
        dict
        """
        data = self._derived_json()
        histories: dict[str, Any] = {}
        groups = {group: {name: self._derived_record(group, name)
                          for name in getattr(self, names)}
                  for group, (names, _) in self._by_name.items()}
        for entry in self._saved_fields():
            value = getattr(self, entry.name)
            if entry.keys_of is not None or (value is None and entry.omit_none) or \
                    (entry.history and not history) or \
                    (entry.only_with is not None and _empty(getattr(self, entry.only_with))):
                continue
            if entry.records is not None:
                _write_records(data, entry, value, self)
                continue
            if entry.by_name is not None:
                data.setdefault(entry.by_name, groups[entry.by_name])
                for name, record in groups[entry.by_name].items():
                    one = value.get(name, *entry.missing) if entry.missing else value[name]
                    record[entry.key] = entry.codec.write(one)
                continue
            if entry.rows_by is not None and entry.mapping:
                written: Any = entry.codec.write({name: value[name]
                                                  for name in getattr(self, entry.rows_by)})
            elif entry.rows_by is not None:
                written = {name: entry.codec.write(row)
                           for name, row in zip(getattr(self, entry.rows_by), value)}
            else:
                written = entry.codec.write(value)
            if entry.inline:
                data.update(written)
            elif entry.inside is not None:
                data.setdefault(entry.inside, {})[entry.key] = written
            else:
                (histories if entry.history else data)[entry.key] = written
        if histories:
            data["history"] = histories
        for group, (_, order) in self._by_name.items():
            data[group] = {name: _ordered(record, order, f"{type(self).__name__}.{group}")
                           for name, record in groups[group].items()}
        for group, order in self._group_order.items():
            kind = f"{type(self).__name__}.{group}"
            if isinstance(data.get(group), list):
                data[group] = [_ordered(record, order, kind) for record in data[group]]
            elif group in data:
                data[group] = _ordered(data[group], order, kind)
        return _ordered(data, self._json_order, type(self).__name__)

    @classmethod
    def from_dict(cls: type[T], data: Mapping[str, Any]) -> T:
        """The result back from its :meth:`to_dict` (read back from JSON).

        Parameters
        ----------
        data : mapping
            What :meth:`to_dict` gave.

        Returns
        -------
        The result.

        Raises
        ------
        AnalysisError
            When a key is missing or holds the wrong kind of value or shape (the message
            names it).
        """
        return cls.read_saved(Saved(data, cls.__name__))

    @classmethod
    def _check_saved(cls, values: dict[str, Any], saved_data: Saved) -> None:
        """Checks between saved fields beyond their shapes (raise ``saved_data.error``);
        may complete a value from the others (a field saved inside another's)."""

    @classmethod
    def read_saved(cls: type[T], saved_data: Saved) -> T:
        """The result from a checked reader (:meth:`from_dict` and nested results)."""
        values: dict[str, Any] = {}
        entries = cls._saved_fields()
        histories = saved_data
        if any(e.history for e in entries):
            if "history" not in saved_data:
                raise AnalysisError(f"the saved {cls.__name__} has no time history: save it "
                                    "with to_dict(history=True)")
            histories = saved_data.mapping("history")
        by_name = {e.name: e for e in entries}
        for entry in _reading_order(entries):
            source = histories if entry.history else saved_data.mapping(entry.inside) \
                if entry.inside is not None else saved_data
            if entry.keys_of is not None:
                of = by_name.get(entry.keys_of)
                inner = saved_data.mapping(entry.keys_of) if entry.keys_of in cls._by_name \
                    else (histories if of is not None and of.history else saved_data).mapping(
                        of.key if of is not None else entry.keys_of)
                values[entry.name] = tuple(str(k) for k in inner.data)
                continue
            if entry.by_name is not None:
                values[entry.name] = _read_by_name(entry, saved_data.mapping(entry.by_name))
                continue
            if entry.records is not None:
                shape = None if entry.axes is None else _shape(entry, values, source)
                records = saved_data.records(entry.records)
                if entry.has_default and records and not _in_record(entry, records[0],
                                                                     values):
                    continue
                values[entry.name] = _read_records(entry, records, shape, values)
                continue
            other = _other(entry)
            if entry.key not in source and entry.has_default and not entry.inline and \
                    (other is None or _empty(values.get(other))):
                continue
            shape = None if entry.axes is None else _shape(entry, values, source)
            if entry.rows_by is not None and not entry.mapping:
                values[entry.name] = _rows_by_name(entry, source, shape)
            else:
                values[entry.name] = entry.codec.read(source, entry.key, shape)
        cls._check_saved(values, saved_data)
        try:
            return cls(**values)
        except (TypeError, ValueError) as exc:
            raise saved_data.error(f"does not make a {cls.__name__}: {exc}") from None


def _write_records(data: dict[str, Any], entry: _Entry,
                   value: Mapping[str, np.ndarray] | Sequence[object] | np.ndarray,
                   result: FieldsJSON) -> None:
    """Each value of the field ``entry`` into its record (``saved(records=...)``): of a
    mapping the object of its entries at that index, with ``rows_by`` the object of the
    rows there by name (merged into an object another field wrote under the same key)."""
    assert entry.records is not None
    if isinstance(value, Mapping):
        count = _length(next(iter(value.values()))) if value else \
            len(data.get(entry.records, []))
        items: list[Any] = [{k: v[i] for k, v in value.items()} for i in range(count)]
    else:
        items = list(value)
    records = data.setdefault(entry.records, [{} for _ in items])
    if len(records) != len(items):
        raise ValueError(f"{type(result).__name__}.{entry.name} has {len(items)} values, but "
                         f"its records '{entry.records}' are {len(records)}")
    names = None if entry.rows_by is None else getattr(result, entry.rows_by)
    for record, one in zip(records, items):
        if names is None:
            record[entry.key] = entry.codec.write(one)
        else:
            record.setdefault(entry.key, {}).update(
                {name: entry.codec.write(row) for name, row in zip(names, one)})


def _in_record(entry: _Entry, record: Saved, values: Mapping[str, Any]) -> bool:
    """Whether a record holds the field ``entry`` (with ``rows_by``: its first row)."""
    if entry.rows_by is None or entry.key not in record:
        return entry.key in record
    names: Sequence[str] = values.get(entry.rows_by) or ()
    inner = record.value(entry.key)
    return bool(names) and isinstance(inner, Mapping) and names[0] in inner


def _read_records(entry: _Entry, records: list[Saved], shape: Shape,
                  values: Mapping[str, Any]) -> Any:
    """The field ``entry`` back from its records (see :func:`_write_records`)."""
    if entry.rows_by is not None:
        names = values.get(entry.rows_by, ())
        read = [(record.mapping(entry.key), [np.asarray(entry.codec.read(
            record.mapping(entry.key), str(n), shape)) for n in names]) for record in records]
        shapes = Counter(row.shape for _, rows in read for row in rows)
        if len(shapes) > 1:   # the row that differs from most
            usual = shapes.most_common(1)[0][0]
            inner, name, row = next((inner, n, row) for inner, rows in read
                                    for n, row in zip(names, rows) if row.shape != usual)
            raise inner.error(f"has shape {row.shape}, not {usual}", str(name))
        return np.array([rows for _, rows in read]) if read else np.zeros((0, len(names)))
    read = [entry.codec.read(record, entry.key, shape) for record in records]
    if entry.mapping:
        names = list(read[0]) if read else []
        for record, one in zip(records, read):
            for name in names:
                if name not in one:
                    record.mapping(entry.key).value(name)   # the error naming it
        return {name: np.array([one[name] for one in read]) for name in names}
    return tuple(read) if entry.listed else np.array(read)


def _read_by_name(entry: _Entry, records: Saved) -> dict[str, Any]:
    """A mapping saved by name (``saved(by_name=...)``): each record's ``entry.key`` (a
    record without it is left out when the field has a ``missing`` value)."""
    out = {}
    for name in records.data:
        record = records.mapping(str(name))
        if entry.key in record or not entry.missing:
            out[str(name)] = entry.codec.read(record, entry.key, None)
    return out


def _rows_by_name(entry: _Entry, saved_data: Saved, shape: Shape) -> np.ndarray:
    """An array saved as an object of rows (``saved(rows_by=...)``), each row read by the
    field's codec with the shape's trailing lengths."""
    inner = saved_data.mapping(entry.key)
    row_shape = None if shape is None else shape[1:]
    rows = [np.asarray(entry.codec.read(inner, str(k), row_shape)) for k in inner.data]
    if len({r.shape for r in rows}) > 1:
        raise saved_data.error("holds rows of different lengths", entry.key)
    return np.array(rows) if rows else np.zeros((0,) + tuple(
        s or 0 for s in (row_shape or ())))


def _ordered(data: dict[str, Any], order: tuple[str, ...], kind: str) -> dict[str, Any]:
    """``data`` with its keys in ``order`` (every key must be listed, or ``"..."`` stand for
    those not listed; unchanged without)."""
    if not order:
        return data
    if "..." in order:
        rest = [key for key in data if key not in order]
        order = tuple(k for o in order for k in (rest if o == "..." else [o]))
    unlisted = [key for key in data if key not in order]
    if unlisted:
        raise TypeError(f"{kind}._json_order does not list {unlisted}")
    return {key: data[key] for key in order if key in data}


def _reading_order(entries: tuple[_Entry, ...]) -> list[_Entry]:
    """The fields in an order where every axis is read before the arrays it measures."""
    names = {e.name for e in entries}
    done: set[str] = set()
    order: list[_Entry] = []
    waiting = list(entries)
    while waiting:
        ready = [e for e in waiting if all(not isinstance(a, str) or a in done or a not in names
                                           for a in (*(e.axes or ()), e.keys_of, _other(e),
                                                     e.rows_by if e.records else None))]
        if not ready:   # a cycle of axes: read in field order (the check then says which)
            ready = waiting[:1]
        order += ready
        done.update(e.name for e in ready)
        waiting = [e for e in waiting if e not in ready]
    return order


def _shape(entry: _Entry, values: Mapping[str, Any], saved_data: Saved
           ) -> tuple[int | None, ...]:
    shape: list[int | None] = []
    for axis in entry.axes or ():
        if axis is None or isinstance(axis, int):
            shape.append(axis)
        elif axis in values and values[axis] is not None:
            if np.ndim(values[axis]) == 0 and isinstance(values[axis], np.ndarray):
                raise saved_data.error(f"cannot be checked: its axis '{axis}' is a number, "
                                       "not a list", entry.key)
            shape.append(_length(values[axis]))
        else:
            raise saved_data.error(f"cannot be checked: its axis '{axis}' was not saved",
                                   entry.key)
    return tuple(shape)


class Framed:
    """``to_frame()`` of a result whose numbers are a table, from the attributes it names.

    A subclass lists its columns in ``_frame``: (attribute, label) pairs in order, the first
    the rows.  An attribute holding an array is one column; one holding a mapping of arrays
    is a column per key.  The label is formatted with the result's attributes and, for a
    mapping, ``key``: ``"{parameter}"`` names the column by the swept parameter,
    ``"amplitude:{key}"`` the amplitude of each quantity.  Every column has the rows'
    length (checked).

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> import numpy as np
    >>> @dataclass(frozen=True)
    ... class Levels(Framed):
    ...     _frame = (("time", "{unit}"), ("levels", "level:{key}"))
    ...     unit: str
    ...     time: np.ndarray
    ...     levels: dict
    >>> Levels("s", np.array([0.0, 1.0]), {"x": np.array([2.0, 3.0])}).frame_columns()
    {'s': array([0., 1.]), 'level:x': array([2., 3.])}
    """

    _frame: ClassVar[tuple[tuple[str, str], ...]] = ()

    def frame_columns(self) -> dict[str, np.ndarray]:
        """The table's columns, label -> values, in the order of ``_frame``.

        Returns
        -------
        dict
        """
        names = dict(vars(self))
        columns: dict[str, np.ndarray] = {}
        for attribute, label in self._frame:
            value = getattr(self, attribute)
            if isinstance(value, Mapping):
                for key, column in value.items():
                    columns[label.format(key=key, **names)] = np.asarray(column)
            else:
                columns[label.format(**names)] = np.asarray(value)
        rows = {len(c) for c in columns.values()}
        if len(rows) > 1:
            raise AnalysisError(f"the columns of {type(self).__name__} have the lengths "
                                f"{sorted(rows)}: they do not make one table")
        return columns

    def to_frame(self) -> Any:
        """The result as a table, one row per entry of its first column (pandas, the
        ``study`` extra).

        Returns
        -------
        pandas.DataFrame
        """
        return frame_of(self.frame_columns())


def frame_of(columns: Mapping[str, Sequence[float] | np.ndarray]) -> Any:
    """A pandas DataFrame of named columns (pandas imported here: it is optional).

    Parameters
    ----------
    columns : mapping
        column name -> values, all of one length.

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    AnalysisError
        Without pandas.
    """
    try:
        import pandas as pd
    except ImportError:  # pragma: no cover - pandas is a dependency of the test extra
        raise AnalysisError("to_frame() needs pandas: pip install pandas") from None
    return pd.DataFrame(dict(columns))
