"""The figure of a mechanism, drawn like that of a textbook exercise (matplotlib).

:func:`draw_mechanism` draws the :class:`~resonant.views.sketch.Sketch` of a
model (:func:`resonant.views.sketch.sketch` computes it): blocks, bars and discs,
pins, springs as zig-zags and dampers as dash-pots, hatched supports (a moving
one with its signal), forces and torques as labelled arrows and the generalized
coordinates as labelled arrows (blue).  matplotlib's object API only: a
:class:`~matplotlib.figure.Figure` is made directly (never through ``pyplot``),
given ``ax=`` the drawing goes into the caller's axes.  Text from the model file
is drawn without math parsing, so a ``$`` in a name is shown as it is.

Examples
--------
>>> import pathlib, resonant
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples" / "parts" / "pendulum.toml"
>>> fig = draw_mechanism(resonant.load(path))
>>> sorted(t.get_text() for t in fig.axes[0].texts)
['$\\\\theta$', '$s(t)$', 'bob']
"""

from __future__ import annotations

import io
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TypedDict, Unpack

from ..charts import FIGURE_DPI
from ..charts import figure_of as _figure_of
from ..errors import AnalysisError, ModelError, Problem
from ..model import Model
from .sketch import Arc, Arrow, BodyShape, Label, LinkShape, Point, Sketch, Support, sketch

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    from matplotlib.axes import Axes
    from matplotlib.backend_bases import RendererBase
    from matplotlib.figure import Figure
    from matplotlib.transforms import Bbox

#: formats ``resonant draw`` writes (from the file ending)
FORMATS = (".svg", ".png", ".pdf")
#: colours: parts in greys, forces dark red, generalized coordinates blue
INK, FILL, FORCE, COORDINATE = "#1d1d1f", "#d9d6cf", "#a8322d", "#1f4e9c"


def drawing_format(path: str | Path) -> str:
    """The format of a drawing file from its ending (``"svg"``, ``"png"``, ``"pdf"``).

    Raises
    ------
    ModelError
        For any other ending.

    Examples
    --------
    >>> drawing_format("figure.SVG")
    'svg'
    """
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ModelError(Problem(f"cannot tell the drawing format from '{path}': use a file "
                                 "ending in .svg, .png or .pdf", "-o"))
    return suffix[1:]


class _TextOptions(TypedDict, total=False):
    """The keyword arguments the drawing gives :meth:`matplotlib.axes.Axes.text`."""

    ha: str
    va: str
    fontsize: float
    color: str
    style: str


def _text(ax: Axes, at: Point, label: Label, **options: Unpack[_TextOptions]) -> None:
    if not label.text:
        return
    text = f"${label.text}$" if label.math else label.text
    options.setdefault("fontsize", 11 if label.math else 9)
    ax.text(at[0], at[1], text, parse_math=label.math, zorder=8, **options)


def _along(a: Point, b: Point, t: float, side: float = 0.0) -> Point:
    d = (b[0] - a[0], b[1] - a[1])
    n = math.hypot(*d) or 1.0
    return (a[0] + t * d[0] - side * d[1] / n, a[1] + t * d[1] + side * d[0] / n)


def _zigzag(link: LinkShape, u: float) -> list[Point]:
    a, b = link.start, link.end
    length = math.hypot(b[0] - a[0], b[1] - a[1])
    lead = min(0.2, 0.06 * u / length) if length else 0.2
    teeth = 8
    amplitude = 0.045 * u
    points = [a, _along(a, b, lead)]
    for i in range(teeth):
        t = lead + (1 - 2 * lead) * (i + 0.5) / teeth
        points.append(_along(a, b, t, amplitude * (1 if i % 2 == 0 else -1)))
    points += [_along(a, b, 1 - lead), b]
    return points


def coil(link: LinkShape, u: float, turns: int = 6, steps: int = 24) -> list[Point]:
    """A torsion spring seen from the side: a coil wound about the shaft from ``start`` to
    ``end`` (a prolate cycloid: loops of radius 0.05 u, each advancing along the shaft).

    Examples
    --------
    >>> from resonant.views.sketch import Label
    >>> link = LinkShape("spring", "s", (0.0, 0.0), (1.0, 0.0), Label(""), torsion=True)
    >>> points = coil(link, 1.0)
    >>> points[0], points[-1]
    ((0.0, 0.0), (1.0, 0.0))
    >>> max(abs(y) for _, y in points) <= 0.05 + 1e-12
    True
    """
    a, b = link.start, link.end
    length = math.hypot(b[0] - a[0], b[1] - a[1])
    lead = min(0.2, 0.06 * u / length) if length else 0.2
    radius = 0.05 * u
    pitch = (1 - 2 * lead) / turns
    # each turn runs back by more than it advances at its top: a loop, as a coil looks
    back = 0.4 * pitch
    points = [a]
    for k in range(turns * steps + 1):
        theta = 2 * math.pi * k / steps
        t = lead + pitch * k / steps + back * (math.cos(theta) - 1)
        points.append(_along(a, b, max(0.0, t), radius * math.sin(theta)))
    points += [_along(a, b, 1 - lead), b]
    return points


def _draw_spring(ax: Axes, link: LinkShape, u: float) -> None:
    if link.torsion:  # the shaft, and the coil about it
        ax.plot([link.start[0], link.end[0]], [link.start[1], link.end[1]], color=INK,
                linewidth=0.7, zorder=2, dashes=(6, 2, 1, 2))
        xs, ys = zip(*coil(link, u))
        ax.plot(xs, ys, color=INK, linewidth=1.1, zorder=2)
        return
    xs, ys = zip(*_zigzag(link, u))
    ax.plot(xs, ys, color=INK, linewidth=1.1, zorder=2, solid_joinstyle="miter")


def _draw_damper(ax: Axes, link: LinkShape, u: float) -> None:
    a, b = link.start, link.end
    w = 0.05 * u
    cyl0, cyl1, plate = 0.35, 0.65, 0.55
    segments = [
        [a, _along(a, b, cyl0)],  # lead to the cylinder's bottom
        [_along(a, b, cyl0, -w), _along(a, b, cyl0, w)],  # bottom
        [_along(a, b, cyl0, -w), _along(a, b, cyl1, -w)],  # walls
        [_along(a, b, cyl0, w), _along(a, b, cyl1, w)],
        [_along(a, b, plate, -0.75 * w), _along(a, b, plate, 0.75 * w)],  # piston
        [_along(a, b, plate), b],  # rod
    ]
    for seg in segments:
        xs, ys = zip(*seg)
        ax.plot(xs, ys, color=INK, linewidth=1.1, zorder=2, solid_capstyle="butt")


def _link_label(ax: Axes, link: LinkShape, u: float) -> None:
    _text(ax, link.label_at, link.label, ha="center", va="center")


def _draw_support(ax: Axes, support: Support, u: float) -> None:
    from matplotlib.patches import Polygon

    n = support.normal
    t = (-n[1], n[0])
    p = support.position
    half = support.width / 2
    a = (p[0] - half * t[0], p[1] - half * t[1])
    b = (p[0] + half * t[0], p[1] + half * t[1])
    depth = 0.06 * u
    if support.post is not None:
        ax.plot([support.post[0], p[0]], [support.post[1], p[1]], color=INK, linewidth=2.2,
                zorder=1, solid_capstyle="butt")
    # a light band behind the hatching, then the ground line and its hatch
    band = [a, b, (b[0] - depth * n[0], b[1] - depth * n[1]),
            (a[0] - depth * n[0], a[1] - depth * n[1])]
    ax.add_patch(Polygon(band, closed=True, facecolor="#ece9e3", edgecolor="none", zorder=0))
    ax.plot([a[0], b[0]], [a[1], b[1]], color=INK, linewidth=1.4, zorder=1)
    slant = 0.6 * depth
    count = max(4, int((support.width - slant) / (0.045 * u)))
    for i in range(count + 1):
        s = -half + slant + (support.width - slant) * i / count
        x0, y0 = p[0] + s * t[0], p[1] + s * t[1]
        x1 = x0 - depth * n[0] - 0.6 * depth * t[0]
        y1 = y0 - depth * n[1] - 0.6 * depth * t[1]
        ax.plot([x0, x1], [y0, y1], color=INK, linewidth=0.7, zorder=1)
    if support.signals:
        # the prescribed motion: a double arrow beyond the hatch, with the signal
        from matplotlib.patches import FancyArrowPatch

        motion = support.motion or t
        centre = (p[0] - 2.4 * depth * n[0], p[1] - 2.4 * depth * n[1])
        half_arrow = 0.09 * u
        start = (centre[0] - half_arrow * motion[0], centre[1] - half_arrow * motion[1])
        end = (centre[0] + half_arrow * motion[0], centre[1] + half_arrow * motion[1])
        ax.add_patch(FancyArrowPatch(start, end, arrowstyle="<|-|>", mutation_scale=9,
                                     color=FORCE, linewidth=1.0, zorder=6))
        side = (-motion[1], motion[0])
        if side[1] < 0 or (side[1] == 0 and side[0] > 0):
            side = (-side[0], -side[1])  # the label above or left of the arrow
        _text(ax, (centre[0] + 0.07 * u * side[0], centre[1] + 0.07 * u * side[1]),
              support.label, ha="center", va="center", color=FORCE)


def _room(at: Point, busy: Sequence[tuple[Point, Point]]) -> float:
    """How far ``at`` is from the nearest busy segment (arrows, springs)."""
    best = math.inf
    for a, b in busy:
        d = (b[0] - a[0], b[1] - a[1])
        n = d[0] ** 2 + d[1] ** 2
        t = 0.0 if n == 0 else max(0.0, min(1.0, ((at[0] - a[0]) * d[0] +
                                                   (at[1] - a[1]) * d[1]) / n))
        best = min(best, math.hypot(at[0] - a[0] - t * d[0], at[1] - a[1] - t * d[1]))
    return best


def _busy(data: Sketch) -> list[tuple[Point, Point]]:
    """Segments a label should keep away from: arrows and springs."""
    out = [(link.start, link.end) for link in data.links]
    for s in data.supports:  # the ground line and the far edge of its hatch
        t = (-s.normal[1], s.normal[0])
        for depth in (0.0, 0.06 * data.scale):
            base = (s.position[0] - depth * s.normal[0], s.position[1] - depth * s.normal[1])
            out.append(((base[0] - s.width / 2 * t[0], base[1] - s.width / 2 * t[1]),
                        (base[0] + s.width / 2 * t[0], base[1] + s.width / 2 * t[1])))
    for item in (*data.forces, *data.coordinates):
        if isinstance(item, Arrow):
            out.append((item.start, (item.start[0] + item.vector[0],
                                     item.start[1] + item.vector[1])))
        else:  # an arc, and its label beside its middle
            points = [(item.centre[0] + item.radius * math.cos(a),
                       item.centre[1] + item.radius * math.sin(a))
                      for a in (item.start + (item.stop - item.start) * k / 4 for k in range(5))]
            out.extend(zip(points, points[1:]))
    return out


def _corner_label(ax: Axes, body: BodyShape, u: float, busy: Sequence[tuple[Point, Point]],
                  reach: float) -> None:
    """A round body's name at the corner (of four) farthest from arrows and springs."""
    places = [(sx, sy) for sx in (1.0, -1.0) for sy in (-1.0, 1.0)] + [(0.0, -1.0), (0.0, 1.0)]
    r = reach * body.radius
    half = 0.018 * u * len(body.label.text)  # about half the width of the name

    def room(place: tuple[float, float]) -> float:
        sx, sy = place
        x = body.centre[0] + sx * (r + 0.03 * u + half) if sx else body.centre[0]
        y = body.centre[1] + sy * ((r if sx else body.radius) + 0.05 * u)
        return min(_room((x - half, y), busy), _room((x, y), busy), _room((x + half, y), busy))

    sx, sy = max(places, key=room)
    x = body.centre[0] + sx * (r + 0.03 * u)
    y = body.centre[1] + sy * ((r if sx else body.radius) + 0.01 * u)
    _text(ax, (x, y), body.label, ha="left" if sx > 0 else "right" if sx < 0 else "center",
          va="bottom" if sy > 0 else "top")


def _draw_body(ax: Axes, body: BodyShape, u: float, pins: Sequence[Point] = (),
               busy: Sequence[tuple[Point, Point]] = ()) -> None:
    from matplotlib.patches import Circle, Polygon, Rectangle, Wedge

    if body.shape == "block":
        x, y = body.centre
        ax.add_patch(Rectangle((x - body.width / 2, y - body.height / 2), body.width,
                               body.height, angle=math.degrees(body.angle),
                               rotation_point="center", facecolor=FILL, edgecolor=INK,
                               linewidth=1.3, zorder=3))
        at, va = body.centre, "center"
        if any(math.hypot(p[0] - at[0], p[1] - at[1]) < 0.25 * body.height for p in pins):
            # not on what sits at its middle: under its top edge
            at, va = (at[0], at[1] + body.height / 2 - 0.025 * u), "top"
        _text(ax, at, body.label, ha="center", va=va)
    elif body.shape in ("disc", "point"):
        fill = FILL if body.shape == "disc" else "#4a4a4a"
        if body.path and body.path_centre is not None:  # the circle an unbalance runs on
            ax.add_patch(Circle(body.path_centre, body.path, fill=False, edgecolor=INK,
                                linewidth=0.8, linestyle=(0, (4, 3)), zorder=3.5))
            ax.plot([body.path_centre[0], body.centre[0]],
                    [body.path_centre[1], body.centre[1]], color=INK, linewidth=1.0,
                    zorder=3.5)
            ax.add_patch(Circle(body.path_centre, 0.012 * u, facecolor=INK, zorder=3.6))
        ax.add_patch(Circle(body.centre, body.radius, facecolor=fill, edgecolor=INK,
                            linewidth=1.3 if body.shape == "disc" else 0.8, zorder=3))
        if body.shape == "disc":
            # a radius marks the body's rotation, and its centre
            end = (body.centre[0] + body.radius * math.cos(body.angle),
                   body.centre[1] + body.radius * math.sin(body.angle))
            ax.plot([body.centre[0], end[0]], [body.centre[1], end[1]], color=INK,
                    linewidth=0.9, zorder=4)
            ax.add_patch(Circle(body.centre, 0.012 * u, facecolor=INK, zorder=4))
            if 2 * body.radius > 2.2 * 0.02 * u * len(body.label.text):  # the name fits
                _text(ax, (body.centre[0], body.centre[1] - 0.45 * body.radius), body.label,
                      ha="center", va="center")
            else:  # too small to hold its name: beside it, where there is room
                _corner_label(ax, body, u, busy, 0.75)
        else:
            _corner_label(ax, body, u, busy, 1.0)
    elif body.shape == "bar":
        a, b = body.start, body.end
        w = body.width / 2
        corners = [_along(a, b, 0, w), _along(a, b, 1, w), _along(a, b, 1, -w),
                   _along(a, b, 0, -w)]
        ax.add_patch(Polygon(corners, closed=True, facecolor="#bdb8ae", edgecolor=INK,
                             linewidth=1.0, zorder=3))
        if body.bob:
            ax.add_patch(Circle(body.centre, body.bob, facecolor="#4a4a4a", edgecolor=INK,
                                linewidth=0.8, zorder=4))
        if body.gravity_centre is not None:
            r = max(0.022 * u, 0.7 * w)
            c = body.gravity_centre
            ax.add_patch(Circle(c, r, facecolor="white", edgecolor=INK, linewidth=0.8,
                                zorder=4))
            for start in (0, 180):
                ax.add_patch(Wedge(c, r, start, start + 90, facecolor=INK, edgecolor=INK,
                                   linewidth=0.5, zorder=4))
        if body.bob:  # the name beside the point mass
            at = (body.centre[0] - body.bob - 0.03 * u, body.centre[1] + body.bob)
        else:
            at = _along(a, b, 0.3, -(0.05 * u + w))
        _text(ax, at, body.label, ha="right" if b[1] < a[1] else "left", va="center")


def _draw_arrow(ax: Axes, arrow: Arrow, u: float) -> None:
    from matplotlib.patches import FancyArrowPatch

    colour = FORCE if arrow.kind == "force" else COORDINATE
    s = arrow.start
    e = (s[0] + arrow.vector[0], s[1] + arrow.vector[1])
    ax.add_patch(FancyArrowPatch(s, e, arrowstyle="-|>", mutation_scale=12, color=colour,
                                 linewidth=1.4, shrinkA=0, shrinkB=0, zorder=7))
    direction = (arrow.vector[0], arrow.vector[1])
    length = math.hypot(*direction) or 1.0
    d = (direction[0] / length, direction[1] / length)
    if arrow.kind == "coordinate":  # the reference mark at the start
        tick = 0.035 * u
        ax.plot([s[0] - tick * d[1], s[0] + tick * d[1]], [s[1] + tick * d[0],
                s[1] - tick * d[0]], color=colour, linewidth=1.2, zorder=7)
    at = (e[0] + 0.05 * u * d[0], e[1] + 0.05 * u * d[1])
    ha = "left" if d[0] > 0.3 else "right" if d[0] < -0.3 else "center"
    va = "bottom" if d[1] > 0.3 else "top" if d[1] < -0.3 else "center"
    _text(ax, at, arrow.label, ha=ha, va=va, color=colour)


def _draw_arc(ax: Axes, arc: Arc, u: float) -> None:
    from matplotlib.patches import FancyArrowPatch
    from matplotlib.path import Path as MplPath

    colour = FORCE if arc.kind == "torque" else COORDINATE
    steps = 24
    angles = [arc.start + (arc.stop - arc.start) * i / steps for i in range(steps + 1)]
    vertices = [(arc.centre[0] + arc.radius * math.cos(a),
                 arc.centre[1] + arc.radius * math.sin(a)) for a in angles]
    path = MplPath(vertices, [MplPath.MOVETO] + [MplPath.LINETO] * steps)
    ax.add_patch(FancyArrowPatch(path=path, arrowstyle="-|>", mutation_scale=11,
                                 color=colour, linewidth=1.3, zorder=7))
    middle = (arc.start + arc.stop) / 2
    at = (arc.centre[0] + (arc.radius + 0.06 * u) * math.cos(middle),
          arc.centre[1] + (arc.radius + 0.06 * u) * math.sin(middle))
    _text(ax, at, arc.label, ha="center", va="center", color=colour)


def _draw_points(ax: Axes, data: Sketch) -> None:
    from matplotlib.patches import Circle

    u = data.scale
    for pin in data.pins:
        ax.add_patch(Circle(pin, 0.022 * u, facecolor="white", edgecolor=INK, linewidth=1.1,
                            zorder=6))
    for name, at in data.points.items():
        if any(math.hypot(at[0] - p[0], at[1] - p[1]) < 1e-9 for p in data.pins):
            continue
        ax.add_patch(Circle(at, 0.012 * u, facecolor=INK, zorder=6))
        _text(ax, (at[0] - 0.04 * u, at[1] - 0.02 * u), Label(name.split(".", 1)[1]),
              ha="right", va="top", fontsize=9, style="italic")


def draw_sketch(data: Sketch, ax: Axes | None = None) -> Figure:
    """Draw a :class:`Sketch`; returns the Figure (the one ``ax`` belongs to, if given)."""
    if ax is None:
        from matplotlib.figure import Figure

        xmin, xmax, ymin, ymax = data.bounds()
        ratio = (ymax - ymin + 0.5 * data.scale) / max(xmax - xmin + 0.5 * data.scale, 1e-12)
        # wider for a long chain of parts, so that the labels keep their distance
        width = min(16.0, max(6.4, 1.5 * (xmax - xmin) / data.scale))
        fig = Figure(figsize=(width, min(7.5, max(2.6, width * ratio))))
        ax = fig.add_axes((0.02, 0.02, 0.96, 0.96))
    else:
        fig = _figure_of(ax)
    u = data.scale
    for support in data.supports:
        _draw_support(ax, support, u)
    for link in data.links:
        if link.kind == "damper":
            _draw_damper(ax, link, u)
        else:
            _draw_spring(ax, link, u)
        _link_label(ax, link, u)
    for body in data.bodies:
        occupied = [*data.pins, *(b.centre for b in data.bodies
                                  if b is not body and b.shape == "point")]
        occupied += [b.path_centre for b in data.bodies if b.path_centre is not None]
        _draw_body(ax, body, u, occupied, _busy(data))
    _draw_points(ax, data)
    for item in (*data.forces, *data.coordinates):
        if isinstance(item, Arrow):
            _draw_arrow(ax, item, u)
        else:
            _draw_arc(ax, item, u)
    xmin, xmax, ymin, ymax = data.bounds()
    margin = 0.12 * u
    ax.set_xlim(xmin - 2 * margin, xmax + 2 * margin)  # labels beside the arrows
    ax.set_ylim(ymin - margin, ymax + margin)
    ax.set_aspect("equal", adjustable="box")
    ax.set_axis_off()
    separate_labels(ax)
    return fig


#: the room kept around a label (display points)
LABEL_PAD = 2.0


def _label_obstacles(ax: Axes, renderer: RendererBase) -> list[npt.NDArray[np.float64]]:
    """The drawn lines and arrows of ``ax`` as display-space vertex arrays."""
    import numpy as np
    from matplotlib.patches import FancyArrowPatch

    out = []
    for line in ax.lines:
        xy = np.column_stack([np.asarray(line.get_xdata(), dtype=float),
                              np.asarray(line.get_ydata(), dtype=float)])
        if len(xy) >= 2:
            out.append(ax.transData.transform(xy))
    for patch in ax.patches:
        if isinstance(patch, FancyArrowPatch):
            for poly in patch.get_path().to_polygons(closed_only=False):
                vertices = np.asarray(poly, dtype=float)
                if vertices.shape[0] >= 2:
                    out.append(ax.transData.transform(vertices))
    return out


def _crosses(box: Bbox, polyline: npt.NDArray[np.float64]) -> bool:
    """Whether a display-space polyline enters ``box`` (sampled finely enough for text)."""
    import numpy as np

    a, b = polyline[:-1], polyline[1:]
    steps = np.maximum(1, np.ceil(np.hypot(*(b - a).T) / 2.0)).astype(int)
    for start, end, n in zip(a, b, steps):
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        points = start + t * (end - start)
        inside = (points[:, 0] > box.x0) & (points[:, 0] < box.x1) & \
            (points[:, 1] > box.y0) & (points[:, 1] < box.y1)
        if inside.any():
            return True
    return False


def separate_labels(ax: Axes) -> int:
    """Move each label that overlaps an earlier one, a line or an arrow to the nearest free
    place around it (rings of 8 directions, up to 36 points away); returns how many moved.

    The labels are taken in the order they were drawn (links, bodies, points, then forces
    and coordinates), so the later, smaller ones give way.
    """
    from matplotlib.backend_bases import FigureCanvasBase
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = _figure_of(ax)
    if type(fig.canvas) is FigureCanvasBase:
        FigureCanvasAgg(fig)
    renderer = fig.canvas.get_renderer()
    obstacles = _label_obstacles(ax, renderer)
    placed: list[Bbox] = []
    moved = 0
    scale = fig.dpi / 72.0
    pad = LABEL_PAD * scale

    def free(box: Bbox) -> bool:
        grown = box.expanded(1.0, 1.0).padded(pad)
        return not any(grown.overlaps(p) for p in placed) and \
            not any(_crosses(grown, o) for o in obstacles)

    for text in [t for t in ax.texts if t.get_text()]:
        box = text.get_window_extent(renderer)
        if not free(box):
            origin = ax.transData.transform(text.get_position())
            best = None
            for radius in (4, 8, 12, 18, 26, 36):
                for k in range(8):
                    angle = math.pi / 2 - k * math.pi / 4
                    shift = (radius * scale * math.cos(angle), radius * scale * math.sin(angle))
                    if free(box.translated(*shift)):
                        best = shift
                        break
                if best is not None:
                    break
            if best is not None:
                at = ax.transData.inverted().transform((origin[0] + best[0],
                                                        origin[1] + best[1]))
                text.set_position((float(at[0]), float(at[1])))
                box = text.get_window_extent(renderer)
                moved += 1
        placed.append(box)
    return moved


def draw_mechanism(model: Model | Sketch, path: str | Path | None = None,
                   ax: Axes | None = None) -> Figure:
    """The figure of a model's parts at its reference state, like a textbook exercise's.

    Parameters
    ----------
    model : Model or Sketch
        A model with parts, or its sketch (:func:`resonant.views.sketch.sketch`).
    path : str or Path, optional
        Also write the figure there (``.svg``, ``.png`` or ``.pdf``).
    ax : matplotlib.axes.Axes, optional
        Draw into the caller's axes instead of a new figure.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ModelError
        For a model without parts or an unsupported file ending.
    AnalysisError
        If the file cannot be written.
    """
    if path is not None:
        drawing_format(path)
    data = model if isinstance(model, Sketch) else sketch(model)
    fig = draw_sketch(data, ax)
    if path is not None:
        save_figure(fig, path)
    return fig


def save_figure(fig: Figure, path: str | Path) -> None:
    """Write a drawing (format from the ending), with reproducible SVG ids."""
    import matplotlib
    from matplotlib.backend_bases import FigureCanvasBase
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fmt = drawing_format(path)
    if type(fig.canvas) is FigureCanvasBase:
        FigureCanvasAgg(fig)
    metadata = {"Date": None} if fmt == "svg" else None
    try:
        with matplotlib.rc_context({"svg.hashsalt": "resonant-drawing"}):
            fig.savefig(path, format=fmt, dpi=FIGURE_DPI if fmt == "png" else "figure",
                        metadata=metadata, bbox_inches="tight", pad_inches=0.08)
    except OSError as exc:
        raise AnalysisError(f"cannot write the drawing '{path}': "
                            f"{exc.strerror or exc}") from None


def to_svg(data: Sketch, salt: str = "resonant-drawing") -> str:
    """The drawing as an ``<svg>`` element (no XML prolog) for inline HTML."""
    import matplotlib

    buffer = io.StringIO()
    fig = draw_sketch(data)
    with matplotlib.rc_context({"svg.hashsalt": salt, "svg.fonttype": "path"}):
        fig.savefig(buffer, format="svg", metadata={"Date": None}, bbox_inches="tight",
                    pad_inches=0.08)
    text = buffer.getvalue()
    text = re.sub(r"<metadata>.*?</metadata>\s*", "", text[text.find("<svg"):], flags=re.S)
    return text.strip()


def labels(fig: Figure) -> Sequence[str]:
    """The texts of a drawing (for tests and checks)."""
    return [t.get_text() for ax in fig.axes for t in ax.texts]


__all__ = ["draw_mechanism", "draw_sketch", "save_figure", "to_svg", "drawing_format",
           "labels", "FORMATS"]
