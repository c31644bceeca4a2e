"""The explore page as a user handles it, at 375 px (a phone) and 1280 px (a desktop).

Headless Chromium (Debian's ``/usr/bin/chromium``, driven by Playwright) opens pages
written by ``resonant explore``; nothing but the page itself may load (as in
``test_explore_browser.py``, whose helpers are reused).  Checked:

* no horizontal overflow (``scrollWidth <= clientWidth``) at either width,
* a field and its slider always agree: a typed number moves the slider and its spoken
  value (``aria-valuetext``), the arrow keys in the field or on the slider move both, and
  ``resonant.set`` from a script moves both,
* "abc" or an empty field is said next to the field, the last valid value is kept (and
  put back in the field when it is left), the results do not change,
* the diagnosis next to the controls is the one of ``resonant solve --json`` word for word
  (an indefinite mass matrix, a K that is not positive definite, an unstable equilibrium),
  and an unstable system lists no amplitudes,
* the response plot's y range holds every point of the curves shown (above the 8 decades
  below the highest peak it shows at most), a frequency beyond the plotted range is said,
  and the curves have distinct colours,
* the response plot's axis labels and curve styles are those of the chart description the
  library's plots draw (``response_chart``, from ``resonant.analyses.sweep.response_axes``),
* at 375 px the mechanism stays in view while a slider far down is used.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from conftest import run_cli, run_json
from test_explore_browser import PARTS, REFERENCE, SIX, browser, opened  # noqa: F401


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("pages")
    out = {}
    for model in (REFERENCE, PARTS, SIX):
        target = folder / f"{model.parent.name}-{model.stem}.html"
        status, _, err = run_cli(["explore", model, "-o", target])
        assert status == 0, err
        out[model.stem if model != PARTS else "parts"] = target
    return out


def _control(page: Any, name: str) -> dict[str, Any]:
    return page.evaluate(f"""() => {{
        const r = document.querySelector('input[type=range][data-name="{name}"]');
        const f = document.querySelector('input.value[data-name="{name}"]');
        const e = document.querySelector('.field-error[data-name="{name}"]');
        return {{slider: Number(r.value), spoken: r.getAttribute('aria-valuetext'),
                 field: f.value, error: e.textContent, invalid: f.getAttribute('aria-invalid')}};
    }}""")


@pytest.mark.parametrize("width", [375, 1280])
@pytest.mark.parametrize("name", ["cart_pendulum", "parts", "shear_building6"])
def test_no_horizontal_overflow(browser: Any, written: dict[str, Path], width: int,  # noqa: F811
                                name: str) -> None:
    with opened(browser, written[name], width=width, height=800) as page:
        overflow = page.page.evaluate(
            "document.documentElement.scrollWidth - document.documentElement.clientWidth")
        assert overflow <= 0, f"the page is {overflow} px wider than the screen"
        # no caption or table cut: everything outside a scroll box lies within the screen
        cut = page.page.evaluate("""(w) => [...document.querySelectorAll('p, h1, h2, h3, label')]
            .filter(e => !e.closest('.scroll') && e.getClientRects().length)
            .filter(e => { const r = e.getBoundingClientRect();
                           return r.left < -0.5 || r.right > w + 0.5; })
            .map(e => e.textContent.slice(0, 40))""", width)
        assert cut == []


@pytest.mark.parametrize("width", [375, 1280])
def test_field_slider_and_script_stay_in_sync(browser: Any, written: dict[str, Path],  # noqa: F811
                                              width: int) -> None:
    with opened(browser, written["cart_pendulum"], width=width) as page:
        p = page.page
        before = _control(p, "k")
        field = p.locator('input.value[data-name="k"]')
        field.fill("250")
        typed = _control(p, "k")
        assert page.state()["parameters"]["k"] == 250.0
        assert typed["slider"] > before["slider"], "the slider did not follow the typed value"
        assert typed["spoken"] == "250 N/m"
        field.press("Tab")
        assert _control(p, "k")["field"] == "250"
        # the arrow keys in the field step like the slider, and both follow
        field.focus()
        field.press("ArrowDown")
        stepped = _control(p, "k")
        k = page.state()["parameters"]["k"]
        assert k < 250.0 and stepped["slider"] == typed["slider"] - 10
        assert float(stepped["field"]) == pytest.approx(k, rel=1e-9)
        # the slider's keys move the field
        slider = p.locator('input[type=range][data-name="k"]')
        slider.focus()
        slider.press("ArrowRight")
        moved = _control(p, "k")
        k2 = page.state()["parameters"]["k"]
        assert k2 > k and float(moved["field"]) == pytest.approx(k2, rel=1e-9)
        assert moved["spoken"].endswith(" N/m")
        # a script moves both
        p.evaluate("resonant.set({k: 42})")
        scripted = _control(p, "k")
        assert scripted["field"] == "42" and scripted["spoken"] == "42 N/m"
        assert scripted["slider"] < moved["slider"]


@pytest.mark.parametrize("text, said", [("abc", "“abc” is not a number"),
                                        ("", "an empty field is not a number"),
                                        ("0x10", "“0x10” is not a number")])
def test_invalid_input_is_said_next_to_the_field(browser: Any,  # noqa: F811
                                                  written: dict[str, Path], text: str,
                                                  said: str) -> None:
    with opened(browser, written["cart_pendulum"], width=375) as page:
        p = page.page
        start = page.state()
        field = p.locator('input.value[data-name="k"]')
        field.fill(text)
        control = _control(p, "k")
        assert control["error"] == f"{said}; k stays 100 N/m"
        assert control["invalid"] == "true"
        assert page.state()["amplitudes"] == start["amplitudes"]
        # the message sits next to its field, on the screen
        box = p.locator('.field-error[data-name="k"]').bounding_box()
        field_box = field.bounding_box()
        assert box is not None and field_box is not None
        assert 0 <= box["y"] - (field_box["y"] + field_box["height"]) < 30
        field.press("Tab")
        control = _control(p, "k")
        assert control["field"] == "100", "the last valid value is not shown again"
        assert control["error"] == f"{said}; k is back at 100 N/m"
        # a valid number clears it
        field.fill("110")
        assert _control(p, "k")["error"] == "" and _control(p, "k")["invalid"] is None


@pytest.mark.parametrize("settings", [{"m1": -5.0}, {"k": -500.0}])
def test_the_diagnosis_is_that_of_solve_next_to_the_controls(browser: Any,  # noqa: F811
                                                             written: dict[str, Path],
                                                             settings: dict[str, float]
                                                             ) -> None:
    extra = [a for name, value in settings.items() for a in ("--set", f"{name}={value!r}")]
    cli = run_json("solve", REFERENCE, *extra)
    assert cli["stability"] == "unstable"
    with opened(browser, written["cart_pendulum"]) as page:
        p = page.page
        p.evaluate(f"resonant.set({settings!r})".replace("'", '"'))
        shown = p.locator("#control-warnings li").all_inner_texts()
        assert shown == cli["warnings"]
        assert page.state()["warnings"] == cli["warnings"]
        # next to the controls: inside their box, above the first slider
        box = p.locator("#diagnosis").bounding_box()
        controls = p.locator(".controls").bounding_box()
        first = p.locator("#sliders").bounding_box()
        assert box and controls and first
        assert controls["y"] <= box["y"] and box["y"] + box["height"] <= first["y"] + 1
        # no amplitudes listed for an unstable system
        cells = p.locator('#response-table [data-key^="amplitudes."]').count()
        assert cells == 0
        assert "unstable" in p.locator("#response-table caption").inner_text()


def test_the_response_plot_fits_its_curves(browser: Any, written: dict[str, Path]  # noqa: F811
                                           ) -> None:
    with opened(browser, written["cart_pendulum"]) as page:
        p = page.page
        for settings in ({}, {"omega": 30.0}, {"k": 400.0}):
            p.evaluate(f"resonant.set({settings!r})".replace("'", '"'))
            plot = p.evaluate("resonant.response()")
            low, high = plot["log_range"]
            values = [y for ys in plot["curves"].values() for y in ys if y and y > 0]
            top = math.log10(max(values))
            assert top <= high, "the highest peak is above the plot"
            assert high - top < 0.15 * (high - low), "more than the headroom above the peak"
            inside = [y for y in values if math.log10(y) >= low]
            # every point within 8 decades of the peak is drawn; the range holds no empty
            # decades below the lowest point
            assert all(math.log10(y) >= low for y in values if math.log10(y) >= top - 8)
            assert low >= math.log10(min(values)) - 0.1 * (high - low) or top - low > 8
            assert inside and not plot["beyond"]
        p.evaluate("resonant.set({omega: 1e9})")
        assert p.evaluate("resonant.response()")["beyond"] is True
        assert "outside this range" in p.locator("#response-caption").inner_text()
        p.evaluate("resonant.set({omega: -5})")
        assert p.evaluate("resonant.response()")["beyond"] is True
        p.evaluate("resonant.set({omega: 20})")
        assert p.evaluate("resonant.response()")["beyond"] is False


def test_the_response_plot_draws_the_chart_description(browser: Any,  # noqa: F811
                                                       written: dict[str, Path]) -> None:
    """The page takes the frequency response's axis labels and curve styles from the same
    description as plot_frequency_response: its labels as Unicode text, its colours,
    widths and dashes (in pixels: the description's are in line widths)."""
    import resonant
    from resonant.views.explore import explore_data
    from resonant.analyses.sweep import frequency_response_chart

    model = resonant.load(REFERENCE)
    chart = explore_data(model)[0]["response_chart"]
    names = [*model.coordinates, *model.outputs]
    assert chart["xtext"] == "excitation frequency ω [rad/s]"
    sweep = model.linearize().sweep("omega", [1.0, 2.0, 3.0])
    drawn = frequency_response_chart(sweep, units={"x1": "m", "x2": "m", "phi": "rad"})
    assert [c.label for c in drawn.panels[0].curves] == [c["label"] for c in chart["curves"]]
    assert drawn.panels[0].ylabel == chart["ylabel"]
    with opened(browser, written["cart_pendulum"]) as page:
        plot = page.page.evaluate("resonant.response()")
        assert plot["xlabel"] == chart["xtext"] and plot["ylabel"] == chart["ytext"]
        for name, style in zip(plot["names"], plot["styles"]):
            own = chart["curves"][names.index(name)]
            assert style["colour"] == own["color"] and style["width"] == own["width"]
            assert style["dash"] == []


def test_curves_have_distinct_colours_and_names_are_typeset(browser: Any,  # noqa: F811
                                                            written: dict[str, Path]) -> None:
    with opened(browser, written["shear_building6"]) as page:
        swatches = page.page.evaluate(
            "[...document.querySelectorAll('#shown .swatch')].map(s => s.style.background)")
        assert len(swatches) >= 9 and len(set(swatches)) == len(swatches)
    with opened(browser, written["cart_pendulum"]) as page:
        caption = page.page.locator("#response-caption").inner_text()
        assert "omega" not in caption and "ω" in caption
        units = page.page.locator("#sliders .unit").all_inner_texts()
        assert "m/s²" in units and not any("^" in u or "*" in u for u in units)


def test_the_mechanism_stays_in_view_on_a_phone(browser: Any,  # noqa: F811
                                                written: dict[str, Path]) -> None:
    with opened(browser, written["parts"], width=375, height=740) as page:
        p = page.page
        last = p.locator('input[type=range][data-name="r0"]')
        last.scroll_into_view_if_needed()
        last.focus()
        last.press("ArrowRight")
        slider = last.bounding_box()
        mechanism = p.locator("#mechanism").bounding_box()
        assert slider and mechanism
        assert mechanism["y"] >= -0.5 and mechanism["y"] + mechanism["height"] <= 740
        assert slider["y"] >= mechanism["y"] + mechanism["height"], "the mechanism covers it"
        assert slider["y"] + slider["height"] <= 740


@pytest.fixture(scope="module")
def quarter_car(tmp_path_factory: pytest.TempPathFactory) -> Path:
    target = tmp_path_factory.mktemp("quarter") / "quarter_car.html"
    status, _, err = run_cli(["explore", PARTS.parent / "quarter_car.toml", "-o", target])
    assert status == 0, err
    return target


@pytest.mark.parametrize("typed, end", [("-5", 0), ("1e6", 1000)])
def test_a_typed_value_beyond_the_range_moves_the_slider_to_it(
        browser: Any, written: dict[str, Path], typed: str, end: int) -> None:  # noqa: F811
    """k = -5 (or 1e6) typed in the field: the page computes with it and the slider's range
    extends to it, so the slider stands at that end (it stayed in the middle)."""
    with opened(browser, written["cart_pendulum"], width=375) as page:
        p = page.page
        p.locator('input.value[data-name="k"]').fill(typed)
        assert page.state()["parameters"]["k"] == float(typed)
        assert _control(p, "k")["slider"] == end
        # the slider moves within the extended range, back towards the file's value
        slider = p.locator('input[type=range][data-name="k"]')
        slider.focus()
        slider.press("ArrowRight" if end == 0 else "ArrowLeft")
        k = page.state()["parameters"]["k"]
        assert (k > float(typed)) if end == 0 else (k < float(typed))


def test_two_letter_names_are_a_letter_with_its_index(browser: Any,  # noqa: F811
                                                      quarter_car: Path) -> None:
    """ks, cs, kt are written k_s, c_s, k_t (an italic letter, an upright subscript)."""
    with opened(browser, quarter_car) as page:
        names = page.page.evaluate("""() => [...document.querySelectorAll('#sliders .name')]
            .map(n => [n.getAttribute('title'), n.querySelector('i').textContent,
                       (n.querySelector('sub') || {}).textContent || ''])""")
    shown = {title: (base, sub) for title, base, sub in names}
    for name in ("ks", "cs", "kt"):
        if name in shown:
            assert shown[name] == (name[0], name[1]), shown
    assert {"ks", "cs"} <= set(shown), shown


def test_the_page_writes_names_as_resonant_typesets_them(browser: Any,  # noqa: F811
                                                        quarter_car: Path,
                                                        tmp_path: Path) -> None:
    """One naming rule: the page reads the LaTeX resonant writes (name_latex) and has no
    rule of its own; a page whose data said \\mathrm{ks} (upright ks) shows ks, not k_s
    (once the page's script turned any two-letter \\mathrm name into a letter and its
    index, a second copy of name_latex's rule)."""
    text = quarter_car.read_text(encoding="utf-8")
    assert '"symbol": "k_{s}"' in text
    changed = tmp_path / "upright.html"
    changed.write_text(text.replace('"symbol": "k_{s}"', '"symbol": "\\\\mathrm{ks}"'),
                       encoding="utf-8")
    with opened(browser, changed) as page:
        names = page.page.evaluate("""() => [...document.querySelectorAll('#sliders .name')]
            .map(n => [n.getAttribute('title'), n.querySelector('i').textContent,
                       (n.querySelector('sub') || {}).textContent || ''])""")
    shown = {title: (base, sub) for title, base, sub in names}
    assert shown["ks"] == ("ks", ""), shown
    assert shown["cs"] == ("c", "s"), shown


def test_the_motion_heading_is_shown_on_a_phone(browser: Any,  # noqa: F811
                                                written: dict[str, Path]) -> None:
    with opened(browser, written["cart_pendulum"], width=375) as page:
        heading = page.page.locator("#motion-heading")
        assert heading.is_visible() and heading.inner_text() == "Motion"
        box = heading.bounding_box()
        assert box is not None and box["height"] > 8
