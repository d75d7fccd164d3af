"""The refinement of one reference pentagon, numbered like the paper, built once and reused.

Every node of a refined pentagon is a fixed combination of the pentagon's five corners
(docs/mathematics.md §1), and the paper's numbering of a single pentagon does not depend on its
shape. So the connectivity of the refined reference pentagon and the position of its nodes on its
five edges are computed once per level for local node ids ``0..n_L-1`` and cached;
:func:`blockmesh.refine` maps local ids to global ids block by block and computes coordinates
level by level.

Local numbering (0-based, the paper's program ``nodaladdressesforpentagon``): corners ``0..4``;
then level by level, cells in order, each cell numbers the midpoints of its edges ``v_i -> v_i+1``
that are not numbered yet, then its five inner points. The nodes new at level ``l`` are therefore
the contiguous range ``n_(l-1) .. n_l - 1``, and the cells of a coarser level are a function of
the finer ones (corner k of cell j is corner 0 of its child k).

The construction tracks, for every cell edge, the cell across it (or none on the boundary); the
walking order then decides which cell numbers a shared midpoint (the lower-numbered one) without
sorting or hashing, in O(6^L) time and memory.

Examples
--------
>>> t = pentagon_template(1)
>>> t.cells.tolist()  # the paper's Fig. 2, 0-based  # doctest: +NORMALIZE_WHITESPACE
[[0, 5, 10, 14, 9], [1, 6, 11, 10, 5], [2, 7, 12, 11, 6],
 [3, 8, 13, 12, 7], [4, 9, 14, 13, 8], [10, 11, 12, 13, 14]]
>>> t.edge_nodes[0].tolist()  # nodes along the edge from corner 0 to corner 1
[0, 5, 1]
"""

from __future__ import annotations

import threading
import weakref
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

__all__ = [
    "CHILD_PATTERN",
    "TEMPLATE_CACHE_BYTES",
    "LevelStep",
    "PentagonTemplate",
    "cached_template_bytes",
    "node_count",
    "pentagon_template",
    "template_is_alive",
]

#: Templates kept for reuse after their refinement returns, at most this many bytes in all
#: (least recently used first out). A bigger template lives only while something uses it: a
#: level-10 template is about 3.7 GB, which a process should not keep after its mesh is made.
TEMPLATE_CACHE_BYTES = 192 * 2**20

#: Child ``k`` of a cell ``<v0..v4>`` with midpoints ``u`` and inner points ``w`` (paper eq. 1a):
#: ``<v_k, u_k, w_k, w_(k-1), u_(k-1)>`` for k = 0..4, then ``<w_0..w_4>``. Entries index the
#: 15 points ``[v0..v4, u0..u4, w0..w4]``.
CHILD_PATTERN = np.array(
    [[k, 5 + k, 10 + k, 10 + (k - 1) % 5, 5 + (k - 1) % 5] for k in range(5)]
    + [[10, 11, 12, 13, 14]],
    dtype=np.int64,
)

_K = np.arange(5)
# Cell edges are addressed by "slot" 10 * cell + edge (slots 5..9 of a cell are its inner points
# during numbering). Neighbour of child edge (c, e) inside the same parent, as the offset
# 10 * c' + e' of the facing child edge within the parent's 60 child slots, or -1 where the edge
# is half of a parent edge (then it faces a child of the cell across the parent's edge).
_SIBLING = np.full((6, 10), -1, dtype=np.int64)
_SIBLING[:5, 1] = 10 * ((_K + 1) % 5) + 3  # (u_k, w_k)     faces child k+1, edge 3
_SIBLING[:5, 2] = 10 * 5 + (_K - 1) % 5  # (w_k, w_k-1)   faces the centre child
_SIBLING[:5, 3] = 10 * ((_K - 1) % 5) + 1  # (w_k-1, u_k-1) faces child k-1, edge 1
_SIBLING[5, :5] = 10 * ((_K + 1) % 5) + 2  # (w_m, w_m+1)   faces child m+1, edge 2
_SIBLING = _SIBLING[:, :5]


def node_count(level: int) -> int:
    """Nodes of one pentagon refined ``level`` times: ``1 + (3/2) 6^L + (5/2) 2^L``.

    Examples
    --------
    >>> [node_count(level) for level in range(6)]
    [5, 15, 65, 345, 1985, 11745]
    """
    return (2 + 3 * 6**level + 5 * 2**level) // 2


@dataclass(frozen=True)
class LevelStep:
    """How the coordinates of the nodes new at one level follow from the previous level.

    Attributes
    ----------
    corners : ndarray (5, C) int64
        Corner ``i`` of every cell of the previous level (corner-major, so that the arithmetic runs
        on contiguous rows).
    source : ndarray (n_l - n_(l-1),) int64, increasing
        For each new node in numbering order, its slot ``10 j + k``: midpoint ``u_k`` (k < 5) or
        inner point ``w_(k-5)`` of cell j of the previous level. The new nodes of cells
        ``j0..j1-1`` are therefore a contiguous run of ``source`` (found by ``searchsorted``).
    """

    corners: np.ndarray
    source: np.ndarray


@dataclass(frozen=True)
class PentagonTemplate:
    """One pentagon refined ``level`` times, in the paper's numbering (arrays are read-only).

    Attributes
    ----------
    level : int
    cells : ndarray (6^L, 5) int64
        Local node ids of the cells, counter-clockwise; the children of cell j of the previous
        level are rows 6j..6j+5 in the paper's child order.
    edge_nodes : ndarray (5, 2^L + 1) int64
        ``edge_nodes[e]`` lists the nodes on the edge from corner e to corner e+1, in order.
    edge_of_node : ndarray (n_L,) int8
        For a node strictly inside edge e: e; for the corners: -2; for interior nodes: -1.
    steps : tuple of LevelStep
        ``steps[l - 1]`` computes the coordinates of the nodes new at level ``l``.
    """

    level: int
    cells: np.ndarray
    edge_nodes: np.ndarray
    edge_of_node: np.ndarray
    steps: tuple[LevelStep, ...]

    @property
    def n_nodes(self) -> int:
        """Number of local nodes ``n_L``."""
        return node_count(self.level)

    def cells_of_level(self, level: int) -> np.ndarray:
        """The cells of a coarser level ``0 <= level <= self.level`` (the nested numbering's).

        Read from this template (each step keeps its parents' corners), so a refinement that
        holds the finest template never fetches a coarser one.

        Examples
        --------
        >>> t = pentagon_template(3)
        >>> bool(np.array_equal(t.cells_of_level(2), pentagon_template(2).cells))
        True
        """
        if level == self.level:
            return self.cells
        return self.steps[level].corners.T

    @property
    def nbytes(self) -> int:
        """Bytes held by the template's arrays."""
        arrays = [self.cells, self.edge_nodes, self.edge_of_node]
        arrays += [a for step in self.steps for a in (step.corners, step.source)]
        return sum(a.nbytes for a in arrays)


def _readonly(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def _refine_step(parents, neighbour, boundary, n_old, *, want_neighbours):
    """One level: number new nodes, build children, their neighbours and boundary segments.

    ``neighbour[j, i]`` is the slot ``10 * j' + i'`` of the cell edge (j', i') across edge i of
    cell j, or -1 on the outer boundary. Every step is a handful of whole-array operations; gathers
    use ``np.take(..., mode="clip")`` (indices are valid by construction; numpy's bounds check would
    cost more than the gather).
    """
    n_parents = parents.shape[0]
    row = np.arange(n_parents)[:, None]
    # The lower-numbered of the two cells sharing an edge numbers its midpoint.
    first = (neighbour < 0) | (neighbour >= 10 * (row + 1))

    # Walking order: parent j owns slots 10j..10j+9 = its midpoints u_0..u_4 (present only where
    # it numbers them), then its inner points w_0..w_4. Node ids follow the present slots in order.
    present = np.ones((n_parents, 10), dtype=bool)
    present[:, :5] = first
    rank = present.ravel().astype(np.int64)
    np.cumsum(rank, out=rank)
    rank += n_old - 1
    points15 = np.empty((n_parents, 15), dtype=np.int64)  # [v, u, w] of every parent
    points15[:, :5] = parents
    points15[:, 5:10] = np.where(
        first,
        rank.reshape(n_parents, 10)[:, :5],
        np.take(rank, np.maximum(neighbour, 0), mode="clip"),  # numbered by the cell across
    )
    points15[:, 10:] = rank.reshape(n_parents, 10)[:, 5:]
    cells = np.take(points15, CHILD_PATTERN.ravel(), axis=1, mode="clip").reshape(-1, 5)

    # Where each new node's coordinates come from: the present slots, in order.
    source = np.flatnonzero(present.ravel())

    # The outer boundary: segment (cell j, edge i) splits into (child i, edge 0) and
    # (child i+1, edge 4); its midpoint is u[j, i].
    seg_cell, seg_edge = boundary
    seg_mids = points15[seg_cell, 5 + seg_edge]
    new_boundary = (
        np.stack([6 * seg_cell + seg_edge, 6 * seg_cell + (seg_edge + 1) % 5], -1).reshape(5, -1),
        np.stack([np.zeros_like(seg_edge), np.full_like(seg_edge, 4)], -1).reshape(5, -1),
    )

    child_neighbour = None
    if want_neighbours:
        child_neighbour = 60 * row + _SIBLING.ravel()  # (C, 30): child c, edge e at 5c + e
        # Half (v_k, u_k) of parent edge k faces (child i'+1, edge 4) of the cell j' across it;
        # half (u_k-1, v_k) of parent edge k-1 faces (child i', edge 0) there.
        j_across, i_across = np.divmod(neighbour, 10)
        outside = neighbour < 0
        child_neighbour[:, 0:25:5] = np.where(
            outside, -1, 60 * j_across + 10 * ((i_across + 1) % 5) + 4
        )
        child_neighbour[:, 4:25:5] = np.roll(
            np.where(outside, -1, 60 * j_across + 10 * i_across), 1, axis=1
        )
        child_neighbour = child_neighbour.reshape(-1, 5)
    step = LevelStep(_readonly(np.ascontiguousarray(parents.T)), _readonly(source))
    return cells, seg_mids, new_boundary, child_neighbour, step


class _TemplateCache:
    """Least-recently-used templates up to :data:`TEMPLATE_CACHE_BYTES`, plus weak references.

    Templates over the budget are found again while they are alive (e.g. while several blocks or
    workers' tasks of one refinement use them) and freed with their last user.
    """

    def __init__(self) -> None:
        self._kept: OrderedDict[int, PentagonTemplate] = OrderedDict()
        self._alive: weakref.WeakValueDictionary[int, PentagonTemplate] = (
            weakref.WeakValueDictionary()
        )
        self._lock = threading.Lock()

    def get(self, level: int) -> PentagonTemplate | None:
        with self._lock:
            found = self._kept.get(level)
            if found is not None:
                self._kept.move_to_end(level)
                return found
            return self._alive.get(level)

    def put(self, template: PentagonTemplate) -> None:
        with self._lock:
            self._alive[template.level] = template
            if template.nbytes > TEMPLATE_CACHE_BYTES:
                return
            self._kept[template.level] = template
            while sum(t.nbytes for t in self._kept.values()) > TEMPLATE_CACHE_BYTES:
                self._kept.popitem(last=False)

    def kept_bytes(self) -> int:
        """Bytes the cache keeps alive by itself."""
        with self._lock:
            return sum(t.nbytes for t in self._kept.values())


_CACHE = _TemplateCache()


def cached_template_bytes() -> int:
    """Bytes of templates the cache keeps alive by itself (at most TEMPLATE_CACHE_BYTES).

    Examples
    --------
    >>> cached_template_bytes() <= TEMPLATE_CACHE_BYTES
    True
    """
    return _CACHE.kept_bytes()


def template_is_alive(level: int) -> bool:
    """Whether the template of ``level`` is in memory now (cached, or in use somewhere).

    Examples
    --------
    >>> _ = pentagon_template(2)
    >>> template_is_alive(2)
    True
    """
    return _CACHE.get(level) is not None


def pentagon_template(level: int) -> PentagonTemplate:
    """The reference pentagon refined ``level`` times (cached, within a memory budget).

    Cost: O(6^L) time and about 62 bytes per cell of memory, once per level while cached; the
    cache keeps at most :data:`TEMPLATE_CACHE_BYTES` (levels up to 8 fit), bigger templates
    are rebuilt when needed again after their last user let them go.

    Examples
    --------
    >>> t = pentagon_template(2)
    >>> t.cells.shape, t.n_nodes, t.edge_nodes.shape
    ((36, 5), 65, (5, 5))
    """
    if level < 0:
        raise ValueError(f"level must be >= 0, got {level}")
    found = _CACHE.get(level)
    if found is None:
        found = _build_template(level)
        _CACHE.put(found)
    return found


def _build_template(level: int) -> PentagonTemplate:
    cells = np.arange(5, dtype=np.int64).reshape(1, 5)
    neighbour = np.full((1, 5), -1, dtype=np.int64)
    boundary = (np.zeros((5, 1), dtype=np.int64), np.arange(5, dtype=np.int64)[:, None])
    edge_nodes = np.array([[e, (e + 1) % 5] for e in range(5)], dtype=np.int64)
    edge_of_node = np.full(node_count(level), -1, dtype=np.int8)
    edge_of_node[:5] = -2
    steps = []
    for step in range(1, level + 1):
        cells, seg_mids, boundary, neighbour, how = _refine_step(
            cells, neighbour, boundary, node_count(step - 1), want_neighbours=step < level
        )
        steps.append(how)
        refined = np.empty((5, 2 * edge_nodes.shape[1] - 1), dtype=np.int64)
        refined[:, 0::2] = edge_nodes
        refined[:, 1::2] = seg_mids
        edge_nodes = refined
        edge_of_node[seg_mids] = np.arange(5, dtype=np.int8)[:, None]
    return PentagonTemplate(
        level, _readonly(cells), _readonly(edge_nodes), _readonly(edge_of_node), tuple(steps)
    )
