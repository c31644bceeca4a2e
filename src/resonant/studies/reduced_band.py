"""One reduced model per sample over a peak's band (large models).

The peak search (:mod:`.quantities`) solves the band's grid and then rounds of
a few frequencies around the best point.  For a large model whose direct solves
are expensive, every round calling the kernel anew would choose a method and
factorize again.  Where the kernel itself would take a reduced model for the
band (:func:`resonant.analyses.kernel.reduced_budget`: fixed sparse matrices
and load, direct solves estimated above a second), :func:`reduced_band` builds
one (:func:`resonant.analyses.reduced.reduced_model`, certified to
:data:`TOLERANCE` at twice the band's grid density) and every round is an r x r
solve per frequency.  The caller solves the found peak once more exactly.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> from resonant.system import Batch, BatchHarmonic
>>> n = 600
>>> K = sp.diags([-np.ones(n - 1), np.r_[2 * np.ones(n - 1), 1.0], -np.ones(n - 1)],
...              [-1, 0, 1], format="csr") * 1e4
>>> M = sp.identity(n, format="csr")
>>> grid = np.linspace(0.5, 5.0, 200)
>>> load = np.zeros(n); load[-1] = 1.0
>>> batch = Batch(tuple(f"q{i}" for i in range(1, n + 1)), M, 0.05 * M + 1e-4 * K, K,
...               [BatchHarmonic(grid, load, np.zeros(n), {})], {}, "", True, 200)
>>> band = reduced_band(batch, grid, [f"q{n}"], budget=10.0)
>>> z = np.linalg.solve((K - 4.0 * M + 2j * (0.05 * M + 1e-4 * K)).toarray(), load)[-1]
>>> bool(abs(band.amplitudes(np.array([[2.0]]))[0, 0, 0] - abs(z)) < 1e-8 * abs(z))
True
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..analyses.kernel import reduced_budget
from ..analyses.reduced import ReducedModel, reduced_model
from ..errors import AnalysisError
from ..system.batch import Batch

#: the reduced model's certified relative error over the band (the found peak is solved
#: again exactly)
TOLERANCE = 1e-8


@dataclass(frozen=True)
class ReducedBand:
    """The amplitudes of some coordinates at any frequency of a band, from one reduced
    model.

    Parameters
    ----------
    model : ReducedModel
    rows : ndarray of int
        The coordinates' indices, in the order of the names asked for.

    Examples
    --------
    See the module's example.
    """

    model: ReducedModel
    rows: np.ndarray

    def amplitudes(self, points: np.ndarray) -> np.ndarray:
        """|z| at the frequencies ``points`` (N, F): shape (N, F, coordinates).

        Parameters
        ----------
        points : ndarray
            Frequencies (rad/s).

        Returns
        -------
        ndarray
        """
        rom = self.model
        w = np.asarray(points, dtype=float).ravel()[:, None, None]
        A = rom.Kr[None] - w * w * rom.Mr[None] + 1j * w * rom.Cr[None]
        y = np.linalg.solve(A, np.broadcast_to(rom.Br, (len(w), *rom.Br.shape)))
        z = np.einsum("kr,frl->fk", rom.V[self.rows], y)
        return np.abs(z).reshape(*np.shape(points), len(self.rows))


def _load(batch: Batch, grid: np.ndarray) -> np.ndarray | None:
    """The one harmonic's load F_C - i F_S at the band's first point, when its frequency
    is the band's parameter and the matrices do not change along the band; else None."""
    if len(batch.harmonics) != 1 or not batch.constant or batch.outputs:
        return None
    h = batch.harmonics[0]
    if not np.array_equal(np.asarray(h.omega, dtype=float), grid):
        return None
    f_c, f_s = (np.asarray(f, dtype=float) for f in (h.F_C, h.F_S))
    rhs = (f_c[0] if f_c.ndim == 2 else f_c) - 1j * (f_s[0] if f_s.ndim == 2 else f_s)
    return rhs if np.any(rhs) else None


def _same_along(batch: Batch) -> bool:
    """Whether the load is the same at every point of the band."""
    h = batch.harmonics[0]
    return all(np.ndim(f) == 1 or bool(np.all(f == f[:1])) for f in (h.F_C, h.F_S))


def reduced_band(batch: Batch, grid: np.ndarray, names: Sequence[str],
                 budget: float | None = None) -> ReducedBand | None:
    """A reduced model of one sample over the band, where it pays; else None.

    Parameters
    ----------
    batch : Batch
        The sample's system at the band's grid (the band's parameter is the excitation
        frequency).
    grid : ndarray
        The band's grid (F,).
    names : sequence of str
        Coordinates.
    budget : float, optional
        Seconds the reduced model may take (default: the kernel's choice, None when the
        direct solves are cheap).

    Returns
    -------
    ReducedBand or None
        None when the model does not qualify (the frequency is not the band's parameter,
        the matrices or the load change along the band, several harmonics, outputs), the
        direct solves are cheap, or the reduced model misses :data:`TOLERANCE`.
    """
    rhs = _load(batch, grid)
    if rhs is None or any(name not in batch.coordinates for name in names):
        return None
    budget = budget if budget is not None else reduced_budget(batch, grid, rhs)
    if budget is None or not _same_along(batch):
        return None
    checked = np.linspace(grid[0], grid[-1], 2 * len(grid) - 1)
    try:
        rom = reduced_model(batch.M, batch.C, batch.K, rhs[:, None], checked, tol=TOLERANCE,
                            budget=budget)
    except AnalysisError:
        return None
    if not rom.converged:
        return None
    rows = np.array([batch.coordinates.index(name) for name in names], dtype=int)
    return ReducedBand(rom, rows)


__all__ = ["ReducedBand", "reduced_band", "TOLERANCE"]
