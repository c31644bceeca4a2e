"""A model written beside FE files (``resonant import``): the ``[matrices]`` section that
names them, so that every command runs on them.

The matrices are not copied: the model refers to the FE file (``M = "model.op4:MAA"``)
by a path relative to the model's folder, under the usual file policy (docs/security.md).
Which matrix is the mass, the stiffness, the damping and the DOF map is taken from the
names Nastran gives them (``MAA``/``MGG``/``MXX``..., ``KAA``..., ``BAA``... for viscous
damping; an n x 2 matrix named like ``DOFS`` or ``USET`` for the DOF map, else a USET
table of bit masks, :mod:`resonant.model.uset_map`), from the file
names of Abaqus matrix output (``job_MASS2.mtx``, ``job_STIF2.mtx``), or from the names
given (``names={"M": "MHH"}``). Anything ambiguous is an error that lists the candidates.

Examples
--------
>>> guess_matrix("M", [("kaa", (3, 3), 2), ("maa", (3, 3), 2)], 3)
'maa'
>>> toml_string('a "b"')
'"a \\\\"b\\\\""'
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from .abaqus_files import looks_like_abaqus
from .files import FileRefused, open_regular_file
from .full_files import has_damping
from .op4_files import op4_directory

#: Nastran's matrix names by role, in the order they are tried (the a-, g-, x- (EXTSEOUT
#: boundary), h- (modal), l-, f-, n-sets ...)
NASTRAN_NAMES = {
    "M": tuple(f"m{s}" for s in ("aa", "gg", "xx", "hh", "ll", "ff", "nn", "kk", "jj",
                                 "bb", "qq")),
    "K": tuple(f"k{s}" for s in ("aa", "gg", "xx", "hh", "ll", "ff", "nn", "kk", "jj",
                                 "bb", "qq")),
    "C": tuple(f"b{s}" for s in ("aa", "gg", "xx", "hh", "ll", "ff", "nn", "kk", "jj",
                                 "bb", "qq")),
}
#: what the role is called in messages
ROLE_WORDS = {"M": "mass", "K": "stiffness", "C": "damping", "dofs": "DOF map"}
#: Abaqus matrix output file names by role
_ABAQUS_ROLES = (("M", re.compile(r"mass", re.I)), ("K", re.compile(r"stif", re.I)),
                 ("C", re.compile(r"dmp|damp|visc", re.I)))


class ImportRefused(FileRefused):
    """An FE file that cannot be imported: the message says why, ``path`` which file."""

    def __init__(self, path: Path, message: str) -> None:
        super().__init__(message)
        self.path = path


@dataclass(frozen=True)
class ImportedModel:
    """The model text written for FE files.

    Attributes
    ----------
    text : str
        The TOML model.
    matrices : dict
        ``[matrices]`` key -> the value written (``"model.op4:MAA"``).
    outside : tuple of str
        Folders of FE files outside the model's folder (to pass as ``--allow-path``).
    """

    text: str
    matrices: dict[str, str]
    outside: tuple[str, ...] = ()


def toml_string(value: str) -> str:
    """A TOML basic string (JSON's escapes are TOML's)."""
    return json.dumps(value, ensure_ascii=False)


def guess_matrix(role: str, directory: Sequence[tuple[str, tuple[int, int], int]],
                 size: int | None) -> str | None:
    """The matrix of a file's directory that plays ``role`` (None: none does).

    Parameters
    ----------
    role : {"M", "K", "C", "dofs"}
    directory : sequence of (name, (rows, columns), Nastran type)
    size : int or None
        The order of K, when known (M, C and the DOF map must fit it).

    Returns
    -------
    str or None

    Raises
    ------
    FileRefused
        When several matrices fit equally.
    """
    real = [(n, s) for n, s, t in directory if t in (1, 2)]
    if role == "dofs":
        fitting = [n for n, (r, c) in real if c == 2 and r > 1 and (size is None or r == size)]
        named = [n for n in fitting if "dof" in n or "uset" in n]
        tables = [n for n, (r, c) in real if c >= 3 and r > 1 and "uset" in n]  # bit masks
        chosen = named or fitting or tables
        misfit = [(n, r) for n, (r, c) in real if c == 2 and "dof" in n and n not in fitting]
        if not chosen and misfit:   # a DOF map of other matrices: not dropped in silence
            name, rows = misfit[0]
            raise FileRefused(f"matrix {name.upper()} looks like the DOF map but lists {rows} "
                              f"DOFs where the matrices have {size} rows: it does not belong "
                              "to them")
    else:
        square = {n: r for n, (r, c) in real if r == c and (size is None or r == size)}
        exact = [n for n in NASTRAN_NAMES[role] if n in square]
        if exact:
            return exact[0]
        letter = NASTRAN_NAMES[role][0][0]
        chosen = [n for n in square if n.startswith(letter) and not n.startswith("k4")]
    if len(chosen) > 1:
        raise FileRefused(f"several matrices could be the {ROLE_WORDS[role]} matrix "
                          f"({', '.join(n.upper() for n in chosen)}); name the one for "
                          f"{role}")
    return chosen[0] if chosen else None


def _directory(path: Path) -> list[tuple[str, tuple[int, int], int]]:
    suffix = path.suffix.lower()
    if suffix == ".op4":
        return op4_directory(str(path))
    return _dmig_directory(path)


def _dmig_directory(path: Path) -> list[tuple[str, tuple[int, int], int]]:
    """The DMIG matrices of a punch or bulk file: names, sizes, type (from the header
    cards: ``DMIG NAME 0 IFO TIN ...``)."""
    with open_regular_file(path, follow_symlinks=False, max_bytes=2**30) as handle:
        text = handle.read(2**30).decode("ascii", "replace")
    found: dict[str, set[tuple[str, str]]] = {}
    types: dict[str, int] = {}
    for line in text.splitlines():
        if not line[:4].upper() == "DMIG":
            continue
        fields = _card_fields(line)
        if len(fields) < 4:
            continue
        name = fields[1].lower()
        if fields[2] == "0":  # the header card: its matrix type (TIN)
            types[name] = int(fields[4]) if len(fields) > 4 and fields[4].isdigit() else 1
            found.setdefault(name, set())
        else:
            found.setdefault(name, set()).add((fields[2], fields[3]))
    return [(name, (len(columns), len(columns)), types.get(name, 1))
            for name, columns in found.items()]


def _card_fields(line: str) -> list[str]:
    """The fields of a bulk data card in free (comma), small (8) or large (16, ``*``)
    field format."""
    if "," in line:
        return [f.strip() for f in line.split(",")]
    width = 16 if line[:8].rstrip().endswith("*") else 8
    fields = [line[:8].strip().rstrip("*")]
    fields += [line[i:i + width].strip() for i in range(8, min(len(line), 8 + 4 * width
                                                              if width == 16 else 72), width)]
    return fields


def _reference(path: Path, folder: Path) -> str:
    return Path(os.path.relpath(path, folder)).as_posix()


def _named_file_matrices(path: Path, names: Mapping[str, str], reference: str
                         ) -> dict[str, str]:
    """``[matrices]`` entries of one OP4 or punch file."""
    directory = _directory(path)
    sized = path.suffix.lower() == ".op4"  # DMIG: a symmetric matrix lists one triangle
    listed = ", ".join(n.upper() for n, _, _ in directory[:12])
    chosen: dict[str, str] = {}
    size = None
    for role in ("K", "M", "C", "dofs"):
        name = names.get(role)
        if name is None:
            name = guess_matrix(role, directory, size)
            if name is None:
                if role in ("K", "M"):
                    raise FileRefused(f"it holds no matrix that is clearly the "
                                      f"{ROLE_WORDS[role]} matrix (it holds {listed}); "
                                      f"name the {ROLE_WORDS[role]} matrix ({role})")
                continue
        elif name.lower() not in {n for n, _, _ in directory}:
            raise FileRefused(f"it holds no matrix named {name.upper()} (it holds {listed})")
        chosen[role] = f"{reference}:{name.upper()}"
        if role == "K" and sized:
            size = next(s[0] for n, s, _ in directory if n == name.lower())
    return chosen


def _abaqus_matrices(paths: Sequence[Path], names: Mapping[str, str], folder: Path
                     ) -> dict[str, str]:
    """``[matrices]`` entries of Abaqus matrix output files: each file's role from
    ``names`` (role -> file) or from its name (MASS, STIF, DMP)."""
    chosen: dict[str, str] = {}
    given = {Path(v).resolve(): k for k, v in names.items() if k in ("M", "K", "C")}
    for path in paths:
        role = given.get(path.resolve()) or next(
            (r for r, pattern in _ABAQUS_ROLES if pattern.search(path.name)), None)
        if role is None:
            raise ImportRefused(path, "is it the mass, the stiffness or the damping matrix? "
                                      "Its name does not say (MASS, STIF, DMP); name its "
                                      "role (M, K or C)")
        if role in chosen:
            raise ImportRefused(path, f"a second file for the {ROLE_WORDS[role]} matrix")
        chosen[role] = _reference(path, folder)
    for role in ("M", "K"):
        if role not in chosen:
            generated = "MASS" if role == "M" else "STIFFNESS"
            raise ImportRefused(paths[0], f"no file for the {ROLE_WORDS[role]} matrix "
                                f"(Abaqus writes it with *MATRIX GENERATE, {generated})")
    return chosen


def _kind(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix in (".op4", ".full"):
        return suffix[1:]
    if suffix in (".pch", ".bdf", ".dat"):
        return "dmig"
    if suffix == ".mtx":
        with open_regular_file(path, follow_symlinks=False, max_bytes=2**30) as handle:
            if looks_like_abaqus(handle.read(4096)):
                return "abaqus"
        raise FileRefused("it is a Matrix Market file, not Abaqus matrix output: name it "
                          "in a [matrices] section directly (M = \"m.mtx\")")
    raise FileRefused("not an FE file resonant imports (.op4, .pch/.bdf/.dat with DMIG "
                      "entries, .full, Abaqus .mtx)")


def fe_model(files: Sequence[str | os.PathLike[str]], output: str | os.PathLike[str], *,
             names: Mapping[str, str] | None = None, title: str | None = None,
             drop_unconnected: bool = False) -> ImportedModel:
    """The model text for FE files, to be written to ``output``.

    Parameters
    ----------
    files : sequence of paths
        One OP4, punch/bulk (DMIG) or ``.full`` file, or the Abaqus matrix output files.
    output : path
        Where the model will be written (paths are made relative to its folder).
    names : mapping, optional
        Role (``M``, ``K``, ``C``, ``dofs``) -> matrix name (OP4, DMIG) or file (Abaqus).
    title : str, optional
        The model's title (default: "Imported from FILE").
    drop_unconnected : bool
        Write ``drop_unconnected = true`` (remove coordinates with neither mass nor
        stiffness).

    Returns
    -------
    ImportedModel

    Raises
    ------
    ImportRefused
        For a file that is not an FE file, or matrices that cannot be told apart
        (``path``: which file).
    """
    paths = [Path(f).resolve() for f in files]
    if not paths:
        raise ImportRefused(Path(output), "no FE file given")
    folder = Path(output).resolve().parent
    names = dict(names or {})
    given = {path: Path(f) for path, f in zip(paths, files)}  # as the user wrote them
    kinds = set()
    for path in paths:
        try:
            kinds.add(_kind(path))
        except FileRefused as exc:
            raise ImportRefused(given[path], str(exc)) from None
    if kinds == {"abaqus"}:
        try:
            matrices = _abaqus_matrices(paths, names, folder)
        except ImportRefused as exc:
            raise ImportRefused(given[exc.path], str(exc)) from None
    elif len(paths) > 1:
        raise ImportRefused(given[paths[1]], "give one OP4, punch or .full file (several files: "
                                      "Abaqus matrix output only)")
    else:
        path, reference = paths[0], _reference(paths[0], folder)
        try:
            if kinds == {"full"}:
                matrices = {"M": f"{reference}:M", "K": f"{reference}:K"}
                if "C" in names or has_damping(str(path)):
                    matrices["C"] = f"{reference}:C"
                matrices["dofs"] = reference
            else:
                matrices = _named_file_matrices(path, names, reference)
        except FileRefused as exc:
            raise ImportRefused(given[path], str(exc)) from None
    shown = ", ".join(p.name for p in paths)
    lines = [f"title = {toml_string(title or f'Imported from {shown}')}", "",
             "[matrices]"]
    lines += [f"{key} = {toml_string(value)}" for key, value in matrices.items()]
    if drop_unconnected:
        lines.append("drop_unconnected = true")
    outside = tuple(sorted({str(p.parent) for p in paths
                            if not p.parent.is_relative_to(folder)}))
    return ImportedModel("\n".join(lines) + "\n", matrices, outside)


__all__ = ["ImportedModel", "ImportRefused", "fe_model", "guess_matrix", "toml_string",
           "NASTRAN_NAMES", "ROLE_WORDS"]
