"""The samples of a study, chunk by chunk, independent of who computes them.

A study's rows are cut into chunks of a fixed size that depends only on the
study and the model's size (:func:`chunk_size`), never on the number of
workers.  Chunk ``k`` of a ``random`` or ``lhs`` design draws its numbers from
its own generator, ``SeedSequence(seed, spawn_key=(k,))``; a ``grid`` computes
its rows from their indices; a ``sobol`` design is Saltelli's sample drawn by
SALib once and cut.  So the same seed gives the same samples in one process,
on N workers or on a cluster, in any order.

Examples
--------
>>> from resonant.model.study import study_spec
>>> spec = study_spec({"k": "uniform(1, 2)"}, ["stable"], samples=10, seed=3,
...                   parameters=["k"], coordinates=["x"], outputs=[])
>>> a = chunk_values(spec, 0, 4)["k"]
>>> b = chunk_values(spec, 0, 4)["k"]
>>> bool((a == b).all()), a.shape
(True, (4,))
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator

import numpy as np

from ..errors import ModelError
from ..model.study import StudySpec

#: samples x coordinates^2 x frequencies per chunk: a chunk's arrays stay near 30 MB
CHUNK_WORK = 2**21
MAX_CHUNK = 65_536
#: points of each peak refinement round and the number of rounds (see quantities)
REFINE_POINTS = 9
REFINE_ROUNDS = 6
#: samples per chunk of a study with a nonlinear steady state (harmonic balance per
#: sample, about 0.05 to 2 s each): small chunks spread over the workers
NONLINEAR_CHUNK = 4
#: the largest base sample of a Sobol design (its sample is drawn at once)
MAX_SOBOL_BASE = 2**22


def points_per_sample(spec: StudySpec) -> int:
    """Model evaluations per sample: 1, or the band's grid and refinement for peaks."""
    if spec.band is None or not any(q.kind == "peak" for q in spec.quantities):
        return 1
    return spec.band.points + REFINE_POINTS * REFINE_ROUNDS + 1


def chunk_size(spec: StudySpec, n: int) -> int:
    """Samples per chunk for a model of ``n`` coordinates (a function of both only).

    Parameters
    ----------
    spec : StudySpec
    n : int
        The number of coordinates.

    Returns
    -------
    int
    """
    if any(q.kind == "nonlinear_amplitude" for q in spec.quantities):
        return NONLINEAR_CHUNK
    work = max(n, 1) ** 2 * points_per_sample(spec)
    return int(min(MAX_CHUNK, max(1, CHUNK_WORK // work)))


def chunks(spec: StudySpec, size: int, first: int = 0) -> Iterator[tuple[int, int, int]]:
    """``(k, start, stop)`` of every chunk from chunk ``first`` on.

    Parameters
    ----------
    spec : StudySpec
    size : int
        Samples per chunk.
    first : int
        The first chunk (when resuming).

    Yields
    ------
    tuple of int
    """
    total = spec.size
    for k in range(first, math.ceil(total / size)):
        yield k, k * size, min(total, (k + 1) * size)


def _open_unit(u: np.ndarray) -> np.ndarray:
    """Points of [0, 1) moved into (0, 1), so that inverse normal CDFs stay finite."""
    return np.clip(u, 2.0**-54, 1 - 2.0**-53)


def _random(spec: StudySpec, k: int, count: int) -> np.ndarray:
    rng = np.random.default_rng(np.random.SeedSequence(spec.seed, spawn_key=(k,)))
    if spec.design == "lhs":
        from scipy.stats import qmc

        return qmc.LatinHypercube(d=len(spec.vary), seed=rng).random(count)
    return rng.random((count, len(spec.vary)))


@functools.lru_cache(maxsize=2)
def _saltelli(base: int, dimensions: int, seed: int) -> np.ndarray:
    from SALib.sample import sobol

    problem = sobol_problem(dimensions)
    sample = sobol.sample(problem, base, calc_second_order=False, seed=seed)
    sample.flags.writeable = False
    return sample


def sobol_problem(dimensions: int) -> dict:
    """SALib's problem on the unit cube (inputs are mapped to their distributions after).

    Parameters
    ----------
    dimensions : int

    Returns
    -------
    dict
    """
    return {"num_vars": dimensions, "names": [f"u{i}" for i in range(dimensions)],
            "bounds": [[0.0, 1.0]] * dimensions}


def _grid(spec: StudySpec, start: int, stop: int) -> dict[str, np.ndarray]:
    axes = [d.grid(spec.samples) for d in spec.vary.values()]
    index = np.unravel_index(np.arange(start, stop), [len(a) for a in axes])
    return {name: axis[i] for name, axis, i in zip(spec.vary, axes, index)}


def chunk_values(spec: StudySpec, k: int, size: int) -> dict[str, np.ndarray]:
    """The varied parameters' values of chunk ``k`` (SI).

    Parameters
    ----------
    spec : StudySpec
    k : int
        The chunk.
    size : int
        Samples per chunk (:func:`chunk_size`).

    Returns
    -------
    dict
        parameter -> values, shape (rows of the chunk,).
    """
    start, stop = k * size, min(spec.size, (k + 1) * size)
    if spec.design == "grid":
        return _grid(spec, start, stop)
    if spec.design == "sobol":
        if spec.samples > MAX_SOBOL_BASE:
            raise ModelError(f"a Sobol design takes at most {MAX_SOBOL_BASE} base samples")
        u = _saltelli(spec.samples, len(spec.vary), spec.seed)[start:stop]
    else:
        u = _random(spec, k, stop - start)
    u = _open_unit(u)
    return {name: d.from_unit(u[:, j]) for j, (name, d) in enumerate(spec.vary.items())}


__all__ = ["chunk_size", "chunk_values", "chunks", "points_per_sample", "sobol_problem"]
