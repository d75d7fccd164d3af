"""The validated multi-block domain every mesh starts from, and where domains come from.

- :mod:`~blockmesh.domain.domain`: :class:`Domain`, its fields, and one thin method per
  query and meshing entry point;
- :mod:`~blockmesh.domain.constructors`: the alternate constructors (``from_polygon``,
  ``from_blocks``, ...), bound to :class:`Domain` as classmethods;
- :mod:`~blockmesh.domain.assemble`: the fields checked and stored, however a Domain is made;
- :mod:`~blockmesh.domain.validate`: checks and repairs of input, each failure located (points,
  rings, blocks, topology, names);
- :mod:`~blockmesh.domain.merge`: vertices closer than ``merge_tol`` merged;
- :mod:`~blockmesh.domain.polygons`: polygons and shapely geometry decomposed into a Domain;
  :mod:`~blockmesh.domain.polygon_edges`: polygon edges as a user names them in patches;
- :mod:`~blockmesh.domain.converted`: triangle and quadrilateral meshes converted;
- :mod:`~blockmesh.domain.tomlio`: domain files (TOML) read and written;
- :mod:`~blockmesh.domain.loading`: catalogue names, files, map outlines, meshes, polygons;
- :mod:`~blockmesh.domain.catalogue`: the ready-made domains shipped with the package;
- :mod:`~blockmesh.domain.blockgraph`: blocks and their shared edges as a networkx graph;
- :mod:`~blockmesh.domain.curved_polygons` and :mod:`~blockmesh.domain.curve_checks`: arcs and
  circles on polygons, and the checks of curved blocks;
- :mod:`~blockmesh.domain.parts`, :mod:`~blockmesh.domain.compose` and
  :mod:`~blockmesh.domain.interfaces`: composite domains, their parts and interfaces;
- :mod:`~blockmesh.domain.sized`: a domain re-cut into blocks of the sizes asked.
"""

from __future__ import annotations

from blockmesh.domain.domain import Domain

__all__ = ["Domain"]
