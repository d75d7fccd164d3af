"""Meshes of polygon cells of any number of vertices: hanging nodes, local refinement, VEM.

A :class:`PolygonMesh` holds everything a :class:`~blockmesh.mesh.Mesh` holds (nodes, cells,
blocks, parents, patches, regions, interfaces, level, name, curves) for cells of 3 or more
vertices each. The cells are stored in compressed rows
(:class:`~blockmesh.geometry.topology.PolygonCells`: cell ``c`` is
``nodes[offsets[c]:offsets[c + 1]]``), and grouped by vertex count on demand
(:attr:`PolygonMesh.groups`) so that work on cells of one size is one rectangular array. The
class holds the arrays and the conversions to and from :class:`~blockmesh.mesh.Mesh`; its jobs
live in modules of their own: the checks (:mod:`~blockmesh.mesh.polygon_checks`), building from
bare polygons (:mod:`~blockmesh.mesh.polygon_build`), the geometry of the cells
(:mod:`~blockmesh.mesh.polygon_geometry`), and what it shares with a Mesh
(:mod:`~blockmesh.mesh.arrays`, :mod:`~blockmesh.mesh.labels`, :mod:`~blockmesh.mesh.numbering`).

Where it comes from: :func:`blockmesh.refine` with ``cells=`` (local refinement: a refined cell's
new edge nodes become extra vertices of its coarse neighbours, *hanging nodes*), the readers when
a file holds cells other than pentagons, :meth:`PolygonMesh.from_cells` (any polygons, e.g.
triangles for the virtual element solver) and :meth:`PolygonMesh.from_mesh`. An all-pentagon
:class:`~blockmesh.mesh.Mesh` converts both ways without loss (:meth:`PolygonMesh.to_mesh`).

Corners, straight vertices and convexity. Walking a cell's vertices counter-clockwise, a vertex
where the boundary turns left (the sine of the turn above
:data:`~blockmesh.geometry.COLLINEAR_SIN_TOL`) is a **corner**; one where it goes straight on
(sine within the tolerance, the edges continuing forwards) is a **straight vertex**, 180 degrees:
that is what a hanging node is. A vertex between two edges on the same curve of
:attr:`PolygonMesh.curves` (a node a finer neighbour put on the curve) is straight too, whatever
its turn. A cell is **convex** when every vertex is a corner or straight, it has at least three
corners, and its turns add up to one full turn; **strictly convex** when it is convex without
straight vertices. The run of edges from one corner to the next is the cell's **side** (the edge
of its geometric polygon); a side of ``k`` edges carries ``k - 1`` hanging nodes.

Examples
--------
>>> import blockmesh
>>> mesh = PolygonMesh.from_mesh(blockmesh.load_domain("sp").mesh(1))
>>> mesh.n_cells, mesh.n_points, mesh.cell_sizes().tolist()
(6, 15, [5, 5, 5, 5, 5, 5])
>>> mesh.to_mesh().n_cells
6
>>> pts = [(0, 0), (1, 0), (1, 0.5), (1, 1), (0, 1), (2, 0), (2, 0.5), (2, 1)]
>>> hanging = PolygonMesh.from_cells(pts, [[0, 1, 2, 3, 4], [1, 5, 6, 2], [2, 6, 7, 3]])
>>> hanging.hanging_nodes().tolist(), int(hanging.side_lengths().max())
([2], 2)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from blockmesh.checks import readonly
from blockmesh.curves.edges import CurvedEdges, area_corrections
from blockmesh.errors import ArgumentTypeError, DomainError
from blockmesh.geometry.topology import PolygonCells, unique_edges
from blockmesh.mesh import labels, numbering
from blockmesh.mesh import polygon_geometry as geometry
from blockmesh.mesh.arrays import (
    NO_EDGES,
    NO_IDS,
    check_finite,
    own_blocks,
    shared_values,
    trusted,
)
from blockmesh.mesh.common import MeshBase
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygon_build import polygon_layout
from blockmesh.mesh.polygon_checks import (
    check_polygon_arrays,
    check_polygon_cells,
    freeze_polygon_arrays,
)
from blockmesh.mesh.quality import MeshQuality

__all__ = ["CellGroup", "PolygonMesh", "as_polygon_mesh"]


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


@dataclass(frozen=True, eq=False, repr=False)
class PolygonMesh(MeshBase):
    """A conforming mesh of counter-clockwise polygons (hanging nodes are straight vertices).

    Attributes
    ----------
    points : ndarray (N, 2) float64
        Node coordinates.
    offsets : ndarray (M + 1,) int64
        Cell ``c`` is ``nodes[offsets[c]:offsets[c + 1]]`` (``offsets[0] = 0``).
    nodes : ndarray (S,) int64
        The node ids of all cells, each cell counter-clockwise, one cell after another.
    block_id : ndarray (M,) int64
        The domain block each cell lies in.
    parent : ndarray (M,) int64
        The cell of the mesh this one was refined from that the cell is, or lies in (-1 for a
        mesh that was not refined).
    boundary_edges : ndarray (Eb, 2) int64
        Boundary edges, oriented with the domain on their left.
    boundary_patch : ndarray (Eb,) int64
        Index into ``patch_names`` of each boundary edge.
    patch_names : tuple of str
    region : ndarray (M,) int64
        Index into ``region_names`` of each cell.
    region_names : tuple of str
    cell_level : ndarray (M,) int64
        How many times each cell's ancestors were split since the block mesh (its depth in the
        refinement tree; a Mesh at level L has L everywhere).
    level : int
        Refinement rounds applied since the block mesh.
    name : str
    curves : CurvedEdges or None
        The edges on curved block edges (see :class:`~blockmesh.mesh.Mesh`).
    interface_edges : ndarray (Ei, 2) int64
        Interior edges named as internal patches, where two regions of a composite domain meet
        (see :class:`~blockmesh.mesh.Mesh`): each an edge of two cells, the interface's first
        side on its left. An interface edge a finer neighbour split is two interface edges.
    interface_patch : ndarray (Ei,) int64
        Index into ``interface_names`` of each interface edge.
    interface_names : tuple of str
        Different from every patch name.

    The constructor checks: shapes and index ranges, cells of at least 3 distinct nodes, finite
    points, every cell counter-clockwise and star-shaped from its vertex mean (what the
    composite quadrature and the virtual elements need), boundary edges exactly the free cell
    edges, directed, no edge in three cells, and every interface edge an edge of two cells.
    Convexity is checked by :meth:`check_geometry` (the writers' final guard).
    """

    points: np.ndarray
    offsets: np.ndarray
    nodes: np.ndarray
    block_id: np.ndarray
    parent: np.ndarray
    boundary_edges: np.ndarray
    boundary_patch: np.ndarray
    patch_names: tuple[str, ...]
    region: np.ndarray
    region_names: tuple[str, ...]
    cell_level: np.ndarray
    level: int = 0
    name: str = ""
    curves: CurvedEdges | None = None
    interface_edges: np.ndarray = field(default_factory=lambda: NO_EDGES)
    interface_patch: np.ndarray = field(default_factory=lambda: NO_IDS)
    interface_names: tuple[str, ...] = ()
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    @classmethod
    def _trusted(cls, **values: Any) -> PolygonMesh:
        """A mesh from arrays consistent by construction (local refinement): cheap checks only."""
        mesh = trusted(cls, values)
        mesh._freeze()
        mesh._check_arrays()
        return mesh

    # ----------------------------------------------------------------- checks
    def _freeze(self) -> None:
        freeze_polygon_arrays(self)

    def _check_arrays(self) -> None:
        """Shapes, lengths, offsets and index ranges (O(S))."""
        check_polygon_arrays(self)

    def _check_cells(self) -> None:
        """Finite points, distinct nodes, CCW and star-shaped cells, the boundary edges."""
        check_polygon_cells(self)

    # ---------------------------------------------------------- construction
    @classmethod
    def from_mesh(cls, mesh: Mesh) -> PolygonMesh:
        """The all-pentagon ``mesh`` as a PolygonMesh, every array and name kept.

        Examples
        --------
        >>> import blockmesh
        >>> PolygonMesh.from_mesh(blockmesh.load_domain("square").mesh(1)).n_cells
        48
        """
        if not isinstance(mesh, Mesh):
            raise ArgumentTypeError(f"mesh must be a blockmesh Mesh, not {type(mesh).__name__}")
        m = mesh.n_cells
        out = cls._trusted(
            **shared_values(mesh),
            offsets=np.arange(m + 1, dtype=np.int64) * 5,
            nodes=mesh.cells.reshape(-1),
            cell_level=np.full(m, mesh.level, dtype=np.int64),
        )
        out._cache["mesh"] = mesh
        return out

    def to_mesh(self) -> Mesh:
        """The same mesh as an all-pentagon :class:`~blockmesh.mesh.Mesh` (lossless).

        Raises DomainError naming a cell that is not a pentagon. Every array, name, the level,
        the interfaces and the curves are kept (``cell_level`` is the level everywhere in a
        uniformly refined mesh; a Mesh has no per-cell level).

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("sp").mesh(2)
        >>> again = PolygonMesh.from_mesh(mesh).to_mesh()
        >>> bool(np.array_equal(again.cells, mesh.cells)), again.level
        (True, 2)
        """
        if "mesh" in self._cache:
            return self._cache["mesh"]
        sizes = self.cell_sizes()
        if np.any(sizes != 5):
            bad = int(np.flatnonzero(sizes != 5)[0])
            raise DomainError(
                f"cell {bad} has {int(sizes[bad])} vertices ({self.cell(bad).tolist()}); only a "
                f"mesh of pentagons becomes a Mesh ({int(np.count_nonzero(sizes != 5)):,} of the "
                f"{self.n_cells:,} cells are not pentagons); keep the PolygonMesh"
            )
        mesh = Mesh._trusted(**shared_values(self), cells=self.nodes.reshape(-1, 5))
        self._cache["mesh"] = mesh
        return mesh

    @classmethod
    def from_cells(
        cls,
        points: Any,
        cells: Any,
        patches: Mapping[str, Any] | None = None,
        *,
        level: int = 0,
        name: str = "",
    ) -> PolygonMesh:
        """A mesh from nodes and polygons of any sizes: each cell its own block.

        Parameters
        ----------
        points : array_like (N, 2)
        cells : array_like (M, n), sequence of sequences, or PolygonCells
            Node ids of every cell, counter-clockwise; cells may have different sizes (>= 3).
            A node inside a neighbour's edge must be a vertex of that neighbour too (then it is
            a straight vertex of it, a hanging node).
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
            On an edge of three cells, or a node lying inside a neighbour's edge that is not a
            vertex of that neighbour (cells not meeting edge to edge).

        Examples
        --------
        >>> pts = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]
        >>> mesh = PolygonMesh.from_cells(pts, [[0, 1, 4, 5], [1, 2, 3, 4]],
        ...                               patches={"left": [(5, 0)]})
        >>> mesh.patch_names, int((mesh.boundary_patch == 0).sum())
        (('left', 'boundary'), 1)
        """
        xy, rows, edges, patch, names = polygon_layout(points, cells, patches)
        m = rows.n_cells
        return cls(
            points=xy,
            offsets=rows.offsets,
            nodes=rows.nodes,
            boundary_edges=edges,
            boundary_patch=patch,
            patch_names=names,
            cell_level=np.full(m, level, dtype=np.int64),
            level=level,
            name=name,
            **own_blocks(m),
        )

    # ----------------------------------------------------------------- sizes
    @property
    def n_cells(self) -> int:
        """Number of cells M."""
        return int(self.offsets.shape[0]) - 1

    @property
    def n_edges(self) -> int:
        """Number of unique edges: (S + boundary edges) / 2."""
        return (int(self.nodes.size) + int(self.boundary_edges.shape[0])) // 2

    def polygon_cells(self) -> PolygonCells:
        """The cells as :class:`~blockmesh.geometry.topology.PolygonCells` (no copy)."""
        return PolygonCells(self.offsets, self.nodes)

    def cell_sizes(self) -> np.ndarray:
        """Vertex count of every cell, in cell order (M,)."""
        return np.diff(self.offsets)

    def cell(self, index: int) -> np.ndarray:
        """The node ids of cell ``index``, counter-clockwise."""
        return self.nodes[self.offsets[index] : self.offsets[index + 1]]

    def cell_lists(self) -> list[list[int]]:
        """The cells as lists of node ids (for small meshes and tests)."""
        return [self.cell(c).tolist() for c in range(self.n_cells)]

    @property
    def groups(self) -> tuple[CellGroup, ...]:
        """The cells grouped by vertex count (increasing), each group one (M_n, n) array."""
        if "groups" not in self._cache:
            sizes = self.cell_sizes()
            groups = []
            for size in np.unique(sizes).tolist():
                index = np.flatnonzero(sizes == size)
                cells = self.nodes[self.offsets[index][:, None] + np.arange(size)]
                groups.append(CellGroup(int(size), readonly(cells), readonly(index)))
            self._cache["groups"] = tuple(groups)
        return self._cache["groups"]

    def edges(self) -> np.ndarray:
        """Unique undirected edges (E, 2) as (lower id, higher id), sorted, cached."""
        if "edges" not in self._cache:
            edges = unique_edges(self.polygon_cells(), self.n_points)
            edges.setflags(write=False)
            self._cache["edges"] = edges
        return self._cache["edges"]

    def boundary_nodes(self) -> np.ndarray:
        """Sorted ids of the nodes on the boundary."""
        return np.unique(self.boundary_edges)

    # -------------------------------------------------------------- geometry
    # -------------------------------------------------------------- geometry
    def _slot_vectors(self) -> tuple[np.ndarray, np.ndarray]:
        """For every slot (vertex), the incoming and the outgoing edge vectors (S, 2) each."""
        return geometry.slot_vectors(self)

    def vertex_means(self) -> np.ndarray:
        """The mean of every cell's vertices (M, 2), hanging nodes included."""
        return geometry.vertex_means(self)

    def cell_areas(self) -> np.ndarray:
        """Area of every cell (positive for counter-clockwise cells), shape (M,).

        Measured relative to each cell's first vertex (areas do not depend on where the mesh
        lies).
        """
        return geometry.cell_areas(self)

    @property
    def area(self) -> float:
        """Total area of the mesh (sum of the cell areas)."""
        return math.fsum(self.cell_areas().tolist())

    def curved_cell_areas(self) -> np.ndarray:
        """Area of every cell bounded by its curved edges (see :meth:`Mesh.curved_cell_areas`)."""
        return self.cell_areas() + area_corrections(
            self.polygon_cells(), self.n_points, self.curves
        )

    def cell_diameters(self) -> np.ndarray:
        """Largest distance between two vertices of every cell (M,)."""
        return geometry.cell_diameters(self)

    # ------------------------------------------------------ corners and sides
    def _curve_continues(self) -> np.ndarray:
        """For every slot, whether its vertex sits between two edges on the same curve."""
        return geometry.curve_continues(self)

    def turn_sines(self) -> np.ndarray:
        """Sine of the turn at every vertex (S,), in slot order: > 0 left, 0 straight.

        NaN at a vertex with a zero-length edge.
        """
        return geometry.turn_sines(self)

    def straight_vertices(self) -> np.ndarray:
        """For every slot, whether its vertex is straight in its cell (180 degrees), (S,) bool.

        Straight: the edges continue forwards and the turn's sine is within
        :data:`~blockmesh.geometry.COLLINEAR_SIN_TOL` or the vertex is within 16 coordinate
        spacings of the chord of its neighbours (a rounded midpoint); or both edges lie on the
        same curve. Hanging nodes are straight
        vertices of the coarser cell.
        """
        return geometry.straight_vertices(self)

    def corner_counts(self) -> np.ndarray:
        """Corners of every cell (M,): its vertices that are not straight."""
        return geometry.corner_counts(self)

    def sides(self) -> tuple[np.ndarray, np.ndarray]:
        """The side (corner to corner run of edges) of every slot, and each side's edge count.

        Returns ``(side (S,), length (K,))``: slot ``s`` lies on side ``side[s]``, numbered cell
        by cell; a side of length ``k`` carries ``k - 1`` straight vertices (hanging nodes).
        Raises DomainError naming a cell without three corners.
        """
        return geometry.sides(self)

    def side_lengths(self) -> np.ndarray:
        """Edges per side of every slot's side (S,): 1 plus the hanging nodes on that side."""
        side, length = self.sides()
        return length[side]

    def hanging_nodes(self) -> np.ndarray:
        """Sorted ids of the nodes that are a straight vertex of some cell (hanging nodes)."""
        return np.unique(self.nodes[self.straight_vertices()])

    # --------------------------------------------------------------- quality
    def quality(self, **_: Any) -> MeshQuality:
        """Angles (at the corners; straight vertices are not corners), aspect ratios and areas.

        ``not_strictly_convex`` counts the cells that are not convex in the sense of the module
        notes (straight vertices are allowed).

        Examples
        --------
        >>> import blockmesh
        >>> q = PolygonMesh.from_mesh(blockmesh.load_domain("sp").mesh(1)).quality()
        >>> round(q.min_angle, 1), round(q.max_angle, 1), q.not_strictly_convex
        (56.3, 150.3, 0)
        """
        return MeshQuality.from_measures(geometry.measure(self))

    def check_geometry(self) -> None:
        """Raise DomainError unless every cell is convex and counter-clockwise.

        Convex as the module notes define it: every vertex a left-turning corner or straight
        (a hanging node), at least three corners, one full turn.

        Examples
        --------
        >>> import blockmesh
        >>> PolygonMesh.from_mesh(blockmesh.load_domain("sp").mesh(2)).check_geometry()
        """
        check_finite(self.points, DomainError)
        invalid = geometry.measure(self)["invalid"]
        if invalid.size:
            first = int(invalid[0])
            corners = self.points[self.cell(first)]
            raise DomainError(
                f"{invalid.size:,} of the {self.n_cells:,} cells are not convex and "
                f"counter-clockwise, the first being cell {first} with vertices "
                f"{', '.join(f'({x:.17g}, {y:.17g})' for x, y in corners)}; the mesh is broken"
            )

    def bandwidth(self) -> int:
        """Largest difference between two node ids of one cell."""
        return numbering.polygon_bandwidth(self.polygon_cells())

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """A fan of triangles from vertex 0 of every cell: ``(triangles (T, 3), cell (T,))``.

        Each cell of n vertices gives n - 2 triangles, counter-clockwise (convex cells only
        make valid fans; a straight vertex 0 gives a triangle of no area, which the pictures and
        the formats that need triangles tolerate).
        """
        return geometry.triangles(self)

    # ------------------------------------------------------------ boundaries
    def patch_index(self, patch: str) -> int:
        """Index of ``patch`` in ``patch_names`` (UnknownNameError listing the patches)."""
        return labels.patch_index(self, patch)

    def interface_cells(self) -> np.ndarray:
        """The two cells of every interface edge, (Ei, 2): the one on its left, then its right.

        Raises ArgumentError naming the first interface edge that is not an edge of two cells.
        O(S log S), cached.
        """
        return labels.interface_cells(self, self.polygon_cells())

    # ------------------------------------------------------------------ copies
    def renumbered(self, order: np.ndarray) -> PolygonMesh:
        """The same mesh with node ``order[k]`` renamed ``k`` (a permutation of ``0..N-1``)."""
        return numbering.renumbered(self, order, "nodes")

    def nbytes(self) -> int:
        """Bytes held by the mesh's arrays."""
        arrays = (
            self.points,
            self.offsets,
            self.nodes,
            self.block_id,
            self.parent,
            self.region,
            self.cell_level,
            self.boundary_edges,
            self.boundary_patch,
            self.interface_edges,
            self.interface_patch,
        )
        return sum(a.nbytes for a in arrays)

    def __repr__(self) -> str:
        """A one-line summary (the arrays are not printed)."""
        sizes = np.bincount(self.cell_sizes()) if self.n_cells else np.zeros(0, dtype=np.int64)
        counts = ", ".join(f"{int(c):,} with {k}" for k, c in enumerate(sizes) if c)
        name = f"{self.name!r}, " if self.name else ""
        return (
            f"PolygonMesh({name}level {self.level}: {self.n_cells:,} cells ({counts or 'none'} "
            f"vertices), {self.n_points:,} points; {labels.labels_text(self)})"
        )


def as_polygon_mesh(mesh: Mesh | PolygonMesh) -> PolygonMesh:
    """``mesh`` as a PolygonMesh (a Mesh is converted, a PolygonMesh returned as it is)."""
    if isinstance(mesh, PolygonMesh):
        return mesh
    if isinstance(mesh, Mesh):
        return PolygonMesh.from_mesh(mesh)
    raise ArgumentTypeError(
        f"mesh must be a blockmesh Mesh or a PolygonMesh, not {type(mesh).__name__}"
    )
