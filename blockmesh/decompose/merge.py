"""Pairs of neighbouring triangles merged into convex quadrilaterals (fewer, larger pieces).

A quadrilateral piece becomes 12 pentagons (its ring-and-hub template) where its two triangles
would become 18, with the same nodes on every outer side, so merging keeps the mesh conforming.
Two triangles sharing an interior edge form a candidate when their union is strictly convex with
every corner below ``max_angle``; candidates are taken greedily, the roundest first (smallest
largest corner), each triangle in at most one pair.

Examples
--------
>>> import numpy as np
>>> points = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> quads, rest = pair_triangles(points, np.array([[0, 1, 2], [0, 2, 3]]))
>>> quads.tolist(), rest.shape  # the square, from corner 2 round
([[2, 3, 0, 1]], (0, 3))
"""

from __future__ import annotations

import numpy as np

from blockmesh.geometry.polygons import corner_sines, interior_angles
from blockmesh.geometry.topology import cell_neighbours

__all__ = ["pair_triangles"]

#: Largest corner (degrees) a merged quadrilateral may have.
DEFAULT_MAX_ANGLE = 150.0
#: Smallest corner sine a merged quadrilateral may have (well clear of straight).
_MIN_SINE = 1e-3


def pair_triangles(
    points: np.ndarray, triangles: np.ndarray, *, max_angle: float = DEFAULT_MAX_ANGLE
) -> tuple[np.ndarray, np.ndarray]:
    """Merge neighbouring triangles into convex quadrilaterals, greedily, roundest first.

    Parameters
    ----------
    points : ndarray (N, 2)
    triangles : ndarray (T, 3)
        Counter-clockwise, meeting edge to edge.
    max_angle : float
        Largest corner (degrees) a quadrilateral may have.

    Returns
    -------
    quads : ndarray (Q, 4)
        Counter-clockwise quadrilaterals.
    rest : ndarray (T - 2 Q, 3)
        The triangles left unpaired, in their original order.

    Notes
    -----
    O(T log T): the candidates are scored with whole-array operations, then chosen in one pass.
    """
    triangles = np.asarray(triangles, dtype=np.int64)
    neighbour = cell_neighbours(triangles, len(points))
    t, e = np.nonzero(neighbour >= 0)
    other, other_e = np.divmod(neighbour[t, e], 3)
    keep = t < other
    t, e, other, other_e = t[keep], e[keep], other[keep], other_e[keep]
    a, b = triangles[t, e], triangles[t, (e + 1) % 3]
    apex, far = triangles[t, (e + 2) % 3], triangles[other, (other_e + 2) % 3]
    quads = np.stack([a, far, b, apex], axis=1)
    corners = points[quads]
    angles = interior_angles(corners)
    good = np.all(corner_sines(corners) > _MIN_SINE, axis=1) & (angles.max(axis=1) < max_angle)
    order = np.flatnonzero(good)[np.argsort(angles.max(axis=1)[good], kind="stable")]
    used = np.zeros(len(triangles), dtype=bool)
    chosen = []
    for i, x, y in zip(order.tolist(), t[order].tolist(), other[order].tolist(), strict=True):
        if not used[x] and not used[y]:
            used[x] = used[y] = True
            chosen.append(i)
    return quads[chosen].reshape(-1, 4), triangles[~used]
