"""The all-pentagon mesh: a frozen dataclass of read-only arrays, its measures and quality.

A :class:`Mesh` is what :func:`blockmesh.refine` returns and what integration and the writers take.
Level 0 is the block mesh of a domain itself; every level splits each cell into six. What it
shares with :class:`~blockmesh.mesh.polygons.PolygonMesh` has one home each: the methods both
have (their base class, :mod:`~blockmesh.mesh.common`), the arrays frozen and checked
(:mod:`~blockmesh.mesh.arrays`), patches, regions, interfaces and relabelled copies
(:mod:`~blockmesh.mesh.labels`), node numbering (:mod:`~blockmesh.mesh.numbering`).

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

from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from blockmesh.curves.edges import CurvedEdges, area_corrections
from blockmesh.errors import ArgumentError, DomainError
from blockmesh.geometry.topology import boundary_of_cells, check_boundary
from blockmesh.mesh import labels, numbering
from blockmesh.mesh.arrays import (
    NO_EDGES,
    NO_IDS,
    check_finite,
    check_label_lengths,
    check_range,
    freeze_labels,
    frozen,
    own_blocks,
    trusted,
)
from blockmesh.mesh.common import MeshBase
from blockmesh.mesh.labels import interface_summary
from blockmesh.mesh.measures import CellMeasures, measure_cells, signed_areas
from blockmesh.mesh.numbering import BANDWIDTH_CHUNK
from blockmesh.mesh.quality import MeshQuality

__all__ = ["Mesh", "MeshQuality", "interface_summary"]

#: Cells whose areas :meth:`Mesh._check_cells` holds at once.
_CHUNK = 1 << 18


@dataclass(frozen=True, eq=False, repr=False)
class Mesh(MeshBase):
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
    curves : CurvedEdges or None
        The edges that lie on curved block edges, with the curve and the stretch of its parameter
        each covers (:class:`blockmesh.curves.edges.CurvedEdges`); None when every edge is straight.
        A Domain with curves passes them to its block mesh and :func:`blockmesh.refine` carries
        them to every level. The ``.npz``, ``.xdmf`` and ``.vtu`` files keep them (a mesh read
        back refines onto its curves); the other formats keep only the nodes, which are on the
        curves, and their readers warn that refining such a mesh gives straight edges.
    interface_edges : ndarray (Ei, 2) int64
        Interior edges named as internal patches: where two regions of a composite domain meet.
        Each is an edge of two cells; the cell on its left (as it runs from its first node to its
        second) is the interface's first side. Empty for a domain of one material.
    interface_patch : ndarray (Ei,) int64
        Index into ``interface_names`` of each interface edge.
    interface_names : tuple of str
        Different from every patch name. :func:`blockmesh.refine` carries the interfaces to every
        level, as it carries the boundary patches.
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
    curves: CurvedEdges | None = None
    interface_edges: np.ndarray = field(default_factory=lambda: NO_EDGES)
    interface_patch: np.ndarray = field(default_factory=lambda: NO_IDS)
    interface_names: tuple[str, ...] = ()
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    @classmethod
    def _trusted(cls, *, check_ranges: bool = True, **values: Any) -> Mesh:
        """A Mesh from arrays consistent by construction (refinement, a validated Domain).

        Only the cheap O(M) checks of :meth:`_check_arrays` run (shapes, lengths and, unless
        ``check_ranges`` is false, index ranges); orientation and boundary matching, which the
        constructor also checks, are skipped. The refinement, whose indices come from the plan and
        are tested against the paper's numbering, skips the ranges (a pass over every array).
        """
        mesh = trusted(cls, values)
        mesh._freeze()
        mesh._check_arrays(ranges=check_ranges)
        return mesh

    def _freeze(self) -> None:
        set_ = object.__setattr__
        set_(self, "points", frozen(self.points, np.float64, "points", (2,)))
        set_(self, "cells", frozen(self.cells, np.int64, "cells", (5,)))
        for name in ("block_id", "parent", "boundary_patch", "region", "interface_patch"):
            set_(self, name, frozen(getattr(self, name), np.int64, name))
        set_(self, "boundary_edges", frozen(self.boundary_edges, np.int64, "boundary_edges", (2,)))
        set_(
            self,
            "interface_edges",
            frozen(self.interface_edges, np.int64, "interface_edges", (2,)),
        )
        freeze_labels(self, "Mesh")

    def _check_arrays(self, *, ranges: bool = True) -> None:
        """Shapes, lengths and (O(M)) index ranges."""
        check_label_lengths(self, "Mesh", ("block_id", "parent", "region"))
        if not ranges:
            return
        n = self.n_points
        points_note = f"there are {n} points"
        check_range(self.cells, 0, n, "cell", points_note)
        check_range(self.boundary_edges, 0, n, "boundary edge", points_note)
        if self.curves is not None:
            check_range(self.curves.edges, 0, n, "curved edge", points_note)
        check_range(self.block_id, 0, np.iinfo(np.int64).max, "block_id of cell", "ids are >= 0")
        check_range(self.parent, -1, np.iinfo(np.int64).max, "parent of cell", "ids are >= -1")
        check_range(
            self.boundary_patch,
            0,
            len(self.patch_names),
            "boundary_patch of edge",
            f"there are {len(self.patch_names)} patch names",
        )
        check_range(
            self.region,
            0,
            len(self.region_names),
            "region of cell",
            f"there are {len(self.region_names)} region names",
        )
        check_range(self.interface_edges, 0, n, "interface edge", points_note)
        check_range(
            self.interface_patch,
            0,
            len(self.interface_names),
            "interface_patch of edge",
            f"there are {len(self.interface_names)} interface names",
        )

    def _check_cells(self) -> None:
        """Finite points, counter-clockwise cells, boundary edges exactly the free cell edges."""
        check_finite(self.points)
        areas = np.empty(min(self.n_cells, _CHUNK))
        for start in range(0, self.n_cells, _CHUNK):
            cells = self.cells[start : start + _CHUNK]
            part = signed_areas(self.points, cells, out=areas[: cells.shape[0]])
            if not part[np.argmin(part)] > 0:  # argmin: NaN is found, as by min
                bad = start + int(np.flatnonzero(~(part > 0))[0])
                raise ArgumentError(
                    f"cell {bad} (nodes {', '.join(map(str, self.cells[bad]))}) is clockwise or "
                    "has no area; cells run counter-clockwise"
                )
        check_boundary(self.cells, self.boundary_edges, self.n_points)
        if self.interface_edges.shape[0]:
            self.interface_cells()

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
        boundary = boundary_of_cells(cells, points.shape[0])
        return cls(
            points=points,
            cells=cells,
            boundary_edges=boundary,
            boundary_patch=np.zeros(boundary.shape[0], dtype=np.int64),
            patch_names=("boundary",),
            level=level,
            name=name,
            **own_blocks(cells.shape[0]),
        )

    # ----------------------------------------------------------------- sizes
    @property
    def n_cells(self) -> int:
        """Number of cells M."""
        return int(self.cells.shape[0])

    @property
    def n_edges(self) -> int:
        """Number of unique edges: (5 M + boundary edges) / 2, as every other edge has two cells."""
        return (5 * self.n_cells + int(self.boundary_edges.shape[0])) // 2

    def edges(self) -> np.ndarray:
        """Unique undirected edges (E, 2) as (lower id, higher id), cached. O(M), no sorting.

        Cells run counter-clockwise, so an edge two cells share runs one way in one and the other
        way in the other: each is listed once where it runs from its lower node to its higher.
        Boundary edges, in one cell only, are added where they run downwards. Edges come in the
        order of the cells (boundary edges running downwards last).

        Examples
        --------
        >>> import blockmesh
        >>> blockmesh.load_domain("joined-2").mesh(0).edges().tolist()
        [[0, 1], [1, 2], [2, 3], [3, 4], [1, 5], [5, 6], [6, 7], [2, 7], [0, 4]]
        """
        if "edges" not in self._cache:
            edges = np.empty((self.n_edges, 2), dtype=np.int64)
            filled = 0
            for start in range(0, self.n_cells, BANDWIDTH_CHUNK):
                tail = self.cells[start : start + BANDWIDTH_CHUNK]
                head = tail[:, [1, 2, 3, 4, 0]]
                upward = tail < head
                count = int(np.count_nonzero(upward))
                edges[filled : filled + count, 0] = tail[upward]
                edges[filled : filled + count, 1] = head[upward]
                filled += count
            down = self.boundary_edges[self.boundary_edges[:, 0] > self.boundary_edges[:, 1]]
            if filled + down.shape[0] != edges.shape[0]:
                raise DomainError(
                    "the cells do not meet edge to edge with consistent orientation; the mesh "
                    "is broken"
                )
            edges[filled:] = down[:, ::-1]
            edges.setflags(write=False)
            self._cache["edges"] = edges
        return self._cache["edges"]

    def cell_coordinates(self) -> np.ndarray:
        """Corner coordinates of every cell, shape (M, 5, 2)."""
        return self.points[self.cells]

    def cell_areas(self) -> np.ndarray:
        """Area of every cell (positive for counter-clockwise cells), shape (M,).

        Measured relative to each cell's first corner: differences of nearby points lose no
        digits, so areas do not depend on where the mesh lies (a unit square at 1e9 has area 1).
        """
        return signed_areas(self.points, self.cells)

    def _measures(self, progress: Callable[[int, int], None] | None = None) -> CellMeasures:
        """Areas, angles, aspect and convexity of all cells, measured once (cached)."""
        if "measures" not in self._cache:
            self._cache["measures"] = measure_cells(self, progress=progress)
        return self._cache["measures"]

    @property
    def area(self) -> float:
        """Total area of the mesh (sum of cell areas)."""
        return self._measures().area

    def curved_cell_areas(self) -> np.ndarray:
        """Area of every cell bounded by its curved edges (the exact geometry), shape (M,).

        A cell's straight area plus the signed area between each of its curved edges and the
        chord (closed forms; see :func:`blockmesh.curves.edges.area_corrections`). Equals
        :meth:`cell_areas` when the mesh has no curves.
        """
        return self.cell_areas() + area_corrections(self.cells, self.n_points, self.curves)

    # --------------------------------------------------------------- quality
    def quality(
        self, *, chunk: int | None = None, progress: Callable[[int, int], None] | None = None
    ) -> MeshQuality:
        """Angles, aspect ratios and areas of the cells, in chunks (bounded memory).

        One pass over the cells, shared with :attr:`area`, :meth:`check_geometry` and
        :meth:`bandwidth` and cached; ``chunk`` (cells per pass step) changes the memory used, not
        the measures (the areas are summed chunk by chunk, so :attr:`area` may differ in its last
        bits with it).
        ``progress(done, total)`` hears how many cells are measured, when they are.

        Examples
        --------
        >>> import blockmesh
        >>> q = blockmesh.load_domain("sp").mesh(1).quality()
        >>> round(q.min_angle, 1), round(q.max_angle, 1), q.not_strictly_convex
        (56.3, 150.3, 0)
        """
        m = self._measures(progress) if chunk is None else measure_cells(self, chunk=chunk)
        return MeshQuality.from_measures(asdict(m))

    def check_geometry(self) -> None:
        """Raise DomainError unless every cell is a strictly convex, counter-clockwise polygon.

        The final guard before a mesh is written or reported as made: O(M), in chunks. A corner
        counts as straight when the sine of its turn is at most
        :data:`~blockmesh.geometry.COLLINEAR_SIN_TOL`.

        Examples
        --------
        >>> import blockmesh
        >>> blockmesh.load_domain("sp").mesh(3).check_geometry()
        """
        check_finite(self.points, DomainError)
        measures = self._measures()
        failed, first = measures.invalid, measures.first_invalid
        if failed:
            corners = self.points[self.cells[first]]
            raise DomainError(
                f"{failed:,} of the {self.n_cells:,} cells are not strictly convex and "
                f"counter-clockwise, the first being cell {first} with corners "
                f"{', '.join(f'({x:.17g}, {y:.17g})' for x, y in corners)}; the mesh is broken "
                "(far from the origin double precision may not resolve its cells)"
            )

    # ------------------------------------------------------------- numbering
    def bandwidth(self) -> int:
        """Largest difference between two node ids of one cell (the half-bandwidth of an FE matrix).

        Read from the cell measures when :meth:`quality` (or :attr:`area`) has measured them
        already (they find it in the same pass); otherwise one pass of its own.

        Examples
        --------
        >>> import blockmesh
        >>> blockmesh.load_domain("sp").mesh(1).bandwidth()
        14
        """
        if "measures" in self._cache:
            return self._cache["measures"].bandwidth
        return numbering.bandwidth(self.cells)

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
        return numbering.renumbered(self, order, "cells")

    def with_rcm_numbering(self) -> Mesh:
        """Nodes renumbered by reverse Cuthill-McKee (scipy) on the cell connectivity graph.

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("square-cut").mesh(3)
        >>> mesh.with_rcm_numbering().bandwidth() < mesh.bandwidth()
        True
        """
        return self.renumbered(numbering.rcm_order(self.cells, self.n_points))

    # ------------------------------------------------------------ boundaries
    def interface_cells(self) -> np.ndarray:
        """The two cells of every interface edge, (Ei, 2): the one on its left, then its right.

        Raises ArgumentError naming the first interface edge that is not an edge of two cells
        (a boundary edge, or no edge at all). O(M log M), cached.

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("layered-plate").mesh(0)
        >>> sides = mesh.region[mesh.interface_cells()]
        >>> [mesh.region_names[k] for k in sides[0]]
        ['bottom', 'core']
        """
        return labels.interface_cells(self, self.cells)

    # ------------------------------------------------------------ copies
    def __repr__(self) -> str:
        """A one-line summary (the arrays are not printed)."""
        name = f"{self.name!r}, " if self.name else ""
        return (
            f"Mesh({name}level {self.level}: {self.n_cells:,} cells, {self.n_points:,} points, "
            f"{self.boundary_edges.shape[0]:,} boundary edges; {labels.labels_text(self)})"
        )

    def nbytes(self) -> int:
        """Bytes held by the mesh's arrays."""
        arrays = (self.points, self.cells, self.block_id, self.parent, self.region)
        return (
            sum(a.nbytes for a in arrays)
            + self.boundary_edges.nbytes
            + self.boundary_patch.nbytes
            + self.interface_edges.nbytes
            + self.interface_patch.nbytes
        )
