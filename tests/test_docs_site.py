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
from typing import Any

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
    examples = [p for folder in ("", "parts", "teaching", "rotors", "matrices")
                for p in (ROOT / "examples" / folder).glob("*.toml")]
    pages = list((site / "gallery").glob("*.html"))
    assert len(pages) == len(examples) + 1  # and the index
    duffing = (site / "gallery" / "duffing.html").read_text(encoding="utf-8")
    assert "duffing_nonlinear.png" in duffing and "duffing_modes.png" in duffing
    images = list((site / "_images").glob("*.png"))
    assert any(p.name.endswith("_drawing.png") for p in images)
    assert all(p.stat().st_size > 5_000 for p in images if p.name.startswith("duffing"))


#: the inline code names and signature names whose right edge is past the screen's (outside
#: code blocks and tables, which scroll or wrap in their own boxes)
OFF_SCREEN = """() => [...document.querySelectorAll(
    '.bd-article code span.pre, .bd-article dt.sig .sig-name, .bd-article dt.sig .sig-prename')]
  .filter(c => c.offsetParent !== null && !c.closest('pre, table, .highlight'))
  .filter(c => c.getBoundingClientRect().right > document.documentElement.clientWidth + 1)
  .map(c => c.textContent)"""


@pytest.mark.parametrize("width", [375, 1280])
def test_the_site_fits_a_phone_and_a_laptop(site: Path, width: int) -> None:
    """Chromium (Debian's, via Playwright) opens pages of the built site: none is wider
    than the screen (a wide formula or table scrolls in its own box), no entry of the
    page's table of contents runs past its column (a long module name wraps), and no
    inline code name (in a paragraph, a heading, an API signature) runs past the screen's
    edge, where the page cuts it off; a first visit logs no console error."""
    chromium = Path("/usr/bin/chromium")
    if not chromium.exists():
        pytest.skip("Debian's chromium (/usr/bin/chromium) is not installed")
    api = pytest.importorskip("playwright.sync_api")
    pages = ["index", "model-format", "sweeps", "studies", "explore", "gallery/index",
             "generated/resonant.LinearSystem", "api", "random",
             "generated/resonant.analyses.random_response.RandomResponse"]
    with api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(chromium), args=[
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            for name in pages:
                page = browser.new_page(viewport={"width": width, "height": 900})
                errors: list[str] = []
                page.on("console", lambda m, e=errors: e.append(m.text)
                        if m.type == "error" else None)
                page.goto((site / f"{name}.html").as_uri())
                overflow = page.evaluate("document.documentElement.scrollWidth"
                                         " - document.documentElement.clientWidth")
                cut = page.evaluate("""() => [...document.querySelectorAll('.bd-toc code')]
                    .filter(c => c.offsetParent !== null)
                    .filter(c => c.getBoundingClientRect().right >
                                 c.closest('.bd-toc').getBoundingClientRect().right + 1)
                    .map(c => c.textContent)""")
                beyond = page.evaluate(OFF_SCREEN)
                page.close()
                assert overflow <= 0, f"{name} is {overflow} px wider than {width} px"
                assert cut == [], f"{name}: {cut} run past the table of contents"
                assert beyond == [], f"{name}: {beyond} run past the screen's edge"
                assert errors == [], f"{name}: console errors {errors}"
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


def _results_and_analyses() -> dict[str, object]:
    """Every result type of resonant.analyses (a dataclass with ``to_dict`` in a module's
    ``__all__``) and every function there that returns one, by dotted home name."""
    import dataclasses
    import importlib
    import inspect
    import pkgutil
    import typing

    import resonant.analyses

    modules = [importlib.import_module(info.name) for info in
               pkgutil.iter_modules(resonant.analyses.__path__, "resonant.analyses.")]
    exported = [(m, getattr(m, n)) for m in modules for n in getattr(m, "__all__", ())]
    results = {obj for m, obj in exported if inspect.isclass(obj) and obj.__module__ ==
               m.__name__ and dataclasses.is_dataclass(obj) and hasattr(obj, "to_dict")}
    found: dict[str, object] = {f"{o.__module__}.{o.__qualname__}": o for o in results}
    names = {r.__name__ for r in results}
    for m, obj in exported:
        if inspect.isfunction(obj) and obj.__module__ == m.__name__:
            try:
                returned = typing.get_type_hints(obj).get("return")
            except NameError:  # an annotation only a type checker resolves
                returned = obj.__annotations__.get("return")
            if returned in results or returned in names:
                found[f"{m.__name__}.{obj.__name__}"] = obj
    return found


def test_every_public_result_and_analysis_has_its_api_page(site: Path) -> None:
    """The names of ``import resonant`` and every result type and analysis function of
    resonant.analyses have a page of their own: under ``resonant.NAME`` where the package
    names them, else under their module (docs/_ext/public_names.py, HOME_PAGES)."""
    import inspect

    import resonant

    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import public_names

    pages = {p.stem for p in (site / "generated").glob("*.html")}
    public = {getattr(resonant, n) for n in resonant.__all__ if n != "__version__"}
    for name in resonant.__all__:
        obj = getattr(resonant, name, None)
        if inspect.isfunction(obj) or inspect.isclass(obj):
            assert f"resonant.{name}" in pages, name
    homes = {f"{module}.{name}" for module, names in public_names.HOME_PAGES.items()
             for name in names}
    missing = [name for name, obj in _results_and_analyses().items()
               if obj not in public and name not in homes]
    assert not missing, f"no API page for {missing}: add them to HOME_PAGES and docs/api.rst"
    assert not homes - pages, sorted(homes - pages)
    for name in ("RandomResponse", "ShockSpectrum", "PeriodicResponse", "SpectralFatigue",
                 "RainflowDamage", "TransientResponse", "PeriodicSolution", "SweptState"):
        assert any(page.endswith(f".{name}") for page in pages), name


def test_returns_link_to_the_result_and_types_to_numpy(site: Path) -> None:
    """"Returns: RandomResponse" is a link to its page; numpy's and matplotlib's types
    link to their references through the inventories made offline."""
    page = (site / "generated" / "resonant.analyses.random_response.random_response.html"
            ).read_text(encoding="utf-8")
    returns = page.split('Returns<span class="colon">:</span>')[1][:600]
    assert 'href="resonant.analyses.random_response.RandomResponse.html' in returns
    texts = "".join(p.read_text(encoding="utf-8") for p in (site / "generated").glob("*.html"))
    assert "https://numpy.org/doc/stable/reference/generated/numpy.ndarray.html" in texts
    assert "https://matplotlib.org/stable/api/_as_gen/matplotlib.figure.Figure.html" in texts
    assert "https://docs.python.org/3/library/stdtypes.html#str" in texts
    inventories = site / ".doctrees" / "inventories"
    assert {p.stem for p in inventories.glob("*.inv")} >= {"numpy", "scipy", "matplotlib"}


def test_the_landing_page_has_cards_and_the_site_its_version(site: Path) -> None:
    import re

    import resonant

    index = (site / "index.html").read_text(encoding="utf-8")
    article = index.split('<article', 1)[1]
    cards = re.findall(r'class="[^"]*landing-card', article)
    assert len(cards) >= 5
    for target in ("install.html", "first-model.html", "gallery/index.html", "guide.html",
                   "api.html"):
        assert f'href="{target}' in article, target
    # no table of contents of every page on the landing page any more
    assert len(re.findall(r"<a ", article)) < 40
    assert f"v{resonant.__version__}" in index
    # copy buttons, served from the site itself
    assert (site / "_static" / "copybutton.js").is_file()
    assert 'src="_static/copybutton.js' in index


def test_the_gallery_shows_each_example_its_own_analysis(site: Path) -> None:
    """A model with [random], [shock], [periodic] or [fatigue] shows that analysis and
    suggests the command that computes it (resonant solve prints zeros for a random
    input); the guide's random page shows the densities and an SRS, typeset."""
    import re

    gallery = site / "gallery"
    for name, image, command in (
            ("shaker_gevs", "shaker_gevs_random.png", "resonant random"),
            ("teaching_miles_shaker", "teaching_miles_shaker_random.png", "resonant random"),
            ("shock_half_sine", "shock_half_sine_srs_a.png", "resonant srs"),
            ("periodic_sawtooth", "periodic_sawtooth_periodic.png", "resonant solve"),
            ("teaching_fourier_square", "teaching_fourier_square_periodic.png",
             "resonant solve"),
            ("bracket_fatigue", "bracket_fatigue_fatigue.png", "resonant study"),
            ("rotating_unbalance", "rotating_unbalance_sweep.png", "resonant sweep")):
        page = (gallery / f"{name}.html").read_text(encoding="utf-8")
        text = re.sub(r"<[^>]+>", "", page)
        assert image in page and (site / "_images" / image).is_file(), name
        assert command in text, name
    gevs = re.sub(r"<[^>]+>", "", (gallery / "shaker_gevs.html").read_text(encoding="utf-8"))
    assert "resonant solve" not in gevs
    sections = {s for p in (ROOT / "examples").glob("*.toml")
                for s in ("random", "shock", "periodic", "fatigue")
                if f"\n[{s}]" in p.read_text(encoding="utf-8")}
    assert sections == {"random", "shock", "periodic", "fatigue"}
    random = (site / "random.html").read_text(encoding="utf-8")
    for image in ("shaker_gevs_random.png", "shock_half_sine_srs.png"):
        assert image in random, image
    prose = re.sub(r"<[^>]+>", "", random.split("<pre", 1)[0])
    assert random.count('class="m"') > 40
    for ascii_math in ("integral of", "sqrt(m2/m0)", "sum_jl"):
        assert ascii_math not in re.sub(r"<[^>]+>", "", random), ascii_math
    assert prose
    exercise = (site / "reference-exercise.html").read_text(encoding="utf-8")
    assert exercise.count('class="math-display"') >= 20
    assert "d^2 T / (dq_i' dq_j')" not in exercise


NAVIGATION = """() => {
  const header = [...document.querySelectorAll('.bd-header .navbar-header-items__start '
      + '.nav-link, .bd-header .navbar-nav .nav-link')].filter(a => a.offsetParent !== null);
  const links = header.map(a => [a.textContent.trim(), a.getBoundingClientRect().height]);
  const line = parseFloat(getComputedStyle(header[0]).lineHeight) || 24;
  const side = [...document.querySelectorAll('.bd-sidebar-primary nav a')]
      .filter(a => a.offsetParent !== null).map(a => a.textContent.trim());
  const more = [...document.querySelectorAll('.bd-header .navbar-nav .dropdown-toggle')]
      .filter(a => a.offsetParent !== null).length;
  return {links, line, side, more};
}"""

TABLES = """() => [...document.querySelectorAll('article table')].map(t => {
  const box = t.closest('.pst-scrollable-table-container') || t.parentElement;
  const last = [...t.querySelectorAll('tr')].map(r => r.lastElementChild)
      .filter(c => c).map(c => c.getBoundingClientRect().right);
  return {right: Math.max(...last), edge: box.getBoundingClientRect().right,
          scrolls: box.scrollWidth > box.clientWidth + 1};
})"""


@pytest.fixture(scope="module")
def chromium() -> Any:
    path = Path("/usr/bin/chromium")
    if not path.exists():
        pytest.skip("Debian's chromium (/usr/bin/chromium) is not installed")
    api = pytest.importorskip("playwright.sync_api")
    with api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(path), args=[
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            yield browser
        finally:
            browser.close()


def test_the_header_shows_every_section_on_one_line_and_the_sidebar_its_pages(
        site: Path, chromium: Any) -> None:
    """At 1280 px the header's entries (guide, gallery, API reference, ...) are all shown,
    none wraps, none is hidden under "More"; a guide page's left sidebar lists the
    guide's pages; the reference's long table (errors.md) is not cut off."""
    page = chromium.new_page(viewport={"width": 1280, "height": 900})
    try:
        page.goto((site / "sweeps.html").as_uri())
        nav = page.evaluate(NAVIGATION)
        page.goto((site / "errors.html").as_uri())
        errors = page.evaluate(NAVIGATION)
        tables = page.evaluate(TABLES)
    finally:
        page.close()
    names = [name for name, _ in nav["links"]]
    for entry in ("User guide", "Gallery", "API reference", "Reference"):
        assert entry in names, names
    assert nav["more"] == 0, "an entry is hidden under More"
    assert all(height < 1.6 * nav["line"] for _, height in nav["links"]), nav["links"]
    assert {"Model files", "Frequency sweeps", "Units"} & set(nav["side"]) or \
        len(nav["side"]) >= 8, nav["side"]
    assert len(nav["side"]) >= 8 and len(errors["side"]) >= 5, (nav["side"], errors["side"])
    assert tables
    for table in tables:
        assert table["right"] <= table["edge"] + 1 or table["scrolls"], table


@pytest.mark.parametrize("width", [375, 1280])
def test_the_error_tables_fit_without_cutting_a_column(site: Path, chromium: Any,
                                                       width: int) -> None:
    page = chromium.new_page(viewport={"width": width, "height": 900})
    try:
        page.goto((site / "errors.html").as_uri())
        tables = page.evaluate(TABLES)
    finally:
        page.close()
    cut = [t for t in tables if t["right"] > t["edge"] + 1 and not t["scrolls"]]
    assert not cut, cut
    if width == 1280:  # on a laptop the four columns fit: nothing to scroll
        assert not [t for t in tables if t["scrolls"]], tables


def test_the_long_references_are_split_into_pages(site: Path) -> None:
    """performance.md was one page of 55,000 px: the overview keeps the targets and the
    sections benchmarks/run.py writes, each other area has its page, linked from it."""
    import re

    overview = (site / "performance.html").read_text(encoding="utf-8")
    areas = sorted(site.glob("performance-*.html"))
    assert len(areas) >= 4
    for page in areas:
        assert f'href="{page.name}"' in overview, page.name
    text = len(re.sub(r"<[^>]+>", "", overview.split("<article", 1)[1]))
    assert text < 60_000, text
