"""A reduced sweep on a model read from a Nastran OUTPUT4 file (docs/performance-large.md,
"Nastran OUTPUT4"): ``resonant sweep --method reduced`` against ``--method direct`` (the
exact banded solve) on the five-diagonal chain of benchmarks/bench_op4.py, 1,500 rows
written by pyYeti as a binary bigmat file, M = I, C = 1e-3 K, a unit force on q1.

The band, 1e-4 to 2e-2 rad/s, holds the chain's five lowest modes (their damping ratios
below 1e-5: sharp peaks).  Away from them (more than 1 % from each undamped natural
frequency, from ``resonant modes --count 8``: Lanczos) the reduced amplitudes agree with the exact ones to
the sweep's tolerance, 1e-6 relative (measured: 3e-10), and the reduced model's own
estimate of its error is below that tolerance; the whole curve agrees to 1e-4 (the peaks
included).  The same sweep on 200,000 rows is the benchmark
(``python benchmarks/bench_op4.py reduced``)."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import run_json

pytest.importorskip("pyyeti")

ROWS = 1500
SWEEP = ["--param", "omega", "--from", "1e-4", "--to", "2e-2", "--points", "80",
         "--only", "q1"]


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    import scipy.sparse as sp

    from resonant.model.op4_files import numpy_print_options_kept, write_op4

    folder = tmp_path_factory.mktemp("op4")
    main, first, second = np.full(ROWS, 3.0), np.full(ROWS - 1, -1.0), np.full(ROWS - 2, -0.5)
    K = sp.diags([second, first, main, first, second], [-2, -1, 0, 1, 2], format="csr")
    with numpy_print_options_kept():
        write_op4(folder / "chain.op4", {"kaa": K}, binary=True, sparse="bigmat")
    sp.save_npz(folder / "mass.npz", sp.identity(ROWS, format="csr"))
    path = folder / "chain.toml"
    path.write_text('title = "chain"\n[parameters]\nomega = 1.0\n[matrices]\n'
                    'M = "mass.npz"\nK = "chain.op4:KAA"\nC = "1e-3*K"\n[[harmonic]]\n'
                    'omega = "omega"\nF_C = { q1 = 1.0 }\n', encoding="utf-8")
    return path


def test_reduced_sweep_agrees_with_the_direct_one(model):
    reduced = run_json("sweep", model, *SWEEP, "--method", "reduced")
    direct = run_json("sweep", model, *SWEEP, "--method", "direct")
    assert reduced["method"] == "reduced" and direct["method"] in ("banded", "sparse")
    assert reduced["estimated_error"] <= reduced["tolerance"] == 1e-6
    omega = np.array(reduced["values"])
    assert np.array_equal(omega, direct["values"])
    a, b = (np.array(r["amplitudes"]["q1"], dtype=float) for r in (reduced, direct))
    natural = np.array(run_json("modes", model, "--count", "8")["natural_frequencies"])
    natural = natural[natural <= 4e-2]
    assert np.count_nonzero((natural > 1e-4) & (natural < 2e-2)) == 5
    away = np.min(np.abs(omega[:, None] / natural[None, :] - 1), axis=1) > 0.01
    assert away.sum() > 40
    assert np.max(np.abs(a[away] - b[away]) / b[away]) < 1e-6
    assert np.max(np.abs(a - b) / b) < 1e-4
