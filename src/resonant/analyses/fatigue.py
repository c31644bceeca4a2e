"""Fatigue damage from a stress spectral density or a stress time series.

The field's libraries do the counting and the spectral estimates; this module wires them
to resonant's results and fixes the conventions:

* **S-N curve** N S^k = C with S the stress **amplitude** (half the range), in the units
  of the stress (SI: Pa).  :class:`SNCurve` also reads a curve given for ranges
  (C_amplitude = C_range / 2^k) or by one point (S_ref at N_ref cycles: C = N_ref S_ref^k).
* **Spectral methods** from a one-sided stress density per Hz (a
  :class:`~resonant.analyses.random_response.RandomResponse`'s ``psd``): narrow-band
  (Miles/Bendat: Rayleigh amplitudes at the zero up-crossing rate), Dirlik (1985) and
  Tovo-Benasciutti (2005, "method 2"), computed by FLife (Zorman, Slavic, Boltezar et al.,
  https://github.com/ladisk/FLife), which implements these and a dozen more estimators with
  its own tests; resonant does not re-derive them.  FLife integrates the spectral moments
  by the trapezoidal rule on the density's own frequencies.
* **Time series**: rainflow counting (ASTM E1049-85 (2017), 5.4.4) by the ``rainflow``
  package, half cycles counted as 0.5, and Palmgren-Miner's sum D = sum n_i / N(S_i).

FLife and rainflow are optional (``pip install resonant[fatigue]``) and imported only
here, when a damage is computed.

Examples
--------
>>> import numpy as np
>>> sn = SNCurve(C=1e12, k=3.0)
>>> t = np.linspace(0, 10, 10001)
>>> round(rainflow_damage(100 * np.cos(2 * np.pi * t), sn).damage, 12)   # 10 cycles
1e-05
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import freeze_fields
from ..charts import (
    COLORS,
    Bar,
    Chart,
    Charted,
    Charts,
    PathArg,
    check_plot_path,
    draw_figure,
    save_figure,
)
from ..errors import AnalysisError, name_list, printable
from ..model.load_spec import FATIGUE_METHODS
from ..model.units_display import ResultUnits, Shown, shown_unit
from ..tables import ResultTable, number_cell
from .result_fields import FieldsJSON, Framed, saved
from .results_json import Saved

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .random_response import RandomResponse

#: the spectral methods (FLife's Narrowband, Dirlik, TovoBenasciutti)
METHODS = FATIGUE_METHODS


@dataclass(frozen=True)
class SNCurve(FieldsJSON):
    """An S-N curve N S^k = C, S the stress amplitude.

    Parameters
    ----------
    C : float
        The intercept (stress^k).
    k : float
        The inverse slope (positive).

    Examples
    --------
    >>> SNCurve.from_range(8e12, 3).C                        # 8e12 / 2^3
    1000000000000.0
    >>> SNCurve.from_point(100.0, 2e6, 5).C == 2e6 * 100.0**5
    True
    """

    C: float
    k: float

    def _derived_json(self) -> dict[str, Any]:
        return {"stress": "amplitude"}

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        if reader.string("stress", "amplitude") != "amplitude":
            raise reader.error("is not of stress amplitudes", "stress")

    def __post_init__(self) -> None:
        if not (math.isfinite(self.C) and self.C > 0 and math.isfinite(self.k) and self.k > 0):
            raise AnalysisError(f"an S-N curve needs C > 0 and k > 0 (got C = {self.C:g}, "
                                f"k = {self.k:g})")

    @classmethod
    def from_range(cls, C: float, k: float) -> SNCurve:
        """The curve N S_range^k = C, as an amplitude curve.

        Parameters
        ----------
        C, k : float

        Returns
        -------
        SNCurve
        """
        return cls(C / 2.0**k, k)

    @classmethod
    def from_point(cls, amplitude: float, cycles: float, k: float) -> SNCurve:
        """The curve through ``cycles`` at the stress ``amplitude`` with inverse slope k.

        Parameters
        ----------
        amplitude, cycles, k : float

        Returns
        -------
        SNCurve
        """
        return cls(cycles * amplitude**k, k)

    def cycles(self, amplitude: np.ndarray | float) -> Any:
        """The cycles to failure at a stress amplitude."""
        return self.C / np.asarray(amplitude, dtype=float) ** self.k


@dataclass(frozen=True)
class SpectralFatigue(FieldsJSON):
    """Damage intensities and lives of one stress density by the spectral methods.

    Attributes
    ----------
    damage_rate : mapping
        method -> damage per second.
    life : mapping
        method -> seconds to failure (1 / damage rate).
    damage : mapping or None
        method -> damage over ``duration`` (None without one).
    duration : float or None
        The exposure (s).
    rms : float
        The stress RMS (sqrt m0).
    zero_crossing_rate, peak_rate : float
        Rice's rates (Hz) from the same moments.
    irregularity : float
        alpha_2 = m2 / sqrt(m0 m4).
    """

    damage_rate: dict[str, float] = saved(key="damage_rate_per_s")
    life: dict[str, float] = saved(key="life_s")
    damage: dict[str, float] | None = saved()
    duration: float | None = saved(key="duration_s")
    rms: float = saved()
    zero_crossing_rate: float = saved(key="zero_crossing_rate_hz")
    peak_rate: float = saved(key="peak_rate_hz")
    irregularity: float = saved()
    sn: SNCurve = saved(SNCurve(1.0, 1.0), key="sn_curve")

def _flife() -> Any:
    try:
        import FLife
    except ImportError:  # pragma: no cover - the extra is installed in the tests
        raise AnalysisError("the spectral fatigue methods need FLife: pip install "
                            "'resonant[fatigue]'") from None
    return FLife


def spectral_fatigue(frequency: Sequence[float] | np.ndarray,
                     psd: Sequence[float] | np.ndarray, sn: SNCurve,
                     duration: float | None = None,
                     methods: Sequence[str] = METHODS) -> SpectralFatigue:
    """Fatigue damage of a Gaussian stress with a one-sided density per Hz (FLife).

    Parameters
    ----------
    frequency : array_like
        Frequencies (Hz), increasing.
    psd : array_like
        The stress's one-sided density per Hz (stress^2/Hz) at those frequencies.
    sn : SNCurve
        The S-N curve (amplitudes).
    duration : float, optional
        The exposure (s): the damage over it is reported too.
    methods : sequence of str
        Some of :data:`METHODS`.

    Returns
    -------
    SpectralFatigue

    Raises
    ------
    AnalysisError
        For a density that is not finite, negative or zero, an unknown method, or without
        FLife.

    Examples
    --------
    >>> f = np.linspace(90, 110, 201)
    >>> result = spectral_fatigue(f, np.full(201, 50.0), SNCurve(1e20, 4.0), 3600.0)
    >>> sorted(result.life)
    ['dirlik', 'narrowband', 'tovo-benasciutti']
    """
    f = np.asarray(frequency, dtype=float).ravel()
    G = np.asarray(psd, dtype=float).ravel()
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise AnalysisError(f"unknown fatigue method '{unknown[0]}'; one of {', '.join(METHODS)}")
    if f.shape != G.shape or len(f) < 3 or not np.isfinite(f).all() or \
            not np.isfinite(G).all() or (np.diff(f) <= 0).any() or (f < 0).any():
        raise AnalysisError("the stress density needs at least three increasing, finite, "
                            "non-negative frequencies and as many finite values")
    if (G < 0).any() or not G.any():
        raise AnalysisError("the stress density must be non-negative and not zero everywhere")
    if duration is not None and not (math.isfinite(duration) and duration > 0):
        raise AnalysisError(f"the duration {duration:g} s must be positive")
    FLife = _flife()
    data = FLife.SpectralData(input={"PSD": G, "f": f})
    estimators = {"narrowband": lambda: FLife.Narrowband(data).get_life(sn.C, sn.k),
                  "dirlik": lambda: FLife.Dirlik(data).get_life(sn.C, sn.k),
                  "tovo-benasciutti": lambda: FLife.TovoBenasciutti(data).get_life(
                      sn.C, sn.k, method="method 2")}
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)   # FLife's overflows: checked below
        life = {m: float(estimators[m]()) for m in methods}
    lost = [m for m, v in life.items() if not (math.isfinite(v) and v > 0)]
    if lost:
        raise AnalysisError(
            f"the {lost[0]} estimate of the fatigue life has no digit left in double precision "
            f"(it came out as {life[lost[0]]:g} s): the stress amplitudes raised to k = {sn.k:g} "
            f"against C = {sn.C:g} leave the floating-point range; an S-N curve's k is usually "
            "3 to 20 and C the cycles to failure at a unit stress amplitude, in the stress's "
            "unit (check both, and the unit of the stress)")
    rate = {m: 1.0 / v for m, v in life.items()}
    m0, m2, m4 = (float(np.trapezoid(f**i * G, f)) for i in (0, 2, 4))
    return SpectralFatigue(rate, life,
                           None if duration is None else {m: r * duration
                                                          for m, r in rate.items()},
                           duration, math.sqrt(m0), math.sqrt(m2 / m0), math.sqrt(m4 / m2),
                           m2 / math.sqrt(m0 * m4), sn)


@dataclass(frozen=True)
class ResponseFatigue(FieldsJSON, Charted):
    """The fatigue of a model's stress responses under its ``[random]`` inputs: for each
    response, its :class:`SpectralFatigue` by every method asked for.

    Attributes
    ----------
    names : tuple of str
        The responses (stress outputs), in order.
    results : mapping
        name -> :class:`SpectralFatigue` of that response's density.
    units : mapping
        name -> the response's SI unit ("" where the model has no units).
    method : str
        The method the model's ``[fatigue]`` section chose (the study's ``damage:NAME``).
    warnings : tuple of str
        What the random response and the fatigue estimates warned of.

    Examples
    --------
    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`, the JSON of
    ``resonant fatigue``) and read back:

    >>> import json
    >>> f = np.linspace(90, 110, 201)
    >>> one = spectral_fatigue(f, np.full(201, 50.0), SNCurve(1e20, 4.0), 3600.0)
    >>> result = ResponseFatigue(("s",), {"s": one}, {"s": "Pa"}, "dirlik")
    >>> ResponseFatigue.from_dict(json.loads(json.dumps(result.to_dict()))) == result
    True
    """

    names: tuple[str, ...]
    results: Mapping[str, SpectralFatigue]
    units: Mapping[str, str]
    method: str
    warnings: tuple[str, ...] = ()

    def table(self, units: ResultUnits | None = None) -> ResultTable:
        """Each response's RMS, and its damage and life by each method (:func:`fatigue_table`).

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units MPa``; default SI).

        Returns
        -------
        resonant.tables.ResultTable
        """
        return fatigue_table(self, units)

    def summary(self, units: ResultUnits | None = None) -> str:
        """The text ``resonant fatigue`` prints (:func:`fatigue_text`).

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units MPa``; default SI).

        Returns
        -------
        str
        """
        return fatigue_text(self, units=units)

    def chart(self) -> Charts:
        """The figure's description (:func:`fatigue_chart`).

        Returns
        -------
        resonant.charts.Charts
        """
        return fatigue_chart(self)


def response_fatigue(response: RandomResponse, sn: SNCurve, duration: float, *,
                     names: Sequence[str] | None = None, methods: Sequence[str] = METHODS,
                     method: str = "dirlik") -> ResponseFatigue:
    """The fatigue damage over ``duration`` of the responses of a random response, from
    their densities by the spectral methods (:func:`spectral_fatigue`).

    Parameters
    ----------
    response : RandomResponse
        The model's random response (its densities of the stress outputs).
    sn : SNCurve
        The S-N curve, in the responses' units (SI: Pa).
    duration : float
        The exposure (s).
    names : sequence of str, optional
        The responses (default every response of ``response``).
    methods : sequence of str
        Some of :data:`METHODS`.
    method : str
        The model's chosen method (reported as such; it is computed whether or not it is
        in ``methods``).

    Returns
    -------
    ResponseFatigue

    Raises
    ------
    AnalysisError
        For a name that is not a response of ``response``, a response with no density
        (zero everywhere), or as :func:`spectral_fatigue`.

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/bracket_fatigue.toml")
    >>> from resonant.analyses.random_response import random_response
    >>> response = random_response(model.linearize(), names=["stress"])
    >>> spec = model.fatigue_section
    >>> result = response_fatigue(response, SNCurve(spec.C, spec.k), spec.duration)
    >>> 0.02 < result.results["stress"].damage["dirlik"] < 0.04
    True
    """
    chosen = list(response.names if names is None else names)
    missing = [n for n in chosen if n not in response.psd]
    if missing:
        raise AnalysisError(f"'{printable(missing[0], limit=40)}' is not a response of the "
                            f"random response (of {name_list(response.names, 20)})")
    wanted = list(dict.fromkeys([*methods, method]))
    results, warned = {}, list(response.warnings)
    for name in chosen:
        unit = response.units.get(name, "")
        if unit and unit != "Pa":
            warned.append(f"{printable(name, limit=40)} is in {unit}, not a stress (Pa): the "
                          "S-N curve is applied to it as given")
        psd = np.asarray(response.psd[name])
        if not psd.any():
            raise AnalysisError(f"{printable(name, limit=40)} does not respond to the "
                                "[random] inputs (its density is zero): it has no fatigue "
                                "damage to estimate; choose a stress that the inputs load")
        results[name] = spectral_fatigue(response.frequency, psd, sn, duration, wanted)
    return ResponseFatigue(tuple(chosen), results,
                           {n: response.units.get(n, "") for n in chosen}, method,
                           tuple(dict.fromkeys(warned)))


def fatigue_table(result: ResponseFatigue, units: ResultUnits | None = None) -> ResultTable:
    """Each response's RMS, and its damage over the exposure and its life by each method
    (the model's method marked ``*``).

    Parameters
    ----------
    result : ResponseFatigue
    units : ResultUnits, optional
        The display units of the RMS (``--units MPa``; default SI).

    Returns
    -------
    resonant.tables.ResultTable
    """
    rows = []
    for name in result.names:
        one = result.results[name]
        shown = shown_unit(units, result.units.get(name, ""))
        for m in one.life:
            damage = None if one.damage is None else one.damage[m]
            rows.append((printable(name, limit=40), shown.text or "SI",
                         number_cell(shown(one.rms)), m + (" *" if m == result.method else ""),
                         number_cell(damage), number_cell(one.life[m]),
                         number_cell(one.life[m] / 3600)))
    return ResultTable(("name", "unit", "RMS", "method", "damage", "life [s]", "life [h]"),
                       tuple(rows), align="llrlrrr")


def fatigue_text(result: ResponseFatigue, warnings: bool = True,
                 units: ResultUnits | None = None) -> str:
    """The fatigue damage of a model's stress responses as text: the S-N curve and the
    exposure, the table (:func:`fatigue_table`), the warnings.

    Parameters
    ----------
    result : ResponseFatigue
    warnings : bool
        End with the result's warnings (the command line writes them to standard error).
    units : ResultUnits, optional
        The display units (``--units MPa``: the RMS and the S-N curve's S; default SI).

    Returns
    -------
    str
    """
    first = result.results[result.names[0]] if result.names else None
    lines = ["Fatigue under the [random] inputs (spectral methods, FLife)"]
    if first is not None:
        shown = shown_unit(units, result.units.get(result.names[0], ""))
        # N S^k = C with S = factor S': N S'^k = C / factor^k
        C = first.sn.C / shown.factor ** first.sn.k
        lines.append(f"  S-N curve N S^{first.sn.k:g} = {C:.4g} (S the stress amplitude"
                     + (f" in {shown.text}" if shown.text else "") + "); exposure "
                     f"{first.duration or 0:.4g} s; * the [fatigue] section's method")
    lines.append(fatigue_table(result, units).text())
    lines += [f"warning: {w}" for w in result.warnings] if warnings else []
    return "\n".join(lines) + "\n"


def fatigue_chart(result: ResponseFatigue) -> Charts:
    """What the figure of the fatigue damage shows: each response's damage over the
    exposure by method, as bars (one panel per response).

    Parameters
    ----------
    result : ResponseFatigue

    Returns
    -------
    Charts
    """
    panels = []
    for name in result.names:
        one = result.results[name]
        methods = list(one.life)
        damage = [float(one.damage[m]) if one.damage is not None else math.nan
                  for m in methods]
        x = np.arange(len(methods), dtype=float)
        panels.append(Chart((), "spectral method",
                            f"Miner's damage over {one.duration or 0:g} s", (-0.6, x[-1] + 0.6),
                            title=f"fatigue of {printable(name, limit=40)} (RMS "
                                  f"{one.rms:.3g} {result.units.get(name, '') or 'SI'})",
                            legend="none",
                            bars=(Bar(x, np.array(damage), tuple(COLORS[:len(methods)])),),
                            xticks=tuple(zip(x.tolist(), methods))))
    return Charts(tuple(panels), size=(7.0, 3.2 * max(1, len(panels))), sharex=False)


@dataclass(frozen=True)
class RainflowDamage(Framed, FieldsJSON, Charted):
    """Rainflow cycles of a stress history and Miner's damage.

    Attributes
    ----------
    ranges : ndarray
        The stress ranges of the counted cycles.
    counts : ndarray
        Their counts (0.5 for a half cycle).
    damage : float
        Miner's sum over the history.
    sn : SNCurve
    """

    #: the columns of to_frame() (resonant.analyses.result_fields.Framed)
    _frame = (("ranges", "range"), ("counts", "count"))

    ranges: np.ndarray
    counts: np.ndarray = saved(axes=("ranges",))
    damage: float = saved()
    sn: SNCurve = saved(key="sn_curve")
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        freeze_fields(self)

    def life(self, duration: float) -> float:
        """The time to failure when the history, ``duration`` seconds long, repeats
        (duration / damage; infinite without damage).

        Parameters
        ----------
        duration : float
            The history's length (s).

        Returns
        -------
        float

        Examples
        --------
        >>> result = rainflow_damage([0.0, 100.0, -100.0, 0.0], SNCurve(1e12, 3.0))
        >>> result.life(2.0) == 2.0 / result.damage
        True
        """
        return duration / self.damage if self.damage > 0 else math.inf

    def table(self, unit: str | Shown = "") -> ResultTable:
        """The counted cycles by range (:data:`RANGE_BINS` bins at most): the cycles, the
        damage and its share.

        Parameters
        ----------
        unit : str or Shown
            The stress's unit, for the headings (a :class:`Shown` also converts).

        Returns
        -------
        resonant.tables.ResultTable
        """
        return rainflow_table(self, unit)

    def summary(self, unit: str | Shown = "", duration: float | None = None) -> str:
        """The text ``resonant fatigue --csv`` prints (:func:`rainflow_text`).

        Parameters
        ----------
        unit : str or Shown
            The stress's unit (a :class:`Shown` also converts from SI).
        duration : float, optional
            The history's length (s): the life is given too.

        Returns
        -------
        str
        """
        return rainflow_text(self, unit, duration)

    def chart(self, unit: str | Shown = "") -> Charts:
        """The figure's description (:func:`rainflow_chart`).

        Parameters
        ----------
        unit : str or Shown
            The stress's unit, for the labels (a :class:`Shown` also converts).

        Returns
        -------
        resonant.charts.Charts
        """
        return rainflow_chart(self, unit)

    def plot(self, path: PathArg = None, ax: Axes | Sequence[Axes] | None = None,
             unit: str | Shown = "") -> Figure:
        """Draw :meth:`chart` (the stress in ``unit``) and write it to ``path`` where given.

        Parameters
        ----------
        path : str or PathLike, optional
        ax : matplotlib Axes or sequence of them, optional
        unit : str or Shown
            The stress's unit (a :class:`Shown` also converts the ranges from SI).

        Returns
        -------
        matplotlib.figure.Figure
        """
        check_plot_path(path)
        return save_figure(draw_figure(self.chart(unit), ax), path)


def rainflow_damage(stress: Sequence[float] | np.ndarray, sn: SNCurve) -> RainflowDamage:
    """Rainflow counting (ASTM E1049) and Palmgren-Miner's damage of a stress history.

    Parameters
    ----------
    stress : array_like
        The stress samples (the turning points are found by the counter).
    sn : SNCurve
        The S-N curve (amplitudes: a cycle of range r counts n / N(r / 2)).

    Returns
    -------
    RainflowDamage

    Raises
    ------
    AnalysisError
        For a history with fewer than two finite samples, or without ``rainflow``.
    """
    x = np.asarray(stress, dtype=float).ravel()
    if len(x) < 2 or not np.isfinite(x).all():
        raise AnalysisError("the stress history needs at least two finite samples")
    try:
        import rainflow
    except ImportError:  # pragma: no cover - the extra is installed in the tests
        raise AnalysisError("rainflow counting needs the package rainflow: pip install "
                            "'resonant[fatigue]'") from None
    cycles = list(rainflow.count_cycles(x))
    ranges = np.array([r for r, _ in cycles], dtype=float)
    counts = np.array([n for _, n in cycles], dtype=float)
    with np.errstate(all="ignore"):
        damage = float(np.sum(counts / sn.cycles(ranges / 2))) if len(ranges) else 0.0
    if not math.isfinite(damage):
        raise AnalysisError(
            f"Miner's damage has no digit left in double precision: the stress ranges (up to "
            f"{ranges.max():.3g}) raised to k = {sn.k:g} against C = {sn.C:g} leave the "
            "floating-point range; check the S-N curve and the unit of the stress")
    return RainflowDamage(ranges, counts, damage, sn)


#: most range bins in the table and the chart of a rainflow count
RANGE_BINS = 12


def _range_bins(result: RainflowDamage) -> list[tuple[float, float, float, float]]:
    """(low, high, cycles, damage) of equal range bins from 0 to the largest range."""
    if not len(result.ranges):
        return []
    top = float(result.ranges.max())
    edges = np.linspace(0.0, top if top > 0 else 1.0, RANGE_BINS + 1)
    index = np.clip(np.searchsorted(edges, result.ranges, side="right") - 1, 0, RANGE_BINS - 1)
    with np.errstate(all="ignore"):
        each = result.counts / result.sn.cycles(result.ranges / 2)
    return [(float(edges[b]), float(edges[b + 1]), float(result.counts[index == b].sum()),
             float(each[index == b].sum())) for b in range(RANGE_BINS)
            if (index == b).any()]


def _stress_unit(unit: str | Shown) -> Shown:
    """The display unit of a history's stress: a :class:`Shown` converts the SI (Pa)
    numbers (``ResultUnits.of("Pa")``, ``--units MPa``), a text only labels them."""
    return unit if isinstance(unit, Shown) else Shown(unit)


def rainflow_table(result: RainflowDamage, unit: str | Shown = "") -> ResultTable:
    """A rainflow count by range bin: the bin, its cycles (half cycles 0.5), their damage
    and its share of the whole.

    Parameters
    ----------
    result : RainflowDamage
    unit : str or Shown
        The stress's unit, for the headings; a :class:`Shown` (``MPa``) also converts
        the ranges from SI.

    Returns
    -------
    resonant.tables.ResultTable

    Examples
    --------
    >>> result = rainflow_damage([0.0, 100.0, -100.0, 0.0], SNCurve(1e12, 3.0))
    >>> print(rainflow_table(result, "Pa").text())
      range [Pa]  cycles    damage  share
       100-116.7       1  1.25e-07    20%
       183.3-200     0.5     5e-07    80%
    """
    shown = _stress_unit(unit)
    suffix = f" [{printable(shown.text, limit=20)}]" if shown.text else ""
    rows = tuple((f"{number_cell(shown(low))}-{number_cell(shown(high))}", number_cell(cycles),
                  number_cell(damage, 3),
                  f"{100 * damage / result.damage:.3g}%" if result.damage > 0 else "-")
                 for low, high, cycles, damage in _range_bins(result))
    return ResultTable((f"range{suffix}", "cycles", "damage", "share"), rows, align="rrrr")


#: what the text calls the stress's unit where none is known (a history without units)
THE_STRESS_UNIT = "the stress's unit"


def rainflow_text(result: RainflowDamage, unit: str | Shown = "",
                  duration: float | None = None, warnings: bool = True) -> str:
    """A rainflow count and Miner's damage as text: the S-N curve, the damage (and the
    life where the history's length is given), the cycles by range.

    Parameters
    ----------
    result : RainflowDamage
    unit : str or Shown
        The stress's unit; a :class:`Shown` (``MPa``) also converts the ranges and the
        S-N curve's C from SI.
    duration : float, optional
        The history's length (s).
    warnings : bool
        End with the result's warnings (the command line writes them to standard error).

    Returns
    -------
    str

    Examples
    --------
    >>> result = rainflow_damage([0.0, 100.0, -100.0, 0.0], SNCurve(1e12, 3.0))
    >>> print(rainflow_text(result, "Pa", 2.0).splitlines()[1])
      Miner's damage 6.25e-07 over the history (2 s); life 3.2e+06 s (888.9 h)
    """
    shown = _stress_unit(unit)
    # N S^k = C with S = factor S': N S'^k = C / factor^k
    C = result.sn.C / shown.factor ** result.sn.k
    lines = [f"Rainflow counting (ASTM E1049) and Miner's rule: S-N curve N S^{result.sn.k:g} "
             f"= {C:.4g} (S the amplitude in "
             f"{printable(shown.text, limit=20) or THE_STRESS_UNIT}); "
             f"{result.counts.sum():g} cycles"]
    text = f"  Miner's damage {result.damage:.4g} over the history"
    if duration is not None:
        life = result.life(duration)
        text += f" ({duration:.4g} s); life " + (
            "infinite (no damage)" if not math.isfinite(life) else
            f"{life:.4g} s ({life / 3600:.4g} h)")
    lines += [text, rainflow_table(result, unit).text()]
    lines += [f"warning: {w}" for w in result.warnings] if warnings else []
    return "\n".join(lines) + "\n"


def rainflow_chart(result: RainflowDamage, unit: str | Shown = "") -> Charts:
    """What the figure of a rainflow count shows: the cycles and their damage by range
    bin, as bars.

    Parameters
    ----------
    result : RainflowDamage
    unit : str or Shown
        The stress's unit, for the labels; a :class:`Shown` (``MPa``) also converts the
        ranges from SI.

    Returns
    -------
    Charts

    Examples
    --------
    >>> result = rainflow_damage([0.0, 100.0, -100.0, 0.0], SNCurve(1e12, 3.0))
    >>> [p.ylabel for p in rainflow_chart(result, "Pa").panels]
    ['cycles', "Miner's damage"]
    """
    shown = _stress_unit(unit)
    bins = [(shown(low), shown(high), cycles, damage)
            for low, high, cycles, damage in _range_bins(result)]
    label = f" [{printable(shown.text, limit=20)}]" if shown.text else ""
    x = np.array([(low + high) / 2 for low, high, _, _ in bins])
    width = (bins[0][1] - bins[0][0]) * 0.85 if bins else 1.0
    xlim = (0.0, bins[-1][1]) if bins else (0.0, 1.0)
    panels = tuple(
        Chart((), f"stress range{label}", ylabel, xlim, title=title, legend="none",
              bars=(Bar(x, np.array([b[column] for b in bins]), (COLORS[column - 2],),
                        width),))
        for column, ylabel, title in ((2, "cycles", "rainflow cycles by range"),
                                      (3, "Miner's damage", "damage by range")))
    return Charts(panels, size=(7.0, 5.6), sharex=True)


__all__ = ["METHODS", "SNCurve", "SpectralFatigue", "spectral_fatigue", "ResponseFatigue",
           "response_fatigue", "RainflowDamage", "rainflow_damage"]
