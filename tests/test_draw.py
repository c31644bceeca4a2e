"""``resonant draw`` -- the figure of a mechanism described by its parts (docs/parts.md).

The geometry is checked on the sketch (the computed figure data, in model units), the
drawing on the matplotlib Figure (its texts and patches), the command on its files and
exit statuses.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import resonant
from conftest import EXAMPLES, run_cli
from resonant.errors import ModelError
from resonant.views.drawing import draw_mechanism, drawing_format, labels, to_svg
from resonant.views.sketch import Arc, Arrow, sketch

PARTS = sorted((EXAMPLES / "parts").glob("*.toml"))


def load_text(text: str) -> resonant.Model:
    return resonant.loads(text, source="test.toml")


@pytest.mark.parametrize("path", PARTS, ids=lambda p: p.stem)
def test_every_parts_example_draws(path: Path, tmp_path: Path) -> None:
    for suffix in (".svg", ".png"):
        out = tmp_path / f"{path.stem}{suffix}"
        status, _, err = run_cli(["draw", path, "-o", out])
        assert status == 0, err
        assert out.stat().st_size > 2000
    assert (tmp_path / f"{path.stem}.svg").read_text().lstrip().startswith(("<?xml", "<svg"))
    assert (tmp_path / f"{path.stem}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    model = resonant.load(path)
    fig = draw_mechanism(model)
    texts = labels(fig)
    data = sketch(model)
    # every body named, every coordinate drawn and labelled
    for body in model.parts.parts.bodies:
        assert body.name in texts
    assert not data.undrawn
    assert len(data.coordinates) == len(model.coordinates)
    for q in model.coordinates:
        assert any(q[0] in t for t in texts if t.startswith("$")), (q, texts)
    assert len(fig.axes[0].patches) >= len(model.parts.parts.bodies)


def test_cart_pendulum_geometry() -> None:
    """The reference exercise: the rod hangs from the cart's joint B; its end C is l below."""
    model = resonant.load(EXAMPLES / "parts" / "cart_pendulum.toml")
    data = sketch(model)
    length = model.parameter_values["l"]
    shapes = {b.name: b for b in data.bodies}
    assert shapes["cart"].shape == "block" and shapes["rod"].shape == "bar"
    rod = shapes["rod"]
    assert rod.start == pytest.approx(shapes["cart"].centre)
    assert rod.end[0] - rod.start[0] == pytest.approx(0.0, abs=1e-12)
    assert rod.start[1] - rod.end[1] == pytest.approx(length)
    assert rod.gravity_centre == pytest.approx((rod.start[0], rod.start[1] - length / 2))
    assert data.points["rod.C"] == pytest.approx(rod.end)
    # the support (r = 0 at the reference state, on the cart) is drawn to the left of the
    # cart, the spring between them; its signal r(t) is named
    (support,) = data.supports
    assert support.position[0] < shapes["cart"].centre[0] - shapes["cart"].width / 2
    assert support.signals == ("r",) and support.motion == pytest.approx((1.0, 0.0))
    (spring,) = data.links
    assert spring.kind == "spring" and spring.label.text == "k"
    assert spring.end[0] == pytest.approx(shapes["cart"].centre[0] - shapes["cart"].width / 2)
    # F(t) at C to the right; x1 at the cart, x2 at C, both to the right
    (force,) = data.forces
    assert isinstance(force, Arrow) and force.start == pytest.approx(data.points["rod.C"])
    assert force.vector[0] > 0 and force.vector[1] == 0 and force.label.text == "F(t)"
    x1, x2 = data.coordinates
    assert isinstance(x1, Arrow) and isinstance(x2, Arrow)
    assert x1.vector[0] > 0 and x2.vector[0] > 0
    assert abs(x1.start[0] - shapes["cart"].centre[0]) < 1e-12
    assert abs(x2.start[0] - data.points["rod.C"][0]) < 1e-12
    texts = labels(draw_mechanism(model))
    assert {"$x_{1}$", "$x_{2}$", "$F(t)$", "$r(t)$", "$k$", "cart", "rod", "C"} <= set(texts)


def test_two_letter_names_are_a_letter_with_an_index() -> None:
    """The quarter car's ks, cs, kt, ct are drawn as k_s, c_s, k_t, c_t (italic letter,
    subscript), as the report and the explore page write them, never upright "ks"."""
    model = resonant.load(EXAMPLES / "parts" / "quarter_car.toml")
    texts = set(labels(draw_mechanism(model)))
    assert {"$k_{s}$", "$c_{s}$", "$k_{t}$", "$c_{t}$"} <= texts, texts
    assert not {"$\\mathrm{ks}$", "$\\mathrm{cs}$", "ks", "cs"} & texts


def test_pinned_rod_end_follows_parameters_and_equilibrium() -> None:
    """A rod at a nonzero reference angle: its end at l (sin a, -cos a) from the pin."""
    model = load_text("""
gravity = "g"
[parameters]
m = 1
l = 1.5
g = 9.81
a = 0.3
[coordinates]
phi = ""
[equilibrium]
phi = "a"
[[point]]
name = "O"
position = ["0.2", "1"]
[[body]]
name = "rod"
mass = "m"
inertia = "m*l^2/12"
pin = "O"
angle = "phi"
centre = ["0", "-l/2"]
points = { E = ["0", "-l"] }
[energy]
U = "-m*g*l/2*(cos(phi) - cos(a)) + m*g*l/2*sin(a)*(phi - a)"
""")
    data = sketch(model)
    (rod,) = data.bodies
    assert rod.start == pytest.approx((0.2, 1.0))
    assert rod.end == pytest.approx((0.2 + 1.5 * math.sin(0.3), 1.0 - 1.5 * math.cos(0.3)))
    (arc,) = data.coordinates
    assert isinstance(arc, Arc) and arc.centre == pytest.approx((0.2, 1.0))
    assert arc.stop > arc.start  # phi counter-clockwise


def test_shapes_and_hints() -> None:
    model = load_text("""
[parameters]
m = 2
R = 0.5
k = 1
[coordinates]
x = ""
[[point]]
name = "wall"
position = ["-2", "R"]
[[body]]
name = "wheel"
mass = "m"
inertia = "m*R^2/2"
position = ["x", "R"]
angle = "-x/R"
[[body]]
name = "box"
mass = "m"
position = ["x + 2", "0"]
shape = "block"
size = ["1.2", "0.4"]
[[body]]
name = "tiny"
mass = "m"
position = ["x + 3", "0"]
shape = "disc"
size = "1e-9"
[[spring]]
between = ["wall", "wheel"]
stiffness = "k"
along = ["1", "0"]
""")
    data = sketch(model)
    shapes = {b.name: b for b in data.bodies}
    assert shapes["wheel"].shape == "disc" and shapes["wheel"].radius == pytest.approx(0.5)
    assert (shapes["box"].width, shapes["box"].height) == pytest.approx((1.2, 0.4))
    assert shapes["tiny"].radius >= 0.04 * data.scale  # a minimum size
    # the wheel rolls: a floor under it
    assert any(s.position == pytest.approx((0.0, 0.0)) and s.normal == (0.0, 1.0)
               for s in data.supports)


def test_bad_hint_is_a_model_error() -> None:
    with pytest.raises(ModelError, match=r'\[body "b"\] shape: shape must be one of'):
        load_text("""
[parameters]
m = 1
[coordinates]
x = ""
[[body]]
name = "b"
mass = "m"
position = ["x", "0"]
shape = "triangle"
""")


def test_along_springs_are_spread_apart() -> None:
    """Quarter car: every point at the origin at the reference state; drawn stacked."""
    model = resonant.load(EXAMPLES / "parts" / "quarter_car.toml")
    data = sketch(model)
    shapes = {b.name: b for b in data.bodies}
    road = data.supports[0].position
    assert road[1] < shapes["wheel"].centre[1] < shapes["car"].centre[1]
    # spring and damper between the same points side by side
    tyre = [link for link in data.links if link.name == "tyre"]
    assert {link.kind for link in tyre} == {"spring", "damper"}
    assert abs(tyre[0].start[0] - tyre[1].start[0]) > 0.05 * data.scale


def test_user_text_is_not_mathtext(tmp_path: Path) -> None:
    """A force name with $...$ is drawn as it is (no mathtext), to SVG and PNG."""
    model = load_text(r"""
[parameters]
m = 1
k = 1
[coordinates]
x = ""
[signals]
F = "sin(t)"
[[point]]
name = "wall"
position = ["-1", "0"]
[[body]]
name = "b"
mass = "m"
position = ["x", "0"]
[[spring]]
between = ["wall", "b"]
stiffness = "k"
[[force]]
name = "$\\x$ <b>&amp;"
point = "b"
vector = ["F", "2*F"]
""")
    fig = draw_mechanism(model, tmp_path / "f.svg")
    assert "$\\x$ <b>&amp;" in labels(fig)
    draw_mechanism(model, tmp_path / "f.png")
    svg = to_svg(sketch(model))
    assert "<b>" not in svg


def test_draw_into_callers_axes() -> None:
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.add_subplot(1, 2, 2)
    out = draw_mechanism(resonant.load(EXAMPLES / "parts" / "pendulum.toml"), ax=ax)
    assert out is fig and len(ax.patches) > 0


def test_errors(tmp_path: Path) -> None:
    status, _, err = run_cli(["draw", EXAMPLES / "parts" / "pendulum.toml", "-o",
                              tmp_path / "x.jpg"])
    assert status == 2 and "use a file ending in .svg, .png or .pdf" in err
    status, _, err = run_cli(["draw", EXAMPLES / "cart_pendulum.toml", "-o",
                              tmp_path / "x.svg"])
    assert status == 2 and "has no parts to draw" in err
    assert not (tmp_path / "x.svg").exists()
    status, _, err = run_cli(["draw", EXAMPLES / "parts" / "pendulum.toml", "-o",
                              tmp_path / "missing" / "x.svg"])
    assert status == 2 and "does not exist" in err
    with pytest.raises(ModelError):
        drawing_format("figure.gif")


def test_pulley_on_an_axle() -> None:
    """A body turning about its own centre of gravity is a disc on a post to the ground."""
    model = load_text("""
[parameters]
J = 0.1
r = 0.2
k = 50
[coordinates]
phi = ""
[[point]]
name = "O"
position = ["0", "0"]
[[point]]
name = "floor"
position = ["r", "-1"]
[[body]]
name = "pulley"
mass = 0
inertia = "J"
pin = "O"
angle = "phi"
points = { A = ["r", "0"] }
[[spring]]
between = ["pulley.A", "floor"]
stiffness = "k"
""")
    data = sketch(model)
    (pulley,) = data.bodies
    assert pulley.shape == "disc" and pulley.radius == pytest.approx(0.2)
    axle = next(s for s in data.supports if s.name == "O")
    assert axle.post == pytest.approx((0.0, 0.0)) and axle.position[1] < -0.2
    (arc,) = data.coordinates
    assert isinstance(arc, Arc) and arc.centre == pytest.approx((0.0, 0.0))


def test_unbalance_on_its_circle() -> None:
    model = resonant.load(EXAMPLES / "parts" / "rotating_unbalance.toml")
    data = sketch(model)
    shapes = {b.name: b for b in data.bodies}
    unbalance, machine = shapes["unbalance"], shapes["machine"]
    assert unbalance.shape == "point" and unbalance.path_centre == pytest.approx(machine.centre)
    # at t = 0: u = e, w = 0 -> on the circle to the right of the axle
    assert unbalance.centre[0] - machine.centre[0] == pytest.approx(unbalance.path)
    assert unbalance.path >= 0.1 * data.scale


EXTREME = """title = "a block far out"
[parameters]
m = 1
k = 100
[coordinates]
x = "cart"
[[point]]
name = "wall"
position = ["{wall}", "0"]
[[body]]
name = "cart"
mass = "m"
position = ["x", "0"]
size = "{size}"
[[spring]]
name = "k"
between = ["wall", "cart"]
stiffness = "k"
"""


@pytest.mark.parametrize("wall", ["1e300", "-1e300", "1e150"])
def test_a_point_too_far_out_to_draw_names_the_part(tmp_path: Path, wall: str) -> None:
    """A position of 1e300 overflowed the figure's arithmetic (exit 1); now exit 2 naming
    the part and the key, or (1e150, still drawable after the check) a figure."""
    path = tmp_path / "far.toml"
    path.write_text(EXTREME.format(wall=wall, size="0.2"), encoding="utf-8")
    status, _, err = run_cli(["draw", path, "-o", tmp_path / "far.svg"])
    if abs(float(wall)) > 1e100:
        assert status == 2 and '[point "wall"] position' in err and "too far out" in err
    else:
        assert status in (0, 2) and "internal error" not in err


@pytest.mark.parametrize("size", ["1e300", "-1e300", "1e-300"])
def test_an_extreme_body_size_gives_a_bounded_figure(tmp_path: Path, size: str) -> None:
    """A body size of 1e300 draws (the figure is scaled to it), never an overflow."""
    path = tmp_path / "big.toml"
    path.write_text(EXTREME.format(wall="-1", size=size), encoding="utf-8")
    for suffix in ("svg", "png"):
        status, _, err = run_cli(["draw", path, "-o", tmp_path / f"big.{suffix}"])
        assert status == 0, err
    status, _, err = run_cli(["report", path, "-o", tmp_path / "big.html"])
    assert status == 0, err
