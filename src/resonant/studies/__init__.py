"""Layer between the analyses and the views: parameter studies of a model.

A study evaluates quantities of a model at many samples of its parameters
(docs/studies.md): :mod:`.designs` draws the samples chunk by chunk,
:mod:`.quantities` evaluates a chunk with the batched kernel (:mod:`.nonlinear`
the nonlinear steady state, sample by sample), :mod:`.engine`
runs chunks on Dask (in this process, local workers or a cluster),
:mod:`.files` streams the rows to Parquet or CSV, :mod:`.run` ties them
together, :mod:`.result` summarizes (SALib for Sobol indices).
"""

from __future__ import annotations

from .engine import Engine, engine_for, ordered_map
from .result import StudyResult, sobol_indices, summary_table
from .run import (
    RunSummary,
    StudyJob,
    collect,
    evaluate_chunk,
    model_text,
    read_table,
    request,
    run_study,
    study_of,
)

__all__ = ["Engine", "RunSummary", "StudyJob", "StudyResult", "collect", "engine_for",
           "evaluate_chunk", "model_text", "ordered_map", "read_table", "request", "run_study",
           "sobol_indices", "study_of", "summary_table"]
