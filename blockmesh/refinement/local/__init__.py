"""Local refinement: the marked cells split, their new edge nodes hanging on coarse neighbours.

:func:`refine_marked` splits the marked cells of a mesh once and returns a
:class:`~blockmesh.mesh.polygons.PolygonMesh`; :func:`blockmesh.refine` calls it when given
``cells=``. The rule for a cell with ``k`` corners ``v_1 .. v_k`` (its vertices where the boundary
turns; hanging nodes are straight vertices, not corners), counter-clockwise:

- ``u_i`` is the midpoint of the side ``v_i v_i+1``: the node already there when the side carries
  a hanging node (a finer neighbour put it at the side's midpoint), else a new node
  ``(v_i + v_i+1) / 2`` (on a curved side: the curve's point at the mean of the side's two
  parameters);
- ``p`` is the mean of the corners ``(v_1 + ... + v_k) / k`` (with a curved side:
  ``p = (2/k) Σ u_i - (1/k) Σ v_i``, the rule of :mod:`blockmesh.refinement.curved`);
- ``w_i = (u_i + p) / 2``;
- the children are the ``k`` corner pentagons ``<v_i, u_i, w_i, w_i-1, u_i-1>`` and the central
  ``k``-gon ``<w_1 .. w_k>``.

For ``k = 5`` this is the paper's rule (eq. 1a), with its arithmetic: marking every cell of a
pentagon mesh gives :func:`blockmesh.refine` one level, bit for bit and numbered alike. For other
``k`` it is the seed's "refinement scheme of a general polygon based on the pentagon scheme":
every child but the centre is a pentagon, and the centre keeps the parent's shape (why this one:
``docs/mathematics.md``, "Local refinement").

A new midpoint becomes a vertex of the neighbour across the side too (a straight vertex, a
*hanging node*), so the mesh stays conforming: no edge has a node inside it that its cells do not
list. At most one hanging node per side is kept: a marked cell whose side would split an edge
that already halves a coarser neighbour's side makes that neighbour refined as well (repeated
until nothing changes). New nodes are numbered as the paper numbers them: cell by cell in order,
the new midpoints of its sides, then its inner points.

Costs: O(S log S) for S = the vertex slots of all cells (one sort of the edge keys); the marked
set is closed in a few whole-array passes; the memory needed is predicted from the marked count
before anything is built.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("sp").mesh(1)
>>> fine = refine_marked(mesh, [0])
>>> fine.n_cells, fine.n_points, sorted(set(fine.cell_sizes().tolist()))
(11, 25, [5, 6])
>>> bool(abs(fine.area - mesh.area) < 1e-12), fine.hanging_nodes().size
(True, 3)
"""

from __future__ import annotations

from blockmesh.refinement.local.marked import HANGING_PER_SIDE, close_marking, marked_cells
from blockmesh.refinement.local.refine import refine_locally, refine_marked
from blockmesh.refinement.local.sizes import LocalSize, predict_local_size
from blockmesh.refinement.local.split import SCHEMES, check_scheme

__all__ = [
    "HANGING_PER_SIDE",
    "SCHEMES",
    "LocalSize",
    "check_scheme",
    "close_marking",
    "marked_cells",
    "predict_local_size",
    "refine_locally",
    "refine_marked",
]
