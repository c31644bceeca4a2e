"""A corpus of structures for the large-model paths, built by a real finite-element
assembler (scikit-fem) and by hand for the lumped ones.

Every builder takes a target number of coordinates ``n`` (from 10^2 up to
2.5 x 10^5; the structure's own discretisation rounds it) and returns a
:class:`Structure`: real sparse (CSR) M, C, K, a complex load b (a unit force at
one coordinate) and a frequency band covering its lowest resonances.  Nothing
is written unless asked: :func:`write_mtx` writes Matrix Market files and a
``[matrices]`` model beside them.

The structures, each with a different difficulty for the solvers:

``eb_beam``
    clamped-free Euler-Bernoulli beam, cubic Hermite elements (w and slope per
    node), C = 1.05 M (2 % damping in mode 1): cond(K) grows as n^4.
``timoshenko_beam``
    clamped-free Timoshenko beam (deflection and rotation, quadratic elements,
    shear-flexible), heavy Rayleigh damping (about 20 % in mode 1).
``plate``
    clamped Kirchhoff plate, Morley triangles (deflection at the vertices, normal
    slopes at the edge midpoints), light Rayleigh damping.
``solid``
    3-D cantilever block of trilinear hexahedra (elasticity), non-proportional
    damping: dashpots on the free face only.
``chain``
    spring-mass chain fixed at one end, light damping (0.1 % in mode 1).
``grid``
    2-D grid of masses and springs, supported at one edge, Rayleigh damping.
``beam_spring``
    the Euler-Bernoulli beam with a stiff local spring (10^6 times the largest
    diagonal stiffness: a near-rigid support) at mid-span.
``clustered``
    identical oscillators coupled by weak springs: their natural frequencies lie
    in a cluster 10^-4 wide (repeated in the limit).
``free_beam``
    free-free Euler-Bernoulli beam: two rigid-body modes (K singular), Rayleigh
    damping.
``stiff_chain``
    a chain whose spring stiffnesses span 12 decades (cond(K) about 10^12 and
    beyond), non-proportional damping (one dashpot).

Examples
--------
>>> s = build("chain", 200)
>>> s.n, s.M.shape, s.band[0] < s.band[1]
(200, (200, 200), True)
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

#: steel
YOUNG, DENSITY, POISSON = 210e9, 7850.0, 0.3


@dataclass(frozen=True)
class Structure:
    """One corpus model: K - w^2 M + i w C, load b, the band of its first resonances."""

    name: str
    M: Any
    C: Any
    K: Any
    b: np.ndarray
    band: tuple[float, float]
    description: str = ""
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def n(self) -> int:
        return int(self.M.shape[0])

    def matrix(self, w: float) -> Any:
        """A(w) = K - w^2 M + i w C (sparse CSC)."""
        return (self.K - (w * w) * self.M + (1j * w) * self.C).tocsc()


# -- helpers ------------------------------------------------------------------------------

def _lowest(M: Any, K: Any, count: int, shift: float) -> np.ndarray:
    """The ``count`` lowest natural frequencies (rad/s) by shift-invert Lanczos (dense
    for small models)."""
    n = M.shape[0]
    if n <= 600:
        import scipy.linalg

        lam = scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True,
                                subset_by_index=[0, min(count, n) - 1])
    else:
        from scipy.sparse.linalg import eigsh

        lam = np.sort(eigsh(K.tocsc(), k=count, M=M.tocsc(), sigma=shift,
                            return_eigenvectors=False))
    return np.sqrt(np.maximum(lam, 0.0))


def _band(M: Any, K: Any, modes: int = 4, shift: float = 0.0) -> tuple[float, float]:
    """From half the first elastic frequency to 1.2 times the ``modes``-th one."""
    w = _lowest(M, K, modes + 3, shift)
    elastic = w[w > 1e-3 * w.max()]
    return float(0.5 * elastic[0]), float(1.2 * elastic[min(modes, len(elastic)) - 1])


def _unit_load(n: int, at: int) -> np.ndarray:
    b = np.zeros(n, dtype=complex)
    b[at] = 1.0
    return b


def _free(A: Any, fixed: np.ndarray) -> Any:
    keep = np.setdiff1d(np.arange(A.shape[0]), fixed)
    return A[keep][:, keep].tocsr(), keep


def _hermite_beam(elements: int, clamped: bool) -> tuple[Any, Any, np.ndarray]:
    """M, K of a beam (1 m, 20 x 5 mm steel strip) of cubic Hermite elements (scikit-fem);
    the coordinates w_i, w'_i per node, the clamped node's removed when ``clamped``."""
    from skfem import Basis, BilinearForm, ElementLineHermite, MeshLine
    from skfem.helpers import dd

    width, thickness = 0.02, 0.005
    EI = YOUNG * width * thickness**3 / 12
    rho_A = DENSITY * width * thickness
    basis = Basis(MeshLine(np.linspace(0.0, 1.0, elements + 1)), ElementLineHermite())

    @BilinearForm
    def stiffness(u, v, _):
        return EI * dd(u)[0, 0] * dd(v)[0, 0]

    @BilinearForm
    def mass(u, v, _):
        return rho_A * u * v

    K, M = stiffness.assemble(basis), mass.assemble(basis)
    # coordinate order per node (w, w'), as the nodal dofs of the Hermite element
    order = basis.nodal_dofs.T.ravel()
    K, M = K[order][:, order].tocsr(), M[order][:, order].tocsr()
    if clamped:
        K, keep = _free(K, np.array([0, 1]))
        M, _ = _free(M, np.array([0, 1]))
    return M, K, order


# -- the structures -----------------------------------------------------------------------

def eb_beam(n: int) -> Structure:
    elements = max(2, n // 2)
    M, K, _ = _hermite_beam(elements, clamped=True)
    C = (1.05 * M).tocsr()
    size = M.shape[0]
    return Structure("eb_beam", M, C, K, _unit_load(size, size - 2), _band(M, K),
                     f"clamped-free Euler-Bernoulli beam, {elements} Hermite elements, "
                     "C = 1.05 M", {"elements": elements})


def beam_spring(n: int) -> Structure:
    s = eb_beam(n)
    size = s.n
    mid = 2 * (size // 4)  # a deflection coordinate near mid-span
    spring = 1e6 * float(s.K.diagonal().max())   # a near-rigid support
    K = (s.K + sp.csr_matrix(([spring], ([mid], [mid])), shape=s.K.shape)).tocsr()
    return Structure("beam_spring", s.M, s.C, K, s.b, _band(s.M, K),
                     "the Euler-Bernoulli beam (C = 1.05 M) with a stiff spring (1e6 times "
                     "the largest diagonal stiffness) at mid-span", {"spring_at": mid})


def free_beam(n: int) -> Structure:
    elements = max(2, n // 2 - 1)
    M, K, _ = _hermite_beam(elements, clamped=False)
    C = (0.5 * M + 2e-5 * K).tocsr()
    size = M.shape[0]
    return Structure("free_beam", M, C, K, _unit_load(size, size - 2),
                     _band(M, K, 4, shift=-1.0),
                     f"free-free Euler-Bernoulli beam, {elements} Hermite elements (two "
                     "rigid-body modes), Rayleigh damping", {"rigid_modes": 2})


def timoshenko_beam(n: int) -> Structure:
    """Deflection w and rotation theta, quadratic Lagrange elements each (shear locking
    is mild for this thickness at quadratic order)."""
    from skfem import Basis, BilinearForm, ElementComposite, ElementLineP2, MeshLine
    from skfem.helpers import grad

    elements = max(2, n // 4)
    width, depth, length = 0.02, 0.05, 1.0       # a deep section: shear matters
    A, I_ = width * depth, width * depth**3 / 12
    G = YOUNG / (2 * (1 + POISSON))
    kappa = 5.0 / 6.0
    basis = Basis(MeshLine(np.linspace(0.0, length, elements + 1)),
                  ElementComposite(ElementLineP2(), ElementLineP2()))

    @BilinearForm
    def stiffness(w, t, v, s, _):
        return (YOUNG * I_ * grad(t)[0] * grad(s)[0]
                + kappa * G * A * (grad(w)[0] - t) * (grad(v)[0] - s))

    @BilinearForm
    def mass(w, t, v, s, _):
        return DENSITY * A * w * v + DENSITY * I_ * t * s

    K, M = stiffness.assemble(basis), mass.assemble(basis)
    fixed = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    K, keep = _free(K, fixed)
    M, _ = _free(M, fixed)
    # the tip's deflection: the first field's dof at x = L
    tip_dofs = basis.get_dofs(lambda x: np.isclose(x[0], length)).all()
    tip = int(np.flatnonzero(np.isin(keep, tip_dofs))[0])
    w1 = _lowest(M, K, 1, 0.0)[0]
    zeta = 0.2
    C = (zeta * w1 * M + zeta / w1 * K).tocsr()  # 20 % at mode 1 (Rayleigh)
    return Structure("timoshenko_beam", M, C, K, _unit_load(M.shape[0], tip), _band(M, K),
                     f"clamped-free Timoshenko beam, {elements} quadratic elements, heavy "
                     "Rayleigh damping (20 % in mode 1)", {"elements": elements})


def plate(n: int) -> Structure:
    """A clamped square steel plate (0.5 m, 2 mm), Morley triangles."""
    from skfem import Basis, BilinearForm, ElementTriMorley, MeshTri
    from skfem.helpers import dd, ddot, trace

    # a refined mesh of 2 x 4^k triangles has about 3 x 2 x 4^k / 2 + ... dofs: pick k
    refine = 1
    while 3 * 2 * 4 ** (refine + 1) // 2 <= n and refine < 10:
        refine += 1
    mesh = MeshTri.init_symmetric().refined(refine).scaled(0.5)
    basis = Basis(mesh, ElementTriMorley())
    t = 0.002
    D = YOUNG * t**3 / (12 * (1 - POISSON**2))

    @BilinearForm
    def stiffness(u, v, _):
        return D * ((1 - POISSON) * ddot(dd(u), dd(v)) + POISSON * trace(dd(u)) * trace(dd(v)))

    @BilinearForm
    def mass(u, v, _):
        return DENSITY * t * u * v

    K, M = stiffness.assemble(basis), mass.assemble(basis)
    fixed = basis.get_dofs().all()   # clamped: deflection and normal slope on the boundary
    K, keep = _free(K, fixed)
    M, _ = _free(M, fixed)
    # load at the vertex nearest to (0.15, 0.2)
    vertex = int(np.argmin(np.hypot(mesh.p[0] - 0.15, mesh.p[1] - 0.2)))
    dof = basis.nodal_dofs[0, vertex]
    at = int(np.flatnonzero(keep == dof)[0])
    C = (2.0 * M + 1e-6 * K).tocsr()
    return Structure("plate", M, C, K, _unit_load(M.shape[0], at), _band(M, K),
                     f"clamped Kirchhoff plate, Morley triangles ({mesh.t.shape[1]} "
                     "elements), light Rayleigh damping", {"refine": refine})


def solid(n: int) -> Structure:
    """A steel cantilever block 0.4 x 0.1 x 0.1 m of trilinear hexahedra, clamped at x = 0;
    dashpots (normal and tangential) on every node of the free face."""
    from skfem import Basis, BilinearForm, ElementHex1, ElementVector, MeshHex
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    # nodes (4 m + 1)(m + 1)^2, 3 dofs each
    m = 1
    while 3 * (4 * (m + 1) + 1) * (m + 2) ** 2 <= n:
        m += 1
    mesh = MeshHex.init_tensor(np.linspace(0, 0.4, 4 * m + 1), np.linspace(0, 0.1, m + 1),
                               np.linspace(0, 0.1, m + 1))
    basis = Basis(mesh, ElementVector(ElementHex1()))
    K = linear_elasticity(*lame_parameters(YOUNG, POISSON)).assemble(basis)

    @BilinearForm
    def mass(u, v, _):
        return DENSITY * (u[0] * v[0] + u[1] * v[1] + u[2] * v[2])

    M = mass.assemble(basis)
    fixed = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    free_face = basis.get_dofs(lambda x: np.isclose(x[0], 0.4)).all()
    c = np.zeros(K.shape[0])
    c[free_face] = 50.0
    C = sp.diags(c).tocsr()
    K, keep = _free(K, fixed)
    M, _ = _free(M, fixed)
    C, _ = _free(C, fixed)
    corner = int(np.argmin(np.hypot(np.hypot(mesh.p[0] - 0.4, mesh.p[1] - 0.1),
                                    mesh.p[2] - 0.1)))
    dof = basis.nodal_dofs[2, corner]  # z-displacement of the free corner
    at = int(np.flatnonzero(keep == dof)[0])
    return Structure("solid", M, C, K, _unit_load(M.shape[0], at), _band(M, K, 3),
                     f"3-D cantilever block, {mesh.t.shape[1]} trilinear hexahedra, "
                     "dashpots on the free face (non-proportional damping)", {"m": m})


def chain(n: int) -> Structure:
    k, m = 1e4, 1.0
    main = np.full(n, 2 * k)
    main[-1] = k
    K = sp.diags([np.full(n - 1, -k), main, np.full(n - 1, -k)], [-1, 0, 1], format="csr")
    M = sp.identity(n, format="csr") * m
    w1 = _lowest(M, K, 1, 0.0)[0]
    C = (2 * 1e-3 * w1 * M).tocsr()   # 0.1 % in mode 1
    return Structure("chain", M, C, K, _unit_load(n, n - 1), _band(M, K),
                     "spring-mass chain fixed at one end, light damping (0.1 % in mode 1)")


def grid(n: int) -> Structure:
    side = max(2, int(round(np.sqrt(n))))
    size = side * side
    k = 1e4
    line = sp.diags([np.full(side - 1, -1.0), np.full(side, 2.0), np.full(side - 1, -1.0)],
                    [-1, 0, 1])
    eye = sp.identity(side)
    K = (k * (sp.kron(line, eye) + sp.kron(eye, line))).tocsr()
    # supported at one edge only: the other edges free (Neumann: diagonal 1 at the ends)
    free_line = line.tolil()
    free_line[side - 1, side - 1] = 1.0
    free_line[0, 0] = 1.0
    K = (k * (sp.kron(line, eye) + sp.kron(eye, free_line.tocsr()))).tocsr()
    M = sp.identity(size, format="csr")
    C = (0.1 * M + 1e-5 * K).tocsr()
    return Structure("grid", M, C, K, _unit_load(size, size - 1), _band(M, K),
                     f"{side} x {side} grid of masses, Rayleigh damping")


def clustered(n: int) -> Structure:
    """n unit masses on springs k to the ground, each coupled to the next by eps k: the
    n natural frequencies fill sqrt(k (1 .. 1 + 4 eps)/m), a cluster 2 eps wide."""
    k, eps = 1e4, 1e-4
    main = np.full(n, k * (1 + 2 * eps))
    main[[0, -1]] = k * (1 + eps)
    K = sp.diags([np.full(n - 1, -eps * k), main, np.full(n - 1, -eps * k)], [-1, 0, 1],
                 format="csr")
    M = sp.identity(n, format="csr")
    C = (0.02 * M).tocsr()   # 0.01 % of critical: resonances sharper than the cluster
    w0 = np.sqrt(k)
    return Structure("clustered", M, C, K, _unit_load(n, 0), (0.98 * w0, 1.02 * w0),
                     "weakly coupled identical oscillators: a cluster of n natural "
                     "frequencies 2e-4 wide, light damping")


def stiff_chain(n: int) -> Structure:
    """Springs from 1 to 1e12 (log-spaced) in a chain fixed at one end; masses 1; a dashpot
    at the free end only (non-proportional)."""
    k = np.logspace(0, 12, n)
    main = k.copy()
    main[:-1] += k[1:]
    K = sp.diags([-k[1:], main, -k[1:]], [-1, 0, 1], format="csr")
    M = sp.identity(n, format="csr")
    c = np.zeros(n)
    c[-1] = 0.5
    C = sp.diags(c).tocsr()
    return Structure("stiff_chain", M, C, K, _unit_load(n, n - 1), _band(M, K, 3),
                     "chain with springs from 1 to 1e12 N/m (cond(K) about 1e12 and beyond), "
                     "one dashpot (non-proportional damping)")


#: name -> builder(n)
BUILDERS: dict[str, Callable[[int], Structure]] = {
    "eb_beam": eb_beam, "timoshenko_beam": timoshenko_beam, "plate": plate, "solid": solid,
    "chain": chain, "grid": grid, "beam_spring": beam_spring, "clustered": clustered,
    "free_beam": free_beam, "stiff_chain": stiff_chain,
}


def build(name: str, n: int) -> Structure:
    """The corpus structure ``name`` with about ``n`` coordinates (100 to 250,000)."""
    if name not in BUILDERS:
        raise KeyError(f"no corpus structure {name!r}; choose one of {sorted(BUILDERS)}")
    if not 10 <= n <= 250_000:
        raise ValueError("n must be between 10 and 250000")
    return BUILDERS[name](n)


# -- references: a sparse LU refined with residuals in double-double arithmetic -------------

def _split(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    c = 134217729.0 * a          # Dekker's split, 2^27 + 1
    hi = c - (c - a)
    return hi, a - hi


def _two_prod(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _two_sum(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def _dd_add(x: tuple[np.ndarray, np.ndarray], y: tuple[np.ndarray, np.ndarray]
            ) -> tuple[np.ndarray, np.ndarray]:
    s, e = _two_sum(x[0], y[0])
    e = e + x[1] + y[1]
    return _two_sum(s, e)


def _dd_scale(c: float, x: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    p, e = _two_prod(np.full_like(x[0], c), x[0])
    return _two_sum(p, e + c * x[1])


def _dd_matvec(A: Any, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A x (A real CSR, x real) in double-double: every product exact, sums compensated."""
    A = A.tocsr()
    n = A.shape[0]
    hi, lo = np.zeros(n), np.zeros(n)
    lengths = np.diff(A.indptr)
    for k in range(int(lengths.max(initial=0))):
        rows = np.flatnonzero(lengths > k)
        at = A.indptr[rows] + k
        p, e = _two_prod(A.data[at], x[A.indices[at]])
        s, t = _two_sum(hi[rows], p)
        hi[rows], lo[rows] = _two_sum(s, t + lo[rows] + e)
    return hi, lo


def exact_residual(structure: Structure, w: float, x: np.ndarray) -> np.ndarray:
    """b - (K - w^2 M + i w C) x with M, C, K, w as given (not A(w) rounded), in
    double-double arithmetic, rounded to double."""
    w2 = _two_prod(np.array([w]), np.array([w]))
    parts = []
    for sign, (xr, xi) in ((1, (x.real, x.imag)), (1j, (x.imag, -x.real))):
        # real part: b_re - K x_re + w^2 M x_re + w C x_im; imaginary likewise with
        # (x_im, -x_re) for (x_re, x_im)
        Kx = _dd_matvec(structure.K, xr)
        Mx = _dd_matvec(structure.M, xr)
        Cx = _dd_matvec(structure.C, xi)
        # w^2 M x with w^2 = w2[0] + w2[1] (double-double)
        wMx = _dd_add(_dd_scale(float(w2[0][0]), Mx), (float(w2[1][0]) * Mx[0], 0 * Mx[0]))
        total = _dd_add(_dd_add((-Kx[0], -Kx[1]), wMx), _dd_scale(w, Cx))
        b = structure.b.real if sign == 1 else structure.b.imag
        total = _dd_add(total, (b, np.zeros_like(b)))
        parts.append(total[0] + total[1])
    return parts[0] + 1j * parts[1]


def reference(structure: Structure, w: np.ndarray, refinements: int = 4) -> np.ndarray:
    """The responses at the frequencies w, (N, n): SuperLU (partial pivoting) with
    iterative refinement on residuals in double-double arithmetic, to about the
    double rounding of the solution (the refinement converges for cond(A) eps < 1:
    Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., Sect. 12.1)."""
    from scipy.sparse.linalg import splu

    out = np.empty((len(w), structure.n), dtype=complex)
    for i, wi in enumerate(np.asarray(w, dtype=float)):
        lu = splu(structure.matrix(wi))
        x = lu.solve(structure.b)
        for _ in range(refinements):
            d = lu.solve(exact_residual(structure, float(wi), x))
            x = x + d
            if np.linalg.norm(d) <= 1e-17 * np.linalg.norm(x):
                break
        out[i] = x
    return out


def write_mtx(structure: Structure, directory: str | Path) -> Path:
    """M.mtx, C.mtx, K.mtx, b.npy and a ``[matrices]`` model ``{name}.toml`` in
    ``directory``; the path of the model."""
    import scipy.io

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    for name in ("M", "C", "K"):
        scipy.io.mmwrite(directory / f"{name}.mtx", getattr(structure, name).tocoo())
    at = int(np.flatnonzero(structure.b)[0])
    path = directory / f"{structure.name}.toml"
    path.write_text(
        f'title = "{structure.description}"\n\n[parameters]\nF0 = 1\nomega = '
        f"{structure.band[0]:.6g}\n\n[matrices]\n"
        'M = "M.mtx"\nC = "C.mtx"\nK = "K.mtx"\n\n[[harmonic]]\nomega = "omega"\n'
        f'F_C = {{ q{at + 1} = "F0" }}\n', encoding="utf-8")
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="write a corpus structure as .mtx files")
    parser.add_argument("name", choices=sorted(BUILDERS))
    parser.add_argument("n", type=int)
    parser.add_argument("directory")
    args = parser.parse_args(argv)
    print(write_mtx(build(args.name, args.n), args.directory))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
