"""How blocks fit together checked: edge to edge, no overlaps, gaps, hanging nodes or loose blocks.

See :func:`check_topology`: topological first, geometric only where it must be, so that the
verdict does not depend on where the domain sits or how thin its blocks are.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import shapely

from blockmesh.domain.validate.problems import raise_problems
from blockmesh.domain.validate.tolerances import NEAR_TOL, same_point_tol
from blockmesh.errors import DomainError, TopologyError, fmt_point
from blockmesh.geometry.polygons import LocalFrame, interior_angles, local_frame
from blockmesh.geometry.topology import connected_pieces, graph_components

__all__ = ["check_topology"]


def check_topology(
    vertices: np.ndarray, blocks: np.ndarray, neighbour: np.ndarray, components: int = 1
) -> None:
    """Check that blocks meet edge to edge: no overlaps, gaps, hanging nodes, loose blocks.

    ``neighbour`` is :func:`blockmesh.geometry.topology.cell_neighbours` of the blocks (computed by
    the caller, which also rejects edges shared by three blocks). Raises TopologyError.

    The test is topological first and geometric only where it must be, so that it does not depend
    on where the domain sits or how thin its blocks are: counter-clockwise strictly convex blocks
    that pair up along their edges tile a region exactly when their boundary edges meet only at
    shared corners (else a hanging node or an overlap) and the corners around every inner vertex
    add up to one full turn. Separate boundary loops closer than :data:`NEAR_TOL` times the
    domain's size are reported as a gap. O(B log B), in the domain's local frame.

    ``components`` is how many separate pieces the blocks are meant to form (a composite domain
    of disjoint parts has several); pieces must not touch, not even at a corner.
    """
    frame = local_frame(vertices)
    local = frame.to_local(vertices)
    _check_same_direction(blocks, neighbour)
    slot = np.flatnonzero(np.asarray(neighbour).ravel() < 0)
    boundary = _Boundary(
        slot, blocks.ravel()[slot], np.roll(blocks, -1, axis=1).ravel()[slot], local
    )
    _check_contacts(vertices, blocks, boundary, same_point_tol(frame))
    _check_gaps(vertices, boundary, frame)
    _check_connected(neighbour, blocks, components)
    _check_full_turns(vertices, local, blocks, boundary.start, boundary.stop)


class _Boundary(NamedTuple):
    """The blocks' boundary edges, ``start[k]`` to ``stop[k]`` on block ``slot[k] // 5``.

    ``local`` is every vertex in the domain's local frame.
    """

    slot: np.ndarray
    start: np.ndarray
    stop: np.ndarray
    local: np.ndarray

    def edge(self, k: int) -> tuple[int, int, int]:
        """Boundary edge ``k``: its first vertex, its second and its block."""
        return int(self.start[k]), int(self.stop[k]), int(self.slot[k]) // 5

    def ends_to_edges(
        self, points: np.ndarray, segments: np.ndarray, i: int, j: int
    ) -> list[tuple[float, int, int]]:
        """``(distance, vertex, edge)`` of the ends of edge ``j`` to edge ``i``, then the reverse.

        ``points`` and ``segments`` are the vertices and the boundary edges as shapely geometries.
        """
        return [
            (float(shapely.distance(points[v], segments[edge])), int(v), edge)
            for edge, other in ((i, j), (j, i))
            for v in (self.start[other], self.stop[other])
        ]


def _check_same_direction(blocks: np.ndarray, neighbour: np.ndarray) -> None:
    # Two counter-clockwise blocks on either side of an edge run along it in opposite directions.
    b, e = np.nonzero(neighbour >= 0)
    ob, oe = np.divmod(neighbour[b, e], 5)
    same = (blocks[b, e] == blocks[ob, oe]) & (b < ob)
    raise_problems(
        TopologyError,
        [
            f"blocks {int(x)} and {int(y)} both run along edge ({blocks[x, i]}, "
            f"{blocks[x, (i + 1) % 5]}) in the same direction, so they lie on the same side of it "
            "and overlap; move one of them to the other side"
            for x, i, y in zip(b[same], e[same], ob[same], strict=True)
        ],
    )


#: Boundary edges queried for their neighbours at a time (bounds the work before the cap).
_CONTACT_CHUNK = 256


def _contact_pairs(
    local: np.ndarray, start: np.ndarray, stop: np.ndarray, distance: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pairs of boundary edges within ``distance`` that share no vertex; and the segments.

    Queried a chunk of edges at a time: more than about 64 pairs per edge means that
    features far smaller than the domain crowd together (a spike millions of times longer than
    the rest), which no check separates: a DomainError then, not hours of pairs.
    """
    segments = shapely.linestrings(np.stack([local[start], local[stop]], axis=1))
    tree = shapely.STRtree(segments)
    cap = 64 * segments.size + 10_000
    firsts, seconds, found = [], [], 0
    for low in range(0, segments.size, _CONTACT_CHUNK):
        first, second = tree.query(
            segments[low : low + _CONTACT_CHUNK], predicate="dwithin", distance=distance
        )
        first = first + low
        found += first.size
        if found > cap:
            where = fmt_point(local[start[first[0]]])
            raise DomainError(
                f"more than {cap:,} pairs of boundary edges come within {distance:g} of the "
                f"domain's size of each other (near {where} in units of that size): features "
                "this small for the domain's size cannot be checked apart; simplify the outline "
                "or mesh the small part on its own"
            )
        apart = (
            (first < second)
            & (start[first] != start[second])
            & (start[first] != stop[second])
            & (stop[first] != start[second])
            & (stop[first] != stop[second])
        )
        firsts.append(first[apart])
        seconds.append(second[apart])
    empty = np.empty(0, dtype=np.int64)
    return (
        np.concatenate(firsts) if firsts else empty,
        np.concatenate(seconds) if seconds else empty,
        segments,
    )


def _check_contacts(
    vertices: np.ndarray, blocks: np.ndarray, boundary: _Boundary, tol: float
) -> None:
    """Boundary edges that touch or cross away from shared corners: hanging nodes and overlaps."""
    local, slot = boundary.local, boundary.slot
    first, second, segments = _contact_pairs(local, boundary.start, boundary.stop, tol)
    if first.size == 0:
        return
    points = shapely.points(local)
    problems = []
    seen: set[tuple[int, int, int]] = set()
    seen_pairs: set[tuple[int, int]] = set()
    for i, j in zip(first.tolist(), second.tolist(), strict=True):
        touching = [
            (v, edge) for d, v, edge in boundary.ends_to_edges(points, segments, i, j) if d <= tol
        ]
        if touching:
            v, edge = touching[-1]
            a, b, owner = boundary.edge(edge)
            key = (v, min(a, b), max(a, b))
            if key in seen:
                continue
            seen.add(key)
            problems.append(
                f"vertex {v} {fmt_point(vertices[v])} lies on edge ({a}, {b}) of block {owner} "
                f"without being one of its corners (a hanging node); blocks must meet edge to "
                f"edge: split that edge at vertex {v} by giving block {owner} the corner {v}, or "
                "move the vertex"
            )
            continue
        x, y = sorted((int(slot[i]) // 5, int(slot[j]) // 5))
        if (x, y) in seen_pairs:
            continue
        seen_pairs.add((x, y))
        problems.append(_overlap_message(vertices, local, blocks, x, y))
    raise_problems(TopologyError, problems)


def _overlap_message(
    vertices: np.ndarray, local: np.ndarray, blocks: np.ndarray, x: int, y: int
) -> str:
    frame = local_frame(vertices)
    one, two = shapely.Polygon(local[blocks[x]]), shapely.Polygon(local[blocks[y]])
    shared = shapely.intersection(one, two)
    if shared.is_empty or shared.area == 0:
        shared = shapely.intersection(one.boundary, two.boundary)
    where = frame.to_global(shapely.get_coordinates(shapely.centroid(shared))[0])
    area = shapely.area(shapely.intersection(one, two)) * frame.scale**2
    return (
        f"blocks {x} and {y} overlap (shared area {area:.3g} around {fmt_point(where)}); "
        "blocks may touch only along whole edges"
    )


def _check_gaps(vertices: np.ndarray, boundary: _Boundary, frame: LocalFrame) -> None:
    """Separate boundary loops that come closer than NEAR_TOL: blocks that should share vertices."""
    local, start, stop = boundary.local, boundary.start, boundary.stop
    first, second, segments = _contact_pairs(local, start, stop, NEAR_TOL)
    if first.size == 0:
        return
    loop = _loop_labels(start, stop, local.shape[0])
    apart = loop[first] != loop[second]
    problems = []
    seen = set()
    points = shapely.points(local)
    for i, j in zip(first[apart].tolist(), second[apart].tolist(), strict=True):
        d, v, edge = min(boundary.ends_to_edges(points, segments, i, j), key=lambda end: end[0])
        a, b, owner = boundary.edge(edge)
        key = (v, min(a, b), max(a, b))
        if d > NEAR_TOL or key in seen:
            continue
        seen.add(key)
        problems.append(
            f"vertex {v} {fmt_point(vertices[v])} is only {d * frame.scale:.3g} from edge "
            f"({a}, {b}) of block {owner} (a gap or an overlap between blocks); blocks that meet "
            "must share their vertices"
        )
    raise_problems(TopologyError, problems)


def _loop_labels(start: np.ndarray, stop: np.ndarray, n_points: int) -> np.ndarray:
    """Which boundary loop (connected piece of the boundary graph) each boundary edge is on."""
    _, label = graph_components(n_points, start, stop)
    return label[start]


def _check_connected(neighbour: np.ndarray, blocks: np.ndarray, components: int = 1) -> None:
    count, label = connected_pieces(neighbour)
    if count == components and count > 1:
        _check_pieces_apart(blocks, label)
    if count == components:
        return
    if components > 1:
        raise TopologyError(
            f"the blocks form {count} separate pieces, but {components} are stated (components "
            f"= {components}); state the number of pieces the blocks form"
        )
    groups = [np.flatnonzero(label == k) for k in range(count)]
    groups.sort(key=len, reverse=True)
    listed = "; ".join(
        "blocks " + ", ".join(map(str, g[:10])) + (" ..." if g.size > 10 else "") for g in groups
    )
    loose = ", ".join(str(b) for g in groups[1:] for b in g[:5])
    raise TopologyError(
        f"the blocks form {count} separate pieces ({listed}); every block must share a whole "
        f"edge with another: connect block{'s' if ',' in loose else ''} {loose} to the rest "
        "(touching at a corner is not enough)"
    )


def _check_pieces_apart(blocks: np.ndarray, label: np.ndarray) -> None:
    """Separate pieces share no vertex (touching at a corner would pinch the domain)."""
    pieces = np.repeat(label, blocks.shape[1])
    vertex, first = np.unique(blocks.ravel(), return_index=True)
    owner = np.empty(int(blocks.max()) + 1, dtype=np.int64)
    owner[vertex] = pieces[first]
    shared = blocks.ravel()[owner[blocks.ravel()] != pieces]
    if shared.size:
        v = int(shared[0])
        touching = sorted({int(p) for p in pieces[blocks.ravel() == v]})
        raise TopologyError(
            f"pieces {touching[0]} and {touching[1]} of the blocks touch at vertex {v} only "
            "(touching at a corner is not enough): join them along an edge or move them apart"
        )


def _check_full_turns(
    vertices: np.ndarray, local: np.ndarray, blocks: np.ndarray, start: np.ndarray, stop: np.ndarray
) -> None:
    """The corners around each vertex add up to one turn (inside) or to the boundary's angle."""
    n = local.shape[0]
    total = np.bincount(blocks.ravel(), weights=interior_angles(local[blocks]).ravel(), minlength=n)
    passes = np.bincount(start, minlength=n)
    expected = np.full(n, 360.0)
    single = np.flatnonzero(passes == 1)
    incoming = np.empty(n, dtype=np.int64)
    incoming[stop] = start
    outgoing = np.empty(n, dtype=np.int64)
    outgoing[start] = stop
    ahead = local[outgoing[single]] - local[single]
    behind = local[incoming[single]] - local[single]
    cross = ahead[:, 0] * behind[:, 1] - ahead[:, 1] * behind[:, 0]
    dot = np.sum(ahead * behind, axis=1)
    expected[single] = np.degrees(np.arctan2(cross, dot)) % 360.0
    check = passes <= 1
    off = np.flatnonzero(check & (np.abs(total - expected) > 1e-6 * 360))
    raise_problems(
        TopologyError,
        [
            f"the blocks around vertex {v} {fmt_point(vertices[v])} overlap: their corners there "
            f"add up to {total[v]:.1f}° instead of {expected[v]:.1f}°; blocks may touch only "
            "along whole edges"
            for v in off.tolist()
        ],
    )
