"""The test against the model: identified modes paired with the model's by the MAC, their
frequency errors, and the figure of both (docs/testing.md).  Shown when the report is given
a :class:`~resonant.analyses.correlate.Correlation` (``resonant correlate --json``, read by
``resonant report --test FILE``); its figure is the correlation's own chart."""

from __future__ import annotations

import math

import numpy as np

from ..blocks import Block, Heading, Note, Table, cell, paragraph
from .context import Context, _m

#: paired MACs below this are pointed out (a pair that is not the same shape)
LOW_MAC = 0.9


def _t(value: float, digits: int = 4) -> str:
    return f"{float(value):.{digits}g}" if math.isfinite(value) else "-"


def measured_modes(ctx: Context) -> list[Block]:
    """The pairs, MACs and frequency errors of the report's correlation (none: nothing)."""
    c = ctx.correlation
    if c is None:
        return []
    blocks: list[Block] = [Heading("Test against model")]
    blocks.append(paragraph(
        f"{len(c.test_frequency)} modes identified from the measured frequency response "
        f"functions are compared with the model's {len(c.model_frequency)} by the modal "
        "assurance criterion of the test shape ", _m(r"\phi_{j}"), " and the model shape ",
        _m(r"\psi_{k}"), " at the measured channels:"))
    blocks.append(ctx.equation(
        r"\mathrm{MAC}_{jk} = \frac{|\phi_{j}^{H}\psi_{k}|^{2}}"
        r"{(\phi_{j}^{H}\phi_{j})(\psi_{k}^{H}\psi_{k})}", "mac"))
    blocks.append(paragraph(
        "Each test mode is paired with the model mode that maximizes the sum of the paired "
        "MACs (two close test modes are not both paired with one model mode); the frequency "
        "error of a pair is ", _m(r"(f_{\mathrm{test}} - f_{\mathrm{model}})/f_{\mathrm{model}}"),
        "."))
    header = (cell("test mode"), cell(_m(r"f_{\mathrm{test}}"), " [Hz]"), cell("model mode"),
              cell(_m(r"f_{\mathrm{model}}"), " [Hz]"), cell("error [%]"), cell("MAC"))
    rows = []
    for j, k in enumerate(c.pairs):
        paired = k >= 0
        rows.append((cell(str(j + 1)), cell(_t(c.test_frequency[j])),
                     cell(str(k + 1) if paired else "none"),
                     cell(_t(c.model_frequency[k]) if paired else "-"),
                     cell(_t(100 * c.frequency_error[j], 3)),
                     cell(_t(c.paired_mac[j], 4))))
    blocks.append(Table(header, tuple(rows)))
    if ctx.plots and len(c.pairs):
        blocks.append(ctx.figure(c.chart(), "The MAC of each test mode with its paired model "
                                 "mode (top) and their frequency errors (bottom)."))
    low = [j + 1 for j, m in enumerate(c.paired_mac) if not m >= LOW_MAC]
    if low:
        blocks.append(Note((f"Test mode{'s' if len(low) > 1 else ''} "
                            f"{', '.join(map(str, low))}: no model mode of MAC above "
                            f"{LOW_MAC:g}; the shape is not the model's (a mode the model "
                            "lacks, a channel mapped to the wrong coordinate, or noise).",)))
    off = np.abs(c.auto_mac_test - np.eye(len(c.test_frequency)))
    if off.size and float(off.max()) > LOW_MAC:
        blocks.append(Note(("Two identified shapes have an auto-MAC above "
                            f"{LOW_MAC:g}: too few channels to tell them apart.",)))
    return blocks


def measured_frfs(ctx: Context) -> list[Block]:
    """The measured FRFs beside the model's, with their FRAC (none given: nothing)."""
    t = ctx.measured
    if t is None:
        return []
    several = len(t.inputs) > 1
    # what each input is in the model comes from the test itself (it names the model's
    # input and the coordinates its load acts on)
    named = [f"{name}: {t.input_label(i)}" if t.input_label(i) else name
             for i, name in enumerate(t.inputs)]
    inputs = (f"{len(t.inputs)} inputs ({'; '.join(named)})" if several
              else f"1 input ({named[0]})" if t.inputs else "1 input")
    blocks: list[Block] = [Heading("Measured against model FRFs")]
    blocks.append(paragraph(
        f"The file {t.source} holds the frequency response functions of "
        f"{len(t.responses)} response channel{'s' if len(t.responses) > 1 else ''} to "
        f"{inputs}, at {len(t.frequency)} lines from "
        f"{_t(t.frequency[0])} to {_t(t.frequency[-1])} Hz (the model's natural frequencies: "
        f"{_t(t.band[0])} to {_t(t.band[1])} Hz).  Each is compared with the model's own FRF "
        "H at the same lines by the frequency response assurance criterion ",
        _m(r"\mathrm{FRAC} = |H_{\mathrm{test}}^{H} H|^{2} / "
           r"((H_{\mathrm{test}}^{H} H_{\mathrm{test}})(H^{H} H))"),
        " (1: the same curve up to a complex factor):"))
    header = (cell("response"), *(cell(f"FRAC to {i}") for i in t.inputs))
    rows = tuple((cell(r), *(cell(_t(x, 4)) for x in row))
                 for r, row in zip(t.responses, t.frac, strict=True))
    blocks.append(Table(header, rows))
    if ctx.plots:
        blocks.append(ctx.figure(t.chart(), "The measured |H| of each response (solid) and "
                                 "the model's (dashed)" + (", a panel per input." if several
                                                           else ".")))
    return blocks
