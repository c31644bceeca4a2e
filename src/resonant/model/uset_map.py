"""Nastran's USET table: which degree of freedom is in which displacement set (a, o, q ...).

Nastran orders the rows of its matrices by set: ``KAA`` holds the a-set DOFs, ``KGG``
the g-set, both in the internal (g-set) sequence.  The USET table says which
(grid or scalar point, component) pairs each set holds, so that the rows of a matrix get
their names (``n1042_uz``).  It comes in two forms:

* the table Nastran prints with ``PARAM,USETPRT,0`` (the "USET DEFINITION TABLE
  (INTERNAL SEQUENCE, ROW SORT)" of the ``.f06``/``.out`` file: each set's DOFs in order,
  ``1042-3``), read by :func:`parse_usetprt`;
* a table of bit masks, one row per g-set DOF: ``[node, component, mask, ...]`` (the
  first three columns of pyYeti's ``uset``, as its ``nas2cam`` reads it from an OUTPUT2
  file, written to an OUTPUT4 file as a matrix), read by :func:`uset_from_table`.

The bits are those of Nastran's NDDL, as pyYeti's ``pyyeti.nastran.n2p.mkusetmask`` lists
them (:data:`USET_MASKS`: a set's mask is the union of its own bit and the bits of the
sets it holds, so that ``mask & bits != 0`` tells membership).  In a model:
``dofs = { uset = "run.f06", set = "a" }`` or ``dofs = { uset = "model.op4:USET" }``
(docs/interop.md); without ``set``, the set is the one the matrices are named for
(``KAA``: a) or the one set whose size is the matrices'.

Examples
--------
>>> table = np.array([[3, 1, USET_MASKS["b"]], [3, 2, USET_MASKS["b"]],
...                   [9, 0, USET_MASKS["q"]], [7, 3, USET_MASKS["o"]]])
>>> uset = uset_from_table(table)
>>> uset.names("a"), uset.names("o"), uset.sizes()["g"]
(['n3_ux', 'n3_uy', 'n9'], ['n7_uz'], 4)
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

import resonant.model.limits as limits

from .files import FileRefused, open_regular_file, read_bounded
from .op4_files import DIRECTIONS

#: each set's own bit in Nastran's USET word (NDDL; pyYeti's ``mkusetmask`` lists them)
USET_BITS = {
    "m": 0,
    "o": 2,
    "r": 3,
    "g": 4,
    "n": 5,
    "f": 6,
    "a": 7,
    "l": 8,
    "s": 10,
    "e": 11,
    "p": 12,
    "ne": 13,
    "fe": 14,
    "d": 15,
    "c": 20,
    "b": 21,
    "q": 22,
    "t": 23,
    "u6": 26,
    "u5": 27,
    "u4": 28,
    "u3": 29,
    "u2": 30,
    "u1": 31,
}


def _masks() -> dict[str, int]:
    m, o, r, q, c, e = 1, 1 << 2, 1 << 3, 1 << 22, 1 << 20, 1 << 11
    b = 2 | (1 << 21)
    s = (1 << 9) | (1 << 10)  # sg, sb
    a = q | r | b | c | (1 << 7)
    ell = c | b | (1 << 8)
    t = ell | r | (1 << 23)
    f = a | o | (1 << 6)
    n = f | s | (1 << 5)
    g = n | m | (1 << 4)
    p = g | e | (1 << 12)
    masks = {
        "m": m,
        "b": b,
        "o": o,
        "r": r,
        "s": s,
        "q": q,
        "c": c,
        "e": e,
        "a": a,
        "l": ell,
        "t": t,
        "f": f,
        "n": n,
        "g": g,
        "p": p,
        "fe": f | e | (1 << 14),
        "d": e | a | (1 << 15),
        "ne": n | e | (1 << 13),
    }
    masks.update({f"u{i}": 1 << (32 - i) for i in range(1, 7)})
    return masks


#: set -> the bit mask of its members (the union of the bits of the sets it holds)
USET_MASKS = _masks()
#: the sets a matrix's rows can be named for, in the order they are tried (equal sets: the
#: first is named)
MATRIX_SETS = ("g", "a", "f", "n", "l", "t", "p", "o", "m", "s", "r", "q", "c", "b", "e")
#: the largest bit mask of a 32-bit USET word
_WORD = 2**32
_TITLE = re.compile(r"U S E T\s+D E F I N I T I O N\s+T A B L E(?P<rest>[^\n]*)")
_SET_HEADER = re.compile(r"^\s*(?P<set>[A-Z][A-Z0-9]?)\s+DISPLACEMENT SET\s*$")
_ROW = re.compile(r"^\s*(?P<first>\d+)=(?P<entries>(?:\s+\d+-\d)+)(?:\s*=\s*(?P<last>\d+))?\s*$")
_ENTRY = re.compile(r"(\d+)-(\d)")


def _read_only(array: np.ndarray) -> np.ndarray:
    array = np.array(array)
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class UsetMap:
    """The displacement sets of a model's DOFs, in Nastran's internal sequence.

    Attributes
    ----------
    nodes, components : ndarray
        The grid or scalar point and the component (0 for a scalar point, 1..6) of each DOF
        (the g-set, or the largest set printed), read-only.
    bits : ndarray
        Each DOF's USET word (:data:`USET_MASKS` tells the sets), read-only.
    known : tuple of str
        The sets the table tells completely: all of them for a table of bit masks, the sets
        printed for a printout.
    source : str
        Where it was read from (for the messages).

    Examples
    --------
    >>> uset = uset_from_table(np.array([[1, 3, USET_MASKS["a"]], [2, 3, USET_MASKS["o"]]]))
    >>> uset.partition("f", "a").tolist()
    [True, False]
    """

    nodes: np.ndarray
    components: np.ndarray
    bits: np.ndarray
    known: tuple[str, ...] = tuple(USET_MASKS)
    source: str = ""
    _names: tuple[str, ...] = field(default=(), repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "nodes", _read_only(np.asarray(self.nodes, np.int64)))
        object.__setattr__(self, "components", _read_only(np.asarray(self.components, np.int64)))
        object.__setattr__(self, "bits", _read_only(np.asarray(self.bits, np.int64)))
        names = [
            f"n{node}_{DIRECTIONS[int(c)]}" if c else f"n{node}"
            for node, c in zip(self.nodes.tolist(), self.components.tolist())
        ]
        object.__setattr__(self, "_names", tuple(names))

    def _mask(self, nasset: str) -> int:
        mask = 0
        for part in nasset.lower().replace(" ", "").split("+"):
            if part not in USET_MASKS:
                raise FileRefused(
                    f"'{part}' is not a Nastran displacement set (sets: {', '.join(USET_MASKS)})"
                )
            if part not in self.known:
                raise FileRefused(
                    f"{self._where()}does not tell the {part}-set (it tells "
                    f"the {', '.join(self.known)} sets)"
                )
            mask |= USET_MASKS[part]
        return mask

    def _where(self) -> str:
        return f"the USET table of {self.source} " if self.source else "the USET table "

    def members(self, nasset: str) -> np.ndarray:
        """Which DOFs are in a set (``"a"``, or a union such as ``"q+r"``): booleans.

        Examples
        --------
        >>> uset = uset_from_table(np.array([[1, 3, USET_MASKS["q"]], [2, 3, USET_MASKS["s"]]]))
        >>> uset.members("a").tolist(), uset.members("s+q").tolist()
        ([True, False], [True, True])
        """
        return _read_only((self.bits & self._mask(nasset)) != 0)

    def names(self, nasset: str) -> list[str]:
        """The coordinate names of a set's DOFs in the order of its matrices' rows.

        Examples
        --------
        >>> uset_from_table(np.array([[5, 0, USET_MASKS["a"]]])).names("a")
        ['n5']
        """
        return [self._names[i] for i in np.flatnonzero(self.members(nasset))]

    def partition(self, major: str, minor: str) -> np.ndarray:
        """Which rows of a ``major``-set matrix are the ``minor`` set's (as pyYeti's
        ``mksetpv``).

        Raises
        ------
        FileRefused
            When ``minor`` is not inside ``major``.

        Examples
        --------
        >>> uset = uset_from_table(np.array([[1, 1, USET_MASKS["m"]], [1, 2, USET_MASKS["q"]]]))
        >>> uset.partition("g", "a").tolist()
        [False, True]
        """
        big, small = self.members(major), self.members(minor)
        if np.any(small & ~big):
            raise FileRefused(f"the {minor}-set is not inside the {major}-set")
        return _read_only(small[big])

    def sizes(self) -> dict[str, int]:
        """The number of DOFs of each set the table tells (every set, zero or not).

        Examples
        --------
        >>> uset_from_table(np.array([[1, 1, USET_MASKS["m"]]])).sizes()["m"]
        1
        """
        return {s: int(np.count_nonzero(self.bits & USET_MASKS[s])) for s in self.known}

    def set_for(self, rows: int, hint: str | None = None) -> str:
        """The set whose DOFs are the rows of a matrix of ``rows`` rows.

        Parameters
        ----------
        rows : int
            The matrices' order.
        hint : str, optional
            The set asked for, or the one the matrices are named for (``KAA``: ``"a"``).

        Returns
        -------
        str

        Raises
        ------
        FileRefused
            When the set asked for has another size, or no set or several different ones
            fit.

        Examples
        --------
        >>> uset = uset_from_table(np.array([[1, 1, USET_MASKS["m"]], [1, 2, USET_MASKS["q"]]]))
        >>> uset.set_for(2), uset.set_for(1, "a")
        ('g', 'a')
        """
        sizes = self.sizes()
        if hint is not None:
            self._mask(hint)
            if int(np.count_nonzero(self.members(hint))) == rows:
                return hint
            raise FileRefused(
                f"{self._where()}lists {np.count_nonzero(self.members(hint))} "
                f"DOFs in the {hint}-set but the matrices have {rows} rows"
            )
        fitting = [s for s in MATRIX_SETS if s in self.known and sizes[s] == rows]
        distinct: dict[bytes, str] = {}
        for nasset in fitting:
            distinct.setdefault(self.members(nasset).tobytes(), nasset)
        if len(distinct) == 1:
            return fitting[0]
        listed = ", ".join(f"{s} {sizes[s]}" for s in MATRIX_SETS if s in self.known and sizes[s])
        if not distinct:
            raise FileRefused(
                f"{self._where()}has no set of {rows} DOFs, the matrices' "
                f"order (its sets: {listed})"
            )
        raise FileRefused(
            f"{self._where()}has several different sets of {rows} DOFs "
            f"({', '.join(distinct.values())}); name the set of the matrices' "
            'rows (dofs = { uset = "...", set = "a" })'
        )

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready form.

        Examples
        --------
        >>> uset = uset_from_table(np.array([[1, 1, USET_MASKS["m"]]]))
        >>> UsetMap.from_dict(uset.to_dict()) == uset
        True
        """
        return {
            "nodes": self.nodes.tolist(),
            "components": self.components.tolist(),
            "bits": self.bits.tolist(),
            "known": list(self.known),
            "source": self.source,
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> UsetMap:
        """The map of :meth:`to_dict`."""
        return cls(
            np.asarray(data["nodes"]),
            np.asarray(data["components"]),
            np.asarray(data["bits"]),
            tuple(data["known"]),
            str(data.get("source", "")),
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, UsetMap):
            return NotImplemented
        return (
            np.array_equal(self.nodes, other.nodes)
            and np.array_equal(self.components, other.components)
            and np.array_equal(self.bits, other.bits)
            and self.known == other.known
        )

    __hash__ = None  # type: ignore[assignment]


def set_of_matrix(name: str) -> str | None:
    """The set a Nastran matrix name is for (``KAA``, ``MGG``: a, g; ``KXX``: none).

    Examples
    --------
    >>> set_of_matrix("KAA"), set_of_matrix("mll"), set_of_matrix("KXX")
    ('a', 'l', None)
    """
    match = re.fullmatch(r"(?:k4|[mkb])([a-z])\1", name.lower())
    if match is None or match.group(1) not in MATRIX_SETS:
        return None
    return match.group(1)


def uset_names(
    uset: UsetMap, rows: int, asked: str | None = None, matrix_names: Sequence[str] = ()
) -> list[str]:
    """The coordinate names of a matrix's rows from a USET map: the set asked for, else the
    set the matrices' names say (``KAA``) when its size fits, else the one set that fits.

    Parameters
    ----------
    uset : UsetMap
    rows : int
        The matrices' order.
    asked : str, optional
        The set given in the model (``set = "a"``).
    matrix_names : sequence of str
        The names of the matrices in their files (``KAA``, ``MAA``).

    Returns
    -------
    list of str

    Raises
    ------
    FileRefused
        As :meth:`UsetMap.set_for`.

    Examples
    --------
    >>> uset = uset_from_table([[1, 1, USET_MASKS["m"]], [1, 2, USET_MASKS["q"]]])
    >>> uset_names(uset, 1, matrix_names=["KAA"])
    ['n1_uy']
    """
    if asked is not None:
        return uset.names(uset.set_for(rows, asked.lower()))
    for name in matrix_names:
        hint = set_of_matrix(name)
        if (
            hint is not None
            and hint in uset.known
            and int(np.count_nonzero(uset.members(hint))) == rows
        ):
            return uset.names(hint)
    return uset.names(uset.set_for(rows))


def _checked_dofs(nodes: np.ndarray, components: np.ndarray, what: str) -> None:
    if np.any(nodes < 0) or np.any((components < 0) | (components > 6)):
        raise FileRefused(
            f"{what}: every DOF is a node id >= 0 and a Nastran component 0 (scalar point) or 1..6"
        )
    pairs = nodes * 8 + components
    unique, counts = np.unique(pairs, return_counts=True)
    if np.any(counts > 1):
        twice = int(unique[np.argmax(counts > 1)])
        raise FileRefused(f"{what} lists the DOF {twice // 8}-{twice % 8} twice")


def uset_from_table(table: npt.ArrayLike, source: str = "") -> UsetMap:
    """The USET map of a table of bit masks: one row per g-set DOF, ``[node, component,
    mask, ...]`` (pyYeti's ``uset`` layout; further columns, the coordinates, are ignored).

    Parameters
    ----------
    table : array_like
        n x 3 or wider, whole numbers (an OP4 matrix holds them as floats).
    source : str
        Where it came from, for the messages.

    Returns
    -------
    UsetMap

    Raises
    ------
    FileRefused
        For a table of another shape, numbers that are no ids or masks, a DOF twice.

    Examples
    --------
    >>> uset_from_table([[10, 0, USET_MASKS["q"]]]).names("q")
    ['n10']
    """
    array = np.asarray(table.toarray() if hasattr(table, "toarray") else table, dtype=float)
    what = "the USET table"
    if array.ndim != 2 or array.shape[0] == 0 or array.shape[1] < 3:
        raise FileRefused(
            f"{what} must have a row per DOF and the columns node, component, "
            f"set mask (it is {'x'.join(map(str, array.shape))})"
        )
    head = array[:, :3]
    if (
        not np.all(np.isfinite(head))
        or np.any(head != np.round(head))
        or np.any(head[:, 2] < 0)
        or np.any(head[:, 2] >= _WORD)
    ):
        raise FileRefused(
            f"{what}: node, component and set mask must be whole numbers, the "
            "mask a 32-bit USET word"
        )
    nodes, components, bits = (head[:, i].astype(np.int64) for i in range(3))
    _checked_dofs(nodes, components, what)
    return UsetMap(nodes, components, bits, source=source)


def read_usetprt(path: str, table: int | None = None, shown: str = "") -> UsetMap:
    """The USET map printed in a Nastran ``.f06``/``.out`` file (:func:`parse_usetprt`).

    Parameters
    ----------
    path : str
        A checked path (:func:`resonant.model.matrix_files.resolve_matrix_path`).
    table : int, optional
        Which table, when the file prints several.
    shown : str
        The file as the model names it, for the messages.

    Returns
    -------
    UsetMap

    Raises
    ------
    FileRefused
        For a file that is no regular file, too large, or prints no USET table.
    """
    with open_regular_file(
        path, follow_symlinks=False, max_bytes=limits.MAX_MATRIX_FILE_BYTES
    ) as handle:
        try:
            data = read_bounded(handle, limits.MAX_MATRIX_FILE_BYTES)
        except MemoryError:
            raise FileRefused("not enough memory to read it") from None
    return parse_usetprt(data.decode("latin-1"), table, shown)


def usetprt_tables(text: str) -> int:
    """How many USET tables sorted by rows a printout holds (one per superelement).

    Examples
    --------
    >>> usetprt_tables("no table here")
    0
    """
    return sum(1 for m in _TITLE.finditer(text) if "C O L U M N" not in m.group("rest"))


def parse_usetprt(text: str, table: int | None = None, source: str = "") -> UsetMap:
    """The USET map of the table Nastran prints with ``PARAM,USETPRT,0`` (row sort).

    Each set's DOFs, ``grid-component`` ten to a line, follow its header ``A
    DISPLACEMENT SET``; the page headers between them are skipped.  The DOFs are those of
    the largest set printed (the g-set when it is printed); every other set printed must
    lie inside it.

    Parameters
    ----------
    text : str
        The ``.f06`` (or ``.out``) file's text.
    table : int, optional
        Which table (1, 2 ...) when the file prints several (one per superelement).
    source : str
        The file's name, for the messages.

    Returns
    -------
    UsetMap
        ``known`` lists the sets printed.

    Raises
    ------
    FileRefused
        For a file with no such table (or only the column sort), several tables and no
        ``table``, a row whose count or total does not follow on, a set outside the largest.

    Examples
    --------
    >>> text = '''   U S E T   D E F I N I T I O N   T A B L E   ( I N T E R N A L ...
    ...                  A        DISPLACEMENT SET
    ... 0               -1-        -2-        -3-
    ...       1=        3-1        3-2  9990001-0
    ...                  G        DISPLACEMENT SET
    ...       1=        3-1        3-2        4-1  9990001-0
    ... '''
    >>> uset = parse_usetprt(text)
    >>> uset.names("a"), uset.known
    (['n3_ux', 'n3_uy', 'n9990001'], ('a', 'g'))
    """
    where = f"{source}: " if source else ""
    starts = [m for m in _TITLE.finditer(text) if "C O L U M N" not in m.group("rest")]
    if not starts:
        column = "; it prints the table sorted by columns only" if _TITLE.search(text) else ""
        raise FileRefused(
            f"{where}it prints no USET DEFINITION TABLE sorted by rows (Nastran "
            f"prints one with PARAM,USETPRT,0){column}"
        )
    if table is None and len(starts) > 1:
        raise FileRefused(
            f"{where}it prints {len(starts)} USET tables (one per superelement);"
            ' name the one: dofs = { uset = "...", table = 1 }'
        )
    index = 1 if table is None else table
    if not 1 <= index <= len(starts):
        raise FileRefused(f"{where}it prints {len(starts)} USET table(s), not a table {index}")
    begin = starts[index - 1].end()
    end = starts[index].start() if index < len(starts) else len(text)
    sets = _printed_sets(text[begin:end], where)
    return _from_printed(sets, source, where)


def _printed_sets(chunk: str, where: str) -> dict[str, list[tuple[int, int]]]:
    sets: dict[str, list[tuple[int, int]]] = {}
    current: list[tuple[int, int]] | None = None
    name = ""
    for line in chunk.splitlines():
        header = _SET_HEADER.match(line)
        if header:
            name = header.group("set").lower()
            if name not in USET_MASKS:
                raise FileRefused(
                    f"{where}the USET table prints a set '{name.upper()}' "
                    "that is no Nastran displacement set"
                )
            if name in sets and current is not sets[name]:
                break  # a set printed again: the table is over
            current = sets.setdefault(name, [])  # a set's next page repeats its header
            continue
        row = _ROW.match(line)
        if row is None or current is None:
            continue
        first = int(row.group("first"))
        if first != len(current) + 1:
            if current and first == 1:
                break  # not this set's
            raise FileRefused(
                f"{where}the {name}-set of the USET table goes on at DOF "
                f"{first} after {len(current)} DOFs (a line is missing)"
            )
        entries = [(int(a), int(b)) for a, b in _ENTRY.findall(row.group("entries"))]
        current.extend(entries)
        last = row.group("last")
        if last is not None and int(last) != len(current):
            raise FileRefused(
                f"{where}a line of the {name}-set of the USET table ends at "
                f"{last} but lists DOFs up to {len(current)}"
            )
    sets = {k: v for k, v in sets.items() if v}
    if not sets:
        raise FileRefused(f"{where}its USET table lists no DOF")
    return sets


def _from_printed(
    sets: Mapping[str, Sequence[tuple[int, int]]], source: str, where: str
) -> UsetMap:
    base_name = "g" if "g" in sets else max(sets, key=lambda s: len(sets[s]))
    base = np.array(sets[base_name], dtype=np.int64).reshape(-1, 2)
    _checked_dofs(base[:, 0], base[:, 1], f"{where}the {base_name}-set of the USET table")
    position = {(int(n), int(c)): i for i, (n, c) in enumerate(base)}
    bits = np.zeros(len(base), dtype=np.int64)
    for name, dofs in sets.items():
        rows = [position.get((n, c), -1) for n, c in dofs]
        if -1 in rows:
            n, c = dofs[rows.index(-1)]
            raise FileRefused(
                f"{where}the {name}-set of the USET table holds {n}-{c}, which "
                f"is not in its {base_name}-set"
            )
        if len(set(rows)) != len(rows) or np.any(np.diff(rows) <= 0):
            raise FileRefused(
                f"{where}the {name}-set of the USET table is not in the order "
                f"of its {base_name}-set (or lists a DOF twice)"
            )
        bits[rows] |= 1 << USET_BITS[name]
    return UsetMap(base[:, 0], base[:, 1], bits, tuple(sets), source)


__all__ = [
    "UsetMap",
    "USET_BITS",
    "USET_MASKS",
    "MATRIX_SETS",
    "uset_from_table",
    "parse_usetprt",
    "read_usetprt",
    "usetprt_tables",
    "set_of_matrix",
    "uset_names",
]
