"""Which cells a local refinement splits: the marking read, the cells' sides, the marking closed.

:func:`marked_cells` reads a marking (a mask, cell ids or a callable) as a mask;
:func:`cell_sides` finds the sides (corner-to-corner runs of edges) of every cell;
:func:`close_marking` grows the marked set until splitting it leaves at most
:data:`HANGING_PER_SIDE` hanging node per side, and :func:`check_sides` refuses a marked cell
with more.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError, DomainError
from blockmesh.geometry.topology import cell_neighbours
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "HANGING_PER_SIDE",
    "Marking",
    "Sides",
    "cell_sides",
    "check_sides",
    "close_marking",
    "marked_cells",
]

#: Hanging nodes a side of a cell may carry after local refinement.
HANGING_PER_SIDE = 1

Marking = Any  # a boolean mask, cell ids, or a callable mesh -> mask


def marked_cells(
    mesh: PolygonMesh | Mesh, cells: Marking, *, allow_empty: bool = False
) -> np.ndarray:
    """``cells`` as a boolean mask over the cells of ``mesh``.

    ``cells`` is a boolean mask (M,), an array or sequence of cell ids, or a callable
    ``cells(mesh)`` returning either. ArgumentError for ids out of range or a mask of the wrong
    length; a marking that marks nothing is an ArgumentError too (saying so, not a silent no-op)
    unless ``allow_empty``.

    Examples
    --------
    >>> import blockmesh
    >>> mesh = blockmesh.load_domain("sp").mesh(1)
    >>> marked_cells(mesh, [0, 5]).tolist()
    [True, False, False, False, False, True]
    """
    m = mesh.n_cells
    what = "the marking"
    if callable(cells):
        what = f"the marking ({cells.__doc__})" if cells.__doc__ else what
        cells = cells(mesh)
    if isinstance(cells, bool | str) or cells is None:
        raise ArgumentTypeError(
            f"cells must be a boolean mask, cell ids or a callable, not {cells!r}"
        )
    try:
        array = np.asarray(cells)
    except (TypeError, ValueError) as error:
        raise ArgumentTypeError(f"cells cannot be read as cell ids or a mask: {error}") from None
    if array.dtype == bool:
        if array.shape != (m,):
            raise ArgumentError(
                f"a cell mask must have one entry per cell ({m}), got shape {array.shape}"
            )
        mask = array.copy()
    else:
        if array.size and array.dtype.kind not in "iu":
            raise ArgumentTypeError(f"cell ids must be integers, got {array.dtype}")
        ids = array.astype(np.int64).ravel()
        if ids.size and (ids.min() < 0 or ids.max() >= m):
            bad = int(ids[(ids < 0) | (ids >= m)][0])
            raise ArgumentError(f"cell {bad} does not exist: the mesh has cells 0..{m - 1}")
        mask = np.zeros(m, dtype=bool)
        mask[ids] = True
    if not mask.any() and not allow_empty:
        raise ArgumentError(
            f"{what} marks none of the {m:,} cells; nothing would be refined (mark at "
            "least one cell, or refine uniformly with level=)"
        )
    return mask


class Sides(NamedTuple):
    """The sides (corner-to-corner runs of edges) of every cell, indexed by side."""

    first_slot: np.ndarray  # (K,) the slot starting at the side's corner
    length: np.ndarray  # (K,) edges on the side (1, or 2 with a hanging node)
    cell: np.ndarray  # (K,) the side's cell
    cell_first: np.ndarray  # (M + 1,) sides of cell c are cell_first[c] .. cell_first[c+1]-1
    slot_side: np.ndarray  # (S,) the side of every slot


def cell_sides(mesh: PolygonMesh) -> Sides:
    """The sides of every cell of ``mesh``, cell by cell (:class:`Sides`)."""
    side, length = mesh.sides()
    corner = ~mesh.straight_vertices()
    first_slot = np.flatnonzero(corner)
    cells = mesh.polygon_cells()
    cell = cells.slot_cell()[first_slot]
    cell_first = np.searchsorted(cell, np.arange(mesh.n_cells + 1))
    return Sides(first_slot, length, cell, cell_first, side)


def close_marking(mesh: PolygonMesh, marked: np.ndarray) -> np.ndarray:
    """The marked set grown until splitting it leaves at most one hanging node per side.

    A marked cell splits each of its sides that carries no hanging node. When such a side is
    half of a coarser neighbour's side (which then already carries one hanging node), that
    neighbour is marked too; repeated until nothing changes (at most the number of levels the
    mesh's cells differ by). Whole-array passes, O(S) each.

    Examples
    --------
    >>> import blockmesh
    >>> from blockmesh.refinement.local import refine_marked
    >>> once = refine_marked(blockmesh.load_domain("joined-2").mesh(0), [0])
    >>> int(once.side_lengths().max())  # cell 1 got hanging nodes from cell 0's split
    2
    >>> once.cell_lists()[1], once.cell_lists()[6]  # child 1 halves a side of the hexagon
    ([1, 9, 14, 13, 8], [1, 5, 6, 7, 2, 9])
    >>> close_marking(once, np.arange(7) == 1).tolist()  # so splitting it splits the hexagon
    [False, True, False, False, False, False, True]
    """
    sides = cell_sides(mesh)
    cells = mesh.polygon_cells()
    neighbour = cell_neighbours(cells, mesh.n_points)
    single = sides.length[sides.slot_side] == 1
    across = neighbour >= 0
    coarse_across = np.zeros(neighbour.size, dtype=bool)
    coarse_across[across] = sides.length[sides.slot_side[neighbour[across]]] >= 2
    # slots whose split would add a second hanging node to the cell across
    pushes = single & coarse_across
    owner = cells.slot_cell()
    target = np.where(across, owner[np.maximum(neighbour, 0)], -1)
    marked = marked.copy()
    while True:
        active = pushes & marked[owner]
        grow = np.unique(target[active])
        grow = grow[~marked[grow]]
        if grow.size == 0:
            return marked
        marked[grow] = True


def check_sides(mesh: PolygonMesh, sides: Sides, marked: np.ndarray) -> None:
    """DomainError naming a marked cell with more than :data:`HANGING_PER_SIDE` on a side."""
    too_long = marked[sides.cell] & (sides.length > HANGING_PER_SIDE + 1)
    if np.any(too_long):
        side = int(np.flatnonzero(too_long)[0])
        cell = int(sides.cell[side])
        raise DomainError(
            f"cell {cell} (nodes {mesh.cell(cell).tolist()}) has {int(sides.length[side]) - 1} "
            "hanging nodes on one side; local refinement splits cells with at most "
            f"{HANGING_PER_SIDE} per side (refine its finer neighbours' parents first, or split "
            "that side's cell by hand)"
        )
