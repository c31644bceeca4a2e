"""Checks of a model read from a finite-element code, before it is trusted.

:func:`check_matrices` looks at M and K as a structural engineer would on receiving
them: the mass matrix is there and not zero (with which analysis writes one, when it is
missing), M and K are symmetric, M is positive definite (or semi-definite: which
coordinates carry no mass), K is positive semi-definite and its rigid-body modes (the
zero eigenvalues: six for a free structure, fewer for a constrained one), and, from the
coordinates named by node and direction (``n1042_uz``, :mod:`resonant.model.op4_files`),
a rigid-body check (as pyYeti's ``cbcheck`` does for a Craig-Bampton model): the unit
translations and rotations of the nodes give the 6 x 6 rigid-body mass about the origin,
hence the total mass, the centre of gravity and the inertia about it, and the forces
``K T`` a rigid motion leaves (zero for a free structure).  Eigenvalues come from the
modal kernel (:func:`resonant.modal.symmetric_eigenvalues`).

Examples
--------
>>> import numpy as np
>>> from resonant.system.base import NumericEOM
>>> names = ("n1_ux", "n2_ux")
>>> system = NumericEOM(names, np.diag([1.0, 1.0]), np.zeros((2, 2)),
...                     np.array([[1.0, -1.0], [-1.0, 1.0]]))
>>> checks = check_matrices(system)
>>> checks.rigid_body_modes, checks.mass_by_direction["x"]
(1, 2.0)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import Matrix, freeze_fields
from ..memory import dense_matrix
from ..modal import ZERO_EIGENVALUE, symmetric_eigenvalues
from ..model.op4_files import dof_of
from ..system.base import LinearSystem, NumericEOM
from .result_fields import FieldsJSON, saved

#: dense eigenvalues of M and K are computed up to this many coordinates
MAX_DENSE_CHECK = 3000
#: relative asymmetry max|A - A^T| / max|A| above which a matrix is called unsymmetric
SYMMETRY_TOLERANCE = 1e-10
#: where the mass matrix comes from, for the message when it is missing
MASS_SOURCES = ("Nastran writes the mass matrix in a modal or dynamic solution (SOL 103, "
                "SOL 111/112, or EXTSEOUT) with PARAM,EXTOUT or OUTPUT4 of MGG/MAA; ANSYS "
                "writes it to the .full file only in a modal, harmonic or transient "
                "analysis (ANTYPE,MODAL), never in a static one; Abaqus in a *MATRIX "
                "GENERATE step with MASS")
#: max |K T| / max |K| of a rigid translation above which the structure is not free
RIGID_FORCE_TOLERANCE = 1e-8


@dataclass(frozen=True)
class MatrixChecks(FieldsJSON):
    """What :func:`~resonant.analyses.fe_checks.check_matrices` found.

    Parameters
    ----------
    n : int
        The number of coordinates.
    mass_present : bool
        False for a missing or zero mass matrix.
    asymmetry : mapping
        ``"M"``, ``"K"`` -> max |A - A^T| / max |A|.
    mass_eigenvalues : tuple of float
        The smallest and largest eigenvalue of M (empty above :data:`MAX_DENSE_CHECK`).
    massless : tuple of str
        Coordinates without mass (a zero row and column of M).
    stiffness_eigenvalues : tuple of float
        The smallest and largest eigenvalue of K (empty above :data:`MAX_DENSE_CHECK`).
    rigid_body_modes : int or None
        The zero eigenvalues of K (None when not computed).
    mass_by_direction : mapping
        ``"x"``, ``"y"``, ``"z"`` -> T^T M T of the unit translation (0 without such DOFs).
    rigid_body_mass : ndarray or None
        The 6 x 6 rigid-body mass about the origin (with node positions).
    centre_of_gravity : tuple of float or None
        From the rigid-body mass.
    inertia : ndarray or None
        3 x 3 inertia about the centre of gravity.
    rigid_body_forces : mapping
        Translation direction -> max |K T| / max |K| (0 for a free structure).
    problems : tuple of str
        What is wrong (the model should not be trusted).
    notes : tuple of str
        What a user should know.

    Examples
    --------
    >>> import numpy as np
    >>> from resonant.system.base import NumericEOM
    >>> system = NumericEOM(("q1",), np.zeros((1, 1)), np.zeros((1, 1)), np.eye(1))
    >>> check_matrices(system).problems[0][:35]
    'the mass matrix M is zero: no analy'
    >>> saved = check_matrices(system).to_dict()    # saved by its fields (FieldsJSON)
    >>> saved["ok"], MatrixChecks.from_dict(saved).massless
    (False, ('q1',))
    """

    n: int = saved()
    mass_present: bool = saved()
    asymmetry: Mapping[str, float] = saved()
    mass_eigenvalues: tuple[float, ...] = saved(())
    massless: tuple[str, ...] = saved(())
    stiffness_eigenvalues: tuple[float, ...] = saved(())
    rigid_body_modes: int | None = saved(None)
    mass_by_direction: Mapping[str, float] = saved(default_factory=dict)
    rigid_body_mass: np.ndarray | None = saved(None, axes=(6, 6))
    centre_of_gravity: tuple[float, float, float] | None = saved(None)
    inertia: np.ndarray | None = saved(None, axes=(3, 3))
    rigid_body_forces: Mapping[str, float] = saved(default_factory=dict)
    problems: tuple[str, ...] = saved(())
    notes: tuple[str, ...] = saved(())

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def ok(self) -> bool:
        """True when nothing is wrong."""
        return not self.problems

    def _derived_json(self) -> dict[str, Any]:
        return {"ok": self.ok}

    def summary(self) -> str:
        """The report a user reads before trusting the model.

        Returns
        -------
        str

        Examples
        --------
        >>> import numpy as np
        >>> from resonant.system.base import NumericEOM
        >>> system = NumericEOM(("q1",), np.eye(1), np.zeros((1, 1)), np.eye(1))
        >>> print(check_matrices(system).summary().splitlines()[0])
        model checks: 1 coordinates, nothing wrong
        """
        head = "nothing wrong" if self.ok else f"{len(self.problems)} problem(s)"
        lines = [f"model checks: {self.n} coordinates, {head}"]
        lines += [f"  problem: {p}" for p in self.problems]
        lines.append("  symmetry: " + ", ".join(f"{k} {v:.1e}"
                                                for k, v in self.asymmetry.items()))
        if self.mass_eigenvalues:
            lines.append(f"  M eigenvalues: {self.mass_eigenvalues[0]:.6g} .. "
                         f"{self.mass_eigenvalues[1]:.6g}")
        if self.stiffness_eigenvalues:
            lines.append(f"  K eigenvalues: {self.stiffness_eigenvalues[0]:.6g} .. "
                         f"{self.stiffness_eigenvalues[1]:.6g}; rigid-body modes: "
                         f"{self.rigid_body_modes}")
        if self.mass_by_direction:
            lines.append("  mass by translation: " + ", ".join(
                f"{k} {v:.7g}" for k, v in self.mass_by_direction.items()))
        if self.rigid_body_forces:
            lines.append("  |K T| / |K| of a rigid translation: " + ", ".join(
                f"{k} {v:.1e}" for k, v in self.rigid_body_forces.items()))
        if self.centre_of_gravity is not None and self.inertia is not None:
            cg = ", ".join(f"{v:.7g}" for v in self.centre_of_gravity)
            lines.append(f"  centre of gravity: ({cg})")
            lines.append("  inertia about it: " + "; ".join(
                ", ".join(f"{v:.7g}" for v in row) for row in self.inertia))
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)


def _asymmetry(a: Matrix) -> float:
    scale = abs(a).max()
    if scale == 0:
        return 0.0
    return float(abs(a - a.T).max() / scale)


def _parse_dof(name: str) -> tuple[int, int] | None:
    """(node, direction 0..5) of ``n1042_uz``; None for other names (scalar points)."""
    dof = dof_of(name)
    return (dof[0], dof[1] - 1) if dof is not None and dof[1] else None


def rigid_body_modes(coordinates: Sequence[str],
                     nodes: Mapping[int, Sequence[float]] | None = None,
                     frames: Mapping[int, Any] | None = None) -> np.ndarray:
    """The n x 6 rigid-body motions (x, y, z translations, then rotations about the
    origin) of coordinates named by node and direction; rows of other names are zero.

    Parameters
    ----------
    coordinates : sequence of str
        ``n<node>_<ux|uy|uz|rx|ry|rz>`` names.
    nodes : mapping, optional
        node -> (x, y, z) in the basic system; without them the rotations are zero
        columns beyond the rotation DOFs themselves (translations need no positions).
    frames : mapping, optional
        node -> 3 x 3 matrix whose rows are the node's output axes in the basic system
        (Nastran's CD coordinate system); default the basic axes.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> rigid_body_modes(["n1_uy"], {1: (2.0, 0.0, 0.0)})[0].tolist()
    [0.0, 1.0, 0.0, 0.0, 0.0, 2.0]
    """
    T = np.zeros((len(coordinates), 6))
    for i, name in enumerate(coordinates):
        dof = _parse_dof(name)
        if dof is None:
            continue
        node, direction = dof
        x, y, z = (float(v) for v in (nodes or {}).get(node, (0.0, 0.0, 0.0)))
        # basic translation and rotation of the node per unit rigid motion (6 columns)
        translation = np.array([[1, 0, 0, 0, z, -y], [0, 1, 0, -z, 0, x],
                                [0, 0, 1, y, -x, 0]], dtype=float)
        rotation = np.hstack([np.zeros((3, 3)), np.eye(3)])
        axes = np.asarray((frames or {}).get(node, np.eye(3)), dtype=float)
        block = translation if direction < 3 else rotation
        T[i] = axes[direction % 3] @ block
    return T


def check_matrices(system: LinearSystem, *, nodes: Mapping[int, Sequence[float]] | None = None,
                   frames: Mapping[int, Any] | None = None) -> MatrixChecks:
    """Check M and K of a system as read from a finite-element file.

    Parameters
    ----------
    system : LinearSystem
        Any linear system (its numbers at the model's parameter values).
    nodes : mapping, optional
        node -> (x, y, z): with them the rigid-body check gives the centre of gravity and
        the inertia.
    frames : mapping, optional
        node -> the rows of its output axes in the basic system.

    Returns
    -------
    MatrixChecks

    Examples
    --------
    >>> import numpy as np
    >>> from resonant.system.base import NumericEOM
    >>> system = NumericEOM(("q1", "q2"), np.eye(2), np.zeros((2, 2)),
    ...                     np.array([[1.0, 0.5], [0.0, 1.0]]))
    >>> check_matrices(system).problems
    ('K is not symmetric (max |K - K^T| / max |K| = 0.5)',)
    """
    num = system.numeric()
    n = num.n
    problems: list[str] = []
    notes: list[str] = []
    present = bool(abs(num.M).max() > 0) if n else False
    if not present:
        problems.append("the mass matrix M is zero: no analysis in time or frequency can use "
                        f"the model. {MASS_SOURCES}")
    asymmetry = {"M": _asymmetry(num.M), "K": _asymmetry(num.K)}
    for key, value in asymmetry.items():
        if value > SYMMETRY_TOLERANCE:
            problems.append(f"{key} is not symmetric (max |{key} - {key}^T| / max |{key}| = "
                            f"{value:.2g})")
    massless = tuple(q for q, row in zip(num.coordinates, _row_norms(num.M)) if row == 0)
    free = [q for q, m, k in zip(num.coordinates, _row_norms(num.M), _row_norms(num.K))
            if m == 0 and k == 0]
    if free:
        problems.append(f"{len(free)} coordinates have neither mass nor stiffness "
                        f"({', '.join(free[:6])}{', ...' if len(free) > 6 else ''}): "
                        "unconnected DOFs of the FE model; drop them (drop_unconnected = "
                        "true in [matrices])")
    if massless and present and len(massless) > len(free):
        notes.append(f"{len(massless)} coordinates carry no mass ({', '.join(massless[:6])}"
                     f"{', ...' if len(massless) > 6 else ''}): M is singular; condense them "
                     "(Guyan) or add mass before a transient or state-space analysis")
    dense = n <= MAX_DENSE_CHECK
    mass_eigen: tuple[float, ...] = ()
    stiff_eigen: tuple[float, ...] = ()
    rigid: int | None = None
    if dense and present and not problems:
        lam_m = symmetric_eigenvalues(dense_matrix(num.M))
        lam_k = symmetric_eigenvalues(dense_matrix(num.K))
        mass_eigen = (float(lam_m[0]), float(lam_m[-1]))
        stiff_eigen = (float(lam_k[0]), float(lam_k[-1]))
        zero_k = ZERO_EIGENVALUE * 1e3 * max(abs(lam_k[-1]), 1e-300)
        rigid = int(np.sum(np.abs(lam_k) <= zero_k))
        if lam_m[0] < -ZERO_EIGENVALUE * 1e3 * lam_m[-1]:
            problems.append(f"M is not positive semi-definite (smallest eigenvalue "
                            f"{lam_m[0]:.6g})")
        elif lam_m[0] <= ZERO_EIGENVALUE * 1e3 * lam_m[-1] and not massless:
            notes.append("M is positive semi-definite, not definite: some motion carries no "
                         "mass")
        if lam_k[0] < -zero_k:
            problems.append(f"K is not positive semi-definite (smallest eigenvalue "
                            f"{lam_k[0]:.6g}): the structure is unstable or the matrix "
                            "damaged")
    elif not dense:
        notes.append(f"eigenvalues of M and K not computed above {MAX_DENSE_CHECK} "
                     "coordinates (resonant modes finds the lowest modes)")
    rigid_fields = _rigid_body_check(num, nodes, frames, notes)
    return MatrixChecks(n=n, mass_present=present, asymmetry=asymmetry,
                        mass_eigenvalues=mass_eigen, massless=massless,
                        stiffness_eigenvalues=stiff_eigen, rigid_body_modes=rigid,
                        problems=tuple(problems), notes=tuple(notes), **rigid_fields)


def _row_norms(a: Matrix) -> np.ndarray:
    return np.asarray(abs(a).sum(axis=1)).ravel()


def _rigid_body_check(num: NumericEOM, nodes: Mapping[int, Sequence[float]] | None,
                      frames: Mapping[int, Any] | None, notes: list[str]) -> dict[str, Any]:
    """Mass by direction, the forces of a rigid translation, and with node positions the
    rigid-body mass, centre of gravity and inertia."""
    T = rigid_body_modes(num.coordinates, nodes, frames)
    if not np.any(T):
        notes.append("no coordinate is named by node and direction (n1042_uz): no "
                     "rigid-body check")
        return {}
    MT = np.asarray(num.M @ T)
    KT = np.asarray(num.K @ T)
    scale = float(abs(num.K).max()) or 1.0
    mass = {axis: float(T[:, k] @ MT[:, k]) for k, axis in enumerate("xyz")}
    forces = {axis: float(np.max(np.abs(KT[:, k])) / scale) for k, axis in enumerate("xyz")
              if np.any(T[:, k])}
    if any(v > RIGID_FORCE_TOLERANCE for v in forces.values()):
        notes.append("a rigid translation leaves forces K T: the structure is constrained "
                     "(supports, springs to ground), or some nodes' DOFs are not in the "
                     "basic system (give their output frames); the mass by translation then "
                     "is not the total mass")
    out: dict[str, Any] = {"mass_by_direction": mass, "rigid_body_forces": forces}
    if nodes is None:
        return out
    rbm = T.T @ MT
    rbm = 0.5 * (rbm + rbm.T)
    m = rbm[0, 0]
    if m <= 0:
        return {**out, "rigid_body_mass": rbm}
    cg = (rbm[1, 5] / m, rbm[2, 3] / m, rbm[0, 4] / m)
    x, y, z = cg
    skew = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    inertia = rbm[3:, 3:] + m * skew @ skew  # parallel axes: I_cg = I_o - m S^T S
    return {**out, "rigid_body_mass": rbm, "centre_of_gravity": tuple(float(v) for v in cg),
            "inertia": inertia}


__all__ = ["MatrixChecks", "check_matrices", "rigid_body_modes", "MASS_SOURCES",
           "MAX_DENSE_CHECK"]
