"""Interfaces carried through a refinement: every interface edge becomes its ``2^L`` pieces.

An interface (an internal patch, :attr:`blockmesh.Mesh.interface_edges`) is a set of edges
shared by two cells. Refining splits each of them as it splits every edge: the nodes along it are
the ones the refinement plan numbers for that edge
(:func:`~blockmesh.refinement.plan.edge_node_ids`), the same for both cells, so the refined
interface is a chain of fine edges between the same two coarse cells' children. Found from the
plan alone, by topology: no coordinates are compared.

Examples
--------
>>> import numpy as np
>>> import blockmesh
>>> from blockmesh.geometry.topology import cell_neighbours
>>> base = blockmesh.load_domain("joined-2").mesh(0).with_interfaces([[1, 2]], [0], ["glue"])
>>> refined_interfaces(base, cell_neighbours(base.cells, base.n_points), 2).tolist()
[[1, 37], [37, 9], [9, 49], [49, 2]]
"""

from __future__ import annotations

import numpy as np

from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.plan import edge_node_ids, plan_refinement

__all__ = ["refined_interfaces"]


def refined_interfaces(base: Mesh, neighbour: np.ndarray, steps: int) -> np.ndarray:
    """The interface edges of ``base`` refined ``steps`` times, (Ei 2^steps, 2), in order.

    Edge ``k`` of the base becomes rows ``k 2^steps .. (k + 1) 2^steps - 1``, running the same
    way (so the first side stays on the left); the patch of each is the base edge's
    (``np.repeat(base.interface_patch, 2**steps)``). O(B steps + Ei 2^steps).
    """
    edges = base.interface_edges
    if edges.shape[0] == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if steps == 0:
        return np.array(edges)
    left = base.interface_cells()[:, 0]
    following = np.roll(base.cells[left], -1, axis=1)
    slot = np.argmax((base.cells[left] == edges[:, :1]) & (following == edges[:, 1:]), axis=1)
    plan = plan_refinement(base.cells, neighbour, base.n_points, steps)
    chains = np.stack(
        [edge_node_ids(plan, int(c), int(e)) for c, e in zip(left, slot, strict=True)]
    )
    return np.stack([chains[:, :-1], chains[:, 1:]], axis=-1).reshape(-1, 2)
