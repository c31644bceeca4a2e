"""The units of results: SI units for JSON, chosen display units for text, plots, reports.

The analyses compute in SI and never see units; this module only labels and
converts their numbers for display.  Units follow from the model
(:attr:`Model.units <resonant.model.Model.units>`): a coordinate's declared unit, an
output's inferred (or declared) one, and the entries of M, C, K and Q from the
coordinates' units (mixed translational and rotational coordinates give mixed
units per entry).  The display unit of a quantity is, in this order, the one chosen
by ``--units`` / ``[display]`` for its kind (length, angle, frequency, ...), the unit
declared for it, or its SI unit.  A model without units shows what it always showed.

Examples
--------
>>> from resonant.model import loads
>>> model = loads('''
... [parameters]
... m = "2 kg"
... J = "0.5 kg*m^2"
... k = "0.8 N/mm"
... kt = "10 N*m"
... [coordinates]
... x = { description = "displacement", unit = "mm" }
... phi = { description = "rotation", unit = "rad" }
... [energy]
... T = "m*x'^2/2 + J*phi'^2/2"
... U = "k*x^2/2 + kt*phi^2/2"
... [display]
... angle = "deg"
... ''')
>>> units = result_units(model)
>>> units.shown["x"].text, units.shown["phi"].text, units.si["phi"]
('mm', 'deg', 'rad')
>>> units.matrices["K"]
[['N/m', 'N'], ['N', 'N*m']]
>>> units.frequency.text, round(units.frequency(2 * 3.141592653589793), 12)
('Hz', 1.0)
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from fractions import Fraction
from types import MappingProxyType
from typing import Any, TypeVar

import numpy as np

from ..charts import unit_text
from ..expressions.notation import dollar_name
from ..model import Model
from ..model.units import (
    DIMENSIONLESS,
    ENERGY,
    TIME,
    Dimension,
    ModelUnits,
    Unit,
    UnitError,
    display_quantity,
    parse_unit,
)

#: a number or an array of numbers in SI
FloatOrArray = TypeVar("FloatOrArray", float, np.ndarray)


@dataclass(frozen=True)
class Shown:
    """A display unit: its text and the SI value of one of it (``shown = si / factor``)."""

    text: str
    factor: float = 1.0

    def __call__(self, value: FloatOrArray) -> FloatOrArray:
        return value / self.factor if self.factor != 1.0 else value


NO_UNIT = Shown("")
RAD = Shown("rad")
RAD_PER_S = Shown("rad/s")
HZ = Shown("Hz", 2 * math.pi)


@dataclass(frozen=True)
class ResultUnits:
    """The units of a model's results.

    Attributes
    ----------
    si : mapping
        coordinate or output -> its SI unit (``""`` where unknown); what JSON reports.
    shown : mapping
        coordinate or output -> its display unit.
    matrices : mapping
        ``"M"``, ``"C"``, ``"K"`` -> the SI unit of every entry (lists of rows);
        ``"Q"`` -> the unit of every row of the excitation (N, or N*m for an angle).
    phase, frequency : Shown
        The display units of phases and of (angular) frequencies.
    display : mapping
        quantity (length, acceleration, ...) -> the display unit chosen for it
        (``--units``, ``[display]``); what :meth:`of` converts to.
    """

    si: Mapping[str, str] = field(default_factory=dict)
    shown: Mapping[str, Shown] = field(default_factory=dict)
    matrices: Mapping[str, Any] = field(default_factory=dict)
    phase: Shown = RAD
    frequency: Shown = HZ
    display: Mapping[str, Unit] = field(default_factory=dict)

    def unit(self, name: str) -> Shown:
        return self.shown.get(name, NO_UNIT)

    def of(self, si: str) -> Shown:
        """The display unit of a quantity whose SI unit is ``si`` (``"m/s^2"``): the one
        chosen for its kind, else ``si`` itself (``""`` stays without a unit).

        Examples
        --------
        >>> from resonant.model.units import display_units
        >>> units = ResultUnits(display=display_units(["g", "mm"]))
        >>> [(s.text, round(s(19.6133), 6)) for s in map(units.of, ("m/s^2", "m", "N"))]
        [('g', 2.0), ('mm', 19613.3), ('N', 19.6133)]
        """
        kind = _si_quantity(si)
        if kind is None or kind not in self.display:
            return Shown(si)
        return _display_unit(self.display[kind], kind == "frequency")

    def chosen(self, kind: str) -> bool:
        """Whether a display unit was chosen for ``kind`` (``"frequency"``, ...)."""
        return kind in self.display

    def to_json(self) -> dict[str, Any]:
        """``{name: SI unit}`` for every coordinate, output and matrix (JSON stays SI)."""
        out: dict[str, Any] = {name: unit for name, unit in self.si.items()}
        out.update(self.matrices)
        out.update({"natural_frequencies": "rad/s", "omega": "rad/s", "phases": "rad"})
        return out


def _display_unit(unit: Unit, frequency: bool = False) -> Shown:
    """A unit for display; a cyclic one (Hz) shows an angular frequency divided by 2 pi."""
    factor = unit.to_si() * (2 * math.pi if frequency and unit.cyclic else 1.0)
    return Shown(unit.text, factor)


def _si_text(dim: Dimension | None, angle: bool) -> str:
    if dim is None:
        return ""
    if angle and dim.dimensionless:
        return "rad"
    return dim.text()


def _quantity(dim: Dimension | None, declared: Unit | None) -> str | None:
    if declared is not None and declared.angle:
        return "angle"
    return None if dim is None else display_quantity(Unit("", Fraction(1), 0, dim))


def _si_quantity(si: str) -> str | None:
    """The quantity of an SI unit text (``"m/s^2"`` -> acceleration; None if unknown)."""
    if not si or si == "1":
        return None
    if si == "rad":
        return "angle"
    try:
        return display_quantity(parse_unit(si))
    except UnitError:
        return None


def shown_unit(units: ResultUnits | None, si: str) -> Shown:
    """``units.of(si)``, or ``si`` unchanged without units (a model without them).

    Examples
    --------
    >>> shown_unit(None, "m").text
    'm'
    """
    return Shown(si) if units is None else units.of(si)


def curve_units(units: Mapping[str, str] | ResultUnits | None,
                names: Sequence[str]) -> dict[str, Shown]:
    """Each named curve's display unit: from :class:`ResultUnits` (converted), from a
    mapping name -> unit text (shown as it is), none without.

    Examples
    --------
    >>> from resonant.model.units import display_units
    >>> units = ResultUnits(shown={"x": Shown("mm", 1e-3)})
    >>> curve_units(units, ["x"])["x"](0.002), curve_units({"x": "m"}, ["x"])["x"].text
    (2.0, 'm')
    """
    if units is None:
        return {n: NO_UNIT for n in names}
    if isinstance(units, ResultUnits):
        return {n: units.unit(n) for n in names}
    return {n: Shown(units.get(n, "")) for n in names}


def frequency_axis(units: Mapping[str, str] | ResultUnits | None, scale: float | None,
                   unit: str) -> tuple[Shown, float]:
    """How a parameter axis in ``unit`` whose value times ``scale`` is an angular frequency
    (rad/s) is shown: (the display unit of that angular frequency, ``scale``) where a
    frequency unit was chosen (``--units Hz``), else (``unit`` as it is, 1).

    Examples
    --------
    >>> from resonant.model.units import display_units
    >>> shown, scale = frequency_axis(ResultUnits(display=display_units(["Hz"])), 1.0, "rad/s")
    >>> shown.text, round(shown(scale * 2 * math.pi), 12)
    ('Hz', 1.0)
    """
    if isinstance(units, ResultUnits) and units.chosen("frequency") and scale is not None \
            and unit in ("rad/s", "Hz"):
        return units.frequency, scale
    return Shown(unit), 1.0


def angular_shown(units: ResultUnits | None, default: Shown = RAD_PER_S) -> Shown:
    """How a value in rad/s (an angular frequency, a speed) is shown: in the frequency
    unit chosen (``--units Hz``, ``rpm``), else in ``default``.

    Examples
    --------
    >>> from resonant.model.units import display_units
    >>> rpm = angular_shown(ResultUnits(display=display_units(["rpm"])))
    >>> rpm.text, round(rpm(2 * math.pi), 9), angular_shown(None).text
    ('rpm', 60.0, 'rad/s')
    """
    return frequency_shown(units.display) if units is not None and units.chosen("frequency") \
        else default


def cyclic_shown(units: ResultUnits | None) -> Shown:
    """How a value in Hz (a measured or cyclic frequency) is shown: in the frequency unit
    chosen, else in Hz.

    Examples
    --------
    >>> from resonant.model.units import display_units
    >>> w = cyclic_shown(ResultUnits(display=display_units(["rad/s"])))
    >>> w.text, round(w(1.0), 12)
    ('rad/s', 6.28318530718)
    """
    angular = angular_shown(units, HZ)
    return Shown(angular.text, angular.factor / (2 * math.pi))


def density_unit(shown: Shown) -> Shown:
    """The unit of a one-sided spectral density of a quantity shown in ``shown``:
    ``mm`` -> ``mm^2/Hz`` (its factor squared; ``SI^2/Hz`` without a unit).

    Examples
    --------
    >>> d = density_unit(Shown("g", 9.80665))
    >>> d.text, round(d(9.80665 ** 2), 12)
    ('g^2/Hz', 1.0)
    """
    text = shown.text
    if not text:
        return Shown("SI^2/Hz")
    base = f"({text})" if any(c in text for c in "*/^") else text
    return Shown(f"{base}^2/Hz", shown.factor ** 2)


def result_units(model: Model | None, chosen: Mapping[str, Unit] | None = None
                 ) -> ResultUnits | None:
    """The units of the results of ``model`` (None for a model without units).

    ``chosen`` (quantity -> unit, like ``--units``) takes precedence over the model's
    ``[display]`` section.
    """
    if model is None or model.units is None:
        return None
    units = model.units
    display = {**units.display, **(chosen or {})}
    si: dict[str, str] = {}
    shown: dict[str, Shown] = {}
    declared_all = {**units.coordinates, **units.outputs}
    for name in [*model.coordinates, *model.outputs]:
        dim = units.dimensions.get(name)
        declared = declared_all.get(name)
        angle = declared is not None and declared.angle
        si[name] = _si_text(dim, angle)
        kind = _quantity(dim, declared)
        if kind is not None and kind in display:
            shown[name] = _display_unit(display[kind], kind == "frequency")
        elif declared is not None:
            shown[name] = _display_unit(declared)
        elif si[name] and si[name] != "1":
            shown[name] = Shown(si[name])
    coordinate_dims = [units.dimensions.get(q) for q in model.coordinates]
    matrices: dict[str, Any] = {}
    if coordinate_dims and all(d is not None for d in coordinate_dims):
        dims: list[Dimension] = [d for d in coordinate_dims if d is not None]
        for key, scale in (("M", TIME ** 2), ("C", TIME), ("K", DIMENSIONLESS)):
            matrices[key] = [[(ENERGY * scale / (di * dj)).text(moment=True) for dj in dims]
                             for di in dims]
        matrices["Q"] = [(ENERGY / di).text(moment=True) for di in dims]
    phase = _display_unit(display["angle"]) if "angle" in display else RAD
    frequency = frequency_shown(display)
    return ResultUnits(si, shown, matrices, phase, frequency, display)


def with_display(model: Model, display: Mapping[str, Unit]) -> Model:
    """``model`` with its results shown in ``display`` (quantity -> unit, like the command
    line's units), which takes precedence over the model's own ``[display]``.

    Examples
    --------
    >>> from resonant.model import loads
    >>> from resonant.model.units import display_units
    >>> model = loads('[coordinates]\\nx = ""\\n[energy]\\nT = "x\\'^2/2"\\nU = "x^2/2"')
    >>> result_units(with_display(model, display_units(["Hz"]))).frequency.text
    'Hz'
    """
    if not display:
        return model
    own = model.units or ModelUnits()
    return replace(model, units=replace(own, display=MappingProxyType({**own.display,
                                                                       **display})))


def frequency_shown(display: Mapping[str, Unit]) -> Shown:
    """How (angular) frequencies are shown: in the unit chosen for them, else in Hz."""
    return _display_unit(display["frequency"], True) if "frequency" in display else HZ


def uniform(units: Sequence[Any]) -> str | None:
    """The one unit of all entries (rows of units flattened), or None if they differ.

    Examples
    --------
    >>> uniform([["kg", "kg"], ["kg", "kg"]]), uniform(["N", "N*m"])
    ('kg', None)
    """
    flat = [u for row in units for u in (row if isinstance(row, list) else [row])]
    return flat[0] if flat and all(u == flat[0] for u in flat) else None


def units_grid(units: Sequence[Sequence[str]], indent: str = "    ") -> str:
    """The units of a matrix's entries as an aligned grid (for mixed units)."""
    width = max((len(u) for row in units for u in row), default=1)
    return "\n".join(indent + "[" + "  ".join(u.rjust(width) for u in row) + "]"
                     for row in units)


def shown_vector(values: np.ndarray, names: Sequence[str], units: ResultUnits) -> str:
    """``[2.17, -38.6] mm`` (one unit) or ``[2.17 mm, 5.1 deg]`` (mixed), in display units."""
    shown = [units.unit(n) for n in names]
    numbers = [f"{shown[i](float(v)) + 0.0:.6g}" for i, v in enumerate(values)]
    texts = {s.text for s in shown}
    if len(texts) == 1:
        text = next(iter(texts))
        return "[" + ", ".join(numbers) + "]" + (f" {text}" if text else "")
    return "[" + ", ".join(f"{n} {s.text}".rstrip() for n, s in zip(numbers, shown)) + "]"


def unit_latex(text: str) -> str:
    r"""A unit in LaTeX after a number: ``kg*m^2/s`` -> ``\ \mathrm{kg\,m^{2}/s}``.

    Examples
    --------
    >>> unit_latex("N*s/m"), unit_latex("")
    ('\\ \\mathrm{N\\,s/m}', '')
    """
    if not text:
        return ""
    body = re.sub(r"\^\(?(-?[0-9/]+)\)?", r"^{\1}", text.replace("*", r"\,"))
    body = body.replace("deg", r"^{\circ}") if text == "deg" else body
    return r"\ \mathrm{" + body + "}"


def axis_label(label: str, unit: str) -> str:
    """``amplitude [mm]`` (or the label alone without a unit)."""
    return f"{label} [{unit}]" if unit else label


def unit_math(unit: str) -> str:
    """A unit for a matplotlib label: ``N*s/m`` and ``m/s^2`` typeset (a product's dot,
    a power's superscript), a plain one (``m``, ``rad/s``) as it is.

    Examples
    --------
    >>> print(unit_math("m"), unit_math("N*s/m"))
    m $\\mathrm{N\\,s/m}$
    """
    if not any(c in unit for c in "*^"):
        return unit.replace("$", r"\$")
    return "$" + unit_latex(unit).removeprefix("\\ ") + "$"


def name_label(name: str, units: Mapping[str, str] | None = None) -> str:
    """A curve's label: the name typeset, and its unit where given (``$x_{1}$ [m]``)."""
    unit = (units or {}).get(name, "")
    return dollar_name(name) + (f" [{unit_text(unit)}]" if unit and unit != "1" else "")


def unit_suffix(names: Sequence[str], units: Mapping[str, str]) -> tuple[str, Mapping[str, str]]:
    """`` [m]`` for the y axis when every curve has that unit (and no per-curve units),
    else `` [m, rad]`` (in the order of the curves) and the units for each curve's label.

    Examples
    --------
    >>> unit_suffix(["x", "y"], {"x": "m", "y": "m"})
    (' [m]', {})
    """
    shown = {units.get(n, "") for n in names}
    if len(shown) <= 1:
        unit = next(iter(shown), "")
        return (f" [{unit_text(unit)}]" if unit and unit != "1" else ""), {}
    named = [unit_text(u) if u and u != "1" else "1"
             for u in dict.fromkeys(units.get(n, "") for n in names)]
    return f" [{', '.join(named)}]", units


__all__ = ["angular_shown", "cyclic_shown", "curve_units", "frequency_axis", "frequency_shown",
           "shown_unit", "density_unit", "unit_math", "name_label", "unit_suffix", "ResultUnits",
           "Shown", "result_units", "uniform", "units_grid", "shown_vector", "axis_label",
           "unit_latex", "with_display", "HZ", "RAD", "RAD_PER_S", "NO_UNIT", "display_quantity"]
