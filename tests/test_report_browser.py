"""The HTML report in a real browser: MathML is laid out, SVG plots are drawn.

Runs headless Chromium (Debian package ``chromium``) on a copy of the report
with a small script appended that writes the rendered sizes of the ``math``,
``mtable`` (matrices) and ``svg`` elements into the DOM, then reads them back
from ``--dump-dom``.  Skipped, with the reason, when Chromium is not installed.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import pytest

from conftest import EXAMPLES, run_cli

BROWSERS = ("chromium", "chromium-browser", "google-chrome")

PROBE = """
<script>
window.addEventListener("load", () => {
  const box = (e) => { const r = e.getBoundingClientRect(); return [r.width, r.height]; };
  const line = parseFloat(getComputedStyle(document.querySelector("p")).lineHeight);
  const data = {
    math: [...document.querySelectorAll("math")].map(box),
    mtable: [...document.querySelectorAll("mtable")].map(box),
    mfrac: [...document.querySelectorAll("mfrac")].map(box),
    svg: [...document.querySelectorAll("figure svg")].map(box),
    paragraphLine: line,
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


def _chromium(browser: str, profile, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
         "--no-first-run", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", f"--user-data-dir={profile}", *args],
        capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def browser() -> str:
    found = _browser()
    if found is None:
        pytest.skip("Chromium is not installed (apt-get install -y chromium); the HTML "
                    "report cannot be rendered in a real browser here")
    return found


def test_mathml_and_svg_are_rendered(browser, tmp_path):
    report = tmp_path / "cart.html"
    code, _, err = run_cli(["report", EXAMPLES / "cart_pendulum.toml", "-o", report])
    assert code == 0, err
    page = report.read_text(encoding="utf-8")
    probe = tmp_path / "probe.html"
    probe.write_text(page.replace("</body>", PROBE + "</body>"), encoding="utf-8")
    result = _chromium(browser, tmp_path / "profile", "--virtual-time-budget=10000",
                       "--dump-dom", probe.as_uri())
    match = re.search(r'<pre id="probe">(.*?)</pre>', result.stdout, re.S)
    assert match, f"no probe output; stderr:\n{result.stderr[-2000:]}"
    data = json.loads(match.group(1).replace("&quot;", '"'))
    assert len(data["math"]) == page.count("<math") >= 50
    assert all(w > 0 and h > 0 for w, h in data["math"]), "a formula has no rendered size"
    line = data["paragraphLine"]
    # laid out as MathML: fractions and matrices are two-dimensional, taller than text
    assert data["mfrac"] and max(h for _, h in data["mfrac"]) > 1.2 * line
    matrices = data["mtable"]
    assert matrices and all(h > 0 for _, h in matrices)
    assert max(h for _, h in matrices) > 2.5 * line  # the 4 x 4 system of Eq. (39)
    assert len(data["svg"]) == 2
    assert all(w > 300 and h > 150 for w, h in data["svg"])


def test_screenshot(browser, tmp_path):
    report = tmp_path / "free.html"
    code, _, err = run_cli(["report", EXAMPLES / "two_dof_free.toml", "-o", report])
    assert code == 0, err
    shot = tmp_path / "shot.png"
    result = _chromium(browser, tmp_path / "profile", "--hide-scrollbars",
                       f"--screenshot={shot}", "--window-size=1000,1400", report.as_uri())
    assert shot.exists() and shot.stat().st_size > 20_000, result.stderr[-2000:]
