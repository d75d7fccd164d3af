"""The validated multi-block domain every mesh starts from, and where domains come from.

- :mod:`~blockmesh.domain.domain`: :class:`Domain` and its constructors;
- :mod:`~blockmesh.domain.validate`: checks and repairs of input, each failure located;
- :mod:`~blockmesh.domain.tomlio`: domain files (TOML) read and written;
- :mod:`~blockmesh.domain.loading`: catalogue names, files, map outlines, meshes, polygons;
- :mod:`~blockmesh.domain.catalogue`: the ready-made domains shipped with the package;
- :mod:`~blockmesh.domain.blockgraph`: blocks and their shared edges as a networkx graph;
- :mod:`~blockmesh.domain.curved_polygons` and :mod:`~blockmesh.domain.curve_checks`: arcs and
  circles on polygons, and the checks of curved blocks.
"""

from __future__ import annotations

from blockmesh.domain.domain import Domain

__all__ = ["Domain"]
