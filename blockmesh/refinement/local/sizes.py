"""What a local refinement makes, predicted before it is built, and the check that it fits.

:func:`predict_local_size` counts the cells, nodes and peak memory of splitting a closed marking
(closed forms, no mesh built); :func:`check_memory` refuses one that does not fit.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from blockmesh._system.memory import available_memory, format_bytes, format_count
from blockmesh.errors import ResourceError
from blockmesh.geometry.topology import edge_keys
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.local.marked import Sides, cell_sides
from blockmesh.refinement.local.split import check_scheme

__all__ = ["LocalSize", "check_memory", "predict_local_size"]

#: Bytes per cell and per node of a PolygonMesh and the work of refining it (the cell arrays,
#: about six vertices a cell at 8 bytes, the node coordinates, and the sorts' temporaries).
_BYTES_PER_CELL = 8 * 6 * 4 + 5 * 8
_BYTES_PER_NODE = 16 * 3


class LocalSize(NamedTuple):
    """What refining a marked set makes, predicted before it is built.

    Attributes
    ----------
    marked : int
        Cells split (the marking closed by the hanging-node bound).
    cells, nodes : int
        Cells and nodes of the refined mesh.
    peak_bytes : int
        Memory the refinement needs at its peak (an estimate on the safe side).
    """

    marked: int
    cells: int
    nodes: int
    peak_bytes: int


def predict_local_size(
    mesh: PolygonMesh, marked: np.ndarray, scheme: str = "pentagons"
) -> LocalSize:
    """Cells, nodes and memory of :func:`refine_marked` for a closed marking.

    Closed forms, over the marked cells c with ``k_c`` corners and ``E_split`` the distinct
    edges that are a whole side of a marked cell (each gets one new node): ``"pentagons"``
    makes ``cells = M + Σ k_c`` and ``nodes = N + Σ k_c + E_split``; ``"quads"`` makes
    ``cells = M + Σ (k_c - 1)`` and ``nodes = N + (marked cells) + E_split``.
    """
    check_scheme(scheme)
    sides = cell_sides(mesh)
    corners = np.diff(sides.cell_first)
    n_marked = int(np.count_nonzero(marked))
    added = int(corners[marked].sum())
    split = _split_keys(mesh, sides, marked)
    if scheme == "quads":
        cells = mesh.n_cells + added - n_marked
        nodes = mesh.n_points + n_marked + int(split.size)
    else:
        cells = mesh.n_cells + added
        nodes = mesh.n_points + added + int(split.size)
    slots = int(mesh.nodes.size) + 6 * added
    peak = _BYTES_PER_CELL * cells + _BYTES_PER_NODE * nodes + 8 * 6 * slots
    return LocalSize(n_marked, cells, nodes, peak)


def _split_keys(mesh: PolygonMesh, sides: Sides, marked: np.ndarray) -> np.ndarray:
    """Sorted unique keys of the edges the marked cells split (their one-edge sides)."""
    chosen = marked[sides.cell] & (sides.length == 1)
    slots = sides.first_slot[chosen]
    following = mesh.polygon_cells().following()
    return np.unique(edge_keys(mesh.nodes[slots], following[slots], mesh.n_points))


def check_memory(mesh: PolygonMesh, size: LocalSize, max_memory: int | None) -> None:
    """ResourceError when ``size`` needs more than ``max_memory`` (default: the memory free)."""
    limit = available_memory() if max_memory is None else int(max_memory)
    if size.peak_bytes <= limit:
        return
    source = "the limit given" if max_memory is not None else "the memory available now"
    per_cell = size.peak_bytes / max(size.cells, 1)
    fits = max(int(limit / per_cell) - mesh.n_cells, 0) // 5
    raise ResourceError(
        f"refining {format_count(size.marked)} marked cells of {mesh.name or 'the mesh'} "
        f"({format_count(mesh.n_cells)} cells) needs about {format_bytes(size.peak_bytes)} for "
        f"{format_count(size.cells)} cells and {format_count(size.nodes)} nodes, more than "
        f"{source} ({format_bytes(limit)}); mark fewer cells (about {format_count(fits)} fit)"
    )
