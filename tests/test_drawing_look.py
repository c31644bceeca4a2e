"""Drawings of mechanisms: torsion springs drawn as coils, labels that do not collide, and
every size from the model bounded before it is drawn.

The label check reads the rendered extents of the texts of each drawing (matplotlib's
Agg renderer) and the display-space paths of its lines and arrows.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import resonant
from conftest import EXAMPLES, run_cli
from resonant.views.drawing import _crosses, _label_obstacles, coil, draw_mechanism
from resonant.views.sketch import sketch

PARTS = sorted((EXAMPLES / "parts").glob("*.toml"))


@pytest.mark.parametrize("model", PARTS, ids=lambda p: p.stem)
def test_no_label_overlaps_another_or_a_line(model: Path) -> None:
    fig = draw_mechanism(resonant.load(model))
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in ax.texts if t.get_text()]
    for i, (name, box) in enumerate(boxes):
        for other, second in boxes[i + 1:]:
            assert not box.overlaps(second), f"{name!r} overlaps {other!r}"
    obstacles = _label_obstacles(ax, renderer)
    crossed = [name for name, box in boxes if any(_crosses(box, o) for o in obstacles)]
    # a label may sit on a line only where no free place was found within 36 points
    assert len(crossed) <= 1, f"labels on lines or arrows: {crossed}"


def test_torsion_springs_are_coils_about_the_shaft() -> None:
    data = sketch(resonant.load(EXAMPLES / "parts" / "torsional_chain.toml"))
    springs = [link for link in data.links if link.kind == "spring"]
    assert springs and all(link.torsion for link in springs)
    for link in springs:
        points = np.array(coil(link, data.scale))
        axis = np.subtract(link.end, link.start)
        along = (points - link.start) @ axis / np.dot(axis, axis)
        # a coil turns back on itself: it runs backwards along the shaft in every turn
        assert np.sum(np.diff(along) < 0) >= 6
    straight = sketch(resonant.load(EXAMPLES / "parts" / "cart_pendulum.toml"))
    assert not any(link.torsion for link in straight.links)
    # the page draws it too
    html_data = straight.to_dict()
    assert all("torsion" in link for link in html_data["links"])


@pytest.mark.parametrize("shape", ["disc", "point", "block", "bar"])
@pytest.mark.parametrize("size", ["1e300", "1e160", "1e-300"])
def test_a_huge_or_tiny_size_of_any_shape_is_drawn(tmp_path: Path, shape: str,
                                                   size: str) -> None:
    """Each size is bounded before it is drawn (a disc of radius 1e300 overflowed in the
    clipping of the spring at its rim): every command that draws exits 0."""
    text = (EXAMPLES / "parts" / "cart_pendulum.toml").read_text(encoding="utf-8").replace(
        'name = "cart"\nmass = "m1"', f'name = "cart"\nmass = "m1"\nshape = "{shape}"\n'
                                      f'size = "{size}"')
    model = tmp_path / "big.toml"
    model.write_text(text, encoding="utf-8")
    for command, target in (("draw", "d.svg"), ("draw", "d.png"), ("explore", "p.html"),
                            ("report", "r.html")):
        status, _, err = run_cli([command, model, "-o", tmp_path / target])
        assert status == 0, (command, shape, size, err)
        assert (tmp_path / target).stat().st_size > 0
