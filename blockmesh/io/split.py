"""Splitting pentagons into triangles or quadrilaterals, for formats without polygons (Gmsh).

Three splits, each keeping every pentagon's children together and counter-clockwise:

``tri5``
    5 triangles ``(v_i, v_i+1, c)`` around the vertex mean ``c`` (one new node per cell).
``tri3``
    a fan of 3 triangles from corner 0: ``(v0, v1, v2), (v0, v2, v3), (v0, v3, v4)``; no new nodes.
``quad5``
    5 quadrilaterals ``(v_i, m_i, c, m_i-1)`` through the vertex mean ``c`` and the edge
    midpoints ``m_i`` (of edge ``v_i v_i+1``). A midpoint is one node shared by the two cells of
    its edge, so the split mesh is conforming; boundary edges split into two lines.

New nodes are appended after the mesh's own: for ``quad5`` first the edge midpoints (in the
order of :func:`blockmesh.geometry.topology.unique_edges`), then the centres (in cell order); for
``tri5`` the centres. Element ``k`` of cell ``p`` is row ``n * p + k`` (``n`` = 5 or 3), and its
first node is corner 0 of ``p`` when ``k = 0`` — which lets a reader rebuild each pentagon with its
own corner order.

Examples
--------
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> pts = np.array([[0, 0], [2, 0], [2.5, 1], [2, 2], [0, 2], [4, 0], [4.5, 1], [4, 2.0]])
>>> mesh = Mesh.from_cells(pts, [[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]])
>>> s = split_cells(mesh, "quad5")
>>> s.points.shape, s.cells.shape, s.parent.tolist()
((19, 2), (10, 4), [0, 0, 0, 0, 0, 1, 1, 1, 1, 1])
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from blockmesh.errors import ExportError
from blockmesh.geometry.topology import edge_index, edge_keys
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["SPLITS", "SplitBoundary", "SplitCells", "split_boundary", "split_cells", "split_edges"]

#: The splits :func:`split_cells` offers, with one line each.
SPLITS = {
    "tri5": "5 triangles around the vertex mean of each cell (1 new node per cell)",
    "tri3": "3 triangles fanned from corner 0 (no new nodes)",
    "quad5": "5 quadrilaterals through the vertex mean and the edge midpoints (conforming)",
}


class SplitCells(NamedTuple):
    """The elements of a split mesh.

    Attributes
    ----------
    points : ndarray (N', 2)
        The mesh's nodes followed by the new ones.
    cells : ndarray (K, 3) or (K, 4)
        Counter-clockwise elements; the ``n`` children of cell ``p`` are rows ``n*p .. n*p+n-1``.
    parent : ndarray (K,)
        The pentagon (cell index of the mesh) each element comes from.
    """

    points: np.ndarray
    cells: np.ndarray
    parent: np.ndarray


class SplitBoundary(NamedTuple):
    """The boundary lines of a split mesh.

    ``edges`` (Eb', 2) are oriented like the mesh's boundary
    edges (domain on the left), and the patch index of each.
    """

    edges: np.ndarray
    patch: np.ndarray


def check_split(split: str | None) -> str:
    """``split`` itself if it is one of :data:`SPLITS`, else :class:`ExportError`."""
    if split not in SPLITS:
        choices = "; ".join(f"{k}: {v}" for k, v in SPLITS.items())
        raise ExportError(f"unknown split {split!r}; choose one of tri5, tri3, quad5 ({choices})")
    return split


def _midpoints(mesh: Mesh | PolygonMesh) -> tuple[np.ndarray, np.ndarray]:
    """Unique edge keys (sorted) and, per cell edge slot (M, 5), the index of its edge."""
    cells = mesh.polygon_cells() if isinstance(mesh, PolygonMesh) else mesh.cells
    return edge_index(cells, mesh.n_points)


def split_cells(mesh: Mesh | PolygonMesh, split: str) -> SplitCells:
    """Split every pentagon of ``mesh`` into triangles or quadrilaterals (see the module notes).

    O(M) for ``tri5`` and ``tri3``, O(M log M) for ``quad5`` (the edge numbering).

    Parameters
    ----------
    mesh : Mesh or PolygonMesh
    split : {"tri5", "tri3", "quad5"}
        A PolygonMesh takes ``tri5`` only: n triangles around the vertex mean of a cell of n
        vertices.

    Returns
    -------
    SplitCells
        ``(points, cells, parent)``.

    Examples
    --------
    >>> import numpy as np
    >>> from blockmesh.mesh import Mesh
    >>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
    >>> s = split_cells(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), "tri3")
    >>> s.cells.tolist()
    [[0, 1, 2], [0, 2, 3], [0, 3, 4]]
    """
    check_split(split)
    if isinstance(mesh, PolygonMesh):
        return _split_polygons(mesh, split)
    cells, n, m = mesh.cells, mesh.n_points, mesh.n_cells
    if split == "tri3":
        tris = np.stack([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]], cells[:, [0, 3, 4]]], axis=1)
        return SplitCells(mesh.points.copy(), tris.reshape(-1, 3), np.repeat(np.arange(m), 3))
    centre_xy = mesh.points[cells].mean(axis=1)
    if split == "tri5":
        centre = np.broadcast_to((n + np.arange(m))[:, None], (m, 5))
        tris = np.stack([cells, np.roll(cells, -1, axis=1), centre], axis=2)
        points = np.concatenate([mesh.points, centre_xy])
        return SplitCells(points, tris.reshape(-1, 3), np.repeat(np.arange(m), 5))
    unique, slot_edge = _midpoints(mesh)
    a, b = np.divmod(unique, n)
    mid_xy = 0.5 * (mesh.points[a] + mesh.points[b])
    mid = n + slot_edge
    centre = np.broadcast_to((n + unique.size + np.arange(m))[:, None], (m, 5))
    quads = np.stack([cells, mid, centre, np.roll(mid, 1, axis=1)], axis=2)
    points = np.concatenate([mesh.points, mid_xy, centre_xy])
    return SplitCells(points, quads.reshape(-1, 4), np.repeat(np.arange(m), 5))


def _split_polygons(mesh: PolygonMesh, split: str) -> SplitCells:
    """A polygon mesh's cells as the fan of triangles around each vertex mean (``tri5``).

    A cell of n vertices gives n triangles ``(v_i, v_i+1, c)``, valid for every cell star-shaped
    from its vertex mean (which PolygonMesh requires), hanging nodes included; a fan from a
    corner (``tri3``) would give triangles of no area at straight vertices, so only ``tri5`` is
    offered.
    """
    if split != "tri5":
        raise ExportError(
            f"split {split!r} is for pentagons; a polygon mesh (cells of {mesh.cell_sizes().min()}"
            f" to {mesh.cell_sizes().max()} vertices) is split by tri5: the fan of triangles "
            "around each cell's vertex mean"
        )
    cells = mesh.polygon_cells()
    owner = cells.slot_cell()
    tris = np.stack([mesh.nodes, cells.following(), mesh.n_points + owner], axis=1)
    points = np.concatenate([mesh.points, mesh.vertex_means()])
    return SplitCells(points, tris, owner)


def split_boundary(mesh: Mesh | PolygonMesh, split: str) -> SplitBoundary:
    """The boundary lines matching :func:`split_cells` (halved edges for ``quad5``).

    Examples
    --------
    >>> import numpy as np
    >>> from blockmesh.mesh import Mesh
    >>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
    >>> split_boundary(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), "quad5").edges[:2].tolist()
    [[0, 5], [5, 1]]
    """
    return split_edges(mesh, split, mesh.boundary_edges, mesh.boundary_patch, "boundary edge")


def split_edges(
    mesh: Mesh | PolygonMesh, split: str, edges: np.ndarray, group: np.ndarray, what: str = "edge"
) -> SplitBoundary:
    """Any edges of the mesh's cells (boundary, interfaces) as lines matching :func:`split_cells`.

    Each edge keeps its ``group`` (a patch or interface index); halved for ``quad5``.
    """
    check_split(split)
    if split != "quad5":
        return SplitBoundary(np.array(edges, dtype=np.int64), np.array(group, dtype=np.int64))
    unique, _ = _midpoints(mesh)
    be = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    keys = edge_keys(be[:, 0], be[:, 1], mesh.n_points)
    pos = np.minimum(np.searchsorted(unique, keys), max(unique.size - 1, 0))
    if keys.size and not np.array_equal(unique[pos], keys):
        bad = int(np.flatnonzero(unique[pos] != keys)[0])
        raise ExportError(
            f"{what} {bad} (nodes {be[bad, 0]}, {be[bad, 1]}) is not an edge of any cell; "
            "the mesh is inconsistent"
        )
    mid = mesh.n_points + pos
    halves = np.stack([np.stack([be[:, 0], mid], 1), np.stack([mid, be[:, 1]], 1)], axis=1)
    return SplitBoundary(halves.reshape(-1, 2), np.repeat(np.asarray(group, np.int64), 2))
