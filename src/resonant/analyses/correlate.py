"""Test against model: identified modes paired with the model's by MAC, the frequency
errors, and the auto-MAC of each set (docs/testing.md).

The model's mode shapes are read at the measured channels: each channel of
``[measurement.channels]`` names a coordinate (its derivative does not change a shape).
The pairing maximizes the sum of the paired MACs (the assignment problem,
:func:`scipy.optimize.linear_sum_assignment`), so two close modes are not both paired with
one.

Examples
--------
>>> import numpy as np
>>> c = correlate_shapes(np.array([2.2, 6.3]), np.eye(2), np.array([2.24, 6.28]),
...                      np.array([[1.0, 0.1], [0.0, 1.0]]))
>>> c.pairs, [round(e, 4) for e in c.frequency_error]
((0, 1), [-0.0179, 0.0032])
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..arrays import freeze_fields
from ..charts import (
    Bar,
    Chart,
    Charted,
    Charts,
    charts_svg,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..memory import dense_matrix
from ..modal import modal_assurance, undamped_eigen
from ..model.measurement_spec import ChannelMap
from ..model.units_display import ResultUnits, cyclic_shown
from ..system.base import LinearSystem
from .identify import ModalIdentification
from .result_fields import FieldsJSON, saved

__all__ = ["Correlation", "correlate", "correlate_shapes", "model_shapes"]


@dataclass(frozen=True)
class Correlation(FieldsJSON, Charted):
    """Identified (test) modes against the model's: MAC, pairs, frequency errors.

    Attributes
    ----------
    test_frequency, model_frequency : ndarray
        Natural frequencies (Hz).
    mac : ndarray
        (test modes, model modes).
    pairs : tuple of int
        For each test mode the model mode paired with it (-1: none).
    frequency_error : tuple of float
        (f_test - f_model) / f_model of each pair (NaN without a pair).
    auto_mac_test, auto_mac_model : ndarray
        The MAC of each set with itself (off-diagonal: how distinct the shapes are).

    Examples
    --------
    >>> import numpy as np
    >>> from resonant.analyses.correlate import correlate_shapes
    >>> c = correlate_shapes(np.array([2.2, 6.3]), np.eye(2), np.array([2.24, 6.28]),
    ...                      np.array([[1.0, 0.1], [0.0, 1.0]]))
    >>> c.pairs, round(float(c.mac[1, 1]), 4)
    ((0, 1), 0.9901)
    >>> Correlation.from_dict(c.to_dict()).to_dict() == c.to_dict()   # by its fields
    True
    """

    test_frequency: np.ndarray = saved(key="test_frequency_hz")
    model_frequency: np.ndarray = saved(key="model_frequency_hz")
    mac: np.ndarray = saved(axes=("test_frequency", "model_frequency"))
    pairs: tuple[int, ...] = saved()
    frequency_error: tuple[float, ...] = saved()
    auto_mac_test: np.ndarray = saved(axes=("test_frequency", "test_frequency"))
    auto_mac_model: np.ndarray = saved(axes=("model_frequency", "model_frequency"))

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def paired_mac(self) -> np.ndarray:
        """The MAC of each test mode with its pair (NaN without one)."""
        return np.array([self.mac[i, j] if j >= 0 else np.nan
                         for i, j in enumerate(self.pairs)])

    def chart(self) -> Charts:
        """The paired MACs and the frequency errors as bars, one per test mode.

        Returns
        -------
        Charts
        """
        x = np.arange(1, len(self.pairs) + 1, dtype=float)
        xlim = (0.4, len(x) + 0.6)
        ticks = tuple((float(k), str(int(k))) for k in x)
        mac = Chart((), "test mode", "MAC with its pair", xlim, ylim=(0.0, 1.05),
                    bars=(Bar(x, self.paired_mac, ("#1f77b4",), label="MAC"),), xticks=ticks)
        errors = 100 * np.array(self.frequency_error)
        span = max(1.0, float(np.nanmax(np.abs(errors), initial=0.0)) * 1.2)
        freq = Chart((), "test mode", "frequency error [%]", xlim, ylim=(-span, span),
                     bars=(Bar(x, errors, ("#d62728",), label="(f test - f model) / f model"),),
                     xticks=ticks)
        return Charts((mac, freq), title="test against model", sharex=True)

    def summary(self, units: ResultUnits | None = None) -> str:
        """The pairs as a text table.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``: frequencies in the unit chosen; default Hz).

        Returns
        -------
        str
        """
        hz = cyclic_shown(units)
        lines = [f"{'test':>4} {f'f test [{hz.text}]':>11} {'model':>5} "
                 f"{f'f model [{hz.text}]':>12} {'error [%]':>9} {'MAC':>6}"]
        for i, j in enumerate(self.pairs):
            if j < 0:
                lines.append(f"{i + 1:>4} {hz(self.test_frequency[i]):>11.5g} {'-':>5}")
                continue
            lines.append(f"{i + 1:>4} {hz(self.test_frequency[i]):>11.5g} {j + 1:>5} "
                         f"{hz(self.model_frequency[j]):>12.5g} "
                         f"{100 * self.frequency_error[i]:>9.3f} {self.mac[i, j]:>6.3f}")
        return "\n".join(lines) + "\n"

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "correlation")


def correlate_shapes(test_frequency: np.ndarray, test_shapes: np.ndarray,
                     model_frequency: np.ndarray, model_shapes: np.ndarray) -> Correlation:
    """Pair two sets of modes by MAC and compare their frequencies.

    Parameters
    ----------
    test_frequency : ndarray
        (Hz), one per test mode.
    test_shapes : ndarray
        (channels, test modes), complex allowed.
    model_frequency : ndarray
        (Hz).
    model_shapes : ndarray
        (channels, model modes) at the same channels.

    Returns
    -------
    Correlation
    """
    from scipy.optimize import linear_sum_assignment

    tf, mf = np.asarray(test_frequency, float), np.asarray(model_frequency, float)
    a, b = np.asarray(test_shapes), np.asarray(model_shapes)
    if a.shape[0] != b.shape[0] or a.shape[1] != len(tf) or b.shape[1] != len(mf):
        raise ModelError(Problem(f"the shapes must share their channels ({a.shape[0]} test, "
                                 f"{b.shape[0]} model) and hold one column per mode"))
    mac = modal_assurance(a, b)
    rows, cols = linear_sum_assignment(-mac)
    pairs = [-1] * len(tf)
    for i, j in zip(rows, cols):
        pairs[int(i)] = int(j)
    errors = tuple(float((tf[i] - mf[j]) / mf[j]) if j >= 0 else float("nan")
                   for i, j in enumerate(pairs))
    return Correlation(tf, mf, mac, tuple(pairs), errors, modal_assurance(a, a),
                       modal_assurance(b, b))


def model_shapes(system: LinearSystem, channels: Mapping[str, ChannelMap], *,
                 deadline: Deadline = NO_DEADLINE, **values: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The model's undamped natural frequencies (Hz) and mode shapes at the channels.

    Parameters
    ----------
    system : LinearSystem
    channels : mapping
        Channel -> its coordinate (``[measurement.channels]``).
    deadline : Deadline, optional
    **values
        Parameter values replacing the model's (SI).

    Returns
    -------
    frequency : ndarray
    shapes : ndarray
        (channels, modes).

    Raises
    ------
    ModelError
        For a channel that names an output (a shape is read at coordinates only).

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_damped.toml").linearize()
    >>> f, phi = model_shapes(system, {"a3": ChannelMap("x3", 2)})
    >>> round(float(f[0]), 4), phi.shape
    (2.2399, (1, 3))
    """
    num = system.numeric(deadline, **values)
    rows = []
    for channel, c in channels.items():
        if c.name not in num.coordinates:
            raise ModelError(Problem(f"channel '{printable(channel, limit=40)}' is the output "
                                     f"'{c.name}'; mode shapes are compared at coordinates",
                                     system.source, "measurement.channels", channel))
        rows.append(num.coordinates.index(c.name))
    M, K = (dense_matrix(a) for a in (num.M, num.K))
    lam, phi = undamped_eigen(M, K)
    return np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi), phi[rows]


def correlate(identified: ModalIdentification, system: LinearSystem,
              channels: Mapping[str, ChannelMap], *,
              deadline: Deadline = NO_DEADLINE) -> Correlation:
    """The identified modes against the model's at the measured channels.

    Parameters
    ----------
    identified : ModalIdentification
    system : LinearSystem
    channels : mapping
        Channel -> coordinate, for every channel of the identification.
    deadline : Deadline, optional

    Returns
    -------
    Correlation

    Raises
    ------
    ModelError
        When a channel of the identification is not mapped.
    """
    missing = [c for c in identified.channels if c not in channels]
    if missing:
        raise ModelError(Problem(f"channel '{printable(missing[0], limit=40)}' is not mapped "
                                 "to a coordinate", system.source, "measurement.channels"))
    ordered = {c: channels[c] for c in identified.channels}
    f, phi = model_shapes(system, ordered, deadline=deadline)
    return correlate_shapes(identified.frequency, identified.shapes, f, phi)
