"""The triangles under the sized blocks: points filling an outline, relaxed, triangulated.

Steps 3-5 of the size-driven decomposition (:mod:`blockmesh.decompose.sized`): the sampled outline
(:class:`~blockmesh.decompose.outline._Chains`) is filled with points (centroids of triangles
larger than the field asks, round after round), thinned to the count the field asks, given points
in the gaps that slivers still span, and relaxed as in Persson and Strang's DistMesh (every
triangle edge a spring that pushes when shorter than the length wanted); the triangulation is then
made to follow every chain segment (segments missing from the Delaunay triangulation are split),
and its triangles are labelled by region across the segments.

Examples
--------
>>> _edges(np.array([[0, 1, 2], [1, 3, 2]])).tolist()  # the triangles' edges, each once
[[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]
"""

from __future__ import annotations

import math

import numpy as np

from blockmesh.decompose.outline import MAX_BLOCKS, _Chains
from blockmesh.errors import DomainError, ResourceError, fmt_point

__all__: list[str] = []

#: Relaxation: iterations, step, and the springs' overshoot (DistMesh's Fscale).
_ITERATIONS = 60
_STEP = 0.2
_FSCALE = 1.2
#: After the thinning, a triangle with a side longer than this times the side wanted at its
#: centroid gets a point there: a triangle spanning a gap between two stretches of the outline
#: sampled closer than the field asks (a fibre's arcs, sampled every 40 degrees, beside a wall
#: or another fibre), or running from the outline's crowded points into an interior the count
#: left empty. Without it the relaxation keeps such slivers, and their templates are seams of
#: thin cells (fibre-cell at sqrt(area) / 25: worst angle 13.5 degrees, neighbour ratio 4.75).
_SPAN = 1.75
#: The triangle side allowed beside the outline, in units of the spacing of its points there:
#: a triangle on a segment of length s may rise to this times s (its apex angle at least 2
#: asin(1 / 3), 39 degrees), so the dense points of a curve do not shrink the cells beside it.
_SPACING_RISE = 1.5


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
