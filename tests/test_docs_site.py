"""The documentation site builds from the repository with no warning (docs/conf.py).

The build runs Sphinx with ``-W`` (warnings are errors) into a temporary folder, as the
README's command does into ``docs/_build/html``, and makes the gallery of the bundled
examples on the way; the test then checks that the guide, the API reference and every
example's page are there with their figures.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("myst_parser")

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("site")
    # nitpicky (-n): every reference must resolve, any warning fails the build
    run = subprocess.run([sys.executable, "-m", "sphinx", "-n", "-W", "--keep-going", "-q", "-b",
                          "html", "-d", str(out / ".doctrees"), str(ROOT / "docs"),
                          str(out)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    return out


def test_module_paths_in_docstrings_link_to_the_public_pages(site: Path) -> None:
    """``resonant.analyses.sweep.sweep`` in a docstring is a link to resonant.sweep's page;
    a name that exists nowhere is not resolved (the nitpicky build would fail on it)."""
    page = (site / "generated" / "resonant.LinearSystem.html").read_text(encoding="utf-8")
    assert 'href="resonant.sweep.html#resonant.sweep"' in page
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import public_names

    assert public_names._find("resonant.analyses.sweep.sweep", None) is not None
    assert public_names._find("resonant.analyses.sweep.no_such_function", None) is None
    assert public_names._find("sweep", "resonant.analyses.sweep") is not None


def test_mentions_of_guide_files_are_links(site: Path) -> None:
    """"docs/errors.md" in the guide's text and in docstrings links to the page."""
    import re

    page = (site / "explore.html").read_text(encoding="utf-8")
    assert '<a class="reference internal" href="errors.html">docs/errors.md</a>' in page
    for html in [*site.glob("*.html"), *site.glob("generated/*.html")]:
        body = re.sub(r"<(nav|script)\b.*?</\1>", "", html.read_text(encoding="utf-8"),
                      flags=re.S)
        text = re.sub(r"<a\b[^>]*>.*?</a>|<[^>]+>", " ", body, flags=re.S)
        assert not re.search(r"docs/[a-z-]+\.md", text), html.name


def test_the_guide_and_the_reference_are_built(site: Path) -> None:
    for page in ("index", "model-format", "parts", "units", "nonlinear", "exercises",
                 "architecture", "api"):
        assert (site / f"{page}.html").is_file(), page
    api = (site / "api.html").read_text(encoding="utf-8")
    assert "resonant.Model" in api and "generated/resonant.load.html" in api


def test_one_api_page_per_public_object_with_its_source(site: Path) -> None:
    pages = {p.stem for p in (site / "generated").glob("*.html")}
    for name in ("load", "Model", "LinearSystem", "StationarySolution", "ModelError",
                 "exercises.generate"):
        assert f"resonant.{name}" in pages, name
    system = (site / "generated" / "resonant.LinearSystem.html").read_text(encoding="utf-8")
    assert "viewcode-link" in system and 'id="resonant.LinearSystem.numeric"' in system
    for page in (site / "generated").glob("*.html"):
        text = page.read_text(encoding="utf-8")
        for helper in ("with_methods", "promote", "fields_of_base"):
            assert f'id="resonant.{helper}' not in text and f".{helper}(" not in text, page


def test_the_site_loads_nothing_and_draws_its_mathematics(site: Path) -> None:
    import re

    for page in site.rglob("*.html"):
        text = page.read_text(encoding="utf-8")
        external = re.findall(r'<(?:script|link|img)[^>]*(?:src|href)="(?:https?:)?//[^"]*"',
                              text)
        assert not external, (page.name, external[:3])
        assert not re.search(r"<script[^>]*mathjax|MathJax\.js|tex-mml", text, re.I), page.name
    sweeps = (site / "sweeps.html").read_text(encoding="utf-8")
    assert "<math" in sweeps and "$" not in re.sub(r"<[^>]+>", "", sweeps.split("<math")[0])[-200:]
    assert "pydata" in (site / "index.html").read_text(encoding="utf-8")


def test_the_guide_shows_its_figures(site: Path) -> None:
    for page, image in (("studies", "study-grid-cells.png"), ("sweeps", "sweep-cart-pendulum.png"),
                        ("nonlinear", "nonlinear-duffing.png"), ("explore", "explore-375.png"),
                        ("parts", "parts-torsional-chain.png"),
                        ("reference-exercise", "report-375.png")):
        assert image in (site / f"{page}.html").read_text(encoding="utf-8"), page
        assert (site / "_images" / image).is_file(), image


def test_the_gallery_index_has_thumbnails_and_distinct_titles(site: Path) -> None:
    import re

    index = (site / "gallery" / "index.html").read_text(encoding="utf-8")
    cards = re.findall(r'class="[^"]*gallery-card', index)
    thumbnails = re.findall(r'<img[^>]+src="[^"]*\.png"', index)
    assert len(cards) == len(thumbnails) >= 20
    titles = [re.sub(r"<[^>]+>", "", t).strip()
              for t in re.findall(r"<title>(.*?)</title>", "".join(
                  p.read_text(encoding="utf-8") for p in (site / "gallery").glob("*.html")))]
    assert len(titles) == len(set(titles))


def test_every_example_has_a_gallery_page_with_its_figures(site: Path) -> None:
    examples = [p for folder in ("", "parts", "teaching")
                for p in (ROOT / "examples" / folder).glob("*.toml")]
    pages = list((site / "gallery").glob("*.html"))
    assert len(pages) == len(examples) + 1  # and the index
    duffing = (site / "gallery" / "duffing.html").read_text(encoding="utf-8")
    assert "duffing_nonlinear.png" in duffing and "duffing_modes.png" in duffing
    images = list((site / "_images").glob("*.png"))
    assert any(p.name.endswith("_drawing.png") for p in images)
    assert all(p.stat().st_size > 5_000 for p in images if p.name.startswith("duffing"))


@pytest.mark.parametrize("width", [375, 1280])
def test_the_site_fits_a_phone_and_a_laptop(site: Path, width: int) -> None:
    """Chromium (Debian's, via Playwright) opens pages of the built site: none is wider
    than the screen (a wide formula or table scrolls in its own box)."""
    chromium = Path("/usr/bin/chromium")
    if not chromium.exists():
        pytest.skip("Debian's chromium (/usr/bin/chromium) is not installed")
    api = pytest.importorskip("playwright.sync_api")
    pages = ["index", "model-format", "sweeps", "studies", "explore", "gallery/index",
             "generated/resonant.LinearSystem", "api"]
    with api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(chromium), args=[
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            for name in pages:
                page = browser.new_page(viewport={"width": width, "height": 900})
                page.goto((site / f"{name}.html").as_uri())
                overflow = page.evaluate("document.documentElement.scrollWidth"
                                         " - document.documentElement.clientWidth")
                page.close()
                assert overflow <= 0, f"{name} is {overflow} px wider than {width} px"
        finally:
            browser.close()


def _contrast(a: tuple[float, ...], b: tuple[float, ...]) -> float:
    """WCAG contrast ratio of two sRGB colours (0-255)."""
    def luminance(c: tuple[float, ...]) -> float:
        lin = [(v / 255) / 12.92 if v / 255 <= 0.04045 else ((v / 255 + 0.055) / 1.055) ** 2.4
               for v in c[:3]]
        return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]
    hi, lo = sorted((luminance(a), luminance(b)), reverse=True)
    return (hi + 0.05) / (lo + 0.05)


@pytest.mark.parametrize("scheme", ["light", "dark"])
def test_formulas_are_legible_in_light_and_dark_mode(site: Path, scheme: str) -> None:
    """The typeset formulas of a guide page, photographed in Chromium with the reader's OS
    in light and in dark mode: the glyphs stand out from the page (the contrast of the
    inkiest pixel against the background, measured on the screenshot, at least 4.5)."""
    import io

    from PIL import Image

    chromium = Path("/usr/bin/chromium")
    if not chromium.exists():
        pytest.skip("Debian's chromium (/usr/bin/chromium) is not installed")
    api = pytest.importorskip("playwright.sync_api")
    with api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(chromium), args=[
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900},
                                    color_scheme=scheme)
            page.goto((site / "sweeps.html").as_uri())
            assert page.evaluate("document.documentElement.dataset.theme") == scheme
            formulas = page.locator("svg.m")
            assert formulas.count() > 3
            ratios = []
            for i in range(min(formulas.count(), 6)):
                shot = Image.open(io.BytesIO(formulas.nth(i).screenshot())).convert("RGB")
                colours = shot.getcolors(shot.width * shot.height) or []
                background = max(colours)[1]
                ratios.append(max(_contrast(background, c) for _, c in colours))
            page.close()
        finally:
            browser.close()
    assert min(ratios) >= 4.5, ratios
