"""One partition's piece of the mesh, built on its own from the partitioning alone.

A piece holds the cells of its units and every node they use, numbered locally in increasing
global id, with

- ``global_node_ids``: the id of each local node in the whole mesh (the serial ``refine``
  numbering), so that pieces can be put together (:func:`blockmesh.distributed.gather`);
- ``ghost``: True for the nodes another partition owns (shared unit corners and the nodes of
  edges numbered by a unit of a lower partition);
- ``boundary_order``: the position of each of the piece's boundary edges in the whole mesh's
  boundary list.

The cells of a piece are a contiguous run of the whole mesh's cells, starting at
``first_cell``. Coordinates are computed by the paper's arithmetic unit by unit, and a unit with a
curved edge by the curve-aware rule of :mod:`blockmesh.refinement.curved`, so each node has bit
for bit the coordinates the serial refinement gives it; the piece's mesh carries its curved edges
(``Mesh.curves``), so that it integrates over the exact geometry too.

Examples
--------
>>> import blockmesh
>>> from blockmesh.distributed.partition import partition
>>> parts = partition(blockmesh.load_domain("joined-2"), 2, 2)
>>> first, second = build_piece(parts, 0), build_piece(parts, 1)
>>> first.mesh.n_cells, second.first_cell, int(second.ghost.sum())
(36, 36, 5)
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np

from blockmesh.distributed.partition import Partitioning
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.curved import CurvedBlocks, refined_curves
from blockmesh.refinement.plan import block_node_ids, edge_node_ids, place_block
from blockmesh.refinement.template import node_count, pentagon_template

__all__ = ["Piece", "build_piece", "piece_node_count", "piece_nodes"]


@dataclass(frozen=True)
class Piece:
    """One partition of a mesh: a Mesh in local node ids and how it sits in the whole.

    Attributes
    ----------
    mesh : Mesh
        The piece's cells on its nodes; ``parent`` holds global cell ids, ``boundary_edges``
        only the whole mesh's boundary edges that lie in the piece.
    global_node_ids : ndarray (n,) int64
        Increasing.
    ghost : ndarray (n,) bool
    boundary_order : ndarray (Eb,) int64
    index, n_pieces, first_cell : int
    n_cells_total, n_nodes_total, n_boundary_total : int
        Sizes of the whole mesh.
    """

    mesh: Mesh
    global_node_ids: np.ndarray
    ghost: np.ndarray
    boundary_order: np.ndarray
    index: int
    n_pieces: int
    first_cell: int
    n_cells_total: int
    n_nodes_total: int
    n_boundary_total: int

    @property
    def n_owned(self) -> int:
        """Nodes this piece owns (its nodes that are not ghosts)."""
        return int(self.ghost.size - np.count_nonzero(self.ghost))


@dataclass(frozen=True)
class _Layout:
    """Where the global ids of a piece go locally: per-level runs and the few other nodes."""

    range_start: np.ndarray  # (steps,) first global id of the piece's run at each level
    range_size: np.ndarray  # (steps,)
    local_start: np.ndarray  # (steps,) local id of each run's first node
    others: np.ndarray  # sorted global ids of unit corners and ghost edge nodes
    others_local: np.ndarray  # their local ids
    n_nodes: int


def _outside_edges(parts: Partitioning, piece: int) -> list[tuple[int, int]]:
    """(unit, edge) of the piece's edges numbered by a unit of a lower partition."""
    units = parts.units(piece)
    plan = parts.plan
    lower = plan.neighbour[units.start : units.stop] // 5
    unit, edge = np.nonzero(plan.taken[units.start : units.stop] & (lower < units.start))
    return [(int(u) + units.start, int(e)) for u, e in zip(unit, edge, strict=True)]


def _layout(parts: Partitioning, piece: int) -> tuple[_Layout, np.ndarray]:
    plan = parts.plan
    units = parts.units(piece)
    first, last = units.start, units.stop - 1
    range_start = plan.offsets[1:, first].copy()
    range_size = plan.offsets[1:, last] + plan.counts[1:, last] - range_start
    ghosts = [edge_node_ids(plan, u, e)[1:-1] for u, e in _outside_edges(parts, piece)]
    corners = plan.cells[units.start : units.stop].ravel()
    others = np.unique(np.concatenate([corners, *ghosts]))
    below = np.clip(others[:, None] - range_start[None, :], 0, range_size[None, :]).sum(axis=1)
    others_local = np.arange(others.size, dtype=np.int64) + below
    local_start = np.searchsorted(others, range_start) + np.cumsum(range_size) - range_size
    n_nodes = int(others.size + range_size.sum())
    ghost_others = np.ones(others.size, dtype=bool)
    is_corner = others < plan.n_base_points
    ghost_others[is_corner] = parts.corner_owner[others[is_corner]] != piece
    layout = _Layout(range_start, range_size, local_start, others, others_local, n_nodes)
    return layout, ghost_others


def piece_node_count(parts: Partitioning, piece: int) -> int:
    """Nodes of partition ``piece`` (its own and its ghosts), without building any of them.

    Examples
    --------
    >>> import blockmesh
    >>> from blockmesh.distributed.partition import partition
    >>> piece_node_count(partition(blockmesh.load_domain("joined-2"), 1, 2), 1)
    15
    """
    return _layout(parts, piece)[0].n_nodes


def piece_nodes(parts: Partitioning, piece: int) -> tuple[np.ndarray, np.ndarray]:
    """Global ids (increasing) and ghost marks of the nodes of partition ``piece``. O(nodes).

    Examples
    --------
    >>> import blockmesh
    >>> from blockmesh.distributed.partition import partition
    >>> parts = partition(blockmesh.load_domain("joined-2"), 1, 2)
    >>> ids, ghost = piece_nodes(parts, 1)
    >>> ids.tolist()  # corners 1, 2 and the midpoint 9 of the shared edge are block 0's
    [1, 2, 5, 6, 7, 9, 18, 19, 20, 21, 22, 23, 24, 25, 26]
    >>> ghost.astype(int).tolist()
    [1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0]
    """
    return _nodes(*_layout(parts, piece))


def _nodes(layout: _Layout, ghost_others: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    ids = np.empty(layout.n_nodes, dtype=np.int64)
    ghost = np.zeros(layout.n_nodes, dtype=bool)
    ids[layout.others_local] = layout.others
    ghost[layout.others_local] = ghost_others
    for start, size, local in zip(
        layout.range_start, layout.range_size, layout.local_start, strict=True
    ):
        ids[local : local + size] = np.arange(start, start + size)
    return ids, ghost


def build_piece(parts: Partitioning, piece: int) -> Piece:
    """The piece of partition ``piece``: coordinates, cells and boundary of its units.

    O(cells of the piece); memory: the piece's arrays plus one unit's working arrays.
    """
    plan, base = parts.plan, parts.base
    steps = parts.steps
    template = pentagon_template(steps)
    per_unit = 6**steps
    units = parts.units(piece)
    layout, ghost_others = _layout(parts, piece)
    global_ids, ghost = _nodes(layout, ghost_others)
    points = np.empty(layout.n_nodes, dtype=np.complex128)
    cells = np.empty((len(units) * per_unit, 5), dtype=np.int64)
    corners_xy = base.points.view(np.complex128)[:, 0]
    local = np.empty(template.n_nodes, dtype=np.complex128)
    ids = np.empty(template.n_nodes, dtype=np.int64)
    bounds = [node_count(level) for level in range(steps + 1)]
    shift = layout.local_start - layout.range_start
    outside: dict[int, list[int]] = {}
    for unit, edge in _outside_edges(parts, piece):
        outside.setdefault(unit, []).append(edge)
    along = template.edge_nodes
    in_piece = (parts.boundary_unit >= units.start) & (parts.boundary_unit < units.stop)
    boundary_rows = np.flatnonzero(in_piece)
    boundary_nodes = np.empty((boundary_rows.size, along.shape[1]), dtype=np.int64)
    rows_of: dict[int, list[int]] = {}
    for k, unit in enumerate(parts.boundary_unit[boundary_rows].tolist()):
        rows_of.setdefault(unit, []).append(k)
    curves = base.curves if base.curves is not None and len(base.curves) else None
    # The curve-aware rule in the same pass as the straight arithmetic, as refine does.
    rule = CurvedBlocks(base, steps) if curves is not None else None
    along_curve: dict[int, np.ndarray] = {}  # row of base.curves -> local ids along it
    for unit in units:
        curved_unit = rule is not None and bool(rule.is_curved[unit])
        fix = partial(rule.fix_level, block=unit) if rule is not None and curved_unit else None
        place_block(template, corners_xy[base.cells[unit]], local, fix)
        _, numbered = block_node_ids(plan, unit, out=ids)
        # Corners and nodes of edges a lower partition numbered are not in the per-level runs.
        special = np.concatenate(
            [np.arange(5), *(along[edge][1:-1] for edge in outside.get(unit, ()))]
        )
        special_global = ids[special]
        for level in range(1, steps + 1):
            lo, hi = bounds[level - 1], bounds[level]
            ids[lo:hi] += shift[level - 1]
            start = int(shift[level - 1] + plan.offsets[level, unit])
            target = points[start : start + int(plan.counts[level, unit])]
            np.compress(numbered[lo:hi], local[lo:hi], out=target)
        ids[special] = layout.others_local[np.searchsorted(layout.others, special_global)]
        points[ids[special]] = local[special]
        k = unit - units.start
        np.take(
            ids, template.cells, axis=0, out=cells[k * per_unit : (k + 1) * per_unit], mode="clip"
        )
        for row in rows_of.get(unit, ()):
            boundary_nodes[row] = ids[along[int(parts.boundary_side[boundary_rows[row]])]]
        if rule is not None and curved_unit:
            for edge in np.flatnonzero(rule.row[unit] >= 0).tolist():
                nodes = ids[along[edge]]
                along_curve.setdefault(
                    int(rule.row[unit, edge]), nodes if rule.forward[unit, edge] else nodes[::-1]
                )
    piece_curves = None
    if curves is not None:
        rows = np.array(sorted(along_curve), dtype=np.int64)
        ids_along = np.array([along_curve[r] for r in rows.tolist()], dtype=np.int64)
        piece_curves = refined_curves(
            curves, rows, ids_along.reshape(rows.size, along.shape[1]), steps
        )
    return _assemble(
        parts, piece, points, cells, global_ids, ghost, boundary_rows, boundary_nodes, piece_curves
    )


def _assemble(
    parts, piece, points, cells, global_ids, ghost, boundary_rows, boundary_nodes, curves=None
):
    base, steps = parts.base, parts.steps
    units = parts.units(piece)
    per_unit = 6**steps
    segments = 2**steps
    edges = np.stack([boundary_nodes[:, :-1], boundary_nodes[:, 1:]], axis=-1).reshape(-1, 2)
    order = (boundary_rows[:, None] * segments + np.arange(segments)).ravel()
    first_parent = units.start * per_unit // 6
    parent = np.repeat(np.arange(first_parent, units.stop * per_unit // 6, dtype=np.int64), 6)
    arrays = {
        "points": points.view(np.float64).reshape(-1, 2),
        "cells": cells,
        "block_id": np.repeat(base.block_id[units.start : units.stop], per_unit),
        "parent": parent,
        "boundary_edges": edges,
        "boundary_patch": np.repeat(base.boundary_patch[boundary_rows], segments),
        "region": np.repeat(base.region[units.start : units.stop], per_unit),
    }
    for array in (*arrays.values(), global_ids, ghost, order):
        array.setflags(write=False)
    mesh = Mesh._trusted(
        **arrays,
        patch_names=base.patch_names,
        region_names=base.region_names,
        level=base.level + steps,
        name=base.name,
        curves=curves,
    )
    return Piece(
        mesh=mesh,
        global_node_ids=global_ids,
        ghost=ghost,
        boundary_order=order,
        index=piece,
        n_pieces=parts.n_partitions,
        first_cell=parts.first_cell(piece),
        n_cells_total=parts.n_cells,
        n_nodes_total=parts.n_nodes,
        n_boundary_total=int(base.boundary_edges.shape[0]) * segments,
    )
