"""Fatigue from a stress density (FLife) and from a stress history (rainflow + Miner).

The spectral estimates are FLife's; these tests check the wiring, the units and the S-N
convention (N S^k = C, S the amplitude) against the published formulas written out here:

* narrow band (Bendat 1964; Miles 1954): damage rate nu0 (sqrt(2 m0))^k Gamma(1 + k/2) / C
  with nu0 = sqrt(m2/m0) (Hz);
* Dirlik (1985; Sherratt & Bishop's form, e.g. Benasciutti & Tovo, Int. J. Fatigue 27
  (2005) 867-877, Eq. 8): with Z = S_amplitude / sqrt(m0), the density
  G1/Q e^(-Z/Q) + G2 Z/R^2 e^(-Z^2/(2 R^2)) + G3 Z e^(-Z^2/2) and the peak rate
  sqrt(m4/m2), rate = nu_p m0^(k/2) (G1 Q^k Gamma(1 + k) + sqrt(2)^k Gamma(1 + k/2)
  (G2 |R|^k + G3)) / C;
  both to 1e-6 with the moments by the trapezoidal rule on the same frequencies (FLife's);
* rainflow: the ASTM E1049-85 example history counts ranges 3 (0.5), 4 (1.5), 6 (0.5),
  8 (1), 9 (0.5); a sine of amplitude S for n cycles has Miner's sum n S^k / C exactly.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from resonant.analyses.fatigue import SNCurve, rainflow_damage, spectral_fatigue
from resonant.analyses.random_response import random_response
from resonant.errors import AnalysisError
from resonant.model import loads
from resonant.system import linear_system

pytest.importorskip("FLife")
pytest.importorskip("rainflow")


def moments(f: np.ndarray, G: np.ndarray) -> list[float]:
    return [float(np.trapezoid(f**i * G, f)) for i in range(5)]


def dirlik_rate(f: np.ndarray, G: np.ndarray, C: float, k: float) -> float:
    m0, m1, m2, _, m4 = moments(f, G)
    xm = m1 / m0 * math.sqrt(m2 / m4)
    g = m2 / math.sqrt(m0 * m4)
    G1 = 2 * (xm - g**2) / (1 + g**2)
    R = (g - xm - G1**2) / (1 - g - G1 + G1**2)
    G2 = (1 - g - G1 + G1**2) / (1 - R)
    G3 = 1 - G1 - G2
    Q = 1.25 * (g - G3 - G2 * R) / G1
    moment = G1 * Q**k * math.gamma(1 + k) + math.sqrt(2) ** k * math.gamma(1 + k / 2) * (
        G2 * abs(R) ** k + G3)
    return math.sqrt(m4 / m2) * m0 ** (k / 2) * moment / C


def two_peaks() -> tuple[np.ndarray, np.ndarray]:
    """A broad-band stress density: two resonances (MPa^2/Hz)."""
    f = np.linspace(1, 400, 4000)
    G = 40 / (1 + ((f - 50) / 5) ** 2) + 15 / (1 + ((f - 220) / 12) ** 2)
    return f, G


def test_narrowband_and_dirlik_formulas() -> None:
    f, G = two_peaks()
    C, k = 1.2e13, 4.5
    result = spectral_fatigue(f, G, SNCurve(C, k), duration=3600.0)
    m0, _, m2, _, m4 = moments(f, G)
    narrow = math.sqrt(m2 / m0) * math.sqrt(2 * m0) ** k * math.gamma(1 + k / 2) / C
    assert result.damage_rate["narrowband"] == pytest.approx(narrow, rel=1e-6)
    assert result.damage_rate["dirlik"] == pytest.approx(dirlik_rate(f, G, C, k), rel=1e-6)
    assert result.life["dirlik"] == pytest.approx(1 / result.damage_rate["dirlik"], rel=1e-12)
    assert result.damage is not None
    assert result.damage["dirlik"] == pytest.approx(3600 * result.damage_rate["dirlik"])
    # broad band: narrow band is conservative, Dirlik and Tovo-Benasciutti below it
    assert result.damage_rate["dirlik"] < result.damage_rate["narrowband"]
    assert result.damage_rate["tovo-benasciutti"] < result.damage_rate["narrowband"]
    assert result.irregularity == pytest.approx(m2 / math.sqrt(m0 * m4), rel=1e-12)


def test_dirlik_is_flife() -> None:
    FLife = pytest.importorskip("FLife")
    f, G = two_peaks()
    ours = spectral_fatigue(f, G, SNCurve(3e12, 5.0), methods=["dirlik"])
    data = FLife.SpectralData(input={"PSD": G, "f": f})
    assert ours.life["dirlik"] == pytest.approx(FLife.Dirlik(data).get_life(3e12, 5.0),
                                                rel=1e-6)


def test_sn_conventions() -> None:
    f, G = two_peaks()
    by_amplitude = spectral_fatigue(f, G, SNCurve(1e13, 4.0))
    by_range = spectral_fatigue(f, G, SNCurve.from_range(1e13 * 2**4, 4.0))
    assert by_range.life == pytest.approx(by_amplitude.life, rel=1e-12)
    point = SNCurve.from_point(100.0, 1e6, 4.0)
    assert point.cycles(100.0) == pytest.approx(1e6)
    # units: the same stress in Pa with C in Pa^k gives the same life
    pascal = spectral_fatigue(f, G * 1e12, SNCurve(1e13 * 1e24, 4.0))
    assert pascal.life["dirlik"] == pytest.approx(by_amplitude.life["dirlik"], rel=1e-9)


def test_rainflow_astm_example() -> None:
    result = rainflow_damage([-2, 1, -3, 5, -1, 3, -4, 4, -2], SNCurve(1.0, 2.0))
    assert list(zip(result.ranges.tolist(), result.counts.tolist())) == [
        (3.0, 0.5), (4.0, 1.5), (6.0, 0.5), (8.0, 1.0), (9.0, 0.5)]
    expected = sum(n * (r / 2) ** 2 for r, n in [(3, 0.5), (4, 1.5), (6, 0.5), (8, 1), (9, 0.5)])
    assert result.damage == pytest.approx(expected, rel=1e-12)


def test_miner_sine() -> None:
    t = np.linspace(0, 25, 25 * 64 + 1)
    result = rainflow_damage(80 * np.cos(2 * np.pi * t), SNCurve(2e11, 3.0))
    assert result.damage == pytest.approx(25 * 80**3 / 2e11, rel=1e-12)


def test_random_response_to_damage() -> None:
    """A stress output of a random response goes straight into the spectral methods."""
    model = loads("""
[parameters]
m = 1
k = 40000
c = 8
E = 2e7
[coordinates]
x = ""
[signals]
F = "0"
[energy]
T = "m*x'^2/2"
U = "k*x^2/2 - F*x"
D = "c*x'^2/2"
[outputs]
stress = "E*x"
[random]
band = [1, 300]
[random.psd.F]
values = 4.0
""")
    response = random_response(linear_system(model))
    result = spectral_fatigue(response.frequency, response.psd["stress"], SNCurve(1e30, 3.0))
    assert result.rms == pytest.approx(response.rms["stress"], rel=1e-3)
    assert result.zero_crossing_rate == pytest.approx(response.zero_crossing_rate["stress"],
                                                      rel=1e-3)


@pytest.mark.parametrize("call, message", [
    (lambda: SNCurve(-1.0, 3.0), "C > 0"),
    (lambda: spectral_fatigue([1, 2, 3], [1, 1, 1], SNCurve(1, 3), methods=["x"]),
     "unknown fatigue method"),
    (lambda: spectral_fatigue([1, 3, 2], [1, 1, 1], SNCurve(1, 3)), "increasing"),
    (lambda: spectral_fatigue([1, 2, 3], [0, 0, 0], SNCurve(1, 3)), "not zero everywhere"),
    (lambda: spectral_fatigue([1, 2, 3], [1, 1, 1], SNCurve(1, 3), duration=-1), "positive"),
    (lambda: rainflow_damage([1.0], SNCurve(1, 3)), "two finite samples"),
])
def test_errors(call, message: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(AnalysisError, match=message):
        call()
