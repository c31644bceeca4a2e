"""Plots use matplotlib's object API only; analysis results hold read-only arrays."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

import resonant.api
import resonant.model
from resonant.errors import AnalysisError

pytest.importorskip("matplotlib.figure")

import matplotlib.pyplot as plt  # noqa: E402  (only to inspect its figure manager)
from matplotlib.figure import Figure  # noqa: E402

TWO_DOF = '''
[parameters]
m1 = 1
m2 = {m2}
k1 = 100
k2 = {k2}
c1 = 0.8
omega = 6
[coordinates]
x1 = "displacement"
x2 = "displacement"
[signals]
F = "sin(omega*t)"
[energy]
T = "m1*x1'^2/2 + m2*x2'^2/2"
U = "k1*x1^2/2 + k2*(x2 - x1)^2/2"
D = "c1*x1'^2/2"
[[force]]
generalized = {{ x1 = "F" }}
[outputs]
spring = "x2 - x1"
'''


def _model(m2: float = 0.5, k2: float = 40.0):
    return resonant.api.loads(TWO_DOF.format(m2=m2, k2=k2))


@pytest.fixture(scope="module")
def results():
    """Sweeps, modal analyses and simulations of a few small models."""
    models = [_model(), _model(0.2, 25.0), _model(1.5, 80.0)]
    sweeps, modal, sims = [], [], []
    for model in models:
        eom = model.linearize()
        sweeps.append(eom.sweep("omega", np.linspace(1.0, 20.0, 120)))
        sweeps.append(eom.sweep("k2", np.geomspace(10.0, 200.0, 60)))
        modal.append(eom.modes())
        sims.append(model.simulate(duration=2.0))
    return sweeps, modal, sims


def test_plots_leave_pyplot_and_backend_alone(results, tmp_path):
    """Every kind of plot (both sweeps, modes, a simulation), drawn and written to each
    format, leaves pyplot's figures and the backend alone.  One model's results: the
    other two models take the same code path, and each plot costs about a second."""
    sweeps, modal, sims = results
    backend = matplotlib.get_backend()
    before = plt.get_fignums()
    calls = 0
    figures = []
    for i, fr in enumerate(sweeps[:2]):                  # the omega and k2 sweeps x 2 = 4
        figures.append(fr.plot())
        figures.append(fr.plot(tmp_path / f"sweep{i}.png", names=fr.names[:1]))
        calls += 2
    for i, m in enumerate(modal[:1]):                    # 1 x 2 = 2
        figures.append(m.plot())
        figures.append(m.plot(tmp_path / f"modes{i}.svg", count=1))
        calls += 2
    for i, s in enumerate(sims[:1]):                     # 1 x 2 = 2
        figures.append(s.plot())
        figures.append(s.plot(tmp_path / f"sim{i}.pdf"))
        calls += 2
    figures.append(sweeps[0].plot(tmp_path / "again.svg"))  # 1
    calls += 1
    assert calls == 9
    assert all(isinstance(f, Figure) for f in figures)
    assert plt.get_fignums() == before
    assert matplotlib.get_backend() == backend
    written = sorted(p.name for p in tmp_path.iterdir())
    assert len(written) == 5 and all((tmp_path / n).stat().st_size > 0 for n in written)
    assert (tmp_path / "sweep0.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_frequency_response_into_given_axes(results):
    fr = results[0][0]
    fig = Figure()
    amp, phase = fig.subplots(2, 1)
    assert fr.plot(ax=(amp, phase)) is fig
    assert len(amp.get_lines()) > 0 and len(phase.get_lines()) > 0
    assert amp.get_yscale() == "log"
    # a single Axes: the amplitude panel alone
    fig2 = Figure()
    single = fig2.add_subplot()
    assert fr.plot(ax=single) is fig2
    assert len(fig2.axes) == 1 and single.get_lines()
    with pytest.raises(AnalysisError):
        fr.plot(ax=(amp, phase, single))


def test_modes_and_simulation_into_given_axes(results):
    _, modal, sims = results
    fig = Figure()
    ax = fig.add_subplot()
    assert modal[0].plot(ax=ax) is fig
    assert len(ax.patches) == 2           # one bar per coordinate, the first mode
    assert "mode 1" in ax.get_title()
    fig2 = Figure()
    axes = fig2.subplots(1, 2)
    assert modal[0].plot(ax=axes) is fig2
    assert "mode 2" in axes[1].get_title()
    fig3 = Figure()
    axes3 = fig3.subplots(len(sims[0].names), 1)
    assert sims[0].plot(axes=axes3) is fig3
    assert all(a.get_lines() for a in axes3)
    fig4 = Figure()
    one = fig4.add_subplot()
    assert sims[0].plot(axes=one) is fig4 and one.get_lines()
    assert plt.get_fignums() == []


def test_axes_in_a_subfigure_return_the_top_figure(results):
    fig = Figure()
    sub = fig.subfigures(1, 2)[0]
    ax = sub.add_subplot()
    assert results[1][0].plot(ax=ax) is fig


@pytest.mark.parametrize("suffix", [".jpg", ".txt", ""])
def test_unsupported_suffix(results, tmp_path, suffix):
    sweeps, modal, sims = results
    for result in (sweeps[0], modal[0], sims[0]):
        with pytest.raises(AnalysisError, match="png, .svg or .pdf"):
            result.plot(tmp_path / f"plot{suffix}")
    assert list(tmp_path.iterdir()) == []
    assert plt.get_fignums() == []


def test_unwritable_path(results, tmp_path):
    with pytest.raises(AnalysisError, match="cannot write the plot"):
        results[0][0].plot(tmp_path / "missing" / "dir" / "plot.png")


def _read_only(array) -> None:
    assert isinstance(array, np.ndarray)
    assert not array.flags.writeable
    with pytest.raises(ValueError):
        array[(0,) * array.ndim] = 99


def test_stationary_solution_is_read_only():
    sol = _model().linearize().stationary()
    for h in sol.harmonics:
        for a in (h.L, h.N, h.F_S, h.F_C):
            _read_only(a)
    for a in (sol.eom.M, sol.eom.C, sol.eom.K, sol.natural_frequencies, sol.eigenvalues):
        _read_only(a)
    with pytest.raises(ValueError):
        sol.eom.M[0, 0] = 99
    assert sol.amplitudes["x1"] > 0        # the mappings are read-only too
    with pytest.raises(TypeError):
        sol.amplitudes["x1"] = 1.0          # type: ignore[index]


def test_frequency_response_is_read_only(results):
    fr = results[0][0]
    for a in (fr.values, fr.response, fr.harmonic_omegas, fr.natural_frequencies):
        _read_only(a)
    for name in fr.names:
        _read_only(fr.amplitudes[name])
        _read_only(fr.phases[name])
    table = fr.peak_table
    for a in (table.index, table.values, table.amplitudes):
        if a.size:
            _read_only(a)
        else:
            assert not a.flags.writeable


def test_frequency_response_does_not_alias_the_callers_array():
    values = np.linspace(1.0, 20.0, 50)
    fr = _model().linearize().sweep("omega", values)
    values[0] = -1.0                        # the caller's array stays writable ...
    assert values.flags.writeable
    assert fr.values[0] == 1.0              # ... and the result keeps its own values


def test_modal_analysis_is_read_only(results):
    m = results[1][0]
    for a in (m.natural_frequencies, m.mode_shapes, m.omega_squared,
              m.mass_normalised_modes, m.eigenvalues, m.damping_ratios,
              m.damped_frequencies):
        _read_only(a)
    limited = m.limited(1)
    _read_only(limited.mode_shapes)


def test_simulation_is_read_only(results):
    s = results[2][0]
    _read_only(s.t)
    for name in s.names:
        _read_only(s.states[name])
    for y in s.linear_response.values():
        _read_only(y)
    with pytest.raises(TypeError):
        s.states["x1"] = s.t                # type: ignore[index]
    # the data still work: CSV and JSON read the arrays
    assert s.to_dict()["samples"] == s.t.size


def test_solve_text_of_a_large_model_summarizes_the_matrices(monkeypatch):
    """Beyond 12 coordinates the text of ``solve`` gives the matrices' sizes, not their
    entries, and never derives the symbolic matrices (a 100-link chain printed 15 MB of
    symbolic entries and took 30 s; the JSON output keeps them, as the contract says)."""
    from conftest import pendulum_chain_text

    from resonant.api import loads
    from resonant.system import symbolic

    eom = loads(pendulum_chain_text(20)).linearize()
    assert isinstance(eom, symbolic.DeferredEOM)

    def symbolic_derivation(*args, **kwargs):
        raise AssertionError("the text derived the symbolic matrices")

    monkeypatch.setattr(symbolic.DeferredEOM, "raw", symbolic_derivation)
    text = eom.stationary().summary()
    assert "mass matrix M: 20 x 20, 400 nonzero entries" in text
    assert "not printed entry by entry" in text and "omega_20" in text
