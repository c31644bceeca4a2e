"""Complex modes of a heavily damped structure: the modal kernel's search along the
imaginary axis against scipy's shift-invert Arnoldi by hand.

The structure (``damped_layer.kelvin_voigt_plate``): a cantilever grid under a strong
Kelvin-Voigt layer, 2 side^2 coordinates (4,050 at the default side 45), whose side^2
overdamped layer modes cluster near s = -400 s^-1, below the structural modes from the
fourth on.

Three routes to the ``count`` complex modes of lowest damped frequency, timed (median of
``--repeats``, one BLAS thread):

- ``resonant``: :func:`resonant.modal.lowest_state_eigenvalues` (shifts along the
  imaginary axis chosen by the kernel, one n x n sparse LU each);
- ``by hand``: :func:`scipy.sparse.linalg.eigs` on the 2n x 2n state pencil
  A x = s B x with ``sigma`` = i y at the shifts y a user who knows the band would pick
  (``--band`` split into ``--slices`` shifts, ``k`` = ``count`` + 8 each), the union
  sorted by Im s: the reference;
- ``by |s|``: the same eigs with one real shift just left of 0 and k = 2 count (the
  search by modulus the kernel made before): how many of the ``count`` modes it finds.

Usage::

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/bench_complex_modes.py
    python benchmarks/bench_complex_modes.py --side 15 --repeats 1     # 450 coordinates
"""

from __future__ import annotations

import argparse
import os

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from common import median_time  # noqa: E402
from damped_layer import kelvin_voigt_plate  # noqa: E402
from scipy.sparse.linalg import eigs  # noqa: E402

from resonant.modal import lowest_state_eigenvalues  # noqa: E402


def _pencil(M: sp.csr_matrix, C: sp.csr_matrix, K: sp.csr_matrix
            ) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    n = M.shape[0]
    eye = sp.identity(n, format="csc")
    A = sp.bmat([[None, eye], [-K, -C]], format="csc")
    B = sp.bmat([[eye, None], [None, M]], format="csc")
    return A, B


def by_hand(M: sp.csr_matrix, C: sp.csr_matrix, K: sp.csr_matrix, count: int,
            shifts: np.ndarray) -> np.ndarray:
    """The ``count`` underdamped eigenvalues of lowest Im s from eigs at ``sigma`` = i y."""
    A, B = (a.astype(complex) for a in _pencil(M, C, K))   # complex shifts: complex ARPACK
    start = np.random.default_rng(0).standard_normal(A.shape[0]).astype(complex)
    found = [eigs(A, k=count + 8, M=B, sigma=1j * y, v0=start, return_eigenvectors=False)
             for y in shifts]
    s = np.concatenate(found)
    s = s[s.imag > 1e-8 * np.abs(s)]
    s = s[np.argsort(s.imag)]
    keep = np.concatenate([[True], np.abs(np.diff(s)) > 1e-9 * np.abs(s[1:])])
    result: np.ndarray = s[keep][:count]
    return result


def by_modulus(M: sp.csr_matrix, C: sp.csr_matrix, K: sp.csr_matrix, count: int
               ) -> np.ndarray:
    """The 2 count eigenvalues nearest a small negative real shift (the search by |s|)."""
    A, B = _pencil(M, C, K)
    sigma = -1e-6 * float(np.sqrt(abs(K).sum() / abs(M).sum()))
    start = np.random.default_rng(0).standard_normal(A.shape[0])
    result: np.ndarray = eigs(A, k=2 * count, M=B, sigma=sigma, v0=start,
                              return_eigenvectors=False)
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--side", type=int, default=45)
    parser.add_argument("--count", type=int, default=10)
    parser.add_argument("--band", type=float, nargs=2, default=(100.0, 800.0))
    parser.add_argument("--slices", type=int, default=4)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    plate = kelvin_voigt_plate(args.side)
    M, C, K = plate.M, plate.C, plate.K
    ours, search, _ = median_time(lambda: lowest_state_eigenvalues(M, C, K, args.count),
                                  args.repeats)
    shifts = np.linspace(args.band[0], args.band[1], args.slices)
    hand, reference, _ = median_time(lambda: by_hand(M, C, K, args.count, shifts),
                                     args.repeats)
    modulus = by_modulus(M, C, K, args.count)
    found = search.eigenvalues[search.eigenvalues.imag > 0]
    found = found[np.argsort(found.imag)]
    error = float(np.max(np.abs(found - reference) / np.abs(reference)))
    hits = sum(bool(np.min(np.abs(modulus - v)) <= 1e-8 * abs(v)) for v in reference)
    print(f"{plate.n} coordinates, the {args.count} complex modes of lowest damped "
          f"frequency ({plate.description})")
    print(f"zeta {np.round(-reference.real / np.abs(reference), 3).tolist()}")
    print(f"Im s {np.round(reference.imag, 2).tolist()}")
    print("| n | resonant | shifts | eigs by hand | ratio | max rel. difference | "
          "by abs(s): found | reach |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    print(f"| {plate.n:,} | {ours:.2f} s | {search.shifts.size} | {hand:.2f} s "
          f"({args.slices} shifts) | {ours / hand:.2f}x | {error:.1e} | "
          f"{hits} of {args.count} | zeta {search.reach:.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
