"""The faces of the fragmented parts over one point set, and the checks of the arrangement.

:meth:`Arrangement.of` nodes the regions' boundaries, finds the faces (each a connected piece of
one region, its rings point ids of one point set, in a canonical order) and checks them: faces
touching themselves, parts meeting at a point only, slivers and gaps thinner than
:data:`~blockmesh.domain.validate.NEAR_TOL` times the domain's size, each a located
:class:`~blockmesh.errors.DomainError` naming the parts.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from blockmesh.domain.compose.fragments import SourcePieces
from blockmesh.domain.parts import Part
from blockmesh.domain.validate.tolerances import NEAR_TOL
from blockmesh.errors import DomainError, fmt_point

__all__ = ["Arrangement"]


@dataclass
class Arrangement:
    """The faces of the fragmented parts over one point set, and what lies on their edges."""

    points: np.ndarray
    faces: list[list[np.ndarray]]
    face_region: np.ndarray
    edge_faces: dict[tuple[int, int], list[int]]  # undirected edge -> faces on it

    @classmethod
    def of(cls, parts: list[Part], regions: list[Any], pieces: SourcePieces, tol: float):
        """The checked arrangement of the regions (parts cut out of the earlier ones)."""
        lines = shapely.union_all([shapely.boundary(r) for r in regions])
        polygons = [
            p for p in shapely.get_parts(shapely.polygonize(shapely.get_parts(lines)))
            if isinstance(p, shapely.Polygon) and not p.is_empty
        ]  # fmt: skip
        inside = shapely.point_on_surface(polygons) if polygons else []
        tree = shapely.STRtree(regions)
        owner = np.full(len(polygons), -1, dtype=np.int64)
        at, hit = tree.query(inside, predicate="within")
        owner[at] = hit
        for k in np.flatnonzero(owner < 0).tolist():  # a hole of the union: it must not be thin
            _check_thin(polygons[k], None, pieces, tol)
        kept = [k for k in range(len(polygons)) if owner[k] >= 0]
        # A canonical order, whatever the input's ring starts and directions.
        key = [(int(owner[k]), *_lowest(polygons[k])) for k in kept]
        kept = [k for _, k in sorted(zip(key, kept, strict=True))]
        ids: dict[tuple[float, float], int] = {}
        faces: list[list[np.ndarray]] = []
        for k in kept:
            polygon = polygons[k]
            rings = [_canonical(np.asarray(polygon.exterior.coords)[:-1], True)]
            rings += [_canonical(np.asarray(h.coords)[:-1], False) for h in polygon.interiors]
            face = []
            for ring in rings:
                face.append(np.array([ids.setdefault((float(x), float(y)), len(ids))
                                      for x, y in ring.tolist()], dtype=np.int64))  # fmt: skip
            faces.append(face)
        points = np.array(list(ids), dtype=np.float64).reshape(-1, 2)
        face_region = owner[kept]
        arrangement = cls(points, faces, face_region, {})
        arrangement._index_edges()
        arrangement._check(parts, polygons, kept, pieces, tol)
        return arrangement

    def _index_edges(self) -> None:
        for f, face in enumerate(self.faces):
            for ring in face:
                for a, b in zip(ring.tolist(), np.roll(ring, -1).tolist(), strict=True):
                    self.edge_faces.setdefault((min(a, b), max(a, b)), []).append(f)

    def _check(self, parts, polygons, kept, pieces: SourcePieces, tol: float) -> None:
        """Faces touching themselves, parts meeting at a point only, slivers and gaps."""
        names = [parts[int(r)].label for r in self.face_region]
        for f, face in enumerate(self.faces):
            ids = np.concatenate(face)
            unique, counts = np.unique(ids, return_counts=True)
            if np.any(counts > 1):
                where = self.points[unique[counts > 1][0]]
                near = _listed(pieces.near(where, 10 * tol))
                raise DomainError(
                    f"{names[f]} touches itself at the single point {fmt_point(where)} ({near} "
                    "meet there): a region must not pinch to a point; move the parts apart or "
                    "let them overlap"
                )
        boundary = [e for e, faces in self.edge_faces.items() if len(faces) == 1]
        ends = np.array(boundary, dtype=np.int64).reshape(-1, 2)
        count = np.bincount(ends.ravel(), minlength=len(self.points))
        pinched = np.flatnonzero(count > 2)
        if pinched.size:
            where = self.points[pinched[0]]
            around = sorted(
                {names[f] for e in boundary if pinched[0] in e for f in self.edge_faces[e]}
            )
            raise DomainError(
                f"{_listed(around)} touch at the single point {fmt_point(where)} only (the "
                "domain pinches there, so no block can be shared across it): move them apart, "
                "or let them meet along an edge"
            )
        for k, f in zip(kept, range(len(self.faces)), strict=True):
            _check_thin(polygons[k], names[f], pieces, tol)
        # Points too near an edge they are not on: a gap or a sliver between parts.
        edges = np.array(list(self.edge_faces), dtype=np.int64).reshape(-1, 2)
        segments = shapely.linestrings(
            np.stack([self.points[edges[:, 0]], self.points[edges[:, 1]]], axis=1)
        )
        point_ids, edge_ids = shapely.STRtree(segments).query(
            shapely.points(self.points), predicate="dwithin", distance=tol
        )
        apart = (edges[edge_ids, 0] != point_ids) & (edges[edge_ids, 1] != point_ids)
        if np.any(apart):
            p = int(point_ids[apart][0])
            e = int(edge_ids[apart][0])
            gap = float(shapely.distance(shapely.Point(*self.points[p]), segments[e]))
            where = self.points[p]
            close = pieces.near(where, 10 * tol + gap)
            raise DomainError(
                f"{_listed(close)} come within {gap:.3g} of each other near {fmt_point(where)} "
                f"without meeting: a sliver or gap thinner than the tolerance ({tol:.3g}, "
                f"{NEAR_TOL:g} times the domain's size); make the parts meet exactly (same "
                "corners on the shared edge) or keep them clearly apart"
            )


def _check_thin(polygon: Any, name: str | None, pieces: SourcePieces, tol: float) -> None:
    """A face (or a hole of the union) thinner than ``tol`` somewhere: a located error."""
    clearance = shapely.minimum_clearance(polygon)
    if clearance >= tol:
        return
    line = shapely.minimum_clearance_line(polygon)
    if line.is_empty:
        where = np.asarray(polygon.exterior.coords[0])
    else:
        where = np.asarray(line.coords).mean(axis=0)
    near = pieces.near(where, 10 * tol + clearance)
    what = f"a sliver of {name}" if name is not None else "a gap between the parts (a hole of none)"
    raise DomainError(
        f"{what} is only {clearance:.3g} wide near {fmt_point(where)}, thinner than the "
        f"tolerance ({tol:.3g}, {NEAR_TOL:g} times the domain's size); it comes from "
        f"{_listed(near)}: make the parts meet exactly or overlap clearly"
    )


def _listed(labels: Sequence[str]) -> str:
    labels = list(labels)
    if not labels:
        return "the parts"
    if len(labels) == 1:
        return labels[0]
    return ", ".join(labels[:-1]) + " and " + labels[-1]


def _lowest(polygon: Any) -> tuple[float, float]:
    xy = np.asarray(polygon.exterior.coords)[:-1]
    k = int(np.lexsort((xy[:, 1], xy[:, 0]))[0])
    return float(xy[k, 0]), float(xy[k, 1])


def _canonical(ring: np.ndarray, outer: bool) -> np.ndarray:
    """A ring counter-clockwise (outer) or clockwise (hole), from its lowest corner."""
    area = float(
        np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1])
    )
    if (area > 0) != outer:
        ring = ring[::-1]
    start = int(np.lexsort((ring[:, 1], ring[:, 0]))[0])
    return np.roll(ring, -start, axis=0)
