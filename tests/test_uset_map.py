"""Nastran's USET table: set membership to coordinates named by node and direction
(resonant.model.uset_map, ``dofs = { uset = ..., set = ... }`` in [matrices]).

References:

* the bit masks of Nastran's USET word: pyYeti's ``pyyeti.nastran.n2p.mkusetmask`` (from
  the NDDL), compared exactly; set partitions against pyYeti's ``mksetpv`` (hypothesis,
  random USET words: equal);
* ``data/uset/inboard_xtmatrix_usetprt.out``: the USET DEFINITION TABLE that NX Nastran
  printed for pyYeti's ``nas2cam_csuper/inboard_xtmatrix.out`` (superelement 102, sets L,
  A, F, N, G; tests/data/README.md for source and licence): its set sizes and DOFs as
  printed (its line totals "= 10", "= 20", "= 30");
* small hand-made printouts and OP4 tables for every path and every refusal.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from resonant.errors import ModelError
from resonant.model.fe_import import fe_model
from resonant.model.files import FileRefused
from resonant.model.loader import loads
from resonant.model.uset_map import (
    USET_MASKS,
    UsetMap,
    parse_usetprt,
    read_usetprt,
    set_of_matrix,
    uset_from_table,
    uset_names,
    usetprt_tables,
)

DATA = Path(__file__).resolve().parent / "data" / "uset"
TITLE = (
    "                U S E T   D E F I N I T I O N   T A B L E   ( I N T E R N A L   "
    "S E Q U E N C E ,   R O W   S O R T )"
)
COLUMNS = "0               -1-        -2-        -3-        -4-        -5-"
PAGE = (
    "1    HAND-MADE MODEL                                  DECEMBER 2, 2026  NX NASTRAN"
    "   PAGE     7\n      SUBTITLE 1042\n0"
)


def _set(name: str, dofs: list[tuple[int, int]], split_page_after: int | None = None) -> str:
    """A set as Nastran prints it: ten DOFs a line, the count at each line's start and the
    running total at the end of each full line."""
    lines = [
        f"                                                       {name}        DISPLACEMENT SET",
        COLUMNS,
        " ",
    ]
    for start in range(0, len(dofs), 10):
        chunk = dofs[start : start + 10]
        row = f"{start + 1:6d}=" + "".join(f" {g:8d}-{c:1d}" for g, c in chunk)
        if len(chunk) == 10:
            row += f"    ={start + 10:6d}"
        lines.append(row)
        if split_page_after is not None and start + 10 == split_page_after:
            lines += [PAGE, lines[0], COLUMNS, " "]  # the next page repeats the header
    return "\n".join(lines)


#: a hand-made model: grid 1 (all six: 1-3 in the a-set, 4-6 SPC'd), grid 2 (1-3 omitted,
#: 4-6 dependent by an RBE2), scalar points 100, 101 (modal, q-set)
G_SET = [(1, c) for c in range(1, 7)] + [(2, c) for c in range(1, 7)] + [(100, 0), (101, 0)]
A_SET = [(1, 1), (1, 2), (1, 3), (100, 0), (101, 0)]
O_SET = [(2, 1), (2, 2), (2, 3)]
F_SET = [(1, 1), (1, 2), (1, 3), (2, 1), (2, 2), (2, 3), (100, 0), (101, 0)]
PRINTOUT = "\n".join(
    [
        PAGE,
        TITLE,
        _set("A", A_SET),
        PAGE,
        _set("O", O_SET),
        _set("F", F_SET),
        PAGE,
        _set("G", G_SET, split_page_after=10),
        " *** USER INFORMATION MESSAGE 4106 (INPTT4)",
    ]
)


def _table() -> np.ndarray:
    """The same model as a table of bit masks: [node, component, mask, x, y, z]."""
    words = {
        (1, 4): "s",
        (1, 5): "s",
        (1, 6): "s",
        (2, 4): "m",
        (2, 5): "m",
        (2, 6): "m",
        (2, 1): "o",
        (2, 2): "o",
        (2, 3): "o",
        (100, 0): "q",
        (101, 0): "q",
    }
    return np.array([[g, c, USET_MASKS[words.get((g, c), "b")], 0.0, 0.0, 0.0] for g, c in G_SET])


def test_masks_are_pyyetis() -> None:
    pytest.importorskip("pyyeti")
    from resonant.model.op4_files import numpy_print_options_kept

    with numpy_print_options_kept():
        from pyyeti.nastran import n2p
    assert n2p.mkusetmask() == USET_MASKS


def test_hand_made_printout_gives_each_set_by_node_and_direction() -> None:
    uset = parse_usetprt(PRINTOUT, source="run.f06")
    assert uset.known == ("a", "o", "f", "g")
    assert uset.names("a") == ["n1_ux", "n1_uy", "n1_uz", "n100", "n101"]
    assert uset.names("o") == ["n2_ux", "n2_uy", "n2_uz"]
    assert uset.names("g")[-3:] == ["n2_rz", "n100", "n101"]
    assert uset.partition("f", "a").tolist() == [True] * 3 + [False] * 3 + [True] * 2
    assert uset.sizes() == {"a": 5, "o": 3, "f": 8, "g": 14}
    assert usetprt_tables(PRINTOUT) == 1
    assert UsetMap.from_dict(uset.to_dict()) == uset
    assert not uset.bits.flags.writeable


def test_printout_and_bit_table_give_the_same_names() -> None:
    printed, table = parse_usetprt(PRINTOUT), uset_from_table(_table())
    for nasset in ("a", "o", "f", "g"):
        assert printed.names(nasset) == table.names(nasset)
    assert table.names("m") == ["n2_rx", "n2_ry", "n2_rz"]
    assert table.names("q+b") == table.names("a")
    with pytest.raises(FileRefused, match="does not tell the m-set"):
        printed.names("m")
    with pytest.raises(FileRefused, match="'x' is not a Nastran displacement set"):
        table.names("x")


def test_real_nastran_printout() -> None:
    uset = read_usetprt(str(DATA / "inboard_xtmatrix_usetprt.out"), shown="inboard.out")
    assert uset.known == ("l", "a", "f", "n", "g")
    assert uset.sizes() == {"l": 28, "a": 36, "f": 36, "n": 36, "g": 36}
    names = uset.names("a")
    assert names[:7] == ["n3_ux", "n3_uy", "n3_uz", "n3_rx", "n3_ry", "n3_rz", "n11_ux"]
    assert names[24:] == [f"n9990001_{d}" for d in ("ux", "uy", "uz", "rx", "ry", "rz")] + [
        f"n9990002_{d}" for d in ("ux", "uy", "uz", "rx", "ry", "rz")
    ]
    assert uset.names("l")[24:] == ["n9990002_uz", "n9990002_rx", "n9990002_ry", "n9990002_rz"]
    assert uset_names(uset, 28) == uset.names("l")
    with pytest.raises(FileRefused, match="several different sets|no set of 30"):
        uset_names(uset, 30)


def test_set_named_by_the_matrices_or_the_size() -> None:
    uset = uset_from_table(_table())
    assert set_of_matrix("KAA") == "a" and set_of_matrix("K4GG") == "g"
    assert set_of_matrix("KXX") is None and set_of_matrix("MZZ") is None
    assert uset_names(uset, 5, matrix_names=["KAA"]) == uset.names("a")
    assert uset_names(uset, 14) == uset.names("g")
    assert uset_names(uset, 5, "A") == uset.names("a")
    with pytest.raises(
        FileRefused, match="lists 14 DOFs in the g-set but the matrices have 5 rows"
    ):
        uset_names(uset, 5, "g")
    with pytest.raises(FileRefused, match="several different sets of 3 DOFs"):
        uset_names(uset, 3)  # o and m (and s, r ...): name it
    with pytest.raises(FileRefused, match="no set of 4 DOFs"):
        uset_names(uset, 4)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("nothing here", "no USET DEFINITION TABLE sorted by rows .*PARAM,USETPRT,0"),
        (TITLE.replace("R O W", "C O L U M N"), "sorted by columns only"),
        (PRINTOUT + "\n" + PRINTOUT, "prints 2 USET tables .*table = 1"),
        (PRINTOUT.replace("    11=", "    21="), "goes on at DOF 21 after 10 DOFs"),
        (PRINTOUT.replace("    =    10", "    =    11", 1), "ends at 11 but lists DOFs up to 10"),
        (PRINTOUT.replace("A        DISPLACEMENT", "X        DISPLACEMENT"), "no Nastran"),
        (PRINTOUT.replace("  101-0", "  777-0", 1), "holds 777-0, which is not in its g-set"),
        (TITLE + "\n" + _set("A", [(1, 1), (1, 1)]), "lists the DOF 1-1 twice"),
        (
            TITLE + "\n" + _set("G", [(1, 1), (1, 2)]) + "\n" + _set("A", [(1, 2), (1, 1)]),
            "not in the order of its g-set",
        ),
        (TITLE + "\n" + _set("A", [(1, 7)]), "component 0 .*or 1..6"),
    ],
)
def test_bad_printouts_are_refused_with_what_is_wrong(text: str, match: str) -> None:
    with pytest.raises(FileRefused, match=match):
        parse_usetprt(text, source="run.f06")


def test_table_of_several_printouts() -> None:
    twice = PRINTOUT + "\n" + PRINTOUT.replace("  101-0", "  102-0")
    assert parse_usetprt(twice, table=2).names("a")[-1] == "n102"
    with pytest.raises(FileRefused, match="prints 2 USET table"):
        parse_usetprt(twice, table=3)


@pytest.mark.parametrize(
    ("table", "match"),
    [
        (np.zeros((3, 2)), "columns node, component, set mask .*3x2"),
        (np.array([[1, 1, 0.5]]), "whole numbers"),
        (np.array([[1, 1, 2.0**33]]), "32-bit USET word"),
        (np.array([[1, 1, 1], [1, 1, 1]]), "lists the DOF 1-1 twice"),
        (np.array([[-1, 1, 1]]), "node id >= 0"),
    ],
)
def test_bad_bit_tables_are_refused(table: np.ndarray, match: str) -> None:
    with pytest.raises(FileRefused, match=match):
        uset_from_table(table)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.integers(0, 2**32 - 1), min_size=1, max_size=30),
    st.sampled_from(["g", "n", "f", "a", "p"]),
    st.sampled_from(["a", "o", "q+r", "b", "m"]),
)
def test_partition_is_pyyetis_mksetpv(words: list[int], major: str, minor: str) -> None:
    pytest.importorskip("pyyeti")
    import pandas as pd

    from resonant.model.op4_files import numpy_print_options_kept

    with numpy_print_options_kept():
        from pyyeti.nastran import n2p
    frame = pd.DataFrame({"nasset": np.array(words, dtype=np.int64)})
    table = uset_from_table(np.column_stack([np.arange(len(words)), np.ones(len(words)), words]))
    try:
        expected = n2p.mksetpv(frame, major, minor)
    except ValueError:
        with pytest.raises(FileRefused, match="is not inside"):
            table.partition(major, minor)
        return
    assert table.partition(major, minor).tolist() == expected.tolist()


# -- in a model ------------------------------------------------------------------------


def _model(folder: Path, dofs: str, mass: str = "MAA", stiffness: str = "KAA") -> tuple:
    text = f'title = "u"\n[matrices]\nM = "m.op4:{mass}"\nK = "m.op4:{stiffness}"\ndofs = {dofs}\n'
    return loads(text, source="u.toml", base_dir=folder).coordinates


@pytest.fixture()
def folder(tmp_path: Path) -> Path:
    pytest.importorskip("pyyeti")
    from resonant.model.op4_files import write_op4

    k = np.diag(np.arange(1.0, 15.0))
    write_op4(
        tmp_path / "m.op4",
        {
            "kaa": k[:5, :5],
            "maa": np.eye(5),
            "kgg": k,
            "mgg": np.eye(14),
            "kxx": k[:5, :5],
            "mxx": np.eye(5),
            "uset": _table(),
        },
    )
    (tmp_path / "run.f06").write_text(PRINTOUT, encoding="latin-1")
    return tmp_path


def test_model_names_its_coordinates_from_a_uset_table(folder: Path) -> None:
    a = ("n1_ux", "n1_uy", "n1_uz", "n100", "n101")
    assert _model(folder, '"m.op4:USET"') == a
    assert _model(folder, '{ uset = "m.op4:USET", set = "a" }', "MXX", "KXX") == a
    assert _model(folder, '{ uset = "run.f06" }') == a
    assert _model(folder, '{ uset = "run.f06", table = 1 }', "MGG", "KGG")[-2:] == ("n100", "n101")
    model = loads(
        'title = "u"\n[matrices]\nM = "m.op4:MAA"\nK = "m.op4:KAA"\n'
        'dofs = "m.op4:USET"\n[[harmonic]]\nomega = 1\nF_C = { n100 = 1 }\n',
        source="u.toml",
        base_dir=folder,
    )
    assert model.coordinates[3] == "n100"


@pytest.mark.parametrize(
    ("dofs", "match"),
    [
        ('{ uset = "run.f06", set = "g" }', "g-set but the matrices have 5 rows"),
        ('{ uset = "run.f06", set = "m" }', "does not tell the m-set"),
        ('{ uset = "run.f06", sets = "a" }', "unknown key.* sets"),
        ('{ uset = "run.f06", table = 0 }', "table = 1"),
        ('{ uset = "m.mtx" }', "printout .*or an OP4 matrix of bit masks"),
        ('{ uset = "m.op4:NONE" }', "no matrix named NONE"),
        ('{ uset = "../run.f06" }', "outside the model's folder"),
    ],
)
def test_model_with_a_bad_uset_is_refused(folder: Path, dofs: str, match: str) -> None:
    with pytest.raises(ModelError, match=match) as caught:
        _model(folder, dofs)
    assert "[matrices] dofs" in str(caught.value)


def test_import_finds_the_uset_table(folder: Path) -> None:
    from resonant.model.op4_files import write_op4

    write_op4(folder / "n.op4", {"kaa": np.eye(5), "maa": np.eye(5), "uset": _table()})
    imported = fe_model([folder / "n.op4"], folder / "n.toml")
    assert imported.matrices["dofs"] == "n.op4:USET"
    model = loads(imported.text, source="n.toml", base_dir=folder)
    assert model.coordinates == ("n1_ux", "n1_uy", "n1_uz", "n100", "n101")
