"""The all-pentagon mesh: a frozen dataclass of read-only arrays, and its measures.

A :class:`Mesh` is what :func:`blockmesh.refine` returns and what integration and the writers take.
Level 0 is the block mesh of a domain itself; every level splits each cell into six.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("sp").mesh(2)
>>> mesh.n_cells, mesh.n_points, mesh.level
(36, 65, 2)
>>> round(mesh.area, 12)
5.0
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .geometry import COLLINEAR_SIN_TOL, corner_sines, interior_angles, signed_area

__all__ = ["Mesh", "MeshQuality", "edge_keys", "unique_edges"]


def _frozen(a: Any, dtype: Any, shape_tail: tuple[int, ...] = ()) -> np.ndarray:
    arr = np.ascontiguousarray(a, dtype=dtype)
    if shape_tail and arr.shape[1:] != shape_tail:
        raise ValueError(f"expected shape (n, {', '.join(map(str, shape_tail))}), got {arr.shape}")
    if arr.flags.writeable:
        if arr.base is not None or arr is a:
            arr = arr.copy()
        arr.setflags(write=False)
    return arr


def edge_keys(a: np.ndarray, b: np.ndarray, n_points: int) -> np.ndarray:
    """One int64 per undirected edge: ``min * n_points + max``.

    Examples
    --------
    >>> edge_keys(np.array([3, 1]), np.array([1, 3]), 10).tolist()
    [13, 13]
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    return np.minimum(a, b) * n_points + np.maximum(a, b)


def unique_edges(cells: np.ndarray, n_points: int) -> np.ndarray:
    """Unique undirected edges (E, 2) of polygon cells, sorted by (min, max) node id.

    Examples
    --------
    >>> unique_edges(np.array([[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]]), 8).shape
    (9, 2)
    """
    keys = np.unique(edge_keys(cells, np.roll(cells, -1, axis=1), n_points).ravel())
    return np.stack(np.divmod(keys, n_points), axis=1)


@dataclass(frozen=True)
class MeshQuality:
    """Shape measures of a mesh's cells (angles in degrees).

    ``max_aspect_ratio`` is the largest diameter**2 / area over the cells (a regular pentagon has
    1.52); ``area_ratio`` is the smallest cell area over the largest.
    """

    min_angle: float
    max_angle: float
    max_aspect_ratio: float
    min_area: float
    max_area: float
    area_ratio: float
    not_strictly_convex: int

    def as_dict(self) -> dict[str, float | int]:
        """Plain dictionary (JSON-ready)."""
        return {
            "min_angle": self.min_angle,
            "max_angle": self.max_angle,
            "max_aspect_ratio": self.max_aspect_ratio,
            "min_area": self.min_area,
            "max_area": self.max_area,
            "area_ratio": self.area_ratio,
            "not_strictly_convex": self.not_strictly_convex,
        }


@dataclass(frozen=True, eq=False)
class Mesh:
    """A conforming all-pentagon mesh.

    Attributes
    ----------
    points : ndarray (N, 2) float64
        Node coordinates.
    cells : ndarray (M, 5) int64
        Node ids of each cell, counter-clockwise.
    block_id : ndarray (M,) int64
        The domain block each cell lies in.
    parent : ndarray (M,) int64
        The cell's parent at ``level - 1`` (-1 at level 0).
    boundary_edges : ndarray (Eb, 2) int64
        Boundary edges, oriented with the domain on their left.
    boundary_patch : ndarray (Eb,) int64
        Index into ``patch_names`` of each boundary edge.
    patch_names : tuple of str
    region : ndarray (M,) int64
        Index into ``region_names`` of each cell.
    region_names : tuple of str
    level : int
        Refinement level (0 = the block mesh).
    name : str
        Name of the domain the mesh was made from.
    """

    points: np.ndarray
    cells: np.ndarray
    block_id: np.ndarray
    parent: np.ndarray
    boundary_edges: np.ndarray
    boundary_patch: np.ndarray
    patch_names: tuple[str, ...]
    region: np.ndarray
    region_names: tuple[str, ...]
    level: int = 0
    name: str = ""
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "points", _frozen(self.points, np.float64, (2,)))
        set_(self, "cells", _frozen(self.cells, np.int64, (5,)))
        for name in ("block_id", "parent", "boundary_patch", "region"):
            set_(self, name, _frozen(getattr(self, name), np.int64))
        set_(self, "boundary_edges", _frozen(self.boundary_edges, np.int64, (2,)))
        set_(self, "patch_names", tuple(self.patch_names))
        set_(self, "region_names", tuple(self.region_names))

    @classmethod
    def from_cells(
        cls, points: np.ndarray, cells: np.ndarray, *, level: int = 0, name: str = ""
    ) -> Mesh:
        """A mesh from bare arrays: every cell its own block, one patch ``boundary``.

        The boundary edges are found from the cells (edges used by one cell), oriented as the
        cells run. The cells must be counter-clockwise pentagons meeting edge to edge; use
        :class:`blockmesh.Domain` to have that checked.

        Examples
        --------
        >>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0]], dtype=float)
        >>> mesh = Mesh.from_cells(sp, [[0, 1, 2, 3, 4]])
        >>> mesh.boundary_edges.tolist()
        [[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]]
        """
        points = np.asarray(points, dtype=np.float64)
        cells = np.asarray(cells, dtype=np.int64).reshape(-1, 5)
        nxt = np.roll(cells, -1, axis=1)
        keys = edge_keys(cells, nxt, points.shape[0]).ravel()
        _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
        on_boundary = counts[inverse] == 1
        boundary = np.stack([cells.ravel()[on_boundary], nxt.ravel()[on_boundary]], axis=1)
        n = cells.shape[0]
        return cls(
            points=points,
            cells=cells,
            block_id=np.arange(n),
            parent=np.full(n, -1),
            boundary_edges=boundary,
            boundary_patch=np.zeros(boundary.shape[0], dtype=np.int64),
            patch_names=("boundary",),
            region=np.zeros(n, dtype=np.int64),
            region_names=("domain",),
            level=level,
            name=name,
        )

    # ----------------------------------------------------------------- sizes
    @property
    def n_points(self) -> int:
        """Number of nodes N."""
        return int(self.points.shape[0])

    @property
    def n_cells(self) -> int:
        """Number of cells M."""
        return int(self.cells.shape[0])

    @property
    def n_edges(self) -> int:
        """Number of unique edges: (5 M + boundary edges) / 2, as every other edge has two cells."""
        return (5 * self.n_cells + int(self.boundary_edges.shape[0])) // 2

    def edges(self) -> np.ndarray:
        """Unique undirected edges (E, 2), cached. O(M log M)."""
        if "edges" not in self._cache:
            edges = unique_edges(self.cells, self.n_points)
            edges.setflags(write=False)
            self._cache["edges"] = edges
        return self._cache["edges"]

    def cell_coordinates(self) -> np.ndarray:
        """Corner coordinates of every cell, shape (M, 5, 2)."""
        return self.points[self.cells]

    def cell_areas(self) -> np.ndarray:
        """Area of every cell (positive for counter-clockwise cells), shape (M,)."""
        return signed_area(self.cell_coordinates())

    @property
    def area(self) -> float:
        """Total area of the mesh (sum of cell areas)."""
        return float(np.sum(self.cell_areas()))

    # --------------------------------------------------------------- quality
    def quality(self, *, chunk: int = 1 << 18) -> MeshQuality:
        """Angles, aspect ratios and areas of the cells, in chunks (bounded memory).

        Examples
        --------
        >>> import blockmesh
        >>> q = blockmesh.load_domain("sp").mesh(1).quality()
        >>> round(q.min_angle, 1), round(q.max_angle, 1), q.not_strictly_convex
        (56.3, 150.3, 0)
        """
        min_angle, max_angle, max_aspect = np.inf, -np.inf, 0.0
        min_area, max_area, bad = np.inf, -np.inf, 0
        for start in range(0, self.n_cells, chunk):
            xy = self.points[self.cells[start : start + chunk]]
            angles = interior_angles(xy)
            areas = signed_area(xy)
            diff = xy[:, :, None, :] - xy[:, None, :, :]
            diam2 = np.max(np.einsum("mijk,mijk->mij", diff, diff), axis=(1, 2))
            with np.errstate(divide="ignore", invalid="ignore"):
                aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
            sines = np.nan_to_num(corner_sines(xy), nan=-1.0)
            bad += int(np.count_nonzero(~np.all(sines > COLLINEAR_SIN_TOL, axis=1)))
            min_angle = min(min_angle, float(angles.min()))
            max_angle = max(max_angle, float(angles.max()))
            max_aspect = max(max_aspect, float(aspect.max()))
            min_area = min(min_area, float(areas.min()))
            max_area = max(max_area, float(areas.max()))
        ratio = min_area / max_area if max_area > 0 else 0.0
        return MeshQuality(min_angle, max_angle, max_aspect, min_area, max_area, ratio, bad)

    # ------------------------------------------------------------- numbering
    def bandwidth(self) -> int:
        """Largest difference between two node ids of one cell (the half-bandwidth of an FE matrix).

        Examples
        --------
        >>> import blockmesh
        >>> blockmesh.load_domain("sp").mesh(1).bandwidth()
        14
        """
        if self.n_cells == 0:
            return 0
        return int(np.max(self.cells.max(axis=1) - self.cells.min(axis=1)))

    def renumbered(self, order: np.ndarray) -> Mesh:
        """The same mesh with node ``order[k]`` renamed ``k`` (a permutation of ``0..N-1``).

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("sp").mesh(1)
        >>> again = mesh.renumbered(np.arange(mesh.n_points)[::-1])
        >>> bool(np.allclose(again.points[again.cells], mesh.points[mesh.cells]))
        True
        """
        order = np.asarray(order, dtype=np.int64)
        if order.shape != (self.n_points,) or not np.array_equal(
            np.sort(order), np.arange(self.n_points)
        ):
            raise ValueError("order must be a permutation of the node ids 0..N-1")
        new_id = np.empty_like(order)
        new_id[order] = np.arange(self.n_points)
        return replace(
            self,
            points=self.points[order],
            cells=new_id[self.cells],
            boundary_edges=new_id[self.boundary_edges],
            _cache={},
        )

    def with_rcm_numbering(self) -> Mesh:
        """Nodes renumbered by reverse Cuthill-McKee (scipy) on the cell connectivity graph.

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("square-cut").mesh(3)
        >>> mesh.with_rcm_numbering().bandwidth() < mesh.bandwidth()
        True
        """
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import reverse_cuthill_mckee

        rows = np.repeat(self.cells, 5, axis=1).ravel()
        cols = np.tile(self.cells, (1, 5)).ravel()
        graph = coo_matrix(
            (np.ones(rows.size, dtype=np.int8), (rows, cols)), shape=(self.n_points,) * 2
        ).tocsr()
        order = reverse_cuthill_mckee(graph, symmetric_mode=True)
        return self.renumbered(np.asarray(order, dtype=np.int64))

    # ------------------------------------------------------------ boundaries
    def patch_edges(self, patch: str) -> np.ndarray:
        """Boundary edges (E, 2) of the named patch.

        Examples
        --------
        >>> import blockmesh
        >>> blockmesh.load_domain("sp").mesh(2).patch_edges("boundary").shape
        (20, 2)
        """
        if patch not in self.patch_names:
            raise KeyError(f"no patch {patch!r}; the patches are {', '.join(self.patch_names)}")
        return self.boundary_edges[self.boundary_patch == self.patch_names.index(patch)]

    def nbytes(self) -> int:
        """Bytes held by the mesh's arrays."""
        arrays = (self.points, self.cells, self.block_id, self.parent, self.region)
        return (
            sum(a.nbytes for a in arrays) + self.boundary_edges.nbytes + self.boundary_patch.nbytes
        )
