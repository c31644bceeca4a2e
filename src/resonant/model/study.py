"""What a parameter study asks: the varied parameters, the design and the quantities.

A study (docs/studies.md) varies some parameters of a model by a *design*
(``grid``, ``random``, ``lhs``, ``sobol``) and records *quantities* of every
sample.  This module reads and checks the request -- from a ``[study]``
section, from command-line texts or from Python arguments -- into a frozen
:class:`StudySpec`; computing it is :mod:`resonant.studies`.

A varied parameter's *specification* is one of::

    "uniform(80 N/m, 120 N/m)"     # lower and upper bound
    "normal(100 N/m, 5 N/m)"       # mean and standard deviation
    "lognormal(100 N/m, 5 N/m)"    # mean and standard deviation of the value itself
    [80, 100, "120 N/m"]           # a list of values (equally likely)
    { from = 80, to = 120, step = 10 }   # a range, as in [variants]

Examples
--------
>>> spec = study_spec({"k": "uniform(80, 120)"}, ["natural_frequency:1"],
...                   parameters=["m", "k"], coordinates=["x"], outputs=[])
>>> spec.vary["k"].kind, spec.vary["k"].arguments, spec.quantities[0].columns
('uniform', (80.0, 120.0), ('natural_frequency:1',))
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, field, replace
from decimal import Decimal, InvalidOperation
from types import MappingProxyType
from typing import Any

import numpy as np

from ..errors import ModelError, Problem, name_list
from ..expressions import ExpressionError, numeric_value
from .campbell_spec import parse_speed
from .load_spec import quantity_value
from .options import MAX_GIVEN_HARMONICS
from .units import FREQUENCY, ModelUnits, parse_with_unit

#: the designs: a full factorial grid, independent random samples, a Latin hypercube
#: (per chunk of samples), and Saltelli's scheme for Sobol indices
DESIGNS = ("grid", "random", "lhs", "sobol")
DISTRIBUTIONS = ("uniform", "normal", "lognormal")


@dataclass(frozen=True)
class QuantityKind:
    """One kind of quantity a study records (``kind:target``), with what it means.

    Parameters
    ----------
    name : str
        The kind, before the colon (``peak``).
    target : str
        What follows the colon: ``"index"`` (a mode number), ``"name"`` (a coordinate or
        output), ``"name@frequency"``, ``"index@order"``, ``"index@speed"``, or ``""``.
    unit : str
        Its column's SI unit: a unit (``"rad/s"``), ``""`` for a pure number, or
        ``"target"``: the unit of the coordinate or output it names.
    label : str
        Its axis title, ``{}`` standing for the typeset target (a name, or a mode number
        as a subscript); ``""``: the column as written.
    band : bool
        It needs the study's band (searched over it, or swept up from its start).
    rotor : bool
        It needs a rotor (the model's ``[campbell]`` speeds).
    derived : str
        The kind of a second column it gives (a peak's frequency), or ``""``.

    Examples
    --------
    >>> QUANTITY_KINDS["peak"].label.format("x")
    'peak of x over the band'
    """

    name: str
    target: str
    unit: str
    label: str = ""
    band: bool = False
    rotor: bool = False
    derived: str = ""


#: the quantities a study records (docs/studies.md): a new kind is one entry here and its
#: evaluation in resonant.studies.quantities
QUANTITY_KIND_TABLE = (
    QuantityKind("natural_frequency", "index", "rad/s", r"natural frequency $\omega_{{{}}}$"),
    QuantityKind("damping_ratio", "index", "", r"damping ratio $\zeta_{{{}}}$"),
    QuantityKind("amplitude", "name", "target", "amplitude of {}"),
    QuantityKind("phase", "name", "rad", "phase of {}"),
    QuantityKind("peak", "name", "target", "peak of {} over the band", band=True,
                 derived="peak_frequency"),
    QuantityKind("stable", "", ""),
    QuantityKind("nonlinear_amplitude", "name", "target", "amplitude of {} (nonlinear)",
                 band=True),
    QuantityKind("rms", "name", "target"),
    QuantityKind("srs", "name@frequency", "target"),
    QuantityKind("damage", "name", ""),
    QuantityKind("critical_speed", "index@order", "rad/s", rotor=True),
    QuantityKind("stability_threshold", "", "rad/s", rotor=True),
    QuantityKind("log_decrement", "index@speed", "", rotor=True),
)
#: kind -> its entry
QUANTITY_KINDS = MappingProxyType({kind.name: kind for kind in QUANTITY_KIND_TABLE})
#: the second columns some kinds give: a peak's frequency, in the unit of the band's parameter
DERIVED_COLUMNS = MappingProxyType({"peak_frequency": QuantityKind(
    "peak_frequency", "name", "band", "frequency of the peak of {}")})
#: the rotor quantities (docs/rotors.md): computed from the model's [campbell] section
ROTOR_KINDS = tuple(kind.name for kind in QUANTITY_KIND_TABLE if kind.rotor)
#: the quantities that need a band: peaks (searched over it) and the nonlinear steady state
#: (swept up from its start)
BAND_KINDS = tuple(kind.name for kind in QUANTITY_KIND_TABLE if kind.band)
#: the most harmonics of the nonlinear steady state (every nonlinear analysis's limit)
MAX_HARMONICS = MAX_GIVEN_HARMONICS
#: most samples of one study (a grid's product included): 10^9 rows is ~10 GB per column
MAX_SAMPLES = 1_000_000_000
MAX_VARIED = 100
MAX_QUANTITIES = 200
MAX_LIST_VALUES = 100_000
MAX_BAND_POINTS = 100_000
MAX_SEED = 2**63 - 1
#: columns of every result besides the varied parameters and the quantities
RESERVED_COLUMNS = ("sample", "status", "reason")


@dataclass(frozen=True)
class Distribution:
    """How one parameter varies.

    Parameters
    ----------
    kind : {"uniform", "normal", "lognormal", "values"}
    arguments : tuple of float
        (lower, upper), (mean, standard deviation), or the listed values (SI).
    text : str
        The specification as written.

    Examples
    --------
    >>> d = Distribution("uniform", (1.0, 3.0), "uniform(1, 3)")
    >>> d.from_unit(np.array([0.0, 0.5])).tolist(), d.grid(3).tolist()
    ([1.0, 2.0], [1.0, 2.0, 3.0])
    """

    kind: str
    arguments: tuple[float, ...]
    text: str

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        """The values at the points ``u`` of (0, 1) (the inverse distribution function).

        Parameters
        ----------
        u : ndarray
            Probabilities in [0, 1).

        Returns
        -------
        ndarray
        """
        a = self.arguments
        if self.kind == "uniform":
            return a[0] + u * (a[1] - a[0])
        if self.kind == "values":
            values = np.asarray(a)
            return values[np.minimum((u * len(values)).astype(np.int64), len(values) - 1)]
        from scipy.special import ndtri  # only normal distributions need it (start-up)

        if self.kind == "normal":
            return a[0] + a[1] * ndtri(u)
        sigma2 = math.log1p((a[1] / a[0]) ** 2)  # lognormal
        return np.exp(math.log(a[0]) - sigma2 / 2 + math.sqrt(sigma2) * ndtri(u))

    def grid(self, points: int) -> np.ndarray:
        """The values of a grid axis: the listed values, or ``points`` evenly spaced
        between the bounds of a uniform distribution.

        Parameters
        ----------
        points : int

        Returns
        -------
        ndarray
        """
        if self.kind == "values":
            return np.asarray(self.arguments)
        if self.kind == "uniform":
            return np.linspace(self.arguments[0], self.arguments[1], points)
        raise ModelError(f"a grid needs a list, a range or uniform(a, b), not {self.text}")

    def to_dict(self) -> dict[str, Any]:
        """The JSON form.

        Returns
        -------
        dict
        """
        return {"kind": self.kind, "arguments": list(self.arguments), "text": self.text}


@dataclass(frozen=True)
class Quantity:
    """One recorded quantity, named as written (``natural_frequency:1``, ``peak:x2``).

    Parameters
    ----------
    kind : str
        A key of :data:`QUANTITY_KINDS`.
    target : str
        The coordinate or output (amplitude, phase, peak).
    index : int
        The mode, counted from 1, lowest first (natural_frequency, damping_ratio).
    text : str
        As written.
    frequency : float
        The oscillator's natural frequency in Hz (``srs:NAME@f``).
    order : float
        The excitation order of ``critical_speed:K@R`` (1 without ``@``).
    speed : float
        The rotor speed in rad/s of ``log_decrement:K@SPEED``.

    Examples
    --------
    >>> Quantity("peak", "x2", 0, "peak:x2").columns
    ('peak:x2', 'peak_frequency:x2')
    """

    kind: str
    target: str
    index: int
    text: str
    frequency: float = 0.0
    order: float = 1.0
    speed: float = 0.0

    @property
    def columns(self) -> tuple[str, ...]:
        """The columns of the result (a peak also gives the frequency where it is)."""
        derived = QUANTITY_KINDS[self.kind].derived if self.kind in QUANTITY_KINDS else ""
        return (self.text, f"{derived}:{self.target}") if derived else (self.text,)


@dataclass(frozen=True)
class Band:
    """The band over which ``peak:NAME`` looks for the largest amplitude.

    Parameters
    ----------
    parameter : str
        The parameter swept (the excitation frequency).
    start, stop : float
        Its bounds (SI).
    points : int
        The grid of the first search (the peak is then refined between grid points).

    Examples
    --------
    >>> Band("omega", 1.0, 10.0, 200).to_dict()["points"]
    200
    """

    parameter: str
    start: float
    stop: float
    points: int = 200

    def to_dict(self) -> dict[str, Any]:
        """The JSON form.

        Returns
        -------
        dict
        """
        return {"parameter": self.parameter, "from": self.start, "to": self.stop,
                "points": self.points}


@dataclass(frozen=True)
class StudySpec:
    """A checked study request.

    Parameters
    ----------
    vary : mapping
        parameter -> :class:`Distribution`, in the order given.
    quantities : tuple of Quantity
    design : str
        One of :data:`DESIGNS`.
    samples : int
        The number of samples (``random``, ``lhs``), the base sample count N of
        Saltelli's scheme (``sobol``: N (D + 2) model runs), or the points per
        axis of a uniform distribution on a ``grid``.
    seed : int
    band : Band or None
        For ``peak:`` quantities (searched over it) and ``nonlinear_amplitude:``
        (swept up from its start).
    harmonics : int or None
        The harmonics of ``nonlinear_amplitude:`` (None: chosen, as ``sweep --nonlinear``).

    Examples
    --------
    >>> spec = study_spec({"k": [1, 2, 3], "m": [1, 2]}, ["stable"], design="grid",
    ...                   parameters=["m", "k"], coordinates=["x"], outputs=[])
    >>> spec.size
    6
    """

    vary: Mapping[str, Distribution]
    quantities: tuple[Quantity, ...]
    design: str = "random"
    samples: int = 1000
    seed: int = 0
    band: Band | None = None
    harmonics: int | None = None
    columns: tuple[str, ...] = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "vary", MappingProxyType(dict(self.vary)))
        clash = [n for n in self.vary if n in RESERVED_COLUMNS or n in
                 {c for q in self.quantities for c in q.columns}]
        if clash:
            raise ModelError(f"the parameter '{clash[0]}' has the name of a column of the "
                             "result (sample, status, reason or a quantity): rename it")
        object.__setattr__(self, "columns", tuple(
            c for q in self.quantities for c in q.columns))

    def __reduce__(self) -> tuple[Any, tuple]:
        # a mapping proxy does not pickle: rebuild from the fields (workers get the spec)
        return (StudySpec, (dict(self.vary), self.quantities, self.design, self.samples,
                            self.seed, self.band, self.harmonics))

    @property
    def size(self) -> int:
        """The number of model evaluations (rows of the result)."""
        if self.design == "grid":
            return math.prod(len(d.grid(self.samples)) for d in self.vary.values())
        if self.design == "sobol":
            return self.samples * (len(self.vary) + 2)
        return self.samples

    def to_request(self) -> dict[str, Any]:
        """The arguments of :func:`study_spec` that give this study again.

        Returns
        -------
        dict
        """
        return {"vary": {k: list(d.arguments) if d.kind == "values" else
                         f"{d.kind}({d.arguments[0]!r}, {d.arguments[1]!r})"
                         for k, d in self.vary.items()},
                "quantities": [q.text for q in self.quantities], "design": self.design,
                "samples": self.samples, "seed": self.seed,
                "band": self.band.to_dict() if self.band else None, **self._harmonics()}

    def _harmonics(self) -> dict[str, int]:
        return {} if self.harmonics is None else {"harmonics": self.harmonics}

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (what a result file records as its study).

        Returns
        -------
        dict
        """
        return {"vary": {k: d.to_dict() for k, d in self.vary.items()},
                "quantities": [q.text for q in self.quantities], "design": self.design,
                "samples": self.samples, "seed": self.seed,
                "band": self.band.to_dict() if self.band else None, **self._harmonics()}


# -- reading ----------------------------------------------------------------------------------

class _Reader:
    """Collects the problems of one study request; ``where`` names file and section."""

    def __init__(self, source: str, section: str, units: ModelUnits | None) -> None:
        self.source, self.section, self.units = source, section, units
        self.problems: list[Problem] = []

    def problem(self, message: str, key: str) -> None:
        self.problems.append(Problem(message, self.source, self.section, key))

    def number(self, raw: object, name: str, key: str) -> float | None:
        """A number with an optional unit, in SI; the unit checked against ``name``'s."""
        if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
            self.problem(f"expected a number, got {type(raw).__name__}", key)
            return None
        try:
            expression, given = parse_with_unit(raw, allowed=(), file=self.source,
                                                section=self.section, key=key)
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            return None
        if given is not None and self.units is not None:
            mismatch = self.units.replacement_problem(name, *given)
            if mismatch:
                self.problem(mismatch, key)
                return None
        value = float(numeric_value(expression, {}))
        if not math.isfinite(value):
            self.problem(f"'{raw}' is not a finite number", key)
            return None
        return value


def _split_arguments(text: str) -> list[str]:
    """Top-level comma-separated pieces of ``text`` (commas inside brackets stay)."""
    pieces, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        depth += ch in "([{"
        depth -= ch in ")]}"
        if ch == "," and depth == 0:
            pieces.append(text[start:i].strip())
            start = i + 1
    pieces.append(text[start:].strip())
    return [p for p in pieces if p] if pieces != [""] else []


_CALL = re.compile(r"^\s*([A-Za-z_]+)\s*\((.*)\)\s*$", re.S)


def _distribution_call(reader: _Reader, name: str, text: str) -> Distribution | None:
    match = _CALL.match(text)
    if match is None:
        return None
    kind, inner = match.group(1), match.group(2)
    if kind not in DISTRIBUTIONS:
        reader.problem(f"unknown distribution '{kind}'; use uniform(a, b), normal(mean, sd), "
                       "lognormal(mean, sd), a list [..] or a range {from, to, step}", name)
        return None
    args = _split_arguments(inner)
    if len(args) != 2:
        reader.problem(f"{kind}(...) takes 2 values, got {len(args)}: {text.strip()}", name)
        return None
    numbers = [reader.number(a, name, name) for a in args]
    if None in numbers:
        return None
    a, b = (float(x) for x in numbers)  # type: ignore[arg-type]
    if kind == "uniform" and not a < b:
        reader.problem(f"uniform(a, b) needs a < b, got {text.strip()}", name)
        return None
    if kind != "uniform" and not b > 0:
        reader.problem(f"the standard deviation of {kind}(mean, sd) must be > 0", name)
        return None
    if kind == "lognormal" and not a > 0:
        reader.problem("the mean of lognormal(mean, sd) must be > 0", name)
        return None
    return Distribution(kind, (a, b), text.strip())


def _listed(reader: _Reader, name: str, items: Sequence[Any], text: str
            ) -> Distribution | None:
    if not items:
        reader.problem("the list of values is empty", name)
        return None
    if len(items) > MAX_LIST_VALUES:
        reader.problem(f"{len(items)} values; at most {MAX_LIST_VALUES}", name)
        return None
    values = [reader.number(item, name, name) for item in items]
    if None in values:
        return None
    return Distribution("values", tuple(float(v) for v in values), text)  # type: ignore[arg-type]


def _range(reader: _Reader, name: str, spec: Mapping[str, Any], text: str
           ) -> Distribution | None:
    unknown = sorted(set(spec) - {"from", "to", "step"})
    if unknown or len(spec) != 3:
        reader.problem("a range is { from = ..., to = ..., step = ... }"
                       + (f"; unknown key '{unknown[0]}'" if unknown else ""), name)
        return None
    parts = {k: reader.number(spec[k], name, name) for k in ("from", "to", "step")}
    if None in parts.values():
        return None
    start, stop, step = (Decimal(repr(float(parts[k])))  # type: ignore[arg-type]
                         for k in ("from", "to", "step"))
    if not step > 0 or stop < start:
        reader.problem("a range needs step > 0 and to >= from", name)
        return None
    try:
        count = int((stop - start) / step) + 1
    except InvalidOperation:
        count = MAX_LIST_VALUES + 1
    if count > MAX_LIST_VALUES:
        reader.problem(f"the range has {count} values; at most {MAX_LIST_VALUES}", name)
        return None
    return Distribution("values", tuple(float(start + i * step) for i in range(count)), text)


def parse_distribution(raw: object, name: str, reader: _Reader) -> Distribution | None:
    """One parameter's specification (see the module docstring); None after a problem."""
    if isinstance(raw, str):
        text = raw.strip()
        if text.startswith("[") or text.startswith("{"):
            try:
                raw = tomllib.loads(f"v = {text}")["v"]
            except tomllib.TOMLDecodeError:
                if text.startswith("[") and text.endswith("]"):
                    return _listed(reader, name, _split_arguments(text[1:-1]), text)
                reader.problem(f"cannot read '{text}': a list is [1, 2, 3], a range "
                               "{from = 1, to = 3, step = 1}", name)
                return None
        else:
            call = _distribution_call(reader, name, text)
            if call is not None or _CALL.match(text):
                return call
            value = reader.number(text, name, name)
            return None if value is None else Distribution("values", (value,), text)
    if isinstance(raw, list):
        return _listed(reader, name, raw, str(raw))
    if isinstance(raw, dict):
        return _range(reader, name, raw, str(raw))
    value = reader.number(raw, name, name)
    return None if value is None else Distribution("values", (value,), str(raw))


def parse_quantity(text: object, names: Collection[str], reader: _Reader) -> Quantity | None:
    """``kind[:target]`` checked against the model's coordinates and outputs."""
    if not isinstance(text, str):
        reader.problem(f"a quantity is a text such as 'natural_frequency:1', got "
                       f"{type(text).__name__}", "quantities")
        return None
    kind, _, target = (part.strip() for part in text.strip().partition(":"))
    entry = QUANTITY_KINDS.get(kind)
    if entry is None:
        reader.problem(f"unknown quantity '{text}'; the quantities are "
                       + ", ".join(f"{k.name}:{k.target.upper()}" if k.target else k.name
                                   for k in QUANTITY_KIND_TABLE), "quantities")
        return None
    what = entry.target
    if what in ("index@order", "index@speed"):
        return _rotor_quantity(kind, what, target, text, reader)
    if what == "index":
        if not target.isdigit() or not 1 <= int(target) <= 100_000:
            reader.problem(f"'{text}' needs a mode number counted from 1, as in {kind}:1",
                           "quantities")
            return None
        return Quantity(kind, "", int(target), f"{kind}:{int(target)}")
    if what == "name":
        if target not in names:
            reader.problem(f"'{text}': '{target}' is not a coordinate or output; they are "
                           + name_list(names, 20), "quantities")
            return None
        return Quantity(kind, target, 0, f"{kind}:{target}")
    if what == "name@frequency":
        name, _, at = (part.strip() for part in target.partition("@"))
        frequency = _frequency_hz(at)
        if not (math.isfinite(frequency) and frequency > 0):
            reader.problem(f"'{text}' needs a natural frequency in Hz after '@' (positive; "
                           "or a number with a unit of frequency), as in "
                           f"{kind}:{name or 'NAME'}@100 or @0.1 kHz", "quantities")
            return None
        if name not in names:
            reader.problem(f"'{text}': '{name}' is not a coordinate or output; they are "
                           + name_list(names, 20), "quantities")
            return None
        return Quantity(kind, name, 0, f"{kind}:{name}@{frequency:.12g}", frequency)
    if target:
        reader.problem(f"'{kind}' takes no ':'", "quantities")
        return None
    return Quantity(kind, "", 0, kind)


def _rotor_quantity(kind: str, what: str, target: str, text: str, reader: _Reader
                    ) -> Quantity | None:
    """``critical_speed:K[@ORDER]`` (the K-th critical speed of that excitation order) and
    ``log_decrement:K@SPEED`` (a number in rad/s or a speed with its unit, as ``3000 rpm``).
    """
    index, _, at = (part.strip() for part in target.partition("@"))
    example = f"{kind}:1@2" if what == "index@order" else f"{kind}:1@3000 rpm"
    if not index.isdigit() or not 1 <= int(index) <= 100_000:
        reader.problem(f"'{text}' needs a number counted from 1, as in {example}",
                       "quantities")
        return None
    if what == "index@order":
        try:
            order = float(at) if at else 1.0
        except ValueError:
            order = math.nan
        if not (math.isfinite(order) and order > 0):
            reader.problem(f"'{text}' needs a positive excitation order after '@', as in "
                           f"{example}", "quantities")
            return None
        suffix = "" if order == 1.0 else f"@{order:.12g}"
        return Quantity(kind, "", int(index), f"{kind}:{int(index)}{suffix}", order=order)
    if not at:
        reader.problem(f"'{text}' needs a speed after '@', as in {example}", "quantities")
        return None
    speed = parse_speed(at, reader.source, reader.section, "quantities", reader.problems)
    if speed is None:
        return None
    return Quantity(kind, "", int(index), f"{kind}:{int(index)}@{at}", speed=speed)


def _frequency_hz(text: str) -> float:
    """A natural frequency in Hz from ``text``: a number (Hz), arithmetic of numbers, or
    either with a unit of frequency as ``[parameters]`` takes it (``0.1 kHz``, ``628.3
    rad/s``: an angular frequency is divided by 2 pi); NaN where it is none of these.

    Examples
    --------
    >>> _frequency_hz("100"), _frequency_hz("0.1 kHz"), round(_frequency_hz("2*pi*50 rad/s"), 9)
    (100.0, 100.0, 50.0)
    >>> _frequency_hz("3 m")
    nan
    """
    problems: list[Problem] = []
    value = quantity_value(text, FREQUENCY, "", "", "", problems)
    return math.nan if problems or not isinstance(value, float) else value


def _integer(reader: _Reader, raw: object, key: str, low: int, high: int) -> int | None:
    if isinstance(raw, bool) or not isinstance(raw, int) or not low <= raw <= high:
        reader.problem(f"{key} must be a whole number from {low} to {high}, got {raw!r}", key)
        return None
    return raw


def parse_band(raw: object, parameters: Collection[str], reader: _Reader) -> Band | None:
    """``{parameter = "omega", from = 1, to = 30, points = 200}`` (points optional)."""
    if not isinstance(raw, dict):
        reader.problem("band is { parameter = \"omega\", from = ..., to = ..., points = ... }",
                       "band")
        return None
    unknown = sorted(set(raw) - {"parameter", "from", "to", "points"})
    if unknown:
        reader.problem(f"unknown key '{unknown[0]}' in band; it has parameter, from, to, "
                       "points", "band")
        return None
    param = raw.get("parameter", "omega")
    if param not in parameters:
        reader.problem(f"the band's parameter '{param}' is not a parameter of the model",
                       "band")
        return None
    if "from" not in raw or "to" not in raw:
        reader.problem("band needs from and to", "band")
        return None
    start, stop = (reader.number(raw[k], str(param), "band") for k in ("from", "to"))
    points = _integer(reader, raw.get("points", 200), "points", 3, MAX_BAND_POINTS)
    if start is None or stop is None or points is None:
        return None
    if not 0 <= start < stop:
        reader.problem(f"the band needs 0 <= from < to, got {start:g} to {stop:g}", "band")
        return None
    return Band(str(param), start, stop, points)


def _design(reader: _Reader, design: object, samples: object, seed: object
            ) -> tuple[str, int, int] | None:
    if design not in DESIGNS:
        reader.problem(f"unknown design {design!r}; the designs are {', '.join(DESIGNS)}",
                       "design")
        return None
    count = _integer(reader, samples, "samples", 1, MAX_SAMPLES)
    start = _integer(reader, seed, "seed", 0, MAX_SEED)
    if count is None or start is None:
        return None
    return str(design), count, start


def study_spec(vary: Mapping[str, Any], quantities: Sequence[Any], *, design: object = "random",
               samples: object = 1000, seed: object = 0, band: object = None,
               harmonics: object = None,
               parameters: Collection[str], coordinates: Collection[str],
               outputs: Collection[str], units: ModelUnits | None = None,
               source: str = "", section: str = "study") -> StudySpec:
    """Check a study request against a model's names.

    Parameters
    ----------
    vary : mapping
        parameter -> specification (see the module docstring).
    quantities : sequence of str
        As ``natural_frequency:1``, ``amplitude:x2``, ``peak:x2``, ``stable``,
        ``nonlinear_amplitude:x2``.
    design, samples, seed, band, harmonics
        See :class:`StudySpec`; ``band`` a mapping as in :func:`parse_band`.
    parameters, coordinates, outputs : collection of str
        The model's names.
    units : ModelUnits, optional
        The model's units, to check values given with a unit.
    source, section : str
        Where the request comes from, for the messages.

    Returns
    -------
    StudySpec

    Raises
    ------
    ModelError
        Naming every problem (file, section, key).

    Examples
    --------
    >>> study_spec({"k": "uniform(2, 1)"}, ["stable"], parameters=["k"], coordinates=["x"],
    ...            outputs=[])
    Traceback (most recent call last):
    ...
    resonant.errors.ModelError: <model>: [study] k: uniform(a, b) needs a < b, got uniform(2, 1)
    """
    reader = _Reader(source, section, units)
    spec = _read(reader, vary, quantities, design, samples, seed, band, parameters,
                 [*coordinates, *outputs], outputs)
    if harmonics is not None:
        count = _integer(reader, harmonics, "harmonics", 1, MAX_HARMONICS)
        if spec is not None and count is not None:
            spec = replace(spec, harmonics=count)
    if reader.problems or spec is None:
        raise ModelError(reader.problems or [Problem("invalid study", source, section)])
    return spec


def _read(reader: _Reader, vary: object, quantities: object, design: object, samples: object,
          seed: object, band: object, parameters: Collection[str], names: Collection[str],
          outputs: Collection[str]) -> StudySpec | None:
    if not isinstance(vary, Mapping) or not vary:
        reader.problem("a study varies at least one parameter (vary = { k = \"...\" })",
                       "vary")
        return None
    if len(vary) > MAX_VARIED:
        reader.problem(f"{len(vary)} varied parameters; at most {MAX_VARIED}", "vary")
        return None
    distributions: dict[str, Distribution] = {}
    for name, raw in vary.items():
        if name not in parameters:
            reader.problem(f"'{name}' is not a parameter of the model", str(name))
            continue
        distribution = parse_distribution(raw, name, reader)
        if distribution is not None:
            distributions[name] = distribution
    if isinstance(quantities, str) or not isinstance(quantities, Sequence) or not quantities \
            or len(quantities) > MAX_QUANTITIES:
        reader.problem(f"quantities is a list of 1 to {MAX_QUANTITIES} texts such as "
                       "[\"natural_frequency:1\", \"peak:x2\"]", "quantities")
        return None
    read = [parse_quantity(q, names, reader) for q in quantities]
    modes = len([n for n in names if n not in outputs])
    for q in read:
        if q is not None and q.kind != "critical_speed" and q.index > modes > 0:
            reader.problem(f"'{q.text}': the model has {modes} modes", "quantities")
    chosen = _design(reader, design, samples, seed)
    needs_band = [q.kind for q in read if q is not None and q.kind in BAND_KINDS]
    band_spec = parse_band(band, parameters, reader) if band is not None else None
    if needs_band and band is None:
        reader.problem(f"{needs_band[0]}: quantities need a band = {{ parameter = \"omega\", "
                       "from = ..., to = ... }", "band")
    if reader.problems or chosen is None:
        return None
    unique = list(dict.fromkeys(q for q in read if q is not None))
    spec = StudySpec(distributions, tuple(unique), *chosen, band=band_spec)
    return _checked_size(reader, spec)


def _checked_size(reader: _Reader, spec: StudySpec) -> StudySpec | None:
    if spec.design == "grid":
        for name, d in spec.vary.items():
            if d.kind not in ("values", "uniform"):
                reader.problem(f"a grid needs a list, a range or uniform(a, b), not {d.text}",
                               name)
                return None
    if spec.size > MAX_SAMPLES:
        reader.problem(f"the study has {spec.size} samples; at most {MAX_SAMPLES}", "samples")
        return None
    return spec


def rotor_problems(spec: StudySpec, has_campbell: bool, has_speed: bool, source: str
                   ) -> list[Problem]:
    """What the rotor quantities of ``spec`` miss: the ``[campbell]`` section's speed
    range (critical speeds, the threshold) and a speed parameter (all of them).

    Examples
    --------
    >>> spec = study_spec({"k": [1.0]}, ["stability_threshold"], parameters=["k"],
    ...                   coordinates=["x"], outputs=[])
    >>> rotor_problems(spec, False, True, "r.toml")[0].section
    'campbell'
    """
    kinds = {q.kind for q in spec.quantities}
    problems = []
    if not has_speed and kinds & set(ROTOR_KINDS):
        problems.append(Problem(f"{sorted(kinds & set(ROTOR_KINDS))[0]} needs a rotor: a "
                                "speed parameter (speed = \"NAME\" in [matrices] or [rotor])",
                                source, "study", "quantities"))
    ranged = sorted(kinds & {"critical_speed", "stability_threshold"})
    if ranged and not has_campbell:
        problems.append(Problem(f"{ranged[0]} is searched over the [campbell] section's "
                                "speed range: add [campbell] with from, to and points",
                                source, "campbell"))
    return problems


STUDY_KEYS = ("vary", "quantities", "design", "samples", "seed", "band", "harmonics")


def parse_study(raw: object, parameters: Collection[str], coordinates: Collection[str],
                outputs: Collection[str], units: ModelUnits | None, source: str,
                problems: list[Problem]) -> StudySpec | None:
    """The ``[study]`` section of a model file; problems appended, None after one.

    Parameters
    ----------
    raw : object
        The section as read from TOML.
    parameters, coordinates, outputs : collection of str
        The model's names.
    units : ModelUnits or None
    source : str
    problems : list of Problem
        Receives the problems.

    Returns
    -------
    StudySpec or None
    """
    if not isinstance(raw, dict):
        problems.append(Problem("[study] must be a table", source, "study"))
        return None
    unknown = sorted(set(raw) - set(STUDY_KEYS))
    if unknown:
        problems.append(Problem(f"unknown key '{unknown[0]}'; [study] has "
                                + ", ".join(STUDY_KEYS), source, "study", unknown[0]))
        return None
    try:
        return study_spec(raw.get("vary", {}), raw.get("quantities", []),
                          design=raw.get("design", "random"), samples=raw.get("samples", 1000),
                          seed=raw.get("seed", 0), band=raw.get("band"),
                          harmonics=raw.get("harmonics"), parameters=parameters,
                          coordinates=coordinates, outputs=outputs, units=units, source=source)
    except ModelError as exc:
        problems.extend(exc.problems)
        return None


__all__ = ["Band", "BAND_KINDS", "DERIVED_COLUMNS", "DESIGNS", "DISTRIBUTIONS", "Distribution",
           "QUANTITY_KINDS", "QUANTITY_KIND_TABLE", "QuantityKind",
           "ROTOR_KINDS", "Quantity", "StudySpec", "parse_study", "rotor_problems", "study_spec"]
