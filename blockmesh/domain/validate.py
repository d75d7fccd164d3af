"""Checks and repairs of domain input, each failure a typed error with a located message.

The functions here take raw user input (lists from TOML or Python, numpy arrays) and return clean
arrays, or raise :class:`~blockmesh.errors.DomainError` (geometry),
:class:`~blockmesh.errors.DomainFormatError` (types and shapes) or
:class:`~blockmesh.errors.TopologyError` (how blocks fit together). Every message names the vertex,
edge or block with its coordinates and says how to fix it. Where a stage finds several problems,
all of them are reported at once (one per line). Harmless repairs (clockwise order, a closing
vertex that repeats the first, straight corners of a polygon) are made with a
:class:`~blockmesh.errors.BlockMeshWarning`.

Examples
--------
>>> parse_points([[0, 0], [1, "a"]], "vertex")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
blockmesh.errors.DomainFormatError: vertex 1 has a y coordinate that is not a number ('a'); ...
"""

from __future__ import annotations

import numbers
import re
import warnings
from collections.abc import Iterable, Mapping
from typing import NamedTuple

import numpy as np
import shapely

from blockmesh.errors import (
    BlockMeshWarning,
    DomainError,
    DomainFormatError,
    TopologyError,
    fmt_point,
)
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    MAX_COORDINATE,
    LocalFrame,
    corner_sines,
    interior_angles,
    local_frame,
    signed_area,
)
from blockmesh.geometry.topology import connected_pieces, graph_components

__all__ = [
    "DEFAULT_PATCH",
    "DEFAULT_REGION",
    "GAP_TOL",
    "MAX_COORDINATE",
    "MIN_EXTENT",
    "NEAR_TOL",
    "Ring",
    "check_block_shapes",
    "check_rings",
    "check_topology",
    "edge_pair",
    "fmt_point",
    "parse_blocks",
    "parse_points",
    "resolve_patches",
    "resolve_regions",
    "ring_label",
]

#: Patch of every boundary edge no patch names.
DEFAULT_PATCH = "boundary"
#: Region of every block no region names.
DEFAULT_REGION = "domain"
#: Two distinct points closer than this (relative to the domain's size, or 4 ulps of its
#: coordinates where that is more) are "the same point"; a vertex this close to an edge it is not
#: on is a hanging node. Small enough for slivers of aspect ratio up to about 1e10.
GAP_TOL = 1e-11
#: Separate boundary loops (or rings) closer than this, relative to the domain's size, are taken
#: for a gap between blocks that should meet (or rings that touch).
NEAR_TOL = 1e-6
#: Smallest span of a domain's coordinates accepted: its areas (squares of spans, and smaller
#: still at high levels) must not underflow to zero.
MIN_EXTENT = 1e-100
#: Most problems listed in one message.
_MAX_LISTED = 8
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")


def _raise(kind: type[Exception], problems: list[str]) -> None:
    if not problems:
        return
    if len(problems) == 1:
        raise kind(problems[0])
    shown = problems[:_MAX_LISTED]
    more = len(problems) - len(shown)
    tail = f"\n  ... and {more} more" if more else ""
    raise kind(f"{len(problems)} problems:\n  " + "\n  ".join(shown) + tail)


def _is_number(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


# --------------------------------------------------------------------------- points
def parse_points(raw: object, what: str = "vertex") -> np.ndarray:
    """Validate a list of ``[x, y]`` pairs; returns a new (K, 2) float64 array.

    Raises DomainFormatError for wrong shapes or non-numbers and DomainError for non-finite values.

    Examples
    --------
    >>> parse_points([[0, 0], [1, 2.5]]).tolist()
    [[0.0, 0.0], [1.0, 2.5]]
    """
    if isinstance(raw, np.ndarray):
        if raw.ndim != 2 or raw.shape[1] != 2:
            raise DomainFormatError(f"{what} coordinates must have shape (n, 2), got {raw.shape}")
        if not (np.issubdtype(raw.dtype, np.number) and not np.issubdtype(raw.dtype, np.bool_)):
            raise DomainFormatError(f"{what} coordinates must be numbers, got dtype {raw.dtype}")
        if np.issubdtype(raw.dtype, np.floating) or np.issubdtype(raw.dtype, np.integer):
            return _checked_values(np.array(raw, dtype=np.float64), what)
        items = raw.tolist()
    elif isinstance(raw, str | bytes) or not isinstance(raw, Iterable):
        raise DomainFormatError(
            f"expected a list of [x, y] pairs for the {what} coordinates, got {type(raw).__name__}"
        )
    else:
        items = list(raw)
    problems = []
    for i, item in enumerate(items):
        if isinstance(item, str | bytes) or not isinstance(item, Iterable):
            problems.append(f"{what} {i} is {item!r}: each {what} must be a pair [x, y]")
            continue
        pair = list(item)
        if len(pair) != 2:
            problems.append(f"{what} {i} is {pair!r}: each {what} must be a pair [x, y]")
            continue
        for axis, value in zip("xy", pair, strict=True):
            if not _is_number(value):
                problems.append(
                    f"{what} {i} has a{'n' if axis == 'x' else ''} {axis} coordinate that is not "
                    f"a number ({value!r}); coordinates must be numbers"
                )
    _raise(DomainFormatError, problems)
    try:
        points = np.array(items, dtype=np.float64).reshape(-1, 2)
    except OverflowError:
        big = next(i for i, item in enumerate(items) if not _fits(item))
        raise DomainError(
            f"{what} {big} has a coordinate too large for a double ({_short(items[big])}); "
            f"coordinates must be at most {MAX_COORDINATE:g} in magnitude"
        ) from None
    return _checked_values(points, what)


def _checked_values(points: np.ndarray, what: str) -> np.ndarray:
    bad = np.flatnonzero(~np.all(np.isfinite(points), axis=1))
    _raise(
        DomainError,
        [
            f"{what} {i} ({float(points[i, 0])!r}, {float(points[i, 1])!r}) is not finite: "
            "coordinates must be finite numbers"
            for i in bad
        ],
    )
    huge = np.flatnonzero(np.any(np.abs(points) > MAX_COORDINATE, axis=1))
    _raise(
        DomainError,
        [
            f"{what} {i} {fmt_point(points[i])} is too far out: coordinates must be at most "
            f"{MAX_COORDINATE:g} in magnitude (move the domain nearer the origin, or change units)"
            for i in huge
        ],
    )
    if points.shape[0] >= 3:
        span = float(np.max(np.ptp(points, axis=0)))
        if 0 < span < MIN_EXTENT:
            raise DomainError(
                f"the {what} coordinates span only {span:.3g}: below {MIN_EXTENT:g} areas and "
                "angles underflow in double precision (to 0); scale the domain up (change units)"
            )
    return points


def _fits(item: Iterable) -> bool:
    try:
        np.array(list(item), dtype=np.float64)
    except OverflowError:
        return False
    return True


def _short(item: object) -> str:
    text = repr(item)
    return text if len(text) <= 60 else text[:57] + "..."


#: Up to this many points, close pairs are found by comparing all pairs (chunked numpy), so that
#: loading a catalogue domain does not import ``scipy.spatial`` (0.3-0.5 s in a fresh process);
#: above it, by a sweep along x (the composite catalogue domains have a few thousand vertices),
#: or with a k-d tree when the sweep would compare more than :data:`_SWEEP_PAIRS` pairs per point
#: (many points within ``r`` of one another in x).
_BRUTE_FORCE_POINTS = 2048
_SWEEP_PAIRS = 32


def close_pairs(points: np.ndarray, r: float) -> np.ndarray:
    """Pairs ``(i, j)``, ``i < j``, of points at most ``r`` apart, as an ``(n, 2)`` array.

    The same pairs as :meth:`scipy.spatial.cKDTree.query_pairs` (in another order).

    Examples
    --------
    >>> close_pairs(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1e-13]]), 1e-12).tolist()
    [[0, 2]]
    """
    points = np.asarray(points, dtype=np.float64)
    n = points.shape[0]
    if n > _BRUTE_FORCE_POINTS:
        swept = _swept_pairs(points, r)
        if swept is not None:
            return swept
        from scipy.spatial import cKDTree

        return cKDTree(points).query_pairs(r=r, output_type="ndarray")
    found = [np.empty((0, 2), dtype=np.intp)]
    for start in range(0, n, 256):
        block = points[start : start + 256]
        gap = block[:, None, :] - points[None, :, :]
        i, j = np.nonzero(np.hypot(gap[..., 0], gap[..., 1]) <= r)
        i += start
        keep = i < j
        found.append(np.stack([i[keep], j[keep]], axis=1))
    return np.concatenate(found)


def _swept_pairs(points: np.ndarray, r: float) -> np.ndarray | None:
    """The pairs of :func:`close_pairs` by a sweep along x; None when it would compare too many.

    Every point is compared with the points after it in x order that are at most ``r`` further
    in x: O(n log n) plus the pairs compared.
    """
    n = points.shape[0]
    order = np.argsort(points[:, 0], kind="stable")
    xs = points[order, 0]
    counts = np.searchsorted(xs, xs + r, side="right") - np.arange(n) - 1
    total = int(counts.sum())
    if total > _SWEEP_PAIRS * n:
        return None
    first = np.repeat(np.arange(n), counts)
    step = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    i, j = order[first], order[first + 1 + step]
    gap = points[i] - points[j]
    keep = np.hypot(gap[:, 0], gap[:, 1]) <= r
    pairs = np.stack([i[keep], j[keep]], axis=1).astype(np.intp)
    return np.sort(pairs, axis=1)


def _coincident_pairs(points: np.ndarray) -> list[tuple[int, int]]:
    """Pairs ``(i, j)``, ``i < j``, of points closer than the same-point tolerance, sorted."""
    frame = local_frame(points)
    pairs = close_pairs(frame.to_local(points), _same_point_tol(frame))
    return sorted((int(a), int(b)) for a, b in np.sort(pairs, axis=1))


# --------------------------------------------------------------------------- polygons
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
    tol = _same_point_tol(frame)
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
                    stacklevel=4,
                )
            vertex = np.r_[0, np.arange(n - 1, 0, -1)]
        checked = Ring(pts[vertex], vertex, bool(backwards), pts)
        patch_names = None if edge_patch is None else edge_patch[r]
        out.append(_drop_straight_corners(checked, r, patch_names))
    return out


def _same_point_tol(frame: LocalFrame) -> float:
    """Distance (local units) under which two points count as one: GAP_TOL or a few ulps."""
    return max(GAP_TOL, 4.0 * frame.ulp() / frame.scale)


def _drop_closing_vertex(pts: np.ndarray, ring: int) -> np.ndarray:
    if len(pts) >= 4 and np.array_equal(pts[0], pts[-1]):
        warnings.warn(
            f"the last vertex {fmt_point(pts[-1])} of {ring_label(ring)} repeats the first; it was "
            "dropped (a ring is closed automatically)",
            BlockMeshWarning,
            stacklevel=5,
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
    _raise(DomainError, problems)


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
        stacklevel=5,
    )
    keep_ids = np.setdiff1d(np.arange(ring.points.shape[0]), straight)
    if keep_ids.size < 3:
        raise DomainError(f"{ring_label(r)} has fewer than 3 real corners")
    return Ring(ring.points[keep_ids], ring.vertex[keep_ids], ring.reversed, ring.given)


# --------------------------------------------------------------------------- blocks
def parse_blocks(raw: object, n_vertices: int) -> np.ndarray:
    """Validate a list of 5-tuples of vertex ids; returns a new (B, 5) int64 array.

    Examples
    --------
    >>> parse_blocks([[0, 1, 2, 3, 4]], 5).tolist()
    [[0, 1, 2, 3, 4]]
    >>> parse_blocks([[0, 1, 2, 3]], 5)
    Traceback (most recent call last):
    ...
    blockmesh.errors.DomainFormatError: block 0 is [0, 1, 2, 3]: a block is a pentagon, 5 vertex ids
    """
    if (
        isinstance(raw, np.ndarray)
        and np.issubdtype(raw.dtype, np.integer)
        and raw.ndim == 2
        and raw.shape[1] == 5
        and raw.shape[0] > 0
    ):
        ids = raw.astype(np.int64)
        ordered = np.sort(ids, axis=1)
        if (
            ids.min() >= 0
            and ids.max() < n_vertices
            and not np.any(ordered[:, 1:] == ordered[:, :-1])
        ):
            return ids
        items = raw.tolist()
    elif isinstance(raw, np.ndarray):
        items = raw.tolist()
    elif isinstance(raw, str | bytes) or not isinstance(raw, Iterable):
        raise DomainFormatError(
            f"expected a list of blocks (5 vertex ids each), got {type(raw).__name__}"
        )
    else:
        items = [list(b) if isinstance(b, Iterable) and not isinstance(b, str) else b for b in raw]
    if not items:
        raise DomainFormatError("a domain needs at least one block")
    problems = []
    for i, block in enumerate(items):
        if not isinstance(block, list) or len(block) != 5:
            problems.append(f"block {i} is {block!r}: a block is a pentagon, 5 vertex ids")
            continue
        for v in block:
            if not isinstance(v, numbers.Integral) or isinstance(v, bool):
                problems.append(f"block {i} has vertex id {_short(v)}, which is not a whole number")
            elif not 0 <= int(v) < n_vertices:
                problems.append(
                    f"block {i} refers to vertex {_short(v)}, but the vertices are numbered "
                    f"0..{n_vertices - 1}"
                )
        whole = all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in block)
        if whole and len(set(block)) != len(block):
            twice = sorted({v for v in block if block.count(v) > 1})
            problems.append(
                f"block {i} ({', '.join(map(str, block))}) uses vertex "
                f"{', '.join(map(str, twice))} twice; a block has five different corners"
            )
    _raise(DomainFormatError, problems)
    return np.array(items, dtype=np.int64).reshape(-1, 5)


def block_label(blocks: np.ndarray, b: int) -> str:
    """How messages name a block: ``block 3 (vertices 4, 7, 9, 2, 5)``."""
    return f"block {b} (vertices {', '.join(map(str, blocks[b]))})"


def check_block_shapes(vertices: np.ndarray, blocks: np.ndarray, *, repair: bool) -> np.ndarray:
    """Check every block is a strictly convex pentagon; reverse clockwise ones when ``repair``.

    Returns the (possibly repaired) blocks as a new array. Also rejects vertices at the same
    coordinates and vertices no block uses. Works in the domain's local frame, so the verdict does
    not depend on where the domain sits. O(B) plus O(K log K) for the repeated points.

    Examples
    --------
    >>> v = np.array([[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]], dtype=float)
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     check_block_shapes(v, np.array([[0, 4, 3, 2, 1]]), repair=True).tolist()
    [[0, 1, 2, 3, 4]]
    >>> str(caught[0].message)[:25]
    '1 block was clockwise and'
    """
    blocks = np.array(blocks, dtype=np.int64)
    same = _coincident_pairs(vertices)
    _raise(
        DomainError,
        [
            f"vertices {a} and {b} are the same point {fmt_point(vertices[a])}: list each point "
            f"once and use vertex {a} in every block that has this corner"
            for a, b in same
        ],
    )
    used = np.zeros(vertices.shape[0], dtype=bool)
    used[blocks.ravel()] = True
    unused = np.flatnonzero(~used)
    _raise(
        DomainError,
        [
            f"vertex {v} {fmt_point(vertices[v])} is not used by any block; remove it or make it "
            "a corner of a block"
            for v in unused
        ],
    )
    local = local_frame(vertices).to_local(vertices)
    xy = local[blocks]
    areas = signed_area(xy)
    extent = np.ptp(xy, axis=1).max(axis=1)
    flat = np.flatnonzero(np.abs(areas) <= 1e-12 * extent**2)
    _raise(
        DomainError,
        [f"{block_label(blocks, int(b))} has zero area: its corners lie on one line" for b in flat],
    )
    clockwise = np.flatnonzero(areas < 0)
    if clockwise.size:
        if not repair:
            _raise(
                DomainError,
                [
                    f"{block_label(blocks, int(b))} runs clockwise; list its corners "
                    "counter-clockwise"
                    for b in clockwise
                ],
            )
        reversed_order = [0, 4, 3, 2, 1]
        blocks[clockwise] = blocks[clockwise][:, reversed_order]
        xy = local[blocks]
        shown = "; ".join(
            f"block {b} is now {', '.join(map(str, blocks[b]))}" for b in clockwise[:4]
        )
        warnings.warn(
            f"{clockwise.size} block{'s were' if clockwise.size > 1 else ' was'} clockwise and "
            f"reversed to counter-clockwise order (first vertex kept): {shown}",
            BlockMeshWarning,
            stacklevel=3,
        )
    sines = corner_sines(xy)
    angles = interior_angles(xy)
    straight = (np.abs(sines) <= COLLINEAR_SIN_TOL) & (angles > 90)
    wrong = sines < -COLLINEAR_SIN_TOL
    turning = np.sum(180.0 - angles, axis=1)
    crossing = ~np.isclose(turning, 360.0, atol=1e-6)
    problems = []
    for b in np.flatnonzero(np.any(straight | wrong, axis=1) | crossing).tolist():
        label = block_label(blocks, int(b))
        for k in range(5):
            v = blocks[b, k]
            if straight[b, k]:
                problems.append(
                    f"{label} is not strictly convex: the corner at vertex {v} "
                    f"{fmt_point(vertices[v])} is straight (180°); move vertex {v} off the line "
                    "through its neighbours, or use a block with that corner removed"
                )
                break
            if wrong[b, k]:
                problems.append(
                    f"{label} is not convex: the corner at vertex {v} {fmt_point(vertices[v])} "
                    f"turns the wrong way ({angles[b, k]:.1f}°); split the block or move the vertex"
                )
                break
        else:
            problems.append(
                f"{label} crosses itself (its corners go around {turning[b] / 360:.0f} times); "
                "list its corners in order around it"
            )
    _raise(DomainError, problems)
    return blocks


# --------------------------------------------------------------------------- topology
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
    start = blocks.ravel()[slot]
    stop = np.roll(blocks, -1, axis=1).ravel()[slot]
    _check_contacts(vertices, local, blocks, slot, start, stop, _same_point_tol(frame))
    _check_gaps(vertices, local, slot, start, stop, frame)
    _check_connected(neighbour, blocks, components)
    _check_full_turns(vertices, local, blocks, start, stop)


def _check_same_direction(blocks: np.ndarray, neighbour: np.ndarray) -> None:
    # Two counter-clockwise blocks on either side of an edge run along it in opposite directions.
    b, e = np.nonzero(neighbour >= 0)
    ob, oe = np.divmod(neighbour[b, e], 5)
    same = (blocks[b, e] == blocks[ob, oe]) & (b < ob)
    _raise(
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
    vertices: np.ndarray,
    local: np.ndarray,
    blocks: np.ndarray,
    slot: np.ndarray,
    start: np.ndarray,
    stop: np.ndarray,
    tol: float,
) -> None:
    """Boundary edges that touch or cross away from shared corners: hanging nodes and overlaps."""
    first, second, segments = _contact_pairs(local, start, stop, tol)
    if first.size == 0:
        return
    points = shapely.points(local)
    problems = []
    seen: set[tuple[int, int, int]] = set()
    seen_pairs: set[tuple[int, int]] = set()
    for i, j in zip(first.tolist(), second.tolist(), strict=True):
        hanging = None
        for edge, other in ((i, j), (j, i)):
            for v in (start[other], stop[other]):
                if shapely.distance(points[v], segments[edge]) <= tol:
                    hanging = (int(v), edge)
        if hanging is not None:
            v, edge = hanging
            a, b, owner = int(start[edge]), int(stop[edge]), int(slot[edge]) // 5
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
    _raise(TopologyError, problems)


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


def _check_gaps(
    vertices: np.ndarray,
    local: np.ndarray,
    slot: np.ndarray,
    start: np.ndarray,
    stop: np.ndarray,
    frame: LocalFrame,
) -> None:
    """Separate boundary loops that come closer than NEAR_TOL: blocks that should share vertices."""
    first, second, segments = _contact_pairs(local, start, stop, NEAR_TOL)
    if first.size == 0:
        return
    loop = _loop_labels(start, stop, local.shape[0])
    apart = loop[first] != loop[second]
    problems = []
    seen = set()
    points = shapely.points(local)
    for i, j in zip(first[apart].tolist(), second[apart].tolist(), strict=True):
        best = None
        for edge, other in ((i, j), (j, i)):
            for v in (start[other], stop[other]):
                d = float(shapely.distance(points[v], segments[edge]))
                if best is None or d < best[0]:
                    best = (d, int(v), edge)
        assert best is not None
        d, v, edge = best
        a, b, owner = int(start[edge]), int(stop[edge]), int(slot[edge]) // 5
        key = (v, min(a, b), max(a, b))
        if d > NEAR_TOL or key in seen:
            continue
        seen.add(key)
        problems.append(
            f"vertex {v} {fmt_point(vertices[v])} is only {d * frame.scale:.3g} from edge "
            f"({a}, {b}) of block {owner} (a gap or an overlap between blocks); blocks that meet "
            "must share their vertices"
        )
    _raise(TopologyError, problems)


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
    _raise(
        TopologyError,
        [
            f"the blocks around vertex {v} {fmt_point(vertices[v])} overlap: their corners there "
            f"add up to {total[v]:.1f}° instead of {expected[v]:.1f}°; blocks may touch only "
            "along whole edges"
            for v in off.tolist()
        ],
    )


# --------------------------------------------------------------------------- patches, regions
def _check_name(name: object, what: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise DomainFormatError(
            f"{what} name {name!r} is not valid: use letters, digits, '_', '-' or '.', starting "
            "with a letter or '_'"
        )
    return name


def _mapping(raw: object, what: str, of: str) -> dict[str, object]:
    """``raw`` (a mapping, or None for none) as a dict; a located error for anything else."""
    if raw is None:
        return {}
    if not isinstance(raw, Mapping):
        raise DomainFormatError(f"{what} must map {of}, got {type(raw).__name__} {raw!r:.60}")
    return dict(raw)


def resolve_patches(
    boundary: np.ndarray, raw: Mapping[str, object] | None, blocks: np.ndarray
) -> tuple[tuple[str, ...], np.ndarray]:
    """Assign every boundary edge to one patch.

    Parameters
    ----------
    boundary : ndarray (Eb, 2)
        The boundary edges, oriented with the domain on their left.
    raw : mapping of name to a list of [a, b] vertex pairs, or None
    blocks : ndarray (B, 5)
        The blocks (to name the owners of an edge that is not on the boundary).

    Returns
    -------
    names : tuple of str
        Patch names in the order given, then ``"boundary"`` for unnamed edges (if any).
    patch : ndarray (Eb,)
        Index into ``names`` for each boundary edge.
    """
    raw = _mapping(raw, "patches", "patch names to lists of edges [a, b]")
    index = {(int(a), int(b)): k for k, (a, b) in enumerate(boundary)}
    index.update({(b, a): k for (a, b), k in list(index.items())})
    patch = np.full(boundary.shape[0], -1, dtype=np.int64)
    names: list[str] = []
    problems = []
    for name, edges in raw.items():
        _check_name(name, "patch")
        if isinstance(edges, str | bytes) or not isinstance(edges, Iterable):
            raise DomainFormatError(
                f"patch {name!r} must be a list of edges [a, b] (vertex pairs), got {edges!r}"
            )
        names.append(name)
        k_name = len(names) - 1
        for edge in edges:
            key = edge_pair(edge, f"patch {name!r}")
            k = index.get(key)
            if k is None:
                owners = _edge_owners(blocks, *key)
                if owners:
                    problems.append(
                        f"patch {name!r} names edge {key}, which is not on the boundary: it is "
                        f"shared by blocks {owners[0]} and {owners[1]}"
                    )
                else:
                    problems.append(
                        f"patch {name!r} names edge {key}, which is not an edge of any block"
                    )
                continue
            if patch[k] == k_name:
                problems.append(f"patch {name!r} lists edge {key} twice")
            elif patch[k] >= 0:
                problems.append(
                    f"edge {key} is in patches {names[patch[k]]!r} and {name!r}; a boundary edge "
                    "belongs to one patch"
                )
            patch[k] = k_name
    _raise(DomainError, problems)
    if np.any(patch < 0):
        if DEFAULT_PATCH in names:
            patch[patch < 0] = names.index(DEFAULT_PATCH)
        else:
            names.append(DEFAULT_PATCH)
            patch[patch < 0] = len(names) - 1
    used = np.unique(patch)
    empty = [n for k, n in enumerate(names) if k not in used]
    _raise(DomainError, [f"patch {n!r} has no edges; give it edges or remove it" for n in empty])
    return tuple(names), patch


def edge_pair(edge: object, owner: str) -> tuple[int, int]:
    """``edge`` as a pair of vertex ids ``(a, b)``; DomainFormatError naming ``owner`` otherwise.

    Examples
    --------
    >>> edge_pair([3, 4], "patch 'inlet'")
    (3, 4)
    """
    pair = list(edge) if isinstance(edge, Iterable) and not isinstance(edge, str) else None
    if (
        pair is None
        or len(pair) != 2
        or not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in pair)
    ):
        raise DomainFormatError(f"{owner} has {edge!r}; each edge is a pair of vertex ids [a, b]")
    return int(pair[0]), int(pair[1])


def _edge_owners(blocks: np.ndarray, a: int, b: int) -> list[int]:
    """The blocks having the edge ``(a, b)`` either way round. O(B)."""
    ahead = np.roll(blocks, -1, axis=1)
    hit = ((blocks == a) & (ahead == b)) | ((blocks == b) & (ahead == a))
    return np.flatnonzero(np.any(hit, axis=1)).tolist()


def resolve_regions(
    n_blocks: int, raw: Mapping[str, object] | None
) -> tuple[tuple[str, ...], np.ndarray]:
    """Assign every block to one region; unnamed blocks form the region ``"domain"``.

    Examples
    --------
    >>> resolve_regions(3, {"left": [0]})
    (('left', 'domain'), array([0, 1, 1]))
    """
    region = np.full(n_blocks, -1, dtype=np.int64)
    names: list[str] = []
    problems = []
    for name, ids in _mapping(raw, "regions", "region names to lists of block ids").items():
        _check_name(name, "region")
        if isinstance(ids, str | bytes) or not isinstance(ids, Iterable):
            raise DomainFormatError(f"region {name!r} must be a list of block ids, got {ids!r}")
        names.append(name)
        for b in ids:
            if not isinstance(b, numbers.Integral) or isinstance(b, bool):
                raise DomainFormatError(f"region {name!r} has block id {b!r}, not a whole number")
            if not 0 <= int(b) < n_blocks:
                problems.append(
                    f"region {name!r} names block {b}, but the blocks are numbered "
                    f"0..{n_blocks - 1}"
                )
            elif region[b] >= 0 and region[b] != len(names) - 1:
                problems.append(
                    f"block {b} is in regions {names[region[b]]!r} and {name!r}; a block belongs "
                    "to one region"
                )
            else:
                region[b] = len(names) - 1
    _raise(DomainError, problems)
    if np.any(region < 0):
        if DEFAULT_REGION in names:
            region[region < 0] = names.index(DEFAULT_REGION)
        else:
            names.append(DEFAULT_REGION)
            region[region < 0] = len(names) - 1
    return tuple(names), region
