"""Drawing and checking exercise variants: N distinct value sets of one model, each an
equilibrium, stable and away from resonance, solved on the shared symbolic system.

Examples
--------
>>> import pathlib, resonant
>>> from resonant.exercises import generate
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples/teaching/cart_pendulum.toml"
>>> batch = generate(resonant.load(path), 3, seed=1)
>>> len(batch.variants), sorted(batch.variants[0].answers)[:2]
(3, ['C', 'K'])
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analyses.periodic_load import periodic_load_response
from ..analyses.random_response import random_response
from ..analyses.stationary import StationarySolution, stationary
from ..deadline import NO_DEADLINE, Deadline, DeadlineExceeded
from ..derivation.residual import is_zero
from ..errors import AnalysisError, ModelError, Problem, printable
from ..model import Model, symbol
from ..model.exercise import Exercise
from ..model.units_display import ResultUnits, result_units
from ..system import LinearSystem, linear_system
from ..system.stability import UNSTABLE

#: an excitation frequency within this relative distance of a natural one is refused
RESONANCE_MARGIN = 0.05
#: most variants of one run
MAX_VARIANTS = 10_000
#: most candidates tried before giving up (a multiple of the variants asked for)
ATTEMPTS_PER_VARIANT = 20
#: largest energy model whose derivation the solutions show (as resonant report)
MAX_DERIVED = 12

_LABELS = {"M": "mass matrix M", "C": "damping matrix C", "K": "stiffness matrix K",
           "L": "cosine coefficients L of the stationary solution",
           "N": "sine coefficients N of the stationary solution",
           "F_S": "sine amplitudes F_S of the excitation",
           "F_C": "cosine amplitudes F_C of the excitation",
           "natural_frequencies": "natural frequencies (ascending)"}


@dataclass(frozen=True)
class Answer:
    """One answer of a variant: a number, a vector or a matrix (nested lists).

    Parameters
    ----------
    key : str
        What is asked, as in ``[exercise] answers`` (``"K"``, ``"amplitude:x1"`` ...).
    label : str
        The question in words.
    value : float or list
        The right answer.
    unit : str or None
        Its unit (models with units).

    Examples
    --------
    >>> Answer("K", "stiffness matrix K", [[100.0, 0.0], [0.0, 9.81]], None).label
    'stiffness matrix K'
    """

    key: str
    label: str
    value: Any
    unit: str | None


@dataclass(frozen=True)
class Variant:
    """One student's exercise: the varied values, the model with them, the solution.

    Parameters
    ----------
    number : int
        The variant's number, from 1.
    values : mapping
        The varied parameters' values (SI).
    texts : mapping
        The same values as written in the statement (with units).
    model : Model
        The model with these values.
    eom : LinearSystem
        Its linear system (sharing the symbolic derivation).
    solution : StationarySolution
        Its stationary solution.
    answers : mapping
        key -> :class:`Answer`.

    Examples
    --------
    >>> import resonant
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 2, seed=1)
    >>> batch.variants[1].number, sorted(batch.variants[1].values) == sorted(
    ...     v.name for v in batch.exercise.variants)
    (2, True)
    """

    number: int
    values: Mapping[str, float]
    texts: Mapping[str, str]
    model: Model
    eom: LinearSystem
    solution: StationarySolution
    answers: Mapping[str, Answer]


@dataclass(frozen=True)
class Replacement:
    """A drawn value set that was not used, and why.

    Parameters
    ----------
    values : mapping
        The drawn values.
    reason : str
        Why it was replaced (not an equilibrium, unstable, near resonance).

    Examples
    --------
    >>> Replacement({"k": 90.0}, "within 5 % of a natural frequency").reason
    'within 5 % of a natural frequency'
    """

    values: Mapping[str, float]
    reason: str


@dataclass(frozen=True)
class ExerciseSet:
    """The variants of one run (``seed``), the replaced value sets, the shared derivation.

    Parameters
    ----------
    model : Model
        The teacher's model.
    exercise : Exercise
        Its ``[exercise]`` and ``[variants]``.
    seed : int
        The seed the values were drawn with.
    variants : tuple of Variant
        The variants, numbered from 1.
    replaced : tuple of Replacement
        The value sets drawn but not used.
    eom : LinearSystem
        The symbolic system all variants share.

    Examples
    --------
    >>> import resonant
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 2, seed=1)
    >>> batch.seed, len(batch.variants)
    (1, 2)
    """

    model: Model
    exercise: Exercise
    seed: int
    variants: tuple[Variant, ...]
    replaced: tuple[Replacement, ...]
    eom: LinearSystem


# -- generation ----------------------------------------------------------------------------

def _candidates(exercise: Exercise, rng: np.random.Generator) -> Iterator[tuple[int, ...]]:
    """Distinct index tuples (one index per varied parameter), in a seeded random order."""
    sizes = [len(v.values) for v in exercise.variants]
    total = math.prod(sizes)
    if total <= 1_000_000:
        for flat in rng.permutation(total):
            digits, rest = [], int(flat)
            for size in reversed(sizes):
                rest, i = divmod(rest, size)
                digits.append(i)
            yield tuple(reversed(digits))
        return
    seen: set[tuple[int, ...]] = set()
    while True:
        index = tuple(int(rng.integers(size)) for size in sizes)
        if index not in seen:
            seen.add(index)
            yield index


def _shared(eom: LinearSystem, model: Model) -> LinearSystem:
    """The system of ``model`` (same equations, other numbers) without a new derivation:
    the symbolic system and its compiled form are shared."""
    names = {f.name for f in dataclasses.fields(eom)}  # type: ignore[arg-type]
    copy = dataclasses.replace(eom, model=model)  # type: ignore[type-var]
    for key, value in eom.__dict__.items():
        if key not in names:  # cached symbolic work (harmonics, compiled layout, ...)
            copy.__dict__[key] = value
    return copy


def _not_equilibrium(eom: LinearSystem, model: Model) -> str | None:
    residual = getattr(eom, "residual", None)
    if residual is None:
        return None
    subs = {symbol(n): v for n, v in model.exact_values.items()}
    for k, expr in enumerate(residual):
        if expr == 0:
            continue
        zero, value = is_zero(expr, subs)
        if not zero:
            return (f"not an equilibrium (residual {value.real:.3g} in the equation of "
                    f"{eom.coordinates[k]})")
    return None


def _rejection(eom: LinearSystem, model: Model, deadline: Deadline
               ) -> tuple[str | None, StationarySolution | None]:
    reason = _not_equilibrium(eom, model)
    if reason:
        return reason, None
    try:
        solution = stationary(eom, deadline)
    except DeadlineExceeded:
        raise
    except (AnalysisError, ModelError) as exc:
        return f"cannot be solved ({printable(str(exc), limit=200)})", None
    if solution.stability == UNSTABLE:
        return "the equilibrium is unstable", None
    for h in solution.harmonics:
        for i, wn in enumerate(solution.natural_frequencies):
            if h.omega > 0 and wn > 0 and abs(h.omega - wn) <= RESONANCE_MARGIN * wn:
                return (f"the excitation frequency {h.omega:.6g} rad/s is within "
                        f"{100 * abs(h.omega - wn) / wn:.2g} % of natural frequency {i + 1} "
                        f"({wn:.6g} rad/s)"), None
    return None, solution


def _coordinate_unit(exercise: Exercise, coordinates: Sequence[str]) -> str | None:
    units = exercise.units or {}
    found = {units.get(c) for c in coordinates}
    return found.pop() if len(found) == 1 else None


def _answers(exercise: Exercise, solution: StationarySolution, model: Model
             ) -> dict[str, Answer]:
    units = exercise.units or {}
    shown = result_units(model)
    e = solution.eom
    q = _coordinate_unit(exercise, e.coordinates)
    metre = q == "m"
    out: dict[str, Answer] = {}
    for key in exercise.answers:
        kind, _, name = key.partition(":")
        value: Any
        unit: str | None = None
        if key in ("M", "C", "K"):
            value = np.asarray(getattr(e, key), dtype=float).tolist()
            unit = {"M": "kg", "C": "N*s/m", "K": "N/m"}[key] if metre else None
        elif key in ("L", "N", "F_S", "F_C"):
            if not solution.harmonics:
                raise ModelError(Problem(f"the answer '{key}' needs a harmonic excitation; "
                                         "this model has none", model.source, "exercise",
                                         "answers"))
            rows = [np.asarray(getattr(h, key), dtype=float).tolist()
                    for h in solution.harmonics]
            value = rows[0] if len(rows) == 1 else rows
            unit = q if key in ("L", "N") else ("N" if metre else None)
        elif key == "natural_frequencies":
            value = solution.natural_frequencies.tolist()
            unit = "rad/s"
        elif kind == "amplitude":
            if name not in solution.amplitudes:
                raise ModelError(Problem(f"the answer '{key}' is not defined: the model has no "
                                         "stationary solution", model.source, "exercise",
                                         "answers"))
            value = float(solution.amplitudes[name])
            unit = units.get(name)
        elif kind in ("rms", "miles", "largest"):
            value = _load_answer(kind, name, solution, model)
            unit = units.get(name)
        else:  # phase
            if name not in solution.phases:
                raise ModelError(Problem(f"the answer '{key}' is not defined (a phase needs "
                                         "one excitation frequency and a non-zero amplitude)",
                                         model.source, "exercise", "answers"))
            value = float(solution.phases[name])
            unit = "rad"
        label = _LABELS.get(key) or {
            "amplitude": f"amplitude of {name}", "phase": f"phase of {name}",
            "rms": f"RMS value of {name} under the random load",
            "miles": f"Miles' estimate of the RMS value of {name}",
            "largest": f"largest excursion of {name} under the periodic load"}[kind]
        out[key] = Answer(key, label, *_in_display_units(value, unit, shown))
    return out


def _in_display_units(value: object, unit: str | None, units: ResultUnits | None
                      ) -> tuple[object, str | None]:
    """An answer (SI, in ``unit``) in the display unit chosen for its quantity
    (``[display]``, or the command line's units), as every result is shown: natural
    frequencies in Hz, amplitudes in mm, phases in degrees; unchanged where none was chosen.

    Examples
    --------
    >>> from resonant.model.units import display_units
    >>> units = ResultUnits(display=display_units(["Hz", "mm"]))
    >>> _in_display_units([6.283185307179586], "rad/s", units)
    ([1.0], 'Hz')
    >>> _in_display_units(0.0025, "m", units), _in_display_units(2.0, "kg", units)
    ((2.5, 'mm'), (2.0, 'kg'))
    """
    if units is None or not unit:
        return value, unit
    shown = units.of(unit)
    if shown.factor == 1.0 and shown.text == unit:
        return value, unit
    scaled = shown(np.asarray(value, dtype=float))
    return (scaled.tolist() if isinstance(value, list) else float(scaled)), shown.text


def _load_answer(kind: str, name: str, solution: StationarySolution, model: Model) -> float:
    """``rms:NAME`` and ``miles:NAME`` (the [random] section), ``largest:NAME`` (the
    [periodic] section) of one variant."""
    if kind == "largest":
        return float(periodic_load_response(solution.eom, names=[name]).largest[name])
    result = random_response(solution.eom, names=[name])
    if kind == "rms":
        return float(result.rms[name])
    if result.miles is None or name not in result.miles:
        raise ModelError(Problem(f"the answer 'miles:{name}' is not defined: Miles' equation "
                                 "needs one degree of freedom, one random input, a natural "
                                 "frequency inside the band and a response with a static gain "
                                 "that resonates", model.source, "exercise", "answers"))
    return float(result.miles[name])


def generate(model: Model, count: int, seed: int, deadline: Deadline = NO_DEADLINE
             ) -> ExerciseSet:
    """``count`` distinct, solved variants of the model's exercise.

    Parameters
    ----------
    model : Model
        A model with ``[exercise]`` and ``[variants]``.
    count : int
        How many variants.
    seed : int
        The seed of the draw (the same seed, the same variants).
    deadline : Deadline, optional
        Checked between variants.

    Returns
    -------
    ExerciseSet
        The variants and the replaced value sets.

    Raises
    ------
    ModelError
        No ``[exercise]``; fewer acceptable value sets than ``count``.

    Examples
    --------
    >>> import resonant
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 2, seed=1)
    >>> [v.number for v in batch.variants]
    [1, 2]
    """
    exercise = model.exercise
    if exercise is None:
        raise ModelError(Problem("the model has no [exercise] section (statement, answers) "
                                 "and [variants]; see docs/exercises.md", model.source,
                                 "exercise"))
    if not 1 <= count <= MAX_VARIANTS:
        raise ModelError(Problem(f"--variants must be between 1 and {MAX_VARIANTS}, got "
                                 f"{count}", "--variants"))
    if not 0 <= seed < 2**63:
        raise ModelError(Problem(f"--seed must be between 0 and 2^63 - 1, got {seed}", "--seed"))
    if count > exercise.combinations:
        raise ModelError(Problem(f"{count} variants asked for, but [variants] allows only "
                                 f"{exercise.combinations} distinct value sets", model.source,
                                 "variants"))
    eom = linear_system(model, deadline)
    eom.numeric(deadline)  # the harmonic split and the compilation, once, for all variants
    rng = np.random.Generator(np.random.PCG64(seed))
    variants: list[Variant] = []
    replaced: list[Replacement] = []
    attempts = 0
    for index in _candidates(exercise, rng):
        if len(variants) == count:
            break
        attempts += 1
        if attempts > ATTEMPTS_PER_VARIANT * count + 100:
            break
        deadline.check("while generating the exercise variants", analysis=True)
        values = {v.name: v.values[i] for v, i in zip(exercise.variants, index)}
        texts = {v.name: v.texts[i] for v, i in zip(exercise.variants, index)}
        try:
            vmodel = model.with_parameters(**texts)
            veom = _shared(eom, vmodel)
            reason, solution = _rejection(veom, vmodel, deadline)
        except DeadlineExceeded:
            raise
        except ModelError as exc:
            reason, solution = f"invalid ({printable(str(exc), limit=200)})", None
        if reason is not None or solution is None:
            replaced.append(Replacement(values, reason or "no solution"))
            continue
        variants.append(Variant(len(variants) + 1, values, texts, vmodel, veom, solution,
                                _answers(exercise, solution, vmodel)))
    if len(variants) < count:
        raise ModelError(Problem(
            f"only {len(variants)} of the {count} variants could be made: {len(replaced)} "
            "value sets were refused (not an equilibrium, unstable or near a resonance); "
            "widen [variants]", model.source, "variants"))
    return ExerciseSet(model, exercise, seed, tuple(variants), tuple(replaced), eom)
