"""The validated multi-block domain every mesh starts from.

A :class:`Domain` is a set of strictly convex, counter-clockwise pentagonal blocks meeting edge to
edge, with every boundary edge in exactly one named patch and every block in one named region. It
is built from a convex polygon (decomposed automatically), from explicit blocks, or from a TOML
file of either form (:mod:`blockmesh.tomlio`), and it is checked on construction: an invalid
domain never exists.

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

import numbers
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from .checks import readonly
from .errors import DomainError, DomainFormatError
from .geometry import interior_angles, signed_area
from .mesh import Mesh
from .tomlio import dumps_domain, parse_domain_text, read_domain_file
from .topology import boundary_loops, cell_neighbours
from .validate import (
    check_block_shapes,
    check_polygon,
    check_topology,
    parse_blocks,
    parse_points,
    resolve_patches,
    resolve_regions,
)

__all__ = ["Domain"]


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
        How the blocks came about: ``"blocks"`` (given) or the decomposition used.
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
    _neighbour: np.ndarray = field(default_factory=lambda: np.zeros((0, 5), np.int64), repr=False)

    def __post_init__(self) -> None:
        vertices = parse_points(self.vertices, "vertex")
        blocks = parse_blocks(self.blocks, vertices.shape[0])
        check_block_shapes(vertices, blocks, repair=False)
        neighbour = _neighbours(blocks, vertices.shape[0])
        check_topology(vertices, blocks, neighbour)
        boundary = boundary_loops(blocks, neighbour)
        given = np.asarray(self.boundary_edges, dtype=np.int64).reshape(-1, 2)
        if not np.array_equal(given, boundary):
            raise DomainError(
                "boundary_edges must be the blocks' boundary edges in loop order; build domains "
                "with Domain.from_blocks() or Domain.from_polygon()"
            )
        patch = np.asarray(self.boundary_patch, dtype=np.int64)
        region = np.asarray(self.region, dtype=np.int64)
        if patch.shape != (boundary.shape[0],) or not np.all(
            (patch >= 0) & (patch < len(self.patch_names))
        ):
            raise DomainError("every boundary edge needs one patch (an index into patch_names)")
        if region.shape != (blocks.shape[0],) or not np.all(
            (region >= 0) & (region < len(self.region_names))
        ):
            raise DomainError("every block needs one region (an index into region_names)")
        self._store(vertices, blocks, boundary, patch, region, neighbour)

    def _store(self, vertices, blocks, boundary, patch, region, neighbour) -> None:
        set_ = object.__setattr__
        set_(self, "vertices", readonly(vertices, np.float64))
        set_(self, "blocks", readonly(blocks, np.int64))
        set_(self, "boundary_edges", readonly(boundary, np.int64))
        set_(self, "boundary_patch", readonly(patch, np.int64))
        set_(self, "region", readonly(region, np.int64))
        set_(self, "patch_names", tuple(self.patch_names))
        set_(self, "region_names", tuple(self.region_names))
        set_(self, "_neighbour", readonly(neighbour, np.int64))

    @classmethod
    def _trusted(cls, *, neighbour: np.ndarray, **values: Any) -> Domain:
        """A Domain from data :meth:`from_blocks` has just checked (no second validation)."""
        domain = object.__new__(cls)
        for f in fields(cls):
            if f.name != "_neighbour":
                object.__setattr__(domain, f.name, values.get(f.name, f.default))
        domain._store(
            values["vertices"],
            values["blocks"],
            values["boundary_edges"],
            values["boundary_patch"],
            values["region"],
            neighbour,
        )
        return domain

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_blocks(
        cls,
        vertices: Any,
        blocks: Any,
        patches: Mapping[str, Iterable] | None = None,
        regions: Mapping[str, Iterable[int]] | None = None,
        *,
        name: str = "blocks",
        description: str = "",
        layout: str = "blocks",
    ) -> Domain:
        """A domain from explicit blocks, like OpenFOAM's blockMeshDict.

        Parameters
        ----------
        vertices : sequence of (x, y)
        blocks : sequence of 5 vertex ids each
            Clockwise blocks are reversed (first vertex kept) with a warning.
        patches : mapping of name to a list of (a, b) boundary edges, optional
            Unlisted boundary edges go to the patch ``"boundary"``.
        regions : mapping of name to a list of block ids, optional
            Unlisted blocks go to the region ``"domain"``.

        Examples
        --------
        >>> d = Domain.from_blocks(
        ...     [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)],
        ...     [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)],
        ...     patches={"inlet": [(4, 0)]},
        ... )
        >>> d.patch_names, len(d.patches["boundary"])
        (('inlet', 'boundary'), 7)
        """
        points = parse_points(vertices, "vertex")
        block_ids = parse_blocks(blocks, points.shape[0])
        block_ids = check_block_shapes(points, block_ids, repair=True)
        neighbour = _neighbours(block_ids, points.shape[0])
        check_topology(points, block_ids, neighbour)
        boundary = boundary_loops(block_ids, neighbour)
        owners = _edge_owners(block_ids)
        patch_names, patch = resolve_patches(boundary, patches, owners)
        region_names, region = resolve_regions(block_ids.shape[0], regions)
        return cls._trusted(
            neighbour=neighbour,
            name=_check_text(name, "name"),
            vertices=points,
            blocks=block_ids,
            boundary_edges=boundary,
            boundary_patch=patch,
            patch_names=patch_names,
            region=region,
            region_names=region_names,
            description=_check_text(description, "description"),
            layout=layout,
        )

    @classmethod
    def from_polygon(
        cls,
        coords: Any,
        *,
        name: str = "polygon",
        patches: Mapping[str, Iterable[int]] | None = None,
        description: str = "",
    ) -> Domain:
        """A convex polygon with any n >= 3 corners, decomposed into pentagonal blocks.

        Parameters
        ----------
        coords : sequence of (x, y)
            The corners in order (clockwise is reversed with a warning; a repeated closing
            corner and straight corners are dropped with a warning).
        patches : mapping of name to a list of polygon edge indices, optional
            Edge i runs from corner i to corner i+1 (as given). Unlisted edges go to
            ``"boundary"``.

        Examples
        --------
        >>> d = Domain.from_polygon([(0, 0), (1, 0), (1, 1), (0, 1)], patches={"bottom": [0]})
        >>> d.n_blocks, d.layout, d.patch_names
        (8, 'quad-template', ('bottom', 'boundary'))
        """
        from .decompose import decompose_convex_polygon

        points = parse_points(coords, "polygon vertex")
        edge_patch = _polygon_edge_patches(patches, points.shape[0])
        polygon, source = check_polygon(points, edge_patch)
        decomposition = decompose_convex_polygon(polygon)
        named: dict[str, list[tuple[int, int]]] = {}
        for chain, input_edge in zip(decomposition.edge_chains, source, strict=True):
            patch_name = edge_patch[input_edge] if edge_patch is not None else None
            if patch_name is not None:
                pairs = zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True)
                named.setdefault(patch_name, []).extend(pairs)
        # Keep the user's patch order.
        order = list(patches or {})
        named = {k: named[k] for k in order if k in named}
        return cls.from_blocks(
            decomposition.vertices,
            decomposition.blocks,
            named,
            name=name,
            description=description,
            layout=decomposition.layout,
        )

    @classmethod
    def from_toml(cls, path: str | Path) -> Domain:
        """Read a domain file (polygon or explicit blocks); see :mod:`blockmesh.tomlio`."""
        return _from_raw(read_domain_file(path), source=str(path))

    @classmethod
    def from_toml_text(cls, text: str, *, name: str = "domain") -> Domain:
        """A domain from TOML text (as in a domain file).

        Examples
        --------
        >>> Domain.from_toml_text("polygon = [[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]]").area
        6.0
        """
        raw = parse_domain_text(text, source="<text>")
        raw.setdefault("name", name)
        return _from_raw(raw, source="<text>")

    # ------------------------------------------------------------------ output
    def to_toml(self) -> str:
        """The domain as TOML text (explicit blocks); :meth:`from_toml_text` reads it back."""
        return dumps_domain(self)

    def write_toml(self, path: str | Path) -> Path:
        """Write :meth:`to_toml` to ``path`` atomically (temporary file, then rename)."""
        from .atomic import atomic_file

        path = Path(path)
        with atomic_file(path) as temporary:
            temporary.write_text(self.to_toml(), encoding="utf-8")
        return path

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
        """Area of each block, shape (B,)."""
        return signed_area(self.vertices[self.blocks])

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

    def block_graph(self):
        """The networkx graph of blocks and shared edges; see :mod:`blockmesh.blockgraph`."""
        from .blockgraph import block_graph

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
        )

    def mesh(self, level: int, **options: Any) -> Mesh:
        """Refine the blocks ``level`` times; options as :func:`blockmesh.refine`."""
        from .refinement import refine

        return refine(self, level, **options)


# ---------------------------------------------------------------------- helpers
def _check_text(value: object, what: str) -> str:
    """``value`` if it is a string without control characters (new lines allowed but in names)."""
    if not isinstance(value, str):
        raise DomainFormatError(f"the domain's {what} must be a string, got {value!r}")
    allowed = "" if what == "name" else "\n\t"
    for position, char in enumerate(value):
        if not char.isprintable() and char not in allowed:
            raise DomainFormatError(
                f"the domain's {what} has the control character {char!r} at position "
                f"{position}; use printable text"
            )
    return value


def _neighbours(blocks: np.ndarray, n_vertices: int) -> np.ndarray:
    from .errors import BlockMeshError, TopologyError

    try:
        return cell_neighbours(blocks, n_vertices)
    except BlockMeshError as error:
        raise TopologyError(f"{error}: the blocks overlap there") from None


def _edge_owners(blocks: np.ndarray) -> dict[tuple[int, int], list[int]]:
    owners: dict[tuple[int, int], list[int]] = {}
    for b, block in enumerate(blocks.tolist()):
        for k in range(5):
            a, c = block[k], block[(k + 1) % 5]
            owners.setdefault((min(a, c), max(a, c)), []).append(b)
    return owners


def _polygon_edge_patches(
    patches: Mapping[str, Iterable[int]] | None, n_edges: int
) -> list[str | None] | None:
    if not patches:
        return None
    if not isinstance(patches, Mapping):
        raise DomainFormatError(
            f"patches must map patch names to polygon edge indices, got {type(patches).__name__}"
        )
    edge_patch: list[str | None] = [None] * n_edges
    for patch_name, edges in patches.items():
        if isinstance(edges, str | bytes) or not isinstance(edges, Iterable):
            raise DomainFormatError(
                f"patch {patch_name!r} must be a list of polygon edge indices, got {edges!r}"
            )
        for edge in edges:
            if not isinstance(edge, numbers.Integral) or isinstance(edge, bool):
                raise DomainFormatError(
                    f"patch {patch_name!r} has {edge!r}; for a polygon, a patch lists edge "
                    f"indices 0..{n_edges - 1} (edge i runs from corner i to corner i+1)"
                )
            if not 0 <= edge < n_edges:
                raise DomainError(
                    f"patch {patch_name!r} names edge {edge}, but the polygon's edges are "
                    f"numbered 0..{n_edges - 1}"
                )
            if edge_patch[edge] is not None:
                raise DomainError(
                    f"polygon edge {edge} is in patches {edge_patch[edge]!r} and "
                    f"{patch_name!r}; an edge belongs to one patch"
                )
            edge_patch[edge] = str(patch_name)
    return edge_patch


def _from_raw(raw: dict[str, Any], *, source: str) -> Domain:
    name = raw.get("name", "domain")
    description = raw.get("description", "")
    try:
        if "polygon" in raw:
            return Domain.from_polygon(
                raw["polygon"], name=name, patches=raw.get("patches"), description=description
            )
        return Domain.from_blocks(
            raw["vertices"],
            raw["blocks"],
            raw.get("patches"),
            raw.get("regions"),
            name=name,
            description=description,
        )
    except DomainError as error:
        raise type(error)(f"{source}: {error}") from None
