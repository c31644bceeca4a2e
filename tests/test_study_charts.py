"""The study's pictures are chart descriptions: histogram, scatter plots, Sobol indices and
the map of a grid are each built by one view function (``*_chart``) and drawn both by
matplotlib and as SVG text.

Each test draws a description both ways and reads back from each drawing what it shows --
bars, error bars, dots and crosses, reference lines, bands, the grid's cells and their
colours, labels, legend entries, axis scales -- and checks that the two agree with the
description and with each other.  The grid's colours are also checked against matplotlib's
own viridis map (a second route), and the description survives JSON.
"""

from __future__ import annotations

import json
import math
import re
from xml.etree import ElementTree

import numpy as np
import pandas as pd
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import QuadMesh
from matplotlib.colors import to_hex
from matplotlib.container import BarContainer, ErrorbarContainer

from resonant.charts import (
    Chart,
    Charts,
    Field,
    charts_svg,
    draw_figure,
    legend_keys,
    mathtext_label,
    plain_text,
    x_limits,
    y_limits,
)
from resonant.studies.study_charts import (
    contour_chart,
    histogram_chart,
    plot_contour,
    plot_histogram,
    plot_scatter,
    plot_sobol,
    plot_study,
    scatter_chart,
    sobol_chart,
    study_charts,
)

SVG = "{http://www.w3.org/2000/svg}"
UNITS = {"k2": "N/m", "c2": "N*s/m", "m": "kg", "peak:x1": "m", "peak_frequency:x1": "rad/s"}


def _grid() -> pd.DataFrame:
    """A 12 x 10 grid: a quantity over five decades, a jump, and 20 samples without a value
    (k2 <= 0; 6 resonant, 14 unstable)."""
    k, c = np.meshgrid(np.linspace(-100, 1000, 12), np.linspace(0.1, 10, 10))
    k, c = k.ravel(), c.ravel()
    peak = np.where(k > 0, 10.0 ** (-3 + 5 * c / 10), np.nan)
    jump = np.where(k > 400, 20.0, 12.0)
    status = np.where(k > 0, "ok", np.where(c < 3, "resonance", "unstable"))
    return pd.DataFrame({"k2": k, "c2": c, "peak:x1": peak,
                         "peak_frequency:x1": np.where(k > 0, jump, np.nan), "status": status})


def _monte_carlo() -> pd.DataFrame:
    """400 random samples of three parameters, every 37th without a value."""
    rng = np.random.default_rng(7)
    frame = pd.DataFrame({"k2": rng.normal(100, 10, 400), "c2": rng.uniform(1, 2, 400),
                          "m": rng.uniform(0.5, 1, 400)})
    frame["peak:x1"] = 0.01 * frame.k2 / frame.c2 + rng.normal(0, 0.05, 400)
    frame.loc[::37, "peak:x1"] = np.nan
    frame["status"] = np.where(np.isfinite(frame["peak:x1"]), "ok", "unstable")
    return frame


SOBOL = {"parameters": ["k2", "c2", "m"], "S1": [0.6, -0.04, None], "S1_conf": [0.05, 0.04, None],
         "ST": [0.7, 0.3, 0.02], "ST_conf": [0.06, 0.05, 0.01], "note": "512 samples"}


def _levels_chart() -> Charts:
    """A field in bands of one colour each (levels), not from a study."""
    x, y = np.linspace(0.0, 4.0, 9), np.linspace(0.0, 2.0, 5)
    z = np.add.outer(np.arange(4.0), np.arange(8.0))
    z[1, 2] = math.nan
    field = Field(x, y, z, "sum of the indices", levels=(0.0, 2.5, 5.0, 7.5, 10.0),
                  missing="no value")
    return Charts((Chart((), "$x$", "$y$", (0.0, 4.0), ylim=(0.0, 2.0), fields=(field,)),))


@pytest.fixture(scope="module")
def descriptions() -> dict[str, Charts]:
    grid, mc = _grid(), _monte_carlo()
    return {
        "histogram (log)": histogram_chart(grid, "peak:x1", UNITS),
        "histogram": histogram_chart(mc, "peak:x1", UNITS),
        "scatter": scatter_chart(mc, "peak:x1", ["k2", "c2", "m"], UNITS,
                                 {"k2": 100.0, "c2": 1.5, "m": 0.75}),
        "scatter (log)": scatter_chart(grid, "peak:x1", ["k2", "c2"], UNITS,
                                       {"k2": 500.0, "c2": 5.0}),
        "sobol": sobol_chart(SOBOL, "peak:x1", UNITS),
        "contour (log)": contour_chart(grid, "peak:x1", "k2", "c2", UNITS,
                                       {"k2": 500.0, "c2": 5.0}),
        "contour (jump)": contour_chart(grid, "peak_frequency:x1", "k2", "c2", UNITS),
        "levels": _levels_chart(),
    }


KINDS = ["histogram (log)", "histogram", "scatter", "scatter (log)", "sobol", "contour (log)",
         "contour (jump)", "levels"]


def _svg_panels(svg: str) -> list[ElementTree.Element]:
    root = ElementTree.fromstring(svg)
    return [g for g in root if g.tag == f"{SVG}g" and g.get("transform", "").startswith(
        "translate")]


def _plot_area(group: ElementTree.Element) -> ElementTree.Element:
    return next(g for g in group.iter(f"{SVG}g") if g.get("clip-path"))


def _finite_count(values: np.ndarray) -> int:
    return int(np.isfinite(np.asarray(values, dtype=float)).sum())


def _legend_texts(fig, ax) -> list[str]:
    legends = [ax.get_legend()] if ax.get_legend() is not None else list(fig.legends)
    return [t.get_text() for legend in legends for t in legend.get_texts()]


@pytest.mark.parametrize("kind", KINDS)
def test_matplotlib_and_svg_draw_one_description(descriptions, kind) -> None:
    charts = descriptions[kind]
    fig = draw_figure(charts)
    FigureCanvasAgg(fig).draw()
    panels = _svg_panels(charts_svg(charts, "study"))
    assert len(panels) == len(charts.panels) >= 1
    # the panels first; a colour bar is an Axes of its own, after them
    axes = fig.axes[:len(charts.panels)]
    assert len(fig.axes) == len(charts.panels) + sum(
        1 for p in charts.panels for f in p.fields if f.label)
    legend_labels: dict[str, None] = {}
    for chart, ax, group in zip(charts.panels, axes, panels):
        area = _plot_area(group)
        texts = ["".join(t.itertext()) for t in group.iter(f"{SVG}text")]
        # labels, scales and ranges
        assert ax.get_xlabel() == mathtext_label(chart.xlabel)
        assert ax.get_ylabel() == mathtext_label(chart.ylabel)
        assert plain_text(chart.xlabel) in texts and plain_text(chart.ylabel) in texts
        assert ax.get_title() == mathtext_label(chart.title)
        assert not chart.title or plain_text(chart.title) in texts
        assert ax.get_xscale() == ("log" if chart.xlog else "linear")
        assert ax.get_yscale() == ("log" if chart.ylog else "linear")
        np.testing.assert_allclose(ax.get_xlim(), x_limits(chart), rtol=1e-12)
        if chart.ylim is not None:
            np.testing.assert_allclose(ax.get_ylim(), y_limits(chart), rtol=1e-12)
        # bars: matplotlib's rectangles and the SVG's, as many, in the bars' colours
        colours = {c for b in chart.bars for c in b.colors}
        svg_bars = [e for e in area if e.tag == f"{SVG}rect" and e.get("fill") in colours]
        mpl_bars = [p for c in ax.containers if isinstance(c, BarContainer) for p in c
                    if np.isfinite(p.get_height())]
        assert len(svg_bars) == len(mpl_bars) == sum(_finite_count(b.heights)
                                                      for b in chart.bars)
        assert [to_hex(p.get_facecolor()) for p in mpl_bars] == [e.get("fill") for e in svg_bars]
        # error bars: a stem and two caps each in the SVG, a segment each in matplotlib
        errors = sum(_finite_count(np.asarray(b.heights) + b.errors) for b in chart.bars
                     if b.errors is not None)
        stems = sum(int(len(segment) > 0 and np.isfinite(segment).all())
                    for c in ax.containers if isinstance(c, ErrorbarContainer)
                    for segment in c.lines[2][0].get_segments())
        lines = [e for e in area if e.tag == f"{SVG}line"]
        assert stems == errors and len(lines) == 3 * errors + len(chart.rules)
        # reference lines (mean, quantiles, nominal design, zero): one drawn line each
        rules = [ln for ln in ax.get_lines() if len(ln.get_xdata()) == 2
                 and ln.get_linestyle() != "None"]
        assert len(rules) == len(chart.rules)
        # dots and crosses: one matplotlib line and one SVG path per curve, a mark per point
        paths = [e for e in area if e.tag == f"{SVG}path"]
        assert len(paths) == len([c for c in chart.curves if len(c.x)])
        for curve, path in zip([c for c in chart.curves if len(c.x)], paths):
            line = next(ln for ln in ax.get_lines() if len(ln.get_xdata()) == len(curve.x)
                        and np.array_equal(ln.get_xdata(), curve.x))
            assert line.get_linestyle() == "None" and not curve.line
            assert line.get_marker() == ("x" if curve.marker == "cross" else ".")
            assert to_hex(line.get_color()) == path.get("stroke") == curve.color
            assert path.get("d", "").count("M") == len(curve.x)
        # markers (the nominal design's star): one point each
        points = [ln for ln in ax.get_lines() if len(ln.get_xdata()) == 1]
        shapes = [e for e in area if e.tag == f"{SVG}polygon"]
        assert len(points) == len(shapes) == len(chart.markers)
        # bands (the samples without a value): hatched both ways
        hatched = [p for p in ax.patches if p.get_hatch()]
        svg_bands = [e for e in group if e.tag == f"{SVG}rect"
                     and "-hatch-" in e.get("fill", "") and not e.get("stroke")]
        assert len(hatched) == len(svg_bands) == len([s for s in chart.spans if s.hatch])
        # fields: a QuadMesh and a colour bar; the same cells in the same colours
        meshes = [c for c in ax.collections if isinstance(c, QuadMesh)]
        assert len(meshes) == len(chart.fields)
        for field, mesh in zip(chart.fields, meshes):
            cells = [e for g in area if g.tag == f"{SVG}g" for e in g
                     if e.get("fill", "").startswith("#")]
            drawn = np.ma.masked_invalid(mesh.get_array())
            expected = [c for row in field.colors() for c in row if c is not None]
            assert len(cells) == drawn.count() == len(expected)
            mpl_colours = [to_hex(c) for c, bad in zip(mesh.to_rgba(drawn.ravel()),
                                                       np.ma.getmaskarray(drawn).ravel())
                           if not bad]
            assert mpl_colours == [e.get("fill") for e in cells] == expected
            assert any(plain_text(field.label) == t for t in texts)
            colorbar = fig.axes[len(charts.panels)]
            assert colorbar.get_ylabel() == mathtext_label(field.label)
            if field.missing:
                assert [c for c in ax.collections if c.get_hatch()]
                assert any(e.get("fill", "").startswith("url(#") for g in area
                           if g.tag == f"{SVG}g" for e in g)
        # the legend: the description's entries, in its order, both ways
        keys = [k.label for k in legend_keys(chart)]
        assert all(plain_text(k) in texts for k in keys)
        for k in keys:
            legend_labels.setdefault(mathtext_label(k), None)
        if len(charts.panels) == 1:
            assert _legend_texts(fig, ax) == [mathtext_label(k) for k in keys]
    assert _legend_texts(fig, axes[0]) == list(legend_labels)


@pytest.mark.parametrize("kind", KINDS)
def test_the_description_is_json(descriptions, kind) -> None:
    charts = descriptions[kind]
    data = json.loads(json.dumps(charts.to_dict(), allow_nan=False))
    for chart, panel in zip(charts.panels, data["panels"]):
        assert [b["label"] for b in panel["bars"]] == [b.label for b in chart.bars]
        assert [c["marker"] for c in panel["curves"]] == [c.marker for c in chart.curves]
        assert [s["hatch"] for s in panel["spans"]] == [s.hatch for s in chart.spans]
        for field, stored in zip(chart.fields, panel["fields"], strict=True):
            back = Field.from_dict(stored)
            z, z_back = np.asarray(field.z, dtype=float), back.z
            np.testing.assert_array_equal(np.isnan(z_back), np.isnan(z))
            np.testing.assert_array_equal(z_back[np.isfinite(z)], z[np.isfinite(z)])
            np.testing.assert_array_equal(back.x, field.x)
            np.testing.assert_array_equal(back.y, field.y)
            assert (back.label, back.log, back.levels, back.limits, back.missing) == \
                (field.label, field.log, field.levels, field.limits, field.missing)
            assert back.colors() == field.colors() == stored["colors"]


def test_the_field_s_colours_are_matplotlib_s_viridis() -> None:
    """Two routes: the field's colour table (33 points of viridis, interpolated) against
    matplotlib's own viridis map at every one of 200 values, within 3/255 a channel (the
    interpolation's error, 2.8/255 at most over the whole map, and the rounding to a hex
    colour, 0.5/255)."""
    from matplotlib import colormaps
    from matplotlib.colors import Normalize

    values = np.linspace(-3.0, 5.0, 200)
    field = Field(np.arange(201.0), np.array([0.0, 1.0]), values[None, :], "z")
    ours = np.array([[int(c[k:k + 2], 16) for k in (1, 3, 5)] for c in field.colors()[0]])
    theirs = colormaps["viridis"](Normalize(-3.0, 5.0)(values))[:, :3] * 255
    assert np.max(np.abs(ours - theirs)) <= 3.3
    # on a log scale the colour follows log10 of the value
    log = Field(np.arange(4.0), np.array([0.0, 1.0]), np.array([[1e-3, 1e-1, 10.0]]), "z",
                log=True)
    assert log.steps(log.values()).tolist() == [[0, 128, 255]]


def test_a_field_without_positive_values_on_a_log_scale_draws_nothing() -> None:
    field = Field(np.arange(3.0), np.array([0.0, 1.0]), np.array([[-1.0, 0.0]]), "z", log=True,
                  missing="no value")
    assert field.colors() == [[None, None]]
    charts = Charts((Chart((), "x", "y", (0.0, 2.0), fields=(field,)),))
    draw_figure(charts)
    ElementTree.fromstring(charts_svg(charts, "empty"))


def test_the_svg_places_the_samples_on_the_axes() -> None:
    """Two routes: the SVG dots, mapped back through the linear axes, are the samples."""
    charts = scatter_chart(_monte_carlo(), "peak:x1", ["k2"], UNITS)
    chart = charts.panels[0]
    path = next(e for e in _plot_area(_svg_panels(charts_svg(charts, "s"))[0])
                if e.tag == f"{SVG}path")
    points = np.array([[float(a), float(b)] for a, b in
                       re.findall(r"M(-?[0-9.]+) (-?[0-9.]+)h0", path.get("d", ""))])
    curve = chart.curves[0]
    for data, drawn, sign in ((curve.x, points[:, 0], 1), (curve.y, points[:, 1], -1)):
        fit = np.polyfit(data, drawn, 1)
        assert sign * fit[0] > 0
        assert np.max(np.abs(np.polyval(fit, data) - drawn)) < 0.01  # 2 decimals in the SVG


HOSTILE = "<script>alert('&')</script>"


def test_hostile_names_are_escaped_in_the_svg_and_drawn_by_matplotlib() -> None:
    """A column, a parameter, a status and a note that are markup: the SVG stays well-formed
    XML with the text escaped, matplotlib draws them as text."""
    k, c = np.meshgrid(np.linspace(1.0, 2.0, 4), np.linspace(1.0, 2.0, 3))
    frame = pd.DataFrame({HOSTILE: k.ravel(), "a & b": c.ravel(),
                          "q<&>": np.where(k.ravel() > 1.5, k.ravel() * c.ravel(), np.nan),
                          "status": np.where(k.ravel() > 1.5, "ok", "<b>&amp;</b>")})
    sobol = {"parameters": [HOSTILE, "a & b"], "S1": [0.5, 0.2], "S1_conf": [0.1, 0.1],
             "ST": [0.6, 0.3], "ST_conf": [0.1, 0.1], "note": "</svg><script>"}
    charts = [histogram_chart(frame, "q<&>"), scatter_chart(frame, "q<&>", [HOSTILE, "a & b"],
                                                            nominal={HOSTILE: 1.5}),
              sobol_chart(sobol, "q<&>"),
              contour_chart(frame, "q<&>", HOSTILE, "a & b", nominal={HOSTILE: 1.5,
                                                                       "a & b": 1.5})]
    for chart in charts:
        svg = charts_svg(chart, "h")
        root = ElementTree.fromstring(svg)  # well-formed: nothing broke out of its text
        assert "<script" not in svg and "<b>" not in svg
        assert "&lt;script&gt;" in svg or "&lt;&amp;&gt;" in svg
        assert not [e for e in root.iter() if e.tag in (f"{SVG}script", "script")]
        FigureCanvasAgg(draw_figure(chart)).draw()  # no mathtext error
    texts = "".join(ElementTree.fromstring(charts_svg(charts[3], "h")).itertext())
    assert "no value: 6 <b>&amp;</b>" in texts and "q<&>" in texts


def test_the_plot_functions_draw_the_charts(tmp_path) -> None:
    """plot_* draw what *_chart describe (also into the caller's axes); plot_study writes
    one file per chart of study_charts."""
    from matplotlib.figure import Figure

    grid = _grid()
    fig = plot_histogram(grid, "peak:x1", units=UNITS, path=tmp_path / "h.svg")
    chart = histogram_chart(grid, "peak:x1", UNITS).panels[0]
    assert sum(len(c) for c in fig.axes[0].containers) == len(chart.bars[0].heights)
    assert (tmp_path / "h.svg").stat().st_size > 0
    own = Figure()
    ax = own.add_subplot()
    assert plot_scatter(grid, "peak:x1", ["k2"], ax=ax, units=UNITS) is own
    assert [t.get_text() for t in ax.get_legend().get_texts()] == \
        ["sample", "no value: 6 resonance, 14 unstable"]
    own = Figure()
    assert plot_sobol(SOBOL, "peak:x1", ax=own.add_subplot()) is own
    own = Figure()
    assert plot_contour(grid, "peak:x1", "k2", "c2", ax=own.add_subplot()) is own
    assert len(own.axes) == 2  # the cells' axes and the colour bar
    charts = study_charts(grid, ["k2", "c2"], ["peak:x1"], {"peak:x1": SOBOL}, grid=True,
                          units=UNITS)
    assert [kind for _, kind, _ in charts] == ["histogram", "scatter", "sobol", "contour"]
    written = plot_study(grid, ["k2", "c2"], ["peak:x1"], tmp_path / "plots",
                         {"peak:x1": SOBOL}, grid=True, units=UNITS)
    assert [p.name for p in written] == [f"{kind}-peak_x1.png" for _, kind, _ in charts]
    assert all(p.stat().st_size > 1000 for p in written)


@pytest.mark.parametrize("kind", ["histogram (log)", "contour (log)"])
def test_a_legend_below_covers_nothing_and_stays_in_the_figure(descriptions, kind) -> None:
    """Rendered extents: the legend under the axes lies below the x label and the tick
    labels, and inside the figure (constrained layout makes room for it)."""
    fig = draw_figure(descriptions[kind])
    FigureCanvasAgg(fig).draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent(renderer)
    label = ax.xaxis.label.get_window_extent(renderer)
    ticks = [t.get_window_extent(renderer) for t in ax.get_xticklabels() if t.get_text()]
    assert legend.y1 <= label.y0 + 0.5 and all(legend.y1 <= t.y0 for t in ticks)
    assert legend.y0 >= 0 and legend.x0 >= 0 and legend.x1 <= fig.bbox.width
