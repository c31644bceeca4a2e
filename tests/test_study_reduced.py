"""The peak search of large matrix models on one reduced model per sample
(resonant.studies.reduced_band) against the direct route, and the evaluation of large
load vectors."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.io

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import bench_reduced  # noqa: E402

import resonant  # noqa: E402
from resonant.analyses import kernel  # noqa: E402
from resonant.studies import StudyJob, collect, engine_for, request  # noqa: E402
from resonant.studies import quantities as quantities_module  # noqa: E402
from resonant.studies import reduced_band as reduced_band_module  # noqa: E402

pytest.importorskip("pandas")


def grid_model(directory: Path, nx: int = 24) -> Path:
    """An nx x nx mass-spring grid (random masses and springs, edges grounded, Rayleigh
    damping), a force F0 at one interior mass: the sparse kind a reduced model is for."""
    M, _, K, f = bench_reduced.grid_matrices(nx)
    C = (0.5 * M + 1e-4 * K).tocsr()
    for key, a in (("M", M), ("C", C), ("K", K)):
        scipy.io.mmwrite(str(directory / f"{key}.mtx"), a)
    load = ['"F0"' if v else "0" for v in f]
    path = directory / "grid.toml"
    path.write_text('[parameters]\nF0 = 1\nomega = 10\n[matrices]\nM = "M.mtx"\n'
                    'C = "C.mtx"\nK = "K.mtx"\n[[harmonic]]\nomega = "omega"\n'
                    f"F_C = [{', '.join(load)}]\n", encoding="utf-8")
    return path


def peaks(path: Path, shared: bool, monkeypatch) -> tuple[object, list[str]]:
    model = resonant.load(path)
    n = len(model.coordinates)
    loaded = model.coordinates[(24 // 3) * 24 + 24 // 4]
    names = [loaded, model.coordinates[n // 2]]
    spec = request(model, {"F0": "uniform(0.5, 1.5)"}, [f"peak:{q}" for q in names],
                   samples=3, seed=1, band={"parameter": "omega", "from": 5, "to": 40,
                                            "points": 120})
    monkeypatch.setattr(kernel, "REDUCED_WORTH", 0.0 if shared else float("inf"))
    return collect(StudyJob.of(model, spec), engine_for(0)).table, names


def test_peaks_on_the_shared_reduced_model_equal_the_direct_route(tmp_path, monkeypatch):
    """576 coordinates, a band over the grid's lowest dozen modes.  The reduced model is
    certified to 1e-8 and the peak found on it is solved exactly: the peak agrees with
    the direct route's to 1e-9 relative, its frequency to 1e-7."""
    path = grid_model(tmp_path)
    used = []
    original = reduced_band_module.reduced_band

    def spy(*args, **kwargs):
        band = original(*args, **kwargs)
        used.append(band is not None)
        return band

    monkeypatch.setattr(quantities_module, "reduced_band", spy)
    shared, names = peaks(path, True, monkeypatch)
    assert used == [True] * 3
    direct, _ = peaks(path, False, monkeypatch)
    assert used[3:] == [False] * 3
    for q in names:
        np.testing.assert_allclose(shared[f"peak:{q}"], direct[f"peak:{q}"], rtol=1e-9)
        np.testing.assert_allclose(shared[f"peak_frequency:{q}"],
                                   direct[f"peak_frequency:{q}"], rtol=1e-7)
    # the peak scales with F0 (a linear model): the search found the same frequency
    ratio = shared[f"peak:{names[0]}"] / shared["F0"]
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)


def test_large_load_vectors_evaluate_as_before(tmp_path):
    """The numbers of a load vector are read once; its expressions still follow the
    parameters (a vector of numbers and one expression)."""
    path = grid_model(tmp_path, nx=6)
    system = resonant.load(path).linearize()
    batch = system.evaluate({"F0": np.array([1.0, 2.5]), "omega": 3.0}, 2)
    f_c = batch.harmonics[0].F_C
    assert f_c.shape == (2, 36) and f_c[:, 13].tolist() == [1.0, 2.5]
    assert np.count_nonzero(f_c) == 2
