"""Decomposition of polygons into strictly convex pentagonal blocks that meet edge to edge.

- :func:`decompose_polygon`: any simple polygon with holes (validated rings), the front door;
- :func:`decompose_convex_polygon`: the exact layouts of a strictly convex polygon;
- :func:`pentagons_from_pieces`: convex pieces (triangles, quadrilaterals, ...) to pentagons,
  conformingly (used for triangulations and for converting existing meshes).

Modules: :mod:`~blockmesh.decompose.templates` (the templates), :mod:`~.convex` (exact convex
layouts), :mod:`~.triangulate` (quality triangulation), :mod:`~.pieces` (templates over pieces),
:mod:`~.optimise` (moving free nodes), :mod:`~.polygon` (the route), :mod:`~.conversion` (meshes).

Examples
--------
>>> import numpy as np
>>> d = decompose_convex_polygon(np.array([[0, 0], [1, 0], [0, 1]], dtype=float))
>>> d.layout, d.blocks.shape
('triangle-template', (9, 5))
"""

from blockmesh.decompose.convex import Decomposition, decompose_convex_polygon
from blockmesh.decompose.pieces import PiecePentagons, pentagons_from_pieces
from blockmesh.decompose.polygon import decompose_polygon

__all__ = [
    "Decomposition",
    "PiecePentagons",
    "decompose_convex_polygon",
    "decompose_polygon",
    "pentagons_from_pieces",
]
