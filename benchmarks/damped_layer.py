"""A cantilever plate under a strong Kelvin-Voigt damping layer: many overdamped modes
below its structural modes, for the complex modes of the modal kernel.

The plate is a square grid of unit masses joined by springs (a membrane's five-point
stencil, one edge held by springs to the ground, the others free; ``side`` x ``side``
coordinates).  The layer is a second grid of light masses (``mu`` = 0.05 of the plate's),
each tied to its plate mass by a spring ``kc`` and joined to its neighbours by springs
``kl``; the layer's springs are Kelvin-Voigt elements: C = beta (K_layer + K_tie),
beta = 2.5e-3 s.  So:

- the structural modes (plate and layer moving together) are underdamped, with damping
  ratios from 0.03 to 0.2 over the first dozen;
- the layer's own modes (its masses against the ties) are overdamped: each has a slow
  root near s = -1 / beta = -400 s^-1, a cluster of side^2 real eigenvalues with |s|
  below the structural modes from the fourth on, and a fast root far to the left.

The plate's springs grow with side^2, so that its lowest frequencies (about 110, 257,
329 rad/s) do not depend on the mesh.  n = 2 side^2: 450 coordinates at side 15 (the
tests), 4,050 at side 45 (the benchmark).

Examples
--------
>>> s = kelvin_voigt_plate(6)
>>> s.n, s.M.shape == s.C.shape == s.K.shape
(72, True)
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from corpus import Structure

#: the Kelvin-Voigt time constant of the layer (s): its overdamped modes sit near -1/BETA
BETA = 2.5e-3


def _stencil(side: int, held: bool) -> sp.csr_matrix:
    """The five-point stencil of a side x side grid with unit springs: free edges, and with
    ``held`` the first row tied to the ground."""
    line = sp.diags([np.full(side - 1, -1.0), np.full(side, 2.0), np.full(side - 1, -1.0)],
                    [-1, 0, 1]).tolil()
    free = line.copy()
    free[0, 0] = free[side - 1, side - 1] = 1.0
    along = line.copy()
    along[side - 1, side - 1] = 1.0
    eye = sp.identity(side)
    first = along if held else free
    return sp.csr_matrix(sp.kron(first.tocsr(), eye) + sp.kron(eye, free.tocsr()))


def kelvin_voigt_plate(side: int, beta: float = BETA, mu: float = 0.05) -> Structure:
    """The plate with its damping layer (see the module): M, C, K (CSR) of 2 side^2
    coordinates, the plate's first, the layer's next; a unit force at the free corner."""
    m = side * side
    scale = (side / 15.0) ** 2
    plate = 1e6 * scale * _stencil(side, held=True)
    ties = sp.bmat([[sp.identity(m), -sp.identity(m)], [-sp.identity(m), sp.identity(m)]])
    layer = sp.block_diag([sp.csr_matrix((m, m)), 3e5 * scale * _stencil(side, held=False)])
    damped = (layer + 1e6 * ties).tocsr()
    K = (sp.block_diag([plate, sp.csr_matrix((m, m))]) + damped).tocsr()
    M = sp.diags(np.concatenate([np.ones(m), np.full(m, mu)])).tocsr()
    C = (beta * damped).tocsr()
    b = np.zeros(2 * m, dtype=complex)
    b[m - 1] = 1.0
    return Structure("kelvin_voigt_plate", M, C, K, b, (50.0, 800.0),
                     f"{side} x {side} cantilever grid under a Kelvin-Voigt layer "
                     f"(beta = {beta:g} s): {m} overdamped modes near -1/beta")
