"""How many cells a size field asks for, predicted before anything is built, in bounded time.

A mesh whose cells have diameter at most ``h`` has at least ``area / (a h^2)`` cells, with
``a = 0.6572`` the area of a regular pentagon of diameter 1. The *ideal* count of a field is the
integral of ``1 / (a h(x)^2)`` over the domain; blockmesh's size-driven meshes land within a
small factor of it, so the integral tells the memory guard, before a single block is made,
whether the mesh fits.

:func:`ideal_count` integrates by adaptive quadrature on triangles: the domain is triangulated
(constrained Delaunay, so every sample is inside it), and each triangle compares the midpoint
rule on itself with the midpoint rule on its four children by side midpoints (four evaluations;
the four points are spread in every direction, so a field that varies along one direction only
is seen). A triangle whose two answers agree (to :data:`RELATIVE_TOLERANCE`, or whose
difference is negligible beside the total) is counted by the finer; the others are cut in two
at the middle of their longest side. The work follows how the field *varies*, not how small it
is: a constant size of ``1e-5`` is counted exactly from the first triangles, in about a thousand
evaluations, and the count of a field scaled by ``s`` is the count divided by ``s^2``. The
evaluations are capped (``budget``, :data:`EVALUATIONS` by default), so the prediction ends in
bounded time whatever the field; a count that was not finished is a lower bound, to within the
tolerance (the triangles left are counted by their own rule, and the midpoint rule
underestimates the integral of a convex function, which ``1 / h^2`` is wherever ``h`` is
affine). A field that goes to 0 somewhere (along a line, at a point) has no finite count: it
uses the whole budget, and :func:`smallest_size` (a compass search from the smallest size
sampled, down to :data:`FLOOR` of the domain's width) finds where it falls.

Examples
--------
>>> import shapely
>>> from blockmesh.sizing.fields import Constant
>>> count = ideal_count(Constant(0.1), shapely.box(0, 0, 1, 1))
>>> round(count.cells), count.complete  # 1 / (0.6572 * 0.01)
(152, True)
>>> ideal_count(Constant(1e-5), shapely.box(0, 0, 1, 1)).cells > 1.5e10  # counted at once
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.geometry.topology import PolygonCells
from blockmesh.sizing.fields import PENTAGON_AREA, SizeField, checked_sizes

__all__ = [
    "EVALUATIONS",
    "FLOOR",
    "RELATIVE_TOLERANCE",
    "CellCount",
    "ideal_count",
    "mesh_ideal_count",
    "smallest_size",
]

#: Most field evaluations (points) of one prediction: about a second of an expression's work.
EVALUATIONS = 1 << 18
#: A triangle is counted when the midpoint rule on it and on its four children agree to this.
RELATIVE_TOLERANCE = 0.03
#: ... or when their difference is below this fraction of the total over the triangles left.
_NEGLIGIBLE = 1e-3
#: The rules compared on each triangle: its centroid, and the centroids of its four children
#: by side midpoints (the middle one's is the centroid), as barycentric weights (4, 3).
_RULE_WEIGHTS = np.array([[1, 1, 1], [4, 1, 1], [1, 4, 1], [1, 1, 4]]) / np.array(
    [[3], [6], [6], [6]]
)
_RULE = len(_RULE_WEIGHTS)
#: The first triangles are split until no side is longer than the domain's width over this.
_FIRST_DIVISIONS = 8
#: Sizes below this fraction of the domain's width count as 0: no mesh resolves them (and a
#: field reaching them has fallen through every scale the search looked at).
FLOOR = 1e-9
#: Points around the current best of the pattern search, and its most steps (a step that finds
#: no smaller size halves the radius: 48 such take it from an eighth of the width to 1e-15).
_STENCIL = 8
_SEARCH_STEPS = 160


@dataclass(frozen=True)
class CellCount:
    """A predicted cell count.

    Attributes
    ----------
    cells : float
        The ideal count; when not ``complete``, what was counted before the quadrature stopped
        (a lower bound to within the tolerance: the triangles not resolved are counted by their
        own rule, which underestimates where the field asks for more cells than it saw).
    complete : bool
        Whether the quadrature converged everywhere (else it ran out of evaluations, or passed
        ``limit``).
    finest : (float, float) or None
        Where the smallest size was sampled.
    finest_size : float
        That size.
    evaluations : int
        Points at which the field was evaluated.
    """

    cells: float
    complete: bool
    finest: tuple[float, float] | None = None
    finest_size: float = float("inf")
    evaluations: int = 0


def _triangles(polygon: Any) -> np.ndarray:
    """The polygon's constrained Delaunay triangles (T, 3, 2), split until none is long."""
    import shapely

    parts = shapely.get_parts(shapely.constrained_delaunay_triangles(polygon))
    if not len(parts):
        return np.zeros((0, 3, 2))
    corners = shapely.get_coordinates(shapely.get_exterior_ring(parts)).reshape(len(parts), 4, 2)
    corners = corners[:, :3]
    low_x, low_y, high_x, high_y = polygon.bounds
    longest = max(high_x - low_x, high_y - low_y) / _FIRST_DIVISIONS
    while True:
        sides = np.hypot(*(corners - np.roll(corners, -1, axis=1)).transpose(2, 0, 1))
        long = sides.max(axis=1) > longest
        if not long.any():
            return corners
        corners = np.concatenate([corners[~long], _halves(corners[long]).reshape(-1, 3, 2)])


def _halves(corners: np.ndarray) -> np.ndarray:
    """Each triangle cut in two at the middle of its longest side (T, 2, 3, 2).

    Cutting the longest side keeps the triangles' angles bounded away from 0 (Rivara), so even
    the slivers of a constrained triangulation become well-shaped triangles as they are cut.
    """
    sides = np.sum((np.roll(corners, -1, axis=1) - corners) ** 2, axis=2)
    k = np.argmax(sides, axis=1)  # the longest side runs from corner k to corner k + 1
    rows = np.arange(len(corners))[:, None]
    a, b, c = (corners[rows, (k[:, None] + j) % 3][:, 0] for j in range(3))
    middle = 0.5 * (a + b)
    return np.stack([np.stack([a, middle, c], axis=1), np.stack([middle, b, c], axis=1)], axis=1)


def ideal_count(
    field: SizeField,
    polygon: Any,
    *,
    limit: float | None = None,
    budget: int = EVALUATIONS,
) -> CellCount:
    """The integral of ``1 / (a h^2)`` over ``polygon`` (see the module notes).

    Parameters
    ----------
    field : SizeField
        Checked (finite, positive) at every point where it is evaluated (all inside the
        polygon).
    polygon : shapely Polygon or MultiPolygon
    limit : float, optional
        Stop once the count (a lower bound as it goes) passes this many cells.
    budget : int
        Most points at which the field is evaluated.

    Returns
    -------
    CellCount
        With the place of the smallest size sampled and that size.

    Examples
    --------
    >>> import shapely
    >>> from blockmesh.sizing.fields import Expression
    >>> line = ideal_count(Expression("0.1*abs(x - 0.3)"), shapely.box(0, 0, 1, 1))
    >>> line.complete, line.evaluations <= EVALUATIONS, round(line.finest[0], 3)
    (False, True, 0.3)
    """
    corners = _triangles(polygon)
    if not len(corners):
        return CellCount(0.0, True)
    counted = estimate = 0.0
    evaluations = 0
    finest: tuple[float, float] | None = None
    finest_size = float("inf")
    while len(corners):
        if evaluations + _RULE * len(corners) > budget:
            return CellCount(counted + estimate, False, finest, finest_size, evaluations)
        u, v = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        points = (_RULE_WEIGHTS @ corners).reshape(-1, 2)  # (T * 4, 2): the centroid first
        sizes = checked_sizes(field, points)
        evaluations += len(points)
        least = int(np.argmin(sizes))
        if sizes[least] < finest_size:
            finest = (float(points[least, 0]), float(points[least, 1]))
            finest_size = float(sizes[least])
        value = (1.0 / (PENTAGON_AREA * sizes**2)).reshape(-1, _RULE)
        coarse = area * value[:, 0]
        fine = area * value.mean(axis=1)
        error = np.abs(fine - coarse)
        estimate = float(fine.sum())
        if limit is not None and counted + estimate > limit:
            return CellCount(counted + estimate, False, finest, finest_size, evaluations)
        done = (error <= RELATIVE_TOLERANCE * fine) | (
            error <= _NEGLIGIBLE * (counted + estimate) / len(fine)
        )
        counted += float(fine[done].sum())
        estimate -= float(fine[done].sum())
        corners = _halves(corners[~done]).reshape(-1, 3, 2)
    return CellCount(counted, True, finest, finest_size, evaluations)


def smallest_size(
    field: SizeField, polygon: Any, start: tuple[float, float]
) -> tuple[tuple[float, float], float]:
    """Where the field is smallest near ``start``, and the size there (a pattern search).

    From ``start`` (the smallest size a count sampled), :data:`_STENCIL` points around the best
    point so far are sampled, and the best moves to the smallest of them inside the polygon; a
    step that finds none smaller halves the radius, from an eighth of the domain's width down to
    about ``1e-15`` of it (a compass search: at most :data:`_SEARCH_STEPS` steps, 1,280
    evaluations). A field that goes to 0 at a point or along a line is followed down to
    it (the size found falls below :data:`FLOOR` of the width); one with a positive minimum
    stops at it.

    Examples
    --------
    >>> import shapely
    >>> from blockmesh.sizing.fields import Expression
    >>> where, size = smallest_size(Expression("0.1*abs(x - 0.30017)"), shapely.box(0, 0, 1, 1),
    ...                             (0.25, 0.5))
    >>> round(where[0], 6), size < 1e-12
    (0.30017, True)
    >>> round(smallest_size(Expression("0.01 + abs(y - 0.5)"), shapely.box(0, 0, 1, 1),
    ...                     (0.2, 0.1))[1], 12)  # a positive minimum, found from afar
    0.01
    """
    import shapely

    low_x, low_y, high_x, high_y = polygon.bounds
    radius = max(high_x - low_x, high_y - low_y) / _FIRST_DIVISIONS
    best = np.array(start, dtype=np.float64)
    size = float(checked_sizes(field, best[None])[0])
    turn = 2 * np.pi * np.arange(_STENCIL) / _STENCIL
    ring = np.column_stack([np.cos(turn), np.sin(turn)])
    smallest_radius = radius * 1e-14
    for _ in range(_SEARCH_STEPS):
        around = best + radius * ring
        around = around[shapely.intersects_xy(polygon, around[:, 0], around[:, 1])]
        sizes = checked_sizes(field, around) if len(around) else np.zeros(0)
        k = int(np.argmin(sizes)) if len(sizes) else -1
        if k >= 0 and sizes[k] < size:
            best, size = around[k], float(sizes[k])
        else:
            radius *= 0.5
            if radius < smallest_radius:
                break
    return (float(best[0]), float(best[1])), size


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
