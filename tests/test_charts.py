"""Charts written as SVG directly (resonant.charts) and their matplotlib drawing.

The HTML report and the exercise solutions draw frequency responses and time histories
as SVG text (docs/performance.md, "Parameter studies": 100 exercise variants with their
figures); these tests check the ticks, the text, hostile values and that the drawn path
is the data.
"""

from __future__ import annotations

import math
import re
from xml.etree import ElementTree

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from resonant.api import load
from resonant.charts import (
    FIGURE_DPI,
    HEIGHT,
    WIDTH,
    Chart,
    Charts,
    Curve,
    Marker,
    Rule,
    chart_svg,
    draw_chart,
    draw_figure,
    log_ticks,
    nice_ticks,
    save_figure,
    text_runs,
    tick_labels,
)
from resonant.report import plots

SVG = "{http://www.w3.org/2000/svg}"
finite = st.floats(-1e12, 1e12, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(finite, st.floats(1e-9, 1e12), st.integers(3, 10))
def test_nice_ticks_are_round_evenly_spaced_and_inside(low, span, most):
    high = low + span
    if not span > 1e-4 * max(1.0, abs(low)):
        return  # beyond what the floats can space evenly (the ticks would coincide)
    ticks = nice_ticks(low, high, most)
    assert 1 <= len(ticks) <= most
    step = (high - low) / max(most - 1, 1)
    assert all(low - 1e-6 * span <= t <= high + 1e-6 * span for t in ticks)
    if len(ticks) > 1:
        gaps = np.diff(ticks)
        assert np.allclose(gaps, gaps[0], rtol=1e-6, atol=1e-9 * span)
        mantissa = gaps[0] / 10.0 ** math.floor(math.log10(gaps[0]))
        assert any(math.isclose(mantissa, m, rel_tol=1e-6) for m in (1, 2, 2.5, 5, 10))
        assert gaps[0] >= step * (1 - 1e-9)  # never more ticks than asked for


def test_tick_labels_reference_values():
    assert tick_labels([-0.04, -0.02, 0.0, 0.02, 0.04]) == (
        ["\u22120.04", "\u22120.02", "0.00", "0.02", "0.04"], 0)
    assert tick_labels([0.0, 2.5, 5.0]) == (["0.0", "2.5", "5.0"], 0)
    assert tick_labels([1e5, 2e5]) == (["1", "2"], 5)
    assert tick_labels([0.0, 1e-6, 2e-6]) == (["0", "1", "2"], -6)


def test_log_ticks_label_decades_inside_the_range():
    majors, minors = log_ticks(3e-4, 2e2)
    assert majors == [-3, -2, -1, 0, 1, 2]
    assert all(3e-4 <= m <= 2e2 for m in minors) and 2e-3 in [round(m, 12) for m in minors]
    majors, minors = log_ticks(1e-300, 1e300)
    assert len(majors) <= 8 and not minors


def test_label_text_runs():
    assert text_runs(r"$x_{2}$ [m]") == [("x", 0, True), ("2", -1, False), (" [m]", 0, False)]
    assert text_runs(r"$\varphi$") == [("\u03c6", 0, True)]
    assert text_runs(r"$\dot{x}_{1}$")[0] == ("x\u0307", 0, True)
    assert text_runs(r"$\theta_{\mathrm{dot}}$") == [("\u03b8", 0, True), ("dot", -1, False)]


hostile = st.floats(allow_nan=True, allow_infinity=True)


@settings(max_examples=100, deadline=None)
@given(st.lists(hostile, min_size=0, max_size=30), st.booleans(), st.text(max_size=20))
def test_any_values_give_a_wellformed_bounded_svg(values, ylog, label):
    y = np.array(values, dtype=float)
    x = np.arange(y.size, dtype=float)
    chart = Chart((Curve(x, y, label + "$x_{1}$"),), label, "y <&>", (0.0, max(y.size, 1.0)),
                  ylog=ylog, markers=(Marker(1.0, 1e300, "#000"),),
                  rules=(Rule(1e300), Rule(-1e300, vertical=False)))
    svg = chart_svg(chart, 'id"><script>')
    root = ElementTree.fromstring(svg)  # well-formed: every string escaped
    assert root.tag == f"{SVG}svg" and "<script" not in svg
    assert root.find(f"{SVG}title").text  # an accessible name (role="img")
    numbers = [float(v) for v in re.findall(r' (?:x|y|x1|x2|y1|y2|cx|cy)="([-0-9.e]+)"', svg)]
    for path in root.iter(f"{SVG}path"):
        numbers += [float(v) for v in re.findall(r"-?[0-9.]+", path.get("d"))]
    assert all(math.isfinite(v) and abs(v) <= 1e4 * max(WIDTH, HEIGHT) for v in numbers)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1e6, 1e6), min_size=2, max_size=40), st.floats(0.1, 1e4))
def test_the_drawn_path_is_the_data(values, xmax):
    """Two routes: the points of the SVG path, mapped back through the axes, are the data
    (to the 0.01 pt the path and the frame are written with)."""
    y = np.array(values)
    x = np.linspace(0.0, xmax, y.size)
    svg = chart_svg(Chart((Curve(x, y, "q"),), "t", "q", (0.0, xmax)), "f")
    root = ElementTree.fromstring(svg)
    path = next(p for p in root.iter(f"{SVG}path"))
    points = np.array([[float(a), float(b)] for a, b in
                       re.findall(r"[ML](-?[0-9.]+) (-?[0-9.]+)", path.get("d"))])
    clip = next(r for r in root.iter(f"{SVG}rect") if r.get("width") != "100%")
    left, top = float(clip.get("x")), float(clip.get("y"))
    width, height = float(clip.get("width")), float(clip.get("height"))
    assert np.allclose(points[:, 0], left + x / xmax * width, atol=0.011)
    # the y axis spans the data with 5 % margins
    low, high = y.min(), y.max()
    # (a spread below 1e-300, subnormal numbers, is drawn as a flat line: no margins)
    if high - low > 1e-9 * max(abs(low), abs(high), 1e-300):
        low, high = low - 0.05 * (high - low), high + 0.05 * (high - low)
        back = low + (top + height - points[:, 1]) / height * (high - low)
        assert np.allclose(back, y, atol=0.02 / height * (high - low))


@pytest.fixture(scope="module")
def reference():
    eom = load("examples/cart_pendulum.toml").linearize()
    solution = eom.stationary()
    units = {"x1": "m", "x2": "m", "phi": "rad"}
    frf = plots.frequency_response(eom, solution)
    return (plots.response_chart(frf, plots.operating_frequency(solution), units),
            plots.history_figure(plots.time_history(solution)))


def test_report_figures_are_written_without_matplotlib(reference, monkeypatch):
    def refuse(plot):
        raise AssertionError("matplotlib drew an HTML figure")

    monkeypatch.setattr(plots, "_figure", refuse)
    frf, history = reference
    for number, plot in enumerate(reference, 1):
        svg = plots.to_svg(plot, number)
        root = ElementTree.fromstring(svg)
        assert root.get("viewBox") == f"0 0 {WIDTH:g} {HEIGHT:g}"
        assert f"resonant-figure-{number}-plot" in svg
    svg = plots.to_svg(frf, 1)
    title = ElementTree.fromstring(svg).find(f"{SVG}title").text
    assert title == ("amplitude X [m, rad] (logarithmic) against excitation frequency "
                     "\u03c9 [rad/s]: "
                     "x1 [m], x2 [m], \u03c6 (output) [rad]")
    # three curves (x1, x2 and the output phi), their operating points, the natural
    # frequencies (two in the range) and the excitation frequency
    assert svg.count("<path") == 3 and svg.count("<circle") == 3
    natural = [r for r in frf.rules if r.dash == "1 1.65"]
    assert len(natural) == 2 and svg.count('stroke-dasharray="1 1.65"') == 2 + 1  # + legend
    assert [r.dash for r in frf.rules if r not in natural] == ["3.7 1.6"]


def test_both_drawings_show_the_same_chart(reference):
    """The matplotlib figure (files, users' figures) draws the same curves, markers and
    reference lines as the SVG written directly."""
    from matplotlib.figure import Figure

    for chart in reference:
        ax = draw_chart(chart, Figure())
        lines = ax.get_lines()
        curves = [ln for ln in lines if ln.get_label() in {c.label for c in chart.curves}]
        assert len(curves) == len(chart.curves)
        for line, curve in zip(curves, chart.colored()):
            assert line.get_color() == curve.color
            np.testing.assert_array_equal(line.get_xdata(), curve.x)
        assert len(lines) == len(chart.curves) + len(chart.markers) + len(chart.rules)
        assert (ax.get_yscale() == "log") == chart.ylog


def _two_panels() -> Charts:
    curve = Curve(np.linspace(1.0, 10.0, 50), np.linspace(1.0, 10.0, 50) ** 2, "$x_{1}$")
    chart = Chart((curve,), "excitation frequency $\\omega$ [rad/s]", "amplitude $X$ [m]",
                  (1.0, 10.0), ylog=True)
    return Charts((chart, chart), title="two panels")


def test_a_laid_out_png_is_matplotlib_s_picture_drawn_once(tmp_path, monkeypatch):
    """save_figure runs the constrained layout itself and prints with it fixed
    (docs/performance.md, "Figures"): the PNG is, pixel for pixel, the one matplotlib's
    savefig writes, the figure is drawn once instead of twice, and it keeps its layout
    engine and dpi; "tight" does not pad a figure its layout engine already fits."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from PIL import Image

    reference = draw_figure(_two_panels())
    FigureCanvasAgg(reference)
    reference.savefig(tmp_path / "reference.png", dpi=FIGURE_DPI)
    fig = draw_figure(_two_panels())
    engine, dpi = fig.get_layout_engine(), fig.dpi
    draws = []
    original = Figure.draw
    monkeypatch.setattr(Figure, "draw", lambda self, r: (draws.append(r), original(self, r)))
    save_figure(fig, tmp_path / "saved.png", bbox_inches="tight")
    assert len(draws) == 1
    assert fig.get_layout_engine() is engine and fig.dpi == dpi
    saved = np.asarray(Image.open(tmp_path / "saved.png").convert("RGB"))
    expected = np.asarray(Image.open(tmp_path / "reference.png").convert("RGB"))
    assert saved.shape == expected.shape == (round(fig.get_figheight() * FIGURE_DPI),
                                             round(fig.get_figwidth() * FIGURE_DPI), 3)
    assert np.array_equal(saved, expected)
