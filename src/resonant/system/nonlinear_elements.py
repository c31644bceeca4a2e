"""The nonlinear elements of a ``[matrices]`` model, compiled: forces over one period.

:class:`ElementForces` evaluates the forces of the ``[[nonlinear]]`` elements at
time samples of the coordinates they connect (the *local* coordinates, m of
them) and their derivatives along given directions, as the alternating
frequency-time scheme of harmonic balance needs them:

``force``
    the expression and its partial derivatives (sympy, compiled once);
``gap``
    ``kc max(u - g, 0)`` with u = q_a - q_b;
``friction``
    a Jenkins element (spring kt in series with a slider at ``slip_force``),
    *marched* through the samples: f_j = clip(f_(j-1) + kt (u_j - u_(j-1)),
    -F_s, F_s), two periods from f = clip(kt (u_0 - mean u)), the second one
    kept (a slip in the first erases the start); its derivative is marched
    alongside (zero where it slips).

Each element's force f enters the first coordinate's equation with + and the
second's with - (``M q'' + C q' + K q + f_nl = F``).

Examples
--------
>>> import numpy as np
>>> from resonant.model.nonlinear_elements import read_nonlinear_elements
>>> el = read_nonlinear_elements([{"coordinates": ["q1"], "force": "k3*q1^3"}],
...                              ["k3"], ["q1"], "m.toml")
>>> forces = ElementForces(el, {"k3": 2.0})
>>> F, _ = forces.evaluate(np.array([[0.5, -1.0]]), np.zeros((1, 2)))
>>> F.tolist()
[[0.25, -2.0]]
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import sympy

from ..errors import AnalysisError
from ..expressions import compilable, numeric_value
from ..model.nonlinear_elements import NonlinearElement

#: a law's force (N,), its derivative along the directions (N, c) or None, and its tangent
#: stiffness (N,) at the samples of a relative displacement
_Law = tuple[np.ndarray, np.ndarray | None, np.ndarray]


def _rate(name: str) -> sympy.Symbol:
    return sympy.Symbol(f"{name}__rate", real=True)


class _Expression:
    """A force expression and its derivatives, compiled once."""

    def __init__(self, element: NonlinearElement, params: Sequence[str]) -> None:
        assert element.force is not None
        names = element.coordinates

        def resolve(name: str, primes: int) -> sympy.Expr:
            if name in names:
                return _rate(name) if primes else sympy.Symbol(name, real=True)
            return sympy.Symbol(name, real=True)

        expr = element.force.to_sympy(resolve)
        q = [sympy.Symbol(n, real=True) for n in names]
        qd = [_rate(n) for n in names]
        p = [sympy.Symbol(n, real=True) for n in params]
        parts = [expr] + [sympy.diff(expr, v) for v in q + qd]
        self.count = len(names)
        self._fn = sympy.lambdify([*q, *qd, *p], [compilable(e) for e in parts],
                                  modules="numpy", cse=True)

    def __call__(self, q: np.ndarray, qd: np.ndarray, pvals: Sequence[float]
                 ) -> list[np.ndarray]:
        with np.errstate(all="ignore"):
            raw = self._fn(*q, *qd, *pvals)
        N = q.shape[1]
        return [np.broadcast_to(np.asarray(v, dtype=float), (N,)) for v in raw]


class ElementForces:
    """The forces of the ``[[nonlinear]]`` elements at time samples of their coordinates.

    Parameters
    ----------
    elements : sequence of NonlinearElement
    parameters : mapping
        Parameter name -> value (the elements' expressions use them).

    Attributes
    ----------
    dofs : tuple of int
        The model coordinates the elements connect (the local coordinates, in order).
    """

    def __init__(self, elements: Sequence[NonlinearElement],
                 parameters: Mapping[str, float]) -> None:
        self.elements = tuple(elements)
        self.params = tuple(parameters)
        self.values = {k: float(v) for k, v in parameters.items()}
        dofs: list[int] = []
        for e in self.elements:
            dofs += [i for i in e.indices if i not in dofs]
        self.dofs = tuple(dofs)
        self.local = [tuple(dofs.index(i) for i in e.indices) for e in self.elements]
        self._compiled = [_Expression(e, self.params) if e.kind == "force" else None
                          for e in self.elements]
        self.hysteretic = any(e.kind == "friction" for e in self.elements)
        #: the laws of relative displacement, by kind (a force's law is its expression)
        self._laws: dict[str, Callable[[NonlinearElement, np.ndarray, np.ndarray | None],
                                       _Law]] = {"gap": self._gap, "friction": self._jenkins}

    def with_parameters(self, values: Mapping[str, float]) -> ElementForces:
        """The same elements with other parameter values (no recompilation)."""
        out = object.__new__(ElementForces)
        out.__dict__.update(self.__dict__)
        out.values = {**self.values, **{k: float(v) for k, v in values.items()}}
        return out

    def _constant(self, e: NonlinearElement, key: str) -> float:
        value = float(numeric_value(getattr(e, key), self.values))
        if not np.isfinite(value):
            raise AnalysisError(f"[nonlinear '{e.name}'] {key} is not finite for the given "
                                "parameter values")
        if key in ("stiffness", "slip_force") and value < 0:
            raise AnalysisError(f"[nonlinear '{e.name}'] {key} must not be negative, not "
                                f"{value:g}")
        if e.kind == "friction" and key == "stiffness" and value == 0:
            raise AnalysisError(f"[nonlinear '{e.name}'] the stiffness of a friction element "
                                "must be positive (it carries the force until it slips)")
        return value

    def _relative(self, loc: tuple[int, ...], X: np.ndarray) -> np.ndarray:
        return np.asarray(X[loc[0]] - X[loc[1]] if len(loc) == 2 else X[loc[0]])

    def evaluate(self, U: np.ndarray, Ud: np.ndarray, dU: np.ndarray | None = None,
                 dUd: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        """Forces at the samples and, optionally, their derivatives along directions.

        Parameters
        ----------
        U, Ud : ndarray
            Displacements and velocities of the local coordinates, shape (m, N): N
            samples of one period (evenly spaced).
        dU, dUd : ndarray, optional
            Directions, shape (m, N, c): the derivative of the forces along each.

        Returns
        -------
        F : ndarray
            (m, N) generalized forces on the local coordinates.
        dF : ndarray or None
            (m, N, c) their derivatives along the directions.
        """
        m, N = U.shape
        F = np.zeros((m, N))
        dF = None if dU is None else np.zeros(dU.shape)
        pvals = [self.values[k] for k in self.params]
        for e, loc, fn in zip(self.elements, self.local, self._compiled):
            u = self._relative(loc, U)
            du = None if dU is None else self._relative(loc, dU)
            if e.kind == "force":
                assert fn is not None
                parts = fn(U[list(loc)], Ud[list(loc)], pvals)
                f = parts[0]
                if dU is not None and dUd is not None:
                    k = len(loc)
                    g = sum(parts[1 + j][:, None] * dU[loc[j]] for j in range(k)) + \
                        sum(parts[1 + k + j][:, None] * dUd[loc[j]] for j in range(k))
            else:
                f, g, _ = self._laws[e.kind](e, u, du)
            F[loc[0]] += f
            if len(loc) == 2:
                F[loc[1]] -= f
            if dF is not None:
                dF[loc[0]] += g
                if len(loc) == 2:
                    dF[loc[1]] -= g
        return F, dF

    def _gap(self, e: NonlinearElement, u: np.ndarray, du: np.ndarray | None) -> _Law:
        """A contact: kc (u - g) while u exceeds the clearance g."""
        gap, kc = self._constant(e, "gap"), self._constant(e, "stiffness")
        closed = u > gap
        along = None if du is None else np.where(closed[:, None], kc * du, 0.0)
        return np.where(closed, kc * (u - gap), 0.0), along, np.where(closed, kc, 0.0)

    def _jenkins(self, e: NonlinearElement, u: np.ndarray, du: np.ndarray | None) -> _Law:
        """The Jenkins element: its tangent kt while it sticks, zero while it slips."""
        f, along = self._friction(e, u, du)
        fs, kt = self._constant(e, "slip_force"), self._constant(e, "stiffness")
        return f, along, np.where(np.abs(f) < fs * (1 - 1e-12), kt, 0.0)

    def _friction(self, e: NonlinearElement, u: np.ndarray, du: np.ndarray | None
                  ) -> tuple[np.ndarray, Any]:
        """The Jenkins element's force over one period of the periodic motion u (N,) and
        its derivative along the directions du (N, c): f = kt (u - z) with the slider z
        marched through two periods (:func:`_slider`)."""
        kt, fs = self._constant(e, "stiffness"), self._constant(e, "slip_force")
        N = u.size
        f0 = float(np.clip(kt * (u[0] - u.mean()), -fs, fs))
        z, source = _slider(np.concatenate([u, u]), fs / kt, u[0] - f0 / kt)
        z, source = z[N:], source[N:]
        if du is None:
            return kt * (u - z), None
        if np.all(source < 0):  # sticks throughout: the slider at the mean of the motion
            return kt * (u - z), kt * (du - du.mean(axis=0))
        return kt * (u - z), kt * (du - du[source % N])

    def stiffness(self, U: np.ndarray, Ud: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The instantaneous tangent stiffness and damping, shape (m, m, N) each.

        For the friction element: kt while it sticks, zero while it slips.  This is
        not the whole linearization of a friction element: a perturbation of the motion
        also moves its slider while it slips, and the element remembers that shift while
        it sticks again (:meth:`sliders` gives what a stability analysis needs for it).
        """
        _, G0, G1 = self.forces_and_tangent(U, Ud)
        return G0, G1

    def sliders(self, U: np.ndarray) -> list[tuple[np.ndarray, float, np.ndarray]]:
        """The friction elements that slip during the periodic motion, for the
        linearization about it.

        Perturbed by du, such an element's force changes by kt (du - dz) while it sticks,
        dz the shift of its slider, fixed while it sticks and reset to du while it slips
        (where the force stays at the slip force): the memory the instantaneous tangent
        (:meth:`stiffness`) leaves out.  An element that sticks throughout is the spring
        kt of :meth:`stiffness` alone.

        Parameters
        ----------
        U : ndarray
            (m, N) displacements of the local coordinates at the samples of one period.

        Returns
        -------
        list of (ndarray, float, ndarray)
            Per slipping element: its direction b (m,) in the local coordinates
            (du = b . dU), kt, and where it sticks (N,) bool.

        Examples
        --------
        >>> from resonant.model.nonlinear_elements import read_nonlinear_elements
        >>> el = read_nonlinear_elements([{"coordinates": ["q1"], "kind": "friction",
        ...                                "stiffness": 2.0, "slip_force": 0.5}],
        ...                              [], ["q1"], "m.toml")
        >>> t = np.linspace(0, 2 * np.pi, 8, endpoint=False)
        >>> [(b.tolist(), kt, stick.tolist()) for b, kt, stick in
        ...  ElementForces(el, {}).sliders(np.cos(t)[None])]  # doctest: +NORMALIZE_WHITESPACE
        [([1.0], 2.0, [False, True, False, False, False, True, False, False])]
        """
        m, _ = U.shape
        out = []
        for e, loc in zip(self.elements, self.local):
            if e.kind != "friction":
                continue
            _, _, t = self._jenkins(e, self._relative(loc, U), None)
            stick = t > 0
            if stick.all():
                continue
            b = np.zeros(m)
            b[loc[0]] = 1.0
            if len(loc) == 2:
                b[loc[1]] = -1.0
            out.append((b, self._constant(e, "stiffness"), stick))
        return out

    def forces_and_tangent(self, U: np.ndarray, Ud: np.ndarray
                           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The forces (m, N) and the tangent stiffness and damping (m, m, N) in one pass
        over the elements (a force's expression gives its value and derivatives at once)."""
        m, N = U.shape
        F, G0, G1 = np.zeros((m, N)), np.zeros((m, m, N)), np.zeros((m, m, N))
        pvals = [self.values[k] for k in self.params]
        for e, loc, fn in zip(self.elements, self.local, self._compiled):
            k = len(loc)
            sign = np.array([1.0, -1.0][:k])
            if e.kind == "force":
                assert fn is not None
                parts = fn(U[list(loc)], Ud[list(loc)], pvals)
                for a in range(k):
                    F[loc[a]] += sign[a] * parts[0]
                    for b in range(k):
                        G0[loc[a], loc[b]] += sign[a] * parts[1 + b]
                        G1[loc[a], loc[b]] += sign[a] * parts[1 + k + b]
                continue
            f, _, t = self._laws[e.kind](e, self._relative(loc, U), None)
            for a in range(k):
                F[loc[a]] += sign[a] * f
                for b in range(k):
                    G0[loc[a], loc[b]] += sign[a] * sign[b] * t
        return F, G0, G1


def _slider(u: np.ndarray, r: float, z0: float) -> tuple[np.ndarray, np.ndarray]:
    """The slider of a Jenkins element, z_j = clip(z_(j-1), u_j - r, u_j + r) from z0.

    Each step is a clamp to an interval, and clamps compose into clamps, so all
    prefixes come from log2(N) vectorized doublings (a Hillis-Steele scan) instead of
    a loop over the samples; z takes its values from u -+ r or z0 exactly.  ``source``
    is the index of the sample where the slider last slipped (-1 before the first).

    Examples
    --------
    >>> z, source = _slider(np.array([0.0, 2.0, 1.5, -1.0]), 1.0, 0.0)
    >>> z.tolist(), source.tolist()
    ([0.0, 1.0, 1.0, 0.0], [-1, 1, 1, 3])
    """
    lo, hi = u - r, u + r
    shift = 1
    while shift < u.size:
        new_lo, new_hi = lo.copy(), hi.copy()
        new_lo[shift:] = np.clip(lo[:-shift], lo[shift:], hi[shift:])
        new_hi[shift:] = np.clip(hi[:-shift], lo[shift:], hi[shift:])
        lo, hi = new_lo, new_hi
        shift *= 2
    z = np.clip(z0, lo, hi)
    previous = np.concatenate([[z0], z[:-1]])
    slipped = (z != previous) | (z == u - r) | (z == u + r)
    source = np.maximum.accumulate(np.where(slipped, np.arange(u.size), -1))
    return z, source


__all__ = ["ElementForces"]
