"""Modal analysis: natural frequencies, mode shapes, damping ratios, stability.

The undamped modes solve K phi = omega^2 M phi.  They are reported twice:
mass-normalised (phi^T M phi = 1) and scaled so that the largest component
is +1 (the view of the model-file contract, ``mode_shapes``).

Damping is described by the eigenvalues s of the state matrix
(s^2 M + s C + K) x = 0: damping ratio zeta = -Re s / |s| and damped
frequency Im s.  When the damping is *proportional* (Caughey & O'Kelly:
K M^-1 C = C M^-1 K, which includes Rayleigh damping C = a M + b K) the
undamped modes decouple C too, so each mode j has c_j = phi_j^T C phi_j,
zeta_j = c_j / (2 omega_j) and s = (-c_j +- sqrt(c_j^2 - 4 omega_j^2)) / 2;
these are reported per mode, together with a and b when C = a M + b K.

Large sparse matrix models: with ``count`` the lowest modes come from
shift-invert Lanczos, refined with compensated residuals
(:func:`~resonant.modal.lowest_modes`: the shift at 0, or just below it when
rigid-body modes make K singular), and nothing dense of size n x n is formed.  Every
natural frequency comes with a bound on its error from its residual
(``frequency_errors``), and a warning where the conditioning of M and K limits it.

The numbers come from the modal kernel :mod:`resonant.modal`, which the
stability checks and the study quantities share: ``modes`` is that kernel at one point.

Examples
--------
>>> from resonant.api import load
>>> from resonant.analyses.modes import modes
>>> from pathlib import Path
>>> path = Path(__file__).parents[3] / "examples" / "two_dof_free.toml"
>>> result = modes(load(path).linearize())
>>> result.natural_frequencies.round(4).tolist()     # sqrt(k/m), sqrt(3k/m)
[20.0, 34.641]
>>> result.mode_shapes.round(12).T.tolist()
[[1.0, 1.0], [1.0, -1.0]]
"""

from __future__ import annotations

import html
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, TypeGuard

import numpy as np

from ..arrays import Matrix, freeze_fields
from ..charts import (
    COLORS,
    Bar,
    Chart,
    Charts,
    Curve,
    PathArg,
    Rule,
    check_plot_path,
    draw_figure,
    save_figure,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, printable
from ..expressions.notation import dollar_name
from ..memory import dense_matrix
from ..modal import (
    LIMITED_ACCURACY,
    accurate_product,
    damping_ratios,
    eigenvalue_bounds,
    frequency_bounds,
    lowest_by_frequency,
    lowest_modes,
    lowest_state_eigenvalues,
    order,
    overdamped,
    point_state_eigenvalues,
    undamped_eigen,
)
from ..model.units_display import HZ, Shown
from ..system.base import LinearSystem
from ..system.stability import (
    ASYMPTOTIC,
    MARGINAL,
    PROPORTIONAL_TOLERANCE,
    UNSTABLE,
    check_mass_matrix,
    mass_warning,
    rayleigh,
    stiffness_eigenvalues,
)
from ..system.stability import (
    stability as definite_stability,
)
from ..tables import ResultTable, number_cell, number_column
from .result_fields import COMPLEX_PAIRS, ROWS, Codec, FieldsJSON, Shape, saved
from .results_json import Saved

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from scipy.sparse import sparray, spmatrix

    from ..model.units_display import ResultUnits

#: matrices up to this size are analysed densely when no ``count`` is given
DENSE_MODES = 1500


def _rayleigh_read(reader: Saved, key: str, shape: Shape) -> tuple[float, float] | None:
    if reader.value(key) is None:
        return None
    coefficients = reader.mapping(key)
    return coefficients.number("a"), coefficients.number("b")


#: Rayleigh's coefficients (a, b) of C = a M + b K as {"a": ..., "b": ...}, or null
_RAYLEIGH = Codec(lambda v: None if v is None else {"a": v[0], "b": v[1]}, _rayleigh_read)


@dataclass(frozen=True)
class ModalAnalysis(FieldsJSON):
    """The modes of M q'' + C q' + K q = 0.

    Attributes
    ----------
    coordinates : tuple of str
    omega_squared : ndarray
        Eigenvalues lambda of K phi = lambda M phi, ascending (negative: a
        statically unstable mode).
    natural_frequencies : ndarray
        sqrt(lambda) in rad/s for the modes with lambda >= 0, ascending.
    mode_shapes : ndarray
        (n, modes): one column per natural frequency, largest component +1.
    mass_normalised_modes : ndarray
        The same modes with phi^T M phi = 1 (largest component positive).
    eigenvalues : ndarray
        Complex eigenvalues s of the state matrix (all 2n, or 2 per computed
        mode for proportional damping), ordered by ``|s|``, then Im s.
    damping_ratios, damped_frequencies : ndarray
        Per mode (proportional damping), else per eigenvalue pair with
        Im s >= 0 ordered by ``|s|``; with a ``count`` (and always for a large sparse
        model) those of the ``count`` complex modes of lowest damped frequency, the
        overdamped (real) eigenvalues counted apart (``overdamped``).
    proportional_damping : bool
        C is diagonalised by the undamped modes (always true without damping).
    rayleigh : tuple of float or None
        (a, b) with C = a M + b K, when C has that form.
    stability : str
    method : str
        ``"dense"`` or ``"shift-invert Lanczos"``.
    frequency_errors : ndarray
        A bound on the error of each natural frequency in rad/s, from the residual of its
        mode (:func:`~resonant.modal.eigenvalue_bounds`); NaN where the pencil is
        not symmetric definite.  A warning says when it exceeds 1e-8 of the frequency
        (the conditioning of M and K limits the accuracy).
    damped : bool
        Whether C is nonzero.
    warnings : tuple of str
        What the user should know (rigid-body modes, unstable modes).
    title : str
        The model's title.

    Examples
    --------
    >>> import resonant
    >>> m = modes(resonant.load("examples/two_dof_free.toml").linearize())
    >>> m.natural_frequencies.round(6).tolist()
    [20.0, 34.641016]
    """

    coordinates: tuple[str, ...]
    omega_squared: np.ndarray
    natural_frequencies: np.ndarray
    mode_shapes: np.ndarray = saved(codec=ROWS, axes=("coordinates", "natural_frequencies"))
    mass_normalised_modes: np.ndarray = saved(codec=ROWS,
                                              axes=("coordinates", "natural_frequencies"))
    eigenvalues: np.ndarray = saved(codec=COMPLEX_PAIRS)
    damping_ratios: np.ndarray = saved()
    damped_frequencies: np.ndarray = saved()
    proportional_damping: bool = saved()
    rayleigh: tuple[float, float] | None = saved(codec=_RAYLEIGH)
    damped: bool = saved()
    stability: str = saved()
    method: str = "dense"
    warnings: tuple[str, ...] = ()
    title: str = ""
    frequency_errors: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        freeze_fields(self)

    def _derived_json(self) -> dict[str, Any]:
        return {"frequencies_hz": self.frequencies_hz.tolist(),
                "overdamped": self.overdamped.tolist()}

    @property
    def frequencies_hz(self) -> np.ndarray:
        return self.natural_frequencies / (2 * math.pi)

    def limited(self, count: int | None) -> ModalAnalysis:
        """The analysis restricted to the lowest ``count`` modes (dense path with --count)."""
        if count is None or count >= len(self.omega_squared):
            return self
        keep = int(np.sum(self.omega_squared[:count] >= 0))
        per_mode = len(self.damping_ratios) == len(self.natural_frequencies)
        eig = self.eigenvalues
        zeta = self.damping_ratios[:keep if per_mode else count]
        damped = self.damped_frequencies[:keep if per_mode else count]
        if self.proportional_damping:
            # two eigenvalues per kept mode: those of the modes' quadratic factors
            eig = eig[np.argsort(np.abs(eig), kind="stable")][:2 * count]
        else:
            # the count lowest by damped frequency; the overdamped ones counted apart
            zeta, damped = _underdamped_ratios(lowest_by_frequency(eig, count))
        return replace(self, omega_squared=self.omega_squared[:count],
                       natural_frequencies=self.natural_frequencies[:keep],
                       mode_shapes=self.mode_shapes[:, :keep],
                       mass_normalised_modes=self.mass_normalised_modes[:, :keep],
                       frequency_errors=self.frequency_errors[:keep],
                       eigenvalues=eig, damping_ratios=zeta, damped_frequencies=damped)

    @property
    def overdamped(self) -> np.ndarray:
        """The real eigenvalues among ``eigenvalues`` (overdamped modes, damping ratio 1 or
        more), in the one order: counted apart from the complex modes."""
        result: np.ndarray = self.eigenvalues[overdamped(self.eigenvalues)].real
        return result

    def _repr_html_(self) -> str:
        head = "".join(f"<th>{html.escape(q)}</th>" for q in self.coordinates[:12])
        rows = []
        for j, w in enumerate(self.natural_frequencies):
            zeta = (f"{self.damping_ratios[j]:.4g}" if self.proportional_damping and
                    j < len(self.damping_ratios) else "")
            shape = "".join(f"<td>{v:.4g}</td>" for v in self.mode_shapes[:12, j])
            rows.append(f"<tr><td>{j + 1}</td><td>{w:.6g}</td><td>{w / (2 * math.pi):.6g}</td>"
                        f"<td>{zeta}</td>{shape}</tr>")
        return (f"<p><b>Modes</b> ({html.escape(self.stability)}"
                f"{', proportional damping' if self.damped and self.proportional_damping else ''}"
                f")</p><table><tr><th>mode</th><th>&omega; [rad/s]</th><th>f [Hz]</th>"
                f"<th>&zeta;</th>{head}</tr>{''.join(rows)}</table>")

    def _repr_latex_(self) -> str:
        freqs = r",\ ".join(f"{w:.6g}" for w in self.natural_frequencies[:12])
        return rf"$\omega_j = {freqs}\ \mathrm{{rad/s}}$"

    def chart(self, count: int | None = 6) -> Charts:
        """The figure's description: each mode shape in a panel of its own
        (:func:`modes_chart`).

        Parameters
        ----------
        count : int or None
            The lowest modes to draw (None: all).

        Returns
        -------
        resonant.charts.Charts
        """
        return modes_chart(self, count)

    def plot(self, path: str | os.PathLike[str] | None = None, count: int | None = 6,
             ax: Axes | None = None) -> Figure:
        """The mode shapes (:func:`resonant.analyses.modes.plot_modes`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        count : int, optional
            How many modes to draw, lowest first (default 6, as ``resonant modes
            --plot`` draws; None: all).
        ax : matplotlib.axes.Axes, optional
            Draw into the caller's axes.

        Returns
        -------
        matplotlib.figure.Figure

        Examples
        --------
        >>> import resonant
        >>> fig = resonant.load("examples/two_dof_free.toml").linearize().modes().plot()
        >>> len(fig.axes) >= 1
        True
        """
        return plot_modes(self, path=path, count=count, ax=ax)

    def summary(self, units: ResultUnits | None = None) -> str:
        """The text ``resonant modes`` prints (:func:`resonant.analyses.modes.modes_text`).

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (:mod:`resonant.model.units_display`); Hz by default.

        Returns
        -------
        str

        Examples
        --------
        >>> import resonant
        >>> m = resonant.load("examples/two_dof_free.toml").linearize().modes()
        >>> "mode" in m.summary().lower()
        True
        """
        return modes_text(self, units)


# -- the numeric system ---------------------------------------------------------------------

def _is_sparse(a: Matrix) -> TypeGuard[spmatrix | sparray]:
    return hasattr(a, "tocsr")


def _symmetric(a: Matrix) -> bool:
    if _is_sparse(a):
        diff = abs(a - a.T)
        return bool(diff.nnz == 0 or diff.max() <= 1e-12 * abs(a).max())
    return bool(np.allclose(a, a.T, rtol=1e-12, atol=1e-12 * (np.abs(a).max() if a.size else 0)))


def _commutes(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> bool:
    """Caughey & O'Kelly: C M^-1 K = K M^-1 C."""
    minv_k = np.linalg.solve(M, K)
    minv_c = np.linalg.solve(M, C)
    scale = np.linalg.norm(C) * np.linalg.norm(minv_k) + 1e-300
    return bool(np.linalg.norm(C @ minv_k - K @ minv_c) <= PROPORTIONAL_TOLERANCE * scale)


def _normalise(phi: np.ndarray, M: Matrix) -> tuple[np.ndarray, np.ndarray]:
    """(mass-normalised, largest component +1) versions of the columns of phi."""
    phi = np.array(phi, dtype=float)
    mass = np.einsum("ij,ij->j", phi, M @ phi)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(mass > 0, 1 / np.sqrt(np.abs(mass)), 1 / np.linalg.norm(phi, axis=0))
    phi = phi * scale
    if phi.size:
        big = phi[np.argmax(np.abs(phi), axis=0), np.arange(phi.shape[1])]
        # tiny components are rounding noise of exact zeros: clean them in the +1 view
        unit = phi / big
        unit[np.abs(unit) < 1e-13] = 0.0
        phi = phi * np.sign(big)
    else:
        unit = phi
    return phi, unit


def _modal_eigenvalues(lam: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Both roots of s^2 + c s + lambda = 0 for every mode."""
    root = np.sqrt((c * c - 4 * lam).astype(complex))
    return np.concatenate([(-c + root) / 2, (-c - root) / 2])


# -- the analysis -------------------------------------------------------------------------

def modes(system: LinearSystem, count: int | None = None,
          deadline: Deadline = NO_DEADLINE) -> ModalAnalysis:
    """Natural frequencies, mode shapes, damping and stability of a linear system.

    Parameters
    ----------
    system : LinearSystem
    count : int, optional
        Report only the ``count`` lowest modes.  For sparse matrices with
        ``count < n - 1`` (and for any model larger than 1500 coordinates)
        they are computed by shift-invert Lanczos; the default then is 10.
    deadline : Deadline, optional
        The run's time limit.

    Returns
    -------
    ModalAnalysis

    Raises
    ------
    AnalysisError
        For a singular mass matrix or a non-positive ``count``.

    Examples
    --------
    >>> import resonant
    >>> modes(resonant.load("examples/two_dof_free.toml").linearize()).natural_frequencies.round(
    ...     3).tolist()
    [20.0, 34.641]
    """
    if count is not None and count < 1:
        raise AnalysisError(f"count must be at least 1, not {count}")
    eom = system.numeric(deadline)
    coordinates, M, C, K = eom.coordinates, eom.M, eom.C, eom.K
    n = len(coordinates)
    warnings: list[str] = []
    damped = bool((C.nnz and abs(C).max() > 0) if _is_sparse(C) else np.any(C))
    symmetric = _symmetric(M) and _symmetric(K) and _symmetric(C)
    sparse = any(_is_sparse(a) for a in (M, C, K))
    lanczos = n > DENSE_MODES or (sparse and count is not None and count < n - 1)
    if lanczos:
        if count is None:
            count = 10
            warnings.append(f"{n} coordinates: only the lowest {count} modes are computed "
                            "(use --count)")
        count = min(count, n - 1)
        lam, phi, bounds = _lanczos(M, K, count)
        method = "shift-invert Lanczos"
    else:
        M, C, K = dense_matrix(M), dense_matrix(C), dense_matrix(K)
        check_mass_matrix(M, coordinates)
        lam, phi = undamped_eigen(M, K)
        bounds = _dense_bounds(M, K, lam, phi)
        method = "dense"
    lam = stiffness_eigenvalues(lam, K)
    errors = _frequency_errors(lam, bounds, warnings)
    mass_phi, unit_phi = _normalise(phi, M)
    fit = rayleigh(M, C, K) if damped and symmetric else (0.0, 0.0) if not damped else None
    proportional = _is_proportional(M, C, K, mass_phi, damped, symmetric, lanczos, fit)
    if not symmetric:
        warnings.append("M, C or K is not symmetric (gyroscopic or circulatory terms): the "
                        "undamped modes are those of the symmetric problem K phi = lambda M phi "
                        "as computed by a general eigensolver; see the complex eigenvalues")
    eigenvalues, damping_ratios, damped_freq, extra = _damped_modes(
        M, C, K, lam, mass_phi, damped, proportional and symmetric, lanczos, warnings)
    stability = _modal_stability(order(eigenvalues), lam, (M, C, K), damped, lanczos, warnings)
    keep = lam >= 0
    return ModalAnalysis(
        coordinates=coordinates, omega_squared=lam, natural_frequencies=np.sqrt(lam[keep]),
        mode_shapes=unit_phi[:, keep], mass_normalised_modes=mass_phi[:, keep],
        eigenvalues=order(eigenvalues),
        damping_ratios=np.asarray(damping_ratios), damped_frequencies=np.asarray(damped_freq),
        proportional_damping=bool(proportional), rayleigh=fit, damped=damped,
        stability=stability, method=method + extra, warnings=tuple(warnings),
        title=eom.title, frequency_errors=errors).limited(count if not lanczos else None)


def _is_proportional(M: Matrix, C: Matrix, K: Matrix, mass_phi: np.ndarray, damped: bool,
                     symmetric: bool, lanczos: bool, fit: tuple[float, float] | None) -> bool:
    """Whether C is diagonal in the undamped modes (Rayleigh fit, commuting matrices, or,
    for a large model, the modal damping matrix of the computed modes)."""
    if not damped or fit is not None:
        return True
    if symmetric and not lanczos:
        return bool(_commutes(M, C, K))
    if not (symmetric and lanczos):
        return False
    # compensated: C phi cancels for the smooth modes of a stiff structure (C = a M + b K)
    modal_c = mass_phi.T @ accurate_product(C, mass_phi)
    off = modal_c - np.diag(np.diag(modal_c))
    return bool(np.abs(off).max(initial=0) <= PROPORTIONAL_TOLERANCE *
                np.abs(np.diag(modal_c)).max(initial=1e-300))


def _damped_modes(M: Matrix, C: Matrix, K: Matrix, lam: np.ndarray, mass_phi: np.ndarray,
                  damped: bool, modal: bool, lanczos: bool, warnings: list[str]
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """(eigenvalues, damping ratios, damped frequencies, what was added to the method):
    from the undamped modes where the damping is modal, else from the state-space
    eigenproblem (dense, or by sparse shift-invert for a large model)."""
    if modal:
        c_modal = np.zeros(len(lam))
        if damped:
            c_phi = accurate_product(C, mass_phi) if lanczos else np.asarray(C @ mass_phi)
            c_modal = np.einsum("ij,ij->j", mass_phi, c_phi)
        ok = lam > 0
        zeta = np.where(ok, c_modal / (2 * np.sqrt(np.where(ok, lam, 1.0))), 0.0)
        damped_freq = np.sqrt(np.maximum(lam - c_modal**2 / 4, 0.0))[lam >= 0]
        return _modal_eigenvalues(lam, c_modal), zeta[lam >= 0], damped_freq, ""
    if not lanczos:
        eigenvalues = point_state_eigenvalues(M, C, K)
        return (eigenvalues, *damping_ratios(eigenvalues), "")
    search = lowest_state_eigenvalues(M, C, K, len(lam))
    zeta, damped_freq = _underdamped_ratios(search.eigenvalues)
    if not search.complete:
        warnings.append(f"only {zeta.size} of the {len(lam)} complex modes asked for were "
                        f"found within {search.shifts.size} shifts of the eigensolver")
    if zeta.size and search.reach < min(1.0, 1.5 * float(np.max(zeta))):
        warnings.append(
            f"complex modes with a damping ratio above {search.reach:.2g} and a damped "
            f"frequency below {float(np.max(damped_freq)):.6g} rad/s lie outside the "
            "region searched and may be missing (a larger --count widens it)")
    return (search.eigenvalues, zeta, damped_freq, " + shift-invert Arnoldi (complex modes)")


def _underdamped_ratios(eigenvalues: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Damping ratios and damped frequencies of the eigenvalues that are not overdamped."""
    return damping_ratios(eigenvalues[~overdamped(eigenvalues)])


def _modal_stability(eigenvalues: np.ndarray, lam: np.ndarray,
                     matrices: tuple[Matrix, Matrix, Matrix], damped: bool, lanczos: bool,
                     warnings: list[str]) -> str:
    """The stability verdict, with the warnings that qualify it."""
    M = matrices[0]
    stability = definite_stability(eigenvalues, *matrices)
    if lanczos:
        warnings.append(f"stability judged from the lowest {len(lam)} modes only")
        if stability == ASYMPTOTIC and not damped:
            stability = MARGINAL
    negative_mass = mass_warning(M) if isinstance(M, np.ndarray) else None
    if negative_mass:
        warnings.append(negative_mass)
    if np.any(lam < 0):
        warnings.append(f"{int(np.sum(lam < 0))} mode(s) with omega^2 < 0: " + (
            "M is not positive definite (see above)" if negative_mass else
            "K is not positive definite (statically unstable)"))
        stability = UNSTABLE if stability != UNSTABLE and not damped else stability
    return stability


def _lanczos(M: Matrix, K: Matrix, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ``count`` lowest eigenpairs of K phi = lambda M phi (sparse, symmetric) and the
    error bounds of their eigenvalues."""
    if not (_symmetric(M) and _symmetric(K)):
        raise AnalysisError("the sparse eigensolver needs symmetric M and K; this model has "
                            "gyroscopic or circulatory terms")
    if np.any(M.diagonal() == 0):
        raise AnalysisError("the mass matrix M has a zero diagonal entry (a coordinate without "
                            "inertia): M is singular")
    return lowest_modes(M, K, count)


def _dense_bounds(M: np.ndarray, K: np.ndarray, lam: np.ndarray, phi: np.ndarray
                  ) -> np.ndarray:
    """The error bounds of the eigenvalues of the dense route (NaN where the pencil is
    not symmetric positive definite)."""
    if not (_symmetric(M) and _symmetric(K)) or mass_warning(M) is not None:
        return np.full(len(lam), np.nan)
    try:
        return eigenvalue_bounds(M, K, lam, phi, accurate=False)
    except (np.linalg.LinAlgError, ValueError):
        return np.full(len(lam), np.nan)


def _frequency_errors(lam: np.ndarray, bounds: np.ndarray, warnings: list[str]) -> np.ndarray:
    """Bounds on the errors of the natural frequencies (the modes with lambda >= 0), and a
    warning where the conditioning limits them."""
    keep = lam >= 0
    errors = frequency_bounds(lam[keep], bounds[keep])
    omega = np.sqrt(lam[keep])
    with np.errstate(invalid="ignore", divide="ignore"):
        relative = errors / np.where(omega > 0, omega, np.inf)
    limited = np.nonzero(relative > LIMITED_ACCURACY)[0]
    if limited.size:
        j = int(limited[np.argmax(relative[limited])])
        warnings.append(
            f"the conditioning of M and K limits the accuracy of {limited.size} natural "
            f"frequenc{'y' if limited.size == 1 else 'ies'}: mode {j + 1} "
            f"({omega[j]:.10g} rad/s) is accurate to {errors[j]:.2g} rad/s (relative "
            f"{relative[j]:.1g}), a bound from its residual")
    return errors


def modal_damping_ratios(rayleigh: tuple[float, float], omegas: Sequence[float] | np.ndarray
                         ) -> np.ndarray:
    """zeta_j = a / (2 omega_j) + b omega_j / 2 for Rayleigh damping C = a M + b K.

    Examples
    --------
    >>> modal_damping_ratios((0.1, 1e-4), [10.0]).round(6).tolist()
    [0.0055]
    """
    a, b = rayleigh
    w = np.asarray(omegas, dtype=float)
    return a / (2 * w) + b * w / 2


def modes_chart(analysis: ModalAnalysis, count: int | None = 6) -> Charts:
    """What the figure of the mode shapes shows: each mode (largest component +1) in a
    panel of its own, bars for up to 24 coordinates (positive blue, negative red) under
    the coordinates' names, a line for more.

    Parameters
    ----------
    analysis : ModalAnalysis
        The modes (those with omega^2 >= 0).
    count : int, optional
        How many modes, lowest first (default 6; None: all).

    Returns
    -------
    Charts

    Raises
    ------
    AnalysisError
        Without modes to draw.
    """
    shapes = analysis.mode_shapes
    total = shapes.shape[1]
    if total == 0:
        raise AnalysisError("there are no modes with omega^2 >= 0 to plot")
    count = total if count is None else max(1, min(count, total))
    panels = []
    for j in range(count):
        shape = np.asarray(shapes[:, j], dtype=float)
        n = shape.shape[0]
        positions = np.arange(1, n + 1, dtype=float)
        w = analysis.natural_frequencies[j]
        text = (f"mode {j + 1}: $\\omega_{{{j + 1}}}$ = {w:.5g} rad/s "
                f"($f_{{{j + 1}}}$ = {w / (2 * math.pi):.4g} Hz)")
        if analysis.proportional_damping and analysis.damped and \
                j < len(analysis.damping_ratios):
            text += f", $\\zeta_{{{j + 1}}}$ = {analysis.damping_ratios[j]:.3g}"
        zero = Rule(0.0, vertical=False, color="#000000", width=0.6)
        if n <= 24:
            colors = tuple(COLORS[0] if v >= 0 else COLORS[3] for v in shape)
            panels.append(Chart((), "", "", (0.4, n + 0.6), rules=(zero,), ylim=(-1.15, 1.15),
                                title=text, legend="none",
                                bars=(Bar(positions, shape, colors),),
                                xticks=tuple((float(p), dollar_name(c)) for p, c in
                                             zip(positions, analysis.coordinates))))
        else:
            panels.append(Chart((Curve(positions, shape, "", COLORS[0], 1.2),),
                                "coordinate number", "", (1.0, float(n)), rules=(zero,),
                                ylim=(-1.15, 1.15), title=text, legend="none"))
    columns = 2 if count > 1 else 1
    rows = math.ceil(count / columns)
    return Charts(tuple(panels), printable(analysis.title or "mode shapes", limit=80)
                  + " (largest component +1)", size=(4.9 * columns, 2.5 * rows),
                  sharex=False, columns=columns)


def plot_modes(analysis: ModalAnalysis, path: PathArg = None, count: int | None = 6,
               ax: Axes | None = None) -> Figure:
    """The mode shapes (largest component +1): the chart of :func:`modes_chart` (bars for
    few coordinates, lines for many), drawn with matplotlib.

    Parameters
    ----------
    analysis : ModalAnalysis
        The modes to draw (those with omega^2 >= 0).
    path : str or Path, optional
        Also write the figure there; the format follows the suffix (``.png``,
        ``.svg`` or ``.pdf``, anything else raises :class:`AnalysisError`).
    count : int, optional
        How many modes to draw, lowest first (default 6; None: all).
    ax : matplotlib.axes.Axes or sequence of Axes, optional
        Draw into the caller's figure: one mode per Axes (a single Axes shows
        the first mode), at most ``count``.  By default a new figure with a
        grid of two columns is made.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the one ``ax`` belongs to.

    Raises
    ------
    AnalysisError
        Without modes to draw, or for an unsupported file suffix.
    """
    check_plot_path(path)
    charts = modes_chart(analysis, count)
    axes = None
    if ax is not None:
        axes = list(np.ravel(np.asarray(ax, dtype=object)))
        if not axes:
            raise AnalysisError("ax= takes an Axes or a non-empty sequence of Axes")
    fig = draw_figure(charts, axes)
    save_figure(fig, path, bbox_inches="tight")
    return fig


def _mode_table(result: ModalAnalysis, frequency: Shown) -> ResultTable:
    """Frequency, damping ratio and shape of every mode, each column in one notation."""
    per_mode = result.proportional_damping
    shown = min(8, len(result.coordinates))
    count = len(result.natural_frequencies)
    zetas = [float(result.damping_ratios[j]) if per_mode and j < len(result.damping_ratios)
             else None for j in range(count)]
    columns = [tuple(str(j + 1) for j in range(count)),
               number_column(result.natural_frequencies.tolist(), 6),
               number_column([float(frequency(w)) for w in result.natural_frequencies], 6),
               tuple("" if z is None else number_cell(z, 4) for z in zetas)]
    columns += [number_column([float(v) for v in result.mode_shapes[i, :count]], 4)
                for i in range(shown)]
    header = ("mode", "omega [rad/s]", f"f [{frequency.text}]", "zeta",
              *(printable(c, limit=12) for c in result.coordinates[:shown]))
    rows = tuple(zip(*columns)) if count else ()
    return ResultTable(header, rows, align="r" * len(header))


def _complex_mode_lines(eigenvalues: np.ndarray) -> list[str]:
    """The complex modes of lowest damped frequency (up to 20, in the one order), and the
    overdamped (real) eigenvalues counted apart on a line of their own."""
    real = overdamped(eigenvalues)
    shown = lowest_by_frequency(eigenvalues[~real], 20)
    out = ["non-proportional damping: eigenvalues s of the state matrix",
           f"{'Re s':>14}  {'Im s':>14}  {'zeta':>8}"]
    for s in shown[:2 * 20]:
        if s.imag >= 0:
            ratio = -s.real / abs(s) if abs(s) else 0.0
            out.append(f"{s.real:14.6g}  {s.imag:14.6g}  {ratio:8.4g}")
    if np.any(real):
        values = np.sort(eigenvalues[real].real)
        out.append(f"and {values.size} overdamped mode{'s' if values.size > 1 else ''} (real "
                   f"s from {values[-1]:.6g} to {values[0]:.6g}, zeta >= 1; not listed)")
    return out


def modes_text(result: ModalAnalysis, units: ResultUnits | None = None) -> str:
    """The human-readable table of ``resonant modes``; the second frequency column is in
    the display unit of frequencies (``units.frequency``, Hz by default)."""
    out = [printable(result.title or "modes"), ""]
    names = result.coordinates
    shown = ", ".join(names[:8]) + (" ..." if len(names) > 8 else "")
    frequency = units.frequency if units is not None and units.frequency.text != "rad/s" \
        else HZ
    out.append(f"mode shapes (largest component +1) over {shown}:")
    out.append(_mode_table(result, frequency).text(indent=""))
    if result.damped:
        out.append("")
        if result.rayleigh is not None and len(names) <= 2:
            # with two coordinates every C that commutes with M^-1 K is some a M + b K:
            # the fit says nothing about the damping, the modal ratios do
            out.append("proportional damping: the modes decouple C (with two coordinates "
                       "every such C is a M + b K); modal damping ratios: " + ", ".join(
                           f"zeta_{j + 1} = {z:.4g}"
                           for j, z in enumerate(result.damping_ratios)))
        elif result.rayleigh is not None:
            a, b = result.rayleigh
            out.append(f"proportional (Rayleigh) damping: C = {a:.6g} M + {b:.6g} K")
        elif result.proportional_damping:
            out.append("proportional damping (K M^-1 C = C M^-1 K): the modes decouple C")
        else:
            out.extend(_complex_mode_lines(result.eigenvalues))
    out.append("")
    out.append(f"stability: {result.stability}   (method: {result.method})")
    return "\n".join(out) + "\n"


__all__ = ["plot_modes", "modes_chart", "modes", "ModalAnalysis", "modal_damping_ratios"]
