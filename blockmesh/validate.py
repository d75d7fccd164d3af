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

import numpy as np
import shapely

from .errors import BlockMeshWarning, DomainError, DomainFormatError, TopologyError
from .geometry import COLLINEAR_SIN_TOL, corner_sines, interior_angles, signed_area
from .topology import connected_pieces

__all__ = [
    "DEFAULT_PATCH",
    "DEFAULT_REGION",
    "GAP_TOL",
    "check_block_shapes",
    "check_polygon",
    "check_topology",
    "fmt_point",
    "parse_blocks",
    "parse_points",
    "resolve_patches",
    "resolve_regions",
]

#: Patch of every boundary edge no patch names.
DEFAULT_PATCH = "boundary"
#: Region of every block no region names.
DEFAULT_REGION = "domain"
#: Two distinct points closer than this (relative to the domain's size) are "the same point";
#: a vertex this close to an edge it is not on leaves a gap or a hanging node.
GAP_TOL = 1e-9
#: Most problems listed in one message.
_MAX_LISTED = 8
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")


def fmt_point(p: Iterable[float]) -> str:
    """A point as ``(x, y)`` with the shortest exact repr of each coordinate.

    Examples
    --------
    >>> fmt_point([1.0, 0.25])
    '(1, 0.25)'
    """
    return "(" + ", ".join(f"{float(c):.12g}" for c in p) + ")"


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
    points = np.array(items, dtype=np.float64).reshape(-1, 2)
    bad = np.flatnonzero(~np.all(np.isfinite(points), axis=1))
    _raise(
        DomainError,
        [
            f"{what} {i} ({float(points[i, 0])!r}, {float(points[i, 1])!r}) is not finite: "
            "coordinates must be finite numbers"
            for i in bad
        ],
    )
    return points


def _scale(points: np.ndarray) -> float:
    """The size of a point set: the diagonal of its bounding box."""
    extent = np.ptp(points, axis=0) if points.size else np.zeros(2)
    return float(max(np.hypot(*extent), 1e-300))


def _coincident_pairs(points: np.ndarray) -> list[tuple[int, int]]:
    from scipy.spatial import cKDTree

    tol = GAP_TOL * _scale(points)
    pairs = cKDTree(points).query_pairs(r=tol, output_type="ndarray")
    return sorted((int(a), int(b)) for a, b in np.sort(pairs, axis=1))


# --------------------------------------------------------------------------- polygons
def check_polygon(
    points: np.ndarray, edge_patch: list[str | None] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Validate a convex polygon and bring it to counter-clockwise, strictly convex form.

    Parameters
    ----------
    points : ndarray (n, 2)
        Corners in order (already parsed by :func:`parse_points`).
    edge_patch : list, optional
        Patch name of each edge (edge i runs from corner i to corner i+1), or None entries.

    Returns
    -------
    polygon : ndarray (m, 2)
        Counter-clockwise corners, corner 0 first, straight corners dropped.
    source_edge : ndarray (m,)
        For each output edge, the input edge it starts with (to carry patches over).

    Repairs with a warning: a last vertex repeating the first (dropped), clockwise order
    (reversed, vertex 0 stays first), straight corners (dropped; an error if they separate two
    different patches). Raises DomainError for everything else.

    Examples
    --------
    >>> poly, source = check_polygon(np.array([[0, 0], [1, 0], [1, 1.0]]))
    >>> poly.tolist(), source.tolist()
    ([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [0, 1, 2])
    """
    pts = np.asarray(points, dtype=np.float64)
    n = pts.shape[0]
    source = np.arange(n)
    if n >= 4 and np.array_equal(pts[0], pts[-1]):
        warnings.warn(
            f"the last vertex {fmt_point(pts[-1])} repeats the first; it was dropped "
            "(a polygon is closed automatically)",
            BlockMeshWarning,
            stacklevel=3,
        )
        pts, source, n = pts[:-1], source[:-1], n - 1
    if n < 3:
        raise DomainError(f"a polygon needs at least 3 vertices, got {n}")
    same = _coincident_pairs(pts)
    _raise(
        DomainError,
        [
            f"vertices {a} and {b} are the same point {fmt_point(pts[a])}: each corner must be "
            "listed once"
            for a, b in same
        ],
    )
    crossing = _crossing_edges(pts)
    if crossing:
        raise DomainError(crossing)
    scale = _scale(pts)
    area = float(signed_area(pts))
    if abs(area) <= 1e-12 * scale**2:
        raise DomainError(
            f"the polygon has zero area ({area:.3g}): its vertices lie on one line; "
            "give the corners of a real region"
        )
    if not shapely.is_valid(shapely.Polygon(pts)):
        reason = shapely.is_valid_reason(shapely.Polygon(pts))
        raise DomainError(
            f"the polygon is not simple ({reason}): list the vertices in order around the boundary"
        )
    if area < 0:
        warnings.warn(
            "the polygon was given clockwise; its vertices were reversed to counter-clockwise "
            "order (vertex 0 stays first)",
            BlockMeshWarning,
            stacklevel=3,
        )
        order = np.r_[0, np.arange(n - 1, 0, -1)]
        pts = pts[order]
        # Edge i of the reversed polygon runs along input edge order[i+1] (backwards).
        source = source[np.roll(order, -1)]
    sines = corner_sines(pts)
    straight = np.flatnonzero(np.abs(sines) <= COLLINEAR_SIN_TOL)
    reflex = np.flatnonzero(sines < -COLLINEAR_SIN_TOL)
    if reflex.size:
        angles = interior_angles(pts)
        corners = ", ".join(
            f"vertex {int(source[i])} {fmt_point(pts[i])} ({angles[i]:.1f}°)" for i in reflex[:4]
        )
        raise DomainError(
            f"the polygon is not convex: the corner{'s' if reflex.size > 1 else ''} at {corners} "
            f"turn{'' if reflex.size > 1 else 's'} inward; only convex polygons are decomposed "
            "automatically: give explicit blocks instead (README, 'Domain files')"
        )
    if straight.size:
        if edge_patch is not None:
            for i in straight:
                before, after = edge_patch[source[i - 1]], edge_patch[source[i]]
                if before != after:
                    raise DomainError(
                        f"vertex {int(source[i])} {fmt_point(pts[i])} is a straight (180°) corner "
                        f"between patches {before or DEFAULT_PATCH!r} and "
                        f"{after or DEFAULT_PATCH!r}; blocks cannot have straight corners: move "
                        "it off the line or give explicit blocks"
                    )
        names = ", ".join(f"vertex {int(source[i])} {fmt_point(pts[i])}" for i in straight)
        warnings.warn(
            f"{names} lie{'s' if straight.size == 1 else ''} on a straight line between "
            "neighbouring corners; dropped (a block cannot have a 180° corner)",
            BlockMeshWarning,
            stacklevel=3,
        )
        keep = np.setdiff1d(np.arange(pts.shape[0]), straight)
        pts, source = pts[keep], source[keep]
        if pts.shape[0] < 3:
            raise DomainError("the polygon has fewer than 3 real corners")
    return pts, source


def _crossing_edges(pts: np.ndarray) -> str | None:
    """A message naming two non-adjacent edges that meet, and where; None if there are none."""
    n = pts.shape[0]
    segments = shapely.linestrings(np.stack([pts, np.roll(pts, -1, axis=0)], axis=1))
    first, second = shapely.STRtree(segments).query(segments, predicate="intersects")
    adjacent = (second == first) | (second == (first + 1) % n) | (first == (second + 1) % n)
    for i, j in zip(first[~adjacent], second[~adjacent], strict=True):
        if i < j:
            where = shapely.get_coordinates(shapely.intersection(segments[i], segments[j]))[0]
            return (
                f"the polygon's edges {i} {fmt_point(pts[i])}->{fmt_point(pts[(i + 1) % n])} and "
                f"{j} {fmt_point(pts[j])}->{fmt_point(pts[(j + 1) % n])} cross at "
                f"{fmt_point(where)}: list the vertices in order around the boundary"
            )
    return None


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
    if isinstance(raw, np.ndarray):
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
                problems.append(f"block {i} has vertex id {v!r}, which is not a whole number")
            elif not 0 <= v < n_vertices:
                problems.append(
                    f"block {i} refers to vertex {v}, but the vertices are numbered "
                    f"0..{n_vertices - 1}"
                )
        if len(set(block)) != len(block) and all(isinstance(v, numbers.Integral) for v in block):
            twice = sorted({v for v in block if block.count(v) > 1})
            problems.append(
                f"block {i} ({', '.join(map(str, block))}) uses vertex "
                f"{', '.join(map(str, twice))} twice; a block has five different corners"
            )
    _raise(DomainFormatError, problems)
    return np.array(items, dtype=np.int64).reshape(-1, 5)


def _block_label(blocks: np.ndarray, b: int) -> str:
    return f"block {b} (vertices {', '.join(map(str, blocks[b]))})"


def check_block_shapes(vertices: np.ndarray, blocks: np.ndarray, *, repair: bool) -> np.ndarray:
    """Check every block is a strictly convex pentagon; reverse clockwise ones when ``repair``.

    Returns the (possibly repaired) blocks as a new array. Also rejects vertices at the same
    coordinates and vertices no block uses.

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
    unused = np.setdiff1d(np.arange(vertices.shape[0]), blocks)
    _raise(
        DomainError,
        [
            f"vertex {v} {fmt_point(vertices[v])} is not used by any block; remove it or make it "
            "a corner of a block"
            for v in unused
        ],
    )
    xy = vertices[blocks]
    scale = _scale(vertices)
    areas = signed_area(xy)
    flat = np.flatnonzero(np.abs(areas) <= 1e-12 * scale**2)
    _raise(
        DomainError,
        [f"{_block_label(blocks, b)} has zero area: its corners lie on one line" for b in flat],
    )
    clockwise = np.flatnonzero(areas < 0)
    if clockwise.size:
        if not repair:
            _raise(
                DomainError,
                [
                    f"{_block_label(blocks, b)} runs clockwise; list its corners counter-clockwise"
                    for b in clockwise
                ],
            )
        reversed_order = [0, 4, 3, 2, 1]
        blocks[clockwise] = blocks[clockwise][:, reversed_order]
        xy = vertices[blocks]
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
    problems = []
    for b in range(blocks.shape[0]):
        label = _block_label(blocks, b)
        for k in range(5):
            v = blocks[b, k]
            if abs(sines[b, k]) <= COLLINEAR_SIN_TOL and angles[b, k] > 90:
                problems.append(
                    f"{label} is not strictly convex: the corner at vertex {v} "
                    f"{fmt_point(vertices[v])} is straight (180°); move vertex {v} off the line "
                    "through its neighbours, or use a block with that corner removed"
                )
                break
            if sines[b, k] < -COLLINEAR_SIN_TOL:
                problems.append(
                    f"{label} is not convex: the corner at vertex {v} {fmt_point(vertices[v])} "
                    f"turns the wrong way ({angles[b, k]:.1f}°); split the block or move the vertex"
                )
                break
        else:
            turning = float(np.sum(180.0 - angles[b]))
            if not np.isclose(turning, 360.0, atol=1e-6):
                problems.append(
                    f"{label} crosses itself (its corners go around {turning / 360:.0f} times); "
                    "list its corners in order around it"
                )
    _raise(DomainError, problems)
    return blocks


# --------------------------------------------------------------------------- topology
def check_topology(vertices: np.ndarray, blocks: np.ndarray, neighbour: np.ndarray) -> None:
    """Check that blocks meet edge to edge: no overlaps, gaps, hanging nodes, loose blocks.

    ``neighbour`` is :func:`blockmesh.topology.cell_neighbours` of the blocks (computed by the
    caller, which also rejects edges shared by three blocks). Raises TopologyError.
    """
    polygons = shapely.polygons(vertices[blocks])
    scale = _scale(vertices)
    _check_same_direction(blocks, neighbour)
    _check_overlaps(polygons)
    _check_near_edges(vertices, blocks, scale)
    _check_connected(neighbour)


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


def _check_overlaps(polygons: np.ndarray) -> None:
    areas = shapely.area(polygons)
    tree = shapely.STRtree(polygons)
    first, second = tree.query(polygons, predicate="intersects")
    pairs = first < second
    first, second = first[pairs], second[pairs]
    if first.size == 0:
        return
    shared = shapely.intersection(polygons[first], polygons[second])
    shared_area = shapely.area(shared)
    overlapping = shared_area > 1e-9 * np.minimum(areas[first], areas[second])
    problems = []
    for a, b, piece, area in zip(
        first[overlapping],
        second[overlapping],
        shared[overlapping],
        shared_area[overlapping],
        strict=True,
    ):
        where = shapely.get_coordinates(shapely.centroid(piece))[0]
        problems.append(
            f"blocks {a} and {b} overlap (shared area {area:.3g} around {fmt_point(where)}); "
            "blocks may touch only along whole edges"
        )
    _raise(TopologyError, problems)


def _check_near_edges(vertices: np.ndarray, blocks: np.ndarray, scale: float) -> None:
    """Hanging nodes (a vertex inside another block's edge) and gaps (a vertex next to one)."""
    start = blocks.ravel()
    stop = np.roll(blocks, -1, axis=1).ravel()
    segments = shapely.linestrings(np.stack([vertices[start], vertices[stop]], axis=1))
    points = shapely.points(vertices)
    tol = 1e-6 * scale
    tree = shapely.STRtree(segments)
    vertex, segment = tree.query(points, predicate="dwithin", distance=tol)
    touching = (vertex != start[segment]) & (vertex != stop[segment])
    vertex, segment = vertex[touching], segment[touching]
    if vertex.size == 0:
        return
    distance = shapely.distance(points[vertex], segments[segment])
    problems = []
    seen = set()
    for v, s, d in zip(vertex, segment, distance, strict=True):
        a, b, owner = start[s], stop[s], s // 5
        key = (int(v), min(a, b), max(a, b))
        if key in seen:
            continue
        seen.add(key)
        where = f"vertex {v} {fmt_point(vertices[v])}"
        if d <= GAP_TOL * scale:
            problems.append(
                f"{where} lies on edge ({a}, {b}) of block {owner} without being one of its "
                f"corners (a hanging node); blocks must meet edge to edge: split that edge at "
                f"vertex {v} by giving block {owner} the corner {v}, or move the vertex"
            )
        else:
            problems.append(
                f"{where} is only {d:.3g} from edge ({a}, {b}) of block {owner} (a gap or an "
                "overlap between blocks); blocks that meet must share their vertices"
            )
    _raise(TopologyError, problems)


def _check_connected(neighbour: np.ndarray) -> None:
    count, label = connected_pieces(neighbour)
    if count == 1:
        return
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


# --------------------------------------------------------------------------- patches, regions
def _check_name(name: object, what: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise DomainFormatError(
            f"{what} name {name!r} is not valid: use letters, digits, '_', '-' or '.', starting "
            "with a letter or '_'"
        )
    return name


def resolve_patches(
    boundary: np.ndarray, raw: Mapping[str, object] | None, edge_owner: Mapping[tuple, list]
) -> tuple[tuple[str, ...], np.ndarray]:
    """Assign every boundary edge to one patch.

    Parameters
    ----------
    boundary : ndarray (Eb, 2)
        The boundary edges, oriented with the domain on their left.
    raw : mapping of name to a list of [a, b] vertex pairs, or None
    edge_owner : mapping from a sorted vertex pair to the blocks using that edge

    Returns
    -------
    names : tuple of str
        Patch names in the order given, then ``"boundary"`` for unnamed edges (if any).
    patch : ndarray (Eb,)
        Index into ``names`` for each boundary edge.
    """
    raw = dict(raw or {})
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
            pair = list(edge) if isinstance(edge, Iterable) and not isinstance(edge, str) else None
            if (
                pair is None
                or len(pair) != 2
                or not all(
                    isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in pair
                )
            ):
                raise DomainFormatError(
                    f"patch {name!r} has {edge!r}; each edge is a pair of vertex ids [a, b]"
                )
            key = (int(pair[0]), int(pair[1]))
            k = index.get(key)
            if k is None:
                owners = edge_owner.get(tuple(sorted(key)), [])
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
    for name, ids in dict(raw or {}).items():
        _check_name(name, "region")
        if isinstance(ids, str | bytes) or not isinstance(ids, Iterable):
            raise DomainFormatError(f"region {name!r} must be a list of block ids, got {ids!r}")
        names.append(name)
        for b in ids:
            if not isinstance(b, numbers.Integral) or isinstance(b, bool):
                raise DomainFormatError(f"region {name!r} has block id {b!r}, not a whole number")
            if not 0 <= b < n_blocks:
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
