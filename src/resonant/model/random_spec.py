"""The ``[random]`` section: stationary random excitation given by spectral densities.

Each input is a one-sided spectral density per Hz (the convention of test standards) of
a signal of the model, of a force on a coordinate, or of a load or base acceleration
given by a vector (``[matrices]`` models)::

    [random]
    band = [20, 2000]            # Hz; default: the range of the tables
    tolerance = 1e-4             # relative error of the mean squares' quadrature

    [random.psd.y]               # y: a signal of the model
    derivative = 2               # the density is of y'' (0: of y itself, the default)
    unit = "g^2/Hz"              # g in a density's unit is standard gravity
    values = [[20, 0.026], [50, 0.16], [800, 0.16], [2000, 0.026]]   # Hz, value: log-log

    [[random.coherence]]         # between two inputs (default: uncorrelated)
    inputs = ["F1", "F2"]
    value = 0.5                  # ordinary coherence gamma^2 in [0, 1], or an expression of f
    phase = "30 deg"             # phase of the cross density S_12 (default 0)

``values`` is a table of ``[frequency in Hz, density]`` rows (interpolated linearly in
log f and log S, as standards give their spectra), a number (white), or an expression
of ``f`` (Hz) and the parameters.  Every problem names the file, the section and the key.

Examples
--------
>>> problems = []
>>> spec = parse_random({"psd": {"F": {"values": 2.0, "unit": "N^2/Hz"}},
...                      "band": [0, 100]}, ["k"], ["F"], ["x"], "f.toml", problems)
>>> spec.inputs[0].name, spec.band, problems
('F', (0.0, 100.0), [])
"""

from __future__ import annotations

import difflib
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

import resonant.model.limits as limits

from ..errors import Problem, printable
from ..expressions import (
    Expression,
    ExpressionError,
    numeric_value,
    parse,
    primed_names,
    validate_name,
)
from .csv_tables import read_csv_table
from .files import FileRefused
from .limits import MAX_FREQUENCY_HZ
from .load_spec import check_input_dimension, quantity_parts, quantity_value
from .matrix_files import read_vector_file
from .units import (
    DIMENSIONLESS,
    FREQUENCY,
    GRAVITY_IN_UNIT,
    Dimension,
    ModelUnits,
    UnitError,
    parse_unit,
    parse_with_unit,
    split_value,
)

SECTION = "random"
#: the options of ``[random]`` besides its tables
OPTIONS = ("band", "tolerance", "lines", "psd", "coherence")
#: the keys of one input's table
INPUT_KEYS = ("values", "unit", "derivative", "load", "base")
#: the keys of one ``[[random.coherence]]`` entry
COHERENCE_KEYS = ("inputs", "value", "phase")
#: most inputs and most rows of one table
MAX_INPUTS = 100
MAX_ROWS = 100_000
#: the finest relative quadrature tolerance accepted
MIN_TOLERANCE = 1e-10
#: standard gravity (m/s^2): ``g`` in a spectral density's unit
STANDARD_GRAVITY = 9.80665
#: the density's unit dimension is (quantity)^2 * s (per Hz or per rad/s)
PER_FREQUENCY = Dimension.of(s=1)


@dataclass(frozen=True)
class RandomInput:
    """One random input: the one-sided spectral density of a quantity, per Hz, in SI.

    Parameters
    ----------
    name : str
        A signal of the model, a coordinate (a generalized force on it), or a name of
        the section's own (with ``load`` or ``base``).
    derivative : int
        The density is of the ``derivative``-th time derivative of the signal.
    table : ndarray or None
        ``(rows, 2)``: frequency (Hz) and density (SI per Hz), interpolated log-log.
    expression : Expression or None
        The density (in ``unit``) as an expression of ``f`` (Hz) and the parameters.
    factor : float
        SI factor of the expression's unit (per Hz).
    load : tuple of Expression, optional
        The generalized force per unit input (``load``), one entry per coordinate.
    base : tuple of Expression, optional
        The influence vector of a base acceleration (``base``): the load is ``-M base``.
    unit : str
        The unit as written ("" for SI per Hz).

    Examples
    --------
    >>> RandomInput("F", 0, np.array([[1.0, 2.0], [10.0, 2.0]]), None).density(
    ...     np.array([3.0]), {}).tolist()
    [2.0]
    """

    name: str
    derivative: int
    table: np.ndarray | None
    expression: Expression | None
    factor: float = 1.0
    load: tuple[Expression, ...] = ()
    base: tuple[Expression, ...] = ()
    unit: str = ""

    def density(self, f: np.ndarray, parameters: Mapping[str, Any]) -> np.ndarray:
        """The one-sided density per Hz (SI) at the frequencies ``f`` (Hz).

        Parameters
        ----------
        f : ndarray
            Frequencies in Hz, inside the table's range.
        parameters : mapping
            The parameter values (for an expression).

        Returns
        -------
        ndarray
        """
        f = np.asarray(f, dtype=float)
        if self.table is not None:
            fi, si = self.table[:, 0], self.table[:, 1]
            with np.errstate(divide="ignore"):
                out = np.exp(np.interp(np.log(f), np.log(fi), np.log(si)))
            return np.where((f >= fi[0]) & (f <= fi[-1]), out, 0.0)
        assert self.expression is not None
        value = numeric_value(self.expression, {**parameters, "f": f})
        return np.broadcast_to(np.asarray(value, dtype=float) * self.factor, f.shape).copy()


@dataclass(frozen=True)
class Coherence:
    """The correlation of two inputs: S_ab = sqrt(gamma^2 S_aa S_bb) exp(i phase).

    Parameters
    ----------
    first, second : str
        The two inputs.
    value : Expression
        The ordinary coherence gamma^2 in [0, 1], a number or an expression of ``f`` (Hz).
    phase : Expression
        The phase of S_ab in rad.

    Examples
    --------
    >>> Coherence("a", "b", parse(1), parse(0)).first
    'a'
    """

    first: str
    second: str
    value: Expression
    phase: Expression


@dataclass(frozen=True)
class RandomSpec:
    """The ``[random]`` section.

    Parameters
    ----------
    inputs : tuple of RandomInput
        The inputs, in the file's order.
    coherences : tuple of Coherence
        The correlated pairs.
    band : tuple of float
        The frequency band (Hz) of the response: (low, high).
    tolerance : float
        Relative error of the mean squares' quadrature.
    lines : int
        Frequency lines of the first grid (refined where the response needs it).

    Examples
    --------
    >>> RandomSpec((), (), (1.0, 10.0)).tolerance
    0.0001
    """

    inputs: tuple[RandomInput, ...]
    coherences: tuple[Coherence, ...]
    band: tuple[float, float]
    tolerance: float = 1e-4
    lines: int = 400
    source: str = field(default="", compare=False)


def _unit_factor(text: object, where: tuple[str, str, str], problems: list[Problem]
                 ) -> tuple[float, Dimension | None] | None:
    """(SI factor per Hz, dimension of the density's quantity) of a density's unit."""
    if not isinstance(text, str) or not text.strip():
        problems.append(Problem("unit must be a unit text such as \"g^2/Hz\", "
                                "\"(m/s^2)^2/Hz\" or \"N^2/Hz\"", *where))
        return None
    try:
        unit = parse_unit(GRAVITY_IN_UNIT.sub("g0", text))
    except UnitError as exc:
        problems.append(Problem(f"{exc}", *where))
        return None
    if unit.cyclic:
        factor = unit.to_si()
    elif "rad" in text:
        factor = unit.to_si() * 2 * math.pi     # S per Hz = 2 pi S per (rad/s)
    else:
        problems.append(Problem(f"the unit '{text}' is not a density per frequency: divide "
                                "by Hz (e.g. \"g^2/Hz\") or by rad/s (\"N^2/(rad/s)\")",
                                *where))
        return None
    root = (unit.dimension / PER_FREQUENCY) ** Fraction(1, 2)
    if any(isinstance(e, Fraction) and e.denominator != 1 for e in root.exponents):
        # ("m^2/rad": a density per radian, not per rad/s)
        problems.append(Problem(f"the unit '{text}' is not a density per frequency: divide "
                                "a squared unit by Hz (e.g. \"g^2/Hz\") or by rad/s "
                                "(\"N^2/(rad/s)\")", *where))
        return None
    return factor, root


def _cells(values: list, where: tuple[str, str, str], problems: list[Problem],
           params: Sequence[str], unit: tuple[float, Dimension | None] | None) -> list:
    """A table's rows with its texts read: a frequency with a unit (``"2 kHz"``), a density
    as arithmetic of numbers in the input's ``unit`` (:func:`quantity_value`), or with a
    density unit of that unit's quantity (``unit``: its SI factor and quantity; None where
    the input has no key unit)."""
    if not any(isinstance(x, str) for r in values if isinstance(r, list) for x in r):
        return values
    count = len(problems)
    rows = []
    for row in values:
        if not (isinstance(row, list) and len(row) == 2):
            rows.append(row)
            continue
        frequency = quantity_value(row[0], FREQUENCY, *where, problems, params)
        rows.append([frequency, _density_cell(row[1], where, problems, params, unit)])
        if len(problems) > count:    # one problem for a table, not one per row
            break
    return rows


def _density_cell(density: object, where: tuple[str, str, str], problems: list[Problem],
                  params: Sequence[str], unit: tuple[float, Dimension | None] | None
                  ) -> object:
    """A table's density: a number, arithmetic in the key unit, or a value with a density
    unit of the key unit's quantity (converted to the key unit)."""
    if not isinstance(density, str):
        return density
    text, own = split_value(density)
    parts = quantity_parts(text, *where, problems, params)
    if parts is None or own is None:
        return None if parts is None else parts[0]
    if unit is None:
        problems.append(Problem(f"{printable(density, limit=40)!r}: a density with a unit "
                                "needs the input's key unit (the unit of its other values)",
                                *where))
        return None
    found = _unit_factor(own, where, problems)
    if found is None:
        return None
    if found[1] != unit[1]:
        problems.append(Problem(f"{printable(density, limit=40)!r}: a density of "
                                f"{_root_text(found[1])}, but the key unit is one of "
                                f"{_root_text(unit[1])}; give it in a unit of that quantity",
                                *where))
        return None
    return parts[0] * found[0] / unit[0]


def _root_text(quantity: Dimension | None) -> str:
    return "an unknown quantity" if quantity is None else quantity.text() or "1"


def _table(values: list, where: tuple[str, str, str], problems: list[Problem],
           params: Sequence[str] = (), unit: tuple[float, Dimension | None] | None = None
           ) -> np.ndarray | None:
    count = len(problems)
    values = _cells(values, where, problems, params, unit) if len(values) <= MAX_ROWS \
        else values
    if len(problems) > count:
        return None
    if len(values) > MAX_ROWS:
        problems.append(Problem(f"{len(values)} rows; a table is limited to {MAX_ROWS}", *where))
        return None
    if len(values) < 2 or not all(isinstance(r, list) and len(r) == 2 for r in values):
        problems.append(Problem("a table is a list of at least two [frequency in Hz, density] "
                                "rows", *where))
        return None
    if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for r in values for x in r):
        problems.append(Problem("the rows of the table must hold numbers", *where))
        return None
    try:
        table = np.array(values, dtype=float)
    except OverflowError:   # a whole number beyond the floating-point range
        table = np.full((len(values), 2), math.inf)
    if not np.isfinite(table).all() or (table <= 0).any():
        problems.append(Problem("the frequencies and densities of a table must be positive "
                                "numbers (log-log interpolation)", *where))
        return None
    if (np.diff(table[:, 0]) <= 0).any():
        problems.append(Problem("the frequencies of the table must increase", *where))
        return None
    return table


#: the files a load or base vector may be read from (one entry per coordinate)
VECTOR_FILES = (".npy", ".mtx", ".csv")
#: the file a density's table may be read from (rows of frequency in Hz, density)
TABLE_FILES = (".csv",)


@dataclass(frozen=True)
class Files:
    """Where the files a section names are read from: the model's folder (None for a
    model given as text) and the other folders allowed (``--allow-path``)."""

    base_dir: Path | None = None
    allow_paths: tuple[str | os.PathLike[str], ...] = ()


def _vector_file(value: str, n: int | None, files: Files, where: tuple[str, str, str],
                 problems: list[Problem]) -> tuple[Expression, ...]:
    """A load or base vector from a file (``.npy``, ``.mtx``, or ``.csv``: one number a
    line), one number per coordinate, as expressions (one per distinct value)."""
    shown = printable(value, limit=60)
    if n is None:
        problems.append(Problem(f"'{shown}': a vector from a file needs the model's "
                                "coordinates ([matrices])", *where))
        return ()
    try:
        if value.lower().endswith(".csv"):
            numbers = read_csv_table(value, 1, files.base_dir, files.allow_paths,
                                     max_rows=limits.MAX_MATRIX_DIMENSION)[:, 0]
            if len(numbers) != n:
                raise FileRefused(f"it holds {len(numbers)} entries; the model has {n} "
                                  "coordinates")
        else:
            numbers = read_vector_file(value, n, files.base_dir, files.allow_paths)
    except FileRefused as exc:
        problems.append(Problem(f"'{shown}': {exc}", *where))
        return ()
    if not np.isfinite(numbers).all():
        i = int(np.flatnonzero(~np.isfinite(numbers))[0])
        problems.append(Problem(f"'{shown}': entry {i + 1} is {numbers[i]}; a vector needs "
                                "finite numbers", *where))
        return ()
    parsed: dict[float, Expression] = {}
    return tuple(parsed.setdefault(x, parse(repr(x))) for x in map(float, numbers))


def _table_file(value: str, files: Files, where: tuple[str, str, str],
                problems: list[Problem]) -> np.ndarray | None:
    """A density's table from a CSV file of [frequency in Hz, density] rows."""
    try:
        rows = read_csv_table(value, 2, files.base_dir, files.allow_paths, max_rows=MAX_ROWS)
    except FileRefused as exc:
        problems.append(Problem(f"'{printable(value, limit=60)}': {exc}", *where))
        return None
    return _table(rows.tolist(), where, problems)


def _is_file(value: object, suffixes: Sequence[str]) -> bool:
    return isinstance(value, str) and value.strip().lower().endswith(tuple(suffixes))


def _vector(value: object, allowed: list[str], n: int | None, where: tuple[str, str, str],
            problems: list[Problem], files: Files = Files()) -> tuple[Expression, ...]:
    if _is_file(value, VECTOR_FILES):
        assert isinstance(value, str)
        return _vector_file(value.strip(), n, files, where, problems)
    if not isinstance(value, list) or (n is not None and len(value) != n):
        problems.append(Problem(f"expected a list of {n if n is not None else 'the'} "
                                "entries, one per coordinate, or a file of them ("
                                f"{', '.join(VECTOR_FILES)})", *where))
        return ()
    out = []
    for entry in value:
        try:
            expression = parse(entry, allowed=allowed, file=where[0], section=where[1],
                               key=where[2])
        except ExpressionError as exc:
            problems.extend(exc.problems)
            continue
        if _no_primes(expression, where, problems):
            out.append(expression)
    return tuple(out)


def _no_primes(expression: Expression, where: tuple[str, str, str],
               problems: list[Problem]) -> bool:
    """Whether ``expression`` has no time derivative (``f'``, ``k'``): a density, a load
    vector or a coherence is a function of the frequency and the parameters, constants in
    time (a prime was read as a zero)."""
    primed = primed_names(expression)
    if primed:
        problems.append(Problem(f"{primed[0]}: a time derivative has no meaning here (a "
                                "function of the frequency f and the parameters); remove the "
                                "prime", *where))
    return not primed


def _input(name: str, table: object, params: list[str], signals: Sequence[str],
           coordinates: Sequence[str], units: ModelUnits | None, source: str,
           problems: list[Problem], files: Files = Files()) -> RandomInput | None:
    section = f"{SECTION}.psd.{name}"
    reason = validate_name(name)
    if reason is not None:  # a name is printed in reports, on terminals and in LaTeX
        shown = printable(name, limit=40)
        reason = reason.replace(repr(name), f"'{shown}'")
        problems.append(Problem(f"an input's name, like every name of the model: {reason}",
                                source, f"{SECTION}.psd", shown))
        return None
    if not isinstance(table, dict):
        problems.append(Problem("expected a table with 'values' and 'unit'", source,
                                f"{SECTION}.psd", name))
        return None
    count = len(problems)
    for key in table:
        if key not in INPUT_KEYS:
            close = difflib.get_close_matches(key, INPUT_KEYS, n=1)
            hint = f"did you mean '{close[0]}'?" if close else f"known: {', '.join(INPUT_KEYS)}"
            problems.append(Problem(f"unknown key '{key}'; {hint}", source, section, key))
    load = _vector(table["load"], params, len(coordinates) or None, (source, section, "load"),
                   problems, files) if "load" in table else ()
    base = _vector(table["base"], params, len(coordinates) or None, (source, section, "base"),
                   problems, files) if "base" in table else ()
    if load and base:
        problems.append(Problem("give either 'load' or 'base', not both", source, section))
    vector = "load" in table or "base" in table   # (a vector that failed: its problem said)
    if not vector and name not in signals and name not in coordinates:
        close = difflib.get_close_matches(name, [*signals, *coordinates], n=1)
        hint = f"did you mean '{close[0]}'?" if close else \
            "give a signal or a coordinate of the model, or a 'load' or 'base' vector"
        problems.append(Problem(f"'{name}' is neither a signal nor a coordinate; {hint}",
                                source, f"{SECTION}.psd", name))
    derivative = table.get("derivative", 2 if base else 0)
    if isinstance(derivative, bool) or derivative not in (0, 1, 2):
        problems.append(Problem("derivative must be 0, 1 or 2 (the density is of the "
                                "signal, its rate or its acceleration)", source, section,
                                "derivative"))
        derivative = 0
    if (base and derivative != 2) or (name in coordinates and not load and derivative != 0):
        problems.append(Problem("derivative must be 2 for a base acceleration and 0 for a "
                                "force on a coordinate", source, section, "derivative"))
    factor, quantity = 1.0, None
    if "unit" in table:
        found = _unit_factor(table["unit"], (source, section, "unit"), problems)
        if found is not None:
            factor, quantity = found
    check_input_dimension(name, quantity, int(derivative), bool(base), units, coordinates,
                          (source, section, "unit"), problems, density=True)
    values = table.get("values")
    array, expression = None, None
    if values is None:
        problems.append(Problem("missing 'values': a table [[Hz, density], ...], a number or "
                                "an expression of f (Hz)", source, section))
    elif isinstance(values, list) or _is_file(values, TABLE_FILES):
        array = _table(values, (source, section, "values"), problems, params,
                       (factor, quantity) if "unit" in table else None) \
            if isinstance(values, list) else \
            _table_file(str(values).strip(), files, (source, section, "values"), problems)
        if array is not None:
            with np.errstate(over="ignore", under="ignore"):
                array[:, 1] *= factor
            if not np.isfinite(array[:, 1]).all() or (array[:, 1] == 0).any():
                problems.append(Problem(f"the densities in SI units ({factor:g} x the values) "
                                        "leave the floating-point range; give smaller values",
                                        source, section, "values"))
    else:
        expression = _density_expression(values, params, (source, section, "values"), problems)
    if len(problems) > count:
        return None
    return RandomInput(name, int(derivative), array, expression, factor, load, base,
                       str(table.get("unit", "")))


def _density_expression(values: str | float, params: list[str], where: tuple[str, str, str],
                        problems: list[Problem]) -> Expression | None:
    """A density given as a number or an expression of f and the parameters, in the
    input's unit (a unit of its own is refused: the key ``unit`` gives it)."""
    if isinstance(values, str) and split_value(values)[1] is not None:
        problems.append(Problem(f"{printable(values, limit=40)!r}: a density takes no unit of "
                                "its own; give the number (or an expression of f) in the "
                                "input's unit, and the unit once, in the key unit", *where))
        return None
    try:
        expression = parse(values, allowed=[*params, "f"], file=where[0], section=where[1],
                           key=where[2])
    except ExpressionError as exc:
        problems.extend(exc.problems)
        return None
    _no_primes(expression, where, problems)
    return expression


def _coherence(entry: object, index: int, params: list[str], names: list[str], source: str,
               problems: list[Problem]) -> Coherence | None:
    section = f"{SECTION}.coherence"
    key = f"#{index + 1}"
    if not isinstance(entry, dict):
        problems.append(Problem("expected a table with 'inputs' and 'value'", source, section,
                                key))
        return None
    for k in entry:
        if k not in COHERENCE_KEYS:
            problems.append(Problem(f"unknown key '{k}'; known: {', '.join(COHERENCE_KEYS)}",
                                    source, section, key))
    pair = entry.get("inputs")
    if not (isinstance(pair, list) and len(pair) == 2 and all(p in names for p in pair)
            and pair[0] != pair[1]):
        problems.append(Problem("inputs must name two different inputs of [random.psd] "
                                f"(known: {', '.join(names) or 'none'})", source, section, key))
        return None
    try:
        value = parse(entry.get("value", 1), allowed=[*params, "f"], file=source,
                      section=section, key=key)
        phase, given = parse_with_unit(entry.get("phase", 0), params, source, section, key)
    except ExpressionError as exc:
        problems.extend(exc.problems)
        return None
    if not (_no_primes(value, (source, section, key), problems)
            and _no_primes(phase, (source, section, key), problems)):
        return None
    if given is not None and not given[1].dimension.dimensionless:
        problems.append(Problem(f"the phase's unit '{given[1].text}' is not an angle; give it "
                                "in rad or deg (\"30 deg\")", source, section, key))
        return None
    return Coherence(pair[0], pair[1], value, phase)


def _check_pairs_once(coherences: Sequence[Coherence | None], source: str,
                      problems: list[Problem]) -> None:
    """A pair of inputs has one coherence: a second entry for it (in either order) would
    leave which value holds to the order of the file."""
    first: dict[frozenset[str], int] = {}
    for index, c in enumerate(coherences):
        if c is None:
            continue
        pair = frozenset((c.first, c.second))
        if pair in first:
            problems.append(Problem(
                f"the coherence of {c.first} and {c.second} is given twice (entries "
                f"#{first[pair] + 1} and #{index + 1}); give each pair once",
                source, f"{SECTION}.coherence", f"#{index + 1}"))
        else:
            first[pair] = index


def parse_random(data: object, params: list[str], signals: Sequence[str],
                 coordinates: Sequence[str], source: str, problems: list[Problem],
                 units: ModelUnits | None = None, files: Files = Files()
                 ) -> RandomSpec | None:
    """The ``[random]`` section, its problems appended to ``problems``.

    Parameters
    ----------
    data : object
        The section as read from TOML.
    params : list of str
        The parameters (allowed in expressions, with ``f``).
    signals, coordinates : sequence of str
        The model's signals and coordinates (the names an input may have).
    source : str
        The model file.
    problems : list of Problem
        Receives every problem found.
    units : ModelUnits, optional
        The model's units: a density's unit is checked against its signal's.
    files : Files, optional
        Where the files of ``load``, ``base`` and ``values`` are read from (without a
        folder, none is).

    Returns
    -------
    RandomSpec or None
        None when the section has problems.

    Examples
    --------
    >>> problems = []
    >>> parse_random({"psd": {"xx": {"values": 1}}}, [], [], ["x"], "m.toml", problems)
    >>> print(problems[0])
    m.toml: [random.psd] xx: 'xx' is neither a signal nor a coordinate; did you mean 'x'?
    """
    count = len(problems)
    if not isinstance(data, dict):
        problems.append(Problem("expected a table", source, SECTION))
        return None
    for key in data:
        if key not in OPTIONS:
            close = difflib.get_close_matches(key, OPTIONS, n=1)
            hint = f"did you mean '{close[0]}'?" if close else f"known: {', '.join(OPTIONS)}"
            problems.append(Problem(f"unknown key '{key}'; {hint}", source, SECTION, key))
    tables = data.get("psd")
    if not isinstance(tables, dict) or not tables:
        problems.append(Problem("no input: add a table [random.psd.NAME] for each random "
                                "signal (its spectral density)", source, SECTION, "psd"))
        return None
    if len(tables) > MAX_INPUTS:
        problems.append(Problem(f"{len(tables)} inputs; at most {MAX_INPUTS}", source, SECTION,
                                "psd"))
        return None
    inputs = [_input(str(name), table, params, signals, coordinates, units, source, problems,
                     files) for name, table in tables.items()]
    entries = data.get("coherence", [])
    if not isinstance(entries, list) or len(entries) > MAX_INPUTS ** 2:
        problems.append(Problem("coherence must be a list of tables [[random.coherence]]",
                                source, SECTION, "coherence"))
        entries = []
    coherences = [_coherence(e, i, params, [str(n) for n in tables], source, problems)
                  for i, e in enumerate(entries)]
    _check_pairs_once(coherences, source, problems)
    count_band = len(problems)
    band_hz = _band_hz(data.get("band"), source, problems, params)
    band = _band(band_hz, [i for i in inputs if i is not None], source, problems) \
        if len(problems) == count_band else None
    count_options = len(problems)
    tolerance = quantity_value(data.get("tolerance", 1e-4), DIMENSIONLESS, source, SECTION,
                               "tolerance", problems, params)
    if len(problems) == count_options and (
            isinstance(tolerance, bool) or not isinstance(tolerance, (int, float))
            or not MIN_TOLERANCE <= tolerance < 1):
        problems.append(Problem(f"tolerance must be a number in [{MIN_TOLERANCE:g}, 1)", source,
                                SECTION, "tolerance"))
    count_options = len(problems)
    lines = quantity_value(data.get("lines", 400), DIMENSIONLESS, source, SECTION, "lines",
                           problems, params)
    if isinstance(lines, float) and lines.is_integer() and isinstance(data.get("lines"), str):
        lines = int(lines)  # a whole number written as arithmetic ("2*500")
    if len(problems) == count_options and (
            isinstance(lines, bool) or not isinstance(lines, int) or not 8 <= lines <= 1_000_000):
        problems.append(Problem("lines must be an integer from 8 to 1000000", source, SECTION,
                                "lines"))
    if len(problems) > count or band is None:
        return None
    assert isinstance(tolerance, (int, float)) and isinstance(lines, int)
    return RandomSpec(tuple(i for i in inputs if i is not None),
                      tuple(c for c in coherences if c is not None), band, float(tolerance),
                      int(lines), source)


def _band_hz(value: object, source: str, problems: list[Problem], params: Sequence[str]
             ) -> object:
    """``band`` with its texts read as frequencies in Hz (``["20 Hz", "2 kHz"]``), their
    problems appended to ``problems``."""
    if not (isinstance(value, list) and any(isinstance(v, str) for v in value)):
        return value
    return [quantity_value(v, FREQUENCY, source, SECTION, "band", problems, params)
            for v in value]


def _band(value: object, inputs: list[RandomInput], source: str, problems: list[Problem]
          ) -> tuple[float, float] | None:
    tables = [i for i in inputs if i.table is not None]
    if value is None:
        if not inputs:
            return None
        if not tables or len(tables) < len(inputs):
            problems.append(Problem("band = [low, high] (Hz) is needed when an input is not "
                                    "a table", source, SECTION, "band"))
            return None
        low = max(float(i.table[0, 0]) for i in tables)  # type: ignore[index]
        high = min(float(i.table[-1, 0]) for i in tables)  # type: ignore[index]
    elif (isinstance(value, list) and len(value) == 2
          and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
        # a TOML whole number may lie beyond the floating-point range: then infinite
        low, high = (float(v) if not isinstance(v, int) or abs(v) < 2**1023 else
                     math.inf if v > 0 else -math.inf for v in value)
    else:
        problems.append(Problem("band must be [low, high] in Hz", source, SECTION, "band"))
        return None
    if not (math.isfinite(high) and 0 <= low < high):
        problems.append(Problem(f"band [{low:g}, {high:g}] Hz must be finite with 0 <= low < high",
                                source, SECTION, "band"))
        return None
    if high > MAX_FREQUENCY_HZ:
        problems.append(Problem(
            f"the band ends at {high:g} Hz, above {MAX_FREQUENCY_HZ:g} Hz: there the "
            "dynamic stiffness (2 pi f)^2 M and the moments of the densities leave the "
            "floating-point range; end the band at the highest frequency that matters"
            + (" (without a band, the band is the tables' span)" if value is None else ""),
            source, SECTION, "band"))
        return None
    for i in tables:
        assert i.table is not None
        if low < i.table[0, 0] * (1 - 1e-12) or high > i.table[-1, 0] * (1 + 1e-12):
            problems.append(Problem(
                f"the band {low:g}-{high:g} Hz goes beyond the table of {i.name} "
                f"({i.table[0, 0]:g}-{i.table[-1, 0]:g} Hz); narrow the band or extend the "
                "table", source, SECTION, "band"))
            return None
    return low, high


__all__ = ["RandomInput", "Coherence", "RandomSpec", "parse_random", "STANDARD_GRAVITY"]
