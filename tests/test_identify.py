"""Modal identification (LSCF poles, stabilization, LSFD residues) on simulated FRFs whose
modes are known.

References: the FRFs are written from their modes (receptance of a proportionally damped
system, H_o = sum_r phi_o phi_ref / (w_r^2 - w^2 + 2 i zeta_r w_r w); Ewins, Modal Testing,
2nd ed., eq. 2.72), so the poles s_r = -zeta w_r + i w_r sqrt(1 - zeta^2) and the shapes are
exact.  Tolerances: without noise the identified frequencies to 1e-6 (relative), damping
ratios to 1e-5 (absolute), MAC with the true shapes above 0.99999; with 1 % noise on every
line, frequencies to 1e-3 and damping to 5e-3.  The 3-mass chain (examples/chain3_damped.toml,
c = 8 N s/m) through resonant's own FRF (the kernel) against its closed-form modes
omega_j = 2 sqrt(k/m) sin((2j - 1) pi / 14), zeta_j = c omega_j / (2 k).  sdypy-EMA (pyEMA)
on the same data, where it is installed, within the same tolerances.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import resonant
from resonant.analyses.frf_estimate import model_frf
from resonant.analyses.identify import (
    ModalIdentification,
    identify_modes,
    lscf_poles,
    modal_assurance,
)
from resonant.errors import ModelError
from resonant.model.measurement_spec import ChannelMap

FN = np.array([10.0, 10.6, 25.0])           # two close modes (0.6 Hz apart, 1 Hz wide)
ZETA = np.array([0.05, 0.05, 0.05])
PHI = np.array([[1.0, 0.8, 0.5], [0.7, -0.9, 1.0], [0.4, 1.0, -0.8], [0.9, 0.2, 0.3],
                [-0.5, 0.6, 0.9], [0.2, -0.4, -1.0]])


def modal_frf(f: np.ndarray, reference: int = 0) -> np.ndarray:
    w = 2 * np.pi * f[None, :, None]
    wr = 2 * np.pi * FN[None, None, :]
    terms = PHI[:, None, :] * PHI[reference][None, None, :] / (
        wr ** 2 - w ** 2 + 2j * ZETA * wr * w)
    return terms.sum(axis=2)


def _frfs(H: np.ndarray) -> dict[str, np.ndarray]:
    return {f"p{k + 1}": h for k, h in enumerate(H)}


def _shapes_mac(r: ModalIdentification) -> np.ndarray:
    return np.diag(modal_assurance(r.shapes, PHI))


def test_close_modes_without_noise():
    f = np.linspace(2.0, 40.0, 761)
    r = identify_modes(f, _frfs(modal_frf(f)), max_order=30)
    assert len(r.frequency) == 3, r.summary()
    np.testing.assert_allclose(r.frequency, FN, rtol=1e-6)
    np.testing.assert_allclose(r.damping, ZETA, atol=1e-5)
    assert (_shapes_mac(r) > 0.99999).all()
    assert max(r.errors.values()) < 1e-4
    assert "s" in set(np.concatenate(r.stabilization.stable))


def test_close_modes_with_noise():
    f = np.linspace(2.0, 40.0, 761)
    H = modal_frf(f)
    rng = np.random.default_rng(7)
    noisy = H + 0.01 * np.abs(H) * (rng.standard_normal(H.shape)
                                    + 1j * rng.standard_normal(H.shape)) / np.sqrt(2)
    r = identify_modes(f, _frfs(noisy), max_order=40, near=list(FN))
    np.testing.assert_allclose(r.frequency, FN, rtol=1e-3)
    np.testing.assert_allclose(r.damping, ZETA, atol=5e-3)
    assert (_shapes_mac(r) > 0.99).all()
    # the fit's error is the noise's (1 %), not the model's
    assert 0.005 < np.median(list(r.errors.values())) < 0.02


def test_chain_from_the_kernels_frf():
    system = resonant.load("examples/chain3_damped.toml").with_parameters(c="8 N*s/m") \
        .linearize()
    f = np.linspace(0.5, 15.0, 600)
    channels = {q: ChannelMap(q, 2) for q in ("x1", "x2", "x3")}
    r = identify_modes(f, model_frf(system, "F", f, channels), max_order=30, derivative=2)
    j = np.arange(1, 4)
    omega = 2 * np.sqrt(1000.0) * np.sin((2 * j - 1) * np.pi / 14)
    np.testing.assert_allclose(r.frequency, omega / (2 * np.pi), rtol=1e-6)
    np.testing.assert_allclose(r.damping, 8 * omega / 2000, atol=1e-5)
    back = ModalIdentification.from_dict(json.loads(json.dumps(r.to_dict())))
    assert back.to_dict() == r.to_dict()
    assert r.chart().panels[0].curves


def test_against_sdypy_ema():
    """pyEMA's LSCF and ours on the same FRFs: the same poles where pyEMA finds them.  Its
    pole picking (select_closest_poles) returns the 10.6 Hz pole for both 10.0 and 10.6 Hz
    (sdypy-EMA 0.31); ours keeps the two close modes apart."""
    EMA = pytest.importorskip("sdypy.EMA")
    f = np.arange(0.0, 40.0 + 1e-9, 0.05)
    H = modal_frf(f)
    ours = identify_modes(f[40:], _frfs(H[:, 40:]), max_order=40)
    model = EMA.Model(frf=H, freq=f, lower=2.0, upper=40.0, pol_order_high=20,
                      frf_form="receptance")
    model.get_poles(show_progress=False)
    model.select_closest_poles(list(FN), f_window=2)   # the default (50) finds nothing here
    theirs_f, theirs_z = np.asarray(model.nat_freq), np.asarray(model.nat_xi)
    np.testing.assert_allclose(theirs_f[1:], FN[1:], rtol=1e-6)
    np.testing.assert_allclose(ours.frequency[1:], theirs_f[1:], rtol=1e-6)
    np.testing.assert_allclose(ours.damping[1:], theirs_z[1:], atol=1e-5)
    np.testing.assert_allclose(ours.frequency, FN, rtol=1e-6)


def test_lscf_poles_of_one_mode():
    f = np.linspace(1, 10, 200)
    s = -1 + 20j
    iw = 2j * np.pi * f
    h = 1 / (iw - s) + 1 / (iw - np.conj(s))
    p = lscf_poles(f, h[None, :], 10)
    assert np.min(np.abs(p - s)) < 1e-5


@pytest.mark.parametrize("frequency, frfs, kwargs, match", [
    (np.array([1.0, 2.0]), {"a": np.ones(2)}, {}, "at least 4"),
    (np.linspace(1, 2, 8), {}, {}, "no FRF"),
    (np.linspace(1, 2, 8), {"a": np.ones(7)}, {}, "needs 8 values"),
    (np.linspace(1, 2, 8), {"a": np.full(8, np.nan)}, {}, "'a' holds NaN"),
    (np.linspace(1, 2, 8), {"a": np.ones(8)}, {"max_order": 500}, "order must lie"),
])
def test_bad_input(frequency, frfs, kwargs, match):
    with pytest.raises(ModelError, match=match):
        identify_modes(frequency, frfs, **kwargs)
