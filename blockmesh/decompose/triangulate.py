"""Quality triangulation of a polygon with holes: constrained Delaunay, then Delaunay refinement.

The start is GEOS's constrained Delaunay triangulation
(:func:`shapely.constrained_delaunay_triangles`), which keeps every ring edge and never adds a
point. Slivers are then removed by Delaunay refinement in the manner of Ruppert's algorithm: the
circumcentre of the worst triangle is inserted (Bowyer-Watson, the cavity never crossing the
boundary) unless it falls outside the domain or inside the diametral circle of a boundary segment,
in which case that segment is split instead (at its midpoint, or at a power-of-two distance from
an input corner, so that segments meeting at a sharp corner do not split each other forever).
Triangles that cannot be repaired within the point budget (slivers of aspect ratio beyond it,
corners of the domain sharper than the target, and triangles across a corner sharper than 60
degrees whose shortest edge joins two points one shell from it, as Shewchuk's Triangle leaves them)
are left as they are: the triangulation is always valid, its quality is the best the budget
allows.

Everything here works in the caller's coordinates, which should be local ones (origin inside the
domain, size about 1, as :func:`blockmesh.geometry.local_frame` gives): the predicates are plain
floating-point determinants of differences.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> t = triangulate([square])
>>> t.triangles.shape[1], bool(t.min_angle() >= 22.0)
(3, True)
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely

from blockmesh.errors import DomainError, ResourceError
from blockmesh.geometry.polygons import interior_angles

__all__ = ["Triangulation", "triangulate"]

#: Target smallest angle (degrees) of the refined triangles. Modest on purpose: the blocks' worst
#: angles come out near 35-45 degrees after their nodes are moved either way (the corner cells
#: at interior triangle vertices are free to even out), while a 30-degree target costs about a
#: third more triangles, hence blocks.
DEFAULT_MIN_ANGLE = 22.0
#: Relative difference under which two points are at one distance from a corner (on one of the
#: concentric shells the segment splits put around it).
_SAME_SHELL = 1e-3


@dataclass(frozen=True)
class Triangulation:
    """A triangulation of a polygon with holes whose boundary segments know their ring edge.

    Attributes
    ----------
    points : ndarray (N, 2)
        The ring vertices first (rings concatenated in order), then the added points.
    triangles : ndarray (T, 3)
        Counter-clockwise vertex ids.
    segments : ndarray (S, 2)
        Boundary segments, each oriented with the domain on its left.
    segment_edge : ndarray (S,)
        The ring edge (numbered across the rings: ring 0's edges first) each segment lies on.
    """

    points: np.ndarray
    triangles: np.ndarray
    segments: np.ndarray
    segment_edge: np.ndarray

    def min_angle(self) -> float:
        """Smallest angle of any triangle, in degrees."""
        return float(interior_angles(self.points[self.triangles]).min())


def triangulate(
    rings: Sequence[np.ndarray],
    *,
    min_angle: float = DEFAULT_MIN_ANGLE,
    max_points: int | None = None,
) -> Triangulation:
    """Triangulate a polygon with holes and refine it towards ``min_angle``.

    Parameters
    ----------
    rings : sequence of ndarray (n_r, 2)
        The outer ring first, counter-clockwise, then the holes, clockwise (the domain on the left
        of every edge); simple, disjoint and nested as validated by
        :func:`blockmesh.domain.validate.check_rings`.
    min_angle : float
        Target smallest angle in degrees (at most 33; 0 skips the refinement).
    max_points : int, optional
        Most points to add; by default ``20 * n + 2000`` for ``n`` ring vertices (ordinary
        polygons need far fewer; the budget bounds the work on thin gaps and slivers, which are
        repaired worst first and otherwise left valid but thin).

    Returns
    -------
    Triangulation

    Notes
    -----
    Time O(N log N) for the constrained triangulation and about 20-40 microseconds per added
    point (Python); memory O(N).
    """
    counts = [len(r) for r in rings]
    points = np.vstack([np.asarray(r, dtype=np.float64) for r in rings])
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    edge_a = np.concatenate([s + np.arange(c) for s, c in zip(start, counts, strict=True)])
    edge_b = np.concatenate(
        [s + (np.arange(c) + 1) % c for s, c in zip(start, counts, strict=True)]
    )
    triangles = _constrained_triangles(rings, points)
    budget = 20 * len(points) + 2000 if max_points is None else int(max_points)
    refiner = _Refiner(points, triangles, edge_a, edge_b)
    if min_angle > 0 and budget > 0:
        refiner.refine(min(float(min_angle), 33.0), budget)
    return refiner.result()


def constrained_delaunay(polygon: shapely.Polygon) -> shapely.GeometryCollection:
    """GEOS's constrained Delaunay triangles of ``polygon`` (shapely >= 2.1).

    With an older shapely, which lacks :func:`shapely.constrained_delaunay_triangles`, a
    :class:`~blockmesh.errors.ResourceError` names the version needed and the one installed.

    Examples
    --------
    >>> len(shapely.get_parts(constrained_delaunay(shapely.box(0, 0, 1, 1))))
    2
    """
    try:
        triangles = shapely.constrained_delaunay_triangles
    except AttributeError:
        raise ResourceError(
            "decomposing a polygon needs shapely >= 2.1 (its constrained_delaunay_triangles); "
            f"this is shapely {shapely.__version__}: pip install 'shapely>=2.1'"
        ) from None
    return triangles(polygon)


def _constrained_triangles(rings: Sequence[np.ndarray], points: np.ndarray) -> np.ndarray:
    """GEOS's constrained Delaunay triangles as counter-clockwise vertex-id triples."""
    polygon = shapely.Polygon(rings[0], list(rings[1:]))
    collection = constrained_delaunay(polygon)
    parts = shapely.get_parts(collection)
    coords = shapely.get_coordinates(parts).reshape(len(parts), 4, 2)[:, :3]
    ids = {(float(x), float(y)): k for k, (x, y) in enumerate(points.tolist())}
    try:
        triangles = np.array(
            [[ids[(float(x), float(y))] for x, y in tri] for tri in coords.tolist()],
            dtype=np.int64,
        ).reshape(-1, 3)
    except KeyError:
        raise DomainError(
            "the polygon could not be triangulated (the triangulation has a point that is not a "
            "corner); check the rings for nearly touching edges"
        ) from None
    expected = len(points) + 2 * (len(rings) - 1) - 2
    if triangles.shape[0] != expected:
        raise DomainError(
            f"the polygon could not be triangulated ({triangles.shape[0]} triangles instead of "
            f"{expected}); check the rings for nearly touching edges"
        )
    p = points[triangles]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (
        p[:, 2, 0] - p[:, 0, 0]
    )
    triangles[cross < 0] = triangles[cross < 0][:, [0, 2, 1]]
    return triangles


def _orient(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


class _Refiner:
    """Mutable triangle mesh with neighbour links, for Bowyer-Watson insertions and splits.

    ``tri[t]`` are the corners of triangle ``t`` (counter-clockwise); ``nbr[t][i]`` is the triangle
    across the edge from ``tri[t][i]`` to ``tri[t][i + 1]``, or -1 on the boundary. Boundary edges
    are the segments; ``seg[(a, b)]`` (as the triangle runs along it) is its ring edge.
    """

    def __init__(
        self,
        points: np.ndarray,
        triangles: np.ndarray,
        edge_a: np.ndarray,
        edge_b: np.ndarray,
        sharp: list[bool] | None = None,
    ) -> None:
        self.x = points[:, 0].tolist()
        self.y = points[:, 1].tolist()
        self.n_input = len(self.x)
        self.tri = triangles.tolist()
        self.alive = [True] * len(self.tri)
        self.free: list[int] = []
        self.nbr = [[-1, -1, -1] for _ in self.tri]
        self.tri_of: list[int] = [0] * len(self.x)  # some triangle at each vertex
        ring_edge = {
            (int(a), int(b)): k for k, (a, b) in enumerate(zip(edge_a, edge_b, strict=True))
        }
        owner: dict[tuple[int, int], tuple[int, int]] = {}
        for t, (a, b, c) in enumerate(self.tri):
            for i, (p, q) in enumerate(((a, b), (b, c), (c, a))):
                self.tri_of[p] = t
                if (p, q) in ring_edge:  # a segment (an internal one too) is never crossed
                    owner[(p, q)] = (t, i)
                    continue
                other = owner.pop((q, p), None)
                if other is None:
                    owner[(p, q)] = (t, i)
                else:
                    self.nbr[t][i] = other[0]
                    self.nbr[other[0]][other[1]] = t
        # The ring edge each point added on a segment lies on (-1: an input point).
        self.ends = list(zip(edge_a.tolist(), edge_b.tolist(), strict=True))
        self.on_edge = [-1] * len(self.x)
        self.seg: dict[tuple[int, int], int] = {}
        for (p, q), _ in owner.items():
            if (p, q) not in ring_edge:
                raise DomainError(
                    "the polygon could not be triangulated (an edge of the triangulation is "
                    "unmatched); check the rings for nearly touching edges"
                )
            self.seg[(p, q)] = ring_edge[(p, q)]
        if sharp is not None:
            self.sharp = list(sharp)
            return
        # Input corners sharper than 60 degrees: triangles in them cannot be repaired.
        self.sharp = [False] * len(self.x)
        previous = np.empty(len(self.x), dtype=np.int64)
        previous[edge_b] = edge_a
        for v in range(len(self.x)):
            u, w = int(previous[v]), int(edge_b[v])
            ux, uy = self.x[u] - self.x[v], self.y[u] - self.y[v]
            wx, wy = self.x[w] - self.x[v], self.y[w] - self.y[v]
            angle = math.degrees(math.atan2(wx * uy - wy * ux, wx * ux + wy * uy)) % 360.0
            self.sharp[v] = angle < 60.0

    # ---------------------------------------------------------------- geometry helpers
    def _angles(self, t: int) -> tuple[float, int]:
        """Smallest angle of triangle ``t`` (degrees) and the corner (0-2) where it is."""
        a, b, c = self.tri[t]
        x, y = self.x, self.y
        best, where = 180.0, 0
        for i, (p, q, r) in enumerate(((a, b, c), (b, c, a), (c, a, b))):
            ux, uy = x[q] - x[p], y[q] - y[p]
            vx, vy = x[r] - x[p], y[r] - y[p]
            angle = math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy))
            if angle < best:
                best, where = angle, i
        return best, where

    def _circumcentre(self, t: int) -> tuple[float, float] | None:
        a, b, c = self.tri[t]
        x, y = self.x, self.y
        bx, by = x[b] - x[a], y[b] - y[a]
        cx, cy = x[c] - x[a], y[c] - y[a]
        d = 2.0 * (bx * cy - by * cx)
        if d <= 0.0:
            return None
        b2, c2 = bx * bx + by * by, cx * cx + cy * cy
        return x[a] + (cy * b2 - by * c2) / d, y[a] + (bx * c2 - cx * b2) / d

    def _in_circle(self, t: int, px: float, py: float) -> bool:
        a, b, c = self.tri[t]
        x, y = self.x, self.y
        adx, ady = x[a] - px, y[a] - py
        bdx, bdy = x[b] - px, y[b] - py
        cdx, cdy = x[c] - px, y[c] - py
        det = (
            (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
            - (bdx * bdx + bdy * bdy) * (adx * cdy - cdx * ady)
            + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady)
        )
        return det > 0.0

    def _encroaches(self, a: int, b: int, px: float, py: float) -> bool:
        """Whether ``(px, py)`` lies inside the diametral circle of segment ``a``-``b``."""
        x, y = self.x, self.y
        return (x[a] - px) * (x[b] - px) + (y[a] - py) * (y[b] - py) < 0.0

    # ---------------------------------------------------------------- point location
    def _locate(self, t: int, px: float, py: float) -> tuple[str, int, int]:
        """Walk from ``t`` towards the point: ("inside", t, -1) or ("blocked", t, edge)."""
        x, y = self.x, self.y
        for step in range(4 * len(self.tri) + 16):
            tri, nbr = self.tri[t], self.nbr[t]
            for k in range(3):
                i = (k + step) % 3
                p, q = tri[i], tri[(i + 1) % 3]
                if _orient(x[p], y[p], x[q], y[q], px, py) < 0.0:
                    if nbr[i] < 0:
                        return "blocked", t, i
                    t = nbr[i]
                    break
            else:
                return "inside", t, -1
        return "lost", t, -1

    # ---------------------------------------------------------------- cavities
    def _cavity(self, t: int, px: float, py: float, *, on_edge: tuple[int, int] | None = None):
        """The Bowyer-Watson cavity of a point, grown from ``t`` without crossing a segment.

        Returns the triangles whose circumcircle holds the point and the cavity's boundary edges
        ``(p, q, triangle outside)``; with ``on_edge`` (a segment being split) that segment is
        left out of the boundary.
        """
        cavity = [t]
        inside = {t}
        stack = [t]
        while stack:
            s = stack.pop()
            for i in range(3):
                u = self.nbr[s][i]
                if u >= 0 and u not in inside and self._in_circle(u, px, py):
                    inside.add(u)
                    cavity.append(u)
                    stack.append(u)
        edges = []
        for s in cavity:
            tri, nbr = self.tri[s], self.nbr[s]
            for i in range(3):
                if nbr[i] not in inside:
                    p, q = tri[i], tri[(i + 1) % 3]
                    if on_edge is not None and (p, q) == on_edge:
                        continue
                    edges.append((p, q, nbr[i]))
        return cavity, edges

    def _star_shaped(self, edges, px: float, py: float) -> bool:
        x, y = self.x, self.y
        for p, q, _ in edges:
            ax, ay, bx, by = x[p], y[p], x[q], y[q]
            area = _orient(ax, ay, bx, by, px, py)
            # Relative test: the new triangle must have a real area compared with its edge.
            length2 = (bx - ax) ** 2 + (by - ay) ** 2
            if area <= 1e-12 * length2:
                return False
        return True

    def _fill(self, cavity: list[int], edges, v: int) -> list[int]:
        """Replace the cavity by the fan of triangles ``(p, q, v)`` over its boundary edges."""
        slots = list(cavity)
        for s in cavity:
            self.alive[s] = False
        new: list[int] = []
        for p, q, outside in edges:
            if slots:
                t = slots.pop()
                self.tri[t] = [p, q, v]
                self.nbr[t] = [outside, -1, -1]
                self.alive[t] = True
            elif self.free:
                t = self.free.pop()
                self.tri[t] = [p, q, v]
                self.nbr[t] = [outside, -1, -1]
                self.alive[t] = True
            else:
                t = len(self.tri)
                self.tri.append([p, q, v])
                self.nbr.append([outside, -1, -1])
                self.alive.append(True)
            new.append(t)
            if outside >= 0:
                on = self.tri[outside]
                for j in range(3):
                    if on[j] == q and on[(j + 1) % 3] == p:
                        self.nbr[outside][j] = t
                        break
            self.tri_of[p] = self.tri_of[q] = t
        self.free.extend(slots)
        # Link the fan: edge (q, v) of the triangle on (p, q) meets edge (v, q) of the next one.
        starting = {self.tri[t][0]: t for t in new}
        ending = {self.tri[t][1]: t for t in new}
        for t in new:
            p, q, _ = self.tri[t]
            after = starting.get(q)
            if after is not None:
                self.nbr[t][1] = after
            before = ending.get(p)
            if before is not None:
                self.nbr[t][2] = before
        self.tri_of[v] = new[0]
        return new

    def _add_point(self, px: float, py: float) -> int:
        self.x.append(px)
        self.y.append(py)
        self.tri_of.append(-1)
        self.sharp.append(False)
        self.on_edge.append(-1)
        return len(self.x) - 1

    # ---------------------------------------------------------------- operations
    def insert(self, t: int, px: float, py: float) -> tuple[str, list]:
        """Insert an interior point, walking from ``t`` to it.

        Returns ``("done", new triangles)``, ``("split", segments to split first)`` when the
        point is outside or encroaches on boundary segments, or ``("skip", [])``.
        """
        where, s, i = self._locate(t, px, py)
        if where == "blocked":
            p, q = self.tri[s][i], self.tri[s][(i + 1) % 3]
            return "split", [(p, q)]
        if where != "inside":
            return "skip", []
        cavity, edges = self._cavity(s, px, py)
        encroached = [(p, q) for p, q, o in edges if o < 0 and self._encroaches(p, q, px, py)]
        if encroached:
            return "split", encroached
        if not self._star_shaped(edges, px, py):
            return "skip", []
        v = self._add_point(px, py)
        return "done", self._fill(cavity, edges, v)

    def split(self, p: int, q: int) -> list[int] | None:
        """Split the boundary segment ``p -> q`` (as its triangle runs along it)."""
        ring_edge = self.seg.get((p, q))
        if ring_edge is None:
            return None
        x, y = self.x, self.y
        t = self._segment_triangle(p, q)
        if t < 0:
            return None
        f = self._split_fraction(p, q)
        mx = x[p] + f * (x[q] - x[p])
        my = y[p] + f * (y[q] - y[p])
        cavity, edges = self._cavity(t, mx, my, on_edge=(p, q))
        # The segment is no cavity edge: the fan's end triangles get the halves (p, m), (m, q).
        if not self._star_shaped(edges, mx, my):
            return None
        # An internal segment (two faces meet along it) is listed both ways: both sides are split
        # at the same new point, or neither is.
        twin = self.seg.get((q, p))
        if twin is not None:
            s = self._segment_triangle(q, p)
            if s < 0:
                return None
            twin_cavity, twin_edges = self._cavity(s, mx, my, on_edge=(q, p))
            if not self._star_shaped(twin_edges, mx, my):
                return None
        m = self._add_point(mx, my)
        self.on_edge[m] = ring_edge
        new = self._fill(cavity, edges, m)
        del self.seg[(p, q)]
        self.seg[(p, m)] = ring_edge
        self.seg[(m, q)] = ring_edge
        if twin is not None:
            new += self._fill(twin_cavity, twin_edges, m)
            del self.seg[(q, p)]
            self.seg[(q, m)] = twin
            self.seg[(m, p)] = twin
        return new

    def _segment_triangle(self, p: int, q: int) -> int:
        """The triangle running along boundary segment ``p -> q``: turn clockwise around ``p``."""
        t = self.tri_of[p]
        for _ in range(len(self.tri) + 1):
            if t < 0 or not self.alive[t] or p not in self.tri[t]:
                break
            tri = self.tri[t]
            j = tri.index(p)
            if tri[(j + 1) % 3] == q:
                return t
            t = self.nbr[t][j]
        for t, tri in enumerate(self.tri):
            if self.alive[t]:
                for i in range(3):
                    if tri[i] == p and tri[(i + 1) % 3] == q:
                        return t
        return -1

    def _split_fraction(self, p: int, q: int) -> float:
        """Midpoint, or a power-of-two distance from an input corner (concentric shells)."""
        p_input, q_input = p < self.n_input, q < self.n_input
        if p_input == q_input:
            return 0.5
        length = math.hypot(self.x[q] - self.x[p], self.y[q] - self.y[p])
        shell = 2.0 ** round(math.log2(0.5 * length))
        f = min(max(shell / length, 0.25), 0.75)
        return f if p_input else 1.0 - f

    # ---------------------------------------------------------------- driver
    def refine(self, min_angle: float, budget: int) -> None:
        limit = self.n_input + budget
        queue: list[tuple[float, int, tuple[int, int, int]]] = []

        def consider(t: int) -> None:
            angle, _ = self._angles(t)
            if angle < min_angle:
                heapq.heappush(queue, (angle, t, tuple(self.tri[t])))

        # Encroached segments first.
        pending = list(self.seg)
        while pending and len(self.x) < limit:
            p, q = pending.pop()
            if (p, q) not in self.seg:
                continue
            t = self._segment_triangle(p, q)
            if t < 0:
                continue
            r = next(v for v in self.tri[t] if v != p and v != q)
            if self._encroaches(p, q, self.x[r], self.y[r]) and not self._too_short(p, q):
                new = self.split(p, q)
                if new:
                    m = len(self.x) - 1
                    pending.extend([(p, m), (m, q)])
        for t in range(len(self.tri)):
            if self.alive[t]:
                consider(t)
        while queue and len(self.x) < limit:
            _, t, corners = heapq.heappop(queue)
            if not self.alive[t] or tuple(self.tri[t]) != corners:
                continue
            if self._hopeless(t, limit - len(self.x)):
                continue
            centre = self._circumcentre(t)
            if centre is None:
                continue
            status, payload = self.insert(t, *centre)
            if status == "done":
                for s in payload:
                    consider(s)
            elif status == "split":
                split_any = False
                for p, q in payload:
                    if self._too_short(p, q):
                        continue
                    new = self.split(p, q)
                    if new:
                        split_any = True
                        for s in new:
                            consider(s)
                if split_any and self.alive[t] and tuple(self.tri[t]) == corners:
                    consider(t)

    def _too_short(self, p: int, q: int) -> bool:
        return math.hypot(self.x[q] - self.x[p], self.y[q] - self.y[p]) < 1e-9

    def _hopeless(self, t: int, remaining: int) -> bool:
        """A sliver the budget cannot repair, or a triangle in a corner sharper than the target."""
        a, b, c = self.tri[t]
        x, y = self.x, self.y
        lengths = [
            math.hypot(x[b] - x[a], y[b] - y[a]),
            math.hypot(x[c] - x[b], y[c] - y[b]),
            math.hypot(x[a] - x[c], y[a] - y[c]),
        ]
        area2 = abs(_orient(x[a], y[a], x[b], y[b], x[c], y[c]))
        longest = max(lengths)
        if area2 <= 0.0:
            return True
        altitude = area2 / longest
        if longest / altitude > max(remaining, 1):
            return True
        _, where = self._angles(t)
        corner = self.tri[t][where]
        return self.sharp[corner] or self._across_sharp_corner(
            self.tri[t][(where + 1) % 3], self.tri[t][(where + 2) % 3]
        )

    def _across_sharp_corner(self, u: int, v: int) -> bool:
        """Whether ``u``-``v`` joins two segments at one distance from the sharp corner they share.

        Such an edge (points the concentric shells put on both sides of a corner sharper than 60
        degrees) is as short as the corner is sharp: a triangle with it as its shortest edge
        cannot be repaired, as a point inside it would split both segments again, closer to the
        corner, without end.
        """
        ku, kv = self.on_edge[u], self.on_edge[v]
        if ku < 0 or kv < 0:
            return False
        common = set(self.ends[ku]) & set(self.ends[kv])
        if len(common) != 1:
            return False  # one segment (or its twin), or segments that do not meet
        apex = common.pop()
        x, y = self.x, self.y
        ux, uy = x[u] - x[apex], y[u] - y[apex]
        vx, vy = x[v] - x[apex], y[v] - y[apex]
        du, dv = math.hypot(ux, uy), math.hypot(vx, vy)
        if abs(du - dv) > _SAME_SHELL * max(du, dv):
            return False
        return math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy)) < 60.0

    def result(self) -> Triangulation:
        keep = [t for t in range(len(self.tri)) if self.alive[t]]
        triangles = np.array([self.tri[t] for t in keep], dtype=np.int64).reshape(-1, 3)
        points = np.column_stack([self.x, self.y])
        segments = np.array(list(self.seg), dtype=np.int64).reshape(-1, 2)
        segment_edge = np.array(list(self.seg.values()), dtype=np.int64)
        return Triangulation(points, triangles, segments, segment_edge)
