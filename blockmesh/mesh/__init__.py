"""The all-pentagon mesh (:class:`Mesh`), its measures, and meshes of any polygons.

:mod:`~blockmesh.mesh.mesh` defines the frozen dataclass of read-only arrays every stage passes
on; :mod:`~blockmesh.mesh.measures` measures its cells in one chunked pass;
:mod:`~blockmesh.mesh.polygons` holds :class:`PolygonMesh`, cells of any vertex count (local
refinement's hanging nodes, the virtual element solver's meshes).
"""

from __future__ import annotations

from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.mesh.quality import MeshQuality

__all__ = ["Mesh", "MeshQuality", "PolygonMesh"]
