"""The steps of the worked solution, one function per step, in the exercise's order.

Each step takes the shared :class:`Context` (model, equation of motion,
stationary solution, derivation, equation counter) and returns a list of
blocks.  The order and notation follow the reference exercise "Practice 12 -
2 DoF forced system": Data; Task 1 (method, Eqs. (1)-(6); coordinates (7);
kinetic energy and M (8)-(20); potential energy and K (21)-(29); excitation
forces (30)-(34); the equation of motion (35)); Task 2 (stationary solution,
(36)-(44)); Task 3 (maximal excursions, (45)-(48)); then natural frequencies,
stability, plots and warnings.  A free-vibration model shows its modes
instead of Tasks 2 and 3.

"""

from __future__ import annotations

from collections.abc import Callable

import resonant.report.parts as part_steps

from ..blocks import Block
from .closing import plots, warnings
from .context import Context
from .correlation import measured_frfs, measured_modes
from .energies import coordinates, dissipation, kinetic, potential
from .excitation import equation_of_motion, forces
from .excursions import excursions
from .given_matrices import given_matrices
from .loads import periodic_load, random_load, shock_load
from .modal import natural_frequencies
from .opening import data, method, title
from .rotor import rotor
from .stationary_solution import stationary

# -- the order of the steps ------------------------------------------------------------------

Step = Callable[[Context], list[Block]]


def step_order(ctx: Context) -> list[Step]:
    """The steps for this model, in the exercise's order."""
    free = not ctx.eom.excitation
    if ctx.model.matrices is not None or ctx.derivation is None:
        steps: list[Step] = [title, data, given_matrices]
    elif ctx.model.parts is not None:  # the energies derived part by part (report/parts.py)
        steps = [title, data, method, coordinates, part_steps.kinetic, kinetic,
                 part_steps.after_heading(dissipation, part_steps.dissipation),
                 part_steps.after_heading(potential, part_steps.potential), forces,
                 equation_of_motion]
    else:
        steps = [title, data, method, coordinates, kinetic, dissipation, potential, forces,
                 equation_of_motion]
    if ctx.model.parts is not None:
        steps.insert(1, part_steps.figure)  # "In Fig. 1 ...": the figure first, as the exercise
    if free:
        steps.append(lambda c: natural_frequencies(c, with_modes=True))
    else:
        steps.extend([stationary, excursions, natural_frequencies, plots])
    steps.extend([periodic_load, random_load, shock_load])  # loads beyond a sine (docs/random.md)
    steps.append(measured_frfs)  # measured FRFs against the model's (testing.md)
    steps.append(measured_modes)  # a measurement's modes against the model's (testing.md)
    steps.append(rotor)  # the Campbell diagram and the unbalance response (docs/rotors.md)
    steps.append(warnings)
    return steps


__all__ = ["Context", "step_order"]
