"""The parts of a composite domain as shapes, each later part cut out of the earlier ones.

:func:`part_shape` makes a part's followed outlines one valid shapely (Multi)Polygon,
:func:`fragments` cuts each part out of the earlier ones (the regions), and
:class:`SourcePieces` remembers every piece of every outline, to name the parts near a point in
messages and to find the patch of a boundary edge.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import shapely

from blockmesh.domain.compose.circles import FollowedRing
from blockmesh.domain.interfaces import default_interface_name
from blockmesh.domain.parts import Part
from blockmesh.errors import BlockMeshWarning, DomainError, fmt_point

__all__ = ["SourcePieces", "fragments", "part_shape", "report_filled_holes"]


def part_shape(part: Part, rings: list[list[FollowedRing]]) -> Any:
    """The part as one valid shapely (Multi)Polygon; a located error when it is not valid."""
    polygons = []
    for polygon, followed in zip(part.polygons, rings, strict=True):
        shape = shapely.Polygon(followed[0].xy, [r.xy for r in followed[1:]])
        if not shapely.is_valid(shape):
            reason = shapely.is_valid_reason(shape)
            raise DomainError(
                f"{part.label} is not a valid polygon ({_reason(reason)}): its outline must not "
                "cross or touch itself, and its holes must lie inside it, apart from each other"
            )
        if shape.area <= 0:
            raise DomainError(f"{part.label} has no area")
        del polygon
        polygons.append(shape)
    union = shapely.union_all(polygons)
    if len(polygons) > 1 and not math.isclose(
        union.area, sum(p.area for p in polygons), rel_tol=1e-9
    ):
        raise DomainError(
            f"the polygons of {part.label} overlap; a part's polygons are its separate pieces "
            "(give overlapping pieces as separate parts, where the later one is cut out of the "
            "earlier)"
        )
    return union


def _reason(text: str) -> str:
    """Shapely's validity reason with its point as blockmesh shows points."""
    if "[" in text and text.endswith("]"):
        what, _, where = text.partition("[")
        try:
            x, y = (float(v) for v in where[:-1].split()[:2])
        except ValueError:
            return text
        return f"{what.strip().lower()} near {fmt_point((x, y))}"
    return text


def fragments(parts: list[Part], shapes: list[Any]) -> list[Any]:
    """Region ``i``: part ``i`` minus every later part. A part left empty is an error."""
    regions: list[Any] = [None] * len(parts)
    covered = shapely.Polygon()
    for i in range(len(parts) - 1, -1, -1):
        region = shapely.difference(shapes[i], covered) if not covered.is_empty else shapes[i]
        region = shapely.union_all(
            [g for g in shapely.get_parts(region) if isinstance(g, shapely.Polygon)]
        )
        if region.is_empty or region.area <= 1e-12 * shapes[i].area:
            later = [
                p.label
                for p in parts[i + 1 :]
                if shapely.intersects(shapes[i], shapes[parts.index(p)])
            ]
            raise DomainError(
                f"{parts[i].label} is covered entirely by the later {', '.join(later)}: a later "
                "part is cut out of the earlier ones, so nothing is left of it; list it after "
                "them (to cut it out of them), or leave it out"
            )
        regions[i] = region
        covered = shapely.union_all([covered, shapes[i]]) if not covered.is_empty else shapes[i]
    return regions


class SourcePieces:
    """Every followed piece of every part's outline: the parts near a point, patches, curves."""

    def __init__(self, parts: list[Part], rings: list[list[list[FollowedRing]]]) -> None:
        lines, owner, patch = [], [], []
        self.curves: dict[tuple[float, float, float, float], int] = {}
        for i, part_rings in enumerate(rings):
            for polygon in part_rings:
                for ring in polygon:
                    xy = ring.xy
                    ahead = np.roll(xy, -1, axis=0)
                    lines += shapely.linestrings(np.stack([xy, ahead], axis=1)).tolist()
                    owner += [i] * len(xy)
                    patch += ring.patch
                    for (ax, ay), (bx, by), k in zip(
                        xy.tolist(), ahead.tolist(), ring.curve, strict=True
                    ):
                        self.curves[_piece_key(ax, ay, bx, by)] = k
        self.parts = parts
        self.lines = np.array(lines, dtype=object)
        self.owner = np.array(owner, dtype=np.int64)
        self.patch = patch
        self.tree = shapely.STRtree(self.lines)

    def curve(self, p: Any, q: Any) -> int:
        """The circle a followed piece from ``p`` to ``q`` is a chord of: its index, else -1.

        -1 also for two points no outline joins by one piece (a piece of a straight edge
        another outline crosses). Outlines share a piece only along one curve
        (:func:`~blockmesh.domain.compose.circles.split_shared_chords`).
        """
        return self.curves.get(_piece_key(float(p[0]), float(p[1]), float(q[0]), float(q[1])), -1)

    def near(self, point: Any, distance: float) -> list[str]:
        """The labels of the parts whose outline passes within ``distance`` of ``point``."""
        hits = self.tree.query(shapely.Point(*point), predicate="dwithin", distance=distance)
        found = sorted(set(self.owner[hits].tolist()))
        return [self.parts[i].label for i in found]

    def patches_at(self, points: np.ndarray, distance: float) -> list[str | None]:
        """At each point, the patch of the latest part whose outline passes there (or None)."""
        where, hit = self.tree.query(shapely.points(points), predicate="dwithin", distance=distance)
        out: list[str | None] = [None] * len(points)
        best = [-1] * len(points)
        for k, h in zip(where.tolist(), hit.tolist(), strict=True):
            name = self.patch[h]
            if name is not None and self.owner[h] > best[k]:
                out[k] = name
                best[k] = int(self.owner[h])
        return out


def _piece_key(ax: float, ay: float, bx: float, by: float) -> tuple[float, float, float, float]:
    """A piece by its two ends, the same whichever way it is run."""
    return (ax, ay, bx, by) if (ax, ay) <= (bx, by) else (bx, by, ax, ay)


def report_filled_holes(
    parts: list[Part], rings: list[list[list[FollowedRing]]], regions: list[Any], tol: float
) -> None:
    """Say how a hole of one part that another part's region fills is read (a warning)."""
    for i, part in enumerate(parts):
        for polygon, followed in zip(part.polygons, rings[i], strict=True):
            for outline, ring in zip(polygon[1:], followed[1:], strict=True):
                hole = shapely.Polygon(ring.xy)
                for j, region in enumerate(regions):
                    if j == i:
                        continue
                    shared = shapely.intersection(hole, region).area
                    if shared <= tol * tol:
                        continue
                    share = "fills" if shared >= hole.area * (1 - 1e-9) else "fills part of"
                    first, second = sorted((i, j))
                    interface = default_interface_name(parts[first].region, parts[second].region)
                    warnings.warn(
                        f"{outline.label} of {part.label} is not empty: {parts[j].label} "
                        f"{share} it, so its edge is read as the interface {interface!r} "
                        "between them (a hole stays empty only where no part covers it)",
                        BlockMeshWarning,
                        stacklevel=6,
                    )
