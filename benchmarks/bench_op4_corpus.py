"""Corpus run of resonant's OP4 reader against pyYeti's (docs/performance-large.md,
"OP4 corpus").

Every matrix of every file is read by both readers and compared bit for bit (the float64
bit patterns of the dense matrix, signed zeros included; the directory: names, sizes,
forms and types, in file order, repeated names kept):

* **Nastran's own files**: every ``*.op4`` under pyYeti's installed ``tests`` folder
  (its OP4 suite in every layout Nastran writes, single and double precision, 4- and
  8-byte integers, both byte orders, ASCII with and without the ``D`` exponent; the
  nas2cam and EXTSEOUT outputs of several matrices each, repeated names included; a
  large-dimension set; complex matrices);
* **generated** by pyYeti's writer (not timed): dense, bigmat and non-bigmat layouts x
  little-endian, big-endian and ASCII (16 and 9 digits) x real and complex, each file of
  twelve matrices of varied shapes (1 x 1, a row, a column, an all-zero matrix, empty
  columns, random sparse and dense, a symmetric one), and a real file of 70,000 rows (past
  the 65,535 rows at which a non-bigmat file switches to bigmat strings).

Complex matrices are not values resonant takes (M, K, C are real): the reader must refuse
them with a :class:`~resonant.model.files.FileRefused` naming the type, and read the
directory as pyYeti does. Files pyYeti itself cannot read are listed, not compared.

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_op4_corpus.py [--json OUT]``.

Examples
--------
>>> shapes = varied_shapes(np.random.default_rng(0), complex_values=False)
>>> len(shapes), shapes["one"].shape, shapes["row"].shape
(12, (1, 1), (1, 17))
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from resonant.model.files import FileRefused
from resonant.model.op4_files import numpy_print_options_kept
from resonant.model.op4_records import forget_parsed_text, op4_entries, op4_runs


def _pyyeti() -> Any:
    with numpy_print_options_kept():
        from pyyeti.nastran import op4
    return op4


def varied_shapes(rng: np.random.Generator, complex_values: bool) -> dict[str, Any]:
    """Twelve matrices of varied shapes and fill (dense arrays; some sparse)."""

    def numbers(*shape: int) -> np.ndarray:
        values = rng.standard_normal(shape) * 10.0 ** rng.integers(-30, 30, shape)
        if complex_values:
            values = values + 1j * rng.standard_normal(shape)
        return values

    sparse_part = sp.random(300, 200, density=0.02, random_state=rng, format="csc")
    with_empty = numbers(40, 30)
    with_empty[:, 5:12] = 0.0
    with_empty[10:20, :] = 0.0
    symmetric = numbers(25, 25).real
    symmetric = symmetric + symmetric.T
    shapes = {
        "one": numbers(1, 1),
        "row": numbers(1, 17),
        "column": numbers(23, 1),
        "zeros": np.zeros((6, 4)),
        "empty_cols": with_empty,
        "sparse": (sparse_part.toarray() * (1 + (1j if complex_values else 0))),
        "dense": numbers(64, 48),
        "symmetric": symmetric,
        "tall": numbers(500, 3),
        "wide": numbers(3, 500),
        "tiny_values": numbers(9, 9) * 1e-300,
        "signed_zero": np.array([[-0.0, 1.0], [0.0, -0.0]]),
    }
    return shapes


def generated_files(folder: Path) -> list[Path]:
    """The files pyYeti's writer makes for the corpus."""
    op4 = _pyyeti()
    rng = np.random.default_rng(20261202)
    files = []
    for layout in ("dense", "bigmat", "nonbigmat"):
        for style in ("le", "be", "ascii16", "ascii9"):
            for complex_values in (False, True):
                name = f"gen_{layout}_{style}_{'complex' if complex_values else 'real'}.op4"
                path = folder / name
                matrices = varied_shapes(rng, complex_values)
                if style.startswith("ascii"):  # pyYeti's fields overflow at |exponent| > 99
                    del matrices["tiny_values"]
                    op4.write(str(path), matrices, binary=False,
                              digits=int(style[5:]), sparse=layout)
                else:
                    op4.write(str(path), matrices, binary=True,
                              endian="<" if style == "le" else ">", sparse=layout)
                files.append(path)
    big = sp.random(70_000, 40, density=2e-4, random_state=rng, format="csc")
    big.data = rng.standard_normal(big.nnz)
    for style in ("le", "ascii16"):
        path = folder / f"gen_70000rows_nonbigmat_{style}.op4"
        op4.write(str(path), {"tall": big}, binary=style == "le", sparse="nonbigmat")
        files.append(path)
    return files


def nastran_files() -> list[Path]:
    """Every OP4 file of pyYeti's installed tests."""
    import pyyeti

    return sorted(Path(pyyeti.__file__).parent.joinpath("tests").rglob("*.op4"))


#: above this many entries a matrix is compared sparse (pyYeti's dense read would not fit)
DENSE_ENTRIES = 10_000_000


def _bits(matrix: Any) -> np.ndarray:
    dense = matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix)
    return np.ascontiguousarray(dense, dtype=np.float64).view(np.uint64)


def _stored(matrix: Any) -> tuple[np.ndarray, ...]:
    """A sparse matrix's non-zero entries, sorted: rows, columns, value bits."""
    coo = sp.coo_matrix(matrix)
    keep = coo.data != 0
    rows, columns, values = coo.row[keep], coo.col[keep], coo.data[keep]
    order = np.lexsort((rows, columns))
    return rows[order], columns[order], values[order].astype(np.float64).view(np.uint64)


def _equal(mine: Any, theirs: Any) -> bool:
    if sp.issparse(theirs):
        return all(np.array_equal(a, b) for a, b in zip(_stored(mine), _stored(theirs)))
    return np.array_equal(_bits(mine), _bits(theirs))


def compare(path: Path) -> dict[str, Any]:
    """One file read by both readers: the directory, each matrix's bits, the times."""
    op4 = _pyyeti()
    record: dict[str, Any] = {"file": path.name, "bytes": path.stat().st_size}
    shapes = op4.dir(str(path), verbose=False)[1]
    large = any(r * c > DENSE_ENTRIES for r, c in shapes)
    record["sparse"] = large
    try:
        start = time.perf_counter()
        names, matrices, forms, types = op4.load(str(path), into="list", sparse=large)
        record["pyyeti_s"] = time.perf_counter() - start
    except Exception as exc:  # noqa: BLE001 - a file pyYeti cannot read is listed
        record["pyyeti_error"] = f"{type(exc).__name__}: {str(exc)[:120]}"
        return record
    start = time.perf_counter()
    data = path.read_bytes()
    try:
        try:
            entries = op4_entries(data)
        except FileRefused as exc:
            record.update(resonant_error=str(exc), matrices=len(names), real=len(names),
                          resonant_s=time.perf_counter() - start,
                          complex_refused=0, unequal=["(the whole file refused)"],
                          directory_equal=False)
            return record
        ours = []
        for entry in entries:
            try:
                runs = op4_runs(data, entry)
                if large:
                    rows, columns, values = runs.coo()
                    ours.append(sp.coo_matrix((values, (rows, columns)),
                                              shape=(entry.rows, entry.columns)))
                else:
                    ours.append(runs.dense())
            except FileRefused as exc:
                ours.append(exc)
    finally:
        forget_parsed_text()
    record["resonant_s"] = time.perf_counter() - start
    record["names_equal"] = [e.name for e in entries] == [n.lower() for n in names]
    record["directory_equal"] = (
        [(e.rows, e.columns) for e in entries] == [m.shape for m in matrices]
        and [e.form for e in entries] == list(forms)
        and [e.kind for e in entries] == list(types))
    real = complex_refused = 0
    unequal: list[str] = []
    for name, theirs, mine, kind in zip(names, matrices, ours, types):
        if kind in (3, 4):
            if isinstance(mine, FileRefused) and f"type {kind}" in str(mine):
                complex_refused += 1
            else:
                unequal.append(f"{name} (complex, not refused)")
            continue
        real += 1
        if isinstance(mine, FileRefused) or not _equal(mine, theirs):
            unequal.append(name)
    record.update(matrices=len(names), real=real, complex_refused=complex_refused,
                  unequal=unequal, kinds=sorted({int(t) for t in types}))
    return record


def three_digit_exponents(folder: Path) -> dict[str, str]:
    """What each reader makes of exponents beyond 99 in ASCII: pyYeti's writer (its field
    overflows: ``1.5000000000000001E-300-3.2500000000000000E-301``) and Fortran's own
    ``E16.9`` form (the ``E`` dropped: `` 1.500000000-300``)."""
    from resonant.model.op4_files import read_op4_matrix

    op4 = _pyyeti()
    written = np.array([[1.5e-300, 2.0], [-3.25e-301, 4e200]])
    overflowing = folder / "overflowing.op4"
    op4.write(str(overflowing), {"kaa": written}, binary=False)
    fortran = folder / "fortran.op4"
    fortran.write_text("       1       1       2       2KAA     1P,5E16.9\n"
                       "       1       1       1\n 1.500000000-300\n"
                       "       2       1       1\n 1.000000000E+00\n", encoding="ascii")
    found = {}
    for label, path, truth in (("pyyeti_writer", overflowing, written),
                               ("fortran_form", fortran, np.array([[1.5e-300]]))):
        for side in ("pyyeti", "resonant"):
            try:
                matrix = (op4.load(str(path), into="list")[1][0] if side == "pyyeti"
                          else read_op4_matrix(str(path), "KAA", "K", square=False))
                found[f"{label}:{side}"] = ("read, equal" if np.array_equal(matrix, truth)
                                            else f"read, WRONG: {matrix.tolist()}")
            except Exception as exc:  # noqa: BLE001 - each side's outcome is the record
                found[f"{label}:{side}"] = f"refused: {type(exc).__name__}: {exc}"
    return found


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", type=Path, help="write the records here")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # pyYeti's notes on matrix names
        files = nastran_files() + generated_files(Path(folder))
        records = [compare(path) for path in files]
        exponents = three_digit_exponents(Path(folder))
    read = [r for r in records if "pyyeti_error" not in r]
    failed = [r for r in read if r["unequal"] or not r["directory_equal"]]
    totals = {
        "files": len(records),
        "compared": len(read),
        "pyyeti_cannot_read": [(r["file"], r["pyyeti_error"]) for r in records
                               if "pyyeti_error" in r],
        "matrices": sum(r["matrices"] for r in read),
        "real_bit_equal": sum(r["real"] for r in read) - sum(len(r["unequal"]) for r in read),
        "real": sum(r["real"] for r in read),
        "complex_refused": sum(r["complex_refused"] for r in read),
        "files_not_equal": [(r["file"], r["unequal"], r["directory_equal"],
                             r.get("resonant_error", "")) for r in failed],
        "pyyeti_s": sum(r["pyyeti_s"] for r in read),
        "resonant_s": sum(r["resonant_s"] for r in read),
        "megabytes": sum(r["bytes"] for r in read) / 2**20,
        "names_differ": [r["file"] for r in read if not r.get("names_equal", True)],
        "compared_sparse": [r["file"] for r in read if r.get("sparse")],
        "three_digit_exponents": exponents,
    }
    print(json.dumps(totals, indent=1))
    if args.json:
        args.json.write_text(json.dumps({"totals": totals, "records": records}, indent=1),
                             encoding="utf-8")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
