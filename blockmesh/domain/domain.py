"""The validated multi-block domain every mesh starts from.

A :class:`Domain` is a set of strictly convex, counter-clockwise pentagonal blocks meeting edge to
edge, with every boundary edge in exactly one named patch and every block in one named region. It
is built from any simple polygon with holes (decomposed automatically), a shapely polygon, an
existing triangle/quadrilateral mesh (converted), explicit blocks, or a domain file
(:mod:`blockmesh.domain.tomlio`), and it is checked on construction: an invalid domain never exists.

Examples
--------
>>> from blockmesh import Domain
>>> d = Domain.from_polygon([(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)], name="usp")
>>> d.blocks.tolist(), d.area
([[0, 1, 2, 3, 4]], 6.0)
>>> d.mesh(2).n_cells
36
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from blockmesh.curves.edges import area_corrections
from blockmesh.curves.types import Curve
from blockmesh.domain import constructors
from blockmesh.domain.assemble import check_fields, from_parsed
from blockmesh.domain.curve_checks import curved_edges
from blockmesh.domain.polygons import edge_chains
from blockmesh.domain.sized import DomainGeometry, resized
from blockmesh.domain.tomlio.writing import dumps_domain, write_domain
from blockmesh.errors import ArgumentError
from blockmesh.geometry.polygons import interior_angles, signed_area
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.pipeline import refine
from blockmesh.sizing.fields import PENTAGON_AREA, SizeField
from blockmesh.sizing.measure import SizeReport, size_report
from blockmesh.sizing.spec import as_size_spec

__all__ = ["UNIFORM_COUNT", "Domain"]

#: Cells a size-driven decomposition makes per ideal cell (``area / (0.6572 h^2)``) with a
#: uniform size, measured on the catalogue at fine sizes (1.32-1.37): :meth:`Domain.uniform`
#: divides by it to aim at a cell count.
UNIFORM_COUNT = 1.35


def _no_source() -> np.ndarray:
    """The default of the ``*_source`` fields: not known (filled with -1 on construction)."""
    return np.zeros(0, dtype=np.int64)


@dataclass(frozen=True, eq=False)
class Domain:
    """A conforming block mesh of strictly convex pentagons, with patches and regions.

    Build one with :meth:`from_polygon`, :meth:`from_blocks`, :meth:`from_toml` or
    :func:`blockmesh.load_domain`; the constructor checks everything, so a Domain is always valid.

    Attributes
    ----------
    name : str
    vertices : ndarray (K, 2) float64
    blocks : ndarray (B, 5) int64
        Vertex ids of each block, counter-clockwise.
    boundary_edges : ndarray (Eb, 2) int64
        Boundary edges in loops, each oriented with the domain on its left.
    boundary_patch : ndarray (Eb,) int64
        Index into ``patch_names`` of each boundary edge.
    patch_names : tuple of str
    region : ndarray (B,) int64
        Index into ``region_names`` of each block.
    region_names : tuple of str
    description : str
    layout : str
        How the blocks came about: ``"blocks"`` (given), ``"mesh"`` (converted) or the
        decomposition used.
    boundary_source : ndarray (Eb, 2) int64
        For each boundary edge (in ``boundary_edges`` order), the polygon edge it lies on, as
        ``(ring, edge)``: ring 0 is the outer boundary, ring ``K + 1`` is hole ``K``, and edge
        ``i`` of a ring runs from its corner ``i`` to corner ``i + 1`` *as given* (before any
        reversal); ``(-1, -1)`` for domains given as blocks. :attr:`polygon_edges` groups them.
        This is where curved boundaries attach: every block edge on a polygon edge is listed,
        in order along it.
    block_source : ndarray (B,) int64
        For a domain converted from a mesh (:meth:`from_mesh`), the element each block came
        from (its index among the mesh's 2-D elements in file order); -1 otherwise.
    curves : mapping of (a, b) to Curve
        The curved block edges (read-only view): each curve runs from vertex ``a`` to vertex
        ``b`` (:mod:`blockmesh.curves`); empty when every edge is straight.
    interface_edges : ndarray (Ei, 2) int64
        Block edges between two blocks that are named as internal patches (where two regions
        meet, :mod:`blockmesh.domain.interfaces`), each with its first side's block on its left.
    interface_patch : ndarray (Ei,) int64
        Index into ``interface_names`` of each interface edge.
    interface_names : tuple of str
        Different from every patch name; a composite domain names the edges between regions
        ``A`` and ``B`` ``"A|B"`` by default.
    components : int
        How many separate pieces the blocks form (1 unless a composite domain's parts lie
        apart); pieces do not touch, not even at a corner.
    grading : mapping of (a, b) to float
        Graded block edges (read-only view): refined, the nodes along edge ``(a, b)`` are spaced
        geometrically from ``a`` to ``b``, the last piece ``ratio`` times the first
        (:mod:`blockmesh.refinement.grading`); empty when nothing is graded.
    size_field : SizeField or None
        The size field the blocks were made for (:meth:`with_size`), or None.
    size_gradation : float or None
        The gradation the field was made to keep (the largest size ratio between neighbours).
    """

    name: str
    vertices: np.ndarray
    blocks: np.ndarray
    boundary_edges: np.ndarray
    boundary_patch: np.ndarray
    patch_names: tuple[str, ...]
    region: np.ndarray
    region_names: tuple[str, ...]
    description: str = ""
    layout: str = "blocks"
    boundary_source: np.ndarray = field(default_factory=_no_source, repr=False)
    block_source: np.ndarray = field(default_factory=_no_source, repr=False)
    curves: Mapping[tuple[int, int], Curve] = field(default_factory=dict)
    interface_edges: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    interface_patch: np.ndarray = field(default_factory=_no_source)
    interface_names: tuple[str, ...] = ()
    components: int = 1
    grading: Mapping[tuple[int, int], float] = field(default_factory=dict)
    size_field: SizeField | None = field(default=None, repr=False, compare=False)
    size_gradation: float | None = field(default=None, repr=False, compare=False)
    _neighbour: np.ndarray = field(default_factory=lambda: np.zeros((0, 5), np.int64), repr=False)

    def __post_init__(self) -> None:
        check_fields(self)

    # ------------------------------------------------------------------ constructors
    # Functions of blockmesh.domain.constructors, where their parameters and examples are written
    # (help(Domain.from_polygon) shows them), bound here as classmethods.
    from_blocks = classmethod(constructors.from_blocks)
    from_polygon = classmethod(constructors.from_polygon)
    from_circle = classmethod(constructors.from_circle)
    from_shapely = classmethod(constructors.from_shapely)
    compose = classmethod(constructors.compose)
    from_mesh = classmethod(constructors.from_mesh)
    from_toml = classmethod(constructors.from_toml)
    from_toml_text = classmethod(constructors.from_toml_text)

    @classmethod
    def _from_parsed(
        cls, points: np.ndarray, block_ids: np.ndarray, patches: Any, regions: Any, **options: Any
    ) -> Domain:
        """Check parsed blocks and build the Domain (:mod:`~blockmesh.domain.assemble`).

        ``made_for`` names what blockmesh decomposed, so that its own blocks failing the checks
        read as "too thin" rather than as a fault in blocks the user never wrote.
        ``curve_levels`` is how deep curved blocks are refined to be checked.
        """
        return from_parsed(cls, points, block_ids, patches, regions, **options)

    # ------------------------------------------------------------------ output
    def to_toml(self) -> str:
        """The domain as TOML text (explicit blocks); :meth:`from_toml_text` reads it back."""
        return dumps_domain(self)

    def write_toml(self, path: str | Path) -> Path:
        """Write :meth:`to_toml` to ``path`` atomically (temporary file, then rename)."""
        return write_domain(self, path)

    # ------------------------------------------------------------------ measures
    @property
    def n_blocks(self) -> int:
        """Number of blocks B."""
        return int(self.blocks.shape[0])

    @property
    def n_vertices(self) -> int:
        """Number of vertices K."""
        return int(self.vertices.shape[0])

    @property
    def area(self) -> float:
        """Total area of the blocks."""
        return float(np.sum(self.block_areas()))

    def block_areas(self) -> np.ndarray:
        """Area of each block, shape (B,), bounded by its curved edges where it has any."""
        areas = signed_area(self.vertices[self.blocks])
        if self.curves:
            areas = areas + area_corrections(self.blocks, self.n_vertices, self.block_mesh().curves)
        return areas

    def block_angles(self) -> np.ndarray:
        """Interior angles of each block in degrees, shape (B, 5)."""
        return interior_angles(self.vertices[self.blocks])

    @property
    def n_shared_edges(self) -> int:
        """Number of edges shared by two blocks."""
        return int(np.count_nonzero(self._neighbour >= 0)) // 2

    @property
    def patches(self) -> Mapping[str, np.ndarray]:
        """Boundary edges (E, 2) of each patch, by name (read-only view)."""
        return MappingProxyType(
            {
                name: self.boundary_edges[self.boundary_patch == k]
                for k, name in enumerate(self.patch_names)
            }
        )

    @property
    def regions(self) -> Mapping[str, np.ndarray]:
        """Block ids of each region, by name (read-only view)."""
        return MappingProxyType(
            {name: np.flatnonzero(self.region == k) for k, name in enumerate(self.region_names)}
        )

    @property
    def interfaces(self) -> Mapping[str, np.ndarray]:
        """Interface edges (E, 2) of each interface, by name (read-only view; empty if none).

        Examples
        --------
        >>> d = Domain.from_blocks(
        ...     [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)],
        ...     [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)],
        ...     regions={"left": [0], "right": [1]},
        ...     interfaces={"left|right": [(1, 2)]},
        ... )
        >>> d.interfaces["left|right"].tolist()  # the left block on its left
        [[1, 2]]
        """
        return MappingProxyType(
            {
                name: self.interface_edges[self.interface_patch == k]
                for k, name in enumerate(self.interface_names)
            }
        )

    @property
    def polygon_edges(self) -> Mapping[tuple[int, int], np.ndarray]:
        """The block vertices along each polygon edge, by ``(ring, edge)`` (read-only view).

        For a domain made from a polygon (see :attr:`boundary_source`): each chain lists the
        vertex ids from one end of the polygon edge to the other, in the boundary's direction
        (the domain on the left), so consecutive ids are boundary edges of the blocks. Empty for
        a domain given as blocks. O(Eb log Eb).

        Examples
        --------
        >>> d = Domain.from_polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
        >>> d.polygon_edges[(0, 0)].tolist()  # the bottom edge: corner 0, a node, corner 1
        [0, 4, 1]
        """
        return edge_chains(self.boundary_edges, self.boundary_source)

    def block_graph(self):
        """The networkx graph of blocks and shared edges; see :mod:`blockmesh.domain.blockgraph`."""
        from blockmesh.domain.blockgraph import block_graph

        return block_graph(self)

    # ------------------------------------------------------------------ meshing
    def block_mesh(self) -> Mesh:
        """The blocks themselves as a level-0 :class:`~blockmesh.mesh.Mesh`."""
        n = self.n_blocks
        return Mesh._trusted(
            points=self.vertices,
            cells=self.blocks,
            block_id=np.arange(n),
            parent=np.full(n, -1),
            boundary_edges=self.boundary_edges,
            boundary_patch=self.boundary_patch,
            patch_names=self.patch_names,
            region=self.region,
            region_names=self.region_names,
            level=0,
            name=self.name,
            curves=curved_edges(self.curves),
            interface_edges=self.interface_edges,
            interface_patch=self.interface_patch,
            interface_names=self.interface_names,
        )

    def mesh(self, level: int | None = None, *, size: Any = None, **options: Any) -> Mesh:
        """Refine the blocks ``level`` times; options as :func:`blockmesh.refine`.

        With ``size`` (see :meth:`with_size`) the blocks are first cut to the sizes asked, and
        ``level`` (default 0) refines them further. A domain already made for a size field
        meshes at level 0 when no level is given.

        Examples
        --------
        >>> d = Domain.from_polygon([(0, 0), (2, 0), (2, 1), (0, 1)])
        >>> mesh = d.mesh(size=0.25)
        >>> mesh.level, bool(mesh.n_cells > 50)
        (0, True)
        """
        if size is not None:
            return self.with_size(size).mesh(level, **options)
        if level is None:
            if self.size_field is None:
                raise ArgumentError(
                    "mesh() needs a level (uniform refinement) or a size (cells of that diameter)"
                )
            level = 0
        return refine(self, level, **options)

    def with_size(
        self, size: Any, *, gradation: float | None = None, max_memory: int | None = None
    ) -> Domain:
        """The domain re-cut into blocks of the sizes asked: every block is a cell of that size.

        The blocks follow the size field (every block's diameter at most 1.5 times the size asked
        at its centroid, about 1.5 times the fewest cells that allows), conform, keep the
        patches, regions and curves, and refine further like any others. See
        :mod:`blockmesh.domain.sized` and :mod:`blockmesh.sizing.spec` for the forms of ``size``.

        Parameters
        ----------
        size : number, str, callable, mapping, SizeField, or a list of these
            A cell diameter; an expression in ``x`` and ``y``; a function ``f(x, y)`` of arrays;
            a size table (``default``, ``regions``, ``near`` patches or points with ``growth``
            or ``distance``, ``expression``, ``gradation``); their minimum (a list).
        gradation : float, optional
            Largest size ratio between neighbouring cells the field may ask (default 1.3).
        max_memory : int, optional
            Refuse fields predicted to need more bytes than this (default: the memory available).

        Examples
        --------
        >>> d = Domain.from_polygon([(0, 0), (2, 0), (2, 1), (0, 1)], patches={"left": [3]})
        >>> graded = d.with_size({"default": 0.3, "near": [{"patch": "left", "size": 0.05,
        ...                                                  "growth": 1.2}]})
        >>> report = graded.size_report()
        >>> bool(report.worst_ratio <= 1.5), bool(0.5 < report.count_ratio < 2)
        (True, True)
        """
        return resized(self, size, gradation=gradation, max_memory=max_memory)

    def uniform(self, level: int, *, max_memory: int | None = None) -> Domain:
        """The domain cut into cells of one size, about as many as ``mesh(level)`` makes.

        The corner-true alternative to refining the blocks: the paper's rule lets the cells at
        block corners grow 1.5 times per level relative to the others (the corner child keeps a
        quarter of its parent, the mean child a sixth), while here every cell is made to the one
        size (:meth:`with_size`) whose count is about ``n_blocks * 6**level``, so the largest
        ratio between neighbouring cells stays that of the size-driven decomposition (below 3,
        about 2 on the catalogue) at every level.

        Examples
        --------
        >>> d = Domain.from_polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
        >>> even = d.uniform(2)
        >>> bool(0.6 < even.n_blocks / d.mesh(2).n_cells < 1.6)
        True
        """
        level = int(level)
        if level < 0:
            raise ArgumentError(f"uniform() needs a level >= 0, got {level}")
        cells = self.n_blocks * 6**level
        size = math.sqrt(UNIFORM_COUNT * self.area / (PENTAGON_AREA * cells))
        return self.with_size(size, max_memory=max_memory)

    def size_report(self, field: Any = None) -> SizeReport:
        """The blocks' sizes against ``field`` (default: the field they were made for).

        See :class:`blockmesh.sizing.SizeReport`.
        """
        asked = (
            self.size_field if field is None else as_size_spec(field).field(DomainGeometry(self))
        )
        mesh = self.block_mesh()
        return size_report(mesh.points, mesh.cells, asked, curves=mesh.curves)
