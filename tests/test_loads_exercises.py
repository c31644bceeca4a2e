"""Exercise variants with keys beyond a sine: a Miles problem (examples/teaching/
miles_shaker.toml) and a Fourier-series problem (examples/teaching/fourier_square.toml)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import resonant
from resonant.exercises.variants import generate

TEACHING = Path(__file__).parents[1] / "examples" / "teaching"
G = 9.80665


def test_miles_variants_against_the_closed_form() -> None:
    """miles:a is Miles' equation sqrt(pi/2 f_n Q S0) written out from m, k, c, S0
    (Miles 1954; rel 1e-6: the code reads the static gain from |H| extrapolated to 0 Hz);
    rms:a is the exact value of random_response (rel 1e-12), which Miles' estimate
    approaches to about 1/(4Q) for Q ~ 10 (here within 2 %).  The spectrum is given in
    g^2/Hz, so the key is in g (1 g = 9.80665 m/s^2, exact)."""
    model = resonant.load(TEACHING / "miles_shaker.toml")
    batch = generate(model, 4, seed=3)
    for v in batch.variants:
        m, k, c, S0 = (v.values[n] for n in ("m", "k", "c", "S0"))
        fn = math.sqrt(k / m) / (2 * math.pi)
        Q = math.sqrt(k * m) / c
        miles = math.sqrt(math.pi / 2 * fn * Q * S0)  # in g, as S0 is in g^2/Hz
        assert v.answers["miles:a"].value == pytest.approx(miles, rel=1e-6)
        assert v.answers["miles:a"].unit == v.answers["rms:a"].unit == "g"
        exact = v.model.random_response(names=["a"]).rms["a"]
        assert v.answers["rms:a"].value == pytest.approx(exact / G, rel=1e-12)
        assert v.answers["rms:a"].value == pytest.approx(miles, rel=0.02)


def test_fourier_variants_against_a_hand_written_superposition() -> None:
    """largest:x against the textbook sum written here with numpy: the square wave
    4 F0/pi sum_{n odd} sin(n W t)/n, each harmonic through 1/(k - m (nW)^2 + i c nW),
    2001 harmonics, 2^16 samples of a period (the key keeps the harmonics up to a 1 %
    RMS remainder of the force; the displacement's remainder is far smaller: rel 2e-3).
    The sum over the samples t_j = j T / N is sum_n c_n e^(2 pi i n j / N), numpy's
    inverse FFT times N (exact, not an approximation of the sum)."""
    model = resonant.load(TEACHING / "fourier_square.toml")
    batch = generate(model, 4, seed=5)
    F0, T = 10.0, 0.5
    W = 2 * math.pi / T
    N = 2**16
    n = np.arange(1, 2002, 2)
    for v in batch.variants:
        m, k, c = (v.values[name] for name in ("m", "k", "c"))
        H = 1 / (k - m * (n * W) ** 2 + 1j * c * n * W)
        b = 4 * F0 / (n * math.pi)
        coefficients = np.zeros(N, dtype=complex)
        coefficients[n] = b * H / 1j
        x = (np.fft.ifft(coefficients) * N).real
        assert v.answers["largest:x"].value == pytest.approx(np.abs(x).max(), rel=2e-3)
        assert v.answers["largest:x"].unit == "m"


@pytest.mark.parametrize("name", ["miles_shaker", "fourier_square"])
def test_exercise_command_writes_the_keys(tmp_path: Path, name: str) -> None:
    from conftest import run_cli
    code, out, err = run_cli(["exercise", str(TEACHING / f"{name}.toml"), "--variants", "2",
                              "--seed", "1", "-o", str(tmp_path), "--no-plots"])
    assert code == 0, err
    key = json.loads((tmp_path / "key.json").read_text())
    text = json.dumps(key)
    assert ("miles:a" in text) if name == "miles_shaker" else ("largest:x" in text)


def test_unknown_load_answer_is_named(tmp_path: Path) -> None:
    from resonant.errors import ModelError
    text = (TEACHING / "fourier_square.toml").read_text().replace(
        '"largest:x"]', '"largest:nope"]')
    path = tmp_path / "f.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match="'nope' is neither a coordinate nor an output"):
        resonant.load(path)


def test_a_load_answer_without_its_section_is_said(tmp_path: Path) -> None:
    from resonant.errors import ModelError
    text = (TEACHING / "fourier_square.toml").read_text()
    text = text[:text.index("[periodic]")] + text[text.index("[exercise]"):]
    path = tmp_path / "f.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match=r"no \[periodic\] section"):
        generate(resonant.load(path), 1, seed=1)
