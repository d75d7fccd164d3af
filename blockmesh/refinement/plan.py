"""The paper's global numbering of a refined block mesh, block by block, from prefix sums.

The paper's walk numbers, level by level, the new nodes of every cell in order; the cells of a
refined block mesh are block-major at every level (block b owns cells ``b 6^l .. (b+1) 6^l - 1``),
so the nodes new at level ``l`` are grouped by block: block 0's, then block 1's, and so on.
Within a block they come in the order of the refined reference pentagon
(:mod:`blockmesh.refinement.template`), except that the nodes inside a block edge shared with a
lower block were numbered by that block. A level-``l`` refinement adds ``2^(l-1)`` nodes inside each
block edge, so

    count(l, b) = n_l - n_(l-1) - (edges of b numbered by a lower block) 2^(l-1)

and the first id block b gives out at level l is a prefix sum of these counts
(:class:`RefinementPlan`). From the plan alone, without the other blocks' arrays, any block's
node ids (:func:`block_node_ids`) and the ids along any block edge (:func:`edge_node_ids`)
follow in O(n_L) and O(2^L log 2^L): this is what lets each block, or each worker of a
distributed run, work on its own.

Coordinates are the paper's arithmetic level by level (:func:`place_level`); the nodes inside a
shared edge are midpoints of midpoints of the edge's two corners, which both blocks compute bit
for bit alike (addition commutes in floating point).

Examples
--------
>>> import blockmesh
>>> from blockmesh.geometry.topology import cell_neighbours
>>> base = blockmesh.load_domain("joined-2").block_mesh()
>>> plan = plan_refinement(base.cells, cell_neighbours(base.cells, base.n_points),
...                        base.n_points, 2)
>>> plan.n_nodes == blockmesh.refine(base, 2).n_points
True
>>> plan.counts.tolist()  # new nodes per level (rows) and block (columns)
[[0, 0], [10, 9], [50, 48]]
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from blockmesh.refinement.template import LevelStep, PentagonTemplate, node_count, pentagon_template

__all__ = [
    "PLACE_CHUNK",
    "NodePattern",
    "PlaceScratch",
    "RefinementPlan",
    "block_node_ids",
    "chunk_coordinates",
    "edge_id_table",
    "edge_node_ids",
    "group_node_ids",
    "node_pattern",
    "place_block",
    "place_level",
    "plan_refinement",
]


@dataclass(frozen=True)
class RefinementPlan:
    """Where each block's nodes go in the global numbering of a refinement (small arrays only).

    Attributes
    ----------
    steps : int
        Levels of refinement.
    cells : ndarray (B, 5) int64
        The base cells (blocks) and their node ids.
    neighbour : ndarray (B, 5) int64
        Slot ``5 c + e`` of the same edge in the cell across edge e, or -1 on the boundary.
    taken : ndarray (B, 5) bool
        Edges whose inner nodes a lower-numbered cell numbers.
    offsets, counts : ndarray (steps + 1, B) int64
        The first global id and the number of ids block b gives out at level l (row 0 unused).
    n_base_points : int
    n_nodes : int
        Nodes of the refined mesh.
    """

    steps: int
    cells: np.ndarray
    neighbour: np.ndarray
    taken: np.ndarray
    offsets: np.ndarray
    counts: np.ndarray
    n_base_points: int
    n_nodes: int

    @property
    def n_blocks(self) -> int:
        """Number of base cells B."""
        return int(self.cells.shape[0])

    def nodes_of_block(self, block: int) -> int:
        """Ids block ``block`` gives out over all levels (its corners excluded)."""
        return int(self.counts[1:, block].sum())


def plan_refinement(
    cells: np.ndarray, neighbour: np.ndarray, n_points: int, steps: int
) -> RefinementPlan:
    """The numbering plan of ``steps`` levels of refinement of the base ``cells``. O(B steps).

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 3)
    >>> plan.n_nodes, plan.offsets[1:, 0].tolist()
    (345, [5, 15, 65])
    """
    cells = np.asarray(cells, dtype=np.int64)
    neighbour = np.asarray(neighbour, dtype=np.int64)
    n_blocks = cells.shape[0]
    row = np.arange(n_blocks)[:, None]
    taken = (neighbour >= 0) & (neighbour < 5 * row)
    n_taken = taken.sum(axis=1)
    counts = np.zeros((steps + 1, n_blocks), dtype=np.int64)
    for level in range(1, steps + 1):
        counts[level] = node_count(level) - node_count(level - 1) - n_taken * 2 ** (level - 1)
    flat = counts[1:].ravel()
    offsets = np.zeros_like(counts)
    offsets[1:] = (n_points + np.cumsum(flat) - flat).reshape(steps, n_blocks)
    return RefinementPlan(
        steps, cells, neighbour, taken, offsets, counts, int(n_points), int(n_points + flat.sum())
    )


def _level_bounds(steps: int) -> np.ndarray:
    return np.array([node_count(level) for level in range(steps + 1)], dtype=np.int64)


def edge_node_ids(plan: RefinementPlan, block: int, edge: int) -> np.ndarray:
    """Global ids of the ``2^L + 1`` nodes along edge ``edge`` of ``block``, corner to corner.

    Computed from the plan alone: for an edge the block numbers itself, each node's id is its
    block's offset at its level plus its rank among the nodes the block numbers at that level;
    for an edge a lower block numbered, that block's ids read backwards.

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 1)
    >>> edge_node_ids(plan, 0, 0).tolist()
    [0, 5, 1]
    """
    if plan.taken[block, edge]:
        lower, lower_edge = divmod(int(plan.neighbour[block, edge]), 5)
        return edge_node_ids(plan, lower, lower_edge)[::-1].copy()
    level, rank = _edge_ranks(plan.steps, edge, tuple(plan.taken[block].tolist()))
    ids = np.empty(rank.size + 2, dtype=np.int64)
    ids[0] = plan.cells[block, edge]
    ids[-1] = plan.cells[block, (edge + 1) % 5]
    ids[1:-1] = plan.offsets[level, block] + rank
    return ids


@lru_cache(maxsize=256)
def _edge_ranks(steps: int, edge: int, taken: tuple[bool, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Level and rank among the block's own new nodes of that level, of each node inside ``edge``.

    Depends only on the template and on which edges (``taken``) a lower block numbers, so it is
    computed once per combination (2^steps - 1 entries each).
    """
    template = pentagon_template(steps)
    inner = template.edge_nodes[edge][1:-1]
    bounds = _level_bounds(steps)
    level = np.searchsorted(bounds, inner, side="right")
    first = bounds[level - 1]
    skipped = np.zeros(inner.size, dtype=np.int64)
    for other in np.flatnonzero(taken):
        nodes = np.sort(template.edge_nodes[other][1:-1])
        skipped += np.searchsorted(nodes, inner) - np.searchsorted(nodes, first)
    rank = (inner - first) - skipped
    level.setflags(write=False)
    rank.setflags(write=False)
    return level, rank


def edge_id_table(plan: RefinementPlan) -> np.ndarray:
    """Global ids along every block edge, (B, 5, 2^L + 1): row ``[b, e]`` from corner e to e+1.

    The same ids as :func:`edge_node_ids`, for all edges at once: the edges a block numbers
    itself are grouped by edge and by which edges the block leaves to lower blocks (at most 160
    kinds), each kind filled for all its blocks in one operation; an edge a lower block numbered
    is that block's row read backwards. O(B 2^L).

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 1)
    >>> edge_id_table(plan)[0].tolist()
    [[0, 5, 1], [1, 6, 2], [2, 7, 3], [3, 8, 4], [4, 9, 0]]
    """
    steps = plan.steps
    table = np.empty((plan.n_blocks, 5, 2**steps + 1), dtype=np.int64)
    table[:, :, 0] = plan.cells
    table[:, :, -1] = np.roll(plan.cells, -1, axis=1)
    kind = plan.taken @ (1 << np.arange(5))
    for edge in range(5):
        own = ~plan.taken[:, edge]
        for pattern in np.unique(kind[own]).tolist():
            blocks = np.flatnonzero(own & (kind == pattern))
            taken = tuple(bool(pattern >> k & 1) for k in range(5))
            level, rank = _edge_ranks(steps, edge, taken)
            table[blocks, edge, 1:-1] = plan.offsets[level][:, blocks].T + rank
    high, high_edge = np.nonzero(plan.taken)
    low, low_edge = np.divmod(plan.neighbour[high, high_edge], 5)
    table[high, high_edge] = table[low, low_edge, ::-1]
    return table


@dataclass(frozen=True)
class NodePattern:
    """Which template nodes a block numbers itself, given the edges lower blocks number.

    Attributes
    ----------
    taken : tuple of bool
        The block's edges whose inner nodes a lower block numbers.
    own : ndarray (n_L,) bool
        The nodes the block numbers (not a corner, not inside a taken edge).
    rank : ndarray (n_L,) int64
        Of each own node, its rank among the block's own nodes of the same level (0-based);
        meaningless elsewhere.
    keep : tuple of ndarray
        ``keep[l - 1]``: the positions, within level ``l``'s range of local ids, of the own nodes.
    last_source : ndarray
        The slots (:attr:`LevelStep.source`) of the own nodes of the finest level, increasing.
    """

    taken: tuple[bool, ...]
    own: np.ndarray
    rank: np.ndarray
    keep: tuple[np.ndarray, ...]
    last_source: np.ndarray


#: Node patterns are cached up to this level (about 1.2 MB each at level 6; at most 32 kinds).
_CACHED_PATTERN_LEVEL = 6


def node_pattern(steps: int, taken: tuple[bool, ...]) -> NodePattern:
    """The :class:`NodePattern` of a block refined ``steps`` times, ``taken`` edges left to others.

    Examples
    --------
    >>> p = node_pattern(1, (True, False, False, False, False))
    >>> p.own.nonzero()[0].tolist(), p.rank[6:15].tolist()
    ([6, 7, 8, 9, 10, 11, 12, 13, 14], [0, 1, 2, 3, 4, 5, 6, 7, 8])
    """
    taken = tuple(bool(t) for t in taken)
    if steps <= _CACHED_PATTERN_LEVEL:
        return _cached_node_pattern(steps, taken)
    return _node_pattern(steps, taken)


def _node_pattern(steps: int, taken: tuple[bool, ...]) -> NodePattern:
    template = pentagon_template(steps)
    own = np.ones(template.n_nodes, dtype=bool)
    own[:5] = False
    for edge in np.flatnonzero(taken).tolist():
        own[template.edge_nodes[edge][1:-1]] = False
    counted = np.cumsum(own)
    rank = counted - 1
    bounds = _level_bounds(steps)
    keep = []
    for level in range(1, steps + 1):
        lo, hi = int(bounds[level - 1]), int(bounds[level])
        rank[lo:hi] -= counted[lo - 1]
        keep.append(np.flatnonzero(own[lo:hi]))
    last_source = template.steps[-1].source[keep[-1]] if steps else np.empty(0, dtype=np.int64)
    for array in (own, rank, *keep, last_source):
        array.setflags(write=False)
    return NodePattern(taken, own, rank, tuple(keep), last_source)


_cached_node_pattern = lru_cache(maxsize=64)(_node_pattern)


def group_node_ids(
    plan: RefinementPlan,
    first: int,
    stop: int,
    edge_ids: np.ndarray,
    out: np.ndarray | None = None,
    template: PentagonTemplate | None = None,
) -> np.ndarray:
    """Global ids of the template nodes of blocks ``first`` to ``stop - 1``, (G, n_L) int64.

    ``edge_ids`` (G, 5, 2^L + 1) are the ids along the blocks' edges (rows of
    :func:`edge_id_table`); ``out`` (G, n_L) int64 is filled and returned when given;
    ``template`` is the plan's level's template when the caller holds it already. Each of a
    block's own nodes is its level's offset plus its rank (:func:`node_pattern`), the corners and
    edges come from ``edge_ids``. O(G n_L).

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 2)
    >>> ids = group_node_ids(plan, 0, 1, edge_id_table(plan))
    >>> bool(np.array_equal(ids[0], np.arange(65)))
    True
    """
    if template is None:
        template = pentagon_template(plan.steps)
    ids = np.empty((stop - first, template.n_nodes), dtype=np.int64) if out is None else out
    bounds = _level_bounds(plan.steps)
    for k, block in enumerate(range(first, stop)):
        rank = node_pattern(plan.steps, tuple(plan.taken[block].tolist())).rank
        for level in range(1, plan.steps + 1):
            lo, hi = int(bounds[level - 1]), int(bounds[level])
            np.add(rank[lo:hi], plan.offsets[level, block], out=ids[k, lo:hi])
    for edge in range(5):
        ids[:, template.edge_nodes[edge]] = edge_ids[:, edge]
    return ids


def block_node_ids(
    plan: RefinementPlan, block: int, out: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Global ids of every template node of ``block`` (n_L,), and which ones the block numbers.

    ``out`` (n_L,) int64 is filled and returned when given (reused buffers save page faults).
    O(n_L), from the plan alone (see :func:`group_node_ids` for many blocks at once).

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 2)
    >>> ids, own = block_node_ids(plan, 0)
    >>> bool(np.array_equal(ids, np.arange(65))), int(own.sum())
    (True, 60)
    """
    edge_ids = np.stack([edge_node_ids(plan, block, edge) for edge in range(5)])
    ids = group_node_ids(plan, block, block + 1, edge_ids[None], None if out is None else out[None])
    return ids[0], node_pattern(plan.steps, tuple(plan.taken[block].tolist())).own.copy()


#: Parent cells (times blocks) processed at once by :func:`place_level`: small enough for the
#: working arrays to stay in the CPU caches, large enough for numpy's per-call overhead not to
#: matter.
PLACE_CHUNK = 8192


class PlaceScratch:
    """Working arrays of :func:`place_level` for up to ``rows`` blocks, reused from call to call.

    A refinement calls :func:`place_level` thousands of times; allocating its temporaries anew
    each time makes the C library map and unmap memory over and over (each first touch of a page
    is a fault), which was measured to cost up to 5x the arithmetic. One scratch per thread
    avoids that.

    Examples
    --------
    >>> scratch = PlaceScratch(4)
    >>> scratch.rows, scratch.chunk
    (4, 2048)
    """

    def __init__(self, rows: int) -> None:
        self.rows = rows
        #: Parent cells per chunk.
        self.chunk = max(1, PLACE_CHUNK // rows)
        size = rows * self.chunk
        self.corners = np.empty(5 * size, dtype=np.complex128)
        self.centres = np.empty(2 * size, dtype=np.float64)
        self.new = np.empty(10 * size, dtype=np.complex128)
        self.slots = np.empty(10 * size, dtype=np.complex128)
        self.picked = np.empty(10 * size, dtype=np.complex128)
        self.index = np.empty(10 * self.chunk, dtype=np.int64)


def place_level(
    local: np.ndarray, step: LevelStep, lo: int, scratch: PlaceScratch | None = None
) -> None:
    """Coordinates of the nodes new at one level, in every block's local numbering.

    ``local`` holds one complex128 per local node and block, shape (B, n_L) (a point ``(x, y)`` as
    ``x + iy``, which makes gathers and scatters several times faster than on (N, 2) rows); the
    nodes new at this level go to ``local[:, lo:]``. Parent cells go in chunks
    (:func:`chunk_coordinates`) whose new nodes are a contiguous run of the output, in the working
    arrays of ``scratch`` (made for the call when not given), so that they stay in cache and
    nothing is allocated.
    """
    n_blocks = local.shape[0]
    if scratch is None or scratch.rows < n_blocks:
        scratch = PlaceScratch(n_blocks)
    n_parents = step.corners.shape[1]
    for j0 in range(0, n_parents, scratch.chunk):
        j1 = min(j0 + scratch.chunk, n_parents)
        slots = chunk_coordinates(local, step, j0, j1, scratch)
        first, last = np.searchsorted(step.source, (10 * j0, 10 * j1))
        index = np.subtract(step.source[first:last], 10 * j0, out=scratch.index[: last - first])
        target = local[:, lo + first : lo + last]
        if n_blocks > 1:  # rows of local are not contiguous: gather, then copy
            picked = scratch.picked[: n_blocks * (last - first)].reshape(n_blocks, -1)
            np.take(slots, index, axis=1, out=picked, mode="clip")
            np.copyto(target, picked)
        else:
            np.take(slots, index, axis=1, out=target, mode="clip")


def chunk_coordinates(
    local: np.ndarray,
    step: LevelStep,
    j0: int,
    j1: int,
    scratch: PlaceScratch,
    *,
    slot_major: bool = False,
) -> np.ndarray:
    """The midpoints and inner points of parent cells ``j0`` to ``j1 - 1`` of every block.

    Returns a view into ``scratch``, (B, 10 (j1 - j0)) complex128: slot ``10 j + k`` holds
    ``u_k`` (k < 5) or ``w_(k-5)`` of parent ``j0 + j`` (``step.source`` says which slot each
    new node is). With ``slot_major``, the (B, 10 C) layout the arithmetic produces is returned
    as it is (no transposition): slot ``10 j + k`` is at ``k C + j`` with ``C`` =
    ``scratch.chunk``, whatever the chunk's length.

    The arithmetic runs on the float64 view, corner-major, and is the paper's:
    ``u = (v_i + v_i+1) / 2``, ``p = (v1 + v2 + v3 + v4 + v5) / 5``, ``w = (u + p) / 2``; so the
    results are bit for bit those of the paper's program.
    """
    n_blocks = local.shape[0]
    size = n_blocks * (j1 - j0)
    stride = scratch.chunk if slot_major else j1 - j0
    # (B, 5, 2c): corner-major, x/y interleaved. The template's indices are valid by
    # construction; mode="clip" skips numpy's bounds check, which costs more than the gather.
    corners = np.take(
        local,
        step.corners[:, j0:j1],
        axis=1,
        mode="clip",
        out=scratch.corners[: 5 * size].reshape(n_blocks, 5, j1 - j0),
    ).view(np.float64)
    p = np.add(corners[:, 0], corners[:, 1], out=scratch.centres[: 2 * size].reshape(n_blocks, -1))
    p += corners[:, 2]
    p += corners[:, 3]
    p += corners[:, 4]
    p /= 5
    whole = scratch.new[: 10 * n_blocks * stride].view(np.float64).reshape(n_blocks, 2, 5, -1)
    new = whole[..., : 2 * (j1 - j0)]
    u, w = new[:, 0], new[:, 1]  # [u, w]
    np.add(corners[:, :4], corners[:, 1:], out=u[:, :4])
    np.add(corners[:, 4], corners[:, 0], out=u[:, 4])
    u *= 0.5  # exact, as / 2
    np.add(u, p[:, None, :], out=w)
    w *= 0.5
    if slot_major:
        return whole.view(np.complex128).reshape(n_blocks, -1)
    slots = scratch.slots[: 10 * size].reshape(n_blocks, j1 - j0, 10)
    np.copyto(slots, whole.view(np.complex128).reshape(n_blocks, 10, -1).swapaxes(1, 2))
    return slots.reshape(n_blocks, -1)


def place_block(
    template: PentagonTemplate,
    corners: np.ndarray,
    out: np.ndarray,
    after_level: Callable[[np.ndarray, int], None] | None = None,
) -> np.ndarray:
    """Coordinates (complex128) of all template nodes of one block with ``corners`` (5,) complex.

    ``out`` (n_L,) complex128 is filled and returned. O(n_L), the paper's arithmetic.
    ``after_level(out, level)``, when given, runs after each level and may change that level's
    nodes in place (the curve-aware rule of :class:`blockmesh.refinement.curved.CurvedBlocks`).
    """
    out[:5] = corners
    view = out[None, :]
    scratch = PlaceScratch(1)
    for level in range(1, template.level + 1):
        place_level(view, template.steps[level - 1], node_count(level - 1), scratch)
        if after_level is not None:
            after_level(out, level)
    return out
