"""The explore page shows the response to the model's periodic load ([periodic], docs/random.md
"Periodic loads", docs/explore.md): the page sums the harmonics' stationary responses itself
(live, as the sliders move) and its largest excursion is the one ``resonant solve --json``
gives (its key ``periodic``): two routes, the browser's numerics and the kernel, to 1e-6
relative (the two sum over slightly different samplings of one period: 65,536 points by an
FFT on the page, 16 per harmonic on resonant's side).  Headless Chromium (Debian's
``/usr/bin/chromium``) opens pages written by ``resonant explore``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from conftest import EXAMPLES, run_cli, run_json
from test_explore_browser import browser, opened  # noqa: F401

SQUARE = EXAMPLES / "teaching" / "fourier_square.toml"

#: a base-excited 2-DOF model: the series is of the base acceleration, the load reaches the
#: masses through k1 and c1 (columns that change with the sliders), and an output (the
#: relative deflection) depends on the signal itself
BASE = """title = "Two masses on a base under a sawtooth acceleration"
[parameters]
m1 = 2
m2 = 1
k1 = 800
k2 = 300
c1 = 4
c2 = 1
[coordinates]
x1 = {}
x2 = {}
[signals]
y = "0"
[energy]
T = "m1*x1'^2/2 + m2*x2'^2/2"
U = "k1*(x1 - y)^2/2 + k2*(x2 - x1)^2/2"
D = "c1*(x1' - y')^2/2 + c2*(x2' - x1')^2/2"
[outputs]
deflection = "x1 - y"
[periodic]
signal = "y"
derivative = 0
shape = "triangle"
amplitude = 0.002
period = 0.4
tolerance = 1e-4
"""


def _largest(solved: dict[str, Any]) -> dict[str, float]:
    return {name: r["largest"] for name, r in solved["periodic"]["responses"].items()}


def _written(tmp_path: Path, model: Path) -> Path:
    target = tmp_path / f"{model.stem}.html"
    status, _, err = run_cli(["explore", model, "-o", target])
    assert status == 0, err
    return target


@pytest.mark.parametrize("which", ["square", "base"])
def test_the_page_gives_the_largest_excursion_of_solve(browser: Any, tmp_path: Path,  # noqa: F811
                                                       which: str) -> None:
    model = SQUARE
    if which == "base":
        model = tmp_path / "base.toml"
        model.write_text(BASE, encoding="utf-8")
    expected = _largest(run_json("solve", model))
    with opened(browser, _written(tmp_path, model)) as page:
        state = page.page.evaluate("resonant.state()")
        assert not page.page.locator("#periodic-panel").is_hidden()
        caption = page.page.locator("#periodic-caption").text_content()
        assert "harmonics" in caption and "period" in caption
    largest = state["periodic"]["largest"]
    for name, value in expected.items():
        assert largest[name] == pytest.approx(value, rel=1e-6), name


def test_a_slider_moves_the_periodic_response(browser: Any, tmp_path: Path) -> None:  # noqa: F811
    """k1 = 1600 on the page equals ``resonant solve --set k1=1600``: the load's columns
    (k1 y + c1 y') are recomputed from the sliders, not frozen at the file's values."""
    model = tmp_path / "base.toml"
    model.write_text(BASE, encoding="utf-8")
    expected = _largest(run_json("solve", model, "--set", "k1=1600"))
    with opened(browser, _written(tmp_path, model)) as page:
        state = page.page.evaluate("resonant.set({k1: 1600})")
    for name, value in expected.items():
        assert state["periodic"]["largest"][name] == pytest.approx(value, rel=1e-6), name


def test_a_model_without_a_periodic_load_shows_no_panel(browser: Any,  # noqa: F811
                                                         tmp_path: Path) -> None:
    with opened(browser, _written(tmp_path, EXAMPLES / "absorber.toml")) as page:
        assert page.page.locator("#periodic-panel").is_hidden()
        assert "periodic" not in page.page.evaluate("resonant.state()")


def test_a_precomputed_page_shows_resonants_periodic_response(browser: Any,  # noqa: F811
                                                              tmp_path: Path) -> None:
    """Above the live limit (a 45-mass chain given by its matrices) the page shows the
    periodic response resonant computed at the file's values: the same numbers."""
    import numpy as np

    n = 45
    K = 2e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = 2e4
    for name, matrix in (("M", np.eye(n)), ("C", 1e-4 * K + 0.2 * np.eye(n)), ("K", K)):
        np.save(tmp_path / f"{name}.npy", matrix)
    model = tmp_path / "chain.toml"
    model.write_text('title = "chain"\n[matrices]\nM = "M.npy"\nC = "C.npy"\nK = "K.npy"\n'
                     f'[periodic]\nsignal = "q{n}"\nshape = "sawtooth"\namplitude = 5\n'
                     'period = 0.2\ntolerance = 0.01\n', encoding="utf-8")
    expected = _largest(run_json("solve", model))
    with opened(browser, _written(tmp_path, model)) as page:
        state = page.page.evaluate("resonant.state()")
        assert state["live"] is False
        assert not page.page.locator("#periodic-panel").is_hidden()
    for name, value in state["periodic"]["largest"].items():
        assert value == pytest.approx(expected[name], rel=1e-12), name
