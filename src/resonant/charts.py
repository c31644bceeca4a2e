"""Line charts as data, drawn either as SVG text directly or on a matplotlib figure.

A :class:`Chart` says what a plot shows (curves, markers, reference lines, labels,
limits); :func:`chart_svg` writes it as an ``<svg>`` element for an HTML page and
:func:`draw_chart` draws it with matplotlib for files and for users' figures.
Writing the SVG directly costs about a millisecond a chart, against about 0.15 s
for matplotlib's SVG backend (tick objects, text layout, glyph outlines): the
exercise generator draws two charts for every variant of a class set.

Labels are plain text with LaTeX math between dollar signs, of the small kind the
report writes for names (``$x_{2}$``, ``$\\varphi$``, ``$\\dot{x}_{1}$``):
:func:`chart_svg` sets them as SVG text (Greek letters, sub- and superscripts),
matplotlib as mathtext.  Every string is escaped.

Examples
--------
>>> import numpy as np
>>> chart = Chart((Curve(np.array([0.0, 1.0, 2.0]), np.array([1.0, 10.0, 2.0]), "$x_{1}$"),),
...               xlabel="excitation frequency $\\\\omega$ [rad/s]", ylabel="amplitude $X$",
...               xlim=(0.0, 2.0), ylog=True)
>>> svg = chart_svg(chart, "figure-1")
>>> svg.startswith("<svg") and "figure-1-plot" in svg and "\\u03c9" in svg
True
>>> nice_ticks(0.0, 1.0)
[0.0, 0.2, 0.4, 0.6, 0.8, 1.0]
"""

from __future__ import annotations

import html
import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .errors import AnalysisError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.axis import Axis
    from matplotlib.figure import Figure

#: a file to write a figure to (None: no file)
PathArg = str | os.PathLike[str] | None
#: the report's figures: 7.0 x 3.6 in, in points (the size of its matplotlib figures)
WIDTH, HEIGHT = 504.0, 259.2
#: matplotlib's default colour cycle, so that both drawings of a chart agree
COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
          "#7f7f7f", "#bcbd22", "#17becf")
FONT = "DejaVu Sans, Helvetica, Arial, sans-serif"
TICK_FONT = 10.0
#: pixel coordinates are kept within this many chart sizes (a value of 1e300 stays finite)
_FAR = 1e4


def _number(value: float) -> float | None:
    """A float for JSON: None for NaN and infinities."""
    value = float(value)
    return value if math.isfinite(value) else None


def _numbers(values: npt.ArrayLike) -> list[float | None]:
    return [_number(v) for v in np.asarray(values, dtype=float).ravel()]


@dataclass(frozen=True, eq=False)
class Curve:
    """A line through the points (x, y); NaN breaks it (a left-out point).

    ``dash`` is a dash pattern (on, off, ...) in multiples of the line's width, as
    matplotlib scales it (``"3.7 1.6"`` dashed, ``"1 1.65"`` dotted); None: solid.
    ``marker`` marks every point (one of :data:`CURVE_MARKERS`), ``line=False`` leaves the
    line out (a scatter plot: markers only), ``opacity`` below 1 lets dense points show
    through each other.
    """

    x: np.ndarray
    y: np.ndarray
    label: str
    color: str | None = None
    width: float = 1.4
    dash: str | None = None
    marker: str = ""
    line: bool = True
    opacity: float = 1.0

    def to_dict(self) -> dict[str, Any]:
        return {"x": _numbers(self.x), "y": _numbers(self.y), "label": self.label,
                "text": unicode_text(self.label), "color": self.color, "width": self.width,
                "dash": self.dash, "marker": self.marker, "line": self.line,
                "opacity": self.opacity}


#: the marks a :class:`Curve` can put at every point: a small dot, a small cross
CURVE_MARKERS = ("point", "cross")
#: the hatch of an area without values (matplotlib's pattern; the SVG's diagonal lines)
HATCH = "////"
HATCH_COLOR = "#8c8c8c"


#: the kinds of :class:`Marker`: a filled dot, a downward triangle with a black edge (a
#: resonance peak), a circle on white (an antiresonance); and the special points' shapes,
#: open (``filled=False``: the outline in the colour) or filled (a black outline)
MARKER_SHAPES = ("dot", "peak", "ring", "circle", "square", "diamond", "triangle", "star")


@dataclass(frozen=True)
class Marker:
    """A mark at one point (the operating point on a curve, a peak); markers with a
    ``label`` are named once in the legend (in grey where the colour is the curve's)."""

    x: float
    y: float
    color: str
    shape: str = "dot"
    label: str = ""
    filled: bool = True

    def to_dict(self) -> dict[str, Any]:
        return {"x": _number(self.x), "y": _number(self.y), "color": self.color,
                "shape": self.shape, "label": self.label, "filled": self.filled}


@dataclass(frozen=True)
class Rule:
    """A reference line across the axes: vertical at x = ``at`` or horizontal at y = ``at``;
    one with a ``label`` is named once in the legend."""

    at: float
    vertical: bool = True
    color: str = "#999999"
    dash: str | None = None
    width: float = 1.0
    label: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {"at": _number(self.at), "vertical": self.vertical, "color": self.color,
                "dash": self.dash, "width": self.width, "label": self.label}


@dataclass(frozen=True)
class Span:
    """A shaded band across the axes from x = ``start`` to x = ``stop`` (under the curves);
    with ``vertical=False`` from y = ``start`` to y = ``stop``.  A ``hatch`` colour draws
    it white with diagonal lines of that colour (where there are no values)."""

    start: float
    stop: float
    color: str = "#e6e6e6"
    label: str = ""
    vertical: bool = True
    hatch: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {"start": _number(self.start), "stop": _number(self.stop), "color": self.color,
                "label": self.label, "vertical": self.vertical, "hatch": self.hatch}


@dataclass(frozen=True)
class Annotation:
    """A short text at the top of the axes above x = ``at`` (the value of a peak), on a
    white ground."""

    at: float
    text: str
    color: str = "#000000"

    def to_dict(self) -> dict[str, Any]:
        return {"at": _number(self.at), "text": self.text, "color": self.color}


@dataclass(frozen=True, eq=False)
class Bar:
    """Bars of width ``width`` (one for all, or one each) centred at ``x``, from zero to
    ``heights``, in the ``colors`` in turn (a mode shape's components, a histogram's
    bins); NaN: no bar.

    ``label`` names the series once in the legend, ``errors`` are half-widths of error
    bars (a confidence interval; NaN: none), ``edge`` the colour of a thin outline.
    """

    x: np.ndarray
    heights: np.ndarray
    colors: tuple[str, ...]
    width: float | np.ndarray = 0.6
    label: str = ""
    errors: np.ndarray | None = None
    edge: str | None = None

    def widths(self) -> np.ndarray:
        """Each bar's width."""
        x = np.asarray(self.x, dtype=float)
        return np.broadcast_to(np.asarray(self.width, dtype=float), x.shape)

    def to_dict(self) -> dict[str, Any]:
        width = self.width if np.ndim(self.width) == 0 else _numbers(self.width)
        return {"x": _numbers(self.x), "heights": _numbers(self.heights),
                "colors": list(self.colors), "width": width, "label": self.label,
                "errors": None if self.errors is None else _numbers(self.errors),
                "edge": self.edge}


#: the colours of a :class:`Field`: matplotlib's viridis at 33 points, interpolated
#: linearly to :data:`FIELD_STEPS` steps (for matplotlib and the SVG alike)
FIELD_COLORS = ("#440154", "#470d60", "#48186a", "#482374", "#472d7b", "#453781", "#424086",
                "#3e4989", "#3b528b", "#375b8d", "#33638d", "#2f6b8e", "#2c728e", "#297a8e",
                "#26828e", "#23898e", "#21918c", "#1f988b", "#1fa088", "#22a785", "#28ae80",
                "#32b67a", "#3fbc73", "#4ec36b", "#5ec962", "#70cf57", "#84d44b", "#98d83e",
                "#addc30", "#c2df23", "#d8e219", "#ece51b", "#fde725")
FIELD_STEPS = 256


@lru_cache(maxsize=1)
def _field_table() -> np.ndarray:
    """The field's colour table: :data:`FIELD_STEPS` RGB rows in [0, 1]."""
    anchors = np.array([[int(c[k:k + 2], 16) / 255.0 for k in (1, 3, 5)]
                        for c in FIELD_COLORS])
    at = np.linspace(0.0, 1.0, len(FIELD_COLORS))
    steps = np.linspace(0.0, 1.0, FIELD_STEPS)
    table = np.column_stack([np.interp(steps, at, anchors[:, k]) for k in range(3)])
    table.flags.writeable = False
    return table


def _hex(rgb: npt.ArrayLike) -> str:
    r, g, b = (int(round(float(v) * 255.0)) for v in np.asarray(rgb, dtype=float)[:3])
    return f"#{r:02x}{g:02x}{b:02x}"


@dataclass(frozen=True, eq=False)
class Field:
    """A quantity over a rectangular grid: one coloured cell per value.

    ``x`` and ``y`` are the cells' edges (increasing), ``z`` the values, one row per y
    cell (``z[j, i]`` between ``y[j]``, ``y[j + 1]`` and ``x[i]``, ``x[i + 1]``); NaN is a
    cell without a value, hatched where ``missing`` names them in the legend.  The
    colour scale runs over ``limits`` (None: the values' range), logarithmic with
    ``log``; ``levels`` (increasing) makes it bands of one colour each.  ``label`` is the
    colour bar's (none without it).  Cells, not contour lines: a jump stays a sharp edge.

    Examples
    --------
    >>> f = Field(np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0]), np.array([[1.0, 3.0]]),
    ...           "$z$ [m]")
    >>> f.colors()
    [['#440154', '#fde725']]
    >>> Field.from_dict(f.to_dict()).z.tolist()
    [[1.0, 3.0]]
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    label: str = ""
    log: bool = False
    levels: tuple[float, ...] | None = None
    limits: tuple[float, float] | None = None
    missing: str = ""

    def values(self) -> np.ndarray:
        """The values as a float array (ny, nx); NaN where there is none (also a value
        that is not positive on a logarithmic scale)."""
        z = np.array(self.z, dtype=float, ndmin=2)
        if self.log:
            z[~(z > 0)] = np.nan
        return z

    def range(self) -> tuple[float, float]:
        """The colour scale's ends: ``limits``, the levels' ends or the values' range."""
        if self.levels is not None and len(self.levels) >= 2:
            return float(self.levels[0]), float(self.levels[-1])
        if self.limits is not None:
            low, high = float(self.limits[0]), float(self.limits[1])
        else:
            z = self.values()
            finite = z[np.isfinite(z)]
            low, high = ((float(finite.min()), float(finite.max())) if finite.size else
                         (1.0, 10.0) if self.log else (0.0, 1.0))
        if self.log and not low > 0:
            low = high / 10.0 if high > 0 else 1.0
            high = max(high, 10.0 * low)
        return low, high

    def bands(self) -> list[str]:
        """The colour of each band between ``levels`` (the colour at its middle)."""
        count = max(len(self.levels or ()) - 1, 1)
        table = _field_table()
        return [_hex(table[min(int((k + 0.5) / count * FIELD_STEPS), FIELD_STEPS - 1)])
                for k in range(count)]

    def steps(self, values: npt.ArrayLike) -> np.ndarray:
        """The index of each value's colour: in the table of :func:`_field_table`, or
        among the bands (-1: no value)."""
        v = np.asarray(values, dtype=float)
        finite = np.isfinite(v) & ((v > 0) if self.log else True)
        if self.levels is not None and len(self.levels) >= 2:
            index = np.searchsorted(np.asarray(self.levels, dtype=float), v, side="right") - 1
            index = np.clip(index, 0, len(self.levels) - 2)
        else:
            low, high = self.range()
            with np.errstate(all="ignore"):
                if self.log:
                    v, low, high = np.log10(v), math.log10(low), math.log10(high)
                t = (v - low) / (high - low) if high > low else np.zeros_like(v)
                index = np.clip(np.floor(np.nan_to_num(t) * FIELD_STEPS), 0,
                                FIELD_STEPS - 1).astype(int)
        return np.where(finite, index, -1)

    def colors(self) -> list[list[str | None]]:
        """Each cell's colour (rows of ``z``); None for a cell without a value."""
        table = self.bands() if self.levels is not None and len(self.levels) >= 2 else [
            _hex(row) for row in _field_table()]
        return [[table[k] if k >= 0 else None for k in row.tolist()]
                for row in self.steps(self.values())]

    def to_dict(self) -> dict[str, Any]:
        return {"x": _numbers(self.x), "y": _numbers(self.y),
                "z": [_numbers(row) for row in np.array(self.z, dtype=float, ndmin=2)],
                "label": self.label, "text": unicode_text(self.label), "log": self.log,
                "levels": None if self.levels is None else _numbers(self.levels),
                "limits": None if self.limits is None else _numbers(self.limits),
                "missing": self.missing, "colors": self.colors()}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Field:
        """The field of :meth:`to_dict`'s data (None as NaN)."""
        def array(values: Any) -> np.ndarray:
            return np.array([[math.nan if v is None else v for v in row] for row in values]
                            if values and isinstance(values[0], list) else
                            [math.nan if v is None else v for v in values], dtype=float)

        levels, limits = data.get("levels"), data.get("limits")
        return cls(array(data["x"]), array(data["y"]), array(data["z"]),
                   str(data.get("label", "")), bool(data.get("log", False)),
                   None if levels is None else tuple(float(v) for v in levels),
                   None if limits is None else (float(limits[0]), float(limits[1])),
                   str(data.get("missing", "")))


#: where a chart's legend goes: inside the axes, beside them (right of a figure of its
#: own; inside when drawn into a caller's axes), under them (matplotlib; the SVG puts every
#: legend above the plot), or none
LEGENDS = ("best", "beside", "below", "none")


@dataclass(frozen=True)
class Chart:
    """What a line chart shows; drawn by :func:`chart_svg` or :func:`draw_chart`.

    ``xlim`` is the x range; ``ylim`` the y range (None: the data's with 5 % margins);
    ``yticks`` the y ticks where the view chooses them (a phase at multiples of 90
    degrees); ``title`` a short title over the axes.
    """

    curves: tuple[Curve, ...]
    xlabel: str
    ylabel: str
    xlim: tuple[float, float]
    ylog: bool = False
    markers: tuple[Marker, ...] = ()
    rules: tuple[Rule, ...] = ()
    xlog: bool = False
    ylim: tuple[float, float] | None = None
    yticks: tuple[float, ...] | None = None
    spans: tuple[Span, ...] = ()
    notes: tuple[Annotation, ...] = ()
    title: str = ""
    legend: str = "best"
    bars: tuple[Bar, ...] = ()
    #: the x ticks where the view names them: (value, label) (a coordinate under its bar)
    xticks: tuple[tuple[float, str], ...] | None = None
    #: quantities over a grid, as coloured cells under the curves (with a colour bar)
    fields: tuple[Field, ...] = ()

    def colored(self) -> tuple[Curve, ...]:
        """The curves with the colour cycle filled in where a curve has none."""
        return tuple(c if c.color else replace(c, color=COLORS[i % len(COLORS)])
                     for i, c in enumerate(self.curves))

    def to_dict(self) -> dict[str, Any]:
        """The chart as JSON-ready data (non-finite numbers as None), for a page's drawing;
    the labels also as Unicode text (``xtext``, ``ytext``, each curve's ``text``) for a
    canvas.

        Examples
        --------
        >>> c = Chart((Curve(np.array([1.0, 2.0]), np.array([np.nan, 3.0]), "$y$"),), "t",
        ...           "y", (1.0, 2.0))
        >>> c.to_dict()["curves"][0]["y"], c.to_dict()["xlog"]
        ([None, 3.0], False)
        """
        return {"curves": [c.to_dict() for c in self.colored()], "xlabel": self.xlabel,
                "ylabel": self.ylabel, "xtext": unicode_text(self.xlabel),
                "ytext": unicode_text(self.ylabel), "xlim": _numbers(self.xlim),
                "ylim": None if self.ylim is None else _numbers(self.ylim),
                "xlog": self.xlog, "ylog": self.ylog,
                "yticks": None if self.yticks is None else _numbers(self.yticks),
                "markers": [m.to_dict() for m in self.markers],
                "rules": [r.to_dict() for r in self.rules],
                "spans": [s.to_dict() for s in self.spans],
                "notes": [n.to_dict() for n in self.notes], "title": self.title,
                "legend": self.legend, "bars": [b.to_dict() for b in self.bars],
                "xticks": None if self.xticks is None else
                [[_number(v), label] for v, label in self.xticks],
                "fields": [f.to_dict() for f in self.fields]}


@dataclass(frozen=True)
class Charts:
    """A figure of charts stacked one above the other (amplitude above phase, the inputs'
    densities above the responses'), drawn by :func:`charts_svg` or :func:`draw_figure`.

    ``heights`` are the panels' relative heights, ``size`` the figure's size in inches
    when drawn with matplotlib, ``sharex`` whether the panels share the x axis,
    ``legend`` ``"panels"`` (each chart's own) or ``"below"`` (the first chart's entries
    once, under the figure).
    """

    panels: tuple[Chart, ...]
    title: str = ""
    heights: tuple[float, ...] | None = None
    size: tuple[float, float] = (7.0, 3.6)
    sharex: bool = True
    legend: str = "panels"
    #: panels side by side in this many columns (matplotlib; the SVG stacks them)
    columns: int = 1

    def to_dict(self) -> dict[str, Any]:
        return {"title": self.title, "panels": [p.to_dict() for p in self.panels],
                "heights": None if self.heights is None else list(self.heights),
                "size": list(self.size), "sharex": self.sharex, "legend": self.legend,
                "columns": self.columns}


# -- limits and ticks ----------------------------------------------------------------------

def _finite(values: np.ndarray, log: bool) -> np.ndarray:
    values = np.asarray(values, dtype=float).ravel()
    keep = np.isfinite(values) & ((values > 0) if log else True)
    return values[keep]


def y_limits(chart: Chart) -> tuple[float, float]:
    """The y range of the data with 5 % margins (in decades on a log axis), or the chart's
    own ``ylim``."""
    if chart.ylim is not None:
        low, high = float(chart.ylim[0]), float(chart.ylim[1])
        if math.isfinite(low) and math.isfinite(high) and high > low and (
                low > 0 or not chart.ylog):
            return low, high
    data = [_finite(c.y, chart.ylog) for c in chart.curves]
    data += [_finite(np.append(b.heights, 0.0), chart.ylog) for b in chart.bars]
    with np.errstate(all="ignore"):
        data += [_finite(np.concatenate([np.asarray(b.heights, float) - b.errors,
                                         np.asarray(b.heights, float) + b.errors]), chart.ylog)
                 for b in chart.bars if b.errors is not None]
    data += [_finite(np.array([s.start, s.stop]), chart.ylog) for s in chart.spans
             if not s.vertical]
    data += [_finite(f.y, chart.ylog) for f in chart.fields]
    data.append(_finite(np.array([m.y for m in chart.markers]), chart.ylog))
    values = np.concatenate(data) if data else np.empty(0)
    # within the floats' range, so that limits, margins and ticks stay finite
    values = np.clip(np.log10(values), -300.0, 300.0) if chart.ylog else \
        np.clip(values, -1e300, 1e300)
    if values.size == 0:
        low, high = (-1.0, 1.0) if chart.ylog else (0.0, 1.0)
    else:
        low, high = float(values.min()), float(values.max())
    if not high - low > 1e-12 * max(abs(low), abs(high), 1e-300):
        pad = 0.5 if chart.ylog else max(abs(low) * 0.1, 1e-300) if low else 1.0
        low, high = low - pad, high + pad
    pad = 0.05 * high - 0.05 * low
    low, high = low - pad, high + pad
    if chart.ylog:
        return 10.0 ** max(low, -307.0), 10.0 ** min(high, 307.0)
    return low, high


def nice_ticks(low: float, high: float, most: int = 8) -> list[float]:
    """Evenly spaced round values (steps of 1, 2, 2.5 or 5 times a power of ten) within
    [low, high], at most ``most`` of them (Heckbert's nice numbers)."""
    if not (math.isfinite(low) and math.isfinite(high)) or high <= low:
        return [low] if math.isfinite(low) else []
    raw = (high - low) / max(most - 1, 1)
    power = 10.0 ** math.floor(math.log10(raw))
    step = next(s * power for s in (1.0, 2.0, 2.5, 5.0, 10.0) if s * power >= raw * (1 - 1e-9))
    first = math.ceil(low / step - 1e-9)
    last = math.floor(high / step + 1e-9)
    return [round(k * step, 12) + 0.0 for k in range(first, last + 1)]


def log_ticks(low: float, high: float, most: int = 8) -> tuple[list[int], list[float]]:
    """Decades (exponents) to label and the minor ticks between them on a log axis."""
    lo, hi = math.log10(low), math.log10(high)
    first, last = math.ceil(lo - 1e-9), math.floor(hi + 1e-9)
    every = max(1, math.ceil((last - first + 1) / most))
    majors = [k for k in range(first, last + 1) if k % every == 0]
    minors: list[float] = []
    if every == 1 and hi - lo <= 8:
        minors = [m * 10.0 ** k for k in range(math.floor(lo), math.ceil(hi) + 1)
                  for m in range(2, 10) if lo <= math.log10(m) + k <= hi]
    return majors, minors


def tick_labels(ticks: list[float]) -> tuple[list[str], int]:
    """Labels of linear ticks and the power of ten they are given in (0: none)."""
    if not ticks:
        return [], 0
    biggest = max(abs(t) for t in ticks)
    power = 0
    if biggest and (biggest >= 1e5 or biggest < 1e-3):
        power = math.floor(math.log10(biggest))
    scaled = [t / 10.0 ** power for t in ticks]
    step = min((abs(b - a) for a, b in zip(scaled, scaled[1:])), default=1.0) or 1.0
    decimals = max(0, -math.floor(math.log10(step) + 1e-9))
    if any(abs(round(s, decimals) - s) > 1e-6 * step for s in scaled):
        decimals += 1
    # a tick that rounds to zero is written without a sign
    labels = [f"{s + 0.0 if round(s, decimals) else 0.0:.{decimals}f}".replace("-", "\u2212")
              for s in scaled]
    return labels, power


# -- SVG text --------------------------------------------------------------------------------

_GREEK = {"alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ϵ",
          "varepsilon": "ε", "zeta": "ζ", "eta": "η", "theta": "θ", "vartheta": "ϑ",
          "iota": "ι", "kappa": "κ", "lambda": "λ", "mu": "μ", "nu": "ν", "xi": "ξ",
          "pi": "π", "rho": "ρ", "sigma": "σ", "tau": "τ", "upsilon": "υ", "phi": "ϕ",
          "varphi": "φ", "chi": "χ", "psi": "ψ", "omega": "ω", "Gamma": "Γ", "Delta": "Δ",
          "Theta": "Θ", "Lambda": "Λ", "Xi": "Ξ", "Pi": "Π", "Sigma": "Σ",
          "Upsilon": "Υ", "Phi": "Φ", "Psi": "Ψ", "Omega": "Ω", "cdot": "·", "times": "×"}
_ACCENTS = {"dot": "\u0307", "ddot": "\u0308", "hat": "\u0302", "bar": "\u0304",
            "tilde": "\u0303"}
#: characters XML does not allow in text (control characters become spaces)
_NOT_XML = re.compile("[\x00-\x1f\x7f\ufffe\uffff]")
_TOKEN = re.compile(r"\\([A-Za-z]+)|([_^])|([{}])|(\\.|[^\\_^{}])")


def _group(tokens: list[tuple[str, str, str, str]], i: int) -> tuple[list, int]:
    """The tokens of one argument (a braced group or one token) starting at ``i``."""
    if i < len(tokens) and tokens[i][2] == "{":
        depth, j = 1, i + 1
        while j < len(tokens) and depth:
            depth += {"{": 1, "}": -1}.get(tokens[j][2], 0)
            j += 1
        return tokens[i + 1:j - 1], j
    return tokens[i:i + 1], i + 1


def _math_runs(tokens: list, shift: int = 0) -> list[tuple[str, int, bool]]:
    """(text, level, italic) runs of a token list: level 0 on the line, -1 below, 1 above."""
    runs: list[tuple[str, int, bool]] = []
    i = 0
    while i < len(tokens):
        command, script, brace, char = tokens[i]
        if script:
            inner, i = _group(tokens, i + 1)
            runs += _math_runs(inner, -1 if script == "_" else 1)
            continue
        i += 1
        if command in _ACCENTS:
            inner, i = _group(tokens, i)
            body = _math_runs(inner, shift)
            runs += [(t + _ACCENTS[command] if k == 0 else t, lv, it)
                     for k, (t, lv, it) in enumerate(body)]
        elif command in ("mathrm", "text", "operatorname"):
            inner, i = _group(tokens, i)
            runs += [(t, lv, False) for t, lv, _ in _math_runs(inner, shift)]
        elif command:
            runs.append((_GREEK.get(command, command), shift, command in _GREEK
                         and command[0].islower()))
        elif char:
            text = char[1:] if char.startswith("\\") else char
            text = "\u2009" if text in (",", ";") and char.startswith("\\") else text
            runs.append((text, shift, text.isalpha()))
    return runs


def text_runs(label: str) -> list[tuple[str, int, bool]]:
    """A label's (text, level, italic) runs; LaTeX math between dollar signs."""
    runs: list[tuple[str, int, bool]] = []
    for k, part in enumerate(label.split("$")):
        if k % 2 == 0:
            runs.append((part, 0, False))
        else:
            runs += _math_runs([m.groups("") for m in _TOKEN.finditer(part)])
    merged: list[tuple[str, int, bool]] = []
    for run in runs:
        if run[0] and merged and merged[-1][1:] == run[1:]:
            merged[-1] = (merged[-1][0] + run[0], *run[1:])
        elif run[0]:
            merged.append(run)
    return merged


def _tspans(label: str, size: float) -> str:
    """SVG ``tspan`` elements of a label (sub- and superscripts by dy, so that every
    browser sets them)."""
    out, level = [], 0
    for text, new, italic in text_runs(label):
        dy = (level - new) * 0.35 * size
        style = (f' dy="{dy:g}"' if dy else "") + (f' font-size="{0.75 * size:g}"'
                                                  if new else "")
        style += ' font-style="italic"' if italic else ""
        out.append(f"<tspan{style}>{html.escape(_NOT_XML.sub(' ', text))}</tspan>")
        level = new
    if level:
        out.append(f'<tspan dy="{level * 0.35 * size:g}"></tspan>')
    return "".join(out)


def text_width(label: str, size: float) -> float:
    """An estimate of a label's width: about 0.6 em a character."""
    return sum(len(t) * (0.75 if lv else 1.0) for t, lv, _ in text_runs(label)) * 0.6 * size


def _text(x: float, y: float, label: str, size: float, anchor: str = "middle",
          rotate: bool = False) -> str:
    turn = f' transform="rotate(-90 {x:.2f} {y:.2f})"' if rotate else ""
    return (f'<text x="{x:.2f}" y="{y:.2f}" font-size="{size:g}" text-anchor="{anchor}"'
            f"{turn}>{_tspans(label, size)}</text>")


# -- SVG chart -------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Frame:
    """The plot area in points and the maps from data to it."""

    left: float
    right: float
    top: float
    bottom: float
    xlim: tuple[float, float]
    ylim: tuple[float, float]
    ylog: bool
    xlog: bool = False
    yticks: tuple[float, ...] | None = None
    xticks: tuple[tuple[float, str], ...] | None = None

    def x(self, values: npt.ArrayLike) -> np.ndarray:
        lo, hi = self.xlim
        with np.errstate(all="ignore"):
            v = np.asarray(values, dtype=float)
            if self.xlog:
                v, lo, hi = np.log10(np.where(v > 0, v, np.nan)), math.log10(lo), math.log10(hi)
            span = hi - lo if hi > lo else 1.0
            pos = self.left + (v - lo) / span * (self.right - self.left)
        return np.clip(pos, -_FAR * WIDTH, _FAR * WIDTH)

    def y(self, values: npt.ArrayLike) -> np.ndarray:
        lo, hi = self.ylim
        with np.errstate(all="ignore"):
            v = np.asarray(values, dtype=float)
            if self.ylog:
                v, lo, hi = np.log10(np.where(v > 0, v, np.nan)), math.log10(lo), math.log10(hi)
            span = hi - lo if hi > lo else 1.0
            pos = self.bottom - (v - lo) / span * (self.bottom - self.top)
        return np.clip(pos, -_FAR * HEIGHT, _FAR * HEIGHT)


def x_limits(chart: Chart) -> tuple[float, float]:
    """The chart's x range, made usable (finite, increasing, positive on a log axis)."""
    low, high = float(chart.xlim[0]), float(chart.xlim[1])
    if not (math.isfinite(low) and math.isfinite(high) and high > low):
        return (1.0, 10.0) if chart.xlog else (0.0, 1.0)
    if chart.xlog and low <= 0:
        return (high / 10.0, high) if high > 0 else (1.0, 10.0)
    return low, high


def _frame(chart: Chart, legend_rows: int, ylabels: list[str], height: float = HEIGHT) -> _Frame:
    widest = max((text_width(s, TICK_FONT) for s in ylabels), default=10.0)
    left = min(0.35 * WIDTH, 30.0 + widest)
    top = 8.0 + 15.0 * legend_rows + (15.0 if chart.title else 0.0)
    low, high = x_limits(chart)
    probe = _Frame(0.0, 1.0, 0.0, 1.0, (low, high), (0.0, 1.0), False, chart.xlog,
                   xticks=chart.xticks)
    xlabels = [label for _, label, minor in _x_ticks(probe) if not minor]
    right = WIDTH - max(0.02 * WIDTH, 4.0 + text_width(xlabels[-1] if xlabels else "", TICK_FONT)
                        / 2) - _colorbar_room(chart)
    return _Frame(left, right, top, height - 0.14 * HEIGHT, (low, high), y_limits(chart),
                  chart.ylog, chart.xlog, chart.yticks, chart.xticks)


@dataclass(frozen=True)
class _Key:
    """One legend entry: a line (curves, rules), a marker's shape or a band."""

    label: str
    color: str
    width: float = 1.4
    dash: str | None = None
    shape: str = ""
    filled: bool = True
    #: a band hatched in this colour (no values)
    hatch: str = ""


#: marker shapes named in the legend in their own colour (the special points' kinds)
_OWN_COLOUR = ("circle", "square", "diamond", "triangle", "star")


def legend_keys(chart: Chart) -> list[_Key]:
    """The legend's entries: the curves, then each labelled rule, band and marker kind once."""
    if chart.legend == "none":
        return []
    keys = [_Key(c.label, c.color or "#000", c.width, c.dash) if c.line else
            _Key(c.label, c.color or "#000", shape=c.marker or "point") for c in chart.colored()
            if c.label]
    seen: set[str] = set()
    for bar in chart.bars:
        if bar.label and bar.label not in seen:
            seen.add(bar.label)
            keys.append(_Key(bar.label, bar.colors[0] if bar.colors else COLORS[0], 8.0))
    for rule in chart.rules:
        if rule.label and rule.label not in seen:
            seen.add(rule.label)
            keys.append(_Key(rule.label, rule.color, rule.width, rule.dash))
    for span in chart.spans:
        if span.label and span.label not in seen:
            seen.add(span.label)
            keys.append(_Key(span.label, span.color, 8.0, hatch=span.hatch))
    for field in chart.fields:
        if field.missing and field.missing not in seen:
            seen.add(field.missing)
            keys.append(_Key(field.missing, "#ffffff", 8.0, hatch=HATCH_COLOR))
    for marker in chart.markers:
        if marker.label and marker.label not in seen:
            seen.add(marker.label)
            keys.append(_Key(marker.label, marker.color if marker.shape in _OWN_COLOUR
                             else "#4d4d4d", shape=marker.shape, filled=marker.filled))
    return keys


def _legend_rows(keys: list[_Key], room: float) -> list[list[tuple[_Key, float]]]:
    rows: list[list[tuple[_Key, float]]] = [[]]
    used = 0.0
    for key in keys:
        width = 26.0 + text_width(key.label, TICK_FONT) + 14.0
        if rows[-1] and used + width > room:
            rows.append([])
            used = 0.0
        rows[-1].append((key, width))
        used += width
    return rows if rows[0] else []


#: a curve of more points than this is thinned for the SVG (see :func:`_thinned`)
THIN_ABOVE = 2000
#: the width of a column of the thinning, in points of the SVG (a screen pixel or less)
THIN_COLUMN = 0.5


def _thinned(xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """The indices of the points of a long curve that its drawing needs: in every column
    of :data:`THIN_COLUMN` points its first, lowest, highest and last point, in order (a
    curve drawn through them differs from the full one by less than a column; a history
    of 10^5 samples becomes about 4 per column).  A curve that goes back and forth in x,
    or a short one, keeps every point; a left-out (NaN) point is kept as the gap it is.

    Examples
    --------
    >>> x = np.linspace(0.0, 100.0, 100_001)
    >>> keep = _thinned(x, np.sin(x))
    >>> len(keep) < 1000, keep[0], keep[-1]
    (True, np.int64(0), np.int64(100000))
    """
    n = xs.size
    if n <= THIN_ABOVE:
        return np.arange(n)
    ok = np.isfinite(xs) & np.isfinite(ys)
    columns = np.where(ok, np.floor(np.where(ok, xs, 0.0) / THIN_COLUMN), -1.0 - np.arange(n))
    starts = np.concatenate(([0], np.flatnonzero(np.diff(columns) != 0) + 1))
    if starts.size > n // 4:
        return np.arange(n)
    ends = np.append(starts[1:], n)
    keep = {0, n - 1}
    for start, end in zip(starts.tolist(), ends.tolist()):
        column = ys[start:end]
        keep.update((start, end - 1, start + int(np.argmin(column)),
                     start + int(np.argmax(column))))
    return np.array(sorted(keep))


def _polyline(xs: np.ndarray, ys: np.ndarray) -> str:
    """Path data with a new piece after each left-out (NaN) point (a long curve thinned to
    what its drawing shows, :func:`_thinned`)."""
    keep = _thinned(xs, ys)
    xs, ys = xs[keep], ys[keep]
    ok = np.isfinite(xs) & np.isfinite(ys)
    parts, pen = [], False
    for x, y, good in zip(xs.tolist(), ys.tolist(), ok.tolist()):
        if good:
            parts.append(f"{'L' if pen else 'M'}{x:.2f} {y:.2f}")
        pen = good
    return "".join(parts)


def _dasharray(dash: str | None, width: float) -> str:
    """The SVG attribute of a dash pattern given in line widths (empty for a solid line)."""
    if not dash:
        return ""
    try:
        values = [float(v) * width for v in dash.replace(",", " ").split()]
    except ValueError:
        return ""
    if not values or not all(math.isfinite(v) and v >= 0 for v in values):
        return ""
    return ' stroke-dasharray="' + " ".join(f"{v:g}" for v in values) + '"'


def _minor_labels(majors: list[int], minors: list[float]) -> list[tuple[float, str]]:
    """The minor ticks of a log axis, those at 2, 3 and 5 times a power of ten labelled
    (``3``, ``0.02``) when the axis spans less than two labelled decades."""
    if len(majors) >= 2:
        return [(m, "") for m in minors]
    out = []
    for m in minors:
        mantissa = m / 10.0 ** math.floor(math.log10(m) + 1e-9)
        label = f"{m:.3g}" if any(abs(mantissa - v) < 1e-6 for v in (2, 3, 5)) else ""
        out.append((m, label.replace("-", "\u2212")))
    return out


def _x_ticks(frame: _Frame) -> list[tuple[float, str, bool]]:
    """(value, label, minor) of the x ticks."""
    if frame.xticks is not None:
        return [(float(v), label, False) for v, label in frame.xticks
                if frame.xlim[0] <= v <= frame.xlim[1]]
    if frame.xlog:
        majors, minors = log_ticks(*frame.xlim)
        return ([(10.0 ** k, f"$10^{{{k}}}$", False) for k in majors]
                + [(m, label, not label) for m, label in _minor_labels(majors, minors)])
    ticks = [t for t in nice_ticks(*frame.xlim) if frame.xlim[0] <= t <= frame.xlim[1]]
    labels, _ = tick_labels(ticks)
    return [(t, label, False) for t, label in zip(ticks, labels)]


def _axes(frame: _Frame, grid: bool = True) -> tuple[list[str], list[str]]:
    """Grid lines (under the curves; none with ``grid=False``) and ticks with labels
    (over them)."""
    under: list[str] = []
    over: list[str] = []
    tick = 'stroke="#000" stroke-width="0.8"'
    for t, label, minor in _x_ticks(frame):
        x = float(frame.x(t))
        if minor:
            over.append(f'<line x1="{x:.2f}" y1="{frame.bottom:.2f}" x2="{x:.2f}" '
                        f'y2="{frame.bottom + 2.0:.2f}" stroke="#000" stroke-width="0.6"/>')
            continue
        if frame.xticks is None:  # named ticks (under bars) have no grid line
            under.append(f'<line x1="{x:.2f}" y1="{frame.top:.2f}" x2="{x:.2f}" '
                         f'y2="{frame.bottom:.2f}" stroke="#e6e6e6" stroke-width="0.8"/>')
        over.append(f'<line x1="{x:.2f}" y1="{frame.bottom:.2f}" x2="{x:.2f}" '
                    f'y2="{frame.bottom + 3.5:.2f}" {tick}/>')
        over.append(_text(x, frame.bottom + 15.0, label, TICK_FONT))
    xpower = 0 if frame.xlog or frame.xticks is not None else tick_labels(
        [t for t in nice_ticks(*frame.xlim) if frame.xlim[0] <= t <= frame.xlim[1]])[1]
    if xpower:
        over.append(_text(frame.right, frame.bottom + 27.0, f"$\\times 10^{{{xpower}}}$",
                          TICK_FONT, "end"))
    if not grid:
        under = []
    for y, label, minor in _y_ticks(frame):
        length = 2.0 if minor else 3.5
        if not minor:
            under.append(f'<line x1="{frame.left:.2f}" y1="{y:.2f}" x2="{frame.right:.2f}" '
                         f'y2="{y:.2f}" stroke="#e6e6e6" stroke-width="0.8"/>')
            over.append(_text(frame.left - 6.0, y + 3.5, label, TICK_FONT, "end"))
        over.append(f'<line x1="{frame.left - length:.2f}" y1="{y:.2f}" x2="{frame.left:.2f}" '
                    f'y2="{y:.2f}" stroke="#000" stroke-width="{0.6 if minor else 0.8}"/>')
    power = _y_power(frame)
    if power:
        over.append(_text(frame.left, frame.top - 5.0, f"$\\times 10^{{{power}}}$", TICK_FONT,
                          "start"))
    return under, over


def _linear_y_ticks(frame: _Frame) -> list[float]:
    if frame.yticks is not None:
        return [float(t) for t in frame.yticks if frame.ylim[0] <= t <= frame.ylim[1]]
    return [t for t in nice_ticks(*frame.ylim, most=7) if frame.ylim[0] <= t <= frame.ylim[1]]


def _y_ticks(frame: _Frame) -> list[tuple[float, str, bool]]:
    """(position, label, minor) of the y ticks."""
    if frame.ylog:
        majors, minors = log_ticks(*frame.ylim)
        return ([(float(frame.y(10.0 ** k)), f"$10^{{{k}}}$", False) for k in majors]
                + [(float(frame.y(m)), label, not label)
                   for m, label in _minor_labels(majors, minors)])
    ticks = _linear_y_ticks(frame)
    labels, _ = tick_labels(ticks)
    return [(float(frame.y(t)), label, False) for t, label in zip(ticks, labels)]


def _y_power(frame: _Frame) -> int:
    """The power of ten the linear y tick labels are given in (0: none)."""
    if frame.ylog:
        return 0
    return tick_labels(_linear_y_ticks(frame))[1]


def _y_label_texts(chart: Chart) -> list[str]:
    frame = _Frame(0.0, 1.0, 0.0, 1.0, (0.0, 1.0), y_limits(chart), chart.ylog,
                   yticks=chart.yticks)
    return [label for _, label, minor in _y_ticks(frame) if not minor]


def _star(x: float, y: float, outer: float, inner: float) -> str:
    points = []
    for k in range(10):
        r = outer if k % 2 == 0 else inner
        angle = math.pi / 2 + k * math.pi / 5
        points.append(f"{x + r * math.cos(angle):.2f},{y - r * math.sin(angle):.2f}")
    return " ".join(points)


def _marker_svg(shape: str, x: float, y: float, color: str, filled: bool = True) -> str:
    if shape == "point":
        return f'<circle cx="{x:.2f}" cy="{y:.2f}" r="2.2" fill="{color}"/>'
    if shape == "cross":
        return (f'<path d="M{x - 2.5:.2f} {y - 2.5:.2f}l5 5m0 -5l-5 5" stroke="{color}" '
                'stroke-width="1" fill="none"/>')
    if shape in _OWN_COLOUR:
        paint = (f'fill="{color}" stroke="#000" stroke-width="0.6"' if filled else
                 f'fill="none" stroke="{color}" stroke-width="1"')
        if shape == "circle":
            return f'<circle cx="{x:.2f}" cy="{y:.2f}" r="3.5" {paint}/>'
        if shape == "square":
            return f'<rect x="{x - 3:.2f}" y="{y - 3:.2f}" width="6" height="6" {paint}/>'
        points = {"diamond": f"{x:.2f},{y - 4:.2f} {x + 3:.2f},{y:.2f} {x:.2f},{y + 4:.2f} "
                             f"{x - 3:.2f},{y:.2f}",
                  "triangle": f"{x:.2f},{y - 4:.2f} {x + 3.5:.2f},{y + 3:.2f} "
                              f"{x - 3.5:.2f},{y + 3:.2f}",
                  "star": _star(x, y, 5.5, 2.2)}[shape]
        return f'<polygon points="{points}" {paint}/>'
    if shape == "peak":
        return (f'<polygon points="{x - 3.5:.2f},{y - 3.0:.2f} {x + 3.5:.2f},{y - 3.0:.2f} '
                f'{x:.2f},{y + 3.5:.2f}" fill="{color}" stroke="#000" stroke-width="0.6"/>')
    if shape == "ring":
        return (f'<circle cx="{x:.2f}" cy="{y:.2f}" r="3" fill="#fff" stroke="{color}"'
                ' stroke-width="1"/>')
    return f'<circle cx="{x:.2f}" cy="{y:.2f}" r="2.5" fill="{color}"/>'


def _panel(chart: Chart, ident: str, height: float = HEIGHT) -> list[str]:
    """The SVG elements of one chart (its legend, axes, curves and labels)."""
    rows = _legend_rows(legend_keys(chart), 0.9 * WIDTH)
    frame = _frame(chart, len(rows), _y_label_texts(chart), height)
    clip = f"{ident}-plot"
    hatches = _hatches(chart, ident)
    under, over = _axes(frame, grid=not chart.fields)
    body = [f'<defs><clipPath id="{clip}"><rect x="{frame.left:.2f}" y="{frame.top:.2f}" '
            f'width="{frame.right - frame.left:.2f}" height="{frame.bottom - frame.top:.2f}"/>'
            f"</clipPath>{''.join(_pattern(i, c) for c, i in hatches.items())}</defs>",
            f'<rect width="100%" height="{height:g}" fill="#fff"/>'
            if height != HEIGHT else '<rect width="100%" height="100%" fill="#fff"/>']
    for span in chart.spans:
        body += _span_svg(span, frame, hatches)
    body += [*under, f'<g clip-path="url(#{clip})" fill="none">']
    for field in chart.fields:
        body.append(_field_svg(field, frame, hatches))
    for bar in chart.bars:
        body += _bar_svg(bar, frame)
    for rule in chart.rules:
        dash = _dasharray(rule.dash, 1.0)
        if rule.vertical:
            x = float(frame.x(rule.at))
            coords = f'x1="{x:.2f}" y1="{frame.top:.2f}" x2="{x:.2f}" y2="{frame.bottom:.2f}"'
        else:
            y = float(frame.y(rule.at))
            coords = f'x1="{frame.left:.2f}" y1="{y:.2f}" x2="{frame.right:.2f}" y2="{y:.2f}"'
        body.append(f'<line {coords} stroke="{rule.color}" stroke-width="{rule.width:g}"{dash}/>')
    for curve in chart.colored():
        path = _polyline(frame.x(curve.x), frame.y(curve.y)) if curve.line else ""
        opacity = f' opacity="{curve.opacity:g}"' if curve.opacity < 1.0 else ""
        if path:
            body.append(f'<path d="{path}" stroke="{curve.color}" stroke-width="{curve.width:g}"'
                        f'{_dasharray(curve.dash, curve.width)}{opacity}'
                        ' stroke-linejoin="round" stroke-linecap="round"/>')
        marks = _marks(curve, frame) if curve.marker or not curve.line else ""
        if marks:
            width = 0.9 if curve.marker == "cross" else 2.4
            body.append(f'<path d="{marks}" stroke="{curve.color}" stroke-width="{width:g}"'
                        f'{opacity} stroke-linecap="round"/>')
    for m in chart.markers:
        x, y = float(frame.x(m.x)), float(frame.y(m.y))
        if math.isfinite(x) and math.isfinite(y):
            body.append(_marker_svg(m.shape, x, y, m.color, m.filled))
    body.append("</g>")
    body.append(f'<rect x="{frame.left:.2f}" y="{frame.top:.2f}" '
                f'width="{frame.right - frame.left:.2f}" height="{frame.bottom - frame.top:.2f}"'
                ' fill="none" stroke="#000" stroke-width="0.8"/>')
    body += over
    for field in chart.fields:
        body += _colorbar_svg(field, frame, ident)
    for note in chart.notes:
        x = float(frame.x(note.at))
        if math.isfinite(x) and frame.left <= x <= frame.right:
            body.append(f'<text x="{x:.2f}" y="{frame.top + 10.0:.2f}" font-size="8" '
                        f'text-anchor="middle" fill="{note.color}" stroke="#fff" '
                        f'stroke-width="3" paint-order="stroke">{_tspans(note.text, 8.0)}</text>')
    if chart.title:
        body.append(_text((frame.left + frame.right) / 2, frame.top - 5.0, chart.title,
                          TICK_FONT))
    body.append(_text((frame.left + frame.right) / 2, height - 8.0, chart.xlabel, TICK_FONT))
    body.append(_text(13.0, (frame.top + frame.bottom) / 2, chart.ylabel, TICK_FONT,
                      rotate=True))
    body += _legend(rows, frame, hatches)
    return body


def _hatches(chart: Chart, ident: str) -> dict[str, str]:
    """The hatch colours a chart uses, each with the id of its SVG pattern."""
    colors = [s.hatch for s in chart.spans if s.hatch]
    colors += [HATCH_COLOR for f in chart.fields if f.missing]
    return {c: f"{ident}-hatch-{k}" for k, c in enumerate(dict.fromkeys(colors))}


def _pattern(ident: str, color: str) -> str:
    """An SVG pattern of diagonal lines on white (matplotlib's ``////`` hatch)."""
    return (f'<pattern id="{ident}" patternUnits="userSpaceOnUse" width="5" height="5">'
            '<rect width="5" height="5" fill="#fff"/>'
            f'<path d="M-1 1l2 -2M0 5l5 -5M4 6l2 -2" stroke="{html.escape(color)}" '
            'stroke-width="0.7"/></pattern>')


def _span_svg(span: Span, frame: _Frame, hatches: dict[str, str]) -> list[str]:
    fill = f"url(#{hatches[span.hatch]})" if span.hatch else span.color
    if span.vertical:
        x0, x1 = sorted((float(frame.x(span.start)), float(frame.x(span.stop))))
        x0, x1 = max(x0, frame.left), min(x1, frame.right)
        if math.isfinite(x0) and math.isfinite(x1) and x1 > x0:
            return [f'<rect x="{x0:.2f}" y="{frame.top:.2f}" width="{x1 - x0:.2f}" '
                    f'height="{frame.bottom - frame.top:.2f}" fill="{fill}"/>']
        return []
    y0, y1 = sorted((float(frame.y(span.start)), float(frame.y(span.stop))))
    y0, y1 = max(y0, frame.top), min(y1, frame.bottom)
    if math.isfinite(y0) and math.isfinite(y1) and y1 > y0:
        return [f'<rect x="{frame.left:.2f}" y="{y0:.2f}" width="{frame.right - frame.left:.2f}" '
                f'height="{y1 - y0:.2f}" fill="{fill}"/>']
    return []


def _bar_svg(bar: Bar, frame: _Frame) -> list[str]:
    """A bar series' rectangles, then its error bars (a stem and two caps each)."""
    out, whiskers = [], []
    zero = float(frame.y(0.0))
    edge = (f' stroke="{bar.edge}" stroke-width="0.4"' if bar.edge else ' stroke="none"')
    x = np.asarray(bar.x, float)
    heights = np.asarray(bar.heights, float)
    errors = (np.full(x.shape, math.nan) if bar.errors is None else
              np.broadcast_to(np.asarray(bar.errors, float), x.shape))
    for k, (c, h, w, e) in enumerate(zip(x.tolist(), heights.tolist(), bar.widths().tolist(),
                                         errors.tolist())):
        x0, x1 = float(frame.x(c - w / 2)), float(frame.x(c + w / 2))
        y = float(frame.y(h))
        if all(math.isfinite(v) for v in (x0, x1, y, zero)):
            color = bar.colors[k % len(bar.colors)] if bar.colors else COLORS[0]
            out.append(f'<rect x="{x0:.2f}" y="{min(y, zero):.2f}" width="{x1 - x0:.2f}" '
                       f'height="{abs(zero - y):.2f}" fill="{color}"{edge}/>')
        mid = float(frame.x(c))
        low, high = float(frame.y(h - e)), float(frame.y(h + e))
        if all(math.isfinite(v) for v in (mid, low, high)):
            whiskers += [f'<line x1="{mid:.2f}" y1="{low:.2f}" x2="{mid:.2f}" y2="{high:.2f}" '
                         'stroke="#000" stroke-width="1"/>']
            whiskers += [f'<line x1="{mid - 3:.2f}" y1="{v:.2f}" x2="{mid + 3:.2f}" '
                         f'y2="{v:.2f}" stroke="#000" stroke-width="1"/>' for v in (low, high)]
    return out + whiskers


def _marks(curve: Curve, frame: _Frame) -> str:
    """Path data of a mark at every point of a curve: a dot (a zero-length piece with a
    round cap) or a small cross."""
    xs, ys = frame.x(curve.x), frame.y(curve.y)
    ok = np.isfinite(xs) & np.isfinite(ys)
    if curve.marker == "cross":
        return "".join(f"M{x - 1.6:.2f} {y - 1.6:.2f}l3.2 3.2m0 -3.2l-3.2 3.2"
                       for x, y in zip(xs[ok].tolist(), ys[ok].tolist()))
    return "".join(f"M{x:.2f} {y:.2f}h0" for x, y in zip(xs[ok].tolist(), ys[ok].tolist()))


def _field_svg(field: Field, frame: _Frame, hatches: dict[str, str]) -> str:
    """A field's cells as rectangles (edges crisp, so that neighbours leave no seam),
    over a hatched ground where cells without a value are named."""
    xs, ys = frame.x(field.x), frame.y(field.y)
    out = ['<g shape-rendering="crispEdges">']
    if field.missing and xs.size >= 2 and ys.size >= 2:
        x0, x1 = sorted((float(xs[0]), float(xs[-1])))
        y0, y1 = sorted((float(ys[0]), float(ys[-1])))
        if all(math.isfinite(v) for v in (x0, x1, y0, y1)):
            out.append(f'<rect x="{x0:.2f}" y="{y0:.2f}" width="{x1 - x0:.2f}" '
                       f'height="{y1 - y0:.2f}" fill="url(#{hatches[HATCH_COLOR]})"/>')
    for j, row in enumerate(field.colors()[:max(ys.size - 1, 0)]):
        y0, y1 = sorted((float(ys[j]), float(ys[j + 1])))
        for i, color in enumerate(row[:max(xs.size - 1, 0)]):
            x0, x1 = sorted((float(xs[i]), float(xs[i + 1])))
            if color is not None and all(math.isfinite(v) for v in (x0, x1, y0, y1)):
                out.append(f'<rect x="{x0:.2f}" y="{y0:.2f}" width="{x1 - x0:.2f}" '
                           f'height="{y1 - y0:.2f}" fill="{color}"/>')
    return "".join(out) + "</g>"


def field_ticks(field: Field) -> tuple[list[tuple[float, str]], int]:
    """The colour bar's ticks: (position from 0 at the bottom to 1 at the top, label), and
    the power of ten linear labels are given in (0: none).

    Examples
    --------
    >>> f = Field(np.arange(3.0), np.arange(2.0), np.array([[1e-2, 1e2]]), "z", log=True)
    >>> ticks, power = field_ticks(f)
    >>> [at for at, _ in ticks], ticks[0][1], power
    ([0.0, 0.25, 0.5, 0.75, 1.0], '$10^{-2}$', 0)
    """
    low, high = field.range()
    if field.levels is not None and len(field.levels) >= 2:
        levels = [float(v) for v in field.levels]
        every = max(1, math.ceil(len(levels) / 9))
        chosen = list(range(0, len(levels), every))
        labels, power = tick_labels([levels[k] for k in chosen])
        return [(k / (len(levels) - 1), label) for k, label in zip(chosen, labels)], power
    if field.log:
        lo, hi = math.log10(low), math.log10(high)
        majors, _ = log_ticks(low, high, most=7)
        return [((k - lo) / (hi - lo), f"$10^{{{k}}}$") for k in majors], 0
    ticks = [t for t in nice_ticks(low, high, most=7) if low <= t <= high]
    labels, power = tick_labels(ticks)
    span = high - low if high > low else 1.0
    return [((t - low) / span, label) for t, label in zip(ticks, labels)], power


def _colorbar_room(chart: Chart) -> float:
    """The width the colour bars right of the plot take."""
    room = 0.0
    for field in chart.fields:
        if field.label:
            ticks, _ = field_ticks(field)
            widest = max((text_width(label, TICK_FONT) for _, label in ticks), default=10.0)
            room += 10.0 + 12.0 + 4.0 + widest + 24.0
    return room


def _colorbar_svg(field: Field, frame: _Frame, ident: str) -> list[str]:
    """The colour bar of a field right of the plot: its colours bottom to top, ticks and
    labels on its right, its label beside them."""
    if not field.label:
        return []
    left, top, bottom = frame.right + 10.0, frame.top, frame.bottom
    out = []
    if field.levels is not None and len(field.levels) >= 2:
        bands = field.bands()
        step = (bottom - top) / len(bands)
        out += [f'<rect x="{left:.2f}" y="{bottom - (k + 1) * step:.2f}" width="12" '
                f'height="{step:.2f}" fill="{color}"/>' for k, color in enumerate(bands)]
    else:
        gradient = f"{ident}-colors"
        stops = "".join(f'<stop offset="{k / (len(FIELD_COLORS) - 1):.4f}" stop-color="{c}"/>'
                        for k, c in enumerate(FIELD_COLORS))
        out.append(f'<defs><linearGradient id="{gradient}" x1="0" y1="1" x2="0" y2="0">{stops}'
                   '</linearGradient></defs>')
        out.append(f'<rect x="{left:.2f}" y="{top:.2f}" width="12" height="{bottom - top:.2f}" '
                   f'fill="url(#{gradient})"/>')
    out.append(f'<rect x="{left:.2f}" y="{top:.2f}" width="12" height="{bottom - top:.2f}" '
               'fill="none" stroke="#000" stroke-width="0.8"/>')
    ticks, power = field_ticks(field)
    widest = max((text_width(label, TICK_FONT) for _, label in ticks), default=10.0)
    for at, label in ticks:
        y = bottom - at * (bottom - top)
        out.append(f'<line x1="{left + 12:.2f}" y1="{y:.2f}" x2="{left + 15.5:.2f}" '
                   f'y2="{y:.2f}" stroke="#000" stroke-width="0.8"/>')
        out.append(_text(left + 18.0, y + 3.5, label, TICK_FONT, "start"))
    if power:
        out.append(_text(left, top - 5.0, f"$\\times 10^{{{power}}}$", TICK_FONT, "start"))
    out.append(_text(left + 12.0 + 4.0 + widest + 18.0, (top + bottom) / 2, field.label,
                     TICK_FONT, rotate=True))
    return out


def _svg(body: list[str], height: float, title: str) -> str:
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH:g}pt" height="{height:g}pt"'
            f' viewBox="0 0 {WIDTH:g} {height:g}" version="1.1" role="img"'
            f' font-family="{FONT}"><title>{html.escape(title)}</title>'
            + "".join(body) + "</svg>")


def chart_svg(chart: Chart, ident: str) -> str:
    """The chart as an ``<svg>`` element for inline HTML.

    Parameters
    ----------
    chart : Chart
    ident : str
        A prefix for the element ids of this chart (unique in its page).

    Returns
    -------
    str

    Examples
    --------
    >>> c = Chart((Curve(np.linspace(0, 1, 5), np.linspace(0, 1, 5) ** 2, "$y$"),),
    ...           "t [s]", "y", (0.0, 1.0), rules=(Rule(0.0, vertical=False),))
    >>> s = chart_svg(c, "f1")
    >>> s.count("<path"), s.endswith("</svg>")
    (1, True)
    """
    ident = re.sub(r"[^A-Za-z0-9_-]", "-", ident)
    return _svg(_panel(chart, ident), HEIGHT, describe(chart))


def panel_heights(charts: Charts) -> list[float]:
    """The SVG height of each panel in points (the tallest as high as a single chart)."""
    ratios = list(charts.heights or [1.0] * len(charts.panels))
    ratios += [1.0] * (len(charts.panels) - len(ratios))
    tallest = max(ratios[:len(charts.panels)], default=1.0) or 1.0
    return [HEIGHT * max(0.6, r / tallest) for r in ratios[:len(charts.panels)]]


def charts_svg(charts: Charts, ident: str) -> str:
    """The stacked charts as one ``<svg>`` element for inline HTML (the figure's title on
    top, each panel as high as its share).

    Examples
    --------
    >>> a = Chart((Curve(np.array([1.0, 10.0]), np.array([1.0, 2.0]), "$x$"),), "f [Hz]",
    ...           "amplitude", (1.0, 10.0), xlog=True, ylog=True)
    >>> s = charts_svg(Charts((a, a), title="two"), "f2")
    >>> s.count("<path"), "f2-1-plot" in s
    (2, True)
    """
    ident = re.sub(r"[^A-Za-z0-9_-]", "-", ident)
    lines = [line for line in charts.title.split("\n") if line] if charts.title else []
    y = 16.0 * len(lines) + (6.0 if lines else 0.0)
    body = ['<rect width="100%" height="100%" fill="#fff"/>']
    body += [_text(WIDTH / 2, 14.0 + 16.0 * k, line, 11.0) for k, line in enumerate(lines)]
    for k, (panel, height) in enumerate(zip(charts.panels, panel_heights(charts))):
        inner = _panel(panel, ident if k == 0 else f"{ident}-{k}", height)
        body.append(f'<g transform="translate(0 {y:.2f})">' + "".join(inner) + "</g>")
        y += height
    return _svg(body, y, describe(charts))


def unit_text(unit: str) -> str:
    """A unit for a chart label, its powers raised (``m/s^2`` -> ``m/s$^{2}$``).

    Examples
    --------
    >>> unit_text("(m/s^2)^2/Hz")
    '(m/s$^{2}$)$^{2}$/Hz'
    """
    return re.sub(r"\^(-?[0-9]+)", r"$^{\1}$", unit.replace("$", ""))


def plain_text(label: str) -> str:
    """A label as plain text (its math set as characters: ``$x_{2}$`` -> ``x2``)."""
    return _NOT_XML.sub(" ", "".join(text for text, _, _ in text_runs(label)))


_SUBSCRIPTS = dict(zip("0123456789+-=()aehijklmnoprstuvx",
                       "₀₁₂₃₄₅₆₇₈₉₊₋₌₍₎ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓ"))
_SUPERSCRIPTS = dict(zip("0123456789+-=()ni", "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻⁼⁽⁾ⁿⁱ"))


def unicode_text(label: str) -> str:
    """A label as one line of Unicode text, for a canvas that sets no math: sub- and
    superscripts as their Unicode forms where every character has one
    (``$x_{1}$ [m/s$^{2}$]`` -> ``x₁ [m/s²]``), else written ``x_ab``; accents combined.

    Examples
    --------
    >>> unicode_text("amplitude $X$ [m/s$^{2}$]"), unicode_text("$x_{12}$")
    ('amplitude X [m/s²]', 'x₁₂')
    >>> unicode_text("$F_{ab}$")
    'F_ab'

    """
    out = []
    for text, level, _ in text_runs(label):
        table = _SUBSCRIPTS if level < 0 else _SUPERSCRIPTS if level > 0 else None
        if table is None:
            out.append(text)
        elif all(ch in table for ch in text):
            out.append("".join(table[ch] for ch in text))
        else:
            out.append(("_" if level < 0 else "^") + text)
    return _NOT_XML.sub(" ", "".join(out))


def describe(chart: Chart | Charts) -> str:
    """A one-line description of the chart for readers that cannot see it.

    Examples
    --------
    >>> describe(Chart((Curve(np.zeros(2), np.zeros(2), "$x_{1}$"),), "time $t$ [s]",
    ...                "response", (0.0, 1.0)))
    'response against time t [s]: x1'
    """
    if isinstance(chart, Charts):
        title = plain_text(chart.title.replace("\n", " ")).strip()
        return (f"{title}: " if title else "") + "; ".join(describe(p) for p in chart.panels)
    scale = " (logarithmic)" if chart.ylog else ""
    colours = "".join(f"; colour: {plain_text(f.label)}" for f in chart.fields if f.label)
    return (f"{plain_text(chart.ylabel)}{scale} against {plain_text(chart.xlabel)}: "
            + ", ".join(plain_text(c.label) for c in chart.curves) + colours)


def _legend(rows: list[list[tuple[_Key, float]]], frame: _Frame,
            hatches: dict[str, str] | None = None) -> list[str]:
    out = []
    for r, row in enumerate(rows):
        x = frame.right - sum(w for _, w in row) + 14.0
        y = 12.0 + 15.0 * r
        for key, width in row:
            if key.shape:
                out.append(_marker_svg(key.shape, x + 10.0, y - 3.5, key.color, key.filled))
            elif key.width > 4.0:  # a band
                hatch = (hatches or {}).get(key.hatch) if key.hatch else None
                paint = (f'fill="url(#{hatch})" stroke="{key.hatch}" stroke-width="0.6"'
                         if hatch else f'fill="{key.color}"')
                out.append(f'<rect x="{x:.2f}" y="{y - 7.5:.2f}" width="20" height="8" '
                           f'{paint}/>')
            else:
                out.append(f'<line x1="{x:.2f}" y1="{y - 3.5:.2f}" x2="{x + 20:.2f}" '
                           f'y2="{y - 3.5:.2f}" stroke="{key.color}" '
                           f'stroke-width="{key.width:g}"{_dasharray(key.dash, key.width)}/>')
            out.append(_text(x + 26.0, y, key.label, TICK_FONT, "start"))
            x += width
    return out


# -- matplotlib ------------------------------------------------------------------------------

def _linestyle(dash: str | None) -> Any:
    """A matplotlib line style from a dash pattern in line widths (solid if none)."""
    if not dash or not _dasharray(dash, 1.0):
        return "-"
    return (0, tuple(float(v) for v in dash.replace(",", " ").split()))


@lru_cache(maxsize=512)
def mathtext_label(label: str) -> str:
    """The label as matplotlib sets it: as it is where mathtext can set its math, else as
    plain text (its dollar signs escaped)."""
    if label.count("$") % 2 == 0 and "$" in label:
        from matplotlib.mathtext import MathTextParser

        try:
            for k, part in enumerate(label.split("$")):
                if k % 2:
                    MathTextParser("path").parse(f"${part}$")
        except ValueError:
            return plain_text(label).replace("$", r"\$")
        return label
    return label.replace("$", r"\$")


_MPL_MARKERS: dict[str, dict[str, Any]] = {
    "dot": {"marker": "o", "markersize": 5}, "point": {"marker": "o", "markersize": 4.4},
    "cross": {"marker": "x", "markersize": 5},
    "peak": {"marker": "v", "markersize": 7, "mec": "black", "mew": 0.6},
    "ring": {"marker": "o", "markersize": 6, "mfc": "white"},
    "circle": {"marker": "o", "markersize": 7}, "square": {"marker": "s", "markersize": 6},
    "diamond": {"marker": "D", "markersize": 6}, "triangle": {"marker": "^", "markersize": 7},
    "star": {"marker": "*", "markersize": 11}}


def _marker_style(shape: str, color: str, filled: bool) -> dict[str, Any]:
    """matplotlib's keywords of a marker: its shape, and its fill and outline."""
    style = dict(_MPL_MARKERS.get(shape, _MPL_MARKERS["dot"]))
    if shape in _OWN_COLOUR:
        style.update({"mfc": color, "mec": "black", "mew": 0.6} if filled else
                     {"mfc": "none", "mec": color, "mew": 1.0})
    return style


def _draw_panel(chart: Chart, ax: Axes, own: bool, legend_size: float | None = None,
                show_legend: bool = True) -> tuple[list[Any], list[str]]:
    """Draw one chart on an Axes (the drawing behind :func:`draw_chart` and
    :func:`draw_figure`); return its legend's handles and labels (in the order of
    :func:`legend_keys`, as the SVG lists them)."""
    for span in chart.spans:
        style: dict[str, Any] = ({"facecolor": "white", "edgecolor": span.hatch, "hatch": HATCH,
                                  "linewidth": 0} if span.hatch else {"color": span.color})
        (ax.axvspan if span.vertical else ax.axhspan)(span.start, span.stop, zorder=0, **style)
    for field in chart.fields:
        _draw_field(field, ax)
    for bar in chart.bars:
        errors: dict[str, Any] = {} if bar.errors is None else {
            "yerr": np.asarray(bar.errors, dtype=float), "capsize": 3,
            "error_kw": {"ecolor": "black", "elinewidth": 1.0, "capthick": 1.0}}
        edge: dict[str, Any] = {} if bar.edge is None else {"edgecolor": bar.edge,
                                                             "linewidth": 0.4}
        ax.bar(bar.x, bar.heights, width=bar.widths(), color=list(bar.colors) or None,
               **edge, **errors)
    lines = []
    for curve in chart.colored():
        y = np.where(np.asarray(curve.y) > 0, curve.y, np.nan) if chart.ylog else curve.y
        mark: dict[str, Any] = {} if not (curve.marker or not curve.line) else {
            "marker": "x" if curve.marker == "cross" else ".", "markersize": 3}
        (line,) = ax.plot(curve.x, y, label=mathtext_label(curve.label), color=curve.color,
                          linewidth=curve.width, linestyle=_linestyle(curve.dash)
                          if curve.line else "", alpha=curve.opacity if curve.opacity < 1 else None,
                          **mark)
        if curve.label:
            lines.append((curve, line))
    for m in chart.markers:
        ax.plot([m.x], [m.y], ls="", color=m.color, zorder=3,
                **_marker_style(m.shape, m.color, m.filled))
    for rule in chart.rules:
        style = {"color": rule.color, "linewidth": rule.width, "linestyle": _linestyle(rule.dash)}
        (ax.axvline if rule.vertical else ax.axhline)(rule.at, **style)
    for note in chart.notes:
        # above the curves (in the headroom the view leaves), on a white ground
        ax.annotate(mathtext_label(note.text), (note.at, 1.0),
                    xycoords=("data", "axes fraction"), textcoords="offset points",
                    xytext=(0, -3), ha="center", va="top", fontsize=8, color=note.color,
                    zorder=5, bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none",
                                    "alpha": 0.9})
    if chart.xlog:
        ax.set_xscale("log")
    if chart.ylog:
        ax.set_yscale("log")
    ax.set_xlabel(mathtext_label(chart.xlabel))
    ax.set_ylabel(mathtext_label(chart.ylabel))
    ax.set_xlim(*x_limits(chart))
    if chart.ylim is not None:
        ax.set_ylim(*y_limits(chart))
    if chart.yticks is not None:
        ax.set_yticks(list(chart.yticks))
    if chart.xticks is not None:
        ax.set_xticks([v for v, _ in chart.xticks])
        ax.set_xticklabels([mathtext_label(label) for _, label in chart.xticks], fontsize=10,
                           rotation=0 if len(chart.xticks) <= 8 else 90)
    if chart.title:
        ax.set_title(mathtext_label(chart.title), fontsize=10)
    ax.set_axisbelow(True)  # the grid under the bars
    if not chart.fields:  # the cells would hide it
        ax.grid(True, which="major", color="0.9",
                axis="y" if chart.xticks is not None else "both")
        if chart.xlog or chart.ylog:
            ax.grid(True, which="minor", color="0.95", linewidth=0.5)
    if chart.xlog:
        _log_minor_ticks(ax.xaxis, *ax.get_xlim())
    if chart.ylog:
        _log_minor_ticks(ax.yaxis, *ax.get_ylim())
    return _panel_legend(chart, ax, own, lines, legend_size, show_legend)


def _log_minor_ticks(axis: Axis, low: float, high: float) -> None:
    """A log axis's minor ticks as the SVG writer draws them (:func:`log_ticks`): on an
    axis of fewer than two labelled decades those at 2, 3 and 5 times a power of ten read
    ``3`` or ``0.02``, not ``3×10^0``; the others carry no label."""
    from matplotlib.ticker import FixedLocator, FuncFormatter

    low, high = min(low, high), max(low, high)
    if not (low > 0 and math.isfinite(high)):
        return
    majors, minors = log_ticks(low, high)
    labels = {f"{m:.6g}": label for m, label in _minor_labels(majors, minors)}
    axis.set_minor_locator(FixedLocator(minors))
    axis.set_minor_formatter(FuncFormatter(lambda v, _: labels.get(f"{v:.6g}", "")))
    axis.set_tick_params(which="minor", labelsize=8)


def _panel_legend(chart: Chart, ax: Axes, own: bool, lines: list[tuple[Curve, Any]],
                  legend_size: float | None, show: bool) -> tuple[list[Any], list[str]]:
    """The legend of a panel (``lines``: its labelled curves and their drawn lines), drawn
    where the chart puts it when ``show``; its handles and labels."""
    keys = legend_keys(chart)
    handles = [line if curve.line else _key_handle(key)
               for (curve, line), key in zip(lines, keys)]
    handles += [_key_handle(key) for key in keys[len(lines):]]
    labels = [mathtext_label(key.label) for key in keys]
    if show and chart.legend != "none" and (chart.curves or handles):
        options: dict[str, Any] = {"frameon": False}
        if legend_size is not None:
            options["fontsize"] = legend_size
        if chart.legend == "beside" and own:
            options.update(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                           frameon=True)
        elif chart.legend == "below":  # under the x label: it hides nothing
            from matplotlib.transforms import ScaledTranslation

            below = ScaledTranslation(0.0, -0.55, figure_of(ax).dpi_scale_trans)
            options.update(loc="upper center", bbox_to_anchor=(0.5, 0.0),
                           bbox_transform=ax.transAxes + below, ncols=min(3, len(handles) or 1))
        else:
            options["loc"] = "best"
        ax.legend(handles, labels, **options)
    return handles, labels


def _key_handle(key: _Key) -> Any:
    """A matplotlib legend handle drawn as the SVG draws the key."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    label = mathtext_label(key.label)
    if key.shape:
        return Line2D([], [], ls="", color=key.color, label=label,
                      **_marker_style(key.shape, key.color, key.filled))
    if key.width > 4.0:  # a band
        if key.hatch:
            return Patch(facecolor="white", edgecolor=key.hatch, hatch=HATCH, label=label)
        return Patch(color=key.color, label=label)
    return Line2D([], [], color=key.color, linewidth=key.width, linestyle=_linestyle(key.dash),
                  label=label)


def field_colormap(field: Field) -> tuple[Any, Any]:
    """matplotlib's colour map and norm of a field: the colour table of
    :data:`FIELD_COLORS` (the bands' colours with levels), over the field's range.

    Examples
    --------
    >>> f = Field(np.arange(3.0), np.arange(2.0), np.array([[0.0, 4.0]]), levels=(0, 2, 4))
    >>> cmap, norm = field_colormap(f)
    >>> cmap.N, type(norm).__name__
    (2, 'BoundaryNorm')
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm, Normalize

    if field.levels is not None and len(field.levels) >= 2:
        bands = field.bands()
        return (ListedColormap(bands, name="resonant-bands"),
                BoundaryNorm(list(field.levels), len(bands)))
    low, high = field.range()
    norm = LogNorm(low, high) if field.log else Normalize(low, high)
    return ListedColormap(_field_table(), name="resonant-field"), norm


def _draw_field(field: Field, ax: Axes) -> None:
    """A field's cells (a QuadMesh over a hatched ground where cells without a value are
    named) and its colour bar."""
    x, y = np.asarray(field.x, dtype=float), np.asarray(field.y, dtype=float)
    if field.missing and x.size >= 2 and y.size >= 2:  # the hatch shows through
        ax.fill_between([x[0], x[-1]], y[0], y[-1], facecolor="white", edgecolor=HATCH_COLOR,
                        hatch=HATCH, linewidth=0, zorder=0)
    cmap, norm = field_colormap(field)
    cells = ax.pcolormesh(x, y, np.ma.masked_invalid(field.values()), cmap=cmap, norm=norm,
                          shading="flat", zorder=1)
    if field.label:
        figure_of(ax).colorbar(cells, ax=ax, label=mathtext_label(field.label))


def draw_chart(chart: Chart, figure: Figure | None = None, ax: Axes | None = None) -> Any:
    """Draw the chart on a matplotlib figure (a new Axes filling it) or on the caller's
    ``ax``; return the Axes.

    Parameters
    ----------
    chart : Chart
    figure : matplotlib.figure.Figure, optional
        The figure to add the Axes to (needed unless ``ax`` is given).
    ax : matplotlib.axes.Axes, optional
        Draw here instead (the legend stays inside the axes).

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        if figure is None:
            raise ValueError("draw_chart needs a figure or an Axes")
        ax = figure.add_subplot(1, 1, 1)
        _draw_panel(chart, ax, own=True)
    else:
        _draw_panel(chart, ax, own=False)
    return ax


def figure_of(ax: Axes) -> Any:
    """The figure an Axes belongs to (the top-level one for a subfigure)."""
    fig = ax.figure
    root = getattr(fig, "get_figure", None)
    if root is not None:
        try:
            return root(root=True)
        except TypeError:  # matplotlib < 3.8: no ``root`` argument
            pass
    return getattr(fig, "figure", fig)


def axes_list(ax: Axes | Sequence[Axes] | npt.NDArray[Any]) -> list[Axes]:
    """One Axes, a sequence or an array of them (``fig.subplots``) as a list.

    Examples
    --------
    >>> axes_list([1, 2])
    [1, 2]
    """
    found: list[Axes] = list(np.ravel(np.asarray(ax, dtype=object)))
    return found


class Charted:
    """A result that describes its figure: the result writes :meth:`chart`, and
    :meth:`plot` draws that one description with matplotlib and writes it to a file, so
    that a result's plot, its report figure and its page show one picture.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Line(Charted):
    ...     def chart(self) -> Chart:
    ...         return Chart((Curve([0.0, 1.0], [0.0, 1.0], "y"),), "x", "y", (0.0, 1.0))
    >>> len(Line().plot().axes)
    1
    """

    def chart(self) -> Chart | Charts:
        """The figure's description (written by each result).

        Returns
        -------
        Chart or Charts
        """
        raise NotImplementedError

    def plot(self, path: PathArg = None, ax: Axes | Sequence[Axes] | None = None) -> Figure:
        """Draw :meth:`chart` with matplotlib (into ``ax`` where given) and write it to
        ``path`` where given (.png, .svg or .pdf).

        Parameters
        ----------
        path : str or PathLike, optional
        ax : matplotlib Axes or sequence of them, optional

        Returns
        -------
        matplotlib.figure.Figure
        """
        check_plot_path(path)
        return save_figure(draw_figure(self.chart(), ax), path)


def check_plot_path(path: PathArg) -> Path | None:
    """``path`` as a :class:`~pathlib.Path` if it names a ``.png``, ``.svg`` or ``.pdf`` file
    (None for None), before any work is done.

    Examples
    --------
    >>> check_plot_path("response.svg").name
    'response.svg'
    >>> check_plot_path("r.txt")
    Traceback (most recent call last):
    ...
    resonant.errors.AnalysisError: cannot write a plot to 'r.txt': use a .png, .svg or .pdf file
    """
    if path is None:
        return None
    path = Path(path)
    if path.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise AnalysisError(f"cannot write a plot to '{path}': use a .png, .svg or .pdf file")
    return path


#: the resolution of every figure written to a raster file (dots per inch)
FIGURE_DPI = 150


def save_figure(fig: Figure, path: PathArg, *, dpi: float | str = FIGURE_DPI,
                bbox_inches: str | None = None,
                metadata: Mapping[str, str | None] | None = None) -> Figure:
    """Write ``fig`` to ``path`` (nothing for None), attaching an Agg canvas if it has none,
    and return it; ``dpi`` (default :data:`FIGURE_DPI`, one resolution for every figure),
    ``bbox_inches`` and ``metadata`` as :meth:`matplotlib.figure.Figure.savefig` takes them.

    A figure with a layout engine (:func:`draw_figure`'s constrained layout) already fills
    its size, so ``bbox_inches="tight"`` is not applied to it (measuring every text once
    more cost 15-50 % of a save); a PNG of such a figure is laid out once at the file's
    resolution and printed with the layout fixed, which spares the second, draw-disabled
    pass over every artist that :meth:`~matplotlib.figure.Figure.savefig` makes to run
    the layout (docs/performance.md, "Figures").

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> save_figure(Figure(), None).__class__.__name__
    'Figure'
    """
    path = check_plot_path(path)
    if path is None:
        return fig
    from matplotlib.backend_bases import FigureCanvasBase
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if type(fig.canvas) is FigureCanvasBase:  # a bare Figure: give it a canvas to print on
        FigureCanvasAgg(fig)
    engine = fig.get_layout_engine()
    if engine is not None:
        bbox_inches = None
    raster = path.suffix.lower() == ".png" and not isinstance(dpi, str)
    try:
        # the plain Agg canvas only: a GUI canvas would resize its window with the dpi
        if engine is not None and raster and type(fig.canvas) is FigureCanvasAgg:
            _save_laid_out(fig, path, float(dpi), metadata)
        else:
            fig.savefig(path, dpi=dpi, bbox_inches=bbox_inches,
                        metadata=dict(metadata) if metadata is not None else None)
    except OSError as exc:
        raise AnalysisError(f"cannot write the plot '{path}': {exc.strerror or exc}") from None
    return fig


def _save_laid_out(fig: Figure, path: Path, dpi: float,
                   metadata: Mapping[str, str | None] | None) -> None:
    """Run ``fig``'s layout engine at ``dpi`` (as savefig would, on the same Agg renderer)
    and print the PNG with no engine, then give the figure its engine and dpi back."""
    import matplotlib

    engine = fig.get_layout_engine()
    assert engine is not None
    shown = fig.dpi
    try:
        fig.set_dpi(dpi)
        engine.execute(fig)
        # no engine at all (None; "none" leaves a placeholder, and savefig would run
        # its draw-disabled pass for that one too)
        with matplotlib.rc_context({"figure.autolayout": False,
                                    "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)
        fig.savefig(path, dpi=dpi, metadata=dict(metadata) if metadata is not None else None)
    finally:
        fig.set_layout_engine(engine)
        fig.set_dpi(shown)


def draw_figure(charts: Charts | Chart, ax: Axes | Sequence[Axes] | None = None) -> Figure:
    """Draw the charts with matplotlib's object API: a new figure (no pyplot) with one
    Axes per panel, or the caller's Axes (one per panel, the first panels when fewer).

    Parameters
    ----------
    charts : Charts or Chart
    ax : Axes or sequence of Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the one ``ax`` belongs to.

    Examples
    --------
    >>> c = Chart((Curve(np.array([1.0, 10.0]), np.array([1.0, 2.0]), "$x$"),), "f [Hz]",
    ...           "amplitude", (1.0, 10.0), xlog=True)
    >>> fig = draw_figure(Charts((c, c), title="two"))
    >>> len(fig.axes), fig.axes[0].get_xscale()
    (2, 'log')
    """
    if isinstance(charts, Chart):
        charts = Charts((charts,))
    if ax is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=charts.size, layout="constrained")
        n = len(charts.panels)
        columns = max(1, min(charts.columns, n))
        rows = math.ceil(n / columns)
        grid = fig.subplots(rows, columns, sharex=charts.sharex, squeeze=False,
                            gridspec_kw={"height_ratios": list(charts.heights)}
                            if charts.heights and columns == 1 else None)
        axes = list(grid.ravel())
        for extra in axes[n:]:
            extra.set_visible(False)
        axes = axes[:n]
    else:
        axes = list(np.ravel(np.asarray(ax, dtype=object)))
        if not axes:
            raise ValueError("draw_figure needs at least one Axes")
        fig = figure_of(axes[0])
    own = ax is None
    below = charts.legend == "below" and own
    entries: dict[str, Any] = {}  # the panels' legend entries, each label once
    for k, (panel, axis) in enumerate(zip(charts.panels, axes)):
        handles, labels = _draw_panel(panel, axis, own, legend_size=8.0, show_legend=not (
            below or (charts.legend == "below" and k > 0)))
        for handle, label in zip(handles, labels):
            entries.setdefault(label, handle)
        if own and charts.sharex and charts.columns == 1 and k < len(charts.panels) - 1:
            axis.set_xlabel("")
    if below and entries:
        fig.legend(list(entries.values()), list(entries), loc="outside lower center", fontsize=9,
                   ncols=3, frameon=False)
    title = "\n".join(mathtext_label(t) for t in charts.title.split("\n"))
    if charts.title and not charts.panels[0].title:  # over the first panel (also ax=)
        axes[0].set_title(title, fontsize=10)
    elif own and charts.title:
        fig.suptitle(title, fontsize=11)
    return fig


#: at most this many curves are drawn (a 1000-coordinate sweep shows the first ones)
MAX_CURVES = 8


__all__ = ["Charted", "MAX_CURVES", "Annotation", "Bar", "Chart", "Charts", "Curve", "Field",
           "Marker", "Rule", "Span", "chart_svg", "field_colormap", "field_ticks", "CURVE_MARKERS",
           "FIELD_COLORS", "HATCH", "HATCH_COLOR", "charts_svg", "check_plot_path", "describe",
           "draw_chart", "draw_figure", "figure_of", "legend_keys", "mathtext_label",
           "panel_heights", "plain_text", "nice_ticks", "log_ticks", "tick_labels", "text_runs",
           "unicode_text", "unit_text", "FIGURE_DPI", "text_width", "x_limits", "y_limits",
           "save_figure",
           "WIDTH", "HEIGHT", "COLORS", "MARKER_SHAPES", "LEGENDS"]
