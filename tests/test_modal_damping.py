"""Modal damping of [matrices] models: ``modal_damping = 0.02`` (one ratio for every mode) or
``modal_damping = [0.01, 0.03]`` (one per mode from the lowest; later modes take the last).

Reference: for C = M Phi diag(2 zeta_r omega_r) Phi^T M with mass-normalized Phi the damped
system stays classically damped, so each mode's damping ratio is exactly zeta_r (closed form;
checked to 1e-10 against the ratios `modes` computes from the complex eigenvalues)."""

from __future__ import annotations

import numpy as np
import pytest

from resonant.analyses.modes import modes
from resonant.api import load as load_model
from resonant.errors import ModelError

MODEL = ('title = "3 masses"\n[matrices]\nM = [[1, 0, 0], [0, 2, 0], [0, 0, 1.5]]\n'
         'K = [[300, -100, 0], [-100, 250, -150], [0, -150, 150]]\n{extra}\n')


def modes_of(tmp_path, extra: str):
    path = tmp_path / "m.toml"
    path.write_text(MODEL.format(extra=extra), encoding="utf-8")
    return modes(load_model(str(path)).linearize())


@pytest.mark.parametrize("extra, expected", [
    ("modal_damping = 0.02", [0.02, 0.02, 0.02]),
    ("modal_damping = [0.01, 0.05, 0.1]", [0.01, 0.05, 0.1]),
    ("modal_damping = [0.01, 0.04]", [0.01, 0.04, 0.04]),   # beyond the list: the last ratio
])
def test_each_mode_has_its_given_ratio(tmp_path, extra, expected):
    result = modes_of(tmp_path, extra)
    order = np.argsort(result.natural_frequencies)
    assert np.allclose(np.asarray(result.damping_ratios)[order], expected, rtol=0, atol=1e-10)


@pytest.mark.parametrize("extra, message", [
    ("modal_damping = -0.1", "in [0, 1)"),
    ("modal_damping = 1.5", "in [0, 1)"),
    ('modal_damping = "x"', "modal_damping must be one damping ratio"),
    ("modal_damping = []", "modal_damping must be one damping ratio"),
    ("modal_damping = [0.01, 0.01, 0.01, 0.01]", "lists 4 ratios but the model has only 3"),
    ('modal_damping = 0.02\nC = "0.1*M"', "give either C or modal_damping, not both"),
])
def test_bad_modal_damping_names_the_key(tmp_path, extra, message):
    with pytest.raises(ModelError) as info:
        modes_of(tmp_path, extra)
    text = str(info.value)
    assert message in text and "modal_damping" in text and "m.toml" in text


def test_matrices_from_files(tmp_path):
    """Sparse M, K read from .mtx files: the same ratios (a 20-mass chain)."""
    import scipy.io
    import scipy.sparse as sp

    n = 20
    K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tocsr() * 1e3
    scipy.io.mmwrite(tmp_path / "K.mtx", K)
    scipy.io.mmwrite(tmp_path / "M.mtx", sp.identity(n, format="csr"))
    path = tmp_path / "f.toml"
    path.write_text('title = "chain"\n[matrices]\nM = "M.mtx"\nK = "K.mtx"\n'
                    "modal_damping = [0.01, 0.02]\n", encoding="utf-8")
    result = modes(load_model(str(path)).linearize())
    ratios = np.asarray(result.damping_ratios)[np.argsort(result.natural_frequencies)]
    assert np.allclose(ratios, [0.01] + [0.02] * (n - 1), rtol=0, atol=1e-10)
