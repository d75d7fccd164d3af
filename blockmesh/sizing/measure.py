"""Sizes achieved: cell diameters, neighbours' size ratios, and the size asked against the size got.

A cell's *size* is its diameter: the largest distance between two of its points (corners, and
the middles of its curved edges, which bulge beyond the corners). :func:`size_report` measures
a mesh against a size field: the worst ratio of a cell's diameter to the size asked at its
centroid (and where), the count against the ideal ``integral of 1 / (a h^2)``, and the largest
ratio between the diameters of two cells that share an edge (which any mesh has, field or not).

Examples
--------
>>> import numpy as np
>>> points = np.array([[0, 0], [1, 0], [1.5, 1], [1, 2], [0, 2], [2, 0], [3, 0.5], [2.5, 1.5]])
>>> cells = np.array([[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]])
>>> cell_diameters(points, cells).round(3).tolist()
[2.236, 2.121]
>>> r = size_report(points, cells)
>>> round(r.neighbour_ratio, 3), r.neighbour_cells
(1.054, (0, 1))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.curves.edges import CurvedEdges, curved_slots
from blockmesh.errors import fmt_point
from blockmesh.geometry.topology import PolygonCells, cell_neighbours
from blockmesh.sizing.fields import SizeField, checked_sizes
from blockmesh.sizing.predict import _cell_groups, mesh_ideal_count

#: Cells as an ``(M, k)`` array of node ids, or in compressed rows (any corner counts).
Cells = np.ndarray | PolygonCells

__all__ = ["SizeReport", "cell_centroids", "cell_diameters", "neighbour_ratios", "size_report"]

#: Cells measured per step (bounded memory on large meshes).
_CHUNK = 1 << 16


def _curved_middles(
    points: np.ndarray, cells: np.ndarray, curves: CurvedEdges | None
) -> tuple[np.ndarray, np.ndarray]:
    """The cells with a curved edge, and each one's edge middles (the curve's on curved ones)."""
    if curves is None or not len(curves):
        return np.zeros(0, dtype=np.int64), np.zeros((0, cells.shape[1], 2))
    row, _ = curved_slots(cells, len(points), curves)
    bent = np.flatnonzero(np.any(row >= 0, axis=1))
    xy = points[cells[bent]]
    middles = 0.5 * (xy + np.roll(xy, -1, axis=1))
    rows = row[bent]
    slot = rows >= 0
    which = rows[slot]
    t = 0.5 * (curves.start[which] + curves.stop[which])
    on_curve = np.empty((which.size, 2))
    for k in np.unique(curves.curve[which]):
        sel = curves.curve[which] == k
        on_curve[sel] = curves.curves[int(k)].point(t[sel])
    middles[slot] = on_curve
    return bent, middles


def _diameters(polygons: np.ndarray) -> np.ndarray:
    """Largest distance between two of each polygon's points, (M, k, 2) -> (M,)."""
    i, j = np.triu_indices(polygons.shape[1], 1)
    diff = polygons[:, i] - polygons[:, j]
    return np.sqrt(np.max(diff[..., 0] ** 2 + diff[..., 1] ** 2, axis=1))


def cell_diameters(
    points: np.ndarray, cells: Cells, curves: CurvedEdges | None = None
) -> np.ndarray:
    """Diameter of every cell: the largest distance between two of its corners or edge middles.

    Only curved edges' middles can be farther than the corners (a point of a straight edge is
    never farther from anything than both its ends), so only cells with a curved edge look at
    them. ``cells`` is an ``(M, k)`` array or :class:`~blockmesh.geometry.topology.PolygonCells`.
    O(M k^2), in chunks.
    """
    points = np.asarray(points, dtype=np.float64)
    out = np.empty(_count(cells))
    for index, group in _cell_groups(cells):
        for start in range(0, len(group), _CHUNK):
            part = group[start : start + _CHUNK]
            out[index[start : start + len(part)]] = _diameters(points[part])
        bent, middles = _curved_middles(points, group, curves)
        if bent.size:
            out[index[bent]] = _diameters(np.concatenate([points[group[bent]], middles], axis=1))
    return out


def _count(cells: Cells) -> int:
    return cells.n_cells if isinstance(cells, PolygonCells) else len(cells)


def cell_centroids(points: np.ndarray, cells: Cells) -> np.ndarray:
    """Area centroid of every (straight) cell, (M, 2).

    Examples
    --------
    >>> square = np.array([[0, 0], [2, 0], [2, 1], [2, 2], [0, 2]], dtype=float)
    >>> cell_centroids(square, np.array([[0, 1, 2, 3, 4]])).tolist()
    [[1.0, 1.0]]
    >>> cell_centroids(square, PolygonCells.from_lists([[0, 1, 3, 4]])).tolist()
    [[1.0, 1.0]]
    """
    points = np.asarray(points, dtype=np.float64)
    out = np.empty((_count(cells), 2))
    for index, group in _cell_groups(cells):
        xy = points[group]
        base = xy[:, :1]
        u = xy - base
        v = np.roll(u, -1, axis=1)
        cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
        area = cross.sum(axis=1)
        centre = np.sum((u + v) * cross[..., None], axis=1) / (3.0 * area[:, None])
        out[index] = base[:, 0] + centre
    return out


def neighbour_ratios(cells: Cells, n_points: int, sizes: np.ndarray) -> np.ndarray:
    """For every edge shared by two cells, ``(cell, other, larger / smaller of their sizes)``.

    Returns an (E, 3) float array (cell ids as floats), one row per shared edge.
    """
    if not isinstance(cells, PolygonCells):
        cells = np.asarray(cells, dtype=np.int64)
    neighbour = cell_neighbours(cells, n_points).ravel()
    slot = np.flatnonzero(neighbour >= 0)
    if isinstance(cells, PolygonCells):
        owner = cells.slot_cell()
        cell, other = owner[slot], owner[neighbour[slot]]
    else:
        k = cells.shape[1]
        cell, other = slot // k, neighbour[slot] // k
    keep = cell < other
    cell, other = cell[keep], other[keep]
    a, b = sizes[cell], sizes[other]
    return np.column_stack([cell, other, np.maximum(a, b) / np.minimum(a, b)])


@dataclass(frozen=True)
class SizeReport:
    """A mesh's sizes against the sizes asked (see the module notes).

    Attributes
    ----------
    cells : int
    min_diameter, max_diameter : float
        Smallest and largest cell diameter.
    neighbour_ratio : float
        Largest ratio of the diameters of two cells sharing an edge.
    neighbour_cells : (int, int)
        Those two cells.
    worst_ratio : float or None
        Largest ``diameter / size asked at the centroid`` (None without a field).
    worst_cell : int or None
    worst_point : (float, float) or None
        The worst cell's centroid.
    mean_ratio : float or None
        Mean of ``diameter / size asked``.
    ideal_cells : float or None
        The integral of ``1 / (a h^2)`` over the mesh (the fewest cells the field allows if
        they were regular pentagons).
    """

    cells: int
    min_diameter: float
    max_diameter: float
    neighbour_ratio: float
    neighbour_cells: tuple[int, int]
    worst_ratio: float | None = None
    worst_cell: int | None = None
    worst_point: tuple[float, float] | None = None
    mean_ratio: float | None = None
    ideal_cells: float | None = None

    @property
    def count_ratio(self) -> float | None:
        """Cells over the ideal count."""
        if self.ideal_cells is None or not self.ideal_cells > 0:
            return None
        return self.cells / self.ideal_cells

    def as_dict(self) -> dict[str, Any]:
        """The report as JSON-ready values."""
        return {
            "cells": self.cells,
            "min_diameter": self.min_diameter,
            "max_diameter": self.max_diameter,
            "neighbour_ratio": self.neighbour_ratio,
            "neighbour_cells": list(self.neighbour_cells),
            "worst_ratio": self.worst_ratio,
            "worst_cell": self.worst_cell,
            "worst_point": None if self.worst_point is None else list(self.worst_point),
            "mean_ratio": self.mean_ratio,
            "ideal_cells": self.ideal_cells,
            "count_ratio": self.count_ratio,
        }

    def summary(self) -> str:
        """One or two lines for people."""
        a, b = self.neighbour_cells
        text = (
            f"cell diameters {self.min_diameter:.4g} .. {self.max_diameter:.4g}; largest "
            f"neighbour size ratio {self.neighbour_ratio:.3g} (cells {a} and {b})"
        )
        if self.worst_ratio is not None and self.worst_point is not None:
            text += (
                f"\nsize got / size asked: worst {self.worst_ratio:.3g} (cell {self.worst_cell} "
                f"at {fmt_point(self.worst_point, 6)}), mean {self.mean_ratio:.3g}; "
                f"{self.cells:,} cells = {self.count_ratio:.3g} x the ideal "
                f"{self.ideal_cells:,.0f}"
            )
        return text


def size_report(
    points: np.ndarray,
    cells: Cells,
    field: SizeField | None = None,
    *,
    curves: CurvedEdges | None = None,
) -> SizeReport:
    """Measure a mesh's cell sizes, and against ``field`` when given (see the module notes).

    ``cells`` is an ``(M, k)`` array or :class:`~blockmesh.geometry.topology.PolygonCells` (a
    polygon mesh's cells, whose hanging nodes are corners of the coarse cells). O(M) time,
    memory in chunks for the diameters.
    """
    points = np.asarray(points, dtype=np.float64)
    if not isinstance(cells, PolygonCells):
        cells = np.asarray(cells, dtype=np.int64)
    n_cells = _count(cells)
    diameters = cell_diameters(points, cells, curves)
    pairs = neighbour_ratios(cells, len(points), diameters)
    if len(pairs):
        k = int(np.argmax(pairs[:, 2]))
        neighbour = float(pairs[k, 2])
        between = (int(pairs[k, 0]), int(pairs[k, 1]))
    else:
        neighbour, between = 1.0, (0, 0)
    report: dict[str, Any] = {}
    if field is not None and n_cells:
        centroids = cell_centroids(points, cells)
        ratio = diameters / checked_sizes(field, centroids)
        worst = int(np.argmax(ratio))
        report = {
            "worst_ratio": float(ratio[worst]),
            "worst_cell": worst,
            "worst_point": (float(centroids[worst, 0]), float(centroids[worst, 1])),
            "mean_ratio": float(ratio.mean()),
            "ideal_cells": mesh_ideal_count(field, points, cells),
        }
    return SizeReport(
        cells=n_cells,
        min_diameter=float(diameters.min()) if n_cells else 0.0,
        max_diameter=float(diameters.max()) if n_cells else 0.0,
        neighbour_ratio=neighbour,
        neighbour_cells=between,
        **report,
    )
