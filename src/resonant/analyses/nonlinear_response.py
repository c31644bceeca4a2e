"""The result of a nonlinear frequency response: the periodic steady state along a branch.

:class:`NonlinearResponse` is what :func:`resonant.analyses.harmonic_balance.nonlinear_sweep`
returns, whether the balance is of the full equations of a model given by its energies or
condensed onto the coordinates of a ``[matrices]`` model's ``[[nonlinear]]`` elements
(:mod:`resonant.analyses.condensed`).

Examples
--------
>>> import resonant
>>> r = resonant.load("examples/duffing.toml").nonlinear_sweep(
...     "omega", 0.8, 1.2, harmonics=1, points=20)
>>> type(r).__name__, r.parameter
('NonlinearResponse', 'omega')
"""

from __future__ import annotations

import csv
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import ComplexArray, freeze_fields
from ..charts import (
    COLORS,
    MAX_CURVES,
    Chart,
    Charts,
    Curve,
    Marker,
    PathArg,
    Rule,
    check_plot_path,
    draw_figure,
    save_figure,
)
from ..errors import printable
from ..expressions.notation import dollar_name
from ..model.units_display import ResultUnits, Shown, curve_units, frequency_axis, unit_math
from ..tables import ResultTable, number_column
from .result_fields import (
    HARMONIC_LISTS,
    PLAIN_NUMBER,
    PLAIN_NUMBERS,
    Codec,
    FieldsJSON,
    Framed,
    saved,
)
from .results_json import Saved
from .special_points import SpecialPoint
from .sweep import FrequencyResponse

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


MARKERS = {"fold": "o", "period-doubling": "s", "neimark-sacker": "D", "branch": "^",
           "peak": "*"}


#: the chart's marker shape of each kind of special point (as :data:`MARKERS`)
SHAPES = {"fold": "circle", "period-doubling": "square", "neimark-sacker": "diamond",
          "branch": "triangle", "peak": "star"}


def _segments(values: np.ndarray, amplitudes: np.ndarray, stable: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, stable y, unstable y): the branch as two curves broken by NaN, each running on
    to the point where the stability changes (the two join there)."""
    n = values.size
    keep = np.zeros((2, n), dtype=bool)  # [stable, unstable]
    for i in range(n):
        k = 0 if stable[i] else 1
        keep[k, i] = True
        if i + 1 < n and stable[i + 1] != stable[i]:
            keep[k, i + 1] = True  # the segment reaches the switching point
    with np.errstate(invalid="ignore"):
        return (values.astype(float), np.where(keep[0], amplitudes, np.nan),
                np.where(keep[1], amplitudes, np.nan))


def nonlinear_response_chart(response: NonlinearResponse, names: Sequence[str] | None = None,
                             linear: bool = True,
                             units: Mapping[str, str] | ResultUnits | None = None, *,
                             title: bool = True,
                             operating: tuple[float, Mapping[str, float]] | None = None
                             ) -> Chart:
    """What the figure of a nonlinear steady-state sweep shows: the peak amplitude of each
    coordinate and output against the parameter, stable parts solid, unstable dashed,
    special points marked, the linear frequency response dotted beside it.

    Parameters
    ----------
    response : NonlinearResponse
    names : sequence of str, optional
        The curves (default: the first :data:`MAX_CURVES`).
    linear : bool
        Draw the linear frequency response beside.
    units : ResultUnits or mapping, optional
        The display units (amplitudes and a frequency axis converted, ``--units``), or
        name -> SI unit, on the curves and the axis.
    title : bool
        Give the chart the model's title.
    operating : (value, amplitudes), optional
        The operating point: a dashed line at the value and a star on each curve.

    Returns
    -------
    Chart
    """
    chosen = list(names) if names else list(response.amplitudes)[:MAX_CURVES]
    base = np.asarray(response.base_frequencies, dtype=float)
    v = np.asarray(response.values, dtype=float)
    frequency = base.shape == v.shape and bool(np.allclose(base, v))  # the parameter is ω
    along, scale = frequency_axis(units, 1.0 if frequency else None, "rad/s")
    along_text = along.text if frequency else ""
    v = along(v * scale)
    each = curve_units(units, chosen)
    stable = np.asarray(response.stable, dtype=bool)
    curves: list[Curve] = []
    markers: list[Marker] = []
    for k, name in enumerate(chosen):
        color = COLORS[k % len(COLORS)]
        a = each[name](np.asarray(response.amplitudes[name], dtype=float))
        unit = each[name].text
        shown = dollar_name(name) + (f" [{unit_math(unit)}]" if unit not in ("", "1") else "")
        if linear and response.linear is not None and name in response.linear.amplitudes:
            curves.append(Curve(along(np.asarray(response.linear.values, dtype=float) * scale),
                                each[name](np.asarray(response.linear.amplitudes[name],
                                                      dtype=float)),
                                f"{shown} (linear)", color, 1.1, "1 1.65"))
        x, on, off = _segments(v, a, stable)
        curves.append(Curve(x, on, f"{shown} (harmonic balance, H = {response.harmonics})",
                            color, 1.6))
        if np.isfinite(off).any():
            curves.append(Curve(x, off, "", color, 1.6, "3.7 1.6"))
        for point in response.special_points:
            if name in point.amplitudes and point.quantity in (None, name):
                markers.append(Marker(along(point.value * scale),
                                      each[name](point.amplitudes[name]), "#000000",
                                      SHAPES.get(point.kind, "circle"), point.kind,
                                      filled=False))
    if not stable.all():
        curves.append(Curve(np.empty(0), np.empty(0), "unstable", "#4d4d4d", 1.6, "3.7 1.6"))
    rules: tuple[Rule, ...] = ()
    if operating is not None:
        value, amplitudes = operating
        markers += [Marker(along(value * scale), each[name](amplitudes[name]),
                           COLORS[k % len(COLORS)], "star",
                           f"{dollar_name(name)} at the operating point")
                    for k, name in enumerate(chosen) if name in amplitudes]
        rules = (Rule(along(float(value) * scale), color="#404040", dash="3.7 1.6"),)
    parameter = "f" if along_text in ("Hz", "kHz") else response.parameter
    xlabel = (("excitation frequency " if frequency else "") + dollar_name(parameter)
              + (f" [{along_text}]" if frequency else ""))
    shown_units = sorted({each[n].text for n in chosen} - {"", "1"})
    ylabel = ("peak amplitude $X$ (deviation)"
              + (f" [{', '.join(unit_math(u) for u in shown_units)}]" if shown_units else ""))
    top = max((float(np.nanmax(each[n](np.asarray(response.amplitudes[n], dtype=float))))
               for n in chosen), default=1.0)
    xlim = (along(min(response.start, response.stop) * scale),
            along(max(response.start, response.stop) * scale))
    return Chart(tuple(curves), xlabel, ylabel, xlim,
                 markers=_apart(markers, xlim, top), rules=rules,
                 ylim=(0.0, 1.15 * top) if top > 0 else None,
                 title=printable(response.title or "nonlinear steady state", limit=80)
                 if title else "")


#: markers closer than this fraction of both axes are one point drawn once (a fold where
#: the peak is, both marked, read as a blot)
MARKER_GAP = 0.012


def _apart(markers: Sequence[Marker], xlim: tuple[float, float], top: float
           ) -> tuple[Marker, ...]:
    """The markers without those that would cover an earlier one (the earlier kept)."""
    width = abs(xlim[1] - xlim[0]) or 1.0
    height = abs(top) or 1.0
    kept: list[Marker] = []
    for m in markers:
        if all(abs(m.x - k.x) > MARKER_GAP * width or abs(m.y - k.y) > MARKER_GAP * height
               for k in kept):
            kept.append(m)
    return tuple(kept)


def plot_nonlinear_response(response: NonlinearResponse, path: PathArg = None,
                            names: Sequence[str] | None = None, ax: Axes | None = None,
                            linear: bool = True,
                            units: Mapping[str, str] | ResultUnits | None = None) -> Figure:
    """Amplitude against the parameter (the chart of :func:`nonlinear_response_chart`, drawn
    with matplotlib); returns the Figure (and writes it to ``path``).

    ``units`` (name -> SI unit, ``ResultUnits.si``) labels the curves and the axis."""
    check_plot_path(path)
    chart = nonlinear_response_chart(response, names, linear, units)
    fig = draw_figure(Charts((chart,), size=(7.5, 4.8)), ax)
    save_figure(fig, path)
    return fig


def special_points_table(response: NonlinearResponse, units: ResultUnits | None = None
                         ) -> ResultTable:
    """The special points of the branch (folds, changes of stability, peaks) as a table:
    where, and the amplitude of every quantity in its display unit where the model gives
    one, each column in one notation (6 significant digits).

    Parameters
    ----------
    response : NonlinearResponse
    units : ResultUnits, optional
        The model's display units.

    Returns
    -------
    resonant.tables.ResultTable
    """
    names = list(response.special_points[0].amplitudes) if response.special_points else []
    shown = {n: units.unit(n) if units is not None else None for n in names}
    kinds = []
    for p in response.special_points:
        kind = f"peak of {printable(p.quantity, limit=20)}" if p.kind == "peak" else p.kind
        kinds.append(kind + (" (unstable)" if p.stable is False else ""))
    along, scale = _parameter_axis(response, units)
    columns = [tuple(kinds),
               number_column([along(p.value * scale) for p in response.special_points], 6)]
    for n in names:
        unit = shown[n]
        columns.append(number_column([
            float(unit(p.amplitudes[n])) if unit is not None else p.amplitudes[n]
            for p in response.special_points], 6))
    def heading(name: str) -> str:
        unit = shown[name]
        return printable(name, limit=20) + (f" [{unit.text}]" if unit and unit.text else "")

    where = printable(response.parameter, limit=20) + (f" [{along.text}]" if along.text else "")
    header = ("point", where, *(heading(n) for n in names))
    return ResultTable(header, tuple(zip(*columns)), align="l" + "r" * (len(header) - 1))


def _parameter_axis(response: NonlinearResponse, units: ResultUnits | None
                    ) -> tuple[Shown, float]:
    """How the continuation parameter is shown: an excitation frequency in rad/s, or in
    the frequency unit ``units`` chooses; another parameter as it is."""
    base = np.asarray(response.base_frequencies, dtype=float)
    v = np.asarray(response.values, dtype=float)
    if base.shape != v.shape or not np.allclose(base, v):
        return Shown(""), 1.0
    return frequency_axis(units, 1.0, "rad/s")


def nonlinear_text(response: NonlinearResponse, units: ResultUnits | None = None) -> str:
    """Special points and the peak of the stable branch, as plain text (the amplitudes in
    the display units of ``units`` where given)."""
    along, scale = _parameter_axis(response, units)
    unit = f" {along.text}" if along.text else ""

    def amplitude(name: str, value: float) -> str:
        shown = units.unit(name) if units is not None else Shown("")
        return f"{shown(value):.6g}" + (f" {shown.text}" if shown.text else "")

    lines = [f"{response.title or 'model'}: nonlinear steady state (harmonic balance, "
             f"H = {response.harmonics}) against {response.parameter} from "
             f"{along(response.start * scale):g} to {along(response.stop * scale):g}{unit}",
             f"  {response.values.size} branch points, {int(response.stable.sum())} stable; "
             f"largest residual {response.residual:.3g}; highest harmonics carry up to "
             f"{response.truncation:.3g} of the amplitude"]
    if response.special_points:
        lines.append("  special points (peak amplitudes):")
        lines.append(special_points_table(response, units).text(indent="    "))
    else:
        lines.append("  no special points (no fold, no change of stability, no peak)")
    top = response.peak()
    if top is not None:
        value, peak_amps = top
        lines.append(f"  peak of the stable branch at {response.parameter} = "
                     f"{along(value * scale):.6g}{unit}: "
                     + ", ".join(f"{k} = {amplitude(k, v)}" for k, v in peak_amps.items()))
        if response.linear is not None:
            first = response.coordinates[0]
            lin = np.asarray(response.linear.amplitudes.get(first, []), dtype=float)
            if lin.size and np.isfinite(lin).any():
                lines.append(f"  linear peak of {first}: "
                             f"{amplitude(first, float(np.nanmax(lin)))}")
    else:
        lines.append("  no stable point on the branch")
    return "\n".join(lines) + "\n"


__all__ = ["NonlinearResponse"]

#: H, saved as a whole number of at least 1
_HARMONICS = Codec(int, lambda reader, key, shape: reader.integer(key, minimum=1))
#: true or false per branch point
_FLAG = Codec(bool, lambda reader, key, shape: reader.boolean(key))


@dataclass(frozen=True)
class NonlinearResponse(Framed, FieldsJSON):
    """The periodic steady state of the full equations, followed along a parameter.

    Attributes
    ----------
    parameter : str
        The continuation parameter.
    values : numpy.ndarray
        Its value at every branch point, in the order of the continuation.
    amplitudes : mapping
        ``coordinate or output -> peak |deviation from the reference state|`` over one
        period, at every branch point.
    coefficients : numpy.ndarray
        (points, n, 2H+1): per coordinate ``[a_0, a_1, b_1, ..., a_H, b_H]``.
    outputs : tuple of str
        The model's outputs (``[outputs]``), evaluated in full on every point.
    output_coefficients : numpy.ndarray or None
        (points, outputs, 2H+1): the first H harmonics of every output's deviation (None
        without outputs).
    base_frequencies : numpy.ndarray
        The base frequency W (rad/s) at every point.
    stable : numpy.ndarray
        bool per point.
    multipliers : numpy.ndarray
        (points, 2n) Floquet multipliers (Hill's method).
    special_points : tuple of SpecialPoint
        Folds, changes of stability and the peaks of every coordinate and output, in the
        order of the branch.
    harmonics : int
        H.
    residual : float
        The largest harmonic-balance residual (max ``|R|``) of the branch.
    truncation : float
        The largest relative amplitude of the highest harmonic pair (H, H-1).
    linear : FrequencyResponse or None
        The linear sweep over the same range, for comparison.
    title, coordinates
        The model's title and its coordinates.
    start, stop : float
        The range of the parameter asked for.
    warnings : tuple of str
        What the user should know (truncation, a branch that left the range).

    Examples
    --------
    See :func:`resonant.analyses.harmonic_balance.nonlinear_sweep` and the module's example.
    Its JSON (``resonant sweep --nonlinear --json``) comes back by ``from_dict``:

    >>> import json, resonant
    >>> r = resonant.load("examples/duffing.toml").nonlinear_sweep(
    ...     "omega", 0.8, 1.2, harmonics=1, points=20)
    >>> back = NonlinearResponse.from_dict(json.loads(json.dumps(r.to_dict())))
    >>> back.to_dict() == r.to_dict()
    True
    """

    #: the columns of to_frame() (resonant.analyses.result_fields.Framed)
    _frame = (("values", "{parameter}"), ("stable", "stable"),
              ("amplitudes", "amplitude:{key}"))

    #: the saved form (resonant.analyses.result_fields.FieldsJSON): the linear sweep's keys
    #: (when there is one) first, then the branch as one record per point, and the rest
    #: of the result inside "continuation"
    _json_order = ("...", "branch", "special_points", "harmonics", "residual", "truncation",
                   "continuation")
    _group_order = {"branch": ("value", "amplitudes", "stable", "harmonics"),
                    "continuation": ("title", "parameter", "coordinates", "outputs",
                                     "quantities", "output_coefficients", "base_frequencies",
                                     "multipliers", "start", "stop", "warnings", "linear")}

    title: str = saved(inside="continuation")
    parameter: str = saved(inside="continuation")
    coordinates: tuple[str, ...] = saved(inside="continuation")
    values: np.ndarray = saved(records="branch", key="value", codec=PLAIN_NUMBER)
    amplitudes: Mapping[str, np.ndarray] = saved(records="branch", codec=PLAIN_NUMBERS)
    coefficients: np.ndarray = saved(records="branch", key="harmonics",
                                     rows_by="coordinates", codec=HARMONIC_LISTS)
    base_frequencies: np.ndarray = saved(inside="continuation", axes=("values",))
    stable: np.ndarray = saved(records="branch", codec=_FLAG)
    multipliers: ComplexArray = saved(inside="continuation", axes=(None, None))
    special_points: tuple[SpecialPoint, ...] = saved()
    harmonics: int = saved(codec=_HARMONICS)
    residual: float = saved(codec=PLAIN_NUMBER)
    truncation: float = saved(codec=PLAIN_NUMBER)
    start: float = saved(inside="continuation", codec=PLAIN_NUMBER)
    stop: float = saved(inside="continuation", codec=PLAIN_NUMBER)
    linear: FrequencyResponse | None = saved(None, written=False)
    warnings: tuple[str, ...] = saved((), inside="continuation", required=True)
    outputs: tuple[str, ...] = saved((), inside="continuation", required=True)
    output_coefficients: np.ndarray | None = saved(
        None, records="branch", key="harmonics", rows_by="outputs", codec=HARMONIC_LISTS,
        omit_none=True)

    def __post_init__(self) -> None:
        freeze_fields(self)

    def peak(self) -> tuple[float, dict[str, float]] | None:
        """(value, amplitudes) of the largest stable amplitude of the first coordinate: its
        located ``peak`` point, or the largest stable branch point when that is larger
        (None when no point is stable)."""
        if not self.stable.any():
            return None
        first = self.coordinates[0]
        a = self.amplitudes[first]
        i = int(np.argmax(np.where(self.stable, a, -np.inf)))
        best = (float(self.values[i]), {k: float(v[i]) for k, v in self.amplitudes.items()})
        for p in self.special_points:
            if p.kind == "peak" and p.quantity == first and p.stable and \
                    p.amplitudes[first] >= best[1][first]:
                best = (p.value, dict(p.amplitudes))
        return best

    def _derived_json(self) -> dict[str, Any]:
        """The linear sweep's keys (when there is one; else the title and the parameter),
        every warning (the linear sweep's, then the branch's) and, inside "continuation",
        what :meth:`from_dict` needs to know of the fields."""
        data: dict[str, Any] = self.linear.to_dict() if self.linear is not None else {
            "title": self.title, "parameter": self.parameter}
        data["warnings"] = list(data.get("warnings", [])) + list(self.warnings)
        data["continuation"] = {"quantities": list(self.amplitudes),
                                "output_coefficients": self.output_coefficients is not None,
                                "linear": self.linear is not None}
        return data

    @classmethod
    def _check_saved(cls, values: dict[str, Any], saved_data: Saved) -> None:
        """The amplitudes of ``continuation.quantities`` in that order, the coefficients
        2H+1 per name, the output harmonics when saved, and the linear sweep from the keys
        beside the branch (its warnings those before the branch's).

        The values, amplitudes, stability and coefficients come from ``branch``, the rest
        from ``continuation``; finite numbers come back bit for bit (a multiplier that
        overflowed to infinity comes back as NaN).
        """
        rest = saved_data.mapping("continuation")
        points = len(values["values"])
        values["values"] = np.asarray(values["values"], dtype=float)
        values["stable"] = np.asarray(values["stable"], dtype=bool)
        amplitudes = values["amplitudes"]
        branch = saved_data.records("branch")
        for name in rest.strings("quantities"):
            if name not in amplitudes:
                if points:
                    branch[0].mapping("amplitudes").value(name)   # the error naming it
                amplitudes[name] = np.zeros(0)
        values["amplitudes"] = MappingProxyType(
            {name: amplitudes[name] for name in rest.strings("quantities")})
        width = 2 * values["harmonics"] + 1
        if not rest.boolean("output_coefficients"):
            values["output_coefficients"] = None
        elif "output_coefficients" not in values:   # saved, but of no output
            if values["outputs"] and branch:
                branch[0].mapping("harmonics").value(values["outputs"][0])  # names it
            values["output_coefficients"] = np.zeros((points, 0, width))
        for key, names in (("coefficients", "coordinates"), ("output_coefficients", "outputs")):
            c = values.get(key)
            if c is None:
                continue
            if c.size == 0:
                values[key] = np.zeros((points, len(values[names]), width))
            elif c.shape[-1] != width:
                raise branch[0].mapping("harmonics").error(
                    f"has shape {c.shape[-1:]}, not ({width},)", values[names][0])
        own = values["warnings"]
        every = saved_data.strings("warnings")
        if every[len(every) - len(own):] != own:
            raise saved_data.error("has warnings that do not end with those of "
                                   "'continuation.warnings'", "warnings")
        if rest.boolean("linear"):
            values["linear"] = FrequencyResponse.from_dict(
                {**saved_data.data, "warnings": list(every[:len(every) - len(own)])})

    def to_csv(self, path: str | Path) -> None:
        """One row per branch point: value, stable, the amplitudes."""
        names = list(self.amplitudes)
        with open(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow([self.parameter, "stable", *names])
            for i in range(self.values.size):
                writer.writerow([repr(float(self.values[i])), int(self.stable[i]),
                                 *(repr(float(self.amplitudes[n][i])) for n in names)])

    def chart(self, names: Sequence[str] | None = None, linear: bool = True,
              units: Mapping[str, str] | None = None) -> Chart:
        """The figure's description: the peak amplitudes along the branch, stable solid,
        unstable dashed, special points marked (:func:`nonlinear_response_chart`).

        Parameters
        ----------
        names : sequence of str, optional
            The quantities to draw.
        linear : bool
            With the linear frequency response dotted beside.
        units : mapping, optional
            quantity -> unit text for the axis labels.

        Returns
        -------
        resonant.charts.Chart
        """
        return nonlinear_response_chart(self, names, linear, units)

    def plot(self, path: str | os.PathLike[str] | None = None,
             names: Sequence[str] | None = None, ax: Axes | None = None,
             linear: bool = True) -> Figure:
        """Amplitude against the parameter: stable solid, unstable dashed, special points
        (:func:`resonant.analyses.nonlinear_response.plot_nonlinear_response`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        names : sequence of str, optional
            The quantities to draw.
        ax : matplotlib.axes.Axes, optional
            Draw into the caller's axes.
        linear : bool
            Also draw the linear response.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return plot_nonlinear_response(self, path, names, ax, linear)

    def summary(self) -> str:
        """The text ``resonant sweep --nonlinear`` prints
        (:func:`resonant.analyses.nonlinear_response.nonlinear_text`).

        Returns
        -------
        str

        Examples
        --------
        >>> import resonant
        >>> r = resonant.load("examples/duffing.toml").nonlinear_sweep(
        ...     "omega", 0.8, 1.2, harmonics=1, points=20)
        >>> r.parameter, r.harmonics
        ('omega', 1)
        """
        return nonlinear_text(self)
