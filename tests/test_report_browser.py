"""The HTML report in a real browser with no math font: formulas are drawn, nothing is cut.

Runs headless Chromium (Debian package ``chromium``) with the system's fonts only
(Debian's defaults have no OpenType math font, so MathML brackets would not
stretch) on a copy of the report with a small script appended that measures the
drawn formulas and writes the results into the DOM, read back from
``--dump-dom``.  Checked on the reference exercise and on a damped 4-mass chain
whose equation of motion is a row of 4 x 4 matrices far wider than the page:

* every formula is drawn as SVG (no MathML left visible),
* the brackets of a 4 x 4 matrix stretch over more than two text lines,
* no formula reaches past the text column, on screen (1000 px) and with the
  ``@media print`` rules applied at the width of an A4 page (print emulation).

Skipped, with the reason, when Chromium is not installed.  ``python
tests/test_report_browser.py`` writes the screenshots ``docs/report-screenshot.png``
and ``docs/report-screenshot-4dof.png``.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from conftest import EXAMPLES, run_cli

BROWSERS = ("chromium", "chromium-browser", "google-chrome")
DOCS = Path(__file__).parents[1] / "docs"

#: A4 (210 mm) less Chromium's default print margins (2 x 0.4 in), in CSS px
PRINT_WIDTH = 717

CHAIN4 = """
title = "Damped 4-mass chain with a harmonic force"

[parameters]
m1 = 1.0
m2 = 1.5
m3 = 2.0
m4 = 2.5
k1 = 1000
k2 = 1200
k3 = 1500
k4 = 1800
c1 = 2
c2 = 3
c3 = 4
c4 = 5
F0 = 10
omega = 30

[coordinates]
x1 = "displacement of mass 1"
x2 = "displacement of mass 2"
x3 = "displacement of mass 3"
x4 = "displacement of mass 4"

[signals]
F = "F0*sin(omega*t)"

[energy]
T = "(m1*x1'^2 + m2*x2'^2 + m3*x3'^2 + m4*x4'^2)/2"
U = "(k1*x1^2 + k2*(x2 - x1)^2 + k3*(x3 - x2)^2 + k4*(x4 - x3)^2)/2"
D = "(c1*x1'^2 + c2*(x2' - x1')^2 + c3*(x3' - x2')^2 + c4*(x4' - x3')^2)/2"

[[force]]
name = "F on mass 4"
vector = ["F"]
point = ["x4"]
"""

PROBE = """
<script>
window.addEventListener("load", () => {
  const main = document.querySelector("main");
  const mainBox = main.getBoundingClientRect();
  const pad = getComputedStyle(main);
  const left = mainBox.left + parseFloat(pad.paddingLeft);
  const right = mainBox.right - parseFloat(pad.paddingRight);
  const line = parseFloat(getComputedStyle(document.querySelector("p")).lineHeight);
  const equations = [...document.querySelectorAll(".equation")].map((eq) => {
    const body = eq.querySelector(".body");
    const svgs = [...body.querySelectorAll("svg.m")].map((s) => s.getBoundingClientRect());
    // stretched fences: narrow glyphs taller than a text line
    const fences = [...body.querySelectorAll("svg.m use")]
      .map((u) => u.getBoundingClientRect())
      .filter((r) => r.width > 0 && r.width < 0.8 * line && r.height > line)
      .map((r) => r.height);
    const rows = [...eq.querySelectorAll(".mathml mtable")].map(
      (t) => [t.querySelectorAll(":scope > mtr").length,
              Math.max(0, ...[...t.querySelectorAll(":scope > mtr")].map(
                (r) => r.querySelectorAll(":scope > mtd").length))]);
    return {
      svgs: svgs.length,
      left: Math.min(...svgs.map((r) => r.left)),
      right: Math.max(...svgs.map((r) => r.right)),
      minHeight: Math.min(...svgs.map((r) => r.height)),
      number: eq.querySelector(".number").getBoundingClientRect().left,
      overflow: body.scrollWidth - body.clientWidth,
      fences: fences,
      tables: rows,
    };
  });
  const inline = [...document.querySelectorAll("p svg.m, td svg.m")].map(
    (s) => s.getBoundingClientRect().height);
  const printRules = [...document.styleSheets].flatMap((sheet) => [...sheet.cssRules])
    .filter((r) => r.media && [...r.media].includes("print"))
    .map((r) => r.cssText).join(" ");
  const data = {
    left: left, right: right, line: line,
    pageWidth: document.documentElement.scrollWidth, viewWidth: window.innerWidth,
    pageHeight: document.documentElement.scrollHeight,
    equations: equations, inline: inline,
    visibleMathml: [...document.querySelectorAll("math")]
      .filter((m) => !m.closest(".mathml")).length,
    hiddenMathml: document.querySelectorAll(".mathml math").length,
    figures: [...document.querySelectorAll("figure svg")].map(
      (s) => [s.getBoundingClientRect().width, s.getBoundingClientRect().height]),
    printRules: printRules,
  };
  const out = document.createElement("pre");
  out.id = "probe";
  out.textContent = JSON.stringify(data);
  document.body.appendChild(out);
});
</script>
"""


def _browser() -> str | None:
    return next((b for b in map(shutil.which, BROWSERS) if b), None)


def _chromium(browser: str, profile: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
         "--no-first-run", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", f"--user-data-dir={profile}", *args],
        capture_output=True, text=True, timeout=180)


def _report(model: Path, out: Path) -> str:
    code, _, err = run_cli(["report", model, "-o", out])
    assert code == 0, err
    return out.read_text(encoding="utf-8")


def _measure(browser: str, page: str, tmp: Path, width: int, print_rules: bool) -> dict:
    """The probe's measurements of ``page`` laid out ``width`` px wide.

    With ``print_rules`` the ``@media print`` rules apply on screen (how the page
    is laid out for printing, without a printer)."""
    if print_rules:
        page = page.replace("@media print {", "@media all {")
    probe = tmp / f"probe-{width}-{int(print_rules)}.html"
    probe.write_text(page.replace("</body>", PROBE + "</body>"), encoding="utf-8")
    result = _chromium(browser, tmp / f"profile-{width}-{int(print_rules)}",
                       "--virtual-time-budget=20000", f"--window-size={width},2000",
                       "--dump-dom", probe.as_uri())
    match = re.search(r'<pre id="probe">(.*?)</pre>', result.stdout, re.S)
    assert match, f"no probe output; stderr:\n{result.stderr[-2000:]}"
    return json.loads(match.group(1).replace("&quot;", '"').replace("&amp;", "&"))


def _screenshot(browser: str, html: Path, png: Path, height: int, tmp: Path) -> None:
    result = _chromium(browser, tmp / "profile-shot", "--hide-scrollbars",
                       f"--screenshot={png}", f"--window-size=1000,{height}", html.as_uri())
    assert png.exists() and png.stat().st_size > 20_000, result.stderr[-2000:]


@pytest.fixture(scope="module")
def browser() -> str:
    found = _browser()
    if found is None:
        pytest.skip("Chromium is not installed (apt-get install -y chromium); the HTML "
                    "report cannot be rendered in a real browser here")
    return found


@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> dict[str, tuple[Path, str]]:
    tmp = tmp_path_factory.mktemp("reports")
    chain = tmp / "chain4.toml"
    chain.write_text(CHAIN4, encoding="utf-8")
    out = {}
    for name, model in (("cart", EXAMPLES / "cart_pendulum.toml"), ("chain4", chain)):
        html = tmp / f"{name}.html"
        out[name] = (html, _report(model, html))
    return out


def _check_layout(data: dict, where: str) -> None:
    slack = 1.0  # px, rounding of the layout
    assert data["pageWidth"] <= data["viewWidth"], f"{where}: the page scrolls sideways"
    assert data["visibleMathml"] == 0, f"{where}: a formula fell back to MathML"
    for number, eq in enumerate(data["equations"], 1):
        assert eq["svgs"] >= 1, f"{where}: equation {number} is not drawn"
        assert eq["minHeight"] > 0, f"{where}: equation {number} has an empty piece"
        assert eq["left"] >= data["left"] - slack, f"{where}: equation {number} cut on the left"
        assert eq["right"] <= data["right"] + slack, \
            f"{where}: equation {number} reaches past the text column"
        assert eq["right"] <= eq["number"] + slack, \
            f"{where}: equation {number} runs into its number"
        assert eq["overflow"] <= slack, f"{where}: equation {number} overflows its box"


def _matrix_fences(data: dict, rows: int) -> list[float]:
    """Heights of the stretched fences of the equations holding a rows x rows matrix."""
    return [h for eq in data["equations"] if [rows, rows] in eq["tables"] for h in eq["fences"]]


@pytest.mark.parametrize("name", ["cart", "chain4"])
def test_formulas_drawn_and_never_cut(browser, pages, tmp_path, name):
    html, page = pages[name]
    assert "<script" not in page and "http://" not in page.replace(
        "http://www.w3.org/", "")  # self-contained: no scripts, no remote resources
    screen = _measure(browser, page, tmp_path, 1000, print_rules=False)
    line = screen["line"]
    assert len(screen["equations"]) == page.count('<div class="equation">') >= 40
    assert screen["hiddenMathml"] >= len(screen["equations"])  # the accessible copy
    # brackets of a 4 x 4 matrix stretch over its rows: taller than two text lines
    fences = _matrix_fences(screen, 4)
    assert fences, "no 4 x 4 matrix in the report"
    assert max(fences) > 2 * line, (max(fences), line)
    # inline formulas sit in the text lines: about a line high, never collapsed
    assert screen["inline"] and all(0.2 * line < h < 4 * line for h in screen["inline"])
    assert len(screen["figures"]) == 2
    assert all(w > 300 and h > 150 for w, h in screen["figures"])
    _check_layout(screen, f"{name} on screen")
    # printing: the print rules keep formulas within the page and never split them
    assert "svg.m" in screen["printRules"] and "max-width: 100%" in screen["printRules"]
    assert "break-inside: avoid" in screen["printRules"]
    printed = _measure(browser, page, tmp_path, PRINT_WIDTH, print_rules=True)
    _check_layout(printed, f"{name} printed")
    assert max(_matrix_fences(printed, 4)) > 2 * printed["line"]


def test_wide_equation_is_broken_not_shrunk(browser, pages, tmp_path):
    """The 4-mass chain's M q'' + C q' + K q = F is wider than the page: it is broken
    between its terms, and its pieces keep the size of the other formulas."""
    _, page = pages["chain4"]
    data = _measure(browser, page, tmp_path, PRINT_WIDTH, print_rules=True)
    wide = [eq for eq in data["equations"] if eq["tables"].count([4, 4]) == 3]
    assert wide, "no equation with the three 4 x 4 matrices"
    # all brackets of the three matrices and four vectors still stretch fully
    assert sum(h > 2 * data["line"] for h in wide[0]["fences"]) >= 14


def test_screenshot(browser, pages, tmp_path):
    for name in ("cart", "chain4"):
        html, _ = pages[name]
        shot = tmp_path / f"{name}.png"
        _screenshot(browser, html, shot, 3000, tmp_path)


def main() -> None:
    """Write the documentation's screenshots of both reports (whole pages, 1000 px wide)."""
    browser = _browser()
    if browser is None:
        sys.exit("chromium is not installed")
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        chain = tmp / "chain4.toml"
        chain.write_text(CHAIN4, encoding="utf-8")
        for model, png in ((EXAMPLES / "cart_pendulum.toml", "report-screenshot.png"),
                           (chain, "report-screenshot-4dof.png")):
            html = tmp / "report.html"
            page = _report(model, html)
            height = _measure(browser, page, tmp, 1000, print_rules=False)["pageHeight"]
            _screenshot(browser, html, DOCS / png, height, tmp)
            print(f"wrote {DOCS / png} (1000 x {height})")


if __name__ == "__main__":
    main()
