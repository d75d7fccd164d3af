"""The entry points of local refinement: one split of the marked cells, or several rounds.

:func:`refine_marked` closes a marking, checks it and its memory, and splits it once;
:func:`refine_locally` repeats that round after round (what :func:`blockmesh.refine` calls with
``cells=``).
"""

from __future__ import annotations

from collections.abc import Callable

from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh, as_polygon_mesh
from blockmesh.refinement.local.marked import (
    Marking,
    cell_sides,
    check_sides,
    close_marking,
    marked_cells,
)
from blockmesh.refinement.local.sizes import check_memory, predict_local_size
from blockmesh.refinement.local.split import check_scheme, split_cells

__all__ = ["refine_locally", "refine_marked"]


def refine_marked(
    mesh: PolygonMesh | Mesh,
    cells: Marking,
    *,
    max_memory: int | None = None,
    scheme: str = "pentagons",
) -> PolygonMesh:
    """Split the marked cells once (and the neighbours the hanging-node bound needs).

    Parameters
    ----------
    mesh : PolygonMesh or Mesh
    cells : boolean mask, cell ids, or callable
        The cells to split (see :func:`marked_cells`).
    max_memory : int, optional
        Refuse a refinement predicted to need more bytes (default: the memory available now).
    scheme : {"pentagons", "quads"}
        How a marked cell is split (:data:`SCHEMES`); ``"pentagons"``, the paper's, by default.

    Returns
    -------
    PolygonMesh
        Level ``mesh.level + 1``; ``parent`` is the cell of ``mesh`` each cell is or lies in,
        ``cell_level`` one more on the children.

    Raises
    ------
    ArgumentError
        A marking that marks nothing, or ids out of range.
    DomainError
        A cell that cannot be split: a side with more than one hanging node, or a cell next to
        a curve whose children would fold (named, with its vertices).
    ResourceError
        When the predicted size does not fit the memory.
    """
    scheme = check_scheme(scheme)
    pm = as_polygon_mesh(mesh)
    marked = close_marking(pm, marked_cells(pm, cells))
    sides = cell_sides(pm)
    check_sides(pm, sides, marked)
    size = predict_local_size(pm, marked, scheme)
    check_memory(pm, size, max_memory)
    return split_cells(pm, sides, marked, scheme)


def refine_locally(
    mesh: PolygonMesh | Mesh,
    cells: Marking,
    rounds: int = 1,
    *,
    max_memory: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    scheme: str = "pentagons",
) -> PolygonMesh:
    """Split the marked cells ``rounds`` times.

    A callable ``cells(mesh)`` is asked again on every round's mesh (e.g. "the cells within 0.1
    of the wall": their children near the wall are split again); a mask or ids mark the given
    cells in the first round and their children in the next ones. A later round that marks
    nothing ends the refinement there.

    Examples
    --------
    >>> import blockmesh
    >>> mesh = refine_locally(blockmesh.load_domain("sp").mesh(1), [0], rounds=2)
    >>> mesh.n_cells, mesh.level, int(mesh.cell_level.max())
    (56, 3, 3)
    """
    current = as_polygon_mesh(mesh)
    chosen = marked_cells(current, cells)
    previous_level = current.cell_level
    for done in range(rounds):
        if done:
            if callable(cells):
                chosen = marked_cells(current, cells, allow_empty=True)
            else:
                was = chosen[current.parent]
                chosen = was & (current.cell_level > previous_level[current.parent])
            if not chosen.any():
                break
        previous_level = current.cell_level
        current = refine_marked(current, chosen, max_memory=max_memory, scheme=scheme)
        if progress is not None:
            progress(done + 1, rounds)
    return current
