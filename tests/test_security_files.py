"""Matrix files and the model file are untrusted input (docs/security.md).

Every attack below was found in a review: out-of-range sparse indices (SIGSEGV, double
free, silent corruption), paths leaving the model's folder, FIFOs and devices, headers
claiming huge sizes, unreadable dtypes, silently ignored keys.  Each must end in exit
status 2 with a message that says what is wrong.  The attacks that crashed or ate memory
run in a subprocess under ``RLIMIT_AS``, so a regression fails instead of killing the
test run or the machine.
"""

from __future__ import annotations

import io
import os
import zipfile
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

from conftest import run_cli
from limited_runner import run_resonant
from resonant.api import load, loads
from resonant.errors import ModelError
from resonant.model import limits

MEMORY = 1 << 30  # the address-space limit of the subprocess runs
HEADER = "[parameters]\nw = 3\n[matrices]\n"
HARMONIC = "[[harmonic]]\nomega = \"w\"\nF_S = [1, 0, 0]\n"
OUTSIDE = "the path leads outside the model's folder"


def model(directory: Path, K: str = '"K.npz"', M: str = "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
          name: str = "model.toml") -> Path:
    path = directory / name
    path.write_text(f"{HEADER}M = {M}\nK = {K}\n{HARMONIC}", encoding="utf-8")
    return path


def run_limited(args: list[str], timeout: float = 60) -> tuple[int, str, str]:
    """``resonant ARGS`` in a child process with at most MEMORY bytes of address space
    (tests/limited_runner.py: one interpreter start for the session, a fork per run)."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    proc = run_resonant(list(map(str, args)), memory=MEMORY, timeout=timeout, env=env)
    return proc.returncode, proc.stdout, proc.stderr


def run_commands_limited(commands: list[list[str]], timeout: float = 60
                         ) -> list[tuple[int, str]]:
    """Each of ``resonant COMMAND`` in a child process with at most MEMORY bytes of address
    space: (exit status, stderr) of each."""
    return [(code, err) for code, _, err in (run_limited(c, timeout) for c in commands)]


def refused(path: Path, *words: str, command: str = "solve", extra: tuple[str, ...] = ()
            ) -> str:
    code, out, err = run_limited([command, path, *extra])
    assert code == 2, f"exit {code}\n{err}\n{out}"
    for word in words:
        assert word in err, err
    assert "Traceback" not in err
    return err


def sparse_npz(path: Path, fmt: str = "csr", shape=(3, 3), data=(1.0, 2.0, 3.0),
               **arrays) -> None:
    """A .npz in scipy.sparse.save_npz's layout, with arbitrary (hostile) contents."""
    np.savez(path, format=fmt.encode(), shape=np.array(shape), data=np.array(data), **arrays)


# -- 1. sparse structure --------------------------------------------------------------------

SPARSE_ATTACKS = [
    ("csr-far-index", "csr", dict(indices=np.array([0, 1000000, 2]), indptr=np.array([0, 1, 2, 3])),
     "'indices' array holds an index outside 0..2"),
    ("csc-far-index", "csc", dict(indices=np.array([0, 1000000, 2]), indptr=np.array([0, 1, 2, 3])),
     "'indices' array holds an index outside 0..2"),
    ("csr-just-past-edge", "csr", dict(indices=np.array([0, 3, 2]), indptr=np.array([0, 1, 2, 3])),
     "'indices' array holds an index outside 0..2"),
    ("csr-negative", "csr", dict(indices=np.array([0, -1, 2]), indptr=np.array([0, 1, 2, 3])),
     "outside 0..2"),
    ("indptr-too-far", "csr", dict(indices=np.array([0, 1, 2]), indptr=np.array([0, 1, 2, 9])),
     "'indptr' array holds an index outside 0..3"),
    ("indptr-decreasing", "csr", dict(indices=np.array([0, 1, 2]), indptr=np.array([0, 2, 1, 3])),
     "without decreasing"),
    ("indptr-not-from-0", "csr", dict(indices=np.array([0, 1, 2]), indptr=np.array([1, 1, 2, 3])),
     "rise from 0 to 3"),
    ("indptr-short", "csr", dict(indices=np.array([0, 1, 2]), indptr=np.array([0, 3])),
     "'indptr' array has 2 entries; expected 4"),
    ("indices-float", "csr", dict(indices=np.array([0.0, 1.0, 2.0]), indptr=np.array([0, 1, 2, 3])),
     "1-D array of integers"),
    ("coo-far-row", "coo", dict(row=np.array([0, 1, 7]), col=np.array([0, 1, 2])),
     "'row' array holds an index outside 0..2"),
    ("coo-length", "coo", dict(row=np.array([0, 1]), col=np.array([0, 1, 2])),
     "'row' array has 2 entries; expected 3"),
    ("bsr", "bsr", dict(indices=np.array([0]), indptr=np.array([0, 1])), "'bsr'"),
    ("unknown-format", "xyz\x1b[2J", {}, "an unknown format"),
]


@pytest.mark.parametrize("fmt, arrays, words", [a[1:] for a in SPARSE_ATTACKS],
                         ids=[a[0] for a in SPARSE_ATTACKS])
def test_sparse_structure_is_validated_before_scipy(tmp_path, fmt, arrays, words):
    sparse_npz(tmp_path / "K.npz", fmt, **arrays)
    path = str(model(tmp_path))
    for code, err in run_commands_limited([["solve", path], ["check", path], ["modes", path]]):
        assert code == 2, err
        for word in ("[matrices] K", "cannot read 'K.npz'", words):
            assert word in err, err
        assert "Traceback" not in err


@pytest.mark.parametrize("shape, data, words", [
    ((3, 4), (1.0, 2.0, 3.0), "3x4, not a square matrix"),
    ((0, 0), (), "at least one row"),
    ((3,), (1.0, 2.0, 3.0), "'shape' array must hold two integers"),
    ((3, 3), (1.0, np.nan, 3.0), "non-finite"),
    ((3, 3), (1 + 1j, 2, 3), "complex numbers"),
    ((300_000, 300_000), (1.0, 2.0, 3.0), "limited to 200000x200000"),
])
def test_sparse_shape_and_data(tmp_path, shape, data, words):
    sparse_npz(tmp_path / "K.npz", "csr", shape=shape, data=data,
               indices=np.array([0, 1, 2][:len(data)]), indptr=np.array([0, 1, 2, 3]))
    with pytest.raises(ModelError, match="K.npz") as info:
        load(model(tmp_path))
    assert words in str(info.value)


def test_valid_sparse_layouts_and_duplicates_are_summed(tmp_path):
    K = np.array([[3.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    for fmt in ("csr", "csc", "coo"):
        sp.save_npz(tmp_path / "K.npz", sp.coo_matrix(K).asformat(fmt))
        np.testing.assert_array_equal(load(model(tmp_path)).matrices.K.toarray(), K)
    # duplicate (row, col) entries add up, as in scipy's own constructors
    sparse_npz(tmp_path / "K.npz", "coo", data=(1.0, 2.0, 3.0), row=np.array([0, 0, 1]),
               col=np.array([0, 0, 1]))
    assert load(model(tmp_path)).matrices.K.toarray()[0, 0] == 3.0


# -- 2. the file policy ---------------------------------------------------------------------

@pytest.fixture
def layout(tmp_path):
    """tmp/outside/{secret.npy} and tmp/model/{model.toml, K.npy}."""
    outside, inside = tmp_path / "outside", tmp_path / "model"
    outside.mkdir()
    inside.mkdir()
    K = np.diag([1.0, 2.0, 3.0])
    np.save(outside / "secret.npy", K)
    np.save(inside / "K.npy", K)
    return outside, inside


def test_paths_outside_the_folder_are_refused_alike(layout):
    outside, inside = layout
    messages = []
    for value in ("../outside/secret.npy", "../outside/missing.npy",
                  str(outside / "secret.npy"), str(outside / "missing.npy"),
                  "sub/../../outside/secret.npy", "/etc/passwd.npy"):
        path = model(inside, K=f'"{value}"')
        with pytest.raises(ModelError) as info:
            load(path)
        message = str(info.value)
        assert OUTSIDE in message and "--allow-path" in message
        messages.append(message.replace(value, "VALUE"))
    # existing and missing files outside get the same message: nothing is revealed
    assert len(set(messages)) == 1, messages


def test_symlinks_are_resolved(layout):
    outside, inside = layout
    (inside / "escape.npy").symlink_to(outside / "secret.npy")
    (inside / "dangling.npy").symlink_to(outside / "missing.npy")
    (inside / "out").symlink_to(outside)
    (inside / "alias.npy").symlink_to(inside / "K.npy")
    texts = []
    for value in ("escape.npy", "dangling.npy", "out/secret.npy"):
        with pytest.raises(ModelError) as info:
            load(model(inside, K=f'"{value}"'))
        assert OUTSIDE in str(info.value)
        texts.append(str(info.value).replace(value, "VALUE"))
    assert len(set(texts)) == 1
    assert load(model(inside, K='"alias.npy"')).matrices.K[2, 2] == 3.0  # inside: fine


def test_allow_path(layout):
    outside, inside = layout
    path = model(inside, K='"../outside/secret.npy"')
    assert load(path, allow_paths=[outside]).matrices.K[1, 1] == 2.0
    absolute = model(inside, K=f'"{outside / "secret.npy"}"', name="abs.toml")
    assert load(absolute, allow_paths=[str(outside)]).matrices.K[1, 1] == 2.0
    code, out, err = run_cli(["check", path, "--allow-path", outside])
    assert code == 0, err
    code, _, err = run_cli(["check", path])
    assert code == 2 and OUTSIDE in err
    code, _, err = run_cli(["check", path, "--allow-path", inside / "elsewhere",
                            "--allow-path", outside])
    assert code == 0, err
    # allowing a directory does not allow its neighbours
    code, _, err = run_cli(["check", model(inside, K='"../outside2/x.npy"', name="n.toml"),
                            "--allow-path", outside])
    assert code == 2 and OUTSIDE in err


def test_loads_without_base_dir_refuses_files(layout):
    outside, inside = layout
    text = f'{HEADER}M = "K.npy"\nK = "K.npy"\n'
    with pytest.raises(ModelError, match="model was given as text.*base_dir"):
        loads(text)
    assert loads(text, base_dir=inside).matrices.M.shape == (3, 3)
    text = f'{HEADER}M = "K.npy"\nK = "../outside/secret.npy"\n'
    with pytest.raises(ModelError, match=OUTSIDE):
        loads(text, base_dir=inside)
    assert loads(text, base_dir=inside, allow_paths=[outside]).matrices.K[0, 0] == 1.0


def test_missing_file_inside_names_no_os_error(layout):
    _, inside = layout
    with pytest.raises(ModelError) as info:
        load(model(inside, K='"nothere.npy"'))
    assert "cannot read 'nothere.npy': no such file" in str(info.value)
    assert "Errno" not in str(info.value) and str(inside) not in str(info.value).split(":", 1)[1]


# -- 3. only regular files -------------------------------------------------------------------

def test_fifo_model_and_matrix_do_not_block(tmp_path):
    fifo = tmp_path / "model.toml"
    os.mkfifo(fifo)
    refused(fifo, "not a regular file but a FIFO")
    os.mkfifo(tmp_path / "K.npy")
    refused(model(tmp_path, K='"K.npy"', name="m.toml"), "cannot read 'K.npy'",
            "not a regular file but a FIFO")


def test_dev_zero_fails_fast(tmp_path):
    (tmp_path / "model.toml").symlink_to("/dev/zero")
    refused(tmp_path / "model.toml", "not a regular file but a character device")
    (tmp_path / "K.npy").symlink_to("/dev/zero")
    path = model(tmp_path, K='"K.npy"', name="m.toml")
    err = refused(path, OUTSIDE)  # /dev is outside the folder
    err = refused(path, "not a regular file but a character device", extra=("--allow-path", "/dev"))
    assert "pickle" not in err
    with pytest.raises(ModelError, match="not a regular file"):
        load("/dev/zero")
    with pytest.raises(ModelError, match="directory"):
        load(tmp_path)


# -- 4. sizes from the headers ---------------------------------------------------------------

def npy_header(shape, descr="<f8") -> bytes:
    handle = io.BytesIO()
    np.lib.format.write_array_header_1_0(handle, {"descr": descr, "fortran_order": False,
                                                  "shape": shape})
    return handle.getvalue()


@pytest.mark.parametrize("shape, words", [
    ((2**40, 2**40), "limited to 200000x200000"),
    ((100_000, 100_000), "dense matrices are limited to 25000000 entries"),
    ((4000, 4000), "claims 128000000 bytes of data but the file holds fewer"),
    ((3, 3, 3), "3 dimensions"),
    ((0, 0), "at least one row"),
    ((2, 3), "not a square matrix"),
])
def test_npy_header_claims(tmp_path, shape, words):
    (tmp_path / "K.npy").write_bytes(npy_header(shape) + bytes(72))
    refused(model(tmp_path, K='"K.npy"'), words)


def test_npz_bomb_is_refused_before_decompressing(tmp_path):
    n = 8300  # 551 MB of zeros in a 2.4 MB file
    with zipfile.ZipFile(tmp_path / "K.npz", "w", zipfile.ZIP_DEFLATED, compresslevel=1) as zf:
        with zf.open("K.npy", "w", force_zip64=True) as member:
            member.write(npy_header((n, n)))
            chunk, left = bytes(1 << 22), n * n * 8
            while left:
                member.write(chunk[:min(left, len(chunk))])
                left -= min(left, len(chunk))
    refused(model(tmp_path), "bytes decompressed; limited to 536870912")


def test_npz_other_compression_and_many_members(tmp_path):
    with zipfile.ZipFile(tmp_path / "K.npz", "w", zipfile.ZIP_BZIP2) as zf:
        zf.writestr("K.npy", npy_header((1, 1)) + bytes(8))
    refused(model(tmp_path), "only stored and deflated members are read")
    with zipfile.ZipFile(tmp_path / "K.npz", "w") as zf:
        for i in range(limits.MAX_ARCHIVE_MEMBERS + 1):
            zf.writestr(f"a{i}.npy", b"")
    refused(model(tmp_path), "more than 64 members")


def test_npz_member_names_are_not_echoed(tmp_path):
    np.savez(tmp_path / "K.npz", **{"../../etc/passwd": np.eye(3), "\x1b[31mred": np.eye(3)})
    with pytest.raises(ModelError) as info:
        load(model(tmp_path))
    message = str(info.value)
    assert "holds 2 arrays but none named 'K'" in message
    assert "passwd" not in message and "\x1b" not in message and "red" not in message


MTX = "%%MatrixMarket matrix coordinate real general\n"


@pytest.mark.parametrize("text, words", [
    (MTX + "20000000 20000000 1\n1 1 1\n", "limited to 200000x200000"),
    (MTX + "1000000000 1000000000 1\n1 1 1\n", "limited to 200000x200000"),
    (MTX + "3 3 19000000\n1 1 1\n", "claims more entries than the file"),
    (MTX + "3 3 30000000\n1 1 1\n", "limited to 20000000"),
    (MTX + "3 3 2\n1 1 1\n9 2 3\n", "an entry at (9, 2) lies outside the 3x3 matrix"),
    # found by fuzz campaign 3 (seed 2028, docs/fuzzing.md): NUL bytes crashed scipy's reader
    (MTX + "3 3 2\n1 1 2.0\n3 3 2\x00\x00\x00\x80 2 -1.0\n", "other than numbers"),
    (MTX + "0 0 0\n", "at least one row"),
    (MTX + "3 2 1\n1 1 1\n", "not a square matrix"),
    (MTX + "3 3 1\n1 1 nan\n", "non-finite"),
    (MTX.replace("real", "complex") + "3 3 1\n1 1 1 1\n", "complex entries"),
    ("%%MatrixMarket matrix array real general\n30000 30000\n1\n", "limited to 25000000"),
    ("not a matrix market file\n", "not a valid Matrix Market file"),
])
def test_mtx_header_claims(tmp_path, text, words):
    (tmp_path / "K.mtx").write_text(text)
    refused(model(tmp_path, K='"K.mtx"'), "cannot read 'K.mtx'", words)


def test_valid_mtx_symmetric(tmp_path):
    scipy.io.mmwrite(str(tmp_path / "K.mtx"), sp.coo_matrix(np.array(
        [[2.0, -1, 0], [-1, 2, -1], [0, -1, 1]])), symmetry="symmetric")
    assert load(model(tmp_path, K='"K.mtx"')).matrices.K.toarray()[2, 1] == -1.0


def test_limits_are_overridable(tmp_path, monkeypatch):
    np.save(tmp_path / "K.npy", np.eye(3))
    path = model(tmp_path, K='"K.npy"')
    load(path)
    monkeypatch.setattr(limits, "MAX_MATRIX_DIMENSION", 2)
    with pytest.raises(ModelError, match="limited to 2x2"):
        load(path)


# -- 5. dtypes ------------------------------------------------------------------------------

@pytest.mark.parametrize("array, words", [
    (np.eye(3, dtype=complex), "complex numbers"),
    (np.array([[object()] * 3] * 3, dtype=object), "pickled data), which resonant never loads"),
    (np.eye(3, dtype=np.longdouble), "long-double (float128)"),
    (np.zeros((3, 3), dtype=[("a", "<f8")]), "structured"),
    (np.full((3, 3), "a"), "holds text"),
    (np.eye(3, dtype=bool), "booleans"),
    (np.array([[1.0, np.inf, 0], [0, 1, 0], [0, 0, 1]]), "non-finite"),
    (np.ones(3), "1 dimensions"),
    (np.zeros((0, 0)), "at least one row"),
    (np.eye(3).astype(">f8"), None),
    (np.asfortranarray(np.arange(9.0).reshape(3, 3)), None),
])
def test_npy_dtypes(tmp_path, array, words):
    if array.dtype == np.longdouble and np.finfo(np.longdouble).bits <= 64:
        pytest.skip("no long double on this platform")
    np.save(tmp_path / "K.npy", array, allow_pickle=True)
    np.savez(tmp_path / "K.npz", K=array)  # numpy writes object arrays pickled here too
    for name in ("K.npy", "K.npz"):
        path = model(tmp_path, K=f'"{name}"')
        if words is None:
            np.testing.assert_array_equal(load(path).matrices.K, array)
            continue
        code, _, err = run_cli(["check", path])
        assert code == 2 and f"cannot read '{name}'" in err and words in err, err


# -- 6. silently accepted input -------------------------------------------------------------

@pytest.mark.parametrize("extra, words", [
    ("[matrices.harmonic]\nomega = 1\nF_S = [1, 0]\n", "harmonic inside [matrices] must be"),
    ("harmonic = 5\n", "harmonic inside [matrices] must be"),
    ("harmonic = [{ omega = 1, F_S = [1, 0] }]\n[[harmonic]]\nomega = 2\nF_S = [0, 1]\n",
     "not both"),
])
def test_harmonic_inside_matrices(tmp_path, extra, words):
    path = tmp_path / "m.toml"
    path.write_text("[matrices]\nM = [[1, 0], [0, 1]]\nK = [[2, 0], [0, 2]]\n" + extra)
    code, _, err = run_cli(["solve", path])
    assert code == 2 and words in err and "[matrices] harmonic" in err, err


def test_harmonic_list_inside_matrices_still_works():
    model = loads("[matrices]\nM = [[1, 0], [0, 1]]\nK = [[2, 0], [0, 2]]\n"
                  "harmonic = [{ omega = 1, F_S = [1, 0] }]\n")
    assert len(model.matrices.harmonics) == 1


@pytest.mark.parametrize("coordinates, words", [
    ("[1, 2]", "must list names as strings"),
    ('["a", 2]', "must list names as strings"),
    ('["a", "a"]', "'a' is listed twice"),
])
def test_coordinates_list_entries(tmp_path, coordinates, words):
    path = tmp_path / "m.toml"
    path.write_text(f"coordinates = {coordinates}\n[matrices]\nM = [[1, 0], [0, 1]]\n"
                    "K = [[2, 0], [0, 2]]\n")
    code, _, err = run_cli(["check", path])
    assert code == 2 and words in err, err


@pytest.mark.parametrize("command", ["solve", "check", "modes"])
def test_zero_size_matrix_is_an_error(tmp_path, command):
    np.save(tmp_path / "Z.npy", np.zeros((0, 0)))
    path = tmp_path / "m.toml"
    path.write_text('[matrices]\nM = "Z.npy"\nK = "Z.npy"\n')
    code, out, err = run_cli([command, path])
    assert code == 2 and "at least one row" in err and "stable" not in out, err
