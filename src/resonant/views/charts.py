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
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
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
    """

    x: np.ndarray
    y: np.ndarray
    label: str
    color: str | None = None
    width: float = 1.4
    dash: str | None = None

    def to_dict(self) -> dict[str, Any]:
        return {"x": _numbers(self.x), "y": _numbers(self.y), "label": self.label,
                "text": unicode_text(self.label), "color": self.color, "width": self.width,
                "dash": self.dash}


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
    """A shaded band across the axes from x = ``start`` to x = ``stop`` (under the curves)."""

    start: float
    stop: float
    color: str = "#e6e6e6"
    label: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {"start": _number(self.start), "stop": _number(self.stop), "color": self.color,
                "label": self.label}


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
    """Bars of width ``width`` centred at ``x``, from zero to ``heights``, each in its
    colour (a mode shape's components)."""

    x: np.ndarray
    heights: np.ndarray
    colors: tuple[str, ...]
    width: float = 0.6

    def to_dict(self) -> dict[str, Any]:
        return {"x": _numbers(self.x), "heights": _numbers(self.heights),
                "colors": list(self.colors), "width": self.width}


#: where a chart's legend goes: inside the axes, beside them (right of a figure of its
#: own; inside when drawn into a caller's axes), or none
LEGENDS = ("best", "beside", "none")


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
                [[_number(v), label] for v, label in self.xticks]}


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
                        / 2)
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


#: marker shapes named in the legend in their own colour (the special points' kinds)
_OWN_COLOUR = ("circle", "square", "diamond", "triangle", "star")


def legend_keys(chart: Chart) -> list[_Key]:
    """The legend's entries: the curves, then each labelled rule, band and marker kind once."""
    if chart.legend == "none":
        return []
    keys = [_Key(c.label, c.color or "#000", c.width, c.dash) for c in chart.colored()
            if c.label]
    seen: set[str] = set()
    for rule in chart.rules:
        if rule.label and rule.label not in seen:
            seen.add(rule.label)
            keys.append(_Key(rule.label, rule.color, rule.width, rule.dash))
    for span in chart.spans:
        if span.label and span.label not in seen:
            seen.add(span.label)
            keys.append(_Key(span.label, span.color, 8.0))
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


def _polyline(xs: np.ndarray, ys: np.ndarray) -> str:
    """Path data with a new piece after each left-out (NaN) point."""
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


def _axes(frame: _Frame) -> tuple[list[str], list[str]]:
    """Grid lines (under the curves) and ticks with labels (over them)."""
    under, over = [], []
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
    under, over = _axes(frame)
    body = [f'<defs><clipPath id="{clip}"><rect x="{frame.left:.2f}" y="{frame.top:.2f}" '
            f'width="{frame.right - frame.left:.2f}" height="{frame.bottom - frame.top:.2f}"/>'
            f"</clipPath></defs>", f'<rect width="100%" height="{height:g}" fill="#fff"/>'
            if height != HEIGHT else '<rect width="100%" height="100%" fill="#fff"/>']
    for span in chart.spans:
        x0, x1 = sorted((float(frame.x(span.start)), float(frame.x(span.stop))))
        x0, x1 = max(x0, frame.left), min(x1, frame.right)
        if math.isfinite(x0) and math.isfinite(x1) and x1 > x0:
            body.append(f'<rect x="{x0:.2f}" y="{frame.top:.2f}" width="{x1 - x0:.2f}" '
                        f'height="{frame.bottom - frame.top:.2f}" fill="{span.color}"/>')
    body += [*under, f'<g clip-path="url(#{clip})" fill="none">']
    for bar in chart.bars:
        zero = float(frame.y(0.0))
        for k, (x, h) in enumerate(zip(np.asarray(bar.x, float).tolist(),
                                       np.asarray(bar.heights, float).tolist())):
            x0, x1 = float(frame.x(x - bar.width / 2)), float(frame.x(x + bar.width / 2))
            y = float(frame.y(h))
            if all(math.isfinite(v) for v in (x0, x1, y, zero)):
                color = bar.colors[k % len(bar.colors)] if bar.colors else COLORS[0]
                body.append(f'<rect x="{x0:.2f}" y="{min(y, zero):.2f}" width="{x1 - x0:.2f}" '
                            f'height="{abs(zero - y):.2f}" fill="{color}" stroke="none"/>')
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
        path = _polyline(frame.x(curve.x), frame.y(curve.y))
        if path:
            body.append(f'<path d="{path}" stroke="{curve.color}" stroke-width="{curve.width:g}"'
                        f'{_dasharray(curve.dash, curve.width)}'
                        ' stroke-linejoin="round" stroke-linecap="round"/>')
    for m in chart.markers:
        x, y = float(frame.x(m.x)), float(frame.y(m.y))
        if math.isfinite(x) and math.isfinite(y):
            body.append(_marker_svg(m.shape, x, y, m.color, m.filled))
    body.append("</g>")
    body.append(f'<rect x="{frame.left:.2f}" y="{frame.top:.2f}" '
                f'width="{frame.right - frame.left:.2f}" height="{frame.bottom - frame.top:.2f}"'
                ' fill="none" stroke="#000" stroke-width="0.8"/>')
    body += over
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
    body += _legend(rows, frame)
    return body


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
    return (f"{plain_text(chart.ylabel)}{scale} against {plain_text(chart.xlabel)}: "
            + ", ".join(plain_text(c.label) for c in chart.curves))


def _legend(rows: list[list[tuple[_Key, float]]], frame: _Frame) -> list[str]:
    out = []
    for r, row in enumerate(rows):
        x = frame.right - sum(w for _, w in row) + 14.0
        y = 12.0 + 15.0 * r
        for key, width in row:
            if key.shape:
                out.append(_marker_svg(key.shape, x + 10.0, y - 3.5, key.color, key.filled))
            elif key.width > 4.0:  # a band
                out.append(f'<rect x="{x:.2f}" y="{y - 7.5:.2f}" width="20" height="8" '
                           f'fill="{key.color}"/>')
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
    "dot": {"marker": "o", "markersize": 5},
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


def _draw_panel(chart: Chart, ax: Axes, own: bool, legend_size: float | None = None) -> None:
    """Draw one chart on an Axes (the drawing behind :func:`draw_chart` and
    :func:`draw_figure`)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    for span in chart.spans:
        ax.axvspan(span.start, span.stop, color=span.color, zorder=0,
                   label=mathtext_label(span.label) if span.label else None)
    for bar in chart.bars:
        ax.bar(bar.x, bar.heights, width=bar.width, color=list(bar.colors) or None)
    for curve in chart.colored():
        y = np.where(np.asarray(curve.y) > 0, curve.y, np.nan) if chart.ylog else curve.y
        ax.plot(curve.x, y, label=mathtext_label(curve.label), color=curve.color,
                linewidth=curve.width, linestyle=_linestyle(curve.dash))
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
    ax.grid(True, which="major", color="0.9", axis="y" if chart.xticks is not None else "both")
    if chart.xlog or chart.ylog:
        ax.grid(True, which="minor", color="0.95", linewidth=0.5)
    keys = legend_keys(chart)[len([c for c in chart.curves if c.label]):]
    handles = [Patch(color=k.color, label=mathtext_label(k.label)) if k.width > 4.0 and
               not k.shape else
               Line2D([], [], ls="", color=k.color, label=mathtext_label(k.label),
                      **_marker_style(k.shape, k.color, k.filled)) if k.shape else
               Line2D([], [], color=k.color, linewidth=k.width, linestyle=_linestyle(k.dash),
                      label=mathtext_label(k.label)) for k in keys
               if not any(s.label == k.label for s in chart.spans)]
    if chart.legend != "none" and (chart.curves or handles):
        curve_handles, labels = ax.get_legend_handles_labels()
        options: dict[str, Any] = {"frameon": False}
        if legend_size is not None:
            options["fontsize"] = legend_size
        if chart.legend == "beside" and own:
            options.update(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                           frameon=True)
        else:
            options["loc"] = "best"
        ax.legend([*curve_handles, *handles], labels + [h.get_label() for h in handles],
                  **options)


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


def draw_figure(charts: Charts | Chart, ax: Axes | Sequence[Axes] | None = None) -> Any:
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
    for k, (panel, axis) in enumerate(zip(charts.panels, axes)):
        if below or (charts.legend == "below" and k > 0):
            panel = replace(panel, legend="none")
        _draw_panel(panel, axis, own, legend_size=8.0)
        if own and charts.sharex and charts.columns == 1 and k < len(charts.panels) - 1:
            axis.set_xlabel("")
    if below:
        handles, labels = axes[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside lower center", fontsize=9, ncols=3,
                   frameon=False)
    title = "\n".join(mathtext_label(t) for t in charts.title.split("\n"))
    if charts.title and not charts.panels[0].title:  # over the first panel (also ax=)
        axes[0].set_title(title, fontsize=10)
    elif own and charts.title:
        fig.suptitle(title, fontsize=11)
    return fig


__all__ = ["Annotation", "Bar", "Chart", "Charts", "Curve", "Marker", "Rule", "Span", "chart_svg",
           "charts_svg", "describe", "draw_chart", "draw_figure", "figure_of", "legend_keys",
           "mathtext_label", "panel_heights", "plain_text", "nice_ticks", "log_ticks",
           "tick_labels", "text_runs", "unicode_text", "unit_text", "text_width", "x_limits",
           "y_limits", "WIDTH", "HEIGHT", "COLORS", "MARKER_SHAPES", "LEGENDS"]
