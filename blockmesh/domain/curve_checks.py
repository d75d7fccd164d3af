"""Checks of curved block edges, each failure a located :class:`~blockmesh.errors.DomainError`.

:func:`resolve_curves` turns the ``edges`` a user gives (``{(a, b): curve}``) into curves bound
to their vertices, refusing pairs that are not block edges and shapes that are invalid in
themselves (:mod:`blockmesh.curves`). :func:`check_curved_blocks` then checks that the blocks stay
valid with their curves:

- at every corner of a curved block the curve's tangent keeps the corner below 180 degrees;
- refined level by level with the curve-aware rule (:mod:`blockmesh.refinement.curved`) up to
  :data:`CHECK_LEVELS`, every cell of a curved block is strictly convex and counter-clockwise;
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

import numbers
from collections.abc import Mapping

import numpy as np
import shapely

from blockmesh.curves.edges import CurvedEdges, curved_slots, edge_points
from blockmesh.curves.types import SHAPE_TOL, Curve
from blockmesh.domain.validate import block_label
from blockmesh.errors import DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    corner_sines,
    interior_angles,
    signed_area,
)
from blockmesh.refinement.curved import curved_block_levels
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

    Cost: O(6^levels) per curved block (7,776 cells at the default depth).
    """
    table = curved_edges(curves)
    if table is None:
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
    xy = np.zeros(0)
    for step, xy in curved_block_levels(corners, along, mask, levels):
        if step:
            _check_cells(xy, step, blocks, curved_blocks, table, row[curved_blocks])
    outlines = _outlines(xy, levels)
    _check_outlines(vertices, blocks, curved_blocks, outlines, table, row[curved_blocks])


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


def _check_cells(xy, step, blocks, curved_blocks, table, row) -> None:
    template = pentagon_template(step)
    cells = template.cells
    corners = xy[:, cells]  # (B, C, 5, 2)
    local = corners - corners[:, :, :1]
    sines = np.nan_to_num(corner_sines(local), nan=-1.0)
    good = np.all(sines > COLLINEAR_SIN_TOL, axis=2) & (signed_area(local) > 0)
    if good.all():
        return
    i, cell = (int(v[0]) for v in np.nonzero(~good))
    b = int(curved_blocks[i])
    on_edges = {int(e) for e in template.edge_of_node[cells[cell]] if e >= 0}
    near = [e for e in sorted(on_edges) if row[i, e] >= 0] or [
        e for e in range(5) if row[i, e] >= 0
    ]
    names = " and ".join(_edge_label(table, row[i, e]) for e in near)
    angles = interior_angles(local[i, cell])
    worst = int(np.argmax(angles))
    raise DomainError(
        f"{block_label(blocks, b)} does not stay convex with {names}: refined to level {step}, "
        f"its cell with corners {', '.join(fmt_point(p, 6) for p in corners[i, cell])} has a "
        "corner of "
        f"{angles[worst]:.2f}° at {fmt_point(corners[i, cell, worst], 6)}; make the curve bulge "
        "less, or "
        "split the block so that the curve spans less of it"
    )


def _outlines(xy: np.ndarray, level: int) -> np.ndarray:
    """The boundary nodes of each refined block in order, (B, 5 * 2^level, 2)."""
    along = pentagon_template(level).edge_nodes[:, :-1].ravel()
    return xy[:, along]


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
    tree = shapely.STRtree(polygons)
    areas = shapely.area(polygons)
    for i, b in enumerate(curved_blocks.tolist()):
        for other in tree.query(polygons[b], predicate="intersects").tolist():
            if other == b:
                continue
            shared = shapely.intersection(polygons[b], polygons[other])
            overlap = float(shapely.area(shared))
            if overlap > _OVERLAP_TOL * min(float(areas[b]), float(areas[other])):
                names = " and ".join(_edge_label(table, r) for r in row[i] if r >= 0)
                centre = shapely.centroid(shared)
                raise DomainError(
                    f"{block_label(blocks, b)} with {names} runs into block {other} near "
                    f"{fmt_point((centre.x, centre.y), 6)} (they overlap by {overlap:.3g}); make "
                    "the "
                    "curve bulge less or move the vertices"
                )
