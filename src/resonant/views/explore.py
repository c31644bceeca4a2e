"""The explore page: one self-contained HTML file in which a model can be played with.

:func:`explore_page` writes, for any model, a page with a slider and a number field
for every parameter, the numbers of the linear system (M, C, K, natural frequencies,
damping ratios, stability, amplitudes and phases), the frequency response, the time
history over one period and the mechanism drawn from its parts moving with the
response or in a mode shape (a model without parts: a bar per coordinate).

How it computes (docs/explore.md): the model's symbolic M, C, K, loads, outputs and
drawing are printed as JavaScript by resonant's own printer
(:mod:`resonant.views.explore_export`), and the page solves the complex stationary
system and the eigenproblems with its own small solvers
(``explore_assets/numerics.js``).  A model too large for that (more than
:data:`LIVE_LIMIT` coordinates), or one whose expressions the printer cannot write,
gets curves, modes and numbers computed here instead, and the page says so.

The page loads nothing: its style, scripts and data are inline, a Content Security
Policy forbids any request and any ``eval``, and every string of the model reaches
the page as JSON data shown as text.

Examples
--------
>>> import resonant
>>> page = explore_page(resonant.load("examples/cart_pendulum.toml"))
>>> page.live, page.html.startswith("<!DOCTYPE html>"), "resonantMatrices" in page.html
(True, True, True)
"""

from __future__ import annotations

import html
import json
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..analyses.campbell import RPM, Campbell, campbell
from ..analyses.measured_match import MatchedTest
from ..analyses.modes import modes
from ..analyses.periodic_load import load_series, periodic_response
from ..analyses.rotor_map import MAP_MODES, MAP_STIFFNESS, CriticalSpeedMap, critical_speed_map
from ..analyses.stationary import stationary
from ..analyses.sweep import response_axes, sweep
from ..analyses.unbalance import unbalance_response
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem
from ..expressions.notation import name_latex
from ..model import Model
from ..model.campbell_spec import unbalance_columns
from ..model.rotor import Bearing, SpeedTable
from ..model.units_display import ResultUnits, result_units
from ..system.base import LinearSystem
from ..system.build import linear_system
from ..system.stability import natural_frequencies
from .explore_export import ExportedSystem, equilibrium_values, export_system
from .explore_measured import measured_first, measured_overlay
from .js_printer import NotPrintable
from .sketch import SketchMotion, sketch_motion

#: the most coordinates for which the page computes everything itself
LIVE_LIMIT = 40
#: points of the frequency response curve
CURVE_POINTS = 400
#: at most this many names in the frequency response by default
DEFAULT_SHOWN = 6
#: modes a precomputed page shows
PRECOMPUTED_MODES = 12
#: the largest matrices a precomputed page prints
PRECOMPUTED_MATRICES = 12
#: the working memory a precomputed page of a model given by its energies may take, in
#: bytes: its frequency response evaluates M, C and K (n * n complex numbers each) at
#: every point of the curve, and holds about twice that at once
PAGE_MEMORY = 2**30
#: the most coordinates of a model given by its energies that the page shows (decided
#: from the coordinates alone, before anything is derived): 167 for PAGE_MEMORY; a
#: [matrices] model is evaluated once, sparse, and has no such bound
MAX_ENERGY_COORDINATES = math.isqrt(PAGE_MEMORY // (2 * 3 * CURVE_POINTS * 16))
#: names preferred as the excitation frequency, in order
FREQUENCY_NAMES = ("omega", "Omega", "w", "W", "omega_e", "Omega_e")


@dataclass(frozen=True)
class ExplorePage:
    """The explore page of a model: one self-contained HTML document.

    Parameters
    ----------
    html : str
        The whole document.
    title : str
        The model's title.
    live : bool
        True when the page computes from the model's equations (False: precomputed).
    warnings : tuple of str, optional
        What the page could not show (measured FRFs that cannot give the response to the
        model's load: :func:`resonant.views.explore_measured.measured_overlay`'s note).

    Examples
    --------
    >>> page = ExplorePage("<!DOCTYPE html><title>x</title>", "x", True)
    >>> page._repr_html_().startswith("<iframe")
    True
    """

    html: str
    title: str
    live: bool
    warnings: tuple[str, ...] = ()

    def saved(self, path: str | Path | None) -> ExplorePage:
        """The page itself, written to ``path`` first where one is given.

        Parameters
        ----------
        path : str or Path, optional

        Returns
        -------
        ExplorePage
        """
        if path is not None:
            self.save(path)
        return self

    def save(self, path: str | Path) -> Path:
        """Write the page to ``path`` (UTF-8).

        Parameters
        ----------
        path : str or Path
            The file to write.

        Returns
        -------
        Path
            The file written.

        Raises
        ------
        ModelError
            If the file cannot be written.
        """
        target = Path(path)
        try:
            target.write_text(self.html, encoding="utf-8")
        except OSError as exc:
            raise ModelError(Problem(f"cannot write the page: {exc.strerror or exc}",
                                     str(path))) from None
        return target

    def _repr_html_(self) -> str:
        """The page in an iframe (``srcdoc``), where its scripts run in Jupyter."""
        return (f'<iframe title="{html.escape(self.title or "resonant explore")}" '
                f'srcdoc="{html.escape(self.html, quote=True)}" sandbox="allow-scripts" '
                'style="width: 100%; height: 920px; border: 1px solid #ccc;"></iframe>')


# -- choices ---------------------------------------------------------------------------------

def default_range(value: float) -> tuple[float, float, bool]:
    """The slider range of a parameter without one: a log range around a positive value.

    Parameters
    ----------
    value : float
        The parameter's value (SI).

    Returns
    -------
    tuple
        (from, to, logarithmic).

    Examples
    --------
    >>> default_range(100.0), default_range(0.0), default_range(-2.0)
    ((25.0, 400.0, True), (-1.0, 1.0, False), (-8.0, 0.0, False))
    """
    if value > 0:
        return value / 4, value * 4, True
    if value < 0:
        return 4 * value, 0.0, False
    return -1.0, 1.0, False


def frequency_parameter(model: Model, system: LinearSystem) -> str | None:
    """The parameter that sets the excitation frequency (swept by the frequency response).

    ``[explore] frequency`` if given; else the parameter in the symbolic excitation
    frequencies (``omega`` preferred when there are several); None when the frequency
    is no parameter (or there is no excitation).

    Parameters
    ----------
    model : Model
    system : LinearSystem

    Returns
    -------
    str or None

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> frequency_parameter(model, resonant.system.linear_system(model))
    'omega'
    """
    if model.explore_section is not None and model.explore_section.frequency is not None:
        return model.explore_section.frequency
    harmonics = getattr(system, "harmonics", None)
    if harmonics is None:
        return None
    found: list[str] = []
    for w in harmonics.frequencies:
        found += [s.name for s in w.free_symbols if s.name in model.parameters]
    candidates = [p for p in model.parameters if p in found]
    if not candidates:
        return None
    preferred = [p for p in FREQUENCY_NAMES if p in candidates]
    return preferred[0] if preferred else candidates[0]


def _frequency_range(system: LinearSystem, value: float, deadline: Deadline
                     ) -> tuple[float, float, bool]:
    """0 to 1.5 times the highest natural frequency (at least twice the value)."""
    top = 0.0
    try:
        numeric = system.numeric(deadline)
        if numeric.n <= LIVE_LIMIT:
            omegas = natural_frequencies(np.asarray(numeric.dense().M),
                                         np.asarray(numeric.dense().K))
            top = float(omegas.max()) if omegas.size else 0.0
    except (AnalysisError, ModelError, np.linalg.LinAlgError, ValueError):
        top = 0.0
    stop = max(1.5 * top, 2 * abs(value), 1e-9)
    return 0.0, float(f"{stop:.3g}"), False


def _range_of(model: Model, name: str, value: float) -> tuple[float, float, bool]:
    spec = model.explore_section.ranges.get(name) if model.explore_section is not None else None
    if spec is not None:
        return spec.start, spec.stop, spec.log
    variants = {v.name: v.values for v in model.exercise.variants} \
        if model.exercise is not None else {}
    values = variants.get(name)
    if values and min(values) < max(values):
        low, high = min(values), max(values)
        return low, high, low > 0 and high / low >= 20
    return default_range(value)


def controls(model: Model, system: LinearSystem, frequency: str | None,
             deadline: Deadline = NO_DEADLINE) -> list[dict[str, Any]]:
    """A slider's data for every parameter: value, unit, range, formula.

    Ranges come from ``[explore]``, else from ``[variants]``, else
    :func:`default_range` (the excitation frequency: 0 to beyond the highest natural
    frequency).

    Parameters
    ----------
    model : Model
    system : LinearSystem
    frequency : str or None
        The excitation frequency's parameter.
    deadline : Deadline, optional

    Returns
    -------
    list of dict
        JSON-ready, one per parameter in the model's order.

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> k = controls(model, resonant.system.linear_system(model), "omega")[3]
    >>> k["name"], k["value"], k["unit"], k["from"], k["to"]
    ('k', 100.0, 'N/m', 25.0, 400.0)
    """
    given = model.units.given if model.units is not None else {}
    out = []
    for name, expression in model.parameters.items():
        value = float(model.parameter_values[name])
        start, stop, log = _range_of(model, name, value)
        spec = model.explore_section
        if name == frequency and (spec is None or name not in spec.ranges):
            start, stop, log = _frequency_range(system, value, deadline)
        unit = given[name][1] if name in given else None
        out.append({"name": name, "symbol": name_latex(name), "value": value,
                    "from": start, "to": stop, "log": log,
                    "unit": unit.text if unit is not None else "",
                    "factor": unit.to_si() if unit is not None else 1.0,
                    "formula": expression.text if expression.names() else "",
                    "frequency": name == frequency})
    return out


def shown_names(model: Model, system: LinearSystem) -> list[str]:
    """The names the frequency response shows: ``[explore] show``, else the outputs and
    coordinates (at most :data:`DEFAULT_SHOWN`).

    Parameters
    ----------
    model : Model
    system : LinearSystem

    Returns
    -------
    list of str

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> shown_names(model, resonant.system.linear_system(model))
    ['x1', 'x2', 'phi']
    """
    if model.explore_section is not None and model.explore_section.show:
        return list(model.explore_section.show)
    return [*system.coordinates, *model.outputs][:DEFAULT_SHOWN]


def _unit_text(units: ResultUnits | None, name: str) -> str:
    """The unit a name is shown in: its display unit, else its SI unit (an angle: rad);
    "" for a pure number."""
    shown = units.unit(name) if units is not None else None
    if units is None or shown is None:
        return ""
    text = shown.text or (units.si.get(name, "") if shown.factor == 1 else "")
    return "" if text == "1" else str(text)


def _name_units(model: Model, names: list[str]) -> list[dict[str, Any]]:
    units = result_units(model)
    out = []
    for name in names:
        shown = units.unit(name) if units is not None else None
        out.append({"name": name, "symbol": name_latex(name),
                    "description": model.descriptions.get(name, ""),
                    "unit": _unit_text(units, name),
                    "factor": shown.factor if shown is not None else 1.0})
    return out


def _response_chart(model: Model, system: LinearSystem, sliders: list[dict[str, Any]],
                    names: list[str]) -> dict[str, Any] | None:
    """The frequency response's axes and curve styles as resonant's plots draw them
    (:func:`resonant.analyses.sweep.response_axes`, as JSON): the page draws its curve with
    them; None without an excitation frequency.  The page samples its curve evenly from
    the range's start: a linear axis."""
    control = next((c for c in sliders if c["frequency"]), None)
    if control is None:
        return None
    units = result_units(model)
    return response_axes(control["name"], names, coordinates=list(system.coordinates),
                         units={n: _unit_text(units, n) for n in names}, unit=control["unit"],
                         frequency_sweep=True, log=False).to_dict()


def _drawing(motion: SketchMotion) -> dict[str, Any]:
    """The sketch as JSON with what carries each item."""
    data = motion.sketch.to_dict()
    data["bounds"] = list(motion.sketch.bounds())
    data["points"] = [[name, *at, motion.points.get(name, -1)]
                      for name, at in motion.sketch.points.items()]
    data["owners"] = list(motion.owners)
    data["shifts"] = [list(s) for s in motion.shifts]
    data["carriers"] = {"bodies": list(motion.bodies), "links": [list(p) for p in motion.links],
                        "supports": list(motion.supports), "pins": list(motion.pins),
                        "forces": list(motion.forces)}
    return data


# -- the precomputed page -------------------------------------------------------------------

def precomputed(system: LinearSystem, frequency: str | None, frequency_control: dict[str, Any]
                | None, names: list[str], deadline: Deadline = NO_DEADLINE) -> dict[str, Any]:
    """Curves, modes and numbers at the file's parameter values, for a page that cannot
    compute them itself.

    Parameters
    ----------
    system : LinearSystem
    frequency : str or None
        The excitation frequency's parameter (the curves' abscissa).
    frequency_control : dict or None
        Its slider (the curves' range).
    names : list of str
        The names of the curves.
    deadline : Deadline, optional

    Returns
    -------
    dict
        JSON-ready: ``solution`` (as ``resonant solve --json``, without the matrices of a
        large model), ``modes`` and ``curve`` (``values``, per name ``amplitudes`` and
        the complex amplitudes ``L``, ``N`` per frequency).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/absorber.toml")
    >>> system = resonant.system.linear_system(model)
    >>> data = precomputed(system, None, None, ["x1"])
    >>> sorted(data), data["curve"] is None
    (['curve', 'modes', 'solution'], True)
    """
    solution = stationary(system, deadline).to_dict()
    if system.n > PRECOMPUTED_MATRICES:
        for key in ("M", "C", "K", "symbolic", "eigenvalues"):
            solution.pop(key, None)
    found = modes(system, count=min(PRECOMPUTED_MODES, system.n), deadline=deadline)
    curve = None
    if frequency is not None and frequency_control is not None:
        start, stop = frequency_control["from"], frequency_control["to"]
        values = np.linspace(start, stop, CURVE_POINTS)
        result = sweep(system, frequency, values, names=[n for n in names
                                                         if n in system.coordinates],
                       deadline=deadline)
        index = {q: i for i, q in enumerate(result.quantities)}
        # response: (harmonics, values, quantities) complex L - iN; omegas (harmonics, values)
        curve = {"values": values.tolist(), "omegas": result.harmonic_omegas.T.tolist(),
                 "names": {name: {"amplitudes": _finite(result.amplitudes[name]),
                                  "L": _finite(result.response[:, :, index[name]].real.T),
                                  "N": _finite(-result.response[:, :, index[name]].imag.T)}
                           for name in names if name in index}}
    return {"solution": solution, "curve": curve, "modes": {
        "natural_frequencies": found.natural_frequencies.tolist(),
        "mode_shapes": found.mode_shapes.T.tolist(),
        "damping_ratios": found.damping_ratios.tolist(), "stability": found.stability}}


def _finite(array: np.ndarray) -> list[Any]:
    """An array as JSON lists, NaN (a skipped point) as null."""
    return json.loads(json.dumps(np.where(np.isfinite(array), array, np.nan).tolist())
                      .replace("NaN", "null"))


# -- the page -------------------------------------------------------------------------------

def script_json(data: object) -> str:
    """JSON safe inside ``<script type="application/json">``: ``<``, ``>``, ``&`` and the
    line separators escaped, so no text of a model can close the element.

    Parameters
    ----------
    data : object
        JSON-ready data.

    Returns
    -------
    str

    Examples
    --------
    >>> script_json({"title": "</script><b>"})
    '{"title": "\\\\u003c/script\\\\u003e\\\\u003cb\\\\u003e"}'
    """
    text = json.dumps(data, ensure_ascii=False, allow_nan=False)
    for char, escape in (("<", "\\u003c"), (">", "\\u003e"), ("&", "\\u0026"),
                         ("\u2028", "\\u2028"), ("\u2029", "\\u2029")):
        text = text.replace(char, escape)
    return text


def _asset(name: str) -> str:
    return resources.files("resonant.views").joinpath("explore_assets", name) \
        .read_text(encoding="utf-8")


def page_html(data: dict[str, Any], program: str) -> str:
    """Fill the page's template with the model's data and program.

    Parameters
    ----------
    data : dict
        The page's data (JSON-ready).
    program : str
        The JavaScript functions printed from the model (may be empty).

    Returns
    -------
    str
        The HTML document.

    Examples
    --------
    >>> page_html({"title": "A & B"}, "").count("A &amp; B")
    1
    """
    pieces = {"@TITLE@": html.escape(data.get("title") or "resonant explore"),
              "@STYLE@": _asset("page.css"), "@DATA@": script_json(data),
              "@PROGRAM@": program.replace("</", "<\\/"),
              "@NUMERICS@": _asset("numerics.js"), "@UI@": _asset("page.js"),
              "@ROTOR@": _asset("rotor.js")}
    text = _asset("page.html")
    for marker, value in pieces.items():
        text = text.replace(marker, value)
    return text


def _exported(system: LinearSystem, motion: SketchMotion | None
              ) -> tuple[ExportedSystem | None, str]:
    """The live program, or None and why the page is precomputed."""
    if system.n > LIVE_LIMIT:
        return None, (f"This model has {system.n} coordinates; above {LIVE_LIMIT} the page "
                      "shows curves, modes and numbers precomputed by resonant at the file's "
                      "parameter values.")
    try:
        return export_system(system, motion), ""
    except NotPrintable as exc:
        return None, (f"The page cannot compute this model itself ({exc}); it shows curves, "
                      "modes and numbers precomputed by resonant at the file's parameter "
                      "values.")


def check_page_size(model: Model) -> None:
    """Refuse, before any work, a model too large for the page (see
    :data:`MAX_ENERGY_COORDINATES`).

    Parameters
    ----------
    model : Model

    Raises
    ------
    ModelError
        Naming the model's coordinates, the bound and what to do instead.
    AnalysisError
        For what the page cannot evaluate yet (a bearing coefficient tabulated in speed).

    Examples
    --------
    >>> import resonant
    >>> check_page_size(resonant.load("examples/absorber.toml"))  # 2 coordinates: fine
    """
    tabulated = [t.where for t in getattr(model.matrices, "speed_terms", ())
                 if isinstance(t.value, SpeedTable)]
    if tabulated:
        # the page's numerics evaluate expressions; a table interpolated in speed has no
        # printed form there yet, and the page would show no number at all
        raise AnalysisError(
            f"the explore page does not yet evaluate bearing coefficients tabulated in "
            f"speed ([rotor] {tabulated[0]}); give them as expressions of the speed, or use "
            "campbell and unbalance on this model")
    n = len(model.coordinates)
    if model.matrices is None and n > MAX_ENERGY_COORDINATES:
        raise ModelError(Problem(
            f"{n} coordinates are more than the explore page shows of a model given by its "
            f"energies (at most {MAX_ENERGY_COORDINATES}: its frequency response would need "
            f"about {2 * 3 * n * n * CURVE_POINTS * 16 / 2**30:.0f} GiB of memory); give "
            "the model by its matrices ([matrices]), or use modes and sweep on it",
            model.source, "coordinates"))


#: the most harmonics of a periodic load the page sums (a square wave to 1 % has 4053)
MAX_PAGE_HARMONICS = 20_000


def periodic_data(model: Model, system: LinearSystem, live: bool,
                  deadline: Deadline = NO_DEADLINE) -> dict[str, Any] | None:
    """What the page needs of the model's ``[periodic]`` load (None without one): its
    series (the page sums the response to it live, per harmonic, as ``resonant solve``
    does), or on a precomputed page the summed response at the file's values.

    Parameters
    ----------
    model : Model
    system : LinearSystem
    live : bool
        Whether the page computes itself.
    deadline : Deadline, optional

    Returns
    -------
    dict or None
        ``name``, ``derivative``, ``shape``, ``amplitude``, ``period``, ``tolerance``,
        ``harmonics``,
        ``a0``, ``a``, ``b`` (the series; ``a``/``b`` None when it has more than
        :data:`MAX_PAGE_HARMONICS` harmonics) and ``precomputed`` (``time``, ``history``,
        ``largest``; None on a live page).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/teaching/fourier_square.toml")
    >>> data = periodic_data(model, model.linearize(), True)
    >>> data["name"], data["harmonics"], round(data["b"][0], 6)
    ('x', 4053, 12.732395)
    """
    spec = model.periodic_section
    if spec is None:
        return None
    series = load_series(system, spec)
    summable = series.harmonics <= MAX_PAGE_HARMONICS
    data: dict[str, Any] = {
        "name": spec.signal, "derivative": spec.derivative, "shape": spec.shape,
        "amplitude": spec.amplitude,
        "period": series.period, "tolerance": spec.tolerance, "harmonics": series.harmonics,
        "a0": series.a0, "a": series.a.tolist() if summable else None,
        "b": series.b.tolist() if summable else None, "precomputed": None}
    if not live or not summable:
        result = periodic_response(system, spec.signal, series, derivative=spec.derivative,
                                   names=shown_names(model, system), deadline=deadline)
        step = max(1, result.time.size // CURVE_POINTS)
        data["precomputed"] = {
            "time": result.time[::step].tolist(),
            "history": {k: v[::step].tolist() for k, v in result.history.items()},
            "largest": dict(result.largest)}
    return data


#: the most stations whose orbits the rotor panel draws
ROTOR_STATIONS = 12
#: speeds of the bearing force chart at least, evenly over the slider's range (with the
#: slider's speeds and the critical speeds of order 1, where an unbalance peaks)
ROTOR_FORCE_POINTS = 400
#: a 1x critical speed joins the force chart's speeds where its mode's damping ratio is
#: above this (an undamped one is a singular solve)
DAMPED_PEAK = 1e-9
#: the most coordinates of a rotor whose damped critical speed map the page holds (dense
#: complex modes at every speed it tries: about 1.5 s for Friswell's 28 coordinates)
PAGE_DAMPED_MAP_COORDINATES = LIVE_LIMIT


def _complex_json(array: np.ndarray) -> dict[str, list[Any]]:
    """A complex array as its real and imaginary parts (NaN as null)."""
    return {"re": _finite(np.real(array)), "im": _finite(np.imag(array))}


def rotor_start(speeds: np.ndarray, value: float, critical: list[float],
                finite: np.ndarray) -> int:
    """The speed the rotor panel opens at (its index in ``speeds``): the file's speed
    where it is not 0, else the first critical speed in the range, else the middle of the
    range -- the speed nearest to it whose orbits are finite (an undamped rotor's orbit is
    unbounded at its critical speed).  At 0 rpm there is nothing to see: the unbalance
    force m e Omega^2 is zero.

    Parameters
    ----------
    speeds : ndarray
        The speeds the slider steps through (rad/s).
    value : float
        The speed parameter's value in the file (rad/s).
    critical : list of float
        The critical speeds in the range (rad/s), lowest first.
    finite : ndarray of bool
        Per speed, whether every orbit there is finite.

    Returns
    -------
    int

    Examples
    --------
    >>> speeds, finite = np.linspace(0.0, 100.0, 11), np.ones(11, bool)
    >>> rotor_start(speeds, 0.0, [41.0], finite), rotor_start(speeds, 0.0, [], finite)
    (4, 5)
    >>> rotor_start(speeds, 70.0, [41.0], finite), rotor_start(speeds, 0.0, [41.0], speeds != 40)
    (7, 5)
    """
    target = value if value != 0 else (critical[0] if critical else
                                       (speeds[0] + speeds[-1]) / 2)
    distance = np.where(finite, np.abs(speeds - target), np.inf)
    if not np.any(np.isfinite(distance)):
        distance = np.abs(speeds - target)
    return int(np.argmin(distance))


def _own_stiffness(bearings: tuple[Bearing, ...]) -> list[float]:
    """The bearings' direct stiffness values (kxx, kyy) given as numbers, each once."""
    return sorted({float(v) for b in bearings for key, v in b.coefficients
                   if key in ("kxx", "kyy") and isinstance(v, float) and v > 0})


def map_stiffness(own: list[float]) -> np.ndarray:
    """The stiffness values of the rotor panel's critical speed map: the range of
    ``resonant speed-map`` (:data:`resonant.analyses.rotor_map.MAP_STIFFNESS`), widened to a
    decade beyond the bearings' own direct stiffness where it lies outside, at the same
    number of values per decade.

    Parameters
    ----------
    own : list of float
        The bearings' own direct stiffness values (N/m).

    Returns
    -------
    ndarray

    Examples
    --------
    >>> map_stiffness([1e6])[[0, -1]].tolist(), map_stiffness([3e9]).size
    ([100000.0, 1000000000.0], 25)
    """
    low, high, count = MAP_STIFFNESS
    per_decade = (count - 1) / math.log10(high / low)
    if own:
        low = min(low, 10.0 ** (math.floor(math.log10(own[0])) - 1))
        high = max(high, 10.0 ** (math.ceil(math.log10(own[-1])) + 1))
    return np.geomspace(low, high, round(per_decade * math.log10(high / low)) + 1)


def _damped_bearings(bearings: tuple[Bearing, ...]) -> bool:
    """Whether a bearing has damping or cross-coupled stiffness (what the damped map keeps)."""
    return any(key not in ("kxx", "kyy") for b in bearings for key, _ in b.coefficients)


def _map_json(result: CriticalSpeedMap) -> dict[str, Any]:
    ratios = result.damping_ratios
    return {"stiffness": result.stiffness.tolist(), "orders": list(result.orders),
            "speeds": _finite(result.speeds),
            "whirl": [[list(row) for row in block] for block in result.whirl],
            "damping_ratios": _finite(ratios) if ratios is not None else None,
            "chart": result.chart().to_dict()}


def map_data(model: Model, system: LinearSystem, orders: tuple[float, ...],
             deadline: Deadline = NO_DEADLINE) -> dict[str, Any] | None:
    """The rotor panel's critical speed maps (None without a ``[rotor]`` with bearings):
    the undamped map (:func:`resonant.analyses.rotor_map.critical_speed_map`) over
    :func:`map_stiffness` for the Campbell diagram's orders and, where a bearing has damping
    or cross-coupled stiffness and the rotor at most :data:`PAGE_DAMPED_MAP_COORDINATES`
    coordinates, the damped map too; each with its chart as resonant draws it (``chart``,
    rpm against N/m).  Where a map cannot be solved, ``note`` says why.

    Parameters
    ----------
    model : Model
    system : LinearSystem
    orders : tuple of float
        The excitation orders.
    deadline : Deadline, optional

    Returns
    -------
    dict or None
        ``own`` (the bearings' own direct stiffness, N/m), ``undamped`` and ``damped``
        (each None or ``stiffness`` (N/m), ``orders``, ``speeds`` (rad/s; stiffness,
        orders, modes), ``whirl``, ``damping_ratios`` (None undamped) and ``chart``
        (``Chart.to_dict()``)) and ``note``.

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/rotors/friswell_5_9_1.toml")
    >>> data = map_data(model, model.linearize(), (1.0,))
    >>> data["own"], len(data["undamped"]["stiffness"]), data["damped"]
    ([1000000.0], 17, None)
    """
    bearings = system.bearings
    if not bearings:
        return None
    own = _own_stiffness(bearings)
    stiffness = map_stiffness(own)
    out: dict[str, Any] = {"own": own, "undamped": None, "damped": None, "note": ""}
    notes = []
    try:
        out["undamped"] = _map_json(critical_speed_map(system, stiffness, modes=MAP_MODES,
                                                       orders=orders, deadline=deadline))
    except ModelError as exc:
        notes.append(f"no undamped critical speed map: {exc.problems[0].message}")
    if _damped_bearings(bearings):
        if system.n > PAGE_DAMPED_MAP_COORDINATES:
            notes.append(f"no damped critical speed map on the page above "
                         f"{PAGE_DAMPED_MAP_COORDINATES} coordinates (resonant speed-map "
                         "--damped gives it)")
        else:
            try:
                out["damped"] = _map_json(critical_speed_map(
                    system, stiffness, modes=MAP_MODES, orders=orders, damped=True,
                    deadline=deadline))
            except ModelError as exc:
                notes.append(f"no damped critical speed map: {exc.problems[0].message}")
    out["note"] = "; ".join(notes)
    return out


def _force_curve(system: LinearSystem, result: Campbell, deadline: Deadline
                 ) -> dict[str, Any]:
    """The bearing force chart's curve: the major semi-axis (0-pk, N) of each bearing's
    force on a grid finer than the slider's (:data:`ROTOR_FORCE_POINTS`, the slider's
    speeds and the 1x critical speeds of damped modes), so that a lightly damped peak
    between two of the slider's speeds is drawn."""
    speeds = result.speeds
    zeta = np.asarray(result.damping_ratios)
    # an undamped mode's critical speed is a singular solve (no finite peak to draw)
    critical = [c.speed for c in result.critical_speeds if c.order == 1 and
                zeta[int(np.argmin(np.abs(speeds - c.speed))), c.mode - 1] > DAMPED_PEAK]
    grid = np.unique(np.concatenate([
        speeds, np.linspace(speeds[0], speeds[-1], ROTOR_FORCE_POINTS), critical]))
    response = unbalance_response(system, grid, deadline=deadline)
    return {"speeds": grid.tolist(),
            "major": _finite(np.asarray(response.bearing_force).T)}


def rotor_data(model: Model, system: LinearSystem, deadline: Deadline = NO_DEADLINE
               ) -> dict[str, Any] | None:
    """The rotor panel's data (None without a ``[campbell]`` section): the Campbell diagram
    over its range (:func:`resonant.analyses.campbell.campbell`: each branch's damped
    frequency, damping ratio and whirl at every speed, the critical speeds and the
    threshold); with ``[[unbalance]]``, the unbalance orbits at the same speeds
    (:func:`resonant.analyses.unbalance.unbalance_response`, complex amplitudes X, Y of
    each station, 0-pk) and the forces each bearing transmits there (complex amplitudes of
    their x and y components), which the page's speed slider steps through; and the
    critical speed map (:func:`map_data`).

    Parameters
    ----------
    model : Model
    system : LinearSystem
    deadline : Deadline, optional

    Returns
    -------
    dict or None
        JSON-ready: ``speed_parameter``, ``speeds`` (rad/s), ``frequencies``,
        ``damping_ratios``, ``whirl``, ``motion``, ``orders``, ``critical``, ``threshold``,
        ``start`` (the index of the speed the slider starts at, :func:`rotor_start`),
        ``orbits`` (``stations``, ``X``, ``Y``; None without ``[[unbalance]]``),
        ``forces`` (``bearings``, ``FX``, ``FY``, N; None without ``[[unbalance]]`` or
        bearings) and ``map`` (:func:`map_data`).

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/rotors/jeffcott_rotor.toml")
    >>> data = rotor_data(model, model.linearize())
    >>> len(data["speeds"]), data["orbits"]["stations"], data["threshold"]["verdict"]
    (49, [''], 'threshold')
    """
    spec = model.campbell_section
    if spec is None:
        return None
    result = campbell(system, deadline=deadline)
    speeds = result.speeds
    name = result.speed_parameter
    value = float(model.parameter_values.get(name, speeds[0]))
    orbits = forces = None
    finite = np.ones(len(speeds), bool)
    if model.unbalances:
        response = unbalance_response(system, speeds, deadline=deadline)
        keep = slice(0, ROTOR_STATIONS)
        index = {q: i for i, q in enumerate(system.coordinates)}
        s, c = unbalance_columns(response.unbalances, system.coordinates)
        orbits = {"stations": list(response.stations[keep]),
                  "X": _complex_json(response.X[:, keep]),
                  "Y": _complex_json(response.Y[:, keep]),
                  "amount": [u.amount for u in response.unbalances],
                  "at": [u.station for u in response.unbalances],
                  # what the page solves at the sliders' values: the rows of each station's
                  # x, y and the load per Omega^2 (F = Omega^2 (c - i s))
                  "rows": [[index[f"{st}_x" if st else "x"], index[f"{st}_y" if st else "y"]]
                           for st in response.stations[keep]],
                  "load": {"s": s.tolist(), "c": c.tolist()}}
        finite = np.all(np.isfinite(response.X) & np.isfinite(response.Y), axis=1)
        if response.bearings:
            bearings = model.matrices.bearings if model.matrices is not None else ()
            forces = {"bearings": list(response.bearings),
                      "FX": _complex_json(response.bearing_forces[..., 0]),
                      "FY": _complex_json(response.bearing_forces[..., 1]),
                      "curve": _force_curve(system, result, deadline),
                      "station": [list(b.station) for b in bearings],
                      "pedestal": [list(b.pedestal) if b.pedestal is not None else None
                                   for b in bearings]}
    threshold = result.threshold
    critical = [c.speed for c in result.critical_speeds]
    return {"speed_parameter": name, "rpm": RPM, "speeds": speeds.tolist(),
            "frequencies": _finite(result.frequencies),
            "damping_ratios": _finite(result.damping_ratios),
            "whirl": [list(row) for row in result.whirl], "motion": list(result.motion),
            "orders": list(result.orders),
            "critical": [{"speed": c.speed, "order": c.order, "mode": c.mode,
                          "whirl": c.whirl} for c in result.critical_speeds],
            "threshold": {"speed": threshold.speed, "verdict": threshold.verdict,
                          "mode": threshold.mode, "whirl": threshold.whirl},
            "start": rotor_start(speeds, value, sorted(critical), finite),
            "orbits": orbits, "forces": forces,
            "map": map_data(model, system, tuple(result.orders), deadline),
            "warnings": list(result.warnings)}


def explore_data(model: Model, system: LinearSystem | None = None,
                 deadline: Deadline = NO_DEADLINE, measured: MatchedTest | None = None
                 ) -> tuple[dict[str, Any], str]:
    """Everything the explore page of a model holds: its data and its program.

    Parameters
    ----------
    model : Model
    system : LinearSystem, optional
        The model's linear system (derived if not given).
    deadline : Deadline, optional
    measured : MatchedTest, optional
        Measured FRFs checked against the model, drawn over the frequency response
        (:func:`resonant.views.explore_measured.measured_overlay`).

    Returns
    -------
    tuple
        (data, JavaScript program); the program is empty for a precomputed page.

    Examples
    --------
    >>> import resonant
    >>> data, program = explore_data(resonant.load("examples/parts/pendulum.toml"))
    >>> data["live"], data["drawing"]["owners"], data["frequency"]
    (True, ['pivot', 'bob'], 'omega')
    """
    check_page_size(model)
    system = system if system is not None else linear_system(model, deadline)
    motion = sketch_motion(model) if model.parts is not None and (
        model.parts.parts.bodies or model.parts.parts.points) else None
    exported, note = _exported(system, motion)
    frequency = frequency_parameter(model, system)
    sliders = controls(model, system, frequency, deadline)
    names = [*system.coordinates, *model.outputs]
    shown = [n for n in shown_names(model, system) if n in names]
    if measured is not None:
        shown = measured_first(measured, model, shown, DEFAULT_SHOWN)
    data: dict[str, Any] = {
        "title": model.title, "file": Path(model.source).name, "live": exported is not None,
        "has_units": model.units is not None,
        "note": note, "coordinates": _name_units(model, list(system.coordinates)),
        "outputs": _name_units(model, list(model.outputs)), "parameters": sliders,
        "frequency": frequency, "show": shown, "equilibrium": equilibrium_values(model)
        if model.matrices is None else [0.0] * system.n,
        "layout": exported.layout if exported is not None else None,
        "drawing": _drawing(motion) if motion is not None and exported is not None else None,
        "precomputed": None}
    data["periodic"] = periodic_data(model, system, exported is not None, deadline)
    if exported is None:
        control = next((c for c in sliders if c["frequency"]), None)
        data["precomputed"] = precomputed(system, frequency, control, shown, deadline)
    data["response_chart"] = _response_chart(model, system, sliders, names)
    data["rotor"] = rotor_data(model, system, deadline)
    data["measured"] = measured_overlay(measured, model, system, frequency, deadline) \
        if measured is not None else None
    return data, exported.program if exported is not None else ""


def explore_page(model: Model, system: LinearSystem | None = None,
                 deadline: Deadline = NO_DEADLINE, measured: MatchedTest | None = None
                 ) -> ExplorePage:
    """The explore page of a model (``resonant explore``, ``model.explore()``).

    Parameters
    ----------
    model : Model
    system : LinearSystem, optional
        The model's linear system (derived if not given).
    deadline : Deadline, optional
    measured : MatchedTest, optional
        Measured FRFs checked against the model
        (:func:`resonant.analyses.measured_match.match_test`): drawn as points over the
        frequency response (``resonant explore --test FILE``).

    Returns
    -------
    ExplorePage

    Raises
    ------
    ModelError
        If the model cannot be derived.
    AnalysisError
        If a precomputed page's analyses are impossible.

    Examples
    --------
    >>> import resonant
    >>> page = explore_page(resonant.load("examples/absorber.toml"))
    >>> page.live, len(page.html) < 1_500_000
    (True, True)
    """
    data, program = explore_data(model, system, deadline, measured)
    note = data["measured"]["note"] if data.get("measured") else None
    return ExplorePage(page_html(data, program), model.title, bool(data["live"]),
                       (f"--test: {note}",) if note else ())


__all__ = ["ExplorePage", "check_page_size", "explore_page", "explore_data", "controls",
           "default_range",
           "frequency_parameter", "shown_names", "precomputed", "page_html", "script_json",
           "rotor_data", "rotor_start", "map_stiffness", "map_data",
           "LIVE_LIMIT", "CURVE_POINTS"]
