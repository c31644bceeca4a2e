"""Loads beyond a sine: the periodic load of ``[periodic]`` (Fourier series, the response
per harmonic, the sum, its largest excursion), the random inputs of ``[random]``
(spectral densities, RMS, Rice's rates, Miles beside the exact value) and the pulse of
``[shock]`` (its shock response spectrum, the largest responses), as a textbook shows them
(docs/random.md).  Their figures are the views' chart descriptions (the ones the library's
plots draw): :func:`~resonant.analyses.simulate.history_chart`,
:func:`~resonant.analyses.random_response.random_chart`,
:func:`~resonant.analyses.shock.srs_chart`."""

from __future__ import annotations

import numpy as np

from ...analyses.periodic_load import periodic_load_response
from ...analyses.random_response import random_chart, random_response
from ...analyses.shock import pulse, pulse_end, shock_response_spectrum, srs_chart
from ...analyses.simulate import history_chart
from ...analyses.transient import shock_response
from ...errors import ResonantError
from ...expressions.notation import number_latex
from ...model.fourier_shapes import FOURIER_SHAPES
from ...model.pulses import PULSE_KINDS
from ...model.random_spec import STANDARD_GRAVITY
from ...model.units import Dimension
from ...model.units_display import ResultUnits, Shown, result_units, shown_unit, unit_latex
from ...tables import number_column
from ..blocks import Block, Heading, Note, Part, Table, cell, paragraph
from .context import Context, _m

#: harmonics listed in the table of the periodic response
SHOWN_HARMONICS = 8
#: responses in the table of harmonics (the first coordinates; it fits a phone)
SHOWN_RESPONSES = 2
#: curves in the figure of the periodic response (the first responses)
DRAWN_RESPONSES = 4
#: natural frequencies of the shock response spectrum's oscillators
SRS_POINTS = 80

def _shape_description(shape: str) -> str:
    known = FOURIER_SHAPES.get(shape)
    if known is not None:
        return known.description
    return "the model's expression over one period" if shape == "expression" else shape


def _n(value: float) -> str:
    return number_latex(float(value), 4)


def _t(value: float, unit: str = "") -> str:
    """A number (and its unit) as plain text for a table cell: it wraps on a phone."""
    text = f"{float(value):.4g}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")
    return f"{text} {unit}" if unit and unit != "1" else text


def _cell(value: float, unit: str = "") -> tuple[Part, ...]:
    """A number and its unit as a table cell: the number as plain text (it wraps on a
    phone), the unit typeset (``m/s²``, not ``m/s^2``, in every writer)."""
    if not unit or unit == "1":
        return cell(_t(value))
    return cell(_t(value), _m(unit_latex(unit)))


def _amount(value: float, unit: str, units: ResultUnits | None = None) -> str:
    """``490.3 m/s² (50 g)`` in LaTeX: a value with its unit (in the display unit where
    one is chosen: ``50 g``), an acceleration in SI also in g."""
    shown = shown_unit(units, unit)
    text = _n(shown(value)) + unit_latex(shown.text) if shown.text and shown.text != "1" \
        else _n(value)
    if shown.text == "m/s^2":
        text += rf"\ ({_n(value / STANDARD_GRAVITY)}\ \mathrm{{g}})"
    return text


def _header(latex: str, shown: Shown) -> tuple[Part, ...]:
    """A column's header with the one unit of its numbers: ``b_n [m]`` (the unit typeset)."""
    if not shown.text or shown.text == "1":
        return cell(_m(latex))
    return cell(_m(latex + r"\ [" + unit_latex(shown.text).removeprefix("\\ ") + "]"))


def _column(values: list[float]) -> list[tuple[Part, ...]]:
    """A column's numbers in one notation (never ``0.0002056`` above ``8.637e-5``)."""
    return [cell(text.replace("e-0", "e-").replace("e+0", "e").replace("e+", "e"))
            for text in number_column(values)]


def _shown_cell(value: float, shown: Shown) -> tuple[Part, ...]:
    """A value (SI) in its display unit, as a table cell."""
    return _cell(shown(value), shown.text)


def _signal(ctx: Context, name: str, derivative: int) -> str:
    """The input as a function of time, as the report names it: y(t), its derivatives."""
    text = ctx.namer(name, derivative)
    return text if text.endswith("(t)") else text + "(t)"


def periodic_load(ctx: Context) -> list[Block]:
    """The stationary response to the ``[periodic]`` load, harmonic by harmonic."""
    spec = ctx.model.periodic_section
    if spec is None:
        return []
    blocks: list[Block] = [Heading("Periodic load: Fourier series and superposition")]
    try:
        result = periodic_load_response(ctx.system)
    except ResonantError as exc:
        return blocks + [Note((f"The periodic response cannot be computed: {exc}",))]
    series = result.series
    s = _signal(ctx, spec.signal, spec.derivative)
    units = result_units(ctx.model)
    load_unit = shown_unit(units, _input_unit(ctx, spec.signal, spec.derivative))
    blocks.append(paragraph(
        "The load ", _m(s), f" is {_shape_description(series.shape)} of "
        "period ", _m(rf"T = {_n(series.period)}\ \mathrm{{s}}"),
        *((" and amplitude ", _m("A = " + _amount(
            spec.amplitude, _input_unit(ctx, spec.signal, spec.derivative), units)))
          if spec.expression is None else ()),
        ". It is not harmonic, but it is the sum of its Fourier series,"))
    blocks.append(ctx.equation(
        s + r" = a_{0} + \sum_{n=1}^{H} \left(a_{n}\cos n\Omega t + b_{n}\sin n\Omega t"
        rf"\right),\quad \Omega = \frac{{2\pi}}{{T}} = {_n(2 * np.pi / series.period)}"
        r"\ \mathrm{rad/s},", label="fourier"))
    if series.shape in FOURIER_SHAPES:
        blocks.append(paragraph("with the coefficients of the shape"))
        blocks.append(ctx.equation(FOURIER_SHAPES[series.shape].latex + "."))
    else:
        blocks.append(paragraph("its coefficients from samples of one period (FFT)."))
    blocks.append(paragraph(
        "The series is cut at ", _m(f"H = {series.harmonics}"), " harmonics, where the "
        "remainder's RMS is ", _m(_n(100 * series.remainder) + r"\,\%"), " of the signal's "
        "(Parseval). The system is linear, so each harmonic gives a stationary response "
        "of its own, from the same equations as a single harmonic load, at the frequency ",
        _m(r"n\Omega"), ", and the response is their sum,"))
    blocks.append(ctx.equation(
        r"q_{k}(t) = q_{k,0} + \sum_{n=1}^{H} \mathrm{Re}\left(z_{k,n}\, e^{i n\Omega t}"
        r"\right),\quad z_{k,n} = H_{k}(n\Omega)\,(a_{n} - i\,b_{n}),", label="superposed"))
    blocks.append(paragraph("with ", _m(r"q_{k,0}"), " the static response to ",
                            _m("a_{0}"), ". The first harmonics:"))
    names = list(result.names[:SHOWN_RESPONSES])
    labels = [ctx.namer(name) for name in names]
    si = dict(units.si) if units is not None else {}
    shown = {name: shown_unit(units, si.get(name, "")) for name in result.names}
    # each column in one unit, written in its header (the numbers alone fit a phone)
    header = (cell(_m("n")), cell(_m(r"n\Omega/2\pi"), " [Hz]"), _header("a_{n}", load_unit),
              _header("b_{n}", load_unit),
              *(_header(f"|z_{{{label}}}|", shown[name]) for name, label in zip(names, labels)))
    shown_harmonics = range(min(SHOWN_HARMONICS, series.harmonics))
    columns = [_column([(i + 1) / series.period for i in shown_harmonics]),
               _column([float(load_unit(series.a[i])) for i in shown_harmonics]),
               _column([float(load_unit(series.b[i])) for i in shown_harmonics]),
               *(_column([float(shown[name](abs(result.harmonics[name][i])))
                          for i in shown_harmonics]) for name in names)]
    rows = [(cell(str(i + 1)), *(column[i] for column in columns)) for i in shown_harmonics]
    blocks.append(Table(header, tuple(rows)))
    blocks.append(paragraph("The sum over one period gives the largest excursions:"))
    rows = [(cell(_m(ctx.namer(name))), _shown_cell(result.mean[name], shown[name]),
             _shown_cell(result.largest[name], shown[name]))
            for name in result.names]
    blocks.append(Table((cell("response"), cell("mean ", _m("q_{k,0}")),
                         cell(_m(r"\max_{t}|q_{k}(t)|"))), tuple(rows)))
    # the first responses of the first one's unit: one axis, one scale
    drawn = [n for n in result.names if si.get(n, "") == si.get(result.names[0], "")]
    drawn = drawn[:DRAWN_RESPONSES]
    blocks += [] if not ctx.plots else [ctx.figure(
        history_chart(result.time, {name: shown[name](np.asarray(result.history[name]))
                                    for name in drawn},
                      {name: shown[name].text for name in drawn},
                      "periodic response $q_{k}(t)$"),
        f"The summed response over one period (T = {series.period:.4g} s): the static part "
        f"and the stationary responses to the first {series.harmonics} harmonics.")]
    blocks.extend(Note((w,)) for w in result.warnings)
    return blocks


def random_load(ctx: Context) -> list[Block]:
    """The response to the ``[random]`` inputs: densities, RMS, rates, Miles."""
    spec = ctx.model.random_section
    if spec is None:
        return []
    blocks: list[Block] = [Heading("Random load: spectral densities and RMS values")]
    try:
        result = random_response(ctx.system)
    except ResonantError as exc:
        return blocks + [Note((f"The random response cannot be computed: {exc}",))]
    inputs = [_signal(ctx, name, result.input_derivatives.get(name, 0))
              for name in result.inputs]
    blocks.append(paragraph(
        "The input" + ("s " if len(inputs) > 1 else " "), *_join([_m(u) for u in inputs]),
        " are stationary random signals given by their one-sided spectral densities per "
        "hertz over " if len(inputs) > 1 else " is a stationary random signal given by its "
        "one-sided spectral density per hertz over ",
        _m(rf"{_n(result.band[0])} \le f \le {_n(result.band[1])}\ \mathrm{{Hz}}"),
        ". Each response's density is the input's density filtered by the squared "
        "magnitude of the frequency response, and its mean square is the area under it:"))
    if len(result.inputs) == 1:
        blocks.append(ctx.equation(
            r"S_{r}(f) = |H_{r}(f)|^{2}\, S_{u}(f),\qquad \sigma_{r}^{2} = "
            r"\int S_{r}(f)\, \mathrm{d}f,", label="psd"))
    else:
        blocks.append(ctx.equation(
            r"S_{r}(f) = \mathbf{H}_{r}(f)\, \mathbf{S}_{uu}(f)\, \mathbf{H}_{r}^{H}(f),"
            r"\qquad \sigma_{r}^{2} = \int S_{r}(f)\, \mathrm{d}f,", label="psd"))
    blocks.append(paragraph(
        "A Gaussian response crosses zero upwards ", _m(r"\nu_{0}^{+} = \sqrt{m_{2}/m_{0}}"),
        " times a second and peaks ", _m(r"\nu_{p} = \sqrt{m_{4}/m_{2}}"), " times a second "
        "(Rice), ", _m(r"m_{j} = \int f^{j} S_{r}\, \mathrm{d}f"), ":"))
    units = result_units(ctx.model)
    shown = {name: shown_unit(units, result.units.get(name, "")) for name in result.names}
    rows = []
    for name in result.names:
        rows.append((cell(_m(ctx.namer(name))), _shown_cell(result.rms[name], shown[name]),
                     _shown_cell(3 * result.rms[name], shown[name]),
                     _cell(result.zero_crossing_rate[name]),
                     _cell(result.peak_rate[name])))
    blocks.append(Table((cell("response"), cell("RMS ", _m(r"\sigma")),
                         cell(_m(r"3\sigma")), cell(_m(r"\nu_{0}^{+}"), " [1/s]"),
                         cell(_m(r"\nu_{p}"), " [1/s]")), tuple(rows)))
    blocks.append(paragraph(
        "The integrals are adaptive quadratures whose estimated relative error is at most ",
        _m(_n(max(result.error.values(), default=0.0))), "."))
    if result.miles and result.natural_frequency is not None and result.quality is not None:
        blocks.append(paragraph(
            "For one degree of freedom with light damping, Miles' equation takes the input "
            "density as flat near the natural frequency ",
            _m(rf"f_{{n}} = {_n(result.natural_frequency)}\ \mathrm{{Hz}}"), ", with ",
            _m(rf"Q = {_n(result.quality)}"), ":"))
        blocks.append(ctx.equation(
            r"\sigma_{r} \approx g_{r} \sqrt{\frac{\pi}{2}\, f_{n}\, Q\, S_{u}(f_{n})},",
            label="miles"))
        blocks.append(paragraph(
            "with ", _m("g_{r}"), " the response's static gain (1 for the absolute "
            "acceleration under a base acceleration, Miles 1954). Beside the exact value:"))
        miles_rows = [(cell(_m(ctx.namer(name))), _shown_cell(value, shown[name]),
                 _shown_cell(result.rms[name], shown[name]),
                 cell(f"{100 * (value / result.rms[name] - 1):+.2f} %"))
                for name, value in result.miles.items() if result.rms.get(name)]
        blocks.append(Table((cell("response"), cell("Miles"), cell("exact"),
                             cell("difference")), tuple(miles_rows)))
    blocks += [] if not ctx.plots else [ctx.figure(
        random_chart(result, units=units),
        "One-sided spectral densities on log-log axes: the input" +
        ("s" if len(result.inputs) > 1 else "") + " (top) and the responses (one panel "
        "per unit), each labelled with its RMS value" +
        ("; dashed: the natural frequency." if result.natural_frequency is not None
         else "."))]
    blocks.extend(Note((w,)) for w in result.warnings)
    return blocks


def _input_unit(ctx: Context, name: str, derivative: int) -> str:
    """The SI unit of a signal's derivative (a force for a coordinate), "" without units."""
    units = ctx.model.units
    found = units.dimensions.get(name) if units is not None else None
    if found is None:
        return ""
    dim = (Dimension.of(kg=1, m=2, s=-2) / found if name in ctx.model.coordinates
           else found / Dimension.of(s=derivative))
    return dim.text() or "1"


def _srs_frequencies(ctx: Context, duration: float, step: float) -> np.ndarray:
    """The oscillators' natural frequencies (Hz): around the pulse's own (1/duration) and
    the system's, below a tenth of the sampling rate."""
    natural = [w / (2 * np.pi) for w in ctx.solution.natural_frequencies if w > 0] \
        if ctx.solution.available else []
    low = min([0.1 / duration, *(f / 3 for f in natural)])
    high = min(max([20.0 / duration, *(3 * f for f in natural)]), 0.1 / step)
    return np.geomspace(low, max(high, 10 * low), SRS_POINTS)


def shock_load(ctx: Context) -> list[Block]:
    """The ``[shock]`` pulse: its shock response spectrum and the largest responses."""
    spec = ctx.model.shock_section
    if spec is None:
        return []
    blocks: list[Block] = [Heading("Shock load: the pulse and its shock response spectrum")]
    try:
        t, values = pulse(spec.pulse, spec.amplitude, spec.duration, spec.step)
        spectrum = shock_response_spectrum(values, spec.step,
                                           _srs_frequencies(ctx, spec.duration, spec.step),
                                           Q=spec.Q,
                                           excitation_end=pulse_end(spec.pulse, spec.duration,
                                                                    spec.step))
        result = shock_response(ctx.system, spec)
    except ResonantError as exc:
        return blocks + [Note((f"The shock response cannot be computed: {exc}",))]
    s = _signal(ctx, spec.signal, spec.derivative)
    unit = _input_unit(ctx, spec.signal, spec.derivative)
    units = result_units(ctx.model)
    blocks.append(paragraph(
        "The input ", _m(s), f" is {PULSE_KINDS[spec.pulse].description} pulse of "
        "amplitude ", _m("A = " + _amount(spec.amplitude, unit, units)), " and duration ",
        _m(rf"\tau = {_n(spec.duration)}\ \mathrm{{s}}"), ". Its shock response spectrum "
        "is the largest absolute acceleration of a single-degree-of-freedom oscillator of "
        "natural frequency ", _m("f_{n}"), " and ", _m(rf"Q = {_n(spec.Q)}"), " on it, "
        "against ", _m("f_{n}"), ": over all time (maximax), while the pulse lasts "
        "(primary) and after it (residual)."))
    blocks += [] if not ctx.plots else [ctx.figure(
        srs_chart(spectrum, t, values, unit, units=units),
        "The pulse (top) and its shock response spectrum on log-log axes (bottom).")]
    blocks.append(paragraph(
        "The model's own response, computed step by step over ",
        _m(rf"{_n(spec.total)}\ \mathrm{{s}}"), ", reaches at most:"))
    si = dict(units.si) if units is not None else {}
    rows = [(cell(_m(ctx.namer(name))),
             _shown_cell(result.largest[name], shown_unit(units, si.get(name, ""))))
            for name in result.names]
    blocks.append(Table((cell("response"), cell(_m(r"\max_{t}|q_{k}(t)|"))), tuple(rows)))
    blocks.extend(Note((w,)) for w in (*spectrum.warnings, *result.warnings))
    return blocks


def _join(parts: list) -> list:
    out: list = []
    for i, part in enumerate(parts):
        if i:
            out.append(" and " if i == len(parts) - 1 else ", ")
        out.append(part)
    return out
