"""The parts of a composite domain, from every form a user gives them in.

A composite domain (:mod:`blockmesh.domain.compose`) is a list of parts, each a region name with
its geometry. Whatever the form, a part becomes a :class:`Part`: polygons (an outline and its
holes), each outline a ring of corners whose edges are straight or circular arcs, or a whole
circle, with the patch of each edge when the user names one. The forms:

- a table of a domain file's ``[[parts]]`` (:func:`part_from_table`): ``region`` with the keys of
  the polygon form, ``polygon``, ``holes``, ``arcs``, ``circles`` (holes of the polygon, or without
  a polygon the part's own discs) and ``patches``;
- a shapely Polygon or MultiPolygon (:func:`part_from_shapely`), as GeoJSON features and WKT
  geometries are read;
- a :class:`~blockmesh.Domain` (:func:`part_from_domain`), curved ones included: its boundary
  loops, straight runs and arcs joined back into polygon edges and circles.

Examples
--------
>>> part = part_from_table({"region": "fibre", "circles": [{"center": [1, 1], "radius": 0.3}]}, 1)
>>> part.region, len(part.polygons), part.polygons[0][0].circle
('fibre', 1, ((1.0, 1.0), 0.3, 8))
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from blockmesh.checks import key_list, unknown_keys
from blockmesh.curves.types import Arc
from blockmesh.domain.curved_polygons import _circle_fields, _edge_key
from blockmesh.domain.polygon_edges import facing_resolved, hole_list, ring_edge_patches
from blockmesh.domain.tomlio.tables import polygon_arcs, toml_type
from blockmesh.domain.validate.names import DEFAULT_PATCH, check_name
from blockmesh.domain.validate.points import parse_points
from blockmesh.errors import ArgumentTypeError, DomainError, DomainFormatError
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = [
    "PART_KEYS",
    "ArcEdge",
    "Outline",
    "Part",
    "part_from_domain",
    "part_from_shapely",
    "part_from_table",
]

#: Keys of a ``[[parts]]`` table and what each holds.
PART_KEYS = {
    "region": "the region's name (a string)",
    "polygon": "corners of the part's outline, [[x, y], ...]",
    "holes": "holes of the outline, each a list of corners",
    "arcs": 'arcs on the outline\'s edges: tables with edge = i or "hole K:E" and through|center',
    "circles": "circular holes of the polygon or, without a polygon, the part's discs: "
    '[{center = [x, y], radius = r, patch = "name"}]',
    "circle": "one disc as the part: {center = [x, y], radius = r}",
    "patches": 'a table: patch name = polygon edges (i, "hole K", "hole K:E")',
}


@dataclass(frozen=True)
class ArcEdge:
    """A polygon edge that is a circular arc: its circle and its signed turn.

    Attributes
    ----------
    centre : (x, y)
    radius : float
    sweep : float
        Signed angle from the edge's first corner to its second, radians (counter-clockwise > 0).
    exact : bool
        Whether the centre is as the user gave it (an arc around a centre), rather than computed
        from a point the arc passes through (with its rounding).
    """

    centre: tuple[float, float]
    radius: float
    sweep: float
    exact: bool = False


@dataclass(frozen=True)
class Outline:
    """One ring of a part: corners and the kind and patch of each edge, or a whole circle.

    Attributes
    ----------
    corners : ndarray (n, 2)
        Edge ``i`` runs from corner ``i`` to corner ``i + 1`` (cyclically); (0, 2) for a circle.
    arcs : tuple of ArcEdge or None
        Per edge, its arc (None: straight).
    patches : tuple of str or None
        Per edge, the patch a user named (None: none named); one entry for a circle.
    circle : ((x, y), radius, sides) or None
        A whole circle (``sides`` sets how finely it is followed: 2 sides per 45 degrees by
        default, as the polygon form's circular holes).
    label : str
        The ring as the user knows it (``"the polygon"``, ``"hole 1"``, ``"circle 0"``).
    circle_exact : bool
        Whether the circle's centre and radius are as a user gave them (not computed from points
        on it, with their rounding).
    """

    corners: np.ndarray
    arcs: tuple[ArcEdge | None, ...]
    patches: tuple[str | None, ...]
    circle: tuple[tuple[float, float], float, int] | None
    label: str
    circle_exact: bool = True


@dataclass(frozen=True)
class Part:
    """A region name and its geometry: polygons, each an outline followed by its holes.

    Attributes
    ----------
    region : str
    polygons : tuple of tuple of Outline
    label : str
        How messages name the part (``"part 2 ('fibre')"``).
    """

    region: str
    polygons: tuple[tuple[Outline, ...], ...]
    label: str


# ------------------------------------------------------------------------------ tables
def part_from_table(table: object, k: int, source: str = "") -> Part:
    """A part from a ``[[parts]]`` table (or a mapping of the same keys), numbered ``k``.

    ``source`` (the file) starts every message.

    Examples
    --------
    >>> part = part_from_table({"region": "a", "polygon": [[0, 0], [1, 0], [1, 1]],
    ...                         "patches": {"floor": [0]}}, 0)
    >>> part.polygons[0][0].patches
    ('floor', None, None)
    """
    where = f"{source}: " if source else ""
    if not isinstance(table, Mapping):
        raise DomainFormatError(
            f"{where}parts entry {k} must be a table (region = ..., polygon = ... or circles = "
            f"...), got {toml_type(table)}"
        )
    unknown = unknown_keys(table, PART_KEYS)
    if unknown:
        raise DomainFormatError(
            f"{where}parts entry {k} has the unknown {unknown}; a part takes: {key_list(PART_KEYS)}"
        )
    if "region" not in table:
        raise DomainFormatError(f'{where}parts entry {k} needs region = "name"')
    region = _region_name(table["region"], f"{where}parts entry {k}")
    label = f"part {k} ({region!r})"
    try:
        return _part_from_fields(table, region, label)
    except DomainError as error:
        raise type(error)(f"{where}{label}: {error}") from None


def _region_name(value: object, where: str) -> str:
    try:
        return check_name(value, "region")
    except DomainFormatError as error:
        raise DomainFormatError(f"{where}: {error}") from None


def _part_from_fields(table: Mapping[str, Any], region: str, label: str) -> Part:
    circles = list(table.get("circles") or [])
    if "circle" in table:
        circles.append(table["circle"])
    if "polygon" not in table:
        for key in ("holes", "arcs", "patches"):
            if key in table:
                raise DomainFormatError(
                    f"{key!r} belong to a polygon; a part of circles names each circle's patch "
                    'with patch = "name"'
                )
        if not circles:
            raise DomainFormatError("no geometry: give polygon = [[x, y], ...] or circles = [...]")
        discs = [_circle(circle, f"circle {c}") for c, circle in enumerate(circles)]
        return Part(region, tuple((disc,) for disc in discs), label)
    rings = [parse_points(table["polygon"], "polygon vertex")]
    rings += [
        parse_points(h, f"hole {j} vertex") for j, h in enumerate(hole_list(table.get("holes")))
    ]
    n_holes = len(rings) - 1
    shapes = [_circle(circle, f"circle {c}") for c, circle in enumerate(circles)]
    sizes = [len(r) for r in rings] + [1] * len(shapes)
    named = ring_edge_patches(facing_resolved(table.get("patches"), rings[0]), sizes)
    arcs: dict[tuple[int, int], Any] = {}
    raw_arcs = table.get("arcs")
    if raw_arcs is not None:
        specs = polygon_arcs(raw_arcs, "arcs") if isinstance(raw_arcs, list) else raw_arcs
        if not isinstance(specs, Mapping):
            raise DomainFormatError(
                f"arcs must be a list of tables (edge = ..., through|center = ...), got "
                f"{toml_type(raw_arcs)}"
            )
        for spec, arc in specs.items():
            edge_key = _edge_key(spec, sizes[: len(rings)])
            if not isinstance(arc, Arc):
                raise DomainFormatError(
                    f"arc on edge {spec!r} must be an Arc(through=...) or Arc(center=...), got "
                    f"{type(arc).__name__}"
                )
            arcs[edge_key] = arc
    outlines = []
    for r, corners in enumerate(rings):
        text = "the polygon" if r == 0 else f"hole {r - 1}"
        outlines.append(_outline(corners, r, arcs, named, text))
    for c, shape in enumerate(shapes):
        patch = named[n_holes + 1 + c][0] if named is not None else None
        outlines.append(Outline(shape.corners, (), (patch or shape.patches[0],), shape.circle,
                                shape.label))  # fmt: skip
    return Part(region, (tuple(outlines),), label)


def _circle(circle: object, what: str) -> Outline:
    centre, radius, sides, patch = _circle_fields(circle, what)
    return Outline(np.zeros((0, 2)), (), (patch,), (centre, radius, sides), what)


def _outline(
    corners: np.ndarray,
    ring: int,
    arcs: Mapping[tuple[int, int], Any],
    named: list[list[str | None]] | None,
    label: str,
) -> Outline:
    n = len(corners)
    edges: list[ArcEdge | None] = []
    for e in range(n):
        arc = arcs.get((ring, e))
        if arc is None:
            edges.append(None)
            continue
        where = "the polygon's edge" if ring == 0 else f"hole {ring - 1}'s edge"
        bound = arc.with_ends(corners[e], corners[(e + 1) % n], f"{where} {e}")
        exact = arc.center is not None
        edges.append(ArcEdge(bound.centre_point, bound.radius, bound.sweep, exact))
    patches = tuple(named[ring]) if named is not None else (None,) * n
    return Outline(corners, tuple(edges), patches, None, label)


# ------------------------------------------------------------------------------ shapely
def part_from_shapely(
    region: str,
    geometry: Any,
    label: str,
    patches: Mapping[str, Iterable[int | str]] | None = None,
) -> Part:
    """A part from a shapely Polygon or MultiPolygon (or a collection of them).

    ``patches`` names polygon edges as in :meth:`blockmesh.Domain.from_polygon`, counted along
    the rings as shapely stores them; only for a single Polygon.

    Examples
    --------
    >>> part = part_from_shapely("a", shapely.box(0, 0, 2, 1), "part 0 ('a')")
    >>> part.polygons[0][0].corners.shape
    (4, 2)
    """
    polygons = _polygons_of(geometry, label)
    if patches and len(polygons) != 1:
        raise DomainError(
            f"{label}: patches name the edges of one polygon; this part has "
            f"{len(polygons)} (give each its own part, or name the patches per polygon)"
        )
    out = []
    for polygon in polygons:
        rings = [np.asarray(polygon.exterior.coords)[:-1, :2]]
        rings += [np.asarray(ring.coords)[:-1, :2] for ring in polygon.interiors]
        try:
            named = ring_edge_patches(facing_resolved(patches, rings[0]), [len(r) for r in rings])
        except DomainError as error:
            raise type(error)(f"{label}: {error}") from None
        out.append(
            tuple(
                _outline(corners, r, {}, named, "the polygon" if r == 0 else f"hole {r - 1}")
                for r, corners in enumerate(rings)
            )
        )
    return Part(region, tuple(out), label)


def _polygons_of(geometry: Any, label: str) -> list[Any]:
    """The polygons of a Polygon, MultiPolygon or GeometryCollection of them; else an error."""
    if isinstance(geometry, shapely.Polygon):
        found = [geometry]
    elif isinstance(geometry, shapely.MultiPolygon | shapely.GeometryCollection):
        found = []
        for member in geometry.geoms:
            found += _polygons_of(member, label)
    else:
        raise ArgumentTypeError(
            f"{label} is a {type(geometry).__name__}; a part is a Polygon or MultiPolygon (a "
            "shapely geometry), a Domain, or a table of the polygon form"
        )
    found = [p for p in found if not p.is_empty]
    if not found:
        raise DomainError(f"{label} is empty")
    return found


# ------------------------------------------------------------------------------ domains
def part_from_domain(region: str, domain: Domain, label: str) -> Part:
    """A part whose outline is a Domain's boundary (its patches kept, its arcs as arcs).

    Consecutive straight boundary edges on one line and consecutive arcs of one circle (in one
    patch each) are joined back into one polygon edge or arc; a loop of arcs of one circle is a
    whole circle. Splines and polylines have no exact counterpart in a composite domain: a
    Domain with them is refused.

    Examples
    --------
    >>> from blockmesh import Domain
    >>> part = part_from_domain("fibre", Domain.from_circle((0, 0), 1), "part 1 ('fibre')")
    >>> part.polygons[0][0].circle
    ((0.0, 0.0), 1.0, 8)
    """
    loops = _loops(domain.boundary_edges)
    patch_of = {
        (int(a), int(b)): domain.patch_names[int(k)]
        for (a, b), k in zip(domain.boundary_edges, domain.boundary_patch, strict=True)
    }
    rings: list[Outline] = []
    areas = []
    for loop in loops:
        pieces = []
        for a, b in zip(loop, np.roll(loop, -1), strict=True):
            arc = _arc_of(domain, int(a), int(b), label)
            patch = patch_of[(int(a), int(b))]
            pieces.append((int(a), arc, None if patch == DEFAULT_PATCH else patch))
        rings.append(_joined(domain.vertices, pieces))
        areas.append(_loop_area(domain.vertices[loop], [arc for _, arc, _ in pieces]))
    shells = [k for k, a in enumerate(areas) if a > 0]
    polygons: dict[int, list[Outline]] = {k: [rings[k]] for k in shells}
    shapes = {k: shapely.Polygon(_sampled(rings[k])) for k in shells}
    for k, area in enumerate(areas):
        if area > 0:
            continue
        inside = shapely.Point(*_sampled(rings[k])[0])
        owner = min(
            (s for s in shells if shapes[s].covers(inside)), key=lambda s: areas[s], default=None
        )
        if owner is None:  # pragma: no cover - a Domain's hole lies in one of its outlines
            raise DomainError(f"{label}: a hole of the domain lies in none of its outlines")
        polygons[owner].append(rings[k])
    named = [
        (replace(rings[0], label="the outline"),
         *(replace(hole, label=f"hole {k}") for k, hole in enumerate(rings[1:])))
        for rings in polygons.values()
    ]  # fmt: skip
    return Part(region, tuple(named), label)


def _loops(boundary: np.ndarray) -> list[np.ndarray]:
    """The boundary edges (in loop order) cut into loops of vertex ids."""
    ends = np.flatnonzero(boundary[1:, 0] != boundary[:-1, 1]) + 1
    return [run[:, 0] for run in np.split(boundary, ends)]


def _arc_of(domain: Domain, a: int, b: int, label: str) -> ArcEdge | None:
    curve = domain.curves.get((a, b))
    sign = 1.0
    if curve is None:
        curve = domain.curves.get((b, a))
        sign = -1.0
    if curve is None:
        return None
    if not isinstance(curve, Arc):
        raise DomainError(
            f"{label}: the domain's boundary edge ({a}, {b}) is a {curve.kind}; a part's curved "
            "edges must be circular arcs (a composite domain follows circles exactly)"
        )
    return ArcEdge(curve.centre_point, curve.radius, sign * curve.sweep, curve.center is not None)


def _same_circle(one: ArcEdge, two: ArcEdge) -> bool:
    size = max(one.radius, two.radius)
    return (
        math.dist(one.centre, two.centre) <= 1e-9 * size
        and abs(one.radius - two.radius) <= 1e-9 * size
        and one.sweep * two.sweep > 0
    )


def _joined(vertices: np.ndarray, pieces: list[tuple[int, ArcEdge | None, str | None]]) -> Outline:
    """One loop's edges joined where they continue one another (one line, one circle)."""
    n = len(pieces)

    def continues(k: int) -> bool:
        """Whether piece ``k`` continues piece ``k - 1`` (so corner ``k`` can go)."""
        (a, arc0, patch0), (v, arc1, patch1) = pieces[k - 1], pieces[k]
        if patch0 != patch1 or (arc0 is None) != (arc1 is None):
            return False
        if arc0 is not None and arc1 is not None:
            return _same_circle(arc0, arc1)
        w = pieces[(k + 1) % n][0]
        u, t = vertices[v] - vertices[a], vertices[w] - vertices[v]
        sine = (u[0] * t[1] - u[1] * t[0]) / (math.hypot(*u) * math.hypot(*t))
        return abs(sine) <= COLLINEAR_SIN_TOL and float(u @ t) > 0

    keep = [k for k in range(n) if not continues(k)]
    if not keep:  # one circle all round
        arc = pieces[0][1]
        if arc is None:  # pragma: no cover - a loop of straight edges on one line has no area
            raise DomainError("a boundary loop of the domain has no area")
        exact = all(piece[1] is not None and piece[1].exact for piece in pieces)
        circle = (arc.centre, arc.radius, 8)
        return Outline(np.zeros((0, 2)), (), (pieces[0][2],), circle, "the outline", exact)
    corners: list[np.ndarray] = []
    arcs: list[ArcEdge | None] = []
    patches: list[str | None] = []
    for j, k in enumerate(keep):
        stop = keep[(j + 1) % len(keep)]
        run = [(k + m) % n for m in range(((stop - k - 1) % n) + 1)]
        corners.append(vertices[pieces[k][0]])
        first = pieces[k][1]
        if first is None:
            arcs.append(None)
        else:
            turn = sum(piece.sweep for m in run if (piece := pieces[m][1]) is not None)
            arcs.append(ArcEdge(first.centre, first.radius, turn, first.exact))
        patches.append(pieces[k][2])
    return Outline(np.array(corners), tuple(arcs), tuple(patches), None, "the outline")


def _loop_area(corners: np.ndarray, arcs: list[ArcEdge | None]) -> float:
    """Signed area of a loop (counter-clockwise > 0): its corners' polygon and arc segments."""
    x, y = corners[:, 0] - corners[0, 0], corners[:, 1] - corners[0, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    for arc in arcs:
        if arc is not None:  # the circular segment between the arc and its chord, signed
            area += 0.5 * arc.radius**2 * (arc.sweep - math.sin(arc.sweep))
    return area


def _sampled(ring: Outline, turn: float = math.pi / 12) -> np.ndarray:
    """Points along a ring (arcs followed every ``turn`` radians), counter-clockwise or not."""
    if ring.circle is not None:
        (cx, cy), r, _ = ring.circle
        angles = np.linspace(0, 2 * math.pi, 25)[:-1]
        return np.c_[cx + r * np.cos(angles), cy + r * np.sin(angles)]
    out = []
    n = len(ring.corners)
    for e in range(n):
        p = ring.corners[e]
        out.append(p[None])
        arc = ring.arcs[e]
        if arc is None:
            continue
        count = max(1, math.ceil(abs(arc.sweep) / turn))
        start = math.atan2(p[1] - arc.centre[1], p[0] - arc.centre[0])
        angles = start + arc.sweep * np.arange(1, count) / count
        out.append(np.c_[arc.centre[0] + arc.radius * np.cos(angles),
                         arc.centre[1] + arc.radius * np.sin(angles)])  # fmt: skip
    return np.vstack(out)


def part_from_value(
    domain_type: type,
    region: object,
    value: object,
    k: int,
    patches: Mapping[str, Iterable[int | str]] | None = None,
) -> Part:
    """Part ``k`` from what :meth:`blockmesh.Domain.compose` takes as a value.

    A shapely geometry (:func:`part_from_shapely`, with ``patches`` naming its edges), a Domain
    (an instance of ``domain_type``; :func:`part_from_domain`) or a mapping of the ``[[parts]]``
    keys without ``region`` (:func:`part_from_table`).
    """
    name = _region_name(region, f"part {k}")
    label = f"part {k} ({name!r})"
    if isinstance(value, domain_type):
        if patches:
            raise DomainError(f"{label}: a Domain brings its own patches; leave out patches")
        return part_from_domain(name, value, label)  # type: ignore[arg-type]
    if isinstance(value, Mapping):
        if "region" in value and value["region"] != name:
            raise DomainFormatError(
                f"{label}: the table names the region {value['region']!r}; leave region out "
                "(the key names it)"
            )
        table = {**value, "region": name}
        if patches:
            table["patches"] = patches
        return part_from_table(table, k)
    if isinstance(value, shapely.Geometry):
        return part_from_shapely(name, value, label, patches)
    raise ArgumentTypeError(
        f"{label} is a {type(value).__name__}; a part is a shapely Polygon or MultiPolygon, a "
        "Domain, or a table of the polygon form (polygon, holes, arcs, circles, patches)"
    )
