"""``[[nonlinear]]`` entries of a ``[matrices]`` model: local nonlinear elements.

A large linear model (M, C, K from files) carries a few nonlinear elements, each
between two coordinates or from one coordinate to the ground:

``force``
    ``force = "k3*(q12 - q40)^3"``: an expression of the parameters, the
    coordinates it connects and their rates (``q7'``); it enters the first
    coordinate's equation with + and the second's with - (as a spring:
    ``M q'' + C q' + K q + f_nl = F``).
``gap``
    ``kind = "gap"``, ``gap = "g"``, ``stiffness = "kc"``: a unilateral contact,
    force ``kc (u - g)`` while the relative displacement u = q_a - q_b exceeds
    the clearance g, else zero.
``friction``
    ``kind = "friction"``, ``stiffness = "kt"``, ``slip_force = "mu*N"``: an
    elastic dry-friction (Jenkins) element, a spring kt in series with a slider
    that slips at ``slip_force``; its force depends on the path.

Examples
--------
>>> elements = read_nonlinear_elements(
...     [{"name": "mount", "coordinates": ["q2"], "force": "k3*q2^3"}],
...     ["k3"], ["q1", "q2"], "model.toml")
>>> elements[0].kind, elements[0].indices, elements[0].force.text
('force', (1,), 'k3*q2^3')
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy

from ..errors import ModelError, Problem
from ..expressions import Expression, ExpressionError, parse


@dataclass(frozen=True)
class ElementKind:
    """A kind of nonlinear element: what its entry takes and what its force is like.

    Parameters
    ----------
    name : str
        Its ``kind`` in a model file.
    keys : tuple of str
        The keys its entry takes (besides name, coordinates, kind).
    smooth : bool
        Whether its force is a smooth function of the motion (its harmonics decay fast);
        a gap's or a slider's kinks need more samples and harmonics.
    description : str
        How a sentence names it.
    """

    name: str
    keys: tuple[str, ...]
    smooth: bool
    description: str


#: every kind of nonlinear element, by its ``kind`` in a model file
ELEMENT_KINDS: dict[str, ElementKind] = {kind.name: kind for kind in (
    ElementKind("force", ("force",), True, "a force expression"),
    ElementKind("gap", ("gap", "stiffness"), False, "a unilateral contact"),
    ElementKind("friction", ("stiffness", "slip_force"), False,
                "an elastic dry-friction (Jenkins) element"),
)}
#: the kinds of nonlinear element
KINDS = tuple(ELEMENT_KINDS)
#: the keys each kind takes (besides name, coordinates, kind)
KIND_KEYS = {name: kind.keys for name, kind in ELEMENT_KINDS.items()}
#: most [[nonlinear]] entries of one model (the condensed harmonic balance grows with them)
MAX_ELEMENTS = 200


@dataclass(frozen=True)
class NonlinearElement:
    """One ``[[nonlinear]]`` entry, validated.

    Attributes
    ----------
    name : str
        Its name (for messages and results).
    coordinates : tuple of str
        One coordinate (to the ground) or two (between them).
    indices : tuple of int
        Their positions among the model's coordinates.
    kind : str
        ``force``, ``gap`` or ``friction``.
    force : Expression or None
        The force expression (``force`` kind).
    gap, stiffness, slip_force : Expression or None
        The parameters of the ``gap`` and ``friction`` kinds.
    """

    name: str
    coordinates: tuple[str, ...]
    indices: tuple[int, ...]
    kind: str
    force: Expression | None = None
    gap: Expression | None = None
    stiffness: Expression | None = None
    slip_force: Expression | None = None

    @property
    def section(self) -> str:
        return f"nonlinear '{self.name}'"

    @property
    def law(self) -> ElementKind:
        """Its kind's entry (:data:`ELEMENT_KINDS`)."""
        return ELEMENT_KINDS[self.kind]


def _finite(expression: Expression) -> bool:
    """False for an expression that is infinite or undefined whatever its names' values
    (``1/0*q2``, ``0/0``): its exact form holds an infinity or NaN."""
    try:
        exact = expression.to_sympy(lambda name, primes: sympy.Symbol(name + "'" * primes))
    except ExpressionError:
        return True  # too large to build exactly: later stages bound and report it
    return not exact.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo)


def _entry(entry: object, number: int, params: Sequence[str], coordinates: Sequence[str],
           source: str, problems: list[Problem]) -> NonlinearElement | None:
    where = f"nonlinear {number}"
    if not isinstance(entry, dict):
        problems.append(Problem("each [[nonlinear]] entry must be a table with name, "
                                "coordinates and force (or kind)", source, where))
        return None
    name = entry.get("name", f"nonlinear{number}")
    if not isinstance(name, str) or not name:
        problems.append(Problem("name must be a non-empty string", source, where, "name"))
        return None
    where = f"nonlinear '{name}'"
    kind = entry.get("kind", "force")
    if kind not in KINDS:
        problems.append(Problem(f"unknown kind {kind!r}; choose one of {', '.join(KINDS)}",
                                source, where, "kind"))
        return None
    allowed = {"name", "coordinates", "kind", *KIND_KEYS[kind]}
    for key in entry:
        if key not in allowed:
            problems.append(Problem(f"unknown key '{key}'; a {kind} element takes "
                                    f"{', '.join(sorted(allowed))}", source, where, key))
    names = entry.get("coordinates")
    if isinstance(names, str):
        names = [names]
    position = {q: i for i, q in enumerate(coordinates)}
    count = len(problems)
    if not (isinstance(names, list) and 1 <= len(names) <= 2
            and all(isinstance(q, str) for q in names)):
        problems.append(Problem("coordinates must be a list of one name (to the ground) or two "
                                "(between them), e.g. [\"q5\"] or [\"q5\", \"q9\"]",
                                source, where, "coordinates"))
        names = []
    elif [q for q in names if q not in position]:
        unknown = [q for q in names if q not in position]
        problems.append(Problem(f"unknown coordinate(s) {', '.join(map(repr, unknown))}; the "
                                f"coordinates are {', '.join(coordinates[:8])}"
                                f"{' ...' if len(coordinates) > 8 else ''}",
                                source, where, "coordinates"))
    elif len(names) == 2 and names[0] == names[1]:
        problems.append(Problem("the two coordinates must differ (one name: to the ground)",
                                source, where, "coordinates"))
    placed = len(problems) == count
    parsed: dict[str, Expression] = {}
    for key in KIND_KEYS[kind]:
        if key not in entry:
            problems.append(Problem(f"{key} is missing (a {kind} element needs "
                                    f"{' and '.join(KIND_KEYS[kind])})", source, where, key))
            continue
        value = entry[key]
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            problems.append(Problem(f"{key} must be a number or an expression string",
                                    source, where, key))
            continue
        scope = [*params, *names] if key == "force" else list(params)
        try:
            parsed[key] = parse(value, allowed=scope, file=source, section=where, key=key)
        except ExpressionError as exc:
            problems.extend(exc.problems)
            continue
        if not _finite(parsed[key]):
            problems.append(Problem("the expression is not finite (it divides by zero or "
                                    "holds an infinity, as 1/0 does); write a finite one",
                                    source, where, key))
            del parsed[key]
            continue
        if key != "force":
            primed = [n for n, p in parsed[key].names() if p]
            if primed:
                problems.append(Problem(f"{key} is a constant of the parameters: no rates "
                                        f"({primed[0]}')", source, where, key))
        else:
            wrong = [n for n, p in parsed[key].names() if p > 1 or (p and n in params)]
            if wrong:
                problems.append(Problem("a force may use the coordinates and their first "
                                        f"rates only (not {wrong[0]}'')", source, where, key))
    if len(parsed) != len(KIND_KEYS[kind]) or not placed:
        return None
    return NonlinearElement(name, tuple(names), tuple(position[q] for q in names), kind,
                            **parsed)


def read_nonlinear_elements(entries: object, params: Sequence[str], coordinates: Sequence[str],
                            source: str) -> tuple[NonlinearElement, ...]:
    """Validate the ``[[nonlinear]]`` entries; every problem in one ModelError.

    Parameters
    ----------
    entries : list of dict
        The TOML array of tables.
    params : sequence of str
        The parameter names.
    coordinates : sequence of str
        The model's coordinates.
    source : str
        The model file, for messages.

    Returns
    -------
    tuple of NonlinearElement

    Raises
    ------
    ModelError
        Naming file, entry and key of every problem.

    Examples
    --------
    >>> try:
    ...     read_nonlinear_elements([{"coordinates": ["q9"], "kind": "gap", "gap": 0.1}],
    ...                             [], ["q1"], "m.toml")
    ... except ModelError as exc:
    ...     print(len(exc.problems))
    2
    """
    if not isinstance(entries, list):
        raise ModelError(Problem("[[nonlinear]] must be an array of tables ([[nonlinear]] "
                                 "headers)", source, "nonlinear"))
    if len(entries) > MAX_ELEMENTS:
        raise ModelError(Problem(f"{len(entries)} [[nonlinear]] entries; a model is limited "
                                 f"to {MAX_ELEMENTS}", source, "nonlinear"))
    problems: list[Problem] = []
    out = []
    seen: set[str] = set()
    for number, entry in enumerate(entries, start=1):
        element = _entry(entry, number, params, coordinates, source, problems)
        if element is None:
            continue
        if element.name in seen:
            problems.append(Problem(f"the name '{element.name}' is used twice", source,
                                    element.section, "name"))
        seen.add(element.name)
        out.append(element)
    if problems:
        raise ModelError(problems)
    return tuple(out)


__all__ = ["NonlinearElement", "read_nonlinear_elements", "KINDS", "MAX_ELEMENTS",
           "ELEMENT_KINDS", "ElementKind"]
