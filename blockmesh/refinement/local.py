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

from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from blockmesh._system.memory import available_memory, format_bytes, format_count
from blockmesh.curves.edges import CurvedEdges, curved_slots
from blockmesh.errors import ArgumentError, ArgumentTypeError, DomainError, ResourceError
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL
from blockmesh.geometry.topology import PolygonCells, cell_neighbours, edge_keys
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh, as_polygon_mesh

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

#: An empty curve table (meshes without curves).
_NO_CURVES = CurvedEdges(
    edges=np.empty((0, 2), np.int64),
    curve=np.empty(0, np.int64),
    start=np.empty(0),
    stop=np.empty(0),
    curves=(),
)

#: How a marked cell of k corners is split, by name (``scheme=``).
SCHEMES = {
    "pentagons": "the paper's rule: k corner pentagons <v_i, u_i, w_i, w_i-1, u_i-1> and the "
    "central k-gon <w_1 .. w_k> (six pentagons for a pentagon)",
    "quads": "k quadrilaterals <v_i, u_i, p, u_i-1> through the centre p (a quadtree on squares)",
}


def check_scheme(scheme: object) -> str:
    """``scheme`` if it is one of :data:`SCHEMES` (ArgumentError listing them otherwise)."""
    if scheme not in SCHEMES:
        listed = "; ".join(f"{k}: {v}" for k, v in SCHEMES.items())
        raise ArgumentError(f"unknown scheme {scheme!r}; choose one of {listed}")
    return str(scheme)


#: Hanging nodes a side of a cell may carry after local refinement.
HANGING_PER_SIDE = 1

#: Bytes per cell and per node of a PolygonMesh and the work of refining it (the cell arrays,
#: about six vertices a cell at 8 bytes, the node coordinates, and the sorts' temporaries).
_BYTES_PER_CELL = 8 * 6 * 4 + 5 * 8
_BYTES_PER_NODE = 16 * 3

Marking = Any  # a boolean mask, cell ids, or a callable mesh -> mask


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


# ---------------------------------------------------------------------- marking
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


class _Sides(NamedTuple):
    """The sides (corner-to-corner runs of edges) of every cell, indexed by side."""

    first_slot: np.ndarray  # (K,) the slot starting at the side's corner
    length: np.ndarray  # (K,) edges on the side (1, or 2 with a hanging node)
    cell: np.ndarray  # (K,) the side's cell
    cell_first: np.ndarray  # (M + 1,) sides of cell c are cell_first[c] .. cell_first[c+1]-1
    slot_side: np.ndarray  # (S,) the side of every slot


def _sides(mesh: PolygonMesh) -> _Sides:
    side, length = mesh.sides()
    corner = ~mesh.straight_vertices()
    first_slot = np.flatnonzero(corner)
    cells = mesh.polygon_cells()
    cell = cells.slot_cell()[first_slot]
    cell_first = np.searchsorted(cell, np.arange(mesh.n_cells + 1))
    return _Sides(first_slot, length, cell, cell_first, side)


def close_marking(mesh: PolygonMesh, marked: np.ndarray) -> np.ndarray:
    """The marked set grown until splitting it leaves at most one hanging node per side.

    A marked cell splits each of its sides that carries no hanging node. When such a side is
    half of a coarser neighbour's side (which then already carries one hanging node), that
    neighbour is marked too; repeated until nothing changes (at most the number of levels the
    mesh's cells differ by). Whole-array passes, O(S) each.

    Examples
    --------
    >>> import blockmesh
    >>> once = refine_marked(blockmesh.load_domain("joined-2").mesh(0), [0])
    >>> int(once.side_lengths().max())  # cell 1 got hanging nodes from cell 0's split
    2
    >>> once.cell_lists()[1], once.cell_lists()[6]  # child 1 halves a side of the hexagon
    ([1, 9, 14, 13, 8], [1, 5, 6, 7, 2, 9])
    >>> close_marking(once, np.arange(7) == 1).tolist()  # so splitting it splits the hexagon
    [False, True, False, False, False, False, True]
    """
    sides = _sides(mesh)
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
    sides = _sides(mesh)
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


def _split_keys(mesh: PolygonMesh, sides: _Sides, marked: np.ndarray) -> np.ndarray:
    """Sorted unique keys of the edges the marked cells split (their one-edge sides)."""
    chosen = marked[sides.cell] & (sides.length == 1)
    slots = sides.first_slot[chosen]
    following = mesh.polygon_cells().following()
    return np.unique(edge_keys(mesh.nodes[slots], following[slots], mesh.n_points))


# ------------------------------------------------------------------- refinement
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
    sides = _sides(pm)
    _check_sides(pm, sides, marked)
    size = predict_local_size(pm, marked, scheme)
    _check_memory(pm, size, max_memory)
    return _split(pm, sides, marked, scheme)


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


def _check_sides(mesh: PolygonMesh, sides: _Sides, marked: np.ndarray) -> None:
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


def _check_memory(mesh: PolygonMesh, size: LocalSize, max_memory: int | None) -> None:
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


def _corner_sums(values: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Per marked cell, the sum of its rows of ``values`` (R, 2), left to right as the paper.

    ``values`` holds each cell's ``counts[c]`` rows one cell after another; the sum runs
    ``((v1 + v2) + v3) + ...`` (the paper's order, so a pentagon's centre has its bits).
    """
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    out = values[starts].copy()
    for j in range(1, int(counts.max(initial=0))):
        more = counts > j
        out[more] += values[starts[more] + j]
    return out


def _split(
    mesh: PolygonMesh, sides: _Sides, marked: np.ndarray, scheme: str = "pentagons"
) -> PolygonMesh:
    """The refined mesh of a closed, checked marking, by ``scheme`` (see :data:`SCHEMES`)."""
    quads = scheme == "quads"
    n = mesh.n_points
    cells = mesh.polygon_cells()
    following = cells.following()
    next_slot = cells.next_slot()
    owner_side = sides.cell
    k_all = np.diff(sides.cell_first)

    # The sides of the marked cells, cell by cell (R rows).
    rows = np.flatnonzero(marked[owner_side])
    marked_ids = np.flatnonzero(marked)
    k = k_all[marked_ids]
    first = sides.first_slot[rows]
    length = sides.length[rows]
    corner = mesh.nodes[first]
    end = np.where(length == 1, following[first], following[next_slot[first]])
    hanging = following[first]  # the side's middle node when length == 2

    # Curved sides: the row of the curves table of each (first) edge.
    curves = mesh.curves if mesh.curves is not None else _NO_CURVES
    has_curves = len(curves) > 0
    if has_curves:
        slot_row, _ = curved_slots(cells, n, curves)
        side_row = slot_row[first]
        curved_side = side_row >= 0
    else:
        side_row = np.full(rows.size, -1, dtype=np.int64)
        curved_side = np.zeros(rows.size, dtype=bool)

    # New nodes, numbered as the paper: per marked cell, its new midpoints, then inner points.
    split_side = length == 1
    split_key = edge_keys(corner[split_side], end[split_side], n)
    rank = np.repeat(np.arange(marked_ids.size), k)  # the marked cell of every side row
    within = np.arange(rows.size) - np.repeat(np.cumsum(k) - k, k)
    keys_sorted, first_request = np.unique(split_key, return_index=True)
    split_rows = np.flatnonzero(split_side)
    owner_of_key = rank[split_rows[first_request]]
    order_of_key = within[split_rows[first_request]]
    # request order: (marked cell, 0 = midpoint / 1 = inner point, side)
    inner_cell = np.arange(marked_ids.size) if quads else rank  # quads: one centre per cell
    inner_side = np.zeros(marked_ids.size, np.int64) if quads else within
    req_cell = np.concatenate([owner_of_key, inner_cell])
    req_kind = np.concatenate(
        [np.zeros(keys_sorted.size, np.int64), np.ones(inner_cell.size, np.int64)]
    )
    req_side = np.concatenate([order_of_key, inner_side])
    request_order = np.lexsort((req_side, req_kind, req_cell))
    new_id = np.empty(request_order.size, dtype=np.int64)
    new_id[request_order] = n + np.arange(request_order.size)
    mid_id_of_key = new_id[: keys_sorted.size]
    inner_id = new_id[keys_sorted.size :]  # per side row: w_i (per marked cell: p for quads)

    # u_i per side row: the existing hanging node, or the new midpoint of the side's edge.
    u_id = hanging.copy()
    at = np.searchsorted(keys_sorted, split_key)
    u_id[split_side] = mid_id_of_key[at]
    # From here on edges may end at new nodes: key them by the new node count.
    n_total = n + int(request_order.size)
    low, high = np.divmod(keys_sorted, n)
    keys_sorted = low * n_total + high  # same order: both ends are old nodes

    # Coordinates.
    points = np.empty((n + request_order.size, 2))
    points[:n] = mesh.points
    # midpoints of the split edges: the paper's arithmetic, or the curve's point
    key_rows = split_rows[first_request]
    a, b = corner[key_rows], end[key_rows]
    mid_xy = mesh.points[a] + mesh.points[b]
    mid_xy *= 0.5
    if has_curves:
        on_curve = curved_side[key_rows]
        if np.any(on_curve):
            r = side_row[key_rows[on_curve]]
            mid_xy[on_curve] = _curve_midpoints(curves, r)
    points[mid_id_of_key] = mid_xy
    v_xy = mesh.points[corner]
    u_xy = points[u_id]
    # centres
    p = _corner_sums(v_xy, k)
    p /= k[:, None]
    if has_curves:
        curved_any = curved_side | _curved_with_hanging(mesh, first, length)
        cell_curved = np.bincount(rank, curved_any, minlength=marked_ids.size) > 0
        if np.any(cell_curved):
            p[cell_curved] = _curved_centres(u_xy, v_xy, k, cell_curved)
    if quads:
        points[inner_id] = p
    else:
        w_xy = u_xy + p[rank]
        w_xy *= 0.5
        points[inner_id] = w_xy

    # Children as base cells: per marked cell k corner pentagons then the central k-gon.
    prev_row = np.arange(rows.size) - 1
    starts_r = np.cumsum(k) - k
    prev_row[starts_r] = starts_r + k - 1  # wrap within each cell
    if quads:  # <v_i, u_i, p, u_i-1>
        corner_children = np.stack([corner, u_id, inner_id[rank], u_id[prev_row]], axis=1)
    else:  # <v_i, u_i, w_i, w_i-1, u_i-1>
        corner_children = np.stack(
            [corner, u_id, inner_id, inner_id[prev_row], u_id[prev_row]], axis=1
        )
    child_size = corner_children.shape[1]
    # Output cell order: every old cell in place; a marked one replaced by its children.
    per_old = np.ones(mesh.n_cells, dtype=np.int64)
    per_old[marked_ids] = k if quads else k + 1
    out_start = np.concatenate([[0], np.cumsum(per_old)])
    n_out = int(out_start[-1])
    base_size = np.empty(n_out, dtype=np.int64)
    sizes = mesh.cell_sizes()
    kept = np.flatnonzero(~marked)
    base_size[out_start[kept]] = sizes[kept]
    child_slot = out_start[marked_ids][rank] + within  # output cell of each corner child
    base_size[child_slot] = child_size
    centre_cell = out_start[marked_ids] + k
    if not quads:
        base_size[centre_cell] = k
    base_offsets = np.concatenate([[0], np.cumsum(base_size)])
    base_nodes = np.empty(int(base_offsets[-1]), dtype=np.int64)
    # kept cells' nodes
    kept_slots = _cell_slots(mesh.offsets, kept)
    kept_out = _cell_slots(base_offsets, out_start[kept])
    base_nodes[kept_out] = mesh.nodes[kept_slots]
    # corner children
    base_nodes[base_offsets[child_slot][:, None] + np.arange(child_size)] = corner_children
    if not quads:  # central children
        centre_out = _cell_slots(base_offsets, centre_cell)
        base_nodes[centre_out] = inner_id

    # Every edge of a split key gets its midpoint inserted, in every cell that has it.
    base = PolygonCells(base_offsets, base_nodes)
    start, stop = base_nodes, base.following()
    slot_key = edge_keys(start, stop, n_total)
    where = np.minimum(np.searchsorted(keys_sorted, slot_key), max(keys_sorted.size - 1, 0))
    insert = (keys_sorted.size > 0) & (keys_sorted[where] == slot_key)
    repeats = 1 + insert.astype(np.int64)
    nodes = np.repeat(start, repeats)
    position = np.cumsum(repeats) - 1  # the last entry of each slot's run
    nodes[position[insert]] = mid_id_of_key[where[insert]]
    owner = base.slot_cell()
    final_size = base_size + np.bincount(owner[insert], minlength=n_out)
    offsets = np.concatenate([[0], np.cumsum(final_size)])

    # Per-cell data.
    old_of_out = np.repeat(np.arange(mesh.n_cells), per_old)
    is_child = np.repeat(marked, per_old)
    cell_level = mesh.cell_level[old_of_out] + is_child

    # Boundary edges: a split one becomes its two halves, in place.
    boundary_edges, boundary_patch = _split_boundary(
        mesh.boundary_edges, mesh.boundary_patch, keys_sorted, mid_id_of_key, n_total
    )
    new_curves = None
    if has_curves:
        new_curves = _split_curves(curves, keys_sorted, mid_id_of_key, n_total)
    out = PolygonMesh._trusted(
        points=points,
        offsets=offsets,
        nodes=nodes,
        block_id=mesh.block_id[old_of_out],
        parent=old_of_out,
        boundary_edges=boundary_edges,
        boundary_patch=boundary_patch,
        patch_names=mesh.patch_names,
        region=mesh.region[old_of_out],
        region_names=mesh.region_names,
        cell_level=cell_level,
        level=mesh.level + 1,
        name=mesh.name,
        curves=new_curves,
    )
    if has_curves:
        _check_folds(mesh, out, marked_ids, out_start)
    return out


def _cell_slots(offsets: np.ndarray, which: np.ndarray) -> np.ndarray:
    """The slots of cells ``which`` of a CSR with ``offsets``, cell after cell (flat)."""
    counts = offsets[which + 1] - offsets[which]
    starts = np.repeat(offsets[which], counts)
    return starts + np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)


def _curve_midpoints(curves: CurvedEdges, rows: np.ndarray) -> np.ndarray:
    """The curve's point at the mean parameter of each of ``rows`` (the dyadic midpoint)."""
    out = np.empty((rows.size, 2))
    start, stop = curves.start[rows], curves.stop[rows]
    middle = start + 0.5 * (stop - start)
    for index, curve in enumerate(curves.curves):
        mine = curves.curve[rows] == index
        if np.any(mine):
            out[mine] = curve.point(middle[mine])
    return out


def _curved_with_hanging(mesh: PolygonMesh, first: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Sides of two edges whose middle node continues a curve (curved, with a hanging node)."""
    continues = np.zeros(first.size, dtype=bool)
    two = length == 2
    if np.any(two):
        straight_on_curve = mesh._curve_continues()
        following_slot = mesh.polygon_cells().next_slot()
        continues[two] = straight_on_curve[following_slot[first[two]]]
    return continues


def _curved_centres(
    u_xy: np.ndarray, v_xy: np.ndarray, k: np.ndarray, which: np.ndarray
) -> np.ndarray:
    """``p = (2/k) Σ u_i - (1/k) Σ v_i`` of the marked cells ``which`` (the curved rule).

    For pentagons ``0.4 Σ u - 0.2 Σ v`` with numpy's sums over the five rows, the operations of
    :func:`blockmesh.refinement.curved.curved_block_levels` (so the bits agree). Cells of one
    corner count at a time.
    """
    starts = np.cumsum(k) - k
    chosen = np.flatnonzero(which)
    out = np.empty((chosen.size, 2))
    for size in np.unique(k[chosen]).tolist():
        mine = k[chosen] == size
        rows = starts[chosen[mine]][:, None] + np.arange(size)
        u, v = u_xy[rows], v_xy[rows]
        if size == 5:
            out[mine] = 0.4 * u.sum(axis=1) - 0.2 * v.sum(axis=1)
        else:
            out[mine] = (2.0 / size) * u.sum(axis=1) - (1.0 / size) * v.sum(axis=1)
    return out


def _split_boundary(
    edges: np.ndarray, patch: np.ndarray, keys: np.ndarray, mids: np.ndarray, n: int
) -> tuple[np.ndarray, np.ndarray]:
    if keys.size == 0 or edges.size == 0:
        return edges, patch
    key = edge_keys(edges[:, 0], edges[:, 1], n)
    where = np.minimum(np.searchsorted(keys, key), keys.size - 1)
    split = keys[where] == key
    repeats = 1 + split.astype(np.int64)
    out = np.repeat(edges, repeats, axis=0)
    last = np.cumsum(repeats) - 1
    middle = mids[where[split]]
    out[last[split] - 1, 1] = middle
    out[last[split], 0] = middle
    return out, np.repeat(patch, repeats)


def _split_curves(curves: CurvedEdges, keys: np.ndarray, mids: np.ndarray, n: int) -> CurvedEdges:
    key = edge_keys(curves.edges[:, 0], curves.edges[:, 1], n)
    where = np.minimum(np.searchsorted(keys, key), max(keys.size - 1, 0))
    split = (keys.size > 0) & (keys[where] == key)
    repeats = 1 + split.astype(np.int64)
    edges = np.repeat(curves.edges, repeats, axis=0)
    start = np.repeat(curves.start, repeats)
    stop = np.repeat(curves.stop, repeats)
    last = np.cumsum(repeats) - 1
    middle_node = mids[where[split]]
    middle = curves.start[split] + 0.5 * (curves.stop[split] - curves.start[split])
    edges[last[split] - 1, 1] = middle_node
    edges[last[split], 0] = middle_node
    stop[last[split] - 1] = middle
    start[last[split]] = middle
    return CurvedEdges(
        edges=edges,
        curve=np.repeat(curves.curve, repeats),
        start=start,
        stop=stop,
        curves=curves.curves,
    )


def _check_folds(
    old: PolygonMesh,
    new: PolygonMesh,
    marked_ids: np.ndarray,
    out_start: np.ndarray,
) -> None:
    """DomainError naming the first split cell next to a curve whose children fold."""
    children = _cell_slots(out_start, marked_ids)  # output cells of the marked cells
    areas = new.cell_areas()[children]
    sines = new.turn_sines()
    straight = new.straight_vertices()
    owner = new.polygon_cells().slot_cell()
    bad_vertex = ~(np.nan_to_num(sines, nan=-1.0) > COLLINEAR_SIN_TOL) & ~straight
    bad_cell = np.bincount(owner, bad_vertex, minlength=new.n_cells) > 0
    folded = ~(areas > 0) | bad_cell[children]
    if not np.any(folded):
        return
    child = int(children[np.flatnonzero(folded)[0]])
    parent = int(new.parent[child])
    corners = ", ".join(f"({x:.6g}, {y:.6g})" for x, y in old.points[old.cell(parent)])
    raise DomainError(
        f"refining cell {parent} (vertices {corners}) would fold it: its child {child} next "
        "to the curve is not convex and counter-clockwise; the curve bends too much for this "
        "cell. Refine the blocks along the curve uniformly first (a higher level), or give "
        "the curve more blocks"
    )
