"""Measured FRFs checked against the model they are said to test, and the model's FRFs
at their lines (docs/testing.md, "The report").

A file of measured FRFs belongs to a model when

* it holds an FRF of every response channel of ``[measurement.channels]`` to every input
  of ``[measurement]`` (by name: the channel, or ``RESPONSE/INPUT`` with several inputs,
  :func:`resonant.analyses.frf_mimo.pair_name`), and no FRF of a response or an input the
  section does not name: the same number of responses and references;
* with one input, its FRFs share one reference (node and direction);
* where a function's response (or reference) node and direction name a coordinate of the
  model (``n1042_uz``: node 1042, direction +Z or -Z), it is the coordinate the channel (or
  the input) is mapped to;
* its lines overlap the model's band: the lowest to the highest undamped natural frequency.

:func:`match_test` refuses anything else with a :class:`~resonant.errors.ModelError` (exit
2) naming the file, what does not match and how to fix it, and returns a
:class:`MatchedTest`: the measured FRFs beside the model's, their FRAC and their figure.

Examples
--------
>>> import resonant
>>> from resonant.model.measured import MeasuredData, MeasuredFunction
>>> model = resonant.load("examples/chain3_lab.toml")
>>> system = resonant.system.linear_system(model)
>>> f = np.linspace(0.5, 12.0, 5)
>>> H = model_frf_matrix(system, ["F"], f, model.measurement_section.channels)
>>> data = MeasuredData("lab.uff", tuple(MeasuredFunction(c, "frf", f, H[:, k, 0], "Hz",
...                     "m/N") for k, c in enumerate(("d1", "d2", "d3"))))
>>> test = match_test(data, model.measurement_section, system, model.source)
>>> [round(float(x), 9) for x in test.frac[:, 0]]
[1.0, 1.0, 1.0]
>>> bad = MeasuredData("lab.uff", data.functions[:2])
>>> match_test(bad, model.measurement_section, system, "chain3_lab.toml")
Traceback (most recent call last):
resonant.errors.ModelError: chain3_lab.toml: [measurement.channels] d3: lab.uff has no \
channel 'd3' (its channels: d1, d2)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import COLORS, Chart, Charted, Charts, Curve
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..model.measured import MeasuredData, MeasuredFunction, read_uff
from ..model.measurement_spec import MeasurementSpec, match_channels, measurement_dofs
from ..model.op4_files import DIRECTIONS
from ..model.types import Model
from ..system.base import LinearSystem
from ..system.build import linear_system
from ..system.excitation import loaded_coordinates
from .correlate import Correlation, model_shapes
from .frf_mimo import frf_matrix_of, pair_name
from .frf_update import frac, model_frf_matrix
from .modes import modes
from .result_fields import FieldsJSON, saved
from .results_json import floats_json

__all__ = ["MatchedTest", "match_test", "match_test_file", "model_band", "dof_label",
           "check_correlation", "saved_dofs"]

#: the lowest modes computed for the band of a model above this many coordinates
BAND_MODES = 20
#: the most coordinates for which the band comes from every mode
DENSE_BAND = 200


@dataclass(frozen=True)
class MatchedTest(FieldsJSON, Charted):
    """Measured FRFs that belong to the model, beside the model's own at their lines.

    Attributes
    ----------
    source : str
        The measurement file (its name).
    frequency : ndarray
        The lines (Hz).
    measured, model : ndarray
        (lines, responses, inputs) complex: the test's FRFs and the model's.
    responses, inputs : tuple of str
        The response channels and the input (excitation) channels, in order.
    units : tuple of str
        The FRFs' unit of each response (``""`` where the file gives none).
    band : tuple of float
        The model's lowest and highest undamped natural frequency (Hz).
    model_inputs : tuple of str
        The model's signal or coordinate each input measures (``[measurement] input``), in
        the inputs' order (empty: not known, a test made by hand).
    acts_on : tuple of str
        The coordinates each input's load acts on, ``", "``-separated: a coordinate input
        its own, a signal those of its load columns
        (:func:`resonant.system.excitation.loaded_coordinates`); ``""`` for a signal that
        acts through outputs only.
    """

    source: str
    frequency: np.ndarray = saved(key="frequency_hz")
    measured: np.ndarray = saved(axes=("frequency", "responses", "inputs"))
    model: np.ndarray = saved(axes=("frequency", "responses", "inputs"))
    responses: tuple[str, ...] = ()
    inputs: tuple[str, ...] = ()
    units: tuple[str, ...] = ()
    band: tuple[float, ...] = saved((), key="band_hz")
    model_inputs: tuple[str, ...] = ()
    acts_on: tuple[str, ...] = ()

    _json_order = ("source", "frequency_hz", "measured", "model", "responses", "inputs",
                   "model_inputs", "acts_on", "units", "band_hz", "frac")

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def frac(self) -> np.ndarray:
        """(responses, inputs): the FRAC of each measured FRF with the model's (1: alike up
        to a complex factor; :func:`resonant.analyses.frf_update.frac`)."""
        return np.array([[frac(self.measured[:, r, i], self.model[:, r, i])
                          for i in range(len(self.inputs))]
                         for r in range(len(self.responses))])

    def input_label(self, i: int) -> str:
        """What input ``i`` is in the model: ``"the model's x1"`` for a coordinate,
        ``"the model's F1, on x1"`` for a signal (``"..., through outputs only"`` where it
        loads no coordinate); ``""`` where the test does not say.

        Parameters
        ----------
        i : int

        Returns
        -------
        str

        Examples
        --------
        >>> f = np.array([1.0])
        >>> test = MatchedTest("lab.uff", f, np.ones((1, 1, 2)), np.ones((1, 1, 2)), ("d1",),
        ...                    ("hammer", "shaker"), ("m/N",), (1.0, 2.0), ("F", "x1"),
        ...                    ("x3", "x1"))
        >>> test.input_label(0), test.input_label(1)
        ("the model's F, on x3", "the model's x1")
        """
        if i >= len(self.model_inputs):
            return ""
        name = self.model_inputs[i]
        acts = self.acts_on[i] if i < len(self.acts_on) else name
        if acts == name:
            return f"the model's {name}"
        return f"the model's {name}, " + (f"on {acts}" if acts else "through outputs only")

    def chart(self) -> Charts:
        """|H| of each response measured (solid) and the model's (dashed), a panel per
        input; with several, the panels' one legend once (over the first panel in SVG,
        under the figure with matplotlib, where it hides no curve).

        Returns
        -------
        Charts
        """
        f = np.asarray(self.frequency)
        xlim = (float(f[0]), float(f[-1]))
        unit = next((u for u in self.units if u), "")
        several = len(self.inputs) > 1
        panels = []
        for i, name in enumerate(self.inputs):
            curves = []
            for r, response in enumerate(self.responses):
                color = COLORS[r % len(COLORS)]
                curves.append(Curve(f, np.abs(self.measured[:, r, i]),
                                    f"{response} (measured)", color))
                curves.append(Curve(f, np.abs(self.model[:, r, i]), f"{response} (model)",
                                    color, dash="3.7 1.6"))
            label = self.input_label(i)
            title = (f"input {name}" + (f" ({label})" if label else "")) if several else ""
            panels.append(Chart(tuple(curves), "frequency [Hz]",
                                f"|H| [{unit}]" if unit else "|H|", xlim, ylog=True,
                                title=title, legend="none" if i else "best"))
        to = "" if several or not self.inputs else f" to {self.inputs[0]}" + (
            f" ({self.input_label(0)})" if self.input_label(0) else "")
        return Charts(tuple(panels), title=f"measured ({self.source}) and model FRFs{to}",
                      size=(7.0, 3.2 * len(panels) + (0.8 if several else 0.0)),
                      legend="below" if several else "panels")

    def _derived_json(self) -> dict[str, Any]:
        return {"frac": floats_json(self.frac)}


def dof_label(node: int, direction: int) -> str:
    """The coordinate name of a node and a Universal File direction code (the FE imports'
    names: ``n1042_uz``; a scalar point, direction 0, ``n1042``).

    Parameters
    ----------
    node : int
    direction : int
        1-6 (+X, +Y, +Z, +RX, +RY, +RZ), negative for the opposite sense, 0 for a scalar.

    Returns
    -------
    str

    Examples
    --------
    >>> dof_label(1042, -3), dof_label(7, 0)
    ('n1042_uz', 'n7')
    """
    code = abs(int(direction))
    return f"n{int(node)}_{DIRECTIONS[code]}" if code in DIRECTIONS else f"n{int(node)}"


def saved_dofs(spec: MeasurementSpec, system: LinearSystem,
               deadline: Deadline = NO_DEADLINE) -> dict[str, tuple[int, int]]:
    """The node and direction of every channel of ``[measurement]`` that a saved file
    carries (:func:`resonant.model.measurement_spec.measurement_dofs`), an input that is a
    signal traced to the coordinate its load acts on
    (:func:`resonant.system.excitation.loaded_coordinates`).

    Parameters
    ----------
    spec : MeasurementSpec
    system : LinearSystem
        The model's system.
    deadline : Deadline, optional

    Returns
    -------
    dict
        Channel (response or excitation) -> (node, direction).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/chain3_lab.toml")
    >>> saved_dofs(model.measurement_section, model.linearize())   # the hammer's F on x3
    {'d1': (1, 0), 'd2': (2, 0), 'd3': (3, 0), 'hammer': (3, 0)}
    """
    signals = [name for name in spec.model_inputs if name not in system.coordinates]
    acts = loaded_coordinates(system, signals, deadline) if signals else {}
    return measurement_dofs(spec, system.coordinates, acts)


def model_band(system: LinearSystem, deadline: Deadline = NO_DEADLINE) -> tuple[float, float]:
    """The model's lowest and highest undamped natural frequency above zero (Hz).

    Above :data:`DENSE_BAND` coordinates, the highest of the lowest :data:`BAND_MODES`.

    Parameters
    ----------
    system : LinearSystem
    deadline : Deadline, optional

    Returns
    -------
    tuple of float
        (0, 0) for a model without an elastic mode.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_lab.toml").linearize()
    >>> [round(x, 4) for x in model_band(system)]
    [2.2399, 9.069]
    """
    count = None if system.n <= DENSE_BAND else BAND_MODES
    omega = np.asarray(modes(system, count=count, deadline=deadline).natural_frequencies)
    hz = omega[np.isfinite(omega) & (omega > 0)] / (2 * np.pi)
    return (float(hz.min()), float(hz.max())) if hz.size else (0.0, 0.0)


def _frfs_of(data: MeasuredData, spec: MeasurementSpec, source: str
             ) -> tuple[list[str], dict[str, MeasuredFunction]]:
    """The input channels and the FRFs of the file by their matrix names, after the
    checks of names and counts."""
    frfs = [f for f in data.functions if f.kind == "frf"]
    if not frfs:
        raise ModelError(Problem("the file holds no FRF (dataset 58, function type 4): give "
                                 "the FRFs resonant frf --save writes, or the JSON of "
                                 "resonant correlate --json", data.source))
    inputs = [r[0] for r in spec.references] or [spec.excitation or "input"]
    single = not spec.references
    named = {pair_name(f.name, inputs[0]) if single else f.name: f for f in frfs}
    if single:
        match_channels(MeasurementSpec("", spec.input, spec.channels), [f.name for f in frfs],
                       source, data.source)
    wanted = {pair_name(c, i) for c in spec.channels for i in inputs}
    extra = [f.name for key, f in named.items() if key not in wanted]
    if extra:
        raise ModelError(Problem(
            f"{printable(data.source)} holds {len(named)} FRFs, the model's [measurement] "
            f"maps {len(spec.channels)} responses x {len(inputs)} input"
            f"{'s' if len(inputs) > 1 else ''}: "
            f"{', '.join(printable(n, limit=40) for n in extra[:6])} "
            f"{'is' if len(extra) == 1 else 'are'} not in it (map "
            f"{'it' if len(extra) == 1 else 'them'} in [measurement.channels] and "
            "[measurement] excitation, or leave them out of the file)",
            source, "measurement.channels"))
    references = sorted({f.reference for f in frfs})
    if single and len(references) > 1:
        shown = ", ".join(f"node {n} direction {d}" for n, d in references[:4])
        raise ModelError(Problem(
            f"{printable(data.source)} holds FRFs to {len(references)} references ({shown}) "
            "and [measurement] names one input: name each excitation channel and its input "
            "as lists of one length (docs/testing.md, several references)", source,
            "measurement", "excitation"))
    return inputs, named


def _check_dofs(named: dict[str, MeasuredFunction], spec: MeasurementSpec,
                coordinates: Sequence[str], acts: dict[str, tuple[str, ...]],
                data: MeasuredData, source: str) -> None:
    """A function's response (reference) node and direction that name a coordinate of the
    model must name the channel's (one the input's load acts on: ``acts``, input ->
    coordinates; a signal input is traced through its load columns)."""
    known = set(coordinates)
    inputs = dict(spec.references) or {spec.excitation or "input": spec.input}
    problems = []
    for key, f in named.items():
        channel, _, excitation = key.rpartition("/")
        given = inputs.get(excitation, "")
        checks = [("response", f.response, spec.channels[channel].name,
                   (spec.channels[channel].name,), "measurement.channels", channel),
                  ("reference", f.reference, given, acts.get(given, (given,)), "measurement",
                   "input")]
        for what, (node, direction), mapped, places, section, entry in checks:
            label = dof_label(node, direction) if node > 0 else ""
            if label in known and known.intersection(places) and label not in places:
                where = mapped if places == (mapped,) else \
                    f"{mapped}, whose load acts on {', '.join(places)}"
                problems.append(Problem(
                    f"{printable(data.source)}: the {what} of FRF "
                    f"'{printable(f.name, limit=40)}' is node {node} direction {direction}, "
                    f"the model's coordinate {label}; [measurement] maps it to {where} (map "
                    f"the {'channel' if what == 'response' else 'input'} to {label}, or "
                    "correct the file's node)", source, section, entry))
    if problems:
        raise ModelError(problems[:8])


def match_test(data: MeasuredData, spec: MeasurementSpec, system: LinearSystem, source: str,
               *, deadline: Deadline = NO_DEADLINE) -> MatchedTest:
    """The measured FRFs of ``data`` checked against the model, with the model's FRFs.

    Parameters
    ----------
    data : MeasuredData
        The measurement (a Universal File's functions).
    spec : MeasurementSpec
        The model's ``[measurement]`` section.
    system : LinearSystem
        The model's system.
    source : str
        The model file (named in the errors).
    deadline : Deadline, optional

    Returns
    -------
    MatchedTest

    Raises
    ------
    ModelError
        For a file that does not belong to the model (module docstring: what is checked).
    """
    if not spec.input:
        raise ModelError(Problem("the model's FRFs need the input they are measured to: name "
                                 "it (a signal or coordinate)", source, "measurement", "input"))
    inputs, named = _frfs_of(data, spec, source)
    acts = loaded_coordinates(system, spec.model_inputs, deadline)
    _check_dofs(named, spec, system.coordinates, acts, data, source)
    renamed = MeasuredData(data.source, tuple(dataclasses.replace(f, name=key)
                                              for key, f in named.items()))
    f, H, units = frf_matrix_of(renamed, list(spec.channels), inputs)
    low, high = model_band(system, deadline)
    if not (f[0] <= high and f[-1] >= low):
        raise ModelError(Problem(
            f"{printable(data.source)}'s lines, {f[0]:.6g} to {f[-1]:.6g} Hz, do not overlap "
            f"the model's natural frequencies, {low:.6g} to {high:.6g} Hz: a test of another "
            "structure, or a frequency axis in other units (rad/s for Hz?)", source,
            "measurement"))
    model = model_frf_matrix(system, spec.model_inputs, f, spec.channels, deadline=deadline)
    return MatchedTest(data.source, f, H, model, tuple(spec.channels), tuple(inputs),
                       tuple(units[c] for c in spec.channels), (low, high),
                       tuple(spec.model_inputs),
                       tuple(", ".join(acts[m]) for m in spec.model_inputs))


def check_correlation(correlation: Correlation, system: LinearSystem, name: str, *,
                      deadline: Deadline = NO_DEADLINE) -> None:
    """Check that a saved correlation was made with this model: its model frequencies are
    the model's undamped natural frequencies (all of them, to 1e-6 relative).

    Parameters
    ----------
    correlation : Correlation
        As ``resonant correlate --json`` saved it.
    system : LinearSystem
        The model's system.
    name : str
        The correlation's file (named in the error).
    deadline : Deadline, optional

    Raises
    ------
    ModelError
        Naming the first frequency that differs, or the counts.

    Examples
    --------
    >>> import resonant
    >>> from resonant.analyses.correlate import correlate_shapes
    >>> system = resonant.load("examples/chain3_lab.toml").linearize()
    >>> c = correlate_shapes(np.array([2.3]), np.ones((1, 1)), np.array([2.3]),
    ...                      np.ones((1, 1)))
    >>> check_correlation(c, system, "mac.json")
    Traceback (most recent call last):
    resonant.errors.ModelError: mac.json: made with a model of 1 modes; this model has 3 \
(2.2399 to 9.069 Hz): run resonant correlate --json with this model
    """
    mine, _ = model_shapes(system, {}, deadline=deadline)
    saved = np.asarray(correlation.model_frequency, dtype=float)
    span = f"{mine.min():.5g} to {mine.max():.5g} Hz" if mine.size else "none"
    fix = "run resonant correlate --json with this model"
    if saved.shape != mine.shape:
        raise ModelError(Problem(f"made with a model of {saved.size} modes; this model has "
                                 f"{mine.size} ({span}): {fix}", name))
    scale = max(float(np.max(np.abs(mine), initial=0.0)), 1e-300)
    off = np.flatnonzero(np.abs(saved - mine) > 1e-6 * np.maximum(np.abs(mine), 1e-6 * scale))
    if off.size:
        k = int(off[0])
        raise ModelError(Problem(f"made with another model: its mode {k + 1} is at "
                                 f"{saved[k]:.6g} Hz, this model's at {mine[k]:.6g} Hz: {fix}",
                                 name))


def match_test_file(path: str, model: Model, deadline: Deadline = NO_DEADLINE) -> MatchedTest:
    """The measured FRFs of a Universal File checked against the model (``--test FILE`` of
    ``resonant report`` and ``resonant explore``).

    Parameters
    ----------
    path : str
        The file.
    model : Model
        The model, with its ``[measurement]`` section.
    deadline : Deadline, optional

    Returns
    -------
    MatchedTest

    Raises
    ------
    ModelError
        For a model without ``[measurement]``, a file that cannot be read, or one that does
        not belong to the model (:func:`match_test`).
    """
    spec = model.measurement_section
    if spec is None:
        raise ModelError(Problem("measured FRFs need the model's [measurement] section: add "
                                 "one naming the excitation channel, the input and the "
                                 "response channels (docs/testing.md)", model.source,
                                 "measurement"))
    return match_test(read_uff(path), spec, linear_system(model, deadline), model.source,
                      deadline=deadline)
