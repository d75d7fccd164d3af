"""How many cells a size field asks for, predicted before anything is built.

A mesh whose cells have diameter at most ``h`` has at least ``area / (a h^2)`` cells, with
``a = 0.6572`` the area of a regular pentagon of diameter 1. The *ideal* count of a field is the
integral of ``1 / (a h(x)^2)`` over the domain; blockmesh's size-driven meshes land within a
small factor of it, so the integral tells the memory guard, before a single block is made,
whether the mesh fits.

:func:`ideal_count` integrates over a shapely polygon with an adaptive quadtree: a box is split
until it is no wider than the size at its centre, boxes clear of the polygon are dropped, and
each kept box adds ``w^2 / (a h^2)`` when its centre is inside (the midpoint rule on boxes that
resolve the field). The work is about ``0.7 x`` the count it predicts, so a limit stops it early:
a field asking for more than ``limit`` cells is known to, without being integrated in full.

Examples
--------
>>> import shapely
>>> from blockmesh.sizing.fields import Constant
>>> count = ideal_count(Constant(0.1), shapely.box(0, 0, 1, 1))
>>> round(count.cells), count.complete  # 1 / (0.6572 * 0.01)
(152, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.geometry.topology import PolygonCells
from blockmesh.sizing.fields import PENTAGON_AREA, SizeField, checked_sizes

__all__ = ["CellCount", "ideal_count", "mesh_ideal_count"]

#: Boxes examined per step of the quadtree (bounds the memory of the prediction itself).
_BATCH = 1 << 18


@dataclass(frozen=True)
class CellCount:
    """A predicted cell count.

    Attributes
    ----------
    cells : float
        The ideal count (or, when not ``complete``, the part counted before ``limit`` was
        passed: a lower bound).
    complete : bool
        Whether the whole domain was integrated.
    """

    cells: float
    complete: bool
    finest: tuple[float, float] | None = None
    finest_size: float = float("inf")


def ideal_count(field: SizeField, polygon: Any, *, limit: float | None = None) -> CellCount:
    """The integral of ``1 / (a h^2)`` over ``polygon`` (see the module notes).

    Parameters
    ----------
    field : SizeField
        Checked (finite, positive) at every point where it is evaluated.
    polygon : shapely Polygon or MultiPolygon
    limit : float, optional
        Stop once the count passes this many cells.

    Returns
    -------
    CellCount
        With the centre of the smallest box counted and the size there (where the field is
        smallest, as far as the count went).
    """
    import shapely

    shapely.prepare(polygon)
    low_x, low_y, high_x, high_y = polygon.bounds
    width = max(high_x - low_x, high_y - low_y)
    if not width > 0:
        return CellCount(0.0, True)
    finest: tuple[float, float] | None = None
    finest_size = float("inf")
    # Start with an 8 x 8 grid of boxes over the bounding square.
    k = np.arange(8) + 0.5
    cx, cy = np.meshgrid(low_x + k * width / 8, low_y + k * width / 8)
    pending = [(np.column_stack([cx.ravel(), cy.ravel()]), width / 8)]
    total = 0.0
    while pending:
        centres, w = pending.pop()
        for start in range(0, len(centres), _BATCH):
            batch = centres[start : start + _BATCH]
            near = shapely.dwithin(polygon, shapely.points(batch), w * 0.7072)
            batch = batch[near]
            if not len(batch):
                continue
            sizes = checked_sizes(field, batch)
            least = int(np.argmin(sizes))
            if sizes[least] < finest_size:
                finest = (float(batch[least, 0]), float(batch[least, 1]))
                finest_size = float(sizes[least])
            coarse = w > sizes
            fine = batch[~coarse]
            inside = shapely.intersects_xy(polygon, fine[:, 0], fine[:, 1])
            total += float(np.sum(w * w / (PENTAGON_AREA * sizes[~coarse][inside] ** 2)))
            if limit is not None and total > limit:
                return CellCount(total, False, finest, finest_size)
            split = batch[coarse]
            if len(split):
                quarter = w / 4
                offsets = np.array([[-1, -1], [1, -1], [-1, 1], [1, 1]]) * quarter
                pending.append(((split[:, None, :] + offsets).reshape(-1, 2), w / 2))
    return CellCount(total, True, finest, finest_size)


def _cell_groups(cells: np.ndarray | PolygonCells) -> list[tuple[np.ndarray, np.ndarray]]:
    """The cells by corner count: ``(index, (M_n, n) node ids)`` pairs (one for an array)."""
    if not isinstance(cells, PolygonCells):
        array = np.asarray(cells, dtype=np.int64)
        return [(np.arange(len(array)), array)]
    sizes = cells.sizes()
    out = []
    for n in np.unique(sizes).tolist():
        index = np.flatnonzero(sizes == n)
        out.append((index, cells.nodes[cells.offsets[index][:, None] + np.arange(n)]))
    return out


def mesh_ideal_count(
    field: SizeField, points: np.ndarray, cells: np.ndarray | PolygonCells
) -> float:
    """The ideal count integrated over a mesh's own cells (a triangle per edge, midpoint rule).

    ``cells`` is an ``(M, k)`` array or :class:`~blockmesh.geometry.topology.PolygonCells`
    (cells of any corner counts). Each cell is split into the triangles from its vertex mean to
    its edges, and each triangle adds its area over ``a h^2`` at its centroid: accurate once
    the cells resolve the field, as a mesh made for it does.

    Examples
    --------
    >>> from blockmesh.sizing.fields import Constant
    >>> square = np.array([[0, 0], [1, 0], [1, 0.5], [1, 1], [0, 1]], dtype=float)
    >>> round(mesh_ideal_count(Constant(0.5), square, np.array([[0, 1, 2, 3, 4]])), 4)
    6.0864
    """
    points = np.asarray(points, dtype=np.float64)
    total = 0.0
    for _, group in _cell_groups(cells):
        xy = points[group]
        centre = xy.mean(axis=1, keepdims=True)
        ahead = np.roll(xy, -1, axis=1)
        u, v = xy - centre, ahead - centre
        area = 0.5 * (u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
        middle = ((xy + ahead + centre) / 3).reshape(-1, 2)
        sizes = checked_sizes(field, middle).reshape(area.shape)
        total += float(np.sum(area / (PENTAGON_AREA * sizes**2)))
    return total
