"""Inputs of matrix models a finite-element user needs: the load vector from a file (.npy,
.mtx) or as entries by coordinate name, and Rayleigh damping C = "alpha*M + beta*K".

References: each form is checked against the same model written with the full inline
list / the explicit C matrix (exact equality of the matrices and loads read)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

from resonant.api import load as load_model
from resonant.errors import ModelError
from resonant.model.loader import load

N = 30


def write(tmp_path, harmonic: str, C: str = '"C.mtx"') -> str:
    K = sp.diags([-np.ones(N - 1), 2 * np.ones(N), -np.ones(N - 1)], [-1, 0, 1]).tocsr() * 1e4
    M = sp.identity(N, format="csr")
    scipy.io.mmwrite(tmp_path / "K.mtx", K)
    scipy.io.mmwrite(tmp_path / "M.mtx", M)
    scipy.io.mmwrite(tmp_path / "C.mtx", (0.1 * M + 1e-5 * K).tocsr())
    b = np.zeros(N)
    b[-1] = 1.5
    np.save(tmp_path / "b.npy", b)
    np.save(tmp_path / "b2.npy", b[:, None])
    scipy.io.mmwrite(tmp_path / "b.mtx", b[:, None])                 # array layout
    scipy.io.mmwrite(tmp_path / "bc.mtx", sp.csr_matrix(b[:, None]))  # coordinate layout
    path = tmp_path / "model.toml"
    path.write_text(f'title = "chain"\n[parameters]\nF0 = 1.5\nomega = 10\n[matrices]\n'
                    f'M = "M.mtx"\nK = "K.mtx"\nC = {C}\n[[harmonic]]\nomega = "omega"\n'
                    f"{harmonic}\n", encoding="utf-8")
    return str(path)


def loads(model):
    h = model.matrices.harmonics[0]
    return [e.text for e in h.F_C]


def dense(a):
    return a.toarray() if hasattr(a, "toarray") else np.asarray(a)


@pytest.mark.parametrize("given", ['F_C = { q30 = "F0" }', 'F_C = "b.npy"', 'F_C = "b2.npy"',
                                   'F_C = "b.mtx"', 'F_C = "bc.mtx"'])
def test_load_vector_forms_equal_the_full_list(tmp_path, given):
    full = load(write(tmp_path, "F_C = [" + ", ".join(["0"] * (N - 1) + ['"F0"']) + "]"))
    other = load(write(tmp_path, given))
    value = [float(t) if t != "F0" else 1.5 for t in loads(other)]
    expected = [float(t) if t != "F0" else 1.5 for t in loads(full)]
    assert value == expected


def test_rayleigh_damping_equals_the_explicit_matrix(tmp_path):
    explicit = load(write(tmp_path, 'F_C = { q30 = "F0" }'))
    rayleigh = load(write(tmp_path, 'F_C = { q30 = "F0" }', C='"0.1*M + 1e-5*K"'))
    assert np.array_equal(dense(explicit.matrices.C), dense(rayleigh.matrices.C))
    mass_only = load(write(tmp_path, 'F_C = { q30 = "F0" }', C='"2*(M/4)"'))
    assert np.array_equal(dense(mass_only.matrices.C), 0.5 * np.eye(N))


def test_rayleigh_on_inline_matrices_with_parameters(tmp_path):
    path = tmp_path / "inline.toml"
    path.write_text('title = "2"\n[parameters]\na = 0.5\nb = 0.01\nomega = 1\n[matrices]\n'
                    'M = [[1, 0], [0, 2]]\nK = [[4, -1], [-1, "3*a"]]\nC = "a*M + b*K"\n'
                    '[[harmonic]]\nomega = "omega"\nF_C = { q2 = 1 }\n', encoding="utf-8")
    system = load_model(str(path)).linearize()
    eom = system.numeric()
    M, K, C = (dense(a) for a in (eom.M, eom.K, eom.C))
    assert np.allclose(C, 0.5 * M + 0.01 * K, rtol=1e-15, atol=0)


@pytest.mark.parametrize("harmonic, C, message", [
    ('F_C = { q31 = "F0" }', '"C.mtx"', "F_C names 'q31', which is not a coordinate"),
    ('F_C = "missing.npy"', '"C.mtx"', "cannot read 'missing.npy'"),
    ('F_C = { q30 = "F0" }', '"M*K"', "is not of that form"),
    ('F_C = { q30 = "F0" }', '"F0*M"', "needs numbers for alpha and beta"),
    ('F_C = 3', '"C.mtx"', "F_C must be a list of 30 entries, a table of entries"),
])
def test_input_errors_name_the_key(tmp_path, harmonic, C, message):
    with pytest.raises(ModelError, match=message.replace("(", r"\(")):
        load(write(tmp_path, harmonic, C))


def test_vector_of_the_wrong_length(tmp_path):
    np.save(tmp_path / "short.npy", np.ones(N - 1))
    with pytest.raises(ModelError, match="holds 29 entries; the matrices have 30"):
        load(write(tmp_path, 'F_C = "short.npy"'))
