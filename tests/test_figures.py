"""Figures read like a textbook's: typeset names, units on every axis, a continuous phase,
labels nothing covers, study pictures that show impossible samples, decades and grid cells.

Every check reads the drawn matplotlib objects (labels, lines, the rendered extents of
texts), never a hard-coded picture.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

import resonant
from conftest import EXAMPLES, run_cli
from resonant.analyses.modes import plot_modes
from resonant.analyses.sweep import plot_frequency_response, unwrapped_degrees
from resonant.studies.study_charts import (
    axis_label,
    plot_contour,
    plot_histogram,
    plot_scatter,
    study_units,
)


def _sweep(name: str, start: float, stop: float) -> tuple:
    model = resonant.load(EXAMPLES / name)
    system = model.linearize()
    response = system.sweep("omega", np.linspace(start, stop, 600))
    from resonant.model.units_display import result_units

    units = result_units(model)
    return response, (units.si if units is not None else None)


def test_the_response_axes_are_typeset_with_units() -> None:
    response, units = _sweep("cart_pendulum.toml", 0.5, 30)
    fig = plot_frequency_response(response, units=units)
    amplitude, phase = fig.axes[:2]
    assert amplitude.get_ylabel() == "amplitude $X$ [m, rad]"
    assert phase.get_xlabel() == r"excitation frequency $\omega$ [rad/s]"
    assert phase.get_ylabel() == r"phase $\delta$ [°]"
    labels = [t.get_text() for t in amplitude.get_legend().get_texts()]
    assert "$x_{1}$ [m]" in labels and r"$\varphi$ (output) [rad]" in labels
    title = amplitude.get_title()
    assert r"\omega" in title and "omega" not in title.replace(r"\omega", "")


def test_the_phase_is_continuous() -> None:
    """A damped chain: its phase falls steadily through -180 and -360 degrees (no jump of
    a full turn between neighbouring samples, no gap)."""
    response, units = _sweep("chain3_damped.toml", 1, 80)
    fig = plot_frequency_response(response, units=units)
    phase_axes = fig.axes[1]
    for line in phase_axes.get_lines():
        y = np.asarray(line.get_ydata(), dtype=float)
        if y.size < 10:
            continue  # the natural frequencies' vertical lines
        assert np.all(np.isfinite(y))
        assert np.max(np.abs(np.diff(y))) < 60, "the phase jumps"
    lowest = min(np.nanmin(np.asarray(line.get_ydata(), dtype=float))
                 for line in phase_axes.get_lines())
    assert lowest < -360  # three modes: the lag of the far mass reaches -3 x 180


def test_unwrapping_takes_half_turns_as_a_growing_lag() -> None:
    assert unwrapped_degrees(np.radians([60.0, 60.0, -120.0, -120.0])).tolist() == \
        pytest.approx([60.0, 60.0, -120.0, -120.0])
    assert unwrapped_degrees(np.radians([-120.0, 60.0])).tolist() == \
        pytest.approx([-120.0, -300.0])
    with_gap = unwrapped_degrees(np.array([3.0, np.nan, -3.0, 3.1]))
    assert math.isnan(with_gap[1]) and with_gap[3] - with_gap[2] == pytest.approx(
        math.degrees(6.1 - 2 * math.pi))


def test_no_curve_crosses_a_peak_label() -> None:
    """Every peak label lies above every drawn point of every curve (rendered extents)."""
    for name, start, stop in (("chain3_damped.toml", 1, 80), ("cart_pendulum.toml", 0.5, 30)):
        response, units = _sweep(name, start, stop)
        fig = plot_frequency_response(response, units=units)
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig).draw()
        amplitude = fig.axes[0]
        renderer = fig.canvas.get_renderer()
        labels = [t for t in amplitude.texts if t.get_text()]
        assert labels, "no peak is labelled"
        highest = -np.inf
        for line in amplitude.get_lines():
            xy = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            if len(xy) > 10:
                highest = max(highest, amplitude.transData.transform(xy)[:, 1].max())
        legend = amplitude.get_legend().get_window_extent(renderer)
        axes_box = amplitude.get_window_extent(renderer)
        assert legend.x0 >= axes_box.x1, "the legend lies on the curves"
        for text in labels:
            box = text.get_window_extent(renderer)
            assert box.y0 > highest, f"label {text.get_text()} is covered by a curve"


def test_mode_shapes_have_readable_typeset_ticks() -> None:
    analysis = resonant.load(EXAMPLES / "shear_building6.toml").linearize().modes()
    fig = plot_modes(analysis)
    ax = fig.axes[0]
    ticks = ax.get_xticklabels()
    assert [t.get_text() for t in ticks] == [f"$x_{{{i}}}$" for i in range(1, 7)]
    assert min(t.get_fontsize() for t in ticks) >= 10
    assert min(t.get_fontsize() for t in ax.get_yticklabels()) >= 10
    assert r"$\omega_{1}$" in ax.get_title()


# -- studies ---------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def grid_frame() -> pd.DataFrame:
    """A 12 x 10 grid: a quantity spanning five decades, a jump, and impossible cells
    (k2 <= 0: 2 columns x 10 rows, 3 of them resonant)."""
    k, c = np.meshgrid(np.linspace(-100, 1000, 12), np.linspace(0.1, 10, 10))
    k, c = k.ravel(), c.ravel()
    peak = np.where(k > 0, 10.0 ** (-3 + 5 * c / 10), np.nan)
    jump = np.where(k > 400, 20.0, 12.0)
    status = np.where(k > 0, "ok", np.where(c < 3, "resonance", "unstable"))
    return pd.DataFrame({"k2": k, "c2": c, "peak:x1": peak,
                         "peak_frequency:x1": np.where(k > 0, jump, np.nan), "status": status})


UNITS = {"k2": "N/m", "c2": "N*s/m", "peak:x1": "m", "peak_frequency:x1": "rad/s"}


def test_a_grid_is_drawn_as_cells_with_impossible_samples_hatched(grid_frame) -> None:
    from matplotlib.collections import QuadMesh
    from matplotlib.colors import LogNorm

    fig = plot_contour(grid_frame, "peak:x1", "k2", "c2", units=UNITS,
                       nominal={"k2": 500.0, "c2": 5.0})
    ax = fig.axes[0]
    meshes = [c for c in ax.collections if isinstance(c, QuadMesh)]
    assert len(meshes) == 1 and not any(type(c).__name__ == "ContourSet"
                                        for c in ax.collections)
    assert isinstance(meshes[0].norm, LogNorm), "five decades on a linear colour scale"
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "no value: 6 resonance, 14 unstable" in legend
    assert "nominal design" in legend
    hatched = [c for c in ax.collections if c.get_hatch()]
    assert hatched, "the cells without a value are not hatched"
    star = [line for line in ax.get_lines() if line.get_marker() == "*"]
    assert star and list(star[0].get_xdata()) == [500.0]
    assert ax.get_xlabel() == "$k_{2}$ [N/m]"
    assert ax.get_ylabel() == r"$c_{2}$ [$\mathrm{N\,s/m}$]"


def test_a_jump_stays_sharp(grid_frame) -> None:
    """Cells, not contours: only the values that occur are drawn (12 and 20)."""
    fig = plot_contour(grid_frame, "peak_frequency:x1", "k2", "c2", units=UNITS)
    mesh = fig.axes[0].collections[-1]
    drawn = np.unique(np.ma.compressed(mesh.get_array()))
    assert drawn.tolist() == [12.0, 20.0]
    assert mesh.norm.__class__.__name__ == "Normalize"


def test_scatter_and_histogram_show_the_missing_samples(grid_frame) -> None:
    fig = plot_scatter(grid_frame, "peak:x1", ["k2", "c2"], units=UNITS,
                       nominal={"k2": 500.0, "c2": 5.0})
    texts = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert "no value: 6 resonance, 14 unstable" in texts and "nominal design" in texts
    ax = fig.axes[0]
    assert ax.get_yscale() == "log"
    crosses = [line for line in ax.get_lines() if line.get_marker() == "x"]
    assert crosses and len(crosses[0].get_xdata()) == 20
    width, height = fig.get_size_inches() * fig.dpi
    assert width >= 900 and height >= 380
    hist = plot_histogram(grid_frame, "peak:x1", units=UNITS)
    axes = hist.axes[0]
    assert axes.get_xscale() == "log"
    assert axes.get_title() == "100 samples (6 resonance, 14 unstable: no value)"


def test_study_axes_name_the_quantity_and_its_unit() -> None:
    model = resonant.load(EXAMPLES / "absorber_tolerances.toml")
    units = study_units(model, model.study_section)
    assert axis_label("peak_frequency:x1", units) == \
        "frequency of the peak of $x_{1}$ [rad/s]"
    assert axis_label("c2", units) == r"$c_{2}$ [$\mathrm{N\,s/m}$]"


def test_the_study_command_labels_its_pictures(tmp_path) -> None:
    status, _, err = run_cli(["study", EXAMPLES / "absorber_tolerances.toml", "--samples", "36",
                              "--design", "grid", "--workers", "0", "-o", tmp_path / "g.parquet",
                              "--plot", tmp_path / "plots"])
    assert status == 0, err
    names = sorted(p.name for p in (tmp_path / "plots").iterdir())
    assert "contour-peak_frequency_x1.png" in names


def test_the_study_table_and_json_carry_each_quantitys_unit(tmp_path) -> None:
    import json

    model = EXAMPLES / "absorber_tolerances.toml"
    status, out, err = run_cli(["study", model, "--samples", "20", "--workers", "0",
                                "-o", tmp_path / "s.parquet"])
    assert status == 0, err
    rows = {line.split()[0]: line.split()[1] for line in out.splitlines()[3:]
            if ":" in line.split()[0]}
    assert rows["peak:x1"] == "m" and rows["peak_frequency:x1"] == "rad/s"
    assert rows["natural_frequency:2"] == "rad/s"
    status, out, err = run_cli(["study", model, "--samples", "20", "--workers", "0",
                                "-o", tmp_path / "t.parquet", "--json"])
    assert status == 0, err
    units = json.loads(out)["units"]
    assert units == {"k2": "N/m", "c2": "N*s/m", "peak:x1": "m", "peak_frequency:x1": "rad/s",
                     "natural_frequency:1": "rad/s", "natural_frequency:2": "rad/s",
                     "amplitude:x1": "m"}
