"""Measured FRFs on the explore page (``resonant explore MODEL --test FILE.uff``,
resonant.views.explore_measured), in a real browser.

The "test" is the chain's own FRF to the hammer times 3 (so that the points lie half a
decade above the model's curves, where no curve is drawn), written as a binary Universal
File.  Under the model's load F0 sin(omega t), F0 = 10 N, the page must draw at omega =
2 pi f the amplitude 3 * 10 N * |H(f)| of each coordinate: the values it drew are compared
with that, computed here from the kernel's FRF, to 1e-9 relative (the file keeps every
bit; the rest is rounding).  The canvas is read back: the name's colour is found at the
drawn position of the points (within 3 px).  The points stay where they are when a slider
moves the model's curves.  A file that does not belong to the model is exit 2 before any
page is written.  Skipped without Chromium or Playwright, as tests/test_explore_browser.py.
"""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import resonant
from conftest import run_cli
from resonant.analyses.frf_update import model_frf_matrix
from resonant.analyses.sweep import sweep
from resonant.model.measured import MeasuredData, MeasuredFunction, write_uff
from test_explore_browser import CHROMIUM, opened
from test_explore_measured_inputs import two_loads_text, two_reference_file
from test_measured_signal_inputs import feedthrough_text, write_test

EXAMPLE = Path(__file__).parents[1] / "examples" / "chain3_lab.toml"
LINES = np.linspace(0.5, 12.0, 47)
FACTOR = 3.0
F0 = 10.0


@pytest.fixture(scope="module")
def browser() -> Any:
    if not CHROMIUM.exists():
        pytest.skip("Debian's chromium (/usr/bin/chromium) is not installed")
    pytest.importorskip("pyuff")
    api = pytest.importorskip("playwright.sync_api")
    with api.sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=str(CHROMIUM),
                                     args=["--headless", "--no-sandbox", "--disable-gpu"])
        try:
            yield chromium
        finally:
            chromium.close()


@pytest.fixture(scope="module")
def frf() -> np.ndarray:
    model = resonant.load(EXAMPLE)
    return model_frf_matrix(model.linearize(), ["F"], LINES,
                            model.measurement_section.channels)[:, :, 0]


def _uff(path: Path, H: np.ndarray, lines: np.ndarray = LINES) -> Path:
    functions = tuple(MeasuredFunction(name, "frf", lines, H[:, k], "Hz", "m/N", (k + 1, 3),
                                       (3, 3)) for k, name in enumerate(("d1", "d2", "d3")))
    write_uff(path, MeasuredData(path.name, functions), binary=True)
    return path


def _colour_near(page: Any, px: float, py: float, colour: str) -> bool:
    """Whether the canvas holds ``colour`` within 3 px of (px, py) (CSS pixels)."""
    return page.evaluate("""([px, py, colour]) => {
      const c = document.getElementById("response"), g = c.getContext("2d");
      const s = c.width / c.getBoundingClientRect().width;
      const want = [1, 3, 5].map(i => parseInt(colour.slice(i, i + 2), 16));
      const d = g.getImageData(Math.round((px - 3) * s), Math.round((py - 3) * s),
                               Math.round(7 * s), Math.round(7 * s)).data;
      for (let i = 0; i < d.length; i += 4) {
        if (Math.abs(d[i] - want[0]) + Math.abs(d[i + 1] - want[1]) + Math.abs(d[i + 2] - want[2]) < 60) return true;
      }
      return false;
    }""", [px, py, colour])


def test_measured_points_are_drawn_with_their_values(browser, frf, tmp_path):
    test = _uff(tmp_path / "lab.uff", FACTOR * frf)
    page_file = tmp_path / "page.html"
    status, _, err = run_cli(["explore", EXAMPLE, "-o", page_file, "--test", test])
    assert status == 0, err
    with opened(browser, page_file) as page:
        drawn = page.page.evaluate("resonant.response()")["measured"]
        assert sorted(drawn) == ["x1", "x2", "x3"]
        for k, name in enumerate(("x1", "x2", "x3")):
            points = np.array(drawn[name])
            expected = FACTOR * F0 * np.abs(frf[:, k])
            assert points.shape == (len(LINES), 4)
            assert np.allclose(points[:, 0], 2 * np.pi * LINES, rtol=1e-12)
            assert np.allclose(points[:, 1], expected, rtol=1e-9)
            assert np.all(np.diff(points[:, 2]) > 0)      # left to right, as omega grows
            colour = page.page.evaluate(f"resonant.response().styles[{k}].colour")
            found = [_colour_near(page.page, px, py, colour) for px, py in points[:, 2:]]
            assert np.mean(found) >= 0.9, (name, colour)
        caption = page.page.inner_text("#response-caption")
        assert "Open circles: measured (lab.uff)" in caption
        # a slider moves the curves, not the measurement
        before = page.page.evaluate("resonant.response()")
        page.page.evaluate("resonant.set({k1: 1500})")
        after = page.page.evaluate("resonant.response()")
        assert after["curves"]["x1"] != before["curves"]["x1"]
        assert np.allclose(np.array(after["measured"]["x1"])[:, :2],
                           np.array(drawn["x1"])[:, :2], rtol=1e-12)


def test_a_file_of_another_model_is_refused(frf, tmp_path):
    test = _uff(tmp_path / "lab.uff", frf, lines=LINES * 50)
    page_file = tmp_path / "page.html"
    status, _, err = run_cli(["explore", EXAMPLE, "-o", page_file, "--test", test])
    assert status == 2 and "do not overlap the model's natural frequencies" in err, err
    assert "Traceback" not in err and not page_file.exists()


def test_no_measured_data_no_points(browser, tmp_path):
    page_file = tmp_path / "page.html"
    assert run_cli(["explore", EXAMPLE, "-o", page_file])[0] == 0
    with contextlib.ExitStack() as stack:
        page = stack.enter_context(opened(browser, page_file))
        state = page.page.evaluate("resonant.response()")
        assert state["measured"] is None
        assert "Open circles" not in page.page.inner_text("#response-caption")


def test_two_references_are_summed_on_the_page(browser, tmp_path):
    """The chain loaded on masses 1 and 3, a shaker at each: the page draws, at every line,
    the sweep's amplitude (the test's FRFs being the model's own: sum_j H_ij u_j, to 1e-9);
    a test with the shaker on mass 1 only draws nothing and says why in the caption."""
    (tmp_path / "two.toml").write_text(two_loads_text(["shaker1", "shaker3"], ["x1", "x3"]))
    two = resonant.load(tmp_path / "two.toml")
    test = two_reference_file(tmp_path / "two.uff", two, ["shaker1", "shaker3"], [1, 3])
    page_file = tmp_path / "two.html"
    status, _, err = run_cli(["explore", tmp_path / "two.toml", "-o", page_file, "--test", test])
    assert status == 0, err
    swept = sweep(two.linearize(), "omega", 2 * np.pi * LINES, method="direct")
    with opened(browser, page_file) as page:
        drawn = page.page.evaluate("resonant.response()")["measured"]
        assert sorted(drawn) == ["x1", "x2", "x3"]
        for k, name in enumerate(("x1", "x2", "x3")):
            points = np.array(drawn[name])
            assert points.shape == (len(LINES), 4)
            assert np.allclose(points[:, 0], 2 * np.pi * LINES, rtol=1e-12)
            assert np.allclose(points[:, 1], swept.amplitudes[name], rtol=1e-9)
            colour = page.page.evaluate(f"resonant.response().styles[{k}].colour")
            found = [_colour_near(page.page, px, py, colour) for px, py in points[:, 2:]]
            assert np.mean(found) >= 0.9, (name, colour)
        caption = page.page.inner_text("#response-caption")
        assert ("the FRFs to shaker1, shaker3, each times the model's load at its input, "
                "summed (phases included), at the file's values") in caption, caption
        page.page.screenshot(path=str(tmp_path / "two.png"))
    (tmp_path / "one.toml").write_text(two_loads_text(["shaker1"], ["x1"]))
    test = two_reference_file(tmp_path / "one.uff", resonant.load(tmp_path / "one.toml"),
                              ["shaker1"], [1])
    status, _, err = run_cli(["explore", tmp_path / "one.toml", "-o", page_file, "--test", test])
    assert status == 0 and "no measured points" in err, err
    with opened(browser, page_file) as page:
        assert page.page.evaluate("resonant.response()")["measured"] == {}
        caption = page.page.inner_text("#response-caption")
        assert ("Measured (one.uff): no measured points: the model's load acts on x3") in caption
        assert "Open circles" not in caption


def test_an_output_through_an_unmeasured_signal_is_left_out(browser, tmp_path):
    """The two-load chain with a sensor channel v = x3 + E/2 that picks up a signal E no
    input measures: the page draws the masses' points, none for v, and its caption says
    both what is drawn and why v is not (tests/test_measured_signal_inputs.py)."""
    (tmp_path / "v.toml").write_text(feedthrough_text(["shaker1", "shaker3"], ["F1", "F3"]))
    model = resonant.load(tmp_path / "v.toml")
    _, test = write_test(tmp_path / "v.uff", model, ["shaker1", "shaker3"], [(5, 0), (6, 0)])
    page_file = tmp_path / "v.html"
    status, _, err = run_cli(["explore", tmp_path / "v.toml", "-o", page_file, "--test", test])
    assert status == 0 and "no measured points for v (through E)" in err, err
    with opened(browser, page_file) as page:
        assert sorted(page.page.evaluate("resonant.response()")["measured"]) == [
            "x1", "x2", "x3"]
        caption = page.page.inner_text("#response-caption")
        assert "Open circles: measured (v.uff)" in caption, caption
        assert "no measured points for v (through E)" in caption, caption
