"""The answer key of a set of variants (``key.json``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .variants import ExerciseSet

KEY_FORMAT = "resonant-exercise-key"

# -- key and Moodle -----------------------------------------------------------------------------

def key_data(batch: ExerciseSet) -> dict[str, Any]:
    """The answer key as JSON data.

    Parameters
    ----------
    batch : ExerciseSet
        The variants.

    Returns
    -------
    dict
        ``format``, ``seed``, ``tolerance`` and per variant its varied values, all
        parameters and every answer with its tolerance and unit.

    Examples
    --------
    >>> import resonant
    >>> from resonant.exercises import generate
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 2, seed=1)
    >>> data = key_data(batch)
    >>> data["format"], [v["variant"] for v in data["variants"]]
    ('resonant-exercise-key', [1, 2])
    """
    ex = batch.exercise
    return {
        "format": KEY_FORMAT, "version": 1,
        "model": Path(batch.model.source).name if batch.model.source else None,
        "title": batch.model.title,
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
