"""Model updating: parameters adjusted so that the model's natural frequencies (and mode
shapes, through the MAC) meet the measured ones (docs/testing.md).

The residuals, one per measured mode j paired with model mode m(j),

    r_j = (f_m(j)(p) - f_j) / f_j,        and, with shapes, w (1 - MAC_j(p)),

are minimized by :func:`scipy.optimize.least_squares` (trust-region reflective, inside the
bounds) over x = ln p, so that parameters of any size weigh alike.  The frequencies'
sensitivities are the eigenvalues' (Fox & Kapoor 1968): with mass-normalized phi,
d lambda / dp = phi^T (dK/dp - lambda dM/dp) phi, the matrices' derivatives by central
differences of the system's numbers (exact for matrices linear in p); the MAC rows by
forward differences.  The pairing follows the MAC when shapes are given (else mode j with
model mode j).  The fitted values' standard deviations come from the Jacobian at the
solution: cov(x) = s^2 (J^T J)^-1, s the frequencies' relative standard deviation if known
(``sigma``), else the residuals' (with more residuals than parameters).

Examples
--------
>>> import resonant
>>> system = resonant.load("examples/chain3_damped.toml").linearize()
>>> target = [2.2399 * 1.05]                   # the first mode 5 % higher
>>> r = update_parameters(system, {"k": ("500 N/m", "2000 N/m")}, target)
>>> round(r.fitted["k"] / 1000, 4)              # the stiffness 1.05^2 times larger
1.1025
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import (
    Bar,
    Chart,
    Charted,
    Charts,
    charts_svg,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..expressions import ExpressionError, numeric_value
from ..memory import dense_matrix
from ..modal import mass_normalized_modes, modal_assurance
from ..model.measurement_spec import ChannelMap
from ..model.units import parse_with_unit
from ..model.units_display import ResultUnits, cyclic_shown
from ..system.base import LinearSystem
from .correlate import Correlation, correlate_shapes
from .result_fields import PLAIN_NUMBER, FieldsJSON, saved

__all__ = ["ModelUpdate", "update_parameters", "parameter_bounds", "log_std"]

#: relative step of the matrices' central differences
_STEP = 1e-6


@dataclass(frozen=True)
class FittedParameters(FieldsJSON):
    """The fields that :class:`ModelUpdate` and
    :class:`~resonant.analyses.frf_update.FRFUpdate` share: the parameters a fit changed
    (``names``), each one's value before (``start``) and after (``fitted``, SI), its
    standard deviation (``std``) and its ``bounds`` (low, high); saved as one record per
    parameter under ``"parameters"``.
    """

    #: the records of to_dict() (resonant.analyses.result_fields.FieldsJSON): one per
    #: parameter
    _by_name = {"parameters": ("names", ("start", "fitted", "std", "bounds"))}

    names: tuple[str, ...] = saved(keys_of="parameters")
    start: dict[str, float] = saved(by_name="parameters", codec=PLAIN_NUMBER)
    fitted: dict[str, float] = saved(by_name="parameters", codec=PLAIN_NUMBER)
    std: dict[str, float] = saved(by_name="parameters", codec=PLAIN_NUMBER)
    bounds: dict[str, tuple[float, float]] = saved(by_name="parameters")


@dataclass(frozen=True)
class ModelUpdate(FittedParameters, Charted):
    """Parameters fitted to measured modes, with their uncertainty.

    Attributes
    ----------
    names : tuple of str
        The parameters.
    start, fitted, std : mapping
        Their values before and after (SI), and the fitted values' standard deviations.
    bounds : mapping
        name -> (low, high).
    target : ndarray
        The measured natural frequencies (Hz).
    before, after : ndarray
        The paired model frequencies before and after (Hz).
    correlation_before, correlation_after : Correlation or None
        With shapes: the test against the model before and after.
    cost : float
        Half the sum of the squared residuals at the solution.
    message : str
        The optimizer's.
    warnings : tuple of str

    Examples
    --------
    >>> import resonant
    >>> from resonant.analyses.model_update import update_parameters
    >>> system = resonant.load("examples/chain3_damped.toml").linearize()
    >>> r = update_parameters(system, {"k": ("500 N/m", "2000 N/m")}, [2.2399 * 1.05])
    >>> r.names, round(r.fitted["k"] / r.start["k"], 4)         # 5 % higher: k 1.05^2
    (('k',), 1.1025)
    """

    target: np.ndarray = saved(key="target_hz", axes=(None,))
    before: np.ndarray = saved(key="before_hz", axes=("target",))
    after: np.ndarray = saved(key="after_hz", axes=("target",))
    correlation_before: Correlation | None = saved(None)
    correlation_after: Correlation | None = saved(None)
    cost: float = saved(0.0, codec=PLAIN_NUMBER)
    message: str = saved("")
    warnings: tuple[str, ...] = saved(())

    def __post_init__(self) -> None:
        freeze_fields(self)

    def chart(self) -> Charts:
        """The frequency errors before and after, per measured mode.

        Returns
        -------
        Charts
        """
        x = np.arange(1, len(self.target) + 1, dtype=float)
        before = 100 * (np.asarray(self.before) - self.target) / self.target
        after = 100 * (np.asarray(self.after) - self.target) / self.target
        span = max(0.1, float(np.nanmax(np.abs(np.r_[before, after]), initial=0.0)) * 1.2)
        chart = Chart((), "measured mode", "(f model - f test) / f test [%]",
                      (0.4, len(x) + 0.6), ylim=(-span, span),
                      bars=(Bar(x - 0.2, before, ("#7f7f7f",), 0.35, "before"),
                            Bar(x + 0.2, after, ("#1f77b4",), 0.35, "after")),
                      xticks=tuple((float(k), str(int(k))) for k in x))
        return Charts((chart,), title="model updating")

    def summary(self, units: ResultUnits | None = None) -> str:
        """The fitted parameters and the frequencies before and after.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``: frequencies in the unit chosen; default Hz).

        Returns
        -------
        str
        """
        lines = [f"{'parameter':<12} {'start':>12} {'fitted':>12} {'std':>10}"]
        lines += [f"{printable(n, limit=12):<12} {self.start[n]:>12.6g} "
                  f"{self.fitted[n]:>12.6g} {self.std[n]:>10.3g}" for n in self.names]
        hz = cyclic_shown(units)
        lines.append(f"{'mode':>4} {f'test [{hz.text}]':>10} {'before':>10} {'after':>10}")
        lines += [f"{k + 1:>4} {hz(t):>10.5g} {hz(b):>10.5g} {hz(a):>10.5g}"
                  for k, (t, b, a) in enumerate(zip(self.target, self.before, self.after))]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines) + "\n"

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "model-update")


def _si(value: object, name: str, source: str) -> float:
    """A bound: a number (SI) or a text with a unit ("800 N/m")."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ModelError(Problem("a bound is a number or a text with a unit", source,
                                 "update", name))
    try:
        expression, _ = parse_with_unit(value, [], source, "update", name)
        number = float(numeric_value(expression, {}))
    except (ExpressionError, TypeError, ValueError):
        raise ModelError(Problem(f"'{printable(value, limit=30)}' is not a number with a "
                                 "unit", source, "update", name)) from None
    if not (math.isfinite(number) and number > 0):
        raise ModelError(Problem("the bounds must be positive (the fit is in ln p)", source,
                                 "update", name))
    return number


def parameter_bounds(system: LinearSystem, parameters: Mapping[str, tuple[Any, Any]],
                     model_values: Mapping[str, Any]) -> dict[str, tuple[float, float]]:
    """The bounds (SI) of the parameters to fit, checked.

    Parameters
    ----------
    system : LinearSystem
        Its source names the file in the messages.
    parameters : mapping
        name -> (low, high): numbers (SI) or texts with units.
    model_values : mapping
        The model's parameters and their values.

    Returns
    -------
    dict
        name -> (low, high).

    Raises
    ------
    ModelError
        For an unknown parameter, or bounds that are not positive and increasing.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_damped.toml").linearize()
    >>> parameter_bounds(system, {"k": ("0.5 kN/m", 2000)}, {"k": 1000.0})
    {'k': (500.0, 2000.0)}
    """
    bounds = {}
    for name in parameters:
        if name not in model_values:
            raise ModelError(Problem(f"'{printable(name, limit=40)}' is not a parameter of "
                                     "the model", system.source, "update", name))
        low, high = (_si(v, name, system.source) for v in parameters[name])
        if not low < high:
            raise ModelError(Problem("the lower bound must be below the upper", system.source,
                                     "update", name))
        bounds[name] = (low, high)
    return bounds


class _Problem:
    """The residuals and their Jacobian at x = ln p."""

    def __init__(self, system: LinearSystem, names: Sequence[str], target: np.ndarray,
                 shapes: np.ndarray | None, rows: list[int], mac_weight: float,
                 deadline: Deadline) -> None:
        self.system, self.names, self.target = system, list(names), target
        self.shapes, self.rows, self.mac_weight = shapes, rows, mac_weight
        self.deadline = deadline

    def matrices(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        self.deadline.check("while updating the model", analysis=True)
        num = self.system.numeric(self.deadline, **dict(zip(self.names, map(float, p))))
        return tuple(dense_matrix(a) for a in (num.M, num.K))  # type: ignore[return-value]

    def modes(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The paired model frequencies (Hz), eigenvalues and mass-normalized shapes."""
        M, K = self.matrices(p)
        lam, phi = mass_normalized_modes(M, K)
        pair = self.pairing(phi)
        lam, phi = lam[pair], phi[:, pair]
        return np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi), lam, phi

    def pairing(self, phi: np.ndarray) -> np.ndarray:
        if self.shapes is None:
            return np.arange(len(self.target))
        from scipy.optimize import linear_sum_assignment

        mac = modal_assurance(self.shapes, phi[self.rows])
        _, cols = linear_sum_assignment(-mac)
        return np.asarray(cols)

    def residuals(self, x: np.ndarray) -> np.ndarray:
        f, _, phi = self.modes(np.exp(x))
        r = (f - self.target) / self.target
        if self.shapes is None:
            return np.asarray(r)
        mac = np.diag(modal_assurance(self.shapes, phi[self.rows]))
        return np.concatenate([r, self.mac_weight * (1 - mac)])

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        p = np.exp(x)
        f, lam, phi = self.modes(p)
        J = np.empty((len(self.target), len(p)))
        for k in range(len(p)):
            h = _STEP * p[k]
            up, down = p.copy(), p.copy()
            up[k] += h
            down[k] -= h
            (Mu, Ku), (Md, Kd) = self.matrices(up), self.matrices(down)
            dM, dK = (Mu - Md) / (2 * h), (Ku - Kd) / (2 * h)
            dlam = np.einsum("ij,ik,kj->j", phi, dK, phi) - lam * np.einsum(
                "ij,ik,kj->j", phi, dM, phi)
            J[:, k] = p[k] * dlam / (8 * np.pi ** 2 * f) / self.target
        if self.shapes is None:
            return J
        base = self.residuals(x)[len(self.target):]
        mac_rows = np.empty((len(base), len(p)))
        for k in range(len(p)):
            step = np.zeros(len(p))
            step[k] = 1e-6
            mac_rows[:, k] = (self.residuals(x + step)[len(self.target):] - base) / 1e-6
        return np.vstack([J, mac_rows])


def update_parameters(system: LinearSystem, parameters: Mapping[str, tuple[Any, Any]],
                      target_frequency: Sequence[float] | np.ndarray, *,
                      target_shapes: np.ndarray | None = None,
                      channels: Mapping[str, ChannelMap] | None = None,
                      mac_weight: float = 1.0, sigma: float | None = None,
                      start: Mapping[str, float] | None = None,
                      deadline: Deadline = NO_DEADLINE) -> ModelUpdate:
    """Fit parameters within bounds to measured natural frequencies (and shapes).

    Parameters
    ----------
    system : LinearSystem
    parameters : mapping
        name -> (low, high): numbers (SI) or texts with units; the fit starts from the
        model's value (clipped into the bounds).
    target_frequency : array_like
        The measured natural frequencies (Hz), each paired with a model mode.
    target_shapes : ndarray, optional
        (channels, modes) measured shapes (the identification's residues); ``channels``
        then maps their rows to coordinates, in order.
    channels : mapping, optional
        Channel -> coordinate of each row of ``target_shapes``.
    mac_weight : float
        The weight of the (1 - MAC) residuals.
    sigma : float, optional
        The measured frequencies' relative standard deviation (for the uncertainty).
    start : mapping, optional
        name -> the value (SI) the fit starts from (default the model's), clipped into the
        bounds: one start of a multi-start (:mod:`resonant.studies.multi_start`).
    deadline : Deadline, optional

    Returns
    -------
    ModelUpdate

    Raises
    ------
    ModelError
        For an unknown parameter, bounds that are not positive and increasing, more
        measured modes than the model has, or shapes without their channels.
    """
    from scipy.optimize import least_squares

    num = system.numeric(deadline)
    model_values = dict(num.parameters)
    target = np.asarray(target_frequency, float).ravel()
    names = list(parameters)
    bounds = parameter_bounds(system, parameters, model_values)
    if not len(target) or len(target) > num.n or not np.all(target > 0):
        raise ModelError(Problem(f"give 1 to {num.n} positive measured frequencies",
                                 system.source, "update"))
    rows: list[int] = []
    shapes = None
    if target_shapes is not None:
        shapes = np.asarray(target_shapes)
        if channels is None or len(channels) != shapes.shape[0]:
            raise ModelError(Problem("measured shapes need their channels, one per row",
                                     system.source, "update"))
        rows = [num.coordinates.index(c.name) for c in channels.values()]
    problem = _Problem(system, names, target, shapes, rows, mac_weight, deadline)
    first = {**model_values, **(start or {})}
    start_values = np.array([min(max(float(first[n]), bounds[n][0]), bounds[n][1])
                             for n in names])
    lower = np.log([bounds[n][0] for n in names])
    upper = np.log([bounds[n][1] for n in names])
    solution = least_squares(problem.residuals, np.log(start_values), jac=problem.jacobian,
                             bounds=(lower, upper), x_scale=1.0, xtol=1e-12, ftol=1e-12,
                             gtol=1e-12)
    fitted = np.exp(solution.x)
    std = log_std(solution.jac, solution.fun, fitted, sigma, len(target))
    correlation = _correlations(problem, start_values, fitted) if shapes is not None \
        else (None, None)
    warnings = [f"{n} ended on its bound {fitted[k]:.6g}" for k, n in enumerate(names)
                if np.isclose(solution.x[k], lower[k]) or np.isclose(solution.x[k], upper[k])]
    return ModelUpdate(tuple(names), dict(zip(names, start_values.tolist())),
                       dict(zip(names, fitted.tolist())), dict(zip(names, std.tolist())),
                       bounds, target, problem.modes(start_values)[0], problem.modes(fitted)[0],
                       correlation[0], correlation[1], float(solution.cost),
                       str(solution.message), tuple(warnings))


def log_std(J: np.ndarray, r: np.ndarray, p: np.ndarray, sigma: float | None,
            frequencies: int) -> np.ndarray:
    """The fitted values' standard deviations from the Jacobian in ln p.

    Parameters
    ----------
    J : ndarray
        (residuals, parameters) the Jacobian of the residuals in ln p at the solution.
    r : ndarray
        The residuals there.
    p : ndarray
        The fitted values.
    sigma : float or None
        The residuals' standard deviation, else estimated from ``r`` (NaN without more
        residuals than parameters).
    frequencies : int
        How many leading rows of ``J`` the covariance takes (all: ``len(r)``).

    Returns
    -------
    ndarray

    Examples
    --------
    >>> log_std(np.array([[1.0], [1.0]]), np.array([0.1, -0.1]), np.array([2.0]), None, 2)
    array([0.2])
    """
    m, n = J.shape
    if sigma is None:
        if m <= n:
            return np.full(n, np.nan)
        sigma = float(np.sqrt(np.sum(r ** 2) / (m - n)))
    try:
        cov = sigma ** 2 * np.linalg.inv(J[:frequencies].T @ J[:frequencies]) \
            if frequencies >= n else sigma ** 2 * np.linalg.pinv(J.T @ J)
    except np.linalg.LinAlgError:
        return np.full(n, np.nan)
    return np.asarray(p * np.sqrt(np.maximum(np.diag(cov), 0.0)))


def _correlations(problem: _Problem, start: np.ndarray, fitted: np.ndarray
                  ) -> tuple[Correlation, Correlation]:
    assert problem.shapes is not None
    out = []
    for p in (start, fitted):
        M, K = problem.matrices(p)
        lam, phi = mass_normalized_modes(M, K)
        f = np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)
        out.append(correlate_shapes(problem.target, problem.shapes, f, phi[problem.rows]))
    return out[0], out[1]
