"""What the formats share for polygon meshes (:class:`~blockmesh.mesh.polygons.PolygonMesh`).

Every writer takes a PolygonMesh as well as a Mesh: the cells are written as the format holds
polygons (VTK polygons, XDMF ``Mixed`` topology, MATLAB cell arrays, OpenFOAM n-gon faces, the
compressed rows in ``.npz``; Gmsh, which has no polygons, gets each cell as the fan of triangles
around its vertex mean). The metadata then says ``"cells": "polygons"`` and carries nothing else
new; the per-cell ``cell_level`` goes where the format has cell data. Readers return a
PolygonMesh for such a file, and for any file whose cells are not all pentagons; a file of
pentagons without that mark is read as a Mesh, as before.

Examples
--------
>>> import numpy as np
>>> offsets, nodes = blocks_to_rows([np.array([[0, 1, 2]]), np.array([[2, 1, 3, 4]])])
>>> offsets.tolist(), nodes.tolist()
([0, 3, 7], [0, 1, 2, 2, 1, 3, 4])
"""

from __future__ import annotations

from typing import Any

import numpy as np

from blockmesh.errors import BlockMeshError, ExportError
from blockmesh.geometry.topology import PolygonCells, boundary_of_cells
from blockmesh.io.common import _level, check_points, interface_arrays
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "POLYGONS",
    "as_written",
    "blocks_to_rows",
    "is_polygon_file",
    "polygon_mesh_from_arrays",
    "rows_to_blocks",
]

#: The value of the metadata key ``cells`` in files of polygon meshes.
POLYGONS = "polygons"


def is_polygon_file(meta: dict[str, Any]) -> bool:
    """Whether a file's blockmesh metadata says it holds a polygon mesh."""
    return meta.get("cells") == POLYGONS


def blocks_to_rows(blocks: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Compressed rows (offsets, nodes) of rectangular blocks of cells, in order."""
    parts = [np.full(b.shape[0], b.shape[1], dtype=np.int64) for b in blocks]
    sizes = np.concatenate(parts) if parts else np.zeros(0, np.int64)
    offsets = np.zeros(sizes.size + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    rows = [np.asarray(b, dtype=np.int64).ravel() for b in blocks]
    return offsets, np.concatenate(rows) if rows else np.zeros(0, np.int64)


def rows_to_blocks(offsets: np.ndarray, nodes: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """The rows grouped by size: ``(index, cells (M_n, n))`` per size, increasing."""
    sizes = np.diff(offsets)
    out = []
    for size in np.unique(sizes).tolist():
        index = np.flatnonzero(sizes == size)
        out.append((index, nodes[offsets[index][:, None] + np.arange(size)]))
    return out


def _column(values: Any, m: int, what: str, where: str) -> np.ndarray | None:
    if values is None:
        return None
    arr = np.asarray(values).reshape(-1)
    if arr.shape[0] != m:
        raise ExportError(f"{where}: {what} has {arr.shape[0]} entries, expected {m}")
    return _integers(arr, what, where)


def _integers(values: Any, what: str, where: str) -> np.ndarray:
    """``values`` as a flat int64 array; ExportError unless they are whole numbers below 2**62."""
    try:
        arr = np.asarray(values).reshape(-1)
    except (TypeError, ValueError) as error:
        raise ExportError(f"{where}: {what} is not an array of numbers ({error})") from None
    if arr.dtype.kind == "f":
        whole = np.isfinite(arr) & (np.abs(arr) < 2.0**62)
        whole[whole] = arr[whole] == np.round(arr[whole])
        if not whole.all():
            bad = int(np.flatnonzero(~whole)[0])
            raise ExportError(f"{where}: {what} entry {bad} is {arr[bad]!r}, not a whole number")
    elif arr.dtype.kind == "u" and arr.size and arr.max() >= 2**62:
        raise ExportError(f"{where}: {what} holds {arr.max()}, beyond any index")
    elif arr.dtype.kind not in "iu":
        raise ExportError(f"{where}: {what} does not hold whole numbers ({arr.dtype})")
    return arr.astype(np.int64)


def polygon_mesh_from_arrays(
    points: np.ndarray,
    offsets: np.ndarray,
    nodes: np.ndarray,
    *,
    where: str,
    block_id: Any = None,
    parent: Any = None,
    region: Any = None,
    region_names: Any = None,
    boundary_edges: Any = None,
    boundary_patch: Any = None,
    patch_names: Any = None,
    cell_level: Any = None,
    level: Any = 0,
    name: str = "",
    interface_edges: Any = None,
    interface_patch: Any = None,
    interface_names: Any = None,
) -> PolygonMesh:
    """A :class:`PolygonMesh` from a file's arrays, with the defaults of ``mesh_from_arrays``.

    Missing block ids are 0, parents -1, regions the one region ``"domain"``, cell levels the
    mesh's level; missing boundary edges are found from the cells (one patch ``"boundary"``);
    missing interfaces are none. Everything is checked (PolygonMesh's constructor, every
    interface edge an edge of two cells); a failure is an ExportError naming ``where``.
    """
    points = np.asarray(points)
    if points.ndim != 2 or points.shape[1] < 2 or points.dtype.kind not in "iuf":
        raise ExportError(f"{where}: the points have shape {points.shape}, expected (N, 2)")
    points = np.ascontiguousarray(points[:, :2], dtype=np.float64)
    check_points(points, where)
    offsets = _integers(offsets, "cell offsets", where)
    nodes = _integers(nodes, "cell nodes", where)
    m = offsets.size - 1
    if m < 0:
        raise ExportError(f"{where}: no cell offsets")
    level = _level(level, m, where, polygons=True)
    n = points.shape[0]
    if nodes.size and (nodes.min() < 0 or nodes.max() >= n):
        raise ExportError(
            f"{where}: cell node ids run from {nodes.min()} to {nodes.max()}, but there are "
            f"{n} points"
        )
    if region is None:
        region_names = region_names or ("domain",)
    region_arr = _column(region, m, "region", where)
    if region_arr is None:
        region_arr = np.zeros(m, dtype=np.int64)
    if region_names is None:
        region_names = tuple(f"region_{k}" for k in range(int(region_arr.max(initial=-1)) + 1))
    if boundary_edges is None:
        boundary_edges = boundary_of_cells(PolygonCells(offsets, nodes), n)
        boundary_patch = np.zeros(boundary_edges.shape[0], dtype=np.int64)
        patch_names = patch_names or ("boundary",)
    edges = np.asarray(boundary_edges, dtype=np.int64).reshape(-1, 2)
    patch = _column(boundary_patch, edges.shape[0], "boundary_patch", where)
    if patch is None:
        patch = np.zeros(edges.shape[0], dtype=np.int64)
    if patch_names is None:
        patch_names = tuple(f"patch_{k}" for k in range(int(patch.max(initial=-1)) + 1))
    levels = _column(cell_level, m, "cell_level", where)
    if levels is not None and levels.size and not 0 <= levels.min() <= levels.max() <= m:
        raise ExportError(
            f"{where}: the cell levels run from {levels.min()} to {levels.max()}: impossible for "
            f"{m:,} cells (0..{m:,})"
        )
    interfaces = interface_arrays(interface_edges, interface_patch, interface_names, n, where)
    try:
        return PolygonMesh(
            points=points,
            offsets=offsets,
            nodes=nodes,
            block_id=_default(_column(block_id, m, "block_id", where), np.zeros(m, np.int64)),
            parent=_default(_column(parent, m, "parent", where), np.full(m, -1, np.int64)),
            boundary_edges=edges,
            boundary_patch=patch,
            patch_names=tuple(str(p) for p in patch_names),
            region=region_arr,
            region_names=tuple(str(r) for r in region_names),
            cell_level=_default(levels, np.full(m, int(level), np.int64)),
            level=int(level),
            name=str(name),
            **interfaces,
        )
    except (BlockMeshError, TypeError, ValueError) as error:
        raise ExportError(f"{where} does not hold a valid mesh: {error}") from None


def _default(value: np.ndarray | None, fallback: np.ndarray) -> np.ndarray:
    return fallback if value is None else value


def as_written(mesh: Mesh | PolygonMesh) -> PolygonMesh:
    """A PolygonMesh to write (the formats' polygon paths take any mesh)."""
    return mesh if isinstance(mesh, PolygonMesh) else PolygonMesh.from_mesh(mesh)
