"""A rotor's worked solution (docs/rotors.md): the Campbell diagram over the ``[campbell]``
range with its critical speeds and stability threshold, and the unbalance response of the
``[[unbalance]]`` with the bearing forces, amplitudes said 0-pk and pk-pk.  The figures
are the results' own chart descriptions (:meth:`Campbell.chart
<resonant.analyses.campbell.Campbell.chart>`, :meth:`UnbalanceResponse.chart
<resonant.analyses.unbalance.UnbalanceResponse.chart>`)."""

from __future__ import annotations

import numpy as np

from ...analyses.campbell import RPM, Campbell, campbell
from ...analyses.unbalance import CONVENTION, UnbalanceResponse, unbalance_response
from ...errors import ResonantError
from ..blocks import Block, Heading, Note, Table, cell, paragraph
from .context import Context, _m

#: stations listed in the unbalance table (the first ones; it fits a phone)
SHOWN_STATIONS = 8


def _t(value: float) -> str:
    """A number as plain text for a table cell."""
    return f"{float(value):.5g}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")


def rotor(ctx: Context) -> list[Block]:
    """The Campbell diagram and the unbalance response of a model with ``[campbell]``."""
    if ctx.model.campbell_section is None:
        return []
    blocks: list[Block] = [Heading("Rotor: Campbell diagram, critical speeds, stability")]
    try:
        result = campbell(ctx.system)
    except ResonantError as exc:
        return blocks + [Note((f"The Campbell diagram cannot be computed: {exc}",))]
    blocks += _campbell_blocks(ctx, result)
    if ctx.model.unbalances:
        blocks.append(Heading("Rotor: unbalance response and bearing forces"))
        try:
            blocks += _unbalance_blocks(ctx, unbalance_response(ctx.system))
        except ResonantError as exc:
            blocks.append(Note((f"The unbalance response cannot be computed: {exc}",)))
    return blocks


def _campbell_blocks(ctx: Context, result: Campbell) -> list[Block]:
    blocks: list[Block] = [paragraph(
        "Spinning at the speed ", _m(r"\Omega"), ", the rotor obeys"),
        ctx.equation(r"\mathbf{M}\ddot{\mathbf{q}} + (\mathbf{C} + \Omega\,\mathbf{G})"
                     r"\dot{\mathbf{q}} + \mathbf{K}\mathbf{q} = \mathbf{0},", label="rotor"),
        paragraph(
            "with ", _m(r"\mathbf{G}"), " the skew gyroscopic matrix. Its complex modes ",
            _m(r"\mathbf{q}\,e^{st}"), " are solved at ", f"{len(result.speeds)} speeds "
            f"from {result.speeds[0] / RPM:.5g} to {result.speeds[-1] / RPM:.5g} rpm "
            f"({result.refined} added where two modes were hard to tell apart), each mode "
            "followed from speed to speed by the likeness of its shape (the modal "
            "assurance criterion). The damped frequency is ", _m(r"|\mathrm{Im}\,s|"),
            ", the logarithmic decrement ", _m(r"\delta = -2\pi\,\mathrm{Re}\,s / "
                                               r"\mathrm{Im}\,s"),
            ". A critical speed of order ", _m("r"), " is where a branch's frequency "
            "meets ", _m(r"r\,\Omega"), ":")]
    rows = tuple((cell(_t(c.speed / RPM)), cell(_t(c.speed)), cell(str(c.mode)),
                  cell(f"{c.order:g}x"), cell(c.whirl)) for c in result.critical_speeds)
    if rows:
        blocks.append(Table((cell("speed [rpm]"), cell("speed [rad/s]"), cell("mode"),
                             cell("order"), cell("whirl")), rows))
    else:
        blocks.append(paragraph("none lies in the range."))
    t = result.threshold
    if t.verdict == "threshold" and t.speed is not None:
        blocks.append(paragraph(
            f"The rotor is stable up to {t.speed / RPM:.5g} rpm ({t.speed:.5g} rad/s), where "
            f"the damping of mode {t.mode} ({t.whirl} whirl) crosses zero: above it the "
            "motion grows."))
    elif t.verdict == "unstable in range":
        blocks.append(paragraph(f"Mode {t.mode} is unstable at the first speed already."))
    else:
        blocks.append(paragraph("Every mode is damped (or undamped, neutral) over the whole "
                                "range: there is no threshold of instability in it."))
    if ctx.plots:
        blocks.append(ctx.figure(result.chart(), "The Campbell diagram (frequency against "
                                 "speed, with the excitation orders; dashed: backward "
                                 "whirl) above the logarithmic decrement of each branch."))
    return blocks


def _unbalance_blocks(ctx: Context, result: UnbalanceResponse) -> list[Block]:
    blocks: list[Block] = [paragraph(
        "An unbalance ", _m("m e"), " turning with the rotor loads it with ",
        _m(r"m e\,\Omega^{2}"), " rotating at ", _m(r"\Omega"), "; each station moves on an "
        "ellipse. Amplitudes here are ", f"{CONVENTION}.")]
    rows = []
    for i, name in enumerate(result.stations[:SHOWN_STATIONS]):
        k = int(np.nanargmax(result.major[:, i]))
        rows.append((cell(name or "(x, y)"), cell(_t(result.major[k, i])),
                     cell(_t(2 * result.major[k, i])), cell(_t(result.speeds[k] / RPM)),
                     cell(result.precession[k][i])))
    blocks.append(Table((cell("station"), cell("largest major semi-axis, 0-pk [m]"),
                         cell("pk-pk [m]"), cell("at [rpm]"), cell("whirl")), tuple(rows)))
    if result.bearings:
        blocks.append(paragraph(
            "Each bearing transmits the force ", _m(r"(\mathbf{K}_{b} + i\Omega\,"
                                                   r"\mathbf{C}_{b})(\mathbf{z}_{s} - "
                                                   r"\mathbf{z}_{p})"),
            " (station minus pedestal, or the ground):"))
        force_rows = []
        for i, name in enumerate(result.bearings):
            k = int(np.nanargmax(result.bearing_force[:, i]))
            force_rows.append((cell(name), cell(_t(result.bearing_force[k, i])),
                               cell(_t(2 * result.bearing_force[k, i])),
                               cell(_t(result.speeds[k] / RPM))))
        blocks.append(Table((cell("bearing"), cell("largest force, 0-pk [N]"),
                             cell("pk-pk [N]"), cell("at [rpm]")), tuple(force_rows)))
    if ctx.plots:
        blocks.append(ctx.figure(result.chart(), "The major semi-axis (0-pk) of each "
                                 "station's orbit against speed (top) and the phase lag of "
                                 "x behind the unbalance (bottom)."))
    return blocks
