"""Curved edges on a mesh: which edges lie on which curve, and over which stretch of it.

:class:`CurvedEdges` is the table every stage shares: a Domain's block mesh has one row per
curved block edge, and each refinement splits every row at the mean parameter. The functions
here answer what every stage asks of it: which cell edges are curved (:func:`curved_slots`), the
curve's points at the dyadic parameters of a level (:func:`edge_points`), and the area between a
cell's curved edges and their chords (:func:`area_corrections`).

Examples
--------
>>> import numpy as np
>>> from blockmesh.curves.types import Arc
>>> quarter = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
>>> table = CurvedEdges(edges=[[0, 1]], curve=[0], start=[0.0], stop=[1.0], curves=(quarter,))
>>> row, forward = curved_slots(np.array([[0, 1, 2]]), 3, table)
>>> row.tolist(), forward.tolist()
([[0, -1, -1]], [[True, False, False]])
>>> edge_points(table, 1).round(6).tolist()
[[[1.0, 0.0], [0.707107, 0.707107], [0.0, 1.0]]]
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from blockmesh.curves.types import Curve
from blockmesh.errors import ArgumentError
from blockmesh.geometry.topology import PolygonCells, edge_keys

__all__ = ["CurvedEdges", "area_corrections", "curved_slots", "edge_points"]


@dataclass(frozen=True, eq=False)
class CurvedEdges:
    """The edges of a mesh that lie on curves, with the stretch of the curve each one covers.

    Attributes
    ----------
    edges : ndarray (E, 2) int64
        Node ids, ordered as the curve's parameter increases.
    curve : ndarray (E,) int64
        Index into ``curves`` of each edge's curve.
    start, stop : ndarray (E,) float64
        The curve's parameter at ``edges[:, 0]`` and at ``edges[:, 1]`` (``start < stop``).
    curves : tuple of Curve
        The curves (bound to their ends).

    A block mesh has one row per curved block edge with ``start = 0``, ``stop = 1``; each
    refinement splits every row into two at the mean parameter.
    """

    edges: np.ndarray
    curve: np.ndarray
    start: np.ndarray
    stop: np.ndarray
    curves: tuple[Curve, ...]

    def __post_init__(self) -> None:
        for name, dtype in (
            ("edges", np.int64),
            ("curve", np.int64),
            ("start", np.float64),
            ("stop", np.float64),
        ):
            array = np.array(getattr(self, name), dtype=dtype)
            array.setflags(write=False)
            object.__setattr__(self, name, array)
        object.__setattr__(self, "curves", tuple(self.curves))
        n = self.edges.shape[0]
        if self.edges.shape != (n, 2) or not all(
            getattr(self, k).shape == (n,) for k in ("curve", "start", "stop")
        ):
            raise ArgumentError("CurvedEdges needs edges (E, 2) and curve, start, stop (E,)")
        if n and not (int(self.curve.min()) >= 0 and int(self.curve.max()) < len(self.curves)):
            raise ArgumentError("CurvedEdges curve indices must index curves")

    def __len__(self) -> int:
        return int(self.edges.shape[0])

    def renumbered(self, new_id: np.ndarray) -> CurvedEdges:
        """The same curved edges with node ``k`` renamed ``new_id[k]``."""
        return replace(self, edges=np.asarray(new_id)[self.edges])

    def distances(self, points: np.ndarray) -> np.ndarray:
        """For every curved edge, the larger distance of its two nodes from the curve's points.

        The curve's point at the edge's parameters is compared with the node (0 when the node
        is exactly where the curve puts it).
        """
        out = np.zeros(len(self))
        for k, curve in enumerate(self.curves):
            rows = np.flatnonzero(self.curve == k)
            if rows.size == 0:
                continue
            for column, params in ((0, self.start[rows]), (1, self.stop[rows])):
                gap = np.hypot(*(points[self.edges[rows, column]] - curve.point(params)).T)
                out[rows] = np.maximum(out[rows], gap)
        return out


def curved_slots(
    cells: np.ndarray | PolygonCells, n_points: int, curves: CurvedEdges
) -> tuple[np.ndarray, np.ndarray]:
    """For every cell edge (slot), its row in ``curves`` (-1 when straight) and direction.

    ``cells`` is (M, k), k >= 2 (edge ``i`` from corner ``i`` to ``i + 1``; boundary edges are
    (E, 2) cells), or :class:`~blockmesh.geometry.topology.PolygonCells`. Returns
    ``(row, forward)``, each (M, k) (flat, one per slot, for PolygonCells): ``forward`` is True
    where the cell runs along the edge as the curve's parameter increases.
    """
    if isinstance(cells, PolygonCells):
        following = cells.following()
        cells = cells.nodes
    else:
        cells = np.asarray(cells, dtype=np.int64)
        following = np.roll(cells, -1, axis=1)
    keys = edge_keys(cells, following, n_points)
    curve_keys = edge_keys(curves.edges[:, 0], curves.edges[:, 1], n_points)
    order = np.argsort(curve_keys)
    sorted_keys = curve_keys[order]
    position = np.clip(np.searchsorted(sorted_keys, keys), 0, max(sorted_keys.size - 1, 0))
    found = sorted_keys.size > 0
    match = (sorted_keys[position] == keys) if found else np.zeros(keys.shape, dtype=bool)
    row = np.where(match, order[position] if found else -1, -1)
    forward = match & (curves.edges[np.maximum(row, 0), 0] == cells)
    return row, forward


def edge_points(curves: CurvedEdges, level: int) -> np.ndarray:
    """The curve's points at ``start + (j/2^level)(stop - start)``, j = 0..2^level, of every row.

    Shape (E, 2^level + 1, 2). Computed once per curved edge, so every cell along the edge reads
    the same bits. The dyadic parameters are exact in floating point.
    """
    fractions = np.arange(2**level + 1) / 2**level
    out = np.empty((len(curves), fractions.size, 2))
    for k, curve in enumerate(curves.curves):
        rows = np.flatnonzero(curves.curve == k)
        if rows.size:
            start, stop = curves.start[rows, None], curves.stop[rows, None]
            out[rows] = curve.point(start + fractions * (stop - start))
    return out


def area_corrections(
    cells: np.ndarray | PolygonCells, n_points: int, curves: CurvedEdges | None
) -> np.ndarray:
    """For every cell, the signed area between its curved edges and their chords, shape (M,).

    Positive where a curve bulges out of its cell. Cells without curved edges get 0. ``cells``
    is (M, k) or :class:`~blockmesh.geometry.topology.PolygonCells`.
    """
    if not isinstance(cells, PolygonCells):
        cells = np.asarray(cells, dtype=np.int64)
    n_cells = cells.n_cells if isinstance(cells, PolygonCells) else cells.shape[0]
    out = np.zeros(n_cells)
    if curves is None or len(curves) == 0:
        return out
    row, forward = curved_slots(cells, n_points, curves)
    if isinstance(cells, PolygonCells):
        cell = cells.slot_cell()[row >= 0]
    else:
        cell, _ = np.nonzero(row >= 0)
    rows, ahead = row[row >= 0], forward[row >= 0]
    first = np.where(ahead, curves.start[rows], curves.stop[rows])
    last = np.where(ahead, curves.stop[rows], curves.start[rows])
    for k, curve in enumerate(curves.curves):
        mine = curves.curve[rows] == k
        if np.any(mine):
            np.add.at(out, cell[mine], curve.segment_area(first[mine], last[mine]))
    return out
