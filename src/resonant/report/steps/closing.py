"""The closing steps: the figures of the response and the warnings."""

from __future__ import annotations

from ...charts import plain_text
from ...expressions.notation import name_latex
from ...model.units_display import result_units
from ..blocks import Block, Heading, Note
from ..plots import (
    follows_frequency,
    frequency_response,
    history_figure,
    operating_frequency,
    response_chart,
    time_history,
)
from .context import Context


def plots(ctx: Context) -> list[Block]:
    if not ctx.plots:
        return []

    sol = ctx.solution
    if not sol.available or not sol.harmonics:
        return []
    frf = frequency_response(ctx.system, sol)
    history = time_history(sol)
    if frf is None and history is None:
        return []
    blocks: list[Block] = [Heading("Frequency response and time history")]
    if frf is not None:
        follows = follows_frequency(ctx.eom, sol)
        parameter = plain_text(f"${name_latex(follows)}$") if follows else ""
        how = (f"the excitation frequency {parameter} is swept and the excitation "
               "amplitudes follow it" if follows else
               "the excitation amplitudes are held at their operating values")
        what = "coordinates and outputs" if len(frf.amplitudes) > ctx.n else "coordinates"
        units = result_units(ctx.model)
        chart = response_chart(frf, operating_frequency(sol), units.si if units else None)
        blocks.append(ctx.figure(chart, f"Amplitudes of the {what} against the excitation "
                                 f"frequency ({how}); dots: the operating point, dashed: the "
                                 "excitation frequency, dotted: the natural frequencies."))
    if history is not None:
        several = len([h for h in ctx.solution.harmonics if h.omega > 0]) > 1
        what = ("two periods of the excitation" if not several else
                f"two common periods (T = {history.period:.4g} s) of the excitation's "
                "frequencies" if history.periodic else
                "two periods of the slowest excitation frequency (the frequencies are "
                "incommensurate: the excitation is not periodic)")
        blocks.append(ctx.figure(history_figure(history), f"The stationary solution over {what}."))
    return blocks


def warnings(ctx: Context) -> list[Block]:
    if not ctx.solution.warnings:
        return []
    blocks: list[Block] = [Heading("Warnings")]
    blocks.extend(Note((w,)) for w in ctx.solution.warnings)
    return blocks
