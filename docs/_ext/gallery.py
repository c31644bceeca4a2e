"""A Sphinx extension that makes the gallery of the bundled examples while the site builds.

For every model in ``examples/`` (and its ``parts/`` and ``teaching/`` folders) it writes a
page ``gallery/<name>.md`` with the model file, the mechanism drawn from its parts, the
mode shapes, the frequency response about the natural frequencies and, for the models
that are nonlinear beyond small oscillations, the nonlinear frequency response with its
stability — every figure computed by resonant's own API at build time, so the gallery
shows what the code does today.  ``gallery/`` is generated (listed in ``.gitignore``).
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import resonant  # noqa: E402
from resonant.errors import ResonantError  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
FOLDERS = ("", "parts", "teaching")
#: examples whose nonlinear steady state the gallery shows
NONLINEAR = ("duffing.toml", "two_dof_cubic.toml")


def example_files() -> list[Path]:
    """The bundled model files, in a stable order."""
    return [path for folder in FOLDERS
            for path in sorted((ROOT / "examples" / folder).glob("*.toml"))]


def _save(figure: Any, path: Path) -> str:
    figure.savefig(path, dpi=90, bbox_inches="tight")
    plt.close(figure)
    return path.name


def _frequency_range(system: Any) -> tuple[float, float] | None:
    frequencies = system.modes().natural_frequencies
    positive = frequencies[frequencies > 0]
    if positive.size == 0:
        return None
    return 0.3 * float(positive.min()), 1.6 * float(positive.max())


def _figures(model: Any, path: Path, out: Path) -> list[tuple[str, str]]:
    """(caption, image file) for each figure of one example."""
    stem = path.stem if path.parent.name == "examples" else f"{path.parent.name}_{path.stem}"
    figures: list[tuple[str, str]] = []
    if model.parts is not None:
        figures.append(("The mechanism, drawn from its parts (`resonant draw`)",
                        _save(model.draw(), out / f"{stem}_drawing.png")))
    system = model.linearize()
    figures.append(("Mode shapes (`resonant modes --plot`)",
                    _save(system.modes().plot(), out / f"{stem}_modes.png")))
    band = _frequency_range(system)
    if band is not None and "omega" in model.parameters:
        values = np.linspace(band[0], band[1], 400)
        try:
            response = system.sweep("omega", values)
        except ResonantError:
            response = None
        if response is not None:
            figures.append(("Frequency response about the natural frequencies "
                            "(`resonant sweep --param omega`)",
                            _save(response.plot(), out / f"{stem}_sweep.png")))
    if model.campbell_section is not None:
        figures.append(("Campbell diagram: modes tracked over the speed, critical speeds, "
                        "log decrements (`resonant campbell --plot`)",
                        _save(model.campbell().plot(), out / f"{stem}_campbell.png")))
    if path.name in NONLINEAR and band is not None:
        low = float(system.modes().natural_frequencies.min())
        branch = model.nonlinear_sweep("omega", 0.5 * low, 2.5 * low, harmonics=3,
                                       points=150)
        figures.append(("Nonlinear frequency response: stable solid, unstable dashed, "
                        "special points marked (`resonant sweep --nonlinear`)",
                        _save(branch.plot(), out / f"{stem}_nonlinear.png")))
    return figures


def _title(path: Path, model: Any) -> str:
    """The example's title, with its folder where the folder's model shares it (the
    teaching copy of the reference exercise)."""
    title = model.title or path.stem
    folder = path.parent.name
    if folder != "examples" and f"({folder})" not in title:
        title += f" ({folder})"
    return title


def _page(path: Path, model: Any, figures: list[tuple[str, str]]) -> str:
    relative = path.relative_to(ROOT).as_posix()
    title = _title(path, model)
    lines = [f"# {title}", "", f"`{relative}`", "", "```console",
             f"$ resonant solve {relative}", "```", ""]
    for caption, image in figures:
        lines += [f"```{{figure}} {image}", ":alt: " + caption.split(" (")[0], "",
                  caption, "```", ""]
    lines += ["## The model file", "", f"```{{literalinclude}} ../../{relative}",
              ":language: toml", "```", ""]
    return "\n".join(lines)


def build_gallery(app: Any) -> None:
    """Write ``gallery/`` into the source folder: an index and one page per example."""
    out = Path(app.srcdir) / "gallery"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir()
    entries = []
    cards = []
    for path in example_files():
        model = resonant.load(path)
        name = path.stem if path.parent.name == "examples" else \
            f"{path.parent.name}_{path.stem}"
        figures = _figures(model, path, out)
        (out / f"{name}.md").write_text(_page(path, model, figures), encoding="utf-8")
        entries.append(name)
        # the card: the first figure (the mechanism where there are parts) as thumbnail
        thumbnail = figures[-1][1] if model.parts is None and len(figures) > 1 else \
            figures[0][1]
        cards += ["````{container} gallery-card", f"```{{image}} {thumbnail}",
                  f":alt: {_title(path, model)}", f":target: {name}.html", "```", "",
                  f"[{_title(path, model)}]({name}.md)", "````", ""]
    index = ["# Gallery of the bundled examples", "",
             "Every figure on these pages is computed by resonant when the site is built; "
             "`resonant example NAME` writes the model file of one of them.", "",
             "`````{container} gallery-grid", "", *cards, "`````", "",
             "```{toctree}", ":hidden:", ":maxdepth: 1", "", *entries, "```", ""]
    (out / "index.md").write_text("\n".join(index), encoding="utf-8")


def setup(app: Any) -> dict[str, Any]:
    """Register the gallery with Sphinx."""
    app.connect("builder-inited", build_gallery)
    return {"parallel_read_safe": True, "version": "1"}
