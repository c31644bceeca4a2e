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
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

#: the report's figures: 7.0 x 3.6 in, in points (the size of its matplotlib figures)
WIDTH, HEIGHT = 504.0, 259.2
#: matplotlib's default colour cycle, so that both drawings of a chart agree
COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
          "#7f7f7f", "#bcbd22", "#17becf")
FONT = "DejaVu Sans, Helvetica, Arial, sans-serif"
TICK_FONT = 10.0
#: pixel coordinates are kept within this many chart sizes (a value of 1e300 stays finite)
_FAR = 1e4


@dataclass(frozen=True)
class Curve:
    """A line through the points (x, y); NaN breaks it (a left-out point)."""

    x: np.ndarray
    y: np.ndarray
    label: str
    color: str | None = None
    width: float = 1.4


@dataclass(frozen=True)
class Marker:
    """A dot at one point (the operating point on a curve)."""

    x: float
    y: float
    color: str


@dataclass(frozen=True)
class Rule:
    """A reference line across the axes: vertical at x = ``at`` or horizontal at y = ``at``."""

    at: float
    vertical: bool = True
    color: str = "#999999"
    dash: str | None = None
    width: float = 1.0


@dataclass(frozen=True)
class Chart:
    """What a line chart shows; drawn by :func:`chart_svg` or :func:`draw_chart`."""

    curves: tuple[Curve, ...]
    xlabel: str
    ylabel: str
    xlim: tuple[float, float]
    ylog: bool = False
    markers: tuple[Marker, ...] = ()
    rules: tuple[Rule, ...] = ()

    def colored(self) -> tuple[Curve, ...]:
        """The curves with the colour cycle filled in where a curve has none."""
        return tuple(c if c.color else Curve(c.x, c.y, c.label, COLORS[i % len(COLORS)],
                                             c.width)
                     for i, c in enumerate(self.curves))


# -- limits and ticks ----------------------------------------------------------------------

def _finite(values: np.ndarray, log: bool) -> np.ndarray:
    values = np.asarray(values, dtype=float).ravel()
    keep = np.isfinite(values) & ((values > 0) if log else True)
    return values[keep]


def y_limits(chart: Chart) -> tuple[float, float]:
    """The y range of the data with 5 % margins (in decades on a log axis)."""
    data = [_finite(c.y, chart.ylog) for c in chart.curves]
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

    def x(self, values: Any) -> np.ndarray:
        lo, hi = self.xlim
        span = hi - lo if hi > lo else 1.0
        pos = self.left + (np.asarray(values, dtype=float) - lo) / span * (self.right - self.left)
        return np.clip(pos, -_FAR * WIDTH, _FAR * WIDTH)

    def y(self, values: Any) -> np.ndarray:
        lo, hi = self.ylim
        with np.errstate(all="ignore"):
            v = np.asarray(values, dtype=float)
            if self.ylog:
                v, lo, hi = np.log10(np.where(v > 0, v, np.nan)), math.log10(lo), math.log10(hi)
            span = hi - lo if hi > lo else 1.0
            pos = self.bottom - (v - lo) / span * (self.bottom - self.top)
        return np.clip(pos, -_FAR * HEIGHT, _FAR * HEIGHT)


def _frame(chart: Chart, legend_rows: int, ylabels: list[str]) -> _Frame:
    widest = max((text_width(s, TICK_FONT) for s in ylabels), default=10.0)
    left = min(0.35 * WIDTH, 30.0 + widest)
    top = 8.0 + 15.0 * legend_rows
    low, high = float(chart.xlim[0]), float(chart.xlim[1])
    if not (math.isfinite(low) and math.isfinite(high) and high > low):
        low, high = 0.0, 1.0
    xlabels = tick_labels([t for t in nice_ticks(low, high) if low <= t <= high])[0]
    right = WIDTH - max(0.02 * WIDTH, 4.0 + text_width(xlabels[-1] if xlabels else "", TICK_FONT)
                        / 2)
    return _Frame(left, right, top, 0.86 * HEIGHT, (low, high), y_limits(chart), chart.ylog)


def _legend_rows(curves: tuple[Curve, ...], room: float) -> list[list[tuple[Curve, float]]]:
    rows: list[list[tuple[Curve, float]]] = [[]]
    used = 0.0
    for curve in curves:
        width = 26.0 + text_width(curve.label, TICK_FONT) + 14.0
        if rows[-1] and used + width > room:
            rows.append([])
            used = 0.0
        rows[-1].append((curve, width))
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


def _axes(frame: _Frame) -> tuple[list[str], list[str]]:
    """Grid lines (under the curves) and ticks with labels (over them)."""
    under, over = [], []
    tick = 'stroke="#000" stroke-width="0.8"'
    xticks = [t for t in nice_ticks(*frame.xlim) if frame.xlim[0] <= t <= frame.xlim[1]]
    xlabels, xpower = tick_labels(xticks)
    for t, label in zip(xticks, xlabels):
        x = float(frame.x(t))
        under.append(f'<line x1="{x:.2f}" y1="{frame.top:.2f}" x2="{x:.2f}" '
                     f'y2="{frame.bottom:.2f}" stroke="#e6e6e6" stroke-width="0.8"/>')
        over.append(f'<line x1="{x:.2f}" y1="{frame.bottom:.2f}" x2="{x:.2f}" '
                    f'y2="{frame.bottom + 3.5:.2f}" {tick}/>')
        over.append(_text(x, frame.bottom + 15.0, label, TICK_FONT))
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


def _y_ticks(frame: _Frame) -> list[tuple[float, str, bool]]:
    """(position, label, minor) of the y ticks."""
    if frame.ylog:
        majors, minors = log_ticks(*frame.ylim)
        return ([(float(frame.y(10.0 ** k)), f"$10^{{{k}}}$", False) for k in majors]
                + [(float(frame.y(m)), "", True) for m in minors])
    ticks = [t for t in nice_ticks(*frame.ylim, most=7) if frame.ylim[0] <= t <= frame.ylim[1]]
    labels, _ = tick_labels(ticks)
    return [(float(frame.y(t)), label, False) for t, label in zip(ticks, labels)]


def _y_power(frame: _Frame) -> int:
    """The power of ten the linear y tick labels are given in (0: none)."""
    if frame.ylog:
        return 0
    return tick_labels([t for t in nice_ticks(*frame.ylim, most=7)
                        if frame.ylim[0] <= t <= frame.ylim[1]])[1]


def _y_label_texts(chart: Chart) -> list[str]:
    frame = _Frame(0.0, 1.0, 0.0, 1.0, (0.0, 1.0), y_limits(chart), chart.ylog)
    return [label for _, label, minor in _y_ticks(frame) if not minor]


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
    curves = chart.colored()
    rows = _legend_rows(curves, 0.9 * WIDTH)
    frame = _frame(chart, len(rows), _y_label_texts(chart))
    ident = re.sub(r"[^A-Za-z0-9_-]", "-", ident)
    clip = f"{ident}-plot"
    under, over = _axes(frame)
    body = [f'<defs><clipPath id="{clip}"><rect x="{frame.left:.2f}" y="{frame.top:.2f}" '
            f'width="{frame.right - frame.left:.2f}" height="{frame.bottom - frame.top:.2f}"/>'
            f"</clipPath></defs>", '<rect width="100%" height="100%" fill="#fff"/>', *under,
            f'<g clip-path="url(#{clip})" fill="none">']
    for rule in chart.rules:
        dash = f' stroke-dasharray="{rule.dash}"' if rule.dash else ""
        if rule.vertical:
            x = float(frame.x(rule.at))
            coords = f'x1="{x:.2f}" y1="{frame.top:.2f}" x2="{x:.2f}" y2="{frame.bottom:.2f}"'
        else:
            y = float(frame.y(rule.at))
            coords = f'x1="{frame.left:.2f}" y1="{y:.2f}" x2="{frame.right:.2f}" y2="{y:.2f}"'
        body.append(f'<line {coords} stroke="{rule.color}" stroke-width="{rule.width:g}"{dash}/>')
    for curve in curves:
        path = _polyline(frame.x(curve.x), frame.y(curve.y))
        if path:
            body.append(f'<path d="{path}" stroke="{curve.color}" stroke-width="{curve.width:g}"'
                        ' stroke-linejoin="round" stroke-linecap="round"/>')
    for m in chart.markers:
        x, y = float(frame.x(m.x)), float(frame.y(m.y))
        if math.isfinite(x) and math.isfinite(y):
            body.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="2.5" fill="{m.color}"/>')
    body.append("</g>")
    body.append(f'<rect x="{frame.left:.2f}" y="{frame.top:.2f}" '
                f'width="{frame.right - frame.left:.2f}" height="{frame.bottom - frame.top:.2f}"'
                ' fill="none" stroke="#000" stroke-width="0.8"/>')
    body += over
    body.append(_text((frame.left + frame.right) / 2, HEIGHT - 8.0, chart.xlabel, TICK_FONT))
    body.append(_text(13.0, (frame.top + frame.bottom) / 2, chart.ylabel, TICK_FONT,
                      rotate=True))
    body += _legend(rows, frame)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH:g}pt" height="{HEIGHT:g}pt"'
            f' viewBox="0 0 {WIDTH:g} {HEIGHT:g}" version="1.1" role="img"'
            f' font-family="{FONT}"><title>{html.escape(describe(chart))}</title>'
            + "".join(body) + "</svg>")


def plain_text(label: str) -> str:
    """A label as plain text (its math set as characters: ``$x_{2}$`` -> ``x2``)."""
    return _NOT_XML.sub(" ", "".join(text for text, _, _ in text_runs(label)))


def describe(chart: Chart) -> str:
    """A one-line description of the chart for readers that cannot see it.

    Examples
    --------
    >>> describe(Chart((Curve(np.zeros(2), np.zeros(2), "$x_{1}$"),), "time $t$ [s]",
    ...                "response", (0.0, 1.0)))
    'response against time t [s]: x1'
    """
    scale = " (logarithmic)" if chart.ylog else ""
    return (f"{plain_text(chart.ylabel)}{scale} against {plain_text(chart.xlabel)}: "
            + ", ".join(plain_text(c.label) for c in chart.curves))


def _legend(rows: list[list[tuple[Curve, float]]], frame: _Frame) -> list[str]:
    out = []
    for r, row in enumerate(rows):
        x = frame.right - sum(w for _, w in row) + 14.0
        y = 12.0 + 15.0 * r
        for curve, width in row:
            out.append(f'<line x1="{x:.2f}" y1="{y - 3.5:.2f}" x2="{x + 20:.2f}" '
                       f'y2="{y - 3.5:.2f}" stroke="{curve.color}" '
                       f'stroke-width="{curve.width:g}"/>')
            out.append(_text(x + 26.0, y, curve.label, TICK_FONT, "start"))
            x += width
    return out


# -- matplotlib ------------------------------------------------------------------------------

def draw_chart(chart: Chart, figure: Any) -> Any:
    """Draw the chart on a matplotlib figure; return its axes.

    Parameters
    ----------
    chart : Chart
    figure : matplotlib.figure.Figure

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = figure.add_subplot(1, 1, 1)
    for curve in chart.colored():
        y = np.where(np.asarray(curve.y) > 0, curve.y, np.nan) if chart.ylog else curve.y
        ax.plot(curve.x, y, label=curve.label, color=curve.color, linewidth=curve.width)
    for m in chart.markers:
        ax.plot([m.x], [m.y], "o", color=m.color, markersize=5, zorder=3)
    for rule in chart.rules:
        style = {"color": rule.color, "linewidth": rule.width,
                 "linestyle": (0, tuple(float(v) for v in rule.dash.split()))
                 if rule.dash else "-"}
        (ax.axvline if rule.vertical else ax.axhline)(rule.at, **style)
    if chart.ylog:
        ax.set_yscale("log")
    ax.set_xlabel(chart.xlabel)
    ax.set_ylabel(chart.ylabel)
    ax.set_xlim(*chart.xlim)
    ax.grid(True, which="major", color="0.9")
    ax.legend(loc="best", frameon=False)
    return ax


__all__ = ["Chart", "Curve", "Marker", "Rule", "chart_svg", "describe", "draw_chart",
           "plain_text", "nice_ticks",
           "log_ticks", "tick_labels", "text_runs", "text_width", "y_limits", "WIDTH",
           "HEIGHT", "COLORS"]
