"""The HTML report on a phone (375 px) and a desktop (1280 px) in a real browser.

Headless Chromium (Debian's ``/usr/bin/chromium``, driven by Playwright) opens the
reports of the reference exercise and of the damped chain; at each width:

* the page never scrolls sideways (``scrollWidth <= clientWidth``): a display formula
  wider than a phone keeps its line and scrolls inside its own box,
* no two display formulas (nor a formula and the next paragraph) overlap,
* on a phone no formula is broken at its operators: each stays one line tall,
* the first paragraph names the model by its file name, the characteristic equation is
  in descending powers of omega_n, the figure caption writes ω, and the amplitude axis
  carries its units.

Skipped, with the reason, when Chromium or Playwright is missing.
"""

from __future__ import annotations

import io
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from conftest import EXAMPLES, run_cli

CHROMIUM = Path("/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"]
MODELS = [EXAMPLES / "cart_pendulum.toml", EXAMPLES / "chain3_damped.toml"]


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    if not CHROMIUM.exists():
        pytest.skip("Debian's chromium (/usr/bin/chromium) is not installed")
    api = pytest.importorskip("playwright.sync_api")
    with api.sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=str(CHROMIUM), args=ARGS)
        try:
            yield chromium
        finally:
            chromium.close()


@pytest.fixture(scope="module")
def reports(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("reports")
    out = {}
    for model in MODELS:
        target = folder / f"{model.stem}.html"
        status, _, err = run_cli(["report", model.resolve(), "-o", target])
        assert status == 0, err
        out[model.stem] = target
    return out


LAYOUT = """() => {
  const doc = document.documentElement;
  const boxes = [...document.querySelectorAll('main > *')].map(e => {
    const r = e.getBoundingClientRect();
    return {tag: e.tagName, cls: e.className, top: r.top + scrollY, bottom: r.bottom + scrollY};
  });
  const equations = [...document.querySelectorAll('.equation .body')].map(b => {
    return [...b.querySelectorAll('svg.m')].map(s => {
      const r = s.getBoundingClientRect();
      return [r.top, r.bottom];
    });
  });
  return {scroll: doc.scrollWidth, client: doc.clientWidth, boxes, equations};
}"""


@pytest.mark.parametrize("width", [375, 1280])
@pytest.mark.parametrize("name", [m.stem for m in MODELS])
def test_the_report_fits_the_screen(browser: Any, reports: dict[str, Path], width: int,
                                    name: str) -> None:
    page = browser.new_page(viewport={"width": width, "height": 900})
    try:
        page.goto(reports[name].resolve().as_uri())
        layout = page.evaluate(LAYOUT)
    finally:
        page.close()
    assert layout["scroll"] <= layout["client"], \
        f"the page is {layout['scroll'] - layout['client']} px wider than the screen"
    boxes = layout["boxes"]
    for upper, lower in zip(boxes, boxes[1:]):
        assert upper["bottom"] <= lower["top"] + 1, f"{upper} overlaps {lower}"
    if width == 375:
        for k, pieces in enumerate(layout["equations"]):
            # one line: the pieces of a formula sit side by side, none below another
            lowest_top = max(top for top, _ in pieces)
            highest_bottom = min(bottom for _, bottom in pieces)
            assert lowest_top < highest_bottom, f"formula {k + 1} is broken: {pieces}"


FIGURE_TEXTS = """() => [...document.querySelectorAll('figure svg')].map(svg =>
  [...svg.querySelectorAll('text')].filter(t => t.textContent.trim()).map(t => {
    const r = t.getBoundingClientRect();
    return [t.textContent, r.left, r.top, r.right, r.bottom];
  }))"""


@pytest.mark.parametrize("width", [375, 1280])
def test_no_two_texts_of_a_figure_overlap(browser: Any, reports: dict[str, Path],
                                          width: int) -> None:
    page = browser.new_page(viewport={"width": width, "height": 900})
    try:
        page.goto(reports["cart_pendulum"].resolve().as_uri())
        figures = page.evaluate(FIGURE_TEXTS)
    finally:
        page.close()
    assert len(figures) == 2
    for texts in figures:
        for i, (a, *box) in enumerate(texts):
            for b, *other in texts[i + 1:]:
                apart = box[2] <= other[0] + 0.5 or other[2] <= box[0] + 0.5 or \
                    box[3] <= other[1] + 0.5 or other[3] <= box[1] + 0.5
                assert apart, f"{a!r} overlaps {b!r} at {width} px"


def test_the_report_reads_like_a_textbook(reports: dict[str, Path]) -> None:
    text = reports["cart_pendulum"].read_text(encoding="utf-8")
    assert "“cart_pendulum.toml”" in text
    assert str(EXAMPLES.resolve()) not in text
    caption = re.search(r"Figure 1: ([^<]*)", text)
    assert caption and "omega" not in caption.group(1) and "ω" in caption.group(1)
    assert "amplitude X [m, rad]" in text
    # the characteristic polynomial: omega_n^4 before omega_n^2 before the constant
    latex = run_cli(["report", EXAMPLES / "cart_pendulum.toml", "-o",
                     reports["cart_pendulum"].with_suffix(".tex")])
    assert latex[0] == 0
    tex = reports["cart_pendulum"].with_suffix(".tex").read_text(encoding="utf-8")
    line = next(ln for ln in tex.splitlines() if r"\det\left(\mathbf{K}" in ln
                and "= 0" in ln)
    fourth, second = line.find(r"\omega_{n}^{4}"), line.find(r"\omega_{n}^{2}", 30)
    assert 0 < fourth < second, line


PHONE = """() => ({
  equations: [...document.querySelectorAll('.equation .body')].map(b => {
    const style = getComputedStyle(b);
    return {hidden: b.scrollWidth - b.clientWidth, font: parseFloat(style.fontSize),
            text: parseFloat(getComputedStyle(document.querySelector('p')).fontSize),
            cue: style.backgroundImage.includes('radial-gradient'),
            scrolls: ['auto', 'scroll'].includes(style.overflowX)};
  }),
  figures: [...document.querySelectorAll('figure svg')].map(svg => {
    const scale = svg.getBoundingClientRect().width / svg.viewBox.baseVal.width;
    const box = svg.parentElement, style = getComputedStyle(box);
    return {text: Math.min(...[...svg.querySelectorAll('text')].map(
              t => parseFloat(t.getAttribute('font-size') || '10') * scale)),
            hidden: box.scrollWidth - box.clientWidth,
            cue: style.backgroundImage.includes('radial-gradient'),
            scrolls: ['auto', 'scroll'].includes(style.overflowX)};
  }),
  tables: [...document.querySelectorAll('table')].map(t => {
    const box = t.parentElement, style = getComputedStyle(box);
    return {hidden: box.scrollWidth - box.clientWidth,
            cue: style.backgroundImage.includes('radial-gradient'),
            scrolls: ['auto', 'scroll'].includes(style.overflowX)};
  })})"""


@pytest.mark.parametrize("name", [m.stem for m in MODELS])
def test_on_a_phone_nothing_is_clipped_without_a_cue(browser: Any, reports: dict[str, Path],
                                                     name: str) -> None:
    """At 375 px a formula wider than the screen is first set smaller (down to 0.7 of the
    text); one still wider scrolls in its box with a visible cue (shadows at the edges
    where more of it lies), never cut silently; figure text is at least 9 px."""
    page = browser.new_page(viewport={"width": 375, "height": 900})
    try:
        page.goto(reports[name].resolve().as_uri())
        found = page.evaluate(PHONE)
    finally:
        page.close()
    equations = found["equations"]
    assert any(eq["font"] < eq["text"] - 0.5 for eq in equations), "no formula was scaled"
    for k, eq in enumerate(equations):
        assert eq["font"] >= 0.7 * eq["text"] - 0.5, f"formula {k + 1} is set too small"
        if eq["hidden"] > 1:
            assert eq["scrolls"] and eq["cue"], f"formula {k + 1} is cut with no cue: {eq}"
            assert eq["font"] <= 0.7 * eq["text"] + 0.5, f"formula {k + 1} scrolls unscaled"
    assert found["figures"]
    for figure in found["figures"]:
        assert figure["text"] >= 9 - 0.05, figure
        if figure["hidden"] > 1:
            assert figure["scrolls"] and figure["cue"], figure
    for table in found["tables"]:
        if table["hidden"] > 1:
            assert table["scrolls"] and table["cue"], table


def test_units_in_tables_are_typeset(tmp_path: Path) -> None:
    """The random section's table writes m/s² (HTML: a superscript, Markdown: ², LaTeX:
    \\textsuperscript), never the typed m/s^2 or TeX's \\textasciicircum.  The input is
    given in g, so the report answers in g unless asked for m/s^2 (docs/units.md)."""
    model = EXAMPLES / "shaker_gevs.toml"
    written = {}
    for suffix in ("html", "md", "tex"):
        target = tmp_path / f"gevs.{suffix}"
        status, _, err = run_cli(["report", model, "--no-plots", "--units", "m/s^2", "-o", target])
        assert status == 0, err
        written[suffix] = target.read_text(encoding="utf-8")
    # HTML: a superscript, or the unit typeset as mathematics (MathML's msup)
    assert "m/s<sup>2</sup>" in written["html"] or re.search(
        r"<msup><mi[^>]*>s</mi><mrow><mn>2</mn></mrow></msup>", written["html"])
    assert "m/s²" in written["md"] or re.search(r"\$[^$]*s\^\{?2\}?[^$]*\$", written["md"])
    assert r"m/s\textsuperscript{2}" in written["tex"] or re.search(
        r"\$[^$]*s\^\{?2\}?[^$]*\$", written["tex"])
    for text in written.values():
        outside_math = re.sub(r"\$[^$]*\$|<svg.*?</svg>|<math.*?</math>", "", text, flags=re.S)
        assert "m/s^2" not in outside_math and r"\textasciicircum" not in outside_math


def test_a_figure_wider_than_a_phone_shows_its_scroll_cue(browser: Any,
                                                          reports: dict[str, Path]) -> None:
    """The cue is measured, not assumed: at 375 px the right edge of a figure that scrolls
    is shaded (the median of its last 4 pixel columns darker than 235 of 255), where the
    chart's white ground used to cover the shadow; scrolled to its end, the right edge is
    clear and the left one shaded."""
    from PIL import Image, ImageStat

    page = browser.new_page(viewport={"width": 375, "height": 900})
    try:
        page.goto(reports["cart_pendulum"].resolve().as_uri())
        box = page.query_selector("figure .plot")
        assert box is not None
        box.scroll_into_view_if_needed()
        assert page.evaluate("(e) => e.scrollWidth - e.clientWidth", box) > 1

        def edges() -> tuple[float, float]:
            image = Image.open(io.BytesIO(box.screenshot())).convert("L")
            w, h = image.size
            left = ImageStat.Stat(image.crop((0, 0, 4, h))).median[0]
            right = ImageStat.Stat(image.crop((w - 4, 0, w, h))).median[0]
            return left, right

        left, right = edges()
        assert right < 235 and left > 245, (left, right)
        page.evaluate("(e) => { e.scrollLeft = e.scrollWidth; }", box)
        left, right = edges()
        assert left < 235 and right > 245, (left, right)
    finally:
        page.close()


def test_a_reader_in_dark_mode_sees_the_page_as_printed(browser: Any,
                                                         reports: dict[str, Path]) -> None:
    """The report is a document (``color-scheme: light``): in a dark colour scheme its page
    stays white with dark text and its formulas keep their contrast, measured on the
    rendered pixels of a formula (darker than 100 of 255 where it is drawn)."""
    from PIL import Image, ImageStat

    page = browser.new_page(viewport={"width": 1280, "height": 900}, color_scheme="dark")
    try:
        page.goto(reports["cart_pendulum"].resolve().as_uri())
        colours = page.evaluate("""() => {
            const main = getComputedStyle(document.querySelector('main'));
            return [main.backgroundColor, main.color];
        }""")
        assert colours == ["rgb(255, 255, 255)", "rgb(29, 29, 31)"], colours
        formula = page.query_selector(".equation .body")
        assert formula is not None
        formula.scroll_into_view_if_needed()
        image = Image.open(io.BytesIO(formula.screenshot())).convert("L")
        assert ImageStat.Stat(image).extrema[0][0] < 100   # the glyphs are drawn dark
        assert ImageStat.Stat(image).median[0] > 235       # on the white page
    finally:
        page.close()
