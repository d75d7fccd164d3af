"""The solver's mesh: :class:`~blockmesh.mesh.polygons.PolygonMesh`, cells of any size.

The virtual element solver works on a :class:`~blockmesh.mesh.polygons.PolygonMesh` (one type for
the whole package: the meshes local refinement makes, and the triangle, quadrilateral or mixed
meshes of :meth:`~blockmesh.mesh.polygons.PolygonMesh.from_cells`); a blockmesh
:class:`~blockmesh.mesh.Mesh` (all pentagons) is converted by :func:`as_polygon_mesh`. Its cells,
grouped by vertex count (:attr:`~blockmesh.mesh.polygons.PolygonMesh.groups`), let the element
matrices of a group be computed at once. Every cell runs counter-clockwise and is star-shaped with
respect to its vertex mean; hanging nodes are straight vertices of the coarser cell, which the
lowest-order virtual element space takes as it is.

Examples
--------
>>> import numpy as np
>>> square = [(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5)]
>>> mesh = PolygonMesh.from_cells(square, [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
>>> mesh.n_cells, mesh.n_points, [g.size for g in mesh.groups]
(4, 5, [3])
>>> mesh.patch_names, mesh.boundary_edges.shape
(('boundary',), (4, 2))
"""

from __future__ import annotations

from blockmesh.mesh.polygons import CellGroup, PolygonMesh, as_polygon_mesh

__all__ = ["CellGroup", "PolygonMesh", "as_polygon_mesh"]
