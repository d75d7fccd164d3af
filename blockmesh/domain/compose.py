"""Composite domains: several parts (materials) meshed together, conforming across interfaces.

A composite domain is a list of parts (:mod:`blockmesh.domain.parts`), each a region with its
geometry. They are put together the way gmsh's boolean *fragment* does it:

**a later part is cut out of the earlier ones.** A fibre listed after the matrix it lies in makes
the matrix a part with a hole and the fibre its own region; parts may also touch along edges or
overlap anywhere, and where two overlap the later one wins. Nobody cuts holes by hand.

The steps (``docs/composite.md``):

1. every circle (circular holes, discs, arcs, a Domain's arcs) is followed at points shared by
   every part on it, with the points where other parts cross it computed exactly;
2. the parts are fragmented (shapely: region ``i`` is part ``i`` minus the later parts), their
   boundaries noded, and the faces of the arrangement found (:func:`shapely.polygonize`); each
   face is a connected piece of one region, its rings point ids of the arrangement;
3. the input is checked, each problem a located :class:`~blockmesh.errors.DomainError` naming the
   parts: a part the later ones cover entirely, parts that touch at a point only, slivers and
   gaps thinner than :data:`~blockmesh.domain.validate.NEAR_TOL` times the domain's size;
4. all faces are decomposed at once (:func:`blockmesh.decompose.fragments.decompose_faces`): the
   blocks of neighbouring regions meet edge to edge along every interface;
5. block vertices on a chord of a circle move onto the circle, and every block edge along it
   becomes an arc around the circle's centre: stored once per edge, so a fibre keeps a true
   circle on both sides and both regions share its nodes bit for bit at every level;
6. the Domain gets its regions, boundary patches (the parts' patches where their edges are on
   the boundary, ``"boundary"`` elsewhere) and interfaces (``"A|B"`` between regions ``A`` and
   ``B``, in the order of the parts, unless renamed).

Examples
--------
>>> import shapely
>>> from blockmesh import Domain
>>> d = Domain.compose({"a": shapely.box(0, 0, 1, 1), "b": shapely.box(1, 0, 2, 1)})
>>> d.region_names, d.interface_names, round(d.area, 12)
(('a', 'b'), ('a|b',), 2.0)
>>> fibre = Domain.compose({"matrix": shapely.box(0, 0, 2, 2),
...                         "fibre": Domain.from_circle((1, 1), 0.5)})
>>> fibre.interface_names, round(fibre.area, 12)
(('matrix|fibre',), 4.0)
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from blockmesh.curves.types import Arc, Curve
from blockmesh.decompose.fragments import decompose_faces
from blockmesh.domain.interfaces import check_interface_name, default_interface_name
from blockmesh.domain.parts import Outline, Part
from blockmesh.domain.validate.tolerances import NEAR_TOL
from blockmesh.errors import BlockMeshWarning, DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.topology import graph_components

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["CIRCLE_PIECES", "MIN_ANGLE", "compose_parts"]

#: Chords a whole circle is followed with by default (two per 45 degrees; a part's circle may
#: ask for more with ``sides``); between the points fixed on a circle no chord turns more.
CIRCLE_PIECES = 16
#: How many times finer circles are followed when the blocks along them do not stay convex with
#: their arcs (a chord's bulge larger than the blocks beside it, as where two circles cross at a
#: sharp angle): each try doubles the chords of every circle.
FINER = (1, 2, 4, 8)
#: Smallest angle (degrees) the triangulation of the faces aims at: above the single polygon's
#: default, as the faces' chords of circles make corners where many triangles would meet
#: (measured on a disc in a square: 22 degrees gives blocks of 22.5, 30 gives 43.7, 18 % more).
MIN_ANGLE = 30.0
#: Relative distance under which two circles are the same circle (centres and radii).
_SAME_CIRCLE = 1e-9


# ------------------------------------------------------------------------------ circles
@dataclass
class _Circle:
    """One circle of the domain, the points fixed on it, and the points it is followed at."""

    centre: np.ndarray
    radius: float
    exact: bool = False  # the centre and radius as a user gave them (not computed)
    pieces: int = 0  # chords for a whole circle with no fixed points (0: no whole circle)
    spans: list[tuple[tuple[float, float], float]] = field(default_factory=list)  # (start, sweep)
    anchors: set[tuple[float, float]] = field(default_factory=set)  # points fixed on it
    xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    angle: np.ndarray = field(default_factory=lambda: np.zeros(0))
    index: dict[tuple[float, float], int] = field(default_factory=dict)

    def angle_of(self, point: Any) -> float:
        return math.atan2(point[1] - self.centre[1], point[0] - self.centre[0])

    def anchor(self, point: np.ndarray) -> None:
        self.anchors.add((float(point[0]), float(point[1])))

    def covers(self, angle: float) -> bool:
        """Whether a point of the circle at ``angle`` lies on a whole circle or an arc of it."""
        if self.pieces:
            return True
        for start, sweep in self.spans:
            turn = (angle - self.angle_of(start)) * math.copysign(1.0, sweep) % (2 * math.pi)
            if turn <= abs(sweep):
                return True
        return False

    def sample(self, finer: int = 1) -> None:
        """The points the circle is followed at: its fixed points, and more between them.

        ``finer`` multiplies the number of chords (see :data:`FINER`).
        """
        wanted = max(self.pieces, CIRCLE_PIECES) * finer
        limit = 2 * math.pi / wanted
        if not self.anchors:
            even = 2 * math.pi * np.arange(wanted) / wanted
            self.angle = even
            self.xy = self.centre + self.radius * np.c_[np.cos(even), np.sin(even)]
        else:
            keys = sorted(self.anchors, key=self.angle_of)
            first = [self.angle_of(k) for k in keys]
            angles: list[float] = []
            points: list[np.ndarray] = []
            for j, key in enumerate(keys):
                start = first[j]
                gap = (first[(j + 1) % len(keys)] - start) % (2 * math.pi)
                if gap == 0.0:
                    gap = 2 * math.pi
                count = max(1, math.ceil(gap / limit - 1e-9))
                inner = start + gap * np.arange(1, count) / count
                angles += [start, *inner.tolist()]
                points += [np.array(key)[None], self.centre + self.radius * np.c_[
                    np.cos(inner), np.sin(inner)]]  # fmt: skip
            self.angle = np.array(angles)
            self.xy = np.vstack(points)
        self.index = {(float(x), float(y)): k for k, (x, y) in enumerate(self.xy.tolist())}

    def between(self, p: np.ndarray, q: np.ndarray, sweep: float) -> np.ndarray:
        """The points followed strictly between fixed points ``p`` and ``q``, going ``sweep``."""
        n = len(self.xy)
        i = self.index[(float(p[0]), float(p[1]))]
        j = self.index[(float(q[0]), float(q[1]))]
        step = 1 if sweep > 0 else -1
        count = ((j - i) * step) % n
        return self.xy[[(i + step * m) % n for m in range(1, count)]]


class _Circles:
    """The circles of all parts, each once (circles within a hair of each other are one)."""

    def __init__(self, size: float) -> None:
        self.items: list[_Circle] = []
        self.tol = _SAME_CIRCLE * size

    def find(self, centre: Sequence[float], radius: float, exact: bool = False) -> int:
        """The circle's index; a circle given exactly replaces one computed (within a hair)."""
        c = np.asarray(centre, dtype=np.float64)
        for k, circle in enumerate(self.items):
            if (
                float(np.hypot(*(circle.centre - c))) <= self.tol
                and abs(circle.radius - radius) <= self.tol
            ):
                if exact and not circle.exact:
                    circle.centre, circle.radius, circle.exact = c, float(radius), True
                return k
        self.items.append(_Circle(c, float(radius), exact))
        return len(self.items) - 1


# ------------------------------------------------------------------------------ the steps
@dataclass
class _Ring:
    """An outline followed as a closed list of points, with the part and patch of each piece."""

    xy: np.ndarray
    patch: list[str | None]


def compose_parts(
    cls: type[Domain],
    parts: Sequence[Part],
    *,
    name: str = "composite",
    description: str = "",
    interfaces: Mapping[str, str] | None = None,
) -> Domain:
    """The composite Domain of ``parts`` (see the module docstring).

    The front door is :meth:`blockmesh.Domain.compose` (and the domain files' ``[[parts]]``).

    ``interfaces`` renames interfaces: ``{"matrix|fibre": "bond"}`` (either order of the two
    regions).
    """
    parts = list(parts)
    if not parts:
        raise DomainError("a composite domain needs at least one part")
    _check_region_names(parts)
    renames = _renames(interfaces, parts)
    size = _size(parts)
    tol = NEAR_TOL * size
    for attempt, finer in enumerate(FINER):
        circles = _circles(parts, size)
        splits = _crossings(parts, circles, tol)
        for circle in circles.items:
            circle.sample(finer)
        rings = [
            [[_follow(o, circles, splits, (i, j, r)) for r, o in enumerate(polygon)]
             for j, polygon in enumerate(part.polygons)]
            for i, part in enumerate(parts)
        ]  # fmt: skip
        shapes = [_part_shape(part, ring) for part, ring in zip(parts, rings, strict=True)]
        regions = _fragments(parts, shapes)
        pieces = _SourcePieces(parts, rings)
        if attempt == 0:
            _report_filled_holes(parts, rings, regions, tol)
        arrangement = _Arrangement.of(parts, regions, pieces, tol)
        result = decompose_faces(arrangement.points, arrangement.faces, min_angle=MIN_ANGLE)
        try:
            return _build(
                cls, parts, arrangement, result, circles, pieces, renames, name, description
            )
        except _BlocksFailError as failed:
            # Blocks that fold with their arcs: follow the circles more finely and try again.
            if not circles.items or finer == FINER[-1]:
                raise failed.error from None
    raise AssertionError("unreachable")  # pragma: no cover


class _BlocksFailError(Exception):
    """The blocks made for the faces fail the Domain's checks (``error`` says how)."""

    def __init__(self, error: DomainError) -> None:
        super().__init__(str(error))
        self.error = error


def _check_region_names(parts: list[Part]) -> None:
    seen: dict[str, Part] = {}
    for part in parts:
        if part.region in seen:
            raise DomainError(
                f"the region {part.region!r} is given twice, by {seen[part.region].label} and "
                f"{part.label}; a region is one part (give its pieces together: one part with "
                "several circles, or a MultiPolygon)"
            )
        seen[part.region] = part


def _size(parts: list[Part]) -> float:
    points = []
    for part in parts:
        for polygon in part.polygons:
            for outline in polygon:
                if outline.circle is not None:
                    (cx, cy), r, _ = outline.circle
                    points.append(np.array([[cx - r, cy - r], [cx + r, cy + r]]))
                else:
                    points.append(outline.corners)
    xy = np.vstack(points)
    return float(np.hypot(*np.ptp(xy, axis=0))) or 1.0


def _circles(parts: list[Part], size: float) -> _Circles:
    """Every circle once, with the arcs' ends fixed on it."""
    circles = _Circles(size)
    for part in parts:
        for polygon in part.polygons:
            for outline in polygon:
                if outline.circle is not None:
                    centre, radius, sides = outline.circle
                    circle = circles.items[circles.find(centre, radius, outline.circle_exact)]
                    circle.pieces = max(circle.pieces, 2 * sides)
                    continue
                n = len(outline.corners)
                for e, arc in enumerate(outline.arcs):
                    if arc is None:
                        continue
                    circle = circles.items[circles.find(arc.centre, arc.radius, arc.exact)]
                    p, q = outline.corners[e], outline.corners[(e + 1) % n]
                    circle.anchor(p)
                    circle.anchor(q)
                    circle.spans.append(((float(p[0]), float(p[1])), arc.sweep))
    return circles


def _straight_edges(
    parts: list[Part],
) -> tuple[np.ndarray, np.ndarray, list[tuple[int, int, int, int]]]:
    """Every straight edge of every outline: starts, ends, and (part, polygon, ring, edge)."""
    starts, ends, keys = [], [], []
    for i, part in enumerate(parts):
        for j, polygon in enumerate(part.polygons):
            for r, outline in enumerate(polygon):
                n = len(outline.corners)
                for e in range(n):
                    if outline.arcs[e] is None:
                        starts.append(outline.corners[e])
                        ends.append(outline.corners[(e + 1) % n])
                        keys.append((i, j, r, e))
    if not keys:
        return np.zeros((0, 2)), np.zeros((0, 2)), keys
    return np.array(starts), np.array(ends), keys


def _crossings(
    parts: list[Part], circles: _Circles, tol: float
) -> dict[tuple[int, int, int, int], list[tuple[float, np.ndarray]]]:
    """Where straight edges and circles cross: points fixed on both, computed once.

    Returns, per straight edge (part, polygon, ring, edge), the points inside it where a circle
    crosses or touches it, with their fraction along the edge; the same points are fixed on the
    circles (so the two share them bit for bit). Corners lying on a circle are fixed on it.
    """
    starts, ends, keys = _straight_edges(parts)
    splits: dict[tuple[int, int, int, int], list[tuple[float, np.ndarray]]] = {}
    corners = [
        outline.corners
        for part in parts
        for polygon in part.polygons
        for outline in polygon
        if len(outline.corners)
    ]
    all_corners = np.vstack(corners) if corners else np.zeros((0, 2))
    for circle in circles.items:
        c, radius = circle.centre, circle.radius
        if all_corners.size:
            on = np.abs(np.hypot(*(all_corners - c).T) - radius) <= tol
            for point in all_corners[on]:
                if circle.covers(circle.angle_of(point)):
                    circle.anchor(point)
        if not keys:
            continue
        d = ends - starts
        f = starts - c
        a = np.sum(d * d, axis=1)
        b = 2 * np.sum(f * d, axis=1)
        cc = np.sum(f * f, axis=1) - radius * radius
        disc = b * b - 4 * a * cc
        for k in np.flatnonzero(disc >= 0).tolist():
            root = math.sqrt(disc[k])
            length = math.sqrt(a[k])
            for t in sorted({(-b[k] - root) / (2 * a[k]), (-b[k] + root) / (2 * a[k])}):
                if not tol < t * length < length - tol:
                    continue
                point = starts[k] + t * d[k]
                if not circle.covers(circle.angle_of(point)):
                    continue
                circle.anchor(point)
                splits.setdefault(keys[k], []).append((t, point))
    for m, one in enumerate(circles.items):
        for two in circles.items[m + 1 :]:
            for point in _circle_crossings(one, two):
                if one.covers(one.angle_of(point)) and two.covers(two.angle_of(point)):
                    one.anchor(point)
                    two.anchor(point)
    return splits


def _circle_crossings(one: _Circle, two: _Circle) -> list[np.ndarray]:
    d = float(np.hypot(*(two.centre - one.centre)))
    if d == 0.0 or d > one.radius + two.radius or d < abs(one.radius - two.radius):
        return []
    a = (one.radius**2 - two.radius**2 + d * d) / (2 * d)
    h = math.sqrt(max(one.radius**2 - a * a, 0.0))
    unit = (two.centre - one.centre) / d
    base = one.centre + a * unit
    normal = np.array([-unit[1], unit[0]])
    if h == 0.0:
        return [base]
    return [base + h * normal, base - h * normal]


def _follow(
    outline: Outline,
    circles: _Circles,
    splits: Mapping[tuple[int, int, int, int], list[tuple[float, np.ndarray]]],
    key: tuple[int, int, int] | None = None,
) -> _Ring:
    """An outline as the closed list of points every part on its circles shares."""
    if outline.circle is not None:
        centre, radius, _ = outline.circle
        circle = circles.items[circles.find(centre, radius)]
        return _Ring(circle.xy.copy(), [outline.patches[0]] * len(circle.xy))
    points: list[np.ndarray] = []
    patch: list[str | None] = []
    n = len(outline.corners)
    for e in range(n):
        p, q = outline.corners[e], outline.corners[(e + 1) % n]
        arc = outline.arcs[e]
        if arc is None:
            inner = sorted(splits.get((*key, e), []), key=lambda s: s[0]) if key else []
            run = [p[None], *(point[None] for _, point in inner)]
        else:
            circle = circles.items[circles.find(arc.centre, arc.radius)]
            run = [p[None], circle.between(p, q, arc.sweep)]
        block = np.vstack(run)
        points.append(block)
        patch += [outline.patches[e]] * len(block)
    return _Ring(np.vstack(points), patch)


def _part_shape(part: Part, rings: list[list[_Ring]]) -> Any:
    """The part as one valid shapely (Multi)Polygon; a located error when it is not valid."""
    polygons = []
    for polygon, followed in zip(part.polygons, rings, strict=True):
        shape = shapely.Polygon(followed[0].xy, [r.xy for r in followed[1:]])
        if not shapely.is_valid(shape):
            reason = shapely.is_valid_reason(shape)
            raise DomainError(
                f"{part.label} is not a valid polygon ({_reason(reason)}): its outline must not "
                "cross or touch itself, and its holes must lie inside it, apart from each other"
            )
        if shape.area <= 0:
            raise DomainError(f"{part.label} has no area")
        del polygon
        polygons.append(shape)
    union = shapely.union_all(polygons)
    if len(polygons) > 1 and not math.isclose(
        union.area, sum(p.area for p in polygons), rel_tol=1e-9
    ):
        raise DomainError(
            f"the polygons of {part.label} overlap; a part's polygons are its separate pieces "
            "(give overlapping pieces as separate parts, where the later one is cut out of the "
            "earlier)"
        )
    return union


def _reason(text: str) -> str:
    """Shapely's validity reason with its point as blockmesh shows points."""
    if "[" in text and text.endswith("]"):
        what, _, where = text.partition("[")
        try:
            x, y = (float(v) for v in where[:-1].split()[:2])
        except ValueError:
            return text
        return f"{what.strip().lower()} near {fmt_point((x, y))}"
    return text


def _fragments(parts: list[Part], shapes: list[Any]) -> list[Any]:
    """Region ``i``: part ``i`` minus every later part. A part left empty is an error."""
    regions: list[Any] = [None] * len(parts)
    covered = shapely.Polygon()
    for i in range(len(parts) - 1, -1, -1):
        region = shapely.difference(shapes[i], covered) if not covered.is_empty else shapes[i]
        region = shapely.union_all(
            [g for g in shapely.get_parts(region) if isinstance(g, shapely.Polygon)]
        )
        if region.is_empty or region.area <= 1e-12 * shapes[i].area:
            later = [
                p.label
                for p in parts[i + 1 :]
                if shapely.intersects(shapes[i], shapes[parts.index(p)])
            ]
            raise DomainError(
                f"{parts[i].label} is covered entirely by the later {', '.join(later)}: a later "
                "part is cut out of the earlier ones, so nothing is left of it; list it after "
                "them (to cut it out of them), or leave it out"
            )
        regions[i] = region
        covered = shapely.union_all([covered, shapes[i]]) if not covered.is_empty else shapes[i]
    return regions


class _SourcePieces:
    """Every followed piece of every part's outline, to name parts near a point and patches."""

    def __init__(self, parts: list[Part], rings: list[list[list[_Ring]]]) -> None:
        lines, owner, patch = [], [], []
        for i, part_rings in enumerate(rings):
            for polygon in part_rings:
                for ring in polygon:
                    xy = ring.xy
                    ahead = np.roll(xy, -1, axis=0)
                    lines += shapely.linestrings(np.stack([xy, ahead], axis=1)).tolist()
                    owner += [i] * len(xy)
                    patch += ring.patch
        self.parts = parts
        self.lines = np.array(lines, dtype=object)
        self.owner = np.array(owner, dtype=np.int64)
        self.patch = patch
        self.tree = shapely.STRtree(self.lines)

    def near(self, point: Any, distance: float) -> list[str]:
        """The labels of the parts whose outline passes within ``distance`` of ``point``."""
        hits = self.tree.query(shapely.Point(*point), predicate="dwithin", distance=distance)
        found = sorted(set(self.owner[hits].tolist()))
        return [self.parts[i].label for i in found]

    def patches_at(self, points: np.ndarray, distance: float) -> list[str | None]:
        """At each point, the patch of the latest part whose outline passes there (or None)."""
        where, hit = self.tree.query(shapely.points(points), predicate="dwithin", distance=distance)
        out: list[str | None] = [None] * len(points)
        best = [-1] * len(points)
        for k, h in zip(where.tolist(), hit.tolist(), strict=True):
            name = self.patch[h]
            if name is not None and self.owner[h] > best[k]:
                out[k] = name
                best[k] = int(self.owner[h])
        return out


def _report_filled_holes(
    parts: list[Part], rings: list[list[list[_Ring]]], regions: list[Any], tol: float
) -> None:
    """Say how a hole of one part that another part's region fills is read (a warning)."""
    for i, part in enumerate(parts):
        for polygon, followed in zip(part.polygons, rings[i], strict=True):
            for outline, ring in zip(polygon[1:], followed[1:], strict=True):
                hole = shapely.Polygon(ring.xy)
                for j, region in enumerate(regions):
                    if j == i:
                        continue
                    shared = shapely.intersection(hole, region).area
                    if shared <= tol * tol:
                        continue
                    share = "fills" if shared >= hole.area * (1 - 1e-9) else "fills part of"
                    first, second = sorted((i, j))
                    interface = default_interface_name(parts[first].region, parts[second].region)
                    warnings.warn(
                        f"{outline.label} of {part.label} is not empty: {parts[j].label} "
                        f"{share} it, so its edge is read as the interface {interface!r} "
                        "between them (a hole stays empty only where no part covers it)",
                        BlockMeshWarning,
                        stacklevel=4,
                    )


# ------------------------------------------------------------------------------ arrangement
@dataclass
class _Arrangement:
    """The faces of the fragmented parts over one point set, and what lies on their edges."""

    points: np.ndarray
    faces: list[list[np.ndarray]]
    face_region: np.ndarray
    edge_faces: dict[tuple[int, int], list[int]]  # undirected edge -> faces on it

    @classmethod
    def of(cls, parts: list[Part], regions: list[Any], pieces: _SourcePieces, tol: float):
        lines = shapely.union_all([shapely.boundary(r) for r in regions])
        polygons = [
            p for p in shapely.get_parts(shapely.polygonize(shapely.get_parts(lines)))
            if isinstance(p, shapely.Polygon) and not p.is_empty
        ]  # fmt: skip
        inside = shapely.point_on_surface(polygons) if polygons else []
        tree = shapely.STRtree(regions)
        owner = np.full(len(polygons), -1, dtype=np.int64)
        at, hit = tree.query(inside, predicate="within")
        owner[at] = hit
        for k in np.flatnonzero(owner < 0).tolist():  # a hole of the union: it must not be thin
            _check_thin(polygons[k], None, pieces, tol)
        kept = [k for k in range(len(polygons)) if owner[k] >= 0]
        # A canonical order, whatever the input's ring starts and directions.
        key = [(int(owner[k]), *_lowest(polygons[k])) for k in kept]
        kept = [k for _, k in sorted(zip(key, kept, strict=True))]
        ids: dict[tuple[float, float], int] = {}
        faces: list[list[np.ndarray]] = []
        for k in kept:
            polygon = polygons[k]
            rings = [_canonical(np.asarray(polygon.exterior.coords)[:-1], True)]
            rings += [_canonical(np.asarray(h.coords)[:-1], False) for h in polygon.interiors]
            face = []
            for ring in rings:
                face.append(np.array([ids.setdefault((float(x), float(y)), len(ids))
                                      for x, y in ring.tolist()], dtype=np.int64))  # fmt: skip
            faces.append(face)
        points = np.array(list(ids), dtype=np.float64).reshape(-1, 2)
        face_region = owner[kept]
        arrangement = cls(points, faces, face_region, {})
        arrangement._index_edges()
        arrangement._check(parts, polygons, kept, pieces, tol)
        return arrangement

    def _index_edges(self) -> None:
        for f, face in enumerate(self.faces):
            for ring in face:
                for a, b in zip(ring.tolist(), np.roll(ring, -1).tolist(), strict=True):
                    self.edge_faces.setdefault((min(a, b), max(a, b)), []).append(f)

    def _check(self, parts, polygons, kept, pieces: _SourcePieces, tol: float) -> None:
        """Faces touching themselves, parts meeting at a point only, slivers and gaps."""
        names = [parts[int(r)].label for r in self.face_region]
        for f, face in enumerate(self.faces):
            ids = np.concatenate(face)
            unique, counts = np.unique(ids, return_counts=True)
            if np.any(counts > 1):
                where = self.points[unique[counts > 1][0]]
                near = _listed(pieces.near(where, 10 * tol))
                raise DomainError(
                    f"{names[f]} touches itself at the single point {fmt_point(where)} ({near} "
                    "meet there): a region must not pinch to a point; move the parts apart or "
                    "let them overlap"
                )
        boundary = [e for e, faces in self.edge_faces.items() if len(faces) == 1]
        ends = np.array(boundary, dtype=np.int64).reshape(-1, 2)
        count = np.bincount(ends.ravel(), minlength=len(self.points))
        pinched = np.flatnonzero(count > 2)
        if pinched.size:
            where = self.points[pinched[0]]
            around = sorted(
                {names[f] for e in boundary if pinched[0] in e for f in self.edge_faces[e]}
            )
            raise DomainError(
                f"{_listed(around)} touch at the single point {fmt_point(where)} only (the "
                "domain pinches there, so no block can be shared across it): move them apart, "
                "or let them meet along an edge"
            )
        for k, f in zip(kept, range(len(self.faces)), strict=True):
            _check_thin(polygons[k], names[f], pieces, tol)
        # Points too near an edge they are not on: a gap or a sliver between parts.
        edges = np.array(list(self.edge_faces), dtype=np.int64).reshape(-1, 2)
        segments = shapely.linestrings(
            np.stack([self.points[edges[:, 0]], self.points[edges[:, 1]]], axis=1)
        )
        point_ids, edge_ids = shapely.STRtree(segments).query(
            shapely.points(self.points), predicate="dwithin", distance=tol
        )
        apart = (edges[edge_ids, 0] != point_ids) & (edges[edge_ids, 1] != point_ids)
        if np.any(apart):
            p = int(point_ids[apart][0])
            e = int(edge_ids[apart][0])
            gap = float(shapely.distance(shapely.Point(*self.points[p]), segments[e]))
            where = self.points[p]
            close = pieces.near(where, 10 * tol + gap)
            raise DomainError(
                f"{_listed(close)} come within {gap:.3g} of each other near {fmt_point(where)} "
                f"without meeting: a sliver or gap thinner than the tolerance ({tol:.3g}, "
                f"{NEAR_TOL:g} times the domain's size); make the parts meet exactly (same "
                "corners on the shared edge) or keep them clearly apart"
            )


def _check_thin(polygon: Any, name: str | None, pieces: _SourcePieces, tol: float) -> None:
    """A face (or a hole of the union) thinner than ``tol`` somewhere: a located error."""
    clearance = shapely.minimum_clearance(polygon)
    if clearance >= tol:
        return
    line = shapely.minimum_clearance_line(polygon)
    if line.is_empty:
        where = np.asarray(polygon.exterior.coords[0])
    else:
        where = np.asarray(line.coords).mean(axis=0)
    near = pieces.near(where, 10 * tol + clearance)
    what = f"a sliver of {name}" if name is not None else "a gap between the parts (a hole of none)"
    raise DomainError(
        f"{what} is only {clearance:.3g} wide near {fmt_point(where)}, thinner than the "
        f"tolerance ({tol:.3g}, {NEAR_TOL:g} times the domain's size); it comes from "
        f"{_listed(near)}: make the parts meet exactly or overlap clearly"
    )


def _listed(labels: Sequence[str]) -> str:
    labels = list(labels)
    if not labels:
        return "the parts"
    if len(labels) == 1:
        return labels[0]
    return ", ".join(labels[:-1]) + " and " + labels[-1]


def _lowest(polygon: Any) -> tuple[float, float]:
    xy = np.asarray(polygon.exterior.coords)[:-1]
    k = int(np.lexsort((xy[:, 1], xy[:, 0]))[0])
    return float(xy[k, 0]), float(xy[k, 1])


def _canonical(ring: np.ndarray, outer: bool) -> np.ndarray:
    """A ring counter-clockwise (outer) or clockwise (hole), from its lowest corner."""
    area = float(
        np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1])
    )
    if (area > 0) != outer:
        ring = ring[::-1]
    start = int(np.lexsort((ring[:, 1], ring[:, 0]))[0])
    return np.roll(ring, -start, axis=0)


# ------------------------------------------------------------------------------ the Domain
def _renames(interfaces: Mapping[str, str] | None, parts: list[Part]) -> dict[tuple[str, str], str]:
    """User names of interfaces by region pair (either order), checked."""
    if not interfaces:
        return {}
    if not isinstance(interfaces, Mapping):
        raise DomainFormatError(
            'interfaces must map "A|B" (two regions) to a name, e.g. {"matrix|fibre": "bond"}, '
            f"got {type(interfaces).__name__}"
        )
    regions = {p.region for p in parts}
    out: dict[tuple[str, str], str] = {}
    for pair, new in interfaces.items():
        if not isinstance(pair, str) or pair.count("|") != 1:
            raise DomainFormatError(
                f'interface {pair!r}: name an interface by its two regions, "A|B"'
            )
        a, b = (s.strip() for s in pair.split("|"))
        for region in (a, b):
            if region not in regions:
                raise DomainError(
                    f"interface {pair!r} names the region {region!r}, but the regions are "
                    f"{', '.join(p.region for p in parts)}"
                )
        check_interface_name(new, ())
        out[(a, b)] = out[(b, a)] = new
    return out


def _build(
    cls: type[Domain],
    parts: list[Part],
    arrangement: _Arrangement,
    result: Any,
    circles: _Circles,
    pieces: _SourcePieces,
    renames: dict[tuple[str, str], str],
    name: str,
    description: str,
) -> Domain:
    """Regions, patches, interfaces and arcs on the decomposed faces: the Domain."""
    vertices = np.array(result.vertices)
    chains: dict[tuple[int, int], np.ndarray] = {}  # arrangement edge (a < b) -> chain a..b
    for face, face_chains in zip(arrangement.faces, result.ring_chains, strict=True):
        for ring, ring_chains in zip(face, face_chains, strict=True):
            for a, b, chain in zip(
                ring.tolist(), np.roll(ring, -1).tolist(), ring_chains, strict=True
            ):
                chains.setdefault((min(a, b), max(a, b)), chain if a < b else chain[::-1])
    edges: dict[tuple[int, int], Curve] = {}
    sample_of: dict[tuple[float, float], list[tuple[int, int]]] = {}
    for k, circle in enumerate(circles.items):
        for key, j in circle.index.items():
            sample_of.setdefault(key, []).append((k, j))
    points = arrangement.points
    for (a, b), chain in chains.items():
        arc = _chord_of(points[a], points[b], sample_of, circles)
        if arc is None:
            continue
        k, start, turn = arc
        circle = circles.items[k]
        p, q = points[a], points[b]
        d = q - p
        inner = chain[1:-1]
        fraction = (vertices[inner] - p) @ d / float(d @ d)
        angles = start + fraction * turn
        vertices[inner] = circle.centre + circle.radius * np.c_[np.cos(angles), np.sin(angles)]
        centre = (float(circle.centre[0]), float(circle.centre[1]))
        for u, v in zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True):
            edges[(u, v)] = Arc(center=centre)
    region_names = [p.region for p in parts]
    regions: dict[str, list[int]] = {n: [] for n in region_names}
    face_of_block = result.block_face
    block_region = arrangement.face_region[face_of_block]
    for b, r in enumerate(block_region.tolist()):
        regions[region_names[r]].append(b)
    patches: dict[str, list[tuple[int, int]]] = {}
    interfaces: dict[str, list[tuple[int, int]]] = {}
    boundary_keys = [e for e, f in arrangement.edge_faces.items() if len(f) == 1]
    middles = np.array([(points[a] + points[b]) / 2 for a, b in boundary_keys]).reshape(-1, 2)
    tol = NEAR_TOL * float(np.hypot(*np.ptp(points, axis=0)))
    named = pieces.patches_at(middles, tol) if boundary_keys else []
    for (a, b), patch in zip(boundary_keys, named, strict=True):
        if patch is not None:
            chain = chains[(a, b)]
            patches.setdefault(patch, []).extend(
                zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True)
            )
    pairs = []
    for (a, b), faces in arrangement.edge_faces.items():
        if len(faces) != 2:
            continue
        r1, r2 = sorted(int(arrangement.face_region[f]) for f in faces)
        if r1 == r2:
            continue
        pairs.append((r1, r2, a, b))
    for r1, r2, a, b in sorted(pairs):
        first, second = region_names[r1], region_names[r2]
        label = renames.get((first, second), default_interface_name(first, second))
        chain = chains[(a, b)]
        interfaces.setdefault(label, []).extend(
            zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True)
        )
    for label in interfaces:
        if label in patches:
            raise DomainError(
                f"interface {label!r} has the name of a boundary patch; an interface is an "
                "internal patch (between two regions), so give one of them another name"
            )
    joined = np.array(
        [faces for faces in arrangement.edge_faces.values() if len(faces) == 2], dtype=np.int64
    ).reshape(-1, 2)
    components, _ = graph_components(len(arrangement.faces), joined[:, 0], joined[:, 1])
    try:
        return cls._from_parsed(
            vertices,
            np.array(result.blocks),
            patches,
            regions,
            made_for="the composite domain",
            name=name,
            description=description,
            layout="composite",
            edges=edges,
            interfaces=interfaces,
            components=components,
        )
    except DomainError as error:
        raise _BlocksFailError(error) from None


def _chord_of(
    p: np.ndarray,
    q: np.ndarray,
    sample_of: Mapping[tuple[float, float], list[tuple[int, int]]],
    circles: _Circles,
) -> tuple[int, float, float] | None:
    """``(circle, start angle, turn)`` of a chord between neighbouring points of a circle.

    None when ``p``-``q`` is a straight edge (not two neighbouring points a circle is followed at).
    """
    at_p = sample_of.get((float(p[0]), float(p[1])), [])
    at_q = dict(sample_of.get((float(q[0]), float(q[1])), []))
    for k, i in at_p:
        j = at_q.get(k)
        if j is None:
            continue
        circle = circles.items[k]
        n = len(circle.xy)
        if (j - i) % n == 1:
            return (
                k,
                float(circle.angle[i]),
                float((circle.angle[j] - circle.angle[i]) % (2 * math.pi)),
            )
        if (i - j) % n == 1:
            return (
                k,
                float(circle.angle[i]),
                -float((circle.angle[i] - circle.angle[j]) % (2 * math.pi)),
            )
    return None
