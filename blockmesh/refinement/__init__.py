"""Refinement of a block mesh into a conforming all-pentagon mesh: plan, place, assemble.

:func:`refine` is the one entry point. The path it takes, module by module:

- :mod:`~blockmesh.refinement.sizes`: counts and memory predicted before anything is built;
- :mod:`~blockmesh.refinement.template`: one reference pentagon refined, numbered like the paper;
- :mod:`~blockmesh.refinement.plan`: global node ids of every block from prefix sums;
- :mod:`~blockmesh.refinement.grouped`: groups of blocks refined on worker threads;
- :mod:`~blockmesh.refinement.curved`, :mod:`~blockmesh.refinement.smoothing`,
  :mod:`~blockmesh.refinement.improve`: node placements other than the paper's midpoints;
- :mod:`~blockmesh.refinement.limits`: the memory and precision a level needs, checked first;
- :mod:`~blockmesh.refinement.assemble`: the blocks refined and the Mesh assembled from them;
- :mod:`~blockmesh.refinement.pipeline`: :func:`refine` itself, which ties them together;
- :mod:`~blockmesh.refinement.local`: with ``cells=``, only the marked cells split (hanging
  nodes, a :class:`~blockmesh.mesh.polygons.PolygonMesh`); :mod:`~blockmesh.refinement.marking`
  chooses them by expression, region or distance to a patch.
"""

from __future__ import annotations

from blockmesh._system.memory import available_memory
from blockmesh.refinement.pipeline import NUMBERINGS, refine
from blockmesh.refinement.sizes import MeshSize, predict_size

__all__ = ["NUMBERINGS", "MeshSize", "available_memory", "predict_size", "refine"]
