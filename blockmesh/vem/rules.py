"""Quadrature on the cells and boundary edges of a polygon mesh, cell by cell.

The load, the reaction term and the error norms need integrals over every cell of functions
that are not polynomials, so they use blockmesh's composite Gauss rule: each cell is cut into
triangles at its vertex mean and every triangle gets ``order`` Gauss-Jacobi(0, 1) points in the
radial direction times ``order`` Gauss-Legendre points along its edge, exact for polynomials of
degree ``2 order - 1`` (the ``"jacobi"`` rule of :mod:`blockmesh.quadrature`).

For pentagons the points come from :func:`blockmesh.quadrature_points` itself, on chunks of
cells, grouped per cell by its layout (each cell's points are contiguous, cells in order). Cells
of other sizes (triangles and quadrilaterals of other meshes) get the same construction from
blockmesh's Gauss rules (:mod:`blockmesh.numerics.gauss`); the tests check that both give the same
points and weights on pentagons. Boundary edges get Gauss-Legendre points.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
>>> x, y, w = cell_rule(square, np.array([[0, 1, 2, 3]]), order=2)
>>> x.shape, round(float(w.sum()), 15), round(float((w * x * y).sum()), 15)
((1, 16), 1.0, 0.25)
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import lru_cache

import numpy as np

from blockmesh.checks import whole_number
from blockmesh.mesh.mesh import Mesh
from blockmesh.numerics.gauss import gauss_jacobi, gauss_legendre
from blockmesh.quadrature import quadrature_points, rule_info

__all__ = [
    "CHUNK_POINTS",
    "cell_chunks",
    "cell_rule",
    "check_order",
    "edge_rule",
    "fan_rule",
    "points_per_cell",
]

#: Quadrature points held at once when a group of cells is integrated chunk by chunk.
CHUNK_POINTS = 1 << 20

_MAX_ORDER = 30


def check_order(order: object) -> int:
    """``order`` as an int in 1..30 (ArgumentError otherwise)."""
    return whole_number(order, "order", minimum=1, maximum=_MAX_ORDER)


@lru_cache(maxsize=32)
def _triangle_table(order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Collapsed-coordinate points ``(r, s)`` and weights on a triangle, for ``2A * sum``."""
    x, wx = gauss_jacobi(order, 0, 1)
    t, wt = gauss_legendre(order)
    r = np.repeat((1 + x) / 2, order)
    s = np.tile((1 + t) / 2, order)
    weights = np.multiply.outer(wx, wt).ravel() / 8
    for array in (r, s, weights):
        array.setflags(write=False)
    return r, s, weights


def cell_rule(
    points: np.ndarray, cells: np.ndarray, order: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quadrature points and weights of every cell: ``x, y, w`` of shape (M, P).

    ``∫_cell f ≈ Σ_q w[m, q] f(x[m, q], y[m, q])``, exact to degree ``2 order - 1``. The cells
    are one group (same vertex count n), counter-clockwise and star-shaped with respect to their
    vertex mean; ``P = n order²``. Pentagons go through :func:`blockmesh.quadrature_points`.
    """
    order = check_order(order)
    if cells.shape[1] == 5:
        return _pentagon_rule(points, cells, order)
    return fan_rule(points, cells, order)


def fan_rule(
    points: np.ndarray, cells: np.ndarray, order: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rule of :func:`cell_rule` built here for cells of any size (pentagons included)."""
    r, s, weights = _triangle_table(order)
    corners = points[cells]  # (M, n, 2)
    centre = corners.mean(axis=1)  # (M, 2)
    nxt = np.roll(corners, -1, axis=1)
    rim = corners[:, :, None, :] * (1 - s)[:, None] + nxt[:, :, None, :] * s[:, None]
    xy = centre[:, None, None, :] * (1 - r)[:, None] + rim * r[:, None]  # (M, n, P, 2)
    a = corners - centre[:, None, :]
    b = nxt - centre[:, None, :]
    twice_area = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]  # (M, n)
    w = twice_area[:, :, None] * weights
    m = cells.shape[0]
    return xy[..., 0].reshape(m, -1), xy[..., 1].reshape(m, -1), w.reshape(m, -1)


def _pentagon_rule(
    points: np.ndarray, cells: np.ndarray, order: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ``"jacobi"`` rule of :func:`blockmesh.quadrature_points` on pentagons, per cell."""
    m = cells.shape[0]
    per_cell = rule_info("jacobi", order).points_per_cell
    chunk = Mesh.from_cells(points, cells)
    x, y, w = quadrature_points(chunk, order=order, rule="jacobi")
    return x.reshape(m, per_cell), y.reshape(m, per_cell), w.reshape(m, per_cell)


def cell_chunks(n_cells: int, points_per_cell: int) -> Iterator[slice]:
    """Slices of a group's cells holding at most :data:`CHUNK_POINTS` quadrature points."""
    step = max(1, CHUNK_POINTS // max(points_per_cell, 1))
    for start in range(0, n_cells, step):
        yield slice(start, min(start + step, n_cells))


def points_per_cell(size: int, order: int) -> int:
    """Quadrature points of one cell with ``size`` vertices at ``order``."""
    return size * order * order


@lru_cache(maxsize=32)
def _line_table(order: int) -> tuple[np.ndarray, np.ndarray]:
    t, wt = gauss_legendre(order)
    s = (1 + t) / 2
    w = wt / 2
    s.setflags(write=False)
    w.setflags(write=False)
    return s, w


def edge_rule(
    points: np.ndarray, edges: np.ndarray, order: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Gauss-Legendre points on straight edges: ``x, y, w, s`` of shape (E, order).

    ``s`` is the parameter of each point from the edge's first node (0) to its second (1); ``w``
    includes the edge length, so ``∫_e g ≈ Σ w g(x, y)``.

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [3.0, 4.0]])
    >>> x, y, w, s = edge_rule(pts, np.array([[0, 1]]), order=2)
    >>> round(float(w.sum()), 15), round(float((w * x).sum()), 14)
    (5.0, 7.5)
    """
    order = check_order(order)
    s, w = _line_table(order)
    a = points[edges[:, 0]]
    b = points[edges[:, 1]]
    xy = a[:, None, :] * (1 - s)[:, None] + b[:, None, :] * s[:, None]
    length = np.hypot(*(b - a).T)
    return xy[..., 0], xy[..., 1], length[:, None] * w, np.broadcast_to(s, (edges.shape[0], order))
