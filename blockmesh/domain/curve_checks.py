"""Checks of curved block edges, each failure a located :class:`~blockmesh.errors.DomainError`.

:func:`resolve_curves` turns the ``edges`` a user gives (``{(a, b): curve}``) into curves bound
to their vertices, refusing pairs that are not block edges and shapes that are invalid in
themselves (:mod:`blockmesh.curves`). :func:`check_curved_blocks` then checks that the blocks stay
valid with their curves:

- at every corner of a curved block the curve's tangent keeps the corner below 180 degrees;
- refined level by level with the curve-aware rule (:mod:`blockmesh.refinement.curved`) up to
  :data:`CHECK_LEVELS`, every cell of a curved block is strictly convex and counter-clockwise;
  only the children of cells that touch a curve are measured at each level: every other cell
  is refined by the paper's straight rule, which keeps a strictly convex pentagon's children
  strictly convex (``docs/mathematics.md`` §1: the vertex mean lies strictly inside the pentagon
  of the edge midpoints), so the work grows as ``2^level`` per curved edge, not ``6^level``;
- the outline of a curved block (its edges at that depth) does not cross itself or another block.

Every message names the block, the curved edge and a point, and says how to fix it.

Examples
--------
>>> from blockmesh import Domain
>>> from blockmesh.curves import Arc
>>> pentagon = [(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)]
>>> Domain.from_blocks(pentagon, [(0, 1, 2, 3, 4)], edges={(0, 2): Arc(center=(1, 1))})
Traceback (most recent call last):
...
blockmesh.errors.DomainError: edge (0, 2) is not a block edge: vertices 0 and 2 are not ...
"""

from __future__ import annotations

import hashlib
import numbers
from collections import OrderedDict
from collections.abc import Mapping
from functools import cache

import numpy as np
import shapely

from blockmesh.curves.edges import CurvedEdges, curved_slots, edge_points
from blockmesh.curves.types import SHAPE_TOL, Curve
from blockmesh.domain.validate.blocks import block_label
from blockmesh.errors import DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    corner_sines,
    interior_angles,
    signed_area,
)
from blockmesh.refinement.curved import curved_block_levels, edge_midpoints
from blockmesh.refinement.template import pentagon_template

__all__ = ["CHECK_LEVELS", "check_curved_blocks", "curved_edges", "resolve_curves"]

#: Levels to which the cells of curved blocks are checked (strictly convex and counter-clockwise).
CHECK_LEVELS = 5
#: Two blocks overlapping by more than this fraction of the smaller one's area cross each other.
_OVERLAP_TOL = 1e-9


def _vertex_id(value: object, n_vertices: int, key: object) -> int:
    if not isinstance(value, numbers.Integral) or isinstance(value, bool):
        raise DomainFormatError(
            f"curved edge {key!r}: vertex ids must be whole numbers, got {value!r}"
        )
    if not 0 <= int(value) < n_vertices:
        raise DomainError(
            f"curved edge {key!r} names vertex {value}, but the vertices are numbered "
            f"0..{n_vertices - 1}"
        )
    return int(value)


def resolve_curves(
    vertices: np.ndarray, blocks: np.ndarray, edges: object
) -> dict[tuple[int, int], Curve]:
    """The curves of ``edges`` bound to the vertices, keyed ``(a, b)`` as each curve runs.

    ``edges`` maps vertex pairs ``(a, b)`` to curves (:class:`~blockmesh.curves.Arc`,
    :class:`~blockmesh.curves.Spline`, :class:`~blockmesh.curves.Polyline`); the curve runs from
    vertex ``a`` to vertex ``b``. Curves that already have ends must have them at those vertices.
    """
    if edges is None:
        return {}
    if not isinstance(edges, Mapping):
        raise DomainFormatError(
            "edges must map vertex pairs (a, b) to curves (Arc, Spline, Polyline), got "
            f"{type(edges).__name__}"
        )
    owners: dict[tuple[int, int], int] = {}
    for b, block in enumerate(blocks.tolist()):
        for k in range(5):
            a, c = block[k], block[(k + 1) % 5]
            owners.setdefault((min(a, c), max(a, c)), b)
    scale = float(np.hypot(*np.ptp(vertices, axis=0))) or 1.0
    out: dict[tuple[int, int], Curve] = {}
    seen: dict[tuple[int, int], tuple[int, int]] = {}
    for key, curve in edges.items():
        if isinstance(key, str | bytes) or not hasattr(key, "__len__") or len(key) != 2:
            raise DomainFormatError(f"curved edge {key!r} must be a pair (a, b) of vertex ids")
        a, b = (_vertex_id(v, vertices.shape[0], key) for v in key)
        if not isinstance(curve, Curve):
            raise DomainFormatError(
                f"edge ({a}, {b}) must map to a curve (Arc, Spline or Polyline), got "
                f"{type(curve).__name__}"
            )
        undirected = (min(a, b), max(a, b))
        if undirected in seen:
            raise DomainError(
                f"edge ({a}, {b}) has two curves (it is also given as {seen[undirected]}); "
                "give each edge one curve"
            )
        seen[undirected] = (a, b)
        if undirected not in owners:
            raise DomainError(_not_a_block_edge(a, b, blocks))
        if curve.start is not None and curve.end is not None:
            for end, vertex in ((curve.start, a), (curve.end, b)):
                if float(np.hypot(*(np.array(end) - vertices[vertex]))) > SHAPE_TOL * scale:
                    raise DomainError(
                        f"the {curve.kind} on edge ({a}, {b}) has an end at {fmt_point(end, 6)}, "
                        "but "
                        f"vertex {vertex} is at {fmt_point(vertices[vertex], 6)}; leave the ends "
                        "out (the "
                        "vertices are used) or give them in the order of the pair"
                    )
        out[(a, b)] = curve.with_ends(vertices[a], vertices[b], f"edge ({a}, {b})")
    return out


def _not_a_block_edge(a: int, b: int, blocks: np.ndarray) -> str:
    holders = [k for k, block in enumerate(blocks.tolist()) if a in block or b in block]
    hint = ""
    if holders:
        block = blocks[holders[0]].tolist()
        pairs = ", ".join(f"({block[k]}, {block[(k + 1) % 5]})" for k in range(5))
        hint = f" (block {holders[0]} has the edges {pairs})"
    return (
        f"edge ({a}, {b}) is not a block edge: vertices {a} and {b} are not consecutive corners "
        f"of any block{hint}; a curve replaces a whole block edge"
    )


def curved_edges(curves: Mapping[tuple[int, int], Curve]) -> CurvedEdges | None:
    """The block mesh's :class:`~blockmesh.curves.CurvedEdges` (one row per curve), or None."""
    if not curves:
        return None
    n = len(curves)
    return CurvedEdges(
        edges=np.array(list(curves), dtype=np.int64).reshape(n, 2),
        curve=np.arange(n),
        start=np.zeros(n),
        stop=np.ones(n),
        curves=tuple(curves.values()),
    )


# ---------------------------------------------------------------------------- the blocks
def _edge_label(table: CurvedEdges, row: int) -> str:
    a, b = table.edges[row]
    return f"the {table.curves[int(table.curve[row])].kind} on edge ({a}, {b})"


def check_curved_blocks(
    vertices: np.ndarray,
    blocks: np.ndarray,
    curves: Mapping[tuple[int, int], Curve],
    levels: int = CHECK_LEVELS,
) -> None:
    """Raise DomainError unless every block stays valid with its curved edges (module docstring).

    Cost: O(2^levels) cells per curved block, refined along the block's edges only, and
    measured next to its curved edges. A domain that passed is remembered (by a digest of its
    vertices, blocks and curves; the last :data:`_PASSED_KEPT`), so that building it again in
    the same process does not check it again.
    """
    table = curved_edges(curves)
    if table is None:
        return
    key = _digest(vertices, blocks, table, levels)
    if key in _PASSED:
        _PASSED.move_to_end(key)
        return
    row, forward = curved_slots(blocks, vertices.shape[0], table)
    curved_blocks = np.flatnonzero(np.any(row >= 0, axis=1))
    _check_tangents(
        vertices, blocks, table, row[curved_blocks], forward[curved_blocks], curved_blocks
    )
    corners = vertices[blocks[curved_blocks]]
    along = np.zeros((curved_blocks.size, 5, 2**levels + 1, 2))
    points = edge_points(table, levels)
    mask = row[curved_blocks] >= 0
    along[mask] = points[row[curved_blocks][mask]]
    backward = mask & ~forward[curved_blocks]
    along[backward] = along[backward][:, ::-1]
    for step, xy in curved_block_levels(corners, along, mask, levels, ring=True):
        if step:
            _check_cells(xy, step, levels, mask, blocks, curved_blocks, table, row[curved_blocks])
    _check_outlines(
        vertices, blocks, curved_blocks, _outlines(corners, along, mask), table, row[curved_blocks]
    )
    _PASSED[key] = None
    while len(_PASSED) > _PASSED_KEPT:
        _PASSED.popitem(last=False)


#: Digests of the domains that passed :func:`check_curved_blocks` (most recent last).
_PASSED: OrderedDict[bytes, None] = OrderedDict()
_PASSED_KEPT = 64


def _digest(vertices: np.ndarray, blocks: np.ndarray, table: CurvedEdges, levels: int) -> bytes:
    """A digest of everything the checks look at: coordinates, blocks, curves and depth."""
    digest = hashlib.blake2b(digest_size=20)
    for array in (vertices, blocks, table.edges):
        array = np.ascontiguousarray(array)
        digest.update(f"{array.dtype}{array.shape}".encode())
        digest.update(array.tobytes())
    for curve in table.curves:
        digest.update(repr((curve.kind, curve.start, curve.end, curve.to_fields())).encode())
    digest.update(str(levels).encode())
    return digest.digest()


def _tangent(curve: Curve, forward: bool, at_start: bool) -> np.ndarray:
    """The direction a block runs along a curved edge, at the edge's first or last corner."""
    t = (0.0 if at_start else 1.0) if forward else (1.0 if at_start else 0.0)
    d = curve.derivative(t)
    return d if forward else -d


def _check_tangents(vertices, blocks, table, row, forward, which) -> None:
    for i, b in enumerate(which.tolist()):
        corners = vertices[blocks[b]]
        for k in range(5):
            before, after = (k - 1) % 5, k
            incoming = corners[k] - corners[before]
            outgoing = corners[(k + 1) % 5] - corners[k]
            named = []
            if row[i, before] >= 0:
                incoming = _tangent(
                    table.curves[int(table.curve[row[i, before]])], bool(forward[i, before]), False
                )
                named.append(_edge_label(table, row[i, before]))
            if row[i, after] >= 0:
                outgoing = _tangent(
                    table.curves[int(table.curve[row[i, after]])], bool(forward[i, after]), True
                )
                named.append(_edge_label(table, row[i, after]))
            if not named:
                continue
            cross = incoming[0] * outgoing[1] - incoming[1] * outgoing[0]
            turn = float(np.arctan2(cross, incoming @ outgoing))
            if turn < -COLLINEAR_SIN_TOL:
                angle = 180.0 - np.degrees(turn)
                raise DomainError(
                    f"{block_label(blocks, b)} is not convex at vertex {blocks[b, k]} "
                    f"{fmt_point(corners[k], 6)}: with {' and '.join(named)} the corner is "
                    f"{angle:.2f}° "
                    "(more than 180°); make the curve bulge less there, or move the vertex"
                )


@cache
def _children_near(step: int, level: int, edge: int) -> np.ndarray:
    """The cells at ``step`` whose parent (at ``step - 1``) has an edge on block edge ``edge``.

    Only these are placed by the curve-aware rule when ``edge`` is curved (sorted ids into
    ``pentagon_template(step).cells``; child ``k`` of parent ``j`` is cell ``6 j + k``).
    """
    parents = np.unique(edge_midpoints(step, level)[edge][0])
    return (6 * parents[:, None] + np.arange(6)).ravel()


def _check_cells(xy, step, level, curved, blocks, curved_blocks, table, row) -> None:
    """Every cell at ``step`` that the curves placed is strictly convex and counter-clockwise.

    ``curved`` (B, 5) says which edges of each curved block are curved; the blocks are taken
    in groups of the same curved edges, each measuring only the children of the cells on them.
    """
    template = pentagon_template(step)
    patterns, group = np.unique(curved, axis=0, return_inverse=True)
    bad: list[tuple[int, int]] = []
    for g, pattern in enumerate(patterns):
        members = np.flatnonzero(group.ravel() == g)
        near = np.unique(
            np.concatenate([_children_near(step, level, e) for e in np.flatnonzero(pattern)])
        )
        local = xy[members[:, None, None], template.cells[near]]  # (G, C, 5, 2)
        local -= local[:, :, :1]
        sines = np.nan_to_num(corner_sines(local), nan=-1.0)
        good = np.all(sines > COLLINEAR_SIN_TOL, axis=2) & (signed_area(local) > 0)
        if not good.all():
            i, c = (int(v[0]) for v in np.nonzero(~good))
            bad.append((int(members[i]), int(near[c])))
    if not bad:
        return
    i, cell = min(bad)  # the first curved block with a broken cell, as the blocks are numbered
    cells = template.cells
    corners = xy[i][cells[cell]][None, None]
    local = corners - corners[:, :, :1]
    b = int(curved_blocks[i])
    on_edges = {int(e) for e in template.edge_of_node[cells[cell]] if e >= 0}
    curved_here = [e for e in sorted(on_edges) if row[i, e] >= 0] or [
        e for e in range(5) if row[i, e] >= 0
    ]
    names = " and ".join(_edge_label(table, row[i, e]) for e in curved_here)
    angles = interior_angles(local[0, 0])
    worst = int(np.argmax(angles))
    raise DomainError(
        f"{block_label(blocks, b)} does not stay convex with {names}: refined to level {step}, "
        f"its cell with corners {', '.join(fmt_point(p, 6) for p in corners[0, 0])} has a "
        f"corner of {angles[worst]:.2f}° at {fmt_point(corners[0, 0, worst], 6)}; make the curve "
        "bulge less, or "
        "split the block so that the curve spans less of it"
    )


def _outlines(corners: np.ndarray, along: np.ndarray, curved: np.ndarray) -> np.ndarray:
    """Each curved block's outline, (B, 5 * 2^level, 2): its curves' points, its corners.

    A straight edge is its first corner repeated (the refined nodes on it lie on the segment),
    so a block meets its neighbours across a straight edge exactly at the segment's ends, and
    across a curved edge at the same points of the curve: neither leaves slivers to measure.
    """
    outline = along[:, :, :-1].copy()
    outline[~curved] = corners[~curved][:, None, :]
    return outline.reshape(corners.shape[0], -1, 2)


def _check_outlines(vertices, blocks, curved_blocks, outlines, table, row) -> None:
    polygons = shapely.polygons(vertices[blocks])
    curved_polygons = shapely.polygons(outlines)
    for i, b in enumerate(curved_blocks.tolist()):
        reason = shapely.is_valid_reason(curved_polygons[i])
        if reason != "Valid Geometry":
            names = " and ".join(_edge_label(table, r) for r in row[i] if r >= 0)
            where = reason.split("[", 1)[1].rstrip("]").split() if "[" in reason else []
            at = f" near ({', '.join(where)})" if where else ""
            raise DomainError(
                f"{block_label(blocks, b)} crosses itself with {names}{at}: a curve runs over "
                "another edge of its block; make it bulge less or move the vertices"
            )
    polygons[curved_blocks] = curved_polygons
    # Every pair (curved block, block) whose insides meet, all at once; the neighbours across a
    # curved edge meet in slivers of round-off, so the overlap's area decides.
    i, other = shapely.STRtree(polygons).query(polygons[curved_blocks], predicate="intersects")
    b = curved_blocks[i]
    meet = other != b
    i, b, other = i[meet], b[meet], other[meet]
    meet = shapely.relate_pattern(polygons[b], polygons[other], "2********")
    i, b, other = i[meet], b[meet], other[meet]
    shared = shapely.intersection(polygons[b], polygons[other])
    overlap = shapely.area(shared)
    areas = shapely.area(polygons)
    bad = np.flatnonzero(overlap > _OVERLAP_TOL * np.minimum(areas[b], areas[other]))
    if bad.size:
        k = bad[np.lexsort((other[bad], i[bad]))[0]]  # the first curved block, as numbered
        names = " and ".join(_edge_label(table, r) for r in row[i[k]] if r >= 0)
        centre = shapely.centroid(shared[k])
        raise DomainError(
            f"{block_label(blocks, int(b[k]))} with {names} runs into block {int(other[k])} "
            f"near {fmt_point((centre.x, centre.y), 6)} (they overlap by {overlap[k]:.3g}); make "
            "the curve bulge less or move the vertices"
        )
