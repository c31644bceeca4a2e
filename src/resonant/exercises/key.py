"""The answer key of a set of variants (``key.json``)."""

from __future__ import annotations

from typing import Any

from .variants import ExerciseSet

KEY_FORMAT = "resonant-exercise-key"

# -- key and Moodle -----------------------------------------------------------------------------

def key_data(batch: ExerciseSet) -> dict[str, Any]:
    """The answer key as JSON data."""
    ex = batch.exercise
    return {
        "format": KEY_FORMAT, "version": 1,
        "model": batch.model.source, "title": batch.model.title,
        "seed": batch.seed, "tolerance": ex.tolerance, "tolerance_kind": "relative",
        "answers": list(ex.answers),
        "variants": [{
            "variant": v.number,
            "varied": dict(v.values),
            "parameters": dict(v.model.parameter_values),
            "answers": {a.key: {"label": a.label, "value": a.value, "tolerance": ex.tolerance,
                                "unit": a.unit} for a in v.answers.values()},
        } for v in batch.variants],
        "replaced": [{"varied": dict(r.values), "reason": r.reason} for r in batch.replaced],
    }
