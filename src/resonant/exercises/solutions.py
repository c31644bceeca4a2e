"""A variant's worked solution: the report of ``resonant report`` on the shared derivation."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from ..errors import AnalysisError
from ..report.blocks import Report
from ..report.derivation import Derivation
from ..report.steps import Context, step_order
from .variants import Variant

# -- solutions ----------------------------------------------------------------------------

def solution_report(variant: Variant, derivation: Derivation | None, plots: bool) -> Report:
    """The worked solution of one variant (the report of ``resonant report``), built on the
    shared derivation.

    Parameters
    ----------
    variant : Variant
        The variant.
    derivation : Derivation or None
        The derivation shared by all variants (None: the solution starts from M, C, K).
    plots : bool
        Whether to include the figures.

    Returns
    -------
    Report
        The blocks of the solution.

    Examples
    --------
    >>> import resonant
    >>> from resonant.exercises import generate
    >>> batch = generate(resonant.load("examples/teaching/cart_pendulum.toml"), 2, seed=1)
    >>> solution_report(batch.variants[0], None, plots=False).title.endswith("variant 1")
    True
    """
    d = dataclasses.replace(derivation, model=variant.model) if derivation is not None \
        else None
    equations = variant.eom.symbolic()
    if equations is None:
        raise AnalysisError("a worked solution needs the system's equations in symbols")
    ctx = Context(variant.model, variant.eom, equations, variant.solution, d, plots=plots)
    blocks = []
    for step in step_order(ctx):
        blocks.extend(step(ctx))
    title = variant.model.title or Path(variant.model.source).stem or "Worked solution"
    return Report(f"{title} — variant {variant.number}", tuple(blocks))
