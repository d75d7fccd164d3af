"""Meshes of polygon cells of any number of vertices: hanging nodes, local refinement, VEM.

A :class:`PolygonMesh` holds everything a :class:`~blockmesh.mesh.Mesh` holds (nodes, cells,
blocks, parents, patches, regions, interfaces, level, name, curves) for cells of 3 or more
vertices each. The cells are stored in compressed rows
(:class:`~blockmesh.geometry.topology.PolygonCells`: cell ``c`` is
``nodes[offsets[c]:offsets[c + 1]]``), and grouped by vertex count on demand
(:attr:`PolygonMesh.groups`) so that work on cells of one size is one rectangular array.

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
from collections.abc import Mapping, Sequence
from dataclasses import MISSING, dataclass, field, fields
from types import MappingProxyType
from typing import Any

import numpy as np

from blockmesh.checks import readonly
from blockmesh.curves.edges import CurvedEdges, area_corrections, curved_slots
from blockmesh.errors import (
    ArgumentError,
    ArgumentTypeError,
    DomainError,
    TopologyError,
    UnknownNameError,
)
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL
from blockmesh.geometry.topology import (
    PolygonCells,
    boundary_of_cells,
    check_boundary,
    edge_keys,
    unique_edges,
)
from blockmesh.mesh.mesh import Mesh, MeshQuality, _edge_cells

__all__ = ["CellGroup", "PolygonMesh", "as_polygon_mesh"]

#: The interfaces of a mesh that has none.
_NO_EDGES = np.zeros((0, 2), dtype=np.int64)
_NO_EDGES.setflags(write=False)
_NO_IDS = np.zeros(0, dtype=np.int64)
_NO_IDS.setflags(write=False)

#: A vertex within this many coordinate spacings (ulps) of the chord of its two neighbours is
#: straight whatever its sine: midpoints are rounded to the spacing.
_STRAIGHT_ULPS = 16

#: Relative size (against the squared size of the cell) below which a fan triangle from the
#: vertex mean counts as having no area: such a cell is not star-shaped from its vertex mean.
_STAR_TOL = 1e-14


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


def _int_array(values: Any, what: str) -> np.ndarray:
    if isinstance(values, np.ndarray) and values.dtype.kind == "f":
        raise ArgumentTypeError(f"PolygonMesh {what} must be integers, got {values.dtype}")
    try:
        array = np.asarray(values, dtype=np.int64)
    except (TypeError, ValueError) as error:
        raise ArgumentTypeError(f"PolygonMesh {what} cannot be read as int64: {error}") from None
    return array


def _frozen(array: np.ndarray, original: Any) -> np.ndarray:
    array = np.ascontiguousarray(array)
    if array.flags.writeable:
        if array.base is not None or array is original:
            array = array.copy()
        array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False, repr=False)
class PolygonMesh:
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
    interface_edges: np.ndarray = field(default_factory=lambda: _NO_EDGES)
    interface_patch: np.ndarray = field(default_factory=lambda: _NO_IDS)
    interface_names: tuple[str, ...] = ()
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._freeze()
        self._check_arrays()
        self._check_cells()

    @classmethod
    def _trusted(cls, **values: Any) -> PolygonMesh:
        """A mesh from arrays consistent by construction (local refinement): cheap checks only."""
        mesh = object.__new__(cls)
        for f in fields(cls):
            if f.name in values:
                value = values[f.name]
            elif f.default_factory is not MISSING:
                value = f.default_factory()
            else:
                value = f.default
            object.__setattr__(mesh, f.name, value)
        mesh._freeze()
        mesh._check_arrays()
        return mesh

    # ----------------------------------------------------------------- checks
    def _freeze(self) -> None:
        set_ = object.__setattr__
        try:
            points = np.asarray(self.points, dtype=np.float64)
        except (TypeError, ValueError) as error:
            raise ArgumentTypeError(
                f"PolygonMesh points cannot be read as float64: {error}"
            ) from None
        if points.ndim != 2 or points.shape[1] != 2:
            raise ArgumentError(f"PolygonMesh points must have shape (n, 2), got {points.shape}")
        set_(self, "points", _frozen(points, self.points))
        for name, tail in (
            ("offsets", ()),
            ("nodes", ()),
            ("block_id", ()),
            ("parent", ()),
            ("boundary_patch", ()),
            ("region", ()),
            ("cell_level", ()),
            ("interface_patch", ()),
            ("boundary_edges", (2,)),
            ("interface_edges", (2,)),
        ):
            original = getattr(self, name)
            array = _int_array(original, name)
            if name in ("boundary_edges", "interface_edges"):
                array = array.reshape(-1, 2) if array.size == 0 else array
            if array.ndim != 1 + len(tail) or array.shape[1:] != tail:
                shape = "(n" + "".join(f", {t}" for t in tail) + ")"
                raise ArgumentError(
                    f"PolygonMesh {name} must have shape {shape}, got {array.shape}"
                )
            set_(self, name, _frozen(array, original))
        for name in ("patch_names", "region_names", "interface_names"):
            names = getattr(self, name)
            if isinstance(names, str) or not all(isinstance(n, str) for n in names):
                raise ArgumentTypeError(
                    f"PolygonMesh {name} must be a sequence of strings, got {names!r}"
                )
            if len(set(names)) != len(names):
                raise ArgumentError(f"PolygonMesh {name} must be different names, got {names!r}")
            set_(self, name, tuple(names))
        clash = sorted(set(self.interface_names) & set(self.patch_names))
        if clash:
            raise ArgumentError(
                f"PolygonMesh interface {clash[0]!r} has the name of a boundary patch; an "
                "interface is an internal patch and needs a name of its own"
            )
        if isinstance(self.level, bool) or not isinstance(self.level, int | np.integer):
            raise ArgumentTypeError(f"PolygonMesh level must be a whole number, got {self.level!r}")
        set_(self, "level", int(self.level))
        if not isinstance(self.name, str):
            raise ArgumentTypeError(f"PolygonMesh name must be a string, got {self.name!r}")
        if self.curves is not None and not isinstance(self.curves, CurvedEdges):
            raise ArgumentTypeError(
                "PolygonMesh curves must be a blockmesh.curves.CurvedEdges or None, got "
                f"{self.curves!r}"
            )

    def _check_arrays(self) -> None:
        """Shapes, lengths, offsets and index ranges (O(S))."""
        offsets, m = self.offsets, self.n_cells
        if offsets.size == 0 or offsets[0] != 0 or offsets[-1] != self.nodes.size:
            raise ArgumentError(
                f"PolygonMesh offsets must run from 0 to the number of nodes listed "
                f"({self.nodes.size}), got {offsets[:1].tolist()}..{offsets[-1:].tolist()}"
            )
        sizes = np.diff(offsets)
        if np.any(sizes < 3):
            small = int(np.flatnonzero(sizes < 3)[0])
            raise ArgumentError(
                f"cell {small} has {int(sizes[small])} vertices; a cell needs 3 or more"
            )
        for name in ("block_id", "parent", "region", "cell_level"):
            length = getattr(self, name).shape[0]
            if length != m:
                raise ArgumentError(f"PolygonMesh {name} has {length} entries for {m} cells")
        eb = int(self.boundary_edges.shape[0])
        if self.boundary_patch.shape[0] != eb:
            raise ArgumentError(
                f"PolygonMesh boundary_patch has {self.boundary_patch.shape[0]} entries for {eb} "
                "boundary edges"
            )
        ei = int(self.interface_edges.shape[0])
        if self.interface_patch.shape[0] != ei:
            raise ArgumentError(
                f"PolygonMesh interface_patch has {self.interface_patch.shape[0]} entries for "
                f"{ei} interface edges"
            )
        n = self.n_points
        for values, what, low, high in (
            (self.nodes, "cell node", 0, n),
            (self.boundary_edges, "boundary edge node", 0, n),
            (self.block_id, "block_id", 0, None),
            (self.parent, "parent", -1, None),
            (self.cell_level, "cell_level", 0, None),
            (self.boundary_patch, "boundary_patch", 0, len(self.patch_names)),
            (self.region, "region", 0, len(self.region_names)),
            (self.interface_edges, "interface edge node", 0, n),
            (self.interface_patch, "interface_patch", 0, len(self.interface_names)),
        ):
            if values.size == 0:
                continue
            bad: np.ndarray = values < low
            if high is not None:
                bad |= values >= high
            if np.any(bad):
                at = int(np.flatnonzero(bad.ravel())[0])
                valid = f"{low}.." if high is None else f"{low}..{high - 1}"
                raise ArgumentError(
                    f"{what} {values.ravel()[at]} (entry {at}) is out of range (valid: {valid})"
                )
        if self.curves is not None and len(self.curves) and int(self.curves.edges.max()) >= n:
            raise ArgumentError(f"a curved edge names a node >= {n}, the number of points")

    def _check_cells(self) -> None:
        """Finite points, distinct nodes, CCW and star-shaped cells, the boundary edges."""
        if not np.all(np.isfinite(self.points)):
            bad = int(np.flatnonzero(~np.all(np.isfinite(self.points), axis=1))[0])
            raise ArgumentError(f"point {bad} {self.points[bad].tolist()} is not finite")
        cells = self.polygon_cells()
        owner = cells.slot_cell()
        order = np.lexsort((self.nodes, owner))
        repeated = (self.nodes[order][1:] == self.nodes[order][:-1]) & (
            owner[order][1:] == owner[order][:-1]
        )
        if np.any(repeated):
            cell = int(owner[order][1:][repeated][0])
            raise ArgumentError(f"cell {cell} {self.cell(cell).tolist()} repeats a node")
        fan = self._fan_areas()
        scale = self._cell_scale()
        bad = ~(fan > _STAR_TOL * scale[owner])
        if np.any(bad):
            cell = int(owner[np.flatnonzero(bad)[0]])
            clockwise = not self.cell_areas()[cell] > 0
            why = (
                "is clockwise or has no area; cells run counter-clockwise"
                if clockwise
                else "is not star-shaped with respect to its vertex mean"
            )
            raise ArgumentError(f"cell {cell} (nodes {self.cell(cell).tolist()}) {why}")
        check_boundary(cells, self.boundary_edges, self.n_points)
        if self.interface_edges.shape[0]:
            self.interface_cells()

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
            points=mesh.points,
            offsets=np.arange(m + 1, dtype=np.int64) * 5,
            nodes=mesh.cells.reshape(-1),
            block_id=mesh.block_id,
            parent=mesh.parent,
            boundary_edges=mesh.boundary_edges,
            boundary_patch=mesh.boundary_patch,
            patch_names=mesh.patch_names,
            region=mesh.region,
            region_names=mesh.region_names,
            cell_level=np.full(m, mesh.level, dtype=np.int64),
            level=mesh.level,
            name=mesh.name,
            curves=mesh.curves,
            interface_edges=mesh.interface_edges,
            interface_patch=mesh.interface_patch,
            interface_names=mesh.interface_names,
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
        mesh = Mesh._trusted(
            points=self.points,
            cells=self.nodes.reshape(-1, 5),
            block_id=self.block_id,
            parent=self.parent,
            boundary_edges=self.boundary_edges,
            boundary_patch=self.boundary_patch,
            patch_names=self.patch_names,
            region=self.region,
            region_names=self.region_names,
            level=self.level,
            name=self.name,
            curves=self.curves,
            interface_edges=self.interface_edges,
            interface_patch=self.interface_patch,
            interface_names=self.interface_names,
        )
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
        xy = np.array(points, dtype=np.float64)
        if xy.ndim != 2 or xy.shape[1] != 2:
            raise ArgumentError(f"points must have shape (N, 2), got {xy.shape}")
        if not np.all(np.isfinite(xy)):
            bad = int(np.flatnonzero(~np.all(np.isfinite(xy), axis=1))[0])
            raise ArgumentError(f"point {bad} {xy[bad].tolist()} is not finite")
        rows = _as_polygon_cells(cells)
        n_points = xy.shape[0]
        if rows.nodes.size and (rows.nodes.min() < 0 or rows.nodes.max() >= n_points):
            slot = int(np.flatnonzero((rows.nodes < 0) | (rows.nodes >= n_points))[0])
            cell = int(np.searchsorted(rows.offsets, slot, side="right") - 1)
            cell_nodes = rows.nodes[rows.offsets[cell] : rows.offsets[cell + 1]].tolist()
            raise ArgumentError(f"cell {cell} {cell_nodes} has a node id outside 0..{n_points - 1}")
        sizes = np.diff(rows.offsets)
        if np.any(sizes < 3):
            bad = int(np.flatnonzero(sizes < 3)[0])
            raise ArgumentError(
                f"cell {bad} has {int(sizes[bad])} vertices; a cell needs 3 or more"
            )
        edges = _boundary(rows, n_points)
        _check_edge_to_edge(xy, edges)
        patch, names = _assign_patches(edges, patches or {}, n_points)
        m = rows.n_cells
        return cls(
            points=xy,
            offsets=rows.offsets,
            nodes=rows.nodes,
            block_id=np.arange(m, dtype=np.int64),
            parent=np.full(m, -1, dtype=np.int64),
            boundary_edges=edges,
            boundary_patch=patch,
            patch_names=names,
            region=np.zeros(m, dtype=np.int64),
            region_names=("domain",),
            cell_level=np.full(m, level, dtype=np.int64),
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
    def _slot_vectors(self) -> tuple[np.ndarray, np.ndarray]:
        """For every slot (vertex), the incoming and the outgoing edge vectors (S, 2) each."""
        cells = self.polygon_cells()
        here = self.points[self.nodes]
        after = self.points[cells.following()]
        before = self.points[self.nodes[cells.previous_slot()]]
        return here - before, after - here

    def _fan_areas(self) -> np.ndarray:
        """Areas of the triangles (vertex mean, vertex s, next vertex) of every slot (S,)."""
        cells = self.polygon_cells()
        owner = cells.slot_cell()
        centre = self.vertex_means()[owner]
        a = self.points[self.nodes] - centre
        b = self.points[cells.following()] - centre
        return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])

    def _cell_scale(self) -> np.ndarray:
        """The squared largest distance of a cell's vertex from its vertex mean (M,)."""
        owner = self.polygon_cells().slot_cell()
        offset = self.points[self.nodes] - self.vertex_means()[owner]
        reach = np.max(np.abs(offset), axis=1) ** 2
        out = np.zeros(self.n_cells)
        np.maximum.at(out, owner, reach)
        return out

    def vertex_means(self) -> np.ndarray:
        """The mean of every cell's vertices (M, 2), hanging nodes included."""
        owner = self.polygon_cells().slot_cell()
        sizes = self.cell_sizes()
        xy = self.points[self.nodes]
        return np.stack(
            [np.bincount(owner, xy[:, k], minlength=self.n_cells) / sizes for k in range(2)],
            axis=1,
        )

    def cell_areas(self) -> np.ndarray:
        """Area of every cell (positive for counter-clockwise cells), shape (M,).

        Measured relative to each cell's first vertex (areas do not depend on where the mesh
        lies).
        """
        cells = self.polygon_cells()
        owner = cells.slot_cell()
        first = self.points[self.nodes[self.offsets[:-1]]][owner]
        a = self.points[self.nodes] - first
        b = self.points[cells.following()] - first
        twice = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        return 0.5 * np.bincount(owner, twice, minlength=self.n_cells)

    @property
    def area(self) -> float:
        """Total area of the mesh (sum of the cell areas)."""
        return math.fsum(self.cell_areas().tolist())

    def curved_cell_areas(self) -> np.ndarray:
        """Area of every cell bounded by its curved edges (see :meth:`Mesh.curved_cell_areas`)."""
        return self.cell_areas() + area_corrections(
            self.polygon_cells(), self.n_points, self.curves
        )

    @property
    def curved_area(self) -> float:
        """Total area of the mesh bounded by its curved edges."""
        return float(np.sum(self.curved_cell_areas()))

    def cell_diameters(self) -> np.ndarray:
        """Largest distance between two vertices of every cell (M,)."""
        out = np.empty(self.n_cells)
        for group in self.groups:
            xy = self.points[group.cells]
            diff = xy[:, :, None, :] - xy[:, None, :, :]
            out[group.index] = np.sqrt(np.max(np.sum(diff * diff, axis=-1), axis=(1, 2)))
        return out

    # ------------------------------------------------------ corners and sides
    def _curve_continues(self) -> np.ndarray:
        """For every slot, whether its vertex sits between two edges on the same curve."""
        if self.curves is None or len(self.curves) == 0:
            return np.zeros(self.nodes.size, dtype=bool)
        if "curve_continues" not in self._cache:
            cells = self.polygon_cells()
            row, _ = curved_slots(cells, self.n_points, self.curves)
            previous = row[cells.previous_slot()]
            same = (row >= 0) & (previous >= 0)
            same &= (
                self.curves.curve[np.maximum(row, 0)] == self.curves.curve[np.maximum(previous, 0)]
            )
            self._cache["curve_continues"] = same
        return self._cache["curve_continues"]

    def turn_sines(self) -> np.ndarray:
        """Sine of the turn at every vertex (S,), in slot order: > 0 left, 0 straight.

        NaN at a vertex with a zero-length edge.
        """
        incoming, outgoing = self._slot_vectors()
        cross = incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0]
        norms = np.hypot(*incoming.T) * np.hypot(*outgoing.T)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(norms > 0, cross / np.where(norms > 0, norms, 1.0), np.nan)

    def straight_vertices(self) -> np.ndarray:
        """For every slot, whether its vertex is straight in its cell (180 degrees), (S,) bool.

        Straight: the edges continue forwards and the turn's sine is within
        :data:`~blockmesh.geometry.COLLINEAR_SIN_TOL` or the vertex is within 16 coordinate
        spacings of the chord of its neighbours (a rounded midpoint); or both edges lie on the
        same curve. Hanging nodes are straight
        vertices of the coarser cell.
        """
        if "straight" not in self._cache:
            incoming, outgoing = self._slot_vectors()
            sines = self.turn_sines()
            forward = np.einsum("sd,sd->s", incoming, outgoing) > 0
            straight = (np.abs(np.nan_to_num(sines, nan=1.0)) <= COLLINEAR_SIN_TOL) & forward
            # A midpoint is rounded to the coordinates' spacing: far from the origin a node
            # halving a short edge can be that far off the chord. Within a few spacings of it
            # the vertex is straight.
            cross = np.abs(incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0])
            chord = np.hypot(*(incoming + outgoing).T)
            reach = np.max(np.abs(self.points[self.nodes]), axis=1)
            off = np.divide(cross, chord, out=np.full_like(cross, np.inf), where=chord > 0)
            straight |= forward & (off <= _STRAIGHT_ULPS * np.spacing(reach))
            straight |= self._curve_continues()
            straight.setflags(write=False)
            self._cache["straight"] = straight
        return self._cache["straight"]

    def corner_counts(self) -> np.ndarray:
        """Corners of every cell (M,): its vertices that are not straight."""
        owner = self.polygon_cells().slot_cell()
        return np.bincount(owner, ~self.straight_vertices(), minlength=self.n_cells).astype(
            np.int64
        )

    def sides(self) -> tuple[np.ndarray, np.ndarray]:
        """The side (corner to corner run of edges) of every slot, and each side's edge count.

        Returns ``(side (S,), length (K,))``: slot ``s`` lies on side ``side[s]``, numbered cell
        by cell; a side of length ``k`` carries ``k - 1`` straight vertices (hanging nodes).
        Raises DomainError naming a cell without three corners.
        """
        if "sides" not in self._cache:
            corner = ~self.straight_vertices()
            counts = self.corner_counts()
            if np.any(counts < 3):
                bad = int(np.flatnonzero(counts < 3)[0])
                raise DomainError(
                    f"cell {bad} (nodes {self.cell(bad).tolist()}) has {int(counts[bad])} "
                    "corners; a cell needs three or more vertices where its boundary turns"
                )
            cells = self.polygon_cells()
            owner = cells.slot_cell()
            running = np.cumsum(corner)  # corners up to and including each slot
            before = np.concatenate([[0], running])[self.offsets[:-1]]  # corners of earlier cells
            last = running[self.offsets[1:] - 1] - 1  # the last side of every cell
            side = running - 1
            wraps = (running - before[owner]) == 0  # slots before the cell's first corner
            side[wraps] = last[owner[wraps]]
            length = np.bincount(side, minlength=int(running[-1]) if running.size else 0)
            side.setflags(write=False)
            length.setflags(write=False)
            self._cache["sides"] = (side, length)
        return self._cache["sides"]

    def side_lengths(self) -> np.ndarray:
        """Edges per side of every slot's side (S,): 1 plus the hanging nodes on that side."""
        side, length = self.sides()
        return length[side]

    def hanging_nodes(self) -> np.ndarray:
        """Sorted ids of the nodes that are a straight vertex of some cell (hanging nodes)."""
        return np.unique(self.nodes[self.straight_vertices()])

    # --------------------------------------------------------------- quality
    def _measure(self) -> dict[str, Any]:
        """Corner angles, areas, aspect and convexity of all cells, once (cached)."""
        if "measures" in self._cache:
            return self._cache["measures"]
        sines = self.turn_sines()
        straight = self.straight_vertices()
        incoming, outgoing = self._slot_vectors()
        cross = incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0]
        dot = np.einsum("sd,sd->s", incoming, outgoing)
        angles = 180.0 - np.degrees(np.arctan2(cross, dot))
        corner = ~straight
        left = np.nan_to_num(sines, nan=-1.0) > COLLINEAR_SIN_TOL
        owner = self.polygon_cells().slot_cell()
        bad_vertex = ~(left | straight)
        bad = np.bincount(owner, bad_vertex, minlength=self.n_cells) > 0
        corners = np.bincount(owner, corner, minlength=self.n_cells)
        turning = np.bincount(
            owner, np.where(straight, 0.0, 180.0 - angles), minlength=self.n_cells
        )
        bad |= corners < 3
        bad |= ~np.isclose(turning, 360.0, atol=1e-6)
        areas = self.cell_areas()
        bad |= ~(areas > 0)
        diam2 = self.cell_diameters() ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
        corner_angles = angles[corner]
        result = {
            "area": math.fsum(areas.tolist()),
            "min_area": float(areas.min()) if areas.size else math.nan,
            "max_area": float(areas.max()) if areas.size else math.nan,
            "min_angle": float(corner_angles.min()) if corner_angles.size else math.nan,
            "max_angle": float(corner_angles.max()) if corner_angles.size else math.nan,
            "max_aspect": float(aspect.max()) if aspect.size else math.nan,
            "not_strictly_convex": int(np.count_nonzero(bad)),
            "invalid": np.flatnonzero(bad),
        }
        self._cache["measures"] = result
        return result

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
        m = self._measure()
        ratio = m["min_area"] / m["max_area"] if m["max_area"] > 0 else 0.0
        return MeshQuality(
            m["min_angle"],
            m["max_angle"],
            m["max_aspect"],
            m["min_area"],
            m["max_area"],
            ratio,
            m["not_strictly_convex"],
        )

    def check_geometry(self) -> None:
        """Raise DomainError unless every cell is convex and counter-clockwise.

        Convex as the module notes define it: every vertex a left-turning corner or straight
        (a hanging node), at least three corners, one full turn.

        Examples
        --------
        >>> import blockmesh
        >>> PolygonMesh.from_mesh(blockmesh.load_domain("sp").mesh(2)).check_geometry()
        """
        if not np.all(np.isfinite(self.points)):
            bad = int(np.flatnonzero(~np.all(np.isfinite(self.points), axis=1))[0])
            raise DomainError(f"point {bad} {self.points[bad].tolist()} is not finite")
        invalid = self._measure()["invalid"]
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
        owner = self.polygon_cells().slot_cell()
        high = np.full(self.n_cells, -1, dtype=np.int64)
        low = np.full(self.n_cells, np.iinfo(np.int64).max, dtype=np.int64)
        np.maximum.at(high, owner, self.nodes)
        np.minimum.at(low, owner, self.nodes)
        return int((high - low).max(initial=0))

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """A fan of triangles from vertex 0 of every cell: ``(triangles (T, 3), cell (T,))``.

        Each cell of n vertices gives n - 2 triangles, counter-clockwise (convex cells only
        make valid fans; a straight vertex 0 gives a triangle of no area, which the pictures and
        the formats that need triangles tolerate).
        """
        sizes = self.cell_sizes()
        count = sizes - 2
        cell = np.repeat(np.arange(self.n_cells, dtype=np.int64), count)
        start = np.repeat(self.offsets[:-1], count)
        k = np.arange(cell.size) - np.repeat(np.cumsum(count) - count, count)
        tris = np.stack(
            [self.nodes[start], self.nodes[start + k + 1], self.nodes[start + k + 2]], 1
        )
        return tris, cell

    # ------------------------------------------------------------ boundaries
    def patch_index(self, patch: str) -> int:
        """Index of ``patch`` in ``patch_names`` (UnknownNameError listing the patches)."""
        if patch not in self.patch_names:
            raise UnknownNameError(
                f"no patch {patch!r}; the patches are {', '.join(self.patch_names)}"
            )
        return self.patch_names.index(patch)

    def patch_edges(self, patch: str) -> np.ndarray:
        """Boundary edges (E, 2) of the named patch."""
        return self.boundary_edges[self.boundary_patch == self.patch_index(patch)]

    @property
    def interfaces(self) -> Mapping[str, np.ndarray]:
        """Interface edges (E, 2) of each interface, by name (read-only view; empty if none).

        Examples
        --------
        >>> import blockmesh
        >>> mesh = PolygonMesh.from_mesh(blockmesh.load_domain("layered-plate").mesh(1))
        >>> {name: len(edges) for name, edges in mesh.interfaces.items()}
        {'bottom|core': 24, 'core|top': 24}
        """
        return MappingProxyType(
            {
                name: self.interface_edges[self.interface_patch == k]
                for k, name in enumerate(self.interface_names)
            }
        )

    def interface_cells(self) -> np.ndarray:
        """The two cells of every interface edge, (Ei, 2): the one on its left, then its right.

        Raises ArgumentError naming the first interface edge that is not an edge of two cells.
        O(S log S), cached.
        """
        if "interface_cells" not in self._cache:
            self._cache["interface_cells"] = _edge_cells(
                self.polygon_cells(), self.interface_edges, self.n_points
            )
        return self._cache["interface_cells"]

    # ------------------------------------------------------------------ copies
    def _copy(self, **changes: Any) -> PolygonMesh:
        values = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "_cache"}
        values.update(changes)
        return PolygonMesh._trusted(**values)

    def renumbered(self, order: np.ndarray) -> PolygonMesh:
        """The same mesh with node ``order[k]`` renamed ``k`` (a permutation of ``0..N-1``)."""
        order = np.asarray(order, dtype=np.int64)
        if order.shape != (self.n_points,) or not np.array_equal(
            np.sort(order), np.arange(self.n_points)
        ):
            raise ArgumentError("order must be a permutation of the node ids 0..N-1")
        new_id = np.empty_like(order)
        new_id[order] = np.arange(self.n_points)
        return self._copy(
            points=self.points[order],
            nodes=new_id[self.nodes],
            boundary_edges=new_id[self.boundary_edges],
            interface_edges=new_id[self.interface_edges],
            curves=None if self.curves is None else self.curves.renumbered(new_id),
        )

    def with_patches(self, boundary_patch: Any, patch_names: Any) -> PolygonMesh:
        """The same mesh with its boundary edges put in other patches."""
        return self._copy(boundary_patch=boundary_patch, patch_names=tuple(patch_names))

    def with_regions(self, region: Any, region_names: Any) -> PolygonMesh:
        """The same mesh with its cells put in other regions (``region`` indexes the names)."""
        return self._copy(region=region, region_names=tuple(region_names))

    def with_interfaces(
        self, interface_edges: Any, interface_patch: Any, interface_names: Any
    ) -> PolygonMesh:
        """The same mesh with other interfaces (internal patches); each edge is checked.

        Examples
        --------
        >>> pts = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]
        >>> mesh = PolygonMesh.from_cells(pts, [[0, 1, 4, 5], [1, 2, 3, 4]])
        >>> mesh.with_interfaces([[1, 4]], [0], ["glue"]).interface_cells().tolist()
        [[0, 1]]
        """
        changed = self._copy(
            interface_edges=interface_edges,
            interface_patch=interface_patch,
            interface_names=tuple(interface_names),
        )
        changed.interface_cells()
        return changed

    def with_points(self, points: Any) -> PolygonMesh:
        """The same cells on moved nodes; orientation and star shape are checked again."""
        moved = self._copy(points=points)
        moved._check_cells()
        return moved

    def with_name(self, name: str) -> PolygonMesh:
        """The same mesh under another name."""
        return self._copy(name=name)

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
        interfaces = (
            f"; interfaces {', '.join(self.interface_names)}" if self.interface_names else ""
        )
        return (
            f"PolygonMesh({name}level {self.level}: {self.n_cells:,} cells ({counts or 'none'} "
            f"vertices), {self.n_points:,} points; patches {', '.join(self.patch_names) or '-'}; "
            f"regions {', '.join(self.region_names) or '-'}{interfaces})"
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


# ---------------------------------------------------------------------- helpers
def _as_polygon_cells(cells: Any) -> PolygonCells:
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


def _boundary(cells: PolygonCells, n_points: int) -> np.ndarray:
    """Directed boundary edges; TopologyError on an edge of three or more cells."""
    keys = edge_keys(cells.nodes, cells.following(), n_points)
    unique, counts = np.unique(keys, return_counts=True)
    if np.any(counts > 2):
        a, b = divmod(int(unique[np.flatnonzero(counts > 2)[0]]), n_points)
        raise TopologyError(f"edge ({a}, {b}) belongs to three or more cells")
    return boundary_of_cells(cells, n_points)


def _check_edge_to_edge(points: np.ndarray, edges: np.ndarray) -> None:
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
