"""One chart description per output: the matplotlib figure, the SVG text and the page's JSON
all come from it.

For every kind of result (a frequency response, a simulation, a random response, a shock
response spectrum, the report's figures) the view builds a :class:`Charts` description;
these tests draw it both ways and read back from each drawing what it shows (curves,
labels, axis scales, where the points land), and check that the description survives
JSON (no NaN, no arrays) with the same content.
"""

from __future__ import annotations

import json
import math
import re
from xml.etree import ElementTree

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

import resonant
import resonant.charts
from conftest import EXAMPLES
from resonant.analyses.backbone import backbone, backbones_chart
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.analyses.modes import modes_chart
from resonant.analyses.nonlinear_response import nonlinear_response_chart
from resonant.analyses.random_response import plot_random, random_chart, random_response
from resonant.analyses.shock import plot_srs, pulse, shock_response_spectrum, srs_chart
from resonant.analyses.simulate import simulate, simulation_chart
from resonant.analyses.sweep import frequency_response_chart, plot_frequency_response
from resonant.charts import (
    Chart,
    Charts,
    Curve,
    charts_svg,
    draw_figure,
    mathtext_label,
    plain_text,
)
from resonant.model.units_display import result_units
from resonant.report import plots
from resonant.system import nonlinear_system

SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def descriptions() -> dict[str, Charts]:
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    eom = model.linearize()
    units = result_units(model)
    si = units.si if units is not None else {}
    sweep = eom.sweep("omega", np.linspace(0.5, 30.0, 300))
    shaker = resonant.load(EXAMPLES / "shaker_gevs.toml").linearize()
    t, a = pulse("half-sine", 100.0, 0.011, 1e-5)
    srs = shock_response_spectrum(a, 1e-5, np.geomspace(10.0, 2000.0, 25))
    duffing = resonant.load(EXAMPLES / "duffing.toml")
    solution = eom.stationary()
    frf = plots.frequency_response(eom, solution)
    assert frf is not None
    history = plots.time_history(solution)
    assert history is not None
    return {
        "frequency response": frequency_response_chart(sweep, units=si),
        "simulation": simulation_chart(simulate(eom, 2.0), si),
        "random": random_chart(random_response(shaker)),
        "srs": srs_chart(srs, t, a, "m/s^2", reference=srs),
        "report response": Charts((plots.response_chart(
            frf, plots.operating_frequency(solution), si),)),
        "report history": Charts((plots.history_figure(history),)),
        "nonlinear": Charts((nonlinear_response_chart(
            nonlinear_sweep(nonlinear_system(duffing), "omega", 0.5, 2.5, harmonics=3, points=41),
            operating=(1.0, {"x": 0.8})),)),
        "backbones": Charts((backbones_chart(backbone(nonlinear_system(duffing), amplitude=2.0,
                                                      harmonics=1, points=20)),)),
        "modes": modes_chart(eom.modes(), count=2),
    }


KINDS = ["frequency response", "simulation", "random", "srs", "report response",
         "report history", "nonlinear", "backbones", "modes"]


def _svg_panels(svg: str) -> list[ElementTree.Element]:
    root = ElementTree.fromstring(svg)
    return [g for g in root if g.tag == f"{SVG}g" and g.get("transform", "").startswith(
        "translate")]


def _path_points(path: ElementTree.Element) -> np.ndarray:
    return np.array([[float(a), float(b)] for a, b in
                     re.findall(r"[ML](-?[0-9.]+) (-?[0-9.]+)", path.get("d", ""))])


@pytest.mark.parametrize("kind", KINDS)
def test_matplotlib_and_svg_draw_the_same_description(descriptions, kind) -> None:
    charts = descriptions[kind]
    fig = draw_figure(charts)
    svg = charts_svg(charts, "t")
    panels = _svg_panels(svg)
    assert len(fig.axes) == len(panels) == len(charts.panels) >= 1
    for chart, ax, group in zip(charts.panels, fig.axes, panels):
        # the curves: one matplotlib line and one SVG path each, with the chart's labels
        labels = [mathtext_label(c.label) for c in chart.curves]
        drawn = [line for line in ax.get_lines() if line.get_label() in labels
                 or (line.get_label().startswith("_") and len(line.get_xdata()) > 2)]
        assert len(drawn) == len(chart.curves)
        paths = [p for p in group.iter(f"{SVG}path")]
        with_points = [c for c in chart.colored()
                       if np.any(np.isfinite(c.x) & np.isfinite(c.y)
                                 & ((np.asarray(c.y) > 0) if chart.ylog else True))]
        assert len(paths) == len(with_points)
        for line, curve in zip(drawn, chart.colored()):
            assert line.get_color() == curve.color
        for path, curve in zip(paths, with_points):
            assert path.get("stroke") == curve.color
        # the axes' scales
        assert ax.get_xscale() == ("log" if chart.xlog else "linear")
        assert ax.get_yscale() == ("log" if chart.ylog else "linear")
        # the labels: matplotlib's as the chart's (the x label of a shared axis on the
        # last panel only), the SVG's texts as their plain text
        assert ax.get_ylabel() == mathtext_label(chart.ylabel)
        texts = ["".join(t.itertext()) for t in group.iter(f"{SVG}text")]
        assert plain_text(chart.ylabel) in texts and plain_text(chart.xlabel) in texts
        if chart.legend != "none":
            for curve in chart.curves:
                assert not curve.label or plain_text(curve.label) in texts
        if chart.title:
            assert ax.get_title() == mathtext_label(chart.title)
        # the markers: one matplotlib line of one point each, one SVG shape each (in the
        # clipped plot area, where the curves are)
        points = [ln for ln in ax.get_lines() if len(ln.get_xdata()) == 1]
        assert len(points) == len(chart.markers)
        plot_area = next(g for g in group.iter(f"{SVG}g") if g.get("clip-path"))
        shapes = [e for e in plot_area if e.tag in (f"{SVG}circle", f"{SVG}polygon",
                                                    f"{SVG}rect") and e.get("stroke") != "none"]
        assert len(shapes) == len(chart.markers)
        # the bars: matplotlib's rectangles and the SVG's, of the bars' colours
        bars = [e for e in plot_area if e.tag == f"{SVG}rect" and e.get("stroke") == "none"]
        heights = [h for b in chart.bars for h in np.asarray(b.heights)]
        assert sum(len(c) for c in ax.containers) == len(bars) == len(heights)
        assert [e.get("fill") for e in bars] == [c for b in chart.bars for c in b.colors]
    assert fig.axes[len(charts.panels) - 1].get_xlabel() == mathtext_label(
        charts.panels[-1].xlabel)


@pytest.mark.parametrize("kind", KINDS)
def test_the_svg_places_the_points_on_the_description_s_axes(descriptions, kind,
                                                           monkeypatch) -> None:
    """Two routes: the SVG path's points, mapped back through the axis scale, follow the
    data -- affine in log10(x) on a log axis, in x on a linear one (every point written:
    the thinning of long curves is tested in tests/test_units_option.py)."""
    monkeypatch.setattr(resonant.charts, "THIN_ABOVE", 10**9)
    charts = descriptions[kind]
    for chart, group in zip(charts.panels, _svg_panels(charts_svg(charts, "p"))):
        for bar in chart.bars:  # the bars' free ends, affine in their heights
            rects = [e for e in group.iter(f"{SVG}rect") if e.get("stroke") == "none"]
            h = np.asarray(bar.heights, dtype=float)
            ends = np.array([float(r.get("y")) + (float(r.get("height")) if v < 0 else 0.0)
                             for r, v in zip(rects, h)])
            fit = np.polyfit(h, ends, 1)
            assert fit[0] < 0 and np.max(np.abs(np.polyval(fit, h) - ends)) < 0.02
        if not chart.curves:
            continue
        path = next(group.iter(f"{SVG}path"))
        curve = next(c for c in chart.curves
                     if np.any(np.isfinite(c.y) & ((np.asarray(c.y) > 0) if chart.ylog
                                                    else True)))
        x = np.asarray(curve.x, dtype=float)
        y = np.asarray(curve.y, dtype=float)
        keep = np.isfinite(x) & np.isfinite(y) & ((y > 0) if chart.ylog else True)
        points = _path_points(path)
        assert len(points) == keep.sum()
        data_x = np.log10(x[keep]) if chart.xlog else x[keep]
        if np.ptp(data_x) > 0:
            fit = np.polyfit(data_x, points[:, 0], 1)
            assert fit[0] > 0
            assert np.max(np.abs(np.polyval(fit, data_x) - points[:, 0])) < 0.02
        data_y = np.log10(y[keep]) if chart.ylog else y[keep]
        inside = (points[:, 1] > -1e3) & (points[:, 1] < 1e4)  # not clipped far outside
        if np.ptp(data_y[inside]) > 0:
            fit = np.polyfit(data_y[inside], points[inside, 1], 1)
            assert fit[0] < 0  # up is smaller y in SVG
            assert np.max(np.abs(np.polyval(fit, data_y[inside]) - points[inside, 1])) < 0.02


@pytest.mark.parametrize("kind", KINDS)
def test_the_description_is_json_for_the_page(descriptions, kind) -> None:
    charts = descriptions[kind]
    text = json.dumps(charts.to_dict(), allow_nan=False)
    data = json.loads(text)
    assert len(data["panels"]) == len(charts.panels)
    for chart, panel in zip(charts.panels, data["panels"]):
        assert [c["label"] for c in panel["curves"]] == [c.label for c in chart.curves]
        assert panel["xlog"] == chart.xlog and panel["ylog"] == chart.ylog
        assert panel["xlabel"] == chart.xlabel and panel["ylabel"] == chart.ylabel
        for curve, stored in zip(chart.curves, panel["curves"]):
            y = np.asarray(curve.y, dtype=float)
            back = np.array([math.nan if v is None else v for v in stored["y"]])
            np.testing.assert_array_equal(np.isfinite(back), np.isfinite(y))
            np.testing.assert_array_equal(back[np.isfinite(y)], y[np.isfinite(y)])
        assert len(panel["markers"]) == len(chart.markers)
        assert len(panel["rules"]) == len(chart.rules)


def test_the_plot_functions_draw_the_view_s_description(tmp_path) -> None:
    """plot_frequency_response, plot_random and plot_srs draw what their chart functions
    describe (the same curves and scales), also into the caller's axes."""
    from matplotlib.figure import Figure

    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    sweep = model.linearize().sweep("omega", np.linspace(0.5, 30.0, 200))
    chart = frequency_response_chart(sweep)
    fig = plot_frequency_response(sweep, tmp_path / "f.png")
    assert [ax.get_yscale() for ax in fig.axes[:2]] == ["log", "linear"]
    assert len([ln for ln in fig.axes[0].get_lines() if not ln.get_label().startswith("_")]) \
        == len(chart.panels[0].curves)
    own = Figure()
    one = own.add_subplot()
    assert plot_frequency_response(sweep, ax=one) is own and len(own.axes) == 1

    result = random_response(resonant.load(EXAMPLES / "shaker_gevs.toml").linearize())
    charts = random_chart(result)
    fig = plot_random(result)
    assert len(fig.axes) == len(charts.panels)
    assert all(ax.get_xscale() == ax.get_yscale() == "log" for ax in fig.axes)
    assert [ax.get_ylabel() for ax in fig.axes] == [mathtext_label(p.ylabel)
                                                     for p in charts.panels]
    assert "$^{2}$" in charts.panels[1].ylabel or "$^{2}$" in charts.panels[-1].ylabel

    t, a = pulse("half-sine", 100.0, 0.011, 1e-5)
    srs = shock_response_spectrum(a, 1e-5, np.geomspace(10.0, 2000.0, 20))
    own = Figure()
    spectrum_axes = own.add_subplot()
    plot_srs(srs, t, a, ax=spectrum_axes, unit="m/s^2")
    assert spectrum_axes.get_xscale() == "log" and len(spectrum_axes.get_lines()) == 3


def test_a_chart_of_hostile_labels_draws_both_ways() -> None:
    """A label mathtext cannot set is drawn as plain text by matplotlib; the SVG escapes it."""
    chart = Chart((Curve(np.array([1.0, 10.0]), np.array([1.0, 2.0]), "$\\undefinedcmd{x}$"),),
                  "x $\\frac{$", "y <&>", (1.0, 10.0), xlog=True)
    fig = draw_figure(chart)
    FigureCanvasAgg(fig).draw()  # no mathtext error
    ElementTree.fromstring(charts_svg(Charts((chart,)), "h"))


LOADS = """
[shock]
signal = "y"
derivative = 2
pulse = "half-sine"
amplitude = 50
unit = "g"
duration = 0.011
step = 1e-5
total = 0.04

[periodic]
signal = "y"
shape = "triangle"
amplitude = 0.5
unit = "mm"
period = 0.004
"""


def test_the_report_s_load_sections_draw_the_views_charts(tmp_path) -> None:
    """The periodic, random and shock sections of the report carry the views' chart
    descriptions: the periodic response against time, the densities on log-log axes with
    units in the labels, the pulse above its SRS; their SVG is written directly (no
    matplotlib) and without plots there are none."""
    from resonant.analyses.random_response import random_response as random_route
    from resonant.report import build_report, render
    from resonant.report.blocks import Figure

    path = tmp_path / "loads.toml"
    path.write_text((EXAMPLES / "shaker_gevs.toml").read_text() + LOADS)
    model = resonant.load(path)
    report = build_report(model)
    figures = {b.caption.split(" ")[0] + " " + b.caption.split(" ")[1]: b.plot
               for b in report.blocks if isinstance(b, Figure)}
    periodic = next(p for c, p in figures.items() if c.startswith("The summed"))
    assert isinstance(periodic, Chart) and not periodic.xlog and periodic.ylabel.endswith("[m]")
    densities = next(p for c, p in figures.items() if c.startswith("One-sided"))
    assert isinstance(densities, Charts)
    assert all(p.xlog and p.ylog for p in densities.panels)
    # the spectrum is given in g^2/Hz: the accelerations are shown in g
    assert densities.panels[0].ylabel == "input [g$^{2}$/Hz]"
    assert "response [m$^{2}$/Hz]" in [p.ylabel for p in densities.panels]
    direct = random_route(model.linearize())
    labels = [c.label for p in densities.panels for c in p.curves]
    assert f"a (RMS {direct.rms['a'] / 9.80665:.3g} g)" in labels
    shock = next(p for c, p in figures.items() if c.startswith("The pulse"))
    assert isinstance(shock, Charts) and len(shock.panels) == 2
    history, spectrum = shock.panels
    assert not history.xlog and spectrum.xlog and spectrum.ylog
    assert max(history.curves[0].y) == pytest.approx(50.0, rel=1e-9)  # the 50 g pulse, in g
    assert [c.label for c in spectrum.curves] == ["maximax", "primary", "residual"]
    html = render(report, "html")
    for chart in figures.values():
        assert plain_text(chart.panels[0].ylabel if isinstance(chart, Charts)
                          else chart.ylabel) in html
    assert html.count("<figure>") == len([b for b in report.blocks if isinstance(b, Figure)])
    bare = build_report(model, plots=False)
    assert not [b for b in bare.blocks if isinstance(b, Figure)]
    assert "Shock load: the pulse and its shock response spectrum" in bare.headings()


@pytest.mark.parametrize("example", ["cart_pendulum", "pendulum"])
def test_a_nonlinear_simulation_of_an_undamped_example_plots(example, tmp_path) -> None:
    """``resonant simulate MODEL --nonlinear --plot F`` on the README's examples: an undamped
    model starts on its periodic solution, and the plot says so (it once stopped with a
    KeyError there)."""
    from conftest import run_cli

    path = tmp_path / "sim.png"
    status, _, err = run_cli(["simulate", EXAMPLES / f"{example}.toml", "--nonlinear",
                              "--plot", path])
    assert status == 0, err
    assert path.stat().st_size > 10_000


def test_every_start_kind_is_described() -> None:
    """Every start a simulation reports has its words in the plot's title."""
    from dataclasses import replace

    from resonant.analyses.simulate import simulation_chart
    from resonant.model.options import START_KINDS, START_MODES

    sim = simulate(resonant.load(EXAMPLES / "two_dof_free.toml").linearize(), 0.05,
                   initial={"x1": 0.01})
    assert set(START_MODES) - {"auto"} <= set(START_KINDS)
    for kind, words in START_KINDS.items():
        assert words in simulation_chart(replace(sim, start=kind)).title


def test_a_simulation_of_many_coordinates_draws_those_that_move_most() -> None:
    """A rotor's 28 coordinates once gave a 28-panel figure of 9,000 px; at most
    MAX_CURVES panels are drawn, those that move most each relative to the largest of its
    own unit (once ranked by SI sizes, metres against radians: the tilts of 1e-2 rad hid
    the pushed disc's 1 mm), and the title says how many of how many and by what rule."""
    from resonant.analyses.simulate import MOST_MOTION, simulation_chart
    from resonant.charts import MAX_CURVES
    from resonant.expressions.notation import dollar_name
    from resonant.model.units_display import result_units

    model = resonant.load(EXAMPLES / "rotors" / "friswell_5_9_1.toml")
    sim = simulate(model.linearize(), 0.01, initial={"disc1_x": 1e-3})
    assert len(sim.names) > MAX_CURVES
    units = result_units(model)
    assert units is not None
    chart = simulation_chart(sim, units)
    assert len(chart.panels) == MAX_CURVES
    assert f"{MAX_CURVES} of {len(sim.names)}" in chart.title and MOST_MOTION in chart.title
    by_label = {dollar_name(n): n for n in sim.names}
    drawn = {by_label[p.title.split(": ")[0]] for p in chart.panels}
    size = {n: float(np.max(np.abs(sim.states[n]))) for n in sim.names}
    largest = {u: max(size[n] for n in sim.names if units.si[n] == u)
               for u in set(units.si.values())}
    share = {n: size[n] / largest[units.si[n]] for n in sim.names}
    assert min(share[n] for n in drawn) >= max(share[n] for n in set(sim.names) - drawn)
    assert "disc1_x" in drawn and {units.si[n] for n in drawn} == {"m", "rad"}


