"""The all-pentagon mesh (:class:`Mesh`) and its measures.

:mod:`~blockmesh.mesh.mesh` defines the frozen dataclass of read-only arrays every stage passes
on; :mod:`~blockmesh.mesh.measures` measures its cells in one chunked pass.
"""

from __future__ import annotations

from blockmesh.mesh.mesh import Mesh, MeshQuality

__all__ = ["Mesh", "MeshQuality"]
