"""Topology of polygon meshes, written once: edge keys, neighbours, boundaries, loops, pieces.

Every function takes cells as an integer array of shape ``(M, k)`` (``k`` corners each,
counter-clockwise, node ids ``0..n_points-1``) or, for cells of different sizes, as
:class:`PolygonCells` (compressed rows: offsets and the nodes of all cells one after another), and
works with whole-array operations. An undirected edge is keyed by one int64,
``min * n_points + max`` (no dense lookup tables). A cell edge is addressed by its **slot**: for
an ``(M, k)`` array ``k * cell + i``, the edge from corner ``i`` to corner ``i + 1``; for
:class:`PolygonCells` the position of its first node in ``nodes``. Functions that return one value
per slot return an ``(M, k)`` array for rectangular cells and a flat ``(S,)`` array for
:class:`PolygonCells`. Boundary edges are directed as the cells run along them, so the domain is on
their left.

Refinement, domain validation, the conformity certificate and every writer use these functions.

Examples
--------
>>> import numpy as np
>>> two = np.array([[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]])
>>> cell_neighbours(two, 8).tolist()
[[-1, 9, -1, -1, -1], [-1, -1, -1, -1, 1]]
>>> boundary_loops(two, cell_neighbours(two, 8)).tolist()
[[0, 1], [1, 5], [5, 6], [6, 7], [7, 2], [2, 3], [3, 4], [4, 0]]
>>> connected_pieces(cell_neighbours(two, 8))[0]
1
>>> mixed = PolygonCells.from_lists([[0, 1, 2, 3, 4], [1, 5, 2]])
>>> cell_neighbours(mixed, 6).tolist()
[-1, 7, -1, -1, -1, -1, -1, 1]
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import NamedTuple

import numpy as np

from blockmesh.errors import TopologyError

__all__ = [
    "PolygonCells",
    "boundary_loops",
    "boundary_of_cells",
    "boundary_slots",
    "cell_neighbours",
    "check_boundary",
    "connected_pieces",
    "count_loops",
    "edge_index",
    "edge_keys",
    "graph_components",
    "unique_edges",
]


def edge_keys(a: np.ndarray, b: np.ndarray, n_points: int) -> np.ndarray:
    """One int64 per undirected edge: ``min(a, b) * n_points + max(a, b)``.

    Examples
    --------
    >>> edge_keys(np.array([3, 1]), np.array([1, 3]), 10).tolist()
    [13, 13]
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    return np.minimum(a, b) * n_points + np.maximum(a, b)


class PolygonCells(NamedTuple):
    """Cells of any numbers of corners in compressed rows (CSR).

    Cell ``c`` is ``nodes[offsets[c]:offsets[c + 1]]``, counter-clockwise. Its slots (edges) are
    the positions ``offsets[c] .. offsets[c + 1] - 1``: slot ``s`` runs from ``nodes[s]`` to
    the next node of the same cell (the cell's first node after its last).

    Examples
    --------
    >>> cells = PolygonCells.from_lists([[0, 1, 2], [2, 1, 3, 4]])
    >>> cells.sizes().tolist(), cells.following().tolist(), cells.slot_cell().tolist()
    ([3, 4], [1, 2, 0, 1, 3, 4, 2], [0, 0, 0, 1, 1, 1, 1])
    """

    offsets: np.ndarray
    nodes: np.ndarray

    @classmethod
    def from_lists(cls, cells: Sequence[Sequence[int]]) -> PolygonCells:
        """Compressed rows of a list of node-id lists."""
        sizes = np.array([len(c) for c in cells], dtype=np.int64)
        offsets = np.zeros(sizes.size + 1, dtype=np.int64)
        np.cumsum(sizes, out=offsets[1:])
        nodes = np.array([v for c in cells for v in c], dtype=np.int64)
        return cls(offsets, nodes)

    @classmethod
    def from_array(cls, cells: np.ndarray) -> PolygonCells:
        """Compressed rows of an ``(M, k)`` array (each row one cell)."""
        cells = np.asarray(cells, dtype=np.int64)
        m, k = cells.shape
        return cls(np.arange(m + 1, dtype=np.int64) * k, cells.reshape(-1))

    @property
    def n_cells(self) -> int:
        """Number of cells M."""
        return int(self.offsets.shape[0]) - 1

    def sizes(self) -> np.ndarray:
        """Corners of every cell (M,)."""
        return np.diff(self.offsets)

    def slot_cell(self) -> np.ndarray:
        """The cell of every slot (S,)."""
        return np.repeat(np.arange(self.n_cells, dtype=np.int64), self.sizes())

    def following(self) -> np.ndarray:
        """The node after every slot's node in its cell (S,): the slot's second end."""
        out = np.empty_like(self.nodes)
        if out.size:
            out[:-1] = self.nodes[1:]
            last = self.offsets[1:] - 1
            nonempty = self.offsets[1:] > self.offsets[:-1]
            out[last[nonempty]] = self.nodes[self.offsets[:-1][nonempty]]
        return out

    def next_slot(self) -> np.ndarray:
        """The slot after every slot in its cell (S,)."""
        out = np.arange(1, self.nodes.size + 1, dtype=np.int64)
        if out.size:
            last = self.offsets[1:] - 1
            nonempty = self.offsets[1:] > self.offsets[:-1]
            out[last[nonempty]] = self.offsets[:-1][nonempty]
        return out

    def previous_slot(self) -> np.ndarray:
        """The slot before every slot in its cell (S,)."""
        out = np.empty(self.nodes.size, dtype=np.int64)
        out[self.next_slot()] = np.arange(self.nodes.size, dtype=np.int64)
        return out


#: Cells as the functions here take them: an (M, k) array of node ids, or PolygonCells.
Cells = np.ndarray | PolygonCells


def _next(cells: np.ndarray | PolygonCells) -> np.ndarray:
    """The second end of every slot: (M, k) for an array, (S,) for PolygonCells."""
    if isinstance(cells, PolygonCells):
        return cells.following()
    return np.roll(cells, -1, axis=1)


def _as_cells(cells: np.ndarray | PolygonCells | Sequence) -> np.ndarray | PolygonCells:
    """``cells`` as an int64 (M, k) array, or the PolygonCells it is."""
    if isinstance(cells, PolygonCells):
        return cells
    return np.asarray(cells, dtype=np.int64)


def _starts(cells: np.ndarray | PolygonCells) -> np.ndarray:
    """The first end of every slot, in slot order (flat)."""
    return cells.nodes if isinstance(cells, PolygonCells) else cells.ravel()


def _cells_of_slots(cells: np.ndarray | PolygonCells, slots: np.ndarray) -> np.ndarray:
    """The cell of each of ``slots``."""
    if isinstance(cells, PolygonCells):
        return np.searchsorted(cells.offsets, slots, side="right") - 1
    k = cells.shape[1] if cells.ndim == 2 else 1
    return np.asarray(slots) // k


def _slot_shape(cells: np.ndarray | PolygonCells) -> tuple[int, ...]:
    return cells.nodes.shape if isinstance(cells, PolygonCells) else cells.shape


def edge_index(cells: Cells, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    """The sorted unique edge keys, and for every slot (M, k) the index of its edge among them.

    O(M log M).

    Examples
    --------
    >>> keys, slot_edge = edge_index(np.array([[0, 1, 2], [2, 1, 3]]), 4)
    >>> keys.tolist(), slot_edge.tolist()
    ([1, 2, 6, 7, 11], [[0, 2, 1], [2, 3, 4]])
    """
    cells = _as_cells(cells)
    keys = edge_keys(_starts(cells), _next(cells).ravel(), n_points)
    unique, inverse = np.unique(keys, return_inverse=True)
    return unique, inverse.reshape(_slot_shape(cells))


def unique_edges(cells: Cells, n_points: int) -> np.ndarray:
    """Unique undirected edges (E, 2) of polygon cells, sorted by (min, max) node id.

    Examples
    --------
    >>> unique_edges(np.array([[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]]), 8).shape
    (9, 2)
    """
    cells = _as_cells(cells)
    keys = np.unique(edge_keys(_starts(cells), _next(cells).ravel(), n_points))
    return np.stack(np.divmod(keys, n_points), axis=1)


def cell_neighbours(cells: Cells, n_points: int) -> np.ndarray:
    """For every slot, the slot of the same edge in the cell across it, or -1 on the boundary.

    Raises :class:`~blockmesh.errors.TopologyError` naming the edge and its cells when an edge
    belongs to three or more cells. O(M log M).

    Examples
    --------
    >>> cell_neighbours(np.array([[0, 1, 2], [0, 2, 1], [2, 1, 3]]), 4)
    Traceback (most recent call last):
    ...
    blockmesh.errors.TopologyError: edge (1, 2) belongs to three or more cells (0, 1, 2); ...
    """
    cells = _as_cells(cells)
    keys = edge_keys(_starts(cells), _next(cells).ravel(), n_points)
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]
    same_as_next = sorted_keys[1:] == sorted_keys[:-1]
    triple = same_as_next[1:] & same_as_next[:-1]
    if np.any(triple):
        first = int(np.flatnonzero(triple)[0])
        a, b = divmod(int(sorted_keys[first]), n_points)
        run = order[first : first + 3]
        owners = sorted({int(x) for x in _cells_of_slots(cells, run)})
        raise TopologyError(
            f"edge ({a}, {b}) belongs to three or more cells ({', '.join(map(str, owners))}); "
            "an edge may be shared by two cells at most"
        )
    neighbour = np.full(keys.size, -1, dtype=np.int64)
    pairs = np.flatnonzero(same_as_next)
    neighbour[order[pairs]] = order[pairs + 1]
    neighbour[order[pairs + 1]] = order[pairs]
    return neighbour.reshape(_slot_shape(cells))


def boundary_of_cells(cells: Cells, n_points: int) -> np.ndarray:
    """Directed boundary edges (E, 2): the cell edges no other cell shares, in slot order.

    Examples
    --------
    >>> boundary_of_cells(np.array([[0, 1, 2, 3, 4]]), 5).tolist()
    [[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]]
    """
    cells = _as_cells(cells)
    start, stop = _starts(cells), _next(cells).ravel()
    keys = edge_keys(start, stop, n_points)
    _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
    on_boundary = counts[inverse] == 1
    return np.stack([start[on_boundary], stop[on_boundary]], axis=1)


def boundary_slots(
    cells: Cells, neighbour: np.ndarray, boundary_edges: np.ndarray, n_points: int
) -> np.ndarray:
    """The slot of every listed boundary edge (directed as the cells run), in the list's order.

    Raises :class:`~blockmesh.errors.TopologyError` unless ``boundary_edges`` are exactly the
    cell edges without a neighbour, each once, each directed as its cell runs. O(E log E).

    Examples
    --------
    >>> cells = np.array([[0, 1, 2, 3, 4]])
    >>> boundary_slots(cells, np.full((1, 5), -1), np.array([[2, 3], [0, 1]]), 5).tolist()
    Traceback (most recent call last):
    ...
    blockmesh.errors.TopologyError: 2 boundary edges are listed, but the cells have 5 ...
    >>> edges = np.array([[2, 3], [3, 4], [4, 0], [0, 1], [1, 2]])
    >>> boundary_slots(cells, np.full((1, 5), -1), edges, 5).tolist()
    [2, 3, 4, 0, 1]
    """
    cells = _as_cells(cells)
    free = np.flatnonzero(np.asarray(neighbour).ravel() < 0)
    start = _starts(cells)[free]
    stop = _next(cells).ravel()[free]
    edges = np.asarray(boundary_edges, dtype=np.int64).reshape(-1, 2)
    if edges.shape[0] != free.size:
        raise TopologyError(
            f"{edges.shape[0]} boundary edges are listed, but the cells have {free.size} edges "
            "without a neighbour; the boundary edges must be exactly those, each once, directed "
            "as their cell runs (domain on the left)"
        )
    known = start * n_points + stop
    order = np.argsort(known)
    listed = edges[:, 0] * n_points + edges[:, 1]
    pos = np.minimum(np.searchsorted(known[order], listed), max(known.size - 1, 0))
    found = known[order][pos] == listed
    if not np.all(found):
        bad = int(np.flatnonzero(~found)[0])
        raise TopologyError(
            f"boundary edge {bad} ({edges[bad, 0]}, {edges[bad, 1]}) is not a cell edge without "
            "a neighbour, directed as its cell runs (domain on the left)"
        )
    slots = free[order][pos]
    if np.unique(slots).size != slots.size:
        raise TopologyError("a boundary edge is listed twice")
    return slots


#: Cells whose edge keys are computed at once by :func:`check_boundary` (temporaries in cache).
_KEY_CHUNK = 1 << 15


def _fill_edge_keys(cells: np.ndarray | PolygonCells, n_points: int, out: np.ndarray) -> None:
    """Write every slot's undirected edge key (:func:`edge_keys`) into ``out`` (``cells.size``).

    Chunk by chunk: the temporaries are a chunk's, not the mesh's.
    """
    if isinstance(cells, PolygonCells):
        out[:] = edge_keys(cells.nodes, cells.following(), n_points)
        return
    k = cells.shape[1]
    for start in range(0, cells.shape[0], _KEY_CHUNK):
        a = cells[start : start + _KEY_CHUNK]
        b = _next(a)
        target = out[start * k : start * k + a.size].reshape(a.shape)
        np.minimum(a, b, out=target)
        target *= n_points
        target += np.maximum(a, b)


def _directed_keys_among(
    cells: np.ndarray | PolygonCells, free: np.ndarray, n_points: int
) -> np.ndarray:
    """Sorted directed keys of the slots whose two ends are both nodes of a ``free`` edge.

    Every slot running along a free edge is among them (a few others may be, e.g. a cell edge
    joining two boundary nodes across a corner); so a listed boundary edge that is free runs as
    its cell does exactly when its directed key is here. One pass of two boolean look-ups per
    slot, chunk by chunk, instead of sorting the directed keys of every slot.
    """
    on_free = np.zeros(n_points, dtype=bool)
    ends = np.divmod(free, n_points)
    on_free[ends[0]] = True
    on_free[ends[1]] = True
    found = []
    pieces: Iterable[tuple[np.ndarray, np.ndarray]]
    if isinstance(cells, PolygonCells):
        pieces = [(cells.nodes, cells.following())]
    else:
        pieces = (
            (cells[start : start + _KEY_CHUNK], _next(cells[start : start + _KEY_CHUNK]))
            for start in range(0, cells.shape[0], _KEY_CHUNK)
        )
    for a, b in pieces:
        both = on_free[a]
        both &= on_free[b]
        if both.any():
            found.append(a[both] * n_points + b[both])
    keys = np.concatenate(found) if found else np.zeros(0, dtype=np.int64)
    keys.sort()  # in place: when every node is on the boundary, these are all the slots
    return keys


def check_boundary(cells: Cells, boundary_edges: np.ndarray, n_points: int) -> None:
    """Raise TopologyError unless ``boundary_edges`` are exactly the cells' free edges, directed.

    The same verdict as :func:`boundary_slots` on :func:`cell_neighbours`, in one int64 per slot
    (filled chunk by chunk, sorted in place) and two booleans per slot: about 0.6x the memory of
    the mesh's own arrays, which matters when every mesh read from a file is checked. Also
    refuses an edge in three or more cells. One sort of the whole mesh: the directions are read
    only from the slots whose both ends lie on free edges.

    Examples
    --------
    >>> cells = np.array([[0, 1, 2], [2, 1, 3]])
    >>> check_boundary(cells, np.array([[0, 1], [1, 3], [3, 2], [2, 0]]), 4)
    >>> check_boundary(cells, np.array([[0, 1], [1, 3], [2, 3], [2, 0]]), 4)
    Traceback (most recent call last):
    ...
    blockmesh.errors.TopologyError: boundary edge 2 (2, 3) is not a cell edge without a ...
    """
    cells = _as_cells(cells)
    edges = np.asarray(boundary_edges, dtype=np.int64).reshape(-1, 2)
    keys = np.empty(_starts(cells).size, dtype=np.int64)
    _fill_edge_keys(cells, n_points, keys)
    keys.sort()
    same = keys[1:] == keys[:-1]
    triple = same[1:] & same[:-1]
    if np.any(triple):
        a, b = divmod(int(keys[1:-1][triple][0]), n_points)
        raise TopologyError(
            f"edge ({a}, {b}) belongs to three or more cells; an edge may be shared by two cells "
            "at most"
        )
    del triple
    single = np.ones(keys.size, dtype=bool)
    single[1:] &= ~same
    single[:-1] &= ~same
    del same
    free = keys[single]
    del single
    if edges.shape[0] != free.size:
        raise TopologyError(
            f"{edges.shape[0]} boundary edges are listed, but the cells have {free.size} edges "
            "without a neighbour; the boundary edges must be exactly those, each once, directed "
            "as their cell runs (domain on the left)"
        )
    del keys
    directed = _directed_keys_among(cells, free, n_points)
    listed = edges[:, 0] * n_points + edges[:, 1]
    pos = np.minimum(np.searchsorted(directed, listed), max(directed.size - 1, 0))
    runs_so = directed[pos] == listed
    undirected_listed = edge_keys(edges[:, 0], edges[:, 1], n_points)
    where = np.minimum(np.searchsorted(free, undirected_listed), max(free.size - 1, 0))
    is_free = free[where] == undirected_listed
    ok = runs_so & is_free
    if not np.all(ok):
        bad = int(np.flatnonzero(~ok)[0])
        raise TopologyError(
            f"boundary edge {bad} ({edges[bad, 0]}, {edges[bad, 1]}) is not a cell edge without "
            "a neighbour, directed as its cell runs (domain on the left)"
        )
    if np.unique(undirected_listed).size != undirected_listed.size:
        raise TopologyError("a boundary edge is listed twice")


def boundary_loops(cells: Cells, neighbour: np.ndarray) -> np.ndarray:
    """Boundary edges (E, 2) chained into closed loops, directed with the domain on their left.

    Loops start at their lowest vertex id and are listed by it; where several boundary edges leave
    one vertex (two loops touching there) the walk takes the lowest-numbered remaining edge.
    O(E log E) plus a linear walk.

    Examples
    --------
    >>> boundary_loops(np.array([[0, 1, 2, 3, 4]]), np.full((1, 5), -1)).tolist()
    [[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]]
    """
    cells = _as_cells(cells)
    free = np.flatnonzero(np.asarray(neighbour).ravel() < 0)
    start = _starts(cells)[free]
    stop = _next(cells).ravel()[free]
    by_start = np.lexsort((stop, start))
    leaving: dict[int, list[int]] = {}
    for j in by_start.tolist():
        leaving.setdefault(int(start[j]), []).append(j)
    used = np.zeros(start.size, dtype=bool)
    ordered: list[int] = []
    for first in by_start.tolist():
        j = first
        while not used[j]:
            used[j] = True
            ordered.append(j)
            candidates = [i for i in leaving.get(int(stop[j]), []) if not used[i]]
            if not candidates:
                break
            j = candidates[0]
    return np.stack([start[ordered], stop[ordered]], axis=1).reshape(-1, 2)


def count_loops(boundary_edges: np.ndarray) -> int:
    """Number of closed boundary loops: connected pieces of the graph the boundary edges form.

    Examples
    --------
    >>> count_loops(np.array([[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3]]))
    2
    """
    edges = np.asarray(boundary_edges, dtype=np.int64).reshape(-1, 2)
    if edges.size == 0:
        return 0
    nodes, local = np.unique(edges, return_inverse=True)
    local = local.reshape(-1, 2)
    return graph_components(nodes.size, local[:, 0], local[:, 1])[0]


def connected_pieces(
    neighbour: np.ndarray | tuple[np.ndarray, PolygonCells],
) -> tuple[int, np.ndarray]:
    """Pieces of cells joined through whole shared edges: their number and each cell's piece.

    Cells touching only at a corner are in different pieces. ``neighbour`` is what
    :func:`cell_neighbours` returns for an ``(M, k)`` array, or for :class:`PolygonCells` the
    pair ``(neighbour, cells)``.

    Examples
    --------
    >>> connected_pieces(np.array([[-1, -1, -1], [-1, -1, -1]]))
    (2, array([0, 1], dtype=int32))
    """
    if isinstance(neighbour, tuple):  # (neighbour slots (S,), PolygonCells)
        flat, cells = np.asarray(neighbour[0], dtype=np.int64), neighbour[1]
        own = np.flatnonzero(flat >= 0)
        return graph_components(
            cells.n_cells, _cells_of_slots(cells, own), _cells_of_slots(cells, flat[own])
        )
    neighbour = np.asarray(neighbour, dtype=np.int64)
    m, k = neighbour.shape
    c, e = np.nonzero(neighbour >= 0)
    return graph_components(m, c, neighbour[c, e] // k)


#: Graphs up to this many vertices (a domain's blocks, its boundary) are labelled in numpy, so
#: that loading a domain does not import ``scipy.sparse`` (a large part of a fresh process's
#: start); bigger ones with :func:`scipy.sparse.csgraph.connected_components`.
_SMALL_GRAPH = 4096


def graph_components(n: int, a: np.ndarray, b: np.ndarray) -> tuple[int, np.ndarray]:
    """Connected components of ``n`` vertices joined by the edges ``(a[i], b[i])``.

    Returns their number and each vertex's component, numbered like
    :func:`scipy.sparse.csgraph.connected_components` (in the order of each component's lowest
    vertex). Small graphs are labelled by hooking each edge's higher root onto its lower one and
    pointer jumping until every vertex points at its root (a root is its component's lowest
    vertex).

    Examples
    --------
    >>> graph_components(4, np.array([3]), np.array([1]))
    (3, array([0, 1, 2, 1], dtype=int32))
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    if n > _SMALL_GRAPH:
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        graph = coo_matrix((np.ones(a.size), (a, b)), shape=(n, n))
        count, label = connected_components(graph, directed=False)
        return int(count), label
    label = np.arange(n, dtype=np.int64)
    while True:
        la, lb = label[a], label[b]
        differ = la != lb
        if not differ.any():
            break
        la, lb = la[differ], lb[differ]
        np.minimum.at(label, np.maximum(la, lb), np.minimum(la, lb))
        while True:
            jumped = label[label]
            if np.array_equal(jumped, label):
                break
            label = jumped
    roots, numbered = np.unique(label, return_inverse=True)
    return int(roots.size), numbered.astype(np.int32)
