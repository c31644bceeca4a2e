"""The unbalance response of a rotor: the orbit of every station over a speed range.

An unbalance m e at angle phi (from x towards y at t = 0) on a station spinning at Omega
loads it with m e Omega^2 (cos(Omega t + phi), sin(Omega t + phi)); the stationary
response at each speed is one harmonic solve (:func:`resonant.analyses.kernel.solve_harmonic`)
of (K(Omega) - Omega^2 M + i Omega (C + Omega G)) z = F.  A station's motion
x = Re(X e^(i Omega t)), y = Re(Y e^(i Omega t)) is an ellipse: with the forward and
backward circles a_f = (X + i Y) / 2 and a_b = (conj X + i conj Y) / 2 (x + i y = a_f
e^(i Omega t) + a_b e^(-i Omega t)), its semi-axes are |a_f| + |a_b| and ||a_f| - |a_b||
and it is run forward (in the direction of the spin) where |a_f| > |a_b|.

**Amplitudes are 0-peak (semi-axes); peak-to-peak is twice them** -- every output says so.

Examples
--------
>>> import resonant
>>> r = unbalance_response(resonant.load("examples/rotors/jeffcott_rotor.toml").linearize(),
...                        np.array([100.0, 316.2, 600.0]))
>>> r.major[:, 0].round(9).tolist()        # 0-pk, m (1e-4 kg m at x, y)
[1.111e-06, 0.001580391, 1.3846e-05]
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import (
    COLORS,
    Chart,
    Charted,
    Charts,
    Curve,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem
from ..expressions import Expression
from ..expressions.numeric import numeric_value
from ..model.campbell_spec import Unbalance, unbalance_columns
from ..model.rotor import Bearing, SpeedTable
from ..model.units_display import ResultUnits, Shown, angular_shown, shown_unit
from ..system.base import LinearSystem
from ..system.batch import BatchHarmonic
from ..tables import ResultTable
from .campbell import RPM, speed_parameter
from .kernel import solve_harmonic
from .result_fields import Codec, FieldsJSON, Shape, saved
from .results_json import Saved, floats_json
from .rotor_tracking import check_speeds

#: what every output says of its amplitudes
CONVENTION = "0-pk (semi-axes of the orbit); pk-pk = 2 x 0-pk"


def _unbalances_read(saved_data: Saved, key: str, shape: Shape) -> tuple[Unbalance, ...]:
    return tuple(Unbalance(r.string("at"), r.number("amount_kg_m"), r.number("phase_rad"))
                 for r in saved_data.records(key))


#: the unbalances as ``[{"at", "amount_kg_m", "phase_rad"}, ...]``
_UNBALANCES = Codec(lambda value: [{"at": u.station, "amount_kg_m": u.amount,
                                    "phase_rad": u.phase} for u in value], _unbalances_read)


@dataclass(frozen=True)
class UnbalanceResponse(FieldsJSON, Charted):
    """The orbits of a rotor's stations over the speed.

    Attributes
    ----------
    title : str
        The model's title.
    speed_parameter : str
        The speed parameter.
    stations : tuple of str
        The stations ("" for a model's plain ``x``, ``y``).
    speeds : ndarray
        The speeds (rad/s), shape (N,).
    X, Y : ndarray
        The complex amplitudes of x and y (x = Re(X e^(i Omega t))), shape (N, stations).
    unbalances : tuple of Unbalance
        The unbalances.
    warnings : tuple of str
    bearings : tuple of str
        The bearings whose transmitted forces are given.
    bearing_forces : ndarray
        The complex amplitudes of the x and y forces each bearing transmits,
        (K_b + i Omega C_b) (z_station - z_pedestal), shape (N, bearings, 2).

    Examples
    --------
    >>> import numpy as np, resonant
    >>> model = resonant.load("examples/rotors/jeffcott_rotor.toml")
    >>> r = model.unbalance_response(np.array([100.0, 316.2, 600.0]))
    >>> r.stations, r.speeds[int(np.argmax(r.major[:, 0]))]     # largest at the critical
    (('',), np.float64(316.2))
    """

    title: str
    speed_parameter: str
    stations: tuple[str, ...] = saved(key="station_names")
    speeds: np.ndarray = saved(key="speeds_rad_s")
    X: np.ndarray = saved(axes=("speeds", "stations"))
    Y: np.ndarray = saved(axes=("speeds", "stations"))
    unbalances: tuple[Unbalance, ...] = saved(codec=_UNBALANCES)
    warnings: tuple[str, ...] = field(default=())
    bearings: tuple[str, ...] = saved((), key="bearing_names")
    bearing_forces: np.ndarray = saved(key="bearing_forces_complex",
                                       axes=("speeds", "bearings", 2),
                                       default_factory=lambda: np.zeros((0, 0, 2), complex))

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def bearing_force(self) -> np.ndarray:
        """The major semi-axis (0-pk, N) of the force each bearing transmits, shape
        (N, bearings): its x and y components are ``bearing_forces`` (N, bearings, 2), the
        complex amplitudes of (K_b + i Omega C_b) (z_station - z_pedestal)."""
        FX, FY = self.bearing_forces[..., 0], self.bearing_forces[..., 1]
        result: np.ndarray = (np.abs(FX + 1j * FY) + np.abs(np.conj(FX) + 1j * np.conj(FY))) / 2
        return result

    @property
    def forward_circle(self) -> np.ndarray:
        """|a_f| = |X + i Y| / 2, shape (N, stations)."""
        result: np.ndarray = np.abs(self.X + 1j * self.Y) / 2
        return result

    @property
    def backward_circle(self) -> np.ndarray:
        """|a_b| = |conj X + i conj Y| / 2, shape (N, stations)."""
        result: np.ndarray = np.abs(np.conj(self.X) + 1j * np.conj(self.Y)) / 2
        return result

    @property
    def major(self) -> np.ndarray:
        """The major semi-axis (0-pk), shape (N, stations)."""
        result: np.ndarray = self.forward_circle + self.backward_circle
        return result

    @property
    def minor(self) -> np.ndarray:
        """The minor semi-axis (0-pk), shape (N, stations)."""
        result: np.ndarray = np.abs(self.forward_circle - self.backward_circle)
        return result

    @property
    def precession(self) -> tuple[tuple[str, ...], ...]:
        """``"forward"``, ``"backward"`` or ``"line"`` (a straight orbit) per speed and
        station."""
        f, b = self.forward_circle, self.backward_circle
        tol = 1e-9 * np.maximum(f + b, 1e-300)
        return tuple(tuple("line" if abs(fi - bi) <= ti else
                           ("forward" if fi > bi else "backward")
                           for fi, bi, ti in zip(fr, br, tr))
                     for fr, br, tr in zip(f, b, tol))

    @property
    def phase_lag(self) -> np.ndarray:
        """The lag of x behind the unbalance force's x component, (phi - arg X) modulo
        2 pi (rad; about pi/2 at a lightly damped critical speed)."""
        phases = np.array([u.phase for u in self.unbalances] or [0.0])
        result: np.ndarray = np.mod(phases[0] - np.angle(self.X), 2 * np.pi)
        return result

    def _derived_json(self) -> dict[str, Any]:
        """The numbers for a reader of the JSON: rpm, the orbits' semi-axes 0-pk and pk-pk,
        phases and precession by station, the bearing forces by bearing (computed again by
        :meth:`from_dict` from the fields ``X``, ``Y``, ``bearing_forces_complex``)."""
        return {"amplitude_convention": CONVENTION,
                "speeds_rpm": floats_json(self.speeds / RPM),
                "stations": {name or "(x, y)": {
                    "major_semi_axis_0pk": floats_json(self.major[:, i]),
                    "minor_semi_axis_0pk": floats_json(self.minor[:, i]),
                    "major_axis_pk_pk": floats_json(2 * self.major[:, i]),
                    "x": {"real": floats_json(self.X[:, i].real),
                          "imag": floats_json(self.X[:, i].imag)},
                    "y": {"real": floats_json(self.Y[:, i].real),
                          "imag": floats_json(self.Y[:, i].imag)},
                    "phase_lag_x_rad": floats_json(self.phase_lag[:, i]),
                    "precession": [row[i] for row in self.precession]}
                    for i, name in enumerate(self.stations)},
                "bearing_forces": {name: {
                    "major_semi_axis_0pk_N": floats_json(self.bearing_force[:, i]),
                    "major_axis_pk_pk_N": floats_json(2 * self.bearing_force[:, i]),
                    "fx": {"real": floats_json(self.bearing_forces[:, i, 0].real),
                           "imag": floats_json(self.bearing_forces[:, i, 0].imag)},
                    "fy": {"real": floats_json(self.bearing_forces[:, i, 1].real),
                           "imag": floats_json(self.bearing_forces[:, i, 1].imag)}}
                    for i, name in enumerate(self.bearings)}}

    def summary(self, units: ResultUnits | None = None) -> str:
        """The largest orbit of each station and the speed where it is.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``: lengths, speeds; default m and rpm).

        Returns
        -------
        str
        """
        length = shown_unit(units, "m")
        speed = angular_shown(units, Shown("rpm", RPM))
        lines = [self.title or "Unbalance response",
                 f"amplitudes: {CONVENTION}, in {length.text}", ""]
        rows = []
        for i, name in enumerate(self.stations):
            k = int(np.nanargmax(self.major[:, i]))
            rows.append((name or "(x, y)", f"{length(self.major[k, i]):.6g}",
                         f"{length(2 * self.major[k, i]):.6g}", f"{speed(self.speeds[k]):.6g}",
                         f"{length(self.minor[k, i]):.6g}", self.precession[k][i]))
        # each column as wide as its widest cell (long station names, "backward")
        lines.append(ResultTable(("station", "peak major 0-pk", "pk-pk", f"at [{speed.text}]",
                                  "minor 0-pk", "precession"), tuple(rows),
                                 align="rrrrrl").text(indent=""))
        forces = []
        for i, name in enumerate(self.bearings):
            k = int(np.nanargmax(self.bearing_force[:, i]))
            forces.append((name, f"{self.bearing_force[k, i]:.6g}",
                           f"{2 * self.bearing_force[k, i]:.6g}", f"{speed(self.speeds[k]):.6g}"))
        if forces:
            lines += ["", ResultTable(("bearing", "peak force 0-pk [N]", "pk-pk",
                                       f"at [{speed.text}]"), tuple(forces),
                                      align="rrrr").text(indent="")]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines) + "\n"

    def chart(self) -> Charts:
        """The major semi-axis (0-pk) of each station against speed (rpm), log scale,
        above the phase lag of x.

        Returns
        -------
        resonant.charts.Charts
        """
        rpm = self.speeds / RPM
        amplitude, phase = [], []
        for i, name in enumerate(self.stations):
            color = COLORS[i % len(COLORS)]
            label = name or "x, y"
            amplitude.append(Curve(rpm, self.major[:, i], label, color=color))
            phase.append(Curve(rpm, np.degrees(self.phase_lag[:, i]), label, color=color))
        xlim = (float(rpm[0]), float(rpm[-1]))
        top = Chart(tuple(amplitude), "speed [rpm]", "major semi-axis, 0-pk [m]", xlim,
                    ylog=True, title="unbalance response (pk-pk = 2 x 0-pk)")
        bottom = Chart(tuple(phase), "speed [rpm]", "phase lag of x [deg]", xlim,
                       ylim=(0.0, 360.0), yticks=(0.0, 90.0, 180.0, 270.0, 360.0),
                       legend="none")
        return Charts((top, bottom), title=self.title, heights=(2.0, 1.0), size=(7.0, 5.5))


def _stations(system: LinearSystem) -> list[tuple[str, int, int]]:
    index = {n: i for i, n in enumerate(system.coordinates)}
    out = [(n[:-2], i, index[n[:-2] + "_y"]) for n, i in index.items()
           if n.endswith("_x") and n[:-2] + "_y" in index]
    if "x" in index and "y" in index:
        out.insert(0, ("", index["x"], index["y"]))
    return out


def _loads(system: LinearSystem, unbalances: Sequence[Unbalance], speeds: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """F_S and F_C (N, n) of the unbalances (F = F_C - i F_S, x = Re(z e^(i Omega t)))."""
    s, c = unbalance_columns(unbalances, system.coordinates)
    squared = speeds[:, None] ** 2
    return squared * s, squared * c


def unbalance_response(system: LinearSystem, speeds: Sequence[float] | np.ndarray | None = None,
                       unbalances: Sequence[Unbalance] | None = None, *,
                       speed: str | None = None, deadline: Deadline = NO_DEADLINE
                       ) -> UnbalanceResponse:
    """The orbits of every station (``NAME_x``/``NAME_y`` pairs, or ``x``, ``y``) under the
    unbalances over ``speeds``.

    Parameters
    ----------
    system : LinearSystem
        The rotor.
    speeds : sequence of float, optional
        The speeds (rad/s); default the ``[campbell]`` range.
    unbalances : sequence of Unbalance, optional
        Default: the model's ``[[unbalance]]``, else 1e-4 kg m at the first station.
    speed : str, optional
        The speed parameter.
    deadline : Deadline, optional

    Returns
    -------
    UnbalanceResponse
    """
    name = speed_parameter(system, speed)
    model = system.model
    if speeds is None:
        spec = model.campbell_section if model is not None else None
        if spec is None:
            raise ModelError(Problem("no speeds: give them or a [campbell] section",
                                     system.source, "campbell", "to"))
        speeds = np.linspace(spec.start, spec.stop, spec.points)
    values = check_speeds(np.asarray(speeds, dtype=float), system.source, least=1)
    stations = _stations(system)
    if not stations:
        raise ModelError(Problem("no stations: the unbalance response needs coordinate pairs "
                                 "NAME_x, NAME_y (or x, y)", system.source, "coordinates"))
    warnings = []
    if unbalances is None:
        unbalances = model.unbalances if model is not None and model.unbalances else None
    if unbalances is None:
        unbalances = (Unbalance(stations[0][0], 1e-4, 0.0),)
        warnings.append(f"no [[unbalance]]: 1e-4 kg m at {stations[0][0] or '(x, y)'}")
    batch = system.batch(name, values, deadline)
    F_S, F_C = _loads(system, unbalances, values)
    result = solve_harmonic(batch, BatchHarmonic(values, F_S, F_C), "direct",
                            deadline=deadline, warnings=warnings)
    Z = result.Z
    if np.any(result.singular):
        warnings.append("the response is unbounded at some speed (an undamped critical "
                        "speed): NaN there")
    X = np.stack([Z[:, i] for _, i, _ in stations], axis=1)
    Y = np.stack([Z[:, j] for _, _, j in stations], axis=1)
    bearings = system.bearings
    forces = np.stack([bearing_force(b, Z, values, system.parameters_along(name, values))
                       for b in bearings], axis=1) if bearings else \
        np.zeros((len(values), 0, 2), complex)
    return UnbalanceResponse(system.title, name, tuple(s for s, _, _ in stations), values,
                             X, Y, tuple(unbalances), tuple(warnings),
                             tuple(b.name for b in bearings), forces)


def coefficient_values(value: float | Expression | SpeedTable, speeds: np.ndarray,
                       values: Mapping[str, Any]) -> np.ndarray:
    """A bearing coefficient (a number, an expression of the parameters or a table in
    speed) at each speed, shape (N,).

    Examples
    --------
    >>> coefficient_values(SpeedTable((0.0, 10.0), (1.0, 3.0)), np.array([5.0]), {}).tolist()
    [2.0]
    """
    if isinstance(value, SpeedTable):
        return value(speeds)
    if isinstance(value, float):
        return np.full(len(speeds), value)
    return np.broadcast_to(np.asarray(numeric_value(value, values), float), speeds.shape)


def bearing_force(bearing: Bearing, Z: np.ndarray, speeds: np.ndarray,
                  values: Mapping[str, Any]) -> np.ndarray:
    """The complex amplitudes (N, 2) of the force a bearing transmits,
    (K_b + i Omega C_b) (z_station - z_pedestal), at each speed.

    Parameters
    ----------
    bearing : Bearing
    Z : ndarray
        The response (N, n) at the speeds.
    speeds : ndarray
        (N,) rad/s.
    values : mapping
        The parameters at the speeds (for coefficients that are expressions).

    Returns
    -------
    ndarray
    """
    relative = Z[:, list(bearing.station)]
    if bearing.pedestal is not None:
        relative = relative - Z[:, list(bearing.pedestal)]
    impedance = np.zeros((len(speeds), 2, 2), complex)
    for key, value in bearing.coefficients:
        number = coefficient_values(value, speeds, values)
        factor = 1.0 if key[0] == "k" else 1j * speeds
        impedance[:, int(key[1] == "y"), int(key[2] == "y")] += factor * number
    result: np.ndarray = np.einsum("nij,nj->ni", impedance, relative)
    return result


__all__ = ["unbalance_response", "UnbalanceResponse", "CONVENTION", "bearing_force",
           "coefficient_values"]
