"""Write a large fixed-free chain as a ``[matrices]`` model with sparse matrix files.

    python examples/make_chain.py DIRECTORY [--n 1000]

writes ``DIRECTORY/chain{n}.toml`` with ``K.mtx`` (Matrix Market), ``M.npz`` and
``C.npz`` (``scipy.sparse.save_npz``) beside it:

    ground --k-- m --k-- m ... --k-- m  <- F0 sin(omega t)

masses m = 1 kg, springs k = 1e4 N/m, Rayleigh damping C = 0.1 M + 1e-4 K, the force
at the free end.  The undamped natural frequencies are (Rao, Mechanical Vibrations,
Sect. 6; Meirovitch, Fundamentals of Vibrations, Sect. 8)

    omega_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2n + 1))),  j = 1..n.

The files are generated rather than committed (they are large).
"""

from __future__ import annotations

import argparse
from pathlib import Path

MASS = 1.0
STIFFNESS = 1e4
RAYLEIGH = (0.1, 1e-4)


def chain_matrices(n: int, m: float = MASS, k: float = STIFFNESS,
                   rayleigh: tuple[float, float] = RAYLEIGH):
    """Sparse (CSR) M, C, K of the fixed-free chain of n masses."""
    import numpy as np
    import scipy.sparse as sp

    main = np.full(n, 2 * k)
    main[-1] = k
    off = np.full(n - 1, -k)
    K = sp.diags([off, main, off], [-1, 0, 1], format="csr")
    M = sp.identity(n, format="csr") * m
    C = (rayleigh[0] * M + rayleigh[1] * K).tocsr()
    return M, C, K


def write_chain(directory: str | Path, n: int = 1000, omega: float = 50.0) -> Path:
    """Write the model and its matrix files; return the path of the model file."""
    import scipy.io
    import scipy.sparse as sp

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    M, C, K = chain_matrices(n)
    scipy.io.mmwrite(str(directory / "K.mtx"), K.tocoo(), comment="fixed-free chain stiffness")
    sp.save_npz(directory / "M.npz", M.tocsr())
    sp.save_npz(directory / "C.npz", C.tocsr())
    force = ", ".join(["0"] * (n - 1) + ['"F0"'])
    path = directory / f"chain{n}.toml"
    path.write_text(
        f'title = "Fixed-free chain of {n} masses (m = {MASS}, k = {STIFFNESS}, '
        f'C = {RAYLEIGH[0]} M + {RAYLEIGH[1]} K)"\n\n'
        "[parameters]\n"
        "F0 = 1          # N, force at the free end\n"
        f"omega = {omega}   # rad/s, excitation frequency\n\n"
        "[matrices]\n"
        'M = "M.npz"\n'
        'C = "C.npz"\n'
        'K = "K.mtx"\n\n'
        "[[harmonic]]\n"
        'omega = "omega"\n'
        f"F_S = [{force}]\n", encoding="utf-8")
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", help="where to write the model and matrix files")
    parser.add_argument("--n", type=int, default=1000, help="number of masses (default 1000)")
    parser.add_argument("--omega", type=float, default=50.0, help="excitation frequency")
    args = parser.parse_args(argv)
    if args.n < 2:
        parser.error("--n must be at least 2")
    print(write_chain(args.directory, args.n, args.omega))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
