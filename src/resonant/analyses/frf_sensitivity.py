"""The sensitivities of a model's FRFs to its parameters, analytically (docs/testing.md).

With the dynamic stiffness Z(w; p) = K - w^2 M + i w C and an input's load b(w; p)
(the sum of its generalized-force columns times (i w)^order), the response is
x = Z^-1 b and, differentiating Z x = b,

    dx/dp = Z^-1 (db/dp - (dK/dp - w^2 dM/dp + i w dC/dp) x),

the classical dH/dp = -H (dZ/dp) H for a load that does not depend on p (Fox & Kapoor,
AIAA J. 6, 1968; Heylen, Lammens & Sas, Modal Analysis Theory and Testing, sec. A.4).
The matrices' and the loads' derivatives are central differences of the system's numbers
at p (1 -+ 1e-6; the matrices of both points in one :meth:`~resonant.system.base.NumericEOM.batch`,
a matrix that does not depend on p has the derivative 0 exactly): exact to rounding for
matrices linear or quadratic in p (a mass, a stiffness, a dashpot; k L^2), as they are in a
lumped model.  The loads' columns are differenced only for the parameters they depend on
(:func:`loads_depend_on`, probed once).  One factorization of Z per line serves the
response and every parameter's derivative (stacked dense solves up to
:data:`STACKED_LIMIT` coordinates, a banded or dense LU per line above), where finite differences of
the FRF solve the whole model twice per parameter.

The analytic route covers FRFs of coordinates (and their derivatives); for a channel that
is an output of the model, or a model above :data:`ANALYTIC_LIMIT` coordinates (the
matrices' derivatives are held dense), :func:`frf_with_sensitivities` returns None and the
caller differences the FRF instead.

Examples
--------
>>> import numpy as np, resonant
>>> from resonant.model.measurement_spec import ChannelMap
>>> system = resonant.load("examples/chain3_lab.toml").linearize()
>>> f = np.array([0.0])
>>> H, dH = frf_with_sensitivities(system, ["F"], f, {"d3": ChannelMap("x3")}, ["k1"], {})
>>> round(float(H[0, 0, 0].real), 6), round(float(dH[0, 0, 0, 0].real * 1e6), 6)
(0.003, -1.0)
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence

import numpy as np

from ..deadline import NO_DEADLINE, Deadline
from ..memory import dense_matrix, require
from ..model.measurement_spec import ChannelMap
from ..system.base import LinearSystem, NumericEOM
from ..system.excitation import excitation_columns
from .kernel import LineFactors

__all__ = ["frf_with_sensitivities", "loads_depend_on", "ANALYTIC_LIMIT", "STACKED_LIMIT"]

#: the most coordinates of the analytic route (the matrices' derivatives are held dense)
ANALYTIC_LIMIT = 2000
#: up to this many coordinates the lines are solved as one stacked dense system, above
#: by a banded or dense LU per line (:class:`resonant.analyses.kernel.LineFactors`)
STACKED_LIMIT = 24
#: relative step of the matrices' central differences
_STEP = 1e-6


def _loads(system: LinearSystem, num: NumericEOM, signals: Sequence[str],
           iw: np.ndarray) -> np.ndarray | None:
    """The loads b_j(w) (lines, n, inputs) of each input at ``num``'s parameters; None for an
    input that is neither a signal with a force column nor a coordinate."""
    columns = excitation_columns(system, dict(num.parameters))
    B = np.zeros((len(iw), num.n, len(signals)), complex)
    for j, name in enumerate(signals):
        found = [(order, c) for (var, order), c in sorted(columns.items()) if var == name]
        if found:
            for order, c in found:
                B[:, :, j] += iw[:, None] ** order * np.asarray(c, dtype=float)[None, :]
        elif name in num.coordinates:
            B[:, num.coordinates.index(name), j] = 1.0
        else:
            return None
    return B


def loads_depend_on(system: LinearSystem, signals: Sequence[str], names: Sequence[str],
                    values: Mapping[str, float], deadline: Deadline = NO_DEADLINE
                    ) -> frozenset[str]:
    """The parameters the inputs' force columns depend on: those for which the columns
    differ at 0.5, 1.3 or 2.1 times the parameter's value (parameters defined from it
    following) from the columns at ``values``.

    Parameters
    ----------
    system : LinearSystem
    signals : sequence of str
    names : sequence of str
    values : mapping
    deadline : Deadline, optional

    Returns
    -------
    frozenset of str

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_lab.toml").linearize()
    >>> loads_depend_on(system, ["F"], ["k1", "m"], {})
    frozenset()
    """
    iw = np.array([1j])
    num = system.numeric(deadline, **values)
    base = _loads(system, num, signals, iw)
    found = set()
    for name in names:
        p = float(num.parameters[name])
        for scale in (0.5, 1.3, 2.1):
            moved = _loads(system, system.numeric(deadline, **{**values, name: scale * p}),
                           signals, iw)
            if base is None or moved is None or not np.array_equal(base, moved):
                found.add(name)
                break
    return frozenset(found)


def _derivative(a: np.ndarray | object, up: int, down: int, h: float) -> np.ndarray | float:
    """The central difference of a batch's matrix of two points (0 when it is constant)."""
    a = dense_matrix(a, None)
    return (a[up] - a[down]) / (2 * h) if np.ndim(a) == 3 else 0.0


def _times(a: np.ndarray | float, X: np.ndarray) -> np.ndarray | float:
    """dA X for every line (X (lines, n, inputs)); 0 for a constant matrix."""
    if isinstance(a, float):
        return 0.0
    return np.asarray(np.matmul(a, X))


def frf_with_sensitivities(system: LinearSystem, signals: Sequence[str],
                           frequency: np.ndarray, channels: Mapping[str, ChannelMap],
                           names: Sequence[str], values: Mapping[str, float], *,
                           loads_vary: Collection[str] | None = None,
                           deadline: Deadline = NO_DEADLINE
                           ) -> tuple[np.ndarray, np.ndarray] | None:
    """The model's FRFs and their derivatives with respect to parameters, analytically.

    Parameters
    ----------
    system : LinearSystem
    signals : sequence of str
        The inputs (signals with a force column, or coordinates).
    frequency : ndarray
        The lines (Hz).
    channels : mapping
        Channel -> its coordinate and derivative.
    names : sequence of str
        The parameters differentiated.
    values : mapping
        The parameter point (SI; those not given keep the model's values).
    loads_vary : collection of str, optional
        The parameters the inputs' force columns depend on (:func:`loads_depend_on`);
        default all of ``names`` (their columns differenced too).
    deadline : Deadline, optional

    Returns
    -------
    (H, dH) or None
        H (lines, channels, inputs) as
        :func:`resonant.analyses.frf_update.model_frf_matrix`, dH (parameters, lines,
        channels, inputs) its derivatives d H / d p; None where the analytic route does not
        apply (module docstring).
    """
    num = system.numeric(deadline, **values)
    if num.n > ANALYTIC_LIMIT or any(c.name not in num.coordinates for c in channels.values()):
        return None
    f = np.asarray(frequency, dtype=float)
    w = 2 * np.pi * f
    iw = 1j * w
    n, lines, inputs = num.n, len(f), len(signals)
    require(16.0 * lines * min(n, STACKED_LIMIT) * (min(n, STACKED_LIMIT) + inputs * (
        2 + len(names))) + 24.0 * n * n * 3,
            f"the dynamic stiffness of {n} coordinates at {lines} lines",
            "fit fewer lines or fewer parameters")
    B = _loads(system, num, signals, iw)
    if B is None:
        return None
    rows = [num.coordinates.index(c.name) for c in channels.values()]
    factor = np.array([iw ** c.derivative for c in channels.values()]).T[:, :, None]
    derivatives: list[tuple[np.ndarray, np.ndarray | float, np.ndarray | float,
                            np.ndarray | float]] = []
    base = dict(num.parameters)
    for name in names:
        deadline.check("while differentiating the FRFs", analysis=True)
        p = float(base[name])
        h = _STEP * abs(p) if p else _STEP
        pair = num.batch(name, np.array([p + h, p - h]), deadline)
        dM, dC, dK = (_derivative(a, 0, 1, h) for a in (pair.M, pair.C, pair.K))
        dB = np.zeros_like(B)
        if loads_vary is None or name in loads_vary:
            up, down = (system.numeric(deadline, **{**values, name: p + s}) for s in (h, -h))
            bu, bd = _loads(system, up, signals, iw), _loads(system, down, signals, iw)
            if bu is None or bd is None:
                return None
            dB = (bu - bd) / (2 * h)
        derivatives.append((dB, dM, dC, dK))
    if not names:
        X = _solve_lines(num, w, B, [])[0]
        return X[:, rows, :] * factor, np.zeros((0, lines, len(rows), inputs), complex)
    X, dX = _solve_lines(num, w, B, derivatives, rows)
    H = X[:, rows, :] * factor
    dH = np.moveaxis(dX.reshape(lines, len(rows), len(names), inputs), 2, 0) * factor[None]
    return H, dH


def _solve_lines(num: NumericEOM, w: np.ndarray, B: np.ndarray,
                 derivatives: list[tuple[np.ndarray, np.ndarray | float, np.ndarray | float,
                                         np.ndarray | float]],
                 rows: Sequence[int] = ()) -> tuple[np.ndarray, np.ndarray]:
    """X = Z^-1 B at every line and dX = Z^-1 (dB - dZ X) at ``rows``, one factorization of
    Z per line (:class:`resonant.analyses.kernel.LineFactors`)."""
    factors = LineFactors(num.M, num.C, num.K, w, STACKED_LIMIT)
    X = factors.solve(B)
    if not derivatives:
        return X, np.zeros((len(w), 0, 0), complex)
    iw = 1j * w[:, None, None]
    w2 = (w ** 2)[:, None, None]
    R = np.concatenate([dB - _times(dK, X) + w2 * _times(dM, X) - iw * _times(dC, X)
                        for dB, dM, dC, dK in derivatives], axis=2)
    return X, factors.solve(R)[:, list(rows), :]
