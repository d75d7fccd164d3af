"""Geometry and topology on plain arrays: polygon predicates and measures, edge keys and boundaries.

Nothing here knows a Mesh or a Domain: every function takes coordinate arrays ``(..., K, 2)`` or
cell arrays ``(M, K)`` of node ids. :mod:`~blockmesh.geometry.polygons` measures polygons
(areas, angles, convexity); :mod:`~blockmesh.geometry.topology` relates cells through their
edges (edge keys, neighbours, boundary loops), for cells of any number of corners.
"""

from __future__ import annotations

from blockmesh.geometry import polygons
from blockmesh.geometry.polygons import (  # noqa: F401 (given through polygons.PACKAGE_NAMES)
    COLLINEAR_SIN_TOL,
    LocalFrame,
    corner_sines,
    interior_angles,
    is_strictly_convex,
    local_frame,
    polygon_diameter,
    signed_area,
    vertex_mean,
)

__all__ = list(polygons.PACKAGE_NAMES)
