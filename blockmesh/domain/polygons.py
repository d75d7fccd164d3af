"""A polygon with holes, or shapely geometry, made a Domain: decomposed, its edges traced.

The polygon forms of :class:`~blockmesh.Domain` (:meth:`~blockmesh.Domain.from_polygon`,
:meth:`~blockmesh.Domain.from_shapely`): the rings are checked
(:func:`~blockmesh.domain.validate.check_rings`), decomposed
(:func:`blockmesh.decompose.decompose_polygon`), and every block edge on the boundary is traced
back to the polygon edge it lies on, for :attr:`~blockmesh.Domain.boundary_source` and the
patches; arcs and circles go through :mod:`~blockmesh.domain.curved_polygons`, a MultiPolygon
through :func:`~blockmesh.domain.compose.compose_parts`.

Examples
--------
>>> from blockmesh import Domain
>>> d = polygon_domain(Domain, [(0, 0), (1, 0), (1, 1), (0, 1)], patches={"bottom": [0]})
>>> d.patch_names, d.boundary_source[:3].tolist()
(('bottom', 'boundary'), [[0, 0], [0, 0], [0, 1]])
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh.checks import readonly
from blockmesh.decompose import decompose_polygon
from blockmesh.decompose.polygon import check_corner_count
from blockmesh.domain.compose import compose_parts
from blockmesh.domain.curved_polygons import curved_polygon
from blockmesh.domain.parts import part_from_shapely, part_from_value
from blockmesh.domain.polygon_edges import facing_resolved, hole_list, ring_edge_patches
from blockmesh.domain.validate.points import parse_points
from blockmesh.domain.validate.rings import Ring, check_rings
from blockmesh.errors import ArgumentTypeError, DomainError

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["edge_chains", "polygon_domain", "shapely_domain"]


def polygon_domain(
    cls: type[Domain], coords: Any, holes: Any = None, *, size: Any = None, **options: Any
) -> Domain:
    """The Domain of :meth:`blockmesh.Domain.from_polygon` (see there), as ``cls``.

    ``options`` are the method's other keywords (``name``, ``patches``, ``description``,
    ``arcs``, ``circles``).
    """
    name, description = options.get("name", "polygon"), options.get("description", "")
    patches, arcs, circles = options.get("patches"), options.get("arcs"), options.get("circles")
    holes = hole_list(holes) if holes is not None else []
    check_corner_count(sum(len(r) if hasattr(r, "__len__") else 0 for r in (coords, *holes)))
    if size is not None:
        unsized = polygon_domain(cls, coords, holes, **options)
        return unsized.with_size(size)
    patches = facing_resolved(patches, coords)
    if arcs or circles:  # decomposed through the chords, then curved: domain.curved_polygons
        return curved_polygon(
            cls, coords, holes, arcs=arcs, circles=circles, patches=patches, name=name,
            description=description,
        )  # fmt: skip

    given = [parse_points(coords, "polygon vertex")]
    for k, hole in enumerate(hole_list(holes)):
        given.append(parse_points(hole, f"hole {k} vertex"))
    edge_patch = ring_edge_patches(patches, [len(g) for g in given])
    rings = check_rings(given, edge_patch)
    decomposition = decompose_polygon([r.points for r in rings])
    chains = [decomposition.edge_chains, *decomposition.hole_chains]
    named: dict[str, list[tuple[int, int]]] = {}
    source: dict[tuple[int, int], tuple[int, int]] = {}
    for r, (ring, ring_chains) in enumerate(zip(rings, chains, strict=True)):
        for i, chain in enumerate(ring_chains):
            for a, b, edge in _steps_on_input_edges(ring, i, chain, decomposition.vertices):
                source[(a, b)] = (r, edge)
                patch_name = edge_patch[r][edge] if edge_patch is not None else None
                if patch_name is not None:
                    named.setdefault(patch_name, []).append((a, b))
    # Keep the user's patch order.
    order = list(patches or {})
    named = {k: named[k] for k in order if k in named}
    return cls._from_parsed(
        np.array(decomposition.vertices),
        np.array(decomposition.blocks),
        named,
        None,
        made_for="the polygon",
        name=name,
        description=description,
        layout=decomposition.layout,
        boundary_source=source,
    )


def shapely_domain(
    cls: type[Domain], polygon: Any, *, region: Any = None, **options: Any
) -> Domain:
    """The Domain of :meth:`blockmesh.Domain.from_shapely` (see there), as ``cls``.

    ``options`` are the method's other keywords (``name``, ``patches``, ``description``).
    """
    name, description = options.get("name", "polygon"), options.get("description", "")
    patches = options.get("patches")
    import shapely

    if isinstance(polygon, shapely.MultiPolygon | shapely.GeometryCollection):
        return _from_pieces(cls, polygon, region, name, patches, description)
    if not isinstance(polygon, shapely.Polygon):
        raise ArgumentTypeError(
            f"from_shapely takes a shapely Polygon or MultiPolygon, got {type(polygon).__name__}"
        )
    if region is not None:
        raise DomainError(
            "region names the regions of a MultiPolygon's pieces; a Polygon is one region"
        )
    if polygon.is_empty:
        raise DomainError("the shapely polygon is empty")
    exterior = np.asarray(polygon.exterior.coords)[:-1, :2]
    holes = [np.asarray(ring.coords)[:-1, :2] for ring in polygon.interiors]
    # shapely keeps rings either way round: reversing a clockwise one is no news to report.
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        domain = polygon_domain(cls, exterior, holes, **options)
    for warning in caught:
        if not str(warning.message).startswith("the polygon was given clockwise"):
            warnings.warn_explicit(
                warning.message, warning.category, warning.filename, warning.lineno
            )
    return domain


def _steps_on_input_edges(
    ring: Ring, i: int, chain: np.ndarray, vertices: np.ndarray
) -> list[tuple[int, int, int]]:
    """The block edges ``(a, b)`` along output edge ``i`` of a ring, each with its input edge.

    Where straight corners were dropped, output edge ``i`` runs along several input edges; a
    block edge goes to the one its midpoint lies on.
    """
    inputs = ring.input_edges(i)
    steps = list(zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True))
    if len(inputs) == 1:
        return [(a, b, inputs[0]) for a, b in steps]
    # The dropped corners, in order along the edge: where one input edge hands over to the next.
    dropped = inputs[:-1] if ring.reversed else inputs[1:]
    start = vertices[chain[0]]
    direction = vertices[chain[-1]] - start
    scale = float(direction @ direction)
    breaks = (ring.given[dropped] - start) @ direction / scale
    middles = ((vertices[chain[:-1]] + vertices[chain[1:]]) / 2 - start) @ direction / scale
    which = np.searchsorted(breaks, middles)
    return [(a, b, inputs[int(k)]) for (a, b), k in zip(steps, which, strict=True)]


def _from_pieces(
    cls: type[Domain],
    multi: Any,
    region: str | Iterable[str] | None,
    name: str,
    patches: Mapping[str, Iterable[int | str]] | None,
    description: str,
) -> Domain:
    """The composite domain of a MultiPolygon's pieces (see :meth:`Domain.from_shapely`)."""
    pieces = list(multi.geoms)
    if patches:
        raise DomainError(
            "patches of a MultiPolygon's pieces: use Domain.compose with one part per piece "
            "(patches={region: {patch: [edges]}})"
        )
    if isinstance(region, str):
        parts = [part_from_shapely(region, multi, f"part 0 ({region!r})")]
    else:
        names = [f"part{k}" for k in range(len(pieces))] if region is None else list(region)
        if len(names) != len(pieces):
            raise DomainError(
                f"region gives {len(names)} names for the {len(pieces)} pieces of the "
                "MultiPolygon; give one name per piece (or one name for all)"
            )
        parts = [
            part_from_value(cls, label, piece, k)
            for k, (label, piece) in enumerate(zip(names, pieces, strict=True))
        ]
    return compose_parts(cls, parts, name=name, description=description)


def edge_chains(
    boundary_edges: np.ndarray, boundary_source: np.ndarray
) -> Mapping[tuple[int, int], np.ndarray]:
    """The block vertices along each polygon edge (:attr:`blockmesh.Domain.polygon_edges`)."""
    chains: dict[tuple[int, int], np.ndarray] = {}
    known = boundary_source[:, 0] >= 0
    if not known.any():
        return MappingProxyType(chains)
    keys = boundary_source[known, 0] * (boundary_edges.shape[0] + 1)
    keys = keys + boundary_source[known, 1]
    edges = boundary_edges[known]
    order = np.argsort(keys, kind="stable")
    keys, edges = keys[order], edges[order]
    starts = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    for lo, hi in zip(starts, np.r_[starts[1:], keys.size], strict=True):
        run = edges[lo:hi]
        following = dict(zip(run[:, 0].tolist(), run[:, 1].tolist(), strict=True))
        first = next(a for a in following if a not in set(run[:, 1].tolist()))
        chain = [first]
        while chain[-1] in following:
            chain.append(following[chain[-1]])
        ring, edge = (int(x) for x in boundary_source[known][order][lo])
        chains[(ring, edge)] = readonly(np.array(chain, dtype=np.int64), np.int64)
    return MappingProxyType(chains)
