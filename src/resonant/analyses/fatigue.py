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
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..errors import AnalysisError
from ..model.load_spec import FATIGUE_METHODS
from .result_fields import FieldsJSON, saved
from .results_json import Saved

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
class RainflowDamage(FieldsJSON):
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

    ranges: np.ndarray
    counts: np.ndarray = saved(axes=("ranges",))
    damage: float = saved()
    sn: SNCurve = saved(key="sn_curve")
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        freeze_fields(self)

    def to_frame(self) -> Any:
        """The counted cycles as a table: their ``range`` and ``count`` (pandas, the
        ``study`` extra).

        Returns
        -------
        pandas.DataFrame

        Examples
        --------
        >>> result = rainflow_damage([0.0, 100.0, -50.0, 80.0, -100.0, 0.0], SNCurve(1e12, 3.0))
        >>> list(result.to_frame().columns)
        ['range', 'count']
        """
        import pandas as pd
        return pd.DataFrame({"range": self.ranges, "count": self.counts})


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
    damage = float(np.sum(counts / sn.cycles(ranges / 2))) if len(ranges) else 0.0
    return RainflowDamage(ranges, counts, damage, sn)


__all__ = ["METHODS", "SNCurve", "SpectralFatigue", "spectral_fatigue", "RainflowDamage",
           "rainflow_damage"]
