"""Models from finite-element files: Nastran OUTPUT4 through pyYeti, the DOF map, the
checks on the way in (resonant.model.op4_files, resonant.analyses.fe_checks,
docs/interop.md).

References (tests/data/README.md for the files' source and licence):

* pyYeti's OP4 suite: RMAT in every layout Nastran writes (dense, bigmat, non-bigmat;
  single, double; little-, big-endian, ASCII) against its MATLAB ground truth
  ``r_c_rc.mat``: double precision bit for bit, single precision to float32 rounding;
* ``inboard.op4`` (NX Nastran EXTSEOUT, a Craig-Bampton model): the fixed-interface
  eigenvalue table of ``inboard.out`` (6.129345, 6.130134, 23.63188 Hz, printed to 7
  digits); its grid point weight check (mass 1.755052, the 6 x 6 rigid-body mass about
  the origin, centre of gravity (1039.998, 150, 150), inertia about it; printed to 7
  digits) from resonant's rigid-body check; six rigid-body modes of the free model;
* a scikit-fem beam written to OP4 in each layout and read back bit for bit.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pyyeti")

import resonant  # noqa: E402
from resonant.analyses.fe_checks import check_matrices  # noqa: E402
from resonant.errors import ModelError  # noqa: E402
from resonant.model.op4_files import read_op4_matrix, write_op4  # noqa: E402

DATA = Path(__file__).resolve().parent / "data" / "op4"
LAYOUTS = [f"{p}_{s}_{o}.op4" for p in ("double", "single")
           for s in ("dense", "bigmat", "nonbigmat") for o in ("le", "be", "ascii")]
#: the inboard model's DOFs: the b-set (grids 3, 11, 19, 27; all six components), then
#: the q-set (scalar points 2995001-2995008), as EXTSEOUT orders them
INBOARD_DOFS = [[g, c] for g in (3, 11, 19, 27) for c in range(1, 7)] + \
    [[p, 0] for p in range(2995001, 2995009)]
INBOARD_NODES = {3: (600.0, 0.0, 300.0), 11: (600.0, 300.0, 300.0),
                 19: (600.0, 300.0, 0.0), 27: (600.0, 0.0, 0.0)}
#: grid 11's output system CORD2R 10 (inboard.blk): local x, y, z = basic y, z, x
INBOARD_FRAMES = {11: [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_pyyeti_op4_suite_against_its_ground_truth(layout: str) -> None:
    from scipy.io import loadmat

    truth = loadmat(DATA / "r_c_rc.mat")["rmat"]
    single = layout.startswith("single")
    matrix = read_op4_matrix(str(DATA / layout), "RMATS" if single else "RMAT", "M",
                             square=False)
    matrix = matrix.toarray() if hasattr(matrix, "toarray") else matrix
    expected = truth.astype(np.float32).astype(float) if single else truth
    if layout.endswith("_ascii.op4"):  # Nastran prints 10 (double) or 7 (single) digits
        assert np.allclose(matrix, expected, rtol=1e-6 if single else 1e-9, atol=0)
    else:
        assert np.array_equal(matrix, expected)


def _inboard(folder: Path, dofs: list[list[int]] = INBOARD_DOFS, extra: str = "") -> Path:
    shutil.copy(DATA / "inboard.op4", folder / "inboard.op4")
    path = folder / "inboard.toml"
    path.write_text('title = "inboard"\n[matrices]\nM = "inboard.op4:MXX"\n'
                    f'K = "inboard.op4:KXX"\ndofs = {dofs}\n{extra}', encoding="utf-8")
    return path


def test_inboard_names_and_nastran_weight_check(tmp_path: Path) -> None:
    model = resonant.load(_inboard(tmp_path))
    assert model.coordinates[:3] == ("n3_ux", "n3_uy", "n3_uz")
    assert model.coordinates[23:25] == ("n27_rz", "n2995001")
    checks = check_matrices(model.linearize(), nodes=INBOARD_NODES, frames=INBOARD_FRAMES)
    assert checks.ok, checks.problems
    assert checks.rigid_body_modes == 6
    assert all(v < 1e-14 for v in checks.rigid_body_forces.values())
    # NX Nastran, inboard.out page 19: O U T P U T   F R O M   W E I G H T   C H E C K
    nastran = np.array([
        [1.755052e+00, 0, 0, 0, 2.632578e+02, -2.632578e+02],
        [0, 1.755052e+00, 0, -2.632578e+02, 0, 1.825251e+03],
        [0, 0, 1.755052e+00, 2.632578e+02, -1.825251e+03, 0],
        [0, -2.632578e+02, 2.632578e+02, 1.148825e+05, -2.737877e+05, -2.737877e+05],
        [2.632578e+02, 0, -1.825251e+03, -2.737877e+05, 2.305948e+06, -3.937911e+04],
        [-2.632578e+02, 1.825251e+03, 0, -2.737877e+05, -3.937911e+04, 2.305948e+06]])
    assert checks.rigid_body_mass is not None
    assert np.allclose(checks.rigid_body_mass, nastran, rtol=5e-7, atol=1e-8)
    for value in checks.mass_by_direction.values():
        assert value == pytest.approx(1.755052, rel=5e-7)
    assert checks.centre_of_gravity == pytest.approx((1.039998e3, 150.0, 150.0), rel=5e-7)
    # page 17, I(S) about the centre of gravity; Nastran prints the products of inertia
    # with the sign opposite to the tensor's (I_yz = -sum m y z)
    assert checks.inertia is not None
    assert np.diag(checks.inertia) == pytest.approx([3.590520e4, 3.682012e5, 3.682012e5],
                                                     rel=5e-7)
    assert checks.inertia[1, 2] == pytest.approx(1.095583e2, rel=5e-7)
    assert "rigid-body modes: 6" in checks.summary()


def test_inboard_fixed_interface_frequencies(tmp_path: Path) -> None:
    """The b-set clamped: the q-set blocks give Nastran's eigenvalue table."""
    K = read_op4_matrix(str(DATA / "inboard.op4"), "KXX", "K")[24:, 24:]
    M = read_op4_matrix(str(DATA / "inboard.op4"), "MXX", "M")[24:, 24:]
    write_op4(tmp_path / "fixed.op4", {"kqq": K, "mqq": M})
    (tmp_path / "fixed.toml").write_text(
        '[matrices]\nM = "fixed.op4:MQQ"\nK = "fixed.op4:KQQ"\n'
        f"dofs = {[[p, 0] for p in range(2995001, 2995009)]}\n", encoding="utf-8")
    modes = resonant.load(tmp_path / "fixed.toml").linearize().modes()
    hz = modes.natural_frequencies[:3] / (2 * np.pi)
    assert hz == pytest.approx([6.129345, 6.130134, 23.63188], rel=5e-7)


@pytest.mark.parametrize("binary", [True, False])
@pytest.mark.parametrize("sparse", [None, "dense", "bigmat", "nonbigmat"])
def test_scikit_fem_beam_round_trip(tmp_path: Path, binary: bool, sparse: str | None) -> None:
    """A scikit-fem model written to OP4 and read back: bit for bit in binary, to the 16
    significant digits pyYeti prints in ASCII."""
    pytest.importorskip("skfem")
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import corpus

    structure = corpus.build("eb_beam", 40)
    K, M = structure.K.tocsr(), structure.M.tocsr()
    write_op4(tmp_path / "beam.op4", {"kaa": K if sparse != "dense" else K.toarray(),
                                      "maa": M if sparse != "dense" else M.toarray()},
              binary=binary, sparse="auto" if sparse is None else sparse)
    for name, original in (("KAA", K), ("MAA", M)):
        back = read_op4_matrix(str(tmp_path / "beam.op4"), name, name[0])
        back = back.toarray() if hasattr(back, "toarray") else back
        if binary:
            assert np.array_equal(back, original.toarray())
        else:
            assert np.allclose(back, original.toarray(), rtol=1e-15, atol=0)


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    code = "import sys\nfrom resonant.cli import main\nsys.exit(main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True,
                          text=True, timeout=120)


def test_truncated_op4_record_is_exit_2_naming_file_and_matrix(tmp_path: Path) -> None:
    path = _inboard(tmp_path)
    data = (tmp_path / "inboard.op4").read_bytes()
    (tmp_path / "inboard.op4").write_bytes(data[:len(data) // 3])
    run = _cli("check", str(path))
    assert run.returncode == 2, run.stderr
    assert "inboard.op4" in run.stderr and "Traceback" not in run.stderr
    assert "truncated" in run.stderr
    assert "[matrices]" in run.stderr


def test_missing_matrix_name_lists_what_the_file_holds(tmp_path: Path) -> None:
    path = _inboard(tmp_path)
    path.write_text(path.read_text().replace("MXX", "MGG"), encoding="utf-8")
    with pytest.raises(ModelError, match=r"no matrix named MGG \(it holds KXX, MXX"):
        resonant.load(path)


def test_dof_map_that_does_not_match(tmp_path: Path) -> None:
    with pytest.raises(ModelError, match="lists 31 DOFs but the matrices have 32 rows"):
        resonant.load(_inboard(tmp_path, INBOARD_DOFS[:-1]))
    with pytest.raises(ModelError, match="n3_ux twice"):
        resonant.load(_inboard(tmp_path, [[3, 1], *INBOARD_DOFS[1:-1], [3, 1]]))
    with pytest.raises(ModelError, match="component"):
        resonant.load(_inboard(tmp_path, [[3, 7], *INBOARD_DOFS[1:]]))


def test_complex_and_unsquare_matrices_are_refused(tmp_path: Path) -> None:
    shutil.copy(DATA / "double_dense_le.op4", tmp_path / "m.op4")
    (tmp_path / "model.toml").write_text('[matrices]\nM = "m.op4:CMAT"\nK = "m.op4:RMAT"\n',
                                         encoding="utf-8")
    with pytest.raises(ModelError) as info:
        resonant.load(tmp_path / "model.toml")
    text = str(info.value)
    assert "CMAT holds complex numbers" in text and "RMAT is 25x31, not a square" in text


def test_op4_outside_the_folder_is_refused(tmp_path: Path) -> None:
    (tmp_path / "sub").mkdir()
    shutil.copy(DATA / "inboard.op4", tmp_path / "inboard.op4")
    (tmp_path / "sub" / "model.toml").write_text(
        '[matrices]\nM = "../inboard.op4:MXX"\nK = "../inboard.op4:KXX"\n', encoding="utf-8")
    with pytest.raises(ModelError, match="outside the model's folder"):
        resonant.load(tmp_path / "sub" / "model.toml")
    model = resonant.load(tmp_path / "sub" / "model.toml", allow_paths=[tmp_path])
    assert model.coordinates[0] == "q1"


def test_loads_by_node_name_and_a_sweep(tmp_path: Path) -> None:
    """F_C given at a named DOF: the clamped q-set responds; the free model's names
    reach the load table."""
    path = _inboard(tmp_path, extra='C = "1e-4*K"\n[[harmonic]]\nomega = 40\n'
                                    'F_C = { n2995001 = 1.0 }\n')
    model = resonant.load(path)
    assert model.matrices is not None
    assert model.matrices.harmonics[0].F_C[24].text == "1.0"


def test_a_missing_mass_matrix_says_which_analysis_writes_one() -> None:
    from resonant.system.base import NumericEOM

    system = NumericEOM(("n1_ux", "n2_ux"), np.zeros((2, 2)), np.zeros((2, 2)), np.eye(2))
    checks = check_matrices(system)
    assert not checks.ok
    assert "SOL 103" in checks.problems[0] and "ANTYPE,MODAL" in checks.problems[0]


def _ansys(folder: Path, extra: str = "drop_unconnected = true\n") -> Path:
    from ansys.mapdl.reader import examples

    shutil.copy(examples.fullfile, folder / "file.full")
    path = folder / "model.toml"
    path.write_text('[matrices]\nM = "file.full"\nK = "file.full"\ndofs = "file.full"\n'
                    + extra, encoding="utf-8")
    return path


def test_ansys_full_example_against_its_frequencies(tmp_path: Path) -> None:
    """ansys-mapdl-reader's example file.full: its documented first frequencies
    (examples.load_km: 1283.20036921, 1283.20036921, 5781.97486169, 6919.39887714 Hz),
    the 63 unconnected DOFs (no mass, no stiffness) found and dropped."""
    pytest.importorskip("ansys.mapdl.reader")
    raw = resonant.load(_ansys(tmp_path, ""))
    assert len(raw.coordinates) == 963 and raw.coordinates[:2] == ("n1_ux", "n1_uy")
    checks = check_matrices(raw.linearize())
    assert "63 coordinates have neither mass nor stiffness" in checks.problems[0]
    model = resonant.load(_ansys(tmp_path))
    assert len(model.coordinates) == 900
    assert check_matrices(model.linearize()).ok
    hz = model.linearize().modes(count=4).natural_frequencies / (2 * np.pi)
    assert hz == pytest.approx([1283.20036921, 1283.20036921, 5781.97486169, 6919.39887714],
                               rel=1e-9)


def test_a_truncated_full_file_is_exit_2_not_a_crash(tmp_path: Path) -> None:
    """ansys-mapdl-reader's example file.full cut short (inside its matrices, and 4 bytes
    before the end of its data, ptrEND): exit 2 naming the file and the record past
    the end, in a fresh process (the reader's compiled code aborted it with
    ``std::bad_alloc``, exit 134, on the 5,000-byte cut)."""
    pytest.importorskip("ansys.mapdl.reader")
    from ansys.mapdl.reader import examples

    data = Path(examples.fullfile).read_bytes()
    for cut in (5000, 400_000, 801_592):
        (tmp_path / "cut.full").write_bytes(data[:cut])
        run = _cli("import", str(tmp_path / "cut.full"), "-o", str(tmp_path / "cut.toml"),
                   "--force")
        assert run.returncode == 2, (cut, run.returncode, run.stderr[-300:])
        assert "cut.full" in run.stderr and "truncated" in run.stderr
        assert f"the file has {cut} bytes" in run.stderr and "Traceback" not in run.stderr


def test_ansys_full_without_mass_is_exit_2(tmp_path: Path, monkeypatch) -> None:
    """A static run's .full holds K only: the message names the file, M, and the analysis
    that writes a mass matrix (the reader's empty mass matrix stands in for such a file)."""
    pytest.importorskip("ansys.mapdl.reader")
    import scipy.sparse as sp

    from resonant.model import full_files

    real = full_files._load

    def without_mass(path: str):
        dof_ref, k, m = real(path)
        return dof_ref, k, sp.csc_matrix(m.shape)

    monkeypatch.setattr(full_files, "_load", without_mass)
    with pytest.raises(ModelError) as info:
        resonant.load(_ansys(tmp_path))
    text = str(info.value)
    assert "file.full" in text and "[matrices] M" in text
    assert "no mass matrix" in text and "ANTYPE,MODAL" in text


def _write_abaqus(path: Path, matrix, dofs: list[tuple[int, int]], triangle: str) -> None:
    """Abaqus's MATRIX INPUT text (row node, row DOF, column node, column DOF, value)."""
    import scipy.sparse as sp

    coo = sp.coo_matrix(matrix)
    keep = {"lower": coo.row >= coo.col, "upper": coo.row <= coo.col,
            "full": np.ones(coo.nnz, dtype=bool)}[triangle]
    lines = ["** written like Abaqus *MATRIX OUTPUT, FORMAT=MATRIX INPUT"]
    for i, j, v in zip(coo.row[keep], coo.col[keep], coo.data[keep]):
        lines.append(f"{dofs[i][0]},{dofs[i][1]}, {dofs[j][0]},{dofs[j][1]}, {float(v)!r}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


@pytest.mark.parametrize("triangle", ["lower", "upper", "full"])
def test_abaqus_matrix_output_round_trip(tmp_path: Path, triangle: str) -> None:
    """A scikit-fem beam written as Abaqus matrix output (repr: 17 digits) and read back
    bit for bit, the coordinates named by node and DOF."""
    pytest.importorskip("skfem")
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import corpus

    structure = corpus.build("eb_beam", 40)
    # Abaqus writes symmetric matrices; the assembled beam is symmetric to rounding
    K, M = ((a + a.T).tocsr() / 2 for a in (structure.K, structure.M))
    # a beam node carries a deflection (uz, 3) and a rotation (ry, 5)
    dofs = [(10 + i // 2, 3 if i % 2 == 0 else 5) for i in range(K.shape[0])]
    _write_abaqus(tmp_path / "job_STIF2.mtx", K, dofs, triangle)
    _write_abaqus(tmp_path / "job_MASS2.mtx", M, dofs, triangle)
    (tmp_path / "beam.toml").write_text('[matrices]\nK = "job_STIF2.mtx"\n'
                                        'M = "job_MASS2.mtx"\n', encoding="utf-8")
    model = resonant.load(tmp_path / "beam.toml")
    assert model.coordinates[:3] == ("n10_uz", "n10_ry", "n11_uz")
    num = model.linearize().numeric()
    assert np.array_equal(num.K.toarray(), K.toarray())
    assert np.array_equal(num.M.toarray(), M.toarray())


def test_abaqus_bad_input_names_the_problem(tmp_path: Path) -> None:
    (tmp_path / "k.mtx").write_text("1,1, 1,1, 2.0\n1,1, 1\n", encoding="utf-8")
    (tmp_path / "m.mtx").write_text("1,1, 1,1, 1.0\n1,1, 1,1, 1.0\n", encoding="utf-8")
    (tmp_path / "model.toml").write_text('[matrices]\nK = "k.mtx"\nM = "m.mtx"\n',
                                         encoding="utf-8")
    with pytest.raises(ModelError) as info:
        resonant.load(tmp_path / "model.toml")
    text = str(info.value)
    assert "[matrices] K: cannot read 'k.mtx'" in text and "5 numbers" in text
    (tmp_path / "k.mtx").write_text("1,1, 1,1, 2.0\n", encoding="utf-8")
    with pytest.raises(ModelError, match="an entry of M is listed twice"):
        resonant.load(tmp_path / "model.toml")
    (tmp_path / "m.mtx").write_text("1,1, 1,1, 1.0\n1,1, 2,1, 0.5\n2,1, 1,1, 0.25\n"
                                    "2,1, 2,1, 1.0\n", encoding="utf-8")
    with pytest.raises(ModelError, match="M is listed in full but is not symmetric"):
        resonant.load(tmp_path / "model.toml")


WORKED = """title = "Clamped beam from a Nastran OUTPUT4 file"
[matrices]
M = "beam.op4:MAA"
K = "beam.op4:KAA"
C = "1e-5*K"
dofs = "beam.op4:DOFS"

[random]
band = [1, 2000]
[random.psd.n110_uz]      # a random force on node 110 in z
unit = "N^2/Hz"
values = 1.0
"""


def test_worked_example_op4_to_random_response_at_a_node(tmp_path: Path) -> None:
    """docs/interop.md's worked example: the RMS at n110_uz and n120_uz against the
    exported state space's Lyapunov equation (another route than the random analysis's
    quadrature over the kernel's responses), to 1e-3."""
    pytest.importorskip("skfem")
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import corpus

    structure = corpus.build("eb_beam", 40)
    K, M = ((a + a.T).tocsr() / 2 for a in (structure.K, structure.M))
    dofs = np.array([[101 + i // 2, 3 if i % 2 == 0 else 5] for i in range(K.shape[0])])
    write_op4(tmp_path / "beam.op4", {"kaa": K, "maa": M, "dofs": dofs.astype(float)})
    (tmp_path / "beam.toml").write_text(WORKED, encoding="utf-8")
    model = resonant.load(tmp_path / "beam.toml")
    system = model.linearize()
    result = system.random_response(names=["n110_uz", "n120_uz"])
    exported = system.state_space(inputs=["n110_uz"], outputs=["n110_uz", "n120_uz"])
    # white noise of one-sided density 1 N^2/Hz is intensity 1/2: the variance over
    # 0..inf is C P C^T with A P + P A^T + B B^T / 2 = 0; the parts below 1 Hz and above
    # 2000 Hz (smooth) are taken off by quadrature
    from scipy.linalg import solve_continuous_lyapunov

    P = solve_continuous_lyapunov(exported.A, -0.5 * exported.B @ exported.B.T)
    total = np.diag(exported.C @ P @ exported.C.T)

    def outside(f: np.ndarray) -> np.ndarray:
        power = np.abs(exported.frequency_response(2 * np.pi * f)[:, :, 0]) ** 2
        return np.sum((power[1:] + power[:-1]) / 2 * np.diff(f)[:, None], axis=0)

    band = total - outside(np.linspace(0.0, 1.0, 201)) - outside(np.geomspace(2e3, 2e6, 2001))
    for k, name in enumerate(("n110_uz", "n120_uz")):
        assert result.rms[name] == pytest.approx(np.sqrt(band[k]), rel=1e-3), name
    assert result.rms["n110_uz"] == pytest.approx(0.1356, rel=1e-3)  # the page's table


def test_check_command_prints_the_matrix_report(tmp_path: Path) -> None:
    run = _cli("check", "--matrices", str(_inboard(tmp_path)))
    assert run.returncode == 0, run.stderr
    # no output frames on the command line: grid 11's DOFs (in CORD2R 10) spoil the
    # basic translations, and the report says so
    assert "rigid-body modes: 6" in run.stdout and "give their output frames" in run.stdout
    (tmp_path / "zero.toml").write_text("[matrices]\nM = [[0, 0], [0, 0]]\n"
                                        "K = [[2, -1], [-1, 2]]\n", encoding="utf-8")
    run = _cli("check", "--matrices", str(tmp_path / "zero.toml"))
    assert run.returncode == 2 and "the mass matrix M is zero" in run.stdout


DMIG = Path(__file__).resolve().parent / "data" / "dmig" / "matrix_factory.pch"


def test_dmig_from_a_punch_file(tmp_path: Path) -> None:
    """pyYeti's punch file of DMIG entries (21 DOFs: grids 1-3 with six components,
    scalar points 10-12): IDENT as M and K gives 21 modes at 1 rad/s, the coordinates
    named from the DMIG labels; the unsymmetric PATRN as K is refused by name."""
    shutil.copy(DMIG, tmp_path / "matrix_factory.pch")
    path = tmp_path / "model.toml"
    path.write_text('[matrices]\nM = "matrix_factory.pch:IDENT"\n'
                    'K = "matrix_factory.pch:IDENT"\n', encoding="utf-8")
    model = resonant.load(path)
    assert model.coordinates[:2] == ("n1_ux", "n1_uy")
    assert model.coordinates[-3:] == ("n10", "n11", "n12")
    assert np.allclose(model.linearize().modes().natural_frequencies, 1.0, rtol=1e-14)
    path.write_text('[matrices]\nM = "matrix_factory.pch:IDENT"\n'
                    'K = "matrix_factory.pch:PATRN"\n', encoding="utf-8")
    with pytest.raises(ModelError, match="K is listed in full but is not symmetric"):
        resonant.load(path)
    path.write_text('[matrices]\nM = "matrix_factory.pch:IDENT"\n'
                    'K = "matrix_factory.pch:KAAX"\n', encoding="utf-8")
    with pytest.raises(ModelError, match="no DMIG named KAAX"):
        resonant.load(path)
