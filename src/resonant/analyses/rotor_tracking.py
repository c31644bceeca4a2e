"""The complex modes of a rotor over its speed, tracked from speed to speed.

A rotor's equation of motion at spin speed Omega is M q'' + (C + Omega G) q' + K(Omega) q
= 0 (G gyroscopic, K and C of the bearings possibly speed dependent): a
:class:`~resonant.system.base.LinearSystem` whose parameter ``speed`` is Omega.  At each
speed the modal kernel (:func:`resonant.modal.gyroscopic_modes`, or
:func:`resonant.modal.lowest_gyroscopic_modes` for a sparse model) gives the modes in
its one order; here they are *followed*: mode j at the next speed is the candidate whose
shape is closest to mode j's (the modal assurance criterion, MAC, maximised over all
branches at once by the Hungarian assignment).  Where that assignment is ambiguous (a
MAC below :data:`CONFIDENT` or a runner-up above :data:`RIVAL`, as at a veering sampled
too coarsely) the step is halved, up to :data:`MAX_HALVINGS` times, so that a branch
never jumps to another.  Degenerate modes (an isotropic rotor at rest: any combination
of the two planes is a mode) have their shapes chosen inside their eigenspace as the
nearest to the neighbouring speed's.

Examples
--------
>>> import resonant
>>> m = resonant.loads('''
... [parameters]
... Omega = 0
... [matrices]
... M = [[1, 0], [0, 1]]
... K = [[1, 0], [0, 1]]
... G = [[0, 1], [-1, 0]]
... speed = "Omega"
... ''')
>>> track = track_modes(m.linearize(), "Omega", np.array([0.0, 1.0]), 2)
>>> track.frequencies[-1].round(6).tolist()
[0.618034, 1.618034]
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import Matrix
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem
from ..modal import (
    ZERO_STATE,
    gyroscopic_modes,
    gyroscopic_modes_near,
    lowest_gyroscopic_modes,
    modal_assurance,
)
from ..system.base import LinearSystem

#: an assignment with every MAC at least this is confident
CONFIDENT = 0.8
#: a second candidate with a MAC above this (to the same branch) makes it ambiguous
RIVAL = 0.5
#: the most halvings of one speed step where the assignment is ambiguous
MAX_HALVINGS = 8
#: the most rigid-body eigenvalues of a rotor (its four lateral, one axial and one
#: torsional free motions, each a pair of s = 0): computed beside a sparse rotor's candidates
RIGID_ROOM = 12
#: a model with more coordinates than this (or sparse) uses the sparse eigensolver
DENSE_LIMIT = 400
#: the modes a large rotor's root finder computes near the followed branch's eigenvalue
NEAR_CANDIDATES = 6
#: eigenvalues this close (relative to |s|) form one degenerate eigenspace
DEGENERATE = 1e-7
#: |precession| below this is no whirl (a planar or a non-lateral motion)
PLANAR = 1e-6
#: a mode whose pairs hold less than this share of |q|^2 has no lateral motion (an axial
#: or torsional mode: its x, y are round-off, amplitudes below 1e-10 of the shape's)
LATERAL_SHARE = 1e-20

Modes = tuple[np.ndarray, np.ndarray]


@dataclass(frozen=True)
class Tracked:
    """Modes followed over the speeds (the grid and the points refinement added).

    Attributes
    ----------
    speeds : ndarray
        The speeds (rad/s), ascending, shape (P,).
    eigenvalues : ndarray
        s of each branch at each speed, shape (P, k).
    shapes : ndarray
        The unit mode shapes, shape (P, n, k).
    mac : ndarray
        The MAC of each branch between a speed and the one before (1 at the first),
        shape (P, k).
    refined : int
        The speeds refinement added.
    ambiguous : tuple of float
        Speeds where the assignment stayed ambiguous after :data:`MAX_HALVINGS`.
    rigid : int
        The rigid-body eigenvalues (s = 0) left out (:meth:`ModeSolver.modes`).
    """

    speeds: np.ndarray
    eigenvalues: np.ndarray
    shapes: np.ndarray
    mac: np.ndarray
    refined: int
    ambiguous: tuple[float, ...]
    rigid: int = 0

    @property
    def frequencies(self) -> np.ndarray:
        """The damped natural frequencies |Im s| (rad/s), shape (P, k)."""
        result: np.ndarray = np.abs(self.eigenvalues.imag)
        return result


def whirl_pairs(coordinates: Sequence[str]) -> list[tuple[int, int]]:
    """The (x, y) coordinate pairs a whirl is judged on: ``NAME_x``/``NAME_y`` (a
    station's displacements), ``NAME_ax``/``NAME_ay`` (its tilts) and ``x``/``y``.

    Examples
    --------
    >>> whirl_pairs(["disc_x", "disc_y", "disc_ax", "disc_ay", "z"])
    [(0, 1), (2, 3)]
    """
    index = {name: i for i, name in enumerate(coordinates)}
    pairs = []
    for name, i in index.items():
        for x_end, y_end in (("_x", "_y"), ("_ax", "_ay")):
            if name.endswith(x_end) and name[:-len(x_end)] + y_end in index:
                pairs.append((i, index[name[:-len(x_end)] + y_end]))
    if "x" in index and "y" in index:
        pairs.append((index["x"], index["y"]))
    return sorted(pairs)


def precession(shapes: np.ndarray, pairs: Sequence[tuple[int, int]]) -> np.ndarray:
    """The direction of precession of each mode (columns, shape (n, k) or (P, n, k)):
    2 Im(X conj(Y)) / (|X|^2 + |Y|^2) summed over the pairs, +1 a circular forward whirl
    (from x towards y, the direction of a positive spin about z), -1 a circular backward
    one, 0 a planar motion (or one without lateral motion: the pairs hold less than
    :data:`LATERAL_SHARE` of |q|^2).  The motion of a mode is Re(q e^(s t)).

    Examples
    --------
    >>> precession(np.array([[1.0, 1.0], [-1j, 1j]]), [(0, 1)]).round(12).tolist()
    [1.0, -1.0]
    """
    if not pairs:
        return np.zeros(shapes.shape[:-2] + shapes.shape[-1:])
    x = shapes[..., [p[0] for p in pairs], :]
    y = shapes[..., [p[1] for p in pairs], :]
    signed = (2 * (x * np.conj(y)).imag).sum(axis=-2)
    size = (np.abs(x) ** 2 + np.abs(y) ** 2).sum(axis=-2)
    size = np.where(size > LATERAL_SHARE * (np.abs(shapes) ** 2).sum(axis=-2), size, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        result: np.ndarray = np.where(size > 0, signed / np.where(size > 0, size, 1), 0.0)
    return result


def motion_kinds(shapes: np.ndarray, coordinates: Sequence[str]) -> tuple[str, ...]:
    """``"lateral"``, ``"axial"`` or ``"torsional"`` for each mode (columns of ``shapes``,
    (n, k)): the kind of coordinate that holds the largest share of |q|^2 -- a station's
    ``NAME_z`` (axial) and ``NAME_az`` (its twist), beside its ``NAME_x``; the rest
    lateral.  Empty where the rotor has neither axial nor torsional coordinates.

    Examples
    --------
    >>> names = ["d_x", "d_y", "d_ax", "d_ay", "d_z", "d_az"]
    >>> motion_kinds(np.array([[1, 0], [1j, 0], [0, 0], [0, 0], [0, 0], [0, 1.0]]), names)
    ('lateral', 'torsional')
    """
    index = set(coordinates)
    axial = [i for i, n in enumerate(coordinates) if n.endswith("_z") and
             n[:-2] + "_x" in index]
    torsional = [i for i, n in enumerate(coordinates) if n.endswith("_az") and
                 n[:-3] + "_x" in index]
    if not axial and not torsional:
        return ()
    energy = np.abs(shapes) ** 2
    total = energy.sum(axis=0)
    shares = np.stack([total - energy[axial].sum(axis=0) - energy[torsional].sum(axis=0),
                       energy[axial].sum(axis=0), energy[torsional].sum(axis=0)])
    kinds = ("lateral", "axial", "torsional")
    return tuple(kinds[int(i)] for i in np.argmax(shares, axis=0))


def whirl_label(value: float) -> str:
    """``"forward"``, ``"backward"`` or ``"none"`` (planar) for a precession value.

    Examples
    --------
    >>> whirl_label(0.7), whirl_label(-1.0), whirl_label(0.0)
    ('forward', 'backward', 'none')
    """
    if not np.isfinite(value) or abs(value) < PLANAR:
        return "none"
    return "forward" if value > 0 else "backward"


def check_speeds(speeds: np.ndarray, source: str, key: str = "speeds", least: int = 2
                 ) -> np.ndarray:
    """The speeds as an ascending float array; ModelError naming ``key`` if they are not
    finite, not increasing or fewer than ``least``.

    Examples
    --------
    >>> check_speeds(np.array([0.0, 10.0]), "rotor.toml").tolist()
    [0.0, 10.0]
    """
    values = np.asarray(speeds, dtype=float).reshape(-1)
    if values.size < least or not np.all(np.isfinite(values)) or np.any(np.diff(values) <= 0):
        raise ModelError(Problem(f"the speeds must be at least {least} finite values in "
                                 "increasing order (rad/s)", source, "campbell", key))
    return values


class ModeSolver:
    """The lowest modes of a system at any speed, dense or sparse, with the matrices
    evaluated for many speeds at once.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speed : str
        The speed parameter.
    count : int
        The modes wanted (a few more are computed: candidates for the assignment).
    deadline : Deadline, optional
    """

    def __init__(self, system: LinearSystem, speed: str, count: int,
                 deadline: Deadline = NO_DEADLINE) -> None:
        if count < 1 or count > system.n:
            raise ModelError(Problem(f"modes must be between 1 and {system.n} (the number of "
                                     f"coordinates); got {count}", system.source, "campbell",
                                     "modes"))
        self.system, self.speed, self.count, self.deadline = system, speed, count, deadline
        self.candidates = min(system.n, count + max(4, count // 2))
        self.calls = 0
        #: the mass matrix of the last speed: the weight of the MAC
        self.mass: Any = None
        #: the most rigid-body eigenvalues (s = 0) left out at one speed
        self.rigid = 0

    def matrices(self, speeds: np.ndarray) -> list[tuple[Any, Any, Any]]:
        """(M, C, K) at each speed: one evaluation of the model for them all, or, for a
        large model (whose stacks would not fit), one speed at a time (sparse stays
        sparse)."""
        speeds = np.asarray(speeds, dtype=float)
        if self.system.n > DENSE_LIMIT and len(speeds) > 1:
            return [m for value in speeds for m in self.matrices(np.array([value]))]
        batch = self.system.batch(self.speed, speeds, self.deadline)

        def at(a: Matrix, i: int) -> Any:
            return a[i] if isinstance(a, np.ndarray) and a.ndim == 3 else a

        return [(at(batch.M, i), at(batch.C, i), at(batch.K, i)) for i in range(len(speeds))]

    @property
    def large(self) -> bool:
        """Whether the rotor is solved by the sparse eigensolver."""
        return self.system.n > DENSE_LIMIT

    def near(self, speed: float, target: complex) -> Modes:
        """The candidate modes at one speed: a large rotor's few nearest ``target`` (a
        branch's eigenvalue at a neighbouring speed: what a root finder follows), a small
        one's lowest (:meth:`modes`)."""
        M, C, K = self.matrices(np.array([speed]))[0]
        if not (self.large or hasattr(M, "tocsc") or hasattr(K, "tocsc")):
            return self.modes(np.array([speed]))[0]
        self.mass = M
        self.deadline.check("while computing the modes over the speed", "speeds",
                            analysis=True)
        self.calls += 1
        # off the eigenvalue itself (the pencil is singular there): 1e-3 of its size
        shift = complex(target) + 1e-3 * max(abs(target), 1.0) * (1 + 1j)
        return gyroscopic_modes_near(M, C, K, shift, NEAR_CANDIDATES)

    def modes(self, speeds: np.ndarray) -> list[Modes]:
        """The candidate modes (s, shapes) at each speed; the rigid-body eigenvalues (|s|
        within the kernel's zero threshold :data:`resonant.modal.ZERO_STATE`: a free axial
        or torsional motion, a rotor without bearings) are left out, dense or sparse, as
        they have no frequency to follow and no shape the MAC can tell apart."""
        out = []
        for M, C, K in self.matrices(speeds):
            self.mass = M
            self.deadline.check("while computing the modes over the speed", "speeds",
                                analysis=True)
            self.calls += 1
            sparse = hasattr(M, "tocsc") or hasattr(K, "tocsc")
            if sparse or self.system.n > DENSE_LIMIT:
                # room for the rigid-body eigenvalues beside the candidates
                s, q = lowest_gyroscopic_modes(
                    M, C, K, min(self.system.n - 1, self.candidates + RIGID_ROOM))
                top = largest_state_estimate(M, K)
            else:
                s, q = gyroscopic_modes(M, C, K)
                top = float(np.abs(s).max(initial=0.0))
            out.append(self._moving(s, q, top))
        return out

    def _moving(self, s: np.ndarray, q: np.ndarray, top: float) -> Modes:
        """The candidates among modes (s, q) of one speed without its rigid-body
        eigenvalues, |s| <= ZERO_STATE max(1, ``top``), ``top`` the largest |s| of the
        point (or its estimate); counted in :attr:`rigid`."""
        moving = np.abs(s) > ZERO_STATE * max(1.0, top)
        self.rigid = max(self.rigid, int(np.count_nonzero(~moving)))
        if np.count_nonzero(moving) < self.count:
            raise ModelError(Problem(
                f"modes must be at most {np.count_nonzero(moving)}: the rotor has "
                f"{np.count_nonzero(~moving)} rigid-body eigenvalue(s) (s = 0) beside "
                "them", self.system.source, "campbell", "modes"))
        s, q = s[moving], q[:, moving]
        return s[:self.candidates], q[:, :self.candidates]


def largest_state_estimate(M: Matrix, K: Matrix) -> float:
    """An estimate of a rotor's largest |s| without its whole spectrum: the square root of
    the largest Rayleigh quotient K_ii / M_ii of a unit vector (a lower bound of the
    largest omega^2 of the undamped symmetric pencil), the scale of the zero threshold
    where only the lowest modes are computed.

    Examples
    --------
    >>> largest_state_estimate(np.diag([1.0, 2.0]), np.array([[4.0, -1.0], [-1.0, 50.0]]))
    5.0
    """
    k = np.abs(np.asarray(K.diagonal(), dtype=float))
    m = np.asarray(M.diagonal(), dtype=float)
    held = m > 0
    return float(np.sqrt(np.max(k[held] / m[held], initial=0.0)))


def align_degenerate(modes: Modes, reference: np.ndarray) -> Modes:
    """Modes whose eigenvalues coincide (one eigenspace) with their shapes chosen in it
    as the projections of the reference shapes nearest to it.

    Examples
    --------
    >>> s = np.array([1j, 1j])
    >>> _, q = align_degenerate((s, np.eye(2, dtype=complex)), np.array([[1], [-1j]]) / 2**.5)
    >>> abs(q[1, 0] / q[0, 0]).round(12)
    np.float64(1.0)
    """
    s, q = modes
    q = q.copy()
    scale = np.maximum(np.abs(s), 1e-300)
    done = np.zeros(len(s), dtype=bool)
    for i in range(len(s)):
        group = np.flatnonzero((np.abs(s - s[i]) <= DEGENERATE * scale[i]) & ~done)
        done[group] = True
        if len(group) < 2:
            continue
        basis, _ = np.linalg.qr(q[:, group])
        projected = basis @ (np.conj(basis).T @ reference)
        nearest = np.sort(np.argsort(-np.linalg.norm(projected, axis=0), kind="stable")
                          [:len(group)])
        chosen = projected[:, nearest]
        chosen, _ = np.linalg.qr(chosen)   # independent shapes of the eigenspace
        q[:, group] = chosen / np.linalg.norm(chosen, axis=0)
    return s, q


def _assign(reference: np.ndarray, modes: Modes, mass: Matrix | None
            ) -> tuple[np.ndarray, np.ndarray, bool]:
    """The candidate of each branch (indices), its MAC (weighted by the mass matrix) and
    whether the choice is ambiguous."""
    from scipy.optimize import linear_sum_assignment

    mac = modal_assurance(reference, modes[1], mass)
    rows, cols = linear_sum_assignment(-mac)
    chosen = cols[np.argsort(rows)]
    best = mac[np.arange(len(chosen)), chosen]
    rival = mac.copy()
    rival[np.arange(len(chosen)), chosen] = -1.0
    ambiguous = bool(np.any(best < CONFIDENT) or
                     np.any(rival.max(axis=1, initial=-1.0) > RIVAL))
    return chosen, best, ambiguous


class _Tracker:
    """The steps of :func:`track_modes`, with the halving of ambiguous ones."""

    def __init__(self, solver: ModeSolver, budget: int) -> None:
        self.solver = solver
        #: the most speeds refinement may add (a persistent ambiguity costs no more)
        self.budget = budget
        self.rows: list[tuple[float, np.ndarray, np.ndarray, np.ndarray]] = []
        self.refined = 0
        self.ambiguous: list[float] = []

    def start(self, speed: float, modes: Modes, following: Modes) -> None:
        k = self.solver.count
        s, q = align_degenerate(modes, following[1])
        self.rows.append((speed, s[:k], q[:, :k], np.ones(k)))

    def step(self, speed: float, modes: Modes, halvings: int = 0) -> None:
        last_speed, _, reference, _ = self.rows[-1]
        modes = align_degenerate(modes, reference)
        chosen, best, ambiguous = _assign(reference, modes, self.solver.mass)
        if ambiguous and halvings < MAX_HALVINGS and self.refined < self.budget:
            middle = 0.5 * (last_speed + speed)
            self.refined += 1
            self.step(middle, self.solver.modes(np.array([middle]))[0], halvings + 1)
            self.step(speed, align_degenerate(modes, self.rows[-1][2]), halvings + 1)
            return
        if ambiguous:
            self.ambiguous.append(speed)
        s, q = modes
        self.rows.append((speed, s[chosen], q[:, chosen], best))


def track_modes(system: LinearSystem, speed: str, speeds: np.ndarray, count: int,
                deadline: Deadline = NO_DEADLINE) -> Tracked:
    """The ``count`` lowest modes at the first speed followed over ``speeds`` (rad/s).

    Parameters
    ----------
    system : LinearSystem
        The rotor: M q'' + (C + Omega G) q' + K q = 0 at speed Omega.
    speed : str
        The speed parameter.
    speeds : ndarray
        The speeds, ascending (rad/s).
    count : int
        The number of branches.
    deadline : Deadline, optional

    Returns
    -------
    Tracked
    """
    speeds = check_speeds(speeds, system.source)
    solver = ModeSolver(system, speed, count, deadline)
    grid = solver.modes(speeds)
    tracker = _Tracker(solver, budget=4 * len(speeds) + 64)
    tracker.start(float(speeds[0]), grid[0], grid[1])
    for value, modes in zip(speeds[1:], grid[1:]):
        tracker.step(float(value), modes)
    rows = tracker.rows
    return Tracked(np.array([r[0] for r in rows]), np.array([r[1] for r in rows]),
                   np.array([r[2] for r in rows]), np.array([r[3] for r in rows]),
                   tracker.refined, tuple(tracker.ambiguous), solver.rigid)


def branch_value(solver: ModeSolver, reference: np.ndarray,
                 quantity: Callable[[complex, float], float], target: complex = 0j
                 ) -> Callable[[float], float]:
    """quantity(s, speed) of the mode at any speed that continues a branch (the candidate
    nearest, by MAC, to the branch's shape ``reference`` (n,) at a bracketing speed, where
    its eigenvalue is ``target``): the function a root finder calls."""
    def value(speed: float) -> float:
        s, q = solver.near(speed, target)
        mac = modal_assurance(reference[:, None], q, solver.mass)[0]
        return quantity(complex(s[int(np.argmax(mac))]), speed)
    return value


def crossings(values: np.ndarray) -> np.ndarray:
    """Indices i where values (P,) changes sign between i and i + 1 (a zero at i counts
    once, at the step it starts).

    Examples
    --------
    >>> crossings(np.array([-1.0, -0.5, 2.0, 3.0, -1.0])).tolist()
    [1, 3]
    """
    sign = np.sign(values)
    result: np.ndarray = np.flatnonzero((sign[:-1] * sign[1:] < 0) |
                                        ((sign[:-1] == 0) & (sign[1:] != 0) &
                                         (np.arange(len(sign) - 1) > 0)))
    return result


def find_root(function: Callable[[float], float], low: float, high: float,
              tolerance: float) -> float:
    """The root of ``function`` between ``low`` and ``high`` (a change of sign) by Brent's
    method to ``tolerance`` (rad/s); AnalysisError if the bracket does not hold.

    Examples
    --------
    >>> round(find_root(lambda x: x * x - 2.0, 1.0, 2.0, 1e-12), 10)
    1.4142135624
    """
    from scipy.optimize import brentq

    a, b = function(low), function(high)
    if a == 0:
        return low
    if b == 0:
        return high
    if np.sign(a) == np.sign(b):
        raise AnalysisError(f"no change of sign between {low:g} and {high:g} rad/s: the "
                            "branch could not be followed there")
    return float(brentq(function, low, high, xtol=tolerance, rtol=4 * np.finfo(float).eps))


__all__ = ["Tracked", "track_modes", "whirl_pairs", "precession", "whirl_label", "motion_kinds",
           "check_speeds", "ModeSolver", "align_degenerate", "branch_value", "crossings",
           "find_root", "largest_state_estimate", "CONFIDENT", "RIVAL", "MAX_HALVINGS",
           "DENSE_LIMIT", "RIGID_ROOM"]
