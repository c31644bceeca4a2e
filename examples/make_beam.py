"""Write a cantilever beam of Euler-Bernoulli elements as a ``[matrices]`` model with a
nonlinear element at its tip.

    python examples/make_beam.py DIRECTORY [--elements 20] [--tip cubic|gap|both]

writes ``DIRECTORY/beam{n}.toml`` with ``M.npz``, ``C.npz`` and ``K.npz``
(``scipy.sparse.save_npz``) beside it, n = 2 x elements coordinates:

    clamped |=====================================| <- F0 cos(omega t), tip spring or stop

a steel strip 1 m long, 20 mm wide, 5 mm thick (E = 210 GPa, rho = 7850 kg/m^3), two
coordinates per node (deflection w and slope theta: q1 = w_1, q2 = theta_1, ...,
q_{n-1} = w at the tip), the cubic Hermite element's stiffness and consistent mass
(Przemieniecki, Theory of Matrix Structural Analysis, 1968, Sect. 5.6 and 11.3), Rayleigh
damping C = a M + b K.  The first natural frequency of the cantilever is (Rao,
Mechanical Vibrations, Sect. 8.5)

    omega_1 = 1.8751^2 sqrt(E I / (rho A L^4)) = 26.25 rad/s,

which the element model approaches from above (0.01 % with 10 elements).

At the tip, ``--tip cubic``: a hardening spring ``k3 q_tip^3`` to the ground;
``--tip gap``: a stop at clearance ``g`` of stiffness ``kc`` (contact only when the tip
moves up by more than g); ``both``: the spring at the tip and the stop at mid-span.  ``resonant sweep beam40.toml --nonlinear
--param omega --from 15 --to 40`` follows the periodic response by the harmonic
balance condensed onto the tip.  The files are generated rather than committed.
"""

from __future__ import annotations

import argparse
from pathlib import Path

LENGTH = 1.0          # m
WIDTH, THICKNESS = 0.02, 0.005
YOUNG = 210e9         # Pa
DENSITY = 7850.0      # kg/m^3
RAYLEIGH = (0.5, 1e-5)


def element_matrices(length: float, EI: float, rho_A: float):
    """Stiffness and consistent mass of one Euler-Bernoulli element (w1, t1, w2, t2)."""
    import numpy as np

    L = length
    k = EI / L**3 * np.array([[12, 6 * L, -12, 6 * L],
                              [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                              [-12, -6 * L, 12, -6 * L],
                              [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
    m = rho_A * L / 420 * np.array([[156, 22 * L, 54, -13 * L],
                                    [22 * L, 4 * L * L, 13 * L, -3 * L * L],
                                    [54, 13 * L, 156, -22 * L],
                                    [-13 * L, -3 * L * L, -22 * L, 4 * L * L]])
    return k, m


def beam_matrices(elements: int):
    """Sparse (CSR) M, C, K of the clamped-free beam (the clamped node's two
    coordinates removed), 2 x elements coordinates."""
    import numpy as np
    import scipy.sparse as sp

    EI = YOUNG * WIDTH * THICKNESS**3 / 12
    rho_A = DENSITY * WIDTH * THICKNESS
    k, m = element_matrices(LENGTH / elements, EI, rho_A)
    rows, cols = np.meshgrid(np.arange(4), np.arange(4), indexing="ij")
    first = 2 * np.arange(elements)          # global index of each element's w1
    I = (first[:, None, None] + rows).ravel()
    J = (first[:, None, None] + cols).ravel()
    size = 2 * (elements + 1)
    K = sp.coo_matrix((np.tile(k.ravel(), elements), (I, J)), shape=(size, size)).tocsr()
    M = sp.coo_matrix((np.tile(m.ravel(), elements), (I, J)), shape=(size, size)).tocsr()
    K, M = K[2:, 2:], M[2:, 2:]
    C = (RAYLEIGH[0] * M + RAYLEIGH[1] * K).tocsr()
    return M.tocsr(), C, K.tocsr()


WHAT = {"cubic": "a cubic spring at the tip", "gap": "a stop at the tip",
        "both": "a cubic spring at the tip, a stop at mid-span"}
TIP_ELEMENTS = {
    "cubic": ('[[nonlinear]]\nname = "tip spring"\ncoordinates = ["{tip}"]\n'
              'force = "k3*{tip}^3"\n'),
    "gap": ('[[nonlinear]]\nname = "stop"\ncoordinates = ["{at}"]\nkind = "gap"\n'
            'gap = "g"\nstiffness = "kc"\n'),
}


def write_beam(directory: str | Path, elements: int = 20, tip: str = "cubic") -> Path:
    """Write the model and its matrix files; return the path of the model file."""
    import scipy.sparse as sp

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    M, C, K = beam_matrices(elements)
    n = M.shape[0]
    for name, matrix in (("M", M), ("C", C), ("K", K)):
        sp.save_npz(directory / f"{name}.npz", matrix)
    tip_name = f"q{n - 1}"
    # with both elements the stop sits at mid-span (two nonlinear coordinates)
    stop_name = f"q{2 * (elements // 2) - 1}" if tip == "both" and elements >= 2 else tip_name
    kinds = ["cubic", "gap"] if tip == "both" else [tip]
    force = ", ".join(["0"] * (n - 2) + ['"F0"', "0"])
    path = directory / f"beam{n}.toml"
    path.write_text(
        f'title = "Cantilever beam, {elements} Euler-Bernoulli elements, {WHAT[tip]}"\n\n'
        "[parameters]\n"
        "F0 = 0.1        # N, force at the tip\n"
        "omega = 20      # rad/s, excitation frequency\n"
        "k3 = 5e4        # N/m^3, cubic spring at the tip\n"
        f"g = {0.004 if tip == 'both' else 0.01}       # m, clearance of the stop\n"
        "kc = 500        # N/m, stiffness of the stop\n\n"
        "[matrices]\n"
        'M = "M.npz"\n'
        'C = "C.npz"\n'
        'K = "K.npz"\n\n'
        "[[harmonic]]\n"
        'omega = "omega"\n'
        f"F_C = [{force}]\n\n"
        + "\n".join(TIP_ELEMENTS[k].format(tip=tip_name, at=stop_name) for k in kinds),
        encoding="utf-8")
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", help="where to write the model and matrix files")
    parser.add_argument("--elements", type=int, default=20,
                        help="number of beam elements (default 20)")
    parser.add_argument("--tip", choices=["cubic", "gap", "both"], default="cubic",
                        help="the nonlinear element at the tip (default cubic)")
    args = parser.parse_args(argv)
    if not 1 <= args.elements <= 10**6:
        parser.error("--elements must be between 1 and 1000000")
    print(write_beam(args.directory, args.elements, args.tip))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
