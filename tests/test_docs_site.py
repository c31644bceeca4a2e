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
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b",
                          "html", "-d", str(out / ".doctrees"), str(ROOT / "docs"),
                          str(out)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    return out


def test_the_guide_and_the_reference_are_built(site: Path) -> None:
    for page in ("index", "model-format", "parts", "units", "nonlinear", "exercises",
                 "architecture", "api"):
        assert (site / f"{page}.html").is_file(), page
    api = (site / "api.html").read_text(encoding="utf-8")
    assert "resonant.model.types.Model" in api and "Parameters" in api


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
