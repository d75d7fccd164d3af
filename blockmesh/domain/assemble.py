"""A Domain's fields checked and stored: the checks every Domain passes, however it is made.

``Domain(...)`` runs :func:`check_fields` on construction (an invalid domain never exists); the
constructors go through :func:`from_parsed`, which checks parsed blocks, resolves their patches,
regions, interfaces, curves and grading, and stores them without a second check
(:func:`trusted`).

Examples
--------
>>> import numpy as np
>>> from blockmesh import Domain
>>> corners = np.array([[0.0, 0.0], [2.0, 0.0], [3.0, 1.0], [1.0, 3.0], [0.0, 2.0]])
>>> d = from_parsed(Domain, corners, np.array([[0, 1, 2, 3, 4]]), {"floor": [(0, 1)]}, None)
>>> d.patch_names, d.region_names, d.name
(('floor', 'boundary'), ('domain',), 'blocks')
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable, Mapping
from dataclasses import MISSING, fields
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh.checks import readonly
from blockmesh.curves.types import Curve
from blockmesh.domain.curve_checks import CHECK_LEVELS, check_curved_blocks, resolve_curves
from blockmesh.domain.interfaces import resolve_interfaces
from blockmesh.domain.merge import merge_vertices, merged_edges
from blockmesh.domain.validate.blocks import check_block_shapes, parse_blocks
from blockmesh.domain.validate.names import resolve_patches, resolve_regions
from blockmesh.domain.validate.points import parse_points
from blockmesh.domain.validate.topology import check_topology
from blockmesh.errors import BlockMeshError, DomainError, DomainFormatError, TopologyError
from blockmesh.geometry.topology import boundary_loops, cell_neighbours
from blockmesh.refinement.grading import check_grading

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = [
    "block_source_rows",
    "blocks_domain",
    "boundary_source_rows",
    "check_fields",
    "check_interfaces",
    "check_text",
    "checked_curves",
    "components_count",
    "from_parsed",
    "neighbours",
    "store",
    "trusted",
]


def check_fields(domain: Domain) -> None:
    """Check every field of ``domain`` (as given to ``Domain(...)``) and store them read-only."""
    vertices = parse_points(domain.vertices, "vertex")
    blocks = parse_blocks(domain.blocks, vertices.shape[0])
    check_block_shapes(vertices, blocks, repair=False)
    neighbour = neighbours(blocks, vertices.shape[0])
    check_topology(vertices, blocks, neighbour, components_count(domain.components))
    boundary = boundary_loops(blocks, neighbour)
    given = np.asarray(domain.boundary_edges, dtype=np.int64).reshape(-1, 2)
    if not np.array_equal(given, boundary):
        raise DomainError(
            "boundary_edges must be the blocks' boundary edges in loop order; build domains "
            "with Domain.from_blocks() or Domain.from_polygon()"
        )
    patch = np.asarray(domain.boundary_patch, dtype=np.int64)
    region = np.asarray(domain.region, dtype=np.int64)
    if patch.shape != (boundary.shape[0],) or not np.all(
        (patch >= 0) & (patch < len(domain.patch_names))
    ):
        raise DomainError("every boundary edge needs one patch (an index into patch_names)")
    if region.shape != (blocks.shape[0],) or not np.all(
        (region >= 0) & (region < len(domain.region_names))
    ):
        raise DomainError("every block needs one region (an index into region_names)")
    object.__setattr__(domain, "curves", checked_curves(vertices, blocks, domain.curves))
    object.__setattr__(domain, "grading", check_grading(domain.grading, blocks, domain.curves))
    store(domain, vertices, blocks, boundary, patch, region, neighbour)
    check_interfaces(domain)


def check_interfaces(domain: Domain) -> None:
    """Every interface edge an edge of two blocks, indices in range, names of their own."""
    edges, patch = domain.interface_edges, domain.interface_patch
    if patch.shape != (edges.shape[0],) or not np.all(
        (patch >= 0) & (patch < len(domain.interface_names))
    ):
        raise DomainError(
            "every interface edge needs one interface (an index into interface_names)"
        )
    names = {name: edges[patch == k].tolist() for k, name in enumerate(domain.interface_names)}
    resolve_interfaces(domain.blocks, domain.region, names, domain.patch_names)


def store(domain: Domain, vertices, blocks, boundary, patch, region, neighbour) -> None:
    """Set the checked arrays on ``domain``, read-only, and the other fields in their types."""
    set_ = object.__setattr__
    set_(domain, "vertices", readonly(vertices, np.float64))
    set_(domain, "blocks", readonly(blocks, np.int64))
    set_(domain, "boundary_edges", readonly(boundary, np.int64))
    set_(domain, "boundary_patch", readonly(patch, np.int64))
    set_(domain, "region", readonly(region, np.int64))
    set_(domain, "patch_names", tuple(domain.patch_names))
    set_(domain, "region_names", tuple(domain.region_names))
    set_(domain, "_neighbour", readonly(neighbour, np.int64))
    set_(domain, "boundary_source", boundary_source_rows(domain.boundary_source, boundary.shape[0]))
    set_(domain, "block_source", block_source_rows(domain.block_source, blocks.shape[0]))
    set_(domain, "curves", MappingProxyType(dict(domain.curves)))
    edges, patch, names = domain.interface_edges, domain.interface_patch, domain.interface_names
    if edges is MISSING or edges is None:
        edges, patch, names = np.zeros((0, 2)), np.zeros(0), ()
    set_(domain, "interface_edges", readonly(np.asarray(edges).reshape(-1, 2), np.int64))
    set_(domain, "interface_patch", readonly(np.asarray(patch).reshape(-1), np.int64))
    set_(domain, "interface_names", tuple(names))
    set_(domain, "grading", MappingProxyType(dict(domain.grading or {})))


def trusted(cls: type[Domain], *, neighbour: np.ndarray, **values: Any) -> Domain:
    """A ``cls`` from data :func:`from_parsed` has just checked (no second validation)."""
    domain = object.__new__(cls)
    for f in fields(cls):
        if f.name != "_neighbour":
            object.__setattr__(domain, f.name, values.get(f.name, f.default))
    store(
        domain,
        values["vertices"],
        values["blocks"],
        values["boundary_edges"],
        values["boundary_patch"],
        values["region"],
        neighbour,
    )
    return domain


def blocks_domain(
    cls: type[Domain], vertices: Any, blocks: Any, patches: Any, regions: Any, **options: Any
) -> Domain:
    """The Domain of :meth:`blockmesh.Domain.from_blocks` (see there), as ``cls``.

    ``options`` are the method's keywords: ``merge_tol`` merges the vertices first (and maps
    the vertex ids of ``patches``, ``interfaces``, ``edges`` and ``grading``); the others go to
    :func:`from_parsed` as they are.
    """
    merge_tol = options.pop("merge_tol", None)
    edges, grading = options.pop("edges", None), options.pop("grading", None)
    interfaces = options.pop("interfaces", None)
    points = parse_points(vertices, "vertex")
    block_ids = parse_blocks(blocks, points.shape[0])
    if merge_tol is not None:
        given = points
        points, block_ids, (patches, interfaces) = merge_vertices(
            points, block_ids, (patches, interfaces), merge_tol
        )
        edges = merged_edges(edges, given, points)
        grading = merged_edges(grading, given, points)
    return from_parsed(
        cls,
        points,
        block_ids,
        patches,
        regions,
        edges=edges,
        interfaces=interfaces,
        grading=grading,
        **options,
    )


def from_parsed(
    cls: type[Domain],
    points: np.ndarray,
    block_ids: np.ndarray,
    patches: Any,
    regions: Any,
    *,
    made_for: str | None = None,
    boundary_source: Mapping[tuple[int, int], tuple[int, int]] | None = None,
    block_source: Any = None,
    edges: Mapping[tuple[int, int], Curve] | None = None,
    curve_levels: int = CHECK_LEVELS,
    grading: Mapping[tuple[int, int], float] | None = None,
    interfaces: Mapping[str, Iterable] | None = None,
    components: int = 1,
    **text: str,
) -> Domain:
    """Check parsed blocks and build the Domain (a ``cls``).

    ``made_for`` names what blockmesh decomposed, so that its own blocks failing the checks
    read as "too thin" rather than as a fault in blocks the user never wrote.
    ``curve_levels`` is how deep curved blocks are refined to be checked.
    """
    try:
        block_ids = check_block_shapes(points, block_ids, repair=made_for is None)
        neighbour = neighbours(block_ids, points.shape[0])
        check_topology(points, block_ids, neighbour, components_count(components))
    except (DomainError, TopologyError) as error:
        if made_for is None:
            raise
        lines = [line.strip() for line in str(error).splitlines()]
        first = lines[1] if len(lines) > 1 and lines[0].endswith("problems:") else lines[0]
        raise DomainError(
            f"{made_for} is too thin (or too small for where it sits) to decompose in double "
            f"precision: the blocks made for it fail their own check ({first}); widen its "
            "thinnest part or move it nearer the origin"
        ) from None
    boundary = boundary_loops(block_ids, neighbour)
    patch_names, patch = resolve_patches(boundary, patches, block_ids)
    region_names, region = resolve_regions(block_ids.shape[0], regions)
    interface_names, interface_edges, interface_patch = resolve_interfaces(
        block_ids, region, interfaces, patch_names
    )
    curves = checked_curves(points, block_ids, edges, curve_levels)
    graded = check_grading(grading, block_ids, curves)
    source = None
    if boundary_source is not None:
        source = np.array(
            [boundary_source.get((int(a), int(b)), (-1, -1)) for a, b in boundary],
            dtype=np.int64,
        ).reshape(-1, 2)
    return trusted(
        cls,
        neighbour=neighbour,
        name=check_text(text.get("name", "blocks"), "name"),
        vertices=points,
        blocks=block_ids,
        boundary_edges=boundary,
        boundary_patch=patch,
        patch_names=patch_names,
        region=region,
        region_names=region_names,
        description=check_text(text.get("description", ""), "description"),
        layout=text.get("layout", "blocks"),
        boundary_source=source,
        block_source=block_source,
        curves=curves,
        interface_edges=interface_edges,
        interface_patch=interface_patch,
        interface_names=interface_names,
        components=components,
        grading=graded,
    )


def check_text(value: object, what: str) -> str:
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


def checked_curves(
    vertices: np.ndarray, blocks: np.ndarray, edges: Mapping | None, levels: int = CHECK_LEVELS
) -> dict[tuple[int, int], Curve]:
    """The curves of ``edges`` bound to their vertices, after the blocks are checked with them."""
    curves = resolve_curves(vertices, blocks, edges)
    check_curved_blocks(vertices, blocks, curves, levels)
    return curves


def neighbours(blocks: np.ndarray, n_vertices: int) -> np.ndarray:
    """The blocks' neighbours; where they overlap (an edge of three blocks), a TopologyError."""
    try:
        return cell_neighbours(blocks, n_vertices)
    except BlockMeshError as error:
        raise TopologyError(f"{error}: the blocks overlap there") from None


def boundary_source_rows(source: Any, n_boundary: int) -> np.ndarray:
    """The ``boundary_source`` field checked: one ``(ring, edge)`` row per boundary edge."""
    return _source_rows(
        source, (n_boundary, 2), "boundary_source must have one (ring, edge) row per boundary edge"
    )


def components_count(value: object) -> int:
    """``value`` as a number of pieces (a whole number >= 1), or DomainFormatError."""
    if not isinstance(value, numbers.Integral) or isinstance(value, bool) or int(value) < 1:
        raise DomainFormatError(f"components must be a whole number >= 1, got {value!r}")
    return int(value)


def block_source_rows(source: Any, n_blocks: int) -> np.ndarray:
    """The ``block_source`` field checked: one element number per block."""
    return _source_rows(source, (n_blocks,), "block_source must have one entry per block")


def _source_rows(source: Any, shape: tuple[int, ...], what: str) -> np.ndarray:
    """``source`` as a read-only int64 array of ``shape``; all -1 (not known) when not given."""
    if source is None or source is MISSING or np.size(source) == 0:
        return readonly(np.full(shape, -1, dtype=np.int64), np.int64)
    array = np.asarray(source, dtype=np.int64)
    if array.shape != shape:
        raise DomainError(f"{what}, shape {shape}, got {array.shape}")
    return readonly(array, np.int64)
