"""The report's section "Beyond small oscillations" (``resonant report --nonlinear``).

For a model with one harmonic excitation frequency, the periodic steady state of the
full (not linearized) equations is followed by harmonic balance over a range around
the operating frequency (:func:`resonant.analyses.harmonic_balance.nonlinear_sweep`),
and solved at the operating point itself
(:func:`resonant.analyses.periodic.periodic_solution`).  The section shows the
nonlinear frequency-response curve beside the linear one with the operating point
marked, the special points (folds, changes of stability), and a table of the
amplitudes at the operating point: linear, nonlinear, and their difference.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ..analyses.harmonic_balance import nonlinear_sweep
from ..analyses.nonlinear_response import NonlinearResponse, nonlinear_response_chart
from ..analyses.periodic import PeriodicSolution, periodic_solution
from ..charts import Chart, draw_chart
from ..errors import AnalysisError
from ..expressions.notation import number_text
from ..model.units_display import name_label as _label
from ..system.build import nonlinear_system
from ..system.nonlinear import NonlinearSystem
from .blocks import Block, Heading, Math, Note, Table, cell, paragraph
from .plots import _swept_parameter
from .steps import Context

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

#: the curve runs over [LOW, HIGH] times the operating frequency
LOW, HIGH = 0.6, 1.5
#: about this many steps of the continuation across the range
POINTS = 80


@dataclass(frozen=True)
class NonlinearCurve:
    """The nonlinear frequency-response curve with the operating point (plot data)."""

    response: NonlinearResponse
    operating: float
    operating_amplitudes: dict[str, float]

    def chart(self) -> Chart:
        """What its figure shows: the view's chart of the curve, the operating point starred
        (:func:`resonant.analyses.nonlinear_response.nonlinear_response_chart`)."""
        return replace(nonlinear_response_chart(
            self.response, title=False, operating=(self.operating, self.operating_amplitudes)),
            legend="best")

    def draw(self, figure: Figure) -> None:
        draw_chart(self.chart(), figure)
        figure.tight_layout()

    def to_dict(self) -> dict:
        return {"operating": self.operating, "operating_amplitudes": self.operating_amplitudes,
                "curve": self.response.to_dict()}


def _difference(a: float, linear: float) -> str:
    return f"{100 * (a / linear - 1):+.3g} %" if linear > 0 else "-"


def _operating_point(periodic: PeriodicSolution) -> list[Block]:
    """The periodic solution at the operating point against the linear amplitudes."""
    blocks: list[Block] = []
    rows = []
    for name in periodic.coordinates:
        lin = periodic.linear_amplitudes.get(name, float("nan"))
        a = periodic.amplitudes[name]
        rows.append((cell(Math(f"{_label(name)[1:-1]}")), cell(number_text(lin)),
                     cell(number_text(a)), cell(_difference(a, lin))))
    blocks.append(paragraph(
        "At the operating point the periodic solution of the full equations "
        f"(H = {periodic.harmonics}, period {number_text(periodic.period)} s, residual "
        f"{periodic.residual:.2g}) is {'stable' if periodic.stable else 'unstable'}"
        + (" (undamped: the multipliers lie on the unit circle)"
           if periodic.stable and np.allclose(np.abs(periodic.multipliers), 1, atol=1e-6)
           else "")
        + ". Its peak amplitudes against the linear ones:"))
    blocks.append(Table((cell("coordinate"), cell("linear"), cell("full equations"),
                         cell("difference")), tuple(rows)))
    worst = max(periodic.relative_difference.items(), key=lambda kv: abs(kv[1]),
                default=None)
    if worst is not None:
        blocks.append(paragraph(
            f"The largest difference is {100 * worst[1]:+.3g} % ({worst[0]}): "
            + ("small oscillations hold to within 1 %." if abs(worst[1]) < 0.01 else
               "the small-oscillation answer is off by that much.")))
    return blocks


def beyond_small_oscillations(ctx: Context) -> list[Block]:
    """The step: the nonlinear curve, the operating point on it, the difference to linear."""
    blocks: list[Block] = [Heading("Beyond small oscillations")]
    model = ctx.model
    if model.matrices is not None:
        blocks.append(Note(("A [matrices] model's equations are its given matrices: where it "
                            "has no [[nonlinear]] elements they are linear and the results "
                            "above are exact; the steady state with its elements is the "
                            "nonlinear frequency response's (docs/nonlinear.md).",)))
        return blocks
    blocks.append(paragraph(
        "The results above hold for small oscillations. Without linearizing, Lagrange's "
        "equations of the same energies and forces are solved for the periodic steady state "
        "by harmonic balance: every coordinate is a Fourier series of the excitation's base "
        "frequency, ", Math(r"q(t) = a_0 + \sum_{k=1}^{H} a_k\cos k\Omega t + b_k\sin k\Omega "
                            r"t"), ", whose coefficients make the equations' harmonics vanish "
        "(Newton's method, the nonlinear terms sampled over one period). Its stability comes "
        "from the Floquet multipliers (Hill's method)."))
    system: NonlinearSystem = nonlinear_system(ctx.system)  # compiled once for both analyses
    try:
        periodic: PeriodicSolution | None = periodic_solution(system)
    except AnalysisError as exc:
        periodic = None
        blocks.append(Note((f"No periodic solution of the full equations was found near the "
                            f"linear stationary solution at the operating point: {exc}",)))
    moving = [h.omega for h in ctx.solution.harmonics if h.omega > 0]
    parameter = _swept_parameter(ctx.eom, moving[0]) if len(moving) == 1 else None
    curve: NonlinearResponse | None = None
    if parameter is not None:
        w0 = moving[0]
        try:
            curve = nonlinear_sweep(system, parameter, LOW * w0, HIGH * w0, points=POINTS)
        except AnalysisError as exc:
            blocks.append(Note((f"The nonlinear frequency-response curve could not be "
                                f"followed: {exc}",)))
    if curve is not None and ctx.plots:
        amplitudes = dict(periodic.amplitudes) if periodic is not None else {}
        blocks.append(ctx.figure(
            NonlinearCurve(curve, moving[0], amplitudes),
            f"Peak amplitudes of the periodic steady state of the full equations against "
            f"the excitation frequency {parameter} (harmonic balance, H = {curve.harmonics}; "
            "solid: stable, dashed: unstable, open markers: special points, the peaks open "
            "stars), the linear response dotted, the operating point a filled star."))
    if curve is not None:
        if curve.special_points:
            items = "; ".join(
                (f"the peak of {p.quantity}" if p.kind == "peak" else p.kind)
                + f" at {parameter} = {number_text(p.value)}" for p in curve.special_points)
            blocks.append(paragraph(f"Special points between {parameter} = "
                                    f"{number_text(curve.start)} and "
                                    f"{number_text(curve.stop)}: {items}."))
        else:
            blocks.append(paragraph(
                f"Between {parameter} = {number_text(curve.start)} and "
                f"{number_text(curve.stop)} the curve has no fold, no change of stability and "
                "no peak"
                + (" (every point stable)." if curve.stable.all() else ".")))
        blocks.extend(Note((w,)) for w in curve.warnings)
    if periodic is not None:
        blocks.extend(_operating_point(periodic))
    return blocks


__all__ = ["NonlinearCurve", "beyond_small_oscillations"]
