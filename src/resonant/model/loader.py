"""Read, parse and validate a model file (the model layer's entry point).

A model file (TOML) is untrusted input: its expressions are parsed by
:mod:`resonant.expressions`, never evaluated as code.  Every problem found is
collected into one :class:`~resonant.errors.ModelError`.

Examples
--------
>>> model = loads('''
... [parameters]
... m = 2
... k = 800
... [coordinates]
... x = "displacement"
... [energy]
... T = "m*x'^2/2"
... U = "k*x^2/2"
... ''')
>>> model.coordinates
('x',)
>>> model.parameter_values["k"]
800.0
"""

from __future__ import annotations

import difflib
import os
import tomllib
from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import replace
from fractions import Fraction
from pathlib import Path
from types import MappingProxyType
from typing import Any

import sympy

import resonant.model.limits as limits

from ..arrays import Matrix
from ..errors import ModelError, Problem
from ..expressions import (
    BinOp,
    Expression,
    ExpressionError,
    Name,
    Neg,
    Num,
    parse,
    primed_names,
    validate_name,
)
from ..expressions.parser import Node
from .campbell_spec import CampbellSpec, Unbalance, parse_campbell, parse_unbalances
from .dimensions import check_units
from .exercise import Exercise, parse_exercise
from .explore import parse_explore
from .files import FileRefused, open_regular_file, read_bounded
from .gravity_display import given_in_g, gravity_default
from .inline_matrices import extract_numeric_matrices
from .limits import (
    ENERGY_KEYS,
    MAX_COORDINATES,
    MAX_FILE_BYTES,
    MAX_INLINED_DEGREE,
    MAX_INLINED_NODES,
    TOP_LEVEL,
)
from .load_spec import (
    FatigueSpec,
    PeriodicSpec,
    ShockSpec,
    parse_fatigue,
    parse_periodic,
    parse_shock,
)
from .matrix_files import read_matrix_spec
from .measurement_spec import MeasurementSpec, parse_measurement
from .nonlinear_elements import read_nonlinear_elements
from .part_energies import Mechanism, derive_energies, point_expressions
from .parts import DerivedEnergies, Parts, read_parts
from .random_spec import Files, RandomSpec, parse_random
from .rotor import read_rotor
from .study import StudySpec, parse_study, rotor_problems
from .types import (
    Force,
    MatrixSpec,
    Model,
    constant_prime_message,
    evaluate_parameters,
    unknown_parameter,
)
from .units import (
    DISPLAY_QUANTITIES,
    ModelUnits,
    Unit,
    UnitError,
    display_units,
    parse_unit,
    parse_with_unit,
    split_value,
)

# -- loading -------------------------------------------------------------------------------

def load(path: str | Path, overrides: Mapping[str, float | str] | None = None,
         allow_paths: Sequence[str | os.PathLike[str]] = ()) -> Model:
    """Read and validate a model file.

    Parameters
    ----------
    path : str or Path
        The TOML model file (a regular file; symbolic links are followed).
    overrides : mapping, optional
        Parameter values that replace those of the file (``--set``); strings
        are parsed as expressions.
    allow_paths : sequence of paths, optional
        Directories, besides the model file's folder, that ``[matrices]`` files
        may be read from (``--allow-path DIR``).  See docs/security.md.

    Returns
    -------
    Model
        The validated model.

    Raises
    ------
    ModelError
        With every problem found: file, section, key and what is wrong.

    Examples
    --------
    >>> load("examples/two_dof_free.toml", {"k": "3000 N/m"}).parameter_values["k3"]
    3000.0
    """
    path = Path(path)
    name = str(path)
    try:
        with open_regular_file(path, follow_symlinks=True, max_bytes=MAX_FILE_BYTES) as handle:
            data = read_bounded(handle, MAX_FILE_BYTES)
    except FileRefused as exc:
        raise ModelError(Problem(f"cannot read the model file: {exc}", name)) from None
    except OSError as exc:
        raise ModelError(Problem(f"cannot read the model file: {exc.strerror or 'I/O error'}",
                                 name)) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelError(Problem(f"the file is not UTF-8 text (byte {exc.start})", name)
                         ) from None
    return loads(text, source=name, base_dir=path.parent, overrides=overrides,
                 allow_paths=allow_paths)


def loads(text: str, source: str = "<string>", base_dir: str | Path | None = None,
          overrides: Mapping[str, float | str] | None = None,
          allow_paths: Sequence[str | os.PathLike[str]] = ()) -> Model:
    """Parse and validate a model given as TOML text. See :func:`load`.

    Parameters
    ----------
    text : str
        The TOML model.
    source : str
        The name used in messages (a file name).
    base_dir : str or Path, optional
        The folder ``[matrices]`` file paths are relative to; without it a model
        that names a matrix file is refused (there is no folder to confine it to).
    overrides : mapping, optional
        Parameter values that replace those of the text.
    allow_paths : sequence of paths, optional
        Further folders from which matrix files may be read.

    Returns
    -------
    Model
        The validated model.

    Raises
    ------
    ModelError
        With every problem found: source, section, key and what is wrong.

    Examples
    --------
    >>> from resonant.model import loads
    >>> model = loads('[parameters]\\nm = 1\\nk = 400\\nc = 4\\n[coordinates]\\nx = ""\\n'
    ...               '[energy]\\nT = "m*x\\'^2/2"\\nU = "k*x^2/2"\\nD = "c*x\\'^2/2"')
    >>> model.coordinates, model.parameter_values["k"]
    (('x',), 400.0)
    """
    if not isinstance(text, str):
        raise ModelError(Problem(f"the model text must be a str, not {type(text).__name__}",
                                 source))
    text, inline_arrays = extract_numeric_matrices(text)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(Problem(f"invalid TOML: {exc}", source)) from None
    except RecursionError:
        raise ModelError(Problem("invalid TOML: nested too deeply", source)) from None
    builder = _Builder(data, source, Path(base_dir) if base_dir is not None else None,
                       overrides or {}, tuple(allow_paths))
    builder.inline_arrays = inline_arrays
    return builder.build()


class _Builder:
    """Validates the TOML data section by section, collecting problems."""

    def __init__(self, data: dict, source: str, base_dir: Path | None,
                 overrides: Mapping[str, float | str],
                 allow_paths: Sequence[str | os.PathLike[str]] = ()) -> None:
        self.data = data
        self.source = source
        self.base_dir = base_dir
        self.allow_paths = allow_paths
        self.overrides = overrides
        self.problems: list[Problem] = []
        self.inline_arrays: dict[str, Any] = {}  # placeholder -> large number-only matrix
        self.declared: dict[str, str] = {}  # name -> section
        self.force_points: dict[str, str] = {}  # [[force]] name -> the named point (parts)
        # physical units (resonant.model.units): what the file gives, checked in build()
        self.unit_given: dict[str, tuple[Expression, Unit]] = {}
        self.coordinate_units: dict[str, Unit] = {}
        self.output_units: dict[str, Unit] = {}

    # helpers
    def problem(self, message: str, section: str = "", key: str = "") -> None:
        self.problems.append(Problem(message, self.source, section, key))

    def table(self, key: str, required: bool = False) -> dict:
        value = self.data.get(key, {})
        if key not in self.data and required:
            self.problem(f"the section [{key}] is missing", key)
        if not isinstance(value, dict):
            self.problem(f"[{key}] must be a table (name = value lines), "
                         f"not {type(value).__name__}", key)
            return {}
        return value

    def declare(self, name: str, section: str) -> bool:
        reason = validate_name(name)
        if reason:
            self.problem(f"'{name}' cannot be used as a name: {reason}", section, name)
            return False
        if name in self.declared:
            self.problem(f"'{name}' is already declared in [{self.declared[name]}]; "
                         "every name must be unique", section, name)
            return False
        self.declared[name] = section
        return True

    def expression(self, value: object, section: str, key: str,
                   allowed: Collection[str]) -> Expression | None:
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            self.problem(f"expected a number or an expression string, got "
                         f"{type(value).__name__}", section, key)
            return None
        try:
            return parse(value, allowed=allowed, file=self.source, section=section, key=key)
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            return None

    def valued(self, value: object, section: str, key: str, allowed: Collection[str],
               file: str | None = None, name: str | None = None) -> Expression | None:
        """A parameter value, with an optional unit after it (converted to SI)."""
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            self.problems.append(Problem(f"expected a number or an expression string, got "
                                         f"{type(value).__name__}", file or self.source,
                                         section, key))
            return None
        try:
            expression, given = parse_with_unit(value, allowed, file or self.source,
                                                section, key)
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            return None
        if given is not None:
            self.unit_given[name or key] = given
        else:
            self.unit_given.pop(name or key, None)
        return expression

    # sections
    def counts(self) -> None:
        """Refuse tables with more entries than the limits, before any expression is parsed."""
        for section, limit in (("parameters", limits.MAX_PARAMETERS),
                               ("signals", limits.MAX_SIGNALS),
                               ("definitions", limits.MAX_DEFINITIONS),
                               ("outputs", limits.MAX_OUTPUTS),
                               ("force", limits.MAX_FORCES),
                               ("harmonic", limits.MAX_HARMONICS),
                               *((kind, limits.MAX_PARTS) for kind in limits.PART_SECTIONS)):
            value = self.data.get(section)
            if isinstance(value, (dict, list)) and len(value) > limit:
                kind = f"[{section}] entries" if isinstance(value, dict) else \
                    f"[[{section}]] entries"
                self.problem(f"{len(value)} {kind}; a model is limited to {limit} (see "
                             "docs/security.md; large systems belong in [matrices] files)",
                             section)
        if self.problems:
            raise ModelError(self.problems)

    def build(self) -> Model:
        self.counts()
        misplaced = self.unknown_sections()
        title = self.title()
        parameters = self.parameters()
        # every declared parameter, also those whose value is invalid, so that one bad
        # value is reported once and not again as an unknown name wherever it is used
        param_names = [n for n, sec in self.declared.items() if sec == "parameters"]
        matrices = self.data.get("matrices") is not None or "rotor" in self.data
        coordinates, descriptions = self.coordinates(required=not matrices)
        equilibrium = self.equilibrium(param_names, coordinates)
        signals = self.named_table("signals", [*param_names, "t"])
        state_names = [*param_names, *coordinates, *signals]
        definitions = self.definitions(state_names)
        # every declared definition, also those that failed: a failed one is reported
        # once, not again as an unknown name wherever it is used
        allowed = [*state_names, *(n for n, sec in self.declared.items()
                                   if sec == "definitions")]
        has_parts = any(section in self.data for section in limits.PART_SECTIONS)
        parts = read_parts(self.data, param_names, allowed, self.source, self.problems) \
            if has_parts else None
        mechanism = self.mechanism(parts, param_names, coordinates, signals, definitions,
                                   equilibrium)
        # a model with parts needs no [energy], also when its parts are invalid
        energy = self.energy(allowed, required=not matrices and not has_parts)
        forces = self.forces(allowed, coordinates, mechanism)
        display = self.display()
        matrix_spec, coordinates = self.matrices(param_names, coordinates) if matrices \
            else (None, coordinates)
        self.check_one_kind(matrices, bool(energy or forces), parts is not None)
        names = coordinates or (_matrix_names(matrix_spec) if matrix_spec is not None else [])
        # a matrix model's outputs are functions of its coordinates (also the default
        # names q1 ... qn) and parameters
        outputs = self.outputs([*param_names, *names] if matrices else allowed)
        exercise = self.exercise(param_names, names, list(outputs))
        exact, floats = self.values(parameters)
        derived: DerivedEnergies | None = None
        if mechanism is not None and not self.problems:
            derived, energy, forces = self.derived(mechanism, energy, forces, exact, allowed)
        units = None
        if self.unit_given or self.coordinate_units or self.output_units:
            units, unit_problems = check_units(
                self.source, parameters, self.unit_given, self.coordinate_units,
                self.output_units, display, equilibrium, signals, definitions, energy,
                forces, outputs, matrix_spec, coordinates)
            self.problems.extend(unit_problems)
        elif display:  # no units in the model: [display] still chooses phases and frequencies
            units = ModelUnits(display=MappingProxyType(display))
        study = parse_study(self.data["study"], param_names, names, list(outputs), units,
                            self.source, self.problems) if "study" in self.data else None
        explore = parse_explore(self.data["explore"], param_names, names, list(outputs),
                                self.source, self.problems, units) \
            if "explore" in self.data else None
        random, shock, periodic = self.loads(param_names, list(signals), names, units)
        units = gravity_default(units, given_in_g(random, self.data))  # input in g: output too
        fatigue, campbell = self.fatigue(param_names), self.campbell(param_names, names, study,
                                                          matrix_spec)
        measurement = self.measurement(list(signals), names, list(outputs))
        self.raise_problems(misplaced)
        if matrix_spec is not None and not coordinates:
            coordinates = _matrix_names(matrix_spec)
        return Model(
            title=title, source=self.source,
            parameters=MappingProxyType(parameters),
            parameter_values=MappingProxyType(floats), exact_values=MappingProxyType(exact),
            coordinates=tuple(coordinates), descriptions=MappingProxyType(descriptions),
            equilibrium=MappingProxyType(equilibrium), signals=MappingProxyType(signals),
            definitions=MappingProxyType(definitions), energy=MappingProxyType(energy),
            forces=tuple(forces), outputs=MappingProxyType(outputs), matrices=matrix_spec,
            exercise=exercise, parts=derived, units=units, study_section=study,
            explore_section=explore, random_section=random,
            shock_section=shock, fatigue_section=fatigue,
            periodic_section=periodic, measurement_section=measurement,
            campbell_section=campbell[0], unbalances=campbell[1])

    def loads(self, param_names: list[str], signals: list[str], names: list[str],
              units: ModelUnits | None
              ) -> tuple[RandomSpec | None, ShockSpec | None, PeriodicSpec | None]:
        """The ``[random]``, ``[shock]`` and ``[periodic]`` sections (None where absent)."""
        random = parse_random(self.data["random"], param_names, signals, names,
                              self.source, self.problems, units,
                              Files(self.base_dir, tuple(self.allow_paths))) \
            if "random" in self.data else None
        shock = parse_shock(self.data["shock"], signals, names, self.source,
                            self.problems, units, param_names) if "shock" in self.data else None
        periodic = parse_periodic(self.data["periodic"], param_names, signals, names,
                                  self.source, self.problems, units) \
            if "periodic" in self.data else None
        return random, shock, periodic

    def measurement(self, signals: list[str], names: list[str], outputs: list[str]
                    ) -> MeasurementSpec | None:
        if "measurement" not in self.data:
            return None
        return parse_measurement(self.data["measurement"], signals, names, outputs,
                                 self.source, self.problems)

    def fatigue(self, param_names: list[str]) -> FatigueSpec | None:
        if "fatigue" not in self.data:
            return None
        return parse_fatigue(self.data["fatigue"], self.source, self.problems, param_names)

    def campbell(self, param_names: list[str], coordinates: list[str],
                 study: StudySpec | None = None, matrices: MatrixSpec | None = None
                 ) -> tuple[CampbellSpec | None, tuple[Unbalance, ...]]:
        """[campbell] and [[unbalance]]: a rotor's speed range and unbalances (and what
        the study's rotor quantities need of them)."""
        spec = parse_campbell(self.data["campbell"], param_names, self.source,
                              self.problems) if "campbell" in self.data else None
        if study is not None:
            self.problems.extend(rotor_problems(study, spec is not None,
                                                _speed_named(matrices, spec), self.source))
        unbalances = parse_unbalances(self.data["unbalance"], coordinates, self.source,
                                      self.problems) if "unbalance" in self.data else ()
        return spec, unbalances

    def exercise(self, param_names: list[str], names: list[str], outputs: list[str]
                 ) -> Exercise | None:
        if "exercise" not in self.data and "variants" not in self.data:
            return None
        return parse_exercise(self.data.get("exercise"), self.data.get("variants"),
                              param_names, names, outputs, self.source, self.problems)

    def unknown_sections(self) -> set[str]:
        """A problem for each unknown top-level key; the names a misspelled section declares
        (their "unknown name" problems are then left out)."""
        misplaced: set[str] = set()
        for key in self.data:
            if key not in TOP_LEVEL:
                close = difflib.get_close_matches(key, TOP_LEVEL, n=1)
                hint = f"did you mean '{close[0]}'?" if close else \
                    f"known sections: {', '.join(TOP_LEVEL)}"
                self.problem(f"unknown section or key '{key}'; {hint}", key)
                if isinstance(self.data[key], dict):
                    misplaced |= {str(name) for name in self.data[key]}
        return misplaced

    def title(self) -> str:
        title = self.data.get("title", "")
        if not isinstance(title, str):
            self.problem("title must be a string", "title")
            return ""
        return title

    def equilibrium(self, param_names: list[str], coordinates: list[str]
                    ) -> dict[str, Expression]:
        equilibrium = self.simple_table("equilibrium", param_names, keys=coordinates)
        for name, expression in equilibrium.items():
            if primed_names(expression):
                self.problem(constant_prime_message(primed_names(expression)), "equilibrium",
                             name)
        return equilibrium

    def check_one_kind(self, matrices: bool, energies: bool, parts: bool) -> None:
        """A model is given by its energies (and parts) or by matrices, not both; only a
        matrix model has ``[[nonlinear]]`` elements."""
        if "nonlinear" in self.data and not matrices:
            self.problem("[[nonlinear]] elements belong to a [matrices] model; a model given "
                         "by its energies writes its nonlinear terms into [energy]", "nonlinear")
        if matrices and energies:
            self.problem("a model gives either [energy] (and [[force]]) or [matrices], not both",
                         "matrices")
        elif matrices and parts:
            self.problem("a model gives either parts ([[body]], [[spring]], ...) or [matrices], "
                         "not both", "matrices")

    def values(self, parameters: dict[str, Expression]
               ) -> tuple[dict[str, sympy.Expr], dict[str, float]]:
        """The parameters' exact and float values, once the file has no other problem."""
        if not self.problems:
            try:
                return evaluate_parameters(parameters, self.source)
            except ModelError as exc:
                self.problems.extend(exc.problems)
        return {}, {}

    def derived(self, mechanism: Mechanism, energy: dict[str, Expression],
                forces: list[Force], exact: Mapping[str, sympy.Expr], allowed: list[str]
                ) -> tuple[DerivedEnergies | None, dict[str, Expression], list[Force]]:
        """The energies (and the torques' forces) of the parts."""
        try:
            derived, energy, torques = derive_energies(mechanism, energy, exact, allowed,
                                                       self.force_points)
        except ModelError as exc:
            self.problems.extend(exc.problems)
            return None, energy, forces
        if "T" not in energy:
            self.problem("there is no kinetic energy: no body has a mass and [energy] "
                         "gives no T", "body")
        return derived, energy, [*forces, *torques]

    def raise_problems(self, misplaced: set[str]) -> None:
        if self.problems:
            # a misspelled section explains the unknown names it declares: say it once
            cascade = {f"unknown name '{name}'" for name in misplaced}
            raise ModelError([p for p in self.problems
                              if not any(p.message.startswith(c) for c in cascade)])

    def parameters(self) -> dict[str, Expression]:
        table = self.table("parameters")
        params: dict[str, Expression] = {}
        # the names before this one, also those whose value is invalid: one bad value is
        # reported once, not again as an unknown name in every parameter that uses it
        earlier: list[str] = []
        for name, value in table.items():
            if not self.declare(name, "parameters"):
                continue
            expression = self.valued(value, "parameters", name, list(earlier))
            earlier.append(name)
            if expression is not None:
                params[name] = expression
        for name, value in self.overrides.items():
            if name not in params:
                if name not in table:
                    self.problems.append(unknown_parameter(name, self.source, params))
                continue
            earlier = list(params)[: list(params).index(name)]
            had = self.unit_given.get(name)
            override = self.valued(value, "", "", earlier, file=f"--set {name}", name=name)
            if override is not None:
                params[name] = override
                if had is not None and name not in self.unit_given and \
                        not override.names() and not had[0].names():
                    # a bare number replacing a value with a unit: SI, of the same dimension
                    dim = had[1].dimension
                    self.unit_given[name] = (override, Unit(dim.text(), Fraction(1), 0, dim))
        return params

    def coordinates(self, required: bool) -> tuple[list[str], dict[str, str]]:
        raw = self.data.get("coordinates", {} if not required else None)
        if raw is None:
            self.problem("the section [coordinates] is missing: list the generalized "
                         "coordinates, e.g. x1 = \"displacement of the cart\"", "coordinates")
            return [], {}
        if isinstance(raw, list):
            wrong = [item for item in raw if not isinstance(item, str)]
            if wrong:
                self.problem("coordinates = [...] must list names as strings (coordinates = "
                             f"[\"x1\", \"x2\"]), got {type(wrong[0]).__name__}", "coordinates")
                return [], {}
            repeated = sorted({name for name in raw if raw.count(name) > 1})
            if repeated:
                self.problem(f"'{repeated[0]}' is listed twice in coordinates = [...]",
                             "coordinates", repeated[0])
            raw = {name: "" for name in raw}
        if not isinstance(raw, dict):
            self.problem("[coordinates] must be a table: name = \"description\"", "coordinates")
            return [], {}
        if required and not raw:
            self.problem("[coordinates] is empty: a model needs at least one coordinate",
                         "coordinates")
        if len(raw) > MAX_COORDINATES:
            self.problem(f"{len(raw)} coordinates; energy models are limited to "
                         f"{MAX_COORDINATES} (use [matrices] for larger systems)", "coordinates")
            return [], {}
        names, descriptions = [], {}
        for name, text in raw.items():
            if self.declare(name, "coordinates"):
                names.append(name)
                if isinstance(text, dict):  # { description = "...", unit = "m" }
                    text = self.coordinate_entry(name, text)
                descriptions[name] = text if isinstance(text, str) else str(text)
        return names, descriptions

    def coordinate_entry(self, name: str, entry: dict) -> str:
        """The description of ``name = { description = ..., unit = ... }``; its unit noted."""
        for key in sorted(set(entry) - {"description", "unit"}):
            self.problem(f"unknown key '{key}'; a coordinate takes description and unit",
                         "coordinates", f"{name}.{key}")
        description = entry.get("description", "")
        if not isinstance(description, str):
            self.problem("description must be a string", "coordinates", f"{name}.description")
            description = ""
        unit = entry.get("unit")
        if unit is not None:
            try:
                if not isinstance(unit, str):
                    raise UnitError(f"the unit must be a string like \"m\" or \"rad\", "
                                    f"not {type(unit).__name__}")
                self.coordinate_units[name] = parse_unit(unit.strip())
            except UnitError as exc:
                self.problem(str(exc), "coordinates", f"{name}.unit")
        return description

    def simple_table(self, section: str, allowed: list[str], keys: Iterable[str] | None = None,
                     declare: bool = False) -> dict[str, Expression]:
        out: dict[str, Expression] = {}
        keys = list(keys) if keys is not None else None
        for name, value in self.table(section).items():
            if keys is not None and name not in keys:
                self.problem(f"'{name}' is not a coordinate; [{section}] takes coordinates "
                             f"({', '.join(keys) or 'none declared'})", section, name)
                continue
            if declare and not self.declare(name, section):
                continue
            expression = self.expression(value, section, name, allowed)
            if expression is not None:
                out[name] = expression
        return out

    def outputs(self, allowed: Collection[str]) -> dict[str, Expression]:
        """``[outputs]``: name = "expression", optionally with the unit to show it in."""
        out: dict[str, Expression] = {}
        for name, value in self.table("outputs").items():
            text, unit = split_value(value) if isinstance(value, str) else (value, None)
            expression = self.expression(text, "outputs", name, allowed)
            if expression is None:
                continue
            out[name] = expression
            if validate_name(name):
                self.problem(f"'{name}' cannot be used as a name: {validate_name(name)}",
                             "outputs", name)
            if unit is not None:
                try:
                    self.output_units[name] = parse_unit(unit)
                except UnitError as exc:
                    self.problem(str(exc), "outputs", name)
        return out

    def display(self) -> dict[str, Unit]:
        """``[display]``: quantity = "unit" (length = "mm", angle = "deg", frequency = "Hz")."""
        out: dict[str, Unit] = {}
        for key, value in self.table("display").items():
            if key not in DISPLAY_QUANTITIES:
                self.problem(f"unknown quantity '{key}'; [display] takes "
                             f"{', '.join(DISPLAY_QUANTITIES)}", "display", key)
                continue
            try:
                if not isinstance(value, str):
                    raise UnitError(f"expected a unit string, got {type(value).__name__}")
                chosen = display_units([value])
                if key not in chosen and not (key == "moment" and "energy" in chosen):
                    raise UnitError(f"'{value.strip()}' is not a unit of {key}")
                out[key] = next(iter(chosen.values()))
            except UnitError as exc:
                self.problem(str(exc), "display", key)
        return out

    def named_table(self, section: str, allowed: list[str]) -> dict[str, Expression]:
        out: dict[str, Expression] = {}
        table = self.table(section)
        for name in table:
            self.declare(name, section)
        for name, value in table.items():
            if self.declared.get(name) != section:
                continue
            expression = self.expression(value, section, name, allowed)
            if expression is not None:
                out[name] = expression
                if section == "signals" and any(p for n, p in expression.names() if n != "t"):
                    self.problem("a signal may not contain primes; write its derivative "
                                 "out or use a definition", section, name)
        return out

    def definitions(self, allowed: list[str]) -> dict[str, Expression]:
        table = self.table("definitions")
        names = [n for n in table if self.declare(n, "definitions")]
        parsed: dict[str, Expression] = {}
        for name in names:
            expression = self.expression(table[name], "definitions", name, [*allowed, *names])
            if expression is not None:
                parsed[name] = expression
        # topological order, rejecting cycles
        order: list[str] = []
        state: dict[str, int] = {}

        def visit(name: str, path: list[str]) -> None:
            if state.get(name) == 2:
                return
            if state.get(name) == 1:
                cycle = path[path.index(name):] + [name]
                self.problem("definitions refer to each other in a cycle: "
                             + " -> ".join(cycle) + "; break the cycle", "definitions", name)
                raise _Cycle
            state[name] = 1
            for dep, _ in sorted(parsed[name].names()):
                if dep in parsed:
                    visit(dep, path + [name])
            state[name] = 2
            order.append(name)

        for name in parsed:
            try:
                visit(name, [])
            except _Cycle:
                return {}
        ordered = {name: parsed[name] for name in order}
        for name, message in _inlined_size_problems(ordered):
            self.problem(message, "definitions", name)
        return ordered

    def energy(self, allowed: list[str], required: bool) -> dict[str, Expression]:
        table = self.table("energy", required=required)
        out: dict[str, Expression] = {}
        for key, value in table.items():
            if key not in ENERGY_KEYS:
                self.problem(f"unknown energy '{key}'; [energy] takes T (kinetic), "
                             "U (potential) and D (Rayleigh dissipation)", "energy", key)
                continue
            expression = self.expression(value, "energy", key, allowed)
            if expression is not None:
                out[key] = expression
        if required and table and "T" not in table:
            self.problem("the kinetic energy T is missing; without it there is no mass "
                         "matrix", "energy", "T")
        return out

    def mechanism(self, parts: Parts | None, params: list[str], coordinates: list[str],
                  signals: Mapping[str, Expression], definitions: Mapping[str, Expression],
                  equilibrium: Mapping[str, Expression]) -> Mechanism | None:
        """The geometry of the parts (resonant.model.part_energies), None without parts."""
        if not parts:
            return None
        try:
            return Mechanism(parts, params, coordinates, signals, definitions, equilibrium,
                             self.source)
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            return None

    def forces(self, allowed: list[str], coordinates: list[str],
               mechanism: Mechanism | None = None) -> list[Force]:
        raw = self.data.get("force", [])
        if isinstance(raw, dict):
            raw = [raw]
        if not isinstance(raw, list):
            self.problem("[[force]] entries must be tables", "force")
            return []
        forces = []
        for i, entry in enumerate(raw, start=1):
            section = f"force {i}"
            if not isinstance(entry, dict):
                self.problem("each [[force]] must be a table", section)
                continue
            name = entry.get("name", f"force {i}")
            if not isinstance(name, str):
                self.problem("name must be a string", section, "name")
                name = f"force {i}"
            section = f"force '{name}'"
            unknown = set(entry) - {"name", "vector", "point", "generalized"}
            for key in sorted(unknown):
                self.problem(f"unknown key '{key}'; a force has name, vector + point, "
                             "or generalized", section, key)
            if "generalized" in entry:
                if "vector" in entry or "point" in entry:
                    self.problem("give either vector + point or generalized, not both", section)
                gen = entry["generalized"]
                if not isinstance(gen, dict) or not gen:
                    self.problem("generalized must be a table { coordinate = \"force\" }",
                                 section, "generalized")
                    continue
                parsed = {}
                for coord, value in gen.items():
                    if coord not in coordinates:
                        self.problem(f"'{coord}' is not a coordinate", section,
                                     f"generalized.{coord}")
                        continue
                    expression = self.expression(value, section, f"generalized.{coord}", allowed)
                    if expression is not None:
                        parsed[coord] = expression
                forces.append(Force(name, generalized=MappingProxyType(parsed)))
                continue
            vector, point = entry.get("vector"), entry.get("point")
            if isinstance(point, str) and mechanism is not None and \
                    point in mechanism.parts.point_names():
                resolved = point_expressions(mechanism, point, allowed, self.source,
                                             section, self.problems)
                if resolved is None:
                    continue
                self.force_points[name] = point
                point = [e.text for e in resolved]
            elif isinstance(point, str) and "." in point:
                known = mechanism.parts.point_names() if mechanism is not None else []
                self.problem(f"unknown point '{point}'; known points: "
                             f"{', '.join(known) or 'none (no [[body]] or [[point]])'}",
                             section, "point")
                continue
            if vector is None or point is None:
                self.problem("a force needs both vector and point (or generalized)", section)
                continue
            if isinstance(vector, (str, int, float)) and not isinstance(vector, bool):
                vector = [vector]
            if isinstance(point, (str, int, float)) and not isinstance(point, bool):
                point = [point]
            if not isinstance(vector, list) or not isinstance(point, list) \
                    or not 1 <= len(vector) <= 3 or len(vector) != len(point):
                self.problem("vector and point must be lists of the same length (1 to 3 "
                             "components)", section)
                continue
            vec = [self.expression(v, section, f"vector[{j}]", allowed)
                   for j, v in enumerate(vector)]
            pnt = [self.expression(v, section, f"point[{j}]", allowed)
                   for j, v in enumerate(point)]
            if all(e is not None for e in vec + pnt):
                forces.append(Force(name, vector=tuple(vec), point=tuple(pnt)))  # type: ignore
        return forces

    def matrices(self, params: list[str], coordinates: list[str]
                 ) -> tuple[MatrixSpec | None, list[str]]:
        """The [matrices] (or the assembled [rotor]) and the coordinates."""
        if "rotor" not in self.data:
            return self.matrix_section(params, coordinates), coordinates
        if "matrices" in self.data or coordinates:
            self.problems.append(Problem("a [rotor] makes its own matrices and coordinates: "
                                         "give no [matrices] or [coordinates] with it",
                                         self.source, "rotor"))
            return None, coordinates
        try:
            spec, names = read_rotor(self.data["rotor"], params, self.source)
        except ModelError as exc:
            self.problems.extend(exc.problems)
            return None, coordinates
        for name in names:   # the stations' displacements (m) and tilts (rad)
            self.coordinate_units[name] = parse_unit("rad" if name.endswith(("_ax", "_ay", "_az"))
                                                     else "m")
        return spec, list(names)

    def matrix_section(self, params: list[str], coordinates: list[str]) -> MatrixSpec | None:
        section = self.data.get("matrices")
        harmonics = self.data.get("harmonic", [])
        try:
            spec: MatrixSpec = read_matrix_spec(section, harmonics, params, coordinates,
                                                self.source, self.base_dir, self.allow_paths,
                                                self.inline_arrays)
            if "nonlinear" in self.data:
                names = coordinates or _matrix_names(spec)
                spec = replace(spec, nonlinear=read_nonlinear_elements(
                    self.data["nonlinear"], params, names, self.source))
            return spec
        except ModelError as exc:
            self.problems.extend(exc.problems)
            return None


def _speed_named(matrices: MatrixSpec | None, campbell: CampbellSpec | None) -> bool:
    """Whether the model names its rotor's speed parameter (``[matrices]``/``[rotor]`` or
    ``[campbell]`` ``speed``)."""
    return (matrices is not None and matrices.speed is not None) or \
        (campbell is not None and campbell.speed is not None)


def _matrix_names(spec: MatrixSpec) -> list[str]:
    """The coordinates of a matrix model without [coordinates]: its DOF map's names
    (``n1042_uz``) or q1 ... qn."""
    return list(spec.coordinates) or [f"q{i + 1}" for i in range(_matrix_size(spec.M))]


class _Cycle(Exception):
    pass


# -- resource limits ---------------------------------------------------------------------------

def _exponent_value(node: Node) -> float | None:
    """The value of a literal exponent (``2``, ``-1``, ``(3)``), else None."""
    if isinstance(node, Num):
        return float(node.value)
    if isinstance(node, Neg):
        inner = _exponent_value(node.operand)
        return None if inner is None else -inner
    return None


def _inlined_cost(expression: Expression, costs: Mapping[str, tuple[float, float]]
                  ) -> tuple[float, float]:
    """(size, degree) of an expression with the definitions in ``costs`` substituted.

    ``size`` counts tree nodes with multiplicity (what repeated substitution builds);
    ``degree`` is the polynomial degree, a function of a variable counting as 1.
    """
    stack: list[tuple[Node, bool]] = [(expression.root, False)]
    out: list[tuple[float, float]] = []
    while stack:
        node, expanded = stack.pop()
        if isinstance(node, Num):
            out.append((1.0, 0.0))
        elif isinstance(node, Name):
            size, degree = costs.get(node.name, (1.0, 0.0 if node.name == "pi" else 1.0))
            out.append((size, degree))
        elif not expanded:
            stack.append((node, True))
            children = (node.left, node.right) if isinstance(node, BinOp) else \
                (node.operand,) if isinstance(node, Neg) else node.args
            stack.extend((child, False) for child in reversed(children))
        else:
            count = 2 if isinstance(node, BinOp) else 1 if isinstance(node, Neg) \
                else len(node.args)
            args = out[len(out) - count:]
            del out[len(out) - count:]
            size = 1.0 + sum(a[0] for a in args)
            if isinstance(node, BinOp) and node.op in "+-":
                degree = max(args[0][1], args[1][1])
            elif isinstance(node, BinOp) and node.op == "^":
                power = _exponent_value(node.right)
                degree = args[0][1] * abs(power) if power is not None \
                    else args[0][1] + args[1][1]
            elif isinstance(node, BinOp):
                degree = args[0][1] + args[1][1]
            elif isinstance(node, Neg):
                degree = args[0][1]
            else:  # sin(u), exp(u)...: coefficients are values of the function, not powers
                degree = min(1.0, max(a[1] for a in args))
            out.append((size, degree))
    return out[0]


def _inlined_size_problems(definitions: Mapping[str, Expression]) -> list[tuple[str, str]]:
    """Definitions that explode when the definitions they use are substituted.

    ``definitions`` must be in dependency order.  Checked before any symbolic
    work, so ``d2 = d1*d1``, ``d3 = d2*d2``, ... fails at once instead of hanging.
    """
    costs: dict[str, tuple[float, float]] = {}
    problems = []
    exploded: set[str] = set()  # reported once, not again for every definition using it
    for name, expression in definitions.items():
        uses = sorted({n for n, _ in expression.names() if n in definitions})
        if exploded.intersection(uses):
            exploded.add(name)
            costs[name] = (1.0, 1.0)
            continue
        size, degree = _inlined_cost(expression, costs)
        costs[name] = (size, degree)
        via = f" (it uses {', '.join(uses)})" if uses else ""
        if size > MAX_INLINED_NODES:
            problems.append((name, (
                f"'{name}' grows to about {size:.2g} terms when the definitions it uses are "
                f"substituted{via}; at most {MAX_INLINED_NODES:.0e} are derived in reasonable "
                "time -- a definition that uses another several times repeats it, so "
                "such chains grow exponentially; simplify them")))
        elif degree > MAX_INLINED_DEGREE:
            problems.append((name, (
                f"'{name}' has polynomial degree about {degree:.3g} once the definitions "
                f"it uses are substituted{via}; at most {MAX_INLINED_DEGREE} -- products "
                "and powers of definitions multiply their degrees; simplify them")))
        else:
            continue
        exploded.add(name)
    return problems


def definition_chain(definitions: Mapping[str, Expression]) -> str:
    """`` (definition chain d3 -> d2 -> d1, 3 levels)`` for the longest chain, or ''."""
    depth: dict[str, tuple[int, str | None]] = {}
    for name, expression in definitions.items():  # dependency order
        uses = [n for n, _ in expression.names() if n in depth]
        best = max(uses, key=lambda n: depth[n][0], default=None)
        depth[name] = (1 + (depth[best][0] if best else 0), best)
    if not depth:
        return ""
    deepest = max(depth, key=lambda n: depth[n][0])
    levels, chain = depth[deepest][0], list[str]()
    link: str | None = deepest
    while link is not None and len(chain) < 6:
        chain.append(link)
        link = depth[link][1]
    more = " -> ..." if levels > len(chain) else ""
    return f" (definition chain {' -> '.join(chain)}{more}, {levels} levels)"


def _matrix_size(matrix: Matrix | list[Any]) -> int:
    return int(matrix.shape[0]) if hasattr(matrix, "shape") else len(matrix)



__all__ = ["load", "loads", "definition_chain"]
