"""The damping matrix of an ANSYS ``.full`` file (resonant.model.full_files, ``C =
"file.full"``), read where the file holds one.

ansys-mapdl-reader's example ``file.full`` (a modal run) has no damping matrix. The file
with one is made from it: its header's damping pointer and term count (``ptrDMP``,
``ntermD``; fdfull.inc) are set to those of its mass (or stiffness) matrix, which ANSYS
stores in the same layout. The damping matrix read must then equal M (or K) bit for bit,
and a model with ``C = "file.full"`` has C = M: every mode's damping ratio is
1 / (2 omega) (viscous damping C = 1 * M), to 1e-9.

Skipped without ansys-mapdl-reader (the optional extra ``resonant[ansys]``).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

reader = pytest.importorskip("ansys.mapdl.reader")

import resonant  # noqa: E402
from resonant.errors import ModelError  # noqa: E402
from resonant.model.fe_import import fe_model  # noqa: E402
from resonant.model.full_files import has_damping, read_full_matrix  # noqa: E402


def _with_damping(folder: Path, like: str) -> Path:
    """The example file with its damping pointer and term count set to those of M or K."""
    from ansys.mapdl.reader import examples, full

    words = np.fromfile(examples.fullfile, "<i4")
    header = 2 + int(words[0]) + 1 + 2  # past the standard header record and its trailer
    assert words[header + 1] == 963  # neqn: the full header's second word
    keys = full.SYMBOLIC_FULL_HEADER_KEYS
    source = {"M": ("ptrMAS", "ntermM"), "K": ("ptrSTF", "ntermK")}[like]
    for part in ("l", "h"):
        words[header + keys.index(f"ptrDMP{part}")] = words[
            header + keys.index(f"{source[0]}{part}")
        ]
        words[header + keys.index(f"ntermD{part}")] = words[
            header + keys.index(f"{source[1]}{part}")
        ]
    words[header + keys.index("nmatrx")] = 3
    path = folder / f"damped_{like}.full"
    words.tofile(path)
    return path


@pytest.mark.parametrize("like", ["M", "K"])
def test_damping_matrix_is_read_bit_for_bit(tmp_path: Path, like: str) -> None:
    path = str(_with_damping(tmp_path, like))
    damping = read_full_matrix(path, "C", "C")
    same = read_full_matrix(path, like, like)
    assert damping.shape == same.shape == (963, 963)
    assert (damping != same).nnz == 0
    assert has_damping(path)


def test_no_damping_matrix_is_a_clear_refusal(tmp_path: Path) -> None:
    from ansys.mapdl.reader import examples

    shutil.copy(examples.fullfile, tmp_path / "file.full")
    assert not has_damping(str(tmp_path / "file.full"))
    (tmp_path / "model.toml").write_text(
        '[matrices]\nM = "file.full"\nK = "file.full"\nC = "file.full"\n', encoding="utf-8"
    )
    with pytest.raises(ModelError) as info:
        resonant.load(tmp_path / "model.toml")
    text = str(info.value)
    assert "[matrices] C" in text and "file.full" in text
    assert "no damping matrix" in text and "modal_damping" in text


def test_model_takes_the_damping_matrix(tmp_path: Path) -> None:
    path = _with_damping(tmp_path, "M")
    imported = fe_model([path], tmp_path / "damped.toml", drop_unconnected=True)
    assert imported.matrices["C"] == "damped_M.full:C"  # found by the import
    (tmp_path / "damped.toml").write_text(imported.text, encoding="utf-8")
    system = resonant.load(tmp_path / "damped.toml").linearize()
    modes = system.modes(count=4)
    omega = modes.natural_frequencies
    assert omega / (2 * np.pi) == pytest.approx(
        [1283.20036921, 1283.20036921, 5781.97486169, 6919.39887714], rel=1e-9
    )
    assert modes.damping_ratios == pytest.approx(1 / (2 * omega), rel=1e-9)
