"""The ``[measurement]`` section: which measured channel is which quantity of the model
(docs/testing.md).

.. code-block:: toml

    [measurement]
    excitation = "hammer"     # the channel that measures the input (a force)
    input = "F"               # the model's signal or coordinate that channel is
    [measurement.channels]    # response channel = coordinate or output, ' per derivative
    a1 = "x1''"               # an accelerometer on mass 1
    a3 = "x3''"

Several inputs measured together (two shakers; the H1 matrix,
:func:`resonant.analyses.frf_mimo.frf_matrix_from_measurement`) are lists of one length:
``excitation = ["shaker1", "shaker2"]``, ``input = ["F", "x1"]``.

Examples
--------
>>> problems = []
>>> spec = parse_measurement({"excitation": "hammer", "input": "F",
...                           "channels": {"a3": "x3''"}}, ["F"], ["x1", "x3"], [],
...                           "m.toml", problems)
>>> spec.channels["a3"], problems
(ChannelMap(name='x3', derivative=2), [])
>>> parse_measurement({"input": "G", "channels": {"a": "y"}}, ["F"], ["x"], [], "m.toml",
...                   problems)
>>> print(problems[0])
m.toml: [measurement] input: 'G' is neither a signal nor a coordinate of the model (signals: \
F; coordinates: x)
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType

from ..errors import ModelError, Problem, name_list, printable
from .op4_files import dof_of

#: the keys of ``[measurement]``
MEASUREMENT_KEYS = ("excitation", "input", "channels")
#: most channels mapped
MAX_CHANNELS = 4096
#: most inputs (excitation channels) of one measurement
MAX_INPUTS = 16

__all__ = ["ChannelMap", "MeasurementSpec", "parse_measurement", "match_channels",
           "measurement_dofs", "position_dofs", "MEASUREMENT_KEYS"]


@dataclass(frozen=True)
class ChannelMap:
    """A measured channel's quantity: a coordinate or output and its time derivative.

    Parameters
    ----------
    name : str
        The coordinate or output.
    derivative : int
        0 (displacement), 1 (velocity) or 2 (acceleration).
    """

    name: str
    derivative: int = 0


@dataclass(frozen=True)
class MeasurementSpec:
    """The ``[measurement]`` section.

    Parameters
    ----------
    excitation : str
        The channel of the input (``""`` when the file has FRFs only).
    input : str
        The model's signal or coordinate the input channel measures.
    channels : mapping
        Response channel name -> :class:`ChannelMap`.
    references : tuple of (str, str)
        With several inputs (``excitation`` and ``input`` given as lists of one length):
        each input's (channel, model signal or coordinate); ``excitation`` and ``input``
        are then the first.  Empty with one input.
    """

    excitation: str
    input: str
    channels: Mapping[str, ChannelMap]
    references: tuple[tuple[str, str], ...] = ()

    @property
    def model_inputs(self) -> tuple[str, ...]:
        """The model's signal or coordinate of each input, in order (the FRFs' columns).

        Returns
        -------
        tuple of str
        """
        return tuple(s for _, s in self.references) or (self.input,)


def parse_measurement(data: object, signals: Sequence[str], coordinates: Sequence[str],
                      outputs: Sequence[str], source: str, problems: list[Problem]
                      ) -> MeasurementSpec | None:
    """The ``[measurement]`` section, its problems appended to ``problems``.

    Parameters
    ----------
    data : Any
        The section as read from TOML.
    signals, coordinates, outputs : sequence of str
        The model's names.
    source : str
        The model file.
    problems : list of Problem
        Receives every problem found.

    Returns
    -------
    MeasurementSpec or None
        None when the section has problems.
    """
    section = "measurement"
    count = len(problems)
    if not isinstance(data, dict):
        problems.append(Problem("expected a table", source, section))
        return None
    for key in data:
        if key not in MEASUREMENT_KEYS:
            close = difflib.get_close_matches(str(key), MEASUREMENT_KEYS, n=1)
            hint = f"did you mean '{close[0]}'?" if close else \
                f"known: {', '.join(MEASUREMENT_KEYS)}"
            problems.append(Problem(f"unknown key '{printable(key, limit=40)}'; {hint}",
                                    source, section, str(key)))
    excitations = _names(data.get("excitation", ""), "the name of a channel", source,
                         "excitation", problems)
    inputs = _names(data.get("input", ""), "a signal or coordinate", source, "input",
                    problems)
    for given in inputs:
        if given and given not in (*signals, *coordinates):
            problems.append(Problem(
                f"'{printable(given, limit=40)}' is neither a signal nor a coordinate of the "
                f"model (signals: {name_list(signals) or 'none'}; coordinates: "
                f"{name_list(coordinates) or 'none'})", source, section, "input"))
    several = isinstance(data.get("excitation"), list) or isinstance(data.get("input"), list)
    if several and len(excitations) != len(inputs):
        problems.append(Problem(f"{len(excitations)} excitation channels for {len(inputs)} "
                                "inputs: give one input per excitation channel, in order",
                                source, section, "input"))
    channels = _channels(data.get("channels"), [*coordinates, *outputs], source, problems)
    if len(problems) > count:
        return None
    references = tuple(zip(excitations, inputs, strict=True)) if several else ()
    return MeasurementSpec(excitations[0] if excitations else "",
                           inputs[0] if inputs else "", MappingProxyType(channels),
                           references)


def _names(value: object, what: str, source: str, key: str, problems: list[Problem]
           ) -> list[str]:
    """A name, or a list of 1 to :data:`MAX_INPUTS` distinct names (several inputs)."""
    if isinstance(value, str):
        return [value]
    if isinstance(value, list) and 1 <= len(value) <= MAX_INPUTS and all(
            isinstance(v, str) and v for v in value) and len(set(value)) == len(value):
        return [str(v) for v in value]
    problems.append(Problem(f"expected {what}, or a list of 1 to {MAX_INPUTS} distinct ones "
                            "(several inputs)", source, "measurement", key))
    return []


def _channels(table: object, names: Sequence[str], source: str, problems: list[Problem]
              ) -> dict[str, ChannelMap]:
    section = "measurement.channels"
    if not isinstance(table, dict) or not table:
        problems.append(Problem("expected a table of channel = \"coordinate or output\" "
                                "(with ' for each time derivative)", source, section))
        return {}
    if len(table) > MAX_CHANNELS:
        problems.append(Problem(f"{len(table)} channels; at most {MAX_CHANNELS}", source,
                                section))
        return {}
    channels = {}
    for channel, value in table.items():
        text = value.strip() if isinstance(value, str) else ""
        name = text.rstrip("'")
        derivative = len(text) - len(name)
        if name not in names or derivative > 2:
            problems.append(Problem(
                f"'{printable(value, limit=40)}' is not a coordinate or output with at most "
                f"two primes (known: {name_list(names) or 'none'})", source, section,
                str(channel)))
            continue
        channels[str(channel)] = ChannelMap(name, derivative)
    return channels


def match_channels(spec: MeasurementSpec, available: Sequence[str], source: str,
                   measured: str) -> None:
    """Check that every channel the section names is in the measurement.

    Parameters
    ----------
    spec : MeasurementSpec
    available : sequence of str
        The channel names of the measurement.
    source : str
        The model file (the section's).
    measured : str
        The measurement file's name.

    Raises
    ------
    ModelError
        Naming each channel of ``[measurement]`` the file does not hold.

    Examples
    --------
    >>> spec = MeasurementSpec("hammer", "F", {"a3": ChannelMap("x3", 2)})
    >>> match_channels(spec, ["hammer", "a1"], "m.toml", "lab.uff")
    Traceback (most recent call last):
    resonant.errors.ModelError: m.toml: [measurement.channels] a3: lab.uff has no channel 'a3' \
(its channels: hammer, a1)
    """
    problems = []
    listed = name_list(available) or "none"
    for excitation in [r[0] for r in spec.references] or [spec.excitation]:
        if excitation and excitation not in available:
            problems.append(Problem(f"{printable(measured)} has no channel "
                                    f"'{printable(excitation, limit=40)}' (its channels: "
                                    f"{listed})", source, "measurement", "excitation"))
    for channel in spec.channels:
        if channel not in available:
            problems.append(Problem(f"{printable(measured)} has no channel "
                                    f"'{printable(channel, limit=40)}' (its channels: "
                                    f"{listed})", source, "measurement.channels", channel))
    if problems:
        raise ModelError(problems)


def position_dofs(names: Sequence[str], after: int = 0) -> dict[str, tuple[int, int]]:
    """The node and direction of places that no coordinate's name gives: their positions.

    Parameters
    ----------
    names : sequence of str
        The places (channels, or the quantities they measure) in order; a name repeated
        keeps its first node.
    after : int, optional
        The nodes are counted from ``after + 1`` (past the nodes the model names).

    Returns
    -------
    dict
        Name -> (node, direction 0): the k-th distinct name at node ``after + k``.

    Examples
    --------
    >>> position_dofs(["d1", "d2"]), position_dofs(["F", "x3", "F"], after=12)
    ({'d1': (1, 0), 'd2': (2, 0)}, {'F': (13, 0), 'x3': (14, 0)})
    """
    distinct = list(dict.fromkeys(names))
    return {name: (after + k, 0) for k, name in enumerate(distinct, start=1)}


def measurement_dofs(spec: MeasurementSpec, coordinates: Sequence[str],
                     acts_on: Mapping[str, Sequence[str]] | None = None
                     ) -> dict[str, tuple[int, int]]:
    """The node and direction (Universal File codes) of every channel of the section: what
    ``resonant frf --save`` writes as each FRF's response and reference.

    A channel measures a quantity (a response channel its coordinate or output, an
    excitation channel its input).  A coordinate named by node and direction
    (``n1042_uz``, :func:`resonant.model.op4_files.dof_of`) is at that node in that
    direction (+Z for ``uz``); every other quantity at its position among the distinct
    quantities, responses first, counted past the highest node the model's coordinates
    name (:func:`position_dofs`), so that it names none of them.  Channels of one quantity
    share its node: a driving point's response and reference are one.  An input that is
    a signal whose load acts on one coordinate (``acts_on``) is at that coordinate.

    Parameters
    ----------
    spec : MeasurementSpec
    coordinates : sequence of str
        The model's coordinates.
    acts_on : mapping, optional
        Input (signal) -> the coordinates its load acts on
        (:func:`resonant.system.excitation.loaded_coordinates`); without it, or where
        there are none or several, a signal gets a position of its own.

    Returns
    -------
    dict
        Channel (response or excitation) -> (node, direction).

    Examples
    --------
    >>> spec = MeasurementSpec("hammer", "n12_uz", {"a": ChannelMap("n11_uz", 2),
    ...                                             "y": ChannelMap("y")})
    >>> measurement_dofs(spec, ["n11_uz", "n12_uz"])
    {'a': (11, 3), 'y': (13, 0), 'hammer': (12, 3)}
    >>> spec = MeasurementSpec("hammer", "F", {"d1": ChannelMap("x1"),
    ...                                        "a1": ChannelMap("x1", 2)})
    >>> measurement_dofs(spec, ["x1"])
    {'d1': (1, 0), 'a1': (1, 0), 'hammer': (2, 0)}
    >>> measurement_dofs(spec, ["x1"], {"F": ("x1",)})     # F loads x1: a driving point
    {'d1': (1, 0), 'a1': (1, 0), 'hammer': (1, 0)}
    """
    known = set(coordinates)
    after = max((dof[0] for dof in map(dof_of, coordinates) if dof is not None), default=0)
    traced = {name: acts[0] for name, acts in (acts_on or {}).items() if len(acts) == 1}
    inputs = {channel: traced.get(name, name) for channel, name in
              (dict(spec.references) or {spec.excitation: spec.input}).items()}
    measures = {**{c: m.name for c, m in spec.channels.items()}, **inputs}
    named = {q: dof for q in measures.values() if q in known
             and (dof := dof_of(q)) is not None}
    places = {**position_dofs([q for q in measures.values() if q not in named], after),
              **named}
    return {channel: places[quantity] for channel, quantity in measures.items()}
