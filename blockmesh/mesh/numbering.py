"""Node numbering of a mesh: its bandwidth, a permutation applied, reverse Cuthill-McKee.

:func:`renumbered` gives any mesh (a :class:`~blockmesh.mesh.Mesh` or a
:class:`~blockmesh.mesh.polygons.PolygonMesh`) its nodes in another order; :func:`bandwidth` and
:func:`polygon_bandwidth` measure the largest spread of node ids in a cell;
:func:`rcm_order` finds the reverse Cuthill-McKee order of a pentagon mesh (scipy).

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("sp").mesh(1)
>>> bandwidth(mesh.cells), bandwidth(mesh.cells[:, ::-1])
(14, 14)
"""

from __future__ import annotations

from typing import Any, TypeVar

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.geometry.topology import PolygonCells
from blockmesh.mesh.labels import copy_mesh
from blockmesh.mesh.measures import widest_id_spread

__all__ = [
    "BANDWIDTH_CHUNK",
    "bandwidth",
    "checked_order",
    "polygon_bandwidth",
    "rcm_order",
    "renumbered",
]

M = TypeVar("M")

#: Cells per step of :func:`bandwidth` (five columns of int64 temporaries in cache).
BANDWIDTH_CHUNK = 1 << 15


def bandwidth(cells: np.ndarray) -> int:
    """Largest difference between two node ids of one cell of ``cells`` (M, k), in chunks."""
    work = np.empty((2, BANDWIDTH_CHUNK), dtype=np.int64)
    widest = 0
    for start in range(0, cells.shape[0], BANDWIDTH_CHUNK):
        columns = cells[start : start + BANDWIDTH_CHUNK].T
        widest = max(widest, widest_id_spread(columns, work[:, : columns.shape[1]]))
    return widest


def polygon_bandwidth(cells: PolygonCells) -> int:
    """Largest difference between two node ids of one cell of ``cells`` (compressed rows)."""
    owner = cells.slot_cell()
    high = np.full(cells.n_cells, -1, dtype=np.int64)
    low = np.full(cells.n_cells, np.iinfo(np.int64).max, dtype=np.int64)
    np.maximum.at(high, owner, cells.nodes)
    np.minimum.at(low, owner, cells.nodes)
    return int((high - low).max(initial=0))


def checked_order(order: Any, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """``order`` checked as a permutation of ``0..n_points - 1``, and its inverse (new ids)."""
    try:
        order = np.asarray(order, dtype=np.int64)
    except (TypeError, ValueError) as error:
        raise ArgumentTypeError(
            f"order must be an array of node ids, got {type(order).__name__} {order!r:.60}"
        ) from error
    if order.shape != (n_points,) or not np.array_equal(np.sort(order), np.arange(n_points)):
        raise ArgumentError("order must be a permutation of the node ids 0..N-1")
    new_id = np.empty_like(order)
    new_id[order] = np.arange(n_points)
    return order, new_id


def renumbered(mesh: M, order: Any, cells: str) -> M:
    """``mesh`` with node ``order[k]`` renamed ``k``; ``cells`` names its array of node ids."""
    order, new_id = checked_order(order, mesh.n_points)  # type: ignore[attr-defined]
    curves = mesh.curves  # type: ignore[attr-defined]
    return copy_mesh(
        mesh,
        {
            "points": mesh.points[order],  # type: ignore[attr-defined]
            cells: new_id[getattr(mesh, cells)],
            "boundary_edges": new_id[mesh.boundary_edges],  # type: ignore[attr-defined]
            "interface_edges": new_id[mesh.interface_edges],  # type: ignore[attr-defined]
            "curves": None if curves is None else curves.renumbered(new_id),
        },
    )


def rcm_order(cells: np.ndarray, n_points: int) -> np.ndarray:
    """The reverse Cuthill-McKee order of the nodes of ``cells`` (M, 5) (scipy)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    rows = np.repeat(cells, 5, axis=1).ravel()
    cols = np.tile(cells, (1, 5)).ravel()
    graph = coo_matrix(
        (np.ones(rows.size, dtype=np.int8), (rows, cols)), shape=(n_points,) * 2
    ).tocsr()
    order = reverse_cuthill_mckee(graph, symmetric_mode=True)
    return np.asarray(order, dtype=np.int64)
