"""The ``[matrices]`` section as data: the matrices and the ``[[harmonic]]`` loads of a
matrix model (docs/model-format.md)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..expressions import Expression


@dataclass(frozen=True)
class Harmonic:
    """One harmonic excitation of a matrix model: Q = F_S sin(omega t) + F_C cos(omega t).

    Parameters
    ----------
    omega : Expression
        The circular frequency (rad/s).
    F_S, F_C : tuple of Expression
        The sine and cosine amplitudes, one per coordinate.

    Examples
    --------
    >>> from resonant.expressions import parse
    >>> Harmonic(parse("w"), (parse("1"),), (parse("0"),)).omega.text
    'w'
    """

    omega: Expression
    F_S: tuple[Expression, ...]
    F_C: tuple[Expression, ...]


@dataclass(frozen=True)
class MatrixSpec:
    """The ``[matrices]`` section: M, K, optional C, given directly.

    Parameters
    ----------
    M, K : array_like or sparse matrix
        Mass and stiffness (numbers, or expressions for inline matrices).
    C : array_like or sparse matrix, optional
        Damping (None: undamped).
    harmonics : tuple of Harmonic
        The ``[[harmonic]]`` loads.
    nonlinear : tuple of NonlinearElement
        The ``[[nonlinear]]`` elements (:mod:`resonant.model.nonlinear_elements`).
    coordinates : tuple of str
        The coordinate names of a DOF map (``dofs``: ``n1042_uz``), or empty.
    G : array_like or sparse matrix, optional
        The gyroscopic matrix, multiplied by the speed parameter: the equation of motion
        is M q'' + (C + speed G) q' + K q = Q (None: no gyroscopic part).
    speed : str, optional
        The parameter that is the spin speed (rad/s); G needs it (docs/rotors.md).
    speed_terms : tuple of SpeedTerm
        Entries of K and C that depend on the parameters (a ``[rotor]``'s bearing
        coefficients: :class:`resonant.model.rotor.SpeedTerm`), added to the numbers.
    bearings : tuple of Bearing
        A ``[rotor]``'s bearings (:class:`resonant.model.rotor.Bearing`): where they are
        and their coefficients, for the bearing forces.

    Examples
    --------
    >>> from resonant.model import loads
    >>> m = loads('[matrices]\\nM = [[1]]\\nK = [[4]]\\n')
    >>> m.matrices.C is None, len(m.matrices.harmonics)
    (True, 0)
    """

    M: Any
    K: Any
    C: Any = None
    harmonics: tuple[Harmonic, ...] = ()
    nonlinear: tuple[Any, ...] = ()
    coordinates: tuple[str, ...] = ()
    G: Any = None
    speed: str | None = None
    speed_terms: tuple[Any, ...] = ()
    bearings: tuple[Any, ...] = ()
