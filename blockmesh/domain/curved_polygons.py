"""Curved edges on polygons: arcs on polygon and hole edges, circular holes, whole circles.

A polygon with curves is decomposed through its chords (the straight polygon, with every circular
hole an inscribed regular polygon), then every block vertex on a curved polygon edge moves onto
the curve at the same fraction of the edge, and every block edge along it becomes the piece of
the curve between its ends. The blocks are then checked with their curves like any other
(:mod:`blockmesh.domain.curve_checks`: strictly convex and counter-clockwise, level by level), with
the block and the edge named when one fails.

A whole circle is not decomposed: :func:`disc_layout` places 11 blocks (a central pentagon, five
pentagons around it and five on the circle, one arc each), the layout of the catalogue's
``disc``.

Examples
--------
>>> from blockmesh import Domain
>>> from blockmesh.curves import Arc
>>> arc = Arc(through=(1, 1.3))
>>> d = Domain.from_polygon([(0, 0), (2, 0), (2, 1), (0, 1)], arcs={2: arc})
>>> bulge = float(arc.with_ends((2, 1), (0, 1)).segment_area(0, 1))
>>> round(d.area, 12) == round(2 + bulge, 12)
True
"""

from __future__ import annotations

import itertools
import math
import numbers
import re
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh.curves.types import Arc, Curve, as_point
from blockmesh.decompose.polygon import check_corner_count
from blockmesh.domain.validate.points import parse_points
from blockmesh.domain.validate.tolerances import MIN_EXTENT
from blockmesh.errors import DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.polygons import MAX_COORDINATE

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["CIRCLE_SIDES", "circle_domain", "curved_polygon", "disc_layout"]

#: Sides of the polygon inscribed in a circular hole (its chords are decomposed).
CIRCLE_SIDES = 8
_HOLE_EDGE = re.compile(r"^hole (\d+):(\d+)$")


def _edge_key(spec: object, sizes: list[int]) -> tuple[int, int]:
    """``(ring, edge)`` of an arc's edge: ``i`` (outer edge i) or ``"hole K:E"``."""
    if isinstance(spec, numbers.Integral) and not isinstance(spec, bool):
        ring, edge = 0, int(spec)
    elif isinstance(spec, str) and _HOLE_EDGE.match(spec.strip()):
        k, e = (int(v) for v in _HOLE_EDGE.match(spec.strip()).groups())  # type: ignore[union-attr]
        ring, edge = k + 1, e
        if ring >= len(sizes):
            raise DomainError(
                f"arc on {spec!r}: there is no hole {k} (the holes are numbered "
                f"0..{len(sizes) - 2})"
                if len(sizes) > 1
                else f"arc on {spec!r}: there are no holes"
            )
    else:
        raise DomainFormatError(
            f"an arc's edge must be an outer edge index i or 'hole K:E' (edge E of hole K), got "
            f"{spec!r}"
        )
    if not 0 <= edge < sizes[ring]:
        where = "the polygon" if ring == 0 else f"hole {ring - 1}"
        raise DomainError(
            f"arc on edge {spec!r}: {where} has edges 0..{sizes[ring] - 1} (edge i runs from "
            "corner i to corner i + 1)"
        )
    return ring, edge


def _circle_fields(circle: object, what: str) -> tuple[tuple[float, float], float, int, str | None]:
    """A circle's ``center``, ``radius``, ``sides`` and ``patch``, checked."""
    if not isinstance(circle, Mapping):
        raise DomainFormatError(
            f'{what} must be a table {{center = [x, y], radius = r, patch = "name"}}, got '
            f"{circle!r}"
        )
    unknown = sorted(set(circle) - {"center", "radius", "sides", "patch"})
    if unknown:
        raise DomainFormatError(
            f"{what} takes center, radius and optionally sides and patch, not "
            f"{', '.join(map(repr, unknown))}"
        )
    if "center" not in circle or "radius" not in circle:
        raise DomainFormatError(f"{what} needs center = [x, y] and radius = r")
    centre = as_point(circle["center"], f"{what}'s center")
    radius = circle["radius"]
    if isinstance(radius, bool) or not isinstance(radius, numbers.Real):
        raise DomainFormatError(f"{what}'s radius must be a number, got {radius!r:.60}")
    try:
        size = float(radius)
    except OverflowError:
        size = math.inf
    if not (math.isfinite(size) and size > 0):
        raise DomainError(f"{what}'s radius must be a finite number > 0, got {radius!r:.60}")

    if max(abs(centre[0]), abs(centre[1])) + size > MAX_COORDINATE or size < MIN_EXTENT:
        raise DomainError(
            f"{what} (center {centre}, radius {size:g}) reaches beyond {MAX_COORDINATE:g} or is "
            f"smaller than {MIN_EXTENT:g}: coordinates must stay within {MAX_COORDINATE:g} and "
            f"a domain span at least {MIN_EXTENT:g} (change units)"
        )
    sides = circle.get("sides", CIRCLE_SIDES)
    if (
        isinstance(sides, bool)
        or not isinstance(sides, numbers.Integral)
        or not 3 <= int(sides) <= 64
    ):
        raise DomainFormatError(f"{what}'s sides must be a whole number in 3..64, got {sides!r}")
    patch = circle.get("patch")
    if patch is not None and not isinstance(patch, str):
        raise DomainFormatError(f"{what}'s patch must be a name, got {patch!r}")
    return centre, float(radius), int(sides), patch


def _inscribed(centre: tuple[float, float], radius: float, sides: int) -> np.ndarray:
    angles = 2 * math.pi * np.arange(sides) / sides
    return np.asarray(centre) + radius * np.c_[np.cos(angles), np.sin(angles)]


#: Largest turn of a curved polygon edge between two of the points it is sampled at before the
#: decomposition (radians): the blocks along it then start close to the curve.
_PIECE_TURN = math.pi / 6


def curved_polygon(
    cls: type[Domain],
    coords: Any,
    holes: Iterable[Any] | None,
    *,
    arcs: Mapping[Any, Curve] | None,
    circles: Iterable[Mapping[str, Any]] | None,
    patches: Mapping[str, Iterable[int | str]] | None,
    name: str,
    description: str,
) -> Domain:
    """A polygon with arcs on its edges and circular holes, decomposed (module docstring).

    Called by :meth:`blockmesh.Domain.from_polygon` when ``arcs`` or ``circles`` are given.
    """
    rings = [parse_points(coords, "polygon vertex")]
    hole_list = [] if holes is None else list(holes)
    rings += [parse_points(h, f"hole {k} vertex") for k, h in enumerate(hole_list)]
    n_given = len(rings)  # rings after these are circles
    shapes: dict[tuple[int, int], Curve] = {}
    patch_lists = {k: list(v) for k, v in (patches or {}).items()}
    if circles is not None:
        if isinstance(circles, Mapping | str) or not isinstance(circles, Iterable):
            raise DomainFormatError("circles must be a list of tables (one per circular hole)")

        circles = list(circles)

        def sides_of(circle: object) -> int:
            sides = circle.get("sides") if isinstance(circle, Mapping) else None
            return sides if isinstance(sides, int) and 3 <= sides <= 64 else CIRCLE_SIDES

        check_corner_count(sum(len(r) for r in rings) + sum(sides_of(c) for c in circles))
        for k, circle in enumerate(circles):
            centre, radius, sides, patch = _circle_fields(circle, f"circle {k}")
            ring = len(rings)
            rings.append(_inscribed(centre, radius, sides))
            for e in range(sides):
                shapes[(ring, e)] = Arc(center=centre)
            if patch is not None:
                patch_lists.setdefault(patch, []).append(f"hole {ring - 1}")
    sizes = [len(r) for r in rings]
    if arcs is not None:
        if not isinstance(arcs, Mapping):
            raise DomainFormatError(
                f"arcs must map polygon edges (i, or 'hole K:E') to arcs, got {type(arcs).__name__}"
            )
        for spec, arc in arcs.items():
            if not isinstance(arc, Arc):
                raise DomainFormatError(
                    f"arc on edge {spec!r} must be an Arc(through=...) or Arc(center=...), got "
                    f"{type(arc).__name__}"
                )
            key = _edge_key(spec, sizes)
            if key in shapes:
                raise DomainError(f"edge {spec!r} has two arcs; give each edge one")
            shapes[key] = arc
    # Bind every curve to its polygon edge and sample it: the decomposed polygon's corners.
    curves: dict[tuple[int, int], Curve] = {}
    sampled: list[list[np.ndarray]] = []
    pieces: list[list[tuple[int, float, float]]] = []  # per new edge: (input edge, t0, t1)
    for r, given in enumerate(rings):
        corners, origin = [], []
        for e in range(len(given)):
            p, q = given[e], given[(e + 1) % len(given)]
            if (r, e) not in shapes:
                corners.append(p)
                origin.append((e, 0.0, 1.0))
                continue
            where = "the polygon's edge" if r == 0 else f"hole {r - 1}'s edge"
            curve = shapes[(r, e)].with_ends(p, q, f"{where} {e}")
            curves[(r, e)] = curve
            count = max(1, math.ceil(abs(curve.sweep) / _PIECE_TURN))  # type: ignore[attr-defined]
            ts = np.arange(count + 1) / count
            corners += [p, *curve.point(ts[1:-1])]
            origin += [(e, float(a), float(b)) for a, b in itertools.pairwise(ts)]
        sampled.append(corners)
        pieces.append(origin)
    _check_curves_apart(rings, curves, n_given)
    new_patches = _expanded_patches(patch_lists, pieces)
    straight = cls.from_polygon(
        np.array(sampled[0]),
        [np.array(h) for h in sampled[1:]] or None,
        name=name,
        patches=new_patches or None,
        description=description,
    )
    return _attach(cls, straight, sampled, pieces, curves, n_given)


#: Largest turn (radians) between two of the points a curve is drawn with to find crossings.
_CROSSING_TURN = math.pi / 180


def _edge_label(ring: int, edge: int, n_given: int, curved: bool) -> str:
    """How the user named an edge: the polygon's or a hole's edge, or a circle."""
    if ring >= n_given:
        return f"circle {ring - n_given}"
    what = "the polygon's edge" if ring == 0 else f"hole {ring - 1}'s edge"
    return f"{what} {edge}{' (an arc)' if curved else ''}"


def _check_curves_apart(
    rings: list[np.ndarray], curves: Mapping[tuple[int, int], Curve], n_given: int
) -> None:
    """Raise DomainError, naming the edges as given, where two edges of the curved rings meet.

    Every edge is drawn as it is (an arc with a point every degree), so a curve that crosses or
    touches another edge, a hole or a circle is reported with the edges as the user numbered them
    (the decomposition numbers the sampled edges otherwise). Neighbours may share their corner.
    """
    import shapely

    lines, keys = [], []
    for r, ring in enumerate(rings):
        for e in range(len(ring)):
            curve = curves.get((r, e))
            if curve is None:
                xy = np.array([ring[e], ring[(e + 1) % len(ring)]])
            else:
                count = max(8, math.ceil(abs(curve.sweep) / _CROSSING_TURN))  # type: ignore[attr-defined]
                xy = curve.point(np.linspace(0.0, 1.0, count + 1))
            lines.append(shapely.LineString(xy))
            keys.append((r, e))
    size = float(np.ptp(np.vstack(rings), axis=0).max())
    tol = 1e-12 * size
    first, second = shapely.STRtree(lines).query(lines, predicate="intersects")
    for i, j in zip(first.tolist(), second.tolist(), strict=True):
        (ri, ei), (rj, ej) = keys[i], keys[j]
        if i >= j or (ri == rj and ri >= n_given):  # a circle's own arcs meet end to end
            continue
        meeting = shapely.intersection(lines[i], lines[j])
        n = len(rings[ri])
        if ri == rj and (ej - ei) % n in (1, n - 1):  # neighbours: only their shared corner
            corner = rings[ri][ej] if (ej - ei) % n == 1 else rings[ri][ei]
            meeting = meeting.difference(shapely.Point(corner).buffer(tol))
            if meeting.is_empty:
                continue
        met = shapely.get_coordinates(meeting)
        where = met[0] if met.size else rings[ri][ei]
        one = _edge_label(ri, ei, n_given, (ri, ei) in curves)
        two = _edge_label(rj, ej, n_given, (rj, ej) in curves)
        hint = (
            "the boundary may not touch itself"
            if ri == rj == 0
            else "holes and circles must lie strictly inside the polygon, apart from it and "
            "from each other"
        )
        raise DomainError(f"{one} and {two} meet near {fmt_point(where)}: {hint}")


def _expanded_patches(
    patches: Mapping[str, list[Any]], pieces: list[list[tuple[int, float, float]]]
) -> dict[str, list[Any]]:
    """Patches over the sampled rings' edges (every piece of an input edge in its patch)."""
    out: dict[str, list[Any]] = {}
    for name, edges in patches.items():
        listed: list[Any] = []
        for edge in edges:
            if isinstance(edge, str) and _HOLE_EDGE.match(edge.strip()):
                k, e = (int(v) for v in _HOLE_EDGE.match(edge.strip()).groups())  # type: ignore[union-attr]
                ring, edge_index = k + 1, e
            elif isinstance(edge, numbers.Integral) and not isinstance(edge, bool):
                ring, edge_index = 0, int(edge)
            else:  # "hole K" and anything unexpected: the straight constructor reads it
                listed.append(edge)
                continue
            if ring >= len(pieces) or not 0 <= edge_index < max(o[0] for o in pieces[ring]) + 1:
                listed.append(edge)  # out of range: reported by the straight constructor
                continue
            for j, (origin, _, _) in enumerate(pieces[ring]):
                if origin == edge_index:
                    listed.append(j if ring == 0 else f"hole {ring - 1}:{j}")
        out[name] = listed
    return out


def _attach(
    cls: type[Domain],
    straight: Domain,
    rings: list[list[np.ndarray]],
    pieces: list[list[tuple[int, float, float]]],
    curves: Mapping[tuple[int, int], Curve],
    n_given: int,
) -> Domain:
    """The decomposed sampled polygon with its curved edges: vertices moved, curves bound.

    When a block does not stay strictly convex with its vertices on the curves, the DomainError
    names the blocks and the curved edges (as the user numbered them) that moved their vertices.
    """
    vertices = np.array(straight.vertices)
    source = straight.boundary_source
    edges: dict[tuple[int, int], Curve] = {}
    mapping: dict[tuple[int, int], tuple[int, int]] = {}
    for _row, ((a, b), (ring, j)) in enumerate(
        zip(straight.boundary_edges.tolist(), source.tolist(), strict=True)
    ):
        if ring < 0:
            continue
        e, t0, t1 = pieces[ring][j]
        mapping[(a, b)] = (ring, e)
        curve = curves.get((ring, e))
        if curve is None:
            continue
        corners = rings[ring]
        p, q = corners[j], corners[(j + 1) % len(corners)]
        chord = q - p
        length2 = float(chord @ chord)
        fraction = []
        for v in (a, b):
            f = float((straight.vertices[v] - p) @ chord) / length2
            f = 0.0 if abs(f) < 1e-12 else 1.0 if abs(f - 1) < 1e-12 else f
            fraction.append(t0 + f * (t1 - t0))
            if 0.0 < f < 1.0:
                vertices[v] = curve.point(t0 + f * (t1 - t0))
        middle = curve.point(0.5 * (fraction[0] + fraction[1]))
        edges[(a, b)] = Arc(through=(float(middle[0]), float(middle[1])))
    patches = {
        name: [tuple(map(int, e)) for e in straight.patches[name]] for name in straight.patch_names
    }
    regions = {name: straight.regions[name].tolist() for name in straight.region_names}
    try:
        return cls.from_blocks(
            vertices,
            straight.blocks,
            patches,
            regions,
            name=straight.name,
            description=straight.description,
            layout=straight.layout,
            boundary_source=mapping,
            edges=edges,
        )
    except DomainError as error:
        on_curve: dict[int, set[tuple[int, int]]] = {}
        for (a, b), key in mapping.items():
            if key in curves:
                on_curve.setdefault(a, set()).add(key)
                on_curve.setdefault(b, set()).add(key)
        named = {int(k) for k in re.findall(r"block (\d+)", str(error))}
        culprits = sorted(
            {key for k in named if k < straight.n_blocks for v in straight.blocks[k].tolist()
             for key in on_curve.get(int(v), ())}
        )  # fmt: skip
        labels = [
            _edge_label(r, e, n_given, False) if r >= n_given
            else f"the arc on {_edge_label(r, e, n_given, False)}"
            for r, e in culprits
        ]  # fmt: skip
        which = (
            f" ({', '.join(labels)} moved the vertices of the blocks below onto the curve; make "
            "an arc bulge less or put a polygon corner on it to split it, give a circle more "
            "sides)"
            if labels
            else ""
        )
        raise type(error)(
            f"the polygon's curved edges do not fit its decomposition{which}: {error}"
        ) from None


def disc_layout(
    centre: Iterable[float], radius: float, radii: tuple[float, float, float] = (0.25, 0.43, 0.7)
) -> tuple[np.ndarray, list[list[int]], dict[tuple[int, int], Curve], list[tuple[int, int]]]:
    """11 blocks for a disc: ``(vertices, blocks, arcs, boundary edges)``.

    A central pentagon with corners at ``radii[0] * radius``, five pentagons around it and five on
    the circle (inner corners at ``radii[1]`` and ``radii[2]`` times the radius), each of the
    last with one arc of 72 degrees. Every inner vertex belongs to three blocks and every vertex
    on the circle to two, so no cell corner on the circle approaches 180 degrees.

    Examples
    --------
    >>> vertices, blocks, arcs, boundary = disc_layout((0, 0), 1.0)
    >>> len(vertices), len(blocks), len(arcs), len(boundary)
    (20, 11, 5, 5)
    """
    c = np.asarray(list(centre), dtype=float)
    rc, rz, ry = radii
    beta = math.pi / 2 + 2 * math.pi * np.arange(5) / 5
    step = math.pi / 5

    def ring(r: float, shift: float) -> np.ndarray:
        return c + r * np.c_[np.cos(beta + shift), np.sin(beta + shift)]

    vertices = np.vstack(
        [ring(radius, 0), ring(ry * radius, 0), ring(rz * radius, step), ring(rc * radius, step)]
    )
    o, y, z, m = (np.arange(5) + 5 * k for k in range(4))
    blocks: list[list[int]] = []
    arcs: dict[tuple[int, int], Curve] = {}
    for k in range(5):
        n = (k + 1) % 5
        blocks.append([int(y[k]), int(o[k]), int(o[n]), int(y[n]), int(z[k])])
        blocks.append([int(m[k]), int(z[k]), int(y[n]), int(z[n]), int(m[n])])
        arcs[(int(o[k]), int(o[n]))] = Arc(center=(float(c[0]), float(c[1])))
    blocks.append([int(v) for v in m])
    return vertices, blocks, arcs, list(arcs)


def circle_domain(
    cls: type[Domain], center: Any, radius: Any, *, name: str, patch: str, description: str
) -> Domain:
    """The disc of :func:`disc_layout` as a Domain, its boundary in one patch."""
    centre, size, _, _ = _circle_fields(
        {"center": center, "radius": radius, "patch": patch}, "the circle"
    )
    vertices, blocks, arcs, boundary = disc_layout(centre, size)
    return cls.from_blocks(
        vertices,
        blocks,
        {patch: boundary},
        name=name,
        description=description,
        layout="disc",
        edges=arcs,
    )
