"""The straight edges of a composite domain's parts, and the points where two of them cross.

Where a straight edge of one part crosses a straight edge of another, the crossing point is
computed here once and fixed on both edges (as :func:`~.circles.crossings` fixes the points where
edges cross circles). Left to the fragmenting, each shapely operation would compute it again
with its own rounding: the point cut into one region's outline and the point noded into the
other's could differ by 1e-17, and the arrangement would hold a point that far from an edge it
is not on (a "gap", refused). Followed through the fixed point, both outlines meet there exactly.

Examples
--------
>>> import shapely
>>> from blockmesh.domain.parts import part_from_shapely
>>> box = part_from_shapely("box", shapely.box(0, 0, 2, 2), 0)
>>> bar = part_from_shapely("bar", shapely.box(1, 0.5, 3, 1.5), 1)
>>> splits = edge_crossings([box, bar], 1e-9)
>>> sorted({tuple(point.tolist()) for found in splits.values() for _, point in found})
[(2.0, 0.5), (2.0, 1.5)]
>>> len(splits)  # the box's right edge, the bar's bottom and top edges
3
"""

from __future__ import annotations

import numpy as np
import shapely

from blockmesh.domain.parts import Part
from blockmesh.domain.validate.tolerances import GAP_TOL

__all__ = [
    "EdgeKey",
    "Splits",
    "edge_crossings",
    "merge_splits",
    "on_edge_tol",
    "straight_edges",
]

#: An edge of a part's outline: (part, polygon, ring, edge).
EdgeKey = tuple[int, int, int, int]
#: Per edge, the points fixed inside it, each with its fraction along the edge.
Splits = dict[EdgeKey, list[tuple[float, np.ndarray]]]


def straight_edges(parts: list[Part]) -> tuple[np.ndarray, np.ndarray, list[EdgeKey]]:
    """Every straight edge of every outline: starts (E, 2), ends (E, 2), and their keys."""
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
    return np.array(starts, dtype=np.float64), np.array(ends, dtype=np.float64), keys


def edge_crossings(parts: list[Part], tol: float, snap: float = 0.0) -> Splits:
    """The points where straight edges of different parts cross or touch, fixed on the edges.

    A crossing counts when it lies farther than ``tol`` from both ends of both edges (one nearer
    an end is a corner near an edge: the arrangement's checks judge it), and is fixed on both
    edges. A corner of one part within ``snap`` of the inside of another part's straight edge
    (a point meant to lie on it, off by rounding) is fixed on that edge as it is. Parallel edges
    never cross here (where they overlap, their corners lie on each other). Candidate pairs come
    from an R-tree, so the work is about linear in the number of edges.
    """
    starts, ends, keys = straight_edges(parts)
    splits: Splits = {}
    if len(keys) < 2:
        return splits
    part_of = np.array([key[0] for key in keys], dtype=np.int64)
    lines = shapely.linestrings(np.stack([starts, ends], axis=1))
    tree = shapely.STRtree(lines)
    first, second = tree.query(lines, predicate="intersects")
    pair = (first < second) & (part_of[first] != part_of[second])
    a, b = first[pair], second[pair]
    d = ends[a] - starts[a]
    e = ends[b] - starts[b]
    f = starts[b] - starts[a]
    cross = d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0]
    proper = cross != 0.0
    a, b, d, e, f, cross = a[proper], b[proper], d[proper], e[proper], f[proper], cross[proper]
    s = (f[:, 0] * e[:, 1] - f[:, 1] * e[:, 0]) / cross  # along edge a
    t = (f[:, 0] * d[:, 1] - f[:, 1] * d[:, 0]) / cross  # along edge b
    inside = _inside(s, np.hypot(d[:, 0], d[:, 1]), tol) & _inside(t, np.hypot(*e.T), tol)
    points = starts[a] + s[:, None] * d
    for k in np.flatnonzero(inside).tolist():
        splits.setdefault(keys[a[k]], []).append((float(s[k]), points[k]))
        splits.setdefault(keys[b[k]], []).append((float(t[k]), points[k]))
    if snap > 0.0:
        corners, corner_part = _corners(parts)
        at, edge = tree.query(shapely.points(corners), predicate="dwithin", distance=snap)
        other = corner_part[at] != part_of[edge]
        at, edge = at[other], edge[other]
        d = ends[edge] - starts[edge]
        length = np.hypot(d[:, 0], d[:, 1])
        along = np.sum((corners[at] - starts[edge]) * d, axis=1) / length**2
        for k in np.flatnonzero(_inside(along, length, tol)).tolist():
            splits.setdefault(keys[edge[k]], []).append((float(along[k]), corners[at[k]]))
    return splits


def _inside(fraction: np.ndarray, length: np.ndarray, tol: float) -> np.ndarray:
    """Whether points at ``fraction`` along edges of ``length`` are over ``tol`` from both ends."""
    return (fraction * length > tol) & ((1.0 - fraction) * length > tol)


def _corners(parts: list[Part]) -> tuple[np.ndarray, np.ndarray]:
    """Every corner of every outline (C, 2), and the part of each (C,)."""
    corners, owner = [np.zeros((0, 2))], [np.zeros(0, dtype=np.int64)]
    for i, part in enumerate(parts):
        for polygon in part.polygons:
            for outline in polygon:
                corners.append(np.asarray(outline.corners, dtype=np.float64).reshape(-1, 2))
                owner.append(np.full(len(corners[-1]), i, dtype=np.int64))
    return np.vstack(corners), np.concatenate(owner)


def merge_splits(into: Splits, more: Splits) -> None:
    """Add the points of ``more`` to ``into``, each point of an edge once."""
    for key, found in more.items():
        have = into.setdefault(key, [])
        seen = {(float(x), float(y)) for _, (x, y) in have}
        for fraction, point in found:
            if (float(point[0]), float(point[1])) not in seen:
                seen.add((float(point[0]), float(point[1])))
                have.append((fraction, point))


def on_edge_tol(parts: list[Part], size: float) -> float:
    """Distance under which a corner lies on an edge (``snap`` of :func:`edge_crossings`).

    :data:`~blockmesh.domain.validate.tolerances.GAP_TOL` times ``size`` (the domain's size), or
    4 ulps of the largest coordinate where that is more: the distance at which a domain's vertex
    counts as lying on an edge.
    """
    corners, _ = _corners(parts)
    largest = float(np.abs(corners).max()) if corners.size else 0.0
    return max(GAP_TOL * size, 4.0 * float(np.spacing(largest)))
