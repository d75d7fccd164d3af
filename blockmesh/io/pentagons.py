"""Rebuilding pentagons from the triangles or quadrilaterals they were split into.

For formats without pentagons (Gmsh): every element names the pentagon it comes from; the
elements of one pentagon are merged back into it. Two ways, the first tried first:

* **the split itself** (O(K), no sorting): when the elements of each pentagon are consecutive
  and form exactly one of the splits of :mod:`blockmesh.io.split` (as blockmesh writes them), the
  corners are read off the elements, checked against the split's pattern;
* **outlines** (O(K log K)): otherwise the outline of each pentagon's elements is traced (edges
  met twice inside one pentagon are interior) and the pentagon's corners are kept: the mesh's own
  nodes when their number is known, else the vertices where the outline turns.

Nodes that are no corner (edge midpoints, centres) are dropped and boundary lines are joined back
across them (:func:`join_lines`).

Examples
--------
>>> import numpy as np
>>> from blockmesh.io.split import split_cells
>>> from blockmesh.mesh import Mesh
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> s = split_cells(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), "quad5")
>>> merge_elements(s.cells, s.parent, s.points, where="x", split="quad5").cells.tolist()
[[0, 1, 2, 3, 4]]
>>> merge_elements(s.cells, s.parent, s.points, where="x", corner_nodes=5).cells.tolist()
[[0, 1, 2, 3, 4]]
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from blockmesh.errors import ExportError
from blockmesh.geometry.topology import edge_keys
from blockmesh.io.common import check_points

__all__ = ["Merged", "join_lines", "merge_elements", "merge_polygons"]

#: Elements per pentagon of each split.
_PER_PENTAGON = {"tri3": 3, "tri5": 5, "quad5": 5}
#: Most elements one pentagon is merged from (the splits make 3 or 5).
_MOST_ELEMENTS = 8
#: Most nodes that are no corner along one boundary edge (quad5 puts one there).
_MOST_INNER = 4


class Merged(NamedTuple):
    """Pentagons rebuilt by :func:`merge_elements`.

    Attributes
    ----------
    cells : ndarray (M, 5) int64
        Pentagon ``p`` (the ids the elements named), counter-clockwise, numbered as ``points``.
    first_element : ndarray (M,) int64
        For each pentagon, the index of its first element (for per-element data).
    is_corner : ndarray (N',) bool
        Which of the input nodes are pentagon corners.
    point_index : ndarray or None
        The input nodes kept, in order (None: the first ``corner_nodes`` of them).
    renumber : ndarray or None
        Input node -> new node id (None: unchanged).
    """

    cells: np.ndarray
    first_element: np.ndarray
    is_corner: np.ndarray
    point_index: np.ndarray | None
    renumber: np.ndarray | None


def _from_split(
    conn: np.ndarray, pentagon: np.ndarray, split: str
) -> tuple[np.ndarray, np.ndarray] | None:
    """Cells and first elements when ``conn`` is exactly ``split`` of some pentagons, else None."""
    per = _PER_PENTAGON.get(split)
    width = 4 if split == "quad5" else 3
    if per is None or conn.ndim != 2 or conn.shape[1] != width or conn.shape[0] % per:
        return None
    m = conn.shape[0] // per
    grouped = pentagon.reshape(m, per)
    ids = grouped[:, 0]
    if not all(np.array_equal(grouped[:, j], ids) for j in range(1, per)):
        return None
    in_order = m < 2 or bool(np.all(ids[1:] > ids[:-1]))  # then ids is 0..m-1 if in range
    if m and in_order and (ids[0] != 0 or ids[-1] != m - 1):
        return None
    if (
        m
        and not in_order
        and (ids.min() < 0 or ids.max() >= m or np.any(np.bincount(ids, minlength=m) != 1))
    ):
        return None
    kids = conn.reshape(m, per, width)
    # checked and copied column by column: the temporaries are flags per pentagon, not copies
    # of the elements
    if split == "tri3":  # the fan (c0 c1 c2), (c0 c2 c3), (c0 c3 c4)
        same = [((1, 0), (0, 0)), ((2, 0), (0, 0)), ((1, 1), (0, 2)), ((2, 1), (1, 2))]
        columns = [(0, 0), (0, 1), (0, 2), (1, 2), (2, 2)]
    else:  # corner j is node 0 of element j; all share the centre (node 2)
        same = [((j, 2), (0, 2)) for j in range(1, 5)]
        if split == "tri5":  # element j is (c_j, c_j+1, centre)
            same += [((j, 1), ((j + 1) % 5, 0)) for j in range(5)]
        else:  # element j is (c_j, m_j, centre, m_j-1)
            same += [((j, 3), ((j - 1) % 5, 1)) for j in range(5)]
        columns = [(j, 0) for j in range(5)]
    if not all(np.array_equal(kids[:, i, j], kids[:, k, l]) for (i, j), (k, l) in same):
        return None
    out = np.empty((m, 5), dtype=np.int64)
    for c, (i, j) in enumerate(columns):
        if in_order:
            out[:, c] = kids[:, i, j]
        else:
            out[ids, c] = kids[:, i, j]
    first = np.empty(m, dtype=np.int64)
    first[ids] = np.arange(m, dtype=np.int64) * per
    return out, first


def _outlines(
    edges: np.ndarray, owner: np.ndarray, start: np.ndarray, n_nodes: int, where: str
) -> np.ndarray:
    """For each owner 0..P-1, its outline from ``start[p]``: (P, L) node ids, -1 padded.

    ``edges`` (E, 2) are the directed edges of CCW elements, ``owner`` their pentagon; edges met
    in both directions within a pentagon are interior and dropped. O(E log E).
    """
    key = edge_keys(edges[:, 0], edges[:, 1], n_nodes)
    order = np.argsort(key)  # an edge is in at most two elements: equal keys are neighbours
    k_sorted, o_sorted = key[order], owner[order]
    same = (k_sorted[1:] == k_sorted[:-1]) & (o_sorted[1:] == o_sorted[:-1])
    twin = np.zeros(order.size, dtype=bool)
    twin[order[1:][same]] = True
    twin[order[:-1][same]] = True
    out_edges, out_owner = edges[~twin], owner[~twin]
    n_parents = start.size
    length = np.bincount(out_owner, minlength=n_parents)
    src_key = out_owner * n_nodes + out_edges[:, 0]
    by_src = np.argsort(src_key)
    src_sorted = src_key[by_src]
    if np.any(src_sorted[1:] == src_sorted[:-1]):
        raise ExportError(f"{where}: the elements of some pentagon do not form one simple polygon")
    longest = int(length.max(initial=0))
    ring = np.full((n_parents, longest), -1, dtype=np.int64)
    current = start.copy()
    parents = np.arange(n_parents)
    for step in range(longest):
        active = step < length
        ring[active, step] = current[active]
        look = parents[active] * n_nodes + current[active]
        pos = np.minimum(np.searchsorted(src_sorted, look), max(src_sorted.size - 1, 0))
        if src_sorted.size == 0 or np.any(src_sorted[pos] != look):
            raise ExportError(
                f"{where}: the elements of some pentagon do not form a closed outline"
            )
        current[active] = out_edges[by_src[pos], 1]
    if np.any(current != start):
        raise ExportError(f"{where}: the elements of some pentagon do not form one closed outline")
    return ring


def _corners(
    ring: np.ndarray, points: np.ndarray, is_node: np.ndarray | None, where: str
) -> np.ndarray:
    """Keep the pentagon corners of each outline: mesh nodes (when known) or turning vertices."""
    valid = ring >= 0
    if is_node is not None:
        keep = valid & is_node[np.where(valid, ring, 0)]
    else:
        xy = points[np.where(valid, ring, 0)]
        length = valid.sum(axis=1)
        idx = np.arange(ring.shape[1])
        prev = (idx - 1) % np.maximum(length, 1)[:, None]
        nxt = (idx + 1) % np.maximum(length, 1)[:, None]
        rows = np.arange(ring.shape[0])[:, None]
        a, b = xy - xy[rows, prev], xy[rows, nxt] - xy
        cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
        scale = np.hypot(*np.moveaxis(a, -1, 0)) * np.hypot(*np.moveaxis(b, -1, 0))
        keep = valid & (np.abs(cross) > 1e-9 * scale)
    counts = keep.sum(axis=1)
    if np.any(counts != 5):
        bad = int(np.flatnonzero(counts != 5)[0])
        raise ExportError(
            f"{where}: the elements of pentagon {bad} merge into a polygon of {counts[bad]} "
            "corners, not a pentagon"
        )
    return ring[keep].reshape(-1, 5)


def _rings(
    conn: np.ndarray, owner_ids: np.ndarray, n_nodes: int, where: str, what: str
) -> tuple[np.ndarray, np.ndarray]:
    """Each owner's outline from its first element's first node, and that first element."""
    ids, elem_p = np.unique(owner_ids, return_inverse=True)
    if ids.size and (ids[0] < 0 or ids[-1] != ids.size - 1):
        raise ExportError(
            f"{where}: the {what} ids of the elements are not 0..{ids.size - 1} (found "
            f"{ids[0]}..{ids[-1]})"
        )
    per = np.bincount(elem_p, minlength=ids.size)
    if per.size and per.max() > _MOST_ELEMENTS:
        worst = int(np.argmax(per))
        raise ExportError(
            f"{where}: pentagon {int(ids[worst])} is made of {int(per[worst])} elements; the "
            f"splits make 3 or 5 (at most {_MOST_ELEMENTS} are merged)"
        )
    k = conn.shape[1]
    conn = conn.astype(np.int64, copy=False)
    edges = np.stack([conn, np.roll(conn, -1, axis=1)], axis=2).reshape(-1, 2)
    owner = np.repeat(elem_p, k)
    first = np.lexsort((np.arange(conn.shape[0]), elem_p))
    first = first[np.r_[True, elem_p[first][1:] != elem_p[first][:-1]]]
    return _outlines(edges, owner, conn[first, 0], n_nodes, where), first


def _from_outlines(
    conn: np.ndarray,
    pentagon: np.ndarray,
    points: np.ndarray,
    is_node: np.ndarray | None,
    where: str,
) -> tuple[np.ndarray, np.ndarray]:
    ring, first = _rings(conn, pentagon, points.shape[0], where, "pentagon")
    return _corners(ring, points, is_node, where), first


def merge_elements(
    conn: np.ndarray,
    pentagon: np.ndarray,
    points: np.ndarray,
    *,
    where: str,
    split: str | None = None,
    corner_nodes: int | None = None,
) -> Merged:
    """Merge the elements ``conn`` (K, 3 or 4), counter-clockwise, into their pentagons.

    Parameters
    ----------
    conn : ndarray (K, k)
        Node ids (rows of ``points``) of each element.
    pentagon : ndarray (K,) or (M, K / M)
        The pentagon each element comes from, 0..M-1 (as a 2-D array: the elements' values in
        rows of K / M, e.g. a broadcast ``(M, 5)`` view when the elements of pentagon ``p`` are
        rows ``5 p .. 5 p + 4``).
    points : ndarray (N', 2)
    where : str
        Names the file in errors.
    split : str, optional
        The split the elements were made with, if known: tried first (see the module notes).
    corner_nodes : int, optional
        If the pentagons' corners are exactly the first ``corner_nodes`` nodes.

    Raises
    ------
    ExportError
        When some pentagon's elements do not merge into one pentagon.
    """
    check_points(points, where)  # before any arithmetic on them (the corners' turns)
    n = points.shape[0]
    quick = _from_split(conn, pentagon, split) if split else None
    if quick is not None:
        cells, first = quick
    else:
        is_node = None
        if corner_nodes is not None:
            is_node = np.zeros(n, dtype=bool)
            is_node[:corner_nodes] = True
        cells, first = _from_outlines(conn, np.reshape(pentagon, -1), points, is_node, where)
    is_corner = np.zeros(n, dtype=bool)
    is_corner[cells] = True
    if (
        corner_nodes is not None
        and is_corner[:corner_nodes].all()
        and not is_corner[corner_nodes:].any()
    ):
        return Merged(cells, first, is_corner, None, None)
    renumber = np.cumsum(is_corner) - 1
    return Merged(renumber[cells], first, is_corner, np.flatnonzero(is_corner), renumber)


def merge_polygons(
    conn: np.ndarray, cell: np.ndarray, points: np.ndarray, *, where: str, corner_nodes: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Merge elements back into the polygons they were split from (any vertex counts).

    ``conn`` (K, k) are the counter-clockwise elements, ``cell`` (K,) the polygon of each
    (0..M-1), and the polygons' vertices are the first ``corner_nodes`` nodes (the mesh's own;
    the split's centres come after). Returns ``(offsets, nodes, first_element)``: each polygon
    from its first element's first node, counter-clockwise, with every one of the mesh's nodes
    on its outline (hanging nodes included). O(K log K).
    """
    ring, first = _rings(conn, np.reshape(cell, -1), points.shape[0], where, "cell")
    valid = ring >= 0
    keep = valid & (np.where(valid, ring, corner_nodes) < corner_nodes)
    counts = keep.sum(axis=1)
    if np.any(counts < 3):
        bad = int(np.flatnonzero(counts < 3)[0])
        raise ExportError(f"{where}: the elements of cell {bad} merge into fewer than 3 nodes")
    offsets = np.concatenate([[0], np.cumsum(counts)])
    return offsets, ring[keep], first


def join_lines(
    lines: np.ndarray, is_corner: np.ndarray, where: str
) -> tuple[np.ndarray, np.ndarray]:
    """Boundary lines joined across nodes that are not corners (quad5's midpoints).

    Returns the joined lines (in the numbering of ``is_corner``) and the index of the first line
    of each. O(E) when each line is split in two consecutive halves (as blockmesh writes them),
    else O(E log E).

    Examples
    --------
    >>> corner = np.array([True, True, False])
    >>> [a.tolist() for a in join_lines(np.array([[0, 2], [2, 1]]), corner, "x")]
    [[[0, 1]], [0]]
    """
    lines = np.asarray(lines, dtype=np.int64).reshape(-1, 2)
    if lines.size == 0 or np.all(is_corner[lines]):
        return lines, np.arange(lines.shape[0])
    if lines.shape[0] % 2 == 0:
        halves = lines.reshape(-1, 2, 2)
        mid = halves[:, 0, 1]
        if (
            np.array_equal(mid, halves[:, 1, 0])
            and not is_corner[mid].any()
            and is_corner[halves[:, 0, 0]].all()
            and is_corner[halves[:, 1, 1]].all()
        ):
            joined = np.stack([halves[:, 0, 0], halves[:, 1, 1]], axis=1)
            return joined, np.arange(0, lines.shape[0], 2)
    first = np.flatnonzero(is_corner[lines[:, 0]])
    starts = lines[first]
    inner = lines[~is_corner[lines[:, 0]]]
    order = np.argsort(inner[:, 0])
    src = inner[order, 0]
    end = starts[:, 1].copy()
    for _ in range(min(inner.shape[0], _MOST_INNER) + 1):
        todo = ~is_corner[end]
        if not todo.any():
            return np.stack([starts[:, 0], end], axis=1), first
        pos = np.minimum(np.searchsorted(src, end[todo]), max(src.size - 1, 0))
        if src.size == 0 or np.any(src[pos] != end[todo]):
            raise ExportError(f"{where}: a boundary line ends at a node that no line continues")
        end[todo] = inner[order[pos], 1]
    raise ExportError(
        f"{where}: a boundary line runs through more than {_MOST_INNER} nodes that are no "
        "pentagon corner (or lines form a loop without corners)"
    )
