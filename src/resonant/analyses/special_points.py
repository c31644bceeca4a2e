"""The special points of a continued branch: folds, changes of stability, peaks.

Each is bracketed between two branch points and located by regula falsi on the arc
(:func:`resonant.analyses.continuation.refine`), every trial point corrected onto
the branch by Newton's method:

* ``fold``: the parameter component of the tangent changes sign;
* a change of the count of Floquet multipliers outside the unit circle, its kind
  read from the crossing multiplier: real positive -> ``branch`` (the tangent does
  not turn), real negative -> ``period-doubling``, complex pair -> ``neimark-sacker``;
* ``peak``: a largest amplitude of a coordinate or output along the branch, where
  d(amplitude)/d(arc) changes sign from + to - (a fold of the amplitude along the
  arc; the derivative a central difference along the tangent).  It carries the
  quantity it is the peak of and its stability.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Protocol

import numpy as np

from ..deadline import NO_DEADLINE, Deadline
from .continuation import Balance, Branch, arc, probe, refine
from .result_fields import FieldsJSON, saved
from .results_json import Saved

#: a multiplier with |mu| > 1 + this is unstable
STABILITY_TOL = 1e-6
SPECIAL_KINDS = ("fold", "period-doubling", "neimark-sacker", "branch", "peak")
#: step along the tangent (scaled variables) of the derivative of an amplitude
ARC_STEP = 1e-5
#: a local maximum of a sampled amplitude counts when it stands out by this (relative)
PEAK_MARGIN = 1e-10
#: a sampled extremum of a growth rate that keeps its sign (the largest rate of the stable
#: multipliers at a local maximum, the smallest of the unstable ones at a local minimum) is
#: searched for a narrow window of the other stability between its neighbours when it lies
#: within this many times its rise from them of the unit circle
WINDOW_FACTOR = 4.0
#: corrected points tried per suspected window, and in all per branch point
WINDOW_PROBES = 4
WINDOW_SHARE = 0.1


class BranchEquations(Balance, Protocol):
    """The equations of a branch as its special points need them."""

    def exponents(self, J: np.ndarray, blocks: Any) -> np.ndarray:
        """The Floquet exponents of a point (``blocks`` from :meth:`jacobian`)."""
        ...

    def amplitudes(self, x: np.ndarray, p: float) -> np.ndarray:
        """The amplitude of every quantity of :meth:`names` at a point."""
        ...

    def amplitude(self, x: np.ndarray, p: float, j: int) -> float:
        """The amplitude of quantity ``j`` of :meth:`names` (``amplitudes(x, p)[j]``)."""
        ...

    def names(self) -> tuple[str, ...]:
        """The quantities whose amplitudes are reported (and whose peaks are located)."""
        ...


@dataclass(frozen=True)
class SpecialPoint(FieldsJSON):
    """A point where the stability or the direction of the branch changes, or a peak.

    ``quantity`` (peaks) names the coordinate or output whose amplitude is largest
    there; ``stable`` (peaks) is the stability of the periodic solution there.
    """

    kind: str
    value: float
    amplitudes: Mapping[str, float]
    index: int
    quantity: str | None = saved(None, omit_none=True)
    stable: bool | None = saved(None, omit_none=True)

    def __post_init__(self) -> None:
        object.__setattr__(self, "amplitudes", MappingProxyType(dict(self.amplitudes)))

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        if values["index"] < 0:
            raise reader.error(f"is {values['index']}, less than 0", "index")


def classify(lam: np.ndarray, W: float) -> tuple[int, int, int]:
    """Counts of unstable exponents: (real positive mu, real negative mu, complex)."""
    T = 2 * np.pi / W
    unstable = lam[lam.real * T > math.log1p(STABILITY_TOL)]
    phase = np.abs(unstable.imag) / W
    pos = int(np.sum(phase < 0.02))
    neg = int(np.sum(phase > 0.48))
    return pos, neg, unstable.size - pos - neg


class Locator:
    """Finds and refines the special points of one branch."""

    def __init__(self, hb: BranchEquations, branch: Branch, lam: np.ndarray,
                 Ws: np.ndarray, deadline: Deadline = NO_DEADLINE) -> None:
        self.hb, self.branch, self.lam, self.Ws = hb, branch, lam, Ws
        self.names = hb.names()
        self.deadline = deadline

    def check(self) -> None:
        """Stop when the run's time is up (a branch may have many special points)."""
        self.deadline.check("while locating the special points", analysis=True)

    def point(self, i: int, kind: str, found: tuple[np.ndarray, float] | None,
              quantity: str | None = None) -> SpecialPoint:
        branch = self.branch
        if found is None:  # not refined: halfway
            found = (0.5 * (branch.x[i] + branch.x[i + 1]), 0.5 * (branch.p[i] + branch.p[i + 1]))
        x, p = found
        a = self.hb.amplitudes(x, p)
        stable = None
        if kind == "peak":
            R, J, blocks = self.hb.jacobian(x, p)
            mult = np.exp(self.hb.exponents(J, blocks) * 2 * np.pi / blocks[-1])
            stable = bool(np.all(np.abs(mult) <= 1 + STABILITY_TOL))
        return SpecialPoint(kind, float(p), MappingProxyType(
            {nm: float(a[j]) for j, nm in enumerate(self.names)}), i, quantity, stable)

    def folds(self) -> tuple[list[SpecialPoint], set[int]]:
        tp = np.array(self.branch.tp)
        found, near = [], set()
        for i in range(tp.size - 1):
            if tp[i] * tp[i + 1] < 0:
                self.check()
                at = refine(self.hb, self.branch, i, lambda x, p, t: float(t[-1]),
                            float(tp[i]), float(tp[i + 1]))
                found.append(self.point(i, "fold", at))
                near.update({i - 1, i, i + 1})
        return found, near

    def growth(self, k: int) -> Callable[[np.ndarray, float, np.ndarray], float]:
        """The k-th largest log|mu| (zero where the k-th multiplier crosses the circle)."""
        def g(x: np.ndarray, p: float, t: np.ndarray) -> float:
            _, J, blocks = self.hb.jacobian(x, p)
            rates = np.sort(self.hb.exponents(J, blocks).real)[::-1] * 2 * np.pi / blocks[-1]
            return float(rates[k])
        return g

    def rate(self, i: int, k: int) -> float:
        return float(np.sort(self.lam[i].real)[::-1][k] * 2 * np.pi / self.Ws[i])

    def counts(self) -> list[tuple[int, int, int]]:
        return [classify(self.lam[i], self.Ws[i]) for i in range(self.Ws.size)]

    def stability_changes(self, folds: set[int]) -> list[SpecialPoint]:
        counts = self.counts()
        found = []
        for i in range(len(counts) - 1):
            a, b = counts[i], counts[i + 1]
            changes = [kind for j, kind in
                       ((1, "period-doubling"), (2, "neimark-sacker"), (0, "branch"))
                       if a[j] != b[j] and not (j == 0 and i in folds)]
            for kind in changes:
                self.check()
                k = sum(a) if sum(b) > sum(a) else sum(b)  # the multiplier that crosses
                at = None
                if k < self.lam.shape[1]:
                    at = refine(self.hb, self.branch, i, self.growth(k), self.rate(i, k),
                                self.rate(i + 1, k))
                found.append(self.point(i, kind, at))
        return found

    def windows(self, counts: list[tuple[int, int, int]]) -> list[SpecialPoint]:
        """The changes of stability of windows narrower than a step.

        Where the largest rate of the stable multipliers has a sampled local maximum at
        point i near the circle (within WINDOW_FACTOR times its rise from the lower
        neighbour), or the smallest rate of the unstable ones a local minimum, the step
        towards the higher (lower) neighbour and then the other are searched by at most
        WINDOW_PROBES corrected points for a crossing, each crossing located by
        :func:`refine` between them.  At most WINDOW_SHARE corrected points per branch
        point in all.
        """
        budget = int(WINDOW_SHARE * len(counts)) + WINDOW_PROBES
        found: list[SpecialPoint] = []
        edge = math.log1p(STABILITY_TOL)
        width = self.lam.shape[1]
        for i in range(1, len(counts) - 1):
            if not counts[i - 1] == counts[i] == counts[i + 1]:
                continue
            u = sum(counts[i])
            for k, sign in ((u, 1.0), (u - 1, -1.0)):
                if budget <= 0 or not 0 <= k < width:
                    continue
                r = [sign * (self.rate(j, k) - edge) for j in (i - 1, i, i + 1)]
                # r < 0 at all three; a window where r rises above 0 between them
                rise = r[1] - min(r[0], r[2])
                if not (r[1] > r[0] and r[1] >= r[2] and -r[1] < WINDOW_FACTOR * rise):
                    continue
                sides = (i, i - 1) if r[2] >= r[0] else (i - 1, i)
                for j in sides:
                    self.check()
                    more, used = self.window(j, k, sign, edge, min(budget, WINDOW_PROBES))
                    budget -= used
                    found += more
                    if more or budget <= 0:
                        break
        return found

    def window(self, i: int, k: int, sign: float, edge: float, probes: int
               ) -> tuple[list[SpecialPoint], int]:
        """Search step i -> i+1 for sign * (rate k - edge) > 0 by up to ``probes``
        corrected points (each halving the gap beside the highest so far); the two
        crossings around the first point found there, and the points used."""
        growth = self.growth(k)
        b = arc(self.branch, i)
        if not b > 0:
            return [], 0
        samples = [(0.0, sign * (self.rate(i, k) - edge)),
                   (b, sign * (self.rate(i + 1, k) - edge))]
        for used in range(1, probes + 1):
            top = max(range(len(samples)), key=lambda m: samples[m][1])
            if top == 0:
                gap = 0
            elif top == len(samples) - 1:
                gap = top - 1
            else:
                gap = top if samples[top + 1][1] >= samples[top - 1][1] else top - 1
            sigma = 0.5 * (samples[gap][0] + samples[gap + 1][0])
            at = probe(self.hb, self.branch, i, sigma)
            if at is None:
                return [], used
            x, p, t = at
            f = sign * (growth(x, p, t) - edge)
            samples.insert(gap + 1, (sigma, f))
            if f > 0:
                inside = self.counts_at(x, p)
                before = classify(self.lam[i], self.Ws[i])
                crossings = []
                for lo, hi in ((samples[gap], samples[gap + 1]),
                               (samples[gap + 1], samples[gap + 2])):
                    # the crossing of the circle itself (rate 0), as stability_changes
                    located = refine(self.hb, self.branch, i,
                                     lambda x, p, t: sign * growth(x, p, t),
                                     lo[1] + sign * edge, hi[1] + sign * edge,
                                     span=(lo[0], hi[0]))
                    # every count that changes, as between two branch points
                    crossings += [self.point(i, kind, located or (x, p)) for j, kind in
                                  ((1, "period-doubling"), (2, "neimark-sacker"),
                                   (0, "branch")) if inside[j] != before[j]]
                return crossings, used
        return [], probes

    def counts_at(self, x: np.ndarray, p: float) -> tuple[int, int, int]:
        _, J, blocks = self.hb.jacobian(x, p)
        return classify(self.hb.exponents(J, blocks), blocks[-1])

    def slope(self, j: int) -> Callable[[np.ndarray, float, np.ndarray], float]:
        """d(amplitude of quantity j)/d(arc) by a central difference along the tangent."""
        sx, sp = self.branch.sx, self.branch.sp

        def g(x: np.ndarray, p: float, t: np.ndarray) -> float:
            h = ARC_STEP
            up = self.hb.amplitude(x + h * sx * t[:-1], p + h * sp * t[-1], j)
            down = self.hb.amplitude(x - h * sx * t[:-1], p - h * sp * t[-1], j)
            return float((up - down) / (2 * h))
        return g

    def peaks(self, amplitudes: np.ndarray) -> list[SpecialPoint]:
        """Interior maxima of each quantity's amplitude (points, quantities) along the arc."""
        found = []
        for j, name in enumerate(self.names):
            a = amplitudes[:, j]
            top = float(np.max(a, initial=0.0))
            for i in range(1, a.size - 1):
                if not (a[i] > a[i - 1] and a[i] >= a[i + 1]
                        and a[i] - max(a[i - 1], a[i + 1]) > PEAK_MARGIN * a[i]
                        and a[i] > 1e-9 * top):
                    continue
                self.check()
                g = self.slope(j)
                here = g(self.branch.x[i], self.branch.p[i], self.branch.tangents[i])
                k = i if here > 0 else i - 1  # the bracket [k, k+1] where the slope turns
                left = here if k == i else g(self.branch.x[k], self.branch.p[k],
                                             self.branch.tangents[k])
                right = here if k == i - 1 else g(self.branch.x[k + 1], self.branch.p[k + 1],
                                                  self.branch.tangents[k + 1])
                at = refine(self.hb, self.branch, k, g, left, right)
                if at is None:  # no sign change of the slope: the sampled maximum
                    at = (self.branch.x[i], self.branch.p[i])
                found.append(self.point(k, "peak", at, name))
        return found


def special_points(hb: BranchEquations, branch: Branch, lam: np.ndarray, Ws: np.ndarray,
                   amplitudes: np.ndarray, deadline: Deadline = NO_DEADLINE
                   ) -> tuple[SpecialPoint, ...]:
    """Folds, changes of stability and peaks of a branch, in the order of the arc.

    Parameters
    ----------
    hb : BranchEquations
        The equations the branch solves.
    branch : Branch
        The continued points with their tangents.
    lam : numpy.ndarray
        (points, 2n) Floquet exponents of every point.
    Ws : numpy.ndarray
        (points,) base frequencies.
    amplitudes : numpy.ndarray
        (points, quantities) amplitudes of the coordinates and outputs (``hb.names()``).
    deadline : Deadline, optional
        The run's time limit, checked before each refinement.

    Returns
    -------
    tuple of SpecialPoint
    """
    locator = Locator(hb, branch, lam, Ws, deadline)
    folds, near = locator.folds()
    found = (folds + locator.stability_changes(near) + locator.windows(locator.counts())
             + locator.peaks(amplitudes))
    found.sort(key=lambda sp: sp.index)
    return tuple(found)


__all__ = ["SpecialPoint", "SPECIAL_KINDS", "STABILITY_TOL", "classify", "special_points"]
