"""The undamped critical speed map of a ``[rotor]``: its critical speeds against the
stiffness of its bearings (docs/rotors.md).

Every bearing is replaced by a direct stiffness k on x and y (kxx = kyy = k; no cross
coupling, no damping; a pedestal and its support stay), and at each k the critical speeds
of an excitation order r are the speeds where a mode's frequency is r Omega: with
s = i r Omega the undamped equation M q'' + Omega G q' + K(k) q = 0 becomes
K(k) q = Omega^2 (r^2 M - i r G) q, solved directly
(:func:`resonant.modal.synchronous_speeds`), not tracked over a speed grid.  Soft
bearings give the rigid-rotor modes (bouncing and rocking, rising as sqrt(k)); stiff ones
the pinned shaft's bending modes (a plateau).

With ``damped=True`` the bearings keep their damping and cross-coupled stiffness (kxy,
kyx, c..; numbers, expressions or tables at each speed) and only their direct stiffness
kxx = kyy becomes k; the critical speeds are then the **damped** ones, where a mode's
damped frequency |Im s| equals r Omega of M q'' + (C(Omega) + Omega G) q' + K(k, Omega) q =
0.  They are found on a speed grid without tracking: the number of modes whose frequency
is above r Omega changes at each, and the change is bisected to
:data:`resonant.analyses.campbell.SPEED_TOLERANCE`; each comes with the damping ratio of
its mode there.

Examples
--------
>>> import resonant
>>> rotor = resonant.load("examples/rotors/friswell_5_9_1.toml").linearize()
>>> result = critical_speed_map(rotor, [1e6], modes=2)
>>> (result.speeds[0, 0] * 60 / (2 * np.pi)).round(1).tolist()   # rpm, 1x
[825.1, 829.9]
>>> result.whirl[0][0]
('backward', 'forward')
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import COLORS, Chart, Charted, Curve
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem
from ..memory import dense_matrix, require
from ..modal import ZERO_STATE, gyroscopic_modes, overdamped, synchronous_speeds
from ..model.rotor import Bearing
from ..system.base import LinearSystem
from ..tables import ResultTable
from .campbell import RPM, SPEED_TOLERANCE, speed_parameter
from .result_fields import Codec, FieldsJSON, Shape, saved
from .results_json import Saved, floats_json
from .rotor_tracking import ModeSolver, check_speeds, precession, whirl_label, whirl_pairs
from .unbalance import coefficient_values


def _whirl_read(saved_data: Saved, key: str, shape: Shape
                ) -> tuple[tuple[tuple[str, ...], ...], ...]:
    blocks = saved_data.value(key)
    if not isinstance(blocks, list) or not all(
            isinstance(block, list) and all(isinstance(row, list) and
                                            all(isinstance(w, str) for w in row)
                                            for row in block) for block in blocks):
        raise saved_data.error("is not a list (stiffness) of lists (orders) of lists of "
                               "whirl labels", key)
    return tuple(tuple(tuple(row) for row in block) for block in blocks)


def _nested_shape(whirl: tuple[tuple[tuple[str, ...], ...], ...]) -> tuple[int, ...] | None:
    """(stiffness, orders, modes) of the nested labels, None where they are ragged."""
    rows = {len(block) for block in whirl}
    labels = {len(row) for block in whirl for row in block}
    if len(rows) > 1 or len(labels) > 1:
        return None
    return (len(whirl), rows.pop() if rows else 0, labels.pop() if labels else 0)


#: the whirl labels nested as the critical speeds (stiffness, orders, modes)
_WHIRL = Codec(lambda value: [[list(row) for row in block] for block in value], _whirl_read)

#: the most coordinates of a map (each stiffness is one dense complex eigenproblem)
MAX_MAP_COORDINATES = 2000
#: a damped critical speed's mode with |Im s| at most this fraction of |s| there is an
#: overdamped root the speed's gyroscopic coupling split into a pair, not a critical speed
SPLIT_ROOT = 1e-6
#: the most coordinates of a damped map (dense complex modes at every speed it tries)
MAX_DAMPED_MAP_COORDINATES = 400
#: the bearing stiffness values of a map by default (N/m): from, to and how many,
#: logarithmically spaced (``resonant speed-map``, the explore page)
MAP_STIFFNESS = (1e5, 1e9, 17)
#: the critical speeds per order of a map by default
MAP_MODES = 4


@dataclass(frozen=True)
class CriticalSpeedMap(FieldsJSON, Charted):
    """The undamped critical speeds of a rotor against its bearings' stiffness.

    Attributes
    ----------
    title : str
    stiffness : ndarray
        The bearings' direct stiffness k (N/m), shape (S,).
    orders : tuple of float
        The excitation orders r.
    speeds : ndarray
        The ``modes`` lowest critical speeds (rad/s) of each order at each k, shape
        (S, orders, modes); NaN where there are fewer.
    whirl : tuple
        Their whirl (``"forward"``, ``"backward"``, ``"none"``; "" where NaN), nested as
        ``speeds``.
    damped : bool
        Whether the bearings kept their damping and cross coupling (damped critical
        speeds), or not (undamped, no cross coupling).
    damping_ratios : ndarray or None
        A damped map's damping ratio -Re s / |s| of each critical speed's mode there, as
        ``speeds`` (None for an undamped map).
    """

    title: str
    stiffness: np.ndarray = saved(key="stiffness_N_m", axes=(None,))
    orders: tuple[float, ...] = saved()
    speeds: np.ndarray = saved(key="critical_speeds_rad_s", axes=("stiffness", "orders", None))
    whirl: tuple[tuple[tuple[str, ...], ...], ...] = saved(codec=_WHIRL)
    damped: bool = False
    damping_ratios: np.ndarray | None = saved(None, omit_none=True,
                                              axes=("stiffness", "orders", None))

    def __post_init__(self) -> None:
        freeze_fields(self)

    def _derived_json(self) -> dict[str, Any]:
        bearings = ("kxx = kyy = stiffness, their cross coupling and damping kept; damped "
                    "critical speeds (|Im s| = order x speed)" if self.damped else
                    "kxx = kyy = stiffness, no cross coupling, undamped")
        return {"conventions": {"bearings": bearings},
                "critical_speeds_rpm": floats_json(self.speeds / RPM)}

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        shape = np.shape(values["speeds"])
        if _nested_shape(values["whirl"]) != shape:
            raise reader.error(f"does not hold a label for each of the {shape} critical "
                               "speeds", "whirl")
        if values.get("damped", False) != (values.get("damping_ratios") is not None):
            raise reader.error("has damping ratios exactly when it is damped", "damped")

    def summary(self) -> str:
        """The critical speeds (rpm) at each stiffness, a row per stiffness.

        Returns
        -------
        str
        """
        lines = [self.title or "Critical speed map",
                 "damped: every bearing kxx = kyy = k, its cross coupling and damping kept "
                 "(damping ratio in brackets)" if self.damped else
                 "undamped; every bearing kxx = kyy = k (no cross coupling)", ""]
        for o, r in enumerate(self.orders):
            lines.append(f"{r:g}x critical speeds [rpm] (F forward, B backward whirl, N none: "
                         "no lateral motion):")
            rows = []
            for i, k in enumerate(self.stiffness):
                ratios = (self.damping_ratios[i, o] if self.damping_ratios is not None else
                          [math.nan] * len(self.whirl[i][o]))
                rows.append((f"{k:.4g}", *(
                    f"{v / RPM:.5g} {w[:1].upper()}" + (f" ({z:.3g})" if math.isfinite(z) else "")
                    if math.isfinite(v) else "-"
                    for v, w, z in zip(self.speeds[i, o], self.whirl[i][o], ratios))))
            # each column as wide as its widest cell, whatever the whirl and damping shown
            count = self.speeds.shape[2]
            lines.append(ResultTable(("k [N/m]", *(f"mode {j + 1}" for j in range(count))),
                                     tuple(rows), align="r" * (count + 1)).text())
        return "\n".join(lines) + "\n"

    def chart(self) -> Chart:
        """The critical speeds (rpm) against k (N/m), both axes logarithmic.

        Returns
        -------
        resonant.charts.Chart
        """
        curves = []
        for o, r in enumerate(self.orders):
            for j in range(self.speeds.shape[2]):
                curves.append(Curve(self.stiffness, self.speeds[:, o, j] / RPM,
                                    f"mode {j + 1}" + (f" ({r:g}x)" if len(self.orders) > 1
                                                       else ""),
                                    color=COLORS[j % len(COLORS)],
                                    dash=None if o == 0 else "3.7 1.6", marker="o"))
        xlim = (float(self.stiffness[0]), float(self.stiffness[-1]))
        return Chart(tuple(curves), "bearing stiffness [N/m]", "critical speed [rpm]", xlim,
                     ylog=True, xlog=True, title=("damped" if self.damped else "undamped") +
                     " critical speed map")


def _stiffness_pattern(bearing: Bearing, n: int, axes: tuple[int, ...] = (0, 1)
                       ) -> np.ndarray:
    """The stiffness matrix of one bearing of kxx = kyy = 1 (to the ground or its
    pedestal; ``axes`` (0,): kxx only, (1,): kyy only)."""
    out = np.zeros((n, n))
    for axis in axes:
        ends = [(bearing.station[axis], bearing.station[axis], 1.0)]
        if bearing.pedestal is not None:
            p = bearing.pedestal[axis]
            ends += [(bearing.station[axis], p, -1.0), (p, bearing.station[axis], -1.0),
                     (p, p, 1.0)]
        for row, column, sign in ends:
            out[row, column] += sign
    return out


def _without_bearings(K: np.ndarray, bearings: Sequence[Bearing]) -> np.ndarray:
    """The assembled constant stiffness with the bearings' constant coefficients taken
    out (those given as expressions or tables are speed terms, never in it)."""
    out = K.copy()
    for b in bearings:
        for key, value in b.coefficients:
            if key[0] != "k" or not isinstance(value, float):
                continue
            a, c = int(key[1] == "y"), int(key[2] == "y")
            ends = [(b.station[a], b.station[c], 1.0)]
            if b.pedestal is not None:
                ends += [(b.station[a], b.pedestal[c], -1.0), (b.pedestal[a], b.station[c],
                                                               -1.0),
                         (b.pedestal[a], b.pedestal[c], 1.0)]
            for row, column, sign in ends:
                out[row, column] -= sign * value
    return out


def critical_speed_map(system: LinearSystem, stiffness: Sequence[float] | np.ndarray, *,
                       modes: int = 4, orders: Sequence[float] = (1.0,), damped: bool = False,
                       speeds: Sequence[float] | np.ndarray | None = None,
                       deadline: Deadline = NO_DEADLINE) -> CriticalSpeedMap:
    """The critical speeds of a ``[rotor]`` at each bearing stiffness: undamped (no cross
    coupling), or damped (the bearings' damping and cross coupling kept).

    Parameters
    ----------
    system : LinearSystem
        A rotor from a ``[rotor]`` section (its bearings are known by name and place).
    stiffness : sequence of float
        The bearings' direct stiffness values k (N/m), positive, increasing.
    modes : int
        The lowest critical speeds kept per order.
    orders : sequence of float
        The excitation orders r.
    damped : bool
        Keep the bearings' damping and cross-coupled stiffness: the damped critical speeds
        (|Im s| = r Omega) and their damping ratios.
    speeds : sequence of float, optional
        A damped map's speed grid (rad/s, increasing), which brackets its critical speeds
        (those beyond it are not found); default the ``[campbell]`` range.
    deadline : Deadline, optional

    Returns
    -------
    CriticalSpeedMap

    Examples
    --------
    >>> import resonant
    >>> rotor = resonant.load("examples/rotors/friswell_5_9_5.toml").linearize()
    >>> damped = critical_speed_map(rotor, [1e6], modes=2, damped=True)
    >>> (damped.speeds[0, 0] * 60 / (2 * np.pi)).round(1).tolist()     # rpm, 1x
    [830.8, 835.7]
    """
    spec = system.given_matrices
    if spec is None or not spec.bearings:
        raise ModelError(Problem("the critical speed map needs a [rotor] with bearings",
                                 system.source, "rotor", "bearing"))
    k = np.asarray(stiffness, dtype=float).reshape(-1)
    if k.size < 1 or not np.all(np.isfinite(k) & (k > 0)) or np.any(np.diff(k) <= 0):
        raise ModelError(Problem("the bearing stiffness values must be positive and "
                                 "increasing (N/m)", system.source, "rotor", "bearing"))
    if not orders or not all(math.isfinite(r) and r > 0 for r in orders) or modes < 1:
        raise ModelError(Problem("orders must be positive numbers and modes at least 1",
                                 system.source, "campbell", "orders"))
    n = system.n
    if not damped and any(" pedestal " in t.where for t in spec.speed_terms):
        raise ModelError(Problem("a pedestal's coefficients depend on the speed, and the "
                                 "undamped map is solved for the speed directly: give "
                                 "damped=True (the damped map takes them at each speed)",
                                 system.source, "rotor", "pedestal"))
    if damped:
        return _damped_map(system, k, modes, tuple(float(r) for r in orders), speeds,
                           deadline)
    if n > MAX_MAP_COORDINATES:
        raise ModelError(Problem(f"the critical speed map is dense: at most "
                                 f"{MAX_MAP_COORDINATES} coordinates, the rotor has {n}",
                                 system.source, "rotor", "shaft"))
    require(6 * 16.0 * n * n, f"the critical speed map of {n} coordinates", "use fewer "
            "shaft elements")
    M, K0, G = (dense_matrix(a)
                for a in (spec.M, spec.K, spec.G if spec.G is not None else np.zeros((n, n))))
    base = _without_bearings(K0, spec.bearings)
    pattern = sum(_stiffness_pattern(b, n) for b in spec.bearings)
    pairs = whirl_pairs(system.coordinates)
    speeds = np.full((len(k), len(orders), modes), np.nan)
    whirl = []
    for i, value in enumerate(k):
        rows = []
        for o, r in enumerate(orders):
            found, shapes = synchronous_speeds(M, G, base + value * pattern, float(r))
            count = min(modes, len(found))
            speeds[i, o, :count] = found[:count]
            labels = [whirl_label(float(v)) for v in precession(shapes[:, :count], pairs)]
            rows.append(tuple(labels + [""] * (modes - count)))
        whirl.append(tuple(rows))
    return CriticalSpeedMap(system.title, k, tuple(float(r) for r in orders), speeds,
                            tuple(whirl))


def _damped_map_speeds(system: LinearSystem, speeds: Sequence[float] | np.ndarray | None
                       ) -> np.ndarray:
    """The speeds the damped map searches over: given, or the ``[campbell]`` range."""
    model = system.model
    if speeds is None:
        spec = None if model is None else model.campbell_section
        if spec is None:
            raise ModelError(Problem("the damped critical speed map needs a speed range: "
                                     "give speeds, or a [campbell] section with from, to "
                                     "and points", system.source, "campbell", "to"))
        speeds = np.linspace(spec.start, spec.stop, spec.points)
    return check_speeds(np.asarray(speeds, dtype=float), system.source)


def _damped_map(system: LinearSystem, stiffness: np.ndarray, modes: int,
                orders: tuple[float, ...], speeds: Sequence[float] | np.ndarray | None,
                deadline: Deadline) -> CriticalSpeedMap:
    """:func:`critical_speed_map` with the bearings' damping and cross coupling kept."""
    n = system.n
    if n > MAX_DAMPED_MAP_COORDINATES:
        raise ModelError(Problem(f"the damped critical speed map is dense: at most "
                                 f"{MAX_DAMPED_MAP_COORDINATES} coordinates, the rotor has "
                                 f"{n}", system.source, "rotor", "shaft"))
    grid = _damped_map_speeds(system, speeds)
    name = speed_parameter(system, None)
    require(8 * 16.0 * n * n, f"the damped critical speed map of {n} coordinates",
            "use fewer shaft elements")
    bearings = system.bearings
    pattern = sum(_stiffness_pattern(b, n) for b in bearings)
    solver = ModeSolver(system, name, 1, deadline)
    pairs = whirl_pairs(system.coordinates)
    tolerance = SPEED_TOLERANCE * max(abs(float(grid[-1])), 1.0)

    def direct(speed: float) -> np.ndarray:
        """The bearings' direct stiffness kxx, kyy at ``speed`` as assembled."""
        at = np.array([speed])
        values = system.parameters_along(name, at)
        out = np.zeros((n, n))
        for b in bearings:
            for key, value in b.coefficients:
                if key in ("kxx", "kyy"):
                    axis = int(key == "kyy")
                    one = _stiffness_pattern(b, n, axes=(axis,))
                    out += float(coefficient_values(value, at, values)[0]) * one
        return out

    def modes_at(speed: float, k: float) -> tuple[np.ndarray, np.ndarray]:
        M, C, K = (dense_matrix(a)
                   for a in solver.matrices(np.array([speed]))[0])
        deadline.check("while computing the damped critical speed map", "stiffness",
                       analysis=True)
        s, q = gyroscopic_modes(M, C, K - direct(speed) + k * pattern)
        size = np.abs(s)
        # an overdamped (real) root has no damped frequency to cross r Omega: counted, its
        # rounding-level |Im s| would put a critical speed at the grid's first speed, 0
        moving = (size > ZERO_STATE * max(1.0, float(size.max(initial=0.0)))) & ~overdamped(s)
        return s[moving], q[:, moving]

    def above(speed: float, k: float, r: float) -> int:
        return int(np.count_nonzero(np.abs(modes_at(speed, k)[0].imag) > r * speed))

    out = np.full((len(stiffness), len(orders), modes), np.nan)
    ratios = np.full_like(out, np.nan)
    whirl = []
    for i, k in enumerate(stiffness):
        rows = []
        for o, r in enumerate(orders):
            def count(w: float, k: float = float(k), r: float = r) -> int:
                return above(w, k, r)

            def mode(w: float, k: float = float(k)) -> tuple[np.ndarray, np.ndarray]:
                return modes_at(w, k)

            found = _crossings(count, mode, grid, r, modes, tolerance, pairs)
            for j, (speed, ratio, _) in enumerate(found):
                out[i, o, j], ratios[i, o, j] = speed, ratio
            rows.append(tuple([c[2] for c in found] + [""] * (modes - len(found))))
        whirl.append(tuple(rows))
    return CriticalSpeedMap(system.title, stiffness, orders, out, tuple(whirl), True, ratios)


def _crossings(count: Callable[[float], int],
               mode: Callable[[float], tuple[np.ndarray, np.ndarray]], grid: np.ndarray,
               r: float, modes: int, tolerance: float,
               pairs: Sequence[tuple[int, int]]
               ) -> list[tuple[float, float, str]]:
    """The lowest ``modes`` damped critical speeds of order ``r`` over ``grid``: each speed
    where the count of modes above r Omega changes, its mode's damping ratio and whirl.

    A change whose mode has a damped frequency below :data:`SPLIT_ROOT` of its |s| is no
    critical speed: an overdamped root that the speed's gyroscopic coupling has just split
    into a pair (|Im s| about proportional to Omega), met by r Omega at Omega = 0 only.
    """
    counts = [count(float(w)) for w in grid]
    speeds: list[float] = []
    for a, b, ca, cb in zip(grid[:-1], grid[1:], counts[:-1], counts[1:]):
        if ca != cb:
            speeds += _changes(count, float(a), float(b), ca, cb, tolerance)
    speeds.sort()
    found: list[tuple[float, float, str]] = []
    for j, speed in enumerate(speeds):
        if len(found) == modes:
            break
        # the mode whose frequency is r Omega there (the next nearest for a second critical
        # speed at the same place: a forward and a backward mode together)
        repeat = sum(1 for x in speeds[:j] if x == speed)
        s, q = mode(speed)
        best = int(np.argsort(np.abs(np.abs(s.imag) - r * speed),
                              kind="stable")[min(repeat, len(s) - 1)])
        if abs(s[best].imag) <= SPLIT_ROOT * abs(s[best]):
            continue
        found.append((speed, float(-s[best].real / abs(s[best])),
                      whirl_label(float(precession(q[:, [best]], pairs)[0]))))
    return found


def _changes(count: Callable[[float], int], low: float, high: float, at_low: int,
             at_high: int, tolerance: float) -> list[float]:
    """The speeds in (low, high) where the integer ``count`` changes, each bisected to
    ``tolerance`` (a bracket whose ends differ by more than one holds several)."""
    if high - low <= tolerance:
        return [0.5 * (low + high)] * abs(at_high - at_low)
    middle = 0.5 * (low + high)
    at_middle = count(middle)
    out = []
    if at_middle != at_low:
        out += _changes(count, low, middle, at_low, at_middle, tolerance)
    if at_middle != at_high:
        out += _changes(count, middle, high, at_middle, at_high, tolerance)
    return out


__all__ = ["critical_speed_map", "CriticalSpeedMap", "MAX_MAP_COORDINATES",
           "MAX_DAMPED_MAP_COORDINATES", "MAP_STIFFNESS", "MAP_MODES", "SPLIT_ROOT"]
