"""The explore page of a rotor (a model with ``[campbell]``) in a real browser: the speed
slider, the unbalance orbits drawn at the current speed, the bearing forces, the Campbell
diagram with the current speed marked and the critical speed map (docs/explore.md,
Rotors).

The page's numbers are compared with the Python solve of the same model
(``resonant.analyses.campbell.campbell``, ``resonant.analyses.unbalance
.unbalance_response`` at the diagram's speeds and ``resonant.analyses.rotor_map
.critical_speed_map``): the branches' frequencies, damping ratios and whirl are
resonant's (to 1e-12, their JSON), the orbits' semi-axes and the bearing forces'
amplitudes are computed by the page from the complex amplitudes (to 1e-9, as the other
explore tests), the maps are resonant's (to 1e-9). Headless Chromium
(``/usr/bin/chromium``) through Playwright, every request refused; skipped with the
reason where either is missing. Models: Friswell, Penny, Garvey & Lees (2010), Example
5.9.1 (examples/rotors/friswell_5_9_1.toml; 7 stations, a disc unbalance, undamped
bearings) and Example 5.9.5 (the same rotor on damped bearings: its damped map).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import test_explore_browser
from conftest import EXAMPLES, run_cli
from resonant.analyses.campbell import RPM, campbell
from resonant.analyses.rotor_map import MAP_MODES, critical_speed_map
from resonant.analyses.unbalance import unbalance_response
from resonant.model import load
from resonant.system import linear_system
from resonant.views.explore import map_stiffness, rotor_data
from test_explore_browser import REFERENCE, _changed, opened

#: the browser of the explore tests (headless Chromium, one per module)
browser = test_explore_browser.browser

FRISWELL = EXAMPLES / "rotors" / "friswell_5_9_1.toml"
DAMPED = EXAMPLES / "rotors" / "friswell_5_9_5.toml"
JEFFCOTT = EXAMPLES / "rotors" / "jeffcott_rotor.toml"
RTOL = 1e-9


@pytest.fixture(scope="module")
def rotor_page(tmp_path_factory: pytest.TempPathFactory) -> Path:
    target = tmp_path_factory.mktemp("rotor") / "friswell.html"
    status, _, err = run_cli(["explore", FRISWELL, "-o", target])
    assert status == 0, err
    return target


@pytest.fixture(scope="module")
def solved() -> tuple[Any, Any]:
    system = linear_system(load(FRISWELL))
    diagram = campbell(system)
    return diagram, unbalance_response(system, diagram.speeds)


def _pixels(page: Any, canvas: str) -> np.ndarray:
    """A canvas's pixels (grey), read from the page itself (no screenshot)."""
    import base64
    import io

    from PIL import Image

    url = page.page.evaluate(f"document.getElementById({canvas!r}).toDataURL('image/png')")
    png = base64.b64decode(url.split(",", 1)[1])
    return np.asarray(Image.open(io.BytesIO(png)).convert("L"), dtype=int)


def _state(page: Any, index: int | None = None) -> dict[str, Any]:
    call = "resonantRotor.state()" if index is None else f"resonantRotor.set({index})"
    return page.page.evaluate(f"JSON.parse(JSON.stringify({call}))")  # type: ignore[no-any-return]


def _fits(page: Any, width: int) -> None:
    """No scrolling sideways; the panel's canvases and slider inside the screen."""
    overflow = page.page.evaluate(
        "document.documentElement.scrollWidth - document.documentElement.clientWidth")
    assert overflow <= 0, f"the page is {overflow} px wider than the screen"
    for selector in ("#rotor-orbit", "#rotor-campbell", "#rotor-forces", "#rotor-map",
                     "#rotor-speed"):
        box = page.page.locator(selector).bounding_box()
        assert box is not None and box["width"] > 100, selector
        assert box["x"] >= 0 and box["x"] + box["width"] <= width + 0.5, selector


def test_the_rotor_panel_shows_what_the_python_solve_computes(
        browser: Any, rotor_page: Path, solved: tuple[Any, Any]) -> None:
    diagram, response = solved
    with opened(browser, rotor_page) as page:
        assert page.page.locator("#rotor-panel").is_visible()
        assert page.page.evaluate("resonantRotor.speeds()") == diagram.speeds.tolist()
        for k in (0, len(diagram.speeds) // 3, len(diagram.speeds) - 1):
            shown = _state(page, k)
            assert shown["speed"] == diagram.speeds[k]
            assert np.allclose(shown["frequencies"], diagram.frequencies[k], rtol=1e-12)
            assert np.allclose(shown["damping_ratios"], diagram.damping_ratios[k], atol=1e-12)
            assert shown["whirl"] == list(diagram.whirl[k])
            orbits = shown["orbits"]
            assert [o["station"] for o in orbits] == list(response.stations)
            assert np.allclose([o["major"] for o in orbits], response.major[k], rtol=RTOL)
            assert np.allclose([o["minor"] for o in orbits], response.minor[k], rtol=RTOL,
                               atol=RTOL * float(np.max(response.major[k])))
            assert [o["precession"] for o in orbits] == list(response.precession[k])
            # the tables show the same numbers (full values in data-value)
            cell = page.page.locator('[data-key="rotor.frequency.0"]')
            assert float(cell.get_attribute("data-value")) == pytest.approx(
                diagram.frequencies[k, 0], rel=1e-12)
            cell = page.page.locator('[data-key="rotor.major.0"]')
            assert float(cell.get_attribute("data-value")) == pytest.approx(
                response.major[k, 0], rel=RTOL)
        assert "0-pk" in page.page.locator("#rotor-panel").inner_text()
        _fits(page, 1280)
        critical = page.page.locator("#rotor-campbell-caption").inner_text()
        first = diagram.critical_speeds[0].speed * 30 / np.pi
        assert f"{float(f'{first:.5g}'):g} rpm" in critical


def test_the_slider_moves_the_speed_and_the_marked_speed(browser: Any, rotor_page: Path
                                                         ) -> None:
    with opened(browser, rotor_page) as page:
        _state(page, 0)
        before_campbell = _pixels(page, "rotor-campbell")
        before_orbit = _pixels(page, "rotor-orbit")
        slider = page.page.locator("#rotor-speed")
        slider.focus()
        page.page.keyboard.press("ArrowRight")
        page.page.keyboard.press("ArrowRight")
        assert _state(page)["index"] == 2
        assert "rpm" in page.page.locator("#rotor-speed-out").inner_text()
        # the current speed's line moved on the diagram, and the orbits were drawn again
        assert _changed(before_campbell, _pixels(page, "rotor-campbell")) > 0.002
        assert _changed(before_orbit, _pixels(page, "rotor-orbit")) > 0.002


def test_the_bearing_forces_are_those_of_unbalance_response(
        browser: Any, rotor_page: Path, solved: tuple[Any, Any]) -> None:
    diagram, response = solved
    assert response.bearings == ("bearing1", "bearing2")
    with opened(browser, rotor_page) as page:
        for k in (0, 3, len(diagram.speeds) // 2, len(diagram.speeds) - 1):
            forces = _state(page, k)["bearing_forces"]
            assert [f["bearing"] for f in forces] == list(response.bearings)
            expected = response.bearing_force[k]
            assert np.allclose([f["major"] for f in forces], expected, rtol=RTOL,
                               atol=RTOL * float(np.max(expected)))
            cell = page.page.locator('[data-key="rotor.force.1"]')
            assert float(cell.get_attribute("data-value")) == pytest.approx(
                expected[1], rel=RTOL, abs=RTOL * float(np.max(expected)))
        # at rest the unbalance force m e Omega^2 is zero: so are the bearing forces
        assert _state(page, 0)["bearing_forces"][0]["major"] == 0
        text = page.page.locator("#rotor-panel").inner_text()
        assert "The bearing forces at this speed" in text
        assert "none (the unbalance force m e Ω² is zero)" in text


def test_the_critical_speed_map_is_that_of_critical_speed_map(
        browser: Any, rotor_page: Path, solved: tuple[Any, Any]) -> None:
    diagram, _ = solved
    system = linear_system(load(FRISWELL))
    stiffness = map_stiffness([1e6])
    assert stiffness[0] == 1e5 and stiffness[-1] == 1e9
    expected = critical_speed_map(system, stiffness, modes=MAP_MODES, orders=diagram.orders)
    with opened(browser, rotor_page) as page:
        shown = _state(page)["map"]
        assert shown["own"] == [1e6] and shown["shown"] == "undamped"
        assert shown["damped"] is None          # undamped bearings: the two maps are one
        undamped = shown["undamped"]
        assert np.allclose(undamped["stiffness"], expected.stiffness, rtol=1e-15)
        speeds = np.array(undamped["speeds"], dtype=float)
        assert speeds.shape == expected.speeds.shape
        assert np.allclose(speeds, expected.speeds, rtol=RTOL, equal_nan=True)
        assert [[tuple(r) for r in block] for block in undamped["whirl"]] == \
            [list(block) for block in expected.whirl]
        # the chart drawn is resonant's: rpm, one curve per mode
        drawn = np.array(undamped["drawn"], dtype=float)
        assert np.allclose(drawn, expected.speeds[:, 0, :].T / RPM, rtol=RTOL, equal_nan=True)
        # at the bearings' own stiffness the map's critical speeds are the Campbell
        # diagram's (docs/rotors.md: 1e-8)
        at = int(np.argmin(np.abs(np.log(stiffness / 1e6))))
        tracked = sorted(c.speed for c in diagram.critical_speeds)
        assert np.allclose(speeds[at, 0, :len(tracked)], tracked, rtol=1e-8)
        caption = page.page.locator("#rotor-map-caption").inner_text()
        assert "undamped critical speeds" in caption and "1e6 N/m" in caption
        assert page.page.locator("#rotor-map-kind").is_hidden()


def test_a_damped_rotor_has_its_damped_map_too(browser: Any, tmp_path: Path) -> None:
    target = tmp_path / "damped.html"
    assert run_cli(["explore", DAMPED, "-o", target])[0] == 0
    system = linear_system(load(DAMPED))
    orders = campbell(system).orders
    expected = critical_speed_map(system, map_stiffness([1e6]), modes=MAP_MODES,
                                  orders=orders, damped=True)
    with opened(browser, target) as page:
        before = _pixels(page, "rotor-map")
        page.page.locator('#rotor-map-kind button[data-kind="damped"]').click()
        shown = _state(page)["map"]
        assert shown["shown"] == "damped"
        assert _changed(before, _pixels(page, "rotor-map")) > 0.002
        damped = shown["damped"]
        assert np.allclose(np.array(damped["speeds"], dtype=float), expected.speeds,
                           rtol=RTOL, equal_nan=True)
        assert expected.damping_ratios is not None
        assert np.allclose(np.array(damped["damping_ratios"], dtype=float),
                           expected.damping_ratios, rtol=RTOL, equal_nan=True)
        assert "damped critical speeds" in page.page.locator("#rotor-map-caption").inner_text()


def test_the_page_opens_at_the_first_critical_speed(browser: Any, rotor_page: Path,
                                                    solved: tuple[Any, Any]) -> None:
    diagram, response = solved
    # the file's speed is 0 rpm, where there is nothing to see: the page opens at the
    # speed of the grid nearest the first critical speed (docs/explore.md)
    first = min(c.speed for c in diagram.critical_speeds)
    with opened(browser, rotor_page) as page:
        shown = _state(page)
        assert shown["index"] == int(np.argmin(np.abs(diagram.speeds - first)))
        assert shown["speed"] > 0 and min(o["major"] for o in shown["orbits"]) > 0
        assert "no motion" not in page.page.locator("#rotor-orbit-caption").inner_text()
        # at 0 rpm the page says why nothing moves
        _state(page, 0)
        caption = page.page.locator("#rotor-orbit-caption").inner_text()
        assert "at rest" in caption and "m e Ω² is zero" in caption


def test_a_rotor_without_bearings_has_no_map_and_no_forces() -> None:
    model = load(JEFFCOTT)
    data = rotor_data(model, linear_system(model))
    assert data is not None and data["orbits"] is not None
    assert data["forces"] is None and data["map"] is None


def test_the_force_chart_draws_the_peaks_between_the_slider_speeds(
        solved: tuple[Any, Any]) -> None:
    """The force chart's curve is on its own finer grid: on Example 5.9.1's 200-rpm slider
    the unbalance peak near 830 rpm falls between two speeds (41 N there; the curve
    passes within 3 rpm of the undamped critical speed, where the force is unbounded,
    and never at it); on 5.9.5's damped bearings the curve holds each damped 1x critical
    speed, and the forces are those of unbalance_response at its speeds."""
    diagram, response = solved
    model = load(FRISWELL)
    curve = rotor_data(model, linear_system(model))["forces"]["curve"]
    speeds = np.array(curve["speeds"])
    assert set(diagram.speeds) <= set(speeds) and len(speeds) >= 400
    critical = [c.speed for c in diagram.critical_speeds if c.order == 1]
    assert not set(critical) & set(speeds)
    drawn = np.array(curve["major"], dtype=float)
    assert np.nanmax(drawn) > 10 * np.max(response.bearing_force)
    damped = load(DAMPED)
    system = linear_system(damped)
    curve = rotor_data(damped, system)["forces"]["curve"]
    speeds = np.array(curve["speeds"])
    for c in campbell(system).critical_speeds:
        if c.order == 1:
            assert c.speed in speeds
    expected = unbalance_response(system, speeds).bearing_force.T
    assert np.allclose(np.array(curve["major"], dtype=float), expected, rtol=1e-12, atol=0)


@pytest.mark.parametrize("width", [375])
def test_the_rotor_panel_fits_the_width(browser: Any, rotor_page: Path, width: int
                                        ) -> None:
    with opened(browser, rotor_page, width=width) as page:
        _fits(page, width)


def test_a_model_without_campbell_has_no_rotor_panel(browser: Any, tmp_path: Path
                                                     ) -> None:
    target = tmp_path / "page.html"
    assert run_cli(["explore", REFERENCE, "-o", target])[0] == 0
    with opened(browser, target) as page:
        assert page.page.locator("#rotor-panel").is_hidden()
        assert page.page.evaluate("typeof window.resonantRotor") == "undefined"


def test_the_orbits_and_bearing_forces_follow_the_parameter_sliders(
        browser: Any, tmp_path: Path) -> None:
    """Example 5.9.1 with its bearings' stiffness a parameter kb: moved to 2 MN/m on the
    page, the orbits and the bearing forces at the slider's speeds are those of
    unbalance_response of the model with kb = 2 MN/m (1e-9; once they stayed the file's),
    and the page says what follows the sliders and what is the file's (the Campbell
    diagram, the modes, the map)."""
    text = FRISWELL.read_text().replace('Omega = "0 rpm"', 'Omega = "0 rpm"\nkb = "1 MN/m"')
    text = text.replace('kxx = "1 MN/m"', 'kxx = "kb"').replace('kyy = "1 MN/m"', 'kyy = "kb"')
    path = tmp_path / "friswell_kb.toml"
    path.write_text(text)
    target = tmp_path / "friswell_kb.html"
    status, _, err = run_cli(["explore", path, "-o", target])
    assert status == 0, err
    moved = tmp_path / "friswell_kb2.toml"
    moved.write_text(text.replace('kb = "1 MN/m"', 'kb = "2 MN/m"'))
    system = linear_system(load(moved))
    with opened(browser, target) as page:
        speeds = np.array(page.page.evaluate("resonantRotor.speeds()"))
        response = unbalance_response(system, speeds)
        page.page.evaluate("resonant.set({kb: 2e6})")
        for k in (3, len(speeds) // 2, len(speeds) - 1):
            shown = _state(page, k)
            assert np.allclose([o["major"] for o in shown["orbits"]], response.major[k],
                               rtol=RTOL)
            expected = response.bearing_force[k]
            assert np.allclose([f["major"] for f in shown["bearing_forces"]], expected,
                               rtol=RTOL, atol=RTOL * float(np.max(expected)))
            assert shown["follows_sliders"]["orbits"] and \
                shown["follows_sliders"]["bearing_forces"], shown["follows_sliders"]
        note = page.page.locator("#rotor-follows").inner_text()
        assert "The orbits and bearing forces follow the parameter sliders" in note
        assert "critical speed map are resonant's at the file's parameter values" in note


def test_a_precomputed_rotor_page_says_its_orbits_are_the_file_s(browser: Any,
                                                                 tmp_path: Path) -> None:
    """Example 5.9.1 in 12 elements (52 coordinates, above LIVE_LIMIT): the page is
    precomputed, and the rotor panel says that its orbits and forces, like its Campbell
    diagram, are resonant's at the file's values."""
    path = tmp_path / "friswell_12.toml"
    path.write_text(FRISWELL.read_text().replace("count = 6", "count = 12"))
    target = tmp_path / "friswell_12.html"
    status, _, err = run_cli(["explore", path, "-o", target])
    assert status == 0, err
    with opened(browser, target) as page:
        follows = _state(page)["follows_sliders"]
        assert not follows["orbits"] and not follows["bearing_forces"]
        note = page.page.locator("#rotor-follows").inner_text()
        assert "so are the orbits and bearing forces (this page is precomputed)" in note
