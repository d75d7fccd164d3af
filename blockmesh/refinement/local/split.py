"""The split of the marked cells: new nodes numbered as the paper, children, edges halved.

:func:`split_cells` refines a closed, checked marking once by one of the :data:`SCHEMES`: every
marked cell is replaced, in place, by its children, every split edge gets its midpoint in every
cell that has it (a hanging node on the coarse neighbour), and the boundary and interface edges
split likewise.
"""

from __future__ import annotations

import numpy as np

from blockmesh.curves.edges import curved_slots
from blockmesh.errors import ArgumentError
from blockmesh.geometry.topology import PolygonCells, edge_keys
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.local.curves import (
    NO_CURVES,
    check_folds,
    curve_midpoints,
    curved_centres,
    curved_with_hanging,
    split_curves,
)
from blockmesh.refinement.local.marked import Sides

__all__ = ["SCHEMES", "check_scheme", "split_cells"]

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


def split_cells(
    mesh: PolygonMesh, sides: Sides, marked: np.ndarray, scheme: str = "pentagons"
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
    curves = mesh.curves if mesh.curves is not None else NO_CURVES
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
            mid_xy[on_curve] = curve_midpoints(curves, r)
    points[mid_id_of_key] = mid_xy
    v_xy = mesh.points[corner]
    u_xy = points[u_id]
    # centres
    p = _corner_sums(v_xy, k)
    p /= k[:, None]
    if has_curves:
        curved_any = curved_side | curved_with_hanging(mesh, first, length)
        cell_curved = np.bincount(rank, curved_any, minlength=marked_ids.size) > 0
        if np.any(cell_curved):
            p[cell_curved] = curved_centres(u_xy, v_xy, k, cell_curved)
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
    # Interface edges likewise: a split one is two interface edges, its direction (the first
    # region on the left) kept.
    interface_edges, interface_patch = _split_boundary(
        mesh.interface_edges, mesh.interface_patch, keys_sorted, mid_id_of_key, n_total
    )
    new_curves = None
    if has_curves:
        new_curves = split_curves(curves, keys_sorted, mid_id_of_key, n_total)
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
        interface_edges=interface_edges,
        interface_patch=interface_patch,
        interface_names=mesh.interface_names,
    )
    if has_curves:
        check_folds(mesh, out, _cell_slots(out_start, marked_ids))
    return out


def _cell_slots(offsets: np.ndarray, which: np.ndarray) -> np.ndarray:
    """The slots of cells ``which`` of a CSR with ``offsets``, cell after cell (flat)."""
    counts = offsets[which + 1] - offsets[which]
    starts = np.repeat(offsets[which], counts)
    return starts + np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)


def _split_boundary(
    edges: np.ndarray, patch: np.ndarray, keys: np.ndarray, mids: np.ndarray, n: int
) -> tuple[np.ndarray, np.ndarray]:
    """Directed edges (boundary or interface) with every split one replaced by its two halves.

    The halves keep the edge's direction and its ``patch`` entry, in place of the edge.
    """
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
