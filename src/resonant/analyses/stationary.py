"""Stage 3: the stationary (steady-state) solution for harmonic excitation.

For each excitation frequency w the particular solution
q_p = L cos(w t) + N sin(w t) solves (reference exercise, Eq. (38))::

    [ K - w^2 M    w C      ] [L]   [F_C]
    [ -w C         K - w^2 M] [N] = [F_S]

solved here in its complex form (K - w^2 M + i w C)(L - i N) = F_C - i F_S.

Examples
--------
>>> import numpy as np
>>> from resonant.system import NumericEOM, NumericHarmonic
>>> eom = NumericEOM(("x",), np.eye(1), np.zeros((1, 1)), 4 * np.eye(1),
...                  (NumericHarmonic(1.0, np.array([3.0]), np.array([0.0])),))
>>> sol = stationary(eom)
>>> sol.harmonics[0].N, sol.amplitudes["x"]
(array([1.]), 1.0)
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from fractions import Fraction
from functools import reduce
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy

from ..arrays import freeze_fields, frozen_array
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, printable
from ..expressions.mathml import latex_to_mathml
from ..expressions.notation import number_latex, vector_latex
from ..modal import point_state_eigenvalues
from ..model.units_display import HZ, ResultUnits, result_units, shown_vector, uniform, units_grid
from ..system.base import LinearSystem, NumericEOM, NumericHarmonic
from ..system.batch import check_finite
from ..system.output_map import output_map
from ..system.stability import (
    UNSTABLE,
    mass_warning,
    rayleigh,
    stiffness_eigenvalues,
    undamped_eigen,
    undamped_eigenvalues,
)
from ..system.stability import (
    stability as definite_stability,
)
from ..tables import ResultTable, number_cell
from .forward_error import DIGITS_WANTED, ERROR_LIMIT
from .kernel import (
    LOSS_CONDITION,
    KernelResult,
    check_batch_mass,
    equilibration,
    solve_harmonic,
)
from .result_fields import COMPLEX_PAIRS, Codec, FieldsJSON, saved
from .results_json import Saved
from .threads import blas_threads

if TYPE_CHECKING:
    pass

NEAR_RESONANCE = 0.02       # relative distance to a natural frequency that earns a warning
#: above this many coordinates (or with sparse matrices) the eigenvalues come from the
#: undamped ones where the damping allows (no dense 2n x 2n problem) and solves are sparse
LARGE = 200
#: largest system whose stationary solution (with all eigenvalues) is computed
DENSE_LIMIT = 4000
#: largest system whose mass matrix is checked for positive definiteness (dense eigenvalues)
EXACT_MASS_CHECK = 1500
#: samples of the common period in :func:`peak` (several commensurate frequencies); the
#: largest PEAK_CANDIDATES samples are then refined by a golden-section search each
MAX_PEAK_SAMPLES = 20_000
PEAK_CANDIDATES = 16


@dataclass(frozen=True)
class HarmonicResponse(FieldsJSON):
    """The response at one frequency: x = L cos(omega t) + N sin(omega t).

    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`) but the
    condition number of the solve, which is not saved.
    """

    omega: float
    F_S: np.ndarray
    F_C: np.ndarray
    L: np.ndarray
    N: np.ndarray
    condition: float = saved(1.0, written=False)

    def __post_init__(self) -> None:
        freeze_fields(self)


def _eom_write(e: NumericEOM) -> dict[str, Any]:
    data: dict[str, Any] = {"title": e.title, "coordinates": list(e.coordinates),
                            "parameters": dict(e.parameters),
                            "M": e.M.tolist(), "C": e.C.tolist(), "K": e.K.tolist()}
    symbolic = e.symbolic_dict()
    if symbolic:
        data["symbolic"] = symbolic
        data["symbolic"].pop("coordinates", None)
    return data


def _eom_read(saved_data: Saved, key: str, shape: object) -> NumericEOM:
    """The equation's numbers (its excitation is completed from the saved responses)."""
    coordinates = saved_data.strings("coordinates")
    n = len(coordinates)
    M, C, K = (saved_data.floats(k, shape=(n, n)) for k in ("M", "C", "K"))
    return NumericEOM(coordinates=coordinates, M=M, C=C, K=K,
                      parameters=saved_data.numbers_of("parameters", {}),
                      title_=saved_data.string("title", ""))


#: the equation of motion's numbers beside the solution's keys (its symbolic form, text for
#: a reader, is written and not read back)
EOM_KEYS = Codec(_eom_write, _eom_read)


@dataclass(frozen=True)
class StationarySolution(FieldsJSON):
    """The stationary solution of a harmonically excited linear system.

    Attributes
    ----------
    harmonics : tuple of HarmonicResponse
        One per excitation frequency (L and N of the coordinates).
    output_harmonics : mapping
        ``name -> [(L, N), ...]`` per frequency, for coordinates and outputs.
    amplitudes, phases : mapping
        Peak absolute deviation, and delta = atan2(L, N) (single frequency only).
    eom : NumericEOM
        The numbers the solution was computed from.
    natural_frequencies : ndarray
        The undamped natural frequencies (rad/s), ascending.
    eigenvalues : ndarray
        The eigenvalues of the state matrix.
    stability : str
        ``"asymptotically stable"``, ``"marginally stable"`` or ``"unstable"``.
    warnings : tuple of str
        What the user should know (near resonance, no equilibrium ...).
    available : bool
        False when there is no stationary solution (then only the eigenvalues).

    Examples
    --------
    >>> import resonant
    >>> sol = stationary(resonant.load("examples/cart_pendulum.toml").linearize())
    >>> sol.natural_frequencies.round(6).tolist(), sol.stability
    ([4.560711, 7.929966], 'marginally stable')

    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`: the JSON of
    ``resonant solve``): the equation of motion comes back with its numbers (``M``, ``C``,
    ``K``, the excitation's amplitudes per frequency, the parameters) and every response,
    the outputs' ones included (``output_harmonics``); its symbolic form (``symbolic``,
    text for a reader) is not read back.

    >>> import json
    >>> back = StationarySolution.from_dict(json.loads(json.dumps(sol.to_dict())))
    >>> back.amplitudes == sol.amplitudes
    True
    >>> saved = sol.to_dict()
    >>> del saved["symbolic"]
    >>> back.to_dict() == saved
    True
    """

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): the equation's
    #: numbers (``symbolic`` where derived), then the solution
    _json_order = ("title", "coordinates", "parameters", "M", "C", "K", "symbolic",
                   "natural_frequencies", "harmonics", "amplitudes", "phases", "stability",
                   "eigenvalues", "stationary_available", "warnings", "output_harmonics")

    eom: NumericEOM = saved(codec=EOM_KEYS, inline=True)
    natural_frequencies: np.ndarray = saved(axes=(None,))
    eigenvalues: np.ndarray = saved(codec=COMPLEX_PAIRS)
    stability: str = saved()
    harmonics: tuple[HarmonicResponse, ...] = saved()
    output_harmonics: Mapping[str, tuple[tuple[float, float], ...]] = saved(
        axes=("harmonics", 2))
    amplitudes: Mapping[str, float] = saved()
    phases: Mapping[str, float] = saved()
    warnings: tuple[str, ...] = saved(())
    available: bool = saved(True, key="stationary_available")

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.output_harmonics)

    def response(self, t: np.ndarray | float) -> dict[str, np.ndarray]:
        """The stationary time history of every coordinate and output."""
        t = np.asarray(t, dtype=float)
        out = {}
        for name, pairs in self.output_harmonics.items():
            y = np.zeros_like(t)
            for h, (L, N) in zip(self.harmonics, pairs):
                y = y + L * np.cos(h.omega * t) + N * np.sin(h.omega * t)
            out[name] = y
        return out

    @classmethod
    def _check_saved(cls, values: dict[str, Any], saved_data: Saved) -> None:
        eom: NumericEOM = values["eom"]
        n = len(eom.coordinates)
        for i, h in enumerate(values["harmonics"]):
            for key in ("F_S", "F_C", "L", "N"):
                if np.shape(getattr(h, key)) != (n,):
                    raise saved_data.error(f"has {np.shape(getattr(h, key))} numbers, not "
                                           f"({n},): one per coordinate", f"harmonics[{i}].{key}")
        values["eom"] = replace(eom, harmonics=tuple(
            NumericHarmonic(h.omega, h.F_S, h.F_C) for h in values["harmonics"]))

    def summary(self) -> str:
        """The text ``resonant solve`` prints (:func:`resonant.analyses.stationary.solution_text`).

        Returns
        -------
        str

        Examples
        --------
        >>> import resonant
        >>> sol = resonant.load("examples/cart_pendulum.toml").linearize().stationary()
        >>> print(sol.summary().splitlines()[0].split("  (")[0])
        Cart with pendulum under force and support excitation
        """
        return solution_text(self)

    def _repr_html_(self) -> str:
        return stationary_html(self)

    def _repr_latex_(self) -> str:
        return stationary_latex(self)


def _output_pairs(eom: NumericEOM, responses: tuple[HarmonicResponse, ...]
                  ) -> dict[str, tuple[tuple[float, float], ...]]:
    """(L, N) of every coordinate and output at each frequency (z = L - i N)."""
    out: dict[str, tuple[tuple[float, float], ...]] = {
        q: tuple((float(r.L[i]), float(r.N[i])) for r in responses)
        for i, q in enumerate(eom.coordinates)}
    outputs = output_map(eom.outputs, eom.coordinates)
    y = [outputs.harmonic(r.omega, r.L - 1j * r.N,
                          {v: c - 1j * s for v, (s, c) in h.signals.items()})
         for r, h in zip(responses, eom.harmonics)]
    for j, name in enumerate(outputs.names):
        out[name] = tuple((float(each[j].real), float(-each[j].imag)) for each in y)
    return out


def common_period(omegas: list[float]) -> float | None:
    """The common period 2 pi q / w_min of frequencies with rational ratios p/q (q <= 1000),
    None when they are incommensurate.

    Examples
    --------
    >>> round(common_period([2.0, 3.0]), 12) == round(2 * math.pi, 12)
    True
    >>> common_period([1.0, math.sqrt(2)]) is None
    True
    """
    moving = [w for w in omegas if w > 0]
    if not moving:
        return None
    base = min(moving)
    fractions = [Fraction(w / base).limit_denominator(1000) for w in moving]
    if any(abs(float(f) - w / base) > 1e-9 * w / base for f, w in zip(fractions, moving)):
        return None
    denominator = reduce(math.lcm, (f.denominator for f in fractions), 1)
    return 2 * math.pi * denominator / base


def peak(omegas: list[float], pairs: tuple[tuple[float, float], ...]) -> float:
    """Peak |x(t)| of x = sum L_i cos(w_i t) + N_i sin(w_i t) (w = 0: constant L).

    Exact for one frequency; sampled and refined over the common period for
    commensurate frequencies; the supremum sum of amplitudes otherwise.
    """
    amps = [math.hypot(L, N) for L, N in pairs]
    active = [(w, L, N) for w, (L, N), a in zip(omegas, pairs, amps) if a > 0]
    if not active:
        return 0.0
    static = sum(L for w, L, N in active if w == 0)
    moving = [(w, L, N) for w, L, N in active if w > 0]
    if len(moving) <= 1:
        return abs(static) + sum(math.hypot(L, N) for _, L, N in moving)
    period = common_period([w for w, _, _ in moving])
    if period is None:
        return abs(static) + sum(math.hypot(L, N) for _, L, N in moving)
    highest = max(w for w, _, _ in moving)
    samples = int(min(MAX_PEAK_SAMPLES, max(4000, 200 * highest * period / (2 * math.pi))))
    t = np.linspace(0.0, period, samples, endpoint=False)
    ws = np.array([w for w, _, _ in moving])
    Ls = np.array([L for _, L, _ in moving])
    Ns = np.array([N for _, _, N in moving])

    def value(tt: np.ndarray) -> np.ndarray:
        result: np.ndarray = static + np.cos(np.outer(tt, ws)) @ Ls + np.sin(np.outer(tt, ws)) @ Ns
        return result

    y = np.abs(value(t))
    best = float(y.max())
    # refine the largest samples by a local golden-section search each (all at once): with
    # fewer samples than 200 per cycle of the highest frequency the top sample may lie
    # beside a lower local maximum, so several candidates are refined
    top = np.argsort(y)[-PEAK_CANDIDATES:]
    step = period / samples
    a, b = t[top] - step, t[top] + step
    g = (math.sqrt(5) - 1) / 2
    for _ in range(60):
        c, d = b - g * (b - a), a + g * (b - a)
        left = np.abs(value(c)) > np.abs(value(d))
        b = np.where(left, d, b)
        a = np.where(left, a, c)
    return max(best, float(np.abs(value((a + b) / 2)).max()))


def phase_angle(L: float, N: float) -> float:
    """delta = atan2(L, N) in (-pi, pi]: -pi is written as pi, -0 as 0.

    Examples
    --------
    >>> phase_angle(-0.0, -1.0), phase_angle(-0.0, 1.0)
    (3.141592653589793, 0.0)
    """
    delta = math.atan2(L, N) + 0.0
    return math.pi if delta <= -math.pi else delta


def system_warnings(lam: np.ndarray, stability: str, mass_definite: bool = True) -> list[str]:
    """Warnings about the system itself: an indefinite K, an unstable equilibrium."""
    out = []
    if np.any(lam < -1e-12 * max(1.0, float(np.abs(lam).max(initial=0.0)))) and not mass_definite:
        out.append("omega^2 < 0 for some mode because M is not positive definite (see above), "
                   "not necessarily because of K")
    elif np.any(lam < -1e-12 * max(1.0, float(np.abs(lam).max(initial=0.0)))):
        out.append("K is not positive definite about this reference state: a statically "
                   "unstable (buckling, inverted) mode exists")
    if stability == UNSTABLE:
        out.append("the equilibrium is unstable: free vibrations grow, so the stationary "
                   "solution is never reached in practice")
    return out


def resonance_warnings(excitation: list[float], omegas: np.ndarray) -> list[str]:
    """A warning for each excitation frequency within NEAR_RESONANCE of a natural one."""
    out = []
    for w in excitation:
        for i, wn in enumerate(omegas):
            if w > 0 and wn > 0 and abs(w - wn) <= NEAR_RESONANCE * wn:
                out.append(
                    f"near resonance: the excitation frequency {w:.6g} rad/s is within "
                    f"{100 * abs(w - wn) / wn:.2g}% of natural frequency {i + 1} "
                    f"({wn:.6g} rad/s); the amplitudes are sensitive to the data")
    return out


def stationary(system: LinearSystem, deadline: Deadline = NO_DEADLINE,
               **overrides: float | str) -> StationarySolution:
    """Solve for the stationary response of every coordinate and output.

    Parameters
    ----------
    system : LinearSystem
        The system (its numbers are taken at the model's parameter values).
    deadline : Deadline, optional
    **overrides
        Parameter values replacing the model's.

    Returns
    -------
    StationarySolution

    Raises
    ------
    AnalysisError
        For a singular mass matrix, or an undamped system excited exactly at a
        natural frequency (exit status 3).

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> round(stationary(eom).amplitudes["x2"], 5), stationary(eom, k=120).eom.parameters["k"]
    (0.04514, 120.0)
    """
    eom = system.numeric(deadline, **overrides)
    large = eom.n > LARGE
    if eom.n > DENSE_LIMIT:
        raise AnalysisError(
            f"the model has {eom.n} coordinates; the stationary solution with all natural "
            f"frequencies and eigenvalues is limited to {DENSE_LIMIT}: use `modes` with a "
            "count and `sweep`, which work with sparse matrices")
    sparse_eom, eom = eom, eom.dense()  # the solution reports dense matrices
    batch = (sparse_eom if large else eom).constant_batch(1)
    check_batch_mass(batch)
    warnings = _mass_warnings(eom)
    deadline.check("while computing the eigenvalues", analysis=True)
    with blas_threads(8.0 * float(eom.n) ** 3):  # no more threads than idle cores
        lam, eigenvalues = _eigenvalues(sparse_eom, eom, large)
    lam = stiffness_eigenvalues(lam, eom.K)  # (round-off zeros 0 unless K is definite)
    omegas = np.sqrt(lam[lam >= 0])
    stability = definite_stability(eigenvalues, eom.M, eom.C, eom.K)
    warnings += system_warnings(lam, stability, mass_definite=not _negative_mass(eom))
    if not eom.harmonic:
        warnings.append("the stationary solution needs signals that are sums of harmonics "
                        "(sin/cos of a*t + b, constants); the equation of motion is derived, "
                        "use `resonant simulate` for other signals")
        return StationarySolution(eom, omegas, eigenvalues, stability, (),
                                  MappingProxyType({}), MappingProxyType({}),
                                  MappingProxyType({}), tuple(warnings), available=False)
    warnings += resonance_warnings([h.omega for h in eom.harmonics], omegas)
    method = "sparse" if large else "dense"
    responses = tuple(_response(h, solve_harmonic(batch, bh, method, deadline=deadline),
                                omegas, warnings)
                      for h, bh in zip(eom.harmonics, batch.harmonics))
    pairs = _output_pairs(eom, responses)
    amplitudes, phases = _amplitudes_and_phases(pairs, [r.omega for r in responses])
    return StationarySolution(eom, omegas, eigenvalues, stability, responses,
                              MappingProxyType(pairs), MappingProxyType(amplitudes),
                              MappingProxyType(phases), tuple(warnings))


def _negative_mass(eom: NumericEOM) -> str | None:
    """The warning of a mass matrix that is not positive definite (small models only)."""
    return mass_warning(eom.M) if eom.n <= EXACT_MASS_CHECK else None


def _mass_warnings(eom: NumericEOM) -> list[str]:
    """Warnings about M: not positive definite, nearly singular (digits lost)."""
    warnings: list[str] = []
    negative_mass = _negative_mass(eom)
    if negative_mass:
        warnings.append(negative_mass)
    check_finite("M, C, K", np.concatenate([eom.M.ravel(), eom.C.ravel(), eom.K.ravel()]))
    if 0 < eom.n <= 1500:
        row, col = equilibration(eom.M)
        try:
            mass_condition = float(np.linalg.cond(row[:, None] * eom.M * col[None, :]))
        except np.linalg.LinAlgError:  # the SVD failed: entries beyond double precision
            raise AnalysisError("the mass matrix M cannot be analysed: its entries lie beyond "
                                "the range of double precision (subnormal or huge values); "
                                "rescale the units") from None
        if mass_condition > LOSS_CONDITION:
            warnings.append(
                f"the mass matrix M is nearly singular (condition number {mass_condition:.2g}"
                f" after scaling): about {int(math.log10(mass_condition))} of 16 digits of "
                "the natural frequencies and amplitudes are lost; is a mass nearly zero?")
    return warnings


def _eigenvalues(sparse: NumericEOM, dense: NumericEOM, large: bool
                 ) -> tuple[np.ndarray, np.ndarray]:
    """(undamped eigenvalues w², state-space eigenvalues) of the system, given as it was
    made (``sparse``) and dense.

    A large model with proportional damping gets its damped eigenvalues from the
    undamped ones, without the 2n x 2n problem.
    """
    if not large:
        lam, _ = undamped_eigen(dense.M, dense.K)
        return lam, point_state_eigenvalues(dense.M, dense.C, dense.K)
    lam = undamped_eigenvalues(sparse.M, sparse.K)
    proportional = rayleigh(sparse.M, sparse.C, sparse.K) if np.any(dense.C) else (0.0, 0.0)
    if proportional is None:
        return lam, point_state_eigenvalues(dense.M, dense.C, dense.K)
    c = proportional[0] + proportional[1] * lam
    root = np.sqrt((c * c - 4 * lam).astype(complex))
    eigenvalues = np.concatenate([(-c + root) / 2, (-c - root) / 2])
    return lam, eigenvalues[np.lexsort((eigenvalues.imag, np.abs(eigenvalues)))]


def _amplitudes_and_phases(pairs: Mapping[str, Any], freqs: list[float]
                           ) -> tuple[dict[str, float], dict[str, float]]:
    """The peak amplitude of every name, and its phase where one frequency moves."""
    for name, p in pairs.items():
        if not all(math.isfinite(v) for pair in p for v in pair):
            raise AnalysisError(
                f"the stationary response of '{name}' is not finite: the computation "
                "overflowed; check the parameter values (their orders of magnitude)")
    amplitudes = {name: peak(freqs, p) for name, p in pairs.items()}
    moving = [i for i, w in enumerate(freqs) if w > 0]
    phases = {}
    if len(moving) == 1:
        i = moving[0]
        for name, p in pairs.items():
            L, N = p[i]
            if math.hypot(L, N) > 0:
                phases[name] = phase_angle(L, N)
    return amplitudes, phases


def _response(h: NumericHarmonic, result: KernelResult, omegas: np.ndarray,
              warnings: list[str]) -> HarmonicResponse:
    """The kernel's answer at one excitation frequency, or the resonance error."""
    w = h.omega
    condition = float(result.condition[0])
    if result.singular[0]:
        if w == 0:
            raise AnalysisError(
                "a static load acts on a system with a zero-stiffness (rigid-body) mode: "
                "the static deflection is unbounded; support the system or remove the "
                "constant part of the excitation")
        nearest = int(np.argmin(np.abs(omegas - w))) if omegas.size else -1
        where = (f" = natural frequency {nearest + 1} ({omegas[nearest]:.6g} rad/s, mode "
                 f"{nearest + 1})") if nearest >= 0 and math.isclose(
                     omegas[nearest], w, rel_tol=1e-6) else ""
        raise AnalysisError(
            f"resonance: the excitation frequency {w:.6g} rad/s{where} and the system has no "
            "damping in that mode, so the stationary amplitude is unbounded; change the "
            "frequency or add damping")
    bound = "" if result.exact else "at least "
    error = None if result.forward_error is None else float(result.forward_error[0])
    if error is not None and error > ERROR_LIMIT:   # (NaN: not estimated)
        left = max(0, int(math.floor(-math.log10(error)))) if math.isfinite(error) else 0
        warnings.append(f"ill-conditioned system at omega = {w:.6g} rad/s: the estimated "
                        f"relative error of the solution is {error:.2g}, so fewer than "
                        f"{DIGITS_WANTED} correct digits are left ({left}) and the values may "
                        f"be wrong (condition number {bound}{condition:.2g}); the cause is the "
                        "conditioning of the dynamic stiffness, not a resonance: stiffnesses "
                        "or units many orders of magnitude apart, or a fine mesh")
    elif error is None and condition > LOSS_CONDITION:
        digits = int(math.log10(condition))
        warnings.append(f"ill-conditioned system at omega = {w:.6g} rad/s (condition number "
                        f"{bound}{condition:.2g}): about {digits} of 16 digits are lost")
    X = result.Z[0]
    check_finite("the stationary solution", X)
    return HarmonicResponse(w, h.F_S, h.F_C, frozen_array(X.real.copy()),
                            frozen_array(-X.imag.copy()), condition)


def _matrix_text(matrix: np.ndarray, indent: str = "    ") -> str:
    rows = [[f"{v + 0.0: .6g}" for v in row] for row in np.atleast_2d(matrix)]  # no -0
    width = max((len(c) for row in rows for c in row), default=1)
    return "\n".join(indent + "[" + "  ".join(c.rjust(width) for c in row) + "]"
                     for row in rows)


def _vector_text(vector: np.ndarray) -> str:
    return "[" + ", ".join(f"{v + 0.0:.6g}" for v in vector) + "]"  # -0 printed as 0


def _pretty(expr: sympy.Basic, indent: str = "    ") -> str:
    """A symbolic matrix as an aligned grid of its entries (cheap: no 2-D pretty-printer)."""
    matrix = sympy.Matrix(expr)
    rows = [[sympy.sstr(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)]
    widths = [max(len(rows[i][j]) for i in range(matrix.rows)) for j in range(matrix.cols)]
    return "\n".join(indent + "[" + "   ".join(c.ljust(w) for c, w in zip(row, widths)) + "]"
                     for row in rows)


def _coordinate_units(coordinates: tuple[str, ...], units: ResultUnits | None) -> str:
    """`` in m`` or `` in [m, rad]`` after the coordinates (their SI units), or ''."""
    if units is None or not any(units.si.get(q) for q in coordinates):
        return ""
    texts = [units.si.get(q) or "?" for q in coordinates]
    return f" in {texts[0]}" if len(set(texts)) == 1 else f" in [{', '.join(texts)}]"


def _load_units(units: ResultUnits | None) -> str:
    """The unit(s) of the rows of F_S and F_C (N, or N*m for a rotation), or ''."""
    rows = units.matrices.get("Q") if units is not None else None
    if not rows:
        return ""
    one = uniform(rows)
    return f" {one}" if one else f"  ([{', '.join(rows)}])"


#: matrices of more coordinates are summarized in the text of ``solve`` (their entries, numeric
#: and symbolic, are in ``to_dict()``/JSON and the report): a 100-link chain printed 15 MB of
#: symbolic entries and spent 30 s deriving them for the screen
PRINTED_MATRIX_SIZE = 12


def _matrices_in_brief(e: NumericEOM, units: ResultUnits | None) -> list[str]:
    out = []
    for key, label, numeric in (("M", "mass matrix M", e.M), ("C", "damping matrix C", e.C),
                                ("K", "stiffness matrix K", e.K)):
        entry_units = units.matrices.get(key) if units is not None else None
        one = uniform(entry_units) if entry_units else None
        out.append(f"  {label}: {e.n} x {e.n}, {np.count_nonzero(numeric)} nonzero entries"
                   + (f" [{one}]" if one else ""))
    out.append(f"  (matrices of more than {PRINTED_MATRIX_SIZE} coordinates are not printed "
               "entry by entry; the JSON output and the report hold them, numeric and "
               "symbolic)")
    return out


def _matrices_in_full(e: NumericEOM, units: ResultUnits | None) -> list[str]:
    out = []
    # the symbolic form where it says more than the numbers (energies, not given matrices)
    sym = e.system.derived_matrices() if e.system is not None else None
    # headings say what the matrix is: a parameter may be called M, C or L too
    for key, label, numeric in (("M", "mass matrix M", e.M), ("C", "damping matrix C", e.C),
                                ("K", "stiffness matrix K", e.K)):
        entry_units = units.matrices.get(key) if units is not None else None
        one = uniform(entry_units) if entry_units else None
        out.append(f"  {label}" + (f" [{one}]" if one else
                                   " (entries in the units below)" if entry_units else "") + " =")
        if sym is not None:
            out.append(_pretty(sym["MCK".index(key)]))
            out.append("    =")
        out.append(_matrix_text(numeric))
        if entry_units and not one:
            out.append("    units:")
            out.append(units_grid(entry_units))
    if sym is not None:
        out.append("  excitation Q(t) =")
        out.append(_pretty(sym[3]))
    return out


def amplitude_table(sol: StationarySolution, units: ResultUnits | None = None) -> ResultTable:
    """The amplitude X (peak deviation) and the phase delta of every coordinate and output,
    in their display units, one aligned column each.

    Parameters
    ----------
    sol : StationarySolution
    units : ResultUnits, optional
        The display units (SI and rad without).

    Returns
    -------
    resonant.tables.ResultTable
    """
    rows = []
    for name, amplitude in sol.amplitudes.items():
        phase = sol.phases.get(name)
        unit = units.unit(name) if units is not None else None
        shown_phase = None if phase is None else units.phase(phase) if units else phase
        rows.append((printable(name, limit=40),
                     number_cell(unit(amplitude) if unit is not None else amplitude, 6),
                     unit.text if unit is not None else "",
                     number_cell(shown_phase, 6),
                     (units.phase.text if units else "rad") if phase is not None else "",
                     "" if name in sol.eom.coordinates else "(output)"))
    return ResultTable(("name", "X", "unit", "delta", "unit", ""), tuple(rows), align="lrlrll")


def solution_text(sol: StationarySolution) -> str:
    """The human-readable report of ``resonant solve``."""
    e = sol.eom
    out: list[str] = []
    title = printable(e.title or "model")
    out.append(f"{title}" + (f"  ({printable(Path(e.source).name)})" if e.source else ""))
    out.append("=" * min(78, len(out[0])))
    units = result_units(e.model)
    out.append(f"generalized coordinates q = [{', '.join(e.coordinates)}]"
               + _coordinate_units(e.coordinates, units))
    out.append("")
    out.append("linearized equation of motion:  M q'' + C q' + K q = Q(t)")
    if e.n > PRINTED_MATRIX_SIZE:
        out.extend(_matrices_in_brief(e, units))
    else:
        out.extend(_matrices_in_full(e, units))
    out.append("")
    freqs = sol.natural_frequencies
    out.append("natural frequencies (undamped):")
    if freqs.size:
        for i, w in enumerate(freqs, start=1):
            shown = units.frequency if units is not None else HZ
            out.append(f"  omega_{i} = {w:.6g} rad/s"
                       + (f"  ({shown(w):.6g} {shown.text})" if shown.text != "rad/s" else ""))
    else:
        out.append("  none (no positive eigenvalue of K q = lambda M q)")
    out.append(f"stability: {sol.stability}")
    out.append("")
    if not sol.available:
        out.append("stationary solution: not available (signals are not harmonic)")
    elif not sol.harmonics:
        out.append("stationary solution: none (no excitation: free vibration)")
    else:
        out.append("stationary solution  q_p = sum of L cos(omega t) + N sin(omega t):")
        for h in sol.harmonics:
            head = "static load" if h.omega == 0 else f"omega = {h.omega:.6g} rad/s"
            # in the frequency unit chosen (--units Hz, rpm), or one that is not Hz
            if units is not None and h.omega and units.frequency.text != "rad/s" and (
                    units.chosen("frequency") or units.frequency.text != "Hz"):
                head += f"  ({units.frequency(h.omega):.6g} {units.frequency.text})"
            out.append(f"  {head}")
            load = _load_units(units)
            out.append(f"    F_S = {_vector_text(h.F_S)}{load}")
            out.append(f"    F_C = {_vector_text(h.F_C)}{load}")
            if units is None:
                out.append(f"    cos coefficients L = {_vector_text(h.L)}")
                out.append(f"    sin coefficients N = {_vector_text(h.N)}")
            else:
                out.append(f"    cos coefficients L = {shown_vector(h.L, e.coordinates, units)}")
                out.append(f"    sin coefficients N = {shown_vector(h.N, e.coordinates, units)}")
        out.append("  amplitudes (peak deviation) and phases delta = atan2(L, N):")
        out.append(amplitude_table(sol, units).text(indent="    "))
    if sol.warnings:
        out.append("")
        for w in sol.warnings:
            out.append(f"warning: {w}")
    return "\n".join(out) + "\n"


def stationary_latex(sol: StationarySolution) -> str:
    """q_p(t) = sum of L cos(w t) + N sin(w t) with numbers (``_repr_latex_``)."""
    terms = []
    for h in sol.harmonics:
        if h.omega == 0:
            terms.append(vector_latex(h.L))
        else:
            wt = number_latex(h.omega) + "t"
            terms.append(rf"{vector_latex(h.L)}\cos({wt}) + {vector_latex(h.N)}\sin({wt})")
    rhs = " + ".join(terms) or r"\mathbf{0}"
    return rf"$\displaystyle \mathbf{{q}}_{{p}}(t) = {rhs}$"


def stationary_html(sol: StationarySolution) -> str:
    """A compact HTML table of amplitudes and phases (Jupyter ``_repr_html_``)."""
    rows = "".join(
        f"<tr><td>{html.escape(n)}</td><td>{a:.6g}</td>"
        f"<td>{'' if sol.phases.get(n) is None else format(sol.phases[n], '.6g')}</td></tr>"
        for n, a in sol.amplitudes.items())
    freqs = ", ".join(f"{w:.6g}" for w in sol.natural_frequencies)
    warn = "".join(f"<p><b>warning:</b> {html.escape(w)}</p>" for w in sol.warnings)
    body = stationary_latex(sol).removeprefix(r"$\displaystyle ").removesuffix("$")
    solution = latex_to_mathml(body, True) if sol.harmonics else ""
    return (f"{solution}<p>natural frequencies: {freqs} rad/s; {html.escape(sol.stability)}</p>"
            f"<table><tr><th>quantity</th><th>amplitude</th><th>phase [rad]</th></tr>{rows}"
            f"</table>{warn}")


__all__ = ["StationarySolution", "HarmonicResponse", "stationary", "peak"]
