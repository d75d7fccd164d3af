"""Edges of a polygon as a user names them: ``i``, ``"hole K"``, ``"hole K:E"``.

The polygon forms of a domain (:meth:`blockmesh.Domain.from_polygon`, a part of a composite
domain, a GeoJSON feature) put polygon edges in patches by these names: an integer ``i`` is edge
``i`` of the outer boundary (from corner ``i`` to ``i + 1`` as given), ``"hole K"`` every edge of
hole ``K`` and ``"hole K:E"`` edge ``E`` of hole ``K`` (0-based).

Examples
--------
>>> ring_edge_patches({"inlet": [3], "wall": ["hole 0"]}, [4, 3])
[[None, None, None, 'inlet'], ['wall', 'wall', 'wall']]
"""

from __future__ import annotations

import numbers
import re
from collections.abc import Iterable, Mapping
from typing import Any

from blockmesh.errors import DomainError, DomainFormatError

__all__ = ["HOLE_EDGE", "hole_list", "ring_edge_patches", "ring_edges"]


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
        f'an outer edge index 0..{sizes[0] - 1}, "hole K" (every edge of hole K) or '
        '"hole K:E" (edge E of hole K)'
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
