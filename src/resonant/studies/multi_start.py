"""Model updating from many starts, on the study engine (docs/testing.md).

A least-squares update finds the minimum its start leads to; with frequencies alone, or
several parameters of like effect, there may be more than one.  :func:`multi_start_update`
runs :func:`~resonant.analyses.model_update.update_parameters` (``kind="modes"``) or
:func:`~resonant.analyses.frf_update.update_to_frf` (``kind="frf"``) from the model's own
values and from ``starts - 1`` further points drawn by a Latin hypercube, log-uniform within
the bounds (seeded: the same starts for the same seed), one task each
through :func:`~resonant.studies.engine.ordered_map` (this process, local workers or a Dask
cluster; the model's text travels and each worker derives it once), and keeps the one of
least cost.  The result lists every start, its end and its cost, and how many distinct
minima were found (ends that differ by more than 1e-4 relative in some parameter): several
of one low cost mean the measurement does not determine the parameters (a ridge), several of
different costs local minima.

Examples
--------
>>> import resonant
>>> from resonant.studies.engine import Engine
>>> model = resonant.load("examples/chain3_damped.toml")
>>> r = multi_start_update(model, {"k": ("500 N/m", "2000 N/m")}, "modes",
...                        {"target_frequency": [2.2399 * 1.05]}, starts=3,
...                        engine=Engine(mode="process"))
>>> round(r.best.fitted["k"] / 1000, 4), r.costs.shape
(1.1025, (3,))
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analyses.frf_update import FRFUpdate, update_to_frf
from ..analyses.model_update import ModelUpdate, parameter_bounds, update_parameters
from ..arrays import freeze_fields
from ..charts import Bar, Chart, Charted, Charts, charts_svg
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..model import loads
from ..model.measurement_spec import ChannelMap
from ..model.types import Model
from ..system.base import LinearSystem
from ..system.build import linear_system
from .engine import Engine, ordered_map
from .run import model_text

__all__ = ["MultiStartUpdate", "multi_start_update", "UpdateTask", "run_start", "KINDS"]

#: what is fitted: identified modes, or measured FRFs
KINDS = ("modes", "frf")
#: ends closer than this (relative, every parameter) are one minimum
SAME_MINIMUM = 1e-4
#: the most starts of one multi-start
MAX_STARTS = 10_000

_SYSTEMS: dict[str, LinearSystem] = {}


@dataclass(frozen=True)
class UpdateTask:
    """What every start needs: the model as text, the bounds and the measurement.

    Attributes
    ----------
    text, source, base_dir : str
        The model file's text, its name and its folder.
    kind : str
        ``"modes"`` or ``"frf"`` (:data:`KINDS`).
    bounds : mapping
        name -> (low, high) in SI.
    data : mapping
        The keywords of the update function (``target_frequency``, ``target_shapes``,
        ``channels``, ``sigma``; or ``frequency``, ``measured``, ``signal``, ``channels``,
        ``residual``, ``sigma``).
    """

    text: str
    source: str
    base_dir: str
    kind: str
    bounds: Mapping[str, tuple[float, float]]
    data: Mapping[str, Any]

    @property
    def key(self) -> str:
        """A digest of the model's text and source (one derivation per process)."""
        return hashlib.sha256(repr((self.text, self.source, self.base_dir)).encode()
                              ).hexdigest()


def _system(task: UpdateTask) -> LinearSystem:
    system = _SYSTEMS.get(task.key)
    if system is None:
        model = loads(task.text, source=task.source, base_dir=task.base_dir)
        system = _SYSTEMS[task.key] = linear_system(model)
    return system


def run_start(task: UpdateTask, start: Mapping[str, float]) -> ModelUpdate | FRFUpdate:
    """One start of a multi-start update (a module-level function: it travels to workers).

    Parameters
    ----------
    task : UpdateTask
    start : mapping
        name -> the start value (SI).

    Returns
    -------
    ModelUpdate or FRFUpdate
    """
    system = _system(task)
    data = dict(task.data)
    if task.kind == "frf":
        return update_to_frf(system, task.bounds, data.pop("frequency"), data.pop("measured"),
                             data.pop("signal"), data.pop("channels"), start=start, **data)
    return update_parameters(system, task.bounds, data.pop("target_frequency"), start=start,
                             **data)


@dataclass(frozen=True)
class MultiStartUpdate(Charted):
    """Every start of a multi-start update and the best fit.

    Attributes
    ----------
    names : tuple of str
        The parameters.
    starts, ends : ndarray
        (starts, parameters) the start and end values (SI).
    costs : ndarray
        (starts,) each end's cost.
    best : ModelUpdate or FRFUpdate
        The fit of least cost.
    minima : int
        The distinct minima found.
    warnings : tuple of str
    """

    names: tuple[str, ...]
    starts: np.ndarray
    ends: np.ndarray
    costs: np.ndarray
    best: ModelUpdate | FRFUpdate
    minima: int
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        freeze_fields(self)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (the best fit's own, and every start).

        Returns
        -------
        dict
        """
        return {"parameters": list(self.names), "starts": self.starts.tolist(),
                "ends": self.ends.tolist(), "costs": self.costs.tolist(),
                "minima": self.minima, "best": self.best.to_dict(),
                "best_kind": "frf" if isinstance(self.best, FRFUpdate) else "modes",
                "warnings": list(self.warnings)}

    def chart(self) -> Charts:
        """Each start's final cost (log axis), the best one marked.

        Returns
        -------
        Charts
        """
        x = np.arange(1, len(self.costs) + 1, dtype=float)
        floor = max(float(np.min(self.costs[self.costs > 0], initial=1e-30)), 1e-30)
        costs = np.maximum(self.costs, floor)
        colors = tuple("#d62728" if k == int(np.argmin(self.costs)) else "#1f77b4"
                       for k in range(len(x)))
        chart = Chart((), "start", "final cost", (0.4, len(x) + 0.6), ylog=True,
                      bars=(Bar(x, costs, colors, 0.6, "cost"),))
        return Charts((chart,), title=f"{len(x)} starts, {self.minima} distinct minima")

    def summary(self) -> str:
        """The starts sorted by cost, then the best fit's summary.

        Returns
        -------
        str
        """
        head = f"{'start':>5} {'cost':>11} " + " ".join(
            f"{printable(n, limit=12):>12}" for n in self.names)
        lines = [f"{len(self.costs)} starts, {self.minima} distinct minima", head]
        for k in np.argsort(self.costs)[:20]:
            lines.append(f"{k + 1:>5} {self.costs[k]:>11.4g} " + " ".join(
                f"{v:>12.6g}" for v in self.ends[k]))
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines) + "\n" + self.best.summary()

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "multi-start")


def _start_points(bounds: Mapping[str, tuple[float, float]], first: np.ndarray, starts: int,
                  seed: int) -> np.ndarray:
    """The model's values, then a seeded Latin hypercube, log-uniform in the bounds: each
    parameter's range cut into ``starts - 1`` equal strata (in ln p), one point in each, the
    strata shuffled per parameter (McKay, Beckman & Conover 1979)."""
    low = np.log([b[0] for b in bounds.values()])
    high = np.log([b[1] for b in bounds.values()])
    count = starts - 1
    if count == 0:
        return first[None, :]
    rng = np.random.default_rng(seed)
    strata = np.column_stack([rng.permutation(count) for _ in low])
    unit = (strata + rng.random((count, len(low)))) / count
    return np.vstack([first, np.exp(low + unit * (high - low))])


def _count_minima(ends: np.ndarray, costs: np.ndarray) -> int:
    """The ends that differ from every better one by more than :data:`SAME_MINIMUM`."""
    kept: list[int] = []
    for k in np.argsort(costs):
        if not any(np.all(np.abs(ends[k] / ends[j] - 1) < SAME_MINIMUM) for j in kept):
            kept.append(int(k))
    return len(kept)


def multi_start_update(model: Model, parameters: Mapping[str, tuple[Any, Any]], kind: str,
                       data: Mapping[str, Any], *, starts: int = 8, seed: int = 0,
                       engine: Engine | None = None,
                       deadline: Deadline = NO_DEADLINE) -> MultiStartUpdate:
    """The update from many starts, run on the study engine; the best fit kept.

    Parameters
    ----------
    model : Model
        Loaded from a file (its text travels to the workers).
    parameters : mapping
        name -> (low, high): numbers (SI) or texts with units.
    kind : {"modes", "frf"}
        Fit identified modes (``data``: ``target_frequency`` and optionally
        ``target_shapes``, ``channels``, ``mac_weight``, ``sigma``) or measured FRFs
        (``data``: ``frequency``, ``measured``, ``signal``, ``channels`` and optionally
        ``residual``, ``sigma``, ``units``).
    data : mapping
        The measurement, as the keywords of the update function.
    starts : int
        How many starts (the first is the model's own values).
    seed : int
        The Latin hypercube's seed.
    engine : Engine, optional
        Where the starts run (default: ``Engine()``, this process or local workers as pays).
    deadline : Deadline, optional
        The whole run's (each start also checks it).

    Returns
    -------
    MultiStartUpdate

    Raises
    ------
    ModelError
        For an unknown kind, a number of starts out of 1 to :data:`MAX_STARTS`, or what the
        update itself refuses (unknown parameter, bounds, measurement).
    """
    if kind not in KINDS:
        raise ModelError(Problem(f"'{printable(kind, limit=20)}' is not one of "
                                 f"{', '.join(KINDS)}", model.source, "update", "fit"))
    if not 1 <= int(starts) <= MAX_STARTS:
        raise ModelError(Problem(f"starts must be from 1 to {MAX_STARTS}", model.source,
                                 "update", "starts"))
    system = linear_system(model, deadline)
    values = dict(system.numeric(deadline).parameters)
    bounds = parameter_bounds(system, parameters, values)
    first = np.array([min(max(float(values[n]), b[0]), b[1]) for n, b in bounds.items()])
    points = _start_points(bounds, first, int(starts), seed)
    text, base_dir = model_text(model)
    task = UpdateTask(text, model.source, base_dir, kind, bounds, _plain(data))
    names = tuple(bounds)
    engine = engine or Engine(deadline=deadline)
    fits = list(ordered_map(run_start, ((task, dict(zip(names, p.tolist()))) for p in points),
                            engine))
    ends = np.array([[fit.fitted[n] for n in names] for fit in fits])
    costs = np.array([fit.cost for fit in fits])
    best = fits[int(np.argmin(costs))]
    minima = _count_minima(ends, costs)
    warnings = list(best.warnings)
    if minima > 1:
        warnings.append(f"{minima} distinct minima from {len(fits)} starts: the fit kept is "
                        "the one of least cost; the others are listed")
    return MultiStartUpdate(names, points, ends, costs, best, minima, tuple(warnings))


def _plain(data: Mapping[str, Any]) -> dict[str, Any]:
    """The measurement with its arrays and channel maps as plain values (they travel)."""
    out: dict[str, Any] = {}
    for key, value in data.items():
        if key == "channels" and value is not None:
            out[key] = {c: ChannelMap(m.name, m.derivative) for c, m in value.items()}
        elif key == "measured":
            out[key] = {c: np.array(v) for c, v in value.items()}
        elif isinstance(value, np.ndarray):
            out[key] = np.array(value)
        else:
            out[key] = value
    return out
