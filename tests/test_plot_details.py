"""The details of the plots: the sweep's peak notes do not overlap, a local
bump between resonances is not marked as one (the highest peak always is), a curve left
out is said, a log axis of fewer than two decades labels 2, 3, 5 plainly, one resolution
for every figure."""

from __future__ import annotations

import numpy as np
import pytest

import resonant
from resonant.analyses.sweep import _Axis, frequency_response_chart
from resonant.charts import FIGURE_DPI, Chart, Charts, Curve, draw_figure

#: a chain of 9 unit masses and springs under a force on the last (matrices: no derivation)
CHAIN = """
[parameters]
omega = 1
[matrices]
M = {M}
K = {K}
C = {C}

[[harmonic]]
omega = "omega"
F_S = {F}
"""


def _chain(n: int, damping: float) -> resonant.Model:
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    F = [0.0] * (n - 1) + [1.0]
    return resonant.loads(CHAIN.format(M=np.eye(n).tolist(), K=K.tolist(),
                                       C=(damping * K).tolist(), F=F))


@pytest.fixture(scope="module")
def chain9():
    return _chain(9, 0.01).linearize().sweep("omega", np.linspace(0.05, 2.0, 150))


def test_a_left_out_curve_is_said(chain9):
    charts = frequency_response_chart(chain9)
    assert "8 of 9 responses drawn" in charts.title
    assert "of 9" not in frequency_response_chart(chain9, names=["q1", "q2"]).title


def test_peak_notes_do_not_overlap(chain9):
    chart = frequency_response_chart(chain9).panels[0]
    at = sorted(n.at for n in chart.notes)
    span = chart.xlim[1] - chart.xlim[0]
    assert len(at) >= 2 and min(np.diff(at)) > 0.05 * span


def test_a_bump_is_not_a_resonance_but_the_highest_peak_is_marked():
    axis = _Axis(lambda v: v, "rad/s", 1.0, False, np.array([1.0, 2.0]))
    assert axis.resonant(1.05) and not axis.resonant(1.5)
    heavy = _chain(1, 0.8).linearize().sweep("omega", np.linspace(0.05, 2.0, 100))
    peaks = [m for m in frequency_response_chart(heavy).panels[0].markers
             if m.shape == "peak"]
    assert len(peaks) == 1   # zeta = 0.4: the peak is 17 % below the natural frequency


def test_log_minor_ticks_read_plainly():
    chart = Chart((Curve(np.array([1.0, 8.0]), np.array([1.0, 2.0]), "y"),), "x", "y",
                  (1.0, 8.0), xlog=True)
    fig = draw_figure(Charts((chart,)))
    fig.canvas.draw()
    labels = {t.get_text() for t in fig.axes[0].get_xticklabels(minor=True)}
    assert {"2", "3", "5"} <= labels and not any("10" in t for t in labels)
    assert FIGURE_DPI == 150
