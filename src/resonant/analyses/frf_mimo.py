"""FRF matrices from several inputs at once: the multiple-input H1 estimate (docs/testing.md).

With p inputs x (shakers, or hammer hits at several points) and the responses y measured
together, every segment k gives the spectra X_k (p,) and Y_k (q,), and a linear system
Y_k = H X_k + noise.  Averaged over the segments (Welch, windows and overlap as in
:func:`~resonant.analyses.frf_estimate.estimate_frf`),

    G_xx[i, j] = < conj(X_i) X_j >,   G_xy[i, r] = < conj(X_i) Y_r >,   H^T = G_xx^-1 G_xy,

the least-squares H1 matrix (Bendat & Piersol, Random Data, 4th ed., ch. 7): unbiased by
noise on the responses, and exact where the segments' inputs are independent enough for
G_xx to be invertible.  With one input it is the single-input H1.  The multiple coherence
of each response, gamma^2_r = G_xy[:, r]^H G_xx^-1 G_xy[:, r] / G_yy[r], says how much of it
the inputs explain together.  Where the inputs are coherent with each other (one shaker
driving through the other, the same hit pattern on two points) G_xx is singular and H cannot
be separated: its condition number is kept per line, lines above
:data:`CONDITION_WARNING` are warned about, and a band where every line is above
:data:`CONDITION_LIMIT` is refused.  At least as many segments as inputs are needed.

Examples
--------
>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> x = rng.standard_normal((2, 4096))
>>> y = {"y": 2.0 * x[0] - 0.5 * x[1]}           # a static gain from each input
>>> r = estimate_frf_matrix({"a": x[0], "b": x[1]}, y, 0.01, window="rectangular",
...                         segment=256)
>>> np.round(r.frf("y", "a")[:3].real, 9).tolist(), round(float(r.frf("y", "b")[5].real), 9)
([2.0, 2.0, 2.0], -0.5)
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import COLORS, Chart, Charted, Charts, Curve, charts_svg
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..memory import require
from ..model.measured import MeasuredData, MeasuredFunction
from ..model.measurement_spec import MeasurementSpec, match_channels, position_dofs
from .frf_estimate import _band_lines, _clipping, _frames, _samples, _windows
from .result_fields import FieldsJSON, saved

__all__ = ["MIMOFRF", "estimate_frf_matrix", "frf_matrix_from_measurement",
           "CONDITION_WARNING", "CONDITION_LIMIT", "pair_name", "frf_matrix_of",
           "PAIR_SEPARATOR"]

#: condition numbers of G_xx above which a line's separation is warned about
CONDITION_WARNING = 1e4
#: above which a line cannot be separated at all (the inputs coherent)
CONDITION_LIMIT = 1e12
#: joins a response and an input channel in the name of one FRF of a matrix
PAIR_SEPARATOR = "/"


def pair_name(output: str, input: str) -> str:
    """The name of the FRF of ``output`` to ``input`` in a file or a mapping of FRFs
    (``"a3/shaker1"``): the Universal File record of one element of an FRF matrix.

    Parameters
    ----------
    output, input : str
        The response and the input (excitation) channel.

    Returns
    -------
    str

    Examples
    --------
    >>> pair_name("a3", "hammer2")
    'a3/hammer2'
    """
    return f"{output}{PAIR_SEPARATOR}{input}"


@dataclass(frozen=True)
class MIMOFRF(FieldsJSON, Charted):
    """The H1 matrix of every response to every input, with the multiple coherence.

    Attributes
    ----------
    frequency : ndarray
        The spectral lines (Hz).
    inputs, outputs : tuple of str
        The input and response channels.
    H : ndarray
        (lines, outputs, inputs) complex: H[l, r, i] the FRF of output r to input i.
    coherence : ndarray
        (lines, outputs) the multiple coherence of each response.
    condition : ndarray
        (lines,) the condition number of the inputs' cross-spectral matrix G_xx.
    window : str
    averages, segment : int
    step : float
        The sampling step (s).
    warnings : tuple of str
    """

    frequency: np.ndarray = saved(key="frequency_hz")
    inputs: tuple[str, ...] = saved()
    outputs: tuple[str, ...] = saved()
    H: np.ndarray = saved(axes=("frequency", "outputs", "inputs"))
    coherence: np.ndarray = saved(axes=("frequency", "outputs"))
    condition: np.ndarray = saved(axes=("frequency",))
    window: str = saved()
    averages: int = saved()
    segment: int = saved()
    step: float = saved(key="step_s")
    warnings: tuple[str, ...] = saved(default=())

    def __post_init__(self) -> None:
        freeze_fields(self)

    def frf(self, output: str, input: str) -> np.ndarray:
        """The FRF of one response to one input.

        Parameters
        ----------
        output, input : str

        Returns
        -------
        ndarray

        Raises
        ------
        ModelError
            For a channel that is not there.
        """
        for name, names in ((output, self.outputs), (input, self.inputs)):
            if name not in names:
                raise ModelError(Problem(f"no channel '{printable(name, limit=40)}' (have "
                                         f"{', '.join(names)})"))
        return np.asarray(self.H[:, self.outputs.index(output), self.inputs.index(input)])

    def to_measured(self, source: str = "frf", units: Mapping[str, str] | None = None,
                    dofs: Mapping[str, tuple[int, int]] | None = None) -> MeasuredData:
        """The matrix as measured functions (for :func:`resonant.model.measured.write_uff`):
        one ``"frf"`` function per response and input, named :func:`pair_name`, its
        response the response channel's node and direction and its reference the input
        channel's; then the multiple coherence of each response (``"a3 coherence"``).

        Parameters
        ----------
        source : str
            The name the data carries.
        units : mapping, optional
            Response -> the unit of its FRFs (``"m/s^2/N"``).
        dofs : mapping, optional
            Response or input channel -> its (node, direction)
            (:func:`resonant.model.measurement_spec.measurement_dofs`); default their
            positions among the responses and among the inputs, counted from 1, direction
            0.

        Returns
        -------
        MeasuredData

        Examples
        --------
        >>> x = np.random.default_rng(1).standard_normal((2, 2048))
        >>> r = estimate_frf_matrix({"u": x[0], "v": x[1]}, {"y": x[0] + x[1]}, 0.01,
        ...                         segment=256)
        >>> frfs = r.to_measured()
        >>> frfs.names, frfs.functions[1].response, frfs.functions[1].reference
        (('y/u', 'y/v', 'y coherence'), (1, 0), (2, 0))
        """
        f = np.asarray(self.frequency)
        units = units or {}
        places = dict(dofs) if dofs is not None else {**position_dofs(self.outputs),
                                                      **position_dofs(self.inputs)}
        frfs = [MeasuredFunction(pair_name(out, inp), "frf", f, np.asarray(self.H[:, r, i]),
                                 "Hz", units.get(out, ""), places[out], places[inp])
                for r, out in enumerate(self.outputs) for i, inp in enumerate(self.inputs)]
        coherences = [MeasuredFunction(f"{out} coherence", "coherence", f,
                                       np.asarray(self.coherence[:, r]), "Hz", "", places[out],
                                       (0, 0)) for r, out in enumerate(self.outputs)]
        return MeasuredData(source, tuple(frfs + coherences))

    def chart(self) -> Charts:
        """|H| of every response, one panel per input, and the multiple coherence.

        Returns
        -------
        Charts
        """
        f = np.asarray(self.frequency)
        xlim = (float(f[0]), float(f[-1]))
        panels = []
        for i, name in enumerate(self.inputs):
            curves = tuple(Curve(f, np.abs(self.H[:, r, i]), out, COLORS[r % len(COLORS)])
                           for r, out in enumerate(self.outputs))
            panels.append(Chart(curves, "frequency [Hz]", f"|H| to {name}", xlim, ylog=True))
        panels.append(Chart(tuple(Curve(f, self.coherence[:, r], out, COLORS[r % len(COLORS)])
                                  for r, out in enumerate(self.outputs)),
                            "frequency [Hz]", "multiple coherence", xlim, ylim=(0.0, 1.05),
                            legend="none"))
        return Charts(tuple(panels), title=f"H1 matrix, {len(self.inputs)} inputs, "
                                           f"{self.averages} averages",
                      size=(7.0, 2.4 * len(panels)))

    def summary(self) -> str:
        """The channels, the averages and the separation of the inputs.

        Returns
        -------
        str
        """
        lines = [f"H1 matrix: {len(self.outputs)} responses x {len(self.inputs)} inputs "
                 f"({', '.join(self.inputs)}), {len(self.frequency)} lines "
                 f"{self.frequency[0]:.6g} to {self.frequency[-1]:.6g} Hz, {self.window}, "
                 f"{self.averages} averages of {self.segment} samples",
                 f"condition of G_xx: median {float(np.median(self.condition)):.3g}, "
                 f"largest {float(np.max(self.condition)):.3g}",
                 f"{'response':<12} {'min coherence':>14} {'median':>8}"]
        lines += [f"{printable(o, limit=12):<12} {float(self.coherence[:, r].min()):>14.4f} "
                  f"{float(np.median(self.coherence[:, r])):>8.4f}"
                  for r, o in enumerate(self.outputs)]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines) + "\n"

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "frf-matrix")


def _solve_lines(Gxx: np.ndarray, Gxy: np.ndarray, Gyy: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """H (lines, q, p), the multiple coherence (lines, q) and cond(G_xx) (lines,)."""
    scale = np.sqrt(np.einsum("lii->li", Gxx).real)           # equilibrate each line
    scale = np.where(scale > 0, scale, 1.0)
    S = Gxx / (scale[:, :, None] * scale[:, None, :])
    condition = np.linalg.cond(S)
    good = condition < CONDITION_LIMIT
    HT = np.full(Gxy.shape, np.nan, dtype=complex)
    HT[good] = np.linalg.solve(S[good], Gxy[good] / scale[good][:, :, None]) / \
        scale[good][:, :, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        explained = np.einsum("lir,lir->lr", np.conj(Gxy), HT).real
        coherence = np.clip(np.nan_to_num(explained / Gyy), 0.0, 1.0)
    return np.transpose(HT, (0, 2, 1)), coherence, condition


def estimate_frf_matrix(excitations: Mapping[str, np.ndarray | Sequence[float]],
                        responses: Mapping[str, np.ndarray | Sequence[float]], step: float, *,
                        window: str = "hann", segment: int | None = None,
                        overlap: float | None = None, force_window: float | None = None,
                        exponential: float | None = None,
                        band: tuple[float, float] | None = None,
                        deadline: Deadline = NO_DEADLINE) -> MIMOFRF:
    """The H1 matrix of the responses to several inputs measured together.

    Parameters
    ----------
    excitations : mapping
        Input channel -> its samples (two or more for a matrix; one gives the single-input
        H1).
    responses : mapping
        Response channel -> its samples (as many as the inputs').
    step : float
        The sampling step (s).
    window : {"hann", "rectangular"}
    segment : int, optional
        Samples per segment (default an eighth of the record).  With impact windows, the
        length of one record (one hit pattern per segment, at least one per input).
    overlap : float, optional
        0 to below 1 (default 0.5 with ``hann``, else 0).
    force_window, exponential : float, optional
        The impact windows of :func:`~resonant.analyses.frf_estimate.estimate_frf`, on every
        input and response.
    band : (float, float), optional
        The lines kept (Hz).
    deadline : Deadline, optional

    Returns
    -------
    MIMOFRF

    Raises
    ------
    ModelError
        For no input or response, histories of different lengths or with NaN, fewer
        segments than inputs, a band without lines, or inputs coherent at every line.
    """
    if not excitations or not responses:
        raise ModelError(Problem("give at least one input and one response channel", "", "",
                                 "channels"))
    inputs, outputs = list(excitations), list(responses)
    first = _samples(excitations[inputs[0]], f"input '{printable(inputs[0], limit=40)}'")
    x = np.array([first] + [_samples(excitations[n], f"input '{printable(n, limit=40)}'",
                                     len(first)) for n in inputs[1:]])
    if not (math.isfinite(step) and step > 0):
        raise ModelError(Problem("the sampling step must be a positive number", "", "",
                                 "step"))
    n = x.shape[1]
    segment = int(segment) if segment is not None else n // 8
    overlap = (0.5 if window == "hann" and force_window is None and exponential is None
               else 0.0) if overlap is None else float(overlap)
    if not 16 <= segment <= n or not 0 <= overlap < 1:
        raise ModelError(Problem(f"the segment must hold 16 to {n} samples and the overlap "
                                 "lie in [0, 1)", "", "", "segment"))
    hop = max(1, int(round(segment * (1 - overlap))))
    averages = (n - segment) // hop + 1
    if averages < len(inputs):
        raise ModelError(Problem(f"{averages} segments for {len(inputs)} inputs: the H1 matrix "
                                 "needs at least one segment per input (shorter segments or "
                                 "more records)", "", "", "segment"))
    windows = _windows(window, segment, step, force_window, exponential)
    frequency = np.fft.rfftfreq(segment, step)
    lines = _band_lines(frequency, band)
    p, q = len(inputs), len(outputs)
    require(16.0 * averages * len(frequency) * (p + 1) + 16.0 * len(lines) * (p + q) ** 2,
            f"the spectra of {averages} segments x {p + q} channels",
            "use longer segments, fewer samples or fewer channels")
    X = np.stack([np.fft.rfft(_frames(xi, segment, hop) * windows.input, axis=1)[:, lines]
                  for xi in x])                                     # (p, frames, lines)
    Gxx = np.einsum("ikl,jkl->lij", np.conj(X), X) / averages
    Gxy = np.empty((len(lines), p, q), dtype=complex)
    Gyy = np.empty((len(lines), q))
    warnings = [w for k, name in enumerate(inputs)
                for w in _clipping(f"input '{printable(name, limit=40)}'", x[k])]
    for r, name in enumerate(outputs):
        deadline.check("while estimating the FRF matrix", analysis=True)
        y = _samples(responses[name], f"channel '{printable(name, limit=40)}'", n)
        Y = np.fft.rfft(_frames(y, segment, hop) * windows.response, axis=1)[:, lines]
        Gxy[:, :, r] = np.einsum("ikl,kl->li", np.conj(X), Y) / averages
        Gyy[:, r] = (np.abs(Y) ** 2).mean(axis=0)
        warnings += _clipping(f"channel '{printable(name, limit=40)}'", y)
    H, coherence, condition = _solve_lines(Gxx, Gxy, Gyy)
    f = frequency[lines]
    if not (condition < CONDITION_LIMIT).any():
        raise ModelError(Problem("the inputs are coherent with each other at every line: "
                                 "the FRF matrix cannot be separated (drive them with "
                                 "independent signals, or hit the points in different "
                                 "patterns per segment)", "", "", "excitation"))
    poor = np.flatnonzero(condition > CONDITION_WARNING)
    if len(poor):
        warnings.append(f"the inputs are nearly coherent at {len(poor)} lines (the first at "
                        f"{f[poor[0]]:.6g} Hz; condition of G_xx above "
                        f"{CONDITION_WARNING:g}): H is poorly separated there"
                        + (", NaN where singular" if np.isnan(H).any() else ""))
    return MIMOFRF(f, tuple(inputs), tuple(outputs), H, coherence, condition,
                   windows.text, averages, segment, float(step), tuple(warnings))


def frf_matrix_from_measurement(data: MeasuredData, spec: MeasurementSpec, source: str = "",
                                **options: Any) -> MIMOFRF:
    """The H1 matrix of the channels of a ``[measurement]`` section with several inputs.

    Parameters
    ----------
    data : MeasuredData
        Time histories of the excitation and response channels.
    spec : MeasurementSpec
        Its ``references`` (the excitation channels) and ``channels``.
    source : str
        The model file (for the messages).
    **options
        As :func:`estimate_frf_matrix` (window, segment, overlap, force_window,
        exponential, band, deadline).

    Returns
    -------
    MIMOFRF
        Its inputs named by the excitation channels, in the section's order.

    Raises
    ------
    ModelError
        When a channel is missing or is not a time history, or as
        :func:`estimate_frf_matrix`.
    """
    match_channels(spec, data.names, source, data.source)
    references = [r[0] for r in spec.references] or [spec.excitation]
    if not all(references):
        raise ModelError(Problem("name the excitation channels to estimate FRFs from time "
                                 "histories", source, "measurement", "excitation"))
    functions = {name: data.function(name) for name in [*references, *spec.channels]}
    for name, f in functions.items():
        if f.kind != "time":
            raise ModelError(Problem(f"channel '{printable(name, limit=40)}' is a {f.kind} "
                                     "function, not a time history", data.source))
    step = functions[references[0]].step
    return estimate_frf_matrix({r: functions[r].ordinate for r in references},
                               {c: functions[c].ordinate for c in spec.channels}, step,
                               **options)


def frf_matrix_of(data: MeasuredData, outputs: Sequence[str], inputs: Sequence[str]
                  ) -> tuple[np.ndarray, np.ndarray, dict[str, str]]:
    """The FRF matrix of a file's functions named :func:`pair_name` (as
    :meth:`MIMOFRF.to_measured` writes them).

    Parameters
    ----------
    data : MeasuredData
    outputs, inputs : sequence of str
        The response and the input channels.

    Returns
    -------
    frequency : ndarray
        The lines (Hz).
    H : ndarray
        (lines, outputs, inputs) complex.
    units : dict
        Response -> the unit of its FRFs (``""`` when the file gives none).

    Raises
    ------
    ModelError
        For a pair the file does not hold (named), one that is not an FRF, or FRFs at
        different lines.

    Examples
    --------
    >>> x = np.random.default_rng(1).standard_normal((2, 2048))
    >>> r = estimate_frf_matrix({"u": x[0], "v": x[1]}, {"y": 2 * x[0] - x[1]}, 0.01,
    ...                         segment=256)
    >>> f, H, units = frf_matrix_of(r.to_measured(), ["y"], ["u", "v"])
    >>> H.shape, bool(np.allclose(H, r.H))
    ((129, 1, 2), True)
    """
    have = {f.name: f for f in data.functions}
    missing = [pair_name(o, i) for o in outputs for i in inputs if pair_name(o, i) not in have]
    if missing:
        frfs = [f.name for f in data.functions if f.kind == "frf"]
        raise ModelError(Problem(
            f"no FRF '{printable(missing[0], limit=60)}' (response{PAIR_SEPARATOR}input) for "
            f"the matrix of {len(outputs)} responses x {len(inputs)} inputs; the file's FRFs: "
            f"{', '.join(printable(n, limit=40) for n in frfs[:12]) or 'none'}",
            data.source))
    first = have[pair_name(outputs[0], inputs[0])]
    f = np.asarray(first.abscissa, dtype=float)
    H = np.empty((len(f), len(outputs), len(inputs)), dtype=complex)
    for r, out in enumerate(outputs):
        for i, inp in enumerate(inputs):
            g = have[pair_name(out, inp)]
            if g.kind != "frf":
                raise ModelError(Problem(f"'{printable(g.name, limit=60)}' is a {g.kind} "
                                         "function, not an FRF", data.source))
            if g.abscissa.shape != f.shape or not np.allclose(g.abscissa, f, rtol=1e-9):
                raise ModelError(Problem(f"the FRF '{printable(g.name, limit=60)}' has other "
                                         "lines than the matrix's first", data.source))
            H[:, r, i] = g.ordinate
    units = {out: have[pair_name(out, inputs[0])].ordinate_unit for out in outputs}
    return f, H, units
