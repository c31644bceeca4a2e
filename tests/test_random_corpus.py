"""The random response's reduced route on every corpus structure (benchmarks/corpus.py:
beams, plate, solid, chains, grid, a stiff local spring, clustered frequencies, a free-free
beam, a stiffness spread of 12 decades), at a few hundred coordinates: a force with a flat
density (1 N^2/Hz) on the structure's load vector over its band of first resonances.

Two routes to one answer: ``method="reduced"`` (one reduced model of the band for every
refinement round) against ``method="direct"`` (an exact solve at every frequency of the
quadrature).  The mean squares agree within the sum of the two reported error estimates
(each the quadrature's estimate plus, for the reduced route, its model's bound), at a
tolerance of 1e-3 (each estimate relative to its own mean square: a coordinate the load
does not reach, as in the clustered structure of independent oscillators, has rounding
noise of 1e-29 there and a relative estimate of 1e6, which bounds it); where the reduced
route's estimate is above the tolerance it says so.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("skfem")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import corpus  # noqa: E402
import scipy.sparse as sp  # noqa: E402

from resonant.analyses.random_response import random_response  # noqa: E402
from resonant.model import loads  # noqa: E402
from resonant.system import linear_system  # noqa: E402

SIZES = {"plate": 150, "solid": 150, "timoshenko_beam": 120}
TOLERANCE = 1e-3


def _system(name: str, folder: Path):  # type: ignore[no-untyped-def]
    s = corpus.build(name, SIZES.get(name, 160))
    for key, a in (("M", s.M), ("C", s.C), ("K", s.K)):
        sp.save_npz(folder / f"{key}.npz", sp.csr_matrix(a))
    low, high = (float(w) / (2 * np.pi) for w in s.band)
    load = ", ".join(repr(float(v)) for v in np.real(s.b))
    text = ('[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
            f'[random]\nband = [{low!r}, {high!r}]\ntolerance = {TOLERANCE}\n'
            f'[random.psd.F]\nunit = "N^2/Hz"\nload = [{load}]\n'
            f'values = [[{low!r}, 1.0], [{high!r}, 1.0]]\n')
    system = linear_system(loads(text, source=str(folder / f"{name}.toml"), base_dir=folder))
    loaded = int(np.argmax(np.abs(s.b)))
    names = sorted({system.coordinates[loaded], system.coordinates[s.n // 2],
                    system.coordinates[-1]})
    return system, names


@pytest.mark.parametrize("name", sorted(corpus.BUILDERS))
def test_reduced_and_direct_give_one_random_response(name: str, tmp_path: Path) -> None:
    system, names = _system(name, tmp_path)
    reduced = random_response(system, names=names, method="reduced")
    direct = random_response(system, names=names, method="direct")
    assert reduced.method == "reduced" and direct.method != "reduced"
    for q in names:
        a, b = reduced.rms[q] ** 2, direct.rms[q] ** 2
        # each estimate is relative to its own mean square (a coordinate the load does not
        # reach has rounding noise there, and says so with a huge relative estimate)
        allowed = reduced.error[q] * a + direct.error[q] * b + 1e-9 * max(a, b)
        assert abs(a - b) <= allowed, (q, a, b, reduced.error[q], direct.error[q])
        if reduced.error[q] > TOLERANCE:
            assert any("above the tolerance" in w for w in reduced.warnings)
