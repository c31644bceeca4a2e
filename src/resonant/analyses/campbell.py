"""The Campbell diagram of a rotor: its modes tracked over the speed, the critical speeds
where a branch meets an excitation order, and the threshold speed of instability.

The rotor is any :class:`~resonant.system.base.LinearSystem` with a speed parameter
(``[matrices]`` with ``G`` and ``speed``, or energies with Omega in T): M q'' +
(C + Omega G) q' + K(Omega) q = 0.  The modes are followed by
:func:`resonant.analyses.rotor_tracking.track_modes` (MAC between neighbouring speeds,
the step halved where the assignment is ambiguous); the critical speeds (omega_j(Omega)
= r Omega) and the threshold (Re s_j(Omega) = 0) are found by Brent's method on the
followed branch, to a tolerance, not read off the grid.  Conventions (docs/rotors.md):
speeds and frequencies in rad/s (the chart in rpm and Hz), the log decrement
-2 pi Re s / Im s, forward whirl in the direction of a positive spin (from x towards y).

Examples
--------
>>> import resonant
>>> m = resonant.loads('''
... [parameters]
... Omega = 0
... [matrices]
... M = [[1, 0], [0, 1]]
... K = [[100, 0], [0, 100]]
... C = [[0.2, 0], [0, 0.2]]
... speed = "Omega"
... [coordinates]
... x = "x"
... y = "y"
... ''')
>>> result = campbell(m.linearize(), np.linspace(0, 20, 5), modes=2)
>>> [(round(c.speed, 6), c.whirl) for c in result.critical_speeds]
[(9.9995, 'none'), (9.9995, 'none')]
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import (
    COLORS,
    Chart,
    Charts,
    Curve,
    Marker,
    Rule,
    charts_svg,
    check_plot_path,
    draw_figure,
    save_figure,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem
from ..modal import STABILITY_TOLERANCE, modal_assurance
from ..model.units_display import HZ, ResultUnits, Shown, angular_shown
from ..system.base import LinearSystem
from ..tables import ResultTable
from .result_fields import FieldsJSON, saved
from .results_json import Saved, floats_json
from .rotor_tracking import (
    ModeSolver,
    Tracked,
    branch_value,
    check_speeds,
    crossings,
    find_root,
    motion_kinds,
    precession,
    track_modes,
    whirl_label,
    whirl_pairs,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: rad/s per rpm
RPM = 2 * math.pi / 60
#: the relative tolerance (of the largest speed) of critical speeds and thresholds
SPEED_TOLERANCE = 1e-10


@dataclass(frozen=True)
class CriticalSpeed(FieldsJSON):
    """A speed where a branch's damped natural frequency equals an excitation order times
    the speed (omega_j = r Omega).

    Attributes
    ----------
    speed : float
        The critical speed (rad/s).
    mode : int
        The branch (from 1, in the order at the first speed).
    order : float
        The excitation order r (1 for unbalance, 2 for a bent shaft or a crack, ...).
    frequency : float
        omega_j there (rad/s).
    whirl : str
        ``"forward"``, ``"backward"`` or ``"none"``.
    """

    speed: float = saved(key="speed_rad_s")
    mode: int = saved()
    order: float = saved()
    frequency: float = saved(key="frequency_rad_s")
    whirl: str = saved()

    def _derived_json(self) -> dict[str, Any]:
        return {"speed_rpm": self.speed / RPM}


@dataclass(frozen=True)
class StabilityThreshold(FieldsJSON):
    """The lowest speed of the range where a mode's damping crosses zero.

    Attributes
    ----------
    speed : float or None
        The threshold (rad/s); None where no mode crosses in the range.
    mode : int or None
        The branch that goes unstable (from 1).
    frequency : float or None
        Its frequency there (rad/s).
    whirl : str
        Its whirl there ("" without a threshold).
    verdict : str
        ``"threshold"``, ``"stable in range"`` or ``"unstable in range"`` (unstable at
        the first speed already).
    """

    speed: float | None = saved(key="speed_rad_s")
    mode: int | None = saved()
    frequency: float | None = saved(key="frequency_rad_s")
    whirl: str = saved()
    verdict: str = saved()

    def _derived_json(self) -> dict[str, Any]:
        return {"speed_rpm": None if self.speed is None else self.speed / RPM}


@dataclass(frozen=True)
class Campbell(FieldsJSON):
    """The modes of a rotor over its speed, with critical speeds and stability.

    Attributes
    ----------
    title : str
        The model's title.
    speed_parameter : str
        The speed parameter.
    coordinates : tuple of str
        The coordinates.
    speeds : ndarray
        The speeds (rad/s), the grid and the points refinement added, shape (P,).
    eigenvalues : ndarray
        s of each tracked branch at each speed, shape (P, k).
    precession : ndarray
        The direction of precession of each branch at each speed (+1 circular forward,
        -1 circular backward; :func:`resonant.analyses.rotor_tracking.precession`).
    mac : ndarray
        The MAC of each branch to the speed before, shape (P, k).
    orders : tuple of float
        The excitation orders.
    critical_speeds : tuple of CriticalSpeed
        In ascending speed; speeds equal to the root's tolerance (the forward and
        backward whirl of an isotropic rotor without gyroscopic coupling) backward first,
        whatever order the eigen-solver gave the degenerate pair in.
    threshold : StabilityThreshold
        The onset of instability in the range.
    refined : int
        Speeds that refinement added.
    warnings : tuple of str
    motion : tuple of str
        Each branch's kind at the first speed, ``"lateral"``, ``"axial"`` or
        ``"torsional"`` (:func:`resonant.analyses.rotor_tracking.motion_kinds`); empty for
        a rotor with lateral coordinates only.

    Examples
    --------
    >>> import resonant
    >>> r = resonant.load("examples/rotors/jeffcott_rotor.toml").campbell()
    >>> [(round(c.speed, 1), c.whirl) for c in r.critical_speeds]    # rad/s: sqrt(k/m)
    [(316.2, 'backward'), (316.2, 'forward')]
    """

    title: str
    speed_parameter: str
    coordinates: tuple[str, ...]
    speeds: np.ndarray = saved(key="speeds_rad_s", axes=(None,))
    eigenvalues: np.ndarray = saved(axes=("speeds", None))
    precession: np.ndarray = saved(axes=("speeds", None))
    mac: np.ndarray = saved(axes=("speeds", None))
    orders: tuple[float, ...] = saved()
    critical_speeds: tuple[CriticalSpeed, ...] = saved()
    threshold: StabilityThreshold = saved(key="stability_threshold")
    refined: int = saved(0, required=True)
    warnings: tuple[str, ...] = field(default=())
    motion: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def frequencies(self) -> np.ndarray:
        """The damped natural frequencies |Im s| (rad/s), shape (P, k)."""
        result: np.ndarray = np.abs(self.eigenvalues.imag)
        return result

    @property
    def damping_ratios(self) -> np.ndarray:
        """-Re s / |s| of each branch, shape (P, k)."""
        size = np.abs(self.eigenvalues)
        with np.errstate(invalid="ignore", divide="ignore"):
            result: np.ndarray = np.where(size > 0, -self.eigenvalues.real / size, 0.0)
        return result

    @property
    def log_decrements(self) -> np.ndarray:
        """The logarithmic decrement -2 pi Re s / Im s of each branch (inf where Im s = 0).
        """
        with np.errstate(invalid="ignore", divide="ignore"):
            result: np.ndarray = -2 * np.pi * self.eigenvalues.real / self.frequencies
        return result

    @property
    def whirl(self) -> tuple[tuple[str, ...], ...]:
        """The whirl label of each branch at each speed (P tuples of k)."""
        return tuple(tuple(whirl_label(v) for v in row) for row in self.precession)

    def _derived_json(self) -> dict[str, Any]:
        """The numbers for a reader of the JSON (rpm, Hz, damping, whirl), derived from the
        fields."""
        return {
            "conventions": {"speed": "rad/s (speed_rpm: rev/min)",
                            "frequency": "damped natural frequency |Im s| in rad/s",
                            "log_decrement": "-2 pi Re(s) / Im(s)",
                            "whirl": "forward: in the direction of the spin, from x "
                                     "towards y"},
            "speeds_rpm": floats_json(self.speeds / RPM),
            "frequencies_rad_s": floats_json(self.frequencies),
            "frequencies_hz": floats_json(self.frequencies / (2 * np.pi)),
            "damping_ratios": floats_json(self.damping_ratios),
            "log_decrements": floats_json(self.log_decrements),
            "whirl": [list(row) for row in self.whirl]}

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        shape = np.shape(values["eigenvalues"])
        for key in ("precession", "mac"):
            if np.shape(values[key]) != shape:
                raise reader.error(f"has shape {np.shape(values[key])}, not {shape} (that "
                                   "of 'eigenvalues')", key)
        if values.get("refined", 0) < 0:
            raise reader.error("is negative", "refined")

    def summary(self, units: ResultUnits | None = None) -> str:
        """The text ``resonant campbell`` prints: the modes at the first and last speed,
        the critical speeds and the stability threshold.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``: frequencies and speeds in the frequency unit
            chosen; default Hz and rpm).

        Returns
        -------
        str
        """
        return campbell_text(self, units)

    def chart(self, damping: str = "log_decrement") -> Charts:
        """The Campbell diagram (frequency in Hz against speed in rpm, with the excitation
        orders and the critical speeds) above the damping of each branch.

        Parameters
        ----------
        damping : {"log_decrement", "damping_ratio"}
            What the lower panel shows.

        Returns
        -------
        resonant.charts.Charts
        """
        return campbell_chart(self, damping)

    def plot(self, path: str | os.PathLike[str] | None = None, ax: Axes | None = None,
             damping: str = "log_decrement") -> Figure:
        """Draw :meth:`chart` (and save it where ``path`` says).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        ax : matplotlib.axes.Axes or sequence of two, optional
            Draw into the caller's axes.
        damping : {"log_decrement", "damping_ratio"}
            The lower panel.

        Returns
        -------
        matplotlib.figure.Figure
        """
        check_plot_path(path)
        fig = draw_figure(self.chart(damping), ax)
        return save_figure(fig, path)

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "campbell")


# -- the analysis ----------------------------------------------------------------------------

def speed_parameter(system: LinearSystem, speed: str | None) -> str:
    """The speed parameter: ``speed``, else the model's (``[matrices]`` ``speed``).

    Examples
    --------
    >>> import resonant
    >>> speed_parameter(resonant.load("examples/rotors/jeffcott_rotor.toml").linearize(), None)
    'Omega'
    """
    model = system.model
    if speed is None:
        speed = system.speed
    if speed is None:
        raise ModelError(Problem("the rotor's speed parameter is not named: give speed = "
                                 "\"NAME\" in [matrices] or the speed argument",
                                 system.source, "matrices", "speed"))
    if model is not None and speed not in model.parameter_values:
        raise ModelError(Problem(f"the speed parameter {speed!r} is not a parameter of the "
                                 "model", system.source, "parameters", speed))
    return speed


#: the order of critical speeds that are equal to the root's tolerance
WHIRL_ORDER = {"backward": 0, "forward": 1, "none": 2}


def _order_gap(order: float) -> Callable[[complex, float], float]:
    """omega_j - r Omega: zero at a critical speed of order r."""
    def gap(s: complex, speed: float) -> float:
        return abs(s.imag) - order * speed
    return gap


def _critical_speeds(solver: ModeSolver, track: Tracked, orders: Sequence[float],
                     pairs: list[tuple[int, int]], tolerance: float) -> list[CriticalSpeed]:
    found = []
    for j in range(track.eigenvalues.shape[1]):
        for r in orders:
            gap = track.frequencies[:, j] - r * track.speeds
            for i in crossings(gap):
                reference, target = track.shapes[i, :, j], complex(track.eigenvalues[i, j])
                value = branch_value(solver, reference, _order_gap(r), target)
                speed = find_root(value, float(track.speeds[i]), float(track.speeds[i + 1]),
                                  tolerance)
                s, q = _continued(solver, reference, speed, target)
                found.append(CriticalSpeed(speed, j + 1, float(r), abs(s.imag),
                                           whirl_label(float(precession(q[:, None],
                                                                        pairs)[0]))))
    # a degenerate pair crosses at one speed up to rounding, and which of its two modes the
    # solver numbers first is the platform's: the whirl orders it, not the rounding
    return sorted(found, key=lambda c: (round(c.speed / tolerance), WHIRL_ORDER[c.whirl],
                                        c.mode))


def _continued(solver: ModeSolver, reference: np.ndarray, speed: float, target: complex
               ) -> tuple[complex, np.ndarray]:
    """The mode at ``speed`` continuing the branch whose shape is ``reference`` (and
    eigenvalue ``target``) at a neighbouring speed."""
    s, q = solver.near(speed, target)
    best = int(np.argmax(modal_assurance(reference[:, None], q, solver.mass)[0]))
    return complex(s[best]), q[:, best]


def _threshold_root(value: Callable[[float], float], low: float, high: float,
                    tolerance: float, marginal: float) -> float:
    """The speed in [low, high] where a followed branch's Re s crosses zero upwards; the
    bracket's start where the branch is marginal there already (|Re s| within the kernel's
    stability tolerance ``marginal``, with no change of sign to find: an undamped rotor at
    rest whose cross coupling grows with the speed)."""
    try:
        return find_root(value, low, high, tolerance)
    except AnalysisError:
        if value(low) >= -marginal:
            return low
        raise


def _threshold(solver: ModeSolver, track: Tracked, pairs: list[tuple[int, int]],
               tolerance: float) -> StabilityThreshold:
    """The lowest speed where some branch's Re s crosses from below zero to above."""
    scale = np.maximum(np.abs(track.eigenvalues), 1.0)
    real = track.eigenvalues.real
    # a real part within the kernel's tolerance is 0: an undamped rotor is marginal
    real = np.where(np.abs(real) <= STABILITY_TOLERANCE * scale, 0.0, real)
    # the grid's Re s solved again near each eigenvalue before it is a verdict (a sparse
    # rotor's lowest modes carry some 1e-9 |s| of noise in Re s: an undamped rotor is no
    # threshold)
    def re_near(i: int, j: int, at: int) -> float:
        return branch_value(solver, track.shapes[i, :, j], lambda s, w: s.real,
                            complex(track.eigenvalues[i, j]))(float(track.speeds[at]))

    unstable = [int(j) for j in np.argsort(-real[0]) if real[0, j] > 0 and
                re_near(0, int(j), 0) > STABILITY_TOLERANCE * float(scale[0, j])]
    if unstable:
        j = unstable[0]
        return StabilityThreshold(None, j + 1, float(track.frequencies[0, j]), "",
                                  "unstable in range")
    best: tuple[float, int, complex, np.ndarray] | None = None
    for j in range(real.shape[1]):
        # a branch marginal at the first speed and unstable at the next crosses there too
        start = [0] if len(real) > 1 and real[0, j] == 0 and real[1, j] > 0 else []
        for i in start + [i for i in crossings(real[:, j]) if real[i + 1, j] > 0]:
            if best is not None and track.speeds[i] >= best[0]:
                break
            marginal = STABILITY_TOLERANCE * float(scale[i, j])
            if re_near(i, j, i + 1) <= marginal:
                continue    # no crossing: the grid's Re s was noise
            reference, target = track.shapes[i, :, j], complex(track.eigenvalues[i, j])
            value = branch_value(solver, reference, lambda s, w: s.real, target)
            speed = _threshold_root(value, float(track.speeds[i]),
                                    float(track.speeds[i + 1]), tolerance, marginal)
            s, q = _continued(solver, reference, speed, target)
            best = (speed, j, s, q)
            break
    if best is None:
        return StabilityThreshold(None, None, None, "", "stable in range")
    speed, j, s, q = best
    return StabilityThreshold(speed, j + 1, abs(s.imag),
                              whirl_label(float(precession(q[:, None], pairs)[0])),
                              "threshold")


def _section_defaults(system: LinearSystem, speeds: Sequence[float] | np.ndarray | None,
                      modes: int | None, orders: Sequence[float] | None, speed: str | None
                      ) -> tuple[np.ndarray, int, Sequence[float], str | None]:
    """What the call leaves out, from the model's ``[campbell]`` section."""
    spec = system.model.campbell_section if system.model is not None else None
    if speeds is None:
        if spec is None:
            raise ModelError(Problem("no speeds: give them, or a [campbell] section with "
                                     "from, to and points", system.source, "campbell", "to"))
        speeds = np.linspace(spec.start, spec.stop, spec.points)
    if spec is not None:
        modes = spec.modes if modes is None else modes
        orders = spec.orders if orders is None else orders
        speed = spec.speed if speed is None else speed
    return (np.asarray(speeds, dtype=float), 6 if modes is None else modes,
            (1.0,) if orders is None else orders, speed)


def campbell(system: LinearSystem, speeds: Sequence[float] | np.ndarray | None = None, *,
             modes: int | None = None, orders: Sequence[float] | None = None,
             speed: str | None = None, deadline: Deadline = NO_DEADLINE) -> Campbell:
    """The Campbell diagram: the ``modes`` lowest modes at the first speed followed over
    ``speeds``, the critical speeds of each excitation order and the stability threshold.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speeds : sequence of float, optional
        The speeds (rad/s), ascending; refinement adds speeds where the tracking needs.
        Default: the ``[campbell]`` section's range.
    modes : int, optional
        The branches followed (default: the section's, else 6).
    orders : sequence of float, optional
        The excitation orders r (critical speeds where omega_j = r Omega; default the
        section's, else 1).
    speed : str, optional
        The speed parameter (default: the model's ``[matrices]`` ``speed``).
    deadline : Deadline, optional

    Returns
    -------
    Campbell

    Examples
    --------
    >>> import resonant
    >>> r = campbell(resonant.load("examples/rotors/jeffcott_rotor.toml").linearize(),
    ...              np.linspace(0, 500, 11), modes=2)
    >>> round(r.critical_speeds[0].speed, 3)
    316.225
    """
    speeds, modes, orders, speed = _section_defaults(system, speeds, modes, orders, speed)
    name = speed_parameter(system, speed)
    values = check_speeds(speeds, system.source)
    if not orders or not all(math.isfinite(r) and r > 0 for r in orders):
        raise ModelError(Problem("the excitation orders must be positive numbers",
                                 system.source, "campbell", "orders"))
    track = track_modes(system, name, values, modes, deadline)
    solver = ModeSolver(system, name, modes, deadline)
    pairs = whirl_pairs(system.coordinates)
    tolerance = SPEED_TOLERANCE * max(abs(float(values[-1])), 1.0)
    warnings = []
    if track.ambiguous:
        warnings.append(f"the modes could not be told apart at {len(track.ambiguous)} "
                        "speed(s) even with a step halved "
                        f"{8} times (first at {track.ambiguous[0]:.6g} rad/s): the branches "
                        "there may be exchanged; give more speeds")
    if not pairs:
        warnings.append("no (NAME_x, NAME_y) coordinate pairs: no whirl direction")
    if track.rigid:
        warnings.append(f"{track.rigid} rigid-body eigenvalue(s) (s = 0: a free axial, "
                        "torsional or lateral motion) left out of the branches")
    return Campbell(system.title, name, tuple(system.coordinates), track.speeds,
                    track.eigenvalues, precession(track.shapes, pairs), track.mac,
                    tuple(float(r) for r in orders),
                    tuple(_critical_speeds(solver, track, orders, pairs, tolerance)),
                    _threshold(solver, track, pairs, tolerance), track.refined,
                    tuple(warnings), motion_kinds(track.shapes[0], system.coordinates))


def log_decrement(system: LinearSystem, at: float, mode: int = 1, *, speed: str | None = None,
                  deadline: Deadline = NO_DEADLINE) -> float:
    """The logarithmic decrement -2 pi Re s / Im s of one mode at one speed.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    at : float
        The speed (rad/s).
    mode : int
        The mode, counted from 1 in the kernel's order (the lowest first:
        :func:`resonant.modal.gyroscopic_modes`).
    speed : str, optional
        The speed parameter (default: the model's).
    deadline : Deadline, optional

    Returns
    -------
    float
        Positive for a decaying mode, negative for a growing one; inf for a mode that
        does not oscillate (Im s = 0).

    Examples
    --------
    >>> import resonant
    >>> rotor = resonant.load("examples/rotors/jeffcott_rotor.toml").linearize()
    >>> round(log_decrement(rotor, 0.0, 1), 6)
    0.029804
    """
    name = speed_parameter(system, _section_defaults_speed(system, speed))
    check_speeds(np.array([at], dtype=float), system.source, "speed", least=1)
    s, _ = ModeSolver(system, name, mode, deadline).modes(np.array([at], dtype=float))[0]
    value = complex(s[mode - 1])
    if value.imag == 0:
        return math.inf
    return float(-2 * np.pi * value.real / abs(value.imag))


def _section_defaults_speed(system: LinearSystem, speed: str | None) -> str | None:
    """The speed parameter given, else the ``[campbell]`` section's (if any)."""
    spec = system.model.campbell_section if system.model is not None else None
    return spec.speed if speed is None and spec is not None else speed


# -- text and chart ----------------------------------------------------------------------------

def _branch_whirl(result: Campbell, j: int) -> str:
    labels = [whirl_label(v) for v in result.precession[:, j]]
    counts = {k: labels.count(k) for k in ("forward", "backward")}
    if not any(counts.values()):
        return ""
    return "F" if counts["forward"] >= counts["backward"] else "B"


def campbell_text(result: Campbell, units: ResultUnits | None = None) -> str:
    """The summary of a Campbell diagram (frequencies in Hz, speeds in rpm and rad/s, or
    both in the frequency unit ``units`` chooses).

    Parameters
    ----------
    result : Campbell
    units : ResultUnits, optional
        The display units (``--units``).

    Returns
    -------
    str

    Examples
    --------
    >>> import resonant
    >>> r = resonant.load("examples/rotors/jeffcott_rotor.toml").campbell()
    >>> "critical speeds" in campbell_text(r)
    True
    """
    speed = angular_shown(units, Shown("rpm", RPM))
    frequency = angular_shown(units, HZ)
    lines = [result.title or "Campbell diagram",
             f"speed {result.speed_parameter}: {speed(result.speeds[0]):.6g} to "
             f"{speed(result.speeds[-1]):.6g} {speed.text}, {len(result.speeds)} speeds "
             f"({result.refined} added by refinement)", ""]
    f = frequency(result.frequencies)
    rows = []
    for j in range(f.shape[1]):
        whirl = {"F": "forward", "B": "backward"}.get(_branch_whirl(result, j), "-")
        if j < len(result.motion) and result.motion[j] != "lateral":
            whirl = result.motion[j]
        rows.append((str(j + 1), whirl, f"{f[0, j]:.6g}", f"{f[-1, j]:.6g}",
                     f"{result.log_decrements[0, j]:.4g}", f"{result.log_decrements[-1, j]:.4g}"))
    # each column as wide as its widest cell: "torsional" and "backward" never shift a row
    lines.append(ResultTable(("mode", "whirl", f"f first [{frequency.text}]",
                              f"f last [{frequency.text}]", "log dec first", "log dec last"),
                             tuple(rows), align="rlrrrr").text(indent=""))
    lines += ["", "critical speeds (damped frequency = order x speed):"]
    if not result.critical_speeds:
        lines.append("  none in the range")
    else:
        lines.append(ResultTable(
            (f"speed [{speed.text}]", "[rad/s]", "mode", "order", "whirl"),
            tuple((f"{speed(c.speed):.6g}", f"{c.speed:.6g}", str(c.mode), f"{c.order:g}x",
                   c.whirl) for c in result.critical_speeds), align="rrrrl").text())
    t = result.threshold
    lines.append("")
    if t.verdict == "threshold" and t.speed is not None:
        lines.append(f"stability threshold: {speed(t.speed):.6g} {speed.text} ({t.speed:.6g} "
                     "rad/s), "
                     f"mode {t.mode} ({t.whirl}) goes unstable")
    elif t.verdict == "unstable in range":
        lines.append(f"unstable at the first speed already (mode {t.mode}): no threshold "
                     "in the range")
    else:
        lines.append("stable throughout the range: no stability threshold in it (not "
                     "extrapolated)")
    lines += [f"warning: {w}" for w in result.warnings]
    return "\n".join(lines) + "\n"


def campbell_chart(result: Campbell, damping: str = "log_decrement") -> Charts:
    """The Campbell diagram above the damping of each branch, as a chart description.

    Parameters
    ----------
    result : Campbell
    damping : {"log_decrement", "damping_ratio"}

    Returns
    -------
    resonant.charts.Charts

    Examples
    --------
    >>> import resonant
    >>> charts = campbell_chart(resonant.load("examples/rotors/jeffcott_rotor.toml").campbell())
    >>> len(charts.panels)
    2
    """
    if damping not in ("log_decrement", "damping_ratio"):
        raise ModelError(Problem("damping must be log_decrement or damping_ratio", "",
                                 "campbell", "damping"))
    rpm = result.speeds / RPM
    hz = result.frequencies / (2 * np.pi)
    lower = result.log_decrements if damping == "log_decrement" else result.damping_ratios
    curves, below = [], []
    for j in range(hz.shape[1]):
        whirl = _branch_whirl(result, j)
        kind = result.motion[j] if j < len(result.motion) else ""
        label = f"mode {j + 1}" + (f" ({whirl})" if whirl else "") + \
            (f" {kind}" if kind and kind != "lateral" else "")
        color = COLORS[j % len(COLORS)]
        dash = "3.7 1.6" if whirl == "B" else None
        curves.append(Curve(rpm, hz[:, j], label, color=color, dash=dash))
        below.append(Curve(rpm, lower[:, j], label, color=color, dash=dash))
    for r in result.orders:
        curves.append(Curve(rpm, r * result.speeds / (2 * np.pi), f"{r:g}x", color="#7f7f7f",
                            width=1.0, dash="1 1.65"))
    markers = tuple(Marker(c.speed / RPM, c.frequency / (2 * np.pi), "#000000", "dot",
                           "critical speed") for c in result.critical_speeds)
    rules: tuple[Rule, ...] = ()
    if result.threshold.speed is not None:
        rules = (Rule(result.threshold.speed / RPM, color="#d62728", dash="3.7 1.6",
                      label="stability threshold"),)
    xlim = (float(rpm[0]), float(rpm[-1]))
    top = Chart(tuple(curves), "speed [rpm]", "frequency [Hz]", xlim, markers=markers,
                rules=rules, ylim=(0.0, float(np.nanmax(hz)) * 1.1 or 1.0),
                title="Campbell diagram")
    label = "log decrement" if damping == "log_decrement" else "damping ratio"
    bottom = Chart(tuple(below), "speed [rpm]", label, xlim,
                   rules=(Rule(0.0, vertical=False),) + rules, legend="none")
    return Charts((top, bottom), title=result.title, heights=(2.0, 1.0), size=(7.0, 6.0))


__all__ = ["campbell", "Campbell", "log_decrement", "CriticalSpeed", "StabilityThreshold",
           "campbell_text", "campbell_chart", "speed_parameter", "RPM"]
