"""The condensed harmonic balance chooses its number of harmonics H like the full one.

The model: a 30-DOF chain with a cubic spring at its tip (``tests/test_condensed.py``'s
``chain``), whose natural frequencies 1.545, 4.63, 7.70, 10.76, ... rad/s stand nearly
as 1 : 3 : 5 : 7: swept across its first resonance, the 7th harmonic of the motion
resonates with mode 4, so 7 harmonics (the default start) leave 1e-4 of the amplitude in
the highest ones.  References: the same branch with H = 15 given (two routes), the full
(uncondensed) harmonic balance of the same 2-DOF system given by its energies.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from resonant.analyses import condensed
from resonant.analyses.condensed import condensed_sweep
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.analyses.hb_solver import DEFAULT_HARMONICS, TRUNCATION_TOL
from resonant.api import load, loads
from resonant.system import nonlinear_system
from test_condensed import DUFFING_ENERGY, DUFFING_MATRICES, chain

RANGE = (1.4, 1.7)
OBSERVE = ["q10", "q20"]


def _sweep(harmonics: int | None, force: float = 0.004, **options: object):
    model, *_ = chain(30, force=force)
    return condensed_sweep(nonlinear_system(model), "w", *RANGE, harmonics=harmonics, points=10,
                           observe=OBSERVE, linear=False, **options)


@pytest.fixture(scope="module")
def runs():
    return {H: _sweep(H) for H in (None, 7, 15)}


def _folds(r) -> list[float]:
    return sorted(s.value for s in r.special_points if s.kind == "fold")


def test_default_raises_the_harmonics_until_the_truncation_is_small(runs):
    """H not given: raised from 7 (truncation 1e-4) until the highest harmonics carry less
    than 1e-6 of the amplitude; the branch then equals the one with H = 15 given: the
    folds to 1e-10 and the peak amplitude of every reported coordinate to 1e-8 relative
    (about 1e-9 seen), where H = 7 misses them by more than 1e-7 (3e-6 seen)."""
    auto, seven, fifteen = runs[None], runs[7], runs[15]
    assert DEFAULT_HARMONICS == 7 < auto.harmonics <= 15
    assert auto.truncation <= TRUNCATION_TOL < seven.truncation
    assert not any("highest harmonics" in w for w in auto.warnings)
    assert len(_folds(auto)) == 2
    np.testing.assert_allclose(_folds(auto), _folds(fifteen), rtol=1e-10)
    names = ("q30", *OBSERVE)
    for name in names:
        assert max(auto.amplitudes[name]) == pytest.approx(max(fifteen.amplitudes[name]),
                                                           rel=1e-8)
    assert max(abs(max(seven.amplitudes[q]) / max(fifteen.amplitudes[q]) - 1)
               for q in names) > 1e-7


def test_given_harmonics_are_kept_and_the_truncation_is_explained(runs):
    """H given is never raised; the truncation above the tolerance is a warning that names
    the harmonic resonance behind it (the 7th harmonic near mode 4, 10.76 rad/s)."""
    seven = runs[7]
    assert seven.harmonics == 7 and runs[15].harmonics == 15
    [warning] = [w for w in seven.warnings if "highest harmonics" in w]
    assert "with 7 harmonics given" in warning
    assert "the 7th harmonic" in warning and "resonates with mode 4 (10.76 rad/s)" in warning


def test_the_most_harmonics_reached_is_a_warning(monkeypatch):
    """Where the automatic choice stops at its largest H still above the tolerance, the
    result says so and why (here the largest H made 11; the 11th harmonic resonates
    with mode 6)."""
    monkeypatch.setattr(condensed, "MAX_HARMONICS", 11)
    r = _sweep(None, force=0.01)
    assert r.harmonics == 11 and r.truncation > TRUNCATION_TOL
    [warning] = [w for w in r.warnings if "highest harmonics" in w]
    assert "with 11 harmonics, the most the automatic choice takes" in warning
    assert "the 11th harmonic" in warning and "resonates with mode 6" in warning


def test_given_samples_bound_the_harmonics():
    """With samples given, H rises to at most samples / 4 - 1 (the full balance's own
    samples for H), and the warning says so."""
    r = _sweep(None, force=0.01, samples=48)
    assert r.harmonics == 11
    [warning] = [w for w in r.warnings if "highest harmonics" in w]
    assert "the most the automatic choice takes with 48 samples per period" in warning


def test_the_same_choice_as_the_full_balance():
    """The 2-DOF system with a cubic spring between its masses, once as [matrices] with a
    [[nonlinear]] element, once by its energies, H not given: the condensed and the full
    balance raise H alike (to 15), their truncations agree to 1e-8 relative and the
    amplitudes at the branch's end to 1e-8."""
    condensed_ = condensed_sweep(nonlinear_system(loads(DUFFING_MATRICES)), "w", 0.4, 0.6,
                                 points=10, observe=["q1"], linear=False)
    full = nonlinear_sweep(nonlinear_system(loads(DUFFING_ENERGY).linearize()), "w", 0.4, 0.6,
                           points=10, linear=False)
    assert condensed_.harmonics == full.harmonics > DEFAULT_HARMONICS
    assert condensed_.truncation == pytest.approx(full.truncation, rel=1e-8)
    assert condensed_.truncation <= TRUNCATION_TOL
    for name in ("q1", "q2"):
        assert condensed_.amplitudes[name][-1] == pytest.approx(full.amplitudes[name][-1],
                                                                rel=1e-8)


@pytest.mark.parametrize("H, N", [(40, 2048), (7, 2048), (40, 96), (3, 8)])
def test_galerkin_blocks_from_the_spectrum_equal_the_sampled_product(H, N):
    """Two routes to P diag(g) phi (the Jacobian's blocks of an element's tangent g):
    the sampled product and the convolution of g's spectrum (used with many samples),
    aliasing included (N below 4H): equal to 1e-13 relative."""
    basis = condensed._Basis(H, N)
    G = np.random.default_rng(H + N).standard_normal((2, 2, N))
    sampled = (G[:, :, None, :] * basis.P) @ basis.phi
    spectral = basis.galerkin(G)
    assert np.abs(spectral - sampled).max() <= 1e-13 * np.abs(sampled).max()
    np.testing.assert_allclose(basis.phi @ basis.D, basis.dphi, atol=1e-12)


def test_a_raise_that_fails_keeps_the_last_harmonics_and_says_why(monkeypatch):
    """Where the balance cannot be built for more harmonics (here: no linear part beyond
    11, as a reduced model over a wider band might fail), H stays at the last that
    converged and the warning names the failure."""
    at = condensed._Balances.at

    def limited(self, H):
        if H > 11:
            raise condensed.AnalysisError("the reduced model did not reach the tolerance")
        return at(self, H)

    monkeypatch.setattr(condensed._Balances, "at", limited)
    r = _sweep(None, force=0.01)
    assert r.harmonics == 11 and r.truncation > TRUNCATION_TOL
    [warning] = [w for w in r.warnings if "highest harmonics" in w]
    assert ("with 11 harmonics, the automatic choice stopped there: no linear part for 15 "
            "harmonics (the reduced model did not reach the tolerance)") in warning


def _rod(tmp_path, n: int) -> str:
    """``benchmarks/bench_nonlinear_fe.py``'s rod of n masses 1/n on springs n (first
    natural frequency pi/2), a cubic spring 2 q^3 at its tip and no stop: its model file."""
    main = np.full(n, 2.0 * n)
    main[-1] = n
    K = sp.diags([np.full(n - 1, -1.0 * n), main, np.full(n - 1, -1.0 * n)], [-1, 0, 1],
                 format="csr")
    M = sp.identity(n, format="csr") / n
    for name, A in (("M", M), ("K", K), ("C", (0.02 * M + 0.002 * K).tocsr())):
        sp.save_npz(tmp_path / f"{name}.npz", A)
    path = tmp_path / "rod.toml"
    path.write_text(f'[parameters]\nomega = 1\n[matrices]\nM = "M.npz"\nC = "C.npz"\n'
                    f'K = "K.npz"\n[[harmonic]]\nomega = "omega"\nF_C = {{ q{n} = "0.01" }}\n'
                    f'[[nonlinear]]\nname = "spring"\ncoordinates = ["q{n}"]\n'
                    f'force = "2*q{n}^3"\n', encoding="utf-8")
    return str(path)


def test_the_harmonics_tried_build_no_reduced_model(tmp_path, monkeypatch):
    """A 450-coordinate rod (a reduced linear part) swept over 1.0 ... 2.4 rad/s: the
    automatic choice raises H from 7 through 11 to 15, each H tried at one point with
    exact receptances; reduced models are built for the bands of H = 7 and of the H
    chosen only (also for 11 before: on a 2,500-coordinate grid that band alone took 8 s
    and 15's 71 s, docs/performance-nonlinear.md), and the branch is the one the
    raise through 11's reduced model gave (folds 1.62878 and 1.71563, measured before)."""
    built = []
    original = condensed.linear_part

    def counted(*args, **kwargs):
        part = original(*args, **kwargs)
        built.append(float(args[6].max()))
        return part

    monkeypatch.setattr(condensed, "linear_part", counted)
    r = condensed_sweep(nonlinear_system(load(_rod(tmp_path, 450))), "omega", 1.0, 2.4,
                        points=30, linear=False)
    assert r.harmonics == 15
    assert built == pytest.approx([7 * 2.4 * 1.05, 15 * 2.4 * 1.05])
    assert _folds(r) == pytest.approx([1.62878, 1.71563], abs=1e-5)
