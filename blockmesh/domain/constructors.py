"""The ways a :class:`~blockmesh.domain.domain.Domain` is made: its alternate constructors.

Each function here is bound to the class as a classmethod of the same name (``Domain.from_polygon =
classmethod(from_polygon)``), so call them through the class: ``Domain.from_polygon(coords)``,
``Domain.from_blocks(vertices, blocks)``, ... They hold the constructors' signatures and
documentation; each is one call into the module that does the job, with the class as its first
argument: explicit blocks (:mod:`~blockmesh.domain.assemble`), polygons and shapely geometry
(:mod:`~blockmesh.domain.polygons`), discs (:mod:`~blockmesh.domain.curved_polygons`), composite
domains (:mod:`~blockmesh.domain.compose`), converted meshes (:mod:`~blockmesh.domain.converted`)
and domain files (:mod:`~blockmesh.domain.tomlio`).

Examples
--------
>>> from blockmesh import Domain
>>> Domain.from_circle((0, 0), 1).n_blocks
11
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from blockmesh.curves.types import Curve
from blockmesh.domain.assemble import blocks_domain
from blockmesh.domain.compose import compose_mapping
from blockmesh.domain.converted import mesh_domain
from blockmesh.domain.curved_polygons import circle_domain
from blockmesh.domain.polygons import polygon_domain, shapely_domain
from blockmesh.domain.tomlio.reading import domain_from_file, domain_from_text

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = [
    "compose",
    "from_blocks",
    "from_circle",
    "from_mesh",
    "from_polygon",
    "from_shapely",
    "from_toml",
    "from_toml_text",
]


def from_blocks(
    cls: type[Domain],
    vertices: Any,
    blocks: Any,
    patches: Mapping[str, Iterable] | None = None,
    regions: Mapping[str, Iterable[int]] | None = None,
    *,
    name: str = "blocks",
    description: str = "",
    layout: str = "blocks",
    merge_tol: float | None = None,
    boundary_source: Mapping[tuple[int, int], tuple[int, int]] | None = None,
    block_source: Any = None,
    edges: Mapping[tuple[int, int], Curve] | None = None,
    interfaces: Mapping[str, Iterable] | None = None,
    components: int = 1,
    grading: Mapping[tuple[int, int], float] | None = None,
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
    merge_tol : float, optional
        Merge vertices closer than this distance (in the coordinates' units) into one, the
        lowest-numbered, before anything is checked: pieces made separately are glued along
        their common edges. The vertices are then renumbered in order, leaving out the
        merged ones, and ``blocks``, ``patches`` and ``interfaces`` refer to the new numbers'
        old ids as given (the merge maps them).
    grading : mapping of (a, b) to float, optional
        Graded straight block edges, like blockMesh's ``edgeGrading``: refined, the nodes along
        edge ``(a, b)`` are spaced geometrically from ``a`` to ``b``, the last piece ``ratio``
        times the first, at every level (see :attr:`~blockmesh.domain.domain.Domain.grading`).
    boundary_source : mapping of (a, b) to (ring, edge), optional
        The polygon edge each boundary edge lies on (see
        :attr:`~blockmesh.domain.domain.Domain.boundary_source`); used by the polygon constructors.
    block_source : sequence of int, optional
        The source element of each block (see :attr:`~blockmesh.domain.domain.Domain.block_source`);
        used by :meth:`~blockmesh.domain.domain.Domain.from_mesh`.
    edges : mapping of (a, b) to a curve, optional
        Curved block edges: the curve (:class:`~blockmesh.curves.Arc`,
        :class:`~blockmesh.curves.Spline` or :class:`~blockmesh.curves.Polyline`) replaces
        the straight edge from vertex ``a`` to vertex ``b`` (ids as given, before any
        merge). The blocks must stay strictly convex with their curves when refined
        (:mod:`blockmesh.domain.curve_checks`).
    interfaces : mapping of name to a list of (a, b) edges, optional
        Internal patches: edges each shared by two blocks (either way round), named as
        interfaces (:mod:`blockmesh.domain.interfaces`); none by default.
    components : int
        How many separate pieces the blocks form (default 1: every block is joined to the
        others through whole edges). Pieces must not touch, not even at a corner.

    Examples
    --------
    >>> from blockmesh import Domain
    >>> d = Domain.from_blocks(
    ...     [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)],
    ...     [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)],
    ...     patches={"inlet": [(4, 0)]},
    ... )
    >>> d.patch_names, len(d.patches["boundary"])
    (('inlet', 'boundary'), 7)

    Two blocks made separately, glued where their corners (almost) coincide:

    >>> left = [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2)]
    >>> right = [(2 + 1e-12, 0), (4, 0), (4.5, 1), (4, 2), (2.5, 1 - 1e-12)]
    >>> d = Domain.from_blocks(
    ...     left + right, [(0, 1, 2, 3, 4), (5, 6, 7, 8, 9)], merge_tol=1e-9
    ... )
    >>> d.n_vertices, d.n_shared_edges
    (8, 1)

    A curved edge:

    >>> from blockmesh.curves import Arc
    >>> curved = Domain.from_blocks(
    ...     [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2)], [(0, 1, 2, 3, 4)],
    ...     edges={(0, 1): Arc(through=(1, -0.3))},
    ... )
    >>> round(curved.area, 6)  # the pentagon's 4.5 and the circular segment below edge 0
    4.90711
    """
    return blocks_domain(
        cls, vertices, blocks, patches, regions, name=name, description=description,
        layout=layout, merge_tol=merge_tol, boundary_source=boundary_source,
        block_source=block_source, edges=edges, interfaces=interfaces,
        components=components, grading=grading,
    )  # fmt: skip


def from_polygon(
    cls: type[Domain],
    coords: Any,
    holes: Iterable[Any] | None = None,
    *,
    name: str = "polygon",
    patches: Mapping[str, Iterable[int | str]] | None = None,
    description: str = "",
    arcs: Mapping[int | str, Curve] | None = None,
    circles: Iterable[Mapping[str, Any]] | None = None,
    size: Any = None,
) -> Domain:
    """Any simple polygon, convex or not, with any number of holes, decomposed into blocks.

    Parameters
    ----------
    coords : sequence of (x, y)
        The outer boundary's corners in order (clockwise is reversed with a warning; a
        repeated closing corner and straight corners are dropped with a warning, except a
        straight corner where two patches meet, which stays as the point where they change).
    holes : sequence of sequences of (x, y), optional
        Each hole's corners in order, either way round.
    patches : mapping of name to a list of polygon edges, optional
        An integer ``i`` is edge ``i`` of the outer boundary (from corner ``i`` to
        ``i + 1`` as given); ``"hole K"`` is every edge of hole ``K`` (0-based);
        ``"hole K:E"`` is edge ``E`` of hole ``K``; ``"left"``, ``"right"``, ``"top"`` and
        ``"bottom"`` are the outer boundary's edges facing that way (their outward normal
        points most nearly there: :func:`blockmesh.geometry.edges_facing`) and not listed
        by number in another patch. Unlisted edges go to ``"boundary"``.
    arcs : mapping of edge to Arc, optional
        Polygon edges that are circular arcs: edge ``i`` of the outer boundary, or
        ``"hole K:E"``, to an :class:`~blockmesh.curves.Arc` (``through`` or ``center``).
    circles : sequence of mappings, optional
        Circular holes, each ``{"center": (x, y), "radius": r}`` with optionally
        ``"patch"`` (a patch name) and ``"sides"`` (of the inscribed polygon decomposed,
        default 8); they are numbered after the ``holes``.
    size : optional
        Cut the polygon into blocks of these sizes (a number, an expression in x and y, a size
        table, a function; see :meth:`~blockmesh.domain.domain.Domain.with_size`) instead of the
        fewest blocks.

    Notes
    -----
    A strictly convex polygon without holes and with at most 16 corners gets the exact
    layouts (the fewest blocks); anything else a quality triangulation with a 9-pentagon
    template per triangle (:func:`blockmesh.decompose.decompose_polygon`).
    :attr:`~blockmesh.domain.domain.Domain.boundary_source` records which polygon edge every
    boundary edge lies on.

    Examples
    --------
    >>> from blockmesh import Domain
    >>> d = Domain.from_polygon([(0, 0), (1, 0), (1, 1), (0, 1)], patches={"bottom": [0]})
    >>> d.n_blocks, d.layout, d.patch_names
    (8, 'quad-template', ('bottom', 'boundary'))
    >>> plate = Domain.from_polygon(
    ...     [(0, 0), (4, 0), (4, 2), (0, 2)],
    ...     holes=[[(1.5, 0.5), (2.5, 0.5), (2.5, 1.5), (1.5, 1.5)]],
    ...     patches={"inlet": [3], "outlet": [1], "hole": ["hole 0"]},
    ... )
    >>> plate.layout, plate.patch_names, round(plate.area, 12)
    ('triangulation', ('inlet', 'outlet', 'hole', 'boundary'), 7.0)
    """
    return polygon_domain(
        cls, coords, holes, name=name, patches=patches, description=description, arcs=arcs,
        circles=circles, size=size,
    )  # fmt: skip


def from_circle(
    cls: type[Domain],
    center: Any,
    radius: float,
    *,
    name: str = "circle",
    patch: str = "boundary",
    description: str = "",
) -> Domain:
    """A disc of 11 blocks with 5 arcs (:func:`blockmesh.domain.curved_polygons.disc_layout`).

    Examples
    --------
    >>> from blockmesh import Domain
    >>> d = Domain.from_circle((1, 2), 0.5, patch="wall")
    >>> d.n_blocks, d.patch_names, round(d.area, 14) == round(3.141592653589793 / 4, 14)
    (11, ('wall',), True)
    """
    return circle_domain(cls, center, radius, name=name, patch=patch, description=description)


def from_shapely(
    cls: type[Domain],
    polygon: Any,
    *,
    name: str = "polygon",
    patches: Mapping[str, Iterable[int | str]] | None = None,
    description: str = "",
    region: str | Iterable[str] | None = None,
) -> Domain:
    """A domain from a shapely Polygon (its exterior and its interiors as holes).

    Edge numbers for ``patches`` are as in :meth:`~blockmesh.domain.domain.Domain.from_polygon`,
    counted along the rings as shapely stores them (the closing point is not a corner).

    A MultiPolygon (or a GeometryCollection of polygons) is a composite domain
    (:meth:`~blockmesh.domain.domain.Domain.compose`): each of its polygons is a part, of the region
    ``partK`` (K its place), or of the regions named by ``region`` (one name per polygon), or all
    of one region when ``region`` is one name. Disjoint pieces are allowed: the mesh then has
    several connected components (``blockmesh check`` says how many).

    Examples
    --------
    >>> from blockmesh import Domain
    >>> import shapely
    >>> ring = shapely.Point(0, 0).buffer(2, quad_segs=4).difference(shapely.box(-1, -1, 1, 1))
    >>> d = Domain.from_shapely(ring, patches={"inner": ["hole 0"]})
    >>> d.patch_names, round(d.area / ring.area, 12)
    (('inner', 'boundary'), 1.0)
    >>> two = shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1)])
    >>> Domain.from_shapely(two).region_names, Domain.from_shapely(two, region="land").area
    (('part0', 'part1'), 2.0)
    """
    return shapely_domain(
        cls, polygon, name=name, patches=patches, description=description, region=region
    )


def compose(
    cls: type[Domain],
    parts: Mapping[str, Any],
    *,
    name: str = "composite",
    description: str = "",
    patches: Mapping[str, Mapping[str, Iterable[int | str]]] | None = None,
    interfaces: Mapping[str, str] | None = None,
) -> Domain:
    """A composite domain: several regions meshed together, conforming across interfaces.

    **A later part is cut out of the earlier ones** (gmsh's boolean fragment): a fibre listed
    after the matrix it lies in makes the matrix a part with a hole and the fibre its own
    region; parts may touch along edges or overlap, and where they overlap the later one
    wins (:mod:`blockmesh.domain.compose`).

    Parameters
    ----------
    parts : mapping of region name to a part, in order
        Each part a shapely Polygon or MultiPolygon, a Domain (curved ones included: its
        arcs stay arcs; its regions are not kept), or a mapping of the polygon form's keys
        (``polygon``, ``holes``, ``arcs``, ``circles``, ``patches``; without ``polygon``,
        ``circles`` are the part's discs).
    patches : mapping of region to a polygon patch mapping, optional
        Patches of a shapely part's edges, as in
        :meth:`~blockmesh.domain.domain.Domain.from_polygon` (``{"matrix": {"left": [3]}}``).
        Edges of a part that end up inside the domain are interfaces, whatever their patch;
        boundary edges no part names go to ``"boundary"``.
    interfaces : mapping of "A|B" to a name, optional
        Names of interfaces; by default the edges between regions ``A`` and ``B`` (``A``
        first in ``parts``) form the interface ``"A|B"``.

    Examples
    --------
    >>> from blockmesh import Domain
    >>> import shapely
    >>> plate = shapely.box(0, 0, 3, 1)
    >>> d = Domain.compose(
    ...     {"steel": plate, "rubber": shapely.box(1, 0, 2, 1)},
    ...     patches={"steel": {"left": [3]}},
    ...     interfaces={"steel|rubber": "glued"},
    ... )
    >>> d.region_names, d.interface_names, d.patch_names
    (('steel', 'rubber'), ('glued',), ('left', 'boundary'))
    >>> steel = d.block_areas()[d.region == 0].sum()  # the rubber cut out of the steel
    >>> round(float(steel), 12), d.components
    (2.0, 1)
    """
    return compose_mapping(
        cls, parts, name=name, description=description, patches=patches, interfaces=interfaces
    )


def from_mesh(
    cls: type[Domain], source: Any, *, name: str | None = None, description: str = ""
) -> Domain:
    """A domain from an existing triangle, quadrilateral or mixed mesh (pentagonal conversion).

    Every triangle becomes its 9-pentagon template and every convex quadrilateral (or other
    convex polygon) its ring-and-hub template (``3 n`` pentagons), with the nodes of every
    element edge at the same symmetric fractions, so the result conforms. Physical groups
    (or line cell sets) become patches; surface groups become regions; each block keeps the
    id of its source element (see :mod:`blockmesh.decompose.conversion`).

    Parameters
    ----------
    source : str or Path or meshio.Mesh
        A mesh file (Gmsh ``.msh``; ``.vtu``, ``.vtk``, ``.xdmf`` and the other formats
        meshio reads) or a meshio mesh.
    name : str, optional
        Default: the file's stem (or ``"mesh"``).
    """
    return mesh_domain(cls, source, name=name, description=description)


def from_toml(cls: type[Domain], path: str | Path) -> Domain:
    """Read a domain file (polygon or explicit blocks); see :mod:`blockmesh.domain.tomlio`."""
    return domain_from_file(cls, path)


def from_toml_text(cls: type[Domain], text: str, *, name: str = "domain") -> Domain:
    """A domain from TOML text (as in a domain file).

    Examples
    --------
    >>> from blockmesh import Domain
    >>> Domain.from_toml_text("polygon = [[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]]").area
    6.0
    """
    return domain_from_text(cls, text, name=name)
