"""Polygon rings checked and brought to the form the decomposition needs.

A polygon with holes (:func:`check_rings`): at least three corners, no repeated points, no
crossing or touching edges, holes inside the polygon and apart, the outer ring counter-clockwise
and the holes clockwise, straight corners dropped unless two patches meet there. Each
:class:`Ring` remembers where its corners came from in the input.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable
from typing import NamedTuple

import numpy as np
import shapely

from blockmesh.domain.validate.points import close_pairs
from blockmesh.domain.validate.problems import raise_problems
from blockmesh.domain.validate.tolerances import NEAR_TOL, same_point_tol
from blockmesh.errors import BlockMeshWarning, DomainError, fmt_point
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    LocalFrame,
    corner_sines,
    local_frame,
    signed_area,
)

__all__ = ["Ring", "check_rings", "ring_label"]


def ring_label(ring: int) -> str:
    """How messages name a ring: ``"the polygon"`` (ring 0) or ``"hole K"`` (ring K + 1)."""
    return "the polygon" if ring == 0 else f"hole {ring - 1}"


def _vertex_label(ring: int, vertex: int, point: Iterable[float]) -> str:
    where = "vertex" if ring == 0 else f"hole {ring - 1} vertex"
    return f"{where} {vertex} {fmt_point(point)}"


class Ring(NamedTuple):
    """A validated ring: its corners and where each came from in the input.

    Attributes
    ----------
    points : ndarray (m, 2)
        The corners, with the domain on the left of every edge (the outer ring counter-clockwise,
        holes clockwise), the input's first corner first.
    vertex : ndarray (m,)
        The input index of each corner.
    reversed : bool
        Whether the input ran the other way round.
    given : ndarray (size, 2)
        The input corners (after dropping a closing repeat), in the input's order.
    """

    points: np.ndarray
    vertex: np.ndarray
    reversed: bool
    given: np.ndarray

    @property
    def size(self) -> int:
        """Number of corners in the input (after dropping a closing repeat)."""
        return int(self.given.shape[0])

    def input_edges(self, i: int) -> list[int]:
        """The input edges that output edge ``i`` runs along, in order along it.

        Several when straight corners between them were dropped. Input edge j runs from input
        corner j to j + 1.
        """
        a, b = int(self.vertex[i]), int(self.vertex[(i + 1) % len(self.vertex)])
        if self.reversed:
            count = (a - b) % self.size
            return [(a - 1 - k) % self.size for k in range(count)]
        count = (b - a) % self.size
        return [(a + k) % self.size for k in range(count)]


def check_rings(
    rings: list[np.ndarray], edge_patch: list[list[str | None]] | None = None
) -> list[Ring]:
    """Validate a polygon with holes and bring it to the form the decomposition needs.

    Parameters
    ----------
    rings : list of ndarray (n_r, 2)
        The outer boundary first, then the holes, each a list of corners in order (already
        parsed by :func:`parse_points`).
    edge_patch : list of lists, optional
        For each ring, the patch name of each edge as given (edge i runs from corner i to corner
        i + 1), or None entries.

    Returns
    -------
    list of Ring
        Ring 0 counter-clockwise, the holes clockwise (the domain on the left of every edge), each
        input's first corner kept first; straight corners dropped unless they separate two
        patches.

    Repairs with a warning: a last vertex repeating the first (dropped), a clockwise outer
    boundary (reversed; holes may be given either way round), straight corners that do not
    separate patches (dropped). Raises DomainError, naming the vertex, edge or hole, for: fewer
    than 3 corners, repeated points, crossing or touching edges, zero area, holes outside the
    polygon, inside another hole, crossing or touching the boundary or each other.

    Examples
    --------
    >>> square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], dtype=float)
    >>> hole = np.array([[1, 1], [2, 1], [2, 2], [1, 2]], dtype=float)
    >>> outer, inner = check_rings([square, hole])
    >>> inner.points.tolist(), inner.vertex.tolist(), inner.reversed  # now clockwise
    ([[1.0, 1.0], [1.0, 2.0], [2.0, 2.0], [2.0, 1.0]], [0, 3, 2, 1], True)
    >>> inner.input_edges(0)  # (1, 1) -> (1, 2) runs backwards along input edge 3
    [3]
    """
    cleaned = []
    for r, ring in enumerate(rings):
        pts = _drop_closing_vertex(np.asarray(ring, dtype=np.float64).reshape(-1, 2), r)
        if len(pts) < 3:
            raise DomainError(f"{ring_label(r)} needs at least 3 vertices, got {len(pts)}")
        cleaned.append(pts)
    frame = local_frame(np.vstack(cleaned))
    tol = same_point_tol(frame)
    local = [frame.to_local(p) for p in cleaned]
    _check_repeated_points(local, cleaned, tol)
    _check_crossings(local, cleaned, frame, tol)
    for r, pts in enumerate(local):
        area = float(signed_area(pts))
        if abs(area) <= 1e-12 * float(np.ptp(pts, axis=0).max()) ** 2:
            raise DomainError(
                f"{ring_label(r)} has zero area ({area * frame.scale**2:.3g}): its vertices lie on "
                "one line; give the corners of a real region"
            )
    _check_nesting(local, cleaned, frame)
    out = []
    for r, pts in enumerate(cleaned):
        n = len(pts)
        vertex = np.arange(n)
        backwards = (float(signed_area(local[r])) < 0) == (r == 0)
        if backwards:
            if r == 0:
                warnings.warn(
                    "the polygon was given clockwise; its vertices were reversed to "
                    "counter-clockwise order (vertex 0 stays first)",
                    BlockMeshWarning,
                    stacklevel=5,
                )
            vertex = np.r_[0, np.arange(n - 1, 0, -1)]
        checked = Ring(pts[vertex], vertex, bool(backwards), pts)
        patch_names = None if edge_patch is None else edge_patch[r]
        out.append(_drop_straight_corners(checked, r, patch_names))
    return out


def _drop_closing_vertex(pts: np.ndarray, ring: int) -> np.ndarray:
    if len(pts) >= 4 and np.array_equal(pts[0], pts[-1]):
        warnings.warn(
            f"the last vertex {fmt_point(pts[-1])} of {ring_label(ring)} repeats the first; it was "
            "dropped (a ring is closed automatically)",
            BlockMeshWarning,
            stacklevel=6,
        )
        return pts[:-1]
    return pts


def _check_repeated_points(local: list[np.ndarray], given: list[np.ndarray], tol: float) -> None:
    ring = np.concatenate([np.full(len(p), r) for r, p in enumerate(local)])
    index = np.concatenate([np.arange(len(p)) for p in local])
    pairs = close_pairs(np.vstack(local), tol)
    problems = []
    for a, b in sorted(map(tuple, np.sort(pairs, axis=1).tolist())):
        ra, rb, ia, ib = int(ring[a]), int(ring[b]), int(index[a]), int(index[b])
        point = fmt_point(given[ra][ia])
        if ra == rb == 0:
            problems.append(
                f"vertices {ia} and {ib} are the same point {point}: each corner must be "
                "listed once"
            )
        elif ra == rb:
            problems.append(
                f"{ring_label(ra)} has vertices {ia} and {ib} at the same point {point}: each "
                "corner must be listed once"
            )
        else:
            one = _vertex_label(ra, ia, given[ra][ia])
            two = _vertex_label(rb, ib, given[rb][ib])
            problems.append(
                f"{one} and {two} are the same point: holes must lie strictly inside the "
                "polygon, apart from each other"
            )
    raise_problems(DomainError, problems)


def _ring_segments(local: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ring = np.concatenate([np.full(len(p), r) for r, p in enumerate(local)])
    index = np.concatenate([np.arange(len(p)) for p in local])
    start = np.vstack(local)
    stop = np.vstack([np.roll(p, -1, axis=0) for p in local])
    return shapely.linestrings(np.stack([start, stop], axis=1)), ring, index


def _check_crossings(
    local: list[np.ndarray], given: list[np.ndarray], frame: LocalFrame, tol: float
) -> None:
    """Edges that cross or touch (other than neighbours at their shared corner)."""
    segments, ring, index = _ring_segments(local)
    first, second = shapely.STRtree(segments).query(segments, predicate="dwithin", distance=tol)
    size = np.array([len(p) for p in local])[ring]
    same = ring[first] == ring[second]
    neighbours = same & (
        (index[second] == index[first])
        | (index[second] == (index[first] + 1) % size[first])
        | (index[first] == (index[second] + 1) % size[first])
    )
    keep = (first < second) & ~neighbours
    for i, j in zip(first[keep].tolist(), second[keep].tolist(), strict=True):
        ri, rj, ei, ej = int(ring[i]), int(ring[j]), int(index[i]), int(index[j])
        gap = shapely.shortest_line(segments[i], segments[j])
        where = shapely.get_coordinates(gap).mean(axis=0)
        frame_point = frame.to_global(where)
        verb = "cross" if shapely.crosses(segments[i], segments[j]) else "touch"

        def name(r: int, e: int) -> str:
            p = given[r]
            edge = f"{e} {fmt_point(p[e])}->{fmt_point(p[(e + 1) % len(p)])}"
            return f"edge {edge}" if r == 0 else f"hole {r - 1} edge {edge}"

        if ri == rj == 0:
            raise DomainError(
                f"the polygon's edges {ei} {fmt_point(given[0][ei])}->"
                f"{fmt_point(given[0][(ei + 1) % len(given[0])])} and {ej} "
                f"{fmt_point(given[0][ej])}->{fmt_point(given[0][(ej + 1) % len(given[0])])} "
                f"{verb} at {fmt_point(frame_point)}: list the vertices in order around the "
                "boundary (the boundary may not touch itself)"
            )
        if ri == rj:
            raise DomainError(
                f"hole {ri - 1}'s edges {ei} and {ej} {verb} at {fmt_point(frame_point)}: list "
                "the hole's vertices in order around it (a hole may not touch itself)"
            )
        raise DomainError(
            f"{name(ri, ei)} and {name(rj, ej)} {verb} at {fmt_point(frame_point)}: holes must "
            "lie strictly inside the polygon, apart from it and from each other"
        )


def _check_nesting(local: list[np.ndarray], given: list[np.ndarray], frame: LocalFrame) -> None:
    """Holes inside the polygon, not inside each other, and not nearly touching anything."""
    if len(local) == 1:
        return
    outer = shapely.Polygon(local[0])
    holes = [shapely.Polygon(h) for h in local[1:]]
    for k, hole in enumerate(holes):
        if not outer.contains(hole):
            xy = local[k + 1]
            outside = np.flatnonzero(~shapely.contains_xy(outer, xy[:, 0], xy[:, 1]))
            v = int(outside[0]) if outside.size else 0
            raise DomainError(
                f"hole {k} is not inside the polygon: its vertex {v} "
                f"{fmt_point(given[k + 1][v])} is outside; a hole must lie strictly inside"
            )
    tree = shapely.STRtree(holes)
    first, second = tree.query(holes, predicate="contains")
    for a, b in zip(first.tolist(), second.tolist(), strict=True):
        if a != b:
            raise DomainError(
                f"hole {b} lies inside hole {a}: holes must not overlap (leave the inner one out, "
                "or mesh it as a separate domain)"
            )
    # Near misses between different rings: the blocks between them would be slivers that the
    # block check takes for a gap.
    segments, ring, index = _ring_segments(local)
    first, second = shapely.STRtree(segments).query(
        segments, predicate="dwithin", distance=NEAR_TOL
    )
    keep = ring[first] < ring[second]
    for i, j in zip(first[keep].tolist(), second[keep].tolist(), strict=True):
        d = float(shapely.distance(segments[i], segments[j])) * frame.scale
        raise DomainError(
            f"{ring_label(int(ring[j]))} comes within {d:.3g} of {ring_label(int(ring[i]))} "
            f"(edges {int(index[j])} and {int(index[i])}): rings closer than {NEAR_TOL:g} times "
            "the domain's size are taken for touching; move them apart"
        )


def _drop_straight_corners(ring: Ring, r: int, edge_patch: list[str | None] | None) -> Ring:
    """Drop straight (180 degree) corners unless they separate two patches (then they stay)."""
    sines = corner_sines(ring.points)
    straight = np.flatnonzero(np.abs(sines) <= COLLINEAR_SIN_TOL)
    if edge_patch is not None and straight.size:
        before = [ring.input_edges(int(i) - 1)[-1] for i in straight]
        after = [ring.input_edges(int(i))[0] for i in straight]
        keep = [edge_patch[e] != edge_patch[f] for e, f in zip(before, after, strict=True)]
        straight = straight[~np.array(keep, dtype=bool)]
    if straight.size == 0:
        return ring
    names = ", ".join(_vertex_label(r, int(ring.vertex[i]), ring.points[i]) for i in straight[:6])
    more = f" and {straight.size - 6} more" if straight.size > 6 else ""
    warnings.warn(
        f"{names}{more} lie{'s' if straight.size == 1 else ''} on a straight line between "
        "neighbouring corners; dropped (a straight corner is kept only where two patches meet)",
        BlockMeshWarning,
        stacklevel=6,
    )
    keep_ids = np.setdiff1d(np.arange(ring.points.shape[0]), straight)
    if keep_ids.size < 3:
        raise DomainError(f"{ring_label(r)} has fewer than 3 real corners")
    return Ring(ring.points[keep_ids], ring.vertex[keep_ids], ring.reversed, ring.given)
