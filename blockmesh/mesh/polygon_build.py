"""A polygon mesh built from bare polygons: cells read, boundary found, edge-to-edge checked.

:meth:`PolygonMesh.from_cells <blockmesh.mesh.polygons.PolygonMesh.from_cells>` takes nodes and
polygons of any sizes; :func:`polygon_layout` reads and checks them (:func:`as_polygon_cells`
reads the cells, :func:`free_edges` finds the boundary, :func:`check_edge_to_edge` refuses a node
inside a neighbour's edge that the neighbour does not list) and names the boundary edges' patches.

Examples
--------
>>> pts = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]
>>> xy, rows, edges, patch, names = polygon_layout(pts, [[0, 1, 4, 5], [1, 2, 3, 4]], None)
>>> rows.n_cells, edges.shape, names
(2, (6, 2), ('boundary',))
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError, TopologyError
from blockmesh.geometry.topology import PolygonCells, boundary_of_cells, edge_keys
from blockmesh.mesh.arrays import check_finite
from blockmesh.mesh.labels import assign_patches

__all__ = ["as_polygon_cells", "check_edge_to_edge", "free_edges", "polygon_layout"]


def polygon_layout(
    points: Any, cells: Any, patches: Mapping[str, Any] | None
) -> tuple[np.ndarray, PolygonCells, np.ndarray, np.ndarray, tuple[str, ...]]:
    """The arrays :meth:`PolygonMesh.from_cells` builds a mesh of, each input checked.

    Returns ``(points (N, 2), cells, boundary edges (Eb, 2), their patch (Eb,), patch names)``.
    ArgumentError on a bad point, node id or cell size, or a patch edge off the boundary;
    TopologyError on an edge of three cells or cells not meeting edge to edge.
    """
    xy = np.array(points, dtype=np.float64)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ArgumentError(f"points must have shape (N, 2), got {xy.shape}")
    check_finite(xy)
    rows = as_polygon_cells(cells)
    n_points = xy.shape[0]
    if rows.nodes.size and (rows.nodes.min() < 0 or rows.nodes.max() >= n_points):
        slot = int(np.flatnonzero((rows.nodes < 0) | (rows.nodes >= n_points))[0])
        cell = int(np.searchsorted(rows.offsets, slot, side="right") - 1)
        cell_nodes = rows.nodes[rows.offsets[cell] : rows.offsets[cell + 1]].tolist()
        raise ArgumentError(f"cell {cell} {cell_nodes} has a node id outside 0..{n_points - 1}")
    sizes = np.diff(rows.offsets)
    if np.any(sizes < 3):
        bad = int(np.flatnonzero(sizes < 3)[0])
        raise ArgumentError(f"cell {bad} has {int(sizes[bad])} vertices; a cell needs 3 or more")
    edges = free_edges(rows, n_points)
    check_edge_to_edge(xy, edges)
    patch, names = assign_patches(edges, patches or {}, n_points)
    return xy, rows, edges, patch, names


def as_polygon_cells(cells: Any) -> PolygonCells:
    """Compressed rows of an (M, n) integer array, a sequence of sequences, or PolygonCells."""
    if isinstance(cells, PolygonCells):
        return PolygonCells(
            np.asarray(cells.offsets, dtype=np.int64), np.asarray(cells.nodes, dtype=np.int64)
        )
    if isinstance(cells, np.ndarray):
        if cells.dtype.kind not in "iu":
            raise ArgumentTypeError(f"cells must hold integer node ids, got {cells.dtype}")
        if cells.ndim != 2:
            raise ArgumentError(f"cells must have shape (M, n), got {cells.shape}")
        return PolygonCells.from_array(cells)
    try:
        rows: list[Sequence[int]] = [list(row) for row in cells]
    except TypeError:
        raise ArgumentTypeError("cells must be a sequence of node-id sequences") from None
    for k, row in enumerate(rows):
        if not all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in row):
            raise ArgumentTypeError(f"cell {k} {row!r} must hold integer node ids")
    return PolygonCells.from_lists(rows)


def free_edges(cells: PolygonCells, n_points: int) -> np.ndarray:
    """Directed boundary edges; TopologyError on an edge of three or more cells."""
    keys = edge_keys(cells.nodes, cells.following(), n_points)
    unique, counts = np.unique(keys, return_counts=True)
    if np.any(counts > 2):
        a, b = divmod(int(unique[np.flatnonzero(counts > 2)[0]]), n_points)
        raise TopologyError(f"edge ({a}, {b}) belongs to three or more cells")
    return boundary_of_cells(cells, n_points)


def check_edge_to_edge(points: np.ndarray, edges: np.ndarray) -> None:
    """TopologyError when cells do not meet edge to edge (a node inside a neighbour's edge).

    A node in the middle of a neighbour's edge that the neighbour does not list leaves that edge
    unmatched, so it shows up among the boundary edges with a boundary node inside it. The
    boundary nodes near every boundary edge are found with shapely's STRtree (O(Eb log Eb)).
    """
    import shapely

    if edges.shape[0] == 0:
        return
    nodes = np.unique(edges)
    size = float(np.ptp(points, axis=0).max())
    tree = shapely.STRtree(shapely.points(points[nodes]))
    lines = shapely.linestrings(points[edges])
    edge, hit = tree.query(lines, predicate="dwithin", distance=1e-10 * size)
    inside = (nodes[hit] != edges[edge, 0]) & (nodes[hit] != edges[edge, 1])
    if np.any(inside):
        k = int(np.flatnonzero(inside)[0])
        node, (a, b) = int(nodes[hit[k]]), edges[edge[k]].tolist()
        raise TopologyError(
            f"the cells do not meet edge to edge: node {node} {points[node].tolist()} lies "
            f"inside the edge ({a}, {b}) of a neighbouring cell (a hanging node that cell does "
            "not list); add the node to that cell as a vertex (a straight vertex)"
        )
