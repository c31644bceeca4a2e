"""The quantities of a study, evaluated for a whole chunk of samples at once.

A chunk's parameter values go through the system's compiled evaluation
(:meth:`LinearSystem.evaluate`) once, and every quantity is computed for all
samples together: batched eigenvalues (small models), the harmonic kernel
:func:`~resonant.analyses.kernel.solve_harmonic` over all samples (and all
frequencies of a peak's band), never a Python loop per sample.  Models above
:data:`SMALL` coordinates come in chunks of one sample; their modes are those
of :func:`~resonant.analyses.modes.modes` and their responses use the reduced
model of the kernel where it pays.

A sample where the analysis is impossible is not an error of the study: its
row gets a status (``singular mass``, ``unstable``, ``resonance``, ``failed``)
and a reason, and the quantities that do not exist there are NaN.

Examples
--------
>>> import numpy as np, resonant
>>> from resonant.model.study import study_spec
>>> model = resonant.load("examples/cart_pendulum.toml")
>>> spec = study_spec({"k": [100.0]}, ["amplitude:x2"], parameters=model.parameters,
...                   coordinates=model.coordinates, outputs=model.outputs)
>>> rows = evaluate_samples(model.linearize(), spec, {"k": np.array([100.0])})
>>> round(float(rows["amplitude:x2"][0]), 6), str(rows["status"][0])
(0.045141, 'ok')
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from ..analyses.campbell import campbell, log_decrement
from ..analyses.fatigue import SNCurve, spectral_fatigue
from ..analyses.kernel import solve_harmonic
from ..analyses.modes import modes
from ..analyses.random_response import random_response
from ..analyses.shock import shock_response_spectrum
from ..analyses.sweep import amplitude_and_phase, amplitudes, harmonic_responses, kept_coordinates
from ..analyses.transient import shock_response
from ..arrays import Matrix
from ..deadline import NO_DEADLINE, Deadline, DeadlineExceeded
from ..errors import ModelError, Problem, ResonantError
from ..memory import dense_matrix
from ..modal import (
    cholesky_lambdas,
    damping_ratio,
    general_lambdas,
    natural_frequency,
    singular_mass,
    state_eigenvalues,
    undamped_lambdas,
    unstable,
    unstable_by_inertia,
)
from ..model.study import ROTOR_KINDS, Band, Quantity, StudySpec
from ..system.base import LinearSystem, numeric_point
from ..system.batch import Batch
from ..system.build import nonlinear_system
from ..system.nonlinear import NonlinearSystem
from .designs import REFINE_POINTS, REFINE_ROUNDS
from .nonlinear import nonlinear_amplitudes
from .reduced_band import ReducedBand, reduced_band

#: models up to this many coordinates are evaluated as stacks of dense matrices
SMALL = 64
OK = "ok"


class Rows:
    """The columns of one chunk being filled: values, status and reason per sample."""

    def __init__(self, count: int, spec: StudySpec) -> None:
        self.count = count
        self.columns: dict[str, np.ndarray] = {
            c: np.full(count, np.nan) for c in spec.columns}
        if "stable" in self.columns:
            self.columns["stable"] = np.zeros(count, dtype=bool)
        # status and reason per sample, made at the first failure (most chunks have none)
        self.status: np.ndarray = np.empty(0, dtype=object)
        self.reason: np.ndarray = np.empty(0, dtype=object)
        self.marked = False  # whether any sample failed
        #: what failed where: "all" (every quantity), "stability" (responses),
        #: "excitation" (amplitude, phase), "band" (peaks), "nonlinear" (the nonlinear
        #: steady state), "random" (the response to the [random] inputs: rms, damage),
        #: "shock" (the response to the [shock] pulse: srs), "rotor" (the Campbell
        #: diagram and the modes at a speed: critical speeds, threshold, log decrements)
        self.failed = {k: np.zeros(count, dtype=bool)
                       for k in ("all", "stability", "excitation", "band", "nonlinear", "random",
                                 "shock", "rotor")}

    def fail(self, mask: np.ndarray, status: str, reason: str, scope: str = "all") -> None:
        """Mark the samples of ``mask``; the first failure of a sample gives its status."""
        if not mask.any():
            return
        if not self.marked:
            self.status = np.full(self.count, OK, dtype=object)
            self.reason = np.full(self.count, "", dtype=object)
        self.marked = True
        fresh = mask & (self.status == OK)
        self.status[fresh] = status
        self.reason[fresh] = reason
        self.failed[scope] |= mask

    def valid(self, *scopes: str) -> np.ndarray:
        """The samples where nothing of ``scopes`` (nor of "all") failed."""
        bad = self.failed["all"].copy()
        for scope in scopes:
            bad |= self.failed[scope]
        return ~bad

    def table(self) -> dict[str, np.ndarray]:
        out = dict(self.columns)
        if not self.marked:  # every sample ok (the usual chunk): no conversion per sample
            out["status"], out["reason"] = np.full(self.count, OK), np.full(self.count, "")
            return out
        out["status"] = self.status.astype(str)
        out["reason"] = self.reason.astype(str)
        return out


def _stack(a: Matrix) -> np.ndarray:
    """A matrix as a stack: (N, n, n), or (1, n, n) when it is the same for every sample
    (so that what depends on it alone is computed once)."""
    a = dense_matrix(a)
    return a[None] if a.ndim == 2 else a


def _fill_modal(rows: Rows, spec: StudySpec, M: np.ndarray, C: np.ndarray, K: np.ndarray,
                wants_stability: bool) -> None:
    kinds = {q.kind for q in spec.quantities}
    full = (rows.count,)
    stability = wants_stability or "stable" in kinds
    lam = by_cholesky = None
    if "natural_frequency" in kinds or stability:
        by_cholesky = cholesky_lambdas(M, K)
        lam = by_cholesky if by_cholesky is not None else general_lambdas(M, K)
    for q in spec.quantities:
        if q.kind == "natural_frequency" and lam is not None:
            rows.columns[q.text] = np.broadcast_to(natural_frequency(lam, q.index), full)
    bad = unstable_by_inertia(C, K, by_cholesky, symmetric_k=True) \
        if stability and by_cholesky is not None else None
    if "damping_ratio" in kinds or (stability and bad is None):
        eigenvalues = state_eigenvalues(*np.broadcast_arrays(M, C, K))
        if bad is None:
            bad = unstable(eigenvalues) | ~np.isfinite(eigenvalues).all(axis=1)
        for q in spec.quantities:
            if q.kind == "damping_ratio":
                rows.columns[q.text] = np.broadcast_to(damping_ratio(eigenvalues, q.index), full)
    if bad is None:
        return
    bad = np.broadcast_to(bad, full)
    if "stable" in rows.columns:
        rows.columns["stable"] = ~bad
    if wants_stability:
        rows.fail(bad, "unstable", "the equilibrium is unstable: there is no stationary "
                  "response", "stability")


def _fill_modal_large(rows: Rows, spec: StudySpec, system: LinearSystem,
                      values: Mapping[str, Any]) -> None:
    """Modes of a large model, one sample (its chunks have one sample)."""
    wanted = [q for q in spec.quantities if q.kind in ("natural_frequency", "damping_ratio",
                                                      "stable")]
    if not wanted:
        return
    count = max([q.index for q in wanted] + [1])
    for i in range(rows.count):
        one = {k: (v[i] if isinstance(v, np.ndarray) else v) for k, v in values.items()}
        analysis = modes(numeric_point(system.evaluate(one, 1), 0, system, one), count=count)
        for q in wanted:
            if q.kind == "stable":
                rows.columns["stable"][i] = analysis.stability != "unstable"
                continue
            source = analysis.natural_frequencies if q.kind == "natural_frequency" \
                else analysis.damping_ratios
            rows.columns[q.text][i] = source[q.index - 1] if q.index <= len(source) else np.nan


def responses(system: LinearSystem, values: Mapping[str, Any], count: int,
              names: Sequence[str], batch: Batch | None = None, *, phase: bool = True
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Amplitude and phase (count, len(names)) of coordinates and outputs at every point,
    and the points where the harmonic system is singular (an undamped resonance);
    ``batch`` is the system at ``values`` if it was evaluated already; without
    ``phase``, the phases are NaN (not computed)."""
    batch = batch if batch is not None else system.evaluate(values, count)
    if any(name not in names for name in batch.outputs):  # only the outputs asked for
        batch = replace(batch, outputs={k: v for k, v in batch.outputs.items() if k in names})
    coordinates = [q for q in names if q in batch.coordinates]
    keep_names = kept_coordinates(batch, coordinates)
    keep = np.array([batch.coordinates.index(q) for q in keep_names], dtype=int)
    method = "dense" if len(batch.coordinates) <= SMALL else "auto"
    # no forward-error estimates: a study keeps no column or warning of them (docs/studies.md)
    results = [solve_harmonic(batch, h, method, keep=keep, exact_condition=False,
                              forward_error=False)
               for h in batch.harmonics]
    if not results:
        zeros = np.zeros((count, len(names)))
        return zeros, np.full((count, len(names)), np.nan), np.zeros(count, dtype=bool)
    all_names, Z = harmonic_responses(batch, [r.Z for r in results], coordinates)
    omegas = np.array([np.broadcast_to(h.omega, (count,)) for h in batch.harmonics])
    columns = [all_names.index(q) for q in names]
    if phase:
        amplitude, phases = amplitude_and_phase(omegas, Z)
        phases = phases[:, columns]
    else:
        amplitude, phases = amplitudes(omegas, Z), np.full((count, len(names)), np.nan)
    singular = np.zeros(count, dtype=bool)
    for r in results:
        singular |= r.singular
    return amplitude[:, columns], phases, singular


def _fill_responses(rows: Rows, spec: StudySpec, system: LinearSystem,
                    values: Mapping[str, Any], batch: Batch) -> None:
    wanted = [q for q in spec.quantities if q.kind in ("amplitude", "phase")]
    if not wanted:
        return
    names = list(dict.fromkeys(q.target for q in wanted))
    amplitude, phase, singular = responses(system, values, rows.count, names, batch,
                                           phase=any(q.kind == "phase" for q in wanted))
    rows.fail(singular, "resonance", "an undamped resonance at the excitation: the "
              "amplitude is unbounded", "excitation")
    ok = rows.valid("stability", "excitation")
    for q in wanted:
        column = (amplitude if q.kind == "amplitude" else phase)[:, names.index(q.target)]
        rows.columns[q.text] = np.where(ok, column, np.nan)


def _band_values(values: Mapping[str, Any], system: LinearSystem, param: str,
                 grid: np.ndarray
                 ) -> tuple[dict[str, Any], int]:
    """Every sample's values repeated for the points of its own ``grid`` row (N, F); one
    sample's values stay numbers (its matrices and loads are then computed once, not F
    times)."""
    N, F = grid.shape
    varied = {k: float(v[0]) if N == 1 else np.repeat(v, F) for k, v in values.items()
              if isinstance(v, np.ndarray) and k != param}
    varied[param] = grid.ravel()
    out, _, _ = system.parameter_samples(varied, N * F)
    return out, N * F


def _best(rows: np.ndarray, points: np.ndarray, best: np.ndarray, where: np.ndarray
          ) -> None:
    """Keep, per sample, the largest finite amplitude of ``rows`` (N, F) and its point."""
    count = rows.shape[0]
    a = np.where(np.isfinite(rows), rows, -np.inf)
    k = a.argmax(axis=1)
    top = a[np.arange(count), k]
    better = top > best
    best[better] = top[better]
    where[better] = points[np.arange(count), k][better]


def _amplitude_on(system: LinearSystem, values: Mapping[str, Any], param: str,
                  points: np.ndarray, names: Sequence[str]) -> np.ndarray:
    """Amplitudes (N, F, names) with ``param`` at each sample's own points (N, F)."""
    band_values, size = _band_values(values, system, param, points)
    amplitude, _, _ = responses(system, band_values, size, names, phase=False)
    return amplitude.reshape(*points.shape, len(names))


def _peak_search(system: LinearSystem, values: Mapping[str, Any],
                 spec: StudySpec, names: Sequence[str], count: int
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The largest amplitude of each name over the band and where it is, per sample:
    a grid of the band, rounds of finer grids around the best point, then the vertex
    of the parabola through the best point and its neighbours.  A large model whose
    direct solves are expensive searches one reduced model of the sample
    (:mod:`.reduced_band`) and solves the found peak exactly."""
    band = spec.band
    assert band is not None
    grid = np.broadcast_to(np.linspace(band.start, band.stop, band.points), (count, band.points))
    shared = _shared_band(system, values, band, grid, names)

    def on(points: np.ndarray, which: Sequence[str]) -> np.ndarray:
        if shared is not None:
            return shared.amplitudes(points)[..., [names.index(q) for q in which]]
        return _amplitude_on(system, values, band.parameter, points, which)

    amplitude = on(grid, names)
    best = np.full((count, len(names)), -np.inf)
    where = np.full((count, len(names)), np.nan)
    for j in range(len(names)):
        _best(amplitude[:, :, j], grid, best[:, j], where[:, j])
        step = np.full(count, (band.stop - band.start) / (band.points - 1))
        for _ in range(REFINE_ROUNDS):
            points = _refined(where[:, j], step, band)
            a = on(points, names[j:j + 1])
            _best(a[:, :, 0], points, best[:, j], where[:, j])
            step = 2 * step / (REFINE_POINTS - 1)
        points = _vertex(where[:, j], step, band, a[:, :, 0], points)
        a = on(points, names[j:j + 1])
        _best(a[:, :, 0], points, best[:, j], where[:, j])
        if shared is not None:  # the peak found on the reduced model, solved exactly
            best[:, j] = _amplitude_on(system, values, band.parameter,
                                       where[:, j:j + 1], names[j:j + 1])[:, 0, 0]
    return best, where


def _shared_band(system: LinearSystem, values: Mapping[str, Any], band: Band,
                 grid: np.ndarray, names: Sequence[str]) -> ReducedBand | None:
    """One sample of a large model: its reduced model over the band, where it pays."""
    if grid.shape[0] != 1 or system.n <= SMALL:
        return None
    band_values, size = _band_values(values, system, band.parameter, grid)
    return reduced_band(system.evaluate(band_values, size), grid[0], names)


def _vertex(center: np.ndarray, step: np.ndarray, band: Band, last: np.ndarray,
            points: np.ndarray) -> np.ndarray:
    """The vertex of the parabola through the best of the last round and its neighbours."""
    a = np.where(np.isfinite(last), last, -np.inf)
    k = np.clip(a.argmax(axis=1), 1, points.shape[1] - 2)
    rows = np.arange(points.shape[0])
    x = np.stack([points[rows, k - 1], points[rows, k], points[rows, k + 1]], axis=1)
    y = np.stack([last[rows, k - 1], last[rows, k], last[rows, k + 1]], axis=1)
    with np.errstate(all="ignore"):
        h = x[:, 1] - x[:, 0]
        curvature = y[:, 0] - 2 * y[:, 1] + y[:, 2]
        shift = np.where(curvature < 0, h * (y[:, 0] - y[:, 2]) / (2 * curvature), 0.0)
    vertex = np.where(np.isfinite(shift) & (np.abs(shift) <= np.abs(h)), x[:, 1] + shift,
                      center)
    return np.clip(vertex, band.start, band.stop)[:, None]


def _refined(center: np.ndarray, step: np.ndarray, band: Band) -> np.ndarray:
    """REFINE_POINTS points from one grid step below ``center`` to one above, in the band."""
    offsets = np.linspace(-1.0, 1.0, REFINE_POINTS)
    points = center[:, None] + step[:, None] * offsets
    return np.clip(np.nan_to_num(points, nan=band.start), band.start, band.stop)


def undamped_resonance_in_band(lam: np.ndarray, C: np.ndarray, band: Band) -> np.ndarray:
    """Samples without damping that have a natural frequency in the band: their peak is
    unbounded (a mode the load does not excite is counted too)."""
    undamped = ~np.any(C != 0, axis=(1, 2))
    with np.errstate(invalid="ignore"):
        w = np.sqrt(np.where(lam >= 0, lam, np.nan))
    inside = ((w >= band.start) & (w <= band.stop)).any(axis=1)
    return undamped & inside


def _fill_peaks(rows: Rows, spec: StudySpec, system: LinearSystem,
                values: Mapping[str, Any]) -> None:
    wanted = [q for q in spec.quantities if q.kind == "peak"]
    if not wanted:
        return
    names = list(dict.fromkeys(q.target for q in wanted))
    best, where = _peak_search(system, values, spec, names, rows.count)
    for q in wanted:
        j = names.index(q.target)
        ok = rows.valid("stability", "band")
        rows.columns[q.text] = np.where(ok & np.isfinite(best[:, j]), best[:, j], np.nan)
        rows.columns[f"peak_frequency:{q.target}"] = np.where(ok, where[:, j], np.nan)


def _fill_nonlinear(rows: Rows, spec: StudySpec, nonlinear: NonlinearSystem | None,
                    values: Mapping[str, Any], deadline: Deadline = NO_DEADLINE) -> None:
    """The nonlinear steady states, sample by sample (the samples that failed before are
    skipped)."""
    found = nonlinear_amplitudes(nonlinear, spec, values, rows.count, skip=~rows.valid(),
                                 deadline=deadline) if nonlinear is not None else None
    if found is None:
        return
    for i, status in enumerate(found.status):
        if status != OK:
            rows.fail(np.arange(rows.count) == i, status, found.reason[i], "nonlinear")
    for q in spec.quantities:
        if q.kind == "nonlinear_amplitude":
            column = found.amplitudes[:, found.names.index(q.target)]
            rows.columns[q.text] = np.where(rows.valid("nonlinear"), column, np.nan)


def _per_sample(rows: Rows, wanted: list[Quantity], system: LinearSystem,
                values: Mapping[str, Any], batch: Batch, stage: str,
                compute: Callable[[LinearSystem], dict[str, float]],
                deadline: Deadline = NO_DEADLINE) -> None:
    """The ``wanted`` columns sample by sample: ``compute`` of each sample's system gives
    every wanted quantity's value (the samples whose stability failed before are
    skipped; a sample whose analysis fails is marked failed at ``stage``)."""
    for i in np.flatnonzero(rows.valid("stability")):
        deadline.check(f"while computing the study's {stage} quantities", analysis=True)
        try:
            found = compute(numeric_point(batch, int(i), system, values))
            for q in wanted:
                rows.columns[q.text][i] = found[q.text]
        except DeadlineExceeded:
            raise
        except ResonantError as exc:
            rows.fail(np.arange(rows.count) == i, "failed", str(exc), stage)
            for q in wanted:
                rows.columns[q.text][i] = np.nan


def _fill_rms(rows: Rows, spec: StudySpec, system: LinearSystem, values: Mapping[str, Any],
              batch: Batch, deadline: Deadline = NO_DEADLINE) -> None:
    """The RMS values (and the fatigue damage) under the model's ``[random]`` inputs
    (docs/random.md), sample by sample."""
    wanted = [q for q in spec.quantities if q.kind in ("rms", "damage")]
    if not wanted:
        return
    names = list(dict.fromkeys(q.target for q in wanted))

    def compute(point: LinearSystem) -> dict[str, float]:
        result = random_response(point, names=names, deadline=deadline)
        return {q.text: result.rms[q.target] if q.kind == "rms" else
                _damage(point, result.frequency, result.psd[q.target]) for q in wanted}

    _per_sample(rows, wanted, system, values, batch, "random", compute, deadline)


def _damage(system: LinearSystem, frequency: np.ndarray, psd: np.ndarray) -> float:
    """Miner's damage over the ``[fatigue]`` section's exposure of a stress density by the
    section's spectral method (FLife, :func:`~resonant.analyses.fatigue.spectral_fatigue`)."""
    spec = system.model.fatigue_section if system.model is not None else None
    if spec is None:
        raise ModelError(Problem("damage:NAME needs a [fatigue] section: the S-N curve (k and "
                                 "C), the method and the duration (docs/model-format.md)",
                                 system.source, "fatigue"))
    result = spectral_fatigue(frequency, psd, SNCurve(spec.C, spec.k), spec.duration,
                              methods=[spec.method])
    assert result.damage is not None
    return float(result.damage[spec.method])


def _fill_srs(rows: Rows, spec: StudySpec, system: LinearSystem, values: Mapping[str, Any],
              batch: Batch, deadline: Deadline = NO_DEADLINE) -> None:
    """The shock response spectra at the quantities' frequencies of the histories under the
    model's ``[shock]`` pulse, sample by sample."""
    wanted = [q for q in spec.quantities if q.kind == "srs"]
    if not wanted:
        return
    names = list(dict.fromkeys(q.target for q in wanted))

    def compute(point: LinearSystem) -> dict[str, float]:
        response = shock_response(point, names=names, deadline=deadline)
        shock = point.model.shock_section if point.model is not None else None
        assert shock is not None  # shock_response raised otherwise
        found = {}
        for name in names:
            here = [q for q in wanted if q.target == name]
            srs = shock_response_spectrum(response.history[name], shock.step,
                                          [q.frequency for q in here], Q=shock.Q,
                                          deadline=deadline)
            found.update({q.text: float(v) for q, v in zip(here, srs.maximax)})
        return found

    _per_sample(rows, wanted, system, values, batch, "shock", compute, deadline)


def _fill_rotor(rows: Rows, spec: StudySpec, system: LinearSystem, values: Mapping[str, Any],
                batch: Batch, deadline: Deadline = NO_DEADLINE) -> None:
    """The rotor quantities (docs/rotors.md), sample by sample: one Campbell diagram over
    the ``[campbell]`` section's range gives ``critical_speed:K[@R]`` (the K-th lowest
    critical speed of order R, forward or backward) and ``stability_threshold`` (NaN where
    there is none in the range); ``log_decrement:K@SPEED`` is the K-th mode at that speed
    in the kernel's order (lowest first)."""
    wanted = [q for q in spec.quantities if q.kind in ROTOR_KINDS]
    if not wanted:
        return
    ranged = [q for q in wanted if q.kind != "log_decrement"]
    orders = sorted({q.order for q in ranged if q.kind == "critical_speed"}) or [1.0]

    def compute(point: LinearSystem) -> dict[str, float]:
        found: dict[str, float] = {}
        if ranged:
            diagram = campbell(point, orders=orders, deadline=deadline)
            for q in ranged:
                if q.kind == "stability_threshold":
                    t = diagram.threshold.speed
                    found[q.text] = math.nan if t is None else t
                    continue
                speeds = [c.speed for c in diagram.critical_speeds if c.order == q.order]
                found[q.text] = speeds[q.index - 1] if q.index <= len(speeds) else math.nan
        for q in wanted:
            if q.kind == "log_decrement":
                found[q.text] = log_decrement(point, q.speed, q.index, deadline=deadline)
        return found

    _per_sample(rows, wanted, system, values, batch, "rotor", compute, deadline)


def _fill(rows: Rows, spec: StudySpec, system: LinearSystem,
          values: Mapping[str, Any], nonlinear: NonlinearSystem | None = None,
          deadline: Deadline = NO_DEADLINE) -> None:
    """Every quantity of a chunk whose parameters evaluate."""
    batch = system.evaluate(values, rows.count)
    n = len(batch.coordinates)
    responding = any(q.kind in ("amplitude", "phase", "peak") for q in spec.quantities)
    if n <= SMALL and not hasattr(batch.M, "tocsr"):
        M, C, K = (_stack(a) for a in (batch.M, batch.C, batch.K))
        rows.fail(np.broadcast_to(singular_mass(M), (rows.count,)), "singular mass",
                  "the mass matrix M is singular")
        _fill_modal(rows, spec, M, C, K, wants_stability=responding)
        if spec.band is not None and any(q.kind == "peak" for q in spec.quantities):
            rows.fail(np.broadcast_to(undamped_resonance_in_band(undamped_lambdas(M, K), C,
                                                                 spec.band), (rows.count,)),
                      "resonance", "no damping and a natural frequency in the band: the "
                      "peak is unbounded", "band")
    else:
        _fill_modal_large(rows, spec, system, values)
    _fill_responses(rows, spec, system, values, batch)
    _fill_peaks(rows, spec, system, values)
    _fill_nonlinear(rows, spec, nonlinear, values, deadline)
    _fill_rms(rows, spec, system, values, batch, deadline)
    _fill_srs(rows, spec, system, values, batch, deadline)
    _fill_rotor(rows, spec, system, values, batch, deadline)


def evaluate_samples(system: LinearSystem, spec: StudySpec, varied: Mapping[str, np.ndarray],
                     nonlinear: NonlinearSystem | None = None,
                     deadline: Deadline = NO_DEADLINE) -> dict[str, np.ndarray]:
    """The quantities of ``spec`` at the samples ``varied`` (parameter -> values).

    Parameters
    ----------
    system : LinearSystem
        The model's linear system (carrying its model).
    spec : StudySpec
    varied : mapping
        parameter -> values, all of one length N.
    nonlinear : NonlinearSystem, optional
        The model's full equations, for ``nonlinear_amplitude:`` quantities (derived
        from ``system`` when not given).
    deadline : Deadline, optional
        Checked between the samples of the quantities computed sample by sample (RMS,
        SRS, nonlinear amplitudes) and inside their analyses.

    Returns
    -------
    dict
        column -> array (N,): the quantities' columns, ``status`` and ``reason``.
    """
    if nonlinear is None and any(q.kind == "nonlinear_amplitude" for q in spec.quantities):
        nonlinear = nonlinear_system(system)
    count = len(next(iter(varied.values())))
    rows = Rows(count, spec)
    values, bad, reasons = system.parameter_samples(varied, count)
    for i in np.flatnonzero(bad):
        rows.fail(np.arange(count) == i, "failed", reasons[i])
    try:
        _fill(rows, spec, system, values, nonlinear, deadline)
    except DeadlineExceeded:
        raise
    except (ResonantError, np.linalg.LinAlgError, FloatingPointError, OverflowError) as exc:
        if count == 1:
            rows.fail(np.ones(1, dtype=bool), "failed", str(exc).splitlines()[0])
            return rows.table()
        return _one_by_one(system, spec, varied, count, nonlinear, deadline)
    return rows.table()


def empty_rows(spec: StudySpec) -> dict[str, np.ndarray]:
    """The columns of a chunk with no samples: their names, order and types.

    Parameters
    ----------
    spec : StudySpec

    Returns
    -------
    dict
        column -> array of length 0: sample, the varied parameters, the quantities,
        status and reason.
    """
    return {"sample": np.empty(0, dtype=np.int64), **{v: np.empty(0) for v in spec.vary},
            **Rows(0, spec).table()}


def _one_by_one(system: LinearSystem, spec: StudySpec, varied: Mapping[str, np.ndarray],
                count: int, nonlinear: NonlinearSystem | None,
                deadline: Deadline = NO_DEADLINE) -> dict[str, np.ndarray]:
    """A chunk that failed as a whole, sample by sample: the failing ones get the reason."""
    parts = [evaluate_samples(system, spec, {k: v[i:i + 1] for k, v in varied.items()},
                              nonlinear, deadline) for i in range(count)]
    return {c: np.concatenate([p[c] for p in parts]) for c in parts[0]}


__all__ = ["empty_rows", "evaluate_samples", "SMALL"]
