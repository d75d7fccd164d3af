"""Edges of a polygon as a user names them: ``i``, ``"hole K"``, ``"hole K:E"``, ``"left"``.

The polygon forms of a domain (:meth:`blockmesh.Domain.from_polygon`, a part of a composite
domain, a GeoJSON feature) put polygon edges in patches by these names: an integer ``i`` is edge
``i`` of the outer boundary (from corner ``i`` to ``i + 1`` as given), ``"hole K"`` every edge of
hole ``K`` and ``"hole K:E"`` edge ``E`` of hole ``K`` (0-based); ``"left"``, ``"right"``,
``"top"`` and ``"bottom"`` are the outer edges facing that way that no patch lists by number
(:func:`facing_resolved`).

Examples
--------
>>> ring_edge_patches({"inlet": [3], "wall": ["hole 0"]}, [4, 3])
[[None, None, None, 'inlet'], ['wall', 'wall', 'wall']]
>>> facing_resolved({"inlet": ["left"], "top": [2]}, [(0, 0), (2, 0), (2, 1), (0, 1)])
{'inlet': [3], 'top': [2]}
"""

from __future__ import annotations

import numbers
import re
from collections.abc import Iterable, Mapping
from typing import Any

from blockmesh.domain.validate.points import parse_points
from blockmesh.errors import DomainError, DomainFormatError
from blockmesh.geometry.polygons import DIRECTIONS, edges_facing

__all__ = ["HOLE_EDGE", "facing_resolved", "hole_list", "ring_edge_patches", "ring_edges"]


def hole_list(holes: Any) -> list[Any]:
    """The holes as a list (none for None); a located error for anything but a list of rings."""
    if holes is None:
        return []
    if isinstance(holes, str | bytes) or not isinstance(holes, Iterable):
        raise DomainFormatError(
            f"holes must be a list of rings (each a list of [x, y] corners), got "
            f"{type(holes).__name__}"
        )
    return list(holes)


#: ``"hole K"`` (every edge of hole K) or ``"hole K:E"`` (its edge E) in a polygon's patches.
HOLE_EDGE = re.compile(r"^hole (\d+)(?::(\d+))?$")


def facing_resolved(patches: Any, coords: Any) -> Any:
    """``patches`` with the direction words (``"left"`` ...) replaced by outer edge indices.

    ``coords`` are the outer boundary's corners. An edge a patch lists by number (or by another
    word) stays there: a word takes the edges facing its way that nothing else claims.
    """
    if not isinstance(patches, Mapping):
        return patches
    words = {
        name: [e for e in edges if isinstance(e, str) and e.strip().lower() in DIRECTIONS]
        for name, edges in patches.items()
        if not isinstance(edges, str | bytes) and isinstance(edges, Iterable)
    }
    if not any(words.values()):
        return patches
    facing = edges_facing(parse_points(coords, "polygon vertex"))
    claimed: set[int] = {
        int(e)
        for edges in patches.values()
        if not isinstance(edges, str | bytes) and isinstance(edges, Iterable)
        for e in edges
        if isinstance(e, numbers.Integral)
    }
    resolved: dict[str, Any] = {}
    for name, edges in patches.items():
        if not words.get(name):
            resolved[name] = edges
            continue
        listed = [e for e in edges if e not in words[name]]
        for word in words[name]:
            taken = [i for i in facing[word.strip().lower()] if i not in claimed]
            listed += taken
            claimed.update(taken)
        resolved[name] = listed
    return resolved


def ring_edge_patches(
    patches: Mapping[str, Iterable[int | str]] | None, sizes: list[int]
) -> list[list[str | None]] | None:
    """Each ring's edges' patch names from the polygon form of ``patches``; None if none given."""
    if not patches:
        return None
    if not isinstance(patches, Mapping):
        raise DomainFormatError(
            f"patches must map patch names to polygon edges, got {type(patches).__name__}"
        )
    edge_patch: list[list[str | None]] = [[None] * n for n in sizes]
    for patch_name, edges in patches.items():
        if isinstance(edges, str | bytes) or not isinstance(edges, Iterable):
            raise DomainFormatError(
                f"patch {patch_name!r} must be a list of polygon edges, got {edges!r}"
            )
        for edge in edges:
            for ring, index in ring_edges(patch_name, edge, sizes):
                owner = edge_patch[ring][index]
                where = f"edge {index}" if ring == 0 else f"hole {ring - 1} edge {index}"
                if owner is not None and owner != patch_name:
                    raise DomainError(
                        f"polygon {where} is in patches {owner!r} and {patch_name!r}; an edge "
                        "belongs to one patch"
                    )
                edge_patch[ring][index] = str(patch_name)
    return edge_patch


def ring_edges(patch_name: str, edge: object, sizes: list[int]) -> list[tuple[int, int]]:
    """The (ring, edge) pairs one item of a polygon patch list names."""
    forms = (
        f'an outer edge index 0..{sizes[0] - 1}, "hole K" (every edge of hole K), '
        '"hole K:E" (edge E of hole K) or left, right, top, bottom (the outer edges facing '
        "that way)"
    )
    if isinstance(edge, numbers.Integral) and not isinstance(edge, bool):
        if not 0 <= int(edge) < sizes[0]:
            raise DomainError(
                f"patch {patch_name!r} names edge {edge}, but the polygon's edges are numbered "
                f"0..{sizes[0] - 1}"
            )
        return [(0, int(edge))]
    match = HOLE_EDGE.match(edge.strip()) if isinstance(edge, str) else None
    if match is None:
        raise DomainFormatError(
            f"patch {patch_name!r} has {edge!r}; for a polygon, a patch lists {forms} (edge i runs "
            "from corner i to corner i+1)"
        )
    hole = int(match.group(1))
    if hole >= len(sizes) - 1:
        have = f"holes 0..{len(sizes) - 2}" if len(sizes) > 1 else "no holes"
        raise DomainError(f"patch {patch_name!r} names hole {hole}, but the polygon has {have}")
    n = sizes[hole + 1]
    if match.group(2) is None:
        return [(hole + 1, i) for i in range(n)]
    index = int(match.group(2))
    if index >= n:
        raise DomainError(
            f"patch {patch_name!r} names edge {index} of hole {hole}, whose edges are numbered "
            f"0..{n - 1}"
        )
    return [(hole + 1, index)]
