"""Pseudo-arclength continuation of the harmonic-balance equations in one parameter.

The unknowns are scaled, ``v = (x / s_x, p / s_p)``; from a converged point the
predictor steps along the tangent, Newton's method corrects on the plane normal
to it (the analytical dR/dx beside a chord column dR/dp), and the step size follows
the Newton iteration count and the relative change of the amplitude and of the
parameter.  Folds are passed.  :func:`refine` locates the zero of a function of
the branch between two of its points (a fold, a change of stability, a peak).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from ..deadline import Deadline
from .hb_solver import NEWTON_MAX, NEWTON_TOL


class Balance(Protocol):
    """Harmonic-balance equations R(x, p) = 0 as the continuation uses them: the full ones
    (:class:`~resonant.analyses.hb_solver.HarmonicBalance`) or those condensed onto the
    nonlinear coordinates (:class:`~resonant.analyses.condensed.CondensedBalance`)."""

    #: the name of the continuation parameter
    param: str

    def jacobian(self, x: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray, Any]:
        """R, dR/dx and what the stability analysis needs of the point (its last item W)."""
        ...

    def dp(self, x: np.ndarray, p: float) -> np.ndarray:
        """dR/dp."""
        ...

    def newton(self, x: np.ndarray, p: float, scale: float) -> tuple[np.ndarray, bool]:
        """Newton's method at fixed p: the solution and whether it converged."""
        ...

#: largest relative change of the coefficient vector per continuation step
MAX_RELATIVE_CHANGE = 0.08


@dataclass
class Branch:
    x: list[np.ndarray]
    p: list[float]
    tp: list[float]
    warnings: list[str]
    tangents: list[np.ndarray]
    sx: float
    sp: float

    def append(self, x: np.ndarray, p: float, t: np.ndarray) -> None:
        self.x.append(x)
        self.p.append(p)
        self.tp.append(float(t[-1]))
        self.tangents.append(t)


def tangent(J: np.ndarray, Rp: np.ndarray, sx: float, sp: float,
            previous: np.ndarray) -> np.ndarray:
    A = np.vstack([np.hstack([J * sx, (Rp * sp)[:, None]]), previous[None, :]])
    b = np.zeros(A.shape[0])
    b[-1] = 1.0
    t = np.linalg.solve(A, b)
    t /= np.linalg.norm(t)
    return t if t @ previous >= 0 else -t


def correct(hb: Balance, pred: np.ndarray, t: np.ndarray, sx: float, sp: float
            ) -> tuple[np.ndarray, bool, int]:
    """Newton on R(x, p) = 0 and t . (v - pred) = 0 from the predictor (scaled variables)."""
    v = pred.copy()
    # dR/dp (a central difference, two residuals) once at the predictor: a chord column
    # beside the exact dR/dx; the corrected point solves R = 0 all the same
    Rp = hb.dp(pred[:-1] * sx, pred[-1] * sp)
    for iterations in range(1, NEWTON_MAX + 1):
        xv, pv = v[:-1] * sx, v[-1] * sp
        R, J, _ = hb.jacobian(xv, pv)
        A = np.vstack([np.hstack([J * sx, (Rp * sp)[:, None]]), t[None, :]])
        rhs = -np.concatenate([R, [t @ (v - pred)]])
        try:
            dv = np.linalg.solve(A, rhs)
        except np.linalg.LinAlgError:
            return v, False, iterations
        v = v + dv
        if not np.all(np.isfinite(v)):
            return v, False, iterations
        if np.linalg.norm(dv) <= NEWTON_TOL * max(float(np.linalg.norm(v)), 1.0):
            return v, True, iterations
    return v, False, NEWTON_MAX


def follow(hb: Balance, x0: np.ndarray, start: float, stop: float, points: int,
           deadline: Deadline, relative: bool = False) -> Branch:
    """Continue the solution x0 at ``start`` to ``stop`` by pseudo-arclength.

    Parameters
    ----------
    hb : Balance
    x0 : numpy.ndarray
        A converged solution at ``start``.
    start, stop : float
        The range of the continuation parameter.
    points : int
        About this many steps across the range in the parameter direction.
    deadline : Deadline
    relative : bool
        Step control relative to the present amplitude (the condensed balance's): the
        step's ceiling grows with the amplitude beyond the start point's, and the step
        grows after four Newton iterations, not only after three.  Default: the
        ceiling in units of the start point's amplitude.

    Returns
    -------
    Branch
        The points, their tangents and the warnings (stopped early, turned back).
    """
    sp = abs(stop - start)
    direction = 1.0 if stop > start else -1.0
    sx = max(float(np.linalg.norm(x0)), 1e-12)
    size = x0.size
    previous = np.zeros(size + 1)
    previous[-1] = direction
    x, p = x0, start
    R, J, _ = hb.jacobian(x, p)
    t = tangent(J, hb.dp(x, p), sx, sp, previous)
    ds_max = 1.0 / max(points - 1, 2)
    ds_min = 1e-7
    ds = ds_max
    branch = Branch([x], [p], [float(t[-1])], [], [t], sx, sp)
    steps = 0
    max_steps = 50 * points
    while steps < max_steps:
        steps += 1
        deadline.check(f"while following the branch ({hb.param} = {p:.6g})",
                       analysis=True)
        u = np.concatenate([x / sx, [p / sp]])
        v, ok, iterations = correct(hb, u + ds * t, t, sx, sp)
        x_new, p_new = v[:-1] * sx, v[-1] * sp
        change = float(np.linalg.norm(x_new - x)) / max(float(np.linalg.norm(x)), 1e-3 * sx)
        dp_rel = abs(p_new - p) / sp
        if not ok or change > 2 * MAX_RELATIVE_CHANGE or dp_rel > 2 * ds_max:
            ds /= 2
            if ds < ds_min:
                branch.warnings.append(f"the continuation stopped at {hb.param} "
                                       f"= {p:.6g}: no converged step (step size below "
                                       f"{ds_min:g})")
                break
            continue
        R, J, _ = hb.jacobian(x_new, p_new)
        t_new = tangent(J, hb.dp(x_new, p_new), sx, sp, t)
        if t_new @ t < 0.8 and ds > 1e-4:  # turned too sharply: maybe a jump between branches
            ds /= 2
            continue
        x, p, t = x_new, p_new, t_new
        if (p - stop) * direction > 0:  # passed the end: finish exactly at stop
            xs, pp = branch.x[-1], branch.p[-1]
            guess = xs + (x - xs) * (stop - pp) / (p - pp) if p != pp else x
            xe, converged = hb.newton(guess, stop, sx)
            if converged:
                branch.append(xe, stop, t)
            break
        if (p - start) * direction < -0.05 * sp:
            branch.warnings.append(f"the branch turned back out of the range at "
                                   f"{hb.param} = {p:.6g} (an isola or a "
                                   "closed curve); stopped there")
            branch.append(x, p, t)
            break
        branch.append(x, p, t)
        # relative: the last iteration only confirms convergence (its correction below
        # NEWTON_TOL); four are a predictor off by about 1e-4 of the step, not a hard one
        easy = 4 if relative else 3
        factor = 1.5 if iterations <= easy else (1.0 if iterations <= easy + 2 else 0.6)
        factor = min(factor, MAX_RELATIVE_CHANGE / max(change, 1e-12),
                     ds_max / max(dp_rel, 1e-12))
        # relative: the step's ceiling grows with the amplitude (the unknowns are scaled by
        # the start point's amplitude, so where the response has grown 80-fold, a lightly
        # damped resonance, a fixed ceiling held every step to a 0.5 % change); the
        # change, the parameter's step and the Newton iterations bound it there
        ceiling = ds_max * 20 * (max(1.0, float(np.linalg.norm(x)) / sx) if relative else 1.0)
        ds = float(np.clip(ds * max(factor, 0.3), ds_min, ceiling))
    else:
        branch.warnings.append(f"the continuation stopped after {max_steps} steps before "
                               f"reaching {stop:g}")
    return branch


def arc(branch: Branch, i: int) -> float:
    """The length of step i -> i+1 along the tangent at i (scaled variables): the
    coordinate :func:`refine` and :func:`probe` use."""
    sx, sp = branch.sx, branch.sp
    ui = np.concatenate([branch.x[i] / sx, [branch.p[i] / sp]])
    uj = np.concatenate([branch.x[i + 1] / sx, [branch.p[i + 1] / sp]])
    return float(branch.tangents[i] @ (uj - ui))


def probe(hb: Balance, branch: Branch, i: int, sigma: float
          ) -> tuple[np.ndarray, float, np.ndarray] | None:
    """The branch's point at ``sigma`` along the tangent of point i (the coordinate of
    :func:`arc`), corrected by Newton: (x, p, its tangent), or None without convergence."""
    sx, sp = branch.sx, branch.sp
    t = branch.tangents[i]
    ui = np.concatenate([branch.x[i] / sx, [branch.p[i] / sp]])
    v, ok, _ = correct(hb, ui + sigma * t, t, sx, sp)
    if not ok:
        return None
    x, p = v[:-1] * sx, float(v[-1] * sp)
    _, J, _ = hb.jacobian(x, p)
    return x, p, tangent(J, hb.dp(x, p), sx, sp, t)


def refine(hb: Balance, branch: Branch, i: int,
           g: Callable[[np.ndarray, float, np.ndarray], float], g0: float, g1: float,
           span: tuple[float, float] | None = None) -> tuple[np.ndarray, float] | None:
    """The point between branch points i and i+1 where g(x, p, tangent) = 0 (regula falsi
    with the Illinois modification on the arc-length coordinate).  ``span``: the part
    (a, b) of that coordinate to search (g0 at a, g1 at b; :func:`arc` gives the whole:
    the default), for a zero between two corrected points inside the step."""
    sx, sp = branch.sx, branch.sp
    t = branch.tangents[i]
    ui = np.concatenate([branch.x[i] / sx, [branch.p[i] / sp]])
    a, b = (0.0, arc(branch, i)) if span is None else span
    fa, fb = g0, g1
    if not (fa * fb < 0 and b > 0):
        return None
    best: tuple[np.ndarray, float] | None = None
    for _ in range(40):
        sigma = (a * fb - b * fa) / (fb - fa)
        v, ok, _ = correct(hb, ui + sigma * t, t, sx, sp)
        if not ok:
            return best
        x, p = v[:-1] * sx, float(v[-1] * sp)
        R, J, _ = hb.jacobian(x, p)
        f = g(x, p, tangent(J, hb.dp(x, p), sx, sp, t))
        best = (x, p)
        if f * fb < 0:
            a, fa = b, fb
        else:
            fa /= 2
        b, fb = sigma, f
        if abs(b - a) < 1e-13 * max(1.0, abs(b)) or f == 0:
            break
    return best


__all__ = ["Balance", "Branch", "tangent", "correct", "follow", "refine", "arc", "probe",
           "MAX_RELATIVE_CHANGE"]
