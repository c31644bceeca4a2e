"""``resonant import``: a model written beside FE files (resonant.cli.fe_import,
resonant.model.fe_import, docs/interop.md).

References: the written model's natural frequencies equal those of the matrices it names
(scipy.linalg.eigh on the same K and M, 1e-10 relative); pyYeti's test files
(tests/data, BSD-3-Clause). Bad input: exit 2 naming the file, no model written.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from resonant.cli import main
from resonant.model.fe_import import guess_matrix

DATA = Path(__file__).resolve().parent / "data"


def _chain(n: int) -> tuple[np.ndarray, np.ndarray]:
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    M = np.diag(np.linspace(1.0, 2.0, n))
    return K, M


def test_op4_with_dof_map_gives_named_coordinates_and_the_same_modes(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("pyyeti")
    from scipy.linalg import eigh

    import resonant
    from resonant.model.op4_files import write_op4

    K, M = _chain(6)
    dofs = np.array([[100 + i // 2, 3 if i % 2 == 0 else 5] for i in range(6)], dtype=float)
    write_op4(tmp_path / "beam.op4", {"kaa": K, "maa": M, "baa": 1e-3 * K, "dofs": dofs})
    assert main(["import", str(tmp_path / "beam.op4"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["matrices"] == {"K": "beam.op4:KAA", "M": "beam.op4:MAA",
                                  "C": "beam.op4:BAA", "dofs": "beam.op4:DOFS"}
    assert report["coordinates"][:3] == ["n100_uz", "n100_ry", "n101_uz"]
    model = resonant.load(tmp_path / "beam.toml")
    expected = np.sqrt(eigh(K, M, eigvals_only=True)) / (2 * np.pi)
    # C = 1e-3 K: the damped modes' undamped frequencies are K and M's
    frequencies = np.sort(model.linearize().modes().frequencies_hz)
    assert np.allclose(frequencies, expected, rtol=1e-10)


def test_a_dof_map_of_other_matrices_is_exit_2_not_dropped(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A DOFS matrix with fewer rows than K: refused, naming file, matrix and sizes (it
    was passed over in silence: the model got q1 ... q6 and exit 0)."""
    pytest.importorskip("pyyeti")
    from resonant.model.op4_files import write_op4

    K, M = _chain(6)
    dofs = np.array([[100 + i, 3] for i in range(5)], dtype=float)
    write_op4(tmp_path / "beam.op4", {"kaa": K, "maa": M, "dofs": dofs})
    assert main(["import", str(tmp_path / "beam.op4")]) == 2
    err = capsys.readouterr().err
    assert "beam.op4" in err and "matrix DOFS" in err and "5 DOFs" in err and "6 rows" in err
    assert "Traceback" not in err and not (tmp_path / "beam.toml").exists()


def test_inboard_op4_matrices_found_by_nastran_names(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copy(DATA / "op4" / "inboard.op4", tmp_path / "inboard.op4")
    out = tmp_path / "models" / "cb.toml"
    out.parent.mkdir()
    assert main(["import", str(tmp_path / "inboard.op4"), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "K = ../inboard.op4:KXX" in printed and "rigid-body modes: 6" in printed
    assert f"--allow-path {tmp_path}" in printed  # the file lies outside the model's folder
    text = out.read_text(encoding="utf-8")
    assert 'M = "../inboard.op4:MXX"' in text


def test_dmig_matrices_named_by_the_user(tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("pyyeti")
    shutil.copy(DATA / "dmig" / "matrix_factory.pch", tmp_path / "f.pch")
    assert main(["import", str(tmp_path / "f.pch")]) == 2
    assert "f.pch: it holds no matrix that is clearly the stiffness" in \
        capsys.readouterr().err
    assert not (tmp_path / "f.toml").exists()
    assert main(["import", str(tmp_path / "f.pch"), "--mass", "IDENT", "--stiffness",
                 "IDENT"]) == 0
    assert "21 coordinate(s): n1_ux" in capsys.readouterr().out


def test_abaqus_files_by_their_names(tmp_path: Path,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    K, M = _chain(4)
    dofs = [(7, 1), (7, 2), (8, 1), (8, 2)]
    for name, matrix in (("job_STIF2.mtx", K), ("job_MASS2.mtx", M)):
        lines = [f"{dofs[i][0]},{dofs[i][1]}, {dofs[j][0]},{dofs[j][1]}, {float(matrix[i, j])!r}"
                 for i in range(4) for j in range(i + 1) if matrix[i, j]]
        (tmp_path / name).write_text("\n".join(lines) + "\n", encoding="utf-8")
    out = tmp_path / "job.toml"
    assert main(["import", str(tmp_path / "job_STIF2.mtx"), str(tmp_path / "job_MASS2.mtx"),
                 "-o", str(out)]) == 0
    assert "4 coordinate(s): n7_ux, n7_uy, n8_ux, n8_uy" in capsys.readouterr().out
    (tmp_path / "other.mtx").write_bytes((tmp_path / "job_MASS2.mtx").read_bytes())
    assert main(["import", str(tmp_path / "job_STIF2.mtx"), str(tmp_path / "other.mtx"),
                 "-o", str(tmp_path / "x.toml")]) == 2
    assert "other.mtx: is it the mass, the stiffness" in capsys.readouterr().err


def test_ansys_full_file_model_text(tmp_path: Path) -> None:
    """A .full file's model: K and M of the file, its DOF reference (the model is read
    by ansys-mapdl-reader when loaded: tests/test_fe_import.py)."""
    from resonant.model.fe_import import fe_model

    (tmp_path / "plate.full").write_bytes(b"\0" * 64)
    imported = fe_model([tmp_path / "plate.full"], tmp_path / "plate.toml",
                        drop_unconnected=True)
    assert imported.matrices == {"M": "plate.full:M", "K": "plate.full:K",
                                 "dofs": "plate.full"}
    assert imported.text.endswith("drop_unconnected = true\n")


@pytest.mark.parametrize("content, suffix, message", [
    (b"junk\n", ".op4", "not an OUTPUT4 file"),
    (None, ".op4", "truncated"),
    (b"a b\n", ".txt", "not an FE file resonant imports"),
    (b"%%MatrixMarket matrix array real general\n1 1\n1.0\n", ".mtx", "Matrix Market"),
])
def test_bad_files_are_exit_2_naming_the_file(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str],
                                             content: bytes | None, suffix: str,
                                             message: str) -> None:
    data = (DATA / "op4" / "inboard.op4").read_bytes()
    path = tmp_path / f"bad{suffix}"
    path.write_bytes(data[:len(data) // 3] if content is None else content)
    assert main(["import", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"bad{suffix}" in err and message in err and "Traceback" not in err
    assert not (tmp_path / "bad.toml").exists()


def test_existing_model_is_kept_without_force(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    shutil.copy(DATA / "op4" / "inboard.op4", tmp_path / "inboard.op4")
    (tmp_path / "inboard.toml").write_text("kept", encoding="utf-8")
    assert main(["import", str(tmp_path / "inboard.op4")]) == 2
    assert "exists" in capsys.readouterr().err
    assert (tmp_path / "inboard.toml").read_text(encoding="utf-8") == "kept"
    assert main(["import", str(tmp_path / "inboard.op4"), "--force"]) == 0


def test_guess_refuses_two_candidates() -> None:
    from resonant.model.files import FileRefused

    directory = [("kaa", (3, 3), 2), ("mfoo", (3, 3), 2), ("mbar", (3, 3), 2)]
    with pytest.raises(FileRefused, match="MFOO, MBAR"):
        guess_matrix("M", directory, 3)
    assert guess_matrix("C", directory, 3) is None
