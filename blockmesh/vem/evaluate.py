"""Values of a solution at points of the boundary, where the virtual element function is known.

A lowest-order virtual element function is linear on every edge, so on the boundary it is known
exactly between the nodes: the value at a boundary point is the linear interpolation of the two
nodal values of its edge. That is how a benchmark reads a displacement at a point that is not a
node (Cook's membrane: the middle of the loaded edge).

Examples
--------
>>> import numpy as np
>>> import blockmesh
>>> from blockmesh.vem.polygons import PolygonMesh
>>> mesh = PolygonMesh.from_mesh(blockmesh.load_domain("square").mesh(1))
>>> nodal = mesh.points[:, 0] + 2 * mesh.points[:, 1]
>>> boundary_values(mesh, nodal, [(1.0, 0.5), (0.25, 0.0)]).round(12).tolist()
[2.0, 0.25]
"""

from __future__ import annotations

from typing import Any

import numpy as np

from blockmesh.errors import ArgumentError
from blockmesh.vem.polygons import PolygonMesh

__all__ = ["boundary_values"]

#: A point counts as on an edge when it is within this fraction of the mesh's size from it.
ON_EDGE_TOL = 1e-9


def boundary_values(mesh: PolygonMesh, nodal: Any, points: Any) -> np.ndarray:
    """Nodal values ``nodal`` (N,) or (N, c) interpolated at boundary ``points`` (P, 2).

    Raises ArgumentError naming a point that is not on the boundary. O(P Eb).
    """
    values = np.asarray(nodal, dtype=np.float64)
    if values.shape[0] != mesh.n_points:
        raise ArgumentError(
            f"nodal has {values.shape[0]} values for a mesh of {mesh.n_points} nodes"
        )
    query = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    a = mesh.points[mesh.boundary_edges[:, 0]]
    b = mesh.points[mesh.boundary_edges[:, 1]]
    along = b - a
    length2 = np.einsum("ed,ed->e", along, along)
    size = float(np.ptp(mesh.points, axis=0).max())
    out = np.empty((query.shape[0], *values.shape[1:]))
    for k, point in enumerate(query):
        s = np.clip(np.einsum("ed,ed->e", point - a, along) / length2, 0.0, 1.0)
        gap = np.hypot(*(a + s[:, None] * along - point).T)
        edge = int(np.argmin(gap))
        if gap[edge] > ON_EDGE_TOL * size:
            raise ArgumentError(
                f"point {k} ({float(point[0])!r}, {float(point[1])!r}) is not on the boundary "
                f"(nearest boundary edge at distance {gap[edge]:.3g})"
            )
        first, second = mesh.boundary_edges[edge]
        out[k] = (1 - s[edge]) * values[first] + s[edge] * values[second]
    return out
