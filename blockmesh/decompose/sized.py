"""Blocks of the sizes a field asks for: an outline sampled, points relaxed, triangles, pentagons.

The size-driven route of the decomposition. Its input is an :class:`Outline`: corners joined by
chains (straight or curved; boundaries, and interfaces between regions), each chain knowing the
region on its left and on its right. Its output is a conforming mesh of strictly convex
pentagons whose diameters follow the field: every cell's diameter is at most
:data:`SIZE_TOLERANCE` times the size asked at its centroid, and the cells are about as few as
that allows (the count lands near 1.5 times the ideal ``integral of 1 / (a h^2)``).

How:

1. **Gradation.** The field is sampled (the outline and a first fill of points, below) and made
   to grow by at most ``gradation`` per cell (:func:`blockmesh.sizing.grade`).
2. **The outline sampled.** Every chain gets points at spacings that follow the triangle edge
   length wanted, ``L = KAPPA h`` (arc length along curves, which also get a point every
   :data:`CURVE_TURN` of turning); the points are fixed from here on, and each chain is sampled
   once, so a shared interface is the same on both sides.
3. **A fill.** Triangles (Delaunay) larger than an equilateral triangle of side ``L`` get a point
   at their centroid, round after round.
4. **Relaxation** (Persson and Strang's DistMesh): every triangle edge is a spring that pushes
   when shorter than ``L`` (scaled so the springs fill the domain); the free points move, the
   triangulation is made again, until the points settle. The triangles come out nearly
   equilateral, their sides close to ``L``.
5. **Conforming triangulation.** A chain segment missing from the Delaunay triangulation is
   split at its middle (on the curve) until every segment is an edge; the triangles are then
   labelled by region across the segments (a flood fill), those outside dropped.
6. **Pentagons.** Every triangle becomes nine pentagons by the balanced template
   (:data:`~blockmesh.decompose.templates.BALANCED_SECTOR_WEIGHTS`), side nodes shared bit for
   bit; then the decomposition's optimiser raises the worst angles
   (:class:`~blockmesh.decompose.optimise.WorstAngle`), nodes on straight chains sliding along
   them, nodes on curves moved onto the curve first and held.
7. **The guarantee.** Cells larger than the tolerance allows are found, their triangles get a
   point more, and steps 4-6 run again for them, until none is left.

Everything runs in the outline's local frame (:func:`blockmesh.geometry.local_frame`); the
corners and the points on chains are computed in the caller's coordinates and kept bit for bit.

Examples
--------
>>> import numpy as np
>>> from blockmesh.sizing import Constant
>>> outline = Outline.from_rings([np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)])
>>> blocks = sized_blocks(outline, Constant(0.2))
>>> bool(blocks.worst_ratio <= SIZE_TOLERANCE), blocks.blocks.shape[1]
(True, 5)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from blockmesh.curves.types import Arc, Curve
from blockmesh.decompose.optimise import WorstAngle
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.templates import BALANCED_SECTOR_WEIGHTS, EDGE_FRACTIONS
from blockmesh.errors import DomainError, ResourceError, fmt_point
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    corner_sines,
    interior_angles,
    local_frame,
)
from blockmesh.refinement.placement import Freedom
from blockmesh.sizing.fields import SizeField, checked_sizes
from blockmesh.sizing.gradation import DEFAULT_GRADATION, grade
from blockmesh.sizing.measure import cell_centroids, cell_diameters

__all__ = [
    "CURVE_TURN",
    "KAPPA",
    "MAX_BLOCKS",
    "NEIGHBOUR_RATIO",
    "SIZE_TOLERANCE",
    "ChainCurve",
    "Outline",
    "SizedBlocks",
    "arc_pieces",
    "sized_blocks",
]

#: The guarantee: every cell's diameter is at most this times the size asked at its centroid.
SIZE_TOLERANCE = 1.5
#: The stated bound on the ratio of the diameters of two cells that share an edge, with the
#: default gradation (measured on the catalogue at sizes spanning 10 times and with
#: distance-threshold fields: at most about 2.7; checked by the tests, not enforced).
NEIGHBOUR_RATIO = 3.0
#: Triangle side aimed at, in units of the size asked (the balanced template's cells are about
#: a third of the side across; measured so that the cells land at 0.9-1.1 h on average).
KAPPA = 3.2
#: Largest turn of a curved chain between two of its points (radians): 30 degrees (each
#: block edge along it, a third of that).
CURVE_TURN = math.pi / 6
#: Most blocks made (about 9 per triangle); beyond, ResourceError (the memory guard of
#: :func:`blockmesh.sizing.ideal_count` says so first, for sizes it can see).
MAX_BLOCKS = 20_000_000
#: Relaxation: iterations, step, and the springs' overshoot (DistMesh's Fscale).
_ITERATIONS = 60
_STEP = 0.2
_FSCALE = 1.2
#: Rounds of the guarantee before giving up (each adds points where cells are too large).
_REPAIRS = 12
#: Cells above this fraction of the tolerance are repaired (a margin for the final rounding).
_REPAIR_AT = 0.995
#: The optimiser's target: corners scoring below it are worked on (the decomposition's default
#: is 38; here 45, for two or three degrees more at a third more time).
_TARGET_ANGLE = 45.0
#: Cells of the templates (before the optimiser) above this ratio to their size are repaired
#: before the optimiser runs.
_EARLY_REPAIR = 1.6
#: After the thinning, a triangle with a side longer than this times the side wanted at its
#: centroid gets a point there: a triangle spanning a gap between two stretches of the outline
#: sampled closer than the field asks (a fibre's arcs, sampled every 30 degrees, beside a wall
#: or another fibre), or running from the outline's crowded points into an interior the count
#: left empty. Without it the relaxation keeps such slivers, and their templates are seams of
#: thin cells (fibre-cell at sqrt(area) / 25: worst angle 13.5 degrees, neighbour ratio 4.75).
_SPAN = 1.75
#: The triangle side allowed beside the outline, in units of the spacing of its points there:
#: a triangle on a segment of length s may rise to this times s (its apex angle at least 2
#: asin(1 / 3), 39 degrees), so the dense points of a curve do not shrink the cells beside it.
_SPACING_RISE = 1.5


@dataclass(frozen=True, eq=False)
class ChainCurve:
    """A stretch of a curve from parameter ``t0`` to ``t1`` (``t1 < t0`` runs it backwards).

    Examples
    --------
    >>> quarter = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
    >>> ChainCurve(quarter, 1.0, 0.0).point(np.array([0.0, 1.0])).round(12).tolist()
    [[0.0, 1.0], [1.0, 0.0]]
    """

    curve: Curve
    t0: float = 0.0
    t1: float = 1.0

    def parameter(self, s: np.ndarray) -> np.ndarray:
        """The curve's parameter at the chain's parameter ``s``."""
        return self.t0 + np.asarray(s, dtype=np.float64) * (self.t1 - self.t0)

    def point(self, s: np.ndarray) -> np.ndarray:
        """Points at the chain's parameters ``s`` in [0, 1]."""
        return np.asarray(self.curve.point(self.parameter(s)))

    def derivative(self, s: np.ndarray) -> np.ndarray:
        """Derivatives with respect to the chain's parameter."""
        return np.asarray(self.curve.derivative(self.parameter(s))) * (self.t1 - self.t0)


@dataclass(frozen=True, eq=False)
class Outline:
    """Corners joined by chains (straight or curved), with the regions on their sides.

    Attributes
    ----------
    corners : ndarray (K, 2)
    chains : ndarray (C, 2) int
        Each chain runs from corner ``chains[c, 0]`` to ``chains[c, 1]``.
    curves : tuple of (ChainCurve or None)
        Each chain's curve from its start (parameter 0) to its end (1), or None if straight.
    left, right : ndarray (C,) int
        The region on each side of the chain as it runs; -1 outside the domain.
    """

    corners: np.ndarray
    chains: np.ndarray
    curves: tuple[ChainCurve | None, ...]
    left: np.ndarray
    right: np.ndarray

    @classmethod
    def from_rings(
        cls, rings: Sequence[np.ndarray], curves: Sequence[Curve | None] | None = None
    ) -> Outline:
        """A one-region outline from rings (outer counter-clockwise, holes clockwise).

        ``curves`` lists a curve (or None) per ring edge, ring after ring.

        Examples
        --------
        >>> Outline.from_rings([np.array([[0, 0], [1, 0], [0, 1]], dtype=float)]).chains.tolist()
        [[0, 1], [1, 2], [2, 0]]
        """
        counts = [len(r) for r in rings]
        corners = np.vstack([np.asarray(r, dtype=np.float64) for r in rings])
        start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        a = np.concatenate([s + np.arange(c) for s, c in zip(start, counts, strict=True)])
        b = np.concatenate([s + (np.arange(c) + 1) % c for s, c in zip(start, counts, strict=True)])
        n = len(a)
        given = (
            tuple(None if c is None else ChainCurve(c) for c in curves)
            if curves is not None
            else (None,) * n
        )
        return cls(
            corners, np.column_stack([a, b]), given, np.zeros(n, np.int64), -np.ones(n, np.int64)
        )


@dataclass(frozen=True, eq=False)
class SizedBlocks:
    """The pentagons of an outline at the sizes of a field.

    Attributes
    ----------
    vertices : ndarray (N, 2)
        The outline's corners first (bit for bit), then the other nodes.
    blocks : ndarray (B, 5) int
        Counter-clockwise, strictly convex.
    region : ndarray (B,) int
        The region of each block (as the outline numbers them).
    chain_nodes : tuple of ndarray
        The node ids along each chain, from its start to its end.
    chain_params : tuple of ndarray
        The curve parameter of each of those nodes (the chord's fraction on a straight chain).
    triangles : int
        How many triangles the blocks came from.
    worst_ratio : float
        The largest ``diameter / size asked at the centroid`` (at most :data:`SIZE_TOLERANCE`).
    field : SizeField
        The graded field the blocks were made for.
    """

    vertices: np.ndarray
    blocks: np.ndarray
    region: np.ndarray
    chain_nodes: tuple[np.ndarray, ...]
    chain_params: tuple[np.ndarray, ...]
    triangles: int
    worst_ratio: float
    field: SizeField

    @property
    def min_angle(self) -> float:
        """Smallest interior angle of any block, in degrees (of the straight blocks)."""
        return float(interior_angles(self.vertices[self.blocks]).min())


# ---------------------------------------------------------------------------- sampling
def _chain_params(outline: Outline, c: int, length, *, pieces_at_least: int = 1) -> np.ndarray:
    """Parameters (m + 1,) from 0 to 1 spacing the chain at the triangle side ``length``.

    The arc length is integrated with a dense sampling; the points are equally spaced in
    ``integral of ds / L`` (so the pieces follow the field along the chain), at least
    ``pieces_at_least`` of them, and curves get a piece per :data:`CURVE_TURN` of turning.
    """
    a, b = outline.chains[c]
    curve = outline.curves[c]
    p, q = outline.corners[a], outline.corners[b]

    def where(t: np.ndarray) -> np.ndarray:
        return p + t[:, None] * (q - p) if curve is None else curve.point(t)

    samples = 32
    pieces = pieces_at_least
    turns = 0
    if curve is not None:
        tangent = curve.derivative(np.linspace(0.0, 1.0, 257))
        heading = np.unwrap(np.arctan2(tangent[:, 1], tangent[:, 0]))
        turns = math.ceil(float(np.sum(np.abs(np.diff(heading)))) / CURVE_TURN - 1e-9)
    for _ in range(4):
        t = np.linspace(0.0, 1.0, samples + 1)
        xy = where(t)
        ds = np.hypot(*np.diff(xy, axis=0).T)
        middle = where(0.5 * (t[:-1] + t[1:]))
        measure = np.concatenate([[0.0], np.cumsum(ds / length(middle))])
        pieces = max(pieces_at_least, turns, round(float(measure[-1])), 1)
        if samples >= 8 * pieces:
            break
        samples = 8 * pieces
    if pieces > MAX_BLOCKS:
        raise ResourceError(
            f"the size field asks for {pieces:,} pieces along one boundary or interface line; "
            "give larger sizes"
        )
    # Equal steps of the measure (and of the turning, on curves, where it asks for more).
    targets = np.linspace(0.0, float(measure[-1]), pieces + 1)
    params = np.interp(targets, measure, t)
    if turns > round(float(measure[-1])):
        params = np.linspace(0.0, 1.0, pieces + 1)
    params[0], params[-1] = 0.0, 1.0
    return params


def _chain_points(outline: Outline, c: int, params: np.ndarray) -> np.ndarray:
    """Global coordinates of chain ``c`` at ``params`` (the ends are the corners, bit for bit)."""
    a, b = outline.chains[c]
    curve = outline.curves[c]
    p, q = outline.corners[a], outline.corners[b]
    xy = p + params[:, None] * (q - p) if curve is None else np.asarray(curve.point(params))
    xy = np.array(xy, dtype=np.float64)
    xy[0], xy[-1] = p, q
    return xy


class _Chains:
    """The outline's sample points (fixed) and segments, each segment on one chain."""

    def __init__(self, outline: Outline, frame, length) -> None:
        self.outline = outline
        self.frame = frame
        k = len(outline.corners)
        points = [outline.corners]
        seg_a, seg_b, seg_chain, seg_t0, seg_t1 = [], [], [], [], []
        self.params: list[np.ndarray] = []
        next_id = k
        for c in range(len(outline.chains)):
            params = _chain_params(outline, c, length)
            self.params.append(params)
            inner = len(params) - 2
            ids = np.concatenate(
                [[outline.chains[c, 0]], next_id + np.arange(inner), [outline.chains[c, 1]]]
            )
            points.append(_chain_points(outline, c, params)[1:-1])
            next_id += inner
            seg_a.append(ids[:-1])
            seg_b.append(ids[1:])
            seg_chain.append(np.full(len(ids) - 1, c))
            seg_t0.append(params[:-1])
            seg_t1.append(params[1:])
        self.global_points = np.vstack(points)
        self.a = np.concatenate(seg_a)
        self.b = np.concatenate(seg_b)
        self.chain = np.concatenate(seg_chain)
        self.t0 = np.concatenate(seg_t0)
        self.t1 = np.concatenate(seg_t1)

    @property
    def n(self) -> int:
        return len(self.global_points)

    def local(self) -> np.ndarray:
        return self.frame.to_local(self.global_points)

    def segments(self) -> np.ndarray:
        """The segments in local coordinates, (S, 2, 2)."""
        local = self.local()
        return np.stack([local[self.a], local[self.b]], axis=1)

    def split(self, segments: np.ndarray) -> None:
        """Split the given segments at their middle parameter (a new fixed point each)."""
        t = 0.5 * (self.t0[segments] + self.t1[segments])
        new_points = np.empty((len(segments), 2))
        for c in np.unique(self.chain[segments]):
            sel = self.chain[segments] == c
            new_points[sel] = _chain_points(
                self.outline, int(c), np.concatenate([[0.0], t[sel], [1.0]])
            )[1:-1]
        ids = self.n + np.arange(len(segments))
        self.global_points = np.vstack([self.global_points, new_points])
        keep_b, keep_t1 = self.b[segments].copy(), self.t1[segments].copy()
        self.b[segments] = ids
        self.t1[segments] = t
        self.a = np.concatenate([self.a, ids])
        self.b = np.concatenate([self.b, keep_b])
        self.chain = np.concatenate([self.chain, self.chain[segments]])
        self.t0 = np.concatenate([self.t0, t])
        self.t1 = np.concatenate([self.t1, keep_t1])


# ---------------------------------------------------------------------------- triangles
def _delaunay(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Counter-clockwise Delaunay triangles, their neighbours, and which are flat.

    The neighbours are listed opposite each corner; a flat triangle has three points on a line
    of the convex hull (Qhull keeps them).
    """
    from scipy.spatial import Delaunay

    tri = Delaunay(points)
    simplices = tri.simplices.astype(np.int64)
    neighbours = tri.neighbors.astype(np.int64)
    p = points[simplices]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (
        p[:, 2, 0] - p[:, 0, 0]
    )
    flip = cross < 0
    simplices[flip] = simplices[flip][:, [0, 2, 1]]
    neighbours[flip] = neighbours[flip][:, [0, 2, 1]]
    longest = np.max(np.sum((p - np.roll(p, 1, axis=1)) ** 2, axis=2), axis=1)
    flat = np.abs(cross) <= 1e-12 * longest
    return simplices, neighbours, flat


def _domain_test(chains: _Chains, local: np.ndarray):
    """A prepared shapely geometry of the domain (the faces of the sampled chains inside)."""
    import shapely

    segments = np.stack([local[chains.a], local[chains.b]], axis=1)
    faces = list(shapely.get_parts(shapely.polygonize(shapely.linestrings(segments))))
    # A face is inside when the segment along its first edge has a region on the face's side.
    lookup = {}
    for k, (p, q) in enumerate(segments.tolist()):
        lookup[(tuple(p), tuple(q))] = (k, True)
        lookup[(tuple(q), tuple(p))] = (k, False)
    inside = []
    for face in faces:
        ring = np.asarray(face.exterior.coords)
        if not shapely.LinearRing(ring).is_ccw:
            ring = ring[::-1]
        for p, q in zip(ring[:-1].tolist(), ring[1:].tolist(), strict=True):
            hit = lookup.get((tuple(p), tuple(q)))
            if hit is None:
                continue
            k, forward = hit
            c = chains.chain[k]
            region = chains.outline.left[c] if forward else chains.outline.right[c]
            if region >= 0:
                inside.append(face)
            break
    if not inside:
        raise DomainError("the outline encloses no area inside the domain")
    domain = shapely.union_all(inside)
    shapely.prepare(domain)
    return domain


def _inside(domain, xy: np.ndarray) -> np.ndarray:
    import shapely

    return shapely.contains_xy(domain, xy[:, 0], xy[:, 1])


def _kept(points: np.ndarray, domain) -> np.ndarray:
    """Delaunay triangles whose centroid is inside the domain."""
    triangles, _, flat = _delaunay(points)
    triangles = triangles[~flat]
    return triangles[_inside(domain, points[triangles].mean(axis=1))]


def _fill(
    points: np.ndarray, domain, length, rounds: int = 60, *, span: float | None = None
) -> np.ndarray:
    """Add centroids of triangles larger than an equilateral triangle of side ``length``.

    With ``span``, of triangles with a side longer than ``span`` times ``length`` instead: the
    gap-aware step (:data:`_SPAN`). A gap narrower than a few triangle sides, between stretches
    of the outline whose points are closer than the field asks, is first spanned by long thin
    triangles from one side to the other; their centroids put points in the gap, round after
    round, until every triangle there is about as long as wide.
    """
    for _ in range(rounds):
        triangles = _kept(points, domain)
        xy = points[triangles]
        centre = xy.mean(axis=1)
        wanted = length(centre)
        if span is None:
            u, v = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
            area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
            big = area > 1.5 * (math.sqrt(3) / 4) * wanted**2
        else:
            sides = np.hypot(*(xy - np.roll(xy, 1, axis=1)).transpose(2, 0, 1))
            big = sides.max(axis=1) > span * wanted
        if not big.any():
            return points
        if len(points) + int(big.sum()) > MAX_BLOCKS // 4:
            raise ResourceError(
                f"the size field asks for more than {MAX_BLOCKS:,} blocks; give larger sizes"
            )
        points = np.vstack([points, centre[big]])
    return points


def _feature_sizes(chains: _Chains, length) -> np.ndarray:
    """The triangle side the outline itself asks for at each of its points (local units).

    :data:`_SPACING_RISE` times the spacing of a chain's points (shorter than asked on a curve,
    a short chain or where the chain's rounding made it so), and the width of a gap: the
    distance to the nearest segment that does not touch the point's own segments. Triangles
    larger than this beside the outline would be slivers.
    """
    import shapely

    local = chains.local()
    n = len(local)
    seg_length = np.hypot(*(local[chains.b] - local[chains.a]).T)
    spacing = np.full(n, np.inf)
    np.minimum.at(spacing, chains.a, _SPACING_RISE * seg_length)
    np.minimum.at(spacing, chains.b, _SPACING_RISE * seg_length)
    # Neighbours of each point along the outline (the ends of its segments), padded with -1.
    ends = np.concatenate([chains.a, chains.b])
    other = np.concatenate([chains.b, chains.a])
    order = np.argsort(ends, kind="stable")
    degree = np.bincount(ends, minlength=n)
    width = int(degree.max(initial=1))
    slot = np.arange(len(ends)) - np.repeat(np.cumsum(degree) - degree, degree)
    neighbours = np.full((n, width), -1, dtype=np.int64)
    neighbours[ends[order], slot] = other[order]
    segments = chains.segments()
    tree = shapely.STRtree(shapely.linestrings(segments))
    point, seg = tree.query(shapely.points(local), predicate="dwithin", distance=length(local))
    if point.size:
        near = np.column_stack([point, neighbours[point]])
        touching = np.any(
            (near == chains.a[seg][:, None]) | (near == chains.b[seg][:, None]), axis=1
        )
        point, seg = point[~touching], seg[~touching]
        gap = np.hypot(*(local[point] - _closest_on_segments(local[point], segments[seg])).T)
        np.minimum.at(spacing, point, gap)
    return spacing


def _thin(points: np.ndarray, n_fixed: int, domain, length) -> np.ndarray:
    """Drop the most crowded free points until the triangles are as many as the field asks.

    The fill overshoots (a triangle split in three is often too small); the count the field
    asks for is the integral of ``1 / (area of an equilateral triangle of side L)``, and by
    Euler's formula each free point removed removes two triangles. Points go most crowded first
    (shortest edge for its ``L``), never two neighbours in one round.
    """
    for _ in range(20):
        triangles = _kept(points, domain)
        xy = points[triangles]
        u, v = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
        area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        wanted = float(np.sum(area / ((math.sqrt(3) / 4) * length(xy.mean(axis=1)) ** 2)))
        excess = round((len(triangles) - wanted) / 2)
        if excess <= 0:
            return points
        e = _edges(triangles)
        ratio = np.hypot(*(points[e[:, 1]] - points[e[:, 0]]).T) / length(
            0.5 * (points[e[:, 0]] + points[e[:, 1]])
        )
        crowd = np.full(len(points), np.inf)
        np.minimum.at(crowd, e[:, 0], ratio)
        np.minimum.at(crowd, e[:, 1], ratio)
        crowd[:n_fixed] = np.inf
        # A point goes when it is more crowded than every neighbour (ties by id).
        key = crowd + 1e-12 * np.arange(len(points)) / len(points)
        lowest = np.full(len(points), np.inf)
        np.minimum.at(lowest, e[:, 0], key[e[:, 1]])
        np.minimum.at(lowest, e[:, 1], key[e[:, 0]])
        candidates = np.flatnonzero(np.isfinite(key) & (key < lowest))
        if not candidates.size:
            return points
        drop = candidates[np.argsort(key[candidates])[:excess]]
        keep = np.ones(len(points), dtype=bool)
        keep[drop] = False
        points = points[keep]
    return points


def _edges(triangles: np.ndarray) -> np.ndarray:
    """The triangles' undirected edges (E, 2), each once (lower id first)."""
    if not len(triangles):
        return np.zeros((0, 2), dtype=np.int64)
    n = int(triangles.max()) + 1
    e = np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    keys = np.unique(np.minimum(e[:, 0], e[:, 1]) * n + np.maximum(e[:, 0], e[:, 1]))
    return np.column_stack(np.divmod(keys, n))


def _relax(
    points: np.ndarray,
    n_fixed: int,
    domain,
    length,
    segments: np.ndarray,
    iterations: int = _ITERATIONS,
    *,
    movable: np.ndarray | None = None,
    scale: float | None = None,
) -> tuple[np.ndarray, float]:
    """DistMesh: springs along the triangle edges push the free points apart to ``length``.

    ``segments`` (S, 2, 2) is the sampled outline: a free point nearer to it than half its
    ``length`` is pushed straight away from it too (the outline's points are fixed, so without
    this a free point could slip between two of them onto the boundary), and a move that would
    take a free point out of the domain or nearer than that to the outline is not made. The
    triangulation is made again only when some point has moved a fifth of its ``length`` since
    the last one; the outline is only looked at for points within two ``length`` of its points.

    ``movable`` (a mask) limits the points that move, and ``scale`` fixes the springs' rest
    length to ``scale * length`` (by default it is set so that the springs fill the domain): a
    repair moves the points near the ones it added and leaves the rest of the mesh as it was.
    Returns the points and the scale used last.
    """
    import shapely
    from scipy.spatial import cKDTree

    tree = shapely.STRtree(shapely.linestrings(segments))
    outline_points = cKDTree(points[:n_fixed])
    points = points.copy()
    moving = np.arange(len(points)) >= n_fixed
    if movable is not None:
        moving &= movable
    free = np.flatnonzero(moving)
    used = 1.0

    def clearance(xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance to the outline and the unit direction away from its nearest point."""
        index = tree.query_nearest(shapely.points(xy), all_matches=False)
        nearest = np.empty_like(xy)
        nearest[index[0]] = _closest_on_segments(xy[index[0]], segments[index[1]])
        away = xy - nearest
        d = np.hypot(away[:, 0], away[:, 1])
        return d, away / np.maximum(d, 1e-300)[:, None]

    reference = np.full_like(points, np.inf)
    e = np.zeros((0, 2), dtype=np.int64)
    for _ in range(iterations):
        here = length(points)
        moved_far = np.hypot(*(points - reference).T) > 0.2 * here
        if moved_far.any():
            e = _edges(_kept(points, domain))
            reference = points.copy()
        vec = points[e[:, 1]] - points[e[:, 0]]
        lengths = np.hypot(vec[:, 0], vec[:, 1])
        wanted = 0.5 * (here[e[:, 0]] + here[e[:, 1]])
        used = (
            _FSCALE * math.sqrt(float(np.sum(lengths**2)) / float(np.sum(wanted**2)))
            if scale is None
            else scale
        )
        force = np.maximum(used * wanted - lengths, 0.0)
        push = vec * (force / np.maximum(lengths, 1e-300))[:, None]
        total = np.zeros_like(points)
        np.add.at(total, e[:, 0], -push)
        np.add.at(total, e[:, 1], push)
        step = np.zeros_like(points)
        step[free] = _STEP * total[free]
        # Points near the outline: pushed away from it, kept inside and clear of it.
        gap, _ = outline_points.query(points[free])
        edge = free[gap < 2.0 * here[free]]
        if edge.size:
            d, away = clearance(points[edge])
            near = d < 0.5 * here[edge]
            step[edge[near]] += _STEP * (0.5 * here[edge][near] - d[near])[:, None] * away[near]
            target = points[edge] + step[edge]
            d_new, _ = clearance(target)
            ok = _inside(domain, target) & (
                (d_new >= np.minimum(d, 0.5 * here[edge])) | (d_new >= d)
            )
            step[edge[~ok]] = 0.0
        points += step
        if float(np.max(np.hypot(*step[free].T) / here[free], initial=0.0)) < 1e-3:
            break
    return points, used


def _closest_on_segments(xy: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """The point of each segment (S, 2, 2) nearest to the matching point (S, 2)."""
    p, q = segments[:, 0], segments[:, 1]
    d = q - p
    t = np.sum((xy - p) * d, axis=1) / np.maximum(np.sum(d * d, axis=1), 1e-300)
    return p + np.clip(t, 0.0, 1.0)[:, None] * d


def _conforming(
    chains: _Chains, free: np.ndarray, frame
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Delaunay triangles with every chain segment an edge (segments split until so).

    Returns ``(points, triangles, region)``: the local points (fixed then free), the triangles
    inside the domain, and each one's region.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    for _ in range(40):
        fixed = chains.local()
        points = np.vstack([fixed, free])
        n = len(points)
        triangles, neighbours, flat = _delaunay(points)
        # Directed triangle edges, opposite corner k: (k + 1, k + 2); flat ones match nothing.
        tail = triangles[:, [1, 2, 0]].ravel()
        head = triangles[:, [2, 0, 1]].ravel()
        directed = np.where(np.repeat(flat, 3), -1, tail * n + head)
        order = np.argsort(directed)
        forward_key = chains.a * n + chains.b
        backward_key = chains.b * n + chains.a
        found_f = _lookup(directed, order, forward_key)
        found_b = _lookup(directed, order, backward_key)
        missing = np.flatnonzero((found_f < 0) & (found_b < 0))
        if missing.size:
            chains.split(missing)
            # Free points too close to the new points would make slivers: drop them.
            continue
        break
    else:
        raise DomainError(
            "the boundary could not be followed by the size-driven triangulation (segments keep "
            "missing); the domain may have gaps thinner than the sizes asked there"
        )
    m = len(triangles)
    # Flood fill across every triangle edge that is not a segment.
    nbr = neighbours.ravel()
    slot = np.arange(3 * m)
    is_segment = np.zeros(3 * m, dtype=bool)
    is_segment[found_f[found_f >= 0]] = True
    is_segment[found_b[found_b >= 0]] = True
    join = (nbr >= 0) & ~is_segment
    join &= ~np.repeat(flat, 3)
    join[join] &= ~flat[nbr[join]]
    graph = coo_matrix((np.ones(int(join.sum())), (slot[join] // 3, nbr[join])), shape=(m, m))
    _, component = connected_components(graph, directed=False)
    # Regions: the triangle left of a segment as its chain runs is in the chain's left region.
    label = np.full(component.max() + 1, -2, dtype=np.int64)
    for found, side in ((found_f, chains.outline.left), (found_b, chains.outline.right)):
        hit = found >= 0
        comp = component[found[hit] // 3]
        region = side[chains.chain[hit]]
        clash = (label[comp] != -2) & (label[comp] != region)
        if clash.any():
            k = int(np.flatnonzero(hit)[np.flatnonzero(clash)[0]])
            where = frame.to_global(points[chains.a[k]])
            raise DomainError(
                f"the outline is not closed near {fmt_point(where)}: a piece of the domain is on "
                "both sides of a boundary line"
            )
        label[comp] = region
    region = label[component]
    keep = (region >= 0) & ~flat
    return points, triangles[keep], region[keep]


def _lookup(keys: np.ndarray, order: np.ndarray, wanted: np.ndarray) -> np.ndarray:
    """Position in ``keys`` of each wanted key, or -1."""
    sorted_keys = keys[order]
    at = np.clip(np.searchsorted(sorted_keys, wanted), 0, len(keys) - 1)
    return np.where(sorted_keys[at] == wanted, order[at], -1)


# ---------------------------------------------------------------------------- pentagons
def _pentagons(chains: _Chains, points: np.ndarray, triangles: np.ndarray, weight: np.ndarray):
    """Balanced templates on the triangles, graded; the node chains and their parameters.

    The template's nodes are placed by barycentric weights on the triangle's corners; each
    weight is scaled by the corner's ``weight`` (``L^(-1/2)``, ``L`` the triangle side wanted
    there) and the three renormalised, so the cells near a corner asking smaller cells come out
    smaller: to first order, cells proportional to a linearly varying ``L``. A node on a side
    depends only on that side's two corners, so neighbours still share it.
    """
    pieces = pentagons_from_pieces(points, [triangles], BALANCED_SECTOR_WEIGHTS)
    nodes = np.array(pieces.nodes)
    count = len(triangles)
    first_new = len(points) + 2 * len(pieces.side_keys)
    sides = pieces.side_chains(triangles.ravel(), np.roll(triangles, -1, axis=1).ravel())
    ids = np.concatenate(
        [
            sides[:, 1:3].reshape(count, 6),
            first_new + 10 * np.arange(count)[:, None] + np.arange(10),
        ],
        axis=1,
    )
    corner = points[triangles]  # (T, 3, 2)
    matrix = np.stack([corner[:, 0] - corner[:, 2], corner[:, 1] - corner[:, 2]], axis=2)
    lam = np.linalg.solve(matrix[:, None], (nodes[ids] - corner[:, None, 2])[..., None])[..., 0]
    lam = np.concatenate([lam, 1.0 - lam.sum(axis=2, keepdims=True)], axis=2)
    mu = lam * weight[triangles][:, None, :]
    mu /= mu.sum(axis=2, keepdims=True)
    nodes[ids] = np.einsum("tnk,tkd->tnd", mu, corner)
    n_chains = len(chains.outline.chains)
    along = pieces.side_chains(chains.a, chains.b)  # (S, 4): a, two side nodes, b
    wa, wb = weight[chains.a], weight[chains.b]
    f1, f2 = EDGE_FRACTIONS
    g1 = f1 * wb / ((1 - f1) * wa + f1 * wb)
    g2 = f2 * wb / ((1 - f2) * wa + f2 * wb)
    span = chains.t1 - chains.t0
    t_side = np.column_stack([chains.t0, chains.t0 + g1 * span, chains.t0 + g2 * span, chains.t1])
    order = np.lexsort((chains.t0, chains.chain))
    bounds = np.searchsorted(chains.chain[order], np.arange(n_chains + 1))
    chain_nodes, chain_params = [], []
    for c in range(n_chains):
        run = order[bounds[c] : bounds[c + 1]]
        chain_nodes.append(np.concatenate([along[run, :3].ravel(), along[run[-1:], 3]]))
        chain_params.append(np.concatenate([t_side[run, :3].ravel(), t_side[run[-1:], 3]]))
    return pieces, nodes, chain_nodes, chain_params


def _bend(
    chains: _Chains,
    frame,
    pieces,
    nodes: np.ndarray,
    points: np.ndarray,
    triangles: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Template nodes of triangles with a side on a curve, moved with the curve.

    A triangle ``(A, B, C)`` whose side ``AB`` is a chord of curve ``γ`` is mapped by the
    transfinite (Gordon-Hall) map ``x + (λA + λB) (γ(t) - ((1 - t) A + t B))``,
    ``t = λB / (λA + λB)``, with ``λ`` the barycentric coordinates of the straight node: the
    nodes on ``AB`` land on the curve, those on the other sides stay (their neighbours across
    share them), and the inner nodes follow, so the cells keep their shapes. Triangles with two
    curved sides take both displacements. Where the full displacement of the inner nodes would
    fold a cell (a flat triangle on a strongly curved piece), they move less; the triangles
    that fold even so are returned, for their chain segment to be split.
    """
    curved = np.array([c is not None for c in chains.outline.curves], dtype=bool)
    segments = np.flatnonzero(curved[chains.chain])
    if not segments.size:
        return nodes, np.zeros(0, dtype=np.int64)
    n = len(points)
    # The triangles on either side of each curved segment, and which corner is off it.
    keys = np.minimum(triangles, np.roll(triangles, -1, axis=1)) * n + np.maximum(
        triangles, np.roll(triangles, -1, axis=1)
    )
    seg_keys = np.minimum(chains.a[segments], chains.b[segments]) * n + np.maximum(
        chains.a[segments], chains.b[segments]
    )
    tri, side = np.nonzero(np.isin(keys, seg_keys))
    which = segments[np.argsort(seg_keys)][np.searchsorted(np.sort(seg_keys), keys[tri, side])]
    per_piece = 10  # the hub and nine inner nodes of a triangle's template
    first_new = len(points) + 2 * len(pieces.side_keys)
    # Each bent triangle's nodes, their displacement, and whether they are on its curved side.
    bent: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
    for t, k, c in zip(tri.tolist(), side.tolist(), which.tolist(), strict=True):
        corners = triangles[t]
        a_id, b_id = corners[k], corners[(k + 1) % 3]
        ends = {int(chains.a[c]): 0.0, int(chains.b[c]): 1.0}
        own = np.concatenate(
            [
                pieces.side_chains(corners, np.roll(corners, -1))[:, 1:3].ravel(),
                first_new + per_piece * t + np.arange(per_piece),
            ]
        )
        A, B, C = points[a_id], points[b_id], points[corners[(k + 2) % 3]]
        matrix = np.column_stack([A - C, B - C])
        lam = np.linalg.solve(matrix, (nodes[own] - C).T).T
        on = lam[:, 0] + lam[:, 1]
        t_side = np.where(on > 1e-12, lam[:, 1] / np.maximum(on, 1e-300), 0.0)
        # Chain parameter along the segment from a_id to b_id.
        s0, s1 = ends[int(a_id)], ends[int(b_id)]
        param = chains.t0[c] + (s0 + t_side * (s1 - s0)) * (chains.t1[c] - chains.t0[c])
        curve = _chain_points(
            chains.outline, int(chains.chain[c]), np.concatenate([[0.0], param, [1.0]])
        )[1:-1]
        chord = (1 - t_side)[:, None] * A + t_side[:, None] * B
        shift = on[:, None] * (frame.to_local(curve) - chord)
        if t in bent:
            ids, before, side_of = bent[t]
            bent[t] = (ids, before + shift, side_of | (on > 1 - 1e-9))
        else:
            bent[t] = (own, shift, on > 1 - 1e-9)
    # Inner nodes move by the full displacement, or less where that would fold a cell.
    moved = nodes.copy()
    folded = []
    for t, (ids, shift, side_of) in bent.items():
        rows = pieces.blocks[9 * t : 9 * t + 9]
        for factor in (1.0, 0.6, 0.3, 0.0):
            moved[ids] = nodes[ids] + np.where(side_of[:, None], shift, factor * shift)
            if np.all(corner_sines(moved[rows]) > 1e3 * COLLINEAR_SIN_TOL):
                break
        else:
            folded.append(t)
    return moved, np.array(folded, dtype=np.int64)


def _place_on_outline(
    outline: Outline,
    frame,
    nodes: np.ndarray,
    chain_nodes: list[np.ndarray],
    chain_params: list[np.ndarray],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes on chains at their exact places; which nodes are fixed and which slide."""
    fixed = np.zeros(len(nodes), dtype=bool)
    slide = np.zeros((len(nodes), 2))
    fixed[: len(outline.corners)] = True
    exact = np.zeros((len(nodes), 2))
    has_exact = np.zeros(len(nodes), dtype=bool)
    for c, (ids, params) in enumerate(zip(chain_nodes, chain_params, strict=True)):
        xy = _chain_points(outline, c, params)
        exact[ids] = xy
        has_exact[ids] = True
        inner = ids[1:-1]
        if outline.curves[c] is not None:
            fixed[inner] = True
        else:
            d = nodes[ids[-1]] - nodes[ids[0]]
            slide[inner] = d / np.hypot(*d)
    nodes[has_exact] = frame.to_local(exact[has_exact])
    return nodes, fixed, slide


# ---------------------------------------------------------------------------- driver
def sized_blocks(
    outline: Outline,
    field: SizeField,
    *,
    gradation: float = DEFAULT_GRADATION,
) -> SizedBlocks:
    """Strictly convex pentagons following ``field`` over ``outline`` (see the module notes).

    Parameters
    ----------
    outline : Outline
    field : SizeField
        The size asked (a cell diameter) at every point of the domain, in its coordinates.
    gradation : float
        Largest ratio by which the field may grow from a cell to its neighbour (``inf``: as
        asked).

    Returns
    -------
    SizedBlocks

    Raises
    ------
    ResourceError
        When the field asks for more than :data:`MAX_BLOCKS` blocks.
    DomainError
        When the outline cannot be followed (gaps thinner than the sizes and the round-off).
    """
    corners = np.asarray(outline.corners, dtype=np.float64)
    frame = local_frame(corners)

    def local_length(graded: SizeField):
        def length(xy: np.ndarray) -> np.ndarray:
            return KAPPA * checked_sizes(graded, frame.to_global(xy)) / frame.scale

        return length

    # 1. The field graded on a first fill made for the field as asked.
    asked_length = local_length(field)
    chains = _Chains(outline, frame, lambda xy: KAPPA * checked_sizes(field, xy))
    domain = _domain_test(chains, chains.local())
    seeds = field.seeds()
    seeds = frame.to_local(seeds) if len(seeds) else np.zeros((0, 2))
    seeds = seeds[_inside(domain, seeds)] if len(seeds) else seeds
    background = _fill(np.vstack([chains.local(), seeds]), domain, asked_length)
    triangles = _kept(background, domain)
    caps = np.full(len(background), np.inf)
    caps[: chains.n] = _feature_sizes(chains, asked_length) * frame.scale / KAPPA
    graded = grade(field, gradation, frame.to_global(background), _edges(triangles), caps)
    length = local_length(graded)
    # 2-4. The outline sampled, filled and relaxed for the graded field.
    chains = _Chains(outline, frame, lambda xy: KAPPA * checked_sizes(graded, xy))
    domain = _domain_test(chains, chains.local())
    points = _fill(chains.local(), domain, length)
    points = _thin(points, chains.n, domain, length)
    points = _fill(points, domain, length, span=_SPAN)
    points, scale = _relax(points, chains.n, domain, length, chains.segments())
    free = points[chains.n :]
    optimised_once = False
    for _ in range(_REPAIRS):
        # 5-6. Conforming triangles, pentagons, worst angles raised.
        local, triangles, region = _conforming(chains, free, frame)
        if 9 * len(triangles) > MAX_BLOCKS:
            raise ResourceError(
                f"the size field asks for {9 * len(triangles):,} blocks, more than the "
                f"{MAX_BLOCKS:,} a decomposition makes; give larger sizes"
            )
        weight = length(local) ** -0.5
        pieces, nodes, chain_nodes, chain_params = _pentagons(chains, local, triangles, weight)
        nodes, folded = _bend(chains, frame, pieces, nodes, local, triangles)
        nodes, fixed, slide = _place_on_outline(outline, frame, nodes, chain_nodes, chain_params)
        blocks = pieces.blocks
        centroids = frame.to_global(cell_centroids(nodes, blocks))
        asked = checked_sizes(field, centroids)
        # Cells far too large before the optimiser are repaired first (the optimiser is the
        # expensive step; it shrinks cells by a few per cent, not by a fifth).
        ratio = cell_diameters(nodes, blocks) * frame.scale / asked
        early = ratio > _EARLY_REPAIR
        checked = False
        if (early.any() or folded.size) and not optimised_once:
            too_large = early
        else:
            checked = True
            nodes = WorstAngle(target=_TARGET_ANGLE, sweeps=10, sizes=asked / frame.scale).place(
                nodes, blocks, Freedom(fixed, slide)
            )
            optimised_once = True
            # 7. The guarantee.
            vertices = frame.to_global(nodes)
            vertices[: len(corners)] = corners
            centroids = cell_centroids(vertices, blocks)
            ratio = cell_diameters(vertices, blocks) / checked_sizes(field, centroids)
            too_large = ratio > _REPAIR_AT * SIZE_TOLERANCE
            if not too_large.any() and not folded.size:
                break
        bad = np.union1d(pieces.piece[too_large], folded)
        kept = len(local) - chains.n
        free = _repair(chains, local, triangles, bad, length, split=folded)
        points = np.vstack([chains.local(), free])
        # Only the points near the new ones move (the springs keep the rest length they had).
        new = points[chains.n + kept :]
        movable = np.zeros(len(points), dtype=bool)
        if len(new):
            from scipy.spatial import cKDTree  # scipy is imported when blocks are made

            reach = 3.0 * float(length(new).max())
            movable = np.isfinite(cKDTree(new).query(points, distance_upper_bound=reach)[0])
        points, _ = _relax(
            points, chains.n, domain, length, chains.segments(), 20, movable=movable, scale=scale
        )
        free = points[chains.n :]
    else:
        # The repairs aim a little below the tolerance; the last check may hold it still (the
        # blocks, vertices and chains of that check are kept: a repair changes only points).
        if not (checked and not folded.size and float(ratio.max()) <= SIZE_TOLERANCE):
            k = int(np.argmax(ratio))
            raise DomainError(
                "the size-driven decomposition could not bring every cell within "
                f"{SIZE_TOLERANCE} times the size asked: the cell near "
                f"{fmt_point(centroids[k])} is {ratio[k]:.3g} times the "
                f"{checked_sizes(field, centroids[k : k + 1])[0]:.3g} asked there; the domain "
                "may have features smaller than the sizes there, or the sizes asked fall "
                "towards 0 there"
            )
    _check_convex(vertices, blocks, frame)
    triangle_of = pieces.piece
    return SizedBlocks(
        vertices=vertices,
        blocks=blocks,
        region=region[triangle_of],
        chain_nodes=tuple(chain_nodes),
        chain_params=tuple(chain_params),
        triangles=len(triangles),
        worst_ratio=float(ratio.max()),
        field=graded,
    )


def _repair(
    chains: _Chains,
    local: np.ndarray,
    triangles: np.ndarray,
    bad: np.ndarray,
    length,
    split: np.ndarray | None = None,
) -> np.ndarray:
    """More points where cells came out too large: the free points, with the new ones.

    Every bad triangle gets a point at its centroid; a chain segment of a bad triangle that is
    longer than the side wanted there is split too (the cells along a chain are sized by its
    segments), and so is every chain segment of the ``split`` triangles (where a curve folded
    a cell).
    """
    n = len(local)
    key = np.minimum(chains.a, chains.b) * n + np.maximum(chains.a, chains.b)
    sides = triangles[bad][:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
    side_key = np.min(sides, axis=1) * n + np.max(sides, axis=1)
    segment = np.flatnonzero(np.isin(key, side_key))
    p, q = local[chains.a[segment]], local[chains.b[segment]]
    long = np.hypot(*(q - p).T) > 1.2 * length(0.5 * (p + q))
    if split is not None and len(split):
        folded = triangles[split][:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
        folded_key = np.min(folded, axis=1) * n + np.max(folded, axis=1)
        long |= np.isin(key[segment], folded_key)
    extra = local[triangles[bad]].mean(axis=1)
    free = np.vstack([local[chains.n :], extra])
    if long.any():
        chains.split(segment[long])
    return free


def _check_convex(vertices: np.ndarray, blocks: np.ndarray, frame) -> None:
    """Blocks that rounding to the caller's coordinates made non-convex: too small for doubles."""
    sines = corner_sines(vertices[blocks])
    bad = np.flatnonzero(~np.all(sines > COLLINEAR_SIN_TOL, axis=1))
    if bad.size:
        size = float(np.ptp(vertices[blocks[bad[0]]], axis=0).max())
        raise DomainError(
            f"the sizes asked are too small for where the domain sits: blocks about {size:.3g} "
            f"across at coordinates near {float(np.max(np.abs(frame.origin))):.3g} fold when "
            "rounded to double precision; move the domain near the origin or ask larger sizes"
        )


def arc_pieces(outline: Outline, c: int, params: np.ndarray) -> list[Curve]:
    """The curve of chain ``c`` between consecutive ``params``, each as an arc through its middle.

    An arc chain's pieces are arcs of the same circle; a spline's are the arcs through three of
    its points (its ends and its middle), close to it at the sizes of a sized mesh.
    """
    curve = outline.curves[c]
    if curve is None:
        return []
    middle = curve.point(0.5 * (params[:-1] + params[1:]))
    return [Arc(through=(float(x), float(y))) for x, y in np.asarray(middle)]
