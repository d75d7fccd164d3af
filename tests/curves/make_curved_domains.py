"""Build the curved catalogue domains (``domains/*.toml`` with ``[[edges]]``); run to rewrite them.

``python tests/curves/make_curved_domains.py [--optimise]`` writes ``plate-hole``, ``disc``,
``annulus``, ``cylinder-channel`` and ``quarter-plate-hole`` into ``domains/``. The layouts:

- around a circular hole (``plate-hole``, ``annulus``, the cylinder of ``cylinder-channel``): a
  zig-zag ring of pentagons, alternately on the hole and on the outer boundary
  (:func:`hole_ring`), so that every arc belongs to one block and every inner vertex to three;
- ``quarter-plate-hole``: the 8 pentagons of the quadrilateral template (``docs/mathematics.md``
  §4) under the transfinite (Coons) map of the unit square onto the curved quadrilateral;
- the channel behind the cylinder: rectangles of the quadrilateral template, turned so that its
  sides with one node face each other (the nodes meet at mid-height);
- ``disc``: a central pentagon, five pentagons around it and five on the circle, one arc each
  (:func:`blockmesh.domain.curved_polygons.disc_layout`, which ``Domain.from_circle`` uses too).

The free parameters (the ring's radii, the template's inner nodes) maximise the smallest angle of
the curved refinement at a few levels; ``--optimise`` searches them again (Nelder-Mead) and
prints what it found. This module is not a test: pytest imports it only for its doctests (none).
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
from pathlib import Path

import numpy as np

from blockmesh.decompose.templates import SQUARE_FACES as _SQUARE_FACES
from blockmesh.decompose.templates import SQUARE_NODES as _SQUARE_NODES
from blockmesh.domain.curved_polygons import disc_layout
from blockmesh.geometry import interior_angles
from blockmesh.refinement.curved import curved_block_levels
from blockmesh.refinement.template import pentagon_template

DOMAINS = Path(__file__).resolve().parents[2] / "domains"


def _e(theta):
    return np.stack([np.cos(theta), np.sin(theta)], axis=-1)


class Layout:
    """Vertices merged by position, blocks, arcs {(a, b): centre}, patches {name: [(a, b)]}."""

    def __init__(self) -> None:
        self.vertices: list[np.ndarray] = []
        self.blocks: list[list[int]] = []
        self.arcs: dict[tuple[int, int], tuple[float, float]] = {}
        self.patches: dict[str, list[tuple[int, int]]] = {}

    def vertex(self, p) -> int:
        p = np.asarray(p, dtype=float)
        for k, q in enumerate(self.vertices):
            if np.hypot(*(p - q)) < 1e-9:
                return k
        self.vertices.append(p)
        return len(self.vertices) - 1

    def add(self, points, faces, arcs=(), patches=()) -> list[int]:
        ids = [self.vertex(p) for p in points]
        self.blocks += [[ids[v] for v in face] for face in faces]
        for a, b, centre in arcs:
            self.arcs[(ids[a], ids[b])] = tuple(map(float, centre))
        for name, a, b in patches:
            self.patches.setdefault(name, []).append((ids[a], ids[b]))
        return ids


def coons_quad(arc_centre, radius, theta_a, theta_b, outer, outer_arc=None, nodes=_SQUARE_NODES):
    """The 18 template nodes on a curved quadrilateral (unit square (u, v) -> plane).

    ``nodes`` are the template's nodes in the unit square (the shipped domains move the inner
    ones, see :func:`optimise_template`).

    Bottom (v = 0): the circle of ``radius`` around ``arc_centre`` from angle ``theta_a`` (u = 0)
    to ``theta_b`` (u = 1). Top (v = 1): the polyline ``outer`` (three points, u = 0, 1/2, 1), or
    with ``outer_arc = (centre, radius)`` the arc through them. Sides: straight.
    """
    c = np.asarray(arc_centre, dtype=float)

    def bottom(u):
        return c + radius * _e(theta_a + np.asarray(u) * (theta_b - theta_a))

    o = np.asarray(outer, dtype=float)

    def top(u):
        u = np.asarray(u)
        if outer_arc is not None:
            oc, r = np.asarray(outer_arc[0], dtype=float), outer_arc[1]
            a0 = math.atan2(*(o[0] - oc)[::-1])
            a1 = math.atan2(*(o[2] - oc)[::-1])
            a1 = a0 + (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
            return oc + r * _e(a0 + u * (a1 - a0))
        w = u[..., None]
        return np.where(w <= 0.5, o[0] + 2 * w * (o[1] - o[0]), o[1] + (2 * w - 1) * (o[2] - o[1]))

    p00, p10, p01, p11 = bottom(0.0), bottom(1.0), top(0.0), top(1.0)
    u, v = nodes[:, 0], nodes[:, 1]
    uu, vv = u[:, None], v[:, None]
    x = (
        (1 - vv) * bottom(u)
        + vv * top(u)
        + (1 - uu) * (p00 + vv * (p01 - p00))
        + uu * (p10 + vv * (p11 - p10))
        - (1 - uu) * (1 - vv) * p00
        - uu * (1 - vv) * p10
        - (1 - uu) * vv * p01
        - uu * vv * p11
    )
    x[[0, 1, 17]] = bottom(np.array([0.0, 0.5, 1.0]))
    x[[6, 7, 8]] = top(np.array([0.0, 0.5, 1.0]))
    return x


#: Template nodes on each side of the unit square: bottom, right, top, left (in order along it).
SIDES = {"bottom": [0, 1, 17], "right": [17, 16, 9, 8], "top": [8, 7, 6], "left": [6, 5, 4, 0]}


def side_edges(name: str, side: str):
    nodes = SIDES[side]
    return [(name, a, b) for a, b in itertools.pairwise(nodes)]


def worst_angles(layout: Layout, level: int = 3) -> tuple[float, float]:
    """Smallest and largest angle of the curved refinement, levels 0..level."""
    vertices = np.array(layout.vertices)
    blocks = np.array(layout.blocks)
    fractions = np.arange(2**level + 1) / 2**level
    along = np.zeros((len(blocks), 5, fractions.size, 2))
    curved = np.zeros((len(blocks), 5), dtype=bool)
    for i, block in enumerate(blocks.tolist()):
        for k in range(5):
            a, b = block[k], block[(k + 1) % 5]
            for key, t in (((a, b), fractions), ((b, a), 1 - fractions)):
                if key in layout.arcs:
                    c = np.array(layout.arcs[key])
                    p, q = vertices[key[0]] - c, vertices[key[1]] - c
                    sweep = math.atan2(p[0] * q[1] - p[1] * q[0], p @ q)
                    theta0 = math.atan2(p[1], p[0])
                    along[i, k] = c + np.hypot(*p) * _e(theta0 + t * sweep)
                    curved[i, k] = True
    lo, hi = 180.0, 0.0
    for step, xy in curved_block_levels(vertices[blocks], along, curved, level):
        angles = interior_angles(xy[:, pentagon_template(step).cells])
        lo, hi = min(lo, float(angles.min())), max(hi, float(angles.max()))
    return lo, hi


def write(name: str, description: str, layout: Layout) -> Path:
    lines = [f"name = {json.dumps(name)}", f"description = {json.dumps(description)}"]
    lines.append("vertices = [")
    lines += [f"  [{float(x)!r}, {float(y)!r}]," for x, y in layout.vertices]
    lines += ["]", "blocks = ["]
    lines += [f"  [{', '.join(map(str, b))}]," for b in layout.blocks]
    lines += ["]", "", "[patches]"]
    for patch, edges in layout.patches.items():
        lines.append(f"{patch} = [{', '.join(f'[{a}, {b}]' for a, b in edges)}]")
    for (a, b), (cx, cy) in layout.arcs.items():
        lines += ["", "[[edges]]", f"arc = [{a}, {b}]", f"center = [{cx!r}, {cy!r}]"]
    path = DOMAINS / f"{name}.toml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


#: Inner nodes of the quadrilateral template (the others lie on its sides).
INNER = [2, 3, 10, 11, 12, 13, 14, 15]


def optimise_template(build, level: int = 3, iterations: int = 3000) -> np.ndarray:
    """Template nodes whose inner nodes maximise the smallest angle of ``build(nodes)``."""
    from scipy.optimize import minimize

    def nodes_of(x):
        nodes = _SQUARE_NODES.copy()
        nodes[INNER] = x.reshape(-1, 2)
        return nodes

    def cost(x):
        nodes = nodes_of(x)
        if np.any(nodes < 0) or np.any(nodes > 1):
            return 1e3
        lo, hi = worst_angles(build(nodes), level)
        return -lo + 5 * max(0.0, hi - 170.0)

    start = _SQUARE_NODES[INNER].ravel()
    result = minimize(cost, start, method="Nelder-Mead", options={"maxiter": iterations})
    return nodes_of(result.x)


#: The template's nodes for ``quarter-plate-hole``: its inner nodes moved by
#: :func:`optimise_template` (smallest angle at level 3: 20.3 -> 25.4 degrees).
QUARTER_NODES = _SQUARE_NODES.copy()
QUARTER_NODES[INNER] = [
    [0.440399, 0.260538], [0.319385, 0.360601], [0.748804, 0.552489], [0.480164, 0.657602],
    [0.370845, 0.567058], [0.368765, 0.478601], [0.717834, 0.466177], [0.690963, 0.381224],
]  # fmt: skip


def quarter_plate_hole(nodes=QUARTER_NODES) -> Layout:
    """OpenFOAM's plateHole geometry: the quarter [0, 2]^2 of a plate with a hole of radius 0.5."""
    layout = Layout()
    x = coons_quad((0, 0), 0.5, math.pi / 2, 0.0, [(0, 2), (2, 2), (2, 0)], nodes=nodes)
    layout.add(
        x,
        _SQUARE_FACES,
        arcs=[(0, 1, (0, 0)), (1, 17, (0, 0))],
        patches=side_edges("hole", "bottom")
        + side_edges("down", "right")
        + [("right", 8, 7), ("up", 7, 6)]
        + side_edges("left", "left"),
    )
    return layout


def _rotate(points, quarter: int):
    c, s = (round(math.cos(quarter * math.pi / 2)), round(math.sin(quarter * math.pi / 2)))
    points = np.asarray(points, dtype=float)
    return np.stack(
        [c * points[..., 0] - s * points[..., 1], s * points[..., 0] + c * points[..., 1]], -1
    )


def _outward(p, q, names):
    """The patch of a straight outer edge from its outward normal: names (right, up, left, down)."""
    d = np.asarray(q) - np.asarray(p)
    normal = (d[1], -d[0])
    k = int(np.argmax([normal[0], normal[1], -normal[0], -normal[1]]))
    return names[k]


def hole_ring(layout, centre, radius, outer, fractions, *, hole, outer_patch=None, outer_arc=False):
    """A zig-zag ring of 2N pentagons between a circular hole and the N points ``outer``.

    ``outer`` (counter-clockwise around ``centre``) are the outer corners ``s_k``; ``N`` hole
    pentagons <a_k, m_k, n_k, m_k+1, a_k+1> alternate with ``N`` outer ones
    <n_k, s_k, s_k+1, n_k+1, m_k+1>: ``n_k`` on the ray to ``s_k``, ``a_k`` and ``m_k`` on the ray
    half way between ``s_k-1`` and ``s_k``. ``fractions = (f_m, f_n)`` place ``m`` and ``n`` that
    far from the hole towards the outside. Every arc belongs to one block and every inner vertex
    to three. Outer edges are arcs around ``centre`` when ``outer_arc``; their patch is
    ``outer_patch(p, q)``.
    """
    c = np.asarray(centre, dtype=float)
    s = np.asarray(outer, dtype=float)
    count = len(s)
    angle = np.arctan2(s[:, 1] - c[1], s[:, 0] - c[0])
    dist = np.hypot(*(s - c).T)
    previous = np.roll(angle, 1)
    between = previous + ((angle - previous) % (2 * math.pi)) / 2
    reach = np.minimum(dist, np.roll(dist, 1)) * np.cos((angle - previous) % (2 * math.pi) / 2)
    f_m, f_n = fractions
    a = [layout.vertex(c + radius * _e(t)) for t in between]
    m = [
        layout.vertex(c + (radius + f_m * (r - radius)) * _e(t))
        for t, r in zip(between, reach, strict=True)
    ]
    n = [
        layout.vertex(c + (radius + f_n * (d - radius)) * _e(t))
        for t, d in zip(angle, dist, strict=True)
    ]
    b = [layout.vertex(p) for p in s]
    for k in range(count):
        j = (k + 1) % count
        layout.blocks.append([a[k], m[k], n[k], m[j], a[j]])
        layout.blocks.append([n[k], b[k], b[j], n[j], m[j]])
        layout.arcs[(a[j], a[k])] = tuple(map(float, c))
        layout.patches.setdefault(hole, []).append((a[j], a[k]))
        if outer_arc:
            layout.arcs[(b[k], b[j])] = tuple(map(float, c))
        if outer_patch is not None:
            name = outer_patch(s[k], s[j])
            if name is not None:
                layout.patches.setdefault(name, []).append((b[k], b[j]))
    return layout


def _square_ring(half: float, centre=(0.0, 0.0)) -> np.ndarray:
    """The corners and side midpoints of a square, counter-clockwise from the right midpoint."""
    c = np.asarray(centre, dtype=float)
    unit = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)]
    return c + half * np.array(unit, dtype=float)


def plate_hole(fractions=(0.45, 0.45)) -> Layout:
    """The Kirsch plate: [-2, 2]^2 with a central hole of radius 0.5 (:func:`hole_ring`)."""
    return hole_ring(
        Layout(), (0, 0), 0.5, _square_ring(2.0), fractions, hole="hole",
        outer_patch=lambda p, q: _outward(p, q, ("right", "top", "left", "bottom")),
    )  # fmt: skip


def annulus(fractions=(0.4, 0.65), sectors: int = 8) -> Layout:
    """The ring between circles of radius 0.5 and 1 around the origin (:func:`hole_ring`)."""
    outer = _e(2 * math.pi * (np.arange(sectors) + 0.5) / sectors)
    return hole_ring(
        Layout(), (0, 0), 0.5, outer, fractions, hole="inner",
        outer_patch=lambda p, q: "outer", outer_arc=True,
    )  # fmt: skip


#: The DFG 2D benchmark channel (Schäfer and Turek 1996): 2.2 x 0.41, cylinder r = 0.05 at
#: (0.2, 0.2).
CHANNEL = {"length": 2.2, "height": 0.41, "centre": (0.2, 0.2), "radius": 0.05, "pieces": 4}


def cylinder_channel(fractions=(0.35, 0.35)) -> Layout:
    """The DFG channel: a zig-zag ring (:func:`hole_ring`) around the cylinder in the box
    [0, H]^2, then rectangles of the quadrilateral template, turned so that its sides with one
    node (at mid-height) face the box and each other."""
    h = CHANNEL["height"]
    names = (None, "walls", "inlet", "walls")  # by outward normal: right (the box side), up, ...
    layout = hole_ring(
        Layout(), CHANNEL["centre"], CHANNEL["radius"], _square_ring(h / 2, (h / 2, h / 2)),
        fractions, hole="cylinder", outer_patch=lambda p, q: _outward(p, q, names),
    )  # fmt: skip
    pieces = CHANNEL["pieces"]
    xs = np.linspace(h, CHANNEL["length"], pieces + 1)
    u, v = _SQUARE_NODES[:, 0], _SQUARE_NODES[:, 1]
    for j in range(pieces):
        width = xs[j + 1] - xs[j]
        x = np.stack([xs[j] + v * width, h * (1 - u)], axis=-1)
        patches = side_edges("walls", "left") + side_edges("walls", "right")
        if j == pieces - 1:
            patches += side_edges("outlet", "top")
        layout.add(x, _SQUARE_FACES, patches=patches)
    layout.patches = {k: layout.patches[k] for k in ("inlet", "outlet", "walls", "cylinder")}
    return layout


def disc(radii=(0.25, 0.43, 0.7)) -> Layout:
    """The unit disc: :func:`blockmesh.domain.curved_polygons.disc_layout` (11 blocks, 5 arcs)."""
    vertices, blocks, arcs, boundary = disc_layout((0.0, 0.0), 1.0, radii)
    layout = Layout()
    layout.vertices = list(vertices)
    layout.blocks = blocks
    layout.arcs = {key: arc.center for key, arc in arcs.items()}  # type: ignore[misc]
    layout.patches = {"boundary": boundary}
    return layout


#: name: (description, builder, the builder's free parameters and how to search them)
DOMAINS_BUILT = {
    "plate-hole": (
        "A square plate [-2, 2]^2 with a central circular hole of radius 0.5 (the Kirsch problem)",
        plate_hole,
    ),
    "quarter-plate-hole": (
        "The quarter [0, 2]^2 of a plate with a hole of radius 0.5 at the corner (OpenFOAM's "
        "plateHole tutorial geometry)",
        quarter_plate_hole,
    ),
    "disc": ("The unit disc: a central pentagon, five around it and five on the circle", disc),
    "annulus": ("The ring between circles of radius 0.5 and 1 around the origin", annulus),
    "cylinder-channel": (
        "The DFG 2D benchmark channel 2.2 x 0.41 with a cylinder of radius 0.05 at (0.2, 0.2)",
        cylinder_channel,
    ),
}


def _search(name: str) -> None:
    """Search the free parameters of one layout again and print them."""
    from scipy.optimize import minimize

    if name == "quarter-plate-hole":
        nodes = optimise_template(quarter_plate_hole)
        print(name, np.round(nodes[INNER], 6).tolist(), worst_angles(quarter_plate_hole(nodes)))
        return
    builder = DOMAINS_BUILT[name][1]
    start = {"disc": [0.25, 0.43, 0.7]}.get(name, [0.4, 0.5])

    def cost(x):
        try:
            lo, hi = worst_angles(builder(tuple(x)), 4)
        except (ValueError, IndexError):
            return 1e3
        return -lo + 5 * max(0.0, hi - 170.0)

    result = minimize(cost, start, method="Nelder-Mead", options={"maxiter": 300})
    print(name, np.round(result.x, 4).tolist(), -result.fun)


def main() -> None:
    import blockmesh

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--optimise", action="store_true", help="search the parameters again")
    args = parser.parse_args()
    for name, (description, builder) in DOMAINS_BUILT.items():
        if args.optimise:
            _search(name)
            continue
        path = write(name, description, builder())
        domain = blockmesh.load_domain(path)
        low, high = worst_angles(builder(), 5)
        print(f"{path}: {domain.n_blocks} blocks, angles to level 5: {low:.1f}..{high:.1f}")


if __name__ == "__main__":
    main()
