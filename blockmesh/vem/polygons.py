"""Polygon meshes for the virtual element solver: cells of any size, grouped by vertex count.

A :class:`PolygonMesh` is what the solver works on. It holds the nodes, the cells split into
groups of equal vertex count (so that every group is one rectangular array and the element
matrices of a group are computed at once), and the boundary edges with their patches. A
blockmesh :class:`~blockmesh.mesh.Mesh` (all pentagons) becomes one with
:meth:`PolygonMesh.from_mesh`; triangle, quadrilateral or mixed meshes from elsewhere with
:meth:`PolygonMesh.from_cells`.

Every cell must run counter-clockwise and be star-shaped with respect to its vertex mean (every
triangle ``(vertex mean, corner i, corner i+1)`` has positive area): that is what the projections
and the quadrature need. Convex cells always are.

Examples
--------
>>> import numpy as np
>>> square = [(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5)]
>>> mesh = PolygonMesh.from_cells(square, [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
>>> mesh.n_cells, mesh.n_points, [g.size for g in mesh.groups]
(4, 5, [3])
>>> mesh.patch_names, mesh.boundary_edges.shape
(('boundary',), (4, 2))
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.checks import readonly
from blockmesh.errors import ArgumentError, ArgumentTypeError, TopologyError, UnknownNameError
from blockmesh.geometry.polygons import signed_area
from blockmesh.geometry.topology import boundary_of_cells, edge_keys
from blockmesh.mesh.mesh import Mesh

__all__ = ["CellGroup", "PolygonMesh"]


@dataclass(frozen=True, eq=False)
class CellGroup:
    """The cells of one vertex count.

    Attributes
    ----------
    size : int
        Vertices per cell, ``n``.
    cells : ndarray (M_n, n) int64
        Node ids, counter-clockwise.
    index : ndarray (M_n,) int64
        Position of every cell of the group in the mesh's cell order.
    """

    size: int
    cells: np.ndarray
    index: np.ndarray

    @property
    def n_cells(self) -> int:
        """Cells in the group."""
        return int(self.cells.shape[0])


@dataclass(frozen=True, eq=False)
class PolygonMesh:
    """A conforming mesh of counter-clockwise polygons with named boundary patches.

    Attributes
    ----------
    points : ndarray (N, 2) float64
    groups : tuple of CellGroup
        The cells, one group per vertex count (increasing).
    n_cells : int
        Cells in all groups.
    boundary_edges : ndarray (Eb, 2) int64
        Boundary edges, directed with the domain on their left.
    boundary_patch : ndarray (Eb,) int64
        Index into ``patch_names`` of every boundary edge.
    patch_names : tuple of str
    source : Mesh or None
        The blockmesh Mesh this was made from, if any.
    """

    points: np.ndarray
    groups: tuple[CellGroup, ...]
    n_cells: int
    boundary_edges: np.ndarray
    boundary_patch: np.ndarray
    patch_names: tuple[str, ...]
    source: Mesh | None = None

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_mesh(cls, mesh: Mesh) -> PolygonMesh:
        """The pentagons of a blockmesh Mesh, with its boundary edges and patches.

        Examples
        --------
        >>> import blockmesh
        >>> PolygonMesh.from_mesh(blockmesh.load_domain("square").mesh(1)).n_cells
        48
        """
        if not isinstance(mesh, Mesh):
            raise ArgumentTypeError(f"mesh must be a blockmesh Mesh, not {type(mesh).__name__}")
        group = CellGroup(5, mesh.cells, readonly(np.arange(mesh.n_cells)))
        return cls(
            points=mesh.points,
            groups=(group,),
            n_cells=mesh.n_cells,
            boundary_edges=mesh.boundary_edges,
            boundary_patch=mesh.boundary_patch,
            patch_names=mesh.patch_names,
            source=mesh,
        )

    @classmethod
    def from_cells(
        cls,
        points: Any,
        cells: Any,
        patches: Mapping[str, Any] | None = None,
    ) -> PolygonMesh:
        """A mesh from nodes and polygons of any sizes.

        Parameters
        ----------
        points : array_like (N, 2)
        cells : array_like (M, n) or sequence of sequences
            Node ids of every cell, counter-clockwise; cells may have different sizes (>= 3).
        patches : mapping of str to array_like (E, 2), optional
            Boundary edges (node pairs, either direction) of every named patch. Boundary edges no
            patch names go to the patch ``boundary``. Default: every boundary edge in
            ``boundary``.

        Raises
        ------
        ArgumentError
            On a bad index, a clockwise or not star-shaped cell, or a patch edge that is not on
            the boundary (or in two patches).
        TopologyError
            On an edge of three cells or a hanging node (cells not meeting edge to edge).

        Examples
        --------
        >>> pts = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]
        >>> mesh = PolygonMesh.from_cells(pts, [[0, 1, 4, 5], [1, 2, 3, 4]],
        ...                               patches={"left": [(5, 0)]})
        >>> mesh.patch_names, int((mesh.boundary_patch == 0).sum())
        (('left', 'boundary'), 1)
        """
        xy = np.array(points, dtype=np.float64)
        if xy.ndim != 2 or xy.shape[1] != 2:
            raise ArgumentError(f"points must have shape (N, 2), got {xy.shape}")
        if not np.all(np.isfinite(xy)):
            bad = int(np.flatnonzero(~np.all(np.isfinite(xy), axis=1))[0])
            raise ArgumentError(f"point {bad} {xy[bad].tolist()} is not finite")
        n_points = xy.shape[0]
        groups = []
        for index, group_cells in _cell_groups(cells):
            _check_cells(xy, group_cells, index, n_points)
            size = group_cells.shape[1]
            groups.append(CellGroup(size, readonly(group_cells), readonly(index)))
        n_cells = sum(g.n_cells for g in groups)
        edges = _boundary(groups, n_points)
        _check_edge_to_edge(xy, edges)
        patch, names = _assign_patches(edges, patches or {}, n_points)
        return cls(
            points=readonly(xy),
            groups=tuple(groups),
            n_cells=n_cells,
            boundary_edges=readonly(edges),
            boundary_patch=readonly(patch),
            patch_names=names,
        )

    # ------------------------------------------------------------------ queries
    @property
    def n_points(self) -> int:
        """Number of nodes N."""
        return int(self.points.shape[0])

    def patch_edges(self, patch: str) -> np.ndarray:
        """Boundary edges (E, 2) of the named patch (UnknownNameError listing the patches)."""
        return self.boundary_edges[self.boundary_patch == self.patch_index(patch)]

    def patch_index(self, patch: str) -> int:
        """Index of ``patch`` in ``patch_names``."""
        if patch not in self.patch_names:
            raise UnknownNameError(
                f"no patch {patch!r}; the patches are {', '.join(self.patch_names)}"
            )
        return self.patch_names.index(patch)

    def boundary_nodes(self) -> np.ndarray:
        """Sorted ids of the nodes on the boundary."""
        return np.unique(self.boundary_edges)

    def cell_sizes(self) -> np.ndarray:
        """Vertex count of every cell, in cell order (M,)."""
        sizes = np.empty(self.n_cells, dtype=np.int64)
        for group in self.groups:
            sizes[group.index] = group.size
        return sizes

    def __repr__(self) -> str:
        """A one-line summary."""
        sizes = ", ".join(f"{g.n_cells:,} with {g.size} vertices" for g in self.groups)
        return (
            f"PolygonMesh({self.n_points:,} points; cells: {sizes or 'none'}; patches "
            f"{', '.join(self.patch_names) or '-'})"
        )


def as_polygon_mesh(mesh: Mesh | PolygonMesh) -> PolygonMesh:
    """``mesh`` as a PolygonMesh (a blockmesh Mesh is adapted, a PolygonMesh returned as it is)."""
    if isinstance(mesh, PolygonMesh):
        return mesh
    if isinstance(mesh, Mesh):
        return PolygonMesh.from_mesh(mesh)
    raise ArgumentTypeError(
        f"mesh must be a blockmesh Mesh or a PolygonMesh, not {type(mesh).__name__}"
    )


# ---------------------------------------------------------------------- checks
def _cell_groups(cells: Any) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(index, cells)`` per vertex count, from an (M, n) array or a sequence of sequences."""
    if isinstance(cells, np.ndarray):
        if cells.dtype.kind not in "iu":
            raise ArgumentTypeError(f"cells must hold integer node ids, got {cells.dtype}")
        if cells.ndim != 2:
            raise ArgumentError(f"cells must have shape (M, n), got {cells.shape}")
        return [(np.arange(cells.shape[0]), cells.astype(np.int64))]
    try:
        rows: list[Sequence[int]] = [list(row) for row in cells]
    except TypeError:
        raise ArgumentTypeError("cells must be a sequence of node-id sequences") from None
    for k, row in enumerate(rows):
        if not all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in row):
            raise ArgumentTypeError(f"cell {k} {row!r} must hold integer node ids")
    sizes = np.array([len(row) for row in rows], dtype=np.int64)
    out = []
    for size in np.unique(sizes):
        index = np.flatnonzero(sizes == size)
        out.append((index, np.array([rows[i] for i in index], dtype=np.int64).reshape(-1, size)))
    return out


def _check_cells(xy: np.ndarray, cells: np.ndarray, index: np.ndarray, n_points: int) -> None:
    """Index range, size >= 3, distinct corners, star-shaped and counter-clockwise."""
    size = cells.shape[1]
    if size < 3:
        raise ArgumentError(f"cell {int(index[0])} has {size} vertices; a cell needs 3 or more")
    if cells.size and (cells.min() < 0 or cells.max() >= n_points):
        row = int(np.flatnonzero(np.any((cells < 0) | (cells >= n_points), axis=1))[0])
        raise ArgumentError(
            f"cell {int(index[row])} {cells[row].tolist()} has a node id outside 0..{n_points - 1}"
        )
    ordered = np.sort(cells, axis=1)
    repeated = np.any(ordered[:, 1:] == ordered[:, :-1], axis=1)
    if np.any(repeated):
        row = int(np.flatnonzero(repeated)[0])
        raise ArgumentError(f"cell {int(index[row])} {cells[row].tolist()} repeats a node")
    corners = xy[cells]
    centre = corners.mean(axis=1, keepdims=True)
    fan = np.stack([np.broadcast_to(centre, corners.shape), corners, np.roll(corners, -1, 1)], 2)
    areas = signed_area(fan)  # (M, n): the triangles (vertex mean, corner i, corner i + 1)
    scale = np.max(np.abs(corners - centre), axis=(1, 2)) ** 2
    bad = ~np.all(areas > 1e-14 * scale[:, None], axis=1)
    if np.any(bad):
        row = int(np.flatnonzero(bad)[0])
        clockwise = signed_area(corners[row]) <= 0
        why = (
            "is clockwise or has no area; cells run counter-clockwise"
            if clockwise
            else "is not star-shaped with respect to its vertex mean"
        )
        raise ArgumentError(f"cell {int(index[row])} (nodes {cells[row].tolist()}) {why}")


def _boundary(groups: list[CellGroup], n_points: int) -> np.ndarray:
    """Directed boundary edges of all groups; TopologyError on an edge of three or more cells."""
    starts = np.concatenate([g.cells.ravel() for g in groups])
    stops = np.concatenate([np.roll(g.cells, -1, axis=1).ravel() for g in groups])
    keys = edge_keys(starts, stops, n_points)
    _, counts = np.unique(keys, return_counts=True)
    if np.any(counts > 2):
        key = int(np.unique(keys)[np.flatnonzero(counts > 2)[0]])
        a, b = divmod(key, n_points)
        raise TopologyError(f"edge ({a}, {b}) belongs to three or more cells")
    if len(groups) == 1:
        return boundary_of_cells(groups[0].cells, n_points)
    once = np.isin(keys, np.unique(keys)[counts == 1])
    return np.stack([starts[once], stops[once]], axis=1)


def _check_edge_to_edge(points: np.ndarray, edges: np.ndarray) -> None:
    """TopologyError when cells do not meet edge to edge (a hanging node).

    A node in the middle of a neighbour's edge leaves that edge unmatched, so it shows up among
    the boundary edges with a boundary node inside it. The boundary nodes near every boundary
    edge are found with shapely's STRtree (O(Eb log Eb)).
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
            f"inside the edge ({a}, {b}) of a neighbouring cell (a hanging node); split that "
            "edge in both cells"
        )


def _assign_patches(
    edges: np.ndarray, patches: Mapping[str, Any], n_points: int
) -> tuple[np.ndarray, tuple[str, ...]]:
    if not isinstance(patches, Mapping):
        raise ArgumentTypeError("patches must map patch names to edge lists")
    keys = edge_keys(edges[:, 0], edges[:, 1], n_points)
    order = np.argsort(keys)
    sorted_keys = keys[order]
    patch = np.full(edges.shape[0], -1, dtype=np.int64)
    names = list(patches)
    for k, name in enumerate(names):
        if not isinstance(name, str) or not name:
            raise ArgumentTypeError(f"patch names must be non-empty strings, got {name!r}")
        pairs = np.asarray(patches[name], dtype=np.int64).reshape(-1, 2)
        wanted = edge_keys(pairs[:, 0], pairs[:, 1], n_points)
        at = np.minimum(np.searchsorted(sorted_keys, wanted), keys.size - 1)
        found = sorted_keys[at] == wanted
        if not np.all(found):
            a, b = pairs[int(np.flatnonzero(~found)[0])].tolist()
            raise ArgumentError(f"patch {name!r}: edge ({a}, {b}) is not a boundary edge")
        slots = order[at]
        if np.any(patch[slots] >= 0):
            a, b = edges[slots[np.flatnonzero(patch[slots] >= 0)[0]]].tolist()
            raise ArgumentError(f"patch {name!r}: edge ({a}, {b}) is already in another patch")
        patch[slots] = k
    if np.any(patch < 0):
        if "boundary" in names:
            raise ArgumentError(
                "some boundary edges are in no patch, and the patch for them, 'boundary', is "
                "already used: name every boundary edge or rename that patch"
            )
        patch[patch < 0] = len(names)
        names.append("boundary")
    return patch, tuple(names)
